"""The pythonic World: build a scene body by body, step it in compiled blocks, read its state."""

from __future__ import annotations

import numpy as np

from rustycs.body_types import BODY_TYPE_NAMES, DYNAMIC
from rustycs.kernel_cache import ensure_fresh
from rustycs.materials import MATERIALS, Material
from rustycs.shapes import AABB, KIND_NAMES, MAX_VERTICES, Shape, mass_properties

_BODY_TYPES = {name: code for code, name in enumerate(BODY_TYPE_NAMES)}


class SimulationDiverged(RuntimeError):
    """A non-finite value appeared in the state: `tick` (1-based, the tick that failed) and `body`."""

    def __init__(self, tick: int, body: int, message: str, frames: int = 0):
        self.tick = tick
        self.body = body
        self.frames = frames  # frames recorded by the failing `step` call before the bad tick
        super().__init__(message)


def _grow(array: np.ndarray, rows: int) -> np.ndarray:
    grown = np.zeros((rows,) + array.shape[1:], dtype=array.dtype)
    grown[: len(array)] = array
    return grown


class World:
    """A 2D world of rigid bodies.

    Each tick is dt = 1/tick_rate long and runs `precision` solver substeps. Attractors pull with
    the acceleration G*M/max(d, min_distance)^2; forces are constant accelerations.
    """

    _FIELDS = {  # per-body arrays: trailing shape and dtype
        "x": ((2,), np.float64), "angle": ((), np.float64), "v": ((2,), np.float64),
        "w": ((), np.float64), "inv_mass": ((), np.float64), "inv_inertia": ((), np.float64),
        "mass": ((), np.float64), "inertia": ((), np.float64), "body_type": ((), np.int64),
        "kind": ((), np.int64), "radius": ((), np.float64), "nverts": ((), np.int64),
        "local_verts": ((MAX_VERTICES, 2), np.float64), "local_normals": ((MAX_VERTICES, 2), np.float64),
        "origin_offset": ((2,), np.float64), "restitution": ((), np.float64),
        "friction": ((), np.float64), "active": ((), np.bool_), "group": ((), np.int64),
    }

    def __init__(self, tick_rate: float = 60.0, precision: int = 10, gravitational_constant: float = 1.0,
                 bounds=None, restitution_threshold: float = 1.0):
        if not tick_rate > 0:
            raise ValueError("tick_rate must be > 0")
        if int(precision) < 1:
            raise ValueError("precision must be >= 1")
        self.tick_rate = float(tick_rate)
        self.dt = 1.0 / self.tick_rate
        self.precision = int(precision)
        self.gravitational_constant = float(gravitational_constant)
        self.bounds = None if bounds is None else (tuple(map(float, bounds[0])), tuple(map(float, bounds[1])))
        self.restitution_threshold = float(restitution_threshold)
        self.tick = 0
        self.escaped_count = 0
        self.body_count = 0
        self._gravity = np.zeros(2)
        self._inputs: dict | None = None  # the kernels' inputs, rebuilt when bodies or forces change
        self._attractors: list[dict] = []
        self._a = {name: np.zeros((0,) + shape, dtype) for name, (shape, dtype) in self._FIELDS.items()}
        # the step's buffers, kept from block to block (rebuilt when bodies are added)
        self._workspace: tuple | None = None
        # the last tick's contact points, one array per column, built from the workspace when asked
        self._contact_rows = (np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0, np.int64),
                              np.zeros((0, 2)), np.zeros((0, 2)), np.zeros(0), np.zeros(0), np.zeros(0))
        self._contact_rows_stale = False
        self._no_frames: dict[str, np.ndarray] | None = None  # the step's buffer when nothing is recorded

    # ------------------------------------------------------------------ building
    def add_force(self, acceleration) -> None:
        """Add a constant acceleration felt by every dynamic body (gravity, wind)."""
        self._gravity = self._gravity + np.asarray(acceleration, dtype=np.float64)
        self._inputs = None

    def add_attractor(self, position, mass: float, range: float | None = None,
                      min_distance: float = 0.01) -> None:
        """Add a fixed point pulling dynamic bodies; `range` None makes it global."""
        if not min_distance > 0:
            raise ValueError("min_distance must be > 0")
        self._inputs = None
        self._attractors.append(dict(position=np.asarray(position, dtype=np.float64), mass=float(mass),
                                     range=np.inf if range is None else float(range),
                                     min_distance=float(min_distance)))

    @property
    def attractors(self) -> list[dict]:
        return [dict(a, position=a["position"].copy()) for a in self._attractors]

    def add_body(self, shape: Shape, position=(0.0, 0.0), angle: float = 0.0, velocity=(0.0, 0.0),
                 angular_velocity: float = 0.0, body_type: str = "dynamic",
                 material: str | Material = "default", mass: float | None = None,
                 collision_group: int = 0) -> int:
        """Add a body and return its index. `position` is the body origin (a polygon's vertices are
        relative to it); the body rotates about its centre of mass."""
        if body_type not in _BODY_TYPES:
            raise ValueError(f"unknown body type {body_type!r}")
        mat = MATERIALS[material] if isinstance(material, str) else material
        props = mass_properties(shape)
        kind = props.kind
        if kind == AABB and angle != 0.0:
            raise ValueError("an aabb cannot be rotated; use an obb")
        if mass is not None and not mass > 0:
            raise ValueError("mass must be > 0")
        body_mass = float(mass) if mass is not None else props.area * mat.density
        inertia = props.unit_inertia * body_mass / props.area
        code = _BODY_TYPES[body_type]
        moves = code == DYNAMIC
        i = self.body_count
        if i == len(self._a["x"]):
            for name in self._a:
                self._a[name] = _grow(self._a[name], max(8, 2 * i))
        a = self._a
        c, s = np.cos(angle), np.sin(angle)
        rotation = np.array([[c, -s], [s, c]])
        centroid = rotation @ props.centroid
        a["x"][i] = np.asarray(position, dtype=np.float64) + centroid
        a["angle"][i] = angle
        a["v"][i] = velocity
        a["w"][i] = 0.0 if kind == AABB else angular_velocity
        a["mass"][i] = body_mass if moves else np.inf
        a["inertia"][i] = inertia if moves and kind != AABB else np.inf
        a["inv_mass"][i] = 1.0 / body_mass if moves else 0.0
        a["inv_inertia"][i] = 1.0 / inertia if moves and kind != AABB else 0.0
        a["body_type"][i] = code
        a["kind"][i] = kind
        a["radius"][i] = props.radius
        k = len(props.vertices)
        a["nverts"][i] = k
        a["local_verts"][i] = 0.0
        a["local_normals"][i] = 0.0
        if k:
            verts = props.vertices
            edges = np.roll(verts, -1, axis=0) - verts
            normals = np.stack([edges[:, 1], -edges[:, 0]], axis=1)
            a["local_verts"][i, :k] = verts
            a["local_normals"][i, :k] = normals / np.linalg.norm(normals, axis=1)[:, None]
        a["origin_offset"][i] = -props.centroid
        a["restitution"][i] = mat.restitution
        a["friction"][i] = mat.friction
        a["active"][i] = True
        a["group"][i] = collision_group
        self.body_count += 1
        self._inputs = None
        if self._workspace is not None:  # sized for the old body count; its warm-start cache carries over
            self._last_contacts()
            self._workspace = None
        return i

    # ------------------------------------------------------------------ stepping
    def _kernel_inputs(self) -> dict:
        """The arrays the kernels take, built once per change of the world's make-up, so that stepping
        and recording tick by tick cost little Python."""
        if self._inputs is None:
            k = self.body_count
            att = self._attractors
            self._inputs = dict(
                {name: arr[:k] for name, arr in self._a.items()},
                gravity=self._gravity,
                att_pos=np.array([t["position"] for t in att], dtype=np.float64).reshape(-1, 2),
                att_gm=np.array([self.gravitational_constant * t["mass"] for t in att], dtype=np.float64),
                att_range=np.array([t["range"] for t in att], dtype=np.float64),
                att_min=np.array([t["min_distance"] for t in att], dtype=np.float64),
            )
        return self._inputs

    def _settings(self) -> np.ndarray:
        settings = np.zeros(8)
        settings[0] = self.dt
        settings[1] = self.precision
        settings[2] = self.restitution_threshold
        if self.bounds is not None:
            settings[3] = 1.0
            settings[4:8] = (*self.bounds[0], *self.bounds[1])
        return settings

    def step(self, n: int = 1, record: dict[str, np.ndarray] | None = None, every: int = 1) -> int:
        """Advance n ticks in compiled code. Raises SimulationDiverged on a non-finite state.

        With `record` (a `frame_buffer`), the state after every `every`-th tick and after the last is
        written into its rows from 0 on, with no Python per tick; returns the number of frames
        written. The buffer must hold them all: ceil(n / every) rows.
        """
        ensure_fresh()
        from rustycs.step import new_workspace, step_world

        if n <= 0:
            return 0
        a = self._kernel_inputs()
        if record is None:
            every = 0
            record = self._no_frames = self._no_frames or self.frame_buffer(0)
        elif len(record["tick"]) < -(-n // every):
            raise ValueError(f"a frame buffer of {len(record['tick'])} rows cannot hold {-(-n // every)} "
                             "frames")
        if self._workspace is None:
            key, *_, jn, jt = self._last_contacts()
            self._workspace = new_workspace(self.body_count, a["local_verts"].shape[1], key, jn, jt)
        bad, done, escaped, recorded, self._workspace = step_world(
            n, a["x"], a["angle"], a["v"], a["w"], a["inv_mass"], a["inv_inertia"], a["body_type"],
            a["kind"], a["radius"], a["nverts"], a["local_verts"], a["local_normals"], a["restitution"],
            a["friction"], a["active"], a["group"], a["gravity"], a["att_pos"], a["att_gm"], a["att_range"],
            a["att_min"], self._settings(), self._workspace, a["mass"], a["inertia"], a["origin_offset"],
            self.tick, every, tuple(record.values()))
        self._contact_rows_stale = True
        self.escaped_count += escaped
        if bad >= 0:
            self.tick += done + 1
            raise SimulationDiverged(self.tick, int(bad),
                                     f"non-finite state in tick {self.tick} at body {int(bad)}", recorded)
        self.tick += done
        return recorded

    def frame_buffer(self, capacity: int) -> dict[str, np.ndarray]:
        """An empty buffer for `capacity` frames of this world (see `step` and `capture`)."""
        from rustycs.recording import frame_buffer

        return frame_buffer(capacity, self.body_count)

    def capture(self, frames: dict[str, np.ndarray], row: int = 0) -> None:
        """Write the current state into row `row` of a frame buffer, as `step` does after a tick."""
        from rustycs.recording import record_frame

        a = self._kernel_inputs()
        _, _, _, _, _, sep, jn, _ = self._last_contacts()
        record_frame(tuple(frames.values()), row, self.tick, a["x"], a["angle"], a["v"], a["w"], a["active"],
                     a["body_type"], a["mass"], a["inertia"], a["inv_inertia"], a["origin_offset"],
                     a["gravity"], a["att_pos"], a["att_gm"], a["att_range"], a["att_min"], sep, jn)

    # ------------------------------------------------------------------ state
    def _get(self, name: str) -> np.ndarray:
        return self._a[name][: self.body_count].copy()

    @property
    def centers(self) -> np.ndarray:
        return self._get("x")

    @property
    def positions(self) -> np.ndarray:
        """Body origins: the centre of mass plus the rotated offset to the origin."""
        from rustycs.observables import body_origins

        k = self.body_count
        return body_origins(self._a["x"][:k], self._a["angle"][:k], self._a["origin_offset"][:k])

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
    def radii(self) -> np.ndarray:
        return self._get("radius")

    @property
    def vertex_counts(self) -> np.ndarray:
        return self._get("nverts")

    @property
    def local_vertices(self) -> np.ndarray:
        """Unrotated vertices relative to the body origin (the rest shape)."""
        verts = self._get("local_verts")
        off = self._get("origin_offset")
        counts = self._get("nverts")
        mask = np.arange(MAX_VERTICES)[None, :] < counts[:, None]
        return np.where(mask[:, :, None], verts - off[:, None, :], 0.0)

    @property
    def shape_kinds(self) -> np.ndarray:
        return np.array([KIND_NAMES[k] for k in self._get("kind")])

    @property
    def body_types(self) -> np.ndarray:
        return np.array([BODY_TYPE_NAMES[t] for t in self._get("body_type")])

    def set_velocity(self, body: int, velocity, angular_velocity: float | None = None) -> None:
        """Set a body's velocity (e.g. to drive a kinematic body)."""
        self._a["v"][body] = velocity
        if angular_velocity is not None and self._a["kind"][body] != AABB:
            self._a["w"][body] = angular_velocity

    def observables(self) -> dict:
        """Energies and momenta of the dynamic bodies and their fastest speed; contact count and
        deepest overlap of the last tick."""
        from rustycs.recording import OBSERVABLE_FIELDS

        frames = self.frame_buffer(1)
        self.capture(frames)
        return {name: frames[name][0].copy() if frames[name].ndim > 1 else frames[name][0].item()
                for name in OBSERVABLE_FIELDS}

    def _last_contacts(self) -> tuple:
        """The last tick's contact points as columns: key, body a, body b, point, normal, separation,
        normal and tangent impulse."""
        if self._contact_rows_stale:
            from rustycs.step import last_contacts

            self._contact_rows = last_contacts(self._workspace)
            self._contact_rows_stale = False
        return self._contact_rows

    def contacts(self) -> dict:
        """The last tick's touching contact points (overlapping or carrying load), sorted by key."""
        key, a, b, point, normal, sep, jn, _ = self._last_contacts()
        touching = (sep <= 0.0) | (jn > 0.0)
        return dict(body_a=a[touching].astype(np.int32), body_b=b[touching].astype(np.int32),
                    point=point[touching].copy(), normal=normal[touching].copy(),
                    depth=np.maximum(-sep[touching], 0.0), normal_impulse=jn[touching].copy())
