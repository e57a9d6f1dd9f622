"""Turn a validated scene into an engine World (the engine is imported only here, and only when called)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from .build_joints import add_joints
from .scene import Aabb, Body, Capsule, Chain, Circle, Material, MaterialRef, Obb, Polygon, Scene, Segment

if TYPE_CHECKING:
    import rustycs

    from .scenario import RunPlan
    from .scene import Shape


def material_names(scene: Scene) -> list[str]:
    """Per body, the name of its material (preset or user), or "inline" for an inline one."""
    return [_material_name(body.material) for body in scene.bodies]


def shape_material_names(scene: Scene) -> list[str]:
    """Per shape (bodies in scene order, each body's shapes in order, as `World.shapes` lists them), the
    name of the material it uses: its own, else its body's; "inline" for an inline one."""
    return [
        _material_name(body.material if shape.material is None else shape.material)
        for body in scene.bodies
        for shape in body.shapes or ()
    ]


def _material_name(ref: MaterialRef) -> str:
    return "inline" if isinstance(ref, Material) else ref


def build_world(scene: Scene, plan: RunPlan | None = None) -> rustycs.World:
    """A World holding the scene's settings, forces, attractors and bodies (in scene order); with a run's
    plan, the bodies are its scene's (emitted bodies included), each appearing and going as planned."""
    import rustycs

    world = rustycs.World(
        tick_rate=scene.world.tick_rate,
        precision=scene.world.precision,
        gravitational_constant=scene.world.gravitational_constant,
        bounds=None if scene.world.bounds is None else (scene.world.bounds.min, scene.world.bounds.max),
        restitution_threshold=scene.world.restitution_threshold,
        sleep=scene.world.sleep,
        sleep_time=scene.world.sleep_time,
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
    for index, body in enumerate(scene.bodies):
        _add_body(world, scene, body, **(plan.timing(index) if plan else {}))
    add_joints(world, scene)
    return world


def _add_body(world: rustycs.World, scene: Scene, body: Body, **timing: int | None) -> int:
    """Add one body with all its shapes and keys; returns its index."""
    return world.add_body(
        [_shape(shape, scene) for shape in body.shapes or ()],
        position=body.position,
        angle=body.angle,
        velocity=body.velocity,
        angular_velocity=body.angular_velocity,
        body_type=body.type,
        material=_engine_material(scene.material_of(body)),
        mass=body.mass,
        collision_group=body.collision_group,
        collision_category=body.collision_category,
        collision_mask=body.collision_mask,
        linear_damping=body.linear_damping,
        angular_damping=body.angular_damping,
        gravity_scale=body.gravity_scale,
        fixed_rotation=body.fixed_rotation,
        bullet=body.bullet,
        name=body.name,
        **timing,
    )


def _engine_material(material: Material) -> rustycs.Material:
    import rustycs

    return rustycs.Material(material.density, material.restitution, material.friction)


def _shape(shape: Shape, scene: Scene) -> rustycs.shapes.Shape:
    """The engine shape of a scene shape, placed and made of what it names (None: its body's material)."""
    import rustycs

    placed = {
        "offset": shape.offset,
        "angle": shape.angle,
        "material": None if shape.material is None else _engine_material(scene.material(shape.material)),
        "sensor": shape.sensor,
    }
    if isinstance(shape, Circle):
        return rustycs.Circle(shape.radius, **placed)
    if isinstance(shape, (Aabb, Obb)):
        return rustycs.Box(shape.width, shape.height, rotates=isinstance(shape, Obb), **placed)
    if isinstance(shape, Polygon):
        return rustycs.Polygon(shape.vertices, **placed)
    if isinstance(shape, Capsule):
        return rustycs.Capsule(shape.length, shape.radius, **placed)
    if isinstance(shape, Segment):
        return rustycs.Segment(shape.points, **placed)
    assert isinstance(shape, Chain)
    return rustycs.Chain(shape.points, loop=shape.loop, **placed)
