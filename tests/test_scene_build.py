"""build_world: a validated scene becomes an engine World with the same settings and bodies (no stepping)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rustycs_cli.build import build_world, material_names, shape_material_names
from rustycs_cli.loading import load_scene_text
from rustycs_cli.scene import PRESET_MATERIALS

SCENE = """\
world: {tick_rate: 120, precision: 7, gravitational_constant: 2.0, bounds: {min: [-50, -40], max: [50, 60]},
        restitution_threshold: 0.5}
forces:
  - {name: gravity, acceleration: [0, -9.81]}
  - {name: wind, acceleration: [2, 0]}
attractors:
  - {name: sun, position: [1, 2], mass: 1000, range: 5, min_distance: 0.1}
materials:
  metal: {density: 10, restitution: 0.1, friction: 0.2}
bodies:
  - {name: floor, type: static, shape: {type: aabb, width: 10, height: 1}, position: [0, -0.5],
     material: stone}
  - {name: ball, shape: {type: circle, radius: 0.5}, position: [0, 2], velocity: [1, 0], material: metal}
  - {name: crate, shape: {type: obb, width: 2, height: 1}, position: [3, 1], angle: 0.3, angular_velocity: -1,
     material: {density: 2, restitution: 0, friction: 1}}
  - {name: wedge, shape: {type: polygon, vertices: [[0, 0], [3, 0], [0, 3]]}, position: [-3, 1], mass: 4.5,
     collision_group: 1}
  - {name: slider, type: kinematic, shape: {type: aabb, width: 1, height: 0.2}, position: [0, 5],
     velocity: [0.5, 0]}
"""


def test_build_world_carries_settings_and_bodies() -> None:
    scene = load_scene_text(SCENE, "build.yaml").scene
    world = build_world(scene)
    assert world.body_count == 5 and world.tick == 0
    assert world.dt == 1 / 120 and world.bounds == ((-50, -40), (50, 60))
    (sun,) = world.attractors
    assert list(sun["position"]) == [1, 2] and sun["mass"] == 1000 and sun["range"] == 5
    assert sun["min_distance"] == 0.1
    assert list(world.shape_kinds) == ["aabb", "circle", "obb", "polygon", "aabb"]
    assert list(world.body_types) == ["static", "dynamic", "dynamic", "dynamic", "kinematic"]
    np.testing.assert_array_equal(world.positions, [[0, -0.5], [0, 2], [3, 1], [-3, 1], [0, 5]])
    np.testing.assert_array_equal(world.velocities[[1, 4]], [[1, 0], [0.5, 0]])
    assert world.angles[2] == 0.3 and world.angular_velocities[2] == -1
    # the user material 'metal' (density 10) replaces the preset; inline density 2; explicit mass 4.5
    assert world.masses[1] == math.pi * 0.25 * 10
    assert world.masses[2] == 2 * 2 * 1 and world.masses[3] == 4.5
    assert math.isinf(world.masses[0]) and math.isinf(world.masses[4])
    # the wedge's centre of mass is its centroid (1, 1) from its origin
    np.testing.assert_allclose(world.centers[3], [-2, 2])
    assert material_names(scene) == ["stone", "metal", "inline", "default", "default"]


def test_a_scene_leaving_keys_out_builds_the_engines_default_world_and_body() -> None:
    import rustycs

    text = "bodies:\n  - {shape: {type: circle, radius: 1}, position: [0, 0]}\n"
    scene = load_scene_text(text, "d.yaml").scene
    built, default = build_world(scene), rustycs.World()
    default.add_body(rustycs.Circle(1.0))
    for setting in ("dt", "precision", "gravitational_constant", "restitution_threshold"):
        assert getattr(built, setting) == getattr(default, setting), setting
    assert list(built.body_types) == list(default.body_types) == ["dynamic"]
    assert built.masses[0] == default.masses[0] == math.pi * rustycs.MATERIALS["default"].density
    assert material_names(scene) == ["default"]
    assert {name: (m.density, m.restitution, m.friction) for name, m in PRESET_MATERIALS.items()} == {
        "default": (0.1, 0.5, 0.6),
        "rubber": (0.9, 0.6, 0.8),
        "plastic": (1.2, 0.5, 0.6),
        "stone": (2.5, 0.2, 0.4),
        "metal": (7.8, 0.1, 0.2),
    }  # the spec's presets


def test_each_shape_is_named_by_its_own_material_or_its_bodys() -> None:
    text = """\
materials:
  ice: {density: 0.9, restitution: 0.05, friction: 0.02}
bodies:
  - name: cup
    position: [0, 0]
    material: ice
    shapes:
      - {type: obb, width: 2, height: 0.2}
      - {type: obb, width: 0.2, height: 2, offset: [-0.9, 0], material: rubber}
      - {type: circle, radius: 0.5, material: {density: 1, restitution: 0, friction: 1}}
  - {shape: {type: circle, radius: 1}, position: [5, 0], material: {density: 2, restitution: 0, friction: 1}}
  - {shape: {type: circle, radius: 1, material: stone}, position: [9, 0]}
"""
    scene = load_scene_text(text, "m.yaml").scene
    assert material_names(scene) == ["ice", "inline", "default"]
    assert shape_material_names(scene) == ["ice", "rubber", "inline", "inline", "stone"]
    world = build_world(scene)
    # the shapes are made of what they name: ice 0.9 x 0.4 + rubber 0.9 x 0.4 + inline 1 x pi 0.25
    assert world.masses[0] == pytest.approx(0.9 * 0.4 + 0.9 * 0.4 + math.pi * 0.25)
    assert world.masses[2] == pytest.approx(math.pi * PRESET_MATERIALS["stone"].density)
