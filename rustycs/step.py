"""The tick: broad phase, narrow phase, soft contact solver with substeps, integration.

One compiled function runs a block of ticks so that Python costs once per block. Its buffers (the
workspace) belong to the world and live from block to block, growing when a tick needs more: a tick
of a settled scene allocates nothing, even when a recorder steps one tick at a time. The previous
tick's contact points (sorted by key: body a, body b, feature id) are both the warm-start cache and
what `World.contacts()` reports.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from rustycs.broad_phase import fatten, find_pairs, grid_scratch_size, pairs_hold
from rustycs.contact_batches import batch_buffers, schedule
from rustycs.contact_solver import (
    BODY_COLUMNS,
    CONTACT_HERTZ,
    DAMPING_RATIO,
    LANE_FIELDS,
    LANES,
    NORMAL_IMPULSE,
    NX,
    NY,
    SEPARATION,
    TANGENT_IMPULSE,
    load_bodies,
    prepare,
    restitute,
    softness,
    solve,
    store_bodies,
    store_impulses,
    warm_start,
)
from rustycs.hitbox import update_geometry
from rustycs.manifold import LINEAR_SLOP, contact_buffers, narrow_phase
from rustycs.motion import apply_bounds, first_non_finite, integrate_positions, integrate_velocities
from rustycs.recording import record_frame
from rustycs.tick_kernel import tick_kernel

SPECULATIVE_DISTANCE = 4.0 * LINEAR_SLOP

# layout of the `settings` array
DT, SUBSTEPS, RESTITUTION_THRESHOLD, HAS_BOUNDS, BOUNDS = 0, 1, 2, 3, 4
SETTINGS_SIZE = 8

# the workspace tuple: world vertices, world normals, hitboxes, reach, grid scratch, extents, cells,
# pair keys, solver body rows, CONTACTS (the narrow phase's buffers), warm-start keys, normal and
# tangent impulses, SIZES, the batches' buffers (`contact_batches.batch_buffers`), the solver's lanes,
# the fat hitboxes and active flags the pairs were found for
HITBOXES, PAIR_KEYS, BODY_ROWS, CONTACTS, SIZES, BATCHES, FAT_HITBOXES = 2, 7, 8, 9, 13, 14, 16
POINT_ROWS = 7  # the solver rows of the points, in the CONTACTS tuple
# entries of the SIZES array: last tick's manifolds and points, warm-start cache entries, pairs
N_MANIFOLDS, N_POINTS, N_CACHE, N_PAIRS = 0, 1, 2, 3


@njit(cache=True)
def new_workspace(n, max_vertices, c_key, c_jn, c_jt):
    """Buffers for stepping n bodies, with the warm-start cache (keys and impulses) carried over."""
    capacity = max(4 * n + 16, c_key.shape[0])
    cache_key = np.empty(2 * capacity, dtype=np.int64)
    cache_jn = np.empty(2 * capacity)
    cache_jt = np.empty(2 * capacity)
    k = c_key.shape[0]
    cache_key[:k] = c_key
    cache_jn[:k] = c_jn
    cache_jt[:k] = c_jt
    sizes = np.zeros(4, dtype=np.int64)
    sizes[N_CACHE] = k
    batches = batch_buffers(n, capacity)
    return (np.zeros((n, max_vertices, 2)), np.zeros((n, max_vertices, 2)), np.zeros((n, 4)), np.zeros(n),
            np.empty(grid_scratch_size(n), dtype=np.int64), np.empty(n), np.empty(capacity, dtype=np.int64),
            np.empty(capacity, dtype=np.int64), np.empty((n, BODY_COLUMNS)), contact_buffers(capacity),
            cache_key, cache_jn, cache_jt, sizes, batches, np.empty(capacity * LANE_FIELDS),
            np.full((n, 4), np.nan), np.zeros(n, dtype=np.bool_))


@tick_kernel
def substeps_and_restitution(batches, n_chunks, lanes, body, x, angle, body_type, active, gravity, att_pos,
                             att_gm, att_range, att_min_distance, h, substeps, threshold, bouncy):
    """The solver's substeps: integrate velocities, warm start, solve with the soft bias, integrate
    positions, relax; then restitution, when `bouncy` contacts have any. One compiled call with every
    pass inlined: a call per pass cost a quarter of the tick of a five-body scene."""
    for _ in range(substeps):
        integrate_velocities(body, x, body_type, active, gravity, att_pos, att_gm, att_range,
                             att_min_distance, h)
        warm_start(batches, n_chunks, lanes, body)
        solve(batches, n_chunks, lanes, body, 1.0 / h, True)
        integrate_positions(x, angle, body, body_type, active, h)
        solve(batches, n_chunks, lanes, body, 1.0 / h, False)
    # a single pass would favour the first point of a two-point manifold (a flat box would bounce
    # unevenly and spin); repeated passes converge to -e times the approach speed at both
    for _ in range(substeps if bouncy > 0 else 0):
        restitute(batches, n_chunks, lanes, body, threshold)


@njit(cache=True, nogil=True)
def step_world(n_ticks, x, angle, v, w, inv_mass, inv_inertia, body_type, kind, radius, nverts,
               local_verts, local_normals, restitution, friction, active, group,
               gravity, att_pos, att_gm, att_range, att_min_distance, settings, workspace,
               mass, inertia, origin_offset, first_tick, every, frames):
    """Advance `n_ticks` ticks in place. Releases the GIL, so independent worlds step in parallel
    threads.

    With `every` > 0, a frame (`recording.record_frame`) is written into `frames` after every
    `every`-th tick of the block and after its last; ticks are numbered from `first_tick`.
    Returns (bad_body, ticks_done, escaped, frames_recorded, workspace): bad_body is -1, or the first
    body whose state became non-finite in tick `ticks_done` (then the block stops there, its frames so
    far recorded). The workspace is the one given, with any buffer that had to grow replaced.
    """
    dt = settings[DT]
    substeps = int(settings[SUBSTEPS])
    h = dt / substeps
    threshold = settings[RESTITUTION_THRESHOLD]
    bounds = settings[BOUNDS:BOUNDS + 4]
    contact_hertz = min(CONTACT_HERTZ, 0.25 / h)
    soft = softness(contact_hertz, DAMPING_RATIO, h)
    # contacts against an immovable body are stiffer: only one side gives way
    stiff = softness(2.0 * contact_hertz, DAMPING_RATIO, h)
    (world_verts, world_normals, hitbox, reach, grid, extents, cells, pair_keys, body, contacts,
     cache_key, cache_jn, cache_jt, sizes, batches, lanes, fat_hitbox, fat_active) = workspace
    n_cache = sizes[N_CACHE]
    escaped = 0
    bad = -1
    done = 0
    recorded = 0
    for _ in range(n_ticks):
        bad = first_non_finite(x, angle, v, w, body_type, active)
        if bad >= 0:  # set from outside between blocks: report it before it spreads
            break
        update_geometry(x, angle, v, kind, radius, nverts, local_verts, local_normals, active,
                        SPECULATIVE_DISTANCE, dt, world_verts, world_normals, hitbox, reach)
        if not pairs_hold(hitbox, active, fat_hitbox, fat_active):
            fatten(hitbox, active, fat_hitbox, fat_active)
            n_pairs, n_entries = find_pairs(fat_hitbox, inv_mass, active, group, grid, extents, cells,
                                            pair_keys)
            while n_entries > cells.shape[0] or n_pairs > pair_keys.shape[0]:  # rare: the buffers grow
                cells = np.empty(max(2 * n_entries, cells.shape[0]), dtype=np.int64)
                pair_keys = np.empty(max(2 * n_pairs, pair_keys.shape[0]), dtype=np.int64)
                n_pairs, n_entries = find_pairs(fat_hitbox, inv_mass, active, group, grid, extents, cells,
                                                pair_keys)
            sizes[N_PAIRS] = n_pairs
        n_pairs = sizes[N_PAIRS]
        if n_pairs > contacts[0].shape[0]:
            contacts = contact_buffers(2 * n_pairs)
            batches = batch_buffers(x.shape[0], 2 * n_pairs)
        n_man, n_pts = narrow_phase(pair_keys[:n_pairs], x, hitbox, reach, kind, radius, nverts, world_verts,
                                    world_normals, friction, restitution, SPECULATIVE_DISTANCE, contacts)
        sizes[N_MANIFOLDS] = n_man
        sizes[N_POINTS] = n_pts
        m_a = contacts[0][:n_man]
        m_b = contacts[1][:n_man]
        m_first = contacts[2][:n_man]
        m_count = contacts[3][:n_man]
        manifold = contacts[4][:n_man]
        p_key = contacts[5][:n_pts]
        point = contacts[POINT_ROWS][:n_pts]

        # warm start from last tick's impulses of the same (a, b, feature): both key lists are
        # sorted, so one merge pass finds them
        f = 0
        for p in range(n_pts):
            while f < n_cache and cache_key[f] < p_key[p]:
                f += 1
            if f < n_cache and cache_key[f] == p_key[p]:
                point[p, NORMAL_IMPULSE] = cache_jn[f]
                point[p, TANGENT_IMPULSE] = cache_jt[f]

        load_bodies(v, w, inv_mass, inv_inertia, body)
        n_chunks = schedule(m_a, m_b, m_count, body, batches)
        if n_chunks * LANES * LANE_FIELDS > lanes.shape[0]:  # rare: the contacts need more lanes
            lanes = np.empty(2 * n_chunks * LANES * LANE_FIELDS)
        bouncy = prepare(batches, n_chunks, m_a, m_b, manifold, m_first, m_count, point, body, soft, stiff,
                         lanes)
        substeps_and_restitution(batches, n_chunks, lanes, body, x, angle, body_type, active, gravity,
                                 att_pos, att_gm, att_range, att_min_distance, h, substeps, threshold, bouncy)
        store_impulses(batches, n_chunks, m_first, m_count, lanes, point)
        store_bodies(body, v, w, body_type)

        # this tick's impulses warm-start the next
        if n_pts > cache_key.shape[0]:
            cache_key = np.empty(2 * n_pts, dtype=np.int64)
            cache_jn = np.empty(2 * n_pts)
            cache_jt = np.empty(2 * n_pts)
        n_cache = n_pts
        sizes[N_CACHE] = n_pts
        for p in range(n_pts):
            cache_key[p] = p_key[p]
            cache_jn[p] = point[p, NORMAL_IMPULSE]
            cache_jt[p] = point[p, TANGENT_IMPULSE]

        bad = first_non_finite(x, angle, v, w, body_type, active)
        if bad >= 0:
            break
        if settings[HAS_BOUNDS] != 0.0:
            escaped += apply_bounds(x, v, w, body_type, active, bounds)
        done += 1
        if every > 0 and (done % every == 0 or done == n_ticks):
            record_frame(frames, recorded, first_tick + done, x, angle, v, w, active, body_type, mass,
                         inertia, inv_inertia, origin_offset, gravity, att_pos, att_gm, att_range,
                         att_min_distance, point[:, SEPARATION], point[:, NORMAL_IMPULSE])
            recorded += 1
    workspace = (world_verts, world_normals, hitbox, reach, grid, extents, cells, pair_keys, body, contacts,
                 cache_key, cache_jn, cache_jt, sizes, batches, lanes, fat_hitbox, fat_active)
    return bad, done, escaped, recorded, workspace


@njit(cache=True)
def last_contacts(workspace):
    """The last tick's contact points, one row each: key, bodies, position, normal, separation and
    impulses (what `World.contacts()` reports, and the warm-start cache of a rebuilt workspace)."""
    m_a, m_b, m_first, m_count, manifold, p_key, p_point, point = workspace[CONTACTS][:8]
    n_man = workspace[SIZES][N_MANIFOLDS]
    n_pts = workspace[SIZES][N_POINTS]
    c_a = np.empty(n_pts, dtype=np.int64)
    c_b = np.empty(n_pts, dtype=np.int64)
    c_normal = np.empty((n_pts, 2))
    for m in range(n_man):
        for p in range(m_first[m], m_first[m] + m_count[m]):
            c_a[p] = m_a[m]
            c_b[p] = m_b[m]
            c_normal[p, 0] = manifold[m, NX]
            c_normal[p, 1] = manifold[m, NY]
    return (p_key[:n_pts].copy(), c_a, c_b, p_point[:n_pts].copy(), c_normal,
            point[:n_pts, SEPARATION].copy(), point[:n_pts, NORMAL_IMPULSE].copy(),
            point[:n_pts, TANGENT_IMPULSE].copy())
