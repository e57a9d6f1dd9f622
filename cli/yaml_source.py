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

from .errors import UserError

Path = tuple[str | int, ...]


class SceneLoader(yaml.SafeLoader):
    """SafeLoader that also reads 1e-3, 1E5, 1.5e3, -2.5e-3 and .5e2 as floats."""


class SceneDumper(yaml.SafeDumper):
    """SafeDumper that quotes strings SceneLoader would read as floats (a body named "1e3")."""


_EXPONENT_FLOAT = re.compile(r"^[-+]?(?:[0-9][0-9_]*(?:\.[0-9_]*)?|\.[0-9_]+)[eE][-+]?[0-9]+$")
for _cls in (SceneLoader, SceneDumper):
    _cls.add_implicit_resolver("tag:yaml.org,2002:float", _EXPONENT_FLOAT, list("-+0123456789."))


@dataclass(frozen=True)
class Document:
    """A parsed YAML document: the constructed data and the node tree it came from (None when empty)."""

    data: Any
    root: Node | None
    source: str


def parse_document(text: str, source: str) -> Document:
    """Parse one YAML document; a syntax error becomes a UserError at its line and column."""
    loader = SceneLoader(text)
    try:
        root = loader.get_single_node()
        data = loader.construct_document(root) if root is not None else None
    except yaml.MarkedYAMLError as err:
        mark = err.problem_mark or err.context_mark
        where = f"{source}:{mark.line + 1}:{mark.column + 1}" if mark else source
        raise UserError(f"{where}: YAML syntax error: {err.problem or err.context}") from None
    except yaml.YAMLError as err:
        raise UserError(f"{source}: YAML error: {err}") from None
    finally:
        loader.dispose()
    return Document(data, root, source)


def parse_value(text: str) -> Any:
    """A YAML value given on the command line (raises yaml.YAMLError)."""
    return yaml.load(text, Loader=SceneLoader)


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
    """Every key written twice in one mapping (YAML would silently keep the last), with its path."""
    found: list[tuple[Node, Path]] = []

    def walk(node: Node, path: Path) -> None:
        if isinstance(node, MappingNode):
            seen: set[str] = set()
            for key_node, value_node in node.value:
                name = key_node.value if isinstance(key_node, ScalarNode) else None
                if name is not None and name != "<<":
                    if name in seen:
                        found.append((key_node, (*path, name)))
                    seen.add(name)
                walk(value_node, (*path, name if name is not None else "?"))
        elif isinstance(node, SequenceNode):
            for i, item in enumerate(node.value):
                walk(item, (*path, i))

    if root is not None:
        walk(root, ())
    return found


def _flow(value: Any) -> str:
    """A value on one line in YAML flow style."""
    text = yaml.dump(value, Dumper=SceneDumper, default_flow_style=True, width=float("inf"), sort_keys=False)
    return text.strip()


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
