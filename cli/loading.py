"""Load a scene: YAML -> overrides -> validation -> generators expanded -> the resolved scene.

Every problem is collected and reported at once as `FILE:LINE:COLUMN: path: message`, located by walking
the error's place over the YAML node tree (problems in values set by an override are reported at that
override instead). The resolved scene is written back as YAML: that text is what outputs store, and loading
it again gives the same scene.
"""

from __future__ import annotations

import contextlib
import dataclasses
import gc
import hashlib
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

from pydantic import ValidationError
from pydantic_core import ErrorDetails
from yaml.nodes import Node

from . import limits
from .errors import UserError
from .generators import expand_generators
from .overrides import NAMED_LISTS, apply_overrides
from .scene import (
    Loc,
    Scene,
    child_annotation,
    did_you_mean,
    model_fields_at,
    scene_problems,
    union_tags,
)
from .scene_size import size_problems
from .yaml_source import (
    Document,
    dump_scene_yaml,
    duplicate_keys,
    find_node,
    parse_document,
    where,
)

RESOLVED_HEADER = "# resolved by rustycs: overrides applied, generators expanded"


@dataclasses.dataclass(frozen=True)
class LoadedScene:
    """A validated scene and the exact text it resolves to."""

    scene: Scene  # generators expanded into scene.bodies (after the listed ones); scene.generators == []
    text: str  # the resolved scene as YAML; load_scene_text(text) gives the same scene back
    sha256: str  # sha256 hex of `text`
    source: str  # the file path (or a name like "RUN.h5:/parameters/scene")
    overrides: tuple[str, ...]


def load_scene(path: str | Path, overrides: Sequence[str] = (), seed: int | None = None) -> LoadedScene:
    """Load and validate a scene file; `seed` (from `rustycs run --seed`) replaces the scene's seed.
    Raises UserError with every problem found."""
    path = Path(path)
    try:
        text = read_scene_text(path)
    except FileNotFoundError:
        raise UserError(f"{path}: no such scene file") from None
    except IsADirectoryError:
        raise UserError(f"{path}: is a directory, not a scene file") from None
    except UnicodeDecodeError:
        raise UserError(f"{path}: cannot read the scene: not UTF-8 text") from None
    except OSError as err:
        raise UserError(f"{path}: cannot read the scene: {err.strerror or err}") from None
    return load_scene_text(text, str(path), overrides, seed)


def read_scene_text(path: Path) -> str:
    """The text of a scene file, refused when larger than MAX_SCENE_BYTES (also a device that never
    ends, like /dev/zero, without reading more than that)."""
    limit = int(limits.MAX_SCENE_BYTES.value)
    with path.open("rb") as handle:
        data = handle.read(limit + 1)
    if len(data) > limit:
        raise UserError(f"{path}: the scene file is larger than {limits.MAX_SCENE_BYTES}")
    return data.decode("utf-8")


def load_scene_text(
    text: str, source: str, overrides: Sequence[str] = (), seed: int | None = None
) -> LoadedScene:
    """Load and validate a scene given as YAML text; `source` names it in messages and gives the default
    scene name (its stem). Raises UserError with every problem found."""
    with _without_garbage_collection():
        return _load_scene_text(text, source, overrides, seed)


@contextlib.contextmanager
def _without_garbage_collection() -> Iterator[None]:
    """Loading makes millions of small objects and frees none of them as cycles: Python's collector,
    triggered by the allocations, would walk them all again and again (it more than doubles the time
    of a scene of 20,000 bodies)."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


def _load_scene_text(
    text: str, source: str, overrides: Sequence[str], seed: int | None
) -> LoadedScene:
    document = parse_document(text, source)
    data = {} if document.data is None else document.data
    if not isinstance(data, dict):
        raise UserError(
            f"{source}:1:1: a scene is a mapping of keys (version, world, bodies, ...), "
            f"not a {type(data).__name__}"
        )
    applied, override_errors = apply_overrides(data, overrides)
    changed = [(a.path, f"--set {a.text}") for a in applied]
    if seed is not None:
        data["seed"] = seed
        changed.append((("seed",), f"--seed {seed}"))
    data.setdefault("name", Path(source).stem)
    locate = _Locator(document, data, changed)
    too_large = [locate.problem(loc, message) for loc, message in size_problems(data)]
    if too_large:
        raise UserError(override_errors + _sorted(too_large))
    problems = [
        locate.at_node(node, path, f"duplicate key '{path[-1]}' (YAML keeps only the last)")
        for node, path in duplicate_keys(document.root)
    ]
    scene = _validate(data, locate, problems)
    if override_errors or problems:
        raise UserError(override_errors + _sorted(problems))
    assert scene is not None
    scene = _expand(scene, locate)
    resolved = _resolved_text(scene)
    digest = hashlib.sha256(resolved.encode()).hexdigest()
    return LoadedScene(scene, resolved, digest, source, tuple(overrides))


def _validate(data: dict[str, Any], locate: _Locator, problems: list[_Problem]) -> Scene | None:
    """The validated scene, or None with the problems added to `problems`."""
    found = [locate.problem(loc, message) for loc, message in scene_problems(data)]
    try:
        scene = Scene.model_validate(data)
    except ValidationError as err:
        found += locate.pydantic_errors(err.errors())
    problems += found
    return None if found else scene


def _expand(scene: Scene, locate: _Locator) -> Scene:
    """The scene with its generators' bodies appended; problems in them are reported at the generator."""
    if not scene.generators:
        return scene
    generated = expand_generators(scene)
    listed = len(scene.bodies)
    data = scene.model_dump(mode="json", exclude={"generators"})
    data["bodies"] += generated.bodies
    locate.generated(listed, generated.origins, generated.bodies)
    problems: list[_Problem] = []
    full = _validate(data, locate, problems)
    if problems:
        raise UserError(_sorted(problems))
    assert full is not None
    return full


def _resolved_text(scene: Scene) -> str:
    """The scene as YAML: complete settings, and bodies and joints without the fields left at their
    defaults."""
    data = scene.model_dump(mode="json", exclude={"generators", "bodies", "joints"})
    data["bodies"] = [body.model_dump(mode="json", exclude_defaults=True) for body in scene.bodies]
    if scene.joints:  # a scene without joints resolves to the same text as before joints existed
        data["joints"] = [joint.model_dump(mode="json", exclude_defaults=True) for joint in scene.joints]
    data["output"] = data.pop("output")
    return dump_scene_yaml(data, RESOLVED_HEADER)


# ------------------------------------------------------------------------------------------ locating


@dataclasses.dataclass(frozen=True)
class _Problem:
    """One message, and where it sorts (overrides first, then by line and column). Problems with the same
    `key` are reported once (many generated bodies of one generator tend to share a problem)."""

    order: tuple[int, int, int]
    text: str
    key: str = ""


def _sorted(problems: list[_Problem]) -> list[str]:
    return [p.text for p in sorted(_unique(problems), key=lambda p: p.order)]


def _unique(problems: list[_Problem]) -> list[_Problem]:
    unique: dict[str, _Problem] = {}
    for problem in problems:
        unique.setdefault(problem.key or problem.text, problem)
    return list(unique.values())


class _Locator:
    """Turns a place in the scene data (a pydantic `loc`) into `FILE:LINE:COLUMN: path: message`."""

    def __init__(self, document: Document, data: dict[str, Any], changed: list[tuple[Loc, str]]):
        self.document = document
        self.data = data
        self.changed = changed
        self.listed: int | None = None
        self.origins: list[int] = []
        self.bodies: list[dict[str, Any]] = []

    def generated(self, listed: int, origins: list[int], bodies: list[dict[str, Any]]) -> None:
        """From now on, body indices from `listed` on are generated bodies, located at their generator."""
        self.listed, self.origins, self.bodies = listed, origins, bodies

    def pydantic_errors(self, errors: list[ErrorDetails]) -> list[_Problem]:
        """One problem per validation error; a 'missing' key that an unknown key's suggestion names (a
        misspelling) is left out, as the unknown key says it all."""
        problems, suggested, missing = [], set(), []
        for error in errors:
            loc, message, key_node = self._explain(error)
            if error["type"] == "extra_forbidden" and "did you mean '" in message:
                suggested.add((*self._data_path(loc)[:-1], message.split("did you mean '")[1].split("'")[0]))
            if error["type"] in ("missing", "missing_key"):  # missing_key: ctx 'keys' names its keys
                missing.append((loc, message, (error.get("ctx") or {}).get("keys", (loc[-1],))))
                continue
            problems.append(self.problem(loc, message, key_node=key_node))
        problems += [
            self.problem(loc, message)
            for loc, message, keys in missing
            if not any((*self._data_path(loc), key) in suggested for key in keys)
        ]
        return problems

    def _explain(self, error: ErrorDetails) -> tuple[Loc, str, bool]:
        """The place, message and whether to point at the key (not the value) for a pydantic error."""
        loc, kind, ctx = tuple(error["loc"]), error["type"], error.get("ctx") or {}
        if "at" in ctx:  # a place below the one the error was raised at (a key, an index, or a tuple of them)
            loc = (*loc, *(ctx["at"] if isinstance(ctx["at"], tuple) else (ctx["at"],)))
        value = error.get("input")
        if kind == "missing":
            item = loc[-1]
            return (
                loc,
                (
                    f"missing key '{item}'"
                    if isinstance(item, str)
                    else f"missing item {item} (too few items)"
                ),
                False,
            )
        if kind == "extra_forbidden":
            fields = self._fields_at(self._data_path(loc)[:-1])
            return loc, f"unknown key '{loc[-1]}'{did_you_mean(str(loc[-1]), fields)}", True
        if kind in ("shape", "joint") and isinstance(value, dict):
            tags = union_tags(self._annotation_at(self._data_path(loc)))
            kind_value = value.get("type")
            if kind_value is None:
                return loc, f"missing key 'type' (one of: {', '.join(tags)})", False
            hint = did_you_mean(str(kind_value), tags)
            message = f"unknown {kind} type '{kind_value}'{hint}; expected one of: {', '.join(tags)}"
            return (*loc, "type"), message, False
        message = "expected a list of two values, like [x, y]" if kind == "tuple_type" else error["msg"]
        if isinstance(value, (int, float, str, bool)) and kind not in ("polygon", "aabb_angle", "rect"):
            message += f" (got {value!r})"
        return loc, message, bool(ctx.get("at_key"))

    def problem(self, loc: Loc, message: str, key_node: bool = False) -> _Problem:
        """The message for a place in the scene data."""
        if (
            self.listed is not None
            and len(loc) >= 2
            and loc[0] == "bodies"
            and isinstance(loc[1], int)
            and loc[1] >= self.listed
        ):
            return self._generated_problem(loc, message, key_node)
        path = self._data_path(loc)
        for changed_path, label in reversed(self.changed):
            if path[: len(changed_path)] == changed_path:
                return _Problem((0, 0, 0), f"{label}: {self._dotted(path)}: {message}")
        node = find_node(self.document.root, path, key=key_node)
        return self.at_node(node, path, message)

    def at_node(self, node: Node | None, path: Loc, message: str) -> _Problem:
        """The message for a place in the YAML file."""
        line, column = where(node) if node is not None else (1, 1)
        text = f"{self.document.source}:{line}:{column}: {self._dotted(path)}: {message}"
        return _Problem((1, line, column), text)

    def _generated_problem(self, loc: Loc, message: str, key_node: bool) -> _Problem:
        index = int(loc[1]) - (self.listed or 0)
        generator = self.origins[index]
        body = self.bodies[index]["name"]
        rest = self._relative_path(self.data["generators"][generator], loc[2:])
        problem = self.problem(
            ("generators", generator, *rest), f"generated body '{body}': {message}", key_node=key_node
        )
        same = message.split(" (got ")[0]  # the same problem with another drawn value is reported once
        return dataclasses.replace(problem, key=f"{generator} {rest} {same}")

    def _data_path(self, loc: Loc) -> Loc:
        """The part of `loc` that exists in the data, with union tags left out."""
        return self._relative_path(self.data, loc)

    @staticmethod
    def _relative_path(data: Any, loc: Sequence[str | int]) -> Loc:
        path: list[str | int] = []
        for part in loc:
            if isinstance(data, dict) and part in data:
                data = data[part]
            elif isinstance(data, list) and isinstance(part, int) and 0 <= part < len(data):
                data = data[part]
            else:
                continue  # a union tag, or the key a 'missing' error names
            path.append(part)
        return tuple(path)

    def _annotation_at(self, path: Loc) -> Any:
        annotation: Any = Scene
        data: Any = self.data
        for part in path:
            annotation = child_annotation(annotation, part, data)
            data = data[part]
        return annotation

    def _fields_at(self, path: Loc) -> list[str]:
        data: Any = self.data
        for part in path:
            data = data[part]
        return list(model_fields_at(self._annotation_at(path), data) or ())

    def _dotted(self, path: Loc) -> str:
        """A data path as an override KEY would write it (named list items by name)."""
        parts: list[str] = []
        data: Any = self.data
        for part in path:
            item = data[part] if isinstance(data, (dict, list)) else None
            name = item.get("name") if isinstance(item, dict) and isinstance(part, int) else None
            in_named_list = len(parts) == 1 and parts[0] in NAMED_LISTS
            named = in_named_list and isinstance(name, str) and name.isprintable() and "." not in name
            parts.append(name if named else str(part))
            data = item
        return ".".join(parts) or "scene"
