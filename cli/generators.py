"""Expand scene generators into plain body mappings, reproducibly.

Each generator draws from its own numpy SeedSequence, derived from the scene's seed and the generator's
name (not its position), and within it each field (position, angle, shape.radius, ...) has its own child
stream. So changing one generator, or one field's distribution, leaves every other draw unchanged. Only
uniform doubles are taken from numpy (PCG64's `random()`, stable across numpy versions and machines);
every distribution is computed from them with plain IEEE arithmetic and `math`.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .scene import (
    BodyTypeChoice,
    GeneratedChain,
    GeneratedPolygon,
    GeneratedSegment,
    Generator,
    Grid,
    Material,
    MaterialChoice,
    Normal,
    NumberChoice,
    Pyramid,
    RandomAabb,
    RandomCapsule,
    RandomCircle,
    RandomObb,
    RandomPolygon,
    Scene,
    ShapeChoice,
    Stack,
    Uniform,
    UniformInt,
)

# Random polygon vertices sit at evenly spread angles, each moved by up to this fraction of the spacing:
# the points stay in angular order on the circle, so the polygon is convex and never degenerate.
POLYGON_JITTER = 0.25


@dataclass(frozen=True)
class GeneratedBodies:
    """Body mappings drawn from a scene's generators, in generator order, and for each body the index
    of the generator that made it."""

    bodies: list[dict[str, Any]]
    origins: list[int]


def _stable_int(text: str) -> int:
    """A 64-bit integer from text, the same in every process (unlike hash())."""
    return int.from_bytes(hashlib.sha256(text.encode()).digest()[:8], "little")


class _Draws:
    """Uniform numbers in [0, 1) for one generator, one independent stream per field."""

    def __init__(self, seed: int, generator_name: str):
        self._entropy = seed
        self._generator = _stable_int(generator_name)
        self._streams: dict[str, np.random.Generator] = {}

    def unit(self, field: str) -> float:
        stream = self._streams.get(field)
        if stream is None:
            sequence = np.random.SeedSequence(self._entropy, spawn_key=(self._generator, _stable_int(field)))
            stream = self._streams[field] = np.random.Generator(np.random.PCG64(sequence))
        return float(stream.random())

    def pick(self, options: list[Any], field: str) -> tuple[int, Any]:
        """One of `options`, each equally likely, and its index."""
        index = min(int(self.unit(field) * len(options)), len(options) - 1)
        return index, options[index]

    def value(self, spec: Any, field: str) -> Any:
        """A fixed value as it is, or a draw from a distribution."""
        if isinstance(spec, Uniform):
            lo, hi = spec.uniform
            return lo + (hi - lo) * self.unit(field)
        if isinstance(spec, UniformInt):
            lo, hi = spec.uniform_int
            return lo + min(int(self.unit(field) * (hi - lo + 1)), hi - lo)
        if isinstance(spec, Normal):
            mean, std = spec.normal
            radius = math.sqrt(-2.0 * math.log(1.0 - self.unit(field)))
            return mean + std * radius * math.cos(2.0 * math.pi * self.unit(field))
        if isinstance(spec, (NumberChoice, BodyTypeChoice, MaterialChoice)):
            return self.value(self.pick(spec.choice, field)[1], field)
        if isinstance(spec, Material):
            return spec.model_dump()
        return spec


def _shape(spec: Any, draws: _Draws, field: str) -> dict[str, Any]:
    """One body's shape mapping, drawn from the streams named after `field` (shape, shapes.0, ...)."""
    if isinstance(spec, ShapeChoice):
        index, spec = draws.pick(spec.choice, field)
        field = f"{field}.{index}"
    shape = _geometry(spec, draws, field)
    shape["offset"] = [
        draws.value(spec.offset[0], f"{field}.offset.0"),
        draws.value(spec.offset[1], f"{field}.offset.1"),
    ]
    shape["angle"] = draws.value(spec.angle, f"{field}.angle")
    if spec.material is not None:
        shape["material"] = draws.value(spec.material, f"{field}.material")
    shape["sensor"] = spec.sensor
    return shape


def _geometry(spec: Any, draws: _Draws, field: str) -> dict[str, Any]:
    """A shape mapping's type and size."""
    if isinstance(spec, RandomCircle):
        return {"type": "circle", "radius": draws.value(spec.radius, f"{field}.radius")}
    if isinstance(spec, (RandomAabb, RandomObb)):
        return {
            "type": spec.type,
            "width": draws.value(spec.width, f"{field}.width"),
            "height": draws.value(spec.height, f"{field}.height"),
        }
    if isinstance(spec, RandomCapsule):
        return {
            "type": "capsule",
            "length": draws.value(spec.length, f"{field}.length"),
            "radius": draws.value(spec.radius, f"{field}.radius"),
        }
    if isinstance(spec, GeneratedPolygon):
        return {"type": "polygon", "vertices": [list(v) for v in spec.vertices]}
    if isinstance(spec, GeneratedSegment):
        return {"type": "segment", "points": [list(p) for p in spec.points]}
    if isinstance(spec, GeneratedChain):
        return {"type": "chain", "points": [list(p) for p in spec.points], "loop": spec.loop}
    assert isinstance(spec, RandomPolygon)
    count = int(draws.value(spec.vertices, f"{field}.vertices"))
    radius = draws.value(spec.radius, f"{field}.radius")
    step = 2.0 * math.pi / count
    phase = 2.0 * math.pi * draws.unit(f"{field}.angles")
    angles = [
        phase + step * (k + POLYGON_JITTER * (2.0 * draws.unit(f"{field}.angles") - 1.0))
        for k in range(count)
    ]
    return {"type": "polygon", "vertices": [[radius * math.cos(a), radius * math.sin(a)] for a in angles]}


def _positions(generator: Generator, count: int, draws: _Draws) -> list[list[float]]:
    """Where each body goes: uniformly in the region, or at its place in the layout."""
    layout = generator.layout
    if isinstance(layout, Pyramid):
        base, (x0, y0), (dx, dy) = layout.pyramid.base, layout.pyramid.origin, layout.pyramid.spacing
        places = [
            [x0 + (i - (base - row - 1) / 2.0) * dx, y0 + row * dy]
            for row in range(base)
            for i in range(base - row)
        ]
        return places[:count]
    if isinstance(layout, Stack):
        (x0, y0), spacing = layout.stack.origin, layout.stack.spacing
        return [[x0, y0 + k * spacing] for k in range(count)]
    if isinstance(layout, Grid):
        grid = layout.grid
        (x0, y0), (dx, dy), (jx, jy) = grid.origin, grid.spacing, grid.jitter
        places = []
        for k in range(count):
            row, column = divmod(k, grid.columns)
            x = x0 + column * dx + jx * (2.0 * draws.unit("layout.jitter") - 1.0)
            y = y0 + row * dy + jy * (2.0 * draws.unit("layout.jitter") - 1.0)
            places.append([x, y])
        return places
    assert generator.region is not None
    (xmin, ymin), (xmax, ymax) = generator.region.min, generator.region.max
    return [
        [xmin + (xmax - xmin) * draws.unit("position"), ymin + (ymax - ymin) * draws.unit("position")]
        for _ in range(count)
    ]


def _count(generator: Generator) -> int:
    if generator.count is not None:
        return generator.count
    assert isinstance(generator.layout, Pyramid)
    return generator.layout.pyramid.base * (generator.layout.pyramid.base + 1) // 2


def generate(generator: Generator, seed: int) -> list[dict[str, Any]]:
    """The bodies of one generator (named '<name>-<i>'), as mappings in the scene's body format."""
    assert generator.name is not None
    draws = _Draws(seed, generator.name)
    count = _count(generator)
    bodies = []
    for i, position in enumerate(_positions(generator, count, draws)):
        body = {
            "name": f"{generator.name}-{i}",
            "type": draws.value(generator.type, "type"),
            **(
                {"shape": _shape(generator.shape, draws, "shape")}
                if generator.shape is not None
                else {
                    "shapes": [_shape(s, draws, f"shapes.{k}") for k, s in enumerate(generator.shapes or ())]
                }
            ),
            "position": position,
            "velocity": [
                draws.value(generator.velocity[0], "velocity.0"),
                draws.value(generator.velocity[1], "velocity.1"),
            ],
            "angle": draws.value(generator.angle, "angle"),
            "angular_velocity": draws.value(generator.angular_velocity, "angular_velocity"),
            "material": draws.value(generator.material, "material"),
            "collision_group": generator.collision_group,
            "collision_category": generator.collision_category,
            "collision_mask": generator.collision_mask,
            "linear_damping": draws.value(generator.linear_damping, "linear_damping"),
            "angular_damping": draws.value(generator.angular_damping, "angular_damping"),
            "gravity_scale": draws.value(generator.gravity_scale, "gravity_scale"),
            "fixed_rotation": generator.fixed_rotation,
            "bullet": generator.bullet,
        }
        if generator.mass is not None:
            body["mass"] = draws.value(generator.mass, "mass")
        bodies.append(body)
    if generator.placement == "no_overlap" and generator.region is not None:
        from .placement import place_apart

        place_apart(bodies, lambda: _positions(generator, 1, draws)[0], generator.name)
    return bodies


def expand_generators(scene: Scene) -> GeneratedBodies:
    """All generated bodies of a validated scene, generator by generator."""
    bodies: list[dict[str, Any]] = []
    origins: list[int] = []
    for index, generator in enumerate(scene.generators):
        made = generate(generator, scene.seed)
        bodies += made
        origins += [index] * len(made)
    return GeneratedBodies(bodies, origins)
