"""Reading lesson files: ``lessons/NN-slug.toml`` read, validated and turned into the
:mod:`explorer.lessons.model` dataclasses.

A lesson is data, never code: TOML parsed with :mod:`tomllib` (``tomli`` on Python 3.10).
Every step says which scene, settings, corrections, view and plot it shows, which
derivations it typesets, and which controls the reader should try.

File layout (all keys except ``id``, ``title``, ``summary`` and ``steps`` are optional)::

    id = "injection"                 # what `lpv-explorer lessons ID` accepts
    title = "..."
    summary = "..."
    scene = "cornell"                # default for every step; or a scene file or mesh,
                                     # its path relative to this file
    [settings]                       # defaults for every step (Settings fields)
    grid_size = 16
    [[steps]]
    title = "..."
    text = '''markdown, inline math as $...$'''
    formulas = ["sh.clamped_cosine_lobe"]          # derivation registry names
    scene = "single-source"
    corrections = "original"                        # a preset, or a table:
    # corrections = { preset = "original", side_faces = false }
    camera = { eye = [0, 1, 3], target = [0, 1, 0] }
    light = { position = [0, 1.9, 0], target = [0, 0, 0] }
    view = "indirect"                # settings.VIEWS, or "split"/"difference" with compare
    compare = "original"             # preset shown on the other side of split/difference
    plot = "flux-per-step"           # settings.PLOTS
    split_at = 0.4                   # the split view's divider, a fraction of the width
    [steps.settings]
    iterations = 4
    [[steps.try_this]]
    control = "corrections.injection_pi"   # a Settings field, corrections.<switch> or
    value = false                          # "corrections" (a preset); the value to set
    prompt = "..."                         # may quote live numbers, {{audit.injected}}
    compare = "split"                      # optional: how the change is shown, before
                                           # against after (model.TRY_COMPARES; split =
                                           # true is compare = "split")
    camera = { eye = [0, 2, 4], target = [0, 0, 0] }  # optional: reframe with the change
    predict = { question = "Brighter or darker?", choices = ["brighter", "darker"], answer = 2 }
                                           # optional: asked before the button reveals it
    [[steps.figures]]                      # inline live figures (explorer/ui/figures)
    kind = "clamped-cosine"
    id = "lobe"                            # placed in the text by {{figure:lobe}}
    normal_deg = 30
    [steps.show]                           # what the main view draws in the scene
    slice = true                           # (explorer/overlay_params.py OverlayState)
    slice_quantity = "in-flight"
    slice_step = 2
    [[steps.marks]]                        # a labelled point in the scene
    id = "dark"                            # (explorer/lessons/marks.py): drawn in the
    label = "dark side"                    # view; with a normal it measures the LPV's
    at = [0.33, 0.4, -0.6]                 # irradiance there, {{mark.dark.irradiance}}
    normal = [1, 0, 0]
    [[steps.checks]]                       # a claim of the text, checked in CI on the
    claim = "the clamp adds light"         # step's converged frame
    value = "audit.clamp_gain"             # (explorer/lessons/checks.py: fixed operators,
    op = ">"                               # quantity names, numbers; never code)
    than = 0

The text is the markdown dialect of :mod:`explorer.lessons.text`: inline and display math,
live numbers ``{{name:format}}`` (:mod:`explorer.lessons.live_values`), ``{{figure:ID}}``,
``{{formula:NAME}}`` and ``{{try:K}}`` markers; the validator checks every one of them.

The folder's ``glossary.toml`` is not a lesson: it holds the recurring terms the article
explains on hover (:mod:`explorer.lessons.glossary`).

Errors are :class:`LessonError` naming the file and the line of the key
(:mod:`explorer.lessons.where`), the step (number and title) and the field;
:func:`load_all` collects them so one broken lesson never hides the others. The authors'
guide, docs/AUTHORING.md, describes every key (:func:`format_keys` lists them).
"""

from __future__ import annotations

import errno
import re
import sys
from collections.abc import Callable, Mapping
from dataclasses import fields, replace
from pathlib import Path
from typing import Any

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on Python 3.10 only
    import tomli as tomllib

from explorer import safe_files
from explorer.lessons.model import (
    COMPARE_VIEWS,
    MAX_FORMULAS_PER_STEP,
    MAX_STEP_TEXT,
    MAX_STEPS,
    MAX_VARIANTS,
    STEP_VIEWS,
    TRY_COMPARES,
    Lesson,
    LessonError,
    Prediction,
    Step,
    TryThis,
    Vec3,
)
from explorer.lessons.where import located
from explorer.lpv.settings import PLOTS, PRESETS, Corrections, Settings
from explorer.resources import lesson_dir
from explorer.scene.builtin import BUILTIN_SCENES
from explorer.schema import SettingError, Spec, check_fields, from_dict, specs

# The lesson file's own keys, declared like the Settings fields and checked by the same
# schema (explorer/schema.py). Tables with more structure (settings, corrections,
# camera, light, formulas, try_this, steps) are read by the functions below.
_SCENE = Spec(kind="str", doc="A built-in scene (explorer/scene/builtin.py), or a scene file "
                                   "(.toml) or mesh file, its path relative to the lesson.")
_LESSON_FIELDS = {
    "id": Spec(kind="str", doc="What `lpv-explorer lessons ID` accepts."),
    "title": Spec(kind="str", doc="The lesson's title."),
    "summary": Spec(kind="str", doc="One paragraph: what the lesson shows."),
    "scene": _SCENE,
}
_LESSON_TABLES = ("settings", "corrections", "steps")
_STEP_FIELDS = {
    "title": Spec(kind="str", doc="The step's title."),
    "text": Spec(kind="str", doc="Markdown; inline math as $...$."),
    "scene": _SCENE,
    "view": Spec(kind="choice", choices=STEP_VIEWS, doc="What the view shows."),
    "compare": Spec(kind="choice", choices=tuple(PRESETS),
                    doc="The preset on the other side of a split/difference view."),
    "plot": Spec(kind="choice", choices=PLOTS, doc="The plot brought forward."),
    "split_at": Spec(kind="float", low=0.02, high=0.98,
                     doc="Where the split view's divider stands, a fraction of the view's "
                         "width (the step's split view and its split try-this): chosen so "
                         "that the feature compared shows on both sides and the divider "
                         "stays clear of every mark (tests/lessons/test_split_divider.py)."),
    "live_lpv": Spec(kind="bool", doc="On the course's web page: the step's LPV runs live "
                                      "in the page beside its picture (explorer/site/"
                                      "live_lpv.py); the window ignores it."),
}
_STEP_TABLES = ("formulas", "camera", "light", "settings", "corrections", "try_this",
                "figures", "show", "marks", "checks")
_REQUIRED = ("id", "title", "summary")
_STEP_REQUIRED = ("title", "text")
_CAMERA_KEYS = ("eye", "target")
_LIGHT_KEYS = ("position", "target")
OWN_KEYS = tuple(key for key in (*_STEP_FIELDS, *_STEP_TABLES) if key in specs(Settings))
"""Settings fields with their own lesson keys (scene, corrections, camera, light): not
accepted inside [settings], so there is one way to say each thing."""
ID_PATTERN = re.compile(r"^[a-z0-9][a-z0-9-]*$")
_FILE_PATTERN = re.compile(r"^(\d+)-([a-z0-9-]+)\.toml$")


# --- formula names -----------------------------------------------------------------------

def _derived_lookup(name: str) -> Any:
    """The derivation result called ``name``, from the table generated from the registry
    (``explorer.derived``: no sympy; the tests check the names against the registry)."""
    from explorer import derived

    return derived.get(name)


FormulaCheck = Callable[[str], Any]
"""Raises (KeyError/LookupError/ValueError) when a formula name does not resolve."""


# --- loading -------------------------------------------------------------------------------

class _UseDerived:
    """Default of ``check_formula``: :func:`_derived_lookup`, looked up at call time."""


def load_lesson(path: Path | str,
                check_formula: FormulaCheck | None | type[_UseDerived] = _UseDerived
                ) -> Lesson:
    """Read and validate one lesson file. By default formula names are checked against
    the derivation results (the generated table of the registry, ``explorer.derived``);
    ``check_formula=None`` skips them, a callable replaces the check."""
    if check_formula is _UseDerived:
        check_formula = _derived_lookup
    path = Path(path)
    try:
        # regular files only (a FIFO is refused, never waited on), at most the lesson cap
        raw = safe_files.read_text(path, "lesson")
        data = safe_files.parse_toml(raw, path.name)
    except safe_files.UserFileError as exc:
        raise LessonError(path, str(exc).removeprefix(f"{path}: ")) from None
    except tomllib.TOMLDecodeError as exc:
        match = re.search(r"line (\d+)", str(exc))
        raise LessonError(path, f"TOML syntax error: {exc}",
                          line=int(match.group(1)) if match else None) from None
    try:
        return _Reader(path, check_formula).lesson(data)
    except LessonError as exc:
        raise located(exc, raw) from None


def load_all(directory: Path | str | None = None,
             check_formula: FormulaCheck | None | type[_UseDerived] = _UseDerived
             ) -> tuple[list[Lesson], list[LessonError]]:
    """Every ``*.toml`` lesson in ``directory`` (default: the shipped lessons), ordered by
    file name, and the errors of those that failed. Duplicate ids are errors too."""
    directory = lesson_dir() if directory is None else Path(directory)
    lessons: list[Lesson] = []
    errors: list[LessonError] = []
    seen: dict[str, Path] = {}
    from explorer.lessons.glossary import GLOSSARY_FILE

    for path in sorted(directory.glob("*.toml")):
        if path.name == GLOSSARY_FILE:     # the course's glossary, not a lesson
            continue
        try:
            lesson = load_lesson(path, check_formula)
        except LessonError as exc:
            errors.append(exc)
            continue
        if lesson.id in seen:
            errors.append(LessonError(path, f"id {lesson.id!r} is already used by "
                                            f"{seen[lesson.id].name}", field="id"))
            continue
        seen[lesson.id] = path
        lessons.append(lesson)
    return lessons, errors


def find_lesson(key: str, lessons: list[Lesson],
                errors: list[LessonError] | tuple = ()) -> Lesson:
    """The lesson whose id, number (``3`` or ``03``) or file stem is ``key``. A KeyError
    otherwise: the broken lesson's own error when ``key`` names one of ``errors`` (by file
    stem, slug or number), else the list of lessons."""
    for lesson in lessons:
        if key in (lesson.id, lesson.path.stem) or (key.isdigit() and int(key) == lesson.number):
            return lesson
    for error in errors:
        match = _FILE_PATTERN.match(error.path.name)
        names = {error.path.stem} | ({match.group(2)} if match else set())
        if key in names or (match and key.isdigit() and int(key) == int(match.group(1))):
            raise KeyError(f"lesson {key!r} is broken: {error}")
    known = ", ".join(lesson.id for lesson in lessons)
    raise KeyError(f"no lesson {key!r}; the lessons are: {known}")


TRY_KEYS = ("control", "prompt", "value", "values", "compare", "split", "label", "camera",
            "predict")
"""The keys of a ``[[steps.try_this]]`` table."""
PREDICT_KEYS = ("question", "choices", "answer")


def format_keys() -> dict[str, tuple[str, ...]]:
    """Every key the reader accepts, by table: what docs/AUTHORING.md describes."""
    from explorer.figure_params import RESERVED_KEYS
    from explorer.lessons import checks, glossary, marks

    return {"lesson": (*_LESSON_FIELDS, *_LESSON_TABLES),
            "steps": (*_STEP_FIELDS, *_STEP_TABLES),
            "camera": _CAMERA_KEYS, "light": _LIGHT_KEYS,
            "steps.try_this": TRY_KEYS, "steps.try_this.predict": PREDICT_KEYS,
            "steps.figures": RESERVED_KEYS, "steps.marks": marks.KEYS,
            "steps.checks": checks.KEYS, "glossary terms": glossary.KEYS}


def valid_controls() -> tuple[str, ...]:
    """Every name a try-this prompt may point at."""
    settings_fields = tuple(f.name for f in fields(Settings) if f.name != "corrections")
    return settings_fields + ("corrections",) + tuple(
        f"corrections.{name}" for name in Corrections.names())


class _Reader:
    """Reads one parsed lesson file. Every value is checked by a schema :class:`Spec`
    (the lesson's own keys above, the Settings fields for ``[settings]``); the reader adds
    the lesson's structure (steps, required keys, compare ↔ view) and turns each
    :class:`SettingError` into a :class:`LessonError` naming file, step and field."""

    def __init__(self, path: Path, check_formula: FormulaCheck | None) -> None:
        self.path = path
        self.check_formula = check_formula
        self.step_number: int | None = None
        self.step_title: str | None = None
        self._scenes: dict[str, Any] = {}

    def error(self, field: str | None, message: str) -> LessonError:
        return LessonError(self.path, message, step=self.step_number,
                           step_title=self.step_title, field=field)

    def fields(self, table: Mapping, declared: dict[str, Spec], tables: tuple[str, ...],
               required: tuple[str, ...] = (), prefix: str = "") -> dict[str, Any]:
        """The ``declared`` keys of ``table`` checked by their specs; any key neither
        declared nor one of ``tables`` is an error, and so is a missing required one."""
        allowed = (*declared, *tables)
        for key in table:
            if key not in allowed:
                raise self.error(prefix + str(key),
                                 f"unknown field; expected one of {list(allowed)}")
        for key in required:
            if key not in table:
                raise self.error(prefix + key, "missing (required)")
        values = {}
        for key, spec in declared.items():
            if key in table:
                try:
                    values[key] = spec.check(key, table[key])
                except SettingError as exc:
                    raise self.error(prefix + key, str(exc)) from None
        return values

    def scene(self, value: str) -> str:
        """A built-in scene's name as it is, or a scene file or mesh named relative to the
        lesson file, as its absolute path (what ``Settings.scene`` holds); the file must
        exist (it is read when a step shows it, or here when the step has marks)."""
        if value in BUILTIN_SCENES:
            return value
        shown = repr(value) if len(value) <= 80 else repr(value[:77] + "...")
        try:
            path = Path(value).expanduser()
            if not path.is_absolute():
                path = self.path.parent / path
            found, exists = path.is_file(), path.exists()
            resolved = str(path.resolve())
        except (OSError, ValueError, RuntimeError) as exc:   # too long, a NUL, a loop
            if isinstance(exc, RuntimeError) or getattr(exc, "errno", None) == errno.ELOOP:
                # Path.resolve raises RuntimeError for a loop before Python 3.13, OSError after
                where = str(path) if len(str(path)) <= 160 else "it"
                raise self.error("scene", f"{shown} is a symbolic link that leads nowhere "
                                          f"(a loop: {where})") from None
            reason = getattr(exc, "strerror", None) or str(exc)
            raise self.error("scene", f"{shown} is neither a built-in scene nor a usable "
                                      f"path ({reason})") from None
        if not found:
            where = str(path) if len(str(path)) <= 160 else "it"
            raise self.error("scene", f"{shown} is neither a built-in scene "
                             f"({', '.join(BUILTIN_SCENES)}) nor a file ({where} is "
                             f"{'not a file' if exists else 'missing'}); a path is read "
                             "relative to the lesson's folder")
        return resolved

    def loaded_scene(self, name: str) -> Any:
        """The scene ``name`` read (once per lesson file): its box bounds the marks."""
        from explorer.scene import SceneError, load_scene

        if name not in self._scenes:
            try:
                self._scenes[name] = load_scene(name)
            except SceneError as exc:
                raise self.error("scene", str(exc)) from None
        return self._scenes[name]

    # the lesson
    def lesson(self, data: Mapping) -> Lesson:
        own = self.fields(data, _LESSON_FIELDS, _LESSON_TABLES, _REQUIRED)
        if not ID_PATTERN.match(own["id"]):
            raise self.error("id", f"{own['id']!r} must be lower-case letters, digits and '-'")
        match = _FILE_PATTERN.match(self.path.name)
        if match is None:
            raise self.error(None, "the file name must look like NN-slug.toml")
        default_scene = self.scene(own["scene"]) if "scene" in own else Settings().scene
        default_settings = self.setting_overrides(data)
        default_corrections = self.corrections(data) if "corrections" in data else None
        raw_steps = data.get("steps")
        if not isinstance(raw_steps, list) or not raw_steps:
            raise self.error("steps", "a lesson needs at least one [[steps]] table")
        if len(raw_steps) > MAX_STEPS:
            raise self.error("steps", f"{len(raw_steps)} steps, over the {MAX_STEPS} a "
                             f"lesson may have (split it into lessons)")
        steps = tuple(
            self.step(number, raw, default_scene, default_settings, default_corrections)
            for number, raw in enumerate(raw_steps, start=1))
        return Lesson(id=own["id"], title=own["title"], summary=own["summary"], steps=steps,
                      path=self.path, number=int(match.group(1)))

    def step(self, number: int, raw: Any, default_scene: str,
             default_settings: dict[str, Any], default_corrections: Corrections | None) -> Step:
        self.step_number, self.step_title = number, None
        if not isinstance(raw, Mapping):
            raise self.error(None, f"a step must be a table, got {type(raw).__name__}")
        if isinstance(raw.get("title"), str):
            self.step_title = raw["title"]
        own = self.fields(raw, _STEP_FIELDS, _STEP_TABLES, _STEP_REQUIRED)
        if "corrections" in raw:
            corrections = self.corrections(raw)
        else:
            corrections = default_corrections or PRESETS["corrected"]
        overrides = {**default_settings, **self.setting_overrides(raw)}
        view, compare_preset = own.get("view", "final"), own.get("compare")
        if view in COMPARE_VIEWS and compare_preset is None:
            raise self.error("compare", f"view {view!r} needs a compare preset, one of "
                                        f"{list(PRESETS)}")
        if compare_preset is not None and view not in COMPARE_VIEWS:
            raise self.error("compare", f"compare only applies to the views {COMPARE_VIEWS}, "
                                        f"not {view!r}")
        step = Step(
            number=number, title=own["title"], text=own["text"], formulas=self.formulas(raw),
            scene=self.scene(own["scene"]) if "scene" in own else default_scene,
            corrections=corrections,
            overrides=tuple(overrides.items()), view=view,
            compare=PRESETS[compare_preset] if compare_preset else None,
            compare_preset=compare_preset, plot=own.get("plot"), try_this=self.try_this(raw),
            camera=self.pair(raw, "camera", _CAMERA_KEYS),
            light=self.pair(raw, "light", _LIGHT_KEYS), figures=self.figures(raw),
            split_at=own.get("split_at"), live_lpv=own.get("live_lpv", False))
        if step.split_at is not None and step.view != "split" and not any(
                item.split for item in step.try_this):
            raise self.error("split_at", "the step shows no split view (view = \"split\" "
                                         "or a try-this with compare = \"split\")")
        try:  # the rules between fields (e.g. bounces 2 needs a geometry volume)
            settings = step.settings()
        except SettingError as exc:
            raise self.error(f"settings.{exc.field}", str(exc)) from None
        step = replace(step, show=self.show(raw, settings), marks=self.marks(raw, step))
        step = self.try_values(step)
        self.article(step)
        step = replace(step, checks=self.checks(raw, step))
        for index, item in enumerate(step.try_this, start=1):
            if item.predict is not None and not any(c.after_try == index
                                                    for c in step.checks):
                raise self.error(f"try_this[{index - 1}].predict",
                                 "a prediction needs a check of its answer: a "
                                 f"[[steps.checks]] with after_try = {index}")
        self.step_number = self.step_title = None
        return step

    def show(self, raw: Mapping, settings: Settings) -> tuple[tuple[str, Any], ...]:
        """The ``[steps.show]`` table: each field checked by its OverlayState spec and
        against the step's settings (``overlay_params.check_show``)."""
        table = raw.get("show", {})
        if not isinstance(table, Mapping):
            raise self.error("show", f"must be a table of overlay fields, got "
                                     f"{type(table).__name__}")
        from explorer.overlay_params import check_show

        try:
            return tuple(check_show(table, settings).items())
        except SettingError as exc:
            raise self.error(f"show.{exc.field}", str(exc)) from None

    def marks(self, raw: Mapping, step: Step) -> tuple[Any, ...]:
        """The ``[[steps.marks]]`` tables (explorer/lessons/marks.py), each point inside
        the step's scene; ids unique within the step."""
        from explorer.lessons.marks import MarkError, parse_mark

        items = raw.get("marks", [])
        if not isinstance(items, list):
            raise self.error("marks", "must be a list of [[steps.marks]] tables")
        scene = self.loaded_scene(step.scene) if items else None
        bounds = None if scene is None else (tuple(scene.bounds_min), tuple(scene.bounds_max))
        marks = []
        for index, table in enumerate(items):
            try:
                mark = parse_mark(table, bounds, f"marks[{index}].")
            except MarkError as exc:
                raise self.error(exc.field, str(exc)) from None
            if any(other.id == mark.id for other in marks):
                raise self.error(f"marks[{index}].id", f"two marks of the step are called "
                                                       f"{mark.id!r}")
            marks.append(mark)
        return tuple(marks)

    def checks(self, raw: Mapping, step: Step) -> tuple[Any, ...]:
        """The ``[[steps.checks]]`` tables (explorer/lessons/checks.py): quantity names the
        step can read, a fixed operator, literal bounds."""
        from explorer.lessons.checks import CheckError, parse_check
        from explorer.lessons.live_values import lookup

        items = raw.get("checks", [])
        if not isinstance(items, list):
            raise self.error("checks", "must be a list of [[steps.checks]] tables")
        checks = []
        for index, table in enumerate(items):
            try:
                checks.append(parse_check(
                    table, lambda name: lookup(name, step.figure_ids, step.mark_ids),
                    len(step.try_this), step.compare is not None, f"checks[{index}]."))
            except CheckError as exc:
                raise self.error(exc.field, str(exc)) from None
        return tuple(checks)

    def formulas(self, raw: Mapping) -> tuple[str, ...]:
        names = raw.get("formulas", [])
        if not isinstance(names, list) or not all(isinstance(n, str) for n in names):
            raise self.error("formulas", "must be a list of derivation names (strings)")
        for index, name in enumerate(names):
            if self.check_formula is None:
                continue
            try:
                self.check_formula(name)
            except LookupError as exc:  # KeyError is a LookupError
                reason = exc.args[0] if exc.args else exc
                raise self.error(f"formulas[{index}]", f"unknown formula {name!r}: {reason}"
                                 ) from None
            except ValueError as exc:
                raise self.error(f"formulas[{index}]", f"unknown formula {name!r}: {exc}"
                                 ) from None
        return tuple(names)

    def corrections(self, table: Mapping) -> Corrections:
        """A preset name, or a table: ``preset`` (default corrected) and switches."""
        value = table["corrections"]
        if isinstance(value, str):
            value = {"preset": value}
        if not isinstance(value, Mapping):
            raise self.error("corrections", "must be a preset name or a table of switches, "
                                            f"got {type(value).__name__}")
        switches = {key: flag for key, flag in value.items() if key != "preset"}
        name = self.fields({"preset": value.get("preset", "corrected")}, _PRESET, (),
                           prefix="corrections.")["preset"]
        try:
            return from_dict(Corrections, switches, base=PRESETS[name])
        except SettingError as exc:
            raise self.error(f"corrections.{exc.field}", str(exc)) from None

    def setting_overrides(self, table: Mapping) -> dict[str, Any]:
        """The ``[settings]`` table: each value checked by its Settings field's spec."""
        raw = table.get("settings", {})
        if not isinstance(raw, Mapping):
            raise self.error("settings", f"must be a table, got {type(raw).__name__}")
        for key in OWN_KEYS:
            if key in raw:
                raise self.error(f"settings.{key}", f"set {key!r} as a key of the step or "
                                                    "lesson, not inside [settings]")
        try:
            return check_fields(Settings, raw)
        except SettingError as exc:
            raise self.error(f"settings.{exc.field}", str(exc)) from None

    def pair(self, raw: Mapping, key: str, names: tuple[str, str],
             field: str | None = None) -> tuple[Vec3, Vec3] | None:
        """``camera = {eye, target}`` or ``light = {position, target}`` as the Settings
        field of the same name checks it (finite, two different points); ``field``: the
        name errors give (default ``key``)."""
        if key not in raw:
            return None
        field = field or key
        table = raw[key]
        if not isinstance(table, Mapping) or sorted(table) != sorted(names):
            raise self.error(field, f"must be a table with exactly {list(names)}, got "
                                    f"{table!r}")
        try:
            return specs(Settings)[key].check(key, (table[names[0]], table[names[1]]))
        except SettingError as exc:
            raise self.error(field, f"{exc} ({names[0]}, {names[1]})") from None

    def try_this(self, raw: Mapping) -> tuple[TryThis, ...]:
        items = raw.get("try_this", [])
        if not isinstance(items, list):
            raise self.error("try_this", "must be a list of {control, prompt, value} tables")
        declared = {"control": Spec(kind="choice", choices=valid_controls(),
                                    doc="A Settings field or corrections.<switch>."),
                    "prompt": Spec(kind="str", doc="What to change and look for."),
                    "compare": Spec(kind="choice", choices=TRY_COMPARES,
                                    doc="How the change is shown beside the step."),
                    "split": Spec(kind="bool", doc="Show the step | the change side by side."),
                    "label": Spec(kind="text", doc="The button's text (default: the change).")}
        result = []
        for index, item in enumerate(items):
            if not isinstance(item, Mapping):
                raise self.error(f"try_this[{index}]", "must be a {control, prompt} table")
            prefix = f"try_this[{index}]."
            required = ("control", "prompt") + (() if "values" in item else ("value",))
            own = self.fields(item, declared, tuple(k for k in TRY_KEYS if k not in declared),
                              required, prefix=prefix)
            compare = self.try_compare(own, prefix)
            values = self.try_variants(item, compare, prefix)
            camera = self.pair(item, "camera", _CAMERA_KEYS, f"try_this[{index}].camera")
            if camera is not None and compare != "apply":
                raise self.error(f"try_this[{index}].camera", f"a {compare} try-this shows "
                                 "every side from the step's camera; drop the camera or the "
                                 "comparison")
            if camera is not None and own["control"] == "camera":
                raise self.error(f"try_this[{index}].camera", "the control is the camera "
                                 "already: give the new camera as its value")
            result.append(TryThis(control=own["control"], prompt=own["prompt"],
                                  value=values[0] if values else item["value"],
                                  compare=compare, values=values,
                                  label=own.get("label", ""), camera=camera,
                                  predict=self.prediction(item, f"try_this[{index}].predict")))
        return tuple(result)

    def try_compare(self, own: Mapping, prefix: str) -> str:
        """A try-this's comparison mode: ``compare``, or ``split = true`` (the older
        spelling of ``compare = "split"``), else ``apply``."""
        if "split" in own and "compare" in own:
            raise self.error(prefix + "split", 'split = true is compare = "split": give '
                                               "compare alone")
        if own.get("split", False):
            return "split"
        return own.get("compare", "apply")

    def try_variants(self, item: Mapping, compare: str, prefix: str) -> tuple[Any, ...]:
        """A small-multiples try-this's ``values`` (2 to MAX_VARIANTS of them, in place of
        ``value``); () for the other modes, which show one value."""
        if "values" not in item:
            if compare == "small-multiples":
                raise self.error(prefix + "values", "small multiples show several values: "
                                 f"give values = [...] (2 to {MAX_VARIANTS}) in place of "
                                 "value")
            return ()
        values = item["values"]
        if compare != "small-multiples":
            raise self.error(prefix + "values", 'several values need compare = '
                             f'"small-multiples" (this try-this is {compare!r}); give one '
                             "value")
        if "value" in item:
            raise self.error(prefix + "value", "give values alone (the first is the "
                                               "button's)")
        if not isinstance(values, list) or not 2 <= len(values) <= MAX_VARIANTS:
            raise self.error(prefix + "values", f"must be a list of 2 to {MAX_VARIANTS} "
                                                f"values; got {values!r}")
        return tuple(values)

    def prediction(self, item: Mapping, field: str) -> Prediction | None:
        table = item.get("predict")
        if table is None:
            return None
        if not isinstance(table, Mapping) or set(table) != set(PREDICT_KEYS):
            raise self.error(field, "must be a table {question, choices, answer}")
        question, choices, answer = table["question"], table["choices"], table["answer"]
        if not isinstance(question, str) or not question.strip():
            raise self.error(field + ".question", "must be the question in words")
        if (not isinstance(choices, list) or not 2 <= len(choices) <= 4
                or not all(isinstance(c, str) and c.strip() for c in choices)
                or len(set(choices)) != len(choices)):
            raise self.error(field + ".choices", "must be two to four different answers")
        if isinstance(answer, bool) or not isinstance(answer, int) or \
                not 1 <= answer <= len(choices):
            raise self.error(field + ".answer", f"must be the number of the right choice, "
                                                f"1..{len(choices)}; got {answer!r}")
        return Prediction(question.strip(), tuple(c.strip() for c in choices), answer)

    # --- the article: try-this values, figures, markers and live numbers ----------------
    # (new keys of the explorable lessons; explorer/lessons/text.py and live_values.py)

    def try_values(self, step: Step) -> Step:
        """``step`` with each try-this value (each of a small multiples' values) checked
        against the settings schema on top of the step's settings (and normalised: TOML
        lists become tuples)."""
        base = step.settings()
        checked = []
        for index, item in enumerate(step.try_this):
            many = bool(item.values)
            values = []
            for number, raw_value in enumerate(item.variants):
                field = f"try_this[{index}].values[{number}]" if many \
                    else f"try_this[{index}].value"
                value = self.try_value(item, raw_value, base, field)
                if value in values:
                    raise self.error(field, f"{value!r} is shown twice: give each view its "
                                            "own value")
                values.append(value)
            checked.append(replace(item, value=values[0],
                                   values=tuple(values) if many else ()))
        return replace(step, try_this=tuple(checked))

    def try_value(self, item: TryThis, raw_value: Any, base: Settings, field: str) -> Any:
        """One value of ``item`` checked against the settings schema on top of ``base``;
        it must change something."""
        from explorer.schema import SettingError

        if item.control == "corrections":
            if isinstance(raw_value, Mapping):     # a preset with switches changed
                value = self.corrections({"corrections": raw_value})
            elif isinstance(raw_value, str) and raw_value in PRESETS:
                value = raw_value
            else:
                raise self.error(field, f"a corrections preset, one of {list(PRESETS)}, "
                                        f"or a table of switches; got {raw_value!r}")
        elif item.control.startswith("corrections."):
            if not isinstance(raw_value, bool):
                raise self.error(field, f"{item.control} is a switch: true or false, got "
                                        f"{raw_value!r}")
            value = raw_value
        else:
            try:
                value = getattr(Settings.from_dict({item.control: raw_value}, base),
                                item.control)
            except (SettingError, ValueError, TypeError) as exc:
                raise self.error(field, str(exc)) from None
        try:
            after = item.apply(base, value)
        except (ValueError, TypeError) as exc:
            raise self.error(field, str(exc)) from None
        if after == base:
            raise self.error(field, f"{item.control} is already {value!r} in this step: "
                                    "the button would change nothing")
        return value

    def figures(self, raw: Mapping) -> tuple[Any, ...]:
        items = raw.get("figures", [])
        if not isinstance(items, list):
            raise self.error("figures", "must be a list of [[steps.figures]] tables")
        if not items:
            return ()
        from explorer.figure_params import FigureParamError, parse_figure

        specs = []
        for index, table in enumerate(items):
            try:
                specs.append(parse_figure(table, f"figures[{index}]."))
            except (FigureParamError, ValueError) as exc:
                raise self.error(getattr(exc, "field", f"figures[{index}]"), str(exc)
                                 ) from None
        ids = [spec.instance_id for spec in specs]
        for index, name in enumerate(ids):
            if ids.index(name) != index:
                raise self.error(f"figures[{index}].id", f"two figures of the step are "
                                 f"called {name!r}; give each its own id")
        return tuple(specs)

    # complexity: one check per marker kind of a step's text, in reading order
    def article(self, step: Step) -> None:  # noqa: C901
        """Every marker and live number of the step's text, prompts and figure captions
        resolves: figures and try-this entries exist, formulas are derivation results,
        quantities are known and their formats apply."""
        import explorer.lessons.live_values as live_values
        import explorer.lessons.text as lesson_text

        try:
            blocks = lesson_text.parse(step.text)
        except lesson_text.TextError as exc:
            raise self.error("text", str(exc)) from None
        if len(step.text) > MAX_STEP_TEXT:
            raise self.error("text", f"{len(step.text)} characters, over the "
                             f"{MAX_STEP_TEXT} one step may have (the window draws a step's "
                             f"whole article every frame: split the step)")
        formulas = sum(isinstance(item, (lesson_text.Math, lesson_text.DisplayMath,
                                         lesson_text.FormulaRef))
                       for item in [*blocks, *lesson_text.all_runs(blocks)])
        if formulas > MAX_FORMULAS_PER_STEP:
            raise self.error("text", f"{formulas} formulas in one step, over the "
                             f"{MAX_FORMULAS_PER_STEP} a step may typeset (split the step)")
        # the site's side of every variant holds markers too: check both sides
        try:
            blocks = blocks + lesson_text.parse(step.text, "web")
        except lesson_text.TextError as exc:
            raise self.error("text", f"on the web page's side: {exc}") from None
        for block in blocks:
            if isinstance(block, lesson_text.FigureRef) and block.id not in step.figure_ids:
                raise self.error("text", f"{{{{figure:{block.id}}}}}: the step has no figure "
                                 f"with that id (its figures: {list(step.figure_ids)})")
            if isinstance(block, lesson_text.FormulaRef) and self.check_formula is not None:
                try:
                    self.check_formula(block.name)
                except (LookupError, ValueError) as exc:
                    reason = exc.args[0] if exc.args else exc
                    raise self.error("text", f"{{{{formula:{block.name}}}}}: {reason}"
                                     ) from None
        for run in lesson_text.all_runs(blocks):
            if isinstance(run, lesson_text.FigureNumber) and run.id not in (
                    "view", *step.figure_ids):
                raise self.error("text", f"{{{{fig:{run.id}}}}}: the step has no figure "
                                 f"with that id (its figures: {['view', *step.figure_ids]})")
            if isinstance(run, lesson_text.TryButton) and not (
                    1 <= run.index <= len(step.try_this)):
                raise self.error("text", f"{{{{try:{run.index}}}}}: the step has "
                                 f"{len(step.try_this)} try-this entries")
        for index, item in enumerate(step.try_this):
            for field, text in ((f"try_this[{index}].prompt", item.prompt),
                                (f"try_this[{index}].label", item.label)):
                for medium in lesson_text.MEDIA:
                    try:
                        blocks = lesson_text.parse(text, medium)
                    except lesson_text.TextError as exc:
                        raise self.error(field, str(exc)) from None
                    if len(blocks) > 1 or any(not isinstance(b, lesson_text.Paragraph)
                                              for b in blocks):
                        raise self.error(field, "must be one paragraph of text (no lists, "
                                                "display math, tables or markers)")
        texts = [("text", step.text)] + [
            (f"try_this[{i}].prompt", item.prompt) for i, item in enumerate(step.try_this)
        ] + [(f"figures[{i}].caption", spec.caption) for i, spec in enumerate(step.figures)]
        for field, text in texts:
            for name, fmt in lesson_text.placeholders(text):
                try:
                    quantity = live_values.lookup(name, step.figure_ids, step.mark_ids)
                    live_values.check_format(fmt, quantity)
                except KeyError as exc:
                    raise self.error(field, f"{{{{{name}}}}}: {exc.args[0]}") from None
                except ValueError as exc:
                    raise self.error(field, f"{{{{{name}:{fmt}}}}}: {exc}") from None


_PRESET = {"preset": Spec(kind="choice", choices=tuple(PRESETS),
                          doc="The preset a corrections table starts from.")}
