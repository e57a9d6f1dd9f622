"""Write compounds.yaml: Box2D v3's benchmark scene "compounds" (shared/benchmarks.c, CreateCompounds,
itself from the samples' BenchmarkBarrel), with every body written out.

Our transcription of it: one static ground body of 281 boxes (a floor of 81 boxes 1.1 x 1.0 at
x = -40 .. 40, y = 0, and two walls of 100 boxes 1.0 x 1.1 at x = -40 and 40, y = 1 .. 100) and a
segment from (-800, -80) to (800, -80) far below, friction 0.6 (Box2D's default); 20 columns x 150 rows
of dynamic bodies, each made of the two triangles (-1, 0), (0.5, 1), (0, 2) and (1, 0), (-0.5, 1), (0, 2),
density 1, friction 0.5, created column by column at x = 2 i - 19 + side, y = 2.25 j + 0.575 + 5, where
side is +0.25 for the first body and changes sign from each body to the next. Gravity (0, -10), 60 Hz,
4 substeps (rustycs's precision), 500 steps, as Box2D's benchmark runs it. Static boxes are aabb, as in
the other bench scenes; restitution is 0 (Box2D's default).

Usage: python scenes/bench/make_compounds_scene.py [--out FOLDER]
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from rustycs_cli.yaml_source import dump_scene_yaml

HERE = Path(__file__).resolve().parent
HEADER = (
    "# yaml-language-server: $schema=../../rustycs.schema.json\n"
    "# Written by scenes/bench/make_compounds_scene.py after Box2D v3's CreateCompounds: do not edit by "
    "hand.\n"
)
COLUMNS, ROWS = 20, 150
SHIFT, EXTRA_Y, SIDE = 2.0, 0.25, 0.25  # column spacing; row spacing SHIFT + EXTRA_Y; alternating x shift
LEFT = [[-1.0, 0.0], [0.5, 1.0], [0.0, 2.0]]
RIGHT = [[1.0, 0.0], [-0.5, 1.0], [0.0, 2.0]]
MATERIALS = {  # named as make_bench_scenes.py names them
    "bench": {"density": 1.0, "restitution": 0.0, "friction": 0.6},
    "bench-f0.5": {"density": 1.0, "restitution": 0.0, "friction": 0.5},
}


def _box(width: float, height: float, x: float, y: float) -> dict[str, Any]:
    return {"type": "aabb", "width": width, "height": height, "offset": [x, y]}


def ground() -> dict[str, Any]:
    """The static container: floor, two walls and the segment below, all on one body."""
    floor = [_box(1.1, 1.0, float(x), 0.0) for x in range(-40, 41)]
    walls = [_box(1.0, 1.1, float(x), float(y)) for x in (-40, 40) for y in range(1, 101)]
    segment = {"type": "segment", "points": [[-800.0, -80.0], [800.0, -80.0]]}
    return {"name": "ground", "type": "static", "position": [0.0, 0.0], "material": "bench",
            "shapes": [*floor, *walls, segment]}


def compounds() -> list[dict[str, Any]]:
    """The dynamic bodies of two triangles each, in Box2D's creation order."""
    bodies, side = [], SIDE
    center_x, center_y, start_y = SHIFT * COLUMNS / 2 - 1.0, 1.15 / 2, 5.0
    for i in range(COLUMNS):
        x = i * SHIFT - center_x
        for j in range(ROWS):
            y = j * (SHIFT + EXTRA_Y) + center_y + start_y
            bodies.append({"name": f"compound-{len(bodies)}", "position": [round(x + side, 9), round(y, 9)],
                           "material": "bench-f0.5", "shapes": [{"type": "polygon", "vertices": LEFT},
                                                              {"type": "polygon", "vertices": RIGHT}]})
            side = -side
    return bodies


def scene() -> dict[str, Any]:
    """The whole scene, in the rustycs scene format."""
    return {
        "name": "compounds",
        "description": f"Box2D v3's benchmark scene compounds: {COLUMNS * ROWS} dynamic bodies of two "
                       "triangles each falling into a container of 281 static boxes, 500 steps of 1/60 s.",
        "world": {"tick_rate": 60, "ticks": 500, "precision": 4},
        "forces": [{"name": "gravity", "acceleration": [0.0, -10.0]}],
        "materials": MATERIALS,
        "bodies": [ground(), *compounds()],
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=HERE, help="folder for compounds.yaml")
    args = parser.parse_args()
    target = args.out / "compounds.yaml"
    target.write_text(dump_scene_yaml(scene(), HEADER), encoding="utf-8")
    print(f"{target}: {1 + COLUMNS * ROWS} bodies")


if __name__ == "__main__":
    main()
