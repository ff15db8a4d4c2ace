"""SceneBuffers.draw sets its per-run uniforms (``u_base_colour``, ``u_one_sided``) on a
program from the loader only when the program does not hold them already, and every draw
on one that keeps nothing to compare."""

from __future__ import annotations

from explorer.gl.call_counter import GlCallCounter
from explorer.gl.program import ProgramCache, set_uniform
from explorer.gl.targets import RenderTargets
from explorer.scene import load_scene
from explorer.scene.gpu import SceneBuffers

RAW_VERTEX = """#version 330
in vec3 in_position;
uniform bool u_one_sided;
out float v_sided;
void main() { v_sided = float(u_one_sided); gl_Position = vec4(in_position, 1.0); }
"""
RAW_FRAGMENT = """#version 330
in float v_sided;
out vec4 colour;
void main() { colour = vec4(v_sided); }
"""
"""A program made straight with moderngl (no ``extra`` of the loader's): it uses
``u_one_sided`` only."""


def _uploads(buffers: SceneBuffers, program, targets: RenderTargets) -> int:
    with GlCallCounter() as counter, targets.drawing(clear=True):
        buffers.draw(program)
    return counter.tally.calls["uniform uploads"]


def test_a_draw_uploads_only_what_the_program_does_not_hold(ctx):
    scene = load_scene("cornell")
    programs = ProgramCache(ctx)
    buffers = SceneBuffers(ctx, scene)
    targets = RenderTargets(ctx, ("f4",) * 3, depth=True)
    try:
        targets.allocate((16, 16))
        program = programs.get("gbuffer.glsl")
        assert len(buffers.runs) == 1                     # the Cornell box: one run
        one_sided = buffers.runs[0][3]
        assert _uploads(buffers, program, targets) == 2   # both, the first time
        assert _uploads(buffers, program, targets) == 0   # held already
        set_uniform(program, "u_one_sided", int(not one_sided))   # another pass's value
        assert _uploads(buffers, program, targets) == 1
        assert program["u_one_sided"].value == int(one_sided)
        raw = ctx.program(vertex_shader=RAW_VERTEX, fragment_shader=RAW_FRAGMENT)
        try:
            assert _uploads(buffers, raw, targets) == 1   # nothing kept: every draw
            assert _uploads(buffers, raw, targets) == 1
        finally:
            raw.release()
    finally:
        targets.release()
        buffers.release()
        programs.release()
