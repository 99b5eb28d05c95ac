"""Not a benchmark: an A/B of the engine's CPU compute, this tree against an older revision, in one process.

    python bench/ab_trees.py REV [rounds] [threads] [workload]

``git archive REV`` is unpacked into a temporary folder and its package imported as ``fastbearing_ab`` beside
this tree's ``fastbearing`` (each with its own numba cache), so both run in the same process on the same
machine state, alternating round by round. Timed, compute alone (no HDF5), as the runner calls it:

- the 1M example map: 198 000 cases (2 000 lines of 99) in one block (``loadmap.compute_block``);
- the speed map: the shipped spindle example at 25 speeds x 10 x 400 (100 000 cases) in one block;
- a ball-passage table: the DB pair, 1000 points x 64 positions (``passage.compute_block``);
- the roller map: bench/test_rollers.py's 30206 TDO pair, 60 000 cases in one block;
- a batch: ``solve_many`` of 100 000 random loads on the DB pair, cold (the sweep's blocks of independent solves).

Prints the median (min) seconds of each and whether both trees' results are equal bit for bit (every array;
those that differ are named). ``workload``: only those whose name contains it (e.g. ``speed``).
Used for issue 46 (the engine's records replacing positional lists must leave the CPU's speed unchanged) and
issue 45 (threads instead of ``prange``). ``AB_FOLDER=DIR`` unpacks REV there once and keeps it, with its numba
cache, for the next run (else a temporary folder: the old tree compiles again every run).
"""

import importlib
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numba
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # this tree's package, whatever else is installed


def load_old(rev: str, folder: Path):
    """The package of ``rev`` importable as ``fastbearing_ab`` (its relative imports keep it to itself)."""
    if (folder / "fastbearing_ab").is_dir():  # kept by AB_FOLDER
        sys.path.insert(0, str(folder))
        return importlib.import_module("fastbearing_ab")
    tar = subprocess.run(["git", "-C", str(ROOT), "archive", rev, "fastbearing"], capture_output=True, check=True)
    subprocess.run(["tar", "-x", "-C", str(folder)], input=tar.stdout, check=True)
    shutil.move(folder / "fastbearing", folder / "fastbearing_ab")
    sys.path.insert(0, str(folder))
    return importlib.import_module("fastbearing_ab")


def map_case(pkg: str, config, n: int):
    """(compute, buffers, inputs) of the first n cases of a load map, in one block."""
    loadmap = importlib.import_module(f"{pkg}.jobs.loadmap")
    runner = importlib.import_module(f"{pkg}.jobs.runner")
    cfg = loadmap.read_config(config)
    job = loadmap.job(cfg)
    buf = runner.Buffers(list(job.variables), job.sizes, n)
    return job.compute, buf.view(n), cfg.cases.inputs(0, n)


def passage_case(pkg: str, config):
    passage = importlib.import_module(f"{pkg}.jobs.passage")
    runner = importlib.import_module(f"{pkg}.jobs.runner")
    cfg = passage.read_config(config)
    job = passage.job(cfg)
    n = cfg.cases.n_cases
    buf = runner.Buffers(list(job.variables), job.sizes, n)
    return job.compute, buf.view(n), cfg.cases.inputs(0, n)


def batch_case(pkg: str, n: int):
    """(compute, results, loads) of ``solve_many`` on n random loads of the DB pair, cold: the batch's sweep."""
    fb = importlib.import_module(pkg)
    bearing = fb.Bearing.preset("gunduz2013", "DB")
    rng = np.random.default_rng(0)
    loads = np.column_stack([rng.uniform(0, 5000, n), np.zeros(n), rng.uniform(0, 5000, n), np.zeros(n),
                             rng.uniform(-1e5, 1e5, n)])
    res = {}

    def compute(inputs, res, first, stop):
        out = fb.solve_many(bearing, inputs)
        res.update(q=out.q, K=out.K, status=out.status, iterations=out.iterations)

    return compute, res, loads


def workloads():
    import tomllib

    speed = tomllib.loads((ROOT / "data" / "examples" / "spindle-7014-speed.toml").read_text())
    speed["loadmap"]["Fx"] = {"start": 0.0, "stop": 1000.0, "num": 10}
    speed["loadmap"]["Fz"] = {"start": 0.0, "stop": 2000.0, "num": 400}
    speed["bearing"] = str(ROOT / "fastbearing" / "catalogue" / "7014C-DB.toml")
    tdo = tomllib.loads((ROOT / "fastbearing" / "catalogue" / "30206-TDO.toml").read_text())
    roller = {"bearing": tdo["bearing"],
              "loadmap": {"given": "load", "Fx": {"start": 500.0, "stop": 8000.0, "num": 30}, "Fy": 0.0,
                          "Fz": {"start": 0.0, "stop": 3000.0, "num": 20}, "Mx": 0.0,
                          "My": {"start": -1e5, "stop": 1e5, "num": 100}}}
    table = {"bearing": {"preset": "gunduz2013", "arrangement": "DB"},
             "passage": {"given": "load", "Fx": {"start": 200.0, "stop": 5000.0, "num": 40},
                         "Fz": {"start": 500.0, "stop": 5000.0, "num": 25}, "My": -74000.0, "positions": 64}}
    return {"1M example map, 198 000 cases": lambda pkg: map_case(pkg, ROOT / "data" / "examples" /
                                                                  "gunduz2013-db-1M.toml", 198_000),
            "speed map, 100 000 cases": lambda pkg: map_case(pkg, speed, 100_000),
            "passage table, 1000 x 64": lambda pkg: passage_case(pkg, table),
            "roller map, 60 000 cases": lambda pkg: map_case(pkg, roller, 60_000),
            "batch, 100 000 solves": lambda pkg: batch_case(pkg, 100_000)}


def differences(a: dict, b: dict) -> list[str]:
    """The result arrays that differ between the trees, with how many entries."""
    out = []
    for k in a:
        x, y = a[k], b[k]
        same = (x == y) | (np.isnan(x) & np.isnan(y)) if x.dtype.kind == "f" else x == y
        if not same.all():
            out.append(f"{k} ({int((~same).sum())} of {same.size})")
    return out


def main(rev="HEAD", rounds=5, threads=None, only=""):
    if threads:
        numba.set_num_threads(int(threads))
    keep = os.environ.get("AB_FOLDER")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(keep) if keep else Path(tmp)
        folder.mkdir(parents=True, exist_ok=True)
        load_old(rev, folder)
        import fastbearing

        print(f"A: {rev} (fastbearing_ab), B: {Path(fastbearing.__file__).parent}; {numba.get_num_threads()} threads, "
              f"{rounds} rounds")
        for name, make in workloads().items():
            if only and only not in name:
                continue
            runs = {tree: make(pkg) for tree, pkg in (("A", "fastbearing_ab"), ("B", "fastbearing"))}
            stop = np.zeros(1, np.int64)
            for compute, res, inputs in runs.values():
                compute(inputs, res, 0, stop)  # loads (or compiles) the kernels
            times = {tree: [] for tree in runs}
            for _ in range(int(rounds)):
                for tree, (compute, res, inputs) in runs.items():
                    started = time.perf_counter()
                    compute(inputs, res, 0, stop)
                    times[tree].append(time.perf_counter() - started)
            differ = differences(runs["A"][1], runs["B"][1])
            same = "yes" if not differ else "no: " + ", ".join(differ)
            text = ", ".join(f"{tree} {np.median(t):.3f} s ({min(t):.3f})" for tree, t in times.items())
            ratio = np.median(times["B"]) / np.median(times["A"])
            print(f"{name}: {text}; B/A {ratio:.3f}; results equal bit for bit: {same}")


if __name__ == "__main__":
    main(*sys.argv[1:5])
