"""Frozen dataclass configs: JSON round trips and type-checked ``a.b=value`` overrides.

Every experiment declares one frozen dataclass (fields may themselves be frozen dataclasses) with the
named constructors ``smoke()``, ``cpu()`` and ``paper()``. This module is the only place that knows how
to turn such a config into JSON, back, and how to edit it from the command line:

    cfg = apply_overrides(Config.cpu(), ["train.steps=500", "model.layers=4", "rows.ntu13.loop.steps=100"])

Supported field types: ``bool``, ``int``, ``float``, ``str``, ``Literal[...]``, :data:`Seed`,
``tuple[X, ...]`` / ``tuple[X, Y]``, nested dataclasses, unions of dataclasses (``A | B``: a generator that
is one architecture or another, written as the chosen member's fields and read back as the one member whose
fields the mapping fits), ``X | None`` of any of these, and mappings ``Mapping[str, X]`` / ``dict[str, X]``.
Anything else is rejected when the config is first converted, so a config that cannot be written to
``config.json`` never trains.

* **Paths.** A field path names fields and mapping keys joined by dots: ``rows.ntu13.actformer.loop.steps``.
  An override descends into the value the config holds: the member of a union it is, the entries of a
  mapping it has (a key it lacks is an error, not a new entry: a typo never adds a row). A group (a
  dataclass, a mapping, an optional group) can also be set whole from JSON, which replaces it:
  ``--set 'table.evaluator={"dataset": "uestc", ...}'`` (fields left out take their defaults) or
  ``--set table.evaluator=null`` where the group is optional. :func:`field_paths` of a class lists every
  declared leaf (a mapping's keys as ``<key>``), of an instance the leaves it holds.
* **Mappings** are held as :class:`FrozenMap`: immutable, in insertion order, equal to any mapping with the
  same items (as ``dict`` is) and hashable, so configs holding them stay hashable and comparable
  (``types.MappingProxyType`` is not hashable; a ``dict`` is not immutable). Their JSON form is a plain
  object in the same order. Keys are strings usable in a path: not empty, without ``.`` or ``=`` and
  without surrounding spaces.
* **Seeds.** An ``int`` field named ``seed`` or ending in ``_seed``, or declared as :data:`Seed`, takes 0 to
  :data:`MAX_SEED` only: ``jax.random.key`` would wrap a larger one modulo 2**32 and two seeds would make one
  run.
* **Integers.** Any other ``int`` field takes -2**31 to 2**31 - 1 (:data:`MAX_INT`): jax computes in 32 bits
  on a default install, so a larger step count, size or index would overflow where it is used.
* **Errors.** Every bad value raises :class:`ConfigError` naming the dotted path, the expected type and the
  value given.
"""

from __future__ import annotations

import dataclasses
import functools
import json
import math
import types
import typing
from collections.abc import Callable, Iterable, Iterator, Mapping
from typing import Annotated, Any, Literal, Union

PROFILES = ("smoke", "cpu", "paper")
MAX_SEED = 2**32 - 1  # jax.random.key takes a 32-bit seed on a default (x32) install
MAX_INT = 2**31 - 1  # jax's int32 on a default (x32) install: steps, sizes and indices are computed in it
#: A PRNG seed: an integer from 0 to :data:`MAX_SEED`. Int fields named ``seed`` or ``*_seed`` are seeds too.
Seed = Annotated[int, "seed"]


class ConfigError(ValueError):
    """A config value or override that does not fit the config's declared fields."""


class FrozenMap(Mapping):
    """An immutable mapping in insertion order: what a config's ``Mapping[str, X]`` field holds.

    Equal to any mapping with the same items, whatever their order (as ``dict`` is); hashable when its values
    are, so a frozen config holding one stays hashable. ``FrozenMap({"a": 1, "b": 2})``."""

    __slots__ = ("_items",)

    def __init__(self, items: Mapping[str, Any] | Iterable[tuple[str, Any]] = ()):
        self._items = dict(items)

    def __getitem__(self, key: str) -> Any:
        return self._items[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self._items)

    def __len__(self) -> int:
        return len(self._items)

    def __hash__(self) -> int:
        return hash(frozenset(self._items.items()))  # order-free, as equality is

    def __repr__(self) -> str:
        return f"FrozenMap({self._items!r})"


def check_seed(value: Any, where: str) -> int:
    """``value`` if it is a seed (an integer from 0 to :data:`MAX_SEED`), else a :class:`ConfigError`."""
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= MAX_SEED:
        raise _mismatch(where, f"a seed from 0 to {MAX_SEED} (2**32 - 1)", value)
    return value


def check_at_least(config: Any, minimum: int, *names: str) -> None:
    """For a config's ``__post_init__``: a ``ValueError`` naming the first of the fields ``names`` whose value is
    below ``minimum`` (counts and sizes 1, indices 0); ``None``, an unset optional field, passes."""
    for name in names:
        value = getattr(config, name)
        if value is not None and value < minimum:
            raise ValueError(f"{type(config).__name__}.{name}: expected >= {minimum}, got {value}")


def field_paths(config: Any, prefix: str = "") -> list[str]:
    """Every overridable leaf of a config, as dotted paths (``train.steps``), under ``prefix`` if given.

    Of a config *class*: every declared leaf, the fields of optional groups and of every union member
    included, a mapping's entries as ``<key>``. Of a config *instance*: the leaves it holds (the fields of the
    union member it holds, its mappings' keys; an unset optional group or an empty mapping as one path, set
    whole)."""
    if _is_dataclass_type(config):
        return _declared_paths(config, prefix)
    return list(flatten(to_dict(config), prefix))


def flatten(data: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
    """The leaves of ``to_dict`` output by dotted path: ``{"a": {"b": 1}}`` -> ``{"a.b": 1}`` (an empty
    mapping is a leaf)."""
    out: dict[str, Any] = {}
    for key, value in data.items():
        path = _join(prefix, key)
        if isinstance(value, Mapping) and value:
            out.update(flatten(value, path))
        else:
            out[path] = value
    return out


def to_dict(config: Any) -> dict[str, Any]:
    """A config as plain JSON-compatible data (tuples become lists, mappings plain dicts in their order);
    inverse of ``from_dict``."""
    if not dataclasses.is_dataclass(config) or isinstance(config, type):
        raise ConfigError(f"to_dict expects a dataclass instance, got {type(config).__name__}")
    return _encode(config, type(config), "")


def from_dict(cls: type, data: Mapping[str, Any]) -> Any:
    """Rebuild a config of class ``cls`` from ``to_dict`` output, checking every value's type."""
    return _decode(data, cls, "")


def to_json(config: Any) -> str:
    """A config as indented JSON, fields in declaration order and mappings in theirs."""
    return json.dumps(to_dict(config), indent=2)


def apply_overrides(config: Any, overrides: Iterable[str]) -> Any:
    """Return a copy of ``config`` with each ``dotted.path=value`` applied, values parsed by field type.

    Values are read as JSON where the field type needs it (numbers, booleans, lists, groups set whole), so
    ``model.dims=[64,64]`` and ``train.lr=1e-4`` both work; bare words are strings for ``str`` fields.
    An unknown path is an error that lists the valid ones.
    """
    for item in overrides:
        path, sep, raw = item.partition("=")
        path = path.strip()
        if not sep or not path:
            raise ConfigError(f"override {item!r} must look like field.path=value")
        raw = raw.strip()
        config = _edit(config, type(config), path.split("."), "",
                       lambda held, tp, where, raw=raw: _decode_text(raw, held, tp, where))
    return config


def replace_paths(config: Any, changes: Mapping[str, Any]) -> Any:
    """``dataclasses.replace`` through dotted field paths, with Python values (no parsing), each checked
    against its field's type: ``replace_paths(training, {"loop.steps": 500, "losses.kl": 1e-4})``. An unknown
    path is an error."""
    for path, value in changes.items():
        config = _edit(config, type(config), path.split("."), "",
                       lambda held, tp, where, value=value: _decode(_encode(value, tp, where), tp, where))
    return config


def diff(a: Mapping[str, Any], b: Mapping[str, Any]) -> list[str]:
    """Dotted paths whose values differ between two ``to_dict`` outputs (for resume checks), sorted."""
    fa, fb = flatten(a), flatten(b)
    return [f"{path}: {fa.get(path, '<missing>')!r} -> {fb.get(path, '<missing>')!r}"
            for path in sorted(fa.keys() | fb.keys()) if fa.get(path, "<missing>") != fb.get(path, "<missing>")]


# --- internals -------------------------------------------------------------------------------------


@functools.lru_cache(maxsize=None)
def _field_types(cls: type) -> dict[str, Any]:
    if not _is_dataclass_type(cls):
        raise ConfigError(f"{cls!r} is not a dataclass type")
    hints = typing.get_type_hints(cls, include_extras=True)
    return {f.name: _seed_by_name(f.name, hints[f.name]) for f in dataclasses.fields(cls)}


def _seed_by_name(name: str, tp: Any) -> Any:
    """:data:`Seed` for an ``int`` (or ``int | None``) field named ``seed`` or ``*_seed``; else ``tp``."""
    if name != "seed" and not name.endswith("_seed"):
        return tp
    if tp is int:
        return Seed
    return Seed | None if _optional(tp) is int else tp


def _is_dataclass_type(tp: Any) -> bool:
    return isinstance(tp, type) and dataclasses.is_dataclass(tp)


def _union_args(tp: Any) -> tuple[Any, ...]:
    return typing.get_args(tp) if typing.get_origin(tp) in (Union, types.UnionType) else ()


def _dataclass_union(tp: Any) -> tuple[type, ...]:
    """The members of a union of two or more dataclasses (``A | B``), else ``()``."""
    args = _union_args(tp)
    if len(args) > 1 and all(_is_dataclass_type(a) for a in args):
        return args
    return ()


def _optional(tp: Any) -> Any | None:
    """``X`` for ``X | None`` (``X`` may itself be a union of dataclasses), else None."""
    args = _union_args(tp)
    if not args or _dataclass_union(tp):
        return None
    rest = tuple(a for a in args if a is not type(None))
    if len(rest) == len(args) - 1 and (len(rest) == 1 or all(_is_dataclass_type(a) for a in rest)):
        return rest[0] if len(rest) == 1 else Union[rest]
    raise ConfigError(f"unsupported union type {_type_name(tp)}: only `X | None` and unions of dataclasses "
                      f"(optionally `| None`) are allowed")


def _mapping_values(tp: Any) -> Any | None:
    """``X`` for ``Mapping[str, X]`` / ``dict[str, X]``, else None."""
    if typing.get_origin(tp) not in (Mapping, dict):
        return None
    args = typing.get_args(tp)
    if len(args) != 2 or args[0] is not str:
        raise ConfigError(f"unsupported mapping type {_type_name(tp)}: keys must be str (Mapping[str, X])")
    return args[1]


def _members(tp: Any) -> tuple[type, ...]:
    """The dataclasses a field of type ``tp`` may hold: the members of a union, ``(tp,)`` for a dataclass."""
    return _dataclass_union(tp) or ((tp,) if _is_dataclass_type(tp) else ())


def _is_group(tp: Any) -> bool:
    """Whether a field of type ``tp`` holds named sub-fields (a dataclass, a union of them, a mapping)."""
    inner = _optional(tp)
    if inner is not None:
        return _is_group(inner)
    return bool(_members(tp)) or _mapping_values(tp) is not None


def _join(prefix: str, name: str) -> str:
    return f"{prefix}.{name}" if prefix else name


def _type_name(tp: Any) -> str:
    """``tp`` as written in a config class: ``tuple[int, ...]``, ``Mapping[str, Inner] | None``."""
    if tp == Seed:
        return "Seed"
    if tp is type(None):
        return "None"
    if isinstance(tp, type):
        return tp.__name__
    args = typing.get_args(tp)
    if _union_args(tp):
        return " | ".join(_type_name(a) for a in args)
    origin = typing.get_origin(tp)
    if origin is Literal:
        return f"Literal[{', '.join(map(repr, args))}]"
    if origin is Annotated:
        return _type_name(args[0])
    name = getattr(origin, "__name__", repr(origin))
    return f"{name}[{', '.join('...' if a is Ellipsis else _type_name(a) for a in args)}]"


def _show(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 200 else text[:197] + "..."


def _mismatch(where: str, expected: str, value: Any) -> ConfigError:
    """The one error of a bad value: its path, what its field takes, what it got."""
    return ConfigError(f"{where or 'config'}: expected {expected}, got {_show(value)}")


def _declared_paths(tp: Any, where: str) -> list[str]:
    """The leaf paths a field of type ``tp`` at ``where`` may have, whatever value it holds."""
    inner = _optional(tp)
    if inner is not None:
        return _declared_paths(inner, where)
    members = _members(tp)
    if members:
        return list(dict.fromkeys(p for m in members for name, ftp in _field_types(m).items()
                                  for p in _declared_paths(ftp, _join(where, name))))
    values = _mapping_values(tp)
    if values is not None:
        return _declared_paths(values, _join(where, "<key>"))
    return [where]


Leaf = Callable[[Any, Any, str], Any]  # (held value, declared type, path) -> new value


def _edit(held: Any, tp: Any, parts: list[str], where: str, leaf: Leaf) -> Any:
    """``held`` (a field of type ``tp`` at path ``where``) with the value at the rest of the path, ``parts``,
    replaced by ``leaf(held there, its type, its path)``."""
    if not parts:
        return leaf(held, tp, where)
    full = _join(where, ".".join(parts))
    inner = _optional(tp)
    if inner is not None:
        if held is None:
            raise ConfigError(
                f"{full!r}: the group {where!r} is None (no {_type_name(inner)} set), so it has no {parts[0]!r}; "
                f"set the whole group as JSON, e.g. --set '{where}={{\"{parts[0]}\": ...}}' (fields left out take "
                f"their defaults; required: {', '.join(_required_of(inner)) or 'none'}), or --help for its fields")
        return _edit(held, inner, parts, where, leaf)
    if _members(tp):
        fields = _field_types(type(held))
        name = parts[0]
        if name not in fields:
            raise _unknown(full, name, held, tp, where)
        new = _edit(getattr(held, name), fields[name], parts[1:], _join(where, name), leaf)
        return _build(where, lambda: dataclasses.replace(held, **{name: new}), setting=full)
    values = _mapping_values(tp)
    if values is not None:
        key = parts[0]
        if key not in held:
            raise ConfigError(f"unknown config field {full!r}: {where!r} has the keys {list(held)}; to add or "
                              f"remove one, give the whole mapping as JSON: --set '{where}={{...}}'")
        new = _edit(held[key], values, parts[1:], _join(where, key), leaf)
        return FrozenMap({**held, key: new})
    raise ConfigError(f"unknown config field {full!r}: {where!r} is a single value ({_type_name(tp)}), "
                      f"not a group of fields")


def _unknown(full: str, name: str, held: Any, tp: Any, where: str) -> ConfigError:
    """An unknown field ``name`` under the dataclass ``held`` (of type ``tp``): name the fields there are, and
    the union members that have it."""
    others = [m.__name__ for m in _dataclass_union(tp) if name in _field_types(m)]
    switch = (f"; {' and '.join(others)} {'has' if len(others) == 1 else 'have'} it, this config holds "
              f"{type(held).__name__} (switch by setting the whole group as JSON: --set '{where}={{...}}')"
              if others else "")
    return ConfigError(f"unknown config field {full!r}; valid fields: {', '.join(field_paths(held, where))}{switch}")


def _build(where: str, make: Callable[[], Any], setting: str = "") -> Any:
    """``make()``, a dataclass constructor whose own checks (``__post_init__``) fail as a ConfigError here
    (naming the path being ``setting``, for an edit)."""
    try:
        return make()
    except (TypeError, ValueError) as err:
        if isinstance(err, ConfigError):
            raise
        raise ConfigError(f"{where or 'config'}: {err}" + (f" (setting {setting!r})" if setting else "")) from None


def _decode_text(raw: str, held: Any, tp: Any, where: str) -> Any:
    """Command-line text for the field ``where`` of type ``tp`` (holding ``held``), as its Python value."""
    value, json_error = _parse_raw(raw, tp)
    if _is_group(tp) and not (isinstance(value, Mapping) or value is None and _optional(tp) is not None):
        paths = _declared_paths(tp, where) if held is None else list(flatten({where: _encode(held, tp, where)}))
        one_of = [p for p in paths if p != where]  # an empty mapping has no fields to name
        raise ConfigError(f"{where!r} is a group of fields; "
                          + (f"set one of: {', '.join(one_of)}; or " if one_of else "")
                          + f"give the whole group as a JSON mapping ({_type_name(tp)}), got {raw!r}"
                          + (f" (not JSON: {json_error})" if json_error else ""))
    try:
        return _decode(value, tp, where)
    except ConfigError as err:
        if json_error:
            raise ConfigError(f"{err} ({raw!r} is not valid JSON: {json_error})") from None
        raise


def _parse_raw(raw: str, tp: Any) -> tuple[Any, str | None]:
    """Command-line text to a JSON-like value (strings may be written bare), and the JSON error of text that
    looked like JSON but did not parse."""
    if raw in ("None", "null"):
        return None, None
    target = _optional(tp) or tp
    if target is str or typing.get_origin(target) is Literal and all(isinstance(a, str) for a in typing.get_args(target)):
        return raw, None
    try:
        return json.loads({"True": "true", "False": "false"}.get(raw, raw)), None
    except json.JSONDecodeError as err:
        return raw, (str(err) if raw[:1] in "[{\"" else None)


def _encode(value: Any, tp: Any, where: str) -> Any:
    return _check(value, tp, where, encode=True)


def _decode(value: Any, tp: Any, where: str) -> Any:
    return _check(value, tp, where, encode=False)


def _check(value: Any, tp: Any, where: str, *, encode: bool) -> Any:
    """Validate ``value`` against ``tp``; return its JSON form (encode) or its Python form (decode)."""
    members = _dataclass_union(tp)
    if members:
        return _check(value, _union_member(value, members, where, encode=encode), where, encode=encode)
    inner = _optional(tp)
    if inner is not None:
        return None if value is None else _check(value, inner, where, encode=encode)
    if _is_dataclass_type(tp):
        return _check_dataclass(value, tp, where, encode=encode)
    values = _mapping_values(tp)
    if values is not None:
        return _check_mapping(value, tp, values, where, encode=encode)
    origin = typing.get_origin(tp)
    if tp == Seed:
        return check_seed(value, where)
    if origin is Annotated:  # metadata other than Seed's changes nothing
        return _check(value, typing.get_args(tp)[0], where, encode=encode)
    if origin is Literal:
        options = typing.get_args(tp)
        if not any(value == o and type(value) is type(o) for o in options):
            raise _mismatch(where, f"one of {list(options)}", value)
        return value
    if origin is tuple:
        return _check_tuple(value, tp, where, encode=encode)
    if tp is bool:
        if not isinstance(value, bool):
            raise _mismatch(where, "true or false", value)
        return value
    if tp is int:
        if isinstance(value, bool) or not isinstance(value, int) or not -MAX_INT - 1 <= value <= MAX_INT:
            raise _mismatch(where, f"an integer from -2**31 to 2**31 - 1 ({MAX_INT})", value)
        return value
    if tp is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise _mismatch(where, "a number", value)
        if not math.isfinite(value):  # JSON has no NaN or infinity; a config holding one would not resume
            raise _mismatch(where, "a finite number", value)
        return float(value)
    if tp is str:
        if not isinstance(value, str):
            raise _mismatch(where, "a string", value)
        return value
    raise ConfigError(f"{where or 'config'}: unsupported config field type {_type_name(tp)}")


def _check_dataclass(value: Any, cls: type, where: str, *, encode: bool) -> Any:
    fields = _field_types(cls)
    if encode:
        if not isinstance(value, cls):
            raise _mismatch(where, cls.__name__, value)
        return {name: _encode(getattr(value, name), tp, _join(where, name)) for name, tp in fields.items()}
    if not isinstance(value, Mapping):
        raise _mismatch(where, f"a mapping of {cls.__name__}'s fields", value)
    unknown = [k for k in value if k not in fields]
    if unknown:
        raise ConfigError(f"{where or 'config'}: unknown fields {unknown} of {cls.__name__}; valid: {list(fields)}")
    missing = [name for name in _required(cls) if name not in value]
    if missing:
        raise ConfigError(f"{where or 'config'}: missing fields {missing} of {cls.__name__} (they have no "
                          f"default), got {_show(dict(value))}")
    kwargs = {k: _decode(v, fields[k], _join(where, k)) for k, v in value.items()}
    return _build(where, lambda: cls(**kwargs))


def _required(cls: type) -> list[str]:
    return [f.name for f in dataclasses.fields(cls)
            if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING]


def _required_of(tp: Any) -> list[str]:
    """The fields a group of type ``tp`` must be given (those of every member of a union)."""
    return list(dict.fromkeys(name for m in _members(tp) for name in _required(m)))


def _union_member(value: Any, members: tuple[type, ...], where: str, *, encode: bool) -> type:
    """The member of a dataclass union that ``value`` is (encode) or whose fields its mapping fits (decode)."""
    names = " | ".join(m.__name__ for m in members)
    if encode:
        member = next((m for m in members if isinstance(value, m)), None)
        if member is None:
            raise _mismatch(where, f"one of {names}", value)
        return member
    if not isinstance(value, Mapping):
        raise _mismatch(where, f"a mapping of the fields of one of {names}", value)
    fits = [m for m in members if set(value) <= set(_field_types(m)) and set(_required(m)) <= set(value)]
    if len(fits) != 1:
        raise ConfigError(f"{where or 'config'}: the fields {sorted(value)} fit {len(fits)} of {names}; name the "
                          f"fields of exactly one, got {_show(dict(value))}")
    return fits[0]


def _check_mapping(value: Any, tp: Any, values: Any, where: str, *, encode: bool) -> Any:
    # A config holds an immutable FrozenMap (hashable, like the rest of a frozen config); JSON gives any mapping.
    if not isinstance(value, FrozenMap if encode else Mapping):
        raise _mismatch(where, f"a {'FrozenMap' if encode else 'mapping'} ({_type_name(tp)})", value)
    for key in value:
        if not isinstance(key, str) or not key or "." in key or "=" in key or key != key.strip():
            raise _mismatch(where, f"keys usable in a dotted path (non-empty strings without '.', '=' or "
                                   f"surrounding spaces) for {_type_name(tp)}", key)
    items = {k: _check(v, values, _join(where, k), encode=encode) for k, v in value.items()}
    return items if encode else FrozenMap(items)


def _check_tuple(value: Any, tp: Any, where: str, *, encode: bool) -> Any:
    args = typing.get_args(tp)
    if not isinstance(value, (list, tuple)):
        raise _mismatch(where, f"a list ({_type_name(tp)})", value)
    if len(args) == 2 and args[1] is Ellipsis:
        item_types = [args[0]] * len(value)
    elif len(args) != len(value):
        raise _mismatch(where, f"a list of {len(args)} items ({_type_name(tp)})", value)
    else:
        item_types = list(args)
    items = [_check(v, t, f"{where}[{i}]", encode=encode) for i, (v, t) in enumerate(zip(value, item_types))]
    return items if encode else tuple(items)
