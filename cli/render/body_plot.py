"""`rustycs plot RUN.h5 --body NAME --y position.y`: one body's series over time, one line per run (only
the frames where the body exists)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import UserError
from .output import atomic_output, check_suffix
from .plot import PLOT_FORMATS, labels_for

# quantity -> (series, component or None for a scalar; speed is the norm of the velocity)
BODY_QUANTITIES = {"position.x": ("position", 0), "position.y": ("position", 1),
                   "velocity.x": ("velocity", 0), "velocity.y": ("velocity", 1), "speed": ("velocity", None),
                   "angle": ("angle", None), "angular_velocity": ("angular_velocity", None)}


def body_series(path: Path, body: str, quantity: str) -> tuple[np.ndarray, np.ndarray]:
    """(time, value) of one body's quantity in a trajectory, over the frames where it is active."""
    from ..scene import did_you_mean
    from ..trajectory import open_trajectory

    if quantity not in BODY_QUANTITIES:
        raise UserError(f"--y: unknown quantity '{quantity}'{did_you_mean(quantity, list(BODY_QUANTITIES))}; "
                        f"one of: {', '.join(BODY_QUANTITIES)}")
    name, component = BODY_QUANTITIES[quantity]
    with open_trajectory(path) as file:
        names = list(file["particles/bodies/name"].asstr()[()])
        if body not in names:
            raise UserError(f"{path}: no body '{body}'{did_you_mean(body, names)}")
        row = names.index(body)
        group = file[f"particles/bodies/{name}"]
        values = group["value"][:, row]
        time = group["time"][()]
        active = file["particles/bodies/active/value"][:, row]
    if component is not None:
        values = values[:, component]
    elif name == "velocity":
        values = np.hypot(values[:, 0], values[:, 1])
    return time[active], values[active]


def plot_body(paths: list[Path], body: str, quantity: str, out: Path, title: str | None = None) -> int:
    """Plot a body's quantity over time for every run; returns the number of runs."""
    suffix = check_suffix(out, PLOT_FORMATS, "plot")
    series = [body_series(path, body, quantity) for path in paths]
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure(figsize=(7, 4.5), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.add_subplot()
    for (time, values), label in zip(series, labels_for(paths), strict=True):
        axes.plot(time, values, label=label)
    axes.set_xlabel("time (s)")
    axes.set_ylabel(f"{body} {quantity}")
    axes.grid(alpha=0.3)
    if len(paths) > 1:
        axes.legend()
    axes.set_title(title or f"{body}: {quantity}")
    with atomic_output(out) as temporary:
        figure.savefig(temporary, format=suffix[1:], dpi=100)
    return len(paths)
