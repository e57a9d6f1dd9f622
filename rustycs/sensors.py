"""Sensors: shapes that detect overlaps and push nothing.

A sensor body is a body with at least one sensor shape. At the end of every tick each sensor body's
sensor shapes are tested against the other shapes of every active dynamic body, at the poses the tick
ended with, through the narrow phase's own routines (an overlap is a separation <= 0); a body that
starts or stops overlapping a sensor body is a `sensor_enter` or `sensor_exit` event. Sensors are never
paired by the broad phase, so they cost nothing in the solver. The test runs over every dynamic body per
sensor body, cut short by a bounding box: sensors are meant to be few (goals, counters).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from rustycs.body_types import DYNAMIC
from rustycs.compiling import inlined, tick_kernel
from rustycs.events import SENSOR_ENTER, SENSOR_EXIT, record_event
from rustycs.geometry import Geometry, new_geometry, place_piece
from rustycs.manifold import Collision, new_collision
from rustycs.narrow_phase import collide_pair


class Sensors(NamedTuple):
    """The sensor bodies and what overlaps them."""

    body: np.ndarray  # (K,) int64 the sensor bodies
    slot: np.ndarray  # (N,) int64 a body's row in `body`, -1 for a body with no sensor shape
    inside: np.ndarray  # (K, N) bool: body i overlaps sensor body k (after the last tick)
    geometry: Geometry  # scratch: the tested shapes placed at the end of the tick (rows as in Shapes)
    collision: Collision  # scratch


def new_sensors(bodies, shapes, max_vertices: int) -> Sensors:
    """The sensor bodies of a world's records, nothing inside them yet."""
    n = bodies.x.shape[0]
    body = np.unique(shapes.body[shapes.sensor]).astype(np.int64)
    slot = np.full(n, -1, np.int64)
    slot[body] = np.arange(len(body))
    rows = shapes.body.shape[0] if len(body) else 0
    return Sensors(body, slot, np.zeros((len(body), n), np.bool_), new_geometry(0, rows, max_vertices),
                   new_collision())


@inlined
def _overlaps(shapes, sensors, first, count, b, bodies):
    """Whether a non-sensor shape of body b, placed where it is now, overlaps one of the sensor shapes
    first .. first + count (already placed)."""
    x, angle, geometry, out = bodies.x, bodies.angle, sensors.geometry, sensors.collision
    c = math.cos(angle[b])
    s = math.sin(angle[b])
    for j in range(bodies.first_shape[b], bodies.first_shape[b] + bodies.shape_count[b]):
        if shapes.sensor[j]:
            continue
        place_piece(shapes, j, x[b, 0], x[b, 1], c, s, geometry, j)
        for q in range(first, first + count):
            if not shapes.sensor[q]:
                continue
            n = collide_pair(shapes, geometry, q, j, 0.0, out)
            if n > 0 and min(out.separations[0], out.separations[n - 1]) <= 0.0:
                return True
    return False


@tick_kernel
def sense(sensors, bodies, shapes, tick, events):
    """Update what overlaps each sensor body and record the bodies that entered or left (the events
    buffer has room for one event per dynamic body and sensor body)."""
    x, angle, active, body_type = bodies.x, bodies.angle, bodies.active, bodies.body_type
    extent = bodies.extent
    first_shape, shape_count, radius = bodies.first_shape, bodies.shape_count, shapes.radius
    inside = sensors.inside
    for k in range(sensors.body.shape[0]):
        sb = sensors.body[k]
        first, count = first_shape[sb], shape_count[sb]
        c = math.cos(angle[sb])
        s = math.sin(angle[sb])
        lo_x = lo_y = np.inf
        hi_x = hi_y = -np.inf
        for q in range(first, first + count):
            if not shapes.sensor[q]:
                continue
            q_lo_x, q_lo_y, q_hi_x, q_hi_y = place_piece(shapes, q, x[sb, 0], x[sb, 1], c, s,
                                                         sensors.geometry, q)
            lo_x = min(lo_x, q_lo_x - radius[q])
            lo_y = min(lo_y, q_lo_y - radius[q])
            hi_x = max(hi_x, q_hi_x + radius[q])
            hi_y = max(hi_y, q_hi_y + radius[q])
        for b in range(x.shape[0]):
            now = False
            if active[b] and body_type[b] == DYNAMIC and b != sb:
                reach = extent[b]
                for j in range(first_shape[b], first_shape[b] + shape_count[b]):
                    reach = max(reach, extent[b] + radius[j])
                if lo_x - reach <= x[b, 0] <= hi_x + reach and lo_y - reach <= x[b, 1] <= hi_y + reach:
                    now = _overlaps(shapes, sensors, first, count, b, bodies)
            if now != inside[k, b]:
                inside[k, b] = now
                record_event(events, tick, SENSOR_ENTER if now else SENSOR_EXIT, b, sb, x[b, 0], x[b, 1], 0.0)
