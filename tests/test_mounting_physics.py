"""Mounting physics (issue 44 item 3): fits, temperatures and speed -> operating clearance.

Every oracle here is independent of fastbearing.model.mounting's closed forms: catalogue formulas (NSK CAT.
E1102e Table 15.1 and eq. 9.6), the research note's derived 6205 set (shared/research/mounting-and-
tolerances.md 1.3, printed to 3-4 digits), SKF's hollow-shaft example, and a direct numpy solve of the general
Lame solution u = A r + B/r (+ C r^3 under spin) for two cylinders with their boundary and interface
conditions. Units: mm, N/mm^2, deg C, rpm.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from fastbearing.model import mounting as m
from fastbearing.validate import FieldError

# 6205 with the CWRU internal geometry (research 1.3): Di = 31.10, De = 46.98
D6205 = dict(bore=25.0, outer_diameter=52.0, pitch_diameter=39.04, element_diameter=7.94)
E_STEEL = 208000.0


def row(**kw):
    return m.mount_row(**{**D6205, "warn": False, **kw})


# -- formula-exact special cases --------------------------------------------------------------------
@pytest.mark.parametrize("interference", [0.002, 0.0115, 0.021])
def test_solid_shaft_of_the_ring_material_grows_the_raceway_by_interference_times_d_over_di(interference):
    r = row(shaft_interference=interference)
    d, Di = 25.0, 39.04 - 7.94
    k = d / Di
    assert r.inner_raceway_growth == pytest.approx(interference * d / Di, rel=1e-12)
    # NSK E1102e Table 15.1: pm = (E/2)(delta/d)(1 - k^2), sigma_t,max = pm (1 + k^2)/(1 - k^2)
    pm = 0.5 * E_STEEL * interference / d * (1 - k * k)
    assert r.shaft_fit_pressure == pytest.approx(pm, rel=1e-12)
    assert r.inner_ring_hoop_stress == pytest.approx(pm * (1 + k * k) / (1 - k * k), rel=1e-12)
    assert r.mounted_diametral_clearance == pytest.approx(-interference * d / Di, rel=1e-12)


def test_6205_k5_table_of_the_research_note():
    """Research 1.3: 2 / 11.5 / 21 um -> dDi 1.608 / 9.244 / 16.881 um, pm 2.94 / 16.93 / 30.91 MPa,
    sigma_t,max 13.7 / 78.8 / 143.8 MPa."""
    for interference, growth, pm, hoop in ((0.002, 1.608, 2.94, 13.7), (0.0115, 9.244, 16.93, 78.8),
                                           (0.021, 16.881, 30.91, 143.8)):
        r = row(shaft_interference=interference)
        assert r.inner_raceway_growth * 1e3 == pytest.approx(growth, abs=0.0006)
        assert r.shaft_fit_pressure == pytest.approx(pm, abs=0.006)
        assert r.inner_ring_hoop_stress == pytest.approx(hoop, abs=0.06)


def test_hollow_shaft_factor():
    """Research 1.1(b): dDi = delta k (1 - k0^2)/(1 - k^2 k0^2); 6205 on d0 = 15 mm: dDi/delta = 0.6704, so
    14.079 um from 21 um."""
    d, Di, d0 = 25.0, 31.10, 15.0
    k, k0 = d / Di, d0 / d
    factor = (1 - k0 ** 2) / (1 - k ** 2 * k0 ** 2)
    hollow = row(shaft_interference=0.021, shaft_bore=d0)
    solid = row(shaft_interference=0.021)
    assert hollow.inner_raceway_growth / solid.inner_raceway_growth == pytest.approx(factor, rel=1e-12)
    assert hollow.inner_raceway_growth / 0.021 == pytest.approx(k * factor, rel=1e-12)
    assert k * factor == pytest.approx(0.6704, abs=5e-5)
    assert hollow.inner_raceway_growth * 1e3 == pytest.approx(14.079, abs=5e-4)
    pm = 0.5 * E_STEEL * 0.021 / d * (1 - k * k) * (1 - k0 * k0) / (1 - k * k * k0 * k0)
    assert hollow.shaft_fit_pressure == pytest.approx(pm, rel=1e-12)


def test_skf_6208_hollow_shaft_needs_1_726_times_the_interference():
    """SKF 'Fits for hollow shafts': 6208 (d 40, D 80), ci = d0/d = 0.8, ring land de ~ d + 0.3 (D - d) = 52
    (ce = 40/52): the same pressure needs (1 - ce^2 ci^2)/(1 - ci^2) = 1.726 times the solid-shaft
    interference (research 1.2; SKF's diagram reads about 1.7)."""
    kw = dict(bore=40.0, outer_diameter=80.0, pitch_diameter=60.0, element_diameter=12.0,
              inner_raceway_diameter=52.0, shaft_interference=0.02, warn=False)
    solid = m.mount_row(**kw)
    hollow = m.mount_row(**kw, shaft_bore=32.0)
    ratio = solid.shaft_fit_pressure / hollow.shaft_fit_pressure  # interference for equal pressure
    assert ratio == pytest.approx((1 - (40 / 52) ** 2 * 0.8 ** 2) / (1 - 0.8 ** 2), rel=1e-12)
    assert ratio == pytest.approx(1.726, abs=5e-4)


def test_infinitely_thick_and_finite_housing():
    """Research 1.1(b)/1.3: dDe/dD = h = De/D = 0.9035 for D0 -> inf; h (1 - h0^2)/(1 - h^2 h0^2) = 0.7964
    for a housing of 80 mm; pm = (E/2)(dD/D)(1 - h^2)(1 - h0^2)/(1 - h^2 h0^2); sigma_t at the outer ring's
    bore = -2 pm / (1 - h^2) (compression)."""
    De, D = 46.98, 52.0
    h = De / D
    thick = row(housing_interference=0.01)
    assert thick.outer_raceway_contraction / 0.01 == pytest.approx(h, rel=1e-12)
    assert h == pytest.approx(0.9035, abs=5e-5)
    assert thick.housing_fit_pressure == pytest.approx(0.5 * E_STEEL * 0.01 / D * (1 - h * h), rel=1e-12)
    h0 = D / 80.0
    thin = row(housing_interference=0.01, housing_outer_diameter=80.0)
    ratio = h * (1 - h0 ** 2) / (1 - h ** 2 * h0 ** 2)
    assert thin.outer_raceway_contraction / 0.01 == pytest.approx(ratio, rel=1e-12)
    assert ratio == pytest.approx(0.7964, abs=5e-5)
    pm = 0.5 * E_STEEL * 0.01 / D * (1 - h * h) * (1 - h0 * h0) / (1 - h * h * h0 * h0)
    assert thin.housing_fit_pressure == pytest.approx(pm, rel=1e-12)
    assert thin.outer_ring_hoop_stress == pytest.approx(-2 * pm / (1 - h * h), rel=1e-12)
    # a very large housing tends to the infinitely thick one
    far = row(housing_interference=0.01, housing_outer_diameter=5.2e5)
    assert far.outer_raceway_contraction == pytest.approx(thick.outer_raceway_contraction, rel=1e-7)


@pytest.mark.parametrize("t_inner, t_outer", [(30.0, 20.0), (70.0, 45.0), (5.0, 25.0)])
def test_nsk_thermal_rule_is_the_equal_expansion_case(t_inner, t_outer):
    """NSK E1102e eq. (9.6): delta_t = alpha dT De with dT = T(inner ring and balls) - T(outer ring), for equal
    alpha, balls at the inner ring's temperature, no fits (Di + 2 Dw = De)."""
    r = row(unmounted_diametral_clearance=0.015, inner_ring_temperature=t_inner, outer_ring_temperature=t_outer)
    delta_t = 12.5e-6 * (t_inner - t_outer) * 46.98
    assert r.unmounted_diametral_clearance - r.operating_diametral_clearance == pytest.approx(delta_t, rel=1e-12,
                                                                                               abs=1e-15)
    assert r.shaft_fit_pressure == 0.0 and r.housing_fit_pressure == 0.0


def test_research_thermal_value_10_K():
    r = row(inner_ring_temperature=30.0, outer_ring_temperature=20.0)
    assert -r.operating_diametral_clearance * 1e3 == pytest.approx(5.872, abs=6e-4)  # 5.8725


def test_centrifugal_growth_research_values_and_n_squared():
    """Research 1.3: inner raceway 0.220 / 0.882 / 1.983 um and interference loss 0.206 / 0.826 / 1.858 um at
    10 / 20 / 30 krpm (6205 inner ring, solid steel shaft); both scale with n^2."""
    growths, losses = [], []
    for n, growth, loss in ((10000, 0.220, 0.206), (20000, 0.882, 0.826), (30000, 1.983, 1.858)):
        r = row(speed=n, shaft_interference=0.03, warn=False)
        growths.append(r.inner_raceway_free_growth)
        losses.append(r.shaft_fit.nominal_interference - r.shaft_interference)
        assert r.inner_raceway_free_growth * 1e3 == pytest.approx(growth, abs=6e-4)
        assert losses[-1] * 1e3 == pytest.approx(loss, abs=6e-4)
    for values in (growths, losses):
        assert values[1] / values[0] == pytest.approx(4.0, rel=1e-12)
        assert values[2] / values[0] == pytest.approx(9.0, rel=1e-12)
    # a free ring a = 20, b = 24.5 mm (research 1.3 'ring check'): 0.882 / 3.529 / 7.940 um at the raceway
    for n, um in ((10000, 0.882), (20000, 3.529), (30000, 7.940)):
        u = m.centrifugal_displacement(24.5, 20.0, 24.5, m.STEEL, n)
        assert 2 * u * 1e3 == pytest.approx(um, abs=6e-4)


@pytest.mark.parametrize("interference, rpm", [(0.002, 31100), (0.0115, 74600), (0.021, 100900)])
def test_speed_at_which_the_shaft_fit_is_lost(interference, rpm):
    r = row(shaft_interference=interference)
    assert r.shaft_fit.loss_speed == pytest.approx(rpm, abs=50)  # the note prints 3-4 digits
    at = row(shaft_interference=interference, speed=r.shaft_fit.loss_speed)
    assert at.shaft_interference == pytest.approx(0.0, abs=1e-15)
    assert row(shaft_interference=interference, speed=1.001 * r.shaft_fit.loss_speed).shaft_fit.lost
    assert any(f"above {r.shaft_fit.loss_speed:,.0f}".replace(",", " ") in note for note in r.notes)
    # the housing fit of a standing outer ring is not loosened by speed
    assert row(housing_interference=0.005).housing_fit.loss_speed == math.inf


def test_temperature_rise_at_which_a_fit_is_lost():
    r = row(shaft_interference=0.0115)
    rise = r.shaft_fit.loss_temperature_rise
    assert rise == pytest.approx(0.0115 / (12.5e-6 * 25.0), rel=1e-12)  # ring warmer than the shaft
    assert row(shaft_interference=0.0115, inner_ring_temperature=20 + rise,
               shaft_temperature=20.0).shaft_interference == pytest.approx(0.0, abs=1e-15)
    alu = m.ALUMINIUM
    h = row(housing_interference=0.01, housing_material="aluminium")
    assert h.housing_fit.loss_temperature_rise == pytest.approx(0.01 / (alu.thermal_expansion * 52.0), rel=1e-12)


def test_aluminium_housing_outer_fit_loss_of_the_research_note():
    """Research 1.3: an aluminium housing (23.6e-6 vs 12.5e-6 /K) warmer by 30 / 50 K takes 17.3 / 28.9 um
    from the outer fit (D = 52)."""
    alu = dict(name="al", youngs_modulus=70000.0, poisson_ratio=0.33, density=2700.0, thermal_expansion=23.6e-6)
    for dT, um in ((30.0, 17.3), (50.0, 28.9)):
        r = row(housing_interference=0.05, housing_material=alu, outer_ring_temperature=20 + dT)
        assert (0.05 - r.housing_interference) * 1e3 == pytest.approx(um, abs=0.05)


def test_ball_centrifugal_growth_is_negligible():
    g = m.ball_spin_growth(7.94, 39.04, m.STEEL, 30000)
    ring = row(speed=30000).inner_raceway_free_growth
    assert g < 1e-4 and g < 0.05 * ring


# -- dissimilar materials against a direct two-cylinder solve ------------------------------------------
def _direct(inner, outer, radius, delta):
    """Two annuli in plane stress, each u = A r + B/r + C r^3 (C = -(1 - nu^2) rho w^2/(8E): the particular
    solution of d/dr(1/r d(ru)/dr) = -(1 - nu^2) rho w^2 r / E), thermal strain alpha*theta. Bodies are dicts
    a, b (b None: infinite), E, nu, alpha, theta (K), rho (kg/m^3), w (rad/s). Unknowns A1, B1, A2, B2:
    free inner surface of the inner part (B1 = 0 when solid), free outer surface of the outer part (infinite:
    A2 = alpha theta), equal radial stress at the interface, and u2 - u1 = delta/2 there. Returns the two
    displacement functions and the interface pressure."""
    def parts(body):
        E, nu = body["E"], body["nu"]
        C = -(1 - nu ** 2) * 1e-12 * body["rho"] * body["w"] ** 2 / (8 * E)
        f = E / (1 - nu ** 2)

        def sr_row(r):  # sigma_r = f [ (1+nu) A - (1-nu) B / r^2 + (3 + nu) C r^2 ] - E alpha theta/(1-nu)
            return np.array([f * (1 + nu), -f * (1 - nu) / r ** 2]), f * (3 + nu) * C * r ** 2 \
                - E * body["alpha"] * body["theta"] / (1 - nu)
        return C, sr_row

    C1, s1 = parts(inner)
    C2, s2 = parts(outer)
    M, rhs = np.zeros((4, 4)), np.zeros(4)
    if inner["a"] == 0.0:
        M[0, 1] = 1.0
    else:
        c, k = s1(inner["a"])
        M[0, :2], rhs[0] = c, -k
    if outer["b"] is None:
        M[1, 2], rhs[1] = 1.0, outer["alpha"] * outer["theta"]
    else:
        c, k = s2(outer["b"])
        M[1, 2:], rhs[1] = c, -k
    c1, k1 = s1(radius)
    c2, k2 = s2(radius)
    M[2, :2], M[2, 2:], rhs[2] = c1, -c2, k2 - k1
    M[3] = [-radius, -1 / radius, radius, 1 / radius]
    rhs[3] = 0.5 * delta + C1 * radius ** 3 - C2 * radius ** 3
    A1, B1, A2, B2 = np.linalg.solve(M, rhs)

    def u1(r):
        return A1 * r + B1 / r + C1 * r ** 3

    def u2(r):
        return A2 * r + B2 / r + C2 * r ** 3
    pressure = -(c1 @ [A1, B1] + k1)
    return u1, u2, pressure


def _body(a, b, mat, theta=0.0, rpm=0.0):
    return dict(a=a, b=b, E=mat.youngs_modulus, nu=mat.poisson_ratio, alpha=mat.thermal_expansion, theta=theta,
                rho=mat.density, w=2 * math.pi * rpm / 60)


@pytest.mark.parametrize("housing_od", [70.0, 90.0, None])
def test_aluminium_housing_on_a_steel_ring_against_a_direct_solve(housing_od):
    al, st = m.ALUMINIUM, m.STEEL
    De, D = 46.98, 52.0
    r = row(housing_interference=0.04, housing_material="aluminium", housing_outer_diameter=housing_od,
            outer_ring_temperature=35.0, housing_temperature=45.0)
    u1, u2, p = _direct(_body(De / 2, D / 2, st, 15.0), _body(D / 2, None if housing_od is None else housing_od / 2,
                                                               al, 25.0), D / 2, 0.04)
    assert p > 0
    assert r.housing_fit_pressure == pytest.approx(p, rel=1e-9)
    # the outer raceway's total contraction (fit share + free share) is -2 u_ring(De/2)
    total = r.outer_raceway_contraction + r.outer_raceway_free_contraction
    assert total == pytest.approx(-2 * u1(De / 2), rel=1e-9)
    # operating interference: what the solve's pressure needs through the fit's compliance
    assert r.housing_interference == pytest.approx(2 * p * r.housing_fit.compliance, rel=1e-9)


def test_spinning_hollow_aluminium_shaft_in_a_warm_steel_ring_against_a_direct_solve():
    al, st = m.ALUMINIUM, m.STEEL
    d, Di, d0, n = 25.0, 31.10, 10.0, 20000.0
    r = row(shaft_interference=0.03, shaft_bore=d0, shaft_material="aluminium", inner_ring_temperature=40.0,
            shaft_temperature=35.0, speed=n)
    u1, u2, p = _direct(_body(d0 / 2, d / 2, al, 15.0, n), _body(d / 2, Di / 2, st, 20.0, n), d / 2, 0.03)
    assert p > 0
    assert r.shaft_fit_pressure == pytest.approx(p, rel=1e-9)
    assert r.inner_raceway_growth + r.inner_raceway_free_growth == pytest.approx(2 * u2(Di / 2), rel=1e-9)


def test_a_solid_spinning_shaft_against_a_direct_solve():
    st = m.STEEL
    r = row(shaft_interference=0.02, speed=40000.0)
    u1, u2, p = _direct(_body(0.0, 12.5, st, 0.0, 40000.0), _body(12.5, 15.55, st, 0.0, 40000.0), 12.5, 0.02)
    assert r.shaft_fit_pressure == pytest.approx(p, rel=1e-9)
    assert r.inner_raceway_growth + r.inner_raceway_free_growth == pytest.approx(2 * u2(15.55), rel=1e-9)


def test_a_lost_fit_has_no_pressure_and_the_ring_grows_freely():
    r = row(shaft_interference=0.002, inner_ring_temperature=40.0, shaft_temperature=20.0)
    assert r.shaft_fit.lost and r.shaft_fit_pressure == 0.0 and r.inner_raceway_growth == 0.0
    assert r.shaft_interference == pytest.approx(0.002 - 12.5e-6 * 20 * 25, rel=1e-12)
    assert r.inner_raceway_free_growth == pytest.approx(12.5e-6 * 20 * 31.10, rel=1e-12)
    assert any("shaft fit is lost" in note for note in r.notes)
    # the direct solve would need a tensile interface (negative pressure)
    _, _, p = _direct(_body(0.0, 12.5, m.STEEL, 0.0), _body(12.5, 15.55, m.STEEL, 20.0), 12.5, 0.002)
    assert p < 0


# -- the outer ring rotating ---------------------------------------------------------------------
def test_outer_ring_rotating_with_its_housing():
    with pytest.raises(FieldError, match="housing_outer_diameter.*infinitely thick housing cannot spin"):
        row(rotating="outer", speed=5000)
    r = row(rotating="outer", speed=20000, housing_interference=0.01, housing_outer_diameter=70.0,
            shaft_interference=0.01)
    still = row(rotating="outer", speed=0, housing_interference=0.01, housing_outer_diameter=70.0,
                shaft_interference=0.01)
    assert r.shaft_interference == still.shaft_interference  # the shaft stands
    assert r.housing_interference < still.housing_interference  # the housing grows more than the ring's OD
    assert r.inner_raceway_free_growth == 0.0 and r.outer_raceway_free_contraction < 0.0
    assert math.isfinite(still.housing_fit.loss_speed) and still.shaft_fit.loss_speed == math.inf
    lost = row(rotating="outer", speed=still.housing_fit.loss_speed, housing_interference=0.01,
               housing_outer_diameter=70.0)
    assert lost.housing_interference == pytest.approx(0.0, abs=1e-15)


# -- pairs: axial thermal growth -------------------------------------------------------------------
def test_db_and_df_under_a_warmer_shaft():
    """A warmer shaft lowers a DB pair's preload and raises a DF pair's (issue 44 item 3)."""
    eps_i, eps_o = 12.5e-6 * 30, 12.5e-6 * 10
    for name, sign in (("DB", -1), ("DF", 1)):
        change = m.pair_axial_interference_change(name, 40.0, inner_side_strain=eps_i, outer_side_strain=eps_o)
        assert change == pytest.approx(sign * (eps_i - eps_o) * 40.0, rel=1e-12)
    assert m.pair_axial_interference_change("DT", 40.0, inner_side_strain=eps_i, outer_side_strain=eps_o) == 0.0
    # a warmer housing reverses both
    assert m.pair_axial_interference_change("DB", 40.0, inner_side_strain=0.0, outer_side_strain=eps_o) > 0
    assert m.pair_axial_interference_change("DF", 40.0, inner_side_strain=0.0, outer_side_strain=eps_o) < 0


def test_pair_rows_match_fastbearing_contact_directions():
    from fastbearing.model.bearing import _DOUBLE_ROW_DIRECTIONS
    assert m.PAIR_DIRECTIONS == _DOUBLE_ROW_DIRECTIONS


@pytest.mark.parametrize("arrangement", ["DB", "DF"])
@pytest.mark.parametrize("a0_deg", [15.0, 40.0])
def test_pair_change_against_groove_centres_moved_by_hand(arrangement, a0_deg):
    """Independent geometry, not the module's contact directions: place each row's ball centre at -e, +e, its
    contact line (DB: the inner contact lies axially outside the ball centre; DF: inside), the inner groove
    centre (fi - 0.5) Dw from the ball centre towards the outer contact and the outer groove centre
    (fo - 0.5) Dw towards the inner contact. Move inner-ring points axially by eps_i z, outer-ring points by
    eps_o z; the engine's d0 is the growth of the groove centres' axial separation (uz = s (A0 sin a0 + d0),
    exact in A = hypot(A0 cos a0 - rL, A0 sin a0 + d0)), so each row's change is that growth. The sum over
    the rows is the pair's change of axial interference."""
    e, Dw, fi, fo, a0 = 20.0, 7.94, 0.52, 0.53, math.radians(a0_deg)
    eps_i, eps_o = 4e-4, 1e-4
    out = 1.0 if arrangement == "DB" else -1.0
    total = 0.0
    for zc in (-e, e):
        side = math.copysign(1.0, zc)
        to_inner = np.array([-math.cos(a0), out * side * math.sin(a0)])  # (radial, axial) unit, ball -> P_i
        ci = np.array([0.0, zc]) - (fi - 0.5) * Dw * to_inner  # on the outer contact's side
        co = np.array([0.0, zc]) + (fo - 0.5) * Dw * to_inner
        assert abs(co[1] - ci[1]) == pytest.approx((fi + fo - 1) * Dw * math.sin(a0))  # A0 sin(a0)
        ci_new, co_new = ci + [0.0, eps_i * ci[1]], co + [0.0, eps_o * co[1]]
        total += abs(co_new[1] - ci_new[1]) - abs(co[1] - ci[1])
    change = m.pair_axial_interference_change(arrangement, 2 * e, inner_side_strain=eps_i, outer_side_strain=eps_o)
    A0 = (fi + fo - 1) * Dw
    # equal but for the neglected groove-geometry scaling, of order (eps_i + eps_o) A0 sin(a0) per row
    assert change == pytest.approx(total, abs=2 * (eps_i + eps_o) * A0 * math.sin(a0))
    assert abs(change - total) < 0.01 * abs(change)
    assert abs(change) == pytest.approx((eps_i - eps_o) * 2 * e, rel=1e-12)
    assert (change < 0) == (arrangement == "DB")


def test_tandem_pair_shifts_load_and_keeps_the_sum():
    rows = m.axial_preload_changes((-20.0, 20.0), (1, 1), inner_side_strain=3e-4, outer_side_strain=1e-4)
    assert sum(rows) == pytest.approx(0.0, abs=1e-18)
    assert rows[0] == pytest.approx(-rows[1]) and rows[0] != 0.0


def test_axial_equivalent_of_a_clearance_change_to_first_order():
    """-dPd/(2 tan a) moves the rest groove-centre distance A as the radial change does, to first order."""
    A0, a0 = 0.3, math.radians(25.0)
    for dPd in (-2e-4, -5e-5):
        radial = math.hypot(A0 * math.cos(a0) - dPd / 2, A0 * math.sin(a0)) - A0
        axial_d0 = m.axial_equivalent_of_clearance_change(dPd, 25.0)
        axial = math.hypot(A0 * math.cos(a0), A0 * math.sin(a0) + axial_d0) - A0
        assert axial == pytest.approx(radial, rel=5 * abs(dPd) / A0)


# -- the budget ----------------------------------------------------------------------------------
def test_budget_closes():
    r = row(unmounted_diametral_clearance=0.02, shaft_interference=0.012, housing_interference=0.004,
            housing_material="cast_iron", housing_outer_diameter=80.0, shaft_bore=8.0,
            inner_ring_temperature=55.0, outer_ring_temperature=40.0, ball_temperature=60.0,
            shaft_temperature=50.0, housing_temperature=35.0, speed=15000)
    assert r.unmounted_diametral_clearance - sum(r.clearance_reductions.values()) == pytest.approx(
        r.operating_diametral_clearance, abs=1e-15)
    assert r.ball_growth == pytest.approx(12.5e-6 * 40.0 * 7.94, rel=1e-12)
    keys = r.as_dict()
    for k in ("unmounted_diametral_clearance", "mounted_diametral_clearance", "operating_diametral_clearance",
              "shaft_interference", "housing_interference", "shaft_fit_pressure", "housing_fit_pressure",
              "inner_raceway_growth", "outer_raceway_contraction", "notes"):
        assert k in keys


def test_nothing_to_do_gives_the_unmounted_clearance_exactly():
    for kw in ({}, {"assembly_temperature": 35.0, "inner_ring_temperature": 35.0, "outer_ring_temperature": 35.0},
               {"housing_material": "aluminium", "shaft_material": "cast_iron", "shaft_bore": 10.0}):
        r = row(unmounted_diametral_clearance=0.013, **kw)
        assert r.operating_diametral_clearance == 0.013
        assert r.mounted_diametral_clearance == 0.013
        assert r.notes == ()


def test_loose_fits_leave_the_clearance_alone():
    r = row(unmounted_diametral_clearance=0.01, shaft_interference=-0.005, housing_interference=-0.01)
    assert r.operating_diametral_clearance == 0.01 and r.notes == ()


# -- materials and warnings -----------------------------------------------------------------------
def test_named_materials_carry_thermal_expansion():
    assert set(m.BODY_MATERIALS) == {"steel", "cast_iron", "aluminium"}
    for mat in m.BODY_MATERIALS.values():
        assert 5e-6 < mat.thermal_expansion < 3e-5
        assert set(mat.as_dict()) == {"name", "youngs_modulus", "poisson_ratio", "density", "thermal_expansion"}
    assert m.STEEL.thermal_expansion == 12.5e-6 and m.STEEL.youngs_modulus == 208000.0


def test_materials_are_reported_per_body():
    r = row(housing_material="aluminium", shaft_material={"name": "Ti-6Al-4V", "youngs_modulus": 114000.0,
                                                          "poisson_ratio": 0.34, "density": 4430.0,
                                                          "thermal_expansion": 8.6e-6})
    mats = r.as_dict()["materials"]
    assert set(mats) == {"shaft", "inner_ring", "outer_ring", "balls", "housing"}
    assert mats["housing"]["thermal_expansion"] == m.ALUMINIUM.thermal_expansion
    assert mats["shaft"]["name"] == "Ti-6Al-4V" and mats["balls"]["name"] == "steel"


def test_temperature_defaults():
    """Balls and shaft default to the inner ring's temperature, the housing to the outer ring's, the rings to
    the assembly temperature: an aluminium shaft and housing then grow with their rings' temperatures."""
    kw = dict(shaft_material="aluminium", housing_material="aluminium", shaft_interference=0.02,
              housing_interference=0.02)
    implicit = row(**kw, inner_ring_temperature=50.0, outer_ring_temperature=30.0)
    explicit = row(**kw, inner_ring_temperature=50.0, outer_ring_temperature=30.0, ball_temperature=50.0,
                   shaft_temperature=50.0, housing_temperature=30.0, assembly_temperature=20.0)
    assert implicit == explicit
    assert implicit.shaft_interference == pytest.approx(0.02 + (23.4e-6 - 12.5e-6) * 30 * 25, rel=1e-12)
    assert implicit.housing_interference == pytest.approx(0.02 + (12.5e-6 - 23.4e-6) * 10 * 52, rel=1e-12)


def test_hoop_stress_warning_names_the_stress():
    with pytest.warns(UserWarning, match=r"inner ring hoop stress 143\.8 N/mm\^2 \(as mounted\) exceeds the limit "
                                         r"120 N/mm\^2"):
        r = m.mount_row(**D6205, shaft_interference=0.021)
    assert any(note.startswith("warning: the inner ring hoop stress") for note in r.notes)
    assert not any("hoop" in note for note in row(shaft_interference=0.021, hoop_stress_limit=150.0).notes)


# -- refusals ------------------------------------------------------------------------------------
@pytest.mark.parametrize("kw, field, rule", [
    ({"shaft_bore": 25.0}, "shaft_bore", "must be < the bore d = 25 mm"),
    ({"shaft_bore": -1.0}, "shaft_bore", "must be >= 0"),
    ({"housing_outer_diameter": 52.0}, "housing_outer_diameter", "must be > the ring's outer diameter D = 52 mm"),
    ({"inner_ring_temperature": -300.0}, "inner_ring_temperature", "must be >= -273.15 deg C"),
    ({"housing_temperature": -274.0}, "housing_temperature", "must be >= -273.15 deg C"),
    ({"assembly_temperature": float("nan")}, "assembly_temperature", "must be finite"),
    ({"speed": -1.0}, "speed", "must be >= 0 rpm"),
    ({"rotating": "cage"}, "rotating", "must be one of"),
    ({"shaft_material": "brass"}, "shaft_material", "must be one of"),
    ({"housing_material": {"youngs_modulus": 0.0, "poisson_ratio": 0.3, "density": 7000.0,
                           "thermal_expansion": 1e-5}}, "housing_material.youngs_modulus", "must be > 0"),
    ({"housing_material": {"youngs_modulus": 1e5, "poisson_ratio": 0.3, "density": 7000.0,
                           "thermal_expansion": 12.5}}, "housing_material.thermal_expansion", "1/K"),
    ({"shaft_material": {"youngs_modulus": 1e5}}, "shaft_material", "missing required key"),
    ({"bore": 32.0}, "bore", "must be < the inner raceway diameter"),
    ({"outer_diameter": 46.0}, "outer_diameter", "must be > the outer raceway diameter"),
    ({"shaft_interference": "0.01"}, "shaft_interference", "must be a number"),
])
def test_refusals_name_the_field(kw, field, rule):
    with pytest.raises(FieldError) as info:
        row(**kw)
    assert info.value.field == field
    assert rule in str(info.value)


def test_a_loose_housing_fit_tightened_by_a_warm_outer_ring():
    """A 2 um loose fit, the outer ring 20 K warmer than the housing (both steel): 2 alpha dT D/2 = 13 um of
    growth leaves 11 um of interference running, none as mounted."""
    r = row(unmounted_diametral_clearance=0.02, housing_interference=-0.002, outer_ring_temperature=40.0,
            housing_temperature=20.0)
    assert r.housing_interference == pytest.approx(-0.002 + 12.5e-6 * 20.0 * 52.0, rel=1e-12)
    assert r.housing_fit.mounted_pressure == 0.0 and r.mounted_diametral_clearance == 0.02
    h = 46.98 / 52.0
    assert r.housing_fit_pressure == pytest.approx(0.5 * E_STEEL * r.housing_interference / 52.0 * (1 - h * h),
                                                   rel=1e-12)
    assert r.outer_raceway_contraction == pytest.approx(h * r.housing_interference, rel=1e-12)
