"""Frames: the state and observables of the world after chosen ticks, written by compiled code into
buffers the caller owns (so that recording every tick costs no Python per tick).

A frame buffer is a dict of arrays with one row per frame: the tick, each body's origin, velocity,
angle, angular velocity and active flag, and the observables of the dynamic bodies (energies,
momenta, fastest speed) and of the last tick's contacts (count, deepest overlap).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from rustycs.body_types import DYNAMIC
from rustycs.observables import body_origin, contact_statistics, energies_and_momenta

# the buffer's arrays, in the order the compiled code takes them: name -> (per-frame shape, dtype),
# where "n" stands for the body count
FRAME_FIELDS = {
    "tick": ((), np.int64),
    "position": (("n", 2), np.float64),
    "velocity": (("n", 2), np.float64),
    "angle": (("n",), np.float64),
    "angular_velocity": (("n",), np.float64),
    "active": (("n",), np.bool_),
    "kinetic_energy": ((), np.float64),
    "potential_energy": ((), np.float64),
    "linear_momentum": ((2,), np.float64),
    "angular_momentum": ((), np.float64),
    "contact_count": ((), np.int64),
    "max_penetration": ((), np.float64),
    "max_speed": ((), np.float64),
}

OBSERVABLE_FIELDS = ("kinetic_energy", "potential_energy", "linear_momentum", "angular_momentum",
                     "contact_count", "max_penetration", "max_speed")


def frame_buffer(capacity: int, bodies: int) -> dict[str, np.ndarray]:
    """An empty buffer for `capacity` frames of `bodies` bodies."""
    return {name: np.zeros((capacity, *(bodies if d == "n" else d for d in shape)), dtype)
            for name, (shape, dtype) in FRAME_FIELDS.items()}


@njit(cache=True)
def record_frame(frames, k, tick, bodies, forces, points, n_points):
    """Write the current state into row k of `frames` (the buffer's arrays as a tuple, in FRAME_FIELDS
    order); `points` are the last tick's contact points."""
    (ticks, position, velocity, angles, angular_velocity, is_active, kinetic, potential, momentum, angular,
     contact_count, max_penetration, max_speed) = frames
    x, angle, v, w, active, body_type, origin = (bodies.x, bodies.angle, bodies.v, bodies.w, bodies.active,
                                                 bodies.body_type, bodies.origin)
    ticks[k] = tick
    fastest = 0.0
    for i in range(x.shape[0]):
        position[k, i, 0], position[k, i, 1] = body_origin(x, angle, origin, i)
        velocity[k, i, 0] = v[i, 0]
        velocity[k, i, 1] = v[i, 1]
        angles[k, i] = angle[i]
        angular_velocity[k, i] = w[i]
        is_active[k, i] = active[i]
        if body_type[i] == DYNAMIC and active[i]:
            fastest = max(fastest, v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1])
    max_speed[k] = np.sqrt(fastest)
    ke, pe, p, am = energies_and_momenta(bodies, forces)
    kinetic[k] = ke
    potential[k] = pe
    momentum[k, 0] = p[0]
    momentum[k, 1] = p[1]
    angular[k] = am
    contact_count[k], max_penetration[k] = contact_statistics(points, n_points)
