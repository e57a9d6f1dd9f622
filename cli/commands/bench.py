"""`rustycs bench`: stepping speed of the bench scenes, beside pymunk and Box2D v3."""

from __future__ import annotations

import shlex
import sys
from pathlib import Path

import typer

from rustycs.defaults import MAX_THREADS

from ..bench.peers import PYMUNK_MAX_THREADS, SLEEP_TIME

NAME = "bench"


def command(
    ids: list[str] = typer.Argument(None, metavar="SCENE_ID", show_default=False,
                                    help="Scene ids to run, like --scenes."),
    scenes: list[str] = typer.Option([], "--scenes", metavar="ID", show_default=False,
                                     help="Scenes to run: S1 .. S6, compounds, large_pyramid, "
                                     "many_pyramids, smash, tumbler, joint_grid, ragdoll_rain, shower "
                                     "(repeatable, or comma-separated; default: S1 .. S6; Box2D v3's "
                                     "benchmark scenes compounds .. ragdoll_rain, and shower, 500 bullets "
                                     "in a box of thin walls, run only when named)."),
    peers: bool = typer.Option(False, "--peers", help="Also step the same bodies in pymunk and Box2D v3 "
                               "(pyb2d3), from the `bench` extra: pip install 'rustycs\\[bench]'."),
    reps: int = typer.Option(3, "--reps", min=1, help="Repetitions, each in a fresh process."),
    ticks: int = typer.Option(None, "--ticks", min=1, help="Step at most N ticks per run (default: the "
                              "scene's world.ticks; the scaling series runs 300)."),
    block: int = typer.Option(100, "--block", min=1, help="Ticks per world.step(n) call of rustycs."),
    sleep: bool = typer.Option(False, "--sleep", help=f"Bodies at rest for {SLEEP_TIME} s sleep, in every "
                               "engine (default: sleeping off)."),
    threads: int = typer.Option(1, "--threads", min=1, max=MAX_THREADS,
                                help="Threads inside one world: rustycs's world.threads, Box2D v3's workers, "
                                f"pymunk's threaded space ({PYMUNK_MAX_THREADS} at most)."),
    scaling: bool = typer.Option(True, "--scaling/--no-scaling",
                                 help="Also the scaling series: 1k, 4k and 16k circles in a container."),
    compile_: bool = typer.Option(True, "--compile/--no-compile",
                                  help="Also time the cold and warm compile and the start-up."),
    recording: bool = typer.Option(True, "--recording/--no-recording",
                                   help="Also time `rustycs run` of S4 recording every tick (with S4)."),
    scene_dir: Path = typer.Option(None, "--scene-dir", help="Folder of the S*_*.yaml and compounds.yaml "
                                   "scenes (default: scenes/bench of the checkout)."),
    json: bool = typer.Option(False, "--json", help="Print the results as JSON on stdout, nothing else."),
    out: Path = typer.Option(None, "--out", "-o", help="Also write the results as JSON to this file."),
    markdown: bool = typer.Option(False, "--markdown", help="Print the tables as Markdown."),
    quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress lines on stderr."),
) -> None:
    """Measure ms per tick of the bench scenes (median and min of --reps fresh processes, stepping only),
    with --peers beside pymunk and Box2D v3 (ratio rustycs / peer), plus quality at the end of each run,
    compile and start-up times, the cost of recording every tick (rustycs run, S4) and a scaling series.

    Exit codes: 0 all measured, 1 a measurement failed (diverged or crashed), 2 invalid input or the peer
    engines are missing.

    Examples: rustycs bench --scenes S2 S4 --peers --reps 3 --no-scaling;
    rustycs bench compounds --peers --no-scaling --no-compile --sleep --threads 2
    """
    from ..bench import peers as peer_engines
    from ..bench.report import print_report
    from ..bench.scenes import default_scene_dir, find_scenes, parse_ids
    from ..bench.suite import Plan, failures, run
    from ..errors import UserError
    from ..summary import to_json, write_text_atomic

    found = find_scenes(scene_dir or default_scene_dir(), parse_ids([*scenes, *(ids or [])]))
    if peers and (absent := peer_engines.missing()):
        raise UserError(f"--peers needs {' and '.join(absent)} (the `bench` extra): "
                        "pip install 'rustycs[bench]'")
    plan = Plan(scenes=found, engines=("rustycs", *peer_engines.ENGINES) if peers else ("rustycs",),
                reps=reps, max_ticks=ticks, block=block, compile=compile_, scaling=scaling,
                recording=recording, sleep=sleep, threads=threads,
                command=shlex.join(["rustycs", *sys.argv[1:]]))

    def progress(line: str) -> None:
        if not quiet:
            print(line, file=sys.stderr, flush=True)

    result = run(plan, progress)
    text = to_json(result)
    if out is not None:
        write_text_atomic(out, text + "\n")
    if json:
        print(text)
    else:
        print_report(result, markdown)
    problems = failures(result)
    for problem in problems:
        print(f"rustycs bench: {problem}", file=sys.stderr)
    raise typer.Exit(1 if problems else 0)
