"""Figures and rendering. Nothing here switches the matplotlib backend:
figures are built on ``matplotlib.figure.Figure`` and saved atomically.

- :mod:`~mat_hopper.viz.style`: colours, labels, order, figure style;
- :mod:`~mat_hopper.viz.figures`: the paper's figures 4 and 5
  (:mod:`~mat_hopper.viz.sweeps`: its panels D-E);
- :mod:`~mat_hopper.viz.maps`: stable-time-step map, Ashby chart, designs;
- :mod:`~mat_hopper.viz.chapters`: figures of single chapters (controller
  signals, stiffness conventions, the authors' defects);
- :mod:`~mat_hopper.viz.study`: the optimizer report's plots;
- :mod:`~mat_hopper.viz.findings`: the book's findings page from the
  recorded paper-profile results (its public names are handed on here,
  imported when first asked for);
- :mod:`~mat_hopper.viz.scene`: the render scene, camera and off-screen
  OpenGL context;
- :mod:`~mat_hopper.viz.render`: stills, gait tiles and videos.

This package's ``__init__`` imports nothing, so importing one module never
drags in the others.
"""

_FINDINGS = (
    "read_records",
    "findings_table",
    "paired_effects",
    "design_answer",
    "forest_plot",
    "beside_record",
)


def __getattr__(name):
    # findings' names, imported on first use so that importing the package stays free
    if name in _FINDINGS:
        from . import findings

        return getattr(findings, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
