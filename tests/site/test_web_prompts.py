"""Every lesson's try-this prompts as the page prints them, checked without a build: a
prompt sits beside a before/after pair, with no button to press again and no switch to
tick, so its web words name neither (the site test builds only two lessons)."""

from __future__ import annotations

import re

from explorer.lessons import load_all
from explorer.lessons.text import for_medium
from explorer.site.controls import PHRASES


def test_no_try_this_prompt_asks_the_web_reader_to_press_or_tick():
    found, _ = load_all()
    wrong = [f"{lesson.id} step {number} try {index}: {match.group(0)!r}"
             for lesson in found
             for number, step in enumerate(lesson.steps, 1)
             for index, trial in enumerate(step.try_this, 1)
             for name in ("press", "toggle")
             for match in re.finditer(PHRASES[name].pattern,
                                      for_medium(trial.prompt, "web"), re.I)]
    assert wrong == []
