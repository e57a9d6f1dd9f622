"""Joint scenes run through `rustycs run`: the pendulum's period, Newton's cradle, the trajectory's /joints
and /events, and a joint key overridden on the command line."""

from __future__ import annotations

import math
from pathlib import Path

import h5py
import numpy as np
import pytest

from rustycs_cli.trajectory import read_strings

SCENES = Path(__file__).resolve().parents[1] / "scenes"
G = 9.81


def run(cli, scene: Path | str, out: Path, *args: str) -> h5py.File:  # noqa: ANN001
    if not isinstance(scene, Path):
        path = out.with_suffix(".yaml")
        path.write_text(scene)
        scene = path
    result = cli("run", scene, "--out", out, "--quiet", *args)
    assert result.exit_code == 0, result.stderr
    return h5py.File(out, "r")


def test_the_pendulum_scene_swings_with_period_two_pi_sqrt_l_over_g(cli, tmp_path: Path) -> None:
    with run(cli, SCENES / "pendulum.yaml", tmp_path / "pendulum.h5") as file:
        x = file["particles/bodies/position/value"][:, 0, 0]
        dt = file["parameters"].attrs["dt"]
    k = np.nonzero(np.sign(x[:-1]) != np.sign(x[1:]))[0]
    crossings = (k + x[k] / (x[k] - x[k + 1])) * dt
    assert len(crossings) >= 7  # 8 s: about four periods
    period = 2.0 * np.mean(np.diff(crossings))
    assert period == pytest.approx(2.0 * math.pi * math.sqrt(1.0 / G), rel=0.005)


def test_newtons_cradle_scene_hands_the_first_balls_speed_to_the_last(cli, tmp_path: Path) -> None:
    with run(cli, SCENES / "newtons_cradle.yaml", tmp_path / "cradle.h5", "--ticks", "180") as file:
        velocity = file["particles/bodies/velocity/value"][()]
    speed = np.hypot(velocity[..., 0], velocity[..., 1])
    hit = int(np.argmax(speed[:, 0]))  # the first ball is fastest just before it strikes
    assert 0 < hit < len(speed) - 20 and np.all(speed[: hit + 1, 1:] < 1e-6)  # nothing moved before
    # the first ball's speed at the bottom of a 0.6 rad swing on a 1 m string
    assert speed[hit, 0] == pytest.approx(math.sqrt(2 * G * (1 - math.cos(0.6))), rel=0.01)
    after = hit + 2
    assert speed[after, 4] == pytest.approx(speed[hit, 0], rel=0.05)  # the last ball leaves with it
    assert np.all(speed[after, :4] < 0.05 * speed[hit, 0])  # the others are left (nearly) still


HANGING = """\
world: {tick_rate: 240, ticks: 240, precision: 4}
forces: [{name: gravity, acceleration: [0, -9.81]}]
bodies:
  - {name: ceiling, type: static, shape: {type: aabb, width: 2, height: 0.2}, position: [0, 1.1]}
  - {name: bob, shape: {type: circle, radius: 0.1}, position: [0, 0], material: metal}
  - {name: arm, shape: {type: obb, width: 1, height: 0.1}, position: [2.5, 0], material: metal}
joints:
  - {name: string, type: distance, bodies: [ceiling, bob], anchors: [[0, 1], [0, 0]]}
  - {name: hinge, type: revolute, body: arm, anchor: [2, 0], break_force: 5}
output: {every: 1}
"""


def test_the_trajectory_holds_the_joints_and_their_break_events(cli, tmp_path: Path) -> None:
    with run(cli, HANGING, tmp_path / "hanging.h5") as file:
        assert file["parameters/summary"].attrs["broken_joints"] == 1
        joints = file["joints"]
        assert read_strings(joints["name"]) == ["string", "hinge"]
        assert read_strings(joints["type"]) == ["distance", "revolute"]
        assert joints["body_a"][()].tolist() == [0, -1] and joints["body_b"][()].tolist() == [1, 2]
        frames = len(file["particles/bodies/position/step"])
        force = joints["reaction_force/value"][()]
        assert force.shape == (frames, 2, 2) and joints["reaction_torque/value"].shape == (frames, 2)
        steps = file["particles/bodies/position/step"][()]
        assert joints["reaction_force/step"][()].tolist() == steps.tolist()
        weight = file["particles/bodies/mass"][1] * G
        assert force[-1, 0, 1] == pytest.approx(weight, rel=0.01) and abs(force[-1, 0, 0]) < 1e-6 * weight
        # a rod hinged at its end, released horizontal, pulls on the hinge with m g / 4 (1.9 N) at first
        # and more as it swings down: the 5 N hinge breaks on the way
        events = file["events"]
        assert read_strings(events["kind"]) == ["joint_break"]
        (tick,) = events["tick"][()].tolist()
        assert 1 < tick < 240 and events["time"][0] == pytest.approx(tick / 240)
        assert events["body_a"][()].tolist() == [1] and events["body_b"][()].tolist() == [-1]
        active = joints["active/value"][()]
        assert active[:, 0].all() and active[:, 1].tolist() == (steps < tick).tolist()
        hinge = np.hypot(force[:, 1, 0], force[:, 1, 1])
        assert hinge[steps == tick - 1] <= 5.0 < hinge[steps == tick]
        assert events["point"][0] == pytest.approx([2.0, 0.0], abs=1e-3)  # at the hinge
        assert events["speed"][()].tolist() == [0.0]


def test_a_joint_key_is_overridden_on_the_command_line(cli, tmp_path: Path) -> None:
    scene = """\
world: {tick_rate: 60, ticks: 120, precision: 4}
bodies:
  - {name: wheel, shape: {type: circle, radius: 0.5}, position: [0, 0]}
joints:
  - {name: hinge, type: revolute, body: wheel, anchor: [0, 0], motor: {speed: 1, max_torque: 100}}
"""
    with run(cli, scene, tmp_path / "motor.h5", "-s", "joints.hinge.motor.speed=3") as file:
        assert file["particles/bodies/angular_velocity/value"][-1, 0] == pytest.approx(3.0, rel=1e-3)
        assert read_strings(file["parameters/overrides"]) == ["joints.hinge.motor.speed=3"]
    result = cli("run", tmp_path / "motor.yaml", "--out", tmp_path / "x.h5",
                 "-s", "joints.hinge.motr.speed=3")
    assert result.exit_code == 2 and "unknown key 'joints.hinge.motr'" in result.stderr
