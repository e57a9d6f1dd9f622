"""`rustycs run`: validate a scene, simulate it and write its trajectory and summary."""

from __future__ import annotations

import sys
import time
from pathlib import Path

import typer

from rustycs.defaults import MAX_THREADS

from ..errors import UserError
from ..output_files import inside

NAME = "run"


def command(
    scene: Path = typer.Argument(..., help="Scene file (.yaml), or a trajectory (.h5) to repeat its run."),
    ticks: int = typer.Option(None, "--ticks", min=0, help="Ticks to simulate (default: world.ticks)."),
    duration: float = typer.Option(None, "--duration", min=0.0,
                                   help="Seconds to simulate, instead of --ticks (ticks = round(duration * "
                                   "tick_rate))."),
    out: Path = typer.Option(None, "--out", "-o",
                             help="Output trajectory (default: outputs/<scene name>.h5)."),
    overrides: list[str] = typer.Option([], "--set", "-s", metavar="KEY=VALUE",
                                        help="Change the scene before validation (repeatable)."),
    every: int = typer.Option(None, "--every", min=1, help="Record every N ticks (default: output.every)."),
    seed: int = typer.Option(None, "--seed", help="Seed of the generators (default: the scene's seed)."),
    quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress bar, notice or summary table."),
    json: bool = typer.Option(False, "--json", help="Print the summary as JSON on stdout, nothing else."),
    contacts: bool = typer.Option(None, "--contacts/--no-contacts",
                                  help="Record contact points (default: output.contacts)."),
    compress: bool = typer.Option(False, "--compress", help="Compress the datasets (gzip with shuffle)."),
    allow_full_disk: bool = typer.Option(False, "--allow-full-disk",
                                         help="Run even when the output looks larger than the free disk."),
    threads: int = typer.Option(1, "--threads", min=1, max=MAX_THREADS,
                                help="Threads inside the world: placing shapes, colliding pairs and "
                                "preparing contacts run in parts over them; the trajectory is bitwise the "
                                "same for every N (for large worlds; sweeps use the cores across variants)."),
) -> None:
    """Simulate a scene and write its trajectory (HDF5) and summary (table, JSON sidecar).

    Exit codes: 0 complete or stopped (a world.stop_when condition held), 1 diverged, 2 invalid input, 130
    interrupted (the file keeps the frames so far).

    Example: rustycs run scenes/material_bounce.yaml --ticks 1200 -s world.precision=20 --out bounce.h5
    """
    from ..simulation import check_run_options, load_source, run_scene
    from ..summary import summary_table, to_json

    started = time.perf_counter()
    try:
        if ticks is not None and duration is not None:
            raise UserError("give --ticks or --duration, not both")
        check_run_options(ticks, every)
        loaded = load_source(scene, tuple(overrides), seed)
        if duration is not None:
            ticks = round(duration * loaded.scene.world.tick_rate)
        target = out if out is not None else _default_output(loaded.scene.name, scene)
        result = run_scene(loaded, target, ticks, every, contacts,
                           progress=sys.stderr.isatty() and not quiet, compress=compress, quiet=quiet,
                           started=started, allow_full_disk=allow_full_disk, threads=threads)
    except KeyboardInterrupt:  # before the run installed its own handler
        print("rustycs: interrupted", file=sys.stderr)
        raise typer.Exit(130) from None
    if result.message:
        print(result.message, file=sys.stderr)
    if json:
        print(to_json(result.summary))
    elif not quiet:
        from rich.console import Console

        Console().print(summary_table(result.summary, f"{result.path} ({result.sidecar.name})"))
    raise typer.Exit(result.exit_code)


def _default_output(name: str, source: Path) -> Path:
    """outputs/<name>.h5, creating outputs/; `-rerun` is appended rather than overwrite the source run."""
    folder = Path("outputs")
    try:
        folder.mkdir(exist_ok=True)
    except OSError as err:
        raise UserError(f"{folder}: cannot create the output folder ({err.strerror})") from None
    path = inside(folder, name, ".h5")
    if path.exists() and source.exists() and path.samefile(source):
        path = inside(folder, f"{name}-rerun", ".h5")
    return path
