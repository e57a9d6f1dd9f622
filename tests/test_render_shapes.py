"""Pictures of bodies made of shapes: every shape kind drawn from /shapes at its offset and angle on its
body (concave polygons as one outline, capsules as stadiums, lines as lines, sensors translucent),
hitboxes per shape, velocity arrows from the centre of mass; the example scenes' first frames."""

from __future__ import annotations

import math
from pathlib import Path

import h5py
import numpy as np
import pytest
from conftest import EVERY_SHAPE
from PIL import Image

from rustycs_cli.render.colors import BACKGROUND, MATERIAL_COLORS, VELOCITY
from rustycs_cli.render.raster import SENSOR_FILL_ALPHA, SENSOR_LIT_ALPHA

SCENES = Path(__file__).resolve().parent.parent / "scenes"
VIEW = ("-4,-1,4,5", "800x600")  # exactly 100 px per metre: pixel = (100 (x + 4), 100 (5 - y))
STONE, PLASTIC, RUBBER, METAL = (MATERIAL_COLORS[m] for m in ("stone", "plastic", "rubber", "metal"))


@pytest.fixture(scope="module")
def trajectory(run_scene) -> Path:
    return run_scene(EVERY_SHAPE)


def render(cli, trajectory: Path, out: Path, *options: str) -> Image.Image:
    view, size = VIEW
    result = cli("render", trajectory, "-o", out, "--tick", "0", "--view", view, "--size", size, *options)
    assert result.exit_code == 0, result.stderr
    return Image.open(out).convert("RGB")


def at(image: Image.Image, x: float, y: float, box=(-4.0, -1.0, 4.0, 5.0), scale: float = 100.0):
    """The colour of the pixel holding world point (x, y)."""
    return image.getpixel((math.floor((x - box[0]) * scale), math.floor((box[3] - y) * scale)))


def faint(color: tuple[int, int, int], alpha: int = SENSOR_FILL_ALPHA) -> tuple[int, ...]:
    """A sensor's fill over the white background (brighter with SENSOR_LIT_ALPHA: something inside)."""
    return tuple(round(255 * (1 - alpha / 255) + c * alpha / 255) for c in color)


def near(a, b, tolerance: int = 2) -> bool:
    return all(abs(p - q) <= tolerance for p, q in zip(a, b, strict=True))


def empty(color: tuple[int, int, int]) -> bool:
    """Background, or a grid line over it: nothing is drawn there."""
    return min(color) >= 220


def test_every_shape_kind_is_drawn_at_its_place_on_its_body(cli, trajectory: Path, tmp_path: Path):
    image = render(cli, trajectory, tmp_path / "shapes.png")
    # the cup: plastic bottom and left wall, its own rubber right wall, a translucent sensor disc inside
    assert at(image, 0.5, 1.1) == PLASTIC and at(image, -0.9, 2.5) == PLASTIC
    assert at(image, 0.9, 2.5) == RUBBER
    assert near(at(image, 0.2, 2.3), faint(PLASTIC)) and empty(at(image, 0.2, 2.9))
    # the concave hook is one outline: filled in its arms, empty in its notch
    assert at(image, -2.0, 1.6) == METAL and at(image, -2.4, 2.3) == METAL
    assert empty(at(image, -1.9, 2.1))
    # the capsule is a stadium at 0.5 rad: round beyond its end circle's centre, no corners
    direction, side = np.array([math.cos(0.5), math.sin(0.5)]), np.array([-math.sin(0.5), math.cos(0.5)])
    end = np.array([2.5, 1.5]) + 0.5 * direction
    assert at(image, *(end + 0.2 * direction)) == RUBBER and at(image, *(end - 0.6 * direction)) == RUBBER
    assert at(image, *(end + 0.22 * direction + 0.22 * side)) == BACKGROUND  # a box would be filled here
    # the wheel's circle sits 0.3 m right of its body's origin
    assert at(image, -0.4, 4.0) == PLASTIC and at(image, -1.0, 4.1) == PLASTIC
    assert empty(at(image, -1.2, 4.0))
    # static lines are lines: the ground segment, the closed chain's three sides, not its inside
    assert STONE in [image.getpixel((550, row)) for row in range(497, 503)]  # x = 1.5, y = 0
    assert STONE in [at(image, -3.0 + d, 4.5 - d) for d in np.linspace(-0.02, 0.02, 9)]  # the closing side
    assert empty(at(image, -2.8, 4.3))
    # the static sensor region is stone, faint
    assert near(at(image, 3.2, 4.6), faint(STONE))


def test_hitboxes_are_drawn_per_shape(cli, trajectory: Path, tmp_path: Path):
    image = render(cli, trajectory, tmp_path / "boxes.png", "--hitboxes")
    # the inner face of the cup's left wall is the edge of that wall's own box (no box of the whole cup
    # has an edge there)
    def blue(picture: Image.Image) -> bool:  # the box's line, maybe shared with the pixel beside it
        row = [picture.getpixel((column, 250)) for column in range(316, 325)]  # x = -0.84 .. -0.76, y = 2.5
        return any(b > 200 and r < 150 for r, _, b in row)

    assert blue(image) and not blue(render(cli, trajectory, tmp_path / "plain.png"))


def test_velocity_arrows_start_at_the_centre_of_mass(cli, trajectory: Path, tmp_path: Path):
    with h5py.File(trajectory, "r") as f:
        center = f["particles/bodies/local_center"][2]  # the hook's centroid, about its origin
    assert center == pytest.approx([0.3393, 0.3393], abs=1e-4)  # (1 x 0.25 + 0.75 x 0.25) L
    image = np.asarray(render(cli, trajectory, tmp_path / "arrows.png", "--velocities"))
    start = np.array([-2.5, 1.5]) + center  # the arrow goes 0.5 m up from here, through the notch

    def violet(x: float, y: float) -> bool:
        column, row = math.floor((x + 4) * 100), math.floor((5 - y) * 100)
        window = image[row - 2:row + 3, column - 2:column + 3].reshape(-1, 3).astype(int)
        return bool((np.abs(window - VELOCITY).sum(axis=1) < 90).any())

    assert violet(start[0], start[1] + 0.25) and violet(start[0], start[1] + 0.45)
    assert not violet(-2.5 + 0.125, start[1] + 0.25)  # none up from the origin or the arm's middle


def test_pictures_and_videos_light_a_sensor_while_a_body_is_inside(cli, sensor_drop, tmp_path: Path):
    path, enter, leave = sensor_drop  # frame f is tick f; the goal box is x -0.5..0.5, y 0.75..1.25
    view = ("--view", "-2,-0.5,2,2.5", "--size", "400x300")  # 100 px per metre

    def sensor(image: Image.Image) -> tuple[int, int, int]:  # a point of the box the ball never crosses
        return image.convert("RGB").getpixel((240, 165))  # x 0.4, y 0.85

    def png(tick: int) -> tuple[int, int, int]:
        out = tmp_path / f"tick{tick}.png"
        assert cli("render", path, "-o", out, "--tick", str(tick), *view).exit_code == 0
        return sensor(Image.open(out))

    empty, inside, after = png(0), png(enter + 2), png(60)
    assert near(empty, faint(PLASTIC)) and near(after, faint(PLASTIC))
    assert near(inside, faint(PLASTIC, SENSOR_LIT_ALPHA))
    assert near(png(enter), faint(PLASTIC, SENSOR_LIT_ALPHA)) and near(png(enter - 1), faint(PLASTIC))
    assert near(png(leave - 1), faint(PLASTIC, SENSOR_LIT_ALPHA)) and near(png(leave), faint(PLASTIC))

    gif = tmp_path / "drop.gif"
    assert cli("render", path, "-o", gif, "--every", "1", *view).exit_code == 0
    with Image.open(gif) as frames:
        shown = []
        for f in range(frames.n_frames):
            frames.seek(f)
            shown.append(sensor(frames))
    lit = [f for f, color in enumerate(shown) if near(color, faint(PLASTIC, SENSOR_LIT_ALPHA), 4)]
    assert lit == list(range(enter, leave))
    assert all(near(shown[f], faint(PLASTIC), 4) for f in range(61) if f not in lit)

    import imageio_ffmpeg

    mp4 = tmp_path / "drop.mp4"
    assert cli("render", path, "-o", mp4, "--every", "1", *view).exit_code == 0
    reader = imageio_ffmpeg.read_frames(str(mp4))
    width, height = next(reader)["size"]
    decoded = [np.frombuffer(raw, np.uint8).reshape(height, width, 3)[165, 240] for raw in reader]
    red = np.array([int(pixel[0]) for pixel in decoded])  # faint plastic: red 191; lit: 102 (lossy video)
    assert list(np.flatnonzero(red < 150)) == list(range(enter, leave))


def test_a_file_without_shapes_is_refused_with_one_message(cli, trajectory: Path, tmp_path: Path):
    old = tmp_path / "old.h5"
    old.write_bytes(trajectory.read_bytes())
    with h5py.File(old, "a") as f:  # as written before /shapes existed
        del f["shapes"]
    for out in ("x.png", "x.html", "x.gif"):
        result = cli("render", old, "-o", tmp_path / out)
        assert result.exit_code == 2 and "Traceback" not in result.stderr
        assert result.stderr.strip().splitlines() == [
            f"{old}: no /shapes in this trajectory (written by a rustycs before bodies made of shapes), so "
            f"its bodies cannot be drawn; run its scene again to render it: rustycs run {old} --out NEW.h5"
        ]
        assert not (tmp_path / out).exists()


# ------------------------------------------------------------------------------- the example scenes


def first_frame(cli, run_scene, tmp_path: Path, name: str) -> tuple[Image.Image, h5py.File, tuple]:
    """Tick 0 of an example scene, drawn at 100 px per metre around its fitted view."""
    trajectory = run_scene((SCENES / f"{name}.yaml").read_text(), "--ticks", "1")
    out = tmp_path / f"{name}.png"
    result = cli("render", trajectory, "-o", out, "--tick", "0", "--size", "800x600")
    assert result.exit_code == 0, result.stderr
    box = tuple(float(v) for v in result.stdout.split("view ")[1].split(",")[:4])
    return Image.open(out).convert("RGB"), h5py.File(trajectory, "r"), box


def poses(file: h5py.File) -> tuple[np.ndarray, np.ndarray]:
    return file["particles/bodies/position/value"][0], file["particles/bodies/angle/value"][0]


def place(position: np.ndarray, angle: float, local) -> tuple[float, float]:
    c, s = math.cos(angle), math.sin(angle)
    return position[0] + c * local[0] - s * local[1], position[1] + s * local[0] + c * local[1]


def test_example_cup_of_balls(cli, run_scene, tmp_path: Path):
    image, file, box = first_frame(cli, run_scene, tmp_path, "cup_of_balls")
    scale = 800 / (box[2] - box[0])
    with file:
        position, _ = poses(file)
    beside = [(x + 0.1, y) for x, y in position[2:7]]  # the five balls, beside their spokes
    assert [at(image, x, y, box, scale) for x, y in beside] == [RUBBER] * 5
    assert at(image, 0.5, 2.1, box, scale) == PLASTIC and at(image, -0.9, 3.5, box, scale) == PLASTIC
    assert empty(at(image, 0.5, 3.5, box, scale))  # the cup is open between its walls


def test_example_curved_ramp(cli, run_scene, tmp_path: Path):
    image, file, box = first_frame(cli, run_scene, tmp_path, "curved_ramp")
    scale = 800 / (box[2] - box[0])
    with file:
        position, _ = poses(file)
    assert at(image, position[2, 0] + 0.1, position[2, 1], box, scale) == RUBBER  # beside its spoke
    for degrees in (20, 45, 70):  # the chain is drawn along its quarter circle, and only there
        a = math.radians(degrees)
        on = (3 - 3 * math.sin(a), 3 - 3 * math.cos(a))
        assert STONE in [at(image, on[0] + d, on[1] + d, box, scale) for d in np.linspace(-0.03, 0.03, 13)]
        assert empty(at(image, 3 - 2.6 * math.sin(a), 3 - 2.6 * math.cos(a), box, scale))


def test_example_capsule_pile(cli, run_scene, tmp_path: Path):
    image, file, box = first_frame(cli, run_scene, tmp_path, "capsule_pile")
    scale = 800 / (box[2] - box[0])
    with file:
        position, angle = poses(file)
        materials = list(file["shapes/material"].asstr()[()])[3:]
        lengths = file["shapes/length"][3:]
    for k, material in enumerate(materials):  # each capsule's middle and both end circles' centres
        for along in (-lengths[k] / 2, 0.0, lengths[k] / 2):
            point = place(position[k + 1], angle[k + 1], (along, 0.0))
            assert at(image, *point, box, scale) == MATERIAL_COLORS[material], (k, along)


def test_example_l_brackets(cli, run_scene, tmp_path: Path):
    image, file, box = first_frame(cli, run_scene, tmp_path, "l_brackets")
    scale = 800 / (box[2] - box[0])
    with file:
        position, angle = poses(file)
        materials = list(file["shapes/material"].asstr()[()])[3:]
    for k, material in enumerate(materials):
        body = k + 3

        def colour(local: tuple[float, float]) -> tuple[int, int, int]:
            return at(image, *place(position[body], angle[body], local), box, scale)  # noqa: B023

        assert colour((0.1, -0.175)) == colour((-0.175, 0.1)) == MATERIAL_COLORS[material]  # both arms
        assert empty(colour((0.15, 0.15)))  # the notch


def test_a_scene_without_bodies_is_recorded_drawn_and_described(cli, run_scene, tmp_path: Path):
    trajectory = run_scene("name: empty\nworld: {ticks: 3}\n")
    with h5py.File(trajectory, "r") as f:
        assert f["shapes/vertices"].shape == (0, 1, 2) and f["shapes/type"].shape == (0,)
    assert empty(at(render(cli, trajectory, tmp_path / "empty.png"), 0.5, 0.5))
    assert cli("render", trajectory, "-o", tmp_path / "empty.html").exit_code == 0
    info = cli("info", trajectory)
    assert info.exit_code == 0 and "shapes" in info.stdout
