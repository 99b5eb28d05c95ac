"""The job runner's promises that are about time and memory, measured (never asserted in tests/):

- memory is bounded by one block, not by the map: peak RSS of a 200 000-case
  map against a 4 000-case one, same block size (child processes);
- Ctrl-C stops a running map within about a second: time from SIGINT to the
  process's exit, with the finished blocks kept (extra_info sigint_to_exit_s;
  the timed figure itself is the whole child process).
"""

import json
import signal
import subprocess
import sys
import time

import h5py
import pytest

CHILD = """
import json, resource, sys
from fastbearing.loadmap import loadmap
loadmap(json.loads(sys.argv[1]), sys.argv[2], progress=False)
print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)
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


KILL_MAP = ('[bearing]\npreset = "gunduz2013"\narrangement = "DB"\n\n[loadmap]\n'
            "Fx = { start = -2000.0, stop = 2000.0, num = 60 }\nFz = { start = 500.0, stop = 10000.0, num = 40 }\n"
            "My = { start = -1.0e5, stop = 1.0e5, num = 50 }\nchunk = 2000\n")


def _blocks_done(part):
    try:
        with h5py.File(part, "r", locking=False) as fh:
            return int(fh["block_done"][...].sum())
    except (OSError, KeyError):
        return 0


@pytest.mark.benchmark(group="job runner: Ctrl-C to exit, 120 000-case map, blocks of 2 000")
def test_ctrl_c_latency(benchmark, tmp_path):
    cfg = tmp_path / "k.toml"
    cfg.write_text(KILL_MAP)

    def run():
        part = tmp_path / "k.h5.part"
        part.unlink(missing_ok=True)
        proc = subprocess.Popen([sys.executable, "-m", "fastbearing.cli", "loadmap", str(cfg), "--threads", "1"],
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tmp_path)
        while proc.poll() is None and _blocks_done(part) < 2:
            time.sleep(0.01)
        sent = time.perf_counter()
        proc.send_signal(signal.SIGINT)
        proc.communicate(timeout=60)
        latencies.append(time.perf_counter() - sent)
        assert proc.returncode == 130

    latencies = []
    benchmark.pedantic(run, rounds=3, iterations=1)      # times start-up to exit; the figure is the latency
    if not benchmark.disabled:
        benchmark.extra_info["sigint_to_exit_s"] = sorted(latencies)[len(latencies) // 2]
