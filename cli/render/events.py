"""What the player and the pictures show of a run's /events: which sensor bodies hold something at each
shown frame, and (in the player) where events happened, as marks on the scrub bar.

Occupancy is counted from the sensor events, which every trajectory holds whatever `output.events` says
(only contact events depend on it): the engine tests sensors on every tick, so the count at a frame is
exact, and sensors need no geometry here. A body that starts inside a sensor enters it in tick 1 (the
engine senses at the end of a tick), so tick 0 shows every sensor empty.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .colors import EVENT_COLORS, OTHER_EVENT, hex_color

if TYPE_CHECKING:
    import h5py

    from .bodies import Outlines, RunInfo


def read_events(file: h5py.File) -> dict[str, np.ndarray]:
    """tick, kind (str) and body_b of every event (no rows for a file written before /events)."""
    if "events/tick" not in file:
        return {"tick": np.zeros(0, np.int64), "kind": np.zeros(0, str), "body_b": np.zeros(0, np.int64)}
    group = file["events"]
    return {"tick": np.asarray(group["tick"], np.int64), "kind": np.array(group["kind"].asstr()[()], str),
            "body_b": np.asarray(group["body_b"], np.int64)}


def sensor_occupancy(events: dict[str, np.ndarray], sensor_bodies: list[int],
                     steps: np.ndarray) -> np.ndarray:
    """[F, K] uint8: 1 where sensor body k holds at least one body at the frame of tick steps[f]."""
    lit = np.zeros((len(steps), len(sensor_bodies)), np.uint8)
    for k, body in enumerate(sensor_bodies):
        mine = events["body_b"] == body
        entered = np.sort(events["tick"][mine & (events["kind"] == "sensor_enter")])
        left = np.sort(events["tick"][mine & (events["kind"] == "sensor_exit")])
        inside = np.searchsorted(entered, steps, "right") - np.searchsorted(left, steps, "right")
        lit[:, k] = inside > 0
    return lit


def sensor_bodies(outlines: Outlines) -> list[int]:
    """The bodies with a sensor shape, in order."""
    return sorted({int(body) for body in outlines.body[outlines.sensor]})


def lit_sensors(file: h5py.File, run: RunInfo, steps: np.ndarray) -> np.ndarray:
    """[F, N] bool: true for a sensor body that holds at least one body at the frame of tick steps[f]."""
    bodies = sensor_bodies(run.outlines)
    lit = np.zeros((len(steps), len(run.names)), bool)
    lit[:, bodies] = sensor_occupancy(read_events(file), bodies, steps) == 1
    return lit


def event_marks(events: dict[str, np.ndarray], steps: np.ndarray) -> list[dict[str, Any]]:
    """Per event kind that happened (in the engine's order of kinds): its colour, the shown frames where
    such events happened (the first frame at or after the event's tick) and how many at each."""
    frames = np.minimum(np.searchsorted(steps, events["tick"], "left"), max(len(steps) - 1, 0))
    known = list(EVENT_COLORS)
    kinds = sorted(set(events["kind"].tolist()), key=lambda kind: (known.index(kind) if kind in known
                                                                   else len(known), kind))
    marks = []
    for kind in kinds:
        shown, counts = np.unique(frames[events["kind"] == kind], return_counts=True)
        marks.append({"kind": kind, "color": hex_color(EVENT_COLORS.get(kind, OTHER_EVENT)),
                      "frames": shown.tolist(), "counts": counts.tolist()})
    return marks
