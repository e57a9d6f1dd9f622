"""Determinism: a mixed pile of 150 bodies of every shape gives bitwise the same trajectory in two runs
of one process and in two other processes (with different hash seeds)."""

from __future__ import annotations

import hashlib
import os
import random
import subprocess
import sys
from pathlib import Path

import numpy as np

from rustycs import Box, Circle, Polygon, World

TICKS = 150
PRESETS = ("default", "rubber", "plastic", "stone", "metal")


def random_convex(rng: random.Random, n: int, radius: float, centre=(0.0, 0.0)):
    step = 2 * np.pi / n
    phase = rng.uniform(0, 2 * np.pi)
    return [(centre[0] + radius * np.cos(phase + k * step + rng.uniform(-0.3, 0.3) * step),
             centre[1] + radius * np.sin(phase + k * step + rng.uniform(-0.3, 0.3) * step)) for k in range(n)]


def mixed_pile() -> World:
    """150 bodies (circles, aabbs, obbs, polygons around and off their origin) dropped from a jittered
    grid into a box, with a kinematic paddle sweeping through the bottom of the pile."""
    rng = random.Random(2024)
    world = World(tick_rate=60.0, precision=8)
    world.add_force((0.0, -9.81))
    world.add_body(Box(14.0, 1.0), position=(0, -0.5), body_type="static", material="stone")
    world.add_body(Box(1.0, 20.0), position=(-6.5, 10), body_type="static")
    world.add_body(Box(1.0, 20.0), position=(6.5, 10), body_type="static")
    world.add_body(Box(2.0, 0.3), position=(-5.0, 0.5), velocity=(1.0, 0.0), body_type="kinematic")
    kinds = ["circle", "aabb", "obb", "polygon", "offset polygon"] * 30
    rng.shuffle(kinds)
    cells = rng.sample([(c, r) for r in range(15) for c in range(12)], 150)
    for kind, (c, r) in zip(kinds, sorted(cells, key=lambda cr: (cr[1], cr[0])), strict=True):
        position = (-5.5 + c + rng.uniform(-0.05, 0.05), 1.5 + r + rng.uniform(-0.05, 0.05))
        size = rng.uniform(0.2, 0.4)
        angle = rng.uniform(-np.pi, np.pi)
        if kind == "circle":
            shape = Circle(size)
        elif kind in ("aabb", "obb"):
            shape = Box(2 * size, rng.uniform(0.3, 0.8), rotates=kind == "obb")
            angle = angle if kind == "obb" else 0.0
        else:
            centre = (rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3)) if kind == "offset polygon" else (0, 0)
            shape = Polygon(random_convex(rng, rng.randint(3, 8), size + 0.05, centre))
        world.add_body(shape, position=position, angle=angle, material=rng.choice(PRESETS),
                       velocity=(rng.uniform(-1, 1), rng.uniform(-1, 0)), angular_velocity=rng.uniform(-2, 2))
    return world


def pile_trajectory() -> np.ndarray:
    """The state (centres, angles, velocities, angular velocities) of every body after every tick."""
    world = mixed_pile()
    frames = []
    for _ in range(TICKS):
        world.step()
        frames.append(np.concatenate([world.centers.ravel(), world.angles, world.velocities.ravel(),
                                      world.angular_velocities]))
    return np.array(frames)


def trajectory_hash() -> str:
    return hashlib.sha256(pile_trajectory().tobytes()).hexdigest()


def test_pile_has_every_shape_and_collides():
    world = mixed_pile()
    assert set(world.shape_kinds[4:]) == {"circle", "aabb", "obb", "polygon"}
    offset = np.linalg.norm(world.centers - world.positions, axis=1)
    assert np.sum(offset > 0.05) >= 20  # off-centroid polygons
    assert world.body_count == 154
    world.step(TICKS)
    assert world.observables()["contact_count"] > 150


def test_two_runs_give_bitwise_identical_trajectories():
    first = pile_trajectory()
    second = pile_trajectory()
    assert np.all(np.isfinite(first))
    assert first.tobytes() == second.tobytes()


def test_two_processes_give_bitwise_identical_trajectories():
    here = trajectory_hash()
    code = (f"import sys; sys.path.insert(0, {str(Path(__file__).parent)!r}); "
            "from test_engine_determinism import trajectory_hash; print(trajectory_hash())")
    hashes = []
    for seed in ("1", "2"):
        env = dict(os.environ, PYTHONHASHSEED=seed)
        done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env,
                              check=True)
        hashes.append(done.stdout.strip())
    assert hashes == [here, here]
