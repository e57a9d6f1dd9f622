"""Keep numba's on-disk kernel cache consistent with the engine's sources.

numba invalidates a cached kernel only when the file defining it changes, not when a kernel it calls
(in another module) does. So the cache is stamped with a hash of every engine source file, and a
stale cache is cleared before the kernels are loaded.
"""

from __future__ import annotations

import glob
import hashlib
import os

_HERE = os.path.dirname(os.path.abspath(__file__))
_STAMP = "rustycs-sources.sha256"


def _cache_dirs() -> list[str]:
    dirs = [os.path.join(_HERE, "__pycache__")]
    custom = os.environ.get("NUMBA_CACHE_DIR")
    if custom:
        dirs.append(custom)
    return dirs


def sources_hash() -> str:
    digest = hashlib.sha256()
    for path in sorted(glob.glob(os.path.join(_HERE, "*.py"))):
        with open(path, "rb") as f:
            digest.update(os.path.basename(path).encode() + b"\0" + f.read())
    return digest.hexdigest()


def _kernel_files(directory: str) -> list[str]:
    modules = _modules()
    found = []
    for ext in ("nbi", "nbc"):
        for path in glob.glob(os.path.join(directory, "**", f"*.{ext}"), recursive=True):
            if os.path.basename(path).split(".")[0] in modules:
                found.append(path)
    return found


def _modules() -> set[str]:
    return {os.path.splitext(os.path.basename(p))[0] for p in glob.glob(os.path.join(_HERE, "*.py"))}


_checked = False


def ensure_fresh() -> None:
    """Remove cached kernels compiled from other engine sources than the present ones (once per
    process: the sources do not change under a running program)."""
    global _checked
    if _checked:
        return
    _checked = True
    current = sources_hash()
    for directory in _cache_dirs():
        stamp = os.path.join(directory, _STAMP)
        try:
            with open(stamp) as f:
                if f.read().strip() == current:
                    continue
        except OSError:
            pass
        try:
            for path in _kernel_files(directory):
                os.remove(path)
            os.makedirs(directory, exist_ok=True)
            with open(stamp, "w") as f:
                f.write(current)
        except OSError:
            pass  # a read-only install: numba falls back to its own checks


def compile_needed() -> bool:
    """True when the compiled kernels are not yet cached (the first step will compile)."""
    ensure_fresh()
    return not any(glob.glob(os.path.join(d, "**", "step.run_ticks-*.nbi"), recursive=True)
                   for d in _cache_dirs())
