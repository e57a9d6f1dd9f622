"""`--set KEY=VALUE`: change the raw scene data before validation.

KEY is a dotted path; list items are chosen by index or, in the named lists, by name (bodies also by
their default name '<shape type>-<index>', joints by '<type>-<index>'). VALUE is parsed as YAML. A key
exists when the data has it, when the scene format declares it at that place (so defaults such as
`output.every` can be set without being written), or when it names a preset material under
`materials`. Anything else is an error that names the key, with a suggestion for near misses.
"""

from __future__ import annotations

import copy
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import yaml
from pydantic import BaseModel

from .scene import (
    PRESET_MATERIALS,
    Scene,
    child_annotation,
    default_generator_name,
    did_you_mean,
    model_fields_at,
    written_default_body_name,
)
from .scene_joints import default_joint_name
from .yaml_source import Path, parse_value

NAMED_LISTS = ("bodies", "forces", "attractors", "generators", "joints", "emitters", "sinks", "measures")


@dataclass(frozen=True)
class Applied:
    """An override that was applied: where it wrote (list items as indices) and how it was written."""

    path: Path
    text: str


class _OverrideError(Exception):
    """One override that cannot be applied."""


def apply_overrides(data: dict[str, Any], overrides: Sequence[str]) -> tuple[list[Applied], list[str]]:
    """Apply each `KEY=VALUE` in order to `data` (in place). Returns the overrides applied and one error
    message per override that could not be (prefixed with `--set KEY=VALUE:`)."""
    applied: list[Applied] = []
    errors: list[str] = []
    for text in overrides:
        try:
            key, sep, raw = text.partition("=")
            if not sep or not key.strip():
                raise _OverrideError("expected KEY=VALUE, e.g. world.precision=20")
            try:
                value = parse_value(raw)
            except yaml.YAMLError as err:
                problem = getattr(err, "problem", None) or err
                raise _OverrideError(f"VALUE is not valid YAML: {problem}") from None
            trial = copy.deepcopy(data)  # a failing override leaves no half-made keys behind
            applied.append(Applied(_set(trial, key.strip(), value), text))
            data.clear()
            data.update(trial)
        except _OverrideError as err:
            errors.append(f"--set {text}: {err}")
    return applied, errors


def _set(data: dict[str, Any], key: str, value: Any) -> Path:
    """Set `value` at the dotted `key`; returns the resolved path."""
    parts = key.split(".")
    if any(not part for part in parts):
        raise _OverrideError(f"'{key}' is not a dotted path like bodies.crate.angle")
    container: Any = data
    annotation: Any = Scene
    path: list[str | int] = []
    for i, part in enumerate(parts):
        last = i == len(parts) - 1
        step: str | int
        if isinstance(container, list):
            step = _list_index(container, part, path, parts[: i + 1])
            if last:
                container[step] = value
        elif isinstance(container, dict):
            step = part
            if part not in container:
                implicit = _implicit_value(container, part, annotation, parts[: i + 1])
                container[part] = value if last else implicit
            elif last:
                container[part] = value
        else:
            parent = ".".join(parts[:i])
            raise _OverrideError(f"unknown key '{key}': '{parent}' is a value, not a mapping or list")
        path.append(step)
        if not last:
            annotation = child_annotation(annotation, step, container)
            container = container[step]
            if container is None:
                raise _OverrideError(
                    f"'{'.'.join(parts[: i + 1])}' is not set: set it whole ({'.'.join(parts[: i + 1])}=...)"
                )
    return tuple(path)


def _implicit_value(container: dict[str, Any], part: str, annotation: Any, shown: list[str]) -> Any:
    """What a key the data does not write holds implicitly, as a container the path can go on into
    (None when it is not one: then the key can only be set whole); raises for keys the format does not
    declare here."""
    fields = model_fields_at(annotation, container)
    if fields is not None and part in fields:
        default = fields[part].get_default(call_default_factory=True)
        if isinstance(default, (list, tuple)):
            return list(default)
        is_model = model_fields_at(child_annotation(annotation, part, container), {}) is not None
        return {} if default is None or isinstance(default, (dict, BaseModel)) or is_model else None
    if shown[:-1] == ["materials"] and part in PRESET_MATERIALS:
        return PRESET_MATERIALS[part].model_dump()
    candidates = [*map(str, container), *(fields or ())]
    if shown[:-1] == ["materials"]:
        candidates += list(PRESET_MATERIALS)
    raise _OverrideError(f"unknown key '{'.'.join(shown)}'{_suggest(part, candidates, shown)}")


def _suggest(part: str, candidates: list[str], shown: list[str]) -> str:
    """' (did you mean 'a.b.c'?)' with the closest candidate in place of the last path element."""
    hint = did_you_mean(part, candidates)
    if not hint:
        return ""
    close = hint.split("'")[1]
    return f" (did you mean '{'.'.join([*shown[:-1], close])}'?)"


def _list_index(items: list[Any], part: str, path: list[str | int], shown: list[str]) -> int:
    """The index of the item `part` names: a name in the named lists, else a position."""
    names = _item_names(str(path[0]), items) if len(path) == 1 and path[0] in NAMED_LISTS else []
    if part in names:
        return names.index(part)
    if part.isdigit() and int(part) < len(items):
        return int(part)
    where = ".".join(shown[:-1])
    choices = f"an index 0..{len(items) - 1}" if items else "none: the list is empty"
    if names:
        choices = f"a name or {choices}"
    raise _OverrideError(
        f"unknown key '{'.'.join(shown)}': no item '{part}' in '{where}' ({choices})"
        f"{_suggest(part, names, shown)}"
    )


def _item_names(list_name: str, items: list[Any]) -> list[str]:
    """Each item's name as overrides know it: its `name`, or the default name of a body, generator or
    joint."""
    names = []
    for i, item in enumerate(items):
        item = item if isinstance(item, dict) else {}
        name = item.get("name")
        if name is None and list_name == "generators":
            name = default_generator_name(i)
        elif name is None and list_name == "bodies":
            name = written_default_body_name(item, i)
        elif name is None and list_name == "joints":
            name = default_joint_name(item.get("type"), i)
        names.append(str(name) if name is not None else "")
    return names
