"""The five implementation switches: exact published and corrected statements, and the
numpy twin showing the same factors."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from lpv_cases import random_grid

from derivations import errata, rsm
from derivations import implementation_switches as sw
from derivations.registry import get, latex
from derivations.solid_angles import front_face, prove_equal, side_face
from explorer import derived
from explorer.lpv.settings import Corrections
from explorer.lpv.twin import light_grid as R


def expr(name: str) -> sp.Basic:
    return get(f"corrections.{name}").expr


def test_exact_constants_printed_against_exact():
    printed = [errata.check(f"dx11.{key}").printed.value
               for key in ("front_solid_angle", "side_solid_angle", "pi")]
    assert printed == [sp.Rational("0.4006696846"), sp.Rational("0.4234413544"),
                       sp.Rational("3.1415926")]
    assert expr("exact_constants.original").rhs == sp.ImmutableMatrix(printed)
    assert expr("exact_constants.corrected").rhs == sp.ImmutableMatrix(
        [front_face(), side_face(), sp.pi])
    # typeset as the printed decimals, not as fractions
    assert "0.4006696846" in latex("corrections.exact_constants.original")
    assert "3.1415926" in latex("corrections.exact_constants.original")
    front, side, pi_printed = printed
    step = expr("exact_constants.step_flux_original").rhs
    assert step == 6 * (front + 4 * side) / (4 * pi_printed)
    assert step == sp.Rational(31416526533, 31415926000)
    assert expr("exact_constants.step_flux_corrected").rhs == 1
    assert expr("exact_constants.flux_factor") == 1 / step
    assert expr("exact_constants.injected_flux_original").rhs == sp.pi / pi_printed


def test_side_faces_front_only_keeps_under_a_fifth():
    kept = expr("side_faces.step_flux_original").rhs
    assert kept == 6 * sp.atan(sp.sqrt(11) / 33) / sp.pi
    assert sp.simplify(expr("side_faces.original").rhs / sw.Phi_t
                       - 6 * sw.omega_front / (4 * sp.pi)) == 0
    assert sp.simplify(expr("side_faces.corrected").rhs / sw.Phi_t
                       - 6 * (sw.omega_front + 4 * sw.omega_side) / (4 * sp.pi)) == 0
    # with the tiling 6(front + 4 side) = 4π the same value is 3 − 12·atan(3√11/11)/π
    assert prove_equal(kept * sp.pi / 6, (3 - 12 * sp.atan(3 * sp.sqrt(11) / 11) / sp.pi)
                       * sp.pi / 6).equal
    assert expr("side_faces.step_flux_corrected").rhs == 1
    assert expr("side_faces.flux_factor") == 1 / kept
    assert 0.19 < float(kept) < 0.2


def test_surfel_area_squared_is_w_times_the_linear_area():
    assert expr("surfel_area_squared.corrected").rhs == rsm.surfel_area()
    assert expr("surfel_area_squared.original").rhs == 4 * rsm.w / (rsm.W * rsm.H)
    assert expr("surfel_area_squared.flux_factor") == rsm.w


def test_ping_pong_counts_each_power_of_the_step_once():
    P, N, grid_0 = sw.P, sw.N, sw.grid_0
    in_place = expr("ping_pong.accumulated_original").rhs
    ping_pong = expr("ping_pong.accumulated_corrected").rhs
    assert in_place == (1 + P) ** N * grid_0
    # after 5 steps the light propagated k times is counted C(5, k) times in place
    coefficients = sp.Poly(sp.expand(in_place.subs(N, 5) / grid_0), P).all_coeffs()[::-1]
    assert coefficients == [sp.binomial(5, k) for k in range(6)]
    assert sp.expand(ping_pong.subs(N, 5).doit() / grid_0) == sum(P**k for k in range(6))
    # two steps: the once-propagated light is counted twice, i.e. once too often
    assert sp.expand((in_place - ping_pong).subs(N, 2).doit()) == P * grid_0
    assert expr("ping_pong.flux_factor") == (N + 1) / 2**N
    # a step that loses flux (p < 1): the geometric series converges, in place diverges
    p = sw.p
    lossy = sp.Rational(1, 4)
    assert sp.limit(expr("ping_pong.flux_corrected").rhs.subs(p, lossy).doit(), N, sp.oo) \
        == 1 / (1 - lossy)
    assert sp.limit(expr("ping_pong.flux_original").rhs.subs(p, lossy), N, sp.oo) == sp.oo


def test_clamp_front_face_adds_the_negative_part():
    x = sp.Symbol("x", real=True)
    intensity = sw.front_intensity
    gain = expr("clamp_front_face.clamp_gain").rhs
    assert gain == sp.Max(0, -intensity)
    difference = expr("clamp_front_face.corrected").rhs - expr("clamp_front_face.original").rhs
    assert sp.simplify((difference - gain).subs(intensity, x).rewrite(sp.Piecewise)) == 0
    assert expr("clamp_front_face.lobe_behind").rhs == sp.Rational(-1, 4)
    c = sp.Symbol("c", real=True)
    assert sp.simplify(sw.l1_lobe_along_axis(c) - (sp.Rational(1, 4) + c / 2)) == 0


def _lone_source(size: int = 11) -> np.ndarray:
    grid = np.zeros((3, size, size, size, 4))
    grid[:, size // 2, size // 2, size // 2] = random_grid(41, 1, band1=0.4)[:, 0, 0, 0]
    return grid


@pytest.mark.parametrize("switch, item", [
    ("exact_constants", "corrections.exact_constants.step_flux_original"),
    ("side_faces", "corrections.side_faces.step_flux_original"),
    ("model_face_weights", "corrections.model_face_weights.step_flux_original"),
])
def test_the_reference_step_keeps_the_derived_fraction(switch, item):
    grid = _lone_source()
    corrections = Corrections(clamp_front_face=False, **{switch: False})
    out, _ = R.propagation_step(grid, corrections)
    assert np.allclose(R.flux(out), derived.get(item).value * R.flux(grid), rtol=1e-12)


@pytest.mark.parametrize("ping_pong, factor", [(True, 3.0), (False, 4.0)])
def test_the_reference_accumulates_the_derived_series(ping_pong, factor):
    """Two flux-conserving steps (p = 1, no clamp, no border): ping-pong Σ p^t = 3,
    in place (1 + p)^2 = 4."""
    grid = _lone_source()
    steps = R.propagate(grid, Corrections(ping_pong=ping_pong, clamp_front_face=False), 2)
    in_place = expr("ping_pong.flux_original").rhs.subs({sw.p: 1, sw.N: 2})
    series = expr("ping_pong.flux_corrected").rhs.subs({sw.p: 1, sw.N: 2}).doit()
    assert (series, in_place) == (3, 4)
    assert np.allclose(R.flux(sum(steps)), factor * R.flux(grid), rtol=1e-12)
