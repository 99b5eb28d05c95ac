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
            "map_segments": map_segments, "map_float32": lambda: map_float32("k_only"),
            "map_float32_life": lambda: map_float32("life"),
            "passage_roller_speed": passage_roller_speed, "montecarlo": lambda: compare_montecarlo(0.0),
            "montecarlo_balls": lambda: compare_montecarlo(0.002)}


MONTECARLO = {"name": "6205", "arrangement": "single",
              "geometry": {"n_balls": 9, "ball_diameter": 7.938, "pitch_diameter": 38.5, "inner_groove_ratio": 0.52,
                           "outer_groove_ratio": 0.53, "diametral_clearance": "CN", "bore": 25.0,
                           "outer_diameter": 52.0, "width": 15.0},
              "mounting": {"shaft_fit": "k5", "housing_fit": "H7", "inner_ring_temperature": 50.0}}


def compare_montecarlo(variation):
    """fastbearing montecarlo of the 6205 on k5 / H7 (40 samples at rest, ``variation``: each ball's diameter
    spread, mm) on both devices: the drawn inputs and operating clearances equal bit for bit, statuses equal,
    q and Kb to the solver's tolerance (the GPU cuts the clearance-ordered runs into segments of its own)."""
    import h5py

    from fastbearing.jobs.montecarlo import montecarlo

    cfg = {"bearing": MONTECARLO, "montecarlo": {"samples": 40, "seed": 3, "Fx": 2000.0, "Fz": 200.0, "life": True,
                                                  "ball_diameter_variation": variation}}
    with tempfile.TemporaryDirectory() as tmp:
        paths = [montecarlo(cfg, Path(tmp) / f"mc-{d}.h5", progress=False, device=d)[0] for d in ("cpu", "cuda")]
        with h5py.File(paths[0]) as a, h5py.File(paths[1]) as b:
            inputs = [k for k in a if k.endswith("_deviation") or k.startswith("operating_")
                      or k == "unmounted_diametral_clearance"]
            ok = st.converged_mask(a["status"][()])
            return {"cpu_status": a["status"][()].tolist(), "gpu_status": b["status"][()].tolist(),
                    "inputs_equal": all(np.array_equal(a[k][()], b[k][()]) for k in inputs), "inputs": inputs,
                    "q": relative(b["q"][()], a["q"][()], ok), "K": relative(b["K"][()], a["K"][()], ok),
                    "L10r": relative(b["L10r"][()], a["L10r"][()], ok)}


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
            for key in ("q", "f", "K", "max_ball_load", "K_mean", "K_amplitude"):
                x, y = a[key][()], b[key][()]
                scale = max(float(np.nanmax(np.abs(x))), 1e-300)
                same_nan = np.array_equal(np.isfinite(x), np.isfinite(y))
                diffs[key] = float(np.abs(np.where(np.isfinite(x), x - y, 0.0)).max() / scale) if same_nan else 1e300
            status = (a["status"][()].ravel().tolist(), b["status"][()].ravel().tolist())
            residual = residual_difference(a["residual"][()], b["residual"][()])
    return {"cpu_status": status[0], "gpu_status": status[1], "max_relative": diffs, "residual": residual}


def float_difference(key, a, b):
    """0 for equal arrays; else for reals max |a - b| over max |a| (``residual``: absolutely), inf where one is
    finite and the other not or where integers differ."""
    if a.dtype.kind != "f":
        return 0.0 if np.array_equal(a, b) else float("inf")
    if key == "residual":
        return residual_difference(a, b)
    if not np.array_equal(np.isfinite(a), np.isfinite(b)):
        return float("inf")
    scale = max(float(np.nanmax(np.abs(np.where(np.isfinite(a), a, np.nan)), initial=0.0)), 1e-300)
    return float(np.abs(np.where(np.isfinite(a), a.astype(np.float64) - b, 0.0)).max() / scale)


def residual_difference(a, b):
    """Largest |a - b| of two relative residuals (dimensionless), inf where one is finite and the other not. A
    converged residual is a rounding-level number itself (below the solver's rtol), so it is compared absolutely:
    the GPU's scratch is element-major, so the simulator runs the CPU's code compiled for strided views, whose ball
    sums LLVM orders otherwise (q, f, Kb agree to 1e-16; a residual of 1e-12 differs in its own digits)."""
    if not np.array_equal(np.isfinite(a), np.isfinite(b)):
        return float("inf")
    return float(np.abs(np.where(np.isfinite(a), a - b, 0.0)).max())


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
                    if key == "residual":
                        continue
                    if isinstance(a[key], h5py.Dataset) and a[key].dtype.kind in "fiu" and a[key].ndim > 0:
                        x, y = a[key][()], b[key][()]
                        scale = np.nanmax(np.abs(np.where(np.isfinite(x), x, np.nan))) if x.dtype.kind == "f" else 1
                        same_nan = np.array_equal(np.isfinite(x), np.isfinite(y))
                        d = np.abs(np.where(np.isfinite(x), x - y, 0.0)).max() / max(float(scale or 1.0), 1e-300)
                        diffs[key] = float(d) if same_nan else float("inf")
                status = (a["status"][()].ravel().tolist(), b["status"][()].ravel().tolist())
                residual = residual_difference(a["residual"][()], b["residual"][()])
            result = {"cpu_status": status[0], "gpu_status": status[1], "max_relative": diffs, "residual": residual}
    return result


SEGMENTED = {"bearing": {"preset": "gunduz2013", "arrangement": "DB"},
             "loadmap": {"given": "load", "Fx": {"start": -2000.0, "stop": 2000.0, "num": 2}, "Fy": 0.0,
                         "Fz": {"start": 500.0, "stop": 10000.0, "num": 2}, "Mx": 0.0,
                         "My": {"start": -1e5, "stop": 1e5, "num": 21}}}  # runs of 21: GPU segments of 7


def map_segments():
    """One block of a map whose runs the GPU cuts (4 lines of 21 cases: 12 GPU segments of 7), through the driver,
    in one launch and in launches of 3 threads on their own streams (gpu.PART_THREADS lowered: 4 launches): the
    two equal bit for bit; against the CPU's sweep on the same segments equal to rounding (integers exactly; the
    simulator runs the CPU's code compiled for the GPU's strided scratch, summed in another order); and against
    the CPU's own runs (the warm starts differ: converged q and Kb within the solver's tolerance)."""
    from fastbearing.engine import gpu
    from fastbearing.engine.sweep import map_sweep
    from fastbearing.jobs import loadmap, storage

    job = loadmap.job(loadmap.read_config(SEGMENTED), "cuda")
    n = job.cases.n_cases
    inputs = job.cases.inputs(0, n)
    work = job.compute.args[0]  # loadmap.MapWork
    bearing, given_load, line_length, settings, life, spinning = work[:6]
    stop = np.zeros(1, np.int64)

    def block(segments=None):
        res = storage.allocate(job.variables, job.sizes, n)
        elements, cases = loadmap.block_records(bearing, line_length, life, spinning, inputs, res, 0)
        return elements, (cases if segments is None else cases._replace(segments=segments(cases.segments))), res

    elements, cases, cpu_runs = block()
    map_sweep(elements, cases, given_load, settings, stop)
    elements, cases, cpu_same = block(gpu.device_segments)
    map_sweep(elements, cases, given_load, settings, stop)
    launches, gpu_res = {}, {}
    runs = block()[1].segments
    out = {"cpu_segments": runs.tolist(), "gpu_segments": gpu.device_segments(runs).tolist()}
    for name, part_threads in (("one_launch", gpu.PART_THREADS), ("parts", 3)):
        gpu.PART_THREADS = part_threads
        elements, cases, res = block()
        launches[name] = len(gpu.map_parts(elements, cases).launches)
        gpu.map_sweep_cuda(elements, cases, given_load, settings, stop)
        gpu_res[name] = res
    gpu.PART_THREADS = 1 << 17
    # the stored variables alone come back (loadmap.wanted_results: K kept, status always): the rest untouched
    elements, cases, kept = block()
    for a in kept.values():
        a[...] = -7
    gpu.map_sweep_cuda(elements, cases, given_load, settings, stop, loadmap.wanted_results(("K", "status"), None))
    out["stored_only"] = {key: "untouched" if np.all(a == -7) else "equal"
                          if np.array_equal(a, gpu_res["one_launch"][key]) else "other" for key, a in kept.items()}
    res = gpu_res["parts"]
    out["parts_equal_one_launch"] = {key: bool(np.array_equal(res[key], gpu_res["one_launch"][key], equal_nan=True))
                                     for key in res}
    out["same_segments"] = {}
    for key in res:
        a, b = res[key], cpu_same[key]
        if a.dtype.kind != "f":
            out["same_segments"][key] = 0.0 if np.array_equal(a, b) else float("inf")
        elif key != "residual":
            scale = max(float(np.nanmax(np.abs(b))), 1e-300)
            same_nan = np.array_equal(np.isfinite(a), np.isfinite(b))
            out["same_segments"][key] = float(np.abs(np.where(np.isfinite(b), a - b, 0.0)).max() / scale) \
                if same_nan else float("inf")
    out["same_segments_residual"] = residual_difference(cpu_same["residual"], res["residual"])
    ok = (cpu_runs["status"] & st.OUTCOME_MASK) == st.CONVERGED
    out |= {"launches": launches, "cpu_status": cpu_runs["status"].tolist(), "gpu_status": res["status"].tolist(),
            "n_converged": int(ok.sum()), "q": relative(res["q"], cpu_runs["q"], ok),
            "K": relative(res["K"], cpu_runs["K"], ok),
            "iterations": [float(cpu_runs["iterations"].mean()), float(res["iterations"].mean())]}
    return out


def map_float32(only):
    """A float32 map through the runner on both devices (runs of at most 5: no GPU cut), the files compared: integers
    exactly, reals by their largest difference over the variable's largest value (the residual absolutely, as
    :func:`residual_difference`); ``only`` "k_only", K alone (the GPU's buffers hold K in float32, made on the
    device), or "life", the spindle at speed keeping every variable in float32 with life (f and L10r stay float64
    on the host: the ISO lives are made from them)."""
    import h5py

    from fastbearing.jobs import loadmap

    k_only = {"bearing": SEGMENTED["bearing"], "loadmap": SEGMENTED["loadmap"] | {
        "My": {"start": -1e5, "stop": 1e5, "num": 5}, "variables": ["K"], "dtype": "float32"}}
    spindle = {"bearing": str(DATA.parent / "fastbearing" / "catalogue" / "7014C-DB.toml"),
               "loadmap": {"given": "load", "speed": [0.0, 12000.0], "Fx": 500.0,
                           "Fz": {"start": 0.0, "stop": 2000.0, "num": 4}, "life": True, "dtype": "float32"}}
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name, cfg in (("k_only", k_only), ("life", spindle)):
            if name != only:
                continue
            job = loadmap.job(loadmap.read_config(cfg), "cuda")
            paths = [fb.loadmap(cfg, Path(tmp) / f"{name}-{d}.h5", progress=False, device=d) for d in ("cpu", "cuda")]
            with h5py.File(paths[0]) as a, h5py.File(paths[1]) as b:
                names = [k for k in a if isinstance(a[k], h5py.Dataset) and a[k].ndim > 0 and k in b]
                out[name] = {"narrow": list(job.narrow),
                             "buffers": {v.name: v.dtype for v in job.buffer_variables if v.name in job.narrow},
                             "dtypes": {k: b[k].dtype.str for k in names if b[k].dtype.kind == "f"},
                             "difference": {k: float_difference(k, a[k][()], b[k][()]) for k in names},
                             "stored": sorted(k for k in b if isinstance(b[k], h5py.Dataset))}
    return out


if __name__ == "__main__":
    main(set(sys.argv[1:]))
