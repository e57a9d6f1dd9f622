"""Measures: named results of a run, folded in compiled code at the end of every tick, so they are exact
whatever is recorded and cost a loop over their own bodies.

A measure is one of these forms (`FORM_NAMES`):
- value: a quantity of one body, or of a set of bodies through an aggregate (mean, sum, min, max,
  median), reduced over the ticks (final, initial, max, min, mean) or taken at one tick;
- count_inside: how many bodies of a set have their centre of mass in a rectangle;
- histogram: how many bodies of a set have the quantity in each bin (edges ascending; a bin holds its
  lower edge, the last one its upper edge too, as numpy's histogram);
- first: the time of the first event of a kind involving given bodies;
- time_inside: the seconds during which at least one of the bodies overlapped a sensor body.
Only active bodies belong to a set at a tick (an emitted body before it appears, or a removed one, does
not): a value of an empty set is NaN (null), a count 0. A final value is taken from the state when it is
asked for, so only max, min, mean and values at a tick cost anything per tick.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np
from numba import njit

from rustycs.body_types import DYNAMIC
from rustycs.compiling import inlined, tick_kernel
from rustycs.events import EVENT_KIND_NAMES, involves
from rustycs.observables import body_origin, contact_statistics, energies_and_momenta
from rustycs.sorting import sort_run

VALUE, COUNT_INSIDE, HISTOGRAM, FIRST, TIME_INSIDE = range(5)
FORM_NAMES = ("value", "count_inside", "histogram", "first", "time_inside")
# per-body quantities, then the world's observables (which take no bodies)
QUANTITY_NAMES = ("position.x", "position.y", "velocity.x", "velocity.y", "speed", "angle",
                  "angular_velocity", "kinetic_energy")
OBSERVABLE_NAMES = ("kinetic_energy", "potential_energy", "linear_momentum.x", "linear_momentum.y",
                    "angular_momentum", "contact_count", "max_penetration")
OBSERVABLE = len(QUANTITY_NAMES)  # quantity code of the first observable
ONE, MEAN, SUM, MIN, MAX, MEDIAN = range(6)
AGGREGATE_NAMES = ("one", "mean", "sum", "min", "max", "median")
FINAL, INITIAL, REDUCE_MAX, REDUCE_MIN, REDUCE_MEAN, AT = range(6)
REDUCE_NAMES = ("final", "initial", "max", "min", "mean", "at")


class Measures(NamedTuple):
    """The measures of a world (m rows) and their results (one row per number: a histogram has one per
    bin). Body lists are concatenated: measure m's are members[first[m]:first[m + 1]]."""

    form: np.ndarray  # (M,) int64 VALUE ... TIME_INSIDE
    quantity: np.ndarray  # (M,) int64 index in QUANTITY_NAMES + OBSERVABLE_NAMES
    aggregate: np.ndarray  # (M,) int64 ONE ... MEDIAN
    reduce: np.ndarray  # (M,) int64 FINAL ... AT
    at_tick: np.ndarray  # (M,) int64 the tick of AT
    event: np.ndarray  # (M,) int64 the kind of FIRST
    sensor: np.ndarray  # (M,) int64 the slot (`Sensors.body`) of the sensor of TIME_INSIDE
    region: np.ndarray  # (M, 4) xmin, ymin, xmax, ymax of COUNT_INSIDE
    first: np.ndarray  # (M + 1,) int64 into members
    members: np.ndarray  # int64 bodies
    other_first: np.ndarray  # (M + 1,) int64 into others: FIRST's second list of bodies (may be empty)
    others: np.ndarray  # int64 bodies
    edge_first: np.ndarray  # (M + 1,) int64 into edges
    edges: np.ndarray  # float64 a histogram's bin edges
    row_first: np.ndarray  # (M + 1,) int64 the measure's rows of results
    value: np.ndarray  # (R,) the results so far (NaN: none)
    samples: np.ndarray  # (R,) the ticks a mean has summed
    sample: np.ndarray  # (R,) scratch: the values of the tick
    scratch: np.ndarray  # (largest set,) scratch of a median


class MeasureBook:
    """Measures as the World collects them, turned into the compiled record once."""

    def __init__(self) -> None:
        self.rows: list[dict] = []

    def add(self, form: str, *, bodies: Sequence[int] = (), others: Sequence[int] = (), quantity: str = "",
            aggregate: str = "one", reduce: str = "final", at_tick: int = 0, region=None, edges=(),
            event: str = "", sensor_slot: int = -1) -> int:
        """Check and keep one measure; returns its index."""
        if form not in FORM_NAMES:
            raise ValueError(f"unknown measure form {form!r}; one of {', '.join(FORM_NAMES)}")
        quantities = (*QUANTITY_NAMES, *(f"observables.{name}" for name in OBSERVABLE_NAMES))
        code = quantities.index(quantity) if quantity in quantities else -1
        if form in ("value", "histogram") and code < 0:
            raise ValueError(f"unknown quantity {quantity!r}; one of {', '.join(quantities)}")
        if aggregate not in AGGREGATE_NAMES or reduce not in REDUCE_NAMES:
            raise ValueError(f"unknown aggregate {aggregate!r} or reduce {reduce!r}")
        if form == "value" and code < OBSERVABLE and aggregate == "one" and len(bodies) != 1:
            raise ValueError("a value of several bodies needs an aggregate")
        if form == "histogram" and (len(edges) < 2 or np.any(np.diff(edges) <= 0)):
            raise ValueError("a histogram needs at least two edges, strictly ascending")
        if form == "histogram" and reduce not in ("final", "initial", "at"):
            raise ValueError("a histogram is taken at the end, at the start or at a tick")
        if form == "first" and event not in EVENT_KIND_NAMES:
            raise ValueError(f"unknown event {event!r}; one of {', '.join(EVENT_KIND_NAMES)}")
        if form == "time_inside" and sensor_slot < 0:
            raise ValueError("time_inside needs a sensor body")
        if form == "count_inside" and region is None:
            raise ValueError("count_inside needs a region")
        self.rows.append(dict(
            form=FORM_NAMES.index(form), quantity=max(code, 0), aggregate=AGGREGATE_NAMES.index(aggregate),
            reduce=REDUCE_NAMES.index(reduce), at_tick=int(at_tick),
            event=EVENT_KIND_NAMES.index(event) if event else -1, sensor=int(sensor_slot),
            region=np.zeros(4) if region is None else np.asarray(region, np.float64).reshape(4),
            members=np.asarray(bodies, np.int64), others=np.asarray(others, np.int64),
            edges=np.asarray(edges, np.float64), results=len(edges) - 1 if form == "histogram" else 1))
        return len(self.rows) - 1

    def compiled(self) -> Measures:
        """The record the step folds, with no result yet."""
        rows = self.rows

        def column(name, dtype):
            return np.array([r[name] for r in rows], dtype)

        def offsets(name):
            return np.concatenate([[0], np.cumsum([len(r[name]) for r in rows])]).astype(np.int64)

        def joined(name, dtype):
            return np.concatenate([np.zeros(0, dtype)] + [r[name] for r in rows]).astype(dtype)

        row_first = np.concatenate([[0], np.cumsum([r["results"] for r in rows])]).astype(np.int64)
        n = int(row_first[-1])
        largest = max([len(r["members"]) for r in rows] + [1])
        value = np.full(n, np.nan)
        return Measures(column("form", np.int64), column("quantity", np.int64), column("aggregate", np.int64),
                        column("reduce", np.int64), column("at_tick", np.int64), column("event", np.int64),
                        column("sensor", np.int64), np.array([r["region"] for r in rows]).reshape(-1, 4),
                        offsets("members"), joined("members", np.int64), offsets("others"),
                        joined("others", np.int64), offsets("edges"), joined("edges", np.float64), row_first,
                        value, np.zeros(n), np.zeros(n), np.zeros(largest))

    def results(self, measures: Measures) -> list[float | list[int]]:
        """Each measure's result: a number (NaN: none) or, for a histogram, its counts per bin."""
        out: list[float | list[int]] = []
        for m, row in enumerate(self.rows):
            values = measures.value[measures.row_first[m]:measures.row_first[m + 1]]
            if row["form"] == HISTOGRAM:
                out.append([int(v) if math.isfinite(v) else 0 for v in values])
            else:
                out.append(float(values[0]))
        return out


@inlined
def _quantity(code, bodies, i):
    x, v, w, angle = bodies.x, bodies.v, bodies.w, bodies.angle
    if code <= 1:
        px, py = body_origin(x, angle, bodies.origin, i)
        return px if code == 0 else py
    if code <= 3:
        return v[i, code - 2]
    if code == 4:
        return math.sqrt(v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1])
    if code == 5:
        return angle[i]
    if code == 6:
        return w[i]
    spin = bodies.inertia[i] * w[i] * w[i] if bodies.inv_inertia[i] > 0.0 else 0.0
    return 0.5 * (bodies.mass[i] * (v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1]) + spin)


@inlined
def _observable(code, bodies, forces, contacts):
    if code >= OBSERVABLE + 5:
        count, deepest = contact_statistics(contacts)
        return float(count) if code == OBSERVABLE + 5 else deepest
    kinetic, potential, px, py, angular = energies_and_momenta(bodies, forces)
    return (kinetic, potential, px, py, angular)[code - OBSERVABLE]


@inlined
def _counts(bodies, i):
    """Whether body i belongs to a set now: an active dynamic body."""
    return bodies.active[i] and bodies.body_type[i] == DYNAMIC


@inlined
def _median(values, n):
    """The median of values[:n] (sorted in place)."""
    sort_run(values, 0, n)
    return values[n // 2] if n % 2 == 1 else 0.5 * (values[n // 2 - 1] + values[n // 2])


@inlined
def _sample(measures, m, bodies, forces, contacts):
    """Measure m's values now (value, count_inside, histogram) into measures.sample at its rows."""
    row = measures.row_first[m]
    sample, members, q = measures.sample, measures.members, measures.quantity[m]
    form, aggregate = measures.form[m], measures.aggregate[m]
    if form == VALUE and q >= OBSERVABLE:
        sample[row] = _observable(q, bodies, forces, contacts)
        return
    if form == HISTOGRAM:
        edges, e0 = measures.edges, measures.edge_first[m]
        bins = measures.edge_first[m + 1] - e0 - 1
        for k in range(bins):
            sample[row + k] = 0.0
        for k in range(measures.first[m], measures.first[m + 1]):
            i = members[k]
            if not _counts(bodies, i):
                continue
            value = _quantity(q, bodies, i)
            if not (edges[e0] <= value <= edges[e0 + bins]):
                continue
            b = 0
            while b < bins - 1 and value >= edges[e0 + b + 1]:
                b += 1
            sample[row + b] += 1.0
        return
    region, x = measures.region, bodies.x
    n = 0
    total = 0.0
    low = np.inf
    high = -np.inf
    for k in range(measures.first[m], measures.first[m + 1]):
        i = members[k]
        if not _counts(bodies, i):
            continue
        if form == COUNT_INSIDE:
            if region[m, 0] <= x[i, 0] <= region[m, 2] and region[m, 1] <= x[i, 1] <= region[m, 3]:
                n += 1
            continue
        value = _quantity(q, bodies, i)
        if aggregate == MEDIAN:
            measures.scratch[n] = value
        n += 1
        total += value
        low = min(low, value)
        high = max(high, value)
    if form == COUNT_INSIDE:
        sample[row] = float(n)
    elif n == 0:
        sample[row] = np.nan
    elif aggregate == ONE or aggregate == SUM:
        sample[row] = total
    elif aggregate == MEAN:
        sample[row] = total / n
    elif aggregate == MIN:
        sample[row] = low
    elif aggregate == MAX:
        sample[row] = high
    else:
        sample[row] = _median(measures.scratch, n)


@tick_kernel
def fold(measures, bodies, forces, contacts, sensors, events, first_event, tick, dt):
    """Fold the state after `tick` (0: the initial state) into every measure that takes ticks: extremes,
    means, values at a tick, the first events among events[first_event:] and time inside sensors."""
    value, samples, sample = measures.value, measures.samples, measures.sample
    for m in range(measures.form.shape[0]):
        form, reduce, row = measures.form[m], measures.reduce[m], measures.row_first[m]
        if form == FIRST:
            if tick == 0 or not math.isnan(value[row]):
                continue
            a0, a1 = measures.first[m], measures.first[m + 1]
            b0, b1 = measures.other_first[m], measures.other_first[m + 1]
            for e in range(first_event, events.count[0]):
                if involves(events, e, measures.event[m], measures.members, a0, a1, measures.others, b0, b1):
                    value[row] = tick * dt
                    break
            continue
        if form == TIME_INSIDE:
            if math.isnan(value[row]):
                value[row] = 0.0
            slot = measures.sensor[m]
            for k in range(measures.first[m], measures.first[m + 1]):
                if sensors.inside[slot, measures.members[k]]:
                    value[row] += dt if tick > 0 else 0.0
                    break
            continue
        if reduce == FINAL or (reduce == INITIAL and tick > 0) or (
                reduce == AT and tick != measures.at_tick[m]):
            continue
        _sample(measures, m, bodies, forces, contacts)
        for r in range(row, measures.row_first[m + 1]):
            s = sample[r]
            if reduce == INITIAL or reduce == AT:
                value[r] = s
            elif math.isnan(s):
                continue
            elif reduce == REDUCE_MEAN:
                samples[r] += 1.0
                value[r] = s if samples[r] == 1.0 else value[r] + (s - value[r]) / samples[r]
            elif math.isnan(value[r]) or (reduce == REDUCE_MAX and s > value[r]) or (
                    reduce == REDUCE_MIN and s < value[r]):
                value[r] = s


@njit(cache=True)
def finish(measures, bodies, forces, contacts):
    """Take the final values from the state now (the end of the run)."""
    for m in range(measures.form.shape[0]):
        if measures.reduce[m] != FINAL or measures.form[m] == FIRST or measures.form[m] == TIME_INSIDE:
            continue
        _sample(measures, m, bodies, forces, contacts)
        for r in range(measures.row_first[m], measures.row_first[m + 1]):
            measures.value[r] = measures.sample[r]
