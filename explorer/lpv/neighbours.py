"""Over how many neighbours a propagation step moves light (6 or 26), which switches the
26-neighbour step has no form for (docs/MODEL.md "26 neighbours"), and what the flux
budget needs (docs/MODEL.md "Flux budget")."""

from __future__ import annotations

import numpy as np

from explorer.lpv.settings import Corrections

NEIGHBOURS = (6, 26)
"""The propagation's neighbourhoods: the six face neighbours (five faces each) or all 26
neighbours (their outer faces on the 3×3×3 block, ``derivations/neighbours26.py``)."""
FACES_PER_STEP = {6: 6 * 5, 26: 6 * 9}
"""Faces a cell's light is evaluated on per step and colour: six neighbours × five faces,
or the 54 outer squares of the 3×3×3 block (nine on each of its six sides), each owned
by one of the 26 neighbours (``derivations/neighbours26.py`` lists them)."""


def check_neighbours(neighbours: int, corrections: Corrections, bounces: int = 1) -> int:
    """``neighbours`` as an int, or a one-line error for the switches that have no
    26-neighbour form (docs/MODEL.md "26 neighbours")."""
    if isinstance(neighbours, bool) or neighbours not in NEIGHBOURS:
        raise ValueError(f"neighbours must be 6 or 26, got {neighbours!r}")
    if neighbours == 26:
        needed = {"ping_pong": corrections.ping_pong, "side_faces": corrections.side_faces,
                  "model_face_weights": corrections.model_face_weights}
        missing = [name for name, on in needed.items() if not on]
        if missing:
            raise ValueError("26-neighbour propagation needs the corrections "
                             f"{', '.join(missing)} on (no published form of it exists)")
        if bounces != 1:
            raise ValueError("26-neighbour propagation has no second bounce (bounces=1)")
    return int(neighbours)


def check_flux_budget(flux_budget: bool, corrections: Corrections, bounces: int = 1) -> bool:
    """``flux_budget`` as a bool, or a one-line error where it has no form: the budget
    limits what each cell of grid t−1 sends, so it needs ping-pong (in place there is no
    grid t−1), and bounces 1 (the reflection sends light the budget does not count)."""
    if not isinstance(flux_budget, (bool, np.bool_)):
        raise ValueError(f"flux_budget must be True or False, got {flux_budget!r}")
    if flux_budget and (not corrections.ping_pong or bounces != 1):
        raise ValueError("the flux budget needs the ping_pong correction on and bounces 1 "
                         f"(ping_pong {'on' if corrections.ping_pong else 'off'}, bounces "
                         f"{bounces})")
    return bool(flux_budget)
