"""Broad phase: candidate pairs from overlapping hitboxes, through a uniform grid.

The grid covers the hitboxes of the dynamic bodies only and its cell size follows their median size,
so the cost grows near-linearly with evenly spread bodies. Static and kinematic bodies are inserted
clipped to that domain, so a huge floor costs one row of cells. A pair is reported once, by the cell
holding the lower corner of the two hitboxes' intersection. Pairs come out sorted by (a, b): the
order the solver relies on for determinism.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True)
def _overlap(hitbox, i, j):
    return (hitbox[i, 0] <= hitbox[j, 2] and hitbox[j, 0] <= hitbox[i, 2]
            and hitbox[i, 1] <= hitbox[j, 3] and hitbox[j, 1] <= hitbox[i, 3])


@njit(cache=True)
def _cell(value, origin, inv_cell, count):
    """Grid index of a coordinate, clamped in floating point so that far bodies cannot overflow."""
    return int(min(max((value - origin) * inv_cell, 0.0), count - 1.0))


@njit(cache=True)
def find_pairs(hitbox, inv_mass, active, group):
    """Return candidate pairs (P, 2), a < b, sorted, with at least one dynamic body each."""
    n = hitbox.shape[0]
    dynamic = np.empty(n, dtype=np.int64)
    nd = 0
    for i in range(n):
        if active[i] and inv_mass[i] > 0.0:
            dynamic[nd] = i
            nd += 1
    if nd == 0:
        return np.empty((0, 2), dtype=np.int64)
    lo_x = np.inf
    lo_y = np.inf
    hi_x = -np.inf
    hi_y = -np.inf
    extents = np.empty(nd)
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
        return np.empty((0, 2), dtype=np.int64)  # a non-finite state: the step reports it
    cell = max(np.median(extents), 1e-9)
    if not math.isfinite(cell):
        return np.empty((0, 2), dtype=np.int64)
    max_cells = 4.0 * nd + 16.0
    while (width / cell + 1.0) * (height / cell + 1.0) > max_cells:
        cell *= 1.5
    nx = int(width / cell) + 1
    ny = int(height / cell) + 1
    inv_cell = 1.0 / cell

    # cell ranges of every active body that touches the domain
    ranges = np.full((n, 4), -1, dtype=np.int64)
    counts = np.zeros(nx * ny + 1, dtype=np.int64)
    for i in range(n):
        if not active[i]:
            continue
        inside = hitbox[i, 2] >= lo_x and hitbox[i, 0] <= hi_x
        if not (inside and hitbox[i, 3] >= lo_y and hitbox[i, 1] <= hi_y):
            continue  # outside the domain (or not finite)
        x0 = _cell(hitbox[i, 0], lo_x, inv_cell, nx)
        y0 = _cell(hitbox[i, 1], lo_y, inv_cell, ny)
        x1 = _cell(hitbox[i, 2], lo_x, inv_cell, nx)
        y1 = _cell(hitbox[i, 3], lo_y, inv_cell, ny)
        ranges[i, 0] = x0
        ranges[i, 1] = y0
        ranges[i, 2] = x1
        ranges[i, 3] = y1
        for cy in range(y0, y1 + 1):
            for cx in range(x0, x1 + 1):
                counts[cy * nx + cx + 1] += 1
    for c in range(nx * ny):
        counts[c + 1] += counts[c]
    cells = np.empty(counts[nx * ny], dtype=np.int64)
    fill = counts[:-1].copy()
    for i in range(n):
        if ranges[i, 0] < 0:
            continue
        for cy in range(ranges[i, 1], ranges[i, 3] + 1):
            for cx in range(ranges[i, 0], ranges[i, 2] + 1):
                c = cy * nx + cx
                cells[fill[c]] = i
                fill[c] += 1

    keys = np.empty(16 * nd + 16, dtype=np.int64)
    count = 0
    for c in range(nx * ny):
        start = counts[c]
        end = counts[c + 1]
        cx = c % nx
        cy = c // nx
        for p in range(start, end):
            i = cells[p]
            for q in range(p + 1, end):
                j = cells[q]
                if inv_mass[i] == 0.0 and inv_mass[j] == 0.0:
                    continue
                if group[i] != 0 and group[i] == group[j]:
                    continue
                if not _overlap(hitbox, i, j):
                    continue
                # report the pair only in the cell of the intersection's lower corner
                ox = max(ranges[i, 0], ranges[j, 0])
                oy = max(ranges[i, 1], ranges[j, 1])
                if ox != cx or oy != cy:
                    continue
                if count == keys.shape[0]:
                    grown = np.empty(2 * count, dtype=np.int64)
                    grown[:count] = keys
                    keys = grown
                a = min(i, j)
                b = max(i, j)
                keys[count] = a * n + b
                count += 1
    keys = np.sort(keys[:count])
    pairs = np.empty((count, 2), dtype=np.int64)
    for k in range(count):
        pairs[k, 0] = keys[k] // n
        pairs[k, 1] = keys[k] % n
    return pairs
