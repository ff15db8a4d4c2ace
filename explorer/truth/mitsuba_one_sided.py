"""A one-sided surface for Mitsuba 3 as the explorer draws one (docs/MODEL.md "Scene
conventions"): there for a viewer in front of it, absent for a viewer behind it.

The explorer discards a one-sided triangle that a view (the camera or a light) sees from
behind, so the camera sees through its back and a light behind it shines through. Mitsuba
has no such plugin (``twosided`` refuses a transmitting back), so this file registers
``lpv_one_sided``: a BSDF wrapping the front's BSDF (its nested ``front``), that is

* reflective (the front BSDF) where a ray arrives at its front, null (the ray passes on
  unchanged, at no depth) where it arrives at its back: a camera behind it sees through,
  as does a bounce from a surface behind it;
* transparent to a shadow ray exactly when the light at the ray's far end is behind it:
  the shadow ray from a surface point in front towards a light behind passes (``wi``,
  towards the surface point, on the front side), one from behind towards a light in
  front is blocked, as the light's shadow map says.

Mitsuba's ``path`` integrator blocks every shadow ray at any surface; ``volpath`` asks the
BSDF's null transmission, so scenes with such a surface render with ``volpath`` (without
media it is the path tracer, and a null interaction does not count towards
``max_depth``). The file needs nothing but Mitsuba, and the export copies it beside the
scene: ``python lpv_one_sided.py scene.xml [OUT.exr [SPP]]`` registers it and renders."""

from __future__ import annotations

import sys

PLUGIN = "lpv_one_sided"
INTEGRATOR = "volpath"
_REGISTERED: set[str] = set()


def register(mi) -> None:
    """Register :data:`PLUGIN` with ``mi`` (its variant set), once per variant."""
    variant = mi.variant()
    if variant in _REGISTERED:
        return
    import drjit as dr

    class OneSided(mi.BSDF):
        """The front BSDF where a ray arrives at the front, null at the back."""

        def __init__(self, props):
            mi.BSDF.__init__(self, props)
            self.front = props["front"]
            reflect = self.front.flags()
            self.m_flags = reflect | mi.BSDFFlags.Null | mi.BSDFFlags.BackSide
            self.m_components = [reflect, mi.BSDFFlags.Null | mi.BSDFFlags.BackSide]

        def sample(self, ctx, si, sample1, sample2, active=True):
            front = mi.Frame3f.cos_theta(si.wi) > 0
            bs, weight = self.front.sample(ctx, si, sample1, sample2, active & front)
            bs.wo = dr.select(front, bs.wo, -si.wi)
            bs.pdf = dr.select(front, bs.pdf, 1.0)
            bs.eta = dr.select(front, bs.eta, 1.0)
            bs.sampled_type = dr.select(front, bs.sampled_type,
                                        mi.UInt32(int(mi.BSDFFlags.Null)))
            bs.sampled_component = dr.select(front, bs.sampled_component, mi.UInt32(1))
            return bs, dr.select(front, weight, mi.Color3f(1.0))

        def eval(self, ctx, si, wo, active=True):
            front = mi.Frame3f.cos_theta(si.wi) > 0
            return dr.select(front, self.front.eval(ctx, si, wo, active & front),
                             mi.Color3f(0.0))

        def pdf(self, ctx, si, wo, active=True):
            front = mi.Frame3f.cos_theta(si.wi) > 0
            return dr.select(front, self.front.pdf(ctx, si, wo, active & front), 0.0)

        def eval_pdf(self, ctx, si, wo, active=True):
            return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

        def eval_null_transmission(self, si, active=True):
            # a shadow ray's wi points back to the surface point; on the front side the
            # light at the far end sees this surface's back, so the ray passes
            passes = mi.Frame3f.cos_theta(si.wi) > 0
            return dr.select(passes, mi.Color3f(1.0), mi.Color3f(0.0))

        def traverse(self, callback):
            callback.put_object("front", self.front, mi.ParamFlags.Differentiable)

        def to_string(self):
            return f"OneSided[front={self.front}]"

    mi.register_bsdf(PLUGIN, lambda props: OneSided(props))
    _REGISTERED.add(variant)


def main(argv: list[str]) -> int:
    """Render an exported XML scene with :data:`PLUGIN` registered (scalar_rgb)."""
    import mitsuba as mi

    if not argv:
        print("usage: python lpv_one_sided.py SCENE.xml [OUT.exr [SPP]]", file=sys.stderr)
        return 2
    mi.set_variant("scalar_rgb")
    register(mi)
    out = argv[1] if len(argv) > 1 else str(argv[0]).rsplit(".", 1)[0] + ".exr"
    spp = int(argv[2]) if len(argv) > 2 else 256
    mi.util.write_bitmap(out, mi.render(mi.load_file(argv[0]), spp=spp))
    print("wrote", out)
    return 0


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main(sys.argv[1:]))
