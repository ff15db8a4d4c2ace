"""Parameter schemas of the figure kinds: what a lesson step may set, checked field by field.

A figure kind's parameters are a frozen dataclass whose fields carry their documentation
and allowed values in ``metadata`` (:func:`param`). :func:`parse_params` turns a plain table
(a lesson's ``[[steps.figures]]`` entry, command-line options) into that dataclass, and
every rejection is a :class:`FigureParamError` naming the field, the value and what is
allowed, so a lesson author reads e.g.
``figures[0].normal_deg: must be a number in [-180, 180], got 400``.
"""

from __future__ import annotations

import dataclasses
import math
import typing
from dataclasses import dataclass
from typing import Any, Mapping


class FigureParamError(ValueError):
    """A figure parameter was missing, unknown or out of range; ``field`` names it."""

    def __init__(self, field: str, message: str) -> None:
        super().__init__(f"{field}: {message}")
        self.field = field
        self.message = message


@dataclass(frozen=True)
class ParamInfo:
    """One parameter of a figure kind, as a lesson author sees it."""

    name: str
    type: type                      # bool, int, float or str
    default: Any
    doc: str
    low: float | None = None        # inclusive range for int and float
    high: float | None = None
    choices: tuple[str, ...] = ()   # allowed strings for str

    def allowed(self) -> str:
        """The allowed values in words (used in errors and in ``--help``)."""
        if self.type is bool:
            return "true or false"
        if self.type is str:
            return "one of " + ", ".join(repr(c) for c in self.choices)
        kind = "a whole number" if self.type is int else "a number"
        return f"{kind} in [{_number(self.low)}, {_number(self.high)}]"


def param(doc: str, low: float | None = None, high: float | None = None,
          choices: tuple[str, ...] = ()) -> dict[str, Any]:
    """``metadata`` of a parameter field: its documentation and allowed values."""
    return {"doc": doc, "low": low, "high": high, "choices": tuple(choices)}


def schema(params_class: type) -> tuple[ParamInfo, ...]:
    """The parameters of a params dataclass, in declaration order."""
    hints = typing.get_type_hints(params_class)
    infos = []
    for f in dataclasses.fields(params_class):
        meta = f.metadata
        kind = hints[f.name]
        if kind not in (bool, int, float, str):
            raise TypeError(f"{params_class.__name__}.{f.name}: figure parameters are bool, "
                            f"int, float or str, not {kind}")
        if "doc" not in meta:
            raise TypeError(f"{params_class.__name__}.{f.name} lacks param(...) metadata")
        if kind in (int, float) and (meta["low"] is None or meta["high"] is None):
            raise TypeError(f"{params_class.__name__}.{f.name}: a number needs a range")
        if kind is str and not meta["choices"]:
            raise TypeError(f"{params_class.__name__}.{f.name}: a string needs choices")
        infos.append(ParamInfo(f.name, kind, f.default, meta["doc"], meta["low"],
                               meta["high"], meta["choices"]))
    return tuple(infos)


def check_value(info: ParamInfo, value: Any, where: str = "") -> Any:
    """``value`` converted to the parameter's type, or FigureParamError naming the field."""
    name = where + info.name
    if info.type is bool:
        if not isinstance(value, bool):
            raise FigureParamError(name, f"must be true or false, got {value!r}")
        return value
    if info.type is str:
        if not isinstance(value, str) or value not in info.choices:
            raise FigureParamError(name, f"must be {info.allowed()}, got {value!r}")
        return value
    is_number = isinstance(value, (int, float)) and not isinstance(value, bool)
    if info.type is int and not (is_number and float(value).is_integer()):
        raise FigureParamError(name, f"must be {info.allowed()}, got {value!r}")
    if not is_number or not math.isfinite(value) or not info.low <= value <= info.high:
        raise FigureParamError(name, f"must be {info.allowed()}, got {value!r}")
    return int(value) if info.type is int else float(value)


def parse_params(params_class: type, table: Mapping[str, Any], where: str = "") -> Any:
    """A ``params_class`` instance from ``table`` (missing fields keep their defaults).

    ``where`` prefixes field names in errors (e.g. ``"figures[0]."``)."""
    if not isinstance(table, Mapping):
        raise FigureParamError(where.rstrip(".") or "figure",
                               f"must be a table of parameters, got {type(table).__name__}")
    infos = {info.name: info for info in schema(params_class)}
    unknown = [key for key in table if key not in infos]
    if unknown:
        raise FigureParamError(where + str(unknown[0]),
                               f"unknown parameter; expected one of {sorted(infos)}")
    values = {key: check_value(infos[key], value, where) for key, value in table.items()}
    try:
        return params_class(**values)     # __post_init__ checks fields against each other
    except FigureParamError as exc:
        raise FigureParamError(where + exc.field, exc.message) from None


def _number(value: float | None) -> str:
    return f"{value:g}" if value is not None else "?"
