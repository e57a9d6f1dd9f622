"""The self-contained HTML player: one offline file, the run embedded as base64 typed arrays.

The page (player.html + player.js, next to this module) draws on a canvas; the data goes in
<script type="application/octet-stream"> tags (one per array) plus a small JSON header.
"""

from __future__ import annotations

import base64
import json
import math
import re
from dataclasses import asdict, dataclass
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from . import colors
from .bodies import RunInfo
from .colors import asleep_color, hex_color
from .events import event_marks, read_events, sensor_bodies, sensor_occupancy
from .frames import iter_blocks
from .joints import ZIGZAG_TEETH, ZIGZAG_WIDTH
from .raster import VELOCITY_SECONDS, Overlays
from .view import Box

if TYPE_CHECKING:
    import h5py

MAX_FRAMES = 2000
MAX_BYTES = 50_000_000  # embedded array bytes (before base64)
BODY_FRAME_BYTES = 4 * 6 + 2  # float32 x, y, angle, vx, vy, w, one active and one asleep byte
CONTACT_BYTES = 4 * 4  # float32 point and normal


@dataclass(frozen=True)
class PlayerResult:
    frames: int
    every: int
    notes: list[str]


def write_player(
    path: Path, file: h5py.File, run: RunInfo, view: Box, start: int, every: int | None, overlays: Overlays
) -> PlayerResult:
    """Write the player for `run` to `path`, thinned in time to MAX_FRAMES frames and MAX_BYTES."""
    offsets = np.asarray(file["contacts/offset"], dtype=np.int64) if run.has_contacts else None
    stride, note = _stride(run, every, offsets)
    frames = range(start % stride, run.frame_count, stride)
    arrays, contacts = _arrays(file, run, frames)
    arrays["jointActive"] = run.joints.active[frames.start :: frames.step].astype(np.uint8)
    steps = run.steps[frames.start :: frames.step]
    events = read_events(file)
    sensors = sensor_bodies(run.outlines)
    arrays["sensorLit"] = sensor_occupancy(events, sensors, steps)
    header = {
        "source": run.source,
        "bodies": _bodies(run),
        "shapes": _shapes(run),
        "joints": _joints(run),
        "attractors": [
            {"name": a.name, "x": a.position[0], "y": a.position[1], "range": _finite(a.range)}
            for a in run.attractors
        ],
        "bounds": None if run.bounds is None else [float(v) for v in run.bounds.reshape(-1)],
        "view": list(view),
        "steps": steps.tolist(),
        "times": run.times[frames.start :: frames.step].tolist(),
        "recordedFrames": run.frame_count,
        "every": stride,
        "startFrame": (start - frames.start) // stride,
        "hasContacts": contacts is not None,
        "note": note,
        "velocitySeconds": VELOCITY_SECONDS,
        "overlays": asdict(overlays),
        "sensorBodies": sensors,  # the columns of sensorLit: 1 while something is inside
        "eventMarks": event_marks(events, steps),
    }
    blobs = {name: _base64(array) for name, array in {**arrays, **(contacts or {})}.items()}
    html = _page(header, blobs)
    path.write_text(html, encoding="utf-8")
    return PlayerResult(len(frames), stride, [note] if note else [])


def _stride(run: RunInfo, every: int | None, offsets: np.ndarray | None) -> tuple[int, str]:
    """Every how many recorded frames the player keeps, and a note when that was forced by the budget."""
    asked = every or 1
    per_frame = run.body_count * BODY_FRAME_BYTES + run.joints.count  # one active byte per joint
    if offsets is not None:
        per_frame += CONTACT_BYTES * (offsets[-1] - offsets[0]) / max(run.frame_count, 1)
    budget_frames = max(1, min(MAX_FRAMES, int(MAX_BYTES // max(per_frame, 1))))
    needed = math.ceil(run.frame_count / budget_frames)
    if needed <= asked:
        return asked, ""
    shown = math.ceil(run.frame_count / needed)
    return needed, (
        f"Long run thinned: one recorded frame in {needed} is shown ({shown} of {run.frame_count}), "
        f"to keep the player under {MAX_FRAMES} frames and {MAX_BYTES // 1_000_000} MB."
    )


def _arrays(file: h5py.File, run: RunInfo, frames: range) -> tuple[dict[str, np.ndarray], dict | None]:
    """The selected frames as float32/uint8 arrays (read in blocks), and their contacts if recorded."""
    count, bodies = len(frames), run.body_count
    arrays = {
        "position": np.empty((count, bodies, 2), dtype="<f4"),
        "angle": np.empty((count, bodies), dtype="<f4"),
        "velocity": np.empty((count, bodies, 2), dtype="<f4"),
        "angularVelocity": np.empty((count, bodies), dtype="<f4"),
        "active": np.empty((count, bodies), dtype=np.uint8),
        "asleep": np.empty((count, bodies), dtype=np.uint8),
    }
    points, normals, offsets = [], [], [np.zeros(1, dtype=np.int64)]
    row = 0
    for block in iter_blocks(file, frames, run.has_contacts):
        rows = slice(row, row + len(block.indices))
        arrays["position"][rows] = block.position
        arrays["angle"][rows] = block.angle
        arrays["velocity"][rows] = block.velocity
        arrays["angularVelocity"][rows] = block.angular_velocity
        arrays["active"][rows] = block.active
        arrays["asleep"][rows] = block.asleep
        if block.contacts is not None and block.contact_offset is not None:
            points.append(block.contacts.point)
            normals.append(block.contacts.normal)
            offsets.append(offsets[-1][-1] + block.contact_offset[1:])
        row += len(block.indices)
    if not run.has_contacts:
        return arrays, None
    contacts = {
        "contactOffset": np.concatenate(offsets).astype("<i4"),
        "contactPoint": np.concatenate(points + [np.zeros((0, 2))]).astype("<f4"),
        "contactNormal": np.concatenate(normals + [np.zeros((0, 2))]).astype("<f4"),
    }
    return arrays, contacts


def _bodies(run: RunInfo) -> dict:
    """The static body table, as JSON-friendly lists."""
    return {
        "names": run.names,
        "types": run.types,
        "shapes": run.shapes,
        "materials": run.materials,
        "centroid": [[float(c) for c in centroid] for centroid in run.centroid],
    }


def _shapes(run: RunInfo) -> dict:
    """Every shape in its body's frame (`Outlines`), as JSON-friendly lists: points flat per shape."""
    outlines = run.outlines
    points, start = outlines.points, outlines.start
    return {
        "body": outlines.body.tolist(),
        "style": outlines.style,
        "closed": outlines.closed.tolist(),
        "points": [points[start[s]:start[s + 1]].reshape(-1).tolist() for s in range(outlines.count)],
        "radius": outlines.radius.tolist(),
        "spoke": outlines.spoke.tolist(),
        "sensor": outlines.sensor.tolist(),
        "colors": [hex_color(color) for color in outlines.colors],
        "asleepColors": [hex_color(asleep_color(color)) for color in outlines.colors],  # while it sleeps
    }


def _joints(run: RunInfo) -> dict:
    """The joints (`JointTable`) as JSON-friendly lists, and how to draw them."""
    table = run.joints
    return {
        "types": table.types,
        "bodyA": table.body_a.tolist(),
        "bodyB": table.body_b.tolist(),
        "anchorA": table.anchor_a.tolist(),
        "anchorB": table.anchor_b.tolist(),
        "ground": table.ground.tolist(),
        "spring": table.spring.tolist(),
        "color": hex_color(colors.JOINT),
        "zigzag": {"teeth": ZIGZAG_TEETH, "width": ZIGZAG_WIDTH},
    }


def _finite(value: float) -> float | None:
    return value if math.isfinite(value) else None


def _base64(array: np.ndarray) -> str:
    return base64.b64encode(np.ascontiguousarray(array).tobytes()).decode("ascii")


def _page(header: dict, blobs: dict[str, str]) -> str:
    """player.html with the script, the JSON header and the base64 arrays filled in."""
    folder = resources.files("rustycs_cli.render")
    template = folder.joinpath("player.html").read_text(encoding="utf-8")
    script = folder.joinpath("player.js").read_text(encoding="utf-8")
    # "<" escaped so that no string in the data (a body name) can close the <script> element early.
    header_json = json.dumps(header, allow_nan=False).replace("<", "\\u003c")
    data = "\n".join(
        f'<script type="application/octet-stream" id="rustycs-{name}">{blob}</script>'
        for name, blob in blobs.items()
    )
    values = {
        "TITLE": _html_text(Path(header["source"]).name),
        "HEADER": header_json,
        "ARRAYS": data,
        "SCRIPT": script,
    }
    # One pass over the template only: placeholder-like text inside the data is never expanded.
    return re.sub(r"/\*RUSTYCS_(\w+)\*/|<!--RUSTYCS_(\w+)-->", lambda m: values[m[1] or m[2]], template)


def _html_text(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
