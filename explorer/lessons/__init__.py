"""The course: lessons read from ``lessons/NN-slug.toml`` (data, never code), their prose,
the live numbers it quotes, the claims it checks and the terms it explains.

One job per module:

* :mod:`~explorer.lessons.model`: the dataclasses (:class:`Lesson`, :class:`Step`,
  :class:`TryThis`, :class:`Prediction`, :class:`LessonError`) and the limits and
  defaults every step shares;
* :mod:`~explorer.lessons.reader`: reading and checking lesson files (the file format is
  its docstring): :func:`load_lesson`, :func:`load_all`, :func:`find_lesson`;
* :mod:`~explorer.lessons.render`: a step's settings shrunk for quick renders and its view
  rendered (split and difference views included);
* :mod:`~explorer.lessons.text`: the markdown dialect of a step's text, parsed into blocks
  of styled runs;
* :mod:`~explorer.lessons.math_text`: inline math as plain Unicode text;
* :mod:`~explorer.lessons.live_values`: the ``{{name:format}}`` numbers, read from the
  frame on screen;
* :mod:`~explorer.lessons.marks`: labelled points a step places in its scene, and what
  they measure;
* :mod:`~explorer.lessons.checks`: a step's claims about its numbers, as data;
* :mod:`~explorer.lessons.verify`: those claims evaluated on the step's converged frames;
* :mod:`~explorer.lessons.glossary`: the recurring terms the article explains on hover;
* :mod:`~explorer.lessons.folder`: the course read, the shipped lessons and a folder of
  one's own (:class:`~explorer.lessons.folder.Course`);
* :mod:`~explorer.lessons.where`: the line of the key a :class:`LessonError` names;
* :mod:`~explorer.lessons.words`: what a learner reads is words and typeset math;
* :mod:`~explorer.lessons.template`: the lesson ``lessons new`` writes;
* :mod:`~explorer.lessons.guide`: the generated parts of docs/AUTHORING.md.

The names below are re-exported here (``from explorer.lessons import load_all, Step``);
the other modules are imported as submodules (``from explorer.lessons import
live_values``). Inside the package the modules import each other's submodules directly,
never this one.
"""

from explorer.lessons.math_text import MATH_COMMANDS, math_to_text
from explorer.lessons.model import (
    COMPARE_VIEWS,
    CORRECTIONS_TITLES,
    LESSON_DEFAULTS,
    MAX_FORMULAS_PER_STEP,
    MAX_STEP_TEXT,
    MAX_STEPS,
    SCENE_STATE,
    STEP_VIEWS,
    TRY_COMPARES,
    TRY_GRIDS,
    Lesson,
    LessonError,
    Prediction,
    Step,
    TryThis,
    Vec3,
)
from explorer.lessons.reader import FormulaCheck, find_lesson, load_all, load_lesson, valid_controls
from explorer.lessons.render import preview_settings, render_step, shrink_settings

__all__ = [
    "COMPARE_VIEWS", "CORRECTIONS_TITLES", "LESSON_DEFAULTS", "MATH_COMMANDS",
    "MAX_FORMULAS_PER_STEP", "MAX_STEPS", "MAX_STEP_TEXT", "SCENE_STATE", "STEP_VIEWS",
    "TRY_COMPARES", "TRY_GRIDS",
    "FormulaCheck", "Lesson", "LessonError", "Prediction", "Step", "TryThis", "Vec3",
    "find_lesson", "load_all", "load_lesson", "math_to_text", "preview_settings",
    "render_step", "shrink_settings", "valid_controls",
]
