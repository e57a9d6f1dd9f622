"""How much a scene asks for, checked on the raw data before validation: validating, generating and
simulating a scene of a billion bodies would run the machine out of memory long before any message."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from . import limits
from .scene import Problem


def size_problems(data: Mapping[str, Any]) -> list[Problem]:
    """Lists longer than MAX_LIST_ITEMS, more bodies (listed and generated) than MAX_BODIES, and more
    shapes on them than MAX_SHAPES."""
    problems: list[Problem] = []
    for key in ("forces", "attractors", "generators", "materials"):
        items = data.get(key)
        if isinstance(items, list | dict) and len(items) > limits.MAX_LIST_ITEMS.value:
            problems.append(((key,), f"at most {limits.MAX_LIST_ITEMS} entries, this has {len(items)}"))
    bodies = data.get("bodies")
    total = len(bodies) if isinstance(bodies, list) else 0
    shapes = sum(_shape_count(body) for body in bodies) if isinstance(bodies, list) else 0
    where: tuple[str | int, ...] = ("bodies",)
    generators = data.get("generators")
    for g, generator in enumerate(generators if isinstance(generators, list) else ()):
        count = _count(generator) if isinstance(generator, dict) else 0
        total += count
        shapes += count * _shape_count(generator)
        if count > 0 and total > limits.MAX_BODIES.value and where == ("bodies",):
            where = ("generators", g, "count" if "count" in generator else "layout")
    if total > limits.MAX_BODIES.value:
        problems.append((where, f"the scene has {total} bodies, more than {limits.MAX_BODIES}"))
    elif shapes > limits.MAX_SHAPES.value:
        problems.append((("bodies",), f"the bodies have {shapes} shapes, more than {limits.MAX_SHAPES}"))
    return problems


def _shape_count(entry: Any) -> int:
    """The shapes a body or a generator's bodies have, as written (1 for `shape`)."""
    shapes = entry.get("shapes") if isinstance(entry, dict) else None
    return len(shapes) if isinstance(shapes, list) else 1


def _count(generator: Mapping[str, Any]) -> int:
    """The bodies a generator makes as written: its count, or a full pyramid's (0 when not a number)."""
    count = generator.get("count")
    if _whole(count):
        return count
    layout = generator.get("layout")
    pyramid = layout.get("pyramid") if isinstance(layout, dict) else None
    base = pyramid.get("base") if isinstance(pyramid, dict) else None
    return base * (base + 1) // 2 if _whole(base) and base > 0 else 0


def _whole(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)
