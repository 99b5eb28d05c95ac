"""What cutting a map's continuation runs into short GPU segments costs, measured on the CPU (issue 46 item 2).

    python bench/gpu_segments.py [n_fx] [rounds]     # default: 10 Fx values of the 1M example (99 000 cases), 3

The GPU needs >= 100 000 threads per launch; the 1M example has 10 100 runs (lines of 99 cases along My). A run cut
into pieces (engine.gpu.device_segments) gives one thread per piece, each piece starting cold. This script runs the
CPU's own map sweep (engine.sweep.map_sweep, one thread) on a slice of the 1M example with the runs cut into
pieces of at most L cases, L from 1 (one case per thread, all cold) to 99 (the CPU's runs), and prints per L: the
threads the whole 1M map would get, seconds per case (best of ``rounds``), mean Newton iterations, and against the
CPU's runs: statuses that differ, outcome flips, and the largest relative difference of q and Kb where both
converged. The CPU's cost per case stands in for the GPU's (the same kernels; a cold start costs more Newton
iterations on either). Units: N, N*mm, mm, rad.
"""

import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import numba  # noqa: E402

from fastbearing import status as st  # noqa: E402
from fastbearing.engine import gpu  # noqa: E402
from fastbearing.engine.sweep import map_sweep  # noqa: E402
from fastbearing.jobs import loadmap, storage  # noqa: E402
from fastbearing.model.bearing_file import read_toml  # noqa: E402

LENGTHS = (1, 2, 4, 6, 8, 10, 16, 33, 99)


def block(n_fx):
    """(job, inputs, fresh results) of the 1M example with ``n_fx`` Fx values (all Fz, My)."""
    cfg = read_toml(ROOT / "data" / "examples" / "gunduz2013-db-1M.toml")
    cfg["loadmap"]["Fx"]["num"] = n_fx
    job = loadmap.job(loadmap.read_config(cfg))
    n = job.cases.n_cases
    return job, job.cases.inputs(0, n), n


def run(job, inputs, n, longest, rounds):
    """(best seconds, results dict) of the CPU sweep with the runs cut at ``longest`` cases."""
    work = job.compute.args[0]  # loadmap.MapWork
    best, res = np.inf, None
    for _ in range(rounds):
        res = storage.allocate(job.variables, job.sizes, n)
        elements, cases = loadmap.block_records(work.bearing, work.line_length, work.life, work.spinning, inputs,
                                                res, 0)
        cases = cases._replace(segments=gpu.device_segments(cases.segments, longest))
        started = time.perf_counter()
        map_sweep(elements, cases, work.given_load, work.settings, np.zeros(1, np.int64))
        best = min(best, time.perf_counter() - started)
    return best, res


def main(n_fx=10, rounds=3):
    numba.set_num_threads(1)
    job, inputs, n = block(n_fx)
    run(job, inputs, n, 99, 1)  # compile
    results = {L: run(job, inputs, n, L, rounds) for L in LENGTHS}
    base = results[99][1]
    ok = (base["status"] & st.OUTCOME_MASK) == st.CONVERGED
    print(f"1M example, {n_fx} Fx values: {n:,d} cases, one CPU thread, best of {rounds}")
    print("L | threads for the 1M map | us per case | x the CPU's runs | iterations per case | statuses differ | "
          "outcome flips | max rel diff q, Kb (both converged)")
    for L, (t, res) in results.items():
        threads = len(gpu.device_segments(np.arange(0, 999_901, 99), L)) - 1
        both = ok & ((res["status"] & st.OUTCOME_MASK) == st.CONVERGED)
        diff = 0.0
        for key in ("q", "K"):
            a, b = res[key][both].reshape(both.sum(), -1), base[key][both].reshape(both.sum(), -1)
            diff = max(diff, float((np.abs(a - b).max(axis=1) / np.abs(b).max(axis=1)).max()))
        flips = int(((res["status"] & st.OUTCOME_MASK) != (base["status"] & st.OUTCOME_MASK)).sum())
        print(f"{L} | {threads:,d} | {1e6 * t / n:.2f} | {t / results[99][0]:.2f} | {res['iterations'].mean():.2f} | "
              f"{int((res['status'] != base['status']).sum())} | {flips} | {diff:.1e}", flush=True)


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:]))
