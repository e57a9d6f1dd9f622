"""`rustycs render`: pictures of a run (PNG, GIF, MP4, or a self-contained HTML player)."""

from __future__ import annotations

from pathlib import Path

import typer

NAME = "render"


def command(
    run: Path = typer.Argument(..., help="Trajectory file written by `rustycs run`."),
    out: Path = typer.Option(
        ..., "-o", "--out", help="Output: .png, .gif, .mp4 or .html (decides the type)."
    ),
    tick: int = typer.Option(
        None, "--tick", help=".png: the tick drawn (default the last recorded); .html: the tick shown first."
    ),
    fps: float = typer.Option(30.0, "--fps", help=".gif/.mp4: frames per second."),
    every: int = typer.Option(
        None,
        "--every",
        help="Use every Kth recorded frame (.gif/.mp4 default: the "
        "stride that plays in real time at --fps; .html default: 1, thinned for long runs).",
    ),
    size: str = typer.Option("800x600", "--size", help="WIDTHxHEIGHT in pixels (.png/.gif/.mp4)."),
    view: str = typer.Option(
        None,
        "--view",
        help="XMIN,YMIN,XMAX,YMAX in metres (default: fit the bodies of the first frame and those "
        "still in the world at the last); widened to the image's aspect ratio.",
    ),
    hitboxes: bool = typer.Option(False, "--hitboxes", help="Draw each body's axis-aligned hitbox."),
    contacts: bool = typer.Option(False, "--contacts", help="Draw contact points and normals (if recorded)."),
    velocities: bool = typer.Option(False, "--velocities", help="Draw velocity arrows (0.1 s of motion)."),
    names: bool = typer.Option(False, "--names", help="Write each body's name."),
    joints: bool = typer.Option(True, "--joints/--no-joints", help="Draw joints: anchors, the lines between "
                                "them, springs as zigzags."),
) -> None:
    """Draw a run: one frame (.png), an animation (.gif, .mp4) or an interactive player (.html).

    Colours by material (rubber red, plastic green, stone grey, metal dark grey, default black).

    Static bodies are outlined; +y is up, on a metre grid. Prints the view used (metres).

    The .html player works offline: Space plays, arrows step, H/C/V/N/J toggle the overlays, wheel zooms.

    Example: rustycs render outputs/material-bounce.h5 -o bounce.gif --every 2 --velocities
    """
    from ..render.pictures import RenderRequest, render
    from ..render.raster import Overlays

    result = render(
        RenderRequest(
            run=run,
            out=out,
            tick=tick,
            fps=fps,
            every=every,
            size=size,
            view=view,
            overlays=Overlays(hitboxes=hitboxes, contacts=contacts, velocities=velocities, names=names,
                              joints=joints),
        )
    )
    for note in result.notes:
        typer.echo(f"note: {note}", err=True)
    box = ",".join(f"{value:.6g}" for value in result.view.box)
    frames = "1 frame" if result.frames == 1 else f"{result.frames} frames (every {result.every})"
    typer.echo(f"wrote {result.out}: {frames}, view {box}")
