"""`rustycs watch` in headless Chromium: the page shows the run, follows every save, shows problems at
their lines, and the command stops cleanly on Ctrl-C."""

from __future__ import annotations

import queue
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

from test_render_player import browser  # noqa: F401  (the headless Chromium fixture)

SCENE = """\
name: preview
world: {tick_rate: 60, ticks: 20, precision: 2}
forces:
  - {name: gravity, acceleration: [0, -9.81]}
bodies:
  - {name: floor, type: static, shape: {type: aabb, width: 4, height: 0.5}, position: [0, -0.25]}
  - {name: BALL, shape: {type: circle, radius: 0.2}, position: [0, 1]}
"""


def _lines(stream) -> queue.Queue:
    """The lines a process prints, as they come."""
    lines: queue.Queue = queue.Queue()
    threading.Thread(target=lambda: [lines.put(line) for line in stream], daemon=True).start()
    return lines


def _wait(page, script: str, seconds: float = 90.0) -> None:
    """Until `script` is true in the page (which reloads itself meanwhile)."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        try:
            if page.evaluate(script):
                return
        except Exception:  # noqa: BLE001  (the page was reloading)
            pass
        time.sleep(0.2)
    raise AssertionError(f"the page never showed: {script}")


HEADER = "(document.getElementById('rustycs-header') || {textContent: ''}).textContent.includes('%s')"


def test_watch_follows_every_save(browser, tmp_path: Path, compiled_engine):  # noqa: F811
    scene = tmp_path / "preview.yaml"
    scene.write_text(SCENE.replace("BALL", "first-ball"))
    program = Path(sys.executable).with_name("rustycs")
    process = subprocess.Popen([str(program), "watch", str(scene), "--port", "0"], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
    try:
        lines = _lines(process.stdout)
        first = lines.get(timeout=60)
        assert first.startswith(f"watching {scene}: open http://127.0.0.1:")
        url = first.split("open ", 1)[1].split(" ", 1)[0]
        page = browser.new_page()
        page.goto(url)
        _wait(page, HEADER % "first-ball")
        time.sleep(0.05)
        scene.write_text(SCENE.replace("BALL", "second-ball"))
        _wait(page, HEADER % "second-ball")
        scene.write_text(SCENE.replace("BALL", "ball").replace("radius: 0.2", "radius: -0.2"))
        _wait(page, "document.querySelector('#line-7.bad') !== null")
        problems = page.inner_text("#problems")
        assert f"{scene}:7:" in problems and "radius" in problems
        process.send_signal(signal.SIGINT)
        assert process.wait(timeout=30) == 0
        output = []
        while not lines.empty():
            output.append(lines.get())
        assert output[-1].strip() == "rustycs watch: stopped"
        assert "Traceback" not in process.stderr.read()
    finally:
        if process.poll() is None:
            process.kill()


def test_watch_refuses_a_missing_scene(cli, tmp_path: Path):
    result = cli("watch", tmp_path / "none.yaml")
    assert result.exit_code == 2 and "no such scene file" in result.stderr
