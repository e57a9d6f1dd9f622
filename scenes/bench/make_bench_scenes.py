"""Write the six benchmark scenes (S1_bounce.yaml ... S6_orbits.yaml) from the peer benchmark's definitions.

The peers' `scenes.py` is the single definition of the benchmark bodies (its random ones are seeded); this
script imports it by path and writes every body out expanded, so rustycs runs exactly the bodies the
peer engines run. Conventions: dt 1/60 s, 4 solver substeps per tick (like Box2D v3), density 1 through
user materials, static boxes as aabb, dynamic boxes as obb, polygons as their convex hull, Box2D's
negative collision groups as the positive rustycs group with the same meaning, S6's central body G*M as an
attractor of mass GM with G = 1.

Polygons: `_random_convex` in scenes.py draws the x and y of a vertex with different angles, so a few of
its point sets are not convex (4 of S5's 500). Every peer engine builds the convex hull of the points it
is given (Box2D's b2ComputeHull, Chipmunk's cpConvexHull), so the hull is what they simulate, and what is
written here: the points that are not on it are left out, the others keep their order.

Usage: python scenes/bench/make_bench_scenes.py [--peers ../shared/bench/peers/scenes.py]
"""

from __future__ import annotations

import argparse
import importlib.util
from pathlib import Path
from types import ModuleType
from typing import Any

from rustycs.polygon import polygon_problem
from rustycs_cli.yaml_source import dump_scene_yaml

HERE = Path(__file__).resolve().parent
DEFAULT_PEERS = HERE.parents[2] / "shared" / "bench" / "peers" / "scenes.py"
HEADER = (
    "# yaml-language-server: $schema=../../rustycs.schema.json\n"
    "# Written by scenes/bench/make_bench_scenes.py from shared/bench/peers/scenes.py: do not edit by hand.\n"
)
PRECISION = 4


def load_peers(path: Path) -> ModuleType:
    """Import the peers' scenes.py from its path."""
    spec = importlib.util.spec_from_file_location("peer_scenes", path)
    if spec is None or spec.loader is None:
        raise SystemExit(f"{path}: cannot import")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _material(materials: dict[str, Any], friction: float, restitution: float, density: float) -> str:
    """The name of the user material with these coefficients (added to `materials` on first use)."""
    name = "bench" if restitution == 0 else f"bench-e{restitution:g}"
    if friction != 0.6:
        name += f"-f{friction:g}"
    materials.setdefault(name, {"density": density, "restitution": restitution, "friction": friction})
    return name


def convex_hull(points: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """The points on the convex hull (strictly convex corners), in their given cyclic order."""
    ordered = sorted(set(points))

    def chain(pts: list[tuple[float, float]]) -> list[tuple[float, float]]:
        out: list[tuple[float, float]] = []
        for p in pts:
            while len(out) >= 2 and ((out[-1][0] - out[-2][0]) * (p[1] - out[-2][1])
                                     - (out[-1][1] - out[-2][1]) * (p[0] - out[-2][0])) <= 0:
                out.pop()
            out.append(p)
        return out[:-1]

    corners = set(chain(ordered) + chain(ordered[::-1]))
    hull = [p for p in points if p in corners]
    problem = polygon_problem(hull)
    if problem is not None:
        raise SystemExit(f"hull of {points}: {problem.message}")
    return hull


def _group(group: int | None) -> dict[str, int]:
    """Box2D's negative group g (same group never collides) is the rustycs collision_group -g."""
    return {} if group is None else {"collision_group": -group}


def _static_name(index: int, statics: list[dict[str, Any]]) -> str:
    """ground (one box), center (one circle), floor and walls (the container), else static-<i>."""
    if len(statics) == 1:
        return "center" if statics[0].get("shape") == "circle" else "ground"
    if len(statics) == 3:
        return ("floor", "left-wall", "right-wall")[index]
    return f"static-{index}"


def _statics(spec: dict[str, Any], materials: dict[str, Any], density: float) -> list[dict[str, Any]]:
    bodies = []
    for index, static in enumerate(spec["statics"]):
        if static.get("shape") == "circle":
            shape = {"type": "circle", "radius": static["r"]}
        else:
            shape = {"type": "aabb", "width": 2 * static["hx"], "height": 2 * static["hy"]}
        material = _material(materials, static["friction"], static["restitution"], density)
        bodies.append({"name": _static_name(index, spec["statics"]), "type": "static", "shape": shape,
                       "position": [static["cx"], static["cy"]], "material": material,
                       **_group(static.get("group"))})
    return bodies


def _dynamic(spec: dict[str, Any], materials: dict[str, Any], density: float) -> list[dict[str, Any]]:
    counts: dict[str, int] = {}
    bodies = []
    for body in spec["bodies"]:
        kind = body["shape"]
        if kind == "circle":
            shape = {"type": "circle", "radius": body["r"]}
        elif kind == "box":
            shape = {"type": "obb", "width": 2 * body["hx"], "height": 2 * body["hy"]}
        else:
            hull = convex_hull([(x, y) for x, y in body["verts"]])
            shape = {"type": "polygon", "vertices": [[x, y] for x, y in hull]}
        index = counts[kind] = counts.get(kind, -1) + 1
        out: dict[str, Any] = {"name": f"{kind}-{index}", "shape": shape, "position": [body["x"], body["y"]]}
        if body["vx"] or body["vy"]:
            out["velocity"] = [body["vx"], body["vy"]]
        if body["angle"]:
            out["angle"] = body["angle"]
        out["material"] = _material(materials, body["friction"], body["restitution"], density)
        out.update(_group(body.get("group")))
        bodies.append(out)
    return bodies


def convert(scene_id: str, spec: dict[str, Any], peers: ModuleType) -> dict[str, Any]:
    """One benchmark scene in the rustycs scene format."""
    materials: dict[str, Any] = {}
    bodies = _statics(spec, materials, peers.DENSITY) + _dynamic(spec, materials, peers.DENSITY)
    data: dict[str, Any] = {
        "name": spec["name"],
        "description": f"Benchmark scene {scene_id} ({spec['metric']}) with exactly the bodies of the peer "
                       f"benchmark's scenes.py: {len(spec['bodies'])} dynamic bodies, {spec['steps']} steps "
                       "of 1/60 s.",
        "world": {"tick_rate": round(1.0 / peers.DT), "ticks": spec["steps"], "precision": PRECISION},
    }
    if any(spec["gravity"]):
        data["forces"] = [{"name": "gravity", "acceleration": list(spec["gravity"])}]
    if "central_gm" in spec:
        data["world"]["gravitational_constant"] = 1.0
        data["attractors"] = [{"name": "center", "position": [0.0, 0.0], "mass": spec["central_gm"]}]
    data["materials"] = materials
    data["bodies"] = bodies
    return data


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--peers", type=Path, default=DEFAULT_PEERS, help="the peers' scenes.py")
    parser.add_argument("--out", type=Path, default=HERE, help="folder for the YAML files")
    args = parser.parse_args()
    peers = load_peers(args.peers)
    for scene_id, make in peers.SCENES.items():
        spec = make()
        target = args.out / f"{spec['name']}.yaml"
        target.write_text(dump_scene_yaml(convert(scene_id, spec, peers), HEADER), encoding="utf-8")
        print(f"{target}: {len(spec['statics']) + len(spec['bodies'])} bodies")


if __name__ == "__main__":
    main()
