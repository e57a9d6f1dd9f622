"""The window onto the world: which rectangle of metres is shown and how it maps to pixels (+y up)."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from ..errors import UserError
from ..limits import MAX_VIEW, MIN_LENGTH
from .bodies import BODIES, RunInfo
from .geometry import body_hitboxes

if TYPE_CHECKING:
    import h5py

Box = tuple[float, float, float, float]  # xmin, ymin, xmax, ymax in metres
MARGIN = 0.06  # of the fitted box's size, on each side
MIN_SPAN = 1.0  # metres: a single small body still gets some room around it
MIN_WORLD_MARGIN = 20.0  # metres: without bounds, what has left the starting scene by more is not fitted


@dataclass(frozen=True)
class View:
    """World box [xmin, xmax] x [ymin, ymax] shown on a width x height image (same scale on both axes)."""

    xmin: float
    ymin: float
    xmax: float
    ymax: float
    width: int
    height: int

    @property
    def scale(self) -> float:
        """Pixels per metre."""
        return self.width / (self.xmax - self.xmin)

    @property
    def box(self) -> Box:
        return (self.xmin, self.ymin, self.xmax, self.ymax)

    def to_pixel(self, points: np.ndarray) -> np.ndarray:
        """World points [..., 2] to continuous pixel coordinates (x right, y down; pixel (i, j) covers
        [i, i+1) x [j, j+1))."""
        points = np.asarray(points, dtype=np.float64)
        return np.stack(
            [(points[..., 0] - self.xmin) * self.scale, (self.ymax - points[..., 1]) * self.scale], axis=-1
        )

    def scaled(self, factor: int) -> View:
        """The same world box on an image `factor` times larger (for supersampling)."""
        return replace(self, width=self.width * factor, height=self.height * factor)


def make_view(box: Box, width: int, height: int) -> View:
    """A view of `box`, grown around its centre along one axis to the image's aspect ratio."""
    xmin, ymin, xmax, ymax = box
    span_x, span_y = xmax - xmin, ymax - ymin
    aspect = width / height
    if span_x / span_y < aspect:
        span_x = span_y * aspect
    else:
        span_y = span_x / aspect
    cx, cy = (xmin + xmax) / 2, (ymin + ymax) / 2
    return View(cx - span_x / 2, cy - span_y / 2, cx + span_x / 2, cy + span_y / 2, width, height)


def parse_size(text: str, option: str = "--size") -> tuple[int, int]:
    """`WxH` in pixels, each 16..8192."""
    parts = text.lower().split("x")
    try:
        width, height = (int(part) for part in parts)
    except ValueError:
        raise UserError(f"{option} {text!r}: expected WIDTHxHEIGHT in pixels, e.g. 800x600") from None
    if not (16 <= width <= 8192 and 16 <= height <= 8192):
        raise UserError(f"{option} {text!r}: width and height must be between 16 and 8192 pixels")
    return width, height


def parse_box(text: str, option: str = "--view") -> Box:
    """`XMIN,YMIN,XMAX,YMAX` in metres, with XMIN < XMAX and YMIN < YMAX."""
    try:
        xmin, ymin, xmax, ymax = (float(part) for part in text.split(","))
    except ValueError:
        raise UserError(
            f"{option} {text!r}: expected XMIN,YMIN,XMAX,YMAX in metres, e.g. -5,-3,5,4"
        ) from None
    if not all(math.isfinite(v) for v in (xmin, ymin, xmax, ymax)) or xmin >= xmax or ymin >= ymax:
        raise UserError(f"{option} {text!r}: need finite numbers with XMIN < XMAX and YMIN < YMAX")
    too_small = min(xmax - xmin, ymax - ymin) < MIN_LENGTH.value
    if max(map(abs, (xmin, ymin, xmax, ymax))) > MAX_VIEW.value or too_small:
        raise UserError(f"{option} {text!r}: the view must lie within +-{MAX_VIEW} and be at least "
                        f"{MIN_LENGTH} wide and high")
    return (xmin, ymin, xmax, ymax)


def fit_box(file: h5py.File, run: RunInfo) -> Box:
    """A box, with a margin, around the attractors, the bodies as the scene placed them (the first frame,
    statics included) and the bodies still in the world at the last frame: active with their centre,
    when the world has bounds, inside them; without bounds, within the first frame's box grown by its
    own size, and at least MIN_WORLD_MARGIN, on every side (a thrown ball, alone in its scene, is drawn
    where it landed 10 m away). A body that fell off a platform for seconds, or flew away, does not shrink
    the scene to a dot. The joints as the scene placed them are taken in too (a pendulum's pivot)."""
    from .joints import joint_lines

    attractors = [np.asarray(a.position, dtype=np.float64).reshape(1, 2) for a in run.attractors]
    start = _active_boxes(file, run, 0)
    end = _active_boxes(file, run, run.frame_count - 1)
    if run.bounds is not None:
        world = run.bounds.reshape(-1)
    elif len(start):
        low, high = start[:, :2].min(axis=0), start[:, 2:].max(axis=0)
        size = np.maximum(high - low, MIN_WORLD_MARGIN)
        world = np.concatenate([low - size, high + size])
    else:
        world = np.array([-np.inf, -np.inf, np.inf, np.inf])
    centre = (end[:, :2] + end[:, 2:]) / 2
    inside = np.all((centre >= world[:2]) & (centre <= world[2:]), axis=1)
    pose = [np.asarray(file[f"{BODIES}/{name}/value"][0], dtype=np.float64) for name in ("position", "angle")]
    joints = joint_lines(run.joints, 0, *pose)[0]
    points = np.concatenate(attractors + [start[:, :2], start[:, 2:], end[inside, :2], end[inside, 2:],
                                          *joints, np.zeros((0, 2))])
    if len(points) == 0:
        return (-5.0, -5.0, 5.0, 5.0)
    # bodies that flew to 1e300 m: the view stays where a picture can be drawn
    low = np.maximum(points.min(axis=0), -MAX_VIEW.value)
    high = np.minimum(points.max(axis=0), MAX_VIEW.value)
    span = np.maximum(high - low, MIN_SPAN)
    centre = (low + high) / 2
    half = span * (0.5 + MARGIN)
    xmin, ymin = (float(v) for v in centre - half)
    xmax, ymax = (float(v) for v in centre + half)
    return (xmin, ymin, xmax, ymax)


def _active_boxes(file: h5py.File, run: RunInfo, index: int) -> np.ndarray:
    """(K, 4) hitboxes of the bodies active in recorded frame `index` (finite ones only)."""
    position = np.asarray(file[f"{BODIES}/position/value"][index], dtype=np.float64)
    angle = np.asarray(file[f"{BODIES}/angle/value"][index], dtype=np.float64)
    boxes = body_hitboxes(run, position, angle)
    active = np.asarray(file[f"{BODIES}/active/value"][index], dtype=bool)
    return boxes[active & np.isfinite(boxes).all(axis=1)]


def grid_spacing(scale: float, min_pixels: float = 24.0, max_pixels: float = 240.0) -> float:
    """Grid spacing in metres: 1 m when metre lines are between `min_pixels` and `max_pixels` apart;
    zoomed out, the smallest of 2, 5, 10, 20, 50 ... m that keeps lines `min_pixels` apart; zoomed far
    in, the smallest of 0.5, 0.2, 0.1 ... m that keeps them 2 x `min_pixels` apart."""
    if min_pixels <= scale <= max_pixels:
        return 1.0
    target = min_pixels / scale if scale < min_pixels else 2 * min_pixels / scale
    exponent = math.floor(math.log10(target))
    return next(m * 10.0**exponent for m in (1, 2, 5, 10) if m * 10.0**exponent >= target * (1 - 1e-9))
