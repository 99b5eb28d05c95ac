"""GPU against CPU in one run, in stages (issues 36, 46): each stage on the CPU (all of this machine's cores) and on
the GPU (fastbearing.engine.gpu), every case checked.

    python bench/gpu_bench.py --plan                  # no GPU needed: each stage's launches, threads, device memory
    python bench/gpu_bench.py --only cold,1M          # some stages (default: all, in the order below)
    python bench/gpu_bench.py --folder /scratch/me    # where the 1e8-case map's 10 GB file goes (default: .)
    python bench/gpu_bench.py --simulate              # no GPU: numba's CUDA simulator, tiny sizes (checks the script)

Stages, in order of value: ``cold`` (random loads on the paper's DB bearing, solved cold), ``1M`` (the 1M example
map end to end), ``speed`` (7014C-DB over speed), ``roller`` (30206-TDO), ``1e8`` (the paper's DB bearing over the
1M example's ranges on a finer grid, 99 099 000 cases, K only in float32: a 10 GB file).

Each stage prints the device's compile and resource figures of its kernel (registers and local memory per thread,
the occupancy those registers allow: achieved occupancy needs a profiler, ncu), the CPU's time and the GPU's (maps
end to end, compute and HDF5 file; a small warm-up of the same kind first, so compiling is not in the figure),
and the agreement of every case (compare()): NaN-safe, outcome flips within OUTCOME_FLIPS and listed by kind,
q, f and Kb within Q_TOLERANCE where both converged. Any disagreement beyond those ends the run with exit
status 1. The 1e8 stage's CPU figure is a rate measured on ten slices spread over the grid (every ~111th Fx),
which are also the cases checked; no CPU time for the whole map is claimed. Units: N, N*mm, mm, rad, rpm.
"""

import argparse
import os
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # this tree's fastbearing, whatever else is installed
STAGES = ("cold", "1M", "speed", "roller", "1e8")
#: Outcome flips (status & OUTCOME_MASK differing) allowed per case checked: rounding order (FMA on the GPU,
#: reassociated sums on the CPU) decides exact-threshold tests differently on a few cases (docs/gpu.md).
OUTCOME_FLIPS = 1e-4
#: Largest per-case difference of q, f and Kb allowed where both devices converged: max |GPU - CPU| over the
#: CPU's largest entry of the case; about 1e4 x the solver's rtol (1e-10), room for Kb's conditioning.
Q_TOLERANCE = 1e-6
#: float32 K: two float64 results within Q_TOLERANCE, each rounded to float32.
K32_TOLERANCE = Q_TOLERANCE + 2.0 ** -23


def parse(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--plan", action="store_true", help="print each stage's launches, threads and device memory "
                   "(no GPU, nothing computed)")
    p.add_argument("--only", default=",".join(STAGES), help=f"comma-separated stages of {', '.join(STAGES)}")
    p.add_argument("--simulate", action="store_true", help="numba's CUDA simulator (no GPU), implies --small")
    p.add_argument("--small", action="store_true", help="tiny sizes: a check of the script, not a benchmark")
    p.add_argument("--cases", type=int, default=None, help="cold random loads (default 4e6, small 48)")
    p.add_argument("--folder", type=Path, default=Path("."),
                   help="where the 1e8-case map's file (about 10 GB) is written (default: the current folder)")
    p.add_argument("--keep", action="store_true", help="keep the 1e8-case map's file (default: delete it)")
    args = p.parse_args(argv)
    args.only = [s.strip() for s in args.only.split(",") if s.strip()]
    unknown = [s for s in args.only if s not in STAGES]
    if unknown:
        p.error(f"--only: unknown stage(s) {', '.join(unknown)}; the stages are {', '.join(STAGES)}")
    return args


ARGS = parse() if __name__ == "__main__" else parse([])  # imported (tests): the defaults
if ARGS.simulate:  # before numba.cuda is imported anywhere
    os.environ["NUMBA_ENABLE_CUDASIM"] = "1"
    ARGS.small = True

import numba  # noqa: E402
import numpy as np  # noqa: E402

import fastbearing as fb  # noqa: E402
from fastbearing import status as st  # noqa: E402
from fastbearing.engine import gpu  # noqa: E402
from fastbearing.model.bearing_file import read_toml  # noqa: E402

FAILURES = []


# -- checking ----------------------------------------------------------------------------------------------------

def compare(name, cpu_status, gpu_status, cpu_arrays, gpu_arrays, tolerance=Q_TOLERANCE):
    """Every case of a stage: outcome flips (listed by kind; more than OUTCOME_FLIPS of the cases fail), warning
    bits that differ (counted), and for the cases both devices converged each array's largest per-case relative
    difference (a value finite on one device only fails; NaN cannot hide: np.nanmax and a count). Returns one line;
    a disagreement is kept in FAILURES."""
    cpu_status, gpu_status = np.asarray(cpu_status).ravel(), np.asarray(gpu_status).ravel()
    n = cpu_status.size
    outcome_cpu, outcome_gpu = cpu_status & st.OUTCOME_MASK, gpu_status & st.OUTCOME_MASK
    flipped = outcome_cpu != outcome_gpu
    warnings = int(np.sum((cpu_status != gpu_status) & ~flipped))
    both = (outcome_cpu == st.CONVERGED) & (outcome_gpu == st.CONVERGED)
    worst, one_sided = 0.0, 0
    for a, b in zip(cpu_arrays, gpu_arrays):
        a = np.asarray(a, np.float64).reshape(n, -1)[both]
        b = np.asarray(b, np.float64).reshape(n, -1)[both]
        if not a.size:
            continue
        finite_a, finite_b = np.isfinite(a), np.isfinite(b)
        one_sided += int(np.any(finite_a != finite_b, axis=1).sum())
        scale = np.maximum(np.nanmax(np.where(finite_a, np.abs(a), np.nan), axis=1, initial=0.0), 1e-300)
        diff = np.where(finite_a & finite_b, np.abs(a - b), 0.0).max(axis=1) / scale
        worst = max(worst, float(np.nanmax(diff, initial=0.0)))
    allowed = int(OUTCOME_FLIPS * n)
    text = (f"{name}: {n:,d} cases; outcome flips {int(flipped.sum())} (allowed {allowed}), warning bits differ "
            f"{warnings}; both converged {int(both.sum()):,d}: max rel diff {worst:.1e} (allowed {tolerance:.0e}), "
            f"finite on one device only {one_sided}")
    bad = flipped.sum() > allowed or worst > tolerance or one_sided > 0
    if flipped.any():
        kinds = Counter((st.describe(int(c)), st.describe(int(g)))
                        for c, g in zip(outcome_cpu[flipped], outcome_gpu[flipped]))
        text += "\n    flips (CPU -> GPU): " + "; ".join(f"{c} -> {g}: {k}" for (c, g), k in kinds.most_common(10))
    if bad:
        FAILURES.append(name)
        text += "\n    DISAGREEMENT"
    return text


def resources(kind):
    """Registers and local memory per thread of the compiled ``kind`` kernels (each specialisation), and the
    occupancy the registers allow (resident warps of 64 per SM, 65 536 registers, no shared memory)."""
    if gpu.simulated():
        return f"  {kind} kernel: simulator (no registers to report)"
    lines = []
    kernel = gpu.kernel(kind)
    for sig in kernel.overloads:
        regs = kernel.get_regs_per_thread(sig)
        local = kernel.get_local_mem_per_thread(sig)
        warps = min(64, 65536 // max(regs * 32, 1) // 4 * 4)
        lines.append(f"  {kind} kernel, {len(sig)} arguments: {regs} registers, {local} B local memory per thread; "
                     f"registers allow {warps} of 64 warps per SM ({100 * warps / 64:.0f} % theoretical occupancy)")
    return "\n".join(lines) or f"  {kind} kernel: not compiled"


def timed(call):
    started = time.perf_counter()
    out = call()
    return out, time.perf_counter() - started


def report(name, n, t_cpu, t_gpu, check, kind):
    print(f"{name}: {n:,d} cases; CPU {t_cpu:.3f} s ({n / t_cpu:,.0f}/s, {numba.get_num_threads()} threads), "
          f"GPU {t_gpu:.3f} s ({n / t_gpu:,.0f}/s): x{t_cpu / t_gpu:.2f}", flush=True)
    print(resources(kind))
    print("  " + check, flush=True)


# -- the stages' inputs --------------------------------------------------------------------------------------------

def axis(start, stop, num):
    return {"start": start, "stop": stop, "num": num}


def random_loads(n):
    rng = np.random.default_rng(1)
    return np.column_stack([rng.uniform(-2000, 2000, n), rng.uniform(-500, 500, n), rng.uniform(500, 10000, n),
                            rng.uniform(-2e4, 2e4, n), rng.uniform(-1e5, 1e5, n)])


#: The 1e8-case map's grid: the 1M example's ranges (N, N, N*mm), finer in Fx and Fz; continuation along My as
#: there (lines of 99 cases); tiny sizes under --small.
BIG = (1001, 1000, 99)
TINY = (3, 2, 11)  # lines of 11: the GPU cuts them (segments of 6 and 5), so --simulate checks that too
#: Slices of the 1e8 map the CPU computes (single Fx values spread over the grid): its rate and the cases checked.
SLICES, TINY_SLICES = 10, 2


def map_configs(small):
    """Each map stage's (config, a tiny warm-up config of the same kind)."""
    example = read_toml(ROOT / "data" / "examples" / "gunduz2013-db-1M.toml")
    tiny_db = {"bearing": example["bearing"], "loadmap": example["loadmap"] | {
        "Fx": axis(-2000.0, 2000.0, 2), "Fz": axis(500.0, 10000.0, 2), "My": axis(-1e5, 1e5, 11)}}  # cut: 6 + 5
    spindle = read_toml(ROOT / "data" / "examples" / "spindle-7014-speed.toml")
    spindle["bearing"] = str(ROOT / "fastbearing" / "catalogue" / "7014C-DB.toml")
    tiny_speed = {"bearing": spindle["bearing"], "loadmap": spindle["loadmap"] | {
        "speed": [0.0, 12000.0], "Fx": 500.0, "Fz": axis(0.0, 2000.0, 3)}}
    speed = {"bearing": spindle["bearing"], "loadmap": spindle["loadmap"] | {
        "speed": axis(0.0, 24000.0, 49), "Fx": axis(0.0, 1000.0, 21), "Fz": axis(0.0, 2000.0, 201)}}
    taper = str(ROOT / "fastbearing" / "catalogue" / "30206-TDO.toml")
    roller_axes = {"given": "load", "Fy": 0.0, "Mx": 0.0}
    tiny_roller = {"bearing": taper, "loadmap": roller_axes | {
        "Fx": axis(-3000.0, 3000.0, 2), "Fz": axis(-2000.0, 2000.0, 2), "My": axis(-2e4, 2e4, 3)}}
    roller = {"bearing": taper, "loadmap": roller_axes | {
        "Fx": axis(-3000.0, 3000.0, 41), "Fz": axis(-2000.0, 2000.0, 41), "My": axis(-2e4, 2e4, 61)}}
    big = k_only_map(example, *(TINY if small else BIG))
    return {"1M": (tiny_db if small else example, tiny_db), "speed": (tiny_speed if small else speed, tiny_speed),
            "roller": (tiny_roller if small else roller, tiny_roller),
            "1e8": (big, k_only_map(example, *TINY))}


def k_only_map(example, n_fx, n_fz, n_my, fx=None):
    """The DB map over the example's ranges on an n_fx x n_fz x n_my grid, K only in float32; with ``fx`` (N),
    the grid's slice at that Fx value."""
    return {"bearing": example["bearing"], "loadmap": example["loadmap"] | {
        "Fx": axis(-2000.0, 2000.0, n_fx) if fx is None else fx, "Fz": axis(500.0, 10000.0, n_fz),
        "My": axis(-1e5, 1e5, n_my), "chunk": 4_000_000, "variables": ["K"], "dtype": "float32"}}


# -- the plan (no GPU) ------------------------------------------------------------------------------------------------

def placeholder_results(job, n):
    """A block's result arrays by name as the runner's buffers hold them, zero-strided (their nbytes is a real
    block's; nothing allocated)."""
    return {v.name: np.broadcast_to(np.zeros((), v.dtype), (n, *(job.sizes[d] for d in v.trailing)))
            for v in job.buffer_variables}


def map_plan(config):
    """(cases, blocks, [(threads, device bytes) per launch]) of a map on the GPU: the GPU job's blocks
    (loadmap.job(cfg, "cuda"): sized for the device), engine.gpu.map_plan on each block's records as the driver
    builds them (its launches: GPU segments, one per thread)."""
    from fastbearing.jobs import loadmap
    from fastbearing.jobs.grid import plan_blocks

    cfg = loadmap.read_config(config)
    job = loadmap.job(cfg, "cuda")
    life, spinning = job.compute.args[0].life, job.compute.args[0].spinning  # loadmap.MapWork
    launches = []
    n_columns = cfg.cases.inputs(0, 1).shape[1]  # 6 with a speed per case
    blocks_of_map = plan_blocks(cfg.cases.shape, cfg.cases.line_length, job.chunk)
    for block in blocks_of_map:
        inputs = np.broadcast_to(np.zeros(()), (block.size, n_columns))  # only the shape counts
        elements, cases = loadmap.block_records(cfg.bearing, cfg.cases.line_length, life, spinning, inputs,
                                                placeholder_results(job, block.size), block.start)
        plan = gpu.map_plan(elements, cases)
        launches += [(plan.blocks * plan.threads_per_block, plan.device_bytes)] * plan.launches
    return cfg.cases.n_cases, len(blocks_of_map), launches


def print_plan(stages, small):
    """Each stage's launches, threads per launch and device memory, from the drivers' own sizing."""
    from fastbearing.engine.contract import CaseBlock, Solutions
    from fastbearing.jobs.locations import human_size

    print(f"plan ({'tiny sizes' if small else 'full sizes'}; threads per block {gpu.THREADS_PER_BLOCK}; a map's "
          f"blocks of at least {gpu.DEVICE_CHUNK:,d} cases, its continuation runs cut into GPU segments of at most "
          f"{gpu.SEGMENT_CASES}, launches of at least {gpu.PART_THREADS:,d} threads where a block has more; "
          "nothing computed, no GPU needed)")
    if "cold" in stages:
        n = ARGS.cases or (48 if small else 4_000_000)
        db = fb.Bearing.preset("gunduz2013", "DB")
        shape = np.broadcast_to(np.zeros(()), (n, 5))
        cases = CaseBlock(shape, np.zeros(0, np.int64), np.zeros(0), None, None, Solutions(
            shape, shape, np.broadcast_to(np.zeros(()), (n, 5, 5)), np.broadcast_to(np.zeros((), np.int8), (n,)),
            *(np.broadcast_to(np.zeros((), d), (n,)) for d in (np.int32, np.float64, np.int32))))
        blocks, tpb, device, _ = gpu.solve_plan(db.ball_set(), cases)
        print(f"cold: {n:,d} random loads, 1 launch of {blocks * tpb:,d} threads (one case per thread, grid "
              f"stride), {human_size(device)} of device memory")
    configs = map_configs(small)
    for stage in (s for s in stages if s != "cold"):
        n, n_blocks, launches = map_plan(configs[stage][0])
        threads = [t for t, _ in launches]
        device = max(d for _, d in launches)
        name = {"1M": "the 1M example map (data/examples/gunduz2013-db-1M.toml)" if not small else "the example "
                "map, tiny", "speed": "the speed map (7014C-DB)", "roller": "the roller map (30206-TDO)",
                "1e8": "the 1e8-case K-only float32 map (DB)"}[stage]
        spread = f"{min(threads):,d}" if min(threads) == max(threads) else f"{min(threads):,d}-{max(threads):,d}"
        print(f"{stage}: {name}, {n:,d} cases: {n_blocks} block{'s' if n_blocks > 1 else ''}, {len(launches)} "
              f"launch{'es' if len(launches) > 1 else ''} of {spread} threads (one GPU segment of at most "
              f"{gpu.SEGMENT_CASES} cases per thread), at most {human_size(device)} of device memory per block")


# -- the stages ---------------------------------------------------------------------------------------------------

def cold(n):
    db = fb.Bearing.preset("gunduz2013", "DB")
    F = random_loads(n)
    (_, t_compile) = timed(lambda: fb.solve_many(db, F[:8], device="cuda"))  # warm-up: compile
    fb.solve_many(db, F[:8])
    c, t_cpu = timed(lambda: fb.solve_many(db, F))
    g, t_gpu = timed(lambda: fb.solve_many(db, F, device="cuda"))
    print(f"cold: first GPU call (compile and load) {t_compile:.1f} s")
    report("cold random loads, DB", n, t_cpu, t_gpu,
           compare("cold", c.status, g.status, (c.q, c.f, c.K), (g.q, g.f, g.K)), "solve")


def run_map(stage, cfg, tiny, tmp):
    """One map on both devices, end to end, after a tiny warm-up map of the same kind on each; every stored
    real-valued variable compared."""
    import h5py

    _, t_compile = timed(lambda: fb.loadmap(tiny, Path(tmp) / f"warm-{stage}-cuda.h5", progress=False,
                                            device="cuda", overwrite=True))
    fb.loadmap(tiny, Path(tmp) / f"warm-{stage}-cpu.h5", progress=False, overwrite=True)
    print(f"{stage}: first GPU map (compile and load) {t_compile:.1f} s")
    times, paths = {}, {}
    for device in ("cpu", "cuda"):
        paths[device] = Path(tmp) / f"{stage}-{device}.h5"
        _, times[device] = timed(lambda: fb.loadmap(cfg, paths[device], progress=False, device=device,
                                                    overwrite=True))
    with h5py.File(paths["cpu"]) as a, h5py.File(paths["cuda"]) as b:
        # the relative residual at convergence is a rounding-level number (below rtol): its own digits differ
        # with the rounding order, so it is not held to Q_TOLERANCE (the statuses say both converged)
        names = [k for k in a if k not in ("status", "residual") and isinstance(a[k], h5py.Dataset)
                 and a[k].dtype.kind == "f" and a[k].ndim > 0 and a[k].shape[:a["status"].ndim] == a["status"].shape]
        check = compare(stage, a["status"][()], b["status"][()], [a[k][()] for k in names], [b[k][()] for k in names])
        n = a["status"].size
    for p in paths.values():
        p.unlink()
    report(stage, n, times["cpu"], times["cuda"], check, "map")


def k_only(cfg, tiny, small, tmp, folder, keep):
    """The K-only float32 map on the GPU into ``folder``, timed whole (compute and file); the CPU on slices at
    single Fx values spread over the grid (its measured rate; those cases checked)."""
    import h5py

    from fastbearing.jobs import loadmap
    from fastbearing.jobs.locations import check_disk_space, human_size

    fb.loadmap(tiny, Path(tmp) / "warm-k32-cuda.h5", progress=False, device="cuda", overwrite=True)
    fb.loadmap(tiny, Path(tmp) / "warm-k32-cpu.h5", progress=False, overwrite=True)
    job = loadmap.job(loadmap.read_config(cfg))
    n = job.cases.n_cases
    out = folder.resolve() / "gpu-bench-K-float32.h5"
    try:
        check_disk_space(out, job.bytes_needed(), f"the K-only map ({n:,d} cases)")
    except ValueError as err:
        print(f"1e8: refused: {err} (--folder FOLDER, or leave the stage out with --only)", file=sys.stderr)
        FAILURES.append("1e8 (no room)")
        return
    n_fx = cfg["loadmap"]["Fx"]["num"]
    fx_values = np.linspace(-2000.0, 2000.0, n_fx)
    picks = np.unique(np.linspace(0, n_fx - 1, TINY_SLICES if small else SLICES).round().astype(int))
    try:
        _, t_gpu = timed(lambda: fb.loadmap(cfg, out, progress=False, device="cuda", overwrite=True))
        size = out.stat().st_size
        t_cpu, n_cpu, checks = 0.0, 0, []
        with h5py.File(out) as b:
            assert b["K"].dtype == np.float32 and "q" not in b, f"the GPU map stores {sorted(b)}"
            for i in picks:
                part = Path(tmp) / f"slice-{i}.h5"
                slice_cfg = k_only_map({"bearing": cfg["bearing"], "loadmap": cfg["loadmap"]},
                                       n_fx, cfg["loadmap"]["Fz"]["num"], cfg["loadmap"]["My"]["num"],
                                       fx=float(fx_values[i]))
                _, t = timed(lambda: fb.loadmap(slice_cfg, part, progress=False, overwrite=True))
                t_cpu += t
                with h5py.File(part) as a:
                    n_cpu += a["status"].size
                    checks.append((a["status"][()], b["status"][i], a["K"][()], b["K"][i]))
                part.unlink()
    finally:
        if not keep:
            out.unlink(missing_ok=True)
    status = [np.concatenate([c[k].ravel() for c in checks]) for k in (0, 1)]
    K = [np.concatenate([c[k].reshape(-1, 25) for c in checks]) for k in (2, 3)]
    check = compare("1e8", status[0], status[1], [K[0]], [K[1]], K32_TOLERANCE)
    rate_cpu = n_cpu / t_cpu
    print(f"1e8: K-only float32 map (DB), {n:,d} cases, {human_size(size)} ({size / n:.0f} bytes a case): GPU "
          f"{t_gpu:.3f} s end to end ({n / t_gpu:,.0f}/s; target <= 30 s for 1e8: "
          f"{('met' if t_gpu <= 30.0 else 'NOT met') if n >= 9e7 else 'not applicable, tiny grid'}); CPU measured "
          f"on {len(picks)} Fx slices spread over the grid, {n_cpu:,d} cases in {t_cpu:.3f} s ({rate_cpu:,.0f}/s): "
          f"GPU/CPU rate x{n / t_gpu / rate_cpu:.2f}; no CPU time for the whole map is claimed", flush=True)
    print(resources("map"))
    print("  " + check, flush=True)


def main():
    from importlib.metadata import version

    if ARGS.plan:
        print_plan(ARGS.only, ARGS.small)
        return 0
    print(f"device: {gpu.describe()}")
    print(f"CPU: {os.cpu_count()} cores, {numba.config.NUMBA_NUM_THREADS} numba threads; numba {numba.__version__}, "
          f"numba-cuda {version('numba-cuda')}, numpy {np.__version__}, Python {sys.version.split()[0]}")
    print(f"tolerances: outcome flips <= {OUTCOME_FLIPS:g} of the cases, q f Kb <= {Q_TOLERANCE:g} relative, "
          f"float32 K <= {K32_TOLERANCE:.2e}", flush=True)
    configs = map_configs(ARGS.small)
    with tempfile.TemporaryDirectory() as tmp:
        for stage in ARGS.only:
            started = time.perf_counter()
            if stage == "cold":
                cold(ARGS.cases or (48 if ARGS.small else 4_000_000))
            elif stage == "1e8":
                k_only(*configs["1e8"], ARGS.small, tmp, ARGS.folder, ARGS.keep)
            else:
                run_map(stage, *configs[stage], tmp)
            print(f"{stage}: stage took {time.perf_counter() - started:.1f} s", flush=True)
    if FAILURES:
        print(f"gpu_bench: DISAGREEMENT in {', '.join(FAILURES)}", file=sys.stderr)
        return 1
    print("gpu_bench: every stage agrees within the tolerances")
    return 0


if __name__ == "__main__":
    sys.exit(main())
