"""Bearing definitions, bearing files and presets; every bad input is a ValueError naming its field."""

import math
import re
from pathlib import Path

import numpy as np
import pytest

import fastbearing as fb

ROOT = Path(__file__).resolve().parents[1]
GOOD_ROW = dict(n_balls=14, hertz_constant=395000.0, pitch_radius=34.75, groove_center_distance=0.52,
                contact_angle=30.0)


@pytest.mark.parametrize("field, value, words", [
    ("n_balls", 0, "n_balls must be an integer in [1, 10000]"),
    ("n_balls", 2.5, "n_balls must be an integer in [1, 10000]"),
    ("n_balls", math.inf, "n_balls must be an integer in [1, 10000], got inf"),
    ("n_balls", math.nan, "n_balls must be an integer in [1, 10000], got nan"),
    ("n_balls", 1_000_000_000, "n_balls must be an integer in [1, 10000]"),
    ("n_balls", "12", "n_balls must be an integer in [1, 10000], got '12'"),
    ("hertz_constant", 0.0, "hertz_constant must be > 0 N/mm^n"),
    ("hertz_constant", math.nan, "hertz_constant must be finite"),
    ("hertz_constant", True, "hertz_constant must be a number > 0 N/mm^n, got True"),
    ("hertz_constant", "395000", "hertz_constant must be a number"),
    ("groove_center_distance", -0.1, "groove_center_distance must be > 0 mm"),
    ("pitch_radius", 0.0, "pitch_radius must be > 0 mm"),
    ("exponent", 1.0, "exponent must be in (1, 3]"),
    ("contact_angle", 90.0, "contact_angle must be in [0, 90) degrees"),
    ("contact_angle", -1.0, "contact_angle must be in [0, 90) degrees"),
    ("radial_clearance", 10.0, "radial_clearance must be < A0 cos(a0) = 0.450333 mm (beyond it the inner and "
                               "outer groove centres cross)"),
    ("radial_clearance", -0.1, "radial_clearance must be >= -0.0591607 mm: a radial preload (negative clearance) "
                               "may deflect each ball by at most 0.1 A0 = 0.052 mm"),
    ("axial_preload", 0.5, "axial_preload must be <= 0.0926812 mm"),
    ("axial_preload", -0.3, "axial_preload must be >= -A0 sin(a0) = -0.26 mm"),
    ("axial_offset", math.inf, "axial_offset must be finite"),
    ("contact_direction", 0, "contact_direction must be +1 or -1"),
    ("contact_direction", True, "contact_direction must be +1 or -1"),
    ("first_ball_angle", "abc", "first_ball_angle must be a number"),
])
def test_bad_row_values_name_the_field(field, value, words):
    with pytest.raises(ValueError, match=re.escape(words)):
        fb.Row(**{**GOOD_ROW, field: value})


def test_preload_with_clearance_is_rejected():
    with pytest.raises(ValueError, match="axial_preload must be 0 when radial_clearance > 0"):
        fb.Row(**GOOD_ROW, radial_clearance=0.01, axial_preload=0.01)
    fb.Row(**GOOD_ROW, radial_clearance=-0.005, axial_preload=0.01)  # radial and axial preload together


def test_double_row_errors_name_the_row():
    with pytest.raises(ValueError, match=r"rows\[1\]\.hertz_constant"):
        fb.Bearing.from_rows([GOOD_ROW, {**GOOD_ROW, "hertz_constant": -1}])
    with pytest.raises(ValueError, match="arrangement must be one of"):
        fb.Bearing.double("XX", 10.0, **GOOD_ROW)
    with pytest.raises(ValueError, match="row_offset must be >= 0"):
        fb.Bearing.double("DB", -1.0, **GOOD_ROW)
    with pytest.raises(ValueError, match="axial_preload must be one number or a list of 2"):
        fb.Bearing.double("DB", 10.0, axial_preload=[0.0, 0.0, 0.0], **GOOD_ROW)
    with pytest.raises(ValueError, match="axial_offset is set by the arrangement of a double row"):
        fb.Bearing.double("DB", 10.0, axial_offset=3.0, **GOOD_ROW)
    # the tapered names are for tapered pairs: a ball bearing given one is refused, naming the ball name
    with pytest.raises(ValueError, match="arrangement is for tapered roller pairs .* so arranged is DF"):
        fb.Bearing.double("TDI", 10.0, **GOOD_ROW)
    with pytest.raises(ValueError, match="arrangement is for tapered roller pairs .* so arranged is DB"):
        fb.Bearing.preset("gunduz2013", "TDO")


@pytest.mark.parametrize("rows, words", [([5], "rows[0] must be a table, not int"),
                                         (None, "rows must be a list, not NoneType"),
                                         ([], "rows must hold at least 1 item(s), got 0")])
def test_from_rows_refuses_what_is_not_rows(rows, words):
    with pytest.raises(ValueError, match=re.escape(words)):
        fb.Bearing.from_rows(rows)


def test_double_row_layout_follows_model_table():
    for arrangement, dirs in {"DB": (1, -1), "DF": (-1, 1), "DT": (1, 1)}.items():
        b = fb.Bearing.double(arrangement, 10.0, **GOOD_ROW)
        assert [r.axial_offset for r in b.rows] == [-10.0, 10.0]
        assert tuple(r.contact_direction for r in b.rows) == dirs


def write(tmp_path, text, name="b.toml"):
    p = tmp_path / name
    p.write_text(text)
    return p


def test_shipped_example_file_is_the_preset():
    from_file = fb.load_bearing(ROOT / "fastbearing" / "catalogue" / "gunduz2013.toml")
    assert from_file == fb.Bearing.preset("gunduz2013", "DB")
    assert "gunduz2013" in fb.preset_names()


def test_issue_schema_compact_form(tmp_path):
    p = write(tmp_path, """
[bearing]
arrangement = "DF"
n_balls = 14
hertz_constant = 395000.0
pitch_radius = 34.75
groove_center_distance = 0.52
row_offset = 10.0
contact_angle = 30.0
exponent = 1.5
radial_clearance = 0.0
axial_preload = [0.0, 0.01]
first_ball_angle = 0.0
""")
    b = fb.load_bearing(p)
    assert b.arrangement == "DF" and [r.axial_preload for r in b.rows] == [0.0, 0.01]


def test_rows_form_builds_a_triplex_set(tmp_path):
    rows = "".join(f"""
[[bearing.rows]]
axial_offset = {z}
contact_direction = {s}
n_balls = 14
hertz_constant = 395000.0
pitch_radius = 34.75
groove_center_distance = 0.52
contact_angle = 30.0
""" for z, s in ((-20.0, 1), (0.0, 1), (20.0, -1)))
    b = fb.load_bearing(write(tmp_path, "[bearing]\naxial_preload = 0.005\n" + rows))
    assert b.n_rows == 3 and [r.contact_direction for r in b.rows] == [1, 1, -1]
    assert all(r.axial_preload == 0.005 for r in b.rows)


def test_preset_in_a_file_with_overrides(tmp_path):
    b = fb.load_bearing(write(tmp_path, '[bearing]\npreset = "gunduz2013"\narrangement = "DT"\ncontact_angle = 40.0\n'))
    assert b.arrangement == "DT" and all(r.contact_angle == 40.0 for r in b.rows)
    assert b.rows[0].hertz_constant == 395000.0


@pytest.mark.parametrize("text, words", [
    ('[bearing]\npreset = "gunduz2013"\nhertz_constnat = 1.0\n', r"unknown key\(s\) \['hertz_constnat'\]"),
    ('[bearing]\npreset = "gunduz2013"\narrangement = "XY"\n', "arrangement must be one of"),
    ('[bearing]\npreset = "nope"\n', "preset must be one of"),
    ('[bearing]\npreset = "gunduz2013"\n[extra]\n', r"unknown top-level key\(s\) \['extra'\]"),
    ('[bearing]\npreset = "gunduz2013"\nn_balls = 0\n', r"bearing\.n_balls must be an integer in \[1, 10000\]"),
    ('[bearing]\narrangement = "single"\nn_balls = 14\n', "missing required key"),
    ('[bearing]\narrangement = "DB"\nn_balls = 14\n', r"row_offset \(e, mm, >= 0\) is required"),
    ('[bearing]\n[[bearing.rows]]\nn_balls = 3\nbogus = 1\n', r"bearing\.rows\[0\] has unknown key"),
    ('[bearing\n', "not valid TOML"),
    ('x = 1\n', r"unknown top-level key"),
])
def test_bad_bearing_files(tmp_path, text, words):
    with pytest.raises(ValueError, match=words):
        fb.load_bearing(write(tmp_path, text))


def test_missing_file():
    with pytest.raises(ValueError, match="file not found"):
        fb.load_bearing("/nonexistent/bearing.toml")


def test_api_rejects_bad_vectors_before_any_kernel():
    b = fb.Bearing.preset("gunduz2013")
    with pytest.raises(ValueError, match="f must have 5 components"):
        fb.solve(b, [1, 2, 3])
    with pytest.raises(ValueError, match="f must be finite"):
        fb.solve(b, [1, 2, np.nan, 0, 0])
    with pytest.raises(ValueError, match="q must be finite"):
        fb.stiffness(b, [np.inf, 0, 0, 0, 0])
    with pytest.raises(ValueError, match="method must be one of"):
        fb.solve(b, [1, 0, 0, 0, 0], method="secant")
    with pytest.raises(ValueError, match=r"threads must be an integer in \[1"):
        fb.solve_many(b, np.ones((2, 5)), threads=0)
    with pytest.raises(ValueError, match="bearing must be a fastbearing.Bearing"):
        fb.solve("gunduz2013", [1, 0, 0, 0, 0])


def test_ball_table_geometry():
    b = fb.Bearing.preset("gunduz2013", "DB")
    t = b.ball_table()
    assert t.shape == (fb.model.bearing.N_BALL_COLUMNS, 28)
    np.testing.assert_allclose(t[fb.model.bearing.UZ0, :14], 0.52 * 0.5)
    np.testing.assert_allclose(t[fb.model.bearing.UZ0, 14:], -0.52 * 0.5)
    rotated = b.ball_table(cage_angle=2 * np.pi / 14)
    np.testing.assert_allclose(rotated[:2, :13], t[:2, 1:14], atol=1e-14)
    assert b.ball_exponents is None
    assert fb.Bearing.preset("gunduz2013", exponent=1.4).ball_exponents.tolist() == [1.4] * 28
