"""The one entry point, ``load_dataset``, for embedded and real datasets."""

import pickle

import numpy as np
import pytest

from jaxmotion.data import dataset_names, load_dataset, synthetic


def test_embedded_names_resolve_through_the_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("JAXMOTION_CACHE", str(tmp_path))
    small = synthetic.generate("synth-humanact12", count=24)
    small.save(synthetic.cache_path("synth-humanact12", seed=5))  # a planted cache entry is what comes back
    data = load_dataset("synth-humanact12", seed=5)
    np.testing.assert_array_equal(data.joints, small.joints)
    assert len(data) == 24


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
