"""Reading frames from a trajectory in blocks, so a long run never has to fit in memory."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..trajectory import read_series
from .bodies import BODIES

if TYPE_CHECKING:
    import h5py

BLOCK_FRAMES = 64  # a few HDF5 chunks' worth: big reads, bounded memory


@dataclass(frozen=True)
class Contacts:
    """Contact points of one frame (or of a block of frames, split by `offset`)."""

    point: np.ndarray  # [C, 2]
    normal: np.ndarray  # [C, 2] unit, from body a to body b
    depth: np.ndarray  # [C]


@dataclass(frozen=True)
class Block:
    """Consecutive selected frames: arrays with the frame as first axis."""

    indices: np.ndarray  # [F] frame indices in the file
    steps: np.ndarray  # [F]
    times: np.ndarray  # [F]
    position: np.ndarray  # [F, N, 2]
    angle: np.ndarray  # [F, N]
    velocity: np.ndarray  # [F, N, 2]
    angular_velocity: np.ndarray  # [F, N]
    active: np.ndarray  # [F, N] bool
    asleep: np.ndarray  # [F, N] bool
    contacts: Contacts | None  # all contact rows of the block's frames
    contact_offset: np.ndarray | None  # [F + 1] rows of frame f: offset[f] .. offset[f+1]-1


@dataclass(frozen=True)
class Frame:
    """The state of every body at one recorded tick."""

    index: int
    step: int
    time: float
    position: np.ndarray  # [N, 2] body origins
    angle: np.ndarray  # [N]
    velocity: np.ndarray  # [N, 2] centre-of-mass velocity
    angular_velocity: np.ndarray  # [N]
    active: np.ndarray  # [N] bool
    asleep: np.ndarray  # [N] bool: drawn paler
    contacts: Contacts | None


def iter_blocks(
    file: h5py.File, frames: range, with_contacts: bool, block: int = BLOCK_FRAMES
) -> Iterator[Block]:
    """Yield the frames of `frames` (a range of frame indices, step >= 1) in blocks of at most `block`,
    each read with one strided HDF5 selection per dataset."""
    offsets = np.asarray(file["contacts/offset"], dtype=np.int64) if with_contacts else None
    for first in range(0, len(frames), block):
        part = frames[first : first + block]
        selection = slice(part.start, part.stop, part.step)
        indices = np.asarray(part, dtype=np.int64)
        contacts, contact_offset = _block_contacts(file, offsets, indices)
        yield Block(
            indices=indices,
            steps=np.asarray(file[f"{BODIES}/position/step"][selection], dtype=np.int64),
            times=np.asarray(file[f"{BODIES}/position/time"][selection], dtype=np.float64),
            position=file[f"{BODIES}/position/value"][selection],
            angle=file[f"{BODIES}/angle/value"][selection],
            velocity=file[f"{BODIES}/velocity/value"][selection],
            angular_velocity=file[f"{BODIES}/angular_velocity/value"][selection],
            active=np.asarray(file[f"{BODIES}/active/value"][selection], dtype=bool),
            asleep=np.asarray(read_series(file, "asleep")[selection], dtype=bool),
            contacts=contacts,
            contact_offset=contact_offset,
        )


def iter_frames(file: h5py.File, frames: range, with_contacts: bool) -> Iterator[Frame]:
    """Yield the selected frames one by one (read in blocks underneath)."""
    for block in iter_blocks(file, frames, with_contacts):
        for row, index in enumerate(block.indices):
            contacts = None
            if block.contacts is not None and block.contact_offset is not None:
                rows = slice(block.contact_offset[row], block.contact_offset[row + 1])
                contacts = Contacts(
                    block.contacts.point[rows], block.contacts.normal[rows], block.contacts.depth[rows]
                )
            yield Frame(
                index=int(index),
                step=int(block.steps[row]),
                time=float(block.times[row]),
                position=block.position[row],
                angle=block.angle[row],
                velocity=block.velocity[row],
                angular_velocity=block.angular_velocity[row],
                active=block.active[row],
                asleep=block.asleep[row],
                contacts=contacts,
            )


def read_frame(file: h5py.File, index: int, with_contacts: bool) -> Frame:
    """One frame by its index."""
    return next(iter_frames(file, range(index, index + 1), with_contacts))


def _block_contacts(
    file: h5py.File, offsets: np.ndarray | None, indices: np.ndarray
) -> tuple[Contacts | None, np.ndarray | None]:
    """The contact rows of the selected frames, concatenated, with per-frame offsets into them."""
    if offsets is None:
        return None, None
    starts, stops = offsets[indices], offsets[indices + 1]
    local = np.concatenate([[0], np.cumsum(stops - starts)])
    # Consecutive frames: one read. Strided frames: one read per frame, never the skipped frames' rows.
    spans = (
        [(int(starts[0]), int(stops[-1]))]
        if np.all(starts[1:] == stops[:-1])
        else list(zip(starts, stops, strict=True))
    )
    columns = []
    for name in ("point", "normal", "depth"):
        dataset = file[f"contacts/{name}"]
        columns.append(np.concatenate([np.asarray(dataset[a:b], dtype=np.float64) for a, b in spans]))
    point, normal, depth = columns
    return Contacts(point.reshape(-1, 2), normal.reshape(-1, 2), depth), local
