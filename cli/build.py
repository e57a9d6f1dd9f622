"""Turn a validated scene into an engine World (the engine is imported only here, and only when called)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from .errors import UserError
from .scene import Aabb, Body, Circle, Material, Obb, Polygon, Scene

if TYPE_CHECKING:
    import rustycs


def material_names(scene: Scene) -> list[str]:
    """Per body, the name of its material (preset or user), or "inline" for an inline one."""
    return ["inline" if isinstance(body.material, Material) else body.material for body in scene.bodies]


def build_world(scene: Scene) -> rustycs.World:
    """A World holding the scene's settings, forces, attractors and bodies (in scene order)."""
    import rustycs

    world = rustycs.World(
        tick_rate=scene.world.tick_rate,
        precision=scene.world.precision,
        gravitational_constant=scene.world.gravitational_constant,
        bounds=None if scene.world.bounds is None else (scene.world.bounds.min, scene.world.bounds.max),
        restitution_threshold=scene.world.restitution_threshold,
    )
    for force in scene.forces:
        world.add_force(force.acceleration)
    for attractor in scene.attractors:
        world.add_attractor(
            attractor.position,
            mass=attractor.mass,
            range=attractor.range,
            min_distance=attractor.min_distance,
        )
    for body in scene.bodies:
        _check_buildable(body)
        material = scene.material_of(body)
        world.add_body(
            _shape(body),
            position=body.position,
            angle=body.angle,
            velocity=body.velocity,
            angular_velocity=body.angular_velocity,
            body_type=body.type,
            material=rustycs.Material(material.density, material.restitution, material.friction),
            mass=body.mass,
            collision_group=body.collision_group,
        )
    counts = world.vertex_counts  # a polygon split into convex pieces has none
    for body, count in zip(scene.bodies, counts, strict=True):
        if isinstance(body.shape, Polygon) and count == 0:
            raise UserError(
                f"body '{body.name}': its polygon is concave or has more than 8 vertices: {_NOT_YET}"
            )
    return world


# Until building, recording and drawing bodies made of shapes is done (the next phase), bodies that
# need it are refused here rather than run without what they ask for.
_NOT_YET = "this version of rustycs validates it but cannot run it yet"
_NEW_BODY_KEYS = (
    "collision_category",
    "collision_mask",
    "linear_damping",
    "angular_damping",
    "gravity_scale",
    "fixed_rotation",
    "bullet",
)
_NEW_SHAPE_KEYS = ("offset", "angle", "material", "sensor")


def _check_buildable(body: Body) -> None:
    """Raise a UserError when `body` needs what is not built yet: several shapes, a capsule, segment or
    chain, or any of the keys that came with them."""
    shapes = body.shapes or []
    if len(shapes) > 1:
        raise UserError(f"body '{body.name}': it has several shapes: {_NOT_YET}")
    (shape,) = shapes
    if not isinstance(shape, (Circle, Aabb, Obb, Polygon)):
        raise UserError(f"body '{body.name}': its shape is a {shape.type}: {_NOT_YET}")
    keys = [
        f"shape.{key}"
        for key in _NEW_SHAPE_KEYS
        if getattr(shape, key) != type(shape).model_fields[key].default
    ]
    keys += [key for key in _NEW_BODY_KEYS if getattr(body, key) != Body.model_fields[key].default]
    if keys:
        raise UserError(f"body '{body.name}': it sets {', '.join(keys)}: {_NOT_YET}")


def _shape(body: Body) -> rustycs.Circle | rustycs.Box | rustycs.Polygon:
    """The engine shape of a body."""
    import rustycs

    (shape,) = body.shapes or []
    if isinstance(shape, Circle):
        return rustycs.Circle(radius=shape.radius)
    if isinstance(shape, (Aabb, Obb)):
        return rustycs.Box(shape.width, shape.height, rotates=isinstance(shape, Obb))
    return rustycs.Polygon([list(v) for v in shape.vertices])
