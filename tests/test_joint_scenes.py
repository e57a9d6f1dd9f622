"""The joint demos and bench scenes: what scenes/make_joint_scenes.py writes is what scenes/ holds, and
the mechanisms move as designed (the pulley keeps its rope's length, the gears their ratios, the crank
drives the piston over its stroke); the joint grid runs in small."""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import h5py
import numpy as np
import pytest

from rustycs_cli.yaml_source import dump_scene_yaml

SCENES = Path(__file__).resolve().parents[1] / "scenes"


@pytest.fixture(scope="module")
def make():
    spec = importlib.util.spec_from_file_location("make_joint_scenes", SCENES / "make_joint_scenes.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def run(cli, scene: dict, tmp_path: Path, *args: str) -> h5py.File:  # noqa: ANN001
    path = tmp_path / f"{scene['name']}.yaml"
    path.write_text(dump_scene_yaml(scene))
    result = cli("run", path, "--out", tmp_path / f"{scene['name']}.h5", "--quiet", *args)
    assert result.exit_code == 0, result.stderr
    return h5py.File(tmp_path / f"{scene['name']}.h5", "r")


def test_the_demo_files_are_what_the_script_writes(make):
    for scene in (factory() for factory in make.DEMOS):
        assert (SCENES / f"{scene['name']}.yaml").read_text() == dump_scene_yaml(scene, make._header("../"))


def test_the_joint_grid_file_is_box2ds_grid(make):
    lines = (SCENES / "bench" / "joint_grid.yaml").read_text().splitlines()
    bodies = [line for line in lines if line.startswith("  - {name: c-")]
    joints = [line for line in lines if line.startswith(("  - {name: v-", "  - {name: h-"))]
    assert len(bodies) == 100 * 100 and len(joints) == 2 * 100 * 99 == 19_800
    assert sum("type: static" in line for line in bodies) == 7
    assert lines[2] == "name: joint_grid"


def body(file: h5py.File, name: str) -> int:
    return list(file["particles/bodies/name"].asstr()[()]).index(name)


def test_a_small_joint_grid_hangs_together(cli, make, tmp_path: Path, monkeypatch):
    monkeypatch.setattr(make, "GRID", 10)
    scene = make.joint_grid()
    assert len(scene["joints"]) == 180
    with run(cli, scene, tmp_path, "--ticks", "120") as file:
        position = file["particles/bodies/position/value"][-1]
        assert file["parameters"].attrs["status"] == "complete"
    # each circle's neighbours stay 1 m away, give or take the joints' softness
    grid = position.reshape(10, 10, 2)
    gaps = np.concatenate([np.hypot(*(grid[:, 1:] - grid[:, :-1]).T).ravel(),
                           np.hypot(*(grid[1:] - grid[:-1]).T).ravel()])
    assert np.abs(gaps - 1.0).max() < 0.02


def test_the_pulley_keeps_its_rope_and_the_heavier_crate_goes_down(cli, make, tmp_path: Path):
    with run(cli, make.pulley(), tmp_path) as file:
        position = file["particles/bodies/position/value"][()]
    heavy, light = position[:, 0], position[:, 1]
    rope = (5.0 - 0.3 - heavy[:, 1]) + (5.0 - 0.3 - light[:, 1])
    assert np.abs(rope - rope[0]).max() < 0.01
    assert heavy[-1, 1] < -1.0 and light[-1, 1] > 1.0


def test_the_gear_train_turns_at_its_ratios(cli, make, tmp_path: Path):
    with run(cli, make.gear_train(), tmp_path) as file:
        angle = file["particles/bodies/angle/value"][-1]
        rack = file["particles/bodies/position/value"][-1, 3, 0] - 2.25
    drive, idler, pinion = angle[:3]
    assert drive == pytest.approx(5.0, rel=0.02)  # 1 rad/s for 5 s
    assert idler == pytest.approx(-2.0 * drive, rel=0.01) and pinion == pytest.approx(4.0 * drive, rel=0.01)
    assert rack == pytest.approx(0.25 * pinion, rel=0.01)


def test_the_crank_drives_the_piston_over_its_stroke(cli, make, tmp_path: Path):
    with run(cli, make.crank_slider(), tmp_path) as file:
        piston = file["particles/bodies/position/value"][:, 2]
        crank = file["particles/bodies/angular_velocity/value"][:, 0]
    assert np.abs(piston[:, 1]).max() < 0.01  # on its axis
    assert crank[60:].mean() == pytest.approx(3.0, rel=0.01)  # the motor's speed
    reach = math.sqrt(3.0)  # crank 1 m, rod 2 m: the piston moves between 1 and 3 m
    assert piston[:, 0].max() == pytest.approx(3.0, abs=0.02)
    assert piston[:, 0].min() == pytest.approx(1.0, abs=0.02)
    assert piston[0, 0] == pytest.approx(reach)
