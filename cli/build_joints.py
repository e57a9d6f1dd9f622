"""Add a scene's joints to a World, in scene order (so joint rows match `scene.joints`)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from .scene_joints import Distance, Gear, Prismatic, Pulley, Revolute, Rope, Weld, Wheel

if TYPE_CHECKING:
    import rustycs

    from .scene import Scene
    from .scene_joints import Spring


def add_joints(world: rustycs.World, scene: Scene) -> None:
    """Add every joint of `scene` to `world`, whose bodies are the scene's bodies in scene order."""
    bodies = {body.name: i for i, body in enumerate(scene.bodies)}
    rows: dict[str, int] = {}
    for joint in scene.joints:
        assert joint.name is not None  # named by validation
        common = dict(collide_connected=joint.collide_connected, break_force=joint.break_force,
                      break_torque=joint.break_torque)
        if isinstance(joint, Gear):
            rows[joint.name] = world.add_gear(rows[joint.joints[0]], rows[joint.joints[1]], joint.ratio,
                                              **common)
            continue
        first, second = joint.body_names
        pair = (None if first is None else bodies[first], bodies[second])
        rows[joint.name] = _add(world, joint, pair, common)


def _motion(motor: Any, spring: Spring | None, torque: bool = True) -> dict[str, Any]:
    """The engine keywords of an optional motor and spring."""
    found: dict[str, Any] = {}
    if motor is not None:
        found["motor_speed"] = motor.speed
        found["max_motor_torque" if torque else "max_motor_force"] = (
            motor.max_torque if torque else motor.max_force
        )
    if spring is not None:
        found.update(spring_hertz=spring.hertz, spring_damping_ratio=spring.damping_ratio)
    return found


def _add(world: rustycs.World, joint: Any, pair: tuple[int | None, int], common: dict[str, Any]) -> int:
    """Add one joint between two bodies (or the world and a body); returns its row."""
    a, b = pair
    if isinstance(joint, Revolute):
        return world.add_revolute(a, b, joint.anchor, limits=joint.limits,
                                  **_motion(joint.motor, joint.spring), **common)
    if isinstance(joint, Prismatic):
        return world.add_prismatic(a, b, joint.anchor, joint.axis, limits=joint.limits,
                                   **_motion(joint.motor, joint.spring, torque=False), **common)
    if isinstance(joint, Wheel):
        return world.add_wheel(a, b, joint.anchor, joint.axis, limits=joint.limits,
                               **_motion(joint.motor, joint.spring), **common)
    if isinstance(joint, Distance):
        return world.add_distance(a, b, joint.anchors, length=joint.length, min_length=joint.min_length,
                                  max_length=joint.max_length, **_motion(None, joint.spring), **common)
    if isinstance(joint, Rope):
        return world.add_rope(a, b, joint.anchors, length=joint.length, **common)
    if isinstance(joint, Weld):
        spring = joint.spring
        soft = {} if spring is None else dict(linear_hertz=spring.linear_hertz,
                                              angular_hertz=spring.angular_hertz,
                                              damping_ratio=spring.damping_ratio)
        return world.add_weld(a, b, joint.anchor, **soft, **common)
    assert isinstance(joint, Pulley) and a is not None
    return world.add_pulley(a, b, joint.anchors, joint.ground_anchors, joint.ratio, **common)
