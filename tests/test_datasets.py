"""The one entry point, ``load_dataset``, for embedded and real datasets."""

import pickle
import subprocess
import sys
import time

import numpy as np
import pytest

from jaxmotion.data import dataset_names, load_dataset, synthetic
from jaxmotion.files import file_lock


def test_embedded_names_resolve_through_the_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("JAXMOTION_CACHE", str(tmp_path))
    small = synthetic.generate("synth-humanact12", count=24)
    # a planted cache entry is what comes back
    small.save(synthetic.cache_path("synth-humanact12", seed=5), source=synthetic.cache_source("synth-humanact12", seed=5))
    data = load_dataset("synth-humanact12", seed=5)
    np.testing.assert_array_equal(data.joints, small.joints)
    assert len(data) == 24


def test_smoke_sized_sets_are_cached_apart_from_the_whole_split(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("JAXMOTION_CACHE", str(tmp_path))
    first = load_dataset("synth-humanact12", count=12)
    path = synthetic.cache_path("synth-humanact12", count=12)
    assert path.is_file() and path != synthetic.cache_path("synth-humanact12") and "cached" in capsys.readouterr().err
    again = load_dataset("synth-humanact12", count=12)
    assert "cached" not in capsys.readouterr().err  # read back, not generated again
    np.testing.assert_array_equal(again.joints, first.joints)
    np.testing.assert_array_equal(again.joints, synthetic.generate("synth-humanact12", count=12).joints)
    assert len(again) == 12


def test_real_names_read_the_files_in_data_root(tmp_path):
    rng = np.random.default_rng(0)
    clips = {"poses": [0.1 * rng.normal(size=(t, 72)) for t in (4, 6)],
             "joints3D": [rng.normal(size=(t, 24, 3)) for t in (4, 6)], "y": [3, 7], "oldposes": []}
    (tmp_path / "humanact12poses.pkl").write_bytes(pickle.dumps(clips))
    data = load_dataset("humanact12", data_root=tmp_path)
    assert data.name == "humanact12" and list(data.lengths) == [4, 6] and list(data.actions) == [3, 7]
    assert data.rotations is not None


def test_names_are_listed_and_misuse_is_explained(tmp_path):
    names = dataset_names()
    assert "synth-humanact12" in names["embedded"] and "uestc" in names["real"]
    with pytest.raises(ValueError, match="needs data_root.*stand-in is 'synth-humanact12'"):
        load_dataset("humanact12")
    with pytest.raises(ValueError, match="is generated, not read"):
        load_dataset("synth-humanact12", data_root=tmp_path)
    with pytest.raises(ValueError, match="unknown dataset 'mnist'; embedded: .*synth-humanact12"):
        load_dataset("mnist")


@pytest.fixture
def small_generator(monkeypatch, tmp_path):
    """Full splits generated as 12-clip ones, in a cache under tmp_path; returns the generation count."""
    monkeypatch.setenv("JAXMOTION_CACHE", str(tmp_path))
    calls = []
    generate = synthetic.generate

    def small(name, split="train", *, seed=0, count=None, progress=False):
        calls.append((name, split, seed))
        return generate(name, split, seed=seed, count=12)

    monkeypatch.setattr(synthetic, "generate", small)
    return calls


def test_a_cache_file_holding_other_data_is_generated_again(small_generator, capsys):
    ntu = synthetic.load("synth-ntu13", seed=2)
    path = synthetic.cache_path("synth-humanact12", seed=2)
    path.write_bytes(synthetic.cache_path("synth-ntu13", seed=2).read_bytes())  # another variant's file
    data = synthetic.load("synth-humanact12", seed=2)
    assert "variant: 'synth-ntu13' (expected 'synth-humanact12')" in capsys.readouterr().err
    assert data.name == "synth-humanact12" and data.num_classes == 12 and ntu.num_classes == 13
    assert synthetic.load("synth-humanact12", seed=2).name == "synth-humanact12"  # the file now holds it
    assert small_generator == [("synth-ntu13", "train", 2), ("synth-humanact12", "train", 2)]


@pytest.mark.parametrize("damage", [b"", b"PK\x03\x04 cut short"])
def test_an_unreadable_cache_file_is_generated_again_naming_it(small_generator, capsys, damage):
    path = synthetic.cache_path("synth-humanact12", seed=3)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(damage)
    data = synthetic.load("synth-humanact12", seed=3)
    assert f"{path} cannot be read" in capsys.readouterr().err and len(data) == 12
    assert synthetic.load("synth-humanact12", seed=3).name == "synth-humanact12"


@pytest.mark.integration
def test_two_processes_wanting_one_split_generate_it_once(small_generator, tmp_path):
    probe = "from jaxmotion.data import synthetic\nprint(len(synthetic.load('synth-humanact12', seed=4)))"
    path, log = synthetic.cache_path("synth-humanact12", seed=4), tmp_path / "other.log"
    with file_lock(path, what="dataset cache"), log.open("w") as err:  # this process builds first
        other = subprocess.Popen([sys.executable, "-c", probe], stdout=subprocess.PIPE, stderr=err, text=True)
        deadline = time.monotonic() + 120
        while "waiting for" not in log.read_text():
            assert other.poll() is None and time.monotonic() < deadline, log.read_text()
            time.sleep(0.05)
        synthetic.load("synth-humanact12", seed=4)
    out, _ = other.communicate(timeout=120)
    assert other.returncode == 0 and out.strip() == "12", log.read_text()  # it read the 12 clips this one made
    assert "generating" not in log.read_text() and "cached" not in log.read_text()
