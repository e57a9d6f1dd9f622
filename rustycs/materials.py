"""Materials: density, restitution and friction, with the thesis's five presets."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Material:
    """Surface and bulk properties of a body. A contact mixes two materials by the mean."""

    density: float = 0.1
    restitution: float = 0.5
    friction: float = 0.6


MATERIALS: dict[str, Material] = {
    "default": Material(0.1, 0.5, 0.6),
    "rubber": Material(0.9, 0.6, 0.8),
    "plastic": Material(1.2, 0.5, 0.6),
    "stone": Material(2.5, 0.2, 0.4),
    "metal": Material(7.8, 0.1, 0.2),
}
