"""Issue 48 on the command line: `fastbearing bearings`, the top-level description, --bearing NAME|FILE."""

import json

import numpy as np
import pytest

from conftest import cli_run

from fastbearing import cli
from fastbearing.report.catalogue import shipped_bearings, shipped_bearings_text


def test_bearings_lists_the_shipped_bearings(tmp_path):
    out = cli_run("bearings", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert out.stdout.rstrip("\n") == shipped_bearings_text(shipped_bearings())
    assert "6205" in out.stdout and "Where the numbers come from" in out.stdout
    js = cli_run("bearings", "--json", cwd=tmp_path)
    assert js.returncode == 0, js.stderr
    entries = json.loads(js.stdout)
    assert isinstance(entries, list) and [e["name"] for e in entries] == [e["name"] for e in shipped_bearings()]
    six = next(e for e in entries if e["name"] == "6205")
    assert (six["bore"], six["outer_diameter"], six["width"], six["C"], six["C0"]) == (25, 52, 15, 14800, 7800)
    assert six["units"]["C"] == "N" and six["units"]["bore"] == "mm"
    assert cli_run("bearings", "--nonsense").returncode == 2


def test_help_says_what_fastbearing_is_and_that_a_name_does():
    parser = cli.build_parser()
    text = parser.format_help()
    for words in ("deep-groove", "four-point", "tapered roller", "TDO", "ISO 281", "DMIG", "ROSS",
                  "Units: N, mm, rad", "bearings"):
        assert words in " ".join(text.split()), words
    sub = parser._subparsers._group_actions[0].choices
    for command in ("solve", "bearing"):
        help_text = " ".join(sub[command].format_help().split())
        assert "NAME|FILE.toml" in help_text and "fastbearing bearings lists them" in help_text, command
    loadzone = sub["plot"]._subparsers._group_actions[0].choices["loadzone"]
    assert "NAME|FILE.toml" in loadzone.format_help()


# -- item 7: zeros printed as zeros --------------------------------------------------------------------------

def test_noise_prints_as_zero_and_is_no_dropped_coupling():
    import warnings

    import numpy as np

    from fastbearing.report.export import noise_as_zero, ross_arguments, ross_dropped

    K = np.diag([2.0e5, 2.0e5, 5.0e4, 3.0e7, 3.0e7])
    K[0, 1] = 1e-26          # round-off on an exact zero
    K[2, 3] = -1e-9          # noise: 2e-14 of its row's largest (5e4)
    K[3, 4] = 5.0e3          # a real coupling (1.7e-4 of its row's largest): kept
    Z = noise_as_zero(K)
    assert Z[0, 1] == 0 and Z[2, 3] == 0 and Z[3, 4] == 5.0e3 and np.array_equal(np.diag(Z), np.diag(K))
    assert not np.signbit(noise_as_zero(np.full((5, 5), -0.0))).any()
    assert noise_as_zero(np.stack([K, K])).shape == (2, 5, 5)
    text = cli._matrix("Kb", K)
    assert "1e-26" not in text and "e-09" not in text and "5000" in text
    # ROSS: only round-off beyond its kept entries -> no warning
    clean = np.diag([2.0e5, 2.0e5, 5.0e4, 0.0, 0.0])
    clean[0, 3] = 1e-20
    clean[2, 0] = 1e-13
    assert not ross_dropped(clean)[1]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ross_arguments(clean)
    assert ross_dropped(K)[1]  # the tilt stiffness is real: still said


# -- item 8: where C comes from, in every life output ----------------------------------------------------

def test_every_life_output_says_where_C_comes_from(tmp_path):
    import fastbearing as fb
    from fastbearing.analysis.life import CATALOGUE_C, CATALOGUE_C0, ISO_C, ISO_C0, rating_sources
    from fastbearing.jobs.loadmap import job, read_config
    from fastbearing.report.bearing_report import bearing_report

    assert rating_sources(fb.load_bearing("6205")) == {"C": CATALOGUE_C, "C0": CATALOGUE_C0}
    assert rating_sources(fb.load_bearing("7014C-DB")) == {"C": ISO_C, "C0": ISO_C0}
    assert rating_sources(fb.load_bearing("gunduz2013")) == {"C": None, "C0": None}
    # solve --life: text and JSON
    out = cli_run("solve", "--bearing", "6205", "--load", "1000,0,200,0,0", "--life")
    assert out.returncode == 0, out.stderr
    assert f"  C: {CATALOGUE_C}; C0: {CATALOGUE_C0}" in out.stdout.splitlines()
    js = json.loads(cli_run("solve", "--bearing", "7014C-DB", "--load", "1000,0,200,0,0", "--life",
                            "--json").stdout)
    assert (js["life"]["C_source"], js["life"]["C0_source"]) == (ISO_C, ISO_C0)
    # the bearing report
    rep = bearing_report(fb.load_bearing("6205"))
    assert rep["load_ratings"]["C"] == 14800 and rep["load_ratings"]["C_source"] == CATALOGUE_C
    text = cli_run("bearing", "QJ210").stdout
    assert f"({ISO_C})" in text and "load ratings: C = " in text
    assert "load_ratings" not in bearing_report(fb.load_bearing("gunduz2013"))
    # shaft --life: each bearing's life line, and its JSON
    from pathlib import Path

    shaft = Path(__file__).resolve().parents[1] / "data" / "examples" / "shaft-cylindrical-and-ball.toml"
    text = cli_run("shaft", shaft, "--life").stdout
    assert text.count(f"; C: {CATALOGUE_C}") == 2
    lives = [b["life"] for b in json.loads(cli_run("shaft", shaft, "--life", "--json").stdout)["bearings"]]
    assert [lf["C_source"] for lf in lives] == [CATALOGUE_C] * 2
    # a map's attributes where it stores life
    config = tmp_path / "map.toml"
    config.write_text('bearing = "6205"\n[loadmap]\nlife = true\nFx = [100.0, 1000.0, 2]\nFy = 0.0\nFz = 0.0\n'
                      'Mx = 0.0\nMy = 0.0\n')
    attrs = job(read_config(config)).attrs
    assert attrs["dynamic_load_rating_source"] == CATALOGUE_C and attrs["static_load_rating_source"] == CATALOGUE_C0


def test_passage_shaft_speed_takes_the_geometry_diameters(tmp_path):
    import math

    import pytest

    import fastbearing as fb
    from fastbearing.jobs.passage import read_config

    base = 'bearing = "6205"\n[passage]\npoints = [[0.01, 0.0, 0.0, 0.0, 0.0]]\nshaft_speed = 1797.0\n'
    (tmp_path / "p.toml").write_text(base)
    cfg = read_config(tmp_path / "p.toml")
    g = fb.load_bearing("6205").geometry
    assert (cfg.speed.shaft_speed, cfg.speed.ball_diameter, cfg.speed.pitch_diameter) == (
        1797.0, g.ball_diameter, g.pitch_diameter)
    assert cfg.speed.rotating == "inner"
    # BPFO of the CWRU 6205 at 1797 rpm: 3.5848 x the shaft frequency
    bpfo = 9 * cfg.speed.cage_frequency  # Z fc, outer ring at rest
    assert math.isclose(bpfo / (1797 / 60), 3.5848, rel_tol=2e-4)
    (tmp_path / "q.toml").write_text(base + f"ball_diameter = {g.ball_diameter}\n")
    assert read_config(tmp_path / "q.toml").speed.ball_diameter == g.ball_diameter
    (tmp_path / "r.toml").write_text(base + "pitch_diameter = 40.0\n")
    with pytest.raises(ValueError, match=r"passage\.pitch_diameter.*differs from \[bearing\.geometry\]"):
        read_config(tmp_path / "r.toml")
    # a bearing without geometry still needs both diameters
    (tmp_path / "s.toml").write_text('[bearing]\npreset = "gunduz2013"\narrangement = "DB"\n'
                                     + base.split("\n", 1)[1])
    with pytest.raises(ValueError, match="shaft_speed alone for a bearing with"):
        read_config(tmp_path / "s.toml")


# -- item 5: one CSV dialect ----------------------------------------------------------------------------

def test_passage_csv_over_revolutions_is_the_export_dialect(tmp_path):
    import csv

    from fastbearing.report.export import K_COLUMNS, read_csv

    (tmp_path / "r.toml").write_text('bearing = "6205"\n[passage]\ngiven = "load"\nFx = 1000.0\nrevolutions = 2\n'
                                     'positions = 8\nshaft_speed = 1797.0\n')
    out = cli_run("passage", tmp_path / "r.toml", "--csv", "-o", tmp_path / "spall.h5")
    assert out.returncode == 0, out.stderr
    assert not (tmp_path / "r_point0000.csv").exists()  # the CSV's name follows the output's
    with open(tmp_path / "spall_point0000.csv") as fh:
        rows = list(csv.reader(fh))
    assert rows[0][:12] == ["case", "Fx_N", "Fy_N", "Fz_N", "Mx_N_mm", "My_N_mm", "point", "position",
                            "cage_angle_rad", "shaft_angle_rad", "time_s", "status"]
    assert rows[0][12:] == [*K_COLUMNS, "status_name", "matrix"] and len(rows) == 1 + 16
    assert read_csv(tmp_path / "spall_point0000.csv").shape == (16, 5, 5)


def test_exports_carry_lives_loads_speed_and_their_case(tmp_path):
    import csv

    import numpy as np

    from fastbearing.report.export import ROSS_NOTES, read_dmig

    config = tmp_path / "map.toml"
    config.write_text('bearing = "6205"\n[loadmap]\nlife = true\nspeed = 1800.0\nFx = [500.0, 1000.0, 1500.0]\n'
                      'Fy = 0.0\nFz = [0.0, 400.0]\nMx = 0.0\nMy = 0.0\n')
    assert cli_run("loadmap", config, "-o", tmp_path / "map.h5").returncode == 0
    out = cli_run("export", tmp_path / "map.h5", "--format", "csv", "-o", tmp_path / "map.csv")
    assert out.returncode == 0, out.stderr
    with open(tmp_path / "map.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 6
    for name in ("L10r_million_revolutions", "L10_million_revolutions", "static_safety", "L10r_hours_h",
                 "L10_hours_h", "L10r_row0_million_revolutions"):
        assert name in rows[0], (name, list(rows[0]))
    L10 = float(rows[0]["L10_million_revolutions"])  # Fx = 500 N, Fz = 0: (C/P)^3 with P = Fr
    assert abs(L10 - (14800 / 500) ** 3) < 1e-6 * L10
    assert abs(float(rows[0]["L10_hours_h"]) - L10 * 1e6 / (60 * 1800)) < 1e-6 * L10
    js = json.loads(cli_run("export", tmp_path / "map.h5", "--format", "json", "-o", tmp_path / "map.json")
                    .returncode and "{}" or (tmp_path / "map.json").read_text())
    assert js["results"]["L10r"]["units"] == "million revolutions" and len(js["results"]["L10r"]["values"]) == 6
    assert cli_run("export", tmp_path / "map.h5", "--format", "npz", "-o", tmp_path / "map.npz").returncode == 0
    with np.load(tmp_path / "map.npz") as z:
        assert z["L10r"].shape == (6,) and "L10r: million revolutions" in list(z["result_units"])
    # DMIG and ROSS say which case they hold and where it comes from
    out = cli_run("export", tmp_path / "map.h5", "--format", "dmig", "--at", "Fx=1000,Fz=400", "-o",
                  tmp_path / "k.bdf")
    assert out.returncode == 0, out.stderr
    text = (tmp_path / "k.bdf").read_text()
    case_lines = " ".join(line[2:] for line in text.splitlines() if line.startswith("$ "))
    assert f"source: {tmp_path / 'map.h5'}".replace(" ", "") in case_lines.replace(" ", "")
    assert "case 3 of map.h5 (--at picked Fx=1000, Fz=400" in case_lines and "Fz = 400 N" in case_lines
    assert read_dmig(tmp_path / "k.bdf")  # still bulk data
    out = cli_run("export", tmp_path / "map.h5", "--format", "ross", "--case", "5", "-o", tmp_path / "k.json")
    assert out.returncode == 0, out.stderr
    ross = json.loads((tmp_path / "k.json").read_text())
    assert ross["source"] == str(tmp_path / "map.h5") and ross["case"].startswith("case 5 of map.h5 (--case): Fx = 1500 N")
    assert set(ross) - set(ROSS_NOTES) == {"n", "kxx", "kxy", "kyx", "kyy", "kzz", "cxx"}
    # a solve's CSV has its load and speed
    solve = cli_run("solve", "--bearing", "6205", "--load", "1000,0,200,0,0", "--speed", "1800", "--json")
    (tmp_path / "s.json").write_text(solve.stdout)
    assert cli_run("export", tmp_path / "s.json", "--format", "csv", "-o", tmp_path / "s.csv").returncode == 0
    with open(tmp_path / "s.csv") as fh:
        row = next(csv.DictReader(fh))
    got = (float(row["Fx_N"]), float(row["Fz_N"]), float(row["speed_rpm"]))
    assert np.allclose(got, (1000.0, 200.0, 1800.0), rtol=1e-9)  # f: the load the solve carries
    assert cli_run("export", tmp_path / "s.json", "--format", "dmig", "-o", tmp_path / "s.bdf").returncode == 0
    assert "solve --json): Fx = 1000 N" in " ".join(
        line[2:] for line in (tmp_path / "s.bdf").read_text().splitlines() if line.startswith("$ "))


# -- item 4: ROSS over speed --------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def speed_map(tmp_path_factory):
    folder = tmp_path_factory.mktemp("speed")
    (folder / "s.toml").write_text('bearing = "7014C-DB"\n[loadmap]\ngiven = "load"\n'
                                   'speed = { start = 0.0, stop = 24000.0, num = 4 }\nFx = [500.0, 1000.0]\n'
                                   'Fy = 0.0\nFz = { start = 0.0, stop = 1000.0, num = 3 }\nMx = 0.0\nMy = 0.0\n')
    out = cli_run("loadmap", folder / "s.toml", "-o", folder / "s.h5")
    assert out.returncode == 0, out.stderr
    return folder / "s.h5"


def test_ross_over_speed_is_the_frequency_dependent_bearing_element(speed_map, tmp_path):
    import math

    import fastbearing as fb
    from fastbearing.report.export import ROSS_NOTES

    out = cli_run("export", speed_map, "--format", "ross", "--over", "speed", "--at", "Fx=1000,Fz=500",
                  "-o", tmp_path / "b.json")
    assert out.returncode == 0, out.stderr
    assert "at 0 rpm (of 4 speeds)" in out.stderr  # the tilt stiffness is largest at rest here
    args = json.loads((tmp_path / "b.json").read_text())
    np.testing.assert_allclose(args["frequency"], np.array([0.0, 8000.0, 16000.0, 24000.0]) * 2 * math.pi / 60)
    ds = fb.open_dataset(speed_map)
    K = ds["K"].sel(Fx=1000.0, Fz=500.0).values  # (speed, 5, 5), N/mm
    for name, (i, j) in zip(("kxx", "kxy", "kyx", "kyy", "kzz"), ((0, 0), (0, 1), (1, 0), (1, 1), (2, 2))):
        np.testing.assert_array_equal(args[name], K[:, i, j] * 1e3)
    assert args["cxx"] == [0.0] * 4 and len(args["dropped"]) == 4 and args["n"] == 0
    assert set(args) - set(ROSS_NOTES) == {"n", "kxx", "kxy", "kyx", "kyy", "kzz", "cxx", "frequency"}
    assert "Kb over speed (0 to 24000, 4 values) at Fx=1000, Fz=500" in args["case"]
    # the same --over for json and npz, along any axis
    assert cli_run("export", speed_map, "--format", "json", "--over", "Fz", "--at", "speed=8000,Fx=500",
                   "-o", tmp_path / "fz.json").returncode == 0
    body = json.loads((tmp_path / "fz.json").read_text())
    assert np.array(body["K"]).shape == (3, 5, 5) and body["cases"]["Fz"]["values"] == [0.0, 500.0, 1000.0]
    np.testing.assert_array_equal(body["K"], ds["K"].sel(speed=8000.0, Fx=500.0).values)
    assert cli_run("export", speed_map, "--format", "npz", "--over", "speed", "--at", "Fx=500,Fz=0",
                   "-o", tmp_path / "s.npz").returncode == 0
    with np.load(tmp_path / "s.npz") as z:
        assert z["K"].shape == (4, 5, 5) and list(z["speed"]) == [0.0, 8000.0, 16000.0, 24000.0]
    # refused: what cannot be
    for extra, words in ((["--format", "ross", "--over", "Fz", "--at", "speed=0,Fx=500"], "--over speed"),
                         (["--format", "dmig", "--over", "speed", "--at", "Fx=500,Fz=0"], "DMIG matrix holds one"),
                         (["--format", "ross", "--over", "speed", "--at", "Fx=500"], "missing: Fz"),
                         (["--format", "json", "--over", "rpm", "--at", "Fx=500,Fz=0"], "one of this file's axes"),
                         (["--format", "ross", "--over", "speed", "--at", "Fx=500,Fz=0,speed=0"], "name only the other")):
        bad = cli_run("export", speed_map, *extra, "-o", tmp_path / "x.json")
        assert bad.returncode == 2 and words in bad.stderr, (extra, bad.stderr)
        assert not (tmp_path / "x.json").exists()


def test_the_docs_ross_rotor_runs_when_ross_is_installed(speed_map, tmp_path, monkeypatch):
    """docs/shafts-and-export.md's ROSS block (skipped by the docs runner): a rotor on two bearings over speed
    and its Campbell diagram, where ROSS is importable."""
    pytest.importorskip("ross", reason="ROSS (pip install ross-rotordynamics) is not installed here")
    import re
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "docs" / "shafts-and-export.md").read_text()
    block = re.search(r"needs ROSS; tests/test_issue48_cli\.py.*?```python\n(.*?)```", text, re.S).group(1)
    monkeypatch.chdir(tmp_path)
    out = cli_run("export", speed_map, "--format", "ross", "--over", "speed", "--at", "Fx=500,Fz=1000",
                  "-o", "spindle-bearing.json")
    assert out.returncode == 0, out.stderr
    namespace = {}
    exec(compile(block.replace("campbell.plot()", "figure = campbell.plot()"), "shafts-and-export.md", "exec"),
         namespace)
    assert namespace["campbell"] is not None


def test_a_defect_table_takes_the_same_geometry_diameters_and_refuses_others(tmp_path):
    """The table over shaft revolutions places its defects with the kinematics the time axis uses (one
    function, jobs/passage._element_kinematics): the geometry's diameters, a differing one refused."""
    import pytest

    import fastbearing as fb
    from fastbearing.jobs.passage import read_config

    base = ('bearing = "6205"\n[passage]\npoints = [[0.01, 0.0, 0.0, 0.0, 0.0]]\nrevolutions = 2\n'
            'positions = 36\n')
    g = fb.load_bearing("6205").geometry
    cfg = read_config(_write(tmp_path / "a.toml", base))
    assert (cfg.kinematics.ball_diameter, cfg.kinematics.pitch_diameter) == (g.ball_diameter, g.pitch_diameter)
    with pytest.raises(ValueError, match=r"passage\.ball_diameter.*differs from \[bearing\.geometry\]"):
        read_config(_write(tmp_path / "b.toml", base + "ball_diameter = 9.0\n"))


def _write(path, text):
    path.write_text(text)
    return path
