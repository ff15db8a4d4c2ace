"""The porting sheet: the constants and conventions an engine needs to match this LPV,
as GLSL, HLSL, C/C++, JavaScript or JSON (``lpv-explorer constants --format ...``).

Every number comes from the registry (:mod:`derivations.registry`): the constants with a
GLSL name (the published decimals of ``errata`` left out: a port wants the exact values)
and the per-face weights ``Δω/π`` of the corrected propagation step (docs/MODEL.md
"Propagation": ``out += k_R·k_I·Φ_f·lobe(r_f)`` with ``Φ_f = Δω_f·I_f`` and
``k_R·k_I = 1/π``, so a face adds ``(Δω_f/π)·I_f·lobe(r_f)``), computed here exactly from
the two solid angles and π. The SH basis and the lobe are printed from their sympy
expressions. :func:`conventions_markdown` is the text of docs/MODEL.md's "Porting sheet"
section (a test keeps the two equal); the code formats carry the same lines as comments.
"""

from __future__ import annotations

import json
import re
import struct
from dataclasses import dataclass

import sympy as sp

from derivations.registry import all_results, get

FORMATS = ("glsl", "hlsl", "cpp", "js", "json")
FLOAT_DIGITS = 12
"""Significant digits of a ``float`` constant (GLSL, HLSL): more than a float holds."""
DOUBLE_DIGITS = 17
"""Significant digits of a ``double`` constant (C/C++): every double round-trips."""
VALUE_DIGITS = 20
"""Digits of the JSON values (strings, so that none is lost)."""


@dataclass(frozen=True)
class Constant:
    """One constant of the sheet: its name, exact value, the derivation it comes from."""

    name: str
    expr: sp.Expr
    derivation: str
    statement: str


def _face_weight(face: str) -> Constant:
    solid_angle = get(f"solid_angles.{face}_face")
    pi = get("solid_angles.projected_hemisphere").expr
    return Constant(f"{face.upper()}_FACE_WEIGHT", sp.simplify(solid_angle.expr / pi),
                    f"{solid_angle.name} / solid_angles.projected_hemisphere",
                    f"Δω_{face}/π: what one {face} face adds per unit of intensity, "
                    f"times lobe(r_f), in the corrected propagation step.")


def constants() -> list[Constant]:
    """The registry's GLSL constants (not the published decimals) and the face weights."""
    found = [Constant(item.glsl_name, item.expr, item.name, item.statement)
             for item in all_results()
             if item.glsl_name is not None and item.module != "errata"]
    return found + [_face_weight("front"), _face_weight("side")]


def _terms(name: str, symbol: str) -> str:
    """The entries of a registry vector as ``symbol_k = expr`` (k from 0)."""
    vector = get(name).expr
    return "; ".join(f"{symbol}{k} = {sp.sstr(vector[k])}" for k in range(vector.shape[0]))


def conventions() -> list[tuple[str, str]]:
    """``(title, text)`` of each convention, in the order the sheet prints them."""
    side = get("propagation.side_eval_direction").expr
    return [
        ("What a cell stores",
         "per colour channel (r, g, b) the real SH coefficients of the radiant intensity "
         "I(ω) [W/sr] of the light in the cell, ω the direction the light travels; "
         "I(ω) = Σ_k s_k·Y_k(ω). The flux a cell holds is Φ = SH_FLUX_FACTOR·s_0 = 2√π·s_0 "
         "[W] (band 1 and 2 integrate to 0). A grid array is indexed [colour, x, y, z, k] "
         "(x, y, z the cell index along world +x, +y, +z), shape (3, N, N, N, 4) for L1 and "
         "(3, N, N, N, 9) for L2; on the GPU one rgba32f 3D texture per colour, texel "
         "(x, y, z) holding s_0..s_3 (L2: three texel groups stacked along z, "
         "s_4..s_7 and s_8)."),
        ("SH basis, L1 (order and signs)", _terms("sh.basis_l1", "Y") + ", for a unit "
         "direction (x, y, z) in world axes (Condon–Shortley phase: the -y and -x terms)."),
        ("SH basis, L2 (after the four L1 terms)",
         "; ".join(_terms("sh.basis_l2", "Y").split("; ")[4:]) + "."),
        ("Lobe direction",
         "a VPL with unit normal n and flux Φ adds k_I·Φ·lobe(n) with k_I = INV_PI "
         "(corrected) to the cell holding p + δ·h·n (h the cell size, δ = 0.5 by default); "
         "lobe(n) is the SH projection of max(0, ⟨n, ω⟩) around n, pointing where the "
         "light goes: " + _terms("sh.lobe", "lobe_") + ". The final gather at a surface "
         "with normal n reads the light arriving there, which travels against n: "
         "E = max(0, Σ_k s_k·lobe(-n)_k) / h² [W/m²], and the indirect radiance is "
         "albedo/π·E."),
        ("Propagation faces",
         "the target cell gathers from its 6 neighbours; for the neighbour in direction d "
         "(target = source + d) the front face (the target's far face, normal d) is "
         "evaluated and reprojected along d with weight FRONT_FACE_WEIGHT = Δω_front/π, "
         "each of the 4 side faces (normal ±u or ±v, the frame's other two axes) is "
         f"evaluated along ±u·({sp.sstr(side[0])}) + d·({sp.sstr(side[1])}) (SIDE_EVAL_SMALL, "
         "SIDE_EVAL_BIG) and reprojected along ±u or ±v with weight SIDE_FACE_WEIGHT = "
         "Δω_side/π: out += weight·I_f·lobe(r_f), I_f = Σ_k s_k·Y_k(e_f) (the front face "
         "clamped at 0), times the geometry volume's visibility when it is on. "
         "6·(Δω_front + 4·Δω_side) = 4π: a step keeps the flux."),
        ("Propagation faces, 26 neighbours (Settings.neighbours = 26)",
         "the target gathers from all 26 neighbours, source = target - o, o ∈ {-1, 0, 1}³ "
         "minus 0; for every non-zero component i of o one face, the target's face in the "
         "plane 3·o_i half-cells from the source centre along i (on the surface of the "
         "source's 3×3×3 block), evaluated towards its centre, the unit vector of 2·o with "
         "component i replaced by 3·o_i (EDGE_EVAL_BIG, EDGE_EVAL_SMALL, CORNER_EVAL_BIG, "
         "CORNER_EVAL_SMALL), reprojected along o_i·e_i, with weight Δω/π: "
         "FRONT_FACE_SOLID_ANGLE (one non-zero component; the front face is clamped), "
         "EDGE_FACE_SOLID_ANGLE (two), CORNER_FACE_SOLID_ANGLE (three); the geometry "
         "volume's blocker is the mean over the corners source and target share (4, 2 or "
         "1). 6·Δω_front + 24·Δω_edge + 24·Δω_corner = 4π: a step keeps the flux."),
        ("Grid and world",
         "cell i spans origin + [i, i+1)·h; grid coordinate g = (p - origin)/h, cell "
         "floor(g), centre origin + (i + 1/2)·h, texture coordinate g/N (texel centres at "
         "(i + 1/2)/N); the geometry volume's cells are centred on the light grid's "
         "corners (geometry cell g at origin + g·h, (N+1)³ of them)."),
        ("Cell index (rounding)",
         "a VPL at p with unit normal n goes into the cell floor(g) of g = (q - origin)/h, "
         "q = p + δ·h·n, each axis on its own, in float32 as the shaders compute it "
         "(shaders/vpl.glsl, then grid.glsl's grid_cell: q, subtract, divide, floor; floor, "
         "not a cast to int, so a point just below the origin gets cell -1 and is dropped). "
         "Cells are half-open, so a point exactly on the face between cells i-1 and i belongs "
         "to cell i, but only when g comes out exactly i: float32 rounding of p, origin and h, "
         "of the subtraction and of the division (GLSL allows 2.5 ULP) can move it one cell, "
         "and the float64 reference (GridSpec.cell_index) can round the other way. Example: "
         "origin_x = 0.1, h = 0.1, p_x = 0.3 (in decimals the face between cells 1 and 2), "
         "δ = 0: float32 p - origin = 0.20000002, g = 2.0000002, cell 2 (the GPU, llvmpipe "
         "here); float64 g = 1.9999999999999998, cell 1. With the default δ = 0.5 and "
         "n = +x, q_x = 0.35000002 (float32), g = 2.5000002 (float64 2.4999999999999996), "
         "cell 2 in both: the half-cell offset moves a wall's VPLs off the faces to the "
         "cell centres, so the boundary case needs δ = 0 or VPLs that lie on a face "
         "anyway; an engine matching those cells too computes q and g in float32 in this "
         "order."),
        ("Accumulation",
         "grid_0 is the injected grid, grid_t = P(grid_{t-1}) (ping-pong), and the gather "
         "reads acc_N = Σ_{t=0..N} grid_t."),
    ]


def conventions_markdown() -> str:
    """The conventions as a markdown list (docs/MODEL.md's "Porting sheet" section)."""
    return "\n".join(f"* **{title}**: {text}" for title, text in conventions()) + "\n"


def _comment_lines(prefix: str, width: int = 96) -> list[str]:
    """The conventions wrapped into comment lines starting with ``prefix``."""
    import textwrap

    lines = [prefix + "Conventions (docs/MODEL.md \"Porting sheet\"):"]
    for title, text in conventions():
        wrapped = textwrap.wrap(f"{title}: {text}", width - len(prefix) - 2)
        lines += [prefix + ("- " if k == 0 else "  ") + line for k, line in enumerate(wrapped)]
    return lines


def _number(expr: sp.Expr, digits: int) -> str:
    """``expr`` as a C-family floating literal with ``digits`` significant digits."""
    value = float(sp.N(expr, 30))
    literal = repr(value) if digits >= DOUBLE_DIGITS else f"{value:.{digits}g}"
    if "e" not in literal and "." not in literal:
        literal += ".0"
    return literal


def _to_float32(value: float) -> float:
    """The IEEE single nearest ``value`` (a double), as a Python float."""
    return struct.unpack("<f", struct.pack("<f", value))[0]


def _float32_neighbours(single: float) -> list[float]:
    """``single`` and the two singles beside it (one unit in the last place either way)."""
    bits = struct.unpack("<i", struct.pack("<f", single))[0]
    return [struct.unpack("<f", struct.pack("<i", b))[0] for b in (bits - 1, bits, bits + 1)]


def nearest_float32(expr: sp.Expr) -> float:
    """The IEEE single nearest the exact value of ``expr`` (rounding the nearest double to
    a single can round twice; the three candidates are compared with the exact value)."""
    exact = sp.N(expr, 40)
    candidates = _float32_neighbours(_to_float32(float(exact)))
    return min(candidates, key=lambda c: abs(sp.Rational(c) - exact))


def _float_literal(expr: sp.Expr) -> str:
    """The shortest C literal (``…f``) that a correctly rounding compiler reads as the single
    nearest ``expr``; 9 significant digits always suffice."""
    single = nearest_float32(expr)
    for digits in range(6, 10):
        literal = f"{single:.{digits}g}"
        if _to_float32(float(literal)) == single:
            break
    if "e" not in literal and "." not in literal:
        literal += ".0"
    return literal + "f"


DEFAULT_PREFIX = "LPV_"
"""What every name of the GLSL, HLSL and C/C++ sheets starts with (an engine has its own
``PI``); ``--prefix ''`` gives the bare names."""
DEFAULT_NAMESPACE = "lpv"
"""The C++ namespace of the C/C++ header (C sees the same names at file scope)."""
FLOAT_SUFFIX = "_F"
"""The C/C++ header's ``float`` twin of each ``double`` constant: ``LPV_PI_F``."""
_IDENTIFIER = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")


def check_prefix(prefix: str) -> None:
    """Refuse a prefix that would not start an identifier, or that makes names C, C++ or
    GLSL reserve (a leading underscore, ``__`` anywhere, ``gl_``)."""
    if prefix == "":
        return
    if not _IDENTIFIER.match(prefix) or "__" in prefix or prefix.lower().startswith("gl_"):
        raise ValueError(f"prefix {prefix!r} does not begin an identifier every language "
                         "allows: a letter, then letters, digits and single underscores, "
                         "not gl_")


def check_namespace(namespace: str) -> None:
    """Refuse a C++ namespace that is not one plain identifier (C++11 has no ``a::b {``)."""
    if namespace != "" and (not _IDENTIFIER.match(namespace) or "__" in namespace):
        raise ValueError(f"namespace {namespace!r} is not one C++ identifier (a letter, then "
                         "letters, digits and single underscores)")


def _c_comment(text: str) -> str:
    """``text`` safe inside ``/* */``: no ``*/`` ends it early, no ``/*`` nests."""
    return text.replace("*/", "* /").replace("/*", "/ *")


HEADER = ("Generated by `lpv-explorer constants --format {fmt}` from the exact results in "
          "derivations/; each value's closed form and derivation are beside it.")


def _shader_code(fmt: str, prefix: str) -> str:
    """The GLSL, HLSL or JavaScript sheet: one ``float`` (JS: the nearest double) a name."""
    declaration, digits = {"glsl": ("const float", FLOAT_DIGITS),
                           "hlsl": ("static const float", FLOAT_DIGITS),
                           "js": ("export const", DOUBLE_DIGITS)}[fmt]
    guard = f"{prefix}PORTING_SHEET"
    lines = ["// " + HEADER.format(fmt=fmt)]
    if fmt != "js":              # an ES module needs no include guard
        lines += [f"#ifndef {guard}", f"#define {guard}"]
    lines.append("")
    lines += _comment_lines("// ")
    lines.append("")
    for item in constants():
        lines.append(f"{declaration} {prefix}{item.name} = {_number(item.expr, digits)};  "
                     f"// {sp.sstr(item.expr)}  [{item.derivation}]")
    lines += [""] if fmt == "js" else ["", "#endif", ""]
    return "\n".join(lines)


def _c_header(prefix: str, namespace: str) -> str:
    """The C/C++ header: each constant as ``double`` (the nearest double, 17 digits) and as
    ``float`` (``…_F``, the nearest single), ``/* */`` comments only (C89), in ``namespace``
    under C++; ``constexpr`` from C++11 on, ``static const`` in C."""
    guard, qualifier = f"{prefix}PORTING_SHEET_H", f"{prefix}PORTING_CONST"
    lines = ["/* " + _c_comment(HEADER.format(fmt="cpp")) + " */",
             f"#ifndef {guard}", f"#define {guard}", ""]
    lines += ["/*"] + [_c_comment(line.rstrip()) for line in _comment_lines(" * ")] + [" */"]
    lines += ["", "#if defined(__cplusplus) && __cplusplus >= 201103L",
              f"#define {qualifier} constexpr", "#else", f"#define {qualifier} static const",
              "#endif"]
    if namespace:
        lines += ["#ifdef __cplusplus", f"namespace {namespace} {{", "#endif"]
    lines.append("")
    for item in constants():
        about = _c_comment(f"{sp.sstr(item.expr)}  [{item.derivation}]")
        name = prefix + item.name
        lines.append(f"{qualifier} double {name} = {_number(item.expr, DOUBLE_DIGITS)};  "
                     f"/* {about} */")
        lines.append(f"{qualifier} float {name}{FLOAT_SUFFIX} = {_float_literal(item.expr)};  "
                     f"/* the float nearest {name} */")
    lines.append("")
    if namespace:
        lines += ["#ifdef __cplusplus", f"}}  /* namespace {namespace} */", "#endif"]
    lines += [f"#undef {qualifier}", "", f"#endif  /* {guard} */", ""]
    return "\n".join(lines)


def code(fmt: str, prefix: str = DEFAULT_PREFIX, namespace: str = DEFAULT_NAMESPACE) -> str:
    """The sheet as ``glsl``, ``hlsl``, ``cpp`` or ``js`` source, each name after ``prefix``
    (``js``: an ES module of ``export const`` numbers, the nearest doubles, never prefixed:
    a module is its own namespace). ``cpp`` is one header valid as C89/C99/C11 and C++11 on,
    the constants in ``namespace`` under C++ (see :func:`_c_header`)."""
    check_prefix(prefix)
    check_namespace(namespace)
    if fmt == "cpp":
        return _c_header(prefix, namespace)
    return _shader_code(fmt, "" if fmt == "js" else prefix)


def as_json() -> str:
    """The sheet as JSON: the constants (values as strings of :data:`VALUE_DIGITS`
    digits, and as floats) and the conventions."""
    payload = {
        "about": HEADER.format(fmt="json"),
        "constants": [{"name": item.name, "value": str(sp.N(item.expr, VALUE_DIGITS)),
                       "float": float(sp.N(item.expr, 30)), "closed_form": sp.sstr(item.expr),
                       "derivation": item.derivation, "statement": item.statement}
                      for item in constants()],
        "conventions": [{"title": title, "text": text} for title, text in conventions()],
    }
    return json.dumps(payload, indent=2, ensure_ascii=False) + "\n"


def sheet(fmt: str, prefix: str = DEFAULT_PREFIX, namespace: str = DEFAULT_NAMESPACE) -> str:
    """The porting sheet in format ``fmt`` (:data:`FORMATS`); ``prefix`` and ``namespace`` as
    :func:`code` takes them (JSON names stay bare)."""
    if fmt not in FORMATS:
        raise ValueError(f"unknown format {fmt!r}; choose one of {', '.join(FORMATS)}")
    return as_json() if fmt == "json" else code(fmt, prefix, namespace)
