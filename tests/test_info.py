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
    assert info["overrides"] == ["world.precision=5"] and info["contacts_recorded"] is True
    assert info["summary"]["ticks"] == 12 and info["summary"]["bodies"] == 5


def test_info_table(cli, run_file: Path):
    result = cli("info", run_file)
    assert result.exit_code == 0
    for words in ("five", "complete", "ticks_completed", "3 dynamic", "2 aabb", "world.precision=5",
                  "bodies_at_rest"):
        assert words in result.stdout


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
