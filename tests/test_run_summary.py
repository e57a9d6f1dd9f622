"""Summary statistics computed from hand-made frames, and their JSON form."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from rustycs_cli.summary import (
    CONSERVED,
    CONSERVED_WITHOUT_CONTACTS,
    DESCRIPTIONS,
    NOT_CONSERVED,
    SummaryTracker,
    energy_conservation,
    sidecar_path,
    to_json,
    write_text_atomic,
)
from rustycs_cli.trajectory import Frame

TYPES = ["static", "dynamic", "dynamic", "dynamic", "kinematic"]


def frame(tick: int, velocity, angular_velocity, active, kinetic: float, potential: float, contacts: int,
          penetration: float, momentum=(0.0, 0.0), angular_momentum: float = 0.0,
          speed: float = 0.0, asleep=(0, 0, 0, 0, 0)) -> Frame:
    return Frame(
        tick=tick,
        position=np.zeros((5, 2)),
        velocity=np.array(velocity, float),
        angle=np.zeros(5),
        angular_velocity=np.array(angular_velocity, float),
        active=np.array(active, bool),
        asleep=np.array(asleep, bool),
        observables={"kinetic_energy": kinetic, "potential_energy": potential,
                     "linear_momentum": np.array(momentum), "angular_momentum": angular_momentum,
                     "contact_count": contacts, "max_penetration": penetration, "max_speed": speed},
        contacts=None,
    )


def summarise(frames: list[Frame], step_seconds: float = 0.5, conservation: str = NOT_CONSERVED) -> dict:
    tracker = SummaryTracker(TYPES, conservation)
    for item in frames:
        tracker.add(item)
    return tracker.summary(scene="s", scene_sha256="ab", status="complete", seed=7, dt=0.01,
                           wall_seconds=2.0, step_seconds=step_seconds)


def test_statistics():
    fast = [[0, 0], [3, 4], [0, 1], [1, 0], [9, 9]]
    end = [[0, 0], [0, 0.0005], [0, 0], [0, 0], [9, 9]]
    summary = summarise([  # max_speed: the engine's, of the active dynamic bodies (test_engine_recording)
        frame(0, fast, [0, 0, 0, 0, 0], [1, 1, 1, 1, 1], 10.0, 5.0, 0, 0.0, (1, 0), 2.0, speed=5.0),
        frame(10, fast, [0, 0, 0, 0, 0], [1, 1, 1, 1, 1], 8.0, 6.0, 7, 0.02, speed=4.0),
        frame(20, end, [0, 0, 0.01, 0, 5], [1, 1, 1, 0, 1], 1.0, 11.5, 3, 0.005, (4, 4), -1.0, speed=5e-4),
    ])
    assert summary["ticks"] == 20 and summary["frames"] == 3
    assert summary["simulated_seconds"] == pytest.approx(0.2)
    assert summary["bodies"] == 5 and summary["dynamic_bodies"] == 3
    assert summary["ticks_per_second"] == pytest.approx(40.0)
    assert summary["initial_kinetic_energy"] == 10.0 and summary["final_kinetic_energy"] == 1.0
    assert summary["initial_potential_energy"] == 5.0 and summary["final_potential_energy"] == 11.5
    assert summary["energy_change"] == pytest.approx(-2.5)
    assert summary["relative_energy_change"] == pytest.approx(-2.5 / 15)
    assert summary["energy_drift"] is None and summary["relative_energy_drift"] is None
    assert summary["linear_momentum_drift"] == pytest.approx(5.0)
    assert summary["angular_momentum_drift"] == pytest.approx(3.0)
    assert summary["max_penetration"] == 0.02
    assert summary["total_contact_points"] == 10 and summary["peak_contact_points"] == 7
    assert summary["max_speed"] == pytest.approx(5.0)
    assert summary["escaped_bodies"] == 1  # body 3, dynamic and inactive
    assert summary["bodies_at_rest"] == 1  # body 1 (speed 5e-4); body 2 turns, body 3 escaped
    assert summary["bodies_asleep"] == 0  # sleeping is off
    assert list(summary) == list(DESCRIPTIONS)
    assert summary["divergence"] is None and summary["seed"] == 7


def test_bodies_asleep_counts_the_dynamic_bodies_asleep_in_the_last_frame():
    still = [[0, 0]] * 5
    summary = summarise([frame(0, still, [0] * 5, [1] * 5, 0.0, 0.0, 0, 0.0, asleep=[0, 1, 1, 1, 0]),
                         frame(10, still, [0] * 5, [1] * 5, 0.0, 0.0, 0, 0.0, asleep=[1, 1, 0, 1, 1])])
    assert summary["bodies_asleep"] == 2  # bodies 1 and 3; 0 and 4 are static and kinematic (never asleep)
    assert list(summary).index("bodies_asleep") == list(summary).index("bodies_at_rest") + 1


def _orbit(contacts: int) -> list[Frame]:
    """Two frames of a run whose total energy went from 15 J to 14.99 J, with or without contacts."""
    moving = [[0, 0], [1, 0], [1, 0], [1, 0], [0, 0]]
    return [frame(0, moving, [0] * 5, [1] * 5, 10.0, 5.0, 0, 0.0),
            frame(10, moving, [0] * 5, [1] * 5, 9.0, 5.99, contacts, 0.0)]


@pytest.mark.parametrize("conservation, contacts, drift", [
    (CONSERVED, 4, -0.01),  # elastic frictionless contacts: any change is numerical
    (CONSERVED_WITHOUT_CONTACTS, 0, -0.01),  # an orbit: nothing touched
    (CONSERVED_WITHOUT_CONTACTS, 4, None),  # inelastic contacts dissipate: that is physics
    (NOT_CONSERVED, 0, None),  # damping, joints, a moving kinematic body...
])
def test_energy_drift_only_where_energy_cannot_change_physically(conservation, contacts, drift):
    summary = summarise(_orbit(contacts), conservation=conservation)
    assert summary["energy_change"] == pytest.approx(-0.01)
    assert summary["energy_drift"] == (None if drift is None else pytest.approx(drift))
    assert summary["relative_energy_drift"] == (None if drift is None else pytest.approx(drift / 15))


def test_energy_conservation_of_scenes():
    from rustycs_cli.loading import load_scene_text

    def conservation(text: str) -> str:
        return energy_conservation(load_scene_text(text, "s.yaml").scene)

    ball = "bodies: [{name: b, position: [0, 0], shape: {type: circle, radius: 1}%s}]"
    elastic = "materials: {gas: {density: 1, restitution: 1, friction: 0}}\n"
    assert conservation(ball % "") == CONSERVED_WITHOUT_CONTACTS
    assert conservation(elastic + ball % ", material: gas") == CONSERVED
    assert conservation(elastic + ball % ", material: gas, linear_damping: 0.1") == NOT_CONSERVED


def test_undefined_ratios_are_null():
    still = [[0, 0]] * 5
    summary = summarise([frame(0, still, [0] * 5, [1] * 5, 0.0, 0.0, 0, 0.0)], step_seconds=0.0)
    assert summary["relative_energy_drift"] is None and summary["ticks_per_second"] is None
    assert summary["bodies_at_rest"] == 3


def test_json_is_strict_and_the_sidecar_sits_next_to_the_run(tmp_path: Path):
    data = {"a": float("inf"), "b": [float("nan"), 1.0], "c": {"d": float("-inf")}, "e": "x"}
    assert json.loads(to_json(data)) == {"a": None, "b": [None, 1.0], "c": {"d": None}, "e": "x"}
    assert sidecar_path(tmp_path / "runs" / "bounce.h5") == tmp_path / "runs" / "bounce.summary.json"
    target = tmp_path / "bounce.summary.json"
    write_text_atomic(target, to_json(data))
    assert json.loads(target.read_text())["e"] == "x"
    assert [p.name for p in tmp_path.iterdir()] == ["bounce.summary.json"]
