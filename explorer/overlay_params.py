"""What the main view draws in the scene (``explorer/ui/overlays``): :class:`OverlayState`.

The overlays' settings are declared with :func:`explorer.schema.setting`, like the
Settings, and live below the window (no imgui, no GL) so that the lesson loader can check
a step's ``[steps.show]`` table against them (``explorer/lessons/reader.py``) and the window
persists and draws the same declarations (``explorer/ui/state.py`` re-exports them).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from explorer.lpv.settings import MAX_CASCADES, MAX_GRID_SIZE, MAX_ITERATIONS
from explorer.schema import setting, validate

SLICE_AXES = ("x", "y", "z")
SLICE_QUANTITIES = ("intensity", "flux", "in-flight", "sh0", "sh1", "sh2", "sh3", "sh4", "sh5",
                    "sh6", "sh7", "sh8")
"""What the slice plane shows per cell, the mean of the three colour channels:
intensity toward a chosen direction [W/sr] of acc_N; flux 2√π·c0 [W] of acc_N; in-flight:
the flux of grid_t, the light still travelling after t steps; sh<k>: coefficient k of acc_N
(sh4..sh8 exist only with sh_order 2)."""
COLOUR_MAPS = ("auto", "heat", "diverging")
"""auto: diverging (blue < 0 < orange) for signed quantities (sh1..sh8), heat otherwise."""
GLYPH_CELLS = ("slice", "picked")
"""Where SH glyphs are drawn: every cell of the slice (thinned to stay readable) or the
picked cell and its 26 neighbours."""
GLYPH_SIZINGS = ("linear", "sqrt", "equal")
"""Each glyph keeps its lobe's shape (radius ∝ |f(ω)|); its overall size grows with its
peak value linearly, with the square root of it (dim cells stay visible), or not at all."""
PICK_KINDS = ("none", "pixel", "cell")


@dataclass
class OverlayState:
    """The main view's in-scene overlays (the "Show in scene" panel) and the picked point;
    persisted, so every field is declared and checked by the settings schema."""

    slice: bool = setting(False, kind="bool", doc="Draw the slice plane.")
    slice_axis: str = setting("z", kind="choice", choices=SLICE_AXES,
                              doc="The axis the slice plane is normal to.")
    slice_index: int = setting(-1, kind="int", low=-1, high=MAX_GRID_SIZE - 1,
                               doc="Cell layer along the axis; -1 = the middle one.")
    slice_quantity: str = setting("intensity", kind="choice", choices=SLICE_QUANTITIES,
                                  doc="What the slice shows per cell.")
    slice_step: int = setting(0, kind="int", low=0, high=MAX_ITERATIONS << (MAX_CASCADES - 1),
                              doc='The step t of "in-flight".')
    direction_azimuth: float = setting(0.0, kind="float", low=-180.0, high=180.0, unit="°",
                                       doc='Direction of "intensity".')
    direction_elevation: float = setting(90.0, kind="float", low=-90.0, high=90.0, unit="°",
                                         doc='Direction of "intensity".')
    colour_map: str = setting("auto", kind="choice", choices=COLOUR_MAPS,
                              doc="Colour map of the slice and its colour bar.")
    slice_scale: float = setting(0.0, kind="float", low=0.0, high=1e12,
                                 doc="Value at the top of the colour bar; 0 = automatic.")
    slice_log: bool = setting(False, kind="bool",
                              doc="Heat map over LOG_DECADES decades below the top.")
    shared_scale: bool = setting(True, kind="bool",
                                 doc="In a comparison, both sides' slices on one colour "
                                     "scale (A's automatic top), so brightness compares "
                                     "across the divider; false: each side its own.")
    slice_opacity: float = setting(0.8, kind="float", low=0.0, high=1.0,
                                   doc="Opacity of the slice plane.")
    slice_on_top: bool = setting(False, kind="bool",
                                 doc="Draw the slice over the geometry instead of "
                                     "depth-tested.")
    cascade: int = setting(0, kind="int", low=0, high=MAX_CASCADES - 1,
                           doc="The cascade the slice, glyphs and lattice show.")
    glyphs: bool = setting(False, kind="bool", doc="Draw SH glyphs.")
    glyph_cells: str = setting("slice", kind="choice", choices=GLYPH_CELLS,
                               doc="Where glyphs are drawn.")
    glyph_scale: float = setting(1.0, kind="float", low=0.05, high=8.0,
                                 doc="Lobe radius, in units of the glyph's cell spacing.")
    glyph_stride: int = setting(0, kind="int", low=0, high=64,
                                doc="Draw every k-th cell of the slice; 0 = automatic.")
    glyph_sizing: str = setting("sqrt", kind="choice", choices=GLYPH_SIZINGS,
                                doc="How a glyph's size follows its peak value.")
    fly: bool = setting(False, kind="bool", doc="Camera fly mode (WASD + mouse look).")
    vpls: bool = setting(False, kind="bool", doc="Draw the VPLs as discs.")
    vpl_density: float = setting(0.25, kind="float", low=0.0, high=1.0,
                                 doc="Fraction of the VPLs drawn (a fixed random subset).")
    vpl_size: float = setting(0.7, kind="float", low=0.05, high=8.0,
                              doc="Disc radius / the radius of the VPL's surfel.")
    lattice: bool = setting(False, kind="bool",
                            doc="The cell lattice on the slice plane and the grid box.")
    cascade_boxes: bool = setting(False, kind="bool", doc="Every cascade's extent.")
    blockers: bool = setting(False, kind="bool",
                             doc="Geometry volume blockers as oriented discs.")
    # The picked point is anchored in the world, so it stays put when the camera moves
    # (and with it the pixel that shows it, and the cascades that follow the camera).
    picked_kind: str = setting("none", kind="choice", choices=PICK_KINDS,
                               doc="pixel: a surface point; cell: a cell's centre.")
    picked_side: str = setting("A", kind="choice", choices=("A", "B"),
                               doc="Which configuration's frame the pick reads.")
    picked_cascade: int = setting(0, kind="int", low=0, high=MAX_CASCADES - 1,
                                  doc="The cascade whose cell is picked.")
    picked_wx: float = setting(0.0, kind="float", doc="The picked world point, x.")
    picked_wy: float = setting(0.0, kind="float", doc="The picked world point, y.")
    picked_wz: float = setting(0.0, kind="float", doc="The picked world point, z.")

    def __post_init__(self) -> None:
        validate(self)

    @property
    def picked_point(self) -> tuple[float, float, float] | None:
        if self.picked_kind == "none":
            return None
        return (self.picked_wx, self.picked_wy, self.picked_wz)

    def pick(self, kind: str, side: str, cascade: int, world) -> None:
        """Anchor the picked point at ``world`` (a surface point or a cell centre)."""
        self.picked_kind, self.picked_side, self.picked_cascade = kind, side, int(cascade)
        self.picked_wx, self.picked_wy, self.picked_wz = (float(v) for v in world)

    @property
    def any_shown(self) -> bool:
        """Whether the view must be composited (an overlay is on or a point is picked)."""
        return (self.slice or self.glyphs or self.vpls or self.lattice or self.cascade_boxes
                or self.blockers or self.picked_kind != "none")

    @property
    def needs_steps(self) -> bool:
        """The slice or its glyphs show grid_t: the pipeline must keep every step (one
        propagate run when this turns on)."""
        return (self.slice or self.glyphs) and self.slice_quantity == "in-flight"


# --- a lesson step's view ------------------------------------------------------------------
READER_FIELDS = ("fly",)
"""Fields that are the reader's way of moving about, not part of what a step shows: a
lesson step keeps the reader's value and its ``[steps.show]`` table may not set them."""


def step_overlays(show: Mapping[str, Any], base: OverlayState | None = None) -> OverlayState:
    """The overlays a lesson step shows: every field at its default (nothing drawn,
    nothing picked) with the step's ``show`` fields set, and the reader's
    :data:`READER_FIELDS` from ``base``. A new object: the window edits overlays in place,
    so neither the step's nor the reader's copy is ever shared."""
    kept = {} if base is None else {name: getattr(base, name) for name in READER_FIELDS}
    return OverlayState(**{**kept, **dict(show)})


def check_show(show: Mapping[str, Any], settings) -> dict[str, Any]:
    """A lesson step's ``[steps.show]`` table checked field by field against the specs
    (:func:`explorer.schema.check_fields`) and against the step's ``settings``: light
    in flight at a step the propagation runs, coefficients the grid holds, a picked
    point for glyphs around it. Returns the normalised fields; a :class:`SettingError`
    names the field."""
    from explorer.lpv.cascades import cascade_iterations
    from explorer.schema import SettingError, check_fields

    for name in READER_FIELDS:
        if name in show:
            raise SettingError(name, f"{name} is the reader's own control, not part of a "
                                     "step's view; leave it out")
    checked = check_fields(OverlayState, show)
    overlays = step_overlays(checked)
    steps = cascade_iterations(settings, 0)
    if overlays.slice_quantity == "in-flight" and overlays.slice_step > steps:
        field = "slice_step" if "slice_step" in checked else "slice_quantity"
        raise SettingError(field, f"slice_step {overlays.slice_step} is past the last "
                                  f"propagation step of the finest cascade ({steps} with "
                                  f"these settings)")
    coefficients = 4 if settings.sh_order == 1 else 9
    quantity = overlays.slice_quantity
    if quantity.startswith("sh") and int(quantity[2:]) >= coefficients:
        raise SettingError("slice_quantity", f"{quantity} needs sh_order 2; the step's grid "
                                             f"holds {coefficients} coefficients per cell")
    if overlays.glyphs and overlays.glyph_cells == "picked" and overlays.picked_kind == "none":
        raise SettingError("glyph_cells", 'glyph_cells "picked" draws the glyphs around the '
                                          "picked point: set picked_kind and picked_wx, "
                                          "picked_wy, picked_wz too")
    if overlays.blockers and settings.geometry_volume == "off":
        raise SettingError("blockers", "blockers draws the geometry volume, which is off in "
                                       "this step (settings.geometry_volume)")
    if overlays.cascade >= settings.cascades or overlays.picked_cascade >= settings.cascades:
        field = "cascade" if overlays.cascade >= settings.cascades else "picked_cascade"
        raise SettingError(field, f"{field} {getattr(overlays, field)} does not exist: the "
                                  f"step has {settings.cascades} cascade(s)")
    return checked
