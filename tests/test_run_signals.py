"""A real `rustycs run` subprocess stopped by SIGINT or SIGTERM: exit 130 and a valid, consistent file."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np
import pytest

LONG_SCENE = """\
name: long
world: {tick_rate: 240, ticks: 100000000}
forces: [{name: gravity, acceleration: [0, -9.81]}]
bodies:
  - {name: floor, type: static, shape: {type: aabb, width: 20, height: 1}, position: [0, -0.5]}
  - {name: ball, shape: {type: circle, radius: 0.3}, position: [0, 2], material: rubber}
  - {name: box, shape: {type: obb, width: 0.5, height: 0.5}, position: [1, 3], angle: 0.4}
output: {every: 1}
"""


def wait_until_stepping(folder: Path, process: subprocess.Popen, timeout: float = 120.0) -> None:
    """Until the temporary trajectory exists (it is created just before the first step), then a second
    more, so that the signal lands while ticks are being stepped."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        assert process.poll() is None, process.communicate()
        if list(folder.glob(".long.h5.tmp-*")):
            time.sleep(1.0)
            return
        time.sleep(0.05)
    process.kill()
    pytest.fail("the run did not start")


@pytest.mark.usefixtures("compiled_engine")
@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_signal_stops_the_run_with_a_valid_file(tmp_path: Path, signum: int):
    scene = tmp_path / "long.yaml"
    scene.write_text(LONG_SCENE)
    out = tmp_path / "long.h5"
    process = subprocess.Popen(
        [sys.executable, "-c", "from rustycs_cli.app import program; program()", "run", str(scene), "--out",
         str(out), "--json"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )
    wait_until_stepping(tmp_path, process)
    process.send_signal(signum)
    stdout, stderr = process.communicate(timeout=120)
    assert process.returncode == 130, stderr
    assert "interrupted" in stderr and "Traceback" not in stderr
    summary = json.loads(stdout)
    assert summary["status"] == "interrupted"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["long.h5", "long.summary.json", "long.yaml"]
    with h5py.File(out, "r") as f:
        parameters = f["parameters"].attrs
        completed = int(parameters["ticks_completed"])
        step = f["particles/bodies/position/step"][()]
        assert parameters["status"] in ("interrupted", b"interrupted")
        assert 1 <= completed < 100000000
        np.testing.assert_array_equal(step, np.arange(completed + 1))
        for name in ("position", "velocity", "angle", "angular_velocity", "active"):
            assert f[f"particles/bodies/{name}/value"].shape[:2] == (completed + 1, 3)
        assert f["observables/kinetic_energy/value"].shape == (completed + 1,)
        assert np.isfinite(f["particles/bodies/position/value"][()]).all()
    assert summary["ticks"] == completed and summary["frames"] == completed + 1
