"""Picked values as text rows (pure, no imgui): the tooltip and the Picked panel show
these, so both say the same thing."""

from __future__ import annotations

import numpy as np

from explorer.ui.overlays.picking import CellInfo, PickInfo


def vector(values, digits: int = 4) -> str:
    return "(" + ", ".join(f"{float(v):.{digits}g}" for v in np.ravel(values)) + ")"


def pixel_rows(pick: PickInfo, digits: int = 4) -> list[tuple[str, str]]:
    """(label, value) rows of a picked pixel; radiance in W/(m²·sr) per channel."""
    rows = [("pixel", f"({pick.x}, {pick.y})")]
    if not pick.surface:
        return rows + [("surface", "none (background)")]
    rows += [
        ("position", vector(pick.position, digits)),
        ("normal", vector(pick.normal, digits)),
        ("albedo", vector(pick.albedo, digits)),
        ("direct", vector(pick.direct, digits)),
        ("indirect", vector(pick.indirect, digits)),
        ("final (exposed)", vector(pick.final, digits)),
    ]
    if pick.indirect_from_grid is not None:
        rows.append(("indirect from grid", vector(pick.indirect_from_grid, digits)))
    if pick.reference is not None:
        rows.append(("reference", vector(pick.reference, digits)))
    if len(pick.weights) > 1:
        rows.append(("cascade weights", vector(pick.weights, 3)))
    for cell in pick.cells:
        rows.append((f"cell (cascade {cell.cascade})",
                     f"{cell.index}  flux {vector(cell.flux, digits)} W"))
    return rows


def cell_rows(cell: CellInfo, digits: int = 4) -> list[tuple[str, str]]:
    """(label, value) rows of a cell: where it is, its SH (r, g, b rows) and its audit."""
    rows = [
        ("cell", f"{cell.index} of cascade {cell.cascade}"),
        ("centre", vector(cell.centre, digits)),
        ("cell size", f"{cell.cell_size:.{digits}g}"),
    ]
    for channel, name in enumerate("rgb"):
        rows.append((f"SH {name} [W/sr]", vector(cell.coefficients[channel], digits)))
    rows.append(("flux of acc_N [W]", vector(cell.flux, digits)))
    rows.append(("share of acc_N", vector(cell.share, 3)))
    if cell.in_flight is not None:
        rows.append(("injected (grid_0) [W]", vector(cell.injected, digits)))
        rows.append(("Σ_t grid_t [W]", vector(cell.accumulated_from_steps, digits)))
    if cell.blocker_area is not None:
        rows.append(("blocker area [cell faces]", f"{cell.blocker_area:.{digits}g}"))
    return rows
