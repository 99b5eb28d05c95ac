"""GPU against CPU in one run (issue 36): cold random loads, the 1M example map end to end, a speed map, a
roller map and a 1e8-case map with K only in float32, each on the CPU (all of this machine's cores) and on the
GPU (fastbearing.engine.gpu), with the agreement of the two checked on every case (statuses equal; converged q
and Kb within 1e-10 relative; the float32 K within float32 rounding).

    python bench/gpu_bench.py                         # on a GPU machine: a few minutes, 10 GB free in .
    python bench/gpu_bench.py --folder /scratch/me    # where the 1e8-case map's 10 GB file goes
    python bench/gpu_bench.py --simulate              # no GPU: numba's CUDA simulator, tiny sizes (checks the script)

Prints the device, its driver and numba-cuda's version first; times exclude compiling (each device runs a small
warm-up first), maps are timed end to end (fb.loadmap: compute and HDF5 file). Units: N, N*mm, mm, rad, rpm.

The 1e8-case map: the paper's DB bearing over the 1M example's ranges on a finer grid (Fx 1001 x Fz 1000 x
My 99 = 99 099 000 cases), [loadmap] variables = ["K"] (status is always kept) and dtype = "float32": about
101 bytes a case, a 10 GB file in --folder, refused before any work when that folder lacks the room. Its GPU
run is timed whole (target: <= 30 s on one H100/H200); its CPU time is extrapolated from a measured slice of the
same map (the first 10 Fx values, 990 000 cases), which is also the slice whose agreement is checked. The file is
deleted afterwards unless --keep.
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
    p.add_argument("--folder", type=Path, default=Path("."),
                   help="where the 1e8-case map's file (about 10 GB) is written (default: the current folder)")
    p.add_argument("--keep", action="store_true", help="keep the 1e8-case map's file (default: delete it)")
    p.add_argument("--skip-1e8", action="store_true", help="leave out the 1e8-case map")
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


#: The 1e8-case map's grid: the 1M example's ranges (N, N, N*mm), finer in Fx and Fz; continuation along My as
#: there (lines of 99 cases). The CPU's slice: the first SLICE_FX values of Fx (990 000 cases).
BIG_FX, BIG_FZ, BIG_MY, SLICE_FX = 1001, 1000, 99, 10
#: Tiny sizes of the same map under --small / --simulate (18 cases, a 12-case slice).
TINY_FX, TINY_FZ, TINY_MY, TINY_SLICE_FX = 3, 2, 3, 2


def k_only_map(example, n_fx, n_fz, n_my, slice_fx=None):
    """The DB map over the example's ranges on an n_fx x n_fz x n_my grid, K only in float32; with ``slice_fx``,
    its first slice_fx values of Fx (the same grid points)."""
    fx = axis(-2000.0, 2000.0, n_fx)
    if slice_fx is not None:
        fx = axis(-2000.0, -2000.0 + (slice_fx - 1) * 4000.0 / (n_fx - 1), slice_fx)
    return {"bearing": example["bearing"], "loadmap": example["loadmap"] | {
        "Fx": fx, "Fz": axis(500.0, 10000.0, n_fz), "My": axis(-1e5, 1e5, n_my),
        "chunk": 4_000_000, "variables": ["K"], "dtype": "float32"}}


def check_room(cfg, out):
    """The runner's own disk check, early (before minutes of other benchmarks): (cases, bytes); ValueError
    from fastbearing's runner when the output's folder lacks the room."""
    from fastbearing.jobs import loadmap as lm
    from fastbearing.jobs.locations import check_disk_space

    job = lm.job(lm.read_config(cfg))
    n_bytes = job.bytes_needed()
    check_disk_space(Path(out), n_bytes, f"the 1e8-case map ({job.cases.n_cases:,d} cases, K only in float32)")
    return job.cases.n_cases, n_bytes


def refuse(err, ran=""):
    """Stop before (more) work, exit 2: the 1e8-case map cannot be written where asked."""
    print(f"gpu_bench: refused{ran}: {err} (here: --folder FOLDER, or --skip-1e8)", file=sys.stderr)
    sys.exit(2)


def big_map(big, cpu_slice, tiny, out, tmp, keep):
    """The K-only float32 map end to end on the GPU into ``out``, its CPU time extrapolated from ``cpu_slice``
    (the grid's first Fx values, measured, written next to ``out``), agreement on that slice."""
    import h5py

    from fastbearing.jobs.locations import human_size

    for device in ("cpu", "cuda"):  # warm-up: compile (the kernels of the DB map, already; the float32 writing)
        fb.loadmap(tiny, Path(tmp) / f"warm-k32-{device}.h5", progress=False, device=device, overwrite=True)
    late = " (the other benchmarks ran; the 1e8-case map did not: nothing was written)"
    try:  # again: the free space may have changed in the meantime
        n, n_bytes = check_room(big, out)
    except ValueError as err:
        refuse(err, late)
    name = "1e8-case map, K only, float32 (DB)" if n >= 9e7 else "K-only float32 map, tiny (DB)"
    print(f"{name}: {n:,d} cases, about {n_bytes / n:.0f} bytes a case: {human_size(n_bytes)} into {out}",
          flush=True)
    slice_out = out.with_name(out.stem + "-cpu-slice.h5")
    try:
        t = time.perf_counter()
        try:
            fb.loadmap(big, out, progress=False, device="cuda", overwrite=True)
        except ValueError as err:  # the runner's own disk check, before it creates anything
            refuse(err, late)
        t_gpu = time.perf_counter() - t
        size = out.stat().st_size
        t = time.perf_counter()
        fb.loadmap(cpu_slice, slice_out, progress=False, device="cpu", overwrite=True)
        t_slice = time.perf_counter() - t
        with h5py.File(slice_out) as a, h5py.File(out) as b:
            m = a["status"].shape[0]
            n_slice = a["status"].size
            assert a["K"].dtype == np.float32 and b["K"].dtype == np.float32, "K is not stored in float32"
            assert set(b) >= {"K", "status"} and "q" not in b, f"the GPU map stores {sorted(b)}"
            same, worst = agreement(a["status"][()], b["status"][:m], (a["K"][()].astype(np.float64),),
                                    (b["K"][:m].astype(np.float64),))
    finally:
        slice_out.unlink(missing_ok=True)
        if not keep:
            out.unlink(missing_ok=True)
    t_cpu = t_slice * n / n_slice
    print(f"{name:<34} {n:>11,d} cases  CPU {t_cpu:8.3f} s ({n / t_cpu:12,.0f}/s)  "
          f"GPU {t_gpu:8.3f} s ({n / t_gpu:12,.0f}/s)  x{t_cpu / t_gpu:7.2f}  statuses equal {100 * same:6.2f} %  "
          f"max rel diff {worst:.1e}", flush=True)
    ulp = 2.0 ** -23  # float32 rounding of two float64 results within 1e-10: at most one unit in the last place
    target = ("met" if t_gpu <= 30.0 else "NOT met") if n >= 9e7 else "not applicable: tiny grid"
    print(f"  CPU extrapolated from a measured {n_slice:,d}-case slice (first {m} Fx values) in {t_slice:.3f} s; "
          f"K within float32 rounding (<= {ulp:.1e}): {'yes' if worst <= ulp else 'NO'}; file "
          f"{human_size(size)} ({size / n:.0f} bytes a case); GPU end to end <= 30 s: {target}", flush=True)


def main():
    from importlib.metadata import version

    print(f"device: {gpu.describe()}")
    print(f"CPU: {os.cpu_count()} cores, {numba.config.NUMBA_NUM_THREADS} numba threads; numba {numba.__version__}, "
          f"numba-cuda {version('numba-cuda')}, numpy {np.__version__}, Python {sys.version.split()[0]}")
    small = ARGS.small
    from fastbearing.model.bearing_file import read_toml

    example = read_toml(ROOT / "data" / "examples" / "gunduz2013-db-1M.toml")
    sizes = (TINY_FX, TINY_FZ, TINY_MY, TINY_SLICE_FX) if small else (BIG_FX, BIG_FZ, BIG_MY, SLICE_FX)
    big = k_only_map(example, *sizes[:3])
    big_out = ARGS.folder.resolve() / ("gpu-bench-1e8-K-float32.h5" if not small else "gpu-bench-tiny-K-float32.h5")
    if not ARGS.skip_1e8:
        if not ARGS.folder.is_dir():
            refuse(f"--folder {ARGS.folder} is not a folder")
        try:  # before minutes of other benchmarks
            check_room(big, big_out)
        except ValueError as err:
            refuse(err)
    cold_loads(ARGS.cases or (48 if small else 4_000_000))
    tiny_db = {"bearing": example["bearing"], "loadmap": example["loadmap"] | {
        "Fx": axis(-2000.0, 2000.0, 2), "Fz": axis(500.0, 10000.0, 2), "My": axis(-1e5, 1e5, 3)}}
    db = tiny_db if small else example
    spindle = read_toml(ROOT / "data" / "examples" / "spindle-7014-speed.toml")
    tiny_speed = {"bearing": spindle["bearing"], "loadmap": spindle["loadmap"] | {
        "speed": [0.0, 12000.0], "Fx": 500.0, "Fz": axis(0.0, 2000.0, 3)}}
    speed = tiny_speed if small else {"bearing": spindle["bearing"], "loadmap": spindle["loadmap"] | {
        "speed": axis(0.0, 24000.0, 49), "Fx": axis(0.0, 1000.0, 21), "Fz": axis(0.0, 2000.0, 201)}}
    taper = str(ROOT / "fastbearing" / "catalogue" / "30206-TDO.toml")
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
        if not ARGS.skip_1e8:
            big_map(big, k_only_map(example, *sizes), k_only_map(example, TINY_FX, TINY_FZ, TINY_MY), big_out, tmp,
                    ARGS.keep)


if __name__ == "__main__":
    main()
