"""Small helpers for the executable book (``notebooks/``).

The book's chapters are notebooks of narrative over library calls; what a
chapter computes that is not a result of its own module lives here, with
tests (``tests/test_book.py``):

- where things are: :func:`repo_root` (walks up to the ``pyproject.toml``
  of mat-hopper, so a notebook runs from its own folder, the repository
  root or anywhere below it), :func:`setup` (one call at the top of every
  chapter: root, profile, cache folder, figure format);
- the profile of the build: ``MAT_HOPPER_PROFILE`` (``paper`` or
  ``quick``) chooses it for the whole book, :func:`profile_table` sets it
  beside the paper's protocol;
- small tables and figures of the early chapters: the designs
  (:func:`designs_figure`), porosity of the density sweeps
  (:func:`sweep_porosity_table`), masses from densities
  (:func:`mass_table`), the two stiffness conventions and their stable
  time steps (:func:`stiffness_table`, :func:`convention_stability`,
  :func:`convention_figure`), one rollout's controller signals
  (:func:`controller_figure`);
- the results chapters: :func:`run_experiments` (the reproduction, cached
  under ``results/``), percent changes against a baseline
  (:func:`pct_change_table`) and the paper's claims beside ours, chapter
  by chapter (:func:`chapter_claims`).

Units: densities g/cm^3, moduli GPa, stiffness N/m, masses kg, times s.
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from . import reference as ref
from .experiments.paper import PROFILE_ENV, PROFILES, Profile, get_profile
from .materials import CONVENTIONS, LegDesign, material, paper_designs, spring_stiffness
from .experiments.runner import CACHE_ENV, DEFAULT_CACHE_DIR

PROJECT_NAME = "mat-hopper"


# ---------------------------------------------------------------------------
# where things are


def _is_root(folder: Path) -> bool:
    f = folder / "pyproject.toml"
    if not f.is_file():
        return False
    try:
        text = f.read_text(encoding="utf-8")
    except OSError:
        return False
    return f'name = "{PROJECT_NAME}"' in text


def repo_root(start: str | os.PathLike | None = None) -> Path:
    """The repository root: the nearest folder at or above `start` (default
    the current folder) whose pyproject.toml names mat-hopper; failing
    that, the one above this package's source (an editable install)."""
    here = Path(start if start is not None else os.getcwd()).resolve()
    for folder in (here, *here.parents):
        if _is_root(folder):
            return folder
    pkg = Path(__file__).resolve().parent
    for folder in pkg.parents:
        if _is_root(folder):
            return folder
    raise ValueError(f"no mat-hopper repository (pyproject.toml naming {PROJECT_NAME}) at or above {here} "
                     f"nor above {pkg}")


@dataclass(frozen=True)
class Book:
    """What a chapter needs to know: the repository root, the profile of
    the build, the result cache and the reproduction's output folder."""

    root: Path
    profile: Profile
    cache_dir: Path
    out_dir: Path

    def describe(self) -> str:
        p = self.profile
        return (f"profile {p.name}: {p.duration_s:g} s runs at dt = {p.timestep_s:g} s,\n"
                f"hop cycles after {p.transient_s:g} s scored, stiffness convention {p.convention}")


def setup(profile: str | Profile | None = None, *, chdir: bool = True, figure_format: str = "retina") -> Book:
    """Prepare a chapter: find the repository root (and make it the current
    folder, so relative paths are the repository's), pick the profile
    (argument, else $MAT_HOPPER_PROFILE, else paper), point the result
    cache at ``<root>/results/cache`` unless $MAT_HOPPER_CACHE says
    otherwise, and, inside IPython, show matplotlib figures inline as PNG
    (``retina``: twice the pixels) or SVG."""
    root = repo_root()
    prof = get_profile(profile)
    cache = Path(os.environ.get(CACHE_ENV) or root / DEFAULT_CACHE_DIR)
    if not cache.is_absolute():
        cache = root / cache
    os.environ[CACHE_ENV] = str(cache)
    if chdir:
        os.chdir(root)
    _inline_figures(figure_format)
    return Book(root, prof, cache, root / "results" / prof.name)


def _inline_figures(fmt: str) -> None:
    if fmt not in ("png", "retina", "svg"):
        raise ValueError(f"figure_format must be png, retina or svg, got {fmt!r}")
    try:
        from IPython import get_ipython
    except ImportError:        # pragma: no cover (IPython is a dependency of the book only)
        return
    if get_ipython() is None:
        return
    import warnings
    with warnings.catch_warnings():     # tqdm.auto warns once, on import, when ipywidgets is missing;
        warnings.simplefilter("ignore")  # the book shows no progress bars (progress=False everywhere)
        import tqdm.auto  # noqa: F401
    from matplotlib_inline.backend_inline import set_matplotlib_formats
    set_matplotlib_formats(fmt)


def show(frame: pd.DataFrame, formats: dict | None = None, *, index: bool = False, na_rep: str = "–",
         precision: int = 4, decimals: int | None = None, pattern: str | None = None):
    """A table for the page: pandas Styler with floats to `precision`
    significant digits, or to `decimals` places when given (``formats``:
    column -> format string or callable, e.g. ``{"porosity": "{:+.0%}"}``;
    `pattern`: one format string for every float, e.g. ``"{:+.0f} %"``),
    missing values as `na_rep`, and the row index hidden unless `index`."""
    def number(v):
        if isinstance(v, (bool, np.bool_)):
            return str(v)
        if isinstance(v, (int, np.integer)):
            return f"{v:d}"
        if isinstance(v, (float, np.floating)):
            if not np.isfinite(v):
                return na_rep
            if pattern is not None:
                return pattern.format(v)
            return f"{v:.{decimals}f}" if decimals is not None else f"{v:.{precision}g}"
        return str(v)
    st = frame.style.format(number, na_rep=na_rep)
    if formats:
        st = st.format({k: v for k, v in formats.items() if k in frame.columns}, na_rep=na_rep)
    return st if index else st.hide(axis="index")


BUILD_FLAGS = ("-W", "-n", "--keep-going")   # warnings (a failed cell among them) fail the build


def build_command(source: str | os.PathLike | None = None, *, path_output: str | os.PathLike | None = None,
                  toc: str | os.PathLike | None = None) -> list[str]:
    """The command line that builds the book (run it with
    $MAT_HOPPER_PROFILE set): the jupyter-book beside this interpreter (the
    venv's, so notebooks run on the venv's Python), warnings as errors,
    nitpicky, keep going to report every problem, then fail. The HTML goes
    to ``<path_output or source>/_build/html``."""
    import shutil
    import sys
    exe = Path(sys.executable).parent / "jupyter-book"
    if not exe.exists():
        found = shutil.which("jupyter-book")
        if found is None:
            raise ValueError("jupyter-book is not installed beside this Python nor on PATH")
        exe = Path(found)
    cmd = [str(exe), "build", str(source if source is not None else repo_root()), *BUILD_FLAGS]
    if path_output is not None:
        cmd += ["--path-output", str(path_output)]
    if toc is not None:
        cmd += ["--toc", str(toc)]
    return cmd


# ---------------------------------------------------------------------------
# the profile


_PROFILE_FIELDS = (
    ("duration_s", "run length (s of simulated time)"),
    ("transient_s", "transient, hop cycles before it not scored (s)"),
    ("timestep_s", "physics time step (s)"),
    ("record_rate_hz", "recorded samples per simulated second (Hz)"),
    ("convention", "modulus-to-stiffness convention"),
    ("axial_timestep_s", "time step of runs under the axial convention (s)"),
    ("stability_grid_size", "stable-time-step map: designs per axis"),
    ("stability_duration_s", "stable-time-step map: static hopping per try (s)"),
    ("book_replicates", "perturbed replicates per design, hopping in place (chapter 6)"),
)


def profile_table(profile: str | Profile | None = None) -> pd.DataFrame:
    """The profile's settings beside the paper's protocol (the ``paper``
    profile): columns setting, meaning, this build, paper."""
    prof = get_profile(profile)
    paper = PROFILES["paper"]
    rows = [{"setting": f, "meaning": m, "this build": getattr(prof, f), "paper": getattr(paper, f)}
            for f, m in _PROFILE_FIELDS]
    return pd.DataFrame(rows)


def environment_table() -> pd.DataFrame:
    """Versions that change results (mat-hopper, MuJoCo), the interpreter
    running this (relative to the repository when inside it: the book's
    kernel is the venv's Python) and the profile variable as set, one row
    each (columns item, value)."""
    import sys

    from .experiments.runner import versions
    v = versions()
    exe = Path(sys.executable)
    try:
        exe_text = str(exe.relative_to(repo_root()))
    except ValueError:
        exe_text = str(exe)
    rows = [("mat-hopper", v["mat_hopper"]), ("MuJoCo", v["mujoco"]),
            ("Python", f"{sys.version.split()[0]} ({exe_text})"),
            (f"${PROFILE_ENV}", os.environ.get(PROFILE_ENV) or "(unset: paper)")]
    return pd.DataFrame(rows, columns=["item", "value"])


# ---------------------------------------------------------------------------
# designs and materials


def design_table(designs: dict[str, LegDesign] | None = None) -> pd.DataFrame:
    """One row per design and segment (1 nearest the base): design,
    segment, material, density_g_cm3, modulus_gpa (nan: rigid)."""
    designs = paper_designs() if designs is None else designs
    rows = []
    for name, d in designs.items():
        for i, m in enumerate(d.segments, start=1):
            rows.append({"design": name, "segment": i, "material": m.name, "density_g_cm3": m.density_g_cm3,
                         "modulus_gpa": np.nan if m.modulus_gpa is None else m.modulus_gpa})
    return pd.DataFrame(rows)


def designs_figure(designs: dict[str, LegDesign] | None = None):
    """The legs side by side: one column of segments per design (segment 1
    at the top, nearest the base), coloured by density (left panel) and by
    modulus (right panel, grey: rigid), both on log colour scales."""
    from matplotlib import rc_context
    from matplotlib.colors import LogNorm
    from matplotlib.figure import Figure

    from .viz.figures import STYLE, design_label
    t = design_table(designs)
    names = list(dict.fromkeys(t["design"]))
    n_seg = int(t["segment"].max())
    with rc_context({**STYLE, "axes.grid": False}):
        fig = Figure(figsize=(9.0, 3.0), layout="constrained")
        axes = fig.subplots(1, 2)
        for ax, col, label, cmap in ((axes[0], "density_g_cm3", "Density (g/cm³)", "cividis"),
                                     (axes[1], "modulus_gpa", "Modulus (GPa)", "viridis")):
            grid = np.full((n_seg, len(names)), np.nan)
            for r in t.itertuples():
                grid[r.segment - 1, names.index(r.design)] = getattr(r, col)
            vals = grid[np.isfinite(grid)]
            norm = LogNorm(vmin=vals.min(), vmax=vals.max())
            ax.set_facecolor("#bbbbbb")
            mesh = ax.pcolormesh(np.arange(len(names) + 1), np.arange(n_seg + 1), np.ma.masked_invalid(grid),
                                 norm=norm, cmap=cmap, edgecolors="white", linewidth=1.5)
            for (i, j), v in np.ndenumerate(grid):
                txt = "rigid" if not np.isfinite(v) else f"{v:.3g}"
                light = np.isfinite(v) and norm(v) < 0.5
                ax.text(j + 0.5, i + 0.5, txt, ha="center", va="center", fontsize=8,
                        color="white" if light else "black")
            ax.set_xticks(np.arange(len(names)) + 0.5)
            ax.set_xticklabels([design_label(n) for n in names], rotation=45, ha="right")
            ax.set_yticks(np.arange(n_seg) + 0.5)
            ax.set_yticklabels([f"segment {i}" for i in range(1, n_seg + 1)])
            ax.invert_yaxis()
            ax.set_title(label + ", base at the top, foot at the bottom")
            cb = fig.colorbar(mesh, ax=ax, pad=0.01, fraction=0.05)
            cb.ax.minorticks_off()
            cb.set_ticks([v for v in (1, 2, 5, 10, 20, 50, 100, 200, 500, 1000) if vals.min() <= v <= vals.max()])
            cb.ax.yaxis.set_major_formatter("{x:g}")
    return fig


def sweep_porosity_table() -> pd.DataFrame:
    """The density sweeps of experiment 2 read as porosity of the base
    material: for each sweep density rho_b, Phi = 1 - rho_b / rho_s with
    rho_s the base material's own density. Phi < 0 marks a density above
    the solid's: no porosity reaches it, it needs a denser material.
    Columns: base, density_g_cm3, porosity, reachable_by_porosity."""
    rows = []
    for base, sweeps in ref.SWEEPS.items():
        rho_s = ref.MONO_MATERIALS[base][0]
        for rho in sweeps["density"]:
            phi = 1.0 - rho / rho_s
            rows.append({"base": base, "density_g_cm3": float(rho), "porosity": phi,
                         "reachable_by_porosity": bool(phi >= 0)})
    return pd.DataFrame(rows)


def _capsule_volume_m3(radius_m: float, length_m: float) -> float:
    return math.pi * radius_m**2 * length_m + 4.0 / 3.0 * math.pi * radius_m**3


def mass_table(designs: dict[str, LegDesign] | None = None) -> pd.DataFrame:
    """Mass from density, per design: the capsule mass of each material
    segment (kg; two half capsules, end caps included, m = rho V) and the
    whole robot's mass as MuJoCo computes it from the compiled model (kg).
    Columns: design, densities_g_cm3, segment_masses_kg, leg_material_kg,
    total_mass_kg."""
    from .model import build_model
    designs = paper_designs() if designs is None else designs
    rows = []
    for name, d in designs.items():
        half = ref.MATERIAL_LENGTH / d.n_segments / 2.0
        v_half = _capsule_volume_m3(ref.MATERIAL_RADIUS, half)
        seg = [2.0 * v_half * m.density_kg_m3 for m in d.segments]
        rows.append({"design": name, "densities_g_cm3": "/".join(f"{x:g}" for x in d.densities_g_cm3),
                     "segment_masses_kg": "/".join(f"{x:.3f}" for x in seg), "leg_material_kg": sum(seg),
                     "total_mass_kg": build_model(d).total_mass_kg})
    return pd.DataFrame(rows)


def segment_xml(design: LegDesign | str, segment: int = 1, convention: str = "paper") -> str:
    """The MJCF lines that make one material segment of a design: its upper
    half capsule, the child body, the axial spring joint (none for a rigid
    material) and the lower half capsule, as MuJoCo writes the model."""
    from .materials import parse_design
    from .model import build_spec
    d = parse_design(design) if isinstance(design, str) else design
    if not 1 <= int(segment) <= d.n_segments:
        raise ValueError(f"segment must be in 1..{d.n_segments}, got {segment!r}")
    i = int(segment)
    keys = (f'name="seg{i}_upper"', f'<body name="seg{i}"', f'name="mat_spring_{i}"', f'name="seg{i}_lower"')
    lines = [ln for ln in build_spec(d, convention=convention).to_xml().splitlines() if any(k in ln for k in keys)]
    indent = min(len(ln) - len(ln.lstrip()) for ln in lines)
    return "\n".join(ln[indent:] for ln in lines)


def stiffness_table(names=("PVC", "Al", "Ti", "SS"), n_segments: int = ref.REFERENCE_SEGMENTS) -> pd.DataFrame:
    """Spring stiffness (N/m) of one segment under each convention, per
    catalogue material: columns material, modulus_gpa, k_paper_n_m,
    k_axial_n_m, axial_over_paper."""
    rows = []
    for n in names:
        m = material(n)
        if m.rigid:
            raise ValueError(f"material {n} is rigid: it has no spring")
        kp = spring_stiffness(m.modulus_gpa, "paper", n_segments)
        ka = spring_stiffness(m.modulus_gpa, "axial", n_segments)
        rows.append({"material": m.name, "modulus_gpa": m.modulus_gpa, "k_paper_n_m": kp, "k_axial_n_m": ka,
                     "axial_over_paper": ka / kp})
    return pd.DataFrame(rows)


def convention_tasks(names=("MD", "PVC", "Al", "Ti", "SS"), profile: str | Profile | None = None,
                     conventions=CONVENTIONS) -> list:
    """Stable-time-step measurements (runner tasks, cached) of designs
    (names as :func:`~mat_hopper.materials.parse_design` reads them, or
    LegDesigns; default the mono-materials) under each convention, with
    the profile's try
    length, tolerance and tries (no 20-step spec scan)."""
    from .stability import StabilitySpec
    prof = get_profile(profile)
    out = []
    from .materials import parse_design
    for conv in conventions:
        for n in names:
            d = parse_design(n) if isinstance(n, str) else n
            labels = {"experiment": "conventions", "profile": prof.name, "convention": conv, "design": d.name}
            out.append(StabilitySpec(d, duration_s=prof.stability_duration_s, tolerance=prof.stability_tolerance,
                                     max_iter=prof.stability_max_iter, scan=False, convention=conv,
                                     labels=labels))
    return out


def convention_stability(names=("MD", "PVC", "Al", "Ti", "SS"), profile: str | Profile | None = None,
                         conventions=CONVENTIONS, *, cache_dir=None, workers: int | None = None) -> pd.DataFrame:
    """Largest stable time step per design (see :func:`convention_tasks`)
    and convention: measured (the bracket [max_stable_timestep_s,
    unstable_timestep_s] of :mod:`mat_hopper.stability`) and estimated
    (analytic_timestep_s, 2 / w_max of the leg's spring chain;
    controller_timestep_s, the limit 2 I / c of the controller's explicit
    stance attitude damping, the same for every leg), one row each, with
    the stiffest material spring (material_spring_n_m; nan for the rigid
    MD leg)."""
    from .experiments.runner import FAILED, run_grid
    res = run_grid(convention_tasks(names, profile, conventions), cache_dir, workers=workers, progress=False,
                   desc="conventions")
    s = res.summary
    if (s["status"] == FAILED).any():
        bad = s[s["status"] == FAILED]
        raise RuntimeError("stability measurement failed: " + "; ".join(
            f"{r.design} ({r.convention}): {r.error}" for r in bad.itertuples()))
    keep = ["design", "convention", "max_material_spring_n_m", "analytic_timestep_s", "controller_timestep_s",
            "max_stable_timestep_s", "unstable_timestep_s"]
    out = s[keep].rename(columns={"max_material_spring_n_m": "material_spring_n_m"})
    return out.reset_index(drop=True)


def convention_figure(table: pd.DataFrame):
    """Two panels per material, both conventions side by side: the material
    spring's stiffness (N/m) and the largest stable time step (s; bar:
    measured, with its bracket; marker: the estimate 2 / w_max), log
    scales. table: from :func:`convention_stability`."""
    from matplotlib import rc_context
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    from .viz.figures import STYLE
    need = ("design", "convention", "material_spring_n_m", "analytic_timestep_s", "max_stable_timestep_s",
            "unstable_timestep_s")
    missing = [c for c in need if c not in table.columns]
    if missing:
        raise ValueError(f"convention_figure needs columns {missing}")
    designs = list(dict.fromkeys(table["design"]))
    convs = [c for c in CONVENTIONS if c in set(table["convention"])]
    colours = {"paper": "#0173b2", "axial": "#de8f05"}
    w = 0.8 / max(len(convs), 1)
    with rc_context(STYLE):
        fig = Figure(figsize=(9.0, 3.4), layout="constrained")
        ax_k, ax_dt = fig.subplots(1, 2)
        for ci, conv in enumerate(convs):
            sub = table[table["convention"] == conv].set_index("design").reindex(designs)
            x = np.arange(len(designs)) - 0.4 + w * (ci + 0.5)
            k = sub["material_spring_n_m"].to_numpy(float)
            ok = np.isfinite(k)
            ax_k.bar(x[ok], k[ok], w * 0.9, color=colours.get(conv), label=conv)
            lo = sub["max_stable_timestep_s"].to_numpy(float)
            hi = sub["unstable_timestep_s"].to_numpy(float)
            ok = np.isfinite(lo)
            ax_dt.bar(x[ok], lo[ok], w * 0.9, color=colours.get(conv), alpha=0.85)
            both = ok & np.isfinite(hi)
            ax_dt.vlines(x[both], lo[both], hi[both], color="black", lw=1.0)
            ax_dt.plot(x, sub["analytic_timestep_s"].to_numpy(float), "D", ms=4.5, color="black",
                       markerfacecolor="white", zorder=4)
        for ax in (ax_k, ax_dt):
            ax.set_yscale("log")
            ax.set_xticks(np.arange(len(designs)))
            ax.set_xticklabels(designs)
            ax.grid(False, axis="x")
        for i, d in enumerate(designs):
            if d in table["design"].values and table.loc[table["design"] == d, "material_spring_n_m"].isna().all():
                ax_k.text(i, 0.02, "rigid:\nno spring", transform=ax_k.get_xaxis_transform(), ha="center",
                          va="bottom", fontsize=7, color="#555555")
        k_all = table["material_spring_n_m"].to_numpy(float)
        if np.isfinite(k_all).any():
            ax_k.set_ylim(np.nanmin(k_all) / 5, np.nanmax(k_all) * 2)
        dt_all = table[[c for c in ("max_stable_timestep_s", "analytic_timestep_s", "controller_timestep_s")
                        if c in table.columns]].to_numpy(float)
        if np.isfinite(dt_all).any():
            ax_dt.set_ylim(np.nanmin(dt_all) / 3, np.nanmax(dt_all) * 3)
        ax_k.set_ylabel("Material spring stiffness (N/m)")
        ax_dt.set_ylabel("Largest stable time step (s)")
        ax_dt.axhline(ref.TIMESTEP_S, color="#555555", lw=0.8, ls=":")
        ax_dt.text(1.0, ref.TIMESTEP_S, " paper's dt", transform=ax_dt.get_yaxis_transform(), va="center",
                   ha="left", fontsize=7, color="#555555")
        if "controller_timestep_s" in table.columns and np.isfinite(table["controller_timestep_s"]).any():
            ctrl = float(np.nanmin(table["controller_timestep_s"].to_numpy(float)))
            ax_dt.axhline(ctrl, color="#d55e00", lw=0.8, ls="--")
            ax_dt.text(1.0, ctrl, " controller limit", transform=ax_dt.get_yaxis_transform(), va="center",
                       ha="left", fontsize=7, color="#d55e00")
        handles = [Patch(color=colours.get(c), label=f"{c} convention") for c in convs]
        handles += [Line2D([], [], color="black", lw=1.0, label="measured bracket (stable to unstable)"),
                    Line2D([], [], ls="none", marker="D", ms=4.5, color="black", markerfacecolor="white",
                           label="estimate 2/ω_max")]
        fig.legend(handles=handles, loc="outside upper center", ncols=len(handles))
    return fig


# ---------------------------------------------------------------------------
# the hopper and its controller


_JOINT_TYPES = {0: "free", 1: "ball", 2: "slide", 3: "hinge"}


def joint_table(design: LegDesign | str = "SS", convention: str = "paper") -> pd.DataFrame:
    """Every joint of the compiled hopper, from the base down: name, type
    (slide m, hinge rad), stiffness (N/m or N m/rad), damping, range (nan:
    unlimited), the body it moves."""
    from .materials import parse_design
    from .model import build_model
    d = parse_design(design) if isinstance(design, str) else design
    m = build_model(d, convention=convention).model
    rows = []
    for j in range(m.njnt):
        jt = m.joint(j)
        limited = bool(m.jnt_limited[j])
        lo, hi = (float(m.jnt_range[j, 0]), float(m.jnt_range[j, 1])) if limited else (np.nan, np.nan)
        rows.append({"joint": jt.name, "type": _JOINT_TYPES.get(int(m.jnt_type[j]), str(m.jnt_type[j])),
                     "body": m.body(int(m.jnt_bodyid[j])).name, "stiffness": float(m.jnt_stiffness[j]),
                     "damping": float(m.dof_damping[m.jnt_dofadr[j]]), "range_low": lo, "range_high": hi})
    return pd.DataFrame(rows)


def gains_table(settings=None) -> pd.DataFrame:
    """The controller's settings (defaults: the reference hopper's), one
    row each: setting, value (units in the names: _s, _n, _m, _m_s; hip
    gains per rad before the 600:1 gear)."""
    from dataclasses import asdict

    from .control import ControllerSettings
    settings = ControllerSettings() if settings is None else settings
    return pd.DataFrame([{"setting": k, "value": v} for k, v in asdict(settings).items()])


# ---------------------------------------------------------------------------
# one rollout, up close


def controller_figure(rollout, window_s: tuple[float, float] | None = None):
    """The controller at work in one rollout: left, the whole run (hop
    apex heights against the 1 m target, the adaptive thrust setting F,
    tracking error); right, a short window (default: 1.5 s after the
    transient) with stance shaded: base height, thrust force on the foot
    spring, hip pitch angle against its target, base x against the
    desired x. Times are simulated seconds."""
    from matplotlib import rc_context
    from matplotlib.figure import Figure

    from .viz.figures import STYLE
    from .sim import C
    d = rollout.data
    if len(d) < 2:
        raise ValueError("controller_figure: the rollout recorded fewer than 2 samples")
    t = d[:, C["t"]]
    if window_s is None:
        t0 = min(rollout.settings.transient_s, max(float(t[-1]) - 1.5, 0.0))
        window_s = (t0, t0 + 1.5)
    w0, w1 = float(window_s[0]), float(window_s[1])
    if not w1 > w0:
        raise ValueError(f"window_s must be (start, end) with end > start s, got {window_s!r}")
    sel = (t >= w0) & (t <= w1)
    err = np.hypot(d[:, C["x"]] - d[:, C["x_des"]], d[:, C["y"]] - d[:, C["y_des"]])
    from .control import TOUCHDOWN
    ev = rollout.events[rollout.events[:, 1] == TOUCHDOWN]
    apex_t, apex_h = ev[:, 0], ev[:, 2]        # the controller's hop height, logged at each touchdown
    ok = np.isfinite(apex_h)
    stance = d[:, C["phase"]] > 0.5
    transient = rollout.settings.transient_s
    with rc_context(STYLE):
        fig = Figure(figsize=(10.0, 7.0), layout="constrained")
        axes = fig.subplots(4, 2, sharex="col")
        # left: whole run
        a = axes[0, 0]
        a.plot(apex_t[ok], apex_h[ok], ".", ms=3, color="#0173b2")
        a.axhline(ref.HOP_HEIGHT_TARGET, color="black", lw=0.8, ls="--")
        a.set_ylabel("Hop apex (m)")
        a.set_title(f"{rollout.design.name}, {rollout.behaviour.name} hopping: the whole run")
        axes[1, 0].plot(t, d[:, C["thrust_setting"]], color="#d55e00", lw=1.0)
        axes[1, 0].set_ylabel("Thrust setting F (N)")
        axes[2, 0].plot(t, np.degrees(d[:, C["hip_y"]]), color="#029e73", lw=0.6)
        axes[2, 0].set_ylabel("Hip pitch (deg)")
        axes[3, 0].plot(t, err * 1e3, color="#cc78bc", lw=0.8)
        axes[3, 0].set_ylabel("Tracking error (mm)")
        axes[3, 0].set_xlabel("Simulated time (s)")
        for a in axes[:, 0]:
            if transient > 0:
                a.axvspan(0, transient, color="black", alpha=0.06, lw=0)
            a.axvspan(w0, w1, color="#de8f05", alpha=0.25, lw=0)
        # right: the window
        tw = t[sel]
        axes[0, 1].plot(tw, d[sel, C["z"]], color="#0173b2", lw=1.2, label="base z")
        axes[0, 1].axhline(ref.HOP_HEIGHT_TARGET, color="black", lw=0.8, ls="--", label="target apex")
        axes[0, 1].set_ylabel("Base height (m)")
        axes[0, 1].set_title(f"{w1 - w0:g} s up close (stance shaded)")
        axes[0, 1].legend(loc="lower right")
        axes[1, 1].plot(tw, d[sel, C["force_thrust"]], color="#d55e00", lw=1.2)
        axes[1, 1].set_ylabel("Thrust force (N)")
        axes[2, 1].plot(tw, np.degrees(d[sel, C["hip_y"]]), color="#029e73", lw=1.2, label="angle")
        axes[2, 1].plot(tw, np.degrees(d[sel, C["hip_y_target"]]), color="black", lw=0.9, ls="--",
                        label="flight target")
        axes[2, 1].set_ylabel("Hip pitch (deg)")
        axes[2, 1].legend(loc="lower right")
        axes[3, 1].plot(tw, d[sel, C["x"]], color="#cc78bc", lw=1.2, label="base x")
        axes[3, 1].plot(tw, d[sel, C["x_des"]], color="black", lw=0.9, ls="--", label="desired x")
        axes[3, 1].set_ylabel("x (m)")
        axes[3, 1].set_xlabel("Simulated time (s)")
        axes[3, 1].legend(loc="lower right")
        st = stance[sel]
        edges = np.flatnonzero(np.diff(np.concatenate([[0], st.astype(int), [0]])))
        for a in axes[:, 1]:
            for s0, s1 in zip(edges[::2], edges[1::2]):
                a.axvspan(tw[s0], tw[min(s1, len(tw) - 1)], color="black", alpha=0.08, lw=0)
            a.set_xlim(w0, w1)
    return fig


# ---------------------------------------------------------------------------
# the results chapters


def run_experiments(book: Book | None, experiments: str, *, replicates: int = 0, workers: int | None = None,
                    quiet: bool = False) -> dict[str, pd.DataFrame]:
    """Run (or load from the cache) experiments ('1', '2', '3',
    'stability', comma-separated) under the book's profile with
    :func:`mat_hopper.experiments.reproduce.reproduce`, which also writes their
    tables to ``results/<profile>/``. Returns the tables by name
    (``exp1_hops``, ``exp1_runs``, ..., ``stability``,
    ``stability_agreement``). A task that raised (not a diverged run: that
    is a result) raises RuntimeError. Prints one line per experiment (runs
    computed now / loaded from the cache) unless quiet."""
    from .experiments.reproduce import reproduce
    book = setup(chdir=False, figure_format="retina") if book is None else book
    rep = reproduce(book.profile, experiments, str(book.out_dir), workers=workers, replicates=replicates,
                    cache_dir=str(book.cache_dir), progress=False, figures=False, log=lambda *a, **k: None)
    failed = {k: v for k, v in rep.failed.items() if v}
    if failed:
        raise RuntimeError(f"tasks failed in {failed}; see the error column of the runs tables in {book.out_dir}")
    if not quiet:
        for name, n in rep.computed.items():
            runs = rep.tables.get(f"{name}_runs", rep.tables.get(name))
            total = len(runs) if runs is not None else n
            print(f"{name} ({book.profile.name} profile): {total} tasks, {n} computed now, "
                  f"the rest loaded from {os.path.relpath(book.cache_dir, book.root)}/")
    return rep.tables


def in_place_replicates(book: Book, n: int | None = None, *, behaviour: str = "static",
                        workers: int | None = None) -> pd.DataFrame:
    """Experiment 1's five legs hopping in place (or on `behaviour`), the
    unperturbed run and n perturbed replicates each (seeds 0..n-1,
    :meth:`~mat_hopper.perturbations.Perturbation.replicate`; n from the
    profile's ``book_replicates`` by default), run or loaded through the
    result cache. Returns the per-hop table (column ``replicate``, -1 for
    the unperturbed run), for :func:`mat_hopper.analysis.stats.compare_replicates`."""
    from dataclasses import replace

    from .experiments.paper import experiment_1
    from .experiments.runner import run_grid
    n = book.profile.book_replicates if n is None else n
    exp = replace(experiment_1(), behaviours=(behaviour,))
    res = run_grid(exp.tasks(book.profile, n), book.cache_dir, workers=workers, progress=False)
    if res.n_failed:
        raise RuntimeError(f"{res.n_failed} replicate run(s) failed: {res.summary['error'].dropna().unique()[:3]}")
    return res.tables


def replicate_table(comparison: pd.DataFrame, metrics=("tracking_error_m", "power_w")) -> pd.DataFrame:
    """A compare_replicates table for reading: one row per design and
    metric, percent change of the mean with its 95 % bootstrap interval,
    the Holm-adjusted p and a star where p < 0.05."""
    c = comparison[comparison["metric"].isin(metrics)]
    return pd.DataFrame({
        "design": c["design"], "metric": c["metric"], "n": c["n"],
        "change": [f"{p:+.0f} % [{lo:+.0f}, {hi:+.0f}]" for p, lo, hi in zip(c["pct_change"], c["ci_low"], c["ci_high"])],
        "p (Holm)": c["p_holm"].map(lambda p: f"{p:.3g}"),
        "": np.where(c["significant"], "*", ""),
    }).reset_index(drop=True)


BASELINE_FLOOR = 1e-9   # SI units: a baseline mean smaller than this is round-off, not a value


def pct_change_table(hops: pd.DataFrame, metric: str, baseline: str = "MD", *, designs=None,
                     behaviours=None, floor: float = BASELINE_FLOOR) -> pd.DataFrame:
    """Percent change of the mean of `metric` against `baseline` (same
    behaviour, unperturbed runs), designs as rows and behaviours as
    columns (from :func:`mat_hopper.analysis.stats.summary_table`). Where the
    baseline's mean is below `floor` in magnitude (SI units; e.g. the
    tracking error of hopping in place, zero up to round-off) the change
    is nan: a percentage of nothing means nothing."""
    from .analysis import stats
    from .viz.figures import order_behaviours, order_designs
    s = stats.summary_table(hops, metrics=(metric,), baseline=baseline)
    s = s.assign(pct_change_mean=s["pct_change_mean"].where(s["mean_baseline"].abs() >= floor))
    if designs is not None:
        s = s[s["design"].isin(designs)]
    if behaviours is not None:
        s = s[s["behaviour"].isin(behaviours)]
    s = s[s["design"] != baseline]
    t = s.pivot_table(index="design", columns="behaviour", values="pct_change_mean", aggfunc="first")
    t = t.reindex(index=order_designs(designs or t.index), columns=order_behaviours(behaviours or t.columns))
    t.columns.name = f"{metric}: % vs {baseline}"
    return t


def outcome_table(runs: pd.DataFrame) -> pd.DataFrame:
    """How each run ended, designs as rows and behaviours as columns: "ok,
    N hops" (N scored hop cycles), "fell" (the body ended below 0.1 m),
    "diverged at T s" (numerical blow-up, simulated time) or "failed"
    (an error; see the runs table). Unperturbed runs only."""
    from .viz.figures import order_behaviours, order_designs
    need = ("design", "behaviour", "status")
    missing = [c for c in need if c not in runs.columns]
    if missing:
        raise ValueError(f"outcome_table needs columns {missing}")
    r = runs[runs["replicate"] == -1] if "replicate" in runs.columns else runs

    def cell(row) -> str:
        st = row["status"]
        if st == "ok":
            return f"ok, {int(row['n_hops'])} hops" if "n_hops" in row and pd.notna(row["n_hops"]) else "ok"
        if st == "diverged" and pd.notna(row.get("diverged_at_s", np.nan)):
            return f"diverged at {row['diverged_at_s']:.2g} s"
        return str(st)
    t = r.assign(outcome=r.apply(cell, axis=1)).pivot_table(index="design", columns="behaviour", values="outcome",
                                                            aggfunc="first")
    t = t.reindex(index=order_designs(t.index), columns=order_behaviours(t.columns))
    t.columns.name = None
    return t


def outcome_summary(runs: pd.DataFrame) -> str:
    """One paragraph on how the (unperturbed) runs ended: how many ended
    upright, then each design and behaviour that did not, with how
    (diverged at T s, fell, failed)."""
    t = outcome_table(runs)
    cells = [(d, b, v) for d in t.index for b in t.columns if isinstance(v := t.loc[d, b], str)]
    bad = [(d, b, v) for d, b, v in cells if not v.startswith("ok")]
    one_behaviour = len(t.columns) == 1
    text = f"{len(cells) - len(bad)} of {len(cells)} runs ended upright"
    if not bad:
        return text + "."
    items = [f"{d}{'' if one_behaviour else ' ' + b}: {v}" for d, b, v in bad]
    return text + "; not: " + "; ".join(items) + "."


def metric_table(hops: pd.DataFrame, metric: str, stat: str = "mean", *, scale: float = 1.0) -> pd.DataFrame:
    """`stat` (mean or median) of `metric` over the scored hop cycles of
    the unperturbed runs, times `scale` (e.g. 1e3 for mm), designs as rows
    and behaviours as columns."""
    from .analysis import stats
    from .viz.figures import order_behaviours, order_designs
    if stat not in ("mean", "median"):
        raise ValueError(f"stat must be mean or median, got {stat!r}")
    s = stats.summary_table(hops, metrics=(metric,), baseline=None)
    t = s.pivot_table(index="design", columns="behaviour", values=stat, aggfunc="first") * scale
    t = t.reindex(index=order_designs(t.index), columns=order_behaviours(t.columns))
    t.columns.name = None
    return t


def sweep_spans(hops: pd.DataFrame, metric: str = "tracking_error_m") -> pd.DataFrame:
    """Experiment 2, one row per base material and swept property: the
    smallest and largest mean of `metric` over the sweep's points (mean
    over each point's scored hop cycles, unperturbed runs), their span,
    and the property values where they occur. Columns sweep_base,
    sweep_property, n_points, min, at_min, max, at_max, span."""
    need = ("sweep_base", "sweep_property", "density_g_cm3", "modulus_gpa", metric)
    missing = [c for c in need if c not in hops.columns]
    if missing:
        raise ValueError(f"sweep_spans needs columns {missing}")
    h = hops[hops["replicate"] == -1] if "replicate" in hops.columns else hops
    rows = []
    for (base, prop), g in h.groupby(["sweep_base", "sweep_property"], sort=False):
        col = "density_g_cm3" if prop == "density" else "modulus_gpa"
        means = g.groupby(col)[metric].mean()
        rows.append({"sweep_base": base, "sweep_property": prop, "n_points": len(means),
                     "min": means.min(), "at_min": means.idxmin(), "max": means.max(), "at_max": means.idxmax(),
                     "span": means.max() - means.min()})
    return pd.DataFrame(rows)


ORDER_PAIRS = (("rho-inc", "rho-dec"), ("PVC-Ti-SS", "SS-Ti-PVC"))


def order_effect(hops: pd.DataFrame, pairs=ORDER_PAIRS, metrics=("tracking_error_m", "power_w", "jerk_m_s3"),
                 alpha: float = 0.05) -> pd.DataFrame:
    """Does segment order matter? For each pair of designs made of the same
    segments in opposite orders: the percent change of the second's mean
    against the first's, per behaviour and metric, with the Mann-Whitney U
    test on hop cycles (unperturbed runs; Holm over each pair's
    behaviours and metrics). Columns pair, behaviour, metric, pct_change,
    p_holm, significant."""
    from .analysis import stats
    frames = []
    for first, second in pairs:
        sub = hops[hops["design"].isin([first, second])]
        if not {first, second} <= set(sub["design"]):
            raise ValueError(f"order_effect: designs {first} and {second} must both be in the table")
        if "experiment" in sub.columns:
            sub = sub.assign(experiment="+".join(sorted(set(sub["experiment"].astype(str)))))
        res = stats.compare_hops(sub, baseline=first, metrics=metrics, alpha=alpha)
        res = res[res["design"] == second].assign(pair=f"{second} vs {first}")
        frames.append(res[["pair", "behaviour", "metric", "pct_change", "p_holm", "significant"]])
    return pd.concat(frames, ignore_index=True)


def starred(table: pd.DataFrame, rows=("pair", "metric"), column: str = "behaviour", value: str = "pct_change",
            flag: str = "significant") -> pd.DataFrame:
    """A tidy comparison as a wide table for the page: `value` (a percent
    change) as "+12 %" with a star where `flag` is true, `rows` as the
    index and `column` values as columns ("–" where nan)."""
    from .viz.figures import order_behaviours

    def cell(r) -> str:
        v = r[value]
        if not np.isfinite(v):
            return "–"
        return f"{v:+.0f} %" + (" *" if bool(r[flag]) else "")
    t = table.assign(_cell=table.apply(cell, axis=1))
    out = t.pivot_table(index=list(rows), columns=column, values="_cell", aggfunc="first", sort=False)
    if column == "behaviour":
        out = out[order_behaviours(out.columns)]
    out.columns.name = None
    return out


CHAPTER_CLAIMS = {
    "mono": ("hop_height", "tracking_all_beat_md", "tracking_ss_55", "power_higher_dynamic", "power_ss_max"),
    "one_property": ("density_over_modulus", "low_modulus_tracks_worse"),
    "gradients": ("ramp_rho_inc_tracking", "ramp_rho_inc_power", "ramp_ss_tracking", "ramp_ss_power",
                  "headline_tracking", "headline_power"),
    "stability": ("timestep_materials", "timestep_trend"),
}


def _concat(tables: dict, suffix: str) -> pd.DataFrame | None:
    frames = [t for name, t in sorted(tables.items()) if name.startswith("exp") and name.endswith(suffix)
              and t is not None and len(t)]
    return pd.concat(frames, ignore_index=True) if frames else None


def claims_for(tables: dict, chapter: str | None = None, *, conventions=None,
               columns=("claim", "paper", "ours", "verdict")) -> pd.DataFrame:
    """The paper's claims beside ours (:func:`mat_hopper.analysis.claims.claims_table`)
    from a reproduction's tables (``exp*_hops``, ``exp*_runs``,
    ``stability``), for one chapter (a key of :data:`CHAPTER_CLAIMS`) or all
    (None). conventions: default those present in the tables. columns:
    which to keep (None: all)."""
    from .analysis import claims
    if chapter is not None and chapter not in CHAPTER_CLAIMS:
        raise ValueError(f"chapter must be one of {', '.join(CHAPTER_CLAIMS)} or None, got {chapter!r}")
    hops, runs, stab = _concat(tables, "_hops"), _concat(tables, "_runs"), tables.get("stability")
    if conventions is None:
        present = set()
        for t in (hops, runs, stab):
            if t is not None and "convention" in t.columns:
                present |= set(t["convention"].dropna().astype(str))
        conventions = [c for c in CONVENTIONS if c in present] or ["paper"]
    table = claims.claims_table(hops, runs, stab, conventions=tuple(conventions))
    if chapter is not None:
        ids = CHAPTER_CLAIMS[chapter]
        table = table[table["claim_id"].isin(ids)]
        table = table.assign(_o=table["claim_id"].map({c: i for i, c in enumerate(ids)})).sort_values(
            ["_o", "convention"], kind="stable").drop(columns="_o")
    table = table.reset_index(drop=True)
    return table if columns is None else table[[c for c in columns if c in table.columns]]


# ---------------------------------------------------------------------------
# whole rollouts (time series, gait tiles), cached


SERIES_PREFIX = "series-"


def _series_settings(profile: Profile, record_rate_hz: float | None):
    from dataclasses import replace
    s = profile.sim_settings()
    return s if record_rate_hz is None else replace(s, record_rate_hz=float(record_rate_hz))


def _series_path(cache_dir: Path, spec, record_qpos: bool) -> Path:
    return cache_dir / f"{SERIES_PREFIX}{spec.key()[len(spec.kind) + 1:]}{'-qpos' if record_qpos else ''}.npz"


def _series_compute(spec, record_qpos: bool) -> dict:
    from .sim import simulate
    r = simulate(spec.design, spec.behaviour, settings=spec.settings, record_qpos=record_qpos)
    out = {"data": r.data, "events": r.events, "diverged_step": np.array(r.diverged_step),
           "total_mass_kg": np.array(r.total_mass_kg), "spring_stiffness_n_m": np.array(r.spring_stiffness_n_m)}
    if record_qpos:
        out["qpos"] = r.qpos
    return out


def _series_store(path: Path, arrays: dict) -> None:
    import tempfile
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=".tmp-", suffix=".npz")
    try:
        with os.fdopen(fd, "wb") as f:
            np.savez_compressed(f, **arrays)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def rollouts(designs, behaviours, profile: str | Profile | None = None, *, record_rate_hz: float | None = None,
             record_qpos: bool = False, cache_dir=None, workers: int | None = None) -> list:
    """Whole rollouts (:class:`~mat_hopper.sim.Rollout`) of every design
    (names or LegDesigns) on every behaviour under the profile's settings,
    for time series and gait tiles. record_rate_hz: samples per simulated
    second (default the profile's); record_qpos: keep joint positions (for
    rendering). Each rollout is cached as one compressed .npz in the result
    cache (``series-<key>.npz``, the runner's key of the same run), written
    atomically; missing ones run in parallel (all cores by default).
    Returned in design-major order."""
    from concurrent.futures import ProcessPoolExecutor
    import multiprocessing

    from .behaviours import behaviour as get_behaviour
    from .materials import parse_design
    from .experiments.runner import RunSpec, check_workers, default_workers
    from .sim import Rollout
    prof = get_profile(profile)
    settings = _series_settings(prof, record_rate_hz)
    cache = Path(cache_dir or os.environ.get(CACHE_ENV) or DEFAULT_CACHE_DIR).resolve()
    specs = [RunSpec(parse_design(d) if isinstance(d, str) else d,
                     get_behaviour(bh) if isinstance(bh, str) else bh, settings)
             for d in designs for bh in behaviours]
    if not specs:
        raise ValueError("rollouts: give at least one design and one behaviour")
    paths = [_series_path(cache, s, record_qpos) for s in specs]
    todo = [i for i, p in enumerate(paths) if not p.is_file()]
    n = min(len(todo), check_workers(workers) or default_workers())
    if n > 1:
        method = "forkserver" if "forkserver" in multiprocessing.get_all_start_methods() else "spawn"
        with ProcessPoolExecutor(n, mp_context=multiprocessing.get_context(method)) as pool:
            futures = {i: pool.submit(_series_compute, specs[i], record_qpos) for i in todo}
            for i, fut in futures.items():
                _series_store(paths[i], fut.result())
    else:
        for i in todo:
            _series_store(paths[i], _series_compute(specs[i], record_qpos))
    out = []
    for s, p in zip(specs, paths):
        with np.load(p) as z:
            out.append(Rollout(s.design, s.behaviour, s.settings, z["data"], z["events"], int(z["diverged_step"]),
                               float(z["total_mass_kg"]), tuple(z["spring_stiffness_n_m"].tolist()),
                               z["qpos"] if record_qpos else None))
    return out


# ---------------------------------------------------------------------------
# the optimizer chapter


STUDY_TRIALS = {"paper": 24, "quick": 12}   # trials of the book's own study, per profile
STUDY_BEHAVIOURS = ("ramp",)


def book_study(book: Book, *, trials: int | None = None, behaviours=STUDY_BEHAVIOURS, seed: int = 0) -> dict:
    """Run (or resume, or just load) the book's design study with
    :func:`mat_hopper.optimize._study.run_study`: continuous density and modulus
    per segment (3 segments), tracking error and hip power on `behaviours`
    under the optimizer's profile of the book's name, one worker process
    (so a fresh study is exactly reproducible), `trials` trials (default
    :data:`STUDY_TRIALS` of the profile). Storage: ``studies/<name>.db``;
    the name carries a digest of the settings, so changed settings start a
    new study instead of clashing with an old one. Then
    :func:`mat_hopper.optimize.report.write_report` into
    ``results/<profile>/study/``. Returns the report dict (``trials``,
    ``pareto``, ``baselines``, ``hypervolume``, ``importances``,
    ``paths``) plus ``name``, ``url`` and ``config``."""
    import hashlib
    import json

    from .optimize._study import RunOptions, StudyConfig, run_study
    from .optimize._objective import Objective
    from .optimize.report import write_report
    from .optimize._space import SearchSpace
    n = STUDY_TRIALS.get(book.profile.name, STUDY_TRIALS["quick"]) if trials is None else int(trials)
    objective = Objective(behaviours=tuple(behaviours), profile=book.profile)
    probe = StudyConfig("probe", SearchSpace(), objective)
    digest = hashlib.sha256(json.dumps(probe.key(), sort_keys=True).encode()).hexdigest()[:8]
    config = StudyConfig(f"book-{'-'.join(objective.behaviours)}-{book.profile.name}-{digest}", SearchSpace(),
                         objective)
    options = RunOptions(trials=n, workers=1, seed=seed, progress=False, studies_dir=str(book.root / "studies"))
    run_study(config, options)
    url = options.storage_url(config.name)
    report = write_report(config.name, url, str(book.out_dir / "study"))
    report.update(name=config.name, url=url, config=config)
    return report


def front_table(front: pd.DataFrame) -> pd.DataFrame:
    """A Pareto table (:func:`mat_hopper.optimize.report.pareto_frame`) for
    the page: trial, the paper's design it is (if any), tracking error
    (mm), hip power (mW), hop height (m) and the percent changes against
    the baselines, with short column names."""
    out = pd.DataFrame({"trial": front["trial"].astype(int),
                        "paper design": front.get("paper_design", pd.Series([""] * len(front))).fillna(""),
                        "tracking error (mm)": front["tracking_error_m"] * 1e3,
                        "hip power (mW)": front["power_w"] * 1e3,
                        "hop height (m)": front["hop_height_m"]})
    for col in front.columns:
        m = re.fullmatch(r"(tracking_error|power)_vs_(.+)_pct", col)
        if m:
            what = "tracking" if m.group(1) == "tracking_error" else "power"
            out[f"{what} vs {m.group(2)} (%)"] = front[col]
    return out.reset_index(drop=True)


def front_designs(front: pd.DataFrame, k: int | None = None, *, skip_paper: bool = True) -> dict[str, LegDesign]:
    """The designs of a Pareto table (``seg{i}_rho_g_cm3``,
    ``seg{i}_e_gpa`` columns; at most `k`, by tracking error) as
    {"#<trial>": LegDesign}, for :func:`designs_figure`; the paper's own
    designs (a non-empty ``paper_design``) are left out unless
    `skip_paper` is false."""
    rows = front.sort_values("tracking_error_m") if "tracking_error_m" in front.columns else front
    if skip_paper and "paper_design" in rows.columns:
        rows = rows[rows["paper_design"].fillna("").astype(str) == ""]
    if k is not None:
        rows = rows.head(int(k))
    out = {}
    for r in rows.to_dict("records"):
        i, dens, mods = 1, [], []
        while f"seg{i}_rho_g_cm3" in r and pd.notna(r[f"seg{i}_rho_g_cm3"]):
            dens.append(float(r[f"seg{i}_rho_g_cm3"]))
            e = r.get(f"seg{i}_e_gpa")
            mods.append(None if e is None or pd.isna(e) else float(e))
            i += 1
        if not dens:
            raise ValueError("front_designs: the table has no seg1_rho_g_cm3 column")
        name = f"#{int(r['trial'])}" if "trial" in r else f"design {len(out) + 1}"
        out[name] = LegDesign.from_properties(dens, mods, name=name)
    return out


# ---------------------------------------------------------------------------
# the reproduction report: the authors' defects, measured where we can


CLOCK_FACTORS = (1.0, 1.5, 2.0)


def clock_drift(book: Book, designs=("MD", "SS"), factors=CLOCK_FACTORS, behaviour: str = "forward", *,
                workers: int | None = None) -> pd.DataFrame:
    """What the authors' wall-clock desired path does. Their loop sleeps to
    stay in real time, so on a machine that simulates r times slower than
    real time the desired path advances r times faster in simulated time.
    We emulate that by commanding r times the paper's speed (r = 1: the
    paper's protocol, our default) under the book's profile, duration and
    transient unchanged. Runs through the runner (cached). One row per
    design and factor: clock_factor, speed_m_s, status, n_hops,
    mean_tracking_error_m, mean_power_w."""
    from .behaviours import behaviour as get_behaviour
    from .experiments.runner import FAILED, RunSpec, run_grid
    tasks = []
    for d in designs:
        design = LegDesign.mono(d) if isinstance(d, str) and d in ref.MONO_MATERIALS else d
        if isinstance(design, str):
            from .materials import parse_design
            design = parse_design(design)
        for r in factors:
            if not (isinstance(r, (int, float)) and math.isfinite(r) and r > 0):
                raise ValueError(f"clock factors must be finite numbers > 0, got {r!r}")
            beh = get_behaviour(behaviour, speed_m_s=ref.SPEED_M_S * float(r))
            labels = {"experiment": "clock", "profile": book.profile.name, "design": design.name,
                      "behaviour": behaviour, "clock_factor": float(r), "speed_m_s": beh.speed_m_s}
            tasks.append(RunSpec(design, beh, book.profile.sim_settings(), labels))
    res = run_grid(tasks, str(book.cache_dir), workers=workers, progress=False, desc="clock")
    s = res.summary
    if (s["status"] == FAILED).any():
        raise RuntimeError("clock_drift: runs failed: " + "; ".join(s.loc[s["status"] == FAILED, "error"]))
    return s[["design", "clock_factor", "speed_m_s", "status", "n_hops", "mean_tracking_error_m",
              "mean_power_w"]].reset_index(drop=True)


def jerk_by_rate(rollout, rates_hz=(1000.0, 100.0, 10.0)) -> pd.DataFrame:
    """Mean |jerk| (m/s^3) of the body's vertical motion after the
    transient, from its vertical acceleration sampled at each rate (every
    k-th recorded sample) and differentiated by finite differences, as
    :mod:`mat_hopper.metrics` does at the record rate. The authors logged
    at about 10 Hz of wall time. Columns rate_hz, mean_jerk_m_s3."""
    from .sim import C
    d = rollout.data
    t, az = d[:, C["t"]], d[:, C["az"]]
    if len(t) < 4:
        raise ValueError("jerk_by_rate: the rollout recorded fewer than 4 samples")
    dt = float(np.median(np.diff(t)))
    rows = []
    for rate in rates_hz:
        k = int(round(1.0 / (float(rate) * dt)))
        if k < 1:
            raise ValueError(f"rate {rate} Hz exceeds the record rate {1 / dt:g} Hz")
        ts, a = t[::k], az[::k]
        if len(ts) < 3:
            raise ValueError(f"rate {rate} Hz leaves fewer than 3 samples")
        jerk = np.abs(np.gradient(a, ts))
        keep = ts >= rollout.settings.transient_s
        rows.append({"rate_hz": 1.0 / (k * dt), "mean_jerk_m_s3": float(jerk[keep].mean())})
    return pd.DataFrame(rows)


def axial_check(book: Book, designs=("MD", "SS", "rho-inc"), behaviour: str = "ramp", *,
                timestep_s: float | None = None, workers: int | None = None) -> dict:
    """The paper's headline comparison under the physical (axial) stiffness
    convention. The axial springs need a smaller time step: by default the
    profile's ``axial_timestep_s`` (the step ``mat-hopper reproduce
    --conventions`` uses; chapter 3 measures the stable steps). Runs, through the
    runner (cached), every design in three settings: the paper's
    convention at the profile's step (the runs of experiments 1 and 3),
    the paper's convention at the small step (what the step alone
    changes), and the axial convention at the small step (what the
    convention changes). A rigid leg has no springs, so its small-step run
    stands for both conventions. Returns {"timestep_s", "hops" (per-hop
    table with a ``setting`` column, e.g. "paper, dt 0.0001 s",
    "axial, dt 1e-05 s"), "runs"}."""
    from dataclasses import replace

    from .behaviours import behaviour as get_behaviour
    from .materials import parse_design
    from .experiments.runner import FAILED, RunSpec, run_grid
    prof = book.profile
    legs = {d: parse_design(d) for d in designs}
    if timestep_s is None:
        timestep_s = prof.axial_timestep_s
    beh = get_behaviour(behaviour)
    base = prof.sim_settings()
    small = replace(base, timestep_s=float(timestep_s))
    axial = replace(small, convention="axial")
    name = lambda st: f"{st.convention}, dt {st.timestep_s:g} s"
    plan = [(d, st) for d in designs for st in (base, small)]
    plan += [(d, axial) for d in designs if not all(m.rigid for m in legs[d].segments)]
    tasks = []
    for d, st in plan:
        labels = {"experiment": "axial-check", "profile": prof.name, "convention": st.convention, "design": d,
                  "behaviour": beh.name, "setting": name(st), "timestep_s": st.timestep_s}
        tasks.append(RunSpec(legs[d], beh, st, labels))
    res = run_grid(tasks, str(book.cache_dir), workers=workers, progress=False, desc="axial")
    if (res.summary["status"] == FAILED).any():
        raise RuntimeError("axial_check: runs failed: " + "; ".join(res.summary.loc[res.summary["status"] == FAILED,
                                                                                    "error"]))
    hops, runs = res.tables, res.summary
    rigid = [d for d in designs if all(m.rigid for m in legs[d].segments)]
    if rigid:      # a rigid leg has no springs: its run at the small step stands for both conventions
        extra_h = hops[hops["design"].isin(rigid) & (hops["setting"] == name(small))].assign(setting=name(axial))
        extra_r = runs[runs["design"].isin(rigid) & (runs["setting"] == name(small))].assign(setting=name(axial))
        hops = pd.concat([hops, extra_h], ignore_index=True)
        runs = pd.concat([runs, extra_r], ignore_index=True)
    return {"timestep_s": float(timestep_s), "hops": hops, "runs": runs}


def setting_comparison(hops: pd.DataFrame, pairs=(("rho-inc", "MD"), ("SS", "MD"), ("rho-inc", "SS")),
                       metrics=("tracking_error_m", "power_w")) -> pd.DataFrame:
    """Percent change of the mean of each metric for each (design,
    baseline) pair, per ``setting`` of the table (e.g. from
    :func:`axial_check`): rows setting, columns "<metric>: <design> vs
    <baseline>"; nan where either is missing or the baseline's mean is
    below :data:`BASELINE_FLOOR`."""
    if "setting" not in hops.columns:
        raise ValueError("setting_comparison needs a 'setting' column")
    means = hops.groupby(["setting", "design"])[list(metrics)].mean()
    rows = {}
    for setting in dict.fromkeys(hops["setting"]):
        row = {}
        for design, baseline in pairs:
            for m in metrics:
                try:
                    a, b = means.loc[(setting, design), m], means.loc[(setting, baseline), m]
                except KeyError:
                    a, b = np.nan, np.nan
                row[f"{m}: {design} vs {baseline}"] = 100.0 * (a - b) / abs(b) if abs(b) >= BASELINE_FLOOR else np.nan
        rows[setting] = row
    out = pd.DataFrame.from_dict(rows, orient="index")
    out.index.name = "setting"
    return out


def claim_rules() -> pd.DataFrame:
    """The rule behind each claim's verdict (:data:`mat_hopper.analysis.claims.CLAIMS`):
    columns claim, rule."""
    from .analysis import claims
    return pd.DataFrame([{"claim": c.claim, "rule": c.rule} for c in claims.CLAIMS])


def power_formula_table(hops: pd.DataFrame, design: str = "SS", baseline: str = "MD") -> pd.DataFrame:
    """Percent change of `design`'s mean hip power against `baseline`'s, per
    behaviour, measured two ways: the real mechanical power of the hip
    motors (``power_w``, ours) and the authors' formula
    (``power_paper_w``). Rows: the two measures; columns: behaviours."""
    rows = {}
    for metric, label in (("power_w", "real hip power (ours)"), ("power_paper_w", "the authors' formula")):
        t = pct_change_table(hops, metric, baseline, designs=[baseline, design])
        rows[label] = t.loc[design] if design in t.index else pd.Series(dtype=float)
    out = pd.DataFrame(rows).T
    out.columns.name = f"power: {design} vs {baseline} (%)"
    return out


def defects_figure(clock: pd.DataFrame, jerk: dict, power: pd.DataFrame):
    """Three of the authors' code defects, measured: (A) tracking error
    against the wall-clock factor of the desired path (table from
    :func:`clock_drift`); (B) mean |jerk| against the sampling rate, per
    design ({design: table from :func:`jerk_by_rate`}, log-log); (C) the
    percent change of power of one design against another, real hip power
    beside the authors' formula (table from :func:`power_formula_table`)."""
    from matplotlib import rc_context
    from matplotlib.figure import Figure

    from .viz.figures import STYLE, design_colour, order_behaviours
    with rc_context(STYLE):
        fig = Figure(figsize=(11.0, 3.4), layout="constrained")
        a, b, c = fig.subplots(1, 3)
        for i, (d, g) in enumerate(clock.groupby("design", sort=False)):
            g = g.sort_values("clock_factor")
            a.plot(g["clock_factor"], g["mean_tracking_error_m"] * 1e3, "o-", color=design_colour(d, i), label=d)
        a.set_xlabel("Wall clock / simulated clock")
        a.set_ylabel("Tracking error (mm)")
        a.set_title("Desired path on the wall clock")
        a.legend()
        for i, (d, t) in enumerate(jerk.items()):
            b.plot(t["rate_hz"], t["mean_jerk_m_s3"], "o-", color=design_colour(d, i), label=d)
        b.set_xscale("log")
        b.set_yscale("log")
        b.set_xlabel("Sampling rate (Hz)")
        b.set_ylabel("Mean |jerk| (m/s³)")
        b.set_title("Jerk from sparse samples")
        b.legend()
        behs = order_behaviours(power.columns)
        x = np.arange(len(behs))
        for i, (label, row) in enumerate(power.iterrows()):
            c.bar(x - 0.2 + 0.4 * i, row[behs].to_numpy(float), 0.38, label=label,
                  color=("#0173b2", "#de8f05")[i % 2])
        c.axhline(0, color="black", lw=0.8)
        vals = power[behs].to_numpy(float)
        vals = vals[np.isfinite(vals)]
        if len(vals):               # head room for the legend above the bars
            lo, hi = min(0.0, float(vals.min())), max(0.0, float(vals.max()))
            c.set_ylim(lo - 0.05 * (hi - lo), hi + 0.45 * (hi - lo))
        c.set_xticks(x)
        c.set_xticklabels(behs)
        c.set_ylabel(power.columns.name or "% change")
        c.set_title("Power: real or the authors' formula")
        c.legend(loc="upper left")
        c.grid(False, axis="x")
        for ax, letter in zip((a, b, c), "ABC"):
            ax.text(-0.02, 1.02, letter, transform=ax.transAxes, fontsize=12, fontweight="bold", ha="right",
                    va="bottom")
    return fig
