"""Settings of one LPV frame, and the switches between published and corrected formulas.

Every field of :class:`Corrections` is ``True`` for the corrected (recommended) behaviour;
see ``docs/MODEL.md`` for the formula each one selects. They reach the shaders as
uniforms, never as a second copy of a shader.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field, fields, replace

from explorer.lpv.tonemap import TONE_MAPS


@dataclass(frozen=True)
class Corrections:
    """Named switches, one per published formula or implementation detail."""

    injection_pi: bool = True
    """Divide the VPL intensity by π: I_p = Φ_p/π·⟨n,ω⟩⁺ (annotations §4.1)."""
    propagation_4pi: bool = True
    """Drop the 1/(4π) in Φ_f = Δω_f/(4π)·I(ω_c) (annotations §6.2)."""
    reprojection_pi: bool = True
    """Reproject with Φ_l = Φ_f instead of Φ_f/π (annotations §6.3)."""
    exact_constants: bool = True
    """Use the derived constants instead of the decimals printed in the DX11 article."""
    side_faces: bool = True
    """Propagate through the four side faces as well as the front face."""
    surfel_area_squared: bool = True
    """Surfel area grows with the squared view depth (annotations §5), not linearly."""
    ping_pong: bool = True
    """Read grid t−1 and write grid t, instead of the DX11 in-place read-modify-write."""
    clamp_front_face: bool = True
    """Clamp the front-face intensity at zero, as the DX11 propagation shader does."""

    @classmethod
    def names(cls) -> tuple[str, ...]:
        return tuple(f.name for f in fields(cls))

    def as_uniforms(self) -> dict[str, int]:
        """Uniform values for the shaders: ``u_<field>`` = 0 or 1."""
        return {f"u_{name}": int(getattr(self, name)) for name in self.names()}


PRESETS: dict[str, Corrections] = {
    "corrected": Corrections(),
    "original": Corrections(
        injection_pi=False,
        propagation_4pi=False,
        reprojection_pi=False,
        exact_constants=False,
    ),
}


def preset(name: str) -> Corrections:
    """The named preset; raises ``KeyError`` listing the valid names."""
    try:
        return PRESETS[name]
    except KeyError:
        raise KeyError(f"unknown preset {name!r}; choose one of {sorted(PRESETS)}") from None


DOWNSAMPLE_MODES = ("none", "average", "brightest")
INJECTION_MODES = ("points", "compute")
GEOMETRY_VOLUME_MODES = ("off", "one-sided", "double-sided")
GRID_FORMATS = ("rgba32f", "rgba16f")
SH_ORDERS = (1, 2)
"""1 = L1 spherical harmonics (4 coefficients per colour), 2 = L2 (9)."""
BOUNCES = (1, 2)
MAX_INJECTION_OFFSET_CELLS = 1.0
"""A VPL moved by more than a cell would skip the cell in front of its surface."""
MAX_SHADOW_KERNEL = 9
"""Widest PCF box in shadow-map texels (the gather fetches (k+1)² texels per pixel)."""
DEFAULT_SHADOW_KERNEL = 3
"""``Settings.shadow_kernel``'s default (also the gather pass's)."""


@dataclass(frozen=True)
class Settings:
    """Everything a frame depends on. Immutable: the app compares settings to know
    whether the pipeline must run again."""

    scene: str = "cornell"
    """A built-in scene name or a path to a mesh file trimesh can read."""
    corrections: Corrections = field(default_factory=Corrections)
    grid_size: int = 32
    iterations: int = 16
    rsm_size: int = 256
    downsample: str = "none"
    downsample_factor: int = 2
    injection_mode: str = "points"
    geometry_volume: str = "off"
    grid_format: str = "rgba32f"
    sh_order: int = 1
    """SH order of the light grid: 1 = L1 (4 coefficients per colour channel, as published),
    2 = L2 (9; injection, propagation and gather use band 2 too; docs/MODEL.md "L2
    option"). The geometry volume stays L1."""
    # --- cascaded LPV (docs/MODEL.md "Cascades", explorer/lpv/cascades.py) ---
    cascades: int = 1
    """Nested grids of grid_size³ cells, each with twice the cell size of the last;
    1 = the single grid enclosing the scene."""
    cascade_extent: float | None = None
    """Edge of the finest cascade in world units; None = the single grid's extent divided
    by 2^(cascades−1), so the coarsest cascade has the single grid's cells."""
    cascade_focus: float = 1.0
    """Where the cascades are centred on the camera's line of sight: 0 = at the eye,
    1 = at the camera's target (each cascade then snaps to its own cells)."""
    cascade_iterations: str = "same"
    """"same": every cascade propagates ``iterations`` steps (the LPV paper), so light
    travels 2^k finest cells per step in cascade k; "same-distance": cascade k propagates
    ``iterations·2^(cascades−1−k)`` steps, so every cascade carries light as far (in world
    units) as the coarsest."""
    width: int = 512
    height: int = 512
    exposure: float = 1.0
    indirect_only: bool = False
    camera: tuple[tuple[float, float, float], tuple[float, float, float]] | None = None
    """(eye, target) in world units; None = the scene's default camera."""
    light: tuple[tuple[float, float, float], tuple[float, float, float]] | None = None
    """(position, target) of the spot light; None = the scene's default light."""
    light_flux: float | None = None
    """Total flux of the light in watts per channel; None = the scene's default."""
    debug_nan: bool = False
    """Check every pass for NaN/Inf and name the pass that produced one."""
    injection_offset_cells: float = 0.5
    """Inject each VPL at p + δ·cell_size·n, δ in cells (docs/MODEL.md "Injection"):
    half a cell, the LPV paper's practice, keeps a surface from gathering its own VPLs."""
    gather_damping: bool = False
    """Damp the gathered irradiance by the directional derivative along the normal
    (docs/MODEL.md "Final gather")."""
    bounces: int = 1
    """1: the single indirect bounce; 2: the geometry volume also reflects the light it
    blocks (docs/MODEL.md "More bounces"); needs a geometry volume."""
    # --- images that look right (docs/MODEL.md "Spot cone", "Final gather", "Display") ---
    spot_cone: bool = True
    """A spot light shines through its cone with a smooth angular falloff f shared by the
    RSM and the direct light (read by the scene and rsm stages); False: through the 90°
    square frustum with uniform intensity (the published setup, as the RSM lessons
    measure it). Directional lights ignore it."""
    spot_cone_degrees: tuple[float, float] | None = None
    """(inner, outer) half-angles of the spot's cone in degrees, 0 <= inner <= outer <= 80,
    outer > 0; None = the scene light's own cone (scene and rsm stages)."""
    shadow_kernel: int = DEFAULT_SHADOW_KERNEL
    """Width of the PCF box of the direct light's shadow test in shadow-map texels,
    1..MAX_SHADOW_KERNEL: shadow edges become linear ramps this wide; 1 = one hard test
    (gather stage)."""
    tone_map: str = "filmic"
    """The display's tone curve, one of TONE_MAPS: "filmic" (ACES fit, highlights roll
    off) or "linear-clip" (values above 1 clip to white); display stage only, the linear
    images are unchanged."""
    auto_exposure: bool = True
    """Scale the displayed image by key/L̄ (log-average luminance of the unexposed image,
    key 0.18) before the tone curve; ``exposure`` then acts as a compensation on top.
    Display stage only."""

    def __post_init__(self) -> None:
        _check_cascades(self)
        _check_choice("downsample", self.downsample, DOWNSAMPLE_MODES)
        _check_choice("injection_mode", self.injection_mode, INJECTION_MODES)
        _check_choice("geometry_volume", self.geometry_volume, GEOMETRY_VOLUME_MODES)
        _check_choice("grid_format", self.grid_format, GRID_FORMATS)
        if isinstance(self.sh_order, bool) or self.sh_order not in SH_ORDERS:
            raise ValueError(f"sh_order must be 1 (L1, 4 coefficients) or 2 (L2, 9 "
                             f"coefficients), got {self.sh_order!r}")
        for name in ("grid_size", "rsm_size", "width", "height", "downsample_factor"):
            if int(getattr(self, name)) < 1:
                raise ValueError(f"{name} must be at least 1, got {getattr(self, name)!r}")
        if self.iterations < 0:
            raise ValueError(f"iterations must be >= 0, got {self.iterations!r}")
        offset = self.injection_offset_cells
        if isinstance(offset, bool) or not isinstance(offset, (int, float)) or not (
                0.0 <= offset <= MAX_INJECTION_OFFSET_CELLS):
            raise ValueError(f"injection_offset_cells must be a number of cells in "
                             f"[0, {MAX_INJECTION_OFFSET_CELLS}], got {offset!r}")
        if not isinstance(self.gather_damping, bool):
            raise ValueError(f"gather_damping must be True or False, got "
                             f"{self.gather_damping!r}")
        if isinstance(self.bounces, bool) or self.bounces not in BOUNCES:
            raise ValueError(f"bounces must be one of {BOUNCES}, got {self.bounces!r}")
        _check_look(self)
        if self.bounces > 1 and self.geometry_volume == "off":
            raise ValueError("bounces=2 reflects the light the geometry volume blocks, so it "
                             "needs geometry_volume 'one-sided' or 'double-sided' (it is "
                             "'off')")

    def with_changes(self, **changes) -> "Settings":
        """A copy with some fields changed; ``corrections`` may be given as a dict of
        switches or as a preset name."""
        corr = changes.get("corrections")
        if isinstance(corr, str):
            changes["corrections"] = preset(corr)
        elif isinstance(corr, dict):
            changes["corrections"] = replace(self.corrections, **corr)
        return replace(self, **changes)

    def to_dict(self) -> dict:
        return dataclasses.asdict(self)


MAX_CASCADES = 4
CASCADE_ITERATIONS = ("same", "same-distance")


def _check_cascades(settings: "Settings") -> None:
    if not 1 <= int(settings.cascades) <= MAX_CASCADES or \
            int(settings.cascades) != settings.cascades:
        raise ValueError(f"cascades must be a whole number 1..{MAX_CASCADES}, got "
                         f"{settings.cascades!r}")
    if settings.cascade_extent is not None and not settings.cascade_extent > 0:
        raise ValueError(f"cascade_extent must be positive (world units) or None, got "
                         f"{settings.cascade_extent!r}")
    _check_choice("cascade_iterations", settings.cascade_iterations, CASCADE_ITERATIONS)
    if not 0.0 <= settings.cascade_focus <= 1.0:
        raise ValueError(f"cascade_focus must lie in [0, 1] (0 = eye, 1 = target), got "
                         f"{settings.cascade_focus!r}")


def _check_look(settings: "Settings") -> None:
    """The fields of the spot cone, the PCF and the display."""
    for name in ("spot_cone", "auto_exposure"):
        if not isinstance(getattr(settings, name), bool):
            raise ValueError(f"{name} must be True or False, got {getattr(settings, name)!r}")
    cone = settings.spot_cone_degrees
    if cone is not None:
        from explorer.scene.lights import MAX_CONE_DEGREES

        try:
            inner, outer = (float(v) for v in cone)
        except (TypeError, ValueError):
            inner, outer = -1.0, -1.0
        if not (0.0 <= inner <= outer <= MAX_CONE_DEGREES and outer > 0.0):
            raise ValueError(f"spot_cone_degrees must be (inner, outer) half-angles in "
                             f"degrees with 0 <= inner <= outer <= {MAX_CONE_DEGREES:g} and "
                             f"outer > 0, or None; got {cone!r}")
    kernel = settings.shadow_kernel
    if isinstance(kernel, bool) or not isinstance(kernel, int) or not (
            1 <= kernel <= MAX_SHADOW_KERNEL):
        raise ValueError(f"shadow_kernel must be a whole number of texels 1..{MAX_SHADOW_KERNEL}"
                         f" (1 = hard shadows), got {kernel!r}")
    _check_choice("tone_map", settings.tone_map, TONE_MAPS)


def _check_choice(name: str, value: str, choices: tuple[str, ...]) -> None:
    if value not in choices:
        raise ValueError(f"{name} must be one of {choices}, got {value!r}")


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
