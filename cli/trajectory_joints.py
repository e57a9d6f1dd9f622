"""/joints of a trajectory: which joints the world has (names, types, bodies), and where each per-frame
series comes from in the engine's frame buffer."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import h5py

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


def joint_names(world: Any, names: Sequence[str]) -> list[str]:
    """The names of the world's joints: `names` (the scene's, in order), else 'joint-<row>'."""
    return list(names) if names else [f"joint-{k}" for k in range(world.joint_count)]


def write_joint_table(file: h5py.File, world: Any, names: Sequence[str]) -> h5py.Group:
    """/joints/name, type, body_a and body_b (-1: the fixed world; a gear lists the second bodies of the
    joints it couples); returns the group, for the series."""
    import h5py
    import numpy as np

    joints = file.create_group("joints")
    text = h5py.string_dtype()
    joints.create_dataset("name", data=np.array(joint_names(world, names), dtype=object), dtype=text)
    types = np.array([str(kind) for kind in world.joint_types], dtype=object)
    joints.create_dataset("type", data=types, dtype=text)
    bodies = np.asarray(world.joint_bodies, "i4").reshape(-1, 2)
    joints.create_dataset("body_a", data=bodies[:, 0])
    joints.create_dataset("body_b", data=bodies[:, 1])
    return joints


def frame_joints(frames: dict[str, Any], row: int) -> dict[str, Any]:
    """Copies of one frame's joint series from a frame buffer."""
    return {name: frames[field][row].copy() for name, field in FRAME_FIELDS.items()}
