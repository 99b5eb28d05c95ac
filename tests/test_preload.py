"""Radial preload (negative clearance): Kb at rest in closed form, f(0) by symmetry, and the load
distribution against a published clearance study (NASA/TM-2012-217115)."""

import math

import numpy as np
import pytest

import fastbearing as fb

ROW = dict(n_balls=14, hertz_constant=395000.0, pitch_radius=34.75, groove_center_distance=0.52)


def preloaded_kb_at_rest(rows) -> np.ndarray:
    """Kb at q = 0 summed over each row's Z evenly spaced balls, all equally preloaded (Z >= 3).

    Each ball sits at u0 = (A0 cos a0 - rL, s (A0 sin a0 + d0)), |u0| = A, loaded by delta0 = A - A0,
    Q0 = Kn delta0^n, Q0' = n Kn delta0^(n-1); H = (Q0/A)(I - h h^T) + Q0' h h^T, h = u0/A. With
    sum cos^2 = sum sin^2 = Z/2 and the odd sums zero, sum_j J^T H J gives per row (offset z, radius R):
    kxx = kyy = Z/2 H11, kzz = Z H22, kx_ty = -ky_tx = Z/2 (z H11 - R H12),
    ktx_tx = kty_ty = Z/2 (z^2 H11 - 2 z R H12 + R^2 H22), every other entry 0.
    """
    K = np.zeros((5, 5))
    for r in rows:
        a0 = math.radians(r.contact_angle)
        ur = r.groove_center_distance * math.cos(a0) - r.radial_clearance
        uz = r.contact_direction * (r.groove_center_distance * math.sin(a0) + r.axial_preload)
        A = math.hypot(ur, uz)
        d0 = A - r.groove_center_distance
        Q, dQ = r.hertz_constant * d0 ** r.exponent, r.exponent * r.hertz_constant * d0 ** (r.exponent - 1)
        h = np.array([ur, uz]) / A
        H = Q / A * (np.eye(2) - np.outer(h, h)) + dQ * np.outer(h, h)
        Z, z, R = r.n_balls, r.axial_offset, r.pitch_radius
        K[0, 0] += Z / 2 * H[0, 0]
        K[1, 1] += Z / 2 * H[0, 0]
        K[2, 2] += Z * H[1, 1]
        K[0, 4] += Z / 2 * (z * H[0, 0] - R * H[0, 1])
        K[1, 3] -= Z / 2 * (z * H[0, 0] - R * H[0, 1])
        tilt = Z / 2 * (z * z * H[0, 0] - 2 * z * R * H[0, 1] + R * R * H[1, 1])
        K[3, 3] += tilt
        K[4, 4] += tilt
    return K + np.triu(K, 1).T


@pytest.mark.parametrize("bearing", [
    fb.Bearing.single(**ROW, contact_angle=0.0, radial_clearance=-0.01),                      # deep groove
    fb.Bearing.single(**ROW, contact_angle=30.0, radial_clearance=-0.004),
    fb.Bearing.double("DB", 10.0, **ROW, contact_angle=30.0, radial_clearance=-0.005),
    fb.Bearing.double("DF", 10.0, **ROW, contact_angle=25.0, radial_clearance=-0.005, axial_preload=0.003),
    fb.Bearing.double("DT", 12.0, **ROW, contact_angle=15.0, radial_clearance=-0.002),
], ids=["deep-groove", "single-30", "DB", "DF-radial+axial", "DT"])
def test_kb_at_rest_is_the_closed_form(bearing):
    f, K = fb.stiffness(bearing, np.zeros(5))
    expected = preloaded_kb_at_rest(bearing.rows)
    np.testing.assert_allclose(K, expected, rtol=1e-12, atol=1e-12 * np.abs(expected).max())
    assert K[0, 0] > 0 and K[2, 2] > 0                      # a preloaded bearing is stiff at zero load
    Q, _ = fb.ball_loads(bearing, np.zeros(5))
    assert np.all(Q > 0)                                    # every ball loaded at rest


@pytest.mark.parametrize("bearing", [
    fb.Bearing.single(**ROW, contact_angle=0.0, radial_clearance=-0.01),
    fb.Bearing.double("DB", 10.0, **ROW, contact_angle=30.0, radial_clearance=-0.005),
    fb.Bearing.double("DF", 10.0, **ROW, contact_angle=30.0, radial_clearance=-0.005),
], ids=["deep-groove", "DB", "DF"])
def test_no_load_at_rest_by_symmetry(bearing):
    """Radially symmetric preload: the balls' forces cancel (an angular-contact single row would push
    axially, a mirrored pair cancels that too)."""
    f, K = fb.stiffness(bearing, np.zeros(5))
    assert np.abs(f).max() <= 1e-10 * np.abs(K).max() * 1e-3
    r = fb.solve(bearing, np.zeros(5))
    assert r.converged and np.abs(r.q).max() < 1e-12


def test_single_angular_row_with_interference_pushes_axially():
    b = fb.Bearing.single(**ROW, contact_angle=30.0, radial_clearance=-0.004)
    f, _ = fb.stiffness(b, np.zeros(5))
    Q, alpha = fb.ball_loads(b, np.zeros(5))
    assert f[2] == pytest.approx(np.sum(Q * np.sin(alpha)), rel=1e-12) and f[2] > 0


def test_radial_preload_stiffens_under_load():
    load = [2000.0, 0.0, 0.0, 0.0, 0.0]
    k = [fb.solve(fb.Bearing.single(**ROW, contact_angle=0.0, radial_clearance=rl), load).K[0, 0]
         for rl in (0.005, 0.0, -0.005)]
    assert k[0] < k[1] < k[2]


# NASA/TM-2012-217115 (Oswald, Zaretsky, Poplawski 2012), Table II p. 9: 210-size deep-groove ball
# bearing, Z = 10, d = 12.7 mm, conformity 0.52 both races; the pitch diameter is not printed: 70 mm,
# the mean of bore (50) and outside diameter (90), assumed. Radial load giving 1720 MPa inner-race
# maximum Hertz stress at zero clearance. Text of Figs. 6 and 7, pp. 10-11: at +0.051 mm diametral
# clearance 3 balls carry the load, at 0 five, at -0.008 mm seven, at -0.025 mm all ten; the smallest
# maximum ball load is at -0.013 mm.
NASA_210 = dict(n_balls=10, ball_diameter=12.7, pitch_diameter=70.0, inner_groove_ratio=0.52,
                outer_groove_ratio=0.52)


def _nasa_210(clearance, Fr):
    bearing = fb.Geometry(**NASA_210, diametral_clearance=clearance).bearing("single")
    r = fb.solve(bearing, [Fr, 0.0, 0.0, 0.0, 0.0])
    assert r.converged
    return fb.ball_contacts(bearing, r.q)


def test_clearance_study_of_a_210_ball_bearing():
    lo, hi = 100.0, 20000.0                # the load giving 1720 MPa at zero clearance, by bisection
    for _ in range(50):
        Fr = math.sqrt(lo * hi)
        lo, hi = (Fr, hi) if _nasa_210(0.0, Fr).inner_max_pressure.max() < 1720.0 else (lo, Fr)
    loaded = {c: int(np.sum(_nasa_210(c, Fr).load > 0)) for c in (0.051, 0.0, -0.008, -0.025)}
    assert loaded == {0.051: 3, 0.0: 5, -0.008: 7, -0.025: 10}
    clearances = np.linspace(-0.025, 0.051, 39)
    q_max = [_nasa_210(c, Fr).load.max() for c in clearances]
    best = clearances[int(np.argmin(q_max))]
    assert -0.017 <= best <= -0.009                       # NASA: -0.013 mm (ours: -0.014)
    assert np.all(np.diff(q_max)[clearances[1:] > best + 0.004] > 0)   # falls as clearance closes ...
    assert q_max[0] > min(q_max) * 1.2                    # ... then rises steeply with interference
