"""Values a frame computes only when somebody reads them: a :class:`Deferred` (a function
of no arguments, run once) given to a :class:`DeferredField` of a dataclass.

A frame's CPU-side products that only a reader needs (the gathered flux, the RSM's flux
sums, the finite checks of the read-back images) would otherwise cost every frame, and
most frames are never read (the window reads one result per published picture, the bench
none). Reading the field runs the function once and keeps its value; the value is the
one the function would have computed eagerly, so the numbers are the same.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any


class Deferred:
    """``function()``, computed on the first :meth:`value` and kept; ``runs`` counts the
    computations (0 or 1: what a test reads)."""

    __slots__ = ("_function", "_value", "runs")

    def __init__(self, function: Callable[[], Any]) -> None:
        self._function: Callable[[], Any] | None = function
        self._value: Any = None
        self.runs = 0

    @property
    def computed(self) -> bool:
        return self._function is None

    def value(self) -> Any:
        function = self._function
        if function is not None:
            self._value = function()
            self._function = None       # drop what it closed over
            self.runs += 1
        return self._value


class DeferredField:
    """A dataclass field (the field's default) that accepts a plain value or a
    :class:`Deferred`, and reads as the plain value (the Deferred's, computed then).
    ``default``: a function making the default value (called per instance when none is
    given)."""

    def __init__(self, default: Callable[[], Any] | None = None) -> None:
        self._default = default
        self._name = ""

    def __set_name__(self, owner: type, name: str) -> None:
        self._name = f"_{name}_value"

    def __get__(self, obj: object, owner: type | None = None) -> Any:
        if obj is None:
            # what dataclasses takes for the field's default: a marker that __set__ turns
            # into a default of the instance's own
            return _DEFAULT
        value = obj.__dict__[self._name]
        if type(value) is Deferred:
            value = value.value()
            obj.__dict__[self._name] = value
        return value

    def __set__(self, obj: object, value: Any) -> None:
        if value is _DEFAULT:
            if self._default is None:
                raise TypeError(f"{type(obj).__name__} needs a value for "
                                f"{self._name[1:-6]!r}")
            value = Deferred(self._default)
        obj.__dict__[self._name] = value

    def pending(self, obj: object) -> Deferred | None:
        """The Deferred ``obj`` holds in this field, not yet read; None once it is."""
        value = obj.__dict__[self._name]
        return value if type(value) is Deferred else None


class _Default:
    def __repr__(self) -> str:
        return "<the field's default>"


_DEFAULT = _Default()
