"""The minimal training loop: jitted steps, stateless per-step randomness, orbax checkpoints, resume,
initialisation from another run, an evaluation hook, several optimisers, and data-parallel meshes
(:mod:`jaxmotion.distributed`)."""

from jaxmotion.train.checkpoint import Checkpointer
from jaxmotion.train.loop import LoopConfig, StepFn, train
from jaxmotion.progress import Progress
from jaxmotion.train.state import MultiState

__all__ = ["Checkpointer", "LoopConfig", "MultiState", "Progress", "StepFn", "train"]
