"""The float64 numpy twin of the GPU passes, written from docs/MODEL.md independently of
the shaders: :mod:`.light_grid` (injection, geometry volume, propagation), :mod:`.media`
(camera occluders, fog, glossy reflections), :mod:`.tonemap` (display encoding)."""
