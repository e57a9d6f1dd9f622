"""`rustycs render` to PNG, GIF and MP4 on real trajectories from `rustycs run`; bad input gives exit 2."""

from __future__ import annotations

import math
from pathlib import Path

import h5py
import numpy as np
import pytest
from PIL import Image

from rustycs_cli.render.colors import (
    BACKGROUND,
    HITBOX,
    MATERIAL_COLORS,
    VELOCITY,
    asleep_color,
    material_color,
)
from rustycs_cli.render.frames import iter_frames

SCENE = """\
name: render-scene
world: {tick_rate: 60, ticks: 30, precision: 8, bounds: {min: [-20, -20], max: [20, 20]}}
forces:
  - {name: gravity, acceleration: [0, -9.81]}
attractors:
  - {name: lamp, position: [3, 3], mass: 1, range: 1}
materials:
  ice: {density: 0.9, restitution: 0.05, friction: 0.02}
bodies:
  - {name: floor, type: static, shape: {type: aabb, width: 8, height: 0.5}, position: [0, -0.25],
     material: stone}
  - {name: ball, shape: {type: circle, radius: 0.3}, position: [-2, 1.5], material: rubber}
  - {name: crate, shape: {type: obb, width: 0.6, height: 0.6}, position: [0, 0.31], angle: 0.1,
     material: metal}
  - {name: wedge, shape: {type: polygon, vertices: [[0, 0], [0.6, 0], [0, 0.6]]}, position: [2, 0.01],
     material: plastic}
  - {name: puck, shape: {type: circle, radius: 0.2}, position: [1, 2], velocity: [1, 0], material: ice}
output: {every: 1, contacts: true}
"""
RUBBER = MATERIAL_COLORS["rubber"]
VIEW = "-4,-1,4,5"  # with --size 800x600: exactly 100 px per metre, pixel = (100 (x + 4), 100 (5 - y))


@pytest.fixture(scope="module")
def trajectory(run_scene) -> Path:
    return run_scene(SCENE)


def pixel(
    x: float, y: float, box: tuple[float, ...] = (-4, -1, 4, 5), scale: float = 100.0
) -> tuple[int, int]:
    """The image pixel that contains world point (x, y) for a view whose top-left corner is (xmin, ymax)."""
    return math.floor((x - box[0]) * scale), math.floor((box[3] - y) * scale)


def disk_samples(x: float, y: float, radius: float) -> list[tuple[float, float]]:
    """Points at half the radius around a centre, in 8 directions (a spoke covers at most one of them)."""
    return [
        (x + radius / 2 * math.cos(k * math.pi / 4), y + radius / 2 * math.sin(k * math.pi / 4))
        for k in range(8)
    ]


def body_position(path: Path, name: str, frame: int) -> np.ndarray:
    with h5py.File(path, "r") as f:
        index = list(f["particles/bodies/name"].asstr()[()]).index(name)
        return f["particles/bodies/position/value"][frame, index]


def test_png_colours_at_projected_positions(cli, trajectory: Path, tmp_path: Path):
    out = tmp_path / "first.png"
    result = cli("render", trajectory, "-o", out, "--tick", "0", "--view", VIEW, "--size", "800x600")
    assert result.exit_code == 0, result.stderr
    assert "view -4,-1,4,5" in result.stdout
    image = Image.open(out).convert("RGB")
    assert image.size == (800, 600)
    # the rubber ball at (-2, 1.5), +y up: red all around its centre, background just outside it
    reds = [image.getpixel(pixel(x, y)) for x, y in disk_samples(-2, 1.5, 0.3)]
    assert sum(color == RUBBER for color in reds) >= 7, reds
    assert image.getpixel(pixel(-2 - 0.45, 1.5)) == BACKGROUND
    assert image.getpixel(pixel(-2 + 0.45, 1.5)) == BACKGROUND
    # the crate is metal, the wedge plastic (near its centroid (0.2, 0.2)), the puck the hash colour of "ice"
    assert image.getpixel(pixel(0, 0.31)) == MATERIAL_COLORS["metal"]
    assert image.getpixel(pixel(2.2, 0.21)) == MATERIAL_COLORS["plastic"]
    assert image.getpixel(pixel(1.0, 1.9)) == material_color("ice")
    # the static floor is outlined, not filled
    assert image.getpixel(pixel(1.5, -0.25)) == BACKGROUND
    column = [image.getpixel((pixel(1.5, 0)[0], row)) for row in range(495, 505)]
    assert MATERIAL_COLORS["stone"] in column


FALL_OFF = """\
name: fall-off
world: {tick_rate: 60, ticks: 240, precision: 2%s}
forces:
  - {name: gravity, acceleration: [0, -9.81]}
bodies:
  - {name: floor, type: static, shape: {type: aabb, width: 6, height: 0.5}, position: [0, -0.25]}
  - {name: stays, shape: {type: circle, radius: 0.3}, position: [-1, 0.3]}
  - {name: falls, shape: {type: circle, radius: 0.3}, position: [4, 1]}
"""


@pytest.mark.parametrize("bounds", ["", ", bounds: {min: [-30, -30], max: [30, 30]}"])
def test_the_default_view_fits_the_bodies_still_in_the_world(cli, run_scene, tmp_path: Path, bounds: str):
    # `falls` misses the floor and falls 78 m in 4 s: out of the bounds, or far below the scene as placed
    out = tmp_path / "view.png"
    result = cli("render", run_scene(FALL_OFF % bounds), "-o", out, "--size", "800x600")
    assert result.exit_code == 0, result.stderr
    xmin, ymin, xmax, ymax = (float(v) for v in result.stdout.split("view ")[1].split(",")[:4])
    assert xmin < -3 and xmax > 4.3 and ymin < -0.5 and ymax > 1.3  # the floor and both starts
    assert xmax - xmin < 12  # not stretched down to where `falls` ended


def test_png_default_is_last_tick_in_the_fitted_view(cli, trajectory: Path, tmp_path: Path):
    out = tmp_path / "last.png"
    result = cli("render", trajectory, "-o", out, "--size", "640x480")
    assert result.exit_code == 0, result.stderr
    box = tuple(float(v) for v in result.stdout.split("view ")[1].split(",")[:4])
    scale = 640 / (box[2] - box[0])
    assert scale == pytest.approx(480 / (box[3] - box[1]))  # same scale on both axes
    assert box[0] < -4 and box[2] > 4 and box[1] < -0.5 and box[3] > 3  # floor, bodies and lamp fitted
    position = body_position(trajectory, "ball", -1)
    assert position[1] < 1.4  # it fell: the last frame is not the first
    image = Image.open(out).convert("RGB")
    reds = [image.getpixel(pixel(x, y, box, scale)) for x, y in disk_samples(*position, 0.3)]
    assert sum(color == RUBBER for color in reds) >= 7, reds


def test_overlays_add_hitboxes_velocities_and_names(cli, trajectory: Path, tmp_path: Path):
    plain, marked, named = tmp_path / "plain.png", tmp_path / "marked.png", tmp_path / "named.png"
    assert cli("render", trajectory, "-o", plain, "--view", VIEW).exit_code == 0
    result = cli(
        "render", trajectory, "-o", marked, "--view", VIEW, "--hitboxes", "--contacts", "--velocities"
    )
    assert result.exit_code == 0, result.stderr
    assert cli("render", trajectory, "-o", named, "--view", VIEW, "--names").exit_code == 0

    def count(path: Path, color: tuple[int, int, int]) -> int:
        pixels = np.asarray(Image.open(path).convert("RGB")).reshape(-1, 3)
        return int((pixels == color).all(axis=1).sum())

    assert count(plain, HITBOX) == 0 and count(plain, VELOCITY) == 0
    assert count(marked, HITBOX) > 500  # five boxes and the contact dots
    assert count(marked, VELOCITY) > 20  # the falling bodies' arrows
    assert not np.array_equal(np.asarray(Image.open(plain)), np.asarray(Image.open(named)))


def test_gif_has_one_frame_per_selected_recorded_frame(cli, trajectory: Path, tmp_path: Path):
    out = tmp_path / "run.gif"
    result = cli("render", trajectory, "-o", out, "--every", "3", "--size", "320x240")
    assert result.exit_code == 0, result.stderr
    with Image.open(out) as gif:
        assert gif.n_frames == 11  # frames 0, 3, ..., 30 of 31 recorded
        assert gif.size == (320, 240)
        assert gif.info["duration"] == pytest.approx(1000 / 30, abs=5)  # GIF keeps centiseconds
    # by default the stride plays in real time: 60 recorded frames per second at 30 fps -> every 2nd
    default = tmp_path / "default.gif"
    assert cli("render", trajectory, "-o", default, "--size", "160x120").exit_code == 0
    with Image.open(default) as gif:
        assert gif.n_frames == 16


def test_mp4_decodes_to_the_expected_frames(cli, trajectory: Path, tmp_path: Path):
    import imageio_ffmpeg

    out = tmp_path / "run.mp4"
    result = cli("render", trajectory, "-o", out, "--every", "2", "--size", "321x241", "--fps", "24")
    assert result.exit_code == 0, result.stderr
    reader = imageio_ffmpeg.read_frames(str(out))
    meta = next(reader)
    assert meta["size"] == (322, 242)  # rounded up to even sizes for H.264
    assert meta["fps"] == pytest.approx(24)
    assert sum(1 for _ in reader) == 16


def test_frames_read_in_blocks_match_the_file(trajectory: Path):
    """Strided, block-wise reading returns each selected frame with exactly its own contact rows."""
    with h5py.File(trajectory, "r") as f:
        offset = f["contacts/offset"][()]
        frames = list(iter_frames(f, range(1, 31, 4), with_contacts=True))
        assert [frame.index for frame in frames] == list(range(1, 31, 4))
        for frame in frames:
            assert frame.step == f["particles/bodies/position/step"][frame.index]
            np.testing.assert_array_equal(frame.position, f["particles/bodies/position/value"][frame.index])
            np.testing.assert_array_equal(frame.angle, f["particles/bodies/angle/value"][frame.index])
            rows = slice(offset[frame.index], offset[frame.index + 1])
            np.testing.assert_array_equal(frame.contacts.point, f["contacts/point"][rows])
            np.testing.assert_array_equal(frame.contacts.normal, f["contacts/normal"][rows])
        assert sum(len(frame.contacts.depth) for frame in frames) > 0


def test_bodies_asleep_are_drawn_paler(cli, run_scene, tmp_path: Path):
    """NAP's plastic crate at (-1, 0.3) sleeps from tick NAP_SLEEPS until the rubber ball lands on it."""
    from conftest import NAP, NAP_SLEEPS, NAP_WAKES

    nap = run_scene(NAP)

    def crate_and_ball(tick: int) -> tuple[tuple[int, int, int], tuple[int, int, int]]:
        out = tmp_path / f"tick-{tick}.png"
        result = cli("render", nap, "-o", out, "--tick", str(tick), "--view", VIEW, "--size", "800x600")
        assert result.exit_code == 0, result.stderr
        image = Image.open(out).convert("RGB")
        ball = body_position(nap, "ball", tick)
        return image.getpixel(pixel(-1.15, 0.3)), image.getpixel(pixel(ball[0] - 0.1, ball[1]))

    plastic, pale = MATERIAL_COLORS["plastic"], asleep_color(MATERIAL_COLORS["plastic"])
    assert pale == (128, 242, 152)  # halfway to the white background
    assert crate_and_ball(NAP_SLEEPS - 1) == (plastic, RUBBER)
    assert crate_and_ball(NAP_SLEEPS) == (pale, RUBBER)  # the ball, awake, keeps its colour
    assert crate_and_ball(NAP_WAKES - 1)[0] == pale
    assert crate_and_ball(NAP_WAKES)[0] == plastic
    with h5py.File(nap, "r") as file:
        frame = next(iter_frames(file, range(NAP_SLEEPS, NAP_SLEEPS + 1), with_contacts=False))
    assert frame.asleep.tolist() == [False, True, False]


def test_material_colours_are_the_thesis_palette_or_a_stable_hash():
    assert material_color("rubber") == (230, 41, 55) and material_color("default") == (0, 0, 0)
    assert material_color("ice") == material_color("ice")
    assert material_color("ice") != material_color("glass")
    assert material_color("ice") not in MATERIAL_COLORS.values()


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (["--tick", "7", "--every", "1"], "--tick"),
        (["--view", "1,2,3"], "--view"),
        (["--view", "3,0,1,2"], "XMIN < XMAX"),
        (["--size", "big"], "--size"),
        (["--tick", "999"], "tick 999 was not recorded"),
    ],
)
def test_bad_options_exit_2(cli, trajectory: Path, tmp_path: Path, arguments: list[str], message: str):
    out = tmp_path / ("a.gif" if "--every" in arguments else "a.png")
    result = cli("render", trajectory, "-o", out, *arguments)
    assert result.exit_code == 2 and message in result.stderr and "Traceback" not in result.stderr
    assert list(tmp_path.iterdir()) == []


def test_missing_foreign_and_non_hdf5_files_exit_2(cli, tmp_path: Path):
    foreign = tmp_path / "foreign.h5"
    with h5py.File(foreign, "w") as f:
        f["data"] = np.zeros(3)
    text = tmp_path / "notes.h5"
    text.write_text("not a trajectory")
    for source in (tmp_path / "missing.h5", foreign, text):
        for out in ("x.png", "x.html"):
            result = cli("render", source, "-o", tmp_path / out)
            assert result.exit_code == 2, (source, result.stderr)
            assert str(source) in result.stderr and "Traceback" not in result.stderr
    assert not (tmp_path / "x.png").exists() and not (tmp_path / "x.html").exists()


def test_unknown_output_type_exit_2(cli, trajectory: Path, tmp_path: Path):
    result = cli("render", trajectory, "-o", tmp_path / "x.jpg")
    assert result.exit_code == 2 and ".png, .gif, .mp4, .html" in result.stderr


def test_contacts_overlay_without_recorded_contacts_is_a_note(cli, run_scene, tmp_path: Path):
    quiet_run = run_scene(SCENE, "--no-contacts")
    out = tmp_path / "frame.png"
    result = cli("render", quiet_run, "-o", out, "--contacts")
    assert result.exit_code == 0 and out.is_file()
    assert "no contact points were recorded" in result.stderr
