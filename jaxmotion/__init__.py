"""jaxmotion: action-conditioned 3D human motion generation in JAX/Flax.

Subpackages:
  geometry    rotations, skeletons, forward kinematics, the SMPL-format body layer
  train       the minimal training loop: train state, jitted steps, orbax checkpoints, resume
  evaluation  repetitions over seeds and mean ± 95% confidence intervals
  config / cli  frozen experiment configs with smoke / cpu / paper profiles, and their command line
"""

from jaxmotion._xla_workarounds import disable_ynn_fusion_if_affected

__version__ = "0.1.0"

disable_ynn_fusion_if_affected()  # must run before jax's first computation; see _xla_workarounds
