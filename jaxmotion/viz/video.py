"""Motion videos: frames to ``.mp4`` or ``.gif`` (:func:`write_video`), and any motion drawn to one
(:func:`render_video`: a ``Motion`` of one or several persons, a ``MotionDataset`` as a grid of clips, or a padded
batch as the samplers return it).

* ``.mp4``: H.264 (``libx264``), ``yuv420p`` (what browsers and phones play), through the ffmpeg binary that the
  ``imageio-ffmpeg`` wheel ships (no system ffmpeg): the optional extra ``pip install "jaxmotion[video]"``, imported
  only when an ``.mp4`` is written. yuv420p needs even sizes: a frame of odd width or height gets one white column
  or row. Frames are streamed to ffmpeg as they are drawn; none is held.
* ``.gif``: Pillow (matplotlib's own dependency), no extra. Pillow keeps the frames as palette images (one byte a
  pixel) until it writes them, so a GIF suits clips of seconds; an unchanged frame merges into the one before
  (the renderer's frame counter changes every frame, so its GIFs keep every frame).

Both are written under a temporary name and renamed into place: a failed render leaves no partial file.
Drawing is :class:`~jaxmotion.viz.scene.FrameRenderer`'s (cameras, captions, legends, meshes: see
:mod:`jaxmotion.viz.scene`).
"""

from __future__ import annotations

import warnings
from collections.abc import Iterable, Iterator, Mapping, Sequence
from pathlib import Path

import numpy as np

from jaxmotion.data.motion import Motion, MotionDataset, person_axis
from jaxmotion.files import atomic_file, replaced_on_success
from jaxmotion.geometry.body import BodyModel, load_body_model
from jaxmotion.geometry.skeletons import Skeleton
from jaxmotion.progress import phase
from jaxmotion.viz.scene import FrameRenderer, Scene, Timeline, make_scene, take_captions

#: What :func:`write_video` writes, by suffix.
VIDEO_SUFFIXES = (".mp4", ".gif")
#: The most clips :func:`render_video` lays out in one grid (pick others with ``indices``).
MAX_CELLS = 36
_INSTALL = 'pip install "jaxmotion[video]"'


def _imageio_ffmpeg():
    try:
        import imageio_ffmpeg
    except ImportError as error:
        raise ImportError(f"writing .mp4 needs the imageio-ffmpeg package (it ships ffmpeg): {_INSTALL}") from error
    return imageio_ffmpeg


def check_video_path(path: str | Path, field: str = "path") -> Path:
    """``path`` as a ``Path`` once it names a video this module writes, and for ``.mp4`` once the ``video`` extra
    is importable: checked before anything is drawn (``field`` names it in the error)."""
    path = Path(path)
    if path.suffix.lower() not in VIDEO_SUFFIXES:
        raise ValueError(f"{field}: expected a {' or '.join(VIDEO_SUFFIXES)} file, got {path.name!r}")
    if path.suffix.lower() == ".mp4":
        _imageio_ffmpeg()
    return path


def _checked(frames: Iterable[np.ndarray]) -> Iterator[np.ndarray]:
    """The frames, each checked to be ``[H, W, 3]`` uint8 of the first one's size."""
    size = None
    for k, frame in enumerate(frames):
        frame = np.asarray(frame)
        if frame.ndim != 3 or frame.shape[2] != 3 or frame.dtype != np.uint8:
            raise ValueError(f"frames[{k}]: expected [H, W, 3] uint8 (RGB), got {frame.dtype} {frame.shape}")
        if size is None:
            size = frame.shape
        elif frame.shape != size:
            raise ValueError(f"frames[{k}]: expected every frame of the first one's size {size}, got {frame.shape}")
        yield frame


def _even(frame: np.ndarray) -> np.ndarray:
    """``frame`` padded with a white column / row to an even width and height."""
    h, w = frame.shape[:2]
    if h % 2 == 0 and w % 2 == 0:
        return frame
    return np.pad(frame, ((0, h % 2), (0, w % 2), (0, 0)), constant_values=255)


def _write_mp4(path: Path, frames: Iterator[np.ndarray], fps: float) -> None:
    ffmpeg = _imageio_ffmpeg()
    first = _even(next(frames))
    with replaced_on_success(path, suffix=".mp4") as temporary:  # ffmpeg picks the container by the suffix
        writer = ffmpeg.write_frames(str(temporary), (first.shape[1], first.shape[0]), fps=fps, codec="libx264",
                                     pix_fmt_in="rgb24", pix_fmt_out="yuv420p", macro_block_size=1,
                                     ffmpeg_log_level="error", output_params=["-movflags", "+faststart"])
        with warnings.catch_warnings():
            # JAX warns at every fork; the child here only execs ffmpeg (no Python runs in it), which is safe
            warnings.filterwarnings("ignore", message=r"os\.fork\(\) was called", category=RuntimeWarning)
            writer.send(None)  # start ffmpeg
        try:
            writer.send(np.ascontiguousarray(first))
            for frame in frames:
                writer.send(np.ascontiguousarray(_even(frame)))
        finally:
            writer.close()


def _write_gif(path: Path, frames: Iterator[np.ndarray], fps: float) -> None:
    from PIL import Image

    first = Image.fromarray(next(frames))
    with atomic_file(path) as file:
        # a GIF counts time in hundredths of a second: the nearest (15 fps: 70 ms a frame)
        first.save(file, format="GIF", save_all=True, append_images=(Image.fromarray(f) for f in frames),
                   duration=10 * max(1, round(100 / fps)), loop=0)


def write_video(path: str | Path, frames: Iterable[np.ndarray], fps: float) -> Path:
    """Write ``frames`` (an iterable of ``[H, W, 3]`` uint8 RGB arrays, all one size, consumed one at a time) to
    ``path``: ``.mp4`` (H.264, yuv420p; the ``video`` extra) or ``.gif`` (Pillow), at ``fps`` frames per second.
    Returns ``path``."""
    path = check_video_path(path)
    if not (isinstance(fps, (int, float, np.number)) and np.isfinite(fps) and fps > 0):
        raise ValueError(f"fps: expected frames per second > 0, got {fps!r}")
    checked = _checked(frames)
    try:
        first = next(checked)
    except StopIteration:
        raise ValueError("frames: expected at least one frame, got none") from None
    path.parent.mkdir(parents=True, exist_ok=True)
    stream = (f for seq in ((first,), checked) for f in seq)
    (_write_mp4 if path.suffix.lower() == ".mp4" else _write_gif)(path, stream, float(fps))
    return path


def save_animation(path: str | Path, renderer: FrameRenderer) -> Path:
    """Every frame of ``renderer`` written to ``path`` (:func:`write_video`), with a progress line for long ones."""
    path = Path(path)
    with phase(f"[render] {path.name}", renderer.num_frames, unit="frame") as bar:
        def counted():
            for frame in renderer.frames():
                yield frame
                bar.advance()

        return write_video(path, counted(), renderer.fps)


# --- any motion -> scenes ----------------------------------------------------------------------------------


def _body(body: BodyModel | str | Path | None) -> BodyModel | None:
    return body if body is None or isinstance(body, BodyModel) else load_body_model(body)


def _clip_captions(captions, count: int, defaults: Sequence) -> list:
    """One caption entry per clip (a text, or one per frame): ``captions`` checked, or ``defaults``."""
    if captions is None:
        return list(defaults)
    if isinstance(captions, str) or len(captions) != count:
        raise ValueError(f"captions: expected one entry per clip ({count}: a text or one per frame), got "
                         f"{captions!r:.80}")
    return list(captions)


def _chosen(indices: Sequence[int] | None, count: int) -> list[int]:
    """The clips to draw: ``indices`` checked, or all ``count``; at most :data:`MAX_CELLS`."""
    chosen = list(range(count)) if indices is None else [int(i) for i in indices]
    outside = [i for i in chosen if not 0 <= i < count]
    if outside or not chosen:
        raise ValueError(f"indices: expected clip indices in [0, {count}), got {outside or chosen}")
    if len(chosen) > MAX_CELLS:
        raise ValueError(f"motions: {len(chosen)} clips; one video draws at most {MAX_CELLS}: choose them with "
                         f"indices=")
    return chosen


def motion_scenes(motions: Motion | MotionDataset | Mapping, skeleton: Skeleton | None = None, *,
                  captions=None, labels: Sequence[str] | None = None, body: BodyModel | str | Path | None = None,
                  indices: Sequence[int] | None = None) -> list[Scene]:
    """The :class:`~jaxmotion.viz.scene.Scene` of each clip of ``motions`` (see :func:`render_video`)."""
    body = _body(body)
    if isinstance(motions, Motion):
        if skeleton is None:
            raise ValueError("skeleton: required to draw a Motion (e.g. SMPL24)")
        caption = "" if captions is None else captions
        return [make_scene(motions.joints, skeleton, captions=caption, labels=labels, rotations=motions.rotations,
                           translation=motions.translation, body=body)]
    if isinstance(motions, MotionDataset):
        skeleton = motions.skeleton if skeleton is None else skeleton
        chosen = _chosen(indices, len(motions))
        clips = [motions[i] for i in chosen]
        defaults = [motions.class_names[m.action] if m.segments is None
                    else take_captions(m.segments, motions.class_names, m.num_frames) for m in clips]
        texts = _clip_captions(captions, len(clips), defaults)
        return [make_scene(m.joints, skeleton, captions=text, labels=labels, rotations=m.rotations,
                           translation=m.translation, body=body) for m, text in zip(clips, texts, strict=True)]
    if isinstance(motions, Mapping):
        if skeleton is None:
            raise ValueError("skeleton: required to draw a batch of motions (e.g. SMPL24)")
        if "joints" not in motions:
            raise ValueError(f"motions: expected a batch with 'joints' [N, (P,) T, J, 3], got keys {sorted(motions)}")
        joints = np.asarray(motions["joints"])
        if joints.ndim not in (4, 5):
            raise ValueError(f"joints: expected [N, T, J, 3] or [N, P, T, J, 3], got {joints.shape}")
        persons = 1 if joints.ndim == 4 else joints.shape[1]
        count, frames = joints.shape[0], joints.shape[-3]
        lengths = np.asarray(motions.get("lengths", np.full(count, frames)))
        if lengths.shape != (count,) or lengths.min() < 1 or lengths.max() > frames:
            raise ValueError(f"lengths: expected [N] = ({count},) frame counts in [1, {frames}], got {lengths}")
        chosen = _chosen(indices, count)
        texts = _clip_captions(captions, len(chosen), [""] * len(chosen))
        arrays = {k: person_axis(np.asarray(motions[k]), persons, axis=1) if motions.get(k) is not None else None
                  for k in ("joints", "rotations", "translation")}
        return [make_scene(arrays["joints"][n, :, :lengths[n]], skeleton, captions=text, labels=labels,
                           rotations=None if arrays["rotations"] is None else arrays["rotations"][n, :, :lengths[n]],
                           translation=None if arrays["translation"] is None
                           else arrays["translation"][n, :, :lengths[n]], body=body)
                for n, text in zip(chosen, texts, strict=True)]
    raise TypeError(f"motions: expected a Motion, a MotionDataset or a batch mapping, got {type(motions).__name__}")


def render_video(path: str | Path, motions: Motion | MotionDataset | Mapping, skeleton: Skeleton | None = None,
                 fps: float | None = None, *, captions=None, labels: Sequence[str] | None = None,
                 camera: str = "auto", body: BodyModel | str | Path | None = None,
                 indices: Sequence[int] | None = None, columns: int | None = None,
                 max_frames: int | None = None) -> Path:
    """Draw ``motions`` to the video ``path`` (``.mp4`` or ``.gif``) and return it.

    Args:
      motions: a ``Motion`` (one clip, one or several persons); a ``MotionDataset`` (a grid of its clips, or of
        ``indices``; a take of a multi-action dataset gets its tag timeline when it is drawn alone); or a padded
        batch as the samplers return it: ``joints [N, T, J, 3]`` (``[N, P, T, J, 3]`` for several persons),
        optional ``lengths [N]``, and for meshes ``rotations`` and ``translation``.
      skeleton: the joint layout; default the dataset's (required otherwise).
      fps: frames per second; default the dataset's (required otherwise).
      captions: a ``Motion``'s text, or one per frame; for several clips one entry per clip (a text, or one per
        frame). Default: a dataset clip's class name, or a take's current tags; nothing for the rest.
      labels: the persons' names in the legend (default ``person 1``, ``person 2``, ...).
      camera: ``auto``, ``world`` or ``follow`` (:mod:`jaxmotion.viz.scene`), per clip.
      body: an SMPL-format body model (or its file) whose tree is the skeleton's: shaded meshes instead of sticks
        (needs the motions' rotations and translation).
      indices: the dataset's or batch's clips to draw (default all, at most :data:`MAX_CELLS`).
      columns: the grid's columns (default up to 4).
      max_frames: draw at most this many frames (default the longest clip's).
    """
    path = check_video_path(path)
    if isinstance(motions, MotionDataset):
        fps = motions.fps if fps is None else fps
    if fps is None:
        raise ValueError("fps: required to draw a Motion or a batch (frames per second)")
    scenes = motion_scenes(motions, skeleton, captions=captions, labels=labels, body=body, indices=indices)
    timeline = None
    if isinstance(motions, MotionDataset) and motions.segments is not None and len(scenes) == 1:
        index = 0 if indices is None else int(indices[0])
        timeline = Timeline(motions[index].segments, motions.class_names)
    longest = max(s.num_frames for s in scenes)
    if max_frames is not None and max_frames < 1:
        raise ValueError(f"max_frames: expected >= 1, got {max_frames}")
    frames = longest if max_frames is None else min(longest, max_frames)
    renderer = FrameRenderer(scenes, fps, columns=columns, camera=camera, frames=frames, timeline=timeline)
    return save_animation(path, renderer)
