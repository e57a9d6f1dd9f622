"""Bodies in world coordinates at one frame: shape outlines, centres of mass, spoke tips and hitboxes."""

from __future__ import annotations

import numpy as np

from .bodies import RunInfo

STADIUM_STEPS = 12  # segments per half circle of a drawn capsule


def rotate(local: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Rotate vectors [N, ..., 2] by angles [N] (counter-clockwise)."""
    cos = np.cos(angle).reshape(angle.shape + (1,) * (local.ndim - 2))
    sin = np.sin(angle).reshape(cos.shape)
    x, y = local[..., 0], local[..., 1]
    return np.stack([cos * x - sin * y, sin * x + cos * y], axis=-1)


def world_points(run: RunInfo, position: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """[P, 2] every shape's points (`Outlines.points`) placed by its body's pose."""
    owner = run.outlines.point_body
    return position[owner] + rotate(run.outlines.points, angle[owner])


def centers(run: RunInfo, position: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """[N, 2] centres of mass: where velocities apply and arrows start."""
    return position + rotate(run.centroid, angle)


def spoke_tips(run: RunInfo, position: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """[S, 2] the end of each disc's spoke, so that its rotation shows (meaningless for other shapes)."""
    body = run.outlines.body
    return position[body] + rotate(run.outlines.spoke, angle[body])


def shape_boxes(run: RunInfo, points: np.ndarray) -> np.ndarray:
    """[S, 4] axis-aligned boxes (xmin, ymin, xmax, ymax) of the shapes, from their world points."""
    outlines = run.outlines
    if outlines.count == 0:
        return np.zeros((0, 4))
    starts = outlines.start[:-1]
    radius = outlines.radius[:, None]
    low = np.minimum.reduceat(points, starts, axis=0) - radius
    high = np.maximum.reduceat(points, starts, axis=0) + radius
    return np.concatenate([low, high], axis=1)


def hitboxes(run: RunInfo, boxes: np.ndarray) -> np.ndarray:
    """[N, 4] each body's box around its shapes' `boxes`."""
    first = run.outlines.first[:-1]
    if len(first) == 0:
        return np.zeros((0, 4))
    return np.concatenate([np.minimum.reduceat(boxes[:, :2], first, axis=0),
                           np.maximum.reduceat(boxes[:, 2:], first, axis=0)], axis=1)


def body_hitboxes(run: RunInfo, position: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """[N, 4] each body's box around all its shapes at this pose."""
    return hitboxes(run, shape_boxes(run, world_points(run, position, angle)))


def stadium(a: np.ndarray, b: np.ndarray, radius: float) -> np.ndarray:
    """[2 STADIUM_STEPS + 2, 2] the outline of a capsule whose end circles are centred at a and b."""
    heading = np.arctan2(b[1] - a[1], b[0] - a[0])
    turn = np.linspace(-np.pi / 2, np.pi / 2, STADIUM_STEPS + 1)
    ends = [(b, heading + turn), (a, heading + np.pi + turn)]
    return np.concatenate([centre + radius * np.stack([np.cos(t), np.sin(t)], axis=-1) for centre, t in ends])
