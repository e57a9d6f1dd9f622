"""`rustycs run` end to end (in-process through the real entry point): outputs, options, repeat from .h5."""

from __future__ import annotations

import json
from pathlib import Path

import h5py
import numpy as np
import pytest

pytestmark = pytest.mark.usefixtures("compiled_engine")


def attrs(path: Path, group: str) -> dict:
    with h5py.File(path, "r") as f:
        return {k: v.decode() if isinstance(v, bytes) else v for k, v in f[group].attrs.items()}


def test_five_bodies_json_summary_everywhere(cli, five_body_scene: Path, tmp_path: Path):
    out = tmp_path / "runs.h5"
    result = cli("run", five_body_scene, "--out", out, "--json", "-s", "world.ticks=45")
    assert result.exit_code == 0, result.stderr
    summary = json.loads(result.stdout)  # nothing but the JSON on stdout
    assert summary["scene"] == "five" and summary["status"] == "complete"
    assert summary["ticks"] == 45 and summary["frames"] == 46
    assert summary["simulated_seconds"] == pytest.approx(0.75)
    assert summary["bodies"] == 5 and summary["dynamic_bodies"] == 3
    assert summary["total_contact_points"] > 0 and summary["peak_contact_points"] > 0
    assert summary["escaped_bodies"] == 0
    assert summary["step_seconds"] > 0 and summary["wall_seconds"] > summary["step_seconds"]
    assert json.loads((tmp_path / "runs.summary.json").read_text()) == summary
    stored = attrs(out, "parameters/summary")
    assert summary["measures"] == {}  # the scene has none; each would be an attribute measure.<name>
    assert summary["emitters"] == {}  # nor emitters: attributes emitter.<name>.appeared and .skipped
    assert stored == {k: v for k, v in summary.items() if v is not None and k not in ("measures", "emitters")}
    parameters = attrs(out, "parameters")
    assert parameters["status"] == "complete" and parameters["ticks_completed"] == 45
    assert parameters["dt"] == pytest.approx(1 / 60) and parameters["precision"] == 8
    assert parameters["scene_sha256"] == summary["scene_sha256"]
    with h5py.File(out, "r") as f:
        assert f["particles/bodies/position/value"].shape == (46, 5, 2)
        assert list(f["parameters/overrides"].asstr()[()]) == ["world.ticks=45"]
        assert "contacts" in f
    assert sorted(p.name for p in tmp_path.iterdir()) == ["five.yaml", "runs.h5", "runs.summary.json"]


def test_default_output_and_table(cli, five_body_scene: Path, tmp_path: Path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    result = cli("run", five_body_scene, "--ticks", "5")
    assert result.exit_code == 0, result.stderr
    assert (tmp_path / "outputs" / "five.h5").is_file()
    assert (tmp_path / "outputs" / "five.summary.json").is_file()
    assert "status" in result.stdout and "complete" in result.stdout and "five.h5" in result.stdout
    quiet = cli("run", five_body_scene, "--ticks", "5", "--quiet")
    assert quiet.exit_code == 0 and quiet.stdout == "" and quiet.stderr == ""


def test_every_ticks_seed_and_contacts_options(cli, five_body_scene: Path, tmp_path: Path):
    out = tmp_path / "every.h5"
    result = cli("run", five_body_scene, "--out", out, "--every", "7", "--ticks", "30", "--no-contacts",
                 "--seed", "42", "--quiet")
    assert result.exit_code == 0, result.stderr
    with h5py.File(out, "r") as f:
        np.testing.assert_array_equal(f["particles/bodies/position/step"][()], [0, 7, 14, 21, 28, 30])
        assert "contacts" not in f
        assert f["parameters"].attrs["seed"] == 42 and f["parameters"].attrs["every"] == 7


def test_compile_notice_once_on_stderr(cli, five_body_scene: Path, tmp_path: Path, monkeypatch):
    import rustycs

    monkeypatch.setattr(rustycs, "compile_needed", lambda: True)
    result = cli("run", five_body_scene, "--out", tmp_path / "n.h5", "--ticks", "2", "--json")
    assert result.exit_code == 0
    assert result.stderr.count("rustycs: compiling the engine (happens once") == 1
    json.loads(result.stdout)


def datasets(path: Path) -> dict[str, np.ndarray]:
    """Every state, observable and contact array of a run (everything but timings and provenance)."""
    found: dict[str, np.ndarray] = {}
    with h5py.File(path, "r") as f:
        def visit(name: str, item) -> None:
            if isinstance(item, h5py.Dataset) and not name.startswith(("parameters", "h5md")):
                found[name] = item[()]
        f.visititems(visit)
    return found


def test_run_from_trajectory_is_bitwise_identical(cli, five_body_scene: Path, tmp_path: Path):
    first, second = tmp_path / "first.h5", tmp_path / "second.h5"
    assert cli("run", five_body_scene, "--out", first, "--quiet", "-s", "bodies.ball.velocity=[2,1]",
               "-s", "world.ticks=40").exit_code == 0
    result = cli("run", first, "--out", second, "--json")
    assert result.exit_code == 0, result.stderr
    a, b = datasets(first), datasets(second)
    assert a.keys() == b.keys() and "contacts/point" in a and "particles/bodies/velocity/value" in a
    for name in a:
        assert a[name].dtype == b[name].dtype, name
        assert np.array_equal(a[name], b[name]), name
    assert a["particles/bodies/velocity/value"][0, 1].tolist() == [2.0, 1.0]  # the override was applied
    with h5py.File(first, "r") as f, h5py.File(second, "r") as g:
        assert f["parameters/scene"][()] == g["parameters/scene"][()]
        assert list(g["parameters/overrides"].asstr()[()]) == ["bodies.ball.velocity=[2,1]", "world.ticks=40"]
    assert json.loads(result.stdout)["scene_sha256"] == attrs(first, "parameters")["scene_sha256"]


def test_rerun_never_overwrites_its_source_by_default(cli, five_body_scene: Path, tmp_path: Path,
                                                       monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert cli("run", five_body_scene, "--ticks", "3", "--quiet").exit_code == 0
    source = tmp_path / "outputs" / "five.h5"
    before = source.read_bytes()
    assert cli("run", source, "--quiet").exit_code == 0
    assert source.read_bytes() == before
    assert (tmp_path / "outputs" / "five-rerun.h5").is_file()
