"""From a packed ``MotionDataset`` to fixed-shape training batches, on device, with explicit keys.

Every function here is pure and jittable; randomness enters as a key. The batch of step ``n`` is a
function of ``(key, n)`` only (``make_batch_fn``), which is what the training loop needs for a resumed
run to see exactly the batches an uninterrupted one would.

Windows are gathered from the packed frame arrays with one index array: a frame index past the end of
a sequence is clipped to its last frame, so "pad by repeating the last frame" (ACTOR, Action2Motion,
ODMO) is the clip itself, and ActFormer's "snake" padding (0..n-1, n-2..1, 0..) is a reflection of the
index. A mask marks the real frames.

Several persons: a dataset of P >= 2 persons gives batches ``[B, P, T, J, 3]``; the persons share each
window's frames, the canonical frame is set by the first person and applied to all (their placement
relative to each other is the data), and ``BatchSpec.permute_persons`` shuffles their order per window
(ActFormer's augmentation).

Axes: N sequences, F packed frames, B batch, P persons, T window, J joints, C channels.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Callable
from typing import Any, Literal

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.config import check_at_least
from jaxmotion.data.motion import ActionItems, MotionDataset
from jaxmotion.distributed import DATA_AXIS, gather, shard_batch
from jaxmotion.geometry.kinematics import canonicalize_transform, transform_motion

Sampling = Literal["epoch", "uniform", "balanced", "sqrt"]
Padding = Literal["last", "snake"]
_HIGHEST = jax.lax.Precision.HIGHEST


# --- which sequences -------------------------------------------------------------------------------


def sequence_weights(actions: jax.Array, num_classes: int, scheme: Sampling) -> jax.Array:
    """Probability of drawing each sequence: ``[N] -> [N]``, summing to 1.

    ``uniform``/``epoch``: every sequence alike (classes by frequency). ``balanced``: every class alike
    (stratified; ODMO's class weights). ``sqrt``: class mass proportional to the square root of its count
    (ActFormer's BABEL resampling).
    """
    counts = jnp.bincount(actions, length=num_classes).astype(jnp.float32)
    if scheme in ("uniform", "epoch"):
        per_class = counts
    elif scheme == "balanced":
        per_class = (counts > 0).astype(jnp.float32)
    elif scheme == "sqrt":
        per_class = jnp.sqrt(counts)
    else:
        raise ValueError(f"scheme: expected one of uniform, epoch, balanced, sqrt; got {scheme!r}")
    # Each sequence gets its class's mass shared among the class's sequences.
    weights = (per_class / jnp.maximum(counts, 1.0))[actions]
    return weights / jnp.sum(weights)


def sample_sequences(key: jax.Array, weights: jax.Array, batch_size: int) -> jax.Array:
    """``batch_size`` sequence indices drawn with replacement from ``weights [N]``: ``[B]`` int32."""
    return jax.random.choice(key, weights.shape[0], (batch_size,), replace=True, p=weights).astype(jnp.int32)


class EpochOrder:
    """Sequence indices ``[B]`` of batch ``step`` when every epoch visits each sequence once, in a fresh order.

    Epoch ``e`` uses the permutation drawn from ``fold_in(key, e)``; a batch that straddles two epochs takes
    the end of one and the start of the next, so within an epoch no sequence is dropped or repeated. The
    indices depend only on ``(key, step)``; the last two permutations are memoised on the host, because
    drawing one per step costs more than the rest of the batch for datasets of ten thousand sequences.
    """

    def __init__(self, key: jax.Array, num_sequences: int, batch_size: int):
        if batch_size > num_sequences:
            raise ValueError(f"EpochOrder: batch_size ({batch_size}) exceeds num_sequences ({num_sequences})")
        self.key, self.num_sequences, self.batch_size = key, num_sequences, batch_size
        self._permutation = functools.lru_cache(maxsize=2)(self._draw)

    def _draw(self, epoch: int) -> np.ndarray:
        return np.asarray(jax.random.permutation(jax.random.fold_in(self.key, epoch), self.num_sequences))

    def __call__(self, step: int) -> np.ndarray:
        position = int(step) * self.batch_size + np.arange(self.batch_size)
        epoch, offset = position // self.num_sequences, position % self.num_sequences
        first = int(epoch[0])
        this, following = self._permutation(first), self._permutation(first + 1)
        return np.where(epoch == first, this[offset], following[offset]).astype(np.int32)


class BucketedEpochOrder:
    """Sequence indices ``[B]`` and the length bucket of batch ``step`` when every batch draws from one bucket of
    similar lengths (:class:`BatchSpec` ``buckets``), so it is padded to that bucket's longest, not the data's.

    Epoch ``e`` visits each sequence once: each bucket's members in the order of a permutation drawn from
    ``fold_in(fold_in(key, e), b)``, cut into batches (a bucket's last batch is filled up from the start of its
    order, so a few sequences come twice), and the epoch's batches in the order of a permutation drawn from
    ``fold_in(key, e)``. Every epoch has the same number of batches; the indices depend only on ``(key, step)``
    (the last two epochs are memoised on the host).
    """

    def __init__(self, key: jax.Array, bucket_of: np.ndarray, batch_size: int):
        self.key, self.batch_size = key, batch_size
        self.members = [np.flatnonzero(bucket_of == b) for b in range(int(bucket_of.max()) + 1)]
        self.per_epoch = sum(-(-len(m) // batch_size) for m in self.members)
        self._epoch = functools.lru_cache(maxsize=2)(self._draw)

    def _draw(self, epoch: int) -> tuple[np.ndarray, np.ndarray]:
        key = jax.random.fold_in(self.key, epoch)
        batches, buckets = [], []
        for b, members in enumerate(self.members):
            order = members[np.asarray(jax.random.permutation(jax.random.fold_in(key, b), len(members)))]
            count = -(-len(order) // self.batch_size)
            batches.append(np.resize(order, count * self.batch_size).reshape(count, self.batch_size))
            buckets.append(np.full(count, b))
        shuffle = np.asarray(jax.random.permutation(key, self.per_epoch))
        return np.concatenate(batches)[shuffle].astype(np.int32), np.concatenate(buckets)[shuffle]

    def __call__(self, step: int) -> tuple[np.ndarray, int]:
        ids, buckets = self._epoch(int(step) // self.per_epoch)
        return ids[int(step) % self.per_epoch], int(buckets[int(step) % self.per_epoch])


def length_buckets(lengths: np.ndarray, buckets: int) -> tuple[np.ndarray, np.ndarray]:
    """Sequences of ``lengths [N]`` in at most ``buckets`` groups of about equal counts by length (the groups'
    bounds at the quantiles; equal lengths never split) -> ``(bucket of each [N], each bucket's longest [K])``."""
    ordered = np.sort(lengths)
    bounds = np.unique(ordered[np.ceil(np.arange(1, buckets + 1) * len(ordered) / buckets).astype(int) - 1])
    bucket_of = np.searchsorted(bounds, lengths)
    return bucket_of, bounds


# --- which frames ----------------------------------------------------------------------------------


def random_lengths(key: jax.Array, lengths: jax.Array, min_length: int, max_length: int) -> jax.Array:
    """Target lengths for variable-length training: ``[B] -> [B]``, uniform in ``[min, min(n, max)]``.

    Sequences shorter than ``min_length`` keep their own length (they are padded, never dropped).
    """
    high = jnp.minimum(lengths, max_length)
    low = jnp.minimum(min_length, high)
    return jax.random.randint(key, lengths.shape, low, high + 1)


def random_crop_starts(key: jax.Array, lengths: jax.Array, window: jax.Array | int) -> jax.Array:
    """Crop starts ``[B]``, uniform in ``[0, n - window]`` inclusive (0 for sequences shorter than it)."""
    return jax.random.randint(key, lengths.shape, 0, jnp.maximum(lengths - window, 0) + 1)


def window_frames(starts: jax.Array, lengths: jax.Array, window: int,
                  padding: Padding = "last") -> tuple[jax.Array, jax.Array]:
    """Packed frame indices ``[B, T]`` of windows over segments, and the mask ``[B, T]`` of real frames.

    Args:
      starts: ``[B]`` packed index of each segment's first frame (sequence offset plus crop start).
      lengths: ``[B]`` frames in each segment (>= 1).
      window: T.
      padding: past the segment's end, ``last`` repeats its last frame, ``snake`` runs back and forth
        over it (ActFormer).
    """
    t = jnp.arange(window)[None, :]
    n = lengths[:, None]
    if padding == "last":
        local = jnp.minimum(t, n - 1)
    elif padding == "snake":
        period = jnp.maximum(2 * (n - 1), 1)
        phase = t % period
        local = jnp.where(phase < n, phase, period - phase)
    else:
        raise ValueError(f"padding: expected 'last' or 'snake', got {padding!r}")
    return starts[:, None] + local, t < n


# --- canonical frame and model inputs --------------------------------------------------------------


def _fold_persons(fn):
    """Lift ``fn(joints [B, T, J, 3], translation [B, T, 3], rotations | None, *args)`` to several persons
    ``[B, P, T, ...]``: the persons' frames run one after another, so frame 0 is the first person's."""

    @functools.wraps(fn)
    def lifted(joints, translation, rotations, *args):
        if joints.ndim == 4:
            return fn(joints, translation, rotations, *args)
        b, p, t = joints.shape[:3]
        fold = lambda a: None if a is None else a.reshape(b, p * t, *a.shape[3:])  # noqa: E731
        unfold = lambda a: None if a is None else a.reshape(b, p, t, *a.shape[2:])  # noqa: E731
        return tuple(unfold(a) for a in fn(fold(joints), fold(translation), fold(rotations), *args))

    return lifted


@_fold_persons
def canonicalize_motion(joints: jax.Array, translation: jax.Array, rotations: jax.Array | None, left_hip: int,
                        right_hip: int) -> tuple[jax.Array, jax.Array, jax.Array | None]:
    """Root of frame 0 to the origin, facing +Z at frame 0 (a rotation about the vertical only).

    ``joints [B, T, J, 3]``, ``translation [B, T, 3]``, ``rotations [B, T, J, 3]`` axis-angle with joint 0
    global (or None); or all three ``[B, P, T, ...]``, the first person's frame 0 setting the map for every
    person. One rigid map moves all three, so FK of the outputs equals the output joints.
    """
    rot, shift = canonicalize_transform(joints, left_hip, right_hip)  # [B, 3, 3], [B, 3]
    new_joints = jnp.einsum("bij,btkj->btki", rot, joints, precision=_HIGHEST) + shift[:, None, None]
    if rotations is None:
        return new_joints, jnp.einsum("bij,btj->bti", rot, translation, precision=_HIGHEST) + shift[:, None], None
    new_rotations, new_translation = transform_motion(rot, shift, rotations, translation)
    return new_joints, new_translation, new_rotations


@_fold_persons
def to_origin(joints: jax.Array, translation: jax.Array, rotations: jax.Array | None = None
              ) -> tuple[jax.Array, jax.Array, jax.Array | None]:
    """Translate so the root of frame 0 is at the origin, without rotating (Action2Motion, ODMO):
    ``[B, T, J, 3], [B, T, 3]`` (or ``[B, P, T, ...]``: the first person's root) -> same; rotations pass
    through."""
    origin = joints[:, :1, 0, :]  # [B, 1, 3]
    return joints - origin[:, :, None], translation - origin, rotations


# --- batches ---------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class BatchSpec:
    """What a batch holds and how it is drawn (part of an experiment's config).

    ``window``: T. ``min_length``: when set, each window holds a random-length segment of
    ``[min_length, min(n, window)]`` frames followed by padding (ACTOR's 60-100 fine-tuning); otherwise a
    segment of ``min(n, window)`` frames. ``canonical``: root of frame 0 at the origin facing +Z;
    otherwise only the root of frame 0 at the origin (Action2Motion, ODMO), or with ``in_place`` the windows where
    they are (Neural Marionette's action items, normalised later at their last context frame). ``permute_persons``:
    each window's persons in a random order (datasets of several persons only). ``buckets``: with more than 1,
    each batch holds sequences of similar lengths, padded to the longest of its length bucket instead of ``window``
    (:class:`BucketedEpochOrder`; ``epoch`` sampling of whole sequences): batches of short actions cost what they
    hold, at one compilation of the training step per bucket.
    """

    batch_size: int
    window: int
    sampling: Sampling = "epoch"
    min_length: int | None = None
    padding: Padding = "last"
    canonical: bool = True
    permute_persons: bool = False
    in_place: bool = False
    buckets: int = 1

    def __post_init__(self):
        check_at_least(self, 1, "batch_size", "window", "buckets")
        if self.buckets > 1 and (self.sampling != "epoch" or self.min_length is not None):
            raise ValueError(f"BatchSpec.buckets: {self.buckets} length buckets batch whole sequences by epoch; "
                             f"expected sampling='epoch' and no min_length, got {self.sampling!r}, "
                             f"{self.min_length}")
        if self.canonical and self.in_place:
            raise ValueError("BatchSpec.in_place: leaves the windows where they are; set canonical=False too")
        if self.min_length is not None and not 1 <= self.min_length <= self.window:
            raise ValueError(f"BatchSpec.min_length must be in [1, window={self.window}], got {self.min_length}")


def _tables(dataset: MotionDataset, spec: BatchSpec, labels: dict[str, np.ndarray] | None = None) -> dict:
    """The dataset as device arrays, plus what a batch gather needs; checks the spec against the data."""
    if len(dataset) == 0:
        raise ValueError(f"{dataset.name}/{dataset.split}: cannot batch an empty dataset")
    names = dataset.skeleton.joint_names
    if spec.canonical and not {"left_hip", "right_hip"} <= set(names):
        raise ValueError(f"{dataset.skeleton.name} names no left_hip/right_hip: use canonical=False")
    if spec.permute_persons and dataset.persons < 2:
        raise ValueError(f"permute_persons: {dataset.name}/{dataset.split} has one person per sequence")
    frames_of = {"joints": jnp.asarray(dataset.joints), "translation": jnp.asarray(dataset.translation)}
    if dataset.rotations is not None:
        frames_of["rotations"] = jnp.asarray(dataset.rotations)
    extra = dict(labels or {})
    for name, values in extra.items():
        if np.shape(values)[:1] != (len(dataset),):
            raise ValueError(f"labels[{name!r}]: expected one row per sequence ([{len(dataset)}, ...]), got shape "
                             f"{np.shape(values)}")
    labels = {k: jnp.asarray(getattr(dataset, k)) for k in ("actions", "modes", "subjects")}
    labels.update({k: jnp.asarray(v) for k, v in extra.items()})
    return {
        "frames": frames_of,
        "labels": labels,
        "starts": jnp.asarray(dataset.starts[:-1], jnp.int32),
        "lengths": jnp.asarray(dataset.lengths, jnp.int32),
        "weights": sequence_weights(labels["actions"], dataset.num_classes, spec.sampling),
        "hips": (names.index("left_hip"), names.index("right_hip")) if spec.canonical else None,
    }


# The dataset enters as an argument, not a closure: captured arrays would be baked into the program as
# constants, which makes compilation and every call slow for large datasets.
@functools.partial(jax.jit, static_argnames=("spec", "hips"))
def _gather(tables: dict, ids: jax.Array, key: jax.Array, spec: BatchSpec, hips: tuple[int, int] | None) -> dict:
    """Windows of sequences ``ids [B]``: lengths, crops, persons' order and canonical frame as ``spec`` says."""
    k_len, k_crop = jax.random.split(key)
    n = tables["lengths"][ids]
    seg = jnp.minimum(n, spec.window) if spec.min_length is None else random_lengths(k_len, n, spec.min_length,
                                                                                      spec.window)
    crops = random_crop_starts(k_crop, n, seg)
    frames, mask = window_frames(tables["starts"][ids] + crops, seg, spec.window, spec.padding)
    out = {k: v[frames] for k, v in tables["frames"].items()}
    if tables["frames"]["joints"].ndim == 4:  # several persons: [B, T, P, ...] -> [B, P, T, ...]
        out = {k: jnp.moveaxis(v, 2, 1) for k, v in out.items()}
        if spec.permute_persons:  # its own key, so the crops match those of an unpermuted batch
            persons = out["joints"].shape[1]
            keys = jax.random.split(jax.random.fold_in(key, 2), ids.shape[0])
            order = jax.vmap(lambda k: jax.random.permutation(k, persons))(keys)  # [B, P]
            out = {k: jnp.take_along_axis(v, order.reshape(order.shape + (1,) * (v.ndim - 2)), axis=1)
                   for k, v in out.items()}
    if not spec.in_place:
        move = (lambda *a: canonicalize_motion(*a, *hips)) if spec.canonical else to_origin
        out["joints"], out["translation"], rotations = move(out["joints"], out["translation"], out.get("rotations"))
        if rotations is not None:
            out["rotations"] = rotations
    return {**out, "mask": mask, "lengths": seg, **{k: v[ids] for k, v in tables["labels"].items()}}


@dataclasses.dataclass(frozen=True)
class PairSpec:
    """Batches of pairs (ODMO's contrastive training): ``batch`` draws the first windows, and each gets a
    partner, with probability ``same_probability`` another sequence of its class (uniform, never itself;
    itself only when its class has no other), else a sequence of another class, drawn ``other``:
    ``uniform`` (every other-class sequence alike: ODMO on HumanAct12 and UESTC) or ``balanced`` (every other
    class alike: ODMO on CMU MoCap)."""

    batch: BatchSpec
    other: Literal["uniform", "balanced"] = "uniform"
    same_probability: float = 0.5

    def __post_init__(self):
        if self.other not in ("uniform", "balanced"):
            raise ValueError(f"PairSpec.other: expected 'uniform' or 'balanced', got {self.other!r}")
        if not 0.0 <= self.same_probability <= 1.0:
            raise ValueError(f"PairSpec.same_probability: expected a probability in [0, 1], got {self.same_probability!r}")


def class_members(actions: np.ndarray, num_classes: int) -> dict[str, jax.Array]:
    """What drawing a partner needs: ``members [C, M]`` (each class's sequence indices, padded with -1),
    ``counts [C]`` and ``rank [N]`` (each sequence's position among its class's members)."""
    actions = np.asarray(actions)
    counts = np.bincount(actions, minlength=num_classes)
    members = np.full((num_classes, max(int(counts.max()), 1)), -1, np.int32)
    rank = np.zeros(len(actions), np.int32)
    for c in range(num_classes):
        ids = np.flatnonzero(actions == c)
        members[c, :ids.size] = ids
        rank[ids] = np.arange(ids.size)
    return {"members": jnp.asarray(members), "counts": jnp.asarray(counts, jnp.int32), "rank": jnp.asarray(rank),
            "actions": jnp.asarray(actions, jnp.int32)}


def draw_partners(key: jax.Array, ids: jax.Array, table: dict[str, jax.Array], other: str,
                  same_probability: float) -> tuple[jax.Array, jax.Array]:
    """A partner for each sequence ``ids [B]`` (see :class:`PairSpec`; ``table`` from :func:`class_members`)
    -> ``(partners [B], same [B])``, ``same`` True where the partner shares the class."""
    k_same, k_within, k_class, k_member = jax.random.split(key, 4)
    classes, counts = table["actions"][ids], table["counts"]
    n = counts[classes]
    # another member of the class: a position among the n − 1 others, skipping the sequence's own
    pick = jax.random.randint(k_within, ids.shape, 0, jnp.maximum(n - 1, 1))
    pick = jnp.where(n > 1, pick + (pick >= table["rank"][ids]), table["rank"][ids])
    same_partner = table["members"][classes, pick]
    # another class (by its share of the sequences, or all alike), then a member of it
    present = counts > 0
    weight = jnp.where(present, counts.astype(jnp.float32) if other == "uniform" else 1.0, 0.0)
    logits = jnp.log(jnp.where(jnp.arange(counts.shape[0])[None] == classes[:, None], 0.0, weight[None]))
    other_class = jax.random.categorical(k_class, logits)
    member = jax.random.randint(k_member, ids.shape, 0, jnp.maximum(counts[other_class], 1))
    other_partner = table["members"][other_class, member]
    has_other = jnp.sum(present) > 1
    same = jax.random.bernoulli(k_same, same_probability, ids.shape) | ~has_other
    return jnp.where(same, same_partner, other_partner), same


def make_batch_fn(dataset: MotionDataset, key: jax.Array, spec: BatchSpec | PairSpec,
                  labels: dict[str, np.ndarray] | None = None) -> Callable[[int], dict[str, jax.Array]]:
    """``step -> batch`` with static shapes, deterministic in ``(key, step)``; the dataset moves to device once.

    The batch is a dict: ``joints [B, T, J, 3]``, ``translation [B, T, 3]``, ``rotations [B, T, J, 3]``
    (when the dataset has them; ``[B, P, T, ...]`` for a dataset of several persons), ``mask [B, T]`` (real frames; padding repeats the segment's last frame or
    snakes, per ``spec.padding``), ``lengths [B]`` (real frames per window), ``actions``, ``modes``,
    ``subjects`` ``[B]``, and each of ``labels`` (per-sequence arrays ``[N, ...]``, e.g. multi-hot tags) as
    ``[B, ...]``. With a :class:`PairSpec`: ``{"first": batch, "second": batch, "same": [B]}``, the partners'
    windows drawn like the first ones'.
    """
    pairs = spec if isinstance(spec, PairSpec) else None
    spec = pairs.batch if pairs is not None else spec
    if spec.sampling == "epoch" and spec.batch_size > len(dataset):
        raise ValueError(f"batch_size ({spec.batch_size}) exceeds the {len(dataset)} sequences of "
                         f"{dataset.name}/{dataset.split}; use sampling='uniform' (with replacement)")
    tables = _tables(dataset, spec, labels)
    # Training on windows every clip only pads; gathering whole clips into a model's window (gather_windows) may.
    longest = int(np.max(dataset.lengths))
    if spec.window > longest:
        raise ValueError(f"window: {spec.window} frames is longer than every clip of {dataset.name}/{dataset.split} "
                         f"(the longest has {longest}): every training window would be mostly padding; choose at "
                         f"most {longest}")
    hips = tables.pop("hips")
    members = class_members(dataset.actions, dataset.num_classes) if pairs is not None else None
    if pairs is not None and spec.buckets > 1:
        raise ValueError("PairSpec.batch.buckets: pairs are drawn with one window; expected 1 bucket")
    order_key, step_key = jax.random.split(key)  # epoch orders are per epoch, not per step
    if spec.buckets > 1:
        bucket_of, longest_of = length_buckets(np.minimum(dataset.lengths, spec.window), spec.buckets)
        epoch_order = BucketedEpochOrder(order_key, bucket_of, spec.batch_size)
        specs = [dataclasses.replace(spec, window=int(w), buckets=1) for w in longest_of]
    else:
        epoch_order = EpochOrder(order_key, len(dataset), spec.batch_size) if spec.sampling == "epoch" else None

    @jax.jit
    def draw_ids(weights, step):
        return sample_sequences(jax.random.fold_in(step_key, step), weights, spec.batch_size)

    @jax.jit
    def partners(table, ids, key):
        return draw_partners(key, ids, table, pairs.other, pairs.same_probability)

    def batch(step):
        # ids and windows use independent keys folded from the step key
        if spec.buckets > 1:
            ids, bucket = epoch_order(step)
            ids, window_spec = jnp.asarray(ids), specs[bucket]
        else:
            ids = jnp.asarray(epoch_order(step) if epoch_order is not None else draw_ids(tables["weights"], step))
            window_spec = spec
        step_stream = jax.random.fold_in(step_key, step)
        first = _gather(tables, ids, jax.random.fold_in(step_stream, 1), window_spec, hips)
        if pairs is None:
            return first
        k_pick, k_windows = jax.random.split(jax.random.fold_in(step_stream, 2))
        second, same = partners(members, ids, k_pick)
        return {"first": first, "second": _gather(tables, second, k_windows, spec, hips), "same": same}

    return batch


def action_item_batches(items: ActionItems, batch_size: int, *, sampling: Sampling = "epoch", buckets: int = 1
                        ) -> tuple[BatchSpec, dict[str, np.ndarray]]:
    """What makes :func:`make_batch_fn` batch whole action items (:meth:`MotionDataset.action_items`), as Neural
    Marionette trains on them: ``make_batch_fn(items.data, key, *action_item_batches(items, batch_size))`` gives
    ``joints``, ``translation``, ``rotations`` ``[B, K + T, ...]`` (the K context frames, then the action, padded
    after its end with its last frame to the longest item's length), ``mask [B, K + T]``, ``lengths [B]`` (K + the
    action's frames), ``tags``, ``next_tags`` ``[B, C]`` bool and ``durations [B]`` (the action's frames); with
    ``buckets`` > 1, items of similar lengths padded to the longest of their bucket (:class:`BatchSpec`). Items stay
    where they are in their take (the floor at y = 0): Marionette normalises at the last context frame itself
    (:func:`~jaxmotion.geometry.kinematics.heading_transform`)."""
    if len(items) == 0:
        raise ValueError(f"items: {items.data.name}/{items.data.split} has no action items to batch")
    spec = BatchSpec(batch_size=batch_size, window=int(items.data.lengths.max()), sampling=sampling,
                     canonical=False, in_place=True, buckets=buckets)
    return spec, {"tags": items.tags, "next_tags": items.next_tags, "durations": items.durations.astype(np.int32)}


def gather_windows(dataset: MotionDataset, ids: np.ndarray, key: jax.Array, spec: BatchSpec,
                   chunk: int = 1024) -> dict[str, np.ndarray]:
    """Windows of the sequences ``ids [N]`` (repeats allowed) as one host batch dict (as a batch of
    :func:`make_batch_fn`), cropped and canonicalised as ``spec`` says; ``spec.batch_size`` and
    ``spec.sampling`` do not apply. Work is done ``chunk`` sequences at a time to bound memory."""
    ids = np.asarray(ids, np.int32)
    if ids.ndim != 1 or ids.size == 0 or ids.min() < 0 or ids.max() >= len(dataset):
        raise ValueError(f"ids: expected a non-empty [N] array of sequence indices in [0, {len(dataset)}), "
                         f"got shape {ids.shape}" + (f" with range [{ids.min()}, {ids.max()}]" if ids.size else ""))
    tables = _tables(dataset, spec)
    hips = tables.pop("hips")
    return map_in_chunks(lambda i, part: _gather(tables, jnp.asarray(part), jax.random.fold_in(key, i), spec, hips),
                         ids, chunk)


def map_in_chunks(fn: Callable[[int, Any], Any], rows: Any, size: int, mesh: Any = None,
                  on_chunk: Callable[[int, int], None] | None = None) -> Any:
    """Apply ``fn(i, chunk_i)`` to consecutive chunks of ``size`` rows of ``rows`` (a pytree of arrays
    sharing a leading axis N) and concatenate its outputs (a pytree of arrays with a leading row axis) on
    the host. The last chunk is padded by repeating its last row, so ``fn`` sees one shape (one
    compilation); the padding's outputs are dropped.

    ``mesh``: a data mesh (:func:`jaxmotion.distributed.data_mesh`); each chunk is then split along its rows
    over the mesh's devices (``size`` rounded up to a multiple of the device count), and the outputs are
    gathered from every device (and process) before they are concatenated. ``None``: one device.

    ``on_chunk(i, chunks)``: called once chunk i (1-based) of ``chunks`` is on the host (progress reports,
    :meth:`jaxmotion.progress.Progress.per_chunk`)."""
    total = jax.tree.leaves(rows)[0].shape[0]
    size = min(size, total)
    place, fetch = (lambda part: part), np.asarray
    if mesh is not None:
        devices = mesh.shape[DATA_AXIS]
        size = -(-size // devices) * devices
        place, fetch = (lambda part: shard_batch(part, mesh)), gather
    parts, chunks = [], -(-total // size)
    for i, first in enumerate(range(0, total, size)):
        count = min(size, total - first)

        def padded(a, first=first, count=count):
            part = np.asarray(a)[first:first + count]
            return np.pad(part, [(0, size - count)] + [(0, 0)] * (part.ndim - 1), mode="edge")

        out = fn(i, place(jax.tree.map(padded, rows)))
        parts.append(jax.tree.map(lambda a, count=count: fetch(a)[:count], out))
        if on_chunk is not None:
            on_chunk(i + 1, chunks)
    return jax.tree.map(lambda *chunks: np.concatenate(chunks), *parts)


def epoch_windows(dataset: MotionDataset, key: jax.Array, spec: BatchSpec, count: int | None = None) -> dict[str, np.ndarray]:
    """One window from each of ``count`` distinct sequences (default: all), as one host batch dict.

    The sequences are a random subset without repetition drawn with ``key`` (ACTOR's "shuffle the real
    set and keep up to 3 000 clips"); windows are cropped and canonicalised as ``spec`` says.
    """
    total = len(dataset)
    count = total if count is None else count
    if not 1 <= count <= total:
        raise ValueError(f"count: expected 1..{total} (the sequences of {dataset.name}/{dataset.split}), got {count}")
    k_ids, k_windows = jax.random.split(key)
    ids = np.asarray(jax.random.permutation(k_ids, total))[:count]
    return gather_windows(dataset, ids, k_windows, spec)


def tiled_windows(dataset: MotionDataset, window: int) -> dict[str, np.ndarray]:
    """ActFormer's real reference set: every clip cut into non-overlapping windows of ``window`` frames at
    ``0, window, 2·window, ...`` while the start is below ``length - window`` (the code's rule: a clip of exactly
    ``window`` frames or fewer gives none), in the data's own frame. Returns a host batch dict like
    :func:`gather_windows` (``joints``, ``translation``, ``rotations`` when present, ``[W, T, ...]`` or ``[W, P,
    T, ...]``; ``mask``, ``lengths``, ``actions``, ``modes``, ``subjects`` ``[W]``); ``sequence [W]`` says which
    clip each window came from. Raises when no clip is long enough."""
    if window < 1:
        raise ValueError(f"window: expected >= 1, got {window}")
    lengths = dataset.lengths
    clip, start = [], []
    for i, n in enumerate(lengths):
        offsets = np.arange(0, max(int(n) - window, 0), window)
        clip.append(np.full(offsets.size, i))
        start.append(dataset.starts[i] + offsets)
    clip, start = np.concatenate(clip).astype(np.int64), np.concatenate(start).astype(np.int64)
    if clip.size == 0:
        raise ValueError(f"window: no clip of {dataset.name}/{dataset.split} is longer than {window} frames")
    frames = start[:, None] + np.arange(window)[None]  # [W, T]
    arrays = {"joints": dataset.joints, "translation": dataset.translation, "rotations": dataset.rotations}
    out = {k: (np.moveaxis(v[frames], 2, 1) if dataset.persons > 1 else v[frames])
           for k, v in arrays.items() if v is not None}
    labels = {"actions": dataset.actions, "modes": dataset.modes, "subjects": dataset.subjects}
    return {**out, "mask": np.ones(frames.shape, bool), "lengths": np.full(clip.size, window, np.int32),
            **{k: v[clip] for k, v in labels.items()}, "sequence": clip}


def class_windows(dataset: MotionDataset, key: jax.Array, spec: BatchSpec, per_class: int) -> dict[str, np.ndarray]:
    """``per_class`` windows of every class present, clips drawn uniformly within the class (without
    repetition while the class has enough clips, with it beyond): ODMO's and ActFormer's class-balanced
    real sets. Rows are grouped by class, in class order."""
    if per_class < 1:
        raise ValueError(f"per_class: expected >= 1, got {per_class}")
    k_ids, k_windows = jax.random.split(key)
    ids = []
    for c in range(dataset.num_classes):
        members = np.flatnonzero(dataset.actions == c)
        if members.size:
            pick = jax.random.choice(jax.random.fold_in(k_ids, c), members.size, (per_class,),
                                     replace=members.size < per_class)
            ids.append(members[np.asarray(pick)])
    return gather_windows(dataset, np.concatenate(ids), k_windows, spec)
