"""One frame as a Pillow image: grid, bounds, attractors, bodies, the debug overlays and the tick label.

Shapes are drawn at SUPERSAMPLE times the size and reduced (cheap anti-aliasing); text is drawn after
the reduction so it stays crisp.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from . import colors, geometry
from .bodies import RunInfo
from .frames import Frame
from .view import View, grid_spacing

SUPERSAMPLE = 2
VELOCITY_SECONDS = 0.1  # a velocity arrow shows where the body would be this much later
CONTACT_DOT = 3.0  # pixels
JOINT_DOT = 3.0  # pixels: the ring at a joint's anchor
NORMAL_LENGTH = 14.0  # pixels
LABEL_SPACING = 64.0  # pixels between grid labels at least
CORNER_CLEAR = 30.0  # pixels at the top left kept for the tick label
SENSOR_FILL_ALPHA = 64  # of 255: a sensor shows what lies under it
SENSOR_LIT_ALPHA = 153  # while something is inside it (the player's 0.6)
SENSOR_OUTLINE_ALPHA = 160
Color = tuple[int, ...]  # RGB, or RGBA on the sensors' layer


@dataclass(frozen=True)
class Overlays:
    """The thesis's debug views, each off unless asked for."""

    hitboxes: bool = False
    contacts: bool = False
    velocities: bool = False
    names: bool = False
    joints: bool = True


@cache
def font(size: int) -> ImageFont.FreeTypeFont | ImageFont.ImageFont:
    """Pillow's bundled font (no system fonts needed)."""
    return ImageFont.load_default(size=size)


def draw_frame(run: RunInfo, frame: Frame, view: View, overlays: Overlays,
               lit: np.ndarray | None = None) -> Image.Image:
    """Render one frame of `run` as seen through `view` (an RGB image of the view's size); `lit` [N]
    marks the sensor bodies that hold something at this frame (filled brighter)."""
    big = view.scaled(SUPERSAMPLE)
    image = Image.new("RGB", (big.width, big.height), colors.BACKGROUND)
    draw = ImageDraw.Draw(image)
    spacing = grid_spacing(view.scale)
    _grid(draw, big, spacing)
    if run.bounds is not None:
        low, high = big.to_pixel(run.bounds)
        draw.rectangle([low[0], high[1], high[0], low[1]], outline=colors.BOUNDS, width=SUPERSAMPLE)
    _attractors(draw, run, big)
    points = geometry.world_points(run, frame.position, frame.angle)
    shape_boxes = geometry.shape_boxes(run, points)
    boxes = geometry.hitboxes(run, shape_boxes)
    visible = _visible(frame, boxes, big)
    image = _bodies(image, run, frame, big, visible, points, lit)
    draw = ImageDraw.Draw(image)
    if overlays.joints:
        _joints(draw, run, frame, big)
    if overlays.hitboxes:
        shown = shape_boxes[visible[run.outlines.body]]
        for xmin, ymin, xmax, ymax in big.to_pixel(shown.reshape(-1, 2, 2)).reshape(-1, 4):
            draw.rectangle([xmin, ymax, xmax, ymin], outline=colors.HITBOX, width=SUPERSAMPLE)
    if overlays.contacts and frame.contacts is not None:
        _contacts(draw, frame, big)
    if overlays.velocities:
        _velocities(draw, run, frame, big, visible)
    image = image.reduce(SUPERSAMPLE)
    draw = ImageDraw.Draw(image)
    _grid_labels(draw, view, spacing)
    if overlays.names:
        _names(draw, run, frame, view, boxes[visible], visible)
    _corner_label(draw, frame)
    return image


def _visible(frame: Frame, boxes: np.ndarray, view: View) -> np.ndarray:
    """Active, finite bodies whose hitbox meets the view."""
    with np.errstate(invalid="ignore"):
        return (
            frame.active
            & np.isfinite(boxes).all(axis=1)
            & (boxes[:, 2] >= view.xmin)
            & (boxes[:, 0] <= view.xmax)
            & (boxes[:, 3] >= view.ymin)
            & (boxes[:, 1] <= view.ymax)
        )


def _grid_values(low: float, high: float, spacing: float) -> np.ndarray:
    return np.arange(math.ceil(low / spacing), math.floor(high / spacing) + 1) * spacing


def _grid(draw: ImageDraw.ImageDraw, view: View, spacing: float) -> None:
    """Grid lines every `spacing` metres, the axes darker."""
    for x in _grid_values(view.xmin, view.xmax, spacing):
        px = (x - view.xmin) * view.scale
        color = colors.AXES if abs(x) < spacing / 2 else colors.GRID
        draw.line([(px, 0), (px, view.height)], fill=color, width=SUPERSAMPLE)
    for y in _grid_values(view.ymin, view.ymax, spacing):
        py = (view.ymax - y) * view.scale
        color = colors.AXES if abs(y) < spacing / 2 else colors.GRID
        draw.line([(0, py), (view.width, py)], fill=color, width=SUPERSAMPLE)


def _grid_labels(draw: ImageDraw.ImageDraw, view: View, spacing: float) -> None:
    """Metre values along the bottom and left edges, thinned so labels do not collide."""
    every = max(1, math.ceil(LABEL_SPACING / (spacing * view.scale)))
    step = spacing * every
    small = font(10)
    for x in _grid_values(view.xmin, view.xmax, step):
        px = (x - view.xmin) * view.scale
        draw.text((px + 2, view.height - 3), _metres(x, step), fill=colors.AXES, font=small, anchor="ld")
    for y in _grid_values(view.ymin, view.ymax, step):
        py = (view.ymax - y) * view.scale
        if py < CORNER_CLEAR:
            continue
        draw.text((3, py - 2), _metres(y, step), fill=colors.AXES, font=small, anchor="ld")


def _metres(value: float, step: float) -> str:
    decimals = max(0, -math.floor(math.log10(step)))
    text = f"{value:.{decimals}f}"
    return "0" if float(text) == 0 else text


def _attractors(draw: ImageDraw.ImageDraw, run: RunInfo, view: View) -> None:
    """A dot per attractor, and the circle of its range when it is local."""
    dot = 5 * SUPERSAMPLE
    for attractor in run.attractors:
        px, py = view.to_pixel(np.asarray(attractor.position))
        if math.isfinite(attractor.range):
            reach = attractor.range * view.scale
            draw.ellipse(
                [px - reach, py - reach, px + reach, py + reach], outline=colors.ATTRACTOR, width=SUPERSAMPLE
            )
        draw.ellipse(
            [px - dot, py - dot, px + dot, py + dot],
            fill=colors.ATTRACTOR,
            outline=colors.TEXT,
            width=SUPERSAMPLE,
        )


@dataclass(frozen=True)
class Paint:
    """How one shape is drawn: fill and outline colours (None: not drawn), outline width, the colour of a
    disc's spoke and of lines (segments and chains)."""

    fill: Color | None
    outline: Color | None
    width: int
    spoke: Color | None
    line: Color


def paint(color: colors.RGB, body_type: str, sensor: bool, lit: bool = False, asleep: bool = False) -> Paint:
    """Dynamic bodies filled (paler while `asleep`), kinematic ones filled and outlined in black, static
    ones outlined only; sensors filled faintly (brighter while `lit`: something is inside) with a lighter
    outline and no spoke (drawn on a layer blended on top)."""
    if asleep and not sensor:
        color = colors.asleep_color(color)
    if sensor:
        faint, fill = (*color, SENSOR_OUTLINE_ALPHA), (*color, SENSOR_LIT_ALPHA if lit else SENSOR_FILL_ALPHA)
        return Paint(fill, faint, SUPERSAMPLE, None, faint)
    if body_type == "static":
        return Paint(None, color, 2 * SUPERSAMPLE, color, color)
    outline = colors.TEXT if body_type == "kinematic" else None
    return Paint(color, outline, SUPERSAMPLE, colors.SPOKE, color)


def _bodies(image: Image.Image, run: RunInfo, frame: Frame, view: View, visible: np.ndarray,
            points: np.ndarray, lit: np.ndarray | None) -> Image.Image:
    """The visible bodies' shapes in their materials' colours, statics first; sensors on a translucent
    layer over everything. Returns the image drawn on (a new one when sensors were blended in)."""
    outlines = run.outlines
    pixels = view.to_pixel(points)
    tips = view.to_pixel(geometry.spoke_tips(run, frame.position, frame.angle))
    order = sorted(np.flatnonzero(visible), key=lambda i: run.types[i] != "static")
    draw = ImageDraw.Draw(image)
    sensors = []
    for i in order:
        for s in outlines.of_body(i):
            if outlines.sensor[s]:
                sensors.append(s)
            else:
                style = paint(outlines.colors[s], run.types[i], False, asleep=bool(frame.asleep[i]))
                _shape(draw, run, s, pixels, tips, view.scale, style)
    if not sensors:
        return image
    layer = Image.new("RGBA", image.size, (0, 0, 0, 0))
    draw = ImageDraw.Draw(layer)
    for s in sensors:
        body = outlines.body[s]
        style = paint(outlines.colors[s], run.types[body], True, lit is not None and bool(lit[body]))
        _shape(draw, run, s, pixels, tips, view.scale, style)
    return Image.alpha_composite(image.convert("RGBA"), layer).convert("RGB")


def _shape(draw: ImageDraw.ImageDraw, run: RunInfo, s: int, pixels: np.ndarray, tips: np.ndarray,
           scale: float, style: Paint) -> None:
    """Shape s (its points in `pixels`): a disc with its spoke, a polygon, a stadium, or a line."""
    outlines = run.outlines
    points = pixels[outlines.start[s]:outlines.start[s + 1]]
    kind = outlines.style[s]
    if kind == "line":
        line = [tuple(p) for p in points] + ([tuple(points[0])] if outlines.closed[s] else [])
        draw.line(line, fill=style.line, width=2 * SUPERSAMPLE, joint="curve")
        return
    if kind == "disc":
        (px, py), reach = points[0], max(outlines.radius[s] * scale, SUPERSAMPLE / 2)
        draw.ellipse([px - reach, py - reach, px + reach, py + reach], fill=style.fill, outline=style.outline,
                     width=style.width)
        if style.spoke is not None and reach >= 3 * SUPERSAMPLE:
            draw.line([(px, py), tuple(tips[s])], fill=style.spoke, width=SUPERSAMPLE)
        return
    if kind == "stadium":
        points = geometry.stadium(points[0], points[1], outlines.radius[s] * scale)
    draw.polygon([tuple(p) for p in points], fill=style.fill, outline=style.outline, width=style.width)


def _joints(draw: ImageDraw.ImageDraw, run: RunInfo, frame: Frame, view: View) -> None:
    """Each whole joint: the line (zigzag, pulley rope) between its anchors and a ring at each anchor."""
    from .joints import joint_lines

    lines, dots = joint_lines(run.joints, frame.index, frame.position, frame.angle)
    for line in lines:
        pixels = [tuple(p) for p in view.to_pixel(line)]
        draw.line(pixels, fill=colors.JOINT, width=SUPERSAMPLE, joint="curve")
    dot = JOINT_DOT * SUPERSAMPLE
    for px, py in view.to_pixel(dots):
        draw.ellipse([px - dot, py - dot, px + dot, py + dot], outline=colors.JOINT, width=SUPERSAMPLE)


def _contacts(draw: ImageDraw.ImageDraw, frame: Frame, view: View) -> None:
    """A dot at each contact point and a short line along its normal."""
    assert frame.contacts is not None
    dot, length = CONTACT_DOT * SUPERSAMPLE, NORMAL_LENGTH * SUPERSAMPLE
    points = view.to_pixel(frame.contacts.point)
    normals = frame.contacts.normal * np.array([1.0, -1.0])  # +y up in the world, down in the image
    for (px, py), (nx, ny) in zip(points, normals, strict=True):
        if not (math.isfinite(px) and math.isfinite(py)):
            continue
        draw.line([(px, py), (px + nx * length, py + ny * length)], fill=colors.CONTACT, width=SUPERSAMPLE)
        draw.ellipse([px - dot, py - dot, px + dot, py + dot], fill=colors.CONTACT)


def _velocities(
    draw: ImageDraw.ImageDraw, run: RunInfo, frame: Frame, view: View, visible: np.ndarray
) -> None:
    """An arrow from each body's centre of mass to where it would be VELOCITY_SECONDS later."""
    starts_world = geometry.centers(run, frame.position, frame.angle)
    starts = view.to_pixel(starts_world)
    ends = view.to_pixel(starts_world + frame.velocity * VELOCITY_SECONDS)
    head = 6 * SUPERSAMPLE
    for i in np.flatnonzero(visible & (np.array(run.types) != "static")):
        (x0, y0), (x1, y1) = starts[i], ends[i]
        length = math.hypot(x1 - x0, y1 - y0)
        if not math.isfinite(length) or length < 2 * SUPERSAMPLE:
            continue
        ux, uy = (x1 - x0) / length, (y1 - y0) / length
        draw.line([(x0, y0), (x1, y1)], fill=colors.VELOCITY, width=SUPERSAMPLE)
        for side in (1.0, -1.0):
            draw.line(
                [(x1, y1), (x1 - head * (ux + side * uy * 0.5), y1 - head * (uy - side * ux * 0.5))],
                fill=colors.VELOCITY,
                width=SUPERSAMPLE,
            )


def _names(
    draw: ImageDraw.ImageDraw, run: RunInfo, frame: Frame, view: View, boxes: np.ndarray, visible: np.ndarray
) -> None:
    """Each body's name above its hitbox (inside it for static bodies), each attractor's above its dot."""
    small = font(11)
    tops = view.to_pixel(np.stack([(boxes[:, 0] + boxes[:, 2]) / 2, boxes[:, 3]], axis=-1))
    middles = view.to_pixel(
        np.stack([(boxes[:, 0] + boxes[:, 2]) / 2, (boxes[:, 1] + boxes[:, 3]) / 2], axis=-1)
    )
    for n, i in enumerate(np.flatnonzero(visible)):
        if run.types[i] == "static":  # outlined: the name reads inside, clear of what rests on top
            draw.text(tuple(middles[n]), run.names[i], fill=colors.TEXT, font=small, anchor="mm")
        else:
            draw.text((tops[n][0], tops[n][1] - 2), run.names[i], fill=colors.TEXT, font=small, anchor="md")
    for attractor in run.attractors:
        px, py = view.to_pixel(np.asarray(attractor.position))
        draw.text((px, py - 8), attractor.name, fill=colors.TEXT, font=small, anchor="md")


def _corner_label(draw: ImageDraw.ImageDraw, frame: Frame) -> None:
    """`tick N  t = S s` in the top-left corner, on a white patch so it reads over anything."""
    text = f"tick {frame.step}   t = {frame.time:.3f} s"
    label = font(13)
    left, top, right, bottom = draw.textbbox((8, 6), text, font=label)
    draw.rectangle([left - 4, top - 3, right + 4, bottom + 3], fill=colors.BACKGROUND, outline=colors.GRID)
    draw.text((8, 6), text, fill=colors.TEXT, font=label)
