"""The world's forces: one constant acceleration (the sum of the scene's forces, scaled per body by its
gravity scale) and fixed attractors pulling with G*M / max(d, min_distance)^2, whatever the body's mass;
and the potential energy consistent with them."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from rustycs.compiling import inlined


class Forces(NamedTuple):
    """The world force and the attractors (A rows)."""

    gravity: np.ndarray  # (2,) m/s^2, the sum of the constant accelerations
    attractor_position: np.ndarray  # (A, 2) m
    attractor_gm: np.ndarray  # (A,) G*M, m^3/s^2
    attractor_range: np.ndarray  # (A,) m; inf for a global attractor
    attractor_min_distance: np.ndarray  # (A,) m


@inlined
def attraction(px, py, forces):
    """Acceleration towards the attractors; a local attractor acts only within its range."""
    position, gm, reach, softening = (forces.attractor_position, forces.attractor_gm, forces.attractor_range,
                                      forces.attractor_min_distance)
    ax = 0.0
    ay = 0.0
    for k in range(gm.shape[0]):
        dx = position[k, 0] - px
        dy = position[k, 1] - py
        d = math.sqrt(dx * dx + dy * dy)
        if d > reach[k] or d == 0.0:
            continue
        dc = max(d, softening[k])
        g = gm[k] / (dc * dc * d)
        ax += g * dx
        ay += g * dy
    return ax, ay


@inlined
def attractor_potential(px, py, forces):
    """Potential per unit mass consistent with `attraction` (softened core, zero beyond range)."""
    position, gm_all, reach, softening = (forces.attractor_position, forces.attractor_gm,
                                          forces.attractor_range, forces.attractor_min_distance)
    u = 0.0
    for k in range(gm_all.shape[0]):
        dx = position[k, 0] - px
        dy = position[k, 1] - py
        d = math.sqrt(dx * dx + dy * dy)
        if d > reach[k]:
            continue
        dmin = softening[k]
        gm = gm_all[k]
        if d >= dmin:
            u -= gm / d
        else:
            u -= gm / dmin - gm * (d - dmin) / (dmin * dmin)
        if math.isfinite(reach[k]):
            u += gm / max(reach[k], dmin)
    return u
