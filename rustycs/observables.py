"""Energies and momenta of the dynamic bodies, for recording and checks."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rustycs.body_types import DYNAMIC
from rustycs.compiling import inlined
from rustycs.forces import attractor_potential
from rustycs.narrow_phase import NORMAL_IMPULSE, SEPARATION


@inlined
def energies_and_momenta(bodies, forces):
    """Kinetic and potential energy, linear and angular momentum (about the origin) of the active
    dynamic bodies."""
    x, v, w, mass, inertia, inv_inertia, body_type, active = (bodies.x, bodies.v, bodies.w, bodies.mass,
                                                              bodies.inertia, bodies.inv_inertia,
                                                              bodies.body_type, bodies.active)
    gravity, gravity_scale = forces.gravity, bodies.gravity_scale
    kinetic = 0.0
    potential = 0.0
    px = 0.0
    py = 0.0
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
        px += m * v[i, 0]
        py += m * v[i, 1]
        potential -= m * gravity_scale[i] * (gravity[0] * x[i, 0] + gravity[1] * x[i, 1])
        potential += m * attractor_potential(x[i, 0], x[i, 1], forces)
    return kinetic, potential, px, py, angular


@inlined
def _touching(data, n, count, deepest):
    for p in range(n):
        if data[p, SEPARATION] <= 0.0 or data[p, NORMAL_IMPULSE] > 0.0:
            count += 1
            deepest = max(deepest, -data[p, SEPARATION])
    return count, deepest


@inlined
def contact_statistics(contacts):
    """Touching points (overlapping or carrying load) and the deepest overlap among the last tick's
    contact points and those asleep, without building the contact list."""
    count, deepest = _touching(contacts.points.data, contacts.count[1], 0, 0.0)
    return _touching(contacts.asleep.data, contacts.asleep.count[0], count, deepest)


@inlined
def body_origin(x, angle, origin, i):
    """Body i's origin: its centre of mass plus the rotated offset to the origin."""
    ox = origin[i, 0]
    oy = origin[i, 1]
    if ox == 0.0 and oy == 0.0:  # circles, boxes: no turning needed
        return x[i, 0], x[i, 1]
    c = math.cos(angle[i])
    s = math.sin(angle[i])
    return x[i, 0] + c * ox - s * oy, x[i, 1] + s * ox + c * oy


@njit(cache=True)
def body_origins(bodies):
    """Every body's origin."""
    out = np.empty_like(bodies.x)
    for i in range(out.shape[0]):
        out[i, 0], out[i, 1] = body_origin(bodies.x, bodies.angle, bodies.origin, i)
    return out
