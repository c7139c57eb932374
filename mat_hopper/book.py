"""The executable book's plumbing (``notebooks/``), and nothing else.

The chapters are notebooks of narrative over the library's public calls
(the science lives in its modules: masses in :mod:`mat_hopper.core.materials`,
tables in :mod:`mat_hopper.analysis.tables`, figures in
:mod:`mat_hopper.viz`, runs in :mod:`mat_hopper.experiments`). Here:

- :func:`repo_root`: walks up to the ``pyproject.toml`` of mat-hopper, so
  a notebook runs from its own folder, the repository root or anywhere
  below it;
- :func:`setup`: one call at the top of every chapter (root, profile from
  ``MAT_HOPPER_PROFILE``, cache folder, MuJoCo warnings to logging, figure
  format);
- :func:`show`: a table for the page;
- :func:`environment_table` and :func:`build_command`: what the book ran
  on, and how it is built.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from .experiments.cache import CACHE_ENV, DEFAULT_CACHE_DIR
from .experiments.profiles import PROFILE_ENV, Profile, resolve_profile


def _import_tqdm_auto_quietly() -> None:
    """tqdm.auto (Optuna imports it) warns once, on its first import in a
    notebook without ipywidgets ("IProgress not found"), and the warning
    lands on the page. The book shows no progress bars (progress=False
    everywhere), so this module, which every chapter imports first,
    imports it once with that warning ignored."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        import tqdm.auto  # noqa: F401


_import_tqdm_auto_quietly()

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
    that, the one above this package's source (an editable install).

    Args:
        start: the folder to search from, upwards; None (the default) for
            the current working folder.

    Returns:
        The root folder, as a resolved Path.

    Raises:
        ValueError: no folder at or above `start`, nor above this package's
            source, has a pyproject.toml naming mat-hopper.
    """
    here = Path(start if start is not None else os.getcwd()).resolve()
    for folder in (here, *here.parents):
        if _is_root(folder):
            return folder
    pkg = Path(__file__).resolve().parent
    for folder in pkg.parents:
        if _is_root(folder):
            return folder
    raise ValueError(
        f"no mat-hopper repository (pyproject.toml naming {PROJECT_NAME}) at or above {here} nor above {pkg}"
    )


@dataclass(frozen=True)
class Book:
    """What a chapter needs to know: the repository root, the profile of
    the build, the result cache and the reproduction's output folder."""

    root: Path
    profile: Profile
    cache_dir: Path
    out_dir: Path

    def downloads(self, tables: dict[str, pd.DataFrame], *, subdir: str | None = None):
        """Write each table as ``<out_dir>[/subdir]/<name>.csv`` (atomically,
        :func:`mat_hopper.util.atomic.write_csv`) and return an IPython Markdown
        object with a download link to each: MyST ``{download}`` roles, which
        the book renders (``nb_render_markdown_format: myst``) by copying
        the file into the built HTML. Names: letters, digits, ``-``, ``_``."""
        import re

        from IPython.display import Markdown

        from .util.atomic import write_csv

        if not tables:
            raise ValueError("downloads: no tables given")
        folder = self.out_dir / subdir if subdir else self.out_dir
        links = []
        for name, frame in tables.items():
            if not re.fullmatch(r"[A-Za-z0-9_-]+", str(name)):
                raise ValueError(f"downloads: table name {name!r} must be letters, digits, '-' or '_'")
            if not isinstance(frame, pd.DataFrame):
                raise ValueError(f"downloads: {name!r} is a {type(frame).__name__}, not a pandas DataFrame")
            path = folder / f"{name}.csv"
            path.parent.mkdir(parents=True, exist_ok=True)
            write_csv(frame, path)
            rel = path.relative_to(self.root).as_posix()
            links.append(f"{{download}}`{name}.csv </{rel}>` ({len(frame)} rows)")
        return Markdown(f"Result tables of this build ({self.profile.name} profile), CSV: " + "; ".join(links) + ".")

    def describe(self) -> str:
        p = self.profile
        return (
            f"profile {p.name}: {p.duration_s:g} s runs at dt = {p.timestep_s:g} s,\n"
            f"hop cycles after {p.transient_s:g} s scored, stiffness convention {p.convention}"
        )


def setup(profile: str | Profile | None = None, *, chdir: bool = True, figure_format: str = "retina") -> Book:
    """Prepare a chapter: find the repository root (and make it the current
    folder, so relative paths are the repository's), pick the profile
    (argument, else $MAT_HOPPER_PROFILE, else paper), point the result
    cache at ``<root>/results/cache`` unless $MAT_HOPPER_CACHE says
    otherwise, and, inside IPython, show matplotlib figures inline as PNG
    (``retina``: twice the pixels) or SVG.

    Args:
        profile: a profile name (``paper`` or ``quick``) or a Profile; None
            (the default) for $MAT_HOPPER_PROFILE, else ``paper``
            (:func:`mat_hopper.experiments.profiles.resolve_profile`).
        chdir: whether to make the repository root the current folder
            (default True).
        figure_format: ``png``, ``retina`` (the default) or ``svg``; used
            only inside IPython.

    Returns:
        The chapter's Book: the root, the profile, the cache folder (made
        absolute against the root, and written to $MAT_HOPPER_CACHE) and
        the output folder ``<root>/results/<profile name>``.

    Raises:
        ValueError: no repository root (:func:`repo_root`), an unknown
            profile, $MAT_HOPPER_PROFILE or $MAT_HOPPER_CACHE set but empty,
            or a `figure_format` other than png, retina or svg.
    """
    from .util.parsing import env_value

    root = repo_root()
    prof = resolve_profile(profile)
    cache = Path(env_value(CACHE_ENV, "a folder") or root / DEFAULT_CACHE_DIR)  # set but empty: an error
    if not cache.is_absolute():
        cache = root / cache
    os.environ[CACHE_ENV] = str(cache)
    if chdir:
        os.chdir(root)
    from .core.sim import route_mujoco_warnings

    route_mujoco_warnings()
    _inline_figures(figure_format)
    return Book(root, prof, cache, root / "results" / prof.name)


def _inline_figures(fmt: str) -> None:
    if fmt not in ("png", "retina", "svg"):
        raise ValueError(f"figure_format must be png, retina or svg, got {fmt!r}")
    try:
        from IPython import get_ipython
    except ImportError:  # pragma: no cover (IPython is a dependency of the book only)
        return
    if get_ipython() is None:
        return
    from matplotlib_inline.backend_inline import set_matplotlib_formats

    set_matplotlib_formats(fmt)


def show(
    frame: pd.DataFrame,
    formats: dict | None = None,
    *,
    index: bool = False,
    na_rep: str = "–",
    precision: int = 4,
    decimals: int | None = None,
    pattern: str | None = None,
):
    """A table for the page: pandas Styler with floats to `precision`
    significant digits, or to `decimals` places when given (``formats``:
    column -> format string or callable, e.g. ``{"porosity": "{:+.0%}"}``;
    `pattern`: one format string for every float, e.g. ``"{:+.0f} %"``),
    missing values as `na_rep`, and the row index hidden unless `index`.

    Args:
        frame: the table (pandas DataFrame).
        formats: {column: format string or callable}, applied over the
            default number format; columns not in `frame` are ignored. None
            (the default): no per-column formats.
        index: whether to show the row index (default False).
        na_rep: what missing and non-finite values show (default ``–``).
        precision: significant digits of floats (default 4), when neither
            `decimals` nor `pattern` is given.
        decimals: fixed decimal places of floats; None (the default) for
            `precision` significant digits.
        pattern: one format string for every finite float, taking precedence
            over `decimals` and `precision`; None (the default) for none.
            Booleans and integers are shown as they are.

    Returns:
        A pandas Styler of `frame`, its index hidden unless `index`.
    """

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


BUILD_FLAGS = ("-W", "-n", "--keep-going")  # warnings (a failed cell among them) fail the build


def build_command(
    source: str | os.PathLike | None = None,
    *,
    path_output: str | os.PathLike | None = None,
    toc: str | os.PathLike | None = None,
) -> list[str]:
    """The command line that builds the book (run it with
    $MAT_HOPPER_PROFILE set): the jupyter-book beside this interpreter (the
    venv's, so notebooks run on the venv's Python), warnings as errors,
    nitpicky, keep going to report every problem, then fail. The HTML goes
    to ``<path_output or source>/_build/html``.

    Args:
        source: the book's folder; None (the default) for :func:`repo_root`.
        path_output: passed as ``--path-output`` when given (default None:
            not passed).
        toc: the table of contents file, passed as ``--toc`` when given
            (default None: not passed).

    Returns:
        The command as a list of str: the jupyter-book executable,
        ``build``, the source, ``-W -n --keep-going``, then the optional
        ``--path-output`` and ``--toc`` arguments.

    Raises:
        ValueError: jupyter-book is neither beside this Python interpreter
            nor on PATH, or (with `source` None) no repository root.
    """
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


def environment_table(profile: str | Profile | None = None) -> pd.DataFrame:
    """Versions that change results (mat-hopper, MuJoCo), the interpreter
    running this (relative to the repository when inside it: the book's
    kernel is the venv's Python) and the build's profile, one row each
    (columns item, value).

    Args:
        profile: the build's profile or its name; None (default):
            $MAT_HOPPER_PROFILE, else ``paper``
            (:func:`mat_hopper.experiments.profiles.resolve_profile`).

    Returns:
        A pandas DataFrame of four rows (mat-hopper, MuJoCo, Python,
        ``profile ($MAT_HOPPER_PROFILE)``), columns ``item`` and ``value``
        (str); the profile's row holds its name.

    Raises:
        ValueError: as :func:`~mat_hopper.experiments.profiles.resolve_profile`.
    """
    import sys

    from .util.keys import versions

    v = versions()
    exe = Path(sys.executable)
    try:
        exe_text = str(exe.relative_to(repo_root()))
    except ValueError:
        exe_text = str(exe)
    rows = [
        ("mat-hopper", v["mat_hopper"]),
        ("MuJoCo", v["mujoco"]),
        ("Python", f"{sys.version.split()[0]} ({exe_text})"),
        (f"profile (${PROFILE_ENV})", resolve_profile(profile).name),
    ]
    return pd.DataFrame(rows, columns=["item", "value"])
