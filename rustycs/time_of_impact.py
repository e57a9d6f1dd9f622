"""Time of impact: when, within a tick, two moving convex pieces first come within touching distance.

The narrow phase keeps a pair's speculative points within each body's travel of the tick, so that a
fast body is caught before it can pass through anything. Those points alone would also stop bodies
that only pass close by: the features nearest at the start of the tick are not those that meet, and
the gap along their normal closes although the bodies never touch (a circle passing 1 cm over a
corner at 5 m/s kept 0.80 of its speed and turned 18 degrees). So for a pair whose relative motion in
the tick exceeds the speculative distance, this sweep decides: no impact within the tick, no contact;
an impact at time t, the contact of the features that meet there.

The sweep is conservative advancement (Mirtich): at time t place both pieces as their bodies move with
constant velocities (turning about their centres of mass), take the distance d of their cores less
their radii, and advance by d over the fastest that d can shrink: the approach of the bodies along the
direction between the closest points plus each body's |w| times its extent (the approach of the closest
points alone let two tumbling capsules of the capsule pile step past their impact into a 6.5 cm
overlap). The steps never overshoot the impact, and stop where d stops shrinking.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from rustycs.compiling import inlined
from rustycs.geometry import Geometry, new_geometry, place_core, place_faces
from rustycs.pieces import MAX_VERTICES

ADVANCE_STEPS = 32  # conservative advancement steps at most; a pair still undecided counts as an impact


class Sweep(NamedTuple):
    """Scratch of a sweep: the two pieces' kinds and sizes (rows 0 and 1) and their placed geometry."""

    kind: np.ndarray  # (2,) int64
    radius: np.ndarray  # (2,)
    count: np.ndarray  # (2,) int64
    open_ends: np.ndarray  # (2,) int64
    geometry: Geometry


@njit(cache=True)
def new_sweep():
    return Sweep(np.zeros(2, np.int64), np.zeros(2), np.zeros(2, np.int64), np.zeros(2, np.int64),
                 new_geometry(2, 2, MAX_VERTICES))


@inlined
def _point_segment(px, py, ax, ay, bx, by):
    """The point of segment a b closest to p, and its squared distance from p."""
    ex, ey = bx - ax, by - ay
    length2 = ex * ex + ey * ey
    f = 0.0
    if length2 > 0.0:
        f = min(max(((px - ax) * ex + (py - ay) * ey) / length2, 0.0), 1.0)
    cx, cy = ax + f * ex, ay + f * ey
    return cx, cy, (px - cx) * (px - cx) + (py - cy) * (py - cy)


@inlined
def _core_vertex(geometry, row, count, k):
    """Vertex k of a placed core: a circle's core is its centre."""
    if count == 0:
        return geometry.centroid[row, 0], geometry.centroid[row, 1]
    return geometry.vertices[row, k, 0], geometry.vertices[row, k, 1]


@inlined
def _nearest(geometry, row, count, other, other_count, best, ax, ay, bx, by, flip):
    """The closest points of the vertices of core `row` to the edges (or the one vertex) of core
    `other`, improving on squared distance `best` with points a (on the first core) and b (on the
    second)."""
    vertices = max(count, 1)
    edges = other_count if other_count > 2 else other_count - 1
    for k in range(vertices):
        px, py = _core_vertex(geometry, row, count, k)
        if edges <= 0:  # the other core is one point
            cx, cy = _core_vertex(geometry, other, other_count, 0)
            d2 = (px - cx) * (px - cx) + (py - cy) * (py - cy)
            if d2 < best:
                best = d2
                ax, ay, bx, by = (cx, cy, px, py) if flip else (px, py, cx, cy)
            continue
        for e in range(edges):
            e2 = e + 1 if e + 1 < other_count else 0
            qx, qy = geometry.vertices[other, e, 0], geometry.vertices[other, e, 1]
            rx, ry = geometry.vertices[other, e2, 0], geometry.vertices[other, e2, 1]
            cx, cy, d2 = _point_segment(px, py, qx, qy, rx, ry)
            if d2 < best:
                best = d2
                ax, ay, bx, by = (cx, cy, px, py) if flip else (px, py, cx, cy)
    return best, ax, ay, bx, by


@inlined
def core_distance(geometry, a, count_a, b, count_b):
    """Distance between the placed cores in rows a and b of `geometry` (apart: every pair the sweep
    places is), and their closest points. Convex cores that do not overlap are closest between a vertex
    of one and an edge of the other."""
    best, ax, ay, bx, by = _nearest(geometry, a, count_a, b, count_b, math.inf, 0.0, 0.0, 0.0, 0.0, False)
    best, ax, ay, bx, by = _nearest(geometry, b, count_b, a, count_a, best, ax, ay, bx, by, True)
    return math.sqrt(best), ax, ay, bx, by


class Motion(NamedTuple):
    """How a body moves through a sweep: its centre of mass and angle at the sweep's start, its constant
    velocities, and the farthest point of its shapes' cores from its centre of mass."""

    x: float
    y: float
    angle: float
    vx: float
    vy: float
    w: float
    extent: float


@inlined
def motion_now(bodies, i):
    """Body i as it moves at the start of a tick."""
    x, v = bodies.x, bodies.v
    return Motion(x[i, 0], x[i, 1], bodies.angle[i], v[i, 0], v[i, 1], bodies.w[i], bodies.extent[i])


@inlined
def place_pair(shapes, sa, sb, motion_a, motion_b, t, faces, sweep):
    """Place the cores of shapes sa and sb into the sweep's rows 0 and 1 where their bodies' motions take
    them after t seconds, and with `faces` their normals and chain ghosts too (what a manifold needs)."""
    for row in range(2):
        j, m = (sa, motion_a) if row == 0 else (sb, motion_b)
        turn = m.angle + m.w * t
        px, py, c, s = m.x + m.vx * t, m.y + m.vy * t, math.cos(turn), math.sin(turn)
        place_core(shapes, j, px, py, c, s, sweep.geometry, row)
        if faces:
            place_faces(shapes, j, px, py, c, s, sweep.geometry, row)


@inlined
def time_of_impact(shapes, sa, sb, motion_a, motion_b, duration, reach, start, sweep):
    """The first time in [0, duration] at which shapes sa and sb come within `reach` of touching, their
    bodies moving as `motion_a` and `motion_b` say; -1 when they do not. `start` is a geometry that holds
    both where they are at time 0 in their own rows (the tick's, in the narrow phase), or None: then the
    sweep places them. After an impact at t > 0 the sweep's rows hold them placed at t, faces and all.

    Each step bounds how fast the gap can shrink along the direction u between the closest points: for
    a fixed u, the separation of the two cores along u is at most their distance, is equal to it now, and
    shrinks no faster than the bodies approach along u plus both bodies' turning (|w| extent: any point
    of a core turns no faster), so the step to that bound's zero never passes the impact. (|v| plus the
    turning, the bound of any direction, took 4,821 steps where this takes 2,935 for the 1,465 pairs
    swept in a tick of the compound pile.)"""
    for row in range(2):
        j = sa if row == 0 else sb
        sweep.kind[row] = shapes.kind[j]
        sweep.radius[row] = shapes.radius[j]
        sweep.count[row] = shapes.count[j]
        sweep.open_ends[row] = shapes.open_ends[j]
    vx, vy = motion_b.vx - motion_a.vx, motion_b.vy - motion_a.vy
    turning = abs(motion_a.w) * motion_a.extent + abs(motion_b.w) * motion_b.extent
    radii = shapes.radius[sa] + shapes.radius[sb]
    count_a, count_b = shapes.count[sa], shapes.count[sb]
    if start is None:
        place_pair(shapes, sa, sb, motion_a, motion_b, 0.0, False, sweep)
        distance, ax, ay, bx, by = core_distance(sweep.geometry, 0, count_a, 1, count_b)
    else:  # placed already, and in the cache: the narrow phase has just collided them
        distance, ax, ay, bx, by = core_distance(start, sa, count_a, sb, count_b)
    t = 0.0
    for _ in range(ADVANCE_STEPS):
        gap = distance - radii
        if gap <= reach:
            if t > 0.0:
                place_pair(shapes, sa, sb, motion_a, motion_b, t, True, sweep)
            return t
        closing = turning - (vx * (bx - ax) + vy * (by - ay)) / distance
        if closing <= 0.0:
            return -1.0
        t += (gap - 0.5 * reach) / closing  # to mid-band: the next step lands within reach
        if t > duration:
            return -1.0
        place_pair(shapes, sa, sb, motion_a, motion_b, t, False, sweep)
        distance, ax, ay, bx, by = core_distance(sweep.geometry, 0, count_a, 1, count_b)
    place_pair(shapes, sa, sb, motion_a, motion_b, t, True, sweep)
    return t
