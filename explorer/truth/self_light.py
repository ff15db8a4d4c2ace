"""Where an LPV frame's indirect light comes from: per source surface and receiver surface,
per colour channel, against the one-bounce reference of the same VPLs.

The frame's VPLs are split by the surface they lie on (the scene's parts,
explorer/scene/parts.py); each set is injected and propagated alone (the pipeline takes
hand-made VPLs, so the rest of the frame is the same) and gathered, with the reference of
the same set beside it. The LPV is linear in its VPLs (up to the gather's clamp, whose
effect :attr:`SelfLight.closure` measures), so the sets add up to the frame. The
*self* term of a surface is the light its own VPLs give back to it: zero for a plane or a
convex block in the reference (no point of a plane sees another of the same plane), and
in the LPV the light the grid smears along the surface it was injected from.

``python -m explorer.truth.self_light --scene cornell`` prints the table (docs/ERRORS.md
"Why blue is too bright"); ``--net-flux`` with the net-flux gather, whose own-exitance term
counts as each surface's light onto itself.
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass

import numpy as np

from explorer.lpv.vpl import VplArrays


def vpl_surfaces(scene, positions: np.ndarray, normals: np.ndarray,
                 tolerance: float = 1e-3) -> np.ndarray:
    """(M,) index into the scene's surface names of the triangle each VPL lies on: the
    nearest triangle plane, among those whose normal is the VPL's up to its sign, whose
    triangle holds the VPL's projection; −1 for a VPL on none."""
    from explorer.scene.parts import surface_names

    triangles = np.asarray(scene.positions, np.float64).reshape(-1, 3, 3)
    names = surface_names(scene).triangle_names
    points = np.asarray(positions, np.float64)
    directions = np.asarray(normals, np.float64)
    best = np.full(len(points), -1)
    best_distance = np.full(len(points), np.inf)
    for index, (a, b, c) in enumerate(triangles):
        normal = np.cross(b - a, c - a)
        length = np.linalg.norm(normal)
        if length == 0:
            continue
        normal /= length
        height = (points - a) @ normal
        edge0, edge1, offset = b - a, c - a, points - a - height[:, None] * normal
        d00, d01, d11 = edge0 @ edge0, edge0 @ edge1, edge1 @ edge1
        d20, d21 = offset @ edge0, offset @ edge1
        det = d00 * d11 - d01 * d01
        v = (d11 * d20 - d01 * d21) / det
        w = (d00 * d21 - d01 * d20) / det
        inside = (v >= -tolerance) & (w >= -tolerance) & (v + w <= 1 + tolerance)
        facing = np.abs(directions @ normal) > 0.99
        distance = np.where(inside & facing, np.abs(height), np.inf)
        better = distance < best_distance
        best[better], best_distance[better] = index, distance[better]
    found = np.full(len(points), -1)
    on = best >= 0
    found[on] = names[best[on]]
    return found


def subset(vpls: VplArrays, keep: np.ndarray) -> VplArrays:
    return VplArrays(np.asarray(vpls.positions)[keep], np.asarray(vpls.normals)[keep],
                     np.asarray(vpls.flux)[keep], np.asarray(vpls.depth)[keep],
                     vpls.texel_area, vpls.projection,
                     None if vpls.albedo is None else np.asarray(vpls.albedo)[keep])


@dataclass
class SelfLight:
    """The flux (sum of radiance over the receiver's pixels, per channel) each source
    surface gives each receiver, in the LPV and in the reference."""

    names: tuple[str, ...]
    lpv: np.ndarray
    """(sources, receivers, 3)."""
    reference: np.ndarray
    """(sources, receivers, 3)."""
    closure: np.ndarray
    """(3,) Σ over the sources' LPV images / the whole frame's LPV image: 1 when the
    sets add up to the frame."""

    def shares(self) -> dict[str, np.ndarray]:
        """Per channel: the LPV's self term (every surface's light onto itself), its light
        between surfaces, and the reference's total, all over the whole image."""
        index = np.arange(len(self.names))
        own = self.lpv[index, index].sum(axis=0)
        return {"lpv self": own, "lpv between": self.lpv.sum(axis=(0, 1)) - own,
                "reference": self.reference.sum(axis=(0, 1))}


def net_flux_image(grid: np.ndarray, spec, gbuffer, exitance: np.ndarray,
                   own: np.ndarray) -> np.ndarray:
    """(H, W, 3) the net-flux gather's indirect radiance ``a/π·(−⟨n, F⟩/h² + M)`` of one
    source's grid (docs/MODEL.md "Net-flux gather"), unclamped so that the sources add up;
    the exitance ``M`` (H, W, 3) counts only on the source's own pixels ``own`` (H, W): it
    is the light the source's VPLs stand for where they lie."""
    from explorer.lpv.twin import light_grid as twin

    image = np.zeros(gbuffer.valid.shape + (3,))
    valid = gbuffer.valid
    samples = twin.sample_grid(grid, spec, gbuffer.position[valid])
    kernel = twin.net_flux_kernel(-np.asarray(gbuffer.normal[valid], np.float64),
                                  twin.grid_sh_order(grid))
    irradiance = np.einsum("cpk,pk->pc", samples, kernel) / spec.cell_size ** 2
    irradiance += np.where(own[valid][:, None], exitance[valid], 0.0)
    image[valid] = twin.indirect_radiance(gbuffer.albedo[valid], irradiance)
    return image


def measure(settings, ctx, scene=None) -> SelfLight:
    """:class:`SelfLight` of the frame ``settings`` renders (the reference with shadow
    rays, r_min half a cell)."""
    from explorer.lpv.pipeline import Pipeline
    from explorer.scene.parts import surface_names
    from explorer.truth.gbuffer import scene_for
    from explorer.truth.render import reference_for_frame
    from explorer.truth.surface_masks import render_triangle_ids, surface_masks

    scene = scene if scene is not None else scene_for(settings)
    names = tuple(surface_names(scene).names)
    with Pipeline(settings, ctx) as pipeline:
        frame = pipeline.run(settings)
        vpls = frame.vpls
        sources = vpl_surfaces(scene, vpls.positions, vpls.normals)
        masks = surface_masks(scene, render_triangle_ids(ctx, scene, settings.width,
                                                         settings.height), names)
        whole = np.asarray(frame.indirect, np.float64)[..., :3]
        if settings.gather_net_flux:   # the gather adds a·E_direct, split by surface below
            from explorer.truth.gbuffer import gbuffer_from_frame

            gbuffer = gbuffer_from_frame(frame, ctx=ctx)
            exitance = np.pi * np.asarray(frame.direct, np.float64)[..., :3]
        min_distance = 0.5 * frame.grid_spec.cell_size
        lpv = np.zeros((len(names), len(names), 3))
        reference = np.zeros_like(lpv)
        summed = np.zeros_like(whole)
        for source in range(len(names)):
            keep = (sources == source) & (np.asarray(vpls.flux).sum(axis=1) > 0)
            if not keep.any():
                continue
            part = pipeline.run(settings, vpls=subset(vpls, keep))
            image = (net_flux_image(part.accumulated, part.grid_spec, gbuffer, exitance,
                                    masks[names[source]]) if settings.gather_net_flux
                     else np.asarray(part.indirect, np.float64)[..., :3])
            truth, _ = reference_for_frame(part, True, min_distance, ctx=ctx, scene=scene)
            summed += image
            for receiver, name in enumerate(names):
                lpv[source, receiver] = image[masks[name]].sum(axis=0)
                reference[source, receiver] = truth[masks[name]].sum(axis=0)
    total = whole.sum(axis=(0, 1))
    closure = np.where(total > 0, summed.sum(axis=(0, 1)) / np.where(total > 0, total, 1), 1)
    return SelfLight(names, lpv, reference, closure)


def format_report(result: SelfLight) -> str:
    def rgb(values) -> str:
        return ", ".join(f"{v:.1f}" for v in values)

    lines = ["| source surface | LPV onto itself (r, g, b) | LPV onto the others | "
             "reference onto the others | reference onto itself |",
             "|---|---|---|---|---|"]
    for index, name in enumerate(result.names):
        own = result.lpv[index, index]
        others = result.lpv[index].sum(axis=0) - own
        truth_own = result.reference[index, index]
        truth_others = result.reference[index].sum(axis=0) - truth_own
        lines.append(f"| {name} | {rgb(own)} | {rgb(others)} | {rgb(truth_others)} | "
                     f"{rgb(truth_own)} |")
    shares = result.shares()
    lines += ["", "| channel | LPV self | LPV between surfaces | reference | LPV / reference | "
              "(LPV − self) / reference |", "|---|---:|---:|---:|---:|---:|"]
    for channel, name in enumerate("rgb"):
        own, between, truth = (shares[key][channel] for key in
                               ("lpv self", "lpv between", "reference"))
        lines.append(f"| {name} | {own:.1f} | {between:.1f} | {truth:.1f} | "
                     f"{(own + between) / truth:.3f} | {between / truth:.3f} |")
    lines += ["", "sources summed / frame (the gather's clamp): "
              + ", ".join(f"{v:.4f}" for v in result.closure)]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    from explorer.lpv.settings import Settings

    parser = argparse.ArgumentParser(prog="python -m explorer.truth.self_light",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", default="cornell")
    parser.add_argument("--size", type=int, default=96, help="image edge in pixels")
    parser.add_argument("--rsm-size", type=int, default=64)
    parser.add_argument("--grid-size", type=int, default=32)
    parser.add_argument("--iterations", type=int, default=16)
    parser.add_argument("--geometry-volume", default="off")
    parser.add_argument("--injection-offset", type=float, default=0.5)
    parser.add_argument("--preset", default="corrected")
    parser.add_argument("--sh-order", type=int, default=1)
    parser.add_argument("--neighbours", type=int, default=6)
    parser.add_argument("--net-flux", action="store_true",
                        help='the net-flux gather (docs/MODEL.md "Net-flux gather")')
    args = parser.parse_args(argv)
    try:
        settings = Settings(scene=args.scene, width=args.size, height=args.size,
                            rsm_size=args.rsm_size, grid_size=args.grid_size,
                            iterations=args.iterations, geometry_volume=args.geometry_volume,
                            injection_offset_cells=args.injection_offset, sh_order=args.sh_order
                            ).with_changes(corrections=args.preset, neighbours=args.neighbours,
                                           gather_net_flux=args.net_flux)
    except (ValueError, KeyError) as exc:
        print(f"{parser.prog}: error: {exc}", file=sys.stderr)
        return 2
    from explorer.gl.context import given_or_headless

    with given_or_headless(None) as ctx:
        print(format_report(measure(settings, ctx)))
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
