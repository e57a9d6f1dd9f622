"""The tick: geometry, broad phase, narrow phase, warm start, soft contact solver with substeps,
integration, bounds.

One compiled function runs a block of ticks so that Python costs once per block. Its buffers (the
workspace) belong to the world and live from block to block, growing when a tick needs more: a tick
of a settled scene allocates nothing, even when a recorder steps one tick at a time. The previous
tick's contact points (sorted by key: shape a, shape b, feature id) are both the warm-start cache and
what `World.contacts()` reports.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from rustycs.broad_phase import Pairs, fatten, find_pairs, grid_scratch_size, pairs_hold
from rustycs.constants import CONTACT_DAMPING_RATIO, CONTACT_HERTZ, SPECULATIVE_DISTANCE
from rustycs.contact_batches import Batches, new_batches, schedule
from rustycs.contact_cache import ContactCache, new_cache, remember, warm_start_points
from rustycs.contact_solver import (
    BODY_COLUMNS,
    LANE_FIELDS,
    LANES,
    load_bodies,
    prepare,
    restitute,
    softness,
    solve,
    store_bodies,
    store_impulses,
    warm_start,
)
from rustycs.geometry import Geometry, new_geometry, update_geometry
from rustycs.motion import apply_bounds, first_non_finite, integrate_positions, integrate_velocities
from rustycs.narrow_phase import Contacts, narrow_phase, new_contacts
from rustycs.recording import record_frame
from rustycs.tick_kernel import tick_kernel


class Settings(NamedTuple):
    """How a world steps."""

    dt: float  # s per tick
    substeps: int  # solver substeps per tick (the scene's precision)
    restitution_threshold: float  # m/s: slower approaches do not bounce
    bounds: np.ndarray  # (4,) xmin, ymin, xmax, ymax: dynamic bodies leaving them are deactivated
    has_bounds: bool


class Workspace(NamedTuple):
    """The step's buffers, kept by the world from one block to the next."""

    geometry: Geometry
    pairs: Pairs
    contacts: Contacts
    cache: ContactCache  # the last tick's points: the warm start of the next
    body: np.ndarray  # (N, BODY_COLUMNS) the solver's rows of the bodies
    batches: Batches
    lanes: np.ndarray  # the solver's lanes of the scheduled contacts
    statics_placed: np.ndarray  # bool (1,): the static bodies' geometry is up to date


@njit(cache=True)
def new_workspace(n_bodies, n_shapes, max_vertices, c_key, c_jn, c_jt):
    """Buffers for stepping, with a warm-start cache (keys and impulses) carried over."""
    capacity = max(4 * n_shapes + 16, c_key.shape[0])
    pairs = Pairs(np.empty(capacity, np.int64), np.zeros(1, np.int64), np.full((n_shapes, 4), np.nan),
                  np.zeros(n_shapes, np.bool_), np.empty(grid_scratch_size(n_shapes), np.int64),
                  np.empty(n_shapes), np.empty(capacity, np.int64))
    return Workspace(new_geometry(n_bodies, n_shapes, max_vertices), pairs, new_contacts(capacity),
                     new_cache(2 * capacity, c_key, c_jn, c_jt), np.empty((n_bodies, BODY_COLUMNS)),
                     new_batches(n_bodies, capacity), np.empty(capacity * LANE_FIELDS), np.zeros(1, np.bool_))


@njit(cache=True)
def grown(ws, n_bodies, cells, pairs, points, chunks):
    """The workspace with every buffer that holds fewer than these entries replaced by one twice as
    large (the contents of a replaced buffer are not kept: each is refilled by its stage)."""
    p = ws.pairs
    if cells > p.cells.shape[0] or pairs > p.keys.shape[0]:
        p = Pairs(np.empty(max(2 * pairs, p.keys.shape[0]), np.int64), p.count, p.fat_hitbox, p.fat_active,
                  p.grid, p.extents, np.empty(max(2 * cells, p.cells.shape[0]), np.int64))
    contacts, batches = ws.contacts, ws.batches
    if pairs > contacts.manifolds.first.shape[0]:
        contacts = new_contacts(2 * pairs)
        batches = new_batches(n_bodies, 2 * pairs)
    cache = ws.cache
    if points > cache.key.shape[0]:  # keeps its entries: they warm-start the tick that needs more
        cache = new_cache(2 * points, cache.key[:cache.count[0]], cache.normal_impulse[:cache.count[0]],
                          cache.tangent_impulse[:cache.count[0]])
    lanes = ws.lanes
    if chunks * LANES * LANE_FIELDS > lanes.shape[0]:
        lanes = np.empty(2 * chunks * LANES * LANE_FIELDS)
    return Workspace(ws.geometry, p, contacts, cache, ws.body, batches, lanes, ws.statics_placed)


@njit(cache=True)
def broad_phase(bodies, shapes, ws):
    """The candidate pairs, found again only when a hitbox left its fat one (or a body was switched on
    or off); the pair buffers grow when the grid or the pairs need more."""
    if pairs_hold(bodies, shapes, ws.geometry, ws.pairs):
        return ws
    fatten(bodies, shapes, ws.geometry, ws.pairs)
    n_pairs, n_entries = find_pairs(bodies, shapes, ws.pairs)
    while n_entries > ws.pairs.cells.shape[0] or n_pairs > ws.pairs.keys.shape[0]:  # rare
        ws = grown(ws, bodies.x.shape[0], n_entries, n_pairs, 0, 0)
        n_pairs, n_entries = find_pairs(bodies, shapes, ws.pairs)
    ws.pairs.count[0] = n_pairs
    return ws


@tick_kernel
def substeps_and_restitution(batches, n_chunks, lanes, body, bodies, forces, h, substeps, threshold, bouncy):
    """The solver's substeps: integrate velocities, warm start, solve with the soft bias, integrate
    positions, relax; then restitution, when `bouncy` contacts have any. One compiled call with every
    pass inlined: a call per pass cost a quarter of the tick of a five-body scene."""
    for _ in range(substeps):
        integrate_velocities(body, bodies, forces, h)
        warm_start(batches, n_chunks, lanes, body)
        solve(batches, n_chunks, lanes, body, 1.0 / h, True)
        integrate_positions(body, bodies, h)
        solve(batches, n_chunks, lanes, body, 1.0 / h, False)
    # a single pass would favour the first point of a two-point manifold (a flat box would bounce
    # unevenly and spin); repeated passes converge to -e times the approach speed at both
    for _ in range(substeps if bouncy > 0 else 0):
        restitute(batches, n_chunks, lanes, body, threshold)


@njit(cache=True, nogil=True)
def step_world(n_ticks, bodies, shapes, forces, settings, ws, first_tick, every, frames):
    """Advance `n_ticks` ticks in place. Releases the GIL, so independent worlds step in parallel
    threads.

    With `every` > 0, a frame (`recording.record_frame`) is written into `frames` after every
    `every`-th tick of the block and after its last; ticks are numbered from `first_tick`.
    Returns (bad_body, ticks_done, escaped, frames_recorded, workspace): bad_body is -1, or the first
    body whose state became non-finite in tick `ticks_done` (then the block stops there, its frames so
    far recorded). The workspace is the one given, with any buffer that had to grow replaced.
    """
    dt = settings.dt
    h = dt / settings.substeps
    contact_hertz = min(CONTACT_HERTZ, 0.25 / h)
    soft = softness(contact_hertz, CONTACT_DAMPING_RATIO, h)
    # contacts against an immovable body are stiffer: only one side gives way
    stiff = softness(2.0 * contact_hertz, CONTACT_DAMPING_RATIO, h)
    n_bodies = bodies.x.shape[0]
    escaped = 0
    bad = -1
    done = 0
    recorded = 0
    for _ in range(n_ticks):
        bad = first_non_finite(bodies)
        if bad >= 0:  # set from outside between blocks: report it before it spreads
            break
        update_geometry(bodies, shapes, SPECULATIVE_DISTANCE, dt, not ws.statics_placed[0], ws.geometry)
        ws.statics_placed[0] = True
        ws = broad_phase(bodies, shapes, ws)
        n_pairs = ws.pairs.count[0]
        ws = grown(ws, n_bodies, 0, n_pairs, 2 * n_pairs, 0)
        n_man, n_pts = narrow_phase(ws.pairs.keys, n_pairs, bodies, shapes, ws.geometry,
                                    SPECULATIVE_DISTANCE, ws.contacts)
        warm_start_points(ws.contacts.points, n_pts, ws.cache)
        load_bodies(bodies, h, ws.body)
        n_chunks = schedule(ws.contacts.manifolds, n_man, ws.body, ws.batches)
        ws = grown(ws, n_bodies, 0, 0, 0, n_chunks)
        bouncy = prepare(ws.batches, n_chunks, ws.contacts.manifolds, ws.contacts.points, ws.body, soft,
                         stiff, ws.lanes)
        substeps_and_restitution(ws.batches, n_chunks, ws.lanes, ws.body, bodies, forces, h,
                                 settings.substeps, settings.restitution_threshold, bouncy)
        store_impulses(ws.batches, n_chunks, ws.contacts.manifolds, ws.lanes, ws.contacts.points)
        store_bodies(ws.body, bodies)
        remember(ws.contacts.points, n_pts, ws.cache)
        bad = first_non_finite(bodies)
        if bad >= 0:
            break
        if settings.has_bounds:
            escaped += apply_bounds(bodies, settings.bounds)
        done += 1
        if every > 0 and (done % every == 0 or done == n_ticks):
            record_frame(frames, recorded, first_tick + done, bodies, forces, ws.contacts.points, n_pts)
            recorded += 1
    return bad, done, escaped, recorded, ws
