"""Strict uniforms: misspelt names raise, and every program of a stage reads exactly the
correction switches the registry gives that stage."""

from __future__ import annotations

import itertools

import pytest

from explorer.gl.program import (
    ProgramCache,
    UniformError,
    declared_uniforms,
    set_uniform,
    set_uniforms,
)
from explorer.lpv.corrections import CORRECTIONS, STAGES, Corrections, uniforms_read_by
from explorer.lpv.passes.gather import GatherPass
from explorer.lpv.passes.gather import program_defines as gather_defines
from explorer.lpv.passes.geometry import GeometryPass
from explorer.lpv.passes.inject import InjectPass
from explorer.lpv.passes.propagate import COMPILED_SWITCHES, PropagatePass, program_defines
from explorer.lpv.passes.textures import image_format_defines, sh_defines
from explorer.lpv.settings import GRID_FORMATS, SH_ORDERS

VARIANTS = list(itertools.product(GRID_FORMATS, SH_ORDERS))

# Every program a pass runs with the correction switches, in every variant it compiles.
STAGE_PROGRAMS = {
    InjectPass.STAGE: [("inject_points.glsl", sh_defines(order)) for order in SH_ORDERS]
    + [("inject_compute.glsl", {"INJECT_STAGE": 1, **image_format_defines(fmt),
                                **sh_defines(order)}) for fmt, order in VARIANTS],
    GeometryPass.STAGE: [("geometry_inject.glsl", {}),
                         ("geometry_inject.glsl", {"CAMERA_SURFELS": 1})],
    PropagatePass.STAGE: [("propagate.glsl", program_defines(
        fmt, order, Corrections(ping_pong=ping_pong), audit=audit, geometry=geometry,
        reflect=geometry)) for fmt, order in VARIANTS for ping_pong in (True, False)
        for audit, geometry in ((False, False), (True, True))],
    GatherPass.STAGE: [("gather.glsl", gather_defines(order, cascades=cascades, damping=damping))
                       for order in SH_ORDERS for cascades in (False, True)
                       for damping in (False, True)]
    + [("gather.glsl", gather_defines(order, net_flux=True, damping=damping))
       for order in SH_ORDERS for damping in (False, True)],
}
SWITCHES = {entry.uniform for entry in CORRECTIONS}


@pytest.fixture
def programs(ctx):
    cache = ProgramCache(ctx)
    yield cache
    cache.release()


def test_every_stage_program_reads_exactly_its_registry_switches(programs):
    assert set(STAGE_PROGRAMS) == set(STAGES)
    for stage, variants in STAGE_PROGRAMS.items():
        # the switches that choose a code path are compiled in as defines instead
        wanted = set(uniforms_read_by(stage)) - set(COMPILED_SWITCHES)
        for name, defines in variants:
            program = programs.get(name, defines)
            active = {uniform for uniform in SWITCHES if uniform in program}
            assert active == wanted, (stage, name, defines)


def test_a_compiled_switch_follows_its_correction():
    """The propagation reads ping_pong as a define: each value compiles its own program."""
    for uniform, define in COMPILED_SWITCHES.items():
        entry = next(entry for entry in CORRECTIONS if entry.uniform == uniform)
        for value in (True, False):
            corrections = Corrections(**{entry.name: value})
            assert program_defines("rgba32f", 1, corrections)[define] == int(value)


def test_a_program_that_does_not_read_a_required_switch_fails(programs):
    # The compute injection's first stage only bins VPLs: the switches are declared (it
    # includes lpv_corrections.glsl) but unused, so the compiler drops them.
    link = programs.get("inject_compute.glsl", {"INJECT_STAGE": 0})
    values = Corrections().as_uniforms()
    set_uniforms(link, values)                       # declared but unused: skipped
    with pytest.raises(UniformError, match="must read the uniform u_injection_pi"):
        set_uniforms(link, values, reads=uniforms_read_by("inject"))


def test_a_required_switch_without_a_value_fails(programs):
    program = programs.get("geometry_inject.glsl")
    with pytest.raises(UniformError, match="no value given for u_surfel_area_squared"):
        set_uniforms(program, {}, reads=uniforms_read_by("geometry"))
    # once its reads were found active, a later call still needs every value
    values = Corrections().as_uniforms()
    set_uniforms(program, values, reads=uniforms_read_by("geometry"))
    values.pop("u_surfel_area_squared")
    with pytest.raises(UniformError, match="no value given for u_surfel_area_squared"):
        set_uniforms(program, values, reads=uniforms_read_by("geometry"))


def test_a_value_set_again_is_uploaded_only_when_it_changed(programs):
    program = programs.get("propagate.glsl")
    set_uniforms(program, {"u_cell_offset": (0, 0, 4)})
    program["u_cell_offset"].value = (0, 0, 2)        # behind set_uniforms' back
    set_uniforms(program, {"u_cell_offset": (0, 0, 4)})
    assert program["u_cell_offset"].value == (0, 0, 2)   # the same value: not uploaded
    set_uniforms(program, {"u_cell_offset": (0, 0, 8)})
    assert program["u_cell_offset"].value == (0, 0, 8)


def test_set_uniform_uploads_a_changed_number_and_keeps_set_uniforms_right(programs):
    """The one-number path checks a name it has not uploaded as set_uniforms does, uploads
    only a changed value, and a dict set_uniforms would skip as its last one is uploaded
    again once set_uniform changed a value it holds."""
    program = programs.get("audit_reduce.glsl", {"AUDIT_STAGE": 1})
    with pytest.raises(UniformError, match="no uniform 'u_result_slt'"):
        set_uniform(program, "u_result_slt", 1)
    values = {"u_result_slot": 3}
    set_uniforms(program, values)
    program["u_result_slot"].value = 5                # behind their back
    set_uniform(program, "u_result_slot", 3)
    assert program["u_result_slot"].value == 5        # the same value: not uploaded
    set_uniform(program, "u_result_slot", 4)
    assert program["u_result_slot"].value == 4
    set_uniforms(program, values)                     # the last dict, no longer what is set
    assert program["u_result_slot"].value == 3


def test_a_misspelt_uniform_raises_and_names_the_right_one(programs):
    program = programs.get("propagate.glsl")
    set_uniforms(program, {"u_side_faces": 0}, reads=())
    assert program["u_side_faces"].value == 0
    with pytest.raises(UniformError, match="no uniform 'u_side_face'.*u_side_faces"):
        set_uniforms(program, {"u_side_face": 1})


def test_set_uniforms_needs_a_program_from_the_loader(ctx):
    raw = ctx.compute_shader("#version 430 core\nlayout(local_size_x = 1) in;\n"
                             "uniform float u_a;\nlayout(std430, binding = 0) buffer B "
                             "{ float v[]; };\nvoid main() { v[0] = u_a; }\n")
    with pytest.raises(TypeError, match="load_program"):
        set_uniforms(raw, {"u_a": 1.0})
    raw.release()


def test_declared_uniforms_reads_declarations_only():
    source = """
    uniform bool u_flag;                       // uniform float u_in_comment;
    /* uniform int u_in_block_comment; */
    layout(rgba32f, binding = 0) uniform writeonly image3D u_image;
    uniform sampler3D u_cascade_r[MAX_CASCADES];
    uniform vec3 u_origin [4];
    // the uniforms below are set by the pass
    layout(std430, binding = 1) buffer Cells { float cells[]; };
    """
    assert declared_uniforms(source) == {"u_flag", "u_image", "u_cascade_r", "u_origin"}
