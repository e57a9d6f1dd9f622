"""Contact begin and end: which shape pairs touch, tick after tick.

A pair touches in a tick when one of its points overlaps or carries load after the solver (the rule of
`World.contacts`): a speculative point the bodies have not reached yet does not begin a contact. The
pairs that touched in the last tick are kept sorted by pair key, as the manifolds come, so one merge
pass finds the pairs that began and those that ended. A pair of an island asleep still touches.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from rustycs.broad_phase import SHAPE_BITS
from rustycs.compiling import inlined, tick_kernel
from rustycs.events import CONTACT_BEGIN, CONTACT_END, record_event
from rustycs.narrow_phase import NORMAL_IMPULSE, NX, NY, RAX, RAY, RBX, RBY, SEPARATION


class Touching(NamedTuple):
    """The shape pairs that touched in the last tick, sorted by key; the first count[0] rows are in use,
    the rest (and `next_*`) is scratch for the tick being merged."""

    key: np.ndarray  # (C,) int64 pair key (shape a << SHAPE_BITS) | shape b
    body: np.ndarray  # (C, 2) int64 the pair's bodies
    point: np.ndarray  # (C, 2) a touching point, world
    next_key: np.ndarray  # (C,) scratch
    next_body: np.ndarray  # (C, 2)
    next_point: np.ndarray  # (C, 2)
    count: np.ndarray  # int64 (1,)


@njit(cache=True)
def new_touching(capacity):
    """Room for `capacity` pairs, none touching yet."""
    return Touching(np.empty(capacity, np.int64), np.empty((capacity, 2), np.int64), np.empty((capacity, 2)),
                    np.empty(capacity, np.int64), np.empty((capacity, 2), np.int64), np.empty((capacity, 2)),
                    np.zeros(1, np.int64))


@njit(cache=True)
def grown_touching(touching, capacity):
    """Room for `capacity` pairs, holding the pairs of `touching`."""
    grown = new_touching(max(capacity, touching.key.shape[0]))
    n = touching.count[0]
    grown.key[:n] = touching.key[:n]
    grown.body[:n] = touching.body[:n]
    grown.point[:n] = touching.point[:n]
    grown.count[0] = n
    return grown


@inlined
def _touches(points, first, count):
    """The first point of a manifold that overlaps or carries load, or -1."""
    data = points.data
    for p in range(first, first + count):
        if data[p, SEPARATION] <= 0.0 or data[p, NORMAL_IMPULSE] > 0.0:
            return p
    return -1


@inlined
def _approach(bodies, points, manifolds, k, p):
    """The speed at which the bodies of manifold k closed along its normal at point p, from their
    velocities at the start of the tick (`bodies.v`, not yet stored back by the solver)."""
    a, b = manifolds.body_a[k], manifolds.body_b[k]
    v, w, data = bodies.v, bodies.w, points.data
    vax = v[a, 0] - w[a] * data[p, RAY]
    vay = v[a, 1] + w[a] * data[p, RAX]
    vbx = v[b, 0] - w[b] * data[p, RBY]
    vby = v[b, 1] + w[b] * data[p, RBX]
    return max(0.0, -((vbx - vax) * manifolds.data[k, NX] + (vby - vay) * manifolds.data[k, NY]))


@inlined
def _ended(bodies, tick, events, old_key, old_body, old_point, i, new_key, new_body, new_point, n_new):
    """Pair i of the last tick is not in this tick's manifolds: it ended (an event), unless its island
    sleeps (its points are in the store: it still touches). Returns the pairs touching now."""
    a, b = old_body[i, 0], old_body[i, 1]
    if bodies.asleep[a] or bodies.asleep[b]:
        new_key[n_new] = old_key[i]
        new_body[n_new, 0] = a
        new_body[n_new, 1] = b
        new_point[n_new, 0] = old_point[i, 0]
        new_point[n_new, 1] = old_point[i, 1]
        return n_new + 1
    record_event(events, tick, CONTACT_END, a, b, old_point[i, 0], old_point[i, 1], 0.0)
    return n_new


@tick_kernel
def contact_events(manifolds, n_man, points, bodies, tick, touching, events):
    """Record contact_begin for the pairs touching now that did not in the last tick and contact_end for
    those that did and no longer do; keep the pairs touching now. Runs after the solver, before the
    velocities are stored back (the approach speed is that of the start of the tick). The events buffer
    has room for n_man + touching.count[0] more."""
    old_key, old_body, old_point = touching.key, touching.body, touching.point
    new_key, new_body, new_point = touching.next_key, touching.next_body, touching.next_point
    n_old = touching.count[0]
    i = 0
    n_new = 0
    for k in range(n_man):
        p = _touches(points, manifolds.first[k], manifolds.count[k])
        if p < 0:
            continue
        key = (manifolds.shape_a[k] << SHAPE_BITS) | manifolds.shape_b[k]
        while i < n_old and old_key[i] < key:  # touched before, not now
            n_new = _ended(bodies, tick, events, old_key, old_body, old_point, i, new_key, new_body,
                           new_point, n_new)
            i += 1
        px, py = points.position[p, 0], points.position[p, 1]
        if i < n_old and old_key[i] == key:
            i += 1
        else:
            record_event(events, tick, CONTACT_BEGIN, manifolds.body_a[k], manifolds.body_b[k], px, py,
                         _approach(bodies, points, manifolds, k, p))
        new_key[n_new] = key
        new_body[n_new, 0] = manifolds.body_a[k]
        new_body[n_new, 1] = manifolds.body_b[k]
        new_point[n_new, 0] = px
        new_point[n_new, 1] = py
        n_new += 1
    while i < n_old:
        n_new = _ended(bodies, tick, events, old_key, old_body, old_point, i, new_key, new_body, new_point,
                       n_new)
        i += 1
    for j in range(n_new):
        old_key[j] = new_key[j]
        old_body[j, 0] = new_body[j, 0]
        old_body[j, 1] = new_body[j, 1]
        old_point[j, 0] = new_point[j, 0]
        old_point[j, 1] = new_point[j, 1]
    touching.count[0] = n_new
