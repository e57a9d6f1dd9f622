"""Narrow phase: contact manifolds of up to two points for every shape pair.

Boxes are 4-vertex polygons. Polygon pairs use the separating axis test (the axis of greatest
separation over both polygons' edge normals), then clip the incident edge against the reference
edge's side planes (Sutherland-Hodgman on one segment), as Box2D does. Circles against polygons find
the edge of greatest separation of the centre, which stays right when the centre is inside. Points
are reported while their separation is below `margin` (speculative contacts, so that an approaching
body is caught before it overlaps). Each point is placed midway between the two surfaces and carries
a feature id that stays the same while the same edges touch: that is what warm starting matches.

The normal of a manifold always points from body a to body b.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rustycs.broad_phase import BODY_BITS, BODY_MASK, hitboxes_overlap
from rustycs.contact_solver import (
    FRICTION,
    MANIFOLD_COLUMNS,
    NORMAL_IMPULSE,
    NX,
    NY,
    POINT_COLUMNS,
    RAX,
    RAY,
    RBX,
    RBY,
    RESTITUTION,
    SEPARATION,
    TANGENT_IMPULSE,
)
from rustycs.shapes import CIRCLE, POLYGON
from rustycs.tick_kernel import tick_kernel

LINEAR_SLOP = 0.005
FEATURE_BITS = 8  # a point's key: (pair key << FEATURE_BITS) | feature id
REFERENCE_TOLERANCE = 0.1 * LINEAR_SLOP


@njit(cache=True, inline="always")
def collide_circles(xa, ya, ra, xb, yb, rb, margin, normal, points, separations, ids):
    dx = xb - xa
    dy = yb - ya
    dist = math.sqrt(dx * dx + dy * dy)
    sep = dist - ra - rb
    if sep > margin:
        return 0
    if dist > 1e-12:
        nx = dx / dist
        ny = dy / dist
    else:
        nx = 0.0
        ny = 1.0
    normal[0] = nx
    normal[1] = ny
    # midway between the two surfaces
    points[0, 0] = 0.5 * ((xa + ra * nx) + (xb - rb * nx))
    points[0, 1] = 0.5 * ((ya + ra * ny) + (yb - rb * ny))
    separations[0] = sep
    ids[0] = 0
    return 1


@njit(cache=True, inline="always")
def collide_polygon_circle(verts, normals, counts, i, cx, cy, r, margin, normal, points, separations, ids):
    """Polygon i against a circle; the normal points from the polygon to the circle."""
    count = counts[i]
    best = -math.inf
    edge = 0
    for k in range(count):
        s = normals[i, k, 0] * (cx - verts[i, k, 0]) + normals[i, k, 1] * (cy - verts[i, k, 1])
        if s > best:
            best = s
            edge = k
    if best - r > margin:
        return 0
    k2 = edge + 1 if edge + 1 < count else 0
    v1x, v1y = verts[i, edge, 0], verts[i, edge, 1]
    v2x, v2y = verts[i, k2, 0], verts[i, k2, 1]
    u1 = (cx - v1x) * (v2x - v1x) + (cy - v1y) * (v2y - v1y)
    u2 = (cx - v2x) * (v1x - v2x) + (cy - v2y) * (v1y - v2y)
    if best > 1e-12 and (u1 < 0.0 or u2 < 0.0):
        # the centre is outside, in a vertex region
        vx, vy = (v1x, v1y) if u1 < 0.0 else (v2x, v2y)
        dx = cx - vx
        dy = cy - vy
        dist = math.sqrt(dx * dx + dy * dy)
        sep = dist - r
        if sep > margin:
            return 0
        nx = dx / dist
        ny = dy / dist
        ax, ay = vx, vy
    else:
        # face region (also when the centre is inside: push out through the nearest face)
        nx = normals[i, edge, 0]
        ny = normals[i, edge, 1]
        sep = best - r
        ax = cx - best * nx
        ay = cy - best * ny
    normal[0] = nx
    normal[1] = ny
    points[0, 0] = 0.5 * (ax + cx - r * nx)
    points[0, 1] = 0.5 * (ay + cy - r * ny)
    separations[0] = sep
    ids[0] = 0
    return 1


@njit(cache=True, inline="always")
def _max_separation(verts, normals, counts, a, b):
    """Edge of polygon a with the greatest separation of polygon b's vertices from it.

    Written without data-dependent branches in the inner loop (min, not if): with random polygons
    those branches are mispredicted often enough to dominate the test.
    """
    best = -math.inf
    edge = 0
    nb = counts[b]
    for i in range(counts[a]):
        nx = normals[a, i, 0]
        ny = normals[a, i, 1]
        s = math.inf
        for j in range(nb):
            s = min(s, nx * verts[b, j, 0] + ny * verts[b, j, 1])
        s -= nx * verts[a, i, 0] + ny * verts[a, i, 1]
        if s > best:
            best = s
            edge = i
    return edge, best


@njit(cache=True, inline="always")
def _box_axes(verts, normals, x, i):
    """A box's distances from its centre to its faces 0 and 1, which are also those to faces 2 and 3
    (a box's vertices run from its lower left corner, counter-clockwise, so face k + 2 is opposite
    face k)."""
    h0 = normals[i, 0, 0] * (verts[i, 0, 0] - x[i, 0]) + normals[i, 0, 1] * (verts[i, 0, 1] - x[i, 1])
    h1 = normals[i, 1, 0] * (verts[i, 1, 0] - x[i, 0]) + normals[i, 1, 1] * (verts[i, 1, 1] - x[i, 1])
    return h0, h1


@njit(cache=True, inline="always")
def _box_max_separation(normals, x, a, ha0, ha1, b, hb0, hb1):
    """`_max_separation` for two boxes, with a quarter of the projections: the lowest point of box b
    along a normal n lies |n.e0| hb0 + |n.e1| hb1 below its centre (e0, e1 its face normals, hb0, hb1 its
    distances to them), and each of a's two axes serves a pair of opposite faces."""
    dx = x[b, 0] - x[a, 0]
    dy = x[b, 1] - x[a, 1]
    best = -math.inf
    edge = 0
    for k in range(4):
        nx = normals[a, k % 2, 0]
        ny = normals[a, k % 2, 1]
        reach = (abs(nx * normals[b, 0, 0] + ny * normals[b, 0, 1]) * hb0
                 + abs(nx * normals[b, 1, 0] + ny * normals[b, 1, 1]) * hb1)
        centre = nx * dx + ny * dy
        s = (centre if k < 2 else -centre) - (ha0 if k % 2 == 0 else ha1) - reach
        if s > best:
            best = s
            edge = k
    return edge, best


@njit(cache=True)
def _clip(px, py, qx, qy, dp, dq, lo, hi):
    """Move p along the segment towards q until its tangent coordinate dp lies in [lo, hi]."""
    if dp > hi:
        f = (dp - hi) / (dp - dq)
    elif dp < lo:
        f = (lo - dp) / (dq - dp)
    else:
        return px, py
    return px + f * (qx - px), py + f * (qy - py)


@njit(cache=True, inline="always")
def collide_polygons(verts, normals, counts, x, boxes, a, b, margin, normal, points, separations, ids):
    """Polygons a and b (with `boxes`, both boxes); the normal points from a to b."""
    if boxes:
        ha0, ha1 = _box_axes(verts, normals, x, a)
        hb0, hb1 = _box_axes(verts, normals, x, b)
        edge_a, sep_a = _box_max_separation(normals, x, a, ha0, ha1, b, hb0, hb1)
        if sep_a > margin:
            return 0
        edge_b, sep_b = _box_max_separation(normals, x, b, hb0, hb1, a, ha0, ha1)
    else:
        edge_a, sep_a = _max_separation(verts, normals, counts, a, b)
        if sep_a > margin:
            return 0
        edge_b, sep_b = _max_separation(verts, normals, counts, b, a)
    if sep_b > margin:
        return 0
    if sep_b > sep_a + REFERENCE_TOLERANCE:
        r, ref, i = b, edge_b, a
        flip = 1
    else:
        r, ref, i = a, edge_a, b
        flip = 0
    rc = counts[r]
    ic = counts[i]
    nx = normals[r, ref, 0]
    ny = normals[r, ref, 1]
    # incident edge: the one whose normal is most anti-parallel to the reference normal
    inc = 0
    lowest = math.inf
    for k in range(ic):
        d = nx * normals[i, k, 0] + ny * normals[i, k, 1]
        if d < lowest:
            lowest = d
            inc = k
    inc2 = inc + 1 if inc + 1 < ic else 0
    ref2 = ref + 1 if ref + 1 < rc else 0
    r1x, r1y = verts[r, ref, 0], verts[r, ref, 1]
    r2x, r2y = verts[r, ref2, 0], verts[r, ref2, 1]
    # the reference edge's direction: its outward normal turned a quarter back (counter-clockwise winding)
    tx = -ny
    ty = nx
    p1x, p1y = verts[i, inc, 0], verts[i, inc, 1]
    p2x, p2y = verts[i, inc2, 0], verts[i, inc2, 1]
    # clip the incident segment to the slab between the reference edge's side planes
    lo = r1x * tx + r1y * ty
    hi = r2x * tx + r2y * ty
    d1 = p1x * tx + p1y * ty
    d2 = p2x * tx + p2y * ty
    if d1 == d2:
        return 0
    # the incident edge runs against the reference edge, so d1 > d2 normally
    if (d1 < lo and d2 < lo) or (d1 > hi and d2 > hi):
        return 0
    q1x, q1y = _clip(p1x, p1y, p2x, p2y, d1, d2, lo, hi)
    q2x, q2y = _clip(p2x, p2y, p1x, p1y, d2, d1, lo, hi)
    base = (flip << 7) | (ref << 4) | (inc << 1)
    count = 0
    for slot in range(2):
        qx = q1x if slot == 0 else q2x
        qy = q1y if slot == 0 else q2y
        sep = nx * (qx - r1x) + ny * (qy - r1y)
        if sep > margin:
            continue
        points[count, 0] = qx - 0.5 * sep * nx
        points[count, 1] = qy - 0.5 * sep * ny
        separations[count] = sep
        ids[count] = base | slot
        count += 1
    if flip:
        normal[0] = -nx
        normal[1] = -ny
    else:
        normal[0] = nx
        normal[1] = ny
    return count


@njit(cache=True)
def contact_buffers(capacity):
    """Buffers the narrow phase fills, for up to `capacity` pairs: manifold rows (body a, body b,
    first point, point count, normal/friction/restitution), point keys, world positions and solver
    rows, and a pair's scratch (normal, points, separations, feature ids)."""
    return (np.empty(capacity, np.int64), np.empty(capacity, np.int64), np.empty(capacity, np.int64),
            np.empty(capacity, np.int64), np.empty((capacity, MANIFOLD_COLUMNS)),
            np.empty(2 * capacity, np.int64), np.empty((2 * capacity, 2)),
            np.zeros((2 * capacity, POINT_COLUMNS)),
            np.zeros(2), np.zeros((2, 2)), np.zeros(2), np.zeros(2, np.int64))


@tick_kernel
def narrow_phase(pair_keys, x, hitbox, reach, kind, radius, nverts, world_verts, world_normals, friction,
                 restitution, margin, contacts):
    """Manifolds of the candidate pairs (keys (a << BODY_BITS) | b), in pair order, and their points in
    feature order, written into `contacts` (from `contact_buffers`, for at least as many pairs).

    A pair's points are kept within `margin` plus both bodies' travel in one tick (each body's reach is
    the margin plus its travel), so a pair whose hitboxes (grown by the reach) do not overlap has none:
    it is passed over (the broad phase's pairs are those of fat hitboxes). A point's key is its pair's
    key and feature id packed into one int64; its solver row holds the anchors relative to both centres
    of mass and the separation, with zero impulses. Returns (manifold count, point count).
    """
    m_a, m_b, m_first, m_count, manifold, p_key, p_point, point, normal, points, separations, ids = contacts
    n_man = 0
    n_pts = 0
    for k in range(pair_keys.shape[0]):
        a = pair_keys[k] >> BODY_BITS
        b = pair_keys[k] & BODY_MASK
        if not hitboxes_overlap(hitbox, a, b):
            continue
        within = reach[a] + reach[b] - margin
        # dispatch written out here rather than in a function taking every array: a call passing a
        # dozen arrays per pair cost more than the collision test itself
        if kind[a] == CIRCLE and kind[b] == CIRCLE:
            count = collide_circles(x[a, 0], x[a, 1], radius[a], x[b, 0], x[b, 1], radius[b],
                                    within, normal, points, separations, ids)
        elif kind[b] == CIRCLE:
            count = collide_polygon_circle(world_verts, world_normals, nverts, a, x[b, 0], x[b, 1],
                                           radius[b], within, normal, points, separations, ids)
        elif kind[a] == CIRCLE:
            count = collide_polygon_circle(world_verts, world_normals, nverts, b, x[a, 0], x[a, 1],
                                           radius[a], within, normal, points, separations, ids)
            normal[0] = -normal[0]
            normal[1] = -normal[1]
        else:
            boxes = kind[a] != POLYGON and kind[b] != POLYGON
            count = collide_polygons(world_verts, world_normals, nverts, x, boxes, a, b, within,
                                     normal, points, separations, ids)
        if count == 0:
            continue
        swap = count == 2 and ids[0] > ids[1]
        m_a[n_man] = a
        m_b[n_man] = b
        manifold[n_man, NX] = normal[0]
        manifold[n_man, NY] = normal[1]
        manifold[n_man, FRICTION] = 0.5 * (friction[a] + friction[b])
        manifold[n_man, RESTITUTION] = 0.5 * (restitution[a] + restitution[b])
        m_first[n_man] = n_pts
        m_count[n_man] = count
        n_man += 1
        for j in range(count):
            src = 1 - j if swap else j
            p_key[n_pts] = (pair_keys[k] << FEATURE_BITS) | ids[src]
            p_point[n_pts, 0] = points[src, 0]
            p_point[n_pts, 1] = points[src, 1]
            point[n_pts, RAX] = points[src, 0] - x[a, 0]
            point[n_pts, RAY] = points[src, 1] - x[a, 1]
            point[n_pts, RBX] = points[src, 0] - x[b, 0]
            point[n_pts, RBY] = points[src, 1] - x[b, 1]
            point[n_pts, SEPARATION] = separations[src]
            point[n_pts, NORMAL_IMPULSE] = 0.0
            point[n_pts, TANGENT_IMPULSE] = 0.0
            n_pts += 1
    return n_man, n_pts
