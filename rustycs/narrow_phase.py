"""Narrow phase: the manifolds of a tick's candidate pairs, in pair order, and their points in feature
order, as the contact solver takes them.

A manifold names its two shapes and their bodies (the normal points from shape a to shape b) and holds
the mixed friction and restitution (the means of the two shapes' materials, the thesis's rule). A
point holds its key (the pair's key and the feature id: what warm starting matches), its world
position (midway between the surfaces), and its solver row: the anchors from both centres of mass (each on
its own body's surface), the separation and the accumulated impulses (zero here; the warm start fills
them in).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from rustycs.broad_phase import SHAPE_BITS, SHAPE_MASK, hitbox_gap, hitboxes_overlap
from rustycs.compiling import inlined, stage, tick_kernel
from rustycs.constants import LINEAR_SLOP
from rustycs.manifold import (
    Collision,
    collide_capsules,
    collide_chain_circle,
    collide_chain_polygon,
    collide_circles,
    collide_polygon_circle,
    collide_polygons,
    new_collision,
)
from rustycs.pieces import BOX, CHAIN_SEGMENT, CIRCLE
from rustycs.time_of_impact import Sweep, motion_now, new_sweep, time_of_impact

FEATURE_BITS = 8  # a point's key: (pair key << FEATURE_BITS) | feature id

# columns of a manifold's data row
NX, NY, FRICTION, RESTITUTION = 0, 1, 2, 3
MANIFOLD_COLUMNS = 4
# columns of a point's solver row: anchors from both centres of mass, separation, and the accumulated
# impulses (warm start in, result out)
RAX, RAY, RBX, RBY, SEPARATION, NORMAL_IMPULSE, TANGENT_IMPULSE = 0, 1, 2, 3, 4, 5, 6
POINT_COLUMNS = 7


class Manifolds(NamedTuple):
    shape_a: np.ndarray  # (M,) int64 rows in Shapes
    shape_b: np.ndarray
    body_a: np.ndarray  # (M,) int64 rows in Bodies
    body_b: np.ndarray
    first: np.ndarray  # (M,) int64 index of the first point
    count: np.ndarray  # (M,) int64 points: 1 or 2
    data: np.ndarray  # (M, MANIFOLD_COLUMNS)


class Points(NamedTuple):
    key: np.ndarray  # (P,) int64 (pair key << FEATURE_BITS) | feature id, sorted
    position: np.ndarray  # (P, 2) world, midway between the surfaces
    data: np.ndarray  # (P, POINT_COLUMNS)


class SleepingPoints(NamedTuple):
    """The points of the pairs asleep (filled by `rustycs.sleep`), as they were when their island fell
    asleep, sorted by key, each with its pair's bodies and normal; the first count[0] are in use."""

    key: np.ndarray  # (C,) int64
    body: np.ndarray  # (C, 2) int64
    normal: np.ndarray  # (C, 2)
    position: np.ndarray  # (C, 2)
    data: np.ndarray  # (C, POINT_COLUMNS)
    count: np.ndarray  # int64 (1,)


class Contacts(NamedTuple):
    """A tick's manifolds and points, for up to `capacity` pairs, and the points of the pairs asleep."""

    manifolds: Manifolds
    points: Points
    asleep: SleepingPoints  # no room (0 rows) in a world that never sleeps
    count: np.ndarray  # int64 (2,): manifolds and points in use
    # (capacity,) m: how far candidate pair k's bodies may travel in the tick, together, and not meet
    # unseen (`rustycs.continuous`): a lower bound on the gap of its surfaces, infinite when the solver's
    # points hold the pair, 0 where nothing is known
    clearance: np.ndarray
    collision: Collision  # one pair's scratch
    sweep: Sweep  # one pair's scratch of the time of impact


@njit(cache=True)
def new_sleeping_points(capacity, kept):
    """Room for `capacity` sleeping points, holding the entries of `kept` (another store)."""
    capacity = max(capacity, kept.count[0])
    stored = SleepingPoints(np.empty(capacity, np.int64), np.empty((capacity, 2), np.int64),
                            np.empty((capacity, 2)), np.empty((capacity, 2)),
                            np.empty((capacity, POINT_COLUMNS)), np.zeros(1, np.int64))
    n = kept.count[0]
    stored.key[:n] = kept.key[:n]
    stored.body[:n] = kept.body[:n]
    stored.normal[:n] = kept.normal[:n]
    stored.position[:n] = kept.position[:n]
    stored.data[:n] = kept.data[:n]
    stored.count[0] = n
    return stored


@njit(cache=True)
def no_sleeping_points():
    return SleepingPoints(np.empty(0, np.int64), np.empty((0, 2), np.int64), np.empty((0, 2)),
                          np.empty((0, 2)), np.empty((0, POINT_COLUMNS)), np.zeros(1, np.int64))


@njit(cache=True)
def new_contacts(capacity, sleeps, kept):
    """Buffers for a tick's contacts of up to `capacity` pairs; when the world `sleeps`, a store of sleeping
    points as large as the points (a pair's points are in one of the two), holding those of `kept`."""
    manifolds = Manifolds(np.empty(capacity, np.int64), np.empty(capacity, np.int64),
                          np.empty(capacity, np.int64), np.empty(capacity, np.int64),
                          np.empty(capacity, np.int64), np.empty(capacity, np.int64),
                          np.empty((capacity, MANIFOLD_COLUMNS)))
    # unzeroed, as every buffer a tick fills: the points' zeros made all 57 MB of them resident for 64,000
    # circles (0.9 KB a body) where a tick writes 10 MB
    points = Points(np.empty(2 * capacity, np.int64), np.empty((2 * capacity, 2)),
                    np.empty((2 * capacity, POINT_COLUMNS)))
    asleep = new_sleeping_points(2 * capacity if sleeps else 0, kept)
    return Contacts(manifolds, points, asleep, np.zeros(2, np.int64), np.zeros(capacity), new_collision(),
                    new_sweep())


@inlined
def collide_pair(shapes, geometry, sa, sb, within, out):
    """The manifold of shapes sa and sb (kinds in any order), its normal from sa to sb."""
    kind, radius, n_verts = shapes.kind, shapes.radius, shapes.count
    verts, normals, centroid = geometry.vertices, geometry.normals, geometry.centroid
    ka = kind[sa]
    kb = kind[sb]
    out.apart[0] = 0.0  # the routines that can bound the gap of a pair without points do
    # dispatch written out here rather than through a table: each routine is inlined, so a pair pays
    # for one test, not for a call passing a dozen arrays. Two boxes first, with their radii (none) and
    # the box test known here: the piles' pair, 9 us faster over the 820-box pyramid's 2,380 pairs
    if ka == BOX and kb == BOX:
        return collide_polygons(verts, normals, n_verts, centroid, True, sa, 0.0, sb, 0.0, within, out)
    if ka == CIRCLE and kb == CIRCLE:
        return collide_circles(centroid[sa, 0], centroid[sa, 1], radius[sa], centroid[sb, 0], centroid[sb, 1],
                               radius[sb], within, out)
    # the routines take a chain segment first, a circle last
    flipped = (kb == CHAIN_SEGMENT and ka != CHAIN_SEGMENT) or (ka == CIRCLE and kb != CHAIN_SEGMENT)
    if flipped:
        sa, sb = sb, sa
        ka, kb = kb, ka
    if ka == CHAIN_SEGMENT and kb == CIRCLE:
        count = collide_chain_circle(verts, normals, geometry.ghosts, shapes.open_ends, sa, centroid[sb, 0],
                                     centroid[sb, 1], radius[sb], within, out)
    elif ka == CHAIN_SEGMENT:
        count = collide_chain_polygon(verts, normals, n_verts, geometry.ghosts, shapes.open_ends, sa, sb,
                                      radius[sb], within, out)
    elif kb == CIRCLE:
        count = collide_polygon_circle(verts, normals, n_verts, sa, radius[sa], centroid[sb, 0],
                                       centroid[sb, 1], radius[sb], within, out)
    elif n_verts[sa] == 2 and n_verts[sb] == 2:  # capsules and segments
        count = collide_capsules(verts, sa, radius[sa], sb, radius[sb], within, out)
    else:
        count = collide_polygons(verts, normals, n_verts, centroid, False, sa, radius[sa], sb, radius[sb],
                                 within, out)
    if flipped:
        out.normal[0] = -out.normal[0]
        out.normal[1] = -out.normal[1]
    return count


@inlined
def _swept_back(m, t, px, py):
    """Where the point of a body moving as `m` that is at (px, py) after t seconds is now."""
    dx = px - (m.x + m.vx * t)
    dy = py - (m.y + m.vy * t)
    c, s = math.cos(m.w * t), math.sin(m.w * t)
    return m.x + c * dx + s * dy, m.y - s * dx + c * dy


@tick_kernel
def _swept_collision(bodies, shapes, geometry, sa, sb, dt, within, count, sweep, out):
    """Sweep a pair not yet touching, with `count` points now, through the tick: (time of impact, points
    in `out`). Passing by while closing, no points; moving apart, the points they have now (a blow from
    elsewhere may yet drive them together). A call of its own, not inlined: a second copy of the
    collision routines and the sweep inside the narrow phase's loop slowed every pair, swept or not."""
    a, b = shapes.body[sa], shapes.body[sb]
    impact = time_of_impact(shapes, sa, sb, motion_now(bodies, a), motion_now(bodies, b), dt, LINEAR_SLOP,
                            geometry, sweep)
    if impact < 0.0:
        v = bodies.v
        closing = (v[b, 0] - v[a, 0]) * out.normal[0] + (v[b, 1] - v[a, 1]) * out.normal[1] < 0.0
        return 0.0, 0 if closing else count
    if impact == 0.0:
        return 0.0, count
    return impact, collide_pair(sweep, sweep.geometry, 0, 1, within, out)


@stage
def narrow_phase(pair_keys, n_pairs, bodies, shapes, geometry, margin, dt, sleeping, contacts):
    """Manifolds of the first n_pairs candidate pairs (keys (a << SHAPE_BITS) | b), written into
    `contacts` (for at least as many pairs). Returns (manifold count, point count).

    A pair's points are kept within `margin` plus the pair's relative travel in one tick, never more than
    the two bodies' reaches (each the margin plus the body's travel) less the margin. A pair whose
    hitboxes (each shape's way through the tick, grown by the margin and its turning) do not overlap
    cannot come within the margin at the velocities the tick starts with: it is passed over (the broad
    phase's pairs are those of fat hitboxes). A pair not yet touching that
    moves more than `margin` in the tick is swept (`time_of_impact`): passing by, it has no points;
    meeting, it has the points of the features that meet, placed on the bodies where they are now.
    With `sleeping` (a world that sleeps), the pairs of bodies asleep are passed over: their points are
    in the store (`rustycs.sleep`).
    """
    start = np.int64(0)  # not the literal 0: `collide_pairs` is compiled once, for this and for the parts
    n_man, n_pts = collide_pairs(start, n_pairs, start, start, pair_keys, bodies, shapes, geometry, margin,
                                 dt, sleeping, contacts, contacts.collision, contacts.sweep)
    contacts.count[0] = n_man
    contacts.count[1] = n_pts
    return n_man, n_pts


@inlined
def collide_pairs(start, stop, m_start, p_start, pair_keys, bodies, shapes, geometry, margin, dt, sleeping,
                  contacts, out, sweep):
    """The manifolds of candidate pairs start .. stop - 1 (`narrow_phase`), written from manifold row
    `m_start` and point row `p_start` on, with `out` and `sweep` as scratch; returns the manifolds and
    points written. Each pair's are computed from that pair alone, so that ranges may be collided apart
    (`rustycs.threads`) and joined in pair order."""
    m_shape_a, m_shape_b, m_body_a, m_body_b, m_first, m_count, m_data = contacts.manifolds
    p_key, p_position, p_data = contacts.points
    clearance = contacts.clearance
    x, v, w, extent, asleep = bodies.x, bodies.v, bodies.w, bodies.extent, bodies.asleep
    body, hitbox, reach = shapes.body, geometry.hitbox, geometry.reach
    friction, restitution, radius = shapes.friction, shapes.restitution, shapes.radius
    n_man = m_start
    n_pts = p_start
    for k in range(start, stop):
        sa = pair_keys[k] >> SHAPE_BITS
        sb = pair_keys[k] & SHAPE_MASK
        clearance[k] = 0.0
        if not hitboxes_overlap(hitbox, sa, sb):
            # each hitbox holds its shape now grown by at least the margin all round
            clearance[k] = hitbox_gap(hitbox, sa, sb) + 2.0 * margin
            continue
        a = body[sa]
        b = body[sb]
        if sleeping and (asleep[a] or asleep[b]):
            continue
        vx, vy = v[b, 0] - v[a, 0], v[b, 1] - v[a, 1]
        turning = abs(w[a]) * extent[a] + abs(w[b]) * extent[b]
        # points as far apart as the pair can close in the tick: the margin plus its relative travel
        # (bounded by |vx| + |vy|, and by the two reaches the hitboxes were grown by). Bodies falling side
        # by side keep none: the 3,000 falling compounds had 23,800 manifolds a tick, most of them
        # between neighbours that moved together
        within = min(reach[a] + reach[b] - margin, margin + dt * (abs(vx) + abs(vy) + turning))
        count = collide_pair(shapes, geometry, sa, sb, within, out)
        if count == 0:
            clearance[k] = out.apart[0]
            continue
        impact = 0.0
        held = True  # the solver's points hold the pair through the tick
        gap = min(out.separations[0], out.separations[count - 1])
        # a pair that moves less than the margin in the tick (bounded without a square root: |vx| + |vy|
        # is at least the speed) is held by its points, as every resting pair is: 12 us of the 820-box
        # pyramid's narrow phase went to that root
        if gap > LINEAR_SLOP and dt * (abs(vx) + abs(vy) + turning) > margin:
            travel = dt * (math.sqrt(vx * vx + vy * vy) + abs(w[a]) * extent[a] + abs(w[b]) * extent[b])
            if travel + LINEAR_SLOP > gap and travel > margin:  # the slop: a tick of gravity's g dt^2
                impact, count = _swept_collision(bodies, shapes, geometry, sa, sb, dt, within, count, sweep,
                                                 out)
                if count == 0:
                    continue
            elif travel > margin:
                # it cannot close its gap moving as it starts (give or take the slop, more than a tick of
                # gravity adds at 60 Hz: without it a falling ball was caught at the speed the tick started
                # with, and bounced 1.7 % low): its points stay apart along the normal, so the solver never
                # pushes them (a third of the pairs swept in S5). A blow in mid-tick may yet drive it
                # together: swept along the paths taken (`continuous`), as if it had none.
                held = False
        if held:
            clearance[k] = math.inf
        swap = count == 2 and out.ids[0] > out.ids[1]
        nx, ny = out.normal[0], out.normal[1]
        m_shape_a[n_man] = sa
        m_shape_b[n_man] = sb
        m_body_a[n_man] = a
        m_body_b[n_man] = b
        m_data[n_man, NX] = nx
        m_data[n_man, NY] = ny
        m_data[n_man, FRICTION] = 0.5 * (friction[sa] + friction[sb])
        m_data[n_man, RESTITUTION] = 0.5 * (restitution[sa] + restitution[sb])
        m_first[n_man] = n_pts
        m_count[n_man] = count
        n_man += 1
        for j in range(count):
            src = 1 - j if swap else j
            px, py = out.points[src, 0], out.points[src, 1]
            # each anchor on its own body's surface, half the gap from the midpoint: where the bodies
            # will meet, so that friction turns them about their true points of contact
            hx = 0.5 * out.separations[src] * nx
            hy = 0.5 * out.separations[src] * ny
            ax, ay, bx, by = px - hx, py - hy, px + hx, py + hy
            separation = out.separations[src]
            if impact > 0.0:  # the anchors where they meet, carried back to where the bodies are now: their
                # points on the cores turn with the bodies, the radii stay along the normal
                ra, rb = radius[sa], radius[sb]
                ax, ay = _swept_back(motion_now(bodies, a), impact, ax - ra * nx, ay - ra * ny)
                bx, by = _swept_back(motion_now(bodies, b), impact, bx + rb * nx, by + rb * ny)
                ax, ay, bx, by = ax + ra * nx, ay + ra * ny, bx - rb * nx, by - rb * ny
                px, py = 0.5 * (ax + bx), 0.5 * (ay + by)
                separation = (bx - ax) * nx + (by - ay) * ny
            p_key[n_pts] = (pair_keys[k] << FEATURE_BITS) | out.ids[src]
            p_position[n_pts, 0] = px
            p_position[n_pts, 1] = py
            p_data[n_pts, RAX] = ax - x[a, 0]
            p_data[n_pts, RAY] = ay - x[a, 1]
            p_data[n_pts, RBX] = bx - x[b, 0]
            p_data[n_pts, RBY] = by - x[b, 1]
            p_data[n_pts, SEPARATION] = separation
            p_data[n_pts, NORMAL_IMPULSE] = 0.0
            p_data[n_pts, TANGENT_IMPULSE] = 0.0
            n_pts += 1
    return n_man - m_start, n_pts - p_start


class ContactRows(NamedTuple):
    """Contact points one row each, as the World reports them."""

    key: np.ndarray  # (C,) int64
    body_a: np.ndarray  # (C,) int64
    body_b: np.ndarray
    point: np.ndarray  # (C, 2)
    normal: np.ndarray  # (C, 2) from body a to body b
    separation: np.ndarray  # (C,) negative where overlapping
    normal_impulse: np.ndarray  # (C,) N s
    tangent_impulse: np.ndarray


@njit(cache=True)
def contact_rows(contacts):
    """The contact points in use, one row each, sorted by key: key, bodies, position, normal, separation
    and impulses (what `World.contacts()` reports, and the warm-start cache of a rebuilt workspace), the
    tick's points and those asleep together."""
    m, p, stored = contacts.manifolds, contacts.points, contacts.asleep
    n_man, n_pts, n_stored = contacts.count[0], contacts.count[1], stored.count[0]
    n = n_pts + n_stored
    key = np.empty(n, np.int64)
    body_a = np.empty(n, np.int64)
    body_b = np.empty(n, np.int64)
    point = np.empty((n, 2))
    normal = np.empty((n, 2))
    data = np.empty((n, POINT_COLUMNS))
    f = 0
    row = 0
    for k in range(n_man):
        for j in range(m.first[k], m.first[k] + m.count[k]):
            while f < n_stored and stored.key[f] < p.key[j]:
                _stored_row(stored, f, key, body_a, body_b, point, normal, data, row)
                f += 1
                row += 1
            key[row] = p.key[j]
            body_a[row] = m.body_a[k]
            body_b[row] = m.body_b[k]
            point[row] = p.position[j]
            normal[row, 0] = m.data[k, NX]
            normal[row, 1] = m.data[k, NY]
            data[row] = p.data[j]
            row += 1
    while f < n_stored:
        _stored_row(stored, f, key, body_a, body_b, point, normal, data, row)
        f += 1
        row += 1
    return ContactRows(key, body_a, body_b, point, normal, data[:, SEPARATION].copy(),
                       data[:, NORMAL_IMPULSE].copy(), data[:, TANGENT_IMPULSE].copy())


@inlined
def _stored_row(stored, f, key, body_a, body_b, point, normal, data, row):
    key[row] = stored.key[f]
    body_a[row] = stored.body[f, 0]
    body_b[row] = stored.body[f, 1]
    for d in range(2):  # element by element: a row's view would need reference counting
        point[row, d] = stored.position[f, d]
        normal[row, d] = stored.normal[f, d]
    for column in range(data.shape[1]):
        data[row, column] = stored.data[f, column]
