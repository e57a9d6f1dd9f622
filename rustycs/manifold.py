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

from numba import njit

from rustycs.shapes import CIRCLE

LINEAR_SLOP = 0.005
REFERENCE_TOLERANCE = 0.1 * LINEAR_SLOP


@njit(cache=True)
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


@njit(cache=True)
def collide_polygon_circle(verts, normals, count, cx, cy, r, margin, normal, points, separations, ids):
    """Polygon (first) against circle (second); the normal points from the polygon to the circle."""
    best = -math.inf
    edge = 0
    for k in range(count):
        s = normals[k, 0] * (cx - verts[k, 0]) + normals[k, 1] * (cy - verts[k, 1])
        if s > best:
            best = s
            edge = k
    if best - r > margin:
        return 0
    k2 = edge + 1 if edge + 1 < count else 0
    v1x, v1y = verts[edge, 0], verts[edge, 1]
    v2x, v2y = verts[k2, 0], verts[k2, 1]
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
        nx = normals[edge, 0]
        ny = normals[edge, 1]
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


@njit(cache=True)
def _max_separation(va, na, ca, vb, cb):
    """Edge of polygon a with the greatest separation of polygon b's vertices from it."""
    best = -math.inf
    edge = 0
    for i in range(ca):
        nx = na[i, 0]
        ny = na[i, 1]
        px = va[i, 0]
        py = va[i, 1]
        s = math.inf
        for j in range(cb):
            d = nx * (vb[j, 0] - px) + ny * (vb[j, 1] - py)
            if d < s:
                s = d
        if s > best:
            best = s
            edge = i
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


@njit(cache=True)
def collide_polygons(va, na, ca, vb, nb, cb, margin, normal, points, separations, ids):
    edge_a, sep_a = _max_separation(va, na, ca, vb, cb)
    if sep_a > margin:
        return 0
    edge_b, sep_b = _max_separation(vb, nb, cb, va, ca)
    if sep_b > margin:
        return 0
    if sep_b > sep_a + REFERENCE_TOLERANCE:
        rv, rn, rc, ref = vb, nb, cb, edge_b
        iv, inn, ic = va, na, ca
        flip = 1
    else:
        rv, rn, rc, ref = va, na, ca, edge_a
        iv, inn, ic = vb, nb, cb
        flip = 0
    nx = rn[ref, 0]
    ny = rn[ref, 1]
    # incident edge: the one whose normal is most anti-parallel to the reference normal
    inc = 0
    lowest = math.inf
    for k in range(ic):
        d = nx * inn[k, 0] + ny * inn[k, 1]
        if d < lowest:
            lowest = d
            inc = k
    inc2 = inc + 1 if inc + 1 < ic else 0
    ref2 = ref + 1 if ref + 1 < rc else 0
    r1x, r1y = rv[ref, 0], rv[ref, 1]
    r2x, r2y = rv[ref2, 0], rv[ref2, 1]
    tx = r2x - r1x
    ty = r2y - r1y
    tl = math.sqrt(tx * tx + ty * ty)
    tx /= tl
    ty /= tl
    p1x, p1y = iv[inc, 0], iv[inc, 1]
    p2x, p2y = iv[inc2, 0], iv[inc2, 1]
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
def collide(a, b, x, kind, radius, nverts, world_verts, world_normals, margin,
            normal, points, separations, ids):
    """Manifold of bodies a and b (a < b), normal from a to b. Returns the number of points."""
    if kind[a] == CIRCLE and kind[b] == CIRCLE:
        return collide_circles(x[a, 0], x[a, 1], radius[a], x[b, 0], x[b, 1], radius[b],
                               margin, normal, points, separations, ids)
    if kind[b] == CIRCLE:
        return collide_polygon_circle(world_verts[a], world_normals[a], nverts[a], x[b, 0], x[b, 1],
                                      radius[b], margin, normal, points, separations, ids)
    if kind[a] == CIRCLE:
        count = collide_polygon_circle(world_verts[b], world_normals[b], nverts[b], x[a, 0], x[a, 1],
                                       radius[a], margin, normal, points, separations, ids)
        normal[0] = -normal[0]
        normal[1] = -normal[1]
        return count
    return collide_polygons(world_verts[a], world_normals[a], nverts[a],
                            world_verts[b], world_normals[b], nverts[b],
                            margin, normal, points, separations, ids)
