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

Contacts that share no moving body can be solved in any order, and so can whole islands (bodies joined
by contacts): the solver takes the chunks group by group, each group a few islands with about
`SOLVE_GROUP_MANIFOLDS` manifolds, and runs all the substeps of a group before the next, or the groups
side by side on threads (`rustycs.threads`). Every body still meets its contacts in sorted order, in the
same substeps, so the result is bitwise the same for any thread count, and the same as one group to
rounding: a one-point manifold in a chunk with two-point ones takes the two-point path, which rounds
differently (1e-9 m in S5 with groups of 1,024). One group at a time did not run faster on one thread:
the 19 MB of lanes of many_pyramids stream from the processor's last-level cache either way.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from rustycs.body_types import STATIC
from rustycs.compiling import inlined, stage
from rustycs.constants import SOLVE_GROUP_MANIFOLDS
from rustycs.contact_solver import INV_INERTIA, INV_MASS, LANES
from rustycs.union_find import find_root, join


class Batches(NamedTuple):
    """The chunks of a tick's manifolds (M at most, as many chunks at most), in groups of islands."""

    first_chunk: np.ndarray  # (N,) per body: the first chunk its next contact may go to
    next_open: np.ndarray  # (M + 1,) per chunk: the next one with a free lane (union-find)
    fill: np.ndarray  # (M,) per chunk: lanes filled, from the first
    chunk_points: np.ndarray  # (M,) per chunk: the largest point count of its manifolds
    slot_manifold: np.ndarray  # (M * LANES,) per slot (lane): its manifold
    slot_a: np.ndarray  # (M * LANES,) per slot: the manifold's bodies
    slot_b: np.ndarray
    body_order: np.ndarray  # (N,) the bodies, group after group
    group_bodies: np.ndarray  # (N + 2,) per group: its first entry in body_order (then one past the last)
    group_chunks: np.ndarray  # (N + 2,) per group: its first chunk (then the chunk count)
    manifold_order: np.ndarray  # (M,) the manifolds, group after group, each group's in sorted order
    group_manifolds: np.ndarray  # (N + 2,) per group: its first entry in manifold_order
    parent: np.ndarray  # (N,) union-find links of the islands
    island: np.ndarray  # (N,) per island root: its manifolds
    group_of: np.ndarray  # (N,) per body: its group
    cursor: np.ndarray  # (N + 2,) scratch of the counting sorts
    last_a: np.ndarray  # (M,) the manifolds scheduled last: bodies and point counts
    last_b: np.ndarray
    last_count: np.ndarray
    last: np.ndarray  # int64 (3,): their number (-1: none yet), chunk count and group count
    fresh: np.ndarray  # bool (1,): the slots were placed anew since the solver's lanes were last filled


@njit(cache=True)
def new_batches(n_bodies, manifolds):
    """Room for `manifolds` manifolds in as many chunks (each in a chunk of its own at worst). `schedule`
    writes every entry before reading it, so only the entries a tick uses are ever touched, and only their
    pages cost memory: zeroed, the slots of a 64,000-circle pile (4 million, 94 MB) were all resident for
    its 19,000 chunks."""
    slots = manifolds * LANES
    last = np.zeros(3, np.int64)
    last[0] = -1
    n, groups = n_bodies, n_bodies + 2
    return Batches(np.zeros(n, np.int64), np.empty(manifolds + 1, np.int64), np.empty(manifolds, np.int64),
                   np.empty(manifolds, np.int64), np.empty(slots, np.int64), np.empty(slots, np.int64),
                   np.empty(slots, np.int64), np.empty(n, np.int64), np.empty(groups, np.int64),
                   np.empty(groups, np.int64), np.empty(manifolds, np.int64), np.empty(groups, np.int64),
                   np.empty(n, np.int64), np.empty(n, np.int64), np.empty(n, np.int64),
                   np.empty(groups, np.int64), np.empty(manifolds, np.int64), np.empty(manifolds, np.int64),
                   np.empty(manifolds, np.int64), last, np.ones(1, np.bool_))


@inlined
def _movable(body, i):
    return body[i, INV_MASS] != 0.0 or body[i, INV_INERTIA] != 0.0


@inlined
def _island_of(parent, body_type, a, b):
    """The island of a manifold between bodies a and b (at most one of them static)."""
    return find_root(parent, b if body_type[a] == STATIC else a)


@inlined
def _starts(cursor, count, starts):
    """Turn the counts cursor[:count] into first entries, in `starts` and `cursor` alike (starts[count]: the
    total)."""
    total = 0
    for g in range(count):
        c = cursor[g]
        starts[g] = total
        cursor[g] = total
        total += c
    starts[count] = total


@inlined
def _group(m_a, m_b, n_man, body_type, whole, batches):
    """Split the bodies and the manifolds into groups; returns the group count. The islands (bodies joined
    by manifolds; static bodies join nothing) are packed in the order of their least body into groups of
    about `SOLVE_GROUP_MANIFOLDS` manifolds, and a last group holds the bodies of no manifold. With
    `whole`, or fewer manifolds, one group holds them all."""
    order, group_bodies, manifold_order, group_manifolds = (batches.body_order, batches.group_bodies,
                                                             batches.manifold_order, batches.group_manifolds)
    parent, island, group_of, cursor = batches.parent, batches.island, batches.group_of, batches.cursor
    n = body_type.shape[0]
    if whole or n_man < SOLVE_GROUP_MANIFOLDS:
        for i in range(n):
            order[i] = i
        for m in range(n_man):
            manifold_order[m] = m
        group_bodies[0], group_bodies[1] = 0, n
        group_manifolds[0], group_manifolds[1] = 0, n_man
        return 1
    for i in range(n):
        parent[i] = i
        island[i] = 0
    for m in range(n_man):
        a, b = m_a[m], m_b[m]
        if body_type[a] != STATIC and body_type[b] != STATIC:
            join(parent, a, b)
    for m in range(n_man):
        island[_island_of(parent, body_type, m_a[m], m_b[m])] += 1
    n_groups = 0
    in_group = 0
    for i in range(n):  # the roots, each the least body of its island
        if island[i] > 0:
            if n_groups == 0 or in_group + island[i] > SOLVE_GROUP_MANIFOLDS:
                n_groups += 1
                in_group = 0
            group_of[i] = n_groups - 1
            in_group += island[i]
    for g in range(n_groups + 1):
        cursor[g] = 0
    for m in range(n_man):
        cursor[group_of[_island_of(parent, body_type, m_a[m], m_b[m])]] += 1
    _starts(cursor, n_groups + 1, group_manifolds)
    for m in range(n_man):
        g = group_of[_island_of(parent, body_type, m_a[m], m_b[m])]
        manifold_order[cursor[g]] = m
        cursor[g] += 1
    for g in range(n_groups + 1):
        cursor[g] = 0
    for i in range(n):  # a root comes before the other bodies of its island
        root = find_root(parent, i)
        group_of[i] = group_of[root] if island[root] > 0 else n_groups
        cursor[group_of[i]] += 1
    _starts(cursor, n_groups + 1, group_bodies)
    for i in range(n):
        g = group_of[i]
        order[cursor[g]] = i
        cursor[g] += 1
    return n_groups + 1


@stage
def schedule(manifolds, n_man, body, body_type, whole, batches):
    """Place the first n_man manifolds (sorted by body ids) in chunks of lane slots, group by group (see
    `_group`); returns the chunk count, and keeps the group count in `batches.last[2]`. `body` holds the
    solver rows of the bodies, `body_type` their types; `whole`: one group (the joints are solved over all
    bodies at once).

    The manifolds of a resting scene are those of the tick before (same bodies, same point counts):
    then the slots are as they were."""
    m_a, m_b, m_count = manifolds.body_a, manifolds.body_b, manifolds.count
    first_chunk, next_open, fill, chunk_points = (batches.first_chunk, batches.next_open, batches.fill,
                                                  batches.chunk_points)
    slot_manifold, slot_a, slot_b = batches.slot_manifold, batches.slot_a, batches.slot_b
    group_chunks, manifold_order, group_manifolds = (batches.group_chunks, batches.manifold_order,
                                                     batches.group_manifolds)
    last_a, last_b, last_count, last = batches.last_a, batches.last_b, batches.last_count, batches.last
    if n_man == last[0]:
        same = True
        for m in range(n_man):
            if m_a[m] != last_a[m] or m_b[m] != last_b[m] or m_count[m] != last_count[m]:
                same = False
                break
        if same:
            return last[1]
    n_groups = _group(m_a, m_b, n_man, body_type, whole, batches)
    for i in range(first_chunk.shape[0]):
        first_chunk[i] = 0
    n_chunks = 0
    next_open[0] = 0
    for g in range(n_groups):
        group_chunks[g] = n_chunks  # the group's contacts go to chunks of its own
        for e in range(group_manifolds[g], group_manifolds[g + 1]):
            m = manifold_order[e]
            a = m_a[m]
            b = m_b[m]
            k = max(first_chunk[a], first_chunk[b], group_chunks[g])
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
    group_chunks[n_groups] = n_chunks
    for m in range(n_man):
        last_a[m] = m_a[m]
        last_b[m] = m_b[m]
        last_count[m] = m_count[m]
    last[0] = n_man
    last[1] = n_chunks
    last[2] = n_groups
    batches.fresh[0] = True
    return n_chunks
