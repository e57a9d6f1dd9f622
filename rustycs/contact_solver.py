"""Contact solver: soft sequential impulses with substeps and relaxation (Box2D v3's "soft step").

Every tick: prepare the contact points (effective masses, the approach speed for restitution),
then for each substep integrate velocities, warm start, solve with a soft position bias, integrate
positions and relax without bias (so the bias that removed overlap adds no energy), then apply
restitution once and keep the accumulated impulses for the next tick's warm start.

Impulses accumulate per point: the normal impulse is clamped at >= 0 and the friction impulse to
|f| <= mu * normal impulse. The separation of each point is updated inside the step from the bodies'
motion since the narrow phase, so substeps see the overlap shrink.
"""

from __future__ import annotations

import math

from numba import njit

CONTACT_HERTZ = 60.0
DAMPING_RATIO = 10.0
MAX_PUSH_SPEED = 3.0  # m/s: the fastest speed at which overlap is pushed apart


@njit(cache=True)
def softness(hertz, zeta, h):
    """Bias rate, mass scale and impulse scale of a soft constraint (a damped spring)."""
    omega = 2.0 * math.pi * hertz
    a1 = 2.0 * zeta + h * omega
    a2 = h * omega * a1
    a3 = 1.0 / (1.0 + a2)
    return omega / a1, a2 * a3, a3


@njit(cache=True)
def prepare(m_a, m_b, m_normal, m_first, m_count, p_ra, p_rb, p_sep, v, w, inv_mass, inv_inertia,
            p_normal_mass, p_tangent_mass, p_adjusted_sep, p_relative_velocity, p_max_normal):
    for m in range(m_a.shape[0]):
        a = m_a[m]
        b = m_b[m]
        ma, mb = inv_mass[a], inv_mass[b]
        ia, ib = inv_inertia[a], inv_inertia[b]
        nx, ny = m_normal[m, 0], m_normal[m, 1]
        tx, ty = ny, -nx
        for p in range(m_first[m], m_first[m] + m_count[m]):
            rax, ray = p_ra[p, 0], p_ra[p, 1]
            rbx, rby = p_rb[p, 0], p_rb[p, 1]
            rna = rax * ny - ray * nx
            rnb = rbx * ny - rby * nx
            k = ma + mb + ia * rna * rna + ib * rnb * rnb
            p_normal_mass[p] = 1.0 / k if k > 0.0 else 0.0
            rta = rax * ty - ray * tx
            rtb = rbx * ty - rby * tx
            k = ma + mb + ia * rta * rta + ib * rtb * rtb
            p_tangent_mass[p] = 1.0 / k if k > 0.0 else 0.0
            p_adjusted_sep[p] = p_sep[p] - ((rbx - rax) * nx + (rby - ray) * ny)
            dvx = (v[b, 0] - w[b] * rby) - (v[a, 0] - w[a] * ray)
            dvy = (v[b, 1] + w[b] * rbx) - (v[a, 1] + w[a] * rax)
            p_relative_velocity[p] = dvx * nx + dvy * ny
            p_max_normal[p] = 0.0


@njit(cache=True)
def _apply(a, b, px, py, rax, ray, rbx, rby, v, w, inv_mass, inv_inertia):
    v[a, 0] -= inv_mass[a] * px
    v[a, 1] -= inv_mass[a] * py
    w[a] -= inv_inertia[a] * (rax * py - ray * px)
    v[b, 0] += inv_mass[b] * px
    v[b, 1] += inv_mass[b] * py
    w[b] += inv_inertia[b] * (rbx * py - rby * px)


@njit(cache=True)
def warm_start(m_a, m_b, m_normal, m_first, m_count, p_ra, p_rb, p_jn, p_jt, v, w, inv_mass, inv_inertia):
    for m in range(m_a.shape[0]):
        a = m_a[m]
        b = m_b[m]
        nx, ny = m_normal[m, 0], m_normal[m, 1]
        for p in range(m_first[m], m_first[m] + m_count[m]):
            px = p_jn[p] * nx + p_jt[p] * ny
            py = p_jn[p] * ny - p_jt[p] * nx
            _apply(a, b, px, py, p_ra[p, 0], p_ra[p, 1], p_rb[p, 0], p_rb[p, 1], v, w, inv_mass, inv_inertia)


@njit(cache=True)
def solve(m_a, m_b, m_normal, m_friction, m_first, m_count, p_ra, p_rb, p_adjusted_sep,
          p_normal_mass, p_tangent_mass, p_jn, p_jt, p_max_normal, v, w, inv_mass, inv_inertia,
          delta_x, rot, h, contact_hertz, use_bias):
    """One pass over all contacts; with `use_bias` the soft position bias pushes overlap apart."""
    inv_h = 1.0 / h
    bias_rate, mass_scale_soft, impulse_scale_soft = softness(contact_hertz, DAMPING_RATIO, h)
    bias_rate_hard, mass_scale_hard, impulse_scale_hard = softness(2.0 * contact_hertz, DAMPING_RATIO, h)
    for m in range(m_a.shape[0]):
        a = m_a[m]
        b = m_b[m]
        nx, ny = m_normal[m, 0], m_normal[m, 1]
        # contacts against an immovable body are stiffer: only one side gives way
        if inv_mass[a] == 0.0 or inv_mass[b] == 0.0:
            rate, mscale, iscale = bias_rate_hard, mass_scale_hard, impulse_scale_hard
        else:
            rate, mscale, iscale = bias_rate, mass_scale_soft, impulse_scale_soft
        ca, sa = rot[a, 0], rot[a, 1]
        cb, sb = rot[b, 0], rot[b, 1]
        first = m_first[m]
        last = first + m_count[m]
        for p in range(first, last):
            rax, ray = p_ra[p, 0], p_ra[p, 1]
            rbx, rby = p_rb[p, 0], p_rb[p, 1]
            # current separation from the bodies' motion since the narrow phase
            dx = (delta_x[b, 0] + cb * rbx - sb * rby) - (delta_x[a, 0] + ca * rax - sa * ray)
            dy = (delta_x[b, 1] + sb * rbx + cb * rby) - (delta_x[a, 1] + sa * rax + ca * ray)
            s = dx * nx + dy * ny + p_adjusted_sep[p]
            bias = 0.0
            mass_scale = 1.0
            impulse_scale = 0.0
            if s > 0.0:
                bias = s * inv_h  # speculative: allow closing the gap, no more
            elif use_bias:
                bias = max(rate * s, -MAX_PUSH_SPEED)
                mass_scale = mscale
                impulse_scale = iscale
            dvx = (v[b, 0] - w[b] * rby) - (v[a, 0] - w[a] * ray)
            dvy = (v[b, 1] + w[b] * rbx) - (v[a, 1] + w[a] * rax)
            vn = dvx * nx + dvy * ny
            impulse = -p_normal_mass[p] * mass_scale * (vn + bias) - impulse_scale * p_jn[p]
            total = max(p_jn[p] + impulse, 0.0)
            impulse = total - p_jn[p]
            p_jn[p] = total
            p_max_normal[p] = max(p_max_normal[p], impulse)
            _apply(a, b, impulse * nx, impulse * ny, rax, ray, rbx, rby, v, w, inv_mass, inv_inertia)
        tx, ty = ny, -nx
        mu = m_friction[m]
        for p in range(first, last):
            rax, ray = p_ra[p, 0], p_ra[p, 1]
            rbx, rby = p_rb[p, 0], p_rb[p, 1]
            dvx = (v[b, 0] - w[b] * rby) - (v[a, 0] - w[a] * ray)
            dvy = (v[b, 1] + w[b] * rbx) - (v[a, 1] + w[a] * rax)
            vt = dvx * tx + dvy * ty
            limit = mu * p_jn[p]
            total = min(max(p_jt[p] - p_tangent_mass[p] * vt, -limit), limit)
            impulse = total - p_jt[p]
            p_jt[p] = total
            _apply(a, b, impulse * tx, impulse * ty, rax, ray, rbx, rby, v, w, inv_mass, inv_inertia)


@njit(cache=True)
def restitute(m_a, m_b, m_normal, m_restitution, m_first, m_count, p_ra, p_rb, p_normal_mass,
              p_relative_velocity, p_jn, p_max_normal, v, w, inv_mass, inv_inertia, threshold):
    """Bounce: set the normal speed to -e times the approach speed measured before solving."""
    for m in range(m_a.shape[0]):
        e = m_restitution[m]
        if e == 0.0:
            continue
        a = m_a[m]
        b = m_b[m]
        nx, ny = m_normal[m, 0], m_normal[m, 1]
        for p in range(m_first[m], m_first[m] + m_count[m]):
            if p_relative_velocity[p] > -threshold or p_max_normal[p] == 0.0:
                continue
            rax, ray = p_ra[p, 0], p_ra[p, 1]
            rbx, rby = p_rb[p, 0], p_rb[p, 1]
            dvx = (v[b, 0] - w[b] * rby) - (v[a, 0] - w[a] * ray)
            dvy = (v[b, 1] + w[b] * rbx) - (v[a, 1] + w[a] * rax)
            vn = dvx * nx + dvy * ny
            impulse = -p_normal_mass[p] * (vn + e * p_relative_velocity[p])
            total = max(p_jn[p] + impulse, 0.0)
            impulse = total - p_jn[p]
            p_jn[p] = total
            p_max_normal[p] = max(p_max_normal[p], impulse)
            _apply(a, b, impulse * nx, impulse * ny, rax, ray, rbx, rby, v, w, inv_mass, inv_inertia)
