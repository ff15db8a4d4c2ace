"""Typed, ranged fields: one declaration per setting, read by everything that parses one.

A field of a settings dataclass is declared with :func:`setting`, which stores a
:class:`Spec` in the field's metadata: its kind (int, float, bool, choice, ...), its range
or choices, its documentation, its command-line flag, the widget that edits it and the
pipeline stages that read it. Everything that turns outside data into settings derives
from these specs:

* the dataclass checks and normalises every field when it is constructed
  (:func:`validate`, called from ``__post_init__``), so ``Settings(grid_size="8")`` or
  ``Settings(exposure=float("nan"))`` fail at once with the field, the value and the
  allowed range named;
* persisted JSON and lesson tables go through :func:`from_dict` (lists become tuples, a
  nested table becomes the nested dataclass, unknown keys are refused);
* command lines through :func:`explorer.commands.options` (argparse built from the specs);
* the Scene panel draws the fields that declare a widget;
* the pipeline derives its cache keys from :attr:`Spec.stages` (the stages that read the
  field; a change invalidates those and everything downstream).
"""

from __future__ import annotations

import dataclasses
import math
import numbers
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from functools import cache
from typing import Any

KINDS = ("int", "float", "bool", "str", "text", "choice", "points", "size", "range2",
         "switches", "names", "name_set", "transforms", "nested", "int3", "point")
"""``int3``: three whole numbers [a, b, c] each in [low, high] (e.g. a grid's cells per
axis); ``point``: one point [x, y, z] of finite numbers; ``str``: a non-empty text;
``text``: any text (may be empty); ``size``: [width, height] whole numbers in [low, high];
``range2``: a pair (first, second) of finite numbers with
low <= first <= second <= high (``low_open``: second > low, the pair is not empty at the
low end), e.g. a spot cone's inner and outer angle; ``switches``: a table of names to
true/false; ``names``: a list of texts; ``name_set``: 1 to ``high`` different non-empty
texts in order, held as a tuple (e.g. the lights that shine); ``transforms``: a table of
object names to 3, 6 or 9 numbers (translation, rotation in degrees, scale:
explorer/scene/objects.py), held as sorted ``(name, nine numbers)`` pairs."""
WIDGETS = ("combo", "slider", "checkbox", "input")


class SettingError(ValueError):
    """A value a settings field does not allow; the message names field, value, range."""

    def __init__(self, field: str, message: str) -> None:
        self.field = field
        super().__init__(message)


@dataclass(frozen=True)
class Spec:
    """What one settings field holds and who reads it."""

    doc: str
    kind: str
    choices: tuple = ()
    """For ``choice``: the allowed values (their type is checked too: ``"1"`` is not 1)."""
    low: float | None = None
    high: float | None = None
    low_open: bool = False
    """The lower bound itself is excluded (``(low, high]``): e.g. an exposure of 0."""
    optional: bool = False
    """None is allowed (meaning "the scene's default" or "automatic")."""
    flag: str | None = None
    """Long command-line option, e.g. ``--grid``; None: not a plain option."""
    widget: str | None = None
    """How the Scene panel edits it generically (one of :data:`WIDGETS`); None: a panel
    with its own control, or no control."""
    label: str = ""
    group: str = ""
    """Section of the Scene panel the widget sits in."""
    suggested: tuple = ()
    """Values a combo offers for a numeric field (any allowed value can still be set)."""
    widget_high: float | None = None
    """Upper end of a slider when the allowed range is wider (the slider stays usable;
    typing a value, Ctrl+click, can go up to ``high``)."""
    unit: str = ""
    stages: tuple[str, ...] = ()
    """Pipeline stages that read the field directly (names the settings' owner checks:
    :func:`check_stages`; the LPV's are ``explorer.lpv.stage_list.STAGES``)."""
    nested: type | None = None
    """For ``nested``: the dataclass type held."""
    parse: Callable[[Any], Any] | None = None
    """For ``transforms``: the function that checks and normalises the value, returning
    None when it is malformed (``explorer.scene.objects.check_transforms`` for the LPV's
    settings). The declaring module passes it, so that the schema imports nothing of the
    project and sits below every layer that declares settings."""

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"kind must be one of {KINDS}, got {self.kind!r}")
        if self.widget is not None and self.widget not in WIDGETS:
            raise ValueError(f"widget must be one of {WIDGETS}, got {self.widget!r}")
        if self.kind == "range2" and (self.low is None or self.high is None):
            raise ValueError("a range2 field needs both low and high")
        if self.kind == "transforms" and self.parse is None:
            raise ValueError("a transforms field needs parse (the function that checks it)")
        if self.kind == "nested" and self.nested is None:
            raise ValueError("a nested field needs nested (the dataclass it holds)")

    # -- checking --------------------------------------------------------------------
    def allowed(self) -> str:
        """The allowed values in words, e.g. ``"a whole number in [1, 256]"``."""
        if self.kind == "choice":
            text = "one of " + ", ".join(repr(c) for c in self.choices)
        elif self.kind in ("int", "float"):
            noun = "a whole number" if self.kind == "int" else "a finite number"
            text = noun + _range_text(self.low, self.high, self.low_open)
        elif self.kind == "size":
            text = "[width, height], whole numbers" + _range_text(self.low, self.high, False)
        elif self.kind == "int3":
            text = "three whole numbers" + _range_text(self.low, self.high, False)
        elif self.kind == "range2":
            low, high = _range2_bounds(self)
            text = (f"two numbers [first, second] with {_num(low)} <= first <= second "
                    f"<= {_num(high)}" + (f", second > {_num(low)}" if self.low_open else ""))
        elif self.kind == "nested":
            text = f"a {getattr(self.nested, '__name__', 'table')}"
        elif self.kind == "name_set":
            most = "" if self.high is None else f"1 to {_num(self.high)} "
            text = f"a list of {most}different names"
        else:
            text = _ALLOWED_TEXT[self.kind]
        return text + (" or None" if self.optional else "")

    def check(self, name: str, value: Any) -> Any:
        """``value`` normalised to the field's type; :class:`SettingError` if not allowed."""
        if value is None:
            if self.optional:
                return None
            raise self._error(name, value)
        checker = _CHECKERS[self.kind]
        try:
            normal = checker(self, value)
        except (TypeError, ValueError, OverflowError):
            raise self._error(name, value) from None
        if normal is _REFUSED:
            raise self._error(name, value)
        return normal

    def _error(self, name: str, value: Any) -> SettingError:
        shown = repr(value)
        if len(shown) > 60:
            shown = shown[:57] + "..."
        return SettingError(name, f"{name} must be {self.allowed()}, got {shown}")


_REFUSED = object()
_ALLOWED_TEXT = {
    "bool": "true or false",
    "str": "non-empty text",
    "text": "a text",
    "switches": "a table of names to true/false",
    "names": "a list of texts",
    "transforms": "a table of object names to [tx, ty, tz(, rx, ry, rz(, sx, sy, sz))] "
                  "with finite offsets and each scale in [0.01, 100]",
    "points": "two different points [[x, y, z], [x, y, z]] of finite numbers",
    "point": "a point [x, y, z] of finite numbers",
}
"""What a kind allows when that does not depend on the spec (:meth:`Spec.allowed`)."""


def _range_text(low, high, low_open: bool) -> str:
    if low is None and high is None:
        return ""
    if high is None:
        return f" {'>' if low_open else '>='} {_num(low)}"
    if low is None:
        return f" <= {_num(high)}"
    return f" in {'(' if low_open else '['}{_num(low)}, {_num(high)}]"


def _range2_bounds(spec: Spec) -> tuple[float, float]:
    """A ``range2`` field's (low, high): both are set (``Spec.__post_init__`` refuses one
    without)."""
    if spec.low is None or spec.high is None:
        raise ValueError("a range2 field needs both low and high")
    return spec.low, spec.high


def _num(value: float) -> str:
    return str(int(value)) if float(value).is_integer() and abs(value) < 1e15 else f"{value:g}"


def _in_range(spec: Spec, number: float) -> bool:
    if spec.low is not None and (number < spec.low or (spec.low_open and number == spec.low)):
        return False
    return spec.high is None or number <= spec.high


def _check_int(spec: Spec, value: Any):
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        return _REFUSED
    number = int(value)
    return number if _in_range(spec, number) else _REFUSED


def _check_float(spec: Spec, value: Any):
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        return _REFUSED
    number = float(value)
    if not math.isfinite(number) or not _in_range(spec, number):
        return _REFUSED
    return number


def _check_bool(spec: Spec, value: Any):
    # numpy booleans are not bool instances but say so through their type name
    if isinstance(value, bool) or type(value).__name__ == "bool_":
        return bool(value)
    return _REFUSED


def _check_str(spec: Spec, value: Any):
    return value if isinstance(value, str) and value.strip() else _REFUSED


def _check_text(spec: Spec, value: Any):
    return value if isinstance(value, str) else _REFUSED


def _check_size(spec: Spec, value: Any):
    if isinstance(value, (str, bytes, dict)):
        return _REFUSED
    width, height = value
    checked = (_check_int(spec, width), _check_int(spec, height))
    return _REFUSED if _REFUSED in checked else checked


def _check_int3(spec: Spec, value: Any):
    if isinstance(value, (str, bytes, Mapping)):
        return _REFUSED
    values = tuple(value)
    if len(values) != 3:
        return _REFUSED
    checked = tuple(_check_int(spec, v) for v in values)
    return _REFUSED if _REFUSED in checked else checked


def _check_point(spec: Spec, value: Any):
    if isinstance(value, (str, bytes, Mapping)):
        return _REFUSED
    coords = tuple(value)
    if len(coords) != 3 or any(isinstance(c, bool) or not isinstance(c, numbers.Real)
                               for c in coords):
        return _REFUSED
    coords = tuple(float(c) for c in coords)
    return coords if all(math.isfinite(c) for c in coords) else _REFUSED


def _check_range2(spec: Spec, value: Any):
    if isinstance(value, (str, bytes, Mapping)):
        return _REFUSED
    first, second = value
    if any(isinstance(v, bool) or not isinstance(v, numbers.Real) for v in (first, second)):
        return _REFUSED
    first, second = float(first), float(second)
    if not (math.isfinite(first) and math.isfinite(second)) or first > second:
        return _REFUSED
    low, high = _range2_bounds(spec)
    if first < low or second > high or (spec.low_open and second <= low):
        return _REFUSED
    return first, second


def _check_switches(spec: Spec, value: Any):
    if not isinstance(value, Mapping) or not all(
            isinstance(k, str) and isinstance(v, bool) for k, v in value.items()):
        return _REFUSED
    return dict(value)


def _check_names(spec: Spec, value: Any):
    if isinstance(value, (str, bytes, Mapping)):
        return _REFUSED
    names = list(value)
    return names if all(isinstance(n, str) for n in names) else _REFUSED


def _check_name_set(spec: Spec, value: Any):
    names = _check_names(spec, value)
    if names is _REFUSED or not names or len(set(names)) != len(names) or \
            not all(name.strip() for name in names) or \
            (spec.high is not None and len(names) > spec.high):
        return _REFUSED
    return tuple(names)


def _check_transforms(spec: Spec, value: Any):
    if spec.parse is None:              # Spec.__post_init__ refuses a transforms field without
        raise ValueError("a transforms field needs parse")
    checked = spec.parse(value)
    return _REFUSED if checked is None else checked


def _check_choice(spec: Spec, value: Any):
    for choice in spec.choices:
        if type(value) is type(choice) and value == choice:
            return choice
    return _REFUSED


def _check_points(spec: Spec, value: Any):
    if isinstance(value, (str, bytes)):
        return _REFUSED
    first, second = value
    pair = []
    for point in (first, second):
        coords = _check_point(spec, point)
        if coords is _REFUSED:
            return _REFUSED
        pair.append(coords)
    if pair[0] == pair[1]:
        return _REFUSED      # eye == target (or light position == target): no direction
    return (pair[0], pair[1])


def _check_nested(spec: Spec, value: Any):
    return value if spec.nested is not None and isinstance(value, spec.nested) else _REFUSED


_CHECKERS = {"int": _check_int, "float": _check_float, "bool": _check_bool,
             "str": _check_str, "text": _check_text, "choice": _check_choice,
             "points": _check_points, "size": _check_size, "range2": _check_range2,
             "switches": _check_switches,
             "names": _check_names, "name_set": _check_name_set,
             "transforms": _check_transforms, "nested": _check_nested,
             "int3": _check_int3, "point": _check_point}


# -- declaring ---------------------------------------------------------------------------
def setting(default: Any = dataclasses.MISSING, *, doc: str, kind: str,
            default_factory: Any = dataclasses.MISSING, **spec: Any) -> Any:
    """A dataclass field carrying its :class:`Spec` (see the module docstring)."""
    metadata = {"spec": Spec(doc=doc, kind=kind, **spec)}
    if default_factory is not dataclasses.MISSING:
        return dataclasses.field(default_factory=default_factory, metadata=metadata)
    return dataclasses.field(default=default, metadata=metadata)


def specs(cls: type) -> dict[str, Spec]:
    """Field name -> :class:`Spec` of a dataclass declared with :func:`setting`."""
    return _specs_of(cls)


@cache
def _specs_of(cls: type) -> dict[str, Spec]:
    # behind specs(): mypy reads a cached function's argument as Hashable, which type[Any]
    # (what type(obj) gives) is not to it
    return {f.name: f.metadata["spec"] for f in dataclasses.fields(cls) if "spec" in f.metadata}


def validate(obj: Any) -> None:
    """Check and normalise every declared field of ``obj`` in place (frozen or not); the
    first bad field raises :class:`SettingError`."""
    for name, spec in specs(type(obj)).items():
        value = getattr(obj, name)
        normal = spec.check(name, value)
        if normal is not value:
            object.__setattr__(obj, name, normal)


@cache
def stages_reading(cls: type, stage: str) -> tuple[str, ...]:
    """The fields of ``cls`` that ``stage`` reads directly (cached: every stage key of a
    frame asks)."""
    return tuple(name for name, spec in specs(cls).items() if stage in spec.stages)


def check_stages(cls: type, stages: tuple[str, ...]) -> None:
    """A ValueError naming the field when a field of ``cls`` declares a stage that is not
    one of ``stages`` (the schema itself knows no stage names)."""
    for name, spec in specs(cls).items():
        unknown = [stage for stage in spec.stages if stage not in stages]
        if unknown:
            raise ValueError(f"field {name}: unknown stage(s) {unknown}; stages are {stages}")


# -- outside data -------------------------------------------------------------------------
def from_dict(cls: type, data: Any, base: Any = None, where: str = "",
              declared_only: bool = False) -> Any:
    """An instance of ``cls`` from plain data (JSON, TOML): ``base`` (default: ``cls()``)
    with the fields in ``data`` replaced. Lists become tuples, tables become nested
    dataclasses; unknown keys and bad values raise :class:`SettingError` whose message
    starts with ``where`` (e.g. ``"settings: "``). With ``declared_only`` a field without
    a :class:`Spec` counts as unknown (the app state: its runtime part is never read)."""
    if not isinstance(data, Mapping):
        place = where.rstrip(".") or cls.__name__
        raise SettingError(place, f"{place} must be a table of fields, got "
                                  f"{type(data).__name__}")
    base = cls() if base is None else base
    known = {f.name: f for f in dataclasses.fields(cls)}
    field_specs = specs(cls)
    _refuse_unknown(tuple(field_specs) if declared_only else tuple(known), data, where)
    values = {}
    for name, value in data.items():
        spec = field_specs.get(name)
        if spec is not None and spec.kind == "nested" and spec.nested is not None and \
                isinstance(value, Mapping):
            value = from_dict(spec.nested, value, getattr(base, name), f"{where}{name}.",
                              declared_only and bool(specs(spec.nested)))
        elif spec is None and dataclasses.is_dataclass(getattr(base, name)) and \
                isinstance(value, Mapping):
            value = from_dict(type(getattr(base, name)), value, getattr(base, name),
                              f"{where}{name}.")
        elif spec is None:
            value = _plain_field(known[name], getattr(base, name), value, where)
        values[name] = value
    try:
        return dataclasses.replace(base, **values)
    except SettingError as exc:
        # a field checked by the dataclass names itself; give it its full path
        raise SettingError(where + exc.field, f"{where}{exc}") from None


def check_fields(cls: type, data: Any, where: str = "") -> dict[str, Any]:
    """The declared fields in ``data`` checked one at a time and normalised, without
    making an instance: rules between fields (``__post_init__``) are left to whoever
    combines them (a lesson's defaults with a step's own fields). Unknown keys raise."""
    if not isinstance(data, Mapping):
        place = where.rstrip(".") or cls.__name__
        raise SettingError(place, f"{place} must be a table of fields, got "
                                  f"{type(data).__name__}")
    field_specs = specs(cls)
    _refuse_unknown(tuple(field_specs), data, where)
    checked = {}
    for name, value in data.items():
        try:
            checked[name] = field_specs[name].check(name, value)
        except SettingError as exc:
            raise SettingError(where + name, f"{where}{exc}") from None
    return checked


def _refuse_unknown(known: tuple[str, ...], data: Mapping, where: str) -> None:
    unknown = sorted(str(key) for key in data if key not in known)
    if unknown:
        raise SettingError(where + unknown[0], f"{where}{unknown[0]}: unknown field(s) "
                                               f"{', '.join(unknown)}; known: "
                                               f"{', '.join(known)}")


def _plain_field(f: dataclasses.Field, current: Any, value: Any, where: str) -> Any:
    """A field without a spec (e.g. a correction switch): same type as its value now."""
    if isinstance(current, bool):
        if isinstance(value, bool):
            return value
        raise SettingError(where + f.name, f"{where}{f.name} must be true or false, got "
                                           f"{value!r}")
    return value


def to_dict(obj: Any, declared_only: bool = False) -> dict:
    """Plain data (dicts, lists, numbers, text) that :func:`from_dict` reads back; with
    ``declared_only`` only the fields that declare a :class:`Spec` (nested ones too)."""
    if not declared_only:
        return _plain(dataclasses.asdict(obj))
    result = {}
    for name, spec in specs(type(obj)).items():
        value = getattr(obj, name)
        if spec.kind == "nested" and specs(type(value)):
            result[name] = to_dict(value, declared_only=True)
        elif dataclasses.is_dataclass(value):
            result[name] = to_dict(value)
        else:
            result[name] = _plain(value)
    return result


def _plain(value: Any) -> Any:
    if isinstance(value, dict):
        return {key: _plain(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(item) for item in value]
    return value
