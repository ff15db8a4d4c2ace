"""The porting sheet (``lpv-explorer constants --format``): values from the derivations,
docs/MODEL.md's section equal to its conventions, the C/C++ header compiled and run by
``cc``, the HLSL and GLSL declarations parsed line by line, the JSON read back."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
from pathlib import Path

import pytest
import sympy as sp

from derivations import porting
from derivations.registry import get
from derivations.solid_angles import tiling_proof
from explorer.cli import main

ROOT = Path(__file__).resolve().parents[2]
DECLARATION = {
    "glsl": re.compile(r"^const float ([A-Z][A-Z0-9_]*) = (-?[0-9.]+(?:e-?[0-9]+)?);  // .+$"),
    "hlsl": re.compile(r"^static const float ([A-Z][A-Z0-9_]*) = (-?[0-9.]+(?:e-?[0-9]+)?);"
                       r"  // .+$"),
    "cpp": re.compile(r"^static const double ([A-Z][A-Z0-9_]*) = (-?[0-9.]+(?:e-?[0-9]+)?);"
                      r"  // .+$"),
    "js": re.compile(r"^export const ([A-Z][A-Z0-9_]*) = (-?[0-9.]+(?:e-?[0-9]+)?);  // .+$"),
}


def sheet(fmt: str, capsys) -> str:
    assert main(["constants", "--format", fmt]) == 0
    return capsys.readouterr().out


def test_face_weights_are_the_solid_angles_over_pi_and_tile_the_sphere():
    weights = {c.name: c.expr for c in porting.constants()}
    front, side = weights["FRONT_FACE_WEIGHT"], weights["SIDE_FACE_WEIGHT"]
    assert sp.simplify(front - get("solid_angles.front_face").expr / sp.pi) == 0
    assert sp.simplify(side - get("solid_angles.side_face").expr / sp.pi) == 0
    # 6 neighbours × (front + 4 sides) = 4π/π: the step keeps the flux (MODEL.md); the
    # derivations prove front + 4·side = 2π/3 exactly (sympy cannot simplify the atans)
    proof = tiling_proof()
    assert proof.holds
    assert sp.simplify(6 * (front + 4 * side) * sp.pi - 6 * (
        get("solid_angles.front_face").expr + 4 * get("solid_angles.side_face").expr)) == 0
    assert sp.simplify(6 * proof.front_plus_four_sides / sp.pi - 4) == 0
    assert not any(name.startswith("PUBLISHED_") for name in weights)


@pytest.mark.parametrize("fmt", ["glsl", "hlsl", "cpp", "js"])
def test_code_formats_declare_every_constant_with_its_value(fmt, capsys):
    text = sheet(fmt, capsys)
    expected = {c.name: float(sp.N(c.expr, 30)) for c in porting.constants()}
    found = {}
    for line in text.splitlines():
        if not line or line.startswith(("//", "#")):
            continue
        match = DECLARATION[fmt].match(line)
        assert match, f"{fmt}: not a declaration or comment: {line!r}"
        found[match[1]] = float(match[2])
    assert found.keys() == expected.keys()
    tolerance = 0.0 if fmt in ("cpp", "js") else 1e-11     # the nearest double vs 12 digits
    for name, value in expected.items():
        assert found[name] == pytest.approx(value, rel=tolerance, abs=0), name
    guards = 0 if fmt == "js" else 1                        # an ES module has no guard
    assert text.count("#ifndef") == text.count("#endif") == guards
    for title, _ in porting.conventions():            # the conventions ride along as comments
        assert f"// - {title}:" in text


@pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc) on PATH")
def test_cpp_sheet_compiles_as_c_and_cxx_and_holds_the_exact_doubles(tmp_path, capsys):
    header = tmp_path / "lpv_sheet.h"
    header.write_text(sheet("cpp", capsys))
    names = [c.name for c in porting.constants()]
    program = tmp_path / "print.c"
    program.write_text('#include <stdio.h>\n#include "lpv_sheet.h"\nint main(void) {\n'
                       + "".join(f'    printf("%.17g\\n", {name});\n' for name in names)
                       + "    return 0;\n}\n")
    binary = tmp_path / "print"
    subprocess.run(["cc", "-std=c11", "-Wall", "-Werror", "-o", str(binary), str(program)],
                   check=True, capture_output=True)
    printed = subprocess.run([str(binary)], check=True, capture_output=True,
                             text=True).stdout.split()
    for name, value, constant in zip(names, printed, porting.constants()):
        assert float(value) == float(sp.N(constant.expr, 30)), name   # the nearest double
    subprocess.run(["cc", "-x", "c++", "-std=c++17", "-Wall", "-Werror", "-fsyntax-only",
                    str(header)], check=True, capture_output=True)


def test_json_sheet_reads_back(capsys):
    data = json.loads(sheet("json", capsys))
    by_name = {entry["name"]: entry for entry in data["constants"]}
    entry = by_name["SIDE_FACE_WEIGHT"]
    assert sp.simplify(sp.sympify(entry["closed_form"]) - get("solid_angles.side_face").expr
                       / sp.pi) == 0
    assert entry["value"].startswith("0.134782386237406")
    assert [c["title"] for c in data["conventions"]] == [t for t, _ in porting.conventions()]


def test_model_md_porting_section_is_the_sheets_conventions():
    text = (ROOT / "docs" / "MODEL.md").read_text(encoding="utf-8")
    start = text.index("<!-- porting sheet: derivations/porting.py -->\n")
    end = text.index("<!-- end porting sheet -->")
    body = text[start:end].split("\n", 1)[1]
    assert body == porting.conventions_markdown()


def test_sh_conventions_name_the_registry_basis():
    """The basis lines are the registry's expressions, not typed text: the L1 basis evaluated
    at a direction equals the sheet's printed terms evaluated there."""
    x, y, z = sp.symbols("x y z", real=True)
    text = dict(porting.conventions())["SH basis, L1 (order and signs)"]
    terms = [part.split(" = ")[1] for part in text.split(", for")[0].split("; ")]
    basis = get("sh.basis_l1").expr
    for k, term in enumerate(terms):
        parsed = sp.sympify(term, locals={"x": x, "y": y, "z": z})
        assert sp.simplify(parsed - basis[k]) == 0


def test_unknown_format_is_refused_in_one_line(capsys):
    assert main(["constants", "--format", "metal"]) == 2
    assert "invalid choice: 'metal'" in capsys.readouterr().err


def test_glsl_sheet_compiles_on_the_gl_driver_and_holds_the_floats(ctx, capsys):
    """The GLSL sheet compiled by the driver (llvmpipe here) in a compute shader that
    writes every constant out: each is the float nearest its exact value."""
    import numpy as np

    names = [c.name for c in porting.constants()]
    body = "\n".join(f"    values[{k}] = {name};" for k, name in enumerate(names))
    source = ("#version 430\n" + sheet("glsl", capsys) +
              "layout(local_size_x = 1) in;\n"
              "layout(std430, binding = 0) buffer Out { float values[]; };\n"
              "void main() {\n" + body + "\n}\n")
    program = ctx.compute_shader(source)
    buffer = ctx.buffer(reserve=4 * len(names))
    try:
        buffer.bind_to_storage_buffer(0)
        program.run(1)
        got = np.frombuffer(buffer.read(), np.float32)
    finally:
        buffer.release()
        program.release()
    exact = np.array([float(sp.N(c.expr, 30)) for c in porting.constants()], np.float32)
    assert np.array_equal(got, exact), [n for n, a, b in zip(names, got, exact) if a != b]
