"""The solver's substeps, group after group of the schedule's islands (`contact_batches`).

Each substep integrates velocities, warm starts, solves the contacts with the soft bias, integrates
positions and relaxes (the joints before the contacts in each pass). A group shares no moving body with
another, so all the substeps of one group run before the next, or, with threads, groups run side by side:
every body meets the same passes in the same order, and the result is bitwise that of one thread.
"""

from __future__ import annotations

from rustycs.compiling import stage
from rustycs.contact_solver import (
    exchange_warm_velocities,
    keep_free_velocities,
    solve,
    warm_start,
    warm_start_again,
)
from rustycs.joint_solver import RELAX, SOLVE, WARM, joints_pass
from rustycs.motion import integrate_positions, integrate_velocities


@stage
def group_substeps(g, batches, lanes, body, bodies, joints, joint_work, joint_soft, forces, h, count, soft,
                   stiff, direct):
    """All `count` substeps of group g of `batches`, with contact softness `soft`, `stiff` against an
    immovable body; `direct`: g is the one group, of every body in id order (`contact_solver.group_body`).
    The joints, if any, are in the one group of every body. One compiled function with every pass inlined:
    a call per pass cost a quarter of the tick of a five-body scene."""
    jointed = joints.kind.shape[0] > 0  # a call with the records costs a tenth of a five-body tick
    order = batches.body_order
    first, last = batches.group_bodies[g], batches.group_bodies[g + 1]
    chunks, chunks_end = batches.group_chunks[g], batches.group_chunks[g + 1]
    for substep in range(count):
        if substep > 0:
            exchange_warm_velocities(body, order, first, last, direct)
        integrate_velocities(body, bodies, forces, h, order, first, last, direct)
        if jointed:
            joints_pass(WARM, bodies, body, joints, joint_work, joint_soft, h)
        if substep == 0:
            keep_free_velocities(body, order, first, last, direct)
            warm_start(batches, chunks, chunks_end, lanes, body)
        else:
            warm_start_again(body, order, first, last, direct)
        if jointed:
            exchange_warm_velocities(body, order, first, last, direct)
            joints_pass(SOLVE, bodies, body, joints, joint_work, joint_soft, h)
            exchange_warm_velocities(body, order, first, last, direct)
        solve(batches, chunks, chunks_end, lanes, body, 1.0 / h, True, soft, stiff)
        integrate_positions(body, bodies, h, order, first, last, direct)
        if jointed:
            exchange_warm_velocities(body, order, first, last, direct)
            joints_pass(RELAX, bodies, body, joints, joint_work, joint_soft, h)
            exchange_warm_velocities(body, order, first, last, direct)
        solve(batches, chunks, chunks_end, lanes, body, 1.0 / h, False, soft, stiff)


@stage
def substeps(batches, lanes, body, bodies, joints, joint_work, joint_soft, forces, h, count, soft, stiff):
    """The substeps of every group, one group after the other (`group_substeps`). The one group of a small
    world is a call of its own, its bodies' order known at compile time: through the order S6's 200 orbits
    took 9 % longer a tick."""
    if batches.last[2] == 1:
        group_substeps(0, batches, lanes, body, bodies, joints, joint_work, joint_soft, forces, h, count,
                       soft, stiff, True)
        return
    for g in range(batches.last[2]):
        group_substeps(g, batches, lanes, body, bodies, joints, joint_work, joint_soft, forces, h, count,
                       soft, stiff, False)
