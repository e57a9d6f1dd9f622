"""Sorting a run of an array in place, inside compiled code, without allocating."""

from __future__ import annotations

from rustycs.compiling import inlined


@inlined
def sort_run(values, lo, hi):
    """Sort values[lo:hi] in place: by insertion when short (a shape's few partners, found nearly in
    order), else by heapsort. Insertion alone was 0.3 of the 1.35 ms of the tumbler's `find_pairs`: two
    of its drum's walls have ~1,000 partners each, found in cell order (m^2 / 4 moves each)."""
    if hi - lo <= 32:
        for k in range(lo + 1, hi):
            value = values[k]
            j = k
            while j > lo and values[j - 1] > value:
                values[j] = values[j - 1]
                j -= 1
            values[j] = value
        return
    n = hi - lo
    for start in range(n // 2 - 1, -1, -1):
        _sift_down(values, lo, start, n)
    for end in range(n - 1, 0, -1):
        values[lo], values[lo + end] = values[lo + end], values[lo]
        _sift_down(values, lo, 0, end)


@inlined
def _sift_down(values, lo, root, n):
    """Restore the max-heap of values[lo:lo + n] below `root`."""
    while True:
        child = 2 * root + 1
        if child >= n:
            return
        if child + 1 < n and values[lo + child + 1] > values[lo + child]:
            child += 1
        if values[lo + root] >= values[lo + child]:
            return
        values[lo + root], values[lo + child] = values[lo + child], values[lo + root]
        root = child
