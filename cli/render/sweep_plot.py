"""`rustycs plot sweep.csv --x KEY --y measure.NAME`: a measure against a swept value, one line per value
of a second key (`--by`), the mean with error bars (one standard deviation) where variants repeat."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from ..errors import UserError
from .output import atomic_output, check_suffix
from .plot import PLOT_FORMATS


def _number(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        return math.nan


def read_columns(path: Path, names: list[str]) -> dict[str, list[str]]:
    """The named columns of a sweep table (rows that ran); UserError for a missing column."""
    try:
        with open(path, newline="", encoding="utf-8") as file:
            rows = list(csv.DictReader(file))
    except OSError as err:
        raise UserError(f"{path}: cannot read ({err.strerror})") from None
    header = list(rows[0]) if rows else []
    missing = [name for name in names if name not in header]
    if missing:
        from ..scene import did_you_mean

        raise UserError([f"{path}: no column '{name}'{did_you_mean(name, header)}" for name in missing])
    done = [row for row in rows if row.get("status") in ("complete", "stopped")]
    return {name: [row[name] for row in done] for name in names}


def plot_sweep(path: Path, x: str, y: str, out: Path, by: str | None = None, title: str | None = None) -> int:
    """Plot column `y` against column `x` of a sweep table, a line per value of `by`; returns the points."""
    suffix = check_suffix(out, PLOT_FORMATS, "plot")
    columns = read_columns(path, [x, y, *([by] if by else [])])
    groups: dict[str, dict[float, list[float]]] = {}
    for k, (xs, ys) in enumerate(zip(columns[x], columns[y], strict=True)):
        line = columns[by][k] if by else ""
        groups.setdefault(line, {}).setdefault(_number(xs), []).append(_number(ys))
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure(figsize=(7, 4.5), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.add_subplot()
    points = 0
    for line, values in groups.items():
        at = sorted(v for v in values if math.isfinite(v))
        mean = np.array([np.nanmean(values[v]) if np.isfinite(values[v]).any() else np.nan for v in at])
        spread = np.array([np.nanstd(values[v]) if len(values[v]) > 1 else 0.0 for v in at])
        label = f"{by}={line}" if by else None
        if spread.any():
            axes.errorbar(at, mean, yerr=spread, marker="o", capsize=3, label=label)
        else:
            axes.plot(at, mean, marker="o", label=label)
        points += len(at)
    axes.set_xlabel(x)
    axes.set_ylabel(y)
    axes.grid(alpha=0.3)
    if by:
        axes.legend()
    axes.set_title(title or f"{y} against {x} ({path.name})")
    with atomic_output(out) as temporary:
        figure.savefig(temporary, format=suffix[1:], dpi=100)
    return points
