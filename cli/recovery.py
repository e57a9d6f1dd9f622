"""Recovering the frames of a killed run: its temporary file `.NAME.h5.tmp-PID` is flushed to a consistent
state every few seconds (`TrajectoryWriter`), so after SIGKILL, an OOM kill or a lost worker it can be
made into an `interrupted` trajectory of the frames saved so far."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from .errors import UserError
from .output_files import TEMPORARY_NAME, stale_temporaries

FRAMES = "particles/bodies/position"


def recover(temporary: Path) -> tuple[Path, dict[str, Any]]:
    """Make the temporary file of a killed run into a trajectory next to it (NAME.h5, or
    NAME-recovered.h5 when that exists); returns its path and summary. UserError when the file is not
    such a temporary, its process still runs, or it holds no consistent state."""
    import h5py

    from .summary import sidecar_path, to_json, write_text_atomic

    match = TEMPORARY_NAME.match(temporary.name)
    if match is None or not temporary.is_file():
        raise UserError(f"{temporary}: not the temporary file of a run (.NAME.h5.tmp-PID)")
    if temporary not in stale_temporaries(temporary.parent):
        raise UserError(f"{temporary}: process {match['pid']} is still writing it")
    target = temporary.with_name(match["name"])
    if target.exists():
        target = target.with_name(f"{target.stem}-recovered{target.suffix}")
    try:
        with h5py.File(temporary, "r+") as file:
            summary = _truncate(file)
    except (OSError, KeyError, ValueError) as err:
        raise UserError(f"{temporary}: cannot be recovered: no consistent state was saved ({err})") from None
    os.replace(temporary, target)
    write_text_atomic(sidecar_path(target), to_json(summary) + "\n")
    return target, summary


def _truncate(file: Any) -> dict[str, Any]:
    """Cut every series to the frames all of them hold, and mark the run interrupted."""
    import numpy as np
    import yaml

    series = [item for name, item in _datasets(file) if name.endswith("/value") or name.endswith("/step")
              or name.endswith("/time")]
    frames = min(len(item) for item in series)
    if frames == 0:
        raise ValueError("no frame was saved")
    for item in series:
        item.resize(frames, axis=0)
    if "contacts/offset" in file:
        offset = file["contacts/offset"]
        offset.resize(frames + 1, axis=0)
        rows = int(offset[frames])
        for name in file["contacts"]:
            if name != "offset":
                file["contacts"][name].resize(rows, axis=0)
    last = int(file[f"{FRAMES}/step"][frames - 1])
    if "events/tick" in file:  # in tick order: those after the last saved frame go
        kept = int(np.searchsorted(file["events/tick"][()], last, side="right"))
        for name in file["events"]:
            file["events"][name].resize(kept, axis=0)
    scene = yaml.safe_load(file["parameters/scene"].asstr()[()]) or {}
    summary = {"scene": scene.get("name"), "status": "interrupted", "ticks": last, "frames": frames,
               "recovered": True}
    parameters = file["parameters"]
    parameters.attrs.update({"status": "interrupted", "ticks_completed": last, "frames": frames})
    if "summary" in parameters:
        del parameters["summary"]
    group = parameters.create_group("summary", track_order=True)
    group.attrs.update({k: v for k, v in summary.items() if v is not None})
    return summary


def _datasets(file: Any) -> list[tuple[str, Any]]:
    """Every growing dataset of the frame series (hard links appear once)."""
    import h5py

    found: dict[Any, tuple[str, Any]] = {}

    def visit(name: str, item: Any) -> None:
        if isinstance(item, h5py.Dataset) and item.maxshape and item.maxshape[0] is None \
                and not name.startswith(("contacts/", "events/")):
            found.setdefault(item.id, (name, item))

    file.visititems(visit)
    return list(found.values())
