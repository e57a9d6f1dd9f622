"""One measurement in a fresh process, printed as one JSON line on stdout (run by bench.runner).

    python -m rustycs_cli.bench.worker step ENGINE SCENE [--max-ticks N] [--block N] [--metrics a,b]
                                            [--sleep] [--threads N]
    python -m rustycs_cli.bench.worker record SCENE [--max-ticks N] [--sleep] [--threads N]
    python -m rustycs_cli.bench.worker first-step

`step` builds SCENE (a scene file, or `scaling:N`) in ENGINE (rustycs, pymunk or pyb2d3) and times
only the stepping: building, compiling and reading state back are outside the clock. rustycs steps in
blocks of `--block` ticks (world.step(n) runs a block in compiled code), the peers one Python call per
tick, with the attractor force set from Python before each, as the peer harness does. `record` times
what `rustycs run` does with the scene (every tick recorded to HDF5) and its peak memory. `first-step`
times importing rustycs and its first step (compiling the kernels, or loading them from the cache).
`step` also reports the resident memory per body the engine's world holds after the run (rustycs's
world and buffers, not its kernels; a peer's world, not rustycs's world it is described from).
`--sleep` lets bodies at rest sleep (in every engine, after the same time at rest); `--threads` is the
threads inside one world (rustycs's world.threads, pyb2d3's workers, pymunk's threaded space).
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import sys
import time
from typing import Any

import numpy as np

ENGINES = ("rustycs", "pymunk", "pyb2d3")


def load(ref: str, sleep: bool) -> Any:
    """The LoadedScene of a scene file or of `scaling:N`, sleeping after the peers' time at rest or not
    at all (whatever the scene says: every engine runs alike, and so do `step` and `record`)."""
    from ..loading import load_scene, load_scene_text
    from .peers import SLEEP_TIME
    from .scenes import SCALING_PREFIX, scaling_scene_text

    overrides = (f"world.sleep={str(sleep).lower()}", f"world.sleep_time={SLEEP_TIME}")
    if ref.startswith(SCALING_PREFIX):
        count = int(ref[len(SCALING_PREFIX):])
        return load_scene_text(scaling_scene_text(count), ref, overrides)
    return load_scene(ref, overrides)


def step(engine: str, ref: str, max_ticks: int | None, block: int, metrics: list[str], sleep: bool,
         threads: int) -> dict[str, Any]:
    """Time the scene's ticks (at most `max_ticks`) in `engine`, sleeping or not, with `threads` threads
    inside the world; report ms per tick and the quality measures."""
    from ..build import build_world
    from . import peers, quality
    from .spec import describe

    scene = load(ref, sleep).scene
    ticks = scene.world.ticks if max_ticks is None else min(max_ticks, scene.world.ticks)
    before = resident_bytes()
    began = time.perf_counter()
    world = build_world(scene)
    world.threads = threads
    built = resident_bytes()
    bench = describe(scene, world)  # (its first call takes 45 MB, not the world's)
    start = np.column_stack([world.positions, world.angles])
    perf = time.perf_counter
    if engine == "rustycs":
        from ..simulation import warm_up

        warm_up(threads)  # compiling or loading the kernels is not stepping, nor is making the buffers
        own = built - before - resident_bytes()  # the world, not the description and kernels
        world.prepare()
        build_s = perf() - began
        step = world.step
        blocks, rest = divmod(ticks, block)
        t0 = perf()  # the loop timed as a whole, as the peers' (a clock read a call was 0.1 us of a tick)
        for _ in range(blocks):
            step(block)
        if rest:
            step(rest)
        elapsed = perf() - t0
        end = np.column_stack([world.positions, world.angles])
        active = world.active
        ran = dict(sleep=world.sleep, threads=world.threads)
    else:
        importlib.import_module(engine)  # pymunk and pyb2d3 are their modules' names
        own = -resident_bytes()  # the peer's world and its stepping, not rustycs's world it is built from
        peer = peers.build(engine, bench, sleep, threads)
        build_s = perf() - began
        tick = peer.step
        t0 = perf()
        for _ in range(ticks):
            tick()
        elapsed = perf() - t0
        end = np.array(peer.poses(), dtype=np.float64).reshape(-1, 3)
        active = None
        ran = dict(sleep=peer.sleep, threads=peer.threads)
    own += resident_bytes()
    moving = sum(b.body_type == "dynamic" for b in bench.bodies)
    return dict(engine=engine, scene=scene.name, bodies=moving, ticks=ticks,
                block=block if engine == "rustycs" else 1, seconds=elapsed,
                ms_per_tick=1e3 * elapsed / max(ticks, 1), build_s=build_s, **ran,
                quality=quality.measure(metrics, bench, start, end, active),
                kb_per_body=own / 1e3 / max(len(bench.bodies), 1))


def resident_bytes() -> int:
    """This process's resident memory now (Linux's /proc; elsewhere 0, and the memory figures are 0)."""
    try:
        with open("/proc/self/statm") as statm:
            return int(statm.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except OSError:
        return 0


def record(ref: str, max_ticks: int | None, sleep: bool, threads: int) -> dict[str, Any]:
    """The cost per tick of `rustycs run` recording every tick (into a temporary file), and the peak
    memory, sleeping and threaded as the stepping it is put against. Building the world and opening and
    closing the file are taken out: a run of 0 ticks is timed too and subtracted (after an untimed one
    that pays the imports)."""
    import resource
    import tempfile
    from pathlib import Path

    from ..simulation import run_scene, warm_up

    loaded = load(ref, sleep)
    ticks = loaded.scene.world.ticks if max_ticks is None else min(max_ticks, loaded.scene.world.ticks)
    warm_up(threads)
    with tempfile.TemporaryDirectory(prefix="rustycs-bench-") as folder:

        def timed_run(count: int) -> tuple[float, Any]:
            began = time.perf_counter()
            run = run_scene(loaded, Path(folder) / f"run-{count}.h5", count, every=1, quiet=True,
                            threads=threads)
            if run.status != "complete":
                raise SystemExit(run.message or run.status)
            return time.perf_counter() - began, run

        timed_run(0)
        setup, _ = timed_run(0)
        elapsed, run = timed_run(ticks)
    seconds = max(elapsed - setup, 0.0)
    return dict(scene=loaded.scene.name, ticks=ticks, seconds=seconds, setup_seconds=setup,
                ms_per_tick=1e3 * seconds / max(ticks, 1), step_seconds=run.summary["step_seconds"],
                peak_memory_mb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)


def first_step() -> dict[str, float]:
    """Seconds to import rustycs and to run its first step (compile, or load the cached kernels)."""
    t0 = time.perf_counter()
    import rustycs  # noqa: F401

    t1 = time.perf_counter()
    from ..simulation import warm_up

    warm_up()
    return dict(import_s=t1 - t0, first_step_s=time.perf_counter() - t1)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog="python -m rustycs_cli.bench.worker", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="mode", required=True)
    timed = sub.add_parser("step")
    timed.add_argument("engine", choices=ENGINES)
    timed.add_argument("scene")
    timed.add_argument("--max-ticks", type=int)
    timed.add_argument("--block", type=int, default=100)
    timed.add_argument("--metrics", default="")
    recorded = sub.add_parser("record")
    recorded.add_argument("scene")
    recorded.add_argument("--max-ticks", type=int)
    for mode in (timed, recorded):
        mode.add_argument("--sleep", action="store_true")
        mode.add_argument("--threads", type=int, default=1)
    sub.add_parser("first-step")
    args = parser.parse_args(argv)
    if args.mode == "step":
        metrics = [m for m in args.metrics.split(",") if m]
        result: dict[str, Any] = step(args.engine, args.scene, args.max_ticks, args.block, metrics,
                                      args.sleep, args.threads)
    elif args.mode == "record":
        result = record(args.scene, args.max_ticks, args.sleep, args.threads)
    else:
        result = first_step()
    sys.stdout.write(json.dumps(result) + "\n")


if __name__ == "__main__":
    main()
