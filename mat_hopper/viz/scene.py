"""The render scene: a hopper's MuJoCo model dressed for pictures, a camera,
and an off-screen OpenGL context (no display).

- :func:`choose_backend`: OSMesa (software, Debian package ``libosmesa6``)
  by default, EGL (GPU) when ``MUJOCO_GL=egl`` is set or OSMesa is missing;
  :class:`RenderBackendError` names both libraries when neither is found;
- :func:`render_spec`: the model of a design with its segments coloured by
  density (:func:`density_color`: viridis over log density, 0.9 to 20
  g/cm^3) and the behaviour's desired path as a dotted line on the terrain;
- :class:`Camera`, :class:`OffscreenRenderer`: frames of joint positions.

What is made of them (stills, gait tiles, videos, files) is in
:mod:`mat_hopper.viz.render`, which re-exports these names.
"""

from __future__ import annotations

import ctypes.util
import math
import os
from dataclasses import dataclass

import mujoco
import numpy as np

from ..core import reference as ref
from ..core.behaviours import Behaviour
from ..core.materials import DEFAULT_CONVENTION, LegDesign
from ..core.model import build_spec

DENSITY_RANGE_G_CM3 = (0.9, 20.0)  # colour scale: the optimizer's density bounds


class RenderBackendError(RuntimeError):
    """No usable off-screen OpenGL library (OSMesa or EGL)."""


GL_LIBS = {"osmesa": ("OSMesa", "libosmesa6"), "egl": ("EGL", "libegl1")}


def choose_backend(env=None, find_library=ctypes.util.find_library) -> str:
    """The off-screen backend to use: ``osmesa`` or ``egl``.

    $MUJOCO_GL decides when it names one of them (then there is no
    fallback), else $PYOPENGL_PLATFORM when it does; otherwise OSMesa if its
    library is there, else EGL (MUJOCO_GL=glfw, an on-screen window, is not
    used for off-screen work). Raises RenderBackendError naming the missing
    libraries.

    Args:
        env: the environment read (a mapping of variable names to values);
            None: ``os.environ``.
        find_library: the library lookup, called with ``"OSMesa"`` or
            ``"EGL"`` and returning None when absent (default
            ``ctypes.util.find_library``; tests pass their own).

    Returns:
        ``"osmesa"`` or ``"egl"``.

    Raises:
        RenderBackendError: the asked backend's library is missing, or (none
            asked) neither library is found.
    """
    env = os.environ if env is None else env
    asked = env.get("MUJOCO_GL", "").strip().lower()
    if asked not in GL_LIBS:
        asked = env.get("PYOPENGL_PLATFORM", "").strip().lower()
    if asked in GL_LIBS:
        lib, pkg = GL_LIBS[asked]
        if find_library(lib) is None:
            raise RenderBackendError(
                f"MUJOCO_GL={asked} but lib{lib} was not found "
                f"(Debian package {pkg}; scripts/setup.sh installs it as root)"
            )
        return asked
    for name in ("osmesa", "egl"):
        if find_library(GL_LIBS[name][0]) is not None:
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
    """RGBA of a density (g/cm^3) on the viridis scale over log density.

    Args:
        density_g_cm3: the density, g/cm^3 (> 0); values outside
            :data:`DENSITY_RANGE_G_CM3` take the scale's end colours.

    Returns:
        (4,) float array, RGBA in [0, 1].

    Raises:
        ValueError: a density <= 0 (``math.log``).
    """
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
    Joints are unchanged, so recorded qpos replays on it.

    Args:
        design: the :class:`~mat_hopper.core.materials.LegDesign` (not a name).
        behaviour: the :class:`~mat_hopper.core.behaviours.Behaviour`: its ramp
            grade (None: flat) and its desired path.
        convention: the stiffness convention of the model (as the rollout's,
            so its qpos fits).
        path_until_s: the path is marked from 0 to this simulated time, s:
            markers 5 cm of path apart, or 0.5 s apart where that is longer
            (one marker, at the start, for a path that does not move).
        width: frame width, pixels; the off-screen buffer is at least 640.
        height: frame height, pixels; the off-screen buffer is at least 480.

    Returns:
        The uncompiled ``mujoco.MjSpec`` (call ``compile()``).

    Raises:
        ValueError: a design that is not a LegDesign or an unknown convention
            (:func:`mat_hopper.core.model.build_spec`).
    """
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
    _add_path_markers(spec, behaviour, path_until_s)
    return spec


def _add_path_markers(spec: mujoco.MjSpec, behaviour: Behaviour, path_until_s: float) -> None:
    """Mark `behaviour`'s desired path on `spec` from 0 to `path_until_s`
    (render_spec's Args)."""
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
            lib, pkg = GL_LIBS[self.backend]
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
