"""Start-up: a whole `python -c "import fastbearing; <one solve>"` process, cold and warm.

Cold: numba's cache is redirected to an empty folder (NUMBA_CACHE_DIR), so
every kernel the solve needs is compiled. Warm: the same with the cache filled.
"""

import os
import subprocess
import sys

import pytest

SCRIPT = ("import fastbearing as fb; "
          "r = fb.solve(fb.Bearing.preset('gunduz2013', 'DB'), [1000.0, 0.0, 3000.0, 0.0, -74000.0]); "
          "assert r.converged")


@pytest.mark.benchmark(group="start-up to the first solve, whole process")
def test_startup(benchmark, tmp_path):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba-cache")}

    def run():
        subprocess.run([sys.executable, "-c", SCRIPT], env=env, check=True, timeout=300)

    import time
    t = time.perf_counter()
    run()  # cold: empty cache
    cold = time.perf_counter() - t
    benchmark.pedantic(run, rounds=3)  # warm
    if not benchmark.disabled:  # --benchmark-disable: a smoke run, no figures
        benchmark.extra_info.update(cold_s=cold, warm_s=benchmark.stats.stats.median)


FLOOR_MODULE = "from numba import njit\n\n\n@njit(cache=True)\ndef one(x):\n    return x + 1.0\n"


@pytest.mark.benchmark(group="start-up to the first solve, whole process")
def test_numba_floor(benchmark, tmp_path):
    """The floor under any numba program here: import numba and call one trivial cached function (warm
    cache). fastbearing's warm start-up above cannot go below it without leaving numba's runtime."""
    (tmp_path / "floor.py").write_text(FLOOR_MODULE)
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba-cache"), "PYTHONPATH": str(tmp_path)}

    def run():
        subprocess.run([sys.executable, "-c", "import floor; floor.one(1.0)"], env=env, check=True, timeout=120)

    run()  # fill the cache
    benchmark.pedantic(run, rounds=3)


ONE_CASE_MAP = """[bearing]
preset = "gunduz2013"
arrangement = "DB"

[loadmap]
given = "load"
Fx = 1000.0
Fz = 3000.0
My = -74000.0
"""


@pytest.mark.benchmark(group="start-up to the first solve, whole process")
def test_command_startup(benchmark, tmp_path):
    """The command line's way to a first solve: `fastbearing loadmap` of a one-case map, the whole process
    (start-up, the solve, its HDF5 file written and closed, exit), warm cache."""
    config = tmp_path / "one.toml"
    config.write_text(ONE_CASE_MAP)
    command = [sys.executable, "-c", "import sys; from fastbearing.cli import entry_point; sys.exit(entry_point())",
               "loadmap", str(config), "-o", str(tmp_path / "one.h5"), "--overwrite", "--no-progress"]

    def run():
        subprocess.run(command, check=True, timeout=300, capture_output=True)

    run()  # fill the cache (the map sweep compiles once)
    benchmark.pedantic(run, rounds=5)


@pytest.mark.benchmark(group="start-up: fastbearing --help, whole process")
def test_help(benchmark):
    """The command line's parser loads no numba, scipy or h5py (the package's names load on first use)."""

    def run():
        out = subprocess.run([sys.executable, "-m", "fastbearing.cli", "--help"], check=True, timeout=60,
                             capture_output=True, text=True)
        assert "loadmap" in out.stdout

    benchmark.pedantic(run, rounds=5)
