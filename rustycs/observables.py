"""Energies and momenta of the dynamic bodies, for recording and checks."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rustycs.body_types import DYNAMIC


@njit(cache=True)
def attractor_potential(px, py, att_pos, att_gm, att_range, att_min_distance):
    """Potential per unit mass consistent with `motion.attraction` (softened core, zero beyond range)."""
    u = 0.0
    for k in range(att_gm.shape[0]):
        dx = att_pos[k, 0] - px
        dy = att_pos[k, 1] - py
        d = math.sqrt(dx * dx + dy * dy)
        if d > att_range[k]:
            continue
        dmin = att_min_distance[k]
        gm = att_gm[k]
        if d >= dmin:
            u -= gm / d
        else:
            u -= gm / dmin - gm * (d - dmin) / (dmin * dmin)
        if math.isfinite(att_range[k]):
            u += gm / max(att_range[k], dmin)
    return u


@njit(cache=True)
def energies_and_momenta(x, v, w, mass, inertia, inv_inertia, body_type, active, gravity,
                         att_pos, att_gm, att_range, att_min_distance):
    kinetic = 0.0
    potential = 0.0
    momentum = np.zeros(2)
    angular = 0.0
    for i in range(x.shape[0]):
        if body_type[i] != DYNAMIC or not active[i]:
            continue
        m = mass[i]
        kinetic += 0.5 * m * (v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1])
        angular += m * (x[i, 0] * v[i, 1] - x[i, 1] * v[i, 0])
        if inv_inertia[i] > 0.0:
            kinetic += 0.5 * inertia[i] * w[i] * w[i]
            angular += inertia[i] * w[i]
        momentum[0] += m * v[i, 0]
        momentum[1] += m * v[i, 1]
        potential -= m * (gravity[0] * x[i, 0] + gravity[1] * x[i, 1])
        potential += m * attractor_potential(x[i, 0], x[i, 1], att_pos, att_gm, att_range, att_min_distance)
    return kinetic, potential, momentum, angular


@njit(cache=True)
def contact_statistics(separation, normal_impulse):
    """Touching points (overlapping or carrying load) and the deepest overlap among the last tick's
    contact points, without building the contact list."""
    count = 0
    deepest = 0.0
    for p in range(separation.shape[0]):
        if separation[p] <= 0.0 or normal_impulse[p] > 0.0:
            count += 1
            deepest = max(deepest, -separation[p])
    return count, deepest


@njit(cache=True, inline="always")
def body_origin(x, angle, origin_offset, i):
    """Body i's origin: its centre of mass plus the rotated offset to the origin."""
    ox = origin_offset[i, 0]
    oy = origin_offset[i, 1]
    if ox == 0.0 and oy == 0.0:  # circles, boxes: no turning needed
        return x[i, 0], x[i, 1]
    c = math.cos(angle[i])
    s = math.sin(angle[i])
    return x[i, 0] + c * ox - s * oy, x[i, 1] + s * ox + c * oy


@njit(cache=True)
def body_origins(x, angle, origin_offset):
    """Every body's origin."""
    out = np.empty_like(x)
    for i in range(x.shape[0]):
        out[i, 0], out[i, 1] = body_origin(x, angle, origin_offset, i)
    return out
