"""A glfw window with an OpenGL 4.3 core context wrapped by moderngl.

The window asks for GL 4.3 core (compute shaders). A driver that cannot give one still gets
a window when possible (GL 3.3 core), so the app can show *why* it cannot run instead of
crashing: :attr:`Window.gl_problem` then holds the message and :attr:`Window.ctx` is a
plain moderngl context good enough to draw the message.

``imgui_bundle`` must be imported before ``glfw``: it points pyglfw at the GLFW library it
bundles (the one its native imgui backend links against).
"""

from __future__ import annotations

import ctypes
import sys
import time
from collections import deque
from pathlib import Path

# isort: off
import imgui_bundle  # noqa: F401  (must precede `import glfw`, see the module docstring)
import glfw
# isort: on
import moderngl

from explorer.gl.context import GLUnavailableError, wrap_current_context
from explorer.gl.egl import release_current_egl, restore_egl


class WindowError(RuntimeError):
    """glfw could not start or no window could be opened (no display, no GL)."""


_GL_REQUESTS = ((4, 3), (3, 3))
_HEADLESS_SPARE: list = []
"""The (handle, moderngl context, GL problem) of a closed headless window, reused by the
next one (see :meth:`Window.close`)."""


class Window:
    """One glfw window, its GL context and the events the app needs besides imgui's.

    ``visible=False`` opens a hidden window (tests, scripted screenshots); rendering to
    its default framebuffer still works.
    """

    def __init__(self, width: int = 1600, height: int = 960, title: str = "lpv-explorer",
                 visible: bool = True, vsync: bool = True,
                 position: tuple[int, int] | None = None, headless: bool = False) -> None:
        """``position``: the window's top-left corner on the desktop (default: where the
        window manager puts it). ``headless``: no display at all: glfw's null platform
        with an EGL context (Mesa's surfaceless EGL); the window is never shown, draws
        into its default framebuffer and reads it back as a hidden one does (exports)."""
        glfw.set_error_callback(_print_glfw_error)
        # A headless EGL context current on this thread (tests, notebooks) makes Mesa's
        # glXMakeCurrent fail with BadAccess, and Xlib then exits the process: set it
        # aside while the window lives and make it current again in close().
        self._saved_egl = release_current_egl()
        self.headless = bool(headless)
        if not self.headless and _HEADLESS_SPARE:
            _drop_headless_spare()            # glfw is on its null platform: start over
        if not _init_glfw(headless=self.headless):
            restore_egl(self._saved_egl)
            raise WindowError(
                "glfw could not start headless (its null platform)" if self.headless else
                "glfw could not start: is there a display? (set DISPLAY, or run under "
                "xvfb-run for a virtual one)")
        self.handle = None
        self.gl_problem: str | None = None
        spare = _HEADLESS_SPARE.pop() if self.headless and _HEADLESS_SPARE else None
        for major, minor in _GL_REQUESTS if spare is None else ():
            glfw.default_window_hints()
            glfw.window_hint(glfw.CONTEXT_VERSION_MAJOR, major)
            glfw.window_hint(glfw.CONTEXT_VERSION_MINOR, minor)
            glfw.window_hint(glfw.OPENGL_PROFILE, glfw.OPENGL_CORE_PROFILE)
            glfw.window_hint(glfw.OPENGL_FORWARD_COMPAT, True)
            glfw.window_hint(glfw.VISIBLE, bool(visible) and not self.headless)
            if self.headless:
                glfw.window_hint(glfw.CONTEXT_CREATION_API, glfw.EGL_CONTEXT_API)
            glfw.window_hint(glfw.SCALE_TO_MONITOR, True)
            glfw.window_hint(glfw.RESIZABLE, True)
            # only imgui draws into the window (the view and its overlays have framebuffers
            # of their own): a depth and stencil buffer would be cleared and swapped every
            # frame for nothing, 3 ms of CPU a frame at 1600×960 on llvmpipe
            # (scripts/window_clear_swap.py, BENCHMARKS.md)
            glfw.window_hint(glfw.DEPTH_BITS, 0)
            glfw.window_hint(glfw.STENCIL_BITS, 0)
            if position is not None and hasattr(glfw, "POSITION_X"):    # glfw 3.4
                glfw.window_hint(glfw.POSITION_X, int(position[0]))
                glfw.window_hint(glfw.POSITION_Y, int(position[1]))
            self.handle = glfw.create_window(int(width), int(height), title, None, None)
            if self.handle:
                break
        if spare is not None:
            self.handle, self.ctx, self.gl_problem = spare
            glfw.set_window_size(self.handle, int(width), int(height))
        if not self.handle:
            glfw.terminate()
            restore_egl(self._saved_egl)
            raise WindowError("glfw could not open a window with an OpenGL 3.3+ core context")
        glfw.make_context_current(self.handle)
        glfw.swap_interval(1 if vsync else 0)
        if spare is None:
            try:
                self.ctx = wrap_current_context()
            except GLUnavailableError as exc:
                # Keep a context that can at least draw the explanation.
                self.gl_problem = str(exc)
                self.ctx = moderngl.create_context()
        self.dropped_paths: deque[Path] = deque()
        self.events = 0
        """Input and window events since :meth:`take_events` (an idle app waits for one)."""
        glfw.set_drop_callback(self.handle, self._on_drop)
        # Installed before imgui's backend, which chains to them: every event is counted.
        for install in (glfw.set_cursor_pos_callback, glfw.set_mouse_button_callback,
                        glfw.set_scroll_callback, glfw.set_key_callback,
                        glfw.set_char_callback, glfw.set_window_size_callback,
                        glfw.set_framebuffer_size_callback, glfw.set_window_focus_callback,
                        glfw.set_window_refresh_callback, glfw.set_cursor_enter_callback,
                        glfw.set_window_iconify_callback, glfw.set_window_content_scale_callback):
            install(self.handle, self._on_event)

    # -- events -------------------------------------------------------------------------
    def _on_drop(self, _window, paths) -> None:
        self.dropped_paths.extend(Path(p) for p in paths)
        self.events += 1

    def _on_event(self, *_args) -> None:
        self.events += 1

    def take_events(self) -> int:
        """How many events arrived since the last call."""
        count, self.events = self.events, 0
        return count

    @property
    def address(self) -> int:
        """The GLFWwindow* as an integer, what imgui's native glfw backend takes."""
        return int(ctypes.cast(self.handle, ctypes.c_void_p).value)

    def should_close(self) -> bool:
        return bool(glfw.window_should_close(self.handle))

    def request_close(self) -> None:
        glfw.set_window_should_close(self.handle, True)

    @staticmethod
    def poll_events(timeout: float | None = None) -> None:
        """Process pending events; with ``timeout``, sleep until one arrives or it expires
        (an idle or minimised app does not spin)."""
        if timeout is None:
            glfw.poll_events()
        else:
            glfw.wait_events_timeout(timeout)

    def swap_buffers(self) -> None:
        glfw.swap_buffers(self.handle)

    # -- geometry -----------------------------------------------------------------------
    @property
    def framebuffer_size(self) -> tuple[int, int]:
        width, height = glfw.get_framebuffer_size(self.handle)
        return int(width), int(height)

    @property
    def size(self) -> tuple[int, int]:
        width, height = glfw.get_window_size(self.handle)
        return int(width), int(height)

    def set_size(self, width: int, height: int) -> None:
        glfw.set_window_size(self.handle, int(width), int(height))

    @property
    def content_scale(self) -> float:
        """The monitor's content scale (1.0 at 96 dpi, 2.0 on a typical 'retina' screen)."""
        sx, sy = glfw.get_window_content_scale(self.handle)
        return float(max(sx, sy, 1.0))

    @property
    def minimised(self) -> bool:
        width, height = self.framebuffer_size
        return width == 0 or height == 0 or bool(glfw.get_window_attrib(self.handle,
                                                                        glfw.ICONIFIED))

    def set_title(self, title: str) -> None:
        glfw.set_window_title(self.handle, title)

    # -- pixels -------------------------------------------------------------------------
    def read_pixels(self) -> numpy.ndarray:  # noqa: F821 (numpy imported lazily)
        """The back buffer as (H, W, 3) uint8, top row first.

        Reading the default framebuffer through moderngl's ``screen.read`` raises
        GL_INVALID_OPERATION on Mesa (it selects a colour attachment the default
        framebuffer lacks), so the back buffer is blitted into our own framebuffer first.
        """
        import numpy as np

        width, height = self.framebuffer_size
        target = self.ctx.simple_framebuffer((width, height), components=4)
        try:
            self.ctx.copy_framebuffer(target, self.ctx.screen)
            data = target.read(components=3, alignment=1)
        finally:
            target.release()
            self.ctx.screen.use()
        pixels = np.frombuffer(data, dtype=np.uint8).reshape(height, width, 3)
        return pixels[::-1].copy()

    def close(self) -> None:
        if self.handle is not None and self.headless:
            # kept for the next headless window of this process: moderngl finds a
            # second EGL context made current by glfw no more (through GLX)
            glfw.make_context_current(None)
            _HEADLESS_SPARE.append((self.handle, self.ctx, self.gl_problem))
            self.handle = None
        if self.handle is not None:
            glfw.destroy_window(self.handle)
            self.handle = None
        if not self.headless:
            glfw.terminate()
        restore_egl(self._saved_egl)
        self._saved_egl = None


def work_area() -> tuple[int, int, int, int] | None:
    """(x, y, width, height) of the primary monitor's work area (the desktop less its
    panels and task bars), in screen coordinates; None without a display or monitor."""
    glfw.set_error_callback(_print_glfw_error)
    if not _init_glfw():
        return None
    monitor = glfw.get_primary_monitor()
    if not monitor:
        return None
    x, y, width, height = glfw.get_monitor_workarea(monitor)
    return (int(x), int(y), int(width), int(height)) if width > 0 and height > 0 else None


def _drop_headless_spare() -> None:
    while _HEADLESS_SPARE:
        handle, ctx, _ = _HEADLESS_SPARE.pop()
        ctx.release()
        glfw.destroy_window(handle)
    glfw.terminate()


def headless_available() -> bool:
    """Whether this glfw has the null platform (glfw 3.4) that :class:`Window` needs for
    ``headless``."""
    return hasattr(glfw, "PLATFORM_NULL")


def _init_glfw(attempts: int = 3, headless: bool = False) -> bool:
    """``glfw.init()``, retried briefly: a busy X server (e.g. Xvfb on a loaded CI machine)
    occasionally refuses one connection. ``headless``: on glfw's null platform (no
    display); the hint is set either way, as it outlives a ``glfw.terminate()``."""
    if headless_available():
        glfw.init_hint(glfw.PLATFORM, glfw.PLATFORM_NULL if headless else glfw.ANY_PLATFORM)
    elif headless:
        return False
    for attempt in range(attempts):
        if glfw.init():
            return True
        time.sleep(0.2 * (attempt + 1))
    return False


def _print_glfw_error(code: int, description) -> None:
    if isinstance(description, bytes):
        description = description.decode(errors="replace")
    print(f"lpv-explorer: glfw error {code}: {description}", file=sys.stderr)
