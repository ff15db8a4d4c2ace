"""Where the article opens, on the LessonSession alone: every step or
lesson change at the top, a lesson left for the list comes back at its step and scroll,
Next lesson starts the next lesson at its top."""

from __future__ import annotations

import pytest

from explorer.ui.lesson_panel import RESUME_FRAMES, LessonSession


@pytest.fixture(scope="module")
def lessons():
    session = LessonSession.load()
    assert not session.errors
    return session.lessons


def _session(lessons) -> LessonSession:
    return LessonSession(lessons=list(lessons))


def test_every_step_change_opens_at_the_top(lessons):
    session = _session(lessons)
    lesson = session.open(lessons[1].id)
    assert session.opening_scroll() == 0.0          # first drawn: its top
    assert session.opening_scroll() is None         # then it stays as the reader scrolls
    session.keep_scroll(240.0)
    session.next()
    assert session.opening_scroll() == 0.0
    session.keep_scroll(90.0)
    session.go(len(lesson.steps))
    assert session.opening_scroll() == 0.0
    session.previous()
    assert session.opening_scroll() == 0.0


def test_a_lesson_left_half_way_comes_back_at_its_step_and_scroll(lessons):
    session = _session(lessons)
    lesson = session.open(lessons[2].id, resume=True)
    session.opening_scroll()
    session.go(3)
    session.opening_scroll()
    session.keep_scroll(180.0)
    session.close()
    assert session.lesson is None
    other = session.open(lessons[0].id, resume=True)     # another lesson meanwhile
    assert session.step_number == 1 and session.opening_scroll() == 0.0
    session.close()
    assert session.open(lesson.id, resume=True) is lesson
    assert session.step_number == 3
    assert session.opening_scroll() == 180.0
    assert session.resume_frames == RESUME_FRAMES    # until the text's height is known
    assert other is not lesson


def test_next_lesson_opens_at_the_top_even_when_left_there_before(lessons):
    session = _session(lessons)
    session.open(lessons[1].id, resume=True)
    session.opening_scroll()
    session.keep_scroll(300.0)
    session.close()                                   # left at step 1, scrolled
    session.open(lessons[0].id)
    session.opening_scroll()
    session.go(len(lessons[0].steps))
    session.opening_scroll()
    session.keep_scroll(500.0)                        # the Next lesson button, at the end
    session.open(lessons[1].id)                       # Next lesson: not resumed
    session.keep_scroll(500.0)                        # the click's frame: old article
    assert session.step_number == 1
    assert session.opening_scroll() == 0.0


def test_the_scroll_of_a_frame_that_changed_the_step_is_not_kept(lessons):
    session = _session(lessons)
    session.open(lessons[3].id, resume=True)
    session.opening_scroll()
    session.keep_scroll(50.0)
    session.next()                                    # clicked in the article
    session.keep_scroll(700.0)                        # the same frame: not this step's
    session.close()
    assert session.places[lessons[3].id] == (2, 0.0)      # step 2 was never drawn
