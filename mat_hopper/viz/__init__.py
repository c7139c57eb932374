"""Figures and rendering. Nothing here switches the matplotlib backend:
figures are built on ``matplotlib.figure.Figure`` and saved atomically.

- :mod:`~mat_hopper.viz.style`: colours, labels, order, figure style;
- :mod:`~mat_hopper.viz.figures`: the paper's figures 4 and 5
  (:mod:`~mat_hopper.viz.sweeps`: its panels D-E);
- :mod:`~mat_hopper.viz.maps`: stable-time-step map, Ashby chart, designs;
- :mod:`~mat_hopper.viz.chapters`: figures of single chapters (controller
  signals, stiffness conventions, the authors' defects);
- :mod:`~mat_hopper.viz.study`: the optimizer report's plots;
- :mod:`~mat_hopper.viz.scene`: the render scene, camera and off-screen
  OpenGL context;
- :mod:`~mat_hopper.viz.render`: stills, gait tiles and videos.
"""
