"""The bench scene's joints built in pymunk and Box2D v3 (pyb2d3), as `spec_joints.JointSpec` describes
them.

pymunk: a PivotJoint (revolute) or PinJoint (distance), a RotaryLimitJoint for limits and a SimpleMotor
(its rate is the negative of our speed: chipmunk drives w_a - w_b) with max_force as the motor's torque;
static bodies are shapes on the space's static body, so their anchors go in as world points (and a joint
between two of them is left out). Box2D: a
revolute or distance joint def; joints to the fixed world hang from one static body at the origin.
"""

from __future__ import annotations

import math
from typing import Any

from .spec import BodySpec
from .spec_joints import JointSpec


def _world_point(spec: BodySpec, local: tuple[float, float]) -> tuple[float, float]:
    c, s = math.cos(spec.angle), math.sin(spec.angle)
    return spec.position[0] + c * local[0] - s * local[1], spec.position[1] + s * local[0] + c * local[1]


def add_pymunk_joints(space: Any, bodies: list[Any], specs: tuple[BodySpec, ...],
                      joints: tuple[JointSpec, ...]) -> None:
    import pymunk

    def end(index: int, local: tuple[float, float]) -> tuple[Any, tuple[float, float]]:
        if index < 0:
            return space.static_body, local
        if specs[index].body_type == "static":
            return space.static_body, _world_point(specs[index], local)
        return bodies[index], local

    for joint in joints:
        (a, pa), (b, pb) = end(joint.body_a, joint.anchor_a), end(joint.body_b, joint.anchor_b)
        if a is b:  # two static bodies (both on the static body): the joint holds nothing
            continue
        kind = pymunk.PivotJoint if joint.kind == "revolute" else pymunk.PinJoint
        parts = [kind(a, b, pa, pb)]
        if joint.limits is not None:
            lower, upper = joint.limits
            parts.append(pymunk.RotaryLimitJoint(a, b, lower + joint.reference_angle,
                                                 upper + joint.reference_angle))
        if joint.motor is not None:
            motor = pymunk.SimpleMotor(a, b, -joint.motor[0])
            motor.max_force = joint.motor[1]
            parts.append(motor)
        for part in parts:
            part.collide_bodies = joint.collide_connected
        space.add(*parts)


def add_box2d_joints(world: Any, bodies: list[Any], joints: tuple[JointSpec, ...]) -> None:
    import pyb2d3 as b2

    ground = None
    for joint in joints:
        if joint.body_a < 0 and ground is None:
            ground = world.create_body(b2.body_def(type=b2.BodyType.STATIC, position=(0.0, 0.0)))
        a = ground if joint.body_a < 0 else bodies[joint.body_a]
        common = dict(body_a=a, body_b=bodies[joint.body_b], local_anchor_a=joint.anchor_a,
                      local_anchor_b=joint.anchor_b, collide_connected=joint.collide_connected)
        if joint.kind == "distance":
            world.create_distance_joint(b2.distance_joint_def(length=joint.length, **common))
            continue
        settings: dict[str, Any] = dict(reference_angle=joint.reference_angle)
        if joint.limits is not None:
            settings.update(enable_limit=True, lower_angle=joint.limits[0], upper_angle=joint.limits[1])
        if joint.motor is not None:
            settings.update(enable_motor=True, motor_speed=joint.motor[0], max_motor_torque=joint.motor[1])
        world.create_revolute_joint(b2.revolute_joint_def(**common, **settings))
