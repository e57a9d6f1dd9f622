"""The HDF5 trajectory layout, read back with plain h5py against trajectory-format.md, and open_trajectory."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

from rustycs_cli.errors import UserError
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


def make_world():
    """Every shape and body type, a global and a local attractor, bounds, gravity; bodies in contact."""
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
    return world


NAMES = ["floor", "ball", "crate", "wedge", "slider"]
MATERIALS = ["stone", "rubber", "default", "default", "default"]
GROUPS = [0, 3, 0, 0, 0]


def write_run(path: Path, contacts: bool = True, compress: bool = False, frames: int = FRAMES):
    """Write `frames` frames of make_world() and return the captured frames (what the file must hold)."""
    world = make_world()
    tracker = SummaryTracker(list(world.body_types))
    captured = []
    with TrajectoryWriter(path, world, names=NAMES, materials=MATERIALS, collision_groups=GROUPS,
                          attractor_names=["well", "far"], author="tester", scene_text="name: t\n",
                          overrides=("world.precision=6", "bodies.ball.material=rubber"),
                          contacts=contacts, compress=compress) as writer:
        for index in range(frames):
            if index:
                world.step(1)
            frame = Frame.capture(world, contacts)
            writer.append(frame)
            tracker.add(frame)
            captured.append(frame)
        summary = tracker.summary(scene="t", scene_sha256="0" * 64, status="complete", seed=0, dt=world.dt,
                                  wall_seconds=1.0, step_seconds=0.5)
        writer.finish({"scene_sha256": "0" * 64, "seed": 0, "rustycs_version": package_version(),
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
        # something moved: the comparison above is not between two constant arrays
        assert not np.array_equal(bodies["position/value"][0], bodies["position/value"][-1])


def test_step_and_time_are_hard_links(written):
    path, _, _ = written
    with h5py.File(path, "r") as f:
        position = f["particles/bodies/position"]
        groups = [f[f"particles/bodies/{name}"]
                  for name in ("velocity", "angle", "angular_velocity", "active")]
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
        assert_str_dataset(bodies["type"], ["static", "dynamic", "dynamic", "dynamic", "kinematic"])
        assert_str_dataset(bodies["shape"], ["aabb", "circle", "obb", "polygon", "aabb"])
        assert_str_dataset(bodies["material"], MATERIALS)
        mass, inertia = bodies["mass"][()], bodies["inertia"][()]
        assert bodies["mass"].dtype == np.float64 and mass.shape == (5,)
        assert np.isinf(mass[[0, 4]]).all() and np.isfinite(mass[1:4]).all()
        assert mass[1] == pytest.approx(np.pi * 0.25**2 * 0.9)  # rubber
        assert np.isinf(inertia[[0, 4]]).all() and np.isfinite(inertia[1:4]).all()
        assert inertia[2] == pytest.approx(mass[2] * (0.5**2 + 0.5**2) / 12)
        # additions for the renderer
        np.testing.assert_array_equal(bodies["radius"][()], [0, 0.25, 0, 0, 0])
        np.testing.assert_array_equal(bodies["vertex_count"][()], [4, 0, 4, 3, 4])
        vertices = bodies["vertices"][()]
        assert vertices.shape == (5, 8, 2)
        assert sorted(map(tuple, vertices[3, :3])) == [(0.0, 0.0), (0.0, 0.6), (0.6, 0.0)]
        assert np.abs(vertices[2, :4]).max() == 0.25 and not vertices[2, 4:].any()
        np.testing.assert_array_equal(bodies["collision_group"][()], GROUPS)


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
        assert 8 <= value.chunks[0] <= 64 and value.chunks[1:] == (5, 2)
        assert value.compression is None


def test_compress_option(tmp_path: Path):
    path = tmp_path / "small.h5"
    write_run(path, contacts=False, compress=True, frames=3)
    with h5py.File(path, "r") as f:
        value = f["particles/bodies/velocity/value"]
        assert value.compression == "gzip" and value.shuffle
        assert value.shape == (3, 5, 2)
        assert "contacts" not in f


def test_written_under_a_temporary_name(tmp_path: Path):
    path = tmp_path / "run.h5"
    world = make_world()
    writer = TrajectoryWriter(path, world, names=NAMES, materials=MATERIALS, collision_groups=GROUPS,
                              attractor_names=["well", "far"], author="x", scene_text="", overrides=(),
                              contacts=False, compress=False)
    writer.append(Frame.capture(world, False))
    assert temporary_path(path).exists() and not path.exists()
    assert temporary_path(path).parent == tmp_path and temporary_path(path).name.startswith(".run.h5.tmp-")
    writer.finish({"status": "complete"}, {"status": "complete"})
    assert path.exists() and not temporary_path(path).exists()
    with open_trajectory(path) as f:
        assert f["particles/bodies/position/value"].shape == (1, 5, 2)


def test_exception_inside_the_writer_leaves_no_file(tmp_path: Path):
    path = tmp_path / "run.h5"
    world = make_world()
    with pytest.raises(RuntimeError), TrajectoryWriter(
            path, world, names=NAMES, materials=MATERIALS, collision_groups=GROUPS,
            attractor_names=["well", "far"], author="x", scene_text="", overrides=(), contacts=False,
            compress=False) as writer:
        writer.append(Frame.capture(world, False))
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
    with TrajectoryWriter(tmp_path / "blocks.h5", world, names=NAMES, materials=MATERIALS,
                          collision_groups=GROUPS, attractor_names=["well", "far"], author="tester",
                          scene_text="name: t\n", contacts=False, compress=False,
                          overrides=("world.precision=6", "bodies.ball.material=rubber")) as writer:
        buffer = world.frame_buffer(64)
        world.capture(buffer)
        writer.append_block(buffer, 1)
        tracker.add_block(buffer, 1)
        for count in (37, 64, 64, 64, 64, 6):
            recorded = world.step(count, record=buffer, every=1)
            writer.append_block(buffer, recorded)
            tracker.add_block(buffer, recorded)
        blocks = tracker.summary(scene="t", scene_sha256="0" * 64, status="complete", seed=0, dt=world.dt,
                                 wall_seconds=1.0, step_seconds=0.5)
        writer.finish({"status": "complete"}, blocks)
    assert blocks == summary
    with h5py.File(tmp_path / "frames.h5") as a, h5py.File(tmp_path / "blocks.h5") as b:
        names = []
        a.visititems(lambda name, item: names.append(name) if isinstance(item, h5py.Dataset) else None)
        series = [name for name in names if name.startswith(("particles/", "observables/"))]
        assert len(series) > 20
        for name in series:
            assert np.array_equal(a[name][()], b[name][()]), name
        assert a["particles/bodies/position/value"].shape[0] == frames == len(one_by_one)
