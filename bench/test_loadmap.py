"""Load maps end to end, including HDF5 writing.

The one-million-case example runs in a child process so its peak resident
memory can be read (VmHWM: ru_maxrss would carry the pytest parent's over
exec); the child reports the map's own wall time (after import, compiled
kernels cached).
"""

import json
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

import fastbearing as fb
from conftest import PEAK_RSS

EXAMPLE = Path(__file__).resolve().parents[1] / "data" / "examples" / "gunduz2013-db-1M.toml"

CHILD = PEAK_RSS + """
import json, sys, time, tomllib
import fastbearing as fb
doc = tomllib.loads(open(sys.argv[1]).read())
doc["loadmap"]["compression"] = sys.argv[3]
fb.loadmap({"bearing": doc["bearing"], "loadmap": {**doc["loadmap"], "Fx": {**doc["loadmap"]["Fx"], "num": 2}}},
           sys.argv[2] + ".warm.h5", overwrite=True, progress=False)  # compile/load kernels outside the timing
t = time.perf_counter()
fb.loadmap(doc, sys.argv[2], overwrite=True, progress=False)
wall = time.perf_counter() - t
print(json.dumps({"wall_s": wall, "maxrss_mb": own_peak_kb() / 1024}))
"""


@pytest.mark.parametrize("compression", ["none", "lzf"])
@pytest.mark.benchmark(group="end to end: the 1M-case example load map (999 900 cases) to HDF5, 2 threads")
def test_million_case_example(benchmark, tmp_path, compression):
    out = tmp_path / "map.h5"

    def run():
        p = subprocess.run([sys.executable, "-c", CHILD, str(EXAMPLE), str(out), compression],
                           capture_output=True, text=True, timeout=600)
        assert p.returncode == 0, p.stderr
        return json.loads(p.stdout.strip().splitlines()[-1])

    result = benchmark.pedantic(run, rounds=1, iterations=1)
    if not benchmark.disabled:  # --benchmark-disable: a smoke run, no figures
        benchmark.extra_info.update(map_wall_s=result["wall_s"], cases_per_s=999_900 / result["wall_s"],
                                    peak_rss_mb=result["maxrss_mb"], file_mb=out.stat().st_size / 2**20)


def slice_config(num_fx, compression="none"):
    doc = tomllib.loads(EXAMPLE.read_text())
    doc["loadmap"]["Fx"]["num"] = num_fx
    doc["loadmap"]["compression"] = compression
    return doc


@pytest.mark.parametrize("threads", [1, 2])
@pytest.mark.benchmark(group="load map, 10 x 100 x 99 = 99 000 load-given cases, to HDF5")
def test_loadmap_slice(benchmark, tmp_path, threads):
    cfg = slice_config(10)
    fb.loadmap(cfg, tmp_path / "warm.h5", threads=threads, progress=False)
    counter = iter(range(100))
    out = benchmark.pedantic(lambda: fb.loadmap(cfg, tmp_path / f"m{next(counter)}.h5", threads=threads,
                                                progress=False), rounds=3)
    assert fb.open_dataset(out)["status"].size == 99_000
    if not benchmark.disabled:  # --benchmark-disable: a smoke run, no figures
        benchmark.extra_info["cases_per_s"] = 99_000 / benchmark.stats.stats.median


LIFE_CHILD = """
import json, sys, time
import fastbearing as fb
doc = json.loads(sys.argv[1])
small = {**doc, "loadmap": {**doc["loadmap"], "Fx": {**doc["loadmap"]["Fx"], "num": 2}}}
fb.loadmap(small, sys.argv[2] + ".warm.h5", overwrite=True, progress=False)  # kernels compiled or loaded first
t = time.perf_counter()
fb.loadmap(doc, sys.argv[2], overwrite=True, progress=False)
print(json.dumps({"wall_s": time.perf_counter() - t}))
"""


@pytest.mark.benchmark(group="the 1M-case example grid on the SKF 3306 A (geometry), with and without life = true")
def test_life_overhead(benchmark, tmp_path):
    """Rating life adds per case only sums over the balls already loaded: the cost of life = true."""
    doc = tomllib.loads(EXAMPLE.read_text())
    bearing = tomllib.loads((EXAMPLE.parents[2] / "fastbearing" / "catalogue" / "3306.toml").read_text())["bearing"]

    def wall(life):
        config = {"bearing": bearing, "loadmap": {**doc["loadmap"], "life": life}}
        p = subprocess.run([sys.executable, "-c", LIFE_CHILD, json.dumps(config), str(tmp_path / f"m{life}.h5")],
                           capture_output=True, text=True, timeout=600)
        assert p.returncode == 0, p.stderr
        return json.loads(p.stdout.strip().splitlines()[-1])["wall_s"]

    def run():  # alternating, three of each: this VM's speed drifts from minute to minute
        pairs = [(wall(False), wall(True)) for _ in range(1 if benchmark.disabled else 3)]
        return sorted(p[0] for p in pairs)[len(pairs) // 2], sorted(p[1] for p in pairs)[len(pairs) // 2]

    without, with_life = benchmark.pedantic(run, rounds=1, iterations=1)
    if not benchmark.disabled:
        benchmark.extra_info.update(without_life_median_s=without, with_life_median_s=with_life,
                                    overhead=with_life / without - 1)


@pytest.mark.benchmark(group="one 65 536-case block of the 1M grid on the SKF 3306 A, with and without life, 1 thread")
def test_life_block_overhead(benchmark):
    """The same, in process on one thread and without HDF5: what life adds to the compute of a block
    (alternating, eight of each, medians)."""
    import importlib
    import time

    import numpy as np

    from fastbearing.jobs import storage

    loadmap = importlib.import_module("fastbearing.jobs.loadmap")
    doc = tomllib.loads(EXAMPLE.read_text())
    bearing = tomllib.loads((EXAMPLE.parents[2] / "fastbearing" / "catalogue" / "3306.toml").read_text())["bearing"]
    setups = {}
    for life in (False, True):
        cfg = loadmap.read_config({"bearing": bearing, "loadmap": {**doc["loadmap"], "life": life}})
        job = loadmap.job(cfg)
        n = 65536
        inputs = cfg.cases.inputs(0, n)
        res = storage.allocate(job.variables, job.sizes, n)
        setups[life] = (job, inputs, res, np.zeros(1, np.int64))

    def run():
        times = {False: [], True: []}
        with fb.num_threads(1):
            for _ in range(1 if benchmark.disabled else 8):
                for life, (job, inputs, res, stop) in setups.items():
                    t = time.perf_counter()
                    job.compute(inputs, res, 0, stop)
                    times[life].append(time.perf_counter() - t)
        return {k: sorted(v)[len(v) // 2] for k, v in times.items()}

    medians = benchmark.pedantic(run, rounds=1, iterations=1)
    if not benchmark.disabled:
        benchmark.extra_info.update(without_life_s=medians[False], with_life_s=medians[True],
                                    overhead=medians[True] / medians[False] - 1)
