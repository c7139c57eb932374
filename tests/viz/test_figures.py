import numpy as np
import pandas as pd
import pytest
from matplotlib.figure import Figure
from matplotlib.patches import Polygon
from synthetic_results import results, stability_table

from mat_hopper.analysis import stats
from mat_hopper.core.materials import CATALOGUE
from mat_hopper.core.sim import simulate
from mat_hopper.viz import figures as plots
from mat_hopper.viz import maps, style


@pytest.fixture(scope="module")
def tables():
    hops, runs = results(n=8, replicates=2)
    return hops, runs


def _stars(fig) -> int:
    return sum(t.get_text() == "*" for ax in fig.axes for t in ax.texts)


def test_save_figure_png_and_svg_atomic_and_deterministic(tmp_path):
    fig = maps.ashby_figure()
    paths = style.save_figure(fig, tmp_path / "sub" / "ashby.png", dpi=60)  # a suffix is dropped
    assert [p.name for p in paths] == ["ashby.png", "ashby.svg"]
    assert paths[0].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    svg = paths[1].read_bytes()
    assert svg.lstrip().startswith(b"<?xml") and b"<svg" in svg
    again = style.save_figure(maps.ashby_figure(), tmp_path / "again", dpi=60)
    assert [p.read_bytes() for p in again] == [p.read_bytes() for p in paths]  # same figure, same files
    assert not [p for p in (tmp_path / "sub").iterdir() if p.name.startswith(".tmp-")]
    with pytest.raises(ValueError, match="formats"):
        style.save_figure(fig, tmp_path / "x", formats=("jpg",))


def test_figure4_mono_stars_follow_the_comparison(tables):
    hops, runs = tables
    exp1 = hops[hops["experiment"] == "exp1"]
    fig = plots.figure4_mono(exp1, basis="hops")
    assert isinstance(fig, Figure) and len(fig.axes) == 3
    cmp = stats.compare_designs(exp1, "MD", basis="hops", metrics=("power_w", "jerk_m_s3", "tracking_error_m"))
    assert _stars(fig) == int(cmp["significant"].sum()) > 0
    ylabels = [ax.get_ylabel() for ax in fig.axes]
    assert ylabels == ["Hip power (W)", "Jerk (m/s³)", "Tracking error (mm)"]  # units, SI prefix chosen
    # replicate basis: 2 replicates cannot reach Holm significance; dots for the replicate means
    fig = plots.figure4_mono(exp1, basis="replicates")
    assert _stars(fig) == 0
    dots = [ln for ax in fig.axes for ln in ax.lines if ln.get_gid() == "replicate-means"]
    assert sum(len(ln.get_xdata()) for ln in dots) == 3 * 4 * 5 * 2  # metrics x behaviours x designs x replicates


def test_figure4_mono_leaves_out_diverged_runs(tables):
    hops, runs = tables
    runs = runs.copy()
    bad = (runs["design"] == "SS") & (runs["behaviour"] == "ramp")
    runs.loc[bad, ["stable", "status"]] = [False, "diverged"]
    fig = plots.figure4_mono(hops[hops["experiment"] == "exp1"], runs=runs)
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert any(t.startswith("not shown: SS ramp (unstable") for t in labels)


def test_figure4_sweeps_with_baseline_and_diverged_points(tables):
    hops, runs = tables
    exp2 = hops[hops["experiment"] == "exp2"]
    base = hops[(hops["experiment"] == "exp1") & (hops["design"] == "MD") & (hops["behaviour"] == "forward")]
    runs = runs.copy()
    bad = (runs["experiment"] == "exp2") & (runs["design"] == "SS density=20")
    assert bad.sum() == 1
    runs.loc[bad, ["stable", "status", "diverged_at_s"]] = [False, "diverged", 0.002]
    fig = plots.figure4_sweeps(exp2, base, runs=runs)
    d, e = fig.axes
    assert d.get_xscale() == "log" and e.get_xlabel() == "Modulus (GPa)"
    crosses = [ln for ln in d.lines if ln.get_marker() == "x"]
    assert len(crosses) == 1 and crosses[0].get_xdata()[0] == 20.0
    assert not any(20.0 in np.atleast_1d(ln.get_xdata()) for ln in d.lines if ln.get_marker() == "o")


def test_figure5_gradients(tables):
    hops, runs = tables
    fig = plots.figure5_gradients(hops[hops["experiment"].isin(["exp1", "exp3"])])
    assert len(fig.axes) == 6
    assert "ρ-inc / ρ-dec" in fig.axes[0].get_title()


def test_figure5_timeseries_from_rollouts():
    rollouts = [simulate(d, b, duration_s=3, transient_s=1) for d in ("MD", "SS") for b in ("forward", "ramp")]
    fig = plots.figure5_timeseries(rollouts)
    assert len(fig.axes) == 6 and fig.axes[0].get_title() == "Forward hopping"
    assert all(len(ax.lines) == 2 for ax in fig.axes)
    s = plots.rollout_series(rollouts[0])
    assert len(s) >= 2 and (np.diff(s["t_mid_s"]) > 0).all()


def test_stability_figure_both_column_names_and_unstable_cells():
    s = stability_table(size=5)
    s.loc[0, "max_stable_timestep_s"] = np.nan  # no tried step stable
    fig = maps.stability_figure(s)
    assert fig.axes[0].get_xlabel() == "Density (g/cm³)" and fig.axes[0].get_yscale() == "log"
    stab_a = s.rename(columns={"max_stable_timestep_s": "dt_stable_s", "analytic_timestep_s": "dt_estimate_s"})
    assert isinstance(maps.stability_figure(stab_a), Figure)
    with pytest.raises(ValueError, match="conventions"):
        maps.stability_figure(pd.concat([s, s.assign(convention="axial")]))
    with pytest.raises(ValueError, match="modulus_gpa"):
        maps.stability_figure(s.drop(columns="modulus_gpa"))


def test_ashby_figure_regions_and_points():
    fig = maps.ashby_figure()
    ax = fig.axes[0]
    assert ax.get_xscale() == ax.get_yscale() == "log"
    assert sum(isinstance(p, Polygon) for p in ax.patches) == len(maps.CLASS_REGIONS)
    n_points = sum(len(c.get_offsets()) for c in ax.collections)
    assert n_points == sum(m.modulus_gpa is not None for m in CATALOGUE.values())


def test_write_figures_from_reproduction_tables(tmp_path, tables):
    hops, runs = tables
    t = {
        f"{e}_{k}": v[v["experiment"] == e]
        for e in ("exp1", "exp2", "exp3")
        for k, v in (("hops", hops), ("runs", runs))
    }
    t["stability"] = stability_table()
    paths = plots.write_figures(t, tmp_path, basis="hops", formats=("png",), dpi=40)
    names = sorted({p.stem for p in paths})
    assert names == ["ashby", "fig4_mono", "fig4_sweeps", "fig5_gradients", "stability_map"]
    assert all(p.parent == tmp_path / "figures" and p.stat().st_size > 1000 for p in paths)


def test_bad_input_names_the_column():
    with pytest.raises(ValueError, match="power_w"):
        plots.figure4_mono(pd.DataFrame({"design": ["MD"], "behaviour": ["static"]}))
    with pytest.raises(ValueError, match="Rollout"):
        plots.figure5_timeseries([])


@pytest.mark.parametrize(
    ("kwargs", "text"),
    [
        ({"formats": ("png", "jpg")}, r"formats must be among png, svg, pdf; got 'jpg'"),
        ({"formats": ("svg", "png", "tiff")}, r"got 'tiff'"),
        ({"formats": ()}, "at least one"),
        ({"formats": "png"}, "not the string 'png'"),
        ({"dpi": 0}, "dpi must be a finite number > 0, got 0"),
    ],
)
def test_save_figure_checks_every_format_before_writing(tmp_path, kwargs, text):
    # a bad second format leaves nothing written, not even the first
    with pytest.raises(ValueError, match=text):
        style.save_figure(maps.ashby_figure(), tmp_path / "sub" / "x", **kwargs)
    assert list(tmp_path.iterdir()) == []


def test_paper_box_figures_are_seaborn_boxes_at_the_papers_positions(tables):
    """Fig. 4's boxes come from seaborn's boxplot (designs as hue), one box
    per behaviour and design, each centred where the stars and the replicate
    dots are placed: behaviour index - 0.4 + 0.8 / n (design index + 0.5)."""
    from matplotlib.patches import PathPatch

    hops, _ = tables
    exp1 = hops[hops["experiment"] == "exp1"]
    fig = plots.figure4_mono(exp1, basis="replicates")
    ax = fig.axes[0]
    boxes = [p for p in ax.patches if isinstance(p, PathPatch)]
    n_designs, n_behaviours = exp1["design"].nunique(), exp1["behaviour"].nunique()
    assert len(boxes) == n_designs * n_behaviours
    xs = [p.get_path().vertices[:, 0] for p in boxes]
    centres = sorted(round(float(x.min() + x.max()) / 2, 6) for x in xs)
    w = 0.8 / n_designs
    want = sorted(round(g - 0.4 + w * (d + 0.5), 6) for g in range(n_behaviours) for d in range(n_designs))
    assert centres == pytest.approx(want, abs=1e-6)


def test_a_hop_cycle_comparison_is_labelled_descriptive_in_the_figures():
    """Stars and open markers drawn from hop cycles of one run (basis hops)
    describe it: their labels say so and never say "significant"; on
    replicate means the stars are a test."""
    import pandas as pd

    from mat_hopper.viz.figures import _basis_note
    from mat_hopper.viz.sweeps import _sweep_legend

    hops = _basis_note(pd.DataFrame({"basis": ["hops"]}), "MD", 0.05)
    assert "descriptive" in hops and "significant" not in hops
    assert "descriptive" not in _basis_note(pd.DataFrame({"basis": ["replicates"]}), "MD", 0.05)
    labels = [h.get_label() for h in _sweep_legend(["SS"], pd.DataFrame(), pd.DataFrame({"x": [1]}), "MD", 0.05)]
    assert "open: hop-cycle Holm p >= 0.05 vs MD (descriptive)" in labels
    assert not any("significant" in label for label in labels)
