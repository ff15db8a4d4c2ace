"""What each stage of a frame leaves for the next: :class:`FrameState`, one typed field per
thing a stage makes (its images read back, the cascade levels it fills, the passes whose
textures hold its output on the GPU).

The stages (explorer/lpv/stages/) write their own fields and read their upstream
stages' fields; :func:`explorer.lpv.frame.frame_result` assembles the
:class:`~explorer.lpv.frame.FrameResult` from it once every stage is complete. A field
keeps what the stage's last completed run left (a stage whose key has not changed does
not run, and its field stays valid).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from explorer.lpv.cascades import CascadeInput, SampledGrid
from explorer.lpv.deferred import DeferredField
from explorer.lpv.grid import GridSpec
from explorer.lpv.passes.fog import FogImages
from explorer.lpv.passes.gather import GatherImages
from explorer.lpv.vpl import VplArrays

if TYPE_CHECKING:
    from explorer.lpv.cascade_level import CascadeLevel
    from explorer.lpv.guards import StageWarnings
    from explorer.lpv.passes.fog import FogPass
    from explorer.lpv.passes.gather import GatherPass
    from explorer.lpv.passes.gbuffer import GBufferPass


@dataclass
class GBufferImages:
    """The G-buffer read back, ``(H, W, 4)`` each, row 0 at the top."""

    position: np.ndarray
    """World position, w = 1 where a surface is seen."""
    normal: np.ndarray
    """Viewer-facing normal, w = the surface's world area under the pixel."""
    albedo: np.ndarray


@dataclass
class RsmImages:
    """The RSMs read back (docs/MODEL.md "Several lights")."""

    position: np.ndarray
    normal: np.ndarray
    flux: np.ndarray
    """The primary view's position, normal and flux, ``(Hr, Wr, 4)``."""
    # summed when first read (explorer/lpv/deferred.py): only the audit reads them
    total_flux: np.ndarray = DeferredField()  # type: ignore[assignment]
    """(3,) every light's flux together."""
    flux_per_light: np.ndarray = DeferredField()  # type: ignore[assignment]
    """(lights, 3): each light's flux summed over its views."""
    light_views: tuple = ()
    """The views rendered (``explorer.lpv.passes.rsm.LightView``: matrices, light, face)."""
    views: tuple[tuple[np.ndarray, np.ndarray, np.ndarray], ...] | None = None
    """Every view's (position, normal, flux), in ``LightViews.views`` order, when the frame
    keeps its steps (``keep_steps``: a dump writes every view) or has one view; None
    otherwise."""


@dataclass
class VplImages:
    """The VPLs the injection read, read back."""

    vpls: VplArrays
    """Every set together."""
    sets: list[VplArrays]
    """Per set: one per RSM view, or the one hand-made set."""
    view_lights: tuple[int, ...]
    """The light index of each set."""
    hand_made: bool = False
    """The VPLs were handed to the pipeline (one set, no RSM view of their own)."""


@dataclass
class FrameState:
    """What each stage leaves for the next (module docstring), by stage."""

    specs: list[GridSpec] = field(default_factory=list)
    """``grid``: each cascade's grid, finest first."""
    levels: list[CascadeLevel] = field(default_factory=list)
    """``inject``, ``geometry``, ``propagate``: each cascade's grids on the GPU and what
    was read back of them (at least ``len(specs)`` once ``inject`` ran)."""
    gbuffer: GBufferImages | None = None
    rsm: RsmImages | None = None
    vpls: VplImages | None = None
    """``downsample``."""
    gather: GatherImages | None = None
    fog: FogImages | None = None
    """None while the fog is off."""
    display_scale: float = 1.0
    """``display``: what it multiplied the exposed image by (docs/MODEL.md "Display")."""
    warnings: dict[str, StageWarnings] = field(default_factory=dict)
    """Stage -> the warnings of its last run (explorer/lpv/guards.py): a list, or the
    Deferred check that makes it when the frame's warnings are read."""
    # the passes whose textures hold a stage's output on the GPU (set when the stages
    # are made; the textures are (re)allocated when they run)
    gbuffer_pass: GBufferPass | None = None
    gather_pass: GatherPass | None = None
    fog_pass: FogPass | None = None

    @property
    def cascades(self) -> list[CascadeLevel]:
        """The levels of this frame's cascades (``len(specs)`` of them)."""
        return self.levels[: len(self.specs)]

    def sampled_grid(self) -> SampledGrid:
        """The accumulation of every cascade as the gather and the fog sample it now."""
        levels = self.cascades
        assert levels[0].injected is not None, "sampled before the first injection"
        return SampledGrid(tuple(CascadeInput(spec, level.accumulation_textures)
                                 for spec, level in zip(self.specs, levels)),
                           levels[0].injected.sh_order)

    def injected_grid(self) -> SampledGrid:
        """Every cascade's injected grid as the gather samples an accumulation (grid_0:
        what the accumulation holds before the propagation's first step)."""
        grids = []
        for level in self.cascades:
            assert level.injected is not None, "sampled before the injection"
            grids.append(level.injected)
        return SampledGrid(tuple(CascadeInput(spec, grid.textures)
                                 for spec, grid in zip(self.specs, grids)), grids[0].sh_order)

    def drop_steps(self) -> None:
        """Forget every level's kept propagation steps (grid_0..grid_N): a frame that did
        not ask for them gets none, and they stay alive only in the frames that did."""
        for level in self.levels:
            if level.output is not None and level.output.steps is not None:
                level.output = replace(level.output, steps=None)

    def levels_for_specs(self, make: Callable[[], CascadeLevel]) -> list[CascadeLevel]:
        """One level per spec: missing ones made by ``make``, extra ones released."""
        self.release_levels(len(self.specs))
        while len(self.levels) < len(self.specs):
            self.levels.append(make())
        return self.levels

    def release_levels(self, keep: int) -> None:
        for level in self.levels[keep:]:
            level.release()
        del self.levels[keep:]
