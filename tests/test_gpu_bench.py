"""The GPU benchmark and the device check without a GPU (issue 46): bench/gpu_bench.py's plan and its checks, and
bench/gpu_device_check.sh under numba's CUDA simulator, the script a GPU machine runs, at tiny sizes.

No timing is asserted. Units: N, N*mm, mm, rad.
"""

import importlib.util
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from fastbearing import status as st

ROOT = Path(__file__).resolve().parents[1]
HAS_NUMBA_CUDA = importlib.util.find_spec("numba_cuda") is not None


def _env(**extra):
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_ENABLE_CUDASIM"}
    return env | extra


@pytest.fixture(scope="module")
def bench():
    spec = importlib.util.spec_from_file_location("gpu_bench", ROOT / "bench" / "gpu_bench.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_plan_names_every_stage_and_the_1M_map_without_a_gpu():
    run = subprocess.run([sys.executable, str(ROOT / "bench" / "gpu_bench.py"), "--plan"], capture_output=True,
                         text=True, env=_env(), timeout=300)
    assert run.returncode == 0, run.stderr[-3000:]
    lines = run.stdout.splitlines()
    for stage in ("cold", "1M", "speed", "roller", "1e8"):
        assert any(line.startswith(f"{stage}: ") and "threads" in line and "device memory" in line
                   for line in lines), run.stdout
    one_m = next(line for line in lines if line.startswith("1M: "))
    assert "gunduz2013-db-1M.toml" in one_m and "999,900 cases" in one_m
    # issue 46 item 2: one block sized for the device, its runs of 99 cut into GPU segments of at most 8 cases
    assert "999,900 cases: 1 block, 1 launch of 131,328 threads (one GPU segment of at most 8 cases" in one_m
    big = next(line for line in lines if line.startswith("1e8: "))
    assert "26 blocks, 76 launches of 13,056-173,440 threads" in big     # 4M-case blocks: 3 launches each


def test_plan_of_one_stage(bench, capsys):
    bench.print_plan(["roller"], small=True)
    out = capsys.readouterr().out
    assert "roller: the roller map (30206-TDO), 12 cases: 1 block, 1 launch of 4 threads" in out
    assert "cold:" not in out


def test_the_check_sees_a_nan_and_fails(bench):
    """A GPU NaN where the CPU converged is a disagreement (a plain max of the differences would hide it)."""
    n = 20
    status = np.zeros(n, np.int8)
    cpu = np.ones((n, 5))
    gpu = cpu.copy()
    gpu[3, 2] = math.nan
    bench.FAILURES.clear()
    text = bench.compare("nan", status, status, [cpu], [gpu])
    assert "finite on one device only 1" in text and "DISAGREEMENT" in text
    assert bench.FAILURES == ["nan"]


def test_the_check_allows_rounding_but_not_more(bench):
    n = 20_000
    status = np.zeros(n, np.int8)
    cpu = np.full((n, 5), 2.0)
    bench.FAILURES.clear()
    assert "DISAGREEMENT" not in bench.compare("rounding", status, status, [cpu], [cpu * (1 + 1e-12)])
    flipped = status.copy()
    flipped[:2] = st.PRECISION_LIMIT  # two outcome flips in 20 000 cases: the tolerance (1 in 10 000)
    text = bench.compare("flips", status, flipped, [cpu], [cpu])
    assert "outcome flips 2 (allowed 2)" in text and "DISAGREEMENT" not in text
    flipped[2] = st.PRECISION_LIMIT
    assert "DISAGREEMENT" in bench.compare("flips", status, flipped, [cpu], [cpu])
    assert "DISAGREEMENT" in bench.compare("far", status, status, [cpu], [cpu * (1 + 1e-5)])
    assert bench.FAILURES == ["flips", "far"]


@pytest.mark.skipif(not HAS_NUMBA_CUDA, reason="numba-cuda is not installed (pip install '.[cuda]')")
def test_device_check_runs_under_the_simulator(tmp_path):
    """The device check as a GPU machine runs it, simulated at tiny sizes (the quasi-static DB stages: the kernels
    the rest of the suite compiles); its figures land in $OUT and nothing is left behind."""
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    run = subprocess.run(["bash", str(ROOT / "bench" / "gpu_device_check.sh"), "--simulate", "--stages",
                          "cold,1M 1e8"], capture_output=True, text=True, timeout=600,
                         env=_env(OUT=str(tmp_path), PYTHON=sys.executable, TMPDIR=str(tmp)))
    figures = (tmp_path / "gpu-device-check.txt").read_text()
    assert run.returncode == 0, figures + run.stderr[-2000:]
    assert figures.count("every stage agrees within the tolerances") == 2
    assert "1M: the example map, tiny" in figures      # the plan first
    assert "outcome flips 0" in figures and "DISAGREEMENT" not in figures
    assert list(tmp.iterdir()) == []                     # the work folder is gone
