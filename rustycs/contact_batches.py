"""Batches: a tick's contacts placed in chunks of `LANES` that share no movable body, in an order that
solves exactly like one pass over the contacts sorted by body ids.

Sequential impulses depend on the order of two contacts only when they share a body that moves: an
immovable body's velocity is read, never written. Each contact, taken in sorted order, goes into the
first chunk with a free lane after the chunks of the earlier contacts on its movable bodies. Solving
chunk after chunk then applies to every body its contacts in sorted order: the result is bit for bit
that of the sorted sequence, while the contacts of one chunk are independent and are solved side by
side, in SIMD lanes. A chunk's lanes are filled from the first; the solver zeroes the rest, so that
solving them changes nothing.

The chains of contacts that must follow each other are short in practice: the 210-box pyramid's
longest has 111 of its 590 contacts, so four lanes are nearly always full.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from rustycs.compiling import inlined, stage
from rustycs.contact_solver import INV_INERTIA, INV_MASS, LANES


class Batches(NamedTuple):
    """The chunks of a tick's manifolds (M at most, as many chunks at most)."""

    first_chunk: np.ndarray  # (N,) per body: the first chunk its next contact may go to
    next_open: np.ndarray  # (M + 1,) per chunk: the next one with a free lane (union-find)
    fill: np.ndarray  # (M,) per chunk: lanes filled, from the first
    chunk_points: np.ndarray  # (M,) per chunk: the largest point count of its manifolds
    slot_manifold: np.ndarray  # (M * LANES,) per slot (lane): its manifold
    slot_a: np.ndarray  # (M * LANES,) per slot: the manifold's bodies
    slot_b: np.ndarray
    last_a: np.ndarray  # (M,) the manifolds scheduled last: bodies and point counts
    last_b: np.ndarray
    last_count: np.ndarray
    last: np.ndarray  # int64 (2,): their number (-1: none yet) and chunk count
    fresh: np.ndarray  # bool (1,): the slots were placed anew since the solver's lanes were last filled


@njit(cache=True)
def new_batches(n_bodies, manifolds):
    """Room for `manifolds` manifolds in as many chunks (each in a chunk of its own at worst). `schedule`
    writes every entry before reading it, so only the entries a tick uses are ever touched, and only their
    pages cost memory: zeroed, the slots of a 64,000-circle pile (4 million, 94 MB) were all resident for
    its 19,000 chunks."""
    slots = manifolds * LANES
    last = np.zeros(2, np.int64)
    last[0] = -1
    return Batches(np.zeros(n_bodies, np.int64), np.empty(manifolds + 1, np.int64),
                   np.empty(manifolds, np.int64), np.empty(manifolds, np.int64), np.empty(slots, np.int64),
                   np.empty(slots, np.int64), np.empty(slots, np.int64), np.empty(manifolds, np.int64),
                   np.empty(manifolds, np.int64), np.empty(manifolds, np.int64), last, np.ones(1, np.bool_))


@inlined
def _movable(body, i):
    return body[i, INV_MASS] != 0.0 or body[i, INV_INERTIA] != 0.0


@stage
def schedule(manifolds, n_man, body, batches):
    """Place the first n_man manifolds (sorted by body ids) in chunks of lane slots; returns the chunk
    count. `body` holds the solver rows of the bodies.

    The manifolds of a resting scene are those of the tick before (same bodies, same point counts):
    then the slots are as they were."""
    m_a, m_b, m_count = manifolds.body_a, manifolds.body_b, manifolds.count
    (first_chunk, next_open, fill, chunk_points, slot_manifold, slot_a, slot_b, last_a, last_b, last_count,
     last, fresh) = batches
    if n_man == last[0]:
        same = True
        for m in range(n_man):
            if m_a[m] != last_a[m] or m_b[m] != last_b[m] or m_count[m] != last_count[m]:
                same = False
                break
        if same:
            return last[1]
    for i in range(first_chunk.shape[0]):
        first_chunk[i] = 0
    n_chunks = 0
    next_open[0] = 0
    for m in range(n_man):
        a = m_a[m]
        b = m_b[m]
        k = max(first_chunk[a], first_chunk[b])
        while next_open[k] != k:  # the first chunk from k on with a free lane (path halving)
            next_open[k] = next_open[next_open[k]]
            k = next_open[k]
        if k == n_chunks:  # a new chunk
            n_chunks += 1
            next_open[n_chunks] = n_chunks
            fill[k] = 0
            chunk_points[k] = 1
        s = k * LANES + fill[k]
        fill[k] += 1
        if fill[k] == LANES:
            next_open[k] = k + 1
        slot_manifold[s] = m
        slot_a[s] = a
        slot_b[s] = b
        chunk_points[k] = max(chunk_points[k], m_count[m])
        if _movable(body, a):
            first_chunk[a] = k + 1
        if _movable(body, b):
            first_chunk[b] = k + 1
        last_a[m] = a
        last_b[m] = b
        last_count[m] = m_count[m]
    last[0] = n_man
    last[1] = n_chunks
    fresh[0] = True
    return n_chunks
