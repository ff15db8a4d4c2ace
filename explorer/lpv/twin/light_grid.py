"""Numpy twin of injection, geometry-volume injection and propagation.

Written independently of the GPU passes: where the shaders gather (one target cell sums
its six neighbours), this module scatters (every source cell sends to its six neighbours,
whole-grid array slices per direction and face), so a shared mistake is unlikely. It follows
docs/MODEL.md literally and computes in float64. Results are arrays shaped
``(3, N, N, N, 4)`` (channel, x, y, z, SH coefficient) like :func:`explorer.lpv.passes.inject`,
or ``(3, N, N, N, 9)`` with L2 spherical harmonics (docs/MODEL.md "L2 option": the basis
and the clamped-cosine lobe gain band 2; faces, weights, clamp and the L1 geometry volume
are unchanged).

In-place propagation (``ping_pong=False``) uses the race-free reading
``acc_t = acc_{t−1} + P(acc_{t−1})``. The GPU's in-place pass reads some neighbours after
they were already updated in the same step, so it differs from this by an amount that
depends on the invocation order; both double count light propagated before.
:func:`in_place_step_candidates` states exactly what the racing pass can produce.

Every constant (SH basis and lobe, flux factor, face solid angles, π and the published
decimals) is the float64 value of its exact sympy derivation (:data:`K`), read from the
table of derivation results ``explorer/derived_table.py`` (the codegen writes it from
``derivations.registry``; the test suite fails when it is stale), not the generated
mirror ``explorer/lpv/constants.py`` the shaders' constants come from: a wrong shader
constant then makes the GPU disagree with this twin. Reading the table runs no
sympy, so the window's picking and glyphs never stall on the registry.
"""

from __future__ import annotations

import numpy as np

from explorer.lpv.audit import GridAudit
from explorer.lpv.cascades import blend_weights
from explorer.lpv.grid import GridSpec, shape_text
from explorer.lpv.neighbours import check_flux_budget, check_neighbours
from explorer.lpv.settings import (
    GEOMETRY_VISIBILITY_MODES,
    GEOMETRY_VOLUME_MODES,
    INJECTION_MODES,
    REPROJECTION_MODES,
    Corrections,
)
from explorer.lpv.vpl import VplArrays


class DerivedConstants:
    """The constants this twin uses, each the float64 value of the exact result of a
    derivation (``derivations.registry``), looked up on first access in the codegen's
    table of results (``explorer.derived``): deriving the registry takes seconds of
    sympy, which a window must never wait for."""

    DERIVATIONS: dict[str, str] = {
        "PI": "solid_angles.projected_hemisphere",
        "SH_C0": "sh.c0",
        "SH_C1": "sh.c1",
        "SH_L2_C2": "sh.l2_c2",
        "SH_L2_C3": "sh.l2_c3",
        "SH_L2_C4": "sh.l2_c4",
        "SH_COSLOBE_C0": "sh.coslobe_c0",
        "SH_COSLOBE_C1": "sh.coslobe_c1",
        "SH_NET_FLUX_C1": "sh.net_flux_c1",
        "SH_L2_COSLOBE_C2": "sh.l2_coslobe_c2",
        "SH_FLUX_FACTOR": "sh.flux_factor",
        "FRONT_FACE_SOLID_ANGLE": "solid_angles.front_face",
        "SIDE_FACE_SOLID_ANGLE": "solid_angles.side_face",
        "EDGE_FACE_SOLID_ANGLE": "neighbours26.edge_face",
        "CORNER_FACE_SOLID_ANGLE": "neighbours26.corner_face",
        "PUBLISHED_PI": "errata.dx11.pi",
        "PUBLISHED_FRONT_FACE_SOLID_ANGLE": "errata.dx11.front_solid_angle",
        "PUBLISHED_SIDE_FACE_SOLID_ANGLE": "errata.dx11.side_solid_angle",
        "INV_FOUR_PI": "media.isotropic_phase",
        "DX11_FRONT_SHARE": "propagation.front_share_dx11",
        "DX11_SIDE_SHARE": "propagation.side_share_dx11",
    }
    """Constant name -> derivation result name."""

    def __getattr__(self, name: str) -> float:
        if name not in self.DERIVATIONS:
            raise AttributeError(f"no derived constant {name!r}; known: "
                                 f"{', '.join(self.DERIVATIONS)}")
        from explorer.derived import get

        value = get(self.DERIVATIONS[name]).value
        if value is None:
            raise AttributeError(f"the derivation {self.DERIVATIONS[name]} behind {name} "
                                 "is not a number")
        value = float(value)
        setattr(self, name, value)   # looked up once
        return value


K = DerivedConstants()
"""``K.SH_C0`` etc.: see :class:`DerivedConstants`."""

SH_COEFFICIENTS = {1: 4, 2: 9}


def _order(sh_order: int) -> int:
    if isinstance(sh_order, bool) or sh_order not in SH_COEFFICIENTS:
        raise ValueError(f"sh_order must be 1 (L1) or 2 (L2), got {sh_order!r}")
    return int(sh_order)


def sh_basis(direction: np.ndarray, sh_order: int = 1) -> np.ndarray:
    """Y(ω) = (c0, −c1·ω.y, c1·ω.z, −c1·ω.x) for unit directions shaped (..., 3); with
    ``sh_order`` 2 followed by band 2 (c2·xy, −c2·yz, c3·(3z²−1), −c2·xz, c4·(x²−y²))."""
    x, y, z = np.moveaxis(np.asarray(direction, np.float64), -1, 0)
    band01 = [np.full_like(x, K.SH_C0), -K.SH_C1 * y, K.SH_C1 * z, -K.SH_C1 * x]
    if _order(sh_order) == 1:
        return np.stack(band01, -1)
    band2 = [K.SH_L2_C2 * x * y, -K.SH_L2_C2 * y * z, K.SH_L2_C3 * (3.0 * z * z - 1.0),
             -K.SH_L2_C2 * x * z, K.SH_L2_C4 * (x * x - y * y)]
    return np.stack(band01 + band2, -1)


def cosine_lobe(normal: np.ndarray, sh_order: int = 1) -> np.ndarray:
    """SH projection of clamp+(<n, ω>) for unit normals shaped (..., 3). L2: the zonal
    rotation, band l of Y(n) times A_l = √(4π/(2l+1))·(zonal coefficient of band l)."""
    x, y, z = np.moveaxis(np.asarray(normal, np.float64), -1, 0)
    band01 = [np.full_like(x, K.SH_COSLOBE_C0), -K.SH_COSLOBE_C1 * y,
              K.SH_COSLOBE_C1 * z, -K.SH_COSLOBE_C1 * x]
    if _order(sh_order) == 1:
        return np.stack(band01, -1)
    # Band 2 from its zonal coefficient around +z (SH_L2_COSLOBE_C2), not from the
    # shaders' SH_L2_LOBE_* constants: A_2 = √(4π/5)·SH_L2_COSLOBE_C2 (= π/4).
    band2_factor = np.sqrt(4.0 * K.PI / 5.0) * K.SH_L2_COSLOBE_C2
    band2 = sh_basis(np.stack([x, y, z], -1), 2)[..., 4:] * band2_factor
    return np.concatenate([np.stack(band01, -1), band2], -1)


def flux(grid: np.ndarray) -> np.ndarray:
    """(3,) flux of a (3, N, N, N, 4) intensity grid: 2√π times the sum of coefficient 0."""
    grid = np.asarray(grid, np.float64)
    return K.SH_FLUX_FACTOR * grid[..., 0].reshape(grid.shape[0], -1).sum(axis=1)


def formula_pi(corrections: Corrections) -> float:
    """π as the formulas use it: the DX11 article's decimals unless exact constants."""
    return K.PI if corrections.exact_constants else K.PUBLISHED_PI


def injection_factor(corrections: Corrections) -> float:
    """k_I = 1/π (corrected) or 1 (published)."""
    return 1.0 / formula_pi(corrections) if corrections.injection_pi else 1.0


def propagation_factor(corrections: Corrections) -> float:
    """k_P = 1 (corrected) or 1/(4π) (published)."""
    return 1.0 if corrections.propagation_4pi else 1.0 / (4.0 * formula_pi(corrections))


def reprojection_factor(corrections: Corrections) -> float:
    """k_R = 1 (corrected) or 1/π (published)."""
    return 1.0 if corrections.reprojection_pi else 1.0 / formula_pi(corrections)


def face_solid_angles(corrections: Corrections) -> tuple[float, float]:
    """(front, side) solid angles: exact, or the DX11 article's decimals."""
    if corrections.exact_constants:
        return K.FRONT_FACE_SOLID_ANGLE, K.SIDE_FACE_SOLID_ANGLE
    return K.PUBLISHED_FRONT_FACE_SOLID_ANGLE, K.PUBLISHED_SIDE_FACE_SOLID_ANGLE


def face_weights(corrections: Corrections) -> tuple[float, float]:
    """(front, side): the whole factor of a face, k_R·k_I·k_P·Δω_f, or with
    ``model_face_weights`` off the DX11 shader's Δω_front/(2π) and Δω_side/(3π)
    (``propagation.front_share_dx11``, ``side_share_dx11`` of 1/π)."""
    front_angle, side_angle = face_solid_angles(corrections)
    if not corrections.model_face_weights:
        pi = formula_pi(corrections)
        return K.DX11_FRONT_SHARE / pi * front_angle, K.DX11_SIDE_SHARE / pi * side_angle
    scale = (reprojection_factor(corrections) * injection_factor(corrections)
             * propagation_factor(corrections))
    return scale * front_angle, scale * side_angle


def _check_grid(grid: np.ndarray) -> np.ndarray:
    grid = np.asarray(grid, np.float64)
    if grid.ndim != 5 or grid.shape[0] != 3 or grid.shape[4] not in (4, 9) or \
            min(grid.shape[1:4]) < 1:
        raise ValueError(f"grid must have shape (3, nx, ny, nz, 4) (L1) or "
                         f"(3, nx, ny, nz, 9) (L2), got {grid.shape}")
    return grid


def grid_sh_order(grid: np.ndarray) -> int:
    """1 for a grid of 4 coefficients per cell, 2 for 9."""
    return 1 if np.shape(grid)[-1] == 4 else 2


def _check_geometry(geometry: np.ndarray | None, cells: tuple[int, int, int]
                    ) -> np.ndarray | None:
    if geometry is None:
        return None
    geometry = np.asarray(geometry, np.float64)
    expected = tuple(int(n) + 1 for n in cells) + (4,)
    if geometry.shape != expected:
        raise ValueError(f"geometry must have shape {expected} for a {shape_text(cells)} "
                         f"grid, got {geometry.shape}")
    return geometry


# --------------------------------------------------------------------------- injection


def injection_positions(vpls: VplArrays, spec: GridSpec, offset_cells: float = 0.0
                        ) -> np.ndarray:
    """(M, 3) where the VPLs are injected: ``p + δ·cell_size·n`` (docs/MODEL.md
    "Injection")."""
    offset = float(offset_cells)
    if not (np.isfinite(offset) and offset >= 0.0):
        raise ValueError(f"the injection offset must be a finite number of cells >= 0, got "
                         f"{offset_cells!r}")
    positions = np.asarray(vpls.positions, np.float64)
    return positions + offset * spec.cell_size * np.asarray(vpls.normals, np.float64)


def inject(vpls: VplArrays, spec: GridSpec, corrections: Corrections | None = None,
           mode: str = "points", offset_cells: float = 0.0, sh_order: int = 1
           ) -> np.ndarray:
    """grid[c, cell(p + δ·h·n)] += k_I·Φ[c]·lobe(n) for every VPL inside the grid (both
    injection modes compute this same sum); δ = ``offset_cells``, h the cell size;
    ``sh_order`` 2 uses the 9-coefficient L2 lobe."""
    if mode not in INJECTION_MODES:
        raise ValueError(f"injection mode must be one of {INJECTION_MODES}, got {mode!r}")
    corrections = corrections or Corrections()
    grid = np.zeros((3, *spec.cells, SH_COEFFICIENTS[_order(sh_order)]))
    cells = spec.cell_index(injection_positions(vpls, spec, offset_cells))
    keep = spec.inside(cells)
    ix, iy, iz = cells[keep].T
    lobes = injection_factor(corrections) * cosine_lobe(np.asarray(vpls.normals)[keep],
                                                        sh_order)
    for channel in range(3):
        weights = np.asarray(vpls.flux, np.float64)[keep, channel, None]
        np.add.at(grid[channel], (ix, iy, iz), weights * lobes)
    return grid


def inject_geometry(vpls: VplArrays, spec: GridSpec, corrections: Corrections | None = None,
                    mode: str = "one-sided") -> np.ndarray:
    """Geometry volume (nx+1)×(ny+1)×(nz+1)×4: each surfel adds A/cell_size²·lobe(n) (one-sided) or
    A/cell_size²·(lobe(n)+lobe(−n)) to the geometry cell centred on the light-grid corner
    nearest to it, i.e. cell round(g)."""
    if mode not in GEOMETRY_VOLUME_MODES or mode == "off":
        raise ValueError(f"geometry mode must be 'one-sided' or 'double-sided', got {mode!r}")
    corrections = corrections or Corrections()
    size = np.asarray(spec.cells) + 1
    volume = np.zeros((*size, 4))
    cells = np.floor(spec.grid_coords(vpls.positions) + 0.5).astype(np.int64)
    keep = np.all((cells >= 0) & (cells < size), axis=1)
    normals = np.asarray(vpls.normals, np.float64)[keep]
    lobes = cosine_lobe(normals)
    if mode == "double-sided":
        lobes = lobes + cosine_lobe(-normals)
    area = vpls.surfel_area(corrections.surfel_area_squared)[keep] / spec.cell_size ** 2
    np.add.at(volume, tuple(cells[keep].T), area[:, None] * lobes)
    return volume


def inject_geometry_albedo(vpls: VplArrays, spec: GridSpec,
                           corrections: Corrections | None = None) -> np.ndarray:
    """(nx+1)×(ny+1)×(nz+1)×4 albedo sums of the geometry volume: each surfel adds
    A/cell_size²·(a_r, a_g, a_b, 1) to the same geometry cell as in
    :func:`inject_geometry` (zeros when the VPLs carry no albedo)."""
    corrections = corrections or Corrections()
    size = np.asarray(spec.cells) + 1
    sums = np.zeros((*size, 4))
    if vpls.albedo is None:
        return sums
    cells = np.floor(spec.grid_coords(vpls.positions) + 0.5).astype(np.int64)
    keep = np.all((cells >= 0) & (cells < size), axis=1)
    area = vpls.surfel_area(corrections.surfel_area_squared)[keep] / spec.cell_size ** 2
    albedo = np.asarray(vpls.albedo, np.float64)[keep]
    values = area[:, None] * np.hstack([albedo, np.ones((len(albedo), 1))])
    np.add.at(sums, tuple(cells[keep].T), values)
    return sums


# --------------------------------------------------------------------------- propagation


def _faces(axis: int, sign: int, side_faces: bool) -> list[tuple[np.ndarray, np.ndarray, bool]]:
    """(evaluation direction, reprojection direction, is front) of the faces of the cell
    one step along ``sign``·e_axis, seen from the source (docs/MODEL.md)."""
    forward = np.zeros(3)
    forward[axis] = sign
    faces = [(forward, forward, True)]
    if side_faces:
        for other in (axis + 1) % 3, (axis + 2) % 3:
            for side_sign in (1.0, -1.0):
                side = np.zeros(3)
                side[other] = side_sign
                evaluation = side / np.sqrt(5.0) + 2.0 * forward / np.sqrt(5.0)
                faces.append((evaluation, side, False))
    return faces


def reprojection_axis(normal: np.ndarray, evaluation: np.ndarray,
                      reprojection: str = "face-normal") -> np.ndarray:
    """The axis of a face's reprojected cosine lobe (``Settings.reprojection``,
    docs/MODEL.md "Propagation"): the face's ``normal``, or with ``face-centre`` its
    ``evaluation`` direction, the unit direction from the source cell's centre to the
    face's centre."""
    if reprojection not in REPROJECTION_MODES:
        raise ValueError(f"reprojection must be one of {', '.join(REPROJECTION_MODES)}, "
                         f"got {reprojection!r}")
    return evaluation if reprojection == "face-centre" else normal


def _face_blockers(geometry: np.ndarray, axis: int, sign: int) -> np.ndarray:
    """(nx, ny, nz, 4): for every source cell s, the mean geometry SH of the face it shares
    with s + sign·e_axis (corners s_axis + 1 for sign > 0, s_axis for sign < 0)."""
    moved = np.moveaxis(geometry, axis, 0)
    layer = moved[1:] if sign > 0 else moved[:-1]
    mean = 0.25 * (layer[:, :-1, :-1] + layer[:, 1:, :-1] + layer[:, :-1, 1:]
                   + layer[:, 1:, 1:])
    return np.moveaxis(mean, 0, axis)


def _reflection_normals(blockers: np.ndarray, axis: int, sign: int) -> np.ndarray:
    """(N, N, N, 3) direction of the reflected lobe per source cell: the blockers' mean
    normal (band 1 of lobe(n) is (−c·n.y, c·n.z, −c·n.x)) where it faces back towards the
    source (⟨normal, −d⟩ > 0), else −d."""
    normal = np.stack([-blockers[..., 3], -blockers[..., 1], blockers[..., 2]], -1)
    back = np.zeros(3)
    back[axis] = -sign
    facing = normal @ back > 0.0
    length = np.linalg.norm(normal, axis=-1, keepdims=True)
    unit = np.divide(normal, length, out=np.zeros_like(normal), where=length > 0)
    return np.where(facing[..., None], unit, back)


def face_visibility(blockers: np.ndarray, evaluation: np.ndarray,
                    mode: str = "linear") -> np.ndarray:
    """V_f of every source cell's face evaluated along ``evaluation`` (docs/MODEL.md
    "Geometry volume"): the blocking τ = ⟨blockers, Y(−e_f)⟩ of surfels facing −e_f,
    ``linear`` V = 1 − clamp(τ, 0, 1) (the LPV paper's), ``statistical`` V = exp(−max(τ, 0))
    (surfels placed independently at random: the product of their passing
    probabilities, derivation ``occlusion.statistical_visibility``)."""
    if mode not in GEOMETRY_VISIBILITY_MODES:
        raise ValueError(f"visibility must be one of {', '.join(GEOMETRY_VISIBILITY_MODES)}, "
                         f"got {mode!r}")
    tau = blockers @ sh_basis(-evaluation)
    if mode == "statistical":
        return np.exp(-np.maximum(tau, 0.0))
    return 1.0 - np.clip(tau, 0.0, 1.0)


def _used(raw: np.ndarray, clamped: bool, budget: np.ndarray | None
          ) -> tuple[np.ndarray, np.ndarray]:
    """(the intensity a face sends, the intensity the clamp left it before the budget):
    ``raw``, clamp+ on a clamped face; under the flux budget clamp+ on every face, and it
    sends that times the source's factor (docs/MODEL.md "Flux budget")."""
    if budget is not None:
        positive = np.maximum(raw, 0.0)
        return budget * positive, positive
    used = np.maximum(raw, 0.0) if clamped else raw
    return used, used


def _every_face(corrections: Corrections, neighbours: int):
    """(evaluation direction, weight) of every face a cell sends through in one step."""
    if neighbours == 26:
        scale = (reprojection_factor(corrections) * injection_factor(corrections)
                 * propagation_factor(corrections))
        for offset in OFFSETS_26:
            for evaluation, _, angle, _ in outer_faces_26(offset):
                yield evaluation, scale * angle
        return
    front_weight, side_weight = face_weights(corrections)
    for axis, sign in DIRECTIONS:
        for evaluation, _, is_front in _faces(axis, sign, corrections.side_faces):
            yield evaluation, front_weight if is_front else side_weight


def flux_budget_scale(grid: np.ndarray, corrections: Corrections | None = None,
                      neighbours: int = 6) -> np.ndarray:
    """(3, nx, ny, nz) factor of every source cell's faces under the flux budget
    (docs/MODEL.md "Flux budget"): with S = Σ_f π·w_f·clamp+(I_f) over all its faces and Φ
    = clamp+(flux of the cell), Φ/S where S > Φ, else 1; each face then sends
    factor·clamp+(I_f), so no cell sends more than it holds and no face sends negative
    light."""
    corrections = corrections or Corrections()
    grid = _check_grid(grid)
    order = grid_sh_order(grid)
    lobe_flux = K.SH_FLUX_FACTOR * cosine_lobe(np.array([0.0, 0.0, 1.0]), order)[0]
    positive = np.zeros(grid.shape[:4])
    for evaluation, weight in _every_face(corrections, neighbours):
        positive += weight * lobe_flux * np.maximum(grid @ sh_basis(evaluation, order), 0.0)
    held = np.maximum(K.SH_FLUX_FACTOR * grid[..., 0], 0.0)
    return np.where(positive > held, held / np.where(positive > held, positive, 1.0), 1.0)


AUDIT_TERMS = ("propagated", "clamp_gain", "occluded", "border_loss", "reflected", "blocked",
               "budget_withheld")
DIRECTIONS = tuple((axis, sign) for axis in range(3) for sign in (1, -1))
"""The six propagation directions sign·e_axis."""
CELL_TERMS = ("received", "border_loss", "clamp_gain", "occluded", "reflected", "blocked",
              "budget_withheld")
"""The per-cell audit record of a step, in the order of ``shaders/audit_reduce.glsl``:
each (3, N, N, N) watts, booked to the cell whose invocation of ``shaders/propagate.glsl``
computes it (:func:`propagation_step_cells`)."""


def _check_step_inputs(grid, geometry, geometry_albedo, bounces):
    grid = _check_grid(grid)
    n = grid.shape[1:4]
    geometry = _check_geometry(geometry, n)
    if bounces not in (1, 2):
        raise ValueError(f"bounces must be 1 or 2, got {bounces!r}")
    if bounces == 2 and geometry is None:
        raise ValueError("bounces=2 reflects the light the geometry volume blocks: pass "
                         "a geometry volume")
    if bounces == 2:
        geometry_albedo = _check_geometry(
            np.zeros_like(geometry) if geometry_albedo is None else geometry_albedo, n)
    return grid, geometry, geometry_albedo


def _direction_step(grid: np.ndarray, axis: int, sign: int, corrections: Corrections,
                    geometry: np.ndarray | None, geometry_albedo: np.ndarray | None,
                    reflect: bool, visibility_mode: str = "linear",
                    budget: np.ndarray | None = None, reprojection: str = "face-normal"
                    ) -> tuple[np.ndarray, np.ndarray, dict[str, np.ndarray], np.ndarray]:
    """What every source cell sends along ``sign``·e_axis in one step: the light delivered
    into the neighbour cells (3, N, N, N, K) (zero in the first layer, which has no source
    inside), the light reflected back into the source cells (zeros unless ``reflect``),
    this direction's audit terms per cell ((3, N, N, N) watts each, :data:`AUDIT_TERMS`
    but ``propagated``) and its ``propagated`` flux (3,). A term is booked as the GPU
    books it: a face that stays inside the grid to its target cell, which gathers it; a
    face leaving the grid, its border loss, and the light reflected back and blocked, to
    the source cell. ``visibility_mode``: :func:`face_visibility`; ``budget``: the flux
    budget's factors (:func:`flux_budget_scale`), None without it; ``reprojection``:
    :func:`reprojection_axis`."""
    order = grid_sh_order(grid)
    shape = grid.shape[1:4]
    n = shape[axis]
    front_weight, side_weight = face_weights(corrections)
    delivered = np.zeros_like(grid)
    reflected_back = np.zeros_like(grid)
    cells = {name: np.zeros((3, *shape)) for name in AUDIT_TERMS if name != "propagated"}
    propagated = np.zeros(3)
    blockers = None if geometry is None else _face_blockers(geometry, axis, sign)
    blocked = np.zeros((3, *shape))   # flux the volume takes, per source cell
    # Sources whose neighbour along the direction is inside, and those neighbours.
    inside = [slice(None)] * 3
    shifted = [slice(None)] * 3
    leaving = [slice(None)] * 3
    inside[axis] = slice(0, n - 1) if sign > 0 else slice(1, n)
    shifted[axis] = slice(1, n) if sign > 0 else slice(0, n - 1)
    leaving[axis] = slice(n - 1, n) if sign > 0 else slice(0, 1)
    every, to_target = (slice(None), *inside), (slice(None), *shifted)
    border = (slice(None), *leaving)

    def book(name: str, per_source: np.ndarray) -> None:
        """Add a per-source-cell term: to the target where the face stays inside the
        grid, to the source itself where it leaves."""
        cells[name][to_target] += per_source[every]
        cells[name][border] += per_source[border]

    for evaluation, normal, is_front in _faces(axis, sign, corrections.side_faces):
        weight = front_weight if is_front else side_weight
        lobe = cosine_lobe(reprojection_axis(normal, evaluation, reprojection), order)
        flux_per_intensity = weight * K.SH_FLUX_FACTOR * lobe[0]
        raw = grid @ sh_basis(evaluation, order)                 # (3, N, N, N)
        used, clamped = _used(raw, is_front and corrections.clamp_front_face, budget)
        # blocking of light travelling along e_f hits surfels facing -e_f
        visibility = np.ones(shape) if blockers is None else face_visibility(
            blockers, evaluation, visibility_mode)
        sent = weight * used * visibility                         # (3, N, N, N)
        delivered[to_target] += sent[every][..., None] * lobe
        book("clamp_gain", flux_per_intensity * (clamped - raw))
        book("budget_withheld", flux_per_intensity * (clamped - used))
        book("occluded", flux_per_intensity * used * (1.0 - visibility))
        cells["border_loss"][border] += K.SH_FLUX_FACTOR * lobe[0] * sent[border]
        propagated += flux_per_intensity * raw.reshape(3, -1).sum(1)
        blocked += flux_per_intensity * used * (1.0 - visibility)
    if reflect:
        sums = _face_blockers(geometry_albedo, axis, sign)           # (N, N, N, 4)
        area = sums[..., 3]
        albedo = np.divide(sums[..., :3], area[..., None],
                           out=np.zeros_like(sums[..., :3]), where=area[..., None] > 0)
        bounced = np.maximum(blocked, 0.0)
        cells["blocked"] += bounced
        reflected = np.moveaxis(albedo, -1, 0) * bounced
        lobes = cosine_lobe(_reflection_normals(blockers, axis, sign), order)
        per_watt = lobes / (K.SH_FLUX_FACTOR * lobes[..., :1])
        reflected_back += reflected[..., None] * per_watt
        cells["reflected"] += reflected
    return delivered, reflected_back, cells, propagated


OFFSETS_26 = tuple((a, b, c) for a in (-1, 0, 1) for b in (-1, 0, 1) for c in (-1, 0, 1)
                   if (a, b, c) != (0, 0, 0))


def outer_faces_26(offset: tuple[int, int, int]) -> list[tuple[np.ndarray, np.ndarray, float,
                                                                bool]]:
    """(evaluation direction, reprojection direction, solid angle, is front) of the faces
    of neighbour ``offset`` on the surface of the 3×3×3 block around the source (one per
    non-zero component; docs/MODEL.md "26 neighbours")."""
    kind = sum(1 for c in offset if c)
    angle = (K.FRONT_FACE_SOLID_ANGLE, K.EDGE_FACE_SOLID_ANGLE,
             K.CORNER_FACE_SOLID_ANGLE)[kind - 1]
    faces = []
    for axis in range(3):
        if offset[axis] == 0:
            continue
        centre = 2.0 * np.asarray(offset, np.float64)
        centre[axis] = 3.0 * offset[axis]
        normal = np.zeros(3)
        normal[axis] = offset[axis]
        faces.append((centre / np.linalg.norm(centre), normal, angle, kind == 1))
    return faces


def _shared_corner_blockers(geometry: np.ndarray, offset: tuple[int, int, int]) -> np.ndarray:
    """(nx, ny, nz, 4): for every source cell s, the mean geometry SH over the corners s
    shares with s + offset (4 for a face neighbour: :func:`_face_blockers`; 2 for an edge,
    1 for a corner neighbour)."""
    parts = [geometry]
    for axis, o in enumerate(offset):
        picks = [slice(1, None)] if o > 0 else [slice(0, -1)] if o < 0 else [
            slice(0, -1), slice(1, None)]
        parts = [part[(slice(None),) * axis + (pick,)] for part in parts for pick in picks]
    return sum(parts) / len(parts)


def _offset_step(grid: np.ndarray, offset: tuple[int, int, int], corrections: Corrections,
                 geometry: np.ndarray | None, visibility_mode: str = "linear",
                 budget: np.ndarray | None = None, reprojection: str = "face-normal"
                 ) -> tuple[np.ndarray, dict[str, np.ndarray], np.ndarray]:
    """What every source cell sends to its neighbour ``offset`` through that neighbour's
    outer faces (the 26-neighbour step): delivered light, audit terms per cell (booked as
    :func:`_direction_step` books them) and the ``propagated`` flux (3,)."""
    order = grid_sh_order(grid)
    shape = grid.shape[1:4]
    scale = (reprojection_factor(corrections) * injection_factor(corrections)
             * propagation_factor(corrections))
    delivered = np.zeros_like(grid)
    cells = {name: np.zeros((3, *shape)) for name in AUDIT_TERMS if name != "propagated"}
    propagated = np.zeros(3)
    blockers = None if geometry is None else _shared_corner_blockers(geometry, offset)
    source = tuple(slice(0, n - 1) if o > 0 else slice(1, n) if o < 0 else slice(None)
                   for o, n in zip(offset, shape))
    target = tuple(slice(1, n) if o > 0 else slice(0, n - 1) if o < 0 else slice(None)
                   for o, n in zip(offset, shape))
    stays = np.zeros(shape, bool)
    stays[source] = True
    every, to_target = (slice(None), *source), (slice(None), *target)
    for evaluation, normal, angle, is_front in outer_faces_26(offset):
        weight = scale * angle
        lobe = cosine_lobe(reprojection_axis(normal, evaluation, reprojection), order)
        flux_per_intensity = weight * K.SH_FLUX_FACTOR * lobe[0]
        raw = grid @ sh_basis(evaluation, order)
        used, clamped = _used(raw, is_front and corrections.clamp_front_face, budget)
        visibility = np.ones(shape) if blockers is None else face_visibility(
            blockers, evaluation, visibility_mode)
        sent = weight * used * visibility
        delivered[to_target] += sent[every][..., None] * lobe
        for name, term in (("clamp_gain", flux_per_intensity * (clamped - raw)),
                           ("budget_withheld", flux_per_intensity * (clamped - used)),
                           ("occluded", flux_per_intensity * used * (1.0 - visibility))):
            cells[name][to_target] += term[every]
            cells[name] += np.where(stays, 0.0, term)
        cells["border_loss"] += np.where(stays, 0.0, K.SH_FLUX_FACTOR * lobe[0] * sent)
        propagated += flux_per_intensity * raw.reshape(3, -1).sum(1)
    return delivered, cells, propagated


def propagation_step(grid: np.ndarray, corrections: Corrections | None = None,
                     geometry: np.ndarray | None = None,
                     geometry_albedo: np.ndarray | None = None, bounces: int = 1,
                     neighbours: int = 6, visibility: str = "linear",
                     flux_budget: bool = False, reprojection: str = "face-normal"
                     ) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """One step P(grid) in scatter form, and its audit terms (each (3,) watts):
    ``propagated`` (flux of all faces, unclamped and unoccluded), ``clamp_gain``,
    ``occluded``, ``border_loss``, ``reflected``, ``blocked`` (the blocked flux that can
    bounce: per source cell and direction, clamp+; only with ``bounces`` 2) and
    ``budget_withheld`` (what the flux budget's factor took from the clamped faces; 0
    without the budget). L1 or L2 after the grid's last axis; the geometry volume is L1
    either way. The step's balance: flux(P(grid)) = propagated + clamp_gain −
    budget_withheld − occluded − border_loss + reflected.

    ``bounces`` 2 (docs/MODEL.md "More bounces"): for every source cell and direction,
    the flux the geometry volume blocks on the five faces, clamp+, times the shared face's
    area-weighted mean albedo (``geometry_albedo`` sums), goes back into the source cell as
    a cosine lobe (of the grid's order) around the blockers' normal.

    ``visibility``: the geometry volume's :func:`face_visibility`; ``flux_budget``: each
    source cell sends at most its own flux (:func:`flux_budget_scale`; needs ping-pong
    and bounces 1); ``reprojection``: the axis of each face's lobe
    (:func:`reprojection_axis`)."""
    out, cells, propagated = _step_with_cells(grid, corrections, geometry, geometry_albedo,
                                              bounces, neighbours, visibility, flux_budget,
                                              reprojection)
    terms = {name: value.reshape(3, -1).sum(1) for name, value in cells.items()
             if name != "received"}
    return out, {"propagated": propagated, **terms}


def propagation_step_cells(grid: np.ndarray, corrections: Corrections | None = None,
                           geometry: np.ndarray | None = None,
                           geometry_albedo: np.ndarray | None = None, bounces: int = 1,
                           neighbours: int = 6, visibility: str = "linear",
                           flux_budget: bool = False, reprojection: str = "face-normal"
                           ) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """One step P(grid) and its audit record per cell (:data:`CELL_TERMS`, each
    (3, N, N, N) watts), as ``shaders/propagate.glsl`` writes it for the cell whose
    invocation computes it: ``received`` the flux of the cell's new value (everything the
    step delivered into it, reflections included); ``border_loss`` the flux the cell sent
    out of the grid (border cells only); ``clamp_gain``, ``budget_withheld`` and
    ``occluded`` those of the faces the cell gathered through, and of the faces it sent
    out of the grid;
    ``reflected`` and ``blocked`` (``bounces`` 2) those of the light the cell sent. Summed
    over the cells they are :func:`propagation_step`'s terms, and ``received`` sums to
    the flux of the new grid."""
    out, cells, _ = _step_with_cells(grid, corrections, geometry, geometry_albedo, bounces,
                                     neighbours, visibility, flux_budget, reprojection)
    return out, cells


def _step_with_cells(grid, corrections, geometry, geometry_albedo, bounces, neighbours=6,
                     visibility="linear", flux_budget=False, reprojection="face-normal"):
    """(P(grid), the per-cell terms, the propagated total (3,)); ``neighbours`` 6 or 26."""
    corrections = corrections or Corrections()
    neighbours = check_neighbours(neighbours, corrections, bounces)
    check_flux_budget(flux_budget, corrections, bounces)
    grid, geometry, geometry_albedo = _check_step_inputs(grid, geometry, geometry_albedo,
                                                         bounces)
    budget = flux_budget_scale(grid, corrections, neighbours) if flux_budget else None
    out = np.zeros_like(grid)
    cells = {name: np.zeros((3, *grid.shape[1:4])) for name in CELL_TERMS}
    propagated = np.zeros(3)
    for offset in (OFFSETS_26 if neighbours == 26 else ()):
        delivered, direction_cells, direction_propagated = _offset_step(
            grid, offset, corrections, geometry, visibility, budget, reprojection)
        out += delivered
        propagated += direction_propagated
        for name, value in direction_cells.items():
            cells[name] += value
    for axis, sign in (DIRECTIONS if neighbours == 6 else ()):
        delivered, reflected, direction_cells, direction_propagated = _direction_step(
            grid, axis, sign, corrections, geometry, geometry_albedo, bounces == 2,
            visibility, budget, reprojection)
        out += delivered + reflected
        propagated += direction_propagated
        for name, value in direction_cells.items():
            cells[name] += value
    cells["received"] = K.SH_FLUX_FACTOR * out[..., 0]
    return out, cells, propagated


def in_place_step_candidates(before: np.ndarray, after: np.ndarray,
                             corrections: Corrections | None = None,
                             geometry: np.ndarray | None = None,
                             geometry_albedo: np.ndarray | None = None, bounces: int = 1,
                             reprojection: str = "face-normal") -> np.ndarray:
    """(64, 3, N, N, N, K): every value the in-place propagation step (``ping_pong``
    False, ``shaders/propagate.glsl``) can add to a cell, one per read schedule.

    In place, one dispatch reads and writes the accumulated grid: the invocation of cell x
    reads its six source neighbours x − d, each of which another invocation may or may not
    have updated already, then writes ``acc[x] + received`` once. So the step it adds is
    ``Σ_d D_d(source read) + R(acc_{t−1}[x])``, where each neighbour's read is either its
    value ``before`` the step (acc_{t−1}) or ``after`` it (acc_t: every cell is written
    exactly once per step), and R, the reflection of the cell's own blocked light
    (``bounces`` 2), always sees its own cell before its own write. Candidate ``j`` reads
    direction ``DIRECTIONS[i]`` after the update where bit i of j is set (j = 0 is the
    race-free reading of :func:`propagate_audited`). Which candidate a GPU produces depends
    on its invocation order; the statement that holds on every GPU is that each cell's
    step is one of these, per colour channel (r, g and b are separate images, each read
    whole: one texel per cell with L1). ``reprojection``: :func:`reprojection_axis`."""
    corrections = corrections or Corrections()
    before, geometry, geometry_albedo = _check_step_inputs(before, geometry,
                                                           geometry_albedo, bounces)
    after = _check_grid(after)
    if after.shape != before.shape:
        raise ValueError(f"before and after must have the same shape, got {before.shape} "
                         f"and {after.shape}")
    own = np.zeros_like(before)
    reads = []
    for axis, sign in DIRECTIONS:
        old, reflected, _, _ = _direction_step(before, axis, sign, corrections, geometry,
                                               geometry_albedo, bounces == 2,
                                               reprojection=reprojection)
        new, _, _, _ = _direction_step(after, axis, sign, corrections, geometry,
                                       geometry_albedo, False, reprojection=reprojection)
        own += reflected
        reads.append((old, new))
    candidates = np.empty((2 ** len(DIRECTIONS),) + before.shape)
    for j in range(len(candidates)):
        candidates[j] = own + sum(pair[(j >> i) & 1] for i, pair in enumerate(reads))
    return candidates


def propagate_audited(grid: np.ndarray, corrections: Corrections | None = None,
                      iterations: int = 1, geometry: np.ndarray | None = None,
                      geometry_albedo: np.ndarray | None = None, bounces: int = 1,
                      neighbours: int = 6, visibility: str = "linear",
                      flux_budget: bool = False, reprojection: str = "face-normal"
                      ) -> tuple[list[np.ndarray], np.ndarray, GridAudit]:
    """grid_0..grid_N, acc_N and the audit. Ping-pong: grid_t = P(grid_{t−1}); in place:
    grid_t = P(acc_{t−1}) (the light step t adds). Either way acc_N = Σ grid_t.
    ``geometry_albedo``, ``bounces``, ``neighbours``, ``visibility``, ``flux_budget``,
    ``reprojection``: see :func:`propagation_step`."""
    corrections = corrections or Corrections()
    check_neighbours(neighbours, corrections, bounces)
    check_flux_budget(flux_budget, corrections, bounces)
    grid = _check_grid(grid)
    if int(iterations) < 0:
        raise ValueError(f"iterations must be >= 0, got {iterations}")
    steps = [grid]
    accumulated = grid.copy()
    terms = {name: [] for name in AUDIT_TERMS if name != "propagated"}
    for _ in range(int(iterations)):
        source = steps[-1] if corrections.ping_pong else accumulated
        step, step_terms = propagation_step(source, corrections, geometry, geometry_albedo,
                                            bounces, neighbours, visibility, flux_budget,
                                            reprojection)
        for name in terms:
            terms[name].append(step_terms[name])
        steps.append(step)
        accumulated = accumulated + step
    empty = np.zeros((0, 3))
    audit = GridAudit(
        injected=flux(grid),
        per_step=np.stack([flux(step) for step in steps]),
        border_loss=np.array(terms["border_loss"]).reshape(-1, 3) if iterations else empty,
        clamp_gain=np.array(terms["clamp_gain"]).reshape(-1, 3) if iterations else empty,
        occluded=np.array(terms["occluded"]).reshape(-1, 3) if iterations else empty,
        accumulated=flux(accumulated),
        reflected=np.array(terms["reflected"]).reshape(-1, 3) if iterations else empty,
        blocked=np.array(terms["blocked"]).reshape(-1, 3) if iterations else empty,
        budget_withheld=(np.array(terms["budget_withheld"]).reshape(-1, 3) if iterations
                         else empty),
    )
    return steps, accumulated, audit


def propagate(grid: np.ndarray, corrections: Corrections | None = None, iterations: int = 1,
              geometry: np.ndarray | None = None, geometry_albedo: np.ndarray | None = None,
              bounces: int = 1, neighbours: int = 6, visibility: str = "linear",
              flux_budget: bool = False, reprojection: str = "face-normal"
              ) -> list[np.ndarray]:
    """grid_0..grid_N (see :func:`propagate_audited`)."""
    return propagate_audited(grid, corrections, iterations, geometry, geometry_albedo,
                             bounces, neighbours, visibility, flux_budget, reprojection)[0]


# --------------------------------------------------------------------------- final gather


def sample_grid(grid: np.ndarray, spec: GridSpec, points: np.ndarray) -> np.ndarray:
    """Trilinear lookup of a (3, nx, ny, nz, K) grid (K = 4 or 9) at world points (P, 3) ->
    (3, P, K): texel centres at ``i + ½``, clamped to the edge (docs/MODEL.md "Final
    gather"; every coefficient group of an L2 grid clamps to the grid's own edge)."""
    grid = np.asarray(grid, np.float64)
    last = np.asarray(spec.cells) - 1
    u = spec.grid_coords(np.asarray(points, np.float64)) - 0.5
    base = np.floor(u).astype(np.int64)
    frac = u - base
    out = np.zeros((grid.shape[0], len(u), grid.shape[-1]))
    for corner in np.ndindex(2, 2, 2):
        offset = np.array(corner)
        weight = np.prod(np.where(offset == 1, frac, 1.0 - frac), axis=1)
        ix, iy, iz = np.clip(base + offset, 0, last).T
        out += weight[None, :, None] * grid[:, ix, iy, iz, :]
    return out


def gather_irradiance(grid: np.ndarray, spec: GridSpec, positions: np.ndarray,
                      normals: np.ndarray, offset: float = 0.0, *,
                      irradiance: bool = True) -> np.ndarray:
    """(P, 3) irradiance ``clamp+(⟨s(x), lobe(−n)⟩)/h²`` at ``x = p + offset·n`` (world
    units; docs/MODEL.md "Final gather"), with the L1 or L2 lobe after the grid's order;
    ``irradiance`` False (the ``irradiance_gather`` switch off): the DX11 shader's
    ``clamp+(⟨s(x), Y(−n)⟩)``, the intensity toward −n, with no cell area."""
    normals = np.asarray(normals, np.float64)
    samples = sample_grid(grid, spec, np.asarray(positions, np.float64) + offset * normals)
    order = grid_sh_order(grid)
    kernel = cosine_lobe(-normals, order) if irradiance else sh_basis(-normals, order)
    values = np.maximum(np.einsum("cpk,pk->pc", samples, kernel), 0.0)
    return values / spec.cell_size ** 2 if irradiance else values


def derivative_damping(grid: np.ndarray, spec: GridSpec, positions: np.ndarray,
                       normals: np.ndarray, *, irradiance: bool = True) -> np.ndarray:
    """(P, 3) factors ``clamp(E(p + ½h·n)/E(p − ½h·n), 0, 1)`` per channel, 1 where
    ``E(p − ½h·n) = 0`` (docs/MODEL.md "Final gather", derivative damping)."""
    half = 0.5 * spec.cell_size
    front = gather_irradiance(grid, spec, positions, normals, half, irradiance=irradiance)
    back = gather_irradiance(grid, spec, positions, normals, -half, irradiance=irradiance)
    ratio = np.divide(front, back, out=np.ones_like(front), where=back > 0)
    return np.clip(ratio, 0.0, 1.0)


def net_flux_kernel(direction: np.ndarray, sh_order: int = 1) -> np.ndarray:
    """(P, K) SH projection of ``⟨d, ω⟩`` for unit directions ``d`` (P, 3): band 1 only,
    ``SH_NET_FLUX_C1·(−d_y, d_z, −d_x)`` (docs/MODEL.md "Net-flux gather")."""
    d = np.atleast_2d(np.asarray(direction, np.float64))
    kernel = np.zeros((len(d), (_order(sh_order) + 1) ** 2))
    kernel[:, 1:4] = K.SH_NET_FLUX_C1 * np.stack([-d[:, 1], d[:, 2], -d[:, 0]], axis=1)
    return kernel


def net_flux_irradiance(grid: np.ndarray, spec: GridSpec, positions: np.ndarray,
                        normals: np.ndarray, exitance: np.ndarray) -> np.ndarray:
    """(P, 3) ``clamp+(−⟨n, F(p)⟩/h² + M)``: the light vector ``F`` of the grid at ``p``
    (band 1, exact for L1 and L2) taken against ``n`` plus the surface's own exitance ``M``
    (P, 3) (docs/MODEL.md "Net-flux gather")."""
    normals = np.asarray(normals, np.float64)
    samples = sample_grid(grid, spec, np.asarray(positions, np.float64))
    kernel = net_flux_kernel(-normals, grid_sh_order(grid))
    net = np.einsum("cpk,pk->pc", samples, kernel) / spec.cell_size ** 2
    return np.maximum(net + np.asarray(exitance, np.float64), 0.0)


def gather(grid: np.ndarray, spec: GridSpec, positions: np.ndarray, normals: np.ndarray,
           damping: bool = False, *, irradiance: bool = True,
           exitance: np.ndarray | None = None) -> np.ndarray:
    """(P, 3) indirect irradiance the final gather computes at surface points: E(p), times
    the derivative damping factor when ``damping`` (``irradiance``: as in
    :func:`gather_irradiance`); with ``exitance`` (P, 3), the surfaces' own exitance
    ``a·E_direct``, E(p) is the net-flux gather's (:func:`net_flux_irradiance`)."""
    if exitance is not None:
        if not irradiance:
            raise ValueError("the net-flux gather needs the irradiance gather")
        values = net_flux_irradiance(grid, spec, positions, normals, exitance)
    else:
        values = gather_irradiance(grid, spec, positions, normals, irradiance=irradiance)
    if damping:
        values = values * derivative_damping(grid, spec, positions, normals,
                                             irradiance=irradiance)
    return values


def gather_cascades(grids: list[np.ndarray], specs: list[GridSpec], positions: np.ndarray,
                    normals: np.ndarray, damping: bool = False, *,
                    irradiance: bool = True, exitance: np.ndarray | None = None
                    ) -> np.ndarray:
    """(P, 3) irradiance of nested cascades, finest first: ``Σ_k W_k·E_k`` with the blend
    weights ``W_k`` of docs/MODEL.md "Cascades" and ``E_k`` cascade k's :func:`gather`
    (damped over half of its own cell when ``damping``; ``irradiance`` as there). One
    cascade is :func:`gather`, which alone takes ``exitance`` (the net-flux gather)."""
    if len(grids) != len(specs) or not grids:
        raise ValueError(f"need one grid per cascade spec, got {len(grids)} grids and "
                         f"{len(specs)} specs")
    if exitance is not None:
        if len(grids) != 1:
            raise ValueError("the net-flux gather takes one cascade, got "
                             f"{len(grids)}")
        return gather(grids[0], specs[0], positions, normals, damping,
                      irradiance=irradiance, exitance=exitance)
    weights = blend_weights(list(specs), positions)
    total = np.zeros((len(weights), 3))
    for k, (grid, spec) in enumerate(zip(grids, specs)):
        total += weights[:, k:k + 1] * gather(grid, spec, positions, normals, damping,
                                              irradiance=irradiance)
    return total


def indirect_radiance(albedo: np.ndarray, irradiance: np.ndarray) -> np.ndarray:
    """Outgoing indirect radiance ``a/π·E`` of a Lambertian surface (docs/MODEL.md "Final
    gather")."""
    return np.asarray(albedo, np.float64) / K.PI * np.asarray(irradiance, np.float64)
