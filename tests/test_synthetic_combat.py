"""synth-combat-2p .. 5p (GTA Combat stand-ins): GTA-22 scenes of 2-5 fighters, strikes, defences, knockdowns;
the multi-person pictures."""

import numpy as np
import pytest

from jaxmotion.data import synthetic
from jaxmotion.geometry import GTA22
from jaxmotion.viz import motion as pictures


@pytest.fixture(scope="module", params=[2, 5])
def fights(request):
    return synthetic.generate(f"synth-combat-{request.param}p", "train", seed=0, count=8)


def test_layout_and_determinism(fights):
    p = fights.persons
    assert p in (2, 5) and fights.skeleton is GTA22 and fights.joints.shape[1:] == (p, 22, 3)
    assert fights.class_names == ("combat",) and fights.mode_names == (("boxing", "brawling"),)
    again = synthetic.generate(fights.name, "train", seed=0, count=2)
    np.testing.assert_array_equal(again.joints, fights.subset([0, 1]).joints)
    np.testing.assert_array_equal(fights.translation, fights.joints[:, :, 0])


def test_fighters_start_apart_and_strikes_reach_the_opponents(fights):
    wrist = [GTA22.index("left_wrist"), GTA22.index("right_wrist")]
    reached = 0
    for m in fights:
        roots = m.joints[:, 0, 0]  # [P, 3] at frame 0
        gaps = np.linalg.norm((roots[:, None] - roots[None])[..., [0, 2]], axis=-1)
        assert gaps[np.triu_indices(m.persons, 1)].min() > 0.5  # nobody starts inside somebody else
        # a fist comes out of the guard onto another fighter: a wrist within 0.4 m of another's head centre
        heads = m.joints[:, :, GTA22.index("head_center")]
        near = min(np.linalg.norm(m.joints[a, :, w] - heads[b], axis=-1).min()
                   for a in range(m.persons) for b in range(m.persons) if a != b for w in wrist)
        reached += near < 0.4
    assert reached >= len(fights) // 2  # (a short clip may hold one strike, dodged)


def test_brawls_knock_fighters_down_and_they_get_up():
    brawls = synthetic.generate("synth-combat-2p", "train", seed=0, count=16)
    drops = [m.joints[:, :, 0, 1].max(axis=1) - m.joints[:, :, 0, 1].min(axis=1) for m in brawls]
    down = [d.max() for d, mode in zip(drops, brawls.modes) if mode == 1]
    assert max(down) > 0.3  # a knockdown lowers the pelvis by ~0.4 m
    for m, d in zip(brawls, drops):
        if d.max() > 0.3:
            p = int(d.argmax())
            assert m.joints[p, -1, 0, 1] > m.joints[p, :, 0, 1].max() - 0.15  # and stands again by the end


def test_multi_person_previews_render(fights, tmp_path):
    pictures.filmstrip(fights[0], fights.skeleton, str(tmp_path / "strip.png"), frames=3)
    pictures.render_grid(fights, [0], str(tmp_path / "grid.png"), still=True)
    pictures.render_grid(fights, [0], str(tmp_path / "grid.gif"), max_frames=3)
    assert all((tmp_path / f).stat().st_size > 1000 for f in ("strip.png", "grid.png", "grid.gif"))
