"""The minimal training loop: jitted steps, stateless per-step randomness, orbax checkpoints, resume,
initialisation from another run, an evaluation hook, several optimisers, and data-parallel meshes."""

from jaxmotion.train.checkpoint import Checkpointer
from jaxmotion.train.loop import LoopConfig, StepFn, train
from jaxmotion.train.mesh import data_mesh, initialize_distributed, replicate, shard_batch
from jaxmotion.progress import Progress
from jaxmotion.train.state import MultiState

__all__ = ["Checkpointer", "LoopConfig", "MultiState", "Progress", "StepFn", "data_mesh", "initialize_distributed",
           "replicate", "shard_batch", "train"]
