"""The site's tests share one CI-sized build of two lessons (small pictures) and one
headless Chromium (Debian's chromium, driven by selenium and chromedriver through
tests/browser_cases.py), both made once per test session: building is the slow part.
The browser skips, printing why, when chromium, chromedriver or selenium is missing."""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

import pytest
from browser_cases import start_chromium
from sitebuild import BUILT, LESSONS, ROOT, SIZE

from explorer.lessons import find_lesson, load_all


@pytest.fixture(scope="session")
def site(tmp_path_factory) -> Path:
    if BUILT:
        return Path(BUILT)
    out = tmp_path_factory.mktemp("site") / "course"
    start = time.monotonic()
    done = subprocess.run(
        [sys.executable, "-m", "explorer", "site", str(out), "--only", ",".join(LESSONS),
         "--size", f"{SIZE[0]}x{SIZE[1]}", "--figure-width", "480"],
        cwd=ROOT, capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stderr + done.stdout
    print(f"\n{done.stdout.strip()}\n(build {time.monotonic() - start:.0f} s)")
    assert "site: " in done.stdout and " MB in " in done.stdout
    return out


@pytest.fixture(scope="session")
def lessons():
    found, _ = load_all()
    return [find_lesson(key, found) for key in LESSONS]


@pytest.fixture(scope="session")
def browser():
    driver = start_chromium(("--disable-gpu", "--hide-scrollbars"))
    yield driver
    driver.quit()
