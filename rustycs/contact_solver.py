"""Contact solver: soft sequential impulses with substeps and relaxation (Box2D v3's "soft step").

Every tick: prepare the contacts (effective masses, the approach speed for restitution), then for
each substep integrate velocities, warm start, solve with a soft position bias, integrate positions
and relax without bias (so the bias that removed overlap adds no energy), then apply restitution and
keep the accumulated impulses for the next tick's warm start.

Impulses accumulate per point: the normal impulse is clamped at >= 0 and the friction impulse to
|f| <= mu * normal impulse. The separation of each point is updated inside the step from the bodies'
motion since the narrow phase, so substeps see the overlap shrink.

The contacts are solved in the chunks of `contact_batches.schedule`: `LANES` contacts that share no
movable body, side by side in the lane buffer. A pass over a chunk gathers its bodies' velocities
into a chunk's worth of fields on the stack, solves all lanes at once (the loop has no dependencies
between lanes, so LLVM turns it into SIMD instructions) and scatters the velocities back; chunk after
chunk, that is exactly the sequence of contacts sorted by body ids, applied to each body in that order.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rustycs.body_types import DYNAMIC
from rustycs.compiling import inlined, inlined_early, stack_buffer, stage
from rustycs.constants import MAX_PUSH_SPEED
from rustycs.narrow_phase import (
    FRICTION,
    NORMAL_IMPULSE,
    NX,
    NY,
    RAX,
    RAY,
    RBX,
    RBY,
    RESTITUTION,
    SEPARATION,
    TANGENT_IMPULSE,
)

# columns of a solver body row: velocities, inverse masses, displacement and rotation (cos, sin) since the
# narrow phase, and the warm velocity (see `warm_start_again`)
VX, VY, W, INV_MASS, INV_INERTIA, DX, DY, COS, SIN, WARM_VX, WARM_VY, WARM_W = range(12)
BODY_COLUMNS = 12
# The lane buffer: chunks of `LANES` contacts, each field of a chunk `LANES` values wide (field f of
# lane j at the chunk's start + f * LANES + j), so that a loop over a chunk's lanes reads and writes
# consecutive values. Offsets are unsigned: numba then indexes without wrap-around checks, which keep
# LLVM from vectorising. A contact's fields: inverse masses, normal, friction, restitution, the
# approach of the centres along the normal and the rotations since the narrow phase (gathered by the
# relax pass, right after the positions moved, for the biased pass of the next substep too), and the
# inverse determinant of its two points' effective mass matrix (0 for one point, or points that act as
# one: see `_two_points`).
LANES = 8
(L_MA, L_IA, L_MB, L_IB, L_NX, L_NY, L_MU, L_E, L_DN, L_CA, L_SA, L_CB, L_SB,
 L_INV_DET) = (np.uint64(f * LANES) for f in range(14))
CONTACT_FIELDS = 14
# a point's fields, from its first: the anchors' cross products with the normal and the tangent and
# dot products with the normal, the separation less the anchors' projection, effective masses,
# accumulated impulses, the normal impulse of the whole tick (each substep's accumulated one, summed by
# the relax pass: what the bodies' velocities took from the point), the normal speed it should leave at
# (`bounce_targets`)
(P_RNA, P_RNB, P_RTA, P_RTB, P_RDA, P_RDB, P_SEPARATION, P_NORMAL_MASS, P_TANGENT_MASS, P_NORMAL_IMPULSE,
 P_TANGENT_IMPULSE, P_TICK_NORMAL_IMPULSE, P_BOUNCE) = (np.uint64(f * LANES) for f in range(13))
POINT_FIELDS = 13
LANE_FIELDS = CONTACT_FIELDS + 2 * POINT_FIELDS
# The velocities a pass gathers from the bodies of the chunk it solves go to one chunk's worth of fields
# on the stack, laid out as a chunk's, rather than to room kept in every contact (6 fields of 46): the
# 58,000 contacts of many_pyramids, 21 MB of lanes, stream from memory on every pass, and their substeps
# took 7.4-7.6 ms a tick instead of 11-13 (the 5,050-box pyramid's, in cache, 1.22-1.37 against 1.25-1.42).
# Also gathering the poses there (11 fields) cost that pyramid 18 % more: the biased pass gathers them again.
GATHERED_FIELDS = 6
G_VAX, G_VAY, G_WA, G_VBX, G_VBY, G_WB = (np.uint64(f * LANES) for f in range(GATHERED_FIELDS))
_gathered_area = stack_buffer(GATHERED_FIELDS * LANES)
_CHUNK = np.uint64(LANE_FIELDS * LANES)
_FIRST_POINT = np.uint64(CONTACT_FIELDS * LANES)
_POINT_STRIDE = np.uint64(POINT_FIELDS * LANES)


@njit(cache=True)
def softness(hertz, zeta, h):
    """Bias rate, mass scale and impulse scale of a soft constraint (a damped spring)."""
    omega = 2.0 * math.pi * hertz
    a1 = 2.0 * zeta + h * omega
    a2 = h * omega * a1
    a3 = 1.0 / (1.0 + a2)
    return omega / a1, a2 * a3, a3


@inlined_early
def lane_index(c, j):
    """Index of field 0 of lane j of chunk c."""
    return np.uint64(c) * _CHUNK + np.uint64(j)


@inlined_early
def point_index(o, k):
    """Index of field 0 of point k of the contact whose lane index is o."""
    return o + _FIRST_POINT + np.uint64(k) * _POINT_STRIDE


@inlined_early
def _zero(lanes, start, fields):
    """Zero `fields` fields of one lane from index `start`."""
    for f in range(fields):
        lanes[start + np.uint64(f * LANES)] = 0.0


@inlined_early
def relative_speed(vax, vay, wa, vbx, vby, wb, nx, ny, rna, rnb):
    """Speed of b's contact point relative to a's along the normal (n), or along the tangent when given
    the tangent and the anchors' cross products with it: (vb + wb x rb - va - wa x ra) . n."""
    return (vbx - vax) * nx + (vby - vay) * ny + (wb * rnb - wa * rna)


@inlined_early
def load_bodies(bodies, body):
    """Fill the solver rows of the bodies: velocities, inverse masses (none for a body asleep: a joint to
    the world moves it no more than a wall), no displacement yet since the narrow phase."""
    v, w, asleep = bodies.v, bodies.w, bodies.asleep
    inv_mass, inv_inertia = bodies.inv_mass, bodies.inv_inertia
    for i in range(v.shape[0]):
        body[i, VX] = v[i, 0]
        body[i, VY] = v[i, 1]
        body[i, W] = w[i]
        body[i, INV_MASS] = 0.0 if asleep[i] else inv_mass[i]
        body[i, INV_INERTIA] = 0.0 if asleep[i] else inv_inertia[i]
        body[i, DX] = 0.0
        body[i, DY] = 0.0
        body[i, COS] = 1.0
        body[i, SIN] = 0.0


@inlined_early
def store_bodies(body, bodies):
    """Copy velocities back to the dynamic bodies (the others' velocities are theirs to keep)."""
    v, w, body_type = bodies.v, bodies.w, bodies.body_type
    for i in range(v.shape[0]):
        if body_type[i] != DYNAMIC:
            continue
        v[i, 0] = body[i, VX]
        v[i, 1] = body[i, VY]
        w[i] = body[i, W]


@stage
def prepare(batches, n_chunks, manifolds, points, radius, body, lanes):
    """Fill the lanes of the scheduled contacts: inverse masses, normal, friction, restitution, and per
    point the anchors' products with the normal and the tangent, the effective masses and the
    warm-start impulses. An empty lane, or a manifold's missing second point, is all zeros: it solves to
    no impulse, and so stays zero through the passes. So they are zeroed only when the slots were placed
    anew (`Batches.fresh`): a resting pyramid's ticks keep their slots, and zeroing S2's 354 empty lanes
    every tick was a third of its lane stores. Returns the number of contacts that may bounce
    (restitution above 0).

    The separation is followed through the substeps by turning each anchor with its body, less the
    shape's radius (`radius`, per shape): the surface of a rounded shape meets the other where its core
    is nearest, whichever way the shape has turned. With the radius turned too, a ball glancing off a
    wall at 167 m/s, spun up to 800 rad/s by friction, turned its anchor away from the wall and went
    through it."""
    # np.int64(0), not the literal 0: one compiled `prepare_chunks` for this and the parts
    return prepare_chunks(np.int64(0), n_chunks, batches, manifolds, points, radius, body, lanes)


@inlined
def prepare_chunks(start, stop, batches, manifolds, points, radius, body, lanes):
    """`prepare` for chunks start .. stop - 1 (each chunk's lanes depend on its own contacts alone)."""
    fill, slot_manifold, fresh = batches.fill, batches.slot_manifold, batches.fresh[0]
    m_a, m_b, manifold = manifolds.body_a, manifolds.body_b, manifolds.data
    shape_a, shape_b = manifolds.shape_a, manifolds.shape_b
    m_first, m_count = manifolds.first, manifolds.count
    point = points.data
    bouncy = 0
    for c in range(start, stop):
        for j in range(fill[c], LANES if fresh else 0):
            _zero(lanes, lane_index(c, j), LANE_FIELDS)
        for j in range(fill[c]):
            o = lane_index(c, j)
            m = slot_manifold[c * LANES + j]
            a = m_a[m]
            b = m_b[m]
            ma, mb = body[a, INV_MASS], body[b, INV_MASS]
            ia, ib = body[a, INV_INERTIA], body[b, INV_INERTIA]
            nx, ny = manifold[m, NX], manifold[m, NY]
            tx, ty = ny, -nx
            lanes[o + L_MA] = ma
            lanes[o + L_IA] = ia
            lanes[o + L_MB] = mb
            lanes[o + L_IB] = ib
            lanes[o + L_NX] = nx
            lanes[o + L_NY] = ny
            lanes[o + L_MU] = manifold[m, FRICTION]
            lanes[o + L_E] = manifold[m, RESTITUTION]
            bouncy += manifold[m, RESTITUTION] != 0.0
            # no motion yet since the narrow phase (see `solve` for when the poses are gathered)
            lanes[o + L_DN] = 0.0
            lanes[o + L_CA], lanes[o + L_SA], lanes[o + L_CB], lanes[o + L_SB] = 1.0, 0.0, 1.0, 0.0
            for k in range(m_count[m]):
                q = point_index(o, k)
                p = m_first[m] + k
                rax, ray, rbx, rby = point[p, RAX], point[p, RAY], point[p, RBX], point[p, RBY]
                rna = rax * ny - ray * nx
                rnb = rbx * ny - rby * nx
                rta = rax * ty - ray * tx
                rtb = rbx * ty - rby * tx
                rda = rax * nx + ray * ny - radius[shape_a[m]]  # the anchors on the cores
                rdb = rbx * nx + rby * ny + radius[shape_b[m]]
                lanes[q + P_RNA] = rna
                lanes[q + P_RNB] = rnb
                lanes[q + P_RTA] = rta
                lanes[q + P_RTB] = rtb
                lanes[q + P_RDA] = rda
                lanes[q + P_RDB] = rdb
                kn = ma + mb + ia * rna * rna + ib * rnb * rnb
                kt = ma + mb + ia * rta * rta + ib * rtb * rtb
                lanes[q + P_NORMAL_MASS] = 1.0 / kn if kn > 0.0 else 0.0
                lanes[q + P_TANGENT_MASS] = 1.0 / kt if kt > 0.0 else 0.0
                lanes[q + P_SEPARATION] = point[p, SEPARATION] - (rdb - rda)
                lanes[q + P_NORMAL_IMPULSE] = point[p, NORMAL_IMPULSE]
                lanes[q + P_TANGENT_IMPULSE] = point[p, TANGENT_IMPULSE]
                lanes[q + P_TICK_NORMAL_IMPULSE] = 0.0
            lanes[o + L_INV_DET] = 0.0
            if m_count[m] == 1:
                if fresh:
                    _zero(lanes, point_index(o, 1), POINT_FIELDS)
            else:
                q1, q2 = point_index(o, 0), point_index(o, 1)
                k11, k12, k22 = _point_masses(ma, ia, mb, ib, lanes[q1 + P_RNA], lanes[q1 + P_RNB],
                                              lanes[q2 + P_RNA], lanes[q2 + P_RNB])
                det = k11 * k22 - k12 * k12
                if det > 1e-9 * k11 * k22:  # else the points are nearly one: taken one at a time
                    lanes[o + L_INV_DET] = 1.0 / det
    return bouncy


@inlined_early
def store_impulses(batches, first, last, manifolds, lanes, points):
    """Copy the accumulated impulses of chunks first .. last - 1 back to the point rows (the next tick's
    warm start)."""
    fill, slot_manifold = batches.fill, batches.slot_manifold
    m_first, m_count, point = manifolds.first, manifolds.count, points.data
    for c in range(first, last):
        for j in range(fill[c]):
            m = slot_manifold[c * LANES + j]
            for k in range(m_count[m]):
                q = point_index(lane_index(c, j), k)
                point[m_first[m] + k, NORMAL_IMPULSE] = lanes[q + P_NORMAL_IMPULSE]
                point[m_first[m] + k, TANGENT_IMPULSE] = lanes[q + P_TANGENT_IMPULSE]


@inlined_early
def _gather(batches, c, body, lanes, gathered, poses):
    """Load the velocities of chunk c's bodies into `gathered`; with `poses`, also the approach of the
    centres along the normal and the rotations since the narrow phase. Empty lanes get zeros (no impulse
    comes of them)."""
    fill, slot_a, slot_b = batches.fill, batches.slot_a, batches.slot_b
    for j in range(fill[c]):
        o = lane_index(c, j)
        g = np.uint64(j)
        a = slot_a[c * LANES + j]
        b = slot_b[c * LANES + j]
        gathered[g + G_VAX], gathered[g + G_VAY], gathered[g + G_WA] = body[a, VX], body[a, VY], body[a, W]
        gathered[g + G_VBX], gathered[g + G_VBY], gathered[g + G_WB] = body[b, VX], body[b, VY], body[b, W]
        if poses:
            nx, ny = lanes[o + L_NX], lanes[o + L_NY]
            lanes[o + L_DN] = (body[b, DX] - body[a, DX]) * nx + (body[b, DY] - body[a, DY]) * ny
            lanes[o + L_CA], lanes[o + L_SA] = body[a, COS], body[a, SIN]
            lanes[o + L_CB], lanes[o + L_SB] = body[b, COS], body[b, SIN]
    for j in range(fill[c], LANES):
        _zero(gathered, np.uint64(j), GATHERED_FIELDS)


@inlined_early
def _scatter(batches, c, gathered, body):
    """Write chunk c's velocities back from `gathered` to its bodies, except immovable ones: the lanes of
    a chunk may share those, and they are never written, so that no contact waits for another through
    them."""
    fill, slot_a, slot_b = batches.fill, batches.slot_a, batches.slot_b
    for j in range(fill[c]):
        g = np.uint64(j)
        a = slot_a[c * LANES + j]
        b = slot_b[c * LANES + j]
        if body[a, INV_MASS] != 0.0 or body[a, INV_INERTIA] != 0.0:
            body[a, VX], body[a, VY], body[a, W] = (
                gathered[g + G_VAX], gathered[g + G_VAY], gathered[g + G_WA])
        if body[b, INV_MASS] != 0.0 or body[b, INV_INERTIA] != 0.0:
            body[b, VX], body[b, VY], body[b, W] = (
                gathered[g + G_VBX], gathered[g + G_VBY], gathered[g + G_WB])


@inlined_early
def _warm_start_lanes(c, lanes, gathered, points):
    for j in range(LANES):
        o = lane_index(c, j)
        g = np.uint64(j)
        ma, ia, mb, ib = lanes[o + L_MA], lanes[o + L_IA], lanes[o + L_MB], lanes[o + L_IB]
        vax, vay, wa = gathered[g + G_VAX], gathered[g + G_VAY], gathered[g + G_WA]
        vbx, vby, wb = gathered[g + G_VBX], gathered[g + G_VBY], gathered[g + G_WB]
        nx, ny = lanes[o + L_NX], lanes[o + L_NY]
        for k in range(points):
            q = point_index(o, k)
            jn = lanes[q + P_NORMAL_IMPULSE]
            jt = lanes[q + P_TANGENT_IMPULSE]
            px = jn * nx + jt * ny
            py = jn * ny - jt * nx
            vax -= ma * px
            vay -= ma * py
            wa -= ia * (jn * lanes[q + P_RNA] + jt * lanes[q + P_RTA])
            vbx += mb * px
            vby += mb * py
            wb += ib * (jn * lanes[q + P_RNB] + jt * lanes[q + P_RTB])
        gathered[g + G_VAX], gathered[g + G_VAY], gathered[g + G_WA] = vax, vay, wa
        gathered[g + G_VBX], gathered[g + G_VBY], gathered[g + G_WB] = vbx, vby, wb


@inlined_early
def warm_start(batches, first, last, lanes, body):
    """Apply the accumulated impulses of chunks first .. last - 1 again at the start of a substep."""
    chunk_points = batches.chunk_points
    gathered = _gathered_area()
    for c in range(first, last):
        _gather(batches, c, body, lanes, gathered, False)
        if chunk_points[c] == 2:  # a compile-time point count: the lane loop has no inner loop left
            _warm_start_lanes(c, lanes, gathered, 2)
        else:
            _warm_start_lanes(c, lanes, gathered, 1)
        _scatter(batches, c, gathered, body)


@inlined_early
def group_body(order, k, direct):
    """Body k of a group of the schedule (`contact_batches`): order[k], or k itself when `direct` (one group
    holds every body, in id order). Read through the order, S6's 200 orbits took 24 % longer a tick, and
    with the choice made inside the loops 9 % (`substeps.substeps` makes it at compile time)."""
    if direct:
        return np.uint64(k)
    return np.uint64(order[k])


@inlined_early
def keep_free_velocities(body, order, first, last, direct):
    """Before the first warm start of a tick: each body's velocity is its free velocity, what it has
    without the contacts' accumulated impulses (the warm velocity columns hold it from here on)."""
    for k in range(first, last):
        i = group_body(order, k, direct)
        body[i, WARM_VX] = body[i, VX]
        body[i, WARM_VY] = body[i, VY]
        body[i, WARM_W] = body[i, W]


@inlined_early
def exchange_warm_velocities(body, order, first, last, direct):
    """Turn the warm velocity columns from the free velocity into the velocity the contacts' accumulated
    impulses give (velocity less free velocity), or back. The contact passes change a body's velocity and
    its accumulated impulses alike, so its free velocity holds through them; anything else that moves a
    body (gravity, joints) moves its free velocity, and runs while the columns hold the impulses'."""
    for k in range(first, last):
        i = group_body(order, k, direct)
        body[i, WARM_VX] = body[i, VX] - body[i, WARM_VX]
        body[i, WARM_VY] = body[i, VY] - body[i, WARM_VY]
        body[i, WARM_W] = body[i, W] - body[i, WARM_W]


@inlined_early
def warm_start_again(body, order, first, last, direct):
    """The warm start of a substep after the first: add to each body the velocity its contacts'
    accumulated impulses give (the columns hold it: `exchange_warm_velocities`), and keep the velocity
    before as the free velocity. The same as applying every contact's impulses again (`warm_start`), to
    rounding, in one pass over the bodies instead of the contacts: S2's substep 21.7 -> 18 us."""
    for k in range(first, last):
        i = group_body(order, k, direct)
        vx, vy, w = body[i, VX], body[i, VY], body[i, W]
        body[i, VX] = vx + body[i, WARM_VX]
        body[i, VY] = vy + body[i, WARM_VY]
        body[i, W] = w + body[i, WARM_W]
        body[i, WARM_VX], body[i, WARM_VY], body[i, WARM_W] = vx, vy, w


@inlined_early
def _point_separation(lanes, o, q, dn, ca, sa, cb, sb):
    """A point's separation now: the anchors turned by each body's rotation since the narrow phase,
    projected on the normal through their precomputed dot and cross products."""
    b_side = cb * lanes[q + P_RDB] + sb * lanes[q + P_RNB]
    a_side = ca * lanes[q + P_RDA] + sa * lanes[q + P_RNA]
    return dn + b_side - a_side + lanes[q + P_SEPARATION]


@inlined_early
def _point_bias(s, inv_h, use_bias, rate, mscale, iscale):
    """Bias speed, mass scale and impulse scale of a point at separation s: a gap may close within the
    substep, no more; an overlap is pushed apart softly in the biased pass."""
    if s > 0.0:
        return s * inv_h, 1.0, 0.0
    if use_bias:
        return max(rate * s, -MAX_PUSH_SPEED), mscale, iscale
    return 0.0, 1.0, 0.0


@inlined_early
def _point_masses(ma, ia, mb, ib, rna1, rnb1, rna2, rnb2):
    """The effective mass matrix of a manifold's two points along its normal: k11, k12, k22."""
    return (ma + mb + ia * rna1 * rna1 + ib * rnb1 * rnb1, ma + mb + ia * rna1 * rna2 + ib * rnb1 * rnb2,
            ma + mb + ia * rna2 * rna2 + ib * rnb2 * rnb2)


@inlined_early
def _two_points(k11, k12, k22, b1, b2, inv_det, normal_mass1, normal_mass2):
    """`two_point_lcp` without branches or divisions, so that the lane loop stays SIMD: the new normal
    impulses x >= 0 of both points with w = K x + b >= 0 and x . w = 0, from the inverse determinant
    (`prepare`; 0 when there is one point or two nearly the same) and each point's normal mass (1 / k, 0
    where no point is)."""
    x1 = -(k22 * b1 - k12 * b2) * inv_det
    x2 = -(k11 * b2 - k12 * b1) * inv_det
    both = inv_det > 0.0 and x1 >= 0.0 and x2 >= 0.0
    first = -b1 * normal_mass1
    first_alone = first >= 0.0 and (normal_mass2 == 0.0 or k12 * first + b2 >= 0.0)
    second = -b2 * normal_mass2
    second_alone = second >= 0.0 and k12 * second + b1 >= 0.0
    total1 = x1 if both else (first if first_alone else 0.0)
    total2 = x2 if both else (0.0 if first_alone else (second if second_alone else 0.0))
    return total1, total2


@inlined_early
def _solve_lanes(c, lanes, gathered, inv_h, use_bias, soft, stiff, points):
    for j in range(LANES):
        o = lane_index(c, j)
        g = np.uint64(j)
        ma, ia, mb, ib = lanes[o + L_MA], lanes[o + L_IA], lanes[o + L_MB], lanes[o + L_IB]
        vax, vay, wa = gathered[g + G_VAX], gathered[g + G_VAY], gathered[g + G_WA]
        vbx, vby, wb = gathered[g + G_VBX], gathered[g + G_VBY], gathered[g + G_WB]
        nx, ny = lanes[o + L_NX], lanes[o + L_NY]
        # against an immovable body the stiffer softness: only one side gives way
        rate, mscale, iscale = stiff if ma == 0.0 or mb == 0.0 else soft
        dn = lanes[o + L_DN]
        ca, sa, cb, sb = lanes[o + L_CA], lanes[o + L_SA], lanes[o + L_CB], lanes[o + L_SB]
        if points == 1:
            q = point_index(o, 0)
            rna, rnb = lanes[q + P_RNA], lanes[q + P_RNB]
            bias, m_scale, i_scale = _point_bias(_point_separation(lanes, o, q, dn, ca, sa, cb, sb), inv_h,
                                                 use_bias, rate, mscale, iscale)
            old = lanes[q + P_NORMAL_IMPULSE]
            vn = relative_speed(vax, vay, wa, vbx, vby, wb, nx, ny, rna, rnb)
            total = max(old - (lanes[q + P_NORMAL_MASS] * m_scale * (vn + bias) + i_scale * old), 0.0)
            impulse = total - old
            lanes[q + P_NORMAL_IMPULSE] = total
            if not use_bias:
                lanes[q + P_TICK_NORMAL_IMPULSE] += total
            vax -= ma * nx * impulse
            vay -= ma * ny * impulse
            wa -= ia * rna * impulse
            vbx += mb * nx * impulse
            vby += mb * ny * impulse
            wb += ib * rnb * impulse
        else:
            q1, q2 = point_index(o, 0), point_index(o, 1)
            rna1, rnb1 = lanes[q1 + P_RNA], lanes[q1 + P_RNB]
            rna2, rnb2 = lanes[q2 + P_RNA], lanes[q2 + P_RNB]
            s1 = _point_separation(lanes, o, q1, dn, ca, sa, cb, sb)
            s2 = _point_separation(lanes, o, q2, dn, ca, sa, cb, sb)
            bias1, m_scale1, i_scale1 = _point_bias(s1, inv_h, use_bias, rate, mscale, iscale)
            bias2, m_scale2, i_scale2 = _point_bias(s2, inv_h, use_bias, rate, mscale, iscale)
            old1, old2 = lanes[q1 + P_NORMAL_IMPULSE], lanes[q2 + P_NORMAL_IMPULSE]
            mass1, mass2 = lanes[q1 + P_NORMAL_MASS], lanes[q2 + P_NORMAL_MASS]
            k11, k12, k22 = _point_masses(ma, ia, mb, ib, rna1, rnb1, rna2, rnb2)
            vn1 = relative_speed(vax, vay, wa, vbx, vby, wb, nx, ny, rna1, rnb1)
            vn2 = relative_speed(vax, vay, wa, vbx, vby, wb, nx, ny, rna2, rnb2)
            # one point after the other: the second sees the first's impulse
            total1 = max(old1 - (mass1 * m_scale1 * (vn1 + bias1) + i_scale1 * old1), 0.0)
            vn2_after = vn2 + k12 * (total1 - old1)
            total2 = max(old2 - (mass2 * m_scale2 * (vn2_after + bias2) + i_scale2 * old2), 0.0)
            if not use_bias or (s1 > 0.0 and s2 > 0.0):  # both together (see `solve`)
                # the points' speeds with no normal impulse at all: w = K x + b for new impulses x
                b1 = vn1 + bias1 - (k11 * old1 + k12 * old2)
                b2 = vn2 + bias2 - (k12 * old1 + k22 * old2)
                total1, total2 = _two_points(k11, k12, k22, b1, b2, lanes[o + L_INV_DET], mass1, mass2)
            impulse1, impulse2 = total1 - old1, total2 - old2
            lanes[q1 + P_NORMAL_IMPULSE] = total1
            lanes[q2 + P_NORMAL_IMPULSE] = total2
            if not use_bias:
                lanes[q1 + P_TICK_NORMAL_IMPULSE] += total1
                lanes[q2 + P_TICK_NORMAL_IMPULSE] += total2
            impulse = impulse1 + impulse2
            vax -= ma * nx * impulse
            vay -= ma * ny * impulse
            wa -= ia * (rna1 * impulse1 + rna2 * impulse2)
            vbx += mb * nx * impulse
            vby += mb * ny * impulse
            wb += ib * (rnb1 * impulse1 + rnb2 * impulse2)
        # friction in the relax pass only (see `solve`); tested outside the loop, not as its length: an
        # empty loop left in the biased pass made LLVM solve lane 0 alone and the other 7 as a vector,
        # whose loads then waited on lane 0's stores
        if not use_bias:
            tx, ty = ny, -nx
            mu = lanes[o + L_MU]
            for k in range(points):
                q = point_index(o, k)
                rta, rtb = lanes[q + P_RTA], lanes[q + P_RTB]
                vt = relative_speed(vax, vay, wa, vbx, vby, wb, tx, ty, rta, rtb)
                limit = mu * lanes[q + P_NORMAL_IMPULSE]
                old = lanes[q + P_TANGENT_IMPULSE]
                total = min(max(old - lanes[q + P_TANGENT_MASS] * vt, -limit), limit)
                lanes[q + P_TANGENT_IMPULSE] = total
                impulse = total - old
                vax -= ma * tx * impulse
                vay -= ma * ty * impulse
                wa -= ia * rta * impulse
                vbx += mb * tx * impulse
                vby += mb * ty * impulse
                wb += ib * rtb * impulse
        gathered[g + G_VAX], gathered[g + G_VAY], gathered[g + G_WA] = vax, vay, wa
        gathered[g + G_VBX], gathered[g + G_VBY], gathered[g + G_WB] = vbx, vby, wb


@inlined_early
def solve(batches, first, last, lanes, body, inv_h, use_bias, soft, stiff):
    """One pass over the contacts of chunks first .. last - 1; with `use_bias` the soft position bias
    pushes overlap apart, with the contacts' softness (bias rate, mass and impulse scales, `softness`)
    for substeps of 1 / inv_h seconds, `stiff` against an immovable body.

    Friction is solved in the pass without bias only, after the positions moved, as Box2D v3 now does;
    that pass takes the two points of a manifold together (the 2 x 2 problem of their normal impulses,
    `_two_points`), and so does the biased pass where both points are still apart (a face arriving),
    else one point after the other. Measured at 4 substeps over 1,000 ticks: with friction in both
    passes the pyramid of 5,050 boxes sheared sideways (its top box 7.8 m, base 60's 0.54 m). Friction
    in the relax pass alone holds it, but then the order of a manifold's points is felt: the first point
    solved takes more of an impulse, so a crate hit flat by a kinematic box left it turning, faster than
    the pusher (1.567 m/s and 0.047 sideways instead of 1.5), and a box landing flat slid 0.036 m/s
    sideways. With the points together where the faces meet the crate leaves at exactly 1.5 m/s, the box
    lands straight (0.0005 m/s), the top of the 5,050-box pyramid moves 7 cm sideways and sinks 0.46 m
    (Box2D v3: 0.73), and the worst box of bases 20, 40, 60 moves 1.0, 3.6, 7.9 cm. Resting points taken
    together in the biased pass as well made the stacks softer (base 60: 15 cm)."""
    chunk_points = batches.chunk_points
    gathered = _gathered_area()
    for c in range(first, last):
        _gather(batches, c, body, lanes, gathered, not use_bias)
        if chunk_points[c] == 2:
            _solve_lanes(c, lanes, gathered, inv_h, use_bias, soft, stiff, 2)
        else:
            _solve_lanes(c, lanes, gathered, inv_h, use_bias, soft, stiff, 1)
        _scatter(batches, c, gathered, body)


@inlined_early
def two_point_lcp(k11, k12, k22, b1, b2):
    """Impulses x >= 0 of the two points of a manifold with w = K x + b >= 0 and x . w = 0 (K their
    symmetric 2 x 2 effective mass matrix, b their speeds less their targets): both pushing, one, or none
    (Box2D v2's block solver)."""
    det = k11 * k22 - k12 * k12
    if det > 1e-9 * k11 * k22:
        x1 = -(k22 * b1 - k12 * b2) / det
        x2 = -(k11 * b2 - k12 * b1) / det
        if x1 >= 0.0 and x2 >= 0.0:
            return x1, x2
    x1 = -b1 / k11 if k11 > 0.0 else 0.0
    if x1 >= 0.0 and k12 * x1 + b2 >= 0.0:
        return x1, 0.0
    x2 = -b2 / k22 if k22 > 0.0 else 0.0
    if x2 >= 0.0 and k12 * x2 + b1 >= 0.0:
        return 0.0, x2
    return 0.0, 0.0
