"""The executable book: its helpers (mat_hopper/book.py), its notebooks
(clean, in sync with notebooks/src), and the quick book built for real:
every chapter's page exists, holds its figures, and no cell failed."""

from __future__ import annotations

import math
import os
import re
import shutil
import subprocess
from dataclasses import replace
from pathlib import Path

import nbformat
import numpy as np
import pandas as pd
import pytest
import yaml
from synthetic_results import results

from mat_hopper import book, optimize
from mat_hopper import reference as ref
from mat_hopper.analysis import stats
from mat_hopper.analysis import tables as tab
from mat_hopper.experiments import paper, profiles, runner
from mat_hopper.experiments.profiles import PROFILES, Profile
from mat_hopper.materials import spring_stiffness
from mat_hopper.viz import chapters, maps

ROOT = Path(__file__).resolve().parent.parent
NOTEBOOKS = ROOT / "notebooks"

# Figures each chapter must show (at least), by notebook name.
MIN_FIGURES = {
    "01-introduction": 1,          # the designs
    "02-materials": 1,             # Ashby chart
    "03-modelling-material": 1,    # conventions: stiffness and stable step
    "04-hopper-controller": 2,     # the rendered model, one rollout
    "05-numerical-stability": 1,   # the stable-time-step map
    "06-mono-materials": 1,        # power, jerk, tracking error
    "07-one-property": 1,          # sweeps
    "08-gradients": 4,             # gradients, time series, gait tiles forward and ramp
    "09-optimizing-gradients": 1,  # the Pareto front
    "10-reproduction-report": 1,   # a defect measured
}


def toc_files() -> list[str]:
    toc = yaml.safe_load((ROOT / "_toc.yml").read_text())
    files = []
    for part in toc.get("parts", [{"chapters": toc.get("chapters", [])}]):
        files += [c["file"] for c in part["chapters"]]
    return files


# ---------------------------------------------------------------------------
# helpers


def test_repo_root_from_anywhere(tmp_path):
    assert book.repo_root(ROOT / "notebooks" / "src") == ROOT
    assert book.repo_root(ROOT / "mat_hopper") == ROOT
    # outside the repository: falls back to the one above the package
    assert book.repo_root(tmp_path) == ROOT
    # a pyproject.toml of another project is not ours
    (tmp_path / "pyproject.toml").write_text('[project]\nname = "other"\n')
    assert book.repo_root(tmp_path) == ROOT


def test_setup_sets_cache_and_profile(monkeypatch, tmp_path):
    monkeypatch.delenv("MAT_HOPPER_CACHE", raising=False)
    monkeypatch.setenv("MAT_HOPPER_PROFILE", "quick")
    monkeypatch.chdir(tmp_path)
    b = book.setup(chdir=False)
    assert b.profile.name == "quick" and b.root == ROOT
    assert b.cache_dir == ROOT / "results" / "cache"
    assert os.environ["MAT_HOPPER_CACHE"] == str(ROOT / "results" / "cache")
    assert b.out_dir == ROOT / "results" / "quick"
    assert os.getcwd() == str(tmp_path)
    assert "12 s runs" in b.describe()
    monkeypatch.setenv("MAT_HOPPER_PROFILE", "nope")
    with pytest.raises(ValueError, match="profile"):
        book.setup(chdir=False)
    with pytest.raises(ValueError, match="figure_format"):
        book.setup("quick", chdir=False, figure_format="jpeg")


def test_profile_table_sets_build_beside_paper():
    t = profiles.profile_table("quick").set_index("setting")
    assert t.loc["duration_s", "this build"] == PROFILES["quick"].duration_s
    assert t.loc["duration_s", "paper"] == ref.DURATION_S
    assert t.loc["stability_grid_size", "paper"] == ref.STABILITY_GRID_SIZE
    env = book.environment_table().set_index("item")["value"]
    assert env["MuJoCo"] and env["mat-hopper"]


def test_show_formats_and_hides_index():
    st = book.show(pd.DataFrame({"a": [1.23456, np.nan], "b": ["x", "y"]}), decimals=2)
    html = st.to_html()
    assert "1.23" in html and "–" in html and "1.2346" not in html
    assert "1.2 %" in book.show(pd.DataFrame({"a": [1.23]}), pattern="{:.1f} %").to_html()


def test_designs_and_porosity():
    t = tab.design_table()
    assert set(t["design"]) >= {"MD", "SS", "rho-inc", "SS-Ti-PVC"}
    inc = t[t["design"] == "rho-inc"].sort_values("segment")
    assert tuple(inc["density_g_cm3"]) == ref.GRADIENT_DENSITIES
    assert t.loc[t["design"] == "MD", "modulus_gpa"].isna().all()
    fig = maps.designs_figure()
    assert len(fig.axes) == 4          # two panels, two colour bars






def test_joint_and_gains_tables():
    j = tab.joint_table("SS").set_index("joint")
    assert np.isclose(j.loc["mat_spring_1", "stiffness"], spring_stiffness(193.0))
    assert j.loc["spring", "stiffness"] == ref.FOOT_SPRING_STIFFNESS
    assert j.loc["hip_y", "type"] == "hinge" and np.isclose(j.loc["hip_y", "range_high"], math.radians(70))
    assert "mat_spring_1" not in tab.joint_table("MD")["joint"].values


TINY = Profile("tiny", 0.6, 0.1, 1e-4, 1, 0.3, stability_tolerance=2.0, stability_max_iter=3)


def test_convention_stability_measures_both_conventions(tmp_path):
    t = paper.convention_stability(("MD", "SS"), TINY, cache_dir=tmp_path, workers=1)
    assert len(t) == 4 and set(t["convention"]) == {"paper", "axial"}
    ss = t[t["design"] == "SS"].set_index("convention")
    # the physical springs are about 20x stiffer: a smaller stable step
    assert ss.loc["axial", "material_spring_n_m"] > 10 * ss.loc["paper", "material_spring_n_m"]
    assert ss.loc["axial", "analytic_timestep_s"] < ss.loc["paper", "analytic_timestep_s"]
    assert ss.loc["axial", "max_stable_timestep_s"] < ss.loc["paper", "max_stable_timestep_s"]
    assert t.loc[t["design"] == "MD", "material_spring_n_m"].isna().all()
    fig = chapters.convention_figure(t)
    assert len(fig.axes) == 2
    again = paper.convention_stability(("MD", "SS"), TINY, cache_dir=tmp_path, workers=1)
    pd.testing.assert_frame_equal(t, again)


def test_rollouts_are_cached_bit_identical(tmp_path):
    from mat_hopper import simulate
    rs = runner.rollouts(["SS"], ["forward", "ramp"], TINY.sim_settings(), record_rate_hz=500, cache_dir=tmp_path, workers=1)
    assert [r.behaviour.name for r in rs] == ["forward", "ramp"]
    files = sorted(tmp_path.glob("rollout-*.parquet"))       # the runner's one cache
    assert len(files) == 2
    again = runner.rollouts(["SS"], ["forward", "ramp"], TINY.sim_settings(), record_rate_hz=500, cache_dir=tmp_path, workers=1)
    fresh = simulate("SS", "ramp", settings=replace(TINY.sim_settings(), record_rate_hz=500.0))
    for r in (again[1], rs[1]):
        assert np.array_equal(r.data, fresh.data)
        assert np.array_equal(r.events, fresh.events, equal_nan=True)
        assert r.diverged_step == fresh.diverged_step and r.total_mass_kg == fresh.total_mass_kg
    assert rs[1].settings.record_rate_hz == 500
    fig = chapters.controller_figure(rs[0], window_s=(0.2, 0.5))
    assert len(fig.axes) == 8
    with pytest.raises(ValueError, match="window_s"):
        chapters.controller_figure(rs[0], window_s=(0.5, 0.2))
    with pytest.raises(ValueError, match="at least one"):
        runner.rollouts([], ["ramp"], TINY.sim_settings(), cache_dir=tmp_path)


# --- results-chapter tables, on synthetic results with known answers ---------


@pytest.fixture(scope="module")
def synthetic():
    return results(n=20)


def test_pct_change_and_metric_tables(synthetic):
    hops, _ = synthetic
    exp1 = hops[hops["experiment"] == "exp1"]
    t = tab.pct_change_table(exp1, "tracking_error_m")
    assert list(t.index) == ["PVC", "Al", "Ti", "SS"]
    assert list(t.columns) == ["static", "forward", "ramp", "circle"]
    assert abs(t.loc["SS", "ramp"] - (0.028 / 0.10 - 1) * 100) < 3     # set by construction (3 % noise)
    zero = exp1.assign(tracking_error_m=np.where(exp1["design"] == "MD", 1e-17, exp1["tracking_error_m"]))
    assert tab.pct_change_table(zero, "tracking_error_m").isna().all().all()   # % of round-off: none
    vs_ss = tab.pct_change_table(hops[hops["experiment"] == "exp3"], "power_w", baseline="SS")
    assert "SS" not in vs_ss.index and abs(vs_ss.loc["rho-inc", "ramp"] - (2.23 / 2.93 - 1) * 100) < 3
    m = tab.metric_table(exp1, "hop_height_m")
    assert ((m - 1.0).abs() < 0.01).all().all()
    mm = tab.metric_table(exp1, "tracking_error_m", "median", scale=1e3)
    assert abs(mm.loc["MD", "forward"] - 100) < 5
    with pytest.raises(ValueError, match="stat"):
        tab.metric_table(exp1, "power_w", "max")


def test_outcome_table():
    runs = pd.DataFrame({"design": ["SS", "SS", "MD"], "behaviour": ["ramp", "static", "static"],
                         "replicate": [-1, -1, -1], "status": ["diverged", "ok", "fallen"],
                         "n_hops": [3, 40, 10], "diverged_at_s": [12.5, np.nan, np.nan]})
    t = tab.outcome_table(runs)
    assert list(t.index) == ["MD", "SS"] and list(t.columns) == ["static", "ramp"]
    assert t.loc["SS", "ramp"] == "diverged at 12 s"
    text = tab.outcome_summary(runs)
    assert text.startswith("1 of 3 runs ended upright; not: ")
    assert "SS ramp: diverged at 12 s" in text and "MD static: fallen" in text
    ok = runs.assign(status="ok")
    assert tab.outcome_summary(ok) == "3 of 3 runs ended upright."
    assert t.loc["SS", "static"] == "ok, 40 hops" and t.loc["MD", "static"] == "fallen"
    with pytest.raises(ValueError, match="status"):
        tab.outcome_table(runs.drop(columns="status"))


def test_sweep_spans(synthetic):
    hops, _ = synthetic
    s = tab.sweep_spans(hops[hops["experiment"] == "exp2"]).set_index(["sweep_base", "sweep_property"])
    # by construction density moves tracking error strongly, modulus little
    for base in ref.SWEEPS:
        assert s.loc[(base, "density"), "span"] > s.loc[(base, "modulus"), "span"]
    assert s.loc[("Ti", "density"), "at_max"] == min(ref.SWEEPS["Ti"]["density"])   # lightest tracks worst
    assert s.loc[("Ti", "density"), "n_points"] == len(ref.SWEEPS["Ti"]["density"])


def test_order_effect_and_starred(synthetic):
    hops, _ = synthetic
    exp3 = hops[hops["experiment"] == "exp3"]
    t = tab.order_effect(exp3)
    assert set(t["pair"]) == {"rho-dec vs rho-inc", "SS-Ti-PVC vs PVC-Ti-SS"}
    row = t[(t["pair"] == "rho-dec vs rho-inc") & (t["behaviour"] == "ramp") & (t["metric"] == "tracking_error_m")]
    assert abs(row["pct_change"].iloc[0] - (0.04 / 0.018 - 1) * 100) < 10 and bool(row["significant"].iloc[0])
    wide = tab.starred(t)
    assert list(wide.columns) == ["static", "forward", "ramp", "circle"]
    assert wide.loc[("rho-dec vs rho-inc", "tracking_error_m"), "ramp"].endswith("*")
    with pytest.raises(ValueError, match="both"):
        tab.order_effect(exp3[exp3["design"] != "rho-dec"])


def test_claims_for_chapters(synthetic):
    hops, runs = synthetic
    tables = {f"{e}_hops": hops[hops["experiment"] == e] for e in ("exp1", "exp2", "exp3")}
    tables.update({f"{e}_runs": runs[runs["experiment"] == e] for e in ("exp1", "exp2", "exp3")})
    from mat_hopper.analysis import claims
    known = {c.claim_id for c in claims.CLAIMS}
    for ids in tab.CHAPTER_CLAIMS.values():
        assert set(ids) <= known
    every = tab.claims_for(tables, None, columns=None)
    assert set(every["claim_id"]) == known
    mono = tab.claims_for(tables, "mono", columns=None)
    assert list(mono["claim_id"]) == list(tab.CHAPTER_CLAIMS["mono"])
    assert list(tab.claims_for(tables, "gradients").columns) == ["claim", "paper", "ours", "verdict"]
    ramp = mono = tab.claims_for(tables, "gradients", columns=None).set_index("claim_id")
    assert ramp.loc["ramp_rho_inc_tracking", "verdict"] == "holds"        # -82 % by construction
    with pytest.raises(ValueError, match="chapter"):
        tab.claims_for(tables, "nope")


# --- the reproduction report's measurements ------------------------------------


def _tiny_book(tmp_path, profile=TINY) -> book.Book:
    return book.Book(tmp_path, profile, tmp_path / "cache", tmp_path / "results" / profile.name)



def test_clock_drift_moves_the_path(tmp_path):
    t = paper.clock_drift(TINY, cache_dir=tmp_path, designs=("SS",), factors=(1.0, 2.0), workers=1)
    assert list(t["clock_factor"]) == [1.0, 2.0]
    assert np.allclose(t["speed_m_s"], [ref.SPEED_M_S, 2 * ref.SPEED_M_S])
    with pytest.raises(ValueError, match="factors"):
        paper.clock_drift(TINY, cache_dir=tmp_path, designs=("SS",), factors=(0.0,), workers=1)


def test_in_place_replicates_compare_on_run_means(tmp_path):
    prof = Profile("short", 4.0, 1.0, book_replicates=3)
    reps = paper.in_place_replicates(prof, cache_dir=tmp_path, workers=1)
    assert set(reps["behaviour"]) == {"static"}
    assert set(reps["design"]) == set(ref.MONO_MATERIALS)
    assert sorted(set(reps["replicate"])) == [-1, 0, 1, 2]
    # perturbed runs move sideways; the unperturbed one does not
    track = reps.groupby("replicate")["tracking_error_m"].max()
    assert track.loc[-1] < 1e-9 and (track.drop(-1) > 1e-5).all()
    t = tab.replicate_table(stats.compare_replicates(reps, "MD"))
    assert set(t["design"]) == set(ref.MONO_MATERIALS) - {"MD"}
    assert (t["n"] == 3).all() and t["change"].str.match(r"[+-]\d+ % \[").all()
    with pytest.raises(ValueError, match="replicates"):
        Profile("bad", 4.0, 1.0, book_replicates=-1)


def test_jerk_by_rate_subsamples(tmp_path):
    (r,) = runner.rollouts(["SS"], ["static"], TINY.sim_settings(), cache_dir=tmp_path, workers=1)
    t = tab.jerk_by_rate(r, rates_hz=(1000.0, 100.0))
    assert np.allclose(t["rate_hz"], [1000.0, 100.0])
    assert (t["mean_jerk_m_s3"] > 0).all()
    with pytest.raises(ValueError, match="record rate"):
        tab.jerk_by_rate(r, rates_hz=(5000.0,))


def test_axial_check_three_settings(tmp_path):
    hopping = Profile("hopping", 2.0, 0.3, 1e-4, 1, 0.3)       # long enough for a few scored hops
    out = paper.axial_check(hopping, cache_dir=tmp_path, designs=("MD", "SS"), timestep_s=1e-5, workers=1)
    assert out["timestep_s"] == 1e-5
    settings = set(out["runs"]["setting"])
    assert settings == {"paper, dt 0.0001 s", "paper, dt 1e-05 s", "axial, dt 1e-05 s"}
    # the rigid leg has no springs: one small-step run stands for both conventions
    md = out["runs"][out["runs"]["design"] == "MD"]
    assert len(md) == 3 and md["key"].nunique() == 2
    cmp = tab.setting_comparison(out["hops"], pairs=(("SS", "MD"),))
    assert sorted(cmp.index) == sorted(settings)
    assert list(cmp.columns) == ["tracking_error_m: SS vs MD", "power_w: SS vs MD"]
    assert np.isfinite(cmp.to_numpy()).all()
    with pytest.raises(ValueError, match="setting"):
        tab.setting_comparison(out["hops"].drop(columns="setting"))


def test_power_formula_and_defects_figure(synthetic):
    hops, _ = synthetic
    p = tab.power_formula_table(hops[hops["experiment"] == "exp1"])
    assert list(p.index) == ["real hip power (ours)", "the authors' formula"]
    assert abs(p.loc["real hip power (ours)", "ramp"] - (2.93 - 1) * 100) < 10
    clock = pd.DataFrame({"design": ["MD", "MD"], "clock_factor": [1.0, 2.0], "mean_tracking_error_m": [0.06, 0.1]})
    jerk = {"MD": pd.DataFrame({"rate_hz": [1000.0, 10.0], "mean_jerk_m_s3": [500.0, 100.0]})}
    assert len(chapters.defects_figure(clock, jerk, p).axes) == 3
    rules = tab.claim_rules()
    assert len(rules) == len(tab.claims_for({"exp1_hops": hops[hops["experiment"] == "exp1"]}, None))


def test_front_table_and_designs():
    front = pd.DataFrame({"trial": [0, 7], "paper_design": ["SS", ""], "tracking_error_m": [0.01, 0.02],
                          "power_w": [0.008, 0.005], "hop_height_m": [0.96, 0.98],
                          "tracking_error_vs_SS_pct": [0.0, 100.0], "power_vs_SS_pct": [0.0, -37.5],
                          "seg1_rho_g_cm3": [8.0, 13.4], "seg1_e_gpa": [193.0, 4.4],
                          "seg2_rho_g_cm3": [8.0, 2.0], "seg2_e_gpa": [193.0, 2.4]})
    t = optimize.front_table(front)
    assert list(t.columns) == ["trial", "paper design", "tracking error (mm)", "hip power (mW)", "hop height (m)",
                               "tracking vs SS (%)", "power vs SS (%)"]
    assert t.loc[1, "tracking error (mm)"] == 20.0
    legs = optimize.front_designs(front)
    assert list(legs) == ["#7"] and legs["#7"].densities_g_cm3 == (13.4, 2.0)
    assert list(optimize.front_designs(front, skip_paper=False, k=1)) == ["#0"]


def test_book_study_runs_and_resumes(tmp_path):
    b = _tiny_book(tmp_path, PROFILES["quick"])
    rep = optimize.book_study(b.profile, studies_dir=tmp_path / "studies", out_dir=b.out_dir / "study", trials=4)
    assert rep["name"].startswith("book-ramp-quick-")
    t = rep["trials"]
    assert len(t) == 4 and list(t["paper_design"][:3]) == ["SS", "rho-inc", "PVC-Ti-SS"]
    assert (tmp_path / "studies").is_dir() and os.path.isfile(rep["paths"]["pareto_plot"])
    again = optimize.book_study(b.profile, studies_dir=tmp_path / "studies", out_dir=b.out_dir / "study", trials=4)          # resumed: nothing new to run
    pd.testing.assert_frame_equal(rep["trials"].drop(columns="worker"), again["trials"].drop(columns="worker"))


# ---------------------------------------------------------------------------
# notebooks: clean, in sync with their sources, listed in the toc


def test_notebooks_clean_and_in_sync():
    """Each notebook holds exactly the cells jupytext reads from its source
    (run `make notebooks` after editing notebooks/src/*.py)."""
    import jupytext

    sources = sorted((NOTEBOOKS / "src").glob("*.py"))
    assert [p.stem for p in sources] == [p.stem for p in sorted(NOTEBOOKS.glob("*.ipynb"))]
    for src in sources:
        want = jupytext.read(src)
        have = nbformat.read(NOTEBOOKS / f"{src.stem}.ipynb", as_version=4)
        assert [(c.cell_type, c.source, c.metadata.get("tags")) for c in want.cells] == \
               [(c.cell_type, c.source, c.metadata.get("tags")) for c in have.cells], f"{src.name}: run make notebooks"
    for path in sorted(NOTEBOOKS.glob("*.ipynb")):
        nb = nbformat.read(path, as_version=4)
        assert nb.metadata["kernelspec"]["name"] == "python3", path.name
        code = [c for c in nb.cells if c.cell_type == "code"]
        assert code, path.name
        assert all(not c.outputs and c.execution_count is None for c in code), path.name
        assert "book.setup()" in code[0].source, f"{path.name}: the first code cell must call book.setup()"
        titles = []
        for c in nb.cells:
            if c.cell_type == "markdown":
                text = re.sub(r"```.*?```", "", c.source, flags=re.S)      # not inside code blocks
                titles += [ln for ln in text.splitlines() if ln.startswith("# ")]
        assert len(titles) == 1, f"{path.name}: one title (# ...) per chapter, got {titles}"


def test_toc_lists_every_chapter():
    files = toc_files()
    assert [f for f in files if f.startswith("notebooks/")] == [f"notebooks/{n}" for n in MIN_FIGURES]
    for f in files:
        assert any((ROOT / f"{f}{ext}").exists() for ext in (".md", ".ipynb")), f
    config = yaml.safe_load((ROOT / "_config.yml").read_text())
    assert config["execute"]["execute_notebooks"] in ("force", "cache")
    assert config["execute"]["allow_errors"] is False




# ---------------------------------------------------------------------------
# the build itself


def _build(source: Path, out: Path, profile: str, toc: Path | None = None) -> subprocess.CompletedProcess:
    env = dict(os.environ, MAT_HOPPER_PROFILE=profile)
    cmd = book.build_command(source, path_output=out, toc=toc)
    return subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=ROOT, timeout=3000)


def test_a_failing_cell_fails_the_build(tmp_path):
    """The book's own configuration, with one chapter that raises."""
    src = tmp_path / "src"
    (src / "notebooks").mkdir(parents=True)
    shutil.copy(ROOT / "_config.yml", src / "_config.yml")
    (src / "_toc.yml").write_text("format: jb-book\nroot: index\nchapters:\n  - file: notebooks/bad\n")
    (src / "index.md").write_text("# Test\n")
    nb = nbformat.v4.new_notebook()
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    nb.cells = [nbformat.v4.new_markdown_cell("# Bad"), nbformat.v4.new_code_cell("raise RuntimeError('boom')")]
    nbformat.write(nb, src / "notebooks" / "bad.ipynb")
    r = _build(src, tmp_path / "out", "quick")
    assert r.returncode != 0
    assert "boom" in (r.stdout + r.stderr) or "CellExecutionError" in (r.stdout + r.stderr)


@pytest.mark.slow
def test_quick_book_builds_with_every_figure(tmp_path):
    """Build the quick book (results from the cache under results/cache
    when there) and check every chapter's page."""
    out = tmp_path / "book"
    r = _build(ROOT, out, "quick")
    log = r.stdout + r.stderr
    assert r.returncode == 0, log[-5000:]
    html = out / "_build" / "html"
    reports = list((html / "reports").rglob("*.err.log")) if (html / "reports").exists() else []
    assert not reports, [p.read_text()[:2000] for p in reports]
    assert (html / "index.html").exists()
    for name, n_min in MIN_FIGURES.items():
        page = html / "notebooks" / f"{name}.html"
        assert page.exists(), f"missing page {page}"
        text = page.read_text(encoding="utf-8")
        images = re.findall(r'<img[^>]+src="([^"]+)"', text)
        assert len(images) >= n_min, f"{name}: {len(images)} figures, expected at least {n_min}"
        for src in images:
            if src.startswith("data:"):
                continue
            f = (page.parent / src).resolve()
            assert f.is_file() and f.stat().st_size > 1000, f"{name}: figure {src} missing or empty"
        assert "Traceback (most recent call last)" not in text, f"{name}: a cell shows a traceback"
        assert 'class="output traceback' not in text and "ansi-red-fg" not in text, f"{name}: error output"
        if name == "01-introduction":       # the kernel ran the venv's interpreter, under the quick profile
            assert "profile quick" in text
            assert re.search(r"\.venv/bin/python", text), "the book's kernel is not the venv's Python"
