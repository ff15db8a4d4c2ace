"""Settings of one LPV frame.

The switches between published and corrected formulas (:class:`Corrections`, the
presets) come from the corrections registry (``derivations/correction_registry.py``, made
into the dataclass by ``explorer/lpv/corrections.py``); they are imported here because
much code reads them from this module.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from explorer.lpv.corrections import CORRECTIONS, PRESETS, Corrections, preset  # noqa: F401
from explorer.lpv.stage_list import STAGES
from explorer.scene.lights import LIGHT_KINDS, MAX_CONE_DEGREES
from explorer.scene.model import MAX_LIGHTS
from explorer.scene.objects import check_transforms
from explorer.schema import (
    SettingError,
    check_stages,
    from_dict,
    setting,
    to_dict,
    validate,
)


def preset_name(corrections: Corrections) -> str:
    """The name of the preset equal to ``corrections``, or ``"custom"``."""
    for name, value in PRESETS.items():
        if value == corrections:
            return name
    return "custom"


TONE_MAPS = ("linear-clip", "filmic")
"""``Settings.tone_map`` choices; their index is the GLSL ``TONE_MAP_*`` constant."""
DOWNSAMPLE_MODES = ("none", "average", "brightest")
INJECTION_MODES = ("points", "compute")
GEOMETRY_VOLUME_MODES = ("off", "one-sided", "double-sided")
GEOMETRY_VISIBILITY_MODES = ("linear", "statistical")
"""``Settings.geometry_visibility``: V = 1 − clamp(τ, 0, 1) (the LPV paper's blocker) or
V = exp(−τ) (surfels placed independently at random; docs/MODEL.md "Geometry volume")."""
REPROJECTION_MODES = ("face-normal", "face-centre")
"""``Settings.reprojection``: the axis of the cosine lobe a face's light becomes in the
target cell, the face's normal (the LPV paper's) or the direction from the source cell's
centre to the face's centre (docs/MODEL.md "Propagation"); the index is the GLSL
``PROPAGATE_REPROJECTION``."""
GRID_FORMATS = ("rgba32f", "rgba16f")
SH_ORDERS = (1, 2)
"""1 = L1 spherical harmonics (4 coefficients per colour), 2 = L2 (9)."""
BOUNCES = (1, 2)
NEIGHBOURHOODS = (6, 26)
FOG_PHASES = ("isotropic", "henyey-greenstein")
MAX_FOG_G = 0.95
"""|g| of the Henyey–Greenstein phase function: at |g| = 1 it is a delta (no longer a
function to march with), and near it the lobe is far narrower than anything an L1 or L2
grid resolves."""
MAX_FOG_STEPS = 512
MAX_GLOSSY_SAMPLES = 32
MAX_INJECTION_OFFSET_CELLS = 1.0
"""A VPL moved by more than a cell would skip the cell in front of its surface."""
MAX_CASCADES = 4
CASCADE_ITERATIONS = ("same", "same-distance")
MAX_GRID_SIZE = 256
"""256³ cells × 3 colours × 4 grids of RGBA32F is 3.2 GB: beyond that no GPU holds a grid
and its ping-pong copies (the pipeline's texture budget refuses smaller ones too)."""
MAX_ITERATIONS = 1024
"""Light moves one cell per step: after 3·256 steps it has left the largest grid."""
MAX_RSM_SIZE = 4096
MAX_IMAGE_SIZE = 8192
MAX_SHADOW_KERNEL = 9
"""Widest PCF box in shadow-map texels (the gather fetches (k+1)² texels per pixel)."""
DEFAULT_SHADOW_KERNEL = 3
"""``Settings.shadow_kernel``'s default (also the gather pass's)."""


@dataclass(frozen=True)
class Settings:
    """Everything a frame depends on. Immutable: the app compares settings to know
    whether the pipeline must run again.

    Every field is declared with :func:`explorer.schema.setting`: its type and range
    are checked when a Settings is made, and the command line, persisted files, lessons,
    the Scene panel and the pipeline's cache keys are all derived from these declarations.
    """

    scene: str = setting(
        "cornell", kind="str", flag="--scene", stages=("scene",),
        doc="A built-in scene name, a scene file (.toml: meshes, lights, camera, grid box; "
            "docs/SCENES.md) or a path to a mesh file trimesh can read.")
    corrections: Corrections = setting(
        kind="nested", nested=Corrections, default_factory=Corrections,
        # the stages whose programs read any switch (the registry says which per switch)
        stages=tuple(stage for stage in STAGES
                     if any(stage in entry.stages for entry in CORRECTIONS)),
        doc="The switches between the published and the corrected formulas.")
    grid_size: int = setting(
        32, kind="int", low=1, high=MAX_GRID_SIZE, flag="--grid", widget="combo",
        suggested=(8, 16, 24, 32, 48, 64), label="Grid size (cells³)",
        group="Light propagation volume", stages=("grid",),
        doc="Cells along each edge of the (each cascade's) grid: N³ cells, fitted around "
            "the scene's box (unless an exact grid's cells, origin and cell size are "
            "given).")
    grid_cells: tuple[int, int, int] | None = setting(
        None, kind="int3", optional=True, low=1, high=MAX_GRID_SIZE, flag="--grid-cells",
        stages=("grid",),
        doc="An exact grid's cells along x, y, z (with grid_origin and grid_cell_size, all "
            "three or none): it replaces the fitted grid_size³ cube and the scene file's "
            "[grid] cells; None = the scene's, else the fitted cube.")
    grid_origin: tuple[float, float, float] | None = setting(
        None, kind="point", optional=True, flag="--grid-origin", stages=("grid",),
        unit="m", doc="An exact grid's minimum corner in world units (with grid_cells).")
    grid_cell_size: float | None = setting(
        None, kind="float", optional=True, low=0.0, low_open=True, high=1e6,
        flag="--grid-cell-size", stages=("grid",), unit="m",
        doc="An exact grid's cell edge in world units (with grid_cells).")
    iterations: int = setting(
        16, kind="int", low=0, high=MAX_ITERATIONS, flag="--iterations", widget="slider",
        widget_high=64, label="Iterations", group="Light propagation volume",
        stages=("propagate",),
        doc="Propagation steps: light moves one cell per step.")
    rsm_size: int = setting(
        256, kind="int", low=1, high=MAX_RSM_SIZE, flag="--rsm-size", widget="combo",
        suggested=(64, 128, 256, 512, 1024), label="RSM size (texels²)",
        group="Light propagation volume", stages=("rsm",),
        doc="Resolution of the (square) reflective shadow map.")
    rsm_snap: bool = setting(
        False, kind="bool", flag="--rsm-snap", widget="checkbox", label="Snap RSM to texels",
        group="Light propagation volume", stages=("rsm",),
        doc="Move each light's RSM view by whole texels of its image plane only, so that a "
            "light moving by less than a texel keeps its VPLs in place (docs/MODEL.md "
            "\"Moving objects and temporal stability\"); off: the view follows the light "
            "exactly (its VPLs swim; `lpv-explorer stability --snap rsm` measures it).")
    downsample: str = setting(
        "none", kind="choice", choices=DOWNSAMPLE_MODES, flag="--downsample",
        widget="combo", label="Downsample", group="Light propagation volume",
        stages=("downsample",),
        doc="Merge blocks of RSM texels into one VPL before injection: none, their "
            "average, or the brightest.")
    downsample_factor: int = setting(
        2, kind="int", low=1, high=16, flag="--downsample-factor", widget="slider",
        widget_high=8, label="Downsample factor", group="Light propagation volume",
        stages=("downsample",),
        doc="Edge of the block of RSM texels merged into one VPL.")
    injection_mode: str = setting(
        "points", kind="choice", choices=INJECTION_MODES, flag="--injection-mode",
        widget="combo", label="Injection", group="Light propagation volume",
        stages=("inject",),
        doc="points: one point primitive per VPL with additive blending (DX11); compute: "
            "each cell gathers its VPLs (DX12 proposal).")
    geometry_volume: str = setting(
        "off", kind="choice", choices=GEOMETRY_VOLUME_MODES, flag="--geometry-volume",
        label="Geometry volume", group="Light propagation volume", stages=("geometry",),
        doc="Fuzzy occlusion from the RSM's surfels: off, one-sided or double-sided.")
    geometry_visibility: str = setting(
        "linear", kind="choice", choices=GEOMETRY_VISIBILITY_MODES,
        flag="--geometry-visibility", widget="combo", label="GV visibility",
        group="Light propagation volume", stages=("propagate",),
        doc="How a face's blocking τ (the geometry volume's surfels, one- or double-sided) "
            "becomes its visibility: linear V = 1 − clamp(τ, 0, 1), as published; "
            "statistical V = exp(−τ), the chance that a ray passes surfels placed "
            'independently at random (docs/MODEL.md "Geometry volume"); does nothing '
            "while the volume is off.")
    grid_format: str = setting(
        "rgba32f", kind="choice", choices=GRID_FORMATS, flag="--grid-format",
        widget="combo", label="Grid format", group="Light propagation volume",
        stages=("inject", "geometry"),
        doc="Texel format of the light and geometry grids (32- or 16-bit float).")
    sh_order: int = setting(
        1, kind="choice", choices=SH_ORDERS, flag="--sh-order", widget="combo",
        label="SH order", group="Light propagation volume", stages=("inject",),
        doc="SH order of the light grid: 1 = L1 (4 coefficients per colour channel, as "
            "published), 2 = L2 (9; injection, propagation and gather use band 2 too; "
            "docs/MODEL.md \"L2 option\"). The geometry volume stays L1.")
    # --- cascaded LPV (docs/MODEL.md "Cascades", explorer/lpv/cascades.py) ---
    cascades: int = setting(
        1, kind="int", low=1, high=MAX_CASCADES, flag="--cascades", widget="slider",
        label="Cascades", group="Cascades", stages=("grid",),
        doc="Nested grids of N³ cells (N the grid size), each with twice the cell size of "
            "the last; 1 = the single grid enclosing the scene.")
    cascade_extent: float | None = setting(
        None, kind="float", optional=True, low=1e-6, high=1e6, flag="--cascade-extent",
        widget="input", label="Finest extent", unit="m", group="Cascades",
        stages=("grid",),
        doc="Edge of the finest cascade in world units; None = the single grid's extent "
            "divided by 2^(cascades−1), so the coarsest cascade has the single grid's "
            "cells.")
    cascade_focus: float = setting(
        1.0, kind="float", low=0.0, high=1.0, flag="--cascade-focus", widget="slider",
        label="Cascade focus", group="Cascades", stages=("grid",),
        doc="Where the cascades are centred on the camera's line of sight: 0 = at the "
            "eye, 1 = at the camera's target (each cascade then snaps to its own cells).")
    cascade_snap: bool = setting(
        True, kind="bool", flag="--cascade-snap", widget="checkbox", label="Snap to cells",
        group="Cascades", stages=("grid",),
        doc="Snap each cascade to the lattice of its own cells, so that a moving camera "
            "moves it by whole cells only; off: centred exactly on the focus point (the "
            "light swims as the camera moves; `lpv-explorer stability` measures it).")
    cascade_iterations: str = setting(
        "same", kind="choice", choices=CASCADE_ITERATIONS, flag="--cascade-iterations",
        widget="combo", label="Cascade iterations", group="Cascades",
        stages=("propagate",),
        doc='"same": every cascade propagates ``iterations`` steps (the LPV paper), so '
            "light travels 2^k finest cells per step in cascade k; \"same-distance\": "
            "cascade k propagates ``iterations·2^(cascades−1−k)`` steps, so every cascade "
            "carries light as far (in world units) as the coarsest.")
    width: int = setting(
        512, kind="int", low=1, high=MAX_IMAGE_SIZE, stages=("gbuffer",),
        doc="Width of the rendered image in pixels (command line: --size WxH).")
    height: int = setting(
        512, kind="int", low=1, high=MAX_IMAGE_SIZE, stages=("gbuffer",),
        doc="Height of the rendered image in pixels (command line: --size WxH).")
    exposure: float = setting(
        1.0, kind="float", low=0.0, low_open=True, high=1e6, flag="--exposure",
        stages=("display",),
        doc="Multiplier of the linear radiance before display.")
    indirect_only: bool = setting(
        False, kind="bool", flag="--indirect-only", stages=("display",),
        doc="Show only the LPV's indirect light in the final image.")
    camera: tuple[tuple[float, float, float], tuple[float, float, float]] | None = setting(
        None, kind="points", optional=True, stages=("grid", "gbuffer"),
        doc="(eye, target) in world units; None = the scene's default camera.")
    light: tuple[tuple[float, float, float], tuple[float, float, float]] | None = setting(
        None, kind="points", optional=True, stages=("rsm",),
        doc="(position, target) of the primary light (the first that shines; a point "
            "light ignores the target); None = where the scene puts it.")
    camera_fov: float | None = setting(
        None, kind="float", optional=True, low=1.0, high=170.0, stages=("grid", "gbuffer"),
        unit="°", doc="Vertical field of view of the camera in degrees; None = the scene's.")
    light_kind: str | None = setting(
        None, kind="choice", optional=True, choices=LIGHT_KINDS, stages=("rsm",),
        doc="Make the primary light a spot, point or directional light (at the light's "
            "position setting, else where the scene's is; its flux then gives about 2 W/m² "
            "at its target unless the light flux setting says otherwise); None = the "
            "scene's kind.")
    light_flux: float | None = setting(
        None, kind="float", optional=True, low=0.0, low_open=True, high=1e12,
        flag="--light-flux", stages=("rsm",),
        doc="Total flux of the primary light in watts per channel; None = the scene's "
            "default.")
    lights: tuple[str, ...] | None = setting(
        None, kind="name_set", optional=True, high=MAX_LIGHTS, flag="--lights",
        stages=("rsm",),
        doc=f"Names of the scene's lights that shine, the first being the primary light "
            f"(1 to {MAX_LIGHTS}; e.g. cornell: spot, bulb, lamp, sun); each has its own "
            f'RSM and all inject into one grid (docs/MODEL.md "Several lights"). None = '
            f"the scene's own choice.")
    object_transforms: tuple[tuple[str, tuple[float, ...]], ...] = setting(
        (), kind="transforms", parse=check_transforms, flag="--object", stages=("scene",),
        doc="Moved objects: object name -> [tx, ty, tz, rx, ry, rz, sx, sy, sz] "
            "(translation, rotation in degrees about x then y then z, scale; about the "
            "object's pivot, explorer/scene/objects.py); 3 or 6 numbers leave the rest "
            "unchanged. The RSM, the G-buffer and everything after them follow.")
    debug_nan: bool = setting(
        False, kind="bool", flag="--debug-nan", label="Check passes for NaN/Inf",
        widget="checkbox", group="Output",
        doc="Check every pass for NaN/Inf and name the pass that produced one.")
    injection_offset_cells: float = setting(
        0.5, kind="float", low=0.0, high=MAX_INJECTION_OFFSET_CELLS,
        flag="--injection-offset", widget="slider", label="VPL offset", unit="cells",
        group="Leak reduction and bounces", stages=("inject",),
        doc='Inject each VPL at p + δ·h·n, h the cell size, δ in cells (docs/MODEL.md '
            '"Injection"): half a cell, the LPV paper\'s practice, keeps a surface from '
            "gathering its own VPLs.")
    gather_damping: bool = setting(
        False, kind="bool", flag="--gather-damping", widget="checkbox",
        label="Gather damping", group="Leak reduction and bounces", stages=("gather",),
        doc="Damp the gathered irradiance by the directional derivative along the normal "
            '(docs/MODEL.md "Final gather").')
    gather_net_flux: bool = setting(
        False, kind="bool", flag="--gather-net-flux", widget="checkbox",
        label="Net-flux gather", group="Leak reduction and bounces", stages=("gather",),
        doc="Gather E = −⟨n, F⟩ + a·E_direct: the grid's net flux into the surface (light "
            "along the surface counts 0) plus the surface's own exitance, so its own light "
            'is not taken back (docs/MODEL.md "Net-flux gather"); needs cascades 1 and '
            "the irradiance gather.")
    bounces: int = setting(
        1, kind="choice", choices=BOUNCES, flag="--bounces", label="Bounces",
        group="Leak reduction and bounces", stages=("propagate",),
        doc="1: the single indirect bounce; 2: the geometry volume also reflects the light "
            'it blocks (docs/MODEL.md "More bounces"); needs a geometry volume.')
    neighbours: int = setting(
        6, kind="choice", choices=NEIGHBOURHOODS, flag="--neighbours", widget="combo",
        label="Neighbours", group="Light propagation volume", stages=("propagate",),
        doc="6: light moves to the face neighbours through five faces each (as published); "
            "26: to all 26 neighbours through their outer faces on the source's 3×3×3 "
            'block, exact solid angles (docs/MODEL.md "26 neighbours"); needs ping-pong, '
            "side faces, the model's face weights and bounces 1.")
    reprojection: str = setting(
        "face-normal", kind="choice", choices=REPROJECTION_MODES, flag="--reprojection",
        widget="combo", label="Reprojection", group="Light propagation volume",
        stages=("propagate",),
        doc="The axis of the cosine lobe each face's light is reprojected as in the target "
            "cell: face-normal, the face's normal, as published; face-centre, the direction "
            "from the source cell's centre to the face's centre, the way the light that "
            'crosses the face travels (docs/MODEL.md "Propagation"). Same flux either way.')
    flux_budget: bool = setting(
        False, kind="bool", flag="--flux-budget", widget="checkbox", label="Flux budget",
        group="Leak reduction and bounces", stages=("propagate",),
        doc="Each propagation step sends from a cell at most the flux it holds, and no "
            "negative light: every face clamp+, all scaled down where their sum exceeds "
            'the cell\'s flux (docs/MODEL.md "Flux budget"); the audit books the clamp as '
            "clamp gain and the cut as its own term, withheld by the budget. Needs "
            "ping-pong and bounces 1.")
    camera_occluders: bool = setting(
        False, kind="bool", flag="--camera-occluders", widget="checkbox",
        label="Camera occluders", group="Leak reduction and bounces", stages=("geometry",),
        doc="Also inject the camera's G-buffer pixels into the geometry volume, except those "
            'the light sees (already in the RSM) (docs/MODEL.md "Camera occluders"); needs '
            "a geometry volume and does nothing while it is off.")
    # --- beyond diffuse (docs/MODEL.md "Fog", "Glossy reflections") ---
    fog: bool = setting(
        False, kind="bool", flag="--fog", widget="checkbox", label="Fog",
        group="Fog and glossy", stages=("fog",),
        doc="A homogeneous medium in the scene's box, lit by the LPV and the direct light "
            '(single scattering, ray-marched per pixel; docs/MODEL.md "Fog").')
    fog_density: float = setting(
        0.3, kind="float", low=0.0, high=1e3, flag="--fog-density", widget="slider",
        widget_high=3.0, label="Fog density σt", unit="1/m", group="Fog and glossy",
        stages=("fog",),
        doc="Extinction coefficient σ_t of the medium: the transmittance over a length ℓ is "
            "exp(−σ_t·ℓ).")
    fog_albedo: float = setting(
        0.8, kind="float", low=0.0, high=1.0, flag="--fog-albedo", widget="slider",
        label="Fog albedo", group="Fog and glossy", stages=("fog",),
        doc="Single-scattering albedo α = σ_s/σ_t: the share of the extinguished light the "
            "medium scatters (the rest it absorbs).")
    fog_phase: str = setting(
        "henyey-greenstein", kind="choice", choices=FOG_PHASES, flag="--fog-phase",
        widget="combo", label="Phase function", group="Fog and glossy", stages=("fog",),
        doc="isotropic: 1/(4π) in every direction; henyey-greenstein: a lobe around the "
            "light's direction of travel with asymmetry fog_g (its SH factors are g^l).")
    fog_g: float = setting(
        0.4, kind="float", low=-MAX_FOG_G, high=MAX_FOG_G, flag="--fog-g", widget="slider",
        label="HG asymmetry g", group="Fog and glossy", stages=("fog",),
        doc="Henyey–Greenstein asymmetry: > 0 scatters forward (bright towards the light), "
            "< 0 backward, 0 isotropic. Ignored with the isotropic phase function.")
    fog_steps: int = setting(
        32, kind="int", low=1, high=MAX_FOG_STEPS, flag="--fog-steps", widget="slider",
        widget_high=128, label="March steps", group="Fog and glossy", stages=("fog",),
        doc="Samples per view ray through the medium (midpoint of equal segments, each "
            "weighted by its exact transmittance difference).")
    glossy: bool = setting(
        False, kind="bool", flag="--glossy", widget="checkbox", label="Glossy reflections",
        group="Fog and glossy", stages=("gather",),
        doc="Add a glossy reflection of the LPV's light: the gather marches the grid along "
            'the reflected view direction (docs/MODEL.md "Glossy reflections").')
    glossy_roughness: float = setting(
        0.3, kind="float", low=0.0, high=1.0, flag="--glossy-roughness", widget="slider",
        label="Roughness", group="Fog and glossy", stages=("gather",),
        doc="Width of the glossy lobe: a Henyey–Greenstein lobe with g = 1 − roughness (0: "
            "the sharpest lobe the grid's SH holds; 1: the mean incident radiance).")
    glossy_strength: float = setting(
        0.5, kind="float", low=0.0, high=1.0, flag="--glossy-strength", widget="slider",
        label="Specular reflectance", group="Fog and glossy", stages=("gather",),
        doc="k_s: the share of the incident radiance from the reflected direction that the "
            "surface reflects towards the eye (added to its diffuse albedo, not taken from "
            "it).")
    glossy_samples: int = setting(
        4, kind="int", low=1, high=MAX_GLOSSY_SAMPLES, flag="--glossy-samples",
        widget="slider", widget_high=16, label="Glossy samples", group="Fog and glossy",
        stages=("gather",),
        doc="Grid lookups along the reflected ray, one finest cell apart from half a cell "
            "off the surface; their mean is the incident radiance.")
    # --- images that look right (docs/MODEL.md "Spot cone", "Final gather", "Display") ---
    spot_cone: bool = setting(
        True, kind="bool", flag="--spot-cone", widget="checkbox", label="Spot cone",
        group="Light and shadows", stages=("rsm", "gather"),
        doc='A spot light shines through its cone with a smooth angular falloff f '
            '(docs/MODEL.md "Spot cone"), the same in the RSM and the direct light; off: '
            "through the 90° square frustum with uniform intensity (the published setup, "
            "as the RSM lessons measure it). Directional lights ignore it.")
    spot_cone_degrees: tuple[float, float] | None = setting(
        None, kind="range2", optional=True, low=0.0, low_open=True, high=MAX_CONE_DEGREES,
        flag="--cone-angles", label="Cone inner/outer", unit="°", group="Light and shadows",
        stages=("rsm", "gather"),
        doc="(inner, outer) half-angles of the spot's cone in degrees: f = 1 inside the "
            "inner angle, 0 outside the outer one; None = the scene light's own cone.")
    shadow_kernel: int = setting(
        DEFAULT_SHADOW_KERNEL, kind="int", low=1, high=MAX_SHADOW_KERNEL,
        flag="--shadow-kernel", widget="slider", label="Shadow PCF", unit="texels",
        group="Light and shadows", stages=("gather",),
        doc="Width of the PCF box of the direct light's shadow test in shadow-map texels: "
            "shadow edges become linear ramps this wide; 1 = one hard test.")
    tone_map: str = setting(
        "filmic", kind="choice", choices=TONE_MAPS, flag="--tone-map", widget="combo",
        label="Tone map", group="Display", stages=("display",),
        doc='The display\'s tone curve (docs/MODEL.md "Display"): filmic (ACES fit, '
            "highlights roll off) or linear-clip (values above 1 clip to white); the linear "
            "images are unchanged.")
    auto_exposure: bool = setting(
        True, kind="bool", flag="--auto-exposure", widget="checkbox", label="Auto exposure",
        group="Display", stages=("display",),
        doc="Scale the displayed image by key/L̄ (the log-average luminance of its brighter "
            "surfaces) before the tone curve; the exposure then acts as a compensation on "
            "top.")

    def __post_init__(self) -> None:
        validate(self)
        exact = {"grid_cells": self.grid_cells, "grid_origin": self.grid_origin,
                 "grid_cell_size": self.grid_cell_size}
        missing = [name for name, value in exact.items() if value is None]
        if missing and len(missing) < len(exact):
            raise SettingError(missing[0], "an exact grid needs grid_cells, grid_origin and "
                               f"grid_cell_size together (missing: {', '.join(missing)})")
        if self.neighbours == 26:
            c = self.corrections
            missing = [name for name, on in (("ping_pong", c.ping_pong),
                                             ("side_faces", c.side_faces),
                                             ("model_face_weights", c.model_face_weights))
                       if not on]
            if missing or self.bounces != 1:
                raise SettingError("neighbours", "26-neighbour propagation needs "
                                   "ping_pong, side_faces and model_face_weights on and "
                                   f"bounces 1 (off: {', '.join(missing) or 'none'}; "
                                   f"bounces {self.bounces})")
        if self.flux_budget and (not self.corrections.ping_pong or self.bounces != 1):
            raise SettingError("flux_budget", "the flux budget needs the ping_pong "
                               "correction on and bounces 1 (ping_pong "
                               f"{'on' if self.corrections.ping_pong else 'off'}, bounces "
                               f"{self.bounces})")
        if self.gather_net_flux and (self.cascades > 1
                                     or not self.corrections.irradiance_gather):
            raise SettingError("gather_net_flux", "gather_net_flux needs cascades 1 and "
                               "the irradiance_gather correction on (cascades "
                               f"{self.cascades}, irradiance_gather "
                               f"{'on' if self.corrections.irradiance_gather else 'off'})")
        if self.bounces > 1 and self.geometry_volume == "off":
            raise SettingError("bounces", "bounces=2 reflects the light the geometry volume "
                               "blocks, so it needs geometry_volume 'one-sided' or "
                               "'double-sided' (it is 'off')")

    @property
    def grid_shape(self) -> tuple[int, int, int]:
        """Cells along x, y, z that the settings ask for: ``grid_cells``, else the fitted
        ``grid_size``³ cube (a scene file's own exact grid is the scene's)."""
        return self.grid_cells if self.grid_cells is not None else (self.grid_size,) * 3

    @property
    def uses_camera_occluders(self) -> bool:
        """Whether the geometry volume holds camera surfels (and so reads the G-buffer)."""
        return self.camera_occluders and self.geometry_volume != "off"

    def with_changes(self, **changes) -> Settings:
        """A copy with some fields changed; ``corrections`` may be given as a dict of
        switches or as a preset name."""
        corr = changes.get("corrections")
        if isinstance(corr, str):
            changes["corrections"] = preset(corr)
        elif isinstance(corr, dict):
            changes["corrections"] = replace(self.corrections, **corr)
        return replace(self, **changes)

    def to_dict(self) -> dict:
        """Plain data (JSON/TOML) that :func:`explorer.schema.from_dict` reads back."""
        return to_dict(self)

    @classmethod
    def from_dict(cls, data, base: Settings | None = None, where: str = "") -> Settings:
        """Settings from plain data (a settings file, a lesson table): ``base`` with the
        given fields replaced; a :class:`SettingError` names the bad field."""
        return from_dict(cls, data, base, where)


check_stages(Settings, STAGES)


# Names shared by the CLI (`render --view`), the app's view selector and the lessons.
VIEWS = (
    "final",            # direct + indirect, exposure applied
    "direct",           # shadowed direct light only
    "indirect",         # LPV indirect light only
    "albedo",
    "rsm-position",
    "rsm-normal",
    "rsm-flux",
    "grid-slice",       # one z slice of the accumulated grid (intensity or one SH coefficient)
    "geometry-volume",  # one slice of the occlusion grid
    "cascade-weights",  # which cascade the final gather uses at each pixel (blend weights)
)
PLOTS = ("flux-per-step", "audit", "timings", "error")
