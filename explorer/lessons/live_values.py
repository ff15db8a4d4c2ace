"""Live numbers for lesson prose: every ``{{name:format}}`` a lesson writes is one quantity
named here, read from what is on screen now.

Sources (the first part of the name):

* ``settings.<field>`` and ``corrections.<switch>`` / ``corrections.preset``: the
  configuration shown (configuration A);
* ``audit.*`` and ``frame.*``: the current FrameResult (energy audit in watts summed
  over the three colour channels, pass times, grid geometry) and the texture memory
  the settings need;
* ``error.*``: the Error panel's comparison of this configuration with the one-bounce
  reference (``explorer/truth``); pending ("…") until it has been computed;
* ``derived.<result>``: a derivation result's value from the generated table
  (``explorer.derived``): an exact constant, the same on every machine;
* ``figure.<id>.<readout>``: a number an inline figure of the step shows now;
* ``mark.<id>.<readout>``: a number measured at a mark the step places in its scene
  (:mod:`explorer.lessons.marks`: the LPV's indirect irradiance there).

So a number in a lesson is either derived (a constant of the model, exact) or measured
(read from the frame or the error measurement at the settings on screen); nothing is
typed in. :func:`lookup` refuses unknown names with the closest matches.

Index: :class:`Quantity` and :func:`table` (every name), :func:`lookup`, :func:`audit_needed`
(the audit mode a name needs), :func:`check_format`, :func:`render` and
:func:`pending_reason` (a number as the text shows it, or why it waits).

Examples
--------
>>> lookup("audit.injected").unit
'W'
>>> render("derived.sh.c0", ".4f", LiveContext())
'0.2821'
"""

from __future__ import annotations

import difflib
import math
import re
from collections.abc import Callable
from dataclasses import dataclass, field, fields
from typing import Any

import numpy as np

PENDING = "…"
"""Shown for a quantity that is not available yet (no frame, error not computed)."""
SOURCES = ("settings", "corrections", "audit", "frame", "error", "derived", "figure", "mark")
MEASURED_SOURCES = ("audit", "frame", "error", "figure", "mark")
"""Sources whose numbers are measured on the frame (the others are configuration or
exact constants)."""


@dataclass
class LiveContext:
    """What live numbers read: configuration A, its FrameResult, the error measurement
    of that configuration (an ``explorer.truth.metrics.ErrorStats``, None until
    computed) and the readouts of the step's figures (id -> name -> value)."""

    settings: Any = None
    result: Any = None
    error: Any = None
    figures: dict[str, dict[str, float]] = field(default_factory=dict)
    renderer: str = ""
    """GL_RENDERER of the context the frame ran on."""
    marks: dict[str, Any] = field(default_factory=dict)
    """The step's marks (id -> ``explorer.lessons.marks.Mark``) for ``mark.*`` numbers."""


class Unavailable(LookupError):
    """The quantity exists but has no value now (no frame yet, error not computed)."""


@dataclass(frozen=True)
class Quantity:
    name: str
    doc: str
    unit: str
    read: Callable[[LiveContext], Any]
    format: str = ".3g"
    """Format used when the lesson gives none."""
    constant: bool = False
    """A fixed property of the program (the pipeline's stage count): read with the frame
    but neither measured nor changed by any setting."""

    @property
    def source(self) -> str:
        return self.name.split(".", 1)[0]

    @property
    def measured(self) -> bool:
        return self.source in MEASURED_SOURCES and not self.constant

    def value(self, context: LiveContext) -> Any:
        """The value now; :class:`Unavailable` when it has none yet."""
        return self.read(context)


# --- readers ---------------------------------------------------------------------------

def _result(context: LiveContext):
    if context.result is None:
        raise Unavailable("no frame yet")
    return context.result


def _settings(context: LiveContext):
    if context.settings is not None:
        return context.settings
    if context.result is not None:
        return context.result.settings
    raise Unavailable("no settings")


NOT_MEASURED = ("the frame's propagation measured {what} only (audit mode {mode}): the "
                "full energy audit runs while the Energy audit plot, a picked cell or a "
                "lesson quoting this term is shown")
"""Why an audit term has no value (:class:`Unavailable`; the lesson's tooltip says it)."""


def _audit_sum(name: str) -> Callable[[LiveContext], float]:
    def read(context: LiveContext) -> float:
        audit = _result(context).audit
        data = getattr(audit, name, None)
        if data is None and getattr(audit, "mode", "full") != "full":
            raise Unavailable(NOT_MEASURED.format(
                what="the flux per step" if audit.mode == "flux"
                else "the injected and accumulated flux", mode=audit.mode))
        return 0.0 if data is None else float(np.sum(data))
    return read


def _per_step(context: LiveContext) -> np.ndarray:
    audit = _result(context).audit
    if not getattr(audit, "steps_measured", True):
        raise Unavailable(NOT_MEASURED.format(what="the injected and accumulated flux",
                                              mode=audit.mode))
    steps = np.asarray(audit.per_step, np.float64)
    return steps.reshape(len(steps), -1).sum(axis=1)


def _ratio(top: float, bottom: float) -> float:
    return top / bottom if bottom != 0 else math.inf if top else math.nan


def _step_ratio(context: LiveContext) -> float:
    steps = _per_step(context)
    if len(steps) < 2:
        raise Unavailable("no propagation step (iterations = 0)")
    return _ratio(float(steps[1]), float(steps[0]))


def _last_over_first(context: LiveContext) -> float:
    steps = _per_step(context)
    return _ratio(float(steps[-1]), float(steps[0]))


def _lit_vpls(context: LiveContext) -> int:
    vpls = _result(context).vpls
    return int(np.count_nonzero(np.asarray(vpls.flux).sum(axis=1) > 0))


def _vpl_depth(reduce) -> Callable[[LiveContext], float]:
    def read(context: LiveContext) -> float:
        vpls = _result(context).vpls
        lit = np.asarray(vpls.flux).sum(axis=1) > 0
        if not lit.any():
            raise Unavailable("no lit VPL")
        return float(reduce(np.asarray(vpls.depth)[lit]))
    return read


def _primary_rsm(context: LiveContext) -> float:
    """The primary light's RSM flux (its row of ``audit.rsm_per_light``), channels summed."""
    per_light = np.asarray(_result(context).audit.rsm_per_light, np.float64)
    if per_light.size == 0:
        raise Unavailable("no per-light RSM flux")
    return float(per_light[0].sum())


def _ran(stage: str) -> Callable[[LiveContext], str]:
    return lambda c: "yes" if stage in _result(c).stages_run else "no"


def _time(name: str) -> Callable[[LiveContext], float]:
    def read(context: LiveContext) -> float:
        timings = _result(context).timings_ms
        if name == "total":
            return float(sum(timings.values()))
        if name not in timings:
            raise Unavailable(f"the {name} pass did not run")
        return float(timings[name])
    return read


def _timer(context: LiveContext) -> str:
    methods = _result(context).timing_methods
    method = methods.get("propagate")
    if method is None:
        raise Unavailable("the propagation pass was not timed")
    return "GPU timer queries" if method == "timer-query" else "the wall clock"


def _renderer(context: LiveContext) -> str:
    renderer = getattr(context, "renderer", None)
    if not renderer:
        raise Unavailable("the renderer is not known")
    return str(renderer)


def _fog(context: LiveContext):
    fog = _result(context).fog
    if fog is None:
        raise Unavailable("the frame has no fog (settings.fog is off)")
    return fog


def _fog_lpv_share(context: LiveContext) -> float:
    """The LPV's share of the light the fog scatters towards the eye (luminance)."""
    from explorer.lpv.twin.tonemap import luminance

    fog = _fog(context)
    lpv = float(np.sum(luminance(fog.lpv)))
    direct = float(np.sum(luminance(fog.direct)))
    return _ratio(lpv, lpv + direct)


def _fog_transmittance(context: LiveContext) -> float:
    """Mean transmittance over the pixels that show a surface."""
    fog = _fog(context)
    seen = _result(context).gbuffer_position[..., 3] > 0.5
    if not seen.any():
        raise Unavailable("no surface on screen")
    return float(np.mean(fog.transmittance[seen]))


def _face_evaluations(context: LiveContext) -> int:
    from explorer.lpv.neighbours import FACES_PER_STEP

    settings = _settings(context)
    return (FACES_PER_STEP[int(settings.neighbours)] * int(np.prod(settings.grid_shape))
            * int(settings.iterations) * int(settings.cascades))


def _memory_mib(context: LiveContext) -> float:
    from explorer.lpv.cascades import texture_bytes

    s = _settings(context)
    groups = 1 if s.sh_order == 1 else 3
    return texture_bytes(s.grid_shape, s.cascades, s.grid_format, s.geometry_volume != "off",
                         groups) / 2 ** 20


def _error(name: str, channel: int | None = None) -> Callable[[LiveContext], float]:
    def read(context: LiveContext) -> float:
        if context.error is None:
            raise Unavailable("the error against the reference is not computed yet")
        value = getattr(context.error, name, None)
        if value is None:      # error.mitsuba_*: Mitsuba has not measured it (yet)
            raise Unavailable("not measured against Mitsuba yet (Error panel: truth "
                              "\"reference + Mitsuba\")")
        return float(value[channel] if channel is not None else value)
    return read


def _setting(name: str) -> Callable[[LiveContext], Any]:
    return lambda context: getattr(_settings(context), name)


def _switch(name: str) -> Callable[[LiveContext], str]:
    return lambda context: "on" if getattr(_settings(context).corrections, name) else "off"


def _preset(context: LiveContext) -> str:
    from explorer.lpv.settings import PRESETS

    corrections = _settings(context).corrections
    for name, value in PRESETS.items():
        if value == corrections:
            return name
    return "custom"


def _derived(name: str) -> Callable[[LiveContext], float]:
    def read(context: LiveContext) -> float:
        from explorer import derived

        return float(derived.get(name).value)
    return read


# --- the table -------------------------------------------------------------------------

AUDIT_SUMS = (
    ("rsm", "flux the RSM texels reflect (sum of channels)"),
    ("injected", "flux injected into the grid (before any step)"),
    ("accumulated", "flux of the accumulated grid (the sum of all steps)"),
    ("gathered", "flux the visible surfaces receive in the final gather"),
    ("border_loss", "flux that left the grid through its border, all steps"),
    ("clamp_gain", "flux created by the front-face clamp, all steps"),
    ("occluded", "flux the geometry volume removed, all steps"),
    ("reflected", "flux the geometry volume reflected back (bounces 2), all steps"),
    ("budget_withheld", "flux the flux budget kept back (0 without it), all steps"),
)
"""EnergyAudit fields quoted as ``audit.<field>``: watts summed over the colour channels
(and over the steps for the per-step terms)."""
AUDIT_RATIOS = (
    ("injected_over_rsm", "injected", "rsm", "injected flux / RSM flux"),
    ("accumulated_over_injected", "accumulated", "injected", "accumulated flux / injected flux"),
    ("gathered_over_rsm", "gathered", "rsm", "gathered flux / RSM flux"),
    ("clamp_gain_share", "clamp_gain", "injected",
     "flux the front-face clamp created over all steps / injected flux"),
    ("occluded_share", "occluded", "injected",
     "flux the geometry volume removed over all steps / injected flux"),
    ("border_loss_share", "border_loss", "injected",
     "flux that left through the grid border over all steps / injected flux"),
    ("budget_withheld_share", "budget_withheld", "injected",
     "flux the flux budget kept back over all steps / injected flux"),
    ("budget_withheld_over_clamp_gain", "budget_withheld", "clamp_gain",
     "flux the flux budget kept back / flux the clamp created, all steps"),
)
"""``audit.<name>``: one audit sum over another."""


PER_STEP_QUANTITIES = ("audit.step_ratio", "audit.last_over_first", "audit.in_flight_last",
                       "audit.max_over_first")
"""``audit.*`` numbers read from the flux per step (audit mode ``flux`` measures them)."""


def audit_needed(name: str) -> str:
    """The audit mode (explorer.lpv.audit.AUDIT_MODES) the frame must be propagated with
    for ``name`` to have a value: ``full`` for the terms only the full audit measures
    (and ratios of them), ``flux`` for the per-step numbers, ``off`` otherwise."""
    from explorer.lpv.audit import TERMS_OF_FULL_AUDIT

    if not name.startswith("audit."):
        return "off"
    short = name[len("audit."):]
    ratios = {ratio: (top, bottom) for ratio, top, bottom, _ in AUDIT_RATIOS}
    if short in TERMS_OF_FULL_AUDIT or set(ratios.get(short, ())) & set(TERMS_OF_FULL_AUDIT):
        return "full"
    return "flux" if name in PER_STEP_QUANTITIES else "off"


def _audit_ratio(top: str, bottom: str) -> Callable[[LiveContext], float]:
    return lambda c: _ratio(_audit_sum(top)(c), _audit_sum(bottom)(c))


def _fixed() -> dict[str, Quantity]:
    from explorer.lpv.stage_list import PASSES, STAGES

    items = [
        *[Quantity(f"audit.{name}", doc, "W", _audit_sum(name)) for name, doc in AUDIT_SUMS],
        *[Quantity(f"audit.{name}", doc, "", _audit_ratio(top, bottom))
          for name, top, bottom, doc in AUDIT_RATIOS],
        Quantity("audit.step_ratio", "flux in flight after one step / before it", "",
                 _step_ratio),
        Quantity("audit.last_over_first", "flux in flight after the last step / injected",
                 "", _last_over_first),
        Quantity("audit.in_flight_last", "flux in flight after the last step", "W",
                 lambda c: float(_per_step(c)[-1])),
        Quantity("audit.max_over_first", "largest flux in flight over all steps / injected "
                 "flux (above 1: some step added light)", "",
                 lambda c: _ratio(float(_per_step(c).max()), float(_per_step(c)[0]))),
        Quantity("frame.vpls", "VPLs injected (RSM texels after downsampling)", "",
                 lambda c: int(_result(c).vpls.count), "d"),
        Quantity("frame.lit_vpls", "VPLs that carry flux", "", _lit_vpls, "d"),
        Quantity("frame.lights", "lights that shine (Settings.lights)", "",
                 lambda c: len(_result(c).light_names), "d"),
        Quantity("frame.rsm_views", "RSM views of the lights that shine: one per spot or "
                 "directional light, six per point light", "",
                 lambda c: len(_result(c).vpl_sets), "d"),
        Quantity("frame.rsm_texels", "texels of the RSM views (rsm_size² per view), before "
                 "downsampling merges them into VPLs", "",
                 lambda c: int(_result(c).settings.rsm_size) ** 2 * len(_result(c).vpl_sets),
                 ",d"),
        Quantity("audit.rsm_primary", "flux the primary light's RSM reflects (sum of "
                 "channels; a point light's six faces together)", "W", _primary_rsm),
        Quantity("audit.rsm_primary_share", "the primary light's share of the RSM flux", "",
                 lambda c: _ratio(_primary_rsm(c), _audit_sum("rsm")(c))),
        Quantity("frame.stages_ran", "how many stages this frame ran (the others were up "
                 "to date)", "", lambda c: len(_result(c).stages_run), "d"),
        Quantity("frame.stages", "stages of the pipeline (explorer.lpv.stage_list.STAGES)", "",
                 lambda c: len(STAGES), "d", constant=True),
        Quantity("frame.gbuffer_ran", "whether this frame rendered the G-buffer again "
                 "(yes/no)", "", _ran("gbuffer"), ""),
        Quantity("frame.moved_objects", "objects moved from where the scene puts them", "",
                 lambda c: len(_settings(c).object_transforms), "d"),
        Quantity("frame.vpl_depth_min", "nearest depth of a lit VPL in the light's view "
                 "(w, along the light's axis)", "m", _vpl_depth(np.min), ".2f"),
        Quantity("frame.vpl_depth_max", "farthest depth of a lit VPL in the light's view",
                 "m", _vpl_depth(np.max), ".2f"),
        Quantity("frame.cell_size", "edge of a cell of the (finest) grid", "m",
                 lambda c: float(_result(c).grid_spec.cell_size)),
        Quantity("frame.grid_extent", "edge of the (finest) grid (its longest)", "m",
                 lambda c: float(np.max(_result(c).grid_spec.extents))),
        Quantity("frame.cells", "cells of one grid, N³ (nx·ny·nz)", "",
                 lambda c: int(np.prod(_settings(c).grid_shape)), "d"),
        Quantity("frame.face_evaluations", "face evaluations per colour and frame: 30 per "
                 "cell and step (6 neighbours × 5 faces), 54 with 26 neighbours (the outer "
                 "faces of the 3×3×3 block)", "", _face_evaluations, ",d"),
        Quantity("frame.lpv_memory_mib", "GPU memory of the LPV textures at these settings "
                 "(light grids, audit records, geometry volume; all cascades)", "MiB",
                 _memory_mib, ".1f"),
        Quantity("frame.time.total", "time of all passes that ran for this frame", "ms",
                 _time("total"), ".0f"),
        Quantity("frame.timer", "how the propagation pass was timed: GPU timer queries, or "
                 "the wall clock around a finished dispatch (llvmpipe, compute)", "",
                 _timer, ""),
        Quantity("frame.renderer", "the GL renderer the frame ran on", "", _renderer, ""),
        Quantity("frame.fog_lpv_share", "share of the light the fog scatters towards the "
                 "eye that comes from the LPV (the rest is the direct light), by luminance",
                 "", _fog_lpv_share, ".0%"),
        Quantity("frame.fog_transmittance", "mean transmittance exp(−σ_t·ℓ) from the eye to "
                 "the surfaces on screen", "", _fog_transmittance, ".2f"),
        Quantity("frame.grid_origin", "corner of the (finest) grid in world units: it moves "
                 "in whole cells when cascades follow the camera", "m",
                 lambda c: tuple(float(v) for v in _result(c).grid_spec.origin), ".3f"),
        *[Quantity(f"frame.grid_origin_{axis}", f"{axis} of the (finest) grid's corner "
                   "(frame.grid_origin)", "m",
                   lambda c, i=i: float(_result(c).grid_spec.origin[i]), ".3f")
          for i, axis in enumerate("xyz")],
        *[Quantity(f"frame.time.{name}", f"time of the {name} pass (timer query on a GPU, "
                   "wall clock around compute on llvmpipe)", "ms", _time(name), ".1f")
          for name in PASSES],
        Quantity("error.relative_l2", "‖LPV − reference‖ / ‖reference‖ over the visible "
                 "pixels (0 is exact; a black image scores 1)", "", _error("relative_l2"),
                 ".2f"),
        Quantity("error.flux_ratio", "light on screen, LPV / reference (1 is exact)", "",
                 _error("flux_ratio"), ".2f"),
        Quantity("error.rmse", "root mean square of LPV − reference", "W/(m²·sr)",
                 _error("rmse"), ".3g"),
        *[Quantity(f"error.flux_ratio_{colour}", f"flux ratio of the {colour} channel", "",
                   _error("flux_ratio_rgb", i), ".2f")
          for i, colour in enumerate(("red", "green", "blue"))],
        Quantity("error.mitsuba_flux_ratio", "light on screen, LPV / Mitsuba's one bounce "
                 "(physics; measured with the truth \"reference + Mitsuba\")", "",
                 _error("mitsuba_flux_ratio"), ".2f"),
        Quantity("error.mitsuba_relative_l2", "‖LPV − Mitsuba's one bounce‖ / ‖Mitsuba's "
                 "one bounce‖", "", _error("mitsuba_relative_l2"), ".2f"),
        *[Quantity(f"error.mitsuba_flux_ratio_{colour}", f"flux ratio of the {colour} "
                   "channel, LPV / Mitsuba's one bounce", "",
                   _error("mitsuba_flux_ratio_rgb", i), ".2f")
          for i, colour in enumerate(("red", "green", "blue"))],
        Quantity("error.mitsuba_multi_flux_ratio", "light on screen, LPV / Mitsuba's every "
                 "bounce", "", _error("mitsuba_multi_flux_ratio"), ".2f"),
        Quantity("error.reference_mitsuba_flux_ratio", "light on screen, the project's "
                 "reference / Mitsuba's one bounce: what the RSM's sampling costs", "",
                 _error("reference_mitsuba_flux_ratio"), ".3f"),
        Quantity("error.reference_mitsuba_relative_l2", "‖reference − Mitsuba's one "
                 "bounce‖ / ‖Mitsuba's one bounce‖ (about half of it Mitsuba's noise)", "",
                 _error("reference_mitsuba_relative_l2"), ".2f"),
        Quantity("corrections.preset", "the corrections preset shown (or custom)", "",
                 _preset, ""),
    ]
    return {item.name: item for item in items}


_TABLE: dict[str, Quantity] | None = None


def table() -> dict[str, Quantity]:
    """Every fixed quantity (settings, switches, audit, frame, error); ``derived.*`` and
    ``figure.*`` names are checked by :func:`lookup`."""
    global _TABLE
    if _TABLE is None:
        from explorer.lpv.settings import Corrections, Settings

        items = _fixed()
        for f in fields(Settings):
            if f.name in ("corrections", "camera", "light", "object_transforms"):
                continue
            spec = f.metadata.get("spec") if f.metadata else None
            doc = getattr(spec, "doc", "") or f.name
            items[f"settings.{f.name}"] = Quantity(
                f"settings.{f.name}", doc, getattr(spec, "unit", ""), _setting(f.name), "")
        for name in Corrections.names():
            items[f"corrections.{name}"] = Quantity(
                f"corrections.{name}", f"whether the {name} correction is on", "",
                _switch(name), "")
        _TABLE = items
    return _TABLE


def _mark_quantity(name: str, mark_ids: tuple[str, ...]) -> Quantity:
    from explorer.lessons.marks import READOUTS, readout

    parts = name.split(".")
    if len(parts) != 3 or parts[2] not in READOUTS:
        raise KeyError(f"{name!r}: a mark number is mark.<mark id>.<readout>, readouts: "
                       f"{', '.join(READOUTS)}")
    if parts[1] not in mark_ids:
        raise KeyError(f"{name!r}: the step has no mark with id {parts[1]!r} (its marks "
                       f"with a normal: {list(mark_ids) or 'none'})")
    mark_id, what = parts[1], parts[2]

    def read(context: LiveContext) -> float:
        mark = context.marks.get(mark_id)
        if mark is None:
            raise Unavailable(f"the mark {mark_id!r} is not in this context")
        try:
            return readout(mark, _result(context), what)
        except ValueError as exc:
            raise Unavailable(str(exc)) from None
    doc, unit = READOUTS[parts[2]]
    return Quantity(name, doc, unit, read, ".3g" if unit else ".0%")


def lookup(name: str, figure_ids: tuple[str, ...] = (),
           mark_ids: tuple[str, ...] = ()) -> Quantity:
    """The quantity called ``name``; ``figure_ids``: the figures of the step, for
    ``figure.<id>.<readout>``; ``mark_ids``: its marks that measure (have a normal), for
    ``mark.<id>.<readout>``. KeyError with the closest names otherwise."""
    source = name.split(".", 1)[0]
    if source == "mark":
        return _mark_quantity(name, mark_ids)
    if source == "derived":
        from explorer import derived

        result = derived.get(name[len("derived."):])   # KeyError names close matches
        if result.value is None:
            raise KeyError(f"derived.{result.name} has no numeric value (it is a formula); "
                           "show it with {{formula:" + result.name + "}}")
        return Quantity(name, result.statement, "", _derived(result.name), ".6g")
    if source == "figure":
        parts = name.split(".")
        if len(parts) != 3:
            raise KeyError(f"{name!r}: a figure number is figure.<figure id>.<readout>")
        if parts[1] not in figure_ids:
            raise KeyError(f"{name!r}: the step has no figure with id {parts[1]!r} "
                           f"(its figures: {list(figure_ids) or 'none'})")
        figure_id, readout = parts[1], parts[2]

        def read(context: LiveContext) -> float:
            values = context.figures.get(figure_id)
            if values is None or readout not in values:
                raise Unavailable(f"figure {figure_id!r} shows no {readout!r} yet")
            return float(values[readout])
        # in words for the article's hover: "l1_min" reads "l1 min"
        return Quantity(name, f"the {readout.replace('_', ' ')} the figure {figure_id} shows",
                        "", read, ".3g")
    items = table()
    if name in items:
        return items[name]
    close = difflib.get_close_matches(name, list(items), n=5, cutoff=0.6)
    hint = f"; did you mean {', '.join(close)}?" if close else ""
    raise KeyError(f"no live quantity {name!r}{hint} (sources: {', '.join(SOURCES)})")


MAX_FORMAT_WIDTH = 40
"""Widest field and most digits a lesson's format may ask for (``{{x:>40.12f}}`` at most):
a number in prose needs far fewer, and ``{{x:>1000000000}}`` would print a 1 GB line."""

_FORMAT_NUMBERS = re.compile(r"^(?:.?[<>=^])?[-+ ]?z?#?0?(\d*)[,_]?(?:\.(\d+))?[a-zA-Z%]?$")


def bounded_format(fmt: str) -> bool:
    """Whether the format spec ``fmt`` asks for at most :data:`MAX_FORMAT_WIDTH` columns
    and digits (a spec this cannot read is left to ``format`` to judge)."""
    match = _FORMAT_NUMBERS.match(fmt)
    if match is None:
        return not re.search(r"\d{3,}", fmt)
    return all(int(number or 0) <= MAX_FORMAT_WIDTH for number in match.groups())


def check_format(fmt: str, quantity: Quantity) -> None:
    """ValueError when ``fmt`` cannot format the quantity's kind of value, or asks for a
    wider field or more digits than :data:`MAX_FORMAT_WIDTH`."""
    if not bounded_format(fmt):
        raise ValueError(f"format {fmt!r} asks for more than {MAX_FORMAT_WIDTH} columns or "
                         f"digits")
    probe: Any = 1.5
    if quantity.source in ("settings", "corrections") or quantity.format == "":
        return          # configuration values are shown as they are (text or number)
    if quantity.format.endswith("d"):
        probe = 3
    try:
        format(probe, fmt)
    except (ValueError, TypeError) as exc:
        raise ValueError(f"format {fmt!r} does not apply to {quantity.name}: {exc}") from None


def pending_reason(name: str, context: LiveContext,
                   figure_ids: tuple[str, ...] = ()) -> str | None:
    """Why ``name`` shows :data:`PENDING` now (the :class:`Unavailable` message), or None
    when it has a value."""
    try:
        lookup(name, figure_ids, tuple(context.marks)).value(context)
    except Unavailable as exc:
        return str(exc)
    return None


def render(name: str, fmt: str, context: LiveContext,
           figure_ids: tuple[str, ...] = ()) -> str:
    """The text a lesson shows for ``{{name:fmt}}`` now: the formatted value, or
    :data:`PENDING` when the quantity has no value yet. Unknown names raise KeyError."""
    quantity = lookup(name, figure_ids, tuple(context.marks))
    try:
        value = quantity.value(context)
    except Unavailable:
        return PENDING
    return format_value(value, fmt or quantity.format)


def format_value(value: Any, fmt: str) -> str:
    """``value`` as text: booleans as on/off, floats with ``fmt`` (a Python format spec),
    a minus sign rather than a hyphen, inf and nan spelled out."""
    if isinstance(value, bool):
        return "on" if value else "off"
    if isinstance(value, str):
        return value
    if isinstance(value, float) and not math.isfinite(value):
        return "∞" if value > 0 else "−∞" if value < 0 else "undefined"
    if isinstance(value, (tuple, list)):
        return "(" + ", ".join(format_value(v, fmt) for v in value) + ")"
    if fmt == "" and isinstance(value, float):
        fmt = "g"
    if not bounded_format(fmt):
        fmt = ""
    try:
        text = format(value, fmt)
    except (ValueError, TypeError):
        text = str(value)
    return text.replace("-", "−") if isinstance(value, (int, float)) else text
