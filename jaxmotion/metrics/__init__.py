"""Metric kernels of the four papers, jit-compiled, each checked against an independent reference."""

from jaxmotion.metrics.classification import accuracy, confusion_matrix, mean_class_recall
from jaxmotion.metrics.diversity import diversity, multimodality
from jaxmotion.metrics.fid import (
    aggregate_persons,
    fid,
    fid_class_mean,
    fid_per_class,
    frechet_distance,
    gaussian_stats,
)

__all__ = [
    "accuracy", "aggregate_persons", "confusion_matrix", "diversity", "fid", "fid_class_mean",
    "fid_per_class", "frechet_distance", "gaussian_stats", "mean_class_recall", "multimodality",
]
