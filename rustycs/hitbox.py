"""World-space geometry of every body for one tick: rotated vertices, edge normals and hitboxes."""

from __future__ import annotations

import math

import numpy as np

from rustycs.shapes import CIRCLE
from rustycs.tick_kernel import tick_kernel


@tick_kernel
def update_geometry(x, angle, v, kind, radius, nverts, local_verts, local_normals, active,
                    margin, dt, world_verts, world_normals, hitbox, reach):
    """Rotate each polygon from its rest shape (never incrementally, so shapes keep their size)
    and compute its hitbox, fattened by its reach: the speculative margin plus one tick of travel."""
    n = x.shape[0]
    for i in range(n):
        if not active[i]:
            continue
        px, py = x[i, 0], x[i, 1]
        fat = margin + dt * math.sqrt(v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1])
        reach[i] = fat
        if kind[i] == CIRCLE:
            r = radius[i]
            hitbox[i, 0] = px - r - fat
            hitbox[i, 1] = py - r - fat
            hitbox[i, 2] = px + r + fat
            hitbox[i, 3] = py + r + fat
            continue
        c = math.cos(angle[i])
        s = math.sin(angle[i])
        lo_x = np.inf
        lo_y = np.inf
        hi_x = -np.inf
        hi_y = -np.inf
        for k in range(nverts[i]):
            lx, ly = local_verts[i, k, 0], local_verts[i, k, 1]
            wx = px + c * lx - s * ly
            wy = py + s * lx + c * ly
            world_verts[i, k, 0] = wx
            world_verts[i, k, 1] = wy
            nx, ny = local_normals[i, k, 0], local_normals[i, k, 1]
            world_normals[i, k, 0] = c * nx - s * ny
            world_normals[i, k, 1] = s * nx + c * ny
            lo_x = min(lo_x, wx)
            lo_y = min(lo_y, wy)
            hi_x = max(hi_x, wx)
            hi_y = max(hi_y, wy)
        hitbox[i, 0] = lo_x - fat
        hitbox[i, 1] = lo_y - fat
        hitbox[i, 2] = hi_x + fat
        hitbox[i, 3] = hi_y + fat
