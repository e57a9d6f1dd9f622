"""`rustycs plot`: observables of one or more runs over time, on one figure."""

from __future__ import annotations

from pathlib import Path

import typer

NAME = "plot"


def command(
    runs: list[Path] = typer.Argument(..., help="One or more trajectory files written by `rustycs run`, "
                                      "or one sweep.csv."),
    out: Path = typer.Option(..., "-o", "--out", help="Output figure: .png (or .pdf, .svg)."),
    title: str = typer.Option(None, "--title", help="Figure title (default: the number of runs)."),
    x: str = typer.Option(None, "--x", help="sweep.csv: the column on the x axis (a swept key)."),
    y: str = typer.Option(None, "--y", help="sweep.csv: the column plotted (e.g. measure.range); with "
                          "--body: the body's quantity (position.x, position.y, velocity.x, velocity.y, "
                          "speed, angle, angular_velocity)."),
    by: str = typer.Option(None, "--by", help="sweep.csv: one line per value of this column."),
    body: str = typer.Option(None, "--body",
                             help="Plot this body's --y over time instead of the observables."),
) -> None:
    """Plot observables over time: energies, energy drift, momentum, contact count, max penetration.

    Several runs are overlaid, one colour each, to compare a sweep. Given a sweep's table, plot a
    measure against a swept value instead (error bars where variants repeat).

    Example: rustycs plot outputs/sweep/*.h5 -o sweep.png

    Example: rustycs plot outputs/projectile-sweep/sweep.csv --x world.tick_rate --y measure.range -o r.png

    Example: rustycs plot outputs/projectile.h5 --body ball --y position.y -o height.png
    """
    from ..errors import UserError
    from ..render.plot import plot_runs

    if runs[0].suffix == ".csv":
        from ..render.sweep_plot import plot_sweep

        if len(runs) != 1 or not x or not y:
            raise UserError("plot of a sweep table: give one sweep.csv with --x KEY and --y COLUMN")
        points = plot_sweep(runs[0], x, y, out, by, title)
        typer.echo(f"wrote {out}: {points} points")
        return
    if body is not None:
        from ..render.body_plot import plot_body

        count = plot_body(runs, body, y or "position.y", out, title)
        typer.echo(f"wrote {out}: {body} in {count} run{'s' * (count > 1)}")
        return

    count = plot_runs(runs, out, title)
    typer.echo(f"wrote {out}: {count} run{'s' * (count > 1)}")
