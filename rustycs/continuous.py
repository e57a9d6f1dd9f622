"""Continuous collision after the solver: a fast body that went through a static or kinematic shape in
its tick, or a bullet that went through any dynamic body, is put back where it first touched it.

The narrow phase sweeps each pair with the velocities the tick starts with (`time_of_impact`), so the
solver stops every impact those velocities lead to. A body that another contact turns in the middle of
the tick can then meet what it was not heading for: among 500 circles shot at 100-300 m/s inside a box
of 2 cm walls, one deflected by its neighbour crossed a wall it had been moving away from. So after the
solver, every candidate pair that got no contact is swept again along the path its bodies actually took,
straight from their poses at the tick's start to those at its end; a body that passes within touching
distance of such a shape is moved back along that path to where it first touched (Box2D's
b2SolveContinuous), keeping its velocity: the next tick's contact stops it there.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from rustycs.body_types import DYNAMIC, STATIC
from rustycs.broad_phase import SHAPE_BITS, SHAPE_MASK
from rustycs.compiling import inlined, stage, tick_kernel
from rustycs.constants import LINEAR_SLOP
from rustycs.contact_solver import COS, DX, DY, SIN
from rustycs.time_of_impact import Motion, time_of_impact

EARLIEST, TRAVEL = 0, 1  # columns of `HoldBack.bodies`
BODY_COLUMNS = 2
# a shape's part in being held back (`HoldBack.role`), by its body: a dynamic body, a bullet, or a static or
# kinematic one. Two shapes of one role other than BULLET never hold each other back (`_held_back`)
FREE, BULLET, FIXED = 0, 1, 2


class HoldBack(NamedTuple):
    """Scratch of `hold_back_passes`."""

    bodies: np.ndarray  # (N, BODY_COLUMNS) per body the earliest fraction of the tick and the travel
    fixed: np.ndarray  # (S,) int64: the rows of the shapes of active static and kinematic bodies
    role: np.ndarray  # (S,) int8 per shape: FREE, BULLET or FIXED


@njit(cache=True)
def new_hold_back(n_bodies, n_shapes):
    return HoldBack(np.ones((n_bodies, BODY_COLUMNS)), np.empty(n_shapes, np.int64),
                    np.empty(n_shapes, np.int8))


@inlined
def _fixed_shapes(bodies, shapes, fixed):
    """Write the rows of the shapes of active static and kinematic bodies, sensors left out, into `fixed`;
    returns how many."""
    n = 0
    for j in range(shapes.body.shape[0]):
        other = shapes.body[j]
        if bodies.body_type[other] != DYNAMIC and bodies.active[other] and not shapes.sensor[j]:
            fixed[n] = j
            n += 1
    return n


@inlined
def _tick_motion(bodies, body, i, dt):
    """Body i's motion through the tick just solved: straight from its pose at the start of the tick to
    its pose now (the solver rows hold its displacement and its turn since then)."""
    turn = math.atan2(body[i, SIN], body[i, COS])
    return Motion(bodies.x[i, 0] - body[i, DX], bodies.x[i, 1] - body[i, DY], bodies.angle[i] - turn,
                  body[i, DX] / dt, body[i, DY] / dt, turn / dt, bodies.extent[i])


@inlined
def _held_back(bodies, mover, other):
    """Whether a pass of body `mover` through body `other` is undone: a dynamic body's through a static or
    kinematic one, and a bullet's through any other."""
    body_type, bullet = bodies.body_type, bodies.bullet
    return body_type[mover] == DYNAMIC and (body_type[other] != DYNAMIC or bullet[mover])


@inlined
def _near(hitbox, i, j, grow):
    """Whether hitbox i grown by `grow` overlaps hitbox j."""
    return (hitbox[i, 0] - grow <= hitbox[j, 2] and hitbox[j, 0] <= hitbox[i, 2] + grow
            and hitbox[i, 1] - grow <= hitbox[j, 3] and hitbox[j, 1] <= hitbox[i, 3] + grow)


@tick_kernel
def _sweep(shapes, sa, sb, motion_a, motion_b, dt, margin, sweep):
    """The fraction of the tick at which shapes sa and sb, moving as their motions say, first come within
    touching distance; 1 when they do not, or when they touch from the start (no pass) or hardly move.
    Not inlined: a sweep is rare, and two inlined copies made every tick's pass slower."""
    vx, vy = motion_b.vx - motion_a.vx, motion_b.vy - motion_a.vy
    turning = abs(motion_a.w) * motion_a.extent + abs(motion_b.w) * motion_b.extent
    if dt * (math.sqrt(vx * vx + vy * vy) + turning) <= margin:
        return 1.0
    t = time_of_impact(shapes, sa, sb, motion_a, motion_b, dt, LINEAR_SLOP, None, sweep)
    return t / dt if t > 0.0 else 1.0


@inlined
def _travel(body, i, extent):
    """A bound on how far body i's cores moved in the tick: its displacement plus its turn times its
    extent, the turn bounded from its sine and cosine (below a quarter turn, by pi/2 |sin| and by
    |tan|, which is within 0.002 % of the turn of the tumbler's drum) to spare an arctangent per body and
    tick."""
    s, c = abs(body[i, SIN]), body[i, COS]
    turn = min(0.5 * math.pi * s, s / c) if c > 0.0 else math.pi
    return math.sqrt(body[i, DX] * body[i, DX] + body[i, DY] * body[i, DY]) + turn * extent[i]


@inlined
def _path_held(geometry, body, i, extent, exact):
    """Whether body i's path through the tick stayed inside its hitboxes: its displacement strays from
    the one they were swept for by less than they were grown by for the margin and turning. The turn
    bounded from its sine (`_travel`), or `exact`."""
    planned = geometry.travel
    if exact:
        turn = abs(math.atan2(body[i, SIN], body[i, COS]))
    else:
        turn = 0.5 * math.pi * abs(body[i, SIN]) if body[i, COS] >= 0.0 else math.pi
    ox, oy = body[i, DX] - planned[i, 0], body[i, DY] - planned[i, 1]
    spare = geometry.reach[i] - math.sqrt(planned[i, 0] * planned[i, 0] + planned[i, 1] * planned[i, 1])
    return math.sqrt(ox * ox + oy * oy) + turn * extent[i] <= spare


@stage
def hold_back_passes(pair_keys, n_pairs, clearance, bodies, shapes, geometry, body, dt, margin, sweep, work):
    """Sweep the candidate pairs that got no contact along the tick's paths of their bodies (those that
    moved more than `margin` relative to each other, and farther than the pair's `clearance`, the gap the
    narrow phase found at least), and move each body held back by one (`_held_back`) to the earliest
    time it touched one. Without the clearance the tumbler's drum, which turns its walls' ends 11 cm a
    tick, was swept against every box its walls' hitboxes hold (the tick 3.3-3.9 ms, with it 3.1-3.2).
    A dynamic body that moved farther than its hitbox reached (a collision sped it up) is swept against
    every static and kinematic shape its path passes (those are listed once a tick: scanning all 6,281
    shapes for each of the 150 such bodies of a tick of the falling compounds took 0.5 ms)."""
    scratch, role = work.bodies, work.role
    body_type, active, first, count, extent = (bodies.body_type, bodies.active, bodies.first_shape,
                                               bodies.shape_count, bodies.extent)
    moved = False
    for i in range(scratch.shape[0]):
        scratch[i, EARLIEST] = 1.0
        scratch[i, TRAVEL] = _travel(body, i, extent) if body_type[i] != STATIC and active[i] else 0.0
        moved = moved or scratch[i, TRAVEL] > margin
    if not moved:
        return  # nothing moved far enough to pass anything (a pile at rest)
    for i in range(scratch.shape[0]):
        part = FIXED if body_type[i] != DYNAMIC else BULLET if bodies.bullet[i] else FREE
        for j in range(first[i], first[i] + count[i]):
            role[j] = part
    for k in range(n_pairs):
        clear = clearance[k]
        if clear == math.inf:
            continue  # the solver had its contact
        sa = pair_keys[k] >> SHAPE_BITS
        sb = pair_keys[k] & SHAPE_MASK
        # two dynamic bodies (no bullet), or two fixed ones: neither is held back. Read from one small
        # array before the bodies' rows: smash's 64,000 pairs after the impact are nearly all such
        if role[sa] == role[sb] and role[sa] != BULLET:
            continue
        a, b = shapes.body[sa], shapes.body[sb]
        travel = scratch[a, TRAVEL] + scratch[b, TRAVEL]
        # too little to pass through anything, or too little to come within touching distance (the slop)
        if travel <= margin or travel + LINEAR_SLOP < clear:
            continue
        hold_a, hold_b = _held_back(bodies, a, b), _held_back(bodies, b, a)
        if not (hold_a or hold_b):
            continue
        motion_a, motion_b = _tick_motion(bodies, body, a, dt), _tick_motion(bodies, body, b, dt)
        f = _sweep(shapes, sa, sb, motion_a, motion_b, dt, margin, sweep)
        if hold_a:
            scratch[a, EARLIEST] = min(scratch[a, EARLIEST], f)
        if hold_b:
            scratch[b, EARLIEST] = min(scratch[b, EARLIEST], f)
    hitbox, fixed = geometry.hitbox, work.fixed
    n_fixed = -1
    for i in range(scratch.shape[0]):
        if body_type[i] != DYNAMIC or _path_held(geometry, body, i, extent, False):
            continue  # its hitboxes held its path: its pairs were swept above
        if _path_held(geometry, body, i, extent, True):  # the bound from the sine was not enough: exactly
            continue
        turn = math.atan2(body[i, SIN], body[i, COS])
        travel = math.sqrt(body[i, DX] * body[i, DX] + body[i, DY] * body[i, DY]) + abs(turn) * extent[i]
        if n_fixed < 0:
            n_fixed = _fixed_shapes(bodies, shapes, fixed)
        grow = travel + LINEAR_SLOP
        motion = _tick_motion(bodies, body, i, dt)
        for f in range(n_fixed):
            j = fixed[f]
            other = shapes.body[j]
            for sa in range(first[i], first[i] + count[i]):
                if shapes.sensor[sa] or not _near(hitbox, sa, j, grow):
                    continue
                f = _sweep(shapes, sa, j, motion, _tick_motion(bodies, body, other, dt), dt, margin, sweep)
                scratch[i, EARLIEST] = min(scratch[i, EARLIEST], f)
    x, angle = bodies.x, bodies.angle
    for i in range(scratch.shape[0]):
        back = 1.0 - scratch[i, EARLIEST]
        if back > 0.0:
            x[i, 0] -= back * body[i, DX]
            x[i, 1] -= back * body[i, DY]
            angle[i] -= back * math.atan2(body[i, SIN], body[i, COS])
