"""Measures, stop conditions, emitters and sensors through scene files: the summary, the trajectory, the
sweep table, sampled sweeps and located errors."""

from __future__ import annotations

import csv
import json
import math
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

SCENES = Path(__file__).resolve().parent.parent / "scenes"
G = 9.81

DROP = """\
name: drop
world:
  tick_rate: 240
  duration: 2.0
  stop_when:
    - {event: contact_begin, bodies: [ball, floor]}
forces:
  - {name: gravity, acceleration: [0, -9.81]}
bodies:
  - {name: floor, type: static, shape: {type: aabb, width: 10, height: 1}, position: [0, -0.5]}
  - {name: ball, shape: {type: circle, radius: 0.1}, position: [0, 1.6]}
measures:
  - {name: impact, first: {event: contact_begin, bodies: [ball, floor]}}
"""

TAP = """\
name: tap
seed: 4
world: {tick_rate: 60, ticks: 90}
forces:
  - {name: gravity, acceleration: [0, -9.81]}
bodies:
  - {name: floor, type: static, shape: {type: aabb, width: 10, height: 1}, position: [0, -0.5]}
emitters:
  - name: drops
    shape: {type: circle, radius: {uniform: [0.04, 0.06]}}
    region: {min: [-1, 2], max: [1, 2.5]}
    velocity: [{normal: [0, 0.5]}, 0]
    rate: 20
    start: 0.1
    count: 8
sinks:
  - {name: drain, region: {min: [-10, -10], max: [0, 0.3]}}
measures:
  - {name: present, of: emitters.drops, count_inside: {min: [-10, -10], max: [10, 10]}}
  - {name: mean_y, of: emitters.drops.position.y, aggregate: mean}
"""


def run(cli, scene: Path, out: Path, *args: str) -> dict:  # noqa: ANN001
    result = cli("run", scene, "--out", out, "--json", "--quiet", *args)
    assert result.exit_code == 0, result.stderr
    return json.loads(result.stdout)


def write(tmp_path: Path, text: str, name: str = "scene.yaml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.mark.usefixtures("compiled_engine")
def test_projectile_range_apex_and_value_at_1s_against_the_closed_forms(cli, tmp_path: Path) -> None:  # noqa: ANN001
    summary = run(cli, SCENES / "projectile.yaml", tmp_path / "p.h5")
    measures, t = summary["measures"], summary["simulated_seconds"]
    assert summary["ticks"] == round(1.631 * 240)  # world.duration
    assert measures["range"] == pytest.approx(6.0 * t, rel=1e-6)  # no force along x: exact
    assert measures["x_at_1s"] == pytest.approx(6.0, rel=1e-6)
    assert measures["apex"] == pytest.approx(8.0**2 / (2 * G), rel=0.01)  # the integrator's own error
    assert measures["slowest"] == pytest.approx(6.0, rel=1e-3)  # at the apex
    with h5py.File(tmp_path / "p.h5", "r") as file:
        attrs = file["parameters/summary"].attrs
        assert attrs["measure.range"] == measures["range"] and attrs["measure.apex"] == measures["apex"]
    out = tmp_path / "height.png"
    assert cli("plot", tmp_path / "p.h5", "--body", "ball", "--y", "position.y", "-o", out).exit_code == 0
    assert out.read_bytes()[:4] == b"\x89PNG"
    assert cli("plot", tmp_path / "p.h5", "--body", "bal", "-o", out).exit_code == 2


@pytest.mark.usefixtures("compiled_engine")
def test_a_dropped_ball_stops_the_run_at_its_first_contact(cli, tmp_path: Path) -> None:  # noqa: ANN001
    summary = run(cli, write(tmp_path, DROP), tmp_path / "drop.h5", "--every", "50")
    expected = math.sqrt(2 * 1.5 / G)  # its bottom falls 1.5 m
    assert summary["status"] == "stopped" and summary["stop_reason"] == (
        '{"event": "contact_begin", "bodies": ["ball", "floor"]}')
    assert abs(summary["ticks"] - expected * 240) <= 3
    assert summary["measures"]["impact"] == pytest.approx(summary["ticks"] / 240)
    with h5py.File(tmp_path / "drop.h5", "r") as file:
        assert file["parameters"].attrs["status"] == "stopped"
        assert file["parameters"].attrs["stop_reason"] == summary["stop_reason"]
        assert file["particles/bodies/position/step"][-1] == summary["ticks"]  # the last frame is that tick
        assert "contact_begin" not in set(file["events/kind"].asstr()[:])  # output.events is off
    with_events = write(tmp_path, DROP.replace("world:", "output: {events: true}\nworld:"), "events.yaml")
    run(cli, with_events, tmp_path / "events.h5", "--every", "50")
    with h5py.File(tmp_path / "events.h5", "r") as file:
        assert list(file["events/kind"].asstr()[:]) == ["contact_begin"]


@pytest.mark.usefixtures("compiled_engine")
def test_emitted_bodies_names_spawn_ticks_sink_and_determinism(cli, tmp_path: Path) -> None:  # noqa: ANN001
    scene = write(tmp_path, TAP)
    summary = run(cli, scene, tmp_path / "a.h5")
    run(cli, scene, tmp_path / "b.h5")
    with h5py.File(tmp_path / "a.h5", "r") as file:
        names = list(file["particles/bodies/name"].asstr()[()])
        spawn = file["particles/bodies/spawn_tick"][()]
        active = file["particles/bodies/active/value"][()]
        position = file["particles/bodies/position/value"][()]
    assert names == ["floor", *(f"drops-{i}" for i in range(8))]
    assert list(spawn) == [0, *(6 + 3 * i for i in range(8))]  # from 0.1 s, one every 60 / 20 ticks
    for row, tick in enumerate(spawn[1:], start=1):
        assert not active[:tick, row].any() and active[tick, row]
    left = position[-1, 1:, 0] < 0
    assert summary["measures"]["present"] == 8 - left.sum()  # the sink took those left of x = 0
    assert not active[-1, 1:][left].any() and active[-1, 1:][~left].all()
    assert summary["measures"]["mean_y"] == pytest.approx(position[-1, 1:, 1][~left].mean(), rel=1e-12)
    with h5py.File(tmp_path / "b.h5", "r") as file:
        assert np.array_equal(file["particles/bodies/position/value"][()], position)  # run to run
    other = tmp_path / "c.h5"
    done = subprocess.run([sys.executable, "-m", "rustycs_cli", "run", str(scene), "--out", str(other),
                           "--quiet"], capture_output=True, text=True, check=False)
    if done.returncode != 0 and "No module named rustycs_cli.__main__" in done.stderr:
        done = subprocess.run([str(Path(sys.executable).parent / "rustycs"), "run", str(scene), "--out",
                               str(other), "--quiet"], capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    with h5py.File(other, "r") as file:
        assert np.array_equal(file["particles/bodies/position/value"][()], position)  # process to process


@pytest.mark.usefixtures("compiled_engine")
def test_galton_histogram_counts_every_bead_in_the_bins(cli, tmp_path: Path) -> None:  # noqa: ANN001
    summary = run(cli, SCENES / "galton_board.yaml", tmp_path / "g.h5", "--every", "100")
    bins = summary["measures"]["bins"]
    with h5py.File(tmp_path / "g.h5", "r") as file:
        names = list(file["particles/bodies/name"].asstr()[()])
        beads = [i for i, name in enumerate(names) if name.startswith("beads-")]
        x = file["particles/bodies/position/value"][-1, beads, 0]
        active = file["particles/bodies/active/value"][-1, beads]
    assert len(beads) == 60 and len(bins) == 8
    assert sum(bins) == int((active & (x >= -1.2) & (x <= 1.2)).sum())
    assert np.array_equal(bins, np.histogram(x[active], bins=np.linspace(-1.2, 1.2, 9))[0])


@pytest.mark.usefixtures("compiled_engine")
def test_sweep_measure_columns_equal_the_runs_alone_and_duration_keeps_the_time(cli, tmp_path: Path) -> None:  # noqa: ANN001
    scene = SCENES / "projectile.yaml"
    result = cli("sweep", scene, "-p", "world.tick_rate=60,120,240", "--out", tmp_path / "sweep", "--quiet",
                 "--workers", "1")
    assert result.exit_code == 0, result.stderr
    with open(tmp_path / "sweep" / "sweep.csv", newline="") as file:
        rows = list(csv.DictReader(file))
    assert [c for c in rows[0] if c.startswith("measure.")] == [
        "measure.range", "measure.apex", "measure.x_at_1s", "measure.slowest"]
    for row in rows:
        rate = float(row["world.tick_rate"])
        assert int(row["ticks"]) == round(1.631 * rate)  # the same simulated time
        alone = run(cli, scene, tmp_path / f"alone-{row['index']}.h5", "-s", f"world.tick_rate={rate}")
        for name, value in alone["measures"].items():
            assert float(row[f"measure.{name}"]) == value
    out = tmp_path / "range.png"
    plotted = cli("plot", tmp_path / "sweep" / "sweep.csv", "--x", "world.tick_rate", "--y", "measure.range",
                  "-o", out)
    assert plotted.exit_code == 0 and out.read_bytes()[:4] == b"\x89PNG"


@pytest.mark.usefixtures("compiled_engine")
def test_a_sampled_sweep_is_reproducible_for_one_seed(cli, tmp_path: Path) -> None:  # noqa: ANN001
    tables = []
    for attempt, seed in enumerate((7, 7, 8)):
        result = cli("sweep", SCENES / "projectile.yaml", "-p", "bodies.ball.velocity.0=uniform(4,8)",
                     "-p", "world.tick_rate=60,120", "--samples", "3", "--seed", str(seed), "--ticks", "10",
                     "--out", tmp_path / f"s{attempt}", "--quiet", "--workers", "1")
        assert result.exit_code == 0, result.stderr
        with open(tmp_path / f"s{attempt}" / "sweep.csv", newline="") as file:
            tables.append([(r["bodies.ball.velocity.0"], r["world.tick_rate"]) for r in csv.DictReader(file)])
    assert len(tables[0]) == 6 and tables[0] == tables[1] and tables[0] != tables[2]
    assert all(4 <= float(v) <= 8 for v, _ in tables[0])


BAD = """\
name: bad
world:
  ticks: 100
  duration: 2.0
  stop_when:
    - {inside: floor, bodies: [ball]}
bodies:
  - {name: floor, type: static, shape: {type: aabb, width: 10, height: 1}, position: [0, -0.5]}
  - {name: ball, shape: {type: circle, radius: 0.1}, position: [0, 1]}
emitters:
  - {name: tap, shape: {type: circle, radius: 0.1}, position: [0, 2]}
measures:
  - {name: a, of: bodies.bal.position.x}
  - {name: b, of: bodies.ball.position.z}
  - {name: c, of: bodies.ball.position.x, histogram: [0, 2, 1]}
  - {name: d, first: {event: contact_begin, bodies: [ball, flor]}}
"""


def test_bad_measures_and_conditions_at_their_file_line_column(cli, tmp_path: Path) -> None:  # noqa: ANN001
    scene = write(tmp_path, BAD)
    result = cli("validate", scene)
    assert result.exit_code == 2
    lines = result.stderr.strip().splitlines()
    expected = [
        f"{scene}:4:13: world.duration: give world.ticks or world.duration, not both",
        f"{scene}:6:16: world.stop_when.0.inside: 'floor' is not a sensor",
        f"{scene}:11:5: emitters.tap: missing key 'rate'",
        f"{scene}:13:19: measures.a.of: unknown body 'bal' (did you mean 'ball'?)",
        f"{scene}:14:19: measures.b.of: unknown quantity 'position.z'",
        f"{scene}:15:54: measures.c.histogram: histogram edges must be strictly ascending",
        f"{scene}:16:60: measures.d.first.bodies.1: unknown body, generator or emitter 'flor'",
    ]
    assert len(lines) == len(expected), result.stderr
    for line, start in zip(lines, expected, strict=True):
        assert line.startswith(start), (line, start)


@pytest.mark.usefixtures("compiled_engine")
def test_run_duration_option_sets_the_ticks(cli, tmp_path: Path) -> None:  # noqa: ANN001
    scene = write(tmp_path, DROP)
    assert run(cli, scene, tmp_path / "d.h5", "--duration", "0.1")["ticks"] == 24  # 0.1 s at 240 Hz
    both = cli("run", scene, "--out", tmp_path / "e.h5", "--duration", "0.1", "--ticks", "5")
    assert both.exit_code == 2 and "give --ticks or --duration, not both" in both.stderr


TAP_IN_PLACE = """\
name: tap-in-place
world: {tick_rate: 60, duration: 2.0}
forces:
  - {name: gravity, acceleration: [0, -1]}
bodies:
  - {name: floor, type: static, shape: {type: aabb, width: 10, height: 1}, position: [0, -6]}
emitters:
  - {name: tap, shape: {type: circle, radius: 0.5}, position: [0, 2], rate: 10, count: 20,
     placement: no_overlap}
"""


@pytest.mark.usefixtures("compiled_engine")
def test_a_no_overlap_emitter_skips_the_bodies_whose_place_is_taken(cli, tmp_path: Path) -> None:  # noqa: ANN001
    scene = write(tmp_path, TAP_IN_PLACE)
    summary = run(cli, scene, tmp_path / "a.h5")
    with h5py.File(tmp_path / "a.h5", "r") as file:
        spawn = file["particles/bodies/spawn_tick"][()]
        active = file["particles/bodies/active/value"][()]
        position = file["particles/bodies/position/value"][()]
        kinds = list(file["events/kind"].asstr()[()])
        attrs = dict(file["parameters/summary"].attrs)
    appeared = active[:, 1:].any(axis=0)
    # one every 6 ticks, each where the last one was: only once that one has fallen 2 r = 1 m (g = 1:
    # after 1.41 s) is the place free again
    assert 1 < appeared.sum() < 20
    shown = int(appeared.sum())
    assert summary["emitters"] == {"tap": {"appeared": shown, "skipped": 20 - shown}}
    assert summary["escaped_bodies"] == 0  # skipped is not escaped
    assert attrs["emitter.tap.skipped"] == 20 - shown and attrs["emitter.tap.appeared"] == shown
    assert kinds.count("spawn") == appeared.sum() - 1  # the first is there from the start
    assert np.array_equal(spawn[1:] == -1, ~appeared)  # the skipped ones never appeared
    assert list(spawn[1:][appeared][:2]) == [0, 90]  # the drop from tick 0 is 1 m below by tick 85
    for frame in range(len(active)):  # no two present bodies overlap at any frame
        xy = position[frame, 1:][active[frame, 1:]]
        gaps = np.hypot(*(xy[:, None, :] - xy[None, :, :]).transpose(2, 0, 1))
        assert (gaps[np.triu_indices(len(xy), 1)] >= 1.0).all()
    table = cli("run", scene, "--out", tmp_path / "b.h5")  # the table printed by `rustycs run`, and again
    assert table.exit_code == 0 and "emitter.tap.skipped" in table.stdout
    with h5py.File(tmp_path / "b.h5", "r") as file:
        assert np.array_equal(file["particles/bodies/position/value"][()], position)
        assert np.array_equal(file["particles/bodies/spawn_tick"][()], spawn)

    free_scene = write(tmp_path, TAP_IN_PLACE.replace("no_overlap", "free"), "free.yaml")
    free = run(cli, free_scene, tmp_path / "f.h5")
    assert free["emitters"] == {"tap": {"appeared": 20, "skipped": 0}}
    with h5py.File(tmp_path / "f.h5", "r") as file:
        assert list(file["particles/bodies/spawn_tick"][1:]) == list(range(0, 120, 6))
        assert file["particles/bodies/active/value"][-1, 1:].all()


SNAP = """\
name: snap
world: {tick_rate: 240, duration: 1.0}
forces:
  - {name: gravity, acceleration: [0, -9.81]}
bodies:
  - {name: hook, type: static, shape: {type: circle, radius: 0.05}, position: [-2, 2]}
  - {name: bob, shape: {type: circle, radius: 0.1}, position: [-2, 1.5]}
  - {name: pivot, type: static, shape: {type: circle, radius: 0.05}, position: [0, 2]}
  - {name: weight, shape: {type: circle, radius: 0.1}, position: [1, 2]}
  - {name: loose, shape: {type: circle, radius: 0.1}, position: [3, 1]}
joints:
  - {name: thread, type: revolute, bodies: [hook, bob], anchor: [-2, 2], break_force: 0.001}
  - {name: arm, type: revolute, bodies: [pivot, weight], anchor: [0, 2], break_force: 0.06}
measures:
  - {name: snapped, first: {event: joint_break, bodies: [pivot, weight]}}
  - {name: weight_free, first: {event: joint_break, bodies: [weight]}}
  - {name: any_break, first: {event: joint_break}}
"""


@pytest.mark.usefixtures("compiled_engine")
def test_a_joint_break_of_the_named_bodies_is_measured_and_stops_the_run(cli, tmp_path: Path) -> None:  # noqa: ANN001
    # the thread breaks in tick 1 under the bob's weight (0.03 N); the arm, a pendulum let go level,
    # once its tension (3 m g cos of the swing from the vertical) passes 0.06 N, about two bob weights
    summary = run(cli, write(tmp_path, SNAP), tmp_path / "snap.h5")
    with h5py.File(tmp_path / "snap.h5", "r") as file:
        joints = list(file["joints/name"].asstr()[()])
        rows, ticks = file["events/body_a"][()], file["events/tick"][()]  # body_a: the joint's row
        breaks = {joints[row]: int(tick) for row, tick in zip(rows, ticks, strict=True)}
        assert set(file["events/kind"].asstr()[()]) == {"joint_break"}
    assert breaks["thread"] == 1 and breaks["arm"] > 20
    measures = summary["measures"]
    assert measures["snapped"] == pytest.approx(breaks["arm"] / 240)  # not the thread's, which came first
    assert measures["weight_free"] == measures["snapped"]
    assert measures["any_break"] == pytest.approx(1 / 240)

    stopping = SNAP.replace("world: {tick_rate: 240, duration: 1.0}",
                            "world:\n  tick_rate: 240\n  duration: 1.0\n"
                            "  stop_when:\n    - {event: joint_break, bodies: [weight, pivot]}")
    stopped = run(cli, write(tmp_path, stopping, "stop.yaml"), tmp_path / "stop.h5", "--every", "50")
    assert stopped["status"] == "stopped" and stopped["ticks"] == breaks["arm"]
    assert stopped["stop_reason"] == '{"event": "joint_break", "bodies": ["weight", "pivot"]}'
    with h5py.File(tmp_path / "stop.h5", "r") as file:
        assert file["particles/bodies/position/step"][-1] == breaks["arm"]


def test_a_joint_break_of_bodies_no_joint_joins_at_its_file_line_column(cli, tmp_path: Path) -> None:  # noqa: ANN001
    text = SNAP.replace("world: {tick_rate: 240, duration: 1.0}", "world:\n  duration: 1.0\n  stop_when:\n"
                        "    - {event: joint_break, bodies: [bob, pivot]}")
    text = text.replace("[pivot, weight]}}", "[hook, weight]}}").replace("[weight]}}", "[loose]}}")
    scene = write(tmp_path, text + "  - {name: touch, first: {event: contact_begin, bodies: [bob, loose]}}\n")
    result = cli("validate", scene)
    assert result.exit_code == 2
    why = "(a joint_break's bodies name the joints that join them)"
    assert result.stderr.strip().splitlines() == [
        f"{scene}:5:36: world.stop_when.0.bodies: no joint joins 'bob' and 'pivot' {why}",
        f"{scene}:18:57: measures.snapped.first.bodies: no joint joins 'hook' and 'weight' {why}",
        f"{scene}:19:61: measures.weight_free.first.bodies: no joint joins 'loose' {why}",
    ]
