"""`rustycs sweep`: grids, range(), resume, failing variants, up-front validation and the Dask path."""

from __future__ import annotations

import csv
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py
import pytest

from rustycs_cli.errors import UserError
from rustycs_cli.sweep_values import parse_swept_key, parse_swept_keys

TINY = """\
name: tiny
world: {tick_rate: 60, ticks: 20, precision: 4}
forces:
  - {name: gravity, acceleration: [0, -9.81]}
bodies:
  - {name: floor, type: static, shape: {type: aabb, width: 10, height: 0.5}, position: [0, -0.25]}
  - {name: ball, shape: {type: circle, radius: 0.2}, position: [0, 0.3], material: rubber}
  - {name: crate, shape: {type: obb, width: 0.4, height: 0.4}, position: [1, 0.5]}
"""


@pytest.fixture
def tiny(tmp_path: Path) -> Path:
    path = tmp_path / "tiny.yaml"
    path.write_text(TINY)
    return path


def values(option: str) -> list:
    return [v.value for v in parse_swept_key(option).values]


def test_value_lists_and_ranges():
    assert values("world.precision=range(2,8,2)") == [2, 4, 6]
    assert values("k=range(3)") == [0, 1, 2]
    assert values("k=range(5,0,-2)") == [5, 3, 1]
    assert values("k=range(0,0.5,0.1)") == [0.0, 0.1, 0.2, 0.3, 0.4]  # exact decimals, STOP excluded
    assert values("k=range(0.5,2)") == [0.5, 1.5]
    assert values("forces.gravity.acceleration=[0,-9.81],[0,-1.62]") == [[0, -9.81], [0, -1.62]]
    assert values("m=metal, 'a,b', 1e-3") == ["metal", "a,b", 0.001]
    assert [v.text for v in parse_swept_key("k=range(0,0.3,0.1)").values] == ["0.0", "0.1", "0.2"]


@pytest.mark.parametrize("option, message", [
    ("k", "expected KEY=V1"), ("k=", "expected KEY=V1"), ("k=range(1,1)", "empty"),
    ("k=range(0,1,0)", "step must not be 0"), ("k=range(a)", "1 to 3 numbers"), ("k=[1,2", "unbalanced"),
    ("k=1,,2", "empty value"), ("k=1,1", "listed twice"), ("k=[1,2}", "not valid YAML"),
])
def test_bad_values(option, message):
    with pytest.raises(UserError, match=message):
        parse_swept_key(option)


def test_a_key_swept_twice_is_an_error():
    with pytest.raises(UserError, match="swept twice"):
        parse_swept_keys(["a=1,2", "a=3"])


def read_rows(out: Path) -> tuple[list[dict], list[dict]]:
    with open(out / "sweep.csv", newline="") as handle:
        return json.loads((out / "sweep.json").read_text()), list(csv.DictReader(handle))


@pytest.mark.parametrize("local", ["threads", "processes"])
def test_grid_2x3_with_range_then_resume(cli, tiny, tmp_path, compiled_engine, local):
    out = tmp_path / "grid"
    args = ("sweep", tiny, "-p", "world.precision=range(2,8,2)", "-p", "bodies.ball.material=rubber,metal",
            "-s", "world.ticks=12", "--out", out)
    result = cli(*args, "--workers", "2", "--local", local, "--json")
    assert result.exit_code == 0, result.stderr
    rows, csv_rows = read_rows(out)
    assert json.loads(result.stdout) == rows
    files = sorted(out.glob("*.h5"))
    assert len(files) == 6 and len(rows) == 6 and len(csv_rows) == 6
    grid = {(row["world.precision"], row["bodies.ball.material"]) for row in rows}
    assert grid == {(p, m) for p in (2, 4, 6) for m in ("rubber", "metal")}
    assert [row["world.precision"] for row in csv_rows] == ["2", "2", "4", "4", "6", "6"]
    for row in rows:
        assert row["status"] == "complete" and row["skipped"] is False and row["error"] is None
        assert row["ticks"] == 12 and row["scene"] == "tiny"
        path = Path(row["output"])
        assert path.parent == out and path.name.startswith(f"tiny-{row['index']}-world.precision=")
        with h5py.File(path) as file:
            overrides = [o.decode() if isinstance(o, bytes) else o for o in file["parameters/overrides"][()]]
            assert overrides == ["world.ticks=12", f"world.precision={row['world.precision']}",
                                 f"bodies.ball.material={row['bodies.ball.material']}"]
            assert file["parameters"].attrs["precision"] == row["world.precision"]
            materials = [m.decode() for m in file["particles/bodies/material"][()]]
            assert materials[1] == row["bodies.ball.material"]
            assert row["scene_sha256"] == file["parameters"].attrs["scene_sha256"]

    # resume: nothing re-runs; then only a deleted variant does
    mtimes = {f: f.stat().st_mtime_ns for f in files}
    again = cli(*args, "--workers", "1", "--json")
    assert again.exit_code == 0, again.stderr
    assert all(row["skipped"] and row["status"] == "complete" for row in json.loads(again.stdout))
    assert {f: f.stat().st_mtime_ns for f in files} == mtimes
    files[3].unlink()
    third = cli(*args, "--workers", "1", "--json")
    rerun = [row["output"] for row in json.loads(third.stdout) if not row["skipped"]]
    assert third.exit_code == 0 and rerun == [str(files[3])] and files[3].exists()
    assert all(files[i].stat().st_mtime_ns == mtimes[files[i]] for i in (0, 1, 2, 4, 5))


def test_a_batch_of_variants_gives_each_its_own_run(cli, tiny, tmp_path, compiled_engine):
    """Variants of one size step together (two sizes here: 20 and 30 ticks); each trajectory and summary
    is bitwise the one the variant has run alone, also for variants whose stop condition ends them early
    (leaving the batch) and for recording every 3 ticks."""
    args = ("sweep", tiny, "-p", "bodies.ball.position=[0,0.3],[0,0.8],[0,2.5]", "-p", "world.ticks=20,30",
            "-s", "world.stop_when=[{event: contact_begin, bodies: [ball, floor]}]", "--every", "3",
            "-w", "1", "--json")
    together = json.loads(cli(*args, "--out", tmp_path / "batch").stdout)
    alone = json.loads(cli(*args, "--out", tmp_path / "alone", "--batch", "1").stdout)
    assert [(row["status"], row["ticks"]) for row in together] == [
        ("stopped", 9), ("stopped", 9), ("complete", 20), ("stopped", 21), ("complete", 20), ("complete", 30)]
    timing = ("wall_seconds", "step_seconds", "ticks_per_second", "output")
    for one, other in zip(together, alone, strict=True):
        assert {k: v for k, v in one.items() if k not in timing} == {
            k: v for k, v in other.items() if k not in timing}
        with h5py.File(one["output"]) as a, h5py.File(other["output"]) as b:
            for name in ("position/value", "position/step", "velocity/value", "angle/value",
                         "angular_velocity/value"):
                path = f"particles/bodies/{name}"
                assert a[path][()].tobytes() == b[path][()].tobytes()
    empty = cli("sweep", tiny, "-p", "world.precision=3,5", "--ticks", "0", "-w", "1",
                "--out", tmp_path / "none", "--json")
    assert [(row["status"], row["ticks"]) for row in json.loads(empty.stdout)] == [("complete", 0)] * 2


def test_changed_scene_is_not_resumed(cli, tiny, tmp_path, compiled_engine):
    out = tmp_path / "s"
    assert cli("sweep", tiny, "-p", "world.precision=3,5", "--out", out, "-w", "1", "-q").exit_code == 0
    changed = cli("sweep", tiny, "-p", "world.precision=3,5", "-s", "bodies.crate.angle=0.2", "--out", out,
                  "-w", "1", "--json")
    assert changed.exit_code == 0
    assert [row["skipped"] for row in json.loads(changed.stdout)] == [False, False]
    longer = cli("sweep", tiny, "-p", "world.precision=3,5", "-s", "bodies.crate.angle=0.2", "--out", out,
                 "-w", "1", "--ticks", "25", "--json")
    assert [(row["skipped"], row["ticks"]) for row in json.loads(longer.stdout)] == [(False, 25)] * 2


def nan_world_at_tick_rate_61(monkeypatch) -> None:
    """Scenes cannot make the engine diverge (the limits): a world built at 61 Hz gets a NaN velocity."""
    import rustycs_cli.build

    real = rustycs_cli.build.build_world

    def build_world(scene, plan):
        world = real(scene, plan)
        if scene.world.tick_rate == 61:
            world.set_velocity(1, (float("nan"), 0.0))
        return world

    monkeypatch.setattr(rustycs_cli.build, "build_world", build_world)


@pytest.mark.parametrize("batch", ["1", "16"])
def test_diverging_variant_is_reported_while_others_complete(cli, tiny, tmp_path, compiled_engine,
                                                             monkeypatch, batch):
    nan_world_at_tick_rate_61(monkeypatch)
    out = tmp_path / "div"
    result = cli("sweep", tiny, "-p", "world.tick_rate=60,61,30", "--out", out, "-w", "2", "--batch", batch,
                 "--json")
    assert result.exit_code == 1
    rows = json.loads(result.stdout)
    assert [row["status"] for row in rows] == ["complete", "diverged", "complete"]
    assert "diverged" in rows[1]["error"] and rows[0]["error"] is None
    assert "variant 1 (world.tick_rate=61) diverged" in result.stderr
    assert all(Path(row["output"]).exists() for row in rows)
    # the diverged variant is not complete, so a re-run tries it again and skips the others
    again = json.loads(cli("sweep", tiny, "-p", "world.tick_rate=60,61,30", "--out", out, "-w", "1",
                           "--json").stdout)
    assert [row["skipped"] for row in again] == [True, False, True]


@pytest.mark.parametrize("batch", ["1", "16"])
def test_crashing_variant_is_recorded(cli, tiny, tmp_path, monkeypatch, compiled_engine, batch):
    import rustycs_cli.build

    real = rustycs_cli.build.build_world

    def crash_on_metal(scene, plan):
        if scene.bodies[2].material == "metal":
            raise RuntimeError("boom")
        return real(scene, plan)

    monkeypatch.setattr(rustycs_cli.build, "build_world", crash_on_metal)
    out = tmp_path / "crash"
    result = cli("sweep", tiny, "-p", "bodies.crate.material=stone,metal,rubber", "--out", out, "-w", "1",
                 "--batch", batch)
    assert result.exit_code == 1
    assert "variant 1 (bodies.crate.material=metal) failed: RuntimeError: boom" in result.stderr
    rows, csv_rows = read_rows(out)
    assert [row["status"] for row in rows] == ["complete", "failed", "complete"]
    assert csv_rows[1]["error"] == "RuntimeError: boom" and csv_rows[0]["error"] == ""
    assert "failed" in result.stdout  # the table


def test_invalid_variants_stop_the_sweep_before_any_run(cli, tiny, tmp_path):
    out = tmp_path / "bad"
    result = cli("sweep", tiny, "-p", "world.precision=4,0,-1", "-p", "world.tick_rate=60,120", "--out", out)
    assert result.exit_code == 2
    assert "Traceback" not in result.stderr
    assert result.stderr.strip().splitlines() == [  # one line per distinct problem, naming the value
        "-p world.precision=0: world.precision: Input should be greater than or equal to 1 (got 0)",
        "-p world.precision=-1: world.precision: Input should be greater than or equal to 1 (got -1)",
    ]
    assert not out.exists()
    typo = cli("sweep", tiny, "-p", "world.ticks=1,2", "-s", "world.precisoin=3", "--out", out)
    assert typo.exit_code == 2 and typo.stderr.count("unknown key 'world.precisoin'") == 1
    clash = cli("sweep", tiny, "-p", "bodies.ball.name=crate,other", "--out", out)  # variant 0 only
    assert clash.exit_code == 2 and clash.stderr.strip().endswith("[variant 0: bodies.ball.name=crate]")
    assert cli("sweep", tiny, "-p", "x=range(1,1)").exit_code == 2


def test_dask_local_cluster(cli, tiny, tmp_path, compiled_engine):
    distributed = pytest.importorskip("distributed")
    out = tmp_path / "dask"
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster:
        result = cli("sweep", tiny, "-p", "bodies.ball.position=[0,0.3],[0,1]", "--out", out,
                     "--scheduler", cluster.scheduler_address, "--json")
    assert result.exit_code == 0, result.stderr
    rows = json.loads(result.stdout)
    assert [row["bodies.ball.position"] for row in rows] == [[0, 0.3], [0, 1]]
    assert [row["status"] for row in rows] == ["complete", "complete"]
    assert len(list(out.glob("*.h5"))) == 2


def test_dask_errors(cli, tiny, tmp_path, monkeypatch):
    import rustycs_cli.sweep

    monkeypatch.setattr(rustycs_cli.sweep, "CONNECT_TIMEOUT", 0.5)
    unreachable = cli("sweep", tiny, "-p", "world.precision=3", "--out", tmp_path / "x",
                      "--scheduler", "tcp://127.0.0.1:9")
    assert unreachable.exit_code == 2
    assert "cannot reach the Dask scheduler at tcp://127.0.0.1:9" in unreachable.stderr
    monkeypatch.setitem(sys.modules, "distributed", None)
    missing = cli("sweep", tiny, "-p", "world.precision=3", "--out", tmp_path / "x",
                  "--scheduler", "tcp://127.0.0.1:9")
    assert missing.exit_code == 2 and "pip install 'rustycs[dask]'" in missing.stderr


def test_keyboard_interrupt_between_variants_then_resume(cli, tiny, tmp_path, monkeypatch, compiled_engine):
    import rustycs_cli.simulation

    real = rustycs_cli.simulation.run_scene

    def ctrl_c_before_variant_1(loaded, out, **kwargs):
        if "world.precision=5" in loaded.overrides:
            raise KeyboardInterrupt
        return real(loaded, out, **kwargs)

    monkeypatch.setattr(rustycs_cli.simulation, "run_scene", ctrl_c_before_variant_1)
    out = tmp_path / "ctrl-c"
    args = ("sweep", tiny, "-p", "world.precision=3,5,7", "--out", out, "-w", "1", "--batch", "1", "--json")
    result = cli(*args)
    assert result.exit_code == 130 and "run the same command again to resume" in result.stderr
    assert [row["status"] for row in json.loads(result.stdout)] == ["complete", "not run", "not run"]
    assert [row["status"] for row in read_rows(out)[0]] == ["complete", "not run", "not run"]
    monkeypatch.setattr(rustycs_cli.simulation, "run_scene", real)
    resumed = json.loads(cli(*args).stdout)
    assert [(row["status"], row["skipped"]) for row in resumed] == [
        ("complete", True), ("complete", False), ("complete", False)]


@pytest.mark.usefixtures("compiled_engine")
@pytest.mark.parametrize("signum, whole_group, local, batch", [(signal.SIGINT, True, "processes", 1),
                                                               (signal.SIGTERM, False, "processes", 1),
                                                               (signal.SIGINT, True, "threads", 1),
                                                               (signal.SIGINT, True, "threads", 2),
                                                               (signal.SIGTERM, False, "processes", 2)])
def test_signal_stops_a_pool_sweep(tiny, tmp_path, signum, whole_group, local, batch):
    """Ctrl-C in a terminal (SIGINT to the process group) or SIGTERM to the sweep alone: running
    variants stop with valid files, the others never start, the tables are written, exit 130. Each of
    the two workers runs a batch of `batch` variants."""
    out = tmp_path / "sig"
    process = subprocess.Popen(
        [sys.executable, "-c", "from rustycs_cli.app import program; program()", "sweep", str(tiny),
         "-p", "world.precision=3,5,7,9,11", "--ticks", "100000000", "--out", str(out), "-w", "2",
         "--local", local, "--batch", str(batch), "--allow-full-disk", "--json"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True,
    )
    deadline = time.monotonic() + 120
    while len(list(out.glob(".*.tmp-*"))) < 2 * batch:  # both workers are running
        assert process.poll() is None and time.monotonic() < deadline, process.communicate()
        time.sleep(0.05)
    time.sleep(1.0)
    if whole_group:
        os.killpg(process.pid, signum)
    else:
        process.send_signal(signum)
    stdout, stderr = process.communicate(timeout=120)
    assert process.returncode == 130, stderr
    assert "Traceback" not in stderr
    rows = json.loads(stdout)
    ran = 2 * batch
    assert [row["status"] for row in rows] == ["interrupted"] * ran + ["not run"] * (5 - ran)
    for row in rows[:ran]:
        with h5py.File(row["output"]) as file:
            assert file["parameters"].attrs["ticks_completed"] == row["ticks"] > 0
    assert not list(out.glob(".*.tmp-*")) and not any(Path(row["output"]).exists() for row in rows[ran:])


def test_cold_engine_is_compiled_once_before_the_workers(cli, tiny, tmp_path, monkeypatch, compiled_engine):
    import rustycs
    import rustycs_cli.simulation

    out = tmp_path / "c"
    warmed = []  # for each warm-up: how many variants had run before it
    monkeypatch.setattr(rustycs, "compile_needed", lambda: not warmed)
    monkeypatch.setattr(rustycs_cli.simulation, "warm_up", lambda: warmed.append(len(list(out.glob("*.h5")))))
    result = cli("sweep", tiny, "-p", "world.precision=3,5", "--out", out, "-w", "1")
    assert result.exit_code == 0 and warmed[0] == 0
    assert result.stderr.count("compiling the engine") == 1
