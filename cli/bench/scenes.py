"""Which scenes the benchmark runs: S1..S6, Box2D v3's benchmark scenes and shower from scenes/bench/, and the
generated scaling series."""

from __future__ import annotations

import math
from pathlib import Path

from ..errors import UserError

DEFAULT_IDS = ("S1", "S2", "S3", "S4", "S5", "S6")  # run when no scene is named
SCENE_FILES = {  # id: the file pattern in the bench folder
    **{scene_id: f"{scene_id}_*.yaml" for scene_id in DEFAULT_IDS},
    "compounds": "compounds.yaml",  # Box2D v3's compounds: 3000 bodies of two triangles, only when named
    "joint_grid": "joint_grid.yaml",  # Box2D v3's joint grid: 19,800 revolute joints, only when named
    "ragdoll_rain": "ragdoll_rain.yaml",  # 100 of Box2D's ragdolls, only when named
    "shower": "shower.yaml",  # 500 bullets at 100-300 m/s in a box of 2 cm walls, only when named
    # Box2D v3's benchmark scenes (make_box2d_scenes.py), only when named:
    "large_pyramid": "large_pyramid.yaml",  # 5,050 boxes in a pyramid of base 100
    "many_pyramids": "many_pyramids.yaml",  # 400 pyramids of base 10: 22,000 boxes
    "smash": "smash.yaml",  # a heavy box into a block of 9,600 boxes, no gravity
    "tumbler": "tumbler.yaml",  # 2,025 boxes in a turning drum (one kinematic body of four walls)
}
SCALING_SIZES = (1000, 4000, 16000)
SCALING_TICKS = 300
SCALING_PREFIX = "scaling:"

# The scaling scene: S4's circles (r 0.25, 0.62 m grid) in a container as wide as the square grid of N.
_RADIUS = 0.25
_SPACING = 0.62
_PRECISION = 4  # solver substeps per tick, as in scenes/bench


def default_scene_dir() -> Path:
    """scenes/bench of the source checkout this package runs from, else of the working directory."""
    checkout = Path(__file__).resolve().parents[2] / "scenes" / "bench"
    return checkout if checkout.is_dir() else Path("scenes") / "bench"


def find_scenes(directory: Path, ids: list[str]) -> dict[str, Path]:
    """The scene file of each id (`S4` -> `S4_*.yaml`, `compounds` -> `compounds.yaml`), in the order
    given."""
    found, problems = {}, []
    for scene_id in ids:
        if scene_id not in SCENE_FILES:
            problems.append(f"unknown bench scene {scene_id!r}: choose from {', '.join(SCENE_FILES)}")
            continue
        matches = sorted(directory.glob(SCENE_FILES[scene_id]))
        if len(matches) != 1:
            problems.append(f"{directory}: expected one {SCENE_FILES[scene_id]}, found {len(matches)}")
        else:
            found[scene_id] = matches[0]
    if problems:
        raise UserError(problems)
    return found


def parse_ids(values: list[str]) -> list[str]:
    """Scene ids from `S1 S4`, `S1,S4`, `compounds` or any case; S1..S6 when none are given."""
    names = {scene_id.lower(): scene_id for scene_id in SCENE_FILES}
    ids = [part.strip() for value in values for part in value.split(",") if part.strip()]
    return list(dict.fromkeys(names.get(scene_id.lower(), scene_id) for scene_id in ids)) or list(DEFAULT_IDS)


def scaling_ref(count: int) -> str:
    """The worker's name of the scaling scene with `count` circles."""
    return f"{SCALING_PREFIX}{count}"


def scaling_scene_text(count: int) -> str:
    """A scene of `count` circles on a jittered square grid, falling into a container that fits them."""
    columns = max(1, round(math.sqrt(count)))
    rows = math.ceil(count / columns)
    half = columns * _SPACING / 2 + 0.3  # inner half width
    height = rows * _SPACING + 4.0
    return f"""\
name: scaling-{count}
description: {count} circles of radius {_RADIUS} falling into a container (the bench's scaling series).
world: {{tick_rate: 60, ticks: {SCALING_TICKS}, precision: {_PRECISION}}}
forces:
  - {{name: gravity, acceleration: [0, -9.81]}}
materials:
  bench: {{density: 1.0, restitution: 0.0, friction: 0.6}}
bodies:
  - {{name: floor, type: static, shape: {{type: aabb, width: {2 * half + 2}, height: 1}},
     position: [0, -0.5], material: bench}}
  - {{name: left, type: static, shape: {{type: aabb, width: 1, height: {height}}},
     position: [{-half - 0.5}, {height / 2}], material: bench}}
  - {{name: right, type: static, shape: {{type: aabb, width: 1, height: {height}}},
     position: [{half + 0.5}, {height / 2}], material: bench}}
generators:
  - name: circles
    count: {count}
    shape: {{type: circle, radius: {_RADIUS}}}
    material: bench
    layout: {{grid: {{origin: [{-(columns - 1) * _SPACING / 2}, 1.0], columns: {columns},
              spacing: [{_SPACING}, {_SPACING}], jitter: [0.05, 0.05]}}}}
"""
