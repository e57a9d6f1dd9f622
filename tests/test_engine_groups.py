"""The solver's groups: islands of bodies that share no moving body are solved group after group (or
side by side on threads), and each body moves exactly as it would in a world of its island alone."""

from __future__ import annotations

import numpy as np
import pytest

from rustycs import Box, World, debug
from rustycs.constants import SOLVE_GROUP_MANIFOLDS
from rustycs.contact_solver import LANES

BASE = 10  # a pyramid of base 10: 55 boxes, 145 manifolds (45 side by side, 90 above, 10 on the floor)
SPACING = 12.0  # m between pyramids: no pair between two of them
PYRAMIDS = 30  # 4,350 manifolds: more than one group's
TICKS = 40


def pyramids(which: list[int], threads: int = 1) -> World:
    """The pyramids `which` of a row of PYRAMIDS on one floor, each where it stands in the full row."""
    world = World(tick_rate=60, precision=4, threads=threads)
    world.add_force((0.0, -9.81))
    world.add_body(Box(SPACING * PYRAMIDS, 1.0), position=(0.5 * SPACING * (PYRAMIDS - 1), -0.5),
                   body_type="static")
    for p in which:
        for row in range(BASE):
            for k in range(BASE - row):
                world.add_body(Box(1.0, 1.0), position=(SPACING * p + k - 0.5 * (BASE - row - 1), 0.5 + row))
    return world


def state(world: World, bodies: slice) -> bytes:
    return np.concatenate([world.centers[bodies].ravel(), world.angles[bodies],
                           world.velocities[bodies].ravel(), world.angular_velocities[bodies]]).tobytes()


@pytest.fixture(scope="module")
def row() -> World:
    world = pyramids(list(range(PYRAMIDS)))
    world.step(TICKS)
    return world


def test_the_row_has_more_manifolds_than_a_group():
    assert 145 * PYRAMIDS > SOLVE_GROUP_MANIFOLDS  # else one group holds them all


def test_the_groups_share_no_moving_body_and_hold_their_islands_chunks(row):
    s = debug.schedule(row)
    groups = s.group_bodies
    assert len(groups) == 3  # 28 pyramids (4,060 manifolds), 2 pyramids, and the static floor
    assert list(groups[-1]) == [0]
    body_group = np.full(row.body_count, -1)
    for g, members in enumerate(groups):
        assert np.all(body_group[members] == -1), "a body is in two groups"
        body_group[members] = g
    assert np.all(body_group >= 0)
    used = s.slot_manifold >= 0
    chunk_group = np.searchsorted(s.group_chunks, np.arange(s.chunks), side="right") - 1
    slot_group = np.repeat(chunk_group, LANES)[used]
    for bodies in (s.slot_a[used], s.slot_b[used]):
        moving = s.movable[bodies]
        assert np.array_equal(body_group[bodies[moving]], slot_group[moving])
    assert s.group_chunks[-1] == s.chunks


@pytest.mark.parametrize("pyramid", [0, PYRAMIDS - 1])
def test_a_pyramid_of_the_row_moves_as_it_does_alone(row, pyramid):
    alone = pyramids([pyramid])
    alone.step(TICKS)
    boxes = BASE * (BASE + 1) // 2
    first = 1 + pyramid * boxes
    assert state(row, slice(first, first + boxes)) == state(alone, slice(1, 1 + boxes))
    assert abs(alone.centers[-1, 1] - (BASE - 0.5)) < 0.05  # it stands


@pytest.mark.parametrize("threads", [2, 3])
def test_groups_on_threads_give_bitwise_the_trajectory_of_one(row, threads):
    many = pyramids(list(range(PYRAMIDS)), threads)
    many.step(TICKS)
    everything = slice(0, row.body_count)
    assert state(many, everything) == state(row, everything)
