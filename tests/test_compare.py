"""`rustycs compare`: identical files, perturbed copies, tolerances, files that cannot be compared."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest
from rustycs_cli.compare import NotComparable, compare_trajectories
from rustycs_cli.errors import UserError


def fake_trajectory(path: Path, names=("a", "b", "c"), frames: int = 61, dt: float = 1 / 60) -> Path:
    """A minimal rustycs-shaped trajectory (until `rustycs run` exists)."""
    rng = np.random.default_rng(0)
    n = len(names)
    with h5py.File(path, "w") as f:
        f.create_group("h5md/creator").attrs["name"] = "rustycs"
        bodies = f.create_group("particles/bodies")
        bodies["name"] = np.array(names, dtype=h5py.string_dtype())
        steps = np.arange(frames, dtype=np.int64)
        for name, shape in (("position", (2,)), ("velocity", (2,)), ("angle", ()), ("angular_velocity", ())):
            bodies.create_dataset(f"{name}/value", data=rng.normal(size=(frames, n, *shape)), chunks=True)
        bodies["active/value"] = np.ones((frames, n), dtype=bool)
        bodies["position/step"] = steps
        f.create_group("parameters").attrs["dt"] = dt
        f["observables/kinetic_energy/value"] = rng.random(frames)
        f["observables/linear_momentum/value"] = rng.normal(size=(frames, 2))
    return path


@pytest.fixture
def pair(tmp_path: Path) -> tuple[Path, Path]:
    a = fake_trajectory(tmp_path / "a.h5")
    b = tmp_path / "b.h5"
    shutil.copy(a, b)
    return a, b


def perturb(path: Path, dataset: str, index: tuple, delta: float) -> None:
    with h5py.File(path, "r+") as f:
        f[dataset][index] += delta


def test_identical(pair):
    result = compare_trajectories(*pair)
    assert result.identical and result.verdict == "identical" and result.exit_code == 0


@pytest.mark.parametrize("block", [None, 7])
def test_perturbed_at_one_tick(pair, block):
    a, b = pair
    perturb(a, "particles/bodies/position/value", (40, 1, 0), 1e-6)
    result = compare_trajectories(a, b, block_frames=block)
    assert not result.identical and result.exit_code == 1
    position = next(q for q in result.quantities if q.name == "position")
    assert position.outside == 1
    assert position.first_tick == 40
    assert position.max_error == pytest.approx(1e-6, rel=1e-6)
    assert position.mean_error == pytest.approx(1e-6 / (61 * 3 * 2), rel=1e-6)
    assert [w["name"] for w in position.worst_bodies(result.body_names)] == ["b"]
    others = [q for q in result.quantities if q.name != "position"]
    assert all(q.outside == 0 and q.max_error == 0 for q in others)


def test_within_loose_tolerance(pair):
    a, b = pair
    perturb(a, "particles/bodies/velocity/value", (10, 0, 1), 1e-6)
    perturb(a, "observables/kinetic_energy/value", (12,), 1e-6)
    result = compare_trajectories(a, b, atol=1e-5)
    assert not result.identical and result.verdict == "within tolerance" and result.exit_code == 0
    assert compare_trajectories(a, b, atol=1e-7).exit_code == 1
    rtol = compare_trajectories(a, b, rtol=1e-3)  # relative to values of order 1
    assert rtol.exit_code == 0


def test_angle_difference_is_wrapped(pair):
    a, b = pair
    perturb(a, "particles/bodies/angle/value", (5, 2), 2 * np.pi)
    result = compare_trajectories(a, b, atol=1e-9)
    angle = next(q for q in result.quantities if q.name == "angle")
    assert angle.max_error < 1e-9 and result.exit_code == 0


def test_nan_in_one_file_is_outside_any_tolerance(pair):
    a, b = pair
    perturb(a, "particles/bodies/angular_velocity/value", (3, 0), np.nan)
    result = compare_trajectories(a, b, atol=1e9)
    q = next(q for q in result.quantities if q.name == "angular_velocity")
    assert q.outside == 1 and q.first_tick == 3 and q.max_error == np.inf
    assert result.to_json()["quantities"]["angular_velocity"]["max_error"] == "inf"


def test_different_bodies_dt_frames(tmp_path: Path):
    a = fake_trajectory(tmp_path / "a.h5")
    with pytest.raises(NotComparable, match="different bodies"):
        compare_trajectories(a, fake_trajectory(tmp_path / "b.h5", names=("a", "x", "c")))
    with pytest.raises(NotComparable, match="A has 3 bodies, B has 2"):
        compare_trajectories(a, fake_trajectory(tmp_path / "c.h5", names=("a", "b")))
    with pytest.raises(NotComparable, match="time steps"):
        compare_trajectories(a, fake_trajectory(tmp_path / "d.h5", dt=1 / 120))
    with pytest.raises(NotComparable, match="different frames"):
        compare_trajectories(a, fake_trajectory(tmp_path / "e.h5", frames=31))


def test_missing_file(tmp_path: Path):
    with pytest.raises(UserError, match="no such file"):
        compare_trajectories(tmp_path / "nope.h5", tmp_path / "nope2.h5")


def run_cli(capsys, *args: str) -> tuple[int, str, str]:
    """Run `rustycs compare ARGS` through the real entry point; return (exit code, stdout, stderr)."""
    from rustycs_cli.app import main

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr("sys.argv", ["rustycs", "compare", *args])
        with pytest.raises(SystemExit) as exit_info:
            main()
    captured = capsys.readouterr()
    return exit_info.value.code or 0, captured.out, captured.err


def test_cli_exit_codes_and_json(pair, tmp_path: Path, capsys):
    a, b = pair
    code, out, _ = run_cli(capsys, str(a), str(b))
    assert code == 0 and "identical" in out
    perturb(a, "particles/bodies/position/value", (40, 1, 0), 1e-6)
    code, out, _ = run_cli(capsys, str(a), str(b), "--json")
    assert code == 1
    report = json.loads(out)
    assert report["result"] == "different" and report["quantities"]["position"]["first_tick"] == 40
    assert report["quantities"]["position"]["worst_bodies"][0]["name"] == "b"
    code, out, _ = run_cli(capsys, str(a), str(b))
    assert code == 1 and "first at tick 40" in out
    assert run_cli(capsys, str(a), str(b), "--atol", "1e-3")[0] == 0
    other = fake_trajectory(tmp_path / "other.h5", names=("x", "y", "z"))
    code, out, err = run_cli(capsys, str(a), str(other), "--json")
    assert code == 2 and json.loads(out)["comparable"] is False
    assert "different bodies" in err and "Traceback" not in err
