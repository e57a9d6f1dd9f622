"""`rustycs plot`: observables of one or more runs over time, on one figure."""

from __future__ import annotations

from pathlib import Path

import typer

NAME = "plot"


def command(
    runs: list[Path] = typer.Argument(..., help="One or more trajectory files written by `rustycs run`."),
    out: Path = typer.Option(..., "-o", "--out", help="Output figure: .png (or .pdf, .svg)."),
    title: str = typer.Option(None, "--title", help="Figure title (default: the number of runs)."),
) -> None:
    """Plot observables over time: energies, energy drift, momentum, contact count, max penetration.

    Several runs are overlaid, one colour each, to compare a sweep.

    Example: rustycs plot outputs/sweep/*.h5 -o sweep.png
    """
    from ..render.plot import plot_runs

    count = plot_runs(runs, out, title)
    typer.echo(f"wrote {out}: {count} run{'s' * (count > 1)}")
