"""The static part of a trajectory (who the bodies are and what they look like), read once per render."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..errors import UserError
from .colors import RGB, material_color

if TYPE_CHECKING:
    import h5py

BODIES = "particles/bodies"


@dataclass(frozen=True)
class Attractor:
    """A fixed point that pulls bodies, as drawn: `range` is inf for a global attractor."""

    name: str
    position: tuple[float, float]
    range: float


@dataclass(frozen=True)
class RunInfo:
    """Everything about a run that does not change from frame to frame."""

    source: str
    names: list[str]
    types: list[str]
    shapes: list[str]
    materials: list[str]
    colors: list[RGB]
    radius: np.ndarray  # [N] circle radius, 0 for polygons
    vertex_count: np.ndarray  # [N] int, 0 for circles
    vertices: np.ndarray  # [N, 8, 2] body-local about the body origin, unrotated
    centroid: np.ndarray  # [N, 2] body-local centre of mass (where velocities apply)
    attractors: list[Attractor]
    bounds: np.ndarray | None  # [[xmin, ymin], [xmax, ymax]] or None
    steps: np.ndarray  # [T] tick of each recorded frame
    times: np.ndarray  # [T] seconds
    has_contacts: bool

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
    """Read the static body table, attractors and frame times; UserError when a dataset is missing."""
    try:
        return _load(file, source)
    except KeyError as err:
        raise UserError(f"{source}: not a complete rustycs trajectory (missing {err.args[0]})") from None


def _load(file: h5py.File, source: str) -> RunInfo:
    bodies = _group(file, BODIES)
    vertex_count = _array(bodies, "vertex_count").astype(np.int64)
    vertices = _array(bodies, "vertices").astype(np.float64)
    radius = _array(bodies, "radius").astype(np.float64)
    materials = _strings(bodies, "material")
    frames = _group(file, f"{BODIES}/position")
    if len(frames["step"]) == 0:
        raise UserError(f"{source}: the trajectory holds no frames")
    return RunInfo(
        source=source,
        names=_strings(bodies, "name"),
        types=_strings(bodies, "type"),
        shapes=_strings(bodies, "shape"),
        materials=materials,
        colors=[material_color(material) for material in materials],
        radius=radius,
        vertex_count=vertex_count,
        vertices=vertices,
        centroid=_centroids(vertices, vertex_count),
        attractors=_attractors(file),
        bounds=np.asarray(file["world/bounds"], dtype=np.float64) if "world/bounds" in file else None,
        steps=np.asarray(frames["step"], dtype=np.int64),
        times=np.asarray(frames["time"], dtype=np.float64),
        has_contacts="contacts/offset" in file,
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


def _centroids(vertices: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """Area centroid of each polygon or box (body-local); circles have theirs at the origin."""
    centroids = np.zeros((len(counts), 2))
    for i, count in enumerate(counts):
        if count < 3:
            continue
        points = vertices[i, :count]
        following = np.roll(points, -1, axis=0)
        cross = points[:, 0] * following[:, 1] - following[:, 0] * points[:, 1]
        area = cross.sum() / 2.0
        if abs(area) > 1e-300:
            centroids[i] = ((points + following) * cross[:, None]).sum(axis=0) / (6.0 * area)
    return centroids
