"""How the engine's code is compiled: the kernels, and the helpers inlined into them.

numba counts references to every array a compiled function receives or slices: an atomic increment and
decrement per array argument and view, per call. The per-tick kernels only read and write buffers the
step owns for the whole block, so they are compiled without reference counting (numba's `_nrt=False`
option). That took the narrow phase of the 600-polygon benchmark scene from 210 to 145 us per tick.
A tick kernel must not allocate, and must not return an array.

A helper called inside the kernels' loops (a collision routine, a constraint row) is `inlined`: compiled
once for each signature on its own, and marked for LLVM to inline into every caller when that caller is
optimised. numba's own inlining (`inline="always"`) copies the helper's untyped code, and that of every
helper inlined into it, again at every call site: with the collision routines inlined into the narrow
phase, the sweeps, the sensors and the queries, the engine's first compile took 350 s on this 2-core
machine, 245 s of it copying code for two kernels. Inlined by LLVM it takes about 100 s, and every
trajectory is bitwise the same (the same operations in the same order).

The contact solver's lane loops are the exception (`inlined_early`): inlined by LLVM, each loop over the
lanes was vectorised on its own, for any point count and pass, before its caller was, and the substeps of
the 210-box pyramid took 102 instead of 93 us a tick. Inlined by numba, the substeps are one function
before LLVM first sees them (12 s more compiling).
"""

from __future__ import annotations

from numba import njit, types
from numba.core import cgutils
from numba.extending import intrinsic
from numba.np.arrayobj import make_array, populate_array


def tick_kernel(function):
    """Compile `function` (cached on disk) without reference counting."""
    return njit(cache=True, _nrt=False)(function)


def inlined(function):
    """Compile `function` (cached on disk) without reference counting, to be inlined by LLVM into every
    compiled caller. It must not allocate."""
    return njit(cache=True, forceinline=True, _nrt=False)(function)


def stage(function):
    """Compile `function` (cached on disk) without reference counting, to be inlined by LLVM into the
    tick loop (`rustycs.step.step_world`), its one compiled caller."""
    return njit(cache=True, forceinline=True, _nrt=False)(function)


def parallel_kernel(function):
    """Compile `function` (cached on disk) without reference counting, its `prange` loops run by numba's
    threads (`rustycs.threads`)."""
    return njit(cache=True, parallel=True, _nrt=False)(function)


def inlined_early(function):
    """Compile `function` into each caller's own code before LLVM optimises it (numba's inlining)."""
    return njit(cache=True, inline="always")(function)


def stack_buffer(size: int):
    """A compiled function that returns an array of `size` float64 on its caller's stack. LLVM knows such
    an array shares memory with no array argument, so a loop that reads the step's buffers and writes it
    is vectorised; one that writes a second array argument is not (LLVM cannot tell the two apart, and
    gave up on the contact solver's lane loop)."""
    array = types.Array(types.float64, 1, "C")

    @intrinsic
    def buffer(typingctx):
        def codegen(context, builder, signature, args):
            length = context.get_constant(types.intp, size)
            item = context.get_constant(types.intp, 8)
            out = make_array(array)(context, builder)
            data = cgutils.alloca_once(builder, context.get_value_type(types.float64), size=length)
            populate_array(out, data=data, shape=[length], strides=[item], itemsize=item, meminfo=None)
            return out._getvalue()

        return array(), codegen

    return buffer
