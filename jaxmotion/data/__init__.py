"""Motion data: the record and packed-dataset model, the embedded procedural dataset, real-format loaders,
and the batching pipeline."""

from jaxmotion.data.motion import Motion, MotionDataset, pack

__all__ = ["Motion", "MotionDataset", "pack"]
