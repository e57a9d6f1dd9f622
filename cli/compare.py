"""Regression comparison of two trajectories (`rustycs compare`).

Two runs of the same scene should give bitwise identical files (the determinism guarantee), so the
bytes are checked first; when they differ, each quantity gets error statistics so that a user can
tell a rounding-level change from a real regression. Runs recorded at different `--every` are compared
on the ticks both recorded. Files can be far larger than memory, so both are read in blocks of frames
and the statistics are accumulated block by block.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .errors import UserError

if TYPE_CHECKING:
    import h5py

    Series = h5py.Dataset | np.ndarray  # a dataset, or the all-false flags a file from before them lacks

BODIES = "particles/bodies"
# the per-body series compared (trajectory.FRAME_SERIES) -> whether it is an angle whose difference is
# wrapped to +-pi
STATE: dict[str, bool] = {
    "position": False,
    "angle": True,
    "velocity": False,
    "angular_velocity": False,
    "active": False,
    "asleep": False,
}
WORST_BODIES = 5
BLOCK_VALUES = 1 << 21  # values per dataset per block: 16 MB of float64


class NotComparable(UserError):
    """The two files do not describe the same bodies, time step or frames (exit code 2)."""


@dataclass
class QuantityErrors:
    """Error statistics of one quantity, accumulated over blocks of frames."""

    name: str
    per_body: bool
    values: int = 0
    max_error: float = 0.0
    error_sum: float = 0.0
    outside: int = 0
    first_tick: int | None = None
    body_max: np.ndarray | None = None
    body_outside: np.ndarray | None = None

    def add_equal(self, values: int) -> None:
        """Account for a block whose bytes are identical in both files (zero error)."""
        self.values += values

    def add(self, error: np.ndarray, outside: np.ndarray, steps: np.ndarray) -> None:
        """Account for one block: `error` and `outside` have the frames on axis 0, bodies on axis 1."""
        self.values += error.size
        if error.size == 0:
            return
        self.max_error = max(self.max_error, float(error.max()))
        self.error_sum += float(error.sum())
        self.outside += int(outside.sum())
        frames_outside = outside.reshape(len(outside), -1).any(axis=1)
        if self.first_tick is None and frames_outside.any():
            self.first_tick = int(steps[np.argmax(frames_outside)])
        if self.per_body:
            extra_axes = tuple(range(2, error.ndim))
            body_max = error.max(axis=(0, *extra_axes))
            body_outside = outside.sum(axis=(0, *extra_axes))
            if self.body_max is None or self.body_outside is None:
                self.body_max, self.body_outside = body_max, body_outside
            else:
                np.maximum(self.body_max, body_max, out=self.body_max)
                self.body_outside += body_outside

    @property
    def mean_error(self) -> float:
        return self.error_sum / self.values if self.values else 0.0

    def worst_bodies(self, names: list[str]) -> list[dict[str, Any]]:
        """The bodies with the largest error (largest first), those with a non-zero error only."""
        if self.body_max is None or self.body_outside is None:
            return []
        order = np.argsort(-self.body_max, kind="stable")[:WORST_BODIES]
        return [
            {"name": names[i], "max_error": float(self.body_max[i]), "outside": int(self.body_outside[i])}
            for i in order
            if self.body_max[i] > 0
        ]


@dataclass
class Comparison:
    """The result of comparing trajectory `a` against the reference `b`."""

    a: Path
    b: Path
    atol: float
    rtol: float
    frames: int
    body_names: list[str]
    identical: bool
    quantities: list[QuantityErrors]
    only_in_a: list[str] = field(default_factory=list)
    only_in_b: list[str] = field(default_factory=list)
    frames_a: int = 0  # frames each file holds; `frames` of them are at ticks both recorded
    frames_b: int = 0

    @property
    def within_tolerance(self) -> bool:
        return all(q.outside == 0 for q in self.quantities)

    @property
    def verdict(self) -> str:
        if self.identical:
            return "identical"
        return "within tolerance" if self.within_tolerance else "different"

    @property
    def exit_code(self) -> int:
        return 0 if self.within_tolerance else 1

    def to_json(self) -> dict[str, Any]:
        """A JSON-ready dict (an infinite error, where one file is not finite, becomes null in JSON)."""
        return {
            "a": str(self.a),
            "b": str(self.b),
            "comparable": True,
            "result": self.verdict,
            "identical": self.identical,
            "within_tolerance": self.within_tolerance,
            "atol": self.atol,
            "rtol": self.rtol,
            "frames": self.frames,
            "frames_a": self.frames_a,
            "frames_b": self.frames_b,
            "bodies": len(self.body_names),
            "quantities": {
                q.name: {
                    "max_error": q.max_error,
                    "mean_error": q.mean_error,
                    "values": q.values,
                    "outside_tolerance": q.outside,
                    "first_tick": q.first_tick,
                    "worst_bodies": q.worst_bodies(self.body_names),
                }
                for q in self.quantities
            },
            "only_in_a": self.only_in_a,
            "only_in_b": self.only_in_b,
        }


def compare_trajectories(
    a: Path, b: Path, atol: float = 0.0, rtol: float = 0.0, block_frames: int | None = None
) -> Comparison:
    """Compare trajectory `a` against the reference `b`; |a-b| > atol + rtol*|b| is outside tolerance.

    Raises NotComparable when the files hold different bodies, time steps or frames, and UserError
    when either file is missing or is not a trajectory.
    """
    from .trajectory import open_trajectory

    if atol < 0 or rtol < 0:
        raise UserError("--atol and --rtol must not be negative")
    with open_trajectory(a) as fa, open_trajectory(b) as fb:
        names, shared = _check_comparable(fa, fb)
        steps = shared.steps
        datasets = dict(_datasets(fa, fb))
        only_in_a = sorted(set(fa.get("observables", {})) - set(fb.get("observables", {})))
        only_in_b = sorted(set(fb.get("observables", {})) - set(fa.get("observables", {})))
        quantities = {name: QuantityErrors(name, per_body=name in STATE) for name in datasets}
        identical = True
        frames = len(steps)
        block = block_frames or _block_frames(datasets, frames)
        for start in range(0, frames, block):
            stop = min(start + block, frames)
            for name, (da, db, wrap) in datasets.items():
                xa, xb = shared.rows(da, shared.a, start, stop), shared.rows(db, shared.b, start, stop)
                if xa.dtype == xb.dtype and np.array_equal(_raw(xa), _raw(xb)):
                    quantities[name].add_equal(xa.size)
                    continue
                identical = False
                error, outside = _errors(xa, xb, atol, rtol, wrap)
                quantities[name].add(error, outside, steps[start:stop])
    return Comparison(
        a, b, atol, rtol, frames, names, identical, list(quantities.values()), only_in_a, only_in_b,
        len(shared.a_steps), len(shared.b_steps)
    )


@dataclass(frozen=True)
class SharedFrames:
    """The frames of the ticks both files recorded: their rows in each file."""

    a_steps: np.ndarray
    b_steps: np.ndarray
    steps: np.ndarray  # the shared ticks, increasing
    a: np.ndarray  # rows in A of the shared ticks
    b: np.ndarray

    @staticmethod
    def rows(dataset: Series, rows: np.ndarray, start: int, stop: int) -> np.ndarray:
        """The shared frames start..stop of one file: the span read whole, then the rows taken."""
        part = rows[start:stop]
        if len(part) == 0:
            return dataset[0:0]
        span = dataset[int(part[0]) : int(part[-1]) + 1]
        return span if len(span) == len(part) else span[part - part[0]]


def _check_comparable(fa: h5py.File, fb: h5py.File) -> tuple[list[str], SharedFrames]:
    """Return the body names and the frames of the ticks both files recorded, or raise NotComparable."""
    from .trajectory import read_strings

    names_a, names_b = read_strings(fa[f"{BODIES}/name"]), read_strings(fb[f"{BODIES}/name"])
    if names_a != names_b:
        if len(names_a) != len(names_b):
            detail = f"A has {len(names_a)} bodies, B has {len(names_b)}"
        else:
            i = next(i for i, (x, y) in enumerate(zip(names_a, names_b, strict=True)) if x != y)
            detail = f"body {i} is {names_a[i]!r} in A and {names_b[i]!r} in B"
        raise NotComparable(f"not comparable: different bodies ({detail})")
    dt_a, dt_b = fa["parameters"].attrs.get("dt"), fb["parameters"].attrs.get("dt")
    if dt_a != dt_b:
        raise NotComparable(f"not comparable: different time steps (dt {dt_a} in A, {dt_b} in B)")
    steps_a = fa[f"{BODIES}/position/step"][()]
    steps_b = fb[f"{BODIES}/position/step"][()]
    if len(steps_a) and len(steps_b) and steps_a[-1] != steps_b[-1]:
        raise NotComparable(
            f"not comparable: runs of different lengths (A ends at tick {int(steps_a[-1])}, "
            f"B at tick {int(steps_b[-1])})"
        )
    steps, rows_a, rows_b = np.intersect1d(steps_a, steps_b, assume_unique=True, return_indices=True)
    if len(steps) == 0:
        raise NotComparable(
            "not comparable: no tick recorded in both "
            f"(A has {len(steps_a)} frames, ticks {_span(steps_a)}; "
            f"B has {len(steps_b)} frames, ticks {_span(steps_b)})"
        )
    return names_a, SharedFrames(steps_a, steps_b, steps, rows_a, rows_b)


def _span(steps: np.ndarray) -> str:
    if len(steps) < 2:
        return ", ".join(str(int(s)) for s in steps) or "none"
    return f"{int(steps[0])}..{int(steps[-1])} every {int(steps[1] - steps[0])}"


def _datasets(fa: h5py.File, fb: h5py.File) -> Iterator[tuple[str, tuple[Series, Series, bool]]]:
    """The datasets compared: body state first (a file from before the asleep flags slept nowhere), then
    every observable present in both files."""
    from .trajectory import read_series

    for name, wrap in STATE.items():
        yield name, (read_series(fa, name), read_series(fb, name), wrap)
    shared = sorted(set(fa.get("observables", {})) & set(fb.get("observables", {})))
    for name in shared:
        da, db = fa[f"observables/{name}/value"], fb[f"observables/{name}/value"]
        if da.shape[1:] != db.shape[1:]:
            raise NotComparable(
                f"not comparable: observable {name} has shape {da.shape} in A and {db.shape} in B"
            )
        yield name, (da, db, False)


def _block_frames(datasets: dict[str, tuple[Series, Series, bool]], frames: int) -> int:
    """Frames per block: bounded memory, and a whole number of chunks when the file is chunked."""
    values_per_frame = max(int(np.prod(da.shape[1:])) for da, _, _ in datasets.values())
    block = max(1, BLOCK_VALUES // max(1, values_per_frame))
    chunk = datasets["position"][0].chunks
    if chunk and chunk[0] < block:
        block -= block % chunk[0]
    return min(block, max(frames, 1))


def _raw(x: np.ndarray) -> np.ndarray:
    """The array's bytes, so that NaNs and signed zeros compare by their bit patterns."""
    return np.ascontiguousarray(x).view(np.uint8)


def _errors(
    xa: np.ndarray, xb: np.ndarray, atol: float, rtol: float, wrap: bool
) -> tuple[np.ndarray, np.ndarray]:
    """Absolute errors and the mask of values outside tolerance, for one block."""
    if xa.dtype == bool or xb.dtype == bool:
        # a body active in one run and not in the other is a difference whatever the tolerance
        differ = xa != xb
        return differ.astype(np.float64), differ
    with np.errstate(invalid="ignore", over="ignore"):
        diff = xa.astype(np.float64) - xb
        if wrap:
            diff = np.remainder(diff + np.pi, 2 * np.pi) - np.pi
        error = np.abs(diff)
        same = (xa == xb) | (np.isnan(xa) & np.isnan(xb))
        error[same] = 0.0
        error[np.isnan(error)] = np.inf  # one run finite, the other not
        outside = ~(error <= atol + rtol * np.abs(xb))
    outside &= ~same
    return error, outside


def print_comparison(comparison: Comparison) -> None:
    """The human report on stdout: one line of verdict, then a table of errors when the files differ."""
    from rich.console import Console
    from rich.table import Table

    console = Console(highlight=False)
    tolerance = f"atol={comparison.atol:g}, rtol={comparison.rtol:g}"
    console.print(
        f"{comparison.a} vs {comparison.b}: {comparison.frames} frames, "
        f"{len(comparison.body_names)} bodies, tolerance {tolerance}"
    )
    if comparison.frames < max(comparison.frames_a, comparison.frames_b):
        console.print(
            f"compared the {comparison.frames} frames at ticks both recorded "
            f"(A has {comparison.frames_a}, B {comparison.frames_b})"
        )
    for side, names in (("A", comparison.only_in_a), ("B", comparison.only_in_b)):
        if names:
            console.print(f"only in {side} (not compared): {', '.join(names)}")
    if comparison.identical:
        console.print("[bold green]identical[/] (bitwise)")
        return
    table = Table()
    table.add_column("quantity", no_wrap=True)
    for column in ("max error", "mean error", "outside", "first tick"):
        table.add_column(column, justify="right", no_wrap=True)
    table.add_column("worst bodies")
    for q in comparison.quantities:
        worst_bodies = q.worst_bodies(comparison.body_names)
        worst = ", ".join(f"{b['name']} ({b['max_error']:.3g})" for b in worst_bodies)
        style = "red" if q.outside else None
        first = "" if q.first_tick is None else str(q.first_tick)
        table.add_row(
            q.name, f"{q.max_error:.3g}", f"{q.mean_error:.3g}", str(q.outside), first, worst, style=style
        )
    console.print(table)
    if comparison.within_tolerance:
        console.print("[bold green]within tolerance[/]")
    else:
        beyond = [q for q in comparison.quantities if q.outside]
        first = min(q.first_tick for q in beyond if q.first_tick is not None)
        console.print(
            f"[bold red]different[/]: {', '.join(q.name for q in beyond)} beyond tolerance, "
            f"first at tick {first}"
        )
