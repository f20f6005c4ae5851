"""Every ACTOR experiment runs end to end in its smoke profile."""

import json

import pytest

from experiments import actor_ablation_batch, actor_ablation_kl, actor_ablation_layers, actor_ablation_rotation, actor_uestc

COLUMNS = ["FID_tr", "FID_test", "Acc. (%)", "Div.", "Multimod."]


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    """One cache for the module: the smoke evaluator and smoke data are made once."""
    return tmp_path_factory.mktemp("cache")


@pytest.mark.slow
def test_actor_uestc_smoke_writes_the_table_the_gif_and_the_reported_rows(tmp_path, monkeypatch, cache):
    monkeypatch.setenv("JAXMOTION_CACHE", str(cache))
    result = actor_uestc.main(["--profile", "smoke", "--out", str(tmp_path / "out")])
    rows = result["rows"]
    assert list(rows) == ["ACTOR", "Real", "Real (reported)", "ACTOR (reported)"]
    assert list(rows["ACTOR"]) == COLUMNS
    assert rows["ACTOR"]["FID_tr"]["n"] == actor_uestc.ActorUestcConfig.smoke().protocol.repetitions
    folder = tmp_path / "out" / "actor_uestc" / "smoke" / "seed-0"
    assert (folder / "generated.gif").stat().st_size > 0
    assert json.loads((folder / "metrics.json").read_text()) == result


@pytest.mark.slow
@pytest.mark.parametrize("module", [actor_ablation_kl, actor_ablation_batch, actor_ablation_layers,
                                    actor_ablation_rotation], ids=lambda m: m.__name__.rsplit("_", 1)[-1])
def test_appendix_ablation_smoke_has_one_row_per_value_and_the_real_row(tmp_path, monkeypatch, cache, module):
    monkeypatch.setenv("JAXMOTION_CACHE", str(cache))
    result = module.main(["--profile", "smoke", "--out", str(tmp_path)])
    config = next(c for c in vars(module).values() if isinstance(c, type) and hasattr(c, "SMOKE_VALUES")
                  and c.__module__ == module.__name__).smoke()
    assert list(result["rows"]) == [*config.variants(), "Real"]
    assert all(list(cells) == COLUMNS for cells in result["rows"].values())
    # each row trained in its own folder
    workdir = tmp_path / module.__name__.split(".")[-1] / "smoke" / "seed-0"
    assert len([p for p in workdir.iterdir() if (p / "checkpoints").is_dir()]) == len(config.values)
