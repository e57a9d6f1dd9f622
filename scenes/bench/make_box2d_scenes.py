"""Write large_pyramid.yaml, many_pyramids.yaml, smash.yaml and tumbler.yaml: Box2D v3's benchmark scenes
of the same names (shared/benchmarks.c: CreateLargePyramid, CreateManyPyramids, CreateSmash, CreateTumbler),
their boxes placed by the scene format's generators (pyramid, stack and grid layouts) in Box2D's creation
order.

Our transcription, with Box2D's defaults where it sets nothing (density 1, friction 0.6, restitution 0,
gravity (0, -10)); 60 Hz, 4 substeps (rustycs's precision) and the step counts of Box2D's benchmark runner
(benchmark/main.c). Dynamic boxes are obb (Box2D's b2MakeBox polygons), static ones aabb as in the other
bench scenes.

- large_pyramid: a pyramid of base 100 (5,050 boxes of 1 m, rows centred on x = 0, the bottom row at
  y = 0.5) on a static box 200 x 2 centred at (0, -1); 500 steps.
- many_pyramids: 20 rows x 20 columns of pyramids of base 10 (22,000 boxes of 1 m), the pyramids of row i
  standing on the i-th of 20 static segments from (-110, 11 i) to (110, 11 i), the pyramid in column j
  with its bottom row centred on x = 11 j - 104.5; 200 steps.
- smash: no gravity; a box 8 x 8 of density 8 at (-20, 0) moving at (40, 0) m/s into a block of 120
  columns x 80 rows of boxes of 0.4 m, touching, at x = 30 + 0.4 i, y = 0.4 (j - 40), created column by
  column; 300 steps. (Box2D creates the block asleep with sleeping on; here, as in `rustycs bench --peers`,
  nothing sleeps.)
- tumbler: a drum centred at (0, 10) of four walls (1 x 20 at x = +-10 and 20 x 1 at y = +-10 in its frame)
  turning at 25 degrees per second, with 45 x 45 boxes of 0.25 m inside on a 0.4 m grid from (-9, 1),
  row by row; 750 steps. Box2D turns a dynamic drum of density 50 by a revolute motor of 1e8 N m; here
  the drum is one kinematic body turning at the motor's speed.

Usage: python scenes/bench/make_box2d_scenes.py [--out FOLDER]
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

from rustycs_cli.yaml_source import dump_scene_yaml

HERE = Path(__file__).resolve().parent
HEADER = (
    "# yaml-language-server: $schema=../../rustycs.schema.json\n"
    "# Written by scenes/bench/make_box2d_scenes.py after Box2D v3's {function}: do not edit by hand.\n"
)
TICK_RATE, PRECISION = 60, 4
GRAVITY = [{"name": "gravity", "acceleration": [0.0, -10.0]}]
MATERIALS = {"bench": {"density": 1.0, "restitution": 0.0, "friction": 0.6}}  # named as make_bench_scenes.py

PYRAMID_BASE = 100
SMALL_BASE, PYRAMID_ROWS, PYRAMID_COLUMNS = 10, 20, 20
SMASH_COLUMNS, SMASH_ROWS, SMASH_SIZE = 120, 80, 0.4
TUMBLER_GRID, TUMBLER_SPACING, TUMBLER_BOX = 45, 0.4, 0.25
TUMBLER_SPEED = math.radians(25.0)  # rad/s: Box2D's motorSpeed of 25 degrees per second


def _obb(size: float) -> dict[str, Any]:
    return {"type": "obb", "width": size, "height": size}


def _world(ticks: int) -> dict[str, Any]:
    return {"tick_rate": TICK_RATE, "ticks": ticks, "precision": PRECISION}


def large_pyramid() -> dict[str, Any]:
    """CreateLargePyramid: one pyramid of base 100 on a wide static box."""
    count = PYRAMID_BASE * (PYRAMID_BASE + 1) // 2
    return {
        "name": "large_pyramid",
        "description": f"Box2D v3's benchmark scene large_pyramid: a pyramid of {count} boxes (base "
                       f"{PYRAMID_BASE}) on the ground, 500 steps of 1/60 s.",
        "world": _world(500),
        "forces": GRAVITY,
        "materials": MATERIALS,
        "bodies": [{"name": "ground", "type": "static", "position": [0.0, -1.0], "material": "bench",
                    "shape": {"type": "aabb", "width": 200.0, "height": 2.0}}],
        "generators": [{"name": "box", "shape": _obb(1.0), "material": "bench",
                        "layout": {"pyramid": {"base": PYRAMID_BASE, "origin": [0.0, 0.5],
                                               "spacing": [1.0, 1.0]}}}],
    }


def many_pyramids() -> dict[str, Any]:
    """CreateManyPyramids: 20 x 20 pyramids of base 10, each row of them on a segment of its own."""
    floor_step = SMALL_BASE + 1.0  # Box2D's groundDeltaY, also the pitch of the pyramids along x
    half_width = 0.5 * PYRAMID_COLUMNS * floor_step
    floors = [{"type": "segment", "points": [[-half_width, i * floor_step], [half_width, i * floor_step]]}
              for i in range(PYRAMID_ROWS)]
    count = PYRAMID_ROWS * PYRAMID_COLUMNS * SMALL_BASE * (SMALL_BASE + 1) // 2
    pyramids = [{"name": f"pyramid-{i}-{j}", "shape": _obb(1.0), "material": "bench",
                 "layout": {"pyramid": {"base": SMALL_BASE, "spacing": [1.0, 1.0],
                                        "origin": [-half_width + 1.0 + j * floor_step + (SMALL_BASE - 1) / 2,
                                                   i * floor_step + 0.5]}}}
                for i in range(PYRAMID_ROWS) for j in range(PYRAMID_COLUMNS)]
    return {
        "name": "many_pyramids",
        "description": f"Box2D v3's benchmark scene many_pyramids: {PYRAMID_ROWS} x {PYRAMID_COLUMNS} "
                       f"pyramids of base {SMALL_BASE} ({count} boxes), each row of them on a floor of its "
                       "own, 200 steps of 1/60 s.",
        "world": _world(200),
        "forces": GRAVITY,
        "materials": MATERIALS,
        "bodies": [{"name": "floors", "type": "static", "position": [0.0, 0.0], "material": "bench",
                    "shapes": floors}],
        "generators": pyramids,
    }


def smash() -> dict[str, Any]:
    """CreateSmash: a heavy box thrown into a block of small touching boxes, without gravity."""
    bottom = -SMASH_ROWS / 2 * SMASH_SIZE
    columns = [{"name": f"column-{i}", "count": SMASH_ROWS, "shape": _obb(SMASH_SIZE), "material": "bench",
                "layout": {"stack": {"origin": [round(30.0 + i * SMASH_SIZE, 9), bottom],
                                     "spacing": SMASH_SIZE}}}
               for i in range(SMASH_COLUMNS)]
    return {
        "name": "smash",
        "description": f"Box2D v3's benchmark scene smash: a box 8 x 8 of density 8 at 40 m/s into a block "
                       f"of {SMASH_COLUMNS} x {SMASH_ROWS} touching boxes, no gravity, 300 steps of 1/60 s.",
        "world": _world(300),
        "materials": {**MATERIALS, "bench-d8": {"density": 8.0, "restitution": 0.0, "friction": 0.6}},
        "bodies": [{"name": "hammer", "shape": _obb(8.0), "position": [-20.0, 0.0], "velocity": [40.0, 0.0],
                    "material": "bench-d8"}],
        "generators": columns,
    }


def tumbler() -> dict[str, Any]:
    """CreateTumbler: small boxes in a turning square drum (one kinematic body of four walls)."""
    walls = [{"type": "obb", "width": w, "height": h, "offset": [x, y]}
             for w, h, x, y in ((1.0, 20.0, 10.0, 0.0), (1.0, 20.0, -10.0, 0.0),
                                (20.0, 1.0, 0.0, 10.0), (20.0, 1.0, 0.0, -10.0))]
    start = -0.2 * TUMBLER_GRID
    return {
        "name": "tumbler",
        "description": f"Box2D v3's benchmark scene tumbler: {TUMBLER_GRID**2} boxes in a square drum "
                       "turning at 25 degrees per second, 750 steps of 1/60 s.",
        "world": _world(750),
        "forces": GRAVITY,
        "materials": MATERIALS,
        "bodies": [{"name": "drum", "type": "kinematic", "position": [0.0, 10.0],
                    "angular_velocity": round(TUMBLER_SPEED, 12), "material": "bench", "shapes": walls}],
        "generators": [{"name": "box", "count": TUMBLER_GRID**2, "shape": _obb(TUMBLER_BOX),
                        "material": "bench",
                        "layout": {"grid": {"origin": [start, start + 10.0], "columns": TUMBLER_GRID,
                                            "spacing": [TUMBLER_SPACING, TUMBLER_SPACING]}}}],
    }


SCENES: dict[str, tuple[str, Callable[[], dict[str, Any]]]] = {  # file stem: (Box2D's function, ours)
    "large_pyramid": ("CreateLargePyramid", large_pyramid),
    "many_pyramids": ("CreateManyPyramids", many_pyramids),
    "smash": ("CreateSmash", smash),
    "tumbler": ("CreateTumbler", tumbler),
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=HERE, help="folder for the scene files")
    args = parser.parse_args()
    for stem, (function, make) in SCENES.items():
        target = args.out / f"{stem}.yaml"
        target.write_text(dump_scene_yaml(make(), HEADER.format(function=function)), encoding="utf-8")
        print(target)


if __name__ == "__main__":
    main()
