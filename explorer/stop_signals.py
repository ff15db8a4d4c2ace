"""SIGTERM and SIGHUP handled as SIGINT is: a command unwinds (its outputs put back,
explorer/commands/options.py ``Outputs``) and the window quits as its Quit item does
(settings and layout saved). A second signal while the first is being handled ends the
process at once, by that signal.

Python ends a process on SIGTERM and SIGHUP without running a ``finally`` or a context
manager's exit, so a command stopped that way left its half-written outputs and
temporaries behind. :func:`raising` makes them an exception (:class:`Stopped`);
:func:`calling` hands them to a window's quit; :func:`held` keeps all three signals
waiting while a short sequence (renaming a command's outputs into place) must finish.
"""

from __future__ import annotations

import contextlib
import os
import signal
import threading
from collections.abc import Callable, Iterator

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
"""The signals a user sends to stop the explorer: Ctrl-C, ``kill``, a closed terminal."""


class Stopped(BaseException):
    """SIGTERM or SIGHUP arrived; unwinding as for Ctrl-C (a ``BaseException``, so no
    ``except Exception`` swallows it). The exit status is 128 + the signal's number."""

    def __init__(self, signum: int) -> None:
        super().__init__(f"stopped by {signal.Signals(signum).name}")
        self.signum = signum

    @property
    def exit_code(self) -> int:
        return 128 + self.signum


def _at_once(signum: int) -> None:
    """End the process now, by ``signum`` itself (its default action), as if unhandled."""
    signal.signal(signum, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signum})
    os.kill(os.getpid(), signum)


def _installable() -> bool:
    return threading.current_thread() is threading.main_thread()


@contextlib.contextmanager
def raising() -> Iterator[None]:
    """Within the block SIGTERM and SIGHUP raise :class:`Stopped` (SIGINT keeps raising
    ``KeyboardInterrupt``); a second stop signal while unwinding ends the process."""
    if not _installable():
        yield
        return
    stopping = []

    def handler(signum, frame):
        if stopping:
            _at_once(signum)
        stopping.append(signum)
        if signum == signal.SIGINT:
            raise KeyboardInterrupt
        raise Stopped(signum)

    previous = {signum: signal.signal(signum, handler) for signum in STOP_SIGNALS}
    try:
        yield
    finally:
        for signum, old in previous.items():
            signal.signal(signum, old)


def calling(quit_now: Callable[[int], None]) -> Callable[[], None]:
    """Route SIGTERM and SIGHUP to ``quit_now(signum)`` (the window's quit: it sets a flag
    the frame loop reads; a handler must not draw or save itself); a second one ends the
    process at once. Returns a function that puts the previous handlers back."""
    if not _installable():
        return lambda: None
    received = []

    def handler(signum, frame):
        if received:
            _at_once(signum)
        received.append(signum)
        quit_now(signum)

    previous = {signum: signal.signal(signum, handler)
                for signum in (signal.SIGTERM, signal.SIGHUP)}

    def restore() -> None:
        for signum, old in previous.items():
            signal.signal(signum, old)

    return restore


@contextlib.contextmanager
def held() -> Iterator[None]:
    """The stop signals wait until the block ends, then arrive (the first one, to the
    handlers in place before): a sequence of renames finishes whole or, failing, rolls
    back before any handler runs. Deferred by Python-level handlers rather than blocked
    with ``pthread_sigmask``: a signal sent to the process may be taken by another
    thread (numpy's, a progress thread), which a mask of this thread would not stop."""
    if not _installable():
        yield
        return
    pending: list[int] = []

    def defer(signum, frame):
        pending.append(signum)

    previous = {signum: signal.signal(signum, defer) for signum in STOP_SIGNALS}
    try:
        yield
    finally:
        for signum, old in previous.items():
            signal.signal(signum, old)
        if pending:
            signal.raise_signal(pending[0])
