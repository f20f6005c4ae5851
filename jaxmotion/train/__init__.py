"""The minimal training loop: jitted steps, stateless per-step randomness, orbax checkpoints, resume."""

from jaxmotion.train.checkpoint import Checkpointer
from jaxmotion.train.loop import LoopConfig, StepFn, train
from jaxmotion.train.progress import Progress

__all__ = ["Checkpointer", "LoopConfig", "Progress", "StepFn", "train"]
