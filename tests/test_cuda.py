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
QUICK = ("cold_ball", "warm_ball", "broyden_fixed", "map_ball", "passage_ball")
ALL = QUICK + ("speed_ball", "roller", "map_speed_life", "passage_roller_speed")
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


@needs_numba_cuda
@pytest.mark.parametrize("name", ["passage_ball", "passage_roller_speed"])
def test_simulated_passage_tables_match_the_cpu(simulated, name):
    """Ball-passage tables, one operating point per GPU thread: the DB pair; with FASTBEARING_CUDASIM_ALL=1 also
    the tapered roller pair and the spindle pair at 12 000 rpm with an outer-race spall."""
    r = _scenario(simulated, name)
    for table in ([r] if "cpu_status" in r else list(r.values())):
        assert table["gpu_status"] == table["cpu_status"]
        assert max(table["max_relative"].values()) <= 1e-10, table["max_relative"]


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
