"""Quantities drawn in the 3D scene of the main view (slice plane, SH glyphs, VPL splats,
wireframes, blockers, the picked point) and picking.

``quantities`` and ``picking`` are pure numpy over FrameResult arrays; the renderers
(``slice``, ``glyphs``, ``splats``, ``lines``) draw them instanced into the framebuffer of
:class:`~explorer.ui.overlays.compositor.Compositor`, which depth-tests them against the
frame's own G-buffer, so no LPV pass runs when an overlay changes.
"""
