"""A teacher's folder published as a site (``site OUT --lessons DIR``), read in headless
Chromium: the index links each lesson of the folder, every page opens with its live
figure running and no console warning, and every link and picture of the pages is a
file the build wrote."""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path
from urllib.parse import unquote, urlparse

import pytest

from explorer.cli import main

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def teacher_site(tmp_path_factory) -> Path:
    """The site of a folder holding the lesson ``lessons new`` writes, twice."""
    base = tmp_path_factory.mktemp("teacher")
    folder = base / "my-lessons"
    for name in ("First light", "Second look"):
        assert main(["lessons", "new", name, "--dir", str(folder)]) == 0
    out = base / "class-site"
    done = subprocess.run([sys.executable, "-m", "explorer", "site", str(out), "--lessons",
                           str(folder), "--size", "160x100", "--figure-width", "240"],
                          cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    return out


def _local(url: str) -> Path | None:
    """The file a ``file://`` address names (None for another scheme)."""
    parsed = urlparse(url)
    return Path(unquote(parsed.path)) if parsed.scheme == "file" else None


def _warnings(browser) -> list[dict]:
    return [entry for entry in browser.get_log("browser")
            if entry["level"] in ("SEVERE", "WARNING")]


def _readouts(browser) -> dict[str, str]:
    return dict(browser.execute_script(
        "return Array.from(document.querySelectorAll('.live-figure [data-readout]'),"
        " e => [e.dataset.readout, e.dataset.value])"))


def test_the_teachers_site_opens_runs_and_links(teacher_site, browser):
    from selenium.webdriver.common.keys import Keys

    browser.set_window_size(1280, 900)
    browser.get_log("browser")
    browser.get((teacher_site / "index.html").as_uri())
    assert not _warnings(browser)
    lessons = [a.get_attribute("href") for a in
               browser.find_elements("css selector", "a[href$='.html']")]
    pages = sorted({_local(href).name for href in lessons} - {"index.html"})
    assert pages == ["01-first-light.html", "02-second-look.html"], lessons
    for page in pages:
        shown = [a for a in browser.find_elements("css selector", f"a[href='{page}']")
                 if a.is_displayed()]
        assert shown, page
        shown[0].click()
        assert _local(browser.current_url).name == page
        for _ in range(100):             # the live figure starts once the script ran
            if browser.execute_script(
                    "return document.querySelectorAll('figure.is-live').length === "
                    "document.querySelectorAll('[data-live-kind]').length && "
                    "document.querySelectorAll('figure.is-live').length > 0"):
                break
            time.sleep(0.1)
        else:
            raise AssertionError(f"{page}: the live figure did not start: "
                                 f"{browser.get_log('browser')}")
        headings = [h.text for h in browser.find_elements("css selector", "h2")]
        assert any("The bounce of light" in h for h in headings), headings
        before = _readouts(browser)
        slider = browser.find_element("css selector", ".live-figure input[type=range]")
        browser.execute_script("arguments[0].scrollIntoView({block: 'center'})", slider)
        slider.send_keys(Keys.ARROW_RIGHT)
        after = _readouts(browser)
        assert after != before and after["normal_deg"] != before["normal_deg"], (before, after)
        targets = browser.execute_script(
            "return [...Array.from(document.querySelectorAll('a[href]'), a => a.href),"
            " ...Array.from(document.querySelectorAll('img'), i => i.src || i.dataset.src"
            "   && new URL(i.dataset.src, document.baseURI).href)]")
        missing = [url for url in targets if url and _local(url) is not None
                   and not _local(url).is_file()]
        assert not missing, (page, missing)
        anchors = [urlparse(url).fragment for url in targets
                   if url and _local(url) == teacher_site / page and urlparse(url).fragment]
        absent = [name for name in anchors if not browser.execute_script(
            "return document.getElementById(arguments[0]) !== null", name)]
        assert not absent, (page, absent)
        assert not _warnings(browser), page
        browser.back()
