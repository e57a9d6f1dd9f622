"""/events of a trajectory: every event the engine reports (`World.events()`), of every kind, appended
after each step call in the order they happened.

The kind names are the engine's own (`rustycs.events.EVENT_KIND_NAMES`, which `World.events()` returns);
this writer copies whatever kinds it is given, so kinds the engine adds need no change here. For a
joint_break, body_a is the joint's row in /joints.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import h5py

EVENT_FIELDS = {  # name: (row shape, dtype, unit); [E, *shape]
    "tick": ((), "i8", None),
    "time": ((), "f8", "s"),
    "kind": ((), "str", None),
    "body_a": ((), "i4", None),
    "body_b": ((), "i4", None),
    "point": ((2,), "f8", "m"),
    "speed": ((), "f8", "m s-1"),
}
CHUNK_ROWS = 1024


class EventWriter:
    """Creates /events with zero rows (so that every file has its paths) and appends events to it."""

    def __init__(self, file: h5py.File, dt: float):
        import h5py

        self.dt = dt
        group = file.create_group("events")
        self.datasets: dict[str, h5py.Dataset] = {}
        for name, (shape, dtype, unit) in EVENT_FIELDS.items():
            dataset = group.create_dataset(
                name, shape=(0, *shape), maxshape=(None, *shape), chunks=(CHUNK_ROWS, *shape),
                dtype=h5py.string_dtype() if dtype == "str" else dtype)
            if unit:
                dataset.attrs["unit"] = unit
            self.datasets[name] = dataset

    def append(self, events: dict[str, Any], contact_events: bool) -> None:
        """Append the events of one step call, as `World.events()` returns them; contact_begin and
        contact_end only with `contact_events` (the scene's `output.events`: the engine also records
        them when a measure or stop condition watches contacts)."""
        import numpy as np

        from rustycs.events import CONTACT_BEGIN, CONTACT_END, EVENT_KIND_NAMES

        if not contact_events:
            contact = (EVENT_KIND_NAMES[CONTACT_BEGIN], EVENT_KIND_NAMES[CONTACT_END])
            keep = np.array([str(kind) not in contact for kind in events["kind"]], dtype=bool)
            events = {key: np.asarray(value)[keep] for key, value in events.items()}
        count = len(events["tick"])
        if not count:
            return
        rows = {
            "tick": events["tick"], "time": np.asarray(events["tick"]) * self.dt,
            "kind": np.array([str(kind) for kind in events["kind"]], dtype=object),
            "body_a": events["a"], "body_b": events["b"], "point": events["point"], "speed": events["speed"],
        }
        for name, dataset in self.datasets.items():
            start = dataset.shape[0]
            dataset.resize(start + count, axis=0)
            dataset[start:] = rows[name]
