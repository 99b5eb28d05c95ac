"""Mixed boundary conditions (issue 34): a load map with the tilt held (bx = 0, by an axis) against the same
grid with every load given (My an axis), 99 000 cases of the paper's DB pair each, the map's work unit
(``compute_block``, no file) on one thread, in the same process. Target: the fixed map as fast per case as
the all-load map (the solver works on the reduced system, the predictor too).

    python -m pytest bench/test_boundary.py --benchmark-only
"""

import numba
import numpy as np
import pytest

from fastbearing.jobs import loadmap, runner

GRID = {"Fx": {"start": -2000.0, "stop": 2000.0, "num": 10}, "Fz": {"start": 500.0, "stop": 10000.0, "num": 100}}
CONFIGS = {
    "all loads given (My axis)": {**GRID, "My": {"start": -1.0e5, "stop": 1.0e5, "num": 99}},
    "tilt held (bx = 0, by axis)": {**GRID, "fixed": {"bx": 0.0, "by": {"start": -1e-3, "stop": 1e-3, "num": 99}}},
}


def _compute(spec):
    cfg = loadmap.read_config({"bearing": {"preset": "gunduz2013", "arrangement": "DB"}, "loadmap": spec})
    job = loadmap.job(cfg)
    n = cfg.cases.n_cases
    inputs = cfg.cases.inputs(0, n)
    buf = runner.Buffers(list(job.variables), job.sizes, n)
    stop = np.zeros(1, np.int64)

    def run():
        job.compute(inputs, buf.view(n), 0, stop)
        return buf.view(n)

    return run, n


@pytest.mark.parametrize("name", list(CONFIGS))
def test_map_with_fixed_degrees_of_freedom(benchmark, name):
    run, n = _compute(CONFIGS[name])
    numba.set_num_threads(1)
    try:
        res = run()  # loads the kernels
        assert (res["status"] == 0).all()
        benchmark.extra_info.update(cases=n, iterations_per_case=float(res["iterations"].mean()))
        benchmark.pedantic(run, rounds=3, iterations=1)
    finally:
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
