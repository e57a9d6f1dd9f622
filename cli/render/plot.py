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
LEGEND_CHARACTERS = 140  # characters of legend text that fit across the figure, in the legend's font


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


def read_overrides(path: Path) -> list[str]:
    """The `--set KEY=VALUE` texts a run was made with (a sweep's variants: the fixed and swept ones)."""
    from ..trajectory import open_trajectory, read_strings

    with open_trajectory(path) as file:
        return read_strings(file["parameters/overrides"]) if "parameters/overrides" in file else []


def labels_for(paths: list[Path], overrides: list[list[str]]) -> tuple[list[str], str]:
    """Short legend labels and the legend's title. Runs that differ by overrides (a sweep) are labelled by
    the values that differ, each under the last part of its key (`restitution=0.9`), the keys in full in
    the title; other runs by file stem, or by path when two stems are the same."""
    settings = [dict(text.split("=", 1) for text in texts if "=" in text) for texts in overrides]
    keys = list(dict.fromkeys(key for run in settings for key in run))
    varying = [key for key in keys if len({run.get(key) for run in settings}) > 1]
    if len(paths) > 1 and varying:
        short = {key: key.rsplit(".", 1)[-1] for key in varying}
        if len(set(short.values())) < len(short):
            short = {key: key for key in varying}
        labels = [", ".join(f"{short[key]}={run.get(key, '(scene)')}" for key in varying) for run in settings]
        return labels, "runs: " + ", ".join(varying)
    stems = [path.stem for path in paths]
    if len(set(stems)) == len(stems):
        return stems, "runs"
    return [str(path) for path in paths], "runs"


def plot_runs(paths: list[Path], out: Path, title: str | None = None) -> int:
    """Plot the observables of every run in `paths` on one figure written to `out`; returns the run count."""
    suffix = check_suffix(out, PLOT_FORMATS, "plot")
    labels, legend_title = labels_for(paths, [read_overrides(path) for path in paths])
    series = [read_series(path, label) for path, label in zip(paths, labels, strict=True)]
    figure = _figure(series, title or f"rustycs: observables of {len(series)} run{'s' * (len(series) > 1)}",
                     legend_title)
    with atomic_output(out) as temporary:
        figure.savefig(temporary, format=suffix[1:], dpi=100)
    return len(series)


def _figure(series: list[Series], title: str, legend_title: str = "runs"):  # -> matplotlib.figure.Figure
    """Six panels: energies, energy drift, linear and angular momentum, contact count, max penetration.
    One colour per run; line styles tell the quantities of a panel apart. The runs' legend goes below
    the panels in as many columns as its longest label lets fit across the figure."""
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
    longest = max(len(run.label) for run in series) + 10  # the line sample and the gaps
    figure.legend(
        [Line2D([], [], color=color, linewidth=2) for color in colors],
        [run.label for run in series],
        loc="outside lower center",
        ncols=max(1, min(len(series), 5, LEGEND_CHARACTERS // longest)),
        title=legend_title,
        fontsize="small",
    )
    figure.suptitle(title)
    return figure
