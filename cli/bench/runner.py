"""Each measurement in its own fresh process, so that runs cannot disturb each other (heap, caches,
JIT state): the worker prints one JSON line, which is parsed here."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path
from typing import Any


def run_worker(args: list[str], env: dict[str, str] | None = None) -> dict[str, Any]:
    """The worker's JSON result, or {"error": message} when it failed."""
    done = subprocess.run([sys.executable, "-m", "rustycs_cli.bench.worker", *args], capture_output=True,
                          text=True, env=env)
    lines = done.stdout.strip().splitlines()
    if done.returncode != 0 or not lines:
        problem = done.stderr.strip().splitlines()[-1:] or [f"exit code {done.returncode}"]
        return {"error": problem[0]}
    return json.loads(lines[-1])


def measure_steps(engine: str, scene: str, max_ticks: int | None, block: int, metrics: tuple[str, ...],
                  sleep: bool, threads: int) -> dict[str, Any]:
    """Stepping time and quality of `scene` (a file or `scaling:N`) in `engine`."""
    args = ["step", engine, scene, "--block", str(block), "--metrics", ",".join(metrics)]
    if max_ticks is not None:
        args += ["--max-ticks", str(max_ticks)]
    return run_worker(args + _settings(sleep, threads))


def measure_recording(scene: str, max_ticks: int | None, sleep: bool, threads: int) -> dict[str, Any]:
    """Time of `rustycs run` on `scene` recording every tick, and the worker's peak memory."""
    ticks = [] if max_ticks is None else ["--max-ticks", str(max_ticks)]
    return run_worker(["record", scene, *ticks, *_settings(sleep, threads)])


def _settings(sleep: bool, threads: int) -> list[str]:
    """The worker's options for sleeping and threads."""
    return ["--threads", str(threads)] + (["--sleep"] if sleep else [])


def measure_first_step(cache_dir: Path) -> dict[str, Any]:
    """Import and first-step time with numba's kernel cache in `cache_dir`: cold when it is empty,
    warm once a previous measurement has filled it."""
    return run_worker(["first-step"], env={**os.environ, "NUMBA_CACHE_DIR": str(cache_dir)})


def startup_command() -> list[str]:
    """`rustycs --help` through the installed console script (next to this Python, else on PATH)."""
    script = Path(sys.executable).parent / "rustycs"
    found = str(script) if script.exists() else shutil.which("rustycs")
    if found:
        return [found, "--help"]
    return [sys.executable, "-c", "from rustycs_cli.app import main; main()", "--help"]


def measure_startup() -> float:
    """Wall time of `rustycs --help`, s: what every command pays before doing anything."""
    command = startup_command()
    began = time.perf_counter()
    subprocess.run(command, capture_output=True, check=True)
    return time.perf_counter() - began
