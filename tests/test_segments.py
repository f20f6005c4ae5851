"""Segment tables of multi-action sequences: validation, their life in a dataset (pack, index, subset, concatenate,
save and load), action items with context, transition counts, and programs checked action by action."""

import dataclasses
import re

import numpy as np
import pytest

from jaxmotion.data import Motion, Program, ProgramAction, Segments, concatenate, pack, transition_counts
from jaxmotion.geometry import SMPL24

TAGS = ("walk", "turn", "stand", "arms")


def _segments(rows, num_classes=len(TAGS)):
    """``rows``: ``(sequence, start, end, tags, next_tags)`` with tags as index tuples."""
    return Segments.from_rows([(*row, -1) for row in rows], num_classes)


def _take(length, rows, seed):
    rng = np.random.default_rng(seed)
    return Motion(joints=rng.normal(size=(length, 24, 3)).astype(np.float32),
                  translation=rng.normal(size=(length, 3)).astype(np.float32),
                  rotations=rng.normal(size=(length, 24, 3)).astype(np.float32), action=rows[0][3][0],
                  name=f"take{seed}", segments=_segments(rows))


@pytest.fixture
def takes():
    """Two takes: walk, turn, walk+... ; stand with arms, walk."""
    first = _take(30, [(0, 8, 15, (0,), (1,)), (0, 15, 22, (1,), (0,)), (0, 22, 30, (0,), (0,))], 0)
    second = _take(20, [(0, 6, 12, (2, 3), (0,)), (0, 12, 20, (0,), (0,))], 1)
    return pack([first, second], name="toy-mag", split="train", class_names=TAGS, skeleton=SMPL24, fps=30)


def test_a_dataset_keeps_its_segments_through_index_subset_concatenate_and_files(takes, tmp_path):
    seg = takes.segments
    assert seg.sequence.tolist() == [0, 0, 0, 1, 1] and seg.durations.tolist() == [7, 7, 8, 6, 8]
    assert seg.primary.tolist() == [0, 1, 0, 2, 0]
    second = takes[1]
    assert second.segments.sequence.tolist() == [0, 0] and second.segments.start.tolist() == [6, 12]
    swapped = takes.subset([1, 0])
    assert swapped.segments.sequence.tolist() == [0, 0, 1, 1, 1] and swapped.segments.start.tolist() == [6, 12, 8,
                                                                                                          15, 22]
    both = concatenate([takes, takes], split="all")
    assert both.segments.sequence.tolist() == [0, 0, 0, 1, 1, 2, 2, 2, 3, 3]
    path = tmp_path / "mag.npz"
    takes.save(path)
    back = type(takes).load(path)
    for field in dataclasses.fields(Segments):
        np.testing.assert_array_equal(getattr(back.segments, field.name), getattr(seg, field.name))
    plain = dataclasses.replace(takes, segments=None)
    with pytest.raises(ValueError, match=r"segments \(present in one, absent in the other\)"):
        concatenate([takes, plain], split="all")


def test_action_items_carry_the_context_frames_and_drop_actions_without_them(takes):
    items = takes.action_items(context=7)
    assert items.dropped == 1  # the second take's first action starts at frame 6
    assert len(items) == 4 and items.durations.tolist() == [7, 7, 8, 8]
    first = items.data[0]
    np.testing.assert_array_equal(first.joints, takes[0].joints[1:15])  # 7 frames before frame 8, then 8..14
    np.testing.assert_array_equal(items.tags[3], [True, False, False, False])
    np.testing.assert_array_equal(items.next_tags[0], [False, True, False, False])
    assert items.data.actions.tolist() == [0, 1, 0, 0] and items.data.names[0] == "take0/0"
    assert [p.shape for p in items.ground_paths()] == [(7, 2), (7, 2), (8, 2), (8, 2)]
    with pytest.raises(ValueError, match="no segments"):
        dataclasses.replace(takes, segments=None).action_items()


def test_transition_counts_pair_the_tags_of_consecutive_actions_of_a_sequence(takes):
    counts = transition_counts(takes.segments)
    expected = np.zeros((4, 4), int)
    expected[0, 1] = expected[1, 0] = 1  # walk -> turn -> walk
    expected[2, 0] = expected[3, 0] = 1  # stand+arms -> walk; nothing across the two takes
    np.testing.assert_array_equal(counts, expected)


@pytest.mark.parametrize("rows, message", [
    ([(0, 5, 5, (0,), (0,))], "segments.end: row 0: expected after its start"),
    ([(0, 0, 5, (), (0,))], "segments.tags: row 0: expected at least one tag"),
    ([(0, 0, 5, (0,), (0,)), (0, 4, 9, (1,), (1,))], "segments.start: row 1: expected a start at or after the "
                                                    "previous action's end"),
    ([(1, 0, 5, (0,), (0,)), (0, 0, 5, (1,), (1,))], "segments.sequence: row 1: expected rows ordered by sequence"),
])
def test_malformed_tables_name_the_field_and_row(rows, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        _segments(rows)


def test_a_table_must_fit_its_dataset(takes):
    long = _segments([(0, 0, 31, (0,), (0,)), (1, 0, 5, (0,), (0,))])
    with pytest.raises(ValueError, match=r"segments.end: row 0: expected at most its sequence's length"):
        dataclasses.replace(takes, segments=long)
    wide = _segments([(0, 0, 5, (0,), (0,))], num_classes=5)
    with pytest.raises(ValueError, match=r"segments.tags: expected one column per class \(4\), got 5"):
        dataclasses.replace(takes, segments=wide)


PROGRAM = Program((ProgramAction(("walk",), 40, tuple((0.0, 0.05 * t) for t in range(40))),
                   ProgramAction(("stand", "arms"), 30)))


def test_a_program_lists_its_tags_and_frames():
    PROGRAM.check(TAGS, 120, num_joints=24)
    np.testing.assert_array_equal(PROGRAM.tag_matrix(TAGS), [[1, 0, 0, 0], [0, 0, 1, 1]])
    assert PROGRAM.num_frames == 70


@pytest.mark.parametrize("action, message", [
    (ProgramAction(("wlak",), 30), "program: action 1: tags: unknown tag 'wlak'; known tags: walk, turn"),
    (ProgramAction((), 30), "program: action 1: tags: expected one or more tag names"),
    (ProgramAction(("walk",), 0), "program: action 1: duration: expected 1 to 120 frames (the model's longest), "
                                  "got 0"),
    (ProgramAction(("walk",), 121), "program: action 1: duration: expected 1 to 120 frames"),
    (ProgramAction(("walk",), 3, ((0, 0), (0, 1))), "program: action 1: path: expected [duration, 2] = (3, 2) "
                                                   "finite ground points (x, z), got shape (2, 2)"),
    (ProgramAction(("walk",), 2, ((0, 0), (np.nan, 1))), "program: action 1: path: expected [duration, 2] = (2, 2) "
                                                        "finite ground points (x, z), got shape (2, 2), 1 not "
                                                        "finite"),
])
def test_a_bad_program_names_the_action_and_the_field(action, message):
    program = Program((PROGRAM.actions[0], action))
    with pytest.raises(ValueError, match=re.escape(message)):
        program.check(TAGS, 120, num_joints=24)


def test_a_program_context_must_be_six_finite_frames():
    good = {"rotations": np.zeros((6, 24, 3)), "translation": np.zeros((6, 3))}
    dataclasses.replace(PROGRAM, context=good).check(TAGS, 120, num_joints=24)
    with pytest.raises(ValueError, match=re.escape("program: context: translation: expected [6, 3] finite values, "
                                                   "got shape (5, 3)")):
        dataclasses.replace(PROGRAM, context={**good, "translation": np.zeros((5, 3))}).check(TAGS, 120, num_joints=24)
