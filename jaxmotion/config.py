"""Frozen dataclass configs: JSON round trips and type-checked ``a.b=value`` overrides.

Every experiment declares one frozen dataclass (fields may themselves be frozen dataclasses) with the
named constructors ``smoke()``, ``cpu()`` and ``paper()``. This module is the only place that knows how
to turn such a config into JSON, back, and how to edit it from the command line:

    cfg = apply_overrides(Config.cpu(), ["train.steps=500", "model.layers=4"])

Supported field types: ``bool``, ``int``, ``float``, ``str``, ``Literal[...]``, ``X | None``,
``tuple[X, ...]`` / ``tuple[X, Y]``, nested dataclasses, and unions of dataclasses (``A | B``: a generator
that is one architecture or another), written as the chosen member's fields and read back as the one member
whose fields the mapping fits. Anything else is rejected when the config is first converted, so a config that
cannot be written to ``config.json`` never trains.
"""

from __future__ import annotations

import dataclasses
import functools
import json
import math
import types
import typing
from collections.abc import Mapping
from typing import Any, Literal, Union

PROFILES = ("smoke", "cpu", "paper")


class ConfigError(ValueError):
    """A config value or override that does not fit the config's declared fields."""


@functools.lru_cache(maxsize=None)
def _field_types(cls: type) -> dict[str, Any]:
    if not (isinstance(cls, type) and dataclasses.is_dataclass(cls)):
        raise ConfigError(f"{cls!r} is not a dataclass type")
    hints = typing.get_type_hints(cls)
    return {f.name: hints[f.name] for f in dataclasses.fields(cls)}


def field_paths(cls: type, prefix: str = "") -> list[str]:
    """Every overridable leaf field of a config class, as dotted paths (``train.steps``)."""
    paths = []
    for name, tp in _field_types(cls).items():
        members = (tp,) if _is_dataclass_type(tp) else _dataclass_union(tp)
        if members:
            paths.extend(dict.fromkeys(p for m in members for p in field_paths(m, f"{prefix}{name}.")))
        else:
            paths.append(f"{prefix}{name}")
    return paths


def to_dict(config: Any) -> dict[str, Any]:
    """A config as plain JSON-compatible data (tuples become lists); inverse of ``from_dict``."""
    if not dataclasses.is_dataclass(config) or isinstance(config, type):
        raise ConfigError(f"to_dict expects a dataclass instance, got {type(config).__name__}")
    types_ = _field_types(type(config))
    return {name: _encode(getattr(config, name), tp, name) for name, tp in types_.items()}


def from_dict(cls: type, data: dict[str, Any]) -> Any:
    """Rebuild a config of class ``cls`` from ``to_dict`` output, checking every value's type."""
    return _decode(data, cls, cls.__name__)


def to_json(config: Any) -> str:
    return json.dumps(to_dict(config), indent=2, sort_keys=True)


def apply_overrides(config: Any, overrides: list[str] | tuple[str, ...]) -> Any:
    """Return a copy of ``config`` with each ``dotted.path=value`` applied, values parsed by field type.

    Values are read as JSON where the field type needs it (numbers, booleans, lists), so
    ``model.dims=[64,64]`` and ``train.lr=1e-4`` both work; bare words are strings for ``str`` fields.
    An unknown path is an error that lists the valid ones.
    """
    for item in overrides:
        path, sep, raw = item.partition("=")
        if not sep or not path:
            raise ConfigError(f"override {item!r} must look like field.path=value")
        path = path.strip()
        valid = field_paths(type(config))
        groups = {p.rsplit(".", k)[0] for p in valid for k in range(1, p.count(".") + 1)}
        if path not in valid and path not in groups:
            raise ConfigError(f"unknown config field {path!r}; valid fields: {', '.join(valid)}")
        config = _replace_path(config, path.split("."), raw.strip(), path)
    return config


def replace_paths(config: Any, changes: Mapping[str, Any]) -> Any:
    """``dataclasses.replace`` through dotted field paths, with Python values (no parsing):
    ``replace_paths(training, {"loop.steps": 500, "losses.kl": 1e-4})``. An unknown path is an error."""
    for path, value in changes.items():
        config = _replace_value(config, path.split("."), value, path)
    return config


def _replace_value(obj: Any, parts: list[str], value: Any, full: str) -> Any:
    if not dataclasses.is_dataclass(obj) or parts[0] not in {f.name for f in dataclasses.fields(obj)}:
        raise ConfigError(f"{full!r}: {type(obj).__name__} has no field {parts[0]!r}")
    inner = _replace_value(getattr(obj, parts[0]), parts[1:], value, full) if len(parts) > 1 else value
    return dataclasses.replace(obj, **{parts[0]: inner})


def diff(a: dict[str, Any], b: dict[str, Any], prefix: str = "") -> list[str]:
    """Dotted paths whose values differ between two ``to_dict`` outputs (for resume checks)."""
    out = []
    for key in sorted(set(a) | set(b)):
        va, vb = a.get(key, "<missing>"), b.get(key, "<missing>")
        if isinstance(va, dict) and isinstance(vb, dict):
            out.extend(diff(va, vb, f"{prefix}{key}."))
        elif va != vb:
            out.append(f"{prefix}{key}: {va!r} -> {vb!r}")
    return out


# --- internals -------------------------------------------------------------------------------------


def _is_dataclass_type(tp: Any) -> bool:
    return isinstance(tp, type) and dataclasses.is_dataclass(tp)


def _dataclass_union(tp: Any) -> tuple[type, ...]:
    """The members of a union of two or more dataclasses (``A | B``), else ``()``."""
    if typing.get_origin(tp) not in (Union, types.UnionType):
        return ()
    args = typing.get_args(tp)
    if len(args) > 1 and type(None) not in args and all(_is_dataclass_type(a) for a in args):
        return args
    return ()


def _optional_inner(tp: Any) -> Any | None:
    """``X`` for ``X | None`` / ``Optional[X]``, else None."""
    if typing.get_origin(tp) in (Union, types.UnionType) and not _dataclass_union(tp):
        args = [a for a in typing.get_args(tp) if a is not type(None)]
        if len(args) == 1 and len(typing.get_args(tp)) == 2:
            return args[0]
        raise ConfigError(f"unsupported union type {tp!r}: only `X | None` and unions of dataclasses are allowed")
    return None


def _union_member(value: Any, members: tuple[type, ...], where: str, *, encode: bool) -> type:
    """The member of a dataclass union that ``value`` is (encode) or whose fields its mapping fits (decode)."""
    names = " | ".join(m.__name__ for m in members)
    if encode:
        member = next((m for m in members if isinstance(value, m)), None)
        if member is None:
            raise ConfigError(f"{where}: expected one of {names}, got {type(value).__name__}")
        return member
    if not isinstance(value, dict):
        raise ConfigError(f"{where}: expected a mapping for {names}, got {value!r}")
    fits = [m for m in members if set(value) <= set(_field_types(m))
            and {f.name for f in dataclasses.fields(m) if f.default is dataclasses.MISSING
                 and f.default_factory is dataclasses.MISSING} <= set(value)]
    if len(fits) != 1:
        raise ConfigError(f"{where}: the fields {sorted(value)} fit {len(fits)} of {names}; name the fields of "
                          f"exactly one")
    return fits[0]


def _replace_path(config: Any, parts: list[str], raw: str, full: str) -> Any:
    name = parts[0]
    fields = _field_types(type(config))
    if name not in fields:  # a path of another member of a dataclass union
        raise ConfigError(f"{full!r}: this config's {type(config).__name__} has no field {name!r}; its fields: "
                          f"{', '.join(fields)}")
    tp = fields[name]
    if len(parts) > 1:
        return dataclasses.replace(config, **{name: _replace_path(getattr(config, name), parts[1:], raw, full)})
    if _is_dataclass_type(tp):
        raise ConfigError(f"{full!r} is a group of fields; set one of: {', '.join(field_paths(tp, full + '.'))}")
    if _dataclass_union(tp):
        tp = type(getattr(config, name))
        raise ConfigError(f"{full!r} is a group of fields; set one of: {', '.join(field_paths(tp, full + '.'))}")
    return dataclasses.replace(config, **{name: _decode(_parse_raw(raw, tp), tp, full)})


def _parse_raw(raw: str, tp: Any) -> Any:
    """Command-line text to a JSON-like value; strings may be written bare."""
    if raw in ("None", "null"):
        return None
    inner = _optional_inner(tp)
    target = inner if inner is not None else tp
    if target is str or typing.get_origin(target) is Literal and all(isinstance(a, str) for a in typing.get_args(target)):
        return raw
    try:
        return json.loads({"True": "true", "False": "false"}.get(raw, raw))
    except json.JSONDecodeError:
        return raw


def _encode(value: Any, tp: Any, where: str) -> Any:
    return _check(value, tp, where, encode=True)


def _decode(value: Any, tp: Any, where: str) -> Any:
    return _check(value, tp, where, encode=False)


def _check(value: Any, tp: Any, where: str, *, encode: bool) -> Any:
    """Validate ``value`` against ``tp``; return its JSON form (encode) or its Python form (decode)."""
    members = _dataclass_union(tp)
    if members:
        return _check(value, _union_member(value, members, where, encode=encode), where, encode=encode)
    inner = _optional_inner(tp)
    if inner is not None:
        return None if value is None else _check(value, inner, where, encode=encode)
    if _is_dataclass_type(tp):
        if encode:
            if not isinstance(value, tp):
                raise ConfigError(f"{where}: expected {tp.__name__}, got {type(value).__name__}")
            return to_dict(value)
        if not isinstance(value, dict):
            raise ConfigError(f"{where}: expected a mapping for {tp.__name__}, got {value!r}")
        fields = _field_types(tp)
        unknown = set(value) - set(fields)
        if unknown:
            raise ConfigError(f"{where}: unknown fields {sorted(unknown)}; valid: {sorted(fields)}")
        return tp(**{k: _check(v, fields[k], f"{where}.{k}", encode=False) for k, v in value.items()})
    origin = typing.get_origin(tp)
    if origin is Literal:
        if value not in typing.get_args(tp):
            raise ConfigError(f"{where}: expected one of {list(typing.get_args(tp))}, got {value!r}")
        return value
    if origin is tuple:
        args = typing.get_args(tp)
        if not isinstance(value, (list, tuple)):
            raise ConfigError(f"{where}: expected a list for {tp!r}, got {value!r}")
        if len(args) == 2 and args[1] is Ellipsis:
            item_types = [args[0]] * len(value)
        elif len(args) != len(value):
            raise ConfigError(f"{where}: expected {len(args)} items for {tp!r}, got {len(value)}")
        else:
            item_types = list(args)
        items = [_check(v, t, f"{where}[{i}]", encode=encode) for i, (v, t) in enumerate(zip(value, item_types))]
        return items if encode else tuple(items)
    if tp is bool:
        if not isinstance(value, bool):
            raise ConfigError(f"{where}: expected true or false, got {value!r}")
        return value
    if tp is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise ConfigError(f"{where}: expected an integer, got {value!r}")
        return value
    if tp is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ConfigError(f"{where}: expected a number, got {value!r}")
        if not math.isfinite(value):  # JSON has no NaN or infinity; a config holding one would not resume
            raise ConfigError(f"{where}: expected a finite number, got {value!r}")
        return float(value)
    if tp is str:
        if not isinstance(value, str):
            raise ConfigError(f"{where}: expected a string, got {value!r}")
        return value
    raise ConfigError(f"{where}: unsupported config field type {tp!r}")
