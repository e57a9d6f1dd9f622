"""Box2D v3's benchmark scenes in scenes/bench (make_box2d_scenes.py): each builds with Box2D's bodies where
Box2D's shared/benchmarks.c puts them, the tumbler's drum turns in rustycs and in both peers, and the
measures the bench reports for them give the right numbers on hand-made poses. The scenes are large:
nothing here runs more than two ticks."""

from __future__ import annotations

import functools
import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest

from rustycs_cli.bench import peers, quality
from rustycs_cli.bench.scenes import default_scene_dir, find_scenes, parse_ids
from rustycs_cli.bench.spec import BenchScene, BodySpec, ShapeSpec, describe
from rustycs_cli.build import build_world
from rustycs_cli.loading import load_scene

HAVE_PEERS = all(importlib.util.find_spec(name) for name in peers.ENGINES)
needs_peers = pytest.mark.skipif(not HAVE_PEERS, reason="pymunk and pyb2d3 (the bench extra) are missing")
DRUM_SPEED = math.radians(25.0)  # Box2D's motor speed, rad/s


@functools.cache
def built(name: str):  # noqa: ANN201
    """(scene, world) of scenes/bench/NAME.yaml, before its first step."""
    scene = load_scene(Path(default_scene_dir()) / f"{name}.yaml").scene
    return scene, build_world(scene)


def box2d_boxes(name: str) -> list[tuple[float, float]]:
    """The dynamic boxes' positions as Box2D's Create<Name> computes them, in its creation order."""
    if name == "large_pyramid":
        return [((i + 1) * 0.5 + (j - i) - 50.0, i + 0.5) for i in range(100) for j in range(i, 100)]
    if name == "many_pyramids":
        return [((r + 1) * 0.5 + (k - r) - 110.0 + 11 * col + 1.0 - 0.5, r + 0.5 + 11 * row)
                for row in range(20) for col in range(20) for r in range(10) for k in range(r, 10)]
    if name == "smash":
        return [(-20.0, 0.0)] + [(i * 0.4 + 30.0, (j - 40) * 0.4) for i in range(120) for j in range(80)]
    return [(-9.0 + 0.4 * j, 1.0 + 0.4 * i) for i in range(45) for j in range(45)]


@pytest.mark.parametrize(("name", "fixed", "shapes"), [  # fixed: the static ground or the kinematic drum
    ("large_pyramid", 1, 5051), ("many_pyramids", 1, 22020), ("smash", 0, 9601), ("tumbler", 1, 2029)])
def test_scene_builds_with_box2ds_bodies(name: str, fixed: int, shapes: int):
    scene, world = built(name)
    dynamic = world.body_types == "dynamic"
    assert (~dynamic).sum() == fixed and world.shape_count == shapes
    assert world.positions[dynamic] == pytest.approx(np.array(box2d_boxes(name)), abs=1e-9)
    assert scene.world.tick_rate == 60 and scene.world.precision == 4


def test_the_heavy_box_of_smash_and_no_gravity():
    scene, world = built("smash")
    assert world.masses[0] == pytest.approx(8.0 * 64) and tuple(world.velocities[0]) == (40.0, 0.0)
    assert world.masses[1] == pytest.approx(0.16) and not scene.forces


def test_tumbler_drum_turns_in_rustycs(compiled_engine: None):
    scene, _ = built("tumbler")
    world = build_world(scene)  # a fresh one: `built` keeps the unstepped one
    assert world.body_types[0] == "kinematic" and world.angular_velocities[0] == pytest.approx(DRUM_SPEED)
    world.step(2)
    assert world.angles[0] == pytest.approx(2 / 60 * DRUM_SPEED, abs=1e-12)
    assert tuple(world.positions[0]) == (0.0, 10.0)
    assert world.positions[1:, 1].min() < 1.0 and world.active.all()  # the boxes fall, none are lost


@needs_peers
@pytest.mark.parametrize("engine", peers.ENGINES)
def test_peers_build_the_drum_of_four_walls(engine: str):
    scene, world = built("tumbler")
    bench = describe(scene, world)
    drum = bench.bodies[0]
    assert drum.body_type == "kinematic" and [s.kind for s in drum.shapes] == ["polygon"] * 4
    peer = peers.build(engine, bench)
    if engine == "pymunk":
        shapes = len(peer.space.shapes)
    else:
        shapes = sum(body.shape_count for body in peer.bodies)
    assert shapes == world.shape_count == 2029
    for _ in range(2):
        peer.step()
    x, y, angle = peer.poses()[0]
    assert (x, y) == pytest.approx((0.0, 10.0)) and angle == pytest.approx(2 / 60 * DRUM_SPEED, rel=1e-5)


def test_box2d_scenes_are_found_by_name_in_any_case():
    ids = parse_ids(["Large_Pyramid,SMASH", "tumbler", "many_pyramids"])
    assert ids == ["large_pyramid", "smash", "tumbler", "many_pyramids"]
    assert [p.name for p in find_scenes(default_scene_dir(), ids).values()] == [f"{i}.yaml" for i in ids]
    assert "large_pyramid" not in parse_ids([])  # only when named


# --------------------------------------------------------------------------------------------- measures


def box(position, body_type: str = "dynamic") -> BodySpec:
    """A body of one unit square about its origin."""
    dynamic = body_type == "dynamic"
    square = ShapeSpec(kind="polygon", points=((-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)),
                       centre=(0.0, 0.0), radius=0.0, mass=1.0 if dynamic else 0.0, friction=0.6,
                       restitution=0.0)
    return BodySpec(kind="obb", body_type=body_type, position=position, angle=0.0, velocity=(0.0, 0.0),
                    angular_velocity=0.0, mass=1.0 if dynamic else math.inf, fixed_rotation=False, group=0,
                    bullet=False, shapes=(square,))


def test_top_displacement_follows_the_highest_box_at_the_start():
    pile = (box((0.0, -1.0), body_type="static"), box((-0.5, 0.5)), box((0.5, 0.5)), box((0.0, 1.5)))
    scene = BenchScene("pile", 1 / 60, (0.0, -10.0), (), pile)
    start = np.array([(*b.position, 0.0) for b in pile])
    end = start + [[9, 9, 0], [-6.0, 0, 0], [0, 0, 0], [0.3, -0.4, 0]]  # the static's pose is no body's
    got = quality.measure(quality.METRICS["large_pyramid"], scene, start, end)
    assert got == pytest.approx({"top_displacement": 0.5, "max_displacement": 6.0})


def test_outside_is_taken_in_the_frame_of_a_turning_drum():
    """The tumbler's walls (centres at +-10 from the drum's origin) turned by 45 degrees: a box 13 m above
    the centre is in the drum's corner, inside; unturned it is beyond the top wall."""
    walls = [ShapeSpec(kind="polygon", points=(), centre=centre, radius=0.0, mass=0.0, friction=0.6,
                       restitution=0.0) for centre in ((10.0, 0.0), (-10.0, 0.0), (0.0, 10.0), (0.0, -10.0))]
    drum = BodySpec(kind="compound", body_type="kinematic", position=(0.0, 10.0), angle=0.0,
                    velocity=(0.0, 0.0), angular_velocity=DRUM_SPEED, mass=math.inf, fixed_rotation=False,
                    group=0, bullet=False, shapes=tuple(walls))
    scene = BenchScene("drum", 1 / 60, (0.0, -10.0), (), (drum, box((0.0, 23.0)), box((0.0, 10.0))))
    poses = np.array([(0.0, 10.0, 0.0), (0.0, 23.0, 0.0), (0.0, 10.0, 0.0)])
    active = np.ones(3, bool)
    assert quality.outside(scene, poses, active) == 1
    poses[0, 2] = math.pi / 4
    assert quality.outside(scene, poses, active) == 0
    active[2] = False  # deactivated counts as out
    assert quality.outside(scene, poses, active) == 1
