"""An engine-neutral description of a benchmark scene, so that every engine builds the same bodies.

The geometry, masses and initial state are read from a freshly built rustycs World (so generators,
polygon placement and mass overrides are exactly what rustycs simulates); materials and collision
groups come from the scene model, which the World does not expose. A body is made of one shape or
several; the peers build what all three engines have alike: circles, boxes and convex polygons of at
most 8 vertices, capsules and segments, and revolute and rigid distance joints (`spec_joints`).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..errors import UserError
from .spec_joints import JointSpec, describe_joints

if TYPE_CHECKING:
    import rustycs

    from ..scene import Scene

Vec = tuple[float, float]
PEER_SHAPES = ("circle", "aabb", "obb", "polygon", "capsule", "segment")


@dataclass(frozen=True)
class ShapeSpec:
    """One shape of a body in its body's frame, about the body origin."""

    kind: str  # circle | polygon (boxes too: their four corners) | capsule | segment
    points: tuple[Vec, ...]  # a circle's centre, a polygon's corners, a capsule's or a segment's two ends
    centre: Vec  # its area centroid (a segment's midpoint)
    radius: float  # circles and capsules, else 0
    mass: float  # kg: its share of its body's mass (0 on static and kinematic bodies, and for segments)
    friction: float
    restitution: float

    @property
    def area(self) -> float:
        if self.kind == "circle":
            return math.pi * self.radius**2
        v = self.points
        if self.kind == "capsule":
            return math.pi * self.radius**2 + 2 * self.radius * math.dist(v[0], v[1])
        return 0.5 * abs(sum(v[i - 1][0] * v[i][1] - v[i][0] * v[i - 1][1] for i in range(len(v))))


@dataclass(frozen=True)
class BodySpec:
    """One body as every engine builds it."""

    kind: str  # its shape's type, or "compound"
    body_type: str  # static | dynamic | kinematic
    position: Vec  # the body origin
    angle: float
    velocity: Vec  # of the centre of mass
    angular_velocity: float
    mass: float  # kg; inf for static and kinematic bodies
    fixed_rotation: bool  # a body with an aabb, or a dynamic body of infinite inertia
    group: int  # same non-zero group: never collide
    shapes: tuple[ShapeSpec, ...]
    bullet: bool = False  # continuous collision against dynamic bodies too (Box2D's bullets; pymunk: none)


@dataclass(frozen=True)
class BenchScene:
    """A scene reduced to what the peer engines and the quality measures need."""

    name: str
    dt: float
    gravity: Vec
    attractors: tuple[tuple[float, float, float], ...]  # (x, y, G*M) of global attractors
    bodies: tuple[BodySpec, ...]
    joints: tuple[JointSpec, ...] = ()


def describe(scene: Scene, world: rustycs.World) -> BenchScene:
    """The bench description of `scene`, from `world` = build_world(scene) before its first step."""
    from rustycs.shapes import type_name

    if any(a["range"] != math.inf for a in world.attractors):
        raise UserError(f"{scene.name}: the peer engines are only given global attractors (no `range`)")
    shapes: list[list] = [[] for _ in scene.bodies]  # each body's engine shapes, as given
    for owner, shape in world.shapes:
        shapes[owner].append(shape)
    positions, angles, velocities = world.positions, world.angles, world.velocities
    spins, kinds, types = world.angular_velocities, world.shape_kinds, world.body_types
    masses, inertias = world.masses, world.inertias
    bodies = []
    for i, body in enumerate(scene.bodies):
        materials = [scene.material(body.material if shape.material is None else shape.material)
                     for shape in body.shapes or ()]
        aabb = any(type_name(shape) == "aabb" for shape in shapes[i])
        bodies.append(BodySpec(
            kind=str(kinds[i]), body_type=str(types[i]), position=_vec(positions[i]), angle=float(angles[i]),
            velocity=_vec(velocities[i]), angular_velocity=float(spins[i]), mass=float(masses[i]),
            fixed_rotation=aabb or (types[i] == "dynamic" and math.isinf(inertias[i])),
            group=body.collision_group, bullet=body.bullet,
            shapes=_shapes(scene, body.name, shapes[i], materials, float(masses[i]))))
    gravity = (sum(f.acceleration[0] for f in scene.forces), sum(f.acceleration[1] for f in scene.forces))
    g = world.gravitational_constant
    attractors = tuple((float(a["position"][0]), float(a["position"][1]), g * a["mass"])
                       for a in world.attractors)
    return BenchScene(scene.name, world.dt, gravity, attractors, tuple(bodies), describe_joints(scene))


def _shapes(scene: Scene, name: str | None, shapes: list, materials: list,
            mass: float) -> tuple[ShapeSpec, ...]:
    """One body's shapes as the engine places them (`rustycs.pieces`: a polygon's vertices counter-clockwise
    as it collides them). A dynamic body's mass (inf otherwise) is shared among its shapes with area in
    proportion to area x density, as rustycs shares it. UserError for what the peers would build
    differently: a chain, a sensor, or a polygon split into pieces (they would build its hull)."""
    from rustycs.pieces import CAPSULE, CIRCLE, SEGMENT, shape_pieces
    from rustycs.shapes import type_name

    specs = []
    for shape, material in zip(shapes, materials, strict=True):
        kind, pieces = type_name(shape), shape_pieces(shape)
        if kind not in PEER_SHAPES or shape.sensor or len(pieces) > 1:
            what = ("sensor" if shape.sensor else "concave or > 8-vertex polygon" if kind == "polygon"
                    else kind)
            raise UserError(f"{scene.name}: body '{name}' has a {what}; the peer engines are given only "
                            f"{', '.join(PEER_SHAPES[:-1])} and {PEER_SHAPES[-1]} shapes")
        (piece,) = pieces
        points = piece.vertices if len(piece.vertices) else piece.centroid.reshape(1, 2)
        specs.append(ShapeSpec(kind={CIRCLE: "circle", CAPSULE: "capsule", SEGMENT: "segment"}.get(piece.kind,
                                                                                              "polygon"),
                               points=tuple(_vec(p) for p in points), centre=_vec(piece.centroid),
                               radius=piece.radius, mass=0.0, friction=material.friction,
                               restitution=material.restitution))
    if not math.isfinite(mass):
        return tuple(specs)
    weights = [0.0 if spec.kind == "segment" else spec.area * m.density
               for spec, m in zip(specs, materials, strict=True)]
    total = sum(weights)
    return tuple(dataclasses.replace(spec, mass=mass * weight / total)
                 for spec, weight in zip(specs, weights, strict=True))


def _vec(values: object) -> Vec:
    x, y = values  # type: ignore[misc]
    return float(x), float(y)
