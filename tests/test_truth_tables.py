"""docs/ERRORS.md's tables against physics: the page is the data file, and a fresh run of
the small table prints the recorded digits (Mitsuba ``scalar_rgb`` with fixed seeds and
the LPV on llvmpipe are deterministic). Skipped with the reason without Mitsuba."""

from __future__ import annotations

import pytest

from explorer.commands import truth_tables
from explorer.truth.mitsuba_render import mitsuba_available


def test_errors_page_is_the_physics_data_file():
    data = truth_tables.load()
    text = truth_tables.DOCUMENT.read_text(encoding="utf-8")
    assert truth_tables.render_document(text, data) == text
    assert {"physics-cornell", "physics-room", "physics-two-rooms", "physics-atrium",
            "physics-small-cornell"} <= set(data["tables"])


@pytest.mark.skipif(mitsuba_available() is not None, reason=str(mitsuba_available()))
def test_small_physics_table_holds_to_its_printed_digits(gl_context):
    data = truth_tables.load()
    name = "physics-small-cornell"
    fresh = truth_tables.measure_table(data["tables"][name], gl_context)
    assert truth_tables.printed_differences(name, data["tables"][name], fresh) == []
