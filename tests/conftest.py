"""Shared fixtures: the engine compiled once per session, `rustycs` run in-process, small scenes."""

from __future__ import annotations

import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import pytest

FIVE_BODIES = """\
name: five
world: {tick_rate: 60, ticks: 60, precision: 8}
forces:
  - {name: gravity, acceleration: [0, -9.81]}
bodies:
  - {name: floor, type: static, shape: {type: aabb, width: 10, height: 0.5}, position: [0, -0.25],
     material: stone}
  - {name: ball, shape: {type: circle, radius: 0.2}, position: [-2, 0.5], material: rubber}
  - {name: crate, shape: {type: obb, width: 0.5, height: 0.5}, position: [0, 0.26], angle: 0.1}
  - {name: wedge, shape: {type: polygon, vertices: [[0, 0], [0.6, 0], [0, 0.6]]}, position: [2, 0.01]}
  - {name: slider, type: kinematic, shape: {type: aabb, width: 1, height: 0.2}, position: [0, 3],
     velocity: [0.5, 0]}
output: {every: 1, contacts: true}
"""
# Every shape kind: a static body of lines (a segment, a closed chain) and a sensor region, a dynamic cup
# of three boxes (one of its own material) and a sensor disc, a concave L, a turned capsule, an offset circle.
EVERY_SHAPE = """\
name: every-shape
world: {tick_rate: 60, ticks: 2, precision: 4}
bodies:
  - name: ground
    type: static
    position: [0, 0]
    material: stone
    shapes:
      - {type: segment, points: [[-4, 0], [4, 0]]}
      - {type: chain, points: [[-3.5, 4], [-2.5, 4], [-2.5, 5]], loop: true}
      - {type: aabb, width: 1, height: 0.4, offset: [3, 4.5], sensor: true}
  - name: cup
    position: [0, 2]
    material: plastic
    shapes:
      - {type: obb, width: 2.0, height: 0.2, offset: [0, -0.9]}
      - {type: obb, width: 0.2, height: 2.0, offset: [-0.9, 0]}
      - {type: obb, width: 0.2, height: 2.0, offset: [0.9, 0], material: rubber}
      - {type: circle, radius: 0.5, offset: [0, 0.2], sensor: true}
  - name: hook
    position: [-2.5, 1.5]
    velocity: [0, 5]
    material: metal
    shape: {type: polygon, vertices: [[0, 0], [1, 0], [1, 0.25], [0.25, 0.25], [0.25, 1], [0, 1]]}
  - {name: pill, shape: {type: capsule, length: 1, radius: 0.25}, position: [2.5, 1.5], angle: 0.5,
     material: rubber}
  - {name: wheel, shape: {type: circle, radius: 0.4, offset: [0.3, 0]}, position: [-1, 4], material: plastic}
"""


SENSOR_DROP = """\
name: sensor-drop
world: {tick_rate: 60, ticks: 60}
forces:
  - {name: gravity, acceleration: [0, -9.81]}
bodies:
  - {name: floor, type: static, shape: {type: aabb, width: 4, height: 0.2}, position: [0, -0.1]}
  - {name: goal, type: static, material: plastic, position: [0, 1],
     shape: {type: aabb, width: 1, height: 0.5, sensor: true}}
  - {name: ball, shape: {type: circle, radius: 0.1}, position: [0, 2]}
"""
# Sleeping (world.sleep): the crate rests on the floor and falls asleep at tick 31; the ball dropped on it
# lands at tick 62 and wakes it.
NAP = """\
name: nap
world: {tick_rate: 60, ticks: 90, precision: 4, sleep: true}
forces:
  - {name: gravity, acceleration: [0, -9.81]}
bodies:
  - {name: floor, type: static, shape: {type: aabb, width: 6, height: 0.5}, position: [0, -0.25],
     material: stone}
  - {name: crate, shape: {type: obb, width: 0.6, height: 0.6}, position: [-1, 0.3], material: plastic}
  - {name: ball, shape: {type: circle, radius: 0.2}, position: [-1, 6], material: rubber}
"""
NAP_SLEEPS, NAP_WAKES = 31, 62  # ticks


@pytest.fixture(scope="session")
def compiled_engine() -> None:
    """Compile (or load from the disk cache) the engine's kernels once, before runs that are timed or
    interrupted."""
    from rustycs_cli.simulation import warm_up

    warm_up()


@dataclass
class CliResult:
    exit_code: int
    stdout: str
    stderr: str


@pytest.fixture
def cli(capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> Callable[..., CliResult]:
    """Run `rustycs ARGS...` in this process through the real entry point (user errors -> exit 2)."""
    from rustycs_cli.app import main

    def invoke(*args: str | Path) -> CliResult:
        capsys.readouterr()
        monkeypatch.setattr(sys, "argv", ["rustycs", *map(str, args)])
        try:
            main()
            code = 0
        except SystemExit as done:
            code = done.code if isinstance(done.code, int) else (0 if done.code is None else 1)
        out, err = capsys.readouterr()
        return CliResult(code, out, err)

    return invoke


@pytest.fixture
def five_body_scene(tmp_path: Path) -> Path:
    """A 5-body scene (static floor, circle, obb, polygon, kinematic aabb) that records contacts."""
    path = tmp_path / "five.yaml"
    path.write_text(FIVE_BODIES)
    return path


@pytest.fixture(scope="session")
def run_scene(tmp_path_factory: pytest.TempPathFactory, compiled_engine: None) -> Callable[..., Path]:
    """`rustycs run` on scene text (plus extra arguments), once per distinct input per session; returns
    the trajectory. For tests that only read trajectories (render, plot)."""
    from rustycs_cli.app import main

    made: dict[tuple[str, tuple[str, ...]], Path] = {}

    def run(text: str, *args: str) -> Path:
        if (text, args) not in made:
            folder = tmp_path_factory.mktemp("run")
            scene, out = folder / "scene.yaml", folder / "run.h5"
            scene.write_text(text)
            with pytest.MonkeyPatch.context() as patch:
                argv = ["rustycs", "run", str(scene), "--out", str(out), "--quiet", *args]
                patch.setattr(sys, "argv", argv)
                try:
                    main()
                except SystemExit as done:
                    assert done.code in (0, None), f"rustycs run failed with exit code {done.code}"
            made[(text, args)] = out
        return made[(text, args)]

    return run


@pytest.fixture(scope="session")
def sensor_drop(run_scene: Callable[..., Path]) -> tuple[Path, int, int]:
    """A ball falling through a sensor box (output.events off: the sensor events are there anyway), and
    the ticks it entered and left."""
    import h5py

    path = run_scene(SENSOR_DROP)
    with h5py.File(path, "r") as file:
        kinds = list(file["events/kind"].asstr()[()])
        ticks = list(file["events/tick"][()])
    assert kinds == ["sensor_enter", "sensor_exit"]
    return path, int(ticks[0]), int(ticks[1])
