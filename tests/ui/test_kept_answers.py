"""explorer/ui/kept_answers.py: an answer is made again exactly when one of its sources is
another object (frozen ones by identity) or another value (plain ones by value)."""

from __future__ import annotations

from explorer.lpv.settings import Settings
from explorer.ui.kept_answers import KeptAnswers


def test_an_answer_is_kept_while_its_sources_are_the_same_and_made_again_after():
    made = []
    kept = KeptAnswers(most=4)
    a, equal_a = Settings(), Settings()
    assert a == equal_a and a is not equal_a

    def answer(settings, width, changes):
        return kept.answer("A", (settings, width, changes),
                           lambda: made.append((settings, width)) or len(made))

    assert answer(a, 512, (("iterations", 4),)) == 1
    assert answer(a, 512, (("iterations", 4),)) == 1       # the same: kept
    assert answer(equal_a, 512, (("iterations", 4),)) == 2  # an equal, other object: made
    assert answer(equal_a, 640, (("iterations", 4),)) == 3  # another value
    assert answer(equal_a, 640, (("iterations", 8),)) == 4  # another tuple of changes
    assert answer(equal_a, 640.0, (("iterations", 8),)) == 5  # 640.0 is not the int 640
    assert len(made) == 5


def test_a_full_store_is_emptied_for_a_new_slot_and_keeps_its_own_slots_answer():
    kept = KeptAnswers(most=2)
    settings = Settings()
    for slot in ("A", "B"):
        kept.answer(slot, (settings,), lambda name=slot: name)
    assert len(kept) == 2
    assert kept.answer("A", (settings,), lambda: "again") == "A"   # a kept slot: no room needed
    assert kept.answer("C", (settings,), lambda: "C") == "C" and len(kept) == 1
    assert kept.answer("A", (settings,), lambda: "made anew") == "made anew"
