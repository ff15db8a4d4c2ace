"""Result names without sympy: the error for an unknown one, shared by the derivations' registry
and the window's lookup (:mod:`explorer.derived`)."""

from __future__ import annotations

import difflib


def unknown_name(name: str, known: list[str]) -> KeyError:
    """The error for a result name not in ``known``, naming the closest matches (shared by
    ``derivations.registry.get`` and :func:`explorer.derived.get`)."""
    close = difflib.get_close_matches(name, known, n=6, cutoff=0.5)
    if not close:
        prefix = name.split(".", 1)[0]
        close = [n for n in known if n.startswith(prefix + ".")][:12]
    hint = f"; did you mean {', '.join(close)}?" if close else ""
    return KeyError(f"no derivation result named {name!r}{hint} "
                    f"(`lpv-explorer constants` lists all {len(known)} names)")
