"""Threads inside one world: the stages whose work splits by element run in parts, over threads.

A world stepped with `threads` > 1 places its bodies' shapes, finds its shapes' partners in a whole search
of the broad phase, collides its candidate pairs and fills its contacts' solver lanes in parts of a fixed
size (not a share per thread): each part computes its elements from their own inputs alone, into rows of
its own, and the parts are joined in order. So the result is bitwise that of one thread, for any thread
count. The solver's substeps run group by group of islands (`substeps`), the groups side by side; within
an island each body meets its contacts in a fixed order, a chain through the whole pile, so one island
runs on one thread. The broad phase's grid and refresh and the rest of the tick stay on the calling
thread. numba's parallel loops (`prange`) run the parts; a world with fewer than two parts of a stage
runs it on one thread, as waking the threads costs more than the work.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import get_thread_id, njit, prange

from rustycs.broad_phase import make_grid, partners
from rustycs.compiling import inlined, parallel_kernel
from rustycs.contact_solver import prepare_chunks, store_impulses
from rustycs.geometry import Geometry, place_bodies
from rustycs.manifold import Collision
from rustycs.narrow_phase import collide_pairs
from rustycs.pieces import MAX_VERTICES
from rustycs.stepper import borrowed
from rustycs.substeps import group_substeps
from rustycs.time_of_impact import Sweep

BODY_PART = 64  # bodies placed by one part
SHAPE_PART = 128  # shapes whose partners one part of a whole search finds
PAIR_PART = 128  # candidate pairs collided by one part
CHUNK_PART = 16  # chunks of contacts whose lanes one part fills
# A thread's rows of collision and sweep scratch lie this many rows from the next thread's, so that no two
# threads write one cache line (a row of the normal is 16 bytes): rows side by side, two threads collided
# many_pyramids' 58,000 pairs in 10.2-11.3 ms, one thread in 8.3-10.6 and the serial narrow phase in 8.0-8.5
THREAD_ROWS = 16


class ThreadScratch(NamedTuple):
    """Per thread, the scratch of one pair's collision and sweep (rows as `manifold.Collision` and
    `time_of_impact.Sweep`, thread t's at row t * THREAD_ROWS of R = T * THREAD_ROWS); per part of the
    pairs, the manifolds and points it found; per part of the chunks, its bouncing contacts; per thread,
    the pair keys of the parts of a whole search it took, and per part of the shapes, the thread, first key
    and count of its pairs. (A parallel loop sums nothing itself: that needs numba's reference counting,
    which the tick's kernels go without.)"""

    normal: np.ndarray  # (R, 2)
    points: np.ndarray  # (R, 2, 2)
    separations: np.ndarray  # (R, 2)
    ids: np.ndarray  # (R, 2) int64
    apart: np.ndarray  # (R, 1)
    kind: np.ndarray  # (R, 2) int64
    radius: np.ndarray  # (R, 2)
    count: np.ndarray  # (R, 2) int64
    open_ends: np.ndarray  # (R, 2) int64
    vertices: np.ndarray  # (R, 2, MAX_VERTICES, 2)
    normals: np.ndarray  # (R, 2, MAX_VERTICES, 2)
    centroid: np.ndarray  # (R, 2, 2)
    ghosts: np.ndarray  # (R, 2, 2, 2)
    hitbox: np.ndarray  # (R, 2, 4)
    reach: np.ndarray  # (R, 2)
    travel: np.ndarray  # (R, 2, 2)
    found: np.ndarray  # (P, 2) int64 per part of the pairs: manifolds and points
    bouncy: np.ndarray  # (C,) int64 per part of the chunks: contacts that may bounce
    keys: np.ndarray  # (T, K) int64, K as long as the pairs' keys (unzeroed: only rows used are resident)
    filled: np.ndarray  # (T,) int64: keys in each thread's row
    shape_parts: np.ndarray  # (Q, 3) int64 per part of the shapes: thread, first key in its row, count


@njit(cache=True)
def new_thread_scratch(threads, pairs, keys, shapes):
    """Scratch for `threads` threads colliding up to `pairs` candidate pairs, finding up to `keys` pairs
    of `shapes` shapes."""
    t = threads * THREAD_ROWS
    return ThreadScratch(np.zeros((t, 2)), np.zeros((t, 2, 2)), np.zeros((t, 2)), np.zeros((t, 2), np.int64),
                         np.zeros((t, 1)), np.zeros((t, 2), np.int64), np.zeros((t, 2)),
                         np.zeros((t, 2), np.int64), np.zeros((t, 2), np.int64),
                         np.zeros((t, 2, MAX_VERTICES, 2)), np.zeros((t, 2, MAX_VERTICES, 2)),
                         np.zeros((t, 2, 2)), np.zeros((t, 2, 2, 2)), np.zeros((t, 2, 4)), np.zeros((t, 2)),
                         np.zeros((t, 2, 2)),
                         np.zeros((pairs // PAIR_PART + 1, 2), np.int64),
                         np.zeros(pairs // CHUNK_PART + 1, np.int64),
                         np.empty((threads, keys), np.int64), np.zeros(threads, np.int64),
                         np.zeros((shapes // SHAPE_PART + 1, 3), np.int64))


@inlined
def _collision_of(scratch, thread):
    t = thread * THREAD_ROWS
    return Collision(scratch.normal[t], scratch.points[t], scratch.separations[t], scratch.ids[t],
                     scratch.apart[t])


@inlined
def _sweep_of(scratch, thread):
    t = thread * THREAD_ROWS
    return Sweep(scratch.kind[t], scratch.radius[t], scratch.count[t], scratch.open_ends[t],
                 Geometry(scratch.vertices[t], scratch.normals[t], scratch.centroid[t], scratch.ghosts[t],
                          scratch.hitbox[t], scratch.reach[t], scratch.travel[t]))


@parallel_kernel
def place_bodies_in_parts(stepper, margin, dt, statics):
    """`geometry.update_geometry` of the stepper's world, in parts of BODY_PART bodies."""
    n = borrowed(stepper).bodies.x.shape[0]
    for p in prange((n + BODY_PART - 1) // BODY_PART):
        _place_part(stepper, p, n, margin, dt, statics)


# A parallel loop takes only arrays, numbers and the stepper (whose records are read inside it), and its
# body only calls a part's function: numba's parallel loops lost writes made in the loop's own body
# through arrays read from the stepper (not those made in a called function).


@inlined
def _place_part(stepper, p, n, margin, dt, statics):
    world = borrowed(stepper)
    place_bodies(p * BODY_PART, min(n, (p + 1) * BODY_PART), world.bodies, world.shapes, margin, dt, statics,
                 world.workspace.geometry)


@parallel_kernel
def find_pairs_in_parts(stepper):
    """`broad_phase.find_pairs` of the stepper's world, the partners found in parts of SHAPE_PART shapes:
    each thread appends the keys of the parts it takes to a row of its own, then the parts are joined in
    order (each part's keys are sorted and follow the last part's). Returns (pair count, cell entries)."""
    world = borrowed(stepper)
    pairs = world.workspace.pairs
    entries = make_grid(world.bodies, world.shapes, pairs)
    if pairs.layout[0] == 0:
        return 0, entries
    scratch = world.workspace.threads
    _empty_rows(scratch.filled)
    n_parts = (pairs.fat_hitbox.shape[0] + SHAPE_PART - 1) // SHAPE_PART
    for p in prange(n_parts):
        _partners_part(stepper, p, get_thread_id())
    return _join_keys(pairs.keys, scratch, n_parts), entries


@inlined
def _empty_rows(filled):
    """No keys in any thread's row (written in a call: see above)."""
    for t in range(filled.shape[0]):
        filled[t] = 0


@inlined
def _partners_part(stepper, p, thread):
    world = borrowed(stepper)
    ws = world.workspace
    scratch = ws.threads
    n = ws.pairs.fat_hitbox.shape[0]
    start = scratch.filled[thread]
    found = partners(world.bodies, world.shapes, world.joints, world.joint_filter, ws.pairs, p * SHAPE_PART,
                     min(n, (p + 1) * SHAPE_PART), scratch.keys[thread], start)
    scratch.shape_parts[p, 0] = thread
    scratch.shape_parts[p, 1] = start
    scratch.shape_parts[p, 2] = found
    scratch.filled[thread] = start + found


@inlined
def _join_keys(keys, scratch, n_parts):
    """Copy each part's keys after the parts before it; returns the pairs found (copied only when they fit
    in `keys`, and so in every thread's row, as long)."""
    parts = scratch.shape_parts
    total = 0
    for p in range(n_parts):
        total += parts[p, 2]
    if total > keys.shape[0]:
        return total
    out = 0
    for p in range(n_parts):
        row = scratch.keys[parts[p, 0]]
        for k in range(parts[p, 1], parts[p, 1] + parts[p, 2]):
            keys[out] = row[k]
            out += 1
    return total


@parallel_kernel
def collide_pairs_in_parts(stepper, n_pairs, margin, dt, sleeping):
    """`narrow_phase.narrow_phase` of the stepper's world, in parts of PAIR_PART pairs: part p writes from
    manifold row p * PAIR_PART and point row 2 p PAIR_PART (a pair has a manifold and two points at
    most), then the parts are moved together in order."""
    n_parts = (n_pairs + PAIR_PART - 1) // PAIR_PART
    for p in prange(n_parts):
        _collide_part(stepper, p, n_pairs, margin, dt, sleeping, get_thread_id())
    ws = borrowed(stepper).workspace
    return _join(ws.contacts, ws.threads.found, n_parts)


@inlined
def _collide_part(stepper, p, n_pairs, margin, dt, sleeping, thread):
    world = borrowed(stepper)
    ws = world.workspace
    scratch = ws.threads
    first = p * PAIR_PART
    manifolds, points = collide_pairs(first, min(n_pairs, first + PAIR_PART), first, 2 * first,
                                      ws.pairs.keys, world.bodies, world.shapes, ws.geometry, margin, dt,
                                      sleeping, ws.contacts, _collision_of(scratch, thread),
                                      _sweep_of(scratch, thread))
    scratch.found[p, 0] = manifolds
    scratch.found[p, 1] = points


@inlined
def _join(contacts, found, n_parts):
    """Move each part's manifolds and points down to follow the parts before it. A part after none but full
    ones (every pair a manifold of two points) is in place: all 453 of many_pyramids' parts are, and moving
    them onto themselves took 0.9-1.2 ms. (Copied into rows of their own, the parts joined over two threads
    took as long: the copy is bound by memory.)"""
    m = contacts.manifolds
    pts = contacts.points
    n_man = 0
    n_pts = 0
    for p in range(n_parts):
        m_from, p_from = p * PAIR_PART, 2 * p * PAIR_PART
        if n_man == m_from and n_pts == p_from:
            n_man += found[p, 0]
            n_pts += found[p, 1]
            continue
        for k in range(found[p, 0]):
            src, dst = m_from + k, n_man + k
            m.shape_a[dst] = m.shape_a[src]
            m.shape_b[dst] = m.shape_b[src]
            m.body_a[dst] = m.body_a[src]
            m.body_b[dst] = m.body_b[src]
            m.first[dst] = m.first[src] - p_from + n_pts
            m.count[dst] = m.count[src]
            for column in range(m.data.shape[1]):
                m.data[dst, column] = m.data[src, column]
        for k in range(found[p, 1]):
            src, dst = p_from + k, n_pts + k
            pts.key[dst] = pts.key[src]
            pts.position[dst, 0] = pts.position[src, 0]
            pts.position[dst, 1] = pts.position[src, 1]
            for column in range(pts.data.shape[1]):
                pts.data[dst, column] = pts.data[src, column]
        n_man += found[p, 0]
        n_pts += found[p, 1]
    contacts.count[0] = n_man
    contacts.count[1] = n_pts
    return n_man, n_pts


@parallel_kernel
def prepare_in_parts(stepper, n_chunks):
    """`contact_solver.prepare` of the stepper's world, in parts of CHUNK_PART chunks; returns the
    contacts that may bounce."""
    n_parts = (n_chunks + CHUNK_PART - 1) // CHUNK_PART
    for p in prange(n_parts):
        _prepare_part(stepper, p, n_chunks)
    bouncy = borrowed(stepper).workspace.threads.bouncy
    total = 0
    for p in range(n_parts):
        total += bouncy[p]
    return total


@inlined
def _prepare_part(stepper, p, n_chunks):
    world = borrowed(stepper)
    ws = world.workspace
    ws.threads.bouncy[p] = prepare_chunks(p * CHUNK_PART, min(n_chunks, (p + 1) * CHUNK_PART), ws.batches,
                                          ws.contacts.manifolds, ws.contacts.points, world.shapes.radius,
                                          ws.body, ws.lanes)


@parallel_kernel
def substeps_in_groups(stepper, joint_soft, h, count, soft, stiff):
    """`substeps.substeps` of the stepper's world, its groups of islands side by side, each group then
    storing its contacts' impulses (`contact_solver.store_impulses`)."""
    n_groups = borrowed(stepper).workspace.batches.last[2]
    for g in prange(n_groups):
        _group_part(stepper, g, joint_soft, h, count, soft, stiff)


@inlined
def _group_part(stepper, g, joint_soft, h, count, soft, stiff):
    world = borrowed(stepper)
    ws = world.workspace
    batches = ws.batches
    group_substeps(g, batches, ws.lanes, ws.body, world.bodies, world.joints, ws.joint_work, joint_soft,
                   world.forces, h, count, soft, stiff, False)
    store_impulses(batches, batches.group_chunks[g], batches.group_chunks[g + 1], ws.contacts.manifolds,
                   ws.lanes, ws.contacts.points)
