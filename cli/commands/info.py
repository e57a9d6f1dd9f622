"""`rustycs info`: what a trajectory holds."""

from __future__ import annotations

from pathlib import Path

import typer

NAME = "info"


def command(
    run: Path = typer.Argument(..., help="Trajectory file written by `rustycs run`."),
    json: bool = typer.Option(False, "--json", help="Print everything as JSON on stdout."),
) -> None:
    """Show a trajectory's scene, status, ticks, bodies (by type and shape), shapes (by type) and summary.

    Example: rustycs info outputs/material-bounce.h5 --json
    """
    from ..summary import summary_table, to_json
    from ..trajectory import describe

    details = describe(run)
    if json:
        print(to_json(details))
        return
    from rich.console import Console
    from rich.table import Table

    table = Table(title=str(run), show_header=False, title_justify="left")
    table.add_column("key", style="bold")
    table.add_column("value")
    for key, value in details.items():
        if key == "bodies":
            value = (f"{value['total']}: " + ", ".join(f"{n} {k}" for k, n in value["by_type"].items())
                     + "; " + ", ".join(f"{n} {k}" for k, n in value["by_shape"].items()))
        elif key == "shapes":
            value = _shapes_line(value)
        elif key == "overrides":
            value = " ".join(value) or "none"
        if key not in ("file", "summary"):
            table.add_row(key, str(value))
    console = Console()
    console.print(table)
    console.print(summary_table(details["summary"], "summary"))


def _shapes_line(shapes: dict | None) -> str:
    """`S: n type, ...; k sensors`, or a note for files written before /shapes existed."""
    if shapes is None:
        return "not recorded (an older file)"
    if not shapes["total"]:
        return "0"
    sensors = shapes["sensors"]
    return (f"{shapes['total']}: " + ", ".join(f"{n} {k}" for k, n in shapes["by_type"].items())
            + f"; {sensors} sensor{'' if sensors == 1 else 's'}")
