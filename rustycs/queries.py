"""Questions asked of the world between steps: what a ray meets, what lies under a point, what a box
overlaps (pymunk's segment, point and bounding-box queries; Box2D's ray casts and overlaps).

Each call answers a whole batch in compiled code. The shapes' convex pieces are placed at their bodies'
present poses and binned in a uniform grid of about one cell per piece; a ray walks the grid's cells in
order along its path (Amanatides and Woo) and stops at the first cell that starts beyond its closest hit,
so a ray tests the pieces near its path only. The helpers are inlined into the batch kernels: a call
per piece would count references to every array of its records, which costs more than the test.

A piece is a convex core (none for a circle, two points for a capsule or segment, up to 8 corners)
grown by its radius; rays enter it through a face of the core pushed out by the radius or through a
disc around a corner. A ray that starts inside a shape hits it at fraction 0 with the normal against
its direction. Inactive bodies (removed, escaped) are never found; sensors only with `sensors=True`;
`mask` keeps the shapes whose collision category shares a bit with it.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from rustycs.compiling import inlined
from rustycs.geometry import new_geometry, place_piece
from rustycs.pieces import MAX_VERTICES

MISS = math.inf  # the fraction of a ray that hits nothing


class QueryGrid(NamedTuple):
    """The pieces a query may find, placed at their bodies' poses and binned in cells."""

    box: np.ndarray  # (S, 4) each piece's bounding box: xmin, ymin, xmax, ymax
    eligible: np.ndarray  # (S,) bool: active body, sensor and mask filters passed
    origin: np.ndarray  # (2,) lower corner of the grid
    cell: float  # cell size, m
    nx: int
    ny: int
    start: np.ndarray  # (nx * ny + 1,) cell c's pieces are items[start[c]:start[c + 1]]
    items: np.ndarray  # piece rows, by cell


class RayHits(NamedTuple):
    """Where rays hit, one row per hit (a miss: body and shape -1, fraction inf, point and normal NaN)."""

    body: np.ndarray  # int64: the body hit
    shape: np.ndarray  # int64: the shape hit, an index into `World.shapes`
    point: np.ndarray  # (.., 2) world point of the hit
    normal: np.ndarray  # (.., 2) unit surface normal there, against the ray
    fraction: np.ndarray  # of the way from start to end, 0..1
    distance: np.ndarray  # m from the start


# ------------------------------------------------------------------------------------ the grid


@njit(cache=True)
def _place_all(bodies, shapes, sensors, mask):
    """Every piece at its body's pose, its bounding box (core box grown by its radius), and whether a
    query may find it."""
    n_shapes = shapes.body.shape[0]
    geometry = new_geometry(bodies.x.shape[0], n_shapes, MAX_VERTICES)
    box = np.zeros((n_shapes, 4))
    eligible = np.zeros(n_shapes, np.bool_)
    for j in range(n_shapes):
        b = shapes.body[j]
        eligible[j] = (bodies.active[b] and (sensors or not shapes.sensor[j])
                       and (shapes.category[j] & mask) != 0)
        c, s = math.cos(bodies.angle[b]), math.sin(bodies.angle[b])
        lo_x, lo_y, hi_x, hi_y = place_piece(shapes, j, bodies.x[b, 0], bodies.x[b, 1], c, s, geometry, j)
        r = shapes.radius[j]
        box[j, 0], box[j, 1], box[j, 2], box[j, 3] = lo_x - r, lo_y - r, hi_x + r, hi_y + r
    return geometry, box, eligible


@inlined
def _cell_range(grid_origin, cell, nx, ny, x0, y0, x1, y1):
    """The cells (inclusive, clamped to the grid) a box covers."""
    i0 = min(max(int((x0 - grid_origin[0]) / cell), 0), nx - 1)
    j0 = min(max(int((y0 - grid_origin[1]) / cell), 0), ny - 1)
    i1 = min(max(int((x1 - grid_origin[0]) / cell), 0), nx - 1)
    j1 = min(max(int((y1 - grid_origin[1]) / cell), 0), ny - 1)
    return i0, j0, i1, j1


@njit(cache=True)
def _bin(box, eligible):
    """A grid of about one cell per eligible piece over their boxes, and each cell's pieces."""
    lo_x, lo_y, hi_x, hi_y = math.inf, math.inf, -math.inf, -math.inf
    count = 0
    for j in range(box.shape[0]):
        if eligible[j]:
            count += 1
            lo_x, lo_y = min(lo_x, box[j, 0]), min(lo_y, box[j, 1])
            hi_x, hi_y = max(hi_x, box[j, 2]), max(hi_y, box[j, 3])
    origin = np.array([lo_x, lo_y]) if count else np.zeros(2)
    width, height = (hi_x - lo_x, hi_y - lo_y) if count else (1.0, 1.0)
    cell = max(math.sqrt(max(width * height, 1e-12) / max(count, 1)), max(width, height) / 1024.0, 1e-9)
    nx, ny = int(width / cell) + 1, int(height / cell) + 1
    start = np.zeros(nx * ny + 1, np.int64)
    for j in range(box.shape[0]):
        if eligible[j]:
            i0, j0, i1, j1 = _cell_range(origin, cell, nx, ny, box[j, 0], box[j, 1], box[j, 2], box[j, 3])
            for cj in range(j0, j1 + 1):
                for ci in range(i0, i1 + 1):
                    start[cj * nx + ci + 1] += 1
    for c in range(nx * ny):
        start[c + 1] += start[c]
    fill = start[:-1].copy()
    items = np.zeros(start[-1], np.int64)
    for j in range(box.shape[0]):
        if eligible[j]:
            i0, j0, i1, j1 = _cell_range(origin, cell, nx, ny, box[j, 0], box[j, 1], box[j, 2], box[j, 3])
            for cj in range(j0, j1 + 1):
                for ci in range(i0, i1 + 1):
                    items[fill[cj * nx + ci]] = j
                    fill[cj * nx + ci] += 1
    return QueryGrid(box, eligible, origin, cell, nx, ny, start, items)


# ------------------------------------------------------------------------------------ one piece


@inlined
def _core_distance(px, py, geometry, shapes, j):
    """Distance from a point to piece j's core (0 inside a core of 3 or more corners)."""
    k = shapes.count[j]
    if k == 0:
        return math.hypot(px - geometry.centroid[j, 0], py - geometry.centroid[j, 1])
    verts, normals = geometry.vertices, geometry.normals  # indexed in place: a view per call costs more
    inside = k >= 3
    nearest = math.inf
    for i in range(k if k >= 3 else 1):
        ax, ay = verts[j, i, 0], verts[j, i, 1]
        bx, by = verts[j, (i + 1) % k, 0], verts[j, (i + 1) % k, 1]
        if normals[j, i, 0] * (px - ax) + normals[j, i, 1] * (py - ay) > 0.0:
            inside = False
        ex, ey = bx - ax, by - ay
        t = min(max(((px - ax) * ex + (py - ay) * ey) / max(ex * ex + ey * ey, 1e-300), 0.0), 1.0)
        nearest = min(nearest, math.hypot(px - ax - t * ex, py - ay - t * ey))
    return 0.0 if inside else nearest


@inlined
def _contains(px, py, geometry, shapes, j):
    """Whether piece j holds the point (lines, having no area, hold none)."""
    if shapes.count[j] == 2 and shapes.radius[j] == 0.0:
        return False
    return _core_distance(px, py, geometry, shapes, j) <= shapes.radius[j]


@inlined
def _ray_disc(ox, oy, dx, dy, cx, cy, r):
    """Fraction where o + t d (t in [0, 1]) enters the disc from outside, and the normal there."""
    fx, fy = ox - cx, oy - cy
    a = dx * dx + dy * dy
    b = fx * dx + fy * dy
    c = fx * fx + fy * fy - r * r
    disc = b * b - a * c
    if a == 0.0 or b >= 0.0 or disc < 0.0:
        return MISS, 0.0, 0.0
    t = c / (-b + math.sqrt(disc))  # = (-b - sqrt(disc)) / a, without cancellation
    if not 0.0 <= t <= 1.0:
        return MISS, 0.0, 0.0
    return t, (fx + t * dx) / r, (fy + t * dy) / r


@inlined
def _ray_face(ox, oy, dx, dy, ax, ay, bx, by, nx, ny):
    """Fraction where o + t d crosses the face a-b from its outer side (normal n), and n."""
    den = nx * dx + ny * dy
    if den >= 0.0:
        return MISS
    t = (nx * (ax - ox) + ny * (ay - oy)) / den
    if not 0.0 <= t <= 1.0:
        return MISS
    ex, ey = bx - ax, by - ay
    along = (ox + t * dx - ax) * ex + (oy + t * dy - ay) * ey
    return t if 0.0 <= along <= ex * ex + ey * ey else MISS


@inlined
def ray_piece(ox, oy, dx, dy, geometry, shapes, j):
    """Fraction (0..1, MISS for none) where the ray o + t d first meets piece j, and the normal there."""
    length = math.hypot(dx, dy)
    if _contains(ox, oy, geometry, shapes, j):
        return (0.0, -dx / length, -dy / length) if length > 0.0 else (0.0, 0.0, 0.0)
    k, r = shapes.count[j], shapes.radius[j]
    if k == 0:
        return _ray_disc(ox, oy, dx, dy, geometry.centroid[j, 0], geometry.centroid[j, 1], r)
    verts, normals = geometry.vertices, geometry.normals
    best, best_x, best_y = MISS, 0.0, 0.0
    if r > 0.0:
        for i in range(k):
            t, nx, ny = _ray_disc(ox, oy, dx, dy, verts[j, i, 0], verts[j, i, 1], r)
            if t < best:
                best, best_x, best_y = t, nx, ny
    for i in range(k):
        nx, ny = normals[j, i, 0], normals[j, i, 1]
        i2 = (i + 1) % k
        t = _ray_face(ox, oy, dx, dy, verts[j, i, 0] + r * nx, verts[j, i, 1] + r * ny,
                      verts[j, i2, 0] + r * nx, verts[j, i2, 1] + r * ny, nx, ny)
        if t < best:
            best, best_x, best_y = t, nx, ny
    return best, best_x, best_y


# ------------------------------------------------------------------------------------ batches


@inlined
def _walk(grid, geometry, shapes, ox, oy, dx, dy, ray, stamp, closest, hits, found):
    """Walk one ray's cells in order, testing each piece once. `closest`: stop past the nearest hit and
    return it; else write every hit into `hits` rows from `found` on (as far as they reach). Returns
    (fraction, piece, nx, ny) of the nearest hit and the count of hits."""
    best, best_j, best_x, best_y = MISS, -1, 0.0, 0.0
    if grid.items.shape[0] == 0:
        return best, best_j, best_x, best_y, found
    lo_x, lo_y = grid.origin[0], grid.origin[1]
    hi_x, hi_y = lo_x + grid.nx * grid.cell, lo_y + grid.ny * grid.cell
    t0, t1 = 0.0, 1.0  # the ray's part inside the grid (slabs)
    for o, d, lo, hi in ((ox, dx, lo_x, hi_x), (oy, dy, lo_y, hi_y)):
        if d == 0.0:
            if o < lo or o > hi:
                return best, best_j, best_x, best_y, found
        else:
            ta, tb = (lo - o) / d, (hi - o) / d
            t0, t1 = max(t0, min(ta, tb)), min(t1, max(ta, tb))
    if t0 > t1:
        return best, best_j, best_x, best_y, found
    cell = grid.cell
    ci = min(max(int((ox + t0 * dx - lo_x) / cell), 0), grid.nx - 1)
    cj = min(max(int((oy + t0 * dy - lo_y) / cell), 0), grid.ny - 1)
    step_i, step_j = (1 if dx > 0.0 else -1), (1 if dy > 0.0 else -1)
    next_x = (lo_x + (ci + 1 if dx > 0.0 else ci) * cell - ox) / dx if dx != 0.0 else math.inf
    next_y = (lo_y + (cj + 1 if dy > 0.0 else cj) * cell - oy) / dy if dy != 0.0 else math.inf
    delta_x = cell / abs(dx) if dx != 0.0 else math.inf
    delta_y = cell / abs(dy) if dy != 0.0 else math.inf
    while True:
        c = cj * grid.nx + ci
        for k in range(grid.start[c], grid.start[c + 1]):
            j = grid.items[k]
            if stamp[j] == ray:
                continue
            stamp[j] = ray
            t, nx, ny = ray_piece(ox, oy, dx, dy, geometry, shapes, j)
            if t == MISS:
                continue
            if not closest:
                if found < hits.shape[0]:
                    hits[found, 0], hits[found, 1], hits[found, 2] = ray, j, t
                    hits[found, 3], hits[found, 4] = nx, ny
                found += 1
            if t < best or (t == best and j < best_j):
                best, best_j, best_x, best_y = t, j, nx, ny
        leave = min(next_x, next_y)
        if leave > t1 or (closest and best <= leave):
            break
        if next_x < next_y:
            ci += step_i
            next_x += delta_x
        else:
            cj += step_j
            next_y += delta_y
        if not (0 <= ci < grid.nx and 0 <= cj < grid.ny):
            break
    return best, best_j, best_x, best_y, found


@njit(cache=True)
def cast_rays(bodies, shapes, starts, ends, sensors, mask):
    """The nearest hit of each ray start -> end: (R, 4) rows of fraction (MISS: none), piece, normal."""
    geometry, box, eligible = _place_all(bodies, shapes, sensors, mask)
    grid = _bin(box, eligible)
    stamp = np.full(shapes.body.shape[0], -1, np.int64)
    out = np.empty((starts.shape[0], 4))
    no_hits = np.zeros((0, 5))
    for ray in range(starts.shape[0]):
        ox, oy = starts[ray, 0], starts[ray, 1]
        t, j, nx, ny, _ = _walk(grid, geometry, shapes, ox, oy, ends[ray, 0] - ox, ends[ray, 1] - oy, ray,
                                stamp, True, no_hits, 0)
        out[ray, 0], out[ray, 1], out[ray, 2], out[ray, 3] = t, j, nx, ny
    return out


@njit(cache=True)
def cast_rays_all(bodies, shapes, starts, ends, sensors, mask, capacity):
    """Every hit of each ray: rows of ray, piece, fraction, normal (at most `capacity`), and their count
    (more than `capacity`: call again with that much room)."""
    geometry, box, eligible = _place_all(bodies, shapes, sensors, mask)
    grid = _bin(box, eligible)
    stamp = np.full(shapes.body.shape[0], -1, np.int64)
    hits = np.empty((capacity, 5))
    found = 0
    for ray in range(starts.shape[0]):
        ox, oy = starts[ray, 0], starts[ray, 1]
        found = _walk(grid, geometry, shapes, ox, oy, ends[ray, 0] - ox, ends[ray, 1] - oy, ray, stamp,
                      False, hits, found)[4]
    return hits, found


@njit(cache=True)
def pieces_at(bodies, shapes, points, sensors, mask):
    """Per point, the first piece (in shape order) that holds it, or -1."""
    geometry, box, eligible = _place_all(bodies, shapes, sensors, mask)
    grid = _bin(box, eligible)
    out = np.full(points.shape[0], -1, np.int64)
    for p in range(points.shape[0]):
        px, py = points[p, 0], points[p, 1]
        ci, cj, _, _ = _cell_range(grid.origin, grid.cell, grid.nx, grid.ny, px, py, px, py)
        c = cj * grid.nx + ci
        for k in range(grid.start[c], grid.start[c + 1]):
            j = grid.items[k]
            if (out[p] < 0 or j < out[p]) and box[j, 0] <= px <= box[j, 2] and box[j, 1] <= py <= box[j, 3]:
                if _contains(px, py, geometry, shapes, j):
                    out[p] = j
    return out


@njit(cache=True)
def pieces_overlapping(bodies, shapes, lower, upper, sensors, mask):
    """The pieces whose bounding boxes overlap the box lower..upper, in order."""
    _, box, eligible = _place_all(bodies, shapes, sensors, mask)
    found = np.zeros(box.shape[0], np.bool_)
    for j in range(box.shape[0]):
        found[j] = (eligible[j] and box[j, 0] <= upper[0] and lower[0] <= box[j, 2] and box[j, 1] <= upper[1]
                    and lower[1] <= box[j, 3])
    return np.nonzero(found)[0]


# ------------------------------------------------------------------------------------ the World's side


def _points(value, what: str) -> tuple[np.ndarray, bool]:
    """(P, 2) float64 points and whether one point (shape (2,)) was given."""
    points = np.asarray(value, dtype=np.float64)
    one = points.ndim == 1
    points = np.ascontiguousarray(points.reshape(-1, 2))
    if not np.all(np.isfinite(points)):
        raise ValueError(f"{what} must be finite")
    return points, one


class WorldQueries:
    """The World's query methods (mixed into `World`): every shape kind, batched in one compiled call."""

    def _query_inputs(self):
        inputs = self._kernel_inputs()
        return inputs.bodies, inputs.shapes

    def _hits(self, fraction, piece, normal, starts, ends) -> RayHits:
        """Rows of hits as RayHits, pieces turned into their bodies and shapes as given."""
        piece = piece.astype(np.int64)
        hit = piece >= 0
        body = np.full(len(piece), -1, np.int64)
        shape = np.full(len(piece), -1, np.int64)
        body[hit] = self._kernel_inputs().shapes.body[piece[hit]]
        shape[hit] = np.asarray(self._piece_shapes, dtype=np.int64)[piece[hit]]
        along = np.where(hit, fraction, 0.0)
        point = np.where(hit[:, None], starts + along[:, None] * (ends - starts), np.nan)
        distance = np.where(hit, along * np.hypot(*(ends - starts).T), np.inf)
        return RayHits(body, shape, point, np.where(hit[:, None], normal, np.nan), fraction, distance)

    def ray_cast(self, start, end, *, sensors: bool = False, mask: int = -1) -> RayHits:
        """The nearest hit of the ray from `start` to `end` (points (2,), or (R, 2) for R rays in one
        call): body, shape, point, normal, fraction of the way, distance; a miss has body -1. One ray
        gives one row's values (scalars and (2,) arrays)."""
        starts, one = _points(start, "ray starts")
        ends, _ = _points(end, "ray ends")
        if starts.shape != ends.shape:
            raise ValueError("give as many ray ends as starts")
        bodies, shapes = self._query_inputs()
        out = cast_rays(bodies, shapes, starts, ends, sensors, int(mask))
        hits = self._hits(out[:, 0], out[:, 1], out[:, 2:4], starts, ends)
        return RayHits(*(column[0] for column in hits)) if one else hits

    def ray_cast_all(self, start, end, *, sensors: bool = False,
                     mask: int = -1) -> tuple[np.ndarray, RayHits]:
        """Every shape piece each ray from `start` to `end` enters: (ray, hits), one row per hit, sorted by
        ray, then by fraction. A concave polygon or a chain is split into convex pieces, so a ray may
        report a hit on each piece it enters."""
        starts, one = _points(start, "ray starts")
        ends, _ = _points(end, "ray ends")
        if starts.shape != ends.shape:
            raise ValueError("give as many ray ends as starts")
        bodies, shapes = self._query_inputs()
        capacity = 4 * len(starts)
        while True:
            rows, found = cast_rays_all(bodies, shapes, starts, ends, sensors, int(mask), capacity)
            if found <= capacity:
                break
            capacity = found
        rows = rows[:found]
        rows = rows[np.lexsort((rows[:, 1], rows[:, 2], rows[:, 0]))]
        ray = rows[:, 0].astype(np.int64)
        return ray, self._hits(rows[:, 2], rows[:, 1], rows[:, 3:5], starts[ray], ends[ray])

    def point_query(self, points, *, sensors: bool = False, mask: int = -1):
        """The body whose shapes hold each point (the first in shape order), -1 where none does: an int for
        one point (2,), an int64 array for (P, 2) points. Segments and chains hold no point."""
        points, one = _points(points, "points")
        bodies, shapes = self._query_inputs()
        piece = pieces_at(bodies, shapes, points, sensors, int(mask))
        body = np.full(len(piece), -1, np.int64)
        body[piece >= 0] = shapes.body[piece[piece >= 0]]
        return int(body[0]) if one else body

    def aabb_query(self, lower, upper, *, sensors: bool = False, mask: int = -1) -> np.ndarray:
        """The bodies (sorted, each once) with a shape whose bounding box overlaps the box lower..upper, as
        Box2D's b2World_OverlapAABB finds them."""
        (lo,), _ = _points(lower, "lower")
        (hi,), _ = _points(upper, "upper")
        bodies, shapes = self._query_inputs()
        pieces = pieces_overlapping(bodies, shapes, lo, hi, sensors, int(mask))
        return np.unique(shapes.body[pieces])
