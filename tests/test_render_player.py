"""The HTML player made by `rustycs render -o X.html`, driven in headless Chromium (Debian's package)."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

from rustycs_cli.render.colors import BACKGROUND, EVENT_COLORS, MATERIAL_COLORS

CHROMIUM = Path("/usr/bin/chromium")
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]


@pytest.fixture(scope="module")
def trajectory(run_scene) -> Path:
    from conftest import FIVE_BODIES  # ball: rubber, r 0.2 at (-2, 0.5); contacts recorded

    return run_scene(FIVE_BODIES)


@pytest.fixture(scope="module")
def browser():
    sync_api = pytest.importorskip("playwright.sync_api")
    if not CHROMIUM.exists():
        pytest.skip("needs Debian's chromium package (/usr/bin/chromium)")
    with sync_api.sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=str(CHROMIUM), args=CHROMIUM_ARGS)
        yield browser
        browser.close()


def open_player(browser, path: Path):
    """A page showing the player, with its console errors and network requests collected."""
    page = browser.new_page(viewport={"width": 900, "height": 650})
    problems: list[str] = []
    requests: list[str] = []
    page.on("console", lambda message: problems.append(message.text) if message.type == "error" else None)
    page.on("pageerror", lambda error: problems.append(str(error)))
    page.on("request", lambda request: requests.append(request.url))
    page.goto(path.as_uri())
    page.wait_for_function("window.player && window.player.ready", timeout=30_000)
    return page, problems, requests


def canvas_rgb(page, world_x: float, world_y: float) -> tuple[int, int, int]:
    """The canvas colour where world point (x, y) is drawn now."""
    return tuple(
        page.evaluate(
            """([x, y]) => {
                const [sx, sy] = window.player.worldToScreen(x, y), dpr = window.devicePixelRatio || 1;
                const ctx = document.getElementById("view").getContext("2d");
                const pixel = ctx.getImageData(Math.floor(sx * dpr), Math.floor(sy * dpr), 1, 1);
                return Array.from(pixel.data.slice(0, 3));
            }""",
            [world_x, world_y],
        )
    )


def test_player_draws_plays_steps_and_toggles(cli, browser, trajectory: Path, tmp_path: Path):
    out = tmp_path / "player.html"
    result = cli("render", trajectory, "-o", out)
    assert result.exit_code == 0, result.stderr
    assert "61 frames" in result.stdout
    page, problems, requests = open_player(browser, out)
    player = "window.player"
    assert page.evaluate(f"{player}.frameCount") == 61 and page.evaluate(f"{player}.bodyCount") == 5
    state = page.evaluate(f"{player}.state")
    assert state["frame"] == 0 and state["playing"] is False
    # frame 0: the rubber ball is drawn red at its centre's projection, the background elsewhere is white
    assert canvas_rgb(page, -2.0, 0.5 - 0.1) == MATERIAL_COLORS["rubber"]
    assert canvas_rgb(page, -2.5, 1.5) == BACKGROUND

    page.keyboard.press("ArrowRight")
    page.keyboard.press("ArrowRight")
    assert page.evaluate(f"{player}.state.frame") == 2
    page.keyboard.press("ArrowLeft")
    assert page.evaluate(f"{player}.state.frame") == 1

    page.keyboard.press(" ")
    assert page.evaluate(f"{player}.state.playing") is True
    page.wait_for_function(f"{player}.state.frame > 3", timeout=10_000)
    page.keyboard.press(" ")
    assert page.evaluate(f"{player}.state.playing") is False
    paused_at = page.evaluate(f"{player}.state.frame")
    page.wait_for_timeout(300)
    assert page.evaluate(f"{player}.state.frame") == paused_at

    draws = page.evaluate(f"{player}.stats.draws")
    for key, name in (("h", "hitboxes"), ("c", "contacts"), ("v", "velocities"), ("n", "names")):
        assert page.evaluate(f"{player}.state.{name}") is False
        page.keyboard.press(key)
        assert page.evaluate(f"{player}.state.{name}") is True
        assert page.evaluate(f"document.getElementById('{name}').checked") is True
    page.wait_for_function(f"{player}.stats.draws > {draws}", timeout=5_000)  # redrawn with the overlays
    page.keyboard.press("h")
    assert page.evaluate(f"{player}.state.hitboxes") is False

    assert problems == []
    assert requests == [out.as_uri()]  # works offline: nothing fetched but the file itself


def test_player_hover_zoom_and_pan(cli, browser, trajectory: Path, tmp_path: Path):
    out = tmp_path / "player.html"
    assert cli("render", trajectory, "-o", out, "--tick", "0").exit_code == 0
    page, problems, _ = open_player(browser, out)
    x, y = page.evaluate("window.player.worldToScreen(-2, 0.5)")
    page.mouse.move(x, y)
    page.wait_for_function("window.player.state.hover >= 0", timeout=5_000)
    tooltip = page.inner_text("#tooltip")
    assert tooltip.startswith("ball") and "position" in tooltip and "angular velocity" in tooltip
    assert re.search(r"-2\.0000, 0\.5000 m", tooltip)
    scale = page.evaluate("window.player.state.scale")
    page.mouse.wheel(0, -300)
    page.wait_for_function(f"window.player.state.scale > {scale}", timeout=5_000)
    # zooming keeps the point under the cursor in place
    assert page.evaluate("window.player.worldToScreen(-2, 0.5)") == pytest.approx([x, y], abs=0.5)
    cx = page.evaluate("window.player.state.cx")
    page.mouse.move(x, y)
    page.mouse.down()
    page.mouse.move(x + 100, y, steps=4)
    page.mouse.up()
    assert page.evaluate("window.player.state.cx") < cx  # dragging right moves the view left
    assert problems == []


def test_long_runs_are_thinned_with_a_note(cli, browser, trajectory: Path, tmp_path: Path, monkeypatch):
    import rustycs_cli.render.player as player_module

    monkeypatch.setattr(player_module, "MAX_FRAMES", 20)
    out = tmp_path / "thin.html"
    result = cli("render", trajectory, "-o", out)
    assert result.exit_code == 0, result.stderr
    assert "16 frames (every 4)" in result.stdout and "thinned" in result.stderr  # 61 recorded
    header = json.loads(
        re.search(r'<script type="application/json" id="rustycs-header">(.*?)</script>', out.read_text())[1]
    )
    assert header["every"] == 4 and header["steps"][:3] == [0, 4, 8] and len(header["times"]) == 16
    page, problems, _ = open_player(browser, out)
    assert "thinned" in page.inner_text("#note")
    assert page.evaluate("window.player.frameCount") == 16
    assert problems == []


@pytest.fixture(scope="module")
def shapes_trajectory(run_scene) -> Path:
    from conftest import EVERY_SHAPE  # every shape kind, sensors, a concave L, a capsule at 0.5 rad

    return run_scene(EVERY_SHAPE)


def test_player_draws_every_shape_kind_and_picks_bodies_by_their_shapes(cli, browser, shapes_trajectory: Path,
                                                                         tmp_path: Path):
    out = tmp_path / "shapes.html"
    assert cli("render", shapes_trajectory, "-o", out).exit_code == 0
    page, problems, _ = open_player(browser, out)
    assert page.evaluate("window.player.bodyCount") == 5
    rubber, plastic, metal = (MATERIAL_COLORS[m] for m in ("rubber", "plastic", "metal"))

    def empty(color) -> bool:  # the background or a grid line: nothing drawn
        return min(color) >= 220

    assert canvas_rgb(page, 0.9, 2.5) == rubber and canvas_rgb(page, -0.9, 2.5) == plastic  # the cup's walls
    sensor = canvas_rgb(page, 0.2, 2.3)  # a faint plastic disc
    assert not empty(sensor) and sensor != plastic and sensor[1] > sensor[0] + 30
    assert canvas_rgb(page, -2.0, 1.6) == metal and empty(canvas_rgb(page, -1.9, 2.1))  # arm, notch
    c, s = math.cos(0.5), math.sin(0.5)
    end = (2.5 + 0.5 * c, 1.5 + 0.5 * s)  # the centre of the capsule's end circle
    tip = (end[0] + 0.2 * c, end[1] + 0.2 * s)
    corner = (end[0] + 0.22 * (c - s), end[1] + 0.22 * (s + c))
    assert canvas_rgb(page, *tip) == rubber and empty(canvas_rgb(page, *corner))  # a stadium, not a box

    def picked(x: float, y: float) -> int:
        sx, sy = page.evaluate(f"window.player.worldToScreen({x}, {y})")
        return page.evaluate(f"window.player.bodyAt({sx}, {sy})")

    assert picked(-2.0, 1.6) == 2 and picked(-1.9, 2.1) == -1  # the L, not its notch
    assert picked(*tip) == 3 and picked(*corner) == -1
    assert picked(1.5, 0.0) == 0 and picked(1.5, 0.3) == -1  # the ground's segment, a line
    assert picked(-0.4, 4.0) == 4 and picked(-1.2, 4.0) == -1  # the wheel's circle, 0.3 m off its origin
    for key in ("h", "v", "n"):
        page.keyboard.press(key)
    page.mouse.move(*page.evaluate("window.player.worldToScreen(-2.0, 1.6)"))
    page.wait_for_function("window.player.state.hover === 2", timeout=5_000)
    assert page.inner_text("#tooltip").startswith("hook  (dynamic polygon, metal)")
    assert problems == []


def embedded(page_text: str) -> tuple[dict, dict[str, bytes]]:
    """The player's JSON header and its base64 arrays (as bytes)."""
    import base64

    header = json.loads(
        re.search(r'<script type="application/json" id="rustycs-header">(.*?)</script>', page_text)[1])
    blobs = {m[1]: base64.b64decode(m[2]) for m in re.finditer(
        r'<script type="application/octet-stream" id="rustycs-(\w+)">(.*?)</script>', page_text)}
    return header, blobs


def test_player_data_lights_sensors_while_occupied_and_marks_events(cli, sensor_drop, tmp_path: Path):
    path, enter, leave = sensor_drop
    out = tmp_path / "sensor.html"
    assert cli("render", path, "-o", out).exit_code == 0
    header, blobs = embedded(out.read_text())
    assert header["sensorBodies"] == [1] and header["steps"] == list(range(61))  # frame f is tick f
    lit = np.frombuffer(blobs["sensorLit"], np.uint8).reshape(61, 1)[:, 0]
    assert list(np.flatnonzero(lit)) == list(range(enter, leave))  # from its enter tick until it left
    assert [(m["kind"], m["frames"], m["counts"]) for m in header["eventMarks"]] == [
        ("sensor_enter", [enter], [1]), ("sensor_exit", [leave], [1])]
    thin = tmp_path / "thin.html"  # every 4th frame: an event marks the first shown frame at or after it
    assert cli("render", path, "-o", thin, "--every", "4").exit_code == 0
    marks = {m["kind"]: m["frames"] for m in embedded(thin.read_text())[0]["eventMarks"]}
    assert marks == {"sensor_enter": [-(-enter // 4)], "sensor_exit": [-(-leave // 4)]}


def test_player_lights_a_sensor_while_a_body_is_inside_and_marks_the_scrub_bar(cli, browser, sensor_drop,
                                                                            tmp_path: Path):
    path, enter, leave = sensor_drop
    out = tmp_path / "sensor.html"
    assert cli("render", path, "-o", out).exit_code == 0
    page, problems, _ = open_player(browser, out)

    def sensor_at(frame: int) -> tuple[int, int, int]:  # a point of the sensor box the ball never crosses
        page.evaluate(f"window.player.setFrame({frame}); window.player.draw()")
        return canvas_rgb(page, 0.4, 0.85)

    empty, inside, after = sensor_at(0), sensor_at(enter + 2), sensor_at(60)
    assert empty == after and empty != inside and empty != BACKGROUND
    assert inside[1] > inside[0] + 60 and sum(inside) < sum(empty)  # a deeper plastic green
    assert page.evaluate(f"window.player.sensorLit(1, {enter})") is True
    assert page.evaluate(f"window.player.sensorLit(1, {enter - 1})") is False

    def mark_rgb(frame: int) -> tuple[int, int, int]:  # the marks canvas above the track, at a frame's place
        return tuple(page.evaluate(
            """(frame) => {
                const canvas = document.getElementById("marks"), rect = canvas.getBoundingClientRect();
                const [x] = window.player.scrubPoint(frame), dpr = window.devicePixelRatio || 1;
                const column = Math.floor((x - rect.left) * dpr);
                const pixel = canvas.getContext("2d").getImageData(column, 2 * dpr, 1, 1);
                return Array.from(pixel.data.slice(0, 4));
            }""", frame))

    enter_color = EVENT_COLORS["sensor_enter"]
    assert mark_rgb(enter) == (*enter_color, 255) and mark_rgb(leave) == (*EVENT_COLORS["sensor_exit"], 255)
    assert mark_rgb((enter + leave) // 2)[3] == 0  # no event there: transparent
    assert "sensor_enter" in page.inner_text("#legend") and "sensor_exit" in page.inner_text("#legend")
    for frame in (enter, leave, 50):  # a click on the bar, on a mark or not, still scrubs to that frame
        page.mouse.click(*page.evaluate(f"window.player.scrubPoint({frame})"))
        assert page.evaluate("window.player.state.frame") == frame
    x, y = page.evaluate(f"window.player.scrubPoint({enter})")
    page.mouse.move(x, y)
    assert page.get_attribute("#scrub", "title") == f"tick {enter}: 1 sensor_enter"
    assert problems == []


def test_player_carries_the_asleep_flags_and_fills_sleeping_bodies_paler(cli, browser, run_scene,
                                                                        tmp_path: Path):
    from conftest import NAP, NAP_SLEEPS, NAP_WAKES  # the plastic crate at (-1, 0.3) sleeps, then wakes

    from rustycs_cli.render.colors import asleep_color, hex_color

    out = tmp_path / "nap.html"
    assert cli("render", run_scene(NAP), "-o", out).exit_code == 0
    header, blobs = embedded(out.read_text())
    asleep = np.frombuffer(blobs["asleep"], np.uint8).reshape(91, 3)
    assert list(np.flatnonzero(asleep[:, 1])) == list(range(NAP_SLEEPS, NAP_WAKES))
    assert not asleep[:, [0, 2]].any()
    plastic = MATERIAL_COLORS["plastic"]
    assert header["shapes"]["asleepColors"][1] == hex_color(asleep_color(plastic))
    page, problems, _ = open_player(browser, out)

    def crate_at(frame: int) -> tuple[int, int, int]:
        page.evaluate(f"window.player.setFrame({frame}); window.player.draw()")
        return canvas_rgb(page, -1.15, 0.3)

    assert crate_at(NAP_SLEEPS - 1) == plastic
    assert crate_at(NAP_SLEEPS) == asleep_color(plastic)
    assert [page.evaluate(f"window.player.asleep({body})") for body in range(3)] == [False, True, False]
    assert crate_at(NAP_WAKES) == plastic
    page.evaluate(f"window.player.setFrame({NAP_SLEEPS + 5}); window.player.draw()")
    page.mouse.move(*page.evaluate("window.player.worldToScreen(-1.0, 0.3)"))
    page.wait_for_function("window.player.state.hover === 1", timeout=5_000)
    assert page.inner_text("#tooltip").rstrip().endswith("asleep")
    assert problems == []
