"""The tick: broad phase, narrow phase, soft contact solver with substeps, integration.

One compiled function runs a block of ticks so that Python costs once per block. The previous tick's
contact points (sorted by key: body a, body b, feature id) are both the warm-start cache and what
`World.contacts()` reports.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from rustycs.broad_phase import find_pairs
from rustycs.contact_solver import (
    CONTACT_HERTZ,
    NORMAL_IMPULSE,
    NX,
    NY,
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
from rustycs.manifold import LINEAR_SLOP, narrow_phase
from rustycs.motion import apply_bounds, first_non_finite, integrate_positions, integrate_velocities

SPECULATIVE_DISTANCE = 4.0 * LINEAR_SLOP

# layout of the `settings` array
DT, SUBSTEPS, RESTITUTION_THRESHOLD, HAS_BOUNDS, BOUNDS = 0, 1, 2, 3, 4
SETTINGS_SIZE = 8


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
    reach = np.zeros(n)
    escaped = 0
    for tick in range(n_ticks):
        bad = first_non_finite(x, angle, v, w, body_type, active)
        if bad >= 0:  # set from outside between blocks: report it before it spreads
            return bad, tick, escaped, c_key, c_a, c_b, c_point, c_normal, c_sep, c_jn, c_jt
        update_geometry(x, angle, v, kind, radius, nverts, local_verts, local_normals, active,
                        SPECULATIVE_DISTANCE, dt, world_verts, world_normals, hitbox, reach)
        pairs = find_pairs(hitbox, inv_mass, active, group)
        m_a, m_b, m_first, m_count, manifold, p_key, p_point, point = narrow_phase(
            pairs, x, reach, kind, radius, nverts, world_verts, world_normals, friction, restitution,
            SPECULATIVE_DISTANCE)
        n_man = m_a.shape[0]
        n_pts = p_key.shape[0]

        # warm start from last tick's impulses of the same (a, b, feature): both key lists are
        # sorted, so one merge pass finds them
        f = 0
        for p in range(n_pts):
            while f < c_key.shape[0] and c_key[f] < p_key[p]:
                f += 1
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
