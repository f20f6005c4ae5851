"""Config round trips and command-line overrides."""

import dataclasses
import json
import re
from collections.abc import Mapping
from typing import Literal

import pytest
from hypothesis import given
from hypothesis import strategies as st

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
        ("inner.nope=1", "unknown config field 'inner.nope'; valid fields: inner.steps, inner.lr, inner.dims$"),
        ("nope=1", "unknown config field 'nope'; valid fields: inner.steps, inner.lr, inner.dims, rep, name"),
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
    with pytest.raises(cfglib.ConfigError, match="unknown config field 'part.depth'; valid fields: part.steps, "
                                                 "part.lr, part.dims; Other has it, this config holds Inner"):
        cfglib.apply_overrides(Choice(), ["part.depth=5"])
    with pytest.raises(cfglib.ConfigError, match="'part' is a group of fields"):
        cfglib.apply_overrides(Choice(), ["part=3"])
    assert cfglib.field_paths(Choice) == ["part.steps", "part.lr", "part.dims", "part.depth"]


# --- nested groups: optional dataclasses, mappings, seeds -------------------------------------------


@dataclasses.dataclass(frozen=True)
class Loop:
    steps: int = 10
    seed: int = 0  # a seed by its name


@dataclasses.dataclass(frozen=True)
class Training:
    loop: Loop = Loop()
    lr: float = 1e-3


@dataclasses.dataclass(frozen=True)
class Evaluator:
    dataset: str
    loop: Loop = Loop()


@dataclasses.dataclass(frozen=True)
class Table:
    rows: Mapping[str, Mapping[str, Training]] = cfglib.FrozenMap()
    evaluator: Evaluator | None = None
    part: Inner | Other | None = None
    weights: dict[str, float] = cfglib.FrozenMap()
    draw: cfglib.Seed = 0  # a seed by its type

    def __post_init__(self):
        if any(w < 0 for w in self.weights.values()):
            raise ValueError(f"weights: expected non-negative weights, got {dict(self.weights)}")


def _table() -> Table:
    rows = cfglib.FrozenMap({
        "uestc": cfglib.FrozenMap({"actor": Training(Loop(5), 0.5)}),
        "ntu13": cfglib.FrozenMap({"actformer": Training(), "csgn": Training(lr=0.1)}),
    })
    return Table(rows, Evaluator("synth"), Other(3), cfglib.FrozenMap({"b": 2.0, "a": 1.0}), 7)


def test_nested_optional_and_mapping_configs_round_trip_through_json_in_key_order():
    cfg = _table()
    data = json.loads(json.dumps(cfglib.to_dict(cfg)))
    assert list(data["rows"]) == ["uestc", "ntu13"] and list(data["rows"]["ntu13"]) == ["actformer", "csgn"]
    assert data["weights"] == {"b": 2.0, "a": 1.0} and list(data["weights"]) == ["b", "a"]
    assert data["rows"]["uestc"]["actor"] == {"loop": {"steps": 5, "seed": 0}, "lr": 0.5}
    back = cfglib.from_dict(Table, data)
    assert back == cfg and isinstance(back.rows["ntu13"], cfglib.FrozenMap)
    assert cfglib.to_json(back) == cfglib.to_json(cfg) == json.dumps(data, indent=2)
    for unset in (Table(), dataclasses.replace(cfg, evaluator=None, part=Inner())):
        assert cfglib.from_dict(Table, cfglib.to_dict(unset)) == unset


def test_configs_holding_mappings_are_hashable_and_equal_by_value():
    cfg, again = _table(), cfglib.from_dict(Table, cfglib.to_dict(_table()))
    assert cfg == again and hash(cfg) == hash(again) and len({cfg, again}) == 1
    changed = cfglib.apply_overrides(cfg, ["rows.ntu13.csgn.lr=0.2"])
    assert changed != cfg and len({cfg, changed}) == 2
    # a FrozenMap equals any mapping with its items, whatever their order, as dict does; so does its hash
    ab, ba = cfglib.FrozenMap({"a": 1, "b": 2}), cfglib.FrozenMap([("b", 2), ("a", 1)])
    assert ab == ba == {"b": 2, "a": 1} and hash(ab) == hash(ba) and list(ba) == ["b", "a"]
    assert ab != {"a": 1} and repr(ab) == "FrozenMap({'a': 1, 'b': 2})"


def test_overrides_descend_into_mappings_optional_groups_and_the_union_member_held():
    cfg = cfglib.apply_overrides(_table(), ["rows.ntu13.actformer.loop.steps=100", "weights.a=0.25",
                                            "evaluator.loop.steps=3", "part.depth=9", "rows.uestc.actor.lr=1"])
    assert cfg.rows["ntu13"]["actformer"] == Training(Loop(100))
    assert cfg.rows["ntu13"]["csgn"] == Training(lr=0.1) and cfg.rows["uestc"]["actor"] == Training(Loop(5), 1.0)
    assert list(cfg.rows) == ["uestc", "ntu13"] and list(cfg.weights) == ["b", "a"] and cfg.weights["a"] == 0.25
    assert cfg.evaluator == Evaluator("synth", Loop(3)) and cfg.part == Other(9)
    whole = cfglib.apply_overrides(cfg, ['rows={"x": {"y": {"lr": 0.5}}}', 'weights={}'])
    assert whole.rows == {"x": {"y": Training(lr=0.5)}} and whole.weights == {}


def test_a_mapping_of_dataclass_unions_holds_each_key_as_the_member_its_fields_fit():
    @dataclasses.dataclass(frozen=True)
    class Models:
        by_name: Mapping[str, Inner | Other]

    cfg = Models(cfglib.FrozenMap({"gru": Other(2), "mlp": Inner()}))
    assert cfglib.from_dict(Models, cfglib.to_dict(cfg)) == cfg
    assert cfglib.field_paths(Models) == ["by_name.<key>.steps", "by_name.<key>.lr", "by_name.<key>.dims",
                                          "by_name.<key>.depth"]
    edited = cfglib.apply_overrides(cfg, ["by_name.gru.depth=5", "by_name.mlp.dims=[1]"])
    assert edited.by_name == {"gru": Other(5), "mlp": Inner(dims=(1,))}
    with pytest.raises(cfglib.ConfigError, match="unknown config field 'by_name.mlp.depth'; .* Other has it"):
        cfglib.apply_overrides(cfg, ["by_name.mlp.depth=5"])


def test_an_unset_optional_group_is_set_whole_and_unset_with_null():
    cfg = Table()
    with pytest.raises(cfglib.ConfigError, match=r"'evaluator.dataset': the group 'evaluator' is None .* "
                                                 r"--set 'evaluator=\{\"dataset\": ...\}'.*required: dataset"):
        cfglib.apply_overrides(cfg, ["evaluator.dataset=uestc"])
    cfg = cfglib.apply_overrides(cfg, ['evaluator={"dataset": "uestc"}', "evaluator.loop.steps=4",
                                       'part={"depth": 2}'])
    assert cfg.evaluator == Evaluator("uestc", Loop(4)) and cfg.part == Other(2)
    assert cfglib.apply_overrides(cfg, ["evaluator=null", "part=None"]) == Table()
    with pytest.raises(cfglib.ConfigError, match=r"evaluator: missing fields \['dataset'\] of Evaluator"):
        cfglib.apply_overrides(cfg, ['evaluator={"loop": {"steps": 1}}'])
    with pytest.raises(cfglib.ConfigError, match="'evaluator' is a group of fields; set one of: "
                                                 "evaluator.dataset, evaluator.loop.steps, evaluator.loop.seed"):
        cfglib.apply_overrides(cfg, ["evaluator=uestc"])


def test_field_paths_of_a_class_declare_every_leaf_and_of_an_instance_the_leaves_it_holds():
    assert cfglib.field_paths(Table) == [
        "rows.<key>.<key>.loop.steps", "rows.<key>.<key>.loop.seed", "rows.<key>.<key>.lr",
        "evaluator.dataset", "evaluator.loop.steps", "evaluator.loop.seed",
        "part.steps", "part.lr", "part.dims", "part.depth", "weights.<key>", "draw"]
    assert cfglib.field_paths(_table()) == [
        "rows.uestc.actor.loop.steps", "rows.uestc.actor.loop.seed", "rows.uestc.actor.lr",
        "rows.ntu13.actformer.loop.steps", "rows.ntu13.actformer.loop.seed", "rows.ntu13.actformer.lr",
        "rows.ntu13.csgn.loop.steps", "rows.ntu13.csgn.loop.seed", "rows.ntu13.csgn.lr",
        "evaluator.dataset", "evaluator.loop.steps", "evaluator.loop.seed", "part.depth", "part.steps",
        "weights.b", "weights.a", "draw"]
    assert cfglib.field_paths(Table()) == ["rows", "evaluator", "part", "weights", "draw"]  # set whole


def test_unknown_mapping_keys_and_paths_below_a_value_are_named():
    with pytest.raises(cfglib.ConfigError, match=r"unknown config field 'rows.ntu31.actformer.lr': 'rows' has "
                                                 r"the keys \['uestc', 'ntu13'\]; .* --set 'rows=\{...\}'"):
        cfglib.apply_overrides(_table(), ["rows.ntu31.actformer.lr=1"])
    with pytest.raises(cfglib.ConfigError, match=r"unknown config field 'draw.x': 'draw' is a single value \(Seed\)"):
        cfglib.apply_overrides(_table(), ["draw.x=1"])
    with pytest.raises(cfglib.ConfigError, match="unknown config field 'rows.uestc.actor.loop.stpes'; valid fields: "
                                                 "rows.uestc.actor.loop.steps, rows.uestc.actor.loop.seed$"):
        cfglib.apply_overrides(_table(), ["rows.uestc.actor.loop.stpes=1"])


@pytest.mark.parametrize("key", ["a.b", "", " a", "a=b", 3])
def test_mapping_keys_must_fit_a_dotted_path(key):
    with pytest.raises(cfglib.ConfigError, match=rf"weights: expected keys usable in a dotted path .* "
                                                 rf"for dict\[str, float\], got {re.escape(repr(key))}"):
        cfglib.from_dict(Table, {"weights": {key: 1.0}})
    with pytest.raises(cfglib.ConfigError, match=r"rows: expected keys usable in a dotted path"):
        cfglib.to_dict(Table(rows=cfglib.FrozenMap({key: cfglib.FrozenMap()})))


def test_a_config_mapping_must_be_immutable():
    with pytest.raises(cfglib.ConfigError, match=r"weights: expected a FrozenMap \(dict\[str, float\]\), "
                                                 r"got \{'a': 1.0\}"):
        cfglib.to_dict(Table(weights={"a": 1.0}))


def test_replace_paths_edits_through_mappings_and_checks_the_value():
    cfg = cfglib.replace_paths(_table(), {"rows.ntu13.csgn.lr": 1, "evaluator": Evaluator("x"), "weights.b": 3})
    assert cfg.rows["ntu13"]["csgn"].lr == 1.0 and isinstance(cfg.rows["ntu13"]["csgn"].lr, float)
    assert cfg.evaluator == Evaluator("x") and cfg.weights == {"b": 3.0, "a": 1.0}
    with pytest.raises(cfglib.ConfigError, match=r"rows.ntu13.csgn.loop.steps: expected an integer from -2\*\*31 to 2\*\*31 - 1 \(2147483647\), got 'x'"):
        cfglib.replace_paths(cfg, {"rows.ntu13.csgn.loop.steps": "x"})
    with pytest.raises(cfglib.ConfigError, match=r"^config: weights: expected non-negative weights, got \{'b': -1.0, "
                                                 r"'a': 1.0\} \(setting 'weights.b'\)$"):
        cfglib.replace_paths(cfg, {"weights.b": -1})


def test_diff_names_the_paths_inside_mappings_and_groups():
    a = cfglib.to_dict(_table())
    b = cfglib.to_dict(cfglib.apply_overrides(_table(), ["rows.ntu13.actformer.loop.steps=100", "evaluator=null"]))
    assert cfglib.diff(a, b) == [
        "evaluator: '<missing>' -> None", "evaluator.dataset: 'synth' -> '<missing>'",
        "evaluator.loop.seed: 0 -> '<missing>'", "evaluator.loop.steps: 10 -> '<missing>'",
        "rows.ntu13.actformer.loop.steps: 10 -> 100"]


@pytest.mark.parametrize("override, path, expected, value", [
    ("rows.ntu13.csgn.loop.steps=[1]", "rows.ntu13.csgn.loop.steps", "an integer", "[1]"),
    ('rows.ntu13.csgn.loop.steps={"a": 1}', "rows.ntu13.csgn.loop.steps", "an integer", "{'a': 1}"),
    ("rows.ntu13.csgn.lr=fast", "rows.ntu13.csgn.lr", "a number", "'fast'"),
    ("rows.ntu13.csgn.lr=true", "rows.ntu13.csgn.lr", "a number", "True"),
    ("rows.ntu13.csgn.lr=NaN", "rows.ntu13.csgn.lr", "a finite number", "nan"),
    ('part={"dims": [1], "depth": 2}', "part: the fields ['depth', 'dims'] fit 0 of Inner | Other", "exactly one",
     "{'dims': [1], 'depth': 2}"),
    ("evaluator.dataset=null", "evaluator.dataset", "a string", "None"),
    ("evaluator.loop.seed=4294967296", "evaluator.loop.seed", "a seed from 0 to 4294967295 (2**32 - 1)", "4294967296"),
    ("evaluator.loop.seed=-1", "evaluator.loop.seed", "a seed", "-1"),
    # jax counts in 32 bits: a step count past 2**31 - 1 would overflow where it is used
    ("rows.ntu13.csgn.loop.steps=" + str(10**30), "rows.ntu13.csgn.loop.steps",
     "an integer from -2**31 to 2**31 - 1 (2147483647)", str(10**30)),
    ("rows.ntu13.csgn.loop.steps=2147483648", "rows.ntu13.csgn.loop.steps", "an integer from -2**31", "2147483648"),
    ("draw=4294967296", "draw", "a seed from 0 to 4294967295 (2**32 - 1)", "4294967296"),
    ("weights.a=[1,", "weights.a", "a number", "'[1,' ('[1,' is not valid JSON"),
    ("weights=[1]", "'weights' is a group of fields; set one of: weights.b, weights.a", "JSON mapping (dict[str, float])",
     "'[1]'"),
    ('weights={"a": "x"}', "weights.a", "a number", "'x'"),
    ('weights={"a": 1', "'weights' is a group", "JSON mapping", "'{\"a\": 1' (not JSON: Expecting"),
    ('rows={"x": [1]}', "rows.x", "a mapping (Mapping[str, Training])", "[1]"),
])
def test_bad_override_values_name_the_path_the_expected_type_and_the_value(override, path, expected, value):
    with pytest.raises(cfglib.ConfigError) as err:
        cfglib.apply_overrides(_table(), [override])
    message = str(err.value)
    assert path in message and expected in message and value in message, message


@pytest.mark.parametrize("data, path, expected, value", [
    ({"inner": [1]}, "inner", "a mapping of Inner's fields", "[1]"),
    ({"inner": {"dims": [1, "a"]}}, "inner.dims[1]", "an integer", "'a'"),
    ({"inner": {"dims": 3}}, "inner.dims", "a list (tuple[int, ...])", "3"),
    ({"inner": {"typo": 1}}, "inner", "unknown fields ['typo'] of Inner", "valid: ['steps', 'lr', 'dims']"),
    ({"rep": "euler"}, "rep", "one of ['axis_angle', 'rot6d']", "'euler'"),
    ({"maybe": "3"}, "maybe", "an integer", "'3'"),
    ({"flag": 1}, "flag", "true or false", "1"),
])
def test_bad_from_dict_values_name_the_path_the_expected_type_and_the_value(data, path, expected, value):
    with pytest.raises(cfglib.ConfigError) as err:
        cfglib.from_dict(Outer, data)
    message = str(err.value)
    assert message.startswith(path + ":") and expected in message and value in message, message


def test_from_dict_of_nested_mappings_names_the_deep_path():
    bad = {"rows": {"x": {"y": {"loop": {"steps": 1.5}}}}}
    with pytest.raises(cfglib.ConfigError, match=r"^rows.x.y.loop.steps: expected an integer from -2\*\*31 to 2\*\*31 - 1 \(2147483647\), got 1.5$"):
        cfglib.from_dict(Table, bad)
    with pytest.raises(cfglib.ConfigError, match=r"^config: expected a mapping of Table's fields, got \[\]$"):
        cfglib.from_dict(Table, [])


def test_seeds_are_range_checked_by_name_and_by_type_instead_of_wrapping():
    for path in ("evaluator.loop.seed", "draw"):
        assert cfglib.apply_overrides(_table(), [f"{path}={cfglib.MAX_SEED}"]) != _table()
        for bad in (cfglib.MAX_SEED + 1, -1):
            with pytest.raises(cfglib.ConfigError, match=rf"{path}: expected a seed .* got {bad}$"):
                cfglib.apply_overrides(_table(), [f"{path}={bad}"])
    with pytest.raises(cfglib.ConfigError, match=r"evaluator.loop.seed: expected a seed"):
        cfglib.to_dict(dataclasses.replace(_table(), evaluator=Evaluator("x", Loop(seed=2**32))))


    @dataclasses.dataclass(frozen=True)
    class Seeds:
        data_seed: int | None = None  # a seed by its name, optional
        seeds: int = -1  # not a seed: the rule is the name `seed` or `*_seed`

    assert cfglib.apply_overrides(Seeds(), ["data_seed=5", "seeds=-2"]) == Seeds(5, -2)
    with pytest.raises(cfglib.ConfigError, match=r"^data_seed: expected a seed from 0 to 4294967295 \(2\*\*32 - 1\), "
                                                 r"got 4294967296$"):
        cfglib.apply_overrides(Seeds(), ["data_seed=4294967296"])


@given(st.recursive(st.none() | st.booleans() | st.integers() | st.floats(allow_nan=False) | st.text(max_size=5),
                    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=3), inner, max_size=3),
                    max_leaves=8))
def test_any_json_value_at_any_path_is_applied_or_refused_with_a_config_error(value):
    cfg = _table()
    for path in cfglib.field_paths(cfg) + ["rows", "rows.ntu13", "evaluator", "part", "weights"]:
        try:
            cfglib.apply_overrides(cfg, [f"{path}={json.dumps(value)}"])
        except cfglib.ConfigError as err:
            assert path in str(err)
