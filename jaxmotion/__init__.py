"""jaxmotion: action-conditioned 3D human motion generation in JAX/Flax.

Subpackages:
  geometry     rotations, skeletons, forward kinematics, the SMPL-format body layer
  data         motion records, the embedded datasets, real-format loaders, batching, export
  nn           layers as pure functions (core primitives, Transformer, GRU, ST-GCN)
  models       one file per method: its config, parameters, forward functions and feature layout
  losses       training losses; metrics: jit-compiled metric kernels
  train        the minimal loop (checkpoints, resume, init_from, eval hook), fit, the data mesh, trainers
  evaluation   the protocol, evaluators, method-agnostic tables, the papers' claims, statistics
  pipelines    trained models put to use (generation, denoising, interpolation); viz: plots
Modules:
  config       frozen experiment configs: JSON round trip, typed overrides
  experiment   the command line and results folder every experiment shares (only experiments import it)
  provenance   the run record: software, machine, datasets, evaluators
"""

from jaxmotion._xla_workarounds import disable_ynn_fusion_if_affected

__version__ = "0.1.0"

disable_ynn_fusion_if_affected()  # must run before jax's first computation; see _xla_workarounds
