"""Joints in scene files: every type validates and builds, each cross-entry problem is reported at its
place with exit code 2, and joint keys are overridden by joint name like any other key."""

from __future__ import annotations

from pathlib import Path

import pytest

from rustycs_cli.build import build_world
from rustycs_cli.errors import UserError
from rustycs_cli.loading import load_scene_text
from rustycs_cli.scene_joints import JOINTS

BODIES = """\
bodies:
  - {name: base, type: static, shape: {type: aabb, width: 1, height: 1}, position: [0, 0]}
  - {name: arm, shape: {type: obb, width: 1, height: 0.1}, position: [0.5, 1]}
  - {name: bob, shape: {type: circle, radius: 0.1}, position: [2, 0]}
"""
EVERY_JOINT = BODIES + """\
joints:
  - {name: hinge, type: revolute, bodies: [base, arm], anchor: [0, 1], limits: [-0.5, 0.5],
     motor: {speed: 2, max_torque: 50}, spring: {hertz: 4, damping_ratio: 0.7}, break_torque: 100}
  - {name: slide, type: prismatic, bodies: [base, bob], anchor: [2, 0], axis: [1, 0], limits: [-1, 1],
     motor: {speed: 0.5, max_force: 20}}
  - {name: spring, type: distance, body: bob, anchors: [[2, 2], [2, 0]], min_length: 1, max_length: 3,
     spring: {hertz: 2}}
  - {name: leash, type: rope, bodies: [arm, bob], anchors: [[1, 1], [2, 0]], length: 2}
  - {name: glue, type: weld, bodies: [arm, bob], anchor: [1, 0.5],
     spring: {linear_hertz: 5, angular_hertz: 2, damping_ratio: 0.5}, collide_connected: true}
  - {name: axle, type: wheel, bodies: [arm, bob], anchor: [2, 0], spring: {hertz: 4}, limits: [-0.2, 0.2],
     motor: {speed: -10, max_torque: 5}, break_force: 1000}
  - {name: gearing, type: gear, joints: [hinge, slide], ratio: 2}
  - {name: rope, type: pulley, bodies: [arm, bob], anchors: [[1, 1], [2, 0]],
     ground_anchors: [[1, 3], [2, 3]]}
  - {type: revolute, body: arm, anchor: [0, 1]}
"""


def test_every_joint_type_validates_and_builds_in_scene_order() -> None:
    scene = load_scene_text(EVERY_JOINT, "joints.yaml").scene
    assert [joint.type for joint in scene.joints] == [*JOINTS, "revolute"]
    assert scene.joints[-1].name == "revolute-8"  # the default name
    world = build_world(scene)
    assert list(world.joint_types) == [joint.type for joint in scene.joints]
    bodies = world.joint_bodies
    assert bodies[0].tolist() == [0, 1] and bodies[2].tolist() == [-1, 2] and bodies[8].tolist() == [-1, 1]
    # the resolved text is a scene that loads to the same joints
    again = load_scene_text(load_scene_text(EVERY_JOINT, "joints.yaml").text, "again.yaml").scene
    assert again.joints == scene.joints


BAD = BODIES + """\
joints:
  - {name: hinge, type: revolute, bodies: [base, arm], anchor: [0, 1], limits: [0.5, -0.5]}
  - {name: hinge, type: revolute, bodies: [base, lever], anchor: [0, 1]}
  - {name: twice, type: revolute, bodies: [arm, arm], anchor: [0, 1]}
  - {name: coil, type: distance, body: arm, anchors: [[0, 2], [0.5, 1]], length: -1, spring: {hertz: -2}}
  - {name: rod, type: distance, body: arm, anchors: [[0, 2], [0.5, 1]]}
  - {name: gear, type: gear, joints: [hinge, rod]}
  - {name: gear2, type: gear, joints: [hinge, nothing]}
  - {name: slide, type: prismatic, body: ghost, anchor: [0, 1], limits: [1, 0]}
  - {name: odd, type: hinje, body: arm}
"""


def test_each_joint_problem_is_reported_at_its_place_with_exit_code_2(cli, tmp_path: Path) -> None:
    path = tmp_path / "bad.yaml"
    path.write_text(BAD)
    result = cli("validate", path)
    assert result.exit_code == 2 and "Traceback" not in result.stderr
    assert result.stderr.splitlines() == [
        f"{path}:6:86: joints.hinge.limits.1: limits must be [lower, upper] with lower <= upper",
        f"{path}:7:12: joints.hinge.name: duplicate joint name 'hinge'",
        f"{path}:7:50: joints.hinge.bodies.1: unknown body 'lever'",
        f"{path}:8:49: joints.twice.bodies.1: the joint names body 'arm' twice",
        f"{path}:9:82: joints.coil.length: Input should be greater than or equal to 0 (got -1)",
        f"{path}:9:102: joints.coil.spring.hertz: Input should be greater than or equal to 0 (got -2)",
        f"{path}:11:46: joints.gear.joints.1: a gear couples revolute or prismatic joints; 'rod' is a "
        "distance joint",
        f"{path}:12:47: joints.gear2.joints.1: unknown joint 'nothing' (did you mean 'hinge'?)",
        f"{path}:13:42: joints.slide.body: unknown body 'ghost'",
        f"{path}:13:77: joints.slide.limits.1: limits must be [lower, upper] with lower <= upper",
        f"{path}:14:23: joints.odd.type: unknown joint type 'hinje'; expected one of: revolute, prismatic, "
        "distance, rope, weld, wheel, gear, pulley",
    ]


@pytest.mark.parametrize(("joint", "message"), [
    ("{type: revolute, anchor: [0, 1]}", "missing key 'bodies'"),
    ("{type: revolute, bodies: [base, arm], body: arm, anchor: [0, 1]}", "not both"),
    ("{type: pulley, body: arm, anchors: [[0, 0], [0, 0]], ground_anchors: [[0, 1], [0, 1]]}",
     "a pulley hangs two bodies"),
    ("{name: g, type: gear, joints: [g, g]}", "names joint 'g' twice"),
    ("{type: distance, body: arm, anchors: [[0, 2], [0.5, 1]], min_length: 2, max_length: 1}",
     "min_length must not exceed max_length"),
])
def test_malformed_joints_are_refused(joint: str, message: str) -> None:
    with pytest.raises(UserError) as raised:
        load_scene_text(BODIES + f"joints:\n  - {joint}\n", "s.yaml")
    assert any(message in line for line in raised.value.messages), raised.value.messages


def test_a_gear_is_listed_after_the_joints_it_couples() -> None:
    text = BODIES + """\
joints:
  - {name: gearing, type: gear, joints: [hinge, slide]}
  - {name: hinge, type: revolute, body: arm, anchor: [0, 1]}
  - {name: slide, type: prismatic, body: bob, anchor: [2, 0]}
"""
    with pytest.raises(UserError) as raised:
        load_scene_text(text, "s.yaml")
    after = "list the gear after the joints it couples"
    assert raised.value.messages == [
        f"s.yaml:6:42: joints.gearing.joints.0: {after} ('hinge' comes later)",
        f"s.yaml:6:49: joints.gearing.joints.1: {after} ('slide' comes later)",
    ]


def test_joint_keys_are_overridden_by_joint_name() -> None:
    scene = load_scene_text(EVERY_JOINT, "joints.yaml", ["joints.hinge.motor.speed=3"]).scene
    assert scene.joints[0].motor is not None and scene.joints[0].motor.speed == 3
    scene = load_scene_text(EVERY_JOINT, "joints.yaml", ["joints.1.axis=[0,1]",
                                                         "joints.revolute-8.limits=[-1,1]"]).scene
    assert scene.joints[1].axis == (0, 1) and scene.joints[8].limits == (-1, 1)
    with pytest.raises(UserError) as raised:
        load_scene_text(EVERY_JOINT, "joints.yaml",
                        ["joints.hinj.motor.speed=3", "joints.hinge.motor.sped=1"])
    assert raised.value.messages == [
        "--set joints.hinj.motor.speed=3: unknown key 'joints.hinj': no item 'hinj' in 'joints' (a name or "
        "an index 0..8) (did you mean 'joints.hinge'?)",
        "--set joints.hinge.motor.sped=1: unknown key 'joints.hinge.motor.sped' (did you mean "
        "'joints.hinge.motor.speed'?)",
    ]
