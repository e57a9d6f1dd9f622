"""Joints: constraints between two bodies (or a body and the fixed world), as the kernels read them.

A joint row holds its type, its bodies (-1: the fixed world), its anchors in each body's frame about the
centre of mass (a world point for the world), an axis in the first body's frame, the bodies' relative
angle at the start, and its settings in named columns; the solver keeps its accumulated impulses (the
warm start of the next tick) and the reaction of the last tick. A joint's coordinate (its angle, or
translation along the axis) is zero at the start.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

REVOLUTE, PRISMATIC, DISTANCE, ROPE, WELD, WHEEL, GEAR, PULLEY = range(8)
JOINT_TYPE_NAMES = ("revolute", "prismatic", "distance", "rope", "weld", "wheel", "gear", "pulley")

# flag bits
LIMIT, MOTOR, SPRING, COLLIDE_CONNECTED = 1, 2, 4, 8

# columns of a joint's settings
(LOWER, UPPER, MOTOR_SPEED, MAX_MOTOR, HERTZ, DAMPING_RATIO, ANGULAR_HERTZ, LENGTH, MIN_LENGTH, MAX_LENGTH,
 RATIO, CONSTANT, GROUND_AX, GROUND_AY, GROUND_BX, GROUND_BY, BREAK_FORCE, BREAK_TORQUE) = range(18)
SETTING_COLUMNS = 18
# columns of a joint's accumulated impulses: the point constraint (x, y), the rotation it locks, along the
# axis (a rigid length, a spring), its motor, lower and upper limits, and across the axis (numpy integers:
# the solver passes them to a kernel, which an int literal would compile again for each value)
(IMPULSE_X, IMPULSE_Y, ANGULAR_IMPULSE, AXIAL_IMPULSE, SPRING_IMPULSE, MOTOR_IMPULSE, LOWER_IMPULSE,
 UPPER_IMPULSE, PERPENDICULAR_IMPULSE) = (np.int64(k) for k in range(9))
IMPULSE_COLUMNS = 9
# columns of a joint's reaction in the last tick: the force on the second body (x, y) and the torque
FORCE_X, FORCE_Y, TORQUE = 0, 1, 2


class Joints(NamedTuple):
    """Per joint (J rows)."""

    kind: np.ndarray  # (J,) int64: REVOLUTE ... PULLEY
    body_a: np.ndarray  # (J,) int64 row in Bodies; -1: the fixed world
    body_b: np.ndarray  # (J,) int64
    local_a: np.ndarray  # (J, 2) anchor on body a, its frame about its centre of mass (world point for -1)
    local_b: np.ndarray  # (J, 2)
    axis: np.ndarray  # (J, 2) unit axis in body a's frame (prismatic, wheel)
    reference_angle: np.ndarray  # (J,) angle of b less angle of a at the start
    flags: np.ndarray  # (J,) int64 bits: LIMIT, MOTOR, SPRING, COLLIDE_CONNECTED
    settings: np.ndarray  # (J, SETTING_COLUMNS)
    joint_1: np.ndarray  # (J,) int64: a gear's joints
    joint_2: np.ndarray
    active: np.ndarray  # (J,) bool: false once broken
    impulses: np.ndarray  # (J, IMPULSE_COLUMNS) accumulated, warm start in, result out
    reaction: np.ndarray  # (J, 3) FORCE_X, FORCE_Y, TORQUE of the last tick


# trailing shape and dtype of every column (`state.Table`)
JOINT_COLUMNS = {"kind": ((), np.int64), "body_a": ((), np.int64), "body_b": ((), np.int64),
                 "local_a": ((2,), np.float64), "local_b": ((2,), np.float64), "axis": ((2,), np.float64),
                 "reference_angle": ((), np.float64), "flags": ((), np.int64),
                 "settings": ((SETTING_COLUMNS,), np.float64), "joint_1": ((), np.int64),
                 "joint_2": ((), np.int64), "active": ((), np.bool_),
                 "impulses": ((IMPULSE_COLUMNS,), np.float64), "reaction": ((3,), np.float64)}


class JointFilter(NamedTuple):
    """Per body, the bodies a joint keeps it from colliding with (joints without collide_connected), as
    lists of (partner, joint) entries from first[i] to first[i + 1]; a broken joint no longer counts."""

    first: np.ndarray  # (N + 1,) int64
    partner: np.ndarray  # (E,) int64 body
    joint: np.ndarray  # (E,) int64


def joint_filter(bodies: int, joints: Joints) -> JointFilter:
    """The filter of `bodies` bodies and these joints (gears join no bodies of their own)."""
    pairs = [(int(a), int(b), j) for j, (kind, a, b, flags) in
             enumerate(zip(joints.kind, joints.body_a, joints.body_b, joints.flags, strict=True))
             if kind != GEAR and a >= 0 and b >= 0 and not flags & COLLIDE_CONNECTED]
    entries = sorted([(a, b, j) for a, b, j in pairs] + [(b, a, j) for a, b, j in pairs])
    first = np.zeros(bodies + 1, np.int64)
    for a, _, _ in entries:
        first[a + 1] += 1
    return JointFilter(np.cumsum(first), np.array([b for _, b, _ in entries], np.int64),
                       np.array([j for _, _, j in entries], np.int64))
