"""Batches of worlds: every world of a batch steps bitwise as it does alone, for any thread count, in
blocks and one tick per call, with recording, growing buffers, stop conditions and a divergence."""

from __future__ import annotations

import numpy as np
import pytest

from rustycs import Box, Circle, Polygon, SimulationDiverged, World
from rustycs.batch import WorldBatch


def small_world(seed: int) -> World:
    """Five bodies of mixed shapes thrown onto a floor, different for every seed."""
    rng = np.random.default_rng(seed)
    world = World(tick_rate=60.0, precision=4)
    world.add_force((0.0, -9.81))
    world.add_body(Box(20.0, 1.0), position=(0.0, -0.5), body_type="static")
    shapes = [Circle(0.3), Box(0.5, 0.4), Polygon([(0, 0), (0.6, 0), (0.2, 0.5)]), Circle(0.2), Box(0.3, 0.3)]
    for k, shape in enumerate(shapes):
        world.add_body(shape, position=(rng.uniform(-3, 3), 1.0 + k), velocity=tuple(rng.uniform(-2, 2, 2)),
                       angular_velocity=rng.uniform(-3, 3), material="rubber" if k % 2 else "default")
    return world


def heap(seed: int) -> World:
    """40 circles dropped on one spot: their pairs outgrow the first buffers, so the step grows them."""
    world = World(tick_rate=60.0, precision=4)
    world.add_force((0.0, -9.81))
    world.add_body(Box(40.0, 1.0), position=(0.0, -0.5), body_type="static")
    for k in range(40):
        world.add_body(Circle(0.5), position=(0.001 * k + 0.01 * seed, 3.0 + 0.001 * k))
    return world


def state(world: World) -> bytes:
    return np.concatenate([world.centers.ravel(), world.angles, world.velocities.ravel(),
                           world.angular_velocities, [world.tick]]).tobytes()


@pytest.mark.parametrize("threads", [1, 2, 3])
def test_a_batch_steps_every_world_bitwise_as_alone(threads):
    alone = [small_world(seed) for seed in range(7)] + [heap(seed) for seed in range(3)]
    together = [small_world(seed) for seed in range(7)] + [heap(seed) for seed in range(3)]
    for world in alone:
        for _ in range(20):
            world.step(1)
        world.step(100)
    with WorldBatch(together, threads=threads) as batch:
        for _ in range(20):
            batch.step(1)
        batch.step(100)
        assert batch.ticks.tolist() == [120] * 10
    assert [state(w) for w in together] == [state(w) for w in alone]
    assert [w.tick for w in together] == [120] * 10


def test_a_batch_records_each_world_as_alone():
    alone, together = [small_world(seed) for seed in range(4)], [small_world(seed) for seed in range(4)]
    expected = []
    for world in alone:
        frames = world.frame_buffer(10)
        assert world.step(30, record=frames, every=3) == 10
        expected.append(frames)
    records = [world.frame_buffer(10) for world in together]
    with WorldBatch(together, threads=2) as batch:
        assert batch.step(30, records=records, every=3).tolist() == [10] * 4
    for got, want in zip(records, expected, strict=True):
        for name in want:
            assert np.array_equal(got[name], want[name]), name


def test_worlds_of_a_batch_can_still_be_changed_and_stepped_alone():
    alone, together = small_world(1), small_world(1)
    batch = WorldBatch([small_world(0), together])
    batch.step(10)
    alone.step(10)
    for world in (alone, together):  # a change of make-up and of a setting between the batch's steps
        world.add_body(Circle(0.25), position=(0.0, 4.0))
        world.precision = 6
    batch.step(10)
    alone.step(10)
    together.step(5)
    alone.step(5)
    assert state(together) == state(alone) and together.tick == 25
    batch.step(1)
    assert batch.ticks.tolist() == [21, 26]
    # stepped alone with a record, a world's stepper is made again: the batch steps the new one
    together.step(2, record=together.frame_buffer(2))
    batch.step(3)
    alone.step(1)
    alone.step(2, record=alone.frame_buffer(2))
    alone.step(3)
    assert state(together) == state(alone) and batch.ticks.tolist() == [24, 31]


def test_a_stop_condition_ends_only_its_worlds_block():
    stopping, going = small_world(2), small_world(3)
    stopping.add_stop_condition("event", event="contact_begin")
    with WorldBatch([stopping, going], threads=2) as batch:
        batch.step(200)
    assert stopping.stop_condition == 0 and stopping.tick < 200
    assert going.stop_condition is None and going.tick == 200


def test_a_divergence_raises_for_its_world_after_every_block():
    calm, broken, also = small_world(4), small_world(5), small_world(6)
    broken.set_velocity(2, (np.nan, 0.0))
    also.set_velocity(3, (0.0, np.inf))
    with WorldBatch([calm, broken, also]) as batch:
        with pytest.raises(SimulationDiverged) as error:
            batch.step(10)
        found = batch.divergences()
    assert error.value.body == 2 and broken.tick == 1 and also.tick == 1
    assert calm.tick == 10
    assert sorted(found) == [1, 2] and (found[1].body, found[2].body) == (2, 3)


def test_a_batch_refuses_what_it_cannot_step():
    world = small_world(0)
    with pytest.raises(ValueError, match="at least one"):
        WorldBatch([])
    with pytest.raises(ValueError, match="once"):
        WorldBatch([world, world])
    with pytest.raises(ValueError, match="threads"):
        WorldBatch([world], threads=0)
    with pytest.raises(ValueError, match="frame buffers"):
        WorldBatch([world]).step(3, records=[])
