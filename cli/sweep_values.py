"""Parsing of `rustycs sweep -p KEY=V1,V2,...` and `-p KEY=range(START,STOP,STEP)`.

Each swept value keeps the text the user wrote, because that text becomes a `--set KEY=TEXT`
override: the scene loader then parses it exactly as it parses `--set` (YAML), and the parsed value
is what the sweep tables show.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from decimal import Decimal, InvalidOperation
from typing import Any

from .errors import UserError

MAX_RANGE_VALUES = 100_000
RANGE = re.compile(r"range\((?P<args>[^()]*)\)", re.IGNORECASE)
OPENERS, CLOSERS = "[{", "]}"


@dataclass(frozen=True)
class SweptValue:
    """One value of a swept key: its override text and the value it parses to."""

    text: str
    value: Any


@dataclass(frozen=True)
class SweptKey:
    """A scene key (dotted, as in --set) and the values it takes, in order."""

    key: str
    values: tuple[SweptValue, ...]


def parse_swept_keys(options: list[str]) -> list[SweptKey]:
    """Parse every -p option; all problems are reported together as one UserError."""
    swept: list[SweptKey] = []
    problems: list[str] = []
    for option in options:
        try:
            key = parse_swept_key(option)
        except UserError as err:
            problems.extend(err.messages)
            continue
        if any(s.key == key.key for s in swept):
            problems.append(f"-p {option}: {key.key} is swept twice; give all its values in one -p")
        swept.append(key)
    if problems:
        raise UserError(problems)
    return swept


def parse_swept_key(option: str) -> SweptKey:
    """Parse one `KEY=V1,V2,...` or `KEY=range(START,STOP,STEP)` option."""
    key, sep, rest = option.partition("=")
    key, rest = key.strip(), rest.strip()
    if not sep or not key or not rest:
        raise UserError(f"-p {option}: expected KEY=V1,V2,... or KEY=range(START,STOP,STEP)")
    match = RANGE.fullmatch(rest)
    texts = _range_texts(option, match["args"]) if match else _split_top_level(option, rest)
    if len(set(texts)) != len(texts):
        raise UserError(f"-p {option}: a value is listed twice")
    parse = _number if match else _parse  # a range's values are numbers: no YAML needed
    return SweptKey(key, tuple(SweptValue(text, parse(option, text)) for text in texts))


def _number(_option: str, text: str) -> int | float:
    """A number written by `_range_texts` (an int, or a float's repr), as YAML would read it."""
    return float(text) if any(c in text for c in ".en") else int(text)


def _parse(option: str, text: str) -> Any:
    """The value as `--set` reads it (YAML, with 1e-3 a number)."""
    import yaml

    from .yaml_source import parse_value

    try:
        return parse_value(text)
    except yaml.YAMLError as err:
        problem = getattr(err, "problem", None) or err
        raise UserError(f"-p {option}: {text} is not valid YAML: {problem}") from None


def _split_top_level(option: str, text: str) -> list[str]:
    """Split at commas outside brackets, braces and quotes, so `[0,-1],[0,-2]` gives two lists."""
    parts: list[str] = []
    depth, quote, start = 0, "", 0
    for i, char in enumerate(text):
        if quote:
            quote = "" if char == quote else quote
        elif char in "'\"":
            quote = char
        elif char in OPENERS:
            depth += 1
        elif char in CLOSERS:
            depth -= 1
        elif char == "," and depth == 0:
            parts.append(text[start:i].strip())
            start = i + 1
    parts.append(text[start:].strip())
    if depth != 0 or quote:
        raise UserError(f"-p {option}: unbalanced brackets or quotes")
    if not all(parts):
        raise UserError(f"-p {option}: empty value in the list")
    return parts


def _range_texts(option: str, args: str) -> list[str]:
    """range(STOP), range(START,STOP) or range(START,STOP,STEP): STOP excluded, decimals allowed.

    Decimal arithmetic keeps range(0,1,0.1) at 0.3 rather than 0.30000000000000004.
    """
    fields = [a.strip() for a in args.split(",")]
    try:
        numbers = [Decimal(f) for f in fields]
    except InvalidOperation:
        numbers = []
    if not 1 <= len(numbers) <= 3 or not all(n.is_finite() for n in numbers):
        raise UserError(f"-p {option}: range takes 1 to 3 numbers: range(START,STOP,STEP)")
    if len(numbers) == 1:
        start, stop, step = Decimal(0), numbers[0], Decimal(1)
    elif len(numbers) == 2:
        start, stop, step = numbers[0], numbers[1], Decimal(1)
    else:
        start, stop, step = numbers
    if step == 0:
        raise UserError(f"-p {option}: the range step must not be 0")
    integers = all(re.fullmatch(r"[-+]?\d+", f) for f in fields)
    texts: list[str] = []
    value = start
    while (value < stop) if step > 0 else (value > stop):
        texts.append(str(int(value)) if integers else repr(float(value)))
        if len(texts) > MAX_RANGE_VALUES:
            raise UserError(f"-p {option}: more than {MAX_RANGE_VALUES} values")
        value += step
    if not texts:
        raise UserError(f"-p {option}: the range is empty (STOP is excluded)")
    return texts
