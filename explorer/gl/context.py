"""The one place where GL contexts are created, and the capability probe.

The LPV needs OpenGL 4.3 core (compute shaders, image load/store). Everything that
opens a context goes through :func:`create_headless_context` (EGL, no display) or
:func:`wrap_current_context` (a window that already made its context current).
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass

import moderngl

from explorer.gl.egl import EglState, current_egl, restore_egl

REQUIRED_GL = 430


class GLUnavailableError(RuntimeError):
    """No usable GL context: the message says what is missing and how to get it."""


_APT_HINT = (
    "On Debian/Ubuntu: sudo apt-get install -y libegl1 libegl-mesa0 libgl1-mesa-dri "
    "(Mesa's llvmpipe gives GL 4.5 in software)."
)


def create_headless_context(require: int = REQUIRED_GL, check: bool = True) -> moderngl.Context:
    """A standalone context through EGL: works with no display and no GPU (llvmpipe).

    ``check=False`` skips :func:`check_capabilities` (``lpv-explorer doctor`` reports
    what a too-old driver offers instead of failing on it)."""
    previous = current_egl()
    try:
        ctx = moderngl.create_standalone_context(backend="egl", require=require)
    except Exception as exc:  # moderngl raises plain Exception for a missing EGL/GL
        raise GLUnavailableError(
            f"could not open a headless OpenGL {require // 100}.{require % 100 // 10} core "
            f"context through EGL: {exc}. {_APT_HINT}"
        ) from exc
    _CURRENT_BEFORE[id(ctx)] = previous
    if check:
        try:
            check_capabilities(ctx)
        except GLUnavailableError:
            release_headless_context(ctx)
            raise
    return ctx


# What was current before each headless context was made (by id of the context).
_CURRENT_BEFORE: dict[int, EglState | None] = {}


def release_headless_context(ctx: moderngl.Context) -> None:
    """Release a context made by :func:`create_headless_context` and make current again
    whatever EGL context was current before it was made: a command or ``Pipeline`` run
    inside a test session or a notebook must not leave the caller without a context."""
    previous = _CURRENT_BEFORE.pop(id(ctx), None)
    ctx.release()
    restore_egl(previous)


@contextmanager
def given_or_headless(ctx: moderngl.Context | None) -> Iterator[moderngl.Context]:
    """``ctx`` itself, or for None a headless context that is released when the ``with``
    block ends (for functions that take an optional context)."""
    if ctx is not None:
        yield ctx
        return
    ctx = create_headless_context()
    try:
        yield ctx
    finally:
        release_headless_context(ctx)


def wrap_current_context(require: int = REQUIRED_GL) -> moderngl.Context:
    """Wrap the context a window toolkit (glfw) made current on this thread."""
    ctx = moderngl.create_context(require=require)
    check_capabilities(ctx)
    return ctx


@dataclass(frozen=True)
class Capabilities:
    vendor: str
    renderer: str
    version: str
    version_code: int
    compute_shaders: bool
    max_3d_texture_size: int
    max_draw_buffers: int
    max_compute_work_group_invocations: int

    @property
    def missing(self) -> list[str]:
        """What the LPV needs and this context lacks, in words."""
        gaps = []
        if self.version_code < REQUIRED_GL:
            gaps.append(f"OpenGL 4.3 core (this driver offers {self.version})")
        if not self.compute_shaders:
            gaps.append("compute shaders (GL_ARB_compute_shader)")
        if self.max_draw_buffers < 3:
            gaps.append(f"3 draw buffers (this driver offers {self.max_draw_buffers})")
        return gaps


def probe(ctx: moderngl.Context) -> Capabilities:
    info = ctx.info
    compute = ctx.version_code >= 430 or "GL_ARB_compute_shader" in ctx.extensions
    return Capabilities(
        vendor=str(info.get("GL_VENDOR", "?")),
        renderer=str(info.get("GL_RENDERER", "?")),
        version=str(info.get("GL_VERSION", "?")),
        version_code=int(ctx.version_code),
        compute_shaders=bool(compute),
        max_3d_texture_size=int(info.get("GL_MAX_3D_TEXTURE_SIZE", 0)),
        max_draw_buffers=int(info.get("GL_MAX_DRAW_BUFFERS", 0)),
        max_compute_work_group_invocations=int(
            info.get("GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS", 0)),
    )


def check_capabilities(ctx: moderngl.Context) -> Capabilities:
    caps = probe(ctx)
    if caps.missing:
        raise GLUnavailableError(
            f"the GL driver ({caps.renderer}, {caps.version}) lacks what the LPV needs: "
            + "; ".join(caps.missing) + f". {_APT_HINT}"
        )
    return caps


def use_screen(ctx: moderngl.Context) -> None:
    """Bind the window's framebuffer again after offscreen work (a headless context has
    none)."""
    if ctx.screen is not None:
        ctx.screen.use()
