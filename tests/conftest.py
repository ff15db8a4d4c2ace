"""Shared fixtures. :func:`gl_context` is the only place tests create a GL context."""

from __future__ import annotations

import pytest

from explorer.gl.context import create_headless_context, release_headless_context
from explorer.gl.program import ProgramCache


@pytest.fixture(scope="session")
def gl_context():
    """One headless EGL context (Mesa llvmpipe in CI) for the whole session."""
    ctx = create_headless_context()
    yield ctx
    release_headless_context(ctx)


@pytest.fixture
def ctx(gl_context):
    """The session context, made current (a test that created and released a context of
    its own, e.g. a CLI command, leaves none current: GL calls would then fail silently)
    and checked for GL errors before and after each test."""
    gl_context.__enter__()
    assert gl_context.error == "GL_NO_ERROR"
    yield gl_context
    assert gl_context.error == "GL_NO_ERROR"


@pytest.fixture(scope="module")
def programs(gl_context):
    """A program cache on the session context, shared by the tests of one module."""
    cache = ProgramCache(gl_context)
    yield cache
    cache.release()
