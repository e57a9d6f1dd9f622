"""`rustycs compare`: regression comparison of two trajectories."""

from __future__ import annotations

import json
from pathlib import Path

import typer

NAME = "compare"


def command(
    a: Path = typer.Argument(..., metavar="A.h5", help="The trajectory to check.", show_default=False),
    b: Path = typer.Argument(..., metavar="B.h5", help="The reference trajectory.", show_default=False),
    atol: float = typer.Option(0.0, "--atol", help="Absolute tolerance.", min=0.0),
    rtol: float = typer.Option(0.0, "--rtol", help="Relative tolerance, times |B|.", min=0.0),
    as_json: bool = typer.Option(False, "--json", help="Print the comparison as JSON on stdout."),
) -> None:
    """Compare two trajectories of the same scene, e.g. before and after a change.

    Identical bytes first: "identical", exit 0.

    Otherwise, per quantity (position, angle wrapped to +-pi, velocity,
    angular velocity, active, each observable): max and mean absolute error,
    the count of values with |A-B| > atol + rtol*|B|, the first tick beyond
    tolerance and the worst bodies.

    Without --atol/--rtol any difference counts. Exit 0 within tolerance,
    1 beyond, 2 when the files cannot be compared (different bodies, dt or
    frames).

    Example: rustycs compare outputs/new.h5 outputs/reference.h5 --atol 1e-9
    """
    from ..compare import NotComparable, compare_trajectories, print_comparison
    from ..summary import to_json

    try:
        comparison = compare_trajectories(a, b, atol=atol, rtol=rtol)
    except NotComparable as err:
        if as_json:
            print(json.dumps({"a": str(a), "b": str(b), "comparable": False, "reason": err.messages[0]}))
        raise
    if as_json:
        print(to_json(comparison.to_json()))
    else:
        print_comparison(comparison)
    raise typer.Exit(comparison.exit_code)
