"""The text flow keeps a paragraph's measured boxes and lines (explorer/ui/textflow.py):
a step's text is measured once, not every frame, and again only when what it shows
changes (a live number's text, the width)."""

from __future__ import annotations

import pytest

from explorer.lessons import text as lt
from explorer.ui import textflow
from explorer.ui.textflow import Page, PageEnv


@pytest.fixture
def page(monkeypatch):
    from imgui_bundle import imgui

    context = imgui.create_context()
    measured: list[str] = []

    def text_width(self, text: str, style: str) -> float:
        measured.append(text)
        return 10.0 * len(text)

    monkeypatch.setattr(Page, "text_width", text_width)
    monkeypatch.setattr(textflow, "_BOXES", {})
    monkeypatch.setattr(textflow, "_LINES", {})
    values = {"flux": "1.25"}
    env = PageEnv(value=lambda name, fmt: (values[name], f"the {name}"))
    try:
        yield Page(env, 200.0), measured, values
    finally:
        imgui.destroy_context(context)


RUNS = (lt.Text("the light's flux is "), lt.Value("flux", ".2f"), lt.Text(" watts, so"))


def test_a_paragraph_is_measured_once_while_it_shows_the_same(page):
    flow, measured, _ = page
    first = flow.lines(RUNS, 0.0, 12.0, 4.0)
    count = len(measured)
    assert count > 0
    again = flow.lines(RUNS, 0.0, 12.0, 4.0)
    assert again is first and len(measured) == count      # nothing measured again
    assert [box.payload[0] for line in first for box in line.boxes][:3] == \
        ["the", "light's", "flux"]


def test_a_changed_live_number_or_width_lays_it_out_again(page):
    flow, measured, values = page
    before = flow.lines(RUNS, 0.0, 12.0, 4.0)
    values["flux"] = "12.50"
    after = flow.lines(RUNS, 0.0, 12.0, 4.0)
    assert after is not before
    assert "12.50" in [box.payload[0] for line in after for box in line.boxes]
    # a narrower column (an indented item): its own lines, the wider one's untouched
    xs = [box.x for line in after for box in line.boxes]
    narrow = flow.lines(RUNS, 80.0, 12.0, 4.0)
    assert len(narrow) > len(after)
    assert [box.x for line in after for box in line.boxes] == xs
