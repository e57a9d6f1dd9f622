"""The scene's questions to a run: `measures`, `world.stop_when` (and the run length `world.duration`), as
pydantic models, with the checks that need the whole scene (which bodies, generators and emitters exist,
which bodies are sensors), each reported at its own place.

A measure names what it measures as a dotted path: `bodies.<name>`, `generators.<name>`,
`emitters.<name>` or `all` (every dynamic body), then a quantity (`position.x`, ...); or
`observables.<name>` for one of the world's observables.
"""

from __future__ import annotations

import re
from collections.abc import Collection, Hashable, Mapping, Sequence
from typing import Any, Literal

from pydantic import ConfigDict, Field, model_validator
from pydantic_core import PydanticCustomError

from rustycs.events import EVENT_KIND_NAMES
from rustycs.measures import OBSERVABLE_NAMES, QUANTITY_NAMES

from .scene import Problem, Rect, _Model, _one_of, did_you_mean

EventKind = Literal[EVENT_KIND_NAMES]  # type: ignore[valid-type]
REDUCES = ("final", "initial", "max", "min", "mean")
AGGREGATES = ("mean", "sum", "min", "max", "median")
SET_KINDS = ("bodies", "generators", "emitters")


class FirstEvent(_Model):
    """The first event of a kind involving the bodies."""

    event: EventKind = Field(description="The event kind.", examples=["contact_begin"])
    bodies: list[str] = Field(
        [],
        max_length=2,
        description="One or two body names (or a generator or emitter: any of its bodies); with two, the "
        "event is between one of each. A joint_break names the joints: those joining the two, or with one "
        "name, any joint of its bodies. Empty: any event of the kind.",
        examples=[["ball", "floor"]],
    )


class TimeInside(_Model):
    """Seconds during which at least one of the bodies overlapped a sensor body."""

    sensor: str = Field(description="A body with a sensor shape.", examples=["goal"])
    bodies: list[str] = Field(
        min_length=1, description="Body, generator or emitter names.", examples=[["ball"]]
    )


class Measure(_Model):
    """A named result of a run, evaluated on every tick (not only on recorded frames); written into the
    summary and a sweep's table (`measure.<name>`). Give one of `of`, `first` or `time_inside`."""

    model_config = ConfigDict(
        json_schema_extra={
            "examples": [
                {"name": "range", "of": "bodies.ball.position.x"},
                {"name": "apex", "of": "bodies.ball.position.y", "reduce": "max"},
                {"name": "bins", "of": "generators.beads.position.x", "histogram": [-1, 0, 1]},
            ]
        }
    )

    name: str = Field(min_length=1, description="Unique name: the summary key and `measure.<name>` column.",
                      examples=["range"])
    of: str | None = Field(
        None,
        description="What is measured: `bodies.<name>`, `generators.<name>`, `emitters.<name>` or `all` "
        "(every dynamic body), followed by a quantity (" + ", ".join(QUANTITY_NAMES) + ") unless "
        "`count_inside` is given; or `observables.<name>` (" + ", ".join(OBSERVABLE_NAMES) + ").",
        examples=["bodies.ball.position.x"],
    )
    reduce: Literal[REDUCES] = Field(  # type: ignore[valid-type]
        "final", description="Over the ticks: the final or initial value, or the max, min or mean of every "
        "tick's value (tick 0 included).", examples=["max"]
    )
    at: float | None = Field(
        None, ge=0, description="Take the value at this time, s (the tick nearest it) instead of reducing; "
        "null when the run ends earlier.", examples=[1.0]
    )
    aggregate: Literal[AGGREGATES] | None = Field(  # type: ignore[valid-type]
        None, description="Over a set of bodies: mean, sum, min, max or median (default for a generator, "
        "emitter or all: mean). Only bodies that exist at the time (active) count; an empty set gives null.",
        examples=["mean"],
    )
    count_inside: Rect | None = Field(
        None, description="Count the bodies of the set whose centre is inside this rectangle.",
        examples=[{"min": [-1, -5], "max": [1, -4]}],
    )
    histogram: list[float] | None = Field(
        None, min_length=2, description="Count the bodies of the set per bin of the quantity: bin edges, "
        "strictly ascending (a bin holds its lower edge; the last also its upper edge). One column per bin.",
        examples=[[-3, -2, -1, 0, 1, 2, 3]],
    )
    first: FirstEvent | None = Field(
        None, description="The time, s, of the first such event; null if it never happens.",
        examples=[{"event": "contact_begin", "bodies": ["ball", "floor"]}],
    )
    time_inside: TimeInside | None = Field(
        None, description="Seconds during which at least one of the bodies overlapped the sensor body.",
        examples=[{"sensor": "goal", "bodies": ["ball"]}],
    )

    @model_validator(mode="after")
    def _one_form(self) -> Measure:
        given = [key for key in ("of", "first", "time_inside") if getattr(self, key) is not None]
        if len(given) != 1:
            raise PydanticCustomError("measure",
                                      "a measure needs exactly one of 'of', 'first' or 'time_inside'", {})
        if self.count_inside is not None and self.histogram is not None:
            raise PydanticCustomError("measure", "give count_inside or histogram, not both",
                                      {"at": "histogram"})
        edges = self.histogram or []
        if any(b <= a for a, b in zip(edges, edges[1:], strict=False)):
            raise PydanticCustomError("histogram", "histogram edges must be strictly ascending",
                                      {"at": "histogram"})
        if self.histogram is not None and self.reduce not in ("final", "initial"):
            raise PydanticCustomError("measure", "a histogram is taken at the end (final), the start "
                                      "(initial) or `at` a time", {"at": "reduce"})
        return self


class AtRest(_Model):
    """Every dynamic body at rest (speed < 1e-3 m/s, angular speed < 1e-3 rad/s) for this long."""

    at_rest: float = Field(gt=0, description="Seconds at rest.", examples=[0.5])


class OnEvent(_Model):
    """An event of a kind involving the bodies."""

    event: EventKind = Field(description="The event kind.", examples=["contact_begin"])
    bodies: list[str] = Field(
        [], max_length=2, description="One or two body, generator or emitter names, as in a measure's "
        "`first` (for a joint_break, the joints joining them). Empty: any event of the kind.",
        examples=[["ball", "floor"]]
    )


class Inside(_Model):
    """Every listed body has overlapped a sensor body for this long without a break."""

    model_config = ConfigDict(serialize_by_alias=True, validate_by_name=True)

    inside: str = Field(description="A body with a sensor shape.", examples=["goal"])
    bodies: list[str] = Field(min_length=1, description="Body names.", examples=[["ball"]])
    for_: float = Field(0.0, ge=0, alias="for", description="Seconds, default 0 (the first tick all are "
                        "inside).", examples=[3.0])


def _condition_tag(value: Any) -> str | None:
    if isinstance(value, AtRest | OnEvent | Inside):
        return {AtRest: "at_rest", OnEvent: "event", Inside: "inside"}[type(value)]
    if isinstance(value, Mapping):
        for key in ("at_rest", "event", "inside"):
            if key in value:
                return key
    return None


StopCondition = _one_of(
    _condition_tag,
    "stop_condition",
    "expected {at_rest: SECONDS}, {event: KIND, bodies: [...]} or "
    "{inside: SENSOR, bodies: [...], for: SECONDS}",
    at_rest=AtRest,
    event=OnEvent,
    inside=Inside,
)

STOP_WHEN_FIELD = Field(
    [],
    description="The run ends at the first tick where any of these holds (status `stopped`, `stop_reason` "
    "the condition as written).",
    examples=[[{"at_rest": 0.5}, {"inside": "goal", "bodies": ["ball"], "for": 3.0}]],
)
DURATION_FIELD = Field(
    None,
    gt=0,
    description="Run length in seconds (ticks = round(duration * tick_rate)); give `ticks` or `duration`, "
    "not both. `rustycs run --duration` overrides.",
    examples=[5.0],
)
MEASURES_FIELD = Field(
    [],
    description="Named results of the run, evaluated every tick: in the summary and one sweep column each.",
    examples=[[{"name": "range", "of": "bodies.ball.position.x"}]],
)


def describe_condition(condition: AtRest | OnEvent | Inside) -> str:
    """A stop condition as written in the scene (the `stop_reason`)."""
    import json

    return json.dumps(condition.model_dump(mode="json", by_alias=True), separators=(", ", ": "))


# ------------------------------------------------------------------------------- checks of the whole scene

_SET_PATH = re.compile(r"^(?:(bodies|generators|emitters)\.(.+?)|all)(?:\.(.*))?$")


def split_of(of: str, names: Mapping[str, set[str]]) -> tuple[str, str, str] | None:
    """(kind, name, quantity) of a measure's `of` ('all' has the name ''); the name is the longest known
    one that fits (names may hold dots). None when the path names no known set."""
    if of == "all" or of.startswith("all."):
        return "all", "", of[4:]
    kind, _, rest = of.partition(".")
    if kind not in SET_KINDS:
        return None
    candidates = [n for n in names.get(kind, ()) if rest == n or rest.startswith(n + ".")]
    if not candidates:
        return None
    name = max(candidates, key=len)
    return kind, name, rest[len(name) + 1:]


def joints_joining(joints: Sequence[tuple[Hashable, Hashable]],
                   sets: Sequence[Collection[Hashable]]) -> list[int]:
    """The joints (indices into `joints`, each its two bodies) that a joint_break's `bodies` name, each
    name given as its set of bodies: with one, every joint with a body in it; with two, every joint with a
    body in each."""
    if len(sets) == 1:
        return [j for j, (a, b) in enumerate(joints) if a in sets[0] or b in sets[0]]
    first, second = sets
    return [j for j, (a, b) in enumerate(joints)
            if (a in first and b in second) or (a in second and b in first)]


def measure_problems(data: Mapping[str, Any], bodies: Mapping[str, int],
                     generators: Mapping[str, int]) -> list[Problem]:
    """Measures and stop conditions that name an unknown body, generator, emitter, quantity or sensor, a
    quantity missing or given where none is taken, `ticks` with `duration`, and duplicate emitter and
    measure names. `bodies` and `generators` are the names written (with their indices). In a resolved
    scene (generators expanded), a generator is known by its bodies' names, '<name>-<i>'."""
    problems: list[Problem] = []
    emitters = [e for e in data.get("emitters") or [] if isinstance(e, dict)] if isinstance(
        data.get("emitters"), list) else []
    generated = set(generators) if "generators" in data else {
        match.group(1) for name in bodies if (match := re.match(r"^(.+)-\d+$", name))}
    names = {"bodies": set(bodies), "generators": generated,
             "emitters": {e["name"] for e in emitters if isinstance(e.get("name"), str)}}
    sensors = {name for name, i in bodies.items() if _has_sensor(data["bodies"][i])}
    seen_emitters: dict[str, int] = {}
    for i, emitter in enumerate(data.get("emitters") if isinstance(data.get("emitters"), list) else []):
        name = emitter.get("name") if isinstance(emitter, dict) else None
        if isinstance(name, str) and name in seen_emitters:
            problems.append((("emitters", i, "name"),
                             f"duplicate emitter name '{name}' (also emitter {seen_emitters[name]})"))
        elif isinstance(name, str):
            seen_emitters[name] = i
    every_name = {n for kind in SET_KINDS for n in names.get(kind, ())}

    def known(name: str) -> bool:  # a generated body is named '<generator>-<i>'
        match = re.match(r"^(.+)-\d+$", name)
        return name in every_name or bool(match and match.group(1) in names["generators"])

    def check_names(listed: Any, loc: tuple) -> None:
        if not isinstance(listed, list):
            return
        for k, name in enumerate(listed):
            if isinstance(name, str) and not known(name):
                problems.append(((*loc, k), f"unknown body, generator or emitter '{name}'"
                                 f"{did_you_mean(name, sorted(every_name))}"))

    def check_sensor(name: Any, loc: tuple) -> None:
        if isinstance(name, str) and name not in sensors:
            known = names.get("bodies", set())
            why = "is not a sensor (it has no shape with sensor: true)" if name in known else "is not a body"
            problems.append((loc, f"'{name}' {why}{did_you_mean(name, sorted(sensors))}"))

    from .scene_joints import written_joint_bodies  # scene_joints imports the scene, which imports this

    joints = written_joint_bodies(data)
    jointed = {name for pair in joints for name in pair if name is not None}

    def joined(name: str) -> set[str]:  # the jointed bodies a name stands for (emitted bodies have none)
        if name in names["bodies"] or name not in names["generators"]:
            return {name} & jointed
        return {b for b in jointed if re.fullmatch(re.escape(name) + r"-\d+", b)}

    def check_joints(spec: Mapping[str, Any], loc: tuple) -> None:  # a joint_break names joints by bodies
        listed = spec.get("bodies")
        if (spec.get("event") != "joint_break" or not isinstance(listed, list) or not listed
                or not all(isinstance(name, str) and known(name) for name in listed)):
            return
        if not joints_joining(joints, [joined(name) for name in listed]):
            written = " and ".join(f"'{name}'" for name in listed)
            problems.append((loc, f"no joint joins {written} (a joint_break's bodies name the joints "
                                  "that join them)"))

    listed = data.get("measures")
    seen: dict[str, int] = {}
    for i, measure in enumerate(listed if isinstance(listed, list) else []):
        if not isinstance(measure, dict):
            continue
        name = measure.get("name")
        if isinstance(name, str) and name in seen:
            problems.append((("measures", i, "name"),
                             f"duplicate measure name '{name}' (also measure {seen[name]})"))
        elif isinstance(name, str):
            seen[name] = i
        of = measure.get("of")
        if isinstance(of, str):
            problem = of_problem(of, names, counted=measure.get("count_inside") is not None)
            if problem:
                problems.append((("measures", i, "of"), problem))
        for form in ("first", "time_inside"):
            if isinstance(measure.get(form), dict):
                check_names(measure[form].get("bodies"), ("measures", i, form, "bodies"))
        if isinstance(measure.get("first"), dict):
            check_joints(measure["first"], ("measures", i, "first", "bodies"))
        if isinstance(measure.get("time_inside"), dict):
            check_sensor(measure["time_inside"].get("sensor"), ("measures", i, "time_inside", "sensor"))
    world = data.get("world")
    if isinstance(world, dict):
        if "ticks" in world and "duration" in world:
            problems.append((("world", "duration"), "give world.ticks or world.duration, not both"))
        stop_when = world.get("stop_when")
        for c, condition in enumerate(stop_when if isinstance(stop_when, list) else []):
            if isinstance(condition, dict):
                check_names(condition.get("bodies"), ("world", "stop_when", c, "bodies"))
                check_joints(condition, ("world", "stop_when", c, "bodies"))
                if "inside" in condition:
                    check_sensor(condition["inside"], ("world", "stop_when", c, "inside"))
    return problems


def _has_sensor(body: Any) -> bool:
    shapes = [body.get("shape")] if body.get("shape") is not None else body.get("shapes") or []
    return any(isinstance(shape, dict) and shape.get("sensor") is True for shape in shapes)


def of_problem(of: str, names: Mapping[str, set[str]], counted: bool) -> str | None:
    """Why a measure's `of` is wrong, or None."""
    if of.startswith("observables."):
        observable = of[len("observables."):]
        if observable not in OBSERVABLE_NAMES:
            return (f"unknown observable '{observable}'{did_you_mean(observable, OBSERVABLE_NAMES)}; "
                    f"one of: {', '.join(OBSERVABLE_NAMES)}")
        return None
    parts = split_of(of, names)
    if parts is None:
        kind, _, rest = of.partition(".")
        if kind in SET_KINDS:
            known = sorted(names.get(kind, ()))
            name = rest.split(".")[0]
            what = {"bodies": "body", "generators": "generator", "emitters": "emitter"}[kind]
            return f"unknown {what} '{name}'{did_you_mean(name, known)}"
        return ("expected bodies.<name>, generators.<name>, emitters.<name>, all or observables.<name>, "
                f"then a quantity{did_you_mean(kind, [*SET_KINDS, 'all', 'observables'])}")
    quantity = parts[2]
    if counted:
        return None if not quantity else "count_inside counts bodies: give no quantity after the set"
    if quantity not in QUANTITY_NAMES:
        got = f"unknown quantity '{quantity}'" if quantity else "missing quantity"
        return f"{got}{did_you_mean(quantity, QUANTITY_NAMES)}; one of: {', '.join(QUANTITY_NAMES)}"
    return None
