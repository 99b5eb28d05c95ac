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

DATA = Path(__file__).parent.parent / "data" / "bearings"
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
    assert [r.contact_direction for r in QJ210.rows] == [1, -1]
    table = QJ210.to_dict()  # the round trip leaves no contact_direction
    assert "contact_direction" not in table["rows"][0]
    assert [r.contact_direction for r in fb.Bearing.from_table(table).rows] == [1, -1]
