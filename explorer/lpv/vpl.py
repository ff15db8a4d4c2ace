"""Virtual point lights: the hand-over from the reflective shadow map to injection.

On the GPU a VPL set is three 2D textures of the same size (one VPL per texel); tests,
lessons and notebooks build the same thing from numpy arrays. See docs/MODEL.md.
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Generator
from dataclasses import dataclass

import moderngl
import numpy as np

from explorer.gl.gpu_sync import DeferredRead, issue_together

PROJECTIONS = ("perspective", "orthographic")
UPLOAD_ROW = 4096
"""Texels per row when VPL arrays are uploaded (GL guarantees 2D textures this wide)."""
TAKEN_APART_TEXELS = 1 << 18
"""A VPL set of more texels than this (than a 512² RSM has) is taken back in units: each array
compressed and copied in one (:meth:`VplTextures.arrays_taken_units`)."""


@dataclass(frozen=True)
class VplArrays:
    """VPLs as numpy arrays, ``M`` of them.

    ``positions`` (M, 3) world; ``normals`` (M, 3) unit; ``flux`` (M, 3) watts per channel;
    ``depth`` (M,) view depth from the light (used for the surfel area);
    ``texel_area``: for ``projection == "perspective"`` the area of one texel at depth 1
    (``4/(W·H)`` for a 90° frustum), for ``"orthographic"`` the world area of one texel.
    ``albedo`` (M, 3), optional: the diffuse reflectance of each VPL's surface, which the
    geometry volume needs to reflect blocked light (``Settings.bounces`` 2); None = 0.
    """

    positions: np.ndarray
    normals: np.ndarray
    flux: np.ndarray
    depth: np.ndarray
    texel_area: float
    projection: str = "perspective"
    albedo: np.ndarray | None = None

    def __post_init__(self) -> None:
        count = _rows(self.positions, "positions", 3)
        named = [("normals", 3), ("flux", 3)] + ([("albedo", 3)] if self.albedo is not None
                                                 else [])
        for name, cols in named:
            if _rows(getattr(self, name), name, cols) != count:
                raise ValueError(f"{name} must have {count} rows like positions")
        depth = np.asarray(self.depth)
        if depth.shape != (count,):
            raise ValueError(f"depth must have shape ({count},), got {depth.shape}")
        if self.projection not in PROJECTIONS:
            raise ValueError(f"projection must be one of {PROJECTIONS}, got {self.projection!r}")
        if not self.texel_area > 0:
            raise ValueError(f"texel_area must be positive, got {self.texel_area}")

    @property
    def count(self) -> int:
        return int(np.asarray(self.positions).shape[0])

    def digest(self) -> str:
        """Content hash of the arrays, so that the same hand-made VPLs handed to the
        pipeline again do not run the injection again (a stage key)."""
        digest = hashlib.sha1()
        arrays = [self.positions, self.normals, self.flux, self.depth]
        if self.albedo is not None:
            arrays.append(self.albedo)
        for array in arrays:
            digest.update(np.ascontiguousarray(array, np.float32).tobytes())
        digest.update(repr((self.texel_area, self.projection)).encode())
        return digest.hexdigest()

    @classmethod
    def concatenate(cls, sets: list[VplArrays]) -> VplArrays:
        """Every VPL of ``sets`` in one set (several lights' VPLs: docs/MODEL.md "Several
        lights"). ``texel_area`` and ``projection`` are the first set's, so
        :meth:`surfel_area` is right for its VPLs only; the albedo is kept when every set
        has one."""
        if not sets:
            raise ValueError("no VPL sets to concatenate")

        def stack(name: str) -> np.ndarray:
            return np.concatenate([np.asarray(getattr(v, name)) for v in sets])

        albedo = stack("albedo") if all(v.albedo is not None for v in sets) else None
        return cls(stack("positions"), stack("normals"), stack("flux"), stack("depth"),
                   sets[0].texel_area, sets[0].projection, albedo)

    def surfel_area(self, squared: bool) -> np.ndarray:
        """World area of each VPL's surfel (annotations §5): ``texel_area·depth²``, or
        ``texel_area·depth`` when ``squared`` is False (the published bug); orthographic
        texels have the same area at any depth."""
        depth = np.asarray(self.depth, dtype=np.float64)
        if self.projection == "orthographic":
            return np.full_like(depth, self.texel_area)
        return self.texel_area * (depth * depth if squared else depth)


@dataclass
class VplTextures:
    """VPLs as three ``rgba32f`` 2D textures of the same size.

    ``position.xyz`` world position, ``position.w`` = 1 where the light saw a surface and
    0 elsewhere (such texels are skipped); ``normal.xyz`` unit normal, ``normal.w`` = view
    depth from the light; ``flux.rgb`` watts per channel. ``albedo`` (optional, same size):
    ``albedo.rgb`` the surface's diffuse reflectance (the RSM writes it; the geometry volume
    reads it for ``Settings.bounces`` 2).
    """

    position: moderngl.Texture
    normal: moderngl.Texture
    flux: moderngl.Texture
    texel_area: float
    projection: str = "perspective"
    albedo: moderngl.Texture | None = None

    @property
    def size(self) -> tuple[int, int]:
        return self.position.size

    @classmethod
    def from_arrays(cls, ctx: moderngl.Context, vpls: VplArrays) -> VplTextures:
        """Upload VPL arrays as a texture set of rows of at most ``UPLOAD_ROW`` texels
        (row-major); texels past the last VPL are empty (``position.w = 0``)."""
        count = vpls.count
        if count == 0:
            raise ValueError("no VPLs to upload")
        width = min(count, UPLOAD_ROW)
        height = -(-count // width)
        position = np.zeros((width * height, 4), np.float32)
        normal = np.zeros_like(position)
        flux = np.zeros_like(position)
        position[:count, :3] = vpls.positions
        position[:count, 3] = 1.0
        normal[:count, :3] = vpls.normals
        normal[:count, 3] = vpls.depth
        flux[:count, :3] = vpls.flux
        arrays = [position, normal, flux]
        if vpls.albedo is not None:
            albedo = np.zeros_like(position)
            albedo[:count, :3] = vpls.albedo
            arrays.append(albedo)
        textures = [ctx.texture((width, height), 4, data.tobytes(), dtype="f4")
                    for data in arrays]
        for texture in textures:
            texture.filter = (moderngl.NEAREST, moderngl.NEAREST)
        return cls(*textures[:3], texel_area=vpls.texel_area, projection=vpls.projection,
                   albedo=textures[3] if len(textures) > 3 else None)

    def to_arrays(self) -> VplArrays:
        """Read the valid texels back as arrays (row-major over the texture)."""
        return self._arrays([np.frombuffer(texture.read(), dtype=np.float32)
                             for texture in self.all_textures])

    @property
    def all_textures(self) -> list[moderngl.Texture]:
        """Position, normal, flux and (when there is one) albedo."""
        return [self.position, self.normal, self.flux] + (
            [] if self.albedo is None else [self.albedo])

    def read_later(self, reads: list[DeferredRead]) -> None:
        """:meth:`to_arrays` without waiting: each texture copied into its read (one per
        texture of :attr:`all_textures`); :meth:`arrays_taken` of them gives the arrays."""
        textures = self.all_textures
        issue_together(reads[:len(textures)], textures,
                       [(math.prod(texture.size), 4) for texture in textures])

    def arrays_taken(self, reads: list[DeferredRead]) -> VplArrays:
        return self._arrays([read.wait() for read in reads[:len(self.all_textures)]])

    def arrays_taken_units(self, reads: list[DeferredRead]) -> Generator[None, None, VplArrays]:
        """:meth:`arrays_taken` in units (``yield from`` returns the arrays): above
        :data:`TAKEN_APART_TEXELS` texels each array compressed and copied in a unit of its
        own (a 1024² RSM's took 150 ms on llvmpipe as one), the same arrays."""
        texels = [read.wait() for read in reads[:len(self.all_textures)]]
        apart = math.prod(self.position.size) > TAKEN_APART_TEXELS
        return (yield from self._arrays_units(texels, apart))

    def _arrays(self, texels: list[np.ndarray]) -> VplArrays:
        done = self._arrays_units(texels, False)
        while True:
            try:
                next(done)
            except StopIteration as taken:
                return taken.value

    def _arrays_units(self, texels: list[np.ndarray], apart: bool
                      ) -> Generator[None, None, VplArrays]:
        position, normal, flux = (np.asarray(t).reshape(-1, 4) for t in texels[:3])
        # whole valid rows first (one contiguous pass each), then their columns
        valid = position[:, 3] > 0.5
        rows = []
        for array in (position, normal, flux):
            if apart and rows:
                yield
            rows.append(array.compress(valid, axis=0))
        position, normal, flux = rows
        albedo = None
        if self.albedo is not None:
            if apart:
                yield
            albedo = np.asarray(texels[3]).reshape(-1, 4).compress(valid, axis=0)[:, :3].copy()
        columns = []
        for array in (position, normal, flux):
            if apart:
                yield
            columns.append(array[:, :3].copy())
        return VplArrays(*columns, normal[:, 3].copy(), self.texel_area, self.projection,
                         albedo)

    def release(self) -> None:
        for texture in (self.position, self.normal, self.flux, self.albedo):
            if texture is not None:
                texture.release()


def _rows(array: np.ndarray, name: str, cols: int) -> int:
    shape = np.asarray(array).shape
    if len(shape) != 2 or shape[1] != cols:
        raise ValueError(f"{name} must have shape (M, {cols}), got {shape}")
    return shape[0]
