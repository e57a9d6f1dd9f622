"""Threads inside one world: a mixed pile of every shape kind steps bitwise the same with 1, 2 and 3
threads (the shapes placed, their partners found, pairs collided and lanes prepared in parts), in the
engine and through `rustycs run --threads`."""

from __future__ import annotations

import math

import h5py
import numpy as np
import pytest

from rustycs import Box, Capsule, Chain, Circle, Polygon, Segment, World
from rustycs.debug import pairs
from rustycs.threads import BODY_PART, PAIR_PART, SHAPE_PART

TICKS = 90


def every_shape_pile(threads: int) -> World:
    """240 bodies of every kind (circle, aabb, obb, polygon, concave polygon, capsule, compound) poured
    onto a chain floor between segment walls, with a kinematic paddle."""
    rng = np.random.default_rng(7)
    world = World(tick_rate=60.0, precision=4, threads=threads)
    world.add_force((0.0, -9.81))
    floor = [(x, 0.3 * math.sin(0.7 * x)) for x in np.linspace(-8.0, 8.0, 33)]
    world.add_body(Chain(floor), body_type="static")
    world.add_body([Segment([(-8.0, 0.0), (-8.0, 30.0)]), Segment([(8.0, 0.0), (8.0, 30.0)])],
                   body_type="static")
    world.add_body(Box(3.0, 0.3), position=(-5.0, 1.5), velocity=(1.5, 0.0), body_type="kinematic")
    kinds = ["circle", "aabb", "obb", "polygon", "concave", "capsule", "compound"] * 35
    for k, kind in enumerate(kinds[:240]):
        x, y = -7.0 + 0.9 * (k % 16) + rng.uniform(-0.05, 0.05), 2.0 + 0.9 * (k // 16)
        angle = rng.uniform(-math.pi, math.pi)
        shape = {"circle": Circle(0.3), "aabb": Box(0.5, 0.4, rotates=False), "obb": Box(0.6, 0.3),
                 "polygon": Polygon([(0.0, 0.0), (0.5, 0.0), (0.55, 0.35), (0.1, 0.45)]),
                 "concave": Polygon([(0, 0), (0.6, 0), (0.6, 0.2), (0.2, 0.2), (0.2, 0.5), (0, 0.5)]),
                 "capsule": Capsule(0.4, 0.15),
                 "compound": [Box(0.5, 0.15), Circle(0.15, offset=(0.3, 0.0))]}[kind]
        world.add_body(shape, position=(x, y), angle=0.0 if kind == "aabb" else angle,
                       velocity=tuple(rng.uniform(-1, 1, 2)), material="rubber" if k % 3 else "default")
    return world


def state(world: World) -> bytes:
    contacts = world.contacts()
    return np.concatenate([world.centers.ravel(), world.angles, world.velocities.ravel(),
                           world.angular_velocities, contacts["point"].ravel(),
                           contacts["normal_impulse"]]).tobytes()


def test_the_pile_is_large_enough_to_run_in_parts():
    world = every_shape_pile(1)
    world.step(TICKS)
    assert world.body_count >= 2 * BODY_PART
    assert world.shape_count >= 2 * SHAPE_PART
    assert len(pairs(world)) >= 2 * PAIR_PART


@pytest.mark.parametrize("threads", [2, 3])
def test_threads_give_bitwise_the_trajectory_of_one(threads):
    one, many = every_shape_pile(1), every_shape_pile(threads)
    for _ in range(3):
        one.step(TICKS // 3)
        many.step(TICKS // 3)
        assert state(many) == state(one)


def crowd(threads: int) -> World:
    """300 circles of radius 1 dropped within 0.4 m of one spot, 2 m above a floor: all 44,850 pairs of
    circles are candidates, more than the pair buffers first hold (4 a shape), so the first whole search
    outgrows them."""
    rng = np.random.default_rng(3)
    world = World(tick_rate=60.0, precision=4, threads=threads)
    world.add_force((0.0, -9.81))
    world.add_body(Box(40.0, 1.0), position=(0.0, -0.5), body_type="static")
    for _ in range(300):
        world.add_body(Circle(1.0), position=tuple(rng.uniform(-0.2, 0.2, 2) + (0.0, 3.0)))
    return world


def test_a_whole_search_in_parts_that_outgrows_its_buffers_finds_the_pairs_of_one_thread():
    one, many = crowd(1), crowd(2)
    one.step(1)
    many.step(1)
    found = pairs(many)
    assert len(found) == 300 * 299 // 2 > 4 * many.shape_count + 16
    assert np.array_equal(found, pairs(one))
    for _ in range(3):
        one.step(10)
        many.step(10)
        assert np.array_equal(pairs(many), pairs(one))
        assert state(many) == state(one)


def test_threads_can_change_between_steps():
    one, changing = every_shape_pile(1), every_shape_pile(2)
    one.step(40)
    changing.step(20)
    changing.threads = 1
    changing.step(10)
    changing.threads = 3
    changing.step(10)
    assert state(changing) == state(one)
    with pytest.raises(ValueError, match="threads"):
        changing.threads = 0


def test_run_threads_writes_the_same_trajectory(tmp_path, cli):
    outputs = []
    for threads in (1, 2):
        out = tmp_path / f"pile-{threads}.h5"
        done = cli("run", "scenes/pile.yaml", "--ticks", "120", "--threads", threads, "-o", out, "--quiet")
        assert done.exit_code == 0, done.stderr
        with h5py.File(out) as f:
            outputs.append(f["particles/bodies/position/value"][...])
    assert np.array_equal(outputs[0], outputs[1])
    done = cli("run", "scenes/pile.yaml", "--threads", "0")
    assert done.exit_code == 2 and "Traceback" not in done.stderr
