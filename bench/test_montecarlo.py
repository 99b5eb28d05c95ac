"""Tolerance zones sampled (issue 44 item 6): a million samples of the 6205 on k5 / H7 under one load, end to end
(drawing, budgeting, solving in clearance order, HDF5 writing; the summary timed apart), against the 1M example
map run in the same child process as the baseline (a ratio: this shared VM drifts by 10-40 %).

Target (issue 44): 10^6 samples <= 2 s on this 2-core machine."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "data" / "examples" / "6205-k5-montecarlo.toml"
MAP = ROOT / "data" / "examples" / "gunduz2013-db-1M.toml"

CHILD = """
import json, sys, time, tomllib
import fastbearing as fb
from fastbearing.jobs import montecarlo as mc
doc = tomllib.loads(open(sys.argv[1]).read())
doc["montecarlo"].update(samples=1_000_000, speed=0.0)        # the issue's case: one load, at rest
small = {**doc, "montecarlo": {**doc["montecarlo"], "samples": 1000}}
mc.montecarlo(small, sys.argv[3] + ".warm.h5", overwrite=True, progress=False)    # kernels compiled or loaded
mapdoc = tomllib.loads(open(sys.argv[2]).read())
fb.loadmap({**mapdoc, "loadmap": {**mapdoc["loadmap"], "Fx": {**mapdoc["loadmap"]["Fx"], "num": 2}}},
           sys.argv[3] + ".warm-map.h5", overwrite=True, progress=False)
out = {}
for _ in range(2):
    t = time.perf_counter()
    fb.loadmap(mapdoc, sys.argv[3] + ".map.h5", overwrite=True, progress=False)
    base = time.perf_counter() - t
    cfg = mc.read_config(doc)
    t = time.perf_counter()
    path = mc.jobs.run(mc.job(cfg), sys.argv[3], overwrite=True, progress=False)
    run = time.perf_counter() - t
    t = time.perf_counter()
    mc.summarize(path)
    summary = time.perf_counter() - t
    if not out or run < out["samples_s"]:
        out = {"samples_s": run, "summary_s": summary, "map_s": base}
print(json.dumps(out))
"""


@pytest.mark.benchmark(group="Monte Carlo: 10^6 samples of the 6205 on k5 / H7, one load at rest, to HDF5, 2 threads")
def test_million_samples(benchmark, tmp_path):
    out = tmp_path / "mc.h5"

    def run():
        p = subprocess.run([sys.executable, "-c", CHILD, str(EXAMPLE), str(MAP), str(out)], capture_output=True,
                           text=True, timeout=900)
        assert p.returncode == 0, p.stderr
        return json.loads(p.stdout.strip().splitlines()[-1])

    result = benchmark.pedantic(run, rounds=1, iterations=1)
    if not benchmark.disabled:  # --benchmark-disable: a smoke run, no figures
        benchmark.extra_info.update(samples_s=result["samples_s"], summary_s=result["summary_s"],
                                    map_1M_s=result["map_s"], ratio_to_1M_map=result["samples_s"] / result["map_s"])
