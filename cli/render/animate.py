"""Animations: GIF with Pillow, MP4 by piping raw RGB frames to imageio-ffmpeg's bundled ffmpeg."""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

from PIL import Image

GIF_MAX_BYTES = 256 * 1024 * 1024  # Pillow holds every GIF frame (1 byte per pixel) until it writes


def gif_max_frames(width: int, height: int) -> int:
    """How many frames a GIF of this size may have before its frames would exceed GIF_MAX_BYTES."""
    return max(1, GIF_MAX_BYTES // (width * height))


def write_gif(path: Path, images: Iterable[Image.Image], fps: float) -> int:
    """Write the images as a looping GIF at `fps`; returns the number of frames.

    Each frame gets its own adaptive palette (fast octree, no dithering: flat colours stay flat)."""
    frames = [
        image.quantize(colors=256, method=Image.Quantize.FASTOCTREE, dither=Image.Dither.NONE)
        for image in images
    ]
    frames[0].save(
        path,
        format="GIF",
        save_all=True,
        append_images=frames[1:],
        duration=round(1000 / fps),
        loop=0,
        optimize=False,
        disposal=1,
    )
    return len(frames)


def write_mp4(path: Path, images: Iterable[Image.Image], size: tuple[int, int], fps: float) -> int:
    """Write the images (all of `size`, both even) as an H.264 MP4 at `fps`, streaming each frame to
    ffmpeg as soon as it is drawn; returns the number of frames."""
    import imageio_ffmpeg

    writer = imageio_ffmpeg.write_frames(
        str(path),
        size,
        fps=fps,
        codec="libx264",
        pix_fmt_in="rgb24",
        pix_fmt_out="yuv420p",
        macro_block_size=2,
        ffmpeg_log_level="error",
        output_params=["-movflags", "+faststart", "-f", "mp4"],
    )
    writer.send(None)  # start ffmpeg
    count = 0
    try:
        for image in images:
            writer.send(image.tobytes())
            count += 1
    finally:
        writer.close()
    return count
