"""Every ACTOR experiment runs end to end in its smoke profile."""

import json

import pytest

from experiments import actor_uestc


@pytest.mark.slow
def test_actor_uestc_smoke_writes_the_table_the_gif_and_the_reported_rows(tmp_path, monkeypatch):
    monkeypatch.setenv("JAXMOTION_CACHE", str(tmp_path / "cache"))
    result = actor_uestc.main(["--profile", "smoke", "--out", str(tmp_path / "out")])
    rows = result["rows"]
    assert list(rows) == ["ACTOR", "Real", "Real (reported)", "ACTOR (reported)"]
    assert list(rows["ACTOR"]) == ["FID_tr", "FID_test", "Acc. (%)", "Div.", "Multimod."]
    assert rows["ACTOR"]["FID_tr"]["n"] == actor_uestc.ActorUestcConfig.smoke().protocol.repetitions
    folder = tmp_path / "out" / "actor_uestc" / "smoke" / "seed-0"
    assert (folder / "generated.gif").stat().st_size > 0
    assert json.loads((folder / "metrics.json").read_text()) == result
