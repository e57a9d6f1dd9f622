"""A world's stepping state in one compiled object, so that a call from Python costs little.

The step takes a world's records (bodies, shapes, joints, forces, the scenario), its settings, its
buffers (the workspace), the frame buffer it records into and the status of the block. Passed from
Python one by one, numba unboxes each of their ~200 arrays on every call: 5 of the 9 us of a five-body
world's `World.step(1)`. A `Stepper` (a numba structref) holds them all and unboxes as one pointer; it is
made again whenever the world's make-up, settings or frame buffer change, and holds the workspace as
the step grows it (`rustycs.step.step_world`; `step_worlds` steps many worlds, `rustycs.batch`).

The entry reads the stepper's fields without counting references (`borrowed`) and is compiled without
reference counting like the tick: numba's field reads counted a reference to each of the ~200 arrays,
in and out, 2.5 us of every call.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit, types
from numba.core import cgutils
from numba.core.runtime.nrtdynmod import _meminfo_struct_type
from numba.experimental import structref
from numba.extending import intrinsic
from numba.typed import List


@structref.register
class StepperType(types.StructRef):
    def preprocess_fields(self, fields):
        return tuple((name, types.unliteral(typ)) for name, typ in fields)


class Stepper(structref.StructRefProxy):
    """What a world's step takes (`rustycs.step.step_world`): records, settings, workspace, the frame
    buffer's arrays (a tuple in `recording.FRAME_FIELDS` order), the status of the last block and the
    world's clock."""


class StepperFields(NamedTuple):
    """A stepper's fields, as `borrowed` reads them."""

    bodies: tuple
    shapes: tuple
    joints: tuple
    joint_filter: tuple
    forces: tuple
    settings: tuple
    workspace: tuple
    scenario: tuple
    frames: tuple
    status: np.ndarray  # (STATUS_FIELDS,) of the last block
    clock: np.ndarray  # (CLOCK_FIELDS,) int64: ticks done, bodies escaped, since the world was made


# entries of a stepper's clock
TICK, ESCAPED_TOTAL = range(2)
CLOCK_FIELDS = 2


structref.define_proxy(Stepper, StepperType, list(StepperFields._fields))


@njit(cache=True)
def new_stepper(bodies, shapes, joints, joint_filter, forces, settings, workspace, scenario, frames, status,
                clock):
    """A stepper of these records (the arrays are shared, not copied)."""
    return Stepper(bodies, shapes, joints, joint_filter, forces, settings, workspace, scenario, frames,
                   status, clock)


@intrinsic
def borrowed(typingctx, stepper):
    """The stepper's fields as a tuple, read without counting references: for kernels compiled without
    reference counting, while the stepper (held by Python) keeps them alive. The data pointer is read
    from the structref's memory info as numba's own `NRT_MemInfo_data_fast` does."""
    names = StepperFields._fields
    result = types.NamedTuple([stepper.field_dict[name] for name in names], StepperFields)

    def codegen(context, builder, signature, args):
        payload_type = signature.args[0].get_data_type()
        meminfo = cgutils.create_struct_proxy(signature.args[0])(context, builder, value=args[0]).meminfo
        info = builder.bitcast(meminfo, _meminfo_struct_type.as_pointer())
        data = builder.load(cgutils.gep(builder, info, 0, 3))
        payload = cgutils.create_struct_proxy(payload_type)(
            context, builder, ref=builder.bitcast(data, context.get_value_type(payload_type).as_pointer()))
        return context.make_tuple(builder, signature.return_type, [getattr(payload, name) for name in names])

    return result(stepper), codegen


@njit(cache=True)
def workspace_of(stepper):
    """The stepper's workspace (after `step_world` grew it)."""
    return stepper.workspace


@njit(cache=True)
def stepper_list(first):
    """A typed list holding `first`, for `step_worlds`. Made in compiled code, which is cached: numba's
    own `List.append` from Python compiles for a new item type in every process (0.22 s)."""
    steppers = List()
    steppers.append(first)
    return steppers


@njit(cache=True)
def add_stepper(steppers, stepper):
    """Append to a list of `stepper_list`, in cached compiled code."""
    steppers.append(stepper)
