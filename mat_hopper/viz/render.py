"""Off-screen rendering: stills, gait tiles and videos of any design.

No display needed: the scene, the camera and the off-screen OpenGL context
(OSMesa by default, EGL when ``MUJOCO_GL=egl``) are in
:mod:`mat_hopper.viz.scene`. Rendering replays joint positions recorded
during the fast rollout (``simulate(..., record_qpos=True)``), so
simulation never waits for it. The recording and the frames are in
``_frames``, the file checks and writers in ``_files``; this module
re-exports them with the scene's names and holds the two products,
:func:`save_video` and :func:`render_files`.

Leg segments are coloured by density (viridis over log density, 0.9 to 20
g/cm^3) so graded legs show at a glance; the desired path is drawn as a
dotted line of small markers on the ground or ramp.

    from mat_hopper.viz.render import gait_tiles, save_video, render_still
    fig = gait_tiles("rho-inc", "ramp")                 # a matplotlib Figure
    save_video("rho-inc", "ramp", "hop.mp4", seconds=10, fps=30)
"""

from __future__ import annotations

import math

from ..core.behaviours import behaviour as get_behaviour
from ..core.materials import as_design
from ..core.rollout import Rollout
from ..core.sim import SimSettings
from ._files import (
    IMAGE_EXTENSIONS,
    MP4_BLOCK_PX,
    RASTER_EXTENSIONS,
    VIDEO_EXTENSIONS,
    check_extension,
    check_fps,
    check_mp4_size,
    parse_size,
    save_image,
    write_video,
)
from ._frames import (
    drawn_until_s,
    gait_tiles,
    iter_frames,
    record,
    render_frames,
    render_still,
    standing_qpos,
    video_times,
)
from .scene import (
    DENSITY_RANGE_G_CM3,
    GL_LIBS,
    Camera,
    OffscreenRenderer,
    RenderBackendError,
    choose_backend,
    density_color,
    render_spec,
)

__all__ = [
    "DENSITY_RANGE_G_CM3",
    "GL_LIBS",
    "IMAGE_EXTENSIONS",
    "MP4_BLOCK_PX",
    "RASTER_EXTENSIONS",
    "VIDEO_EXTENSIONS",
    "Camera",
    "OffscreenRenderer",
    "RenderBackendError",
    "check_extension",
    "check_fps",
    "check_mp4_size",
    "choose_backend",
    "density_color",
    "drawn_until_s",
    "gait_tiles",
    "iter_frames",
    "parse_size",
    "record",
    "render_files",
    "render_frames",
    "render_spec",
    "render_still",
    "save_image",
    "save_video",
    "standing_qpos",
    "video_times",
    "write_video",
]


def save_video(
    design,
    behaviour,
    path: str,
    *,
    seconds: float = 10.0,
    fps: float = 30.0,
    size=(640, 480),
    start_s: float = 0.0,
    rollout: Rollout | None = None,
    backend: str | None = None,
    progress: bool = False,
) -> str:
    """Simulate (unless a rollout with qpos is given) and write a video,
    frames streamed to the file as they are rendered.

    Args:
        design: a :class:`~mat_hopper.core.materials.LegDesign` or a design name,
            simulated when no `rollout` is given.
        behaviour: a behaviour name or Behaviour, likewise.
        path: the video file, ``.mp4`` or ``.gif``.
        seconds: simulated time shown from `start_s`, s.
        fps: frames per simulated second, in (0, 240].
        size: (width, height) of the frames, pixels.
        start_s: the first frame's time, s.
        rollout: a Rollout with ``qpos`` to show instead; None: :func:`record`
            one.
        backend: ``"osmesa"`` or ``"egl"``; None: :func:`choose_backend`.
        progress: show a progress bar while rendering.

    Returns:
        `path`, as given.

    Raises:
        ValueError: a file extension other than .mp4 or .gif, `fps` outside
            (0, 240], an MP4 size that is not a multiple of 8 pixels
            (:func:`check_mp4_size`), a rollout without joint positions, or an error of
            :func:`record` or :func:`video_times`.
        RenderBackendError: no usable off-screen OpenGL library or context.
    """
    ext = check_extension(path, VIDEO_EXTENSIONS)
    check_fps(fps)
    if ext == ".mp4":
        check_mp4_size(size)
    if rollout is None:
        rollout = record(design, behaviour, seconds, start_s=start_s)
    times = video_times(rollout, start_s=start_s, seconds=seconds, fps=fps)
    write_video(iter_frames(rollout, times, size=size, backend=backend, progress=progress), path, fps)
    return path


def render_files(
    design,
    behaviour,
    *,
    tiles: str | None = None,
    video: str | None = None,
    still: str | None = None,
    seconds: float = 10.0,
    start_s: float = 0.0,
    tile_start_s: float = 5.0,
    fps: float = 30.0,
    size=(640, 480),
    convention: str | None = None,
    backend: str | None = None,
    log=print,
    settings: SimSettings | None = None,
    rollout: Rollout | None = None,
    progress: bool = True,
) -> list[str]:
    """Write gait tiles (`tiles`: .png, .svg, .pdf, .jpg), a video (`video`:
    .mp4 or .gif; `seconds` of simulated time from `start_s` at `fps`) and/or
    a still of the model at rest (`still`) of one design on one behaviour.
    Every input is checked before any work. settings: the run's time step,
    sensor timing and segment mass (:func:`record`); a convention given must be its own.
    Returns the paths written. Nothing past a divergence is drawn: the tiles
    and the video stop at it (the tiles marked), and one whose window starts
    after it is not written (`log` says so).

    Args:
        design: a :class:`~mat_hopper.core.materials.LegDesign` or a design name.
        behaviour: a behaviour name or :class:`~mat_hopper.core.behaviours.Behaviour`.
        tiles: the gait-tile file (:func:`gait_tiles`, 8 frames from
            start_s + tile_start_s; .png, .jpg, .jpeg, .svg or .pdf); None:
            none.
        video: the video file (.mp4 or .gif); None: none.
        still: the still's file (:func:`render_still`, standing; an RGB
            picture: .png, .jpg or .jpeg); None: none.
        seconds: the video's length, simulated s (> 0); the run lasts
            max(seconds, tile_start_s + 1) from `start_s`.
        start_s: the video's start, simulated s (>= 0).
        tile_start_s: the tiles' start after `start_s`, s (>= 0).
        fps: the video's frames per simulated second, in (0, 240].
        size: (width, height) of the video and the still, pixels.
        convention: the stiffness convention (see :func:`record`).
        backend: ``"osmesa"`` or ``"egl"`` (as ``MUJOCO_GL``); None:
            :func:`choose_backend` from the environment.
        log: called with one line of text: a note when the run diverged
            (when, why, what to try; not for a `rollout` given), an output not
            written because its window starts after the divergence, and the
            video's frame count.
        settings: the run's :class:`~mat_hopper.core.sim.SimSettings`; None: the
            defaults.
        rollout: the run to draw, recorded with ``qpos`` over start_s +
            max(seconds, tile_start_s + 1) (e.g. by :func:`record` with
            these settings); None: :func:`record` it here.
        progress: show the video's frames rendered on stderr (default
            True; ``mat-hopper render --no-progress``: False).

    Returns:
        The paths written, in the order still, tiles, video.

    Raises:
        ValueError: no output asked for, `fps` outside (0, 240], an
            unsupported extension, `seconds` not > 0, `tile_start_s` not >= 0,
            an unknown design or behaviour, or an error of :func:`record`.
        RenderBackendError: no usable off-screen OpenGL library or context.
    """
    if not tiles and not video and not still:
        raise ValueError("nothing to render: give tiles, video and/or still")
    fps = check_fps(fps)
    for path, allowed in ((tiles, IMAGE_EXTENSIONS), (still, RASTER_EXTENSIONS), (video, VIDEO_EXTENSIONS)):
        if path:
            check_extension(path, allowed)
    if not (math.isfinite(seconds) and seconds > 0):
        raise ValueError(f"seconds must be > 0, got {seconds!r}")
    if not (math.isfinite(tile_start_s) and tile_start_s >= 0):
        raise ValueError(f"tile start must be >= 0 s, got {tile_start_s!r}")
    design = as_design(design)
    beh = get_behaviour(behaviour) if isinstance(behaviour, str) else behaviour
    backend = choose_backend({"MUJOCO_GL": backend} if backend else None)
    if rollout is None and (tiles or video):
        rollout = record(
            design, beh, max(seconds, tile_start_s + 1.0), start_s=start_s, convention=convention, settings=settings
        )
        if rollout.diverged:
            log(f"note: {design.name} {rollout.divergence_message()}; frames stop there")
    if rollout is not None and rollout.diverged:
        tiles = _drawable(rollout, tiles, start_s + tile_start_s, "tiles", log)
        video = _drawable(rollout, video, start_s, "video", log)
    written = []
    if still:
        written.append(save_image(render_still(design, beh, size=size, backend=backend), still))
    if tiles:
        fig = gait_tiles(design, beh, rollout=rollout, start_s=start_s + tile_start_s, backend=backend)
        written.append(save_image(fig, tiles))
    if video:
        _video(rollout, video, start_s, seconds, fps, size, backend, progress, log)
        written.append(video)
    return written


def _video(rollout: Rollout, video: str, start_s, seconds, fps, size, backend, progress: bool, log) -> None:
    """render_files' video, and its line: frames, the divergence it ends
    at, and how many frames show the hopper after a fall."""
    times = video_times(rollout, start_s=start_s, seconds=seconds, fps=fps)
    write_video(iter_frames(rollout, times, size=size, backend=backend, progress=progress), video, fps)
    cut = f", ending at the divergence at t = {rollout.diverged_at_s:.4f} s" if rollout.diverged else ""
    fell = rollout.fell_at_s
    if fell is not None and times[-1] >= fell:  # frames of a hopper down, not of its gait
        cut += f"; the hopper fell at t = {fell:.3f} s: the last {int((times >= fell).sum())} frames show it after its fall"
    log(f"{video}: {len(times)} frames at {fps:g} fps, {size[0]}x{size[1]}{cut}")


def _drawable(rollout: Rollout, path: str | None, first_s: float, what: str, log) -> str | None:
    """`path`, or None (with a line to `log`) when its window starts after
    the diverged rollout's last drawable record (:func:`drawn_until_s`)."""
    if path and first_s > drawn_until_s(rollout):
        log(
            f"{what} not written ({path}): its window starts at {first_s:g} s, after the run diverged at "
            f"t = {rollout.diverged_at_s:.4f} s"
        )
        return None
    return path
