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


def test_readme_physics_table_is_the_data_file():
    """The README's summary table quotes docs/errors-physics.json to its digits."""
    import re

    data = truth_tables.load()
    readme = (truth_tables.ROOT / "README.md").read_text(encoding="utf-8")
    section = readme.split("**Against physics**", 1)[1].split("```", 1)[0]
    rows = [line for line in section.splitlines() if line.startswith("| ")
            and not line.startswith("| scene")]
    assert len(rows) == 3
    columns = (("reference (project)", "one-bounce"), ("corrected", "one-bounce"),
               ("geometry volume one-sided", "one-bounce"), ("corrected", "multi-bounce"))
    for line in rows:
        cells = [c.strip() for c in line.strip("|").split("|")]
        scene = cells[0].strip("`")
        table = {row["variant"]: row for row in data["tables"][f"physics-{scene}"]["rows"]}
        for cell, (variant, truth) in zip(cells[1:], columns):
            metrics = table[variant][truth]
            flux, l2 = re.fullmatch(r"([\d.]+) \(([\d.]+)\)", cell).groups()
            assert flux == f"{metrics['flux_ratio']:.3f}", (cells[0], variant, truth)
            assert l2 == f"{metrics['relative_l2']:.3f}", (cells[0], variant, truth)
