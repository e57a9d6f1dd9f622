"""`rustycs info`: what a trajectory holds, as a table or JSON; bad files are exit 2."""

from __future__ import annotations

import json
from pathlib import Path

import h5py
import numpy as np
import pytest


@pytest.fixture
def run_file(cli, five_body_scene: Path, tmp_path: Path, compiled_engine) -> Path:
    out = tmp_path / "five.h5"
    assert cli("run", five_body_scene, "--out", out, "--ticks", "12", "--every", "4", "--quiet",
               "-s", "world.precision=5").exit_code == 0
    return out


def test_info_json(cli, run_file: Path):
    result = cli("info", run_file, "--json")
    assert result.exit_code == 0, result.stderr
    info = json.loads(result.stdout)
    assert info["scene"] == "five" and info["status"] == "complete"
    assert info["ticks_completed"] == 12 and info["frames"] == 4
    assert info["dt"] == pytest.approx(1 / 60) and info["precision"] == 5
    assert info["bodies"] == {"total": 5, "by_type": {"static": 1, "dynamic": 3, "kinematic": 1},
                              "by_shape": {"aabb": 2, "circle": 1, "obb": 1, "polygon": 1}}
    assert info["shapes"] == {"total": 5, "by_type": {"aabb": 2, "circle": 1, "obb": 1, "polygon": 1},
                              "sensors": 0}
    assert info["overrides"] == ["world.precision=5"] and info["contacts_recorded"] is True
    assert info["summary"]["ticks"] == 12 and info["summary"]["bodies"] == 5


def test_info_table(cli, run_file: Path):
    result = cli("info", run_file)
    assert result.exit_code == 0
    for words in ("five", "complete", "ticks_completed", "3 dynamic", "2 aabb", "world.precision=5",
                  "bodies_at_rest"):
        assert words in result.stdout


CUP = """\
name: cup
world: {ticks: 3}
bodies:
  - {name: floor, type: static, shape: {type: chain, points: [[-3, 0], [3, 0]]}, position: [0, 0]}
  - name: cup
    position: [0, 2]
    shapes:
      - {type: obb, width: 2.0, height: 0.2, offset: [0, -0.9]}
      - {type: obb, width: 0.2, height: 2.0, offset: [-0.9, 0]}
      - {type: obb, width: 0.2, height: 2.0, offset: [0.9, 0]}
      - {type: circle, radius: 0.5, sensor: true}
"""


def test_info_counts_the_shapes_of_compound_bodies(cli, tmp_path: Path, compiled_engine):
    scene, out = tmp_path / "cup.yaml", tmp_path / "cup.h5"
    scene.write_text(CUP)
    assert cli("run", scene, "--out", out, "--quiet").exit_code == 0
    info = json.loads(cli("info", out, "--json").stdout)
    assert info["bodies"]["by_shape"] == {"chain": 1, "compound": 1}
    assert info["shapes"] == {"total": 5, "by_type": {"chain": 1, "obb": 3, "circle": 1}, "sensors": 1}
    table = cli("info", out).stdout
    assert "5: 1 chain, 3 obb, 1 circle; 1 sensor" in table
    with h5py.File(out, "a") as f:  # as written before /shapes existed
        del f["shapes"]
    result = cli("info", out)
    assert result.exit_code == 0 and "not recorded (an older file)" in result.stdout


def test_info_rejects_bad_files(cli, tmp_path: Path):
    junk = tmp_path / "junk.h5"
    junk.write_bytes(b"\x89HDF\r\n\x1a\n" + bytes(300))
    foreign = tmp_path / "foreign.h5"
    with h5py.File(foreign, "w") as f:
        f["x"] = np.ones(2)
    for path, words in ((tmp_path / "gone.h5", "no such file"), (junk, "corrupt"),
                        (foreign, "not a rustycs trajectory")):
        result = cli("info", path)
        assert result.exit_code == 2 and "Traceback" not in result.stderr
        assert result.stderr.startswith(f"{path}: ") and words in result.stderr
