"""The peer engines, pymunk 7 and Box2D v3 (pyb2d3), building the bodies of a BenchScene, each of its
shapes (circles, polygons, capsules, segments) on one peer body, and its joints (`peer_joints`).

Settings follow the peer harness (../shared/bench/peers), so that our numbers can be put next to its:
pymunk: 10 iterations, collision_slop 0.005 m, no damping; pyb2d3: 4 substeps, continuous collision at
its default (bullets where the scene has them). Sleeping is off unless asked for (`rustycs bench
--sleep`: bodies at rest for SLEEP_TIME s sleep, Box2D v3's fixed time); both step on one thread unless
asked for more (`--threads`: a pyb2d3 thread pool of that many workers, pymunk's threaded space, which
runs at most 2). Both engines mix materials like Box2D
(friction sqrt(f1*f2), restitution max): pymunk multiplies the two shapes' coefficients, so each shape
gets sqrt(friction) and static shapes elasticity 1 (the scenes' statics have restitution 0, so the
product equals Box2D's max). Attractors are applied from Python before every step, as the harness does.

Box2D v3's make_rot and body.angle are fast approximations (errors near 1e-3 rad), so rotations are
built from the exact cosine and sine and read back with atan2.

Each adapter offers `step` (one tick, no adapter layer in between), `poses()` ((x, y, angle) of every
body origin, in scene order), and `sleep` and `threads`: what its engine runs with.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from typing import Any

from .peer_joints import add_box2d_joints, add_pymunk_joints
from .spec import BenchScene, BodySpec, ShapeSpec

PYMUNK_ITERATIONS = 10
PYMUNK_COLLISION_SLOP = 0.005
B2_SUBSTEPS = 4
SLEEP_TIME = 0.5  # s at rest before a body sleeps: Box2D v3's b2_timeToSleep, given to pymunk and rustycs
PYMUNK_MAX_THREADS = 2  # Chipmunk's hasty space runs its solver on at most 2 threads
ENGINES = ("pymunk", "pyb2d3")


def missing() -> list[str]:
    """The peer modules that cannot be imported (install them with the `bench` extra)."""
    import importlib.util

    return [name for name in ENGINES if importlib.util.find_spec(name) is None]


def versions() -> dict[str, str]:
    """Installed version of each peer engine."""
    from importlib.metadata import version

    return {name: version(name) for name in ENGINES}


def build(engine: str, scene: BenchScene, sleep: bool = False, threads: int = 1) -> PymunkWorld | Box2DWorld:
    """The peer world of `engine` ("pymunk" or "pyb2d3") holding the scene's bodies, sleeping or not,
    stepped by up to `threads` threads."""
    return {"pymunk": PymunkWorld, "pyb2d3": Box2DWorld}[engine](scene, sleep, threads)


def threads_used(engine: str, threads: int) -> int:
    """How many threads `engine` steps one world with when asked for `threads`: pymunk at most 2 and one
    on Windows (no threaded space there), a pyb2d3 built without threading one."""
    if engine == "pymunk":
        import platform

        return 1 if platform.system() == "Windows" else min(threads, PYMUNK_MAX_THREADS)
    import pyb2d3

    return threads if pyb2d3.WITH_THREADING else 1


def describe_settings(engine: str, sleep: bool, threads: int) -> str:
    """The settings `engine` runs with, for the report and the JSON: what ran, also where the engine
    cannot use the threads asked for."""
    used = threads_used(engine, threads)
    if engine == "pymunk":
        napping = f"sleeping after {SLEEP_TIME} s idle" if sleep else "no sleeping"
        stepping = ("single-threaded" if used == 1 else
                    f"threaded space, {used} threads (each runs 1/{used} of the solver iterations over all "
                    "contacts at once)")
        if used < threads:
            stepping += f" ({PYMUNK_MAX_THREADS} at most, none on Windows)"
        return (f"iterations {PYMUNK_ITERATIONS}, collision_slop {PYMUNK_COLLISION_SLOP}, {napping}, "
                f"{stepping}")
    napping = f"sleeping on ({SLEEP_TIME} s at rest)" if sleep else "sleeping off"
    stepping = "single-threaded" if used == 1 else f"{used} workers (a pyb2d3 ThreadPool)"
    if used < threads:
        stepping += " (this pyb2d3 is built without threading)"
    return f"{B2_SUBSTEPS} substeps, {napping}, continuous on, {stepping}"


def _group_number(group: int) -> int:
    """A distinct positive number for each non-zero rustycs group (pymunk wants groups >= 0, Box2D
    takes its negative: only negative groups never collide)."""
    return 2 * abs(group) - (group < 0)


def _world_points(spec: BodySpec, shape: ShapeSpec) -> list[tuple[float, float]]:
    """A shape's points placed by its body's pose (the peers' static shapes are in world coordinates)."""
    c, s = math.cos(spec.angle), math.sin(spec.angle)
    x, y = spec.position
    return [(x + c * vx - s * vy, y + s * vx + c * vy) for vx, vy in shape.points]


def _central_force(bodies: list[tuple[Any, float]], attractor: tuple[float, float, float],
                   position: Callable[[Any], tuple[float, float]],
                   apply: Callable[[Any, tuple[float, float]], None]) -> Callable[[], None]:
    """The harness's force loop: F = -G*M*m r/|r|^3 towards the attractor, set before each step."""
    ax, ay, gm = attractor
    sqrt = math.sqrt

    def step_forces() -> None:
        for body, m in bodies:
            x, y = position(body)
            dx, dy = x - ax, y - ay
            r2 = dx * dx + dy * dy
            k = -gm * m / (r2 * sqrt(r2))
            apply(body, (k * dx, k * dy))

    return step_forces


def _with_forces(step: Callable[[], None], forces: list[Callable[[], None]]) -> Callable[[], None]:
    if not forces:
        return step

    def step_with_forces() -> None:
        for force in forces:
            force()
        step()

    return step_with_forces


class PymunkWorld:
    """The scene in a pymunk Space."""

    def __init__(self, scene: BenchScene, sleep: bool, threads: int):
        import pymunk

        space = pymunk.Space(threaded=threads > 1)
        space.threads = threads  # pymunk keeps 1 on a space that is not threaded, 2 at most on one
        space.gravity = scene.gravity
        space.iterations = PYMUNK_ITERATIONS
        space.collision_slop = PYMUNK_COLLISION_SLOP
        if sleep:  # idle_speed_threshold stays 0: pymunk derives it from the gravity
            space.sleep_time_threshold = SLEEP_TIME
        self.space = space
        self.bodies: list[Any] = []
        for spec in scene.bodies:
            self.bodies.append(self._add(pymunk, spec))
        add_pymunk_joints(space, self.bodies, scene.bodies, scene.joints)
        moving = [(b, b.mass) for b, spec in zip(self.bodies, scene.bodies, strict=True)
                  if spec.body_type == "dynamic"]

        def position(body: Any) -> tuple[float, float]:
            return body.position

        def apply(body: Any, force: tuple[float, float]) -> None:
            body.force = force  # world frame, at the centre of gravity; pymunk clears it after the step

        forces = [_central_force(moving, a, position, apply) for a in scene.attractors]
        self.step = _with_forces(functools.partial(space.step, scene.dt), forces)

    @property
    def sleep(self) -> bool:
        return self.space.sleep_time_threshold < math.inf

    @property
    def threads(self) -> int:
        return self.space.threads

    def _add(self, pymunk: Any, spec: BodySpec) -> Any:
        static = spec.body_type == "static"
        if static:  # like the harness: shapes on the space's static body, in world coordinates
            body = self.space.static_body
        else:
            if spec.body_type == "kinematic":
                body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
            elif spec.fixed_rotation:  # rotation locked (an aabb is centred on its origin)
                body = pymunk.Body(spec.mass, math.inf)
            else:
                body = pymunk.Body()
            body.position = spec.position
            body.angle = spec.angle
            body.velocity = spec.velocity
            body.angular_velocity = spec.angular_velocity
        shapes = []
        for part in spec.shapes:
            points = _world_points(spec, part) if static else list(part.points)
            if part.kind == "circle":
                shape = pymunk.Circle(body, part.radius, offset=points[0])
            elif part.kind in ("segment", "capsule"):  # a capsule is a segment with a radius
                shape = pymunk.Segment(body, points[0], points[1], part.radius)
            else:
                shape = pymunk.Poly(body, points, radius=0.0)
            if spec.body_type == "dynamic" and not spec.fixed_rotation and part.mass > 0:
                shape.mass = part.mass  # centre of gravity and moment follow from the shapes
            shape.friction = math.sqrt(part.friction)
            shape.elasticity = 1.0 if static else part.restitution
            shape.filter = pymunk.ShapeFilter(group=_group_number(spec.group))  # 0: no group
            shapes.append(shape)
        if static:
            self.space.add(*shapes)
        else:
            self.space.add(body, *shapes)
        return body

    def poses(self) -> list[tuple[float, float, float]]:
        return [(b.position.x, b.position.y, b.angle) for b in self.bodies]


class Box2DWorld:
    """The scene in a Box2D v3 world (pyb2d3)."""

    def __init__(self, scene: BenchScene, sleep: bool, threads: int):
        import pyb2d3 as b2

        used = threads_used("pyb2d3", threads)
        pool = {"thread_pool": b2.ThreadPool(used)} if used > 1 else {}  # Box2D's workers run its tasks
        world = b2.World(gravity=scene.gravity, **pool)
        world.sleeping_enabled = sleep
        self.world = world
        self.threads = used  # Box2D's worker count (pyb2d3 does not read it back)
        self.bodies = [self._add(b2, spec, sleep) for spec in scene.bodies]
        add_box2d_joints(world, self.bodies, scene.joints)
        moving = [(b, b.mass) for b, spec in zip(self.bodies, scene.bodies, strict=True)
                  if spec.body_type == "dynamic"]

        def position(body: Any) -> tuple[float, float]:
            p = body.position
            return p.x, p.y

        def apply(body: Any, force: tuple[float, float]) -> None:
            body.apply_force_to_center(force, True)

        forces = [_central_force(moving, a, position, apply) for a in scene.attractors]
        self.step = _with_forces(functools.partial(world.step, scene.dt, B2_SUBSTEPS), forces)

    @property
    def sleep(self) -> bool:
        return self.world.sleeping_enabled

    def _add(self, b2: Any, spec: BodySpec, sleep: bool) -> Any:
        kinds = {"static": b2.BodyType.STATIC, "dynamic": b2.BodyType.DYNAMIC,
                 "kinematic": b2.BodyType.KINEMATIC}
        body = self.world.create_body(b2.body_def(
            type=kinds[spec.body_type], position=spec.position, rotation=b2.Rot(spec.angle),
            linear_velocity=spec.velocity, angular_velocity=spec.angular_velocity, enable_sleep=sleep,
            fixed_rotation=spec.fixed_rotation, is_bullet=spec.bullet))
        for part in spec.shapes:
            density = part.mass / part.area if part.mass > 0 else 0.0
            shape = b2.shape_def(density=density, material=b2.surface_material(
                friction=part.friction, restitution=part.restitution))
            if spec.group:
                shape.filter = b2.make_filter(group_index=-_group_number(spec.group))
            if part.kind == "circle":
                body.create_circle_shape(shape, b2.circle(center=part.points[0], radius=part.radius))
            elif part.kind == "segment":
                body.create_segment_shape(shape, b2.segment(*part.points))
            elif part.kind == "capsule":
                body.create_capsule_shape(shape, b2.capsule(*part.points, part.radius))
            else:
                body.create_polygon_shape(shape, b2.polygon(points=list(part.points)))
        return body

    def poses(self) -> list[tuple[float, float, float]]:
        out = []
        for body in self.bodies:
            p, q = body.position, body.rotation
            out.append((p.x, p.y, math.atan2(q.s, q.c)))
        return out
