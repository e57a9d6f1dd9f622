"""Joints in `rustycs bench`: the peers build the scene's revolute and distance joints (with limits and
motors, to the world and to static bodies) and capsules, and move them as rustycs does; the joint gap
measure; joints the peers lack are refused; the joint scenes run only when named."""

from __future__ import annotations

import importlib.util
import math

import numpy as np
import pytest

from rustycs_cli.bench import peers, quality
from rustycs_cli.bench.spec import describe
from rustycs_cli.build import build_world
from rustycs_cli.errors import UserError
from rustycs_cli.loading import load_scene_text

needs_peers = pytest.mark.skipif(not all(importlib.util.find_spec(name) for name in peers.ENGINES),
                                 reason="pymunk and pyb2d3 (the bench extra) are missing")

# a rod hinged to the world at its left end, released horizontal; a capsule hinged to a static post with a
# limit; a bob on a rod from a turned static beam, pushed sideways
HINGED = """\
name: hinged
world: {tick_rate: 60, ticks: 30, precision: 4}
forces: [{name: gravity, acceleration: [0, -10]}]
bodies:
  - {name: rod, shape: {type: obb, width: 2, height: 0.1}, position: [1, 0]}
  - {name: post, type: static, shape: {type: obb, width: 0.2, height: 1}, position: [5, 0]}
  - {name: arm, shape: {type: capsule, length: 1, radius: 0.1}, position: [5.5, 0.5], angle: 0.2}
  - {name: beam, type: static, shape: {type: obb, width: 1, height: 0.2}, position: [8, 1], angle: 0.3}
  - {name: bob, shape: {type: circle, radius: 0.2}, position: [8, -1], velocity: [2, 0]}
joints:
  - {name: hinge, type: revolute, body: rod, anchor: [0, 0]}
  - {name: elbow, type: revolute, bodies: [post, arm], anchor: [5, 0.5], limits: [-0.6, 0.1],
     motor: {speed: 0, max_torque: 0.05}}
  - {name: string, type: distance, bodies: [beam, bob], anchors: [[8, 1], [8, -1]]}
"""


def hinged():
    scene = load_scene_text(HINGED, "hinged.yaml").scene
    world = build_world(scene)
    return describe(scene, world), world


def test_describe_gives_the_joints_in_their_bodies_frames():
    bench, _ = hinged()
    hinge, elbow, string = bench.joints
    assert (hinge.kind, hinge.body_a, hinge.body_b) == ("revolute", -1, 0)
    assert hinge.anchor_a == (0.0, 0.0) and hinge.anchor_b == pytest.approx((-1.0, 0.0))
    assert (elbow.body_a, elbow.body_b, elbow.limits, elbow.motor) == (1, 2, (-0.6, 0.1), (0.0, 0.05))
    assert elbow.reference_angle == pytest.approx(0.2) and elbow.anchor_a == pytest.approx((0.0, 0.5))
    c, s = math.cos(0.2), math.sin(0.2)  # (-0.5, 0) from the arm's origin, in its turned frame
    assert elbow.anchor_b == pytest.approx((-0.5 * c, 0.5 * s))
    assert string.kind == "distance" and string.length == pytest.approx(2.0)
    assert [shape.kind for shape in bench.bodies[2].shapes] == ["capsule"]
    assert bench.bodies[2].shapes[0].area == pytest.approx(math.pi * 0.01 + 0.2)
    assert quality.max_joint_gap(bench, np.array([(*b.position, b.angle) for b in bench.bodies])) < 1e-12


@needs_peers
@pytest.mark.parametrize("engine", peers.ENGINES)
def test_peers_swing_the_joints_as_rustycs_does(engine: str, compiled_engine: None):
    bench, world = hinged()
    peer = peers.build(engine, bench)
    for _ in range(30):
        peer.step()
    world.step(30)
    ours = np.column_stack([world.positions, world.angles])
    theirs = np.array(peer.poses())
    moving = [0, 2, 4]
    # half a second of swinging: the rod has turned by about 0.9 rad; the engines agree to 5 cm and
    # 0.05 rad (pymunk, one step per tick without substeps, lags by 0.04 rad)
    assert ours[0, 2] < -0.8
    assert theirs[moving] == pytest.approx(ours[moving], abs=0.05)
    assert quality.max_joint_gap(bench, theirs) < 0.02 and quality.max_joint_gap(bench, ours) < 0.02


def test_max_joint_gap_measures_how_far_the_anchors_came_apart():
    bench, _ = hinged()
    end = np.array([(*b.position, b.angle) for b in bench.bodies])
    end[0, :2] += (0.03, 0.04)  # the rod 5 cm from its hinge
    end[4, 1] -= 0.07  # the string 7 cm longer
    assert quality.max_joint_gap(bench, end) == pytest.approx(0.07)
    end[4, 1] += 0.07
    assert quality.max_joint_gap(bench, end) == pytest.approx(0.05)


@pytest.mark.parametrize("joint", [
    "{type: prismatic, body: rod, anchor: [0, 0]}",
    "{type: revolute, body: rod, anchor: [0, 0], spring: {hertz: 2}}",
    "{type: distance, body: rod, anchors: [[0, 1], [0, 0]], max_length: 2}",
])
def test_joints_the_peers_lack_are_refused(joint: str):
    rod = "{name: rod, shape: {type: obb, width: 2, height: 0.1}, position: [1, 0]}"
    text = f"name: odd\nbodies:\n  - {rod}\njoints:\n  - {joint}\n"
    scene = load_scene_text(text, "odd.yaml").scene
    with pytest.raises(UserError) as raised:
        describe(scene, build_world(scene))
    (message,) = raised.value.messages
    assert message.startswith("odd: joint '") and "revolute and rigid distance joints" in message


def test_the_joint_scenes_run_only_when_named():
    from rustycs_cli.bench.scenes import DEFAULT_IDS, default_scene_dir, find_scenes, parse_ids

    assert "joint_grid" not in DEFAULT_IDS and parse_ids(["JOINT_GRID,ragdoll_rain"]) == ["joint_grid",
                                                                                           "ragdoll_rain"]
    found = find_scenes(default_scene_dir(), ["joint_grid", "ragdoll_rain"])
    assert [path.name for path in found.values()] == ["joint_grid.yaml", "ragdoll_rain.yaml"]
