"""Semi-implicit Euler integration of the bodies, with forces, attractors and damping; the bounds and
the check for a non-finite state.

Damping multiplies the velocities by exp(-c dt) each tick of dt seconds, so a free body's speed decays
exactly as v0 exp(-c t); once a tick rather than every substep, as it cost a tenth of the 200-orbit
scene's tick where nothing is damped.
"""

from __future__ import annotations

import math

from rustycs.body_types import DYNAMIC, STATIC
from rustycs.compiling import inlined
from rustycs.contact_solver import COS, DX, DY, SIN, VX, VY, W, group_body
from rustycs.events import ESCAPE, record_event
from rustycs.forces import attraction
from rustycs.sleep import wake_island


@inlined
def damping_factors(bodies, dt, decay):
    """Once per block of ticks: the factors exp(-c dt) by which damping shrinks each body's velocities in
    a tick (linear, angular); returns whether any body is damped."""
    linear, angular = bodies.linear_damping, bodies.angular_damping
    damped = False
    for i in range(linear.shape[0]):
        damped = damped or linear[i] != 0.0 or angular[i] != 0.0
    if damped:  # else no factor is read: two exponentials a body were a tenth of a 5-body world's step(1)
        for i in range(linear.shape[0]):
            decay[i, 0] = math.exp(-linear[i] * dt)
            decay[i, 1] = math.exp(-angular[i] * dt)
    return damped


@inlined
def damp(body, bodies, decay):
    """Shrink the dynamic bodies' velocities by a tick's damping: exactly v0 exp(-c t) after t seconds."""
    body_type = bodies.body_type
    for i in range(body_type.shape[0]):
        if body_type[i] == DYNAMIC:
            body[i, VX] *= decay[i, 0]
            body[i, VY] *= decay[i, 0]
            body[i, W] *= decay[i, 1]


@inlined
def integrate_velocities(body, bodies, forces, h, order, first, last, direct):
    """Gravity and attractors on bodies first .. last - 1 of a group of the solver (`group_body`)."""
    x, body_type, active, scale, asleep = (bodies.x, bodies.body_type, bodies.active, bodies.gravity_scale,
                                           bodies.asleep)
    gx, gy = forces.gravity[0], forces.gravity[1]
    for k in range(first, last):
        i = group_body(order, k, direct)
        if body_type[i] != DYNAMIC or not active[i] or asleep[i]:
            continue
        ax, ay = attraction(x[i, 0], x[i, 1], forces)
        body[i, VX] += h * (scale[i] * gx + ax)
        body[i, VY] += h * (scale[i] * gy + ay)


@inlined
def integrate_positions(body, bodies, h, order, first, last, direct):
    """Move bodies first .. last - 1 of a group of the solver (`group_body`) and keep their displacement
    since the narrow phase (for the contact solver)."""
    x, angle, body_type, active = bodies.x, bodies.angle, bodies.body_type, bodies.active
    for k in range(first, last):
        i = group_body(order, k, direct)
        if body_type[i] == STATIC or not active[i]:
            continue
        dx = h * body[i, VX]
        dy = h * body[i, VY]
        x[i, 0] += dx
        x[i, 1] += dy
        body[i, DX] += dx
        body[i, DY] += dy
        if body[i, W] != 0.0:
            da = h * body[i, W]
            angle[i] += da
            # the rotation since the narrow phase, turned by da and renormalised (as Box2D does): no trig
            c = body[i, COS] - da * body[i, SIN]
            s = body[i, SIN] + da * body[i, COS]
            inv = 1.0 / math.sqrt(c * c + s * s)
            body[i, COS] = c * inv
            body[i, SIN] = s * inv


@inlined
def first_non_finite(bodies):
    """Index of the first moving body with a non-finite state, or -1."""
    x, angle, v, w = bodies.x, bodies.angle, bodies.v, bodies.w
    body_type, active = bodies.body_type, bodies.active
    for i in range(x.shape[0]):
        if body_type[i] == STATIC or not active[i]:
            continue
        total = x[i, 0] + x[i, 1] + angle[i] + v[i, 0] + v[i, 1] + w[i]
        if not math.isfinite(total):
            return i
    return -1


@inlined
def deactivate(bodies, i):
    """Take body i out of the world: frozen, no longer collides (it left the bounds or was removed); the
    island it slept in wakes, as it no longer holds the others up."""
    if bodies.asleep[i]:
        wake_island(bodies, bodies.island[i])
    bodies.active[i] = False
    bodies.v[i, 0] = 0.0
    bodies.v[i, 1] = 0.0
    bodies.w[i] = 0.0


@inlined
def apply_bounds(bodies, bounds, tick, events):
    """Deactivate dynamic bodies whose centre left the bounds (an `escape` event each); return how many
    left this tick."""
    x, body_type, active = bodies.x, bodies.body_type, bodies.active
    left = 0
    for i in range(x.shape[0]):
        if body_type[i] != DYNAMIC or not active[i]:
            continue
        if x[i, 0] < bounds[0] or x[i, 1] < bounds[1] or x[i, 0] > bounds[2] or x[i, 1] > bounds[3]:
            deactivate(bodies, i)
            record_event(events, tick, ESCAPE, i, -1, x[i, 0], x[i, 1], 0.0)
            left += 1
    return left
