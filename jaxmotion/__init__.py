"""jaxmotion: action-conditioned 3D human motion generation in JAX/Flax.

Subpackages:
  geometry     rotations, skeletons, forward kinematics, the SMPL-format body layer
  data         motion records, the embedded datasets, real-format loaders, batching, export
  nn           layers as pure functions (core primitives, Transformer, GRU, ST-GCN)
  models       one file per method: its config, parameters, forward functions and feature layout
  losses       training losses; metrics: jit-compiled metric kernels
  train        the minimal loop (checkpoints, resume, init_from, eval hook), fit, one trainer per method
  evaluation   the protocol, evaluators, scoring tables, the papers' claims, statistics
  pipelines    trained models put to use (generators saved and loaded, generation, denoising, interpolation)
  recipes      each paper's home: table rows (fit + generator), profile sizes, evaluators, the table runner
  viz          pictures and videos of motions (skeletons, meshes), plots
Modules:
  config       frozen experiment configs: JSON round trip, typed overrides
  distributed  the data mesh over devices and hosts
  experiment   the command line and results folder every experiment shares (only experiments import it)
  provenance   the run record: software, machine, datasets, evaluators

``jaxmotion.load_generator(path)`` opens the trained generator of any run folder
(:func:`jaxmotion.pipelines.load.load_generator`).
"""

from jaxmotion._xla_workarounds import disable_ynn_fusion_if_affected

__version__ = "0.1.0"

disable_ynn_fusion_if_affected()  # must run before jax's first computation; see _xla_workarounds


def __getattr__(name: str):
    # imported on first use: `import jaxmotion` stays light (no jax computation, no model code)
    if name == "load_generator":
        from jaxmotion.pipelines.load import load_generator

        return load_generator
    raise AttributeError(f"module 'jaxmotion' has no attribute {name!r}")
