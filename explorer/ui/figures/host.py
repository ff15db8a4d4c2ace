"""What a figure reads besides its parameters: the frame results it plots and the
interactive state of each figure instance on the page.

A lesson page may show the same figure kind twice with different parameters; each
instance keeps its own state (the dragged normal, the step t, whether it plays) under its
instance id in one :class:`FigureContext`. The state is made from the parameters the
first time an instance draws, and made again when the parameters change (a new lesson
step), so a step always opens on what its author set.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from explorer.ui.state import AppState


@dataclass
class _Instance:
    kind: str
    params: Any
    state: AppState


@dataclass
class FigureContext:
    """Shared by every figure drawn on one page (the lesson panel owns one).

    ``results``: the FrameResults the audit figures plot, configuration A first and B
    (compare views) second; empty before the first frame."""

    results: tuple = ()
    _instances: dict[str, _Instance] = field(default_factory=dict)

    def state_for(self, instance_id: str, kind: str, params: Any,
                  make: Callable[[Any], Any]) -> Any:
        """The state of ``instance_id``; a fresh ``make(params)`` when the instance is new
        or its kind or parameters changed since it last drew."""
        instance = self._instances.get(instance_id)
        if instance is None or instance.kind != kind or instance.params != params:
            instance = _Instance(kind, params, make(params))
            self._instances[instance_id] = instance
        return instance.state

    def forget(self, instance_id: str) -> None:
        """Drop an instance's state (the page that showed it closed)."""
        self._instances.pop(instance_id, None)

    def update_from_app(self, state) -> None:
        """Take the results an AppState holds: A, and B while a compare view is on."""
        rt = state.runtime
        results = [rt.frame.result] if rt.frame.result is not None else []
        if results and state.comparing and rt.frame.compare_result is not None:
            results.append(rt.frame.compare_result)
        self.results = tuple(results)

    @contextmanager
    def showing(self, state) -> Iterator[FigureContext]:
        """The results an AppState holds (:meth:`update_from_app`) for the figures drawn
        or read inside, none kept after: the context outlives the step, and a frame
        kept past it holds its propagation steps (hundreds of MiB at 64³)."""
        self.update_from_app(state)
        try:
            yield self
        finally:
            self.results = ()
