"""What a lesson is once read: :class:`Lesson`, its :class:`Step` entries, their
:class:`TryThis` prompts (with an optional :class:`Prediction`), the :class:`LessonError`
a broken file gives, and the limits and defaults every step shares.

These are plain frozen dataclasses; :mod:`explorer.lessons.reader` builds them from the
TOML files and checks every value on the way, so code that holds a :class:`Lesson` can
trust it. A step turns into the :class:`~explorer.lpv.settings.Settings` it shows with
:meth:`Step.settings`.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from explorer.lpv.settings import VIEWS, Corrections, Settings
from explorer.schema import specs

MAX_FORMULAS_PER_STEP = 120
"""Most formulas (inline and display math, derivation formulas) one step may typeset:
the richest shipped step has 13; each is a texture the window draws every frame."""
MAX_STEP_TEXT = 16_000
"""Longest text of one step, in characters: the longest shipped step has about 1 700."""
MAX_STEPS = 40
"""Most steps in one lesson: the longest shipped lesson has 6."""

LESSON_DEFAULTS: dict[str, Any] = {"spot_cone": False, "auto_exposure": False}
"""Settings every step starts from unless its lesson or the step sets them: the spot's 90°
square frustum (the lessons' texts and measured numbers are about it) and a fixed exposure
(their prompts ask the reader to watch the image brighten with the flux, the bounces or
the published formulas, which an auto exposure would undo)."""
SCENE_STATE: dict[str, Any] = {"lights": None, "object_transforms": ()}
"""What belongs to the scene on screen and starts afresh with every step (a step may set
them in its [settings]): which lights shine and where the objects are; lights or objects
of another scene would not even exist in the step's."""
COMPARE_VIEWS = ("split", "difference")
"""Views that show the step's corrections against the ``compare`` preset."""
STEP_VIEWS = VIEWS + COMPARE_VIEWS
"""What a step's ``view`` may be: a view of the settings, or one of :data:`COMPARE_VIEWS`."""
TRY_COMPARES = ("apply", "split", "difference", "side-by-side", "small-multiples")
"""How a try-this shows its change: applied on top of the step (no comparison), the step
and the change left | right of a divider, their difference in false colour, the two whole
views side by side, or the step beside each of several values in a grid."""
TRY_GRIDS = ("side-by-side", "small-multiples")
"""The modes that show whole views in a grid, each rendered at its cell's size."""
MAX_VARIANTS = 3
"""Most values a small-multiples try-this shows beside the step (a 2 × 2 grid): each is a
pipeline of its own in the window."""

Vec3 = tuple[float, float, float]


class LessonError(ValueError):
    """A lesson file that cannot be used; the message names file, step and field."""

    def __init__(self, path: Path | str, message: str, step: int | None = None,
                 step_title: str | None = None, field: str | None = None,
                 line: int | None = None) -> None:
        self.path = Path(path)
        self.step = step
        self.step_title = step_title
        self.field = field
        self.line = line
        self.reason = message
        where = [str(self.path)]
        if line is not None:
            where[0] += f":{line}"
        if step is not None:
            where.append(f"step {step}" + (f" ({step_title!r})" if step_title else ""))
        if field is not None:
            where.append(f"field {field!r}")
        # one line whatever the file quoted in it holds (a step title or a {{...}} of
        # several lines): the reader sees line breaks as \n
        text = ", ".join(where) + ": " + message
        super().__init__(text.replace("\r", "\\r").replace("\n", "\\n"))


@dataclass(frozen=True)
class Prediction:
    """"Predict, then press": ``predict = {question, choices, answer}`` in a try-this. The
    article asks ``question`` with the ``choices`` before the button is pressed; pressing
    it shows the prompt and whether the guess was right. The loader requires a check of
    the step after this try-this (``[[steps.checks]]`` with ``after_try``), so CI verifies
    the answer on the frame."""

    question: str
    choices: tuple[str, ...]
    answer: int
    """1-based index of the right choice."""


@dataclass(frozen=True)
class TryThis:
    """A prompt asking the reader to change one control and look for an effect; the
    window's button sets ``control`` to ``value``, nothing else."""

    control: str
    """A Settings field name, ``corrections.<switch>`` or ``corrections`` (a preset name,
    or a Corrections value given as a table like a step's ``corrections``)."""
    prompt: str
    value: Any = None
    """The value the button sets (checked against the settings schema when loaded)."""
    compare: str = "apply"
    """How the change is shown (one of :data:`TRY_COMPARES`): the step is the first side
    (before), the change the second (after)."""
    values: tuple[Any, ...] = ()
    """A small-multiples try-this's values, one view each beside the step's (``value`` is
    the first)."""
    label: str = ""
    """The button's text (default: the control's label and the value)."""
    camera: tuple[Vec3, Vec3] | None = None
    """Where the camera goes with the change (``camera = {eye, target}``): the reframe a
    change of the grid or the scene needs to keep its feature in view."""
    predict: Prediction | None = None
    """A question the article asks before the button reveals the answer."""

    @property
    def split(self) -> bool:
        """Shown as before | after in the split view."""
        return self.compare == "split"

    @property
    def compares(self) -> bool:
        """Shown beside the step (any mode but ``apply``): the change is configuration B."""
        return self.compare != "apply"

    @property
    def variants(self) -> tuple[Any, ...]:
        """The values the try-this shows: ``values`` for small multiples, else ``value``."""
        return self.values or (self.value,)

    def change(self, value: Any = None) -> dict[str, Any]:
        """The change as ``Settings.with_changes`` keywords (``value``: one of
        :attr:`variants`; default :attr:`value`)."""
        value = self.value if value is None else value
        change: dict[str, Any]
        if self.control.startswith("corrections."):
            change = {"corrections": {self.control.split(".", 1)[1]: value}}
        else:
            change = {self.control: value}
        if self.camera is not None:
            change["camera"] = self.camera
        return change

    def apply(self, settings: Settings, value: Any = None) -> Settings:
        """``settings`` with this change made (``value``: one of :attr:`variants`)."""
        return settings.with_changes(**self.change(value))

    def button(self) -> tuple[str, str]:
        """(button text, what the change does) in words: :attr:`label`, else the
        control's label from the settings schema (or the correction's title) and the
        value; the second part is the control's documentation."""
        from explorer.lessons.live_values import format_value
        from explorer.lpv.corrections import CORRECTIONS

        value = format_value(self.value, "g")
        if self.control == "corrections":
            if isinstance(self.value, str):
                label, doc = f"{value} preset", "every correction switch as the preset sets it"
            else:
                off = [CORRECTIONS_TITLES.get(name, name) for name in self.value.names()
                       if not getattr(self.value, name)]
                label = "published: " + (", ".join(off) or "none")
                doc = "the correction switches set as listed"
        elif self.control.startswith("corrections."):
            name = self.control.split(".", 1)[1]
            entry = next(e for e in CORRECTIONS if e.name == name)
            label, doc = f"{entry.title}: {value}", entry.why
        else:
            spec = specs(Settings)[self.control]
            label = f"{spec.label or self.control.replace('_', ' ')}: {value}"
            doc = spec.doc
        return (self.label or label), doc


@dataclass(frozen=True)
class Step:
    """One step of a lesson: what to read, what to show, what to try."""

    number: int
    """1-based position in the lesson."""
    title: str
    text: str
    formulas: tuple[str, ...]
    scene: str
    corrections: Corrections
    overrides: tuple[tuple[str, Any], ...]
    """Settings fields the step sets, in file order (lesson defaults merged in)."""
    view: str
    compare: Corrections | None
    compare_preset: str | None
    plot: str | None
    try_this: tuple[TryThis, ...]
    camera: tuple[Vec3, Vec3] | None = None
    light: tuple[Vec3, Vec3] | None = None
    figures: tuple[Any, ...] = ()
    """Inline figures (``explorer.ui.figures.FigureSpec``), in file order."""
    show: tuple[tuple[str, Any], ...] = ()
    """OverlayState fields the step sets (its ``[steps.show]`` table, checked), in file
    order: what the main view draws in the scene."""
    marks: tuple[Any, ...] = ()
    """Labelled points in the scene (``explorer.lessons.marks.Mark``), in file order."""
    checks: tuple[Any, ...] = ()
    """The text's claims about its live numbers (``explorer.lessons.checks.Check``)."""
    split_at: float | None = None
    """The split view's divider (a fraction of the width), or None: the middle."""
    live_lpv: bool = False
    """The web page runs this step's LPV live beside its picture (explorer/site/live_lpv.py)."""

    @property
    def scene_name(self) -> str:
        """The scene in a word: a built-in scene's name, or a scene file's or mesh's stem
        (``scene`` holds its absolute path)."""
        return Path(self.scene).stem if "/" in self.scene or "\\" in self.scene \
            else self.scene

    @property
    def mark_ids(self) -> tuple[str, ...]:
        """The ids of the marks that measure (have a normal): ``mark.<id>.*`` names."""
        return tuple(mark.id for mark in self.marks if mark.normal is not None)

    def overlays(self, base: Any = None) -> Any:
        """The in-scene overlays this step shows (an ``OverlayState``): nothing drawn or
        picked but what its ``show`` table sets; ``base`` (the reader's overlays) lends
        only the reader's own controls (``overlay_params.READER_FIELDS``)."""
        from explorer.overlay_params import step_overlays

        return step_overlays(dict(self.show), base)

    @property
    def figure_ids(self) -> tuple[str, ...]:
        return tuple(spec.instance_id for spec in self.figures)

    def settings(self, base: Settings | None = None) -> Settings:
        """The Settings this step shows: ``base`` (default: ``Settings()``) with the
        step's scene, corrections, camera, light and overrides applied.

        Scene, corrections, camera and light always come from the step (a step that
        names no camera gets the scene's default one), so a step looks the same whatever
        was on screen before; so do the :data:`LESSON_DEFAULTS` and the
        :data:`SCENE_STATE` (the scene's own lights, its objects where it puts them).
        Other fields the step does not mention (window size, exposure, ...) keep the value
        of ``base``."""
        base = Settings() if base is None else base
        return base.with_changes(scene=self.scene, corrections=self.corrections,
                                 camera=self.camera, light=self.light,
                                 **{**LESSON_DEFAULTS, **SCENE_STATE, **dict(self.overrides)})

    def compare_settings(self, base: Settings | None = None) -> Settings | None:
        """The other side of a split/difference view (the step's settings with the
        ``compare`` preset), or None when the step compares nothing."""
        if self.compare is None:
            return None
        return self.settings(base).with_changes(corrections=self.compare)

    def controls(self) -> tuple[str, ...]:
        return tuple(item.control for item in self.try_this)


@dataclass(frozen=True)
class Lesson:
    id: str
    title: str
    summary: str
    steps: tuple[Step, ...]
    path: Path
    number: int
    """The NN of the file name (orders the lessons)."""

    def step(self, number: int) -> Step:
        """Step ``number`` (1-based); IndexError names the valid range."""
        if not 1 <= number <= len(self.steps):
            raise IndexError(f"lesson {self.id!r} has steps 1..{len(self.steps)}, "
                             f"not {number}")
        return self.steps[number - 1]


def _correction_titles() -> dict[str, str]:
    from explorer.lpv.corrections import CORRECTIONS

    return {entry.name: entry.title for entry in CORRECTIONS}


class _Titles(dict):
    """The corrections' titles by switch name, read on first use."""

    def get(self, key, default=None):  # type: ignore[override]
        if not self:
            self.update(_correction_titles())
        return super().get(key, default)


CORRECTIONS_TITLES = _Titles()
"""Switch name -> the correction's title (``explorer.lpv.corrections``), for the words a
button or a step summary shows."""
