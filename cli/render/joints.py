"""Joints as drawn: each joint's anchors in world coordinates at a frame, and the lines between them (a
zigzag for a spring, over the two fixed points for a pulley; gears and broken joints are not drawn)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .geometry import rotate

if TYPE_CHECKING:
    import h5py

ZIGZAG_TEETH = 8
ZIGZAG_WIDTH = 0.12  # of the spring's length, each side


@dataclass(frozen=True)
class JointTable:
    """The joints of a run (/joints) and whether each is still whole in each recorded frame."""

    types: list[str]
    body_a: np.ndarray  # [J] int, -1: the fixed world
    body_b: np.ndarray  # [J]
    anchor_a: np.ndarray  # [J, 2] body frame about the body origin (a world point for the world)
    anchor_b: np.ndarray  # [J, 2]
    ground: np.ndarray  # [J, 2, 2] a pulley's fixed points
    spring: np.ndarray  # [J] bool
    active: np.ndarray  # [T, J] bool

    @property
    def count(self) -> int:
        return len(self.types)


def read_joints(file: h5py.File, frames: int) -> JointTable:
    """The joints of a trajectory; none for files written before joints were drawn (no anchors)."""
    group = file.get("joints")
    if group is None or "anchor_a" not in group:
        empty = np.zeros((0, 2))
        return JointTable([], np.zeros(0, np.int64), np.zeros(0, np.int64), empty, empty,
                          np.zeros((0, 2, 2)), np.zeros(0, bool), np.zeros((frames, 0), bool))
    return JointTable(
        types=[str(kind) for kind in group["type"].asstr()[()]],
        body_a=np.asarray(group["body_a"], np.int64),
        body_b=np.asarray(group["body_b"], np.int64),
        anchor_a=np.asarray(group["anchor_a"], np.float64).reshape(-1, 2),
        anchor_b=np.asarray(group["anchor_b"], np.float64).reshape(-1, 2),
        ground=np.asarray(group["ground_anchors"], np.float64).reshape(-1, 2, 2),
        spring=np.asarray(group["spring"], bool),
        active=np.asarray(group["active/value"], bool).reshape(frames, -1),
    )


def _anchors(body: np.ndarray, local: np.ndarray, position: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """[J, 2] world points of anchors on `body` (-1: `local` is already a world point)."""
    on_body = body >= 0
    index = np.where(on_body, body, 0)
    placed = position[index] + rotate(local, angle[index]) if len(position) else local
    return np.where(on_body[:, None], placed, local)


def zigzag(start: np.ndarray, end: np.ndarray, teeth: int = ZIGZAG_TEETH) -> np.ndarray:
    """[2 teeth + 2, 2] a spring from `start` to `end`: straight ends and teeth across the line."""
    along = end - start
    across = np.array([-along[1], along[0]]) * ZIGZAG_WIDTH
    t = (np.arange(2 * teeth) + 0.5) / (2 * teeth)
    side = np.where(np.arange(2 * teeth) % 2 == 0, 1.0, -1.0)
    teeth_points = start + t[:, None] * along + side[:, None] * across
    return np.concatenate([[start], teeth_points, [end]])


def joint_lines(table: JointTable, frame: int, position: np.ndarray,
                angle: np.ndarray) -> tuple[list[np.ndarray], np.ndarray]:
    """The polylines (world points) to draw at frame index `frame`, and the anchor points [K, 2]."""
    pa = _anchors(table.body_a, table.anchor_a, position, angle)
    pb = _anchors(table.body_b, table.anchor_b, position, angle)
    lines, dots = [], []
    for j in range(table.count):
        kind = table.types[j]
        if kind == "gear" or not table.active[frame, j]:
            continue
        if kind == "pulley":
            lines.append(np.stack([pa[j], table.ground[j, 0], table.ground[j, 1], pb[j]]))
        elif table.spring[j]:
            lines.append(zigzag(pa[j], pb[j]))
        else:
            lines.append(np.stack([pa[j], pb[j]]))
        dots += [pa[j], pb[j]]
    return lines, np.array(dots, np.float64).reshape(-1, 2)
