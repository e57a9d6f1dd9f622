"""`placement: no_overlap` for generators: a body whose bounding circle would overlap one already placed
is drawn again in the region (its position only: its shape, from its own streams, stays).

Bounding circles are conservative: two bodies kept apart never overlap, though a few that would not have
touched are drawn again.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from .errors import UserError

MAX_DRAWS = 100  # draws of one body's position before the generator is reported


def bounding_radius(body: dict[str, Any]) -> float:
    """The radius about the body origin that holds all its shapes (body mappings as generated)."""
    shapes = [body["shape"]] if body.get("shape") is not None else body.get("shapes", [])
    return max(_shape_reach(shape) for shape in shapes)


def _shape_reach(shape: dict[str, Any]) -> float:
    offset = math.hypot(*shape.get("offset", (0.0, 0.0)))
    kind = shape["type"]
    if kind == "circle":
        reach = shape["radius"]
    elif kind in ("aabb", "obb"):
        reach = 0.5 * math.hypot(shape["width"], shape["height"])
    elif kind == "capsule":
        reach = 0.5 * shape["length"] + shape["radius"]
    else:  # polygon, segment, chain: their points
        reach = max(math.hypot(x, y) for x, y in shape.get("vertices") or shape["points"])
    return offset + reach


def place_apart(bodies: list[dict[str, Any]], draw: Callable[[], list[float]], generator: str) -> None:
    """Move every body that overlaps an earlier one to a new position from `draw`, in order."""
    placed: list[tuple[float, float, float]] = []
    for i, body in enumerate(bodies):
        reach = bounding_radius(body)
        for _ in range(MAX_DRAWS):
            x, y = body["position"]
            if all(math.hypot(x - px, y - py) >= reach + pr for px, py, pr in placed):
                break
            body["position"] = draw()
        else:
            raise UserError(f"generator '{generator}': no free spot for body {i} after {MAX_DRAWS} draws "
                            "(placement: no_overlap); enlarge the region or lower the count")
        placed.append((*body["position"], reach))
