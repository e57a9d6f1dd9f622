"""Write the joint demos into scenes/ and the joint benchmark scenes into scenes/bench/.

Demos: pendulum, double_pendulum, newtons_cradle, chain_bridge, car, ragdoll, crank_slider, pulley,
gear_train. Bench: joint_grid (Box2D v3's benchmark: a 100 x 100 grid of circles joined by 19,800
revolute joints, its middle seven top circles static) and ragdoll_rain (Box2D's ragdolls, its human of
eleven capsules and ten limited, frictional revolute joints, dropped in rows onto pegs and a floor; Box2D's
rain benchmark adds and removes its humans as it goes, these all start at once).

Usage: python scenes/make_joint_scenes.py [--out FOLDER]   (FOLDER/bench for the bench scenes)
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Any

from rustycs_cli.yaml_source import dump_scene_yaml

HERE = Path(__file__).resolve().parent
G = 9.81
GRAVITY = {"name": "gravity", "acceleration": [0.0, -G]}
Scene = dict[str, Any]


def _header(depth: str) -> str:
    return (f"# yaml-language-server: $schema={depth}rustycs.schema.json\n"
            "# Written by scenes/make_joint_scenes.py: do not edit by hand.\n")


def _r(value: float) -> float:
    return round(value, 6)


def _p(x: float, y: float) -> list[float]:
    return [_r(x), _r(y)]


def pendulum() -> Scene:
    length, theta = 1.0, 0.05
    bob = _p(length * math.sin(theta), -length * math.cos(theta))
    return {
        "name": "pendulum",
        "description": f"A {length:g} m pendulum released {theta:g} rad from the vertical: a point bob on a "
                       "rigid rod (a distance joint to the world) swings with the period 2 pi sqrt(L/g) "
                       f"= {2 * math.pi * math.sqrt(length / G):.4f} s.",
        "world": {"tick_rate": 240, "ticks": 1920, "precision": 4},
        "forces": [GRAVITY],
        "bodies": [{"name": "bob", "shape": {"type": "circle", "radius": 0.05}, "position": bob,
                    "material": "metal"}],
        "joints": [{"name": "rod", "type": "distance", "body": "bob", "anchors": [[0.0, 0.0], bob]}],
    }


def _rod(name: str, x0: float, length: float) -> dict[str, Any]:
    return {"name": name, "shape": {"type": "obb", "width": length, "height": 0.05},
            "position": _p(x0 + length / 2, 0.0), "material": "metal"}


def double_pendulum() -> Scene:
    return {
        "name": "double_pendulum",
        "description": "Two 1 m rods hinged end to end, released horizontal: chaotic, and its energy is "
                       "kept.",
        "world": {"tick_rate": 240, "ticks": 2400, "precision": 8},
        "forces": [GRAVITY],
        "bodies": [_rod("upper", 0.0, 1.0), _rod("lower", 1.0, 1.0)],
        "joints": [
            {"name": "shoulder", "type": "revolute", "body": "upper", "anchor": [0.0, 0.0]},
            {"name": "elbow", "type": "revolute", "bodies": ["upper", "lower"], "anchor": [1.0, 0.0]},
        ],
    }


CRADLE_RADIUS, CRADLE_LENGTH, CRADLE_ANGLE = 0.1, 1.0, 0.6


def newtons_cradle() -> Scene:
    bodies, joints = [], []
    for i in range(5):
        top = _p((i - 2) * 2 * CRADLE_RADIUS, CRADLE_LENGTH)
        x, y = top[0], 0.0
        if i == 0:  # pulled back along its arc
            x, y = x - CRADLE_LENGTH * math.sin(CRADLE_ANGLE), CRADLE_LENGTH * (1 - math.cos(CRADLE_ANGLE))
        bodies.append({"name": f"ball-{i + 1}", "shape": {"type": "circle", "radius": CRADLE_RADIUS},
                       "position": _p(x, y), "material": "steel"})
        joints.append({"name": f"string-{i + 1}", "type": "distance", "body": f"ball-{i + 1}",
                       "anchors": [top, _p(x, y)]})
    return {
        "name": "newtons_cradle",
        "description": "Newton's cradle: five touching elastic balls on 1 m strings; the first, released "
                       f"{CRADLE_ANGLE:g} rad up its arc, stops and the last leaves with its speed.",
        "world": {"tick_rate": 240, "ticks": 960, "precision": 4, "restitution_threshold": 0.0},
        "forces": [GRAVITY],
        "materials": {"steel": {"density": 7.8, "restitution": 1.0, "friction": 0.0}},
        "bodies": bodies,
        "joints": joints,
    }


def chain_bridge() -> Scene:
    links, width, y = 30, 0.5, 0.0
    left = -links * width / 2
    bodies: list[dict[str, Any]] = [
        {"name": "bank-left", "type": "static", "shape": {"type": "obb", "width": 2.0, "height": 1.0},
         "position": _p(left - 1.0, y - 0.5)},
        {"name": "bank-right", "type": "static", "shape": {"type": "obb", "width": 2.0, "height": 1.0},
         "position": _p(-left + 1.0, y - 0.5)},
    ]
    joints = []
    for k in range(links):
        bodies.append({"name": f"link-{k}", "shape": {"type": "obb", "width": width, "height": 0.125},
                       "position": _p(left + width * (k + 0.5), y - 0.0625), "material": "plastic"})
        joints.append({"name": f"hinge-{k}", "type": "revolute",
                       "bodies": ["bank-left" if k == 0 else f"link-{k - 1}", f"link-{k}"],
                       "anchor": _p(left + width * k, y - 0.0625)})
    joints.append({"name": f"hinge-{links}", "type": "revolute",
                   "bodies": [f"link-{links - 1}", "bank-right"], "anchor": _p(-left, y - 0.0625)})
    loads = [{"name": f"crate-{k}", "shape": {"type": "obb", "width": 0.6, "height": 0.6},
              "position": _p(x, 2.0 + k), "material": "stone"} for k, x in enumerate((-4.0, 0.5, 3.0))]
    return {
        "name": "chain_bridge",
        "description": f"A bridge of {links} planks hinged end to end between two banks; three crates "
                       "fall on it and it sags under them.",
        "world": {"tick_rate": 60, "ticks": 600, "precision": 8},
        "forces": [GRAVITY],
        "bodies": [*bodies, *loads],
        "joints": joints,
    }


def car() -> Scene:
    # bumps every 2 m, 10-20 cm high, on a 120 m track
    points = [_p(-10.0 + 0.5 * k, 0.12 * math.sin(0.5 * math.pi * k) * (1 + (k % 3) / 2)) for k in range(241)]
    chassis = [[-1.2, -0.2], [1.2, -0.2], [1.2, 0.1], [0.3, 0.5], [-0.9, 0.5], [-1.2, 0.1]]
    wheels = [(f"wheel-{side}", x) for side, x in (("rear", -0.8), ("front", 0.8))]
    return {
        "name": "car",
        "description": "A car of a six-sided chassis and two wheels on sprung wheel joints, the rear one "
                       "driven by a motor, drives over a bumpy chain terrain.",
        "world": {"tick_rate": 60, "ticks": 900, "precision": 8},
        "forces": [GRAVITY],
        "bodies": [
            {"name": "terrain", "type": "static", "shape": {"type": "chain", "points": points},
             "position": [0.0, 0.0], "material": "stone"},
            {"name": "chassis", "shape": {"type": "polygon", "vertices": chassis}, "position": [0.0, 1.0],
             "material": "plastic", "collision_group": 1},
            *({"name": name, "shape": {"type": "circle", "radius": 0.4}, "position": _p(x, 0.6),
               "material": "rubber", "collision_group": 1} for name, x in wheels),
        ],
        "joints": [
            {"name": "suspension-rear", "type": "wheel", "bodies": ["chassis", "wheel-rear"],
             "anchor": [-0.8, 0.6], "axis": [0.0, 1.0], "spring": {"hertz": 5.0, "damping_ratio": 0.7},
             "limits": [-0.25, 0.25], "motor": {"speed": -12.0, "max_torque": 25.0}},
            {"name": "suspension-front", "type": "wheel", "bodies": ["chassis", "wheel-front"],
             "anchor": [0.8, 0.6], "axis": [0.0, 1.0], "spring": {"hertz": 5.0, "damping_ratio": 0.7},
             "limits": [-0.25, 0.25]},
        ],
    }


# Box2D v3's human (shared/human.c) at scale 1, standing with its feet at y = 0: bone, parent, centre,
# capsule end points (vertical, about the centre), radius, joint pivot, joint limits (fractions of pi)
BONES = (
    ("hip", None, 0.95, (-0.02, 0.02), 0.095, None, None),
    ("torso", "hip", 1.2, (-0.135, 0.135), 0.09, 1.0, (-0.25, 0.0)),
    ("head", "torso", 1.475, (-0.0325, 0.0325), 0.08, 1.4, (-0.3, 0.1)),
    ("upper-leg-left", "hip", 0.775, (-0.125, 0.125), 0.06, 0.9, (-0.05, 0.4)),
    ("lower-leg-left", "upper-leg-left", 0.475, (-0.14, 0.125), 0.05, 0.625, (-0.5, -0.02)),
    ("upper-leg-right", "hip", 0.775, (-0.125, 0.125), 0.06, 0.9, (-0.05, 0.4)),
    ("lower-leg-right", "upper-leg-right", 0.475, (-0.14, 0.125), 0.05, 0.625, (-0.5, -0.02)),
    ("upper-arm-left", "torso", 1.225, (-0.125, 0.125), 0.035, 1.35, (-0.1, 0.8)),
    ("lower-arm-left", "upper-arm-left", 0.975, (-0.125, 0.125), 0.03, 1.1, (0.01, 0.5)),
    ("upper-arm-right", "torso", 1.225, (-0.125, 0.125), 0.035, 1.35, (-0.1, 0.8)),
    ("lower-arm-right", "upper-arm-right", 0.975, (-0.125, 0.125), 0.03, 1.1, (0.01, 0.5)),
)
JOINT_FRICTION = 0.05  # N m: Box2D's human holds its joints with motors of speed 0 and this torque
HUMAN_MATERIAL = {"density": 1.0, "restitution": 0.0, "friction": 0.6}


def human(prefix: str, x: float, y: float, group: int) -> tuple[list[dict[str, Any]], list[dict[str, Any]]]:
    """The bodies and joints of one ragdoll with its feet at (x, y); its bones never collide with each
    other (`group`)."""
    bodies, joints = [], []
    for name, parent, centre, (low, high), radius, pivot, limits in BONES:
        bodies.append({"name": f"{prefix}{name}", "position": _p(x, y + centre), "material": "skin",
                       "collision_group": group,
                       "shape": {"type": "capsule", "length": _r(high - low), "radius": radius,
                                 "offset": _p(0.0, (high + low) / 2), "angle": _r(math.pi / 2)}})
        if parent is not None:
            joints.append({"name": f"{prefix}{name}", "type": "revolute",
                           "bodies": [f"{prefix}{parent}", f"{prefix}{name}"], "anchor": _p(x, y + pivot),
                           "limits": [_r(limits[0] * math.pi), _r(limits[1] * math.pi)],
                           "motor": {"speed": 0.0, "max_torque": JOINT_FRICTION}})
    return bodies, joints


def ragdoll() -> Scene:
    bodies, joints = human("", 0.3, 1.0, 1)
    for bone in bodies:  # it stumbles forward off the top step
        bone["velocity"] = [1.5, 0.0]
    steps = [{"name": f"step-{k}", "type": "static", "shape": {"type": "obb", "width": 1.0, "height": 0.4},
              "position": _p(0.6 + k, 0.6 - 0.4 * k)} for k in range(3)]
    return {
        "name": "ragdoll",
        "description": "Box2D's human: eleven capsules held by ten revolute joints with limits and joint "
                       "friction, tumbling down three steps.",
        "world": {"tick_rate": 60, "ticks": 600, "precision": 8},
        "forces": [GRAVITY],
        "materials": {"skin": HUMAN_MATERIAL},
        "bodies": [{"name": "ground", "type": "static",
                    "shape": {"type": "obb", "width": 20.0, "height": 1.0}, "position": [0.0, -1.3]},
                   *steps, *bodies],
        "joints": joints,
    }


def crank_slider() -> Scene:
    crank, rod = 1.0, 2.0
    reach = math.sqrt(rod**2 - crank**2)
    return {
        "name": "crank_slider",
        "description": "A motor turns a crank; a connecting rod pushes a piston back and forth along a "
                       "prismatic joint (Box2D's slider crank).",
        "world": {"tick_rate": 60, "ticks": 600, "precision": 8},
        "forces": [GRAVITY],
        "bodies": [
            {"name": "crank", "shape": {"type": "obb", "width": 0.1, "height": crank},
             "position": _p(0.0, crank / 2), "collision_group": 1},
            {"name": "rod", "shape": {"type": "obb", "width": rod, "height": 0.1},
             "position": _p(reach / 2, crank / 2), "angle": _r(-math.atan2(crank, reach)),
             "collision_group": 1},
            {"name": "piston", "shape": {"type": "obb", "width": 0.6, "height": 0.4},
             "position": _p(reach, 0.0), "collision_group": 1},
        ],
        "joints": [
            {"name": "shaft", "type": "revolute", "body": "crank", "anchor": [0.0, 0.0],
             "motor": {"speed": 3.0, "max_torque": 500.0}},
            {"name": "crank-pin", "type": "revolute", "bodies": ["crank", "rod"], "anchor": _p(0.0, crank)},
            {"name": "wrist-pin", "type": "revolute", "bodies": ["rod", "piston"], "anchor": _p(reach, 0.0)},
            {"name": "cylinder", "type": "prismatic", "body": "piston", "anchor": _p(reach, 0.0),
             "axis": [1.0, 0.0]},
        ],
    }


def pulley() -> Scene:
    return {
        "name": "pulley",
        "description": "Two crates hang from a rope over two fixed wheels: the heavier pulls the lighter up, "
                       "and length_a + length_b stays the same.",
        "world": {"tick_rate": 60, "ticks": 90, "precision": 8},
        "forces": [GRAVITY],
        "bodies": [
            {"name": "heavy", "shape": {"type": "obb", "width": 0.6, "height": 0.6}, "position": [-1.5, 0.0],
             "material": "stone"},
            {"name": "light", "shape": {"type": "obb", "width": 0.6, "height": 0.6}, "position": [1.5, 0.0],
             "material": "plastic"},
        ],
        "joints": [{"name": "rope", "type": "pulley", "bodies": ["heavy", "light"],
                    "anchors": [[-1.5, 0.3], [1.5, 0.3]], "ground_anchors": [[-1.5, 5.0], [1.5, 5.0]]}],
    }


def gear_train() -> Scene:
    gears = (("drive", 1.0, 0.0), ("idler", 0.5, 1.5), ("pinion", 0.25, 2.25))
    bodies: list[dict[str, Any]] = [
        {"name": name, "shape": {"type": "circle", "radius": radius}, "position": [x, 0.0],
         "collision_group": 1} for name, radius, x in gears
    ]
    bodies.append({"name": "rack", "shape": {"type": "obb", "width": 3.0, "height": 0.1},
                   "position": [2.25, -0.3], "collision_group": 1})
    joints: list[dict[str, Any]] = [
        {"name": f"{name}-axle", "type": "revolute", "body": name, "anchor": [x, 0.0]} for name, _, x in gears
    ]
    joints[0]["motor"] = {"speed": 1.0, "max_torque": 100.0}
    joints.append({"name": "rack-guide", "type": "prismatic", "body": "rack", "anchor": [2.25, -0.3],
                   "axis": [1.0, 0.0]})
    for (first, r1, _), (second, r2, _) in zip(gears, gears[1:], strict=False):
        # meshing wheels: r1 w1 = -r2 w2, so angle_1 + (r2 / r1) angle_2 stays constant
        joints.append({"name": f"{first}-{second}", "type": "gear",
                       "joints": [f"{first}-axle", f"{second}-axle"], "ratio": r2 / r1})
    # the rack moves with the pinion's lowest point: v = r w, so angle - translation / r stays constant
    joints.append({"name": "pinion-rack", "type": "gear", "joints": ["pinion-axle", "rack-guide"],
                   "ratio": -1.0 / gears[-1][1]})
    return {
        "name": "gear_train",
        "description": "A motor turns a 1 m wheel geared to a 0.5 m and a 0.25 m wheel, which drives a rack "
                       "on a prismatic joint: each gear joint keeps angle_1 + ratio x angle_2 constant.",
        "world": {"tick_rate": 60, "ticks": 300, "precision": 4},
        "bodies": bodies,
        "joints": joints,
    }


GRID = 100


def joint_grid() -> Scene:
    """Box2D v3's benchmark joint_grid (shared/benchmarks.c, CreateJointGrid): circles of radius 0.4 at
    (k, -i), joined to the one above and the one to the left by revolute joints; the top circles of the
    seven middle columns are static."""
    bodies, joints = [], []
    for k in range(GRID):
        for i in range(GRID):
            static = GRID // 2 - 3 <= k <= GRID // 2 + 3 and i == 0
            bodies.append({"name": f"c-{k}-{i}", **({"type": "static"} if static else {}),
                           "shape": {"type": "circle", "radius": 0.4}, "position": [float(k), float(-i)],
                           "material": "bench", "collision_category": 2, "collision_mask": 1})
            if i > 0:
                joints.append({"name": f"v-{k}-{i}", "type": "revolute",
                               "bodies": [f"c-{k}-{i - 1}", f"c-{k}-{i}"], "anchor": [float(k), -i + 0.5]})
            if k > 0:
                joints.append({"name": f"h-{k}-{i}", "type": "revolute",
                               "bodies": [f"c-{k - 1}-{i}", f"c-{k}-{i}"], "anchor": [k - 0.5, float(-i)]})
    return {
        "name": "joint_grid",
        "description": f"Box2D v3's benchmark joint_grid: {GRID} x {GRID} circles joined by {len(joints)} "
                       "revolute joints hang from seven static circles, 500 steps of 1/60 s.",
        "world": {"tick_rate": 60, "ticks": 500, "precision": 4},
        "forces": [{"name": "gravity", "acceleration": [0.0, -10.0]}],
        "materials": {"bench": {"density": 1.0, "restitution": 0.0, "friction": 0.6}},
        "bodies": bodies,
        "joints": joints,
    }


RAIN_COLUMNS, RAIN_ROWS = 10, 10


def ragdoll_rain() -> Scene:
    # the floor and pegs of Box2D's default material, as the humans' (restitution 0, friction 0.6): with
    # ours (restitution 0.5) the three engines mixed different bounces (pymunk's statics are given
    # elasticity 1 on the bench's rule that statics do not bounce)
    bodies: list[dict[str, Any]] = [
        {"name": "floor", "type": "static", "shape": {"type": "aabb", "width": 60.0, "height": 1.0},
         "position": [0.0, -0.5], "material": "skin"},
        *({"name": f"peg-{k}", "type": "static", "shape": {"type": "circle", "radius": 0.5},
           "position": _p(-13.5 + 3.0 * k, 3.0), "material": "skin"} for k in range(10)),
    ]
    joints: list[dict[str, Any]] = []
    for row in range(RAIN_ROWS):
        for column in range(RAIN_COLUMNS):
            index = row * RAIN_COLUMNS + column
            parts, links = human(f"h{index}-", -13.5 + 3.0 * column + 0.5 * (row % 2), 5.0 + 2.0 * row,
                                 index + 1)
            bodies += parts
            joints += links
    return {
        "name": "ragdoll_rain",
        "description": f"{RAIN_COLUMNS * RAIN_ROWS} of Box2D's ragdolls ({len(joints)} limited, frictional "
                       "revolute joints) fall in rows onto pegs and a floor, after Box2D v3's rain benchmark "
                       "(which adds and removes its humans as it goes), 500 steps of 1/60 s.",
        "world": {"tick_rate": 60, "ticks": 500, "precision": 4},
        "forces": [{"name": "gravity", "acceleration": [0.0, -10.0]}],
        "materials": {"skin": HUMAN_MATERIAL},
        "bodies": bodies,
        "joints": joints,
    }


DEMOS = (pendulum, double_pendulum, newtons_cradle, chain_bridge, car, ragdoll, crank_slider, pulley,
         gear_train)
BENCH = (joint_grid, ragdoll_rain)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=HERE,
                        help="folder of the demos (the bench scenes go to its bench/)")
    args = parser.parse_args()
    for make, folder, depth in [*((m, args.out, "../") for m in DEMOS),
                                *((m, args.out / "bench", "../../") for m in BENCH)]:
        scene = make()
        target = folder / f"{scene['name']}.yaml"
        target.write_text(dump_scene_yaml(scene, _header(depth)), encoding="utf-8")
        print(f"{target}: {len(scene['bodies'])} bodies, {len(scene['joints'])} joints")


if __name__ == "__main__":
    main()
