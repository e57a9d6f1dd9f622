"""Sleeping islands: bodies that rest together stop being simulated until something reaches them.

An island is a set of dynamic bodies joined by the tick's manifolds (speculative ones too) and by active
joints; static and kinematic bodies join nothing. A dynamic body's rest time grows by dt in every tick
it moves slower than `SLEEP_THRESHOLD` (its speed plus its turn at its extent, or half its displacement
over the tick, which sees position correction pushing it: Box2D's rule) and is zero otherwise. When the
least rest time of an island reaches the world's `sleep_time`, the whole island falls asleep at the end
of the tick: its bodies keep their poses, their velocities become zero, and every later stage skips them
(geometry, the narrow phase, the solver, integration). The points of its pairs move from the tick's
contact list to a store of sleeping points, as they were, so that contact counts, the deepest overlap and
`World.contacts()` still report them, and so that the island wakes with the impulses it slept with.

An island wakes as a whole, before the narrow phase of a tick, when an awake dynamic body or a moving
kinematic body has a pair with one of its bodies whose narrow-phase test gives points (Box2D wakes on a
touching contact), or a joint ties one of its bodies to such a body; also when the program moves or
pushes one of its bodies, removes one, or changes the forces (`World`). The order of everything is that
of the body rows and the sorted pairs, so sleeping is deterministic. With `World(sleep=False)` (the
default) none of this runs and results are as they were.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from rustycs.body_types import DYNAMIC
from rustycs.broad_phase import SHAPE_BITS, SHAPE_MASK, hitboxes_overlap
from rustycs.compiling import inlined, tick_kernel
from rustycs.constants import SLEEP_THRESHOLD
from rustycs.contact_solver import DX, DY, SIN
from rustycs.narrow_phase import NORMAL_IMPULSE, NX, NY, TANGENT_IMPULSE, collide_pair
from rustycs.union_find import find_root, join


class Islands(NamedTuple):
    """Scratch of the island search, per body."""

    parent: np.ndarray  # (N,) int64: union-find links
    rest: np.ndarray  # (N,) per island root: the least rest time of its bodies, s
    wake: np.ndarray  # (N,) bool per island (the row of its root): wake it this tick


@njit(cache=True)
def new_islands(n_bodies):
    return Islands(np.arange(n_bodies), np.zeros(n_bodies), np.zeros(n_bodies, np.bool_))


@inlined
def _movable(bodies, i):
    """An awake dynamic body that is in the world (-1, the fixed world, is not)."""
    return i >= 0 and bodies.body_type[i] == DYNAMIC and bodies.active[i] and not bodies.asleep[i]


@inlined
def _moving(bodies, i):
    """A body that reaches what it touches: an awake dynamic body, or a kinematic one in motion."""
    if i < 0 or not bodies.active[i] or bodies.asleep[i]:
        return False
    if bodies.body_type[i] == DYNAMIC:
        return True
    return bodies.v[i, 0] != 0.0 or bodies.v[i, 1] != 0.0 or bodies.w[i] != 0.0


@inlined
def nothing_moves(bodies):
    """Whether no body reaches anything (`_moving`): every active dynamic body asleep, every kinematic
    one still."""
    for i in range(bodies.asleep.shape[0]):
        if _moving(bodies, i):
            return False
    return True


@inlined
def _sleeping(bodies, i):
    return i >= 0 and bodies.asleep[i]


@inlined
def wake_island(bodies, island):
    """Wake every body of `island` (the row of its root)."""
    for i in range(bodies.asleep.shape[0]):
        if bodies.asleep[i] and bodies.island[i] == island:
            bodies.asleep[i] = False
            bodies.sleep_time[i] = 0.0


@tick_kernel
def wake_reached(pair_keys, n_pairs, bodies, shapes, geometry, joints, contacts, margin, islands):
    """Before the narrow phase: wake the islands that an awake dynamic body or a moving kinematic one
    touches (a pair whose narrow-phase test gives points) or holds by a joint."""
    wake, reach, body = islands.wake, geometry.reach, shapes.body
    marked = False
    for k in range(n_pairs):
        sa = pair_keys[k] >> SHAPE_BITS
        sb = pair_keys[k] & SHAPE_MASK
        a, b = body[sa], body[sb]
        if bodies.asleep[a] == bodies.asleep[b]:
            continue
        sleeper, other = (a, b) if bodies.asleep[a] else (b, a)
        if wake[bodies.island[sleeper]] or not _moving(bodies, other):
            continue
        if not hitboxes_overlap(geometry.hitbox, sa, sb):
            continue
        if collide_pair(shapes, geometry, sa, sb, reach[a] + reach[b] - margin, contacts.collision) > 0:
            wake[bodies.island[sleeper]] = True
            marked = True
    for j in range(joints.kind.shape[0]):
        a, b = joints.body_a[j], joints.body_b[j]
        if not joints.active[j] or _sleeping(bodies, a) == _sleeping(bodies, b):
            continue
        sleeper, other = (a, b) if _sleeping(bodies, a) else (b, a)
        if _moving(bodies, other):
            wake[bodies.island[sleeper]] = True
            marked = True
    if not marked:
        return
    for i in range(bodies.asleep.shape[0]):
        if bodies.asleep[i] and wake[bodies.island[i]]:
            bodies.asleep[i] = False
            bodies.sleep_time[i] = 0.0
    for i in range(wake.shape[0]):
        wake[i] = False


@inlined
def _pair_asleep(bodies, a, b):
    """Whether the pair of bodies a and b sleeps: neither awake and dynamic, one of them asleep."""
    return (bodies.asleep[a] or bodies.asleep[b]) and not _movable(bodies, a) and not _movable(bodies, b)


@tick_kernel
def warm_from_sleep(points, n_points, bodies, stored):
    """Give this tick's points of the pairs just woken the impulses they slept with, and drop from the
    store the points of pairs no longer asleep (both lists are sorted by key: one merge pass)."""
    key, data = points.key, points.data
    f = 0
    n = stored.count[0]
    for p in range(n_points):
        while f < n and stored.key[f] < key[p]:
            f += 1
        if f < n and stored.key[f] == key[p]:
            data[p, NORMAL_IMPULSE] = stored.data[f, NORMAL_IMPULSE]
            data[p, TANGENT_IMPULSE] = stored.data[f, TANGENT_IMPULSE]
    kept = 0
    for f in range(n):
        if _pair_asleep(bodies, stored.body[f, 0], stored.body[f, 1]):
            if kept != f:
                _move_stored(stored, f, kept)
            kept += 1
    stored.count[0] = kept


@inlined
def _rest_times(bodies, body, dt):
    """Advance each awake dynamic body's rest time; returns the largest."""
    v, w, extent = bodies.v, bodies.w, bodies.extent
    longest = 0.0
    for i in range(v.shape[0]):
        if not _movable(bodies, i):
            continue
        speed = math.sqrt(v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1]) + extent[i] * abs(w[i])
        moved = math.sqrt(body[i, DX] * body[i, DX] + body[i, DY] * body[i, DY])
        moved += extent[i] * abs(body[i, SIN])
        if max(speed, 0.5 * moved / dt) > SLEEP_THRESHOLD:
            bodies.sleep_time[i] = 0.0
        else:
            bodies.sleep_time[i] += dt
            longest = max(longest, bodies.sleep_time[i])
    return longest


@tick_kernel
def fall_asleep(bodies, body, joints, contacts, sleep_time, dt, islands):
    """At the end of a tick: advance the rest times, and put to sleep every island whose bodies have all
    rested `sleep_time`; their pairs' points leave the tick's contacts for the store of sleeping points."""
    if _rest_times(bodies, body, dt) < sleep_time:
        return  # no island can sleep: none was searched (most ticks of a moving scene)
    parent, rest = islands.parent, islands.rest
    n = parent.shape[0]
    for i in range(n):
        parent[i] = i
        rest[i] = math.inf
    manifolds = contacts.manifolds
    n_man = contacts.count[0]
    for k in range(n_man):
        a, b = manifolds.body_a[k], manifolds.body_b[k]
        if _movable(bodies, a) and _movable(bodies, b):
            join(parent, a, b)
    for j in range(joints.kind.shape[0]):
        a, b = joints.body_a[j], joints.body_b[j]
        if joints.active[j] and _movable(bodies, a) and _movable(bodies, b):
            join(parent, a, b)
    for i in range(n):
        if _movable(bodies, i):
            root = find_root(parent, i)
            rest[root] = min(rest[root], bodies.sleep_time[i])
    fell = 0
    for i in range(n):
        if _movable(bodies, i):
            root = find_root(parent, i)
            if rest[root] >= sleep_time:
                bodies.asleep[i] = True
                bodies.island[i] = root
                bodies.v[i, 0] = 0.0
                bodies.v[i, 1] = 0.0
                bodies.w[i] = 0.0
                fell += 1
    if fell > 0:
        _store_sleeping_points(bodies, contacts)


@inlined
def _store_sleeping_points(bodies, contacts):
    """Move the points of the manifolds whose pair now sleeps into the store (kept sorted by key), and
    close the gaps they leave in the tick's manifolds and points."""
    m, pts, stored = contacts.manifolds, contacts.points, contacts.asleep
    n_man = contacts.count[0]
    moving = 0
    for k in range(n_man):
        if _pair_asleep(bodies, m.body_a[k], m.body_b[k]):
            moving += m.count[k]
    # merge from the back: the store's entries and the moving points, both sorted, into the store
    f = stored.count[0] - 1
    out = stored.count[0] + moving - 1
    for k in range(n_man - 1, -1, -1):
        if not _pair_asleep(bodies, m.body_a[k], m.body_b[k]):
            continue
        for p in range(m.first[k] + m.count[k] - 1, m.first[k] - 1, -1):
            while f >= 0 and stored.key[f] > pts.key[p]:
                _move_stored(stored, f, out)
                f -= 1
                out -= 1
            stored.key[out] = pts.key[p]
            stored.body[out, 0] = m.body_a[k]
            stored.body[out, 1] = m.body_b[k]
            stored.normal[out, 0] = m.data[k, NX]
            stored.normal[out, 1] = m.data[k, NY]
            _copy_row(pts.position, p, stored.position, out)
            _copy_row(pts.data, p, stored.data, out)
            out -= 1
    stored.count[0] += moving
    # close the gaps in the tick's lists, in order
    kept_man = 0
    kept_pts = 0
    for k in range(n_man):
        if _pair_asleep(bodies, m.body_a[k], m.body_b[k]):
            continue
        first, count = m.first[k], m.count[k]
        m.shape_a[kept_man] = m.shape_a[k]
        m.shape_b[kept_man] = m.shape_b[k]
        m.body_a[kept_man] = m.body_a[k]
        m.body_b[kept_man] = m.body_b[k]
        m.first[kept_man] = kept_pts
        m.count[kept_man] = count
        _copy_row(m.data, k, m.data, kept_man)
        for p in range(first, first + count):
            pts.key[kept_pts] = pts.key[p]
            _copy_row(pts.position, p, pts.position, kept_pts)
            _copy_row(pts.data, p, pts.data, kept_pts)
            kept_pts += 1
        kept_man += 1
    contacts.count[0] = kept_man
    contacts.count[1] = kept_pts


@inlined
def _copy_row(source, i, target, j):
    for c in range(source.shape[1]):
        target[j, c] = source[i, c]


@inlined
def _move_stored(stored, src, dst):
    stored.key[dst] = stored.key[src]
    _copy_row(stored.body, src, stored.body, dst)
    _copy_row(stored.normal, src, stored.normal, dst)
    _copy_row(stored.position, src, stored.position, dst)
    _copy_row(stored.data, src, stored.data, dst)

