"""A step's LPV running live in its web page (a lesson step with ``live_lpv = true``).

The build writes what the browser cannot make cheaply, for the step's settings: the
G-buffer of the step's camera (position, normal with the pixel's area, albedo) and, for the
step's light and a few others the reader can pick (:data:`LIGHT_AIMS`), the direct light
and the RSM's VPLs of every light view, as little-endian Float32 arrays in one ``.bin``
file each (named by its content, so steps that share them share the file), fetched on
first use; the grid specs of the sizes the page offers; the corrections registry, the
presets and the display's tone-map constants. The page
(``assets/lpv/``) runs injection and propagation in float64 in a Worker (``twin.js``, a
port of explorer/lpv/twin/light_grid.py), gathers on the G-buffer with WebGL2 and tone-maps as the
window does; without WebGL2 or module scripts it keeps the baked picture.

What the page's LPV cannot do (several cascades, L2, fog, glossy reflections, a second
bounce, camera occluders, downsampled VPLs) makes :func:`unsupported` name the setting,
and the build stops with it.
"""

from __future__ import annotations

import hashlib
import html
import json
from importlib.resources import files
from pathlib import Path

import numpy as np

GRID_SIZES = (8, 16, 24, 32)
"""The grid sizes the page offers (with the step's own). A toggle at 32³ and 16
iterations took 0.3 to 0.4 s from click to picture in headless Chromium on the 2-core VM
(2026-12-02, idle); 64³ would take about eight times that."""
MAX_WIDTH = 400
"""Pixels of the live G-buffer's width at most (its height keeps the view's aspect)."""
LIGHT_AIMS = (("the step's light", 0.0), ("aimed further left", -0.3),
              ("aimed further right", 0.3))
"""(label, shift) of the lights the reader can pick: the step's light with its target moved
along x by ``shift`` times the scene's width."""
ASSET_FOLDER = "lpv"
"""Under the site's ``assets/``: the page's modules (``explorer/site/assets/lpv``)."""
DATA_FOLDER = "live"
"""Under the site root: the baked arrays, one file per content (``<sha1>.bin``), so live
steps with the same scene, camera and light share their files."""


def unsupported(settings) -> str | None:
    """Why the page's LPV cannot run ``settings`` (a Settings field and its value), or
    None when it can."""
    checks = (("cascades", settings.cascades != 1), ("sh_order", settings.sh_order != 1),
              ("fog", settings.fog), ("glossy", settings.glossy),
              # the geometry volume is built from the RSM's texels, not the merged VPLs
              ("downsample", settings.downsample != "none"),
              ("bounces", settings.bounces != 1),
              ("camera_occluders", bool(settings.uses_camera_occluders)),
              # the page's propagation has neither the budget pass nor exp(−τ) visibility,
              # and reprojects along the face normals only
              ("flux_budget", settings.flux_budget),
              ("reprojection", settings.reprojection != "face-normal"),
              ("geometry_visibility", settings.geometry_visibility != "linear"
               and settings.geometry_volume != "off"))
    for name, refused in checks:
        if refused:
            return f"{name} = {getattr(settings, name)!r}"
    return None


def live_size(size: tuple[int, int]) -> tuple[int, int]:
    """The live G-buffer's pixels for a view of ``size``: at most :data:`MAX_WIDTH` wide."""
    width, height = size
    if width <= MAX_WIDTH:
        return width, height
    return MAX_WIDTH, max(1, round(height * MAX_WIDTH / width))


def copy_assets(assets: Path) -> None:
    """Copy the page's modules into the site's ``assets/`` folder, with the generated
    constants module they import (``assets/generated/constants.js``)."""
    shipped = files("explorer.site") / "assets"
    for name, suffixes in ((ASSET_FOLDER, (".js", ".css")), ("generated", (".js",))):
        folder = assets / name
        folder.mkdir(exist_ok=True)
        for entry in (shipped / name).iterdir():
            if entry.name.endswith(suffixes):
                (folder / entry.name).write_bytes(entry.read_bytes())


class _Arrays:
    """Float32 arrays written one after another into one file, with their places."""

    def __init__(self) -> None:
        self.parts: list[bytes] = []
        self.offset = 0

    def add(self, array: np.ndarray) -> list[int]:
        data = np.ascontiguousarray(array, "<f4").tobytes()
        place = [self.offset // 4, len(data) // 4]   # in floats
        self.parts.append(data)
        self.offset += len(data)
        return place

    def write(self, folder: Path) -> str:
        """Write the arrays as ``folder/<sha1 of the bytes>.bin`` (once) and return its
        name."""
        data = b"".join(self.parts)
        name = f"{hashlib.sha1(data).hexdigest()[:20]}.bin"
        if not (folder / name).is_file():
            (folder / name).write_bytes(data)
        return name


def light_choices(settings) -> list[tuple[str, tuple]]:
    """(label, Settings.light) of every light the reader can pick: the primary light of
    the step's scene with its target moved along x (:data:`LIGHT_AIMS`)."""
    from explorer.scene.loader import load_scene

    scene = load_scene(settings.scene).for_settings(settings)
    light = scene.light
    width = float(scene.bounds_max[0] - scene.bounds_min[0])
    choices = []
    for label, shift in LIGHT_AIMS:
        target = np.asarray(light.target, np.float64) + np.array([shift * width, 0.0, 0.0])
        choices.append((label, (tuple(map(float, light.position)),
                                tuple(map(float, target)))))
    return choices


def grid_specs(settings, scene_bounds) -> dict[str, dict]:
    """The grid of every size the page offers: origin and cell size (the frame's own
    ``frame_specs`` at that size)."""
    from explorer.lpv.cascades import frame_specs

    class _Bounds:                  # the built-in scenes the page offers: a fitted cube
        bounds_min, bounds_max = scene_bounds
        exact_grid = None

    sizes = sorted(set(GRID_SIZES) | {int(settings.grid_size)})
    specs = {}
    for size in sizes:
        spec = frame_specs(settings.with_changes(grid_size=size), _Bounds)[0]
        specs[str(size)] = {"origin": list(spec.origin), "cellSize": spec.cell_size,
                            "resolution": spec.resolution}
    return specs


def _step_settings(settings) -> dict:
    """The Settings fields the page's LPV reads, as the step sets them."""
    return {"grid_size": int(settings.grid_size), "iterations": int(settings.iterations),
            "corrections": {name: bool(getattr(settings.corrections, name))
                            for name in settings.corrections.names()},
            "injection_offset_cells": float(settings.injection_offset_cells),
            "geometry_volume": settings.geometry_volume,
            "gather_damping": bool(settings.gather_damping),
            "neighbours": int(settings.neighbours),
            "exposure": float(settings.exposure), "auto_exposure": bool(settings.auto_exposure),
            "tone_map": settings.tone_map, "indirect_only": bool(settings.indirect_only)}


def registry() -> dict:
    """The corrections registry and the presets as the page's controls need them."""
    from explorer.lpv.corrections import CORRECTIONS, PRESETS

    return {"corrections": [{"name": entry.name, "title": entry.title, "why": entry.why,
                             "published": entry.published} for entry in CORRECTIONS],
            "presets": {name: {entry.name: bool(getattr(preset, entry.name))
                               for entry in CORRECTIONS}
                        for name, preset in PRESETS.items()}}


def max_iterations() -> int:
    """The iterations slider's top: the Scene panel's (the Settings field's widget)."""
    from explorer.lpv.settings import Settings
    from explorer.schema import specs

    spec = specs(Settings)["iterations"]
    return int(spec.widget_high if spec.widget_high is not None else spec.high)


def display_constants() -> dict:
    """explorer/lpv/twin/tonemap.py's curve and auto exposure, for the page's port of it."""
    from explorer.lpv.twin import tonemap

    return {"tone_maps": list(tonemap.TONE_MAPS), "aces_fit": list(tonemap.ACES_FIT),
            "key": tonemap.AUTO_EXPOSURE_KEY,
            "percentiles": list(tonemap.METERED_PERCENTILES),
            "floor": tonemap.LOG_AVERAGE_FLOOR, "luma": tonemap.REC709_LUMA.tolist()}


def bake(ctx, settings, root: Path, size: tuple[int, int]) -> dict:
    """Render ``settings`` at the live size of ``size`` for every light choice, write the
    arrays into ``root/live/`` and return the description the page reads; the caller
    checks :func:`unsupported` first."""
    from explorer.lpv.pipeline import Pipeline

    width, height = live_size(size)
    settings = settings.with_changes(width=width, height=height)
    folder = root / DATA_FOLDER
    folder.mkdir(parents=True, exist_ok=True)
    relative = folder.relative_to(root).as_posix()
    lights, gbuffer, specs, opening = [], None, None, None
    pipeline = Pipeline(settings, ctx=ctx)
    try:
        for label, light in light_choices(settings):
            frame = pipeline.run(settings.with_changes(light=light), need_audit="flux")
            if gbuffer is None:
                arrays = _Arrays()
                gbuffer = {"arrays": {
                    "position": arrays.add(frame.gbuffer_position[..., :4]),
                    "normal": arrays.add(frame.gbuffer_normal[..., :4]),
                    "albedo": arrays.add(frame.albedo[..., :3])}}
                gbuffer["url"] = f"{relative}/{arrays.write(folder)}"
                gbuffer["bytes"] = arrays.offset
                specs = grid_specs(settings, frame.scene_bounds)
                # the window's flux in flight per step of the step as it opens (W)
                opening = np.asarray(frame.audit.per_step).sum(axis=1).tolist()
            arrays = _Arrays()
            views = [{"count": vpls.count, "texelArea": float(vpls.texel_area),
                      "projection": vpls.projection,
                      "positions": arrays.add(vpls.positions),
                      "normals": arrays.add(vpls.normals), "flux": arrays.add(vpls.flux),
                      "depth": arrays.add(vpls.depth)} for vpls in frame.vpl_sets]
            entry = {"label": label, "light": [list(light[0]), list(light[1])],
                     "direct": arrays.add(frame.direct[..., :3]), "views": views}
            entry["url"] = f"{relative}/{arrays.write(folder)}"
            entry["bytes"] = arrays.offset
            lights.append(entry)
    finally:
        pipeline.release()
    description = {"width": width, "height": height, "gbuffer": gbuffer, "lights": lights,
                   "grids": specs, "step": _step_settings(settings),
                   "window_per_step": opening,
                   "display": display_constants(), "max_iterations": max_iterations(),
                   **registry()}
    return description


def step_figure(ctx, step, root: Path, size: tuple[int, int], baked_picture: str,
                alt: str) -> str:
    """Bake a live step (a lesson Step) and return its figure; ValueError naming the
    setting when the page's LPV cannot run the step."""
    settings = step.settings()
    reason = unsupported(settings)
    if reason is not None:
        raise ValueError(f"live_lpv: the page's LPV cannot run {reason}")
    description = bake(ctx, settings, root, size)
    # the picture the step shows: its indirect light alone, or the final image
    description["view"] = "indirect" if step.view == "indirect" else "final"
    return figure(description, baked_picture, alt)


def figure(description: dict, baked_picture: str, alt: str) -> str:
    """The live LPV's HTML: the baked picture (shown until the live one is drawn, and
    kept without WebGL2 or module scripts), the controls the script fills in, and the
    description as JSON."""
    first = (description["gbuffer"]["bytes"] + description["lights"][0]["bytes"]) / 2 ** 20
    # "<" escaped: the JSON sits inside a script element
    data = json.dumps(description, separators=(",", ":")).replace("<", "\\u003c")
    return (f'<figure class="live-lpv" data-live-lpv>'
            f'<div class="live-view"><img src="{html.escape(baked_picture)}" '
            f'alt="{html.escape(alt)}" class="live-baked" loading="lazy" decoding="async">'
            '<canvas class="live-canvas" hidden></canvas></div>'
            '<div class="live-controls" hidden></div>'
            f'<figcaption>The LPV of this step, live: switch each correction, a preset, '
            f"the iterations, the grid size, 6 or 26 neighbours or the light, and the page "
            f"runs injection and "
            f"propagation again in float64 (a port of the explorer's numpy twin) and "
            f"gathers the picture with WebGL2. The first change loads "
            f"{first:.1f} MB of baked G-buffer and VPLs.<span class=\"live-status\" "
            'role="status"></span></figcaption>'
            '<noscript><p>The live LPV needs JavaScript; the picture above is the baked '
            "one.</p></noscript>"
            f'<script type="application/json" class="live-description">{data}'
            "</script></figure>")


def module_script() -> str:
    """The tags that style and start every live LPV of a page. Module scripts and
    ``fetch`` refuse ``file://`` pages, so there a classic script says so under each live
    figure (the baked picture stays) instead of failing with a console error."""
    return (f'<link rel="stylesheet" href="assets/{ASSET_FOLDER}/live.css">'
            "<script>(function () {"
            'if (location.protocol !== "file:") {'
            # after the page is parsed: an import map the page adds comes before it
            'document.addEventListener("DOMContentLoaded", function () {'
            'var s = document.createElement("script"); s.type = "module";'
            f's.src = "assets/{ASSET_FOLDER}/live.js"; document.body.appendChild(s); }});'
            "return; }"
            'document.querySelectorAll("[data-live-lpv] .live-status").forEach(function (e) {'
            'e.textContent = " The live LPV needs the site served over HTTP (for instance '
            "python3 -m http.server in the site's folder): opened as a file, the page shows "
            'the baked picture."; });'
            "})();</script>")
