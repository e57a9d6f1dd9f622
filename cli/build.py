"""Turn a validated scene into an engine World (the engine is imported only here, and only when called)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from .scene import Aabb, Body, Circle, Material, Obb, Scene

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
    return world


def _shape(body: Body) -> rustycs.Circle | rustycs.Box | rustycs.Polygon:
    """The engine shape of a body."""
    import rustycs

    shape = body.shape
    if isinstance(shape, Circle):
        return rustycs.Circle(radius=shape.radius)
    if isinstance(shape, (Aabb, Obb)):
        return rustycs.Box(shape.width, shape.height, rotates=isinstance(shape, Obb))
    return rustycs.Polygon([list(v) for v in shape.vertices])
