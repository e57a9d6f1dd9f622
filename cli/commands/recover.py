"""`rustycs recover`: the frames of a killed run, as an interrupted trajectory."""

from __future__ import annotations

from pathlib import Path

import typer

NAME = "recover"


def command(
    temporary: Path = typer.Argument(..., help="The temporary file a killed run left (.NAME.h5.tmp-PID)."),
) -> None:
    """Turn the temporary file of a killed run (SIGKILL, out of memory, a lost worker) into a trajectory
    of the frames saved so far (status interrupted), next to it: NAME.h5, or NAME-recovered.h5.

    Example: rustycs recover outputs/.pile.h5.tmp-12345
    """
    from ..recovery import recover

    path, summary = recover(temporary)
    print(f"{path}: recovered {summary['frames']} frames, up to tick {summary['ticks']} (interrupted)")
