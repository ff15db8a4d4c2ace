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
    process at once. Returns a function that puts the previous handlers back.

    Python runs a handler only when the main thread is back in the interpreter: two
    ``kill`` sent while it draws a frame are one call of the handler. Each signal also
    writes its number to a wakeup pipe from C (``signal.set_wakeup_fd``), so the handler
    counts what really arrived; and once quitting, both signals are back to their default
    action, so a second one ends the process even while the main thread is stuck in C."""
    if not _installable():
        return lambda: None
    received = []
    stops = (signal.SIGTERM, signal.SIGHUP)
    read_end, write_end = os.pipe()
    for end in (read_end, write_end):
        os.set_blocking(end, False)
    try:
        previous_wakeup = signal.set_wakeup_fd(write_end, warn_on_full_buffer=False)
    except ValueError:                   # not the main thread of the main interpreter
        os.close(read_end)
        os.close(write_end)
        previous_wakeup = None

    def arrived() -> int:
        """How many SIGTERM and SIGHUP reached the process since the last call."""
        count = 0
        with contextlib.suppress(OSError):
            while chunk := os.read(read_end, 512):
                count += sum(1 for number in chunk if number in stops)
        return count

    def handler(signum, frame):
        if received or (previous_wakeup is not None and arrived() > 1):
            _at_once(signum)
        received.append(signum)
        for number in stops:             # a further one acts by itself, at once
            signal.signal(number, signal.SIG_DFL)
        quit_now(signum)

    previous = {signum: signal.signal(signum, handler) for signum in stops}

    def restore() -> None:
        for signum, old in previous.items():
            signal.signal(signum, old)
        if previous_wakeup is not None:
            signal.set_wakeup_fd(previous_wakeup)
            os.close(read_end)
            os.close(write_end)

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
