"""Is an opened rustycs trajectory whole? Shapes and dtypes are checked once, where a trajectory is opened
(`open_trajectory`), so that `info`, `compare`, `render`, `plot` and `run X.h5` all refuse a damaged or
edited file with the reason, instead of failing somewhere inside with a traceback or, worse, comparing
the frames that happen to be there."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import h5py

FRAMES = "particles/bodies/position"


def damage(file: h5py.File) -> str | None:
    """Why the trajectory cannot be read as rustycs wrote it, or None when it is whole."""
    import h5py
    import numpy as np

    from .trajectory import FRAME_SERIES, OBSERVABLES

    def dataset(path: str) -> h5py.Dataset | None:
        found = file.get(path)
        return found if isinstance(found, h5py.Dataset) else None

    def numeric(data: h5py.Dataset) -> bool:
        return data.dtype.kind in "biuf"

    for path in ("parameters/scene", f"{FRAMES}/value", f"{FRAMES}/step", f"{FRAMES}/time",
                 "particles/bodies/name"):
        if dataset(path) is None:
            return f"missing dataset /{path}"
    if not isinstance(file.get("parameters"), h5py.Group) or dataset("parameters/scene").dtype.kind != "O":
        return "/parameters/scene is not the stored scene text"
    if not isinstance(file.get("parameters/summary"), h5py.Group):
        return "the run did not finish (no /parameters/summary)"
    value, step, time = (dataset(f"{FRAMES}/{name}") for name in ("value", "step", "time"))
    names = dataset("particles/bodies/name")
    if names.ndim != 1 or names.dtype.kind not in "OSU":
        return "/particles/bodies/name is not a list of names"
    bodies = names.shape[0]
    if value.ndim != 3 or value.shape[1:] != (bodies, 2) or not numeric(value):
        return (f"/{FRAMES}/value has shape {value.shape} ({value.dtype}), "
                f"expected [frames, {bodies}, 2] numbers")
    frames = value.shape[0]
    for name, series in (("step", step), ("time", time)):
        if series.shape != (frames,) or not numeric(series):
            return (f"/{FRAMES}/{name} has shape {series.shape} ({series.dtype}), expected [{frames}] "
                    "numbers, one per frame")
    if frames and not np.all(np.isfinite(time[()])):
        return f"/{FRAMES}/time holds a non-finite time"
    for name, (row, _dtype, _unit) in FRAME_SERIES.items():
        series = dataset(f"particles/bodies/{name}/value")
        if name != "position" and series is not None and (
                series.shape != (frames, bodies, *row) or not numeric(series)):
            return (f"/particles/bodies/{name}/value has shape {series.shape} ({series.dtype}), expected "
                    f"{[frames, bodies, *row]} numbers")
    for name, (row, _dtype, _unit) in OBSERVABLES.items():
        series = dataset(f"observables/{name}/value")
        if series is not None and (series.shape != (frames, *row) or not numeric(series)):
            return (f"/observables/{name}/value has shape {series.shape} ({series.dtype}), expected "
                    f"{[frames, *row]} numbers")
    for name in ("type", "shape", "material", "mass", "inertia"):
        series = dataset(f"particles/bodies/{name}")
        if series is not None and series.shape != (bodies,):
            return f"/particles/bodies/{name} has shape {series.shape}, expected [{bodies}] (one per body)"
    return None
