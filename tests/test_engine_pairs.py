"""The broad phase's pairs are found for fat hitboxes and kept while the bodies stay inside them: they
must always include every pair whose hitboxes overlap, and be found again only when needed."""

from __future__ import annotations

import numpy as np
from test_engine_batches import heap

from rustycs import Box, Circle, World, debug


def stored_pairs(world: World) -> set[tuple[int, int]]:
    return {(int(a), int(b)) for a, b in debug.pairs(world)}


def overlapping_pairs(world: World) -> set[tuple[int, int]]:
    """Every pair of active bodies, one of them dynamic, whose hitboxes overlap (brute force; the bodies
    here have one shape each, so shape rows are body indices)."""
    box = debug.hitboxes(world)
    active = world.active
    moving = world.body_types == "dynamic"
    found = set()
    for i in range(world.body_count):
        for j in range(i + 1, world.body_count):
            if not (active[i] and active[j] and (moving[i] or moving[j])):
                continue
            if (box[i, 0] <= box[j, 2] and box[j, 0] <= box[i, 2]
                    and box[i, 1] <= box[j, 3] and box[j, 1] <= box[i, 3]):
                found.add((i, j))
    return found


def test_kept_pairs_always_include_every_overlapping_pair():
    world = heap()
    for _ in range(40):
        world.step(3)
        missing = overlapping_pairs(world) - stored_pairs(world)
        assert not missing, f"tick {world.tick}: pairs {sorted(missing)[:5]} not in the broad phase"
    assert not world.active.all()  # bodies left the bounds and were switched off


def test_pairs_are_kept_while_a_stack_rests_and_found_again_when_a_body_moves():
    world = World(tick_rate=60, precision=4)
    world.add_force((0.0, -9.81))
    world.add_body(Box(10.0, 1.0), position=(0.0, -0.5), body_type="static")
    for level in range(4):
        world.add_body(Box(1.0, 1.0), position=(0.0, 0.5 + level))
    ball = world.add_body(Circle(0.2), position=(3.0, 5.0))
    world.step(200)  # the stack rests, the ball lies on the floor
    fat = debug.fat_hitboxes(world)
    world.step(60)
    assert np.array_equal(debug.fat_hitboxes(world), fat)  # no body left its fat hitbox
    world.set_velocity(ball, (-6.0, 0.0))  # rolls towards the stack
    world.step(28)  # it hits the bottom box (and bounces back)
    assert not np.array_equal(debug.fat_hitboxes(world)[ball], fat[ball])
    assert (1, ball) in stored_pairs(world)


def test_a_world_whose_filters_keep_every_shape_apart_has_no_broad_phase_and_one_outsider_collides():
    """Bench S6: 200 bodies that share one collision group only feel the attractor; the broad phase was
    half of their tick, finding no pair. Such a world finds none at all; one body outside the group gets
    its pairs and collides."""
    def crossing(outsider_group: int) -> World:
        world = World(tick_rate=60.0, precision=4)
        world.add_body(Circle(0.5), position=(-2.0, 0.0), velocity=(2.0, 0.0), collision_group=1)
        world.add_body(Circle(0.5), position=(2.0, 0.0), velocity=(-2.0, 0.0), collision_group=outsider_group)
        world.add_body(Box(10.0, 1.0), position=(0.0, -3.0), body_type="static", collision_group=1)
        return world

    apart = crossing(1)
    apart.step(60)
    assert len(debug.pairs(apart)) == 0
    np.testing.assert_allclose(apart.centers[:2, 0], [0.0, 0.0], atol=1e-12)  # passed through each other
    meeting = crossing(0)
    meeting.step(45)  # they meet at 0.75 s
    assert len(debug.pairs(meeting)) == 1
    meeting.step(15)
    assert meeting.centers[0, 0] < -0.5 < 0.5 < meeting.centers[1, 0]  # they met and bounced back


def test_a_turning_wall_with_hundreds_of_partners_gets_exactly_the_pairs_of_its_fat_hitbox_in_order():
    """A long kinematic wall turned 45 degrees, its hitbox over a field of 400 circles (a tumbler's drum
    wall): its partners are found in cell order and sorted as a run (heapsort above 32 partners). The
    pairs are exactly those of overlapping fat hitboxes, each once, sorted by (a, b)."""
    rng = np.random.default_rng(7)
    world = World(tick_rate=60, precision=4)
    world.add_body(Box(30.0, 0.5), position=(0.0, 0.0), angle=np.pi / 4, angular_velocity=0.5,
                   body_type="kinematic")
    for x, y in rng.uniform(-9.0, 9.0, size=(400, 2)):
        world.add_body(Circle(0.2), position=(float(x), float(y)), velocity=(0.0, -1.0))
    for _ in range(5):
        world.step(1)
        found = debug.pairs(world)
        fat = debug.fat_hitboxes(world)
        overlap = ((fat[:, None, 0] <= fat[None, :, 2]) & (fat[None, :, 0] <= fat[:, None, 2])
                   & (fat[:, None, 1] <= fat[None, :, 3]) & (fat[None, :, 1] <= fat[:, None, 3]))
        expected = np.argwhere(np.triu(overlap, 1))  # row-major: sorted by (a, b)
        np.testing.assert_array_equal(found, expected)
        assert (found[:, 0] == 0).sum() > 100  # the wall's run is long enough for the heapsort


def test_shapes_that_leave_their_fat_hitboxes_alone_get_their_pairs_found_again():
    """Boxes tumbling in a turning drum of four walls (bench tumbler, smaller): on many ticks a few dozen
    shapes leave their fat hitboxes, and only theirs are found again (`refresh_pairs`), the others' fat
    hitboxes kept (the walls, turning, leave theirs on most ticks). The pairs are always exactly those of
    overlapping fat hitboxes, each once, sorted by (a, b)."""
    world = World(tick_rate=60, precision=4)
    world.add_force((0.0, -10.0))
    walls = [Box(0.5, 10.0, offset=(5.0, 0.0)), Box(0.5, 10.0, offset=(-5.0, 0.0)),
             Box(10.0, 0.5, offset=(0.0, 5.0)), Box(10.0, 0.5, offset=(0.0, -5.0))]
    world.add_body(walls, position=(0.0, 0.0), angular_velocity=0.5, body_type="kinematic")
    for k in range(300):
        world.add_body(Box(0.25, 0.25), position=(-4.0 + 0.4 * (k % 20), -4.0 + 0.4 * (k // 20)))
    world.step(120)  # the pile falls and tumbles
    partial = 0
    fat = debug.fat_hitboxes(world)
    for _ in range(60):
        world.step(1)
        found = debug.pairs(world)
        now = debug.fat_hitboxes(world)
        changed = (now != fat).any(axis=1)
        partial += 0 < changed.sum() < 0.5 * len(changed)
        fat = now
        overlap = ((fat[:, None, 0] <= fat[None, :, 2]) & (fat[None, :, 0] <= fat[:, None, 2])
                   & (fat[:, None, 1] <= fat[None, :, 3]) & (fat[None, :, 1] <= fat[:, None, 3]))
        overlap[:4, :4] = False  # the drum's own walls
        expected = np.argwhere(np.triu(overlap, 1))  # row-major: sorted by (a, b)
        np.testing.assert_array_equal(found, expected)
    assert partial > 15  # ticks that found the pairs of a few shapes again, not all (29 of 60)
