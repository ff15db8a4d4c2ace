"""One-bounce reference: every VPL gathered at every visible pixel (instant radiosity).

The LPV spreads the same reflective-shadow-map VPLs through a grid; the reference sums
them exactly. For VPL ``j`` (position ``x_j``, unit normal ``n_j``, flux ``Φ_j`` per
channel) and a receiver ``p`` (normal ``n``, albedo ``a``):

* intensity of the diffuse VPL (docs/MODEL.md "Injection", corrected):
  ``I_j(ω) = Φ_j/π · clamp+⟨n_j, ω⟩``;
* irradiance: ``E(p) = Σ_j I_j(ω_jp) · clamp+⟨n, −ω_jp⟩ / max(|p − x_j|², r_min²) · V_j(p)``
  with ``ω_jp`` the unit vector from ``x_j`` to ``p``;
* indirect outgoing radiance ``L = a/π · E`` (the LPV's final gather has the same form).

``r_min`` (``min_distance``) clamps the 1/r² singularity of two VPL-receiver pairs that
nearly touch. Its default is half an LPV cell: the grid cannot resolve anything closer, so
the clamp removes the spikes instant radiosity is known for without touching what the
grid can represent. ``V_j(p)`` is 1 without visibility (what the LPV without a geometry
volume approximates) or a shadow ray against the scene triangles (a BVH, see ``bvh.py``).
Shadow rays run between the two points pushed ``ray_offset`` along their normals so that
a surface does not shadow itself.

The GPU pass works in tiles of pixels × chunks of VPLs, one dispatch each, so that a long
render reports progress and can be cancelled from the ``progress`` callback, and a window
can run a few dispatches per frame (:class:`ReferenceGather`).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from explorer.lpv.vpl import VplArrays, VplTextures
from explorer.truth.bvh import Bvh, as_triangles, build_bvh

SHADER = "reference_gather.glsl"
_LOCAL_SIZE = 8  # LOCAL_SIZE in reference_gather.glsl
LOOP_BUDGET = 60000
"""Loop iterations one invocation may run per dispatch. Mesa's llvmpipe silently ends
every loop of a shader invocation once 65535 loop-condition checks have run in total (all
loops together, measured on Mesa 22.3), which cut long VPL chunks with shadow rays short.
Chunks are sized so the worst case stays below this budget (:func:`safe_vpl_chunk`), and
the shader flags a chunk that did not finish anyway (:class:`IncompleteRender`)."""

DISPATCHES_PER_FINISH = 8
"""ReferenceGather.advance waits for the GL to finish its dispatches this often."""

ProgressCallback = Callable[[float], "bool | None"]
"""Called after every dispatch with the fraction done in [0, 1]; returning False cancels."""


class Cancelled(RuntimeError):
    """The progress callback asked the reference render to stop."""


class IncompleteRender(RuntimeError):
    """The GL driver ended the gather loop early (see :data:`LOOP_BUDGET`)."""


def safe_vpl_chunk(vpl_chunk: int, bvh: Bvh | None) -> int:
    """``vpl_chunk`` reduced so that one dispatch stays within :data:`LOOP_BUDGET`.

    Worst case per VPL: one check of the VPL loop, and for a shadow ray up to one check
    per BVH node popped (+1 to leave), each of which may run a leaf's triangle loop
    (leaf size + 1 checks): the lanes of a SIMD batch run in lock step, so one lane at a
    leaf costs the whole batch that loop."""
    per_vpl = 2
    if bvh is not None and len(bvh.nodes):
        leaf = int(bvh.nodes["count"].max())
        per_vpl += (len(bvh.nodes) + 1) * (leaf + 2)
    return max(1, min(int(vpl_chunk), LOOP_BUDGET // per_vpl))


@dataclass(frozen=True)
class GBuffer:
    """What the reference needs per pixel, as (H, W, ·) arrays indexed ``[y, x]``.

    ``position`` world position, ``normal`` unit world normal, ``albedo`` diffuse
    reflectance per channel, ``valid`` True where the camera sees a surface.
    """

    position: np.ndarray
    normal: np.ndarray
    albedo: np.ndarray
    valid: np.ndarray

    def __post_init__(self) -> None:
        valid = np.asarray(self.valid)
        if valid.ndim != 2:
            raise ValueError(f"valid must have shape (H, W), got {valid.shape}")
        shape = valid.shape + (3,)
        for name in ("position", "normal", "albedo"):
            array = np.asarray(getattr(self, name))
            if array.shape != shape:
                raise ValueError(f"{name} must have shape {shape} like valid, got {array.shape}")
            if not np.all(np.isfinite(array[valid.astype(bool)])):
                raise ValueError(f"{name} holds NaN or infinite values at valid pixels")

    @property
    def size(self) -> tuple[int, int]:
        """(width, height)."""
        height, width = np.asarray(self.valid).shape
        return width, height


def default_ray_offset(triangles: np.ndarray | None, gbuffer: GBuffer) -> float:
    """1/1000 of the scene's bounding diagonal: far above float32 rounding of positions
    read back from a rasterised G-buffer, far below any feature of the built-in scenes."""
    if triangles is not None and len(triangles):
        points = np.asarray(triangles, dtype=np.float64).reshape(-1, 3)
    else:
        points = np.asarray(gbuffer.position, dtype=np.float64)[np.asarray(gbuffer.valid, bool)]
    if len(points) == 0:
        return 0.0
    return 1e-3 * float(np.linalg.norm(points.max(axis=0) - points.min(axis=0)))


def _check_min_distance(min_distance: float) -> float:
    value = float(min_distance)
    if not (value >= 0.0 and np.isfinite(value)):
        raise ValueError(f"min_distance must be a finite distance >= 0, got {min_distance!r}")
    return value


class ReferencePass:
    """GPU pass: accumulates the irradiance ``E`` of every VPL at every G-buffer pixel."""

    def __init__(self, ctx, programs=None) -> None:
        from explorer.gl.program import load_program

        self.ctx = ctx
        self.program = programs.get(SHADER) if programs is not None else load_program(ctx, SHADER)
        self._owns_program = programs is None
        renderer = str(ctx.info.get("GL_RENDERER", "")).lower()
        # Only Mesa's software rasterisers have the loop limit (LOOP_BUDGET); a GPU runs
        # whole chunks, and the shader's completeness flag still guards every driver.
        self.loop_limited = any(name in renderer for name in ("llvmpipe", "softpipe"))

    def run(self, gbuffer: GBuffer, vpls: VplArrays | VplTextures, min_distance: float,
            triangles: np.ndarray | Bvh | None = None, visibility: bool = False,
            ray_offset: float | None = None, tile_size: int = 64, vpl_chunk: int = 4096,
            progress: ProgressCallback | None = None) -> np.ndarray:
        """Irradiance (H, W, 3) float32; zero at invalid pixels.

        ``visibility`` needs ``triangles`` ((T, 3, 3) or a prebuilt :class:`Bvh`).
        Raises :class:`Cancelled` when ``progress`` returns False.
        """
        gather = self.start(gbuffer, vpls, min_distance, triangles, visibility, ray_offset,
                            tile_size, vpl_chunk)
        try:
            if progress is None:
                gather.step(gather.total)
            while not gather.finished:
                gather.step(1)
                self.ctx.finish()  # make the fraction mean work finished, not queued
                if progress(gather.done / gather.total) is False:
                    raise Cancelled(f"reference render cancelled after {gather.done} of "
                                    f"{gather.total} dispatches")
            return gather.irradiance()
        finally:
            gather.release()

    def start(self, gbuffer: GBuffer, vpls: VplArrays | VplTextures, min_distance: float,
              triangles: np.ndarray | Bvh | None = None, visibility: bool = False,
              ray_offset: float | None = None, tile_size: int = 64,
              vpl_chunk: int = 4096) -> ReferenceGather:
        """:meth:`run` as a :class:`ReferenceGather` whose dispatches the caller runs, a
        few at a time (a window between its frames)."""
        return ReferenceGather(self, gbuffer, vpls, min_distance, triangles, visibility,
                               ray_offset, tile_size, vpl_chunk)

    def release(self) -> None:
        if self._owns_program:
            self.program.release()


class ReferenceGather:
    """One :meth:`ReferencePass.run` split into its dispatches: a tile of pixels × a chunk
    of VPLs each, tiles row by row and each tile's chunks in order (every pixel sums the
    same VPLs in the same order however the dispatches are grouped). :meth:`step` runs a
    given number of them, :meth:`advance` runs them for a time budget; between calls the
    context may do other work (bindings are made again on each call).
    :meth:`irradiance` reads the result once :attr:`finished`; :meth:`release` frees the
    GL objects at any time."""

    def __init__(self, reference: ReferencePass, gbuffer: GBuffer,
                 vpls: VplArrays | VplTextures, min_distance: float,
                 triangles: np.ndarray | Bvh | None = None, visibility: bool = False,
                 ray_offset: float | None = None, tile_size: int = 64,
                 vpl_chunk: int = 4096) -> None:
        import moderngl

        min_distance = _check_min_distance(min_distance)
        if tile_size < 1 or vpl_chunk < 1:
            raise ValueError(f"tile_size and vpl_chunk must be >= 1, got {tile_size}, "
                             f"{vpl_chunk}")
        if visibility and triangles is None:
            raise ValueError("visibility=True needs the scene triangles")
        bvh = None
        if visibility:
            bvh = triangles if isinstance(triangles, Bvh) else build_bvh(triangles)
        if ray_offset is None:
            soup = bvh.triangles if bvh is not None else None
            ray_offset = default_ray_offset(soup, gbuffer)
        self.ctx = ctx = reference.ctx
        self.program = reference.program
        width, height = self.size = gbuffer.size
        self._owned: list = []  # GL objects this gather created and must free
        self.done = 0
        self.tiles: list[tuple[int, int]] = []
        self.chunks: list[int] = []
        self.vpl_chunk = int(vpl_chunk)
        self.total = 0
        self._result = None
        if isinstance(vpls, VplArrays):
            if vpls.count == 0:
                return                      # nothing to gather: zero irradiance
            vpls = VplTextures.from_arrays(ctx, vpls)
            self._owned.extend([vpls.position, vpls.normal, vpls.flux])
        self._vpls = vpls

        def texture(array: np.ndarray, size: tuple[int, int]):
            tex = ctx.texture(size, 4, np.ascontiguousarray(array, np.float32).tobytes(),
                              dtype="f4")
            tex.filter = (moderngl.NEAREST, moderngl.NEAREST)
            self._owned.append(tex)
            return tex

        valid = np.asarray(gbuffer.valid, bool)[..., None].astype(np.float32)
        self._position = texture(np.concatenate([gbuffer.position, valid], axis=-1),
                                 (width, height))
        self._normal = texture(np.concatenate([gbuffer.normal, valid], axis=-1),
                               (width, height))
        # w starts at 1 and drops to 0 where a dispatch did not finish its chunk
        cleared = np.zeros((height, width, 4))
        cleared[..., 3] = 1.0
        self._result = texture(cleared, (width, height))
        if bvh is not None and bvh.triangle_count:
            corners = np.concatenate(
                [bvh.triangles, np.zeros(bvh.triangles.shape[:2] + (1,))], axis=-1)
            self._tri_buffer = ctx.buffer(np.ascontiguousarray(corners, np.float32).tobytes())
            self._node_buffer = ctx.buffer(bvh.nodes.tobytes())
            node_count = len(bvh.nodes)
        else:  # the shader never reads them, but the bindings must hold a buffer
            self._tri_buffer = ctx.buffer(reserve=64)
            self._node_buffer = ctx.buffer(reserve=64)
            node_count = 0
        self._owned.extend([self._tri_buffer, self._node_buffer])
        vpl_width, vpl_height = vpls.size
        self.vpl_count = vpl_width * vpl_height
        self._values = {
            "u_image_size": (width, height),
            "u_min_distance_sq": min_distance * min_distance,
            "u_visibility": int(bool(visibility)),
            "u_ray_offset": float(ray_offset),
            "u_node_count": node_count,
        }
        self.tiles = [(x, y) for y in range(0, height, tile_size)
                      for x in range(0, width, tile_size)]
        if reference.loop_limited:
            self.vpl_chunk = safe_vpl_chunk(vpl_chunk, bvh)
        self.chunks = list(range(0, self.vpl_count, self.vpl_chunk))
        self.total = len(self.tiles) * len(self.chunks)
        self._groups = -(-tile_size // _LOCAL_SIZE)

    @property
    def finished(self) -> bool:
        return self.done >= self.total

    def _bind(self) -> None:
        program = self.program
        for unit, (name, tex) in enumerate((
                ("u_gbuffer_position", self._position), ("u_gbuffer_normal", self._normal),
                ("u_vpl_position", self._vpls.position), ("u_vpl_normal", self._vpls.normal),
                ("u_vpl_flux", self._vpls.flux))):
            tex.use(location=unit)
            if name in program:
                program[name] = unit
        self._result.bind_to_image(0, read=True, write=True)
        self._tri_buffer.bind_to_storage_buffer(0)
        self._node_buffer.bind_to_storage_buffer(1)
        for key, value in self._values.items():
            if key in program:
                program[key] = value

    def step(self, dispatches: int = 1) -> int:
        """Run up to ``dispatches`` more dispatches; returns how many ran."""
        count = min(int(dispatches), self.total - self.done)
        if count <= 0:
            return 0
        self._bind()
        for _ in range(count):
            self._dispatch()
        return count

    def advance(self, budget_s: float) -> int:
        """Run dispatches for about ``budget_s`` seconds (at least one while any is left);
        returns how many ran. The context finishes them every
        :data:`DISPATCHES_PER_FINISH` and before returning, so the clock measures work
        done, not queued (llvmpipe runs a dispatch when it is issued)."""
        if self.finished:
            return 0
        start = time.perf_counter()
        self._bind()
        ran = 0
        while not self.finished and (ran == 0 or time.perf_counter() - start < budget_s):
            self._dispatch()
            ran += 1
            if ran % DISPATCHES_PER_FINISH == 0:
                self.ctx.finish()
        self.ctx.finish()
        return ran

    def _dispatch(self) -> None:
        program = self.program
        tile, chunk = divmod(self.done, len(self.chunks))
        if "u_tile_origin" in program:
            program["u_tile_origin"] = self.tiles[tile]
        begin = self.chunks[chunk]
        program["u_vpl_begin"] = begin
        program["u_vpl_end"] = min(begin + self.vpl_chunk, self.vpl_count)
        program.run(self._groups, self._groups, 1)
        self.done += 1

    def irradiance(self) -> np.ndarray:
        """(H, W, 3) float32 irradiance of the finished gather; raises
        :class:`IncompleteRender` where the driver cut a dispatch short."""
        if not self.finished:
            raise RuntimeError(f"the gather is not finished: {self.done} of {self.total} "
                               "dispatches ran")
        width, height = self.size
        if self._result is None:
            return np.zeros((height, width, 3), np.float32)
        self.ctx.memory_barrier()
        data = np.frombuffer(self._result.read(), dtype=np.float32).reshape(height, width, 4)
        cut = int(np.count_nonzero(data[..., 3] < 0.5))
        if cut:
            raise IncompleteRender(
                f"the GL driver ended the VPL loop early at {cut} pixels (llvmpipe's "
                f"loop limit); pass a smaller vpl_chunk (was {self.vpl_chunk})")
        return data[..., :3].copy()

    def release(self) -> None:
        for obj in self._owned:
            obj.release()
        self._owned = []


def reference_irradiance(gbuffer: GBuffer, vpls: VplArrays | VplTextures, min_distance: float,
                         triangles: np.ndarray | Bvh | None = None, visibility: bool = False,
                         ctx=None, **options) -> np.ndarray:
    """Irradiance (H, W, 3) of the VPLs at every G-buffer pixel, on the GPU.

    ``ctx`` None opens a headless context for this call. ``options`` go to
    :meth:`ReferencePass.run` (``ray_offset``, ``tile_size``, ``vpl_chunk``, ``progress``).
    """
    from explorer.gl.context import given_or_headless

    with given_or_headless(ctx) as ctx:
        reference = ReferencePass(ctx)
        try:
            return reference.run(gbuffer, vpls, min_distance, triangles, visibility, **options)
        finally:
            reference.release()


def outgoing_radiance(gbuffer: GBuffer, irradiance: np.ndarray) -> np.ndarray:
    """Diffuse outgoing radiance ``a/π · E`` (zero where the G-buffer has no surface)."""
    valid = np.asarray(gbuffer.valid, bool)[..., None]
    return np.where(valid, np.asarray(gbuffer.albedo) / np.pi * irradiance, 0.0).astype(
        np.float32)


# --- numpy twin (tests and small cases) ------------------------------------------------

def segments_blocked(starts: np.ndarray, ends: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Whether any triangle crosses the open segment ``starts[i] → ends[i]`` (brute force,
    Möller–Trumbore, both faces); (K,) bool."""
    starts = np.asarray(starts, np.float64)
    ends = np.asarray(ends, np.float64)
    tris = as_triangles(triangles)
    blocked = np.zeros(len(starts), bool)
    if len(tris) == 0 or len(starts) == 0:
        return blocked
    direction = ends - starts
    for a, b, c in tris:
        e1, e2 = b - a, c - a
        pv = np.cross(direction, e2)
        det = pv @ e1
        ok = np.abs(det) > 1e-12
        inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
        tv = starts - a
        u = np.einsum("ij,ij->i", tv, pv) * inv
        qv = np.cross(tv, e1)
        v = np.einsum("ij,ij->i", direction, qv) * inv
        t = (qv @ e2) * inv
        blocked |= ok & (u >= 0) & (u <= 1) & (v >= 0) & (u + v <= 1) & (t > 1e-6) & (
            t < 1 - 1e-6)
    return blocked


MAX_BRUTE_FORCE_TRIANGLES = 4096
"""Triangles :func:`point_reference_irradiance` tests every shadow ray against at most
(brute force: VPLs × triangles segment tests)."""


def point_reference_irradiance(point, normal, vpls: VplArrays, min_distance: float,
                               triangles: np.ndarray | None = None, visibility: bool = False,
                               ray_offset: float | None = None) -> np.ndarray:
    """(3,) the reference's irradiance at one surface point with unit ``normal``: the sum
    of :func:`numpy_reference_irradiance` for one pixel, over all VPLs at once (shadow
    rays by brute force, so ``visibility`` takes a scene of at most
    :data:`MAX_BRUTE_FORCE_TRIANGLES` triangles)."""
    min_distance = _check_min_distance(min_distance)
    if visibility and triangles is None:
        raise ValueError("visibility=True needs the scene triangles")
    if visibility and len(triangles) > MAX_BRUTE_FORCE_TRIANGLES:
        raise ValueError(f"the reference at one point tests shadow rays against every "
                         f"triangle: {len(triangles)} are more than "
                         f"{MAX_BRUTE_FORCE_TRIANGLES}")
    p = np.asarray(point, np.float64)
    n = np.asarray(normal, np.float64)
    n = n / np.linalg.norm(n)
    sources = np.asarray(vpls.positions, np.float64).reshape(-1, 3)
    source_normals = np.asarray(vpls.normals, np.float64).reshape(-1, 3)
    offset = p - sources
    dist_sq = np.einsum("ij,ij->i", offset, offset)
    w = offset / np.sqrt(np.where(dist_sq > 0, dist_sq, 1.0))[:, None]
    cos_source = np.clip(np.einsum("ij,ij->i", w, source_normals), 0.0, None)
    cos_receiver = np.clip(-(w @ n), 0.0, None)
    geometry = np.where(dist_sq > 0, cos_source * cos_receiver
                        / np.maximum(dist_sq, min_distance ** 2), 0.0)
    if visibility:
        if ray_offset is None:
            ray_offset = default_ray_offset(triangles, None) if len(triangles) else 0.0
        lit = np.flatnonzero(geometry > 0)
        blocked = segments_blocked(sources[lit] + ray_offset * source_normals[lit],
                                   np.broadcast_to(p + ray_offset * n, (len(lit), 3)),
                                   triangles)
        geometry[lit[blocked]] = 0.0
    return geometry @ np.asarray(vpls.flux, np.float64).reshape(-1, 3) / np.pi


def numpy_reference_irradiance(gbuffer: GBuffer, vpls: VplArrays, min_distance: float,
                               triangles: np.ndarray | None = None, visibility: bool = False,
                               ray_offset: float | None = None) -> np.ndarray:
    """The same sum as :class:`ReferencePass` in float64 numpy, one VPL at a time.

    Meant for tests and tiny inputs: the cost is pixels × VPLs (× triangles with
    visibility)."""
    min_distance = _check_min_distance(min_distance)
    if visibility and triangles is None:
        raise ValueError("visibility=True needs the scene triangles")
    if ray_offset is None:
        ray_offset = default_ray_offset(triangles if visibility else None, gbuffer)
    valid = np.asarray(gbuffer.valid, bool)
    p = np.asarray(gbuffer.position, np.float64)[valid]
    n = np.asarray(gbuffer.normal, np.float64)[valid]
    n = n / np.linalg.norm(n, axis=1, keepdims=True)
    irradiance = np.zeros((len(p), 3))
    for x_j, n_j, flux in zip(np.asarray(vpls.positions, np.float64),
                              np.asarray(vpls.normals, np.float64),
                              np.asarray(vpls.flux, np.float64)):
        offset = p - x_j
        dist_sq = np.einsum("ij,ij->i", offset, offset)
        safe = np.where(dist_sq > 0, dist_sq, 1.0)
        w = offset / np.sqrt(safe)[:, None]
        cos_source = np.clip(w @ n_j, 0.0, None)
        cos_receiver = np.clip(-np.einsum("ij,ij->i", w, n), 0.0, None)
        geometry = np.where(dist_sq > 0, cos_source * cos_receiver
                            / np.maximum(dist_sq, min_distance ** 2), 0.0)
        if visibility:
            lit = geometry > 0
            blocked = segments_blocked(np.broadcast_to(x_j + ray_offset * n_j, p[lit].shape),
                                       p[lit] + ray_offset * n[lit], triangles)
            geometry[np.flatnonzero(lit)[blocked]] = 0.0
        irradiance += geometry[:, None] * flux[None, :] / np.pi
    out = np.zeros(valid.shape + (3,))
    out[valid] = irradiance
    return out
