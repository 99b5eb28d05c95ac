"""The job runner's promises that are about time and memory, measured (never asserted in tests/):

- memory is bounded by one block, not by the map: peak RSS of a 200 000-case
  map against a 4 000-case one, same block size (child processes);
- memory does not depend on the map's shape: peak RSS of a 2 000 000-case
  line (one axis) against a 2 000 000-case 3-D grid, default chunk;
- Ctrl-C stops a running map within about a second: time from SIGINT to the
  process's exit, with the finished blocks kept (extra_info sigint_to_exit_s;
  the timed figure itself is the whole child process), on an easy map in
  small blocks and on a hard one (loads of about 1 N on a single row with
  clearance) in the default blocks of several seconds each.
"""

import json
import signal
import subprocess
import sys
import time

import h5py
import pytest
from conftest import PEAK_RSS

CHILD = PEAK_RSS + """
import json, sys
from fastbearing.jobs.loadmap import loadmap
loadmap(json.loads(sys.argv[1]), sys.argv[2], progress=False)
print(own_peak_kb())
"""
BEARING = {"preset": "gunduz2013", "arrangement": "DB"}


def displacement_map(n_dx):
    return {"bearing": BEARING, "loadmap": {"given": "displacement", "dx": {"start": -0.02, "stop": 0.02, "num": n_dx},
                                            "dz": {"start": 0.0, "stop": 0.03, "num": 100}, "chunk": 4000}}


def peak_rss_mb(config, out):
    p = subprocess.run([sys.executable, "-c", CHILD, json.dumps(config), str(out)], capture_output=True, text=True,
                       timeout=600)
    assert p.returncode == 0, p.stderr
    return int(p.stdout.split()[-1]) / 1024


@pytest.mark.benchmark(group="job runner: peak RSS, 4 000 vs 200 000 cases in blocks of 4 000")
def test_memory_is_bounded_by_the_block(benchmark, tmp_path):
    def run():
        return peak_rss_mb(displacement_map(40), tmp_path / "small.h5"), peak_rss_mb(displacement_map(2000),
                                                                                     tmp_path / "large.h5")

    small, large = benchmark.pedantic(run, rounds=1, iterations=1)
    if not benchmark.disabled:
        benchmark.extra_info.update(peak_rss_small_mb=small, peak_rss_large_mb=large, growth_mb=large - small,
                                    results_mb=200_000 * 332 / 2**20)


def load_map(axes):
    return {"bearing": BEARING, "loadmap": {"given": "load", **axes}}


LINE_2M = {"Fz": {"start": 500.0, "stop": 10000.0, "num": 2_000_000}, "Fx": 300.0, "My": -2.0e4}
GRID_2M = {"Fx": {"start": -2000.0, "stop": 2000.0, "num": 200}, "Fz": {"start": 500.0, "stop": 10000.0, "num": 100},
           "My": {"start": -1.0e5, "stop": 1.0e5, "num": 100}}


@pytest.mark.benchmark(group="job runner: peak RSS, 2 000 000 cases as one line vs a 200 x 100 x 100 grid")
def test_memory_does_not_depend_on_the_shape(benchmark, tmp_path):
    def run():
        return (peak_rss_mb(load_map(LINE_2M), tmp_path / "line.h5"),
                peak_rss_mb(load_map(GRID_2M), tmp_path / "grid.h5"))

    line, grid = benchmark.pedantic(run, rounds=1, iterations=1)
    if not benchmark.disabled:
        benchmark.extra_info.update(peak_rss_line_mb=line, peak_rss_grid_mb=grid, line_over_grid=line / grid)


KILL_MAP = ('[bearing]\npreset = "gunduz2013"\narrangement = "DB"\n\n[loadmap]\n'
            "Fx = { start = -2000.0, stop = 2000.0, num = 60 }\nFz = { start = 500.0, stop = 10000.0, num = 40 }\n"
            "My = { start = -1.0e5, stop = 1.0e5, num = 50 }\nchunk = 2000\n")


def _blocks_done(part):
    try:
        with h5py.File(part, "r", locking=False) as fh:
            return int(fh["block_done"][...].sum())
    except (OSError, KeyError):
        return 0


def sigint_latency(benchmark, tmp_path, text, args, started):
    """Run ``fastbearing loadmap`` on the config ``text`` three times, send SIGINT once ``started(part)``
    says the map is computing, and put the median time from the signal to the process's exit into
    extra_info (the timed figure itself is the whole child process)."""
    cfg = tmp_path / "c.toml"
    cfg.write_text(text)
    part = tmp_path / "c.h5.part"
    latencies = []

    def run():
        part.unlink(missing_ok=True)
        proc = subprocess.Popen([sys.executable, "-m", "fastbearing.cli", "loadmap", str(cfg), *args],
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tmp_path)
        started(proc, part)
        sent = time.perf_counter()
        proc.send_signal(signal.SIGINT)
        proc.communicate(timeout=60)
        latencies.append(time.perf_counter() - sent)
        assert proc.returncode == 130

    benchmark.pedantic(run, rounds=3, iterations=1)
    if not benchmark.disabled:
        benchmark.extra_info["sigint_to_exit_s"] = sorted(latencies)[len(latencies) // 2]


@pytest.mark.benchmark(group="job runner: Ctrl-C to exit, 120 000-case map, blocks of 2 000")
def test_ctrl_c_latency(benchmark, tmp_path):
    def two_blocks_done(proc, part):
        while proc.poll() is None and _blocks_done(part) < 2:
            time.sleep(0.01)

    sigint_latency(benchmark, tmp_path, KILL_MAP, ["--threads", "1"], two_blocks_done)


HARD_MAP = ('[bearing]\npreset = "gunduz2013"\narrangement = "single"\nradial_clearance = 0.01\n\n[loadmap]\n'
            "Fx = { start = -1.0, stop = 1.0, num = 40 }\nFz = { start = -1.0, stop = 1.0, num = 40 }\n"
            "My = { start = -30.0, stop = 30.0, num = 1000 }\n")


# 1.6 million cases (about 10 s): the 160 000 of earlier runs now end within the second the test waits
@pytest.mark.benchmark(group="job runner: Ctrl-C to exit, hard 1 600 000-case map, default blocks")
def test_ctrl_c_latency_hard_map(benchmark, tmp_path):
    def inside_the_first_block(proc, part):
        while proc.poll() is None and not part.exists():
            time.sleep(0.01)
        time.sleep(1.0)                                  # kernels cached: the first block is computing

    sigint_latency(benchmark, tmp_path, HARD_MAP, [], inside_the_first_block)
