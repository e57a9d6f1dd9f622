"""Write shower.yaml: the bench's scene of fast bodies (issue 12), 500 small circles shot at 100 to
300 m/s in every direction inside a closed box of walls 2 cm thick, with gravity. Each circle is a
`bullet` (continuous collision against dynamic bodies too), so that Box2D v3 runs them with its bullets.
A circle that ends outside the box passed through a wall.

The box's inside is 20 x 20 m (walls centred 1 cm outside it); the circles' radii are uniform in
[0.05, 0.1] m, their centres uniform in the inside's upper half, 0.2 m clear of the walls, their
speeds uniform in [100, 300] m/s at angles uniform in [0, 2 pi); restitution 0.5, friction 0.3,
density 1; 60 Hz, 4 substeps, 300 ticks. Drawn by numpy's default generator from seed 12, written out
body by body.

Usage: python scenes/bench/make_shower_scene.py [--out FOLDER]
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Any

import numpy as np

from rustycs_cli.yaml_source import dump_scene_yaml

HERE = Path(__file__).resolve().parent
HEADER = (
    "# yaml-language-server: $schema=../../rustycs.schema.json\n"
    "# Written by scenes/bench/make_shower_scene.py: do not edit by hand.\n"
)
COUNT, SEED = 500, 12
HALF, WALL = 10.0, 0.02  # half the inside's width, m; the walls' thickness
MATERIALS = {"shower": {"density": 1.0, "restitution": 0.5, "friction": 0.3}}


def walls() -> dict[str, Any]:
    """The closed box: one static body of four thin walls."""
    span = 2 * HALF + 2 * WALL
    offset = HALF + WALL / 2
    return {"name": "box", "type": "static", "position": [0.0, 0.0], "material": "shower",
            "shapes": [{"type": "aabb", "width": span, "height": WALL, "offset": [0.0, -offset]},
                       {"type": "aabb", "width": span, "height": WALL, "offset": [0.0, offset]},
                       {"type": "aabb", "width": WALL, "height": span, "offset": [-offset, 0.0]},
                       {"type": "aabb", "width": WALL, "height": span, "offset": [offset, 0.0]}]}


def circles() -> list[dict[str, Any]]:
    """The fast circles, drawn reproducibly."""
    rng = np.random.default_rng(SEED)
    bodies = []
    for i in range(COUNT):
        radius = float(rng.uniform(0.05, 0.1))
        x = float(rng.uniform(-HALF + 0.2, HALF - 0.2))
        y = float(rng.uniform(0.2, HALF - 0.2))
        speed = float(rng.uniform(100.0, 300.0))
        heading = float(rng.uniform(0.0, 2.0 * math.pi))
        bodies.append({"name": f"drop-{i}", "shape": {"type": "circle", "radius": round(radius, 6)},
                       "position": [round(x, 6), round(y, 6)],
                       "velocity": [round(speed * math.cos(heading), 6), round(speed * math.sin(heading), 6)],
                       "material": "shower", "bullet": True})
    return bodies


def scene() -> dict[str, Any]:
    """The whole scene, in the rustycs scene format."""
    return {
        "name": "shower",
        "description": f"{COUNT} small circles shot at 100-300 m/s inside a closed box of walls 2 cm thick: "
                       "none may pass through a wall (issue 12's scene of fast bodies).",
        "world": {"tick_rate": 60, "ticks": 300, "precision": 4},
        "forces": [{"name": "gravity", "acceleration": [0.0, -9.81]}],
        "materials": MATERIALS,
        "bodies": [walls(), *circles()],
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=HERE, help="folder for shower.yaml")
    args = parser.parse_args()
    target = args.out / "shower.yaml"
    target.write_text(dump_scene_yaml(scene(), HEADER), encoding="utf-8")
    print(f"{target}: {1 + COUNT} bodies")


if __name__ == "__main__":
    main()
