"""Picked values as text rows (pure, no imgui): the tooltip and the Picked panel show
these, so both say the same thing."""

from __future__ import annotations

import numpy as np

from explorer.ui.overlays.picking import CellAuditInfo, CellInfo, PickInfo
from explorer.ui.overlays.pixel_reference import ratio


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
    for mode, value in pick.references:
        rows.append((f"reference ({mode})", vector(value, digits)))
        rows.append((f"indirect / reference ({mode})", vector(ratio(pick.indirect, value), 3)))
    if len(pick.weights) > 1:
        rows.append(("cascade weights", vector(pick.weights, 3)))
    for cell in pick.cells:
        rows.append((f"cell (cascade {cell.cascade})",
                     f"{cell.index}  flux {vector(cell.flux, digits)} W"))
    return rows


def cell_audit_rows(info: CellAuditInfo, digits: int = 4) -> list[tuple[str, str]]:
    """(label, value) rows of a cell's audit records [W]: over all steps, and the last
    step's; the reflection terms only where a step reflected anything, the budget's
    only where it withheld any."""
    rows = [("injected (accumulated − received)", vector(info.injected, digits))]
    parts = [(f"all {info.steps} steps", info.total)]
    if info.last is not None:
        parts.append((f"step {info.steps}", info.last))
    bounced = any(np.any(audit.reflected) or np.any(audit.blocked) for _, audit in parts)
    budgeted = any(np.any(audit.budget_withheld) for _, audit in parts)
    for when, audit in parts:
        terms = [("received", audit.received), ("sent out of the grid", audit.border_loss),
                 ("clamp gain", audit.clamp_gain), ("occluded", audit.occluded)]
        if budgeted:
            terms.append(("withheld by the budget", audit.budget_withheld))
        if bounced:
            terms += [("reflected back", audit.reflected), ("blocked, can bounce",
                                                           audit.blocked)]
        rows += [(f"{name}, {when}", vector(value, digits)) for name, value in terms]
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
    rows.append(("accumulated flux [W]", vector(cell.flux, digits)))
    rows.append(("share of the accumulated flux", vector(cell.share, 3)))
    if cell.in_flight is not None:
        rows.append(("injected, before any step [W]", vector(cell.injected, digits)))
        rows.append(("sum over the steps [W]", vector(cell.accumulated_from_steps, digits)))
    if cell.blocker_area is not None:
        rows.append(("blocker area [cell faces]", f"{cell.blocker_area:.{digits}g}"))
    return rows
