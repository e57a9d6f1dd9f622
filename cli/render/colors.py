"""Colours of the pictures: bodies by material (the thesis's palette) and the debug overlays."""

from __future__ import annotations

import colorsys
import hashlib

RGB = tuple[int, int, int]

# macroquad's RED, GREEN, GRAY, DARKGRAY and BLACK, as the thesis's demo drew its materials.
MATERIAL_COLORS: dict[str, RGB] = {
    "rubber": (230, 41, 55),
    "plastic": (0, 228, 48),
    "stone": (130, 130, 130),
    "metal": (80, 80, 80),
    "default": (0, 0, 0),
}
BACKGROUND: RGB = (255, 255, 255)
GRID: RGB = (228, 228, 228)
AXES: RGB = (180, 180, 180)
TEXT: RGB = (30, 30, 30)
HITBOX: RGB = (0, 121, 241)  # macroquad BLUE, the thesis's hitbox and contact colour
CONTACT: RGB = (0, 121, 241)
VELOCITY: RGB = (200, 0, 200)
ATTRACTOR: RGB = (230, 160, 0)
BOUNDS: RGB = (230, 120, 120)
SPOKE: RGB = (255, 255, 255)
JOINT: RGB = (0, 150, 136)  # teal: anchors and the lines, zigzags and pulley ropes between them


def material_color(material: str) -> RGB:
    """The colour of a material: the preset's, or a stable colour derived from the name's hash,
    so the same user material looks the same in every picture and in the player."""
    if material in MATERIAL_COLORS:
        return MATERIAL_COLORS[material]
    digest = hashlib.sha256(material.encode("utf-8")).digest()
    hue = int.from_bytes(digest[:2], "big") / 65536.0
    red, green, blue = colorsys.hsv_to_rgb(hue, 0.55 + digest[2] / 255 * 0.3, 0.55 + digest[3] / 255 * 0.3)
    return (round(red * 255), round(green * 255), round(blue * 255))


def asleep_color(color: RGB) -> RGB:
    """A sleeping body's colour: its own blended halfway to the background, so that a picture shows which
    bodies the solver skips while it still tells their materials apart."""
    red, green, blue = (round((own + back) / 2) for own, back in zip(color, BACKGROUND, strict=True))
    return (red, green, blue)


def hex_color(color: RGB) -> str:
    """`#rrggbb`, for the HTML player."""
    return "#{:02x}{:02x}{:02x}".format(*color)
EVENT_COLORS: dict[str, RGB] = {  # the player's marks on its scrub bar, by event kind
    "contact_begin": (0, 121, 241),
    "contact_end": (135, 180, 230),
    "sensor_enter": (0, 170, 70),
    "sensor_exit": (140, 200, 150),
    "spawn": (230, 160, 0),
    "remove": (200, 0, 200),
    "escape": (230, 41, 55),
    "joint_break": (0, 150, 136),
}
OTHER_EVENT: RGB = (30, 30, 30)  # a kind without a colour of its own
