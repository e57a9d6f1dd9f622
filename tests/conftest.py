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
