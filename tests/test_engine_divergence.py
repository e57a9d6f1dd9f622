"""A non-finite value stops the simulation with SimulationDiverged naming the tick and the body.

Each case runs in its own process: an engine that crashes on a non-finite value (a segfault in
compiled code) must fail its test, not take the whole test run down with it.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

from rustycs import Box, Circle, SimulationDiverged, World

OVERFLOW_FORCE = -1e306  # m/s^2, at one tick per second


def three_bodies(**world_options) -> World:
    """A static floor, a kinematic slider and two dynamic circles resting on the floor far apart."""
    world = World(**world_options)
    world.add_body(Box(10.0, 1.0), position=(0, -0.5), body_type="static")
    world.add_body(Box(1.0, 0.2), position=(0, 5), velocity=(0.1, 0), body_type="kinematic")
    world.add_body(Circle(0.5), position=(-3, 0.5))
    world.add_body(Circle(0.5), position=(3, 0.5))
    return world


CASES = {
    "nan vx": ((math.nan, 0.0), None),
    "inf vy": ((0.0, math.inf), None),
    "nan angular velocity": ((0.0, 0.0), math.nan),
}


def diverge(case: str) -> dict:
    """Run one divergence case; report what SimulationDiverged said and where the world stopped."""
    if case == "overflow":
        world = three_bodies(tick_rate=1.0, precision=1)
        world.add_force((0.0, OVERFLOW_FORCE))
    else:
        world = three_bodies()
        world.add_force((0.0, -9.81))
        world.step(5)
        world.set_velocity(3, *CASES[case])
    try:
        world.step(100)
    except SimulationDiverged as error:
        return dict(tick=error.tick, body=error.body, message=str(error), world_tick=world.tick,
                    floor_velocity_finite=bool(math.isfinite(world.velocities[0].sum())))
    return dict(tick=None, body=None, message="", world_tick=world.tick, floor_velocity_finite=True)


def diverge_in_a_process(case: str) -> dict:
    code = (f"import sys, json; sys.path.insert(0, {str(Path(__file__).parent)!r}); "
            f"from test_engine_divergence import diverge; print(json.dumps(diverge({case!r})))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0, f"the engine crashed (exit code {done.returncode}): {done.stderr[-1500:]}"
    return json.loads(done.stdout.strip().splitlines()[-1])


@pytest.mark.parametrize("case", list(CASES))
def test_non_finite_velocity_names_the_tick_and_body(case):
    # body 3 gets the bad value after 5 ticks: tick 6 fails, at body 3 (not at a body it touched)
    result = diverge_in_a_process(case)
    assert (result["tick"], result["body"]) == (6, 3)
    assert "6" in result["message"] and "3" in result["message"]
    assert result["world_tick"] == 6  # the block stopped at the bad tick
    assert result["floor_velocity_finite"]  # the static floor was not contaminated


def test_overflow_is_caught_before_or_at_the_first_non_finite_tick():
    # an absurd force: replay the integrator in Python to find the tick whose state is not finite
    x, v, first_non_finite = 0.5, 0.0, None
    for tick in range(1, 100):
        v += OVERFLOW_FORCE
        x += v
        if not (math.isfinite(x) and math.isfinite(v)):
            first_non_finite = tick
            break
    assert first_non_finite is not None and first_non_finite > 2
    result = diverge_in_a_process("overflow")
    assert result["body"] == 2  # the first dynamic body (both dynamic bodies overflow together)
    assert result["tick"] is not None and 1 <= result["tick"] <= first_non_finite
    assert result["world_tick"] == result["tick"]
