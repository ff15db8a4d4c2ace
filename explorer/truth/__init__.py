"""Ground truth for the LPV: a one-bounce reference renderer and error metrics."""

from explorer.truth.bvh import Bvh, build_bvh
from explorer.truth.reference import (
    Cancelled,
    GBuffer,
    ReferencePass,
    numpy_reference_irradiance,
    outgoing_radiance,
    reference_irradiance,
)
from explorer.truth.render import reference_indirect

__all__ = [
    "Bvh",
    "Cancelled",
    "GBuffer",
    "ReferencePass",
    "build_bvh",
    "numpy_reference_irradiance",
    "outgoing_radiance",
    "reference_indirect",
    "reference_irradiance",
]
