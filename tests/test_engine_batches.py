"""The solver's batches: the contacts are placed in chunks of LANES that share no movable body, each
body's contacts in sorted order, so that solving chunk by chunk equals solving the sorted sequence."""

from __future__ import annotations

import numpy as np
import pytest

from rustycs import Box, Circle, World, debug
from rustycs.contact_solver import LANES


def pyramid(rows: int) -> World:
    world = World(tick_rate=60, precision=4)
    world.add_force((0.0, -9.81))
    world.add_body(Box(4.0 * rows, 1.0), position=(0.0, -0.5), body_type="static")
    for row in range(rows):
        for k in range(rows - row):
            world.add_body(Box(1.0, 1.0), position=(k - 0.5 * (rows - row - 1), 0.5 + row))
    return world


def stack(height: int) -> World:
    world = World(tick_rate=60, precision=4)
    world.add_force((0.0, -9.81))
    world.add_body(Box(10.0, 1.0), position=(0.0, -0.5), body_type="static")
    for level in range(height):
        world.add_body(Box(1.0, 1.0), position=(0.0, 0.5 + level))
    return world


def heap() -> World:
    """Circles heaped in a box swept by a kinematic paddle (one-point manifolds, shared immovable
    bodies), the top row's last ones thrown up out of the bounds."""
    rng = np.random.default_rng(7)
    world = World(tick_rate=60, precision=4, bounds=((-6.0, -2.0), (6.0, 20.0)))
    world.add_force((0.0, -9.81))
    world.add_body(Box(8.0, 1.0), position=(0.0, -0.5), body_type="static")
    world.add_body(Box(1.0, 8.0), position=(-4.5, 4.0), body_type="static")
    world.add_body(Box(1.0, 8.0), position=(4.5, 4.0), body_type="static")
    world.add_body(Box(2.0, 0.3), position=(-3.0, 0.4), velocity=(2.0, 0.0), body_type="kinematic")
    for k in range(200):
        x = -3.6 + 0.4 * (k % 18) + rng.uniform(-0.02, 0.02)
        world.add_body(Circle(0.2), position=(x, 0.3 + 0.4 * (k // 18)),
                       velocity=(0.0, 25.0) if k >= 192 else (0.0, 0.0))
    return world


@pytest.mark.parametrize("world, ticks", [(pyramid(12), 30), (stack(8), 30), (heap(), 90)],
                         ids=["pyramid", "stack", "heap"])
def test_chunks_share_no_movable_body_and_keep_each_bodys_contacts_in_sorted_order(world, ticks):
    for _ in range(3):  # the slots of each tick's manifolds, whether scheduled anew or kept from the last
        world.step(ticks // 3)
        check_batches(world)


def check_batches(world: World) -> None:
    s = debug.schedule(world)
    n_chunks, slot_manifold, slot_a, slot_b = s.chunks, s.slot_manifold, s.slot_a, s.slot_b
    chunk_points = s.chunk_points
    m_a, m_b, m_count, movable = s.body_a, s.body_b, s.point_count, s.movable
    n_man = len(m_a)
    assert n_man >= 8  # the scene is in contact
    # every manifold in exactly one slot, with its bodies
    used = slot_manifold >= 0
    assert np.array_equal(np.sort(slot_manifold[used]), np.arange(n_man))
    assert np.array_equal(slot_a[used], m_a[slot_manifold[used]])
    assert np.array_equal(slot_b[used], m_b[slot_manifold[used]])
    chunk_of = np.empty(n_man, np.int64)
    chunk_of[slot_manifold[used]] = np.nonzero(used)[0] // LANES
    for c in range(n_chunks):
        members = slot_manifold[c * LANES:(c + 1) * LANES]
        members = members[members >= 0]
        assert len(members) > 0
        bodies = np.concatenate([m_a[members], m_b[members]])
        moving = bodies[movable[bodies]]
        assert len(np.unique(moving)) == len(moving), f"chunk {c} shares a movable body"
        assert chunk_points[c] == m_count[members].max()
    for i in np.nonzero(movable)[0]:
        chunks = chunk_of[(m_a == i) | (m_b == i)]  # the body's manifolds in sorted order
        assert np.all(np.diff(chunks) > 0), f"body {i}'s contacts are out of order"


def test_contacts_fill_the_lanes_when_their_chains_are_short():
    """A wide pyramid has short chains of contacts that must follow each other: its chunks are full;
    a stack is one chain: one contact per chunk."""
    wide = pyramid(16)
    wide.step(30)
    s = debug.schedule(wide)
    assert len(s.body_a) / (s.chunks * LANES) > 0.5
    tall = stack(8)
    tall.step(30)
    s = debug.schedule(tall)
    assert s.chunks == len(s.body_a) == 8
