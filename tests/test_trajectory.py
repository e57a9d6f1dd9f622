"""The HDF5 trajectory layout, read back with plain h5py against trajectory-format.md, and open_trajectory."""

from __future__ import annotations

import math
from pathlib import Path

import h5py
import numpy as np
import pytest

from rustycs_cli.errors import UserError
from rustycs_cli.shape_table import read_shapes, shape_table, write_shapes
from rustycs_cli.summary import SummaryTracker
from rustycs_cli.trajectory import (
    BLOCK_FRAMES,
    Frame,
    TrajectoryWriter,
    open_trajectory,
    package_version,
    temporary_path,
)

FRAMES = BLOCK_FRAMES + 6  # more than one buffered block
SERIES_UNITS = {"position": "m", "velocity": "m s-1", "angle": "rad", "angular_velocity": "rad s-1"}
OBSERVABLE_SHAPES = {"kinetic_energy": (), "potential_energy": (), "linear_momentum": (2,),
                     "angular_momentum": (), "contact_count": (), "max_penetration": ()}


L_HOOK = [(0, 0), (1, 0), (1, 0.25), (0.25, 0.25), (0.25, 1), (0, 1)]  # concave: split into pieces


def make_world():
    """Every shape kind and body type, bodies of several shapes (with their own material, a sensor, a
    closed chain), a global and a local attractor, bounds, gravity; bodies in contact."""
    import rustycs

    world = rustycs.World(tick_rate=120.0, precision=6, bounds=((-20.0, -20.0), (20.0, 20.0)))
    world.add_force((0.0, -9.81))
    world.add_attractor((5.0, 5.0), mass=10.0, range=2.0, min_distance=0.1)
    world.add_attractor((-50.0, 0.0), mass=1.0)
    world.add_body(rustycs.Box(10.0, 0.5, rotates=False), position=(0.0, -0.25), body_type="static",
                   material="stone")
    world.add_body(rustycs.Circle(radius=0.25), position=(-1.0, 0.24), material="rubber", collision_group=3)
    world.add_body(rustycs.Box(0.5, 0.5), position=(0.0, 0.24), angle=0.2)
    world.add_body(rustycs.Polygon([(0.0, 0.0), (0.6, 0.0), (0.0, 0.6)]), position=(1.5, -0.01))
    world.add_body(rustycs.Box(1.0, 0.2, rotates=False), position=(0.0, 4.0), body_type="kinematic",
                   velocity=(1.0, 0.0))
    cup = [rustycs.Box(2.0, 0.2, offset=(0, -0.9)), rustycs.Box(0.2, 2.0, offset=(-0.9, 0), angle=0.1),
           rustycs.Box(0.2, 2.0, offset=(0.9, 0), material="rubber"), rustycs.Circle(0.5, sensor=True)]
    world.add_body(cup, position=(10.0, 5.0), material="plastic")
    world.add_body([rustycs.Chain([(0, 0), (2, 0), (1, 1)], loop=True), rustycs.Segment([(0, -1), (3, -1)])],
                   position=(-10.0, 5.0), body_type="static")
    world.add_body(rustycs.Polygon(L_HOOK, offset=(0.5, 0.0), angle=0.25), position=(-10.0, 10.0),
                   material="metal")
    world.add_body(rustycs.Capsule(1.0, 0.2), position=(10.0, 10.0), angle=0.5)
    return world


NAMES = ["floor", "ball", "crate", "wedge", "slider", "cup", "track", "hook", "pill"]
MATERIALS = ["stone", "rubber", "default", "default", "default", "plastic", "default", "metal", "default"]
SHAPE_MATERIALS = ["stone", "rubber", "default", "default", "default", "plastic", "plastic", "rubber",
                   "plastic", "default", "default", "metal", "default"]
GROUPS = [0, 3, 0, 0, 0, 0, 0, 0, 0]
N = len(NAMES)


def writer(path: Path, world, *, contacts: bool = False, compress: bool = False) -> TrajectoryWriter:
    """The writer of make_world()'s runs."""
    return TrajectoryWriter(path, world, names=NAMES, materials=MATERIALS, shape_materials=SHAPE_MATERIALS,
                            collision_groups=GROUPS, attractor_names=["well", "far"], author="tester",
                            scene_text="name: t\n", contacts=contacts, compress=compress,
                            overrides=("world.precision=6", "bodies.ball.material=rubber"))


def write_run(path: Path, contacts: bool = True, compress: bool = False, frames: int = FRAMES):
    """Write `frames` frames of make_world() and return the captured frames (what the file must hold)."""
    world = make_world()
    tracker = SummaryTracker(list(world.body_types))
    captured = []
    with writer(path, world, contacts=contacts, compress=compress) as out:
        for index in range(frames):
            if index:
                world.step(1)
            frame = Frame.capture(world, contacts)
            out.append(frame)
            tracker.add(frame)
            captured.append(frame)
        summary = tracker.summary(scene="t", scene_sha256="0" * 64, status="complete", seed=0, dt=world.dt,
                                  wall_seconds=1.0, step_seconds=0.5)
        out.finish({"scene_sha256": "0" * 64, "seed": 0, "rustycs_version": package_version(),
                    "status": "complete", "ticks_completed": frames - 1, "dt": world.dt,
                    "tick_rate": 120.0, "precision": 6, "wall_seconds": 1.0, "step_seconds": 0.5}, summary)
    return captured, summary


@pytest.fixture(scope="module")
def written(tmp_path_factory: pytest.TempPathFactory):
    path = tmp_path_factory.mktemp("layout") / "run.h5"
    captured, summary = write_run(path)
    return path, captured, summary


def text(value) -> str:
    return value.decode() if isinstance(value, bytes) else str(value)


def assert_str_dataset(dataset: h5py.Dataset, expected: list[str]) -> None:
    assert h5py.check_string_dtype(dataset.dtype).encoding == "utf-8"
    assert dataset.shape == (len(expected),)
    assert list(dataset.asstr()[()]) == expected


def test_h5md_header(written):
    path, _, _ = written
    with h5py.File(path, "r") as f:
        assert list(f["h5md"].attrs["version"]) == [1, 1]
        assert text(f["h5md/creator"].attrs["name"]) == "rustycs"
        assert text(f["h5md/creator"].attrs["version"]) == package_version()
        assert text(f["h5md/author"].attrs["name"]) == "tester"
        box = f["particles/bodies/box"].attrs
        assert int(box["dimension"]) == 2
        assert [text(v) for v in box["boundary"]] == ["none", "none"]


def test_time_series_values_dtypes_units(written):
    path, captured, _ = written
    n, t = len(NAMES), len(captured)
    with h5py.File(path, "r") as f:
        bodies = f["particles/bodies"]
        step, time = bodies["position/step"], bodies["position/time"]
        assert step.dtype == np.int64 and step.shape == (t,)
        assert time.dtype == np.float64 and time.shape == (t,)
        np.testing.assert_array_equal(step[()], np.arange(t))
        np.testing.assert_array_equal(time[()], np.arange(t) * (1 / 120.0))
        for name, unit in SERIES_UNITS.items():
            value = bodies[f"{name}/value"]
            assert value.dtype == np.float64
            assert value.shape == ((t, n, 2) if name in ("position", "velocity") else (t, n))
            assert text(value.attrs["unit"]) == unit
            np.testing.assert_array_equal(value[()], np.stack([getattr(fr, name) for fr in captured]))
        active = bodies["active/value"]
        assert active.dtype == np.bool_ and active.shape == (t, n)
        np.testing.assert_array_equal(active[()], np.stack([fr.active for fr in captured]))
        asleep = bodies["asleep/value"]  # nothing sleeps here: tests/test_run_sleep.py has runs that do
        assert asleep.dtype == np.bool_ and asleep.shape == (t, n) and not asleep[()].any()
        # something moved: the comparison above is not between two constant arrays
        assert not np.array_equal(bodies["position/value"][0], bodies["position/value"][-1])


def test_step_and_time_are_hard_links(written):
    path, _, _ = written
    with h5py.File(path, "r") as f:
        position = f["particles/bodies/position"]
        groups = [f[f"particles/bodies/{name}"]
                  for name in ("velocity", "angle", "angular_velocity", "active", "asleep")]
        groups += [f[f"observables/{name}"] for name in OBSERVABLE_SHAPES]
        for group in groups:
            for key in ("step", "time"):
                assert isinstance(group.get(key, getlink=True), h5py.HardLink)
                assert group[key] == position[key], f"{group.name}/{key} is not position's"
        assert position["step"] != position["time"]


def test_body_tables(written):
    path, _, _ = written
    with h5py.File(path, "r") as f:
        bodies = f["particles/bodies"]
        assert_str_dataset(bodies["name"], NAMES)
        assert_str_dataset(bodies["type"], ["static", "dynamic", "dynamic", "dynamic", "kinematic", "dynamic",
                                            "static", "dynamic", "dynamic"])
        assert_str_dataset(bodies["shape"], ["aabb", "circle", "obb", "polygon", "aabb", "compound",
                                             "compound", "polygon", "capsule"])
        assert_str_dataset(bodies["material"], MATERIALS)
        mass, inertia = bodies["mass"][()], bodies["inertia"][()]
        assert bodies["mass"].dtype == np.float64 and mass.shape == (N,)
        assert np.isinf(mass[[0, 4, 6]]).all() and np.isfinite(mass[[1, 2, 3, 5, 7, 8]]).all()
        assert mass[1] == pytest.approx(np.pi * 0.25**2 * 0.9)  # rubber
        assert mass[5] == pytest.approx(0.4 * (1.2 + 1.2 + 0.9))  # plastic boxes and a rubber one, no sensor
        assert np.isinf(inertia[[0, 4, 6]]).all() and np.isfinite(inertia[[1, 2, 3, 5, 7, 8]]).all()
        assert inertia[2] == pytest.approx(mass[2] * (0.5**2 + 0.5**2) / 12)
        spawn = bodies["spawn_tick"]
        assert spawn.dtype == np.int64 and spawn.shape == (N,) and not spawn[()].any()
        # additions
        center = bodies["local_center"]
        assert center.dtype == np.float64 and center.shape == (N, 2) and center.attrs["unit"] == "m"
        np.testing.assert_allclose(center[3], [0.2, 0.2])  # the wedge's centroid
        np.testing.assert_allclose(center[8], [0, 0], atol=1e-15)
        assert center[5, 1] < -0.3  # the cup's bottom is heavier than its open top
        np.testing.assert_array_equal(bodies["collision_group"][()], GROUPS)
        assert "radius" not in bodies and "vertices" not in bodies  # per body: replaced by /shapes


SHAPE_TYPES = ["aabb", "circle", "obb", "polygon", "aabb", "obb", "obb", "obb", "circle", "chain", "segment",
               "polygon", "capsule"]


def test_shapes_group_per_the_spec(written):
    """/shapes: one row per shape as given (a concave polygon is one row), dtypes and padding as the
    spec says, and our `loop`."""
    path, _, _ = written
    s = len(SHAPE_TYPES)
    with h5py.File(path, "r") as f:
        shapes = f["shapes"]
        for name, dtype, shape in (("body", np.int32, (s,)), ("offset", np.float64, (s, 2)),
                                   ("angle", np.float64, (s,)), ("radius", np.float64, (s,)),
                                   ("length", np.float64, (s,)), ("vertex_count", np.int32, (s,)),
                                   ("vertices", np.float64, (s, 6, 2)), ("sensor", np.bool_, (s,)),
                                   ("loop", np.bool_, (s,))):
            assert shapes[name].dtype == dtype and shapes[name].shape == shape, name
        assert_str_dataset(shapes["type"], SHAPE_TYPES)
        assert_str_dataset(shapes["material"], SHAPE_MATERIALS)
        np.testing.assert_array_equal(shapes["body"][()], [0, 1, 2, 3, 4, 5, 5, 5, 5, 6, 6, 7, 8])
        np.testing.assert_array_equal(shapes["vertex_count"][()], [4, 0, 4, 3, 4, 4, 4, 4, 0, 3, 2, 6, 0])
        np.testing.assert_array_equal(shapes["radius"][()], [0, 0.25] + [0] * 6 + [0.5, 0, 0, 0, 0.2])
        np.testing.assert_array_equal(shapes["length"][()], [0] * 12 + [1.0])
        np.testing.assert_array_equal(shapes["offset"][5:9], [[0, -0.9], [-0.9, 0], [0.9, 0], [0, 0]])
        np.testing.assert_array_equal(shapes["offset"][11], [0.5, 0])
        np.testing.assert_array_equal(shapes["angle"][()], [0] * 6 + [0.1] + [0] * 4 + [0.25, 0])
        np.testing.assert_array_equal(shapes["sensor"][()], [False] * 8 + [True] + [False] * 4)
        np.testing.assert_array_equal(shapes["loop"][()], [False] * 9 + [True] + [False] * 3)
        vertices = shapes["vertices"][()]
        np.testing.assert_array_equal(vertices[11], L_HOOK)  # as written, in the shape's frame
        np.testing.assert_array_equal(vertices[0, :4], [[-5, -0.25], [5, -0.25], [5, 0.25], [-5, 0.25]])
        np.testing.assert_array_equal(vertices[9, :3], [[0, 0], [2, 0], [1, 1]])
        assert not vertices[9, 3:].any() and not vertices[1].any()  # zero-padded
        for name, unit in (("offset", "m"), ("angle", "rad"), ("radius", "m"), ("length", "m"),
                           ("vertices", "m")):
            assert shapes[name].attrs["unit"] == unit


def test_joints_and_events_exist_with_zero_rows(written):
    path, captured, _ = written
    t = len(captured)
    with h5py.File(path, "r") as f:
        joints, events = f["joints"], f["events"]
        for name in ("name", "type"):
            assert h5py.check_string_dtype(joints[name].dtype) and joints[name].shape == (0,), name
        for name in ("body_a", "body_b"):
            assert joints[name].dtype == np.int32 and joints[name].shape == (0,), name
        for name, dtype, shape in (("reaction_force", np.float64, (t, 0, 2)),
                                   ("reaction_torque", np.float64, (t, 0)), ("active", np.bool_, (t, 0))):
            group = joints[name]
            assert group["value"].dtype == dtype and group["value"].shape == shape, name
            for key in ("step", "time"):
                assert group[key] == f["particles/bodies/position"][key]
        for name, dtype, shape in (("tick", np.int64, (0,)), ("time", np.float64, (0,)),
                                   ("body_a", np.int32, (0,)), ("body_b", np.int32, (0,)),
                                   ("point", np.float64, (0, 2)), ("speed", np.float64, (0,))):
            assert events[name].dtype == dtype and events[name].shape == shape, name
        assert h5py.check_string_dtype(events["kind"].dtype) and events["kind"].shape == (0,)


def test_the_shape_table_reads_back_as_written(tmp_path: Path):
    world = make_world()
    path = tmp_path / "shapes.h5"
    with writer(path, world) as out:
        out.append(Frame.capture(world, False))
        out.finish({"status": "complete"}, {"status": "complete"})
    expected = shape_table(world, SHAPE_MATERIALS)
    with h5py.File(path, "r") as f:
        got = read_shapes(f)
    assert got.type == expected.type == SHAPE_TYPES and got.material == expected.material
    for name in ("body", "offset", "angle", "radius", "length", "loop", "sensor", "vertex_count"):
        np.testing.assert_array_equal(getattr(got, name), getattr(expected, name), err_msg=name)
    assert all(np.array_equal(a, b) for a, b in zip(got.points, expected.points, strict=True))


def test_a_long_chain_pads_every_row_but_stores_only_its_own_chunks(tmp_path: Path):
    """One 4096-point chain among 300 triangles: V = 4096, but the padding of the triangles' rows is not
    written (chunks never written read as 0), so the file stays small; every row reads back."""
    import rustycs

    world = rustycs.World()
    chain = [(0.01 * k, math.sin(0.01 * k)) for k in range(4096)]
    world.add_body(rustycs.Chain(chain), body_type="static")
    for k in range(300):
        world.add_body(rustycs.Polygon([(0, 0), (1, 0), (0, 1 + k / 300)]), position=(2 * k, 5))
    shapes = shape_table(world, ["default"] * 301)
    path = tmp_path / "long.h5"
    with h5py.File(path, "w") as f:
        write_shapes(f, shapes)
    padded = 301 * 4096 * 2 * 8
    assert path.stat().st_size < padded / 20
    with h5py.File(path, "r") as f:
        assert f["shapes/vertices"].shape == (301, 4096, 2)
        assert not f["shapes/vertices"][1:, 3:].any()
        got = read_shapes(f)
    np.testing.assert_array_equal(got.points[0], chain)
    np.testing.assert_array_equal(got.points[300], [(0, 0), (1, 0), (0, 1 + 299 / 300)])


def test_world_additions(written):
    path, _, _ = written
    with h5py.File(path, "r") as f:
        attractors = f["world/attractors"]
        assert_str_dataset(attractors["name"], ["well", "far"])
        np.testing.assert_array_equal(attractors["position"][()], [[5, 5], [-50, 0]])
        np.testing.assert_array_equal(attractors["mass"][()], [10, 1])
        np.testing.assert_array_equal(attractors["range"][()], [2, np.inf])
        np.testing.assert_array_equal(attractors["min_distance"][()], [0.1, 0.01])
        np.testing.assert_array_equal(f["world/bounds"][()], [[-20, -20], [20, 20]])


def test_observables(written):
    path, captured, _ = written
    with h5py.File(path, "r") as f:
        for name, shape in OBSERVABLE_SHAPES.items():
            value = f[f"observables/{name}/value"]
            assert value.shape == (len(captured), *shape)
            assert value.dtype == (np.int64 if name == "contact_count" else np.float64)
            np.testing.assert_array_equal(value[()], [np.asarray(fr.observables[name]) for fr in captured])
        assert f["observables/contact_count/value"][1:].max() > 0  # the bodies rest on the floor


def test_contacts(written):
    path, captured, _ = written
    with h5py.File(path, "r") as f:
        contacts = f["contacts"]
        offset = contacts["offset"][()]
        assert contacts["offset"].dtype == np.int64 and offset.shape == (len(captured) + 1,)
        total = offset[-1]
        assert offset[0] == 0 and total > 0
        np.testing.assert_array_equal(np.diff(offset), f["observables/contact_count/value"][()])
        for name, dtype, shape in (("body_a", np.int32, (total,)), ("body_b", np.int32, (total,)),
                                   ("point", np.float64, (total, 2)), ("normal", np.float64, (total, 2)),
                                   ("depth", np.float64, (total,)), ("normal_impulse", np.float64, (total,))):
            assert contacts[name].dtype == dtype and contacts[name].shape == shape, name
        np.testing.assert_allclose(np.linalg.norm(contacts["normal"][()], axis=1), 1.0)
        last = len(captured) - 1
        rows = slice(offset[last], offset[last + 1])
        for name in ("body_a", "body_b", "point", "normal", "depth", "normal_impulse"):
            np.testing.assert_array_equal(contacts[name][rows], captured[last].contacts[name])


def test_parameters_scene_overrides_summary(written):
    path, _, summary = written
    with h5py.File(path, "r") as f:
        parameters = f["parameters"]
        for key in ("scene_sha256", "seed", "rustycs_version", "status", "ticks_completed", "dt",
                    "tick_rate", "precision", "wall_seconds", "step_seconds"):
            assert key in parameters.attrs, key
        assert text(parameters.attrs["status"]) == "complete"
        assert parameters.attrs["ticks_completed"] == FRAMES - 1
        assert parameters["scene"].asstr()[()] == "name: t\n"
        assert_str_dataset(parameters["overrides"], ["world.precision=6", "bodies.ball.material=rubber"])
        stored = dict(parameters["summary"].attrs)
        assert list(stored) == [k for k, v in summary.items() if v is not None]  # order kept, nulls left out
        assert stored["total_contact_points"] == summary["total_contact_points"] > 0
        assert text(stored["status"]) == "complete"


def test_chunked_along_time_uncompressed(written):
    path, _, _ = written
    with h5py.File(path, "r") as f:
        value = f["particles/bodies/position/value"]
        assert value.maxshape[0] is None
        assert 8 <= value.chunks[0] <= 64 and value.chunks[1:] == (N, 2)
        assert value.compression is None


def test_compress_option(tmp_path: Path):
    path = tmp_path / "small.h5"
    write_run(path, contacts=False, compress=True, frames=3)
    with h5py.File(path, "r") as f:
        value = f["particles/bodies/velocity/value"]
        assert value.compression == "gzip" and value.shuffle
        assert value.shape == (3, N, 2)
        assert "contacts" not in f


def test_written_under_a_temporary_name(tmp_path: Path):
    path = tmp_path / "run.h5"
    world = make_world()
    out = writer(path, world)
    out.append(Frame.capture(world, False))
    assert temporary_path(path).exists() and not path.exists()
    assert temporary_path(path).parent == tmp_path and temporary_path(path).name.startswith(".run.h5.tmp-")
    out.finish({"status": "complete"}, {"status": "complete"})
    assert path.exists() and not temporary_path(path).exists()
    with open_trajectory(path) as f:
        assert f["particles/bodies/position/value"].shape == (1, N, 2)


def test_exception_inside_the_writer_leaves_no_file(tmp_path: Path):
    path = tmp_path / "run.h5"
    world = make_world()
    with pytest.raises(RuntimeError), writer(path, world) as out:
        out.append(Frame.capture(world, False))
        raise RuntimeError("boom")
    assert list(tmp_path.iterdir()) == []


@pytest.fixture
def bad_files(tmp_path: Path) -> dict[str, Path]:
    files = {"missing": tmp_path / "missing.h5", "folder": tmp_path}
    files["not_hdf5"] = tmp_path / "notes.h5"
    files["not_hdf5"].write_text("name: not a trajectory\n")
    files["foreign"] = tmp_path / "foreign.h5"
    with h5py.File(files["foreign"], "w") as f:
        f["data"] = np.arange(3)
    files["other_creator"] = tmp_path / "other.h5"
    with h5py.File(files["other_creator"], "w") as f:
        f.create_group("h5md/creator").attrs["name"] = "lammps"
        f["particles/bodies/position/value"] = np.zeros((1, 1, 2))
    files["no_position"] = tmp_path / "empty.h5"
    with h5py.File(files["no_position"], "w") as f:
        f.create_group("h5md/creator").attrs["name"] = "rustycs"
    good = tmp_path / "good.h5"
    write_run(good, contacts=False, frames=2)
    files["truncated"] = tmp_path / "truncated.h5"
    files["truncated"].write_bytes(good.read_bytes()[:2000])
    return files


@pytest.mark.parametrize("kind, words", [
    ("missing", "no such file"), ("folder", "folder"), ("not_hdf5", "not an HDF5 file"),
    ("foreign", "no /h5md"), ("other_creator", "'lammps'"), ("no_position", "missing /particles"),
    ("truncated", "corrupt"),
])
def test_open_trajectory_rejects(bad_files: dict[str, Path], kind: str, words: str):
    with pytest.raises(UserError) as caught:
        open_trajectory(bad_files[kind])
    (message,) = caught.value.messages
    assert message.startswith(f"{bad_files[kind]}: ") and words in message
    assert caught.value.exit_code == 2


def test_blocks_of_frames_are_written_and_summarised_as_frames_one_by_one(tmp_path: Path):
    """`rustycs run` hands the writer and the summary whole blocks of the engine's frame buffer."""
    frames = 300  # blocks of uneven sizes; whole chunks written as they are, then the rest
    one_by_one, summary = write_run(tmp_path / "frames.h5", contacts=False, frames=frames)
    world = make_world()
    tracker = SummaryTracker(list(world.body_types))
    with writer(tmp_path / "blocks.h5", world) as out:
        buffer = world.frame_buffer(64)
        world.capture(buffer)
        out.append_block(buffer, 1)
        tracker.add_block(buffer, 1)
        for count in (37, 64, 64, 64, 64, 6):
            recorded = world.step(count, record=buffer, every=1)
            out.append_block(buffer, recorded)
            tracker.add_block(buffer, recorded)
        blocks = tracker.summary(scene="t", scene_sha256="0" * 64, status="complete", seed=0, dt=world.dt,
                                 wall_seconds=1.0, step_seconds=0.5)
        out.finish({"status": "complete"}, blocks)
    assert blocks == summary
    with h5py.File(tmp_path / "frames.h5") as a, h5py.File(tmp_path / "blocks.h5") as b:
        names = []
        a.visititems(lambda name, item: names.append(name) if isinstance(item, h5py.Dataset) else None)
        series = [name for name in names if name.startswith(("particles/", "observables/", "joints/"))]
        assert len(series) > 20
        for name in series:
            assert np.array_equal(a[name][()], b[name][()]), name
        assert a["particles/bodies/position/value"].shape[0] == frames == len(one_by_one)
