"""ODMO put to use (P-OD §3.3, §4.3, §4.4; OD ``src/modules/ensemble.py``, ``customization/*.py``): the code
bank of real motions, mode discovery, mode-preserving and conventional sampling, the end location from the
nearest real code, interpolation between modes and trajectory customisation by a requested end point.

* :func:`code_bank`: codes ``µ`` of real training windows per class (eval-mode encoder), with each window's
  end root, clip, class and ground-truth style mode: what every sampler and customisation reads.
* :func:`class_modes`: each class's modes, a Gaussian mixture over its codes with K chosen by the
  silhouette rule (:func:`jaxmotion.mixtures.discover_modes_batched`; GMMs keyed from seed 0, as the code's
  ``random_state=0``).
* :func:`sample_codes` with ``sampling="modes"`` (ODMO, mode-preserving): ``n`` codes of a class split
  over its components in proportion to their sizes (components holding ≤ 10 codes get none; the rounding
  remainder goes to the first kept component: :func:`mode_counts`), each drawn from its component's
  Gaussian; ``"conventional"`` (ODMO_conv): one C-component mixture over every class's codes, each class
  kept to the codes in its majority component, the mixture refitted on those (twice, continuing EM, as the
  code's ``warm_start``), and the class's codes drawn from its majority component
  (:func:`conventional_mixture`).
* :func:`nearest_ends`: the end root of the nearest real code of the class (the code's 1-nearest neighbour;
  the paper says "KNN").
* :func:`generate_from_codes`, :func:`sample_motions`, :func:`odmo_sampler`: motions from codes, classes and
  end points; the evaluation protocol's sampler.
* :class:`ODMOGenerator`: a trained ODMO (parameters, the encoder's running statistics, the code bank and the
  mixtures its sampler draws from) as an artefact (:mod:`jaxmotion.pipelines.artefacts`); every function below
  that generates takes one.
* :func:`interpolate_modes`: codes on the segment between two modes' means, decoded (Figure 3's strip).
* :func:`customize_end`: one code sent to many end points (or many codes to one), Figure 4;
  :func:`end_point_trials`: Table 4's population test (dist_e, the hit rate at 10% of the distance).

Motions come back as the library's batch dict (:func:`jaxmotion.data.pipeline.gather_windows`' layout):
``joints [N, T, J, 3]`` (the window's frame: root of frame 0 at the origin), ``translation [N, T, 3]`` (the
root joint's path), ``mask [N, T]``, ``lengths [N]``, ``actions [N]``, plus ``codes [N, Z]``, ``ends [N, 3]``
and, where they come from mixtures, ``components [N]``; :func:`jaxmotion.data.motion.to_dataset` packs one.
Every function takes its randomness from an explicit key.

Where this differs from the code: the mixtures are fitted once per generator (the code refits them in each of
its 10 evaluation repetitions, from fresh code draws), and the bank is drawn once per trained model.

Axes: N motions or codes, T frames, J joints, Z code, C classes, K mixture components.
"""

from __future__ import annotations

import dataclasses
import functools
from pathlib import Path
from typing import Literal, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from jaxmotion.config import check_at_least
from jaxmotion.data.labels import check_actions, check_durations
from jaxmotion.data.motion import MotionDataset
from jaxmotion.data.pipeline import BatchSpec, gather_windows, map_in_chunks, sample_sequences, sequence_weights
from jaxmotion.metrics.apd import mode_homogeneity
from jaxmotion.metrics.clustering import adjusted_rand_index
from jaxmotion.metrics.trajectory import end_point_error, end_point_hit_rate, end_point_squared_error
from jaxmotion.mixtures import (
    MODE_KS,
    GaussianMixture,
    ModesBatch,
    discover_modes_batched,
    fit_gmm,
    gmm_em,
    gmm_predict,
    sample_components,
)
from jaxmotion.models.odmo import (
    ODMOConfig,
    ODMOParams,
    ODMOStats,
    encode,
    flatten_poses,
    generate,
    init_odmo,
    unflatten_poses,
)
from jaxmotion.pipelines.artefacts import Artefact, DataFacts, SamplingGenerator, save_artefact

MIN_MODE_SIZE = 10  # the code gives no samples to components holding this many codes or fewer
GMM_SEED = 0  # the code's random_state


@dataclasses.dataclass(frozen=True)
class CodeBankConfig:
    """How many real windows the samplers' code bank encodes: ``passes`` × ``draws`` class-balanced draws
    (the code: passes over its training loader of 2 048 draws; MoCap 5, HumanAct12 15, UESTC 8), exact
    duplicates dropped (a clip no longer than the window always gives the same window)."""

    passes: int = 15
    draws: int = 2048

    def __post_init__(self):
        check_at_least(self, 1, "passes", "draws")


@dataclasses.dataclass(frozen=True)
class ModeDiscovery:
    """How the samplers find each class's modes (:func:`jaxmotion.mixtures.discover_modes_batched`): the
    silhouette ``rule`` (``"code"``: k 3..9, the authors' code; ``"paper"``: k 3..11) and the GMM restarts."""

    rule: Literal["code", "paper"] = "code"
    n_init: int = 5

    def __post_init__(self):
        if self.rule not in ("code", "paper"):
            raise ValueError(f"ModeDiscovery.rule: expected 'code' or 'paper', got {self.rule!r}")
        check_at_least(self, 1, "n_init")


class CodeBank(NamedTuple):
    """Codes of real training windows (exact duplicates dropped) and what each came from."""

    codes: np.ndarray  # [N, Z] µ of the window (eval-mode encoder)
    ends: np.ndarray  # [N, 3] the window's end root
    actions: np.ndarray  # [N] class
    clips: np.ndarray  # [N] index of the clip in the training set
    modes: np.ndarray  # [N] the clip's ground-truth style mode (-1 where unknown)

    def of_class(self, action: int) -> np.ndarray:
        """Rows of class ``action``."""
        return np.flatnonzero(self.actions == action)


@functools.partial(jax.jit, static_argnames=("config",))
def _encode_rows(params: ODMOParams, stats: ODMOStats, joints: jax.Array, config: ODMOConfig) -> jax.Array:
    return encode(config, params, stats, flatten_poses(joints), train=False)[0]


def encode_windows(params: ODMOParams, stats: ODMOStats, config: ODMOConfig, joints: np.ndarray,
                   chunk: int = 1024) -> np.ndarray:
    """Code means of windows ``joints [N, T, J, 3]`` -> ``µ [N, Z]`` (eval mode, ``chunk`` at a time)."""
    joints = np.asarray(joints, np.float32)
    if joints.ndim != 4 or joints.shape[1:] != (config.num_frames, config.num_joints, 3):
        raise ValueError(f"joints: expected [N, {config.num_frames}, {config.num_joints}, 3], got {joints.shape}")
    return map_in_chunks(lambda _, part: _encode_rows(params, stats, jnp.asarray(part), config), joints, chunk)


def code_bank(params: ODMOParams, stats: ODMOStats, config: ODMOConfig, data: MotionDataset, key: jax.Array, *,
              bank: CodeBankConfig = CodeBankConfig(), canonical: bool = True) -> CodeBank:
    """The codes of ``bank.passes × bank.draws`` class-balanced random windows of ``data`` (in the canonical
    frame, or only moved to the origin: the training windows' frame), duplicates dropped, in class order."""
    k_ids, k_windows = jax.random.split(key)
    weights = sequence_weights(jnp.asarray(data.actions), data.num_classes, "balanced")
    ids = np.asarray(sample_sequences(k_ids, weights, bank.passes * bank.draws))
    spec = BatchSpec(batch_size=1, window=config.num_frames, canonical=canonical)
    windows = gather_windows(data, ids, k_windows, spec)
    codes = encode_windows(params, stats, config, windows["joints"])
    _, first = np.unique(codes, axis=0, return_index=True)
    keep = np.sort(first)
    keep = keep[np.argsort(windows["actions"][keep], kind="stable")]
    return CodeBank(codes[keep], windows["joints"][keep, -1, 0], windows["actions"][keep].astype(np.int32),
                    ids[keep].astype(np.int32), windows["modes"][keep].astype(np.int32))


# ------------------------------------------------------------------------------------------------ mixtures


def padded_classes(bank: CodeBank, num_classes: int) -> tuple[np.ndarray, np.ndarray]:
    """The bank's codes per class, padded: ``codes [C, M, Z]`` and ``mask [C, M]`` (M: the largest class)."""
    rows = [bank.of_class(c) for c in range(num_classes)]
    width = max(len(r) for r in rows)
    codes = np.zeros((num_classes, width, bank.codes.shape[1]), np.float32)
    mask = np.zeros((num_classes, width), bool)
    for c, r in enumerate(rows):
        codes[c, :len(r)], mask[c, :len(r)] = bank.codes[r], True
    return codes, mask


def class_modes(bank: CodeBank, num_classes: int, *, rule: str = "code", n_init: int = 5,
                key: jax.Array | None = None) -> ModesBatch:
    """Every class's modes, all classes fitted together: labels ``[C, M]`` follow :func:`padded_classes`'
    rows (-1 on padding). ``key``: the GMMs' (default: seed 0, the code's ``random_state``).

    A class with no more codes than the rule's largest k (tiny banks: smoke runs) cannot be scored by the
    silhouette rule (the code fails there); it gets one mode, the Gaussian of its codes."""
    codes, mask = padded_classes(bank, num_classes)
    key = jax.random.key(GMM_SEED) if key is None else key
    ks = tuple(MODE_KS[rule])
    counts = mask.sum(1)
    fitted = np.flatnonzero(counts > ks[-1])
    if fitted.size == num_classes:
        return discover_modes_batched(key, jnp.asarray(codes), jnp.asarray(mask), rule=rule, n_init=n_init)
    width = codes.shape[-1]
    weights = np.zeros((num_classes, ks[-1]), np.float32)
    means = np.zeros((num_classes, ks[-1], width), np.float32)
    covariances = np.broadcast_to(np.eye(width, dtype=np.float32), (num_classes, ks[-1], width, width)).copy()
    labels = np.where(mask, 0, -1).astype(np.int32)
    chosen = np.ones(num_classes, np.int64)
    silhouettes = np.full((num_classes, len(ks)), np.nan)
    for c in np.flatnonzero(counts <= ks[-1]):
        x = codes[c, mask[c]].astype(np.float64)
        weights[c, 0], means[c, 0] = 1.0, x.mean(0)
        covariances[c, 0] = np.cov(x.T, bias=True).reshape(width, width) + 1e-6 * np.eye(width)
    if fitted.size:
        part = discover_modes_batched(key, jnp.asarray(codes[fitted]), jnp.asarray(mask[fitted]), rule=rule,
                                      n_init=n_init)
        chosen[fitted], silhouettes[fitted], labels[fitted] = part.k, part.silhouettes, np.asarray(part.labels)
        weights[fitted], means[fitted] = np.asarray(part.gmm.weights), np.asarray(part.gmm.means)
        covariances[fitted] = np.asarray(part.gmm.covariances)
    gmm = GaussianMixture(jnp.asarray(weights), jnp.asarray(means), jnp.asarray(covariances))
    return ModesBatch(chosen, gmm, jnp.asarray(labels), silhouettes, ks)


def bank_labels(bank: CodeBank, modes: ModesBatch) -> np.ndarray:
    """Each bank row's discovered mode (its class's component), ``[N]``, from :func:`class_modes`' labels."""
    labels = np.full(len(bank.codes), -1, np.int32)
    padded = np.asarray(modes.labels)
    for c in range(padded.shape[0]):
        rows = bank.of_class(c)
        labels[rows] = padded[c, :len(rows)]
    return labels


def mode_counts(sizes: np.ndarray, n: int, min_size: int = MIN_MODE_SIZE) -> np.ndarray:
    """The code's split of ``n`` samples over components of ``sizes [K]`` codes: none for components of
    ``≤ min_size`` codes, ``⌊n · size / Σ kept⌋`` for the others, the remainder to the first kept one.
    When no component is larger than ``min_size`` (tiny banks), every non-empty one is kept."""
    sizes = np.asarray(sizes, np.int64)
    kept = sizes > min_size
    if not kept.any():
        kept = sizes > 0
    weights = np.where(kept, sizes, 0)
    counts = (weights / weights.sum() * n).astype(np.int64)
    counts[np.flatnonzero(kept)[0]] += n - counts.sum()
    return counts


class Conventional(NamedTuple):
    """ODMO_conv's mixture: one component per class (``mapping[c]``: class c's component)."""

    gmm: GaussianMixture
    mapping: np.ndarray  # [C]


def _majority(labels: np.ndarray, actions: np.ndarray, num_classes: int, k: int) -> np.ndarray:
    return np.array([np.bincount(labels[actions == c], minlength=k).argmax() for c in range(num_classes)])


def conventional_mixture(bank: CodeBank, num_classes: int, *, key: jax.Array | None = None) -> Conventional:
    """The code's ``create_GMM``: a C-component GMM over all codes (k-means init, tol 1e-4, 200 iterations),
    each class filtered to its majority component, the GMM refitted twice from where it stood on the
    filtered codes, and each class mapped to its majority component after that."""
    key = jax.random.key(GMM_SEED) if key is None else key
    codes = jnp.asarray(bank.codes)
    gmm = fit_gmm(key, codes, num_classes, max_iter=200, tol=1e-4)
    labels = np.asarray(gmm_predict(gmm, codes))
    majority = _majority(labels, bank.actions, num_classes, num_classes)
    keep = labels == majority[bank.actions]
    filtered = codes[np.flatnonzero(keep)]
    for _ in range(2):
        gmm = gmm_em(filtered, gmm.weights, gmm.means, gmm.covariances, max_iter=200, tol=1e-4)
    mapping = _majority(np.asarray(gmm_predict(gmm, filtered)), bank.actions[keep], num_classes, num_classes)
    return Conventional(gmm, mapping)


def sample_codes(key: jax.Array, actions: np.ndarray, mixtures: ModesBatch | Conventional) -> tuple[np.ndarray, np.ndarray]:
    """Codes for ``actions [N]`` -> ``(codes [N, Z], components [N])``. Mode-preserving (a
    :class:`~jaxmotion.mixtures.ModesBatch`): each class's rows split by :func:`mode_counts` over its modes;
    conventional (:class:`Conventional`): each class's component. Class c draws from ``fold_in(key, c)``."""
    actions = np.asarray(actions)
    width = mixtures.gmm.means.shape[-1]
    codes, components = np.zeros((len(actions), width), np.float32), np.zeros(len(actions), np.int32)
    for c in np.unique(actions):
        rows = np.flatnonzero(actions == c)
        key_c = jax.random.fold_in(key, int(c))
        if isinstance(mixtures, Conventional):
            gmm = mixtures.gmm
            component = int(mixtures.mapping[c])
            counts = np.zeros(gmm.weights.shape[0], np.int64)
            counts[component] = len(rows)
        else:
            gmm = GaussianMixture(mixtures.gmm.weights[c], mixtures.gmm.means[c], mixtures.gmm.covariances[c])
            k = int(mixtures.k[c])
            labels = np.asarray(mixtures.labels[c])
            sizes = np.bincount(labels[labels >= 0], minlength=gmm.weights.shape[0])
            counts = mode_counts(sizes[:k], len(rows))
            counts = np.concatenate([counts, np.zeros(gmm.weights.shape[0] - k, np.int64)])
        drawn, which = sample_components(key_c, gmm, jnp.asarray(counts, jnp.int32), len(rows))
        codes[rows], components[rows] = np.asarray(drawn), np.asarray(which)
    return codes, components


def nearest_ends(bank: CodeBank, codes: np.ndarray, actions: np.ndarray) -> np.ndarray:
    """The end root of each code's nearest real code of its class: ``[N, Z], [N] -> [N, 3]``."""
    codes, actions = np.asarray(codes, np.float32), np.asarray(actions)
    ends = np.zeros((len(codes), 3), np.float32)
    for c in np.unique(actions):
        rows, real = np.flatnonzero(actions == c), bank.of_class(int(c))
        if real.size == 0:
            raise ValueError(f"actions: class {c} has no code in the bank to take an end point from")
        d = np.square(codes[rows, None, :] - bank.codes[None, real, :]).sum(-1)
        ends[rows] = bank.ends[real[np.argmin(d, axis=1)]]
    return ends


# ---------------------------------------------------------------------------------------------- generation


@functools.partial(jax.jit, static_argnames=("config",))
def _generate_rows(params: ODMOParams, codes: jax.Array, actions: jax.Array, ends: jax.Array, config: ODMOConfig):
    return generate(config, params, codes, actions, ends)


def generate_from_codes(params: ODMOParams, config: ODMOConfig, codes, actions, ends, *, chunk: int = 2048
                        ) -> dict[str, np.ndarray]:
    """Motions from ``codes [N, Z]``, ``actions [N]`` and requested end roots ``ends [N, 3]`` (the batch dict
    of the module docstring, with the trajectory generator's path as ``trajectory [N, T, 3]``).

    At most ``chunk`` rows per compiled call, in chunks of equal size (the last one is padded): the
    recurrences' matrix products run faster on more rows (3 000 HumanAct12 motions on 2 CPU cores: 2.2-2.5 s
    in chunks of 512, 1.9 s in chunks of 1 500 or more); the trajectory generator's first layer holds
    ``chunk × in·(T−1)`` floats (UESTC: 2 048 × 803·59, 390 MB)."""
    codes, ends = np.asarray(codes, np.float32), np.asarray(ends, np.float32)
    actions = np.asarray(actions)
    if codes.ndim != 2 or codes.shape[1] != config.code_dim:
        raise ValueError(f"codes: expected [N, {config.code_dim}], got {codes.shape}")
    n = len(codes)
    if n == 0:
        raise ValueError("codes: expected at least one code, got none")
    if actions.shape != (n,) or ends.shape != (n, 3):
        raise ValueError(f"actions, ends: expected [{n}] and [{n}, 3], got {actions.shape} and {ends.shape}")
    check_actions(actions, config.num_classes)
    size = -(-n // -(-n // chunk))  # the fewest chunks of at most `chunk` rows, as equal as can be
    out = map_in_chunks(lambda _, rows: _generate_rows(params, *(jnp.asarray(a) for a in rows), config),
                        (codes, actions, ends), size)
    joints = np.asarray(unflatten_poses(out["poses"]))
    t = config.num_frames
    return {"joints": joints, "translation": joints[:, :, 0].copy(), "mask": np.ones((n, t), bool),
            "lengths": np.full(n, t, np.int32), "actions": actions.astype(np.int32), "codes": codes, "ends": ends,
            "trajectory": out["trajectory"]}


Sampling = Literal["modes", "conventional"]


def fit_mixtures(bank: CodeBank, num_classes: int, sampling: Sampling = "modes",
                 modes: ModeDiscovery = ModeDiscovery()) -> ModesBatch | Conventional:
    """The mixtures a sampler draws codes from: each class's modes (``"modes"``, ODMO) or the one C-component
    mixture (``"conventional"``, ODMO_conv)."""
    if sampling == "conventional":
        return conventional_mixture(bank, num_classes)
    if sampling != "modes":
        raise ValueError(f"sampling: expected 'modes' or 'conventional', got {sampling!r}")
    return class_modes(bank, num_classes, rule=modes.rule, n_init=modes.n_init)


@dataclasses.dataclass(frozen=True, eq=False)
class ODMOGenerator(SamplingGenerator):
    """A trained ODMO: model, parameters, the encoder's running statistics (``buffers``), the code bank of real
    training windows, the mixtures its sampler draws codes from (:func:`fit_mixtures`) and the data facts."""

    model: ODMOConfig
    params: ODMOParams
    buffers: ODMOStats
    bank: CodeBank
    mixtures: ModesBatch | Conventional
    facts: DataFacts
    method = "odmo"

    def __post_init__(self):
        if self.model.num_joints != self.facts.skeleton.num_joints:
            raise ValueError(f"skeleton: the model has {self.model.num_joints} joints, {self.facts.skeleton.name} "
                             f"has {self.facts.skeleton.num_joints}")

    @property
    def frames(self) -> int:
        return self.model.num_frames

    def sampler(self):
        return odmo_sampler(self)

    def save(self, folder: str | Path) -> Path:
        conventional = isinstance(self.mixtures, Conventional)
        mixtures = (self.mixtures if conventional
                    else self.mixtures._replace(ks=()))  # the ks are settings, not arrays
        settings = {"mixtures": "conventional" if conventional else "modes",
                    **({} if conventional else {"ks": list(self.mixtures.ks)})}
        return save_artefact(folder, self.method, self.model, self.facts,
                             {"params": self.params, "buffers": self.buffers, "bank": self.bank,
                              "mixtures": mixtures}, settings)

    @classmethod
    def load(cls, artefact: Artefact) -> ODMOGenerator:
        params, buffers = jax.eval_shape(lambda k: init_odmo(k, artefact.model), jax.random.key(0))
        bank = artefact.tree("bank", CodeBank(*[0] * len(CodeBank._fields)))
        gmm = GaussianMixture(*[0] * len(GaussianMixture._fields))
        if artefact.settings["mixtures"] == "conventional":
            mixtures = artefact.tree("mixtures", Conventional(gmm, 0))
        else:
            mixtures = artefact.tree("mixtures", ModesBatch(0, gmm, 0, 0, ()))._replace(
                ks=tuple(artefact.settings["ks"]))
        return cls(artefact.model, artefact.tree("params", params), artefact.tree("buffers", buffers), bank, mixtures,
                   artefact.facts)


def sample_motions(generator: ODMOGenerator, key: jax.Array, actions, *,
                   mixtures: ModesBatch | Conventional | None = None) -> dict[str, np.ndarray]:
    """ODMO's generation: codes for ``actions [N]`` from the mixtures (default: the generator's), each code's
    end point from the nearest real code, decoded. Adds ``components [N]``."""
    actions = np.asarray(actions)
    check_actions(actions, generator.model.num_classes)
    codes, components = sample_codes(key, actions, generator.mixtures if mixtures is None else mixtures)
    ends = nearest_ends(generator.bank, codes, actions)
    return {**generate_from_codes(generator.params, generator.model, codes, actions, ends), "components": components}


def odmo_sampler(generator: ODMOGenerator):
    """The evaluation protocol's sampler ``(key, actions [N], durations [N]) -> motions``: every call draws
    codes from the generator's mixtures and decodes them (:func:`sample_motions`). ODMO generates
    ``model.num_frames`` frames: other durations are refused."""
    frames = generator.model.num_frames

    def sampler(key, actions, durations):
        check_durations(durations, len(actions))
        durations = np.asarray(durations)
        if np.any(durations != frames):
            raise ValueError(f"durations: ODMO generates {frames} frames; got {sorted(set(durations.tolist()))}")
        out = sample_motions(generator, key, actions)
        return {k: out[k] for k in ("joints", "translation", "mask", "lengths", "actions")}

    return sampler


# ---------------------------------------------------------------------------------------------- customisation


def interpolate_modes(generator: ODMOGenerator, action: int, mode_a: int, mode_b: int, steps: int,
                      modes: ModesBatch | None = None) -> dict[str, np.ndarray]:
    """Figure 3's strip: ``steps`` codes evenly spaced from mode ``mode_a``'s mean to ``mode_b``'s (of class
    ``action``), each with its nearest real end point, decoded; adds ``weights [steps]`` (0 at ``mode_a``).
    ``modes``: default the generator's mixtures when they are modes, else each class's modes fitted now."""
    if modes is None:
        modes = (generator.mixtures if isinstance(generator.mixtures, ModesBatch)
                 else fit_mixtures(generator.bank, generator.model.num_classes))
    k = int(modes.k[action])
    if not (0 <= mode_a < k and 0 <= mode_b < k):
        raise ValueError(f"mode_a, mode_b: class {action} has {k} modes (0..{k - 1}), got {mode_a}, {mode_b}")
    if steps < 2:
        raise ValueError(f"steps: expected >= 2, got {steps}")
    means = np.asarray(modes.gmm.means[action])
    weights = np.linspace(0.0, 1.0, steps, dtype=np.float32)
    codes = (1 - weights[:, None]) * means[mode_a] + weights[:, None] * means[mode_b]
    actions = np.full(steps, action, np.int32)
    out = generate_from_codes(generator.params, generator.model, codes, actions,
                              nearest_ends(generator.bank, codes, actions))
    return {**out, "weights": weights}


def customize_end(generator: ODMOGenerator, codes, action: int, ends) -> dict[str, np.ndarray]:
    """Figure 4: motions of class ``action`` that should end at ``ends [N, 3]``; ``codes`` ``[N, Z]``, or one
    code ``[Z]`` sent to every end (one style, many destinations)."""
    ends = np.asarray(ends, np.float32)
    codes = np.asarray(codes, np.float32)
    if codes.ndim == 1:
        codes = np.broadcast_to(codes, (len(ends), codes.shape[0]))
    return generate_from_codes(generator.params, generator.model, codes, np.full(len(ends), action, np.int32), ends)


def end_point_trials(generator: ODMOGenerator, key: jax.Array, *, trials: int = 40, points: int = 10,
                     threshold: float = 0.1) -> dict[str, np.ndarray]:
    """Table 4's test (OD ``trajectory_customization.py``): per class, ``trials`` times, a random real code
    of the class and ``points`` end points evenly spaced from that window's own end root to the end root of
    another random real window of the class (the authors' first end point is the source's); each pair decoded
    and its final root compared with the requested end.

    Returns the motions (the batch dict, ``trials · points`` per class, in class order) and ``dist_e`` (the
    code's metric, :func:`~jaxmotion.metrics.trajectory.end_point_error`: mean over classes of the mean
    squared end error, m²), ``hit_rate`` (:func:`~jaxmotion.metrics.trajectory.end_point_hit_rate` at
    ``threshold``), ``end_error`` (mean over classes of the mean Euclidean error, m), ``squared_error [N]``
    and two diagnostics of where the error comes from: ``path_end_error`` (``end_error`` of the trajectory
    generator's path instead of the motion's root, m) and ``end_response`` (:func:`end_response` of the
    motions' final roots: 1 when they move with the requested end, 0 when they ignore it)."""
    bank, config = generator.bank, generator.model
    codes, ends, actions = [], [], []
    for c in range(config.num_classes):
        rows = bank.of_class(c)
        if rows.size == 0:
            raise ValueError(f"generator: class {c} has no code in its bank (its training data had no clip of it), "
                             "so there are no real end points to steer between")
        pick = np.asarray(jax.random.randint(jax.random.fold_in(key, c), (trials, 2), 0, len(rows)))
        source, end_b = rows[pick[:, 0]], rows[pick[:, 1]]
        w = np.linspace(0.0, 1.0, points, dtype=np.float32)[None, :, None]
        ends.append(((1 - w) * bank.ends[source][:, None] + w * bank.ends[end_b][:, None]).reshape(-1, 3))
        codes.append(np.repeat(bank.codes[source], points, axis=0))
        actions.append(np.full(trials * points, c, np.int32))
    codes, ends, actions = np.concatenate(codes), np.concatenate(ends), np.concatenate(actions)
    motions = generate_from_codes(generator.params, config, codes, actions, ends)
    joints, classes = jnp.asarray(motions["joints"]), config.num_classes
    squared = np.asarray(end_point_squared_error(joints, ends))
    path_distance = np.linalg.norm(motions["trajectory"][:, -1] - ends, axis=-1)

    def class_mean(values):
        return float(np.mean([values[actions == c].mean() for c in range(classes)]))

    return {"motions": motions, "squared_error": squared,
            "dist_e": float(end_point_error(joints, ends, actions, classes)),
            "hit_rate": float(end_point_hit_rate(joints, ends, actions, classes, threshold)),
            "end_error": class_mean(np.sqrt(squared)), "path_end_error": class_mean(path_distance),
            "end_response": end_response(motions["joints"][:, -1, 0].reshape(-1, points, 3),
                                         ends.reshape(-1, points, 3))}


def end_response(finals: np.ndarray, ends: np.ndarray) -> float:
    """How far the final roots ``finals [N, P, 3]`` move per metre the requested ends ``ends [N, P, 3]`` move,
    along each of N sweeps of P end points made with one code: the least-squares slope of the final root's
    displacement from the sweep's first on the request's (1: the motion goes where it is sent; 0: the code
    alone decides where it ends). A motion can end near its targets and still ignore them, when the targets
    lie near where the code's window ended; this tells the two apart."""
    requested = ends - ends[:, :1]
    moved = finals - finals[:, :1]
    scale = float(np.sum(requested * requested))
    if scale == 0.0:
        raise ValueError("ends: every sweep's end points coincide; the response is undefined")
    return float(np.sum(requested * moved) / scale)


# ---------------------------------------------------------------------------------------------- modes scored


def score_modes(codes: np.ndarray, actions: np.ndarray, true_modes: np.ndarray, joints: np.ndarray, num_classes: int,
                *, rule: str = "code", n_init: int = 5, key: jax.Array | None = None) -> dict[str, np.ndarray]:
    """How well the modes discovered in any model's codes of real windows match the motions (Table 3) and the
    ground-truth style modes (the embedded data's): ``codes [N, Z]`` (ODMO's µ, ACTOR's posterior means...),
    ``actions [N]``, ``true_modes [N]`` (-1 where unknown), ``joints [N, T, J, 3]`` the windows.

    Returns ``labels [N]`` (each window's discovered mode), ``k [C]``, ``mode_homogeneity`` (ODMO's, %:
    :func:`~jaxmotion.metrics.apd.mode_homogeneity` with the discovered modes) and ``ari [C]`` (the adjusted
    Rand index of discovered against true modes per class; NaN for a class without true modes)."""
    codes, actions, true_modes = np.asarray(codes, np.float32), np.asarray(actions), np.asarray(true_modes)
    if codes.ndim != 2 or np.shape(joints)[:1] != (len(codes),) or np.ndim(joints) != 4:
        raise ValueError(f"score_modes: expected codes [N, Z] and joints [N, T, J, 3] of the same N, got "
                         f"{codes.shape} and {np.shape(joints)}")
    check_actions(actions, num_classes, count=len(codes), where="score_modes: actions")
    if true_modes.shape != (len(codes),) or not np.issubdtype(true_modes.dtype, np.integer) or true_modes.min(
            initial=0) < -1:
        raise ValueError(f"score_modes: true_modes: expected [{len(codes)}] integer modes (-1: unknown), got "
                         f"{true_modes.dtype} {true_modes.shape} from {true_modes.min(initial=0)}")
    bank = CodeBank(codes, np.zeros((len(codes), 3), np.float32), actions.astype(np.int32),
                    np.arange(len(codes), dtype=np.int32), true_modes.astype(np.int32))
    order = np.argsort(actions, kind="stable")  # the bank's rows in class order, as class_modes reads them
    bank = CodeBank(*(a[order] for a in bank))
    modes = class_modes(bank, num_classes, rule=rule, n_init=n_init, key=key)
    labels = np.empty(len(codes), np.int32)
    labels[order] = bank_labels(bank, modes)
    width = int(max(modes.k.max(), 1))
    homogeneity = float(mode_homogeneity(jnp.asarray(joints), jnp.asarray(actions, jnp.int32),
                                         jnp.asarray(labels), num_classes, width))
    ari = np.full(num_classes, np.nan)
    for c in range(num_classes):
        rows = np.flatnonzero((actions == c) & (true_modes >= 0))
        if rows.size:
            ari[c] = float(adjusted_rand_index(true_modes[rows], labels[rows], int(true_modes[rows].max()) + 1, width))
    return {"labels": labels, "k": np.asarray(modes.k), "mode_homogeneity": homogeneity, "ari": ari}
