"""Which EGL context is current on this thread: save it, set it aside, restore it.

Two situations need this. A headless context made and released by a command or a
``Pipeline`` inside a test session or notebook leaves *no* context current, so the
caller's own context would silently stop working; and Mesa refuses a GLX window beside a
current EGL context. Both save what was current and restore it afterwards.
"""

from __future__ import annotations

import ctypes
from functools import lru_cache

_EGL_DRAW, _EGL_READ = 0x3059, 0x305A

EglState = tuple  # (display, draw surface, read surface, context) as raw pointers


@lru_cache(maxsize=1)
def _libegl():
    try:
        lib = ctypes.CDLL("libEGL.so.1")
    except OSError:
        return None
    for name in ("eglGetCurrentContext", "eglGetCurrentDisplay"):
        getattr(lib, name).restype = ctypes.c_void_p
        getattr(lib, name).argtypes = []
    lib.eglGetCurrentSurface.restype = ctypes.c_void_p
    lib.eglGetCurrentSurface.argtypes = [ctypes.c_int32]
    lib.eglMakeCurrent.restype = ctypes.c_uint32
    lib.eglMakeCurrent.argtypes = [ctypes.c_void_p] * 4
    return lib


def current_egl() -> EglState | None:
    """What is current on this thread, or None (no EGL, or nothing current)."""
    lib = _libegl()
    if lib is None or not lib.eglGetCurrentContext():
        return None
    return (lib.eglGetCurrentDisplay(), lib.eglGetCurrentSurface(_EGL_DRAW),
            lib.eglGetCurrentSurface(_EGL_READ), lib.eglGetCurrentContext())


def release_current_egl() -> EglState | None:
    """Make no EGL context current; return what was current (for :func:`restore_egl`)."""
    saved = current_egl()
    if saved is not None:
        _libegl().eglMakeCurrent(saved[0], None, None, None)
    return saved


def restore_egl(saved: EglState | None) -> None:
    """Make ``saved`` current again (nothing happens for None)."""
    if saved is not None:
        _libegl().eglMakeCurrent(*saved)
