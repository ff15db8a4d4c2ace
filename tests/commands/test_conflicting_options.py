"""An option given twice with different values, and options that contradict each other,
are one line and exit 2 naming both (argparse alone keeps the last silently); a setting
given while the settings switch it off by default is a warning saying so."""

from __future__ import annotations

import re

import pytest

from explorer.cli import main

REFUSED = [
    ("render --grid 8 --grid 16", "--grid 8 and --grid 16 both given"),
    ("render --grid=8 --grid 16", "--grid 8 and --grid 16 both given"),
    ("render --preset original --preset corrected",
     "--preset original and --preset corrected both given"),
    ("render --fog --no-fog", "--fog and --no-fog both given"),
    ("export-mitsuba cornell a.xml --size 8x8 --size 16x16", "--size 8x8 and --size 16x16"),
    ("compare --preset all --preset original", "--preset all and --preset original"),
    ("run --scene cornell --scene room", "--scene cornell and --scene room"),
    ("render --no-spot-cone --cone-angles 20,30",
     "--no-spot-cone and --cone-angles contradict each other"),
    ("render --no-fog --fog-density 0.2 --fog-steps 8",
     "--no-fog and --fog-density, --fog-steps contradict each other"),
    ("render --fog --fog-phase isotropic --fog-g 0.4",
     "--fog-phase isotropic and --fog-g contradict each other"),
    ("render --no-glossy --glossy-roughness 0.3", "--no-glossy and --glossy-roughness"),
    ("render --downsample none --downsample-factor 4",
     "--downsample none and --downsample-factor"),
    ("render --cascades 1 --cascade-focus 0.5", "--cascades 1 and --cascade-focus"),
    ("render --slice 3", "--slice only acts with a grid view"),
    ("render --view geometry-volume --coefficient 0", "--coefficient only acts with --view "
     "grid-slice"),
    ("bench --soak 1 --interactive", "--interactive and --soak each choose a different run"),
    ("bench --overhead --soak 1", "--overhead and --soak each choose a different run"),
    ("bench --soak 1 --grid 8", "--grid only acts with the timing bench"),
    ("bench --root .", "--root only acts with --interactive, --soak or --units"),
    ("run --no-wait", "--no-wait only acts with --screenshot"),
    ("lessons --check a --check b", "--check a and --check b both given"),
    ("lessons --lint --lint b", "--lint and --lint b both given"),
]


@pytest.mark.parametrize("command, message", REFUSED, ids=[c for c, _ in REFUSED])
def test_contradictions_are_one_line_and_exit_2(tmp_path, monkeypatch, capsys, command,
                                                message):
    monkeypatch.chdir(tmp_path)
    assert main(command.split()) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and message in err, err
    assert list(tmp_path.iterdir()) == [], "a refused command wrote something"


def test_the_same_value_twice_is_no_contradiction(tmp_path, capsys):
    out = tmp_path / "a.xml"
    assert main(["export-mitsuba", "cornell", str(out), "--size", "8x8", "--size", "8x8"]) == 0
    assert out.is_file()


def test_a_setting_whose_switch_is_off_by_default_is_a_warning_naming_both(tmp_path, capsys):
    out = tmp_path / "a.png"
    assert main(["render", "--out", str(out), "--grid", "8", "--rsm-size", "32", "--size",
                 "32x32", "--iterations", "2", "--fog-density", "0.2"]) == 0
    err = capsys.readouterr().err
    assert "warning: --fog-density has no effect: the settings have --no-fog; add --fog to " \
           "use it" in err


def test_help_texts_say_nothing_a_command_line_cannot_take():
    """No help text offers None (leaving the option out is how) or shows a stray %, and
    every option taking a value names it with a placeholder of its own (N, X, FILE.json),
    not argparse's upper-cased option name (``--peak-gbs PEAK_GBS``)."""
    from explorer.cli import build_parser

    parser = build_parser()
    for name, command in parser.command_parsers.items():
        text = command.format_help()
        assert "None" not in text, f"{name}: a help text offers None"
        assert "%" not in text, f"{name}: a stray % in a help text"
        lower = [m.group(0) for action in command._actions
                 if action.help and action.help != "==SUPPRESS=="
                 for m in re.finditer(r"\S+[.!?][\"”)]? [a-z]\w*", " ".join(action.help.split()))
                 if not m.group(0).startswith(("e.g.", "i.e.", "(e.g.", "(i.e."))]
        assert lower == [], f"{name}: a sentence starting in lower case: {lower}"
        unnamed = [action.option_strings[0] for action in command._actions
                   if action.option_strings and action.nargs != 0 and action.metavar is None
                   and action.choices is None and action.help != "==SUPPRESS=="]
        assert unnamed == [], f"{name}: options without a placeholder: {unnamed}"


def test_compare_size_and_width_together_are_refused(capsys):
    assert main(["compare", "--size", "64x64", "--width", "32"]) == 2
    assert "--size and --width both set the image size" in capsys.readouterr().err
