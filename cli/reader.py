"""Reading a trajectory from Python (`rustycs.open_trajectory`): numpy arrays with str names, a long-form
pandas table, an xarray Dataset, and the HTML player inline in Jupyter.

Nothing is read until asked: each property reads its datasets when used (the file stays open until
`close()` or the end of a `with` block), `frames(start, stop)` reads a slice of frames and `blocks()`
walks the whole run a block of chunks at a time, so a run larger than memory can still be summed up.
pandas and xarray are optional (`pip install -e ".[frames]"`).
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .errors import UserError
from .trajectory import (
    CHUNK_FRAMES,
    FRAME_SERIES,
    JOINT_SERIES,
    OBSERVABLES,
    read_attrs,
    read_series,
    read_strings,
)

if TYPE_CHECKING:
    import pandas
    import xarray

BODIES = "particles/bodies"
MEASURE_PREFIX = "measure."
# the long table's columns of per-body series: (column, dataset, component or None)
TABLE_COLUMNS = (("x", "position", 0), ("y", "position", 1), ("angle", "angle", None),
                 ("vx", "velocity", 0), ("vy", "velocity", 1), ("w", "angular_velocity", None))
PLAYER_HEIGHT = 560  # px of the inline player's frame in a notebook


def _optional(module: str):
    """Import pandas or xarray, or say which extra installs it."""
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError:
        raise ImportError(
            f"{module} is not installed: pip install -e \".[frames]\" (or pip install {module})"
        ) from None


class Trajectory:
    """One run written by `rustycs run`: body names and per-frame state as numpy arrays."""

    def __init__(self, path: str | Path):
        from .trajectory import open_trajectory

        self.path = Path(path)
        if not self.path.exists():
            raise FileNotFoundError(f"{self.path}: no such file")
        try:
            self._file = open_trajectory(self.path)
        except UserError as err:
            raise ValueError(str(err)) from None

    # ------------------------------------------------------------------ file
    def close(self) -> None:
        self._file.close()

    def __enter__(self) -> Trajectory:
        return self

    def __exit__(self, *_: object) -> None:
        self.close()

    def __repr__(self) -> str:
        return (f"<rustycs trajectory {self.path}: {len(self.names)} bodies, {len(self.steps)} frames, "
                f"{self.parameters.get('status')}>")

    # ------------------------------------------------------------------ bodies
    @property
    def names(self) -> np.ndarray:
        """(N,) str: body names, in body order."""
        return np.array(read_strings(self._file[f"{BODIES}/name"]), dtype=str)

    @property
    def body_types(self) -> np.ndarray:
        """(N,) str: static | dynamic | kinematic."""
        return np.array(read_strings(self._file[f"{BODIES}/type"]), dtype=str)

    def body_index(self, name: str) -> int:
        """The row of the body called `name` (KeyError when there is none)."""
        names = self.names.tolist()
        if name not in names:
            raise KeyError(f"no body named {name!r} in {self.path}")
        return names.index(name)

    # ------------------------------------------------------------------ frames
    @property
    def steps(self) -> np.ndarray:
        """(T,) int64: the tick of each recorded frame."""
        return self._file[f"{BODIES}/position/step"][()]

    @property
    def times(self) -> np.ndarray:
        """(T,) float64: seconds of each recorded frame."""
        return self._file[f"{BODIES}/position/time"][()]

    def _series(self, name: str, frames: slice = slice(None)) -> np.ndarray:
        return np.ascontiguousarray(read_series(self._file, name)[frames])  # a writable array, always

    @property
    def positions(self) -> np.ndarray:
        """(T, N, 2) body origins, m."""
        return self._series("position")

    @property
    def velocities(self) -> np.ndarray:
        """(T, N, 2) centre-of-mass velocities, m/s."""
        return self._series("velocity")

    @property
    def angles(self) -> np.ndarray:
        """(T, N) unwrapped angles, rad."""
        return self._series("angle")

    @property
    def angular_velocities(self) -> np.ndarray:
        """(T, N) rad/s."""
        return self._series("angular_velocity")

    @property
    def active(self) -> np.ndarray:
        """(T, N) bool: false once a body left the world (escaped or removed) or before it appeared."""
        return self._series("active")

    @property
    def asleep(self) -> np.ndarray:
        """(T, N) bool: the body sleeps in that frame (world.sleep; all false in files from before it)."""
        return self._series("asleep")

    def frames(self, start: int = 0, stop: int | None = None) -> dict[str, np.ndarray]:
        """Frames start..stop of every per-body series (position, velocity, angle, angular_velocity,
        active, asleep) and their step and time."""
        rows = slice(start, stop)
        block = {name: self._series(name, rows) for name in FRAME_SERIES}
        return {"step": self.steps[rows], "time": self.times[rows], **block}

    def blocks(self, frames: int = 4 * CHUNK_FRAMES) -> Iterator[dict[str, np.ndarray]]:
        """The run `frames` frames at a time (see `frames`), each block read once from disk."""
        for start in range(0, len(self.steps), frames):
            yield self.frames(start, start + frames)

    # ------------------------------------------------------------------ the rest of the file
    @property
    def observables(self) -> dict[str, np.ndarray]:
        """Per frame: kinetic_energy, potential_energy, linear_momentum (T, 2), angular_momentum,
        contact_count, max_penetration (and any other observable the file holds)."""
        group = self._file.get("observables", {})
        return {name: group[name]["value"][()] for name in group}

    @property
    def events(self) -> dict[str, np.ndarray]:
        """The run's events in order: tick, time, kind (str), body_a, body_b, point (E, 2), speed."""
        group = self._file["events"]
        return {name: (np.array(read_strings(group[name]), dtype=str) if name == "kind" else group[name][()])
                for name in group}

    @property
    def joints(self) -> dict[str, np.ndarray]:
        """The joints: name and type (str), body_a, body_b, and per frame reaction_force (T, J, 2),
        reaction_torque (T, J), active (T, J)."""
        group = self._file["joints"]
        table = {name: np.array(read_strings(group[name]), dtype=str) for name in ("name", "type")
                 if name in group}
        table |= {name: group[name][()] for name in ("body_a", "body_b") if name in group}
        table |= {name: group[name]["value"][()] for name in JOINT_SERIES if name in group}
        return table

    @property
    def summary(self) -> dict[str, Any]:
        """The run's summary statistics (as `rustycs run` printed them)."""
        return read_attrs(self._file["parameters/summary"])

    @property
    def measures(self) -> dict[str, Any]:
        """The scene's measures by name: a number, None, or a histogram's counts."""
        return {key[len(MEASURE_PREFIX):]: value for key, value in self.summary.items()
                if key.startswith(MEASURE_PREFIX)}

    @property
    def parameters(self) -> dict[str, Any]:
        """Run parameters: status, dt, tick_rate, precision, seed, ticks_completed, every, ..."""
        return read_attrs(self._file["parameters"])

    @property
    def overrides(self) -> list[str]:
        """The `-s KEY=VALUE` texts the run was made with (a sweep's variant: its fixed and swept values)."""
        return read_strings(self._file["parameters/overrides"])

    @property
    def scene(self) -> str:
        """The resolved scene as YAML (`rustycs run` takes it back and repeats the run)."""
        return self._file["parameters/scene"].asstr()[()]

    def contacts(self, frame: int) -> dict[str, np.ndarray]:
        """The contact points of one recorded frame (when the scene recorded contacts)."""
        if "contacts" not in self._file:
            raise KeyError(f"{self.path} holds no contacts: run the scene with output.contacts: true")
        group = self._file["contacts"]
        start, stop = group["offset"][frame : frame + 2]
        return {name: group[name][start:stop] for name in group if name != "offset"}

    # ------------------------------------------------------------------ tables
    def to_dataframe(self) -> pandas.DataFrame:
        """A long-form table, one row per frame and body: time, body (its name), x, y, angle, vx, vy, w."""
        pandas = _optional("pandas")
        names = self.names
        times = self.times
        data = {"time": np.repeat(times, len(names)),
                "body": pandas.Categorical.from_codes(np.tile(np.arange(len(names)), len(times)), names)}
        series = {name: self._series(name) for name in ("position", "velocity", "angle", "angular_velocity")}
        for column, name, component in TABLE_COLUMNS:
            values = series[name] if component is None else series[name][..., component]
            data[column] = values.reshape(-1)
        return pandas.DataFrame(data)

    def to_xarray(self) -> xarray.Dataset:
        """A Dataset over dims (time, body), coordinates time (s), tick and body (names): x, y, angle, vx,
        vy, w, active, asleep per body and frame, and the observables per frame."""
        xarray = _optional("xarray")
        series = {name: self._series(name) for name in FRAME_SERIES}
        variables = {}
        for column, name, component in TABLE_COLUMNS:
            values = series[name] if component is None else series[name][..., component]
            variables[column] = (("time", "body"), values)
        for flag in ("active", "asleep"):
            variables[flag] = (("time", "body"), series[flag])
        for name, values in self.observables.items():
            if values.ndim == 2:
                variables[f"{name}_x"] = ("time", values[:, 0])
                variables[f"{name}_y"] = ("time", values[:, 1])
            else:
                variables[name] = ("time", values)
        coords = {"time": self.times, "tick": ("time", self.steps), "body": self.names}
        units = {name: unit for name, (_, _, unit) in {**FRAME_SERIES, **OBSERVABLES}.items() if unit}
        dataset = xarray.Dataset(variables, coords=coords, attrs={"source": str(self.path)})
        for column, name, _ in TABLE_COLUMNS:
            dataset[column].attrs["units"] = units[name]
        dataset["time"].attrs["units"] = "s"
        return dataset

    # ------------------------------------------------------------------ notebooks
    def player_html(self) -> str:
        """The self-contained HTML player of this run (what `rustycs render RUN -o OUT.html` writes)."""
        import tempfile

        from .render.pictures import RenderRequest, render

        with tempfile.TemporaryDirectory() as folder:
            out = Path(folder) / f"{self.path.stem}.html"
            render(RenderRequest(run=self.path, out=out))
            return out.read_text(encoding="utf-8")

    def _repr_html_(self) -> str:
        """Jupyter shows the player inline, in a frame of its own (its script and styles stay apart)."""
        import html

        return (f'<iframe srcdoc="{html.escape(self.player_html(), quote=True)}" '
                f'style="width: 100%; height: {PLAYER_HEIGHT}px; border: 0"></iframe>')
