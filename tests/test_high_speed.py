"""The high-speed ball (fastbearing/engine/high_speed.py; docs/model.md, "High speed"): zero speed is the paper's
model, Kb is df/dq with the balls re-settled, every ball is in equilibrium, an independent slow reference
written from Harris's equations agrees, the physics trends hold, and bad input is refused."""

import json
import math
import warnings
from dataclasses import replace
from pathlib import Path

import h5py
import numpy as np
import pytest
from scipy.optimize import fsolve

import fastbearing as fb
from fastbearing.engine import high_speed as hs
from fastbearing.engine import schema
from fastbearing.analysis.contacts import ball_contacts

DATA = Path(__file__).parent.parent / "fastbearing" / "catalogue"
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
    """The loop keeps its per-chunk summaries in the warm scratch's tail (high_speed.warm_size): a scratch of
    the warm starts alone (or of another ball set) gets NaN and the 'not settled' bit, never a write past its
    end."""
    n = SPINDLE.n_balls
    table, speed_table = SPINDLE.ball_table(), SPINDLE.speed_table
    q = np.array([0.002, 0.0, 0.02, 0.0, 0.0])
    small = np.zeros(schema.N_WARM * n + 1)
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
    states = np.empty((n, schema.N_STATE))
    q_last = _q(rng)
    hs.spinning_balls(q_last, table, speed_table, omega, 0.0, np.empty(5), None, None, None, None, warm)
    for step in (1e-9, 1e-6, 1e-4, 3e-3):
        q = q_last + step * rng.standard_normal(5) * np.array([1, 1, 1, 0.02, 0.02])
        f_cold, K_cold = np.empty(5), np.empty((5, 5))
        hs.spinning_balls(q, table, speed_table, omega, 0.0, f_cold, K_cold, None, None, states, hs.new_warm(n))
        cold_iterations = states[:, schema.STATE_ITERATIONS].sum()
        f, K = np.empty(5), np.empty((5, 5))
        hs.spinning_balls(q, table, speed_table, omega, 0.0, f, K, None, None, states, warm)
        assert np.abs(f - f_cold).max() <= 1e-11 * np.abs(f_cold).max(), step
        assert np.abs(K - K_cold).max() <= 1e-9 * np.abs(K_cold).max(), step
        assert states[:, schema.STATE_RESIDUAL].max() <= 1e-10
        assert states[:, schema.STATE_ITERATIONS].sum() < cold_iterations, step
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
        lin[schema.WARM_LINEARISE * SPINDLE.n_balls] = 1.0
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
        warm[schema.WARM_LINEARISE * SPINDLE.n_balls] = 0.0
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
    ri, ro, Ki, Ko, mass_radius, inertia, gamma = (p[schema.INNER_RADIUS], p[schema.OUTER_RADIUS], p[schema.K_INNER],
                                                   p[schema.K_OUTER], p[schema.MASS_RADIUS], p[schema.INERTIA], p[schema.GAMMA])
    D = p[schema.DIAMETER]

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


# -- an independent Jones-Harris ball, any race control and either ring turning ------------------------------
def _jones_harris_ball(A1, A2, a0, c, w_i, w_o):
    """One ball by Jones-Harris (Harris & Kotzalas, Advanced Concepts, ch. 3), solved with scipy for the ball
    centre (Harris's X1 axial, X2 radial; the deflections follow from it); frame mirrored so that the row's
    contact direction is +z. Kinematics from rolling without slip at both contacts about the spin axis at
    beta (tan beta = sin a_o/(cos a_o + gamma') under outer control, sin a_i/(cos a_i - gamma') under inner),
    written out from the contact velocities, not from the kernel's closed forms. A ball is free where its
    own equilibrium on the outer race alone (no inner contact, so no friction there: the outer race carries
    the gyroscopic moment, lambda_o = 2, and controls) clears the inner race; else it is wedged. Returns the
    ring's share: (F_r, F_z, m) with F = Q_i n_i + lambda_i (M_g/D) t_i and m = lambda_i f_i M_g, the lever
    of the inner friction about the inner groove centre; nothing from a free ball."""
    ri, ro, Ki, Ko, mass_radius, J, gamma, D, fi, li, lo, inner = c

    def parts(x, Ki, li, lo, inner):
        X1, X2 = x
        do, di = math.hypot(X1, X2) - ro, math.hypot(A1 - X1, A2 - X2) - ri
        sin_o, cos_o = X1 / (ro + do), X2 / (ro + do)
        sin_i, cos_i = (A1 - X1) / (ri + di), (A2 - X2) / (ri + di)
        tan_b = sin_i / (cos_i - gamma) if inner else sin_o / (cos_o + gamma)
        beta = math.atan(tan_b)
        X_i = (1 - gamma * cos_i) / (cos_i + tan_b * sin_i)  # race speed over ball speed at each contact
        X_o = (1 + gamma * cos_o) / (cos_o + tan_b * sin_o)
        om = (w_i * X_i + w_o * X_o) / (X_i + X_o)
        oR = -(om - w_o) * X_o / (gamma * math.cos(beta))
        Mg = J * oR * om * math.sin(beta)
        Qi, Qo = Ki * max(di, 0) ** 1.5, Ko * max(do, 0) ** 1.5
        residual = [Qi * sin_i - Qo * sin_o - li * Mg / D * cos_i + lo * Mg / D * cos_o,
                    Qi * cos_i - Qo * cos_o + li * Mg / D * sin_i - lo * Mg / D * sin_o + mass_radius * om * om]
        return residual, Qi, Qo, Mg, sin_i, cos_i, di, mass_radius * om * om

    def solve(x, *constants):
        with warnings.catch_warnings():  # a failed try is judged by its residual below
            warnings.simplefilter("ignore", RuntimeWarning)
            x = fsolve(lambda y: parts(y, *constants)[0], x, xtol=1e-15)
        residual, Qi, Qo, Mg, sin_i, cos_i, di, Fc = parts(x, *constants)
        return x, np.abs(residual).max() <= 1e-9 * (Qi + Qo + Fc + 1.0), Qi, Mg, sin_i, cos_i, di

    # room to be free: on the outer race's bottom under F_c at the nominal orbital speed, clear of the inner race
    wm = 0.5 * (w_i * (1 - gamma * math.cos(a0)) + w_o * (1 + gamma * math.cos(a0)))
    Fc0 = mass_radius * wm * wm
    X2 = ro + (Fc0 / Ko) ** (2 / 3)
    if Fc0 > 0 and math.hypot(A1, A2 - X2) <= ri:
        x, ok, *_, di = solve([0.0, X2], 0.0, 0.0, li + lo, False)
        if ok and di <= 0:
            return 0.0, 0.0, 0.0
    # wedged: start where the circles about O and I of radii ro + delta_o, ri + delta_i cross on the outer
    # side, with Q_o = Q_i + F_c and Q_i = F_c / 4 or the load at rest
    A = math.hypot(A1, A2)
    Q_rest = (Ki ** (-2 / 3) + Ko ** (-2 / 3)) ** -1.5 * max(A - ri - ro, 0) ** 1.5
    Qi0 = max(Q_rest, Fc0 / 4)
    Ro, Ri = ro + ((Qi0 + Fc0) / Ko) ** (2 / 3), ri + (Qi0 / Ki) ** (2 / 3)
    along = (A * A + Ro * Ro - Ri * Ri) / (2 * A)
    across = math.sqrt(max(Ro * Ro - along * along, 0.0))
    side = 1.0 if A1 >= 0 else -1.0  # the crossing at the larger radius (X2)
    x = np.array([along * A1 - side * across * A2, along * A2 + side * across * A1]) / A
    x, ok, Qi, Mg, sin_i, cos_i, di = solve(x, Ki, li, lo, inner)
    assert ok, (A1, A2, x)
    if di <= 0:  # the wedged guess let it out: free after all (up the outer groove, held by its friction)
        return 0.0, 0.0, 0.0
    return Qi * cos_i + li * Mg / D * sin_i, Qi * sin_i - li * Mg / D * cos_i, li * fi * Mg


def jones_harris_load(bearing, q, speed):
    """f (N, N*mm) of a ball bearing at shaft speed ``speed`` (rpm) from :func:`_jones_harris_ball`, ball by
    ball, from the rows' and the geometry's public fields (no kernel table)."""
    g = bearing.geometry
    D, dm = g.ball_diameter, g.pitch_diameter
    omega = speed * math.pi / 30
    w_i, w_o = (0.0, omega) if g.rotating == "outer" else (omega, 0.0)
    li, lo = {"outer": (0.0, 2.0), "inner": (1.0, 1.0), "none": (0.0, 0.0)}[g.race_control]
    mass = g.density * math.pi * (D * 1e-3) ** 3 / 6
    f = np.zeros(5)
    dx, dy, dz, bx, by = q
    for row in bearing.rows:
        a0 = math.radians(row.contact_angle)
        inner, outer = g.contacts(a0)
        c = ((g.inner_groove_ratio - 0.5) * D, (g.outer_groove_ratio - 0.5) * D, inner.constant, outer.constant,
             mass * dm / 2 * 1e-3, mass * D * D / 10 * 1e-3, D / dm, D, g.inner_groove_ratio, li, lo,
             g.race_control == "inner")
        z, R, s, A0 = row.axial_offset, row.pitch_radius, row.contact_direction, row.groove_center_distance
        for j in range(row.n_balls):
            psi = math.radians(row.first_ball_angle) + 2 * math.pi * j / row.n_balls
            cp, sp = math.cos(psi), math.sin(psi)
            A2 = (dx + z * by) * cp + (dy - z * bx) * sp - row.radial_clearance + A0 * math.cos(a0)
            A1 = s * (dz + R * (bx * sp - by * cp)) + A0 * math.sin(a0) + row.axial_preload
            Fr, Fz, m = _jones_harris_ball(A1, A2, a0, c, w_i, w_o)
            Fz, m = s * Fz, s * m  # back from the mirrored frame
            mo = R * Fz - z * Fr + m
            f += (Fr * cp, Fr * sp, Fz, mo * sp, -mo * cp)
    return f


@pytest.mark.parametrize("speed, load", [(12000.0, (0.0, 0.0, 500.0, 0.0, 0.0)),
                                         (12000.0, (1000.0, 0.0, 500.0, 0.0, 0.0)),
                                         (24000.0, (0.0, 0.0, 1000.0, 0.0, 0.0)),
                                         (24000.0, (1000.0, 0.0, 1000.0, 0.0, 0.0))])
def test_inner_race_control_moment_rows_against_the_jones_harris_reference(load, speed):
    """A single 7014-class row under inner-race control: the solved q carries the load by the reference's f
    (moments included: the inner friction's lever is f_i D, its moment lambda_i f_i M_g; it was D times
    larger, and the tilt and moment rows of Kb 4-73 % off), and Kb, every entry, equals central differences
    of the reference's f. (At 24 000 rpm an axial 500 N lies in the model's gap: next test.)"""
    b = replace(GEOMETRY, row_spacing=None, race_control="inner").bearing("single")
    r = fb.solve(b, load, speed=speed)
    assert r.converged
    L = b.rows[0].pitch_radius
    scale = np.array([1, 1, 1, 1 / L, 1 / L])  # moments compared as forces at the pitch radius
    f_ref = jones_harris_load(b, r.q, speed)
    assert np.abs((f_ref - load) * scale).max() <= 1e-8 * np.abs(np.asarray(load) * scale).max()
    K_ref = np.empty((5, 5))
    for j in range(5):
        h = 1e-7 if j < 3 else 1e-9
        e = np.zeros(5)
        e[j] = h
        K_ref[:, j] = (jones_harris_load(b, r.q + e, speed) - jones_harris_load(b, r.q - e, speed)) / (2 * h)
    Ks = r.K * scale[:, None] / scale[None, :]
    assert np.abs(Ks - K_ref * scale[:, None] / scale[None, :]).max() <= 1e-5 * np.abs(Ks).max()


def test_inner_race_control_has_a_load_gap_where_balls_leave_the_inner_race_and_says_so():
    """Under inner control the inner friction carrying M_g does not fall with Q_i, so Fz(dz) of a single row
    at 24 000 rpm jumps from 0 to about 660 N where the balls leave the inner race (the reference shows the
    same jump): an axial 500 N has no solution, and the solve says so instead of calling a wedged, path-
    dependent state converged (it once returned such a q, whose f evaluated afresh was 242 N, not 500)."""
    b = replace(GEOMETRY, row_spacing=None, race_control="inner").bearing("single")
    lo, hi = -0.06, -0.03
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if fb.stiffness(b, [0, 0, mid, 0, 0], speed=24000.0)[0][2] < 1.0 else (lo, mid)
    below, above = (fb.stiffness(b, [0, 0, x, 0, 0], speed=24000.0)[0][2] for x in (lo, hi))
    assert below == 0.0 and above > 600.0
    for dz in (lo - 1e-6, hi + 1e-6):  # the reference, a micrometre either side
        f = fb.stiffness(b, [0, 0, dz, 0, 0], speed=24000.0)[0][2]
        assert jones_harris_load(b, [0, 0, dz, 0, 0], 24000.0)[2] == pytest.approx(f, rel=1e-8, abs=1e-9)
    for load in ((0.0, 0.0, 500.0, 0.0, 0.0), (1000.0, 0.0, 500.0, 0.0, 0.0)):
        r = fb.solve(b, load, speed=24000.0)
        assert not r.converged and "inner-race control" in r.note


@pytest.mark.parametrize("race_control,rotating", [("outer", "inner"), ("inner", "inner"), ("none", "inner"),
                                                   ("outer", "outer"), ("inner", "outer")])
def test_f_at_speed_equals_the_jones_harris_reference_on_a_preloaded_pair(race_control, rotating):
    """The shipped DB pair (preload, two rows of opposite direction, row offsets) at random q: all five
    entries of f, every race control, either ring turning."""
    rng = np.random.default_rng(7)
    b = replace(GEOMETRY, race_control=race_control, rotating=rotating).bearing("DB", axial_preload=0.012)
    L = b.rows[0].pitch_radius
    scale = np.array([1, 1, 1, 1 / L, 1 / L])
    for speed in (6000.0, 20000.0):
        q = _q(rng, 0.005)
        f, _ = fb.stiffness(b, q, speed=speed)
        f_ref = jones_harris_load(b, q, speed)
        assert np.abs((f - f_ref) * scale).max() <= 1e-8 * np.abs(f_ref * scale).max(), (speed, f, f_ref)


def test_orbital_speed_reduces_to_the_cage_speed_and_centrifugal_force_to_half_m_dm_omega_squared():
    """With equal angles the kinematics give omega_m = omega/2 (1 - D cos a/dm) (outer ring fixed) and
    F_c = 0.5 m dm omega_m^2 with m = rho pi D^3/6."""
    p = SPINDLE.speed_table[:, 0]
    a = math.radians(20.0)
    omega = 1000.0
    wm, *_ , S, _, _, _, _ = hs.kinematics(math.cos(a), math.sin(a), math.cos(a), math.sin(a), omega, 0.0,
                                           p[schema.GAMMA], False)
    D, dm = GEOMETRY.ball_diameter, GEOMETRY.pitch_diameter
    assert wm == pytest.approx(omega / 2 * (1 - D * math.cos(a) / dm), rel=1e-14)
    mass = 7850 * math.pi * (D * 1e-3) ** 3 / 6
    assert p[schema.MASS_RADIUS] * wm ** 2 == pytest.approx(0.5 * mass * dm * 1e-3 * wm ** 2, rel=1e-14)


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


def test_a_speed_beyond_the_bearing_s_limit_is_refused_everywhere_naming_the_limit(tmp_path):
    """At 1e6 rpm ball_contacts once returned a centrifugal force of inf and a NaN residual beside a finite
    232 kN contact load (issue 33). A bearing's speed limit is where the centrifugal force alone, at the
    nominal orbital speed, reaches the load of its validity limit (the deflection limit): closed form here;
    beyond it every entry point refuses, naming speed and the limit; just below, the answers are finite."""
    from conftest import cli_run

    from fastbearing.model.bearing import speed_limit
    from fastbearing.model.bearing_file import read_toml
    from fastbearing.jobs.loadmap import loadmap

    g = GEOMETRY
    a0 = math.radians(g.contact_angle)
    mass = 7850.0 * math.pi * (g.ball_diameter * 1e-3) ** 3 / 6
    row = SPINDLE.rows[0]
    Q = row.hertz_constant * row.deflection_limit ** 1.5
    omega_m = math.sqrt(Q / (mass * g.pitch_diameter / 2 * 1e-3))
    limit = omega_m / (0.5 * (1 - g.ball_diameter / g.pitch_diameter * math.cos(a0))) * 30 / math.pi
    assert speed_limit(SPINDLE) == pytest.approx(limit, rel=1e-12) and 1.3e5 < limit < 1.4e5
    words = rf"speed must be <= {limit:.6g} rpm for 7014C-DB"
    q = [0.005, 0.0, 0.01, 0.0, 0.0]
    for call in (lambda: ball_contacts(SPINDLE, q, speed=1e6), lambda: fb.stiffness(SPINDLE, q, speed=1e6),
                 lambda: fb.solve(SPINDLE, (0, 0, 1000.0, 0, 0), speed=1.01 * limit),
                 lambda: fb.rating_life(SPINDLE, (0, 0, 1000.0, 0, 0), speed=1e6)):
        with pytest.raises(ValueError, match=words):
            call()
    with pytest.raises(ValueError, match=r"speed\[1\] must be <="):
        fb.solve_many(SPINDLE, [(0, 0, 1000.0, 0, 0)] * 2, speed=[0.0, 1e6])
    s = cli_run("solve", "--bearing", DATA / "7014C-DB.toml", "--load", "0,0,1000,0,0", "--speed", "1e6")
    assert s.returncode == 2 and f"--speed must be <= {limit:.6g} rpm" in s.stderr
    doc = read_toml(DATA / "7014C-DB.toml")
    doc["loadmap"] = {"given": "load", "Fz": 1000.0, "speed": [0.0, 1e6]}
    with pytest.raises(ValueError, match="loadmap.speed must be <="):
        loadmap(doc, tmp_path / "m.h5", progress=False)
    assert not (tmp_path / "m.h5").exists()
    c = ball_contacts(SPINDLE, q, speed=0.99 * limit)
    assert np.isfinite(c.centrifugal_force).all() and np.isfinite(c.equilibrium_residual).all()


SPINDLE_MAP = Path(__file__).parent.parent / "data" / "examples" / "spindle-7014-speed.toml"


def _spindle_config(**loadmap):
    from fastbearing.model.bearing_file import read_toml

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
    from fastbearing.model.bearing_file import read_toml

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
    from fastbearing.analysis import life as L

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


def test_a_life_map_at_a_standing_still_speed_is_the_life_at_rest(tmp_path):
    """Below the standing-still speed (about 1e-3 rpm here) the balls are at rest: the map's lives equal the
    0 rpm ones, read from a record whose outer contacts the kernel fills too (they were left unwritten)."""
    cfg = _spindle_config(speed=[0.0, 1e-4, 2e-4], Fx=[300.0, 1500.0], Fz=[200.0, 1500.0], life={})
    ds = fb.open_dataset(fb.loadmap(cfg, tmp_path / "still.h5", progress=False))
    L10r = ds["L10r"].values.reshape(3, -1)
    assert np.isfinite(L10r).all()
    np.testing.assert_allclose(L10r[1], L10r[0], rtol=1e-12)
    np.testing.assert_allclose(L10r[2], L10r[0], rtol=1e-12)
    c = ball_contacts(SPINDLE, ds["q"].values.reshape(3, -1, 5)[1, 0], speed=1e-4)
    np.testing.assert_allclose(c.inner_load, c.outer_load, rtol=1e-12)  # standing still, as the kernel took it
    assert np.all(c.centrifugal_force == 0.0)


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
    from fastbearing.model.bearing_file import read_toml

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
    from fastbearing.engine.kernel import ball_loop

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
    from fastbearing.analysis.shaft import read_shaft, solve_shaft, transfer

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

    from fastbearing.model.bearing_file import read_toml
    from fastbearing.analysis.shaft import read_shaft

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


def test_displacement_mode_at_speed_flags_balls_without_equilibrium(tmp_path):
    """solve --displacement, fb.stiffness and fb.stiffness_many flag a displacement at which balls do not
    settle, as a displacement-given map does (issue 33: `status: direct`, exit 0, with a ball's residual at
    0.37); an ordinary displacement at speed is still `direct`. (The issue's case, 200 000 rpm on the 7014C
    pair, is now beyond that bearing's speed limit; here a 3206 near its own.)"""
    from conftest import cli_run

    path = DATA / "3206.toml"
    b = fb.load_bearing(path)
    q, speed = "-0.0145,-0.0256,-0.0179,2.6e-4,5.7e-4", "190000"
    s = cli_run("solve", "--bearing", path, f"--displacement={q}", "--speed", speed)
    assert s.returncode == 1 and s.stdout.startswith("status: ball_equilibrium") and "q (mm" not in s.stdout
    body = json.loads(cli_run("solve", "--bearing", path, f"--displacement={q}", "--speed", speed, "--json").stdout)
    assert body["status"].startswith("ball_equilibrium") and not body["converged"]
    values = [float(v) for v in q.split(",")]
    with pytest.raises(ValueError, match="ball_equilibrium"):
        fb.stiffness(b, values, speed=190000.0)
    with pytest.raises(ValueError, match=r"case 1\).*ball_equilibrium"):
        fb.stiffness_many(b, [values] * 2, speed=[0.0, 190000.0])
    # the same case in a displacement-given map: flagged there too
    from fastbearing.jobs.loadmap import loadmap

    from fastbearing.model.bearing_file import read_toml

    doc = read_toml(path)
    doc["loadmap"] = {"given": "displacement", **dict(zip(("dx", "dy", "dz", "bx", "by"), values)), "speed": 190000.0}
    with h5py.File(loadmap(doc, tmp_path / "m.h5", progress=False)) as fh:
        assert fb.status.describe(int(np.ravel(fh["status"][...])[0])).startswith("ball_equilibrium")
    ok = cli_run("solve", "--bearing", path, "--displacement", "0.005,0,0.01,0,0", "--speed", "12000")
    assert ok.returncode == 0 and ok.stdout.startswith("status: direct")


@pytest.mark.parametrize("arrangement,race_control,rotating", [("single", "outer", "outer"), ("DB", "none", "outer"),
                                                               ("DT", "inner", "outer"), ("single", "none", "inner"),
                                                               ("single", "inner", "inner"), ("DB", "outer", "outer")])
def test_results_are_continuous_as_the_speed_goes_to_zero(arrangement, race_control, rotating):
    """A light load (5, 0, 1, 0, 0) N on the 7014C geometry: from 1e-12 to 1 rpm the solve converges next to
    the quasi-static q (issue 33: `stalled` at 0.001 rpm, `iteration_limit` at 1e-9 rpm, and, in these
    configurations, nonfinite results at 1e-4 .. 1 rpm); the centrifugal force grows with speed^2, so the
    distance does too."""
    g = replace(GEOMETRY, race_control=race_control, rotating=rotating)
    b = replace(g, row_spacing=None).bearing("single") if arrangement == "single" else g.bearing(arrangement)
    load = (5.0, 0.0, 1.0, 0.0, 0.0)
    rest = fb.solve(b, load)
    assert rest.converged
    for speed in (1e-12, 1e-9, 1e-6, 1e-4, 1e-3, 1e-2, 0.1, 1.0):
        r = fb.solve(b, load, speed=speed)
        assert r.converged, (speed, r.status_name)
        assert np.abs(r.q - rest.q).max() <= max(1e-8, 1e-5 * speed ** 2) * np.abs(rest.q).max(), speed


def test_wedged_balls_are_found_where_the_free_ball_would_not_clear_the_inner_race():
    """Outer ring turning at 80 000 rpm, load (2000, 300, 500, 1e4, -5e3) on the 7014C pair: balls 27-30 were
    taken as free at a position where their own force balance was off by 41 % of the centrifugal force, and
    f(q) evaluated afresh was 5.8 % off the load (issue 33). Their own equilibrium on the outer race touches
    the inner race, so they are wedged (Q_i 35-44 N, as the independent model finds); the answer carries
    its load afresh and by the reference."""
    b = replace(GEOMETRY, rotating="outer").bearing("DB", axial_preload=0.012)
    load = np.array([2000.0, 300.0, 500.0, 1e4, -5e3])
    r = fb.solve(b, load, speed=80000.0)
    assert r.converged
    scale = np.array([1, 1, 1, 1 / 45.0, 1 / 45.0])
    for f in (fb.stiffness(b, r.q, speed=80000.0)[0], jones_harris_load(b, r.q, 80000.0)):
        assert np.abs((f - load) * scale).max() <= 1e-8 * np.abs(load * scale).max()
    c = ball_contacts(b, r.q, speed=80000.0)
    assert np.all((c.inner_load[27:31] > 30.0) & (c.inner_load[27:31] < 50.0))
    assert c.equilibrium_residual.max() <= 1e-10


def test_random_speeds_race_controls_and_rings_converge_honestly_or_are_flagged():
    """Random loads (light to heavy, any direction) at random speeds up to each bearing's speed limit, every
    race control, either ring turning: a converged case carries its load evaluated afresh (so no path-
    dependent ball state) and by the independent Jones-Harris reference; the rest are not called converged,
    and under inner control the result says why."""
    from fastbearing.model.bearing import speed_limit

    rng = np.random.default_rng(21)
    checked = 0
    for name in ("6305.toml", "7014C-DB.toml"):
        base = fb.load_bearing(DATA / name).geometry
        for race_control, rotating in (("outer", "inner"), ("inner", "inner"), ("none", "outer"), ("outer", "outer")):
            for arrangement, b in _arrangements(replace(base, race_control=race_control, rotating=rotating)).items():
                loads = np.column_stack([rng.uniform(-1, 1, (2, 2)) * 10 ** rng.uniform(1, 3.5, (2, 1)),
                                         rng.uniform(-0.3, 1, 2) * 10 ** rng.uniform(1, 3.5, 2),
                                         rng.uniform(-1, 1, (2, 2)) * 10 ** rng.uniform(2, 4.5, (2, 1))])
                speeds = rng.uniform(0.0, 0.7, 2) * speed_limit(b)
                out = fb.solve_many(b, loads, speed=speeds, threads=2)
                L = b.rows[0].pitch_radius
                scale = np.array([1, 1, 1, 1 / L, 1 / L])
                for i in range(2):
                    if not out.converged[i]:
                        assert race_control != "inner" or fb.solve(b, loads[i], speed=speeds[i]).note
                        continue
                    size = np.abs(loads[i] * scale).max()
                    f = fb.stiffness(b, out.q[i], speed=speeds[i])[0]
                    assert np.abs((f - loads[i]) * scale).max() <= 1e-8 * size, (name, arrangement, i)
                    if checked < 12:
                        checked += 1
                        f = jones_harris_load(b, out.q[i], speeds[i])
                        assert np.abs((f - loads[i]) * scale).max() <= 1e-7 * size, (name, arrangement, i)
    assert checked == 12
