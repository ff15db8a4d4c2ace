"""Shared fixtures. :func:`gl_context` is the only place tests create a GL context.

The whole suite (``python -m pytest`` with no paths: the README's test command) runs on
the machine's cores with pytest-xdist when it is installed (the ``test`` extra), a
module's tests together in one worker (its module fixtures, e.g. the site build or the
wheel's venv, made once) and each click session of tests/ui/test_click_window.py on its
own; the longest units (:data:`LONGEST`) go out first, longest first, so that the rest
of the suite fills the time they take. Paths on the command line, ``-n``/``--dist``,
``--pdb`` or ``-p no:xdist`` keep it in one process (or to what was asked)."""

from __future__ import annotations

import signal

import pytest

from explorer.gl.context import create_headless_context, release_headless_context
from explorer.gl.program import ProgramCache

MAX_WORKERS = 4
"""Workers at most: each starts its own Xvfb and imports the whole package, and llvmpipe
renders on every core anyway, so more than a few pay no more."""
SPLIT_MODULES = ("tests/ui/test_click_window.py",)
"""Modules whose tests go to the workers one by one rather than as one unit."""
LONGEST = (
    "tests/ui/test_click_window.py::test_click_session[try-this]",
    "tests/lessons/test_lesson_checks.py",
    "tests/ui/test_click_window.py::test_click_session[lessons]",
    "tests/ui/test_click_window.py::test_click_session[figures]",
    "tests/lessons/test_window_words.py",
    "tests/test_wheel_install.py",
    "tests/ui/test_click_window.py::test_click_session[window]",
    "tests/commands/test_bench.py",
    "tests/site/test_site.py",
    "tests/ui/test_click_window.py::test_click_session[return]",
)
"""The units of work (a module, or a test of :data:`SPLIT_MODULES`) that take longest,
longest first (BENCHMARKS.md "The suite in minutes"): handed out first, in this order.
A worker is given its next unit while it runs the last test of the one before (xdist's
workers look one test ahead), so the first four pair up (1 and 3, 2 and 4) and the
longest two never share a worker; handed out last, a long one would end the run alone."""
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


def _unit(nodeid: str) -> str:
    """The unit of work a test belongs to: its module, or itself in :data:`SPLIT_MODULES`."""
    module = nodeid.split("::", 1)[0]
    return nodeid if module in SPLIT_MODULES else module


def pytest_collection_modifyitems(config: pytest.Config, items: list) -> None:
    """While the suite is spread, the :data:`LONGEST` units go first, in its order (the
    folders collect tests/ui/ last); the rest keep the collection's order. Every worker
    collects and so reorders alike, as xdist requires."""
    if not config.stash.get(_SPREAD, False) and not hasattr(config, "workerinput"):
        return
    rank = {unit: index for index, unit in enumerate(LONGEST)}
    # sorted() is stable: a unit's tests keep their order, as do the units not ranked
    items[:] = sorted(items, key=lambda item: rank.get(_unit(item.nodeid), len(rank)))


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config: pytest.Config, log):
    """Modules as units of work, except :data:`SPLIT_MODULES` (one unit a test)."""
    if not config.stash.get(_SPREAD, False):
        return None
    from xdist.scheduler import LoadScopeScheduling

    class ModuleScheduling(LoadScopeScheduling):
        def _split_scope(self, nodeid: str) -> str:
            return _unit(nodeid)

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
