"""Local defects (issue 37): a ball-passage table of the 6205 (the CWRU data set's drive-end bearing) over 10
shaft revolutions at 1 024 positions per revolution (10 240 positions), an outer-race spall, load given
(2.2 kN radial), against the same table without the defect, in the same process: time per position.

    python -m pytest bench/test_defects.py --benchmark-only
"""

from pathlib import Path

import numba
import numpy as np
import pytest

from fastbearing.jobs import passage, runner

BEARING = str(Path(__file__).resolve().parents[1] / "fastbearing" / "catalogue" / "6205.toml")
SPALL = [{"race": "outer", "angle": 0.0, "width": 1.0, "depth": 0.05}]


def _compute(defects):
    spec = {"given": "load", "Fx": 2200.0, "positions": 1024, "revolutions": 10, "harmonics": 64}
    if defects:
        spec["defects"] = defects
    cfg = passage.read_config({"bearing": BEARING, "passage": spec})
    job = passage.job(cfg)
    inputs = cfg.cases.inputs(0, 1)
    buf = runner.Buffers(list(job.variables), job.sizes, 1)
    stop = np.zeros(1, np.int64)

    def run():
        job.compute(inputs, buf.view(1), 0, stop)
        return buf.view(1)

    return run, cfg.n_positions


@pytest.mark.parametrize("defects", [None, SPALL], ids=["no defect", "outer-race spall"])
def test_defect_table_per_position(benchmark, defects):
    run, positions = _compute(defects)
    numba.set_num_threads(1)
    try:
        res = run()  # loads the kernels
        assert (res["status"] == 0).all()
        benchmark.extra_info.update(positions=positions)
        benchmark.pedantic(run, rounds=3, iterations=1)
    finally:
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
