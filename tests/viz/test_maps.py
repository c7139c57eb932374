"""The designs figure (mat_hopper.viz.maps)."""

from __future__ import annotations

from mat_hopper.analysis import tables as tab
from mat_hopper.core import reference as ref
from mat_hopper.viz import maps


def test_design_table_and_figure():
    t = tab.design_table()
    assert set(t["design"]) >= {"MD", "SS", "rho-inc", "SS-Ti-PVC"}
    inc = t[t["design"] == "rho-inc"].sort_values("segment")
    assert tuple(inc["density_g_cm3"]) == ref.GRADIENT_DENSITIES
    assert t.loc[t["design"] == "MD", "modulus_gpa"].isna().all()
    fig = maps.designs_figure()
    assert len(fig.axes) == 4  # two panels, two colour bars


def test_catalogue_table_of_a_selection():
    import pytest

    from mat_hopper.core.materials import material

    whole = maps.catalogue_table()
    assert len(whole) == 13  # the catalogue: 12 elastic materials and MD
    # an empty selection selects nothing: an empty table with the columns, not the catalogue
    for empty in ({}, [], ()):
        t = maps.catalogue_table(empty)
        assert len(t) == 0
        assert list(t.columns) == ["name", "density_g_cm3", "modulus_gpa", "material_class", "source"]
    t = maps.catalogue_table({"ss": material("SS")})
    assert t["name"].tolist() == ["SS"] and t["modulus_gpa"].tolist() == [193.0]
    with pytest.raises(ValueError, match="not the string 'SS'"):
        maps.catalogue_table("SS")
    with pytest.raises(ValueError, match="entries must be Materials; got 'SS'"):
        maps.catalogue_table(["SS"])
