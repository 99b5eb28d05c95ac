"""High speed (issue 13): a load-given solve at speed against the quasi-static solve of the same bearing
and loads, and a load map with a speed axis.

Targets: a high-speed solve costs at most 6x a quasi-static one (solve_many over the same random loads,
same process), and a high-speed map runs at >= 100 000 cases/s on 2 cores.
"""

import tomllib
from pathlib import Path

import numpy as np
import pytest
from conftest import random_loads

import fastbearing as fb

ROOT = Path(__file__).resolve().parents[1]
SPINDLE = fb.load_bearing(ROOT / "fastbearing" / "catalogue" / "7014C-DB.toml")
#: Combined loads scaled to the spindle pair (Fx, Fy +-1.5 kN, Fz +-4 kN, moments +-50 N*m).
LOADS = random_loads(2000, seed=3) * 0.5


@pytest.mark.parametrize("speed", [0.0, 12000.0])
@pytest.mark.benchmark(group="solve: 7014C-DB, 2000 random loads, cold, 1 thread (0 rpm: baseline)")
def test_solve_at_speed(benchmark, speed):
    fb.solve_many(SPINDLE, LOADS[:4], speed=speed, threads=1)
    out = benchmark(fb.solve_many, SPINDLE, LOADS, speed=speed, threads=1)
    assert out.converged.mean() > 0.99
    if not benchmark.disabled:  # --benchmark-disable: a smoke run, no figures
        benchmark.extra_info.update(us_per_case=benchmark.stats.stats.median / len(LOADS) * 1e6,
                                    evaluations_per_case=float(np.mean(out.evaluations)))


QJ210 = fb.load_bearing(ROOT / "fastbearing" / "catalogue" / "QJ210.toml")
#: Fx, Fy, Fz up to 3 kN each way, no moment (the four-point QJ 210 and the 7014C-DB pair alike).
POINT_LOADS = np.column_stack([np.random.default_rng(3).uniform(-3000.0, 3000.0, (2000, 3)), np.zeros((2000, 2))])


@pytest.mark.parametrize("name", ["QJ210 four-point", "7014C-DB angular contact"])
@pytest.mark.benchmark(group="solve at 10 000 rpm: four-point QJ 210 against the 7014C-DB pair, same 2000 loads, "
                             "cold, 1 thread (issue 47: within 3x per ball)")
def test_four_point_ball_at_speed(benchmark, name):
    bearing = QJ210 if name.startswith("QJ") else SPINDLE
    balls = bearing.n_balls // 2 if name.startswith("QJ") else bearing.n_balls  # a four-point ball is two pairs
    fb.solve_many(bearing, POINT_LOADS[:4], speed=10000.0, threads=1)
    out = benchmark(fb.solve_many, bearing, POINT_LOADS, speed=10000.0, threads=1)
    assert out.converged.mean() > 0.99
    if not benchmark.disabled:
        us = benchmark.stats.stats.median / len(POINT_LOADS) * 1e6
        benchmark.extra_info.update(us_per_case=us, us_per_ball=us / balls,
                                    evaluations_per_case=float(np.mean(out.evaluations)))


def speed_map(num_fx=3, num_fz=41):
    """The shipped example's grid, 25 speeds x num_fx radial loads (0-1000 N) x num_fz axial loads (0-2000 N)."""
    doc = tomllib.loads((ROOT / "data" / "examples" / "spindle-7014-speed.toml").read_text())
    doc["loadmap"]["Fx"] = {"start": 0.0, "stop": 1000.0, "num": num_fx}
    doc["loadmap"]["Fz"] = {"start": 0.0, "stop": 2000.0, "num": num_fz}
    return doc


@pytest.mark.benchmark(group="load map: 7014C-DB over speed, 25 x 10 x 400 = 100 000 cases, 2 threads")
def test_speed_map(benchmark, tmp_path):
    """100 000 cases, so that the file's fixed cost (about 50 ms) does not hide the per-case rate; the 1M map
    the issue names runs at the same rate and would take about 20 s per round (measured by hand)."""
    fb.loadmap(speed_map(2, 2), tmp_path / "warm.h5", threads=2, progress=False)
    counter = iter(range(100))
    small = benchmark.disabled  # --benchmark-disable: a smoke run, the shipped example's 3075 cases
    config = speed_map() if small else speed_map(10, 400)
    out = benchmark.pedantic(lambda: fb.loadmap(config, tmp_path / f"m{next(counter)}.h5", threads=2,
                                                progress=False), rounds=3)
    n = fb.open_dataset(out)["status"].size
    assert n == (3075 if small else 100_000)
    if not benchmark.disabled:
        benchmark.extra_info["cases_per_s"] = n / benchmark.stats.stats.median
