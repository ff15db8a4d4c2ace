"""Where the shaders and lessons live, in a checkout and in an installed package.

A checkout keeps them at the top of the repository (``shaders/``, ``lessons/``); a
non-editable install ships them as the packages ``explorer.shaders`` and
``explorer.lessons_data`` (see ``setup.py``). Paths come from ``__file__`` or the
installed package's import spec, never from the working directory.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

_REPO_ROOT = Path(__file__).resolve().parent.parent


def _locate(checkout_name: str, package: str) -> Path:
    checkout = _REPO_ROOT / checkout_name
    # A checkout is recognised by its pyproject.toml, so that an unrelated top-level
    # "shaders" folder in site-packages is never mistaken for ours.
    if (_REPO_ROOT / "pyproject.toml").is_file() and checkout.is_dir():
        return checkout
    # The resource packages have no __init__.py (they are folders of .glsl and .toml
    # files), so they import as namespace packages: their folder is the spec's search
    # location (importlib.resources.files would give a MultiplexedPath, not a folder).
    try:
        spec = importlib.util.find_spec(package)
    except ModuleNotFoundError:  # pragma: no cover - broken install
        spec = None
    locations = list(spec.submodule_search_locations or []) if spec is not None else []
    if not locations:
        raise FileNotFoundError(
            f"cannot find the {checkout_name}/ folder: not in a checkout ({checkout}) "
            f"and the package {package!r} is not installed")
    return Path(locations[0])


def shader_dir() -> Path:
    """Folder holding the ``*.glsl`` files (with ``generated/`` below it)."""
    return _locate("shaders", "explorer.shaders")


def lesson_dir() -> Path:
    """Folder holding the ``NN-slug.toml`` lessons."""
    return _locate("lessons", "explorer.lessons_data")
