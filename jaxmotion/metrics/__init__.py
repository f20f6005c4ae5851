"""Metric kernels of the four papers, jit-compiled, each checked against an independent reference.

| module | metrics | papers |
| --- | --- | --- |
| :mod:`~jaxmotion.metrics.fid` | FID (= FID_w, FID_tr, FID_test), per-class FID and FID_m, FID_a features | all |
| :mod:`~jaxmotion.metrics.classification` | confusion matrix, accuracy, mean class recall | all |
| :mod:`~jaxmotion.metrics.diversity` | diversity, multimodality (Action2Motion) | ACTOR, ODMO, Marionette |
| :mod:`~jaxmotion.metrics.apd` | APD, n-APD, mode-homogeneity | ODMO |
| :mod:`~jaxmotion.metrics.clustering` | adjusted Rand index of discovered against true modes | (ODMO, added) |
| :mod:`~jaxmotion.metrics.transitions` | Δpose, Δvel, action- and motion-level qualification ratios | Marionette |
| :mod:`~jaxmotion.metrics.trajectory` | ΔTraj, ΔJPE, end-point error dist_e and hit rate | Marionette, ODMO |
| :mod:`~jaxmotion.metrics.smoothness` | jitter (mean joint acceleration) | ACTOR (denoising) |

Mean ± 95% interval over repetitions: :func:`jaxmotion.evaluation.summarize`.
"""

from jaxmotion.metrics.apd import apd, apd_per_class, mode_homogeneity, n_apd
from jaxmotion.metrics.clustering import adjusted_rand_index
from jaxmotion.metrics.classification import (
    accuracy,
    confusion_matrix,
    mean_class_recall,
)
from jaxmotion.metrics.diversity import diversity, multimodality
from jaxmotion.metrics.fid import (
    aggregate_persons,
    fid,
    fid_class_mean,
    fid_per_class,
    frechet_distance,
    gaussian_stats,
)
from jaxmotion.metrics.smoothness import mean_acceleration
from jaxmotion.metrics.trajectory import (
    end_point_error,
    end_point_hit_rate,
    end_point_squared_error,
    joint_position_error,
    joint_position_error_per_sample,
    trajectory_error,
    trajectory_error_per_sample,
)
from jaxmotion.metrics.transitions import (
    action_qr,
    mean_transition_gaps,
    motion_qr,
    qualification_ratio_curves,
    transition_gaps,
)

__all__ = [
    "accuracy", "action_qr", "adjusted_rand_index", "aggregate_persons", "apd", "apd_per_class", "confusion_matrix", "diversity",
    "end_point_error", "end_point_hit_rate", "end_point_squared_error", "fid", "fid_class_mean",
    "fid_per_class", "frechet_distance", "gaussian_stats", "joint_position_error", "joint_position_error_per_sample",
    "mean_acceleration", "mean_class_recall",
    "mean_transition_gaps",
    "mode_homogeneity", "motion_qr", "multimodality", "n_apd", "qualification_ratio_curves",
    "trajectory_error", "trajectory_error_per_sample", "transition_gaps",
]
