"""fastbearing against the reference peer (scipy.optimize.root "hybr" + numpy), same loads, same process.

The peer is slow, so it runs on the first 100 of the random loads;
fastbearing solves the same 100 loads ten times over in one call (every
solve is an independent cold start) so that its per-solve time is not
dominated by the fixed cost of one Python call. The speed-up compares time
per solve. The peer's answers must agree with fastbearing's.
"""

import numpy as np
import pytest
from conftest import BEARING, random_loads

import fastbearing as fb
import peer_scipy

LOADS = random_loads(1000)[:100]
_times = {}


@pytest.mark.benchmark(group="peer: load-given solve, 100 random combined loads")
def test_peer_scipy_hybr(benchmark):
    table = BEARING.ball_table()
    out = benchmark.pedantic(lambda: [peer_scipy.solve(table, f, BEARING.length_scale) for f in LOADS], rounds=3)
    q = np.array([o[0] for o in out])
    assert all(o[1] for o in out)
    ref = fb.solve_many(BEARING, LOADS, threads=1)
    np.testing.assert_allclose(q, ref.q, rtol=1e-7, atol=1e-9 * np.abs(ref.q).max())
    if not benchmark.disabled:  # --benchmark-disable: a smoke run, no figures
        _times["peer"] = benchmark.stats.stats.median / len(LOADS)
        benchmark.extra_info["us_per_solve"] = _times["peer"] * 1e6


@pytest.mark.benchmark(group="peer: load-given solve, 100 random combined loads")
def test_fastbearing_same_loads(benchmark):
    repeated = np.tile(LOADS, (10, 1))
    fb.solve_many(BEARING, LOADS[:4], threads=1)
    benchmark(fb.solve_many, BEARING, repeated, threads=1)
    if not benchmark.disabled:  # --benchmark-disable: a smoke run, no figures
        mine = benchmark.stats.stats.median / len(repeated)
        benchmark.extra_info["us_per_solve"] = mine * 1e6
        if "peer" in _times:
            benchmark.extra_info["speedup_vs_scipy"] = _times["peer"] / mine
