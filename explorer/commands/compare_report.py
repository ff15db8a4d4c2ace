"""What ``compare`` reports for one region and how it saves an image: the metric cells
of every error table (docs/ERRORS.md prints them alike), an image's ErrorStats over a
mask, and the linear PNG / false-colour error PNG writers. Shared by ``compare``, its
``--truth mitsuba`` table and ``tables``."""

from __future__ import annotations

from pathlib import Path


def region_metrics(lpv, reference, mask) -> tuple[object | None, tuple[float, float] | None]:
    """The ErrorStats and the (LPV, reference) mean radiance over ``mask``; (None, None)
    when it holds no pixel."""
    from explorer.truth.metrics import EmptyRegionError, error_stats, mean_radiance

    try:
        stats = error_stats(lpv, reference, mask)
    except EmptyRegionError:
        return None, None
    return stats, (mean_radiance(lpv, mask), mean_radiance(reference, mask))


METRIC_HEADERS = ("rel. L2", "RMSE", "flux ratio LPV/ref", "ratio r, g, b")
METRIC_ALIGN = ("---:", "---:", "---:", "---")


def metric_cells(stats) -> list[str]:
    """The table cells of an ErrorStats (:data:`METRIC_HEADERS`), as every table of
    docs/ERRORS.md prints them; None (an empty region) gives dashes."""
    if stats is None:
        return ["–", "–", "–", "empty region"]
    return [f"{stats.relative_l2:.3f}", f"{stats.rmse:.4g}", f"{stats.flux_ratio:.3f}",
            ", ".join(f"{v:.3f}" for v in stats.flux_ratio_rgb)]


def _to_srgb8(linear):
    from explorer.lpv.twin.tonemap import linear_to_srgb

    return (linear_to_srgb(linear) * 255.0 + 0.5).astype("uint8")


def save_png(path: Path, linear) -> None:
    """Linear (H, W, 3), row 0 at the top (FrameResult's order), to an sRGB PNG."""
    from PIL import Image

    Image.fromarray(_to_srgb8(linear)).save(path)


def save_error_png(path: Path, error) -> None:
    """The false-colour error (already display colours) with a colour bar and its scale."""
    import numpy as np

    from explorer.commands.scale_bar import save_with_scale_bar
    from explorer.truth.metrics import diverging_colormap

    width = error.rgb.shape[1]
    ramp = diverging_colormap(np.linspace(-error.scale, error.scale, width), error.scale)
    unit = "log2(LPV/ref)" if error.mode == "log2-ratio" else "LPV - ref"
    save_with_scale_bar(path, error.rgb, ramp, f"-{error.scale:.3g}", f"+{error.scale:.3g}",
                        unit)
