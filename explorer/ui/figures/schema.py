"""Parameters of the figure kinds: what a lesson step may set, checked field by field.

A figure kind's parameters are a frozen dataclass declared with
:func:`explorer.lpv.schema.setting`, the same declarations the Settings use: each field
states its kind, range or choices and documentation, and the dataclass validates itself
when made. :func:`parse_params` reads a plain table (a lesson's ``[[steps.figures]]``
entry, command-line options) through :func:`explorer.lpv.schema.from_dict`, so a lesson
author reads e.g. ``figures[0].normal_deg must be a finite number in [-180, 180], got 400``.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any, Mapping

from explorer.lpv.schema import SettingError, Spec, from_dict, specs

FigureParamError = SettingError
"""A figure parameter that is missing, unknown or out of range; ``.field`` names it."""


@dataclass(frozen=True)
class ParamInfo:
    """One parameter of a figure kind, as a lesson author (or ``--help``) sees it."""

    name: str
    spec: Spec
    default: Any

    @property
    def doc(self) -> str:
        return self.spec.doc

    def allowed(self) -> str:
        return self.spec.allowed()


def schema(params_class: type) -> tuple[ParamInfo, ...]:
    """The parameters of a params dataclass, in declaration order."""
    field_specs = specs(params_class)
    return tuple(ParamInfo(f.name, field_specs[f.name], f.default)
                 for f in dataclasses.fields(params_class))


def parse_params(params_class: type, table: Mapping[str, Any], where: str = "") -> Any:
    """A ``params_class`` instance from ``table`` (missing fields keep their defaults);
    ``where`` prefixes field names in errors (e.g. ``"figures[0]."``)."""
    return from_dict(params_class, table, params_class(), where)
