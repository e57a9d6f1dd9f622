"""Generators: deterministic per seed and per generator name, the distributions, shapes and layouts."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from rustycs.polygon import polygon_problem
from rustycs_cli.errors import UserError
from rustycs_cli.loading import load_scene, load_scene_text
from rustycs_cli.scene import Body, Capsule, Circle, Material, Polygon

HEAD = """\
seed: 5
bodies:
  - {name: floor, type: static, shape: {type: aabb, width: 20, height: 1}, position: [0, -0.5]}
generators:
"""
RAIN = """\
  - name: rain
    count: 20
    shape: {type: circle, radius: {uniform: [0.1, 0.3]}}
    region: {min: [-9, 5], max: [9, 40]}
    material: {choice: [rubber, plastic, stone, metal]}
"""
ROCKS = """\
  - name: rocks
    count: 10
    shape: {type: random_polygon, vertices: {uniform_int: [3, 8]}, radius: {uniform: [0.2, 0.5]}}
    region: {min: [-5, 1], max: [5, 3]}
    angle: {uniform: [-3.14, 3.14]}
"""
TWO_GENERATORS = HEAD + RAIN + ROCKS


def generated(text: str, *overrides: str, seed: int | None = None) -> list[Body]:
    """The bodies of a scene (generated ones included)."""
    return load_scene_text(text, "gen.yaml", overrides, seed).scene.bodies


def by_prefix(bodies: list[Body], prefix: str) -> list[Body]:
    return [b for b in bodies if b.name is not None and b.name.startswith(prefix)]


def test_generated_bodies_follow_the_listed_ones_with_their_names() -> None:
    bodies = generated(TWO_GENERATORS)
    assert [b.name for b in bodies] == ["floor"] + [f"rain-{i}" for i in range(20)] + [
        f"rocks-{i}" for i in range(10)
    ]


def test_generated_names_must_not_clash_with_listed_ones(tmp_path: Path) -> None:
    path = tmp_path / "clash.yaml"
    path.write_text(HEAD.replace("name: floor", "name: rain-2") + RAIN)
    with pytest.raises(UserError) as raised:
        load_scene(path)
    assert raised.value.messages == [
        f"{path}:5:11: generators.rain.name: generated body 'rain-2': duplicate body name 'rain-2' "
        "(also body 0)"
    ]


def test_same_seed_gives_identical_bodies_different_seed_differs() -> None:
    first, again = generated(TWO_GENERATORS), generated(TWO_GENERATORS)
    assert first == again
    other = generated(TWO_GENERATORS, seed=6)
    assert [b.position for b in other[1:]] != [b.position for b in first[1:]]
    assert generated(TWO_GENERATORS, "seed=6") == other


def test_changing_one_generator_leaves_the_other_unchanged() -> None:
    base = generated(TWO_GENERATORS)
    changed = generated(TWO_GENERATORS, "generators.rocks.count=3", "generators.rocks.angle={normal: [0, 1]}")
    assert by_prefix(changed, "rain") == by_prefix(base, "rain")
    assert len(by_prefix(changed, "rocks")) == 3
    # a generator's numbers come from its name, not its place in the list
    reordered = generated(HEAD + ROCKS + RAIN)
    assert by_prefix(reordered, "rain") == by_prefix(base, "rain")
    assert by_prefix(reordered, "rocks") == by_prefix(base, "rocks")


def test_changing_one_field_leaves_the_other_fields_draws_unchanged() -> None:
    base = by_prefix(generated(TWO_GENERATORS), "rain")
    changed = by_prefix(
        generated(TWO_GENERATORS, "generators.rain.shape.radius={normal: [0.2, 0.01]}"), "rain"
    )
    assert [b.position for b in changed] == [b.position for b in base]
    assert [b.material for b in changed] == [b.material for b in base]
    assert [b.shape for b in changed] != [b.shape for b in base]


def test_draws_are_pinned() -> None:
    """The same scene gives the same bodies on every machine and numpy version: pinned values."""
    body = generated(TWO_GENERATORS)[1]
    assert body.position == (7.34781510330432, 6.663616187153162)
    assert isinstance(body.shape, Circle) and body.shape.radius == 0.10820139787742658


def test_distributions() -> None:
    text = """\
generators:
  - name: g
    count: 4000
    shape: {type: circle, radius: {uniform: [0.1, 0.3]}}
    region: {min: [0, 0], max: [1000, 1000]}
    angle: {normal: [1.0, 0.5]}
    angular_velocity: {uniform_int: [-2, 2]}
    velocity: [{choice: [1, 2.5]}, 3]
    mass: {uniform: [1, 1]}
    material: {choice: [metal, {density: 2, restitution: 0, friction: 1}]}
"""
    bodies = generated(text)
    radii = [b.shape.radius for b in bodies]
    assert 0.1 <= min(radii) < 0.101 and 0.299 < max(radii) < 0.3
    angles = [b.angle for b in bodies]
    mean = sum(angles) / len(angles)
    std = math.sqrt(sum((a - mean) ** 2 for a in angles) / len(angles))
    assert abs(mean - 1.0) < 0.03 and abs(std - 0.5) < 0.03
    assert sorted({b.angular_velocity for b in bodies}) == [-2, -1, 0, 1, 2]
    assert {b.velocity for b in bodies} == {(1.0, 3.0), (2.5, 3.0)}
    assert {b.mass for b in bodies} == {1.0}
    assert {str(b.material) for b in bodies} == {"metal", str(Material(density=2, restitution=0, friction=1))}
    assert all(0 <= b.position[0] < 1000 and 0 <= b.position[1] < 1000 for b in bodies)


def test_random_polygons_are_convex_and_inscribed() -> None:
    bodies = by_prefix(generated(TWO_GENERATORS, "generators.rocks.count=200"), "rocks")
    counts = set()
    for body in bodies:
        assert isinstance(body.shape, Polygon)
        vertices = body.shape.vertices
        counts.add(len(vertices))
        assert polygon_problem(vertices) is None
        radii = [math.hypot(x, y) for x, y in vertices]
        assert max(radii) - min(radii) < 1e-12 and 0.2 <= radii[0] <= 0.5
    assert counts == set(range(3, 9))
    many = by_prefix(generated(TWO_GENERATORS, "generators.rocks.shape.vertices=256"), "rocks")
    assert {len(b.shape.vertices) for b in many} == {256}  # split into convex pieces by the engine
    assert all(polygon_problem(b.shape.vertices) is None for b in many)


def test_shape_choice_and_body_type_choice() -> None:
    text = """\
generators:
  - count: 300
    type: {choice: [dynamic, static]}
    shape: {choice: [{type: circle, radius: 0.1}, {type: obb, width: 1, height: 2}, {type: polygon,
            vertices: [[0, 0], [1, 0], [0, 1]]}]}
    region: {min: [0, 0], max: [10, 10]}
"""
    bodies = generated(text)
    assert {b.shape.type for b in bodies} == {"circle", "obb", "polygon"}
    assert {b.type for b in bodies} == {"dynamic", "static"}
    assert bodies[0].name == "generator-0-0"


def test_layouts() -> None:
    text = """\
generators:
  - name: pyramid
    shape: {type: obb, width: 1, height: 1}
    layout: {pyramid: {base: 3, origin: [0, 0.5], spacing: [1, 1]}}
  - name: stack
    count: 3
    shape: {type: aabb, width: 1, height: 0.5}
    layout: {stack: {origin: [5, 0.25], spacing: 0.5}}
  - name: grid
    count: 5
    shape: {type: circle, radius: 0.1}
    layout: {grid: {origin: [-10, 1], columns: 2, spacing: [0.5, 0.25]}}
  - name: jittered
    count: 100
    shape: {type: circle, radius: 0.1}
    layout: {grid: {origin: [0, 0], columns: 10, spacing: [1, 1], jitter: [0.1, 0.2]}}
"""
    bodies = generated(text)
    assert [b.position for b in by_prefix(bodies, "pyramid")] == [
        (-1, 0.5),
        (0, 0.5),
        (1, 0.5),
        (-0.5, 1.5),
        (0.5, 1.5),
        (0, 2.5),
    ]
    assert [b.position for b in by_prefix(bodies, "stack")] == [(5, 0.25), (5, 0.75), (5, 1.25)]
    assert [b.position for b in by_prefix(bodies, "grid")] == [
        (-10, 1),
        (-9.5, 1),
        (-10, 1.25),
        (-9.5, 1.25),
        (-10, 1.5),
    ]
    for k, body in enumerate(by_prefix(bodies, "jittered")):
        row, column = divmod(k, 10)
        assert abs(body.position[0] - column) <= 0.1 and abs(body.position[1] - row) <= 0.2
    partial = generated(text.replace("layout: {pyramid", "count: 4\n    layout: {pyramid"))
    assert len(by_prefix(partial, "pyramid")) == 4


@pytest.mark.parametrize(
    ("generator", "expected"),
    [
        (
            "{name: g, count: 2, shape: {type: circle, radius: 1}}",
            "3:5: generators.g: a generator needs either a region or a layout",
        ),
        (
            "{name: g, count: 2, shape: {type: circle, radius: 1}, region: {min: [0, 0], max: [1, 1]},\n"
            "     layout: {stack: {origin: [0, 0], spacing: 1}}}",
            "3:5: generators.g: a generator needs either",
        ),
        (
            "{name: g, count: 7, shape: {type: circle, radius: 1}, "
            "layout: {pyramid: {base: 2, origin: [0, 0],\n"
            "     spacing: [1, 1]}}}",
            "3:22: generators.g.count: a pyramid of base 2 holds 3 bodies",
        ),
        (
            "{name: g, shape: {type: circle, radius: 1}, region: {min: [0, 0], max: [1, 1]}}",
            "3:5: generators.g: missing key 'count'",
        ),
        (
            "{name: g, count: 1, shape: {type: random_polygon, vertices: {uniform: [3, 8]}, radius: 1},\n"
            "     region: {min: [0, 0], max: [1, 1]}}",
            "3:65: generators.g.shape.vertices: the vertex count must be",
        ),
        (
            "{name: g, count: 1, shape: {type: circle, radius: {unifrom: [1, 2]}}, "
            "region: {min: [0, 0], max: [1, 1]}}",
            "3:56: generators.g.shape.radius.unifrom: unknown key 'unifrom' (did you mean 'uniform'?)",
        ),
        (
            "{name: g, count: 1, shape: {type: circle, radius: {uniform: [2, 1]}}, "
            "region: {min: [0, 0], max: [1, 1]}}",
            "3:65: generators.g.shape.radius.uniform: lo must not exceed hi",
        ),
        (
            "{name: g, count: 1, shape: {type: circle, radius: 1}, region: {min: [0, 0], max: [1, 1]},\n"
            "     material: {choice: [rubber, stne]}}",
            "4:34: generators.g.material.choice.1: unknown material 'stne' (did you mean 'stone'?)",
        ),
        (
            "{name: g, count: 50, shape: {type: circle, radius: {normal: [0.1, 0.2]}}, "
            "region: {min: [0, 0],\n"
            "     max: [1, 1]}}",
            "3:56: generators.g.shape.radius: generated body 'g-",
        ),
    ],
)
def test_generator_problems_are_reported_at_the_generator(
    tmp_path: Path, generator: str, expected: str
) -> None:
    path = tmp_path / "gen.yaml"
    path.write_text(f"seed: 0\ngenerators:\n  - {generator}\n")
    with pytest.raises(UserError) as raised:
        load_scene(path)
    assert len(raised.value.messages) == 1
    assert raised.value.messages[0].startswith(f"{path}:{expected}")


def test_existing_generators_make_the_same_bodies_as_before_bodies_made_of_shapes() -> None:
    """The resolved text (every generated number written out) of the two generators, pinned from before
    generators took capsules, `shapes` and the new body keys."""
    loaded = load_scene_text(TWO_GENERATORS, "x")
    assert loaded.sha256 == "58f6e25866baf83d68a928a999d7220d537128107c0fef886d673161a374000d"


def test_new_fields_leave_the_other_fields_draws_unchanged() -> None:
    base = by_prefix(generated(TWO_GENERATORS), "rain")
    damped = by_prefix(
        generated(
            TWO_GENERATORS,
            "generators.rain.linear_damping={uniform: [0, 1]}",
            "generators.rain.gravity_scale={normal: [1, 0.1]}",
            "generators.rain.shape.offset=[{uniform: [0, 0.1]}, 0]",
        ),
        "rain",
    )
    assert [(b.position, b.material) for b in damped] == [(b.position, b.material) for b in base]
    assert [b.shape.radius for b in damped] == [b.shape.radius for b in base]
    assert len({b.linear_damping for b in damped}) == 20 and all(0 <= b.linear_damping < 1 for b in damped)
    assert all(0 <= b.shape.offset[0] < 0.1 for b in damped)


def test_capsules_and_the_new_body_keys() -> None:
    text = """\
generators:
  - name: pills
    count: 200
    shape: {type: capsule, length: {uniform: [0.5, 1.5]}, radius: {choice: [0.1, 0.2]}}
    region: {min: [0, 0], max: [10, 10]}
    linear_damping: {uniform: [0, 0.5]}
    angular_damping: 0.25
    gravity_scale: {choice: [0.5, 2]}
    fixed_rotation: true
    bullet: true
    collision_category: 4
    collision_mask: 3
"""
    bodies = generated(text)
    assert all(isinstance(b.shape, Capsule) for b in bodies)
    lengths = [b.shape.length for b in bodies]
    assert 0.5 <= min(lengths) < 0.52 and 1.48 < max(lengths) < 1.5
    assert {b.shape.radius for b in bodies} == {0.1, 0.2}
    assert 0 <= min(b.linear_damping for b in bodies) < max(b.linear_damping for b in bodies) < 0.5
    assert {b.angular_damping for b in bodies} == {0.25} and {b.gravity_scale for b in bodies} == {0.5, 2}
    assert all(b.fixed_rotation and b.bullet for b in bodies)
    assert {(b.collision_category, b.collision_mask) for b in bodies} == {(4, 3)}


COMPOUND = """\
seed: 3
generators:
  - name: cups
    count: 50
    shapes:
      - {type: obb, width: 1, height: 0.1, offset: [0, -0.45]}
      - {type: obb, width: 0.1, height: {uniform: [0.5, 1]}, offset: [{uniform: [-0.5, -0.4]}, 0],
         angle: {normal: [0, 0.1]}, material: {choice: [rubber, stone]}}
      - {choice: [{type: circle, radius: 0.2, sensor: true}, {type: capsule, length: 0.3, radius: 0.1}]}
    region: {min: [-10, 0], max: [10, 10]}
    material: metal
"""


def test_compound_generators_draw_each_shape_and_write_shapes() -> None:
    loaded = load_scene_text(COMPOUND, "cups.yaml")
    bodies = loaded.scene.bodies
    assert [b.name for b in bodies] == [f"cups-{i}" for i in range(50)]
    assert all(b.shape is None and len(b.shapes or ()) == 3 and b.material == "metal" for b in bodies)
    floors, walls, extras = zip(*(b.shapes or () for b in bodies), strict=True)
    assert {(s.type, s.width, s.height, s.offset, s.angle, s.material) for s in floors} == {
        ("obb", 1, 0.1, (0, -0.45), 0, None)
    }
    assert all(-0.5 <= s.offset[0] < -0.4 and s.offset[1] == 0 and 0.5 <= s.height < 1 for s in walls)
    assert len({s.angle for s in walls}) == 50 and {s.material for s in walls} == {"rubber", "stone"}
    assert {(s.type, s.sensor) for s in extras} == {("circle", True), ("capsule", False)}
    assert "shapes: [{type: obb, offset: [0.0, -0.45], width: 1.0, height: 0.1}, " in loaded.text
    assert generated(COMPOUND) == bodies  # deterministic
    # a change of one shape's distribution leaves the other shapes' draws alone
    changed = generated(COMPOUND, "generators.cups.shapes.1.angle={uniform: [0, 1]}")
    assert [(b.shapes or [])[1].offset for b in changed] == [s.offset for s in walls]
    assert [(b.shapes or [])[2] for b in changed] == list(extras)


@pytest.mark.parametrize(
    ("generator", "expected"),
    [
        (
            "{name: g, count: 1, region: {min: [0, 0], max: [1, 1]}}",
            "3:5: generators.g: missing key 'shape' (or 'shapes' for several)",
        ),
        (
            "{name: g, count: 1, shape: {type: circle, radius: 1}, shapes: [{type: circle, radius: 1}],\n"
            "     region: {min: [0, 0], max: [1, 1]}}",
            "3:59: generators.g.shapes: give either `shape` or `shapes`, not both",
        ),
        (
            "{name: g, count: 1, shapes: [{type: circle, radius: 1, material: stne}],\n"
            "     region: {min: [0, 0], max: [1, 1]}}",
            "3:70: generators.g.shapes.0.material: unknown material 'stne' (did you mean 'stone'?)",
        ),
        (
            "{name: g, count: 1, shapes: [{choice: [{type: circle, radius: 1, material: {choice: [rubber,\n"
            "     metl]}}]}], region: {min: [0, 0], max: [1, 1]}}",
            "4:6: generators.g.shapes.0.choice.0.material.choice.1: unknown material 'metl'",
        ),
        (
            "{name: g, count: 1, shapes: [{type: aabb, width: 1, height: 1, angle: {uniform: [0, 1]}}],\n"
            "     region: {min: [0, 0], max: [1, 1]}}",
            "3:75: generators.g.shapes.0.angle: an aabb never rotates, so its angle must be 0",
        ),
        (
            "{name: g, count: 3, shapes: [{type: capsule, length: {uniform: [-1, -0.5]}, radius: 1}],\n"
            "     region: {min: [0, 0], max: [1, 1]}}",
            "3:58: generators.g.shapes.0.length: generated body 'g-0': Input should be greater than or equal "
            "to 0 (got -0.78",
        ),
        (
            "{name: g, count: 3, shape: {type: chain, points: [[0, 0], [1, 0]]}, region: {min: [0, 0],\n"
            "     max: [1, 1]}}",
            "3:25: generators.g.shape: generated body 'g-0': a dynamic body needs at least one shape with "
            "area",
        ),
    ],
)
def test_shape_problems_of_generators(tmp_path: Path, generator: str, expected: str) -> None:
    path = tmp_path / "gen.yaml"
    path.write_text(f"seed: 0\ngenerators:\n  - {generator}\n")
    with pytest.raises(UserError) as raised:
        load_scene(path)
    assert len(raised.value.messages) == 1
    assert raised.value.messages[0].startswith(f"{path}:{expected}")
