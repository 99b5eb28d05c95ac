"""The kernel's mirror half: under a planar displacement (dy = bx = 0) a ball set that is its own mirror image
across the xz-plane is summed over one ball of each mirror pair (kernel.quasi_static_balls). It must give
what the printed equations give over every ball, what the full loop gives to rounding, and y-odd terms that
are exactly zero (docs/model.md, "Mirror symmetry")."""

import math

import numpy as np
import pytest
from conftest import random_rows, to_row
from naive import naive_load_stiffness

import fastbearing as fb
from fastbearing.model.bearing import BALL_OF, COS_PSI, HALF_COUNT, KN, MIRROR_HALF, MIRROR_OF, SIN_PSI, WEIGHT
from fastbearing.engine.kernel import ball_loop

#: Kb entries and f components odd in y: zero under a planar displacement of a mirror-symmetric set.
ODD_K = [(0, 1), (0, 3), (1, 2), (1, 4), (2, 3), (3, 4)]
ODD_F = [1, 3]


def scaled_error(K, K_ref):
    """Largest entry error against sqrt(|K_ii K_jj|) (Kb's entries have mixed units), floored at 1e-6 of the
    largest such scale: where every loaded ball sits on the plane kyy is 0 and the reference's y-entries are
    its rounding noise (sin(pi) = 1.2e-16), which the mirror half has as exact zeros."""
    d = np.sqrt(np.abs(np.outer(np.diag(K_ref), np.diag(K_ref))))
    return np.max(np.abs(K - K_ref) / (d + 1e-6 * d.max() + 1e-300))


def symmetric_rows(rng, n_rows=None, exponent=None):
    """Random rows whose balls sit symmetrically about the xz-plane (first ball at a multiple of pi/Z)."""
    rows = random_rows(rng, n_rows, exponent)
    for r in rows:
        r["first_ball_angle"] = math.pi / r["n_balls"] * int(rng.integers(0, 2 * r["n_balls"]))
    return rows


def planar_q(rng, scale=0.03):
    q = np.concatenate([rng.uniform(-scale, scale, 3), rng.uniform(-scale / 40, scale / 40, 2)])
    q[1] = q[3] = 0.0
    return q


def full_loop(balls):
    """The same ball set with its mirror half withheld: the kernel sums every ball."""
    table = balls.balls.copy()
    table[HALF_COUNT] = 0.0
    return balls._replace(balls=table)


def evaluate(balls, q, n):
    f, K, Q, alpha = np.empty(5), np.empty((5, 5)), np.empty(n), np.empty(n)
    total, n_loaded, warnings = ball_loop(np.asarray(q, float), balls, f, K, Q, alpha)
    return f, K, Q, alpha, total, n_loaded, warnings


def test_mirror_half_pairs_each_ball_with_its_image():
    for arrangement, n in (("DB", 28), ("single", 14)):
        table = fb.Bearing.preset("gunduz2013", arrangement).ball_table()
        count = int(table[HALF_COUNT, 0])
        assert count == n // 14 * 8  # psi = 0 and pi on the plane, six pairs per row
        balls = table[BALL_OF, :count].astype(int)
        mirrors = table[MIRROR_OF, :count].astype(int)
        covered = sorted(list(balls) + [m for j, m in zip(balls, mirrors) if m != j])
        assert covered == list(range(n))  # every ball once
        for j, m, w in zip(balls, mirrors, table[MIRROR_HALF + WEIGHT, :count]):
            if m == j:  # on the plane: its own image
                assert w == 1.0 and abs(table[SIN_PSI, j]) < 1e-12
            else:
                assert w == 2.0 and m > j
                assert table[COS_PSI, m] == pytest.approx(table[COS_PSI, j], abs=1e-12)
                assert table[SIN_PSI, m] == pytest.approx(-table[SIN_PSI, j], abs=1e-12)


@pytest.mark.parametrize("n_balls, k", [(1, 0), (2, 1), (7, 3), (13, 20), (14, 5), (200, 7)])
def test_mirror_half_pairs_any_row_turned_by_a_multiple_of_pi_over_z(n_balls, k):
    """First ball at k*180/Z degrees: every ball's image is a ball of the row, and the table pairs them."""
    bearing = fb.Bearing.preset("gunduz2013", "DT", n_balls=n_balls, first_ball_angle=k * 180.0 / n_balls)
    table = bearing.ball_table()
    count = int(table[HALF_COUNT, 0])
    assert count > 0
    balls = table[BALL_OF, :count].astype(int)
    mirrors = table[MIRROR_OF, :count].astype(int)
    assert sorted(set(balls) | set(mirrors)) == list(range(2 * n_balls))
    for j, m in zip(balls, mirrors):
        assert table[COS_PSI, m] == pytest.approx(table[COS_PSI, j], abs=1e-9)
        assert table[SIN_PSI, m] == pytest.approx(-table[SIN_PSI, j], abs=1e-9)


def test_mirror_half_only_where_the_set_is_symmetric():
    bearing = fb.Bearing.preset("gunduz2013", "DB")
    assert bearing.ball_table(math.pi / 14)[HALF_COUNT, 0] == 14  # half a pitch on: seven pairs per row
    assert bearing.ball_table(0.1)[HALF_COUNT, 0] == 0
    odd = fb.Bearing.preset("gunduz2013", "DB", first_ball_angle=7.0)
    assert odd.ball_table()[HALF_COUNT, 0] == 0
    # one row symmetric, the other not: the set as a whole has no mirror half
    rows = [to_row(r) for r in symmetric_rows(np.random.default_rng(3), 2)]
    rows[1] = fb.Row(**{**rows[1].__dict__, "first_ball_angle": 1.234})
    assert fb.Bearing.from_rows(rows).ball_table()[HALF_COUNT, 0] == 0


@pytest.mark.parametrize("exponent", [1.5, None])
def test_planar_kernel_matches_printed_equations(rng, exponent):
    for _ in range(40):
        rows = symmetric_rows(rng, exponent=exponent)
        bearing = fb.Bearing.from_rows([to_row(r) for r in rows])
        assert bearing.ball_table()[HALF_COUNT, 0] > 0
        q = planar_q(rng)
        f, K = fb.stiffness(bearing, q)
        f_ref, K_ref = naive_load_stiffness(q, rows)
        np.testing.assert_allclose(f, f_ref, rtol=1e-9, atol=1e-9 * max(np.max(np.abs(f_ref)), 1e-300))
        if np.any(K_ref != 0):
            assert scaled_error(K, K_ref) < 1e-9
        for i, j in ODD_K:
            assert K[i, j] == 0.0 and K[j, i] == 0.0
        assert all(f[i] == 0.0 for i in ODD_F)


def test_planar_kernel_equals_the_full_loop(rng):
    bearings = [fb.Bearing.preset("gunduz2013", a) for a in ("single", "DB", "DF", "DT")]
    bearings += [fb.Bearing.preset("gunduz2013", "DB", radial_clearance=-0.004, n_balls=13),
                 fb.Bearing.preset("gunduz2013", "DT", exponent=10 / 9, radial_clearance=0.01)]
    for bearing in bearings:
        balls = bearing.ball_set()
        for _ in range(30):
            q = planar_q(rng)
            half = evaluate(balls, q, bearing.n_balls)
            every = evaluate(full_loop(balls), q, bearing.n_balls)
            f, K, Q, alpha = half[:4]
            f_all, K_all, Q_all, alpha_all = every[:4]
            np.testing.assert_allclose(f, f_all, rtol=1e-12, atol=1e-12 * np.max(np.abs(f_all)))
            if np.any(K_all != 0):
                assert scaled_error(K, K_all) < 1e-9  # the full loop's y-entries: noise of sin(pi)
            np.testing.assert_allclose(Q, Q_all, rtol=1e-12, atol=1e-12 * np.max(Q_all))
            np.testing.assert_allclose(alpha, alpha_all, rtol=0, atol=1e-12)
            assert half[4] == pytest.approx(every[4], rel=1e-12)
            assert half[5:] == every[5:]  # loaded balls and warning bits


def test_out_of_plane_displacement_sums_every_ball(rng):
    bearing = fb.Bearing.preset("gunduz2013", "DB")
    balls = bearing.ball_set()
    for _ in range(10):
        q = planar_q(rng)
        q[1] = 1e-3
        half, every = evaluate(balls, q, 28), evaluate(full_loop(balls), q, 28)
        for a, b in zip(half, every):
            assert np.array_equal(a, b)


def test_planar_solve_stays_in_the_plane():
    bearing = fb.Bearing.preset("gunduz2013", "DB")
    r = fb.solve(bearing, [1000.0, 0.0, 3000.0, 0.0, -74000.0])
    assert r.status_name == "converged"
    assert r.q[1] == 0.0 and r.q[3] == 0.0
    for i, j in ODD_K:
        assert r.K[i, j] == 0.0
    # a set turned by 1e-7 degrees has no mirror half (its own dy, bx are about 1e-12 mm, 1e-13 rad)
    every = fb.solve(fb.Bearing.preset("gunduz2013", "DB", first_ball_angle=1e-7), [1000.0, 0.0, 3000.0, 0.0, -74000.0])
    np.testing.assert_allclose(r.q, every.q, rtol=1e-6, atol=1e-10)


def test_a_ball_unlike_its_image_switches_the_mirror_half_off(rng):
    """The element set states its symmetry: any per-ball field that differs between a ball and its mirror
    image (here one ball's Hertz constant, as a per-element property would) leaves no mirror half, so the
    planar kernel sums every ball and agrees with the full loop bit for bit; ball_set(mirror=False) is the
    switch for a feature kept outside the table."""
    from fastbearing.model.bearing import _fill_mirror_half

    bearing = fb.Bearing.preset("gunduz2013", "DB")
    assert bearing.mirror_symmetric
    balls = bearing.ball_set()
    odd = balls.balls.copy()
    odd[KN, 3] *= 1.01
    _fill_mirror_half(odd, bearing._ball_azimuths(0.0))
    assert odd[HALF_COUNT, 0] == 0.0
    off = bearing.ball_set(mirror=False)
    assert off.balls[HALF_COUNT, 0] == 0.0 and balls.balls[HALF_COUNT, 0] > 0  # the bearing's own table untouched
    for _ in range(5):
        q = planar_q(rng)
        for a, b in zip(evaluate(off, q, 28), evaluate(full_loop(balls), q, 28)):
            assert np.array_equal(a, b)
        weaker = evaluate(balls._replace(balls=odd), q, 28)
        every = evaluate(full_loop(balls._replace(balls=odd)), q, 28)
        for a, b in zip(weaker, every):
            assert np.array_equal(a, b)
