"""Recording a rollout and rendering its frames: stills, gait tiles and
the frame times of a video.

Rendering replays joint positions recorded during the fast rollout
(``simulate(..., record_qpos=True)``) in the scene of
:mod:`mat_hopper.viz.scene`; segments are coloured by density (viridis over
log density, :data:`~mat_hopper.viz.scene.DENSITY_RANGE_G_CM3`).
:mod:`mat_hopper.viz.render` re-exports every name here.
"""

from __future__ import annotations

import dataclasses
import math

import mujoco
import numpy as np

from ..core.behaviours import Behaviour
from ..core.behaviours import behaviour as get_behaviour
from ..core.materials import LegDesign, as_design
from ..core.model import reset_to_start
from ..core.rollout import FELL_TILT_DEG, Rollout
from ..core.sim import SimSettings, simulate
from ._files import check_fps
from .scene import DENSITY_RANGE_G_CM3, Camera, OffscreenRenderer, render_spec


def record(
    design,
    behaviour,
    seconds: float,
    *,
    start_s: float = 0.0,
    convention: str | None = None,
    settings: SimSettings | None = None,
    warn: bool = True,
) -> Rollout:
    """A rollout with joint positions recorded up to start_s + seconds (s).
    convention: the stiffness convention (None: the settings', else the
    paper's); settings: the run's other settings (time step, substeps,
    sensor timing, segment mass, convention; its duration and transient are
    replaced). Raises ValueError for a convention other than the settings'.

    Args:
        design: a :class:`~mat_hopper.core.materials.LegDesign` or a design name.
        behaviour: a behaviour name or :class:`~mat_hopper.core.behaviours.Behaviour`.
        seconds: simulated time recorded after `start_s`, s (finite, > 0).
        start_s: start of the window of interest, s (finite, >= 0); the run
            lasts start_s + seconds with no transient.
        convention: the stiffness convention; None: the settings' (or, without
            settings, the default).
        settings: the run's :class:`~mat_hopper.core.sim.SimSettings`; None: the
            defaults.
        warn: :func:`mat_hopper.core.sim.simulate`'s warnings (a step above
            the leg's analytic bound, a divergence); False: none (the caller
            says it).

    Returns:
        The :class:`~mat_hopper.core.rollout.Rollout`, with ``qpos`` (every joint
        position at the record rate).

    Raises:
        ValueError: `seconds` not finite and positive, `start_s` not finite and
            >= 0, a `convention` other than the settings', or any error of
            :func:`mat_hopper.core.sim.simulate` (unknown design, behaviour or
            setting).
    """
    if not (math.isfinite(seconds) and seconds > 0):
        raise ValueError(f"seconds must be > 0, got {seconds!r}")
    if not (math.isfinite(start_s) and start_s >= 0):
        raise ValueError(f"start must be >= 0 s, got {start_s!r}")
    if settings is not None:
        if convention is not None and convention != settings.convention:
            raise ValueError(f"convention {convention!r} given beside settings of convention {settings.convention!r}")
        settings = dataclasses.replace(settings, duration_s=start_s + seconds, transient_s=0.0)
        return simulate(design, behaviour, settings=settings, record_qpos=True, warn=warn)
    return simulate(
        design,
        behaviour,
        duration_s=start_s + seconds,
        transient_s=0.0,
        convention=convention,
        record_qpos=True,
        warn=warn,
    )


def drawn_until_s(rollout: Rollout) -> float:
    """The last simulated time (s) that can be drawn: the rollout's end,
    or for a diverged one its last record with finite joint positions
    (nothing past a divergence is drawn).

    Args:
        rollout: a :class:`~mat_hopper.core.rollout.Rollout`.

    Returns:
        The time, s.
    """
    t = rollout.time
    if rollout.stable or rollout.qpos is None:
        return float(t[-1])
    ok = np.flatnonzero(np.isfinite(rollout.qpos).all(axis=1) & (t < rollout.diverged_at_s))
    return float(t[ok[-1]]) if len(ok) else float(t[0])


def _check_drawable(rollout: Rollout, first_s: float, what: str) -> float:
    """drawn_until_s, or ValueError when `what` starts after it (the run
    ended, or diverged, before): nothing to draw, rather than frozen poses."""
    end = drawn_until_s(rollout)
    if first_s > end:
        why = (
            f"the run diverged at t = {rollout.diverged_at_s:.4f} s"
            if rollout.diverged
            else f"the run ends at {end:g} s"
        )
        raise ValueError(f"nothing to draw: {what} start at {first_s:g} s, after {why}")
    return end


def iter_frames(
    rollout: Rollout,
    times_s,
    *,
    size=(640, 480),
    camera: Camera | None = None,
    backend: str | None = None,
    progress: bool = False,
):
    """Yield RGB frames (height, width, 3) of a rollout at the given times
    (s), one at a time (a long video never sits in memory).

    Args:
        rollout: a :class:`~mat_hopper.core.rollout.Rollout` recorded with
            ``record_qpos=True``.
        times_s: the frames' simulated times, s; each shows the first record
            at or after its time (the last record for later times; never a
            time past a divergence, :func:`drawn_until_s`).
        size: (width, height) of the frames, pixels.
        camera: the :class:`Camera`; None: ``Camera()``.
        backend: ``"osmesa"`` or ``"egl"``; None: :func:`choose_backend`.
        progress: show a progress bar (``mat_hopper.util.progress``).

    Yields:
        (height, width, 3) uint8 RGB arrays, one per time, in order.

    Raises:
        ValueError: a rollout without joint positions, or of a diverged
            run a time after its last drawable record (raised at the first
            frame requested, as for any generator).
        RenderBackendError: no usable off-screen OpenGL library or context.
    """
    if rollout.qpos is None:
        raise ValueError("the rollout has no joint positions: simulate(..., record_qpos=True)")
    times_s = np.asarray(times_s, float)
    if rollout.diverged and len(times_s):
        _check_drawable(rollout, float(times_s.max()), "frames")
    w, h = size
    spec = render_spec(
        rollout.design,
        rollout.behaviour,
        convention=rollout.settings.convention,
        path_until_s=float(rollout.time[-1]) + 1.0,
        width=w,
        height=h,
    )
    model = spec.compile()
    idx = np.clip(np.searchsorted(rollout.time, times_s), 0, len(rollout.time) - 1)
    camera = camera or Camera()
    from ..util.progress import progress_bar

    with OffscreenRenderer(model, w, h, backend) as r:
        for i in progress_bar(idx, desc="render", unit="frame", enabled=progress):
            yield r.frame(rollout.qpos[i], camera, rollout.behaviour)


def render_frames(
    rollout: Rollout, times_s, *, size=(640, 480), camera: Camera | None = None, backend: str | None = None
) -> np.ndarray:
    """RGB frames (n, height, width, 3) of a rollout at the given times (s).

    Args:
        rollout: a :class:`~mat_hopper.core.rollout.Rollout` recorded with
            ``record_qpos=True``.
        times_s: the n frames' simulated times, s (as for :func:`iter_frames`).
        size: (width, height) of the frames, pixels.
        camera: the :class:`Camera`; None: ``Camera()``.
        backend: ``"osmesa"`` or ``"egl"``; None: :func:`choose_backend`.

    Returns:
        (n, height, width, 3) uint8 array.

    Raises:
        ValueError: a rollout without joint positions, or no times.
        RenderBackendError: no usable off-screen OpenGL library or context.
    """
    return np.stack(list(iter_frames(rollout, times_s, size=size, camera=camera, backend=backend)))


def standing_qpos(model: mujoco.MjModel, behaviour: Behaviour) -> np.ndarray:
    """The start pose (upright, at the behaviour's start) lowered until the
    foot rests on the ground or ramp (MuJoCo's own foot-terrain distance, to
    1 um): the pose for a picture of the model.

    Args:
        model: a compiled hopper model (e.g. of :func:`render_spec`), with
            the joint ``base_x`` and the geoms ``foot`` and ``ground`` (and
            ``ramp``).
        behaviour: the :class:`~mat_hopper.core.behaviours.Behaviour` whose
            start_xy_m places the base.

    Returns:
        (model.nq,) qpos array: the start keyframe at the behaviour's start,
        the base z slide lowered by the foot-terrain gap (at most 8
        corrections).
    """
    d = mujoco.MjData(model)
    reset_to_start(model, d)
    bx = int(model.joint("base_x").qposadr[0])
    d.qpos[bx], d.qpos[bx + 1] = behaviour.start_xy_m
    foot = model.geom("foot").id
    terrain = [i for i in range(model.ngeom) if model.geom(i).name in ("ground", "ramp")]
    for _ in range(8):  # a slanted surface needs a few vertical steps
        mujoco.mj_kinematics(model, d)
        gap = min(mujoco.mj_geomDistance(model, d, foot, g, 10.0, None) for g in terrain)
        if abs(gap) < 1e-6:
            break
        d.qpos[bx + 2] -= gap
    return d.qpos.copy()


def render_still(
    design,
    behaviour="static",
    *,
    size=(640, 480),
    camera: Camera | None = None,
    standing: bool = True,
    backend: str | None = None,
) -> np.ndarray:
    """One RGB picture (height, width, 3) of the hopper at its start pose,
    standing on its foot (standing=False: at the simulation's start height,
    0.56 m up), segments coloured by density, the behaviour's path marked.

    Args:
        design: a :class:`~mat_hopper.core.materials.LegDesign` or a design name.
        behaviour: a behaviour name or :class:`~mat_hopper.core.behaviours.Behaviour`
            (its start, terrain and 20 s of its path are drawn).
        size: (width, height) of the picture, pixels.
        camera: the :class:`Camera`; None: a close view for ``standing``, a
            wider, higher one otherwise.
        standing: True: the pose of :func:`standing_qpos`; False: that pose
            with the base z slide (qpos) set to 0.
        backend: ``"osmesa"`` or ``"egl"``; None: :func:`choose_backend`.

    Returns:
        (height, width, 3) uint8 RGB array.

    Raises:
        ValueError: an unknown design or behaviour.
        RenderBackendError: no usable off-screen OpenGL library or context.
    """
    design = as_design(design)
    beh = get_behaviour(behaviour)
    w, h = size
    model = render_spec(design, beh, width=w, height=h, path_until_s=20.0).compile()
    qpos = standing_qpos(model, beh)
    if not standing:
        qpos[int(model.joint("base_z").qposadr[0])] = 0.0
    camera = camera or (
        Camera(distance_m=1.75, azimuth_deg=125.0, elevation_deg=-10.0, height_m=0.42)
        if standing
        else Camera(distance_m=2.2, azimuth_deg=125.0, elevation_deg=-12.0, height_m=0.75)
    )
    with OffscreenRenderer(model, w, h, backend) as r:
        return r.frame(qpos, camera, beh)


def _density_legend(fig, ax, design: LegDesign) -> None:
    """A density colour bar whose labelled ticks are the design's segments
    (``seg 1 1.39``, hip first), plus round numbers that do not crowd them."""
    import matplotlib as mpl

    norm = mpl.colors.LogNorm(*DENSITY_RANGE_G_CM3)
    cb = fig.colorbar(mpl.cm.ScalarMappable(norm=norm, cmap="viridis"), ax=ax, fraction=0.025, pad=0.01)
    cb.set_label("segment density (g/cm$^3$)")
    segs: dict[float, list[str]] = {}
    for i, d in enumerate(design.densities_g_cm3, start=1):
        segs.setdefault(d, []).append(str(i))
        cb.ax.plot([0, 1], [d, d], color="white", lw=1.5)
    lo, hi = DENSITY_RANGE_G_CM3
    rounds = [t for t in (1, 2, 5, 10, 20) if lo <= t <= hi and all(abs(math.log(t / d)) > 0.3 for d in segs)]
    ticks = sorted([(t, f"{t:g}") for t in rounds] + [(d, f"seg {','.join(ids)}: {d:g}") for d, ids in segs.items()])
    cb.set_ticks([t for t, _ in ticks], labels=[lab for _, lab in ticks])
    cb.ax.minorticks_off()
    cb.ax.tick_params(labelsize=7)


def gait_tiles(
    design,
    behaviour="forward",
    *,
    rollout: Rollout | None = None,
    start_s: float = 5.0,
    seconds: float = 0.7,
    n_frames: int = 8,
    size=(280, 400),
    camera: Camera | None = None,
    backend: str | None = None,
):
    """The paper's gait-tile figure: n_frames of a hop sequence (one hop
    cycle, about 0.7 s, by default) side by side, the desired path marked, segments coloured by density. Returns a
    matplotlib Figure (frames also in ``fig.frames``).

    Args:
        design: a :class:`~mat_hopper.core.materials.LegDesign` or a design name,
            simulated when no `rollout` is given.
        behaviour: a behaviour name or Behaviour, likewise.
        rollout: a Rollout with ``qpos`` to show instead (its own design and
            behaviour are shown); None: :func:`record` one of `seconds` from
            `start_s`.
        start_s: time of the first frame, simulated s.
        seconds: span of the frames, s (cut at the rollout's end, or at its
            divergence: the title says so, the last tile is marked); tiles
            at or after a fall (:attr:`~mat_hopper.core.rollout.Rollout.fell_at_s`)
            are marked "(fell)" and the title says when it fell.
        n_frames: the number of frames, evenly spaced, >= 1.
        size: (width, height) of each frame, pixels.
        camera: the :class:`Camera`; None: ``Camera(distance_m=2.1)``.
        backend: ``"osmesa"`` or ``"egl"``; None: :func:`choose_backend`.

    Returns:
        The ``matplotlib.figure.Figure``, the frames side by side with their
        times and a density colour bar; ``fig.frames`` holds them as an
        (n_frames, height, width, 3) uint8 array.

    Raises:
        ValueError: `n_frames` < 1, a rollout without joint positions, a
            `start_s` after the rollout's end or divergence (nothing to draw),
            or an error of :func:`record` (invalid `seconds` or `start_s`,
            unknown design or behaviour).
        RenderBackendError: no usable off-screen OpenGL library or context.
    """
    from matplotlib.figure import Figure

    if int(n_frames) < 1:
        raise ValueError(f"n_frames must be >= 1, got {n_frames!r}")
    if rollout is None:
        rollout = record(design, behaviour, seconds, start_s=start_s)
    end = _check_drawable(rollout, start_s, "the tiles")  # times run forward from start_s, never back
    cut = rollout.diverged and start_s + seconds > end  # the window reaches the divergence
    times = np.linspace(start_s, min(start_s + seconds, end), int(n_frames))
    frames = render_frames(rollout, times, size=size, camera=camera or Camera(distance_m=2.1), backend=backend)
    fig = Figure(figsize=(1.6 * len(frames) + 1.2, 2.6), dpi=150, layout="constrained")
    ax = fig.subplots()
    ax.imshow(np.concatenate(list(frames), axis=1))
    w = frames.shape[2]
    digits = 2 if times[-1] - times[0] >= 0.07 else 4  # tiles a few ms apart keep distinct labels
    fell = rollout.fell_at_s  # a tile after the fall shows a hopper down, not its gait
    for k, t in enumerate(times):
        last = cut and k == len(times) - 1
        down = fell is not None and t >= fell
        label = f"t = {t:.{digits}f} s" + (" (diverged)" if last else " (fell)" if down else "")
        ax.text(k * w + 6, 14, label, fontsize=7, color="red" if last or down else "black")
    ax.set_axis_off()
    d = rollout.design
    beh = rollout.behaviour
    terrain = f", {math.tan(math.radians(beh.ramp_grade_deg)) * 100:.1f} % ramp" if beh.ramp_grade_deg else ""
    div = f"; diverged at t = {rollout.diverged_at_s:.4f} s, the frames end there" if cut else ""
    if fell is not None and times[-1] >= fell:
        div += f"; fell at t = {fell:.3f} s (base tilted past {FELL_TILT_DEG:g} deg): tiles after it marked (fell)"
    ax.set_title(f"{d.name}: {beh.name} hopping{terrain} (red: desired path){div}", fontsize=9)
    _density_legend(fig, ax, d)
    fig.frames = frames
    return fig


def video_times(
    rollout: Rollout, *, start_s: float = 0.0, seconds: float | None = None, fps: float = 30.0
) -> np.ndarray:
    """Simulated times (s) of the frames: start_s + k / fps up to the end of
    the window (start_s + seconds) or of the rollout, both ends included.

    Args:
        rollout: the :class:`~mat_hopper.core.rollout.Rollout`.
        start_s: the first frame's time, s.
        seconds: the window's length, s; None: to the rollout's end.
        fps: frames per simulated second, in (0, 240].

    Returns:
        1-D float array of the frame times, s.

    Raises:
        ValueError: `fps` outside (0, 240], or a window that starts after the
            rollout ends (or diverged: the frames stop there, :func:`drawn_until_s`).
    """
    fps = check_fps(fps)
    end = drawn_until_s(rollout)
    t_end = end if seconds is None else start_s + seconds
    n = int(math.floor((min(t_end, end) - start_s) * fps + 1e-9)) + 1
    if n < 1:
        _check_drawable(rollout, start_s, "the video's frames")
        raise ValueError("nothing to render: the window starts after the rollout ends")
    return start_s + np.arange(n) / fps
