"""Runs with world.sleep: the asleep flags in the trajectory (written in blocks and frame by frame), the
summary's bodies_asleep, the reader, files from before the flags, sweeps, and the demo scene."""

from __future__ import annotations

import csv
import json
import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest
from conftest import FIVE_BODIES, NAP, NAP_SLEEPS, NAP_WAKES

import rustycs

ASLEEP = "particles/bodies/asleep"
SLEEPING_PILE = Path(__file__).resolve().parent.parent / "scenes" / "sleeping_pile.yaml"


@pytest.fixture(scope="module")
def nap(run_scene) -> Path:
    """NAP recorded in blocks of frames (no contacts)."""
    return run_scene(NAP)


def asleep_of(path: Path) -> np.ndarray:
    with h5py.File(path, "r") as file:
        return file[f"{ASLEEP}/value"][()]


def without_asleep(path: Path, folder: Path) -> Path:
    """A copy of a trajectory as rustycs wrote it before the asleep flags existed."""
    old = folder / f"old-{path.name}"
    shutil.copy(path, old)
    with h5py.File(old, "r+") as file:
        del file[ASLEEP]
    return old


def test_the_asleep_flags_are_a_frame_series_like_active(nap: Path) -> None:
    with h5py.File(nap, "r") as file:
        value = file[f"{ASLEEP}/value"]
        assert value.dtype == np.bool_ and value.shape == (91, 3)
        position = file["particles/bodies/position"]
        for key in ("step", "time"):
            assert isinstance(file[ASLEEP].get(key, getlink=True), h5py.HardLink)
            assert file[ASLEEP][key] == position[key]
        asleep = value[()]
        velocity = file["particles/bodies/velocity/value"][()]
        crate = file["particles/bodies/position/value"][:, 1]
    # the crate sleeps from NAP_SLEEPS until the ball lands on it; the floor and the falling ball never do
    assert list(np.flatnonzero(asleep[:, 1])) == list(range(NAP_SLEEPS, NAP_WAKES))
    assert not asleep[:, [0, 2]].any()
    # asleep, it keeps its pose with zero velocity
    assert (velocity[NAP_SLEEPS:NAP_WAKES, 1] == 0).all()
    assert (crate[NAP_SLEEPS:NAP_WAKES] == crate[NAP_SLEEPS]).all()


def test_frames_written_one_by_one_hold_the_same_flags(run_scene, nap: Path) -> None:
    with_contacts = run_scene(NAP, "--contacts")  # contacts: frames are appended one by one
    np.testing.assert_array_equal(asleep_of(with_contacts), asleep_of(nap))
    every = run_scene(NAP, "--every", "7")  # whole blocks of every 7th tick
    np.testing.assert_array_equal(asleep_of(every), asleep_of(nap)[list(range(0, 91, 7)) + [90]])


def test_the_summary_counts_the_dynamic_bodies_asleep_at_the_end(cli, tmp_path: Path,
                                                                  compiled_engine: None) -> None:
    scene = tmp_path / "nap.yaml"
    scene.write_text(NAP)
    out = tmp_path / "nap.h5"
    result = cli("run", scene, "--out", out, "--ticks", "50")  # ends while the crate sleeps
    assert result.exit_code == 0, result.stderr
    assert "bodies_asleep" in result.stdout
    sidecar = json.loads((tmp_path / "nap.summary.json").read_text())
    assert sidecar["bodies_asleep"] == 1
    with h5py.File(out, "r") as file:
        assert file["parameters/summary"].attrs["bodies_asleep"] == 1
    info = cli("info", out, "--json")
    assert info.exit_code == 0 and json.loads(info.stdout)["summary"]["bodies_asleep"] == 1
    awake = json.loads(cli("run", scene, "--out", out, "--json", "-s", "world.sleep=false").stdout)
    assert awake["bodies_asleep"] == 0


def test_the_reader_exposes_the_flags(nap: Path) -> None:
    with rustycs.open_trajectory(nap) as run:
        np.testing.assert_array_equal(run.asleep, asleep_of(nap))
        assert run.frames(30, 33)["asleep"].tolist() == [[0, 0, 0], [0, 1, 0], [0, 1, 0]]
        assert [block["asleep"].sum() for block in run.blocks(frames=40)] == [9, 22, 0]
        data = run.to_xarray()
        assert data["asleep"].dims == ("time", "body") and int(data["asleep"].sum()) == NAP_WAKES - NAP_SLEEPS


def test_files_written_before_the_flags_read_as_never_asleep(cli, nap: Path, tmp_path: Path) -> None:
    old = without_asleep(nap, tmp_path)
    with rustycs.open_trajectory(old) as run:
        asleep = run.asleep
        assert asleep.shape == (91, 3) and asleep.dtype == np.bool_ and not asleep.any()
        asleep[0, 0] = True  # an array of its own, as the other series are
        assert not run.frames(0, 5)["asleep"].any() and not run.to_xarray()["asleep"].any()
    assert cli("info", old).exit_code == 0
    assert cli("render", old, "-o", tmp_path / "old.png").exit_code == 0
    assert cli("render", old, "-o", tmp_path / "old.html").exit_code == 0
    # against itself: identical; against the file with the flags: only they differ
    assert cli("compare", old, old).exit_code == 0
    result = cli("compare", old, nap, "--json")
    assert result.exit_code == 1, result.stderr
    quantities = json.loads(result.stdout)["quantities"]
    assert quantities["asleep"]["outside_tolerance"] == NAP_WAKES - NAP_SLEEPS
    assert quantities["asleep"]["first_tick"] == NAP_SLEEPS
    assert all(q["outside_tolerance"] == 0 for name, q in quantities.items() if name != "asleep")


def test_a_run_without_sleeping_compares_identical_to_one_from_before_the_flags(run_scene, cli,
                                                                                tmp_path: Path) -> None:
    awake = run_scene(FIVE_BODIES)
    result = cli("compare", without_asleep(awake, tmp_path), awake)
    assert result.exit_code == 0 and "identical" in result.stdout, result.stdout


def test_sleeping_changes_nothing_where_nothing_falls_asleep(run_scene, cli) -> None:
    """FIVE_BODIES records contacts of a pile settling; with sleeping on and a sleep_time longer than the
    run, nothing sleeps, and every recorded quantity is bitwise that of the run without sleeping."""
    awake = run_scene(FIVE_BODIES)
    resting = run_scene(FIVE_BODIES, "-s", "world.sleep=true", "-s", "world.sleep_time=5")
    result = cli("compare", resting, awake, "--json")
    assert result.exit_code == 0 and json.loads(result.stdout)["identical"] is True
    with h5py.File(awake, "r") as a, h5py.File(resting, "r") as b:
        for name in ("point", "normal", "depth", "normal_impulse"):
            np.testing.assert_array_equal(a[f"contacts/{name}"][()], b[f"contacts/{name}"][()])


def test_a_sweep_over_sleeping(cli, tmp_path: Path, compiled_engine: None) -> None:
    out = tmp_path / "sweep"
    result = cli("sweep", SLEEPING_PILE, "-p", "world.sleep=false,true", "-s", "world.duration=2",
                 "--out", out, "--workers", "1", "--local", "threads")
    assert result.exit_code == 0, result.stderr
    with open(out / "sweep.csv", newline="") as handle:
        rows = {row["world.sleep"]: row for row in csv.DictReader(handle)}
    assert rows["false"]["bodies_asleep"] == "0"
    assert rows["true"]["bodies_asleep"] == "21"  # the pyramid's crates; the ball comes at 3 s


def test_the_sleeping_pile_sleeps_wakes_when_the_ball_hits_and_sleeps_again(cli, tmp_path: Path,
                                                                            compiled_engine: None) -> None:
    out = tmp_path / "pile.h5"
    result = cli("run", SLEEPING_PILE, "--out", out, "--json", "--quiet")
    assert result.exit_code == 0, result.stderr
    summary = json.loads(result.stdout)
    with rustycs.open_trajectory(out) as run:
        asleep, steps, types = run.asleep, run.steps, run.body_types
        ball = run.body_index("ball-0")
    with h5py.File(out, "r") as file:
        thrown = int(file["particles/bodies/spawn_tick"][ball])
    crates = (types == "dynamic") & (np.arange(len(types)) != ball)
    assert crates.sum() == 21 and summary["emitters"]["ball"]["appeared"] == 1 and thrown == 180
    asleep_crates = asleep[:, crates].sum(axis=1)
    before = steps < thrown
    # at rest from the start, the pyramid falls asleep after sleep_time (0.5 s) and sleeps until the ball
    assert asleep_crates[steps == 31] == 21 and (asleep_crates[before & (steps >= 31)] == 21).all()
    # the ball wakes every crate it reaches through the pile (all of them: they touch), then they sleep again
    woken = np.flatnonzero(~before & (asleep_crates == 0))
    assert len(woken) and woken[0] < np.flatnonzero(steps == thrown + 60)[0]
    assert summary["bodies_asleep"] == asleep[-1, types == "dynamic"].sum() >= 20
    assert summary["bodies_asleep"] > asleep_crates[woken[0]]
