"""Contact solver: soft sequential impulses with substeps and relaxation (Box2D v3's "soft step").

Every tick: prepare the contact points (effective masses, the approach speed for restitution),
then for each substep integrate velocities, warm start, solve with a soft position bias, integrate
positions and relax without bias (so the bias that removed overlap adds no energy), then apply
restitution once and keep the accumulated impulses for the next tick's warm start.

Impulses accumulate per point: the normal impulse is clamped at >= 0 and the friction impulse to
|f| <= mu * normal impulse. The separation of each point is updated inside the step from the bodies'
motion since the narrow phase, so substeps see the overlap shrink.

The solver works on packed rows, one per body and one per contact point, so that a contact touches
three cache lines rather than a dozen arrays.
"""

from __future__ import annotations

import math

from numba import njit

from rustycs.body_types import DYNAMIC
from rustycs.tick_kernel import tick_kernel

CONTACT_HERTZ = 60.0
DAMPING_RATIO = 10.0
MAX_PUSH_SPEED = 3.0  # m/s: the fastest speed at which overlap is pushed apart

# columns of a solver body row: velocities, inverse masses, displacement and rotation (cos, sin) since the
# narrow phase
VX, VY, W, INV_MASS, INV_INERTIA, DX, DY, COS, SIN = 0, 1, 2, 3, 4, 5, 6, 7, 8
BODY_COLUMNS = 9
# columns of a contact point row
RAX, RAY, RBX, RBY, SEPARATION, ADJUSTED_SEPARATION, NORMAL_MASS, TANGENT_MASS = 0, 1, 2, 3, 4, 5, 6, 7
NORMAL_IMPULSE, TANGENT_IMPULSE, MAX_NORMAL_IMPULSE, RELATIVE_VELOCITY = 8, 9, 10, 11
RNA, RNB, RTA, RTB = 12, 13, 14, 15  # anchors crossed with the normal and the tangent
RDA, RDB = 16, 17  # anchors dotted with the normal
POINT_COLUMNS = 18
# columns of a manifold row
NX, NY, FRICTION, RESTITUTION = 0, 1, 2, 3
MANIFOLD_COLUMNS = 4


@njit(cache=True)
def softness(hertz, zeta, h):
    """Bias rate, mass scale and impulse scale of a soft constraint (a damped spring)."""
    omega = 2.0 * math.pi * hertz
    a1 = 2.0 * zeta + h * omega
    a2 = h * omega * a1
    a3 = 1.0 / (1.0 + a2)
    return omega / a1, a2 * a3, a3


@tick_kernel
def load_bodies(v, w, inv_mass, inv_inertia, body):
    """Fill the solver rows of the bodies: velocities, inverse masses, no displacement yet since the
    narrow phase."""
    for i in range(v.shape[0]):
        body[i, VX] = v[i, 0]
        body[i, VY] = v[i, 1]
        body[i, W] = w[i]
        body[i, INV_MASS] = inv_mass[i]
        body[i, INV_INERTIA] = inv_inertia[i]
        body[i, DX] = 0.0
        body[i, DY] = 0.0
        body[i, COS] = 1.0
        body[i, SIN] = 0.0


@tick_kernel
def store_bodies(body, v, w, body_type):
    """Copy velocities back to the dynamic bodies (the others' velocities are theirs to keep)."""
    for i in range(v.shape[0]):
        if body_type[i] != DYNAMIC:
            continue
        v[i, 0] = body[i, VX]
        v[i, 1] = body[i, VY]
        w[i] = body[i, W]


@njit(cache=True, inline="always")
def _relative_velocity(body, a, b, pt):
    """Velocity of b's contact point relative to a's (anchors fixed at the narrow phase)."""
    dvx = (body[b, VX] - body[b, W] * pt[RBY]) - (body[a, VX] - body[a, W] * pt[RAY])
    dvy = (body[b, VY] + body[b, W] * pt[RBX]) - (body[a, VY] + body[a, W] * pt[RAX])
    return dvx, dvy


@tick_kernel
def prepare(m_a, m_b, manifold, m_first, m_count, point, body):
    for m in range(m_a.shape[0]):
        a = m_a[m]
        b = m_b[m]
        ma, mb = body[a, INV_MASS], body[b, INV_MASS]
        ia, ib = body[a, INV_INERTIA], body[b, INV_INERTIA]
        nx, ny = manifold[m, NX], manifold[m, NY]
        tx, ty = ny, -nx
        for p in range(m_first[m], m_first[m] + m_count[m]):
            pt = point[p]
            rna = pt[RNA] = pt[RAX] * ny - pt[RAY] * nx
            rnb = pt[RNB] = pt[RBX] * ny - pt[RBY] * nx
            k = ma + mb + ia * rna * rna + ib * rnb * rnb
            pt[NORMAL_MASS] = 1.0 / k if k > 0.0 else 0.0
            rta = pt[RTA] = pt[RAX] * ty - pt[RAY] * tx
            rtb = pt[RTB] = pt[RBX] * ty - pt[RBY] * tx
            k = ma + mb + ia * rta * rta + ib * rtb * rtb
            pt[TANGENT_MASS] = 1.0 / k if k > 0.0 else 0.0
            rda = pt[RDA] = pt[RAX] * nx + pt[RAY] * ny
            rdb = pt[RDB] = pt[RBX] * nx + pt[RBY] * ny
            pt[ADJUSTED_SEPARATION] = pt[SEPARATION] - (rdb - rda)
            dvx, dvy = _relative_velocity(body, a, b, pt)
            pt[RELATIVE_VELOCITY] = dvx * nx + dvy * ny
            pt[MAX_NORMAL_IMPULSE] = 0.0


@njit(cache=True, inline="always")
def _store_velocity(body, i, inv_mass, inv_inertia, vx, vy, w):
    """Write body i's velocity back, unless it is immovable: then it is left unwritten, so that the next
    contact with it (the ground under a row of boxes) does not wait for this one."""
    if inv_mass != 0.0 or inv_inertia != 0.0:
        body[i, VX], body[i, VY], body[i, W] = vx, vy, w


@tick_kernel
def warm_start(m_a, m_b, manifold, m_first, m_count, point, body):
    for m in range(m_a.shape[0]):
        a = m_a[m]
        b = m_b[m]
        ma, ia, mb, ib = body[a, INV_MASS], body[a, INV_INERTIA], body[b, INV_MASS], body[b, INV_INERTIA]
        vax, vay, wa = body[a, VX], body[a, VY], body[a, W]
        vbx, vby, wb = body[b, VX], body[b, VY], body[b, W]
        nx, ny = manifold[m, NX], manifold[m, NY]
        for p in range(m_first[m], m_first[m] + m_count[m]):
            jn = point[p, NORMAL_IMPULSE]
            jt = point[p, TANGENT_IMPULSE]
            px = jn * nx + jt * ny
            py = jn * ny - jt * nx
            vax -= ma * px
            vay -= ma * py
            wa -= ia * (point[p, RAX] * py - point[p, RAY] * px)
            vbx += mb * px
            vby += mb * py
            wb += ib * (point[p, RBX] * py - point[p, RBY] * px)
        _store_velocity(body, a, ma, ia, vax, vay, wa)
        _store_velocity(body, b, mb, ib, vbx, vby, wb)


@tick_kernel
def solve(m_a, m_b, manifold, m_first, m_count, point, body, inv_h, soft, stiff, use_bias):
    """One pass over all contacts; with `use_bias` the soft position bias pushes overlap apart.

    `soft` and `stiff` are the softness (bias rate, mass scale, impulse scale) of contacts between
    two movable bodies and against an immovable one, for substeps of 1 / inv_h seconds. Both bodies'
    velocities stay in locals while their manifold is solved (fewer loads and stores).
    """
    for m in range(m_a.shape[0]):
        a = m_a[m]
        b = m_b[m]
        ma, ia, mb, ib = body[a, INV_MASS], body[a, INV_INERTIA], body[b, INV_MASS], body[b, INV_INERTIA]
        vax, vay, wa = body[a, VX], body[a, VY], body[a, W]
        vbx, vby, wb = body[b, VX], body[b, VY], body[b, W]
        nx, ny = manifold[m, NX], manifold[m, NY]
        rate, mscale, iscale = stiff if ma == 0.0 or mb == 0.0 else soft
        ca, sa, cb, sb = body[a, COS], body[a, SIN], body[b, COS], body[b, SIN]
        # the centres' approach along the normal since the narrow phase
        dn = (body[b, DX] - body[a, DX]) * nx + (body[b, DY] - body[a, DY]) * ny
        first = m_first[m]
        last = first + m_count[m]
        for p in range(first, last):
            rna, rnb = point[p, RNA], point[p, RNB]
            # current separation: the anchors turned by each body's rotation since the narrow phase,
            # projected on the normal through their precomputed dot and cross products
            s = (dn + (cb * point[p, RDB] + sb * rnb) - (ca * point[p, RDA] + sa * rna)
                 + point[p, ADJUSTED_SEPARATION])
            bias = 0.0
            mass_scale = 1.0
            impulse_scale = 0.0
            if s > 0.0:
                bias = s * inv_h  # speculative: allow closing the gap, no more
            elif use_bias:
                bias = max(rate * s, -MAX_PUSH_SPEED)
                mass_scale = mscale
                impulse_scale = iscale
            # the velocity chain from one point to the next is kept short: cross products precomputed
            vn = (vbx - vax) * nx + (vby - vay) * ny + (wb * rnb - wa * rna)
            old = point[p, NORMAL_IMPULSE]
            total = max(old - point[p, NORMAL_MASS] * mass_scale * (vn + bias) - impulse_scale * old, 0.0)
            impulse = total - old
            point[p, NORMAL_IMPULSE] = total
            point[p, MAX_NORMAL_IMPULSE] = max(point[p, MAX_NORMAL_IMPULSE], impulse)
            vax -= ma * nx * impulse
            vay -= ma * ny * impulse
            wa -= ia * rna * impulse
            vbx += mb * nx * impulse
            vby += mb * ny * impulse
            wb += ib * rnb * impulse
        tx, ty = ny, -nx
        mu = manifold[m, FRICTION]
        for p in range(first, last):
            rta, rtb = point[p, RTA], point[p, RTB]
            vt = (vbx - vax) * tx + (vby - vay) * ty + (wb * rtb - wa * rta)
            limit = mu * point[p, NORMAL_IMPULSE]
            old = point[p, TANGENT_IMPULSE]
            total = min(max(old - point[p, TANGENT_MASS] * vt, -limit), limit)
            point[p, TANGENT_IMPULSE] = total
            impulse = total - old
            vax -= ma * tx * impulse
            vay -= ma * ty * impulse
            wa -= ia * rta * impulse
            vbx += mb * tx * impulse
            vby += mb * ty * impulse
            wb += ib * rtb * impulse
        _store_velocity(body, a, ma, ia, vax, vay, wa)
        _store_velocity(body, b, mb, ib, vbx, vby, wb)


@tick_kernel
def restitute(m_a, m_b, manifold, m_first, m_count, point, body, threshold):
    """Bounce: set the normal speed to -e times the approach speed measured before solving."""
    for m in range(m_a.shape[0]):
        e = manifold[m, RESTITUTION]
        if e == 0.0:
            continue
        a = m_a[m]
        b = m_b[m]
        ma, ia, mb, ib = body[a, INV_MASS], body[a, INV_INERTIA], body[b, INV_MASS], body[b, INV_INERTIA]
        nx, ny = manifold[m, NX], manifold[m, NY]
        for p in range(m_first[m], m_first[m] + m_count[m]):
            pt = point[p]
            if pt[RELATIVE_VELOCITY] > -threshold or pt[MAX_NORMAL_IMPULSE] == 0.0:
                continue
            dvx, dvy = _relative_velocity(body, a, b, pt)
            vn = dvx * nx + dvy * ny
            old = pt[NORMAL_IMPULSE]
            total = max(old - pt[NORMAL_MASS] * (vn + e * pt[RELATIVE_VELOCITY]), 0.0)
            impulse = total - old
            pt[NORMAL_IMPULSE] = total
            pt[MAX_NORMAL_IMPULSE] = max(pt[MAX_NORMAL_IMPULSE], impulse)
            px = impulse * nx
            py = impulse * ny
            body[a, VX] -= ma * px
            body[a, VY] -= ma * py
            body[a, W] -= ia * (pt[RAX] * py - pt[RAY] * px)
            body[b, VX] += mb * px
            body[b, VY] += mb * py
            body[b, W] += ib * (pt[RBX] * py - pt[RBY] * px)
