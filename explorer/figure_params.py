"""What a lesson step may embed as a figure: each figure kind's parameters, checked.

A figure kind's parameters are a frozen dataclass declared with
:func:`explorer.schema.setting`, the same declarations the Settings use: each field
states its kind, range or choices and documentation, and the dataclass validates itself
when made. :func:`parse_figure` reads a lesson's ``[[steps.figures]]`` table (or
command-line options) into a :class:`FigureSpec`, so a lesson author reads e.g.
``figures[0].normal_deg must be a finite number in [-180, 180], got 400``.

This module holds data only (no imgui): the lesson loader checks figures with it, and the
window's figure kinds (``explorer/ui/figures/``, one module per kind) draw them.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from explorer.lpv.settings import PRESETS, Corrections
from explorer.schema import SettingError, Spec, from_dict, setting, specs, validate

SCALES = ("auto", "linear", "log")
"""Value axis of a plot: log when the values span over two decades (auto), or as chosen."""

FigureParamError = SettingError
"""A figure parameter that is missing, unknown or out of range; ``.field`` names it."""


@dataclass(frozen=True)
class ParamInfo:
    """One parameter of a figure kind, as a lesson author (or ``--help``) sees it."""

    name: str
    spec: Spec
    default: Any

    @property
    def doc(self) -> str:
        return self.spec.doc

    def allowed(self) -> str:
        return self.spec.allowed()


def schema(params_class: type) -> tuple[ParamInfo, ...]:
    """The parameters of a params dataclass, in declaration order."""
    field_specs = specs(params_class)
    return tuple(ParamInfo(f.name, field_specs[f.name], f.default)
                 for f in dataclasses.fields(params_class))


def parse_params(params_class: type, table: Mapping[str, Any], where: str = "") -> Any:
    """A ``params_class`` instance from ``table`` (missing fields keep their defaults);
    ``where`` prefixes field names in errors (e.g. ``"figures[0]."``)."""
    return from_dict(params_class, table, params_class(), where)


# --- cell-faces -------------------------------------------------------------------------
DIRECTIONS = ("+x", "-x", "+y", "-y", "+z", "-z")
CELL_FACES_HIGHLIGHTS = ("none", "front", "side")
CELL_FACES_VIEWS = ("both", "cells", "sphere")


@dataclass(frozen=True)
class CellFacesParams:
    direction: str = setting("+x", kind="choice", choices=DIRECTIONS,
        doc="Which neighbour: the axis and sign of its offset from the source cell.")
    highlight: str = setting("front", kind="choice", choices=CELL_FACES_HIGHLIGHTS,
        doc="The face highlighted at first: 'front', 'side' (one of the four) or 'none'.")
    tiling: bool = setting(True, kind="bool",
        doc="Show all 30 faces of the six neighbours on the sphere, not only these five.")
    view: str = setting("both", kind="choice", choices=CELL_FACES_VIEWS,
        doc="'cells', 'sphere' or 'both' side by side.")

    def __post_init__(self) -> None:
        validate(self)


# --- clamped-cosine ---------------------------------------------------------------------
COSINE_ORDERS = ("l1", "l2", "both")
COSINE_VIEWS = ("both", "polar", "3d")


@dataclass(frozen=True)
class ClampedCosineParams:
    normal_deg: float = setting(30.0, kind="float", low=-180, high=180,
        doc="Direction of the normal in the slice, degrees from +y (up) toward +x.")
    probe_deg: float = setting(180.0, kind="float", low=-180, high=180,
        doc="Direction of the probe whose three values the table reads, degrees from +y.")
    orders: str = setting("both", kind="choice", choices=COSINE_ORDERS,
        doc="Which projections to draw: 'l1', 'l2' or 'both'.")
    view: str = setting("both", kind="choice", choices=COSINE_VIEWS,
        doc="'polar' (the slice), '3d' or 'both' side by side.")

    def __post_init__(self) -> None:
        validate(self)


# --- pipeline ---------------------------------------------------------------------------
PIPELINE_STAGES = (
    ("light", "Light", "A spot light with a flux in watts per colour channel. Its direct "
     "light is rendered as usual; the LPV adds one diffuse bounce of it."),
    ("rsm", "Shadow map", "The reflective shadow map: each texel is a surface the light "
     "hits, with its position, normal and the flux it reflects."),
    ("inject", "Injection", "Each texel becomes a virtual point light (VPL): a clamped "
     "cosine lobe of intensity, projected to four SH coefficients and added to the grid "
     "cell that holds it."),
    ("propagate", "Propagation", "Each step moves the light in flight one cell: every cell "
     "sends flux through the five faces of each of its six neighbours. The steps are "
     "summed into the accumulated grid."),
    ("gather", "Final gather", "Each visible pixel reads the accumulated grid (trilinear), "
     "turns the intensity into irradiance and reflects it with its albedo."),
)
PIPELINE_HIGHLIGHTS = ("none",) + tuple(key for key, _, _ in PIPELINE_STAGES)


@dataclass(frozen=True)
class PipelineParams:
    highlight: str = setting("none", kind="choice", choices=PIPELINE_HIGHLIGHTS,
        doc="The stage described under the chain until the reader hovers another one.")

    def __post_init__(self) -> None:
        validate(self)


# --- propagation-stepper ----------------------------------------------------------------
STEPPER_CORRECTIONS = tuple(PRESETS) + tuple(f"{name} off" for name in Corrections.names())
STEPPER_GLYPHS = ("arrow", "lobe", "none")
STEPPER_MAX_GRID = 16
STEPPER_MAX_ITERATIONS = 32


def check_source_cell(params) -> None:
    """The source cell (``source_x``, ``source_y``) of a figure's grid lies inside its
    ``grid_size``: each field's own range allows the largest grid's cells."""
    for name in ("source_x", "source_y"):
        if getattr(params, name) >= params.grid_size:
            raise SettingError(name, f"{name} must be a cell below grid_size "
                                     f"({params.grid_size}), got {getattr(params, name)}")


@dataclass(frozen=True)
class PropagationStepperParams:
    grid_size: int = setting(9, kind="int", low=3, high=STEPPER_MAX_GRID,
        doc="Cells along each edge of the grid.")
    source_x: int = setting(2, kind="int", low=0, high=STEPPER_MAX_GRID - 1,
        doc="Cell of the light along x (0 = left); below grid_size.")
    source_y: int = setting(4, kind="int", low=0, high=STEPPER_MAX_GRID - 1,
        doc="Cell of the light along y (0 = bottom); below grid_size. The slice shown is the "
        "middle one along z, where the light is.")
    normal: str = setting("+x", kind="choice", choices=DIRECTIONS,
        doc="The surface normal of the light (it emits a clamped cosine around it).")
    iterations: int = setting(8, kind="int", low=1, high=STEPPER_MAX_ITERATIONS,
        doc="Propagation steps computed.")
    corrections: str = setting("corrected", kind="choice", choices=STEPPER_CORRECTIONS,
        doc="The formulas: a preset, or the corrected preset with one switch off "
        "(e.g. 'side_faces off').")
    step: int = setting(0, kind="int", low=0, high=STEPPER_MAX_ITERATIONS,
        doc="The step t shown at first; at most iterations.")
    glyph: str = setting("arrow", kind="choice", choices=STEPPER_GLYPHS,
        doc="Per-cell glyph: 'arrow' (along the band-1 vector, where the light is heading), "
        "'lobe' (intensity toward the slice's directions, negative parts red; after a few "
        "steps mostly round) or 'none'.")
    play: bool = setting(False, kind="bool",
        doc="Start playing the steps.")
    scale: str = setting("auto", kind="choice", choices=SCALES,
        doc="Value axis of the flux plot: 'auto', 'linear' or 'log'.")

    def __post_init__(self) -> None:
        validate(self)
        check_source_cell(self)
        if self.step > self.iterations:
            raise SettingError("step", f"step must be at most iterations ({self.iterations}), "
                                       f"got {self.step}")


# --- small-multiples ---------------------------------------------------------------------
MULTIPLES_VARY = ("iterations", "corrections", "sh_order")
MULTIPLES_QUANTITIES = ("accumulated", "in-flight")
MAX_MULTIPLES = 4


@dataclass(frozen=True)
class SmallMultiplesParams:
    vary: str = setting("iterations", kind="choice", choices=MULTIPLES_VARY,
        doc="What differs between the panels: the propagation steps, the formulas (a "
        "preset or the corrected preset with one switch off) or the SH order (1 or 2).")
    values: str = setting("4, 8, 16", kind="str",
        doc="One value per panel, comma-separated (two to four): step counts, formula "
        "names as for the stepper's corrections, or SH orders.")
    quantity: str = setting("accumulated", kind="choice", choices=MULTIPLES_QUANTITIES,
        doc="What each panel's slice shows: the accumulated grid (what the gather reads) "
        "or the light in flight after the last step.")
    iterations: int = setting(8, kind="int", low=1, high=STEPPER_MAX_ITERATIONS,
        doc="Propagation steps of every panel when the panels vary something else.")
    grid_size: int = setting(13, kind="int", low=3, high=STEPPER_MAX_GRID,
        doc="Cells along each edge of the grid.")
    source_x: int = setting(6, kind="int", low=0, high=STEPPER_MAX_GRID - 1,
        doc="Cell of the light along x (0 = left); below grid_size.")
    source_y: int = setting(1, kind="int", low=0, high=STEPPER_MAX_GRID - 1,
        doc="Cell of the light along y (0 = bottom); below grid_size.")
    normal: str = setting("+y", kind="choice", choices=DIRECTIONS,
        doc="The surface normal of the light (it emits a clamped cosine around it).")
    shared_scale: bool = setting(True, kind="bool",
        doc="One colour scale for all panels (the brightest cell of any panel is white), so "
        "that brightness compares across them; false: each panel its own.")

    @property
    def panel_values(self) -> tuple:
        """The parsed :attr:`values`: ints for iterations and SH orders, names else."""
        items = tuple(v.strip() for v in self.values.split(","))
        if self.vary == "corrections":
            return items
        return tuple(int(v) for v in items)

    def __post_init__(self) -> None:
        validate(self)
        check_source_cell(self)
        items = [v.strip() for v in self.values.split(",")]
        if not 2 <= len(items) <= MAX_MULTIPLES or len(set(items)) != len(items):
            raise SettingError("values", f"values must be 2 to {MAX_MULTIPLES} different "
                                         f"comma-separated values, got {self.values!r}")
        if self.vary == "corrections":
            bad = [v for v in items if v not in STEPPER_CORRECTIONS]
            if bad:
                raise SettingError("values", f"values: {bad[0]!r} is not one of "
                                             f"{list(STEPPER_CORRECTIONS)}")
            return
        allowed = range(1, STEPPER_MAX_ITERATIONS + 1) if self.vary == "iterations" \
            else (1, 2)
        for v in items:
            if not v.isdigit() or int(v) not in allowed:
                raise SettingError("values", f"{self.vary} values must be whole numbers in "
                                             f"{allowed[0]}..{allowed[-1]}, got {v!r}")


# --- energy-audit, flux-per-step (the frame's results) ----------------------------------
SIDES = ("a", "both")


@dataclass(frozen=True)
class ResultsParams:
    sides: str = setting("both", kind="choice", choices=SIDES,
        doc="'a': configuration A only; 'both': A and, while a comparison is on, B.")
    scale: str = setting("auto", kind="choice", choices=SCALES,
        doc="Value axis: 'auto' (log when the values span over two decades, else linear from "
        "0), 'linear' or 'log'.")
    relative: bool = setting(False, kind="bool",
        doc="Show each value as a share of its side's injected flux instead of in watts.")

    def __post_init__(self) -> None:
        validate(self)


# --- rsm-texel --------------------------------------------------------------------------
MAX_TILT = 85.0


@dataclass(frozen=True)
class RsmTexelParams:
    theta_deg: float = setting(30.0, kind="float", low=0, high=MAX_TILT,
        doc="Tilt of the surface away from facing the light, degrees.")
    plot: bool = setting(True, kind="bool",
        doc="Show the plot of footprint, irradiance and flux against the tilt.")

    def __post_init__(self) -> None:
        validate(self)


@dataclass(frozen=True)
class FigureKindDecl:
    """One figure kind a lesson may embed, declared once: everything else that names the
    kind (the window's registry, the lesson loader, the audit a step asks for, the tests
    that draw every kind) reads it from :data:`FIGURE_KINDS`."""

    name: str
    """What a lesson's ``kind = "..."`` says."""
    params: type
    """Its parameter dataclass (declared with ``setting(...)``)."""
    title: str
    module: str
    """Its module under ``explorer/ui/figures/`` (``State``, ``draw``, ``readouts``)."""
    results: bool = False
    """It plots the FrameResults of the context (A, and B while comparing)."""
    audit: str = "off"
    """The energy audit its frames must measure (``explorer.lpv.audit.AUDIT_MODES``)."""
    demo: Mapping[str, Any] = field(default_factory=dict)
    """A parameter change that changes the figure visibly (its window test draws it with
    the defaults and with this)."""


FIGURE_KINDS: tuple[FigureKindDecl, ...] = (
    FigureKindDecl("clamped-cosine", ClampedCosineParams,
                   "Clamped cosine and its SH projections", "clamped_cosine",
                   demo={"normal_deg": -60.0}),
    FigureKindDecl("cell-faces", CellFacesParams,
                   "A cell's neighbour, its five faces and their solid angles", "cell_faces",
                   demo={"direction": "+y", "highlight": "side"}),
    FigureKindDecl("propagation-stepper", PropagationStepperParams,
                   "Propagation, step by step", "propagation_stepper", demo={"step": 4}),
    FigureKindDecl("small-multiples", SmallMultiplesParams,
                   "Small multiples: one thing varied, side by side", "small_multiples",
                   demo={"quantity": "in-flight"}),
    FigureKindDecl("rsm-texel", RsmTexelParams, "An RSM texel on a tilted surface",
                   "rsm_texel", demo={"theta_deg": 70.0}),
    FigureKindDecl("energy-audit", ResultsParams, "Energy audit", "energy_audit",
                   results=True, audit="full", demo={"scale": "linear"}),
    FigureKindDecl("flux-per-step", ResultsParams, "Flux in flight per propagation step",
                   "flux_per_step", results=True, audit="flux", demo={"relative": True}),
    FigureKindDecl("pipeline", PipelineParams, "The LPV pipeline at a glance",
                   "pipeline_overview", results=True, demo={"highlight": "propagate"}),
)
FIGURE_PARAMS: dict[str, type] = {kind.name: kind.params for kind in FIGURE_KINDS}
"""Figure kind -> its parameter dataclass."""
RESERVED_KEYS = ("kind", "id", "caption")
"""Keys of a figure table that are not parameters of its kind."""


@dataclass(frozen=True)
class FigureSpec:
    """A figure as a lesson step embeds it."""

    kind: str
    params: Any
    caption: str = ""
    id: str = ""
    """Instance id; two figures on a page need different ids (default: the kind)."""

    @property
    def instance_id(self) -> str:
        return self.id or self.kind


def params_class(name: str, where: str = "") -> type:
    """The parameter dataclass of kind ``name``, or FigureParamError listing the kinds."""
    if not isinstance(name, str) or name not in FIGURE_PARAMS:
        raise FigureParamError(where + "kind", f"{where}kind: unknown figure kind {name!r}; "
                                               f"choose one of {list(FIGURE_PARAMS)}")
    return FIGURE_PARAMS[name]


def parse_figure(table: Mapping[str, Any], where: str = "") -> FigureSpec:
    """A :class:`FigureSpec` from a lesson's figure table: ``kind`` (required), optional
    ``id`` and ``caption`` strings, and the kind's parameters. ``where`` prefixes field
    names in errors (e.g. ``"figures[1]."``)."""
    if not isinstance(table, Mapping):
        place = where.rstrip(".") or "figure"
        raise FigureParamError(place, f"{place} must be a table with a kind, got "
                                      f"{type(table).__name__}")
    if "kind" not in table:
        raise FigureParamError(where + "kind", f"{where}kind is missing; choose one of "
                                               f"{list(FIGURE_PARAMS)}")
    kind = table["kind"]
    cls = params_class(kind, where)
    for key in ("id", "caption"):
        if key in table and not isinstance(table[key], str):
            raise FigureParamError(where + key, f"{where}{key} must be a string, got "
                                                f"{table[key]!r}")
    params = parse_params(cls,
                          {k: v for k, v in table.items() if k not in RESERVED_KEYS}, where)
    return FigureSpec(kind, params, table.get("caption", ""), table.get("id", ""))


def make_figure(kind: str, **params: Any) -> FigureSpec:
    """A FigureSpec from keyword parameters (code, tests), checked like a lesson's."""
    return parse_figure({"kind": kind, **params})
