"""The engine's events, sensors, emitted bodies, sinks, measures and stop conditions, against closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest

import rustycs

G = 9.81


def _drop(tick_rate: float = 240.0, height: float = 2.0, sensor: bool = True) -> tuple[rustycs.World, dict]:
    """A 0.1 m ball whose bottom is `height` above a floor, and a sensor box from 0.75 to 1.25 m."""
    world = rustycs.World(tick_rate=tick_rate)
    world.add_force((0.0, -G))
    rows = {"floor": world.add_body(rustycs.Box(10, 1), position=(0, -0.5), body_type="static"),
            "ball": world.add_body(rustycs.Circle(0.1), position=(0, height + 0.1))}
    if sensor:
        rows["goal"] = world.add_body(rustycs.Box(1, 0.5, sensor=True), position=(0, 1.0),
                                      body_type="static")
    return world, rows


def _tick_of(fall: float, tick_rate: float) -> float:
    """The tick (fractional) at which a body dropped from rest has fallen `fall` metres."""
    return math.sqrt(2 * fall / G) * tick_rate


def test_first_contact_of_a_dropped_ball_stops_the_run_within_3_ticks_of_sqrt_2h_over_g() -> None:
    world, rows = _drop()
    impact = world.add_measure("first", event="contact_begin", bodies=[rows["ball"]], others=[rows["floor"]])
    world.add_stop_condition("event", event="contact_begin", bodies=[rows["ball"]], others=[rows["floor"]])
    world.step(1000)
    expected = _tick_of(2.0, 240)  # 153.3
    assert world.stop_condition == 0 and abs(world.tick - expected) <= 3
    assert world.measure_results()[impact] == pytest.approx(world.tick / 240, abs=1e-12)
    events = world.events()
    begin = list(events["kind"]).index("contact_begin")
    assert events["tick"][begin] == world.tick
    # the approach speed is the ball's speed at the start of the tick it touched in: g (tick - 1) dt
    assert events["speed"][begin] == pytest.approx(G * (world.tick - 1) / 240, rel=1e-9)


def test_a_speculative_contact_does_not_begin() -> None:
    world, rows = _drop(height=0.05, sensor=False)  # within the speculative reach from the first tick
    world.contact_events = True
    world.step(1)
    assert "contact_begin" not in list(world.events()["kind"])  # 5 cm apart, 0.04 m/s closing: no touch
    world.step(60)
    assert list(world.events()["kind"]).count("contact_begin") == 1


def test_sensor_enter_and_exit_ticks_of_a_falling_ball_and_its_velocity_untouched() -> None:
    world, rows = _drop()
    inside = world.add_measure("time_inside", bodies=[rows["ball"]], sensor=rows["goal"])
    plain, _ = _drop(sensor=False)
    world.step(140)
    plain.step(140)
    events = world.events()
    ticks = {kind: tick for kind, tick in zip(events["kind"], events["tick"], strict=True)}
    # the ball (centre 2.1 m, radius 0.1) overlaps the box (0.75 .. 1.25 m) with its centre in 0.65 .. 1.35
    assert abs(ticks["sensor_enter"] - _tick_of(2.1 - 1.35, 240)) <= 2
    assert abs(ticks["sensor_exit"] - _tick_of(2.1 - 0.65, 240)) <= 2
    time_inside = (ticks["sensor_exit"] - ticks["sensor_enter"]) / 240
    assert world.measure_results()[inside] == pytest.approx(time_inside)
    assert np.array_equal(world.velocities[1], plain.velocities[1])  # a sensor pushes nothing
    assert np.array_equal(world.positions[1], plain.positions[1])


def test_inside_stop_condition_holds_after_its_time_without_a_break() -> None:
    world = rustycs.World(tick_rate=60)
    ball = world.add_body(rustycs.Circle(0.1), position=(0, 0))  # no gravity: it stays in the goal
    goal = world.add_body(rustycs.Circle(1.0, sensor=True), position=(0, 0), body_type="static")
    world.add_stop_condition("inside", sensor=goal, bodies=[ball], hold_ticks=90)
    world.step(1000)
    assert world.stop_condition == 0 and world.tick == 90  # inside from tick 1 on: 90 ticks at tick 90


def test_emitted_bodies_appear_in_their_ticks_and_lifetimes_and_sinks_remove_them() -> None:
    world = rustycs.World(tick_rate=60)
    world.add_force((0.0, -G))
    spawn = [3 * k for k in range(6)]  # tick 0: there from the start
    rows = [world.add_body(rustycs.Circle(0.05), position=(2.0 * k, 0.0), spawn_tick=t,
                           remove_tick=t + 10 if k % 2 else None) for k, t in enumerate(spawn)]
    world.add_sink((-1, -100), (1, -0.5))  # under the first body only
    assert list(world.active) == [True] + [False] * 5
    assert list(world.spawn_ticks) == spawn
    world.step(40)
    events = world.events()
    seen = [(str(k), int(t), int(a))
            for k, t, a in zip(events["kind"], events["tick"], events["a"], strict=True)]
    assert [e for e in seen if e[0] == "spawn"] == [("spawn", t, r)
                                                    for t, r in zip(spawn[1:], rows[1:], strict=True)]
    lifetimes = sorted(e for e in seen if e[0] == "remove" and e[2] != rows[0])
    assert lifetimes == sorted(("remove", spawn[k] + 10, rows[k]) for k in (1, 3, 5))
    sunk = [e for e in seen if e[0] == "remove" and e[2] == rows[0]]
    assert sunk == [("remove", math.ceil(_tick_of(0.5, 60)), rows[0])]  # its centre passed -0.5 m
    assert list(world.active) == [False, False, True, False, True, False]


def test_count_inside_histogram_and_aggregates_over_known_positions_are_exact() -> None:
    world = rustycs.World(tick_rate=60)  # no forces: the bodies stay where they are
    xs = [-2.5, -1.0, -0.25, 0.0, 0.75, 2.0, 3.5]
    rows = [world.add_body(rustycs.Circle(0.1), position=(x, 0.1 * k)) for k, x in enumerate(xs)]
    measures = [
        world.add_measure("count_inside", bodies=rows, region=(-1.0, -1.0, 1.0, 1.0)),
        world.add_measure("histogram", bodies=rows, quantity="position.x", edges=[-2, -1, 0, 1, 2]),
        world.add_measure("value", bodies=rows, quantity="position.x", aggregate="mean"),
        world.add_measure("value", bodies=rows, quantity="position.x", aggregate="median"),
        world.add_measure("value", bodies=rows, quantity="position.y", aggregate="max"),
        world.add_measure("value", bodies=rows, quantity="position.x", aggregate="sum", reduce="at",
                          at_tick=5),
        world.add_measure("value", bodies=rows[:0], quantity="position.x", aggregate="mean"),
    ]
    world.step(10)
    results = world.measure_results()
    assert [results[m] for m in measures] == [
        4.0, [0, 2, 2, 1], sum(xs) / len(xs), 0.0, 0.1 * 6, sum(xs), results[measures[-1]]]
    assert math.isnan(results[measures[-1]])  # an empty set: no value


def test_extremes_and_means_over_the_ticks_of_a_free_fall() -> None:
    world = rustycs.World(tick_rate=100)
    world.add_force((0.0, -G))
    ball = world.add_body(rustycs.Circle(0.1), position=(0, 0), velocity=(1.0, 5.0))
    apex, lowest, mean_vx, start, at = (
        world.add_measure("value", bodies=[ball], quantity="position.y", reduce="max"),
        world.add_measure("value", bodies=[ball], quantity="position.y", reduce="min"),
        world.add_measure("value", bodies=[ball], quantity="velocity.x", reduce="mean"),
        world.add_measure("value", bodies=[ball], quantity="velocity.y", reduce="initial"),
        world.add_measure("value", bodies=[ball], quantity="position.x", reduce="at", at_tick=50))
    world.step(110)  # down below its start by then
    results = world.measure_results()
    assert results[apex] == pytest.approx(5.0**2 / (2 * G), rel=0.01)  # the integrator's own error
    assert results[lowest] == pytest.approx(world.positions[0, 1]) and results[start] == 5.0
    assert results[mean_vx] == pytest.approx(1.0, rel=1e-12) and results[at] == pytest.approx(0.5, rel=1e-12)


def test_if_free_bodies_appear_only_where_nothing_collidable_is() -> None:
    world = rustycs.World(tick_rate=60)  # no forces: nothing moves
    world.add_body(rustycs.Box(20.0, 1.0), position=(0, -0.5), body_type="static")  # top at y = 0
    world.add_body(rustycs.Box(0.2, 0.2, sensor=True), position=(5, 2), body_type="static")  # no obstacle
    blocker = world.add_body(rustycs.Circle(0.5), position=(3, 1), collision_group=-2)
    tap = [world.add_body(rustycs.Circle(0.5), position=(0, 1), spawn_tick=t, if_free=True) for t in (1, 2)]
    beside = world.add_body(rustycs.Circle(0.5), position=(1.2, 1), spawn_tick=4, if_free=True)  # 1.2 m away
    sensed = world.add_body(rustycs.Circle(0.5), position=(5, 2.2), spawn_tick=4, if_free=True)  # in a sensor
    grouped = world.add_body(rustycs.Circle(0.5), position=(3.5, 1), spawn_tick=4, if_free=True,
                             collision_group=-2)  # never collides with the blocker
    low = world.add_body(rustycs.Circle(0.5), position=(-3, 0.45), spawn_tick=4, if_free=True)  # in the floor
    loose = world.add_body(rustycs.Circle(0.5), position=(0, 1), spawn_tick=5)  # placement free: appears
    first, second = (world.add_body(rustycs.Circle(0.5), position=(-6, 1), if_free=True) for _ in range(2))
    world.step(6)  # the bodies there from the start are placed in row order when the first step begins
    events = world.events()
    spawned = [int(a) for k, a in zip(events["kind"], events["a"], strict=True) if k == "spawn"]
    assert spawned == [tap[0], beside, sensed, grouped, loose]  # in tick order, then row order
    assert [int(i) for i in np.flatnonzero(world.skipped)] == [tap[1], low, second]
    assert world.active[first] and not world.active[second]
    assert world.spawn_ticks[tap[1]] == -1 and world.spawn_ticks[low] == -1 and world.spawn_ticks[tap[0]] == 1
    assert not world.active[tap[1]] and world.active[blocker]
    world.add_force((0.0, 0.0))  # the kernels' inputs are rebuilt: what was skipped stays so
    world.step(1)
    assert [int(i) for i in np.flatnonzero(world.skipped)] == [tap[1], low, second]
