"""Roller rows (issue 14): the slice loop's cost per slice contact and a double-row tapered map.

Targets: <= 8 ns per slice contact (f and Kb) and >= 60 000 cases/s for the TDO example map with 30
slices on 2 cores. The ball kernel on the paper's bearing runs in the same process as the baseline.
"""

import tomllib
from pathlib import Path

import pytest
from conftest import BEARING, repeat_kernel

import fastbearing as fb

TDO_FILE = Path(__file__).resolve().parents[1] / "fastbearing" / "catalogue" / "30206-TDO.toml"
TDO = fb.load_bearing(TDO_FILE)
EVALS_PER_ROUND = 200


@pytest.mark.parametrize("bearing", ["30206 TDO, 2 x 17 rollers x 30 slices", "paper DB, 28 balls (baseline)"])
@pytest.mark.benchmark(group="kernel per contact: roller slices against balls")
def test_kernel_per_contact(benchmark, bearing):
    b = TDO if bearing.startswith("30206") else BEARING
    # the balls off the xz-plane (Fy, Mx): the kernel sums every ball, as it does every roller slice
    load = [4000.0, 0.0, 1500.0, 0.0, 0.0] if b is TDO else [1000.0, 300.0, 3000.0, 5000.0, -74000.0]
    q = fb.solve(b, load).q.copy()
    balls = b.ball_set()
    contacts = b.n_balls + b.slice_table().shape[1]
    repeat_kernel(q, balls, 2)
    benchmark(repeat_kernel, q, balls, EVALS_PER_ROUND)
    if not benchmark.disabled:  # --benchmark-disable: a smoke run, no figures
        per_eval = benchmark.stats.stats.median / EVALS_PER_ROUND
        benchmark.extra_info.update(ns_per_contact=per_eval / contacts * 1e9, us_per_evaluation=per_eval * 1e6)


def tdo_map(num_my=100):
    """Fx 500-8000 N (30) x Fz 0-3000 N (20) x My +-100 N*m along the line: 60 000 cases at 100."""
    return {"bearing": tomllib.loads(TDO_FILE.read_text())["bearing"],
            "loadmap": {"given": "load", "Fx": {"start": 500.0, "stop": 8000.0, "num": 30}, "Fy": 0.0,
                        "Fz": {"start": 0.0, "stop": 3000.0, "num": 20}, "Mx": 0.0,
                        "My": {"start": -1e5, "stop": 1e5, "num": num_my}}}


@pytest.mark.benchmark(group="load map: 30206 TDO, 60 000 cases, 30 slices, 2 threads")
def test_tdo_map(benchmark, tmp_path):
    fb.loadmap(tdo_map(2), tmp_path / "warm.h5", threads=2, progress=False)
    counter = iter(range(100))
    out = benchmark.pedantic(lambda: fb.loadmap(tdo_map(), tmp_path / f"m{next(counter)}.h5", threads=2,
                                                progress=False), rounds=3)
    ds = fb.open_dataset(out)
    assert ds["status"].size == 60_000
    if not benchmark.disabled:  # --benchmark-disable: a smoke run, no figures
        benchmark.extra_info["cases_per_s"] = 60_000 / benchmark.stats.stats.median
