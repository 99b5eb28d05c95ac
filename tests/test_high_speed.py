"""The high-speed ball (fastbearing/high_speed.py; docs/model.md, "High speed"): zero speed is the paper's
model, Kb is df/dq with the balls re-settled, every ball is in equilibrium, an independent slow reference
written from Harris's equations agrees, the physics trends hold, and bad input is refused."""

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import fsolve

import fastbearing as fb
from fastbearing import high_speed as hs
from fastbearing.contacts import ball_contacts

DATA = Path(__file__).parent.parent / "data" / "bearings"
SPINDLE = fb.load_bearing(DATA / "7014C-DB.toml")
GEOMETRY = SPINDLE.geometry
BALL_FILES = ("6305.toml", "3206.toml", "3208.toml", "3210.toml", "3306.toml", "3310.toml", "7014C-DB.toml")


def _arrangements(geometry, preload=0.004):
    """The geometry as a single row and in every double-row arrangement (DB, DF preloaded)."""
    g = replace(geometry, row_spacing=geometry.row_spacing or 20.0)
    preload = preload if g.diametral_clearance <= 0 else 0.0  # a preload needs no clearance
    return {"single": g.bearing("single"), "DB": g.bearing("DB", axial_preload=preload),
            "DF": g.bearing("DF", axial_preload=preload), "DT": g.bearing("DT")}


def _q(rng, scale=0.01):
    return np.array([scale, -0.6 * scale, 2.0 * scale, 2e-4, -3e-4]) * (1.0 + 0.2 * rng.standard_normal(5))


@pytest.mark.parametrize("name", BALL_FILES)
def test_the_high_speed_element_at_zero_speed_is_the_quasi_static_ball(name):
    """spinning_balls itself (not the kernel's shortcut) at omega = 0, every arrangement: 1e-10."""
    rng = np.random.default_rng(1)
    for arrangement, b in _arrangements(fb.load_bearing(DATA / name).geometry).items():
        for _ in range(3):
            q = _q(rng)
            f0, K0 = fb.stiffness(b, q)
            f, K = np.empty(5), np.zeros((5, 5))
            hs.spinning_balls(q, b.ball_table(), b.speed_table, 0.0, 0.0, f, K, None, None, None,
                              hs.new_warm(b.n_balls))
            assert np.abs(f - f0).max() <= 1e-10 * np.abs(f0).max(), (name, arrangement)
            assert np.abs(K - K0).max() <= 1e-10 * np.abs(K0).max(), (name, arrangement)


def test_zero_speed_through_the_public_calls_is_the_paper_model_exactly():
    f = (800.0, -300.0, 1500.0, 2000.0, -5000.0)
    a, b = fb.solve(SPINDLE, f), fb.solve(SPINDLE, f, speed=0.0)
    assert np.array_equal(a.q, b.q) and np.array_equal(a.K, b.K)
    many = fb.solve_many(SPINDLE, [f, f], speed=[0.0, 0.0])
    assert np.array_equal(many.K[0], a.K)


@pytest.mark.parametrize("race_control,rotating", [("outer", "inner"), ("inner", "inner"), ("none", "inner"),
                                                   ("outer", "outer")])
def test_kb_at_speed_is_the_derivative_of_f_with_the_balls_resettled(race_control, rotating):
    """All 25 entries against central differences of f(q), every arrangement, 8 000 and 25 000 rpm."""
    rng = np.random.default_rng(2)
    geometry = replace(GEOMETRY, race_control=race_control, rotating=rotating)
    for arrangement, b in _arrangements(geometry).items():
        for speed in (8000.0, 25000.0):
            q = _q(rng)
            f, K = fb.stiffness(b, q, speed=speed)
            fd = np.empty((5, 5))
            for j in range(5):
                h = 1e-7 if j < 3 else 1e-9
                e = np.zeros(5)
                e[j] = h
                fd[:, j] = (fb.stiffness(b, q + e, speed=speed)[0] - fb.stiffness(b, q - e, speed=speed)[0]) / (2 * h)
            # columns of tilts scaled by the pitch radius: every entry compared in N/mm
            scale = np.array([1, 1, 1, 45.0, 45.0])
            err = np.abs((K - fd) * scale[None, :] / scale[:, None]).max()
            assert err <= 2e-6 * np.abs(K * scale[None, :] / scale[:, None]).max(), (arrangement, speed, err)


def test_every_ball_is_in_equilibrium_at_the_solution():
    for speed in (5000.0, 15000.0, 30000.0):
        r = fb.solve(SPINDLE, (1000.0, 500.0, 2000.0, 10000.0, 0.0), speed=speed)
        assert r.converged
        c = ball_contacts(SPINDLE, r.q, speed=speed)
        assert c.equilibrium_residual.max() <= 1e-10  # settled to 1e-13, or the rounding floor of the lightest
        # and the ring's load is the balls' inner contacts (with no inner friction under outer control)
        assert np.all(c.inner_load >= 0) and np.all(c.outer_load > 0)


def test_a_scratch_without_room_for_the_summaries_is_reported_not_used():
    """The loop keeps its per-chunk summaries in the warm scratch's tail (high_speed.warm_rows): a scratch of
    the warm-start rows alone gets NaN and the 'not settled' bit, never a write past its end."""
    n = SPINDLE.n_balls
    table, speed_table = SPINDLE.ball_table(), SPINDLE.speed_table
    q = np.array([0.002, 0.0, 0.02, 0.0, 0.0])
    small = np.zeros((hs.N_WARM + 1, n))
    f, K = np.empty(5), np.empty((5, 5))
    total, loaded, flags = hs.spinning_balls(q, table, speed_table, 1000.0, 0.0, f, K, None, None, None, small)
    assert flags & 4 and loaded == 0 and np.isnan(total) and np.isnan(f).all() and np.isnan(K).all()
    assert not small.any()
    f_ok = np.empty(5)
    assert hs.spinning_balls(q, table, speed_table, 1000.0, 0.0, f_ok, None, None, None, None, hs.new_warm(n))[2] == 0
    assert np.isfinite(f_ok).all() and f_ok[2] > 0.0


def test_a_warm_started_ball_settles_where_a_cold_one_does():
    """Each ball starts from its last centre moved by dB = -G_B^-1 G_u du: the same equilibrium as from
    the cold guess (to the ball tolerance), whatever the previous point, and far fewer iterations."""
    rng = np.random.default_rng(7)
    table, speed_table = SPINDLE.ball_table(), SPINDLE.speed_table
    n = SPINDLE.n_balls
    omega = 18000.0 * math.pi / 30.0
    warm = hs.new_warm(n)
    states = np.empty((n, hs.N_STATE))
    q_last = _q(rng)
    hs.spinning_balls(q_last, table, speed_table, omega, 0.0, np.empty(5), None, None, None, None, warm)
    for step in (1e-9, 1e-6, 1e-4, 3e-3):
        q = q_last + step * rng.standard_normal(5) * np.array([1, 1, 1, 0.02, 0.02])
        f_cold, K_cold = np.empty(5), np.empty((5, 5))
        hs.spinning_balls(q, table, speed_table, omega, 0.0, f_cold, K_cold, None, None, states, hs.new_warm(n))
        cold_iterations = states[:, hs.STATE_ITERATIONS].sum()
        f, K = np.empty(5), np.empty((5, 5))
        hs.spinning_balls(q, table, speed_table, omega, 0.0, f, K, None, None, states, warm)
        assert np.abs(f - f_cold).max() <= 1e-11 * np.abs(f_cold).max(), step
        assert np.abs(K - K_cold).max() <= 1e-9 * np.abs(K_cold).max(), step
        assert states[:, hs.STATE_RESIDUAL].max() <= 1e-10
        assert states[:, hs.STATE_ITERATIONS].sum() < cold_iterations, step
        q_last = q


def test_inside_a_solve_a_ball_is_linearised_to_second_order_and_flagged_until_settled():
    """With the solver's WARM_LINEARISE set a ball takes one state per evaluation and hands the ring
    F + F_B dB: the force errs by the square of the ball's step (a fraction of a percent from a poor
    start, nothing from a good one), the evaluation is flagged (bit 8) until dB is within LINEAR_RTOL, and
    each further evaluation at the same q squares the ball's step. Without the flag, or with a record, a
    ball is settled exactly."""
    rng = np.random.default_rng(5)
    table, speed_table = SPINDLE.ball_table(), SPINDLE.speed_table
    omega = 18000.0 * math.pi / 30.0
    warm = hs.new_warm(SPINDLE.n_balls)
    q_last = _q(rng)
    hs.spinning_balls(q_last, table, speed_table, omega, 0.0, np.empty(5), None, None, None, None, warm)
    errors = []
    for step in (3e-3, 1e-4, 1e-6):
        q = q_last + step * rng.standard_normal(5) * np.array([1, 1, 1, 0.02, 0.02])
        f_exact, K_exact = np.empty(5), np.empty((5, 5))
        hs.spinning_balls(q, table, speed_table, omega, 0.0, f_exact, K_exact, None, None, None,
                          hs.new_warm(SPINDLE.n_balls))
        scale = np.abs(f_exact).max()
        lin = warm.copy()
        lin[hs.WARM_LINEARISE, 0] = 1.0
        f, K = np.empty(5), np.empty((5, 5))
        flags = hs.spinning_balls(q, table, speed_table, omega, 0.0, f, K, None, None, None, lin)[2]
        errors.append(np.abs(f - f_exact).max() / scale)
        assert errors[-1] <= 1e-3, step
        if step >= 1e-4:
            assert flags & 8, step  # dB beyond LINEAR_RTOL: not the model's yet
        passes = [errors[-1]]
        while flags & 8 and len(passes) < 5:  # each further pass at the same q squares the ball's step
            flags = hs.spinning_balls(q, table, speed_table, omega, 0.0, f, K, None, None, None, lin)[2]
            passes.append(np.abs(f - f_exact).max() / scale)
        assert not flags & 8, (step, passes)
        assert np.abs(f - f_exact).max() <= 1e-12 * scale, step
        assert np.abs(K - K_exact).max() <= 1e-9 * np.abs(K_exact).max(), step
        # the same start without the solver's flag settles exactly (and is never flagged)
        f2 = np.empty(5)
        assert not hs.spinning_balls(q, table, speed_table, omega, 0.0, f2, None, None, None, None,
                                     warm.copy())[2] & 8
        assert np.abs(f2 - f_exact).max() <= 1e-12 * scale
        warm = lin
        warm[hs.WARM_LINEARISE, 0] = 0.0
        q_last = q
    assert errors[1] < 1e-3 * errors[0] and errors[2] <= 1e-12  # a better start: far smaller error


def test_random_loads_and_speeds_converge_honestly_on_every_shipped_ball_bearing():
    """solve_many (warm-started balls, two threads) over random combined loads and speeds up to 40 000 rpm:
    a converged case carries its load at speed and every ball is in equilibrium (to 1e-10 of its forces,
    or for an all-but-unloaded ball to the rounding floor, 1e-9 N); nothing else is called converged."""
    rng = np.random.default_rng(11)
    for name in ("6305.toml", "3306.toml", "7014C-DB.toml"):
        for arrangement, b in _arrangements(fb.load_bearing(DATA / name).geometry).items():
            loads = np.column_stack([rng.uniform(-1, 1, (8, 2)) * 1500.0, rng.uniform(100, 2000, 8),
                                     rng.uniform(-1, 1, (8, 2)) * 2e4])
            if arrangement in ("DB", "DF"):
                loads[::2, 2] *= -1.0
            speeds = rng.uniform(0.0, 40000.0, len(loads))
            out = fb.solve_many(b, loads, speed=speeds, threads=2)
            assert out.converged.mean() > 0.5, (name, arrangement)
            for i in np.flatnonzero(out.converged):
                f, K = fb.stiffness(b, out.q[i], speed=speeds[i])
                assert np.abs(f - loads[i]).max() <= 1e-8 * np.abs(loads[i]).max(), (name, arrangement, i)
                # Kb from the solve's linearised balls is the model's at q
                assert np.abs(out.K[i] - K).max() <= 1e-8 * np.abs(K).max(), (name, arrangement, i)
                c = ball_contacts(b, out.q[i], speed=speeds[i])
                absolute = c.equilibrium_residual * (c.inner_load + c.outer_load + np.abs(c.centrifugal_force))
                assert np.all((c.equilibrium_residual <= 1e-10) | (absolute <= 1e-9)), (name, arrangement, i)


def _harris_ball(A1, A2, p, omega):
    """One ball by Harris's equations (Advanced Concepts, ch. 3) in his variables X1 (axial), X2 (radial),
    delta_i, delta_o, solved with scipy, outer-raceway control, outer ring fixed: written from the
    textbook's form, with atan2 angles and explicit beta, sharing no code with the kernel."""
    ri, ro, Ki, Ko, mass_radius, inertia, gamma = (p[hs.INNER_RADIUS], p[hs.OUTER_RADIUS], p[hs.K_INNER],
                                                   p[hs.K_OUTER], p[hs.MASS_RADIUS], p[hs.INERTIA], p[hs.GAMMA])
    D = p[hs.DIAMETER]

    def parts(x):
        X1, X2, di, do = x
        sin_o, cos_o = X1 / (ro + do), X2 / (ro + do)
        sin_i, cos_i = (A1 - X1) / (ri + di), (A2 - X2) / (ri + di)
        a_i, a_o = math.atan2(sin_i, cos_i), math.atan2(sin_o, cos_o)
        beta = math.atan2(sin_o, cos_o + gamma)
        om = omega * (1 - gamma * math.cos(a_i)) / (1 + math.cos(a_i - a_o))
        oR = -omega / (((math.cos(a_o) + math.tan(beta) * math.sin(a_o)) / (1 + gamma * math.cos(a_o))
                        + (math.cos(a_i) + math.tan(beta) * math.sin(a_i)) / (1 - gamma * math.cos(a_i)))
                       * gamma * math.cos(beta))
        Mg = inertia * oR * om * math.sin(beta)
        Fc = mass_radius * om * om
        Qi, Qo = Ki * max(di, 0) ** 1.5, Ko * max(do, 0) ** 1.5
        return sin_i, cos_i, sin_o, cos_o, Qi, Qo, Mg, Fc

    def eqs(x):
        X1, X2, di, do = x
        sin_i, cos_i, sin_o, cos_o, Qi, Qo, Mg, Fc = parts(x)
        return [(A1 - X1) ** 2 + (A2 - X2) ** 2 - (ri + di) ** 2, X1 ** 2 + X2 ** 2 - (ro + do) ** 2,
                Qi * sin_i - Qo * sin_o + 2 * Mg / D * cos_o,
                Qi * cos_i - Qo * cos_o - 2 * Mg / D * sin_o + Fc]

    A = math.hypot(A1, A2)
    d = max(A - ri - ro, 1e-4)
    x0 = [ro / A * A1, (ro + d / 2) / A * A2, d / 2, d / 2 + 1e-4]
    x = fsolve(eqs, x0, xtol=1e-13)
    sin_i, cos_i, sin_o, cos_o, Qi, Qo, Mg, Fc = parts(x)
    return Qi * cos_i, Qi * sin_i, math.degrees(math.atan2(sin_i, cos_i)), math.degrees(math.atan2(sin_o, cos_o))


def test_the_kernel_agrees_with_harris_equations_solved_by_scipy():
    """A single row under a combined load at 20 000 rpm: every ball's inner contact force and both
    contact angles, and the ring's f, from the slow reference (Harris's X1, X2, delta_i, delta_o form)."""
    b = replace(GEOMETRY, row_spacing=None).bearing("single")
    speed = 20000.0
    omega = speed * math.pi / 30
    q = np.array([0.004, 0.0, 0.02, 0.0, 0.0])
    table, p_all = b.ball_table(), b.speed_table
    f_ref = np.zeros(3)
    c = ball_contacts(b, q, speed=speed)
    for j in range(b.n_balls):
        cpsi, spsi = table[0, j], table[1, j]
        A2 = q[0] * cpsi + q[1] * spsi + table[4, j]
        A1 = q[2] + table[5, j]
        Fr, Fa, ai, ao = _harris_ball(A1, A2, p_all[:, j], omega)
        f_ref += (Fr * cpsi, Fr * spsi, Fa)
        assert math.degrees(c.inner_contact_angle[j]) == pytest.approx(ai, abs=1e-7)
        assert math.degrees(c.outer_contact_angle[j]) == pytest.approx(ao, abs=1e-7)
    f, _ = fb.stiffness(b, q, speed=speed)
    assert np.allclose(f[:3], f_ref, rtol=1e-8, atol=1e-8 * np.abs(f_ref).max())


def test_orbital_speed_reduces_to_the_cage_speed_and_centrifugal_force_to_half_m_dm_omega_squared():
    """With equal angles the kinematics give omega_m = omega/2 (1 - D cos a/dm) (outer ring fixed) and
    F_c = 0.5 m dm omega_m^2 with m = rho pi D^3/6."""
    p = SPINDLE.speed_table[:, 0]
    a = math.radians(20.0)
    omega = 1000.0
    wm, *_ , S, _, _, _, _ = hs.kinematics(math.cos(a), math.sin(a), math.cos(a), math.sin(a), omega, 0.0,
                                           p[hs.GAMMA], False)
    D, dm = GEOMETRY.ball_diameter, GEOMETRY.pitch_diameter
    assert wm == pytest.approx(omega / 2 * (1 - D * math.cos(a) / dm), rel=1e-14)
    mass = 7850 * math.pi * (D * 1e-3) ** 3 / 6
    assert p[hs.MASS_RADIUS] * wm ** 2 == pytest.approx(0.5 * mass * dm * 1e-3 * wm ** 2, rel=1e-14)


def _angles(b, f, speed):
    r = fb.solve(b, f, speed=speed)
    assert r.converged
    c = ball_contacts(b, r.q, speed=speed)
    return r, c.inner_contact_angle.mean(), c.outer_contact_angle.mean()


def test_with_speed_the_outer_angle_falls_the_inner_rises_and_a_row_softens():
    """Single row under a fixed axial load: alpha_o falls and alpha_i rises with speed, kzz and kxx fall;
    silicon-nitride balls (lighter) soften less than steel."""
    steel = replace(GEOMETRY, row_spacing=None).bearing("single")
    hybrid = replace(GEOMETRY, row_spacing=None, ball_density=3200.0).bearing("single")
    load = (0.0, 0.0, 1000.0, 0.0, 0.0)
    last = None
    for speed in (1.0, 6000.0, 12000.0, 18000.0):
        r, ai, ao = _angles(steel, load, speed)
        if last is not None:
            assert ai > last[1] and ao < last[2]
            assert r.K[2, 2] < last[0].K[2, 2] and r.K[0, 0] < last[0].K[0, 0]
        last = (r, ai, ao)
    assert fb.solve(hybrid, load, speed=18000.0).K[2, 2] > last[0].K[2, 2]


def test_the_preloaded_spindle_pair_loses_radial_stiffness_with_speed():
    """The shipped DB pair under a radial load: kxx and kyy fall from rest to 24 000 rpm. (Its kzz rises:
    the fixed-position preload grows as the balls are wedged outward; see the README.)"""
    load = (1000.0, 0.0, 0.0, 0.0, 0.0)
    k = [np.diag(fb.solve(SPINDLE, load, speed=s).K) for s in (0.0, 12000.0, 24000.0)]
    assert k[0][0] > k[1][0] > k[2][0] and k[0][1] > k[1][1] > k[2][1]


def test_bad_speed_input_is_refused_naming_the_field():
    f = (0, 0, 1000.0, 0, 0)
    for bad in (-1.0, math.nan, math.inf, "fast"):
        with pytest.raises(ValueError, match="speed"):
            fb.solve(SPINDLE, f, speed=bad)
    with pytest.raises(ValueError, match=r"speed.*geometry"):
        fb.solve(fb.Bearing.preset("gunduz2013"), f, speed=1000.0)
    with pytest.raises(ValueError, match=r"speed.*roller"):
        fb.solve(fb.load_bearing(DATA / "NU205.toml"), (1000.0, 0, 0, 0, 0), speed=1000.0)
    with pytest.raises(ValueError, match=r"speed\[1\]"):
        fb.solve_many(SPINDLE, [f, f], speed=[0.0, -5.0])
    with pytest.raises(ValueError, match="ball_density"):
        replace(GEOMETRY, ball_density=0.0)
    with pytest.raises(ValueError, match="race_control"):
        replace(GEOMETRY, race_control="cage")
    with pytest.raises(ValueError, match="rotating"):
        replace(GEOMETRY, rotating="both")
    # at zero speed a bearing without geometry is fine
    assert fb.solve(fb.Bearing.preset("gunduz2013"), f, speed=0.0).converged


SPINDLE_MAP = Path(__file__).parent.parent / "data" / "examples" / "spindle-7014-speed.toml"


def _spindle_config(**loadmap):
    from fastbearing.bearing_file import read_toml

    doc = read_toml(SPINDLE_MAP)
    doc["loadmap"] = {"given": "load", **loadmap}
    return doc


def test_a_load_map_over_speed_puts_speed_first_and_matches_single_solves(tmp_path):
    import h5py

    cfg = _spindle_config(speed=[0.0, 15000.0], Fx=500.0, Fz={"start": 200.0, "stop": 1000.0, "num": 5})
    out = fb.loadmap(cfg, tmp_path / "m.h5", progress=False)
    with h5py.File(out) as fh:
        assert fh["K"].shape == (2, 5, 5, 5) and fh["speed"].attrs["units"] == "rpm"
        assert list(fh["speed"][()]) == [0.0, 15000.0]
        assert (fh["status"][()] == 0).all()
        K = fh["K"][()]
    for i, speed in enumerate((0.0, 15000.0)):
        r = fb.solve(SPINDLE, (500.0, 0.0, 600.0, 0.0, 0.0), speed=speed)
        assert np.allclose(K[i, 2], r.K, rtol=1e-8, atol=1e-8 * np.abs(r.K).max())


def test_a_map_at_zero_speed_is_the_quasi_static_map_and_threads_do_not_matter(tmp_path):
    import h5py

    grid = dict(Fx={"start": 0.0, "stop": 1000.0, "num": 3}, Fz={"start": 100.0, "stop": 900.0, "num": 4})
    plain = fb.loadmap(_spindle_config(**grid), tmp_path / "a.h5", progress=False)
    zero = fb.loadmap(_spindle_config(speed=0.0, **grid), tmp_path / "b.h5", progress=False)
    spun1 = fb.loadmap(_spindle_config(speed=[0.0, 20000.0], **grid), tmp_path / "c.h5", progress=False, threads=1)
    spun2 = fb.loadmap(_spindle_config(speed=[0.0, 20000.0], **grid), tmp_path / "d.h5", progress=False, threads=2)
    with h5py.File(plain) as a, h5py.File(zero) as b, h5py.File(spun1) as c, h5py.File(spun2) as d:
        assert np.array_equal(a["K"][()], b["K"][()])
        assert np.array_equal(a["K"][()], c["K"][0])  # the zero-speed slice of a spinning map
        assert np.array_equal(c["K"][()], d["K"][()])


def test_a_case_table_may_carry_the_speed_in_a_sixth_column(tmp_path):
    import h5py

    cases = np.array([[500.0, 0, 600.0, 0, 0, 0.0], [500.0, 0, 600.0, 0, 0, 15000.0]])
    np.save(tmp_path / "cases.npy", cases)
    cfg = _spindle_config(cases=str(tmp_path / "cases.npy"))
    out = fb.loadmap(cfg, tmp_path / "t.h5", progress=False)
    with h5py.File(out) as fh:
        assert list(fh["speed"][()]) == [0.0, 15000.0]
        K = fh["K"][()]
    ref = fb.solve(SPINDLE, cases[1, :5], speed=15000.0).K
    assert np.allclose(K[1], ref, rtol=1e-8, atol=1e-8 * np.abs(ref).max())
    np.save(tmp_path / "bad.npy", cases * np.array([1, 1, 1, 1, 1, -1]))
    with pytest.raises(ValueError, match="speed"):
        fb.loadmap(_spindle_config(cases=str(tmp_path / "bad.npy")), tmp_path / "u.h5", progress=False)


def test_bad_map_speeds_are_refused_before_anything_runs(tmp_path):
    from fastbearing.bearing_file import read_toml

    for bad in (-100.0, [0.0, math.inf], {"start": -1.0, "stop": 5.0, "num": 3}):
        with pytest.raises(ValueError, match="loadmap.speed"):
            fb.loadmap(_spindle_config(speed=bad, Fz=500.0), tmp_path / "x.h5", progress=False)
    paper = read_toml(Path(__file__).parent.parent / "data" / "examples" / "gunduz2013-db-1M.toml")
    paper["loadmap"] = {"given": "load", "Fz": 500.0, "speed": 1000.0}
    with pytest.raises(ValueError, match=r"loadmap.*speed.*geometry"):
        fb.loadmap(paper, tmp_path / "y.h5", progress=False)
    assert not any(tmp_path.iterdir())


def test_a_life_map_at_speed_takes_each_ring_s_own_contacts(tmp_path):
    """L10r in a map over speed = the single-case life at speed (inner ring rotating: the cubic mean of the
    inner contacts, the 10/3 mean of the outer ones), and at 0 rpm the quasi-static life."""
    from fastbearing import life as L

    for rotating in ("inner", "outer"):
        cfg = _spindle_config(speed=[0.0, 16000.0], Fx=[300.0, 1500.0], Fz={"start": 200.0, "stop": 1500.0, "num": 3},
                              life={"rotating": rotating})
        ds = fb.open_dataset(fb.loadmap(cfg, tmp_path / f"life-{rotating}.h5", progress=False))
        F, q = ds["f"].values.reshape(-1, 5), ds["q"].values.reshape(-1, 5)
        speeds = np.repeat([0.0, 16000.0], len(F) // 2)
        L10r = ds["L10r"].values.ravel()
        for i in range(len(F)):
            settings = L.LifeSettings(rotating=rotating, speed=speeds[i] or None, balls_at_speed=speeds[i] > 0)
            ref = L.life(SPINDLE, F[i], q[i], settings)
            assert L10r[i] == pytest.approx(ref.L10r, rel=1e-9), (rotating, i)
            assert ds["L10r_row"].values.reshape(len(F), -1)[i] == pytest.approx(ref.L10r_row, rel=1e-9)
        half = len(F) // 2
        assert not np.allclose(L10r[:half], L10r[half:])  # the speed changed the lives


def test_solve_on_the_command_line_at_speed_reports_every_ball(tmp_path):
    import json

    from conftest import cli_run

    bearing = str(DATA / "7014C-DB.toml")
    r = cli_run("solve", "--bearing", bearing, "--load", "500,0,1000,0,0", "--speed", "18000", "--balls", "--json")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    assert out["speed"] == 18000.0 and out["converged"]
    ball = out["balls"][0]
    for key in ("inner_contact_angle", "outer_contact_angle", "inner_load", "outer_load", "centrifugal_force",
                "gyroscopic_moment", "orbital_speed"):
        assert key in ball
    assert ball["inner_contact_angle"] > ball["outer_contact_angle"] and ball["outer_load"] > ball["inner_load"]
    text = cli_run("solve", "--bearing", bearing, "--load", "500,0,1000,0,0", "--speed", "18000", "--balls")
    assert "speed: 18000 rpm (high-speed model)" in text.stdout and "alpha_o(deg)" in text.stdout
    for bad in ("-5", "nan", "inf"):
        r = cli_run("solve", "--bearing", bearing, "--load", "0,0,1000,0,0", "--speed", bad)
        assert r.returncode == 2 and "--speed" in r.stderr and not r.stdout
    r = cli_run("solve", "--preset", "gunduz2013", "--load", "0,0,1000,0,0", "--speed", "1000")
    assert r.returncode == 2 and "geometry" in r.stderr


def _spindle_passage(**passage):
    from fastbearing.bearing_file import read_toml

    doc = read_toml(SPINDLE_MAP)
    del doc["loadmap"]
    doc["passage"] = {"given": "load", "points": [[500.0, 0.0, 1000.0, 0.0, 0.0]], "positions": 4, **passage}
    return doc


def test_a_passage_table_at_speed_solves_the_high_speed_balls_at_every_cage_position(tmp_path):
    import h5py

    out = fb.passage(_spindle_passage(speed=15000.0), tmp_path / "p.h5", progress=False)
    with h5py.File(out) as fh:
        K, q, status = fh["K"][0], fh["q"][0], fh["status"][0]
        angles = fh["cage_angle"][()]
        assert fh.attrs["speed_rpm"] == 15000.0
        # the time axis comes from the bearing's own geometry: the nominal cage speed
        g = GEOMETRY
        fc = 15000.0 / 120.0 * (1 - g.ball_diameter * math.cos(math.radians(SPINDLE.rows[0].contact_angle))
                                / g.pitch_diameter)
        assert np.allclose(fh["time"][()], angles / (2 * math.pi * fc), rtol=1e-12)
    assert (status == 0).all()
    load = np.array([500.0, 0.0, 1000.0, 0.0, 0.0])
    from fastbearing.kernel import ball_loop

    for p, angle in enumerate(angles):
        balls = SPINDLE.ball_set(float(angle), speed=15000.0)
        f, Kp = np.empty(5), np.empty((5, 5))
        ball_loop(q[p], balls, f, Kp, None, None)
        assert np.abs(f - load).max() <= 1e-8 * np.abs(load).max()  # the load is carried at speed
        assert np.allclose(K[p], Kp, rtol=1e-8, atol=1e-8 * np.abs(Kp).max())
    # zero speed is the quasi-static table bit for bit
    a = fb.passage(_spindle_passage(), tmp_path / "a.h5", progress=False)
    b = fb.passage(_spindle_passage(speed=0.0), tmp_path / "b.h5", progress=False)
    with h5py.File(a) as fa, h5py.File(b) as fb_:
        assert np.array_equal(fa["K"][()], fb_["K"][()])
        assert not np.allclose(fa["K"][()], K[None])  # and the speed changed it


def test_bad_passage_speeds_are_refused_naming_the_field(tmp_path):
    with pytest.raises(ValueError, match=r"passage\.speed"):
        fb.passage(_spindle_passage(speed=-1.0), tmp_path / "x.h5", progress=False)
    with pytest.raises(ValueError, match=r"passage\.shaft_speed.*must equal passage\.speed"):
        fb.passage(_spindle_passage(speed=12000.0, shaft_speed=3000.0, ball_diameter=11.112, pitch_diameter=90.0),
                   tmp_path / "x.h5", progress=False)
    plain = {"bearing": {"preset": "gunduz2013"}, "passage": {"points": [[0.01, 0, 0, 0, 0]], "speed": 3000.0}}
    with pytest.raises(ValueError, match=r"passage\.speed.*geometry"):
        fb.passage(plain, tmp_path / "x.h5", progress=False)
    assert not list(tmp_path.iterdir())


SPINDLE_SHAFT = Path(__file__).parent.parent / "data" / "examples" / "spindle-shaft-speed.toml"


def test_a_shaft_at_speed_is_in_equilibrium_and_its_stiffness_is_the_sum_of_its_bearings_at_speed():
    from fastbearing.shaft import read_shaft, solve_shaft, transfer

    shaft = read_shaft(SPINDLE_SHAFT)
    assert shaft.speed == 18000.0
    result = solve_shaft(shaft)
    assert result.solution.converged and result.speed == 18000.0
    carried = sum(transfer(b.position - shaft.reference).T @ b.reaction for b in result.bearings)
    assert np.allclose(carried, shaft.external_load(), rtol=0, atol=1e-8 * np.abs(shaft.external_load()).max())
    K_sum = sum(transfer(b.position - shaft.reference).T @ b.K @ transfer(b.position - shaft.reference)
                for b in result.bearings)
    assert np.allclose(result.K_system, K_sum, rtol=1e-9, atol=1e-9 * np.abs(K_sum).max())
    for b in result.bearings:  # each bearing's own high-speed answer
        assert np.allclose(fb.stiffness(SPINDLE, b.q, speed=18000.0)[0], b.reaction, rtol=1e-12, atol=1e-9)
    still = solve_shaft(shaft, speed=0.0)
    assert still.speed == 0.0
    assert still.bearings[0].K[0, 0] > 1.3 * result.bearings[0].K[0, 0]  # the preloaded pairs soften radially


def test_shaft_speed_needs_every_bearing_s_geometry_and_the_command_line_reports_it(tmp_path):
    import json
    import subprocess
    import sys

    from fastbearing.bearing_file import read_toml
    from fastbearing.shaft import read_shaft

    doc = read_toml(SPINDLE_SHAFT)
    doc["shaft"]["bearings"][1]["bearing"] = {"preset": "gunduz2013", "arrangement": "DB"}
    doc["shaft"]["bearings"][0]["bearing"] = str(DATA / "7014C-DB.toml")
    with pytest.raises(ValueError, match=r"shaft\.bearings\[1\]\.speed.*geometry"):
        read_shaft(doc)
    doc["shaft"]["speed"] = -5.0
    with pytest.raises(ValueError, match=r"shaft\.speed"):
        read_shaft(doc)
    run = [sys.executable, "-m", "fastbearing.cli", "shaft", str(SPINDLE_SHAFT), "--json"]
    out = json.loads(subprocess.run(run + ["--speed", "9000"], capture_output=True, text=True, check=True).stdout)
    assert out["speed"] == 9000.0 and out["converged"]
    bad = subprocess.run(run + ["--speed", "nan"], capture_output=True, text=True)
    assert bad.returncode == 2 and "--speed" in bad.stderr
