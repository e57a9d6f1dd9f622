"""Broad phase: candidate pairs from overlapping hitboxes, through a uniform grid.

The pairs are found for fat hitboxes (each hitbox grown by `FAT_MARGIN`) and kept while every body's
hitbox stays inside its fat one and no body is switched on or off: a resting pile then needs no
broad phase at all, as in Box2D's tree of fat boxes. A pair of fat boxes that do not touch as hitboxes
gives no contact in the narrow phase, so the contacts are those of the hitboxes' pairs, bit for bit.

The grid covers the hitboxes of the dynamic bodies only and its cell size follows their median size,
so the cost grows near-linearly with evenly spread bodies. Static and kinematic bodies are inserted
clipped to that domain, so a huge floor costs one row of cells. A pair is reported once, by the cell
holding the lower corner of the two hitboxes' intersection. Pairs come out sorted by (a, b): the
order the solver relies on for determinism. The buffers are the caller's and are reused tick after
tick, so a tick allocates nothing once they have grown to the scene.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rustycs.tick_kernel import tick_kernel


@njit(cache=True, inline="always")
def hitboxes_overlap(hitbox, i, j):
    return (hitbox[i, 0] <= hitbox[j, 2] and hitbox[j, 0] <= hitbox[i, 2]
            and hitbox[i, 1] <= hitbox[j, 3] and hitbox[j, 1] <= hitbox[i, 3])


@njit(cache=True)
def _cell(value, origin, inv_cell, count):
    """Grid index of a coordinate, clamped in floating point so that far bodies cannot overflow."""
    return int(min(max((value - origin) * inv_cell, 0.0), count - 1.0))


FAT_MARGIN = 0.1  # m: how far a hitbox may move or grow before the pairs are found again


@tick_kernel
def pairs_hold(hitbox, active, fat, fat_active):
    """Whether the pairs found for the fat hitboxes still hold: no body was switched on or off, and
    every active body's hitbox lies inside its fat one (a non-finite hitbox does not)."""
    for i in range(hitbox.shape[0]):
        if active[i] != fat_active[i]:
            return False
        if active[i] and not (fat[i, 0] <= hitbox[i, 0] and fat[i, 1] <= hitbox[i, 1]
                              and hitbox[i, 2] <= fat[i, 2] and hitbox[i, 3] <= fat[i, 3]):
            return False
    return True


@tick_kernel
def fatten(hitbox, active, fat, fat_active):
    """The fat hitboxes the pairs are found for, and the active flags they hold for."""
    for i in range(hitbox.shape[0]):
        fat[i, 0] = hitbox[i, 0] - FAT_MARGIN
        fat[i, 1] = hitbox[i, 1] - FAT_MARGIN
        fat[i, 2] = hitbox[i, 2] + FAT_MARGIN
        fat[i, 3] = hitbox[i, 3] + FAT_MARGIN
        fat_active[i] = active[i]


BODY_BITS = 28  # a pair's key: (a << BODY_BITS) | b, so that keys sort by (a, b)
BODY_MASK = (1 << BODY_BITS) - 1


@njit(cache=True)
def grid_scratch_size(n):
    """Integers of scratch `find_pairs` needs for n bodies: cell ranges, dynamic bodies, cell counts."""
    return 13 * n + 33


@njit(cache=True, inline="always")
def _select(values, k):
    """The k-th smallest of `values` (reordered in place): a deterministic quickselect."""
    lo = 0
    hi = values.shape[0] - 1
    while lo < hi:
        pivot = values[(lo + hi) // 2]
        i = lo
        j = hi
        while i <= j:
            while values[i] < pivot:
                i += 1
            while values[j] > pivot:
                j -= 1
            if i <= j:
                values[i], values[j] = values[j], values[i]
                i += 1
                j -= 1
        if k <= j:
            hi = j
        elif k >= i:
            lo = i
        else:
            break
    return values[k]


@tick_kernel
def find_pairs(hitbox, inv_mass, active, group, grid, extents, cells, keys):
    """Candidate pairs as sorted keys (a << BODY_BITS) | b in keys[:count], a < b, each with a
    dynamic body.

    `grid` (grid_scratch_size(n) integers), `extents` (n floats) and `cells` are scratch. Returns
    (pair count, cell entries): when either exceeds its buffer (`keys`, `cells`), the pairs were not
    all written, and the caller grows the buffers and calls again.
    """
    n = hitbox.shape[0]
    dynamic = grid[:n]
    nd = 0
    for i in range(n):
        if active[i] and inv_mass[i] > 0.0:
            dynamic[nd] = i
            nd += 1
    if nd == 0:
        return 0, 0
    lo_x = np.inf
    lo_y = np.inf
    hi_x = -np.inf
    hi_y = -np.inf
    for k in range(nd):
        i = dynamic[k]
        lo_x = min(lo_x, hitbox[i, 0])
        lo_y = min(lo_y, hitbox[i, 1])
        hi_x = max(hi_x, hitbox[i, 2])
        hi_y = max(hi_y, hitbox[i, 3])
        extents[k] = max(hitbox[i, 2] - hitbox[i, 0], hitbox[i, 3] - hitbox[i, 1])
    width = hi_x - lo_x
    height = hi_y - lo_y
    if not (math.isfinite(width) and math.isfinite(height)):
        return 0, 0  # a non-finite state: the step reports it
    # the cell size only decides speed, never which pairs are found
    cell = max(_select(extents[:nd], nd // 2), 1e-9)
    max_cells = 4.0 * nd + 16.0
    while (width / cell + 1.0) * (height / cell + 1.0) > max_cells:
        cell *= 1.5
    nx = int(width / cell) + 1
    ny = int(height / cell) + 1
    n_cells = nx * ny
    inv_cell = 1.0 / cell

    # cell ranges (x0, y0, x1, y1) of every active body that touches the domain
    ranges = grid[n:5 * n]
    counts = grid[5 * n:5 * n + n_cells + 1]
    fill = grid[9 * n + 17:9 * n + 17 + n_cells]
    for c in range(n_cells + 1):
        counts[c] = 0
    for i in range(n):
        ranges[4 * i] = -1
        if not active[i]:
            continue
        inside = hitbox[i, 2] >= lo_x and hitbox[i, 0] <= hi_x
        if not (inside and hitbox[i, 3] >= lo_y and hitbox[i, 1] <= hi_y):
            continue  # outside the domain (or not finite)
        x0 = _cell(hitbox[i, 0], lo_x, inv_cell, nx)
        y0 = _cell(hitbox[i, 1], lo_y, inv_cell, ny)
        x1 = _cell(hitbox[i, 2], lo_x, inv_cell, nx)
        y1 = _cell(hitbox[i, 3], lo_y, inv_cell, ny)
        ranges[4 * i] = x0
        ranges[4 * i + 1] = y0
        ranges[4 * i + 2] = x1
        ranges[4 * i + 3] = y1
        for cy in range(y0, y1 + 1):
            for cx in range(x0, x1 + 1):
                counts[cy * nx + cx + 1] += 1
    for c in range(n_cells):
        counts[c + 1] += counts[c]
    entries = counts[n_cells]
    if entries > cells.shape[0]:
        return 0, entries
    for c in range(n_cells):
        fill[c] = counts[c]
    for i in range(n):
        if ranges[4 * i] < 0:
            continue
        for cy in range(ranges[4 * i + 1], ranges[4 * i + 3] + 1):
            for cx in range(ranges[4 * i], ranges[4 * i + 2] + 1):
                c = cy * nx + cx
                cells[fill[c]] = i
                fill[c] += 1

    # each body's partners of higher index, inserted in order: the keys come out sorted by (a, b)
    # with no sort of the whole list
    count = 0
    for i in range(n):
        if ranges[4 * i] < 0:
            continue
        first = count
        for cy in range(ranges[4 * i + 1], ranges[4 * i + 3] + 1):
            for cx in range(ranges[4 * i], ranges[4 * i + 2] + 1):
                c = cy * nx + cx
                # a cell lists its bodies in index order: walk down from the top to the first j <= i
                for p in range(counts[c + 1] - 1, counts[c] - 1, -1):
                    j = cells[p]
                    if j <= i:
                        break
                    # a pair is reported once: in the cell of its intersection's lower corner
                    if (max(ranges[4 * i], ranges[4 * j]) != cx
                            or max(ranges[4 * i + 1], ranges[4 * j + 1]) != cy):
                        continue
                    if not hitboxes_overlap(hitbox, i, j):
                        continue
                    if inv_mass[i] == 0.0 and inv_mass[j] == 0.0:
                        continue
                    if group[i] != 0 and group[i] == group[j]:
                        continue
                    if count < keys.shape[0]:
                        key = (i << BODY_BITS) | j
                        k = count
                        while k > first and keys[k - 1] > key:
                            keys[k] = keys[k - 1]
                            k -= 1
                        keys[k] = key
                    count += 1
    return count, entries
