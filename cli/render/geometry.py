"""Bodies in world coordinates at one frame: outlines, centres of mass, spoke tips and hitboxes."""

from __future__ import annotations

import numpy as np

from .bodies import RunInfo


def rotate(local: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Rotate body-local vectors [N, ..., 2] by each body's angle [N] (counter-clockwise)."""
    cos = np.cos(angle).reshape(angle.shape + (1,) * (local.ndim - 2))
    sin = np.sin(angle).reshape(cos.shape)
    x, y = local[..., 0], local[..., 1]
    return np.stack([cos * x - sin * y, sin * x + cos * y], axis=-1)


def world_vertices(run: RunInfo, position: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """[N, 8, 2] world vertices (rows beyond each body's vertex_count are meaningless)."""
    return position[:, None, :] + rotate(run.vertices, angle)


def centers(run: RunInfo, position: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """[N, 2] centres of mass: where velocities apply and arrows start."""
    return position + rotate(run.centroid, angle)


def spoke_tips(run: RunInfo, position: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """[N, 2] the end of each circle's spoke, the body-local point (0, r) rotated, so rotation shows."""
    local = np.stack([np.zeros_like(run.radius), run.radius], axis=-1)
    return position + rotate(local, angle)


def hitboxes(run: RunInfo, position: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """[N, 4] axis-aligned boxes (xmin, ymin, xmax, ymax) around each body, as the broad phase sees it."""
    vertices = world_vertices(run, position, angle)
    used = np.arange(vertices.shape[1])[None, :] < run.vertex_count[:, None]
    low = np.where(used[..., None], vertices, np.inf).min(axis=1)
    high = np.where(used[..., None], vertices, -np.inf).max(axis=1)
    circle = run.vertex_count == 0
    radius = run.radius[:, None]
    low[circle] = (position - radius)[circle]
    high[circle] = (position + radius)[circle]
    return np.concatenate([low, high], axis=1)
