"""Not a benchmark: the shipped 1M example's compute alone (no HDF5), as the load map runs it.

    python bench/map_compute.py [n_cases] [threads] [rounds] [Fy]

Runs ``loadmap.compute_block`` (the map's work unit) on the first ``n_cases`` cases (default 198 000,
2000 lines of 99) in one block, once to load the kernels, then ``rounds`` times, and prints the time
per case (us; median and minimum), Newton iterations per case and the statuses. ``Fy`` (N, default 0)
added to every case takes the map off the xz-plane: the kernel then sums every ball, not the mirror half.
Quoted in bench/README.md (issue 16).
"""

import importlib
import sys
import time
from pathlib import Path

import numpy as np
import numba

EXAMPLE = Path(__file__).resolve().parents[1] / "data" / "examples" / "gunduz2013-db-1M.toml"


def main(n=198_000, threads=1, rounds=5, fy=0):
    numba.set_num_threads(threads)
    loadmap = importlib.import_module("fastbearing.jobs.loadmap")
    jobs = importlib.import_module("fastbearing.jobs.runner")
    cfg = loadmap.read_config(EXAMPLE)
    job = loadmap.job(cfg)
    inputs = cfg.cases.inputs(0, n)
    inputs[:, 1] += fy
    buf = jobs.Buffers(list(job.variables), job.sizes, n)
    stop = np.zeros(1, np.int64)
    job.compute(inputs, buf.view(n), 0, stop)  # loads (or compiles) the kernels
    times = []
    for _ in range(rounds):
        t = time.perf_counter()
        job.compute(inputs, buf.view(n), 0, stop)
        times.append(time.perf_counter() - t)
    res = buf.view(n)
    print(f"{n} cases, {threads} thread(s): {np.median(times) / n * 1e6:.3f} us per case (median of {rounds}; "
          f"min {min(times) / n * 1e6:.3f}), {res['iterations'].mean():.3f} Newton iterations per case, "
          f"statuses {dict(zip(*np.unique(res['status'], return_counts=True)))}")


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:5]))
