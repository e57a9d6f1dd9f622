"""The previous tick's contact points: their keys and accumulated impulses, which warm-start this tick's
points of the same shape pair and feature.

Both key lists are sorted (pairs in order, features in order), so one merge pass matches them.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from rustycs.compiling import inlined
from rustycs.narrow_phase import NORMAL_IMPULSE, TANGENT_IMPULSE


class ContactCache(NamedTuple):
    key: np.ndarray  # int64, sorted; the first count[0] are in use
    normal_impulse: np.ndarray
    tangent_impulse: np.ndarray
    count: np.ndarray  # int64 (1,)


@njit(cache=True)
def new_cache(capacity, key, normal_impulse, tangent_impulse):
    """A cache for `capacity` points holding the given entries."""
    capacity = max(capacity, key.shape[0])
    cache = ContactCache(np.empty(capacity, np.int64), np.empty(capacity), np.empty(capacity),
                         np.zeros(1, np.int64))
    k = key.shape[0]
    cache.key[:k] = key
    cache.normal_impulse[:k] = normal_impulse
    cache.tangent_impulse[:k] = tangent_impulse
    cache.count[0] = k
    return cache


@inlined
def warm_start_points(points, n_points, cache):
    """Give each point the impulses last tick's point of the same key ended with."""
    key, data = points.key, points.data
    c_key, c_jn, c_jt = cache.key, cache.normal_impulse, cache.tangent_impulse
    n_cache = cache.count[0]
    f = 0
    for p in range(n_points):
        while f < n_cache and c_key[f] < key[p]:
            f += 1
        if f < n_cache and c_key[f] == key[p]:
            data[p, NORMAL_IMPULSE] = c_jn[f]
            data[p, TANGENT_IMPULSE] = c_jt[f]


@inlined
def remember(points, n_points, cache):
    """Keep this tick's points and impulses for the next tick (the cache holds at least n_points)."""
    key, data = points.key, points.data
    for p in range(n_points):
        cache.key[p] = key[p]
        cache.normal_impulse[p] = data[p, NORMAL_IMPULSE]
        cache.tangent_impulse[p] = data[p, TANGENT_IMPULSE]
    cache.count[0] = n_points
