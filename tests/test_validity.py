"""The status warning ``beyond_validity``: a solution whose ball deflections leave the model's range is
flagged (never hidden), in a solve, a batch, a map and on the command line; the limit is the Hertz
pressure limit where the geometry is known and 0.15 A0 where it is not."""

import math

import h5py
import numpy as np
import pytest
from conftest import cli_run

import fastbearing as fb
from fastbearing import status as st
from fastbearing.model.geometry import CONTACT_PRESSURE_LIMIT

ROOT = __import__("pathlib").Path(__file__).resolve().parents[1]
B6305 = ROOT / "fastbearing" / "catalogue" / "6305.toml"


def test_absurd_load_is_flagged_and_an_ordinary_one_is_not():
    """The issue's case: 6305 under Fz = 1e9 N solves (dz = 57 mm) but no engineer should take it."""
    b = fb.load_bearing(B6305)
    absurd = fb.solve(b, [0.0, 0.0, 1e9, 0.0, 0.0])
    assert absurd.converged and absurd.status & st.BEYOND_VALIDITY
    assert absurd.status_name == "converged+beyond_validity"
    ordinary = fb.solve(b, [1000.0, 0.0, 0.0, 0.0, 0.0])
    assert ordinary.status == st.CONVERGED
    many = fb.solve_many(b, np.array([[0.0, 0.0, 1e9, 0.0, 0.0], [1000.0, 0.0, 0.0, 0.0, 0.0]]))
    assert many.status.tolist() == [absurd.status, ordinary.status]


def test_geometry_limit_is_where_the_hertz_pressure_reaches_the_limit(tmp_path):
    """Radial displacement of a deep-groove row: the top ball's deflection is dx - rL at contact angle 0,
    so a displacement map just below and just above the limit straddles the flag, and the pressure
    there is the limit."""
    b = fb.load_bearing(B6305)
    row = b.rows[0]
    limit = row.validity_deflection
    assert limit == pytest.approx(b.geometry.deflection_limit) and 0.14 < limit / row.groove_center_distance < 0.15
    at_limit = [row.radial_clearance + limit, 0.0, 0.0, 0.0, 0.0]
    contacts = fb.ball_contacts(b, at_limit)
    assert contacts.deflection.max() == pytest.approx(limit, rel=1e-9)
    assert contacts.max_pressure_per_row()[0] == pytest.approx(CONTACT_PRESSURE_LIMIT, rel=1e-6)
    dx = [row.radial_clearance + limit * (1 - 1e-6), row.radial_clearance + limit * (1 + 1e-6)]
    out = fb.loadmap({"bearing": {"geometry": {"n_balls": 7, "ball_diameter": 11.5, "pitch_diameter": 43.5,
                                               "inner_groove_ratio": 0.52, "outer_groove_ratio": 0.53,
                                               "diametral_clearance": 0.01, "youngs_modulus": 210000.0,
                                               "poisson_ratio": 0.3}},
                      "loadmap": {"given": "displacement", "dx": dx}}, tmp_path / "d.h5", progress=False)
    with h5py.File(out, "r") as fh:
        assert fh["status"][...].tolist() == [st.CONVERGED, st.CONVERGED | st.BEYOND_VALIDITY]
        assert "beyond_validity" in fh["status"].attrs["comment"]


def test_pressure_limit_scales_the_deflection_limit_as_its_square():
    """p_max grows as Q^(1/3) and delta as Q^(2/3): the deflection limit goes as the pressure limit squared."""
    g = fb.load_bearing(B6305).geometry
    from dataclasses import replace

    half = replace(g, contact_pressure_limit=CONTACT_PRESSURE_LIMIT / 2)
    assert half.deflection_limit == pytest.approx(g.deflection_limit / 4, rel=1e-12)


def test_without_geometry_the_limit_is_a_fraction_of_A0_or_the_users(tmp_path):
    b = fb.Bearing.preset("gunduz2013", "DB")
    A0 = b.rows[0].groove_center_distance
    assert b.rows[0].validity_deflection == pytest.approx(0.15 * A0)
    # pure axial load: every ball of the loaded row deflects alike, so the flag sits at one load
    q_at = lambda d: [0.0, 0.0, d / math.sin(math.radians(30.0)), 0.0, 0.0]   # noqa: E731 (small-angle guide)
    loads = [fb.stiffness(b, q_at(0.5 * 0.15 * A0))[0], fb.stiffness(b, q_at(2.0 * 0.15 * A0))[0]]
    statuses = [fb.solve(b, f).status for f in loads]
    assert statuses == [st.CONVERGED, st.CONVERGED | st.BEYOND_VALIDITY]
    own = fb.Bearing.preset("gunduz2013", "DB", deflection_limit=1.0)
    assert fb.solve(own, loads[1]).status == st.CONVERGED
    with pytest.raises(ValueError, match=r"deflection_limit must be .*> 0"):
        fb.Bearing.preset("gunduz2013", "DB", deflection_limit=-1.0)
    path = tmp_path / "b.toml"
    path.write_text('[bearing]\ndeflection_limit = 0.1\n[bearing.geometry]\nn_balls = 7\nball_diameter = 11.5\n'
                    "pitch_diameter = 43.5\ninner_groove_ratio = 0.52\nouter_groove_ratio = 0.53\n")
    with pytest.raises(ValueError, match="bearing.deflection_limit is derived from"):
        fb.load_bearing(path)
    path.write_text('[bearing.geometry]\nn_balls = 7\nball_diameter = 11.5\npitch_diameter = 43.5\n'
                    "inner_groove_ratio = 0.52\nouter_groove_ratio = 0.53\ncontact_pressure_limit = 0.0\n")
    with pytest.raises(ValueError, match=r"bearing.geometry.contact_pressure_limit must be .*> 0"):
        fb.load_bearing(path)


def test_map_summary_and_cli_say_it(tmp_path):
    cfg = tmp_path / "m.toml"
    cfg.write_text(f'[bearing]\n{B6305.read_text().split("[bearing]", 1)[1]}\n[loadmap]\nFz = [1000.0, 1.0e9]\n')
    r = cli_run("loadmap", cfg, "-o", tmp_path / "m.h5")
    assert r.returncode == 0 and "converged+beyond_validity 1" in r.stderr, r.stderr
    s = cli_run("solve", "--bearing", B6305, "--load", "0,0,1e9,0,0")
    assert s.returncode == 0 and "status: converged+beyond_validity" in s.stdout
    assert "warning: beyond_validity" in s.stdout
    b = cli_run("bearing", B6305)
    assert "validity: ball deflection <= 0.0830919 mm (Hertz pressure 4200 N/mm^2)" in b.stdout


@pytest.mark.parametrize("speed", [0.0, 3000.0])
def test_a_ring_pushed_through_its_ball_is_flagged_contact_reversed(speed):
    """One ball (at psi = 0) under a load away from it: the equations have a root with the inner ring 0.81 mm
    through the ball (its groove centres crossed over radially, |A| - A0 > 0 again on the far side), which no
    ring can reach; it is flagged, not returned as a plain converged answer. Loaded towards the ball, and a
    full ball set either way, it is not."""
    import dataclasses

    b = fb.load_bearing("6205")
    one = dataclasses.replace(b, rows=(dataclasses.replace(b.rows[0], n_balls=1),))
    away = fb.solve(one, [-1000.0, 0.0, 0.0, 0.0, 0.0], speed=speed)
    assert away.q[0] < -0.5 and away.status_name == "converged+contact_reversed"
    towards = fb.solve(one, [1000.0, 0.0, 0.0, 0.0, 0.0], speed=speed)
    assert towards.status == st.CONVERGED and 0.0 < towards.q[0] < 0.05
    assert fb.solve(b, [-1000.0, 0.0, 0.0, 0.0, 0.0], speed=speed).status == st.CONVERGED
