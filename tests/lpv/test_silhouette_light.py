"""The indirect light "past the silhouettes" (docs/ERRORS.md): the gather writes exactly
zero where no surface is seen, and what glows beside a wall seen off-axis is the wall's
outer face, which the gather damping darkens."""

from __future__ import annotations

import numpy as np

from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings

SIDE = ((3.2, 0.6, 3.2), (0.0, -0.1, 0.0))


def test_no_indirect_light_on_the_background_and_the_outer_face_is_damped(gl_context):
    base = Settings(scene="cornell", width=64, height=48, rsm_size=32, grid_size=16,
                    iterations=8)
    with Pipeline(base, gl_context) as pipeline:
        for camera in (None, SIDE):
            frame = pipeline.run(base.with_changes(camera=camera))
            background = frame.gbuffer_position[..., 3] < 0.5
            assert background.any() and np.all(frame.indirect[background] == 0.0)
        glow = {}
        for damping in (False, True):
            frame = pipeline.run(base.with_changes(camera=SIDE, gather_damping=damping))
            seen = frame.gbuffer_position[..., 3] > 0.5
            outer = seen & (frame.gbuffer_normal[..., 0] > 0.9) & \
                (frame.gbuffer_position[..., 0] > 0.99)        # the green wall, outside
            assert outer.sum() > 100 and np.all(frame.direct[outer] == 0.0)
            glow[damping] = float(frame.indirect[outer][:, 1].mean())
    assert glow[False] > 0.0 and glow[True] < 0.5 * glow[False]
