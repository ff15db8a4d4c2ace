"""Shared fixtures. :func:`gl_context` is the only place tests create a GL context.

The whole suite (``python -m pytest`` with no paths: the README's test command) runs on
the machine's cores with pytest-xdist when it is installed (the ``test`` extra), a
module's tests together in one worker (its module fixtures, e.g. the site build or the
wheel's venv, made once) and each click session of tests/ui/test_click_window.py on its
own and first (they are the longest tests: started first and spread, they overlap the
rest). Paths on the command line, ``-n``/``--dist``, ``--pdb`` or ``-p no:xdist`` keep
it in one process (or to what was asked)."""

from __future__ import annotations

import signal

import pytest

from explorer.gl.context import create_headless_context, release_headless_context
from explorer.gl.program import ProgramCache

MAX_WORKERS = 4
"""Workers at most: each starts its own Xvfb and imports the whole package, and llvmpipe
renders on every core anyway, so more than a few pay no more."""
SPLIT_MODULES = ("tests/ui/test_click_window.py",)
"""Modules whose tests go to the workers one by one rather than as one unit, and first:
the longest tests, so that the rest of the suite fills the time they take."""
_SPREAD = pytest.StashKey[bool]()


# before xdist's own (tryfirst too, and registered after it): it turns -n into workers
@pytest.hookimpl(tryfirst=True)
def pytest_cmdline_main(config: pytest.Config) -> None:
    """Spread the whole suite over the cores (module docstring) unless the command line
    already decided how to run it (or asked for output as it comes, ``-s``)."""
    option = config.option
    whole_suite = getattr(config, "args_source", None) == pytest.Config.ArgsSource.TESTPATHS
    if (not config.pluginmanager.hasplugin("xdist") or hasattr(config, "workerinput")
            or not whole_suite or option.numprocesses is not None or option.dist != "no"
            or option.tx or option.looponfail or option.usepdb or option.collectonly
            or option.capture == "no"):
        return
    # the cores as xdist counts them (PYTEST_XDIST_AUTO_NUM_WORKERS overrides)
    workers = min(config.hook.pytest_xdist_auto_num_workers(config=config), MAX_WORKERS)
    if workers < 2:
        return
    option.numprocesses = workers
    option.dist = "loadscope"
    # units in the order of the collection (xdist would sort them by their number of
    # tests, which puts the one-test click sessions, the longest, last)
    option.loadscopereorder = False
    config.stash[_SPREAD] = True


def pytest_collection_modifyitems(config: pytest.Config, items: list) -> None:
    """While the suite is spread, :data:`SPLIT_MODULES` go first: the folders collect
    tests/ui/ last, and the longest tests handed out last would end the run alone. Every
    worker collects and so reorders alike, as xdist requires."""
    if not config.stash.get(_SPREAD, False) and not hasattr(config, "workerinput"):
        return
    first = [item for item in items if item.nodeid.split("::", 1)[0] in SPLIT_MODULES]
    if first:
        rest = [item for item in items if item.nodeid.split("::", 1)[0] not in SPLIT_MODULES]
        items[:] = first + rest


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config: pytest.Config, log):
    """Modules as units of work, except :data:`SPLIT_MODULES` (one unit a test)."""
    if not config.stash.get(_SPREAD, False):
        return None
    from xdist.scheduler import LoadScopeScheduling

    class ModuleScheduling(LoadScopeScheduling):
        def _split_scope(self, nodeid: str) -> str:
            module = nodeid.split("::", 1)[0]
            return nodeid if module in SPLIT_MODULES else module

    return ModuleScheduling(config, log)


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


@pytest.fixture
def no_hang():
    """Fail (rather than wait forever) when the code under test blocks for 20 s (a reader
    waiting on a FIFO, a handler that never returns)."""
    def alarm(signum, frame):
        raise TimeoutError("blocked: the code waited on a file or a signal that never came")

    previous = signal.signal(signal.SIGALRM, alarm)
    signal.alarm(20)
    yield
    signal.alarm(0)
    signal.signal(signal.SIGALRM, previous)
