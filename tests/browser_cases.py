"""Debian's chromium headless through selenium and chromedriver, for the site's browser
tests: one place that finds them, skips with the reason printed when one is missing, and
starts a driver with the given Chromium arguments."""

from __future__ import annotations

import shutil

import pytest

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
CHROMEDRIVER = shutil.which("chromedriver") or "/usr/bin/chromedriver"
HEADLESS = ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage")


def start_chromium(arguments: tuple[str, ...] = ()):
    """A Chrome driver (headless, with ``arguments`` too) keeping the browser's console
    log; skips the calling test's module when chromium, chromedriver or selenium is
    missing."""
    if CHROMIUM is None or not shutil.which(CHROMEDRIVER):
        reason = ("Debian's chromium and chromium-driver are not installed "
                  "(apt-get install chromium chromium-driver)")
        print(f"\nskipped: {reason}")
        pytest.skip(reason)
    webdriver = pytest.importorskip("selenium.webdriver", reason="selenium is not installed")
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for argument in (*HEADLESS, *arguments):
        options.add_argument(argument)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    driver = webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)
    driver.set_page_load_timeout(60)
    return driver
