"""The generated constants: fresh, complete, and loadable by GLSL and Python."""

from __future__ import annotations

import math
import re
import struct

import pytest

from derivations import codegen
from derivations.registry import get

BOOTSTRAP_NAMES = (
    "PI", "INV_PI", "FOUR_PI", "SH_C0", "SH_C1", "SH_COSLOBE_C0", "SH_COSLOBE_C1",
    "SH_FLUX_FACTOR", "FRONT_FACE_SOLID_ANGLE", "SIDE_FACE_SOLID_ANGLE", "SIDE_EVAL_SMALL",
    "SIDE_EVAL_BIG", "CUBE_FACE_SOLID_ANGLE", "PUBLISHED_FRONT_FACE_SOLID_ANGLE",
    "PUBLISHED_SIDE_FACE_SOLID_ANGLE", "PUBLISHED_PI",
)


def test_committed_files_are_fresh():
    stale = codegen.stale_files()
    assert stale == [], f"regenerate with `python -m derivations.codegen`: {stale}"


def test_check_mode_flags_a_stale_copy(tmp_path, capsys):
    assert codegen.main(["--root", str(tmp_path), "--check"]) == 1
    assert "stale" in capsys.readouterr().err
    assert codegen.main(["--root", str(tmp_path)]) == 0
    assert codegen.main(["--root", str(tmp_path), "--check"]) == 0
    glsl = tmp_path / codegen.GLSL_PATH
    glsl.write_text(glsl.read_text().replace("0.4", "0.5", 1))
    assert codegen.main(["--root", str(tmp_path), "--check"]) == 1


def test_every_bootstrap_name_is_generated_with_its_value():
    from explorer.lpv import constants

    glsl = codegen.glsl_source()
    assert glsl.splitlines()[0] == "#version 430 core"
    assert "GENERATED" in glsl and "python -m derivations.codegen" in glsl
    for name in BOOTSTRAP_NAMES:
        assert f"const float {name} = " in glsl, name
        assert hasattr(constants, name), name
    assert constants.FRONT_FACE_SOLID_ANGLE == 4 * math.atan(math.sqrt(11) / 33)
    assert constants.SIDE_FACE_SOLID_ANGLE == pytest.approx(
        2 * math.atan(3 * math.sqrt(11) / 11) - math.pi / 3, rel=1e-15)
    assert constants.PUBLISHED_SIDE_FACE_SOLID_ANGLE == 0.4234413544
    assert constants.PI == math.pi and constants.INV_PI == 1 / math.pi
    assert constants.DERIVATION["SH_C1"] == "sh.c1"


def test_glsl_values_carry_at_least_nine_digits_and_their_derivation():
    for line in codegen.glsl_source().splitlines():
        if not line.startswith("const float "):
            continue
        name, rest = line[len("const float "):].split(" = ", 1)
        value, comment = rest.split(";", 1)
        derivation = comment.rsplit("[", 1)[1].rstrip("]")
        expected = float(get(derivation).expr.evalf(30))
        assert float(value) == pytest.approx(expected, rel=5e-10), name
        if not name.startswith("PUBLISHED_"):
            digits = value.replace(".", "").replace("-", "").lstrip("0")
            assert len(digits) >= 9 or float(value) == expected, line


def test_generated_glsl_compiles(ctx):
    from explorer.gl.program import _strip_version

    body = _strip_version(codegen.glsl_source())
    source = ("#version 430 core\nlayout(local_size_x = 1) in;\n" + body
              + "\nlayout(std430, binding = 0) buffer Out { float v[]; };\n"
              "void main() { v[0] = FRONT_FACE_SOLID_ANGLE + 4.0 * SIDE_FACE_SOLID_ANGLE; }\n")
    shader = ctx.compute_shader(source)
    buffer = ctx.buffer(reserve=4)
    buffer.bind_to_storage_buffer(0)
    shader.run(1)
    (value,) = struct.unpack("f", buffer.read())
    assert value == pytest.approx(2 * math.pi / 3, rel=1e-6)
    shader.release()
    buffer.release()


def test_the_model_page_shows_the_registry_as_its_corrections_table():
    """docs/MODEL.md's corrections table is generated: a row per registry entry, its
    two forms (the hand-written page around it stays as it is)."""
    from derivations.correction_registry import CORRECTIONS

    table = codegen.corrections_table()
    assert [line.split("`")[1] for line in table.splitlines()[2:]] == [
        entry.name for entry in CORRECTIONS]
    page = (codegen.REPO_ROOT / codegen.MODEL_PATH).read_text(encoding="utf-8")
    assert f"{codegen.TABLE_BEGIN}\n{table}\n{codegen.TABLE_END}" in page


JS_DECLARATION = re.compile(r"^export const ([A-Z][A-Z0-9_]*) = (-?[0-9.]+(?:e-?[0-9]+)?);"
                            r"  // (.+)  \[([a-z0-9_.]+)\]$")


def test_javascript_module_holds_the_python_constants_and_the_figures_extras():
    """explorer/site/assets/generated/constants.js: every constant of
    explorer/lpv/constants.py with the same double, then codegen.JS_EXTRAS, each with its
    closed form and derivation; ``DERIVATION`` maps every name to its derivation."""
    from explorer.lpv import constants

    text = (codegen.REPO_ROOT / codegen.JS_PATH).read_text(encoding="utf-8")
    assert text == codegen.js_source()
    found = {}
    for line in text.splitlines():
        match = JS_DECLARATION.match(line)
        if match:
            name, value, closed, derivation = match.groups()
            found[name] = float(value)
            assert float(value) == float(get(derivation).expr.evalf(30)), name
            assert closed == codegen.closed_form(get(derivation)), name
            assert f'  {name}: "{derivation}",' in text, name
    python_names = list(constants.DERIVATION)
    assert list(found) == python_names + [name for name, _ in codegen.JS_EXTRAS]
    for name in python_names:
        assert found[name] == getattr(constants, name), name        # the same double
    assert found["BAND0_ENERGY_FRACTION"] + found["BAND1_ENERGY_FRACTION"] == \
        found["L1_ENERGY_FRACTION"]


def test_one_result_is_derived_alone_as_the_registry_derives_it(monkeypatch):
    """``constants --name`` derives only the modules a name's prefix names
    (registry.get_one): the same result as the whole registry's, for a name of each of
    the two modules that share the prefix ``corrections.`` and one of another module."""
    from functools import cache

    from derivations import registry

    wanted = ("corrections.injection_pi.corrected", "corrections.exact_constants.corrected",
              "sh.c1")
    expected = {name: get(name) for name in wanted}
    # an empty index of its own for the test (the suite's cached one is put back after)
    monkeypatch.setattr(registry, "_index", cache(registry._index.__wrapped__))
    alone = {name: registry.get_one(name) for name in wanted}
    assert registry._index.cache_info().currsize == 0, "no whole-registry derivation"
    assert alone == expected
