"""Quality beside speed: the same measures for every engine, computed from initial and final poses.

Fast is worth little if the pyramid creeps or the pile sinks into itself, so each scene reports what
it stresses: the top and the worst box displacement of the pyramids, the deepest overlap and the escaped
bodies of the container scenes, the orbit radius drift under the attractor. Overlaps are measured
geometrically (separating axes on the final shapes), not taken from any engine's own contact data.
"""

from __future__ import annotations

import math

import numpy as np

from .spec import BenchScene, BodySpec, ShapeSpec

# Which measures each scene reports (scaling scenes are circles in a container).
METRICS: dict[str, tuple[str, ...]] = {
    "S1": (),
    "S2": ("max_displacement",),
    "S3": ("max_displacement",),
    "S4": ("max_overlap", "escaped"),
    "S5": ("max_overlap", "escaped"),
    "S6": ("mean_radius_drift", "max_radius_drift"),
    "compounds": ("max_overlap", "escaped"),
    "joint_grid": ("max_joint_gap",),
    "ragdoll_rain": ("max_joint_gap",),
    "shower": ("max_overlap", "outside"),
    "large_pyramid": ("top_displacement", "max_displacement"),
    "many_pyramids": ("top_displacement", "max_displacement"),
    "smash": ("max_overlap", "escaped"),  # no container: escaped = left rustycs's world bounds
    "tumbler": ("max_overlap", "outside"),
    "scaling": ("max_overlap", "escaped"),
}


def measure(metrics: tuple[str, ...] | list[str], scene: BenchScene, start: np.ndarray, end: np.ndarray,
            active: np.ndarray | None = None) -> dict[str, float]:
    """The named measures; `start`/`end` are (N, 3) poses (origin x, y, angle) in body order, `active`
    marks the bodies still simulated (rustycs deactivates bodies that leave the world's bounds)."""
    moving = np.array([b.body_type == "dynamic" for b in scene.bodies], dtype=bool)
    alive = np.ones(len(moving), dtype=bool) if active is None else np.asarray(active, dtype=bool)
    out: dict[str, float] = {}
    for name in metrics:
        if name == "max_displacement":
            out[name] = float(np.hypot(*(end[moving, :2] - start[moving, :2]).T).max(initial=0.0))
        elif name == "top_displacement":
            out[name] = top_displacement(start, end, moving)
        elif name == "max_overlap":
            out[name] = deepest_overlap(scene, end, alive)
        elif name == "escaped":
            out[name] = escaped(scene, end, alive)
        elif name == "max_joint_gap":
            out[name] = max_joint_gap(scene, end)
        elif name == "outside":
            out[name] = outside(scene, end, alive)
        elif name in ("mean_radius_drift", "max_radius_drift"):
            drift = radius_drift(scene, start[moving], end[moving])
            out[name] = float(drift.mean() if name.startswith("mean") else drift.max(initial=0.0))
        else:
            raise ValueError(f"unknown quality measure {name!r}")
    return out


def max_joint_gap(scene: BenchScene, poses: np.ndarray) -> float:
    """How far the joints came apart, m: the largest distance between a revolute joint's two anchors, or
    between a distance joint's length and its anchors' distance. Static bodies are where the scene put
    them (pymunk reports its one static body for them all)."""
    fixed = {i: np.array([*body.position, body.angle]) for i, body in enumerate(scene.bodies)
             if body.body_type == "static"}
    worst = 0.0
    for joint in scene.joints:
        ends = []
        for body, local in ((joint.body_a, joint.anchor_a), (joint.body_b, joint.anchor_b)):
            pose = np.zeros(3) if body < 0 else fixed[body] if body in fixed else poses[body]
            ends.append(_place(np.array([local]), pose)[0])
        gap = float(np.hypot(*(ends[1] - ends[0])))
        worst = max(worst, abs(gap - joint.length) if joint.kind == "distance" else gap)
    return worst


def top_displacement(start: np.ndarray, end: np.ndarray, moving: np.ndarray) -> float:
    """How far the highest dynamic body at the start (the first of equals) has moved: a pyramid's top box
    moves only if the pile sinks or shears."""
    if not moving.any():
        return 0.0
    top = int(np.argmax(np.where(moving, start[:, 1], -np.inf)))
    return float(np.hypot(*(end[top, :2] - start[top, :2])))


def radius_drift(scene: BenchScene, start: np.ndarray, end: np.ndarray) -> np.ndarray:
    """|r_end / r_start - 1| per body, r measured from the first attractor."""
    centre = np.array(scene.attractors[0][:2]) if scene.attractors else np.zeros(2)
    r0 = np.hypot(*(start[:, :2] - centre).T)
    r1 = np.hypot(*(end[:, :2] - centre).T)
    return np.abs(r1 / r0 - 1.0)


def escaped(scene: BenchScene, poses: np.ndarray, active: np.ndarray) -> int:
    """Dynamic bodies whose origin left the container: below the middle of the lowest static shape with
    area, or (with such shapes side by side) beyond the middle of the outermost one; deactivated bodies
    count too. (Lines are not walls: a segment far below catches what escaped.)"""
    statics = np.array([_centre(body, shape) for body in scene.bodies if body.body_type == "static"
                        for shape in body.shapes if shape.kind != "segment"]).reshape(-1, 2)
    moving = np.array([b.body_type == "dynamic" for b in scene.bodies], dtype=bool)
    out = ~active
    if len(statics):
        x, y = poses[:, 0], poses[:, 1]
        out = out | (y < statics[:, 1].min())
        if statics[:, 0].max() > statics[:, 0].min():
            out = out | (x < statics[:, 0].min()) | (x > statics[:, 0].max())
    return int((out & moving).sum())


def outside(scene: BenchScene, poses: np.ndarray, active: np.ndarray) -> int:
    """Dynamic bodies outside a closed box: origin beyond the middle of any of its walls (the shapes with
    area of the static and kinematic bodies) on any side, or deactivated. The sides are taken in the frame
    of the first wall's body at the end, so that a turning drum (a kinematic body) is a box too."""
    poses = _statics_at_rest(scene, poses)
    walls = [(i, shape) for i, body in enumerate(scene.bodies) if body.body_type != "dynamic"
             for shape in body.shapes if shape.kind != "segment"]
    frame = poses[walls[0][0]]
    centres = np.array([_place(np.array([shape.centre]), poses[i])[0] for i, shape in walls])
    corners = _local(centres, frame)
    lo, hi = corners.min(axis=0), corners.max(axis=0)
    local = _local(poses[:, :2], frame)
    moving = np.array([b.body_type == "dynamic" for b in scene.bodies], dtype=bool)
    out = ~active | (local < lo).any(axis=1) | (local > hi).any(axis=1)
    return int((out & moving).sum())


def _statics_at_rest(scene: BenchScene, poses: np.ndarray) -> np.ndarray:
    """`poses` with the static bodies at their initial poses: statics do not move (and some engines
    share one static body)."""
    poses = poses.copy()
    for i, spec in enumerate(scene.bodies):
        if spec.body_type == "static":
            poses[i] = (*spec.position, spec.angle)
    return poses


def _centre(body: BodySpec, shape: ShapeSpec) -> np.ndarray:
    """A shape's centroid in the world, at its body's initial pose."""
    return _place(np.array([shape.centre]), np.array([*body.position, body.angle]))[0]


def _place(points: np.ndarray, pose: np.ndarray) -> np.ndarray:
    """Body-frame points [k, 2] in the world at pose (x, y, angle)."""
    x, y, angle = pose
    c, s = math.cos(angle), math.sin(angle)
    return points @ np.array([[c, s], [-s, c]]) + (x, y)


def _local(points: np.ndarray, pose: np.ndarray) -> np.ndarray:
    """World points [k, 2] in the frame of a body at pose (x, y, angle): the inverse of `_place`."""
    x, y, angle = pose
    c, s = math.cos(angle), math.sin(angle)
    return (points - (x, y)) @ np.array([[c, -s], [s, c]])


def deepest_overlap(scene: BenchScene, poses: np.ndarray, active: np.ndarray) -> float:
    """The largest penetration depth between two shapes of bodies that may collide, m (0 when none
    overlap)."""
    specs = scene.bodies
    poses = _statics_at_rest(scene, poses)
    owner = np.array([i for i, spec in enumerate(specs) for _ in spec.shapes], dtype=np.int64)
    shapes = [_world_shape(shape, poses[i]) for i, spec in enumerate(specs) for shape in spec.shapes]
    lo = np.array([s[0] for s in shapes]).reshape(-1, 2)
    hi = np.array([s[1] for s in shapes]).reshape(-1, 2)
    a, b = _overlapping_boxes(lo, hi)
    groups = np.array([s.group for s in specs])[owner]
    moving = np.array([s.body_type != "static" for s in specs])[owner]
    alive = active[owner]
    keep = ((owner[a] != owner[b]) & alive[a] & alive[b] & (moving[a] | moving[b])
            & ~((groups[a] == groups[b]) & (groups[a] != 0)))
    a, b = a[keep], b[keep]
    radius = np.array([s[2][2] if s[2][0] == "circle" else -1.0 for s in shapes])
    both_circles = (radius[a] > 0) & (radius[b] > 0)
    worst = 0.0
    if both_circles.any():
        ca, cb = a[both_circles], b[both_circles]
        centres = np.array([s[2][1] if s[2][0] == "circle" else (np.nan, np.nan) for s in shapes])
        d = np.hypot(*(centres[ca] - centres[cb]).T)
        worst = max(worst, float((radius[ca] + radius[cb] - d).max()))
    for i, j in zip(a[~both_circles], b[~both_circles], strict=True):
        worst = max(worst, _sat_depth(shapes[i][2], shapes[j][2]))
    return max(worst, 0.0)


def _world_shape(shape: ShapeSpec, pose: np.ndarray) -> tuple[np.ndarray, np.ndarray, tuple]:
    """(box min, box max, geometry): geometry is ("circle", centre, r) or ("poly", world vertices), a
    segment being a polygon of two vertices."""
    points = _place(np.array(shape.points), pose)
    if shape.kind == "circle":
        centre = points[0]
        return centre - shape.radius, centre + shape.radius, ("circle", centre, shape.radius)
    return points.min(axis=0), points.max(axis=0), ("poly", points)


def _overlapping_boxes(lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """All pairs (a < b by sweep order) whose bounding boxes overlap: sort and sweep along x."""
    order = np.argsort(lo[:, 0], kind="stable")
    lo, hi = lo[order], hi[order]
    n = len(order)
    ends = np.searchsorted(lo[:, 0], hi[:, 0], side="right")
    counts = np.maximum(ends - np.arange(n) - 1, 0)
    first = np.repeat(np.arange(n), counts)
    offsets = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    second = first + 1 + offsets
    touch = (lo[second, 1] <= hi[first, 1]) & (lo[first, 1] <= hi[second, 1])
    return order[first[touch]], order[second[touch]]


def _axes(verts: np.ndarray) -> np.ndarray:
    edges = np.roll(verts, -1, axis=0) - verts
    normals = np.stack([edges[:, 1], -edges[:, 0]], axis=1)
    return normals / np.linalg.norm(normals, axis=1)[:, None]


def _sat_depth(first: tuple, second: tuple) -> float:
    """Penetration depth of two convex shapes (at least one polygon): the smallest overlap of their
    projections over the separating-axis candidates (<= 0 when apart)."""
    if first[0] == "circle":
        first, second = second, first
    verts = first[1]
    axes = _axes(verts)
    if second[0] == "circle":
        centre, r = second[1], second[2]
        nearest = verts[np.argmin(np.hypot(*(verts - centre).T))]
        towards = centre - nearest
        length = math.hypot(*towards)
        if length > 0:
            axes = np.vstack([axes, towards / length])
        p = verts @ axes.T
        q = centre @ axes.T
        overlap = np.minimum(p.max(axis=0) - (q - r), (q + r) - p.min(axis=0))
    else:
        axes = np.vstack([axes, _axes(second[1])])
        p = verts @ axes.T
        q = second[1] @ axes.T
        overlap = np.minimum(p.max(axis=0) - q.min(axis=0), q.max(axis=0) - p.min(axis=0))
    return float(overlap.min())
