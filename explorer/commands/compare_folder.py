"""The ``--out`` folder of ``lpv-explorer compare``: which of its files compare may replace.

compare keeps a listing, :data:`LISTING_FILE`, of the files it wrote into the folder. It
replaces a file of the folder only when the listing names it; a file of a name it would
write that the listing does not name (the user's ``table.md``, a folder an older compare
made before there was a listing) is never replaced: the command refuses in one line before
any rendering, and again before anything is renamed into place (the Mitsuba images' names
are known only once Mitsuba has rendered).
"""

from __future__ import annotations

from pathlib import Path

from explorer.commands import options

LISTING_FILE = ".lpv-explorer-compare"
"""The listing in compare's folder: one name a line, each a file compare wrote there."""


def planned_names(labels: list[str]) -> list[str]:
    """The files a comparison of the runs ``labels`` writes whatever else is asked."""
    names = ["reference.png", "table.md", "table.json"]
    for label in labels:
        names += [f"lpv-{label}.png", f"error-{label}.png"]
    return names


def earlier_names(folder: Path) -> set[str]:
    """The plain names :data:`LISTING_FILE` of ``folder`` lists (none when it has none);
    a listing that is not a readable text file is a :class:`options.CommandError`."""
    from explorer.safe_files import UserFileError, read_text

    listing = folder / LISTING_FILE
    if not listing.exists() and not listing.is_symlink():
        return set()
    try:
        text = read_text(listing, "compare listing", 64 * 1024)
    except UserFileError as exc:
        raise options.CommandError(f"--out: {exc}; its files are not replaced") from None
    # only plain names: a listing never reaches outside its folder
    return {name for name in text.splitlines()
            if name and Path(name).name == name and not name.startswith(".")}


def check_names(folder: Path, names: list[str], earlier: set[str]) -> None:
    """Refuse (one line) when ``folder`` holds a file of one of ``names`` that compare did
    not write there (``earlier`` does not list it)."""
    theirs = [name for name in names if name not in earlier
              and ((folder / name).exists() or (folder / name).is_symlink())]
    if theirs:
        others = f" and {len(theirs) - 1} more" if len(theirs) > 1 else ""
        raise options.CommandError(
            f"--out: {folder}/ holds {theirs[0]}{others}, which compare did not write "
            f"(no {LISTING_FILE} lists it), so it is not replaced; move it or give "
            f"another --out")


def listing_text(names: list[str], earlier: set[str], folder: Path) -> str:
    """The new listing: ``names`` and the earlier files still in ``folder``."""
    kept = {name for name in earlier if (folder / name).exists()}
    return "".join(f"{name}\n" for name in sorted(kept | set(names)))
