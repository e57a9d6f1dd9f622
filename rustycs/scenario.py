"""What a run does beyond the physics, at the end of every tick: bodies appear and vanish, sensors sense,
measures fold the tick in, stop conditions are checked. One record, so that the step takes one argument
for all of it; each part is empty (and costs nothing) when the world has none.
"""

from __future__ import annotations

from typing import NamedTuple

from rustycs.compiling import inlined, tick_kernel
from rustycs.emitters import Lifecycle, appear_and_vanish
from rustycs.measures import Measures, fold
from rustycs.sensors import Sensors, sense
from rustycs.stop_conditions import StopConditions, first_held

EVENT_MARGIN = 16  # rows of the events buffer kept free beyond a tick's bound


class Scenario(NamedTuple):
    life: Lifecycle
    sensors: Sensors
    measures: Measures
    stops: StopConditions


@tick_kernel
def events_bound(n_sensor_bodies, n_bodies, n_joints, n_manifolds, n_touching):
    """The most events a tick can record: a contact begins or ends per manifold now and pair touching
    before, a body escapes, appears or is removed, enters or leaves each sensor body, a joint breaks."""
    return n_manifolds + n_touching + n_bodies * (2 + n_sensor_bodies) + n_joints + EVENT_MARGIN


@inlined
def has_scenario(scenario):
    """Whether the scenario does anything at the end of a tick (most worlds: no)."""
    return (scenario.life.timed.shape[0] > 0 or scenario.life.sinks.shape[0] > 0
            or scenario.sensors.body.shape[0] > 0 or scenario.measures.form.shape[0] > 0
            or scenario.stops.kind.shape[0] > 0)


@tick_kernel
def after_tick(scenario, bodies, shapes, forces, contacts, events, first_event, tick, dt):
    """Everything but the physics at the end of `tick`, whose events so far are events[first_event:];
    returns the first stop condition that holds (-1: none)."""
    appear_and_vanish(scenario.life, bodies, shapes, tick, events)
    if scenario.sensors.body.shape[0] > 0:
        sense(scenario.sensors, bodies, shapes, tick, events)
    if scenario.measures.form.shape[0] > 0:
        fold(scenario.measures, bodies, forces, contacts, scenario.sensors, events, first_event, tick, dt)
    if scenario.stops.kind.shape[0] == 0:
        return -1
    return first_held(scenario.stops, bodies, scenario.sensors, events, first_event)
