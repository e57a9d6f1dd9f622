"""`rustycs render` behind the command line: pick the frames, the view and the writer for OUT's suffix."""

from __future__ import annotations

import math
import sys
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import UserError
from ..limits import MAX_TICKS
from .bodies import RunInfo, load_run
from .output import atomic_output, check_suffix
from .raster import Overlays
from .view import View, fit_box, make_view, parse_box, parse_size

if TYPE_CHECKING:
    import h5py
    from PIL import Image

FORMATS = (".png", ".gif", ".mp4", ".html")


@dataclass(frozen=True)
class RenderRequest:
    """What the user asked for (option values as typed; checked here)."""

    run: Path
    out: Path
    tick: int | None = None
    fps: float = 30.0
    every: int | None = None
    size: str = "800x600"
    view: str | None = None
    overlays: Overlays = Overlays()


@dataclass(frozen=True)
class RenderResult:
    """What was written, for the command's report."""

    out: Path
    frames: int
    every: int
    view: View
    notes: list[str]


def render(request: RenderRequest) -> RenderResult:
    """Write the picture, animation or player `request.out` asks for."""
    from ..trajectory import open_trajectory

    suffix = check_suffix(request.out, FORMATS, "output")
    if request.tick is not None and suffix in (".gif", ".mp4"):
        raise UserError(
            "--tick picks the frame of a .png (or the first frame of a .html); animations use --every"
        )
    if not (math.isfinite(request.fps) and 0 < request.fps <= 240):
        raise UserError(f"--fps {request.fps}: must be between 0 and 240 frames per second")
    if request.every is not None and not 1 <= request.every <= MAX_TICKS.value:
        raise UserError(f"--every {request.every}: must be from 1 to {MAX_TICKS}")
    width, height = parse_size(request.size)
    if suffix == ".mp4":  # H.264 in yuv420p needs even sizes
        width, height = width + width % 2, height + height % 2
    box = parse_box(request.view) if request.view is not None else None
    with open_trajectory(request.run) as file:
        run = load_run(file, str(request.run))
        box = box or fit_box(file, run)
        view = make_view(box, width, height)
        notes = []
        if request.overlays.contacts and not run.has_contacts:
            notes.append(
                f"{request.run}: no contact points were recorded (scene output.contacts: true records them)"
            )
        if suffix == ".png":
            index = run.frame_count - 1 if request.tick is None else run.frame_of_tick(request.tick)
            _write_png(file, run, index, view, request)
            return RenderResult(request.out, 1, 1, view, notes)
        if suffix == ".html":
            from .player import write_player

            start = 0 if request.tick is None else run.frame_of_tick(request.tick)
            with atomic_output(request.out) as temporary:
                shown = write_player(temporary, file, run, box, start, request.every, request.overlays)
            return RenderResult(request.out, shown.frames, shown.every, view, notes + shown.notes)
        every, more_notes = _animation_every(run, request, view, suffix)
        frames = range(0, run.frame_count, every)
        count = _write_animation(file, run, frames, view, request, suffix)
        return RenderResult(request.out, count, every, view, notes + more_notes)


def _write_png(file: h5py.File, run: RunInfo, index: int, view: View, request: RenderRequest) -> None:
    from .events import lit_sensors
    from .frames import read_frame
    from .raster import draw_frame

    frame = read_frame(file, index, _with_contacts(run, request))
    lit = lit_sensors(file, run, run.steps[index : index + 1])[0]
    image = draw_frame(run, frame, view, request.overlays, lit)
    with atomic_output(request.out) as temporary:
        image.save(temporary, format="PNG")


def _with_contacts(run: RunInfo, request: RenderRequest) -> bool:
    return request.overlays.contacts and run.has_contacts


def _animation_every(run: RunInfo, request: RenderRequest, view: View, suffix: str) -> tuple[int, list[str]]:
    """--every, or by default the stride that plays the run in real time at --fps; GIFs are also kept
    under their frame budget (thinned further with a note, or refused when --every was explicit)."""
    if request.every is not None:
        every = request.every
    else:
        interval = float(run.times[-1] - run.times[0]) / max(run.frame_count - 1, 1)
        every = max(1, round(1.0 / (request.fps * interval))) if interval > 0 else 1
    if suffix != ".gif":
        return every, []
    from .animate import gif_max_frames

    limit = gif_max_frames(view.width, view.height)
    if math.ceil(run.frame_count / every) <= limit:
        return every, []
    needed = math.ceil(run.frame_count / limit)
    if request.every is not None:
        raise UserError(
            f"--every {every}: {math.ceil(run.frame_count / every)} frames is too many for a "
            f"{view.width}x{view.height} GIF (at most {limit}); use --every {needed} or more, a smaller "
            "--size, or an .mp4"
        )
    return needed, [f"GIF thinned to one recorded frame in {needed} (at most {limit} frames at this size)"]


def _write_animation(
    file: h5py.File, run: RunInfo, frames: range, view: View, request: RenderRequest, suffix: str
) -> int:
    from .animate import write_gif, write_mp4

    images = _images(file, run, frames, view, request)
    with atomic_output(request.out) as temporary:
        if suffix == ".gif":
            return write_gif(temporary, images, request.fps)
        return write_mp4(temporary, images, (view.width, view.height), request.fps)


def _images(
    file: h5py.File, run: RunInfo, frames: range, view: View, request: RenderRequest
) -> Iterator[Image.Image]:
    """The frames drawn one by one (read in blocks), with a progress bar on a terminal."""
    from rich.console import Console
    from rich.progress import Progress

    from .events import lit_sensors
    from .frames import iter_frames
    from .raster import draw_frame

    lit = lit_sensors(file, run, run.steps[frames.start : frames.stop : frames.step])
    console = Console(stderr=True)
    with Progress(console=console, transient=True, disable=not sys.stderr.isatty()) as progress:
        task = progress.add_task(f"rendering {request.out.name}", total=len(frames))
        for k, frame in enumerate(iter_frames(file, frames, _with_contacts(run, request))):
            yield draw_frame(run, frame, view, request.overlays, lit[k])
            progress.advance(task)
