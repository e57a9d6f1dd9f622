"""The scene format (version 1) as pydantic models: the single source of the JSON Schema and of validation.

Every field carries a description, a default and an example, because `rustycs schema` turns these models
into the schema that editors use to complete and check scene files. Checks that need the whole scene
(unique names, known materials) live in `scene_problems`, so that each problem can be reported at its own
place. Whether a polygon is valid is the engine's decision (`rustycs.polygon`), so that both agree. A
body's shapes are one list after validation (`Body.shapes`), whether the file wrote `shape` or `shapes`.
The navigation helpers at the end (`resolve_annotation`, `model_fields_at`, `child_annotation`) let
overrides and error messages walk the same types as the data, e.g. to suggest a key.
"""

from __future__ import annotations

import difflib
import functools
import operator
import types
import typing
from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import Annotated, Any, Literal

from pydantic import (
    BaseModel,
    ConfigDict,
    Discriminator,
    Field,
    ModelWrapValidatorHandler,
    SerializerFunctionWrapHandler,
    Tag,
    ValidationError,
    ValidationInfo,
    WithJsonSchema,
    field_validator,
    model_serializer,
    model_validator,
)
from pydantic.fields import FieldInfo
from pydantic_core import ErrorDetails, InitErrorDetails, PydanticCustomError

from rustycs import defaults
from rustycs.materials import MATERIALS
from rustycs.polygon import MAX_POLYGON_VERTICES, polygon_problem
from rustycs.shapes import MAX_CHAIN_POINTS

from .scene_types import (
    AccelerationPair,
    Angle,
    AngularSpeed,
    CollisionBits,
    CollisionGroup,
    Count,
    Damping,
    Density,
    Distance,
    Every,
    Factor,
    FiniteFloat,
    FinitePair,
    Friction,
    Length,
    Mass,
    Name,
    Point,
    PositiveLength,
    Precision,
    Rate,
    Restitution,
    SceneName,
    Seed,
    SleepTime,
    SmallInt,
    Speed,
    Text,
    Ticks,
    VelocityPair,
)

if typing.TYPE_CHECKING:
    from .scene_joints import Joint

Loc = tuple[str | int, ...]
Problem = tuple[Loc, str]

_VEC2_SCHEMA = {"type": "array", "items": {"type": "number"}, "minItems": 2, "maxItems": 2}
Vec2 = Annotated[tuple[float, float], WithJsonSchema(_VEC2_SCHEMA)]
BodyType = Literal["static", "dynamic", "kinematic"]


def did_you_mean(word: str, candidates: Sequence[str]) -> str:
    """' (did you mean 'x'?)' for the closest candidate to a misspelt word, or ''."""
    close = difflib.get_close_matches(word, [str(c) for c in candidates], n=1)
    return f" (did you mean '{close[0]}'?)" if close else ""


class _Model(BaseModel):
    """Base of every scene model: unknown keys are errors, and no number is infinite or NaN (the
    models' bounded types in `scene_types` say more; this holds for every field whatever its type)."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)


def _one_of(tagger: Callable[[Any], str | None], error_type: str, message: str, **members: Any) -> Any:
    """A union whose member is chosen by `tagger` (so that errors come from that member only)."""
    choices = [Annotated[annotation, Tag(tag)] for tag, annotation in members.items()]
    return Annotated[
        functools.reduce(operator.or_, choices),
        Discriminator(tagger, custom_error_type=error_type, custom_error_message=message),
    ]


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _key_tag(value: Any, keys: Sequence[str]) -> str | None:
    """The tag of a one-key mapping such as {uniform: [0, 1]}; a near miss of a key selects that key, so
    that the error names the misspelt key."""
    if isinstance(value, _Keyed):
        return value.key()
    if not isinstance(value, dict) or not value:
        return None
    for key in value:
        if key in keys:
            return str(key)
    close = difflib.get_close_matches(str(next(iter(value))), list(keys), n=1)
    return close[0] if close else None


class _Keyed(_Model):
    """A mapping with a single key that names its kind, like {uniform: [lo, hi]} or {pyramid: {...}}."""

    def key(self) -> str:
        return next(iter(type(self).model_fields))


# ---------------------------------------------------------------------------------------------- materials


class Material(_Model):
    """A material: its density gives a body's mass; restitution and friction of a contact are the means of
    the two bodies' values."""

    density: Density = Field(gt=0, description="Mass per area, kg/m^2. > 0.", examples=[1.2])
    restitution: Restitution = Field(
        ge=0, le=1, description="Bounciness, 0 (none) to 1 (elastic).", examples=[0.5]
    )
    friction: Friction = Field(ge=0, description="Coulomb friction coefficient, >= 0.", examples=[0.6])


PRESET_MATERIALS: dict[str, Material] = {
    name: Material(density=m.density, restitution=m.restitution, friction=m.friction)
    for name, m in MATERIALS.items()
}
_PRESET_VALUES = ", ".join(
    f"{name} ({m.density:g}, {m.restitution:g}, {m.friction:g})" for name, m in PRESET_MATERIALS.items()
)


def _material_tag(value: Any) -> str | None:
    if isinstance(value, str):
        return "name"
    if isinstance(value, (dict, Material)):
        return "inline"
    return None


MaterialRef = _one_of(
    _material_tag,
    "material",
    "expected a material name or an inline material {density, restitution, friction}",
    name=str,
    inline=Material,
)

# ------------------------------------------------------------------------------------------------- shapes

_AABB_TURNS = "an aabb never rotates, so its angle must be 0: use shape type obb for a turned box"


def _no_turn_of_aabb(angle: Any) -> Any:
    """`angle` when it is 0; raises for any other angle (or distribution) of an aabb."""
    if not (_is_number(angle) and angle == 0):
        raise PydanticCustomError("aabb_angle", _AABB_TURNS)
    return angle


def _problem(
    kind: str, message: str, at: Any = None, at_key: bool = False, **ctx: Any
) -> PydanticCustomError:
    """A validation error located below the place it is raised at: `at` is a key, an index or a tuple of
    them; `at_key` points at that key itself rather than its value."""
    if at is not None:
        ctx["at"] = at
    if at_key:
        ctx["at_key"] = True
    return PydanticCustomError(kind, message, ctx)


class _Shape(_Model):
    """The keys every shape of a body takes besides its geometry: where it sits on the body, what it is
    made of, and whether it only detects overlaps."""

    type: str = Field(description="Shape kind.")  # narrowed by each shape; declared here to come first
    offset: Point = Field(
        (0.0, 0.0),
        description="Where the shape's origin sits in the body's frame [x, y], m.",
        examples=[[0, -0.9]],
    )
    angle: Angle = Field(
        0.0, description="The shape's rotation in the body's frame, rad, counter-clockwise.", examples=[0.5]
    )
    material: MaterialRef | None = Field(
        None,
        description="The shape's material: a preset, a name from `materials`, or an inline "
        "{density, restitution, friction}. Default: the body's.",
        examples=["rubber"],
    )
    sensor: bool = Field(
        False,
        description="A sensor detects overlaps but never collides: it pushes nothing and adds no mass.",
        examples=[True],
    )

    has_area: typing.ClassVar[bool] = True

    @property
    def adds_mass(self) -> bool:
        """Whether the shape gives its body mass (sensors, segments and chains give none)."""
        return self.has_area and not self.sensor


class Circle(_Shape):
    """A circle centred on the shape's origin."""

    type: Literal["circle"] = Field(description="Shape kind.", examples=["circle"])
    radius: PositiveLength = Field(gt=0, description="Radius, m. > 0.", examples=[0.5])


class Aabb(_Shape):
    """An axis-aligned box centred on the shape's origin. It never rotates, so neither it nor its body
    may be given an angle (its body has fixed rotation); use `obb` for a box that turns."""

    type: Literal["aabb"] = Field(description="Shape kind.", examples=["aabb"])
    width: PositiveLength = Field(gt=0, description="Extent along x, m. > 0.", examples=[12.0])
    height: PositiveLength = Field(gt=0, description="Extent along y, m. > 0.", examples=[0.5])

    _angle_is_zero = field_validator("angle")(_no_turn_of_aabb)


class Obb(_Shape):
    """An oriented box centred on the shape's origin; the body's `angle` (and the shape's) turn it."""

    type: Literal["obb"] = Field(description="Shape kind.", examples=["obb"])
    width: PositiveLength = Field(
        gt=0, description="Extent along the shape's local x axis, m. > 0.", examples=[1.0]
    )
    height: PositiveLength = Field(
        gt=0, description="Extent along the shape's local y axis, m. > 0.", examples=[1.0]
    )


class _PolygonGeometry(_Model):
    """A simple polygon's vertices; whether they are one is the engine's decision (`polygon_problem`)."""

    vertices: list[Point] = Field(
        description=f"3 to {MAX_POLYGON_VERTICES} points [x, y], m, in the shape's frame: a simple polygon "
        "(no two edges cross or touch), convex or not, either winding.",
        examples=[[[0, 0], [1, 0], [0, 1]]],
        json_schema_extra={"minItems": 3, "maxItems": MAX_POLYGON_VERTICES},
    )

    @field_validator("vertices", mode="before")
    @classmethod
    def _not_too_many(cls, vertices: Any) -> Any:
        """The engine's cheap count check, before each vertex is validated: a list of a million vertices
        is refused at once."""
        if isinstance(vertices, list) and len(vertices) > MAX_POLYGON_VERTICES:
            _raise_polygon_problem(vertices)
        return vertices

    @field_validator("vertices")
    @classmethod
    def _simple_polygon(cls, vertices: list[tuple[float, float]]) -> list[tuple[float, float]]:
        _raise_polygon_problem(vertices)
        return vertices


def _raise_polygon_problem(vertices: Any) -> None:
    """Raise the engine's problem with these vertices (at the vertex it names), if it finds one."""
    problem = polygon_problem(vertices)
    if problem is not None:
        raise _problem("polygon", problem.message, at=problem.vertex)


class Polygon(_PolygonGeometry, _Shape):
    """A polygon. Vertices are placed exactly as written in the shape's frame; its body's centre of mass
    is the area centroid."""

    type: Literal["polygon"] = Field(description="Shape kind.", examples=["polygon"])


class Capsule(_Shape):
    """Two half-discs joined by a box: the centres of the end circles are `length` apart on the shape's
    local x axis, centred on its origin."""

    type: Literal["capsule"] = Field(description="Shape kind.", examples=["capsule"])
    length: Length = Field(
        ge=0,
        description="Distance between the centres of the end circles, m, along the shape's x axis. >= 0 "
        "(0: a circle).",
        examples=[1.0],
    )
    radius: PositiveLength = Field(gt=0, description="Radius of the end circles, m. > 0.", examples=[0.25])


def _count_of(points: Any, least: int, most: int, what: str) -> Any:
    """`points` when a list of `least`..`most` items (or not a list: the item checks report it). Checked
    before the items, so that a list far too long is refused at once."""
    if isinstance(points, list) and not least <= len(points) <= most:
        counts = f"exactly {least}" if least == most else f"{least} to {most}"
        raise _problem("point_count", f"{what} has {counts} points, this one has {len(points)}")
    return points


class _SegmentGeometry(_Model):
    """A segment's two end points."""

    points: list[Point] = Field(
        description="The two end points [[x0, y0], [x1, y1]], m, in the shape's frame.",
        examples=[[[-1, 0], [1, 0]]],
        json_schema_extra={"minItems": 2, "maxItems": 2},
    )

    @field_validator("points", mode="before")
    @classmethod
    def _two_points(cls, points: Any) -> Any:
        return _count_of(points, 2, 2, "a segment")

    @field_validator("points")
    @classmethod
    def _apart(cls, points: list[tuple[float, float]]) -> list[tuple[float, float]]:
        if points[0] == points[1]:
            raise _problem("segment", "the segment's two points are the same: it has no length", at=1)
        return points


class Segment(_SegmentGeometry, _Shape):
    """A line between two points, with no area and no mass."""

    type: Literal["segment"] = Field(description="Shape kind.", examples=["segment"])
    has_area: typing.ClassVar[bool] = False


class _ChainGeometry(_Model):
    """A chain's points and whether it closes."""

    points: list[Point] = Field(
        description=f"2 to {MAX_CHAIN_POINTS} points [x, y], m, in the shape's frame, joined in order by "
        "segments; no two consecutive points equal.",
        examples=[[[-3, 0], [0, -1], [3, 0]]],
        json_schema_extra={"minItems": 2, "maxItems": MAX_CHAIN_POINTS},
    )
    loop: bool = Field(
        False,
        description="true: a segment also joins the last point to the first (at least 3 points; do not "
        "repeat the first point at the end).",
        examples=[True],
    )

    @field_validator("points", mode="before")
    @classmethod
    def _point_count(cls, points: Any) -> Any:
        return _count_of(points, 2, MAX_CHAIN_POINTS, "a chain")

    @model_validator(mode="after")
    def _no_zero_length_segment(self) -> Any:
        points = self.points
        if self.loop and len(points) < 3:
            raise _problem("chain", f"a loop needs at least 3 points, this one has {len(points)}", at="loop")
        for i in range(1, len(points)):
            if points[i] == points[i - 1]:
                raise _problem(
                    "chain",
                    f"point {i} repeats point {i - 1}: consecutive points must differ",
                    at=("points", i),
                )
        if self.loop and points[-1] == points[0]:
            raise _problem(
                "chain",
                "the last point repeats the first: a loop joins its last point to its first by itself",
                at=("points", len(points) - 1),
            )
        return self


class Chain(_ChainGeometry, _Shape):
    """A polyline of segments, with no area and no mass; bodies slide and roll along it smoothly, nothing
    catches at the joints between its segments."""

    type: Literal["chain"] = Field(description="Shape kind.", examples=["chain"])
    has_area: typing.ClassVar[bool] = False


def _shape_tag(value: Any) -> str | None:
    if isinstance(value, dict):
        if "choice" in value and "type" not in value:
            return "choice"
        kind = value.get("type")
        return kind if isinstance(kind, str) else None
    kind = getattr(value, "type", None)
    if kind is None and isinstance(value, _Keyed):
        return value.key()
    return kind


def _shape_error(kinds: Iterable[str]) -> str:
    return f"expected a shape {{type: {' | '.join(kinds)}, ...}}"


_SHAPES = {
    "circle": Circle,
    "aabb": Aabb,
    "obb": Obb,
    "polygon": Polygon,
    "capsule": Capsule,
    "segment": Segment,
    "chain": Chain,
}
Shape = _one_of(_shape_tag, "shape", _shape_error(_SHAPES), **_SHAPES)


def _line_error(error: ErrorDetails) -> InitErrorDetails:
    """A reported validation error as one that can be raised again (with more errors)."""
    return InitErrorDetails(
        type=PydanticCustomError(error["type"], error["msg"], error.get("ctx")),
        loc=error["loc"],
        input=error["input"],
    )


def _shape_keys(cls: type[BaseModel], data: Any, handler: ModelWrapValidatorHandler[Any]) -> Any:
    """Validate a mapping that gives its shape as `shape` or its shapes as `shapes`: giving both (reported
    at the second) or neither is a problem, reported with the others in the mapping."""
    if not isinstance(data, dict):
        return handler(data)
    given = [key for key, value in data.items() if key in ("shape", "shapes") and value is not None]
    if len(given) == 1:
        return handler(data)
    if given:
        problem = _problem(
            "shape_keys", "give either `shape` or `shapes`, not both", at=given[1], at_key=True
        )
    else:
        problem = _problem(
            "missing_key",
            "missing key 'shape' (or 'shapes' for several)",
            at="shape",
            keys=("shape", "shapes"),
        )
    errors: list[InitErrorDetails] = []
    try:
        handler(data)
    except ValidationError as err:
        errors = [_line_error(e) for e in err.errors()]
    errors.append(InitErrorDetails(type=problem, loc=(), input=data))
    raise ValidationError.from_exception_data(cls.__name__, errors)


# ------------------------------------------------------------------------------------------------- bodies


class Body(_Model):
    """One rigid body, made of one shape (`shape`) or several fixed to it (`shapes`)."""

    model_config = ConfigDict(
        json_schema_extra={"oneOf": [{"required": ["shape"]}, {"required": ["shapes"]}]}
    )

    name: Name | None = Field(
        None,
        min_length=1,
        description="Unique name: the body's id in every output. Default: '<shape type>-<index in bodies>', "
        "or 'compound-<index in bodies>' for a body of several shapes.",
        examples=["crate"],
    )
    type: BodyType = Field(
        defaults.BODY_TYPE,
        description="static: never moves; dynamic: moved by forces and contacts; kinematic: moves with its "
        "own velocity, pushes dynamic bodies, unaffected by forces and contacts.",
        examples=["static"],
    )
    shape: Shape | None = Field(
        None,
        description="The body's one shape (chosen by its `type`). Give `shape` or `shapes`.",
        examples=[{"type": "circle", "radius": 0.2}],
    )
    # After validation, `shapes` lists the body's shapes in either form ([shape] for a body given `shape`,
    # which is still written back as `shape`).
    shapes: list[Shape] | None = Field(
        None,
        min_length=1,
        description="Several shapes fixed to the body, each placed by its `offset` and `angle`. Give `shape` "
        "or `shapes`.",
        examples=[
            [
                {"type": "obb", "width": 2.0, "height": 0.2, "offset": [0, -0.9]},
                {"type": "circle", "radius": 0.5, "sensor": True},
            ]
        ],
    )
    position: Point = Field(
        description="The body's origin [x, y], m (the centre for circles and boxes).", examples=[[0, 2]]
    )
    velocity: VelocityPair = Field(
        (0.0, 0.0), description="Initial centre-of-mass velocity [vx, vy], m/s.", examples=[[1, 0]]
    )
    angle: Angle = Field(
        0.0,
        description="Initial orientation, rad, counter-clockwise. Must be 0 for a body with an aabb shape.",
        examples=[0.3],
    )
    angular_velocity: AngularSpeed = Field(
        0.0, description="Initial angular velocity, rad/s, counter-clockwise.", examples=[2.0]
    )
    material: MaterialRef = Field(
        defaults.MATERIAL,
        description=f"A preset ({', '.join(PRESET_MATERIALS)}), a name from `materials`, or an "
        "inline {density, restitution, friction}; the material of every shape that names none.",
        examples=["rubber", {"density": 2.0, "restitution": 0.1, "friction": 0.9}],
    )
    mass: Mass | None = Field(
        None,
        gt=0,
        description="Mass, kg, overriding area x density; inertia scales with it. Default: area x density.",
        examples=[3.0],
    )
    collision_group: CollisionGroup = Field(
        defaults.COLLISION_GROUP,
        description="Two bodies with the same non-zero group never collide with each other (0: collides "
        "with everything).",
        examples=[1],
    )
    collision_category: CollisionBits = Field(
        defaults.COLLISION_CATEGORY,
        ge=0,
        description="Bits: the categories this body belongs to. Two bodies collide only when "
        "(category_a & mask_b) != 0 and (category_b & mask_a) != 0.",
        examples=[2],
    )
    collision_mask: CollisionBits = Field(
        defaults.COLLISION_MASK,
        ge=-1,
        description="Bits: the categories this body collides with (-1: all).",
        examples=[5],
    )
    linear_damping: Damping = Field(
        defaults.LINEAR_DAMPING,
        ge=0,
        description="1/s: the velocity decays as dv/dt = -c v. >= 0.",
        examples=[0.1],
    )
    angular_damping: Damping = Field(
        defaults.ANGULAR_DAMPING,
        ge=0,
        description="1/s: the angular velocity decays as dw/dt = -c w. >= 0.",
        examples=[0.1],
    )
    gravity_scale: Factor = Field(
        defaults.GRAVITY_SCALE,
        description="Multiplies the world force (the sum of `forces`) for this body; attractors are "
        "unaffected.",
        examples=[0.5],
    )
    fixed_rotation: bool = Field(False, description="true: the body never rotates.", examples=[True])
    bullet: bool = Field(
        False,
        description="true: continuous collision against dynamic bodies too, so that a fast body never "
        "passes through anything.",
        examples=[True],
    )

    _shape_or_shapes = model_validator(mode="wrap")(_shape_keys)

    @field_validator("angle")
    @classmethod
    def _aabb_does_not_turn(cls, angle: float, info: ValidationInfo) -> float:
        shapes = info.data.get("shapes") or [info.data.get("shape")]
        if any(isinstance(shape, Aabb) for shape in shapes):
            return _no_turn_of_aabb(angle)
        return angle

    @model_validator(mode="after")
    def _one_list_of_shapes(self) -> Body:
        form = "shape" if self.shape is not None else "shapes"
        if self.shape is not None:
            self.shapes = [self.shape]
        if self.type == "dynamic" and not any(shape.adds_mass for shape in self.shapes or ()):
            raise _problem(
                "no_area",
                "a dynamic body needs at least one shape with area (not a sensor, segment or chain)",
                at=form,
                at_key=True,
            )
        return self

    @model_serializer(mode="wrap")
    def _written_as_given(self, handler: SerializerFunctionWrapHandler) -> dict[str, Any]:
        data = handler(self)
        data.pop("shapes" if self.shape is not None else "shape", None)
        return data


class Force(_Model):
    """A constant acceleration on every dynamic body (all forces are summed into one world force)."""

    name: Name | None = Field(
        None,
        description="Optional name, for overrides like forces.gravity.acceleration.",
        examples=["gravity"],
    )
    acceleration: AccelerationPair = Field(description="Acceleration [ax, ay], m/s^2.", examples=[[0, -9.81]])


class Attractor(_Model):
    """A fixed point pulling dynamic bodies with the acceleration G*M/d^2 towards it, whatever their mass."""

    name: Name | None = Field(
        None, description="Optional name, for overrides like attractors.sun.mass.", examples=["sun"]
    )
    position: Point = Field(description="Position [x, y], m.", examples=[[0, 0]])
    mass: Mass = Field(gt=0, description="M, kg. > 0.", examples=[1000.0])
    range: Distance | None = Field(
        None,
        gt=0,
        description="Only bodies within this distance, m, are pulled. Default: no limit.",
        examples=[5.0],
    )
    min_distance: Distance = Field(
        defaults.MIN_DISTANCE,
        gt=0,
        description="Softening: d is taken as max(d, min_distance), m.",
        examples=[0.1],
    )


class Rect(_Model):
    """An axis-aligned rectangle given by its corners."""

    min: Point = Field(description="Lower-left corner [x, y], m.", examples=[[-100, -100]])
    max: Point = Field(description="Upper-right corner [x, y], m.", examples=[[100, 100]])

    @model_validator(mode="after")
    def _ordered(self) -> Rect:
        if not (self.min[0] < self.max[0] and self.min[1] < self.max[1]):
            raise PydanticCustomError("rect", "min must be below and left of max on both axes", {"at": "max"})
        return self


from .scene_measures import (  # noqa: E402  (built on the models above)
    DURATION_FIELD,
    MEASURES_FIELD,
    STOP_WHEN_FIELD,
    Measure,
    StopCondition,
    measure_problems,
)


class World(_Model):
    """Time stepping and world-wide settings."""

    tick_rate: Rate = Field(
        defaults.TICK_RATE, gt=0, description="Ticks per second; dt = 1 / tick_rate. > 0.", examples=[240]
    )
    ticks: Ticks = Field(
        600,
        ge=0,
        description="Default run length in ticks (`rustycs run --ticks` overrides).",
        examples=[1200],
    )
    precision: Precision = Field(
        defaults.PRECISION,
        ge=1,
        description="Solver substeps per tick (the thesis's collision precision): each substep of "
        "dt / precision applies the forces, solves contacts and joints and moves the bodies. More substeps "
        "hold stacks and joints stiffer and cost more time per tick. >= 1.",
        examples=[10],
    )
    gravitational_constant: Factor = Field(
        defaults.GRAVITATIONAL_CONSTANT, ge=0, description="G used by attractors.", examples=[1.0]
    )
    bounds: Rect | None = Field(
        None,
        description="A dynamic body whose centre leaves this box is deactivated (frozen, no longer "
        "collides) and counted as escaped. Default: unbounded.",
        examples=[{"min": [-100, -100], "max": [100, 100]}],
    )
    restitution_threshold: Speed = Field(
        defaults.RESTITUTION_THRESHOLD,
        ge=0,
        description="Contacts approaching slower than this, m/s, do not bounce (addition).",
        examples=[1.0],
    )
    sleep: bool = Field(
        defaults.SLEEP,
        description="true: dynamic bodies that rest together (touching or jointed) for sleep_time s fall "
        "asleep: they keep their place and skip the solver until an awake or moving body touches one of "
        "them or a joint ties one to it. Where nothing falls asleep, results are those of sleep: false.",
        examples=[True],
    )
    sleep_time: SleepTime = Field(
        defaults.SLEEP_TIME,
        gt=0,
        description="Seconds a group of touching bodies must rest before it sleeps (with sleep: true). > 0.",
        examples=[0.5],
    )
    duration: float | None = DURATION_FIELD
    stop_when: list[StopCondition] = STOP_WHEN_FIELD

    @property
    def run_ticks(self) -> int:
        """The run length in ticks: from `duration` when given, else `ticks`."""
        return self.ticks if self.duration is None else round(self.duration * self.tick_rate)

    @model_serializer(mode="wrap")
    def _one_run_length(self, handler: SerializerFunctionWrapHandler) -> dict[str, Any]:
        data = handler(self)
        data.pop("ticks" if self.duration is not None else "duration", None)
        return _without_unused(data, stop_when=[], sleep=defaults.SLEEP, sleep_time=defaults.SLEEP_TIME)


class Output(_Model):
    """What a run records."""

    every: Every = Field(
        1, ge=1, description="Record every N ticks (tick 0 is always recorded).", examples=[4]
    )
    contacts: bool = Field(False, description="Also record every contact point.", examples=[True])
    events: bool = Field(
        False,
        description="Also record contact_begin / contact_end events (the other events always).",
        examples=[True],
    )

    @model_serializer(mode="wrap")
    def _written_when_used(self, handler: SerializerFunctionWrapHandler) -> dict[str, Any]:
        return _without_unused(handler(self), events=False)


def _without_unused(data: dict[str, Any], **unused: Any) -> dict[str, Any]:
    """A model's data without the keys of emitters, measures and stop conditions left at these values, so a
    scene that does not use them resolves to the same text (and hash) as before they existed."""
    return {key: value for key, value in data.items() if key not in unused or value != unused[key]}


# ----------------------------------------------------------------------------------------------- generators


class Uniform(_Keyed):
    """A value drawn uniformly from [lo, hi)."""

    uniform: FinitePair = Field(description="[lo, hi]", examples=[[0.1, 0.3]])

    @model_validator(mode="after")
    def _ordered(self) -> Uniform:
        if self.uniform[0] > self.uniform[1]:
            raise PydanticCustomError("range", "lo must not exceed hi", {"at": "uniform"})
        return self


class UniformInt(_Keyed):
    """A whole number drawn uniformly from lo..hi (both included)."""

    uniform_int: tuple[SmallInt, SmallInt] = Field(description="[lo, hi], inclusive", examples=[[3, 8]])

    @model_validator(mode="after")
    def _ordered(self) -> UniformInt:
        if self.uniform_int[0] > self.uniform_int[1]:
            raise PydanticCustomError("range", "lo must not exceed hi", {"at": "uniform_int"})
        return self


class Normal(_Keyed):
    """A value drawn from a normal distribution."""

    normal: FinitePair = Field(description="[mean, standard deviation]", examples=[[0.0, 0.5]])

    @model_validator(mode="after")
    def _spread(self) -> Normal:
        if self.normal[1] < 0:
            raise PydanticCustomError("range", "the standard deviation must be >= 0", {"at": "normal"})
        return self


class NumberChoice(_Keyed):
    """One of the listed numbers, each equally likely."""

    choice: list[FiniteFloat] = Field(
        min_length=1, description="The numbers to choose from.", examples=[[0.1, 0.2]]
    )


_DISTRIBUTIONS = ("uniform", "uniform_int", "normal", "choice")


def _number_tag(value: Any) -> str | None:
    return "number" if _is_number(value) else _key_tag(value, _DISTRIBUTIONS)


Number = _one_of(
    _number_tag,
    "number",
    "expected a number or a distribution: {uniform: [lo, hi]}, {uniform_int: [lo, hi]}, "
    "{normal: [mean, std]} or {choice: [a, b, ...]}",
    number=FiniteFloat,
    uniform=Uniform,
    uniform_int=UniformInt,
    normal=Normal,
    choice=NumberChoice,
)
NumberPair = tuple[Number, Number]


class BodyTypeChoice(_Keyed):
    """One of the listed body types, each equally likely."""

    choice: list[BodyType] = Field(
        min_length=1, description="Body types to choose from.", examples=[["dynamic", "static"]]
    )


class MaterialChoice(_Keyed):
    """One of the listed materials, each equally likely."""

    choice: list[MaterialRef] = Field(
        min_length=1,
        description="Materials (names or inline) to choose from.",
        examples=[["rubber", "plastic", "stone", "metal"]],
    )


def _named_tag(value: Any) -> str | None:
    if isinstance(value, (str, Material)):
        return "name" if isinstance(value, str) else "inline"
    if isinstance(value, (dict, _Keyed)):
        return "choice" if _key_tag(value, ("choice",)) == "choice" else "inline"
    return None


GeneratedBodyType = _one_of(
    lambda v: "name" if isinstance(v, str) else _key_tag(v, ("choice",)),
    "body_type",
    "expected static, dynamic, kinematic or {choice: [...]}",
    name=BodyType,
    choice=BodyTypeChoice,
)
GeneratedMaterial = _one_of(
    _named_tag,
    "material",
    "expected a material name, an inline material {density, restitution, friction} or {choice: [...]}",
    name=str,
    inline=Material,
    choice=MaterialChoice,
)


class _GeneratedShape(_Model):
    """The keys every generated shape takes besides its geometry; numbers may be distributions."""

    type: str = Field(description="Shape kind.")  # narrowed by each shape; declared here to come first
    offset: NumberPair = Field(
        (0.0, 0.0),
        description="Where the shape's origin sits in the body's frame [x, y], m; each a number or a "
        "distribution.",
        examples=[[0, {"uniform": [-0.1, 0.1]}]],
    )
    angle: Number = Field(
        0.0,
        description="The shape's rotation in the body's frame, rad (number or distribution).",
        examples=[{"uniform": [-0.5, 0.5]}],
    )
    material: GeneratedMaterial | None = Field(
        None,
        description="Material name, inline material, or {choice: [...]}. Default: the body's.",
        examples=["rubber"],
    )
    sensor: bool = Field(
        False,
        description="A sensor detects overlaps but never collides: it pushes nothing and adds no mass.",
        examples=[True],
    )


class RandomCircle(_GeneratedShape):
    """A circle whose radius may be drawn."""

    type: Literal["circle"] = Field(description="Shape kind.", examples=["circle"])
    radius: Number = Field(
        description="Radius, m (number or distribution).", examples=[{"uniform": [0.1, 0.5]}]
    )


class RandomAabb(_GeneratedShape):
    """An axis-aligned box whose size may be drawn (its angle, and its bodies', must be 0)."""

    type: Literal["aabb"] = Field(description="Shape kind.", examples=["aabb"])
    width: Number = Field(description="Width, m (number or distribution).", examples=[1.0])
    height: Number = Field(
        description="Height, m (number or distribution).", examples=[{"uniform": [0.2, 1]}]
    )

    _angle_is_zero = field_validator("angle")(_no_turn_of_aabb)


class RandomObb(_GeneratedShape):
    """An oriented box whose size may be drawn."""

    type: Literal["obb"] = Field(description="Shape kind.", examples=["obb"])
    width: Number = Field(description="Width, m (number or distribution).", examples=[{"uniform": [0.2, 1]}])
    height: Number = Field(description="Height, m (number or distribution).", examples=[0.5])


class RandomCapsule(_GeneratedShape):
    """A capsule whose length and radius may be drawn."""

    type: Literal["capsule"] = Field(description="Shape kind.", examples=["capsule"])
    length: Number = Field(
        description="Distance between the centres of the end circles, m (number or distribution).",
        examples=[{"uniform": [0.5, 1.5]}],
    )
    radius: Number = Field(
        description="Radius of the end circles, m (number or distribution).", examples=[0.2]
    )


class GeneratedPolygon(_PolygonGeometry, _GeneratedShape):
    """A polygon of fixed vertices, placed on its bodies by an offset and angle that may be drawn."""

    type: Literal["polygon"] = Field(description="Shape kind.", examples=["polygon"])


class GeneratedSegment(_SegmentGeometry, _GeneratedShape):
    """A segment of fixed points, placed on its bodies by an offset and angle that may be drawn."""

    type: Literal["segment"] = Field(description="Shape kind.", examples=["segment"])


class GeneratedChain(_ChainGeometry, _GeneratedShape):
    """A chain of fixed points, placed on its bodies by an offset and angle that may be drawn."""

    type: Literal["chain"] = Field(description="Shape kind.", examples=["chain"])


class RandomPolygon(_GeneratedShape):
    """A random convex polygon inscribed in a circle: `vertices` points at jittered, evenly spread angles."""

    type: Literal["random_polygon"] = Field(description="Shape kind.", examples=["random_polygon"])
    vertices: Number = Field(
        description=f"Vertex count, a whole number 3..{MAX_POLYGON_VERTICES} "
        "(number, {uniform_int: [lo, hi]} or {choice: [...]}).",
        examples=[{"uniform_int": [3, 8]}],
    )
    radius: Number = Field(
        description="Radius of the circle the vertices lie on, m (number or distribution).",
        examples=[{"uniform": [0.3, 0.6]}],
    )

    @field_validator("vertices")
    @classmethod
    def _whole_counts(cls, spec: Any) -> Any:
        values = (
            [spec]
            if isinstance(spec, float)
            else list(spec.uniform_int)
            if isinstance(spec, UniformInt)
            else spec.choice
            if isinstance(spec, NumberChoice)
            else None
        )
        if values is None or any(v != int(v) or not 3 <= v <= MAX_POLYGON_VERTICES for v in values):
            raise PydanticCustomError(
                "vertex_count",
                f"the vertex count must be a whole number from 3 to {MAX_POLYGON_VERTICES}: a number, "
                "{uniform_int: [lo, hi]} or {choice: [...]}",
                {},
            )
        return spec


_GENERATED_SHAPES = {
    "circle": RandomCircle,
    "aabb": RandomAabb,
    "obb": RandomObb,
    "polygon": GeneratedPolygon,
    "capsule": RandomCapsule,
    "segment": GeneratedSegment,
    "chain": GeneratedChain,
    "random_polygon": RandomPolygon,
}
_GENERATED_SHAPE_ERROR = _shape_error(_GENERATED_SHAPES)
GeneratedSingleShape = _one_of(_shape_tag, "shape", _GENERATED_SHAPE_ERROR, **_GENERATED_SHAPES)


class ShapeChoice(_Keyed):
    """One of the listed shapes, each equally likely."""

    choice: list[GeneratedSingleShape] = Field(
        min_length=1,
        description="Shapes to choose from.",
        examples=[[{"type": "circle", "radius": 0.3}, {"type": "obb", "width": 0.5, "height": 0.5}]],
    )


GeneratedShape = _one_of(
    _shape_tag,
    "shape",
    _GENERATED_SHAPE_ERROR + " or {choice: [shape, ...]}",
    **_GENERATED_SHAPES,
    choice=ShapeChoice,
)


class PyramidParams(_Model):
    """Rows of bodies, each row one shorter and centred on the row below."""

    base: Count = Field(ge=1, description="Bodies in the bottom row.", examples=[20])
    origin: Point = Field(description="Centre of the bottom row [x, y], m.", examples=[[0, 0.5]])
    spacing: Point = Field(
        description="[dx, dy]: distance between neighbours in a row and between rows, m.",
        examples=[[1.0, 1.0]],
    )


class StackParams(_Model):
    """A vertical column of bodies, bottom up."""

    origin: Point = Field(description="Position of the bottom body [x, y], m.", examples=[[0, 0.5]])
    spacing: PositiveLength = Field(
        gt=0, description="Vertical distance between consecutive bodies, m.", examples=[1.0]
    )


class GridParams(_Model):
    """Rows of `columns` bodies, filled left to right, bottom up."""

    origin: Point = Field(description="Position of the bottom-left body [x, y], m.", examples=[[-9, 1]])
    columns: Count = Field(ge=1, description="Bodies per row.", examples=[20])
    spacing: Point = Field(
        description="[dx, dy]: distance between columns and between rows, m.", examples=[[0.6, 0.6]]
    )
    jitter: Point = Field(
        (0.0, 0.0),
        description="Each position is moved by a uniform offset in [-jx, jx] x [-jy, jy], m.",
        examples=[[0.05, 0.05]],
    )


class Pyramid(_Keyed):
    """Pyramid layout: the full pyramid has base*(base+1)/2 bodies."""

    pyramid: PyramidParams = Field(
        description="Pyramid parameters.", examples=[{"base": 20, "origin": [0, 0.5], "spacing": [1, 1]}]
    )


class Stack(_Keyed):
    """Stack layout."""

    stack: StackParams = Field(description="Stack parameters.", examples=[{"origin": [0, 0.5], "spacing": 1}])


class Grid(_Keyed):
    """Grid layout."""

    grid: GridParams = Field(
        description="Grid parameters.", examples=[{"origin": [-9, 1], "columns": 20, "spacing": [0.6, 0.6]}]
    )


Layout = _one_of(
    lambda v: _key_tag(v, ("pyramid", "stack", "grid")),
    "layout",
    "expected a layout {pyramid: {...}}, {stack: {...}} or {grid: {...}}",
    pyramid=Pyramid,
    stack=Stack,
    grid=Grid,
)


class Generator(_Model):
    """Many bodies from one entry, named '<name>-<i>'. Numeric fields may be distributions; positions are
    drawn uniformly in `region` unless a `layout` places them."""

    model_config = ConfigDict(json_schema_extra=Body.model_config["json_schema_extra"])

    name: Name | None = Field(
        None,
        min_length=1,
        description="Names the bodies '<name>-<i>' and seeds the generator's random "
        "numbers (with the scene's seed). Default: 'generator-<index>'.",
        examples=["rain"],
    )
    count: Count | None = Field(
        None,
        ge=0,
        description="Number of bodies. Required, except for a pyramid layout, where it defaults "
        "to the full pyramid.",
        examples=[500],
    )
    type: GeneratedBodyType = Field(
        defaults.BODY_TYPE, description="Body type of every body, or {choice: [...]}.", examples=["dynamic"]
    )
    shape: GeneratedShape | None = Field(
        None,
        description="Shape, whose sizes may be distributions; also {type: random_polygon, vertices, radius} "
        "and {choice: [shape, ...]}. Give `shape` or `shapes`.",
        examples=[{"type": "circle", "radius": {"uniform": [0.1, 0.3]}}],
    )
    shapes: list[GeneratedShape] | None = Field(
        None,
        min_length=1,
        description="Several shapes fixed to each body, as in `shape`, each placed by its `offset` and "
        "`angle` (numbers or distributions). Give `shape` or `shapes`.",
        examples=[
            [
                {"type": "obb", "width": 1.0, "height": 0.2},
                {"type": "obb", "width": 0.2, "height": 1.0, "offset": [-0.4, 0.4]},
            ]
        ],
    )
    region: Rect | None = Field(
        None,
        description="Positions are drawn uniformly in this rectangle (when no layout is given).",
        examples=[{"min": [-9, 5], "max": [9, 40]}],
    )
    layout: Layout | None = Field(
        None,
        description="Places bodies in a pyramid, stack or grid instead of a random region.",
        examples=[{"grid": {"origin": [-9, 1], "columns": 20, "spacing": [0.6, 0.6]}}],
    )
    angle: Number = Field(
        0.0,
        description="Initial angle, rad (number or distribution).",
        examples=[{"uniform": [-3.14159, 3.14159]}],
    )
    velocity: NumberPair = Field(
        (0.0, 0.0),
        description="Initial velocity [vx, vy], m/s; each a number or a distribution.",
        examples=[[0, {"uniform": [-1, 1]}]],
    )
    angular_velocity: Number = Field(
        0.0,
        description="Initial angular velocity, rad/s (number or distribution).",
        examples=[{"normal": [0, 1]}],
    )
    material: GeneratedMaterial = Field(
        defaults.MATERIAL,
        description="Material name, inline material, or {choice: [...]}.",
        examples=[{"choice": ["rubber", "plastic", "stone", "metal"]}],
    )
    mass: Number | None = Field(
        None,
        description="Mass override, kg (number or distribution). Default: area x density.",
        examples=[1.0],
    )
    collision_group: CollisionGroup = Field(
        defaults.COLLISION_GROUP, description="collision_group of every body.", examples=[0]
    )
    collision_category: CollisionBits = Field(
        defaults.COLLISION_CATEGORY, ge=0, description="collision_category of every body.", examples=[2]
    )
    collision_mask: CollisionBits = Field(
        defaults.COLLISION_MASK, ge=-1, description="collision_mask of every body.", examples=[5]
    )
    linear_damping: Number = Field(
        defaults.LINEAR_DAMPING,
        description="linear_damping of every body, 1/s (number or distribution).",
        examples=[{"uniform": [0, 0.5]}],
    )
    angular_damping: Number = Field(
        defaults.ANGULAR_DAMPING,
        description="angular_damping of every body, 1/s (number or distribution).",
        examples=[0.1],
    )
    gravity_scale: Number = Field(
        defaults.GRAVITY_SCALE,
        description="gravity_scale of every body (number or distribution).",
        examples=[{"choice": [0.5, 1]}],
    )
    fixed_rotation: bool = Field(False, description="fixed_rotation of every body.", examples=[True])
    bullet: bool = Field(False, description="bullet of every body.", examples=[True])
    placement: Literal["free", "no_overlap"] = Field(
        "free",
        description="free: positions drawn in `region` as they come; no_overlap: a body whose bounding "
        "circle overlaps one placed before is drawn again (an error after 100 draws).",
        examples=["no_overlap"],
    )

    _shape_or_shapes = model_validator(mode="wrap")(_shape_keys)

    @model_validator(mode="after")
    def _placement(self) -> Generator:
        if (self.region is None) == (self.layout is None):
            raise PydanticCustomError("placement", "a generator needs either a region or a layout", {})
        if isinstance(self.layout, Pyramid):
            full = self.layout.pyramid.base * (self.layout.pyramid.base + 1) // 2
            if self.count is not None and self.count > full:
                raise PydanticCustomError(
                    "count",
                    f"a pyramid of base {self.layout.pyramid.base} holds "
                    f"{full} bodies, count must not exceed that",
                    {"at": "count"},
                )
        elif self.count is None:
            raise PydanticCustomError("count_required", "missing key 'count'", {})
        return self


from .scene_emitters import EMITTERS_FIELD, SINKS_FIELD, Emitter, Sink  # noqa: E402  (built on the above)

# -------------------------------------------------------------------------------------------------- scene


class Scene(_Model):
    """A rustycs scene: bodies, forces and attractors, and how to run and record them. Units are SI
    (m, kg, s, rad); +y is up; angles are counter-clockwise."""

    model_config = ConfigDict(
        title="rustycs scene",
        json_schema_extra={
            "examples": [
                {
                    "name": "drop",
                    "bodies": [
                        {
                            "name": "floor",
                            "type": "static",
                            "shape": {"type": "aabb", "width": 10, "height": 1},
                            "position": [0, -0.5],
                        },
                        {
                            "name": "ball",
                            "shape": {"type": "circle", "radius": 0.5},
                            "position": [0, 5],
                            "material": "rubber",
                        },
                    ],
                }
            ]
        },
    )

    version: Literal[1] = Field(1, description="Scene format version.", examples=[1])
    name: SceneName | None = Field(
        None, min_length=1, description="Scene name. Default: the file's stem.", examples=["material-bounce"]
    )
    description: Text = Field("", description="Free text.", examples=["Five balls of different materials."])
    seed: Seed = Field(
        0, ge=0, description="Seeds every generator (`rustycs run --seed` overrides).", examples=[0]
    )
    world: World = Field(
        World(),
        description="Tick rate, run length, solver substeps (precision), G, bounds and restitution "
        "threshold.",
        examples=[{"tick_rate": 240, "ticks": 1200, "precision": 10}],
    )
    forces: list[Force] = Field(
        [],
        description="Constant accelerations on every dynamic body.",
        examples=[[{"name": "gravity", "acceleration": [0, -9.81]}]],
    )
    attractors: list[Attractor] = Field(
        [],
        description="Fixed points that pull dynamic bodies.",
        examples=[[{"name": "sun", "position": [0, 0], "mass": 1000}]],
    )
    materials: dict[Name, Material] = Field(
        {},
        description=f"User materials by name; they extend, and may override, the presets {_PRESET_VALUES} "
        "as (density, restitution, friction).",
        examples=[{"ice": {"density": 0.9, "restitution": 0.05, "friction": 0.02}}],
    )
    bodies: list[Body] = Field(
        [],
        description="The bodies, in output order.",
        examples=[[{"shape": {"type": "circle", "radius": 0.2}, "position": [0, 5]}]],
    )
    generators: list[Generator] = Field(
        [],
        description="Entries that create many bodies, reproducibly from `seed`; "
        "their bodies come after the listed ones.",
        examples=[
            [
                {
                    "name": "rain",
                    "count": 100,
                    "shape": {"type": "circle", "radius": {"uniform": [0.1, 0.3]}},
                    "region": {"min": [-9, 5], "max": [9, 40]},
                }
            ]
        ],
    )
    joints: list[Joint] = Field(
        [],
        description="Joints between bodies, or a body and the fixed world (see docs/joints.md).",
        examples=[[{"name": "hinge", "type": "revolute", "body": "arm", "anchor": [0, 2]}]],
    )
    emitters: list[Emitter] = EMITTERS_FIELD
    sinks: list[Sink] = SINKS_FIELD
    measures: list[Measure] = MEASURES_FIELD
    output: Output = Field(
        Output(),
        description="Recording interval and whether contacts are recorded.",
        examples=[{"every": 1, "contacts": False}],
    )

    @model_validator(mode="after")
    def _default_names(self) -> Scene:
        for i, body in enumerate(self.bodies):
            if body.name is None:
                body.name = default_body_name([shape.type for shape in body.shapes or ()], i)
        for i, generator in enumerate(self.generators):
            if generator.name is None:
                generator.name = default_generator_name(i)
        for j, joint in enumerate(self.joints):
            if joint.name is None:
                joint.name = scene_joints.default_joint_name(joint.type, j)
        return self

    @model_serializer(mode="wrap")
    def _written_when_used(self, handler: SerializerFunctionWrapHandler) -> dict[str, Any]:
        return _without_unused(handler(self), joints=[], emitters=[], sinks=[], measures=[])

    def material_of(self, body: Body) -> Material:
        """The material a body uses (user materials take precedence over presets)."""
        return self.material(body.material)

    def material(self, ref: MaterialRef) -> Material:
        """The material a body's or a shape's `material` names (user materials take precedence over
        presets), or the inline one it is."""
        if isinstance(ref, Material):
            return ref
        return self.materials.get(ref) or PRESET_MATERIALS[ref]


def default_body_name(shape_types: Sequence[Any], index: int) -> str:
    """The name of an unnamed body: '<shape type>-<index in bodies>', or 'compound-<index>' for several."""
    return f"{shape_types[0] if len(shape_types) == 1 else 'compound'}-{index}"


def written_default_body_name(body: Mapping[str, Any], index: int) -> str:
    """The default name of a body as written (before validation)."""
    kinds = [shape.get("type") if isinstance(shape, dict) else None for _, shape in _written_shapes(body)]
    return default_body_name(kinds, index)


def _written_shapes(entry: Mapping[str, Any]) -> list[tuple[Loc, Any]]:
    """The shapes a body or generator writes (before validation), each with its place in the entry."""
    shapes = entry.get("shapes")
    if entry.get("shape") is not None or not isinstance(shapes, list):
        return [(("shape",), entry.get("shape"))]
    return [(("shapes", k), shape) for k, shape in enumerate(shapes)]


def default_generator_name(index: int) -> str:
    """The name of an unnamed generator."""
    return f"generator-{index}"


def scene_problems(data: Mapping[str, Any]) -> list[Problem]:
    """Problems that involve more than one entry: duplicate names and unknown material names. Works on the
    raw scene data, so that these are found even when other fields are invalid, and reported with them."""
    problems: list[Problem] = []
    materials = data.get("materials")
    known = sorted({*PRESET_MATERIALS, *(map(str, materials) if isinstance(materials, dict) else ())})

    def check_material(ref: Any, loc: Loc) -> None:
        if isinstance(ref, str) and ref not in known:
            problems.append(
                (loc, f"unknown material '{ref}'{did_you_mean(ref, known)}; known: {', '.join(known)}")
            )

    def entries(key: str) -> list[tuple[int, dict[str, Any]]]:
        listed = data.get(key)
        return (
            [(i, e) for i, e in enumerate(listed) if isinstance(e, dict)] if isinstance(listed, list) else []
        )

    def check_unique(name: Any, loc: Loc, seen: dict[str, int], what: str) -> None:
        if isinstance(name, str) and name in seen:
            problems.append((loc, f"duplicate {what} name '{name}' (also {what} {seen[name]})"))
        elif isinstance(name, str):
            seen[name] = int(loc[1])

    def check_generated_material(ref: Any, loc: Loc) -> None:
        for k, choice in enumerate(_choices(ref)):
            check_material(choice, (*loc, "choice", k) if ref is not choice else loc)

    body_names: dict[str, int] = {}
    for i, body in entries("bodies"):
        name = body.get("name", written_default_body_name(body, i))
        check_unique(name, ("bodies", i, "name"), body_names, "body")
        check_material(body.get("material"), ("bodies", i, "material"))
        for place, shape in _written_shapes(body):
            if isinstance(shape, dict):
                check_material(shape.get("material"), ("bodies", i, *place, "material"))
    generator_names: dict[str, int] = {}
    for g, generator in entries("generators"):
        check_unique(
            generator.get("name", default_generator_name(g)),
            ("generators", g, "name"),
            generator_names,
            "generator",
        )
        check_generated_material(generator.get("material"), ("generators", g, "material"))
        for place, spec in _written_shapes(generator):
            for k, shape in enumerate(_choices(spec)):
                if isinstance(shape, dict):
                    at = (*place, "choice", k) if shape is not spec else place
                    check_generated_material(shape.get("material"), ("generators", g, *at, "material"))
    generated = _generated_names(entries("generators"))
    return (problems + measure_problems(data, body_names, generator_names)
            + scene_joints.joint_problems(data, [*body_names, *generated]))


def _generated_names(generators: list[tuple[int, dict[str, Any]]]) -> list[str]:
    """The names of the bodies of the generators that give their `count`, as written."""
    return [
        f"{generator.get('name', default_generator_name(g))}-{i}"
        for g, generator in generators
        if isinstance(generator.get("count"), int)
        for i in range(generator["count"])
    ]


def _choices(spec: Any) -> list[Any]:
    """The options of a written {choice: [...]} (not a shape that has a `type`), or [spec] itself."""
    if isinstance(spec, dict) and "type" not in spec and isinstance(spec.get("choice"), list):
        return list(spec["choice"])
    return [spec]


# --------------------------------------------------------------------------------- navigating the types


def resolve_annotation(annotation: Any, value: Any) -> Any:
    """The concrete type that validates `value` at a place typed `annotation` (unions are resolved the way
    validation resolves them), or None when no member applies."""
    origin = typing.get_origin(annotation)
    if origin is Annotated:
        inner, *metadata = typing.get_args(annotation)
        for item in metadata:
            if isinstance(item, Discriminator) and callable(item.discriminator):
                tag = item.discriminator(value)
                for member in typing.get_args(inner):
                    member_meta = getattr(member, "__metadata__", ())
                    if any(isinstance(m, Tag) and m.tag == tag for m in member_meta):
                        return resolve_annotation(member, value)
                return None
        return resolve_annotation(inner, value)
    if origin in (typing.Union, types.UnionType):
        members = [m for m in typing.get_args(annotation) if m is not type(None)]
        if value is None:
            return None
        return resolve_annotation(members[0], value) if len(members) == 1 else None
    return annotation


def model_fields_at(annotation: Any, value: Any) -> dict[str, FieldInfo] | None:
    """The fields of the model that validates `value` at a place typed `annotation` (None: not a model)."""
    resolved = resolve_annotation(annotation, value)
    if isinstance(resolved, type) and issubclass(resolved, BaseModel):
        return dict(resolved.model_fields)
    return None


def child_annotation(annotation: Any, key: str | int, value: Any) -> Any:
    """The annotation of `value[key]` where `value` sits at a place typed `annotation`, or None."""
    resolved = resolve_annotation(annotation, value)
    fields = model_fields_at(annotation, value)
    if fields is not None:
        field = fields.get(str(key))
        if field is None:
            return None
        return Annotated[(field.annotation, *field.metadata)] if field.metadata else field.annotation
    origin, args = typing.get_origin(resolved), typing.get_args(resolved)
    if origin is list and isinstance(key, int):
        return args[0]
    if origin is dict:
        return args[1]
    if origin is tuple and isinstance(key, int) and key < len(args):
        return args[key]
    return None


def union_tags(annotation: Any) -> list[str]:
    """The tags a discriminated union accepts (e.g. the shape types at a place), or []."""
    while typing.get_origin(annotation) in (typing.Union, types.UnionType):
        members = [m for m in typing.get_args(annotation) if m is not type(None)]
        if len(members) != 1:
            break
        annotation = members[0]
    if typing.get_origin(annotation) is not Annotated:
        return []
    inner = typing.get_args(annotation)[0]
    return [
        m.tag
        for member in typing.get_args(inner)
        for m in getattr(member, "__metadata__", ())
        if isinstance(m, Tag)
    ]


from . import scene_joints  # noqa: E402 (the joint models build on the above and complete Scene)
