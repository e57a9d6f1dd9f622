"""The joints of a benchmark scene, as every engine builds them: the revolute and rigid distance joints
all three engines have alike, with limits and motors (Box2D's joint friction is a motor of speed 0)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..errors import UserError

if TYPE_CHECKING:
    from ..scene import Scene

Vec = tuple[float, float]
PEER_JOINTS = ("revolute", "distance")


@dataclass(frozen=True)
class JointSpec:
    """One joint between two bodies (rows of BenchScene.bodies; -1: the fixed world)."""

    kind: str  # revolute | distance
    body_a: int
    body_b: int
    anchor_a: Vec  # in body a's frame about its origin (a world point for the world)
    anchor_b: Vec
    reference_angle: float  # angle of b less angle of a at the start: the joint angle's zero
    limits: tuple[float, float] | None  # joint angle, rad, about the reference
    motor: tuple[float, float] | None  # speed (rad/s), max torque (N m)
    length: float  # distance joints: the rod's length, m
    collide_connected: bool


def describe_joints(scene: Scene) -> tuple[JointSpec, ...]:
    """The scene's joints for the peers; UserError for what they would build differently."""
    from ..scene_joints import Distance, Revolute
    from ..trajectory_joints import joint_drawing

    drawing = joint_drawing(scene)
    rows = {body.name: i for i, body in enumerate(scene.bodies)}
    specs = []
    for k, joint in enumerate(scene.joints):
        if not isinstance(joint, (Revolute, Distance)) or joint.spring is not None or (
                isinstance(joint, Distance) and (joint.min_length, joint.max_length) != (None, None)):
            raise UserError(f"{scene.name}: joint '{joint.name}': the peer engines are given only "
                            f"{' and rigid '.join(PEER_JOINTS)} joints (no springs)")
        first, second = joint.body_names
        a, b = (-1 if first is None else rows[first]), rows[second]
        angle_a = 0.0 if a < 0 else scene.bodies[a].angle
        length = 0.0
        if isinstance(joint, Distance):
            (xa, ya), (xb, yb) = joint.anchors
            length = math.hypot(xb - xa, yb - ya) if joint.length is None else joint.length
        limits = joint.limits if isinstance(joint, Revolute) else None
        motor = joint.motor if isinstance(joint, Revolute) else None
        specs.append(JointSpec(
            kind=joint.type, body_a=a, body_b=b, anchor_a=drawing.anchor_a[k], anchor_b=drawing.anchor_b[k],
            reference_angle=scene.bodies[b].angle - angle_a, limits=None if limits is None else tuple(limits),
            motor=None if motor is None else (motor.speed, motor.max_torque), length=length,
            collide_connected=joint.collide_connected))
    return tuple(specs)
