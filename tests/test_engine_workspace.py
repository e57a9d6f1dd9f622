"""The step's buffers (the world's workspace) persist between calls and grow when a tick needs more:
neither may change a trajectory."""

from __future__ import annotations

import numpy as np

from rustycs import Box, Circle, World


def crowd() -> World:
    """60 circles heaped on one spot: 1770 overlapping pairs, far more than the buffers first hold."""
    world = World(tick_rate=60, precision=4)
    world.add_force((0.0, -9.81))
    world.add_body(Box(40.0, 1.0), position=(0.0, -0.5), body_type="static")
    for k in range(60):
        world.add_body(Circle(0.5), position=(0.001 * k, 3.0 + 0.001 * k))
    return world


def state(world: World) -> bytes:
    return np.concatenate([world.centers.ravel(), world.angles, world.velocities.ravel(),
                           world.angular_velocities]).tobytes()


def test_growing_buffers_and_calls_per_tick_leave_the_trajectory_unchanged():
    block, ticks = crowd(), crowd()
    block.step(1)
    assert block.observables()["contact_count"] > 1000  # the buffers had to grow
    block.step(59)
    for _ in range(60):
        ticks.step(1)
    assert state(block) == state(ticks)
    assert np.all(np.isfinite(block.centers))


def stack_load(world: World) -> float:
    """Sum of the normal impulses between the floor (body 0) and the five boxes (1-5)."""
    contacts = world.contacts()
    return float(contacts["normal_impulse"][contacts["body_b"] <= 5].sum())


def test_adding_a_body_keeps_the_warm_start_and_the_stack_at_rest():
    world = World(tick_rate=60, precision=10)
    world.add_force((0.0, -9.81))
    world.add_body(Box(10.0, 1.0), position=(0.0, -0.5), body_type="static")
    for level in range(5):
        world.add_body(Box(1.0, 1.0), position=(0.0, 0.5 + level))
    world.step(120)
    before = stack_load(world)
    world.add_body(Circle(0.5), position=(5.0, 0.5))  # apart from the stack, resting on the floor
    world.step(1)
    # warm-started: the stack's contacts carry their full load in the first tick after the rebuild
    assert abs(stack_load(world) - before) < 1e-3 * before
    world.step(59)
    assert np.abs(world.velocities[1:6]).max() < 1e-3


def test_load_kernels_steps_once_with_the_entry_that_grows_the_buffers_too():
    """A timed step must load no kernel: the growth kernel, loaded inside the first block of the 210-box
    pyramid, took 31 of its 45 ms. The step's entry grows the buffers itself; after `load_kernels` it is
    loaded and stepping goes on unchanged."""
    from rustycs.step import step_world

    loaded, plain = crowd(), crowd()
    loaded.load_kernels()
    assert loaded.tick == 1 and len(step_world.signatures) >= 1
    loaded.step(29)
    plain.step(30)
    assert state(loaded) == state(plain)


def test_prepare_makes_the_step_ready_and_changes_nothing():
    """`prepare` builds the records, buffers and compiled entry a first step would (so that a timed step
    does no setup), with no tick done and the run going on bit for bit as without it."""
    prepared, plain = crowd(), crowd()
    before = state(prepared)
    prepared.prepare()
    assert prepared.tick == 0 and state(prepared) == before and prepared._entry is not None
    prepared.step(30)
    plain.step(30)
    assert state(prepared) == state(plain)


def test_the_kernel_cache_stamp_covers_what_compiled_code_sees():
    """The stamp hashes the modules defining kernels and all they import (constants are compiled in),
    not the Python-only World layer, so that editing the World compiles nothing again."""
    from rustycs.kernel_cache import _compiled_sources

    modules = set(_compiled_sources())
    assert {"step", "narrow_phase", "contact_solver", "constants", "pieces", "joints"} <= modules
    assert not modules & {"world", "body_control", "world_scenario", "kernel_cache"}
