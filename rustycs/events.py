"""Events: what happened in a tick, in the order it happened, recorded by the compiled step.

The World collects them after every `step` call (`World.events()`), so the buffer only holds one call's
worth.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from rustycs.compiling import inlined

CONTACT_BEGIN, CONTACT_END, SENSOR_ENTER, SENSOR_EXIT, SPAWN, REMOVE, ESCAPE, JOINT_BREAK = range(8)
EVENT_KIND_NAMES = ("contact_begin", "contact_end", "sensor_enter", "sensor_exit", "spawn", "remove",
                    "escape", "joint_break")


class Events(NamedTuple):
    """The events of a step call; the first count[0] rows are in use."""

    tick: np.ndarray  # (E,) int64: the tick it happened in
    kind: np.ndarray  # (E,) int64: CONTACT_BEGIN ... JOINT_BREAK
    a: np.ndarray  # (E,) int64: a body (for JOINT_BREAK: the joint)
    b: np.ndarray  # (E,) int64: the other body, -1 where there is none
    point: np.ndarray  # (E, 2) world point: a contact point, else the body's centre
    speed: np.ndarray  # (E,) m/s: approach speed along the normal of a contact_begin, else 0
    count: np.ndarray  # int64 (1,)


@njit(cache=True)
def new_events(capacity):
    """Room for `capacity` events. Rows are written before they are counted and never read past the
    count, so the buffers are not zeroed: untouched pages cost no memory (a 64,000-circle pile's 640,000
    rows, 34 MB, were all resident)."""
    return Events(np.empty(capacity, np.int64), np.empty(capacity, np.int64), np.empty(capacity, np.int64),
                  np.empty(capacity, np.int64), np.empty((capacity, 2)), np.empty(capacity),
                  np.zeros(1, np.int64))


@inlined
def record_event(events, tick, kind, a, b, px, py, speed):
    """Append an event (the caller has made sure there is room)."""
    k = events.count[0]
    events.tick[k] = tick
    events.kind[k] = kind
    events.a[k] = a
    events.b[k] = b
    events.point[k, 0] = px
    events.point[k, 1] = py
    events.speed[k] = speed
    events.count[0] = k + 1


@njit(cache=True)
def grown_events(events, capacity):
    """A buffer of at least `capacity` rows holding the events recorded so far."""
    n = events.count[0]
    bigger = new_events(max(capacity, 2 * events.tick.shape[0]))
    bigger.tick[:n] = events.tick[:n]
    bigger.kind[:n] = events.kind[:n]
    bigger.a[:n] = events.a[:n]
    bigger.b[:n] = events.b[:n]
    bigger.point[:n] = events.point[:n]
    bigger.speed[:n] = events.speed[:n]
    bigger.count[0] = n
    return bigger


@inlined
def _listed(members, first, last, body):
    for k in range(first, last):
        if members[k] == body:
            return True
    return False


@inlined
def involves(events, e, kind, members, a0, a1, others, b0, b1):
    """Whether event e is of `kind` and concerns the bodies members[a0:a1] (any of them, on either side
    of a two-body event), and when others[b0:b1] is not empty, one body of each list; with no bodies
    listed, any event of the kind."""
    if events.kind[e] != kind:
        return False
    if a1 == a0:
        return True
    a = events.a[e]
    b = events.b[e]
    if b1 == b0:
        return _listed(members, a0, a1, a) or (b >= 0 and _listed(members, a0, a1, b))
    return ((_listed(members, a0, a1, a) and _listed(others, b0, b1, b))
            or (_listed(members, a0, a1, b) and _listed(others, b0, b1, a)))
