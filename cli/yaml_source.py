"""YAML in and out for scenes: parsing that keeps every value's line and column, and a compact writer.

PyYAML follows YAML 1.1, where `1e-3` (no dot) is a string; scenes need it to be a number, so the loader
adds an implicit resolver for exponent floats. The document is composed into a node tree first and then
constructed, so that any problem found in the data can be reported at the line and column it came from.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import yaml
from yaml.nodes import MappingNode, Node, ScalarNode, SequenceNode

from . import limits
from .errors import UserError

Path = tuple[str | int, ...]


class _ResolveOnce:
    """Implicit tags of plain scalars remembered per class and text: a scene repeats the same few values
    (0.5, circle, dynamic) thousands of times, and PyYAML tries every pattern on each."""

    def resolve(self, kind: Any, value: Any, implicit: Any) -> Any:
        if kind is not ScalarNode or not implicit[0] or len(value) > 64:
            return super().resolve(kind, value, implicit)  # type: ignore[misc]
        known = type(self).__dict__.get("_resolved")
        if known is None:
            known = {}
            type.__setattr__(type(self), "_resolved", known)
        key = (value, implicit[1])
        if key not in known:
            if len(known) > 100_000:
                known.clear()
            known[key] = super().resolve(kind, value, implicit)  # type: ignore[misc]
        return known[key]


class SceneLoader(_ResolveOnce, yaml.SafeLoader):
    """SafeLoader that also reads 1e-3, 1E5, 1.5e3, -2.5e-3 and .5e2 as floats, and 1:30 as text (not
    YAML 1.1's sexagesimal 90)."""


class FastSceneLoader(_ResolveOnce, yaml.CSafeLoader):  # type: ignore[misc]
    """The same, parsed by libyaml (several times faster); its error messages are less clear, so a
    document it refuses is parsed again by SceneLoader for the message."""


class SceneDumper(_ResolveOnce, yaml.CSafeDumper):  # type: ignore[misc]
    """SafeDumper (libyaml's: the same text, faster) that quotes strings SceneLoader would read as floats
    (a body named "1e3")."""


_EXPONENT_FLOAT = re.compile(r"^[-+]?(?:[0-9][0-9_]*(?:\.[0-9_]*)?|\.[0-9_]+)[eE][-+]?[0-9]+$")
_SEXAGESIMAL = re.compile(r"^[-+]?[0-9][0-9_]*(?::[0-5]?[0-9])+(?:\.[0-9_]*)?$")
class _DumperResolver(_ResolveOnce, yaml.resolver.Resolver):
    """SceneDumper's resolver alone: whether a string would be written plain."""


_LOADERS = (SceneLoader, FastSceneLoader)
for _cls in (*_LOADERS, SceneDumper, _DumperResolver):
    _cls.add_implicit_resolver("tag:yaml.org,2002:float", _EXPONENT_FLOAT, list("-+0123456789."))
for _cls in _LOADERS:
    # first match wins: 1:30 resolves as a string before the int and float resolvers see it
    _cls.add_implicit_resolver("tag:yaml.org,2002:str", _SEXAGESIMAL, list("-+0123456789"))
    for _first, _resolvers in list(_cls.yaml_implicit_resolvers.items()):
        _cls.yaml_implicit_resolvers[_first] = sorted(
            _resolvers, key=lambda resolver: resolver[0] != "tag:yaml.org,2002:str"
        )


def _checked(construct: Any, what: str) -> Any:
    """A scalar constructor that reports a value its tag cannot read (`!!int abc`) at the value."""

    def checked(loader: yaml.SafeLoader, node: Node) -> Any:
        try:
            return construct(loader, node)
        except (ValueError, KeyError, TypeError, AttributeError, OverflowError):
            raise yaml.constructor.ConstructorError(
                None, None, f"cannot read {node.value!r} as {what}", node.start_mark
            ) from None

    return checked


for _tag, _what in (("int", "an integer"), ("float", "a number"), ("bool", "a boolean"),
                    ("timestamp", "a timestamp"), ("binary", "binary data")):
    _construct = yaml.SafeLoader.yaml_constructors[f"tag:yaml.org,2002:{_tag}"]
    for _cls in _LOADERS:
        _cls.add_constructor(f"tag:yaml.org,2002:{_tag}", _checked(_construct, _what))


@dataclass(frozen=True)
class Document:
    """A parsed YAML document: the constructed data and the node tree it came from (None when empty)."""

    data: Any
    root: Node | None
    source: str


def parse_document(text: str, source: str) -> Document:
    """Parse one YAML document; a syntax error, a value its tag cannot read, nesting deeper than
    MAX_YAML_DEPTH, a recursive alias or aliases that expand beyond MAX_YAML_VALUES become a UserError
    at its line and column."""
    try:
        root, data = _load(text, FastSceneLoader)
    except (TreeError, yaml.constructor.ConstructorError) as err:
        raise UserError(_located(err, source, text)) from None
    except yaml.YAMLError as fast:
        try:  # the same problem, in PyYAML's clearer words
            _load(text, SceneLoader)
        except yaml.YAMLError as err:
            raise UserError(_located(err, source, text)) from None
        except RecursionError:
            pass
        raise UserError(_located(fast, source, text)) from None
    return Document(data, root, source)


def _load(text: str, loader_class: type[yaml.SafeLoader]) -> tuple[Node | None, Any]:
    loader = loader_class(text)
    try:
        root = loader.get_single_node()
        if root is None:
            return None, None
        check_tree(root)
        return root, loader.construct_document(root)
    finally:
        loader.dispose()


def _located(err: yaml.YAMLError, source: str, text: str) -> str:
    """`FILE:LINE:COLUMN: problem` for a YAML error."""
    if isinstance(err, yaml.MarkedYAMLError):
        mark = err.problem_mark or err.context_mark
        where = f"{source}:{mark.line + 1}:{mark.column + 1}" if mark else source
        kind = "YAML syntax error" if isinstance(err, (yaml.scanner.ScannerError, yaml.parser.ParserError,
                                                           yaml.composer.ComposerError)) else "YAML error"
        return f"{where}: {kind}: {err.problem or err.context}"
    if isinstance(err, yaml.reader.ReaderError):
        before = text[: err.position]
        line, column = before.count("\n") + 1, err.position - (before.rfind("\n") + 1) + 1
        return f"{source}:{line}:{column}: YAML error: {err.reason} (character #x{err.character:04x})"
    return f"{source}: YAML error: {err}"


class TreeError(yaml.MarkedYAMLError):
    """A document too deep or too large once its aliases are expanded."""


def check_tree(root: Node) -> None:
    """Raise TreeError for nesting deeper than MAX_YAML_DEPTH, a recursive alias (`a: &x [*x]`) or a
    document that expands to more than MAX_YAML_VALUES values through aliases (a billion laughs). Each
    node is visited once, however many aliases point at it."""
    visited: set[int] = set()
    shared = False
    collections: list[tuple[Node, int]] = [(root, 1)]
    while collections:
        node, depth = collections.pop()
        if id(node) in visited:
            shared = True
            continue
        visited.add(id(node))
        if depth > limits.MAX_YAML_DEPTH.value:
            raise TreeError(None, None, f"nesting deeper than {limits.MAX_YAML_DEPTH}", node.start_mark)
        collections.extend((c, depth + 1) for c in _children(node) if not isinstance(c, ScalarNode))
    if shared:
        _check_aliases(root)


def _check_aliases(root: Node) -> None:
    """TreeError for a value that contains itself, or aliases that expand beyond MAX_YAML_VALUES."""
    sizes: dict[int, int] = {}  # id(node): values it expands to, once known
    stack: list[tuple[Node, bool]] = [(root, False)]
    open_nodes: set[int] = set()
    while stack:
        node, done = stack.pop()
        children = _children(node)
        if done:
            open_nodes.discard(id(node))
            sizes[id(node)] = min(1 + sum(sizes[id(c)] for c in children), limits.MAX_YAML_VALUES.value + 1)
            continue
        if id(node) in sizes:
            continue
        if id(node) in open_nodes:
            raise TreeError(None, None, "a recursive alias (a value that contains itself)", node.start_mark)
        open_nodes.add(id(node))
        stack.append((node, True))
        stack.extend((child, False) for child in children if id(child) not in sizes)
    if sizes[id(root)] > limits.MAX_YAML_VALUES.value:
        raise TreeError(None, None, f"the aliases expand to more than {limits.MAX_YAML_VALUES}",
                        root.start_mark)


def _children(node: Node) -> list[Node]:
    if isinstance(node, MappingNode):
        return [part for pair in node.value for part in pair]
    if isinstance(node, SequenceNode):
        return list(node.value)
    return []


def parse_value(text: str) -> Any:
    """A YAML value given on the command line (raises yaml.YAMLError)."""
    return _load(text, SceneLoader)[1]


def where(node: Node) -> tuple[int, int]:
    """1-based (line, column) of a node's start."""
    return node.start_mark.line + 1, node.start_mark.column + 1


def find_node(root: Node | None, path: Path, key: bool = False) -> Node | None:
    """The node at `path` (the key's node instead of its value when `key`), or the deepest node on the
    way there."""
    node = root
    for i, part in enumerate(path):
        child = None
        if isinstance(node, MappingNode):
            for key_node, value_node in node.value:
                if isinstance(key_node, ScalarNode) and key_node.value == str(part):
                    child = key_node if key and i == len(path) - 1 else value_node
        elif isinstance(node, SequenceNode) and isinstance(part, int) and 0 <= part < len(node.value):
            child = node.value[part]
        if child is None:
            break
        node = child
    return node


def duplicate_keys(root: Node | None) -> list[tuple[Node, Path]]:
    """Every key written twice in one mapping (YAML would silently keep the last), with its path. Each
    node is visited once, at the first path that reaches it, however many aliases point at it."""
    found: list[tuple[Node, Path]] = []
    seen_nodes: set[int] = set()
    stack: list[tuple[Node, Path]] = [(root, ())] if root is not None else []
    while stack:
        node, path = stack.pop()
        if id(node) in seen_nodes:
            continue
        seen_nodes.add(id(node))
        if isinstance(node, MappingNode):
            seen: set[str] = set()
            for key_node, value_node in node.value:
                name = key_node.value if isinstance(key_node, ScalarNode) else None
                if name is not None and name != "<<":
                    if name in seen:
                        found.append((key_node, (*path, name)))
                    seen.add(name)
                stack.append((value_node, (*path, name if name is not None else "?")))
        elif isinstance(node, SequenceNode):
            stack.extend((item, (*path, i)) for i, item in enumerate(node.value))
    return found


def _flow(value: Any) -> str:
    """A value on one line in YAML flow style: the text yaml.dump writes, written directly for the
    plain data of a scene (the representer costs a millisecond per body), by yaml.dump otherwise."""
    try:
        return _plain_flow(value)
    except _Unusual:
        text = yaml.dump(value, Dumper=SceneDumper, default_flow_style=True, width=2**30, sort_keys=False)
        return text.strip()


class _Unusual(Exception):
    """A value `_plain_flow` leaves to yaml.dump."""


_PLAIN_WORD = re.compile(r"^[A-Za-z_][A-Za-z0-9_-]*$")
_PLAIN_TAG = "tag:yaml.org,2002:str"
_RESOLVER = _DumperResolver()


def _plain_flow(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if value != value or value in (float("inf"), float("-inf")):
            raise _Unusual
        text = repr(value).lower()  # SafeRepresenter.represent_float
        return text.replace("e", ".0e", 1) if "." not in text and "e" in text else text
    if value is None:
        return "null"
    if isinstance(value, str):
        if _PLAIN_WORD.match(value) and _RESOLVER.resolve(ScalarNode, value, (True, False)) == _PLAIN_TAG:
            return value
        raise _Unusual
    if isinstance(value, dict):
        return "{" + ", ".join(f"{_plain_flow(k)}: {_plain_flow(v)}" for k, v in value.items()) + "}"
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_plain_flow(item) for item in value) + "]"
    raise _Unusual


def dump_scene_yaml(data: Mapping[str, Any], header: str = "") -> str:
    """Write scene data compactly: block style at the top, one flow-style line per list item (bodies,
    forces, ...), so that files with thousands of bodies stay readable and diffable."""
    lines = [header.rstrip("\n")] if header else []
    for key, value in data.items():
        if isinstance(value, Sequence) and not isinstance(value, str) and value:
            lines.append(f"{key}:")
            lines.extend(f"  - {_flow(item)}" for item in value)
        elif isinstance(value, Mapping) and value:
            lines.append(f"{key}:")
            lines.extend(f"  {_flow({k: v})[1:-1]}" for k, v in value.items())
        else:
            lines.append(_flow({key: value})[1:-1])
    return "\n".join(lines) + "\n"
