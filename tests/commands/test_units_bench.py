"""``lpv-explorer bench --units``: the driver's rows, the command's refusals."""

from __future__ import annotations

from explorer.cli import main
from explorer.commands import units_driver
from explorer.lpv.passes.textures import point_batches


def test_the_unit_driver_reports_each_stage_of_each_change(gl_context, ctx):
    figures = units_driver.measure(grid=8, size=(40, 32), repeat=1, to_grid=12, rsm=64)
    rows = {(row["change"], row["stage"]): row for row in figures["rows"]}
    changes = [name for name, _ in units_driver.changes(units_driver_settings(), 12, 64)]
    assert changes == ["12³ grid", "12³ toggle", "12³ geometry volume",
                       "12³ volume, two lights", "12³ L2", "12³ 26 neighbours",
                       "12³ RSM 64², occluders"]
    assert ("12³ L2", "inject") in rows and ("12³ 26 neighbours", "propagate") in rows
    # what each change runs: the toggle no geometry volume, the volume no injection
    assert ("12³ grid", "inject") in rows and ("12³ toggle", "geometry") not in rows
    assert ("12³ geometry volume", "inject") not in rows
    # the RSM's texels drawn in batches (explorer/lpv/passes/textures.py), then the read
    occluders = units_driver_settings().rsm_size ** 2
    assert rows[("12³ geometry volume", "geometry")]["units"] == len(point_batches(occluders)) + 1
    assert len(point_batches(occluders)) == 2             # a 256² RSM's in two
    # a small grid: its batches of VPLs (the RSM's texels), its copies not apart
    assert rows[("12³ toggle", "inject")]["units"] == len(point_batches(occluders))
    for row in rows.values():
        assert 0.0 <= row["longest_cpu_ms"] <= row["cpu_ms"] + 1e-9
        assert row["longest_wall_ms"] >= 0.0
    table = units_driver.format_units(figures)
    assert table.splitlines()[0].split() == ["change", "stage", "units", "longest", "wall",
                                             "longest", "cpu", "stage", "cpu"]
    assert len(table.splitlines()) == len(figures["rows"]) + 1


def units_driver_settings():
    from explorer.lpv.settings import Settings

    return Settings(grid_size=8)


def test_the_unit_bench_refuses_settings_and_a_root_without_a_pipeline(tmp_path, capsys):
    assert main(["bench", "--units", "--grid", "16"]) == 2
    assert "--grid" in capsys.readouterr().err
    assert main(["bench", "--units", "--root", str(tmp_path)]) == 2
    assert "no explorer/lpv/pipeline.py" in capsys.readouterr().err
    assert main(["bench", "--units", "--overhead"]) == 2
    capsys.readouterr()
