"""The World's part that asks a run questions: bodies that appear and vanish, sinks, sensors, measures and
stop conditions (a base class of `rustycs.World`, kept apart from the physics)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from rustycs.emitters import NEVER, new_lifecycle, place_at_start
from rustycs.events import CONTACT_BEGIN, CONTACT_END, EVENT_KIND_NAMES
from rustycs.measures import MeasureBook, finish, fold
from rustycs.pieces import MAX_VERTICES
from rustycs.scenario import Scenario
from rustycs.sensors import new_sensors
from rustycs.stop_conditions import StopBook

_CONTACT_KINDS = (EVENT_KIND_NAMES[CONTACT_BEGIN], EVENT_KIND_NAMES[CONTACT_END])


class WorldScenario:
    """Sinks, measures and stop conditions of a World, and when its bodies appear and go."""

    def _init_scenario(self) -> None:
        self.contact_events = False
        self._spawn_tick: list[int] = []
        self._remove_tick: list[int] = []
        self._if_free: list[bool] = []
        self._skipped = np.zeros(0, np.bool_)  # filled by the step; kept when the kernels' inputs are rebuilt
        self._sinks: list[list[float]] = []
        self._measures = MeasureBook()
        self._stops = StopBook()
        self._measured = None  # the compiled measures, kept from step to step
        self._initial_folded = False

    def _timing(self, spawn_tick: int, remove_tick: int | None, if_free: bool) -> bool:
        """Keep when a new body appears and goes; returns whether it is there from the start."""
        if spawn_tick < 0 or (remove_tick is not None and remove_tick <= spawn_tick):
            raise ValueError("a body appears at a tick >= 0 and is removed after it appears")
        self._spawn_tick.append(int(spawn_tick))
        self._remove_tick.append(NEVER if remove_tick is None else int(remove_tick))
        self._if_free.append(bool(if_free))
        return spawn_tick == 0

    def add_sink(self, lower, upper) -> None:
        """A region (lower-left and upper-right corners) that removes every dynamic body whose centre of
        mass enters it (a `remove` event each)."""
        self._sinks.append([*map(float, lower), *map(float, upper)])
        self._scenario_changed()

    def sensor_slot(self, body: int) -> int:
        """The row of a sensor body among the world's sensor bodies (-1: it has no sensor shape)."""
        shapes = self._shapes.view()
        sensor_bodies = np.unique(shapes.body[shapes.sensor])
        found = np.flatnonzero(sensor_bodies == body)
        return int(found[0]) if len(found) else -1

    def add_measure(self, form: str, *, bodies: Sequence[int] = (), sensor: int | None = None, **keys) -> int:
        """A measure (see `rustycs.measures`), folded at the end of every tick: form value, count_inside,
        histogram, first or time_inside; keys: others, quantity, aggregate, reduce, at_tick, region,
        edges, event. Returns its index in `measure_results()`."""
        slot = -1 if sensor is None else self._sensor_required(sensor)
        index = self._measures.add(form, bodies=bodies, sensor_slot=slot, **keys)
        self._scenario_changed()
        return index

    def add_stop_condition(self, kind: str, *, sensor: int | None = None, **keys) -> int:
        """A condition that ends `step` at the end of the first tick where it holds (`stop_condition` then
        names it): kind at_rest, event or inside; keys: hold_ticks, event, bodies, others."""
        slot = -1 if sensor is None else self._sensor_required(sensor)
        index = self._stops.add(kind, sensor_slot=slot, **keys)
        self._scenario_changed()
        return index

    def _sensor_required(self, body: int) -> int:
        slot = self.sensor_slot(body)
        if slot < 0:
            raise ValueError(f"body {body} has no sensor shape")
        return slot

    def _scenario_changed(self) -> None:
        if self.tick > 0:
            raise ValueError("sinks, measures and stop conditions are added before the first step")
        self._remake()
        self._measured = None

    @property
    def spawn_ticks(self) -> np.ndarray:
        """(N,) the tick at whose end each body appears (0: there from the start; -1: a body `skipped`,
        that never appears)."""
        return np.where(self.skipped, -1, np.array(self._spawn_tick, dtype=np.int64))

    @property
    def skipped(self) -> np.ndarray:
        """(N,) bool: the bodies added with `if_free` that did not appear, their place being taken."""
        skipped = np.zeros(len(self._spawn_tick), np.bool_)
        skipped[: len(self._skipped)] = self._skipped
        return skipped

    def _records_contacts(self) -> bool:
        rows = (*self._measures.rows, *self._stops.rows)
        return self.contact_events or any(
            row["event"] >= 0 and EVENT_KIND_NAMES[row["event"]] in _CONTACT_KINDS for row in rows)

    def _scenario(self, bodies, shapes) -> Scenario:
        """The step's scenario record for these body and shape records (the measures' results carry over
        while the world is the same)."""
        if self._measured is None:
            self._measured = self._measures.compiled()
        self._skipped = self.skipped  # a row for every body, those skipped so far kept
        life = new_lifecycle(np.array(self._spawn_tick, np.int64), np.array(self._remove_tick, np.int64),
                             np.array(self._sinks, np.float64), np.array(self._if_free, np.bool_),
                             self._skipped)
        if self.tick == 0:
            place_at_start(life, bodies, shapes)
        return Scenario(life, new_sensors(bodies, shapes, MAX_VERTICES), self._measured,
                        self._stops.compiled())

    def _fold_initial(self, inputs) -> None:
        """Fold the initial state (tick 0) into the measures, once, before the first tick."""
        if self._initial_folded or self.tick > 0:
            return
        self._initial_folded = True
        scenario = inputs.scenario
        if scenario.measures.form.shape[0] == 0:
            return  # typing the records for a call of `fold` is a fifth of a five-body world's first block
        fold(scenario.measures, inputs.bodies, inputs.forces, self._contacts_record(), scenario.sensors,
             self._empty_events(), 0, 0, self.dt)

    @staticmethod
    def _empty_events():
        from rustycs.events import new_events

        return new_events(0)

    def measure_results(self) -> list[float | list[int]]:
        """Each measure's result now: a number (NaN where there is none: an empty set, an event that did
        not happen) or a histogram's counts per bin; final values are those of the present state."""
        inputs = self._kernel_inputs()
        finish(inputs.scenario.measures, inputs.bodies, inputs.forces, self._contacts_record())
        return self._measures.results(inputs.scenario.measures)
