"""Hard random loads: every case solved, every answer checked against an independent residual.

The generator throws at every arrangement the loads a plain Newton on the
residual fails on: no axial load on single rows and tandems (the balls must
cross to the other side of the groove, through a region where none is
loaded), pure and tiny moments, loads from 1 N to 10 kN, with clearance,
preload, 85 degree contact angles and the line-contact exponent 10/9, and on
random bearings of 1-3 rows. Every case must end converged, or at the
precision limit where float64 cannot resolve the load (and then the flag
must be justified). Every converged q is checked with Eq. (12) evaluated in
extended precision (tests/naive.py): its true residual is within rtol. The
roller bearings (NU 205, the 30206 pairs) get the same check, their f from
the slice equations (docs/model.md, "Roller slices (cylindrical and tapered roller rows)") in extended precision.
"""

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from conftest import random_rows, to_row
from naive import bearing_load_extended

import fastbearing as fb
from fastbearing import status as st

BEARINGS = Path(__file__).resolve().parents[1] / "fastbearing" / "catalogue"

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


def axial_reach(row):
    """How far from the bearing centre a row's contacts sit axially, mm: |z_r| for balls, |z_r| + the
    outermost slice's |x_k| for rollers (the solver's moment arm, kernel.slice_reach)."""
    half = np.abs(row.slice_positions).max() if hasattr(row, "slice_positions") else 0.0
    return abs(row.axial_offset) + half


def rounding_floor(bearing, q, K):
    """The solver's bound on the rounding of a computed scaled residual at q (N): see solver._rounding_floor.
    Ball and roller rows alike: element loads (balls, and rollers' totals) and each row's deflection scale
    (A0 for balls, 0.02 l for rollers)."""
    L = bearing.length_scale
    D = np.array([1, 1, 1, 1 / L, 1 / L])
    Q, _ = fb.ball_loads(bearing, q)
    arm = 1 + max(axial_reach(r) for r in bearing.rows) / L
    reach = max(r.deflection_scale for r in bearing.rows)
    return np.finfo(float).eps * (Q.sum() * arm + np.trace(K * np.outer(D, D)) * (reach + np.abs(q / D).max()))


def check_every_case(bearing, loads):
    """Solve, then check each case independently; returns the outcome counts."""
    r = fb.solve_many(bearing, loads)
    outcome = r.status & st.OUTCOME_MASK
    counts = {st.NAMES[c]: int(k) for c, k in zip(*np.unique(outcome, return_counts=True))}
    assert set(counts) <= {"converged", "precision_limit"}, counts
    L = bearing.length_scale
    D = np.array([1, 1, 1, 1 / L, 1 / L])
    for i in range(len(loads)):
        scale = np.abs(loads[i] * D).max()
        true = float(np.abs((bearing_load_extended(r.q[i], bearing) - loads[i]) * D).max())
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


def roller_loads(rng, n, axial=True):
    """(n, 5) loads of 0.01 N to 30 kN, moments up to 3 mm times that: a quarter each general, forces
    alone, pure Fx, and pure moments. Without ``axial`` (a cylindrical row holds no axial load) no Fz, and
    the last quarter general too."""
    kind = rng.integers(0, 4, n)
    F = rng.normal(size=(n, 3))
    if not axial:
        F[:, 2] = 0.0
    size = 10 ** rng.uniform(-2.0, 4.5, n)                                                     # 0.01 N .. 30 kN
    F *= (size / np.linalg.norm(F, axis=1))[:, None]
    M = rng.normal(size=(n, 2)) * (size * 10 ** rng.uniform(-2.0, 0.5, n))[:, None]            # arms 0.01-3 mm
    loads = np.column_stack([F, M])
    loads[kind == 1, 3:] = 0.0
    loads[kind == 2, 1:] = 0.0
    if axial:
        loads[kind == 3, :3] = 0.0
    return loads


def tdi_logarithmic():
    """The 30206 pair face to face (TDI) with Lundberg's logarithmic crown for 8 kN, preloaded 0.005 mm."""
    g = fb.load_bearing(BEARINGS / "30206-TDO.toml").geometry
    return replace(g, crown="logarithmic", crown_radius=None, crown_design_load=8000.0).bearing(
        "TDI", axial_preload=0.005)


ROLLER_BEARINGS = {
    "NU205": (lambda: fb.load_bearing(BEARINGS / "NU205.toml"), False),
    "30206-TDO": (lambda: fb.load_bearing(BEARINGS / "30206-TDO.toml"), True),
    "30206-TDO unpreloaded": (lambda: fb.load_bearing(BEARINGS / "30206-TDO.toml").with_rows(axial_preload=0.0),
                              True),
    "30206-TDI logarithmic": (tdi_logarithmic, True),
}


@pytest.mark.parametrize("name", sorted(ROLLER_BEARINGS))
def test_hard_loads_roller_bearings(name, rng):
    """Crowned roller rows from tiny to large loads: every converged case carries its load to 1.2 rtol in
    extended precision (a crown drop formed with cancellation left 300x that at 0.01-0.1 N), every
    precision_limit is justified. A cylindrical row takes radial loads and moments only."""
    make, axial = ROLLER_BEARINGS[name]
    counts = check_every_case(make(), roller_loads(rng, 100, axial))
    assert counts.get("converged", 0) >= 50, counts
