"""Core-engine benchmarks (pytest-benchmark). Run: pytest bench/ --benchmark-only

Every jitted function is called once before timing so compile time is not
mixed in. Baselines run in the same process so ratios are meaningful.
"""

import numpy as np
import pytest

import fastbearing as fb
from fastbearing.kernel import ball_loop

BEARING = fb.Bearing.preset("gunduz2013", "DB")
TABLE4 = np.array([1000.0, 0.0, 3000.0, 0.0, -74000.0])
Q = fb.solve(BEARING, TABLE4).q


def numpy_load_stiffness(q, t):
    """Baseline: the same physics vectorised over balls with numpy (what one writes without numba)."""
    c, s, z, R, ur0, uz0, A0, Kn, n = t[:9]
    ur = (q[0] + z * q[4]) * c + (q[1] - z * q[3]) * s + ur0
    uz = q[2] + R * (q[3] * s - q[4] * c) + uz0
    A = np.hypot(ur, uz)
    delta = np.maximum(A - A0, 0.0)
    Q = Kn * delta ** n
    a = np.stack([c, s, np.zeros_like(c), -z * s, z * c], 1)
    b = np.stack([np.zeros_like(c), np.zeros_like(c), np.ones_like(c), R * s, -R * c], 1)
    g = Q / A
    f = (g * ur) @ a + (g * uz) @ b
    hr, hz = ur / A, uz / A
    dq = np.where(delta > 0, n * Q / np.where(delta > 0, delta, 1.0), 0.0) - g
    h11, h12, h22 = g + dq * hr * hr, dq * hr * hz, g + dq * hz * hz
    K = (a.T * h11) @ a + (a.T * h12) @ b + (b.T * h12) @ a + (b.T * h22) @ b
    return f, K


@pytest.mark.benchmark(group="kernel: f and Kb at q, 28 balls")
def test_kernel_numba(benchmark):
    balls = BEARING.ball_set()
    f, K = np.empty(5), np.empty((5, 5))
    ball_loop(Q, balls, f, K, None, None)
    benchmark(ball_loop, Q, balls, f, K, None, None)
    f_np, K_np = numpy_load_stiffness(Q, balls[0])
    np.testing.assert_allclose(K, K_np, rtol=1e-9, atol=1e-6)


@pytest.mark.benchmark(group="kernel: f and Kb at q, 28 balls")
def test_kernel_numpy_baseline(benchmark):
    benchmark(numpy_load_stiffness, Q, BEARING.ball_table())


@pytest.mark.parametrize("method", ["newton", "broyden"])
@pytest.mark.benchmark(group="one load-given solve (Table 4 load, fb.solve)")
def test_solve(benchmark, method):
    fb.solve(BEARING, TABLE4, method=method)
    r = benchmark(fb.solve, BEARING, TABLE4, method=method)
    assert r.converged
    benchmark.extra_info.update(iterations=r.iterations, evaluations=r.evaluations)


RNG_LOADS = np.column_stack([np.random.default_rng(0).uniform(lo, hi, 10_000) for lo, hi in
                             ((-3000, 3000), (-3000, 3000), (-8000, 8000), (-1e5, 1e5), (-1e5, 1e5))])


@pytest.mark.parametrize("threads", [1, 2])
@pytest.mark.benchmark(group="solve_many: 10 000 random combined loads")
def test_solve_many(benchmark, threads):
    fb.solve_many(BEARING, RNG_LOADS[:10], threads=threads)
    r = benchmark.pedantic(fb.solve_many, args=(BEARING, RNG_LOADS), kwargs=dict(threads=threads), rounds=5)
    assert r.converged.all()
    benchmark.extra_info.update(us_per_case=benchmark.stats.stats.median / len(RNG_LOADS) * 1e6)
