"""/joints of a trajectory: which joints the world has (names, types, bodies) and how to draw them, and
where each per-frame series comes from in the engine's frame buffer.

Additions beyond the spec, for the renderer:

    /joints/anchor_a, anchor_b   float64 [J, 2]     each body's anchor in its frame, about its origin (a
                                                    world point for the fixed world; 0 for gears)
    /joints/ground_anchors       float64 [J, 2, 2]  a pulley's fixed points (0 for other joints)
    /joints/spring               bool [J]           the anchors are joined by a spring (drawn as a zigzag)
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import h5py

    from .scene import Scene

JOINT_SERIES = {  # name: (per-joint row shape, dtype, unit); value [T, J, *shape]
    "reaction_force": ((2,), "f8", "N"),
    "reaction_torque": ((), "f8", "N m"),
    "active": ((), "bool", None),
}
FRAME_FIELDS = {  # series: the engine frame buffer's field it is copied from
    "reaction_force": "joint_force",
    "reaction_torque": "joint_torque",
    "active": "joint_active",
}


Vec = tuple[float, float]


@dataclass(frozen=True)
class JointDrawing:
    """What the scene says of its joints beyond the World: names and where to draw them."""

    names: list[str]
    anchor_a: list[Vec]  # body frame about the body origin; a world point for the fixed world
    anchor_b: list[Vec]
    ground_anchors: list[tuple[Vec, Vec]]
    spring: list[bool]


def joint_drawing(scene: Scene) -> JointDrawing:
    """The scene's joints, their world points at the start carried into their bodies' frames."""
    from .scene_joints import Distance, Gear, Pulley, Rope, Wheel

    bodies = {body.name: body for body in scene.bodies}

    def local(name: str | None, point: Sequence[float]) -> Vec:
        if name is None:
            return float(point[0]), float(point[1])
        body = bodies[name]
        c, s = math.cos(body.angle), math.sin(body.angle)
        dx, dy = point[0] - body.position[0], point[1] - body.position[1]
        return c * dx + s * dy, -s * dx + c * dy

    drawing = JointDrawing([], [], [], [], [])
    for joint in scene.joints:
        assert joint.name is not None  # named by validation
        drawing.names.append(joint.name)
        ground = ((0.0, 0.0), (0.0, 0.0))
        if isinstance(joint, Gear):
            ends: tuple[Vec, Vec] = ((0.0, 0.0), (0.0, 0.0))
        else:
            first, second = joint.body_names
            points = joint.anchors if isinstance(joint, (Distance, Rope, Pulley)) else (joint.anchor,) * 2
            ends = (local(first, points[0]), local(second, points[1]))
            if isinstance(joint, Pulley):
                ground = joint.ground_anchors
        drawing.anchor_a.append(ends[0])
        drawing.anchor_b.append(ends[1])
        drawing.ground_anchors.append(ground)
        drawing.spring.append(isinstance(joint, (Distance, Wheel)) and joint.spring is not None)
    return drawing


def write_joint_table(file: h5py.File, world: Any, drawing: JointDrawing | None) -> h5py.Group:
    """/joints/name, type, body_a and body_b (-1: the fixed world; a gear lists the second bodies of the
    joints it couples) and the drawing (all zero, named 'joint-<row>', without one); returns the group,
    for the series."""
    import h5py
    import numpy as np

    count = world.joint_count
    if drawing is None:
        zero = (0.0, 0.0)
        drawing = JointDrawing([f"joint-{k}" for k in range(count)], [zero] * count, [zero] * count,
                               [(zero, zero)] * count, [False] * count)
    joints = file.create_group("joints")
    text = h5py.string_dtype()
    joints.create_dataset("name", data=np.array(drawing.names, dtype=object), dtype=text)
    types = np.array([str(kind) for kind in world.joint_types], dtype=object)
    joints.create_dataset("type", data=types, dtype=text)
    bodies = np.asarray(world.joint_bodies, "i4").reshape(-1, 2)
    joints.create_dataset("body_a", data=bodies[:, 0])
    joints.create_dataset("body_b", data=bodies[:, 1])
    for name in ("anchor_a", "anchor_b"):
        joints.create_dataset(name, data=np.array(getattr(drawing, name), "f8").reshape(count, 2))
    joints["anchor_a"].attrs["unit"] = joints["anchor_b"].attrs["unit"] = "m"
    ground = np.array(drawing.ground_anchors, "f8").reshape(count, 2, 2)
    joints.create_dataset("ground_anchors", data=ground).attrs["unit"] = "m"
    joints.create_dataset("spring", data=np.array(drawing.spring, bool).reshape(count))
    return joints


def frame_joints(frames: dict[str, Any], row: int) -> dict[str, Any]:
    """Copies of one frame's joint series from a frame buffer."""
    return {name: frames[field][row].copy() for name, field in FRAME_FIELDS.items()}
