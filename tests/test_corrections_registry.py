"""The corrections registry: the one list of switches everything else is built from."""

from __future__ import annotations

import dataclasses
import re

import pytest
import sympy as sp

from derivations import codegen, registry
from explorer import derived
from explorer.lpv import corrections as C
from explorer.lpv import settings
from explorer.resources import shader_dir


def test_corrections_fields_are_the_registry_in_order_all_true_by_default():
    fields = dataclasses.fields(C.Corrections)
    assert [f.name for f in fields] == [entry.name for entry in C.CORRECTIONS]
    # the order persisted files and the tests rely on (a new switch goes at the end)
    assert C.Corrections.names()[:8] == (
        "injection_pi", "propagation_4pi", "reprojection_pi", "exact_constants", "side_faces",
        "surfel_area_squared", "ping_pong", "clamp_front_face")
    assert all(f.default is True and f.type is bool for f in fields)
    assert C.Corrections().as_uniforms() == {f"u_{f.name}": 1 for f in fields}
    with pytest.raises(dataclasses.FrozenInstanceError):
        C.Corrections().ping_pong = False
    assert settings.Corrections is C.Corrections and settings.PRESETS is C.PRESETS
    assert settings.preset is C.preset


def test_presets_switch_off_exactly_the_published_forms():
    original = C.PRESETS["original"]
    off = {name for name in C.Corrections.names() if not getattr(original, name)}
    assert off == {"injection_pi", "propagation_4pi", "reprojection_pi", "exact_constants"}
    assert off == {entry.name for entry in C.CORRECTIONS if entry.published}
    assert C.PRESETS["corrected"] == C.Corrections()
    with pytest.raises(KeyError, match="corrected"):
        C.preset("nope")


def test_every_switch_has_a_derived_published_and_corrected_formula():
    for entry in C.CORRECTIONS:
        original, corrected = (registry.get(name).expr for name in
                               (entry.original, entry.corrected))
        assert isinstance(original, sp.Eq) and isinstance(corrected, sp.Eq), entry.name
        assert original.lhs == corrected.lhs, entry.name
        assert original.rhs != corrected.rhs, entry.name
        for name in entry.derivations():
            assert registry.get(name).statement, name
            # the window reads the same result, typeset at codegen time
            assert derived.get(name).latex == registry.latex(name), name


def test_flux_texts_fill_from_the_derivations():
    assert "{" in C.BY_NAME["side_faces"].flux
    filled = derived.fill(C.BY_NAME["side_faces"].flux)
    assert "×0.191 " in filled
    assert "×1.000019 " in derived.fill(C.BY_NAME["exact_constants"].flux)
    for entry in C.CORRECTIONS:
        assert "{" not in derived.fill(entry.flux), entry.name
    with pytest.raises(KeyError, match="did you mean"):
        derived.fill("{corrections.side_faces.step_flux_orignal:.3f}")
    with pytest.raises(ValueError, match="no numeric value"):
        derived.fill("{corrections.side_faces.original}")


def test_stages_name_the_passes_that_read_each_switch():
    assert C.uniforms_read_by("inject") == ("u_injection_pi", "u_exact_constants")
    assert C.uniforms_read_by("geometry") == ("u_surfel_area_squared",)
    assert set(C.uniforms_read_by("propagate")) == {
        entry.uniform for entry in C.CORRECTIONS} - {"u_surfel_area_squared",
                                                    "u_irradiance_gather"}
    assert C.uniforms_read_by("gather") == ("u_irradiance_gather",)
    with pytest.raises(ValueError, match="unknown stage"):
        C.uniforms_read_by("gahter")


def test_switch_uniforms_are_declared_once_by_the_generated_file():
    generated = (shader_dir() / "generated" / "corrections.glsl").read_text()
    assert generated == codegen.corrections_glsl_source()
    declared = re.findall(r"^uniform bool (u_\w+);", generated, re.MULTILINE)
    assert declared == [entry.uniform for entry in C.CORRECTIONS]
    switches = "|".join(entry.uniform for entry in C.CORRECTIONS)
    for path in shader_dir().glob("*.glsl"):
        assert not re.search(rf"uniform\s+bool\s+({switches})\b", path.read_text()), path.name


def test_codegen_refuses_an_entry_without_its_derivation(monkeypatch):
    ghost = dataclasses.replace(C.CORRECTIONS[0], name="ghost_switch")
    monkeypatch.setattr(codegen, "CORRECTIONS", C.CORRECTIONS + (ghost,))
    with pytest.raises(ValueError, match="corrections.ghost_switch.original"):
        codegen.corrections_glsl_source()


def test_the_derived_table_is_the_registry():
    assert derived.names() == registry.names()
    for item in registry.all_results():
        entry = derived.get(item.name)
        assert entry.statement == item.statement
        expr = item.expr.rhs if isinstance(item.expr, sp.Eq) else item.expr
        if entry.value is not None:
            assert entry.value == pytest.approx(float(sp.N(expr, 30)), rel=1e-15)
    with pytest.raises(KeyError, match="solid_angles.front_face"):
        derived.get("solid_angles.front_fac")


def test_the_window_and_the_lessons_do_not_import_sympy():
    import subprocess
    import sys

    code = ("import sys, explorer.ui.app, explorer.ui.panels.corrections, explorer.lessons\n"
            "explorer.lessons.load_all()\n"
            "print('sympy' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, cwd=shader_dir().parent)
    assert out.stdout.strip() == "False"
