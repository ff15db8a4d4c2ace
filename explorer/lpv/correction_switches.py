"""The correction switches' fields (GENERATED FILE, do not edit).

Written by ``python -m derivations.codegen`` from the corrections registry
(``derivations/correction_registry.py``); its ``--check`` and the test suite fail
when it is stale. :class:`explorer.lpv.corrections.Corrections` adds the methods;
the fields are written out so that type checkers read them (their annotations are
the ``bool`` class itself: no ``from __future__ import annotations``).
"""

from dataclasses import dataclass


@dataclass(frozen=True)
class CorrectionSwitches:
    """One switch per registry entry: True = corrected (the default), False = as
    published."""

    injection_pi: bool = True
    """Injection: intensity = flux / π."""
    propagation_4pi: bool = True
    """Propagation: no 1/(4π) per face."""
    reprojection_pi: bool = True
    """Reprojection: face flux kept as is."""
    exact_constants: bool = True
    """Exact solid angles."""
    side_faces: bool = True
    """Side faces."""
    surfel_area_squared: bool = True
    """Occluder area grows with depth squared."""
    ping_pong: bool = True
    """Ping-pong propagation."""
    clamp_front_face: bool = True
    """Clamp the front face."""
    model_face_weights: bool = True
    """Face weights of the model."""
    irradiance_gather: bool = True
    """Gather the irradiance."""
