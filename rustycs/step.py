"""The tick: broad phase, narrow phase, soft contact solver with substeps, integration.

One compiled function runs a block of ticks so that Python costs once per block. The previous tick's
contact points (sorted by key: body a, body b, feature id) are both the warm-start cache and what
`World.contacts()` reports.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rustycs.broad_phase import find_pairs
from rustycs.contact_solver import CONTACT_HERTZ, prepare, restitute, solve, warm_start
from rustycs.hitbox import update_geometry
from rustycs.manifold import LINEAR_SLOP, collide
from rustycs.motion import apply_bounds, first_non_finite, integrate_positions, integrate_velocities

SPECULATIVE_DISTANCE = 4.0 * LINEAR_SLOP
FEATURE_BITS = 8

# layout of the `settings` array
DT, SUBSTEPS, RESTITUTION_THRESHOLD, HAS_BOUNDS, BOUNDS = 0, 1, 2, 3, 4
SETTINGS_SIZE = 8


@njit(cache=True)
def _speed(v, i):
    return math.sqrt(v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1])


@njit(cache=True)
def step_world(n_ticks, x, angle, v, w, inv_mass, inv_inertia, body_type, kind, radius, nverts,
               local_verts, local_normals, restitution, friction, active, group,
               gravity, att_pos, att_gm, att_range, att_min_distance, settings,
               c_key, c_a, c_b, c_point, c_normal, c_sep, c_jn, c_jt):
    """Advance `n_ticks` ticks in place.

    Returns (bad_body, ticks_done, escaped, contact cache arrays...): bad_body is -1, or the first
    body whose state became non-finite in tick `ticks_done` (then the block stops there).
    """
    n = x.shape[0]
    dt = settings[DT]
    substeps = int(settings[SUBSTEPS])
    h = dt / substeps
    threshold = settings[RESTITUTION_THRESHOLD]
    bounds = settings[BOUNDS:BOUNDS + 4]
    contact_hertz = min(CONTACT_HERTZ, 0.25 / h)
    world_verts = np.zeros((n, local_verts.shape[1], 2))
    world_normals = np.zeros((n, local_verts.shape[1], 2))
    hitbox = np.zeros((n, 4))
    delta_x = np.zeros((n, 2))
    delta_angle = np.zeros(n)
    rot = np.zeros((n, 2))
    normal = np.zeros(2)
    points = np.zeros((2, 2))
    separations = np.zeros(2)
    ids = np.zeros(2, dtype=np.int64)
    escaped = 0
    for tick in range(n_ticks):
        update_geometry(x, angle, v, kind, radius, nverts, local_verts, local_normals, active,
                        SPECULATIVE_DISTANCE, dt, world_verts, world_normals, hitbox)
        pairs = find_pairs(hitbox, inv_mass, active, group)
        n_pairs = pairs.shape[0]

        # narrow phase: manifolds in pair order, points in feature order
        m_a = np.empty(n_pairs, dtype=np.int64)
        m_b = np.empty(n_pairs, dtype=np.int64)
        m_normal = np.empty((n_pairs, 2))
        m_friction = np.empty(n_pairs)
        m_restitution = np.empty(n_pairs)
        m_first = np.empty(n_pairs, dtype=np.int64)
        m_count = np.empty(n_pairs, dtype=np.int64)
        cap = 2 * n_pairs
        p_key = np.empty(cap, dtype=np.int64)
        p_point = np.empty((cap, 2))
        p_ra = np.empty((cap, 2))
        p_rb = np.empty((cap, 2))
        p_sep = np.empty(cap)
        p_jn = np.zeros(cap)
        p_jt = np.zeros(cap)
        n_man = 0
        n_pts = 0
        for k in range(n_pairs):
            a = pairs[k, 0]
            b = pairs[k, 1]
            margin = SPECULATIVE_DISTANCE + dt * (_speed(v, a) + _speed(v, b))
            count = collide(a, b, x, kind, radius, nverts, world_verts, world_normals, margin,
                            normal, points, separations, ids)
            if count == 0:
                continue
            if count == 2 and ids[0] > ids[1]:
                order0, order1 = 1, 0
            else:
                order0, order1 = 0, 1
            m_a[n_man] = a
            m_b[n_man] = b
            m_normal[n_man, 0] = normal[0]
            m_normal[n_man, 1] = normal[1]
            m_friction[n_man] = 0.5 * (friction[a] + friction[b])
            m_restitution[n_man] = 0.5 * (restitution[a] + restitution[b])
            m_first[n_man] = n_pts
            m_count[n_man] = count
            n_man += 1
            for j in range(count):
                src = order0 if j == 0 else order1
                p_key[n_pts] = ((a * n + b) << FEATURE_BITS) | ids[src]
                p_point[n_pts, 0] = points[src, 0]
                p_point[n_pts, 1] = points[src, 1]
                p_ra[n_pts, 0] = points[src, 0] - x[a, 0]
                p_ra[n_pts, 1] = points[src, 1] - x[a, 1]
                p_rb[n_pts, 0] = points[src, 0] - x[b, 0]
                p_rb[n_pts, 1] = points[src, 1] - x[b, 1]
                p_sep[n_pts] = separations[src]
                n_pts += 1
        m_a = m_a[:n_man]
        m_b = m_b[:n_man]
        m_normal = m_normal[:n_man]
        p_key = p_key[:n_pts]

        # warm start from last tick's impulses of the same (a, b, feature)
        if c_key.shape[0] > 0:
            found = np.searchsorted(c_key, p_key)
            for p in range(n_pts):
                f = found[p]
                if f < c_key.shape[0] and c_key[f] == p_key[p]:
                    p_jn[p] = c_jn[f]
                    p_jt[p] = c_jt[f]

        p_normal_mass = np.empty(n_pts)
        p_tangent_mass = np.empty(n_pts)
        p_adjusted_sep = np.empty(n_pts)
        p_relative_velocity = np.empty(n_pts)
        p_max_normal = np.empty(n_pts)
        prepare(m_a, m_b, m_normal, m_first, m_count, p_ra, p_rb, p_sep, v, w, inv_mass, inv_inertia,
                p_normal_mass, p_tangent_mass, p_adjusted_sep, p_relative_velocity, p_max_normal)
        delta_x[:] = 0.0
        delta_angle[:] = 0.0
        rot[:, 0] = 1.0
        rot[:, 1] = 0.0
        for _ in range(substeps):
            integrate_velocities(v, x, body_type, active, gravity, att_pos, att_gm, att_range,
                                 att_min_distance, h)
            warm_start(m_a, m_b, m_normal, m_first, m_count, p_ra, p_rb, p_jn, p_jt,
                       v, w, inv_mass, inv_inertia)
            solve(m_a, m_b, m_normal, m_friction, m_first, m_count, p_ra, p_rb, p_adjusted_sep,
                  p_normal_mass, p_tangent_mass, p_jn, p_jt, p_max_normal, v, w, inv_mass, inv_inertia,
                  delta_x, rot, h, contact_hertz, True)
            integrate_positions(x, angle, v, w, body_type, active, delta_x, delta_angle, rot, h)
            solve(m_a, m_b, m_normal, m_friction, m_first, m_count, p_ra, p_rb, p_adjusted_sep,
                  p_normal_mass, p_tangent_mass, p_jn, p_jt, p_max_normal, v, w, inv_mass, inv_inertia,
                  delta_x, rot, h, contact_hertz, False)
        restitute(m_a, m_b, m_normal, m_restitution, m_first, m_count, p_ra, p_rb, p_normal_mass,
                  p_relative_velocity, p_jn, p_max_normal, v, w, inv_mass, inv_inertia, threshold)

        # this tick's contacts become the cache
        c_key = p_key
        c_a = np.empty(n_pts, dtype=np.int64)
        c_b = np.empty(n_pts, dtype=np.int64)
        c_normal = np.empty((n_pts, 2))
        for m in range(n_man):
            for p in range(m_first[m], m_first[m] + m_count[m]):
                c_a[p] = m_a[m]
                c_b[p] = m_b[m]
                c_normal[p, 0] = m_normal[m, 0]
                c_normal[p, 1] = m_normal[m, 1]
        c_point = p_point[:n_pts]
        c_sep = p_sep[:n_pts]
        c_jn = p_jn[:n_pts]
        c_jt = p_jt[:n_pts]

        bad = first_non_finite(x, angle, v, w, body_type, active)
        if bad >= 0:
            return bad, tick, escaped, c_key, c_a, c_b, c_point, c_normal, c_sep, c_jn, c_jt
        if settings[HAS_BOUNDS] != 0.0:
            escaped += apply_bounds(x, v, w, body_type, active, bounds)
    return -1, n_ticks, escaped, c_key, c_a, c_b, c_point, c_normal, c_sep, c_jn, c_jt
