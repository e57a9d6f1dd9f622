"""A run whose state becomes non-finite: status diverged, exit 1, frames up to the last finite one kept."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

# An absurd force overflows the velocity to infinity after 1e308/(1e308/60) = 60 ticks or so. Scenes
# cannot ask for it (MAX_ACCELERATION): the run gets it past validation, as an engine fault would.
EXPLODING = """\
name: boom
world: {tick_rate: 60, ticks: 200}
forces: [{name: absurd, acceleration: [0, -1e9]}]
bodies:
  - {name: anchor, type: static, shape: {type: circle, radius: 0.5}, position: [10, 0]}
  - {name: rocket, shape: {type: circle, radius: 0.2}, position: [0, 0]}
"""


RUN_WITH_ABSURD_FORCE = """
import dataclasses, sys
from pathlib import Path
from rustycs_cli.loading import load_scene
from rustycs_cli.simulation import run_scene
from rustycs_cli.summary import to_json
loaded = load_scene(sys.argv[1])
force = loaded.scene.forces[0].model_copy(update={"acceleration": (0.0, -1e308)})
loaded = dataclasses.replace(loaded, scene=loaded.scene.model_copy(update={"forces": [force]}))
result = run_scene(loaded, Path(sys.argv[2]), every=int(sys.argv[3]), quiet=True)
print(result.message, file=sys.stderr)
print(to_json(result.summary))
sys.exit(result.exit_code)
"""


@pytest.mark.usefixtures("compiled_engine")
@pytest.mark.parametrize("every", [1, 8])
def test_divergence_keeps_the_finite_frames(tmp_path: Path, every: int):
    scene = tmp_path / "boom.yaml"
    scene.write_text(EXPLODING)
    out = tmp_path / "boom.h5"
    # a subprocess, so that a crash of the engine on non-finite values fails this test only
    result = subprocess.run(
        [sys.executable, "-c", RUN_WITH_ABSURD_FORCE, str(scene), str(out), str(every)],
        capture_output=True, text=True, timeout=300,
    )
    assert result.returncode == 1, result.stderr
    assert "Traceback" not in result.stderr
    summary = json.loads(result.stdout)
    assert summary["status"] == "diverged"
    message = result.stderr.strip()
    assert "diverged at tick" in message and "'rocket'" in message and summary["divergence"] == message
    with h5py.File(out, "r") as f:
        assert f["parameters"].attrs["status"] in ("diverged", b"diverged")
        step = f["particles/bodies/position/step"][()]
        last = int(step[-1])
        assert f["parameters"].attrs["ticks_completed"] == last == summary["ticks"]
        np.testing.assert_array_equal(step, np.arange(0, last + 1, every))
        assert 30 < last < 200
        for name in ("position", "velocity", "angle", "angular_velocity"):
            assert np.isfinite(f[f"particles/bodies/{name}/value"][()]).all(), name
        velocity = f["particles/bodies/velocity/value"][-1, 1, 1]
    assert velocity < -1e306  # it really was on its way out
    tick = int(message.split("diverged at tick ")[1].split(":")[0])
    assert last < tick <= last + every
    assert json.loads((tmp_path / "boom.summary.json").read_text())["status"] == "diverged"


@pytest.mark.usefixtures("compiled_engine")
def test_divergence_reported_by_the_engine_mid_block(cli, five_body_scene: Path, tmp_path: Path, monkeypatch):
    """The engine raises in the middle of a 5-tick block (tick 23, body 1): frames 0..20 are kept."""
    import rustycs

    original = rustycs.World.step

    def step(world, n: int = 1, record=None, every: int = 1) -> int:
        if world.tick + n < 23:
            return original(world, n, record, every)
        original(world, 22 - world.tick)  # ticks 21 and 22 record no frame (every 5)
        raise rustycs.SimulationDiverged(23, 1, "non-finite state in tick 23 at body 1", frames=0)

    monkeypatch.setattr(rustycs.World, "step", step)
    out = tmp_path / "five.h5"
    result = cli("run", five_body_scene, "--out", out, "--every", "5", "--quiet")
    assert result.exit_code == 1
    assert result.stderr.strip() == (f"rustycs: the run diverged at tick 23: body 'ball' (index 1) got a "
                                     f"non-finite state; frames up to tick 20 are kept in {out}")
    with h5py.File(out, "r") as f:
        np.testing.assert_array_equal(f["particles/bodies/position/step"][()], [0, 5, 10, 15, 20])
        assert f["parameters"].attrs["ticks_completed"] == 20
        assert f["parameters/summary"].attrs["status"] in ("diverged", b"diverged")
        assert f["contacts/offset"].shape == (6,)
