"""The porting sheet (``lpv-explorer constants --format``): values from the derivations,
docs/MODEL.md's section equal to its conventions, the C/C++ header compiled by gcc as C89,
C99 and C11 and by g++ as C++11 beside an engine header of its own ``PI`` and run, the HLSL
and GLSL declarations parsed line by line (GLSL compiled by the driver), the JSON read back,
the cell-index rounding example recomputed by the GPU injection and the numpy reference."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
from pathlib import Path

import mpmath
import pytest
import sympy as sp

from derivations import porting
from derivations.registry import get
from derivations.solid_angles import tiling_proof
from explorer.cli import main

ROOT = Path(__file__).resolve().parents[2]
NUMBER = r"(-?[0-9.]+(?:e-?[0-9]+)?)"
DECLARATION = {
    "glsl": re.compile(rf"^const float LPV_([A-Z][A-Z0-9_]*) = {NUMBER};  // .+$"),
    "hlsl": re.compile(rf"^static const float LPV_([A-Z][A-Z0-9_]*) = {NUMBER};  // .+$"),
    "cpp": re.compile(rf"^LPV_PORTING_CONST double LPV_([A-Z][A-Z0-9_]*) = {NUMBER};"
                      r"  /\* .+ \*/$"),
    "js": re.compile(rf"^export const ([A-Z][A-Z0-9_]*) = {NUMBER};  // .+$"),
}
CPP_FLOAT = re.compile(rf"^LPV_PORTING_CONST float LPV_([A-Z][A-Z0-9_]*)_F = {NUMBER}f;"
                       r"  /\* the float nearest LPV_\1 \*/$")
ENGINE_HEADER = """/* an engine's own names, the ones an unprefixed sheet would redefine */
#define PI 3.14159265f
static const double FOUR_PI = 12.566370614359172;
static const float SH_C0 = 0.2820948f;
"""


def sheet(fmt: str, capsys, *options: str) -> str:
    assert main(["constants", "--format", fmt, *options]) == 0
    return capsys.readouterr().out


def nearest_double(expr) -> float:
    """The double nearest ``expr``'s exact value, by mpmath at 50 digits."""
    with mpmath.workdps(50):
        return float(mpmath.mpf(sp.N(expr, 50)))


def nearest_single(expr) -> float:
    """The IEEE single nearest ``expr``'s exact value: mpmath rounded to 24 bits (the
    sheet's own rounding goes through struct; the two must agree)."""
    with mpmath.workdps(50):
        exact = mpmath.mpf(sp.N(expr, 50))
    with mpmath.workprec(24):
        return float(+exact)


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
    found, singles = {}, {}
    comment = "/*" if fmt == "cpp" else "//"
    in_comment = False
    for line in text.splitlines():
        if fmt == "cpp" and (in_comment or line.startswith("/*")):
            in_comment = not line.endswith("*/")
            continue
        if not line or line.startswith(("//", "#", "namespace", "}")):
            continue
        match = DECLARATION[fmt].match(line)
        if fmt == "cpp" and not match:
            single = CPP_FLOAT.match(line)
            assert single, f"cpp: not a declaration or comment: {line!r}"
            singles[single[1]] = float(single[2])
            continue
        assert match, f"{fmt}: not a declaration or comment: {line!r}"
        found[match[1]] = float(match[2])
    assert found.keys() == expected.keys()
    tolerance = 0.0 if fmt in ("cpp", "js") else 1e-11     # the nearest double vs 12 digits
    for name, value in expected.items():
        assert found[name] == pytest.approx(value, rel=tolerance, abs=0), name
    if fmt == "cpp":                                # every double has its float twin
        assert singles.keys() == expected.keys()
    guards = 0 if fmt == "js" else 1                        # an ES module has no guard
    assert text.count("#ifndef") == guards
    for title, _ in porting.conventions():            # the conventions ride along as comments
        assert f"{' *' if fmt == 'cpp' else comment} - {title}:" in text


def _print_program(names: list[str], qualify: str) -> str:
    """C source that includes the engine's header, then the sheet, and prints every double
    with 17 significant digits and every float with 9."""
    lines = "".join(f'    printf("%.17g %.9g\\n", {qualify}{name}, (double) {qualify}{name}_F);\n'
                    for name in names)
    return ('#include <stdio.h>\n#include "engine.h"\n#include "lpv_sheet.h"\n'
            "int main(void) {\n" + lines + "    return 0;\n}\n")


def _compile_and_run(tmp_path: Path, compiler: list[str], source: str, suffix: str
                     ) -> list[str]:
    program = tmp_path / f"print{suffix}"
    program.write_text(source)
    binary = tmp_path / "print"
    done = subprocess.run([*compiler, "-o", str(binary), str(program)], capture_output=True,
                          text=True)
    assert done.returncode == 0, f"{' '.join(compiler)}:\n{done.stderr}"
    return subprocess.run([str(binary)], check=True, capture_output=True,
                          text=True).stdout.splitlines()


def _check_printed(printed: list[str]) -> None:
    """Each printed double is the nearest double of the exact value, each float the
    nearest single (mpmath; read back from the 17 and 9 digits printed)."""
    import numpy as np

    items = porting.constants()
    assert len(printed) == len(items)
    for line, item in zip(printed, items):
        double, single = line.split()
        assert float(double) == nearest_double(item.expr), (item.name, double)
        assert float(np.float32(single)) == nearest_single(item.expr), (item.name, single)
        assert double == f"{nearest_double(item.expr):.17g}"


C_BUILDS = [["gcc", "-x", "c", f"-std={std}", "-pedantic", "-Wall", "-Wextra", "-Werror"]
            for std in ("c89", "c99", "c11")]


@pytest.mark.skipif(shutil.which("gcc") is None, reason="no gcc on PATH")
@pytest.mark.parametrize("compiler", C_BUILDS, ids=lambda c: c[3])
def test_c_header_compiles_beside_an_engines_pi_and_holds_the_exact_values(
        tmp_path, capsys, compiler):
    (tmp_path / "engine.h").write_text(ENGINE_HEADER)
    (tmp_path / "lpv_sheet.h").write_text(sheet("cpp", capsys))
    names = ["LPV_" + c.name for c in porting.constants()]
    _check_printed(_compile_and_run(tmp_path, compiler, _print_program(names, ""), ".c"))


@pytest.mark.skipif(shutil.which("g++") is None, reason="no g++ on PATH")
def test_cxx_header_is_constexpr_in_namespace_lpv_beside_an_engines_pi(tmp_path, capsys):
    (tmp_path / "engine.h").write_text(ENGINE_HEADER)
    (tmp_path / "lpv_sheet.h").write_text(sheet("cpp", capsys))
    names = ["LPV_" + c.name for c in porting.constants()]
    source = _print_program(names, "lpv::") + (
        "static_assert(lpv::LPV_PI_F > 3.0f && lpv::LPV_FOUR_PI == 4 * lpv::LPV_PI,"
        ' "constexpr");\n')
    compiler = ["g++", "-x", "c++", "-std=c++11", "-pedantic", "-Wall", "-Wextra", "-Werror"]
    _check_printed(_compile_and_run(tmp_path, compiler, source, ".cpp"))


@pytest.mark.skipif(shutil.which("gcc") is None, reason="no gcc on PATH")
def test_prefix_and_namespace_options_rename_every_constant(tmp_path, capsys):
    """--prefix ENGINE_LPV_ --namespace gi: the header compiles as C89 and C++11 with the new
    names, and no name of the default prefix is left."""
    text = sheet("cpp", capsys, "--prefix", "ENGINE_LPV_", "--namespace", "gi")
    assert "LPV_PORTING_CONST" not in text.replace("ENGINE_LPV_PORTING_CONST", "")
    assert "namespace gi {" in text and "namespace lpv" not in text
    (tmp_path / "engine.h").write_text(ENGINE_HEADER)
    (tmp_path / "lpv_sheet.h").write_text(text)
    names = ["ENGINE_LPV_" + c.name for c in porting.constants()]
    _check_printed(_compile_and_run(tmp_path, C_BUILDS[0], _print_program(names, ""), ".c"))
    _check_printed(_compile_and_run(tmp_path, ["g++", "-std=c++11", "-Wall", "-Werror"],
                                    _print_program(names, "gi::"), ".cpp"))
    bare = sheet("cpp", capsys, "--prefix", "", "--namespace", "")
    assert not any(line.startswith(("namespace", "}")) for line in bare.splitlines())
    assert "PORTING_CONST double PI = 3.141592653589793;" in bare
    for fmt in ("glsl", "hlsl"):
        assert "float MY_PI = " in sheet(fmt, capsys, "--prefix", "MY_")
        assert " PI = " in sheet(fmt, capsys, "--prefix", "")


@pytest.mark.parametrize("argv, message", [
    (["--format", "js", "--prefix", "X_"], "--prefix only acts with --format glsl, hlsl or cpp"),
    (["--prefix", "X_"], "--prefix only acts with --format glsl, hlsl or cpp"),
    (["--format", "glsl", "--namespace", "x"], "--namespace only acts with --format cpp"),
    (["--format", "glsl", "--prefix", "gl_"], "prefix 'gl_' does not begin an identifier"),
    (["--format", "cpp", "--prefix", "_LPV"], "prefix '_LPV' does not begin an identifier"),
    (["--format", "cpp", "--prefix", "A__"], "prefix 'A__' does not begin an identifier"),
    (["--format", "cpp", "--namespace", "a::b"], "namespace 'a::b' is not one C++ identifier"),
])
def test_bad_prefix_or_namespace_is_one_line(capsys, argv, message):
    assert main(["constants", *argv]) == 2
    out, err = capsys.readouterr()
    assert out == "" and len(err.splitlines()) == 1 and message in err, err


def test_float_twin_is_the_nearest_single_even_where_rounding_twice_is_not():
    """The nearest single of an exact value, not the single nearest its nearest double:
    1 + 2^-24 + 2^-60 lies just above the midpoint of two singles, its nearest double on it
    (rounding that to even gives 1), the exact value rounds up."""
    value = 1 + sp.Rational(1, 2**24) + sp.Rational(1, 2**60)
    assert float(sp.N(value, 40)) == 1 + 2.0**-24
    assert porting.nearest_float32(value) == 1 + 2.0**-23 == nearest_single(value)


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

    names = ["LPV_" + c.name for c in porting.constants()]
    body = "\n".join(f"    values[{k}] = {name};" for k, name in enumerate(names))
    engine = "const float PI = 3.14159265;\nconst float SH_C0 = 0.2820948;\n"
    source = ("#version 430\n" + engine + sheet("glsl", capsys) +
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


def _injected_cell(grid) -> tuple[int, ...]:
    """The one cell that holds flux in an injected grid (3, N, N, N, C)."""
    import numpy as np

    cells = np.argwhere(np.abs(grid[0, ..., 0]) > 0)
    assert len(cells) == 1, cells
    return tuple(int(v) for v in cells[0])


def test_cell_rounding_example_is_what_the_gpu_and_the_reference_compute(ctx):
    """The porting sheet's worked example of the cell-index rule, recomputed: the numbers
    printed (float32 and float64 steps) and the cells the GPU injection (llvmpipe) and the
    numpy reference put the VPL in, with δ = 0 (on the face) and the default δ = 0.5."""
    import numpy as np

    from explorer.lpv import inject
    from explorer.lpv.grid import GridSpec
    from explorer.lpv.settings import Settings
    from explorer.lpv.twin.light_grid import inject as reference_inject
    from explorer.lpv.vpl import VplArrays

    text = dict(porting.conventions())["Cell index (rounding)"]
    f32 = np.float32
    origin, h, p = 0.1, 0.1, 0.3
    delta = Settings().injection_offset_cells
    assert delta == 0.5 and "default δ = 0.5" in text
    # the example's numbers, as the shader's float32 steps and the reference's float64 ones
    on_face = f32(p) - f32(origin)
    g32, g64 = on_face / f32(h), (p - origin) / h
    q32 = f32(p) + f32(delta * h) * f32(1.0)
    g32_offset, g64_offset = (q32 - f32(origin)) / f32(h), (p + delta * h - origin) / h
    for number, text_value in ((on_face, "0.20000002"), (g32, "2.0000002"),
                               (g64, "1.9999999999999998"), (q32, "0.35000002"),
                               (g32_offset, "2.5000002"), (g64_offset, "2.4999999999999996")):
        assert str(number) == text_value and text_value in text
    # the cells: the GPU's float32 floor says 2 on the face, the float64 reference 1
    spec = GridSpec((origin,) * 3, h, 4)
    centre = origin + 2.5 * h                      # y, z at a cell centre: x alone decides
    vpls = VplArrays(np.array([[p, centre, centre]]), np.array([[1.0, 0.0, 0.0]]),
                     np.ones((1, 3)), np.ones(1), 1.0)
    on_gpu = _injected_cell(inject(vpls, spec, ctx=ctx, offset_cells=0.0))
    on_cpu = _injected_cell(reference_inject(vpls, spec, offset_cells=0.0))
    assert on_gpu[0] == int(np.floor(g32)) == 2 and "cell 2 (the GPU" in text
    assert on_cpu[0] == int(np.floor(g64)) == 1 and "float64 g = 1.9999999999999998, cell 1" \
        in text
    assert on_gpu[1:] == on_cpu[1:] == (2, 2)
    # half a cell along the normal: the cell centre, the same cell on both sides
    offset_gpu = _injected_cell(inject(vpls, spec, ctx=ctx, offset_cells=delta))
    offset_cpu = _injected_cell(reference_inject(vpls, spec, offset_cells=delta))
    assert offset_gpu == offset_cpu == (2, 2, 2) and "cell 2 in both" in text


@pytest.mark.skipif(shutil.which("glslangValidator") is None,
                    reason="glslangValidator not installed (the driver compiles the GLSL "
                           "sheet above)")
def test_glsl_sheet_validates_with_glslang_beside_an_engines_pi(tmp_path, capsys):
    source = ("#version 430\nconst float PI = 3.14159265;\n" + sheet("glsl", capsys) +
              "layout(local_size_x = 1) in;\nlayout(std430, binding = 0) buffer Out "
              "{ float v[]; };\nvoid main() { v[0] = LPV_PI + LPV_SH_C0; }\n")
    path = tmp_path / "sheet.comp"
    path.write_text(source)
    done = subprocess.run(["glslangValidator", str(path)], capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
