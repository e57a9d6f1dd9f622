"""`world.sleep` and `world.sleep_time` in scene files: defaults, the World they build, overrides, sweeps and
located errors."""

from __future__ import annotations

from pathlib import Path

import pytest

from rustycs import defaults
from rustycs_cli.build import build_world
from rustycs_cli.errors import UserError
from rustycs_cli.loading import load_scene, load_scene_text

SCENE = """\
name: nap
world:
  tick_rate: 60
  ticks: 10
bodies:
  - {name: floor, type: static, shape: {type: aabb, width: 4, height: 0.5}, position: [0, -0.25]}
  - {name: crate, shape: {type: obb, width: 0.5, height: 0.5}, position: [0, 0.25]}
"""


def problems(tmp_path: Path, text: str) -> list[str]:
    path = tmp_path / "scene.yaml"
    path.write_text(text)
    with pytest.raises(UserError) as raised:
        load_scene(path)
    assert raised.value.exit_code == 2
    return [message.replace(str(path), "scene.yaml") for message in raised.value.messages]


def test_sleep_is_off_by_default_with_the_engines_defaults() -> None:
    loaded = load_scene_text(SCENE, "s.yaml")
    assert loaded.scene.world.sleep is defaults.SLEEP is False
    assert loaded.scene.world.sleep_time == defaults.SLEEP_TIME
    world = build_world(loaded.scene)
    assert world.sleep is False and world.sleep_time == defaults.SLEEP_TIME
    # a scene that leaves sleeping out resolves to the text (and hash) it had before sleeping existed
    assert "sleep" not in loaded.text


def test_the_scene_sets_the_worlds_sleeping() -> None:
    text = SCENE.replace("  ticks: 10\n", "  ticks: 10\n  sleep: true\n  sleep_time: 0.25\n")
    loaded = load_scene_text(text, "s.yaml")
    world = build_world(loaded.scene)
    assert world.sleep is True and world.sleep_time == 0.25
    again = load_scene_text(loaded.text, "resolved.yaml").scene.world  # the stored scene keeps them
    assert again.sleep is True and again.sleep_time == 0.25


def test_overrides_set_sleeping() -> None:
    world = load_scene_text(SCENE, "s.yaml", ("world.sleep=true", "world.sleep_time=2")).scene.world
    assert world.sleep is True and world.sleep_time == 2.0


@pytest.mark.parametrize(("line", "column", "message"), [
    ("sleep_time: 0", 15, "world.sleep_time: Input should be greater than 0 (got 0)"),
    ("sleep_time: -1", 15, "world.sleep_time: Input should be greater than 0 (got -1)"),
    ("sleep_time: .inf", 15, "world.sleep_time: Input should be a finite number"),
    ("sleep_time: 1e10", 15, "world.sleep_time: must be at most 1e+09 s (MAX_SLEEP_TIME, see docs/"),
    ("sleep_time: true", 15, "world.sleep_time: Input should be a valid number"),
    ("sleep: 3", 10, "world.sleep: Input should be a valid boolean"),
    ("slep: true", 3, "world.slep: unknown key 'slep' (did you mean 'sleep'?)"),
])
def test_bad_values_are_reported_at_their_place(tmp_path: Path, line: str, column: int, message: str) -> None:
    text = SCENE.replace("  ticks: 10\n", f"  ticks: 10\n  {line}\n")
    (found,) = problems(tmp_path, text)
    assert found.startswith(f"scene.yaml:5:{column}: {message}"), found


def test_a_bad_value_on_the_command_line_exits_2_without_traceback(cli, tmp_path: Path) -> None:
    scene = tmp_path / "nap.yaml"
    scene.write_text(SCENE.replace("  ticks: 10\n", "  ticks: 10\n  sleep_time: 0\n"))
    result = cli("run", scene, "--out", tmp_path / "nap.h5")
    assert result.exit_code == 2 and "Traceback" not in result.stderr
    assert f"{scene}:5:15: world.sleep_time: Input should be greater than 0" in result.stderr
    assert not (tmp_path / "nap.h5").exists()
    result = cli("validate", tmp_path / "nap.yaml", "-s", "world.sleep_time=1", "-s", "world.sleep=3")
    assert result.exit_code == 2 and "Traceback" not in result.stderr
    assert "--set world.sleep=3: world.sleep: Input should be a valid boolean" in result.stderr


def test_the_schema_describes_sleeping() -> None:
    from rustycs_cli.scene import Scene

    world = Scene.model_json_schema()["$defs"]["World"]["properties"]
    assert world["sleep"]["default"] is False and world["sleep"]["type"] == "boolean"
    assert world["sleep_time"]["default"] == defaults.SLEEP_TIME
    assert world["sleep_time"]["exclusiveMinimum"] == 0 and world["sleep_time"]["maximum"] == 1e9
    assert "MAX_SLEEP_TIME" in world["sleep_time"]["$comment"]
    assert world["sleep"]["description"] and world["sleep_time"]["examples"]
