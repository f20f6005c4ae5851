"""The BABEL-MAG loader (``mag``) on BABEL and AMASS files the tests write in their exact format: labels mapped to
tags, overlaps resolved or counted, takes with segments and next tags, and malformed files named."""

import json
import re

import numpy as np
import pytest

from jaxmotion.data import load_dataset
from jaxmotion.data.formats import babel_mag
from jaxmotion.data.mag_tags import TAG_NAMES

FPS = 30


def _label(category, start, end, seg="s"):
    return {"seg_id": f"{seg}-{category}", "act_cat": [category], "start_t": start, "end_t": end}


#: 4 s: walk, turn (a kick overlapping its end: ambiguous, the rest too short), stand, stand with arm movements;
#: "dance" has no tag.
WALK_TURN_STAND = [_label("walk", 0.0, 1.0), _label("turn", 1.0, 2.0), _label("kick", 1.6, 1.8),
                   _label("stand", 2.0, 4.0), _label("arm movements", 3.0, 4.0), _label("dance", 0.2, 0.6)]
#: 2 s: "sit" while the root descends (Sit Down), then "sit" at rest (Sit).
SIT_DOWN_SIT = [_label("sit", 0.0, 1.0, "a"), _label("sit", 1.0, 2.0, "b")]


def _amass(frames, height):
    rng = np.random.default_rng(frames)
    poses = 0.1 * rng.normal(size=(frames, 156))
    trans = np.stack([0.02 * np.arange(frames), np.zeros(frames), height], axis=1)  # AMASS: z up
    return poses, trans


def write_babel(root, sequences, split="train"):
    """``sequences``: ``{sid: (frames, root heights [frames], frame labels or None)}`` at 30 fps."""
    annotations = {}
    for sid, (frames, height, labels) in sequences.items():
        feat_p = f"CMU/CMU/{sid}/{sid}_poses.npz"
        path = root / "amass" / "rawdata" / feat_p.split("/", 1)[1]
        path.parent.mkdir(parents=True, exist_ok=True)
        poses, trans = _amass(frames, height)
        np.savez(path, poses=poses, trans=trans, mocap_framerate=np.array(float(FPS)))
        annotations[sid] = {"feat_p": feat_p, "dur": frames / FPS,
                            "seq_ann": {"labels": [{"seg_id": "all", "act_cat": ["walk"]}]},
                            "frame_ann": None if labels is None else {"labels": labels}}
    folder = root / "babel_v1.0_release"
    folder.mkdir(parents=True, exist_ok=True)
    (folder / f"{split}.json").write_text(json.dumps(annotations))


def _standard(root):
    descending = np.concatenate([np.linspace(0.9, 0.5, 30), np.full(30, 0.5)])
    write_babel(root, {"1": (120, np.full(120, 0.9), WALK_TURN_STAND), "2": (60, descending, SIT_DOWN_SIT),
                       "3": (45, np.full(45, 0.9), None)})


def _tags(row):
    return [TAG_NAMES[i] for i in np.flatnonzero(row)]


def test_labels_become_tagged_actions_with_next_tags_and_the_rest_is_counted(tmp_path):
    _standard(tmp_path)
    data, report = babel_mag.read_babel_mag(tmp_path, "train")
    assert (data.name, data.fps, len(data), data.class_names) == ("mag", 30.0, 2, TAG_NAMES)
    assert data.names == ("1", "2") and list(data.lengths) == [120, 60]
    seg = data.segments
    rows = [(int(s), int(a), int(b), _tags(t)) for s, a, b, t in zip(seg.sequence, seg.start, seg.end, seg.tags)]
    assert rows == [(0, 0, 30, ["Walk"]), (0, 30, 48, ["Turn"]), (0, 60, 90, ["Stand"]),
                    (0, 90, 120, ["Stand", "Arm Movement"]), (1, 0, 30, ["Sit Down"]), (1, 30, 60, ["Sit"])]
    assert [_tags(t) for t in seg.next_tags] == [["Turn"], ["Stand"], ["Stand", "Arm Movement"],
                                                 ["Stand", "Arm Movement"], ["Sit"], ["Sit"]]
    assert report.no_tag == {"dance": 1} and report.ambiguous_frames == 6 and report.short_actions == 1
    assert report.skipped_sequences == 1 and report.takes == 2 and report.actions == 6
    assert "left out: 1 labels of categories without a tag (dance (1)), 6 frames of ambiguous overlaps" in str(report)
    items = data.action_items(6)
    assert items.dropped == 2 and len(items) == 4  # the takes' first actions have no context frames
    np.testing.assert_allclose(data[0].joints[:, 0], data[0].translation, atol=1e-5)


def test_the_loader_is_registered_and_reports_what_it_left_out(tmp_path, capsys):
    _standard(tmp_path)
    data = load_dataset("mag", "train", data_root=tmp_path)
    assert len(data.segments) == 6
    assert "[data] mag/train from" in capsys.readouterr().err


def test_every_mapped_category_names_one_of_the_31_tags():
    assert {tag for tag, _ in babel_mag.TAG_MAP.values() if tag is not None} <= set(TAG_NAMES)
    assert all(why for _, why in babel_mag.TAG_MAP.values())


def test_a_users_tag_map_replaces_the_shipped_one(tmp_path):
    _standard(tmp_path)
    custom = tmp_path / "tags.json"
    custom.write_text(json.dumps({"walk": "Run", "dance": "Stretch"}))
    data, report = babel_mag.read_babel_mag(tmp_path, "train", tag_map=custom)
    assert _tags(data.segments.tags[0]) == ["Run"] and report.no_tag["turn"] == 1
    custom.write_text(json.dumps({"walk": "Strut"}))
    with pytest.raises(ValueError, match=r"tags.json: 'walk': expected one of the 31 tags or null, got 'Strut'"):
        babel_mag.read_babel_mag(tmp_path, "train", tag_map=custom)


@pytest.mark.parametrize("label, message", [
    (_label("walk", 0.0, 5.0), "['frame_ann']['labels'][0]['end_t']: 5.0 s is past the sequence's end (4.00 s"),
    (_label("walk", 2.0, 1.0), "['frame_ann']['labels'][0]: start_t 2.0 s is after end_t 1.0 s"),
    ({"seg_id": "x", "start_t": 0.0, "end_t": 1.0}, "['frame_ann']['labels'][0]: missing key 'act_cat'"),
])
def test_malformed_labels_name_the_file_and_the_label(tmp_path, label, message):
    write_babel(tmp_path, {"1": (120, np.full(120, 0.9), [label])})
    with pytest.raises(ValueError, match=re.escape(message)) as err:
        babel_mag.read_babel_mag(tmp_path, "train")
    assert "train.json" in str(err.value)


def test_non_finite_poses_name_the_motion_file(tmp_path):
    write_babel(tmp_path, {"1": (60, np.full(60, 0.9), [_label("walk", 0.0, 1.0)])})
    path = next((tmp_path / "amass").rglob("*.npz"))
    with np.load(path) as f:
        arrays = dict(f)
    arrays["poses"][3, 5] = np.nan
    np.savez(path, **arrays)
    with pytest.raises(ValueError, match=re.escape(f"{path}: 'poses'")):
        babel_mag.read_babel_mag(tmp_path, "train")
