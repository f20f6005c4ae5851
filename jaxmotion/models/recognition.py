"""Action recognisers used as evaluators.

**Action2Motion's GRU classifier** (Guo et al. 2020, ``MotionDiscriminator``; the weights in
``shared/a2m/`` are the released ones ACTOR and ODMO evaluated with): a 2-layer GRU (hidden 128) reads the
motion frame by frame, the top layer's output at the last real frame goes through ``linear1`` (128 -> 30)
and ``tanh`` to give the 30-d feature used by FID, diversity and multimodality, and ``linear2`` (30 -> C)
gives the class logits. Input: joints flattened per frame, ``[B, T, J·3]`` (joint-major), in the dataset's
own frame (HumanAct12: y down, root of frame 0 at the origin).

The original starts the GRU from a random normal hidden state on every call, which makes its features
random; here the start is zero by default (deterministic; the reference outputs in ``shared/a2m`` were made
that way), and the random start is available by passing a key.

**Recognisers trained here** (:class:`RecognizerConfig`, :class:`Recognizer`): the evaluators of the
papers, rebuilt for the embedded datasets — the same GRU classifier at any size (Action2Motion's 2 × 128;
ODMO's 3 × 256 for UESTC) and ACTOR's ST-GCN (:mod:`jaxmotion.nn.stgcn`) on rot6d. They read motions in
the canonical frame (root of frame 0 at the origin, facing +Z): where a generator places or turns a
subject says nothing about the action, and removing it lets a small network reach high accuracy on a CPU
budget. Training and caching live in :mod:`jaxmotion.evaluation.recognizers`.

**A Transformer recogniser** (``architecture="transformer"``; Neural Marionette's evaluator is "a Transformer"
and nothing more): each frame's numbers (every person's, side by side) through a linear embedding plus a
sinusoidal position, a post-norm encoder (``layers``, ``heads``, width ``hidden``, FF 4 x ``hidden``, GELU,
``dropout``), the outputs averaged over the real frames (``lengths``), then ``tanh`` of a linear map to the
``feature_dim`` features and a linear map to the logits: the GRU classifier's head on a Transformer's pooling.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any, Literal, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.config import check_at_least
from jaxmotion.distributed import replicate
from jaxmotion.data.pipeline import canonicalize_motion, map_in_chunks
from jaxmotion.geometry.representations import actformer_features
from jaxmotion.geometry.rotations import axis_angle_to_matrix, from_matrix
from jaxmotion.geometry.skeletons import JOINTS15, Skeleton, joints15_indices
from jaxmotion.nn.core import LinearParams, dropout, init_linear, linear
from jaxmotion.nn.recurrent import GRUParams, gru_stack, init_gru
from jaxmotion.nn.stgcn import init_stgcn, spatial_partition, stgcn
from jaxmotion.nn.transformer import (EncoderLayerParams, TransformerOptions, encoder_stack, init_encoder_stack,
                                      sinusoidal_encoding)


class A2MRecognizerParams(NamedTuple):
    layers: tuple[GRUParams, ...]
    linear1: LinearParams  # [30, H], [30]
    linear2: LinearParams  # [C, 30], [C]


def load_a2m_params(npz_path: str | Path) -> A2MRecognizerParams:
    """Read Action2Motion classifier weights saved as PyTorch state-dict names in an ``.npz``."""
    path = Path(npz_path)
    if not path.is_file():
        raise FileNotFoundError(f"Action2Motion recogniser weights not found: {path}")
    with np.load(path) as data:
        arrays = {k: jnp.asarray(data[k], jnp.float32) for k in data.files}

    def take(name: str) -> jax.Array:
        if name not in arrays:
            raise ValueError(f"{path}: missing array {name!r} (found: {sorted(arrays)})")
        return arrays[name]

    num_layers = sum(1 for k in arrays if k.startswith("recurrent.weight_ih_l"))
    if num_layers == 0:
        raise ValueError(f"{path}: no GRU weights 'recurrent.weight_ih_l0' (found: {sorted(arrays)})")
    layers = tuple(
        GRUParams(*(take(f"recurrent.{n}_l{i}") for n in ("weight_ih", "weight_hh", "bias_ih", "bias_hh")))
        for i in range(num_layers)
    )
    hidden = layers[0].w_hh.shape[1]
    for i, layer in enumerate(layers):
        expected_in = layers[i - 1].w_hh.shape[1] if i else layer.w_ih.shape[1]
        if layer.w_ih.shape != (3 * hidden, expected_in) or layer.w_hh.shape != (3 * hidden, hidden):
            raise ValueError(f"{path}: GRU layer {i} has weight_ih {layer.w_ih.shape}, weight_hh {layer.w_hh.shape}; "
                             f"expected [{3 * hidden}, {expected_in}] and [{3 * hidden}, {hidden}]")
    return A2MRecognizerParams(layers, LinearParams(take("linear1.weight"), take("linear1.bias")),
                               LinearParams(take("linear2.weight"), take("linear2.bias")))


def a2m_recognize(params: A2MRecognizerParams, motions: jax.Array, lengths: jax.Array | None = None,
                  key: jax.Array | None = None) -> tuple[jax.Array, jax.Array]:
    """``motions [B, T, F]`` -> ``(logits [B, C], features [B, 30])``.

    ``lengths [B]``: read each sequence at its last real frame (default: frame T - 1). ``key``: start from
    a standard-normal hidden state drawn from it, as the original code does (default: zeros).
    """
    in_dim = params.layers[0].w_ih.shape[1]
    if motions.ndim != 3 or motions.shape[-1] != in_dim:
        raise ValueError(f"motions: expected shape [B, T, {in_dim}], got {tuple(motions.shape)}")
    batch, frames = motions.shape[:2]
    hidden = params.layers[0].w_hh.shape[1]
    if key is None:
        starts = [jnp.zeros((batch, hidden), motions.dtype)] * len(params.layers)
    else:
        starts = list(jax.random.normal(key, (len(params.layers), batch, hidden), motions.dtype))
    xs = gru_stack(params.layers, jnp.swapaxes(motions, 0, 1), tuple(starts))  # [T, B, H]
    last = jnp.full((batch,), frames - 1) if lengths is None else jnp.asarray(lengths) - 1
    top = xs[last, jnp.arange(batch)]  # [B, H]
    features = jnp.tanh(linear(params.linear1, top))
    return linear(params.linear2, features), features


def load_a2m_recognizer(npz_path: str | Path) -> Callable[..., tuple[jax.Array, jax.Array]]:
    """The released recogniser as a jitted callable ``(motions [B, T, F], lengths=None, key=None) ->
    (logits [B, C], features [B, 30])``."""
    params = load_a2m_params(npz_path)
    apply = jax.jit(a2m_recognize)

    def recognize(motions, lengths=None, key=None):
        return apply(params, jnp.asarray(motions, jnp.float32), lengths, key)

    return recognize


# --- recognisers trained on the embedded data ------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class RecognizerConfig:
    """An evaluator network and what it reads.

    ``architecture``: ``gru`` (Action2Motion's classifier; ``hidden``, ``layers``, ``feature_dim``) or
    ``stgcn`` (``channels``, ``strides``, ``temporal_kernel``, ``dropout``; features = the pooled last
    block, ``channels[-1]``-d). ``inputs``: ``joints`` (positions, translation kept), ``rot6d`` (joint
    rotations, no translation, as ACTOR's UESTC ST-GCN), or ActFormer's representations: ``limbs`` (the root
    minus the clip's mean root, then unit limb vectors, :func:`~jaxmotion.geometry.representations.skeleton_features`)
    and ``rot6d+translation`` (rot6d, then the translation de-meaned over the clip as one more node, parent 0:
    ActFormer's SMPL-25). ``canonical``: move every motion to the canonical frame first (needs a skeleton with
    ``left_hip``/``right_hip``). ``graph_center``: the ST-GCN partition's centre joint (ACTOR: the root;
    ActFormer's ``ntu-rgb+d`` layout: 20, the spine shoulder). ``persons``: how the ST-GCN reads motions of
    several persons: ``average`` (ST-GCN's own rule: shared weights, features averaged over persons) or
    ``channels`` (ActFormer's two-person evaluator: the persons' channels stacked per joint, ``P·C`` in,
    so the order of persons matters and training permutes them). ``topology``: ``own`` (the motions'
    skeleton) or ``joints15`` (:data:`~jaxmotion.geometry.skeletons.JOINTS15`, the 15 joints NTU-25 and GTA-22
    share: motions of either are reduced to them first, so one recogniser reads both; ActFormer's FID_a on
    GTA Combat). The graph and the representation are then the 15 joints'; joint positions only.
    """

    architecture: Literal["gru", "stgcn", "transformer"] = "gru"
    inputs: Literal["joints", "rot6d", "limbs", "rot6d+translation"] = "joints"
    canonical: bool = True
    graph_center: int = 0
    hidden: int = 128
    layers: int = 2
    feature_dim: int = 30
    channels: tuple[int, ...] = (64, 64, 64, 64, 128, 128, 128, 256, 256, 256)
    strides: tuple[int, ...] = (1, 1, 1, 1, 2, 1, 1, 2, 1, 1)
    temporal_kernel: int = 9
    dropout: float = 0.0
    persons: Literal["average", "channels"] = "average"
    topology: Literal["own", "joints15"] = "own"
    heads: int = 4

    def __post_init__(self):
        if self.architecture not in ("gru", "stgcn", "transformer"):
            raise ValueError(f"RecognizerConfig.architecture: expected 'gru', 'stgcn' or 'transformer', got "
                             f"{self.architecture!r}")
        if self.architecture == "transformer" and self.hidden % self.heads:
            raise ValueError(f"RecognizerConfig.heads: must divide hidden ({self.hidden}), got {self.heads}")
        if self.topology not in ("own", "joints15"):
            raise ValueError(f"RecognizerConfig.topology: expected 'own' or 'joints15', got {self.topology!r}")
        if self.topology == "joints15" and self.inputs not in ("joints", "limbs"):
            raise ValueError(f"RecognizerConfig.inputs: the joints15 topology keeps joint positions only; "
                             f"{self.inputs!r} reads rotations")
        if self.persons not in ("average", "channels"):
            raise ValueError(f"RecognizerConfig.persons: expected 'average' or 'channels', got {self.persons!r}")
        if len(self.channels) != len(self.strides) or not self.channels:
            raise ValueError(f"RecognizerConfig: channels ({len(self.channels)}) and strides "
                             f"({len(self.strides)}) need one entry per ST-GCN block")
        check_at_least(self, 1, "hidden", "layers", "feature_dim", "temporal_kernel", "heads")
        check_at_least(self, 0, "graph_center")

    @classmethod
    def a2m_gru(cls) -> RecognizerConfig:
        """Action2Motion's classifier: GRU 2 × 128 on joints, 30-d tanh features."""
        return cls()

    @classmethod
    def odmo_gru(cls) -> RecognizerConfig:
        """ODMO's UESTC classifier: GRU 3 × 256 on joints, 30-d features."""
        return cls(hidden=256, layers=3)

    @classmethod
    def actor_stgcn(cls) -> RecognizerConfig:
        """ACTOR's UESTC evaluator: ST-GCN (10 blocks, 64-256 channels) on rot6d, 256-d features."""
        return cls(architecture="stgcn", inputs="rot6d")

    @classmethod
    def actformer_stgcn(cls, inputs: str, graph_center: int = 0, persons: str = "average") -> RecognizerConfig:
        """ActFormer's evaluators (FACTS 5): the same ST-GCN with dropout 0.5 on its own representation, in the
        data's frame (no canonical turn); its two-person one reads the persons stacked on channels."""
        return cls(architecture="stgcn", inputs=inputs, canonical=False, graph_center=graph_center, dropout=0.5,
                   persons=persons)

    @property
    def channels_in(self) -> int:
        return 6 if self.inputs.startswith("rot6d") else 3

    @classmethod
    def transformer(cls, inputs: str = "rot6d+translation") -> RecognizerConfig:
        """The Transformer recogniser (module docstring): 2 layers of width 128, 4 heads, 64-d features, dropout
        0.1, on rot6d with the translation, in the canonical frame."""
        return cls(architecture="transformer", inputs=inputs, hidden=128, layers=2, heads=4, feature_dim=64,
                   dropout=0.1)

    @property
    def features(self) -> int:
        return self.channels[-1] if self.architecture == "stgcn" else self.feature_dim


def recognizer_inputs(config: RecognizerConfig, skeleton: Skeleton, motions: Mapping[str, jax.Array]) -> jax.Array:
    """What the network reads, ``[B, T, J', C]`` (C = 3 joints / limbs, 6 rot6d; J' = J, or J + 1 with the
    translation node), from a batch of motions; ``[B, P, T, J', C]`` for motions of P persons (the first
    person's frame 0 sets the canonical frame of all).

    ``motions``: ``joints [B, T, J, 3]`` (library frame, metres), optional ``translation [B, T, 3]`` (the
    root; default joint 0), and ``rotations [B, T, J, 3]`` axis-angle (joint 0 global), required for the rot6d
    inputs; or all of them ``[B, P, T, ...]``.
    """
    joints = jnp.asarray(motions["joints"], jnp.float32)
    num_joints = skeleton.num_joints
    if joints.ndim not in (4, 5) or joints.shape[-2:] != (num_joints, 3):
        raise ValueError(f"motions['joints']: expected [B, T, {num_joints}, 3] or [B, P, T, {num_joints}, 3] "
                         f"({skeleton.name}), got {tuple(joints.shape)}")
    rotations = motions.get("rotations")
    reads_rotations = config.inputs.startswith("rot6d")
    if reads_rotations:
        if rotations is None:
            raise ValueError(f"motions['rotations']: this recogniser reads {config.inputs} and needs axis-angle "
                             f"rotations [B, T, {num_joints}, 3]; the motions have joint positions only")
        rotations = jnp.asarray(rotations, jnp.float32)
        if rotations.shape != joints.shape:
            raise ValueError(f"motions['rotations']: expected {tuple(joints.shape)} like the joints, "
                             f"got {tuple(rotations.shape)}")
    translation = jnp.asarray(motions.get("translation", joints[..., 0, :]), jnp.float32)
    if config.topology == "joints15":  # the root maps to the root: the translation stays
        joints = joints[..., joints15_indices(skeleton), :]
    skeleton = network_skeleton(config, skeleton)
    if config.canonical:
        hips = skeleton.index("left_hip"), skeleton.index("right_hip")
        joints, translation, rotations = canonicalize_motion(joints, translation, rotations if reads_rotations
                                                             else None, *hips)
    if config.inputs == "joints":
        return joints
    if config.inputs in ("limbs", "rot6d+translation"):
        return actformer_features(config.inputs, skeleton.parents, joints, translation, rotations)
    return from_matrix(axis_angle_to_matrix(rotations), "rot6d")


def network_skeleton(config: RecognizerConfig, skeleton: Skeleton) -> Skeleton:
    """The skeleton the network reads for motions of ``skeleton``: its own, or :data:`JOINTS15`."""
    return JOINTS15 if config.topology == "joints15" else skeleton


def recognizer_parents(config: RecognizerConfig, skeleton: Skeleton) -> tuple[int, ...]:
    """The tree the network's graph is built on: the skeleton's (or :data:`JOINTS15`'s), plus the translation
    node (parent 0)."""
    return network_skeleton(config, skeleton).parents + ((0,) if config.inputs == "rot6d+translation" else ())


def init_gru_recognizer(key: jax.Array, input_dim: int, num_classes: int, hidden: int = 128, layers: int = 2,
                        feature_dim: int = 30) -> A2MRecognizerParams:
    """Fresh Action2Motion-layout classifier parameters (PyTorch's default initialisation)."""
    k_gru, k_1, k_2 = jax.random.split(key, 3)
    grus = [init_gru(k, input_dim if i == 0 else hidden, hidden) for i, k in enumerate(jax.random.split(k_gru, layers))]
    return A2MRecognizerParams(tuple(grus), init_linear(k_1, hidden, feature_dim),
                               init_linear(k_2, feature_dim, num_classes))


class TransformerRecognizerParams(NamedTuple):
    embedding: LinearParams  # frame numbers -> hidden
    layers: EncoderLayerParams
    linear1: LinearParams  # hidden -> feature_dim (tanh): the features
    linear2: LinearParams  # feature_dim -> classes: the logits


def _transformer_options(config: RecognizerConfig) -> TransformerOptions:
    return TransformerOptions(num_heads=config.heads, dropout_rate=config.dropout)


def transformer_recognize(config: RecognizerConfig, params: TransformerRecognizerParams, frames: jax.Array,
                          lengths: jax.Array | None = None, key: jax.Array | None = None
                          ) -> tuple[jax.Array, jax.Array]:
    """``frames [B, T, F]`` -> ``(logits [B, C], features [B, feature_dim])``, averaging over the first
    ``lengths [B]`` frames (default all); dropout with ``key``."""
    batch, count = frames.shape[:2]
    mask = jnp.ones((batch, count), bool) if lengths is None else jnp.arange(count)[None] < jnp.asarray(lengths)[:, None]
    h = linear(params.embedding, frames) + sinusoidal_encoding(jnp.arange(count), config.hidden)
    k_in, k_layers = (None, None) if key is None else tuple(jax.random.split(key))
    h = encoder_stack(params.layers, dropout(h, config.dropout, k_in), _transformer_options(config),
                      key_padding_mask=mask, dropout_key=k_layers)
    pooled = jnp.sum(jnp.where(mask[..., None], h, 0.0), axis=1) / jnp.maximum(mask.sum(axis=1), 1)[:, None]
    features = jnp.tanh(linear(params.linear1, pooled))
    return linear(params.linear2, features), features


def _stgcn_graph(config: RecognizerConfig, skeleton: Skeleton) -> np.ndarray:
    """The ST-GCN's spatial graph ``[3, J', J']``, centred on ``graph_center`` (ACTOR's evaluator: the root)."""
    return spatial_partition(recognizer_parents(config, skeleton), center=config.graph_center)


def init_recognizer(key: jax.Array, config: RecognizerConfig, skeleton: Skeleton, num_classes: int,
                    frames: int = 60, persons: int = 1) -> dict[str, Any]:
    """Fresh variables ``{"params": ..., ["batch_stats": ...]}``; no size depends on ``frames`` (kept so
    every architecture's init has one signature). ``persons``: P of the motions it will read; the GRU reads
    every person's joints in each frame (its input grows with P), the ST-GCN shares its weights across
    persons and averages their features (ST-GCN's own rule), so its size does not depend on P, unless it
    stacks the persons on channels (``config.persons="channels"``: P·C input channels)."""
    channels, nodes = config.channels_in, len(recognizer_parents(config, skeleton))
    if config.architecture == "gru":
        return {"params": init_gru_recognizer(key, persons * nodes * channels, num_classes, config.hidden,
                                              config.layers, config.feature_dim)}
    if config.architecture == "transformer":
        keys = jax.random.split(key, 4)
        return {"params": TransformerRecognizerParams(
            init_linear(keys[0], persons * nodes * channels, config.hidden),
            init_encoder_stack(keys[1], config.layers, config.hidden, 4 * config.hidden),
            init_linear(keys[2], config.hidden, config.feature_dim),
            init_linear(keys[3], config.feature_dim, num_classes))}
    if config.persons == "channels":
        channels *= persons
    params, stats = init_stgcn(key, _stgcn_graph(config, skeleton), channels, num_classes, channels=config.channels,
                               strides=config.strides, temporal_kernel=config.temporal_kernel)
    return {"params": params, "batch_stats": stats}


def apply_recognizer(config: RecognizerConfig, skeleton: Skeleton, num_classes: int, variables: Mapping[str, Any],
                     x: jax.Array, lengths: jax.Array | None = None, *, train: bool = False,
                     key: jax.Array | None = None) -> tuple[tuple[jax.Array, jax.Array], dict[str, Any]]:
    """``x [B, T, J, C]`` or ``[B, P, T, J, C]`` (from :func:`recognizer_inputs`) -> ``((logits [B, K],
    features [B, D]), updates)``; the GRU reads the persons of a frame side by side, in their order, the
    ST-GCN averages them or stacks their channels (``config.persons``).

    ``lengths [B]``: the GRU reads each sequence at its last real frame (the ST-GCN pools over all frames,
    as the reference, whose padding repeats the last frame). ``train``: ST-GCN batch statistics from the
    batch (returned in ``updates``) and dropout from ``key``.
    """
    if config.architecture in ("gru", "transformer"):
        if x.ndim == 5:  # [B, P, T, J, C] -> [B, T, P, J, C]: one frame of every person per step
            x = jnp.moveaxis(x, 1, 2)
        frames = x.reshape(*x.shape[:2], -1)
        if config.architecture == "gru":
            return a2m_recognize(variables["params"], frames, lengths), {}
        return transformer_recognize(config, variables["params"], frames, lengths, key if train else None), {}
    if x.ndim == 5 and config.persons == "channels":  # [B, P, T, J, C] -> [B, T, J, P·C], person-major
        x = jnp.moveaxis(x, 1, -2).reshape(*x.shape[:1], *x.shape[2:4], -1)
    outputs, stats = stgcn(variables["params"], variables["batch_stats"], x, _stgcn_graph(config, skeleton),
                           strides=config.strides, train=train, dropout_rate=config.dropout, dropout_key=key)
    return outputs, ({"batch_stats": stats} if train else {})


@dataclasses.dataclass(frozen=True, eq=False)
class Recognizer:
    """A trained evaluator: call it on a batch of motions to get ``(logits [B, K], features [B, D])``.

    ``motions`` is a mapping as :func:`recognizer_inputs` reads it (the pipeline's batches and the
    generators' outputs are such mappings), with an optional ``lengths [B]``. Large sets are processed in
    chunks of ``chunk`` sequences (one shape, one compilation). ``mesh``: a data mesh
    (:func:`jaxmotion.distributed.data_mesh`) over whose devices each chunk is split, the variables
    replicated on it; ``None``: one device.
    """

    config: RecognizerConfig
    skeleton: Skeleton
    class_names: tuple[str, ...]
    variables: Any
    chunk: int = 1000
    mesh: Any = None

    @property
    def num_classes(self) -> int:
        return len(self.class_names)

    def __post_init__(self):
        def forward(variables, motions):
            x = recognizer_inputs(self.config, self.skeleton, motions)
            return apply_recognizer(self.config, self.skeleton, self.num_classes, variables, x,
                                    motions.get("lengths"))[0]

        object.__setattr__(self, "_forward", jax.jit(forward))
        if self.mesh is None:
            object.__setattr__(self, "_variables", self.variables)
        else:
            object.__setattr__(self, "_variables", replicate(self.variables, self.mesh))

    def reading(self, skeleton: Skeleton) -> Recognizer:
        """This recogniser for motions of ``skeleton``: the same network and weights, which a ``joints15``
        recogniser allows for any skeleton that maps onto the 15 joints (an NTU-25 one reading GTA-22)."""
        if skeleton.name == self.skeleton.name:
            return self
        if self.config.topology != "joints15":
            raise ValueError(f"skeleton: this recogniser reads {self.skeleton.name} motions only; one with "
                             f"topology='joints15' reads any skeleton that maps onto the 15 joints")
        joints15_indices(skeleton)  # refuses a skeleton without a mapping
        return dataclasses.replace(self, skeleton=skeleton)

    def __call__(self, motions: Mapping[str, Any], on_chunk: Callable[[int, int], None] | None = None
                 ) -> tuple[jax.Array, jax.Array]:
        """``on_chunk``: progress, as :func:`~jaxmotion.data.pipeline.map_in_chunks` calls it."""
        rows = {k: motions[k] for k in ("joints", "translation", "rotations", "lengths") if motions.get(k) is not None}
        return map_in_chunks(lambda _, part: self._forward(self._variables, part), rows, self.chunk, mesh=self.mesh,
                             on_chunk=on_chunk)
