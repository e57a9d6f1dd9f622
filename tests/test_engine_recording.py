"""Frames recorded by the compiled step (World.step(record=...)) are the states a tick-by-tick
capture sees, at the ticks asked for, and a diverging block keeps the frames before the bad tick."""

from __future__ import annotations

import numpy as np
import pytest

import rustycs
from rustycs import Box, Circle, Polygon, World


def pile() -> World:
    world = World(tick_rate=60, precision=4)
    world.add_force((0.0, -9.81))
    world.add_body(Box(10.0, 1.0), position=(0.0, -0.5), body_type="static")
    world.add_body(Circle(0.3), position=(-1.0, 0.35))
    world.add_body(Box(0.5, 0.5), position=(0.0, 0.4), angle=0.3)
    world.add_body(Polygon([(0.0, 0.0), (0.6, 0.0), (0.1, 0.5)]), position=(1.0, 0.02))
    return world


def test_block_frames_equal_tick_by_tick_captures():
    block, single = pile(), pile()
    frames = block.frame_buffer(4)
    assert block.step(10, record=frames, every=3) == 4
    captured = single.frame_buffer(4)
    row = 0
    for tick in range(1, 11):
        single.step(1)
        if tick % 3 == 0 or tick == 10:
            single.capture(captured, row)
            row += 1
    np.testing.assert_array_equal(frames["tick"], [3, 6, 9, 10])
    for name in frames:
        np.testing.assert_array_equal(frames[name], captured[name], err_msg=name)  # bitwise
    assert frames["contact_count"][-1] > 0
    # positions are body origins: the off-centroid triangle's differs from its centre of mass
    assert np.allclose(frames["position"][-1], block.positions)
    assert not np.allclose(block.positions[3], block.centers[3])


def test_frame_buffer_too_small_is_refused():
    world = pile()
    with pytest.raises(ValueError, match="cannot hold 4 frames"):
        world.step(10, record=world.frame_buffer(3), every=3)


def test_a_buffer_of_another_world_or_type_is_refused_before_any_tick():
    """The step writes a buffer's arrays unchecked, so a wrong one is refused up front, naming the array."""
    world = pile()
    other = World()
    other.add_body(Circle(0.5))
    with pytest.raises(ValueError, match="'position' must be .* of shape \\(2, 4, 2\\)"):
        world.step(2, record=other.frame_buffer(2))
    wrong = world.frame_buffer(2)
    wrong["angle"] = wrong["angle"].astype(np.float32)
    with pytest.raises(ValueError, match="'angle' must be a writeable C-contiguous float64"):
        world.step(2, record=wrong)
    reordered = dict(reversed(list(world.frame_buffer(2).items())))
    with pytest.raises(ValueError, match="in that order"):
        world.step(2, record=reordered)
    assert world.tick == 0


def test_one_tick_calls_match_one_block_after_the_world_changes():
    """The step's compiled entry is found again when bodies are added between calls."""
    block, single = pile(), pile()
    block.step(5)
    for _ in range(5):
        single.step(1)
    for world in (block, single):
        world.add_body(Circle(0.2), position=(0.0, 2.0))
    block.step(20)
    for _ in range(20):
        single.step(1)
    np.testing.assert_array_equal(block.centers, single.centers)
    np.testing.assert_array_equal(block.velocities, single.velocities)


def test_max_speed_counts_active_dynamic_bodies_only():
    world = World(bounds=((-4.0, -4.0), (4.0, 4.0)))
    world.add_body(Circle(0.5), position=(0.0, 0.0), velocity=(3.0, 4.0))
    world.add_body(Circle(0.5), position=(2.0, 2.0), velocity=(9.0, 0.0), body_type="kinematic")
    world.add_body(Circle(0.5), position=(-5.0, 0.0), velocity=(0.0, 20.0))  # leaves the bounds
    world.step(1)
    assert list(world.active) == [True, True, False]
    assert world.observables()["max_speed"] == pytest.approx(5.0, rel=1e-12)


def test_diverging_block_keeps_the_frames_before_the_bad_tick():
    world = World(tick_rate=60, precision=4)
    world.add_body(Circle(0.5), position=(0.0, 0.0), velocity=(1.7e308, 0.0))  # overflows in tick 4
    frames = world.frame_buffer(10)
    with pytest.raises(rustycs.SimulationDiverged) as failure:
        world.step(10, record=frames, every=1)
    bad = failure.value.tick
    assert 1 < bad < 10
    recorded = failure.value.frames
    assert recorded == bad - 1 == world.tick - 1
    np.testing.assert_array_equal(frames["tick"][:recorded], np.arange(1, recorded + 1))
    assert np.all(np.isfinite(frames["position"][:recorded]))
