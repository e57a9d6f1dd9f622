"""Scene loading: every kind of bad input is reported at its FILE:LINE:COLUMN, all problems at once."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import pytest

from rustycs_cli.errors import UserError
from rustycs_cli.loading import load_scene, load_scene_text
from rustycs_cli.scene import Aabb, Circle, Material, Obb, Polygon

GOOD = """\
name: good
world: {tick_rate: 120, ticks: 10}
bodies:
  - {name: floor, type: static, shape: {type: aabb, width: 10, height: 1}, position: [0, -0.5]}
  - name: ball
    shape: {type: circle, radius: 0.5}
    position: [0, 2]
    material: rubber
"""


def problems(tmp_path: Path, text: str, overrides: tuple[str, ...] = ()) -> tuple[Path, list[str]]:
    """The scene file written from `text` and the messages loading it raises."""
    path = tmp_path / "scene.yaml"
    path.write_text(text)
    with pytest.raises(UserError) as raised:
        load_scene(path, overrides)
    assert raised.value.exit_code == 2
    return path, raised.value.messages


def one_body(shape: str, extra: str = "") -> str:
    """A scene whose third line is the body `b` with this shape (flow mapping) and extra keys."""
    return f"bodies:\n  - name: b\n    shape: {shape}\n    position: [0, 0]\n{extra}"


def test_good_scene_loads_with_defaults_filled_in(tmp_path: Path) -> None:
    path = tmp_path / "good.yaml"
    path.write_text(GOOD)
    loaded = load_scene(path)
    scene = loaded.scene
    assert [b.name for b in scene.bodies] == ["floor", "ball"]
    assert scene.world.tick_rate == 120.0 and scene.world.precision == 10 and scene.output.every == 1
    assert isinstance(scene.bodies[0].shape, Aabb) and isinstance(scene.bodies[1].shape, Circle)
    assert scene.material_of(scene.bodies[1]) == Material(density=0.9, restitution=0.6, friction=0.8)
    assert loaded.source == str(path) and loaded.overrides == ()


def test_exponent_numbers_load_as_floats(tmp_path: Path) -> None:
    text = GOOD.replace("radius: 0.5", "radius: 5e-1").replace("tick_rate: 120", "tick_rate: 1.2E2")
    scene = load_scene_text(text, "x.yaml").scene
    assert scene.bodies[1].shape.radius == 0.5 and scene.world.tick_rate == 120.0
    # -2.5e-3 is read as a number (PyYAML alone reads a string): so it is no valid description
    path, messages = problems(tmp_path, GOOD + "description: -2.5e-3\n")
    assert messages == [f"{path}:9:14: description: Input should be a valid string (got -0.0025)"]


def test_default_names_and_scene_name_from_the_file_stem(tmp_path: Path) -> None:
    path = tmp_path / "my_scene.yaml"
    path.write_text(
        "bodies:\n  - {shape: {type: obb, width: 1, height: 2}, position: [0, 0]}\n"
        "  - {shape: {type: circle, radius: 1}, position: [0, 0]}\n"
    )
    scene = load_scene(path).scene
    assert scene.name == "my_scene"
    assert [b.name for b in scene.bodies] == ["obb-0", "circle-1"]
    assert isinstance(scene.bodies[0].shape, Obb)


def test_yaml_syntax_error(tmp_path: Path) -> None:
    path, messages = problems(tmp_path, "bodies:\n  - {name: a, shape: {type: circle, radius: 1}\n  b: 2\n")
    assert messages == [f"{path}:3:3: YAML syntax error: expected ',' or '}}', but got '<scalar>'"]


def test_unknown_key_with_did_you_mean_at_the_key(tmp_path: Path) -> None:
    path, messages = problems(
        tmp_path, "bodies:\n  - name: b\n    shape: {type: circle, radius: 1}\n    positon: [0, 0]\n"
    )
    # the misspelt key only: no second message about the missing 'position'
    assert messages == [f"{path}:4:5: bodies.b.positon: unknown key 'positon' (did you mean 'position'?)"]


def test_unknown_top_level_key_and_missing_key(tmp_path: Path) -> None:
    path, messages = problems(tmp_path, "wrld: {}\nbodies:\n  - {name: b, position: [0, 0]}\n")
    assert messages == [
        f"{path}:1:1: wrld: unknown key 'wrld' (did you mean 'world'?)",
        f"{path}:3:5: bodies.b: missing key 'shape' (or 'shapes' for several)",
    ]


def test_wrong_type(tmp_path: Path) -> None:
    path, messages = problems(tmp_path, one_body("{type: circle, radius: big}"))
    assert messages == [
        f"{path}:3:35: bodies.b.shape.radius: Input should be a valid number (got 'big')"
    ]


@pytest.mark.parametrize(
    ("text", "where", "path_in_scene"),
    [
        (one_body("{type: circle, radius: 0}"), "3:35", "bodies.b.shape.radius"),
        (one_body("{type: obb, width: -1, height: 1}"), "3:31", "bodies.b.shape.width"),
        (one_body("{type: aabb, width: 1, height: 0}"), "3:43", "bodies.b.shape.height"),
        (one_body("{type: circle, radius: 1}", "    mass: 0\n"), "5:11", "bodies.b.mass"),
        (
            one_body(
                "{type: circle, radius: 1}", "    material: {density: 0, restitution: 0, friction: 0}\n"
            ),
            "5:25",
            "bodies.b.material.density",
        ),
        (
            "materials:\n  ice: {density: -0.9, restitution: 0.1, friction: 0}\n",
            "2:18",
            "materials.ice.density",
        ),
        ("world:\n  tick_rate: 0\n", "2:14", "world.tick_rate"),
    ],
)
def test_non_positive_sizes_densities_masses_tick_rates(
    tmp_path: Path, text: str, where: str, path_in_scene: str
) -> None:
    path, messages = problems(tmp_path, text)
    assert len(messages) == 1
    assert messages[0].startswith(f"{path}:{where}: {path_in_scene}: Input should be greater than 0")


@pytest.mark.parametrize(
    ("vertices", "column", "message"),
    [
        (
            "[[0, 0], [1, 1], [1, 0], [0, 1]]",
            55,
            "vertices.2: edges 0-1 and 2-3 cross: the polygon intersects itself",
        ),
        (  # reported at the first vertex of the later of the crossing edges
            "[[0, 0], [4, 0], [4, 1], [1, 3], [3, 3], [0, 1]]",
            71,
            "vertices.4: edges 2-3 and 4-5 cross: the polygon intersects itself",
        ),
        (
            "[[0, 0], [1, 0], [2, 0], [1, 1]]",
            47,
            "vertices.1: vertex 1 lies on the line through its neighbours: the polygon is degenerate",
        ),
        (
            "[[0, 0], [1, 0], [1, 0], [0, 1]]",
            55,
            "vertices.2: vertex 2 repeats vertex 1: the polygon is degenerate",
        ),
        (
            "[[0, 0], [1e-6, 0], [0, 1e-6]]",
            38,
            "vertices: the polygon's area 5e-13 m^2 is too small: it is degenerate",
        ),
        (
            "["
            + ", ".join(f"[{math.cos(k / 40.8):.6f}, {math.sin(k / 40.8):.6f}]" for k in range(257))
            + "]",
            38,
            "vertices: a polygon has 3 to 256 vertices, this one has 257",
        ),
    ],
)
def test_bad_polygons(tmp_path: Path, vertices: str, column: int, message: str) -> None:
    path, messages = problems(tmp_path, one_body(f"{{type: polygon, vertices: {vertices}}}"))
    assert messages == [f"{path}:3:{column}: bodies.b.shape.{message}"]


def test_good_polygons_convex_or_not_in_either_winding() -> None:
    circle = [[math.cos(k / 40.7), math.sin(k / 40.7)] for k in range(256)]
    for vertices in (
        [[0, 0], [1, 0], [0, 1]],
        [[0, 0], [0, 1], [1, 0]],
        [[0, 0], [2, 0], [2, 1], [1, 2], [0, 1]],
        [[0, 0], [2, 0], [1, 0.5], [1, 2]],  # concave
        [[0, 0], [0.6, 0], [0.6, 0.15], [0.15, 0.15], [0.15, 0.6], [0, 0.6]][::-1],  # an L, clockwise
        circle,  # 256 vertices
    ):
        scene = load_scene_text(one_body(f"{{type: polygon, vertices: {vertices}}}"), "p.yaml").scene
        assert isinstance(scene.bodies[0].shape, Polygon)


def test_pentagram_is_self_intersecting(tmp_path: Path) -> None:
    star = "[[0, 1], [0.59, -0.81], [-0.95, 0.31], [0.95, 0.31], [-0.59, -0.81]]"
    path, messages = problems(tmp_path, one_body(f"{{type: polygon, vertices: {star}}}"))
    assert messages == [
        f"{path}:3:62: bodies.b.shape.vertices.2: edges 0-1 and 2-3 cross: the polygon intersects itself"
    ]


def test_pairs_must_be_lists_of_two(tmp_path: Path) -> None:
    path, messages = problems(tmp_path, one_body("{type: circle, radius: 1}", "    velocity: 3\n"))
    assert messages == [f"{path}:5:15: bodies.b.velocity: expected a list of two values, like [x, y] (got 3)"]


def test_aabb_with_an_angle(tmp_path: Path) -> None:
    path, messages = problems(tmp_path, one_body("{type: aabb, width: 1, height: 1}", "    angle: 0.3\n"))
    assert messages == [
        f"{path}:5:12: bodies.b.angle: an aabb never rotates, so its angle must be 0: use shape "
        "type obb for a turned box"
    ]


def test_unknown_shape_type(tmp_path: Path) -> None:
    path, messages = problems(tmp_path, one_body("{type: circel, radius: 1}"))
    assert messages == [
        f"{path}:3:19: bodies.b.shape.type: unknown shape type 'circel' (did you mean "
        "'circle'?); expected one of: circle, aabb, obb, polygon, capsule, segment, chain"
    ]


def test_duplicate_names(tmp_path: Path) -> None:
    path, messages = problems(
        tmp_path,
        "bodies:\n  - {name: a, shape: {type: circle, radius: 1}, position: [0, 0]}\n"
        "  - {name: a, shape: {type: circle, radius: 1}, position: [3, 0]}\n",
    )
    assert messages == [f"{path}:3:12: bodies.a.name: duplicate body name 'a' (also body 0)"]


def test_duplicate_yaml_keys(tmp_path: Path) -> None:
    path, messages = problems(tmp_path, "seed: 1\nseed: 2\n")
    assert messages == [f"{path}:2:1: seed: duplicate key 'seed' (YAML keeps only the last)"]


def test_unknown_material_with_did_you_mean(tmp_path: Path) -> None:
    path, messages = problems(tmp_path, one_body("{type: circle, radius: 1}", "    material: rubbr\n"))
    assert messages == [
        f"{path}:5:15: bodies.b.material: unknown material 'rubbr' (did you mean 'rubber'?); "
        "known: default, metal, plastic, rubber, stone"
    ]


def test_user_materials_extend_and_override_presets() -> None:
    text = (
        "materials:\n  ice: {density: 0.9, restitution: 0.05, friction: 0.02}\n"
        "  metal: {density: 8, restitution: 0.1, friction: 0.3}\n"
        + one_body("{type: circle, radius: 1}", "    material: ice\n")
        + "  - {name: m, shape: {type: circle, radius: 1}, position: [3, 0], material: metal}\n"
    )
    scene = load_scene_text(text, "m.yaml").scene
    assert scene.material_of(scene.bodies[0]).friction == 0.02
    assert scene.material_of(scene.bodies[1]) == Material(density=8, restitution=0.1, friction=0.3)


def test_every_problem_at_once_sorted_by_line(tmp_path: Path) -> None:
    text = (
        "world: {tick_rate: -1, precision: 0}\n"
        "bodies:\n"
        "  - {name: a, shape: {type: circle, radius: -1}, position: [0, 0], colour: red}\n"
        "  - {name: c, shape: {type: obb, width: 1}, position: [0, 0, 0]}\n"
        "  - {name: a, shape: {type: circle, radius: 1}, position: [0, 0], material: glas}\n"
    )
    path, messages = problems(tmp_path, text)
    assert [m.split(": ")[0] for m in messages] == [
        f"{path}:1:20",
        f"{path}:1:35",
        f"{path}:3:45",
        f"{path}:3:68",
        f"{path}:4:22",
        f"{path}:4:55",
        f"{path}:5:12",
        f"{path}:5:77",
    ]
    assert "duplicate body name 'a'" in messages[6] and "unknown material 'glas'" in messages[7]
    assert "missing key 'height'" in messages[4] and "unknown key 'colour'" in messages[3]


def test_bad_overrides_are_named(tmp_path: Path) -> None:
    path, messages = problems(
        tmp_path,
        GOOD,
        ("bodies.ball.radiuss=1", "bodies.crate.angle=1", "world.precision", "bodies.ball.shape.radius=-2"),
    )
    assert messages == [
        "--set bodies.ball.radiuss=1: unknown key 'bodies.ball.radiuss'",
        "--set bodies.crate.angle=1: unknown key 'bodies.crate': no item 'crate' in 'bodies' "
        "(a name or an index 0..1)",
        "--set world.precision: expected KEY=VALUE, e.g. world.precision=20",
        "--set bodies.ball.shape.radius=-2: bodies.ball.shape.radius: "
        "Input should be greater than 0 (got -2)",
    ]


def test_missing_and_unreadable_files(tmp_path: Path) -> None:
    with pytest.raises(UserError) as raised:
        load_scene(tmp_path / "nope.yaml")
    assert raised.value.messages == [f"{tmp_path / 'nope.yaml'}: no such scene file"]
    with pytest.raises(UserError) as raised:
        load_scene(tmp_path)
    assert raised.value.messages == [f"{tmp_path}: is a directory, not a scene file"]
    binary = tmp_path / "binary.yaml"
    binary.write_bytes(b"\xff\xfe\x00")
    with pytest.raises(UserError, match="not UTF-8"):
        load_scene(binary)


def test_a_scene_must_be_a_mapping(tmp_path: Path) -> None:
    path, messages = problems(tmp_path, "- 1\n- 2\n")
    assert messages == [f"{path}:1:1: a scene is a mapping of keys (version, world, bodies, ...), not a list"]


def test_resolved_text_round_trips(tmp_path: Path) -> None:
    text = GOOD + (
        "generators:\n  - {name: rain, count: 5, shape: {type: circle, radius: {uniform: [0.1, 0.2]}},"
        " region: {min: [-1, 3], max: [1, 5]}, material: {choice: [stone, {density: 2, restitution: 0,"
        " friction: 1}]}}\n"
    )
    first = load_scene_text(text, "round.yaml", ["bodies.ball.angle=1e-3"], seed=7)
    again = load_scene_text(first.text, "stored")
    assert again.scene == first.scene
    assert again.text == first.text and again.sha256 == first.sha256
    assert first.scene.generators == [] and len(first.scene.bodies) == 7 and first.scene.seed == 7
    assert first.overrides == ("bodies.ball.angle=1e-3",)


def test_validate_command(cli, tmp_path: Path) -> None:  # noqa: ANN001 - the conftest fixture
    good = tmp_path / "good.yaml"
    good.write_text(GOOD)
    result = cli("validate", good)
    assert result.exit_code == 0
    assert result.stdout == f"{good}: OK: scene 'good', 2 bodies, 10 ticks at 120 Hz\n"
    result = cli("validate", good, "-s", "bodies.ball.material=rubbr")
    assert result.exit_code == 2 and result.stdout == ""
    assert result.stderr == (
        "--set bodies.ball.material=rubbr: bodies.ball.material: unknown material 'rubbr' "
        "(did you mean 'rubber'?); known: default, metal, plastic, rubber, stone\n"
    )


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        (
            "bodies:\n  - {name: b, shape: {type: circle, radius: 0}, position: [0, 0]}\n",
            "scene.yaml:2:45: bodies.b.shape.radius: Input should be greater than 0 (got 0)",
        ),
        (
            "bodies: [\n",
            "scene.yaml:2:1: YAML syntax error: expected the node content, but found '<stream end>'",
        ),
        (None, "missing.yaml: no such scene file"),
    ],
)
def test_validate_in_a_subprocess(tmp_path: Path, text: str | None, expected: str) -> None:
    scene = tmp_path / ("scene.yaml" if text is not None else "missing.yaml")
    if text is not None:
        scene.write_text(text)
    done = subprocess.run(
        [sys.executable, "-c", "from rustycs_cli.app import program; program()", "validate", str(scene)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 2
    assert done.stderr == f"{tmp_path}/{expected}\n"
    assert "Traceback" not in done.stderr and done.stdout == ""
