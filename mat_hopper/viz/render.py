"""Off-screen rendering: stills, gait tiles and videos of any design.

No display needed. The OpenGL backend is OSMesa (software, Debian package
``libosmesa6``) by default, EGL (GPU) when ``MUJOCO_GL=egl`` is set or when
OSMesa is missing; when neither library can be found the error names both.
Rendering replays joint positions recorded during the fast rollout
(``simulate(..., record_qpos=True)``), so simulation never waits for it.

Leg segments are coloured by density (viridis over log density, 0.9 to 20
g/cm^3) so graded legs show at a glance; the desired path is drawn as a
dotted line of small markers on the ground or ramp.

    from mat_hopper.viz.render import gait_tiles, save_video, render_still
    fig = gait_tiles("rho-inc", "ramp")                 # a matplotlib Figure
    save_video("rho-inc", "ramp", "hop.mp4", seconds=10, fps=30)
"""

from __future__ import annotations

import ctypes.util
import dataclasses
import math
import os
from dataclasses import dataclass

import mujoco
import numpy as np

from .. import reference as ref
from ..atomic import atomic_path
from ..behaviours import Behaviour
from ..behaviours import behaviour as get_behaviour
from ..materials import DEFAULT_CONVENTION, LegDesign
from ..model import build_spec, reset_to_start
from ..sim import Rollout, SimSettings, _as_design, simulate

DENSITY_RANGE_G_CM3 = (0.9, 20.0)  # colour scale: the optimizer's density bounds
VIDEO_EXTENSIONS = (".mp4", ".gif")
IMAGE_EXTENSIONS = (".png", ".jpg", ".jpeg", ".svg", ".pdf")


class RenderBackendError(RuntimeError):
    """No usable off-screen OpenGL library (OSMesa or EGL)."""


_LIBS = {"osmesa": ("OSMesa", "libosmesa6"), "egl": ("EGL", "libegl1")}


def choose_backend(env=None, find_library=ctypes.util.find_library) -> str:
    """The off-screen backend to use: ``osmesa`` or ``egl``.

    $MUJOCO_GL decides when it names one of them (then there is no
    fallback), else $PYOPENGL_PLATFORM when it does; otherwise OSMesa if its
    library is there, else EGL (MUJOCO_GL=glfw, an on-screen window, is not
    used for off-screen work). Raises RenderBackendError naming the missing
    libraries."""
    env = os.environ if env is None else env
    asked = env.get("MUJOCO_GL", "").strip().lower()
    if asked not in _LIBS:
        asked = env.get("PYOPENGL_PLATFORM", "").strip().lower()
    if asked in _LIBS:
        lib, pkg = _LIBS[asked]
        if find_library(lib) is None:
            raise RenderBackendError(
                f"MUJOCO_GL={asked} but lib{lib} was not found "
                f"(Debian package {pkg}; scripts/setup.sh installs it as root)"
            )
        return asked
    for name in ("osmesa", "egl"):
        if find_library(_LIBS[name][0]) is not None:
            return name
    raise RenderBackendError(
        "no off-screen OpenGL library: neither libOSMesa (Debian package libosmesa6) "
        "nor libEGL (libegl1) was found; run scripts/setup.sh as root"
    )


def _gl_context_class(backend: str):
    """The MuJoCo GL context class of a backend (sets PyOpenGL's platform
    first, unless the user already chose one)."""
    if not os.environ.get("PYOPENGL_PLATFORM", "").strip():  # unset or empty: ours to choose
        os.environ["PYOPENGL_PLATFORM"] = backend
    if os.environ["PYOPENGL_PLATFORM"].lower() != backend:
        raise RenderBackendError(
            f"PYOPENGL_PLATFORM={os.environ['PYOPENGL_PLATFORM']} conflicts with the "
            f"{backend} backend; unset it or set MUJOCO_GL to match"
        )
    try:
        if backend == "osmesa":
            from mujoco.osmesa import GLContext
        else:
            from mujoco.egl import GLContext
    except Exception as e:  # ImportError, OSError, PyOpenGL's own errors
        raise RenderBackendError(f"could not load the {backend} OpenGL backend: {e}") from e
    return GLContext


# ---------------------------------------------------------------------------
# the scene


def density_color(density_g_cm3: float) -> np.ndarray:
    """RGBA of a density (g/cm^3) on the viridis scale over log density."""
    from matplotlib import colormaps

    lo, hi = np.log(DENSITY_RANGE_G_CM3)
    u = float(np.clip((math.log(density_g_cm3) - lo) / (hi - lo), 0.0, 1.0))
    return np.array(colormaps["viridis"](u))


def _surface_z(behaviour: Behaviour, x: np.ndarray) -> np.ndarray:
    """Height (m) of the ground or ramp top under x."""
    if behaviour.ramp_grade_deg is None:
        return np.zeros_like(x)
    top = 2 * ref.RAMP_HALF_SIZE[0] * math.cos(math.radians(behaviour.ramp_grade_deg))
    return np.where((x >= 0) & (x <= top), x * math.tan(math.radians(behaviour.ramp_grade_deg)), 0.0)


def render_spec(
    design: LegDesign,
    behaviour: Behaviour,
    *,
    convention: str = DEFAULT_CONVENTION,
    path_until_s: float = 60.0,
    width: int = 640,
    height: int = 480,
) -> mujoco.MjSpec:
    """The simulation's spec, dressed for pictures: segment colours by
    density, a checker floor, sky, and markers along the desired path.
    Joints are unchanged, so recorded qpos replays on it."""
    spec = build_spec(design, ramp_grade_deg=behaviour.ramp_grade_deg, convention=convention)
    # Segment colours glow a little (emission) so they read on a thin leg in shade.
    spec.add_material(name="segment", emission=0.35, specular=0.3)
    for i, mat in enumerate(design.segments, start=1):
        rgba = density_color(mat.density_g_cm3)
        for half in ("upper", "lower"):
            g = spec.geom(f"seg{i}_{half}")
            g.material, g.rgba = "segment", rgba
    spec.visual.global_.offwidth = max(width, 640)
    spec.visual.global_.offheight = max(height, 480)
    spec.visual.quality.shadowsize = 2048
    spec.visual.map.shadowclip = 1.5  # shadow-map extent, in units of the model's extent
    spec.visual.headlight.ambient = [0.22, 0.22, 0.22]
    spec.visual.headlight.diffuse = [0.22, 0.22, 0.22]
    spec.visual.headlight.specular = [0.05, 0.05, 0.05]
    # Lights: the model's overhead sun becomes a soft fill; a key light from
    # the camera's side, slanted, follows the hopper (tracks the centre of
    # mass) and casts the only shadow, offset from the foot by the hop height.
    sun = spec.light("sun")
    sun.castshadow, sun.diffuse, sun.specular = False, [0.22, 0.22, 0.22], [0, 0, 0]
    key = np.array([0.35, 0.6, -1.0])
    spec.worldbody.add_light(
        name="key",
        type=mujoco.mjtLightType.mjLIGHT_DIRECTIONAL,
        mode=mujoco.mjtCamLight.mjCAMLIGHT_TRACKCOM,
        pos=list(-3.0 * key),
        dir=list(key / np.linalg.norm(key)),
        castshadow=True,
        diffuse=[0.5, 0.5, 0.48],
        specular=[0.2, 0.2, 0.2],
    )
    spec.add_texture(
        name="sky",
        type=mujoco.mjtTexture.mjTEXTURE_SKYBOX,
        builtin=mujoco.mjtBuiltin.mjBUILTIN_GRADIENT,
        rgb1=[0.75, 0.85, 0.95],
        rgb2=[1, 1, 1],
        width=256,
        height=256,
    )
    spec.add_texture(
        name="checker",
        type=mujoco.mjtTexture.mjTEXTURE_2D,
        builtin=mujoco.mjtBuiltin.mjBUILTIN_CHECKER,
        rgb1=[0.86, 0.86, 0.83],
        rgb2=[0.74, 0.74, 0.71],
        width=256,
        height=256,
    )
    mat = spec.add_material(name="floor", texrepeat=[8, 8])  # no reflection pass: half the cost
    mat.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = "checker"
    ground = spec.geom("ground")
    ground.material, ground.rgba, ground.size = "floor", [1, 1, 1, 1], [8, 8, 0.1]
    if behaviour.ramp_grade_deg is not None:
        spec.geom("ramp").rgba = [0.5, 0.62, 0.8, 1]
    # The desired path: small flat discs every 5 cm of path (or 0.5 s).
    ts = np.arange(
        0.0, path_until_s, max(0.05 / max(behaviour.speed_m_s, 1e-9), 0.5) if behaviour.speed_m_s > 0 else path_until_s
    )
    xy = np.array([behaviour.desired(t)[:2] for t in ts]) if len(ts) else np.zeros((0, 2))
    z = _surface_z(behaviour, xy[:, 0]) if len(xy) else []
    for k, ((x, y), zz) in enumerate(zip(xy, z)):
        spec.worldbody.add_geom(
            name=f"path{k}",
            type=mujoco.mjtGeom.mjGEOM_CYLINDER,
            size=[0.02, 0.002, 0],
            pos=[x, y, zz + 0.004],
            rgba=[0.85, 0.2, 0.15, 1],
            contype=0,
            conaffinity=0,
            mass=0,
        )
    return spec


@dataclass
class Camera:
    """A camera that follows the base: distance (m), azimuth and elevation
    (deg; azimuth 90 looks along +y, i.e. a side view of forward hopping)."""

    distance_m: float = 2.8
    azimuth_deg: float = 90.0
    elevation_deg: float = -8.0
    height_m: float = 0.6  # look-at height above the ground under the base

    def place(self, cam: mujoco.MjvCamera, base_xyz, behaviour: Behaviour) -> None:
        cam.type = mujoco.mjtCamera.mjCAMERA_FREE
        x, y = float(base_xyz[0]), float(base_xyz[1])
        cam.lookat[:] = [x, y, float(_surface_z(behaviour, np.array([x]))[0]) + self.height_m]
        cam.distance, cam.azimuth, cam.elevation = self.distance_m, self.azimuth_deg, self.elevation_deg


class OffscreenRenderer:
    """Renders RGB frames (height, width, 3, uint8) of one model off-screen."""

    def __init__(self, model: mujoco.MjModel, width: int, height: int, backend: str | None = None):
        self.backend = backend or choose_backend()
        self.width, self.height = int(width), int(height)
        self.model = model
        self.data = mujoco.MjData(model)
        try:
            self._ctx = _gl_context_class(self.backend)(self.width, self.height)
            self._ctx.make_current()
        except RenderBackendError:
            raise
        except Exception as e:  # e.g. PyOpenGL already bound to another platform in this process
            lib, pkg = _LIBS[self.backend]
            raise RenderBackendError(
                f"could not create a {self.backend} OpenGL context ({e}); it needs lib{lib} "
                f"(Debian package {pkg}) and PyOpenGL, and MUJOCO_GL={self.backend} set "
                "before anything else imports OpenGL"
            ) from e
        self._con = mujoco.MjrContext(model, mujoco.mjtFontScale.mjFONTSCALE_150)
        mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, self._con)
        self._scene = mujoco.MjvScene(model, maxgeom=10000)
        self._opt = mujoco.MjvOption()
        self._cam = mujoco.MjvCamera()
        self._rect = mujoco.MjrRect(0, 0, self.width, self.height)

    def frame(self, qpos: np.ndarray, camera: Camera, behaviour: Behaviour) -> np.ndarray:
        self.data.qpos[:] = qpos
        mujoco.mj_kinematics(self.model, self.data)
        mujoco.mj_comPos(self.model, self.data)  # the key light tracks the centre of mass
        mujoco.mj_camlight(self.model, self.data)  # place the lights (else they have no direction)
        camera.place(self._cam, self.data.body("base").xpos, behaviour)
        self._ctx.make_current()
        mujoco.mjv_updateScene(
            self.model, self.data, self._opt, None, self._cam, mujoco.mjtCatBit.mjCAT_ALL, self._scene
        )
        mujoco.mjr_render(self._rect, self._scene, self._con)
        rgb = np.empty((self.height, self.width, 3), dtype=np.uint8)
        mujoco.mjr_readPixels(rgb, None, self._rect, self._con)
        return np.flipud(rgb).copy()

    def close(self) -> None:
        if self._ctx is not None:
            self._con.free()
            self._ctx.free()
            self._ctx = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


# ---------------------------------------------------------------------------
# inputs


def parse_size(text: str) -> tuple[int, int]:
    """'640x480' -> (640, 480) pixels."""
    try:
        w, h = (int(v) for v in str(text).lower().split("x"))
    except ValueError:
        raise ValueError(f"size must be WIDTHxHEIGHT in pixels, e.g. 640x480; got {text!r}") from None
    if not (16 <= w <= 4096 and 16 <= h <= 4096):
        raise ValueError(f"size must be between 16x16 and 4096x4096 pixels, got {text!r}")
    return w, h


def _check_fps(fps) -> float:
    if not (isinstance(fps, (int, float)) and math.isfinite(fps) and 0 < fps <= 240):
        raise ValueError(f"fps must be in (0, 240] frames per second, got {fps!r}")
    return float(fps)


def _check_extension(path: str, allowed: tuple) -> str:
    ext = os.path.splitext(str(path))[1].lower()
    if ext not in allowed:
        raise ValueError(f"unknown file type {ext or '(none)'!r} for {path!r}; accepted: {', '.join(allowed)}")
    return ext


def record(
    design,
    behaviour,
    seconds: float,
    *,
    start_s: float = 0.0,
    convention: str = DEFAULT_CONVENTION,
    settings: SimSettings | None = None,
) -> Rollout:
    """A rollout with joint positions recorded up to start_s + seconds (s).
    settings: the run's other settings (time step, substeps, sensor timing,
    segment mass, convention; its duration and transient are replaced)."""
    if not (math.isfinite(seconds) and seconds > 0):
        raise ValueError(f"seconds must be > 0, got {seconds!r}")
    if not (math.isfinite(start_s) and start_s >= 0):
        raise ValueError(f"start must be >= 0 s, got {start_s!r}")
    if settings is not None:
        settings = dataclasses.replace(settings, duration_s=start_s + seconds, transient_s=0.0)
        return simulate(design, behaviour, settings=settings, record_qpos=True)
    return simulate(
        design, behaviour, duration_s=start_s + seconds, transient_s=0.0, convention=convention, record_qpos=True
    )


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
    (s), one at a time (a long video never sits in memory)."""
    if rollout.qpos is None:
        raise ValueError("the rollout has no joint positions: simulate(..., record_qpos=True)")
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
    idx = np.clip(np.searchsorted(rollout.time, np.asarray(times_s, float)), 0, len(rollout.time) - 1)
    camera = camera or Camera()
    from tqdm import tqdm

    with OffscreenRenderer(model, w, h, backend) as r:
        for i in tqdm(idx, desc="render", unit="frame", disable=not progress):
            yield r.frame(rollout.qpos[i], camera, rollout.behaviour)


def render_frames(
    rollout: Rollout, times_s, *, size=(640, 480), camera: Camera | None = None, backend: str | None = None
) -> np.ndarray:
    """RGB frames (n, height, width, 3) of a rollout at the given times (s)."""
    return np.stack(list(iter_frames(rollout, times_s, size=size, camera=camera, backend=backend)))


# ---------------------------------------------------------------------------
# products


def standing_qpos(model: mujoco.MjModel, behaviour: Behaviour) -> np.ndarray:
    """The start pose (upright, at the behaviour's start) lowered until the
    foot rests on the ground or ramp (MuJoCo's own foot-terrain distance, to
    1 um): the pose for a picture of the model."""
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
    0.56 m up), segments coloured by density, the behaviour's path marked."""
    design = _as_design(design)
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
    matplotlib Figure (frames also in ``fig.frames``)."""
    from matplotlib.figure import Figure

    if int(n_frames) < 1:
        raise ValueError(f"n_frames must be >= 1, got {n_frames!r}")
    if rollout is None:
        rollout = record(design, behaviour, seconds, start_s=start_s)
    times = np.linspace(start_s, min(start_s + seconds, float(rollout.time[-1])), int(n_frames))
    frames = render_frames(rollout, times, size=size, camera=camera or Camera(distance_m=2.1), backend=backend)
    fig = Figure(figsize=(1.6 * len(frames) + 1.2, 2.6), dpi=150, layout="constrained")
    ax = fig.subplots()
    ax.imshow(np.concatenate(list(frames), axis=1))
    w = frames.shape[2]
    for k, t in enumerate(times):
        ax.text(k * w + 6, 14, f"t = {t:.2f} s", fontsize=7, color="black")
    ax.set_axis_off()
    d = rollout.design
    beh = rollout.behaviour
    terrain = f", {math.tan(math.radians(beh.ramp_grade_deg)) * 100:.1f} % ramp" if beh.ramp_grade_deg else ""
    ax.set_title(f"{d.name}: {beh.name} hopping{terrain} (red: desired path)", fontsize=9)
    _density_legend(fig, ax, d)
    fig.frames = frames
    return fig


def video_times(
    rollout: Rollout, *, start_s: float = 0.0, seconds: float | None = None, fps: float = 30.0
) -> np.ndarray:
    """Simulated times (s) of the frames: start_s + k / fps up to the end of
    the window (start_s + seconds) or of the rollout, both ends included."""
    fps = _check_fps(fps)
    t_end = float(rollout.time[-1]) if seconds is None else start_s + seconds
    n = int(math.floor((min(t_end, float(rollout.time[-1])) - start_s) * fps + 1e-9)) + 1
    if n < 1:
        raise ValueError("nothing to render: the window starts after the rollout ends")
    return start_s + np.arange(n) / fps


def video_frames(
    rollout: Rollout,
    *,
    start_s: float = 0.0,
    seconds: float | None = None,
    fps: float = 30.0,
    size=(640, 480),
    camera: Camera | None = None,
    backend: str | None = None,
) -> np.ndarray:
    """Frames (n, height, width, 3) of a rollout at fps frames per simulated second."""
    return render_frames(
        rollout,
        video_times(rollout, start_s=start_s, seconds=seconds, fps=fps),
        size=size,
        camera=camera,
        backend=backend,
    )


def write_video(frames, path: str, fps: float) -> str:
    """Write frames (an array or any iterable of (h, w, 3) uint8 images) as
    MP4 (H.264, imageio-ffmpeg; streamed) or GIF, atomically."""
    import imageio.v2 as imageio

    ext = _check_extension(path, VIDEO_EXTENSIONS)
    fps = _check_fps(fps)
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
    frames streamed to the file as they are rendered."""
    _check_extension(path, VIDEO_EXTENSIONS)
    _check_fps(fps)
    if rollout is None:
        rollout = record(design, behaviour, seconds, start_s=start_s)
    times = video_times(rollout, start_s=start_s, seconds=seconds, fps=fps)
    write_video(iter_frames(rollout, times, size=size, backend=backend, progress=progress), path, fps)
    return path


def save_image(fig_or_rgb, path: str) -> str:
    """Write a Figure or an RGB array as an image file, atomically."""
    ext = _check_extension(path, IMAGE_EXTENSIONS)
    with atomic_path(path) as tmp:
        if isinstance(fig_or_rgb, np.ndarray):
            import imageio.v2 as imageio

            imageio.imwrite(tmp, fig_or_rgb)
        else:
            fig_or_rgb.savefig(tmp, metadata={"Software": None} if ext == ".png" else None)
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
    convention: str = DEFAULT_CONVENTION,
    backend: str | None = None,
    log=print,
    settings: SimSettings | None = None,
) -> list[str]:
    """Write gait tiles (`tiles`: .png, .svg, .pdf, .jpg), a video (`video`:
    .mp4 or .gif; `seconds` of simulated time from `start_s` at `fps`) and/or
    a still of the model at rest (`still`) of one design on one behaviour.
    Every input is checked before any work. settings: the run's time step,
    sensor timing and segment mass (:func:`record`); its convention wins.
    Returns the paths written."""
    if not tiles and not video and not still:
        raise ValueError("nothing to render: give tiles, video and/or still")
    fps = _check_fps(fps)
    for path, allowed in ((tiles, IMAGE_EXTENSIONS), (still, IMAGE_EXTENSIONS), (video, VIDEO_EXTENSIONS)):
        if path:
            _check_extension(path, allowed)
    if not (math.isfinite(seconds) and seconds > 0):
        raise ValueError(f"seconds must be > 0, got {seconds!r}")
    if not (math.isfinite(tile_start_s) and tile_start_s >= 0):
        raise ValueError(f"tile start must be >= 0 s, got {tile_start_s!r}")
    design = _as_design(design)
    beh = get_behaviour(behaviour) if isinstance(behaviour, str) else behaviour
    backend = choose_backend({"MUJOCO_GL": backend} if backend else None)
    rollout = (
        record(design, beh, max(seconds, tile_start_s + 1.0), start_s=start_s, convention=convention, settings=settings)
        if (tiles or video)
        else None
    )
    if rollout is not None and not rollout.stable:
        log(f"note: {design.name} diverged at t = {rollout.diverged_at_s:.3f} s; frames stop there")
    written = []
    if still:
        written.append(save_image(render_still(design, beh, size=size, backend=backend), still))
    if tiles:
        fig = gait_tiles(design, beh, rollout=rollout, start_s=start_s + tile_start_s, backend=backend)
        written.append(save_image(fig, tiles))
    if video:
        times = video_times(rollout, start_s=start_s, seconds=seconds, fps=fps)
        write_video(iter_frames(rollout, times, size=size, backend=backend, progress=True), video, fps)
        log(f"{video}: {len(times)} frames at {fps:g} fps, {size[0]}x{size[1]}")
        written.append(video)
    return written
