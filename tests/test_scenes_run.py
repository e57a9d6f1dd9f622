"""Every scene in scenes/ runs: the demos for their whole length with physical checks, the benchmark
scenes for a few ticks."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

SCENES = Path(__file__).resolve().parent.parent / "scenes"
# TODO(issue "Bodies made of shapes"): run these once the engine builds bodies made of shapes; until then
# they are only validated (tests/test_scene_files.py).
NEED_THE_NEW_ENGINE = {"capsule_pile", "cup_of_balls", "curved_ramp", "l_brackets"}
DEMOS = [
    pytest.param(path, marks=pytest.mark.skip(reason="needs the engine of bodies made of shapes"))
    if path.stem in NEED_THE_NEW_ENGINE
    else path
    for path in sorted(SCENES.glob("*.yaml"))
]
BENCH = sorted((SCENES / "bench").glob("*.yaml"))


def run(cli, path: Path, tmp_path: Path, *args: str) -> dict:  # noqa: ANN001
    result = cli("run", path, "--out", tmp_path / f"{path.stem}.h5", "--json", "--quiet", *args)
    assert result.exit_code == 0, result.stderr
    return json.loads(result.stdout)


@pytest.mark.usefixtures("compiled_engine")
@pytest.mark.parametrize("path", DEMOS, ids=lambda path: path.stem)
def test_demo_scene_runs_to_the_end(cli, path: Path, tmp_path: Path) -> None:  # noqa: ANN001
    summary = run(cli, path, tmp_path, "--every", "10")
    assert summary["status"] == "complete"
    if path.stem in ("material_bounce", "pile", "pool", "solar_system"):  # the others let bodies fall off
        assert summary["escaped_bodies"] == 0
    assert summary["max_penetration"] < 0.1  # metres: transient overlaps of falling bodies, never tunnelling
    if path.stem in ("pile", "pool"):  # the poured bodies come to rest
        assert summary["bodies_at_rest"] >= 0.9 * summary["dynamic_bodies"]
    if path.stem == "solar_system":  # no collisions, energy of the orbits kept to 1%
        assert summary["total_contact_points"] == 0
        assert abs(summary["relative_energy_drift"]) < 0.01


@pytest.mark.usefixtures("compiled_engine")
@pytest.mark.parametrize("path", BENCH, ids=[p.stem for p in BENCH])
def test_bench_scene_runs(cli, path: Path, tmp_path: Path) -> None:  # noqa: ANN001
    summary = run(cli, path, tmp_path, "--ticks", "20")
    assert summary["status"] == "complete" and summary["ticks"] == 20
    assert summary["escaped_bodies"] == 0
