"""Every ACTOR experiment runs end to end in its smoke profile."""

import json
import shutil

import imageio_ffmpeg
import numpy as np
import pytest
from PIL import Image

from experiments import (
    actor_ablation_batch,
    actor_ablation_kl,
    actor_ablation_layers,
    actor_ablation_rotation,
    actor_uestc,
)
from jaxmotion.data.datasets import paper_dataset
from jaxmotion.evaluation.recognizers import cache_folder
from jaxmotion.pipelines.actor import ActorGenerator
from smoke_checks import assert_real_recognised, assert_samples_vary, run_smoke
from smoke_checks import assert_generations_vary as _assert_generations_vary

COLUMNS = ["FID_tr", "FID_test", "Acc. (%)", "Div.", "Multimod."]
UESTC_CLASSES = paper_dataset("UESTC").num_classes


def assert_generations_vary(rows, row):
    _assert_generations_vary(rows, row, "Div.", "Multimod.")


@pytest.fixture(scope="module")
def uestc_smoke(tmp_path_factory):
    """actor_uestc's smoke run, made once for the module: ``(seed folder, result)``."""
    out = tmp_path_factory.mktemp("uestc-smoke")
    return out / "actor_uestc" / "smoke" / "seed-0", actor_uestc.main(["--profile", "smoke", "--out", str(out),
                                                                        "--video"])


@pytest.mark.smoke
@pytest.mark.filterwarnings(r"ignore:os\.fork\(\) was called:RuntimeWarning")  # ffmpeg decodes in a subprocess
def test_actor_uestc_smoke_writes_the_table_the_gif_the_video_and_the_reported_rows(uestc_smoke):
    folder, result = uestc_smoke
    rows = result["rows"]
    assert list(rows) == ["ACTOR", "Real", "Real (reported)", "ACTOR (reported)"]
    assert list(rows["ACTOR"]) == COLUMNS
    assert rows["ACTOR"]["FID_tr"]["n"] == actor_uestc.ActorUestcConfig.smoke().table.protocol.repetitions
    assert_generations_vary(rows, "ACTOR")
    assert_real_recognised(rows, "Acc. (%)", UESTC_CLASSES)
    with Image.open(folder / "generated.gif") as gif:  # the smoke's short clips, one picture per frame
        assert gif.n_frames == actor_uestc.ActorUestcConfig.smoke().picture_frames
    reader = imageio_ffmpeg.read_frames(str(folder / "generated.mp4"))  # --video: the same grid as a video
    size = next(reader)["size"]
    assert size == gif.size or size == tuple(s + s % 2 for s in gif.size)
    assert sum(1 for _ in reader) == actor_uestc.ActorUestcConfig.smoke().picture_frames
    assert json.loads((folder / "metrics.json").read_text()) == result
    assert [c["claim"] for c in result["claims"]] == [str(c) for c in actor_uestc.CLAIMS]
    assert all(c["verdict"] in ("holds", "does not hold", "inconclusive") for c in result["claims"])
    assert "Claims of the paper" in (folder / "table.md").read_text()
    record = json.loads((folder / "config.json").read_text())
    assert record["environment"]["jax"] and record["inputs"]["evaluators"][0]["name"] == "synth-uestc/stgcn"
    evaluator = json.loads((cache_folder(actor_uestc.ActorUestcConfig.smoke().table.evaluator) / "recognizer.json")
                           .read_text())
    assert result["run"]["evaluators"][0]["held_out_accuracy"] == evaluator["held_out"]["accuracy"]


@pytest.mark.smoke
def test_a_constant_sampler_fails_the_smoke_checks(tmp_path, monkeypatch, capsys, uestc_smoke):
    # the trained smoke run without its results: the same command evaluates it again, now constant
    trained = tmp_path / "actor_uestc" / "smoke" / "seed-0"
    shutil.copytree(uestc_smoke[0], trained, ignore=shutil.ignore_patterns("metrics.json", "table.md", "*.gif"))
    real_sampler = ActorGenerator.sampler

    def constant(self):
        sample = real_sampler(self)

        def same_motion(key, actions, durations):
            motions = dict(sample(key, actions * 0, durations))
            return {k: np.broadcast_to(np.asarray(v)[:1], np.shape(v)) for k, v in motions.items()}

        return same_motion

    monkeypatch.setattr(ActorGenerator, "sampler", constant)
    rows = actor_uestc.main(["--profile", "smoke", "--out", str(tmp_path)])["rows"]
    assert "resuming from the checkpoint" in capsys.readouterr().err  # evaluated, not trained again
    # under the same protocol a constant sampler scores no diversity at all, the trained row some
    trained_diversity = uestc_smoke[1]["rows"]["ACTOR"]["Div."]["mean"]
    assert rows["ACTOR"]["Div."]["mean"] == pytest.approx(0.0, abs=1e-4) and trained_diversity > 1e-3
    with pytest.raises(AssertionError, match="do not vary"):
        assert_generations_vary(rows, "ACTOR")
    with pytest.raises(AssertionError, match="do not vary"):
        assert_samples_vary(trained)


@pytest.mark.smoke
@pytest.mark.parametrize("module", [actor_ablation_kl, actor_ablation_batch, actor_ablation_layers,
                                    actor_ablation_rotation], ids=lambda m: m.__name__.rsplit("_", 1)[-1])
def test_appendix_ablation_smoke_has_one_row_per_value_and_the_real_row(tmp_path, module):
    result = run_smoke(module, tmp_path)
    config = next(c for c in vars(module).values() if isinstance(c, type) and hasattr(c, "SMOKE_VALUES")
                  and c.__module__ == module.__name__).smoke()
    assert list(result["rows"]) == [*config.rows(), "Real"]
    assert all(list(cells) == COLUMNS for cells in result["rows"].values())
    for row in config.rows():
        assert_generations_vary(result["rows"], row)
    assert_real_recognised(result["rows"], "Acc. (%)", UESTC_CLASSES)
    assert len(result["claims"]) == len(module.CLAIMS)
    # each row trained in its own folder
    workdir = tmp_path / module.__name__.split(".")[-1] / "smoke" / "seed-0"
    assert len([p for p in workdir.iterdir() if (p / "checkpoints").is_dir()]) == len(config.values)
