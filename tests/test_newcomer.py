"""The newcomer's path, second pass (issue 39): maps that answer life and speed questions, a bearing file named
by a job config, one-line messages that name the flag and the extra to install, roller records that do not
read like edge loading."""

import math
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

import fastbearing as fb
from conftest import cli_run

DATA = Path(__file__).parents[1] / "fastbearing" / "catalogue"


def test_a_life_map_at_speed_stores_iso_l10_hours_and_the_outer_contact_angles(tmp_path):
    """L10 (ISO 281) beside L10r, both in hours at each case's speed, and the outer contacts' angles,
    which at speed fall below the inner ones; L10 and L10r are fb.rating_life's at that load and speed."""
    cfg = tmp_path / "map.toml"
    cfg.write_text(f'bearing = "{DATA / "7014C-DB.toml"}"\n\n[loadmap]\nFx = 600.0\nFz = [500.0, 1000.0]\n'
                   'speed = [0.0, 12000.0]\nlife = true\n')
    out = fb.loadmap(cfg, tmp_path / "m.h5", progress=False)
    with h5py.File(out) as h:
        assert h["L10"].attrs["units"] == "million revolutions" and h["L10_hours"].attrs["units"] == "h"
        L10, L10r = h["L10"][...], h["L10r"][...]
        hours, rhours = h["L10_hours"][...], h["L10r_hours"][...]
        inner, outer = h["min_contact_angle"][...], h["min_outer_contact_angle"][...]
        speeds, Fz = h["speed"][...], h["Fz"][...]
    b = fb.load_bearing(DATA / "7014C-DB.toml")
    for i, rpm in enumerate(speeds):
        for j, fz in enumerate(Fz):
            life = fb.rating_life(b, [600.0, 0, fz, 0, 0], speed=rpm if rpm > 0 else None)
            assert L10[i, j] == pytest.approx(life.L10, rel=1e-9)
            assert L10r[i, j] == pytest.approx(life.L10r, rel=1e-6)
            if rpm > 0:
                assert hours[i, j] == pytest.approx(L10[i, j] * 1e6 / (60 * rpm), rel=1e-12)
                assert rhours[i, j] == pytest.approx(L10r[i, j] * 1e6 / (60 * rpm), rel=1e-12)
                assert np.all(outer[i, j] < inner[i, j])  # the centrifugal force turns the outer contact down
            else:
                assert math.isinf(hours[i, j]) and np.allclose(outer[i, j], inner[i, j], rtol=1e-12)


def test_a_job_config_may_name_a_bearing_file_relative_to_itself(tmp_path):
    folder = tmp_path / "configs"
    folder.mkdir()
    (folder / "map.toml").write_text('bearing = "../b.toml"\n\n[loadmap]\nFx = [1000.0, 2000.0]\nFz = 3000.0\n')
    (tmp_path / "b.toml").write_text((DATA / "6305.toml").read_text())
    out = fb.loadmap(folder / "map.toml", tmp_path / "m.h5", progress=False)
    with h5py.File(out) as h:
        K = h["K"][...]
        assert "6305" in h.attrs["config"]  # the bearing file's text joins the provenance
    one = fb.solve(fb.load_bearing(DATA / "6305.toml"), [2000.0, 0, 3000.0, 0, 0])
    assert np.abs(K[1] - one.K).max() <= 1e-9 * np.abs(one.K).max()
    (folder / "p.toml").write_text('bearing = "../b.toml"\n\n[passage]\ndx = 0.01\ndz = 0.05\npositions = 4\n')
    assert fb.passage(folder / "p.toml", tmp_path / "p.h5", progress=False).exists()
    (folder / "bad.toml").write_text('bearing = "nowhere.toml"\n\n[loadmap]\nFx = 1000.0\n')
    with pytest.raises(ValueError, match=r"bearing = 'nowhere.toml': no bearing file at .*relative to the config"):
        fb.loadmap(folder / "bad.toml", tmp_path / "x.h5", progress=False)


def test_a_plot_without_the_plot_extra_names_it_once(tmp_path, monkeypatch, capsys):
    from fastbearing.cli import main

    monkeypatch.setitem(sys.modules, "matplotlib", None)  # as if not installed
    code = main(["plot", "loadzone", "--preset", "gunduz2013", "--load", "1000,0,3000,0,0",
                 "-o", str(tmp_path / "z.png")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code != 0 and len(err) == 1
    assert err[0].count("[plot]") == 1 and 'pip install ".[plot]"' in err[0] and "matplotlib" in err[0]


def test_an_unloaded_roller_prints_no_largest_slice_place():
    """An unloaded roller has no largest slice load: its x(mm) cell stays empty (it read like edge loading)."""
    s = cli_run("solve", "--bearing", DATA / "NU205.toml", "--load", "3000,0,0,0,0", "--balls")
    rows = [line.split() for line in s.stdout.splitlines() if line[:3].strip().isdigit()]
    unloaded = [r for r in rows if float(r[3]) == 0.0]
    loaded = [r for r in rows if float(r[3]) > 0.0]
    assert unloaded and loaded
    assert all(len(r) < len(loaded[0]) for r in unloaded)


def test_a_partial_run_from_another_config_names_the_overwrite_flag(tmp_path):
    cfg = {"bearing": {"preset": "gunduz2013"}, "loadmap": {"Fx": [1000.0, 2000.0], "Fz": 3000.0}}
    out = tmp_path / "m.h5"
    part = tmp_path / "m.h5.part"
    part.write_bytes(b"not hdf5")
    with pytest.raises(ValueError, match=r"--overwrite \(Python: overwrite=True\)"):
        fb.loadmap(cfg, out, resume=True, progress=False)


def test_a_command_that_starts_compiling_says_so_before_the_wait(monkeypatch, capsys):
    """Any command (here `bearing`, made to compile a new kernel): the notice comes first, once."""
    from numba import njit

    from fastbearing import _cache, cli

    monkeypatch.setattr(_cache, "_told", False)
    fresh = njit(lambda x: x * 2)
    command = cli._bearing_command

    def compiling(args):
        fresh(3)
        print("the command's output")
        return command(args)

    monkeypatch.setattr(cli, "_bearing_command", compiling)
    assert cli.main(["bearing", str(DATA / "6305.toml")]) == 0
    out = capsys.readouterr()
    assert out.err.startswith("fastbearing: compiling the kernels") and out.err.count("compiling") == 1
