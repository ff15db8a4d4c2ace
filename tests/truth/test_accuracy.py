"""Accuracy regression: the small configurations of docs/ERRORS.md (LPV against the
one-bounce reference through ``lpv-explorer compare``) re-run and held to the values
recorded in docs/errors-measured.json, and docs/ERRORS.md's tables are what that file
renders (explorer/commands/tables.py)."""

from __future__ import annotations

import json

import pytest

from explorer.commands import tables

DATA = tables.load()
SMALL = tables.names_of(DATA, "small")
BAND = float(DATA["band"]["relative"])


@pytest.fixture(scope="module")
def fresh(gl_context):
    return tables.measure(DATA, SMALL, ctx=gl_context)


@pytest.mark.parametrize("name", SMALL)
def test_small_configuration_keeps_its_recorded_accuracy(fresh, name):
    """Relative L2, RMSE and the flux ratios (whole and per channel) of every row within
    ±BAND (relative) of the recorded value. Repeated runs on llvmpipe are bit-identical
    (the data file's band.why), so anything outside the band is a change in a pass, the
    reference or the metrics; re-measure with ``python -m explorer.commands.tables --measure
    small`` once the change is understood."""
    recorded = DATA["tables"][name]["rows"]
    assert recorded, f"{name} has no recorded rows"
    problems = tables.differences(name, recorded, fresh[name].rows, BAND)
    assert not problems, "\n".join(problems)


def test_the_band_is_narrower_than_a_one_percent_change(fresh):
    rows = fresh["small-cornell"].rows
    brighter = [dict(row, flux_ratio=1.01 * row["flux_ratio"]) for row in rows]
    assert len(tables.differences("small-cornell", rows, brighter, BAND)) == len(rows)
    assert 100 * BAND <= 0.01


def test_errors_md_shows_the_recorded_tables():
    assert tables.document_differences(tables.DOCUMENT.read_text(encoding="utf-8"), DATA) \
        == []
    for name, table in DATA["tables"].items():
        assert table["rows"], f"{name} was never measured"


def test_check_reports_a_table_edited_by_hand_and_a_drifted_value(tmp_path, gl_context,
                                                                  capsys):
    """``--check`` on a copy holding one small table: clean, then with a table cell typed
    over in the document (exit 1), then with a recorded value 1 % off (exit 1)."""
    name = "small-room-bounces"
    data = dict(DATA, tables={name: DATA["tables"][name]})
    document = tmp_path / "ERRORS.md"
    data_file = tmp_path / "errors.json"
    tables.save(data, data_file)
    document.write_text("intro\n\n" + tables.render_document(
        f"{tables.marker(name)}\n<!-- end measured -->\n", data), encoding="utf-8")
    arguments = ["--check", "--data", str(data_file), "--document", str(document)]
    assert tables.main(arguments) == 0
    assert "within" in capsys.readouterr().out

    text = document.read_text(encoding="utf-8")
    row = data["tables"][name]["rows"][0]
    typed = f"{row['relative_l2']:.3f}"
    document.write_text(text.replace(typed, "0.123", 1), encoding="utf-8")
    assert tables.main(arguments) == 1
    assert f"table {name!r} is not the data file's" in capsys.readouterr().out

    document.write_text(text, encoding="utf-8")
    drifted = json.loads(json.dumps(data))
    drifted["tables"][name]["rows"][0]["flux_ratio"] *= 1.01
    tables.save(drifted, data_file)
    document.write_text(tables.render_document(text, drifted), encoding="utf-8")
    assert tables.main(arguments) == 1
    assert "flux_ratio recorded" in capsys.readouterr().out


def test_document_and_data_file_must_name_the_same_tables():
    name = SMALL[0]
    with pytest.raises(ValueError, match="tables without a block"):
        tables.render_document("no blocks here\n", dict(DATA, tables={name: DATA["tables"][name]}))
    with pytest.raises(ValueError, match="blocks of no table: nope"):
        tables.render_document(f"{tables.marker('nope')}\n<!-- end measured -->\n",
                               dict(DATA, tables={}))


README_SOURCES = {
    ("cornell", "—"): ("cornell-visible", {}),
    ("room", "—"): ("room-visible", {}),
    ("cornell", "one-sided geometry volume"): ("bounces-cornell",
                                               {"variant": "one-sided, bounces 1"}),
    ("room", "one-sided geometry volume"): ("bounces-room", {"variant": "one-sided, bounces 1"}),
}
"""Where each row of the README's accuracy table comes from: (scene, variant) -> (table,
run labels)."""


def test_readme_accuracy_table_quotes_the_recorded_values():
    """Each "relative L2 / flux ratio" cell of README.md's "How accurate is LPV" table is the
    recorded row of that scene, preset and iteration count ("same": equal to the 4-iteration
    cell), so re-measuring shows a stale README here."""
    text = (tables.ROOT / "README.md").read_text(encoding="utf-8")
    section = text[text.index("## How accurate is LPV"):text.index("## Benchmarks")]
    lines = [line for line in section.splitlines()
             if line.startswith(("| cornell |", "| room |"))]
    assert len(lines) == len(README_SOURCES) + 2   # + the two "original" rows
    for line in lines:
        scene, preset, variant, *cells = [c.strip() for c in line.strip().strip("|").split("|")]
        name, labels = README_SOURCES[(scene, variant)]
        rows = DATA["tables"][name]["rows"]
        first = None
        for iterations, cell in zip((4, 8, 16), cells):
            row, = [r for r in rows if r["labels"] == labels and r["preset"] == preset
                    and r["iterations"] == iterations and r["region"] == "image"]
            recorded = f"{row['relative_l2']:.3f} / {row['flux_ratio']:.3f}"
            first = first or recorded
            if cell == "same":
                assert recorded == first, (line, iterations)
            else:
                assert cell.replace("**", "") == recorded, (line, iterations)


def test_readme_accuracy_table_prints_the_commands_that_measured_it():
    """Beside the table, for each of its rows, the compare command line recorded for that
    row's run (the Cornell rows need --no-spot-cone: without it they do not reproduce)."""
    text = (tables.ROOT / "README.md").read_text(encoding="utf-8")
    section = text[text.index("## How accurate is LPV"):text.index("## Benchmarks")]
    commands = {line.strip() for line in section.splitlines()
                if line.startswith("lpv-explorer compare ")}
    for (scene, variant), (name, labels) in README_SOURCES.items():
        runs = [run["args"] for run in DATA["tables"][name]["runs"]
                if run.get("labels", {}) == labels
                and "--preset original" not in run["args"]]
        assert runs, (scene, variant)
        for args in runs:
            assert f"lpv-explorer compare {args}" in commands, (scene, variant, args)
    assert all("--no-spot-cone" in line for line in commands if "cornell" in line)
