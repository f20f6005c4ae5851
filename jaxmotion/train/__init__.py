"""The minimal training loop: jitted steps, stateless per-step randomness, orbax checkpoints, resume,
initialisation from another run, an evaluation hook, several optimisers, data-parallel meshes
(:mod:`jaxmotion.distributed`), and training-log writers (:mod:`jaxmotion.train.writers`: TensorBoard's)."""

from jaxmotion.train.checkpoint import Checkpointer
from jaxmotion.train.loop import LoopConfig, StepFn, train
from jaxmotion.progress import Progress
from jaxmotion.train.state import MultiState
from jaxmotion.train.writers import TensorBoard, Writer, WriterFactory

__all__ = ["Checkpointer", "LoopConfig", "MultiState", "Progress", "StepFn", "TensorBoard", "Writer", "WriterFactory",
           "train"]
