"""Frames: the state and observables of the world after chosen ticks, written by compiled code into
buffers the caller owns (so that recording every tick costs no Python per tick).

A frame buffer is a dict of arrays with one row per frame: the tick, each body's origin, velocity,
angle, angular velocity, active and asleep flags, the observables of the dynamic bodies (energies, momenta,
fastest speed) and of the last tick's contacts (count, deepest overlap), and each joint's reaction
(force on its second body, torque) and active flag.
"""

from __future__ import annotations

import math

import numpy as np

from rustycs.body_types import DYNAMIC
from rustycs.compiling import tick_kernel
from rustycs.joints import FORCE_X, FORCE_Y, TORQUE
from rustycs.observables import body_origin, contact_statistics, energies_and_momenta

# the buffer's arrays, in the order the compiled code takes them: name -> (per-frame shape, dtype),
# where "n" stands for the body count and "j" for the joint count
FRAME_FIELDS = {
    "tick": ((), np.int64),
    "position": (("n", 2), np.float64),
    "velocity": (("n", 2), np.float64),
    "angle": (("n",), np.float64),
    "angular_velocity": (("n",), np.float64),
    "active": (("n",), np.bool_),
    "asleep": (("n",), np.bool_),
    "kinetic_energy": ((), np.float64),
    "potential_energy": ((), np.float64),
    "linear_momentum": ((2,), np.float64),
    "angular_momentum": ((), np.float64),
    "contact_count": ((), np.int64),
    "max_penetration": ((), np.float64),
    "max_speed": ((), np.float64),
    "joint_force": (("j", 2), np.float64),
    "joint_torque": (("j",), np.float64),
    "joint_active": (("j",), np.bool_),
}

OBSERVABLE_FIELDS = ("kinetic_energy", "potential_energy", "linear_momentum", "angular_momentum",
                     "contact_count", "max_penetration", "max_speed")


def frame_buffer(capacity: int, bodies: int, joints: int) -> dict[str, np.ndarray]:
    """An empty buffer for `capacity` frames of `bodies` bodies and `joints` joints."""
    sizes = {"n": bodies, "j": joints}
    return {name: np.zeros((capacity, *(sizes.get(d, d) for d in shape)), dtype)
            for name, (shape, dtype) in FRAME_FIELDS.items()}


def check_frame_buffer(record: dict[str, np.ndarray], bodies: int, joints: int) -> None:
    """Raise ValueError unless `record` is a frame buffer (`frame_buffer`) of a world of `bodies` bodies and
    `joints` joints: the step writes into its arrays unchecked."""
    sizes = {"n": bodies, "j": joints}
    if list(record) != list(FRAME_FIELDS):
        raise ValueError(f"a frame buffer has the arrays {', '.join(FRAME_FIELDS)}, in that order")
    capacity = len(record["tick"])
    for name, (shape, dtype) in FRAME_FIELDS.items():
        array = record[name]
        expected = (capacity, *(sizes.get(d, d) for d in shape))
        if not (isinstance(array, np.ndarray) and array.dtype == dtype and array.shape == expected
                and array.flags.c_contiguous and array.flags.writeable):
            raise ValueError(f"frame buffer array {name!r} must be a writeable C-contiguous "
                             f"{np.dtype(dtype)} array of shape {expected}: make it with World.frame_buffer")


@tick_kernel
def record_frame(frames, k, tick, bodies, joints, forces, contacts):
    """Write the current state into row k of `frames` (the buffer's arrays as a tuple, in FRAME_FIELDS
    order); `contacts` are the last tick's."""
    (ticks, position, velocity, angles, angular_velocity, is_active, is_asleep, kinetic, potential, momentum,
     angular, contact_count, max_penetration, max_speed, joint_force, joint_torque, joint_active) = frames
    for j in range(joints.kind.shape[0]):
        joint_force[k, j, 0] = joints.reaction[j, FORCE_X]
        joint_force[k, j, 1] = joints.reaction[j, FORCE_Y]
        joint_torque[k, j] = joints.reaction[j, TORQUE]
        joint_active[k, j] = joints.active[j]
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
        is_asleep[k, i] = bodies.asleep[i]
        if body_type[i] == DYNAMIC and active[i]:
            fastest = max(fastest, v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1])
    max_speed[k] = math.sqrt(fastest)
    kinetic[k], potential[k], momentum[k, 0], momentum[k, 1], angular[k] = energies_and_momenta(bodies,
                                                                                                forces)
    contact_count[k], max_penetration[k] = contact_statistics(contacts)
