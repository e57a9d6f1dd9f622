"""An engine-neutral description of a benchmark scene, so that every engine builds the same bodies.

The geometry, masses and initial state are read from a freshly built rustycs World (so generators,
polygon placement and mass overrides are exactly what rustycs simulates); materials and collision
groups come from the scene model, which the World does not expose.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..errors import UserError

if TYPE_CHECKING:
    import rustycs

    from ..scene import Scene

Vec = tuple[float, float]


@dataclass(frozen=True)
class BodySpec:
    """One body as every engine builds it. `vertices` are about the body origin (empty for circles)."""

    kind: str  # circle | aabb | obb | polygon
    body_type: str  # static | dynamic | kinematic
    position: Vec  # the body origin
    angle: float
    velocity: Vec  # of the centre of mass
    angular_velocity: float
    radius: float
    vertices: tuple[Vec, ...]
    mass: float  # kg; inf for static and kinematic bodies
    friction: float
    restitution: float
    group: int  # same non-zero group: never collide

    @property
    def area(self) -> float:
        if self.kind == "circle":
            return math.pi * self.radius**2
        v = self.vertices
        return 0.5 * abs(sum(v[i - 1][0] * v[i][1] - v[i][0] * v[i - 1][1] for i in range(len(v))))


@dataclass(frozen=True)
class BenchScene:
    """A scene reduced to what the peer engines and the quality measures need."""

    name: str
    dt: float
    gravity: Vec
    attractors: tuple[tuple[float, float, float], ...]  # (x, y, G*M) of global attractors
    bodies: tuple[BodySpec, ...]


def describe(scene: Scene, world: rustycs.World) -> BenchScene:
    """The bench description of `scene`, from `world` = build_world(scene) before its first step."""
    if any(a["range"] != math.inf for a in world.attractors):
        raise UserError(f"{scene.name}: the peer engines are only given global attractors (no `range`)")
    positions, angles, velocities = world.positions, world.angles, world.velocities
    spins, radii = world.angular_velocities, world.radii
    counts, local = world.vertex_counts, world.local_vertices
    kinds, types, masses = world.shape_kinds, world.body_types, world.masses
    bodies = []
    for i, body in enumerate(scene.bodies):
        material = scene.material_of(body)
        bodies.append(BodySpec(
            kind=str(kinds[i]), body_type=str(types[i]), position=_vec(positions[i]), angle=float(angles[i]),
            velocity=_vec(velocities[i]), angular_velocity=float(spins[i]), radius=float(radii[i]),
            vertices=tuple(_vec(v) for v in local[i, : counts[i]]), mass=float(masses[i]),
            friction=material.friction, restitution=material.restitution, group=body.collision_group))
    gravity = (sum(f.acceleration[0] for f in scene.forces), sum(f.acceleration[1] for f in scene.forces))
    g = world.gravitational_constant
    attractors = tuple((float(a["position"][0]), float(a["position"][1]), g * a["mass"])
                       for a in world.attractors)
    return BenchScene(scene.name, world.dt, gravity, attractors, tuple(bodies))


def _vec(values: object) -> Vec:
    x, y = values  # type: ignore[misc]
    return float(x), float(y)
