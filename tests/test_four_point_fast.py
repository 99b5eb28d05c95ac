"""The four-point ball at speed made cheaper (issue 47 item 6; engine/four_point.py): the cold guess that knows the
centrifugal force, the one look at a moved ball's prediction inside a solve (``linear_look``: taken as settled
only within the settle's own tolerance, linearised only where its Newton step is short against every contact),
and the answers of the Newton path they replace. Timings are in bench/ (bench/README.md), not here."""

import numpy as np
import pytest

import fastbearing as fb
from fastbearing.api import speed_ball_set
from fastbearing.engine import four_point as fp
from fastbearing.engine import high_speed as hs
from fastbearing.engine.schema import COS_NOMINAL, INNER_RADIUS, OUTER_RADIUS

QJ210 = fb.load_bearing("QJ210")
#: combined loads of the benchmark's kind (bench/test_high_speed.py), a few of them
LOADS = np.column_stack([np.random.default_rng(3).uniform(-3000.0, 3000.0, (6, 3)), np.zeros((6, 2))])


def _balls_at(q, speed):
    """(u, p, w_i, w_o) of every four-point ball of the QJ 210 at displacement q."""
    balls = speed_ball_set(QJ210, speed)
    out = []
    for k in range(balls.four_point.shape[1]):
        j, m = int(balls.four_point[0, k]), int(balls.four_point[1, k])
        p, w_i, w_o = hs._ball_constants(balls.speed_table, j, balls.omega)
        u1 = hs._inner_centre(np.asarray(q, float), balls.balls, j)
        u2 = hs._inner_centre(np.asarray(q, float), balls.balls, m)
        out.append(((0.0, 0.0, u1[0], u1[1], u2[0], u2[1]), p, w_i, w_o))
    return out


@pytest.fixture(scope="module")
def solved():
    """The solves' answers at 10 000 and 30 000 rpm."""
    return [(fb.solve_many(QJ210, LOADS, speed=speed, threads=1).q, speed) for speed in (10000.0, 30000.0)]


def test_the_cold_guess_settles_the_balls_without_the_continuation(solved):
    """Newton from the cold guess settles every ball of these cases (the quasi-static guess it replaced left
    2 % of them on a fold, for the continuation in speed, and took 4.4 residual halvings a ball), and reaches
    the root the continuation in speed reaches from standing still, the canonical rule's fallback."""
    iterations = []
    for qs, speed in solved:
        for q in qs:
            for u, p, w_i, w_o in _balls_at(q, speed):
                br, bz = fp._cold_guess(u, p, w_i, w_o)
                first = fp.settle_four_point(u, p, w_i, w_o, 0.0, br, bz, 0.0)
                assert first[3]
                iterations.append(first[2])
                root = fp.canonical_settle(u, p, w_i, w_o, 0.0)
                assert root[:4] == first[:4]
    assert np.mean(iterations) <= 6.0  # Newton steps (deterministic counts, not times)


def test_a_prediction_within_the_tolerance_is_the_settle_bit_for_bit(solved):
    """At a settled centre whose residual is within BALL_RTOL of the ball's largest force the one look says
    settled, and keeps the centre; the ball's evaluation and its Jacobian are the settle's and ball_jacobian's
    there (to rounding: compiled inside another function, fastmath may contract them otherwise); a centre
    settled at the rounding floor of its position (the settle's other test) is linearised by a step at the
    rounding level (1e-12 of its centre distances)."""
    exact = 0
    for qs, speed in solved:
        for q in qs:
            for u, p, w_i, w_o in _balls_at(q, speed):
                br, bz, _, settled, y, st = fp.canonical_settle(u, p, w_i, w_o, 0.0)
                assert settled
                lb, lz, l_settled, stepped, ly, lst, J = fp.linear_look(u, p, w_i, w_o, 0.0, br, bz)
                assert l_settled and not stepped
                J0 = np.array(fp.ball_jacobian((br, bz) + u[2:], p, w_i, w_o, 0.0))
                assert np.abs(np.array(J) - J0).max() <= 1e-14 * np.abs(J0).max()
                assert np.abs(np.array(lst) - np.array(st)).max() <= 1e-14 * np.abs(np.array(st)).max()
                scale = st[0] + st[1] + st[2] + st[3] + abs(st[12])
                if max(abs(y[0]), abs(y[1])) <= hs.BALL_RTOL * scale:
                    assert (lb, lz) == (br, bz)
                    assert np.abs(np.array(ly) - np.array(y)).max() <= 1e-14 * np.abs(np.array(y)).max()
                    exact += 1
                else:
                    assert max(abs(lb - br), abs(lz - bz)) <= 1e-12 * (abs(u[2]) + abs(u[3]) + p[OUTER_RADIUS])
    assert exact >= len(solved) * len(LOADS) * 15 // 2


@pytest.mark.parametrize("move", [1e-6, 1e-4, 1e-2, 0.3])
def test_a_moved_ball_is_linearised_only_where_its_step_is_short(solved, move):
    """The first-order prediction after the rings move: linearised only where the Newton step moves no
    contact's centre distance by more than LINEAR_REACH of its deflection (or gap), and then within second
    order of the settled root (its centre; the ring's forces within what a tenth of a Hertz deflection
    allows); else a step for the settle (large moves)."""
    qs, speed = solved[1]
    rng = np.random.default_rng(4)
    outcomes = set()
    for q in qs:
        q2 = q * (1.0 + move * rng.normal(size=5))
        for (u, p, w_i, w_o), (u2, _, _, _) in zip(_balls_at(q, speed), _balls_at(q2, speed)):
            br, bz = fp.canonical_settle(u, p, w_i, w_o, 0.0)[:2]
            J = fp.ball_jacobian((br, bz) + u[2:], p, w_i, w_o, 0.0)
            G = np.array([[J[0][0], J[1][0]], [J[0][1], J[1][1]]])  # dg/dB
            Gu = np.array([[J[k][0] for k in range(2, 6)], [J[k][1] for k in range(2, 6)]])
            pb, pz = np.array([br, bz]) - np.linalg.solve(G, Gu @ (np.array(u2[2:]) - np.array(u[2:])))
            lb, lz, settled, stepped, y, st, _ = fp.linear_look(u2, p, w_i, w_o, 0.0, pb, pz)
            root = fp.canonical_settle(u2, p, w_i, w_o, 0.0)
            if stepped:
                outcomes.add("stepped")
                continue
            assert settled
            outcomes.add("linearised" if (lb, lz) != (pb, pz) else "settled")
            # the Newton step s (B' = B - s) was short against every contact
            s_r, s_z = pb - lb, pz - lz
            ro, ri = p[OUTER_RADIUS], p[INNER_RADIUS]
            bz2 = 2.0 * ro * np.sqrt(1.0 - p[COS_NOMINAL] ** 2) - pz
            for (vr, vz, sign, r0) in ((pb, pz, 1.0, ro), (pb, bz2, -1.0, ro), (u2[2] - pb, u2[3] - pz, 1.0, ri),
                                       (u2[4] - pb, u2[5] - bz2, -1.0, ri)):
                L = np.hypot(vr, vz)
                assert abs(vr * s_r + sign * vz * s_z) <= hs.LINEAR_REACH * abs(L - r0) * L
            step = np.hypot(s_r, s_z)
            err = np.hypot(lb - root[0], lz - root[1])
            assert err <= max(50.0 * step * step / p[INNER_RADIUS], 1e-12), (err, step)
            ring = np.array(y[2:])
            exact = np.array(root[4][2:])
            # a contact's load to second order in its deflection's change (at most LINEAR_REACH of it): within
            # (3/8) LINEAR_REACH^2 of the load
            assert np.all(np.abs(ring - exact) <= 0.375 * hs.LINEAR_REACH ** 2 * np.abs(exact) + 1e-9)
    if move <= 1e-4:
        assert "linearised" in outcomes and "stepped" not in outcomes
    if move >= 0.3:
        assert "stepped" in outcomes


def test_a_solve_through_linearised_balls_is_repeated_by_a_fresh_evaluation():
    """The solver's iterates take linearised balls (flagged BALL_LINEARISED); its answer is the canonical
    evaluation's at its q, bit for bit, and f there meets the load to the solver's tolerance."""
    for load in LOADS[:3]:
        r = fb.solve(QJ210, load, speed=10000.0)
        assert r.converged
        f, K = fb.stiffness(QJ210, r.q, speed=10000.0)
        assert np.array_equal(f, r.f) and np.array_equal(K, r.K)
        assert np.abs(f[:3] - load[:3]).max() <= 1e-9 * np.abs(load).max()
