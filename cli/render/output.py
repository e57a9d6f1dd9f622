"""Atomic output files: written under a temporary name in the target folder, renamed when complete."""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from ..errors import UserError
from ..output_files import refuse_special


def check_suffix(out: Path, formats: tuple[str, ...], kind: str) -> str:
    """OUT's suffix (lower case) when it is one of `formats`, else UserError naming the choices."""
    suffix = out.suffix.lower()
    if suffix not in formats:
        raise UserError(
            f"{out}: unknown {kind} type {suffix or '(no suffix)'!r}; use one of {', '.join(formats)}"
        )
    return suffix


@contextmanager
def atomic_output(target: str | Path) -> Iterator[Path]:
    """Yield a temporary path next to `target` (same suffix, so writers pick the right format);
    rename it to `target` when the block succeeds and delete it otherwise, so a failed or interrupted
    render never leaves a half-written file under the final name."""
    target = Path(target)
    refuse_special(target)
    folder = target.parent
    try:
        folder.mkdir(parents=True, exist_ok=True)
        handle, name = tempfile.mkstemp(prefix=f".{target.stem}.", suffix=f".tmp{target.suffix}", dir=folder)
    except OSError as err:
        raise UserError(f"{target}: cannot write here ({err.strerror or err})") from None
    os.close(handle)
    temporary = Path(name)
    try:
        yield temporary
        os.chmod(temporary, 0o666 & ~_umask())  # mkstemp made it private; give it a normal file's mode
        os.replace(temporary, target)
    finally:
        temporary.unlink(missing_ok=True)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
