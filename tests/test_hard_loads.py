"""Hard random loads: every case solved, every answer checked against an independent residual.

The generator throws at every arrangement the loads a plain Newton on the
residual fails on: no axial load on single rows and tandems (the balls must
cross to the other side of the groove, through a region where none is
loaded), pure and tiny moments, loads from 1 N to 10 kN, with clearance,
preload, 85 degree contact angles and the line-contact exponent 10/9, and on
random bearings of 1-3 rows. Every case must end converged, or at the
precision limit where float64 cannot resolve the load (and then the flag
must be justified). Every converged q is checked with Eq. (12) evaluated in
extended precision (tests/naive.py): its true residual is within rtol.
"""

import numpy as np
import pytest
from conftest import random_rows, to_row
from naive import bearing_row_dicts, load_extended

import fastbearing as fb
from fastbearing import status as st

RTOL = 1e-10
VARIANTS = {"plain": {}, "clearance": {"radial_clearance": 0.01}, "preload": {"axial_preload": 0.01},
            "85deg": {"contact_angle": 85.0}, "n=10/9": {"exponent": 10 / 9}}


def hard_loads(rng, n):
    """(n, 5) loads: a quarter each general, no axial force, pure moment, and forces with small moments."""
    kind = rng.integers(0, 4, n)
    F = rng.normal(size=(n, 3))
    F *= (10 ** rng.uniform(0.0, 4.0, n) / np.linalg.norm(F, axis=1))[:, None]          # 1 N .. 10 kN
    M = rng.normal(size=(n, 2)) * 10 ** rng.uniform(0.0, 5.0, (n, 1))                  # 1 .. 1e5 N*mm
    loads = np.column_stack([F, M])
    loads[kind == 1, 2] = 0.0
    loads[kind == 2, :3] = 0.0
    loads[kind == 3, 3:] = rng.uniform(-500.0, 500.0, (int(np.sum(kind == 3)), 2))
    return loads


def rounding_floor(bearing, q, K):
    """The solver's bound on the rounding of a computed scaled residual at q (N): see solver._rounding_floor."""
    L = bearing.length_scale
    D = np.array([1, 1, 1, 1 / L, 1 / L])
    Q, _ = fb.ball_loads(bearing, q)
    arm = 1 + max(abs(r.axial_offset) for r in bearing.rows) / L
    reach = max(r.groove_center_distance for r in bearing.rows)
    return np.finfo(float).eps * (Q.sum() * arm + np.trace(K * np.outer(D, D)) * (reach + np.abs(q / D).max()))


def check_every_case(bearing, loads):
    """Solve, then check each case independently; returns the outcome counts."""
    r = fb.solve_many(bearing, loads)
    outcome = r.status & st.OUTCOME_MASK
    counts = {st.NAMES[c]: int(k) for c, k in zip(*np.unique(outcome, return_counts=True))}
    assert set(counts) <= {"converged", "precision_limit"}, counts
    rows = bearing_row_dicts(bearing)
    L = bearing.length_scale
    D = np.array([1, 1, 1, 1 / L, 1 / L])
    for i in range(len(loads)):
        scale = np.abs(loads[i] * D).max()
        true = float(np.abs((load_extended(r.q[i], rows) - loads[i]) * D).max())
        if outcome[i] == st.CONVERGED:
            # computed residual <= rtol, rounding <= 0.19 of the floor <= rtol: true <= 1.2 rtol
            assert true <= 1.2 * RTOL * scale, (i, loads[i], true / scale)
        else:
            floor = rounding_floor(bearing, r.q[i], r.K[i])
            assert floor > RTOL * scale, (i, loads[i])              # the flag is justified ...
            assert true <= r.residual[i] * scale + floor, (i, loads[i])  # ... and the answer as good as it says
    return counts


@pytest.mark.parametrize("variant", sorted(VARIANTS))
@pytest.mark.parametrize("arrangement", ["single", "DB", "DF", "DT"])
def test_hard_loads_paper_bearing(arrangement, variant, rng):
    if (arrangement, variant) == ("single", "preload"):
        pytest.skip("a single row cannot hold a preload by itself")
    bearing = fb.Bearing.preset("gunduz2013", arrangement, **VARIANTS[variant])
    check_every_case(bearing, hard_loads(rng, 120))


@pytest.mark.parametrize("seed", range(3))
def test_hard_loads_random_bearings(seed):
    """Random sets of 1-3 rows (3-19 balls, 5-80 deg, clearance or preload, n in 1.1-2) under hard loads."""
    rng = np.random.default_rng(seed)
    for _ in range(5):
        bearing = fb.Bearing.from_rows([to_row(r) for r in random_rows(rng)])
        check_every_case(bearing, hard_loads(rng, 40))


def test_tandem_without_axial_load_needs_the_fallback_and_gets_it():
    """The paper's Table 3 load on DT and a pure moment on a single row: the cases the fast phase
    cannot cross to, solved and flagged contact_reversed."""
    for arrangement, load in (("DT", [1000.0, 0, 0, 0, -74000.0]), ("single", [0, 0, 0, 13.7, -2.97])):
        bearing = fb.Bearing.preset("gunduz2013", arrangement)
        r = fb.solve(bearing, load)
        assert r.converged and r.status & st.CONTACT_REVERSED
        assert abs(r.q[2]) > 0.2                                  # the ring crossed ~A0 sin(a0) axially
