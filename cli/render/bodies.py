"""The static part of a trajectory (who the bodies are and what they look like), read once per render."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..errors import UserError
from .colors import RGB, material_color

if TYPE_CHECKING:
    import h5py

    from ..shape_table import ShapeTable
    from .joints import JointTable

BODIES = "particles/bodies"


@dataclass(frozen=True)
class Attractor:
    """A fixed point that pulls bodies, as drawn: `range` is inf for a global attractor."""

    name: str
    position: tuple[float, float]
    range: float


@dataclass(frozen=True)
class Outlines:
    """Every shape of a run in its body's frame (its offset and angle applied), as it is drawn.

    Styles: "disc" (a circle: one point, its centre), "area" (a box or polygon: its corners, as written, so
    a concave polygon is one outline), "stadium" (a capsule: the centres of its end circles), "line" (a
    segment or chain: its points; `closed` for a loop). A shape's hitbox is the box of its points grown
    by its radius: exact (the engine fattens it further).
    """

    body: np.ndarray  # [S] int, body of each shape; a body's shapes are consecutive rows
    first: np.ndarray  # [N + 1] body i's shapes are rows first[i] .. first[i + 1] - 1
    style: list[str]
    closed: np.ndarray  # [S] bool: a line drawn back to its first point
    start: np.ndarray  # [S + 1] shape s's points are points[start[s]:start[s + 1]]
    points: np.ndarray  # [P, 2] body frame, about the body origin
    radius: np.ndarray  # [S] discs and stadiums, else 0
    spoke: np.ndarray  # [S, 2] body frame: where a disc's spoke ends (its local (0, r)), else 0
    sensor: np.ndarray  # [S] bool
    colors: list[RGB]  # each shape's material colour

    @property
    def count(self) -> int:
        return len(self.style)

    @property
    def point_body(self) -> np.ndarray:
        """[P] the body of each point."""
        return np.repeat(self.body, np.diff(self.start))

    def of_body(self, body: int) -> range:
        """The rows of a body's shapes."""
        return range(int(self.first[body]), int(self.first[body + 1]))


STYLES = {"circle": "disc", "aabb": "area", "obb": "area", "polygon": "area", "capsule": "stadium",
          "segment": "line", "chain": "line"}


@dataclass(frozen=True)
class RunInfo:
    """Everything about a run that does not change from frame to frame."""

    source: str
    names: list[str]
    types: list[str]
    shapes: list[str]  # per body: its shape's type, or "compound"
    materials: list[str]
    outlines: Outlines
    centroid: np.ndarray  # [N, 2] body-local centre of mass (where velocities apply)
    attractors: list[Attractor]
    bounds: np.ndarray | None  # [[xmin, ymin], [xmax, ymax]] or None
    steps: np.ndarray  # [T] tick of each recorded frame
    times: np.ndarray  # [T] seconds
    has_contacts: bool
    joints: JointTable

    @property
    def body_count(self) -> int:
        return len(self.names)

    @property
    def frame_count(self) -> int:
        return len(self.steps)

    def frame_of_tick(self, tick: int) -> int:
        """The index of the frame recorded at `tick`; UserError naming the nearest recorded ticks if none."""
        index = int(np.searchsorted(self.steps, tick))
        if index < self.frame_count and self.steps[index] == tick:
            return index
        near = sorted({int(self.steps[i]) for i in (index - 1, index) if 0 <= i < self.frame_count})
        raise UserError(
            f"{self.source}: tick {tick} was not recorded (ticks {int(self.steps[0])}..{int(self.steps[-1])}"
            f"; nearest recorded: {', '.join(map(str, near))})"
        )


def load_run(file: h5py.File, source: str) -> RunInfo:
    """Read the static body table, the shapes, attractors and frame times; UserError when a dataset is
    missing, or the file predates /shapes (the bodies' outlines)."""
    if "shapes" not in file:
        raise UserError(
            f"{source}: no /shapes in this trajectory (written by a rustycs before bodies made of "
            f"shapes), so its bodies cannot be drawn; run its scene again to render it: rustycs run {source} "
            "--out NEW.h5"
        )
    try:
        return _load(file, source)
    except KeyError as err:
        raise UserError(f"{source}: not a complete rustycs trajectory (missing {err.args[0]})") from None


def _load(file: h5py.File, source: str) -> RunInfo:
    from ..shape_table import read_shapes
    from .joints import read_joints

    bodies = _group(file, BODIES)
    frames = _group(file, f"{BODIES}/position")
    if len(frames["step"]) == 0:
        raise UserError(f"{source}: the trajectory holds no frames")
    names = _strings(bodies, "name")
    return RunInfo(
        source=source,
        names=names,
        types=_strings(bodies, "type"),
        shapes=_strings(bodies, "shape"),
        materials=_strings(bodies, "material"),
        outlines=outlines(read_shapes(file), len(names)),
        centroid=_array(bodies, "local_center").astype(np.float64).reshape(len(names), 2),
        attractors=_attractors(file),
        bounds=np.asarray(file["world/bounds"], dtype=np.float64) if "world/bounds" in file else None,
        steps=np.asarray(frames["step"], dtype=np.int64),
        times=np.asarray(frames["time"], dtype=np.float64),
        has_contacts="contacts/offset" in file,
        joints=read_joints(file, len(frames["step"])),
    )


def outlines(table: ShapeTable, body_count: int) -> Outlines:
    """The shapes of a /shapes table placed on their bodies, ready to draw."""
    styles = [STYLES[kind] for kind in table.type]
    parts = [table.body_points(s) for s in range(table.count)]
    discs = np.array([style == "disc" for style in styles], dtype=bool).reshape(-1, 1)
    cos, sin = np.cos(table.angle), np.sin(table.angle)
    tips = table.offset + np.stack([-sin * table.radius, cos * table.radius], axis=-1)  # local (0, r)
    return Outlines(
        body=table.body.astype(np.int64),
        first=np.searchsorted(table.body, np.arange(body_count + 1)),
        style=styles,
        closed=table.loop.copy(),
        start=np.concatenate([[0], np.cumsum([len(p) for p in parts], dtype=np.int64)]),
        points=np.concatenate([*parts, np.zeros((0, 2))]),
        radius=table.radius.copy(),
        spoke=np.where(discs, tips, 0.0),
        sensor=table.sensor.copy(),
        colors=[material_color(material) for material in table.material],
    )


def _group(file: h5py.File, path: str) -> h5py.Group:
    if path not in file:
        raise KeyError(f"/{path}")
    return file[path]


def _array(group: h5py.Group, name: str) -> np.ndarray:
    if name not in group:
        raise KeyError(f"{group.name}/{name}")
    return np.asarray(group[name])


def _strings(group: h5py.Group, name: str) -> list[str]:
    if name not in group:
        raise KeyError(f"{group.name}/{name}")
    return [str(text) for text in group[name].asstr()[()]]


def _attractors(file: h5py.File) -> list[Attractor]:
    if "world/attractors/position" not in file:
        return []
    group = file["world/attractors"]
    positions = np.asarray(group["position"], dtype=np.float64).reshape(-1, 2)
    count = len(positions)
    names = _strings(group, "name") if "name" in group else [f"attractor-{i}" for i in range(count)]
    ranges = np.asarray(group["range"], dtype=np.float64) if "range" in group else np.full(count, np.inf)
    return [
        Attractor(names[i], (float(positions[i, 0]), float(positions[i, 1])), float(ranges[i]))
        for i in range(count)
    ]
