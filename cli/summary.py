"""Summary statistics of a run, computed from its recorded frames, and their outputs (JSON sidecar, table).

The statistics are those a batch user compares across a sweep (trajectory-format.md, "Summary
statistics"). Per-tick quantities (contacts, penetration, speed) are taken over the recorded frames,
so with `output.every` > 1 they are sampled every `every` ticks. "Final" values are those of the last
recorded frame, which after a divergence is the last finite one.

The change of total energy is reported in every run, and called drift (numerical error) only in runs
where nothing can gain or lose energy physically: bouncing balls of restitution below 1 lose energy
to their contacts, which is physics, not error.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy as np
    from rich.table import Table

    from .scene import Scene
    from .trajectory import Frame

_EXTREMES = ("max_penetration", "contact_count", "max_speed")  # per-frame observables summed up or maxed
REST_SPEED = 1e-3  # m/s: a dynamic body slower than this (and REST_ANGULAR_SPEED) is at rest
REST_ANGULAR_SPEED = 1e-3  # rad/s
# what can change a run's total energy physically (energy_conservation)
CONSERVED = "conserved"  # nothing: every contact is elastic and frictionless, nothing else does work
CONSERVED_WITHOUT_CONTACTS = "conserved without contacts"  # contacts can dissipate; nothing else does
NOT_CONSERVED = "not conserved"  # damping, joints, moving kinematic bodies, emitters or sinks

DESCRIPTIONS = {  # key: meaning, in output order (documents every statistic)
    "scene": "scene name",
    "scene_sha256": "SHA-256 of the resolved scene text",
    "status": "complete | stopped | interrupted | diverged",
    "seed": "seed of the generators",
    "ticks": "ticks completed",
    "frames": "frames recorded (tick 0 included)",
    "simulated_seconds": "simulated time, s",
    "bodies": "bodies (static included)",
    "dynamic_bodies": "dynamic bodies",
    "wall_seconds": "wall time of the whole command, s",
    "step_seconds": "time spent stepping alone, s",
    "ticks_per_second": "ticks / step_seconds",
    "initial_kinetic_energy": "kinetic energy at tick 0, J",
    "final_kinetic_energy": "kinetic energy at the last frame, J",
    "initial_potential_energy": "potential energy at tick 0, J",
    "final_potential_energy": "potential energy at the last frame, J",
    "energy_change": "final - initial total energy (kinetic + potential), J; negative when energy was "
    "dissipated (restitution below 1, friction, damping) or left with escaped bodies",
    "relative_energy_change": "energy_change / |initial total energy|",
    "energy_drift": "numerical error of the total energy, J: the energy_change of a run in which nothing "
    "can gain or lose energy physically (no contacts, or only elastic frictionless ones; no damping, "
    "joints, moving kinematic bodies or escapes); null in other runs",
    "relative_energy_drift": "energy_drift / |initial total energy|",
    "linear_momentum_drift": "|final - initial linear momentum|, kg m/s",
    "angular_momentum_drift": "|final - initial angular momentum|, kg m^2/s",
    "max_penetration": "deepest overlap over the run, m",
    "total_contact_points": "contact points summed over the recorded frames",
    "peak_contact_points": "most contact points in one frame",
    "max_speed": "highest speed of an active dynamic body, m/s",
    "escaped_bodies": "dynamic bodies that left the world bounds",
    "bodies_at_rest": "active dynamic bodies at rest at the end",
    "bodies_asleep": "dynamic bodies asleep at the end (world.sleep; 0 without it)",
    "broken_joints": "joints broken by the end (break_force, break_torque)",
    "divergence": "where a non-finite value appeared (diverged runs)",
    "stop_reason": "the world.stop_when condition that ended the run (stopped runs), as written",
    "measures": "the scene's measures by name: a number, null, or a histogram's counts per bin",
    "emitters": "per emitter by name: `appeared`, its bodies that appeared, and `skipped`, those that did "
    "not because their place was taken (placement: no_overlap)",
}


class SummaryTracker:
    """Accumulates the statistics frame by frame, so a run never has to be read back to summarise it."""

    def __init__(self, body_types: list[str], conservation: str = NOT_CONSERVED):
        import numpy as np

        self.conservation = conservation  # what can change the run's energy (energy_conservation)
        self.body_types = [str(kind) for kind in body_types]
        self.dynamic = np.array([kind == "dynamic" for kind in self.body_types], dtype=bool)
        self.first: Frame | None = None
        self.last: Frame | None = None
        self.frames = 0
        self.max_penetration = 0.0
        self.total_contacts = 0
        self.peak_contacts = 0
        self.max_speed = 0.0

    def add(self, frame: Frame) -> None:
        """Account for one recorded frame."""
        import numpy as np

        self._account(frame, frame, 1, {name: np.asarray([frame.observables[name]]) for name in _EXTREMES})

    def add_block(self, frames: dict[str, np.ndarray], count: int) -> None:
        """Account for the first `count` rows of a frame buffer filled by `World.step(record=...)`."""
        from .trajectory import Frame

        if count:
            self._account(Frame.from_buffer(frames, 0, None), Frame.from_buffer(frames, count - 1, None),
                          count, {name: frames[name][:count] for name in _EXTREMES})

    def _account(self, first: Frame, last: Frame, count: int, observed: dict[str, np.ndarray]) -> None:
        if self.first is None:
            self.first = first
        self.last = last
        self.frames += count
        self.max_penetration = max(self.max_penetration, float(observed["max_penetration"].max()))
        self.total_contacts += int(observed["contact_count"].sum())
        self.peak_contacts = max(self.peak_contacts, int(observed["contact_count"].max()))
        self.max_speed = max(self.max_speed, float(observed["max_speed"].max()))

    def summary(self, *, scene: str, scene_sha256: str, status: str, seed: int, dt: float,
                wall_seconds: float, step_seconds: float, divergence: str | None = None,
                escaped: int | None = None) -> dict[str, Any]:
        """The statistics as a flat dict of str/int/float (None where undefined), in DESCRIPTIONS order.
        `escaped`: the engine's count of bodies that left the bounds, where known; else the dynamic bodies
        inactive at the end (which also counts those a sink or a lifetime removed, and emitted ones not
        there yet or skipped)."""
        import numpy as np

        first, last = self.first, self.last
        if first is None or last is None:
            raise ValueError("no frame recorded")
        start, end = first.observables, last.observables
        energy_start = float(start["kinetic_energy"]) + float(start["potential_energy"])
        energy_change = float(end["kinetic_energy"]) + float(end["potential_energy"]) - energy_start
        escaped = int((self.dynamic & ~last.active).sum()) if escaped is None else escaped
        conserved = escaped == 0 and (self.conservation == CONSERVED or (
            self.conservation == CONSERVED_WITHOUT_CONTACTS and self.total_contacts == 0))
        energy_drift = energy_change if conserved else None
        moving = self.dynamic & last.active
        speed = np.hypot(last.velocity[:, 0], last.velocity[:, 1])
        at_rest = moving & (speed < REST_SPEED) & (np.abs(last.angular_velocity) < REST_ANGULAR_SPEED)
        values = {
            "scene": scene,
            "scene_sha256": scene_sha256,
            "status": status,
            "seed": int(seed),
            "ticks": last.tick,
            "frames": self.frames,
            "simulated_seconds": last.tick * dt,
            "bodies": len(self.body_types),
            "dynamic_bodies": int(self.dynamic.sum()),
            "wall_seconds": wall_seconds,
            "step_seconds": step_seconds,
            "ticks_per_second": last.tick / step_seconds if step_seconds > 0 else None,
            "initial_kinetic_energy": float(start["kinetic_energy"]),
            "final_kinetic_energy": float(end["kinetic_energy"]),
            "initial_potential_energy": float(start["potential_energy"]),
            "final_potential_energy": float(end["potential_energy"]),
            "energy_change": energy_change,
            "relative_energy_change": energy_change / abs(energy_start) if energy_start else None,
            "energy_drift": energy_drift,
            "relative_energy_drift": energy_drift / abs(energy_start)
            if energy_drift is not None and energy_start else None,
            "linear_momentum_drift": float(np.hypot(*(
                np.asarray(end["linear_momentum"]) - np.asarray(start["linear_momentum"])))),
            "angular_momentum_drift": abs(float(end["angular_momentum"]) - float(start["angular_momentum"])),
            "max_penetration": self.max_penetration,
            "total_contact_points": self.total_contacts,
            "peak_contact_points": self.peak_contacts,
            "max_speed": self.max_speed,
            "escaped_bodies": escaped,
            "bodies_at_rest": int(at_rest.sum()),
            "bodies_asleep": int((self.dynamic & last.asleep).sum()),
            "broken_joints": 0 if last.joints is None else int((~last.joints["active"]).sum()),
            "divergence": divergence,
        }
        return {key: values.get(key) for key in DESCRIPTIONS}


def energy_conservation(scene: Scene) -> str:
    """What can change the scene's total energy physically: CONSERVED when every material is elastic and
    frictionless (restitution 1, friction 0) and nothing else does work, CONSERVED_WITHOUT_CONTACTS when
    only contacts can, else NOT_CONSERVED."""
    if any(getattr(scene, part, None) for part in ("joints", "emitters", "sinks")):
        return NOT_CONSERVED
    for body in scene.bodies:
        if body.type == "kinematic" and (any(body.velocity) or body.angular_velocity):
            return NOT_CONSERVED
        if body.type == "dynamic" and (body.linear_damping or body.angular_damping):
            return NOT_CONSERVED
    materials = [scene.material_of(body) for body in scene.bodies] + [
        scene.material(shape.material) for body in scene.bodies for shape in body.shapes or ()
        if shape.material is not None]
    elastic = all(m.restitution == 1.0 and m.friction == 0.0 for m in materials)
    return CONSERVED if elastic else CONSERVED_WITHOUT_CONTACTS


def sidecar_path(trajectory: Path) -> Path:
    """`<output stem>.summary.json` next to the trajectory."""
    return trajectory.with_name(f"{trajectory.stem}.summary.json")


def to_json(data: dict[str, Any]) -> str:
    """Strict JSON (non-finite numbers become null, at any depth), indented."""
    return json.dumps(_finite(data), indent=2)


def _finite(value: Any) -> Any:
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {key: _finite(item) for key, item in value.items()}
    if isinstance(value, list | tuple):
        return [_finite(item) for item in value]
    return value


def write_text_atomic(path: Path, text: str) -> None:
    """Write `text` under a temporary name in the same folder, then rename it to `path` (never over a
    device, pipe or socket)."""
    from .output_files import refuse_special
    from .trajectory import temporary_path

    refuse_special(path)
    temporary = temporary_path(path)
    try:
        temporary.write_text(text, encoding="utf-8")
        os.replace(temporary, path)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


def summary_table(summary: dict[str, Any], title: str) -> Table:
    """The summary as a two-column rich table (numbers with 6 significant digits, undefined ones left out)."""
    from rich.table import Table

    table = Table(title=title, show_header=False, title_justify="left")
    table.add_column("statistic", style="bold")
    table.add_column("value", overflow="fold")
    from .scenario import summary_columns

    for key, value in summary_columns(summary).items():
        if value is not None:
            table.add_row(key, f"{value:.6g}" if isinstance(value, float) else str(value))
    return table
