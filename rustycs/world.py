"""The pythonic World: build a scene body by body, step it in compiled blocks, read its state."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NamedTuple

import numba
import numpy as np

from rustycs import defaults
from rustycs import joints as J
from rustycs.body_control import Body, BodyControl
from rustycs.body_types import BODY_TYPE_NAMES, DYNAMIC
from rustycs.events import EVENT_KIND_NAMES
from rustycs.forces import Forces
from rustycs.joints import JOINT_COLUMNS, JOINT_TYPE_NAMES, Joints, joint_filter
from rustycs.kernel_cache import compiled_entry, ensure_fresh
from rustycs.materials import MATERIALS, Material
from rustycs.pieces import MAX_VERTICES, body_mass, edge_normals, shape_pieces
from rustycs.queries import WorldQueries
from rustycs.recording import check_frame_buffer, frame_buffer
from rustycs.shapes import Box, Capsule, Chain, Circle, Polygon, Segment, Shape, type_name
from rustycs.state import BODY_COLUMNS, SHAPE_COLUMNS, Bodies, Shapes, Table
from rustycs.step import BAD_BODY, FRAMES, STOPPED, Settings, new_status, new_workspace, step_world
from rustycs.stepper import CLOCK_FIELDS, ESCAPED_TOTAL, TICK, new_stepper, workspace_of
from rustycs.world_scenario import WorldScenario

_BODY_TYPES = {name: code for code, name in enumerate(BODY_TYPE_NAMES)}


class SimulationDiverged(RuntimeError):
    """A non-finite value appeared in the state: `tick` (1-based, the tick that failed) and `body`."""

    def __init__(self, tick: int, body: int, message: str, frames: int = 0):
        self.tick = tick
        self.body = body
        self.frames = frames  # frames recorded by the failing `step` call before the bad tick
        super().__init__(message)


def _material(material: Material | str) -> Material:
    if isinstance(material, Material):
        return material
    if material not in MATERIALS:
        raise ValueError(f"unknown material {material!r}; presets: {', '.join(MATERIALS)}")
    return MATERIALS[material]


def _step_setting(name: str, doc: str) -> property:
    """A setting of the step, which takes effect from the next step on (the stepper is made again)."""
    private = "_" + name

    def set_value(world, value) -> None:
        setattr(world, private, value)
        world._forget_stepper()

    return property(lambda world: getattr(world, private), set_value, doc=doc)


class KernelInputs(NamedTuple):
    """What the kernels read of a world: its records (bodies, shapes, joints and their filter, forces,
    and the scenario: `rustycs.scenario.Scenario`)."""

    bodies: Bodies
    shapes: Shapes
    joints: Joints
    joint_filter: J.JointFilter
    forces: Forces
    scenario: tuple


def _point(value) -> np.ndarray:
    point = np.asarray(value, dtype=np.float64).reshape(2)
    if not np.all(np.isfinite(point)):
        raise ValueError("joint points and axes must be finite")
    return point


class World(BodyControl, WorldQueries, WorldScenario):
    """A 2D world of rigid bodies made of shapes, and joints between them.

    Each tick is dt = 1/tick_rate long and runs `precision` solver substeps. Attractors pull with
    the acceleration G*M/max(d, min_distance)^2; forces are constant accelerations. Bodies may appear
    and go during a run, and measures and stop conditions watch it (`WorldScenario`).
    """

    # bumped whenever a world's stepper is made again or must be: a batch of worlds unchanged since its last
    # step does not look at each (`rustycs.batch`: 1,024 looks were most of a call stepping one tick)
    edits = 0


    def __init__(self, tick_rate: float = defaults.TICK_RATE, precision: int = defaults.PRECISION,
                 gravitational_constant: float = defaults.GRAVITATIONAL_CONSTANT, bounds=None,
                 restitution_threshold: float = defaults.RESTITUTION_THRESHOLD, sleep: bool = defaults.SLEEP,
                 sleep_time: float = defaults.SLEEP_TIME, threads: int = defaults.THREADS):
        ensure_fresh()  # before any kernel runs: a cache compiled from other sources is dropped
        if not 0 < tick_rate < math.inf:
            raise ValueError("tick_rate must be finite and > 0")
        if not 1 <= int(precision) <= defaults.MAX_PRECISION:
            raise ValueError(f"precision must be from 1 to {defaults.MAX_PRECISION}")
        self.tick_rate = float(tick_rate)
        self.dt = 1.0 / self.tick_rate
        self.precision = int(precision)
        self.gravitational_constant = float(gravitational_constant)
        self.bounds = None if bounds is None else (tuple(map(float, bounds[0])), tuple(map(float, bounds[1])))
        self.restitution_threshold = float(restitution_threshold)
        if not 0 < sleep_time < math.inf:
            raise ValueError("sleep_time must be finite and > 0")
        self._sleep = bool(sleep)
        self.sleep_time = float(sleep_time)
        self.threads = threads
        self._clock = np.zeros(CLOCK_FIELDS, np.int64)  # ticks done, bodies escaped (`rustycs.stepper`)
        self._gravity = np.zeros(2)
        self._attractors: list[dict] = []
        self._bodies = Table(Bodies, BODY_COLUMNS)
        self._shapes = Table(Shapes, SHAPE_COLUMNS)  # convex pieces, as the kernels collide them
        self._joints = Table(Joints, JOINT_COLUMNS)
        self._shape_list: list[tuple[int, Shape]] = []  # (body, shape) as given
        self._piece_shapes: list[int] = []  # per convex piece, its shape's index in _shape_list
        self._names: list[str] = []  # per body, unique
        self._name_rows: dict[str, int] = {}
        self._inputs: tuple | None = None  # the kernels' inputs, rebuilt when bodies or forces change
        # the step's buffers, kept from block to block (rebuilt when bodies are added)
        self._workspace = None
        self._contact_rows = None  # the last tick's contact points, built from the workspace when asked
        self._contact_rows_tick = -1  # the tick they are of
        self._no_frames = tuple(frame_buffer(0, 0, 0).values())  # the step's frames when none are recorded
        self._checked_record: tuple = (None, ())  # the last frame buffer checked, and its arrays
        self._status = new_status()  # of the last block (`rustycs.step`)
        # the step's records, buffers and frames in one object (`rustycs.stepper`), made again when the
        # world's make-up (`_inputs` None), its settings, its buffers (`_workspace` None) or the frames change
        self._stepper = None
        self._stepper_frames = None
        self._entry = None  # step_world's compiled entry for the stepper's type
        self._settings_for = None  # (the kernel inputs, the settings' values, the Settings record)
        self._init_scenario()

    dt = _step_setting("dt", "Seconds per tick.")
    precision = _step_setting("precision", "Solver substeps per tick.")
    restitution_threshold = _step_setting("restitution_threshold", "m/s: slower approaches do not bounce.")
    bounds = _step_setting("bounds", "((xmin, ymin), (xmax, ymax)): dynamic bodies leaving them are "
                                     "deactivated; None: no bounds.")
    sleep_time = _step_setting("sleep_time", "Seconds an island rests before it sleeps.")
    @property
    def threads(self) -> int:
        """Threads inside the world: with more than one, the stages that split by element (placing shapes,
        colliding pairs, filling the solver's lanes, the substeps of separate groups of islands) run in
        parts over up to this many threads, with a bitwise equal result for any count (`rustycs.threads`);
        at most numba's thread count is used."""
        return self._threads

    @threads.setter
    def threads(self, value: int) -> None:
        if not 1 <= int(value) <= defaults.MAX_THREADS:
            raise ValueError(f"threads must be from 1 to {defaults.MAX_THREADS}")
        self._threads = int(value)
        self._forget_stepper()

    contact_events = _step_setting("contact_events", "Whether contact_begin and contact_end events are "
                                                     "recorded (also on when a measure or stop condition "
                                                     "watches contacts).")

    @property
    def tick(self) -> int:
        """Ticks done since the world was made."""
        return int(self._clock[TICK])

    @property
    def escaped_count(self) -> int:
        """Bodies deactivated for leaving the bounds since the world was made."""
        return int(self._clock[ESCAPED_TOTAL])

    @property
    def stop_condition(self) -> int | None:
        """The stop condition that ended the last `step`, if any (`add_stop_condition`)."""
        stopped = int(self._status[STOPPED])
        return stopped if stopped >= 0 else None

    @property
    def body_count(self) -> int:
        return self._bodies.rows

    @property
    def sleep(self) -> bool:
        """Whether islands of bodies that rest together for `sleep_time` seconds sleep (`rustycs.sleep`)."""
        return self._sleep

    @sleep.setter
    def sleep(self, value: bool) -> None:
        self._sleep = bool(value)
        self._changed()  # the step's buffers hold the points of islands asleep only where they may sleep

    # ------------------------------------------------------------------ building
    def add_force(self, acceleration) -> None:
        """Add a constant acceleration felt by every dynamic body (gravity, wind), times its gravity
        scale."""
        self._gravity = self._gravity + np.asarray(acceleration, dtype=np.float64)
        self._remake()
        self.wake()  # a change of the forces reaches every body

    def add_attractor(self, position, mass: float, range: float | None = None,
                      min_distance: float = defaults.MIN_DISTANCE) -> None:
        """Add a fixed point pulling dynamic bodies; `range` None makes it global."""
        if not min_distance > 0:
            raise ValueError("min_distance must be > 0")
        self._remake()
        self.wake()
        self._attractors.append(dict(position=np.asarray(position, dtype=np.float64), mass=float(mass),
                                     range=np.inf if range is None else float(range),
                                     min_distance=float(min_distance)))

    @property
    def attractors(self) -> list[dict]:
        return [dict(a, position=a["position"].copy()) for a in self._attractors]

    def add_body(self, shapes: Shape | Sequence[Shape], position=(0.0, 0.0), angle: float = 0.0,
                 velocity=(0.0, 0.0), angular_velocity: float = 0.0, body_type: str = defaults.BODY_TYPE,
                 material: str | Material = defaults.MATERIAL, mass: float | None = None,
                 collision_group: int = defaults.COLLISION_GROUP,
                 collision_category: int = defaults.COLLISION_CATEGORY,
                 collision_mask: int = defaults.COLLISION_MASK,
                 linear_damping: float = defaults.LINEAR_DAMPING,
                 angular_damping: float = defaults.ANGULAR_DAMPING,
                 gravity_scale: float = defaults.GRAVITY_SCALE, fixed_rotation: bool = False,
                 bullet: bool = False, name: str | None = None, spawn_tick: int = 0,
                 remove_tick: int | None = None, if_free: bool = False) -> int:
        """Add a body made of one shape or several and return its index; `name` (unique, default
        `<shape type>-<index>`, "compound-<index>" for several shapes) names it in `body_names`.
        `position` is the body origin (the shapes' offsets and a polygon's vertices are relative to it);
        the body rotates about its centre of mass. A dynamic body needs a shape with area; `mass` scales
        the shapes' masses (area x density) to the given total. A body with `spawn_tick` > 0 is inactive
        until the end of that tick (an emitted body: its row is reserved now); with `remove_tick`, it is
        removed at the end of that tick; with `if_free`, it appears only if no collidable shape of an
        active body is within its bounding circle then (at tick 0: when the first step's inputs are built,
        in row order), and is otherwise skipped for good (`skipped`)."""
        one = isinstance(shapes, (Circle, Box, Polygon, Capsule, Segment, Chain))
        shapes = [shapes] if one else list(shapes)
        if not shapes:
            raise ValueError("a body needs at least one shape")
        body_name = self._new_name(name, type_name(shapes[0]) if len(shapes) == 1 else "compound",
                                   self._bodies.rows)
        if body_type not in _BODY_TYPES:
            raise ValueError(f"unknown body type {body_type!r}")
        code = _BODY_TYPES[body_type]
        moves = code == DYNAMIC
        if mass is not None and not (mass > 0 and math.isfinite(mass)):
            raise ValueError("mass must be > 0")
        if moves and not any(shape.has_area for shape in shapes):
            raise ValueError("a dynamic body needs at least one shape with area "
                             "(not a sensor, segment or chain)")
        for name, value in (("linear_damping", linear_damping), ("angular_damping", angular_damping)):
            if not (value >= 0 and math.isfinite(value)):
                raise ValueError(f"{name} must be >= 0")
        fixed_rotation = fixed_rotation or any(isinstance(s, Box) and not s.rotates for s in shapes)
        if fixed_rotation and any(isinstance(s, Box) and not s.rotates for s in shapes) and angle != 0.0:
            raise ValueError("an aabb cannot be rotated; use an obb")
        body_material = _material(material)
        materials = [body_material if s.material is None else _material(s.material) for s in shapes]
        pieces_of = [shape_pieces(shape) for shape in shapes]
        placed = [(shape, m, piece) for shape, m, pieces in zip(shapes, materials, pieces_of, strict=True)
                  for piece in pieces]
        pieces = [piece for _, _, piece in placed]
        props = body_mass(pieces, [m.density for _, m, _ in placed], [s.has_area for s, _, _ in placed],
                          mass if moves else None)
        rotates = moves and not fixed_rotation
        c, s = math.cos(angle), math.sin(angle)
        center = np.asarray(position, dtype=np.float64) + np.array([[c, -s], [s, c]]) @ props.center
        present = self._timing(spawn_tick, remove_tick, if_free)
        index = self._bodies.rows
        first_shape = self._shapes.rows
        extent = 0.0
        for shape, shape_material, piece in placed:
            k = len(piece.vertices)
            vertices = np.zeros((MAX_VERTICES, 2))
            normals = np.zeros((MAX_VERTICES, 2))
            vertices[:k] = piece.vertices - props.center
            if k > 1:
                normals[:k] = edge_normals(vertices[:k])
            core = np.vstack([vertices[:k], piece.centroid - props.center])
            extent = max(extent, float(np.max(np.hypot(core[:, 0], core[:, 1]))))
            group, category, mask = int(collision_group), int(collision_category), int(collision_mask)
            self._shapes.append(body=index, kind=piece.kind, radius=piece.radius, count=k, vertices=vertices,
                                normals=normals, centroid=piece.centroid - props.center,
                                ghosts=piece.ghosts - props.center, open_ends=piece.open_ends,
                                friction=shape_material.friction, restitution=shape_material.restitution,
                                sensor=shape.sensor, group=group, category=category, mask=mask)
        self._bodies.append(
            x=center, angle=angle, v=velocity, w=0.0 if fixed_rotation else angular_velocity,
            mass=props.mass if moves else np.inf, inertia=props.inertia if rotates else np.inf,
            inv_mass=1.0 / props.mass if moves else 0.0, inv_inertia=1.0 / props.inertia if rotates else 0.0,
            body_type=code, active=present, origin=-props.center, linear_damping=linear_damping,
            angular_damping=angular_damping, gravity_scale=gravity_scale, fixed_rotation=fixed_rotation,
            bullet=bullet, extent=extent, first_shape=first_shape,
            shape_count=self._shapes.rows - first_shape)
        self._piece_shapes += [self.shape_count + k for k, pieces in enumerate(pieces_of) for _ in pieces]
        self._shape_list += [(index, shape) for shape in shapes]
        self._name_body(body_name, index)
        self._changed()
        return index

    # ------------------------------------------------------------------ joints
    def _local(self, body: int, point: np.ndarray) -> np.ndarray:
        """A world point in a body's frame about its centre of mass (a world point for the world, -1)."""
        if body < 0:
            return point
        c, s = math.cos(self._bodies.columns["angle"][body]), math.sin(self._bodies.columns["angle"][body])
        dx, dy = point - self._bodies.columns["x"][body]
        return np.array([c * dx + s * dy, -s * dx + c * dy])

    def _body_index(self, body: int | None) -> int:
        if body is None:
            return -1
        if not 0 <= int(body) < self.body_count:
            raise ValueError(f"no body {body}: the world has {self.body_count}")
        return int(body)

    def _add_joint(self, kind: int, body_a: int | None, body_b: int | None, anchor_a, anchor_b, *,
                   axis=(1.0, 0.0), flags: int = 0, collide_connected: bool = False,
                   break_force: float | None = None, break_torque: float | None = None, **values) -> int:
        """Append a joint row: anchors are world points at the bodies' present poses; `values` fill
        setting columns by name (the rest stay inf, unused)."""
        a, b = self._body_index(body_a), self._body_index(body_b)
        if kind != J.GEAR and a == b:
            raise ValueError("a joint joins two different bodies")
        for name, limit in (("break_force", break_force), ("break_torque", break_torque)):
            if limit is not None and not limit > 0:
                raise ValueError(f"{name} must be > 0")
        settings = np.full(J.SETTING_COLUMNS, np.inf)
        for name, value in values.items():
            settings[getattr(J, name.upper())] = value
        settings[J.BREAK_FORCE] = np.inf if break_force is None else break_force
        settings[J.BREAK_TORQUE] = np.inf if break_torque is None else break_torque
        axis = _point(axis)
        if not np.hypot(*axis) > 0:
            raise ValueError("a joint's axis must not be zero")
        angle_a = self._bodies.columns["angle"][a] if a >= 0 else 0.0
        c, s = math.cos(angle_a), math.sin(angle_a)
        unit = axis / np.hypot(*axis)
        angles = self._bodies.columns["angle"]
        row = self._joints.append(
            kind=kind, body_a=a, body_b=b, local_a=self._local(a, _point(anchor_a)),
            local_b=self._local(b, _point(anchor_b)), axis=(c * unit[0] + s * unit[1],
                                                            -s * unit[0] + c * unit[1]),
            reference_angle=(angles[b] if b >= 0 else 0.0) - angle_a,
            flags=flags | (J.COLLIDE_CONNECTED if collide_connected else 0), settings=settings, active=True)
        self._changed()
        return row

    @staticmethod
    def _motion_flags(limits, motor_speed, spring_hertz) -> int:
        if limits is not None and not limits[0] <= limits[1]:
            raise ValueError("limits must be [lower, upper] with lower <= upper")
        if spring_hertz is not None and not spring_hertz >= 0:
            raise ValueError("a spring's hertz must be >= 0")
        return ((J.LIMIT if limits is not None else 0) | (J.MOTOR if motor_speed is not None else 0)
                | (J.SPRING if spring_hertz else 0))

    def add_revolute(self, body_a: int | None, body_b: int, anchor, *, limits=None, motor_speed=None,
                     max_motor_torque: float = 0.0, spring_hertz=None, spring_damping_ratio: float = 0.0,
                     **common) -> int:
        """The bodies share the world point `anchor` and turn freely about it; `limits` bound the joint
        angle (b's angle relative to a's, zero now), a motor drives it at `motor_speed` (rad/s) with at
        most `max_motor_torque`, a spring pulls it back to zero. `body_a` None: the fixed world. Common
        keywords of every joint: collide_connected, break_force, break_torque. Returns the joint index."""
        flags = self._motion_flags(limits, motor_speed, spring_hertz)
        lower, upper = limits if limits is not None else (np.inf, np.inf)
        return self._add_joint(J.REVOLUTE, body_a, body_b, anchor, anchor, flags=flags, lower=lower,
                               upper=upper, motor_speed=motor_speed or 0.0, max_motor=max_motor_torque,
                               hertz=spring_hertz or 0.0, damping_ratio=spring_damping_ratio, **common)

    def add_prismatic(self, body_a: int | None, body_b: int, anchor, axis, *, limits=None, motor_speed=None,
                      max_motor_force: float = 0.0, spring_hertz=None, spring_damping_ratio: float = 0.0,
                      **common) -> int:
        """b slides along `axis` (a world direction now, turning with a) without turning relative to a;
        limits, motor (m/s, at most `max_motor_force`) and spring act on the translation."""
        flags = self._motion_flags(limits, motor_speed, spring_hertz)
        lower, upper = limits if limits is not None else (np.inf, np.inf)
        return self._add_joint(J.PRISMATIC, body_a, body_b, anchor, anchor, axis=axis, flags=flags,
                               lower=lower, upper=upper, motor_speed=motor_speed or 0.0,
                               max_motor=max_motor_force, hertz=spring_hertz or 0.0,
                               damping_ratio=spring_damping_ratio, **common)

    def add_wheel(self, body_a: int | None, body_b: int, anchor, axis, *, spring_hertz=None,
                  spring_damping_ratio: float = 0.0, limits=None, motor_speed=None,
                  max_motor_torque: float = 0.0, **common) -> int:
        """A car's wheel: b slides along `axis` on a spring (the suspension; limits bound the translation)
        and turns freely, driven by a motor at `motor_speed` (rad/s) with at most `max_motor_torque`."""
        flags = self._motion_flags(limits, motor_speed, spring_hertz)
        lower, upper = limits if limits is not None else (np.inf, np.inf)
        return self._add_joint(J.WHEEL, body_a, body_b, anchor, anchor, axis=axis, flags=flags, lower=lower,
                               upper=upper, motor_speed=motor_speed or 0.0, max_motor=max_motor_torque,
                               hertz=spring_hertz or 0.0, damping_ratio=spring_damping_ratio, **common)

    def add_distance(self, body_a: int | None, body_b: int, anchors, *, length=None, min_length=None,
                     max_length=None, spring_hertz=None, spring_damping_ratio: float = 0.0, **common) -> int:
        """The anchor points (world points now, one on each body) stay `length` apart (default: as now):
        a rod, or with `spring_hertz` a spring, held between min_length and max_length."""
        pa, pb = _point(anchors[0]), _point(anchors[1])
        length = float(np.hypot(*(pb - pa))) if length is None else float(length)
        low = 0.0 if min_length is None else float(min_length)
        high = np.inf if max_length is None else float(max_length)
        if not (length >= 0 and 0 <= low <= high):
            raise ValueError("lengths must be >= 0 with min_length <= max_length")
        flags = self._motion_flags(None, None, spring_hertz)
        if flags & J.SPRING and (min_length is not None or max_length is not None):
            flags |= J.LIMIT
        return self._add_joint(J.DISTANCE, body_a, body_b, pa, pb, flags=flags, length=length, min_length=low,
                               max_length=high, hertz=spring_hertz or 0.0, damping_ratio=spring_damping_ratio,
                               **common)

    def add_rope(self, body_a: int | None, body_b: int, anchors, *, length=None, **common) -> int:
        """The anchor points are at most `length` apart (default: as now); slack is free."""
        pa, pb = _point(anchors[0]), _point(anchors[1])
        length = float(np.hypot(*(pb - pa))) if length is None else float(length)
        if not length >= 0:
            raise ValueError("a rope's length must be >= 0")
        return self._add_joint(J.ROPE, body_a, body_b, pa, pb, flags=J.LIMIT, min_length=0.0,
                               max_length=length, length=length, **common)

    def add_weld(self, body_a: int | None, body_b: int, anchor, *, linear_hertz: float = 0.0,
                 angular_hertz: float = 0.0, damping_ratio: float = 0.0, **common) -> int:
        """The bodies move as one; with a linear or angular hertz, softly (a spring about the pose of now)."""
        if not (linear_hertz >= 0 and angular_hertz >= 0 and damping_ratio >= 0):
            raise ValueError("a weld's hertz and damping ratio must be >= 0")
        return self._add_joint(J.WELD, body_a, body_b, anchor, anchor, hertz=linear_hertz,
                               angular_hertz=angular_hertz, damping_ratio=damping_ratio, **common)

    def add_pulley(self, body_a: int, body_b: int, anchors, ground_anchors, ratio: float = 1.0,
                   **common) -> int:
        """Two bodies hang from two fixed world points: length_a + ratio length_b stays as now (each length
        from a ground anchor to its body's anchor)."""
        pa, pb = _point(anchors[0]), _point(anchors[1])
        ga, gb = _point(ground_anchors[0]), _point(ground_anchors[1])
        if not ratio > 0:
            raise ValueError("a pulley's ratio must be > 0")
        constant = float(np.hypot(*(pa - ga)) + ratio * np.hypot(*(pb - gb)))
        return self._add_joint(J.PULLEY, body_a, body_b, pa, pb, ratio=ratio, constant=constant,
                               ground_ax=ga[0], ground_ay=ga[1], ground_bx=gb[0], ground_by=gb[1], **common)

    def add_gear(self, joint_1: int, joint_2: int, ratio: float = 1.0, **common) -> int:
        """Couples two revolute or prismatic joints: coordinate_1 + ratio coordinate_2 stays as now."""
        kinds = self._joints.columns["kind"]
        for joint in (joint_1, joint_2):
            if not (0 <= joint < self._joints.rows and kinds[joint] in (J.REVOLUTE, J.PRISMATIC)):
                raise ValueError(f"a gear couples revolute or prismatic joints; joint {joint} is not one")
        if joint_1 == joint_2:
            raise ValueError("a gear couples two different joints")
        coordinates = self.joint_coordinates
        constant = coordinates[joint_1] + ratio * coordinates[joint_2]
        b1, b2 = self._joints.columns["body_b"][joint_1], self._joints.columns["body_b"][joint_2]
        point = np.zeros(2)
        row = self._add_joint(J.GEAR, b1, b2, point, point, ratio=ratio, constant=constant, **common)
        self._joints.columns["joint_1"][row], self._joints.columns["joint_2"][row] = joint_1, joint_2
        return row

    def _remake(self) -> None:
        """The world's records changed: the kernels' records and the stepper are made again."""
        self._inputs = None
        self._forget_stepper()

    def _forget_stepper(self) -> None:
        """The stepper no longer holds the world as it is: it is made again before the next step."""
        self._stepper_frames = None
        World.edits += 1

    def _changed(self) -> None:
        """The world's make-up changed: the kernels' inputs and the step's buffers are made again (the
        warm-start cache carries over)."""
        self._remake()
        if self._workspace is not None:
            self._last_contacts()
            self._workspace = None
            self.wake()  # the new buffers hold no island asleep: they start awake, warm-started as they slept

    # joint state, numpy arrays of J rows in joint order
    @property
    def joint_count(self) -> int:
        return self._joints.rows

    @property
    def joint_types(self) -> np.ndarray:
        return np.array([JOINT_TYPE_NAMES[k] for k in self._joints.columns["kind"][: self.joint_count]])

    @property
    def joint_bodies(self) -> np.ndarray:
        """(J, 2) the bodies of each joint (-1: the fixed world; a gear: its joints' second bodies)."""
        columns = self._joints.columns
        return np.stack([columns["body_a"][: self.joint_count], columns["body_b"][: self.joint_count]],
                        axis=1)

    @property
    def joint_coordinates(self) -> np.ndarray:
        """(J,) each joint's coordinate now, zero when it was made: the angle of a revolute or weld joint
        (rad), the translation along the axis of a prismatic or wheel joint, the anchors' distance of a
        distance or rope joint, the length_a + ratio length_b of a pulley (m), a gear's coupled sum."""
        inputs = self._kernel_inputs()
        from rustycs.joint_solver import joint_coordinates

        return joint_coordinates(inputs.bodies, inputs.joints)

    @property
    def joint_reaction_forces(self) -> np.ndarray:
        """(J, 2) the force each joint applied to its second body in the last tick, N."""
        return self._joints.columns["reaction"][: self.joint_count, J.FORCE_X:J.FORCE_Y + 1].copy()

    @property
    def joint_reaction_torques(self) -> np.ndarray:
        """(J,) the torque each joint applied to its second body in the last tick beyond its force's
        moment, N m."""
        return self._joints.columns["reaction"][: self.joint_count, J.TORQUE].copy()

    @property
    def joint_active(self) -> np.ndarray:
        """(J,) bool: false once the joint broke."""
        return self._joints.columns["active"][: self.joint_count].copy()

    def events(self) -> dict[str, np.ndarray]:
        """The events of the last `step` call, in order: tick, kind (str), a and b (bodies; for a
        joint_break, a is the joint), point (E, 2) and speed."""
        from rustycs.events import new_events

        events = new_events(0) if self._workspace is None else self._workspace.events
        n = int(events.count[0])
        return dict(tick=events.tick[:n].copy(),
                    kind=np.array([EVENT_KIND_NAMES[k] for k in events.kind[:n]]), a=events.a[:n].copy(),
                    b=events.b[:n].copy(), point=events.point[:n].copy(), speed=events.speed[:n].copy())

    # ------------------------------------------------------------------ stepping
    def _kernel_inputs(self) -> KernelInputs:
        """The records the kernels take, built once per change of the world's make-up, so that stepping
        and recording tick by tick cost little Python."""
        if self._inputs is None:
            att = self._attractors
            forces = Forces(
                gravity=self._gravity,
                attractor_position=np.array([t["position"] for t in att], dtype=np.float64).reshape(-1, 2),
                attractor_gm=np.array([self.gravitational_constant * t["mass"] for t in att],
                                      dtype=np.float64),
                attractor_range=np.array([t["range"] for t in att], dtype=np.float64),
                attractor_min_distance=np.array([t["min_distance"] for t in att], dtype=np.float64))
            joints = self._joints.view()
            bodies, shapes = self._bodies.view(), self._shapes.view()
            self._inputs = KernelInputs(bodies, shapes, joints, joint_filter(self.body_count, joints), forces,
                                        self._scenario(bodies, shapes))
        return self._inputs

    def _settings(self, inputs: KernelInputs) -> Settings:
        """How the world steps, made again only when a setting or the world's make-up changed."""
        key = (self.dt, self.precision, self.restitution_threshold, self.bounds, self.contact_events,
               self.sleep_time, self.threads)
        if self._settings_for is None or self._settings_for[0] is not inputs or self._settings_for[1] != key:
            bounds = np.zeros(4) if self.bounds is None else np.array([*self.bounds[0], *self.bounds[1]])
            settings = Settings(self.dt, self.precision, self.restitution_threshold, bounds,
                                self.bounds is not None, self._records_contacts(), self._sleep,
                                self.sleep_time, self.threads)
            self._settings_for = inputs, key, settings
        return self._settings_for[2]

    def step(self, n: int = 1, record: dict[str, np.ndarray] | None = None, every: int = 1) -> int:
        """Advance n ticks in compiled code. Raises SimulationDiverged on a non-finite state.

        With `record` (a `frame_buffer`), the state after every `every`-th tick and after the last is
        written into its rows from 0 on, with no Python per tick; returns the number of frames
        written. The buffer must hold them all: ceil(n / every) rows. A stop condition that holds ends
        the call early, after the tick where it held (its frame recorded): `stop_condition` names it.
        """
        if n <= 0:
            return 0
        if record is None:
            every = 0
            frames = self._no_frames
        else:
            frames = self._frames(record, -(-n // every))
        if frames is not self._stepper_frames:  # else the stepper holds the world as it is
            self._prepare(frames)
        if self._threads > 1:  # numba's thread count is the calling thread's
            numba.set_num_threads(min(self._threads, numba.config.NUMBA_NUM_THREADS))
        if self._entry(self._stepper, n, every):
            self._workspace_replaced()
        if self._status.item(BAD_BODY) >= 0:  # `item`: no numpy scalar (a tenth of a 5-body step(1))
            raise self._divergence()
        return 0 if record is None else self._status.item(FRAMES)

    def _workspace_replaced(self) -> None:
        """Take the workspace the step grew (boxing it back costs about 80 us: only when it was replaced)."""
        self._workspace = workspace_of(self._stepper)

    def _divergence(self) -> SimulationDiverged:
        """The error of a step whose state became non-finite."""
        body = int(self._status[BAD_BODY])
        return SimulationDiverged(self.tick, body, f"non-finite state in tick {self.tick} at body {body}",
                                  int(self._status[FRAMES]))

    def prepare(self) -> None:
        """Make what stepping needs now instead of in the next `step`: the kernels' records, the step's
        buffers and its compiled entry (loaded, or compiled on first use), so that a timed step does no
        setup (0.9 ms of a five-body world's first block of 100 ticks). Nothing of the state changes."""
        self._prepare(self._no_frames)

    def _prepare(self, frames: tuple) -> None:
        """Make the stepper for the world as it is and these frames, and the step's compiled entry."""
        inputs = self._kernel_inputs()
        if self._workspace is None:
            last = self._last_contacts()
            self._workspace = new_workspace(self.body_count, inputs.shapes, self._joints.rows,
                                            MAX_VERTICES, last.key, last.normal_impulse, last.tangent_impulse,
                                            self.sleep, numba.config.NUMBA_NUM_THREADS)
        self._fold_initial(inputs)
        self._stepper = new_stepper(*inputs[:5], self._settings(inputs), self._workspace, inputs.scenario,
                                    frames, self._status, self._clock)
        self._stepper_frames = frames
        World.edits += 1
        # zero ticks through numba's dispatcher: it loads (or compiles) the kernel; then its entry
        step_world(self._stepper, 0, 0)
        self._entry = compiled_entry(step_world, (self._stepper, 0, 0))

    def _frames(self, record: dict[str, np.ndarray], needed: int) -> tuple:
        """A frame buffer's arrays as the step writes them, once checked to be one of this world's with
        room for `needed` frames: the step's compiled entry takes them as they come."""
        if record is not self._checked_record[0]:
            check_frame_buffer(record, self.body_count, self._joints.rows)
            self._checked_record = record, tuple(record.values())
        if len(record["tick"]) < needed:
            raise ValueError(f"a frame buffer of {len(record['tick'])} rows cannot hold {needed} frames")
        return self._checked_record[1]

    def load_kernels(self) -> None:
        """Step once, so that a timed step loads no kernel (the step's entry grows its buffers itself: the
        growth kernel, loaded inside the first block of the 210-box pyramid, took 31 of its 45 ms)."""
        self.step(1)

    def frame_buffer(self, capacity: int) -> dict[str, np.ndarray]:
        """An empty buffer for `capacity` frames of this world (see `step` and `capture`)."""
        return frame_buffer(capacity, self.body_count, self._joints.rows)

    def capture(self, frames: dict[str, np.ndarray], row: int = 0) -> None:
        """Write the current state into row `row` of a frame buffer, as `step` does after a tick."""
        from rustycs.recording import record_frame

        inputs = self._kernel_inputs()
        record_frame(tuple(frames.values()), row, self.tick, inputs.bodies, inputs.joints, inputs.forces,
                     self._contacts_record())

    def _contacts_record(self):
        """The last tick's contacts (the step's record; none before the first step)."""
        if self._workspace is None:
            from rustycs.narrow_phase import new_contacts, no_sleeping_points

            return new_contacts(0, False, no_sleeping_points())
        return self._workspace.contacts

    # ------------------------------------------------------------------ state
    def _get(self, name: str) -> np.ndarray:
        return self._bodies.columns[name][: self.body_count].copy()

    @property
    def centers(self) -> np.ndarray:
        """Centres of mass."""
        return self._get("x")

    @property
    def positions(self) -> np.ndarray:
        """Body origins: the centre of mass plus the rotated offset to the origin."""
        from rustycs.observables import body_origins

        return body_origins(self._kernel_inputs().bodies)

    @property
    def angles(self) -> np.ndarray:
        return self._get("angle")

    @property
    def velocities(self) -> np.ndarray:
        return self._get("v")

    @property
    def angular_velocities(self) -> np.ndarray:
        return self._get("w")

    @property
    def active(self) -> np.ndarray:
        return self._get("active")

    @property
    def masses(self) -> np.ndarray:
        return self._get("mass")

    @property
    def inertias(self) -> np.ndarray:
        return self._get("inertia")

    @property
    def local_centers(self) -> np.ndarray:
        """Each body's centre of mass in its own frame, relative to its origin."""
        return -self._get("origin")

    @property
    def body_types(self) -> np.ndarray:
        return np.array([BODY_TYPE_NAMES[t] for t in self._get("body_type")])

    @property
    def shape_kinds(self) -> np.ndarray:
        """Per body, its shape's type, or "compound" for a body of several shapes."""
        kinds: list[list[str]] = [[] for _ in range(self.body_count)]
        for body, shape in self._shape_list:
            kinds[body].append(type_name(shape))
        return np.array([k[0] if len(k) == 1 else "compound" for k in kinds])

    # the shapes as given, one row each (S rows, in body order)
    @property
    def shape_count(self) -> int:
        return len(self._shape_list)

    @property
    def shapes(self) -> list[tuple[int, Shape]]:
        """(body, shape) of every shape, as given to `add_body`."""
        return list(self._shape_list)

    def set_velocity(self, body: Body, velocity, angular_velocity: float | None = None) -> None:
        """Set a body's velocity (e.g. to drive a kinematic body); a body of fixed rotation keeps w = 0."""
        body = self._row(body)
        self._wake_row(body)
        self._bodies.columns["v"][body] = velocity
        if angular_velocity is not None and not self._bodies.columns["fixed_rotation"][body]:
            self._bodies.columns["w"][body] = angular_velocity

    def observables(self) -> dict:
        """Energies and momenta of the dynamic bodies and their fastest speed; contact count and
        deepest overlap of the last tick."""
        from rustycs.recording import OBSERVABLE_FIELDS

        frames = self.frame_buffer(1)
        self.capture(frames)
        return {name: frames[name][0].copy() if frames[name].ndim > 1 else frames[name][0].item()
                for name in OBSERVABLE_FIELDS}

    def _last_contacts(self):
        """The last tick's contact points as named columns (`narrow_phase.ContactRows`)."""
        if self._contact_rows is None or self._contact_rows_tick != self.tick:
            from rustycs.narrow_phase import contact_rows

            self._contact_rows = contact_rows(self._contacts_record())
            self._contact_rows_tick = self.tick
        return self._contact_rows

    def contacts(self) -> dict:
        """The last tick's touching contact points (overlapping or carrying load), sorted by key."""
        rows = self._last_contacts()
        touching = (rows.separation <= 0.0) | (rows.normal_impulse > 0.0)
        return dict(body_a=rows.body_a[touching].astype(np.int32),
                    body_b=rows.body_b[touching].astype(np.int32), point=rows.point[touching].copy(),
                    normal=rows.normal[touching].copy(), depth=np.maximum(-rows.separation[touching], 0.0),
                    normal_impulse=rows.normal_impulse[touching].copy())
