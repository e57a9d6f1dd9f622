"""The Python side: `rustycs.load_scene` and `rustycs.open_trajectory`, and what `import rustycs` costs."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

import rustycs
from tests.conftest import FIVE_BODIES

NAMES = ["floor", "ball", "crate", "wedge", "slider"]


def _packages(statement: str) -> set[str]:
    """The top-level packages loaded by a fresh interpreter after `statement`."""
    code = f"import sys; {statement}; print(' '.join({{m.split('.')[0] for m in sys.modules}}))"
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return set(result.stdout.split())


def test_import_rustycs_loads_nothing_beyond_numpy_and_numba():
    added = _packages("import rustycs") - _packages("import numpy, numba")
    assert "rustycs" in added and not added & {"rustycs_cli", "pydantic", "h5py", "typer", "rich", "pandas"}
    assert added <= {"rustycs", "glob"}  # (numba itself brings in yaml, for its configuration file)


def test_load_scene_builds_the_world_with_names_and_overrides(five_body_scene):
    overrides = ["bodies.ball.position=[1, 2]", "world.precision=3"]
    world = rustycs.load_scene(five_body_scene, overrides=overrides)
    assert world.body_names.tolist() == NAMES
    assert world.precision == 3 and world.tick_rate == 60.0
    assert world.positions[world.body_index("ball")].tolist() == [1.0, 2.0]
    assert world.body_types.tolist() == ["static", "dynamic", "dynamic", "dynamic", "kinematic"]


def test_load_scene_raises_every_problem_located(tmp_path):
    scene = tmp_path / "bad.yaml"
    scene.write_text(FIVE_BODIES.replace("radius: 0.2", "radius: -0.2").replace("width: 0.5,", "widht: 0.5,"))
    with pytest.raises(rustycs.SceneError) as raised:
        rustycs.load_scene(scene)
    messages = raised.value.messages
    assert len(messages) >= 2 and str(raised.value) == "\n".join(messages)
    assert any(m.startswith(f"{scene}:8:48: ") and "radius" in m for m in messages)  # the ball's radius
    assert any(m.startswith(f"{scene}:9:38: ") and "did you mean 'width'" in m for m in messages)
    with pytest.raises(rustycs.SceneError, match="no such scene file"):
        rustycs.load_scene(tmp_path / "missing.yaml")


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory, compiled_engine: None) -> Path:
    from rustycs_cli.loading import load_scene
    from rustycs_cli.simulation import run_scene

    folder = tmp_path_factory.mktemp("reader")
    scene = folder / "five.yaml"
    scene.write_text(FIVE_BODIES.replace("ticks: 60", "ticks: 30"))
    out = folder / "five.h5"
    run_scene(load_scene(scene), out, quiet=True)
    return out


def test_the_reader_gives_what_h5py_reads(run):
    with rustycs.open_trajectory(run) as trajectory, h5py.File(run, "r") as file:
        assert trajectory.names.tolist() == NAMES and isinstance(trajectory.names[0], str)
        bodies = file["particles/bodies"]
        for ours, path in [(trajectory.positions, "position"), (trajectory.velocities, "velocity"),
                           (trajectory.angles, "angle"), (trajectory.angular_velocities, "angular_velocity"),
                           (trajectory.active, "active"), (trajectory.asleep, "asleep")]:
            theirs = bodies[path]["value"][()]
            assert ours.dtype == theirs.dtype and ours.tobytes() == theirs.tobytes()  # bitwise
        assert trajectory.steps.tolist() == list(range(31))
        assert trajectory.times == pytest.approx(np.arange(31) / 60.0, abs=1e-15)
        energy = file["observables/kinetic_energy/value"][()]
        assert trajectory.observables["kinetic_energy"].tobytes() == energy.tobytes()
        assert trajectory.observables["linear_momentum"].shape == (31, 2)
        blocks = list(trajectory.blocks(frames=8))
        assert [len(b["step"]) for b in blocks] == [8, 8, 8, 7]
        assert np.concatenate([b["position"] for b in blocks]).tobytes() == trajectory.positions.tobytes()
        assert trajectory.summary["status"] == "complete" and trajectory.measures == {}
        assert trajectory.parameters["tick_rate"] == 60.0
        assert trajectory.events["kind"].dtype.kind == "U" and trajectory.joints["name"].shape == (0,)
        assert "name: five" in trajectory.scene and trajectory.overrides == []
        assert trajectory.contacts(30)["point"].shape[1] == 2
        assert trajectory.body_index("crate") == 2


def test_the_reader_refuses_what_is_not_a_trajectory(tmp_path):
    with pytest.raises(FileNotFoundError):
        rustycs.open_trajectory(tmp_path / "none.h5")
    (tmp_path / "text.h5").write_text("hello")
    with pytest.raises(ValueError, match="not an HDF5 file"):
        rustycs.open_trajectory(tmp_path / "text.h5")


def test_long_form_dataframe(run):
    pandas = pytest.importorskip("pandas")
    with rustycs.open_trajectory(run) as trajectory:
        table = trajectory.to_dataframe()
        positions, angular = trajectory.positions, trajectory.angular_velocities
    assert isinstance(table, pandas.DataFrame)
    assert table.columns.tolist() == ["time", "body", "x", "y", "angle", "vx", "vy", "w"]
    assert table.shape == (31 * 5, 8)
    crate = table[table.body == "crate"]
    assert crate.x.to_numpy().tobytes() == positions[:, 2, 0].tobytes()
    assert crate.w.to_numpy().tobytes() == angular[:, 2].tobytes()
    assert table.time.iloc[5] == pytest.approx(1 / 60)


def test_xarray_dataset(run):
    pytest.importorskip("xarray")
    with rustycs.open_trajectory(run) as trajectory:
        data = trajectory.to_xarray()
        positions = trajectory.positions
    assert dict(data.sizes) == {"time": 31, "body": 5}
    assert data["body"].values.tolist() == NAMES
    assert data["y"].sel(body="ball").values.tobytes() == positions[:, 1, 1].tobytes()
    assert data["kinetic_energy"].dims == ("time",) and data["x"].attrs["units"] == "m"


def test_the_inline_player(run):
    with rustycs.open_trajectory(run) as trajectory:
        page = trajectory._repr_html_()
    assert page.startswith('<iframe srcdoc="&lt;!DOCTYPE html&gt;') and page.endswith("</iframe>")
    assert 'id=&quot;rustycs-header&quot;' in page and "&quot;ball&quot;" in page
