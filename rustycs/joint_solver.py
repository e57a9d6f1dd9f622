"""Joint solver: the joints' passes of the soft step, solved before the contacts in every pass.

Per tick `prepare_joints` puts each joint's anchors and axis in world orientation, and the softness of
its springs. Each substep then warm starts the accumulated impulses, solves with the soft position bias
and relaxes without it, as the contacts do (Box2D v3's soft step: a rigid constraint pulls its error back
as a stiff damped spring of JOINT_HERTZ, a spring with its own hertz and damping ratio). Anchors are
turned by each body's rotation since the tick began (the solver rows' cos and sin); positions and angles
are the bodies' current ones. Joints are solved one by one, each kind's group in row order (`order_joints`),
so the result is deterministic.

Every joint is a few constraint rows: Jacobians on body a and body b (linear x, y and angular) and an
accumulated impulse. One function per joint type lists its rows; the mode says what to do with each:
warm start (apply the accumulated impulse), solve or relax (find the impulse that cancels the row's rate,
plus the bias when solving), or add it to the joint's reaction (after the tick: the impulse on body b over
a substep's length, and the torque beyond the moment of that force about b's centre). A joint whose
reaction exceeds its break force or torque is switched off (`break_joints`).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from rustycs.compiling import inlined, stage, tick_kernel
from rustycs.contact_solver import COS, INV_INERTIA, INV_MASS, SIN, VX, VY, W, softness
from rustycs.joints import (
    ANGULAR_HERTZ,
    ANGULAR_IMPULSE,
    AXIAL_IMPULSE,
    BREAK_FORCE,
    BREAK_TORQUE,
    CONSTANT,
    DAMPING_RATIO,
    DISTANCE,
    FORCE_X,
    FORCE_Y,
    GEAR,
    GROUND_AX,
    GROUND_AY,
    GROUND_BX,
    GROUND_BY,
    HERTZ,
    IMPULSE_X,
    IMPULSE_Y,
    LENGTH,
    LIMIT,
    LOWER,
    LOWER_IMPULSE,
    MAX_LENGTH,
    MAX_MOTOR,
    MIN_LENGTH,
    MOTOR,
    MOTOR_IMPULSE,
    MOTOR_SPEED,
    PERPENDICULAR_IMPULSE,
    PRISMATIC,
    PULLEY,
    RATIO,
    REVOLUTE,
    ROPE,
    SPRING,
    SPRING_IMPULSE,
    TORQUE,
    UPPER,
    UPPER_IMPULSE,
    WELD,
    WHEEL,
)

# columns of a joint's prepared row (`prepare_joints`): anchors and axis in world orientation at the start
# of the tick, and its spring (and a weld's angular spring): see `_spring`
(RAX, RAY, RBX, RBY, AXIS_X, AXIS_Y, SPRING_COLUMNS, ANGULAR_SPRING_COLUMNS) = (0, 1, 2, 3, 4, 5, 6, 10)
FRAME_COLUMNS = 14

# What a pass does with a joint's rows. Numpy integers, not Python ints: numba compiles a kernel again for
# every distinct int literal it is called with (40 versions of `_row` took 20 s), not for an int64.
WARM, SOLVE, RELAX, REACTION = (np.int64(k) for k in range(4))

# a row's kind: rigid (its error pulled back by the joint softness), a spring (its own softness), a motor
# (drives the rate to a speed, within a largest impulse), or a one-sided limit (C >= 0)
RIGID, SPRINGY, DRIVEN, ONE_SIDED = (np.int64(k) for k in range(4))

# the groups a pass takes the joints in: revolutes and welds, prismatics and wheels, distances, ropes and
# pulleys, then gears (they couple the others' coordinates)
ANGULAR_GROUP, SLIDER_GROUP, LENGTH_GROUP, GEAR_GROUP = range(4)
GROUPS = 4


class JointWork(NamedTuple):
    """The joint solver's buffers, kept by the world from one block to the next."""

    frames: np.ndarray  # (J, FRAME_COLUMNS) the joints' anchors and springs of the tick
    order: np.ndarray  # (J,) int64 joint rows by group, each group in row order (`order_joints`)
    starts: np.ndarray  # (GROUPS + 1,) int64 where each group begins in `order`
    rotation: np.ndarray  # (N, 3) per body the cosine and sine of its angle, and the tick they are of
    broken: np.ndarray  # (J,) int64 the joints that broke in a tick


@njit(cache=True)
def new_joint_work(n_bodies, n_joints):
    rotation = np.zeros((n_bodies, 3))
    rotation[:, 2] = -1.0
    return JointWork(np.zeros((n_joints, FRAME_COLUMNS)), np.zeros(n_joints, np.int64),
                     np.zeros(GROUPS + 1, np.int64), rotation, np.zeros(n_joints, np.int64))


@inlined
def _turned(c, s, x, y):
    return c * x - s * y, s * x + c * y


@inlined
def _cross(ax, ay, bx, by):
    return ax * by - ay * bx


@inlined
def _velocity(body, i):
    """(vx, vy, w, inverse mass, inverse inertia) of body i; the fixed world (-1) is still and immovable."""
    if i < 0:
        return 0.0, 0.0, 0.0, 0.0, 0.0
    return body[i, VX], body[i, VY], body[i, W], body[i, INV_MASS], body[i, INV_INERTIA]


@inlined
def _push(body, i, jx, jy, jw, lam):
    """Body i's velocity after the impulse lam along Jacobian (jx, jy, jw); immovable bodies keep theirs."""
    if i >= 0:
        body[i, VX] += body[i, INV_MASS] * jx * lam
        body[i, VY] += body[i, INV_MASS] * jy * lam
        body[i, W] += body[i, INV_INERTIA] * jw * lam


@inlined
def _anchor(body, x, i, f, cx, cy):
    """Body i's anchor now: its offset from the centre of mass (the tick's, turned by the rotation since)
    and the world point. The world's anchors are world points about the origin."""
    if i < 0:
        return f[cx], f[cy], f[cx], f[cy]
    rx, ry = _turned(body[i, COS], body[i, SIN], f[cx], f[cy])
    return rx, ry, x[i, 0] + rx, x[i, 1] + ry


@inlined
def anchor_point(bodies, joints, j):
    """The world point of joint j's anchor on its second body (where its joint_break event is placed)."""
    b = joints.body_b[j]
    rx, ry = _turned(math.cos(bodies.angle[b]), math.sin(bodies.angle[b]), joints.local_b[j, 0],
                     joints.local_b[j, 1])
    return bodies.x[b, 0] + rx, bodies.x[b, 1] + ry


@inlined
def _rotation(body, i):
    return (1.0, 0.0) if i < 0 else (body[i, COS], body[i, SIN])


@inlined
def _angle(angle, i):
    return 0.0 if i < 0 else angle[i]


@inlined
def _spin(body, a, b):
    """Whether the joint's bodies can turn relative to each other."""
    return (a >= 0 and body[a, INV_INERTIA] > 0.0) or (b >= 0 and body[b, INV_INERTIA] > 0.0)


@tick_kernel
def _row(mode, kind, body, a, b, jax, jay, jaw, jbx, jby, jbw, c, impulses, j, column, soft, spring, target,
         limit, inv_h, reaction, rbx, rby):
    """One constraint row of joint j in a pass (see the module), on the bodies' solver rows: Jacobians
    (jax, jay, jaw) on body a and (jbx, jby, jbw) on body b, c its position error (C), `target` a motor's
    speed and `limit` its largest impulse. A kernel of its own (not inlined by numba): every joint type
    has several rows, and inlining them all made the joints take minutes to compile."""
    old = impulses[j, column]
    if mode == REACTION:
        reaction[j, FORCE_X] += jbx * old * inv_h
        reaction[j, FORCE_Y] += jby * old * inv_h
        reaction[j, TORQUE] += (jbw - _cross(rbx, rby, jbx, jby)) * old * inv_h
        return
    explicit = kind == SPRINGY and spring[3] != 0.0
    if explicit and mode != SOLVE:
        return  # an explicit spring acts once a substep, fresh
    if mode == WARM:
        _push(body, a, jax, jay, jaw, old)
        _push(body, b, jbx, jby, jbw, old)
        return
    vax, vay, wa, ma, ia = _velocity(body, a)
    vbx, vby, wb, mb, ib = _velocity(body, b)
    k = ma * (jax * jax + jay * jay) + ia * jaw * jaw + mb * (jbx * jbx + jby * jby) + ib * jbw * jbw
    if k <= 0.0:
        return
    mass = 1.0 / k
    rate = jax * vax + jay * vay + jaw * wa + jbx * vbx + jby * vby + jbw * wb
    if explicit:
        impulse = -mass * (spring[0] * c + spring[1] * rate)
        impulses[j, column] = impulse
        _push(body, a, jax, jay, jaw, impulse)
        _push(body, b, jbx, jby, jbw, impulse)
        return
    if kind == DRIVEN:
        total = min(max(old - mass * (rate - target), -limit), limit)
    else:
        bias = 0.0
        mass_scale = 1.0
        impulse_scale = 0.0
        if kind == SPRINGY:
            bias, mass_scale, impulse_scale = spring[0] * c, spring[1], spring[2]
        elif kind == ONE_SIDED and c > 0.0:
            bias = c * inv_h  # speculative: allow closing the gap, no more
        elif mode == SOLVE:
            bias, mass_scale, impulse_scale = soft[0] * c, soft[1], soft[2]
        total = old - mass_scale * mass * (rate + bias) - impulse_scale * old
        if kind == ONE_SIDED:
            total = max(total, 0.0)
    impulses[j, column] = total
    _push(body, a, jax, jay, jaw, total - old)
    _push(body, b, jbx, jby, jbw, total - old)


@inlined
def _point(mode, kind, body, a, b, rax, ray, rbx, rby, cx, cy, impulses, j, soft, spring, inv_h, reaction):
    """The anchors meet (error (cx, cy) from a's anchor to b's, lever arms ra and rb): the x and y rows
    solved together through their 2 x 2 effective mass, as Box2D does; one after the other, the rows
    left enough error in each pass that a double pendulum lost a tenth of its energy in 20 s. Inlined:
    as a call (numba passes each array as nine words) it cost 1.7 ms of a ragdoll_rain tick's joints
    against 0.64 inlined, for 10 s more compiling. `_row`, inlined as well, would save another 0.18 ms
    for 53 s more."""
    px, py = impulses[j, IMPULSE_X], impulses[j, IMPULSE_Y]
    if mode == REACTION:
        reaction[j, FORCE_X] += px * inv_h
        reaction[j, FORCE_Y] += py * inv_h
        return
    explicit = kind == SPRINGY and spring[3] != 0.0
    if explicit and mode != SOLVE:
        return  # an explicit spring acts once a substep, fresh
    if mode != WARM:
        vax, vay, wa, ma, ia = _velocity(body, a)
        vbx, vby, wb, mb, ib = _velocity(body, b)
        rate_x = vbx - wb * rby - vax + wa * ray
        rate_y = vby + wb * rbx - vay - wa * rax
        k11 = ma + mb + ray * ray * ia + rby * rby * ib
        k12 = -ray * rax * ia - rby * rbx * ib
        k22 = ma + mb + rax * rax * ia + rbx * rbx * ib
        det = k11 * k22 - k12 * k12
        if det == 0.0:
            return
        if explicit:  # -K^-1 (h omega^2 C + damping fraction dC/dt), fresh each substep
            ex = spring[0] * cx + spring[1] * rate_x
            ey = spring[0] * cy + spring[1] * rate_y
            mass_scale, impulse_scale, px, py = 1.0, 0.0, 0.0, 0.0
        else:
            bias_x = bias_y = 0.0
            mass_scale = 1.0
            impulse_scale = 0.0
            if kind == SPRINGY:
                bias_x, bias_y = spring[0] * cx, spring[0] * cy
                mass_scale, impulse_scale = spring[1], spring[2]
            elif mode == SOLVE:
                bias_x, bias_y, mass_scale, impulse_scale = soft[0] * cx, soft[0] * cy, soft[1], soft[2]
            ex = rate_x + bias_x
            ey = rate_y + bias_y
        dx = -mass_scale * (k22 * ex - k12 * ey) / det - impulse_scale * px
        dy = -mass_scale * (k11 * ey - k12 * ex) / det - impulse_scale * py
        impulses[j, IMPULSE_X] = px + dx
        impulses[j, IMPULSE_Y] = py + dy
        px, py = dx, dy
    _push(body, a, -1.0, 0.0, ray, px)
    _push(body, a, 0.0, -1.0, -rax, py)
    _push(body, b, 1.0, 0.0, -rby, px)
    _push(body, b, 0.0, 1.0, rbx, py)


@inlined
def _along(ux, uy, lax, lay, rbx, rby, sign):
    """Jacobians of the rate of (pb - pa) . u, with a's lever arm la and b's rb, times sign."""
    return (-sign * ux, -sign * uy, -sign * _cross(lax, lay, ux, uy), sign * ux, sign * uy,
            sign * _cross(rbx, rby, ux, uy))


@inlined
def _limits(mode, body, a, b, jac, coordinate, lower, upper, impulses, j, soft, spring, inv_h, reaction, rbx,
            rby):
    """A coordinate held between lower and upper: two one-sided rows along the Jacobian and against it."""
    jax, jay, jaw, jbx, jby, jbw = jac
    _row(mode, ONE_SIDED, body, a, b, jax, jay, jaw, jbx, jby, jbw, coordinate - lower, impulses, j,
         LOWER_IMPULSE, soft, spring, 0.0, 0.0, inv_h, reaction, rbx, rby)
    _row(mode, ONE_SIDED, body, a, b, -jax, -jay, -jaw, -jbx, -jby, -jbw, upper - coordinate, impulses, j,
         UPPER_IMPULSE, soft, spring, 0.0, 0.0, inv_h, reaction, rbx, rby)


@inlined
def _springs(f, column):
    return (f[column], f[column + 1], f[column + 2], f[column + 3])


@inlined
def _revolute_or_weld_pass(mode, bodies, body, joints, work, group, soft, h):
    """Revolute joints (spring, motor, limits on the angle; the anchors meet) and welds (the angle held,
    rigidly or softly; the anchors meet, rigidly or softly), in their order."""
    inv_h = 1.0 / h
    frames = work.frames
    for q in range(work.starts[group], work.starts[group + 1]):
        j = work.order[q]
        kind = joints.kind[j]
        if not joints.active[j]:
            continue
        a, b = joints.body_a[j], joints.body_b[j]
        f = frames[j]
        settings = joints.settings[j]
        flags = joints.flags[j]
        impulses, reaction = joints.impulses, joints.reaction
        spring = _springs(f, SPRING_COLUMNS)
        angle = _angle(bodies.angle, b) - _angle(bodies.angle, a) - joints.reference_angle[j]
        if _spin(body, a, b):
            if kind == WELD:
                angular = _springs(f, ANGULAR_SPRING_COLUMNS)
                _row(mode, SPRINGY if settings[ANGULAR_HERTZ] > 0.0 else RIGID, body, a, b, 0.0, 0.0, -1.0,
                     0.0, 0.0, 1.0, angle, impulses, j, ANGULAR_IMPULSE, soft, angular, 0.0, 0.0, inv_h,
                     reaction, 0.0, 0.0)
            else:
                if flags & SPRING:
                    _row(mode, SPRINGY, body, a, b, 0.0, 0.0, -1.0, 0.0, 0.0, 1.0, angle, impulses, j,
                         SPRING_IMPULSE, soft, spring, 0.0, 0.0, inv_h, reaction, 0.0, 0.0)
                if flags & MOTOR:
                    _row(mode, DRIVEN, body, a, b, 0.0, 0.0, -1.0, 0.0, 0.0, 1.0, 0.0, impulses, j,
                         MOTOR_IMPULSE, soft, spring, settings[MOTOR_SPEED], h * settings[MAX_MOTOR], inv_h,
                         reaction, 0.0, 0.0)
                if flags & LIMIT:
                    _limits(mode, body, a, b, (0.0, 0.0, -1.0, 0.0, 0.0, 1.0), angle, settings[LOWER],
                            settings[UPPER], impulses, j, soft, spring, inv_h, reaction, 0.0, 0.0)
        linear = SPRINGY if kind == WELD and settings[HERTZ] > 0.0 else RIGID
        rax, ray, pax, pay = _anchor(body, bodies.x, a, f, RAX, RAY)
        rbx, rby, pbx, pby = _anchor(body, bodies.x, b, f, RBX, RBY)
        _point(mode, linear, body, a, b, rax, ray, rbx, rby, pbx - pax, pby - pay, impulses, j, soft, spring,
               inv_h, reaction)


@inlined
def _slider_pass(mode, bodies, body, joints, work, group, soft, h):
    """Prismatic joints (spring, motor, limits along the axis; rigid across it and in angle) and wheels
    (spring and limits along the axis, a motor turning the wheel; rigid across the axis), in order."""
    inv_h = 1.0 / h
    frames = work.frames
    for q in range(work.starts[group], work.starts[group + 1]):
        j = work.order[q]
        kind = joints.kind[j]
        if not joints.active[j]:
            continue
        a, b = joints.body_a[j], joints.body_b[j]
        f = frames[j]
        settings = joints.settings[j]
        flags = joints.flags[j]
        impulses, reaction = joints.impulses, joints.reaction
        spring = _springs(f, SPRING_COLUMNS)
        rax, ray, pax, pay = _anchor(body, bodies.x, a, f, RAX, RAY)
        rbx, rby, pbx, pby = _anchor(body, bodies.x, b, f, RBX, RBY)
        dx, dy = pbx - pax, pby - pay
        ca, sa = _rotation(body, a)
        ux, uy = _turned(ca, sa, f[AXIS_X], f[AXIS_Y])
        translation = ux * dx + uy * dy
        lx, ly = dx + rax, dy + ray  # a's lever arm to b's anchor: the axis turns with a
        jac = _along(ux, uy, lx, ly, rbx, rby, 1.0)
        jax, jay, jaw, jbx, jby, jbw = jac
        if flags & SPRING:
            _row(mode, SPRINGY, body, a, b, jax, jay, jaw, jbx, jby, jbw, translation, impulses, j,
                 SPRING_IMPULSE, soft, spring, 0.0, 0.0, inv_h, reaction, rbx, rby)
        if flags & MOTOR:
            if kind == PRISMATIC:
                _row(mode, DRIVEN, body, a, b, jax, jay, jaw, jbx, jby, jbw, 0.0, impulses, j, MOTOR_IMPULSE,
                     soft, spring, settings[MOTOR_SPEED], h * settings[MAX_MOTOR], inv_h, reaction, rbx, rby)
            elif _spin(body, a, b):  # a wheel's motor turns it
                _row(mode, DRIVEN, body, a, b, 0.0, 0.0, -1.0, 0.0, 0.0, 1.0, 0.0, impulses, j, MOTOR_IMPULSE,
                     soft, spring, settings[MOTOR_SPEED], h * settings[MAX_MOTOR], inv_h, reaction, rbx, rby)
        if flags & LIMIT:
            _limits(mode, body, a, b, jac, translation, settings[LOWER], settings[UPPER], impulses, j, soft,
                    spring, inv_h, reaction, rbx, rby)
        nx, ny = -uy, ux
        jax, jay, jaw, jbx, jby, jbw = _along(nx, ny, lx, ly, rbx, rby, 1.0)
        _row(mode, RIGID, body, a, b, jax, jay, jaw, jbx, jby, jbw, nx * dx + ny * dy, impulses, j,
             PERPENDICULAR_IMPULSE, soft, spring, 0.0, 0.0, inv_h, reaction, rbx, rby)
        if kind == PRISMATIC and _spin(body, a, b):
            angle = _angle(bodies.angle, b) - _angle(bodies.angle, a) - joints.reference_angle[j]
            _row(mode, RIGID, body, a, b, 0.0, 0.0, -1.0, 0.0, 0.0, 1.0, angle, impulses, j, ANGULAR_IMPULSE,
                 soft, spring, 0.0, 0.0, inv_h, reaction, rbx, rby)


@inlined
def _length_pass(mode, bodies, body, joints, work, group, soft, h):
    """Distance joints (a rigid rod, or a spring held between min and max length), ropes (at most their
    length) and pulleys (length_a + ratio length_b held), in order."""
    inv_h = 1.0 / h
    frames = work.frames
    for q in range(work.starts[group], work.starts[group + 1]):
        j = work.order[q]
        kind = joints.kind[j]
        if not joints.active[j]:
            continue
        a, b = joints.body_a[j], joints.body_b[j]
        f = frames[j]
        settings = joints.settings[j]
        flags = joints.flags[j]
        impulses, reaction = joints.impulses, joints.reaction
        spring = _springs(f, SPRING_COLUMNS)
        rax, ray, pax, pay = _anchor(body, bodies.x, a, f, RAX, RAY)
        rbx, rby, pbx, pby = _anchor(body, bodies.x, b, f, RBX, RBY)
        if kind == PULLEY:
            # from each ground anchor to its body's anchor
            uax, uay = pax - settings[GROUND_AX], pay - settings[GROUND_AY]
            ubx, uby = pbx - settings[GROUND_BX], pby - settings[GROUND_BY]
            la = math.sqrt(uax * uax + uay * uay)
            lb = math.sqrt(ubx * ubx + uby * uby)
            uax, uay = (uax / la, uay / la) if la > 1e-12 else (0.0, 0.0)
            ubx, uby = (ubx / lb, uby / lb) if lb > 1e-12 else (0.0, 0.0)
            ratio = settings[RATIO]
            _row(mode, RIGID, body, a, b, uax, uay, _cross(rax, ray, uax, uay), ratio * ubx, ratio * uby,
                 ratio * _cross(rbx, rby, ubx, uby), la + ratio * lb - settings[CONSTANT], impulses, j,
                 AXIAL_IMPULSE, soft, spring, 0.0, 0.0, inv_h, reaction, rbx, rby)
            continue
        dx, dy = pbx - pax, pby - pay
        length = math.sqrt(dx * dx + dy * dy)
        ux, uy = (dx / length, dy / length) if length > 1e-12 else (1.0, 0.0)
        jac = _along(ux, uy, rax, ray, rbx, rby, 1.0)
        jax, jay, jaw, jbx, jby, jbw = jac
        if kind == DISTANCE and flags & SPRING:
            _row(mode, SPRINGY, body, a, b, jax, jay, jaw, jbx, jby, jbw, length - settings[LENGTH], impulses,
                 j, SPRING_IMPULSE, soft, spring, 0.0, 0.0, inv_h, reaction, rbx, rby)
        elif kind == DISTANCE:
            _row(mode, RIGID, body, a, b, jax, jay, jaw, jbx, jby, jbw, length - settings[LENGTH], impulses,
                 j, AXIAL_IMPULSE, soft, spring, 0.0, 0.0, inv_h, reaction, rbx, rby)
        if flags & LIMIT:
            _limits(mode, body, a, b, jac, length, settings[MIN_LENGTH], settings[MAX_LENGTH], impulses, j,
                    soft, spring, inv_h, reaction, rbx, rby)


@inlined
def _coordinate(bodies, body, joints, frames, j):
    """Joint j's coordinate now (revolute: angle; prismatic: translation along the axis) and its
    Jacobians on its body a and body b."""
    a, b = joints.body_a[j], joints.body_b[j]
    if joints.kind[j] == REVOLUTE:
        angle = _angle(bodies.angle, b) - _angle(bodies.angle, a) - joints.reference_angle[j]
        return angle, (0.0, 0.0, -1.0, 0.0, 0.0, 1.0)
    f = frames[j]
    rax, ray, pax, pay = _anchor(body, bodies.x, a, f, RAX, RAY)
    rbx, rby, pbx, pby = _anchor(body, bodies.x, b, f, RBX, RBY)
    ca, sa = _rotation(body, a)
    ux, uy = _turned(ca, sa, f[AXIS_X], f[AXIS_Y])
    dx, dy = pbx - pax, pby - pay
    return ux * dx + uy * dy, _along(ux, uy, dx + rax, dy + ray, rbx, rby, 1.0)


@inlined
def _gear_pass(mode, bodies, body, joints, work, soft, h):
    """Gears: coordinate_1 + ratio coordinate_2 stays constant, one row on the four bodies of the two
    joints (a body in two slots takes both parts), with the joints' Jacobians."""
    frames = work.frames
    for q in range(work.starts[GEAR_GROUP], work.starts[GEAR_GROUP + 1]):
        j = work.order[q]
        if not joints.active[j]:
            continue
        j1, j2 = joints.joint_1[j], joints.joint_2[j]
        ratio = joints.settings[j, RATIO]
        q1, jac1 = _coordinate(bodies, body, joints, frames, j1)
        q2, jac2 = _coordinate(bodies, body, joints, frames, j2)
        ids = (joints.body_a[j1], joints.body_b[j1], joints.body_a[j2], joints.body_b[j2])
        jx = (jac1[0], jac1[3], ratio * jac2[0], ratio * jac2[3])
        jy = (jac1[1], jac1[4], ratio * jac2[1], ratio * jac2[4])
        jw = (jac1[2], jac1[5], ratio * jac2[2], ratio * jac2[5])
        old = joints.impulses[j, AXIAL_IMPULSE]
        if mode == REACTION:  # the torque on joint 2's body b, the gear's output
            joints.reaction[j, TORQUE] = jw[3] * old / h
            continue
        impulse = old
        if mode != WARM:
            rate = 0.0
            k = 0.0
            for s in range(4):
                vx, vy, w, m, i = _velocity(body, ids[s])
                rate += jx[s] * vx + jy[s] * vy + jw[s] * w
                for t in range(4):  # the effective mass, with the cross terms of slots on one body
                    if ids[t] == ids[s]:
                        k += m * (jx[s] * jx[t] + jy[s] * jy[t]) + i * jw[s] * jw[t]
            if k <= 0.0:
                continue
            bias = 0.0
            mass_scale = 1.0
            impulse_scale = 0.0
            if mode == SOLVE:
                bias = soft[0] * (q1 + ratio * q2 - joints.settings[j, CONSTANT])
                mass_scale, impulse_scale = soft[1], soft[2]
            impulse = -mass_scale * (rate + bias) / k - impulse_scale * old
            joints.impulses[j, AXIAL_IMPULSE] = old + impulse
        for s in range(4):
            _push(body, ids[s], jx[s], jy[s], jw[s], impulse)


@tick_kernel
def joints_pass(mode, bodies, body, joints, work, soft, h):
    """One pass of `mode` over the active joints, group by group (see `order_joints`). A kernel of its
    own, called by every pass: inlined into each of them, the joints took minutes to compile."""
    _revolute_or_weld_pass(mode, bodies, body, joints, work, ANGULAR_GROUP, soft, h)
    _slider_pass(mode, bodies, body, joints, work, SLIDER_GROUP, soft, h)
    _length_pass(mode, bodies, body, joints, work, LENGTH_GROUP, soft, h)
    _gear_pass(mode, bodies, body, joints, work, soft, h)


@inlined
def _group(kind):
    if kind == REVOLUTE or kind == WELD:
        return ANGULAR_GROUP
    if kind == PRISMATIC or kind == WHEEL:
        return SLIDER_GROUP
    if kind == GEAR:
        return GEAR_GROUP
    return LENGTH_GROUP


@inlined
def order_joints(joints, work):
    """Each group's joint rows, in row order, so that a pass visits only its group's joints: four scans
    of every joint for its kind in each of a tick's 13 passes cost 0.13 ms of the 19,800-joint grid's
    7.3 ms tick."""
    n = 0
    for g in range(GROUPS):
        work.starts[g] = n
        for j in range(joints.kind.shape[0]):
            if _group(joints.kind[j]) == g:
                work.order[n] = j
                n += 1
    work.starts[GROUPS] = n


@inlined
def _spring(hertz, damping_ratio, h, f, column):
    """A spring's four numbers in a prepared row from `column`. A spring slow against the substeps
    (h omega <= 1) is explicit: a row's impulse is -m (h omega^2 C + (1 - exp(-2 zeta omega h)) dC/dt), once
    per substep, so it keeps its energy (symplectic Euler) and its damping is exact: (h omega^2, the
    damping fraction, 0, 1). A stiffer one is a soft constraint (bias rate, mass and impulse scales, 0),
    stable at any stiffness but damped by the implicit step: a 2 Hz spring lost half its amplitude in
    4 s so. No spring: a rigid row's values."""
    if not (0.0 < hertz < math.inf):
        f[column], f[column + 1], f[column + 2], f[column + 3] = 0.0, 1.0, 0.0, 0.0
        return
    omega = 2.0 * math.pi * hertz
    if h * omega <= 1.0:
        f[column], f[column + 1] = h * omega * omega, 1.0 - math.exp(-2.0 * damping_ratio * omega * h)
        f[column + 2], f[column + 3] = 0.0, 1.0
    else:
        f[column], f[column + 1], f[column + 2] = softness(hertz, damping_ratio, h)
        f[column + 3] = 0.0


@inlined
def prepare_springs(joints, h, work):
    """The softness of the joints' springs at substep h (the same for every tick of a block)."""
    for j in range(joints.kind.shape[0]):
        settings = joints.settings[j]
        _spring(settings[HERTZ], settings[DAMPING_RATIO], h, work.frames[j], SPRING_COLUMNS)
        _spring(settings[ANGULAR_HERTZ], settings[DAMPING_RATIO], h, work.frames[j], ANGULAR_SPRING_COLUMNS)


@inlined
def prepare_block(joints, h, work):
    """What stays the same for every tick of a block: the passes' order, the springs' softness; and no
    body's rotation computed yet (the tick numbers of a world may start again)."""
    if joints.kind.shape[0] == 0:
        return
    order_joints(joints, work)
    prepare_springs(joints, h, work)
    for i in range(work.rotation.shape[0]):
        work.rotation[i, 2] = -1.0


@inlined
def _body_rotation(angle, rotation, i, tick):
    """Cosine and sine of body i's angle (the fixed world, -1: none), computed once a tick for all its
    joints (a body of a grid is in four)."""
    if i < 0:
        return 1.0, 0.0
    if rotation[i, 2] != tick:
        rotation[i, 0] = math.cos(angle[i])
        rotation[i, 1] = math.sin(angle[i])
        rotation[i, 2] = tick
    return rotation[i, 0], rotation[i, 1]


@stage
def prepare_joints(bodies, joints, tick, work):
    """The tick's anchors and axes in world orientation."""
    angle, rotation = bodies.angle, work.rotation
    for j in range(joints.kind.shape[0]):
        if not joints.active[j]:
            continue
        f = work.frames[j]
        ca, sa = _body_rotation(angle, rotation, joints.body_a[j], tick)
        cb, sb = _body_rotation(angle, rotation, joints.body_b[j], tick)
        f[RAX], f[RAY] = _turned(ca, sa, joints.local_a[j, 0], joints.local_a[j, 1])
        f[RBX], f[RBY] = _turned(cb, sb, joints.local_b[j, 0], joints.local_b[j, 1])
        f[AXIS_X], f[AXIS_Y] = _turned(ca, sa, joints.axis[j, 0], joints.axis[j, 1])


@inlined
def breakable(joints):
    """Whether any joint has a break force or torque: only then are the reactions needed every tick."""
    for j in range(joints.kind.shape[0]):
        settings = joints.settings[j]
        if settings[BREAK_FORCE] < math.inf or settings[BREAK_TORQUE] < math.inf:
            return True
    return False


@tick_kernel
def joint_reactions(bodies, body, joints, work, h):
    """Each joint's reaction of the tick (see the module)."""
    for j in range(joints.kind.shape[0]):
        joints.reaction[j, FORCE_X] = 0.0
        joints.reaction[j, FORCE_Y] = 0.0
        joints.reaction[j, TORQUE] = 0.0
    joints_pass(REACTION, bodies, body, joints, work, (0.0, 1.0, 0.0), h)


@tick_kernel
def break_joints(joints, broken):
    """Switch off each joint whose reaction (`joint_reactions`) exceeds its break force or torque. Writes
    the broken joints' rows into `broken` and returns their number."""
    count = 0
    for j in range(joints.kind.shape[0]):
        if not joints.active[j]:
            continue
        settings = joints.settings[j]
        if (math.hypot(joints.reaction[j, FORCE_X], joints.reaction[j, FORCE_Y]) > settings[BREAK_FORCE]
                or abs(joints.reaction[j, TORQUE]) > settings[BREAK_TORQUE]):
            joints.active[j] = False
            broken[count] = j
            count += 1
    return count


@njit(cache=True)
def joint_coordinates(bodies, joints):
    """Each joint's coordinate from the bodies' poses (see `World.joint_coordinates`)."""
    x, angle = bodies.x, bodies.angle
    out = np.zeros(joints.kind.shape[0])
    for j in range(out.shape[0]):
        a, b = joints.body_a[j], joints.body_b[j]
        ca, sa = (math.cos(angle[a]), math.sin(angle[a])) if a >= 0 else (1.0, 0.0)
        cb, sb = (math.cos(angle[b]), math.sin(angle[b])) if b >= 0 else (1.0, 0.0)
        rax, ray = _turned(ca, sa, joints.local_a[j, 0], joints.local_a[j, 1])
        rbx, rby = _turned(cb, sb, joints.local_b[j, 0], joints.local_b[j, 1])
        dx = (x[b, 0] if b >= 0 else 0.0) + rbx - (x[a, 0] if a >= 0 else 0.0) - rax
        dy = (x[b, 1] if b >= 0 else 0.0) + rby - (x[a, 1] if a >= 0 else 0.0) - ray
        kind = joints.kind[j]
        settings = joints.settings[j]
        if kind == REVOLUTE or kind == WELD:
            out[j] = _angle(angle, b) - _angle(angle, a) - joints.reference_angle[j]
        elif kind == PRISMATIC or kind == WHEEL:
            ux, uy = _turned(ca, sa, joints.axis[j, 0], joints.axis[j, 1])
            out[j] = ux * dx + uy * dy
        elif kind == DISTANCE or kind == ROPE:
            out[j] = math.sqrt(dx * dx + dy * dy)
        elif kind == PULLEY:
            pax = (x[a, 0] if a >= 0 else 0.0) + rax - settings[GROUND_AX]
            pay = (x[a, 1] if a >= 0 else 0.0) + ray - settings[GROUND_AY]
            pbx = (x[b, 0] if b >= 0 else 0.0) + rbx - settings[GROUND_BX]
            pby = (x[b, 1] if b >= 0 else 0.0) + rby - settings[GROUND_BY]
            out[j] = math.sqrt(pax * pax + pay * pay) + settings[RATIO] * math.sqrt(pbx * pbx + pby * pby)
    for j in range(out.shape[0]):  # gears after the joints they couple
        if joints.kind[j] == GEAR:
            out[j] = out[joints.joint_1[j]] + joints.settings[j, RATIO] * out[joints.joint_2[j]]
    return out
