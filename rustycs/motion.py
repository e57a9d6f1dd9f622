"""Forces, attractors and semi-implicit Euler integration of the bodies."""

from __future__ import annotations

import math

from numba import njit

from rustycs.body_types import DYNAMIC, STATIC
from rustycs.contact_solver import COS, DX, DY, SIN, VX, VY, W


@njit(cache=True)
def attraction(px, py, att_pos, att_gm, att_range, att_min_distance):
    """Acceleration towards the attractors: G*M / max(d, min_distance)^2, whatever the body's mass;
    a local attractor acts only within its range."""
    ax = 0.0
    ay = 0.0
    for k in range(att_gm.shape[0]):
        dx = att_pos[k, 0] - px
        dy = att_pos[k, 1] - py
        d = math.sqrt(dx * dx + dy * dy)
        if d > att_range[k] or d == 0.0:
            continue
        dc = max(d, att_min_distance[k])
        g = att_gm[k] / (dc * dc * d)
        ax += g * dx
        ay += g * dy
    return ax, ay


@njit(cache=True, inline="always")
def integrate_velocities(body, x, body_type, active, gravity, att_pos, att_gm, att_range,
                         att_min_distance, h):
    for i in range(x.shape[0]):
        if body_type[i] != DYNAMIC or not active[i]:
            continue
        ax, ay = attraction(x[i, 0], x[i, 1], att_pos, att_gm, att_range, att_min_distance)
        body[i, VX] += h * (gravity[0] + ax)
        body[i, VY] += h * (gravity[1] + ay)


@njit(cache=True, inline="always")
def integrate_positions(x, angle, body, body_type, active, h):
    """Move bodies and keep their displacement since the narrow phase (for the contact solver)."""
    for i in range(x.shape[0]):
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


@njit(cache=True)
def first_non_finite(x, angle, v, w, body_type, active):
    """Index of the first moving body with a non-finite state, or -1."""
    for i in range(x.shape[0]):
        if body_type[i] == STATIC or not active[i]:
            continue
        total = x[i, 0] + x[i, 1] + angle[i] + v[i, 0] + v[i, 1] + w[i]
        if not math.isfinite(total):
            return i
    return -1


@njit(cache=True)
def apply_bounds(x, v, w, body_type, active, bounds):
    """Deactivate dynamic bodies whose centre left the bounds; return how many left this tick."""
    left = 0
    for i in range(x.shape[0]):
        if body_type[i] != DYNAMIC or not active[i]:
            continue
        if x[i, 0] < bounds[0] or x[i, 1] < bounds[1] or x[i, 0] > bounds[2] or x[i, 1] > bounds[3]:
            active[i] = False
            v[i, 0] = 0.0
            v[i, 1] = 0.0
            w[i] = 0.0
            left += 1
    return left
