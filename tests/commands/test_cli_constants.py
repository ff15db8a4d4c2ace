"""``lpv-explorer constants`` on good and bad input."""

from __future__ import annotations

import json

import sympy as sp

from explorer.cli import main


def run(capsys, *argv: str) -> tuple[int, str, str]:
    code = main(["constants", *argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_json_reproduces_the_twenty_digit_solid_angles(capsys):
    code, out, _ = run(capsys, "--json")
    assert code == 0
    entries = {e["name"]: e for e in json.loads(out)}
    assert entries["solid_angles.front_face"]["value"] == "0.40066968464623918538"
    assert entries["solid_angles.side_face"]["value"] == "0.42343135443673907673"
    # sympy's own 20-digit evaluation of the closed form gives the same digits.
    assert str(sp.N(sp.sympify(entries["solid_angles.side_face"]["closed_form"]), 20)) == \
        "0.42343135443673907673"
    formula = entries["corrections.injection_pi.corrected"]
    assert formula["value"] is None and "\\pi" in formula["latex"] and "=" in formula["latex"]


def test_one_name_by_registry_or_glsl_name(capsys):
    code, out, _ = run(capsys, "--json", "--name", "SIDE_FACE_SOLID_ANGLE")
    assert code == 0 and json.loads(out)["name"] == "solid_angles.side_face"
    code, out, _ = run(capsys, "--name", "propagation.step_flux_factor_original")
    assert code == 0
    assert "1/(4*pi)" in out and "\\frac{1}{4 \\pi}" in out and "0.0795774715459476678" in out


def test_unknown_name_exits_2_with_one_line_of_suggestions(capsys):
    code, out, err = run(capsys, "--name", "solid_angles.frontface")
    assert code == 2 and out == ""
    assert err.startswith("lpv-explorer constants: error: no derivation result named")
    assert "did you mean solid_angles.front_face" in err and len(err.splitlines()) == 1


def test_errata_table(capsys):
    code, out, _ = run(capsys, "--errata")
    assert code == 0 and out.startswith("| where |") and "**wrong**" in out


def test_bad_option_is_an_argparse_error(capsys):
    assert main(["constants", "--digits", "5"]) == 2
    assert capsys.readouterr().err == (
        "lpv-explorer constants: error: unrecognized arguments: --digits 5\n")
