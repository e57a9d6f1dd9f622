"""Hostile inputs and faults (issue 15): every one gets one clear message and the right exit code,
nothing is written where it must not be, nothing is lost."""

from __future__ import annotations

import errno
import os
import shutil
import stat
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

from rustycs_cli import limits
from rustycs_cli.errors import UserError
from rustycs_cli.loading import load_scene_text
from rustycs_cli.output_files import output_lock

SMALL = """\
name: small
world: {tick_rate: 60, ticks: 5, precision: 4}
bodies:
  - {name: floor, type: static, shape: {type: aabb, width: 4, height: 0.5}, position: [0, -0.25]}
  - {name: ball, shape: {type: circle, radius: 0.25}, position: [0, 1]}
"""


def problems_of(text: str, *overrides: str) -> list[str]:
    with pytest.raises(UserError) as raised:
        load_scene_text(text, "s.yaml", overrides)
    assert raised.value.exit_code == 2
    return raised.value.messages


def assert_user_error(result, *words: str) -> None:
    assert result.exit_code == 2, (result.stdout, result.stderr)
    assert "Traceback" not in result.stderr
    for word in words:
        assert word in result.stderr, result.stderr


# ------------------------------------------------------------------------------------ numbers


@pytest.mark.parametrize(("override", "expected"), [
    ("bodies.ball.shape.radius=.inf", "bodies.ball.shape.radius: Input should be a finite number"),
    ("bodies.ball.shape.radius=1e309", "Input should be a finite number"),
    ("bodies.ball.shape.radius=.nan", "Input should be a finite number"),
    ("bodies.ball.shape.radius=1e-300", "must be at least 1e-06 m (MIN_LENGTH"),
    ("bodies.ball.shape.radius=1e300", "must be at most 1e+06 m (MAX_LENGTH"),
    ("bodies.ball.mass=1e300", "(MAX_MASS"),
    ("bodies.ball.position=[0,.inf]", "bodies.ball.position.1: Input should be a finite number"),
    ("bodies.ball.angle=-.inf", "Input should be a finite number"),
    ("bodies.ball.velocity=[1e300,0]", "(MAX_SPEED"),
    ("world.tick_rate=.inf", "world.tick_rate: Input should be a finite number"),
    ("world.tick_rate=1e300", "(MAX_TICK_RATE"),
    ("world.restitution_threshold=.nan", "Input should be a finite number"),
    ("world.precision=9223372036854775808", "must be at most 1000 (MAX_PRECISION"),
    ("world.ticks=10000000000000", "(MAX_TICKS"),
    ("seed=100000000000000000000000000", "(MAX_SEED"),
    ("materials.rubber.density=1e300", "(MAX_DENSITY"),
    ("materials.rubber.friction=.inf", "Input should be a finite number"),
    # lax coercion
    ("bodies.ball.shape.radius=true", "Input should be a valid number (got True)"),
    ("bodies.ball.shape.radius='0.5'", "Input should be a valid number (got '0.5')"),
    ("world.ticks=10.0", "world.ticks: Input should be a valid integer (got 10.0)"),
    ("world.ticks=1:30", "world.ticks: Input should be a valid integer (got '1:30')"),
])
def test_numbers_are_finite_strict_and_bounded(override: str, expected: str) -> None:
    messages = problems_of(SMALL, override)
    assert len(messages) == 1 and expected in messages[0], messages


def test_an_attractor_of_huge_mass_and_tiny_softening_is_refused() -> None:
    text = SMALL + "attractors:\n  - {name: sun, position: [0, 0], mass: 1e300, min_distance: 1e-300}\n"
    messages = problems_of(text)
    assert messages == [
        "s.yaml:7:41: attractors.sun.mass: must be at most 1e+30 kg (MAX_MASS, see docs/limits.md) "
        "(got 1e+300)",
        "s.yaml:7:62: attractors.sun.min_distance: must be at least 1e-06 m (MIN_LENGTH, see docs/limits.md) "
        "(got 1e-300)",
    ]


def test_the_schema_names_the_limits() -> None:
    from rustycs_cli.scene import Scene

    schema = Scene.model_json_schema()
    precision = schema["$defs"]["World"]["properties"]["precision"]
    assert precision["maximum"] == 1000 and "MAX_PRECISION" in precision["$comment"]
    radius = schema["$defs"]["Circle"]["properties"]["radius"]
    assert radius["minimum"] == limits.MIN_LENGTH.value and radius["maximum"] == limits.MAX_LENGTH.value


# ------------------------------------------------------------------------------------ YAML


@pytest.mark.parametrize(("text", "expected"), [
    ("seed: !!float x\n", "s.yaml:1:7: YAML error: cannot read 'x' as a number"),
    ("seed: !!int abc\n", "s.yaml:1:7: YAML error: cannot read 'abc' as an integer"),
    ("seed: !!bool maybe\n", "s.yaml:1:7: YAML error: cannot read 'maybe' as a boolean"),
    ("description: !!timestamp 2001-13-45\n", "s.yaml:1:14: YAML error: cannot read '2001-13-45' as a"),
    ("description: a\x01b\n", "s.yaml:1:15: YAML error: special characters are not allowed (character"),
    ("bodies: &a [*a]\n", "s.yaml:1:9: YAML error: a recursive alias (a value that contains itself)"),
    ("a: " + "[" * 900 + "]" * 900 + "\n", "s.yaml:1:67: YAML error: nesting deeper than 64 levels"),
])
def test_yaml_problems_are_located_messages(text: str, expected: str) -> None:
    messages = problems_of(text)
    assert len(messages) == 1 and messages[0].startswith(expected), messages


def test_an_alias_bomb_costs_what_reading_it_once_costs() -> None:
    lines = ["a: &a [x, x, x, x, x, x, x, x, x]"]
    for i in range(1, 12):  # 9^12 values once expanded
        previous, name = chr(96 + i), chr(97 + i)
        lines.append(f"{name}: &{name} [{', '.join([f'*{previous}'] * 9)}]")
    messages = problems_of("\n".join(lines) + "\n")
    assert messages == ["s.yaml:1:1: YAML error: the aliases expand to more than 10000000 values "
                        "(MAX_YAML_VALUES, see docs/limits.md)"]


@pytest.mark.parametrize("value", ["!!float x", "!!int abc", "&a [*a]", '"a\\0"'])
def test_yaml_problems_in_set_values(value: str) -> None:
    messages = problems_of(SMALL, f"description={value}")
    assert len(messages) == 1 and messages[0].startswith(f"--set description={value}: ")


# ------------------------------------------------------------------------------------ names


@pytest.mark.parametrize(("name", "expected"), [
    ("../../escaped", "must not contain / or \\"),
    ("/abs/path", "must not contain / or \\"),
    ("..", "nor be . or .."),
    ('"a\\0b"', "must not contain control characters"),
    ("x" * 250, "a name has at most 100 characters (MAX_NAME_LENGTH"),
])
def test_scene_names_stay_inside_the_output_folder(name: str, expected: str) -> None:
    messages = problems_of(SMALL.replace("name: small", f"name: {name}"))
    assert len(messages) == 1 and messages[0].startswith("s.yaml:1:7: name: ") and expected in messages[0]


def test_body_names_with_nul_or_too_long_are_refused() -> None:
    messages = problems_of(SMALL.replace("name: ball", 'name: "b\\0"'))
    assert messages[0].startswith("s.yaml:5:12: bodies.1.name: a name must not contain control")
    assert "MAX_NAME_LENGTH" in problems_of(SMALL.replace("name: ball", "name: " + "b" * 250))[0]


def test_traversal_writes_nothing_outside(cli, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    work = tmp_path / "work"
    work.mkdir()
    monkeypatch.chdir(work)
    scene = work / "s.yaml"
    scene.write_text(SMALL.replace("name: small", "name: ../../escaped"))
    assert_user_error(cli("run", scene), "name: a scene name names its output files")
    assert_user_error(cli("sweep", scene, "-p", "world.precision=4,5"), "scene name")
    assert sorted(p.name for p in tmp_path.rglob("*")) == ["s.yaml", "work"]


# ------------------------------------------------------------------------------------ sizes


EMITTING = SMALL + """emitters:
  - {name: rain, shape: {type: circle, radius: 0.05}, region: {min: [-1, 2], max: [1, 3]}, rate: 1000000}
measures:
  - {name: top, of: bodies.ball.position.y, reduce: max}
"""


@pytest.mark.parametrize(("override", "expected"), [
    ("emitters.rain.rate=.inf", "emitters.rain.rate: Input should be a finite number"),
    ("emitters.rain.start=1e309", "Input should be a finite number"),
    ("emitters.rain.lifetime=.nan", "Input should be a finite number"),
])
def test_the_numbers_of_this_rounds_models_are_finite(override: str, expected: str) -> None:
    messages = problems_of(EMITTING, override)
    assert len(messages) == 1 and expected in messages[0], messages


def test_an_emitter_that_would_emit_too_many_bodies_is_refused_before_any_work(cli, tmp_path: Path) -> None:
    scene = tmp_path / "s.yaml"
    scene.write_text(EMITTING)
    result = cli("run", str(scene), "--ticks", "1000000", "--out", str(tmp_path / "s.h5"))
    assert_user_error(result, "emitter 'rain' would emit 1000001 bodies", "MAX_BODIES")
    assert not (tmp_path / "s.h5").exists()



def test_too_many_bodies_are_refused_before_any_work() -> None:
    text = ("generators:\n  - {name: g, count: 1000000000, shape: {type: circle, radius: 0.1},\n"
            "     region: {min: [0, 0], max: [1, 1]}}\n")
    assert problems_of(text) == [
        "s.yaml:2:22: generators.g.count: the scene has 1000000000 bodies, more than 1000000 "
        "(MAX_BODIES, see docs/limits.md)"]
    pyramid = ("generators:\n  - {name: p, shape: {type: circle, radius: 0.1},\n"
               "     layout: {pyramid: {base: 100000, origin: [0, 0], spacing: [1, 1]}}}\n")
    assert "the scene has 5000050000 bodies" in problems_of(pyramid)[0]


def test_a_scene_file_larger_than_the_limit_is_refused_unread(cli, tmp_path: Path,
                                                              monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(limits, "MAX_SCENE_BYTES", limits.Limit("MAX_SCENE_BYTES", 100, "bytes"))
    big = tmp_path / "big.yaml"
    big.write_text(SMALL)
    assert_user_error(cli("validate", big), "the scene file is larger than 100 bytes (MAX_SCENE_BYTES")
    assert_user_error(cli("validate", "/dev/zero"), "/dev/zero: the scene file is larger than")


def test_a_sweep_of_too_many_variants_is_refused(cli, tmp_path: Path) -> None:
    scene = tmp_path / "s.yaml"
    scene.write_text(SMALL)
    result = cli("sweep", scene, "-p", "world.ticks=range(0,100000)", "-p", "seed=range(0,100000)",
                 "--out", tmp_path / "sweep")
    assert_user_error(result, "the sweep has 10000000000 variants, more than 10000 (MAX_VARIANTS")
    assert not (tmp_path / "sweep").exists()


@pytest.mark.parametrize("option", [("--ticks", str(10**29)), ("--every", str(10**23))])
def test_huge_run_options_are_refused(cli, tmp_path: Path, option: tuple[str, str]) -> None:
    scene = tmp_path / "s.yaml"
    scene.write_text(SMALL)
    result = cli("run", scene, *option, "--out", tmp_path / "o.h5")
    assert_user_error(result, f"{option[0]} {option[1]}: must be")
    assert_user_error(cli("run", scene, "--seed", str(10**26), "--out", tmp_path / "o.h5"), "(MAX_SEED")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.yaml"]


# ------------------------------------------------------------------------------------ outputs


def test_out_must_be_an_h5_file_name(cli, tmp_path: Path) -> None:
    scene = tmp_path / "s.yaml"
    scene.write_text(SMALL)
    assert_user_error(cli("run", scene, "--out", scene), "a trajectory file name must end in .h5")
    assert scene.read_text() == SMALL


def test_outputs_that_are_not_regular_files_are_never_replaced(cli, tmp_path: Path) -> None:
    scene = tmp_path / "s.yaml"
    scene.write_text(SMALL)
    fifo = tmp_path / "pipe.h5"
    os.mkfifo(fifo)
    assert_user_error(cli("run", scene, "--out", fifo), "exists and is not a regular file")
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)
    assert_user_error(cli("run", scene, "--out", "/dev/null"), "/dev/null: exists and is not a regular file")
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode) and not Path("/dev/null.summary.json").exists()


def test_sweep_out_onto_an_existing_file(cli, tmp_path: Path) -> None:
    scene = tmp_path / "s.yaml"
    scene.write_text(SMALL)
    assert_user_error(cli("sweep", scene, "-p", "world.precision=4,5", "--out", scene), "is not a folder")
    assert scene.read_text() == SMALL


def test_a_locked_output_is_refused(cli, tmp_path: Path) -> None:
    scene, out = tmp_path / "s.yaml", tmp_path / "o.h5"
    scene.write_text(SMALL)
    with output_lock(out):
        assert_user_error(cli("run", scene, "--out", out), "another rustycs process is writing this output")
    assert not out.exists()


def test_a_full_disk_is_one_message_and_leaves_nothing(cli, tmp_path: Path, compiled_engine: None,
                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    from rustycs_cli import trajectory

    scene, out = tmp_path / "s.yaml", tmp_path / "o.h5"
    scene.write_text(SMALL)
    assert cli("run", scene, "--out", out, "--quiet").exit_code == 0
    before = out.read_bytes()

    def full(*_args: object, **_kwargs: object) -> None:
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(trajectory.TrajectoryWriter, "append_block", full)
    result = cli("run", scene, "--out", out, "--quiet")
    assert result.exit_code == 1 and "Traceback" not in result.stderr
    assert result.stderr.strip().splitlines() == [f"{out}: cannot write the output: the disk is full "
                                                  "(no partial file was left)"]
    assert out.read_bytes() == before  # the previous run's file survives
    assert sorted(p.name for p in tmp_path.iterdir()) == ["o.h5", "o.summary.json", "s.yaml"]


def test_a_failed_summary_never_sits_beside_a_newer_trajectory(cli, tmp_path: Path, compiled_engine: None,
                                                               monkeypatch: pytest.MonkeyPatch) -> None:
    from rustycs_cli import simulation, summary

    scene, out = tmp_path / "s.yaml", tmp_path / "o.h5"
    scene.write_text(SMALL)
    assert cli("run", scene, "--out", out, "--quiet").exit_code == 0

    def full(*_args: object) -> None:
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(summary, "write_text_atomic", full)
    monkeypatch.setattr(simulation, "warm_up", lambda: None)
    result = cli("run", scene, "--out", out, "--quiet", "--ticks", "3")
    assert result.exit_code == 1 and "the disk is full" in result.stderr
    assert not (tmp_path / "o.summary.json").exists()  # the old sidecar went before the new file came


def test_a_run_that_would_fill_the_disk_is_refused(cli, tmp_path: Path, compiled_engine: None,
                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    scene, out = tmp_path / "s.yaml", tmp_path / "o.h5"
    scene.write_text(SMALL)
    monkeypatch.setattr(shutil, "disk_usage", lambda _path: shutil._ntuple_diskusage(10**9, 10**9, 10**6))
    result = cli("run", scene, "--out", out, "--ticks", "1000000")
    assert_user_error(result, "the run would write about", "--allow-full-disk")
    assert not out.exists()


def test_temporaries_of_dead_runs_are_removed(cli, tmp_path: Path, compiled_engine: None) -> None:
    scene, out = tmp_path / "s.yaml", tmp_path / "o.h5"
    scene.write_text(SMALL)
    stale = tmp_path / ".o.h5.tmp-999999999"
    stale.write_bytes(b"\0" * 1000)
    assert cli("run", scene, "--out", out, "--quiet").exit_code == 0
    assert not stale.exists()


# ------------------------------------------------------------------------------------ damaged trajectories


def _damage(path: Path, how: str) -> None:
    with h5py.File(path, "r+") as f:
        position = "particles/bodies/position"
        if how == "extra frame":
            f[f"{position}/value"].resize(f[f"{position}/value"].shape[0] + 1, axis=0)
        elif how == "nan time":
            f[f"{position}/time"][0] = np.nan
        elif how == "no parameters":
            del f["parameters"]
        elif how == "1-D position":
            del f[f"{position}/value"]
            f[f"{position}/value"] = np.zeros(3)
        elif how == "text steps":
            del f[f"{position}/step"]
            f[f"{position}/step"] = np.array(["a"] * f[f"{position}/value"].shape[0], dtype=object)
        elif how == "short velocity":
            del f["particles/bodies/velocity/value"]
            f["particles/bodies/velocity/value"] = np.zeros((1, 2))


@pytest.mark.parametrize("how", ["extra frame", "nan time", "no parameters", "1-D position", "text steps",
                                 "short velocity"])
def test_damaged_trajectories_get_one_message(cli, tmp_path: Path, run_scene, how: str) -> None:
    good = run_scene(SMALL)
    bad = tmp_path / "bad.h5"
    shutil.copy(good, bad)
    _damage(bad, how)
    for args in (("info", bad), ("compare", bad, good), ("compare", good, bad),
                 ("render", bad, "-o", tmp_path / "x.png"), ("run", bad, "--out", tmp_path / "again.h5")):
        result = cli(*args)
        assert_user_error(result, f"{bad}: ")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.h5"]


@pytest.mark.parametrize(("args", "expected"), [
    (("--view", "-1e308,-1e308,1e308,1e308", "-o", "x.png"), "the view must lie within +-1e+12 m (MAX_VIEW"),
    (("--view", "0,0,1e-300,1e-300", "-o", "x.png"), "at least 1e-06 m (MIN_LENGTH"),
    (("--every", str(10**20), "-o", "x.gif"), f"--every {10**20}: must be from 1 to 1000000000 (MAX_TICKS"),
])
def test_render_options_beyond_the_limits(cli, tmp_path: Path, run_scene, monkeypatch: pytest.MonkeyPatch,
                                          args: tuple[str, ...], expected: str) -> None:
    monkeypatch.chdir(tmp_path)
    assert_user_error(cli("render", run_scene(SMALL), *args), expected)
    assert list(tmp_path.iterdir()) == []


# ------------------------------------------------------------------------------------ signals


def test_sigterm_while_loading_is_an_interruption(tmp_path: Path) -> None:
    import signal
    import subprocess
    import time

    fifo = tmp_path / "scene.yaml"
    os.mkfifo(fifo)  # opening it blocks until a writer comes: the program is loading
    process = subprocess.Popen([sys.executable, "-c", "from rustycs_cli.app import program; program()",
                                "validate", str(fifo)], stderr=subprocess.PIPE, text=True)
    wchan = Path(f"/proc/{process.pid}/wchan")
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and wchan.read_text() not in ("wait_for_partner", "fifo_open"):
        time.sleep(0.1)
    process.send_signal(signal.SIGTERM)
    _, stderr = process.communicate(timeout=30)
    assert process.returncode == 130 and stderr.strip() == "rustycs: interrupted"


def test_docs_list_every_limit_with_its_value() -> None:
    text = (Path(__file__).resolve().parents[1] / "docs" / "limits.md").read_text()
    for limit in vars(limits).values():
        if isinstance(limit, limits.Limit):
            value = f"{limit.value:g}" if isinstance(limit.value, float) else str(limit.value)
            assert f"`{limit.name}`" in text and value in text, limit


LONG = SMALL.replace("ticks: 5", "ticks: 100000000").replace("precision: 4", "precision: 1") + """\
generators:
  - {name: rain, count: 200, shape: {type: circle, radius: 0.05}, region: {min: [-2, 1], max: [2, 30]}}
"""


def _wait_for(condition, seconds: float = 120.0) -> None:
    import time

    deadline = time.monotonic() + seconds
    while not condition():
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.2)


@pytest.mark.usefixtures("compiled_engine")
def test_the_frames_of_a_killed_run_are_recovered(cli, tmp_path: Path) -> None:
    import signal
    import subprocess
    import time

    from rustycs_cli.trajectory import RECOVERY_SECONDS

    scene, out = tmp_path / "long.yaml", tmp_path / "long.h5"
    scene.write_text(LONG)
    process = subprocess.Popen([sys.executable, "-c", "from rustycs_cli.app import program; program()", "run",
                                str(scene), "--out", str(out), "--quiet", "--allow-full-disk"],
                               stderr=subprocess.PIPE)
    temporary = tmp_path / f".long.h5.tmp-{process.pid}"
    try:
        _wait_for(lambda: temporary.exists() or process.poll() is not None)
        assert process.poll() is None, process.stderr.read()
        first = temporary.stat().st_mtime
        _wait_for(lambda: temporary.stat().st_mtime > first + RECOVERY_SECONDS)  # flushed once more at least
        # the first write after RECOVERY_SECONDS starts that flush: let it end (a kill between the two, on a
        # loaded machine, left a file whose superblock had never been written)
        time.sleep(1.0)
    finally:
        process.send_signal(signal.SIGKILL)
        process.wait(timeout=30)
    assert_user_error(cli("info", temporary), f"rustycs recover {temporary}")
    result = cli("recover", temporary)
    assert result.exit_code == 0, result.stderr
    assert not temporary.exists() and out.exists()
    info = cli("info", out, "--json")
    assert info.exit_code == 0, info.stderr
    import json

    details = json.loads(info.stdout)
    assert details["status"] == "interrupted" and details["frames"] > 1
    assert details["ticks_completed"] == details["frames"] - 1  # every tick recorded, from 0
    assert json.loads((tmp_path / "long.summary.json").read_text())["status"] == "interrupted"


def test_recover_refuses_what_is_not_a_dead_runs_temporary(cli, tmp_path: Path) -> None:
    mine = tmp_path / f".x.h5.tmp-{os.getpid()}"
    mine.write_bytes(b"")
    assert_user_error(cli("recover", mine), "is still writing it")
    assert_user_error(cli("recover", tmp_path / "x.h5"), "not the temporary file of a run")
    junk = tmp_path / ".y.h5.tmp-999999999"
    junk.write_bytes(b"junk")
    assert_user_error(cli("recover", junk), "cannot be recovered")


def _gone(pid: int) -> bool:
    """True when the process has exited (a zombie nobody reaps counts as gone)."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except FileNotFoundError:
        return True
    return "State:\tZ" in status


@pytest.mark.usefixtures("compiled_engine")
def test_workers_of_a_killed_sweep_keep_their_frames_and_exit(tmp_path: Path) -> None:
    import signal
    import subprocess

    scene, out = tmp_path / "long.yaml", tmp_path / "sweep"
    scene.write_text(LONG)
    process = subprocess.Popen([sys.executable, "-c", "from rustycs_cli.app import program; program()",
                                "sweep", str(scene), "-p", "world.precision=1,2", "--local", "processes",
                                "-w", "2", "--every", "100000", "--out", str(out), "--quiet"],
                               stderr=subprocess.PIPE)
    try:
        def running() -> list[int]:
            names = [p.name for p in out.glob(".*.h5.tmp-*")] if out.exists() else []
            return [int(name.rsplit("-", 1)[1]) for name in names]

        _wait_for(lambda: len(running()) == 2 or process.poll() is not None)
        assert process.poll() is None, process.stderr.read()
        workers = running()
    finally:
        process.send_signal(signal.SIGKILL)
        process.wait(timeout=30)
    _wait_for(lambda: all(_gone(pid) for pid in workers), seconds=60)
    for path in sorted(out.glob("*.h5")):  # each variant ended as interrupted, its frames kept
        with h5py.File(path, "r") as file:
            assert file["parameters"].attrs["status"] == "interrupted"
    assert len(list(out.glob("*.h5"))) == 2 and not list(out.glob(".*.tmp-*"))


@pytest.mark.parametrize(("every", "budgets"), [(1, [1, 7, 300]), (8, [1, 3, 8, 20, 1]),
                                                (64, [5, 5, 200, 1])])
def test_engine_calls_keep_the_recorded_ticks_whatever_their_length(every: int, budgets: list[int]) -> None:
    from rustycs_cli.run_pace import Pace

    ticks, tick, recorded = 1000, 0, []
    pace = Pace(every, most=256 * every)
    calls = 0
    while tick < ticks:
        count, call_every = pace.next_call(tick, ticks)
        assert count >= 1
        if call_every:  # the engine records after every `call_every`-th tick of the call and after its last
            recorded += [t for t in range(tick + 1, tick + count + 1)
                         if (t - tick) % call_every == 0 or t == tick + count]
        tick += count
        pace.budget = budgets[calls % len(budgets)]
        calls += 1
    assert recorded == sorted({*range(every, ticks, every), ticks})


def test_a_scheduler_that_never_answers_is_given_up(cli, tmp_path: Path,
                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    import socket

    pytest.importorskip("distributed")
    from rustycs_cli import sweep

    monkeypatch.setattr(sweep, "CONNECT_TIMEOUT", 1.0)
    scene = tmp_path / "s.yaml"
    scene.write_text(SMALL)
    with socket.socket() as server:
        server.bind(("127.0.0.1", 0))
        server.listen()  # accepts connections (the kernel does) and never answers
        port = server.getsockname()[1]
        result = cli("sweep", scene, "-p", "world.precision=4,5", "--scheduler", f"tcp://127.0.0.1:{port}",
                     "--out", tmp_path / "sweep")
    assert_user_error(result, f"cannot reach the Dask scheduler at tcp://127.0.0.1:{port}")


def test_render_plot_and_schema_never_replace_a_special_file(cli, tmp_path: Path, run_scene) -> None:
    for name, args in (("x.png", ("render", run_scene(SMALL))), ("y.png", ("plot", run_scene(SMALL))),
                       ("s.json", ("schema",))):
        fifo = tmp_path / name
        os.mkfifo(fifo)
        assert_user_error(cli(*args, "-o", fifo), f"{fifo}: exists and is not a regular file")
        assert stat.S_ISFIFO(os.lstat(fifo).st_mode)


@pytest.mark.parametrize("settings", [{"precision": 1001}, {"precision": 0}, {"tick_rate": float("inf")},
                                      {"tick_rate": float("nan")}, {"tick_rate": 0.0}])
def test_the_engine_refuses_settings_it_cannot_step(settings: dict[str, float]) -> None:
    import rustycs

    with pytest.raises(ValueError):
        rustycs.World(**settings)


@pytest.fixture
def small_disk(tmp_path: Path):
    """A 1 MiB tmpfs (needs the right to mount: skipped otherwise)."""
    import subprocess

    folder = tmp_path / "small"
    folder.mkdir()
    mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=1m", "tmpfs", str(folder)],
                             capture_output=True)
    if mounted.returncode != 0:
        pytest.skip("cannot mount a tmpfs here")
    try:
        yield folder
    finally:
        subprocess.run(["umount", str(folder)], check=True)


@pytest.mark.usefixtures("compiled_engine")
def test_a_real_full_disk_leaves_no_temporary(cli, tmp_path: Path, small_disk: Path) -> None:
    scene = tmp_path / "rain.yaml"
    scene.write_text(LONG.replace("ticks: 100000000", "ticks: 3000"))
    out = small_disk / "rain.h5"
    assert_user_error(cli("run", scene, "--out", out, "--quiet"), "the run would write about")
    result = cli("run", scene, "--out", out, "--quiet", "--allow-full-disk")
    assert result.exit_code == 1 and "Traceback" not in result.stderr
    assert result.stderr.strip() == (f"{out}: cannot write the output: the disk is full "
                                     "(no partial file was left)")
    assert list(small_disk.iterdir()) == []


@pytest.mark.usefixtures("compiled_engine")
def test_a_sweep_that_would_fill_the_disk_is_refused_before_any_run(cli, tmp_path: Path,
                                                                    small_disk: Path) -> None:
    scene = tmp_path / "rain.yaml"
    scene.write_text(LONG.replace("ticks: 100000000", "ticks: 3000"))
    out = small_disk / "sweep"
    assert_user_error(cli("sweep", scene, "-p", "world.precision=1,2", "--out", out, "-w", "1", "-q"),
                      "the run would write about")
    assert not out.exists()
    result = cli("sweep", scene, "-p", "world.precision=1,2", "--out", out, "-w", "1", "-q",
                 "--allow-full-disk")
    assert result.exit_code == 1 and "Traceback" not in result.stderr and "the disk is full" in result.stderr
    assert not list(out.glob(".*"))  # no temporaries left


def test_too_many_shapes_are_refused_before_any_work(monkeypatch: pytest.MonkeyPatch) -> None:
    shapes = ", ".join(["{type: circle, radius: 0.1}"] * 5)
    text = (f"bodies:\n  - {{name: b, position: [0, 0], shapes: [{shapes}]}}\n"
            f"generators:\n  - {{name: g, count: 1000, shapes: [{shapes}],\n"
            "     region: {min: [0, 0], max: [9, 9]}}\n")
    monkeypatch.setattr(limits, "MAX_SHAPES", limits.Limit("MAX_SHAPES", 5000))
    assert problems_of(text) == ["s.yaml:2:3: bodies: the bodies have 5005 shapes, more than 5000 "
                                 "(MAX_SHAPES, see docs/limits.md)"]
