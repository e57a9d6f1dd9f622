"""`placement: no_overlap` of generators: bodies drawn apart, reproducibly, or a clear error."""

from __future__ import annotations

import itertools
import math
from pathlib import Path

import pytest

from rustycs_cli.errors import UserError
from rustycs_cli.loading import load_scene

RAIN = """\
name: rain
seed: 3
generators:
  - name: rain
    count: {count}
    shape: {{type: circle, radius: {{uniform: [0.1, 0.3]}}}}
    region: {{min: [-5, 0], max: [5, 10]}}
    placement: {placement}
"""


def rain(tmp_path: Path, count: int, placement: str) -> list:
    path = tmp_path / f"rain-{count}-{placement}.yaml"
    path.write_text(RAIN.format(count=count, placement=placement))
    return load_scene(path).scene.bodies


def overlaps(bodies: list) -> int:
    return sum(math.dist(a.position, b.position) < a.shape.radius + b.shape.radius
               for a, b in itertools.combinations(bodies, 2))


def test_no_overlap_draws_bodies_apart_and_keeps_their_shapes(tmp_path: Path) -> None:
    free, apart = rain(tmp_path, 150, "free"), rain(tmp_path, 150, "no_overlap")
    assert overlaps(free) > 20 and overlaps(apart) == 0
    assert [b.shape.radius for b in free] == [b.shape.radius for b in apart]  # only positions are drawn again
    assert [b.position for b in apart] == [b.position for b in rain(tmp_path, 150, "no_overlap")]


def test_no_free_spot_is_an_error_naming_the_generator(tmp_path: Path) -> None:
    with pytest.raises(UserError) as raised:
        rain(tmp_path, 2000, "no_overlap")
    assert raised.value.exit_code == 2
    assert raised.value.messages[0].startswith("generator 'rain': no free spot for body ")
