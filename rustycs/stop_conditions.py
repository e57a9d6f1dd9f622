"""Stop conditions: the run ends at the end of the first tick where one of them holds.

- at_rest: every active dynamic body has been at rest (speed and angular speed below `AT_REST_SPEED`
  and `AT_REST_ANGULAR_SPEED`) for a number of ticks in a row;
- event: an event of a kind involving given bodies happened in the tick;
- inside: every listed body has overlapped a sensor body for a number of ticks in a row.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from rustycs.body_types import DYNAMIC
from rustycs.compiling import tick_kernel
from rustycs.constants import AT_REST_ANGULAR_SPEED, AT_REST_SPEED
from rustycs.events import EVENT_KIND_NAMES, involves

AT_REST, EVENT, INSIDE = range(3)
CONDITION_NAMES = ("at_rest", "event", "inside")


class StopConditions(NamedTuple):
    """The conditions (C rows) and how long each has held. Body lists are concatenated: condition c's are
    members[first[c]:first[c + 1]]."""

    kind: np.ndarray  # (C,) int64 AT_REST, EVENT or INSIDE
    hold: np.ndarray  # (C,) int64 ticks in a row it must hold (AT_REST, INSIDE)
    event: np.ndarray  # (C,) int64 the event kind of EVENT
    sensor: np.ndarray  # (C,) int64 the slot (`Sensors.body`) of INSIDE's sensor body
    first: np.ndarray  # (C + 1,) int64 into members
    members: np.ndarray  # int64 bodies
    other_first: np.ndarray  # (C + 1,) int64 into others: EVENT's second list (may be empty)
    others: np.ndarray  # int64 bodies
    held: np.ndarray  # (C,) int64 ticks in a row it has held so far


class StopBook:
    """Stop conditions as the World collects them, turned into the compiled record once."""

    def __init__(self) -> None:
        self.rows: list[dict] = []

    def add(self, kind: str, *, hold_ticks: int = 0, event: str = "", sensor_slot: int = -1,
            bodies: Sequence[int] = (), others: Sequence[int] = ()) -> int:
        if kind not in CONDITION_NAMES:
            raise ValueError(f"unknown stop condition {kind!r}; one of {', '.join(CONDITION_NAMES)}")
        if kind == "event" and event not in EVENT_KIND_NAMES:
            raise ValueError(f"unknown event {event!r}; one of {', '.join(EVENT_KIND_NAMES)}")
        if kind == "inside" and (sensor_slot < 0 or not len(bodies)):
            raise ValueError("inside needs a sensor body and bodies")
        self.rows.append(dict(kind=CONDITION_NAMES.index(kind), hold=max(int(hold_ticks), 1),
                              event=EVENT_KIND_NAMES.index(event) if event else -1, sensor=int(sensor_slot),
                              members=np.asarray(bodies, np.int64), others=np.asarray(others, np.int64)))
        return len(self.rows) - 1

    def compiled(self) -> StopConditions:
        rows = self.rows

        def column(name):
            return np.array([r[name] for r in rows], np.int64)

        def offsets(name):
            return np.concatenate([[0], np.cumsum([len(r[name]) for r in rows])]).astype(np.int64)

        def joined(name):
            return np.concatenate([np.zeros(0, np.int64)] + [r[name] for r in rows]).astype(np.int64)

        return StopConditions(column("kind"), column("hold"), column("event"), column("sensor"),
                              offsets("members"), joined("members"), offsets("others"), joined("others"),
                              np.zeros(len(rows), np.int64))


@tick_kernel
def _all_at_rest(bodies):
    v, w, active, body_type = bodies.v, bodies.w, bodies.active, bodies.body_type
    for i in range(v.shape[0]):
        if active[i] and body_type[i] == DYNAMIC and (
                math.sqrt(v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1]) >= AT_REST_SPEED
                or abs(w[i]) >= AT_REST_ANGULAR_SPEED):
            return False
    return True


@tick_kernel
def first_held(stops, bodies, sensors, events, first_event):
    """After a tick whose events are events[first_event:]: the first condition that holds now (-1: none)."""
    held = stops.held
    found = -1
    for c in range(stops.kind.shape[0]):
        kind = stops.kind[c]
        now = False
        if kind == AT_REST:
            now = _all_at_rest(bodies)
        elif kind == INSIDE:
            now = True
            for k in range(stops.first[c], stops.first[c + 1]):
                if not sensors.inside[stops.sensor[c], stops.members[k]]:
                    now = False
                    break
        else:
            for e in range(first_event, events.count[0]):
                if involves(events, e, stops.event[c], stops.members, stops.first[c], stops.first[c + 1],
                            stops.others, stops.other_first[c], stops.other_first[c + 1]):
                    now = True
                    break
        held[c] = held[c] + 1 if now else 0
        if found < 0 and held[c] >= stops.hold[c]:
            found = c
    return found
