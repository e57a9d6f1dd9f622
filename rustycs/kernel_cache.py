"""Keep numba's on-disk kernel cache consistent with the engine's sources.

numba invalidates a cached kernel only when the file defining it changes, not when a kernel it calls
(in another module) does. So the cache is stamped with a hash of the engine's source files that compiled
code can see (those defining kernels and every module they import: constants are compiled in), and a
stale cache is cleared before the kernels are loaded. The Python-only layer (the World, body control)
is left out: a change there compiles nothing again (a full compile takes minutes).
"""

from __future__ import annotations

import glob
import hashlib
import os
import re

_HERE = os.path.dirname(os.path.abspath(__file__))
_STAMP = "rustycs-sources.sha256"


def _cache_dirs() -> list[str]:
    dirs = [os.path.join(_HERE, "__pycache__")]
    custom = os.environ.get("NUMBA_CACHE_DIR")
    if custom:
        dirs.append(custom)
    return dirs


_IMPORT = re.compile(
    r"^(?:from rustycs\.(\w+) import|import rustycs\.(\w+)|from rustycs import \(?([\w ,\n]+))", re.MULTILINE)
_KERNEL = re.compile(r"@(?:njit|tick_kernel|inlined\w*)\b|\bnjit\(")


def _compiled_sources() -> dict[str, bytes]:
    """The engine's modules that compiled code depends on: those defining kernels, and what they import."""
    sources = {}
    for path in glob.glob(os.path.join(_HERE, "*.py")):
        with open(path, "rb") as f:
            sources[os.path.splitext(os.path.basename(path))[0]] = f.read()
    imports = {}
    for name, text in sources.items():
        found = set()
        for match in _IMPORT.finditer(text.decode()):
            found.update(match.group(1, 2))
            found.update(n.strip() for n in (match.group(3) or "").split(","))
        imports[name] = found & sources.keys()
    needed = {name for name, text in sources.items() if _KERNEL.search(text.decode())}
    todo = list(needed)
    while todo:
        for name in imports[todo.pop()] - needed:
            needed.add(name)
            todo.append(name)
    return {name: sources[name] for name in needed}


def sources_hash() -> str:
    digest = hashlib.sha256()
    for name, text in sorted(_compiled_sources().items()):
        digest.update(name.encode() + b"\0" + text)
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
    return not any(glob.glob(os.path.join(d, "**", "step.step_world-*.nbi"), recursive=True)
                   for d in _cache_dirs())


def compiled_entry(kernel, args: tuple):
    """The compiled entry of the numba `kernel` for the types of `args`, to call with arguments of exactly
    those types; call the kernel through its dispatcher with `args` first (that compiles or loads it).

    A kernel called through its dispatcher types every argument on every call: for the step's, whose
    records hold about 200 arrays, that took 29 of the 33 us of a five-body world's `World.step(1)`; its
    entry takes the arrays as they come (2.8 us). With one compiled signature, the dispatcher just chose
    it; else the arguments are typed once here (1.7 ms for the step's)."""
    if len(kernel.overloads) == 1:
        return next(iter(kernel.overloads.values())).entry_point
    return kernel.compile(tuple(kernel.typeof_pyval(arg) for arg in args))
