"""Answers the window asks for every frame, made again only when what they are made of
changes: the sources are frozen objects (settings, a step, a measurement), compared by
identity, and plain values (sizes, tuples of changes), compared by value. An answer holds
its sources, so an id in a slot's name names no other object meanwhile."""

from __future__ import annotations

from collections.abc import Callable, Hashable
from typing import Any

_VALUES = (int, float, str, bool, type(None), tuple)
"""Sources compared by value; any other is compared by identity."""


def _same(kept: tuple, sources: tuple) -> bool:
    return len(kept) == len(sources) and all(
        a is b or (isinstance(a, _VALUES) and type(a) is type(b) and a == b)
        for a, b in zip(kept, sources))


class KeptAnswers:
    """At most ``most`` answers, one per slot (all dropped when a new slot finds it
    full: the slots are a frame's few configurations)."""

    def __init__(self, most: int) -> None:
        self.most = most
        self._kept: dict[Hashable, tuple[tuple, Any]] = {}

    def answer(self, slot: Hashable, sources: tuple, make: Callable[[], Any]) -> Any:
        """The answer kept in ``slot`` if it was made of ``sources``, else ``make()``,
        kept there."""
        kept = self._kept.get(slot)
        if kept is not None and _same(kept[0], sources):
            return kept[1]
        made = make()
        if slot not in self._kept and len(self._kept) >= self.most:
            self._kept.clear()
        self._kept[slot] = (sources, made)
        return made

    def __len__(self) -> int:
        return len(self._kept)
