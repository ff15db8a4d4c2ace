"""The numbers a try-this prompt quotes, before and after its press, kept.

A prompt's live numbers describe the configuration its button sets. Once that frame was
on screen its result is kept here, so the prompt keeps its numbers after Undo; and the
step's own frame as it was before the press is kept too, so the prompt can say what each
number was before ("before the press: 35.9 W"). Both are finished FrameResults of one
lesson step; a change of the step's settings (another scene size, the reader's exposure)
makes the kept frame stale, and it is not used, except the render size of a press shown
in a grid of views (side by side, small multiples: each view renders at its cell's size).
A kept frame holds only what a prompt's numbers read: its propagation steps (grid_0..N,
about 200 MiB a cascade at 64³) and its per-cell audit records are dropped, and at most
:data:`KEPT_FRAMES` of each kind are kept, and no more than :data:`KEPT_BYTES` of arrays
(a 64³ L2 frame's accumulated grids alone are 28 MiB a cascade), the least recently kept
first to go.
"""

from __future__ import annotations

import weakref
from collections import OrderedDict
from dataclasses import dataclass, field, fields, is_dataclass, replace
from typing import Any

import numpy as np

from explorer.lessons import live_values
from explorer.lessons import text as lesson_text

FRAME_PREFIXES = ("audit.", "frame.", "mark.")
"""Quantities read from a frame (the others, settings and derivations, do not change
with the frame and need no "before")."""


KEPT_FRAMES = 12
"""Frames kept per kind (steps' own, presses): a reader who comes back after a dozen
other steps sees the prompt's numbers again once the step's frame is on screen."""


KEPT_BYTES = 24 * 2**20
"""Bytes of arrays the frames of one kind hold at most (the newest is kept whatever its
size): over a course the kept frames' accumulated grids, images and VPLs were the
window's largest growth after its first pass (issue #31: 240 MiB at step 20, up to
1 GiB with twelve 64³ two-cascade frames of each kind); at 48 MiB a kind the soak's
heaviest step stood 4 MiB under the window's budget of 1.2 GiB (BENCHMARKS.md). A 64³
two-cascade frame alone is more: after such a step only its own frame is kept, the
prompts of the steps before it read theirs again once their frame is on screen."""


def held_bytes(value: Any, seen: set[int] | None = None) -> int:
    """The bytes of the numpy arrays ``value`` holds (a frame: its fields, levels, VPL
    sets and images, walked through dataclasses, lists, tuples and dicts), each array
    counted once (views of one buffer as their base)."""
    seen = set() if seen is None else seen
    if isinstance(value, np.ndarray):
        owner = value
        while isinstance(owner.base, np.ndarray):
            owner = owner.base
        if id(owner) in seen:
            return 0
        seen.add(id(owner))
        return int(owner.nbytes)
    if id(value) in seen:
        return 0
    if isinstance(value, (list, tuple)):
        seen.add(id(value))
        return sum(held_bytes(item, seen) for item in value)
    if isinstance(value, dict):
        seen.add(id(value))
        return sum(held_bytes(item, seen) for item in value.values())
    if is_dataclass(value) and not isinstance(value, type):
        seen.add(id(value))
        # what the instance stores, read without running a deferred field's function
        # (explorer/lpv/deferred.py): a Deferred not yet computed holds no array
        stored = getattr(value, "__dict__", None)
        held = (stored.values() if stored is not None else
                [getattr(value, entry.name, None) for entry in fields(value)])
        return sum(held_bytes(item, seen) for item in held)
    return 0


def lean_frame(result: Any) -> Any:
    """``result`` without what no prompt number reads (each level's propagation steps
    and per-cell audit records): the kept frame must not hold a frame's largest arrays
    after the reader has moved on (the window's memory over a course, issue #31)."""
    levels = result.cascades
    if not levels or all(level.steps is None and level.cell_records is None
                         for level in levels):
        return result
    return replace(result, cascades=[replace(level, steps=None, cell_records=None)
                                     for level in levels])


def _keep(kept: OrderedDict, sources: dict, sizes: dict, key: Any, result: Any) -> None:
    """``kept[key] = result``, lean, the newest last, the oldest beyond
    :data:`KEPT_FRAMES` frames or :data:`KEPT_BYTES` bytes dropped; ``sources``
    remembers (weakly) which frame each entry was made from, so the frame on screen is
    made lean (and measured, into ``sizes``) once, not at every draw."""
    source = sources.get(key)
    if key in kept and source is not None and source() is result:
        return
    kept[key] = lean = lean_frame(result)
    sources[key] = weakref.ref(result)
    sizes[key] = held_bytes(lean)
    kept.move_to_end(key)
    while len(kept) > 1 and (len(kept) > KEPT_FRAMES or
                             sum(sizes[entry] for entry in kept) > KEPT_BYTES):
        oldest = kept.popitem(last=False)[0]
        sources.pop(oldest, None)
        sizes.pop(oldest, None)


SIZE_FIELDS = ("width", "height")
"""The render size: a grid comparison's views render at their cell's size, not at the
view's."""


def same_frame(a: Any, b: Any, sized: bool = True) -> bool:
    """Whether Settings ``a`` and ``b`` render the same frame: equal in every field a
    stage before the display reads (exposure, tone curve and the like only change how
    the window shows it, which it applies itself); ``sized`` False: the same
    configuration at any render size."""
    from explorer.lpv.settings import Settings
    from explorer.schema import specs

    return all(getattr(a, name) == getattr(b, name) for name, spec in specs(Settings).items()
               if set(getattr(spec, "stages", ()) or ("?",)) - {"display"}
               and (sized or name not in SIZE_FIELDS))


@dataclass
class TryFrames:
    """Per (lesson id, step, try-this): the frame the press showed; per (lesson id,
    step): the step's own frame."""

    after: OrderedDict[tuple[str, int, int], Any] = field(default_factory=OrderedDict)
    before: OrderedDict[tuple[str, int], Any] = field(default_factory=OrderedDict)
    sources: dict[Any, weakref.ref] = field(default_factory=dict)
    """Per key of :attr:`after` and :attr:`before`: the frame its entry was made from."""
    sizes: dict[Any, int] = field(default_factory=dict)
    """Per key of :attr:`after` and :attr:`before`: the bytes of arrays its entry holds
    (:func:`held_bytes`)."""
    any_size: set[tuple[str, int, int]] = field(default_factory=set)
    """Try-this whose press was shown in a grid of views (side by side, small multiples):
    the kept frame rendered at its cell's size, which the view after Undo does not
    share, and still describes the press."""

    def keep_step(self, key: tuple[str, int], result: Any) -> None:
        """The step's own finished frame, on screen with no try-this pressed."""
        if result is not None:
            _keep(self.before, self.sources, self.sizes, key, result)

    def keep_after(self, key: tuple[str, int, int], result: Any, any_size: bool = False
                   ) -> None:
        """The try-this's finished frame, on screen while it is pressed (``any_size``:
        in a grid of views, at its cell's size)."""
        if result is not None:
            _keep(self.after, self.sources, self.sizes, key, result)
            (self.any_size.add if any_size else self.any_size.discard)(key)

    def after_context(self, key: tuple[str, int, int], context: live_values.LiveContext
                      ) -> live_values.LiveContext:
        """``context`` (the configuration the button sets, no frame) with the frame kept
        from its last press, when that frame shows those settings."""
        kept = self.after.get(key)
        if kept is None or context.result is not None or \
                not same_frame(kept.settings, context.settings, key not in self.any_size):
            return context
        return replace(context, result=kept)

    def before_note(self, key: tuple[str, int], prompt: str,
                    context: live_values.LiveContext, figure_ids: tuple[str, ...] = ()
                    ) -> str:
        """"before the press: 35.9 W, 0.79" for the frame numbers of ``prompt`` read on
        the step's kept frame (``context``: the step's own, its result replaced), or ""
        when no frame is kept or the prompt quotes none."""
        kept = self.before.get(key)
        if kept is None:
            return ""
        before = replace(context, settings=kept.settings, result=kept)
        values = []
        for name, fmt in lesson_text.placeholders(prompt):
            if not name.startswith(FRAME_PREFIXES):
                continue
            try:
                shown = live_values.render(name, fmt, before, figure_ids)
            except KeyError:
                continue
            if shown != live_values.PENDING:
                quantity = live_values.lookup(name, figure_ids, tuple(before.marks))
                values.append(f"{shown} {quantity.unit}".strip())
        return f"before the press: {', '.join(values)}" if values else ""
