"""`rustycs watch`: a live preview of a scene in the browser, run again on every save."""

from __future__ import annotations

from pathlib import Path

import typer

NAME = "watch"


def command(
    scene: Path = typer.Argument(..., help="Scene file (.yaml) to preview."),
    overrides: list[str] = typer.Option([], "--set", "-s", metavar="KEY=VALUE",
                                        help="Change the scene before validation (repeatable)."),
    ticks: int = typer.Option(None, "--ticks", min=0,
                              help="Ticks of each preview run (default: world.ticks)."),
    port: int = typer.Option(8765, "--port", min=0, max=65535,
                             help="Port on 127.0.0.1 (0: any free port; the URL is printed)."),
) -> None:
    """Preview a scene while you write it: serves the HTML player on 127.0.0.1 and runs the scene again
    each time the file is saved (the page reloads itself; problems are shown at their lines).

    Ctrl-C stops it.

    Example: rustycs watch scenes/slope.yaml --ticks 480
    """
    from ..watch import watch

    if not scene.is_file():
        from ..errors import UserError

        raise UserError(f"{scene}: no such scene file")
    watch(scene, overrides, ticks, port, lambda line: typer.echo(line))
