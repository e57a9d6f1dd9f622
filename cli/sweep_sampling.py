"""Random variants of a sweep: `-p KEY=uniform(LO,HI)` and `-p KEY=normal(MEAN,STD)` with `--samples N`.

Each sample draws every sampled key once, in the order given, from one numpy PCG64 stream seeded by
`--seed`: the same command gives the same variants. A drawn value becomes a `--set KEY=VALUE` override
written with its full precision (repr), so the table shows exactly the value that ran.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from .errors import UserError
from .sweep_values import SweptValue

SAMPLED = re.compile(r"^\s*(?P<kind>uniform|normal)\((?P<args>[^()]*)\)\s*$", re.IGNORECASE)
SampledRow = dict[str, SweptValue]  # one sample: key -> its drawn value


@dataclass(frozen=True)
class SampledKey:
    key: str
    kind: str  # uniform | normal
    a: float  # lo | mean
    b: float  # hi | std


def is_sampled(option: str) -> bool:
    """Whether a -p option draws its values (KEY=uniform(..) or KEY=normal(..))."""
    return bool(SAMPLED.match(option.partition("=")[2]))


def parse_sampled(option: str) -> SampledKey:
    key, _, rest = option.partition("=")
    match = SAMPLED.match(rest)
    assert match is not None
    kind = match["kind"].lower()
    try:
        a, b = (float(part) for part in match["args"].split(","))
    except ValueError:
        raise UserError(f"-p {option}: expected {kind}(A,B) with two numbers") from None
    if kind == "uniform" and not a <= b:
        raise UserError(f"-p {option}: uniform(LO,HI) needs LO <= HI")
    if kind == "normal" and not b >= 0:
        raise UserError(f"-p {option}: normal(MEAN,STD) needs STD >= 0")
    return SampledKey(key.strip(), kind, a, b)


def draw_samples(keys: list[SampledKey], count: int, seed: int) -> list[SampledRow]:
    """`count` samples of the keys, reproducibly from `seed`."""
    import numpy as np

    rng = np.random.Generator(np.random.PCG64(seed))
    rows = []
    for _ in range(count):
        row = {}
        for key in keys:
            value = float(rng.uniform(key.a, key.b) if key.kind == "uniform" else rng.normal(key.a, key.b))
            row[key.key] = SweptValue(repr(value), value)
        rows.append(row)
    return rows
