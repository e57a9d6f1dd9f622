"""Joints drawn by `rustycs render` (PNG) and the HTML player: the line between the anchors, a spring as
a zigzag, each toggled off (--no-joints, key J)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from test_render_player import browser, canvas_rgb, open_player  # noqa: F401 (browser: a fixture)

from rustycs_cli.render.colors import BACKGROUND, JOINT
from rustycs_cli.render.joints import zigzag

# a bob on a rod from (-0.7, 1) and one on a spring from (1.3, 1), both 2 m below, drawn at tick 0 (off
# the grid's lines)
JOINTED = """\
world: {tick_rate: 60, ticks: 6, precision: 4}
forces: [{name: gravity, acceleration: [0, -9.81]}]
bodies:
  - {name: bob, shape: {type: circle, radius: 0.1}, position: [-0.7, -1]}
  - {name: weight, shape: {type: circle, radius: 0.1}, position: [1.3, -1]}
joints:
  - {name: rod, type: distance, body: bob, anchors: [[-0.7, 1], [-0.7, -1]]}
  - {name: coil, type: distance, body: weight, anchors: [[1.3, 1], [1.3, -1]], spring: {hertz: 2}}
"""
ROD = (-0.7, 0.35)  # a point on the rod
VIEW = ("--view", "-2,-2,2,2", "--size", "400x400")  # 100 pixels per metre, (0, 0) at pixel (200, 200)


@pytest.fixture(scope="module")
def trajectory(run_scene) -> Path:
    return run_scene(JOINTED)


def rgb(image: Image.Image, x: float, y: float) -> tuple[int, ...]:
    return image.getpixel((int((x + 2) * 100), int((2 - y) * 100)))


def teal(color: tuple[int, ...]) -> bool:
    """The joint colour, or the joint colour blended with the white background at an anti-aliased edge."""
    return color[1] - color[0] >= 60 and abs(color[1] - color[2]) <= 20


def tooth(k: int) -> np.ndarray:
    """The k-th corner of the spring's zigzag, in metres."""
    return zigzag(np.array([1.3, 1.0]), np.array([1.3, -1.0]))[k + 1]


def test_png_draws_rods_and_springs_between_their_anchors(cli, trajectory: Path, tmp_path: Path):
    shown, hidden = tmp_path / "joints.png", tmp_path / "none.png"
    assert cli("render", trajectory, "-o", shown, "--tick", "0", *VIEW).exit_code == 0
    assert cli("render", trajectory, "-o", hidden, "--tick", "0", "--no-joints", *VIEW).exit_code == 0
    with Image.open(shown) as image, Image.open(hidden) as bare:
        assert rgb(image, *ROD) == JOINT and rgb(bare, *ROD) == BACKGROUND
        corner = tooth(6)  # a tooth's corner, 0.24 m beside the spring's axis
        assert abs(corner[0] - 1.3) == pytest.approx(0.24)
        assert teal(rgb(image, *corner)) and rgb(bare, *corner) == BACKGROUND


def test_the_player_draws_joints_and_key_j_hides_them(cli, browser, trajectory: Path, tmp_path: Path):  # noqa: F811
    out = tmp_path / "player.html"
    assert cli("render", trajectory, "-o", out).exit_code == 0
    page, problems, _ = open_player(browser, out)
    assert page.evaluate("window.player.jointCount") == 2 and page.evaluate("window.player.state.joints")
    assert teal(canvas_rgb(page, *ROD))
    page.keyboard.press("j")
    assert page.evaluate("window.player.state.joints") is False
    assert page.evaluate("document.getElementById('joints').checked") is False
    page.evaluate("window.player.draw()")
    assert canvas_rgb(page, *ROD) == BACKGROUND
    assert problems == []
