"""Union-find over body rows: the islands of bodies joined by contacts (sleeping, the solver's groups)."""

from __future__ import annotations

from rustycs.compiling import inlined


@inlined
def find_root(parent, i):
    """The root of i's island, halving the path on the way."""
    while parent[i] != i:
        parent[i] = parent[parent[i]]
        i = parent[i]
    return i


@inlined
def join(parent, a, b):
    """Join the islands of a and b under the smaller root: the roots do not depend on the order."""
    ra = find_root(parent, a)
    rb = find_root(parent, b)
    if ra < rb:
        parent[rb] = ra
    elif rb < ra:
        parent[ra] = rb
