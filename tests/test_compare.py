"""`rustycs compare` on real runs of a tiny scene: identical, perturbed, tolerant, not comparable."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest

from rustycs_cli.compare import NotComparable, compare_trajectories
from rustycs_cli.errors import UserError

TINY = """\
name: tiny
world: {tick_rate: 60, ticks: 60, precision: 4}
forces:
  - {name: gravity, acceleration: [0, -9.81]}
bodies:
  - {name: floor, type: static, shape: {type: aabb, width: 10, height: 0.5}, position: [0, -0.25]}
  - {name: ball, shape: {type: circle, radius: 0.2}, position: [0, 0.6], velocity: [1, 0], material: rubber}
  - {name: crate, shape: {type: obb, width: 0.4, height: 0.4}, position: [1, 0.5], angular_velocity: 2}
"""
POSITION = "particles/bodies/position/value"


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory, compiled_engine: None) -> dict[str, Path]:
    """Runs of the tiny scene: twice the same, then with other bodies, another dt, fewer frames."""
    from rustycs_cli.loading import load_scene
    from rustycs_cli.simulation import run_scene

    folder = tmp_path_factory.mktemp("runs")
    scene = folder / "tiny.yaml"
    scene.write_text(TINY)
    variants = {
        "reference": [], "again": [], "renamed": ["bodies.crate.name=box"],
        "fine_dt": ["world.tick_rate=120"], "short": ["world.ticks=30"], "every_2": ["output.every=2"],
        "every_7": ["output.every=7"],
    }
    paths = {}
    for name, overrides in variants.items():
        paths[name] = folder / f"{name}.h5"
        result = run_scene(load_scene(scene, overrides), paths[name], quiet=True)
        assert result.status == "complete"
    return paths


@pytest.fixture
def copy(runs: dict[str, Path], tmp_path: Path) -> Path:
    """A writable copy of the reference run, to perturb."""
    return Path(shutil.copy(runs["reference"], tmp_path / "copy.h5"))


def perturb(path: Path, dataset: str, index: tuple, delta: float) -> None:
    with h5py.File(path, "r+") as f:
        f[dataset][index] += delta


def quantity(result, name: str):
    return next(q for q in result.quantities if q.name == name)


def test_repeated_run_is_identical(runs):
    result = compare_trajectories(runs["again"], runs["reference"])
    assert result.identical and result.verdict == "identical" and result.exit_code == 0
    assert result.frames == 61 and result.body_names == ["floor", "ball", "crate"]
    assert {q.name for q in result.quantities} >= {
        "position", "angle", "velocity", "angular_velocity", "active", "asleep", "kinetic_energy",
        "linear_momentum"}


@pytest.mark.parametrize("block", [None, 7])  # 7: the difference is found in a later block
def test_perturbed_at_one_tick(runs, copy, block):
    perturb(copy, POSITION, (40, 1, 0), 1e-6)
    result = compare_trajectories(copy, runs["reference"], block_frames=block)
    assert not result.identical and result.exit_code == 1 and result.verdict == "different"
    position = quantity(result, "position")
    assert position.outside == 1 and position.first_tick == 40
    assert position.max_error == pytest.approx(1e-6, rel=1e-6)
    assert position.mean_error == pytest.approx(1e-6 / (61 * 3 * 2), rel=1e-6)
    assert position.worst_bodies(result.body_names) == [
        {"name": "ball", "max_error": pytest.approx(1e-6, rel=1e-6), "outside": 1}]
    assert all(q.outside == 0 and q.max_error == 0 for q in result.quantities if q.name != "position")


def test_within_loose_tolerance(runs, copy):
    perturb(copy, "particles/bodies/velocity/value", (10, 2, 1), 1e-6)
    perturb(copy, "observables/kinetic_energy/value", (12,), 1e-6)
    reference = runs["reference"]
    loose = compare_trajectories(copy, reference, atol=1e-5)
    assert not loose.identical and loose.verdict == "within tolerance" and loose.exit_code == 0
    tight = compare_trajectories(copy, reference, atol=1e-7)
    assert tight.exit_code == 1
    assert quantity(tight, "velocity").first_tick == 10 and quantity(tight, "kinetic_energy").first_tick == 12
    assert compare_trajectories(copy, reference, rtol=1e-3).exit_code == 0  # |value| is of order 1


def test_angle_difference_is_wrapped(runs, copy):
    perturb(copy, "particles/bodies/angle/value", (5, 2), 2 * np.pi)
    result = compare_trajectories(copy, runs["reference"], atol=1e-9)
    assert quantity(result, "angle").max_error < 1e-9 and result.exit_code == 0


def test_nan_in_one_file_is_outside_any_tolerance(runs, copy):
    perturb(copy, "particles/bodies/angular_velocity/value", (3, 2), np.nan)
    result = compare_trajectories(copy, runs["reference"], atol=1e9)
    q = quantity(result, "angular_velocity")
    assert q.outside == 1 and q.first_tick == 3 and q.max_error == np.inf
    from rustycs_cli.summary import to_json

    assert json.loads(to_json(result.to_json()))["quantities"]["angular_velocity"]["max_error"] is None


def test_not_comparable(runs):
    reference = runs["reference"]
    with pytest.raises(NotComparable, match="body 2 is 'box' in A and 'crate' in B"):
        compare_trajectories(runs["renamed"], reference)
    with pytest.raises(NotComparable, match="different time steps"):
        compare_trajectories(runs["fine_dt"], reference)
    with pytest.raises(NotComparable, match="different lengths .A ends at tick 30, B at tick 60"):
        compare_trajectories(runs["short"], reference)


def test_runs_recorded_at_different_every_are_compared_on_the_ticks_they_share(runs, cli):
    result = compare_trajectories(runs["every_2"], runs["reference"])
    assert (result.frames, result.frames_a, result.frames_b) == (31, 31, 61)
    assert result.identical  # the same run, sampled: every shared frame is bitwise equal
    # ticks 0, 7, ..., 56 and the last (60) against 0, 2, ..., 60: shared 0, 14, 28, 42, 56, 60
    result = compare_trajectories(runs["every_7"], runs["every_2"])
    assert (result.frames, result.frames_a, result.frames_b) == (6, 10, 31) and result.identical
    shown = cli("compare", runs["every_2"], runs["reference"])
    assert shown.exit_code == 0
    assert "compared the 31 frames at ticks both recorded (A has 31, B 61)" in shown.stdout


def test_missing_file(tmp_path: Path, runs):
    with pytest.raises(UserError, match="no such file"):
        compare_trajectories(tmp_path / "nope.h5", runs["reference"])


def test_cli_exit_codes_and_json(cli, runs, copy):
    reference = runs["reference"]
    same = cli("compare", runs["again"], reference)
    assert same.exit_code == 0 and "identical" in same.stdout
    perturb(copy, POSITION, (40, 1, 0), 1e-6)
    differ = cli("compare", copy, reference, "--json")
    assert differ.exit_code == 1
    report = json.loads(differ.stdout)
    assert report["result"] == "different" and report["quantities"]["position"]["first_tick"] == 40
    assert report["quantities"]["position"]["worst_bodies"][0]["name"] == "ball"
    table = cli("compare", copy, reference)
    assert table.exit_code == 1 and "first at tick 40" in table.stdout and "ball" in table.stdout
    tolerant = cli("compare", copy, reference, "--atol", "1e-3")
    assert tolerant.exit_code == 0 and "within tolerance" in tolerant.stdout
    other = cli("compare", runs["renamed"], reference, "--json")
    assert other.exit_code == 2 and json.loads(other.stdout)["comparable"] is False
    assert "different bodies" in other.stderr and "Traceback" not in other.stderr
    assert cli("compare", copy, reference, "--atol", "-1").exit_code == 2
