"""Contact manifolds of two convex pieces: up to two points, a normal from the first piece to the second.

Pieces are convex polygons with a radius (circles one vertex, capsules and segments two). Polygon pairs
use the separating axis test (the axis of greatest separation over both pieces' edge normals), then
clip the incident edge against the reference edge's side planes (Sutherland-Hodgman on one segment),
as Box2D does; radii move the surfaces out along the normal. A circle against a polygon takes the edge
of greatest separation of its centre, which stays right when the centre is inside. Points are reported
while their separation is below `margin` (speculative contacts, so that an approaching body is caught
before it overlaps). Each point is placed midway between the two surfaces and carries a feature id of
8 bits that stays the same while the same features touch: that is what warm starting matches. Two
polygons' clipped points are named by the vertex of each piece they come from, A's then B's, whichever
face is the reference: two faces resting nearly parallel swap that role from tick to tick (their
separations within `REFERENCE_TOLERANCE`), and with the reference in the id each swap dropped the
points' impulses. In the 600 polygons of S5 that kept the pile jittering (from tick 600 on, 2.6 bodies a
tick faster than the sleep threshold, 99th-percentile speed 0.033 m/s; with vertex ids none, 0.0002 m/s,
as in Box2D, whose ids are the vertices too). The top bit orders a manifold's two points as A sees them.

Chain segments collide on the side the other piece lies on (its separation is the greater there) and
know their neighbours: a normal that a neighbouring segment should give is not given twice, and a
normal that points into the chain at a joint is snapped to the segment's own (Box2D's "ghost
collisions", https://box2d.org/posts/2020/06/ghost-collisions/). So a body slides and rolls across the
joints of a chain as across one straight or curved surface.

The routines write one pair's manifold into a `Collision` record and return its point count.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from rustycs.compiling import inlined
from rustycs.constants import CHAIN_ANGLE_TOLERANCE, LINEAR_SLOP, REFERENCE_TOLERANCE
from rustycs.pieces import OPEN_END, OPEN_START

VERTEX_TOLERANCE = 0.1 * LINEAR_SLOP  # m: cores further apart may meet vertex to vertex (Box2D)


class Collision(NamedTuple):
    """One pair's manifold as the routines write it."""

    normal: np.ndarray  # (2,) unit, from the first piece to the second
    points: np.ndarray  # (2, 2) world points midway between the surfaces
    separations: np.ndarray  # (2,) m, negative where the pieces overlap
    ids: np.ndarray  # (2,) int64 feature ids
    # (1,) m: with no points, a lower bound on the gap of the surfaces (a separating axis's separation, or
    # the distance), which continuous collision compares with the bodies' travel; 0 where none is known
    apart: np.ndarray


@njit(cache=True)
def new_collision():
    return Collision(np.zeros(2), np.zeros((2, 2)), np.zeros(2), np.zeros(2, np.int64), np.zeros(1))


@inlined
def collide_circles(xa, ya, ra, xb, yb, rb, margin, out):
    normal, points, separations, ids, apart = out  # unpacked once: a field read per use costs
    dx = xb - xa
    dy = yb - ya
    dist = math.sqrt(dx * dx + dy * dy)
    sep = dist - ra - rb
    if sep > margin:
        apart[0] = sep
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


@inlined
def collide_polygon_circle(verts, normals, counts, i, rp, cx, cy, r, margin, out):
    """Piece i (radius rp) against a circle; the normal points from the piece to the circle."""
    normal, points, separations, ids, apart = out  # unpacked once: a field read per use costs
    count = counts[i]
    best = -math.inf
    edge = 0
    for k in range(count):
        s = normals[i, k, 0] * (cx - verts[i, k, 0]) + normals[i, k, 1] * (cy - verts[i, k, 1])
        if s > best:
            best = s
            edge = k
    if best - r - rp > margin:
        apart[0] = best - r - rp
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
        sep = dist - r - rp
        if sep > margin:
            apart[0] = sep
            return 0
        nx = dx / dist
        ny = dy / dist
        ax, ay = vx, vy
    else:
        # face region (also when the centre is inside: push out through the nearest face)
        nx = normals[i, edge, 0]
        ny = normals[i, edge, 1]
        sep = best - r - rp
        ax = cx - best * nx
        ay = cy - best * ny
    normal[0] = nx
    normal[1] = ny
    points[0, 0] = 0.5 * (ax + rp * nx + cx - r * nx)
    points[0, 1] = 0.5 * (ay + rp * ny + cy - r * ny)
    separations[0] = sep
    ids[0] = 0
    return 1


@inlined
def _max_separation(verts, normals, counts, a, b):
    """Edge of piece a with the greatest separation of piece b's vertices from it.

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


@inlined
def _box_axes(verts, normals, centre, i):
    """A box's distances from its centre to its faces 0 and 1, which are also those to faces 2 and 3
    (a box's vertices run from its lower left corner, counter-clockwise, so face k + 2 is opposite
    face k)."""
    cx, cy = centre[i, 0], centre[i, 1]
    h0 = normals[i, 0, 0] * (verts[i, 0, 0] - cx) + normals[i, 0, 1] * (verts[i, 0, 1] - cy)
    h1 = normals[i, 1, 0] * (verts[i, 1, 0] - cx) + normals[i, 1, 1] * (verts[i, 1, 1] - cy)
    return h0, h1


@inlined
def _box_max_separation(normals, centre, a, ha0, ha1, b, hb0, hb1):
    """`_max_separation` for two boxes, with a quarter of the projections: the lowest point of box b
    along a normal n lies |n.e0| hb0 + |n.e1| hb1 below its centre (e0, e1 its face normals, hb0, hb1 its
    distances to them), and each of a's two axes serves a pair of opposite faces."""
    dx = centre[b, 0] - centre[a, 0]
    dy = centre[b, 1] - centre[a, 1]
    best = -math.inf
    edge = 0
    for k in range(4):
        nx = normals[a, k % 2, 0]
        ny = normals[a, k % 2, 1]
        reach = (abs(nx * normals[b, 0, 0] + ny * normals[b, 0, 1]) * hb0
                 + abs(nx * normals[b, 1, 0] + ny * normals[b, 1, 1]) * hb1)
        centre_gap = nx * dx + ny * dy
        s = (centre_gap if k < 2 else -centre_gap) - (ha0 if k % 2 == 0 else ha1) - reach
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


@inlined
def _clip_edges(r1x, r1y, r2x, r2y, nx, ny, p1x, p1y, p2x, p2y, r_ref, r_inc, margin, base, flip, out):
    """Clip the incident edge p1 -> p2 (running against the reference edge) to the slab between the
    reference edge r1 -> r2's side planes, and keep the points within `margin` of the reference
    surface; the normal is the reference's outward n, reversed when `flip`. Point ids are
    base | slot."""
    normal, points, separations, ids, apart = out  # unpacked once: a field read per use costs
    # the reference edge's direction: its outward normal turned a quarter back (counter-clockwise winding)
    tx = -ny
    ty = nx
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
    radius = r_ref + r_inc
    count = 0
    for slot in range(2):
        qx = q1x if slot == 0 else q2x
        qy = q1y if slot == 0 else q2y
        core = nx * (qx - r1x) + ny * (qy - r1y)
        sep = core - radius
        if sep > margin:
            continue
        # midway between the reference surface (r_ref out) and the incident one (r_inc in)
        shift = 0.5 * (r_ref - r_inc - core)
        points[count, 0] = qx + shift * nx
        points[count, 1] = qy + shift * ny
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


@inlined
def collide_polygons(verts, normals, counts, centre, boxes, a, ra, b, rb, margin, out):
    """Pieces a and b with radii ra and rb (with `boxes`, two boxes); the normal points from a to b."""
    normal, points, separations, ids, apart = out  # unpacked once: a field read per use costs
    radius = ra + rb
    if boxes:
        ha0, ha1 = _box_axes(verts, normals, centre, a)
        hb0, hb1 = _box_axes(verts, normals, centre, b)
        edge_a, sep_a = _box_max_separation(normals, centre, a, ha0, ha1, b, hb0, hb1)
        if sep_a - radius > margin:
            apart[0] = sep_a - radius
            return 0
        edge_b, sep_b = _box_max_separation(normals, centre, b, hb0, hb1, a, ha0, ha1)
    else:
        edge_a, sep_a = _max_separation(verts, normals, counts, a, b)
        if sep_a - radius > margin:
            apart[0] = sep_a - radius
            return 0
        edge_b, sep_b = _max_separation(verts, normals, counts, b, a)
    # an axis's separation is at most the distance: a bound for the pair whether or not it has points
    apart[0] = max(sep_a, sep_b) - radius
    if sep_b - radius > margin:
        return 0
    if sep_b > sep_a + REFERENCE_TOLERANCE:
        r, ref, i, r_ref, r_inc = b, edge_b, a, rb, ra
        flip = 1
    else:
        r, ref, i, r_ref, r_inc = a, edge_a, b, ra, rb
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
    count = 0
    # the incident edge runs against the reference edge, so d1 > d2 normally
    if d1 != d2 and not ((d1 < lo and d2 < lo) or (d1 > hi and d2 > hi)):
        q1x, q1y = _clip(p1x, p1y, p2x, p2y, d1, d2, lo, hi)
        q2x, q2y = _clip(p2x, p2y, p1x, p1y, d2, d1, lo, hi)
        for slot in range(2):
            qx = q1x if slot == 0 else q2x
            qy = q1y if slot == 0 else q2y
            core = nx * (qx - r1x) + ny * (qy - r1y)
            sep = core - radius
            if sep > margin:
                continue
            # midway between the reference surface (r_ref out) and the incident one (r_inc in)
            shift = 0.5 * (r_ref - r_inc - core)
            points[count, 0] = qx + shift * nx
            points[count, 1] = qy + shift * ny
            separations[count] = sep
            # the incident edge runs against the reference edge: its first vertex lies by the second
            # reference vertex; a flip swaps the slots, so slot ^ flip orders the points as A sees them
            v_ref, v_inc = (ref2, inc) if slot == 0 else (ref, inc2)
            ids[count] = ((slot ^ flip) << 7) | _vertex_pair(v_ref, v_inc, flip)
            count += 1
    if flip:
        normal[0] = -nx
        normal[1] = -ny
    else:
        normal[0] = nx
        normal[1] = ny
    if radius > 0.0 and max(sep_a, sep_b) > VERTEX_TOLERANCE:
        return _rounded_corners(r1x, r1y, r2x, r2y, p1x, p1y, p2x, p2y, ref, ref2, inc, inc2, r_ref, r_inc,
                                flip, margin, count, out)
    return count


@njit(cache=True)
def _rounded_corners(r1x, r1y, r2x, r2y, p1x, p1y, p2x, p2y, ref, ref2, inc, inc2, r_ref, r_inc, flip, margin,
                     count, out):
    """Rounded pieces whose cores are apart: the closest features of the reference and incident edges
    may be two vertices (a capsule's end against a box's corner), which the faces' axes only bound from
    below; then one point between those vertices replaces the clipped ones. (Not for sharp pieces: the
    vertices' distance cost 7 % of the 600-polygon scene's narrow phase; and a call of its own, so that
    the common pairs' loop stays small.)"""
    normal, points, separations, ids, apart = out  # unpacked once: a field read per use costs
    radius = r_ref + r_inc
    f1, f2, gap2 = _segment_distance(r1x, r1y, r2x, r2y, p1x, p1y, p2x, p2y)
    gap = math.sqrt(gap2)
    if gap - radius > margin:
        return 0
    closest = math.inf
    for k in range(count):
        closest = min(closest, separations[k])
    at_vertices = (f1 == 0.0 or f1 == 1.0) and (f2 == 0.0 or f2 == 1.0)
    if not (at_vertices and gap - radius + VERTEX_TOLERANCE < closest):
        return count
    vx, vy = (r1x, r1y) if f1 == 0.0 else (r2x, r2y)
    wx, wy = (p1x, p1y) if f2 == 0.0 else (p2x, p2y)
    ux, uy = (wx - vx) / gap, (wy - vy) / gap  # from the reference vertex to the incident one
    normal[0], normal[1] = (-ux, -uy) if flip else (ux, uy)
    points[0, 0] = 0.5 * (vx + r_ref * ux + wx - r_inc * ux)
    points[0, 1] = 0.5 * (vy + r_ref * uy + wy - r_inc * uy)
    separations[0] = gap - radius
    # a vertex pair's id: both vertices' indices, A's first, and a bit the clipped points' ids never set
    v_ref = ref if f1 == 0.0 else ref2
    v_inc = inc if f2 == 0.0 else inc2
    ids[0] = (1 << 6) | _vertex_pair(v_ref, v_inc, flip)
    return 1


@inlined
def _vertex_pair(v_ref, v_inc, flip):
    """The 6 bits naming a reference and an incident vertex as A's then B's (`flip`: B holds the reference),
    the same whichever piece's face is the reference."""
    return (v_inc << 3) | v_ref if flip else (v_ref << 3) | v_inc


@inlined
def collide_capsules(verts, a, ra, b, rb, margin, out):
    """Two pieces of two vertices each (capsules, segments): their cores are segments, whose side normals
    alone miss the ends, so the closest points of the segments decide. Where their projections overlap,
    the reference segment's face (the side of greater separation) clips the other to two points, as a
    capsule resting on another needs; otherwise one point between the closest points."""
    normal, points, separations, ids, apart = out  # unpacked once: a field read per use costs
    p1x, p1y, q1x, q1y = verts[a, 0, 0], verts[a, 0, 1], verts[a, 1, 0], verts[a, 1, 1]
    p2x, p2y, q2x, q2y = verts[b, 0, 0], verts[b, 0, 1], verts[b, 1, 0], verts[b, 1, 1]
    radius = ra + rb
    f1, f2, gap2 = _segment_distance(p1x, p1y, q1x, q1y, p2x, p2y, q2x, q2y)
    gap = math.sqrt(gap2)
    if gap - radius > margin:
        apart[0] = gap - radius
        return 0
    count = 0
    for flip in range(2):  # each segment as the reference in turn, the first whose face clips wins
        if count:
            break
        if flip:
            rx, ry, sx, sy, ix, iy, jx, jy, r_ref, r_inc = p2x, p2y, q2x, q2y, p1x, p1y, q1x, q1y, rb, ra
        else:
            rx, ry, sx, sy, ix, iy, jx, jy, r_ref, r_inc = p1x, p1y, q1x, q1y, p2x, p2y, q2x, q2y, ra, rb
        length = math.sqrt((sx - rx) ** 2 + (sy - ry) ** 2)
        ux, uy = (sx - rx) / length, (sy - ry) / length
        di = ux * (ix - rx) + uy * (iy - ry)
        dj = ux * (jx - rx) + uy * (jy - ry)
        if (di <= 0.0 and dj <= 0.0) or (di >= length and dj >= length):
            continue  # the other segment lies beyond an end of this one
        nx, ny = -uy, ux  # the face towards the other segment
        if nx * (ix + jx - rx - sx) + ny * (iy + jy - ry - sy) < 0.0:
            nx, ny = -nx, -ny
        # the other segment clipped to this one's extent
        cix, ciy, cjx, cjy = ix, iy, jx, jy
        if di < 0.0:
            t = -di / (dj - di)
            cix, ciy = ix + t * (jx - ix), iy + t * (jy - iy)
        elif di > length:
            t = (di - length) / (di - dj)
            cix, ciy = ix + t * (jx - ix), iy + t * (jy - iy)
        if dj < 0.0:
            t = -dj / (di - dj)
            cjx, cjy = jx + t * (ix - jx), jy + t * (iy - jy)
        elif dj > length:
            t = (dj - length) / (dj - di)
            cjx, cjy = jx + t * (ix - jx), jy + t * (iy - jy)
        si = nx * (cix - rx) + ny * (ciy - ry)
        sj = nx * (cjx - rx) + ny * (cjy - ry)
        if min(si, sj) > gap + LINEAR_SLOP:
            continue  # the face is not where the segments are closest (crossing or far apart)
        for slot in range(2):
            cx, cy, core = (cix, ciy, si) if slot == 0 else (cjx, cjy, sj)
            if core - radius > margin:
                continue
            shift = 0.5 * (r_ref - r_inc - core)
            points[count, 0] = cx + shift * nx
            points[count, 1] = cy + shift * ny
            separations[count] = core - radius
            ids[count] = (flip << 7) | (1 << 5) | slot
            count += 1
        normal[0], normal[1] = (-nx, -ny) if flip else (nx, ny)
    if count:
        return count
    # one point between the closest points
    cx1, cy1 = p1x + f1 * (q1x - p1x), p1y + f1 * (q1y - p1y)
    cx2, cy2 = p2x + f2 * (q2x - p2x), p2y + f2 * (q2y - p2y)
    if gap > 1e-12:
        nx, ny = (cx2 - cx1) / gap, (cy2 - cy1) / gap
    else:
        length = math.sqrt((q1x - p1x) ** 2 + (q1y - p1y) ** 2)
        nx, ny = -(q1y - p1y) / length, (q1x - p1x) / length
    normal[0], normal[1] = nx, ny
    points[0, 0] = 0.5 * (cx1 + ra * nx + cx2 - rb * nx)
    points[0, 1] = 0.5 * (cy1 + ra * ny + cy2 - rb * ny)
    separations[0] = gap - radius
    ids[0] = (int(f1 > 0.0) << 1) | int(f2 > 0.0)
    return 1


@inlined
def _segment_distance(p1x, p1y, q1x, q1y, p2x, p2y, q2x, q2y):
    """Closest points of the segments p1 q1 and p2 q2: the fractions along each (0 and 1: their ends)
    and the squared distance between the points."""
    d1x, d1y = q1x - p1x, q1y - p1y
    d2x, d2y = q2x - p2x, q2y - p2y
    rx, ry = p1x - p2x, p1y - p2y
    dd1 = d1x * d1x + d1y * d1y
    dd2 = d2x * d2x + d2y * d2y
    rd1 = rx * d1x + ry * d1y
    rd2 = rx * d2x + ry * d2y
    d12 = d1x * d2x + d1y * d2y
    denominator = dd1 * dd2 - d12 * d12
    f1 = min(max((d12 * rd2 - rd1 * dd2) / denominator, 0.0), 1.0) if denominator != 0.0 else 0.0
    f2 = (d12 * f1 + rd2) / dd2
    if f2 < 0.0:  # clamped on segment 2: the closest point on segment 1 again
        f2 = 0.0
        f1 = min(max(-rd1 / dd1, 0.0), 1.0)
    elif f2 > 1.0:
        f2 = 1.0
        f1 = min(max((d12 - rd1) / dd1, 0.0), 1.0)
    cx = p1x + f1 * d1x - p2x - f2 * d2x
    cy = p1y + f1 * d1y - p2y - f2 * d2y
    return f1, f2, cx * cx + cy * cy


# ------------------------------------------------------------------------------- chain segments

@inlined
def _unit(x, y):
    length = math.sqrt(x * x + y * y)
    return x / length, y / length


@inlined
def _chain_side(verts, normals, ghosts, open_ends, c, flip):
    """Segment c's points, neighbours and open ends as seen from its side `flip` (0: the side its
    normal 0 points to; 1: the other, with the segment's direction reversed)."""
    v, g, ends = verts[c], ghosts[c], open_ends[c]
    if flip:
        swapped = ((ends & OPEN_START) != 0) * OPEN_END | ((ends & OPEN_END) != 0) * OPEN_START
        return (v[1, 0], v[1, 1], v[0, 0], v[0, 1], g[1, 0], g[1, 1], g[0, 0], g[0, 1], swapped,
                -normals[c, 0, 0], -normals[c, 0, 1])
    return (v[0, 0], v[0, 1], v[1, 0], v[1, 1], g[0, 0], g[0, 1], g[1, 0], g[1, 1], ends,
            normals[c, 0, 0], normals[c, 0, 1])


@inlined
def collide_chain_circle(verts, normals, ghosts, open_ends, c, cx, cy, r, margin, out):
    """Chain segment c against a circle; the normal points from the segment to the circle. The joint
    with the previous segment belongs to that segment, and a centre over the next segment's face is
    the next segment's."""
    normal, points, separations, ids, apart = out  # unpacked once: a field read per use costs
    offset = normals[c, 0, 0] * (cx - verts[c, 0, 0]) + normals[c, 0, 1] * (cy - verts[c, 0, 1])
    flip = 1 if offset < 0.0 else 0
    p1x, p1y, p2x, p2y, _, _, g2x, g2y, ends, fnx, fny = _chain_side(verts, normals, ghosts, open_ends, c,
                                                                     flip)
    ex = p2x - p1x
    ey = p2y - p1y
    v = ex * (cx - p1x) + ey * (cy - p1y)
    u = ex * (p2x - cx) + ey * (p2y - cy)
    if v <= 0.0:
        if not ends & OPEN_START:
            return 0
        ax, ay, feature = p1x, p1y, 1
    elif u <= 0.0:
        if not ends & OPEN_END and (g2x - p2x) * (cx - p2x) + (g2y - p2y) * (cy - p2y) > 0.0:
            return 0
        ax, ay, feature = p2x, p2y, 2
    else:
        f = v / (ex * ex + ey * ey)
        ax, ay, feature = p1x + f * ex, p1y + f * ey, 0
    dx = cx - ax
    dy = cy - ay
    dist = math.sqrt(dx * dx + dy * dy)
    sep = dist - r
    if sep > margin:
        return 0
    if dist > 1e-12:
        nx = dx / dist
        ny = dy / dist
    else:
        nx, ny = fnx, fny
    normal[0] = nx
    normal[1] = ny
    points[0, 0] = 0.5 * (ax + cx - r * nx)
    points[0, 1] = 0.5 * (ay + cy - r * ny)
    separations[0] = sep
    ids[0] = (flip << 7) | feature
    return 1


SKIP, ADMIT, SNAP = 0, 1, 2


@inlined
def _classify(mx, my, ex, ey, convex1, n0x, n0y, convex2, n2x, n2y):
    """What a candidate normal m (from the segment, direction e) means at the segment's joints: ADMIT
    where it lies in the segment's share of a convex joint's vertex region, SKIP where it belongs to
    the neighbour, SNAP where the joint is concave or flat (the segment's own normal holds)."""
    if mx * ex + my * ey <= 0.0:  # towards the segment's first point
        if convex1:
            return SKIP if mx * n0y - my * n0x > CHAIN_ANGLE_TOLERANCE else ADMIT
        return SNAP
    if convex2:
        return SKIP if n2x * my - n2y * mx > CHAIN_ANGLE_TOLERANCE else ADMIT
    return SNAP


@inlined
def _min_offset(verts, counts, p, nx, ny, ox, oy):
    """The least n . (v - o) over piece p's vertices, and the vertex that gives it."""
    best = math.inf
    which = 0
    for k in range(counts[p]):
        s = nx * (verts[p, k, 0] - ox) + ny * (verts[p, k, 1] - oy)
        if s < best:
            best = s
            which = k
    return best, which


@inlined
def collide_chain_polygon(verts, normals, counts, ghosts, open_ends, c, p, rp, margin, out):
    """Chain segment c against piece p (radius rp: a polygon, a capsule, a segment or another chain's
    segment); the normal points from the segment to the piece.

    The candidate axes are the segment's normal on the piece's side, the normals of convex
    neighbouring segments (the neighbour gives those contacts: none here) and the piece's edge
    normals that `_classify` admits. The greatest separation wins, then the incident edge is clipped
    to the reference edge as for two polygons."""
    nx, ny, ox, oy = normals[c, 0, 0], normals[c, 0, 1], verts[c, 0, 0], verts[c, 0, 1]
    front, _ = _min_offset(verts, counts, p, nx, ny, ox, oy)
    back, _ = _min_offset(verts, counts, p, -nx, -ny, ox, oy)
    flip = 1 if back > front else 0
    p1x, p1y, p2x, p2y, g1x, g1y, g2x, g2y, ends, n1x, n1y = _chain_side(verts, normals, ghosts, open_ends, c,
                                                                         flip)
    ex, ey = _unit(p2x - p1x, p2y - p1y)
    e0x, e0y = _unit(p1x - g1x, p1y - g1y)
    e2x, e2y = _unit(g2x - p2x, g2y - p2y)
    open1 = (ends & OPEN_START) != 0
    open2 = (ends & OPEN_END) != 0
    convex1 = open1 or e0x * ey - e0y * ex >= CHAIN_ANGLE_TOLERANCE
    convex2 = open2 or ex * e2y - ey * e2x >= CHAIN_ANGLE_TOLERANCE
    n0x, n0y = (e0y, -e0x) if convex1 else (n1x, n1y)
    n2x, n2y = (e2y, -e2x) if convex2 else (n1x, n1y)

    edge_separation, incident = _min_offset(verts, counts, p, n1x, n1y, p1x, p1y)
    if convex1 and not open1:
        s0, _ = _min_offset(verts, counts, p, n0x, n0y, p1x, p1y)
        if s0 > edge_separation:
            edge_separation, incident = s0, -1
    if convex2 and not open2:
        s2, _ = _min_offset(verts, counts, p, n2x, n2y, p2x, p2y)
        if s2 > edge_separation:
            edge_separation, incident = s2, -1
    polygon_separation = -math.inf
    reference = -1
    for k in range(counts[p]):
        mx, my = normals[p, k, 0], normals[p, k, 1]
        if _classify(-mx, -my, ex, ey, convex1, n0x, n0y, convex2, n2x, n2y) != ADMIT:
            continue
        vx, vy = verts[p, k, 0], verts[p, k, 1]
        s = min(mx * (p1x - vx) + my * (p1y - vy), mx * (p2x - vx) + my * (p2y - vy))
        if s > polygon_separation:
            polygon_separation, reference = s, k
    if max(edge_separation, polygon_separation) - rp > margin:
        return 0
    base = flip << 7
    if polygon_separation > edge_separation + REFERENCE_TOLERANCE:
        # a face of the piece is the reference, the segment incident; unless a neighbour is more so
        k2 = reference + 1 if reference + 1 < counts[p] else 0
        mx, my = normals[p, reference, 0], normals[p, reference, 1]
        ax, ay = verts[p, reference, 0], verts[p, reference, 1]
        deeper_first = mx * (p1x - ax) + my * (p1y - ay) < mx * (p2x - ax) + my * (p2y - ay)
        own = n1x * mx + n1y * my
        if (deeper_first and n0x * mx + n0y * my < own) or (not deeper_first and n2x * mx + n2y * my < own):
            return 0
        return _clip_edges(ax, ay, verts[p, k2, 0], verts[p, k2, 1], mx, my, p1x, p1y, p2x, p2y, rp, 0.0,
                           margin, base | (1 << 6) | (reference << 3), 1, out)
    if incident < 0:
        return 0  # a neighbouring segment gives this contact
    # the segment is the reference; the incident edge is the one beside the deepest vertex that faces it most
    before = incident - 1 if incident > 0 else counts[p] - 1
    if normals[p, before, 0] * n1x + normals[p, before, 1] * n1y < (normals[p, incident, 0] * n1x
                                                                     + normals[p, incident, 1] * n1y):
        first = before
    else:
        first = incident
    second = first + 1 if first + 1 < counts[p] else 0
    return _clip_edges(p1x, p1y, p2x, p2y, n1x, n1y, verts[p, first, 0], verts[p, first, 1],
                       verts[p, second, 0], verts[p, second, 1], 0.0, rp, margin, base | (first << 3), 0, out)

