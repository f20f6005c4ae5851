"""The one entry point, ``load_dataset``, for embedded and real datasets."""

import sys
from pathlib import Path

import numpy as np
import pytest

from jaxmotion.data import dataset_names, load_dataset
from jaxmotion.data import synthetic

sys.path.insert(0, str(Path(__file__).parent))
import test_formats  # noqa: E402  (its fixture writers produce real-format files)


def test_embedded_names_resolve_through_the_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("JAXMOTION_CACHE", str(tmp_path))
    small = synthetic.generate("synth-humanact12", count=24)
    small.save(synthetic.cache_path("synth-humanact12", seed=5))  # a planted cache entry is what comes back
    data = load_dataset("synth-humanact12", seed=5)
    np.testing.assert_array_equal(data.joints, small.joints)
    assert len(data) == 24


def test_real_names_read_the_files_in_data_root(tmp_path):
    test_formats.write_humanact12poses(tmp_path, np.random.default_rng(0))
    data = load_dataset("humanact12", data_root=tmp_path)
    assert data.name == "humanact12" and len(data) > 0 and data.rotations is not None


def test_names_are_listed_and_misuse_is_explained(tmp_path):
    names = dataset_names()
    assert "synth-humanact12" in names["embedded"] and "uestc" in names["real"]
    with pytest.raises(ValueError, match="needs data_root.*stand-in is 'synth-humanact12'"):
        load_dataset("humanact12")
    with pytest.raises(ValueError, match="is generated, not read"):
        load_dataset("synth-humanact12", data_root=tmp_path)
    with pytest.raises(ValueError, match="unknown dataset 'mnist'; embedded: .*synth-humanact12"):
        load_dataset("mnist")
