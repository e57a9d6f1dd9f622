"""Where outputs may be written, and writing them so that nothing is replaced that should not be.

An output is always written under a temporary name in its folder and renamed when complete, so the
rename must never land on something that is not a plain file: `--out /dev/null` must not replace the
device. Names taken from a scene (its name makes `outputs/<name>.h5`) stay inside their folder. One run
at a time writes an output (a lock next to it), and the temporaries left by processes that died (SIGKILL,
an OOM kill) are removed or recovered by the next run in that folder. A run that would not fit on the disk
is refused before it starts.
"""

from __future__ import annotations

import errno
import fcntl
import os
import re
import shutil
import stat
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from . import limits
from .errors import UserError

TRAJECTORY_SUFFIX = ".h5"
TEMPORARY_NAME = re.compile(r"^\.(?P<name>.+)\.tmp-(?P<pid>\d+)$")


def refuse_special(path: Path) -> None:
    """UserError when `path` exists and is neither a regular file nor a symbolic link (a device such as
    /dev/null, a pipe, a socket): renaming an output over it would destroy it."""
    try:
        mode = os.lstat(path).st_mode
    except FileNotFoundError:
        return
    except OSError as err:
        raise UserError(f"{path}: cannot use as an output ({err.strerror or err})") from None
    if stat.S_ISDIR(mode):
        raise UserError(f"{path}: is a folder; give a file name such as {path / 'run.h5'}")
    if not (stat.S_ISREG(mode) or stat.S_ISLNK(mode)):
        raise UserError(f"{path}: exists and is not a regular file (a device, pipe or socket); "
                        "refusing to replace it: give a file name")


def check_trajectory_output(path: Path, option: str = "--out") -> None:
    """Fail early (before simulating) when a trajectory cannot be written at `path`: a name not ending in
    .h5 (`--out scene.yaml` would overwrite the scene), something other than a file there, or a missing
    or read-only folder. A folder without any write permission bit counts as read-only even for root."""
    from .summary import sidecar_path

    refuse_special(path)
    if path.suffix.lower() != TRAJECTORY_SUFFIX:
        raise UserError(f"{option} {path}: a trajectory file name must end in {TRAJECTORY_SUFFIX}")
    refuse_special(sidecar_path(path))
    folder = path.parent
    if not folder.is_dir():
        raise UserError(f"{path}: output folder {folder} does not exist")
    if not os.access(folder, os.W_OK | os.X_OK) or not folder.stat().st_mode & 0o222:
        raise UserError(f"{path}: output folder {folder} is not writable")


def inside(folder: Path, name: str, suffix: str = "") -> Path:
    """folder/<name><suffix>, refusing a name that would leave the folder (validated scene names never do;
    this guards every other way a name reaches a path)."""
    if not name or "/" in name or "\\" in name or "\0" in name or name in (".", ".."):
        raise UserError(f"{name!r}: cannot be used as a file name (it would leave {folder})")
    return folder / f"{name}{suffix}"


def check_output_folder(path: Path, option: str = "--out") -> None:
    """A folder for many outputs (a sweep's): it may exist as a folder, not as anything else."""
    if path.exists() and not path.is_dir():
        raise UserError(f"{option} {path}: exists and is not a folder; give a folder for the outputs")


@contextmanager
def output_lock(path: Path) -> Iterator[None]:
    """Hold the lock of output `path` (a hidden `.NAME.lock` next to it) for the block; UserError when
    another process holds it, so two runs never write one output and its sidecar at once."""
    lock = path.with_name(f".{path.name}.lock")
    while True:
        try:
            handle = os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)
        except OSError as err:
            raise UserError(f"{path}: cannot lock the output ({err.strerror or err})") from None
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as err:
            os.close(handle)
            if err.errno in (errno.EAGAIN, errno.EACCES):
                raise UserError(f"{path}: another rustycs process is writing this output; "
                                "wait for it or choose another --out") from None
            raise
        try:  # the lock file may have been removed by its last holder between our open and lock
            if os.fstat(handle).st_ino == os.stat(lock).st_ino:
                break
        except FileNotFoundError:
            pass
        os.close(handle)
    try:
        yield
    finally:
        lock.unlink(missing_ok=True)
        os.close(handle)


def stale_temporaries(folder: Path, of: str | None = None) -> list[Path]:
    """Temporary outputs (`.NAME.tmp-PID`) in `folder` whose process no longer exists (only those of
    output NAME `of` when given)."""
    found = []
    try:
        entries = list(folder.iterdir())
    except OSError:
        return []
    for entry in entries:
        match = TEMPORARY_NAME.match(entry.name)
        if match and (of is None or match["name"] == of) and not _alive(int(match["pid"])):
            found.append(entry)
    return found


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OverflowError):
        return True
    return True


def check_free_space(path: Path, needed: int) -> None:
    """UserError when the disk holding `path` has less free space than `needed` bytes plus a margin,
    naming both (`--allow-full-disk` skips the check)."""
    folder = path.parent
    while not folder.exists() and folder != folder.parent:  # an output folder not made yet
        folder = folder.parent
    try:
        free = shutil.disk_usage(folder).free
    except OSError:
        return
    if needed + limits.DISK_MARGIN_BYTES > free:
        raise UserError(
            f"{path}: the run would write about {_size(needed)} but only {_size(free)} is free on that "
            "disk; record fewer frames (--every N), fewer ticks, or pass --allow-full-disk to try anyway"
        )


def _size(count: float) -> str:
    for unit in ("bytes", "KB", "MB", "GB", "TB"):
        if count < 1000 or unit == "TB":
            return f"{count:.0f} {unit}" if unit == "bytes" else f"{count:.1f} {unit}"
        count /= 1000
    raise AssertionError  # pragma: no cover


def estimated_bytes(bodies: int, ticks: int, every: int) -> int:
    """About how large a trajectory of `bodies` bodies recorded every `every` ticks gets (without
    contacts, uncompressed)."""
    import numpy as np

    from .trajectory import FRAME_SERIES, OBSERVABLES

    def row_bytes(table: dict[str, tuple[tuple[int, ...], str, str | None]]) -> int:
        return sum(int(np.prod(shape)) * np.dtype(dtype).itemsize for shape, dtype, _ in table.values())

    frames = ticks // every + 2
    return frames * (bodies * row_bytes(FRAME_SERIES) + row_bytes(OBSERVABLES) + 16) + 1_000_000


@contextmanager
def writing_errors(path: Path) -> Iterator[None]:
    """Turn a failed write (disk full, quota, I/O error) into one message, exit code 1; the writers
    have removed their temporary files by then (an earlier file of that name is kept)."""
    try:
        yield
    except OSError as err:
        if isinstance(err, FileNotFoundError | PermissionError | IsADirectoryError):
            raise
        text = str(err)
        full = err.errno in (errno.ENOSPC, errno.EDQUOT) or "No space left" in text or "errno = 28" in text
        reason = "the disk is full" if full else (err.strerror or str(err))
        raise UserError(f"{path}: cannot write the output: {reason} (no partial file was left)",
                        exit_code=1) from None
