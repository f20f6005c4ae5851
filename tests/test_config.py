"""Config round trips and command-line overrides."""

import dataclasses
from typing import Literal

import pytest

from jaxmotion import config as cfglib


@dataclasses.dataclass(frozen=True)
class Inner:
    steps: int = 10
    lr: float = 1e-3
    dims: tuple[int, ...] = (64, 64)


@dataclasses.dataclass(frozen=True)
class Outer:
    inner: Inner = Inner()
    rep: Literal["axis_angle", "rot6d"] = "rot6d"
    name: str = "x"
    flag: bool = False
    maybe: int | None = None


def test_to_dict_from_dict_round_trip():
    cfg = Outer(Inner(3, 0.5, (1, 2, 3)), "axis_angle", "y", True, 7)
    data = cfglib.to_dict(cfg)
    assert data["inner"]["dims"] == [1, 2, 3]
    assert cfglib.from_dict(Outer, data) == cfg


def test_overrides_parse_by_field_type():
    cfg = cfglib.apply_overrides(
        Outer(), ["inner.steps=5", "inner.lr=2e-4", "inner.dims=[8,16]", "rep=axis_angle", "name=abc",
                  "flag=true", "maybe=3"]
    )
    assert cfg == Outer(Inner(5, 2e-4, (8, 16)), "axis_angle", "abc", True, 3)
    assert cfglib.apply_overrides(cfg, ["maybe=None"]).maybe is None


def test_int_field_accepted_for_float_but_not_the_reverse():
    assert cfglib.apply_overrides(Outer(), ["inner.lr=1"]).inner.lr == 1.0
    with pytest.raises(cfglib.ConfigError, match="inner.steps: expected an integer"):
        cfglib.apply_overrides(Outer(), ["inner.steps=1.5"])


@pytest.mark.parametrize(
    "override, message",
    [
        ("inner.nope=1", "unknown config field 'inner.nope'; valid fields: inner.steps, inner.lr, inner.dims, rep"),
        ("rep=quaternion", r"rep: expected one of \['axis_angle', 'rot6d'\]"),
        ("flag=yes", "flag: expected true or false"),
        ("inner=3", "is a group of fields"),
        ("name", "must look like field.path=value"),
        ("name.x=1", "unknown config field 'name.x'"),
    ],
)
def test_bad_overrides_name_the_field(override, message):
    with pytest.raises(cfglib.ConfigError, match=message):
        cfglib.apply_overrides(Outer(), [override])


def test_from_dict_rejects_unknown_fields():
    with pytest.raises(cfglib.ConfigError, match="unknown fields"):
        cfglib.from_dict(Outer, {"inner": {"steps": 1, "typo": 2}})


def test_diff_lists_changed_paths():
    a, b = cfglib.to_dict(Outer()), cfglib.to_dict(Outer(inner=Inner(steps=11)))
    assert cfglib.diff(a, b) == ["inner.steps: 10 -> 11"]
    assert cfglib.diff(a, a) == []


def test_unsupported_field_type_is_rejected():
    @dataclasses.dataclass(frozen=True)
    class Bad:
        x: dict = dataclasses.field(default_factory=dict)

    with pytest.raises(cfglib.ConfigError, match="unsupported config field type"):
        cfglib.to_dict(Bad())


def test_python_style_booleans_are_accepted():
    assert cfglib.apply_overrides(Outer(), ["flag=True"]).flag is True
    assert cfglib.apply_overrides(Outer(flag=True), ["flag=False"]).flag is False


@dataclasses.dataclass(frozen=True)
class Other:
    depth: int = 2
    steps: int = 1


@dataclasses.dataclass(frozen=True)
class Choice:
    part: Inner | Other = Inner()


def test_a_union_of_dataclasses_round_trips_as_the_member_its_fields_fit():
    for cfg in (Choice(), Choice(Other(depth=3, steps=2))):
        assert cfglib.from_dict(Choice, cfglib.to_dict(cfg)) == cfg
    assert cfglib.from_dict(Choice, {"part": {"depth": 4}}) == Choice(Other(4))  # defaults fill the rest
    with pytest.raises(cfglib.ConfigError, match=r"part: the fields \['steps'\] fit 2 of Inner \| Other"):
        cfglib.from_dict(Choice, {"part": {"steps": 4}})
    with pytest.raises(cfglib.ConfigError, match=r"fit 0 of Inner \| Other"):
        cfglib.from_dict(Choice, {"part": {"depth": 4, "lr": 1.0}})
    with pytest.raises(cfglib.ConfigError, match=r"part: expected one of Inner \| Other, got Outer"):
        cfglib.to_dict(Choice(Outer()))
    # overrides edit the member the config holds; another member's field is refused by name
    assert cfglib.apply_overrides(Choice(Other(1)), ["part.depth=5"]).part == Other(5)
    assert cfglib.apply_overrides(Choice(), ["part.lr=0.5"]).part.lr == 0.5
    with pytest.raises(cfglib.ConfigError, match="'part.depth': this config's Inner has no field 'depth'"):
        cfglib.apply_overrides(Choice(), ["part.depth=5"])
    with pytest.raises(cfglib.ConfigError, match="'part' is a group of fields"):
        cfglib.apply_overrides(Choice(), ["part=3"])
    assert cfglib.field_paths(Choice) == ["part.steps", "part.lr", "part.dims", "part.depth"]
