"""Every experiment's config, in every profile, is one :mod:`jaxmotion.config` can write, read back, hash and
edit through every path it lists; its ``--help`` builds. Configs only: nothing trains."""

import importlib
import json
import pkgutil
import re

import pytest

import experiments
from jaxmotion import config as cfglib

NAMES = sorted(m.name for m in pkgutil.iter_modules(experiments.__path__))


def _config_class(name: str) -> type:
    module = importlib.import_module(f"experiments.{name}")
    classes = [v for v in vars(module).values() if isinstance(v, type) and v.__module__ == module.__name__
               and hasattr(v, "__dataclass_params__") and callable(getattr(v, "paper", None))]
    assert len(classes) == 1, f"experiments.{name}: expected one config class, got {classes}"
    return classes[0]


@pytest.mark.parametrize("name", NAMES)
@pytest.mark.parametrize("profile", cfglib.PROFILES)
def test_config_round_trips_hashes_and_takes_its_own_values_at_every_path(name, profile):
    cls = _config_class(name)
    config = getattr(cls, profile)()
    data = json.loads(cfglib.to_json(config))
    assert cfglib.from_dict(cls, data) == config and hash(cfglib.from_dict(cls, data)) == hash(config)
    leaves = cfglib.flatten(data)
    assert list(leaves) == cfglib.field_paths(config)
    overrides = [f"{path}={value if isinstance(value, str) else json.dumps(value)}" for path, value in leaves.items()]
    assert cfglib.apply_overrides(config, overrides) == config


@pytest.mark.parametrize("name", NAMES)
def test_help_lists_the_config_fields_and_real_examples(name, capsys):
    module = importlib.import_module(f"experiments.{name}")
    with pytest.raises(SystemExit) as exit_:
        module.main(["--help"])
    assert exit_.value.code == 0
    text = capsys.readouterr().out
    assert "FACTS" not in text and "shared/" not in text  # files outside the repository
    assert all(f"\n  {path}\n" in text for path in cfglib.field_paths(_config_class(name))[:3])


@pytest.mark.parametrize("name", NAMES)
def test_no_integer_field_takes_a_negative_value(name):
    """Counts, sizes, steps, indices and seeds are all >= 0 (most >= 1): -1 anywhere is an error naming the path
    being set, before anything runs, not a value some later step wraps, clips or loops over zero times."""
    config = _config_class(name).smoke()
    for path, value in cfglib.flatten(json.loads(cfglib.to_json(config))).items():
        if isinstance(value, int) and not isinstance(value, bool):
            with pytest.raises(cfglib.ConfigError, match=f"'?{re.escape(path)}'?"):
                cfglib.apply_overrides(config, [f"{path}=-1"])
