"""Roller rows: sliced line contacts against a slow reference written from the equations, finite
differences, closed forms, published numbers, and bad input."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

import fastbearing as fb
from fastbearing.model.rollers import RollerRow

# K of a whole roller, both raceways in series (Palmgren's steel line contact, 8.06e4 l^(8/9) per raceway):
# 37 310 l^(8/9) N/mm^(10/9).


def k_line(length):
    return 37310.0 * length ** (8.0 / 9.0)


def cylindrical(**kw):
    row = dict(element="cylindrical_roller", n_rollers=14, hertz_constant=k_line(11.05), pitch_radius=35.0,
               roller_effective_length=11.05, slices=30)
    row.update(kw)
    return fb.Bearing.from_rows([row])


def tapered_pair(arrangement="TDO", **kw):
    row = dict(element="tapered_roller", n_rollers=17, hertz_constant=k_line(13.0), pitch_radius=24.0,
               roller_effective_length=13.0, contact_angle=14.0, slices=20, crown="circular", crown_radius=400.0)
    row.update(kw)
    return fb.Bearing.double(arrangement, 9.0, **row)


def reference_f_K(bearing, q):
    """Slow reference from the roller equations (docs/rollers.md): every slice of every roller, in plain Python."""
    dx, dy, dz, bx, by = q
    f = np.zeros(5)
    K = np.zeros((5, 5))
    for r in bearing.rows:
        a = math.radians(r.contact_angle)
        s = r.contact_direction
        n = np.array([math.cos(a), s * math.sin(a)])
        t = np.array([-s * math.sin(a), math.cos(a)])
        w = r.roller_effective_length / r.slices
        for j in range(r.n_rollers):
            psi = math.radians(r.first_element_angle) + 2 * math.pi * j / r.n_rollers
            c, sn = math.cos(psi), math.sin(psi)
            for k in range(r.slices):
                x = -r.roller_effective_length / 2 + (k + 0.5) * w
                R = r.pitch_radius + x * t[0]
                z = r.axial_offset + x * t[1]
                # radial and axial displacement of the inner ring at (R, z, psi) and their gradients
                Jr = np.array([c, sn, 0.0, -z * sn, z * c])
                Jz = np.array([0.0, 0.0, 1.0, R * sn, -R * c])
                dr, dzz = Jr @ q, Jz @ q
                # a preload presses the row whatever its direction s: s d0 axially, d0 sin(a) along n
                delta = n[0] * dr + n[1] * dzz + r.axial_preload * math.sin(a) - r.radial_clearance * math.cos(a)
                delta -= float(r.crown_drop(np.array([x]))[0])
                if delta <= 0:
                    continue
                kw = r.hertz_constant * w / r.roller_effective_length
                Q = kw * delta ** (10 / 9)
                dQ = kw * 10 / 9 * delta ** (1 / 9)
                g = n[0] * Jr + n[1] * Jz
                f += Q * g
                K += dQ * np.outer(g, g)
    return f, K


@pytest.mark.parametrize("make, q", [
    (cylindrical, [0.02, -0.004, 0.0, 0.0004, -0.0003]),
    (lambda: cylindrical(crown="circular", crown_radius=300.0, radial_clearance=0.005), [0.03, 0.01, 0.0, 2e-4, 5e-4]),
    (tapered_pair, [0.01, 0.003, 0.02, 1e-4, -3e-4]),
    (lambda: tapered_pair("TDI", crown="logarithmic", crown_radius=None, crown_design_load=8000.0,
                          axial_preload=0.005), [0.006, 0.0, -0.01, 2e-4, 1e-4]),
])
def test_kernel_equals_the_slow_reference(make, q):
    bearing = make()
    f, K = fb.stiffness(bearing, q)
    f_ref, K_ref = reference_f_K(bearing, np.array(q))
    np.testing.assert_allclose(f, f_ref, rtol=1e-11, atol=1e-9 * np.abs(f_ref).max())
    np.testing.assert_allclose(K, K_ref, rtol=1e-10, atol=1e-9 * np.abs(K_ref).max())
    np.testing.assert_allclose(K, K.T, atol=1e-9 * np.abs(K).max())


@pytest.mark.parametrize("make", [cylindrical, tapered_pair, lambda: tapered_pair("TDI"), lambda: tapered_pair("DT")])
def test_kb_is_the_derivative_of_f(make):
    bearing = make()
    q = np.array([0.012, -0.005, 0.015, 1.5e-4, -2e-4])
    _, K = fb.stiffness(bearing, q)
    h = np.array([1e-7, 1e-7, 1e-7, 1e-9, 1e-9])
    for i in range(5):
        e = np.zeros(5)
        e[i] = h[i]
        fd = (fb.stiffness(bearing, q + e)[0] - fb.stiffness(bearing, q - e)[0]) / (2 * h[i])
        np.testing.assert_allclose(K[:, i], fd, rtol=2e-5, atol=2e-5 * np.abs(K).max())


def test_one_slice_is_the_unsliced_roller_and_slicing_adds_only_the_rollers_own_tilt_stiffness():
    """Uncrowned, no tilt: f and every Kb entry outside the tilt-tilt block do not depend on the slice
    count; the tilt-tilt block grows by each loaded roller's own stiffness of its slices spread along l,
    K'(delta) sum_k (w/l) x_k^2 (n . J-tilt direction)^2, i.e. K'(delta) l^2 (1 - 1/S^2)/12 about the
    roller's own tilt axis for S slices."""
    q = np.array([0.02, 0.0, 0.0, 0.0, 0.0])
    one = cylindrical(slices=1)
    many = cylindrical(slices=40)
    f1, K1 = fb.stiffness(one, q)
    f40, K40 = fb.stiffness(many, q)
    np.testing.assert_allclose(f40, f1, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(K40[:3, :], K1[:3, :], rtol=1e-12, atol=1e-6)
    # the closed form: per loaded roller at psi, slope K' = (10/9) K delta^(1/9); a slice at x along the
    # roller (axial for a cylindrical roller) turns under tilt b by x (bx sin psi - by cos psi) radially
    r = many.rows[0]
    l, S = r.roller_effective_length, r.slices
    extra = np.zeros((2, 2))
    for j in range(r.n_rollers):
        psi = 2 * math.pi * j / r.n_rollers
        delta = 0.02 * math.cos(psi)
        if delta <= 0:
            continue
        slope = 10 / 9 * r.hertz_constant * delta ** (1 / 9)
        g = np.array([-math.sin(psi), math.cos(psi)])   # d(dr)/d(bx, by) per unit x
        extra += slope * l ** 2 * (1 - 1 / S ** 2) / 12 * np.outer(g, g)
    np.testing.assert_allclose(K40[3:, 3:] - K1[3:, 3:], extra, rtol=1e-10, atol=1e-12 * np.abs(extra).max())


def test_uniformly_loaded_roller_carries_K_delta_to_the_ten_ninths_whatever_the_slices():
    for slices in (1, 7, 30, 200):
        b = fb.Bearing.from_rows([dict(element="cylindrical_roller", n_rollers=1, hertz_constant=2.0e5,
                                       pitch_radius=30.0, roller_effective_length=12.0, slices=slices)])
        f, _ = fb.stiffness(b, [0.01, 0, 0, 0, 0])
        assert f[0] == pytest.approx(2.0e5 * 0.01 ** (10 / 9), rel=1e-12)


def test_cylindrical_rows_have_no_axial_stiffness_and_tilt_stiffness_grows_as_length_squared():
    for length in (8.0, 16.0):
        b = cylindrical(roller_effective_length=length, hertz_constant=3.0e5, slices=200)
        r = fb.solve(b, [5000.0, 0, 0, 0, 0])
        assert r.converged and abs(r.K[2, 2]) <= 1e-12 * r.K[0, 0]
        if length == 8.0:
            k_short = r.K[4, 4]
        else:
            assert r.K[4, 4] == pytest.approx(4.0 * k_short, rel=1e-3)


def test_slicing_converges_with_a_crown_and_a_tilt():
    """A circular crown (Rc = 2000 mm, 7.6 um drop at the ends) and a tilt of 0.2 mrad: the entries of the
    loaded directions at 60 and 120 slices agree within 0.2 %. Not every entry does: kyy and ktxtx come
    from the rollers at the edge of the load zone, whose contact ends inside the roller, where a slice's
    stiffness (10/9) k delta^(1/9) jumps as it enters contact; there the midpoint slices converge as
    about h^1.1 (0.6 % and 1.4 % here; docs/rollers.md)."""
    q = [0.02, 0.0, 0.0, 0.0, 2e-4]
    K60 = fb.stiffness(cylindrical(slices=60, crown="circular", crown_radius=2000.0), q)[1]
    K120 = fb.stiffness(cylindrical(slices=120, crown="circular", crown_radius=2000.0), q)[1]
    for i, j in ((0, 0), (4, 4), (0, 4)):
        assert K60[i, j] == pytest.approx(K120[i, j], rel=2e-3)


def test_stribeck_number_of_a_line_contact_bearing():
    """Rigid rings, zero clearance, a roller at psi = 0: Q_max = 4.08 Fr / Z for line contact
    (Stribeck-Sjovall; NSK Technical Report CAT E728g, sec. 5.1, eq. 5)."""
    b = cylindrical(slices=1)
    r = fb.solve(b, [5000.0, 0, 0, 0, 0])
    Q, _ = fb.ball_loads(b, r.q)
    assert Q.max() * 14 / 5000.0 == pytest.approx(4.08, abs=0.01)


def test_published_slice_model_case_with_clearance():
    """github.com/moritzploss/tribology (commit 09bf75d6), tests/tests_tribology.py lines 112-123: an
    NU206-size bearing, rollers of l = 10 mm, K = 35948 l^(8/9) (DIN 26281), diametral clearance
    0.0184 mm, Fr = 3000 N: max roller load 967.7 N. Its azimuths np.linspace(0, 2 pi, 13) hold 12 rollers
    30 deg apart plus a second roller at 0: here a 12-roller row and a 1-roller row at the same place."""
    K = 35948.0 * 10.0 ** (8.0 / 9.0)
    common = dict(element="cylindrical_roller", hertz_constant=K, pitch_radius=23.25, roller_effective_length=10.0,
                  slices=31, radial_clearance=0.0092)
    b = fb.Bearing.from_rows([{**common, "n_rollers": 12}, {**common, "n_rollers": 1}])
    r = fb.solve(b, [3000.0, 0, 0, 0, 0])
    Q, _ = fb.ball_loads(b, r.q)
    assert r.converged and Q.max() == pytest.approx(967.7, abs=0.1)


@pytest.mark.parametrize("row, words", [
    ({"slices": 0}, r"slices must be an integer in \[1, 1000\]"),
    ({"slices": 10 ** 6}, r"slices must be an integer in \[1, 1000\]"),
    ({"crown": "circular", "crown_radius": 5.0}, r"crown_radius must be .*> 5.525"),
    ({"crown": "circular"}, "crown_radius is required"),
    ({"crown": "parabolic"}, "crown must be one of"),
    ({"roller_effective_length": 100.0}, "roller_effective_length must be <= 2 pitch_radius"),
    ({"element": "needle"}, "element must be one of"),
    ({"contact_angle": 10.0}, "contact_angle must be"),
    ({"groove_center_distance": 0.5}, r"unknown key\(s\) \['groove_center_distance'\]"),
])
def test_bad_roller_rows_name_the_field(row, words):
    base = dict(element="cylindrical_roller", n_rollers=14, hertz_constant=3e5, pitch_radius=35.0,
                roller_effective_length=11.05)
    with pytest.raises(ValueError, match=words):
        fb.Bearing.from_rows([{**base, **row}])


def test_ball_and_roller_rows_mix_and_arrangements_have_tapered_names():
    ball = dict(n_balls=14, hertz_constant=395000.0, pitch_radius=34.75, groove_center_distance=0.52,
                contact_angle=30.0, axial_offset=-20.0)
    roller = dict(element="cylindrical_roller", n_rollers=14, hertz_constant=3e5, pitch_radius=35.0,
                  roller_effective_length=11.05, axial_offset=20.0)
    b = fb.Bearing.from_rows([ball, roller])
    r = fb.solve(b, [3000.0, 0, 1000.0, 0, 0])
    assert r.converged and b.n_elements == 28 and len(fb.ball_loads(b, r.q)[0]) == 28
    # the record: balls first, then each roller's total load, as in a bearing of that row alone
    alone = fb.Bearing.from_rows([roller])
    np.testing.assert_allclose(fb.ball_loads(b, r.q)[0][14:], fb.ball_loads(alone, r.q)[0], rtol=1e-12)
    tdo, db = tapered_pair("TDO"), tapered_pair("DB")
    assert [x.contact_direction for x in tdo.rows] == [x.contact_direction for x in db.rows] == [1, -1]
    assert isinstance(tdo.rows[0], RollerRow)


def test_maps_passage_tables_and_pictures_take_roller_rows(tmp_path):
    """The same sweeps and writer: a map of a TDO pair equals its solves; a passage table runs; the load
    zone draws rollers."""
    bearing = {"name": "TDO", "arrangement": "TDO", "element": "tapered_roller", "n_rollers": 17,
               "hertz_constant": k_line(13.0), "pitch_radius": 24.0, "roller_effective_length": 13.0,
               "contact_angle": 14.0, "row_offset": 9.0, "slices": 12, "crown": "circular",
               "crown_radius": 1500.0, "axial_preload": 0.005}
    out = fb.loadmap({"bearing": bearing, "loadmap": {"Fx": [0.0, 8000.0], "Fz": [-2000.0, 3000.0],
                                                      "My": [0.0, 5.0e4]}}, tmp_path / "m.h5", progress=False)
    ds = fb.open_dataset(out)
    b = fb.bearing_from_table(bearing)
    r = fb.solve(b, [8000.0, 0, 3000.0, 0, 5.0e4])
    np.testing.assert_allclose(ds["K"].sel(Fx=8000.0, Fz=3000.0, My=5.0e4).values, r.K, rtol=1e-8,
                               atol=1e-8 * np.abs(r.K).max())
    Q, _ = fb.ball_loads(b, r.q)
    assert ds["max_ball_load"].sel(Fx=8000.0, Fz=3000.0, My=5.0e4).values.max() == pytest.approx(Q.max(), rel=1e-6)
    assert (ds["status"].values == 0).all()
    table = fb.passage({"bearing": bearing, "passage": {"given": "load", "points": [[6000.0, 0, 1000.0, 0, 0]],
                                                        "positions": 8}}, tmp_path / "p.h5", progress=False)
    assert (fb.open_dataset(table)["status"].values == 0).all()
    pytest.importorskip("matplotlib")
    from fastbearing.report.plot import plot_load_zone

    fig = plot_load_zone(b, r.q)
    assert "rollers loaded" in fig.axes[0].get_title()


DATA = __import__("pathlib").Path(__file__).resolve().parents[1] / "data"


def test_roller_rows_from_catalogue_geometry():
    """K from Palmgren's line contact, 8.06e4 l^(8/9) per raceway, two raceways in series:
    37 310 l^(8/9) N/mm^(10/9) for steel; other materials by E'/E'_steel; pitch radius dm/2; rL = Pd/2."""
    from fastbearing.model.roller_geometry import RollerGeometry, line_constant
    from fastbearing.model.geometry import SILICON_NITRIDE

    assert line_constant(10.0) == pytest.approx(37310.0 * 10.0 ** (8 / 9), rel=2e-4)
    per_raceway = 8.06e4 * 10.0 ** (8 / 9)
    assert line_constant(10.0) == pytest.approx(per_raceway * 2 ** (-10 / 9), rel=1e-3)
    steel = RollerGeometry("cylindrical_roller", 13, 7.5, 7.0, 39.0, diametral_clearance=0.02)
    row = steel.bearing().rows[0]
    assert row.pitch_radius == 19.5 and row.radial_clearance == 0.01
    ceramic = RollerGeometry("cylindrical_roller", 13, 7.5, 7.0, 39.0, roller_material=SILICON_NITRIDE)
    assert ceramic.hertz_constant / steel.hertz_constant == pytest.approx(
        ceramic.reduced_modulus / steel.reduced_modulus, rel=1e-12)
    with pytest.raises(ValueError, match="n_rollers must be <= "):
        RollerGeometry("cylindrical_roller", 40, 7.5, 7.0, 39.0)
    with pytest.raises(ValueError, match="contact_angle must be"):
        RollerGeometry("cylindrical_roller", 13, 7.5, 7.0, 39.0, contact_angle=10.0)


def test_shipped_roller_bearings_and_shafts():
    for name in ("NU205", "30206", "30206-TDO"):
        b = fb.load_bearing(DATA.parent / "fastbearing" / "catalogue" / f"{name}.toml")
        assert b.roller_rows and b.geometry is not None
    nu = fb.load_bearing(DATA.parent / "fastbearing" / "catalogue" / "NU205.toml")
    r = fb.solve(nu, [5000.0, 0, 0, 0, 0])
    assert r.converged and abs(r.K[2, 2]) < 1e-9 * r.K[0, 0]
    axial = fb.solve(nu, [5000.0, 0, 1000.0, 0, 0])                   # a cylindrical row holds no axial load
    assert axial.status_name == "singular"
    pair = fb.load_bearing(DATA.parent / "fastbearing" / "catalogue" / "30206-TDO.toml")
    assert pair.arrangement == "TDO" and fb.solve(pair, [8000.0, 0, 2000.0, 0, 1e5]).converged
    from fastbearing.analysis.shaft import read_shaft, solve_shaft

    gear = solve_shaft(read_shaft(DATA / "examples" / "gearbox-tapered-pair.toml"))
    assert gear.solution.converged
    np.testing.assert_allclose(sum(b.reaction[:3] for b in gear.bearings), [4000.0, 0.0, 1500.0], atol=1e-6)
    mixed = solve_shaft(read_shaft(DATA / "examples" / "shaft-cylindrical-and-ball.toml"))
    assert mixed.solution.converged
    assert mixed.bearings[0].reaction[2] == pytest.approx(0.0, abs=1e-9)   # the floating NU carries no axial load
    assert mixed.bearings[1].reaction[2] == pytest.approx(500.0)


def test_slice_record_edge_loading_and_line_contact_pressure():
    """Under a tilt the most loaded slice of an uncrowned roller is its end slice (edge loading); the
    rollers' totals are the sums of their slices; the pressure is Hertz's line contact
    p = sqrt((q/w) E' / (2 pi R)), R = Dw (1 -+ g)/2."""
    from fastbearing.analysis.contacts import roller_contacts
    from fastbearing.model.roller_geometry import RollerGeometry

    g = RollerGeometry("cylindrical_roller", 13, 7.5, 7.0, 39.0, slices=20)
    b = g.bearing()
    q = [0.01, 0.0, 0.0, 0.0, 4e-4]
    rc = roller_contacts(b, q)
    loaded = rc.load > 0
    x_end = b.rows[0].slice_positions[-1]
    top = int(np.argmax(rc.load))
    assert abs(rc.max_slice_position[top]) == pytest.approx(x_end)
    np.testing.assert_allclose(rc.load, fb.ball_loads(b, q)[0], rtol=1e-12)
    w = 7.0 / 20
    gam = 7.5 / 39.0
    expect = np.sqrt(rc.max_slice_load[loaded] / w * g.reduced_modulus / (math.pi * 7.5 * (1 - gam)))
    np.testing.assert_allclose(rc.inner_max_pressure[loaded], expect, rtol=1e-12)
    assert (rc.outer_max_pressure[loaded] < rc.inner_max_pressure[loaded]).all()
    from conftest import cli_run

    text = cli_run("solve", "--bearing", DATA.parent / "fastbearing" / "catalogue" / "NU205.toml", "--load", "5000,0,0,0,2e4", "--balls").stdout
    assert "rollers (psi azimuth" in text and "p_in(MPa)" in text


# -- preload of tapered pairs (issue 33) ---------------------------------------------------------------

def shipped_pair(arrangement):
    """fastbearing/catalogue/30206-TDO.toml as shipped (d0 = 0.005 mm per row), or the same file face to face."""
    import tomllib

    doc = tomllib.loads((DATA.parent / "fastbearing" / "catalogue" / "30206-TDO.toml").read_text())
    doc["bearing"]["arrangement"] = arrangement
    return fb.bearing_from_table(doc["bearing"])


def row_loads(bearing, q):
    """Each row's total roller load in N at q."""
    from fastbearing.analysis.contacts import slice_loads

    totals, _ = slice_loads(bearing, q)
    rows = bearing.element_rows[bearing.n_balls:]
    return np.array([totals[rows == i].sum() for i, _ in bearing.roller_rows])


@pytest.mark.parametrize("arrangement", ["TDO", "TDI"])
def test_axial_preload_presses_both_rows_of_a_tapered_pair(arrangement):
    """d0 adds d0 sin(a) to the approach of either row (as a ball row's s d0 on the axial approach does):
    at q = 0 both rows carry the same load and f = 0; the preload stiffens the pair; the unloaded pair
    solves to q = 0 with its rollers loaded. (Before: s d0 sin(a) preloaded one row and gave the other
    clearance, f(0) = (0, 0, 161 N, 0, 0), kxx at 2 kN the same with and without preload, and f = 0
    solved at dz = -0.0049 mm with every roller unloaded.)"""
    pair = shipped_pair(arrangement)
    free = pair.with_rows(axial_preload=0.0)
    assert [r.axial_preload for r in pair.rows] == [0.005, 0.005]
    loads = row_loads(pair, np.zeros(5))
    r = pair.rows[0]
    each = r.n_rollers * r.hertz_constant / r.slices * np.sum(np.maximum(
        0.005 * math.sin(math.radians(r.contact_angle)) - r.crown_drop(r.slice_positions), 0.0) ** (10 / 9))
    np.testing.assert_allclose(loads, [each, each], rtol=1e-12)          # 673 N a row
    f0, K0 = fb.stiffness(pair, np.zeros(5))
    L = pair.length_scale
    assert np.abs(f0[:3]).max() <= 1e-12 * loads.sum() and np.abs(f0[3:]).max() <= 1e-12 * loads.sum() * L
    assert K0[0, 0] > 0 and K0[2, 2] > 0                                  # preloaded: stiff at rest
    stiff, soft = fb.solve(pair, [2000.0, 0, 0, 0, 0]), fb.solve(free, [2000.0, 0, 0, 0, 0])
    assert stiff.converged and soft.converged
    assert stiff.K[0, 0] > 1.01 * soft.K[0, 0] and stiff.K[2, 2] > 1.1 * soft.K[2, 2]    # 1.9 %, 22 %
    rest = fb.solve(pair, np.zeros(5))
    assert rest.converged and np.abs(rest.q).max() <= 1e-12
    assert row_loads(pair, rest.q).min() > 600.0


@pytest.mark.parametrize("arrangement", ["TDO", "TDI"])
def test_preloaded_pair_equals_both_references_at_random_q(arrangement, rng):
    """The shipped preloaded pair against the slow float64 reference (f and Kb) and the extended-precision
    one of tests/naive.py (f), at random q around the preload's own deflection."""
    from naive import roller_load_extended

    pair = shipped_pair(arrangement)
    for _ in range(5):
        q = np.concatenate([rng.uniform(-0.005, 0.005, 3), rng.uniform(-2e-4, 2e-4, 2)])
        f, K = fb.stiffness(pair, q)
        f_ref, K_ref = reference_f_K(pair, q)
        np.testing.assert_allclose(f, f_ref, rtol=1e-11, atol=1e-10 * np.abs(f_ref).max())
        np.testing.assert_allclose(K, K_ref, rtol=1e-10, atol=1e-10 * np.abs(K_ref).max())
        np.testing.assert_allclose(f, roller_load_extended(q, pair).astype(float), rtol=1e-12,
                                   atol=1e-12 * np.abs(f_ref).max())


# -- bounds on interference and preload (issue 33) -----------------------------------------------------

def bound_words(field, bound):
    """The refusal's words: the field, then its bound in mm as the message prints it."""
    return rf"{field} must be {'>=' if 'clearance' in field else '<='} {bound:.6g} mm"


@pytest.mark.parametrize("make, key, value, bound", [
    # tapered: l = 13 mm, a = 14 deg, d0 sin(a) - rL cos(a) <= 0.005 l = 0.065 mm
    (tapered_pair, "radial_clearance", -5.0, -0.065 / math.cos(math.radians(14.0))),
    (tapered_pair, "axial_preload", 5.0, 0.065 / math.sin(math.radians(14.0))),
    (cylindrical, "radial_clearance", -0.06, -0.005 * 11.05),
])
def test_roller_interference_and_preload_are_bounded(make, key, value, bound):
    """A preload or interference may press each roller by at most 0.005 l (PRELOAD_APPROACH_LIMIT), where
    steel rollers reach their static rating's contact pressure; just inside the bound still solves."""
    from fastbearing.model.rollers import PRELOAD_APPROACH_LIMIT

    assert PRELOAD_APPROACH_LIMIT == 0.005
    with pytest.raises(ValueError, match=bound_words(f"rows\\[0\\]\\.{key}", bound)):
        make(**{key: value})
    assert fb.solve(make(**{key: 0.999 * bound}), [1000.0, 0, 0, 0, 0]).converged


def test_bounds_name_what_the_bearing_file_says(tmp_path):
    """In a geometry file the user types diametral_clearance (Pd = 2 rL) and [bearing] axial_preload: the
    refusals name those keys and their bounds (l = 12 mm, a = 13.86 deg: Pd >= -0.12 / cos(a) mm,
    d0 <= 0.06 / sin(a) mm); every shipped roller file is within them."""
    text = (DATA.parent / "fastbearing" / "catalogue" / "30206-TDO.toml").read_text()
    a = math.radians(13.86)
    for old, new, words in (
            ("diametral_clearance = 0.0", "diametral_clearance = -10.0",
             bound_words(r"bearing\.geometry\.diametral_clearance", -0.12 / math.cos(a))),
            ("axial_preload = 0.005", "axial_preload = 5.0",
             bound_words(r"bearing\.axial_preload", 0.06 / math.sin(a)))):
        assert old in text
        path = tmp_path / "pair.toml"
        path.write_text(text.replace(old, new))
        with pytest.raises(ValueError, match=words):
            fb.load_bearing(path)
    for path in sorted((DATA.parent / "fastbearing" / "catalogue").glob("*.toml")):
        fb.load_bearing(path)


def test_an_axial_clearance_is_not_bounded():
    """d0 < 0 on a tapered row is an axial clearance: the rollers' normal is fixed, so no contact direction
    can turn round (a ball row's bound -A0 sin(a0) has no roller counterpart); the pair takes it up."""
    pair = tapered_pair(axial_preload=-0.05)
    r = fb.solve(pair, [3000.0, 0, 1000.0, 0, 0])
    assert r.converged and row_loads(pair, r.q).max() > 0


def test_a_single_tapered_row_under_a_pure_radial_load_says_why_it_has_no_solution():
    """The fixed contact normal turns Fr into an axial load: without at least Fr tan(a) of axial load on its
    side there is no solution. Said in one line, with no numbers that pass for results (issue 33: it printed
    `status: singular`, dx = 179 mm, dz = -727 mm and a Kb); with enough axial load it solves."""
    from conftest import cli_run

    path = Path(__file__).parents[1] / "fastbearing" / "catalogue" / "30206.toml"
    b = fb.load_bearing(path)
    r = fb.solve(b, [5000.0, 0, 0, 0, 0])
    need = 5000.0 * math.tan(math.radians(b.rows[0].contact_angle))
    assert not r.converged and "no solution" in r.note and f"{need:g} N" in r.note
    s = cli_run("solve", "--bearing", path, "--load", "5000,0,0,0,0")
    assert s.returncode == 1 and "no solution" in s.stdout and "--fix dz=0" in s.stdout
    assert "q (mm" not in s.stdout and "Kb" not in s.stdout and "dx=" not in s.stdout
    assert json.loads(cli_run("solve", "--bearing", path, "--load", "5000,0,0,0,0", "--json").stdout)["note"] == r.note
    ok = fb.solve(b, [5000.0, 0, 2000.0, 0, 0])
    assert ok.converged and "tilted freely" in ok.note  # solved: the note says the ring tilted (issue 34)
