"""`rustycs plot`: observables of several real runs overlaid on one figure; bad input gives exit 2."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest
from conftest import FIVE_BODIES
from matplotlib.colors import to_rgb
from PIL import Image

from rustycs_cli.render.plot import labels_for


def color_pixels(image: np.ndarray, color: str) -> int:
    """How many pixels have (nearly) exactly this matplotlib colour."""
    rgb = np.array([round(255 * c) for c in to_rgb(color)])
    return int((np.abs(image[..., :3].astype(int) - rgb).max(axis=-1) <= 2).sum())


def test_plot_overlays_several_runs(cli, run_scene, tmp_path: Path):
    bouncy = run_scene(FIVE_BODIES)
    dull = run_scene(FIVE_BODIES, "-s", "materials.rubber.restitution=0.1")
    sweep = tmp_path / "sweep"
    sweep.mkdir()
    runs = [sweep / "bouncy.h5", sweep / "dull.h5"]
    runs[0].write_bytes(bouncy.read_bytes())
    runs[1].write_bytes(dull.read_bytes())
    out = tmp_path / "plot.png"
    result = cli("plot", *runs, "-o", out)
    assert result.exit_code == 0, result.stderr
    assert "2 runs" in result.stdout
    image = np.asarray(Image.open(out).convert("RGB"))
    assert image.shape[1] >= 1000 and image.shape[0] >= 700
    # one colour per run: the second run hides the first where they agree, so fewer C0 pixels show,
    # but far more than its legend patch (~60 pixels); no third colour
    assert color_pixels(image, "C0") > 300 and color_pixels(image, "C1") > 2000
    assert color_pixels(image, "C2") == 0
    single = tmp_path / "single.png"
    assert cli("plot", runs[0], "-o", single).exit_code == 0
    assert color_pixels(np.asarray(Image.open(single).convert("RGB")), "C1") == 0


def test_labels_are_stems_unless_ambiguous():
    assert labels_for([Path("a/x.h5"), Path("b/y.h5")], [[], []]) == (["x", "y"], "runs")
    assert labels_for([Path("a/x.h5"), Path("b/x.h5")], [[], []]) == (["a/x.h5", "b/x.h5"], "runs")


def test_sweep_runs_are_labelled_by_the_values_they_differ_in():
    fixed = "world.precision=4"
    overrides = [[fixed, "materials.rubber.restitution=0.1", "bodies.ball.position=[0,1]"],
                 [fixed, "materials.rubber.restitution=0.9", "bodies.ball.position=[0,1]"]]
    paths = [Path(f"out/long-scene-name-{i}-materials.rubber.restitution=0.1.h5") for i in range(2)]
    assert labels_for(paths, overrides) == (["restitution=0.1", "restitution=0.9"],
                                            "runs: materials.rubber.restitution")
    clash = [["a.x=1", "b.x=2"], ["a.x=3", "b.x=2"], ["a.x=3", "b.x=4"]]
    assert labels_for(paths + paths[:1], clash)[0] == ["a.x=1, b.x=2", "a.x=3, b.x=2", "a.x=3, b.x=4"]


def test_a_legend_of_many_long_labels_fits_in_the_figure():
    from rustycs_cli.render.plot import OBSERVABLES, Series, _figure

    time = np.linspace(0, 1, 5)
    runs = [Series(f"restitution={k / 10:.1f}, friction={k / 20:.2f}, generators.rain.count={100 * k}",
                   {name: time for name in OBSERVABLES},
                   {name: np.zeros((5, 2)) if name == "linear_momentum" else time for name in OBSERVABLES})
            for k in range(12)]
    figure = _figure(runs, "many runs", "runs")
    figure.canvas.draw()
    legend = figure.legends[0].get_window_extent()
    assert legend.x0 >= 0 and legend.y0 >= 0 and legend.x1 <= figure.bbox.x1 and legend.y1 <= figure.bbox.y1


@pytest.mark.parametrize("kind", ["missing", "foreign", "text"])
def test_missing_or_foreign_file_exits_2(cli, run_scene, tmp_path: Path, kind: str):
    bad = tmp_path / f"{kind}.h5"
    if kind == "foreign":
        with h5py.File(bad, "w") as f:
            f["x"] = np.arange(3)
    elif kind == "text":
        bad.write_text("hello")
    out = tmp_path / "plot.png"
    result = cli("plot", run_scene(FIVE_BODIES), bad, "-o", out)
    assert result.exit_code == 2 and str(bad) in result.stderr and "Traceback" not in result.stderr
    assert not out.exists()


def test_unknown_plot_type_exits_2(cli, run_scene, tmp_path: Path):
    result = cli("plot", run_scene(FIVE_BODIES), "-o", tmp_path / "plot.bmp")
    assert result.exit_code == 2 and ".png, .pdf, .svg" in result.stderr
