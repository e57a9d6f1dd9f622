"""`rustycs bench`: the command runs and reports its fields; the peer adapters build the same bodies;
the quality measures give the right numbers on hand-made poses. No test asserts a time."""

from __future__ import annotations

import importlib.util
import json
import math
from pathlib import Path

import numpy as np
import pytest
from conftest import NAP, NAP_SLEEPS
from rich.console import Console

from rustycs_cli.bench import peers, quality, suite, worker
from rustycs_cli.bench.report import print_report
from rustycs_cli.bench.spec import BenchScene, BodySpec, ShapeSpec, describe
from rustycs_cli.build import build_world
from rustycs_cli.errors import UserError
from rustycs_cli.loading import load_scene_text

HAVE_PEERS = all(importlib.util.find_spec(name) for name in peers.ENGINES)
needs_peers = pytest.mark.skipif(not HAVE_PEERS, reason="pymunk and pyb2d3 (the bench extra) are missing")

SQUARE = ((-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5))


def body(kind: str = "circle", position=(0.0, 0.0), body_type: str = "dynamic", radius: float = 0.5,
         vertices=SQUARE, angle: float = 0.0, group: int = 0) -> BodySpec:
    """A body of one shape about its origin: a circle, or a polygon of `vertices`."""
    mass = 1.0 if body_type == "dynamic" else math.inf
    shape = ShapeSpec(kind="circle" if kind == "circle" else "polygon",
                      points=((0.0, 0.0),) if kind == "circle" else tuple(vertices), centre=(0.0, 0.0),
                      radius=radius if kind == "circle" else 0.0, mass=1.0 if body_type == "dynamic" else 0.0,
                      friction=0.6, restitution=0.0)
    return BodySpec(kind=kind, body_type=body_type, position=position, angle=angle, velocity=(0.0, 0.0),
                    angular_velocity=0.0, mass=mass, fixed_rotation=kind == "aabb", group=group, bullet=False,
                    shapes=(shape,))


def bench_scene(*bodies: BodySpec, attractors=()) -> BenchScene:
    return BenchScene("hand-made", 1 / 60, (0.0, -9.81), tuple(attractors), bodies)


def poses(scene: BenchScene) -> np.ndarray:
    return np.array([(*b.position, b.angle) for b in scene.bodies])


# ------------------------------------------------------------------------------------------ quality


def test_deepest_overlap_of_each_shape_pair():
    cases = {
        0.1: (body(position=(0, 0)), body(position=(0.9, 0))),  # circles, 1.0 - 0.9
        0.2: (body("obb", (0, 0)), body("obb", (0.8, 0.05))),  # boxes overlap 0.2 along x
        0.15: (body("obb", (0, 0)), body(position=(0.85, 0.0))),  # circle into a box face
        0.0: (body("obb", (0, 0)), body("obb", (1.3, 0), angle=math.pi / 4)),  # turned box just apart
    }
    for depth, pair in cases.items():
        scene = bench_scene(*pair)
        got = quality.deepest_overlap(scene, poses(scene), np.ones(2, bool))
        assert got == pytest.approx(depth, abs=1e-12)


def test_overlap_skips_same_group_statics_pairs_and_inactive_bodies():
    deep, shallow = body(position=(0, 2), group=3), body(position=(0.5, 2), group=3)  # 0.5 deep, one group
    floor = body("aabb", (0, -0.5), body_type="static", vertices=((-5, -0.5), (5, -0.5), (5, 0.5), (-5, 0.5)))
    wall = body("aabb", (0, 0), body_type="static")  # overlaps the floor: statics never count
    resting = body(position=(3, 0.45))  # 0.05 into the floor
    scene = bench_scene(deep, shallow, floor, wall, resting)
    alive = np.ones(5, bool)
    assert quality.deepest_overlap(scene, poses(scene), alive) == pytest.approx(0.05)
    other = bench_scene(deep, body(position=(0.5, 2), group=4), floor, wall, resting)
    assert quality.deepest_overlap(other, poses(other), alive) == pytest.approx(0.5)
    alive[1] = False  # a deactivated body no longer collides
    assert quality.deepest_overlap(other, poses(other), alive) == pytest.approx(0.05)


def test_escaped_counts_bodies_outside_the_container_and_deactivated_ones():
    floor = body("aabb", (0, -0.5), body_type="static")
    left, right = body("aabb", (-10.5, 30), body_type="static"), body("aabb", (10.5, 30), body_type="static")
    inside, below, beside, frozen = (body(position=p) for p in ((0, 3), (0, -0.7), (11, 5), (2, 2)))
    scene = bench_scene(floor, left, right, inside, below, beside, frozen)
    active = np.array([True] * 6 + [False])
    assert quality.escaped(scene, poses(scene), active) == 3


def test_measures_from_start_and_end_poses():
    sun = (1.0, 0.0, 1000.0)
    floor = body("aabb", (0, -0.5), body_type="static")
    scene = bench_scene(floor, body(position=(3, 0)), body(position=(1, 5)), attractors=[sun])
    start = poses(scene)
    end = start + [[0, 0, 0], [1.0, 0, 0], [0, -0.5, 0]]  # radii about (1, 0): 2 -> 3 and 5 -> 4.5
    got = quality.measure(("max_displacement", "mean_radius_drift", "max_radius_drift"), scene, start, end)
    assert got == pytest.approx({"max_displacement": 1.0, "mean_radius_drift": 0.3, "max_radius_drift": 0.5})


# -------------------------------------------------------------------------------------- peer adapters

FALLING = """\
name: falling
world: {tick_rate: 60, ticks: 10, precision: 4}
forces: [{name: gravity, acceleration: [0, -9.81]}]
materials: {bench: {density: 1.0, restitution: 0.0, friction: 0.6}}
bodies:
  - {name: floor, type: static, shape: {type: aabb, width: 40, height: 1}, position: [0, -10.5],
     material: bench}
  - {name: crate, shape: {type: obb, width: 1, height: 0.5}, position: [-3, 2], angle: 0.3, material: bench}
  - {name: wedge, shape: {type: polygon, vertices: [[0, 0], [1.2, 0], [0, 0.9]]}, position: [0, 2],
     angle: -0.4, material: bench}
  - {name: ball, shape: {type: circle, radius: 0.3}, position: [3, 2], velocity: [1, 2], material: bench}
  - {name: slab, shape: {type: aabb, width: 2, height: 0.4}, position: [6, 2], mass: 5, material: bench}
"""


def falling_scene() -> tuple[BenchScene, object]:
    scene = load_scene_text(FALLING, "falling.yaml").scene
    world = build_world(scene)
    return describe(scene, world), world


def test_describe_reads_the_scene_as_rustycs_builds_it():
    bench, _world = falling_scene()
    floor, crate, wedge, ball, slab = bench.bodies
    assert bench.gravity == (0.0, -9.81) and bench.dt == pytest.approx(1 / 60)
    assert floor.body_type == "static" and floor.mass == math.inf
    assert crate.kind == "obb" and crate.mass == pytest.approx(0.5) and crate.angle == pytest.approx(0.3)
    assert [s.kind for s in crate.shapes] == ["polygon"] and crate.shapes[0].mass == crate.mass
    assert wedge.kind == "polygon" and wedge.shapes[0].area == pytest.approx(0.54)
    assert wedge.position == pytest.approx((0.0, 2.0), abs=1e-12)
    (disc,) = ball.shapes
    assert ball.velocity == (1.0, 2.0) and disc.radius == 0.3 and disc.friction == 0.6
    assert slab.kind == "aabb" and slab.mass == 5.0 and slab.fixed_rotation and not crate.fixed_rotation
    assert floor.fixed_rotation and floor.shapes[0].mass == 0.0


@needs_peers
@pytest.mark.parametrize("engine", peers.ENGINES)
def test_peers_build_the_same_bodies_as_rustycs(engine: str, compiled_engine: None):
    bench, world = falling_scene()
    peer = peers.build(engine, bench)
    start = np.array(peer.poses())
    assert start[1:] == pytest.approx(poses(bench)[1:], abs=1e-6)  # origins, not centroids
    for _ in range(10):
        peer.step()
    world.step(10)
    ours = np.column_stack([world.positions, world.angles])
    # Free flight for 1/6 s (the bodies fall 0.12 to 0.15 m): the engines differ only in integrating
    # (pymunk moves positions before velocities, rustycs and Box2D take substeps).
    assert np.array(peer.poses())[1:] == pytest.approx(ours[1:], abs=0.025)
    assert ours[3, 0] - 3.0 == pytest.approx(1 / 6, abs=1e-9)  # the ball's initial velocity


@needs_peers
@pytest.mark.parametrize("engine", peers.ENGINES)
def test_peers_keep_collision_groups(engine: str):
    def gap_after(group_b: int) -> float:
        scene = BenchScene("pair", 1 / 60, (0.0, 0.0), (), (body(position=(0, 0), group=2),
                                                             body(position=(0.8, 0), group=group_b)))
        peer = peers.build(engine, scene)
        for _ in range(30):
            peer.step()
        (xa, _, _), (xb, _, _) = peer.poses()
        return xb - xa

    assert gap_after(2) == pytest.approx(0.8)  # same group: they pass through each other
    assert gap_after(-2) > 0.95  # another group (also in Box2D, where groups must be negative)


def shape(kind: str, points, radius: float = 0.0, mass: float = 0.0) -> ShapeSpec:
    centre = tuple(np.mean(points, axis=0)) if kind != "circle" else points[0]
    return ShapeSpec(kind=kind, points=tuple(points), centre=centre, radius=radius, mass=mass, friction=0.6,
                     restitution=0.0)


def compound(position, *shapes: ShapeSpec, body_type: str = "dynamic") -> BodySpec:
    return BodySpec(kind="compound", body_type=body_type, position=position, angle=0.0, velocity=(0.0, 0.0),
                    angular_velocity=0.0, mass=1.0 if body_type == "dynamic" else math.inf,
                    fixed_rotation=False, group=0, bullet=False, shapes=shapes)


def square(x: float, y: float, half: float = 0.5) -> list[tuple[float, float]]:
    return [(x - half, y - half), (x + half, y - half), (x + half, y + half), (x - half, y + half)]


def test_quality_of_bodies_made_of_shapes():
    """The container is made of a static body's shapes with area (its segment far below is no wall);
    overlaps are between shapes of different bodies, never within one."""
    container = compound((0.0, 0.0), shape("polygon", square(0, -0.5, 0.5)), shape("polygon", square(-5, 2)),
                         shape("polygon", square(5, 2)), shape("segment", [(-50, -80), (50, -80)]),
                         body_type="static")
    pair = compound((0.0, 3.0), shape("polygon", square(0, 0)), shape("polygon", square(0.5, 0)))  # overlap
    ball = shape("circle", [(0.0, 0.0)], radius=0.3)
    touching = compound((1.2, 3.0), ball)  # 0.1 into the pair's right box
    outside, below = compound((6.0, 3.0), ball), compound((0.0, -2.0), ball)
    scene = bench_scene(container, pair, touching, outside, below)
    active = np.ones(5, bool)
    assert quality.escaped(scene, poses(scene), active) == 2  # beyond the wall at x = 5, below the floor
    assert quality.deepest_overlap(scene, poses(scene), active) == pytest.approx(0.1)


@pytest.fixture(scope="module")
def compounds() -> tuple[BenchScene, object]:
    """Box2D's compounds scene as the bench builds it (from the generator's data: no YAML to parse)."""
    import importlib.util as util

    from rustycs_cli.scene import Scene

    script = Path(__file__).resolve().parents[1] / "scenes" / "bench" / "make_compounds_scene.py"
    spec = util.spec_from_file_location("make_compounds_for_bench", script)
    assert spec is not None and spec.loader is not None
    module = util.module_from_spec(spec)
    spec.loader.exec_module(module)
    scene = Scene.model_validate(module.scene())
    world = build_world(scene)
    return describe(scene, world), world


def test_the_compounds_scene_is_3000_bodies_of_two_triangles(compounds):
    bench, world = compounds
    ground, *bodies = bench.bodies
    assert len(bodies) == 3000 and {b.body_type for b in bodies} == {"dynamic"} and world.shape_count == 6282
    assert ground.kind == "compound" and [s.kind for s in ground.shapes] == ["polygon"] * 281 + ["segment"]
    assert ground.fixed_rotation and all(s.mass == 0 for s in ground.shapes)
    for body in bodies[:10]:
        assert body.kind == "compound" and [s.kind for s in body.shapes] == ["polygon", "polygon"]
        assert body.mass == pytest.approx(2.0) and [s.mass for s in body.shapes] == pytest.approx([1.0, 1.0])
        assert [s.friction for s in body.shapes] == [0.5, 0.5] and not body.fixed_rotation
    assert bodies[0].position == pytest.approx((-18.75, 5.575))
    assert bodies[1].position == pytest.approx((-19.25, 7.825))


@needs_peers
@pytest.mark.parametrize("engine", peers.ENGINES)
def test_peers_build_the_compounds_shape_for_shape(engine: str, compounds):
    bench, world = compounds
    peer = peers.build(engine, bench)
    if engine == "pymunk":
        shapes = len(peer.space.shapes)
    else:
        shapes = sum(body.shape_count for body in peer.bodies)
    assert shapes == world.shape_count == 6282
    masses = [body.mass for body in peer.bodies[1:]]
    assert masses == pytest.approx([2.0] * 3000, rel=1e-6)  # two triangles of area 1, density 1
    assert np.array(peer.poses()) == pytest.approx(poses(bench), abs=1e-4)  # Box2D: float32, y up to 340 m


# ------------------------------------------------------------------------------------- --sleep, --threads


@pytest.fixture
def nap(tmp_path: Path) -> Path:
    """A crate resting on a floor (asleep from tick NAP_SLEEPS where sleeping is on) and a ball falling
    from 6 m; the scene itself says sleep: true."""
    path = tmp_path / "nap.yaml"
    path.write_text(NAP)
    return path


@pytest.mark.parametrize("sleep", [True, False])
def test_the_worker_loads_scenes_sleeping_as_asked(nap: Path, sleep: bool, compiled_engine: None):
    world = build_world(worker.load(str(nap), sleep).scene)  # --sleep, or not, whatever the scene says
    assert world.sleep is sleep and world.sleep_time == peers.SLEEP_TIME
    world.step(NAP_SLEEPS + 10)
    assert list(world.asleep) == [False, sleep, False]  # the floor and the falling ball never sleep


@needs_peers
@pytest.mark.parametrize("engine", peers.ENGINES)
@pytest.mark.parametrize("sleep", [True, False])
def test_peers_sleep_when_asked(engine: str, sleep: bool):
    scene = load_scene_text(NAP, "nap.yaml").scene  # the peers take sleeping from `sleep` alone
    peer = peers.build(engine, describe(scene, build_world(scene)), sleep=sleep)
    assert peer.sleep is sleep
    for _ in range(NAP_SLEEPS + 10):  # the ball lands at about tick 62
        peer.step()
    _floor, crate, ball = peer.bodies
    if engine == "pymunk":
        asleep = [crate.is_sleeping, ball.is_sleeping]
    else:
        asleep = [not crate.awake, not ball.awake]
    assert asleep == [sleep, False]


@needs_peers
@pytest.mark.parametrize("engine", peers.ENGINES)
def test_peers_step_with_the_threads_asked_for(engine: str):
    bench, _world = falling_scene()
    one, two, three = (peers.build(engine, bench, threads=n) for n in (1, 2, 3))
    used = 2 if engine == "pymunk" else 3  # Chipmunk's threaded space runs 2 threads at most
    assert (one.threads, two.threads, three.threads) == (1, 2, used) == tuple(
        peers.threads_used(engine, n) for n in (1, 2, 3))
    for peer in (one, two, three):
        for _ in range(10):
            peer.step()
    assert np.array(two.poses()) == pytest.approx(np.array(one.poses()), abs=1e-9)  # free flight
    assert np.array(three.poses()) == pytest.approx(np.array(one.poses()), abs=1e-9)
    described = peers.describe_settings(engine, False, 3)
    assert ("threaded space, 2 threads" in described and "2 at most" in described if engine == "pymunk"
            else described.endswith("3 workers (a pyb2d3 ThreadPool)"))
    assert "single-threaded" in peers.describe_settings(engine, False, 1)


# ---------------------------------------------------------------------------------- aggregation, report


def test_series_medians_ratios_and_failures(monkeypatch: pytest.MonkeyPatch):
    times = {"rustycs": iter([1.0, 3.0, 2.0]), "pymunk": iter([4.0, 4.0, 5.0]), "pyb2d3": iter([1.0, 1.0])}

    def fake(engine: str, scene: str, max_ticks, block: int, metrics, sleep: bool, threads: int) -> dict:
        value = next(times[engine], None)
        if value is None:
            return {"error": "diverged"}
        return {"ms_per_tick": value, "scene": "S2_pyramid20", "bodies": 210, "ticks": 600,
                "quality": {"max_displacement": value / 10}, "sleep": sleep, "threads": threads,
                "kb_per_body": 3 * value}

    monkeypatch.setattr(suite.runner, "measure_steps", fake)
    plan = suite.Plan(scenes={"S2": Path("S2.yaml")}, engines=("rustycs", "pymunk", "pyb2d3"), reps=3,
                      max_ticks=None, block=100, compile=False, scaling=False, recording=False, sleep=True,
                      threads=2, command="rustycs bench")
    rows = suite._series(plan, [("S2", "S2.yaml", ("max_displacement",))], lambda line: None)
    row = rows["S2"]
    assert row["engines"]["rustycs"]["median_ms"] == 2.0 and row["engines"]["rustycs"]["min_ms"] == 1.0
    assert row["ratios"] == {"pymunk": 0.5, "pyb2d3": 2.0}
    assert row["engines"]["rustycs"]["median_kb_per_body"] == 6.0
    assert row["engines"]["pymunk"]["quality"] == {"max_displacement": 0.4}  # from the first repetition
    assert all((cell["sleep"], cell["threads"]) == (True, 2) for cell in row["engines"].values())
    settings = {"sleep": True, "threads": 2, "engines": {"rustycs": "sleeping on", "pymunk": "2 threads"}}
    result = {"meta": {"cpu": "cpu", "cores": 2, "date": "today", "command": "rustycs bench", "reps": 3,
                       "settings": settings}, "scenes": rows}
    assert suite.failures(result) == ["S2 pyb2d3: diverged"]
    console = Console(record=True, width=200)
    print_report(result, markdown=True, console=console)
    text = console.export_text()
    assert "- rustycs: sleeping on\n- pymunk: 2 threads\n" in text
    titles = [line for line in text.splitlines() if line.startswith("**")]
    assert titles and all(title.endswith("; sleeping on, 2 threads per world**") for title in titles)
    rows = [[cell.strip() for cell in line.strip().strip("|").split("|")]
            for line in text.splitlines() if line.startswith("| S2")]
    assert rows == [
        ["S2_pyramid20", "210", "600", "2.000 (1.000)", "4.000 (4.000)", "0.50", "1.000 (1.000)", "2.00"],
        ["S2_pyramid20", "worst box displacement, m", "0.1", "0.4", "0.1"],
    ]
    result["scaling"] = {"4000": result["scenes"]["S2"]}
    console = Console(record=True, width=200)
    print_report(result, markdown=True, console=console)
    memory = [[cell.strip() for cell in line.strip().strip("|").split("|")]
              for line in console.export_text().splitlines() if line.startswith("| 4000")]
    assert memory[-1] == ["4000", "6.0", "12.0", "3.0"]  # KB per body: rustycs, pymunk, Box2D v3


# ------------------------------------------------------------------------------------- the command


def test_bench_one_scene_json(cli, monkeypatch: pytest.MonkeyPatch):
    monkeypatch.setattr(suite, "SCALING_SIZES", (40, 90))
    done = cli("bench", "--scenes", "S1", "--ticks", "5", "--reps", "1", "--json", "-q")
    assert done.exit_code == 0, done.stderr
    result = json.loads(done.stdout)
    assert result["meta"]["reps"] == 1 and result["meta"]["cores"] >= 1 and result["meta"]["cpu"]
    s1 = result["scenes"]["S1"]
    assert (s1["name"], s1["bodies"], s1["ticks"]) == ("S1_bounce", 5, 5)
    cell = s1["engines"]["rustycs"]
    assert len(cell["ms_per_tick"]) == 1 and cell["median_ms"] == cell["min_ms"] > 0
    assert (cell["sleep"], cell["threads"]) == (False, 1)
    assert result["meta"]["settings"] == {"sleep": False, "threads": 1, "engines": {
        "rustycs": "substeps as the scene's world.precision, sleeping off, single-threaded"}}
    assert s1["ratios"] == {}
    times = result["compile"]
    assert times["errors"] == [] and all(times[k] > 0 for k in ("cold_s", "warm_s", "import_s", "startup_s"))
    for count in ("40", "90"):
        row = result["scaling"][count]
        assert (row["bodies"], row["ticks"]) == (int(count), 5)
        # 5 ticks after release from a grid wider than the circles: nothing touches, nothing escaped
        assert row["engines"]["rustycs"]["quality"] == {"max_overlap": 0.0, "escaped": 0}
        assert 0 < row["engines"]["rustycs"]["median_kb_per_body"] < 100  # its world, not the kernels' 100 MB


@needs_peers
def test_bench_peers_on_the_orbits(cli):
    done = cli("bench", "S6", "--peers", "--ticks", "10", "--reps", "1", "--no-scaling", "--no-compile",
               "--json", "-q")
    assert done.exit_code == 0, done.stderr
    s6 = json.loads(done.stdout)["scenes"]["S6"]
    assert set(s6["ratios"]) == {"pymunk", "pyb2d3"} and all(r > 0 for r in s6["ratios"].values())
    for engine in ("rustycs", "pymunk", "pyb2d3"):
        drift = s6["engines"][engine]["quality"]
        # a sixth of a second of circular orbits: every engine keeps the radii within 2 %
        assert 0 < drift["mean_radius_drift"] <= drift["max_radius_drift"] < 0.02


@needs_peers
def test_bench_sleep_and_threads_reach_every_engine(cli):
    done = cli("bench", "S1", "--peers", "--sleep", "--threads", "2", "--ticks", "5", "--reps", "1",
               "--no-scaling", "--no-compile", "--json", "-q")
    assert done.exit_code == 0, done.stderr
    result = json.loads(done.stdout)
    for engine, cell in result["scenes"]["S1"]["engines"].items():  # as each engine's world reports it
        assert (engine, cell["sleep"], cell["threads"]) == (engine, True, 2)
    settings = result["meta"]["settings"]
    assert (settings["sleep"], settings["threads"], list(settings["engines"])) == (True, 2, [
        "rustycs", "pymunk", "pyb2d3"])
    assert settings["engines"]["rustycs"].endswith("sleeping on (0.5 s at rest), world.threads 2")
    assert "sleeping on (0.5 s at rest), continuous on, 2 workers" in settings["engines"]["pyb2d3"]


@pytest.mark.parametrize("value", ["0", "257", "two"])
def test_bench_threads_out_of_range_is_a_usage_error(cli, value: str):
    done = cli("bench", "S1", "--threads", value, "--no-compile", "--no-scaling")
    assert done.exit_code == 2 and "--threads" in done.stderr and "Traceback" not in done.stderr


def test_bench_peers_missing_is_a_user_error(cli, monkeypatch: pytest.MonkeyPatch):
    monkeypatch.setattr(peers, "missing", lambda: ["pyb2d3"])
    done = cli("bench", "--peers", "--scenes", "S1")
    assert done.exit_code == 2 and "pip install 'rustycs[bench]'" in done.stderr and "pyb2d3" in done.stderr


def test_bench_unknown_scene(cli):
    done = cli("bench", "--scenes", "S1,S9", "--no-compile", "--no-scaling")
    assert done.exit_code == 2 and "unknown bench scene 'S9'" in done.stderr


def test_recording_worker_runs_the_scene(five_body_scene: Path, compiled_engine: None):
    from rustycs_cli.bench.worker import record

    got = record(str(five_body_scene), 7, sleep=True, threads=2)  # as `rustycs bench --sleep --threads 2`
    assert (got["scene"], got["ticks"]) == ("five", 7)
    assert got["step_seconds"] > 0 and got["seconds"] >= 0 and got["peak_memory_mb"] > 1


def test_scene_ids_in_any_case_and_compounds_only_when_named():
    from rustycs_cli.bench.scenes import DEFAULT_IDS, default_scene_dir, find_scenes, parse_ids

    assert parse_ids(["s2,COMPOUNDS", "S2"]) == ["S2", "compounds"]
    assert parse_ids([]) == list(DEFAULT_IDS) == ["S1", "S2", "S3", "S4", "S5", "S6"]
    found = find_scenes(default_scene_dir(), ["compounds", "S1"])
    assert [path.name for path in found.values()] == ["compounds.yaml", "S1_bounce.yaml"]
    assert list(found) == ["compounds", "S1"]


@pytest.mark.parametrize("shape, what", [
    ("{type: chain, points: [[0, 0], [1, 0], [2, 1]]}", "a chain"),
    ("{type: circle, radius: 0.5, sensor: true}", "a sensor"),
    ("{type: polygon, vertices: [[0, 0], [2, 0], [1, 0.5], [1, 2]]}", "a concave or > 8-vertex polygon"),
])
def test_shapes_the_peers_would_build_otherwise_are_refused(shape: str, what: str):
    text = f"name: odd\nbodies:\n  - {{name: odd, type: static, shape: {shape}, position: [0, 0]}}\n"
    scene = load_scene_text(text, "odd.yaml").scene
    with pytest.raises(UserError) as raised:
        describe(scene, build_world(scene))
    assert raised.value.messages == [f"odd: body 'odd' has {what}; the peer engines are given only circle, "
                                     "aabb, obb, polygon, capsule and segment shapes"]
