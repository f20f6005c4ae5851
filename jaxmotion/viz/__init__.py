"""Every experiment's pictures (matplotlib's Agg, no display needed): plots of results (:mod:`~jaxmotion.viz.plots`),
motions drawn frame by frame (:mod:`~jaxmotion.viz.scene`: cameras, captions, legends, meshes), videos
(:mod:`~jaxmotion.viz.video`: ``.mp4`` and ``.gif``), pictures of datasets (:mod:`~jaxmotion.viz.motion`: grids,
filmstrips, takes) and their command line (``python -m jaxmotion.viz.preview``)."""

from jaxmotion.viz.motion import filmstrip, render_grid, take_animation, take_strip, transition_heatmap
from jaxmotion.viz.plots import save_curves, save_scatter, save_trajectories
from jaxmotion.viz.video import render_video, write_video

__all__ = ["filmstrip", "render_grid", "render_video", "save_curves", "save_scatter", "save_trajectories",
           "take_animation", "take_strip", "transition_heatmap", "write_video"]
