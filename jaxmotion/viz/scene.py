"""The one frame renderer of every motion animation (GIF grids, take animations, videos), and the drawing
primitives the still pictures share: bone colours, legends, the camera, a take's tag timeline, posed meshes.

Frame: the library's (metres, +Y up, a subject faces +Z at rest, +X is the subject's left). Axes: P persons,
T frames, J joints, V vertices, F faces. Drawing is matplotlib's Agg on a ``Figure`` of its own (no pyplot state, no
display); a frame comes out as ``[H, W, 3]`` uint8.

**Camera.** Orthographic and never mirrored (seen from the front, the subject's left is on the viewer's right), and
turned with the scene: its azimuth is measured from person 0's facing at frame 0 (from its hips), so every clip is
seen from the same side of its subject whatever its heading.

* ``follow``: a window of fixed size (a standing body fills it) kept on the persons' mean root, seen from the front
  right (azimuth 37 degrees, elevation 15); a ground grid of 0.5 m cells, fixed in the world, slides under a body
  that travels.
* ``world``: one view for the whole clip: the limits are the bounds of all persons over all frames at one metric
  scale, a ground grid under the whole area (0.5 m cells; 1 m when the area is wider than 8 m), each person's root
  path on the ground (the whole path faint, the part travelled so far solid), seen at 60 degrees from the direction
  of travel (from the side the subject faces at frame 0; elevation 25), so a walk crosses the picture.
* ``auto`` (the default): ``world`` when some person's root goes more than :data:`TRAVEL_THRESHOLD` = 1 m
  (horizontally) from where it started (locomotion: a walk, a run, a long jump), else ``follow``: the threshold is
  ours, about two steps, beyond which a following camera hides the path.

Each clip stands on the floor: it is lifted (or lowered) as a whole so that its lowest joint over the clip is at
y = 0 (a model's own frame may put the pelvis at 0).

**Colours.** One person: the left side blue, the right side red, the midline black; several persons: person 1
as one person, then cyan/orange/grey, green/olive/dark green, purple/pink/indigo, brown/gold/saddle brown (left,
right, midline). The legend names what colours mean: for one person its label and the left and right colours, for
several one entry per person showing its three colours. Meshes have one colour per person instead.

**Meshes.** Given an SMPL-format body model (:mod:`jaxmotion.geometry.body`) and the motion's rotations and
translation, each person is drawn as its skinned surface (:func:`posed_body`) instead of sticks: triangles projected
by the camera, sorted back to front (the painter's algorithm: a ``PolyCollection`` drawn in that order) and shaded
flat (Lambert: an ambient 0.35 plus 0.65 times the cosine between the face normal and a light fixed above the
viewer's left shoulder; both sides of a face lit alike, so files whose faces wind either way look the same).
"""

from __future__ import annotations

import dataclasses
import math
import textwrap
from collections.abc import Iterator, Sequence

import matplotlib
import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection, PolyCollection
from matplotlib.figure import Figure
from matplotlib.legend_handler import HandlerTuple
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from jaxmotion.data.segments import Segments
from jaxmotion.geometry.body import BodyModel, body_forward, root_translation
from jaxmotion.geometry.skeletons import Skeleton

#: Metres a root must go (horizontally, from where it starts) for ``camera="auto"`` to choose ``world``.
TRAVEL_THRESHOLD = 1.0
CAMERAS = ("auto", "world", "follow")

#: Per person: (left, right, midline) colours.
PALETTES = (("tab:blue", "tab:red", "black"), ("tab:cyan", "tab:orange", "dimgray"),
            ("tab:green", "tab:olive", "darkgreen"), ("tab:purple", "tab:pink", "indigo"),
            ("tab:brown", "gold", "saddlebrown"))
#: Per person: the colour of its mesh (distinct hues, light enough for shading to show).
MESH_COLOURS = ("#8fa9cc", "#e6a26a", "#8cc47e", "#b89ad9", "#d6bd6a")
#: Still views: the azimuth (degrees from the subject's front toward its right) of a camera level with the ground.
VIEWS = {"front": 0.0, "side": 90.0, "oblique": 36.87}

_UP = np.array([0.0, 1.0, 0.0])
_FOLLOW_VIEW = (VIEWS["oblique"], 15.0)  # azimuth, elevation (degrees)
_WORLD_ELEVATION, _WORLD_ANGLE = 25.0, 60.0  # degrees; the view's angle to the direction of travel
_LIGHT = np.array([-0.4, 0.6, 0.7]) / np.linalg.norm([-0.4, 0.6, 0.7])  # camera axes (right, up, toward)
_AMBIENT = 0.35
_GROUND = "0.82"


# --- colours and legends -----------------------------------------------------------------------------------


def side_of(joint_name: str) -> str:
    """``left`` / ``right`` / ``""`` from names like ``left_knee`` or VIBE's ``LKnee``."""
    for side in ("left", "right"):
        letter = side[0].upper()
        if joint_name.lower().startswith(side) or (joint_name[:1] == letter and joint_name[1:2].isupper()):
            return side
    return ""


def bone_colours(skeleton: Skeleton, person: int = 0) -> list[str]:
    """The colour of each bone of ``skeleton.bones`` for person ``person``: its palette's left, right or midline."""
    left, right, mid = PALETTES[person % len(PALETTES)]
    return [{"left": left, "right": right}.get(side_of(skeleton.joint_names[child]), mid)
            for _, child in skeleton.bones]


def person_labels(persons: int, labels: Sequence[str] | None = None) -> tuple[str, ...]:
    """``labels`` checked to name ``persons`` persons, or ``person 1``, ``person 2``, ..."""
    if labels is None or len(labels) == 0:
        return tuple(f"person {p + 1}" for p in range(persons))
    if len(labels) != persons:
        raise ValueError(f"labels: expected one label per person ({persons}), got {len(labels)}: {list(labels)}")
    return tuple(str(label) for label in labels)


def add_legend(fig: Figure, labels: Sequence[str], *, mesh: bool, y: float, columns: int, fontsize: float = 7):
    """A figure legend centred at height ``y`` (figure fraction) naming what the colours mean: meshes one patch
    per person; sticks one entry per person showing its (left, right, midline) colours, and for one person also
    ``left`` and ``right``."""
    if mesh:
        handles = [Patch(color=MESH_COLOURS[p % len(MESH_COLOURS)]) for p in range(len(labels))]
        names = list(labels)
    else:
        handles = [tuple(Line2D([], [], color=c, lw=2) for c in PALETTES[p % len(PALETTES)])
                   for p in range(len(labels))]
        names = list(labels)
        if len(labels) == 1:
            handles += [Line2D([], [], color=PALETTES[0][0], lw=2), Line2D([], [], color=PALETTES[0][1], lw=2)]
            names += ["left", "right"]
    return fig.legend(handles, names, loc="center", bbox_to_anchor=(0.5, y), ncols=columns, fontsize=fontsize,
                      frameon=False, handlelength=3.0, columnspacing=1.2,
                      handler_map={tuple: HandlerTuple(ndivide=None, pad=0.0)})


def legend_layout(labels: Sequence[str], *, mesh: bool, width: float, fontsize: float = 7) -> tuple[int, int]:
    """``(columns, rows)`` of :func:`add_legend`'s entries fitting ``width`` inches (an estimate from the longest
    label: 0.6 em a character, plus the handle and the spacing)."""
    names = list(labels) + (["left", "right"] if len(labels) == 1 and not mesh else [])
    entry = (max(len(n) for n in names) * 0.6 + 3.0 + 0.8 + 1.2) * fontsize / 72  # text, handle, pad, spacing
    columns = max(1, min(len(names), int(0.95 * width / entry)))
    return columns, math.ceil(len(names) / columns)


def wrap(text: str, width: float, fontsize: float) -> str:
    """``text`` broken into lines that fit ``width`` inches at ``fontsize`` points (0.62 em a character: wider than
    the average of DejaVu Sans, so that lines of capitals fit too)."""
    return textwrap.fill(text, max(6, int(width * 72 / (0.62 * fontsize))), break_long_words=True) if text else ""


# --- the camera --------------------------------------------------------------------------------------------


def facing(joints: np.ndarray, skeleton: Skeleton) -> tuple[np.ndarray, np.ndarray]:
    """``(forward, left)``: horizontal unit vectors of a pose ``[J, 3]``, from its hips (+Z and +X where the
    skeleton names no hips or they coincide)."""
    hips = {side_of(n): i for i, n in enumerate(skeleton.joint_names) if "hip" in n.lower() and side_of(n)}
    across = joints[hips["left"]] - joints[hips["right"]] if {"left", "right"} <= hips.keys() else np.zeros(3)
    across = np.array([across[0], 0.0, across[2]])
    norm = np.linalg.norm(across)
    left = across / norm if norm > 1e-6 else np.array([1.0, 0.0, 0.0])
    return np.cross(left, _UP), left


@dataclasses.dataclass(frozen=True, eq=False)
class Camera:
    """An orthographic view: the screen's ``right`` and ``up`` and the direction ``toward`` the viewer, unit
    vectors in the library frame forming a right-handed basis (so nothing is mirrored)."""

    right: np.ndarray
    up: np.ndarray
    toward: np.ndarray

    @classmethod
    def from_horizontal(cls, horizontal: np.ndarray, elevation: float) -> Camera:
        """Looking back along the horizontal unit vector ``horizontal`` (from the scene to the viewer), from
        ``elevation`` degrees above the ground."""
        e = np.radians(elevation)
        toward = np.cos(e) * horizontal + np.sin(e) * _UP
        right = np.cross(_UP, horizontal)
        right /= np.linalg.norm(right)
        return cls(right, np.cross(toward, right), toward)

    @classmethod
    def looking(cls, forward: np.ndarray, left: np.ndarray, azimuth: float, elevation: float) -> Camera:
        """Seen from ``azimuth`` degrees round from the subject's front (``forward``) toward its right (``-left``):
        0 from the front, 90 from its right side."""
        a = np.radians(azimuth)
        return cls.from_horizontal(np.cos(a) * forward - np.sin(a) * left, elevation)

    def project(self, points: np.ndarray) -> np.ndarray:
        """``[..., 3]`` points -> ``[..., 3]``: screen x and y (metres) and depth (larger: nearer the viewer)."""
        return np.asarray(points) @ np.stack([self.right, self.up, self.toward], axis=1)


def travel(joints: np.ndarray) -> float:
    """The farthest (metres, horizontally) any person's root of ``joints [P, T, J, 3]`` gets from its frame 0."""
    roots = joints[:, :, 0, :][..., [0, 2]]
    return float(np.linalg.norm(roots - roots[:, :1], axis=-1).max())


def camera_mode(camera: str, joints: np.ndarray) -> str:
    """``world`` or ``follow`` for ``camera`` (``auto``: by :data:`TRAVEL_THRESHOLD`) and ``joints [P, T, J, 3]``."""
    if camera not in CAMERAS:
        raise ValueError(f"camera: expected one of {list(CAMERAS)}, got {camera!r}")
    if camera == "auto":
        return "world" if travel(joints) > TRAVEL_THRESHOLD else "follow"
    return camera


def world_camera(joints: np.ndarray, forward: np.ndarray, left: np.ndarray) -> Camera:
    """The ``world`` view of ``joints [P, T, J, 3]``: at 60 degrees from the direction of travel (the persons' mean
    root from first to last frame; where that nets out, as on a round trip, the main axis of the roots' spread), on
    the side the subject faces at frame 0 (``forward``; a tie goes to its right, as the still ``oblique`` view)."""
    roots = joints[:, :, 0].mean(axis=0) * np.array([1.0, 0.0, 1.0])  # [T, 3] on the ground
    direction = roots[-1] - roots[0]
    if np.linalg.norm(direction) < 0.5 * TRAVEL_THRESHOLD:
        spread = roots - roots.mean(axis=0)
        direction = np.linalg.svd(spread[:, [0, 2]], full_matrices=False)[2][0] if len(roots) > 1 else np.ones(2)
        direction = np.array([direction[0], 0.0, direction[1]])
    norm = np.linalg.norm(direction)
    along = direction / norm if norm > 1e-9 else forward
    across = np.cross(_UP, along)
    a = np.radians(_WORLD_ANGLE)
    candidates = [np.cos(a) * s * along + np.sin(a) * r * across for s in (1, -1) for r in (1, -1)]
    best = max(candidates, key=lambda h: h @ forward - 1e-3 * (h @ left))
    return Camera.from_horizontal(best, _WORLD_ELEVATION)


def _fit(x0: float, x1: float, y0: float, y1: float, ratio: float) -> tuple[float, float, float, float]:
    """The limits grown about their centre to the box's width / height ``ratio`` (one metric scale)."""
    width, height = x1 - x0, y1 - y0
    if width / height < ratio:
        grow = (height * ratio - width) / 2
        return x0 - grow, x1 + grow, y0, y1
    grow = (width / ratio - height) / 2
    return x0, x1, y0 - grow, y1 + grow


def _box(x: tuple[float, float], y: tuple[float, float], z: tuple[float, float]) -> np.ndarray:
    """``[8, 3]`` the corners of an axis-aligned box."""
    return np.array([[a, b, c] for a in x for b in y for c in z])


def _grid_lines(x: tuple[float, float], z: tuple[float, float], cell: float) -> np.ndarray:
    """``[L, 2, 3]`` ground lines (y = 0) at the multiples of ``cell`` across ``x`` and ``z`` (metres)."""
    xs = np.arange(math.ceil(x[0] / cell), math.floor(x[1] / cell) + 1) * cell
    zs = np.arange(math.ceil(z[0] / cell), math.floor(z[1] / cell) + 1) * cell
    lines = [[[v, 0.0, z[0]], [v, 0.0, z[1]]] for v in xs] + [[[x[0], 0.0, v], [x[1], 0.0, v]] for v in zs]
    return np.array(lines, float).reshape(-1, 2, 3)


# --- meshes ------------------------------------------------------------------------------------------------


def posed_body(body: BodyModel, rotations: np.ndarray, translation: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The body posed by the library's motion arrays: ``rotations [..., J, 3]`` local axis-angle (joint 0 global)
    and ``translation [..., 3]``, the root position -> ``(vertices [..., V, 3], joints [..., J, 3])``. SMPL puts the
    root at its rest position ``J_0`` plus its translation, so the body gets ``translation - J_0``."""
    vertices, joints = body_forward(body, np.asarray(rotations, np.float32),
                                    translation=root_translation(body, np.asarray(translation, np.float32)))
    return np.asarray(vertices), np.asarray(joints)


@dataclasses.dataclass(frozen=True, eq=False)
class Mesh:
    """The surfaces of a scene's persons, posed frame by frame on demand (a long clip's vertices are never all held).

    Attributes:
      body: the SMPL-format body model (its tree the scene's skeleton's); it needs faces.
      rotations: ``[P, T, J, 3]`` local axis-angle, joint 0 global.
      translation: ``[P, T, 3]`` root positions, on the scene's floor.
    """

    body: BodyModel
    rotations: np.ndarray
    translation: np.ndarray

    def vertices(self, frame: int) -> np.ndarray:
        """``[P, V, 3]`` the persons' vertices at ``frame``."""
        return posed_body(self.body, self.rotations[:, frame], self.translation[:, frame])[0]


def _shaded_triangles(camera: Camera, vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``vertices [P, V, 3]`` -> ``(triangles [P F, 3, 2] on the screen, back to front; colours [P F, 3])``."""
    screen = camera.project(vertices)  # [P, V, 3]
    corners = vertices[:, faces]  # [P, F, 3, 3]
    normals = np.cross(corners[:, :, 1] - corners[:, :, 0], corners[:, :, 2] - corners[:, :, 0])
    normals /= np.maximum(np.linalg.norm(normals, axis=-1, keepdims=True), 1e-12)
    light = _LIGHT @ np.stack([camera.right, camera.up, camera.toward])  # into the library frame
    shade = _AMBIENT + (1 - _AMBIENT) * np.abs(normals @ light)  # [P, F]
    base = np.array([matplotlib.colors.to_rgb(MESH_COLOURS[p % len(MESH_COLOURS)]) for p in range(len(vertices))])
    colours = (shade[..., None] * base[:, None]).reshape(-1, 3)
    triangles = screen[:, faces].reshape(-1, 3, 3)
    order = np.argsort(triangles[:, :, 2].mean(axis=1), kind="stable")  # far first
    return triangles[order, :, :2], colours[order]


# --- scenes ------------------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True, eq=False)
class Scene:
    """One clip to draw, made by :func:`make_scene`.

    Attributes:
      joints: ``[P, T, J, 3]`` on the floor (lowest joint over the clip at y = 0).
      skeleton: the joint layout.
      captions: ``T`` texts, one per frame (a class name repeated, or a take's current tags).
      labels: ``P`` person names for the legend.
      mesh: the persons' surfaces, or None for sticks.
    """

    joints: np.ndarray
    skeleton: Skeleton
    captions: tuple[str, ...]
    labels: tuple[str, ...]
    mesh: Mesh | None = None

    @property
    def persons(self) -> int:
        return self.joints.shape[0]

    @property
    def num_frames(self) -> int:
        return self.joints.shape[1]


def make_scene(joints, skeleton: Skeleton, *, captions: str | Sequence[str] = "", labels: Sequence[str] | None = None,
               rotations=None, translation=None, body: BodyModel | None = None) -> Scene:
    """A :class:`Scene` from one clip: ``joints [T, J, 3]`` or ``[P, T, J, 3]``; ``captions`` one text for the
    clip or one per frame; ``labels`` one per person; with ``body``, the clip's ``rotations`` (``[(P,) T, J, 3]``)
    and ``translation`` (``[(P,) T, 3]``, root positions) pose its mesh."""
    joints = np.asarray(joints, np.float32)
    if joints.ndim == 3:
        joints = joints[None]
    j = skeleton.num_joints
    if joints.ndim != 4 or joints.shape[2:] != (j, 3) or joints.shape[1] < 1:
        raise ValueError(f"joints: expected [T, {j}, 3] or [P, T, {j}, 3] ({skeleton.name}) with T >= 1, "
                         f"got {joints.shape}")
    if not np.isfinite(joints).all():
        raise ValueError("joints: expected finite positions, got NaN or inf")
    persons, frames = joints.shape[:2]
    lift = np.array([0.0, -joints[..., 1].min(), 0.0], np.float32)
    if isinstance(captions, str):
        captions = (captions,) * frames
    captions = tuple(str(c) for c in captions)
    if len(captions) != frames:
        raise ValueError(f"captions: expected one text for the clip or one per frame ({frames}), got {len(captions)}")
    mesh = None
    if body is not None:
        if rotations is None or translation is None:
            raise ValueError("body: a mesh needs the motion's rotations and translation; this motion has joint "
                             "positions only")
        if body.faces is None:
            raise ValueError("body: the body model has no faces (field 'f'); a mesh cannot be drawn")
        if tuple(body.parents) != tuple(skeleton.parents):
            raise ValueError(f"body: the body model's tree ({body.num_joints} joints) is not the motion's skeleton "
                             f"{skeleton.name} ({j} joints)")
        rotations = np.asarray(rotations, np.float32).reshape(persons, frames, j, 3)
        translation = np.asarray(translation, np.float32).reshape(persons, frames, 3)
        mesh = Mesh(body, rotations, translation + lift)
    return Scene(joints + lift, skeleton, captions, person_labels(persons, labels), mesh)


def take_captions(segments: Segments, tag_names: Sequence[str], frames: int) -> tuple[str, ...]:
    """Per frame of a take, its current action's tags (``walk + turn``), or ``(lead-in)`` between actions."""
    captions = ["(lead-in)"] * frames
    for start, end, tags in zip(segments.start, segments.end, segments.tags, strict=True):
        text = " + ".join(tag_names[t] for t in np.flatnonzero(tags))
        captions[start:min(end, frames)] = [text] * (min(end, frames) - start)
    return tuple(captions)


def draw_timeline(ax, segments: Segments, tag_names: Sequence[str], fps: float, num_frames: int) -> None:
    """The actions of one take as labelled bars over time (s): a row per tag an action carries, lead-in bare."""
    rows = max(int(segments.tags.sum(axis=1).max()), 1) if len(segments) else 1
    colours = matplotlib.colormaps["tab20"]
    for start, end, tags in zip(segments.start, segments.end, segments.tags, strict=True):
        for row, tag in enumerate(np.flatnonzero(tags)):
            ax.barh(rows - 1 - row, (end - start) / fps, left=start / fps, height=0.8, color=colours(tag % 20),
                    edgecolor="white")
            ax.text((start + end) / (2 * fps), rows - 1 - row, tag_names[tag], ha="center", va="center", fontsize=6,
                    clip_on=True)
    ax.set_xlim(0, num_frames / fps)
    ax.set_ylim(-0.6, rows - 0.4)
    ax.set_yticks([])
    ax.set_xlabel("time (s)", fontsize=7, labelpad=1)
    ax.tick_params(labelsize=6, pad=1)


# --- the frame renderer --------------------------------------------------------------------------------------


class _Cell:
    """One scene: its camera and screen bounds (made first, so a layout can fit them), then on an axes
    (:meth:`attach`) the artists, made once and moved each frame."""

    def __init__(self, scene: Scene, camera: str):
        self.scene = scene
        joints = scene.joints
        forward, left = facing(joints[0, 0], scene.skeleton)
        self.mode = camera_mode(camera, joints)
        self.camera = world_camera(joints, forward, left) if self.mode == "world" else Camera.looking(
            forward, left, *_FOLLOW_VIEW)
        self.screen = self.camera.project(joints)  # [P, T, J, 3]
        self.bones = np.array(scene.skeleton.bones).reshape(-1, 2)
        margin = 0.3 if scene.mesh is not None else 0.2  # a surface reaches past its joints
        top = max(2.0, float(joints[..., 1].max()) + 0.1)
        if self.mode == "world":
            self.x = (float(joints[..., 0].min()) - margin, float(joints[..., 0].max()) + margin)
            self.z = (float(joints[..., 2].min()) - margin, float(joints[..., 2].max()) + margin)
            corners = self.camera.project(_box(self.x, (0.0, top), self.z))
        else:  # a window this wide, placed on the persons' mean root each frame
            self.half = 1.0 if scene.persons == 1 else 0.6 + 0.5 * scene.persons
            corners = self.camera.project(_box((-self.half, self.half), (0.0, top), (-self.half, self.half)))
        self.bounds = (corners[:, 0].min(), corners[:, 0].max(), corners[:, 1].min(), corners[:, 1].max())

    @property
    def ratio(self) -> float:
        """Width / height of the screen bounds."""
        x0, x1, y0, y1 = self.bounds
        return (x1 - x0) / (y1 - y0)

    def attach(self, ax, linewidth: float) -> None:
        """Draw on ``ax`` (its limits grown to the axes' width / height at one metric scale)."""
        self.ax = ax
        bbox = ax.get_position()
        fig_w, fig_h = ax.figure.get_size_inches()
        self.window = _fit(*self.bounds, bbox.width * fig_w / (bbox.height * fig_h))
        self.ground = LineCollection([], colors=_GROUND, linewidths=0.6, zorder=0)
        ax.add_collection(self.ground)
        if self.mode == "world":
            cell = 0.5 if max(self.x[1] - self.x[0], self.z[1] - self.z[0]) <= 8.0 else 1.0
            area = ((math.floor(self.x[0] / cell) - 1) * cell, (math.ceil(self.x[1] / cell) + 1) * cell)
            depth = ((math.floor(self.z[0] / cell) - 1) * cell, (math.ceil(self.z[1] / cell) + 1) * cell)
            self.ground.set_segments(self.camera.project(_grid_lines(area, depth, cell))[..., :2])
            ax.set_xlim(self.window[0], self.window[1])
            ax.set_ylim(self.window[2], self.window[3])
            paths = self.camera.project(self.scene.joints[:, :, 0] * np.array([1.0, 0.0, 1.0]))[..., :2]  # [P, T, 2]
            self.paths = []
            for p, path in enumerate(paths):
                colour = self._colour(p)
                ax.plot(path[:, 0], path[:, 1], color=colour, alpha=0.25, lw=1.0, zorder=1)
                self.paths.append((ax.plot([], [], color=colour, lw=1.4, zorder=1)[0], path))
        self.sticks = [LineCollection([], colors=bone_colours(self.scene.skeleton, p), linewidths=linewidth,
                                      capstyle="round") for p in range(self.scene.persons)]
        for sticks in self.sticks:
            ax.add_collection(sticks)
        self.surface = None
        if self.scene.mesh is not None:
            self.faces = np.asarray(self.scene.mesh.body.faces)
            self.surface = PolyCollection([], edgecolors="none", linewidths=0, antialiaseds=False, zorder=2)
            ax.add_collection(self.surface)
        ax.set_axis_off()

    def _colour(self, person: int) -> str:
        if self.scene.mesh is not None:
            return MESH_COLOURS[person % len(MESH_COLOURS)]
        return PALETTES[person % len(PALETTES)][2]

    def draw(self, frame: int) -> None:
        t = min(frame, self.scene.num_frames - 1)  # a shorter clip holds its last pose
        joints = self.scene.joints[:, t]
        if self.mode == "world":
            for line, path in self.paths:
                line.set_data(path[: t + 1, 0], path[: t + 1, 1])
        else:
            centre = joints[:, 0].mean(axis=0) * np.array([1.0, 0.0, 1.0])
            h = self.half
            self.ground.set_segments(self.camera.project(
                _grid_lines((centre[0] - h, centre[0] + h), (centre[2] - h, centre[2] + h), 0.5))[..., :2])
            shift = self.camera.project(centre)
            x0, x1, y0, y1 = self.window
            self.ax.set_xlim(x0 + shift[0], x1 + shift[0])
            self.ax.set_ylim(y0 + shift[1], y1 + shift[1])
        if self.surface is not None:
            triangles, colours = _shaded_triangles(self.camera, self.scene.mesh.vertices(t), self.faces)
            self.surface.set_verts(triangles)
            self.surface.set_facecolor(colours)
            return
        depth = self.screen[:, t, 0, 2]
        for rank, p in enumerate(np.argsort(depth)):  # the nearer person drawn over the farther
            self.sticks[p].set_segments(self.screen[p, t][self.bones][..., :2])
            self.sticks[p].set_zorder(2 + 0.01 * rank)


@dataclasses.dataclass(frozen=True)
class Timeline:
    """A take's tag timeline under an animation, with a cursor at the current frame."""

    segments: Segments
    tag_names: tuple[str, ...]


class FrameRenderer:
    """Draws frame ``t`` of one scene, or of several laid out row by row in ``columns`` (None leaves a cell empty),
    to ``[H, W, 3]`` uint8: above each cell its caption (wrapped to the cell's width), at the top left the frame
    counter (``frame 12 / 80 · 0.37 s``: frames counted from 1, the time of a frame from the first), at the bottom
    the legend, and with a ``timeline`` (one scene) the take's tags over time with a cursor.

    The figure and its artists are made once; each frame moves them and redraws the canvas. A clip shorter than
    ``frames`` (default: the longest clip) holds its last pose. ``cell`` is a cell's width in inches, drawn at
    ``dpi``: by default 6 for one scene, its height from its view's shape (from square to 1.9:1, so a walk's world
    view is not a strip of sky), and 2.4 for several, square.
    """

    def __init__(self, scenes: Sequence[Scene | None], fps: float, *, columns: int | None = None,
                 camera: str = "auto", frames: int | None = None, timeline: Timeline | None = None,
                 cell: float | None = None, dpi: float = 100):
        drawn = [s for s in scenes if s is not None]
        if not drawn:
            raise ValueError("scenes: expected at least one scene to draw")
        if not fps > 0:
            raise ValueError(f"fps: expected frames per second > 0, got {fps}")
        if camera not in CAMERAS:
            raise ValueError(f"camera: expected one of {list(CAMERAS)}, got {camera!r}")
        if timeline is not None and len(scenes) != 1:
            raise ValueError(f"timeline: drawn under one scene, got {len(scenes)} scenes")
        self.fps = float(fps)
        self.num_frames = max(s.num_frames for s in drawn) if frames is None else int(frames)
        if self.num_frames < 1:
            raise ValueError(f"frames: expected >= 1, got {frames}")
        columns = columns or (1 if len(scenes) == 1 else min(len(scenes), 4))
        rows = math.ceil(len(scenes) / columns)
        single = len(scenes) == 1
        cells = [None if s is None else _Cell(s, camera) for s in scenes]
        side = cell or (6.0 if single else 2.4)
        # one clip: the cell takes its view's shape (a walk's is wide), from square to 1.9:1; a grid: square cells
        tall = side / min(max(cells[0].ratio, 1.0), 1.9) if single else side
        size = 10.0 if single else 8.0  # caption font (points)
        lines = max(wrap(c, side - 0.1, size).count("\n") + 1 for s in drawn for c in set(s.captions))
        band = lines * size * 1.25 / 72 + 0.08
        mesh = any(s.mesh is not None for s in drawn)
        widest = max(drawn, key=lambda s: s.persons)
        width = columns * side
        legend_columns, legend_rows = legend_layout(widest.labels, mesh=mesh, width=width)
        header, footer = 0.3, 0.1 + 0.22 * legend_rows
        strip = 0.9 if timeline is not None else 0.0
        height = header + rows * (band + tall) + strip + footer
        self.figure = Figure(figsize=(width, height), dpi=dpi, facecolor="white")
        self.canvas = FigureCanvasAgg(self.figure)
        self.cells = [c for c in cells if c is not None]
        self.captions = []
        for k, cell_k in enumerate(cells):
            if cell_k is None:
                continue
            r, c = divmod(k, columns)
            top = height - header - r * (band + tall)
            ax = self.figure.add_axes((c * side / width, (top - band - tall) / height, side / width, tall / height))
            cell_k.attach(ax, 2.2 if single else 1.8)
            self.captions.append(self.figure.text((c + 0.5) * side / width, (top - 0.04) / height, "", ha="center",
                                                  va="top", fontsize=size, linespacing=1.1))
        self.counter = self.figure.text(0.01, 1 - 0.06 / height, "", ha="left", va="top", fontsize=8,
                                        family="monospace")
        self.legend = add_legend(self.figure, widest.labels, mesh=mesh, y=(footer / 2) / height,
                                 columns=legend_columns)
        self.cursor = None
        if timeline is not None:
            line = self.figure.add_axes((0.06, (footer + 0.3) / height, 0.9, (strip - 0.38) / height))
            draw_timeline(line, timeline.segments, timeline.tag_names, self.fps, drawn[0].num_frames)
            self.cursor = line.axvline(0.0, color="black", lw=1.2)
        self.side = side

    def draw(self, frame: int) -> np.ndarray:
        """``[H, W, 3]`` uint8: frame ``frame`` (0-based) of the scenes."""
        if not 0 <= frame < self.num_frames:
            raise ValueError(f"frame: expected an index in [0, {self.num_frames}), got {frame}")
        for cell, caption in zip(self.cells, self.captions, strict=True):
            cell.draw(frame)
            t = min(frame, cell.scene.num_frames - 1)
            caption.set_text(wrap(cell.scene.captions[t], self.side - 0.1, caption.get_fontsize()))
        self.counter.set_text(f"frame {frame + 1} / {self.num_frames} · {frame / self.fps:.2f} s")
        if self.cursor is not None:
            self.cursor.set_xdata([frame / self.fps])
        self.canvas.draw()
        return np.asarray(self.canvas.buffer_rgba())[..., :3].copy()

    def frames(self) -> Iterator[np.ndarray]:
        """Every frame in order, drawn as it is asked for."""
        return (self.draw(t) for t in range(self.num_frames))
