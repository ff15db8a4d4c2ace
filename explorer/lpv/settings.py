"""Settings of one LPV frame.

The switches between published and corrected formulas (:class:`Corrections`, the
presets) live in the corrections registry, ``explorer/lpv/corrections.py``; they are
imported here because much code reads them from this module.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field, replace

from explorer.lpv.corrections import PRESETS, Corrections, preset  # noqa: F401 (re-export)


DOWNSAMPLE_MODES = ("none", "average", "brightest")
INJECTION_MODES = ("points", "compute")
GEOMETRY_VOLUME_MODES = ("off", "one-sided", "double-sided")
GRID_FORMATS = ("rgba32f", "rgba16f")
SH_ORDERS = (1, 2)
"""1 = L1 spherical harmonics (4 coefficients per colour), 2 = L2 (9)."""
BOUNCES = (1, 2)
MAX_INJECTION_OFFSET_CELLS = 1.0
"""A VPL moved by more than a cell would skip the cell in front of its surface."""


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
