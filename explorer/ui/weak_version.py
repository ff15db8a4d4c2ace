"""A version of what an upload or a cached figure was made from that keeps none of it
alive: values compared by value, objects (frames, arrays) by identity through weak
references. A cache that held its sources to keep their ids from being reused kept a
step's frame (hundreds of MiB at 64³) after the view had moved on."""

from __future__ import annotations

import weakref
from collections.abc import Sequence


class _Strong:
    """An object no weak reference can name (compared by identity, held)."""

    __slots__ = ("obj",)

    def __init__(self, obj: object) -> None:
        self.obj = obj

    def __call__(self) -> object:
        return self.obj


class WeakVersion:
    """The parts a version was made of: those of ``values`` by value, the others by
    identity; a part that has been freed matches nothing (its id may name another
    object by now)."""

    __slots__ = ("_parts",)

    def __init__(self, parts: Sequence[object], values: tuple[type, ...]) -> None:
        self._parts = tuple((True, part) if isinstance(part, values) else (False, _ref(part))
                            for part in parts)

    def matches(self, parts: Sequence[object]) -> bool:
        """Whether ``parts`` are the parts this version was made of."""
        if len(parts) != len(self._parts):
            return False
        for (by_value, kept), part in zip(self._parts, parts):
            if by_value:
                if kept != part:
                    return False
            elif kept() is not part:
                return False
        return True


def _ref(obj: object):
    try:
        return weakref.ref(obj)
    except TypeError:
        return _Strong(obj)
