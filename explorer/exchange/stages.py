"""A frame's stages as named float arrays: what ``render --dump`` writes and ``diff``
reads. The names, shapes and units are listed in :data:`ARRAYS` (the sidecar copies
them); the arrays are the FrameResult's own, not converted, so a dump equals the Python
API to the last bit (``Pipeline.run(keep_steps=True)``)."""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

GRID_STEP = re.compile(r"^(?:cascade(?P<cascade>[1-9]\d*)_)?grid_(?P<step>\d+)$")
"""``grid_t`` of cascade 0, ``cascade<k>_grid_t`` of cascade k ≥ 1."""
VIEW_PREFIX = re.compile(r"^(?:cascade|view)[1-9]\d*_")
"""``cascade<k>_`` (cascade k ≥ 1) and ``view<k>_`` (RSM view k ≥ 1) before an array's
name."""


@dataclass(frozen=True)
class ArrayDoc:
    """What one array of a dump holds."""

    shape: str
    units: str
    holds: str


ARRAYS: dict[str, ArrayDoc] = {
    "rsm_position": ArrayDoc("(Hr, Wr, 4)", "world units",
                             "RSM (the first light view; view<k>_rsm_* view k's, the "
                             "sidecar's rsm_views says whose): world position of the surface "
                             "each texel sees; w = 1 where it sees one, 0 elsewhere; row 0 at "
                             "the top"),
    "rsm_normal": ArrayDoc("(Hr, Wr, 4)", "unitless; w in world units",
                           "RSM: unit surface normal (xyz, towards the light for a two-sided "
                           "surface); w = view depth of the texel from the light"),
    "rsm_flux": ArrayDoc("(Hr, Wr, 4)", "W", "RSM: flux the texel's surfel reflects, per "
                         "colour channel (rgb); w unused"),
    "vpl_position": ArrayDoc("(M, 3)", "world units", "VPLs injected (after downsampling): "
                             "world position"),
    "vpl_normal": ArrayDoc("(M, 3)", "unitless", "VPLs: unit normal (the Lambertian lobe's "
                           "axis)"),
    "vpl_flux": ArrayDoc("(M, 3)", "W", "VPLs: flux per colour channel"),
    "vpl_view": ArrayDoc("(M,)", "index", "VPLs: the RSM view each comes from (the "
                         "sidecar's rsm_views[k]: its light, face, matrices and its VPLs' "
                         "rows vpl_first … vpl_first + vpls − 1); absent for VPLs handed in "
                         "with --vpls"),
    "vpl_depth": ArrayDoc("(M,)", "world units", "VPLs: view depth from the light (the "
                          "geometry volume's surfel area texel_area·depth²)"),
    "vpl_albedo": ArrayDoc("(M, 3)", "unitless", "VPLs: diffuse reflectance of the VPL's "
                           "surface (bounces 2 reflect blocked light with it); absent: 0"),
    "vpl_texel_area": ArrayDoc("()", "world units² at depth 1 (perspective) or world "
                               "units² (orthographic)",
                               "area of one RSM texel, the first RSM view's (several views: "
                               "each one's is in the sidecar's rsm_views; VPLs fed back "
                               "through --vpls use this one for all)"),
    "vpl_orthographic": ArrayDoc("()", "bool", "true: vpl_texel_area is a world area "
                                 "(directional light), false: an area at depth 1 "
                                 "(perspective: the surfel's area is texel_area·depth²)"),
    "grid_origin": ArrayDoc("(3,)", "world units", "world position of the grid's minimum "
                            "corner (cascade 0)"),
    "grid_cell_size": ArrayDoc("()", "world units", "edge of one cell (cascade 0)"),
    "grid_t": ArrayDoc("(3, nx, ny, nz, C)", "W/sr (SH coefficients of radiant intensity)",
                       "light in flight after t propagation steps (grid_0: injected); "
                       "index [colour, x, y, z, k], C = 4 (L1) or 9 (L2)"),
    "accumulated": ArrayDoc("(3, nx, ny, nz, C)", "W/sr", "acc_N = Σ_t grid_t: the grid the "
                            "final gather samples"),
    "geometry_volume": ArrayDoc("(nx+1, ny+1, nz+1, 4)", "unitless (blocking probability SH)",
                                "L1 SH of the occluders' blocking, cell centres on the "
                                "light grid's corners: geometry cell g centred at origin + "
                                "g·cell_size; absent when the geometry volume is off"),
    "gbuffer_position": ArrayDoc("(H, W, 4)", "world units", "camera G-buffer: world "
                                 "position, w = 1 where a surface is seen; row 0 at the top"),
    "gbuffer_normal": ArrayDoc("(H, W, 4)", "unitless; w in world units²", "camera "
                               "G-buffer: viewer-facing normal, w = world area of the surface "
                               "under the pixel"),
    "albedo": ArrayDoc("(H, W, 3)", "unitless", "linear diffuse reflectance per pixel"),
    "received": ArrayDoc("(H, W, 3)", "W", "LPV flux the pixel's surface receives: E·A "
                         "(A = gbuffer_normal w)"),
    "irradiance": ArrayDoc("(H, W, 3)", "W/m² (world units⁻²)", "indirect irradiance E the "
                           "gather reads from the grid: received / A (float32 on the CPU), "
                           "0 where no surface is seen"),
    "direct": ArrayDoc("(H, W, 3)", "W/(m² sr)", "direct radiance, no exposure"),
    "indirect": ArrayDoc("(H, W, 3)", "W/(m² sr)", "LPV radiance albedo/π·E (+ glossy), no "
                         "exposure"),
    "final": ArrayDoc("(H, W, 3)", "W/(m² sr) × exposure", "exposure·(direct + indirect), "
                      "(indirect only with indirect_only; fog composed over it): what the "
                      "display scales by display_scale and tone-maps"),
    "reference": ArrayDoc("(H, W, 3)", "W/(m² sr)", "compare only: the one-bounce reference "
                          "radiance from the same VPLs at the same pixels"),
    "fog_transmittance": ArrayDoc("(H, W)", "unitless", "fog: exp(−σ_t·ℓ) to the surface"),
    "fog_direct": ArrayDoc("(H, W, 3)", "W/(m² sr)", "fog: the direct light in-scattered"),
    "fog_lpv": ArrayDoc("(H, W, 3)", "W/(m² sr)", "fog: the LPV light in-scattered"),
}
"""Every array name a dump may hold. ``grid_t`` stands for grid_0 … grid_N; cascades
k ≥ 1 add ``cascade<k>_`` before ``grid_t``, ``accumulated``, ``geometry_volume``,
``grid_origin`` and ``grid_cell_size``; RSM views k ≥ 1 (several lights, a point light's
six faces) add ``view<k>_`` before ``rsm_position``, ``rsm_normal`` and ``rsm_flux``."""

CASCADE_ARRAYS = ("grid_origin", "grid_cell_size", "accumulated", "geometry_volume")


def doc_of(name: str) -> ArrayDoc | None:
    """The :class:`ArrayDoc` of an array name (grid steps and cascade prefixes included);
    None for a name no dump writes."""
    match = GRID_STEP.match(name)
    if match:
        return ARRAYS["grid_t"]
    return ARRAYS.get(VIEW_PREFIX.sub("", name))


def irradiance(received: np.ndarray, normal_area: np.ndarray) -> np.ndarray:
    """``E = received / A`` per pixel (float32), 0 where the pixel sees no surface (A 0)."""
    area = np.asarray(normal_area, np.float32)[..., 3:4]
    out = np.zeros_like(np.asarray(received, np.float32))
    np.divide(received, area, out=out, where=area > 0)
    return out


def frame_arrays(result, reference: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """Every stage of ``result`` (a FrameResult, its steps kept for the grid_t) by the
    names of :data:`ARRAYS`; ``reference`` adds compare's reference image."""
    arrays: dict[str, np.ndarray] = {
        "rsm_position": result.rsm_position, "rsm_normal": result.rsm_normal,
        "rsm_flux": result.rsm_flux,
    }
    for k, (position, normal, flux) in enumerate(result.rsm_views[1:], 1):
        arrays.update({f"view{k}_rsm_position": position, f"view{k}_rsm_normal": normal,
                       f"view{k}_rsm_flux": flux})
    vpls = result.vpls
    arrays.update(vpl_position=np.asarray(vpls.positions), vpl_normal=np.asarray(vpls.normals),
                  vpl_flux=np.asarray(vpls.flux), vpl_depth=np.asarray(vpls.depth),
                  vpl_texel_area=np.asarray(vpls.texel_area, np.float64),
                  vpl_orthographic=np.asarray(vpls.projection == "orthographic"))
    if vpls.albedo is not None:
        arrays["vpl_albedo"] = np.asarray(vpls.albedo)
    if not result.vpls_hand_made and result.vpl_sets:
        arrays["vpl_view"] = np.repeat(np.arange(len(result.vpl_sets), dtype=np.int32),
                                       [vpl_set.count for vpl_set in result.vpl_sets])
    for k, level in enumerate(result.cascades):
        prefix = f"cascade{k}_" if k else ""
        arrays[prefix + "grid_origin"] = np.asarray(level.spec.origin, np.float64)
        arrays[prefix + "grid_cell_size"] = np.asarray(level.spec.cell_size, np.float64)
        for t, step in enumerate(level.steps or ()):
            arrays[f"{prefix}grid_{t}"] = step
        arrays[prefix + "accumulated"] = level.accumulated
        if level.geometry_volume is not None:
            arrays[prefix + "geometry_volume"] = level.geometry_volume
    arrays.update(gbuffer_position=result.gbuffer_position,
                  gbuffer_normal=result.gbuffer_normal, albedo=result.albedo)
    if result.received is not None:
        arrays["received"] = result.received
        arrays["irradiance"] = irradiance(result.received, result.gbuffer_normal)
    arrays.update(direct=result.direct, indirect=result.indirect, final=result.final_image)
    if result.fog is not None:
        arrays.update(fog_transmittance=result.fog.transmittance, fog_direct=result.fog.direct,
                      fog_lpv=result.fog.lpv)
    if reference is not None:
        arrays["reference"] = np.asarray(reference)
    return {name: np.asarray(value) for name, value in arrays.items()}


def view_arrays(arrays: dict[str, np.ndarray]) -> list[dict[str, np.ndarray]]:
    """A dump's arrays view by view (the sidecar's ``rsm_views`` order): each RSM view's
    ``rsm_position``, ``rsm_normal``, ``rsm_flux`` (those the dump holds) and its own rows
    of every ``vpl_*`` array of one row per VPL (by ``vpl_view``; none without it)."""
    count = 1 + max([int(m.group(1)) for m in map(re.compile(r"^view(\d+)_rsm_").match,
                                                    arrays) if m] or [0])
    if "vpl_view" in arrays and arrays["vpl_view"].size:
        count = max(count, int(arrays["vpl_view"].max()) + 1)
    rows = len(arrays["vpl_view"]) if "vpl_view" in arrays else None
    views = []
    for k in range(count):
        prefix = f"view{k}_" if k else ""
        view = {f"rsm_{part}": arrays[prefix + f"rsm_{part}"]
                for part in ("position", "normal", "flux") if prefix + f"rsm_{part}" in arrays}
        if rows is not None:
            mine = arrays["vpl_view"] == k
            view.update({name: array[mine] for name, array in arrays.items()
                         if name.startswith("vpl_") and name != "vpl_view"
                         and array.ndim >= 1 and len(array) == rows})
        views.append(view)
    return views
