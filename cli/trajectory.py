"""HDF5 trajectory files: opening one for reading (this part) and writing a run (below).

The layout is the one of /work/shared/spec/trajectory-format.md (H5MD 1.1, dimension 2).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING

from rustycs_cli.errors import UserError

if TYPE_CHECKING:
    import h5py

CREATOR = "rustycs"
POSITION = "particles/bodies/position/value"


def open_trajectory(path: str | Path) -> h5py.File:
    """Open a rustycs trajectory read-only (use it as a context manager).

    Raises UserError("PATH: ...") when the file is missing or unreadable, is not HDF5, or is an HDF5
    file that rustycs did not write, so every command reading runs reports bad input the same way.
    """
    import h5py

    path = Path(path)
    if not path.exists():
        raise UserError(f"{path}: no such file")
    if path.is_dir():
        raise UserError(f"{path}: is a folder, not a trajectory file")
    if not os.access(path, os.R_OK):
        raise UserError(f"{path}: permission denied")
    try:
        file = h5py.File(path, "r")
    except OSError as err:
        if not _has_hdf5_signature(path):
            raise UserError(f"{path}: not an HDF5 file (expected a rustycs trajectory .h5)") from None
        raise UserError(f"{path}: unreadable or corrupt HDF5 file ({err})") from None
    try:
        problem = _foreign_reason(file)
    except (OSError, KeyError, RuntimeError) as err:  # damaged metadata inside a readable file
        problem = f"corrupt HDF5 file ({err})"
    if problem:
        file.close()
        raise UserError(f"{path}: {problem}")
    return file


def _has_hdf5_signature(path: Path) -> bool:
    """True when the file starts like HDF5 (so an open failure means corruption, not a foreign format)."""
    with open(path, "rb") as handle:
        return handle.read(8) == b"\x89HDF\r\n\x1a\n"


def _foreign_reason(file: h5py.File) -> str | None:
    """Why an open HDF5 file is not a rustycs trajectory, or None when it is one."""
    if "h5md" not in file:
        return "not a rustycs trajectory (no /h5md group: not an H5MD file)"
    creator = file["h5md"].get("creator")
    name = _text(creator.attrs.get("name")) if creator is not None else None
    if name != CREATOR:
        return f"not a rustycs trajectory (H5MD creator is {name!r}, expected {CREATOR!r})"
    if POSITION not in file:
        return f"not a rustycs trajectory (missing /{POSITION})"
    return None


def _text(value: object) -> str | None:
    """An HDF5 string attribute as str (h5py returns str or bytes depending on how it was written)."""
    if isinstance(value, bytes):
        return value.decode("utf-8", "replace")
    return None if value is None else str(value)
