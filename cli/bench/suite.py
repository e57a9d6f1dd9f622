"""The whole benchmark: compile and start-up times, the scenes S1..S6 in every engine, the scaling
series; repetitions interleaved (rep by rep, engine by engine) so that slow phases of a noisy machine
hit every engine alike. Results are a plain dict, ready for JSON and the report."""

from __future__ import annotations

import dataclasses
import os
import platform
import statistics
import subprocess
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from . import runner
from .quality import METRICS
from .scenes import SCALING_SIZES, SCALING_TICKS, scaling_ref

RECORDED_SCENE = "S4"  # the yardstick: recording every tick of S4 costs at most 20 %


@dataclass(frozen=True)
class Plan:
    """What to measure."""

    scenes: dict[str, Path]  # id -> scene file
    engines: tuple[str, ...]  # "rustycs" first, then the peers
    reps: int
    max_ticks: int | None
    block: int
    compile: bool
    scaling: bool
    recording: bool
    sleep: bool  # bodies at rest sleep, in every engine
    threads: int  # threads inside one world, in every engine that has them
    command: str


def run(plan: Plan, progress: Callable[[str], None]) -> dict[str, Any]:
    """Measure everything in `plan`; `progress` gets one line per measurement."""
    began = time.time()
    result: dict[str, Any] = {"meta": _meta(plan)}
    if plan.compile:
        result["compile"] = _compile_times(plan.reps, progress)
    result["scenes"] = _series(plan, [(sid, str(path), METRICS[sid]) for sid, path in plan.scenes.items()],
                               progress)
    if plan.recording and RECORDED_SCENE in plan.scenes:
        result["recording"] = _recording(plan, result["scenes"][RECORDED_SCENE], progress)
    if plan.scaling:
        refs = [(str(n), scaling_ref(n), METRICS["scaling"]) for n in SCALING_SIZES]
        limited = plan.max_ticks if plan.max_ticks is not None else SCALING_TICKS
        result["scaling"] = _series(dataclasses.replace(plan, max_ticks=limited), refs, progress)
    result["meta"]["wall_s"] = round(time.time() - began, 1)
    result["meta"]["load_average_end"] = os.getloadavg()  # other work on the machine: a noise indicator
    return result


def failures(result: dict[str, Any]) -> list[str]:
    """One line per measurement that did not complete."""
    out = [f"recording {error}" for error in result.get("recording", {}).get("errors", [])]
    out += [f"compile {error}" for error in result.get("compile", {}).get("errors", [])]
    for series in ("scenes", "scaling"):
        for key, row in result.get(series, {}).items():
            for engine, cell in row["engines"].items():
                out.extend(f"{key} {engine}: {error}" for error in cell["errors"])
    return out


def _series(plan: Plan, items: list[tuple[str, str, tuple[str, ...]]],
            progress: Callable[[str], None]) -> dict[str, Any]:
    rows: dict[str, Any] = {}
    for rep in range(plan.reps):
        for key, ref, metrics in items:
            row = rows.setdefault(key, {"engines": {}})
            for engine in plan.engines:
                run = runner.measure_steps(engine, ref, plan.max_ticks, plan.block, metrics, plan.sleep,
                                           plan.threads)
                cell = row["engines"].setdefault(engine, {"ms_per_tick": [], "errors": []})
                if "error" in run:
                    cell["errors"].append(run["error"])
                    progress(f"rep {rep + 1} {key:5} {engine:8} failed: {run['error']}")
                    continue
                cell["ms_per_tick"].append(run["ms_per_tick"])
                cell.setdefault("kb_per_body", []).append(run["kb_per_body"])
                cell.setdefault("quality", run["quality"])
                cell.update(sleep=run["sleep"], threads=run["threads"])  # as the engine's world reports them
                row.update(name=run["scene"], bodies=run["bodies"], ticks=run["ticks"])
                progress(f"rep {rep + 1} {key:5} {engine:8} {run['ms_per_tick']:9.4f} ms/tick")
    for row in rows.values():
        for cell in row["engines"].values():
            times = cell["ms_per_tick"]
            cell["median_ms"] = statistics.median(times) if times else None
            cell["min_ms"] = min(times) if times else None
            cell["median_kb_per_body"] = statistics.median(cell["kb_per_body"]) if times else None
        own = row["engines"].get("rustycs", {}).get("median_ms")
        row["ratios"] = {engine: own / cell["median_ms"] for engine, cell in row["engines"].items()
                         if engine != "rustycs" and own is not None and cell["median_ms"]}
    return rows


def _recording(plan: Plan, row: dict[str, Any], progress: Callable[[str], None]) -> dict[str, Any]:
    """`rustycs run` of the recorded scene (every tick to HDF5) against its stepping-only time."""
    scene = str(plan.scenes[RECORDED_SCENE])
    runs = [runner.measure_recording(scene, plan.max_ticks, plan.sleep, plan.threads)
            for _ in range(plan.reps)]
    ok = [r for r in runs if "error" not in r]
    for r in runs:
        progress(f"record {RECORDED_SCENE}: {r.get('error') or format(r['ms_per_tick'], '.4f') + ' ms/tick'}")
    median = statistics.median(r["ms_per_tick"] for r in ok) if ok else None
    stepping = row["engines"]["rustycs"]["median_ms"]
    return {
        "scene": RECORDED_SCENE, "name": row.get("name"), "ticks": row.get("ticks"),
        "ms_per_tick": [r["ms_per_tick"] for r in ok], "median_ms": median, "stepping_median_ms": stepping,
        "overhead": median / stepping - 1.0 if median is not None and stepping else None,
        "peak_memory_mb": max((r["peak_memory_mb"] for r in ok), default=None),
        "errors": [r["error"] for r in runs if "error" in r],
    }


def _compile_times(reps: int, progress: Callable[[str], None]) -> dict[str, Any]:
    """Cold: first step with an empty kernel cache (once, it takes a while); warm: with the cache that
    run filled; start-up: `rustycs --help`."""
    with tempfile.TemporaryDirectory(prefix="rustycs-bench-cache-") as cache:
        cold = runner.measure_first_step(Path(cache))
        progress(f"compile cold: {cold.get('error') or format(cold['first_step_s'], '.1f') + ' s'}")
        warm = [runner.measure_first_step(Path(cache)) for _ in range(reps)]
    startup = [runner.measure_startup() for _ in range(max(reps, 3))]
    progress(f"start-up: {statistics.median(startup):.3f} s")
    ok = [w for w in warm if "error" not in w]
    errors = [r["error"] for r in (cold, *warm) if "error" in r]
    return {
        "cold_s": cold.get("first_step_s"),
        "warm_s": statistics.median(w["first_step_s"] for w in ok) if ok else None,
        "import_s": statistics.median(w["import_s"] for w in ok) if ok else None,
        "startup_s": statistics.median(startup),
        "errors": errors,
    }


def _meta(plan: Plan) -> dict[str, Any]:
    import rustycs

    from . import peers

    versions = {"rustycs": rustycs.__version__, "commit": _git_commit()}
    if len(plan.engines) > 1:
        versions.update(peers.versions())
    peer_settings = {e: peers.describe_settings(e, plan.sleep, plan.threads)
                     for e in plan.engines if e != "rustycs"}
    return {
        "date": time.strftime("%Y-%m-%d %H:%M:%S %Z"), "cpu": _cpu_model(), "cores": os.cpu_count(),
        "platform": platform.platform(), "python": platform.python_version(), "command": plan.command,
        "load_average_start": os.getloadavg(), "reps": plan.reps, "max_ticks": plan.max_ticks,
        "block": plan.block, "versions": versions,
        "settings": {"sleep": plan.sleep, "threads": plan.threads,
                     "engines": {"rustycs": _rustycs_settings(plan.sleep, plan.threads), **peer_settings}},
    }


def _rustycs_settings(sleep: bool, threads: int) -> str:
    """What rustycs runs with (as `peers.describe_settings` for the peers)."""
    import numba

    from .peers import SLEEP_TIME

    napping = f"sleeping on ({SLEEP_TIME} s at rest)" if sleep else "sleeping off"
    stepping = "single-threaded" if threads == 1 else f"world.threads {threads}"
    if threads > numba.config.NUMBA_NUM_THREADS:
        stepping += f" (numba runs {numba.config.NUMBA_NUM_THREADS})"
    return f"substeps as the scene's world.precision, {napping}, {stepping}"


def _cpu_model() -> str:
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
    except OSError:
        out = ""
    for line in out.splitlines():
        if line.startswith("Model name:"):
            return line.split(":", 1)[1].strip()
    return platform.processor() or "unknown"


def _git_commit() -> str | None:
    """The commit of the measured engine, when it runs from a git checkout."""
    try:
        done = subprocess.run(["git", "describe", "--always", "--dirty"], capture_output=True, text=True,
                              cwd=Path(__file__).resolve().parent)
    except OSError:
        return None
    return done.stdout.strip() or None
