"""Broad phase: candidate pairs of shapes from overlapping hitboxes, through a uniform grid.

The pairs are found for fat hitboxes (each hitbox grown by `FAT_MARGIN`) and kept while every shape's
hitbox stays inside its fat one and no body is switched on or off: a resting pile then needs no
broad phase at all, as in Box2D's tree of fat boxes. When a few shapes leave their fat hitboxes, only
theirs are found again, through the last search's grid (`refresh_pairs`), as Box2D's tree moves only
the proxies that left their boxes. A pair of fat boxes that do not touch as hitboxes
gives no contact in the narrow phase, so the contacts are those of the hitboxes' pairs, bit for bit.

The grid covers the hitboxes of the shapes of dynamic bodies only and its cell size follows their
median size, so the cost grows near-linearly with evenly spread bodies. Shapes of static and kinematic
bodies are inserted clipped to that domain, so a huge floor costs one row of cells. A pair is reported
once, by the cell holding the lower corner of the two hitboxes' intersection. Pairs come out sorted by
(a, b), shape rows: the order the solver relies on for determinism. Shapes of one body, sensors, and
shapes that the collision filter keeps apart are never paired. The buffers are the caller's and are
reused tick after tick, so a tick allocates nothing once they have grown to the scene.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from rustycs.compiling import inlined, tick_kernel
from rustycs.constants import FAT_MARGIN, MOST_DISPLACED
from rustycs.sorting import sort_run


class Pairs(NamedTuple):
    """The candidate pairs, the fat hitboxes and active flags they were found for, and scratch."""

    keys: np.ndarray  # int64 (a << SHAPE_BITS) | b, sorted, a < b; the first count[0] are in use
    count: np.ndarray  # int64 (1,); -1: to be found
    fat_hitbox: np.ndarray  # (S, 4); nan until the pairs are first found
    fat_active: np.ndarray  # (S,) bool
    grid: np.ndarray  # int64 scratch of grid_scratch_size(S)
    extents: np.ndarray  # (S,) scratch
    cells: np.ndarray  # int64 scratch: the grid's cell entries
    inert: np.ndarray  # bool (1,): no two shapes may ever touch (`never_collide`): no pairs, ever
    # the last search's grid, kept with the cell ranges and cell entries in `grid` and `cells`
    frame: np.ndarray  # (5,) its domain's lower x, y, upper x, y, and 1 / cell size
    layout: np.ndarray  # int64 (3,): cells along x (0: no grid), along y, shapes displaced since the search
    stale: np.ndarray  # int8 (S,): IN_GRID, DISPLACED (its grid entries stale) or MOVED (in this refresh)
    displaced: np.ndarray  # int64 (S,): the displaced shapes, by their fat hitboxes' lower x
    found: np.ndarray  # int64 scratch: the keys of a refresh's new pairs


IN_GRID, DISPLACED, MOVED = 0, 1, 2  # of `Pairs.stale`


@njit(cache=True)
def never_collide(shapes):
    """Whether the collision filters keep every two shapes apart: all but the sensors share one non-zero
    group (a cloud of bodies that only feel forces, like bench S6's orbits, whose broad phase found no
    pair in 9.7 of its 18 us a tick)."""
    group = 0
    for j in range(shapes.group.shape[0]):
        if shapes.sensor[j]:
            continue
        if shapes.group[j] == 0 or (group != 0 and shapes.group[j] != group):
            return False
        group = shapes.group[j]
    return True


@njit(cache=True)
def new_pairs(shapes, capacity):
    """Room for `capacity` pairs of the shapes, none found yet."""
    n = shapes.body.shape[0]
    inert = np.full(1, never_collide(shapes), np.bool_)
    count = np.full(1, 0 if inert[0] else -1, np.int64)
    return Pairs(np.empty(capacity, np.int64), count, np.full((n, 4), np.nan), np.zeros(n, np.bool_),
                 np.empty(grid_scratch_size(n), np.int64), np.empty(n), np.empty(capacity, np.int64), inert,
                 np.zeros(5), np.zeros(3, np.int64), np.zeros(n, np.int8), np.empty(n, np.int64),
                 np.empty(_found_size(capacity), np.int64))


@njit(cache=True)
def _found_size(capacity):
    """Room for a refresh's new pairs, with room for `capacity` pairs in all (more: a whole search)."""
    return capacity // 2 + 64


@njit(cache=True)
def grown_pairs(pairs, capacity, cells):
    """The pairs with room for `capacity` keys and `cells` grid entries (to be found again)."""
    keys = np.empty(max(2 * capacity, pairs.keys.shape[0]), np.int64)
    entries = np.empty(max(2 * cells, pairs.cells.shape[0]), np.int64)
    return Pairs(keys, pairs.count, pairs.fat_hitbox, pairs.fat_active, pairs.grid, pairs.extents, entries,
                 pairs.inert, pairs.frame, pairs.layout, pairs.stale, pairs.displaced,
                 np.empty(_found_size(keys.shape[0]), np.int64))


@inlined
def hitboxes_overlap(hitbox, i, j):
    return (hitbox[i, 0] <= hitbox[j, 2] and hitbox[j, 0] <= hitbox[i, 2]
            and hitbox[i, 1] <= hitbox[j, 3] and hitbox[j, 1] <= hitbox[i, 3])


@inlined
def hitbox_gap(hitbox, i, j):
    """The widest gap between hitboxes i and j along x or y: at most the distance of the boxes."""
    return max(hitbox[j, 0] - hitbox[i, 2], hitbox[i, 0] - hitbox[j, 2], hitbox[j, 1] - hitbox[i, 3],
               hitbox[i, 1] - hitbox[j, 3])


@njit(cache=True)
def _cell(value, origin, inv_cell, count):
    """Grid index of a coordinate, clamped in floating point so that far bodies cannot overflow."""
    return int(min(max((value - origin) * inv_cell, 0.0), count - 1.0))


@inlined
def _inside(fat, hitbox, j):
    """Whether hitbox j lies inside fat hitbox j."""
    return (fat[j, 0] <= hitbox[j, 0] and fat[j, 1] <= hitbox[j, 1] and hitbox[j, 2] <= fat[j, 2]
            and hitbox[j, 3] <= fat[j, 3])


@inlined
def _cell_range(fat, i, frame, nx, ny, ranges):
    """Write shape i's range of grid cells (x0, y0, x1, y1) for its fat hitbox, or x0 = -1 where the
    hitbox misses the grid's domain (or is not finite)."""
    lo_x, lo_y, hi_x, hi_y, inv_cell = frame[0], frame[1], frame[2], frame[3], frame[4]
    ranges[4 * i] = -1
    if not (fat[i, 2] >= lo_x and fat[i, 0] <= hi_x and fat[i, 3] >= lo_y and fat[i, 1] <= hi_y):
        return
    ranges[4 * i] = _cell(fat[i, 0], lo_x, inv_cell, nx)
    ranges[4 * i + 1] = _cell(fat[i, 1], lo_y, inv_cell, ny)
    ranges[4 * i + 2] = _cell(fat[i, 2], lo_x, inv_cell, nx)
    ranges[4 * i + 3] = _cell(fat[i, 3], lo_y, inv_cell, ny)


@inlined
def pairs_hold(bodies, shapes, geometry, pairs):
    """Whether the pairs found for the fat hitboxes still hold: they were found (count >= 0), no body
    was switched on or off, and every active shape's hitbox lies inside its fat one (a non-finite
    hitbox does not)."""
    hitbox, fat, fat_active = geometry.hitbox, pairs.fat_hitbox, pairs.fat_active
    active, first, count, asleep = bodies.active, bodies.first_shape, bodies.shape_count, bodies.asleep
    if pairs.inert[0]:
        return True
    if pairs.count[0] < 0:
        return False
    for i in range(active.shape[0]):
        on = active[i]
        for j in range(first[i], first[i] + count[i]):
            if on != fat_active[j]:
                return False
            if on and not asleep[i] and not _inside(fat, hitbox, j):
                return False
    return True


@tick_kernel
def fatten(bodies, shapes, geometry, pairs):
    """The fat hitboxes the pairs are found for, and the active flags they hold for."""
    hitbox, fat, fat_active, active, body = (geometry.hitbox, pairs.fat_hitbox, pairs.fat_active,
                                             bodies.active, shapes.body)
    for i in range(hitbox.shape[0]):
        _fatten_shape(hitbox, fat, i)
        fat_active[i] = active[body[i]]


@inlined
def _fatten_shape(hitbox, fat, i):
    """Shape i's fat hitbox: its hitbox grown by the margin."""
    fat[i, 0] = hitbox[i, 0] - FAT_MARGIN
    fat[i, 1] = hitbox[i, 1] - FAT_MARGIN
    fat[i, 2] = hitbox[i, 2] + FAT_MARGIN
    fat[i, 3] = hitbox[i, 3] + FAT_MARGIN


@inlined
def filters_agree(shapes, i, j):
    """Whether the collision filters of shapes i and j let them touch: no shared non-zero group, each
    one's category in the other's mask."""
    group = shapes.group
    if group[i] != 0 and group[i] == group[j]:
        return False
    return (shapes.category[i] & shapes.mask[j]) != 0 and (shapes.category[j] & shapes.mask[i]) != 0


@inlined
def may_collide(shapes, bodies, joints, joint_filter, i, j):
    """Whether shapes i and j may touch: of two bodies, at least one movable, not held apart by an
    active joint, neither a sensor, and the filters agree (no shared non-zero group; each one's category
    in the other's mask)."""
    a = shapes.body[i]
    b = shapes.body[j]
    if a == b or (bodies.inv_mass[a] == 0.0 and bodies.inv_mass[b] == 0.0):
        return False
    if shapes.sensor[i] or shapes.sensor[j] or not filters_agree(shapes, i, j):
        return False
    for k in range(joint_filter.first[a], joint_filter.first[a + 1]):
        if joint_filter.partner[k] == b and joints.active[joint_filter.joint[k]]:
            return False
    return True


SHAPE_BITS = 27  # a pair's key: (a << SHAPE_BITS) | b, so that keys sort by (a, b)
SHAPE_MASK = (1 << SHAPE_BITS) - 1


@inlined
def _pair_key(i, j):
    """The key of the pair of shapes i and j, the lower first."""
    return (min(i, j) << SHAPE_BITS) | max(i, j)


@inlined
def _pairable(shapes, bodies, joints, joint_filter, fat, i, j):
    """Whether shapes i and j are a candidate pair: their fat hitboxes overlap and they `may_collide`."""
    return hitboxes_overlap(fat, i, j) and may_collide(shapes, bodies, joints, joint_filter, i, j)


@inlined
def _add_found(shapes, bodies, joints, joint_filter, fat, i, j, found, n_found):
    """Append the pair of shapes i and j to the `n_found` keys in `found` when they are a candidate pair
    (`_pairable`); returns the keys then found, or -1 when `found` is full."""
    if not _pairable(shapes, bodies, joints, joint_filter, fat, i, j):
        return n_found
    if n_found == found.shape[0]:
        return -1
    found[n_found] = _pair_key(i, j)
    return n_found + 1


@inlined
def _reported_here(ranges, i, j, cx, cy):
    """Whether cell (cx, cy) reports the pair of shapes i and j: the one of their cell ranges'
    intersection's lower corner, so that a pair is reported once."""
    return max(ranges[4 * i], ranges[4 * j]) == cx and max(ranges[4 * i + 1], ranges[4 * j + 1]) == cy


@njit(cache=True)
def grid_scratch_size(n):
    """Integers of scratch `find_pairs` needs for n shapes: cell ranges, moving shapes, cell counts."""
    return 13 * n + 33


@inlined
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
def find_pairs(bodies, shapes, joints, joint_filter, pairs):
    """Candidate pairs as sorted keys (a << SHAPE_BITS) | b in pairs.keys, a < b, that `may_collide`,
    for the fat hitboxes: the grid (`make_grid`), then every shape's partners (`partners`).

    Returns (pair count, cell entries): when either exceeds its buffer (`keys`, `cells`), the pairs
    were not all written, and the caller grows the buffers and calls again.
    """
    entries = make_grid(bodies, shapes, pairs)
    if pairs.layout[0] == 0:
        return 0, entries
    return partners(bodies, shapes, joints, joint_filter, pairs, 0, pairs.fat_hitbox.shape[0], pairs.keys,
                    0), entries


@inlined
def make_grid(bodies, shapes, pairs):
    """The grid of the fat hitboxes (cell ranges, cell starts and entries in `pairs`); returns its cell
    entries. The grid is whole when layout[0] (cells along x) is set: not when there is no dynamic shape,
    a hitbox is not finite, or the entries exceed `cells`."""
    hitbox, grid, extents, cells = pairs.fat_hitbox, pairs.grid, pairs.extents, pairs.cells
    inv_mass, active, body = bodies.inv_mass, bodies.active, shapes.body
    layout, stale, displaced = pairs.layout, pairs.stale, pairs.displaced
    n = hitbox.shape[0]
    for k in range(layout[2]):  # every shape in the grid about to be made
        stale[displaced[k]] = IN_GRID
    layout[0] = 0  # no grid to refresh until this one is whole
    layout[2] = 0
    dynamic = grid[:n]
    nd = 0
    for i in range(n):
        if active[body[i]] and inv_mass[body[i]] > 0.0:
            dynamic[nd] = i
            nd += 1
    if nd == 0:
        return 0
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
        return 0  # a non-finite state: the step reports it
    # the cell size only decides speed, never which pairs are found
    cell = max(_select(extents[:nd], nd // 2), 1e-9)
    # a cell more on every side: dynamic shapes that leave their fat hitboxes stay in the domain a while,
    # where a refresh finds their pairs in this grid (the fixed shapes by the domain are in it)
    lo_x -= cell
    lo_y -= cell
    hi_x += cell
    hi_y += cell
    width = hi_x - lo_x
    height = hi_y - lo_y
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
    frame = pairs.frame
    frame[0], frame[1], frame[2], frame[3], frame[4] = lo_x, lo_y, hi_x, hi_y, inv_cell
    for i in range(n):
        ranges[4 * i] = -1
        if not active[body[i]]:
            continue
        _cell_range(hitbox, i, frame, nx, ny, ranges)
        if ranges[4 * i] < 0:
            continue  # outside the domain (or not finite)
        for cy in range(ranges[4 * i + 1], ranges[4 * i + 3] + 1):
            for cx in range(ranges[4 * i], ranges[4 * i + 2] + 1):
                counts[cy * nx + cx + 1] += 1
    for c in range(n_cells):
        counts[c + 1] += counts[c]
    entries = counts[n_cells]
    if entries > cells.shape[0]:
        return entries
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
    layout[0] = nx  # the grid is whole: a refresh may use it
    layout[1] = ny
    return entries


@inlined
def partners(bodies, shapes, joints, joint_filter, pairs, first, last, out, start):
    """The keys of the pairs of shapes first .. last - 1 with their partners of higher index, in the grid
    of `make_grid`, written into `out` from `start` (as many as fit) in key order; returns how many there
    are. Each shape's pairs come from the grid alone, so that ranges of shapes may be searched apart
    (`rustycs.threads`) and joined in order."""
    hitbox, grid, cells = pairs.fat_hitbox, pairs.grid, pairs.cells
    n = hitbox.shape[0]
    nx, ny = pairs.layout[0], pairs.layout[1]
    ranges = grid[n:5 * n]
    counts = grid[5 * n:5 * n + nx * ny + 1]
    # each shape's partners of higher index, sorted as a run of their own: the keys come out sorted by
    # (a, b) with no sort of the whole list
    count = start
    for i in range(first, last):
        if ranges[4 * i] < 0:
            continue
        run = count
        for cy in range(ranges[4 * i + 1], ranges[4 * i + 3] + 1):
            for cx in range(ranges[4 * i], ranges[4 * i + 2] + 1):
                c = cy * nx + cx
                # a cell lists its bodies in index order: walk down from the top to the first j <= i
                for p in range(counts[c + 1] - 1, counts[c] - 1, -1):
                    j = cells[p]
                    if j <= i:
                        break
                    if not _reported_here(ranges, i, j, cx, cy):
                        continue
                    if not _pairable(shapes, bodies, joints, joint_filter, hitbox, i, j):
                        continue
                    if count < out.shape[0]:
                        out[count] = _pair_key(i, j)
                    count += 1
        sort_run(out, run, min(count, out.shape[0]))
    return count - start


@tick_kernel
def refresh_pairs(bodies, shapes, joints, joint_filter, geometry, pairs):
    """Find again only the pairs of the shapes whose hitboxes left their fat ones, when they are few:
    returns False where the whole search (`fatten`, `find_pairs`) is needed instead. Those shapes get new
    fat hitboxes and are displaced: their entries in the last search's grid are stale, so each finds its
    partners among the shapes still in the grid through the cells of its new fat hitbox, and among the
    displaced ones by a sweep along x; their old pairs are dropped and the new ones merged in, sorted.
    The pairs are then those of the fat hitboxes, as a whole search finds them. A whole search is needed
    when the pairs are to be found, a body was switched on or off, a dynamic shape left the grid's
    domain, more than `MOST_DISPLACED` of the shapes would be displaced, or a buffer is too small."""
    hitbox, fat, fat_active, stale, displaced = (geometry.hitbox, pairs.fat_hitbox, pairs.fat_active,
                                                 pairs.stale, pairs.displaced)
    layout, frame, grid, cells, keys, found = (pairs.layout, pairs.frame, pairs.grid, pairs.cells,
                                               pairs.keys, pairs.found)
    active, first, count, asleep, inv_mass = (bodies.active, bodies.first_shape, bodies.shape_count,
                                              bodies.asleep, bodies.inv_mass)
    n = fat.shape[0]
    if pairs.count[0] < 0 or layout[0] == 0:  # to be found, or no whole grid (no dynamic shape)
        return False
    limit = int(MOST_DISPLACED * n) + 16
    n_displaced = layout[2]
    for i in range(active.shape[0]):
        on = active[i]
        for j in range(first[i], first[i] + count[i]):
            if on != fat_active[j]:
                layout[2] = n_displaced
                return False
            if on and not asleep[i] and not _inside(fat, hitbox, j):
                if stale[j] == IN_GRID:
                    if n_displaced == limit:
                        layout[2] = n_displaced
                        return False
                    displaced[n_displaced] = j
                    n_displaced += 1
                stale[j] = MOVED
    layout[2] = n_displaced
    nx, ny = layout[0], layout[1]
    ranges = grid[n:5 * n]
    for k in range(n_displaced):
        j = displaced[k]
        if stale[j] != MOVED:
            continue
        _fatten_shape(hitbox, fat, j)
        if inv_mass[shapes.body[j]] > 0.0 and not (frame[0] <= fat[j, 0] and fat[j, 2] <= frame[2]
                                                   and frame[1] <= fat[j, 1] and fat[j, 3] <= frame[3]):
            return False  # a dynamic shape beyond the domain could meet a fixed one the grid left out
        _cell_range(fat, j, frame, nx, ny, ranges)
    # the displaced in order of their fat hitboxes' lower x (by insertion: nearly in order already)
    for k in range(1, n_displaced):
        j = displaced[k]
        q = k
        while q > 0 and fat[displaced[q - 1], 0] > fat[j, 0]:
            displaced[q] = displaced[q - 1]
            q -= 1
        displaced[q] = j
    kept = 0
    for k in range(pairs.count[0]):
        a = keys[k] >> SHAPE_BITS
        b = keys[k] & SHAPE_MASK
        if stale[a] != MOVED and stale[b] != MOVED:
            keys[kept] = keys[k]
            kept += 1
    n_found = 0
    starts = grid[5 * n:5 * n + nx * ny + 1]
    for k in range(n_displaced):
        i = displaced[k]
        if stale[i] != MOVED or ranges[4 * i] < 0:
            continue
        for cy in range(ranges[4 * i + 1], ranges[4 * i + 3] + 1):
            for cx in range(ranges[4 * i], ranges[4 * i + 2] + 1):
                c = cy * nx + cx
                for p in range(starts[c], starts[c + 1]):
                    j = cells[p]
                    if stale[j] != IN_GRID:
                        continue  # displaced: found by the sweep below
                    if not _reported_here(ranges, i, j, cx, cy):
                        continue
                    n_found = _add_found(shapes, bodies, joints, joint_filter, fat, i, j, found, n_found)
                    if n_found < 0:
                        return False
    for k in range(n_displaced):
        i = displaced[k]
        for q in range(k + 1, n_displaced):
            j = displaced[q]
            if fat[j, 0] > fat[i, 2]:
                break
            if stale[i] != MOVED and stale[j] != MOVED:
                continue  # kept from before
            n_found = _add_found(shapes, bodies, joints, joint_filter, fat, i, j, found, n_found)
            if n_found < 0:
                return False
    total = kept + n_found
    if total > keys.shape[0]:
        return False
    sort_run(found, 0, n_found)
    a = kept - 1
    b = n_found - 1
    for w in range(total - 1, -1, -1):  # merged from the back, in place
        if b < 0:
            break
        if a >= 0 and keys[a] > found[b]:
            keys[w] = keys[a]
            a -= 1
        else:
            keys[w] = found[b]
            b -= 1
    pairs.count[0] = total
    for k in range(n_displaced):
        stale[displaced[k]] = DISPLACED
    return True
