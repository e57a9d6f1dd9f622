"""A seeded mutation fuzzer over the shipped scenes: whatever a scene file holds, `rustycs validate`
answers with exit code 0 or 2 and never a traceback (issue 15: 262 tracebacks in 7,000 mutants before)."""

from __future__ import annotations

import random
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SCENES = sorted((ROOT / "scenes").glob("*.yaml"))  # the small ones: the bench scenes take seconds each
MUTANTS = 400
SEED = 15

HOSTILE = [
    ".inf", "-.inf", ".nan", "1e309", "-1e309", "1e-300", "1e300", "0", "-1", "-0.0", "true", "no", "null",
    "~", "'0.5'", '"1e3"', "10.0", "1:30", "0x7f", "9223372036854775808", str(10**30), "!!float x",
    "!!int abc", "!!bool maybe", "!!timestamp 2001-13-45", "!!binary '###'", "[]", "{}", "[1]",
    "[1, 2, 3]", "[.inf, 0]", "{uniform: [1, 0]}", "{normal: [0, -1]}", "{uniform_int: [0, 1e30]}",
    "{choice: []}", "*nowhere", "&a [*a]", '"a\\0b"', '"\\x1b[31m"', "../../escaped", "/abs/path", "x" * 300,
    "[[0, 0], [1, 0], [0, 1], [1, 1]]", "{type: random_polygon, vertices: 1000, radius: 1}",
]
PUNCTUATION = list(":-[]{},&*!|>'\"%@`#\t\x00\x01\x7f\u2028\ufeff")


def _mutate(text: str, rng: random.Random) -> str:
    """One to three random edits of the text: hostile values for numbers and words, deleted, repeated
    or swapped lines, stray punctuation and control characters, a truncation."""
    for _ in range(rng.randint(1, 3)):
        lines = text.splitlines(keepends=True)
        kind = rng.randrange(6)
        if kind <= 1:  # replace a value after a colon or in a list
            spots = [i for i, char in enumerate(text) if char in ":,[" and i + 1 < len(text)]
            if spots:
                start = rng.choice(spots) + 1
                end = start + 1
                while end < len(text) and text[end] not in ",]}\n":
                    end += 1
                text = f"{text[:start]} {rng.choice(HOSTILE)}{text[end:]}"
        elif kind == 2 and lines:  # delete or repeat a line
            i = rng.randrange(len(lines))
            lines[i:i + 1] = [] if rng.random() < 0.5 else [lines[i]] * rng.randint(2, 4)
            text = "".join(lines)
        elif kind == 3 and len(lines) > 1:  # swap two lines
            i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
            lines[i], lines[j] = lines[j], lines[i]
            text = "".join(lines)
        elif kind == 4:  # a stray character
            at = rng.randrange(len(text) + 1)
            text = text[:at] + rng.choice(PUNCTUATION) + text[at:]
        else:  # cut the file short
            text = text[:rng.randrange(len(text) + 1)]
    return text


def test_mutated_scenes_never_give_a_traceback(cli, tmp_path: Path) -> None:
    rng = random.Random(SEED)
    originals = [path.read_text(encoding="utf-8") for path in SCENES]
    codes: dict[int, int] = {}
    for n in range(MUTANTS):
        mutant = _mutate(rng.choice(originals), rng)
        path = tmp_path / f"mutant-{n}.yaml"
        path.write_text(mutant, encoding="utf-8", errors="surrogateescape")
        result = cli("validate", path)
        if result.exit_code not in (0, 2) or "Traceback" in result.stderr:
            pytest.fail(f"mutant {n} gave exit code {result.exit_code}:\n{result.stderr[-3000:]}\n"
                        f"--- the mutant:\n{mutant[:3000]}")
        if result.exit_code == 2:
            assert result.stderr.strip(), f"mutant {n}: exit code 2 without a message"
        codes[result.exit_code] = codes.get(result.exit_code, 0) + 1
        path.unlink()
    assert codes.get(2, 0) > MUTANTS // 4 and codes.get(0, 0) > 0  # the mutants do hit both outcomes
