"""`rustycs validate`: check a scene without running it."""

from __future__ import annotations

from pathlib import Path

import typer

NAME = "validate"


def command(
    scene: Path = typer.Argument(..., help="Scene file (.yaml)."),
    overrides: list[str] = typer.Option([], "--set", "-s", metavar="KEY=VALUE",
                                        help="Change the scene before validation (repeatable)."),
    seed: int = typer.Option(None, "--seed", help="Seed of the generators (default: the scene's seed)."),
) -> None:
    """Check a scene: prints FILE:LINE:COLUMN: message for every problem (exit 2), or one OK line (exit 0).

    Example: rustycs validate scenes/pile.yaml -s generators.circles.count=80
    """
    from ..loading import load_scene

    loaded = load_scene(scene, overrides, seed)
    world = loaded.scene.world
    print(f"{scene}: OK: scene '{loaded.scene.name}', {len(loaded.scene.bodies)} bodies, "
          f"{world.run_ticks} ticks at {world.tick_rate:g} Hz")
