"""Joints in the scene format: one model per joint type, chosen by `type`, and the checks that need the
whole scene (the bodies and joints a joint names).

A joint joins two bodies (`bodies: [a, b]`) or one body to the fixed world (`body: b`); a gear joins two
other joints instead. Points are world points at the bodies' initial poses, as the engine takes them.
This module completes `scene.Scene` (its `joints` field) when it is imported, which `scene` does.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any, Literal

from pydantic import Field, field_validator, model_validator

from .scene import Loc, Problem, Scene, Vec2, _Model, _one_of, _problem, did_you_mean
from .scene_types import Name

COUPLED_BY_GEARS = ("revolute", "prismatic")


def _ordered(limits: tuple[float, float] | None) -> tuple[float, float] | None:
    if limits is not None and not limits[0] <= limits[1]:
        raise _problem("limits", "limits must be [lower, upper] with lower <= upper", at=1)
    return limits


def _direction(axis: tuple[float, float]) -> tuple[float, float]:
    if axis[0] == 0 and axis[1] == 0:
        raise _problem("axis", "the axis must not be [0, 0]: it is a direction")
    return axis


class Motor(_Model):
    """Drives the joint's rotation at `speed`, with at most `max_torque`."""

    speed: float = Field(0.0, description="Target speed, rad/s (counter-clockwise).", examples=[2.0])
    max_torque: float = Field(
        ge=0, description="The largest torque the motor applies, N m. >= 0.", examples=[50.0]
    )


class LinearMotor(_Model):
    """Drives the joint's translation at `speed`, with at most `max_force`."""

    speed: float = Field(0.0, description="Target speed along the axis, m/s.", examples=[0.5])
    max_force: float = Field(
        ge=0, description="The largest force the motor applies, N. >= 0.", examples=[200.0]
    )


class Spring(_Model):
    """Pulls the joint's angle (translation) back to its initial value, 0."""

    hertz: float = Field(ge=0, description="Natural frequency, Hz. >= 0 (0: no spring).", examples=[4.0])
    damping_ratio: float = Field(
        0.0, ge=0, description="1: critically damped; 0: undamped. >= 0.", examples=[0.7]
    )


class WeldSpring(_Model):
    """Makes a weld soft: springs about the initial relative pose."""

    linear_hertz: float = Field(
        0.0, ge=0, description="Natural frequency of the position, Hz. >= 0 (0: rigid).", examples=[5.0]
    )
    angular_hertz: float = Field(
        0.0, ge=0, description="Natural frequency of the angle, Hz. >= 0 (0: rigid).", examples=[2.0]
    )
    damping_ratio: float = Field(0.0, ge=0, description="Of both springs. >= 0.", examples=[0.7])


_LIMITS = "Lower and upper joint angle, rad, relative to the start; lower <= upper."
_TRANSLATION_LIMITS = "Lower and upper translation along the axis, m, relative to the start; lower <= upper."


class _Joint(_Model):
    """The keys of every joint."""

    name: Name | None = Field(
        None,
        min_length=1,
        description="Unique name, for overrides like joints.hinge.motor.speed. Default: '<type>-<index in "
        "joints>'.",
        examples=["hinge"],
    )
    type: str = Field(description="Joint kind.")  # narrowed by each joint; declared here to come first
    bodies: tuple[str, str] | None = Field(
        None,
        description="The two bodies joined, by name. Give `bodies` or `body`.",
        examples=[["base", "arm"]],
        json_schema_extra={"minItems": 2, "maxItems": 2},
    )
    body: str | None = Field(
        None,
        description="One body joined to the fixed world (the world is then the first of the two).",
        examples=["arm"],
    )
    collide_connected: bool = Field(
        False, description="true: the two bodies still collide with each other.", examples=[True]
    )
    break_force: float | None = Field(
        None,
        gt=0,
        description="N: the joint breaks (is removed, event `joint_break`) in the tick its reaction force "
        "exceeds this. Default: never.",
        examples=[500.0],
    )
    break_torque: float | None = Field(
        None,
        gt=0,
        description="N m: the joint breaks in the tick its reaction torque exceeds this. Default: never.",
        examples=[100.0],
    )

    @model_validator(mode="after")
    def _two_bodies(self) -> _Joint:
        if (self.bodies is None) == (self.body is None):
            given = self.bodies is not None
            raise _problem(
                "joint_bodies",
                "give either `bodies: [a, b]` or `body: b` (joined to the world), not both"
                if given
                else "missing key 'bodies' (two body names; or 'body' for one joined to the world)",
                at="body" if given else None,
                at_key=given,
            )
        if self.bodies is not None and self.bodies[0] == self.bodies[1]:
            raise _problem("joint_bodies", f"the joint names body '{self.bodies[1]}' twice", at=("bodies", 1))
        return self

    @property
    def body_names(self) -> tuple[str | None, str]:
        """(first, second) body names; None for the fixed world."""
        if self.bodies is not None:
            return self.bodies
        assert self.body is not None
        return None, self.body


class Revolute(_Joint):
    """The bodies share the anchor point and turn freely about it."""

    type: Literal["revolute"] = Field(description="Joint kind.", examples=["revolute"])
    anchor: Vec2 = Field(description="The world point joining the bodies [x, y], m.", examples=[[0, 2]])
    limits: Vec2 | None = Field(None, description=_LIMITS, examples=[[-0.5, 0.5]])
    motor: Motor | None = Field(
        None, description="Drives the joint angle.", examples=[{"speed": 2.0, "max_torque": 50}]
    )
    spring: Spring | None = Field(
        None,
        description="Pulls the joint angle back to 0.",
        examples=[{"hertz": 4.0, "damping_ratio": 0.7}],
    )

    _limits_ordered = field_validator("limits")(_ordered)


class Prismatic(_Joint):
    """The second body slides along `axis` relative to the first, without turning."""

    type: Literal["prismatic"] = Field(description="Joint kind.", examples=["prismatic"])
    anchor: Vec2 = Field(description="A world point on both bodies [x, y], m.", examples=[[0, 2]])
    axis: Vec2 = Field(
        (1.0, 0.0),
        description="World direction of the slide at the start; it turns with the first body.",
        examples=[[0, 1]],
    )
    limits: Vec2 | None = Field(None, description=_TRANSLATION_LIMITS, examples=[[-1.0, 1.0]])
    motor: LinearMotor | None = Field(
        None, description="Drives the translation.", examples=[{"speed": 0.5, "max_force": 200}]
    )
    spring: Spring | None = Field(
        None, description="Pulls the translation back to 0.", examples=[{"hertz": 2.0, "damping_ratio": 0.5}]
    )

    _limits_ordered = field_validator("limits")(_ordered)
    _axis_direction = field_validator("axis")(_direction)


_ANCHORS = Field(
    description="[[xa, ya], [xb, yb]]: a world point on each body at the start, m (with `body` alone, the "
    "world's point first).",
    examples=[[[0, 2], [0, 0]]],
)


class Distance(_Joint):
    """The anchor points stay `length` apart: a rod, or with `spring` a spring."""

    type: Literal["distance"] = Field(description="Joint kind.", examples=["distance"])
    anchors: tuple[Vec2, Vec2] = _ANCHORS
    length: float | None = Field(
        None,
        ge=0,
        description="Rest length, m. >= 0. Default: the anchors' initial distance.",
        examples=[1.0],
    )
    min_length: float | None = Field(
        None, ge=0, description="With a spring: the shortest it gets, m. >= 0. Default: 0.", examples=[0.5]
    )
    max_length: float | None = Field(
        None, ge=0, description="With a spring: the longest it gets, m. Default: no limit.", examples=[2.0]
    )
    spring: Spring | None = Field(
        None, description="Makes the rod a spring of this stiffness.", examples=[{"hertz": 2.0}]
    )

    @model_validator(mode="after")
    def _lengths_ordered(self) -> Distance:
        if self.min_length is not None and self.max_length is not None and self.min_length > self.max_length:
            raise _problem("limits", "min_length must not exceed max_length", at="max_length")
        return self


class Rope(_Joint):
    """The anchor points are at most `length` apart; slack is free."""

    type: Literal["rope"] = Field(description="Joint kind.", examples=["rope"])
    anchors: tuple[Vec2, Vec2] = _ANCHORS
    length: float | None = Field(
        None, ge=0, description="Longest distance, m. >= 0. Default: the anchors' initial distance.",
        examples=[1.5],
    )


class Weld(_Joint):
    """The bodies move as one (softly, with `spring`)."""

    type: Literal["weld"] = Field(description="Joint kind.", examples=["weld"])
    anchor: Vec2 = Field(description="The world point joining the bodies [x, y], m.", examples=[[0, 2]])
    spring: WeldSpring | None = Field(
        None,
        description="Makes the weld soft. Default: rigid.",
        examples=[{"linear_hertz": 5.0, "angular_hertz": 2.0, "damping_ratio": 0.7}],
    )


class Wheel(_Joint):
    """A car wheel: the second body slides along `axis` on a spring (the suspension) and turns freely."""

    type: Literal["wheel"] = Field(description="Joint kind.", examples=["wheel"])
    anchor: Vec2 = Field(description="The wheel's centre, a world point [x, y], m.", examples=[[1, 0.5]])
    axis: Vec2 = Field(
        (0.0, 1.0),
        description="World direction of the suspension at the start; it turns with the first body.",
        examples=[[0, 1]],
    )
    spring: Spring | None = Field(
        None, description="The suspension.", examples=[{"hertz": 4.0, "damping_ratio": 0.7}]
    )
    limits: Vec2 | None = Field(None, description=_TRANSLATION_LIMITS, examples=[[-0.2, 0.2]])
    motor: Motor | None = Field(
        None, description="Drives the wheel's rotation.", examples=[{"speed": -10.0, "max_torque": 40}]
    )

    _limits_ordered = field_validator("limits")(_ordered)
    _axis_direction = field_validator("axis")(_direction)


class Gear(_Model):
    """Couples two revolute or prismatic joints: angle_1 + ratio * angle_2 stays constant (translations
    for prismatic joints)."""

    name: Name | None = _Joint.model_fields["name"]
    type: Literal["gear"] = Field(description="Joint kind.", examples=["gear"])
    joints: tuple[str, str] = Field(
        description="The two revolute or prismatic joints coupled, by name.",
        examples=[["wheel_1", "wheel_2"]],
        json_schema_extra={"minItems": 2, "maxItems": 2},
    )
    ratio: float = Field(
        1.0, description="coordinate_1 + ratio * coordinate_2 stays constant.", examples=[2.0]
    )
    collide_connected: bool = _Joint.model_fields["collide_connected"]
    break_force: float | None = _Joint.model_fields["break_force"]
    break_torque: float | None = _Joint.model_fields["break_torque"]

    @field_validator("joints")
    @classmethod
    def _two_joints(cls, joints: tuple[str, str]) -> tuple[str, str]:
        if joints[0] == joints[1]:
            raise _problem("gear", f"the gear names joint '{joints[1]}' twice", at=1)
        return joints


class Pulley(_Joint):
    """Two bodies hang from two fixed world points: length_a + ratio * length_b stays constant."""

    type: Literal["pulley"] = Field(description="Joint kind.", examples=["pulley"])
    anchors: tuple[Vec2, Vec2] = Field(
        description="[[xa, ya], [xb, yb]]: the rope's end on each body, world points at the start, m.",
        examples=[[[-1, 0], [1, 0]]],
    )
    ground_anchors: tuple[Vec2, Vec2] = Field(
        description="[[x, y], [x, y]]: the fixed points each side hangs from, m.",
        examples=[[[-1, 3], [1, 3]]],
    )
    ratio: float = Field(
        1.0, gt=0, description="length_a + ratio * length_b stays constant. > 0.", examples=[2.0]
    )

    @model_validator(mode="after")
    def _both_bodies(self) -> Pulley:
        if self.bodies is None:
            raise _problem("joint_bodies", "a pulley hangs two bodies: give `bodies: [a, b]`", at="body",
                           at_key=True)
        return self


JOINTS = {
    "revolute": Revolute,
    "prismatic": Prismatic,
    "distance": Distance,
    "rope": Rope,
    "weld": Weld,
    "wheel": Wheel,
    "gear": Gear,
    "pulley": Pulley,
}


def _joint_tag(value: Any) -> str | None:
    kind = value.get("type") if isinstance(value, dict) else getattr(value, "type", None)
    return kind if isinstance(kind, str) else None


Joint = _one_of(_joint_tag, "joint", f"expected a joint {{type: {' | '.join(JOINTS)}, ...}}", **JOINTS)


def default_joint_name(kind: Any, index: int) -> str:
    """The name of an unnamed joint: '<type>-<index in joints>'."""
    return f"{kind}-{index}"


def written_joint_bodies(data: Mapping[str, Any]) -> list[tuple[str | None, str | None]]:
    """The two bodies of each joint of the raw scene data, by name, as the engine's rows take them: None
    for the fixed world (or what is not a name); a gear's bodies are its joints' second bodies."""
    listed = data.get("joints")
    pairs: list[tuple[str | None, str | None]] = []
    second: dict[str, str | None] = {}  # joint name -> its second body
    for j, joint in enumerate(listed if isinstance(listed, list) else []):
        joint = joint if isinstance(joint, dict) else {}
        named = joint.get("joints") if joint.get("type") == "gear" else joint.get("bodies")
        if not (isinstance(named, list) and len(named) == 2):
            named = [None, joint.get("body")]
        elif joint.get("type") == "gear":
            named = [second.get(other) if isinstance(other, str) else None for other in named]
        a, b = (name if isinstance(name, str) else None for name in named)
        pairs.append((a, b))
        name = joint.get("name", default_joint_name(joint.get("type"), j))
        if isinstance(name, str):
            second[name] = b
    return pairs


def joint_problems(data: Mapping[str, Any], body_names: Sequence[str]) -> list[Problem]:
    """Problems of the joints that involve other entries: duplicate joint names, unknown bodies, and gears
    naming joints that are unknown or not revolute or prismatic. Works on the raw scene data."""
    listed = data.get("joints")
    if not isinstance(listed, list):
        return []
    problems: list[Problem] = []
    known = set(body_names)
    kinds: dict[str, Any] = {}
    order: dict[str, int] = {}
    for j, joint in enumerate(listed):
        if not isinstance(joint, dict):
            continue
        name = joint.get("name", default_joint_name(joint.get("type"), j))
        if isinstance(name, str) and name in kinds:
            problems.append((("joints", j, "name"), f"duplicate joint name '{name}'"))
        elif isinstance(name, str):
            kinds[name], order[name] = joint.get("type"), j
        named = joint.get("bodies")
        places: list[tuple[Loc, Any]] = (
            [(("joints", j, "bodies", k), b) for k, b in enumerate(named)] if isinstance(named, list) else []
        )
        places.append((("joints", j, "body"), joint.get("body")))
        for loc, body in places:
            if isinstance(body, str) and body not in known:
                problems.append((loc, f"unknown body '{body}'{did_you_mean(body, list(known))}"))
    for j, joint in enumerate(listed):
        coupled = joint.get("joints") if isinstance(joint, dict) and joint.get("type") == "gear" else None
        for k, other in enumerate(coupled if isinstance(coupled, list) else ()):
            loc = ("joints", j, "joints", k)
            if isinstance(other, str) and other not in kinds:
                problems.append((loc, f"unknown joint '{other}'{did_you_mean(other, list(kinds))}"))
            elif isinstance(other, str) and kinds[other] not in COUPLED_BY_GEARS:
                problems.append((loc, f"a gear couples revolute or prismatic joints; '{other}' is a "
                                      f"{kinds[other]} joint"))
            elif isinstance(other, str) and order[other] > j:
                problems.append((loc, f"list the gear after the joints it couples ('{other}' comes later)"))
    return problems


Scene.model_rebuild(_types_namespace={"Joint": Joint})
