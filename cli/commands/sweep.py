"""`rustycs sweep`: run a scene over the cartesian product of parameter values."""

from __future__ import annotations

from pathlib import Path

import typer

from ..errors import UserError

NAME = "sweep"


def command(
    scene: Path = typer.Argument(
        ..., metavar="SCENE", help="The scene file (.yaml), or a trajectory to repeat.", show_default=False
    ),
    params: list[str] = typer.Option(
        ..., "--param", "-p", metavar="KEY=V1,V2,...", show_default=False,
        help="A swept key and its values (YAML), or KEY=range(START,STOP,STEP) with STOP excluded. "
        "Repeat for a grid.",
    ),
    sets: list[str] = typer.Option(
        [], "--set", "-s", metavar="KEY=VALUE",
        help="A fixed override for every variant (applied before the swept ones).",
    ),
    out: Path | None = typer.Option(
        None, "--out", "-o", metavar="DIR", help="Output folder (default: outputs/<scene name>-sweep/)."
    ),
    workers: int | None = typer.Option(
        None, "--workers", "-w", min=1, help="Local workers (default: the number of cores)."
    ),
    local: str = typer.Option(
        "threads", "--local", metavar="threads|processes",
        help="How local workers run: 'threads' in parallel threads of one process (faster: see README), "
        "'processes' one process per worker.",
    ),
    batch: int = typer.Option(
        16, "--batch", min=1, max=1024, metavar="N",
        help="Variants of the same size (bodies, ticks, recording) step together as one batch of worlds, "
        "up to N at a time; 1 runs them one by one.",
    ),
    scheduler: str | None = typer.Option(
        None, "--scheduler", metavar="ADDRESS",
        help="Run on an existing Dask cluster, e.g. tcp://10.0.0.5:8786 (needs the 'dask' extra, and "
        "SCENE and DIR on a filesystem the workers share).",
    ),
    ticks: int | None = typer.Option(
        None, "--ticks", "-t", min=0, help="Ticks per variant (default: the scene's)."
    ),
    every: int | None = typer.Option(
        None, "--every", min=1, help="Record every N ticks (default: the scene's)."
    ),
    samples: int | None = typer.Option(
        None, "--samples", "-n", min=1,
        help="Random variants: each -p KEY=uniform(LO,HI) or KEY=normal(MEAN,STD) is drawn this many times "
        "(crossed with the listed values of the other keys).",
    ),
    seed: int = typer.Option(0, "--seed", min=0, help="Seed of the random variants (--samples)."),
    quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress bar and no table."),
    as_json: bool = typer.Option(
        False, "--json", help="Print the rows (as in sweep.json) on stdout, nothing else."
    ),
    allow_full_disk: bool = typer.Option(
        False, "--allow-full-disk", help="Run even when the outputs look larger than the free disk."
    ),
) -> None:
    """Run a scene over a grid of parameter values, one trajectory per variant.

    Every variant is validated first. Each writes DIR/<scene>-<index>-<values>.h5;
    DIR/sweep.csv and sweep.json hold one row per variant: its swept values (one
    column per key), status, output file and summary statistics. Variants already
    complete are skipped, so re-running an interrupted sweep resumes it. Exit 1
    when a variant fails or diverges (the others still run), 130 when interrupted.

    Each measure of the scene is a column `measure.<name>` (a histogram one per bin).

    Example: rustycs sweep scenes/material_bounce.yaml -p world.precision=5,10,20
    -p 'forces.gravity.acceleration=[0,-9.81],[0,-1.62]' --ticks 600

    Example: rustycs sweep scenes/projectile.yaml -p 'bodies.ball.velocity.0=uniform(4,8)' --samples 20

    Example: rustycs sweep scenes/material_bounce.yaml -p 'world.precision=range(1,33)' --batch 1
    (one variant at a time instead of batches of worlds)
    """
    from ..summary import to_json
    from ..sweep import default_workers, plan_sweep, run_sweep
    from ..sweep_report import print_sweep_table, report_problems, variant_progress
    from ..sweep_sampling import draw_samples, is_sampled, parse_sampled
    from ..sweep_values import parse_swept_keys

    if local not in ("threads", "processes"):
        raise UserError(f"--local: expected 'threads' or 'processes', got {local!r}")
    sampled = [parse_sampled(option) for option in params if is_sampled(option)]
    if bool(sampled) != (samples is not None):
        raise UserError("give --samples N with -p KEY=uniform(LO,HI) or KEY=normal(MEAN,STD), and only then")
    rows = draw_samples(sampled, samples or 0, seed)
    listed = parse_swept_keys([option for option in params if not is_sampled(option)])
    plan = plan_sweep(scene, listed, sets, out, ticks, every, samples=rows)
    show = not (quiet or as_json)
    with variant_progress(not quiet, len(plan.variants), f"sweep {plan.scene_name}") as on_outcome:
        result = run_sweep(plan, workers or default_workers(), scheduler, on_outcome, quiet=quiet,
                           local=local, allow_full_disk=allow_full_disk, batch=batch)
    if as_json:
        print(to_json(result.rows()))
    elif show:
        print_sweep_table(result)
    report_problems(result)
    raise typer.Exit(result.exit_code)
