"""Bearing fault frequencies (issue 37): the closed forms of rolling without slip, the published table of the
Case Western Reserve University bearing data set against the shipped 6205 and 6203 files, `fastbearing bearing
FILE --speed RPM [--load ...]` (text and JSON), the loaded contact angle, and the marks on the spectrum plot.
Units: mm, N, N*mm, degrees (angles users type), rpm, Hz; orders are multiples of the shaft frequency."""

import json
import math
import shutil
from pathlib import Path

import numpy as np
import pytest

import fastbearing as fb
from conftest import cli_run
from fastbearing.analysis.contacts import ball_contacts
from fastbearing.analysis.faults import NAMES, fault_frequencies, fault_orders
from fastbearing.report.bearing_report import fault_frequency_report, fault_frequency_text

BEARINGS = Path(__file__).resolve().parents[1] / "fastbearing" / "catalogue"


def closed_form(D, dm, Z, a_deg, rotating):
    """The textbook formulas, written out again, as orders (Harris & Kotzalas, Essential Concepts of Bearing
    Technology, ch. 7; Randall & Antoni, MSSP 25 (2011) 485). With ring speeds f_i, f_o the cage turns at
    f_c = f_i/2 (1 - g) + f_o/2 (1 + g); a ball passes a point of a race Z |f_c - f_race| times a second, a
    ball spins at dm/(2 D) |f_i - f_o| (1 - g^2). One ring turning at f_r, the other held: the ball-pass
    and spin frequencies depend only on the rings' relative speed, the cage's (FTF, in the fixed frame) on
    which ring turns."""
    g = D / dm * math.cos(math.radians(a_deg))
    fi, fo = (1.0, 0.0) if rotating == "inner" else (0.0, 1.0)
    fc = fi / 2 * (1 - g) + fo / 2 * (1 + g)
    bsf = dm / (2 * D) * abs(fi - fo) * (1 - g * g)
    return {"FTF": fc, "BPFO": Z * abs(fc - fo), "BPFI": Z * abs(fi - fc), "BSF": bsf, "ball_defect": 2 * bsf}


GEOMETRIES = [(7.94, 39.04, 9, 0.0), (11.112, 90.0, 19, 15.0), (12.7, 70.0, 15, 35.0), (25.4, 300.0, 30, 40.0),
              (3.0, 8.0, 6, 0.0)]


# -- closed forms -------------------------------------------------------------------------------------------
@pytest.mark.parametrize("rotating", ["inner", "outer"])
@pytest.mark.parametrize("D, dm, Z, a", GEOMETRIES)
def test_cage_and_spin_orders_and_frequencies_follow_the_closed_forms(D, dm, Z, a, rotating):
    want = closed_form(D, dm, Z, a, rotating)
    got = fault_orders(D, dm, Z, a, rotating)
    assert set(got) == set(NAMES) == set(want)
    for name in ("FTF", "BSF", "ball_defect"):
        assert got[name] == pytest.approx(want[name], rel=1e-13), name
    assert got["ball_defect"] == 2 * got["BSF"]
    rpm = 1797.0
    hz = fault_frequencies(D, dm, Z, rpm, a, rotating)
    for name in NAMES:
        assert hz[name]["order"] == got[name]
        assert hz[name]["hz"] == pytest.approx(got[name] * rpm / 60.0, rel=1e-14)


@pytest.mark.parametrize("rotating", ["inner", "outer"])
@pytest.mark.parametrize("D, dm, Z, a", GEOMETRIES)
def test_ball_pass_orders_follow_the_closed_forms(D, dm, Z, a, rotating):
    want = closed_form(D, dm, Z, a, rotating)
    got = fault_orders(D, dm, Z, a, rotating)
    for name in ("BPFO", "BPFI"):
        assert got[name] == pytest.approx(want[name], rel=1e-13), name
    # BPFO + BPFI = Z; the balls pass a point of the fixed ring's race Z times a cage turn
    assert got["BPFO"] + got["BPFI"] == pytest.approx(Z, rel=1e-13)
    fixed = "BPFO" if rotating == "inner" else "BPFI"
    assert got[fixed] == pytest.approx(Z * got["FTF"], rel=1e-13)


def test_the_turning_ring_changes_the_cage_frequency():
    inner, outer = fault_orders(10.0, 50.0, 10, 20.0, "inner"), fault_orders(10.0, 50.0, 10, 20.0, "outer")
    assert outer["FTF"] - inner["FTF"] == pytest.approx(10 / 50 * math.cos(math.radians(20.0)), rel=1e-13)
    assert outer["BSF"] == inner["BSF"] and outer["ball_defect"] == inner["ball_defect"]


def test_the_turning_ring_leaves_the_ball_pass_frequencies():
    """The ball-pass frequencies depend on the rings' relative speed only (a defect on a turning outer race
    meets the balls Z (f_r - f_c) = Z f_r/2 (1 - gamma) times a second)."""
    inner, outer = fault_orders(10.0, 50.0, 10, 20.0, "inner"), fault_orders(10.0, 50.0, 10, 20.0, "outer")
    assert outer["BPFO"] == pytest.approx(inner["BPFO"]) and outer["BPFI"] == pytest.approx(inner["BPFI"])


# -- the shipped CWRU bearings against the data set's published table ---------------------------------------
# The Case Western Reserve University Bearing Data Center publishes, on its bearing specification page
# ("Bearing information"), the geometry (in inches) and the defect frequencies as multiples of the running
# speed of the drive-end 6205-2RS JEM SKF and the fan-end 6203-2RS JEM SKF. Its "ball spin" (BSF) column is
# dm/D (1 - gamma^2): a point of a ball meeting both races, fastbearing's ball_defect = 2 BSF.
CWRU = {"6205": {"BPFI": 5.4152, "BPFO": 3.5848, "FTF": 0.39828, "ball_defect": 4.7135},
        "6203": {"BPFI": 4.9469, "BPFO": 3.0530, "FTF": 0.3817, "ball_defect": 3.9874}}


@pytest.mark.parametrize("name", sorted(CWRU))
def test_shipped_cwru_bearings_give_the_published_fault_orders(name):
    bearing = fb.load_bearing(BEARINGS / f"{name}.toml")
    rep = fault_frequency_report(bearing, 1797.0)  # the data set's 0 hp speed
    assert rep["rotating"] == "inner" and rep["contact_angle_source"] == "nominal"
    assert rep["contact_angle_deg"] == 0.0 and rep["shaft_frequency_hz"] == pytest.approx(29.95)
    for key, published in CWRU[name].items():
        got = rep["fault_frequencies"][key]
        assert got["order"] == pytest.approx(published, rel=1e-3), key
        assert got["hz"] == pytest.approx(got["order"] * 1797.0 / 60.0, rel=1e-14)


@pytest.mark.parametrize("name, dims, Z, C, C0", [("6205", (7.94004, 39.0398), 9, 14800.0, 7800.0),
                                                  ("6203", (6.74624, 28.4988), 8, 9950.0, 4750.0)])
def test_shipped_cwru_files_hold_the_published_values_and_solve(name, dims, Z, C, C0):
    bearing = fb.load_bearing(BEARINGS / f"{name}.toml")
    g = bearing.geometry
    assert bearing.name == name and bearing.arrangement == "single"
    assert (g.ball_diameter, g.pitch_diameter, g.n_balls, g.contact_angle) == (*dims, Z, 0.0)
    assert g.ball_diameter == pytest.approx({"6205": 0.3126, "6203": 0.2656}[name] * 25.4, rel=1e-12)
    assert g.pitch_diameter == pytest.approx({"6205": 1.537, "6203": 1.122}[name] * 25.4, rel=1e-12)
    assert (g.dynamic_load_rating, g.static_load_rating, g.rotating) == (C, C0, "inner")
    r = fb.solve(bearing, [1000.0, 0, 0, 0, 0])
    assert r.converged and r.q[0] > 0 and r.f[0] == pytest.approx(1000.0)


# -- the report and the loaded contact angle ----------------------------------------------------------------
def test_a_loaded_angular_contact_bearing_runs_at_its_loaded_angle():
    """7014C-DB (15 deg, preloaded pair) under 3000 N axial: the loaded row's balls turn to about 19 deg, which
    moves every frequency (the cage and BPFO up, BPFI down for the inner ring turning); the orders still
    follow the closed forms at the loaded angle."""
    bearing = fb.load_bearing(BEARINGS / "7014C-DB.toml")
    load = [0.0, 0.0, 3000.0, 0.0, 0.0]
    nominal = fault_frequency_report(bearing, 12000.0)
    loaded = fault_frequency_report(bearing, 12000.0, load)
    assert nominal["contact_angle_deg"] == 15.0 and loaded["contact_angle_source"] == "loaded"
    c = ball_contacts(bearing, fb.solve(bearing, load).q)
    on = c.load > 0
    assert loaded["loaded_contacts"] == on.sum() == 19  # one row takes the axial load
    assert loaded["contact_angle_deg"] == pytest.approx(math.degrees(np.abs(c.contact_angle[on]).mean()), rel=1e-12)
    assert 17.0 < loaded["contact_angle_deg"] < 22.0
    g = bearing.geometry
    for name in NAMES:
        assert loaded["fault_frequencies"][name]["order"] != pytest.approx(nominal["fault_frequencies"][name]["order"],
                                                                           rel=1e-4), name
        want = closed_form(g.ball_diameter, g.pitch_diameter, g.n_balls, loaded["contact_angle_deg"], "inner")[name]
        assert loaded["fault_frequencies"][name]["order"] == pytest.approx(want, rel=1e-12), name
    assert loaded["fault_frequencies"]["FTF"]["hz"] > nominal["fault_frequencies"]["FTF"]["hz"]
    assert loaded["fault_frequencies"]["BPFI"]["hz"] < nominal["fault_frequencies"]["BPFI"]["hz"]
    text = fault_frequency_text(loaded)
    assert "loaded contact angle 19.27 deg (mean of 19 loaded ball contacts" in text


def test_a_deep_groove_bearing_under_radial_load_stays_at_zero_degrees_and_a_roller_bearing_reports_too():
    rep = fault_frequency_report(fb.load_bearing(BEARINGS / "6205.toml"), 1797.0, [2000.0, 0, 0, 0, 0])
    assert rep["contact_angle_deg"] == pytest.approx(0.0, abs=1e-9) and rep["loaded_contacts"] >= 3
    assert rep["fault_frequencies"]["BPFI"]["order"] == pytest.approx(CWRU["6205"]["BPFI"], rel=1e-3)
    nu = fb.load_bearing(BEARINGS / "NU205.toml")  # rollers: D is the roller diameter
    rep = fault_frequency_report(nu, 1500.0)
    g = nu.geometry
    assert rep["element"] == "roller" and rep["fault_frequencies"]["BPFO"]["order"] == pytest.approx(
        closed_form(g.roller_diameter, g.pitch_diameter, g.n_rollers, 0.0, "inner")["BPFO"], rel=1e-13)


def test_the_report_refuses_what_it_cannot_use():
    b = fb.load_bearing(BEARINGS / "6205.toml")
    for bad in (0.0, -100.0, math.nan, math.inf, "1797", True):
        with pytest.raises(ValueError, match=r"^speed must be"):
            fault_frequency_report(b, bad)
    with pytest.raises(ValueError, match=r"has no \[bearing.geometry\] table: fault frequencies need its ball "
                                         r"diameter, pitch diameter \(mm\)"):
        fault_frequency_report(fb.load_bearing(BEARINGS / "gunduz2013.toml"), 1000.0)
    with pytest.raises(ValueError, match="no ball carries load there"):
        fault_frequency_report(b, 1000.0, [0.0] * 5)
    with pytest.raises(ValueError, match="^load"):
        fault_frequency_report(b, 1000.0, [1.0, 2.0])


# -- the command line -----------------------------------------------------------------------------------------
def test_cli_prints_the_fault_frequencies_after_the_report():
    plain = cli_run("bearing", BEARINGS / "6205.toml")
    r = cli_run("bearing", BEARINGS / "6205.toml", "--speed", "1797")
    assert plain.returncode == r.returncode == 0 and r.stderr == ""
    assert r.stdout.startswith(plain.stdout.rstrip("\n"))  # the existing report, unchanged, first
    block = r.stdout[len(plain.stdout.rstrip("\n")):].strip().splitlines()
    assert block[0] == ("fault frequencies at 1797 rpm (shaft f_r = 29.95 Hz), inner ring rotating, nominal "
                        "contact angle 0 deg:")
    assert [line.split()[0] for line in block[1:]] == list(NAMES)
    rows = {line.split()[0]: line for line in block[1:]}
    assert "107.3640 Hz   3.58478 x f_r" in rows["BPFO"] and "162.1860 Hz   5.41522 x f_r" in rows["BPFI"]
    assert "ball defect (2 BSF)" in rows["ball_defect"] and " 4.71344 x f_r" in rows["ball_defect"]


def test_cli_json_has_the_fault_frequencies_by_name():
    r = cli_run("bearing", BEARINGS / "6203.toml", "--speed", "1797", "--json")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    assert set(out["fault_frequencies"]) == set(NAMES)
    for name, published in CWRU["6203"].items():
        v = out["fault_frequencies"][name]
        assert set(v) == {"hz", "order"} and v["order"] == pytest.approx(published, rel=1e-3)
    assert out["fault_frequency_conditions"] == {
        "speed_rpm": 1797.0, "shaft_frequency_hz": pytest.approx(29.95), "element": "ball", "rotating": "inner",
        "contact_angle_deg": 0.0, "contact_angle_source": "nominal", "load": None, "loaded_contacts": 0}
    assert "geometry" in out and "fault_frequencies" not in json.loads(cli_run("bearing", BEARINGS / "6203.toml",
                                                                                "--json").stdout)
    r = cli_run("bearing", BEARINGS / "7014C-DB.toml", "--speed", "12000", "--load", "0,0,3000,0,0", "--json")
    c = json.loads(r.stdout)["fault_frequency_conditions"]
    assert r.returncode == 0 and c["contact_angle_source"] == "loaded" and c["load"] == [0, 0, 3000, 0, 0]
    assert c["contact_angle_deg"] == pytest.approx(19.27, abs=0.01)


@pytest.mark.parametrize("args, words", [
    (["--speed", "0"], "--speed must be > 0 rpm, got 0.0"),
    (["--speed", "-5"], "--speed must be > 0 rpm"),
    (["--speed", "nan"], "--speed must be finite > 0 rpm"),
    (["--speed", "inf"], "--speed must be finite > 0 rpm"),
    (["--load", "1000,0,0,0,0"], "--load goes with --speed"),
    (["--speed", "1000", "--load", "1,2"], "--load needs 5 comma-separated numbers"),
    (["--speed", "1000", "--load", "0,0,0,0,0"], "--load (Fx, Fy, Fz = 0, 0, 0 N; Mx, My = 0, 0 N*mm): no ball "
                                                 "carries load there"),
])
def test_cli_bad_options_are_one_line(args, words):
    r = cli_run("bearing", BEARINGS / "6205.toml", *args)
    assert r.returncode == 2 and r.stdout == "" and words in r.stderr, r.stderr
    assert len(r.stderr.strip().splitlines()) == 1, r.stderr


def test_cli_bearing_without_geometry_says_what_is_missing():
    r = cli_run("bearing", BEARINGS / "gunduz2013.toml", "--speed", "1000")
    assert r.returncode == 2 and r.stdout == "" and len(r.stderr.strip().splitlines()) == 1
    assert "gunduz2013 has no [bearing.geometry] table: fault frequencies need its ball diameter, pitch diameter" \
        in r.stderr


# -- the spectrum plot ------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def passages(tmp_path_factory):
    """Two small passage tables of the paper's pair, with and without a shaft speed (Hz or harmonic axis), each
    also copied with fault-frequency attributes added (as the passage job will store them)."""
    pytest.importorskip("matplotlib")
    h5py = pytest.importorskip("h5py")
    d = tmp_path_factory.mktemp("faults")
    base = {"points": [[0.05, 0, 0, 0, 0]], "positions": 8, "harmonics": 4}
    ff = fault_frequencies(12.0, 70.0, 14, 3000.0, 30.0)
    out = {}
    for key, extra in (("hz", {"shaft_speed": 3000.0, "ball_diameter": 12.0, "pitch_diameter": 70.0}),
                       ("harmonic", {})):
        plain = fb.passage({"bearing": {"preset": "gunduz2013", "arrangement": "DB"},
                            "passage": {**base, **extra}}, d / f"{key}.h5", progress=False)
        marked = d / f"{key}-faults.h5"
        shutil.copy(plain, marked)
        with h5py.File(marked, "r+") as f:
            for name, v in ff.items():
                f.attrs[f"fault_frequency_{name}_hz"] = v["hz"]
                f.attrs[f"fault_frequency_{name}_order"] = v["order"]
        out[key], out[f"{key}-faults"] = plain, marked
    out["ff"] = ff
    return out


LABELS = ["FTF", "BSF", "ball defect", "BPFO", "BPFI"]  # by frequency for this bearing


def _marks(fig):
    ax = fig.axes[0]
    lines = [ln.get_xdata()[0] for ln in ax.get_lines() if ln.get_linestyle() == "--"]
    return [t.get_text() for t in ax.texts], lines


def test_spectrum_marks_the_fault_frequencies_in_hz(passages):
    from fastbearing.report import plot

    fig = plot.plot_spectrum(passages["hz-faults"])
    texts, lines = _marks(fig)
    assert texts == LABELS
    ff = passages["ff"]
    np.testing.assert_allclose(sorted(lines), sorted(v["hz"] for v in ff.values()), rtol=1e-12)
    assert fig.axes[0].get_xlabel() == "frequency (Hz)" and fig.axes[0].get_xlim()[0] >= 0.0
    # one panel per entry: lines on each, labels on the top one
    fig = plot.plot_spectrum(passages["hz-faults"], normalise="none")
    assert [t.get_text() for t in fig.axes[0].texts] == LABELS and not fig.axes[1].texts
    assert len([ln for ln in fig.axes[2].get_lines() if ln.get_linestyle() == "--"]) == 5


def test_spectrum_marks_them_in_harmonics_of_the_ball_pass_frequency_without_a_speed(passages):
    """Without a shaft speed the axis counts harmonics of the ball-pass frequency Z FTF (Z = 14 per row here):
    BPFO (inner ring turning) is harmonic 1 exactly."""
    from fastbearing.report import plot

    fig = plot.plot_spectrum(passages["harmonic-faults"])
    texts, lines = _marks(fig)
    assert texts == LABELS
    ff = passages["ff"]
    bpf = 14 * ff["FTF"]["order"]
    np.testing.assert_allclose(sorted(lines), sorted(v["order"] / bpf for v in ff.values()), rtol=1e-12)
    assert min(abs(x - 1.0) for x in lines) < 1e-12
    assert fig.axes[0].get_xlabel().startswith("harmonic order of the ball-pass frequency")


def test_spectrum_without_fault_attributes_plots_as_before(passages):
    from fastbearing.report import plot

    for key in ("hz", "harmonic"):
        fig = plot.plot_spectrum(passages[key])
        texts, lines = _marks(fig)
        assert texts == [] and lines == []
        assert "beyond" not in fig.axes[-1].get_xlabel()


def test_spectrum_names_fault_frequencies_beyond_its_axis(passages, tmp_path):
    """A table with one harmonic reaches only BPFO's neighbourhood: the marks beyond are named in the label."""
    import h5py

    from fastbearing.report import plot

    path = tmp_path / "far.h5"
    shutil.copy(passages["hz-faults"], path)
    with h5py.File(path, "r+") as f:
        f.attrs["fault_frequency_BPFI_hz"] = 1e5
    fig = plot.plot_spectrum(path)
    assert "BPFI" not in [t.get_text() for t in fig.axes[0].texts]
    assert fig.axes[-1].get_xlabel() == "frequency (Hz); beyond the axis: BPFI"


def test_spectrum_of_a_table_over_shaft_revolutions_marks_the_orders_the_passage_stores(tmp_path):
    """A table over shaft revolutions (the passage job stores the fault orders itself, and with a speed the
    frequencies): without a speed the axis is the order of the shaft speed and the marks sit at the orders;
    with one, at the Hz."""
    from fastbearing.report import plot

    bearing = str(BEARINGS / "6205.toml")
    orders = fault_orders(7.94004, 39.0398, 9, 0.0, "inner")
    for extra, unit in (({}, "order"), ({"speed": 1797.0}, "hz")):
        path = fb.passage({"bearing": bearing, "passage": {"given": "load", "Fx": 2000.0, "positions": 32,
                                                           "revolutions": 2, "harmonics": 16, **extra}},
                          tmp_path / f"{unit}.h5", progress=False)
        fig = plot.plot_spectrum(path)
        texts, lines = _marks(fig)
        assert sorted(texts) == sorted(LABELS)
        scale = 1.0 if unit == "order" else 1797.0 / 60.0
        np.testing.assert_allclose(sorted(lines), sorted(v * scale for v in orders.values()), rtol=1e-6)
        assert fig.axes[-1].get_xlabel() == ("order of the shaft speed (-)" if unit == "order" else "frequency (Hz)")
        assert "over 2 shaft revolutions" in fig.axes[0].get_title()
