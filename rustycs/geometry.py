"""World-space geometry of every shape for one tick: rotated vertices, edge normals, centroids, chain
ghosts and hitboxes, and each body's reach.

Shapes are turned from their rest pose by their body's angle (never incrementally, so they keep their
size). A hitbox is fattened by its body's reach: the speculative distance plus one tick of travel, so
that contacts are found before bodies meet. Static bodies do not move: their shapes are placed once,
when the step's buffers are made.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from rustycs.body_types import STATIC
from rustycs.pieces import CHAIN_SEGMENT, CIRCLE
from rustycs.tick_kernel import tick_kernel


class Geometry(NamedTuple):
    """Per shape in world coordinates, and per body its reach."""

    vertices: np.ndarray  # (S, MAX_VERTICES, 2)
    normals: np.ndarray  # (S, MAX_VERTICES, 2)
    centroid: np.ndarray  # (S, 2)
    ghosts: np.ndarray  # (S, 2, 2) chain segments only
    hitbox: np.ndarray  # (S, 4) xmin, ymin, xmax, ymax, grown by the body's reach
    reach: np.ndarray  # (N,) m: speculative distance plus one tick of travel


@njit(cache=True)
def new_geometry(n_bodies, n_shapes, max_vertices):
    return Geometry(np.zeros((n_shapes, max_vertices, 2)), np.zeros((n_shapes, max_vertices, 2)),
                    np.zeros((n_shapes, 2)), np.zeros((n_shapes, 2, 2)), np.zeros((n_shapes, 4)),
                    np.zeros(n_bodies))


@njit(cache=True, inline="always")
def _turn(px, py, c, s, local, out, k):
    out[k, 0] = px + c * local[k, 0] - s * local[k, 1]
    out[k, 1] = py + s * local[k, 0] + c * local[k, 1]


@tick_kernel
def update_geometry(bodies, shapes, margin, dt, statics, geometry):
    """Place every shape of the active bodies (of static ones too when `statics`)."""
    x, angle, v, active, body_type, first, count = (bodies.x, bodies.angle, bodies.v, bodies.active,
                                                    bodies.body_type, bodies.first_shape, bodies.shape_count)
    kind, radius, n_verts, local_verts, local_normals, local_centroid, local_ghosts = (
        shapes.kind, shapes.radius, shapes.count, shapes.vertices, shapes.normals, shapes.centroid,
        shapes.ghosts)
    verts, normals, centroid, ghosts, hitbox, reach = geometry
    for i in range(x.shape[0]):
        if not active[i] or (body_type[i] == STATIC and not statics):
            continue
        px, py = x[i, 0], x[i, 1]
        fat = margin + dt * math.sqrt(v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1])
        reach[i] = fat
        c = 1.0
        s = 0.0
        turned = False
        for j in range(first[i], first[i] + count[i]):
            r = radius[j]
            if kind[j] == CIRCLE and local_verts[j, 0, 0] == 0.0 and local_verts[j, 0, 1] == 0.0:
                # a circle about the centre of mass: no turning needed
                verts[j, 0, 0] = px
                verts[j, 0, 1] = py
                centroid[j, 0] = px
                centroid[j, 1] = py
                hitbox[j, 0] = px - r - fat
                hitbox[j, 1] = py - r - fat
                hitbox[j, 2] = px + r + fat
                hitbox[j, 3] = py + r + fat
                continue
            if not turned:
                c = math.cos(angle[i])
                s = math.sin(angle[i])
                turned = True
            lo_x = np.inf
            lo_y = np.inf
            hi_x = -np.inf
            hi_y = -np.inf
            for k in range(n_verts[j]):
                _turn(px, py, c, s, local_verts[j], verts[j], k)
                nx, ny = local_normals[j, k, 0], local_normals[j, k, 1]
                normals[j, k, 0] = c * nx - s * ny
                normals[j, k, 1] = s * nx + c * ny
                lo_x = min(lo_x, verts[j, k, 0])
                lo_y = min(lo_y, verts[j, k, 1])
                hi_x = max(hi_x, verts[j, k, 0])
                hi_y = max(hi_y, verts[j, k, 1])
            _turn(px, py, c, s, local_centroid, centroid, j)
            if kind[j] == CHAIN_SEGMENT:
                _turn(px, py, c, s, local_ghosts[j], ghosts[j], 0)
                _turn(px, py, c, s, local_ghosts[j], ghosts[j], 1)
            hitbox[j, 0] = lo_x - r - fat
            hitbox[j, 1] = lo_y - r - fat
            hitbox[j, 2] = hi_x + r + fat
            hitbox[j, 3] = hi_y + r + fat
