"""Four-point contact ball rows (model/four_point.py, engine/four_point.py; docs/model.md, "Four-point contact
balls"), added through the element interface: quasi-statically a DB pair of the same geometry with zero row
spacing; at speed one ball under four contacts, equal to an independent scipy reference written from the
equations (tests/four_point_reference.py), to the angular contact row at speed where one pair carries
nothing, with Kb the derivative of f; the shipped QJ 210 file, its life, records and bad input."""

import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import fastbearing as fb
from fastbearing.analysis.contacts import ball_contacts
from fastbearing.model.four_point import ContactPair, FourPointRow
from four_point_reference import four_point_load

DATA = Path(__file__).parent.parent / "fastbearing" / "catalogue"
QJ210 = fb.load_bearing(DATA / "QJ210.toml")
SPINDLE = fb.load_bearing(DATA / "7014C-DB.toml").geometry


def _four_point(geometry):
    """The geometry as one four-point row, and as the DB pair of it with zero row spacing."""
    fp = replace(fb.Bearing.from_table({**geometry.row_keywords(), "element": "four_point_ball"}), geometry=geometry)
    db = replace(geometry, row_spacing=0.0).bearing("DB")
    return fp, db


def _scaled(K, L):
    s = np.array([1, 1, 1, 1 / L, 1 / L])
    return K * s[:, None] / s[None, :]


@pytest.mark.parametrize("clearance", [0.0, 0.04, -0.004])
def test_quasi_static_four_point_row_is_a_db_pair_with_zero_row_spacing(clearance):
    """f and Kb at random q, and solves, of any load: the DB pair's, to rounding (here bit for bit)."""
    g = replace(QJ210.geometry, diametral_clearance=clearance)
    fp, db = _four_point(g)
    rng = np.random.default_rng(3)
    for _ in range(5):
        q = rng.normal(size=5) * np.array([0.01, 0.01, 0.01, 2e-4, 2e-4])
        (f1, K1), (f2, K2) = fb.stiffness(fp, q), fb.stiffness(db, q)
        assert np.abs(f1 - f2).max() <= 1e-14 * np.abs(f2).max()
        assert np.abs(K1 - K2).max() <= 1e-14 * np.abs(K2).max()
    for load in ([3000.0, 0, 0, 0, 0], [1000.0, -500.0, 4000.0, 2e4, -1e4], [0, 0, -2500.0, 0, 0]):
        a, b = fb.solve(fp, load), fb.solve(db, load)
        assert a.converged and b.converged
        assert np.abs(a.q - b.q).max() <= 1e-12 * np.abs(b.q).max()


@pytest.mark.parametrize("race_control,rotating", [("outer", "inner"), ("inner", "inner"), ("none", "outer")])
def test_f_at_speed_equals_the_independent_four_point_reference(race_control, rotating):
    """All four contacts loaded (a radial load, zero clearance) and a combined q with one pair lifting on
    part of the row: every entry of f, 1e-9 of the largest."""
    g = replace(QJ210.geometry, diametral_clearance=0.0, race_control=race_control, rotating=rotating)
    fp, _ = _four_point(g)
    L = fp.rows[0].pitch_radius
    s = np.array([1, 1, 1, 1 / L, 1 / L])
    for q, speed in (([0.02, 0, 0, 0, 0], 10000.0), ([0.01, -0.004, 0.012, 2e-4, -1e-4], 15000.0)):
        f, _ = fb.stiffness(fp, q, speed=speed)
        f_ref = four_point_load(g, [fp.rows[0]], np.array(q), speed)
        assert np.abs((f - f_ref) * s).max() <= 1e-9 * np.abs(f_ref * s).max(), (f, f_ref)


def test_kb_at_speed_with_all_four_contacts_loaded_is_central_differences_of_f():
    """A radial load on the zero-clearance row (the balls under it touch all four arcs): Kb, every entry,
    against central differences of f with the balls re-settled (the complex-step derivatives are exact)."""
    g = replace(QJ210.geometry, diametral_clearance=0.0)
    fp, _ = _four_point(g)
    speed = 12000.0
    r = fb.solve(fp, [4000.0, 500.0, 300.0, 0, 0], speed=speed)
    assert r.converged
    c = ball_contacts(fp, r.q, speed=speed)
    n = QJ210.rows[0].n_balls
    assert ((c.inner_load[:n] > 0) & (c.inner_load[n:] > 0)).sum() >= 3  # balls with all four contacts
    K_fd = np.empty((5, 5))
    for j in range(5):
        h = 1e-7 if j < 3 else 1e-9
        e = np.zeros(5)
        e[j] = h
        K_fd[:, j] = (fb.stiffness(fp, r.q + e, speed=speed)[0] - fb.stiffness(fp, r.q - e, speed=speed)[0]) / (2 * h)
    L = fp.rows[0].pitch_radius
    assert np.abs(_scaled(r.K - K_fd, L)).max() <= 1e-6 * np.abs(_scaled(r.K, L)).max()


@pytest.mark.parametrize("load,speed", [([250.0, 0, 5000.0, 0, 0], 6000.0), ([0, 0, 20000.0, 0, 0], 12000.0),
                                        ([1000.0, 0, -20000.0, 0, 0], 12000.0)])
def test_at_speed_with_one_pair_unloaded_it_is_the_angular_contact_row_at_speed(load, speed):
    """An axial load large enough that the other pair carries nothing (its arcs lift off, outer ones too):
    q and Kb of the single angular contact row of the same geometry (turned round for a negative load)."""
    fp = QJ210
    direction = 1 if load[2] > 0 else -1
    single = fb.Bearing.from_rows([{**QJ210.geometry.row_keywords(), "contact_direction": direction}])
    single = replace(single, geometry=QJ210.geometry)
    a, b = fb.solve(fp, load, speed=speed), fb.solve(single, load, speed=speed)
    assert a.converged and b.converged
    c = ball_contacts(fp, a.q, speed=speed)
    n = fp.rows[0].n_balls
    idle = slice(n, 2 * n) if direction > 0 else slice(0, n)
    assert np.all(c.inner_load[idle] == 0) and np.all(c.outer_load[idle] == 0)
    assert np.abs(a.q - b.q).max() <= 1e-9 * np.abs(b.q).max()
    assert np.abs(a.K - b.K).max() <= 1e-8 * np.abs(b.K).max()


def test_every_four_point_ball_is_in_equilibrium_and_rests_on_both_outer_arcs_when_free():
    """At speed each ball's residual is at rounding; a ball the load leaves free rides both outer arcs
    (the pairs share its centrifugal force) and gives the ring nothing."""
    r = fb.solve(QJ210, [3000.0, 0, 0, 0, 0], speed=10000.0)
    assert r.converged
    c = ball_contacts(QJ210, r.q, speed=10000.0)
    n = QJ210.rows[0].n_balls
    assert c.equilibrium_residual.max() <= 1e-10
    free = (c.inner_load[:n] == 0) & (c.inner_load[n:] == 0)
    assert free.any()
    assert np.all(c.outer_load[:n][free] > 0) and np.all(c.outer_load[n:][free] > 0)
    assert np.allclose(c.outer_load[:n][free], c.outer_load[n:][free], rtol=1e-6)


def test_standing_still_and_slow_the_coupled_ball_is_close_to_the_pair_model():
    """Below the standing-still speed the kernel takes the pair model (a DB pair); just above it the coupled
    ball, which agrees to first order in the deflections: here within 1e-3 of q (docs/model.md)."""
    load = [3000.0, 0, 500.0, 0, 0]
    rest = fb.solve(QJ210, load, speed=0.0)
    slow = fb.solve(QJ210, load, speed=1.0)
    assert rest.converged and slow.converged
    assert np.abs(slow.q - rest.q).max() <= 1e-3 * np.abs(rest.q).max()


def test_the_shipped_qj210_file_its_life_and_its_rows():
    """One row in the file, two contact pairs in the bearing (pair +a0, pair -a0, alike in all else); life
    rates the row as a double row of its pairs (C with i = 2, tests/test_four_point_life.py): under an axial
    load the idle pair adds nothing, so L10r is the single row's; and the bearing round-trips through its
    table as one four-point row."""
    assert [type(r) for r in QJ210.rows] == [ContactPair, ContactPair]
    assert [r.contact_direction for r in QJ210.rows] == [1, -1]
    assert QJ210.rows[0].element == "four_point_ball"
    single = replace(QJ210.geometry.bearing("single"), geometry=QJ210.geometry)
    load = [0, 0, 3000.0, 0, 0]
    a, b = fb.rating_life(QJ210, load), fb.rating_life(single, load)
    assert a.L10r == pytest.approx(b.L10r, rel=1e-9) and a.C == pytest.approx(2 ** 0.7 * b.C)
    both = fb.rating_life(QJ210, [3000.0, 0, 500.0, 0, 0])
    assert len(both.L10r_row) == 2 and all(math.isfinite(x) for x in both.L10r_row)
    table = QJ210.to_dict()
    assert len(table["rows"]) == 1 and table["rows"][0]["element"] == "four_point_ball"
    again = fb.Bearing.from_table({"rows": table["rows"]})
    assert [replace(r) for r in again.rows] == list(QJ210.rows)


def test_four_point_rows_refuse_a_direction_or_an_axial_preload_and_stray_pairs():
    row = {**QJ210.geometry.row_keywords(), "element": "four_point_ball"}
    with pytest.raises(ValueError, match=r"contact_direction.*both diagonals"):
        fb.Bearing.from_rows([{**row, "contact_direction": -1}])
    with pytest.raises(ValueError, match=r"axial_preload.*negative radial_clearance"):
        fb.Bearing.from_rows([{**row, "axial_preload": 0.01}])
    pair = FourPointRow(**{k: v for k, v in row.items() if k != "element"}).pairs()[0]
    with pytest.raises(ValueError, match="without its partner"):
        fb.Bearing((pair,))
    with pytest.raises(ValueError, match="four_point_ball"):
        fb.Bearing.from_rows([{**row, "element": "four_point"}])


def test_the_command_line_solves_the_qj210_at_speed_and_reports_both_pairs(tmp_path, capsys):
    from fastbearing.cli import main

    assert main(["solve", "--bearing", str(DATA / "QJ210.toml"), "--load", "2000,0,3000,0,0", "--speed", "8000",
                 "--balls", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["status"] == "converged"
    assert len(out["balls"]) == 2 * QJ210.rows[0].n_balls  # each ball once per contact pair
    assert {b["row"] for b in out["balls"]} == {0, 1}


def test_a_four_point_row_is_its_own_mirror_image_on_a_shaft_and_its_pairs_refuse_a_preload():
    """mirrored = true on a shaft: the pairs keep their order (+a0, -a0) and the bearing is the same (it used
    to fail: the flipped pairs came out -a0 first); with_rows cannot give the pairs an axial preload."""
    from fastbearing.analysis.shaft import mirrored

    flipped = mirrored(QJ210)
    assert [r.contact_direction for r in flipped.rows] == [1, -1]
    load = [2000.0, 0, 1500.0, 0, 0]
    assert np.array_equal(fb.solve(flipped, load).q, fb.solve(QJ210, load).q)
    with pytest.raises(ValueError, match="axial_preload must be 0 for a four-point row"):
        QJ210.with_rows(axial_preload=0.01)
