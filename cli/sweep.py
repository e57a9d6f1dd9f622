"""Parameter sweeps (`rustycs sweep`): the cartesian product of swept scene keys, one run per variant.

Every variant is validated before any runs, so a typo in one value cannot waste an hour of compute.
Each variant writes its own trajectory (never two processes in one file), and the sweep tables are
rewritten atomically at the end; a variant whose trajectory is already complete for the same resolved
scene is skipped, which makes an interrupted sweep resumable by running the same command again.
Variants run on local threads or processes, in this process (one worker), or on a Dask cluster through
its concurrent.futures executor: all go through `run_variants`, the unit of work, which steps variants
of the same size together as one batch of worlds (`simulation.run_batch`).
"""

from __future__ import annotations

import functools
import itertools
import json
import os
import re
import signal
import threading
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .errors import UserError
from .scenario import summary_columns
from .sweep_sampling import SampledRow
from .sweep_values import SweptKey

if TYPE_CHECKING:
    from concurrent.futures import Executor, Future

    from .simulation import RunResult

CONNECT_TIMEOUT = 10.0  # seconds to reach a Dask scheduler
MAX_SLUG = 80
BATCH = 16  # variants per batch of worlds at most: each holds an open trajectory until it ends
FAILED = "failed"  # status of a variant that raised instead of finishing a run


@dataclass(frozen=True)
class VariantTask:
    """Everything a worker needs to run one variant; plain data, so it pickles to any worker."""

    index: int
    scene: Path
    overrides: tuple[str, ...]
    output: Path
    ticks: int | None = None
    every: int | None = None
    allow_full_disk: bool = False  # checked once for the whole sweep, before any variant runs


@dataclass
class VariantOutcome:
    """What became of one variant: its run status, summary statistics, and error if any."""

    index: int
    status: str
    summary: dict[str, Any] = field(default_factory=dict)
    error: str | None = None
    skipped: bool = False

    @property
    def failed(self) -> bool:
        return self.status in (FAILED, "diverged")


@dataclass
class Variant:
    """One point of the sweep grid, validated: its swept values, task and resolved-scene hash."""

    parameters: dict[str, Any]
    label: str  # "key=value ..." as the user wrote the values
    task: VariantTask
    sha256: str
    expected_ticks: int
    expected_bytes: int  # about how large its trajectory gets
    size: tuple[int, int, int, bool]  # bodies, ticks, every, contacts: variants of one size batch together


@dataclass
class SweepPlan:
    """The validated variants of a sweep and where its outputs go."""

    scene_name: str
    out_dir: Path
    swept: list[SweptKey]
    variants: list[Variant]


def plan_sweep(
    scene: Path,
    swept: list[SweptKey],
    fixed: Sequence[str] = (),
    out_dir: Path | None = None,
    ticks: int | None = None,
    every: int | None = None,
    samples: Sequence[SampledRow] = (),
) -> SweepPlan:
    """Build and validate every variant (fixed overrides first, then the swept ones).

    With `samples` (random values of sampled keys, `sweep_sampling`), every combination of the swept
    values is run with each sample. Raises one UserError listing the problems of all invalid variants,
    before anything runs.
    """
    from .limits import MAX_VARIANTS
    from .output_files import check_output_folder, estimated_bytes, inside
    from .simulation import check_run_options, load_source

    check_run_options(ticks, every)
    if out_dir is not None:
        check_output_folder(out_dir)
    count = functools.reduce(lambda product, key: product * len(key.values), swept, 1)
    if count > MAX_VARIANTS.value:
        raise UserError(f"the sweep has {count} variants, more than {MAX_VARIANTS}; sweep fewer values")
    combinations = list(itertools.product(*(key.values for key in swept)))
    if samples:
        swept = [*swept, *(SweptKey(key, ()) for key in samples[0])]
        combinations = [(*combination, *row.values()) for combination in combinations for row in samples]
    width = len(str(len(combinations) - 1))
    problems: dict[str, list[str]] = {}
    variants: list[Variant] = []
    scene_name = ""
    for index, values in enumerate(combinations):
        parameters = {key.key: value.value for key, value in zip(swept, values, strict=True)}
        overrides = (*fixed, *(f"{key.key}={value.text}" for key, value in zip(swept, values, strict=True)))
        label = " ".join(f"{key.key}={value.text}" for key, value in zip(swept, values, strict=True))
        try:
            loaded = load_source(scene, overrides)
        except UserError as err:
            for message in err.messages:
                problems.setdefault(_as_swept(message, overrides[len(fixed):]), []).append(
                    f"variant {index}: {label}"
                )
            continue
        scene_name = loaded.scene.name
        folder = out_dir if out_dir is not None else inside(Path("outputs"), f"{scene_name}-sweep")
        output = folder / f"{scene_name}-{index:0{width}d}-{_slug(label)}.h5"
        task = VariantTask(index, scene.resolve(), overrides, output.resolve(), ticks, every, True)
        expected = ticks if ticks is not None else loaded.scene.world.run_ticks
        interval = every if every is not None else loaded.scene.output.every
        bodies = len(loaded.scene.bodies)
        variants.append(Variant(parameters, label, task, loaded.sha256, expected,
                                estimated_bytes(bodies, expected, interval),
                                (bodies, expected, interval, loaded.scene.output.contacts)))
    if problems:
        raise UserError(_name_variants(problems, len(combinations)))
    return SweepPlan(scene_name, folder, swept, variants)


def _slug(text: str) -> str:
    """A file-name-safe version of `key=value ...` (kept short; the index makes names unique)."""
    slug = re.sub(r"[^A-Za-z0-9.=+-]+", "_", text).strip("_")
    return slug[:MAX_SLUG]


def _as_swept(message: str, swept: Sequence[str]) -> str:
    """Say `-p KEY=VALUE` rather than `--set KEY=VALUE` for a problem with a swept value."""
    for override in swept:
        if message.startswith(f"--set {override}:"):
            return f"-p {message.removeprefix('--set ')}"
    return message


def _name_variants(problems: dict[str, list[str]], count: int) -> list[str]:
    """One line per distinct problem. It names the variants it affects unless it affects all of them
    (a problem of the scene or a fixed --set) or already names the swept value at fault."""
    return [
        message if len(labels) == count or message.startswith("-p ") else f"{message} [{'; '.join(labels)}]"
        for message, labels in problems.items()
    ]


def finished_outcome(variant: Variant) -> VariantOutcome | None:
    """The outcome of an earlier complete run of this exact variant, or None when it must run.

    A stored trajectory counts only when its status is complete, its resolved scene hashes the same
    and it ran the requested number of ticks (and frame interval, when one is forced).
    """
    from .summary import sidecar_path
    from .trajectory import open_trajectory, read_attrs

    output = variant.task.output
    if not output.exists():
        return None
    try:
        with open_trajectory(output) as file:
            stored = read_attrs(file["parameters"])
            summary = read_attrs(file["parameters/summary"])
    except (UserError, OSError, KeyError):  # unreadable or half-written: run it again
        return None
    if (
        stored.get("status") not in ("complete", "stopped")
        or stored.get("scene_sha256") != variant.sha256
        or (stored.get("status") == "complete" and stored.get("ticks_completed") != variant.expected_ticks)
        or (variant.task.every is not None and stored.get("every") != variant.task.every)
    ):
        return None
    sidecar = sidecar_path(output)
    if sidecar.exists():  # the same statistics, with None where the attributes cannot hold one
        try:
            summary = json.loads(sidecar.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            pass
    return VariantOutcome(variant.task.index, stored["status"], summary, skipped=True)


def run_variant(task: VariantTask) -> VariantOutcome:
    """Load and run one variant, turning any failure into an outcome rather than an exception."""
    from .simulation import load_source, run_scene

    try:
        loaded = load_source(task.scene, task.overrides)
        result = run_scene(loaded, task.output, ticks=task.ticks, every=task.every, quiet=True,
                           allow_full_disk=task.allow_full_disk)
    except Exception as err:  # a crashed variant must not stop the others
        return _outcome(task.index, err)
    return _outcome(task.index, result)


def _outcome(index: int, result: RunResult | Exception) -> VariantOutcome:
    """A variant's outcome from its run's result or the error that ended it."""
    if isinstance(result, UserError):
        return VariantOutcome(index, FAILED, error="; ".join(result.messages))
    if isinstance(result, Exception):
        return VariantOutcome(index, FAILED, error=f"{type(result).__name__}: {result}")
    return VariantOutcome(index, result.status, dict(result.summary), result.message)


def run_variants(tasks: Sequence[VariantTask]) -> list[VariantOutcome]:
    """Run variants of one size (`units`) as one batch of worlds in this process: the unit of work sent
    to a worker. Each variant's trajectory is bitwise the one it has run alone."""
    from .simulation import load_source, run_batch

    if len(tasks) == 1:
        return [run_variant(tasks[0])]
    outcomes: dict[int, VariantOutcome] = {}
    loaded = []
    for task in tasks:
        try:
            loaded.append((task, load_source(task.scene, task.overrides)))
        except UserError as err:
            outcomes[task.index] = _outcome(task.index, err)
    first = tasks[0]
    results = run_batch([(scene, task.output) for task, scene in loaded], first.ticks, first.every,
                        quiet=True, allow_full_disk=first.allow_full_disk)
    for (task, _), result in zip(loaded, results, strict=True):
        outcomes[task.index] = _outcome(task.index, result)
    return [outcomes[task.index] for task in tasks]


def units(variants: Sequence[Variant], workers: int, batch: int = BATCH) -> list[list[VariantTask]]:
    """The variants' tasks in units of work: variants of one size (bodies, ticks, recording) in batches
    of at most `batch`, each size's variants spread evenly over the workers, in the variants' order."""
    by_size: dict[tuple[int, int, int, bool], list[VariantTask]] = {}
    for variant in variants:
        by_size.setdefault(variant.size, []).append(variant.task)
    found = []
    for tasks in by_size.values():
        per_unit = max(1, min(batch, -(-len(tasks) // max(workers, 1))))
        found += [tasks[k:k + per_unit] for k in range(0, len(tasks), per_unit)]
    return sorted(found, key=lambda unit: unit[0].index)


def _ignore_sigint() -> None:
    """Idle pool workers ignore Ctrl-C (the main process handles it); a running variant's own
    handler still stops its run, which then ends as interrupted with its frames kept. A worker whose
    sweep process is gone (killed) stops its variant the same way and exits."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    threading.Thread(target=_exit_when_orphaned, args=(os.getppid(),), daemon=True).start()


ORPHAN_CHECK_SECONDS = 0.5
ORPHAN_GRACE_SECONDS = 10.0  # for the running variant to close its file as interrupted


def _exit_when_orphaned(parent: int) -> None:
    """In a pool worker: once the parent process has died, interrupt the running variant (its
    trajectory is kept) and exit, rather than wait forever for work that will never come."""
    import time

    while os.getppid() == parent:
        time.sleep(ORPHAN_CHECK_SECONDS)
    os.kill(os.getpid(), signal.SIGINT)
    time.sleep(ORPHAN_GRACE_SECONDS)
    os._exit(1)


def _interrupt_pool_workers() -> None:
    """Ask the running variants of the process pool to stop (as Ctrl-C in a terminal does)."""
    import multiprocessing

    for child in multiprocessing.active_children():
        if child.pid is not None:
            os.kill(child.pid, signal.SIGINT)


def dispatch(
    tasks: Sequence[list[VariantTask]],
    record: Callable[[VariantOutcome], None],
    workers: int,
    scheduler: str | None = None,
    local: str = "threads",
) -> bool:
    """Run the units of tasks (`units`), passing each outcome to `record` as it arrives; True when
    interrupted.

    In this process when one worker suffices; otherwise, locally, in parallel threads of this process
    (`local="threads"`: the engine's step releases the GIL, and the compiled kernels are loaded once)
    or on a process pool (`"processes"`); with a scheduler address, on a Dask cluster. The sweep stops
    at Ctrl-C or at the first interrupted variant.
    """
    if not tasks:
        return False
    if scheduler is None and min(workers, len(tasks)) == 1:
        for unit in tasks:
            interrupted = False
            for outcome in run_variants(unit):
                record(outcome)
                interrupted |= outcome.status == "interrupted"
            if interrupted:
                return True
        return False
    if scheduler is not None:
        client = _dask_client(scheduler)
        executor = client.get_executor(pure=False)
        try:
            # the scheduler spreads the tasks; running ones cannot be stopped, only dropped
            stop = functools.partial(executor.shutdown, wait=False)
            return _run_on_executor(executor, tasks, record, len(tasks), stop)
        finally:
            client.close()
    window = min(workers, len(tasks))
    if local == "threads":
        from concurrent.futures import ThreadPoolExecutor

        from .simulation import THREAD_STOP

        THREAD_STOP.clear()
        with ThreadPoolExecutor(window) as pool:
            return _run_on_executor(pool, tasks, record, window, THREAD_STOP.set)
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    context = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(window, mp_context=context, initializer=_ignore_sigint) as pool:
        return _run_on_executor(pool, tasks, record, window, _interrupt_pool_workers)


def _run_on_executor(
    executor: Executor,
    tasks: Sequence[list[VariantTask]],
    record: Callable[[VariantOutcome], None],
    window: int,
    interrupt: Callable[[], None],
) -> bool:
    """Keep `window` units in flight, record outcomes in completion order; True when interrupted.

    Only as many units as can run are submitted, so that after Ctrl-C nothing queued starts: the
    running ones are interrupted (their outcomes recorded when they come back) and the rest never run.
    """
    from concurrent.futures import FIRST_COMPLETED, wait

    pending = iter(tasks)
    running: dict[Future[list[VariantOutcome]], list[VariantTask]] = {}
    interrupted = False

    def collect(future: Future[list[VariantOutcome]]) -> None:
        nonlocal interrupted
        for outcome in _outcomes(future, running.pop(future)):
            record(outcome)
            interrupted |= outcome.status == "interrupted"

    try:
        while not interrupted:
            while len(running) < window and (unit := next(pending, None)) is not None:
                running[executor.submit(run_variants, unit)] = unit
            if not running:
                return False
            # a short timeout: a signal caught by a worker thread only runs its handler once the main
            # thread wakes, which a wait without timeout would put off until a variant finishes
            done, _ = wait(running, timeout=0.1, return_when=FIRST_COMPLETED)
            for future in done:
                collect(future)
    except KeyboardInterrupt:
        interrupted = True
    interrupt()
    for future in list(running):
        collect(future)
    return True


def _outcomes(future: Future[list[VariantOutcome]], unit: list[VariantTask]) -> list[VariantOutcome]:
    """A finished unit's outcomes; a lost worker is a failure of its variants, a cancelled unit has none."""
    from concurrent.futures import CancelledError

    try:
        return future.result()
    except CancelledError:
        return []
    except Exception as err:  # e.g. a worker process killed by the OS
        return [_outcome(task.index, err) for task in unit]


def _dask_client(address: str) -> Any:
    """Connect to an existing Dask scheduler, with a clear message when that is not possible."""
    try:
        from distributed import Client
    except ImportError:
        raise UserError(
            "--scheduler needs the 'distributed' package: pip install 'rustycs[dask]'"
        ) from None
    # in a thread with a deadline: a scheduler that accepts the connection and never answers would
    # otherwise hang the handshake past Client's own timeout
    found: list[Any] = []

    def connect() -> None:
        try:
            found.append(Client(address, timeout=CONNECT_TIMEOUT))
        except (OSError, TimeoutError, ValueError) as err:
            found.append(err)

    thread = threading.Thread(target=connect, daemon=True)
    thread.start()
    thread.join(2 * CONNECT_TIMEOUT)
    if not found:
        raise UserError(f"cannot reach the Dask scheduler at {address}: no answer in {CONNECT_TIMEOUT:g} s")
    if isinstance(found[0], Exception):
        raise UserError(f"cannot reach the Dask scheduler at {address}: {found[0]}") from None
    return found[0]


@dataclass
class SweepResult:
    """The rows of a finished (or interrupted) sweep and the exit code they imply."""

    plan: SweepPlan
    outcomes: dict[int, VariantOutcome]
    interrupted: bool = False

    def failures(self) -> list[tuple[Variant, VariantOutcome]]:
        return [(v, self.outcomes[v.task.index]) for v in self.plan.variants
                if v.task.index in self.outcomes and self.outcomes[v.task.index].failed]

    @property
    def exit_code(self) -> int:
        if self.interrupted:
            return 130
        return 1 if self.failures() else 0

    def rows(self) -> list[dict[str, Any]]:
        """One row per variant: index, swept keys, status, output, skipped, error, then the summary."""
        rows = []
        for variant in self.plan.variants:
            outcome = self.outcomes.get(variant.task.index)
            row: dict[str, Any] = {"index": variant.task.index, **variant.parameters}
            row["status"] = outcome.status if outcome else "not run"
            row["output"] = str(variant.task.output)
            row["skipped"] = bool(outcome and outcome.skipped)
            row["error"] = outcome.error if outcome else None
            summary = summary_columns(outcome.summary) if outcome else {}
            for key, value in summary.items():
                row.setdefault(key, value)
            rows.append(row)
        return rows


def run_sweep(
    plan: SweepPlan,
    workers: int,
    scheduler: str | None = None,
    on_outcome: Callable[[Variant, VariantOutcome], None] | None = None,
    quiet: bool = False,
    local: str = "threads",
    allow_full_disk: bool = False,
    batch: int = BATCH,
) -> SweepResult:
    """Skip finished variants, run the others, write sweep.csv and sweep.json, and return the result.
    Variants whose trajectories together would not fit on the disk are refused before any runs, unless
    `allow_full_disk`. Variants of one size step together, `batch` at a time (`units`).

    `quiet` silences the one-line notice when the engine must first be compiled. Ctrl-C or SIGTERM
    stops the sweep: running variants end as interrupted (their frames kept), the
    tables are still written (variants that never started as "not run") and the result says
    interrupted.
    """
    from .output_files import check_free_space, writing_errors

    by_index = {variant.task.index: variant for variant in plan.variants}
    result = SweepResult(plan, {})
    pending = []
    for variant in plan.variants:
        outcome = finished_outcome(variant)
        if outcome is None:
            pending.append(variant)
        else:
            _record(result, by_index, outcome, on_outcome)
    if not allow_full_disk:
        needed = sum(variant.expected_bytes for variant in pending)
        check_free_space(plan.out_dir / "sweep.json", needed)
    plan.out_dir.mkdir(parents=True, exist_ok=True)
    try:
        if pending and scheduler is None:
            _compile_engine_once(quiet)
        with _terminate_as_interrupt():
            result.interrupted = dispatch(
                units(pending, workers, batch),
                lambda outcome: _record(result, by_index, outcome, on_outcome), workers, scheduler, local,
            )
    except KeyboardInterrupt:  # between two variants run in this process
        result.interrupted = True
    with writing_errors(plan.out_dir / "sweep.json"):
        write_tables(plan.out_dir, result.rows())
    return result


def _compile_engine_once(quiet: bool) -> None:
    """Compile the engine's kernels here, once, when the disk cache is cold: local workers then load
    them from the cache instead of each compiling them at the same time."""
    import rustycs

    from .simulation import announce_compile, warm_up

    if rustycs.compile_needed():
        if not quiet:
            announce_compile()
        warm_up()


@contextmanager
def _terminate_as_interrupt() -> Iterator[None]:
    """While active, SIGTERM stops the sweep the way Ctrl-C does (in the main thread only, where
    signals can be caught), so that a batch system's kill still leaves valid tables."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def interrupt(_signum: int, _frame: object) -> None:
        raise KeyboardInterrupt

    previous = signal.signal(signal.SIGTERM, interrupt)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def _record(
    result: SweepResult,
    by_index: dict[int, Variant],
    outcome: VariantOutcome,
    on_outcome: Callable[[Variant, VariantOutcome], None] | None,
) -> None:
    result.outcomes[outcome.index] = outcome
    if on_outcome is not None:
        on_outcome(by_index[outcome.index], outcome)


def write_tables(out_dir: Path, rows: list[dict[str, Any]]) -> None:
    """sweep.json (a list of rows, typed, strict JSON) and sweep.csv (same columns), each atomic."""
    import csv
    import io

    from .summary import to_json, write_text_atomic

    text = to_json(rows)
    write_text_atomic(out_dir / "sweep.json", text + "\n")
    clean = json.loads(text)
    columns = list(dict.fromkeys(key for row in clean for key in row))
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=columns, lineterminator="\n")
    writer.writeheader()
    for row in clean:
        writer.writerow({key: _csv_cell(row.get(key)) for key in columns})
    write_text_atomic(out_dir / "sweep.csv", buffer.getvalue())


def _csv_cell(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (list, dict)):
        return json.dumps(value)
    return str(value)


def default_workers() -> int:
    return os.cpu_count() or 1
