"""[bearing.mounting] wired into the package (issue 44 items 2, 4 and 8): parsing and refusals, the operating
bearing used by solve / stiffness / solve_many / life / the CLI, and the clearance budget of the report."""

import json
from pathlib import Path

import numpy as np
import pytest

import fastbearing as fb
from fastbearing.model.bearing_file import bearing_from_table, read_toml
from fastbearing.model.mounted import operating_bearing

from conftest import cli_run

ROOT = Path(__file__).resolve().parents[1]
BEARINGS = sorted((ROOT / "fastbearing" / "catalogue").glob("*.toml"))

GEOMETRY_6205 = {"n_balls": 9, "ball_diameter": 7.938, "pitch_diameter": 38.5, "inner_groove_ratio": 0.52,
                 "outer_groove_ratio": 0.53, "diametral_clearance": "CN", "bore": 25.0, "outer_diameter": 52.0,
                 "width": 15.0}
MOUNTING_6205 = {"shaft_fit": "k5", "housing_fit": "H7", "inner_ring_temperature": 50.0,
                 "outer_ring_temperature": 40.0}
TOML_6205 = """[bearing]
name = "6205 on k5"
arrangement = "single"
[bearing.geometry]
n_balls = 9
ball_diameter = 7.938
pitch_diameter = 38.5
inner_groove_ratio = 0.52
outer_groove_ratio = 0.53
diametral_clearance = "CN"
bore = 25.0
outer_diameter = 52.0
width = 15.0
[bearing.mounting]
shaft_fit = "k5"
housing_fit = "H7"
inner_ring_temperature = 50.0
outer_ring_temperature = 40.0
"""


def bearing_6205(geometry=None, mounting=None, **top):
    table = {"name": "6205", "geometry": {**GEOMETRY_6205, **(geometry or {})}, **top}
    if mounting is not False:
        table["mounting"] = {**MOUNTING_6205, **(mounting or {})}
    return bearing_from_table(table)


def bearing_7014(arrangement, mounting):
    table = read_toml(ROOT / "fastbearing/catalogue/7014C-DB.toml")["bearing"]
    return bearing_from_table({**table, "arrangement": arrangement, "mounting": mounting})


def unmounted_twin(bearing, budget):
    """The same bearing file with the reported operating clearance and preload typed as plain numbers."""
    doc = read_toml(ROOT / "fastbearing/catalogue/7014C-DB.toml")["bearing"] if bearing.name.startswith("7014") else None
    rows = budget["rows"]
    if doc is None:
        geometry = {**GEOMETRY_6205, "diametral_clearance": rows[0]["operating_diametral_clearance"]}
        return bearing_from_table({"name": "6205", "geometry": geometry})
    doc = {**doc, "arrangement": bearing.arrangement,
           "axial_preload": [r["operating_axial_preload"] for r in rows],
           "geometry": {**doc["geometry"], "diametral_clearance": rows[0]["operating_diametral_clearance"]}}
    return bearing_from_table(doc)


# -- no mounting: today's behaviour, bit for bit --------------------------------------------------
@pytest.mark.parametrize("path", BEARINGS, ids=lambda p: p.name)
def test_shipped_bearings_have_no_mounting_and_solve_as_before(path):
    bearing = fb.load_bearing(path)
    assert bearing.mounting is None
    assert operating_bearing(bearing, 1000.0) == (bearing, None)
    rep = fb.bearing_report(bearing)
    assert "mounting" not in rep


# -- the mounted bearing solves exactly as the unmounted one with the reported values ----------
def test_mounted_6205_solves_bit_for_bit_as_its_operating_twin():
    bearing = bearing_6205()
    op, budget = operating_bearing(bearing, 0.0)
    twin = unmounted_twin(bearing, budget)
    assert twin.rows == op.rows
    load = [2000.0, 0.0, 100.0, 0.0, 0.0]
    a, b = fb.solve(bearing, load), fb.solve(twin, load)
    assert np.array_equal(a.q, b.q) and np.array_equal(a.K, b.K) and a.status == b.status
    fa, Ka = fb.stiffness(bearing, a.q)
    fb_, Kb = fb.stiffness(twin, a.q)
    assert np.array_equal(Ka, Kb) and np.array_equal(fa, fb_)
    many_a = fb.solve_many(bearing, [load, [1000.0, 0, 0, 0, 0]], speed=0.0)
    many_b = fb.solve_many(twin, [load, [1000.0, 0, 0, 0, 0]], speed=0.0)
    assert np.array_equal(many_a.K, many_b.K)


def test_mounted_pair_at_speed_solves_as_its_operating_twin():
    mounting = {"shaft_interference": 0.004, "housing_interference": -0.005, "inner_ring_temperature": 35.0,
                "outer_ring_temperature": 30.0, "shaft_temperature": 38.0}
    bearing = bearing_7014("DB", mounting)
    op, budget = operating_bearing(bearing, 6000.0)
    twin = unmounted_twin(bearing, budget)
    assert twin.rows == op.rows
    load = [1000.0, 0.0, 500.0, 0.0, 0.0]
    a, b = fb.solve(bearing, load, speed=6000.0), fb.solve(twin, load, speed=6000.0)
    assert np.array_equal(a.q, b.q) and np.array_equal(a.K, b.K)
    # the budget's clearance is the engine's rL = Pd_op / 2 in every row
    assert all(r.radial_clearance == 0.5 * budget["rows"][0]["operating_diametral_clearance"] for r in op.rows)


def test_stiffness_many_refuses_several_speeds_on_a_mounted_bearing():
    bearing = bearing_6205()  # solve_many and load maps take each case's own (tests/test_operating_cases.py)
    with pytest.raises(ValueError, match="several speeds on a bearing with \\[bearing.mounting\\] are not "
                                         "supported here.*use solve_many or a load map"):
        fb.stiffness_many(bearing, [[0.01, 0, 0, 0, 0]] * 2, speed=[0.0, 3000.0])


# -- clearance groups and ranges ---------------------------------------------------------------
def test_clearance_group_solves_its_mean_and_reports_its_range():
    bearing = bearing_6205(mounting=False)
    assert bearing.geometry.diametral_clearance == pytest.approx(0.0125)  # CN over 24 incl. 30 mm: 5-20 um
    rep = fb.bearing_report(bearing)
    assert rep["mounting"]["rows"][0]["unmounted_diametral_clearance_range"] == [0.005, 0.02]
    ranged = bearing_6205({"diametral_clearance": [0.006, 0.014]}, mounting=False)
    assert ranged.rows[0].radial_clearance == pytest.approx(0.005)
    plain = bearing_6205({"diametral_clearance": 0.0125}, mounting=False)
    r = fb.solve(bearing, [1000.0, 0, 0, 0, 0])
    assert np.array_equal(r.K, fb.solve(plain, [1000.0, 0, 0, 0, 0]).K)


@pytest.mark.parametrize("geometry, mounting, top, message", [
    ({"diametral_clearance": "C7"}, None, {}, "bearing.geometry.diametral_clearance must be an ISO 5753-1"),
    ({"diametral_clearance": "C3", "contact_angle": 15.0}, None, {},
     "bearing.geometry.diametral_clearance may be an ISO 5753-1 group only for a deep-groove ball bearing"),
    ({"diametral_clearance": [0.02, 0.01]}, None, {}, "min <= max"),
    (None, {"shaft_fit": "k9"}, {}, "bearing.mounting.shaft_fit must be an ISO 286 shaft class"),
    (None, {"shaft_fit": "H7"}, {}, "is a housing class"),
    (None, {"colour": "red"}, {}, "bearing.mounting has unknown key"),
    (None, {"shaft_bore": 25.0}, {}, "bearing.mounting.shaft_bore must be < the bore d = 25 mm"),
    (None, {"housing_outer_diameter": 50.0}, {}, "bearing.mounting.housing_outer_diameter must be > the ring's "
     "outer diameter D = 52 mm"),
    (None, {"housing_temperature": -300.0}, {}, "bearing.mounting.housing_temperature must be >= -273.15"),
    (None, {"shaft_material": "wood"}, {}, "bearing.mounting.shaft_material must be one of"),
    (None, {"shaft_fit": "k5", "shaft_interference": 0.01}, {}, "are alternatives"),
    ({"bore": None}, None, {}, "bearing.geometry.diametral_clearance as an ISO 5753-1 group needs "
     "bearing.geometry.bore"),
    ({"bore": None, "diametral_clearance": 0.01}, None, {}, "bearing.mounting needs the boundary dimensions"),
])
def test_bad_mounting_input_is_one_line_naming_the_field(geometry, mounting, top, message):
    geometry = dict(geometry or {})
    table = {"name": "6205", "geometry": {**GEOMETRY_6205, **geometry}, "mounting": {**MOUNTING_6205,
                                                                                      **(mounting or {})}}
    table["geometry"] = {k: v for k, v in table["geometry"].items() if v is not None}
    if "shaft_interference" in (mounting or {}):
        table["mounting"]["shaft_fit"] = "k5"
    with pytest.raises(ValueError, match=message) as info:
        bearing_from_table(table)
    assert "\n" not in str(info.value)


def test_a_fit_size_outside_the_tables_names_the_field():
    table = {"name": "big", "geometry": {**GEOMETRY_6205, "diametral_clearance": 0.01, "n_balls": 12,
                                         "ball_diameter": 60.0, "pitch_diameter": 600.0, "bore": 520.0,
                                         "outer_diameter": 680.0}, "mounting": {"shaft_fit": "k5"}}
    with pytest.raises(ValueError, match=r"bearing.geometry.bore must be in \(3, 500\] mm \(ISO 286 table range\)"):
        bearing_from_table(table)


def test_mounting_without_geometry_is_refused():
    with pytest.raises(ValueError, match="bearing.mounting needs \\[bearing.geometry\\]"):
        bearing_from_table({**fb.model.bearing.preset_table("gunduz2013"), "mounting": {}})


def test_an_operating_preload_beyond_the_model_is_a_clear_error():
    table = {"name": "6205", "geometry": {**GEOMETRY_6205, "diametral_clearance": 0.0},
             "mounting": {"shaft_interference": 0.3}}
    bearing = bearing_from_table(table)
    with pytest.raises(ValueError, match="bearing.mounting gives an operating bearing outside the model's range"), \
            pytest.warns(UserWarning, match="hoop stress"):
        operating_bearing(bearing, 0.0)


# -- pairs: a warmer shaft lowers a DB pair's preload and raises a DF pair's --------------------
def test_warmer_shaft_lowers_db_preload_and_raises_df_preload():
    # a loose shaft seat: no radial fit effect, only the axial growth between the rows
    mounting = {"shaft_interference": -0.05, "shaft_temperature": 40.0}
    preload = {}
    for arrangement in ("DB", "DF"):
        cold = bearing_7014(arrangement, {"shaft_interference": -0.05})
        warm = bearing_7014(arrangement, mounting)
        Q_cold, _ = fb.ball_loads(cold, np.zeros(5))
        Q_warm, _ = fb.ball_loads(warm, np.zeros(5))
        preload[arrangement] = (Q_cold.sum(), Q_warm.sum())
        _, budget = operating_bearing(warm, 0.0)
        change = budget["rows"][0]["operating_axial_preload"] - budget["rows"][0]["unmounted_axial_preload"]
        # d0 changes by -/+ (eps_i - eps_o) e = 12.5e-6 * 20 K * 10 mm
        assert change == pytest.approx(-2.5e-3 if arrangement == "DB" else 2.5e-3)
    assert preload["DB"][1] < preload["DB"][0]
    assert preload["DF"][1] > preload["DF"][0]


# -- the command line ------------------------------------------------------------------------------
def test_cli_solve_says_the_operating_clearance(tmp_path):
    path = tmp_path / "6205-k5.toml"
    path.write_text(TOML_6205)
    run = cli_run("solve", "--bearing", path, "--load", "2000,0,0,0,0", "--speed", "3000")
    assert run.returncode == 0, run.stderr
    first = run.stdout.splitlines()[0]
    assert first.startswith("operating clearance ") and "um (unmounted 12.5 um) at 3000 rpm" in first
    js = cli_run("solve", "--bearing", path, "--load", "2000,0,0,0,0", "--json")
    doc = json.loads(js.stdout)
    op, budget = operating_bearing(fb.load_bearing(path), 0.0)
    assert doc["operating"]["operating_diametral_clearance"] == [budget["rows"][0]["operating_diametral_clearance"]]
    assert doc["operating"]["unmounted_diametral_clearance"] == [0.0125]
    assert np.array_equal(doc["K"], fb.solve(op, [2000.0, 0, 0, 0, 0]).K.tolist())


def test_cli_solve_of_an_unmounted_bearing_prints_no_mounting_line():
    run = cli_run("solve", "--bearing", ROOT / "fastbearing/catalogue/6205.toml", "--load", "1000,0,0,0,0")
    assert run.returncode == 0 and "operating clearance" not in run.stdout
    js = json.loads(cli_run("solve", "--bearing", ROOT / "fastbearing/catalogue/6205.toml", "--load", "1000,0,0,0,0",
                            "--json").stdout)
    assert "operating" not in js


def test_cli_life_uses_the_operating_bearing(tmp_path):
    path = tmp_path / "6205-k5.toml"
    path.write_text(TOML_6205)
    run = cli_run("solve", "--bearing", path, "--load", "2000,0,0,0,0", "--life", "--json")
    assert run.returncode == 0, run.stderr
    life = json.loads(run.stdout)["life"]
    op, _ = operating_bearing(fb.load_bearing(path), 0.0)
    r = fb.solve(op, [2000.0, 0, 0, 0, 0])
    from fastbearing.analysis.life import life as life_of
    assert life["L10r"] == life_of(op, [2000.0, 0, 0, 0, 0], r.q).L10r


def test_bearing_report_budget_keys(tmp_path):
    path = tmp_path / "6205-k5.toml"
    path.write_text(TOML_6205)
    run = cli_run("bearing", path, "--json", "--speed", "3000")
    assert run.returncode == 0, run.stderr
    mounting = json.loads(run.stdout)["mounting"]
    row = mounting["rows"][0]
    for key in ("unmounted_diametral_clearance", "unmounted_diametral_clearance_range",
                "mounted_diametral_clearance", "operating_diametral_clearance", "operating_axial_preload",
                "shaft_interference", "housing_interference", "shaft_interference_range", "shaft_fit_pressure",
                "housing_fit_pressure", "inner_raceway_growth", "outer_raceway_contraction"):
        assert key in row, key
    assert row["shaft_interference_range"] == [0.002, 0.021]  # k5 on a 25 mm bore (issue 44 item 7)
    assert set(mounting["materials"]) == {"shaft", "inner_ring", "outer_ring", "balls", "housing"}
    for material in mounting["materials"].values():
        assert set(material) == {"name", "youngs_modulus", "poisson_ratio", "density", "thermal_expansion"}
    assert mounting["speed"] == 3000.0
    text = cli_run("bearing", path)
    assert "mounting: operating clearance" in text.stdout and "fits: shaft k5, housing H7" in text.stdout


def test_hoop_stress_warning_is_one_cli_line(tmp_path):
    path = tmp_path / "tight.toml"
    path.write_text(TOML_6205.replace('shaft_fit = "k5"', "shaft_interference = 0.06").replace(
        'diametral_clearance = "CN"', "diametral_clearance = 0.02"))
    run = cli_run("bearing", path)
    warnings = [line for line in run.stderr.splitlines() if "hoop stress" in line]
    assert len(warnings) == 1 and warnings[0].startswith("fastbearing: warning: ")


# -- load maps and passage tables: one speed, the operating bearing -------------------------------
MAP = """
[loadmap]
given = "load"
Fx = { start = 500.0, stop = 2000.0, num = 3 }
Fz = [0.0, 100.0]
"""


def test_loadmap_of_a_mounted_bearing_runs_its_operating_bearing(tmp_path):
    import h5py

    path = tmp_path / "map.toml"
    path.write_text(TOML_6205 + MAP + "speed = 3000.0\n")
    out = fb.loadmap(path, tmp_path / "map.h5", progress=False)
    op, budget = operating_bearing(bearing_6205(), 3000.0)
    with h5py.File(out, "r") as fh:
        assert list(fh.attrs["operating_diametral_clearance_mm"]) == [budget["rows"][0]["operating_diametral_clearance"]]
        assert fh.attrs["operating_speed_rpm"] == 3000.0
        K = fh["K"][()]
    r = fb.solve(op, [2000.0, 0, 100.0, 0, 0], speed=3000.0)
    assert np.allclose(K[-1, -1], r.K, rtol=1e-9, atol=1e-6)




def test_passage_table_of_a_mounted_bearing_records_its_operating_clearance(tmp_path):
    import h5py

    path = tmp_path / "p.toml"
    path.write_text(TOML_6205 + '[passage]\ngiven = "displacement"\npoints = [[0.02, 0.0, 0.0, 0.0, 0.0]]\n')
    out = fb.passage(path, tmp_path / "p.h5")
    _, budget = operating_bearing(bearing_6205(), 0.0)
    with h5py.File(out, "r") as fh:
        assert fh.attrs["operating_note"] == budget["line"]
        assert list(fh.attrs["operating_diametral_clearance_mm"]) == [budget["rows"][0]["operating_diametral_clearance"]]


def test_a_shaft_carries_a_mounted_bearing_at_its_operating_clearance(tmp_path):
    from fastbearing.analysis import shaft as sh

    (tmp_path / "row.toml").write_text(TOML_6205)
    (tmp_path / "plain.toml").write_text(TOML_6205.split("[bearing.mounting]")[0])
    op, budget = operating_bearing(bearing_6205(), 0.0)
    (tmp_path / "twin.toml").write_text(TOML_6205.split("[bearing.mounting]")[0].replace(
        'diametral_clearance = "CN"', f'diametral_clearance = {budget["rows"][0]["operating_diametral_clearance"]!r}'))
    K = {}
    for name in ("row", "twin", "plain"):
        path = tmp_path / f"shaft-{name}.toml"
        path.write_text('[shaft]\nreference = 0.0\n'
                        f'[[shaft.bearings]]\nposition = -40.0\nbearing = "{name}.toml"\n'
                        f'[[shaft.bearings]]\nposition = 40.0\nbearing = "{name}.toml"\n'
                        '[[shaft.loads]]\nposition = 0.0\nforce = [2000.0, 0.0, 0.0]\n')
        K[name] = sh.solve_shaft(sh.read_shaft(path)).K_system
    assert np.array_equal(K["row"], K["twin"])
    assert not np.array_equal(K["row"], K["plain"])


def test_tapered_pair_preload_follows_the_shaft_temperature():
    table = read_toml(ROOT / "fastbearing/catalogue/30206-TDO.toml")["bearing"]
    cold = bearing_from_table({**table, "mounting": {"shaft_interference": -0.05}})
    warm = bearing_from_table({**table, "mounting": {"shaft_interference": -0.05, "shaft_temperature": 40.0}})
    d_cold = [r.axial_preload for r in operating_bearing(cold, 0.0)[0].rows]
    d_warm = [r.axial_preload for r in operating_bearing(warm, 0.0)[0].rows]
    assert all(w < c for w, c in zip(d_warm, d_cold))  # TDO is back to back: a warmer shaft unloads it


def test_rows_changed_after_loading_are_refused_not_ignored():
    bearing = bearing_6205().with_rows(radial_clearance=0.002)
    with pytest.raises(ValueError, match="bearing.mounting needs every row's radial_clearance"):
        fb.solve(bearing, [1000.0, 0, 0, 0, 0])
