"""The window's signal handling (explorer/stop_signals.py ``calling``) without a window:
a second SIGTERM ends the process at once even when both arrive while the main thread is
busy in C (drawing a frame), where Python calls its handler once for the two."""

from __future__ import annotations

import signal
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent

_CHILD = r"""
import hashlib, os, signal, sys, threading, time
from explorer import stop_signals

asked = []
restore = stop_signals.calling(asked.append)
count = int(sys.argv[1])
data = b"x" * (64 * 1024 * 1024)

def send():
    time.sleep(0.2)
    for _ in range(count):
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(0.05)

threading.Thread(target=send).start()
# C work that never returns to the interpreter while the signals arrive (a frame's draw)
started = time.monotonic()
while time.monotonic() - started < 0.2 + 0.05 * count + 0.3:
    hashlib.sha256(data * 4).digest()
for _ in range(100):
    if asked:
        break
    time.sleep(0.01)
restore()
print("asked", asked)
"""


@pytest.mark.parametrize("count", [1, 2])
def test_a_second_sigterm_during_a_frame_ends_at_once(count):
    child = subprocess.run([sys.executable, "-c", _CHILD, str(count)], cwd=ROOT,
                           capture_output=True, text=True, timeout=120,
                           env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"})
    if count == 1:
        assert child.returncode == 0, child.stderr
        assert f"asked [{int(signal.SIGTERM)}]" in child.stdout
    else:
        assert child.returncode == -signal.SIGTERM, (child.returncode, child.stdout,
                                                     child.stderr[-2000:])
