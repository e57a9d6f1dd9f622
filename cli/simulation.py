"""Running a scene: build the world, step it in blocks, record frames and the summary.

A run always ends with a valid trajectory: Ctrl-C or SIGTERM stops it after the current block
(status `interrupted`), a non-finite state stops it at the last recorded finite frame (status
`diverged`); both keep the frames so far. Shared by `rustycs run` and `rustycs sweep`.
"""

from __future__ import annotations

import dataclasses
import functools
import signal
import sys
import threading
import time
from collections.abc import Callable, Generator, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

from .errors import UserError

if TYPE_CHECKING:
    from .loading import LoadedScene

EXIT_CODES = {"complete": 0, "stopped": 0, "diverged": 1, "interrupted": 130}
# the first compilation of the engine on a 2-core machine: 4-5 min measured on 2026-12-07, 6.8-7.0 min on
# 2026-12-08 (`rustycs run` of large_pyramid 420 s, the bench's cold row 405 s); it was 150 s on 2026-12-02
COMPILE_TIME = "4-7 min"
BLOCK_TICKS = 256  # at most about this many ticks per engine call, so that Ctrl-C is answered promptly


@dataclass(frozen=True)
class RunResult:
    """What a run produced: the trajectory, its summary sidecar, the statistics and how it ended."""

    path: Path
    sidecar: Path
    summary: dict[str, Any]
    status: str  # complete | stopped | interrupted | diverged
    exit_code: int  # 0 | 130 | 1
    message: str | None  # why a run did not complete, for stderr


def load_source(path: str | Path, overrides: tuple[str, ...] = (), seed: int | None = None) -> LoadedScene:
    """Load a scene file, or the scene stored in a trajectory (to repeat that run).

    A stored scene already has its original overrides applied; they are kept in front of the new ones
    in `overrides`, as the record of how the scene was made.
    """
    from .loading import load_scene, load_scene_text
    from .trajectory import looks_like_trajectory, open_trajectory, read_scene

    if not looks_like_trajectory(path):
        return load_scene(path, overrides, seed)
    with open_trajectory(path) as file:
        text, stored = read_scene(file)
    loaded = load_scene_text(text, f"{path}:/parameters/scene", overrides, seed)
    return dataclasses.replace(loaded, overrides=(*stored, *loaded.overrides))


def run_scene(loaded: LoadedScene, out: Path, ticks: int | None = None, every: int | None = None,
              contacts: bool | None = None, progress: bool = False, *, compress: bool = False,
              quiet: bool = False, started: float | None = None, allow_full_disk: bool = False,
              threads: int = 1) -> RunResult:
    """Simulate `loaded` and write the trajectory to `out` and the summary next to it.

    ticks, every and contacts default to the scene's; `progress` shows a bar on stderr; `quiet`
    silences the one-line compilation notice; `started` (time.perf_counter) is when the command
    began, for the summary's wall time. A run that would not fit on the disk is refused unless
    `allow_full_disk`; a disk that fills up anyway ends the run with one message and no file. `threads`
    are the world's (`rustycs.World.threads`).
    """
    from .run_pace import Pace

    run = _run_calls(loaded, out, ticks, every, contacts, progress, compress=compress, quiet=quiet,
                     started=started, allow_full_disk=allow_full_disk, threads=threads)
    outcome: Stepped | None = None  # the first `send` starts the run
    pace: Pace | None = None
    with _stop_requests() as stop_requested:
        while True:
            try:
                calls = run.send(outcome)
            except StopIteration as end:
                return end.value
            pace = pace or Pace(calls.every, calls.most)
            if stop_requested():
                outcome = Stepped(interrupted=True)
                continue
            count, call_every = pace.next_call(calls.world.tick, calls.ticks)
            outcome = _step(calls.world, count, calls.frames if call_every else None, call_every)
            pace.took(count, outcome.seconds)


def run_batch(scenes: Sequence[tuple[LoadedScene, Path]], ticks: int | None = None, every: int | None = None,
              *, quiet: bool = False, allow_full_disk: bool = False) -> list[RunResult | Exception]:
    """Run scenes that have the same ticks and recording (interval and contacts: the caller groups them,
    as `sweep.units` does) as one batch of worlds (`rustycs.WorldBatch`): one compiled call steps them
    all, each exactly as `run_scene` would (the same trajectory, bitwise), and each writes its own
    trajectory and summary. Returns each scene's result, or the exception that ended it (a UserError,
    say), without stopping the others.

    The batch is a sweep's unit of work: the calls of small worlds are not bound by Python's cost per
    call. Its step time is shared equally by the worlds' summaries.
    """
    import rustycs

    from .run_pace import Pace

    results: list[RunResult | Exception | None] = [None] * len(scenes)
    runs: dict[int, tuple[Generator[Calls, Stepped | None, RunResult], Calls]] = {}

    def advance(index: int, outcome: Stepped | None) -> None:
        """Start scene `index` (outcome None) or give it its call's outcome; keep its next calls."""
        run = runs[index][0] if index in runs else _run_calls(
            *scenes[index], ticks, every, quiet=quiet, allow_full_disk=allow_full_disk)
        try:
            runs[index] = (run, run.send(outcome))
        except StopIteration as end:
            results[index] = end.value
            runs.pop(index, None)
        except Exception as err:  # noqa: BLE001 - one scene's failure must not end the batch
            results[index] = err
            runs.pop(index, None)

    for index in range(len(scenes)):
        advance(index, None)
    pace, batch, members = None, None, []
    with _stop_requests() as stop_requested:
        while runs:
            if members != sorted(runs):  # a world left the batch: the others go on in a new one
                members = sorted(runs)
                batch = rustycs.WorldBatch([runs[index][1].world for index in members])
            calls = [runs[index][1] for index in members]
            if pace is None:
                pace = Pace(calls[0].every, calls[0].most)
            if stop_requested():
                outcomes = [Stepped(interrupted=True)] * len(members)
            else:
                count, call_every = pace.next_call(calls[0].world.tick, calls[0].ticks)
                outcomes = _step_batch(batch, calls, count, call_every)
                pace.took(count, sum(outcome.seconds for outcome in outcomes))
            for index, outcome in zip(members, outcomes, strict=True):
                advance(index, outcome)
    return cast(list[RunResult | Exception], results)  # every scene has ended


@dataclass(frozen=True)
class Calls:
    """What the stepping loop of a run needs: its world, frame buffer, recording interval, tick count
    and the most ticks a call may take."""

    world: Any  # rustycs.World
    frames: dict[str, Any]
    every: int
    ticks: int
    most: int


@dataclass(frozen=True)
class Stepped:
    """The outcome of one engine call of a run: ticks stepped, frames recorded, seconds, and whether
    the state diverged (a rustycs.SimulationDiverged) or the run was asked to stop instead."""

    ticks: int = 0
    frames: int = 0
    seconds: float = 0.0
    diverged: Any = None
    interrupted: bool = False


def _step(world: Any, count: int, frames: dict[str, Any] | None, every: int) -> Stepped:
    """One engine call of a run alone."""
    import rustycs

    begin = time.perf_counter()
    try:
        recorded = world.step(count, record=frames, every=every) if frames is not None else world.step(count)
    except rustycs.SimulationDiverged as err:
        return Stepped(count, err.frames, time.perf_counter() - begin, err)
    return Stepped(count, recorded, time.perf_counter() - begin)


def _step_batch(batch: Any, calls: list[Calls], count: int, every: int) -> list[Stepped]:
    """One engine call of a batch (a rustycs.WorldBatch of the calls' worlds), the time shared equally."""
    import rustycs

    begin = time.perf_counter()
    records = [c.frames for c in calls] if every else None
    try:
        batch.step(count, records, every)
    except rustycs.SimulationDiverged:
        pass  # each world's own error is in `divergences`
    share = (time.perf_counter() - begin) / len(calls)
    recorded, diverged = batch.frames, batch.divergences()
    return [Stepped(count, int(recorded[k]), share, diverged.get(k)) for k in range(len(calls))]


def _run_calls(loaded: LoadedScene, out: Path, ticks: int | None = None, every: int | None = None,
               contacts: bool | None = None, progress: bool = False, *, compress: bool = False,
               quiet: bool = False, started: float | None = None, allow_full_disk: bool = False,
               threads: int = 1) -> Generator[Calls, Stepped | None, RunResult]:
    """A run as a generator: it opens the trajectory and yields its `Calls`, takes the `Stepped` outcome
    of each engine call its driver (`run_scene` alone, `run_batch` in a batch) makes, records the frames
    and events, and returns the RunResult once the run has ended and its files are written."""
    import rustycs

    from .build import build_world, material_names, shape_material_names
    from .output_files import (
        check_free_space,
        check_trajectory_output,
        estimated_bytes,
        output_lock,
        stale_temporaries,
        writing_errors,
    )
    from .scenario import attach, emitter_counts, measure_results, plan_run, stop_reason, summary_columns
    from .summary import SummaryTracker, energy_conservation, sidecar_path, to_json, write_text_atomic
    from .trajectory import (
        BLOCK_FRAMES,
        Frame,
        TrajectoryWriter,
        package_version,
    )
    from .trajectory_joints import joint_drawing

    started = time.perf_counter() if started is None else started
    ticks = loaded.scene.world.run_ticks if ticks is None else ticks
    plan = plan_run(loaded.scene, ticks)
    scene = plan.scene  # with the bodies its emitters may emit
    every = scene.output.every if every is None else every
    contacts = scene.output.contacts if contacts is None else contacts
    check_run_options(ticks, every)
    check_trajectory_output(out)
    with output_lock(out), writing_errors(out):
        for stale in stale_temporaries(out.parent, of=out.name):  # killed runs of this output
            stale.unlink(missing_ok=True)
        world = build_world(scene, plan)
        world.threads = threads
        attach(world, plan, contact_events=scene.output.events)
        if not allow_full_disk:
            check_free_space(out, estimated_bytes(world.body_count, ticks, every))
        if not quiet and rustycs.compile_needed():
            announce_compile()
        warm_up()
        names = [body.name for body in scene.bodies]
        tracker = SummaryTracker(list(world.body_types), energy_conservation(scene))
        writer = TrajectoryWriter(
            out, world, names=names, materials=material_names(scene),
            shape_materials=shape_material_names(scene),
            collision_groups=[body.collision_group for body in scene.bodies],
            attractor_names=[a.name or f"attractor-{k}" for k, a in enumerate(scene.attractors)],
            author="unknown", scene_text=loaded.text, overrides=loaded.overrides,
            contacts=contacts, compress=compress, joints=joint_drawing(scene))
        with writer, _progress_bar(progress, ticks, scene.name) as advance:
            # the engine records a block of frames per call, with no Python per tick; with contacts,
            # one frame per call (the contacts are the world's last tick's)
            per_call = 1 if contacts else max(1, min(BLOCK_FRAMES, BLOCK_TICKS // every))
            frames = world.frame_buffer(per_call)

            def record(count: int) -> None:
                if not contacts:  # whole blocks of frames
                    writer.append_block(frames, count)
                    tracker.add_block(frames, count)
                    return
                for row in range(count):
                    frame = Frame.from_buffer(frames, row, world.contacts())
                    writer.append(frame)
                    tracker.add(frame)

            world.capture(frames)
            record(1)
            world.prepare()  # the step's setup is not stepping time
            status, message, step_seconds = "complete", None, 0.0
            calls = Calls(world, frames, every, ticks, per_call * every)
            while world.tick < ticks:
                step = yield calls
                if step.interrupted:
                    status = "interrupted"
                    message = f"rustycs: interrupted at tick {world.tick}; the frames so far are in {out}"
                    break
                step_seconds += step.seconds
                writer.events.append(world.events(), scene.output.events)
                record(step.frames)
                if step.diverged is not None:
                    status = "diverged"
                    message = _divergence_message(step.diverged, names,
                                                  tracker.last.tick if tracker.last else 0, out)
                    break
                advance(step.ticks)
                if world.stop_condition is not None:
                    status = "stopped"
                    break
            summary = tracker.summary(
                scene=scene.name, scene_sha256=loaded.sha256, status=status, seed=scene.seed, dt=world.dt,
                wall_seconds=time.perf_counter() - started, step_seconds=step_seconds,
                divergence=message if status == "diverged" else None, escaped=world.escaped_count)
            summary.update(stop_reason=stop_reason(world, scene), measures=measure_results(world, scene),
                           emitters=emitter_counts(world, plan))
            parameters = {
                "scene_sha256": loaded.sha256, "seed": scene.seed, "rustycs_version": package_version(),
                "status": status, "ticks_completed": summary["ticks"], "dt": world.dt,
                "tick_rate": scene.world.tick_rate, "precision": scene.world.precision,
                "wall_seconds": summary["wall_seconds"], "step_seconds": step_seconds,
                "ticks_requested": ticks, "every": every, "contacts": contacts,
                "gravitational_constant": scene.world.gravitational_constant, "frames": summary["frames"],
                "divergence": summary["divergence"], "stop_reason": summary["stop_reason"],
            }
            sidecar = sidecar_path(out)
            sidecar.unlink(missing_ok=True)  # never a new trajectory beside an older run's summary
            writer.finish(parameters, summary_columns(summary), world.spawn_ticks)
        write_text_atomic(sidecar, to_json(summary) + "\n")
    return RunResult(out, sidecar, summary, status, EXIT_CODES[status], message)


def check_run_options(ticks: int | None, every: int | None) -> None:
    """UserError for a tick count or recording interval beyond MAX_TICKS (before any work)."""
    from .limits import MAX_TICKS

    for option, value, least in (("--ticks", ticks, 0), ("--every", every, 1)):
        if value is not None and not least <= value <= MAX_TICKS.value:
            raise UserError(f"{option} {value}: must be from {least} to {MAX_TICKS}")


def _divergence_message(err: Any, names: list[str], last_tick: int, out: Path) -> str:
    """Which tick and body went non-finite (err is a rustycs.SimulationDiverged), and what was kept."""
    body = err.body
    who = f"body {names[body]!r} (index {body})" if 0 <= body < len(names) else f"body index {body}"
    return (f"rustycs: the run diverged at tick {err.tick}: {who} got a non-finite state; "
            f"frames up to tick {last_tick} are kept in {out}")


def announce_compile() -> None:
    """Say on stderr that the engine compiles now (its disk cache is cold: `rustycs.compile_needed`)."""
    print(f"rustycs: compiling the engine (happens once, {COMPILE_TIME} on 2 cores)...", file=sys.stderr)


@functools.cache
def warm_up(threads: int = 1) -> None:
    """Load the kernels with a small world, so compiling or loading them is not timed as stepping;
    with `threads` > 1 also start numba's threads (its first parallel step does). Once per process and
    thread count: it takes 20 ms even when loaded (0.65 s of a 2.4 s sweep of 32 small variants).

    The world's 16 circles lie on one spot, so that its first tick has more pairs than its buffers hold
    and loads the kernel that grows them: loaded inside a timed run, it took 13 ms of the 210-box
    pyramid's first tick (0.02 ms of each of its 600)."""
    import rustycs

    world = rustycs.World(threads=threads)
    for k in range(16):
        world.add_body(rustycs.Circle(radius=0.5), position=(0.01 * k, 0.4))
    world.add_body(rustycs.Box(1.0, 1.0), position=(0.0, -0.5), body_type="static")
    world.load_kernels()


THREAD_STOP = threading.Event()
"""Set by the main thread to stop runs going on in other threads (which cannot receive signals)."""


@contextmanager
def _stop_requests() -> Iterator[Callable[[], bool]]:
    """While active, SIGINT and SIGTERM only set a flag (yields a function reading it), so the loop can
    finish its block and close the file. Outside the main thread (where signals cannot be caught) the
    flag is THREAD_STOP."""
    requested: list[int] = []
    if threading.current_thread() is not threading.main_thread():
        yield THREAD_STOP.is_set
        return
    previous = {sig: signal.signal(sig, lambda signum, _frame: requested.append(signum))
                for sig in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield lambda: bool(requested)
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


@contextmanager
def _progress_bar(enabled: bool, total: int, label: str) -> Iterator[Callable[[int], None]]:
    """A transient rich progress bar on stderr; yields `advance(ticks)` (a no-op when disabled)."""
    if not enabled:
        yield lambda _ticks: None
        return
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeRemainingColumn

    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TextColumn("ticks"),
               TimeRemainingColumn())
    with Progress(*columns, console=Console(stderr=True), transient=True) as bar:
        task = bar.add_task(label, total=total)
        yield lambda ticks: bar.advance(task, ticks)
