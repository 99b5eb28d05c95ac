"""Kernel, single solves and batches (pytest-benchmark). Run: pytest bench/ --benchmark-only

Every jitted function runs once before timing so compile time is not mixed
in; every ratio is against a baseline timed in the same process.
"""

import numpy as np
import pytest
from conftest import BEARING, TABLE3, TABLE4, random_loads, repeat_kernel
from peer_scipy import load_and_stiffness

import fastbearing as fb

Q = fb.solve(BEARING, TABLE4).q
#: Table 4's solution moved off the xz-plane (dy, bx not zero): the kernel sums every ball, not the mirror half.
Q_OFF_PLANE = Q + np.array([0.0, 2e-3, 0.0, 2e-5, 0.0])
EVALS_PER_ROUND = 1000


@pytest.mark.parametrize("where", ["off-plane", "planar"])
@pytest.mark.benchmark(group="kernel: f and Kb at q, 28 balls")
def test_kernel_numba(benchmark, where):
    """ns per ball contact from the off-plane q (all 28 balls summed); at the planar q (Table 4) the kernel
    sums the mirror half, 16 columns: its ns_per_ball is per ball of the bearing, not per column."""
    balls = BEARING.ball_set()
    q0 = Q_OFF_PLANE if where == "off-plane" else Q
    q = q0.copy()
    repeat_kernel(q, balls, 10)
    benchmark(repeat_kernel, q, balls, EVALS_PER_ROUND)
    if not benchmark.disabled:  # --benchmark-disable: a smoke run, no figures
        per_eval = benchmark.stats.stats.median / EVALS_PER_ROUND
        benchmark.extra_info.update(ns_per_ball=per_eval / 28 * 1e9, ns_per_evaluation=per_eval * 1e9)
    f, K = fb.stiffness(BEARING, q0)
    f_np, K_np = load_and_stiffness(q0, balls.balls)
    np.testing.assert_allclose(K, K_np, rtol=1e-9, atol=1e-9 * np.abs(K).max())


@pytest.mark.benchmark(group="kernel: f and Kb at q, 28 balls")
def test_kernel_numpy_baseline(benchmark):
    table = BEARING.ball_table()
    benchmark(load_and_stiffness, Q, table)
    if not benchmark.disabled:  # --benchmark-disable: a smoke run, no figures
        benchmark.extra_info["ns_per_ball"] = benchmark.stats.stats.median / 28 * 1e9


@pytest.mark.parametrize("method", ["newton", "broyden"])
@pytest.mark.parametrize("load", ["table3", "table4"])
@pytest.mark.benchmark(group="one solve: paper loads, fb.solve (includes the Python call)")
def test_solve_paper_load(benchmark, load, method):
    f = {"table3": TABLE3, "table4": TABLE4}[load]
    fb.solve(BEARING, f, method=method)
    r = benchmark(fb.solve, BEARING, f, method=method)
    assert r.converged
    if not benchmark.disabled:  # --benchmark-disable: a smoke run, no figures
        benchmark.extra_info.update(iterations=r.iterations, evaluations=r.evaluations)


RANDOM = random_loads(1000)


@pytest.mark.parametrize("method", ["newton", "broyden"])
@pytest.mark.benchmark(group="one solve: 1000 random combined loads, cold start, 1 thread")
def test_solve_random_loads(benchmark, method):
    fb.solve_many(BEARING, RANDOM[:4], method=method, threads=1)
    r = benchmark(fb.solve_many, BEARING, RANDOM, method=method, threads=1)
    assert r.converged.all()
    if not benchmark.disabled:  # --benchmark-disable: a smoke run, no figures
        benchmark.extra_info.update(us_per_solve=benchmark.stats.stats.median / len(RANDOM) * 1e6,
                                    iterations=float(r.iterations.mean()), evaluations=float(r.evaluations.mean()))


BATCH = random_loads(100_000, seed=1)


@pytest.mark.parametrize("threads", [1, 2])
@pytest.mark.benchmark(group="batch: solve_many, 100 000 random loads")
def test_batch(benchmark, threads):
    fb.solve_many(BEARING, BATCH[:8], threads=threads)
    r = benchmark.pedantic(fb.solve_many, args=(BEARING, BATCH), kwargs=dict(threads=threads), rounds=3)
    assert r.converged.all()
    if not benchmark.disabled:  # --benchmark-disable: a smoke run, no figures
        benchmark.extra_info["cases_per_s"] = len(BATCH) / benchmark.stats.stats.median
