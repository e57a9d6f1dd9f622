"""Bad input to `rustycs run`: exit code 2, one clear message, no traceback, no output file."""

from __future__ import annotations

import os
from pathlib import Path

import h5py
import numpy as np
import pytest


def assert_user_error(result, *words: str) -> None:
    assert result.exit_code == 2, (result.stdout, result.stderr)
    assert "Traceback" not in result.stderr and result.stdout == ""
    for word in words:
        assert word in result.stderr


def test_output_folder_missing(cli, five_body_scene: Path, tmp_path: Path):
    out = tmp_path / "nowhere" / "run.h5"
    result = cli("run", five_body_scene, "--out", out)
    assert_user_error(result, f"{out}: output folder", "does not exist")
    assert not out.parent.exists()


def test_output_folder_read_only(cli, five_body_scene: Path, tmp_path: Path):
    folder = tmp_path / "locked"
    folder.mkdir()
    folder.chmod(0o555)
    try:
        result = cli("run", five_body_scene, "--out", folder / "run.h5")
        assert_user_error(result, "not writable")
        assert list(folder.iterdir()) == []
    finally:
        folder.chmod(0o755)


def test_output_is_a_folder(cli, five_body_scene: Path, tmp_path: Path):
    assert_user_error(cli("run", five_body_scene, "--out", tmp_path), "is a folder")


@pytest.mark.parametrize("content", [b"\x89HDF\r\n\x1a\n" + os.urandom(600), b"just text\n"])
def test_corrupt_trajectory_as_scene(cli, tmp_path: Path, content: bytes):
    bad = tmp_path / "bad.h5"
    bad.write_bytes(content)
    assert_user_error(cli("run", bad, "--out", tmp_path / "out.h5"), f"{bad}: ")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.h5"]


def test_foreign_hdf5_as_scene(cli, tmp_path: Path):
    foreign = tmp_path / "foreign.h5"
    with h5py.File(foreign, "w") as f:
        f["data"] = np.arange(4)
    assert_user_error(cli("run", foreign, "--out", tmp_path / "out.h5"), "not a rustycs trajectory")
    assert not (tmp_path / "out.h5").exists()


def test_missing_scene(cli, tmp_path: Path):
    assert_user_error(cli("run", tmp_path / "nope.yaml", "--out", tmp_path / "o.h5"), "nope.yaml")


def test_bad_option_value(cli, five_body_scene: Path, tmp_path: Path):
    result = cli("run", five_body_scene, "--every", "0", "--out", tmp_path / "o.h5")
    assert result.exit_code == 2 and "Traceback" not in result.stderr
    assert not (tmp_path / "o.h5").exists()
