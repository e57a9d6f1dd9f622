"""Impacts: restitution, and the friction of an impact, after the soft step.

The soft step stops every approach: its contacts do not bounce. Afterwards the contacts it stopped get
the normal speeds they should leave at (`bounce_targets`), and passes of `restitute` and `impact_friction`
set them, until the speeds settle.

The targets come from the velocities before the soft step, resolved as a sequence of collisions, one
contact at a time: a contact that closes reflects its approach speed times its restitution, which may
make the next contact close, and so on, pass after pass, until none closes. A ball hitting a row of
touching balls so hands its speed down the row (Newton's cradle: 0, 0, 0, 0, 1) where solving the
contacts at once shares it (-0.47, 0, 0.48, 0.49, 0.49 at 4 substeps). The two points of a manifold
are resolved together (`contact_solver.two_point_lcp`), so that a box falling flat bounces straight
rather than turning on the corner solved first.

Friction during the soft step is limited by the impulse that stopped the approach; the bounce adds more
normal impulse, and `impact_friction` lets friction use it: a disc hitting a slope leaves rolling. The
impulses of a bounce are not kept for the next tick's warm start (the solver's were stored before): a
bounce warm-starting the next tick would push a row of resting balls apart again.
"""

from __future__ import annotations

from rustycs.compiling import inlined, stage
from rustycs.constants import BOUNCE_PASSES, BOUNCE_SPEED_TOLERANCE
from rustycs.contact_solver import (
    L_E,
    L_IA,
    L_IB,
    L_MA,
    L_MB,
    L_MU,
    L_NX,
    L_NY,
    LANES,
    P_BOUNCE,
    P_NORMAL_IMPULSE,
    P_RNA,
    P_RNB,
    P_RTA,
    P_RTB,
    P_TANGENT_IMPULSE,
    P_TANGENT_MASS,
    P_TICK_NORMAL_IMPULSE,
    VX,
    VY,
    W,
    lane_index,
    point_index,
    relative_speed,
    two_point_lcp,
)

NO_BOUNCE = -1.0  # P_BOUNCE of a point that takes no part in an impact (targets are >= 0)
# P_BOUNCE of a point beside an impact, whose target t (>= 0) is held as BESIDE - t: restored like an
# impact's, but no impact's friction (it rests, it was not struck)
BESIDE = -2.0
# columns of the velocity rows before the soft step (`keep_velocities`): the solver rows' VX, VY, W, and
# whether an impact of the sequence moved the body
HIT = 3
BEFORE_COLUMNS = 4


@inlined
def _push(v, lanes, o, a, b, tx, ty, r1a, r1b, x1, r2a, r2b, x2):
    """Apply impulses x1, x2 along the unit direction t at a manifold's two points (r1a: point 1's anchor
    on a crossed with t) to velocity rows v."""
    ma, ia, mb, ib = lanes[o + L_MA], lanes[o + L_IA], lanes[o + L_MB], lanes[o + L_IB]
    total = x1 + x2
    v[a, VX] -= ma * tx * total
    v[a, VY] -= ma * ty * total
    v[a, W] -= ia * (r1a * x1 + r2a * x2)
    v[b, VX] += mb * tx * total
    v[b, VY] += mb * ty * total
    v[b, W] += ib * (r1b * x1 + r2b * x2)


@inlined
def _masses(lanes, o, r1a, r1b, r2a, r2b):
    """The 2 x 2 effective mass matrix of a manifold's two points along one direction."""
    ma, ia, mb, ib = lanes[o + L_MA], lanes[o + L_IA], lanes[o + L_MB], lanes[o + L_IB]
    return (ma + mb + ia * r1a * r1a + ib * r1b * r1b, ma + mb + ia * r1a * r2a + ib * r1b * r2b,
            ma + mb + ia * r2a * r2a + ib * r2b * r2b)


@inlined
def _speed(v, a, b, nx, ny, ra, rb):
    """Speed of b's point relative to a's along (nx, ny), in velocity rows v."""
    return relative_speed(v[a, VX], v[a, VY], v[a, W], v[b, VX], v[b, VY], v[b, W], nx, ny, ra, rb)


@inlined
def keep_velocities(body, before):
    """Copy the solver rows' velocities before the soft step: the impacts start from them."""
    for i in range(body.shape[0]):
        before[i, VX] = body[i, VX]
        before[i, VY] = body[i, VY]
        before[i, W] = body[i, W]
        before[i, HIT] = 0.0


@inlined
def bounce_targets(batches, n_chunks, lanes, before, threshold):
    """The normal speed each point stopped by the soft step should leave the tick at, from the velocity
    rows `before` it (which this overwrites): the sequence of collisions. A point takes part when the
    solver pushed at it and it closes faster than `threshold`. A point the solver pushed at that touches
    a body an impact moved is BESIDE the impact: it gets the speed the sequence leaves it at, or none if
    that closes, since its push is the sequence's to give (three balls meeting in one tick, one pair
    pushed by the soft step but never closing in the sequence, gained 3 % of their energy, and an
    elastic gas up to 1.2 % a minute), but no impact friction (capsule piles of 13 seeds: 2 still creep
    at a few mm/s after 10 s, 1 did before; 3 with impact friction there too). The others get
    NO_BOUNCE. (Taking every slower one in made every tick of a resting pile of bouncy balls solve the
    pile to 1e-6 m/s: 8 ms of a 9 ms tick in the shower scene.)"""
    fill, slot_a, slot_b = batches.fill, batches.slot_a, batches.slot_b
    for c in range(n_chunks):
        for j in range(fill[c]):
            o = lane_index(c, j)
            lanes[point_index(o, 0) + P_BOUNCE] = NO_BOUNCE
            lanes[point_index(o, 1) + P_BOUNCE] = NO_BOUNCE
    for _ in range(BOUNCE_PASSES):
        moved = False
        for c in range(n_chunks):
            for j in range(fill[c]):
                o = lane_index(c, j)
                a = slot_a[c * LANES + j]
                b = slot_b[c * LANES + j]
                nx, ny, e = lanes[o + L_NX], lanes[o + L_NY], lanes[o + L_E]
                q1, q2 = point_index(o, 0), point_index(o, 1)
                b1 = b2 = 0.0  # each point's speed less its target
                closing1 = closing2 = False
                for k in range(2):
                    q = q1 if k == 0 else q2
                    if lanes[q + P_TICK_NORMAL_IMPULSE] == 0.0:
                        continue  # the solver did not push here (a missing second point neither)
                    vn = _speed(before, a, b, nx, ny, lanes[q + P_RNA], lanes[q + P_RNB])
                    if vn >= -max(threshold, BOUNCE_SPEED_TOLERANCE):
                        continue  # too slow to bounce: the soft step's stop stands
                    lanes[q + P_BOUNCE] = 0.0  # takes part; its target is set at the end
                    target = -e * vn
                    if k == 0:
                        b1, closing1 = vn - target, True
                    else:
                        b2, closing2 = vn - target, True
                if not (closing1 or closing2):
                    continue
                moved = True
                if lanes[o + L_MA] > 0.0:
                    before[a, HIT] = 1.0
                if lanes[o + L_MB] > 0.0:
                    before[b, HIT] = 1.0
                r1a, r1b = lanes[q1 + P_RNA], lanes[q1 + P_RNB]
                r2a, r2b = lanes[q2 + P_RNA], lanes[q2 + P_RNB]
                k11, k12, k22 = _masses(lanes, o, r1a, r1b, r2a, r2b)
                if closing1 and closing2:
                    x1, x2 = two_point_lcp(k11, k12, k22, b1, b2)
                elif closing1:
                    x1, x2 = -b1 / k11, 0.0
                else:
                    x1, x2 = 0.0, -b2 / k22
                _push(before, lanes, o, a, b, nx, ny, r1a, r1b, x1, r2a, r2b, x2)
        if not moved:
            break
    for c in range(n_chunks):  # the speeds the points that took part leave at
        for j in range(fill[c]):
            o = lane_index(c, j)
            a = slot_a[c * LANES + j]
            b = slot_b[c * LANES + j]
            near = before[a, HIT] > 0.0 or before[b, HIT] > 0.0
            for k in range(2):
                q = point_index(o, k)
                part = lanes[q + P_BOUNCE] != NO_BOUNCE
                if part or (near and lanes[q + P_TICK_NORMAL_IMPULSE] != 0.0):
                    speed = _speed(before, a, b, lanes[o + L_NX], lanes[o + L_NY], lanes[q + P_RNA],
                                   lanes[q + P_RNB])
                    lanes[q + P_BOUNCE] = speed if part else BESIDE - max(speed, 0.0)


@inlined
def restitute(batches, n_chunks, lanes, body):
    """One pass: restore the normal speed of every point that took part in an impact to its target (a
    manifold's two points together), keeping the normal impulse of the whole tick >= 0 (the soft step's
    last accumulated impulse is only its last substep's share). The accumulated impulses, which limit
    the friction of the impact, follow. Returns the largest change of a speed."""
    fill, slot_a, slot_b = batches.fill, batches.slot_a, batches.slot_b
    largest = 0.0
    for c in range(n_chunks):
        for j in range(fill[c]):
            o = lane_index(c, j)
            q1, q2 = point_index(o, 0), point_index(o, 1)
            t1, t2 = lanes[q1 + P_BOUNCE], lanes[q2 + P_BOUNCE]
            part1, part2 = t1 != NO_BOUNCE, t2 != NO_BOUNCE
            if not (part1 or part2):
                continue
            t1 = BESIDE - t1 if t1 <= BESIDE else t1
            t2 = BESIDE - t2 if t2 <= BESIDE else t2
            a = slot_a[c * LANES + j]
            b = slot_b[c * LANES + j]
            nx, ny = lanes[o + L_NX], lanes[o + L_NY]
            r1a, r1b, r2a, r2b = lanes[q1 + P_RNA], lanes[q1 + P_RNB], lanes[q2 + P_RNA], lanes[q2 + P_RNB]
            old1, old2 = lanes[q1 + P_TICK_NORMAL_IMPULSE], lanes[q2 + P_TICK_NORMAL_IMPULSE]
            k11, k12, k22 = _masses(lanes, o, r1a, r1b, r2a, r2b)
            b1 = _speed(body, a, b, nx, ny, r1a, r1b) - t1
            b2 = _speed(body, a, b, nx, ny, r2a, r2b) - t2
            if part1 and part2:
                # accumulated impulses x >= 0 with the speeds after, K (x - old) + speed, at the targets
                x1, x2 = two_point_lcp(k11, k12, k22, b1 - k11 * old1 - k12 * old2,
                                       b2 - k12 * old1 - k22 * old2)
            elif part1:
                x1, x2 = max(old1 - b1 / k11, 0.0), old2
            else:
                x1, x2 = old1, max(old2 - b2 / k22, 0.0)
            lanes[q1 + P_TICK_NORMAL_IMPULSE], lanes[q2 + P_TICK_NORMAL_IMPULSE] = x1, x2
            lanes[q1 + P_NORMAL_IMPULSE] = max(lanes[q1 + P_NORMAL_IMPULSE] + x1 - old1, 0.0)
            lanes[q2 + P_NORMAL_IMPULSE] = max(lanes[q2 + P_NORMAL_IMPULSE] + x2 - old2, 0.0)
            largest = max(largest, abs(x1 - old1) * k11, abs(x2 - old2) * k22)
            _push(body, lanes, o, a, b, nx, ny, r1a, r1b, x1 - old1, r2a, r2b, x2 - old2)
    return largest


@inlined
def impact_friction(batches, n_chunks, lanes, body):
    """One pass of friction at the points that took part in an impact, towards no slip, with the
    accumulated friction impulse within friction x the accumulated normal impulse, the bounce's
    included. Returns the largest change of a speed."""
    fill, slot_a, slot_b = batches.fill, batches.slot_a, batches.slot_b
    largest = 0.0
    for c in range(n_chunks):
        for j in range(fill[c]):
            o = lane_index(c, j)
            mu = lanes[o + L_MU]
            if mu == 0.0:
                continue
            a = slot_a[c * LANES + j]
            b = slot_b[c * LANES + j]
            tx, ty = lanes[o + L_NY], -lanes[o + L_NX]
            for k in range(2):
                q = point_index(o, k)
                if lanes[q + P_BOUNCE] < 0.0:
                    continue  # no impact here (NO_BOUNCE), or beside one (BESIDE)
                rta, rtb = lanes[q + P_RTA], lanes[q + P_RTB]
                vt = _speed(body, a, b, tx, ty, rta, rtb)
                limit = mu * lanes[q + P_NORMAL_IMPULSE]
                old = lanes[q + P_TANGENT_IMPULSE]
                total = min(max(old - lanes[q + P_TANGENT_MASS] * vt, -limit), limit)
                lanes[q + P_TANGENT_IMPULSE] = total
                if total != old:
                    largest = max(largest, abs(total - old) / lanes[q + P_TANGENT_MASS])
                    _push(body, lanes, o, a, b, tx, ty, rta, rtb, total - old, 0.0, 0.0, 0.0)
    return largest


@stage
def may_bounce(batches, n_chunks, lanes, body, threshold):
    """Whether a point of the scheduled contacts closes faster than `threshold` as the tick starts (the
    solver rows `body` before the soft step). The sequence of collisions starts from such a point: with
    none, `resolve_impacts` changes nothing and is skipped (a resting pile of bodies that can bounce
    paid for five passes over its contacts every tick)."""
    slow = -max(threshold, BOUNCE_SPEED_TOLERANCE)
    fill, slot_a, slot_b = batches.fill, batches.slot_a, batches.slot_b
    for c in range(n_chunks):
        for j in range(fill[c]):
            o = lane_index(c, j)
            a = slot_a[c * LANES + j]
            b = slot_b[c * LANES + j]
            nx, ny = lanes[o + L_NX], lanes[o + L_NY]
            for k in range(2):  # a missing second point (zeros) gives the centres' speed: at worst no skip
                q = point_index(o, k)
                if _speed(body, a, b, nx, ny, lanes[q + P_RNA], lanes[q + P_RNB]) < slow:
                    return True
    return False


@stage
def resolve_impacts(batches, n_chunks, lanes, body, before, threshold):
    """Bounce the contacts the soft step stopped, from the velocity rows `before` it (overwritten):
    targets, then passes of restitution and friction until no speed changes by more than
    BOUNCE_SPEED_TOLERANCE (along a row of touching balls the speeds settle over several passes)."""
    bounce_targets(batches, n_chunks, lanes, before, threshold)
    for _ in range(BOUNCE_PASSES):
        change = restitute(batches, n_chunks, lanes, body)
        change = max(change, impact_friction(batches, n_chunks, lanes, body))
        if change < BOUNCE_SPEED_TOLERANCE:
            break
