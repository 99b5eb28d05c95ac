"""The GPU path (fastbearing.engine.gpu) without a GPU: its drivers under numba's CUDA simulator against the CPU
path, the refusal where no GPU can run, and (where libnvvm is at hand) the kernels lowered to PTX for a real GPU.

The simulator must be switched on before numba.cuda is first imported, and the suite's worker processes run
other tests: the simulated runs go in a subprocess (tests/cuda_simulated.py). Units: N, N*mm, mm, rad.
"""

import importlib.util
import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

import fastbearing as fb
from fastbearing.engine import gpu

HERE = Path(__file__).parent
DATA = HERE.parent / "data"
HAS_NUMBA_CUDA = importlib.util.find_spec("numba_cuda") is not None
needs_numba_cuda = pytest.mark.skipif(not HAS_NUMBA_CUDA, reason="numba-cuda is not installed (pip install '.[cuda]')")


def _env(**extra):
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_ENABLE_CUDASIM"}
    return env | extra


#: The simulated scenarios every run checks: the quasi-static ball bearing's drivers (about 20 s from an empty
#: numba cache). FASTBEARING_CUDASIM_ALL=1 adds the balls at speed, the roller bearing and the speed map with life
#: (about 2 more minutes from an empty cache: they compile the CPU's speed and roller kernels for the simulator's
#: own entry points); bench/gpu_bench.py --simulate runs speed and roller maps too.
QUICK = ("cold_ball", "warm_ball", "broyden_fixed", "map_ball", "passage_ball", "map_segments", "map_float32",
         "montecarlo")
ALL = QUICK + ("speed_ball", "roller", "map_speed_life", "passage_roller_speed", "map_float32_life",
               "montecarlo_balls")
SCENARIOS = ALL if os.environ.get("FASTBEARING_CUDASIM_ALL") == "1" else QUICK


@pytest.fixture(scope="module")
def simulated():
    """tests/cuda_simulated.py's comparisons (one subprocess for the module)."""
    run = subprocess.run([sys.executable, str(HERE / "cuda_simulated.py"), *SCENARIOS], capture_output=True,
                         text=True, env=_env(NUMBA_ENABLE_CUDASIM="1"), timeout=900)
    assert run.returncode == 0, run.stderr[-3000:]
    return json.loads(run.stdout)


def _scenario(simulated, name):
    if name not in SCENARIOS:
        pytest.skip(f"{name}: FASTBEARING_CUDASIM_ALL=1 runs it (minutes from an empty numba cache)")
    return simulated[name]


@needs_numba_cuda
@pytest.mark.parametrize("scenario", ["cold_ball", "warm_ball", "broyden_fixed", "speed_ball", "roller"])
def test_simulated_solves_match_the_cpu(simulated, scenario):
    r = _scenario(simulated, scenario)
    assert r["gpu_status"] == r["cpu_status"]
    assert r["n_converged"] > 0
    assert r["q"] <= 1e-10
    assert r["K"] <= 1e-10


@needs_numba_cuda
def test_simulated_scenarios_cover_the_statuses(simulated):
    """The cold batch includes an unloaded case and cases that end other than plain converged."""
    statuses = set(simulated["cold_ball"]["cpu_status"])
    assert fb.status.UNLOADED in statuses
    assert len(statuses) >= 3


@needs_numba_cuda
@pytest.mark.parametrize("name", ["ball", "speed_life"])
def test_simulated_maps_match_the_cpu(simulated, name):
    r = _scenario(simulated, f"map_{name}")
    assert r["gpu_status"] == r["cpu_status"]
    assert {"q", "K", "f", "max_ball_load", "min_contact_angle"} <= set(r["max_relative"])
    if name == "speed_life":
        assert {"L10r", "min_outer_contact_angle"} <= set(r["max_relative"])
    assert max(r["max_relative"].values()) <= 1e-10, r["max_relative"]
    # relative residuals (below rtol 1e-10) compared absolutely: equal to rounding. The speed map with life, whose
    # f near zero differs by 4e-13 relative, measured 3.9e-14 (FASTBEARING_CUDASIM_ALL=1; 1e-14 failed it)
    assert r["residual"] <= 1e-12


@needs_numba_cuda
@pytest.mark.parametrize("name", ["passage_ball", "passage_roller_speed"])
def test_simulated_passage_tables_match_the_cpu(simulated, name):
    """Ball-passage tables, one operating point per GPU thread: the DB pair; with FASTBEARING_CUDASIM_ALL=1 also
    the tapered roller pair and the spindle pair at 12 000 rpm with an outer-race spall."""
    r = _scenario(simulated, name)
    for table in ([r] if "cpu_status" in r else list(r.values())):
        assert table["gpu_status"] == table["cpu_status"]
        assert max(table["max_relative"].values()) <= 1e-10, table["max_relative"]
        assert table["residual"] <= 1e-14


@needs_numba_cuda
@pytest.mark.parametrize("name", ["montecarlo", "montecarlo_balls"])
def test_simulated_montecarlo_matches_the_cpu(simulated, name):
    """Cases with their own operating values on the GPU (each thread its own tables, gpu.thread_rows): a Monte
    Carlo run's samples, with each ball its own diameter under FASTBEARING_CUDASIM_ALL=1."""
    r = _scenario(simulated, name)
    assert r["gpu_status"] == r["cpu_status"] and r["inputs_equal"]
    assert {"operating_diametral_clearance", "bore_deviation"} <= set(r["inputs"])
    assert r["q"] < 1e-8 and r["K"] < 1e-8 and r["L10r"] < 1e-7, r


@needs_numba_cuda
def test_a_second_simulated_run_compiles_nothing(simulated):
    """Once the simulated runs above have filled numba's cache, another simulated process compiles nothing: the
    simulator runs the kernels' bodies in Python, and their helpers (cuda_kernels.element_set, case_block,
    thread_scratch: inlined on a GPU, so uncached) were compiled again in every simulated process (about 11 s),
    under a notice that said "later runs load the kernels from numba's cache"."""
    from conftest import COUNT_COMPILATIONS

    script = COUNT_COMPILATIONS + textwrap.dedent(f"""
        import runpy
        sys.argv = ["cuda_simulated.py", "cold_ball", "map_ball", "passage_ball", "montecarlo"]
        runpy.run_path({str(HERE / "cuda_simulated.py")!r}, run_name="__main__")
        print("compilations:", count[0], file=sys.stderr)
    """)
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                         env=_env(NUMBA_ENABLE_CUDASIM="1"), timeout=900)
    assert run.returncode == 0, run.stderr[-3000:]
    assert "compilations: 0" in run.stderr and "compiling" not in run.stderr, run.stderr[-3000:]


def test_refusal_names_numba_cuda_when_it_is_missing(monkeypatch):
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "numba_cuda" else real(name, *a))
    with pytest.raises(gpu.CudaUnavailable, match="numba-cuda"):
        gpu.require_cuda()
    with pytest.raises(gpu.CudaUnavailable, match="numba-cuda"):
        fb.solve_many(fb.Bearing.preset("gunduz2013", "DB"), [[1000.0, 0, 1000.0, 0, 0]], device="cuda")


def test_device_must_be_cpu_or_cuda():
    with pytest.raises(ValueError, match="device"):
        fb.solve_many(fb.Bearing.preset("gunduz2013", "DB"), [[1000.0, 0, 1000.0, 0, 0]], device="gpu")


@needs_numba_cuda
def test_refusal_without_a_gpu_is_one_sentence():
    """Where no GPU can run (this CI: no driver), device="cuda" says so in one line and nothing runs; where one
    can, the same call solves."""
    code = ("import fastbearing as fb\n"
            "from fastbearing.engine.device import CudaUnavailable\n"
            "try:\n"
            "    r = fb.solve_many(fb.Bearing.preset('gunduz2013', 'DB'), [[1000.0, 0, 1000.0, 0, -7e4]], device='cuda')\n"
            "    print('ran', int(r.status[0]))\n"
            "except CudaUnavailable as err:\n"
            "    print('refused', err)\n")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=_env(), timeout=300)
    assert run.returncode == 0, run.stderr[-2000:]
    out = run.stdout.strip()
    if out.startswith("ran"):
        assert out == "ran 0"
        return
    assert out.startswith("refused device 'cuda': ")
    assert "\n" not in out
    assert "driver" in out or "GPU" in out


def _libnvvm():
    """True where numba-cuda finds libnvvm and NVRTC (a CUDA toolkit, or the nvidia-*-cu* wheels)."""
    if not HAS_NUMBA_CUDA:
        return False
    try:
        from cuda.pathfinder import load_nvidia_dynamic_lib

        load_nvidia_dynamic_lib("nvvm")
        load_nvidia_dynamic_lib("nvrtc")
    except Exception:
        return False
    return True


def _captured(monkeypatch, name, call):
    """The arguments fastbearing passes to gpu.<name> during ``call()`` (the launch itself not run)."""
    seen = {}
    monkeypatch.setattr(gpu, name, lambda *args: seen.setdefault("args", args))
    call()
    return seen["args"]


@pytest.mark.skipif(not _libnvvm(), reason="no libnvvm/NVRTC for numba-cuda (CUDA toolkit or nvidia wheels)")
@pytest.mark.parametrize("kind", ["solve", "map"])
def test_kernels_lower_to_ptx_for_a_real_gpu(monkeypatch, kind, tmp_path):
    """The engine's own functions, unchanged, compile as CUDA device functions for sm_90 (H100/H200) without a
    GPU: the quasi-static ball bearing by default (about 10-20 s each); FASTBEARING_PTX_ALL=1 adds the balls at
    speed and the roller bearing (minutes each on 2 cores)."""
    import numba.cuda.dispatcher as dispatcher

    class Sm90:  # the device functions are built for the current device's compute capability: there is none
        compute_capability = (9, 0)

    monkeypatch.setattr(dispatcher, "get_current_device", lambda: Sm90())
    bearings = [fb.Bearing.preset("gunduz2013", "DB")]
    if os.environ.get("FASTBEARING_PTX_ALL") == "1":
        bearings += [fb.load_bearing(DATA.parent / "fastbearing" / "catalogue" / "7014C-DB.toml"),
                     fb.load_bearing(DATA.parent / "fastbearing" / "catalogue" / "30206-TDO.toml")]
    for bearing in bearings:
        speed = 6000.0 if bearing.name == "7014C-DB" else 0.0
        if kind == "solve":
            args = _captured(monkeypatch, "solve_sweep_cuda",
                             lambda: fb.solve_many(bearing, [[500.0, 0, 1000.0, 0, 0]], speed=speed, device="cuda"))
        else:
            # the map kernel's code beyond the solve is the driver's (sweep.map_runs): one bearing shows it lowers
            from fastbearing.jobs import loadmap

            if bearing.name != "gunduz2013":
                continue
            cfg = {"bearing": {"preset": "gunduz2013", "arrangement": "DB"},
                   "loadmap": {"given": "load", "Fx": [0.0, 500.0], "Fz": 1000.0}}
            compute = loadmap.job(loadmap.read_config(cfg), "cuda").compute
            cases = np.array([[0.0, 0, 1000, 0, 0], [500.0, 0, 1000, 0, 0]])
            args = _captured(monkeypatch, "map_sweep_cuda",
                             lambda: compute(cases, _map_results(bearing, 2), 0, np.zeros(1, np.int64)))
        ptx = gpu.compile_ptx(kind, args)
        assert ".target sm_90" in ptx and ".entry" in ptx
        assert "div.approx.f64" not in ptx  # double precision stays double precision


def _map_results(bearing, n):
    rows = bearing.n_rows
    return {"q": np.empty((n, 5)), "f": np.empty((n, 5)), "K": np.empty((n, 5, 5)), "status": np.empty(n, np.int8),
            "iterations": np.empty(n, np.int32), "residual": np.empty(n), "max_ball_load": np.empty((n, rows)),
            "loaded_balls": np.empty((n, rows), np.int16), "min_contact_angle": np.empty((n, rows)),
            "max_contact_angle": np.empty((n, rows))}


def test_device_memory_keeps_tables_and_buffers_across_blocks():
    """Issue 46 item 2: a job's element tables go to the device once (by content, whichever block asks) and the
    result and scratch buffers are reused while their role, shape and dtype recur (here with host arrays)."""
    mem = gpu.DeviceMemory(np.array, np.empty)
    table = np.arange(6.0).reshape(2, 3)
    assert mem.table(table) is mem.table(table.copy())
    assert mem.table(table) is not mem.table(table + 1.0)
    q = mem.buffer("results.q", (4, 5))
    assert mem.buffer("results.q", (4, 5)) is q
    assert mem.buffer("results.status", (4,), np.int8).dtype == np.int8
    assert mem.buffer("results.q", (3, 5)) is not q and len(mem.buffers) == 2  # one buffer per role
    assert mem.data(table) is not mem.data(table)                              # a block's own inputs: copied


@needs_numba_cuda
def test_simulated_map_cuts_runs_into_gpu_segments(simulated):
    """Issue 46 item 2: the GPU cuts a map's runs of 21 cases into segments of 7, one per thread, each starting
    cold. Four launches on their own streams give the one launch's results bit for bit; the CPU sweep on the same
    segments gives them to rounding (statuses, iterations and counts equal: the simulator runs the CPU's code,
    compiled for the GPU's strided scratch); against the CPU's own runs the statuses are equal and converged q and
    Kb agree within the solver's tolerance, not to rounding (other warm starts)."""
    r = _scenario(simulated, "map_segments")
    assert r["cpu_segments"] == [0, 21, 42, 63, 84]
    assert r["gpu_segments"] == list(range(0, 85, 7))
    assert r["launches"] == {"one_launch": 1, "parts": 4}
    assert len(r["parts_equal_one_launch"]) == 10 and all(r["parts_equal_one_launch"].values())
    same = r["same_segments"]
    assert same["status"] == same["iterations"] == same["loaded_balls"] == 0.0
    assert len(same) == 9 and max(same.values()) <= 1e-10, same
    assert r["same_segments_residual"] <= 1e-14
    stored = r["stored_only"]                                   # variables = ["K"]: K and status come back
    assert stored.pop("K") == stored.pop("status") == "equal" and set(stored.values()) == {"untouched"}, stored
    assert r["gpu_status"] == r["cpu_status"] and r["n_converged"] == 84
    assert 0.0 < r["q"] <= 1e-8 and 0.0 < r["K"] <= 1e-8     # different warm starts: close, not equal
    assert r["iterations"][1] > r["iterations"][0]              # the extra cold starts cost iterations


@needs_numba_cuda
@pytest.mark.parametrize("name", ["k_only", "life"])
def test_simulated_float32_maps_are_converted_on_the_device(simulated, name):
    """A map stored in float32: the GPU job's buffers hold the engine's outputs in float32 (converted on the
    device), except f and L10r where life is made from them; the files equal the CPU's to float32 rounding
    (integers exactly; the simulator runs the CPU's code compiled for the GPU's strided scratch)."""
    r = _scenario(simulated, "map_float32" if name == "k_only" else "map_float32_life")[name]
    assert set(r["difference"]) >= {"K", "status"}
    assert max(r["difference"].values()) <= 2.0 ** -23, r["difference"]
    if name == "k_only":
        assert r["narrow"] == ["K"] and r["buffers"] == {"K": "f4"}
        assert r["stored"] == ["Fx", "Fy", "Fz", "K", "Mx", "My", "dof", "dof_col", "row", "status"]
    else:
        assert {"q", "K", "L10r_row", "static_safety", "min_outer_contact_angle"} <= set(r["narrow"])
        assert "f" not in r["narrow"] and "L10r" not in r["narrow"]
        assert r["dtypes"]["f"] == r["dtypes"]["L10r"] == r["dtypes"]["K"] == "<f4"   # all stored in float32
    assert r["dtypes"]["K"] == "<f4"


def test_device_segments_cut_every_run_alone():
    """Every run cut into the fewest near-equal pieces of at most SEGMENT_CASES cases, the runs' starts kept, so
    a block's GPU segments are its runs' own (the same whatever the block size)."""
    runs = np.array([0, 1, 9, 17, 116, 120])               # runs of 1, 8, 8, 99 and 4 cases
    cut = gpu.device_segments(runs, 8)
    assert set(runs) <= set(cut)
    assert np.diff(cut).max() <= 8 and np.diff(cut).min() >= 1
    assert cut[3:17].tolist() == [17, 24, 32, 39, 47, 55, 62, 70, 77, 85, 93, 100, 108, 116]  # 99: 13 of 7 or 8
    both = gpu.device_segments(np.array([0, 99, 198]), 8)
    assert np.array_equal(both, np.append(gpu.device_segments(np.array([0, 99]), 8),
                                          99 + gpu.device_segments(np.array([0, 99]), 8)[1:]))
    assert gpu.device_segments(np.array([0, 5]), 1).tolist() == [0, 1, 2, 3, 4, 5]      # one case per thread


def _map_block(cfg, device="cuda"):
    from fastbearing.jobs import loadmap
    from fastbearing.jobs.grid import plan_blocks

    job = loadmap.job(loadmap.read_config(cfg), device)
    block = plan_blocks(job.cases.shape, job.cases.line_length, job.chunk)[0]
    res = {v.name: np.broadcast_to(np.zeros((), v.dtype), (block.size, *(job.sizes[d] for d in v.trailing)))
           for v in job.buffer_variables}
    inputs = np.broadcast_to(np.zeros(()), (block.size, 5))
    work = job.compute.args[0]  # loadmap.MapWork
    return job, loadmap.block_records(work.bearing, work.line_length, work.life, work.spinning, inputs, res,
                                      block.start)


def test_the_1M_example_is_one_block_of_131_300_threads_on_the_gpu():
    """Blocks sized for the device: the 1M example is one GPU block (the CPU's 65 536-case chunk: 17) whose runs
    of 99 give 131 300 threads in one launch (>= 100 000); its device memory is the block's."""
    job, (elements, cases) = _map_block(str(DATA / "examples" / "gunduz2013-db-1M.toml"))
    assert job.chunk == gpu.DEVICE_CHUNK and cases.inputs.shape[0] == 999_900
    plan = gpu.map_plan(elements, cases)
    assert plan.launches == 1 and plan.blocks * plan.threads_per_block == 131_328   # 131 300 in blocks of 128
    assert 250e6 < plan.device_bytes < 600e6


def test_a_large_block_is_split_into_launches_of_part_threads(monkeypatch):
    """More than 2 x PART_THREADS segments: launches of consecutive segments (a range of cases each), at most
    MAX_PARTS (each with its own scratch: the simulated map_segments scenario runs them)."""
    cfg = {"bearing": {"preset": "gunduz2013", "arrangement": "DB"},
           "loadmap": {"given": "load", "Fx": {"start": -2000.0, "stop": 2000.0, "num": 10}, "Fz": 1000.0,
                       "My": {"start": -1e5, "stop": 1e5, "num": 99}}}
    _, (elements, cases) = _map_block(cfg)
    monkeypatch.setattr(gpu, "PART_THREADS", 40)
    parts = gpu.map_parts(elements, cases)
    assert len(parts.segments) - 1 == 130
    assert [launch[2:] for launch in parts.launches] == [(0, 43), (43, 86), (86, 130)]
    assert [blocks * tpb for blocks, tpb, _, _ in parts.launches] == [43, 43, 44]      # a thread per segment
    monkeypatch.setattr(gpu, "PART_THREADS", 10)
    assert len(gpu.map_parts(elements, cases).launches) == gpu.MAX_PARTS


def test_the_gpu_job_sizes_its_blocks_and_narrows_float32():
    """loadmap.job(cfg, "cuda"): blocks of at least DEVICE_CHUNK cases and a fingerprint that tells them from the
    CPU's (no --resume across devices with other blocks); a float32 map's engine outputs in float32 buffers."""
    from fastbearing.jobs import loadmap

    cfg = {"bearing": {"preset": "gunduz2013", "arrangement": "DB"},
           "loadmap": {"given": "load", "Fx": [0.0, 500.0], "Fz": 1000.0, "variables": ["K", "q"],
                       "dtype": "float32", "chunk": 1000}}
    cpu, cuda = (loadmap.job(loadmap.read_config(cfg), d) for d in ("cpu", "cuda"))
    assert (cpu.chunk, cuda.chunk) == (1000, gpu.DEVICE_CHUNK)
    assert cuda.fingerprint != cpu.fingerprint and cuda.fingerprint.startswith(cpu.fingerprint)
    assert cpu.narrow == () and cuda.narrow == ("q", "K")
    dtypes = {v.name: v.dtype for v in cuda.buffer_variables}
    assert dtypes["K"] == dtypes["q"] == "f4" and dtypes["f"] == "f8"     # f is not stored: computed, dropped
    assert {v.name: v.dtype for v in cpu.buffer_variables} == {v.name: v.dtype for v in cpu.variables}
    big = loadmap.job(loadmap.read_config(cfg | {"loadmap": cfg["loadmap"] | {"chunk": 4_000_000}}), "cuda")
    assert big.chunk == 4_000_000 and big.fingerprint == loadmap.read_config(
        cfg | {"loadmap": cfg["loadmap"] | {"chunk": 4_000_000}}).fingerprint     # the config's own blocks


def test_device_memory_pins_each_host_array_once_and_keeps_its_streams(monkeypatch):
    """The results' host arrays are page-locked once (by the array a block's view belongs to), and the same
    streams serve every block (here with stand-ins for numba.cuda's calls)."""
    locked, made = [], []
    mem = gpu.DeviceMemory(np.array, np.empty, pin_host=lambda a: locked.append(a) or len(locked),
                           new_stream=lambda: made.append(object()) or made[-1])
    buffer = np.zeros((10, 5))
    mem.pin(buffer[:4])
    mem.pin(buffer[2:8])
    mem.pin(buffer)
    assert len(locked) == 1 and locked[0] is buffer
    monkeypatch.setattr(gpu, "PINNED_BYTES", 500)                          # 400 bytes held: the next goes first
    mem.pin(np.zeros(20))
    assert len(locked) == 2 and list(mem.pinned.values()) == [2]
    assert mem.streams(2) == made and mem.streams(1) == made[:1] and len(made) == 2
    assert gpu.DeviceMemory(np.array, np.empty).streams(2) == [0, 0]      # no streams: the default one
