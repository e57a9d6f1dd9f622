"""`--set KEY=VALUE` overrides: dotted paths, list items by index or name, implicit keys, errors."""

from __future__ import annotations

from typing import Any

import pytest

from rustycs_cli.errors import UserError
from rustycs_cli.loading import load_scene_text
from rustycs_cli.overrides import apply_overrides
from rustycs_cli.scene import Material, Scene

SCENE = """\
world: {precision: 10}
forces:
  - {name: gravity, acceleration: [0, -9.81]}
materials:
  ice: {density: 0.9, restitution: 0.05, friction: 0.02}
bodies:
  - {name: floor, type: static, shape: {type: aabb, width: 10, height: 1}, position: [0, -0.5]}
  - {name: crate, shape: {type: obb, width: 1, height: 1}, position: [0, 2]}
  - {shape: {type: circle, radius: 0.5}, position: [2, 2]}
generators:
  - {name: rain, count: 3, shape: {type: circle, radius: 0.1}, region: {min: [0, 5], max: [1, 6]}}
"""


def scene(*overrides: str) -> Scene:
    return load_scene_text(SCENE, "s.yaml", overrides).scene


def errors(*overrides: str) -> list[str]:
    with pytest.raises(UserError) as raised:
        load_scene_text(SCENE, "s.yaml", overrides)
    return raised.value.messages


def test_dotted_paths_by_name_and_by_index() -> None:
    s = scene(
        "world.precision=20",
        "forces.gravity.acceleration=[0,-1.62]",
        "bodies.crate.angle=0.5",
        "bodies.0.material=metal",
        "bodies.circle-2.velocity.0=3",
        "generators.rain.count=5",
        "forces.0.name=moon",
    )
    assert s.world.precision == 20
    assert s.forces[0].acceleration == (0.0, -1.62) and s.forces[0].name == "moon"
    assert s.bodies[1].angle == 0.5 and s.bodies[0].material == "metal"
    assert s.bodies[2].velocity == (3.0, 0.0)  # the default [0, 0] exists, its item is set
    assert [b.name for b in s.bodies[3:]] == [f"rain-{i}" for i in range(5)]


def test_keys_with_defaults_and_preset_materials_exist_unwritten() -> None:
    s = scene(
        "output.every=5",
        "world.bounds={min: [-50, -50], max: [50, 50]}",
        "materials.metal.friction=0.3",
        "materials.ice.density=1e-3",
        "bodies.crate.mass=2",
        "world.bounds.max.1=60",
    )
    assert s.output.every == 5
    assert s.world.bounds is not None and s.world.bounds.max == (50.0, 60.0)
    assert s.materials["metal"] == Material(density=7.8, restitution=0.1, friction=0.3)
    assert s.materials["ice"].density == 0.001
    assert s.bodies[1].mass == 2.0


def test_values_are_yaml_and_later_overrides_see_earlier_ones() -> None:
    s = scene("bodies.crate.shape={type: circle, radius: 2}", "bodies.crate.shape.radius=3")
    assert s.bodies[1].shape.type == "circle" and s.bodies[1].shape.radius == 3.0
    with pytest.raises(UserError, match="description: Input should be a valid string"):
        scene("description=no")  # YAML: `no` is false


def test_overrides_are_recorded_and_in_the_resolved_text() -> None:
    loaded = load_scene_text(SCENE, "s.yaml", ["bodies.crate.angle=0.25"])
    assert loaded.overrides == ("bodies.crate.angle=0.25",)
    again = load_scene_text(loaded.text, "stored")
    assert again.scene.bodies[1].angle == 0.25


@pytest.mark.parametrize(
    ("override", "message"),
    [
        ("bodies.crate.angel=1", "unknown key 'bodies.crate.angel' (did you mean 'bodies.crate.angle'?)"),
        (
            "bodies.crat.angle=1",
            "unknown key 'bodies.crat': no item 'crat' in 'bodies' (a name or an index 0..2) "
            "(did you mean 'bodies.crate'?)",
        ),
        ("bodies.7.angle=1", "unknown key 'bodies.7': no item '7' in 'bodies' (a name or an index 0..2)"),
        ("materials.rubbr.density=1", "unknown key 'materials.rubbr' (did you mean 'materials.rubber'?)"),
        ("wrld.precision=3", "unknown key 'wrld' (did you mean 'world'?)"),
        ("bodies.crate.shape.radius=1", "unknown key 'bodies.crate.shape.radius'"),
        (
            "bodies.crate.position.0.x=1",
            "unknown key 'bodies.crate.position.0.x': 'bodies.crate.position.0' is a "
            "value, not a mapping or list",
        ),
        (
            "attractors.sun.mass=1",
            "unknown key 'attractors.sun': no item 'sun' in 'attractors' (none: the list is empty)",
        ),
        ("world.precision", "expected KEY=VALUE, e.g. world.precision=20"),
        ("world..precision=1", "'world..precision' is not a dotted path like bodies.crate.angle"),
        (
            "world.precision=[1,",
            "VALUE is not valid YAML: expected the node content, but found '<stream end>'",
        ),
    ],
)
def test_bad_overrides(override: str, message: str) -> None:
    assert errors(override) == [f"--set {override}: {message}"]


def test_invalid_values_are_reported_at_the_override() -> None:
    assert errors("world.precision=0", "bodies.crate.shape={type: obb, width: 1}") == [
        "--set world.precision=0: world.precision: Input should be greater than or equal to 1 (got 0)",
        "--set bodies.crate.shape={type: obb, width: 1}: bodies.crate.shape: missing key 'height'",
    ]


def test_a_failing_override_changes_nothing() -> None:
    data: dict[str, Any] = {"bodies": []}
    applied, problems = apply_overrides(data, ["world.bounds.mn=[0, 0]", "output.every=2"])
    assert data == {"bodies": [], "output": {"every": 2}}
    assert [a.path for a in applied] == [("output", "every")]
    assert problems == [
        "--set world.bounds.mn=[0, 0]: unknown key 'world.bounds.mn' (did you mean 'world.bounds.min'?)"
    ]
