"""Lesson figures without a window: parameter validation, per-instance state, legends,
axis choices, and every number a figure shows against its exact value."""

from __future__ import annotations

import copy
import dataclasses
import importlib
import math
from types import SimpleNamespace

import numpy as np
import pytest
import sympy as sp
from figure_cases import synthetic_result

from explorer.lpv import constants as K
from explorer.lpv.settings import PRESETS, Settings
from explorer.lpv.twin.light_grid import cosine_lobe
from explorer.ui import legend
from explorer.ui.figures import (
    FIGURES,
    FigureContext,
    FigureParamError,
    cell_faces,
    clamped_cosine,
    declared_readouts,
    energy_audit,
    flux_per_step,
    make_figure,
    parse_figure,
    plotting,
    propagation_stepper,
    rsm_texel,
)

# ----------------------------------------------------------------------------- parameters


def test_each_figure_module_is_a_declared_kind_and_each_kind_has_its_module():
    """The kinds are declared once (explorer/figure_params.py FIGURE_KINDS); every module
    of explorer/ui/figures/ that draws a figure is one of them."""
    import pkgutil

    import explorer.ui.figures as package
    from explorer.figure_params import FIGURE_KINDS, FIGURE_PARAMS

    drawing = {info.name for info in pkgutil.iter_modules(package.__path__)
               if all(hasattr(importlib.import_module(f"{package.__name__}.{info.name}"), n)
                      for n in ("State", "draw", "readouts"))}
    assert drawing == {kind.module for kind in FIGURE_KINDS}
    assert list(FIGURES) == list(FIGURE_PARAMS) == [kind.name for kind in FIGURE_KINDS]


def test_every_kind_validates_its_defaults_and_documents_each_parameter():
    for name, kind in FIGURES.items():
        spec = parse_figure({"kind": name})
        assert spec.params == kind.params_class()
        assert parse_figure({"kind": name, **kind.demo}).params != spec.params
        for info in kind.params:
            assert info.doc and info.allowed()
            # the default passes the field's own check, and every number has a range
            assert info.spec.check(info.name, info.default) == info.default
            if info.spec.kind in ("int", "float"):
                assert info.spec.low is not None and info.spec.high is not None, info.name


def test_a_lesson_table_sets_parameters_caption_and_id():
    spec = parse_figure({"kind": "clamped-cosine", "normal_deg": 30, "orders": "l1",
                         "caption": "Drag the normal.", "id": "left"})
    assert spec.params.normal_deg == 30.0 and isinstance(spec.params.normal_deg, float)
    assert spec.params.orders == "l1"
    assert (spec.caption, spec.instance_id) == ("Drag the normal.", "left")
    assert parse_figure({"kind": "rsm-texel"}).instance_id == "rsm-texel"


@pytest.mark.parametrize("table, field, words", [
    ({"normal_deg": 30}, "kind", "kind is missing"),
    ({"kind": "cosine"}, "kind", "unknown figure kind 'cosine'"),
    ({"kind": "clamped-cosine", "normal": 30}, "normal", "unknown field"),
    ({"kind": "clamped-cosine", "normal_deg": 400}, "normal_deg", "[-180, 180], got 400"),
    ({"kind": "clamped-cosine", "normal_deg": "30"}, "normal_deg", "a finite number"),
    ({"kind": "clamped-cosine", "normal_deg": float("nan")}, "normal_deg", "a finite number"),
    ({"kind": "clamped-cosine", "orders": "l3"}, "orders", "one of 'l1', 'l2', 'both'"),
    ({"kind": "cell-faces", "tiling": 1}, "tiling", "true or false"),
    ({"kind": "propagation-stepper", "grid_size": 8.5}, "grid_size", "a whole number"),
    ({"kind": "propagation-stepper", "grid_size": True}, "grid_size", "a whole number"),
    ({"kind": "propagation-stepper", "grid_size": 6, "source_x": 7}, "source_x",
     "below grid_size (6)"),
    ({"kind": "propagation-stepper", "iterations": 4, "step": 5}, "step", "at most iterations"),
    ({"kind": "rsm-texel", "theta_deg": 90}, "theta_deg", "[0, 85]"),
    ({"kind": "energy-audit", "caption": 3}, "caption", "must be a string"),
])
def test_bad_parameters_are_refused_with_the_field_named(table, field, words):
    with pytest.raises(FigureParamError) as info:
        parse_figure(table, where="figures[1].")
    assert info.value.field == f"figures[1].{field}"
    assert str(info.value).startswith(f"figures[1].{field}")
    assert words in str(info.value)


def test_a_figure_table_must_be_a_table():
    with pytest.raises(FigureParamError, match="figures\\[0\\] must be a table"):
        parse_figure(["clamped-cosine"], where="figures[0].")


# ----------------------------------------------------------------------------- state


def test_two_instances_keep_their_own_state_and_a_new_step_resets_one():
    context = FigureContext()
    kind = FIGURES["clamped-cosine"]
    left = make_figure("clamped-cosine", normal_deg=10)
    a = context.state_for("left", left.kind, left.params, kind.make_state)
    b = context.state_for("right", left.kind, left.params, kind.make_state)
    a.normal_deg = 75.0                          # the reader drags the left one
    assert context.state_for("left", left.kind, left.params, kind.make_state).normal_deg == 75
    assert b.normal_deg == 10.0
    moved = make_figure("clamped-cosine", normal_deg=-40)   # the next lesson step
    assert context.state_for("left", moved.kind, moved.params,
                             kind.make_state).normal_deg == -40.0
    assert context.state_for("right", left.kind, left.params, kind.make_state) is b


def test_declared_readouts_read_the_figure_as_its_step_sets_it():
    """What a lesson check of figure.<id>.<readout> reads: the state the parameters make,
    whatever a reader dragged on screen; the audit figures plot the results handed in."""
    spec = make_figure("clamped-cosine", normal_deg=30)
    context = FigureContext()
    kind = FIGURES["clamped-cosine"]
    context.state_for(spec.instance_id, spec.kind, spec.params, kind.make_state).normal_deg = 75
    declared = declared_readouts(spec)
    assert declared["normal_deg"] == 30.0 and declared["l1_at_normal"] == pytest.approx(0.75)
    a, b = synthetic_result("corrected"), synthetic_result("original")
    audit = make_figure("energy-audit")
    assert declared_readouts(audit) == {}                      # no frame: nothing to read
    both = declared_readouts(audit, (a, b))
    assert both["b_injected"] == pytest.approx(math.pi * both["a_injected"], rel=1e-6)
    assert "b_injected" not in declared_readouts(make_figure("energy-audit", sides="a"), (a, b))


def test_the_context_takes_b_only_while_comparing():
    a, b = object(), object()
    shown = SimpleNamespace(result=a, compare_result=b)
    state = SimpleNamespace(runtime=SimpleNamespace(frame=shown), comparing=False)
    context = FigureContext()
    context.update_from_app(state)
    assert context.results == (a,)
    state.comparing = True
    context.update_from_app(state)
    assert context.results == (a, b)


# ----------------------------------------------------------------------------- legends


def test_legends_name_what_differs_between_a_and_b():
    a = Settings()
    assert legend.side_labels(a, a.with_changes(corrections={"propagation_4pi": False})) \
        == ("A: Propagation: no 1/(4π) per face on", "B: Propagation: no 1/(4π) per face off")
    assert legend.side_labels(a, a.with_changes(corrections="original")) \
        == ("A: corrected preset", "B: original preset")
    assert legend.side_labels(a, a.with_changes(grid_size=16, exposure=4.0)) \
        == ("A: Grid size (cells³) 32", "B: Grid size (cells³) 16")
    assert legend.side_labels(a, a.with_changes(exposure=4.0)) \
        == ("A: corrected preset", "B: same as A")
    assert legend.side_labels(a, a.with_changes(corrections="original", sh_order=2)) \
        == ("A: corrected preset, SH order 1", "B: original preset, SH order 2")
    custom = a.with_changes(corrections={"side_faces": False, "ping_pong": False})
    assert legend.describe(custom) == "Side faces off, Ping-pong propagation off"
    assert "custom" not in "".join(legend.side_labels(custom, a))


# ----------------------------------------------------------------------------- axes


def test_auto_axis_is_log_over_two_decades_and_linear_from_zero_otherwise():
    assert plotting.choose_scale([1.0, 1.03]) == "linear"
    assert plotting.choose_scale([1.0, 99.0]) == "linear"
    assert plotting.choose_scale([1.0, 101.0]) == "log"
    assert plotting.choose_scale([0.0, -1.0, 1e6]) == "linear"   # one positive value
    assert plotting.choose_scale([1.0, 1.03], "log") == "log"
    with pytest.raises(ValueError, match="scale must be one of"):
        plotting.choose_scale([1.0], "exp")
    low, high = plotting.value_limits([1.0, 1.03], "linear")
    assert low == 0.0 and 1.03 < high < 1.2, "a 3 % change must not fill the axis"
    assert plotting.value_limits([-0.5, 2.0], "linear")[0] < -0.5
    assert plotting.value_limits([2e-7, 30.0], "log") == (1e-7, 100.0)
    low, high = plotting.value_limits([1.0, 100.0], "log", room=0.5)
    assert low == 1.0 and high == pytest.approx(1e4)


# ----------------------------------------------------------------------------- numbers


@pytest.fixture(scope="module")
def exact_sh():
    """The exact energy shares and the exact L1/L2 profiles along the normal (sympy)."""
    from derivations import registry
    from derivations.sh import L1_BASIS, L2_BASIS, clamped_cosine_coefficients, z

    profiles = {}
    for order, basis in ((1, L1_BASIS), (2, L2_BASIS)):
        coefficients = clamped_cosine_coefficients(basis)       # normal = +z
        # Around +z only the zonal terms survive: the profile is a polynomial in z = cos.
        g = sp.expand(sum(c * b for c, b in zip(coefficients, basis)).subs(
            {sp.Symbol("x", real=True): 0, sp.Symbol("y", real=True): 0}))
        roots = sorted(r for r in sp.solve(g, z) if r.is_real and -1 <= r <= 1)
        negative = 2 * sp.pi * sp.integrate(g, (z, roots[0], roots[-1])) if len(roots) == 2 \
            else 2 * sp.pi * sp.integrate(g, (z, -1, roots[0]))
        profiles[order] = {"at_normal": g.subs(z, 1), "min": sp.Min(*[
            g.subs(z, p) for p in [-1, 1] + sp.solve(sp.diff(g, z), z)]),
            "negative_share": sp.nsimplify(negative / sp.pi)}
    return {"l1_energy": registry.get("sh.l1_energy_fraction").expr,
            "l2_energy": registry.get("sh.l2_energy_fraction").expr, "profiles": profiles}


@pytest.mark.parametrize("normal_deg", [30.0, -77.3, 180.0, 0.0])
def test_clamped_cosine_numbers_match_the_exact_derivations(exact_sh, normal_deg):
    params = make_figure("clamped-cosine", normal_deg=normal_deg).params
    r = clamped_cosine.readouts(params, clamped_cosine.State.from_params(params))
    assert exact_sh["l1_energy"] == sp.Rational(7, 8)
    assert exact_sh["l2_energy"] == sp.Rational(127, 128)
    # The numerical projection keeps 7/8 and 127/128 at every normal (1e-12: the two
    # Gauss–Legendre rules integrate the polynomial pieces exactly).
    assert r["l1_energy"] == pytest.approx(float(exact_sh["l1_energy"]), abs=1e-12)
    assert r["l2_energy"] == pytest.approx(float(exact_sh["l2_energy"]), abs=1e-12)
    assert r["lobe_energy"] == pytest.approx(2 * math.pi / 3, abs=1e-10)
    for order in (1, 2):
        exact = exact_sh["profiles"][order]
        assert r[f"l{order}_at_normal"] == pytest.approx(float(exact["at_normal"]), abs=1e-9)
        # the minimum is read off the 0.5° samples of the slice
        assert r[f"l{order}_min"] == pytest.approx(float(exact["min"]), abs=1e-4)
        # the tail's kink falls inside a Gauss–Legendre rule: 1e-3 relative
        assert r[f"l{order}_negative_flux"] == pytest.approx(
            float(exact["negative_share"]), rel=1e-3)
    assert exact_sh["profiles"][1]["negative_share"] == sp.Rational(-1, 8)
    # the exact column: the lobe itself, never negative, 1 toward n, 0 from 90° on
    assert (r["exact_energy"], r["exact_at_normal"], r["exact_min"]) == \
        pytest.approx((1.0, 1.0, 0.0), abs=1e-12)
    assert r["exact_min_angle_deg"] == pytest.approx(90.0) and r["exact_negative_flux"] == 0


def test_clamped_cosine_projection_equals_the_reference_lobe():
    for normal in ([0.0, 1.0, 0.0], [0.6, 0.0, 0.8], [0.48, -0.6, 0.64]):
        projection = clamped_cosine.project_clamped_cosine(np.array(normal))
        assert np.allclose(projection.coefficients, cosine_lobe(np.array(normal), 2),
                           atol=1e-12)


def test_clamped_cosine_probe_reads_all_three_functions():
    params = make_figure("clamped-cosine", normal_deg=0, probe_deg=180).params
    r = clamped_cosine.readouts(params, clamped_cosine.State.from_params(params))
    assert r["probe_angle_deg"] == pytest.approx(180.0)
    assert r["exact_probe"] == 0.0
    assert r["l1_probe"] == pytest.approx(-0.25, abs=1e-12)      # 1/4 − 1/2
    assert r["l2_probe"] == pytest.approx(1 / 16, abs=1e-12)      # 1/4 − 1/2 + 5/16


@pytest.mark.parametrize("direction", cell_faces.DIRECTIONS)
def test_cell_faces_solid_angles_match_the_constants_and_tile_the_sphere(direction):
    from derivations import registry

    params = make_figure("cell-faces", direction=direction, highlight="side").params
    r = cell_faces.readouts(params, cell_faces.State.from_params(params))
    assert K.FRONT_FACE_SOLID_ANGLE == pytest.approx(
        float(registry.get("solid_angles.front_face").expr), abs=1e-15)
    assert r["front_numeric"] == pytest.approx(K.FRONT_FACE_SOLID_ANGLE, abs=1e-12)
    assert r["side_numeric"] == pytest.approx(K.SIDE_FACE_SOLID_ANGLE, abs=1e-12)
    assert r["highlighted"] == K.SIDE_FACE_SOLID_ANGLE
    assert r["five_faces"] == pytest.approx(K.CUBE_FACE_SOLID_ANGLE, abs=1e-12)
    assert r["five_faces_numeric"] == pytest.approx(2 * math.pi / 3, abs=1e-12)
    assert r["thirty_faces_numeric"] == pytest.approx(K.FOUR_PI, abs=1e-11)
    faces = cell_faces.neighbour_faces(direction)
    axis = "xyz".index(direction[1])
    assert [f.is_front for f in faces] == [True, False, False, False, False]
    assert faces[0].axis == axis and abs(faces[0].plane) == 3.0
    # Every side face borders both the source cell's face plane and the front face.
    for face in faces[1:]:
        corners = face.corners()
        assert set(np.round(np.abs(corners[:, axis]), 9)) == {1.0, 3.0}


def test_rsm_texel_footprint_grows_irradiance_falls_flux_stays():
    thetas = np.linspace(0.0, rsm_texel.MAX_TILT, 86)
    terms = rsm_texel.texel_terms(thetas)
    cos = np.cos(np.radians(thetas))
    assert np.allclose(terms["footprint"], 1.0 / cos, rtol=1e-12)
    assert np.allclose(terms["irradiance"], cos, rtol=1e-12)
    assert np.allclose(terms["flux"], 1.0, atol=1e-12)
    params = make_figure("rsm-texel", theta_deg=60).params
    r = rsm_texel.readouts(params, rsm_texel.State.from_params(params))
    assert (r["footprint"], r["irradiance"]) == pytest.approx((2.0, 0.5), abs=1e-12)


def test_stepper_books_balance_with_the_corrected_formulas_only():
    params = make_figure("propagation-stepper", iterations=6).params
    state = propagation_stepper.State.from_params(params)
    injected = 3 * propagation_stepper.SOURCE_FLUX      # one VPL, 1 W in each channel
    for t in range(7):
        state.step = t
        r = propagation_stepper.readouts(params, state)
        assert r["injected"] == pytest.approx(injected, rel=1e-12)
        assert r["balance"] == pytest.approx(injected, rel=1e-9)
    assert r["in_flight"] != pytest.approx(injected)      # the clamp and the border act
    original = make_figure("propagation-stepper", iterations=6, step=3,
                           corrections="original").params
    r = propagation_stepper.readouts(original, propagation_stepper.State.from_params(original))
    assert r["injected"] == pytest.approx(math.pi * injected, rel=1e-6)   # no 1/π
    assert r["in_flight"] < 1e-3 * r["injected"]                          # 1/(4π) per step
    off = propagation_stepper.corrections_named("side_faces off")
    assert off == PRESETS["corrected"].__class__(side_faces=False)


def test_audit_bars_carry_values_and_shares_of_the_injected_flux():
    a, b = synthetic_result("corrected"), synthetic_result("original")
    series = energy_audit.audit_series([a, b])
    assert [s.label for s in series] == ["A: corrected preset", "B: original preset"]
    injected_row = [name for _, name in energy_audit.AUDIT_ROWS].index("injected")
    assert series[0].values[injected_row] == pytest.approx(series[0].reference)
    assert [energy_audit.AUDIT_ROWS[i][1] for i in energy_audit.shown_rows(series)] == [
        "rsm", "injected", "accumulated", "gathered", "border_loss", "clamp_gain", "occluded"]
    # the flux budget's own term is a row of its own where a side withheld flux
    budget = copy.copy(b)
    budget.audit = dataclasses.replace(b.audit, budget_withheld=np.full((3, 3), 0.01))
    with_budget = energy_audit.audit_series([a, budget])
    rows = [energy_audit.AUDIT_ROWS[i] for i in energy_audit.shown_rows(with_budget)]
    assert rows[-1] == ("withheld by the budget (Σ)", "budget_withheld")
    assert with_budget[1].values[-1] == pytest.approx(0.09)
    assert energy_audit.bar_label(0.912, 1.0, False) == "0.912 W · 91.2 %"
    assert energy_audit.bar_label(12.3, 1.0, True) == "12.3× · 12.3 W"
    assert energy_audit.bar_label(-0.002, 1.0, False) == "−0.002 W · −0.2 %"
    r = energy_audit.readouts(energy_audit.Params(), None, SimpleNamespace(results=(a, b)))
    assert r["a_gathered_share"] == pytest.approx(0.4)
    assert r["b_injected"] == pytest.approx(math.pi * r["a_injected"], rel=1e-6)


def test_flux_per_step_series_and_summary():
    a, b = synthetic_result("corrected"), synthetic_result("original")
    context = SimpleNamespace(results=(a, b))
    r = flux_per_step.readouts(flux_per_step.Params(), None, context)
    assert r["a_steps"] == 6 and r["a_last"] == pytest.approx(float(a.audit.per_step[-1].sum()))
    only_a = flux_per_step.readouts(flux_per_step.Params(sides="a"), None, context)
    assert "b_last" not in only_a
    lines = flux_per_step.summary([a])
    assert lines[0].startswith("A: after 6 steps") and "of the injected" in lines[0]
