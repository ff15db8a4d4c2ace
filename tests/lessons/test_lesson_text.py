"""Lesson prose: the parser (blocks, runs, markers, live numbers, tables) and the text
flow's line breaking, without a window."""

from __future__ import annotations

import pytest

from explorer.lessons import text as lt
from explorer.ui.textflow import Box, column_widths, layout, words


def test_paragraphs_items_and_display_math():
    blocks = lt.parse("First **bold** and *it*\nline.\n\n* one `code`\n  more\n"
                      "2. two $x^2$\n\n$$E = mc^2$$\n\nafter")
    kinds = [type(b).__name__ for b in blocks]
    assert kinds == ["Paragraph", "Item", "Item", "DisplayMath", "Paragraph"]
    assert blocks[0].runs == (lt.Text("First "), lt.Text("bold", "bold"), lt.Text(" and "),
                              lt.Text("it", "italic"), lt.Text(" line."))
    assert blocks[1].marker == "•" and lt.Text("code", "code") in blocks[1].runs
    assert blocks[1].runs[-1] == lt.Text(" more")
    assert blocks[2].marker == "2." and blocks[2].runs[-1] == lt.Math("x^2")
    assert blocks[3] == lt.DisplayMath("E = mc^2")


def test_display_math_splits_a_paragraph_and_spans_lines():
    blocks = lt.parse("before\n$$a =\n\n b$$\nafter $y$.")
    assert blocks == (lt.Paragraph((lt.Text("before"),)), lt.DisplayMath("a = b"),
                      lt.Paragraph((lt.Text("after "), lt.Math("y"), lt.Text("."))))
    # inside a list item too: the item keeps its text, the formula follows it
    blocks = lt.parse("1. **Cosine.** It is\n   $$E = s/h^2$$\n2. next")
    assert [type(b).__name__ for b in blocks] == ["Item", "DisplayMath", "Item"]
    # a figure marker inside a paragraph splits it
    blocks = lt.parse("see {{figure:lobe}} here")
    assert blocks == (lt.Paragraph((lt.Text("see"),)), lt.FigureRef("lobe"),
                      lt.Paragraph((lt.Text("here"),)))


def test_live_numbers_markers_and_placeholders_in_math():
    text = ("Flux {{audit.injected:.3g}} W, **{{settings.grid_size}}** cells {{try:2}}\n\n"
            "{{figure:lobe}}\n\n{{formula:sh.c0}}\n\n$c_0 = {{derived.sh.c0:.4f}}$")
    blocks = lt.parse(text)
    runs = blocks[0].runs
    assert lt.Value("audit.injected", ".3g") in runs
    assert lt.Value("settings.grid_size", "", "bold") in runs
    assert lt.TryButton(2) in runs
    assert blocks[1] == lt.FigureRef("lobe") and blocks[2] == lt.FormulaRef("sh.c0")
    assert blocks[3].runs[0] == lt.Math("c_0 = {{derived.sh.c0:.4f}}")
    assert lt.placeholders(text) == [("audit.injected", ".3g"), ("settings.grid_size", ""),
                                     ("derived.sh.c0", ".4f")]
    filled = lt.substitute(blocks[3].runs[0].latex, lambda name, fmt: f"<{name}|{fmt}>")
    assert lt.parse("mode `{{settings.downsample}}` on")[0].runs == (
        lt.Text("mode "), lt.Value("settings.downsample", "", "code"), lt.Text(" on"))
    assert filled == "c_0 = <derived.sh.c0|.4f>"


def test_tables():
    blocks = lt.parse("| | A | B |\n|---|:---:|---|\n| row | **x** | $y$ |\n\nafter")
    table = blocks[0]
    assert isinstance(table, lt.Table) and len(table.header) == 3 and len(table.rows) == 1
    assert table.rows[0][1] == (lt.Text("x", "bold"),) and table.rows[0][2] == (lt.Math("y"),)
    assert isinstance(blocks[1], lt.Paragraph)
    assert lt.Math("y") in lt.all_runs(blocks)


@pytest.mark.parametrize("text, message", [
    ("a $x", "unclosed \\$"),
    ("a **b", "unclosed \\*\\*"),
    ("a {{audit.injected", "unclosed \\{\\{"),
    ("{{try:x}}", "try-this number"),
    ("$$a = b", "not closed"),
    ("| a | b |\n| c | d |", "rule under it"),
    ("| a | b |\n|---|---|\n| c |", "1 cells, the header 2"),
])
def test_bad_prose_is_refused(text, message):
    with pytest.raises(lt.TextError, match=message):
        lt.parse(text)


def test_words_keep_their_spaces():
    assert words("a b,  c") == [("a", True), ("b,", True), ("c", False)]
    assert words(" is") == [("", True), ("is", False)]


def _boxes(widths, spaces=None, glue=()):
    spaces = spaces or [2.0] * len(widths)
    return [Box(w, 10.0, 3.0, "text", i, space=s, glue=i in glue)
            for i, (w, s) in enumerate(zip(widths, spaces))]


def test_layout_breaks_lines_in_order_within_the_column():
    boxes = _boxes([10, 20, 15, 30, 5, 25])
    lines = layout(boxes, 40.0)
    order = [b.payload for line in lines for b in line.boxes]
    assert order == list(range(6))
    for line in lines:
        last = line.boxes[-1]
        assert last.x + last.width <= 40.0 or len(line.boxes) == 1
    assert [b.payload for b in lines[0].boxes] == [0, 1]
    # a box wider than the column gets a line of its own
    lines = layout(_boxes([10, 60, 10]), 40.0)
    assert [[b.payload for b in line.boxes] for line in lines] == [[0], [1], [2]]


def test_glued_boxes_move_to_the_next_line_together():
    # "x" + "," glued: the comma never starts a line on its own
    boxes = _boxes([12, 12, 12, 4], spaces=[2, 2, 0, 2], glue=(3,))
    lines = layout(boxes, 40.0)
    assert [[b.payload for b in line.boxes] for line in lines] == [[0, 1], [2, 3]]


def test_lines_share_one_baseline():
    boxes = [Box(10, 10, 3, "text", 0, 2.0), Box(10, 18, 6, "math", 1, 2.0),
             Box(10, 10, 3, "text", 2, 2.0)]
    lines = layout(boxes, 100.0, min_ascent=12.0, min_descent=4.0, leading=2.0)
    assert len(lines) == 1 and lines[0].ascent == 18.0 and lines[0].descent == 6.0
    lines = layout(boxes, 12.0, min_ascent=12.0, min_descent=4.0, leading=2.0)
    assert [line.y for line in lines] == [0.0, 16.0 + 2.0, 18.0 + 24.0 + 2.0]


def test_table_columns_are_at_least_as_wide_as_their_widest_word():
    # room to spare: the weights share the width
    assert column_widths([10.0, 10.0], [1.0, 3.0], 100.0) == [25.0, 75.0]
    # a column whose share is narrower than its widest word ("Screen-space" in lesson
    # 14) gets that word's width; the others share what is left by their weights
    widths = column_widths([10.0, 10.0, 90.0], [0.5, 1.0, 1.0], 200.0)
    assert widths == [pytest.approx(110 / 3), pytest.approx(220 / 3), 90.0]
    assert sum(widths) == pytest.approx(200.0)
    # fixing one column can push another below its word: that one is fixed too
    widths = column_widths([60.0, 60.0, 10.0], [1.0, 1.0, 4.0], 180.0)
    assert widths == [60.0, 60.0, pytest.approx(60.0)]
    # the words do not fit at all: shared in proportion to them
    assert column_widths([60.0, 180.0], [1.0, 1.0], 120.0) == [30.0, 90.0]
    assert all(w >= m for w, m in zip(column_widths([5.0, 70.0, 5.0, 70.0],
                                                   [0.7, 1.0, 1.0, 1.0], 160.0),
                                      [5.0, 70.0, 5.0, 70.0]))


def test_a_variant_reads_one_way_in_the_window_and_another_on_the_site():
    text = ("Open {{window}}the **Inspect** panel{{web}}the picture below, "
            "{{audit.injected:.3f}} W{{end}}.\n\n{{web}}On the site only.{{end}}"
            "{{window}}In the window only.{{end}}")
    window, web = lt.parse(text), lt.parse(text, "web")
    assert lt.runs_text(window[0].runs) == "Open the Inspect panel."
    assert [lt.runs_text(b.runs) for b in window[1:]] == ["In the window only."]
    assert web[0].runs == (lt.Text("Open the picture below, "), lt.Value("audit.injected", ".3f"),
                           lt.Text(" W."))
    assert [lt.runs_text(b.runs) for b in web[1:]] == ["On the site only."]
    # the live numbers of both sides are the text's numbers (the reader checks them all)
    assert lt.placeholders(text) == [("audit.injected", ".3f")]


@pytest.mark.parametrize("text", ["a {{web}} b", "a {{end}}", "{{window}}a{{web}}b{{web}}c{{end}}",
                                  "{{web}}a {{window}}b{{end}}"])
def test_a_broken_variant_is_refused(text):
    for medium in lt.MEDIA:
        with pytest.raises(lt.TextError, match="variant"):
            lt.parse(text, medium)


def test_a_figure_reference_is_a_number_on_the_site_and_words_in_the_window():
    text = "As {{fig:view}} and {{fig:lobe}} show."
    assert lt.runs_text(lt.parse(text)[0].runs) == "As the main view and the figure show."
    assert lt.parse(text, "web")[0].runs == (
        lt.Text("As "), lt.FigureNumber("view"), lt.Text(" and "), lt.FigureNumber("lobe"),
        lt.Text(" show."))
