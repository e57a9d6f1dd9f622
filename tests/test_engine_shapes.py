"""Bodies made of shapes: mass properties from all of a body's shapes, concave polygons, capsules and smooth
chains, and the per-body keys (damping, gravity scale, fixed rotation, collision filters)."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from rustycs import Box, Capsule, Chain, Circle, Material, Polygon, Segment, World, debug

L_POLYGON = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]
L_BOXES = [Box(2.0, 1.0, offset=(1.0, 0.5)), Box(1.0, 1.0, offset=(0.5, 1.5))]
STONE = Material(2.5, 0.0, 0.4)


def one_body(shapes, **options) -> World:
    world = World()
    world.add_body(shapes, material=STONE, **options)
    return world


def test_an_l_of_two_boxes_and_the_same_l_as_one_concave_polygon_have_the_closed_form_mass():
    # boxes 2 x 1 centred (1, 0.5) and 1 x 1 centred (0.5, 1.5), density 2.5
    mass = 3.0 * 2.5
    center = np.array([2.0 * 1.0 + 0.5, 2.0 * 0.5 + 1.5]) / 3.0  # (5/6, 5/6)
    inertia = 2.5 * (2.0 * 5.0 / 12.0 + 2.0 * np.sum((np.array([1.0, 0.5]) - center) ** 2)
                     + 2.0 / 12.0 + np.sum((np.array([0.5, 1.5]) - center) ** 2))
    for world in (one_body(L_BOXES), one_body(Polygon(L_POLYGON))):
        assert world.masses[0] == pytest.approx(mass, rel=1e-9)
        assert world.local_centers[0] == pytest.approx(center, rel=1e-9)
        assert world.inertias[0] == pytest.approx(inertia, rel=1e-9)
    assert len(debug.shape_bodies(one_body(Polygon(L_POLYGON)))) == 2  # two convex pieces


def test_a_capsule_has_the_mass_of_a_box_and_two_half_discs():
    length, radius, density = 1.3, 0.4, 2.5
    disc = math.pi * radius**2 * density
    rectangle = 2.0 * radius * length * density
    inertia = (rectangle * (length**2 + 4.0 * radius**2) / 12.0
               + disc * (radius**2 / 2.0 + length**2 / 4.0 + 4.0 * radius * length / (3.0 * math.pi)))
    world = one_body(Capsule(length, radius, angle=0.7, offset=(0.2, -0.1)))
    assert world.masses[0] == pytest.approx(disc + rectangle, rel=1e-12)
    assert world.inertias[0] == pytest.approx(inertia, rel=1e-12)
    assert world.local_centers[0] == pytest.approx([0.2, -0.1], abs=1e-15)


def test_a_regular_polygon_of_40_vertices_has_the_closed_form_area_and_inertia():
    n, r = 40, 0.8
    angles = 2.0 * math.pi * np.arange(n) / n
    world = one_body(Polygon(np.stack([r * np.cos(angles), r * np.sin(angles)], axis=1)))
    alpha = 2.0 * math.pi / n
    assert world.masses[0] == pytest.approx(2.5 * n / 2.0 * r * r * math.sin(alpha), rel=1e-12)
    polar = n * r**4 / 12.0 * math.sin(alpha) * (2.0 + math.cos(alpha))
    assert world.inertias[0] == pytest.approx(2.5 * polar, rel=1e-9)
    assert len(debug.shape_bodies(world)) == 7  # pieces of at most 8 vertices


def test_mass_given_on_a_compound_body_scales_every_shape():
    world = one_body(L_BOXES, mass=6.0)
    assert world.masses[0] == 6.0
    assert world.inertias[0] == pytest.approx(6.0 / 7.5 * one_body(L_BOXES).inertias[0], rel=1e-12)


def test_sensors_and_lines_add_no_mass_and_a_dynamic_body_needs_area():
    plain = one_body(Circle(0.5))
    decorated = one_body([Circle(0.5), Circle(2.0, offset=(3, 0), sensor=True), Segment([(-1, 0), (1, 0)])])
    assert decorated.masses[0] == plain.masses[0]
    assert decorated.inertias[0] == plain.inertias[0]
    with pytest.raises(ValueError, match="shape with area"):
        one_body([Segment([(-1, 0), (1, 0)]), Circle(1.0, sensor=True)])
    one_body(Chain([(-1, 0), (0, 0), (1, 1)]), body_type="static")  # lines are fine on static bodies


def floor_world(tick_rate: float = 60.0) -> World:
    world = World(tick_rate=tick_rate, precision=4)
    world.add_force((0.0, -9.81))
    world.add_body(Box(40.0, 1.0), position=(0.0, -0.5), body_type="static", material=STONE)
    return world


def test_a_concave_l_dropped_flat_stays_flat_and_comes_to_rest():
    world = floor_world()
    body = world.add_body(Polygon(L_POLYGON), position=(0.0, 0.3), material=STONE)
    world.step(180)
    assert abs(world.angles[body]) < 1e-3
    assert world.positions[body] == pytest.approx([0.0, 0.0], abs=0.01)
    assert np.hypot(*world.velocities[body]) < 1e-3 and abs(world.angular_velocities[body]) < 1e-3


def test_a_concave_cup_carries_a_ball_while_it_slides():
    # a U of outer width 2 and height 1 with walls 0.2 thick, as one concave polygon
    cup = [(-1, 0), (1, 0), (1, 1), (0.8, 1), (0.8, 0.2), (-0.8, 0.2), (-0.8, 1), (-1, 1)]
    world = floor_world()
    body = world.add_body(Polygon(cup), position=(0.0, 0.0), material=Material(2.0, 0.0, 0.3))
    ball = world.add_body(Circle(0.3), position=(0.3, 0.5), material=Material(1.0, 0.0, 0.3))
    world.step(60)
    world.set_velocity(body, (4.0, 0.0))
    for _ in range(120):
        world.step(1)
        local_x = world.positions[ball][0] - world.positions[body][0]
        assert -0.8 + 0.29 < local_x < 0.8 - 0.29  # between the walls
        assert world.positions[ball][1] > 0.2 + 0.29  # above the bottom
    assert world.positions[body][0] > 1.0  # the cup slid and took the ball along


def quarter_circle_ramp(radius: float, points: int) -> list[tuple[float, float]]:
    """From the left end (-radius, radius) down to the bottom (0, 0), centre (0, radius)."""
    angles = np.linspace(math.pi, 1.5 * math.pi, points)
    return [(radius * math.cos(a), radius + radius * math.sin(a)) for a in angles]


@pytest.mark.parametrize("reverse", [False, True], ids=["drawn down", "drawn up"])
def test_a_disc_rolls_down_a_smooth_chain_quarter_circle_like_a_true_circle(reverse):
    """Released at 45 degrees (rolling needs friction above tan(45)/3), a disc reaches the bottom at
    sqrt(4/3 g h) and follows the curve: no bump at the 63 joints."""
    big, r = 3.0, 0.2
    points = quarter_circle_ramp(big, 64)
    world = World(tick_rate=240, precision=4)
    world.add_force((0.0, -9.81))
    world.add_body(Chain(points[::-1] if reverse else points), body_type="static",
                   material=Material(1, 0, 0.8))
    start = 1.25 * math.pi
    disc = world.add_body(Circle(r), material=Material(1.0, 0.0, 0.8),
                          position=((big - r) * math.cos(start), big + (big - r) * math.sin(start)))
    height = (big - r) * (1.0 - math.sin(math.pi / 4))
    while world.positions[disc][0] < 0.0:
        world.step(1)
        x, y = world.positions[disc]
        gap = big - math.hypot(x, y - big) - r
        assert abs(gap) < 0.01, f"tick {world.tick}: {gap:.4f} m off the curve"
        assert world.tick < 600
    speed = float(np.hypot(*world.velocities[disc]))
    assert speed == pytest.approx(math.sqrt(4.0 / 3.0 * 9.81 * height), rel=0.03)
    assert -world.angular_velocities[disc] * r == pytest.approx(speed, rel=0.01)  # rolling, not slipping


@pytest.mark.parametrize("shape", [Box(1.0, 0.5), Capsule(0.6, 0.25)], ids=["box", "capsule"])
def test_a_body_slides_across_the_joints_of_a_straight_chain_slowing_only_by_friction(shape):
    mu, v0 = 0.3, 3.0
    world = World(tick_rate=60, precision=4)
    world.add_force((0.0, -9.81))
    world.add_body(Chain([(-5, 0), (-0.5, 0), (0, 0), (0.37, 0), (5, 0)]), body_type="static",
                   material=Material(1, 0, mu))
    body = world.add_body(shape, position=(-1.0, 0.25), velocity=(v0, 0.0), material=Material(1.0, 0.0, mu))
    for tick in range(1, 61):
        world.step(1)
        vx, vy = world.velocities[body]
        assert vx == pytest.approx(max(v0 - mu * 9.81 * tick / 60, 0.0), abs=1e-3)
        assert abs(vy) < 1e-3 and abs(world.angles[body]) < 1e-3
    assert world.positions[body][0] > 0.37  # it passed all three joints


def test_a_circle_rolls_over_a_convex_chain_corner_without_a_kick():
    """Over a hilltop of a 10-degree bend the ball stays on the surface and keeps its speed: the corner's
    contact is the vertex's, shared by no neighbour."""
    world = World(tick_rate=240, precision=4)
    world.add_force((0.0, -9.81))
    slope = math.radians(10)
    world.add_body(Chain([(-4, 0), (0, 0), (4 * math.cos(slope), -4 * math.sin(slope))]), body_type="static",
                   material=Material(1, 0, 0.8))
    ball = world.add_body(Circle(0.2), position=(-1.0, 0.2), velocity=(1.0, 0.0), angular_velocity=-5.0,
                          material=Material(1.0, 0.0, 0.8))
    energy = world.observables()["kinetic_energy"] + world.observables()["potential_energy"]
    for _ in range(240):
        world.step(1)
        assert world.velocities[ball][1] < 0.05  # never thrown up
    total = world.observables()["kinetic_energy"] + world.observables()["potential_energy"]
    assert total == pytest.approx(energy, rel=0.01)


def test_damping_decays_velocities_exactly_as_exp_minus_c_t():
    world = World(tick_rate=60, precision=4)
    body = world.add_body(Circle(0.5), velocity=(3.0, -1.0), angular_velocity=2.0, linear_damping=0.7,
                          angular_damping=1.3)
    world.step(90)
    t = 1.5
    assert world.velocities[body] == pytest.approx(np.array([3.0, -1.0]) * math.exp(-0.7 * t), rel=1e-12)
    assert world.angular_velocities[body] == pytest.approx(2.0 * math.exp(-1.3 * t), rel=1e-12)


@pytest.mark.parametrize("scale", [0.0, 0.5, 1.0])
def test_gravity_scale_multiplies_the_world_force(scale):
    world = World(tick_rate=60, precision=4)
    world.add_force((0.0, -9.81))
    body = world.add_body(Circle(0.5), position=(0.0, 10.0), gravity_scale=scale)
    world.step(60)
    h = 1.0 / 240
    n = 240
    # semi-implicit Euler over n substeps: y = y0 - g h^2 n (n + 1) / 2, v = -g h n
    assert world.velocities[body][1] == pytest.approx(-9.81 * scale * h * n, abs=1e-12)
    assert world.positions[body][1] == pytest.approx(10.0 - 9.81 * scale * h * h * n * (n + 1) / 2, abs=1e-12)


def test_a_circle_of_fixed_rotation_hit_off_centre_does_not_turn():
    world = World(tick_rate=60, precision=8)
    target = world.add_body(Circle(0.5), position=(0.0, 0.0), fixed_rotation=True)
    world.add_body(Circle(0.2), position=(-2.0, 0.4), velocity=(5.0, 0.0))
    free = World(tick_rate=60, precision=8)
    spun = free.add_body(Circle(0.5), position=(0.0, 0.0))
    free.add_body(Circle(0.2), position=(-2.0, 0.4), velocity=(5.0, 0.0))
    world.step(40)
    free.step(40)
    assert world.angular_velocities[target] == 0.0 and world.angles[target] == 0.0
    assert world.inertias[target] == math.inf
    assert abs(free.angular_velocities[spun]) > 0.1  # the same hit turns a free circle (through friction)
    assert np.hypot(*world.velocities[target]) > 0.5  # and it was hit


def test_categories_and_masks_decide_which_bodies_collide():
    def falls_through(category: int, mask: int) -> bool:
        world = floor_world()
        body = world.add_body(Circle(0.3), position=(0.0, 1.0), collision_category=category,
                              collision_mask=mask)
        world.step(60)
        return world.positions[body][1] < 0.0

    assert not falls_through(1, -1)
    assert falls_through(2, -1 ^ 1)  # it does not take the floor's category 1
    assert not falls_through(1 << 5, -1)  # any category meets the floor's mask of all
    world = floor_world()
    world.add_body(Circle(0.3), position=(0.0, 1.0), collision_category=4, collision_mask=1)
    ghost = world.add_body(Circle(0.3), position=(0.0, 2.0), collision_category=8, collision_mask=1)
    world.step(90)
    assert world.positions[ghost][1] == pytest.approx(0.3, abs=0.02)  # passed through the other ball


def test_shapes_of_one_body_never_collide_with_each_other():
    world = World(tick_rate=60, precision=4)
    body = world.add_body([Circle(0.5), Box(1.0, 1.0, offset=(0.3, 0.0)), Capsule(1.0, 0.3, angle=0.5)])
    world.step(30)
    assert len(world.contacts()["body_a"]) == 0
    assert np.all(world.velocities[body] == 0.0) and world.angular_velocities[body] == 0.0


MIXED_PILE = """
import numpy as np
from rustycs import Box, Capsule, Chain, Circle, Polygon, World

def pile():
    world = World(tick_rate=60, precision=4)
    world.add_force((0.0, -9.81))
    world.add_body(Chain([(-6, 4), (-5, 0), (0, -0.5), (5, 0), (6, 4)]), body_type="static")
    rng = np.random.default_rng(3)
    shapes = [Polygon([(0, 0), (1, 0), (1, 0.3), (0.3, 0.3), (0.3, 1), (0, 1)]), Capsule(0.6, 0.2),
              [Box(0.8, 0.2), Circle(0.25, offset=(0.4, 0.2))], Circle(0.3), Box(0.5, 0.5)]
    for k in range(60):
        world.add_body(shapes[k % 5], position=(rng.uniform(-4, 4), 1 + 0.7 * k), angle=rng.uniform(0, 6))
    world.step(240)
    return np.concatenate([world.positions.ravel(), world.angles, world.velocities.ravel()])
"""


def test_a_pile_of_mixed_compound_bodies_is_bitwise_the_same_in_two_runs_and_two_processes():
    namespace: dict = {}
    exec(MIXED_PILE, namespace)
    first, second = namespace["pile"](), namespace["pile"]()
    assert np.array_equal(first, second)
    code = MIXED_PILE + "\nimport sys\nsys.stdout.buffer.write(pile().tobytes())\n"
    other = np.frombuffer(subprocess.run([sys.executable, "-c", code], capture_output=True,
                                         check=True).stdout)
    assert np.array_equal(first, other)
    heights = first[1:122:2]
    assert np.all(np.isfinite(first)) and heights.min() > -1.0  # settled in the valley, none fell through
