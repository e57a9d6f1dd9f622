"""Bodies that appear and disappear during a run: emitted bodies, lifetimes and sinks.

An emitter's bodies are ordinary rows of the world, added up front with the tick they appear in: they
are inactive (frozen, colliding with nothing) until the end of that tick, when they are switched on
where they were placed, with the velocity they were given. So emission is deterministic and never
rebuilds the world; the broad phase finds new pairs when a body is switched on or off. A body with a
lifetime is removed at the end of its last tick, and a sink removes every active dynamic body whose
centre is inside its region. Removed bodies are deactivated as bodies that leave the world bounds are.

A body marked `if_free` (an emitter's `placement: no_overlap`) appears only where nothing that collides
is: its bounding circle (about its centre of mass, holding its non-sensor shapes) must be clear of every
collidable shape of the active bodies, each taken as its bounding circle and its box (both hold the shape,
so a free spot is never wrongly taken; a long floor or wall is its box, not a circle that would cover the
emitter). Otherwise it is skipped: it never appears (no `spawn` event) and `skipped` marks it. Bodies are
switched on in row order, so a body appearing in the same tick counts for the ones after it. A brute-force
loop over the bodies: spawns are rare.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from rustycs.body_types import DYNAMIC
from rustycs.broad_phase import filters_agree
from rustycs.compiling import inlined, tick_kernel
from rustycs.events import REMOVE, SPAWN, record_event
from rustycs.motion import deactivate

NEVER = -1  # a remove tick: the body stays


class Lifecycle(NamedTuple):
    """When bodies appear and go, and the sinks."""

    timed: np.ndarray  # (T,) int64 the bodies that appear after tick 0 or have a lifetime
    spawn_tick: np.ndarray  # (N,) int64 the tick at whose end a body appears (0: there from the start)
    remove_tick: np.ndarray  # (N,) int64 the tick at whose end it is removed, NEVER: it stays
    sinks: np.ndarray  # (K, 4) xmin, ymin, xmax, ymax
    if_free: np.ndarray  # (N,) bool: appears only if its place is free, else is skipped
    skipped: np.ndarray  # (N,) bool: it was skipped (filled by the step; the world keeps it across builds)


def new_lifecycle(spawn_tick: np.ndarray, remove_tick: np.ndarray, sinks: np.ndarray, if_free: np.ndarray,
                  skipped: np.ndarray) -> Lifecycle:
    timed = np.flatnonzero((spawn_tick > 0) | (remove_tick != NEVER)).astype(np.int64)
    return Lifecycle(timed, spawn_tick.astype(np.int64), remove_tick.astype(np.int64),
                     np.asarray(sinks, np.float64).reshape(-1, 4), if_free.astype(np.bool_), skipped)


@inlined
def _piece_reach(shapes, j):
    """How far piece j reaches from its body's centre of mass (any turn)."""
    reach = math.hypot(shapes.centroid[j, 0], shapes.centroid[j, 1])
    for k in range(shapes.count[j]):
        reach = max(reach, math.hypot(shapes.vertices[j, k, 0], shapes.vertices[j, k, 1]))
    return reach + shapes.radius[j]


@inlined
def _piece_hits(shapes, q, px, py, c, s, cx, cy, r):
    """Whether the circle (cx, cy, r) overlaps the box of piece q of a body at (px, py) turned by
    (cos c, sin s): its core's box grown by its radius."""
    lo_x = hi_x = px + c * shapes.centroid[q, 0] - s * shapes.centroid[q, 1]
    lo_y = hi_y = py + s * shapes.centroid[q, 0] + c * shapes.centroid[q, 1]
    for k in range(shapes.count[q]):
        vx = px + c * shapes.vertices[q, k, 0] - s * shapes.vertices[q, k, 1]
        vy = py + s * shapes.vertices[q, k, 0] + c * shapes.vertices[q, k, 1]
        lo_x, hi_x = min(lo_x, vx), max(hi_x, vx)
        lo_y, hi_y = min(lo_y, vy), max(hi_y, vy)
    grow = shapes.radius[q]
    dx = max(lo_x - grow - cx, 0.0, cx - hi_x - grow)
    dy = max(lo_y - grow - cy, 0.0, cy - hi_y - grow)
    return dx * dx + dy * dy < r * r


@inlined
def _widest(shapes, first, count):
    """The largest radius of the pieces first .. first + count."""
    widest = 0.0
    for q in range(first, first + count):
        widest = max(widest, shapes.radius[q])
    return widest


@tick_kernel
def place_taken(bodies, shapes, i):
    """Whether a collidable shape of an active body other than i is inside body i's bounding circle (one
    per non-sensor shape of i, for the collision filters; each against the other's bounding circle first)."""
    x, angle, active = bodies.x, bodies.angle, bodies.active
    first, count = bodies.first_shape, bodies.shape_count
    for j in range(first[i], first[i] + count[i]):
        if shapes.sensor[j]:
            continue
        r = _piece_reach(shapes, j)
        for b in range(x.shape[0]):
            if b == i or not active[b]:
                continue
            dx, dy = x[b, 0] - x[i, 0], x[b, 1] - x[i, 1]
            if dx * dx + dy * dy >= (r + bodies.extent[b] + _widest(shapes, first[b], count[b])) ** 2:
                continue
            c, s = math.cos(angle[b]), math.sin(angle[b])
            for q in range(first[b], first[b] + count[b]):
                if (not shapes.sensor[q] and filters_agree(shapes, j, q)
                        and _piece_hits(shapes, q, x[b, 0], x[b, 1], c, s, x[i, 0], x[i, 1], r)):
                    return True
    return False


@njit(cache=True)
def place_at_start(life, bodies, shapes):
    """Before the first tick: of the `if_free` bodies there from the start, switch on in row order those
    whose place is free and skip the others (all off first, so that an earlier row wins; the same result
    however often it is called before the first tick)."""
    for i in range(life.if_free.shape[0]):
        if life.if_free[i] and life.spawn_tick[i] == 0:
            bodies.active[i] = False
            life.skipped[i] = False
    for i in range(life.if_free.shape[0]):
        if life.if_free[i] and life.spawn_tick[i] == 0:
            taken = place_taken(bodies, shapes, i)
            bodies.active[i] = not taken
            life.skipped[i] = taken


@tick_kernel
def appear_and_vanish(life, bodies, shapes, tick, events):
    """At the end of `tick`: switch on the bodies that appear in it (or skip those whose place is taken),
    remove those whose lifetime ends and those a sink holds (a `spawn` or `remove` event each)."""
    x, active, body_type = bodies.x, bodies.active, bodies.body_type
    for k in range(life.timed.shape[0]):
        i = life.timed[k]
        if life.spawn_tick[i] == tick and not active[i]:
            if life.if_free[i] and place_taken(bodies, shapes, i):
                life.skipped[i] = True
                continue
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
