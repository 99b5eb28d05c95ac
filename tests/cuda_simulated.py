"""The CUDA drivers under numba's CUDA simulator against the CPU path, on small batches (run by tests/test_cuda.py
in a subprocess: NUMBA_ENABLE_CUDASIM must be set before numba.cuda is first imported, and the rest of the suite
shares its worker processes). Prints one JSON object: per scenario the statuses of both devices and the largest
relative differences of the converged cases' q and Kb (each case's max |GPU - CPU| over its max |CPU|).

Units: N, N*mm (loads); mm, rad (q); rpm (speeds given to the API).
"""

import json
import os
import sys
import tempfile
from pathlib import Path

import numpy as np

assert os.environ.get("NUMBA_ENABLE_CUDASIM") == "1", "run with NUMBA_ENABLE_CUDASIM=1"

import fastbearing as fb  # noqa: E402
from fastbearing import status as st  # noqa: E402

DATA = Path(__file__).resolve().parents[1] / "data"


def relative(a, b, converged):
    """Largest per-case max|a - b| / max|b| over the converged cases (0 when none)."""
    if not converged.any():
        return 0.0
    a, b = a[converged].reshape(converged.sum(), -1), b[converged].reshape(converged.sum(), -1)
    return float((np.abs(a - b).max(axis=1) / np.maximum(np.abs(b).max(axis=1), 1e-300)).max())


def compare(cpu, gpu):
    ok = (cpu.status & st.OUTCOME_MASK) == st.CONVERGED
    return {"cpu_status": cpu.status.tolist(), "gpu_status": gpu.status.tolist(), "n_converged": int(ok.sum()),
            "q": relative(gpu.q, cpu.q, ok), "K": relative(gpu.K, cpu.K, ok),
            "iterations_equal": bool(np.array_equal(cpu.iterations, gpu.iterations))}


def random_loads(rng, n):
    """Loads of the example map's ranges (N, N*mm) and some off-plane ones."""
    return np.column_stack([rng.uniform(-2000, 2000, n), rng.uniform(-300, 300, n), rng.uniform(500, 10000, n),
                            rng.uniform(-1e4, 1e4, n), rng.uniform(-1e5, 1e5, n)])


def scenarios(rng):
    """Each scenario's name and a function that runs it on both devices (called in this order)."""
    db = fb.Bearing.preset("gunduz2013", "DB")
    F = random_loads(rng, 14)
    F = np.vstack([F, np.zeros(5), [1e-9, 0, 0, 0, 0], [0, 0, -8e4, 0, 0]])  # unloaded, tiny, heavy axial
    state = {}

    def cold_ball():
        state["cold"] = fb.solve_many(db, F)
        return compare(state["cold"], fb.solve_many(db, F, device="cuda"))

    def warm_ball():
        cold = state.get("cold") or fb.solve_many(db, F)
        q0 = cold.q * (1.0 + 0.01 * rng.standard_normal(cold.q.shape))
        q0[~np.isfinite(q0)] = 0.0
        return compare(fb.solve_many(db, F, q0=q0), fb.solve_many(db, F, q0=q0, device="cuda"))

    def broyden_fixed():
        Fb = random_loads(rng, 8)
        return compare(fb.solve_many(db, Fb, method="broyden"), fb.solve_many(db, Fb, method="broyden", device="cuda"))

    def speed_ball():
        spindle = fb.load_bearing(DATA.parent / "fastbearing" / "catalogue" / "7014C-DB.toml")
        Fs = np.column_stack([rng.uniform(0, 1000, 6), np.zeros(6), rng.uniform(100, 2000, 6), np.zeros(6),
                              np.zeros(6)])
        speeds = np.array([0.0, 6000.0, 12000.0, 18000.0, 24000.0, 9000.0])
        return compare(fb.solve_many(spindle, Fs, speed=speeds), fb.solve_many(spindle, Fs, speed=speeds, device="cuda"))

    def roller():
        taper = fb.load_bearing(DATA.parent / "fastbearing" / "catalogue" / "30206-TDO.toml")
        Fr = np.column_stack([rng.uniform(-3000, 3000, 8), rng.uniform(-500, 500, 8), rng.uniform(-2000, 2000, 8),
                              rng.uniform(-2e4, 2e4, 8), rng.uniform(-2e4, 2e4, 8)])
        return compare(fb.solve_many(taper, Fr), fb.solve_many(taper, Fr, device="cuda"))

    def passage_ball():
        """A small ball-passage table of the DB pair (quasi-static; every position from the previous one's q)."""
        return compare_passage({"bearing": {"preset": "gunduz2013", "arrangement": "DB"},
                                "passage": {"given": "load", "Fx": [200.0, 3000.0], "Fz": [500.0, 2000.0],
                                            "positions": 8}})

    def passage_roller_speed():
        """The tapered pair's table and the spindle pair's at 12 000 rpm with an outer-race spall."""
        taper = {"bearing": str(DATA.parent / "fastbearing" / "catalogue" / "30206-TDO.toml"),
                 "passage": {"given": "load", "Fx": [1000.0, 3000.0], "Fz": 500.0, "positions": 6}}
        spall = {"bearing": str(DATA.parent / "fastbearing" / "catalogue" / "7014C-DB.toml"),
                 "passage": {"given": "load", "Fx": [500.0], "Fz": 1000.0, "positions": 6, "speed": 12000.0,
                             "defects": [{"race": "outer", "angle": 0.0, "width": 1.0, "depth": 0.01}]}}
        return {"roller": compare_passage(taper), "speed_defect": compare_passage(spall)}

    return {"cold_ball": cold_ball, "warm_ball": warm_ball, "broyden_fixed": broyden_fixed, "speed_ball": speed_ball,
            "roller": roller, "map_ball": lambda: compare_maps("ball"),
            "map_speed_life": lambda: compare_maps("speed_life"), "passage_ball": passage_ball,
            "passage_roller_speed": passage_roller_speed}


def main(wanted):
    """Run the ``wanted`` scenarios (all when empty); print their comparisons and each one's seconds as JSON."""
    import time

    rng = np.random.default_rng(36)
    out, seconds = {}, {}
    for name, run in scenarios(rng).items():
        if wanted and name not in wanted:
            continue
        started = time.perf_counter()
        out[name] = run()
        seconds[name] = time.perf_counter() - started
    out["seconds"] = seconds
    json.dump(out, sys.stdout)


def compare_passage(cfg):
    """One ball-passage table on both devices: statuses, and the largest relative difference of every real-valued
    stored variable."""
    import h5py

    with tempfile.TemporaryDirectory() as tmp:
        paths = [fb.passage(cfg, Path(tmp) / f"p-{d}.h5", progress=False, device=d) for d in ("cpu", "cuda")]
        diffs = {}
        with h5py.File(paths[0]) as a, h5py.File(paths[1]) as b:
            for key in ("q", "f", "K", "residual", "max_ball_load", "K_mean", "K_amplitude"):
                x, y = a[key][()], b[key][()]
                scale = max(float(np.nanmax(np.abs(x))), 1e-300)
                same_nan = np.array_equal(np.isfinite(x), np.isfinite(y))
                diffs[key] = float(np.abs(np.where(np.isfinite(x), x - y, 0.0)).max() / scale) if same_nan else 1e300
            status = (a["status"][()].ravel().tolist(), b["status"][()].ravel().tolist())
    return {"cpu_status": status[0], "gpu_status": status[1], "max_relative": diffs}


def compare_maps(only):
    """A small load map (``only``: "ball", the 1M example's bearing and ranges; "speed_life", the spindle at speed
    with life) on both devices: every stored variable equal to rounding."""
    import h5py

    maps = {
        "ball": {"bearing": {"preset": "gunduz2013", "arrangement": "DB"},
                 "loadmap": {"given": "load", "Fx": {"start": -2000.0, "stop": 2000.0, "num": 3}, "Fy": 0.0,
                             "Fz": {"start": 500.0, "stop": 10000.0, "num": 2}, "Mx": 0.0,
                             "My": {"start": -1e5, "stop": 1e5, "num": 5},
                             "chunk": 10}},  # 3 blocks: the device's tables and buffers are reused
        "speed_life": str(DATA / "examples" / "spindle-7014-speed.toml"),
    }
    result = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name, cfg in maps.items():
            if name != only:
                continue
            if isinstance(cfg, str):  # the example, cut to 2 speeds x 1 radial load x 4 axial loads
                from fastbearing.model.bearing_file import read_toml

                cfg = read_toml(cfg)
                cfg["loadmap"] |= {"speed": [0.0, 12000.0], "Fx": 500.0,
                                   "Fz": {"start": 0.0, "stop": 2000.0, "num": 4}, "life": True}
            paths = [fb.loadmap(cfg, Path(tmp) / f"{name}-{d}.h5", progress=False, device=d) for d in ("cpu", "cuda")]
            diffs = {}
            with h5py.File(paths[0]) as a, h5py.File(paths[1]) as b:
                for key in a:
                    if isinstance(a[key], h5py.Dataset) and a[key].dtype.kind in "fiu" and a[key].ndim > 0:
                        x, y = a[key][()], b[key][()]
                        scale = np.nanmax(np.abs(np.where(np.isfinite(x), x, np.nan))) if x.dtype.kind == "f" else 1
                        same_nan = np.array_equal(np.isfinite(x), np.isfinite(y))
                        d = np.abs(np.where(np.isfinite(x), x - y, 0.0)).max() / max(float(scale or 1.0), 1e-300)
                        diffs[key] = float(d) if same_nan else float("inf")
                status = (a["status"][()].ravel().tolist(), b["status"][()].ravel().tolist())
            result = {"cpu_status": status[0], "gpu_status": status[1], "max_relative": diffs}
    return result


if __name__ == "__main__":
    main(set(sys.argv[1:]))
