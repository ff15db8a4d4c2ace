"""What the site's tests build (shared by their modules)."""

from __future__ import annotations

import os
from pathlib import Path

LESSONS = ("overview", "solid-angles")
SIZE = (320, 200)
ROOT = Path(__file__).resolve().parents[2]
BUILT = os.environ.get("LPV_SITE_DIR")
"""Set to a site built before (e.g. the whole course) to check it instead of building."""
