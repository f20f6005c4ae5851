"""Motion data: the record and packed-dataset model, the embedded procedural datasets, real-format loaders,
and the batching pipeline.

    from jaxmotion.data import load_dataset
    train = load_dataset("synth-humanact12")                      # embedded, generated once and cached
    uestc = load_dataset("uestc", "test", data_root="data/uestc")  # the real files, in their own format
"""

from jaxmotion.data.datasets import dataset_names, load_dataset
from jaxmotion.data.motion import ActionItems, Motion, MotionDataset, concatenate, pack
from jaxmotion.data.segments import Program, ProgramAction, Segments, transition_counts

__all__ = ["ActionItems", "Motion", "MotionDataset", "Program", "ProgramAction", "Segments", "concatenate",
           "dataset_names", "load_dataset", "pack", "transition_counts"]
