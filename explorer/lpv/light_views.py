"""The light's side of a frame: one RSM per view of every light that shines (a point light
has six), their VPLs (downsampled or hand-made) and the atlases that copy several views
side by side (explorer/lpv/passes/atlas.py), so that the injection reads every view's VPLs at
once and the gather and the fog every view's shadow map (docs/MODEL.md "Several lights").

:class:`LightViews` is owned by the pipeline (``Pipeline.light_views``); its ``rsm`` and
``downsample`` stages call :meth:`LightViews.render` and :meth:`LightViews.choose_vpls_later`,
and every later stage reads what they leave: the views, each view's RSM set, the shadow
maps as one set (:attr:`LightViews.rsm_textures`, the atlas of several views, with
:attr:`LightViews.shadow_tiles`) and the VPLs the injection reads
(:attr:`LightViews.vpl_textures`). One view needs no atlas: its set is used as it is.
"""

from __future__ import annotations

from collections.abc import Generator, Iterator

import moderngl
import numpy as np

from explorer.gl.gpu_sync import DeferredRead
from explorer.gl.program import ProgramCache
from explorer.lpv.audit import flux_per_light
from explorer.lpv.deferred import Deferred
from explorer.lpv.frame_state import RsmImages, VplImages
from explorer.lpv.grid import GridSpec
from explorer.lpv.passes.atlas import PerView, VplAtlas
from explorer.lpv.passes.downsample import DownsamplePass
from explorer.lpv.passes.light_records import ShadowMaps
from explorer.lpv.passes.rsm import LightView, RsmPass, light_views, read_texture
from explorer.lpv.settings import Settings
from explorer.lpv.timing import PassTimer
from explorer.lpv.vpl import VplArrays, VplTextures
from explorer.scene import Scene
from explorer.scene.gpu import SceneBuffers


class LightViews:
    """The RSM and downsample passes of every light view, the atlases of their textures
    and what the last ``rsm`` and ``downsample`` stages left."""

    def __init__(self, ctx: moderngl.Context, programs: ProgramCache,
                 timer: PassTimer) -> None:
        self.ctx = ctx
        self.timer = timer
        """The pipeline's timer: the passes and atlases are timed into its ``rsm`` and
        ``downsample`` entries."""
        self.rsm = PerView(lambda: RsmPass(ctx, programs))
        """One RSM pass per view (each owns the textures it renders)."""
        self.downsample = PerView(lambda: DownsamplePass(ctx, programs))
        self._rsm_atlas = VplAtlas(ctx, programs)
        self._vpl_atlas = VplAtlas(ctx, programs)
        self.views: list[LightView] = []
        """The RSM views of every light that shines (primary first)."""
        self.rsm_sets: list[VplTextures] = []
        """Each view's RSM, in the order of :attr:`views`."""
        self.rsm_textures: VplTextures | None = None
        """Every view's RSM (and shadow map) as one set: the atlas, or the one view's."""
        self.shadow_tiles: list[tuple[int, int]] = [(0, 0)]
        """Where each view's tile starts in :attr:`rsm_textures`."""
        self.vpl_sets: list[VplTextures] = []
        """The VPLs the injection reads, per view (one set for hand-made VPLs)."""
        self.vpl_textures: VplTextures | None = None
        """:attr:`vpl_sets` as one set (the atlas, or the one set)."""
        self._override_textures: VplTextures | None = None
        """Hand-made VPLs uploaded by :meth:`choose_vpls_later` (released at the next call)."""

    @staticmethod
    def of(scene: Scene, rsm_size: int, snap: bool = False,
           placed: Scene | None = None) -> list[LightView]:
        """The RSM views of ``scene``'s lights that shine
        (:func:`explorer.lpv.passes.rsm.light_views`; ``snap``: ``Settings.rsm_snap``, on
        the lattices through the lights as ``placed`` (the scene as loaded) has them)."""
        anchors = {} if placed is None else {light.name: light for light in placed.rig}
        return light_views(scene, rsm_size, snap, anchors)

    def render(self, views: list[LightView], geometry: SceneBuffers,
               largest: int) -> Iterator[None]:
        """The ``rsm`` stage's GPU work: one RSM per view (a unit each, yielding after
        it), then the atlas of their shadow maps and VPLs within ``largest`` texels per
        side (several views)."""
        self.timer.reset("rsm")
        sets = []
        for k, view in enumerate(views):
            sets.append(self.timer.timed("rsm", lambda: self.rsm.run(k, geometry, view),
                                         accumulate=True))
            yield
        self.views, self.rsm_sets = views, sets
        self.rsm.keep(len(views))
        self.rsm_textures, self.shadow_tiles = self._atlas(self._rsm_atlas, sets, "rsm",
                                                           largest)

    def rsm_textures_read(self, every_view: bool = False) -> list[moderngl.Texture]:
        """What :meth:`rsm_read_back` reads: the primary view's position and normal, then
        every view's flux (float32 RGBA each); ``every_view``: then the other views'
        positions and normals too (a dump's every RSM)."""
        first = self.rsm_sets[0]
        textures = [first.position, first.normal] + [rsm.flux for rsm in self.rsm_sets]
        if every_view:
            textures += [texture for rsm in self.rsm_sets[1:]
                         for texture in (rsm.position, rsm.normal)]
        return textures

    def rsm_read_back(self, arrays: list[np.ndarray] | None = None, every_view: bool = False
                      ) -> tuple[RsmImages, list[np.ndarray]]:
        """The last RSMs read back: the primary view's position, normal and flux, each
        light's flux summed over its views (docs/MODEL.md "Several lights") and their
        sum, with ``every_view`` (or a single view) every view's position, normal and flux
        (``RsmImages.views``); and every array read, for the finiteness check. ``arrays``:
        those of :meth:`rsm_textures_read` as read already (a deferred read-back)."""
        if arrays is None:
            arrays = [read_texture(texture)
                      for texture in self.rsm_textures_read(every_view)]
        count = len(self.rsm_sets)
        flux = arrays[2:2 + count]
        primary = (arrays[0], arrays[1], flux[0])
        lights = [view.light_index for view in self.views]
        views = (primary,) if count == 1 else None      # one view: read back already
        if every_view and count > 1:
            others = arrays[2 + count:]
            views = (primary,) + tuple((others[2 * k], others[2 * k + 1], flux[k + 1])
                                       for k in range(count - 1))
        # the flux sums are taken when the audit reads them, while the frame keeps every
        # view's arrays anyway (one view, or all kept): else now, so that a kept frame
        # does not hold the other views' flux for its sums
        per_light = Deferred(lambda: flux_per_light(flux, lights))
        if views is None:
            per_light.value()
        return RsmImages(*primary, total_flux=Deferred(lambda: per_light.value().sum(axis=0)),
                         flux_per_light=per_light, light_views=tuple(self.views),
                         views=views), arrays

    def choose_vpls_later(self, s: Settings, vpls: VplArrays | None, spec: GridSpec,
                          largest: int) -> None:
        """The ``downsample`` stage's GPU work: the VPLs the injection reads are the
        hand-made ``vpls``, the RSMs as they are, or each view's RSM downsampled onto the
        finest grid ``spec`` (then their atlas within ``largest`` texels per side). Each
        of :attr:`vpl_sets` then copies its read-back (``VplTextures.read_later``, into
        :meth:`reads_for`'s lists) and :meth:`vpls_taken` takes them."""
        if self._override_textures is not None:
            self._override_textures.release()
            self._override_textures = None
        if vpls is not None or s.downsample == "none" or s.downsample_factor == 1:
            self.downsample.keep(0)         # no set is downsampled: their passes go
            self._vpl_atlas.release_targets()
        if vpls is not None:
            self.timer.forget("downsample")
            self._override_textures = VplTextures.from_arrays(self.ctx, vpls)
            self.vpl_textures = self._override_textures
            self.vpl_sets = [self._override_textures]
        elif s.downsample == "none" or s.downsample_factor == 1:
            self.timer.forget("downsample")
            self.vpl_textures, self.vpl_sets = self.rsm_textures, list(self.rsm_sets)
        else:
            self.timer.reset("downsample")
            self.vpl_sets = [self.timer.timed("downsample", lambda: self.downsample.run(
                k, rsm, s.downsample, s.downsample_factor, spec, view), accumulate=True)
                for k, (rsm, view) in enumerate(zip(self.rsm_sets, self.views))]
            self.downsample.keep(len(self.vpl_sets))
            self.vpl_textures, _ = self._atlas(self._vpl_atlas, self.vpl_sets, "downsample",
                                               largest)

    def reads_for(self, reads: list[list[DeferredRead]]) -> list[list[DeferredRead]]:
        """``reads`` grown to one list of four per VPL set (the caller keeps them), those
        of sets there no longer are released and dropped (a point light's six views'
        read-backs stayed after it went)."""
        count = max(len(self.vpl_sets), len(self.rsm_sets))
        while len(reads) < count:
            reads.append([DeferredRead(self.ctx) for _ in range(4)])
        for extra in reads[count:]:
            for read in extra:
                read.release()
        del reads[count:]
        return reads

    def vpls_taken(self, reads: list[list[DeferredRead]], hand_made: bool) -> VplImages:
        """The VPLs read back (per set, all of them, each set's light index) from the
        copies of :meth:`choose_vpls_later`'s sets."""
        return self._vpl_images([vpl_set.arrays_taken(set_reads)
                                 for vpl_set, set_reads in zip(self.vpl_sets, reads)],
                                hand_made)

    def vpls_taken_units(self, reads: list[list[DeferredRead]], hand_made: bool
                         ) -> Generator[None, None, VplImages]:
        """:meth:`vpls_taken` in units (``VplTextures.arrays_taken_units``; ``yield from``
        returns the VPLs), the same VPLs."""
        sets = []
        for vpl_set, set_reads in zip(self.vpl_sets, reads):
            sets.append((yield from vpl_set.arrays_taken_units(set_reads)))
        return self._vpl_images(sets, hand_made)

    def _vpl_images(self, sets: list[VplArrays], hand_made: bool) -> VplImages:
        return VplImages(
            vpls=sets[0] if len(sets) == 1 else VplArrays.concatenate(sets), sets=sets,
            view_lights=(0,) if hand_made else tuple(
                view.light_index for view in self.views), hand_made=hand_made)

    @property
    def shadow_maps(self) -> ShadowMaps:
        """Every view's shadow map as the gather and the fog read them."""
        return ShadowMaps(self.rsm_textures, tuple(self.views), tuple(self.shadow_tiles))

    def occluders(self, hand_made: bool) -> list[VplTextures]:
        """The sets the geometry volume is built from: every view's RSM, or the
        hand-made VPLs (they have no RSM of their own)."""
        return [self.vpl_textures] if hand_made else self.rsm_sets

    def _atlas(self, atlas: VplAtlas, sets: list[VplTextures], stage: str, largest: int
               ) -> tuple[VplTextures, list[tuple[int, int]]]:
        """The one set, or the atlas of several (timed into ``stage``), and where each
        view's tile starts."""
        if len(sets) == 1:
            atlas.release_targets()         # one set is used as it is
            return sets[0], [(0, 0)]
        textures = self.timer.timed(stage, lambda: atlas.build(sets, largest),
                                    accumulate=True)
        return textures, [atlas.layout.origin(k) for k in range(len(sets))]

    def release(self) -> None:
        for owned in (self.rsm, self.downsample, self._rsm_atlas, self._vpl_atlas):
            owned.release()
        if self._override_textures is not None:
            self._override_textures.release()
            self._override_textures = None
