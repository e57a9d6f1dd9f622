"""The scene files in scenes/ and the JSON Schema at the repository root."""

from __future__ import annotations

import importlib.util
import itertools
import json
import math
from pathlib import Path
from typing import Any

import pytest
import yaml

from rustycs_cli.loading import load_scene
from rustycs_cli.scene import PRESET_MATERIALS, Capsule, Chain, Circle, Obb, Polygon, Scene

ROOT = Path(__file__).resolve().parents[1]
SCENES = sorted((ROOT / "scenes").rglob("*.yaml"))
SHAPES_DEMOS = ["capsule_pile", "cup_of_balls", "curved_ramp", "l_brackets"]  # bodies made of shapes
JOINT_DEMOS = ["car", "chain_bridge", "crank_slider", "double_pendulum", "gear_train", "newtons_cradle",
               "pendulum", "pulley", "ragdoll"]  # written by scenes/make_joint_scenes.py
MEASURES_DEMOS = ["cup_goal", "dominoes", "galton_board", "projectile"]  # emitters, sensors, measures
SLEEP_DEMOS = ["sleeping_pile"]  # world.sleep
DEMOS = sorted(
    [
        "all_platforms",
        "bouncing_ball",
        "material_bounce",
        "pile",
        "pool",
        "slide_and_fall",
        "slope",
        "solar_system",
        *SHAPES_DEMOS,
        *JOINT_DEMOS,
        *MEASURES_DEMOS,
        *SLEEP_DEMOS,
    ]
)
BENCH = ["S1_bounce", "S2_pyramid20", "S3_pyramid40", "S4_rain1000", "S5_polypile500", "S6_orbits",
         "compounds", "joint_grid", "large_pyramid", "many_pyramids", "ragdoll_rain", "shower", "smash",
         "tumbler"]
SLOW_TO_LOAD = ["joint_grid"]  # 30,000 entries: tens of seconds of YAML; tests/test_joint_scenes.py checks it


def test_the_scenes_are_all_there() -> None:
    assert [p.stem for p in SCENES if p.parent.name == "scenes"] == DEMOS
    assert [p.stem for p in SCENES if p.parent.name == "bench"] == BENCH


@pytest.mark.parametrize("path", [p for p in SCENES if p.stem not in SLOW_TO_LOAD], ids=lambda p: p.stem)
def test_every_scene_validates_and_points_at_the_schema(path: Path) -> None:
    loaded = load_scene(path)
    assert loaded.scene.bodies
    schema = path.parent.joinpath(path.read_text().splitlines()[0].split("$schema=")[1]).resolve()
    assert path.read_text().startswith("# yaml-language-server: $schema=")
    assert schema == ROOT / "rustycs.schema.json"


def test_schema_file_is_what_rustycs_schema_writes(cli, tmp_path: Path) -> None:  # noqa: ANN001
    result = cli("schema")
    assert result.exit_code == 0
    assert json.loads(result.stdout) == json.loads((ROOT / "rustycs.schema.json").read_text())
    out = tmp_path / "schema.json"
    assert cli("schema", "-o", out).exit_code == 0
    assert out.read_text() == result.stdout
    assert [p.name for p in tmp_path.iterdir()] == ["schema.json"]  # no temporary left behind


def _properties(schema: dict[str, Any]) -> list[tuple[str, str, dict[str, Any]]]:
    return [
        (model, name, prop)
        for model, definition in [("Scene", schema), *schema["$defs"].items()]
        for name, prop in definition.get("properties", {}).items()
    ]


def test_schema_documents_every_field() -> None:
    schema = Scene.model_json_schema()
    fields = _properties(schema)
    assert len(fields) > 80
    for model, name, prop in fields:
        assert prop.get("description"), f"{model}.{name} has no description"
        assert prop.get("examples"), f"{model}.{name} has no example"
    required = {
        (model, name)
        for model, definition in [("Scene", schema), *schema["$defs"].items()]
        for name in definition.get("required", [])
    }
    for model, name, prop in fields:
        assert (model, name) in required or "default" in prop, f"{model}.{name} has no default"


@pytest.mark.parametrize("path", [p for p in SCENES if p.stem in [*DEMOS, "S1_bounce"]], ids=lambda p: p.stem)
def test_scene_files_satisfy_the_json_schema(path: Path) -> None:  # the big bench scenes take seconds each
    jsonschema = pytest.importorskip("jsonschema")
    schema = json.loads((ROOT / "rustycs.schema.json").read_text())
    data = load_scene(path).text  # every scene as YAML data with generators expanded
    jsonschema.validate(yaml.safe_load(path.read_text()), schema)
    jsonschema.validate(yaml.safe_load(data), schema)


def test_solar_system_planets_are_on_circular_orbits() -> None:
    scene = load_scene(ROOT / "scenes" / "solar_system.yaml").scene
    (sun,) = scene.attractors
    assert sun.mass == 1000 and sun.min_distance == 0.1 and scene.forces == []
    gm = scene.world.gravitational_constant * sun.mass
    assert len(scene.bodies) == 8
    for planet in scene.bodies:
        (x, y), (vx, vy) = planet.position, planet.velocity
        r = math.hypot(x, y)
        assert math.hypot(vx, vy) == pytest.approx(math.sqrt(gm / r), rel=1e-10)
        assert x * vx + y * vy == 0 and x * vy - y * vx > 0  # perpendicular, counter-clockwise


def test_material_bounce_has_the_five_materials() -> None:
    scene = load_scene(ROOT / "scenes" / "material_bounce.yaml").scene
    balls = [b for b in scene.bodies if b.type == "dynamic"]
    assert [b.material for b in balls] == ["rubber", "plastic", "stone", "metal", "default"]
    assert [b.position for b in balls] == [(x, 5.0) for x in (-4, -2, 0, 2, 4)]
    assert all(isinstance(b.shape, Circle) and b.shape.radius == 0.2 for b in balls)
    assert scene.world.tick_rate == 240 and set(PRESET_MATERIALS) == {b.material for b in balls}


def test_cup_of_balls_carries_its_balls_inside() -> None:
    floor, cup, *balls = load_scene(ROOT / "scenes" / "cup_of_balls.yaml").scene.bodies
    assert floor.type == "static" and cup.type == "dynamic" and cup.position == (0, 3)
    shapes = cup.shapes or []
    assert all(isinstance(s, Obb) for s in shapes) and [s.offset for s in shapes] == [
        (0, -0.9),
        (-0.9, 0),
        (0.9, 0),
    ]
    bottom_top = cup.position[1] + shapes[0].offset[1] + shapes[0].height / 2
    inner = shapes[2].offset[0] - shapes[2].width / 2
    assert (bottom_top, inner) == pytest.approx((2.2, 0.8))
    assert len(balls) == 5
    for ball in balls:
        assert isinstance(ball.shape, Circle)
        (x, y), r = ball.position, ball.shape.radius
        assert abs(x) + r < inner and y - r > bottom_top
        assert all(math.dist(ball.position, other.position) > 2 * r for other in balls if other is not ball)


def test_curved_ramp_is_a_quarter_circle_of_64_points() -> None:
    ramp, floor, ball = load_scene(ROOT / "scenes" / "curved_ramp.yaml").scene.bodies
    assert isinstance(ramp.shape, Chain) and ramp.type == "static" and not ramp.shape.loop
    points = ramp.shape.points
    assert len(points) == 64 and points[0] == (0, 3) and points[-1] == (3, 0)
    assert all(abs(math.dist(p, (3, 3)) - 3) < 1e-6 for p in points)
    turns = [math.atan2(y - 3, x - 3) % (2 * math.pi) for x, y in points]  # pi at the top, 3 pi / 2 below
    steps = [b - a for a, b in itertools.pairwise(turns)]
    assert steps == pytest.approx([0.5 * math.pi / 63] * 63, abs=1e-6)  # evenly spread, in order
    assert floor.position[0] - floor.shape.width / 2 == 3  # the floor goes on where the ramp ends
    assert isinstance(ball.shape, Circle)
    assert 3 - math.dist(ball.position, (3, 3)) - ball.shape.radius == pytest.approx(0, abs=1e-6)  # on it
    assert math.degrees(math.atan2(3 - ball.position[0], 3 - ball.position[1])) == pytest.approx(50, abs=1e-4)
    assert ball.position[1] - ball.shape.radius == pytest.approx(1.0, abs=1e-3)  # 1 m above the bottom


def test_capsule_pile_starts_apart_inside_its_container() -> None:
    container, *capsules = load_scene(ROOT / "scenes" / "capsule_pile.yaml").scene.bodies
    assert container.type == "static" and [s.type for s in container.shapes or []] == ["aabb"] * 3
    assert len(capsules) == 40 and all(isinstance(c.shape, Capsule) for c in capsules)
    reach = [c.shape.length / 2 + c.shape.radius for c in capsules]
    assert all(0.15 + 0.08 <= r <= 0.4 + 0.15 for r in reach)
    for k, capsule in enumerate(capsules):
        (x, y) = capsule.position
        assert abs(x) + reach[k] < 3.0 and y - reach[k] > 0  # inside the walls, above the floor
        for j in range(k):
            assert math.dist(capsule.position, capsules[j].position) > reach[k] + reach[j]


def test_l_brackets_are_concave_hexagons_that_start_apart_inside_the_box() -> None:
    floor, left, right, *brackets = load_scene(ROOT / "scenes" / "l_brackets.yaml").scene.bodies
    assert [b.type for b in (floor, left, right)] == ["static"] * 3 and len(brackets) == 40
    inner = right.position[0] - right.shape.width / 2
    for k, bracket in enumerate(brackets):
        assert isinstance(bracket.shape, Polygon) and bracket.type == "dynamic"
        vertices = bracket.shape.vertices
        turns = [
            (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0])
            for a, b, c in zip(
                vertices[-1:] + vertices[:-1], vertices, vertices[1:] + vertices[:1], strict=True
            )
        ]
        assert len(vertices) == 6 and sum(t < 0 for t in turns) == 1  # one reflex corner: an L
        reach = max(math.hypot(x, y) for x, y in vertices)  # about the origin, whatever the angle
        (x, y) = bracket.position
        assert abs(x) + reach < inner and y - reach > 0
        assert all(math.dist(bracket.position, other.position) > 2 * reach for other in brackets[:k])


def _peers() -> Any:
    path = ROOT.parent / "shared" / "bench" / "peers" / "scenes.py"
    if not path.exists():
        pytest.skip(f"the peer benchmark's scenes.py is not next to this checkout ({path})")
    spec = importlib.util.spec_from_file_location("peer_scenes_for_test", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_bench_scenes_are_what_the_converter_writes() -> None:
    _peers()
    script = ROOT / "scenes" / "bench" / "make_bench_scenes.py"
    spec = importlib.util.spec_from_file_location("make_bench", script)
    assert spec is not None and spec.loader is not None
    converter = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(converter)
    peers = converter.load_peers(converter.DEFAULT_PEERS)
    for scene_id, make in peers.SCENES.items():
        made = make()
        text = converter.dump_scene_yaml(converter.convert(scene_id, made, peers), converter.HEADER)
        assert text == (ROOT / "scenes" / "bench" / f"{made['name']}.yaml").read_text()


@pytest.mark.parametrize("scene_id", ["S1", "S2", "S4", "S5", "S6"])
def test_bench_scenes_have_the_peers_bodies(scene_id: str) -> None:
    peers = _peers()
    spec = peers.SCENES[scene_id]()
    scene = load_scene(ROOT / "scenes" / "bench" / f"{spec['name']}.yaml").scene
    statics = [b for b in scene.bodies if b.type == "static"]
    dynamic = [b for b in scene.bodies if b.type == "dynamic"]
    assert len(statics) == len(spec["statics"]) and len(dynamic) == len(spec["bodies"])
    assert scene.world.tick_rate == 60 and scene.world.ticks == spec["steps"] and scene.world.precision == 4
    assert [tuple(f.acceleration) for f in scene.forces] == ([] if scene_id == "S6" else [(0.0, -9.81)])
    for body, peer in zip(dynamic, spec["bodies"], strict=True):
        assert body.position == (peer["x"], peer["y"]) and body.angle == peer["angle"]
        assert body.velocity == (peer["vx"], peer["vy"])
        material = scene.material_of(body)
        assert (material.density, material.friction) == (1.0, 0.6)
        assert material.restitution == peer["restitution"]
        if peer["shape"] == "box":
            assert (body.shape.type, body.shape.width, body.shape.height) == (
                "obb",
                2 * peer["hx"],
                2 * peer["hy"],
            )
        elif peer["shape"] == "circle":
            assert body.shape.radius == peer["r"]
        else:  # the peers' engines all take the convex hull of the points
            hull = [tuple(v) for v in body.shape.vertices]
            assert set(hull) <= {tuple(v) for v in peer["verts"]} and len(hull) >= len(peer["verts"]) - 1
        assert body.collision_group == (1 if scene_id == "S6" else 0)
    for body, peer in zip(statics, spec["statics"], strict=True):
        assert body.position == (peer["cx"], peer["cy"]) and scene.material_of(body).restitution == 0
    if scene_id == "S6":
        (center,) = scene.attractors
        assert center.mass * scene.world.gravitational_constant == peers.ORBIT_GM
        assert statics[0].collision_group == 1
    if scene_id == "S1":
        assert [scene.material_of(b).restitution for b in dynamic] == [0.9, 0.6, 0.4, 0.2, 0.0]


def _compounds_script() -> Any:
    script = ROOT / "scenes" / "bench" / "make_compounds_scene.py"
    spec = importlib.util.spec_from_file_location("make_compounds", script)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_compounds_is_what_its_script_writes() -> None:
    script = _compounds_script()
    text = script.dump_scene_yaml(script.scene(), script.HEADER)
    assert text == (ROOT / "scenes" / "bench" / "compounds.yaml").read_text()


TRIANGLES = ([(-1, 0), (0.5, 1), (0, 2)], [(1, 0), (-0.5, 1), (0, 2)])


def test_compounds_has_box2ds_bodies() -> None:
    """Box2D v3's CreateCompounds: a ground of 281 boxes and a segment on one static body; 20 columns of
    150 bodies of two triangles, side shifted +-0.25 alternately in creation order."""
    scene = Scene.model_validate(_compounds_script().scene())  # what the file holds, without parsing it
    ground, *bodies = scene.bodies
    assert scene.world.tick_rate == 60 and scene.world.ticks == 500 and scene.world.precision == 4
    assert [f.acceleration for f in scene.forces] == [(0.0, -10.0)]
    shapes = ground.shapes or []
    assert ground.type == "static" and [s.type for s in shapes] == ["aabb"] * 281 + ["segment"]
    floor, walls = shapes[:81], shapes[81:281]
    assert [s.offset for s in floor] == [(float(x), 0.0) for x in range(-40, 41)]
    assert {(s.width, s.height) for s in floor} == {(1.1, 1.0)}
    assert {(s.width, s.height) for s in walls} == {(1.0, 1.1)}
    assert sorted(s.offset for s in walls) == [(float(x), float(y)) for x in (-40, 40) for y in range(1, 101)]
    assert shapes[-1].points == [(-800.0, -80.0), (800.0, -80.0)]
    assert scene.material_of(ground).friction == 0.6
    assert len(bodies) == 3000 and {b.type for b in bodies} == {"dynamic"}
    for k, body in enumerate(bodies):
        column, row = divmod(k, 150)
        side = 0.25 if k % 2 == 0 else -0.25
        assert body.position == pytest.approx((2 * column - 19 + side, 2.25 * row + 0.575 + 5), abs=1e-9)
        assert [s.vertices for s in body.shapes or ()] == [TRIANGLES[0], TRIANGLES[1]]
        material = scene.material_of(body)
        assert (material.density, material.friction, material.restitution) == (1.0, 0.5, 0.0)
