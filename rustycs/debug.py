"""A small window on the step's internals, for tests and for looking into a run: every result is named.

Nothing here is needed to simulate; it reads a World's workspace (after at least one step) or runs
one stage on chosen shapes.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from rustycs.broad_phase import SHAPE_BITS, SHAPE_MASK
from rustycs.constants import SPECULATIVE_DISTANCE
from rustycs.contact_batches import schedule as schedule_chunks
from rustycs.contact_solver import INV_INERTIA, INV_MASS, LANES
from rustycs.geometry import new_geometry, update_geometry
from rustycs.narrow_phase import (
    FEATURE_BITS,
    NX,
    NY,
    SEPARATION,
    narrow_phase,
    new_contacts,
    no_sleeping_points,
)
from rustycs.pieces import MAX_VERTICES
from rustycs.shapes import Shape
from rustycs.world import World


def _workspace(world: World):
    if world._workspace is None:
        raise ValueError("step the world first: its step buffers are made by the first step")
    return world._workspace


def shape_bodies(world: World) -> np.ndarray:
    """(S,) the body of each shape row the kernels collide (a concave polygon or a chain gives several)."""
    return world._shapes.view().body.copy()


def hitboxes(world: World) -> np.ndarray:
    """(S, 4) each shape row's hitbox of the last tick (xmin, ymin, xmax, ymax)."""
    return _workspace(world).geometry.hitbox.copy()


def fat_hitboxes(world: World) -> np.ndarray:
    """(S, 4) the fat hitboxes the broad phase's pairs were last found for."""
    return _workspace(world).pairs.fat_hitbox.copy()


def pairs(world: World) -> np.ndarray:
    """(P, 2) the broad phase's candidate pairs of shape rows, sorted."""
    pair_set = _workspace(world).pairs
    keys = pair_set.keys[: pair_set.count[0]]
    return np.stack([keys >> SHAPE_BITS, keys & SHAPE_MASK], axis=1)


def clearance(world: World) -> np.ndarray:
    """(P,) for each of `pairs`, the last tick's lower bound on the gap of its surfaces that continuous
    collision compares with its bodies' travel (inf: the solver's points held the pair; 0: none known)."""
    ws = _workspace(world)
    return ws.contacts.clearance[: ws.pairs.count[0]].copy()


class Schedule(NamedTuple):
    """How the last tick's manifolds were placed in the solver's chunks of LANES slots."""

    chunks: int
    slot_manifold: np.ndarray  # (chunks * LANES,) the manifold of each slot, -1 where empty
    slot_a: np.ndarray  # (chunks * LANES,) its bodies, -1 where empty
    slot_b: np.ndarray
    chunk_points: np.ndarray  # (chunks,) the largest point count of each chunk
    body_a: np.ndarray  # (M,) the manifolds' bodies
    body_b: np.ndarray
    point_count: np.ndarray  # (M,)
    movable: np.ndarray  # (N,) bool: bodies the solver moves
    group_chunks: np.ndarray  # (G + 1,) the first chunk of each group of islands (then the chunk count)
    group_bodies: list[np.ndarray]  # (G,) each group's bodies (the last: those of no manifold)


def schedule(world: World) -> Schedule:
    """The schedule of the world's last contacts, as the last tick made it."""
    ws = _workspace(world)
    m = ws.contacts.manifolds
    n_man = int(ws.contacts.count[0])
    inputs = world._kernel_inputs()
    batches = ws.batches
    n_chunks = schedule_chunks(m, n_man, ws.body, inputs.bodies.body_type, world.joint_count > 0, batches)
    n_groups = int(batches.last[2])
    starts = batches.group_bodies
    fill = ws.batches.fill[:n_chunks]
    used = (np.arange(n_chunks * LANES) % LANES) < np.repeat(fill, LANES)
    slots = [np.where(used, array[: n_chunks * LANES], -1)
             for array in (ws.batches.slot_manifold, ws.batches.slot_a, ws.batches.slot_b)]
    return Schedule(n_chunks, *slots, ws.batches.chunk_points[:n_chunks].copy(), m.body_a[:n_man].copy(),
                    m.body_b[:n_man].copy(), m.count[:n_man].copy(),
                    (ws.body[:, INV_MASS] != 0.0) | (ws.body[:, INV_INERTIA] != 0.0),
                    batches.group_chunks[: n_groups + 1].copy(),
                    [batches.body_order[starts[g]:starts[g + 1]].copy() for g in range(n_groups)])


class Manifold(NamedTuple):
    """One pair's contact: the normal from the first shape to the second and per point its world
    position, depth (negative: a gap) and feature id."""

    normal: np.ndarray  # (2,)
    points: np.ndarray  # (k, 2)
    depths: np.ndarray  # (k,)
    ids: np.ndarray  # (k,) int64


def collide(a: tuple[Shape, tuple[float, float], float], b: tuple[Shape, tuple[float, float], float],
            margin: float = 0.02) -> list[Manifold]:
    """The manifolds the narrow phase gives two posed shapes (shape, body origin, angle), one per pair
    of their shape rows that touch within `margin`, in row order."""
    world = World()
    for shape, origin, angle in (a, b):  # lines on static bodies: the narrow phase does not mind
        kind = "dynamic" if shape.has_area else "static"
        world.add_body(shape, position=origin, angle=angle, body_type=kind)
    inputs = world._kernel_inputs()
    bodies, shapes = inputs.bodies, inputs.shapes
    geometry = new_geometry(world.body_count, len(shapes.body), MAX_VERTICES)
    update_geometry(bodies, shapes, SPECULATIVE_DISTANCE, world.dt, True, geometry)
    geometry.hitbox[:] = (-np.inf, -np.inf, np.inf, np.inf)  # every pair is tested
    geometry.reach[:] = margin  # a pair's points are kept within the margin
    rows = np.arange(len(shapes.body))
    keys = np.array([(i << SHAPE_BITS) | j for i in rows[shapes.body == 0] for j in rows[shapes.body == 1]],
                    dtype=np.int64)
    contacts = new_contacts(max(len(keys), 1), False, no_sleeping_points())
    n_man, _ = narrow_phase(keys, len(keys), bodies, shapes, geometry, margin, world.dt, False,
                            contacts)  # at rest
    m, p = contacts.manifolds, contacts.points
    found = []
    for k in range(n_man):
        span = slice(m.first[k], m.first[k] + m.count[k])
        found.append(Manifold(m.data[k, NX:NY + 1].copy(), p.position[span].copy(), -p.data[span, SEPARATION],
                              p.key[span] & ((1 << FEATURE_BITS) - 1)))
    return found
