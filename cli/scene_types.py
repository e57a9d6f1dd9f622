"""Strict, finite, bounded value types for the scene models.

A scene value must be what it says: a number is a YAML number (not `true`, not "0.5", not 10.0 for a
count), finite (no .inf, no .nan, no 1e309), and inside the range the engine computes correctly or the
machine can hold (cli/limits.py). A value outside its range is refused with the limit named, and the JSON
Schema carries the same bounds (`minimum`/`maximum`, and a `$comment` naming the limit). Names are free
of control characters and bounded; a scene name, which becomes a file name, also stays inside its folder.

Use these types for every number and name of a scene model, e.g. `radius: PositiveLength = Field(...)`.
"""

from __future__ import annotations

import unicodedata
from dataclasses import dataclass
from typing import Annotated, Any

from annotated_types import Gt
from pydantic import (
    AfterValidator,
    AllowInfNan,
    GetCoreSchemaHandler,
    GetJsonSchemaHandler,
    Strict,
    WithJsonSchema,
)
from pydantic.json_schema import JsonSchemaValue
from pydantic_core import PydanticCustomError, core_schema

from . import limits
from .limits import Limit


@dataclass(frozen=True)
class Within:
    """Bounds a number: at least `low` (a Limit, or a plain number that needs no name such as 0) and at
    most `high`; `symmetric` bounds the magnitude |value| <= high instead."""

    low: Limit | float | None = None
    high: Limit | None = None
    symmetric: bool = False

    def __get_pydantic_core_schema__(
        self, source: Any, handler: GetCoreSchemaHandler
    ) -> core_schema.CoreSchema:
        return core_schema.no_info_after_validator_function(self.check, handler(source))

    def __get_pydantic_json_schema__(
        self, schema: core_schema.CoreSchema, handler: GetJsonSchemaHandler
    ) -> JsonSchemaValue:
        json = handler(schema)
        low = -self.high.value if self.symmetric and self.high else _value(self.low)
        if low is not None:
            json["minimum"] = max(low, json.get("minimum", low))
        if self.high is not None:
            json["maximum"] = min(self.high.value, json.get("maximum", self.high.value))
        named = [limit.name for limit in (self.low, self.high) if isinstance(limit, Limit)]
        if named:
            json["$comment"] = f"limits: {', '.join(named)} (docs/limits.md)"
        return json

    def check(self, value: Any) -> Any:
        high = self.high
        if high is not None and self.symmetric and abs(value) > high.value:
            raise _limit_error(f"must be from -{high.value:g} to {high}")
        if high is not None and value > high.value:
            raise _limit_error(f"must be at most {high}")
        low = self.low
        if isinstance(low, Limit) and value < low.value:
            raise _limit_error(f"must be at least {low}")
        if low is not None and not isinstance(low, Limit) and value < low:
            raise _limit_error(f"must be at least {low:g}")
        return value


def _value(limit: Limit | float | None) -> float | None:
    return limit.value if isinstance(limit, Limit) else limit


def _limit_error(message: str) -> PydanticCustomError:
    return PydanticCustomError("limit", message.replace("{", "{{").replace("}", "}}"))


# ------------------------------------------------------------------------------------------- numbers

FiniteFloat = Annotated[float, Strict(), AllowInfNan(False)]
"""Any finite number (an integer is fine); not a bool, not a string."""
StrictInt = Annotated[int, Strict()]
"""A whole number written as one: 10, not 10.0, true or "10"."""

Coordinate = Annotated[FiniteFloat, Within(high=limits.MAX_COORDINATE, symmetric=True)]
PositiveLength = Annotated[FiniteFloat, Gt(0), Within(limits.MIN_LENGTH, limits.MAX_LENGTH)]
Length = Annotated[FiniteFloat, Within(0.0, limits.MAX_LENGTH)]
Distance = Annotated[FiniteFloat, Gt(0), Within(limits.MIN_LENGTH, limits.MAX_COORDINATE)]
Speed = Annotated[FiniteFloat, Within(high=limits.MAX_SPEED, symmetric=True)]
Angle = Annotated[FiniteFloat, Within(high=limits.MAX_ANGLE, symmetric=True)]
AngularSpeed = Annotated[FiniteFloat, Within(high=limits.MAX_ANGULAR_SPEED, symmetric=True)]
Acceleration = Annotated[FiniteFloat, Within(high=limits.MAX_ACCELERATION, symmetric=True)]
Mass = Annotated[FiniteFloat, Gt(0), Within(limits.MIN_MASS, limits.MAX_MASS)]
Density = Annotated[FiniteFloat, Gt(0), Within(limits.MIN_DENSITY, limits.MAX_DENSITY)]
Restitution = FiniteFloat  # 0..1, bounded by its field
Friction = Annotated[FiniteFloat, Within(0.0, limits.MAX_FRICTION)]
Damping = Annotated[FiniteFloat, Within(0.0, limits.MAX_DAMPING)]
Factor = Annotated[FiniteFloat, Within(high=limits.MAX_FACTOR, symmetric=True)]
Rate = Annotated[FiniteFloat, Gt(0), Within(limits.MIN_TICK_RATE, limits.MAX_TICK_RATE)]
SleepTime = Annotated[FiniteFloat, Gt(0), Within(high=limits.MAX_SLEEP_TIME)]

Ticks = Annotated[StrictInt, Within(0, limits.MAX_TICKS)]
Every = Annotated[StrictInt, Within(1, limits.MAX_TICKS)]
Precision = Annotated[StrictInt, Within(1, limits.PRECISION)]
Seed = Annotated[StrictInt, Within(0, limits.MAX_SEED)]
Count = Annotated[StrictInt, Within(0, limits.MAX_BODIES)]
SmallInt = Annotated[StrictInt, Within(high=limits.MAX_GROUP, symmetric=True)]
CollisionGroup = SmallInt
CollisionBits = Annotated[StrictInt, Within(-1, limits.MAX_BITS)]


def _pair(item: Any, schema: dict[str, Any]) -> Any:
    """A list of two values, like [x, y], in the schema as an array of two numbers."""
    return Annotated[tuple[item, item], WithJsonSchema(
        {"type": "array", "items": {"type": "number", **schema}, "minItems": 2, "maxItems": 2}
    )]


def _bounds(limit: Limit) -> dict[str, Any]:
    comment = f"limit: {limit.name} (docs/limits.md)"
    return {"minimum": -limit.value, "maximum": limit.value, "$comment": comment}


FinitePair = _pair(FiniteFloat, {})
Point = _pair(Coordinate, _bounds(limits.MAX_COORDINATE))
VelocityPair = _pair(Speed, _bounds(limits.MAX_SPEED))
AccelerationPair = _pair(Acceleration, _bounds(limits.MAX_ACCELERATION))

# --------------------------------------------------------------------------------------------- names


def _printable(text: str) -> str:
    """`text` when it holds no control character (NUL, newline, escape ...) and is not too long."""
    if len(text) > limits.MAX_NAME_LENGTH.value:
        raise _limit_error(f"a name has at most {limits.MAX_NAME_LENGTH}, this one has {len(text)}")
    if any(unicodedata.category(char) in ("Cc", "Cs") for char in text):
        raise PydanticCustomError(
            "name", "a name must not contain control characters (NUL, newline, tab ...)"
        )
    return text


def _file_safe(text: str) -> str:
    """`text` when it can name a file inside the output folder (the scene name names its outputs)."""
    if "/" in text or "\\" in text or text in (".", ".."):
        raise PydanticCustomError(
            "name", "a scene name names its output files: it must not contain / or \\ nor be . or .."
        )
    return text


def _no_nul(text: str) -> str:
    if len(text) > limits.MAX_TEXT_LENGTH.value:
        raise _limit_error(f"a text has at most {limits.MAX_TEXT_LENGTH}, this one has {len(text)}")
    if "\0" in text:
        raise PydanticCustomError("text", "a text must not contain NUL characters")
    return text


def _name_schema(extra: dict[str, Any]) -> WithJsonSchema:
    return WithJsonSchema({"type": "string", "minLength": 1, "maxLength": limits.MAX_NAME_LENGTH.value,
                           "$comment": "limit: MAX_NAME_LENGTH (docs/limits.md)", **extra})


Name = Annotated[
    str, Strict(), AfterValidator(_printable), _name_schema({"pattern": "^[^\\x00-\\x1f\\x7f]*$"})
]
"""A name of a body, force, attractor, generator or material: printable and at most MAX_NAME_LENGTH."""
SceneName = Annotated[
    str, Strict(), AfterValidator(_printable), AfterValidator(_file_safe),
    _name_schema({"pattern": "^(?!\\.\\.?$)[^/\\\\\\x00-\\x1f\\x7f]*$"}),
]
"""A scene name: a Name that can also name files inside the output folder."""
Text = Annotated[str, Strict(), AfterValidator(_no_nul)]
"""Free text (a description): no NUL, at most MAX_TEXT_LENGTH characters."""
