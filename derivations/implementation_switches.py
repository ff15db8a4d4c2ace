r"""The five implementation switches, each as exact published and corrected statements.

The three published formulas the annotations correct live in ``derivations/corrections``;
the other five switches of ``Corrections`` (``derivations/correction_registry.py``) change how
the DX11 article implements the model. For each ``<key>`` this module derives
``corrections.<key>.original`` and ``.corrected`` (``Eq``s) and what the switch changes,
exactly (docs/MODEL.md "Corrections", "Propagation", "Geometry volume"). The registry
lists this module right after ``derivations/corrections.py`` and names its results
``corrections.…`` (:data:`MODULE`), as the switches' registry entries call them.

``exact_constants``. The DX11 article prints ``Δω_front = 0.4006696846``,
``Δω_side = 0.4234413544`` and ``π = 3.1415926`` (``errata.dx11.*``); the exact values are
``4·atan(√11/33)``, ``2·atan(3√11/11) − π/3`` and ``π``. With the other corrections on,
a step weights face ``f`` by ``Δω_f/π_f`` (``k_I = 1/π_f``), so it maps flux
``Φ_t → 6(Δω_front + 4Δω_side)/(4π_f)·Φ_t``: exactly ``Φ_t`` with the exact values
(``solid_angles.tiling``) and ``31416526533/31415926000·Φ_t`` with the printed ones.

``side_faces``. Front faces only, one step keeps ``6Δω_front/(4π) = 6·atan(√11/33)/π``
(≈ 0.19) of the flux; all five faces keep all of it.

``surfel_area_squared``. A texel of a 90° ``W×H`` map covers ``4w²/(W·H)`` at view depth
``w`` (``rsm.surfel_area``); the bug the annotations warn of (§5) is ``4w/(W·H)``. The
corrected area is ``w`` times the buggy one: too small beyond ``w = 1``, too big nearer.

``ping_pong``. With ``P`` the (linear) propagation step, ping-pong keeps the light in
flight ``grid_t = P(grid_{t−1})`` and accumulates ``acc_t = acc_{t−1} + P(grid_{t−1})``,
so ``acc_N = Σ_{t=0..N} P^t grid_0``. The DX11 in-place update, read race-free, is
``acc_t = acc_{t−1} + P(acc_{t−1})``, so ``acc_N = (1 + P)^N grid_0``: light propagated
``k`` times is counted ``C(N, k)`` times instead of once. For a step that scales flux by
``p``: ``Σ p^t`` against ``(1 + p)^N`` (unbounded for every ``p > 0``, while the
geometric series converges to ``1/(1 − p)`` for ``p < 1``); for the corrected step
(``p = 1``) ``N + 1`` against ``2^N``.

``clamp_front_face``. ``I_f = max(0, I(ω_c))`` instead of ``I(ω_c)`` on the front face:
it adds ``max(0, −I(ω_c)) ≥ 0``, the audit's clamp gain. An L1 clamped-cosine lobe is
``1/4 + ⟨n, ω⟩/2`` per unit, so behind itself (``ω = −n``) it is ``−1/4`` where the
lobe it stands for is 0.

References
----------
A. Kirsch, "Light Propagation Volumes — Annotations" (2010), §2, §5, §6; the DirectX 11 LPV
article (propagation shader, in the seed documents).
"""

from __future__ import annotations

import sympy as sp

from derivations import errata, rsm, sh
from derivations.corrections import Phi_p, emitted_flux
from derivations.propagation import (
    DX11_WEIGHTS,
    dx11_step_flux_factor,
    omega_front,
    omega_side,
    step_flux_factor,
    step_flux_ratio,
)
from derivations.registry import Result, result
from derivations.solid_angles import front_face, side_face

MODULE = "corrections"
KEYS = ("exact_constants", "side_faces", "surfel_area_squared", "ping_pong",
        "clamp_front_face", "model_face_weights", "irradiance_gather")

Phi_t, Phi_next = sp.symbols("Phi_t Phi_t+1", positive=True)
step_ratio = Phi_next / Phi_t
pi_f = sp.Symbol("pi_formula", positive=True)
face_weights = sp.ImmutableMatrix(sp.symbols("w_front w_side", positive=True))
"""The whole factor of a front and of a side face (what multiplies ⟨s, Y(e_f)⟩)."""
"""π as the formulas use it (π, or the article's 3.1415926)."""


# --- exact_constants ---------------------------------------------------------------------

def published_constants() -> tuple[sp.Rational, sp.Rational, sp.Rational]:
    """(Δω_front, Δω_side, π) as the DX11 article prints them, exact rationals."""
    return tuple(errata.check(f"dx11.{key}").printed.value
                 for key in ("front_solid_angle", "side_solid_angle", "pi"))


def constants_step_flux(front: sp.Expr, side: sp.Expr, pi_value: sp.Expr) -> sp.Expr:
    """Flux after ÷ before one step with the other corrections on (``k_I = 1/π_f``)."""
    return step_flux_ratio(front / pi_value, side / pi_value)


# --- side_faces ----------------------------------------------------------------------------

def side_faces_step_flux(with_sides: bool) -> sp.Expr:
    """Symbolic step factor (corrected k's: ``k_R·k_I·k_P = 1/π``), front faces only or
    front + 4 side faces per neighbour."""
    return step_flux_ratio(omega_front / sp.pi, omega_side / sp.pi if with_sides else 0)


# --- surfel_area_squared ---------------------------------------------------------------------

A_s = sp.Symbol("A_s", positive=True)


def surfel_areas() -> tuple[sp.Expr, sp.Expr]:
    """(linear, squared) surfel area: the texel area at depth 1 times ``w`` or ``w²``."""
    squared = rsm.surfel_area()
    at_unit_depth = squared.subs(rsm.w, 1)
    return at_unit_depth * rsm.w, squared


# --- ping_pong -----------------------------------------------------------------------------

P, p = sp.symbols("P p", positive=True)
"""``P``: the linear propagation step acting on ``grid_0`` (polynomials in one operator
commute, so it is a commutative symbol here); ``p``: the factor it applies to the flux."""
t, N = sp.symbols("t N", integer=True, nonnegative=True)
grid_0 = sp.Symbol("grid_0")
acc = sp.Function("acc")


def accumulated(in_place: bool, step: sp.Expr = P) -> sp.Expr:
    """``acc_N`` solved from its recurrence (``rsolve``): in place
    ``acc_t = (1 + step)·acc_{t−1}``, ping-pong ``acc_t = acc_{t−1} + step^t·grid_0``."""
    recurrence = (acc(t) - (1 + step) * acc(t - 1) if in_place
                  else acc(t) - acc(t - 1) - step**t * grid_0)
    return sp.rsolve(recurrence, acc(t), {acc(0): grid_0}).subs(t, N)


def accumulated_forms() -> tuple[sp.Expr, sp.Expr]:
    """(in place, ping-pong) ``acc_N`` in display form, checked against :func:`accumulated`:
    ``(1 + P)^N grid_0`` and ``Σ_{t=0..N} P^t grid_0``. The geometric sum is checked for
    ``P ≠ 1`` and, separately, for ``P = 1`` (where rsolve's closed form has no value)."""
    in_place = (1 + P) ** N * grid_0
    ping_pong = sp.Sum(P**t, (t, 0, N)) * grid_0
    if sp.simplify(accumulated(True) - in_place) != 0:
        raise AssertionError("the in-place recurrence does not give (1 + P)^N grid_0")
    general = grid_0 * (1 - P ** (N + 1)) / (1 - P)
    at_one = accumulated(False, sp.Integer(1))
    if sp.simplify(accumulated(False) - general) != 0 or \
            sp.simplify(at_one - ping_pong.subs(P, 1).doit()) != 0:
        raise AssertionError("the ping-pong recurrence does not give the geometric sum")
    return in_place, ping_pong


# --- clamp_front_face ------------------------------------------------------------------------

omega_c = sp.Symbol("omega_c")
I_f = sp.Symbol("I_f")
front_intensity = sp.Function("I")(omega_c)


def clamp_gain() -> sp.Expr:
    """``max(0, I) − I``, proved equal to ``max(0, −I)`` for every real ``I``."""
    real = sp.Symbol("x", real=True)
    gain = sp.Max(0, real) - real
    if sp.simplify((gain - sp.Max(0, -real)).rewrite(sp.Piecewise)) != 0:
        raise AssertionError("max(0, x) - x != max(0, -x)")
    return sp.Max(0, -front_intensity)


def l1_lobe_along_axis(cos_angle: sp.Expr) -> sp.Expr:
    """The L1 projection of ``clamp⁺⟨n, ω⟩`` for ``n = +z``, at a direction with
    ``⟨n, ω⟩ = cos_angle`` in the x–z plane: ``1/4 + cos_angle/2``."""
    sin_angle = sp.sqrt(1 - cos_angle**2)
    return sp.simplify(sh.evaluate(list(sh.lobe((0, 0, 1))), (sin_angle, 0, cos_angle)))


# --- irradiance_gather -------------------------------------------------------------------

s_coefficients = sp.ImmutableMatrix(sp.symbols("s_0:4", real=True))
"""One colour's L1 SH vector at the surface point (the trilinear sample of the grid)."""
h = sp.Symbol("h", positive=True)
"""The cell size."""
E = sp.Symbol("E", nonnegative=True)


def gather_kernels() -> tuple[sp.ImmutableMatrix, sp.ImmutableMatrix]:
    """(Y(−n), lobe(−n)) for a unit normal n: what the DX11 gather and the model dot
    with the stored SH vector."""
    minus_n = (-sh.n_x, -sh.n_y, -sh.n_z)
    basis = sp.ImmutableMatrix([b.subs(dict(zip((sh.x, sh.y, sh.z), minus_n)),
                                       simultaneous=True) for b in sh.L1_BASIS])
    return basis, sh.lobe(minus_n)


# --- the registry results ----------------------------------------------------------------

def results() -> list[Result]:
    front_pub, side_pub, pi_pub = published_constants()
    published_step = constants_step_flux(front_pub, side_pub, pi_pub)
    exact_step = step_flux_factor(omega_front / sp.pi, omega_side / sp.pi)
    constants = sp.ImmutableMatrix([omega_front, omega_side, pi_f])
    front_only = sp.simplify(side_faces_step_flux(False).subs(omega_front, front_face()))
    linear, squared = surfel_areas()
    in_place, ping_pong = accumulated_forms()
    flux_in_place, flux_ping_pong = in_place.subs({P: p, grid_0: 1}), ping_pong.subs(
        {P: p, grid_0: 1})
    behind = l1_lobe_along_axis(sp.Integer(-1))
    acc_t, acc_prev, grid_prev = sp.symbols("acc_t acc_t-1 grid_t-1")
    acc_N = sp.Symbol("acc_N")
    flux_ratio = sp.Symbol("Phi_N") / sp.Symbol("Phi_0")  # Φ_N: flux of acc_N
    return [
        # exact_constants
        result(MODULE, "exact_constants.original",
               sp.Eq(constants, sp.ImmutableMatrix([front_pub, side_pub, pi_pub])),
               "Front and side solid angles and π as the DX11 article prints them.",
               printed_decimals=True),
        result(MODULE, "exact_constants.corrected",
               sp.Eq(constants, sp.ImmutableMatrix([front_face(), side_face(), sp.pi])),
               "The exact solid angles of the front and side faces and π."),
        result(MODULE, "exact_constants.step_flux_original",
               sp.Eq(step_ratio, published_step),
               "One step with the printed constants (other corrections on): "
               "6(Δω_front + 4Δω_side)/(4π_f) of the flux, not 1."),
        result(MODULE, "exact_constants.step_flux_corrected", sp.Eq(step_ratio, exact_step),
               "One step with the exact constants keeps the flux: "
               "6(Δω_front + 4Δω_side) = 4π."),
        result(MODULE, "exact_constants.injected_flux_original",
               sp.Eq(sp.Symbol("Phi_injected") / Phi_p,
                     emitted_flux(Phi_p / pi_pub) / Phi_p),
               "A VPL injected with k_I = 1/3.1415926 emits π/3.1415926 of its flux."),
        result(MODULE, "exact_constants.flux_factor", sp.simplify(exact_step / published_step),
               "Corrected ÷ published flux after one step: 31415926000/31416526533."),
        # side_faces
        result(MODULE, "side_faces.original",
               sp.Eq(Phi_next, side_faces_step_flux(False) * Phi_t),
               "Front faces only: one step sends 6Δω_front/(4π) of the flux on."),
        result(MODULE, "side_faces.corrected",
               sp.Eq(Phi_next, side_faces_step_flux(True) * Phi_t),
               "Front + 4 side faces per neighbour: 6(Δω_front + 4Δω_side)/(4π) of the flux."),
        result(MODULE, "side_faces.step_flux_original", sp.Eq(step_ratio, front_only),
               "Front faces only, one step keeps 6·atan(√11/33)/π ≈ 0.19 of the flux."),
        result(MODULE, "side_faces.step_flux_corrected", sp.Eq(step_ratio, exact_step),
               "All five faces: one step keeps all the flux."),
        result(MODULE, "side_faces.flux_factor", sp.simplify(exact_step / front_only),
               "Corrected ÷ front-only flux after one step: π/(6·atan(√11/33))."),
        # surfel_area_squared
        result(MODULE, "surfel_area_squared.original", sp.Eq(A_s, linear),
               "Surfel area growing linearly with view depth w (the bug of annotations §5)."),
        result(MODULE, "surfel_area_squared.corrected", sp.Eq(A_s, squared),
               "Surfel area of a 90° W×H texel at view depth w: 4w²/(W·H)."),
        result(MODULE, "surfel_area_squared.flux_factor", sp.simplify(squared / linear),
               "Squared ÷ linear surfel area (and occluder weight): w, so the linear area is "
               "too small beyond w = 1 and too large nearer."),
        # ping_pong
        result(MODULE, "ping_pong.original",
               sp.Eq(acc_t, acc_prev + sp.Function("P")(acc_prev)),
               "DX11 in-place update, read race-free: light already propagated is "
               "propagated again (the GPU version also races)."),
        result(MODULE, "ping_pong.corrected",
               sp.Eq(acc_t, acc_prev + sp.Function("P")(grid_prev)),
               "Ping-pong: only the light in flight moves on, the last step's light "
               "propagated once."),
        result(MODULE, "ping_pong.accumulated_original", sp.Eq(acc_N, in_place),
               "In place after N steps: the injected light propagated k times is counted "
               "C(N, k) times."),
        result(MODULE, "ping_pong.accumulated_corrected", sp.Eq(acc_N, ping_pong),
               "Ping-pong after N steps: each power of P once."),
        result(MODULE, "ping_pong.flux_original", sp.Eq(flux_ratio, flux_in_place),
               "In place, a step scaling flux by p accumulates (1 + p)^N: unbounded for any "
               "p > 0."),
        result(MODULE, "ping_pong.flux_corrected", sp.Eq(flux_ratio, flux_ping_pong),
               "Ping-pong accumulates the geometric series Σ p^t (→ 1/(1 − p) for p < 1)."),
        result(MODULE, "ping_pong.flux_factor",
               sp.simplify(flux_ping_pong.doit().subs(p, 1) / flux_in_place.subs(p, 1)),
               "Ping-pong ÷ in place accumulated flux for a flux-conserving step (p = 1): "
               "(N + 1)/2^N."),
        # clamp_front_face
        result(MODULE, "clamp_front_face.original", sp.Eq(I_f, front_intensity),
               "Front-face intensity unclamped: negative SH lobes send negative light."),
        result(MODULE, "clamp_front_face.corrected", sp.Eq(I_f, sp.Max(0, front_intensity)),
               "Front-face intensity clamped at zero, as the DX11 propagation shader does."),
        result(MODULE, "clamp_front_face.clamp_gain",
               sp.Eq(sp.Symbol(r"\Delta I_f"), clamp_gain()),
               "Clamped − unclamped front-face intensity: max(0, −I) ≥ 0, the audit's clamp "
               "gain."),
        result(MODULE, "clamp_front_face.lobe_behind",
               sp.Eq(sp.Function("I_L1")(-sp.Symbol("n")), behind),
               "The L1 lobe of max(0, ⟨n, ω⟩) (1/4 + ⟨n, ω⟩/2) behind itself, ω = −n: −1/4 "
               "where the lobe it approximates is 0."),
        # irradiance_gather
        result(MODULE, "irradiance_gather.original",
               sp.Eq(E, sp.Max(0, (s_coefficients.T * gather_kernels()[0])[0])),
               "The DX11 gather: ⟨s, Y(−n)⟩, the intensity toward −n (W/sr), clamped, read "
               "as the irradiance: no cosine lobe and no 1/h²."),
        result(MODULE, "irradiance_gather.corrected",
               sp.Eq(E, sp.Max(0, (s_coefficients.T * gather_kernels()[1])[0]) / h**2),
               "The irradiance of the light the cell holds: ⟨s, lobe(−n)⟩/h², clamped."),
        result(MODULE, "irradiance_gather.band0_factor",
               sp.simplify(gather_kernels()[1][0] / gather_kernels()[0][0]),
               "Band 0 of lobe(−n) ÷ band 0 of Y(−n): π (√π/2 against 1/(2√π))."),
        result(MODULE, "irradiance_gather.band1_factor",
               sp.simplify(gather_kernels()[1][2] / gather_kernels()[0][2]),
               "Band 1 of lobe(−n) ÷ band 1 of Y(−n): 2π/3 (√(π/3) against √3/(2√π))."),
        result(MODULE, "irradiance_gather.flux_factor",
               sp.simplify(gather_kernels()[1][0] / gather_kernels()[0][0] / h**2),
               "Corrected ÷ DX11 for light of the same intensity in every direction (band 0 "
               "only): π/h², so the DX11 gather is too bright in cells smaller than √π."),
        # model_face_weights
        result(MODULE, "model_face_weights.original",
               sp.Eq(face_weights, sp.ImmutableMatrix(DX11_WEIGHTS)),
               "The DX11 shader's whole factor of a face, in place of k_R·k_I·k_P·Δω_f: "
               "Δω_front/(2π) for a front face, Δω_side/(3π) for a side face."),
        result(MODULE, "model_face_weights.corrected",
               sp.Eq(face_weights, sp.ImmutableMatrix([omega_front / sp.pi,
                                                       omega_side / sp.pi])),
               "The model's k_R·k_I·k_P·Δω_f with the corrected factors (k_R·k_I·k_P = 1/π) "
               "for every face."),
        result(MODULE, "model_face_weights.step_flux_original",
               sp.Eq(step_ratio, dx11_step_flux_factor()),
               "One step with the DX11 face weights keeps (3Δω_front + 8Δω_side)/(4π) "
               "= 5/6 − 2·atan(3√11/11)/π ≈ 0.365 of the flux."),
        result(MODULE, "model_face_weights.flux_factor",
               sp.simplify(exact_step / dx11_step_flux_factor()),
               "Corrected ÷ DX11 flux after one step: 1/(5/6 − 2·atan(3√11/11)/π) ≈ 2.74."),
    ]
