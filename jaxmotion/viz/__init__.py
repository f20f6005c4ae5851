"""Pictures of experiments: curves and plots (matplotlib, no display needed)."""

from jaxmotion.viz.plots import save_curves, save_scatter, save_trajectories

__all__ = ["save_curves", "save_scatter", "save_trajectories"]
