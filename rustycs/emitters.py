"""Bodies that appear and disappear during a run: emitted bodies, lifetimes and sinks.

An emitter's bodies are ordinary rows of the world, added up front with the tick they appear in: they
are inactive (frozen, colliding with nothing) until the end of that tick, when they are switched on
where they were placed, with the velocity they were given. So emission is deterministic and never
rebuilds the world; the broad phase finds new pairs when a body is switched on or off. A body with a
lifetime is removed at the end of its last tick, and a sink removes every active dynamic body whose
centre is inside its region. Removed bodies are deactivated as bodies that leave the world bounds are.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from rustycs.body_types import DYNAMIC
from rustycs.events import REMOVE, SPAWN, record_event
from rustycs.motion import deactivate
from rustycs.tick_kernel import tick_kernel

NEVER = -1  # a remove tick: the body stays


class Lifecycle(NamedTuple):
    """When bodies appear and go, and the sinks."""

    timed: np.ndarray  # (T,) int64 the bodies that appear after tick 0 or have a lifetime
    spawn_tick: np.ndarray  # (N,) int64 the tick at whose end a body appears (0: there from the start)
    remove_tick: np.ndarray  # (N,) int64 the tick at whose end it is removed, NEVER: it stays
    sinks: np.ndarray  # (K, 4) xmin, ymin, xmax, ymax


def new_lifecycle(spawn_tick: np.ndarray, remove_tick: np.ndarray, sinks: np.ndarray) -> Lifecycle:
    timed = np.flatnonzero((spawn_tick > 0) | (remove_tick != NEVER)).astype(np.int64)
    return Lifecycle(timed, spawn_tick.astype(np.int64), remove_tick.astype(np.int64),
                     np.asarray(sinks, np.float64).reshape(-1, 4))


@tick_kernel
def appear_and_vanish(life, bodies, tick, events):
    """At the end of `tick`: switch on the bodies that appear in it, remove those whose lifetime ends and
    those a sink holds (a `spawn` or `remove` event each)."""
    x, active, body_type = bodies.x, bodies.active, bodies.body_type
    for k in range(life.timed.shape[0]):
        i = life.timed[k]
        if life.spawn_tick[i] == tick and not active[i]:
            active[i] = True
            record_event(events, tick, SPAWN, i, -1, x[i, 0], x[i, 1], 0.0)
        elif life.remove_tick[i] == tick and active[i]:
            deactivate(bodies, i)
            record_event(events, tick, REMOVE, i, -1, x[i, 0], x[i, 1], 0.0)
    sinks = life.sinks
    for s in range(sinks.shape[0]):
        for i in range(x.shape[0]):
            if (active[i] and body_type[i] == DYNAMIC and sinks[s, 0] <= x[i, 0] <= sinks[s, 2]
                    and sinks[s, 1] <= x[i, 1] <= sinks[s, 3]):
                deactivate(bodies, i)
                record_event(events, tick, REMOVE, i, -1, x[i, 0], x[i, 1], 0.0)
