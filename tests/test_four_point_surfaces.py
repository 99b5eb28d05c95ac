"""Issue 47, items 1, 4, 8 and 9 (kill -9 and the four-point tilt note): the fourth attack's repro cases on the
surfaces round the four-point element. The text and JSON report of a four-point bearing; a four-point row at
a0 = 0 or with a contact_direction refused; nonsense refused before any kernel runs (a load far beyond C0 in
`bearing --speed --load`, a speed beyond the bearing's limit, a defect angle of 1e300 deg, a repeated or
out-of-range --fix); a zombie pid counted dead; and the free-tilt note on the QJ 210."""

import json
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from conftest import cli_run

import fastbearing as fb
from fastbearing.model.four_point import FourPointRow

DATA = Path(__file__).parent.parent / "fastbearing" / "catalogue"
QJ210_FILE = DATA / "QJ210.toml"
QJ210 = fb.load_bearing(QJ210_FILE)
ROW = dict(n_balls=12, hertz_constant=3e5, pitch_radius=30.0, groove_center_distance=0.5, contact_angle=30.0)


# -- item 1: the report of a four-point bearing -------------------------------------------------------------

@pytest.mark.parametrize("args", [(), ("--speed", "3000")])
def test_the_text_report_of_a_four_point_bearing_names_its_row_and_two_contact_pairs(args):
    """Was KeyError: 'n_rollers' (every row with an ``element`` key was taken for a roller row)."""
    r = cli_run("bearing", QJ210_FILE, *args)
    assert r.returncode == 0, r.stderr
    text = r.stdout
    assert text.splitlines()[0] == ("QJ210: single, 1 row(s), 1 of them four-point contact ball, each held as its "
                                    "two contact pairs: rows 0 (+a0) and 1 (-a0) below")
    assert "row 0: four-point balls, contact pair +a0 (with row 1: one four-point row, the same balls)" in text
    assert "row 1: four-point balls, contact pair -a0 (with row 0: one four-point row, the same balls)" in text
    assert "Z = 15" in text and "Kn = 347943 N/mm^1.5" in text and "n_rollers" not in text
    assert "a0 = 35 deg (each contact pair of the four-point row: +a0 and -a0)" in text
    assert ("fault frequencies at 3000 rpm" in text) == bool(args)
    assert fb.bearing_report_text(fb.bearing_report(QJ210), QJ210) == text.split("\nfault frequencies")[0].rstrip("\n")


def test_the_json_report_of_a_four_point_bearing_marks_its_pairs():
    body = json.loads(cli_run("bearing", QJ210_FILE, "--json").stdout)
    assert body == json.loads(json.dumps(fb.bearing_report(QJ210)))
    assert body["four_point_rows"] == [[0, 1]]
    assert [(r["element"], r["pair"], r["contact_direction"]) for r in body["rows"]] == [
        ("four_point_ball", 1, 1), ("four_point_ball", -1, -1)]
    plain = fb.bearing_report(fb.load_bearing(DATA / "6205.toml"))
    assert "four_point_rows" not in plain


# -- item 4: a0 = 0 and contact_direction on a four-point row ------------------------------------------------

def _toml(tmp_path, old, new):
    text = QJ210_FILE.read_text()
    assert old in text
    path = tmp_path / "qj.toml"
    path.write_text(text.replace(old, new, 1))
    return path


def test_a_four_point_row_at_zero_contact_angle_is_refused_as_a_ball_row():
    """At a0 = 0 the two arcs of each ring are one groove: every ball counted twice (kxx x1.56, L10r x3.5)."""
    for build in (lambda: FourPointRow(**{**ROW, "contact_angle": 0.0}),
                  lambda: fb.Bearing.from_rows([{**ROW, "element": "four_point_ball", "contact_angle": 0}]),
                  lambda: fb.Bearing.from_table({**QJ210.geometry.row_keywords(), "element": "four_point_ball",
                                                 "contact_angle": 0.0})):
        with pytest.raises(ValueError, match=r"contact_angle must be in \(0, 90\) degrees for a four-point row .*"
                                             r"give a ball row \(element = 'ball', contact_angle = 0\)"):
            build()
    fb.Bearing.from_rows([{**ROW, "contact_angle": 0.0}])  # the deep-groove ball row it names
    FourPointRow(**{**ROW, "contact_angle": 15.0})  # any angle above 0 stands


def test_a_four_point_bearing_file_at_zero_contact_angle_names_the_geometry_key(tmp_path):
    path = _toml(tmp_path, "contact_angle = 35.0 ", "contact_angle = 0.0 ")
    r = cli_run("bearing", path)
    assert r.returncode == 2 and r.stdout == ""
    assert r.stderr.startswith("fastbearing: error: bearing.geometry.contact_angle must be in (0, 90) degrees")
    assert len(r.stderr.strip().splitlines()) == 1
    with pytest.raises(ValueError, match=r"^bearing\.geometry\.contact_angle must be in \(0, 90\)"):
        fb.load_bearing(path)


@pytest.mark.parametrize("value", [1, -1])
def test_a_contact_direction_on_a_four_point_row_is_refused_even_plus_one(tmp_path, value):
    """It was ignored silently when +1 (the ball row's default)."""
    path = _toml(tmp_path, 'element = "four_point_ball"', f'element = "four_point_ball"\ncontact_direction = {value}')
    r = cli_run("bearing", path)
    assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1
    assert "bearing.contact_direction is not given for a four-point row" in r.stderr
    with pytest.raises(ValueError, match=r"rows\[0\]\.contact_direction is not given for a four-point row"):
        fb.Bearing.from_rows([{**ROW, "element": "four_point_ball", "contact_direction": value}])
    with pytest.raises(ValueError, match=r"^contact_direction is not given for a four-point row"):
        FourPointRow(**ROW, contact_direction=value)


def test_a_four_point_row_without_contact_direction_still_builds_its_two_pairs():
    row = FourPointRow(**ROW)
    assert row.contact_direction is None
    assert [p.contact_direction for p in row.pairs()] == [1, -1]
    assert row.describe_line().startswith("four-point balls, pairs +a0 and -a0: z=0 mm, Z=12, a0=30 deg")
    assert row.report()["contact_direction"] is None and row.report()["n_balls"] == 12
    assert [r.contact_direction for r in QJ210.rows] == [1, -1]
    table = QJ210.to_dict()  # the round trip leaves no contact_direction
    assert "contact_direction" not in table["rows"][0]
    assert [r.contact_direction for r in fb.Bearing.from_table(table).rows] == [1, -1]


# -- item 8: nonsense refused before any kernel runs ---------------------------------------------------------

def _no_kernel(monkeypatch):
    """Any solve from here on fails the test: a refusal must come first."""
    import fastbearing.api as api

    def boom(*a, **k):
        raise AssertionError("a kernel ran before the refusal")

    monkeypatch.setattr(api, "solve_case", boom)


def test_bearing_speed_load_far_beyond_c0_is_refused_before_the_solve(monkeypatch):
    """Was: fault frequencies at an unflagged 'loaded contact angle 80 deg', under 128 000 x C0."""
    _no_kernel(monkeypatch)
    r = cli_run("bearing", DATA / "6205.toml", "--speed", "1000", "--load", "1e9,0,0,0,0")
    assert r.returncode == 2 and r.stdout == "" and len(r.stderr.strip().splitlines()) == 1
    assert ("--load (Fx, Fy, Fz = 1e+09, 0, 0 N; Mx, My = 0, 0 N*mm) is 1.28e+05 x the static load rating "
            "C0 = 7800 N of 6205: it must be <= 10 C0") in r.stderr
    from fastbearing.report.bearing_report import fault_frequency_report

    b = fb.load_bearing(DATA / "6205.toml")
    with pytest.raises(ValueError, match=r"^load .* must be <= 10 C0"):
        fault_frequency_report(b, 1000.0, [0, 0, 0, 0, 1e9 * 19.7])  # a moment counts at the pitch radius
    with pytest.raises(ValueError, match=r"^load .* must be <= 10 C0"):
        fault_frequency_report(QJ210, 3000.0, [0, 0, 1e7, 0, 0])


def test_bearing_speed_load_beyond_validity_is_flagged_in_text_and_json():
    """Between C0 and 10 C0 it solves, and the loaded contact angle is marked outside the model's validity."""
    r = cli_run("bearing", DATA / "6205.toml", "--speed", "1000", "--load", "60000,0,0,0,0")
    assert r.returncode == 0, r.stderr
    assert "; OUTSIDE THE MODEL'S VALIDITY):" in r.stdout
    assert r.stdout.strip().splitlines()[-1].startswith("warning: beyond_validity: at this load a ball's deflection "
                                                        "exceeds its row's validity limit")
    body = json.loads(cli_run("bearing", DATA / "6205.toml", "--speed", "1000", "--load", "60000,0,0,0,0",
                              "--json").stdout)
    assert body["fault_frequency_conditions"]["warning"].startswith("beyond_validity")
    ok = json.loads(cli_run("bearing", DATA / "6205.toml", "--speed", "1000", "--load", "2000,0,0,0,0",
                            "--json").stdout)
    assert "warning" not in ok["fault_frequency_conditions"]


def test_bearing_speed_beyond_the_speed_limit_is_refused_as_solve_refuses_it(monkeypatch):
    """Was accepted at 1e12 rpm (4e6 x the 6205's speed limit)."""
    from fastbearing.model.bearing import speed_limit

    _no_kernel(monkeypatch)
    b = fb.load_bearing(DATA / "6205.toml")
    limit = f"--speed must be <= {speed_limit(b):.6g} rpm for 6205: above it the centrifugal"
    for speed, words, as_solve in (("1e12", "--speed must be in (0, 2e+06] rpm, got 1000000000000.0",
                                    "--speed must be in [0, 2e+06] rpm"), ("300000", limit, limit)):
        r = cli_run("bearing", DATA / "6205.toml", "--speed", speed)
        assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1 and words in r.stderr, r.stderr
        solve = cli_run("solve", "--bearing", DATA / "6205.toml", "--load", "1000,0,0,0,0", "--speed", speed)
        assert solve.returncode == 2 and as_solve in solve.stderr, solve.stderr
    assert cli_run("bearing", DATA / "6205.toml", "--speed", f"{0.999 * speed_limit(b):.6g}").returncode == 0
    r = cli_run("bearing", QJ210_FILE, "--speed", "150000")
    assert r.returncode == 2 and "--speed must be <= 143969 rpm for QJ210" in r.stderr
    r = cli_run("bearing", DATA / "NU205.toml", "--speed", "1e12")  # rollers: no speed model, the sanity bound
    assert r.returncode == 2 and "--speed must be in (0, 2e+06] rpm" in r.stderr


@pytest.mark.parametrize("angle", [1e300, -1e300, 360.5, -400.0])
def test_a_defect_angle_beyond_one_turn_is_refused(angle):
    from fastbearing.model.defects import parse_defects

    b = fb.load_bearing(DATA / "6205.toml")
    with pytest.raises(ValueError, match=r"^passage\.defects\[0\]\.angle must be in \[-360, 360\] degrees"):
        parse_defects([{"race": "outer", "angle": angle, "width": 0.5, "depth": 0.05}], b)
    for ok in (-360.0, 0.0, 359.9, 360):
        assert parse_defects([{"race": "outer", "angle": ok, "width": 0.5, "depth": 0.05}], b)[0].angle == ok


def test_a_repeated_fix_is_refused(monkeypatch):
    """Was: --fix bx=0,bx=0.001 kept the last value silently."""
    _no_kernel(monkeypatch)
    r = cli_run("solve", "--bearing", QJ210_FILE, "--load", "3000,0,2000,0,0", "--fix", "bx=0,bx=0.001")
    assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1
    assert "--fix bx is given twice (0 and 0.001); give each degree of freedom once" in r.stderr


@pytest.mark.parametrize("fix, words", [
    ("bx=1", "--fix bx must be in [-0.03607, 0.03607] rad for QJ210"),
    ("dx=1e300", "--fix dx must be in [-1.27, 1.27] mm for QJ210"),
    ("by=-0.5", "--fix by must be in [-0.03607, 0.03607] rad"),
])
def test_a_fix_beyond_two_element_reaches_is_refused_with_its_range(monkeypatch, fix, words):
    """Was accepted, and ended singular or nonfinite."""
    _no_kernel(monkeypatch)
    r = cli_run("solve", "--bearing", QJ210_FILE, "--load", "0,0,2000,0,0", "--fix", fix)
    assert r.returncode == 2 and r.stdout == "" and len(r.stderr.strip().splitlines()) == 1
    assert words in r.stderr and "element reaches" in r.stderr
    name = fix.partition("=")[0]
    with pytest.raises(ValueError, match=rf"^fixed\.{name} must be in \["):
        fb.solve(QJ210, [0, 0, 2000.0, 0, 0], fixed={name: float(fix.partition("=")[2])})
    with pytest.raises(ValueError, match=rf"^fixed\.{name} must be in \["):
        fb.solve_many(QJ210, [[0, 0, 2000.0, 0, 0]] * 2, fixed={name: [0.0, float(fix.partition("=")[2])]})


def test_a_fix_within_its_range_solves_finite():
    from fastbearing.boundary import fixed_bounds

    length, tilt = fixed_bounds(QJ210)
    assert length == pytest.approx(2 * 0.635) and tilt == pytest.approx(2 * 0.635 / 35.2081, rel=1e-5)
    for fixed, load in (({"bx": 0.999 * tilt}, [3000.0, 0, 2000.0, 0, 0]), ({"dx": 0.999 * length}, [0, 0, 0, 0, 0])):
        r = fb.solve(QJ210, load, fixed=fixed)
        assert r.converged and np.isfinite(r.K).all() and "beyond_validity" in r.status_name


# -- item 9: a zombie is not alive; the four-point free-tilt note ---------------------------------------------

@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs /proc")
def test_a_killed_run_not_yet_reaped_is_not_alive_and_its_lock_is_taken_over(tmp_path):
    """Right after a kill -9 the pid is a zombie until its parent waits: os.kill(pid, 0) still succeeds."""
    from fastbearing.jobs.locations import RunLock, alive

    p = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    try:
        assert alive(p.pid)
        out = tmp_path / "m.h5"
        (tmp_path / "m.h5.lock").write_text(str(p.pid))
        with pytest.raises(ValueError, match=f"another run \\(pid {p.pid}\\) is writing"):
            RunLock(out).__enter__()
        os.kill(p.pid, signal.SIGKILL)
        for _ in range(200):  # the kernel marks it a zombie at once; wait for the state, never for the child
            if Path(f"/proc/{p.pid}/stat").read_bytes().split(b")")[-1].split()[0] == b"Z":
                break
            time.sleep(0.01)
        assert not alive(p.pid)  # a zombie: killed, not yet reaped
        with RunLock(out):
            assert (tmp_path / "m.h5.lock").read_text() == str(os.getpid())
    finally:
        p.kill()
        p.wait()
    assert not alive(p.pid)


def test_the_four_point_bearing_says_it_tilted_freely_as_a_single_row_does():
    """QJ 210 under combined load tilts freely by about 1 mrad (held square, its L10r halves): the note."""
    r = fb.solve(QJ210, [3000.0, 0, 2000.0, 0, 0])
    assert r.converged and r.note.startswith("the ring tilted freely by 1.19 mrad (a four-point row, like a single "
                                             "row, carries a combined load with a tilt); where the shaft holds it")
    assert "--fix bx=0,by=0" in r.note
    assert r.note.count("\n") == 0
    assert fb.solve(QJ210, [3000.0, 0, 2000.0, 0, 0], fixed={"bx": 0.0, "by": 0.0}).note == ""
    assert fb.solve(QJ210, [3000.0, 0, 0, 0, 0]).note == ""  # radial alone: no tilt
    single = fb.load_bearing(DATA / "6305.toml")
    assert "(a single row carries a combined load with a tilt)" in fb.solve(single, [1000.0, 0, 1000.0, 0, 0]).note
    spindle = fb.load_bearing(DATA / "7014C-DB.toml")  # a pair at two axial places holds its tilt
    assert fb.solve(spindle, [1000.0, 0, 1000.0, 0, 0]).note == ""
    flat = fb.Bearing.from_rows([{**ROW, "contact_direction": 1}, {**ROW, "contact_direction": -1}])  # DB, e = 0
    assert "(its rows sit at one axial place: like a single row" in fb.solve(flat, [1000.0, 0, 500.0, 0, 0]).note
    cli = cli_run("solve", "--bearing", QJ210_FILE, "--load", "3000,0,2000,0,0")
    assert cli.returncode == 0 and cli.stdout.splitlines()[1].startswith("the ring tilted freely by 1.19 mrad")


@pytest.mark.parametrize("job", ["loadmap", "passage"])
def test_a_job_tables_fixed_values_beyond_the_bearings_reach_are_refused(tmp_path, job):
    """A job table's fixed displacement (a number or an axis) is bounded as --fix is: a 1 rad tilt or a 1e300
    mm displacement is refused naming the field, before any kernel runs, and no output is written."""
    out = tmp_path / "x.h5"
    run = fb.loadmap if job == "loadmap" else fb.passage
    for fixed, name in (({"bx": 0.0, "by": 1.0}, "by"), ({"bx": {"start": 0.0, "stop": 1e300, "num": 3}}, "bx")):
        cfg = {"bearing": {"preset": "gunduz2013"}, job: {"given": "load", "Fx": 1000.0, "fixed": fixed}}
        with pytest.raises(ValueError, match=rf"{job}\.fixed\.{name} must be in \["):
            run(cfg, out, progress=False)
        assert not out.exists()


def test_two_four_point_rows_hold_their_own_pairs_mirrored_or_not():
    """Two four-point rows side by side were refused ('pair without its partner'): the swap that restores a
    mirrored row's pair order took row 0's pair - and row 1's pair + for a mirrored pair. Each row's two pairs
    stay together, +a0 then -a0, also on the mirrored bearing; standing still the set is the sum of its rows."""
    from fastbearing.analysis.shaft import mirrored

    two = fb.Bearing.from_rows([{**ROW, "element": "four_point_ball", "axial_offset": z} for z in (-10.0, 10.0)])
    assert [(r.axial_offset, r.contact_direction) for r in two.rows] == [(-10.0, 1), (-10.0, -1), (10.0, 1),
                                                                        (10.0, -1)]
    flipped = mirrored(two)
    assert [(r.axial_offset, r.contact_direction) for r in flipped.rows] == [(10.0, 1), (10.0, -1), (-10.0, 1),
                                                                            (-10.0, -1)]
    q = np.array([0.01, 0.0, 0.005, 0.0, 0.0002])
    rows = [fb.Bearing.from_rows([{**ROW, "element": "four_point_ball", "axial_offset": z}]) for z in (-10.0, 10.0)]
    f_sum = sum(fb.stiffness(b, q)[0] for b in rows)
    K_sum = sum(fb.stiffness(b, q)[1] for b in rows)
    f, K = fb.stiffness(two, q)
    assert np.allclose(f, f_sum, rtol=1e-12, atol=1e-9) and np.allclose(K, K_sum, rtol=1e-12, atol=1e-6)
