"""Emitters and sinks: the scene models, and the emitted bodies of a run.

An emitter's bodies are drawn like a generator's (one random stream per emitter, from the scene's seed
and the emitter's name) when the run starts, as many as can appear in the run; each has the tick it
appears in, one every round(tick_rate / rate) ticks from `start`. The engine reserves their rows and
switches each on in its tick (`rustycs.emitters`), or with `placement: no_overlap` skips it when its place
is taken then.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal

from pydantic import Field, model_validator
from pydantic_core import PydanticCustomError

from .errors import UserError
from .limits import MAX_BODIES
from .scene import (
    Body,
    GeneratedMaterial,
    GeneratedShape,
    Generator,
    Number,
    NumberPair,
    Rect,
    Vec2,
    _Model,
)

if TYPE_CHECKING:
    from .scene import Scene


class Emitter(_Model):
    """Bodies that appear during the run (the thesis's particle systems), named '<name>-<i>' in order of
    appearance. Numeric fields may be distributions, as in generators."""

    name: str = Field(min_length=1, description="Names the bodies '<name>-<i>' and seeds the emitter's "
                      "random numbers (with the scene's seed).", examples=["tap"])
    shape: GeneratedShape = Field(description="Shape of each body; sizes may be distributions.",
                                  examples=[{"type": "circle", "radius": {"uniform": [0.04, 0.06]}}])
    material: GeneratedMaterial = Field("default", description="Material name, inline material, or "
                                        "{choice: [...]}.", examples=["rubber"])
    position: Vec2 | None = Field(None, description="Where each body appears [x, y], m (or give `region`).",
                                  examples=[[0, 5]])
    region: Rect | None = Field(None, description="Bodies appear uniformly in this rectangle (or give "
                                "`position`).", examples=[{"min": [-1, 5], "max": [1, 5.5]}])
    velocity: NumberPair = Field((0.0, 0.0), description="Initial velocity [vx, vy], m/s; each a number or a "
                                 "distribution.", examples=[[0, -1]])
    angle: Number = Field(0.0, description="Initial angle, rad (number or distribution).", examples=[0.0])
    angular_velocity: Number = Field(0.0, description="Initial angular velocity, rad/s (number or "
                                     "distribution).", examples=[0.0])
    rate: float = Field(gt=0, description="Bodies per second: one every round(tick_rate / rate) ticks (at "
                        "most one a tick).", examples=[20])
    start: float = Field(0.0, ge=0, description="When the first body appears, s.", examples=[0.0])
    stop: float | None = Field(None, ge=0, description="No body appears after this time, s. Default: the "
                               "end of the run.", examples=[5.0])
    count: int | None = Field(None, ge=0, description="At most this many bodies in all.", examples=[200])
    lifetime: float | None = Field(None, gt=0, description="Each body is removed this long after it "
                                   "appeared, s. Default: it stays.", examples=[3.0])
    placement: Literal["free", "no_overlap"] = Field(
        "free", description="free: every body appears; no_overlap: a body whose bounding circle would "
        "overlap a collidable shape of a body present when it is due is skipped (it never appears; "
        "counted in the summary, `emitter.<name>.skipped`).", examples=["no_overlap"])

    @model_validator(mode="after")
    def _placed(self) -> Emitter:
        if (self.position is None) == (self.region is None):
            raise PydanticCustomError("placement", "an emitter needs either a position or a region", {})
        return self


class Sink(_Model):
    """A region that removes every dynamic body whose centre enters it."""

    name: str | None = Field(None, min_length=1, description="Name (optional).", examples=["drain"])
    region: Rect = Field(description="The region.", examples=[{"min": [-10, -6], "max": [10, -5]}])


EMITTERS_FIELD = Field(
    [],
    description="Bodies that appear during the run; their rows are reserved from the start (inactive, "
    "`spawn_tick` in the trajectory).",
    examples=[[{"name": "tap", "shape": {"type": "circle", "radius": 0.05}, "position": [0, 5], "rate": 20}]],
)
SINKS_FIELD = Field(
    [],
    description="Regions that remove every dynamic body whose centre enters them.",
    examples=[[{"name": "drain", "region": {"min": [-10, -6], "max": [10, -5]}}]],
)


@dataclass(frozen=True)
class Emitted:
    """The bodies a run's emitters may emit, in emitter order, and when each appears and goes."""

    bodies: list[Body]
    spawn_ticks: list[int]
    remove_ticks: list[int | None]
    if_free: list[bool]  # each appears only where its place is free (placement: no_overlap)
    by_emitter: dict[str, list[str]]  # emitter name -> its bodies' names


def spawn_ticks(emitter: Emitter, tick_rate: float, ticks: int) -> list[int]:
    """The ticks the emitter's bodies appear in, within a run of `ticks` ticks."""
    period = max(1, round(tick_rate / emitter.rate))
    first = round(emitter.start * tick_rate)
    last = ticks if emitter.stop is None else min(ticks, round(emitter.stop * tick_rate))
    count = (last - first) // period + 1 if last >= first else 0
    count = count if emitter.count is None else min(count, emitter.count)
    if count > MAX_BODIES.value:  # counted before any is drawn: the rows are reserved up front
        raise UserError(f"emitter {emitter.name!r} would emit {count} bodies in a run of {ticks} ticks, more "
                        f"than {MAX_BODIES}; lower its rate or give it a count or a stop time")
    return list(range(first, first + count * period, period))


def emitted_bodies(scene: Scene, ticks: int) -> Emitted:
    """Every body the scene's emitters may emit in a run of `ticks` ticks, drawn reproducibly."""
    from .generators import generate

    bodies: list[Body] = []
    spawn: list[int] = []
    remove: list[int | None] = []
    if_free: list[bool] = []
    by_emitter: dict[str, list[str]] = {}
    rate = scene.world.tick_rate
    for emitter in getattr(scene, "emitters", []):
        at = spawn_ticks(emitter, rate, ticks)
        (x, y) = emitter.position or (0.0, 0.0)
        region = emitter.region or Rect(min=(x - 1.0, y - 1.0), max=(x + 1.0, y + 1.0))
        drawn = generate(Generator(name=f"emitter:{emitter.name}", count=len(at), shape=emitter.shape,
                                   region=region, velocity=emitter.velocity, angle=emitter.angle,
                                   angular_velocity=emitter.angular_velocity, material=emitter.material),
                         scene.seed)
        names = []
        for i, (body, tick) in enumerate(zip(drawn, at, strict=True)):
            body: dict[str, Any] = {**body, "name": f"{emitter.name}-{i}"}
            if emitter.position is not None:
                body["position"] = list(emitter.position)
            bodies.append(Body.model_validate(body))
            names.append(body["name"])
            spawn.append(tick)
            remove.append(None if emitter.lifetime is None else tick + max(1, round(emitter.lifetime * rate)))
            if_free.append(emitter.placement == "no_overlap")
        by_emitter[emitter.name] = names
    return Emitted(bodies, spawn, remove, if_free, by_emitter)
