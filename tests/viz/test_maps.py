"""The designs figure (mat_hopper.viz.maps)."""

from __future__ import annotations

from mat_hopper import reference as ref
from mat_hopper.analysis import tables as tab
from mat_hopper.viz import maps


def test_design_table_and_figure():
    t = tab.design_table()
    assert set(t["design"]) >= {"MD", "SS", "rho-inc", "SS-Ti-PVC"}
    inc = t[t["design"] == "rho-inc"].sort_values("segment")
    assert tuple(inc["density_g_cm3"]) == ref.GRADIENT_DENSITIES
    assert t.loc[t["design"] == "MD", "modulus_gpa"].isna().all()
    fig = maps.designs_figure()
    assert len(fig.axes) == 4  # two panels, two colour bars
