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
from rustycs.contact_solver import (
    CONTACT_HERTZ,
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
    load_bodies,
    prepare,
    restitute,
    solve,
    store_bodies,
    warm_start,
)
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


@njit(cache=True, nogil=True)
def step_world(n_ticks, x, angle, v, w, inv_mass, inv_inertia, body_type, kind, radius, nverts,
               local_verts, local_normals, restitution, friction, active, group,
               gravity, att_pos, att_gm, att_range, att_min_distance, settings,
               c_key, c_a, c_b, c_point, c_normal, c_sep, c_jn, c_jt):
    """Advance `n_ticks` ticks in place. Releases the GIL, so independent worlds step in parallel
    threads.

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
    normal = np.zeros(2)
    points = np.zeros((2, 2))
    separations = np.zeros(2)
    ids = np.zeros(2, dtype=np.int64)
    escaped = 0
    for tick in range(n_ticks):
        bad = first_non_finite(x, angle, v, w, body_type, active)
        if bad >= 0:  # set from outside between blocks: report it before it spreads
            return bad, tick, escaped, c_key, c_a, c_b, c_point, c_normal, c_sep, c_jn, c_jt
        update_geometry(x, angle, v, kind, radius, nverts, local_verts, local_normals, active,
                        SPECULATIVE_DISTANCE, dt, world_verts, world_normals, hitbox)
        pairs = find_pairs(hitbox, inv_mass, active, group)
        n_pairs = pairs.shape[0]

        # narrow phase: manifolds in pair order, points in feature order
        m_a = np.empty(n_pairs, dtype=np.int64)
        m_b = np.empty(n_pairs, dtype=np.int64)
        m_first = np.empty(n_pairs, dtype=np.int64)
        m_count = np.empty(n_pairs, dtype=np.int64)
        manifold = np.empty((n_pairs, MANIFOLD_COLUMNS))
        cap = 2 * n_pairs
        p_key = np.empty(cap, dtype=np.int64)
        p_point = np.empty((cap, 2))
        point = np.zeros((cap, POINT_COLUMNS))
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
                p_key[n_pts] = ((a * n + b) << FEATURE_BITS) | ids[src]
                p_point[n_pts, 0] = points[src, 0]
                p_point[n_pts, 1] = points[src, 1]
                point[n_pts, RAX] = points[src, 0] - x[a, 0]
                point[n_pts, RAY] = points[src, 1] - x[a, 1]
                point[n_pts, RBX] = points[src, 0] - x[b, 0]
                point[n_pts, RBY] = points[src, 1] - x[b, 1]
                point[n_pts, SEPARATION] = separations[src]
                n_pts += 1
        m_a = m_a[:n_man]
        m_b = m_b[:n_man]
        p_key = p_key[:n_pts]

        # warm start from last tick's impulses of the same (a, b, feature)
        if c_key.shape[0] > 0:
            found = np.searchsorted(c_key, p_key)
            for p in range(n_pts):
                f = found[p]
                if f < c_key.shape[0] and c_key[f] == p_key[p]:
                    point[p, NORMAL_IMPULSE] = c_jn[f]
                    point[p, TANGENT_IMPULSE] = c_jt[f]

        body = load_bodies(v, w, inv_mass, inv_inertia)
        prepare(m_a, m_b, manifold, m_first, m_count, point, body)
        for _ in range(substeps):
            integrate_velocities(body, x, body_type, active, gravity, att_pos, att_gm, att_range,
                                 att_min_distance, h)
            warm_start(m_a, m_b, manifold, m_first, m_count, point, body)
            solve(m_a, m_b, manifold, m_first, m_count, point, body, h, contact_hertz, True)
            integrate_positions(x, angle, body, body_type, active, h)
            solve(m_a, m_b, manifold, m_first, m_count, point, body, h, contact_hertz, False)
        # a single pass would favour the first point of a two-point manifold (a flat box would
        # bounce unevenly and spin); repeated passes converge to -e times the approach speed at both
        for _ in range(substeps):
            restitute(m_a, m_b, manifold, m_first, m_count, point, body, threshold)
        store_bodies(body, v, w, body_type)

        # this tick's contacts become the cache
        c_key = p_key
        c_a = np.empty(n_pts, dtype=np.int64)
        c_b = np.empty(n_pts, dtype=np.int64)
        c_normal = np.empty((n_pts, 2))
        for m in range(n_man):
            for p in range(m_first[m], m_first[m] + m_count[m]):
                c_a[p] = m_a[m]
                c_b[p] = m_b[m]
                c_normal[p, 0] = manifold[m, NX]
                c_normal[p, 1] = manifold[m, NY]
        c_point = p_point[:n_pts]
        c_sep = point[:n_pts, SEPARATION].copy()
        c_jn = point[:n_pts, NORMAL_IMPULSE].copy()
        c_jt = point[:n_pts, TANGENT_IMPULSE].copy()

        bad = first_non_finite(x, angle, v, w, body_type, active)
        if bad >= 0:
            return bad, tick, escaped, c_key, c_a, c_b, c_point, c_normal, c_sep, c_jn, c_jt
        if settings[HAS_BOUNDS] != 0.0:
            escaped += apply_bounds(x, v, w, body_type, active, bounds)
    return -1, n_ticks, escaped, c_key, c_a, c_b, c_point, c_normal, c_sep, c_jn, c_jt
