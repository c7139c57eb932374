"""Checks and writers of the rendered files: extensions, sizes, frame
rates, videos (MP4 via imageio-ffmpeg's H.264, or GIF) and images, each
written atomically (:func:`mat_hopper.util.atomic.atomic_path`).
:mod:`mat_hopper.viz.render` re-exports every name here.
"""

from __future__ import annotations

import math
import os

import numpy as np

from ..util.atomic import atomic_path
from ..util.parsing import is_real

VIDEO_EXTENSIONS = (".mp4", ".gif")
IMAGE_EXTENSIONS = (".png", ".jpg", ".jpeg", ".svg", ".pdf")  # a Figure (matplotlib's savefig)
RASTER_EXTENSIONS = (".png", ".jpg", ".jpeg")  # an RGB array (imageio): no vector formats


def parse_size(text: str) -> tuple[int, int]:
    """'640x480' -> (640, 480) pixels; each side a whole ASCII decimal
    (:func:`mat_hopper.util.parsing.parse_number`: not "٦٤٠" or "6_40").

    Args:
        text: ``"WIDTHxHEIGHT"`` (the ``x`` in any case, blanks around the
            whole ignored); anything else is converted with ``str`` first.

    Returns:
        (width, height) in pixels, ints.

    Raises:
        ValueError: not two whole ASCII decimals joined by ``x``, or a side
            outside 16 to 4096 pixels.
    """
    from ..util.parsing import is_decimal, parse_number

    parts = str(text).strip().lower().split("x")
    if len(parts) != 2 or not all(is_decimal(p) and "." not in p and "e" not in p for p in parts):
        raise ValueError(f"size must be WIDTHxHEIGHT in pixels, e.g. 640x480; got {text!r}")
    w, h = (parse_number(p, "size", integer=True) for p in parts)
    if not (16 <= w <= 4096 and 16 <= h <= 4096):
        raise ValueError(f"size must be between 16x16 and 4096x4096 pixels, got {text!r}")
    return w, h


def check_fps(fps) -> float:
    """A video's frame rate, checked.

    Args:
        fps: frames per second.

    Returns:
        `fps` as a float in (0, 240].

    Raises:
        ValueError: not a finite number in (0, 240].
    """
    if not (is_real(fps) and math.isfinite(fps) and 0 < fps <= 240):
        raise ValueError(f"fps must be in (0, 240] frames per second, got {fps!r}")
    return float(fps)


def check_extension(path: str, allowed: tuple) -> str:
    """An output file's extension, checked against what the writer can make.

    Args:
        path: the output path.
        allowed: accepted extensions, lower case with the dot (``".png"``).

    Returns:
        The extension of `path`, lower case.

    Raises:
        ValueError: an extension not in `allowed`, naming those accepted.
    """
    ext = os.path.splitext(str(path))[1].lower()
    if ext not in allowed:
        raise ValueError(f"unknown file type {ext or '(none)'!r} for {path!r}; accepted: {', '.join(allowed)}")
    return ext


MP4_BLOCK_PX = 8  # H.264's macro block as write_video asks imageio-ffmpeg for it: sizes are padded up to it


def check_mp4_size(size) -> tuple[int, int]:
    """An MP4's frame size: its width and height must be multiples of
    :data:`MP4_BLOCK_PX`, else the encoder pads the frames (641x480 is written
    648x480).

    Args:
        size: (width, height) in pixels.

    Returns:
        (width, height) as ints.

    Raises:
        ValueError: a width or height that is not a multiple of MP4_BLOCK_PX,
            naming the padded size and a .gif for any size.
    """
    w, h = (int(v) for v in size)
    if w % MP4_BLOCK_PX or h % MP4_BLOCK_PX:
        pad = tuple(-(-v // MP4_BLOCK_PX) * MP4_BLOCK_PX for v in (w, h))
        raise ValueError(
            f"size {w}x{h}: an MP4's width and height must be multiples of {MP4_BLOCK_PX} pixels (the H.264 "
            f"encoder would pad it to {pad[0]}x{pad[1]}); give e.g. {pad[0]}x{pad[1]}, or write a .gif for any size"
        )
    return w, h


def write_video(frames, path: str, fps: float) -> str:
    """Write frames (an array or any iterable of (h, w, 3) uint8 images) as
    MP4 (H.264, imageio-ffmpeg; streamed) or GIF, atomically.

    Args:
        frames: (n, h, w, 3) uint8 array or iterable of (h, w, 3) uint8
            images (a GIF collects them in memory first).
        path: the file, ending in ``.mp4`` or ``.gif`` (any case).
        fps: frames per second of the video, in (0, 240].

    Returns:
        `path`, as given.

    Raises:
        ValueError: another file extension, or `fps` outside (0, 240].
    """
    import imageio.v2 as imageio

    ext = check_extension(path, VIDEO_EXTENSIONS)
    fps = check_fps(fps)
    with atomic_path(path) as tmp:
        if ext == ".mp4":
            with imageio.get_writer(
                tmp,
                fps=fps,
                codec="libx264",
                quality=7,
                macro_block_size=8,
                ffmpeg_log_level="error",
                pixelformat="yuv420p",
            ) as w:
                for f in frames:
                    w.append_data(f)
        else:
            imageio.mimsave(tmp, list(frames), duration=1000.0 / fps, loop=0)
    return path


def save_image(fig_or_rgb, path: str) -> str:
    """Write a Figure or an RGB array as an image file, atomically.

    Args:
        fig_or_rgb: a matplotlib Figure (``savefig``; PNGs without the
            Software tag) or an (h, w, 3) uint8 ``numpy`` array (imageio).
        path: the file; its extension (any case) picks the format: among
            :data:`IMAGE_EXTENSIONS` for a Figure, among
            :data:`RASTER_EXTENSIONS` (no .svg or .pdf) for an array.

    Returns:
        `path`, as given.

    Raises:
        ValueError: an extension not among those of its input (checked
            before anything is written).
    """
    rgb = isinstance(fig_or_rgb, np.ndarray)
    ext = check_extension(path, RASTER_EXTENSIONS if rgb else IMAGE_EXTENSIONS)
    with atomic_path(path) as tmp:
        if rgb:
            import imageio.v2 as imageio

            imageio.imwrite(tmp, fig_or_rgb)
        else:
            fig_or_rgb.savefig(tmp, metadata={"Software": None} if ext == ".png" else None)
    return path
