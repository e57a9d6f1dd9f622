"""HDF5 trajectory files (H5MD 1.1, dimension 2): writing a run frame by frame, and reading one back.

The layout is the spec's (trajectory-format.md), /shapes written by `shape_table`, the joint table by
`trajectory_joints` and /events by `trajectory_events`. Additions beyond the spec, for the renderer and
analysis:

    /particles/bodies/local_center    float64 [N, 2]    the centre of mass in the body's frame, about its
                                                        origin (where velocities apply)
    /particles/bodies/collision_group int32 [N]         same non-zero group: never collide
    /shapes/loop                      bool [S]          a chain closed from its last point to its first
    /world/attractors/name            str [A]
    /world/attractors/position        float64 [A, 2]
    /world/attractors/mass, range, min_distance  float64 [A]  (range inf for a global attractor)
    /world/bounds                     float64 [2, 2]    [[xmin, ymin], [xmax, ymax]], only when set
    /particles/bodies/asleep/value    bool [T, N]       the body sleeps in that frame (world.sleep), with
                                                        step and time linked like active's
    /observables/*/step, time         hard links to /particles/bodies/position/step and time
    /parameters                       extra attrs: ticks_requested, every, contacts, gravitational_constant,
                                      frames, and `divergence` (the engine's message) when diverged

Frames are buffered in memory a block at a time and appended to resizable datasets chunked along time,
so memory stays bounded whatever the run length. The file is written as `.NAME.tmp-PID` in the output
folder and renamed when finished, so a half-written file never carries the final name; it is flushed to a
consistent state every RECOVERY_SECONDS, so that `rustycs recover` can save the frames of a killed run.
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .errors import UserError
from .trajectory_events import EventWriter
from .trajectory_joints import FRAME_FIELDS, JOINT_SERIES, JointDrawing, frame_joints, write_joint_table

if TYPE_CHECKING:  # imported lazily at run time, so that `rustycs --help` stays fast
    import h5py
    import numpy as np

CREATOR = "rustycs"
POSITION = "particles/bodies/position/value"
HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"
HDF5_SUFFIXES = (".h5", ".hdf5", ".he5")


def open_trajectory(path: str | Path) -> h5py.File:
    """Open a rustycs trajectory read-only (use it as a context manager).

    Raises UserError("PATH: ...") when the file is missing or unreadable, is not HDF5, or is an HDF5
    file that rustycs did not write, so every command reading runs reports bad input the same way.
    """
    import h5py

    from .trajectory_checks import damage

    path = Path(path)
    if not path.exists():
        raise UserError(f"{path}: no such file")
    if path.is_dir():
        raise UserError(f"{path}: is a folder, not a trajectory file")
    if not os.access(path, os.R_OK):
        raise UserError(f"{path}: permission denied")
    try:
        file = h5py.File(path, "r")
    except OSError as err:
        if not _has_hdf5_signature(path):
            raise UserError(f"{path}: not an HDF5 file (expected a rustycs trajectory .h5)") from None
        raise UserError(f"{path}: unreadable or corrupt HDF5 file ({err})") from None
    try:
        problem = _foreign_reason(file) or damage(file)
    except (OSError, KeyError, RuntimeError, ValueError, TypeError) as err:  # damaged metadata
        problem = f"corrupt HDF5 file ({err})"
    if problem:
        file.close()
        raise UserError(f"{path}: {problem}{_temporary_hint(path)}")
    return file


def _temporary_hint(path: Path) -> str:
    """For the temporary file of a run: how to save its frames."""
    from .output_files import TEMPORARY_NAME

    if TEMPORARY_NAME.match(path.name):
        return f"; it is the temporary file of a run: `rustycs recover {path}` saves its frames"
    return ""


def _has_hdf5_signature(path: Path) -> bool:
    """True when the file starts like HDF5 (so an open failure means corruption, not a foreign format)."""
    try:
        with open(path, "rb") as handle:
            return handle.read(8) == HDF5_SIGNATURE
    except OSError:
        return False


def looks_like_trajectory(path: str | Path) -> bool:
    """True for a path meant as a trajectory (an .h5/.hdf5 name or HDF5 content) rather than a scene."""
    path = Path(path)
    return path.suffix.lower() in HDF5_SUFFIXES or (path.is_file() and _has_hdf5_signature(path))


def _foreign_reason(file: h5py.File) -> str | None:
    """Why an open HDF5 file is not a rustycs trajectory, or None when it is one."""
    if "h5md" not in file:
        return "not a rustycs trajectory (no /h5md group: not an H5MD file)"
    creator = file["h5md"].get("creator")
    name = _text(creator.attrs.get("name")) if creator is not None else None
    if name != CREATOR:
        return f"not a rustycs trajectory (H5MD creator is {name!r}, expected {CREATOR!r})"
    if POSITION not in file:
        return f"not a rustycs trajectory (missing /{POSITION})"
    return None


def _text(value: object) -> str | None:
    """An HDF5 string attribute as str (h5py returns str or bytes depending on how it was written)."""
    if isinstance(value, bytes):
        return value.decode("utf-8", "replace")
    return None if value is None else str(value)


FRAME_SERIES = {  # name: (per-body row shape, dtype, unit); value [T, N, *shape]
    "position": ((2,), "f8", "m"),
    "velocity": ((2,), "f8", "m s-1"),
    "angle": ((), "f8", "rad"),
    "angular_velocity": ((), "f8", "rad s-1"),
    "active": ((), "bool", None),
    "asleep": ((), "bool", None),
}
ADDED_SERIES = ("asleep",)  # absent from files written before they existed: read as all false (`read_series`)
OBSERVABLES = {  # name: (shape, dtype, unit); value [T, *shape]
    "kinetic_energy": ((), "f8", "J"),
    "potential_energy": ((), "f8", "J"),
    "linear_momentum": ((2,), "f8", "kg m s-1"),
    "angular_momentum": ((), "f8", "kg m2 s-1"),
    "contact_count": ((), "i8", None),
    "max_penetration": ((), "f8", "m"),
}
CONTACT_FIELDS = {  # name: (row shape, dtype, unit); [C, *shape]
    "body_a": ((), "i4", None),
    "body_b": ((), "i4", None),
    "point": ((2,), "f8", "m"),
    "normal": ((2,), "f8", None),
    "depth": ((), "f8", "m"),
    "normal_impulse": ((), "f8", "N s"),
}
BLOCK_FRAMES = 64  # frames held in memory before they are appended to the file
FLUSH_FRAMES = 4 * BLOCK_FRAMES  # the same when whole blocks are appended (`append_block`)
CHUNK_FRAMES = BLOCK_FRAMES  # frames per chunk (a block fills whole chunks), fewer when a frame is large
CHUNK_BYTES = 1 << 20  # so that a chunk fits h5py's default chunk cache
CONTACT_CHUNK_ROWS = 4096
RECOVERY_SECONDS = 5.0  # the temporary file is flushed to a consistent state this often (`rustycs recover`)


@dataclass(frozen=True)
class Frame:
    """One recorded state of the world: what the file stores and what the summary is computed from."""

    tick: int
    position: np.ndarray
    velocity: np.ndarray
    angle: np.ndarray
    angular_velocity: np.ndarray
    active: np.ndarray
    asleep: np.ndarray
    observables: dict[str, Any]
    contacts: dict[str, np.ndarray] | None
    joints: dict[str, np.ndarray] | None = None  # JOINT_SERIES by name, per joint

    @classmethod
    def capture(cls, world: Any, contacts: bool) -> Frame:
        """The world's current state (and its last tick's contacts when `contacts`)."""
        frames = world.frame_buffer(1)
        world.capture(frames)
        return cls.from_buffer(frames, 0, world.contacts() if contacts else None)

    @classmethod
    def from_buffer(cls, frames: dict[str, np.ndarray], row: int,
                    contacts: dict[str, np.ndarray] | None) -> Frame:
        """A copy of row `row` of a frame buffer filled by `World.step(record=...)` or `World.capture`."""
        return cls(
            tick=int(frames["tick"][row]),
            position=frames["position"][row].copy(),
            velocity=frames["velocity"][row].copy(),
            angle=frames["angle"][row].copy(),
            angular_velocity=frames["angular_velocity"][row].copy(),
            active=frames["active"][row].copy(),
            asleep=frames["asleep"][row].copy(),
            # copies: the buffer's rows are overwritten by the next block (the momentum is a view)
            observables={name: frames[name][row].copy() for name in (*OBSERVABLES, "max_speed")},
            contacts=contacts,
            joints=frame_joints(frames, row),
        )


def temporary_path(path: Path) -> Path:
    """Where an output is written before its atomic rename: hidden, same folder, unique per process."""
    return path.with_name(f".{path.name}.tmp-{os.getpid()}")


class _Growing:
    """A dataset growing along its first axis; rows wait in an in-memory buffer until `flush`."""

    def __init__(self, group: h5py.Group, name: str, row_shape: tuple[int, ...], dtype: str,
                 chunk_rows: int, options: dict[str, Any], unit: str | None = None):
        import numpy as np

        self.dataset = group.create_dataset(
            name,
            shape=(0, *row_shape),
            maxshape=(None, *(size or None for size in row_shape)),
            chunks=(chunk_rows, *(max(size, 1) for size in row_shape)),
            dtype=dtype,
            **options,
        )
        if unit:
            self.dataset.attrs["unit"] = unit
        self.buffer = np.empty((BLOCK_FRAMES, *row_shape), dtype)
        self.used = 0
        # whole chunks of a dataset without filters can be written as they are (`flush`)
        self.raw_chunks = not options and 0 not in row_shape

    def append(self, row: Any) -> None:
        """Buffer one row."""
        if self.used == len(self.buffer):
            self._grow(self.used + 1)
        self.buffer[self.used] = row
        self.used += 1

    def extend(self, rows: np.ndarray) -> None:
        """Buffer several rows (a frame's contacts)."""
        end = self.used + len(rows)
        if end > len(self.buffer):
            self._grow(end)
        self.buffer[self.used:end] = rows
        self.used = end

    def empty_rows(self, count: int) -> np.ndarray:
        """`count` rows of this dataset's shape and dtype (zeros; none at all for zero-width rows)."""
        import numpy as np

        return np.zeros((count, *self.buffer.shape[1:]), self.buffer.dtype)

    def _grow(self, rows: int) -> None:
        import numpy as np

        bigger = np.empty((max(rows, 2 * len(self.buffer)), *self.buffer.shape[1:]), self.buffer.dtype)
        bigger[:self.used] = self.buffer[:self.used]
        self.buffer = bigger

    def flush(self, rows: int | None = None) -> None:
        """Append the first `rows` buffered rows (all by default) to the dataset; the rest stay."""
        import numpy as np

        rows = self.used if rows is None else rows
        if not rows:
            return
        start = self.dataset.shape[0]
        self.dataset.resize(start + rows, axis=0)
        chunk = self.dataset.chunks[0]
        if self.raw_chunks and start % chunk == 0 and rows % chunk == 0:
            # whole chunks go to the file as they are, past HDF5's chunk cache and selections
            inner = (0,) * (self.buffer.ndim - 1)
            for first in range(0, rows, chunk):
                self.dataset.id.write_direct_chunk((start + first, *inner), self.buffer[first:first + chunk])
        elif self.buffer[0].size:  # rows of zero width (no joints) have nothing to write
            # write_direct: the buffer goes to HDF5 as it is, without h5py's slicing machinery
            self.dataset.write_direct(self.buffer, source_sel=np.s_[:rows], dest_sel=np.s_[start:])
        self.buffer[:self.used - rows] = self.buffer[rows:self.used]
        self.used -= rows


def _chunk_frames(frame_bytes: int) -> int:
    """Frames per chunk: a few dozen, fewer for large worlds so that a chunk stays about 1 MiB."""
    return max(1, min(CHUNK_FRAMES, CHUNK_BYTES // max(frame_bytes, 1)))


class TrajectoryWriter:
    """Writes one run: the static description when created, then `append(frame)` per recorded frame,
    then `finish` (flush, parameters, summary, rename) or `discard` (remove the temporary file).

    Use it as a context manager: an exception escaping the block discards the file.
    """

    def __init__(self, path: Path, world: Any, *, names: list[str], materials: list[str],
                 shape_materials: list[str], collision_groups: list[int], attractor_names: list[str],
                 author: str, scene_text: str, overrides: tuple[str, ...], contacts: bool, compress: bool,
                 joints: JointDrawing | None = None):
        import h5py

        from .shape_table import shape_table, write_shapes

        self.path = Path(path)
        self.temporary = temporary_path(self.path)
        self.dt = float(world.dt)
        self.frames = 0
        self._file = h5py.File(self.temporary, "w")
        self._saved = time.monotonic()
        try:
            self._write_static(world, names, materials, collision_groups, attractor_names, author,
                               scene_text, overrides)
            write_shapes(self._file, shape_table(world, shape_materials))
            self.events = EventWriter(self._file, self.dt)
            table = write_joint_table(self._file, world, joints)
            self._create_series(world.body_count, contacts,
                                {"compression": "gzip", "shuffle": True} if compress else {}, table)
        except BaseException:
            self.discard()
            raise

    def __enter__(self) -> TrajectoryWriter:
        return self

    def __exit__(self, kind: type[BaseException] | None, *_: object) -> None:
        if kind is not None:
            self.discard()

    def _write_static(self, world: Any, names: list[str], materials: list[str],
                      collision_groups: list[int], attractor_names: list[str], author: str,
                      scene_text: str, overrides: tuple[str, ...]) -> None:
        import h5py
        import numpy as np

        text = h5py.string_dtype()
        file = self._file
        h5md = file.create_group("h5md")
        h5md.attrs["version"] = np.array([1, 1], dtype="i4")
        h5md.create_group("creator").attrs.update({"name": CREATOR, "version": package_version()})
        h5md.create_group("author").attrs["name"] = author
        bodies = file.create_group("particles/bodies")
        box = bodies.create_group("box")
        box.attrs["dimension"] = np.int32(2)
        box.attrs.create("boundary", np.array(["none", "none"], dtype=object), dtype=text)
        for key, values in (("name", names), ("type", list(world.body_types)),
                            ("shape", list(world.shape_kinds)), ("material", materials)):
            bodies.create_dataset(key, data=np.array([str(v) for v in values], dtype=object), dtype=text)
        bodies.create_dataset("mass", data=np.asarray(world.masses, "f8")).attrs["unit"] = "kg"
        bodies.create_dataset("inertia", data=np.asarray(world.inertias, "f8")).attrs["unit"] = "kg m2"
        bodies.create_dataset("spawn_tick", data=np.asarray(world.spawn_ticks, "i8"))
        center = np.asarray(world.local_centers, "f8").reshape(world.body_count, 2)
        bodies.create_dataset("local_center", data=center).attrs["unit"] = "m"
        bodies.create_dataset("collision_group", data=np.asarray(collision_groups, "i4"))

        attractors = file.create_group("world/attractors")
        found = list(world.attractors)
        attractors.create_dataset("name", data=np.array(attractor_names, dtype=object), dtype=text)
        attractors.create_dataset(
            "position", data=np.array([a["position"] for a in found], "f8").reshape(len(found), 2))
        for key in ("mass", "range", "min_distance"):
            attractors.create_dataset(key, data=np.array([a[key] for a in found], "f8"))
        if world.bounds is not None:
            file["world"].create_dataset("bounds", data=np.array(world.bounds, "f8")).attrs["unit"] = "m"

        parameters = file.create_group("parameters", track_order=True)
        parameters.create_dataset("scene", data=scene_text, dtype=text)
        parameters.create_dataset("overrides", data=np.array(list(overrides), dtype=object), dtype=text)

    def _create_series(self, body_count: int, contacts: bool, options: dict[str, Any],
                       joints: h5py.Group) -> None:
        file = self._file
        position = file.create_group("particles/bodies/position")
        chunk = _chunk_frames(body_count * 16)
        self._step = _Growing(position, "step", (), "i8", CHUNK_FRAMES * 4, options)
        self._time = _Growing(position, "time", (), "f8", CHUNK_FRAMES * 4, options, "s")
        self._series: dict[str, _Growing] = {}
        for name, (shape, dtype, unit) in FRAME_SERIES.items():
            group = position if name == "position" else file.create_group(f"particles/bodies/{name}")
            if name != "position":
                group["step"], group["time"] = self._step.dataset, self._time.dataset
            self._series[name] = _Growing(group, "value", (body_count, *shape), dtype, chunk, options, unit)
        self._observables: dict[str, _Growing] = {}
        for name, (shape, dtype, unit) in OBSERVABLES.items():
            group = file.create_group(f"observables/{name}")
            group["step"], group["time"] = self._step.dataset, self._time.dataset
            self._observables[name] = _Growing(group, "value", shape, dtype, CHUNK_FRAMES * 4, options, unit)
        joint_count = len(joints["name"])
        self._joints: dict[str, _Growing] = {}
        for name, (shape, dtype, unit) in JOINT_SERIES.items():
            group = joints.create_group(name)
            group["step"], group["time"] = self._step.dataset, self._time.dataset
            self._joints[name] = _Growing(group, "value", (joint_count, *shape), dtype,
                                          _chunk_frames(joint_count * 16), options, unit)
        self._contacts: dict[str, _Growing] | None = None
        if contacts:
            group = file.create_group("contacts")
            self._offset = _Growing(group, "offset", (), "i8", CHUNK_FRAMES * 4, options)
            self._offset.append(0)
            self._contact_rows = 0
            self._contacts = {
                name: _Growing(group, name, shape, dtype, CONTACT_CHUNK_ROWS, options, unit)
                for name, (shape, dtype, unit) in CONTACT_FIELDS.items()
            }

    def append(self, frame: Frame) -> None:
        """Record one frame; every BLOCK_FRAMES frames the buffered block is written to the file."""

        self._step.append(frame.tick)
        self._time.append(frame.tick * self.dt)
        for name, series in self._series.items():
            series.append(getattr(frame, name))
        for name, series in self._observables.items():
            series.append(frame.observables[name])
        for name, series in self._joints.items():
            series.append(frame.joints[name] if frame.joints is not None else series.empty_rows(1)[0])
        if self._contacts is not None:
            if frame.contacts is None:
                raise ValueError("this trajectory records contacts: capture frames with contacts=True")
            for name, series in self._contacts.items():
                series.extend(frame.contacts[name])
            self._contact_rows += len(frame.contacts["body_a"])
            self._offset.append(self._contact_rows)
        self.frames += 1
        if self.frames % BLOCK_FRAMES == 0:
            self._flush()

    def append_block(self, frames: dict[str, np.ndarray], count: int) -> None:
        """Record the first `count` rows of a frame buffer filled by `World.step(record=...)`, as whole
        arrays with no Python per frame (a trajectory without contacts)."""
        if self._contacts is not None:
            raise ValueError("this trajectory records contacts: append frames one by one, with them")
        ticks = frames["tick"][:count]
        self._step.extend(ticks)
        self._time.extend(ticks * self.dt)
        for name, series in (*self._series.items(), *self._observables.items()):
            series.extend(frames[name][:count])
        for name, series in self._joints.items():
            series.extend(frames[FRAME_FIELDS[name]][:count])
        self.frames += count
        # whole multiples of FLUSH_FRAMES only, so that each write fills whole chunks (a run's first frame
        # comes alone) and HDF5 is called a few times per 256 frames
        written = self._step.dataset.shape[0]
        whole = self.frames // FLUSH_FRAMES * FLUSH_FRAMES - written
        if whole > 0:
            for series in self._all_series():
                series.flush(whole)
            self._save_now_and_then()

    def _flush(self) -> None:
        for series in self._all_series():
            series.flush()
        self._save_now_and_then()

    def _save_now_and_then(self) -> None:
        """Flush the file to disk every RECOVERY_SECONDS (not per block: that would cost a millisecond
        each), so that the temporary of a killed run holds a consistent state to recover."""
        if time.monotonic() - self._saved >= RECOVERY_SECONDS and self._file.id.valid:
            self._file.flush()
            self._saved = time.monotonic()

    def _all_series(self) -> list[_Growing]:
        found = [self._step, self._time, *self._series.values(), *self._observables.values(),
                 *self._joints.values()]
        if self._contacts is not None:
            found += [self._offset, *self._contacts.values()]
        return found

    def finish(self, parameters: dict[str, Any], summary: dict[str, Any], spawn_ticks: Any = None) -> Path:
        """Write the remaining frames, /parameters and /parameters/summary attrs, and the bodies'
        `spawn_tick` as the run ended (-1 for emitted bodies that were skipped); rename; return the path.

        None values are left out (HDF5 attributes have no null).
        """
        try:
            self._flush()
            if spawn_ticks is not None:
                self._file["particles/bodies/spawn_tick"][...] = spawn_ticks
            group = self._file["parameters"]
            _set_attrs(group, parameters)
            _set_attrs(group.create_group("summary", track_order=True), summary)
            self._file.close()
            os.replace(self.temporary, self.path)
        except BaseException:
            self.discard()
            raise
        return self.path

    def discard(self) -> None:
        """Close and delete the temporary file (nothing is left under the final name), also when closing
        fails (a full disk cannot take the last writes)."""
        try:
            if self._file.id.valid:
                self._file.close()
        except OSError:
            pass
        finally:
            self.temporary.unlink(missing_ok=True)


def _set_attrs(node: h5py.Group, values: dict[str, Any]) -> None:
    """Store values as attributes, None left out; a value HDF5 cannot hold as it is (an integer beyond
    64 bits) is stored as its text, so that the frames of a finished run are never lost over it."""
    for key, value in values.items():
        if value is None:
            continue
        try:
            node.attrs[key] = value
        except (TypeError, ValueError, OverflowError):
            node.attrs[key] = str(value)


def package_version() -> str:
    """The installed rustycs version (stored in every file so a run can be traced to its code)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("rustycs")
    except PackageNotFoundError:
        return "unknown"


def read_series(file: h5py.File, name: str) -> h5py.Dataset | np.ndarray:
    """The values [T, N, ...] of the per-body series `name` (FRAME_SERIES), to slice like a dataset; a series
    of ADDED_SERIES that a file written before it existed lacks reads as all false (nothing slept)."""
    import numpy as np

    path = f"particles/bodies/{name}/value"
    if path in file or name not in ADDED_SERIES:
        return file[path]
    return np.broadcast_to(np.zeros((), bool), file[POSITION].shape[:2])


def read_strings(dataset: h5py.Dataset) -> list[str]:
    """A variable-length string dataset as a list of str."""
    return [str(value) for value in dataset.asstr()[()]]


def read_attrs(group: h5py.Group | h5py.Dataset) -> dict[str, Any]:
    """An HDF5 object's attributes as plain Python values (str, int, float, bool, lists)."""
    result = {}
    for key, value in group.attrs.items():
        if hasattr(value, "tolist"):
            value = value.tolist()
        result[key] = _text(value) if isinstance(value, bytes) else value
    return result


def read_scene(file: h5py.File) -> tuple[str, list[str]]:
    """The stored resolved scene text and the overrides it was made with (a record; already applied)."""
    parameters = file["parameters"]
    return parameters["scene"].asstr()[()], read_strings(parameters["overrides"])


def _shape_counts(file: h5py.File) -> dict[str, Any] | None:
    """How many shapes of each type (and how many sensors) /shapes holds; None for files written before
    it existed."""
    from collections import Counter

    if "shapes" not in file:
        return None
    types = read_strings(file["shapes/type"])
    return {"total": len(types), "by_type": dict(Counter(types)),
            "sensors": int(file["shapes/sensor"][()].sum())}


def describe(path: str | Path) -> dict[str, Any]:
    """What a trajectory holds (for `rustycs info`): run parameters, body counts by type and shape,
    shape counts by type, and the summary. Raises UserError for files that are not readable rustycs
    trajectories."""
    from collections import Counter

    with open_trajectory(path) as file:
        try:
            parameters = read_attrs(file["parameters"])
            bodies = file["particles/bodies"]
            types, shapes = read_strings(bodies["type"]), read_strings(bodies["shape"])
            summary = read_attrs(file["parameters/summary"])
            return {
                "file": str(path),
                "scene": summary.get("scene"),
                "status": parameters.get("status"),
                "ticks_completed": parameters.get("ticks_completed"),
                "frames": int(file[POSITION].shape[0]),
                "dt": parameters.get("dt"),
                **{key: parameters.get(key) for key in
                   ("tick_rate", "precision", "seed", "scene_sha256", "rustycs_version", "every")},
                "overrides": read_strings(file["parameters/overrides"]),
                "contacts_recorded": "contacts" in file,
                "bodies": {"total": len(types), "by_type": dict(Counter(types)),
                           "by_shape": dict(Counter(shapes))},
                "shapes": _shape_counts(file),
                "attractors": len(file["world/attractors/name"]) if "world/attractors/name" in file else 0,
                "summary": summary,
            }
        except (KeyError, OSError, ValueError) as err:
            raise UserError(f"{path}: damaged rustycs trajectory ({err})") from None
