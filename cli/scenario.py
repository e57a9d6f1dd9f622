"""A scene's run beyond its bodies: the emitted bodies it reserves, its sinks, measures and stop conditions
handed to the engine, and the measures' results as the summary and the sweep's table hold them."""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from .scene import Scene  # before the modules below, whose models the scene's models import
from .scene_emitters import emitted_bodies
from .scene_measures import Inside, OnEvent, describe_condition, joints_joining, split_of

if TYPE_CHECKING:
    import rustycs


@dataclass(frozen=True)
class RunPlan:
    """The scene with its emitted bodies after its own (`scene.bodies`), and when each body appears and
    goes."""

    scene: Scene
    spawn_ticks: list[int]
    remove_ticks: list[int | None]
    if_free: list[bool]  # appears only where its place is free (an emitter's placement: no_overlap)
    emitted: dict[str, list[str]]  # emitter name -> its bodies

    def timing(self, index: int) -> dict[str, Any]:
        return {"spawn_tick": self.spawn_ticks[index], "remove_tick": self.remove_ticks[index],
                "if_free": self.if_free[index]}


def plan_run(scene: Scene, ticks: int) -> RunPlan:
    """The bodies of a run of `ticks` ticks: the scene's, then every body its emitters may emit."""
    emitted = emitted_bodies(scene, ticks)
    listed = len(scene.bodies)
    return RunPlan(scene.model_copy(update={"bodies": [*scene.bodies, *emitted.bodies]}),
                   [0] * listed + emitted.spawn_ticks, [None] * listed + emitted.remove_ticks,
                   [False] * listed + emitted.if_free, emitted.by_emitter)


class _Sets:
    """Body names and sets of a run, as lists of body rows."""

    def __init__(self, plan: RunPlan, body_types: list[str]):
        self.plan = plan
        names = [body.name for body in plan.scene.bodies]
        self.row = {name: i for i, name in enumerate(names)}
        self.dynamic = [i for i, kind in enumerate(body_types) if kind == "dynamic"]
        self.generated: dict[str, list[int]] = {}
        for i, name in enumerate(names[: len(names) - sum(map(len, plan.emitted.values()))]):
            match = re.match(r"^(.+)-\d+$", str(name))
            if match:
                self.generated.setdefault(match.group(1), []).append(i)

    def of(self, kind: str, name: str) -> list[int]:
        if kind == "all":
            return self.dynamic
        if kind == "bodies":
            return [self.row[name]]
        if kind == "emitters":
            return [self.row[n] for n in self.plan.emitted[name]]
        return self.generated.get(name, [])

    def named(self, names: list[str]) -> list[int]:
        """A body, or an emitter's or generator's bodies, per name, together."""
        rows: list[int] = []
        for name in names:
            if name in self.row:
                rows.append(self.row[name])
            elif name in self.plan.emitted:
                rows += self.of("emitters", name)
            else:
                rows += self.generated.get(name, [])
        return rows

    def names(self) -> dict[str, set[str]]:
        return {"bodies": set(self.row), "generators": set(self.generated),
                "emitters": set(self.plan.emitted)}


def attach(world: rustycs.World, plan: RunPlan, contact_events: bool) -> None:
    """Give the world the scene's sinks, measures and stop conditions (and whether it records contact
    events)."""
    scene = plan.scene
    rate = scene.world.tick_rate
    sets = _Sets(plan, list(world.body_types))
    world.contact_events = contact_events
    for sink in scene.sinks:
        world.add_sink(sink.region.min, sink.region.max)
    for measure in scene.measures:
        timing = ({"reduce": "at", "at_tick": round(measure.at * rate)} if measure.at is not None
                  else {"reduce": measure.reduce})
        if measure.first is not None:
            bodies, others = _event_rows(world, sets, measure.first.event, measure.first.bodies)
            world.add_measure("first", event=measure.first.event, bodies=bodies, others=others)
        elif measure.time_inside is not None:
            world.add_measure("time_inside", bodies=sets.named(measure.time_inside.bodies),
                              sensor=sets.row[measure.time_inside.sensor])
        elif measure.of is not None and measure.of.startswith("observables."):
            world.add_measure("value", quantity=measure.of, **timing)
        else:
            assert measure.of is not None
            kind, name, quantity = split_of(measure.of, sets.names()) or ("", "", "")
            bodies = sets.of(kind, name)
            if measure.count_inside is not None:
                world.add_measure("count_inside", bodies=bodies,
                                  region=(*measure.count_inside.min, *measure.count_inside.max), **timing)
            elif measure.histogram is not None:
                world.add_measure("histogram", bodies=bodies, quantity=quantity, edges=measure.histogram,
                                  **timing)
            else:
                one = kind == "bodies" and measure.aggregate is None
                world.add_measure("value", bodies=bodies, quantity=quantity,
                                  aggregate="one" if one else measure.aggregate or "mean", **timing)
    for condition in scene.world.stop_when:
        if isinstance(condition, OnEvent):
            bodies, others = _event_rows(world, sets, condition.event, condition.bodies)
            world.add_stop_condition("event", event=condition.event, bodies=bodies, others=others)
        elif isinstance(condition, Inside):
            world.add_stop_condition("inside", sensor=sets.row[condition.inside],
                                     bodies=sets.named(condition.bodies),
                                     hold_ticks=round(condition.for_ * rate))
        else:
            world.add_stop_condition("at_rest", hold_ticks=round(condition.at_rest * rate))


def _event_rows(world: rustycs.World, sets: _Sets, event: str,
                names: list[str]) -> tuple[list[int], list[int]]:
    """The engine's two lists of an event's `bodies` (one or two names): body rows, the event between one
    of each when there are two lists. A joint_break names its joint in place of a body, so its names
    become the rows of the joints joining those bodies, one list."""
    rows = [sets.named([name]) for name in names]
    if event == "joint_break" and rows:
        pairs = [(int(a), int(b)) for a, b in world.joint_bodies]
        joints = joints_joining(pairs, [set(r) for r in rows])
        assert joints, "a scene check reports bodies with no joint between them"
        return joints, []  # else an empty list: any joint
    return (rows[0] if rows else []), (rows[1] if len(rows) > 1 else [])


def stop_reason(world: rustycs.World, scene: Scene) -> str | None:
    """The stop condition that ended the run, as written in the scene, or None."""
    index = world.stop_condition
    return None if index is None else describe_condition(scene.world.stop_when[index])


def measure_results(world: rustycs.World, scene: Scene) -> dict[str, Any]:
    """Each measure by name: a number, None, or a histogram's counts."""
    return {measure.name: (None if isinstance(value, float) and not math.isfinite(value) else value)
            for measure, value in zip(scene.measures, world.measure_results(), strict=True)}


def emitter_counts(world: rustycs.World, plan: RunPlan) -> dict[str, dict[str, int]]:
    """Per emitter: its bodies that appeared by the world's tick, and those skipped (placement:
    no_overlap) because their place was taken."""
    skipped = world.skipped
    row = {body.name: i for i, body in enumerate(plan.scene.bodies)}
    counts = {}
    for emitter, names in plan.emitted.items():
        due = [row[name] for name in names if plan.spawn_ticks[row[name]] <= world.tick]
        missed = int(sum(skipped[i] for i in due))
        counts[emitter] = {"appeared": len(due) - missed, "skipped": missed}
    return counts


def summary_columns(summary: dict[str, Any]) -> dict[str, Any]:
    """The summary as flat columns (HDF5 attributes, the `rustycs run` table, a sweep's rows): its
    measures as `measure.<name>` (`measure_columns`), its emitters' counts as `emitter.<name>.appeared`
    and `emitter.<name>.skipped`."""
    columns = {key: value for key, value in summary.items() if key not in ("measures", "emitters")}
    columns.update(measure_columns(summary.get("measures") or {}))
    for emitter, counts in (summary.get("emitters") or {}).items():
        columns.update({f"emitter.{emitter}.{key}": count for key, count in counts.items()})
    return columns


def measure_columns(measures: dict[str, Any]) -> dict[str, Any]:
    """The measures as flat columns: `measure.<name>`, a histogram `measure.<name>[k]` per bin."""
    columns: dict[str, Any] = {}
    for name, value in measures.items():
        if isinstance(value, list):
            columns.update({f"measure.{name}[{k}]": count for k, count in enumerate(value)})
        else:
            columns[f"measure.{name}"] = value
    return columns
