"""The tick: geometry, broad phase, narrow phase, warm start, soft joint and contact solver with
substeps, integration, broken joints, bounds.

One compiled function runs a block of ticks so that Python costs once per block. Its buffers (the
workspace) belong to the world and live from block to block, growing when a tick needs more: a tick
of a settled scene allocates nothing, even when a recorder steps one tick at a time. The previous
tick's contact points (sorted by key: shape a, shape b, feature id) are both the warm-start cache and
what `World.contacts()` reports.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from rustycs.broad_phase import Pairs, fatten, find_pairs, grown_pairs, new_pairs, pairs_hold, refresh_pairs
from rustycs.constants import (
    CONTACT_DAMPING_RATIO,
    CONTACT_HERTZ,
    JOINT_DAMPING_RATIO,
    JOINT_STIFFNESS,
    SPECULATIVE_DISTANCE,
)
from rustycs.contact_batches import Batches, new_batches, schedule
from rustycs.contact_cache import ContactCache, new_cache, remember, warm_start_points
from rustycs.contact_events import Touching, contact_events, grown_touching, new_touching
from rustycs.contact_solver import (
    BODY_COLUMNS,
    LANE_FIELDS,
    LANES,
    load_bodies,
    prepare,
    softness,
    store_bodies,
    store_impulses,
)
from rustycs.continuous import HoldBack, hold_back_passes, new_hold_back
from rustycs.events import JOINT_BREAK, Events, grown_events, new_events, record_event
from rustycs.geometry import Geometry, new_geometry, update_geometry
from rustycs.impacts import BEFORE_COLUMNS, keep_velocities, may_bounce, resolve_impacts
from rustycs.joint_solver import (
    JointWork,
    anchor_point,
    break_joints,
    breakable,
    joint_reactions,
    new_joint_work,
    prepare_block,
    prepare_joints,
)
from rustycs.motion import (
    apply_bounds,
    damp,
    damping_factors,
    first_non_finite,
)
from rustycs.narrow_phase import Contacts, narrow_phase, new_contacts, no_sleeping_points
from rustycs.recording import record_frame
from rustycs.scenario import after_tick, events_bound, has_scenario
from rustycs.sleep import (
    Islands,
    fall_asleep,
    new_islands,
    nothing_moves,
    wake_reached,
    warm_from_sleep,
)
from rustycs.stepper import ESCAPED_TOTAL, TICK, borrowed
from rustycs.substeps import substeps
from rustycs.threads import (
    BODY_PART,
    CHUNK_PART,
    PAIR_PART,
    SHAPE_PART,
    ThreadScratch,
    collide_pairs_in_parts,
    find_pairs_in_parts,
    new_thread_scratch,
    place_bodies_in_parts,
    prepare_in_parts,
    substeps_in_groups,
)


class Settings(NamedTuple):
    """How a world steps."""

    dt: float  # s per tick
    substeps: int  # solver substeps per tick (the scene's precision)
    restitution_threshold: float  # m/s: slower approaches do not bounce
    bounds: np.ndarray  # (4,) xmin, ymin, xmax, ymax: dynamic bodies leaving them are deactivated
    has_bounds: bool
    contact_events: bool  # record contact_begin and contact_end
    sleep: bool  # islands at rest sleep (`rustycs.sleep`)
    sleep_time: float  # s an island rests before it sleeps
    threads: int  # > 1: the stages that split by element run in parts over threads (`rustycs.threads`)


class Workspace(NamedTuple):
    """The step's buffers, kept by the world from one block to the next."""

    geometry: Geometry
    pairs: Pairs
    contacts: Contacts
    cache: ContactCache  # the last tick's points: the warm start of the next
    body: np.ndarray  # (N, BODY_COLUMNS) the solver's rows of the bodies
    batches: Batches
    lanes: np.ndarray  # the solver's lanes of the scheduled contacts
    decay: np.ndarray  # (N, 2) per body the damping factors of a tick, linear and angular
    bounce_velocity: np.ndarray  # (N, impacts.BEFORE_COLUMNS) the velocities before the soft step
    held_back: HoldBack  # scratch of `hold_back_passes`
    joint_work: JointWork
    events: Events
    statics_placed: np.ndarray  # bool (1,): the static bodies' geometry is up to date
    touching: Touching  # the shape pairs touching in the last tick (contact events)
    islands: Islands  # scratch of sleeping
    threads: ThreadScratch  # scratch of the stages run in parts


@njit(cache=True)
def new_workspace(n_bodies, shapes, n_joints, max_vertices, c_key, c_jn, c_jt, sleeps, threads):
    """Buffers for stepping, with a warm-start cache (keys and impulses) carried over; with `sleeps`, room
    for the points of islands asleep; scratch for `threads` threads."""
    n_shapes = shapes.body.shape[0]
    capacity = max(4 * n_shapes + 16, c_key.shape[0])
    return Workspace(new_geometry(n_bodies, n_shapes, max_vertices), new_pairs(shapes, capacity),
                     new_contacts(capacity, sleeps, no_sleeping_points()),
                     new_cache(2 * capacity, c_key, c_jn, c_jt), np.empty((n_bodies, BODY_COLUMNS)),
                     new_batches(n_bodies, capacity), np.empty(capacity * LANE_FIELDS),
                     np.ones((n_bodies, 2)), np.zeros((n_bodies, BEFORE_COLUMNS)),
                     new_hold_back(n_bodies, n_shapes), new_joint_work(n_bodies, n_joints),
                     new_events(events_bound(0, n_bodies, n_joints, capacity, capacity)),  # tick 1 fits
                     np.zeros(1, np.bool_), new_touching(capacity), new_islands(n_bodies if sleeps else 0),
                     new_thread_scratch(threads, capacity, capacity, n_shapes))


@njit(cache=True)
def grown(ws, n_bodies, cells, pairs, points, chunks, events):
    """The workspace with every buffer that holds fewer than these entries replaced by one twice as
    large (the contents of a replaced buffer are not kept: each is refilled by its stage; the events
    so far, the pairs touching and the points asleep are)."""
    p = ws.pairs
    contacts, batches, touching, threads = ws.contacts, ws.batches, ws.touching, ws.threads
    regrown = False
    if cells > p.cells.shape[0] or pairs > p.keys.shape[0]:
        p = grown_pairs(p, pairs, cells)
        regrown = True
    if pairs > contacts.manifolds.first.shape[0]:
        contacts = new_contacts(2 * pairs, contacts.asleep.key.shape[0] > 0, contacts.asleep)
        batches = new_batches(n_bodies, 2 * pairs)
        touching = grown_touching(touching, 2 * pairs)
        regrown = True
    if regrown:
        threads = new_thread_scratch(threads.filled.shape[0], contacts.manifolds.first.shape[0],
                                     p.keys.shape[0], p.fat_active.shape[0])
    kept = ws.events
    if events > kept.tick.shape[0]:
        kept = grown_events(kept, 2 * events)
    cache = ws.cache
    if points > cache.key.shape[0]:  # keeps its entries: they warm-start the tick that needs more
        n = cache.count[0]
        cache = new_cache(2 * points, cache.key[:n], cache.normal_impulse[:n], cache.tangent_impulse[:n])
    lanes = ws.lanes
    if chunks * LANES * LANE_FIELDS > lanes.shape[0]:
        lanes = np.empty(2 * chunks * LANES * LANE_FIELDS)
    return Workspace(ws.geometry, p, contacts, cache, ws.body, batches, lanes, ws.decay, ws.bounce_velocity,
                     ws.held_back, ws.joint_work, kept, ws.statics_placed, touching, ws.islands, threads)


# entries of a block's status (`step_world`): ticks done, frames recorded, bodies that left the bounds,
# the first body whose state became non-finite (-1: none), what a buffer must hold to go on, and the
# stop condition that ended the block (-1: none)
TICKS_DONE, FRAMES, ESCAPED, BAD_BODY, NEED_CELLS, NEED_PAIRS, NEED_CHUNKS, NEED_EVENTS, STOPPED = range(9)
STATUS_FIELDS = 9


@njit(cache=True, nogil=True, _nrt=False)
def step_world(stepper, n_ticks, every):
    """Run `n_ticks` ticks of the world a stepper holds (`rustycs.stepper`), until they are done, a state
    becomes non-finite or a stop condition of the scenario holds (its frame recorded); returns whether the
    workspace was replaced. A tick that needs larger buffers stops before it changed any state, with the
    sizes it needs in the status: the workspace is grown (`grown`) and the tick starts again.

    With `every` > 0, a frame (`recording.record_frame`) is written into the stepper's frames after every
    `every`-th tick of the block and after its last. The scenario (`rustycs.scenario.Scenario`) makes bodies
    appear and vanish, senses, measures and may stop the block early. In the status (`new_status`)
    BAD_BODY is -1 or the first body whose state became non-finite in the tick after TICKS_DONE; STOPPED is
    -1 or the stop condition that held after tick TICKS_DONE. The stepper's clock counts the ticks done
    (and the failing one) and the bodies escaped.

    Called from Python: it releases the GIL (independent worlds step in parallel threads) and returns no
    records (boxing the workspace back on every call cost 80 unpicklings). Compiled without reference
    counting, like every stage it calls: a tick passes the records to a dozen stages, and counting
    references to their arrays cost a third of a five-body tick. The loop is written here, not called: a
    compiled function calling another passes every array of its records by value (7 to 9 words each,
    about 1,800 words for a world), and each level of calls compiles its callees' code once more.
    """
    if n_ticks <= 0:  # a call that loads the kernel changes nothing
        return False
    fields = borrowed(stepper)
    # the records the tick loop uses in every tick; the scenario, the frames and the joints' filter are
    # read where they are used. Every array read here is held on the stack through the loop: a call began
    # by copying ~1,450 words there, a quarter of a one-tick call (`World.step(1)` of the five-body world
    # 1.9-2.2 us; 1.7-1.8 with these three read where used)
    bodies, shapes, joints, forces = fields.bodies, fields.shapes, fields.joints, fields.forces
    settings, status, clock, ws = fields.settings, fields.status, fields.clock, fields.workspace
    sensors = fields.scenario.sensors.body.shape[0]
    for k in range(STATUS_FIELDS):
        status[k] = 0
    status[BAD_BODY] = -1
    status[STOPPED] = -1
    ws.events.count[0] = 0  # the last block's events were taken
    replaced = False
    first_tick = clock[TICK]
    dt = settings.dt
    h = dt / settings.substeps
    contact_hertz = min(CONTACT_HERTZ, 0.25 / h)
    soft = softness(contact_hertz, CONTACT_DAMPING_RATIO, h)
    # contacts against an immovable body are stiffer, as only one side gives way, but no stiffer than
    # the soft step keeps stable: above a quarter of the substep rate a 1 cm plate standing on the ground
    # rocked ever more and fell after 3.4 s at 4 substeps (capped: at rest for 10 s, to 4e-6 rad)
    stiff = softness(min(2.0 * contact_hertz, 0.25 / h), CONTACT_DAMPING_RATIO, h)
    joint_soft = softness(JOINT_STIFFNESS / h, JOINT_DAMPING_RATIO, h)
    decay, joint_work = ws.decay, ws.joint_work  # kept when the workspace grows
    damped = damping_factors(bodies, dt, decay)
    prepare_block(joints, h, joint_work)
    breaking = breakable(joints)
    jointed = joints.kind.shape[0] > 0
    threaded = settings.threads > 1
    # a call of `after_tick` with its records was a seventh of S1's tick
    scripted = has_scenario(fields.scenario)
    bad = first_non_finite(bodies)
    if bad >= 0:  # set from outside between blocks: report it before it spreads
        status[BAD_BODY] = bad
    while status[BAD_BODY] < 0 and status[TICKS_DONE] < n_ticks:
        if max(status[NEED_CELLS], status[NEED_PAIRS], status[NEED_CHUNKS], status[NEED_EVENTS]) > 0:
            _grow(stepper)
            ws = borrowed(stepper).workspace
            replaced = True
            for k in (NEED_CELLS, NEED_PAIRS, NEED_CHUNKS, NEED_EVENTS):
                status[k] = 0
        (geometry, pairs, contacts, cache, body, batches, lanes, decay, bounce_velocity, held_back,
         joint_work, events, statics_placed, touching, islands, _) = ws
        # a sleeping world in which nothing moves: its stages up to the events would find no manifold and
        # change nothing (the 820-box pyramid asleep: 50 us a tick of passes over its bodies and pairs)
        still = (settings.sleep and not jointed and statics_placed[0] and nothing_moves(bodies)
                 and pairs_hold(bodies, shapes, geometry, pairs))
        if still:
            n_pairs, n_man, n_pts = pairs.count[0], 0, 0
            contacts.count[0] = 0
            contacts.count[1] = 0
        else:
            if threaded and bodies.x.shape[0] >= 2 * BODY_PART:
                place_bodies_in_parts(stepper, SPECULATIVE_DISTANCE, dt, not statics_placed[0])
            else:
                update_geometry(bodies, shapes, SPECULATIVE_DISTANCE, dt, not statics_placed[0], geometry)
            statics_placed[0] = True
            if not pairs_hold(bodies, shapes, geometry, pairs) and not refresh_pairs(
                    bodies, shapes, joints, borrowed(stepper).joint_filter, geometry, pairs):
                fatten(bodies, shapes, geometry, pairs)
                if threaded and shapes.body.shape[0] >= 2 * SHAPE_PART:
                    n_pairs, n_entries = find_pairs_in_parts(stepper)
                else:
                    n_pairs, n_entries = find_pairs(bodies, shapes, joints, borrowed(stepper).joint_filter,
                                                    pairs)
                if n_entries > pairs.cells.shape[0] or n_pairs > pairs.keys.shape[0]:
                    pairs.count[0] = -1  # find them again
                    status[NEED_CELLS] = n_entries
                    status[NEED_PAIRS] = n_pairs
                    continue
                pairs.count[0] = n_pairs
            n_pairs = pairs.count[0]
            if n_pairs > contacts.manifolds.first.shape[0] or 2 * n_pairs > cache.key.shape[0]:
                status[NEED_PAIRS] = n_pairs
                continue
            if settings.sleep:
                wake_reached(pairs.keys, n_pairs, bodies, shapes, geometry, joints, contacts,
                             SPECULATIVE_DISTANCE, islands)
            if threaded and n_pairs >= 2 * PAIR_PART:
                n_man, n_pts = collide_pairs_in_parts(stepper, n_pairs, SPECULATIVE_DISTANCE, dt,
                                                      settings.sleep)
            else:
                n_man, n_pts = narrow_phase(pairs.keys, n_pairs, bodies, shapes, geometry,
                                            SPECULATIVE_DISTANCE, dt, settings.sleep, contacts)
        room = events.count[0] + events_bound(sensors, bodies.x.shape[0],
                                              joints.kind.shape[0], n_man, touching.count[0])
        if room > events.tick.shape[0]:
            status[NEED_EVENTS] = room
            continue
        first_event = events.count[0]
        tick = first_tick + status[TICKS_DONE] + 1
        if not still:
            warm_start_points(contacts.points, n_pts, cache)
            if contacts.asleep.count[0] > 0:
                warm_from_sleep(contacts.points, n_pts, bodies, contacts.asleep)
            load_bodies(bodies, body)
            if damped:
                damp(body, bodies, decay)
            prepare_joints(bodies, joints, tick, joint_work)
            n_chunks = schedule(contacts.manifolds, n_man, body, bodies.body_type, jointed, batches)
            if n_chunks * LANES * LANE_FIELDS > lanes.shape[0]:
                status[NEED_CHUNKS] = n_chunks
                continue
            if threaded and n_chunks >= 2 * CHUNK_PART:
                bouncy = prepare_in_parts(stepper, n_chunks)
            else:
                bouncy = prepare(batches, n_chunks, contacts.manifolds, contacts.points, shapes.radius,
                                 body, lanes)
            batches.fresh[0] = False  # the lanes hold the slots' zeros
            bounces = bouncy > 0 and may_bounce(batches, n_chunks, lanes, body,
                                                settings.restitution_threshold)
            if bounces:
                keep_velocities(body, bounce_velocity)
            # the groups side by side, each storing its impulses, when two have contacts (the last group
            # holds the bodies of none): the 5,050-box pyramid, one island, gains nothing
            if threaded and batches.last[2] > 2:
                substeps_in_groups(stepper, joint_soft, h, settings.substeps, soft, stiff)
            else:
                substeps(batches, lanes, body, bodies, joints, joint_work, joint_soft, forces, h,
                         settings.substeps, soft, stiff)
                store_impulses(batches, 0, n_chunks, contacts.manifolds, lanes, contacts.points)
            if bounces:
                resolve_impacts(batches, n_chunks, lanes, body, bounce_velocity,
                                settings.restitution_threshold)
        if settings.contact_events:
            contact_events(contacts.manifolds, n_man, contacts.points, bodies, tick, touching, events)
        if not still:
            store_bodies(body, bodies)
            hold_back_passes(pairs.keys, n_pairs, contacts.clearance, bodies, shapes, geometry, body, dt,
                             SPECULATIVE_DISTANCE, contacts.sweep, held_back)
        remember(contacts.points, n_pts, cache)
        if settings.sleep and not still:
            fall_asleep(bodies, body, joints, contacts, settings.sleep_time, dt, islands)
        done = status[TICKS_DONE] + 1
        recorded = every > 0 and (done % every == 0 or done == n_ticks)
        # else nobody reads this tick's reactions (a call with the records costs a tenth of a 5-body tick)
        reacted = jointed and (breaking or recorded or done == n_ticks)
        if reacted:
            joint_reactions(bodies, body, joints, joint_work, h)
        if breaking:
            broken = joint_work.broken
            for k in range(break_joints(joints, broken)):
                px, py = anchor_point(bodies, joints, broken[k])
                record_event(events, tick, JOINT_BREAK, broken[k], -1, px, py, 0.0)
                pairs.count[0] = -1  # the joint no longer keeps its bodies apart
        bad = first_non_finite(bodies)
        if bad >= 0:
            status[BAD_BODY] = bad
            break
        if settings.has_bounds:
            status[ESCAPED] += apply_bounds(bodies, settings.bounds, tick, events)
        if scripted:
            status[STOPPED] = after_tick(borrowed(stepper).scenario, bodies, shapes, forces, contacts, events,
                                         first_event, tick, dt)
        status[TICKS_DONE] = done
        stopped = status[STOPPED] >= 0
        if stopped and jointed and not reacted:
            joint_reactions(bodies, body, joints, joint_work, h)  # the last tick of the block
        if recorded or (every > 0 and stopped):
            record_frame(borrowed(stepper).frames, status[FRAMES], first_tick + done, bodies, joints, forces,
                         contacts)
            status[FRAMES] += 1
        if stopped:
            break
    clock[TICK] += status[TICKS_DONE] + (1 if status[BAD_BODY] >= 0 else 0)
    clock[ESCAPED_TOTAL] += status[ESCAPED]
    return replaced


@njit(cache=True, _nrt=True)  # set, not inherited from `step_world`: it makes arrays
def _grow(stepper):
    """Replace the stepper's workspace with one holding what its status says the stopped tick needs."""
    status = stepper.status
    stepper.workspace = grown(stepper.workspace, stepper.bodies.x.shape[0], status[NEED_CELLS],
                              status[NEED_PAIRS], 2 * status[NEED_PAIRS], status[NEED_CHUNKS],
                              status[NEED_EVENTS])


@njit(cache=True, nogil=True)  # a typed list's items are reference counted
def step_worlds(steppers, first, last, n_ticks, every, replaced):
    """`step_world` for steppers first .. last - 1 of a list; `replaced[i]` says whether world i's
    workspace was replaced. Releases the GIL, so that threads step parts of a list."""
    for i in range(first, last):
        replaced[i] = step_world(steppers[i], n_ticks, every)


def new_status() -> np.ndarray:
    """A block's status before its first tick (`run_ticks`)."""
    status = np.zeros(STATUS_FIELDS, np.int64)
    status[BAD_BODY] = -1
    status[STOPPED] = -1
    return status
