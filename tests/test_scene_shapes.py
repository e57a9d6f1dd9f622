"""Bodies made of shapes: `shape` or `shapes`, the shape kinds and keys, the new body keys, and every
problem with them reported at its FILE:LINE:COLUMN by `rustycs validate` (exit 2)."""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np
import pytest
from pydantic import ValidationError

import rustycs
from rustycs import defaults
from rustycs_cli.build import build_world
from rustycs_cli.errors import UserError
from rustycs_cli.loading import load_scene_text
from rustycs_cli.scene import Capsule, Chain, Circle, Material, Obb, Polygon, Scene, Segment

CUP = """\
bodies:
  - name: cup
    position: [0, 2]
    shapes:
      - {type: obb, width: 2.0, height: 0.2, offset: [0, -0.9]}
      - {type: obb, width: 0.2, height: 2.0, offset: [-0.9, 0], angle: 0.1}
      - {type: obb, width: 0.2, height: 2.0, offset: [0.9, 0], material: rubber}
      - {type: circle, radius: 0.5, sensor: true}
    linear_damping: 0.5
    angular_damping: 0.25
    gravity_scale: -2
    fixed_rotation: true
    bullet: true
    collision_category: 6
    collision_mask: 3
  - {shape: {type: capsule, length: 1, radius: 0.2, offset: [1, 0], material: {density: 3, restitution: 0,
     friction: 1}}, position: [0, 0]}
  - {type: static, shapes: [{type: chain, points: [[0, 0], [1, 0], [2, 1]], loop: true}], position: [0, 0]}
  - {type: kinematic, shape: {type: segment, points: [[0, 0], [1, 0]]}, position: [0, 0]}
  - {shapes: [{type: circle, radius: 1}, {type: circle, radius: 1, offset: [2, 0]}], position: [5, 0]}
"""


def test_bodies_of_one_or_several_shapes_have_one_list_of_shapes() -> None:
    cup, capsule, chain, segment, pair = load_scene_text(CUP, "cup.yaml").scene.bodies
    assert [b.name for b in (cup, capsule, chain, segment, pair)] == [
        "cup",
        "capsule-1",
        "chain-2",
        "segment-3",
        "compound-4",
    ]
    assert cup.shape is None and [s.type for s in cup.shapes or ()] == ["obb", "obb", "obb", "circle"]
    walls = cup.shapes or []
    assert [s.offset for s in walls] == [(0, -0.9), (-0.9, 0), (0.9, 0), (0, 0)]
    assert [s.angle for s in walls] == [0, 0.1, 0, 0] and [s.sensor for s in walls] == [False] * 3 + [True]
    assert [s.material for s in walls] == [None, None, "rubber", None]
    assert isinstance(walls[0], Obb) and isinstance(walls[3], Circle) and not walls[3].adds_mass
    assert (cup.linear_damping, cup.angular_damping, cup.gravity_scale) == (0.5, 0.25, -2)
    assert cup.fixed_rotation and cup.bullet and (cup.collision_category, cup.collision_mask) == (6, 3)
    assert isinstance(capsule.shape, Capsule) and capsule.shapes == [capsule.shape]
    assert (capsule.shape.length, capsule.shape.radius, capsule.shape.offset) == (1, 0.2, (1, 0))
    assert capsule.shape.material == Material(density=3, restitution=0, friction=1)
    assert isinstance((chain.shapes or [])[0], Chain) and (chain.shapes or [])[0].loop
    assert isinstance(segment.shape, Segment) and not segment.shape.adds_mass
    # the keys left out are the engine's defaults
    assert (
        (capsule.linear_damping, capsule.angular_damping, capsule.gravity_scale)
        == (0, 0, 1)
        == (
            defaults.LINEAR_DAMPING,
            defaults.ANGULAR_DAMPING,
            defaults.GRAVITY_SCALE,
        )
    )
    assert (
        (capsule.collision_category, capsule.collision_mask)
        == (1, -1)
        == (
            defaults.COLLISION_CATEGORY,
            defaults.COLLISION_MASK,
        )
    )
    assert not capsule.fixed_rotation and not capsule.bullet


def test_resolved_text_writes_each_body_in_its_own_form_and_round_trips() -> None:
    first = load_scene_text(CUP, "cup.yaml")
    bodies = first.text.split("bodies:\n")[1].split("output:")[0].splitlines()
    assert [line.split(", ")[1].split(":")[0] for line in bodies] == [
        "shapes",
        "shape",
        "type",
        "type",
        "shapes",
    ]
    assert "shape: {type: capsule, offset: [1.0, 0.0], material: {density: 3.0" in bodies[1]
    assert "shapes: [{type: circle, sensor: true, radius: 0.5}]" not in bodies[0]  # one list, not two
    assert bodies[0].count("{type: ") == 4 and "shape: " not in bodies[0]
    again = load_scene_text(first.text, "stored")
    assert again.scene == first.scene and again.text == first.text and again.sha256 == first.sha256


def test_overrides_reach_shapes_and_compound_bodies_by_their_default_names() -> None:
    scene = load_scene_text(
        CUP,
        "cup.yaml",
        [
            "bodies.cup.shapes.1.angle=0.3",
            "bodies.compound-4.shapes.1.offset=[3, 0]",
            "bodies.1.shape.offset=[2, 0]",
        ],
    ).scene
    assert (scene.bodies[0].shapes or [])[1].angle == 0.3
    assert (scene.bodies[4].shapes or [])[1].offset == (3, 0)
    assert scene.bodies[1].shape is not None and scene.bodies[1].shape.offset == (2, 0)


def test_static_and_kinematic_bodies_need_no_area() -> None:
    text = (
        "bodies:\n  - {type: static, shape: {type: chain, points: [[0, 0], [1, 0]]}, position: [0, 0]}\n"
        "  - {type: kinematic, shape: {type: circle, radius: 1, sensor: true}, position: [0, 0]}\n"
    )
    assert len(load_scene_text(text, "s.yaml").scene.bodies) == 2


def body(extra: str) -> str:
    """A scene whose body `b` starts on line 2 and has these keys (one per line, indented 4) after its
    position."""
    return f"bodies:\n  - name: b\n    position: [0, 0]\n{extra}"


CIRCLE = "    shape: {type: circle, radius: 1}\n"
RING_257 = "[" + ", ".join(f"[{math.cos(k / 41):.6f}, {math.sin(k / 41):.6f}]" for k in range(257)) + "]"


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        (
            body(CIRCLE + "    shapes:\n      - {type: circle, radius: 2}\n"),
            "5:5: bodies.b.shapes: give either `shape` or `shapes`, not both",
        ),
        (
            body("    shapes: [{type: circle, radius: 2}]\n" + CIRCLE),
            "5:5: bodies.b.shape: give either `shape` or `shapes`, not both",
        ),
        (body(""), "2:5: bodies.b: missing key 'shape' (or 'shapes' for several)"),
        (  # the misspelt key is the message: no second one about the missing shape
            body("    shaps: [{type: circle, radius: 2}]\n"),
            "4:5: bodies.b.shaps: unknown key 'shaps' (did you mean 'shapes'?)",
        ),
        (
            body("    shape: {type: circle, radius: 1, ofset: [0, 1]}\n"),
            "4:38: bodies.b.shape.ofset: unknown key 'ofset' (did you mean 'offset'?)",
        ),
        (
            body("    shapes:\n      - {type: circle, radius: 1}\n      - {type: capsul, length: 1}\n"),
            "6:16: bodies.b.shapes.1.type: unknown shape type 'capsul' (did you mean 'capsule'?); expected "
            "one of: circle, aabb, obb, polygon, capsule, segment, chain",
        ),
        (
            body(
                "    shapes:\n      - {type: circle, radius: 1, sensor: true}\n"
                "      - {type: chain, points: [[0, 0], [1, 0]]}\n"
            ),
            "4:5: bodies.b.shapes: a dynamic body needs at least one shape with area (not a sensor, "
            "segment or chain)",
        ),
        (
            body("    shape: {type: segment, points: [[0, 0], [1, 0]]}\n"),
            "4:5: bodies.b.shape: a dynamic body needs at least one shape with area",
        ),
        (
            body("    type: static\n    shape: {type: chain, points: [[0, 0]]}\n"),
            "5:34: bodies.b.shape.points: a chain has 2 to 4096 points, this one has 1",
        ),
        (
            body("    type: static\n    shape: {type: chain, points: [[0, 0], [1, 0]], loop: true}\n"),
            "5:58: bodies.b.shape.loop: a loop needs at least 3 points, this one has 2",
        ),
        (
            body("    type: static\n    shape: {type: chain, points: [[0, 0], [1, 0], [1, 0], [2, 1]]}\n"),
            "5:51: bodies.b.shape.points.2: point 2 repeats point 1: consecutive points must differ",
        ),
        (
            body(
                "    type: static\n"
                "    shape: {type: chain, points: [[0, 0], [1, 0], [1, 1], [0, 0]],\n      loop: yes}\n"
            ),
            "5:59: bodies.b.shape.points.3: the last point repeats the first: a loop joins its last point to "
            "its first by itself",
        ),
        (
            body("    type: static\n    shape: {type: segment, points: [[0, 0]]}\n"),
            "5:36: bodies.b.shape.points: a segment has exactly 2 points, this one has 1",
        ),
        (
            body("    type: static\n    shape: {type: segment, points: [[0, 0], [1, 0], [2, 0]]}\n"),
            "5:36: bodies.b.shape.points: a segment has exactly 2 points, this one has 3",
        ),
        (
            body("    type: static\n    shape: {type: segment, points: [[1, 0], [1, 0]]}\n"),
            "5:45: bodies.b.shape.points.1: the segment's two points are the same: it has no length",
        ),
        (
            body("    shape: {type: capsule, length: -0.5, radius: 0.2}\n"),
            "4:36: bodies.b.shape.length: Input should be greater than or equal to 0 (got -0.5)",
        ),
        (
            body("    shape: {type: capsule, length: 1, radius: 0}\n"),
            "4:47: bodies.b.shape.radius: Input should be greater than 0 (got 0)",
        ),
        (
            body(CIRCLE + "    linear_damping: -0.1\n"),
            "5:21: bodies.b.linear_damping: Input should be greater than or equal to 0 (got -0.1)",
        ),
        (
            body(CIRCLE + "    angular_damping: -1\n"),
            "5:22: bodies.b.angular_damping: Input should be greater than or equal to 0 (got -1)",
        ),
        (
            body(CIRCLE + "    collision_mask: -2\n"),
            "5:21: bodies.b.collision_mask: Input should be greater than or equal to -1 (got -2)",
        ),
        (
            body(CIRCLE + "    collision_category: -1\n"),
            "5:25: bodies.b.collision_category: Input should be greater than or equal to 0 (got -1)",
        ),
        (
            body(
                "    shapes:\n      - {type: circle, radius: 1}\n"
                "      - {type: aabb, width: 1, height: 1, angle: 0}\n"
                "      - {type: aabb, width: 1, height: 1, angle: 0.2}\n"
            ),
            "7:50: bodies.b.shapes.2.angle: an aabb never rotates, so its angle must be 0: use shape type "
            "obb for a turned box",
        ),
        (
            body(
                "    shapes: [{type: circle, radius: 1}, {type: aabb, width: 1, height: 1}]\n    angle: 0.5\n"
            ),
            "5:12: bodies.b.angle: an aabb never rotates, so its angle must be 0: use shape type obb for a "
            "turned box",
        ),
        (
            body("    shapes: [{type: circle, radius: 1}, {type: circle, radius: 1, material: rubbr}]\n"),
            "4:77: bodies.b.shapes.1.material: unknown material 'rubbr' (did you mean 'rubber'?); known: "
            "default, metal, plastic, rubber, stone",
        ),
        (  # the engine's message, at the first vertex of the later of the two crossing edges
            body(
                "    shapes:\n      - {type: circle, radius: 1}\n"
                "      - {type: polygon, vertices: [[0, 0], [4, 0], [4, 1], [1, 3], [3, 3], [0, 1]]}\n"
            ),
            "6:68: bodies.b.shapes.1.vertices.4: edges 2-3 and 4-5 cross: the polygon intersects itself",
        ),
        (
            body(f"    shapes: [{{type: polygon, vertices: {RING_257}}}]\n"),
            "4:40: bodies.b.shapes.0.vertices: a polygon has 3 to 256 vertices, this one has 257",
        ),
        (
            body("    shapes: []\n"),
            "4:13: bodies.b.shapes: List should have at least 1 item after validation",
        ),
    ],
)
def test_shape_problems_are_reported_where_they_are(
    cli,  # noqa: ANN001 - the conftest fixture
    tmp_path: Path,
    text: str,
    expected: str,
) -> None:
    path = tmp_path / "scene.yaml"
    path.write_text(text)
    result = cli("validate", path)
    assert result.exit_code == 2 and result.stdout == ""
    assert result.stderr.splitlines() == [result.stderr.strip()]  # one message
    assert result.stderr.startswith(f"{path}:{expected}")


def test_concave_polygons_of_up_to_256_vertices_are_valid() -> None:
    l_shape = "[[0, 0], [0.6, 0], [0.6, 0.15], [0.15, 0.15], [0.15, 0.6], [0, 0.6]]"
    ring = RING_257.replace("[1.000000, 0.000000], ", "", 1)
    scene = load_scene_text(
        body(f"    shapes: [{{type: polygon, vertices: {l_shape}}}, {{type: polygon, vertices: {ring}}}]\n"),
        "p.yaml",
    ).scene
    shapes = scene.bodies[0].shapes or []
    assert [len(s.vertices) for s in shapes if isinstance(s, Polygon)] == [6, 256]


@pytest.mark.parametrize(
    ("shape", "message"),
    [
        (
            {"type": "polygon", "vertices": [[k, 0.0] for k in range(10**6)]},
            "a polygon has 3 to 256 vertices",
        ),
        ({"type": "chain", "points": [[k, 0.0] for k in range(10**6)]}, "a chain has 2 to 4096 points"),
    ],
)
def test_a_million_vertices_are_refused_at_once(shape: dict, message: str) -> None:
    data = {"bodies": [{"type": "static", "shapes": [shape], "position": [0, 0]}]}
    started = time.perf_counter()
    with pytest.raises(ValidationError) as raised:
        Scene.model_validate(data)
    assert time.perf_counter() - started < 0.1
    assert [e["msg"] for e in raised.value.errors()] == [f"{message}, this one has 1000000"]


def test_both_keys_and_the_problems_inside_them_are_reported_together(tmp_path: Path) -> None:
    text = body("    shape: {type: circle, radius: -1}\n    shapes: [{type: obb, width: 1}]\n    mass: 0\n")
    with pytest.raises(UserError) as raised:
        load_scene_text(text, "s.yaml")
    assert raised.value.messages == [
        "s.yaml:4:35: bodies.b.shape.radius: Input should be greater than 0 (got -1)",
        "s.yaml:5:5: bodies.b.shapes: give either `shape` or `shapes`, not both",
        "s.yaml:5:14: bodies.b.shapes.0: missing key 'height'",
        "s.yaml:6:11: bodies.b.mass: Input should be greater than 0 (got 0)",
    ]


def test_bodies_made_of_shapes_are_built_as_the_engine_api_builds_them() -> None:
    """build_world passes every shape (kind, geometry, offset, angle, material resolved like a body's,
    sensor) and every body key to the engine: its tables equal those of a World built by hand."""
    built = build_world(load_scene_text(CUP, "cup.yaml").scene)
    rubber = rustycs.MATERIALS["rubber"]
    by_hand = rustycs.World()
    by_hand.add_body(
        [rustycs.Box(2.0, 0.2, offset=(0, -0.9)), rustycs.Box(0.2, 2.0, offset=(-0.9, 0), angle=0.1),
         rustycs.Box(0.2, 2.0, offset=(0.9, 0), material=rubber), rustycs.Circle(0.5, sensor=True)],
        position=(0, 2), linear_damping=0.5, angular_damping=0.25, gravity_scale=-2,
        fixed_rotation=True, bullet=True, collision_category=6, collision_mask=3)
    by_hand.add_body(rustycs.Capsule(1, 0.2, offset=(1, 0), material=rustycs.Material(3, 0, 1)))
    by_hand.add_body(rustycs.Chain([(0, 0), (1, 0), (2, 1)], loop=True), body_type="static")
    by_hand.add_body(rustycs.Segment([(0, 0), (1, 0)]), body_type="kinematic")
    by_hand.add_body([rustycs.Circle(1), rustycs.Circle(1, offset=(2, 0))], position=(5, 0))
    assert built.shapes == by_hand.shapes and built.shape_count == 9
    for table in ("_bodies", "_shapes"):
        ours, theirs = getattr(built, table).view(), getattr(by_hand, table).view()
        for name in ours._fields:
            np.testing.assert_array_equal(getattr(ours, name), getattr(theirs, name), err_msg=name)
    assert list(built.shape_kinds) == ["compound", "capsule", "chain", "segment", "compound"]
    # the cup's sensor adds no mass: boxes of 0.4 m^2, two of the default density 0.1, one of rubber's 0.9
    assert built.masses[0] == pytest.approx(0.4 * (0.1 + 0.1 + 0.9)) and math.isinf(built.inertias[0])
    assert built.masses[1] == pytest.approx(3 * (0.2 * 2 * 1 + math.pi * 0.2**2))  # the inline density 3
    np.testing.assert_allclose(built.local_centers[1], [1, 0])  # the capsule's offset
