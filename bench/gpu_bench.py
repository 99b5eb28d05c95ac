"""GPU against CPU in one run (issue 36): cold random loads, the 1M example map end to end, a speed map and a
roller map, each on the CPU (all of this machine's cores) and on the GPU (fastbearing.engine.gpu), with the
agreement of the two checked on every case (statuses equal; converged q and Kb within 1e-10 relative).

    python bench/gpu_bench.py                 # on a GPU machine: a few minutes
    python bench/gpu_bench.py --simulate      # no GPU: numba's CUDA simulator, tiny sizes (checks the script)

Prints the device, its driver and numba-cuda's version first; times exclude compiling (each device runs a small
warm-up first), maps are timed end to end (fb.loadmap: compute and HDF5 file). Units: N, N*mm, mm, rad, rpm.
The 1e8-case float32 K-only map of the issue needs [loadmap] variables/dtype, not built yet: reported as such.
"""

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def parse():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--simulate", action="store_true", help="numba's CUDA simulator (no GPU), implies --small")
    p.add_argument("--small", action="store_true", help="tiny sizes: a check of the script, not a benchmark")
    p.add_argument("--cases", type=int, default=None, help="cold random loads (default 4e6, small 48)")
    return p.parse_args()


ARGS = parse()
if ARGS.simulate:  # before numba.cuda is imported anywhere
    os.environ["NUMBA_ENABLE_CUDASIM"] = "1"
    ARGS.small = True

import numba  # noqa: E402
import numpy as np  # noqa: E402

import fastbearing as fb  # noqa: E402
from fastbearing import status as st  # noqa: E402
from fastbearing.engine import gpu  # noqa: E402


def agreement(cpu_status, gpu_status, cpu_arrays, gpu_arrays):
    """(share of equal statuses, largest per-case relative difference of the converged cases' arrays)."""
    same = float(np.mean(cpu_status == gpu_status))
    ok = ((cpu_status & st.OUTCOME_MASK) == st.CONVERGED).ravel()
    worst = 0.0
    for a, b in zip(cpu_arrays, gpu_arrays):
        a = a.reshape(ok.size, -1)[ok]
        b = b.reshape(ok.size, -1)[ok]
        if a.size:
            worst = max(worst, float((np.abs(a - b).max(axis=1) / np.maximum(np.abs(a).max(axis=1), 1e-300)).max()))
    return same, worst


def line(name, n, t_cpu, t_gpu, same, worst):
    print(f"{name:<34} {n:>11,d} cases  CPU {t_cpu:8.3f} s ({n / t_cpu:12,.0f}/s)  GPU {t_gpu:8.3f} s "
          f"({n / t_gpu:12,.0f}/s)  x{t_cpu / t_gpu:7.2f}  statuses equal {100 * same:6.2f} %  "
          f"max rel diff {worst:.1e}", flush=True)


def cold_loads(n):
    db = fb.Bearing.preset("gunduz2013", "DB")
    rng = np.random.default_rng(1)
    F = np.column_stack([rng.uniform(-2000, 2000, n), rng.uniform(-500, 500, n), rng.uniform(500, 10000, n),
                         rng.uniform(-2e4, 2e4, n), rng.uniform(-1e5, 1e5, n)])
    for device in ("cpu", "cuda"):  # warm-up: compile
        fb.solve_many(db, F[:8], device=device)
    t = time.perf_counter()
    c = fb.solve_many(db, F)
    t_cpu = time.perf_counter() - t
    t = time.perf_counter()
    g = fb.solve_many(db, F, device="cuda")
    t_gpu = time.perf_counter() - t
    line("cold random loads, DB", n, t_cpu, t_gpu, *agreement(c.status, g.status, (c.q, c.K), (g.q, g.K)))


def run_map(name, cfg, tiny, tmp):
    """One map on both devices, end to end, after a tiny warm-up map of the same kind on each."""
    import h5py

    for device in ("cpu", "cuda"):
        fb.loadmap(tiny, Path(tmp) / f"warm-{name}-{device}.h5", progress=False, device=device, overwrite=True)
    times, paths = {}, {}
    for device in ("cpu", "cuda"):
        paths[device] = Path(tmp) / f"{name}-{device}.h5"
        t = time.perf_counter()
        fb.loadmap(cfg, paths[device], progress=False, device=device, overwrite=True)
        times[device] = time.perf_counter() - t
    with h5py.File(paths["cpu"]) as a, h5py.File(paths["cuda"]) as b:
        n = a["status"].size
        same, worst = agreement(a["status"][()], b["status"][()], (a["q"][()], a["K"][()]), (b["q"][()], b["K"][()]))
    line(name, n, times["cpu"], times["cuda"], same, worst)


def axis(start, stop, num):
    return {"start": start, "stop": stop, "num": num}


def main():
    from importlib.metadata import version

    print(f"device: {gpu.describe()}")
    print(f"CPU: {os.cpu_count()} cores, {numba.config.NUMBA_NUM_THREADS} numba threads; numba {numba.__version__}, "
          f"numba-cuda {version('numba-cuda')}, numpy {np.__version__}, Python {sys.version.split()[0]}")
    small = ARGS.small
    cold_loads(ARGS.cases or (48 if small else 4_000_000))
    from fastbearing.model.bearing_file import read_toml

    example = read_toml(ROOT / "data" / "examples" / "gunduz2013-db-1M.toml")
    tiny_db = {"bearing": example["bearing"], "loadmap": example["loadmap"] | {
        "Fx": axis(-2000.0, 2000.0, 2), "Fz": axis(500.0, 10000.0, 2), "My": axis(-1e5, 1e5, 3)}}
    db = tiny_db if small else example
    spindle = read_toml(ROOT / "data" / "examples" / "spindle-7014-speed.toml")
    tiny_speed = {"bearing": spindle["bearing"], "loadmap": spindle["loadmap"] | {
        "speed": [0.0, 12000.0], "Fx": 500.0, "Fz": axis(0.0, 2000.0, 3)}}
    speed = tiny_speed if small else {"bearing": spindle["bearing"], "loadmap": spindle["loadmap"] | {
        "speed": axis(0.0, 24000.0, 49), "Fx": axis(0.0, 1000.0, 21), "Fz": axis(0.0, 2000.0, 201)}}
    taper = str(ROOT / "data" / "bearings" / "30206-TDO.toml")
    roller_axes = {"given": "load", "Fy": 0.0, "Mx": 0.0}
    tiny_roller = {"bearing": taper, "loadmap": roller_axes | {
        "Fx": axis(-3000.0, 3000.0, 2), "Fz": axis(-2000.0, 2000.0, 2), "My": axis(-2e4, 2e4, 3)}}
    roller = tiny_roller if small else {"bearing": taper, "loadmap": roller_axes | {
        "Fx": axis(-3000.0, 3000.0, 41), "Fz": axis(-2000.0, 2000.0, 41), "My": axis(-2e4, 2e4, 61)}}
    with tempfile.TemporaryDirectory() as tmp:
        for cfg in (tiny_db, db, tiny_speed, speed, tiny_roller, roller):
            if isinstance(cfg["bearing"], str):  # a bearing file: the config's own folder is the tmp dir
                cfg["bearing"] = str(Path(cfg["bearing"]).resolve())
        run_map("1M example map (DB)" if not small else "example map, tiny (DB)", db, tiny_db, tmp)
        run_map("speed map (7014C-DB)", speed, tiny_speed, tmp)
        run_map("roller map (30206-TDO)", roller, tiny_roller, tmp)
    print("1e8-case map, K only, float32: not built ([loadmap] variables and dtype are not implemented yet)")


if __name__ == "__main__":
    main()
