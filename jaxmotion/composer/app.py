"""What the composer's page asks of a trained model, as functions over a loaded generator (no HTTP here).

A **request** is JSON: ``{"actions": [{"tags": ["Walk"], "seconds": 2.0, "path": [[0, 0], [1, 2], [3, 2], [4, 0]]},
{"tags": ["Kick"], "frames": 45}, ...], "seed": 0, "shadow": "revision", "smoothing": 6, "mean": false}``. Each
action has its tags (names as the model knows them, any case), its duration (``seconds`` or ``frames``: one of the
two, 1 frame to the model's longest), and for an action that moves the root optionally ``path``: the control points
``[x, z]`` (metres, world frame: the character starts over the origin facing +z) of the Bézier curve its root
follows, sampled at t = n/T (the supplement's §5.2: the page fits a cubic to each drawn segment, so four points;
two make a straight line). ``shadow``: Table 5's system, ``revision`` (Neural Marionette: Shadow Start on Action
Revision; the default), ``always`` or ``never`` (the pure pipeline); ``smoothing``: frames over which an action that
starts from its shadow, or turned, is blended in (the paper's interface does so; 6 by default, 0 off);
``orientation``: the interface's start orientation check (the supplement's §5.2, on by default:
:class:`~jaxmotion.pipelines.multi_action.ChainOptions`); ``seed`` draws the start and every Z; ``mean`` sets
Z = mu. Anything else is a :class:`RequestError` whose message names the action and the field.

:class:`Composer` generates one request at a time (a lock: a second one waits its turn, and is told so), every action
padded to the model's longest so that any program reuses the compilation made at start-up (:meth:`Composer.warm_up`),
keeps the last motions for download (BVH, AMASS npz, joints npy, the segment table) and reports each action as it is
done. Given an SMPL-format body model, it also sends the page the mesh (:meth:`Composer.body`) and, with each
motion, every frame's skinning transforms (:func:`~jaxmotion.geometry.body.skinning_transforms`: 24 x 12 numbers a
frame), so the page skins the mesh itself.
"""

from __future__ import annotations

import collections
import dataclasses
import itertools
import json
import math
import tempfile
import threading
from collections.abc import Callable
from pathlib import Path
from typing import Any

import jax
import numpy as np

from jaxmotion.compose import canonical_tag, compose, unseen_pairs
from jaxmotion.data.export import AmassOptions, ExportOptions, export_motions
from jaxmotion.data.mag_tags import root_tag_mask
from jaxmotion.data.segments import Program, ProgramAction
from jaxmotion.geometry.body import BodyModel, root_translation, skinning_transforms
from jaxmotion.geometry.rotations import axis_angle_to_matrix
from jaxmotion.geometry.skeletons import SMPL24
from jaxmotion.pipelines.marionette import ContextGenerator
from jaxmotion.pipelines.multi_action import ChainOptions, bezier_path

#: The most actions, and control points per path, a request may hold (a page draws far fewer).
MAX_ACTIONS = 100
MAX_POINTS = 64
SHADOW_MODES = ("revision", "always", "never")
#: Download names: the motion in each export format, and its segment table.
DOWNLOADS = {"motion.bvh": ("bvh", "text/plain"), "motion.npz": ("npz", "application/octet-stream"),
             "motion.npy": ("npy", "application/octet-stream"), "segments.json": (None, "application/json")}
_ACTION_FIELDS = {"tags", "seconds", "frames", "path"}
_REQUEST_FIELDS = {"actions", "seed", "shadow", "smoothing", "orientation", "mean"}


class RequestError(ValueError):
    """A request the composer cannot take; the message names the field. ``status``: the HTTP answer (400 bad request,
    404 unknown motion)."""

    def __init__(self, message: str, status: int = 400):
        super().__init__(message)
        self.status = status


@dataclasses.dataclass(frozen=True)
class Request:
    """A checked request: the :class:`~jaxmotion.data.segments.Program` (paths sampled per frame), each action's
    control points as sent (None: no path), and the settings."""

    program: Program
    controls: tuple[tuple[tuple[float, float], ...] | None, ...]
    seed: int = 0
    options: ChainOptions = ChainOptions("revision", smoothing=6, orientation=True)
    mean: bool = False


def _number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def _integer(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _unknown(fields: dict, known: set[str], where: str) -> None:
    extra = sorted(set(fields) - known)
    if extra:
        raise RequestError(f"{where}: unknown field {extra[0]!r}; expected {', '.join(sorted(known))}")


def read_action(item: Any, index: int, generator: ContextGenerator) -> tuple[ProgramAction, tuple | None]:
    """One action of a request (module docstring) -> the program's action (its path sampled per frame) and its
    control points; a :class:`RequestError` naming ``actions[index]`` and the field."""
    where = f"actions[{index}]"
    if not isinstance(item, dict):
        raise RequestError(f"{where}: expected an object with tags, seconds or frames, and optionally path")
    _unknown(item, _ACTION_FIELDS, where)
    tags = item.get("tags")
    tags = [tags] if isinstance(tags, str) else tags
    if not isinstance(tags, list) or not tags or not all(isinstance(t, str) for t in tags):
        raise RequestError(f"{where}.tags: expected one or more tag names, got {json.dumps(item.get('tags'))}")
    known = []
    for tag in tags:
        try:
            name = canonical_tag(tag, generator.class_names)
        except ValueError as error:
            raise RequestError(f"{where}.tags: {error}") from None
        if name in known:
            raise RequestError(f"{where}.tags: {name!r} given twice")
        known.append(name)
    fps, longest = generator.fps, generator.max_frames
    if ("seconds" in item) == ("frames" in item):
        raise RequestError(f"{where}: expected a duration as seconds or as frames (one of the two)")
    if "seconds" in item:
        if not _number(item["seconds"]):
            raise RequestError(f"{where}.seconds: expected a number, got {json.dumps(item['seconds'])}")
        frames, field = round(item["seconds"] * fps), "seconds"
    else:
        if not _integer(item["frames"]):
            raise RequestError(f"{where}.frames: expected a whole number, got {json.dumps(item['frames'])}")
        frames, field = item["frames"], "frames"
    if not 1 <= frames <= longest:
        raise RequestError(f"{where}.{field}: expected 1 to {longest} frames ({1 / fps:.3g} to {longest / fps:g} s at "
                           f"{fps:g} fps, the model's longest action), got {frames} frames")
    controls = item.get("path")
    if controls is not None:
        if (not isinstance(controls, list) or not 2 <= len(controls) <= MAX_POINTS or not all(
                isinstance(p, list) and len(p) == 2 and all(_number(v) for v in p) for p in controls)):
            raise RequestError(f"{where}.path: expected 2 to {MAX_POINTS} finite ground points [x, z] (the Bézier "
                               f"curve's control points, metres), got {json.dumps(controls)[:200]}")
        controls = tuple((float(x), float(z)) for x, z in controls)
        path = tuple(map(tuple, bezier_path(np.array(controls), frames).tolist()))
    else:
        path = None
    return ProgramAction(tuple(known), int(frames), path), controls


def read_request(payload: Any, generator: ContextGenerator) -> Request:
    """A decoded JSON request (module docstring) -> :class:`Request`; a :class:`RequestError` naming the field."""
    if not isinstance(payload, dict):
        raise RequestError("request: expected a JSON object with 'actions'")
    _unknown(payload, _REQUEST_FIELDS, "request")
    actions = payload.get("actions")
    if not isinstance(actions, list) or not actions:
        raise RequestError("actions: expected a list of one or more actions (the program is empty)")
    if len(actions) > MAX_ACTIONS:
        raise RequestError(f"actions: expected at most {MAX_ACTIONS} actions, got {len(actions)}")
    read = [read_action(item, i, generator) for i, item in enumerate(actions)]
    seed = payload.get("seed", 0)
    if not _integer(seed) or not 0 <= seed < 2 ** 31:
        raise RequestError(f"seed: expected a whole number from 0 to 2^31 - 1, got {json.dumps(seed)}")
    shadow = payload.get("shadow", "revision")
    if shadow not in SHADOW_MODES:
        raise RequestError(f"shadow: expected one of {', '.join(SHADOW_MODES)}, got {json.dumps(shadow)}")
    smoothing = payload.get("smoothing", 6)
    if not _integer(smoothing) or not 0 <= smoothing <= generator.max_frames:
        raise RequestError(f"smoothing: expected a whole number of frames from 0 to {generator.max_frames}, got "
                           f"{json.dumps(smoothing)}")
    flags = {name: payload.get(name, default) for name, default in (("orientation", True), ("mean", False))}
    for name, value in flags.items():
        if not isinstance(value, bool):
            raise RequestError(f"{name}: expected true or false, got {json.dumps(value)}")
    return Request(Program(tuple(action for action, _ in read)), tuple(c for _, c in read), seed,
                   ChainOptions(shadow, smoothing=smoothing, orientation=flags["orientation"]), flags["mean"])


class Composer:
    """A loaded generator serving the page: :meth:`model` (what the page shows), :meth:`generate` (one request at a
    time, progress reported), :meth:`download` (the last ``keep`` motions). ``reviser``: Action Revision's classifier
    (without one, ``shadow: "revision"`` is refused); ``body``: an SMPL-format body model on SMPL's 24-joint tree,
    for the mesh view (:meth:`body`)."""

    def __init__(self, generator: ContextGenerator, reviser: Callable | None = None, *,
                 body: BodyModel | None = None, keep: int = 16):
        if not isinstance(generator, ContextGenerator):
            raise ValueError(f"generator: the composer needs a model that continues a context (MARIONET, MANN, "
                             f"adapted A2M); got a {getattr(generator, 'method', type(generator).__name__)} one")
        if body is not None and tuple(body.parents) != tuple(SMPL24.parents):
            raise ValueError(f"body: expected a body model on SMPL's 24-joint tree, got {body.num_joints} joints "
                             f"with parents {list(body.parents)}")
        self.generator, self.reviser, self.keep, self._body = generator, reviser, keep, body
        # the npz download's trans follows the body model's rest pelvis (AMASS's convention) when there is one
        self._export = ExportOptions() if body is None else ExportOptions(AmassOptions.for_body(body))
        # Shadow Start embeds poses with MARIONET's encoder; Action Revision needs its classifier
        self.shadow_modes = tuple(m for m in SHADOW_MODES if (m != "revision" or reviser is not None)
                                  and (m == "never" or generator.method == "marionet"))
        self._lock = threading.Lock()
        self._motions: collections.OrderedDict[str, dict] = collections.OrderedDict()
        self._ids = itertools.count(1)

    def model(self) -> dict:
        """The page's facts: tags (and which move the root), frame rate, longest action, the skeleton's parents,
        which tag pairs training saw (``seen[a][b]``: b followed a), the systems on offer."""
        g = self.generator
        return {"method": g.method, "tags": list(g.class_names), "root_tags": root_tag_mask(g.class_names).tolist(),
                "fps": g.fps, "max_frames": g.max_frames, "parents": [int(p) for p in g.facts.skeleton.parents],
                "seen": (np.asarray(g.starts.transitions) > 0).tolist(), "shadow_modes": list(self.shadow_modes),
                "body": self._body is not None,
                "defaults": {"shadow": self.shadow_modes[0], "smoothing": 6, "seed": 0}}

    def check(self, request: Request) -> None:
        """What this model cannot do with a well-formed request (a :class:`RequestError`)."""
        mode = request.options.shadow_start
        if mode not in self.shadow_modes:
            raise RequestError(f"shadow: {mode!r} is not on offer here (available: {', '.join(self.shadow_modes)})")

    def warnings(self, request: Request) -> list[str]:
        """Tag pairs never seen in training (the paper's failure case; the page shows them)."""
        return unseen_pairs(self.generator, request.program)

    def generate(self, request: Request, on_action: Callable[[int, bool, bool], None] | None = None,
                 on_wait: Callable[[], None] | None = None) -> dict:
        """The motion of ``request`` (:func:`~jaxmotion.compose.compose`, every action padded to the longest), kept
        for :meth:`download`; ``on_wait()`` is called when another request is being served first, ``on_action(a,
        shadowed, revised)`` as each action is done. Returns the page's motion (:meth:`_payload`)."""
        self.check(request)
        if not self._lock.acquire(blocking=False):
            if on_wait is not None:
                on_wait()
            self._lock.acquire()
        try:
            motion = compose(self.generator, request.program, jax.random.key(request.seed), options=request.options,
                             reviser=self.reviser if request.options.shadow_start == "revision" else None,
                             mean=request.mean, padded=True, on_action=on_action)
            motion_id = f"m{next(self._ids)}"
            self._motions[motion_id] = motion
            while len(self._motions) > self.keep:
                self._motions.popitem(last=False)
        finally:
            self._lock.release()
        return self._payload(motion_id, motion, request)

    def warm_up(self, shadow: str | None = None) -> None:
        """Compile the chain once (a root action on a path, then an in-place one) so the first request runs at
        the speed of the others."""
        g = self.generator
        roots = root_tag_mask(g.class_names)
        moving, still = g.class_names[int(np.argmax(roots))], g.class_names[int(np.argmin(roots))]
        payload = {"actions": [{"tags": [moving], "frames": 2, "path": [[0, 0], [0, 0.1]]},
                               {"tags": [still], "frames": 2}], "shadow": shadow or self.shadow_modes[0]}
        self.generate(read_request(payload, g))

    def body(self) -> dict:
        """The mesh for the page: the rest vertices ``[V * 3]`` (the template, mean shape), the faces ``[F * 3]``, and
        each vertex's four largest skinning weights, renormalised, with their joints ``[V * 4]``; a
        :class:`RequestError` (404) without a body model."""
        if self._body is None:
            raise RequestError("body: the server was started without a body model (--body-model)", 404)
        weights = np.asarray(self._body.weights)
        joints = np.argsort(-weights, axis=1)[:, :4]
        top = np.take_along_axis(weights, joints, axis=1)
        top = top / np.maximum(top.sum(axis=1, keepdims=True), 1e-12)
        faces = np.zeros((0, 3), int) if self._body.faces is None else np.asarray(self._body.faces)
        return {"vertices": np.round(np.asarray(self._body.v_template, np.float64), 5).reshape(-1).tolist(),
                "faces": faces.reshape(-1).tolist(), "joints": joints.reshape(-1).tolist(),
                "weights": np.round(top, 4).reshape(-1).tolist()}

    def _skin(self, motion: dict) -> np.ndarray:
        """Per frame and joint, the rotation (row by row) and shift that skin the body into the motion ``[T, 24,
        12]``: its pelvis on the motion's root (the body's translation is the root minus the body's rest root)."""
        rotations, shifts = skinning_transforms(self._body, axis_angle_to_matrix(motion["rotations"]),
                                                translation=root_translation(self._body, motion["translation"]),
                                                check=False)
        frames = len(motion["rotations"])
        return np.concatenate([np.asarray(rotations).reshape(frames, 24, 9), np.asarray(shifts)], axis=-1)

    def _payload(self, motion_id: str, motion: dict, request: Request) -> dict:
        frames = len(motion["joints"])
        joints = np.round(np.asarray(motion["joints"], np.float64), 4)
        payload = {"id": motion_id, "fps": self.generator.fps, "frames": frames,
                   "joints": joints.reshape(-1).tolist(), "joint_count": int(joints.shape[1]),
                   "segments": motion["segments"],
                   "controls": [None if c is None else [list(p) for p in c] for c in request.controls],
                   "downloads": {name: f"/api/motions/{motion_id}/{name}" for name in DOWNLOADS}}
        if self._body is not None:
            payload["skin"] = np.round(self._skin(motion).astype(np.float64), 5).reshape(-1).tolist()
        return payload

    def download(self, motion_id: str, name: str) -> tuple[bytes, str]:
        """A kept motion as ``name`` (one of :data:`DOWNLOADS`) -> ``(bytes, content type)``."""
        motion = self._motions.get(motion_id)
        if motion is None:
            raise RequestError(f"motion {motion_id!r}: not here (the server keeps the last {self.keep})", 404)
        if name not in DOWNLOADS:
            raise RequestError(f"download {name!r}: expected one of {', '.join(DOWNLOADS)}", 404)
        fmt, content_type = DOWNLOADS[name]
        if fmt is None:
            table = {"fps": self.generator.fps, "frames": len(motion["joints"]), "segments": motion["segments"]}
            return json.dumps(table, indent=1).encode(), content_type
        batch = {k: motion[k][None] for k in ("rotations", "translation", "joints")}
        with tempfile.TemporaryDirectory() as folder:
            written = export_motions(folder, batch, self.generator.facts.skeleton, self.generator.fps,
                                     formats=(fmt,), names=["motion"], options=self._export)
            return Path(written[0]).read_bytes(), content_type
