"""`rustycs plot`: the observables of one or more runs over time, overlaid to compare a sweep."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import UserError
from .output import atomic_output, check_suffix

OBSERVABLES = (
    "kinetic_energy",
    "potential_energy",
    "linear_momentum",
    "angular_momentum",
    "contact_count",
    "max_penetration",
)
PLOT_FORMATS = (".png", ".pdf", ".svg")


@dataclass(frozen=True)
class Series:
    """The observables of one run, each over its own time axis."""

    label: str
    time: dict[str, np.ndarray]
    value: dict[str, np.ndarray]


def read_series(path: Path, label: str) -> Series:
    """Read the observables of a trajectory; UserError when the file is not one or lacks them."""
    from ..trajectory import open_trajectory

    with open_trajectory(path) as file:
        time, value = {}, {}
        for name in OBSERVABLES:
            group = f"observables/{name}"
            if f"{group}/value" not in file or f"{group}/time" not in file:
                raise UserError(f"{path}: not a complete rustycs trajectory (missing /{group})")
            time[name] = np.asarray(file[f"{group}/time"], dtype=np.float64)
            value[name] = np.asarray(file[f"{group}/value"], dtype=np.float64)
        status = file["parameters"].attrs.get("status") if "parameters" in file else None
    if isinstance(status, bytes):
        status = status.decode("utf-8", "replace")
    if status and status != "complete":
        label = f"{label} ({status})"
    return Series(label, time, value)


def labels_for(paths: list[Path]) -> list[str]:
    """Short legend labels: file stems, or the paths themselves when two stems are the same."""
    stems = [path.stem for path in paths]
    if len(set(stems)) == len(stems):
        return stems
    return [str(path) for path in paths]


def plot_runs(paths: list[Path], out: Path, title: str | None = None) -> int:
    """Plot the observables of every run in `paths` on one figure written to `out`; returns the run count."""
    suffix = check_suffix(out, PLOT_FORMATS, "plot")
    series = [read_series(path, label) for path, label in zip(paths, labels_for(paths), strict=True)]
    figure = _figure(series, title or f"rustycs: observables of {len(series)} run{'s' * (len(series) > 1)}")
    with atomic_output(out) as temporary:
        figure.savefig(temporary, format=suffix[1:], dpi=100)
    return len(series)


def _figure(series: list[Series], title: str):  # -> matplotlib.figure.Figure
    """Six panels: energies, energy drift, linear and angular momentum, contact count, max penetration.
    One colour per run; line styles tell the quantities of a panel apart."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D
    from matplotlib.ticker import MaxNLocator

    figure = Figure(figsize=(13, 8.5), layout="constrained")
    FigureCanvasAgg(figure)  # Agg: no display needed, and pyplot's global state stays untouched
    axes = figure.subplots(2, 3, sharex=True).ravel()
    colors = [f"C{i % 10}" for i in range(len(series))]
    for run, color in zip(series, colors, strict=True):
        t, v = run.time, run.value
        kinetic, potential = v["kinetic_energy"], v["potential_energy"]
        total = kinetic + potential
        axes[0].plot(t["kinetic_energy"], kinetic, color=color, linestyle="-")
        axes[0].plot(t["potential_energy"], potential, color=color, linestyle="--")
        axes[0].plot(t["kinetic_energy"], total, color=color, linestyle=":")
        axes[1].plot(t["kinetic_energy"], total - total[0], color=color)
        momentum = v["linear_momentum"].reshape(len(t["linear_momentum"]), -1)
        axes[2].plot(t["linear_momentum"], momentum[:, 0], color=color, linestyle="-")
        axes[2].plot(t["linear_momentum"], momentum[:, 1], color=color, linestyle="--")
        axes[3].plot(t["angular_momentum"], v["angular_momentum"], color=color)
        axes[4].step(t["contact_count"], v["contact_count"], color=color, where="post")
        axes[5].plot(t["max_penetration"], v["max_penetration"], color=color)
    titles = (
        ("energy", "J"),
        ("total energy change E(t) - E(0)", "J"),
        ("linear momentum", "kg m/s"),
        ("angular momentum (about the origin)", "kg m²/s"),
        ("contact points", "count"),
        ("max penetration", "m"),
    )
    for ax, (name, unit) in zip(axes, titles, strict=True):
        ax.set_title(name)
        ax.set_ylabel(unit)
        ax.grid(True, alpha=0.3)
    for ax in axes[3:]:
        ax.set_xlabel("time (s)")
    axes[4].yaxis.set_major_locator(MaxNLocator(integer=True))
    grey = "0.35"
    axes[0].legend(
        [Line2D([], [], color=grey, linestyle=s) for s in ("-", "--", ":")],
        ["kinetic", "potential", "total"],
        loc="best",
        fontsize="small",
    )
    axes[2].legend(
        [Line2D([], [], color=grey, linestyle=s) for s in ("-", "--")],
        ["x", "y"],
        loc="best",
        fontsize="small",
    )
    figure.legend(
        [Line2D([], [], color=color, linewidth=2) for color in colors],
        [run.label for run in series],
        loc="outside lower center",
        ncols=min(len(series), 5),
        title="runs",
    )
    figure.suptitle(title)
    return figure
