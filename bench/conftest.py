"""Shared benchmark inputs: the paper's bearing and a fixed, seeded set of random combined loads."""

import os
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))

import fastbearing as fb  # noqa: E402
from fastbearing.engine.kernel import ball_loop  # noqa: E402
from numba import njit  # noqa: E402

# child processes (the timed whole-process runs) import the same fastbearing as this process, and so share
# its numba cache (tests/conftest.py says why)
os.environ["PYTHONPATH"] = os.pathsep.join(
    p for p in (str(Path(fb.__file__).resolve().parents[1]), os.environ.get("PYTHONPATH")) if p)

#: Source a child process's script starts with: own_peak_kb(), its own peak resident memory in kB (VmHWM;
#: ru_maxrss survives exec, so a child forked from a large pytest process would report the parent's size).
PEAK_RSS = """
import resource


def own_peak_kb():
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1])
    except OSError:  # no /proc: ru_maxrss
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
"""

BEARING = fb.Bearing.preset("gunduz2013", "DB")
TABLE3 = np.array([1000.0, 0.0, 0.0, 0.0, -74000.0])
TABLE4 = np.array([1000.0, 0.0, 3000.0, 0.0, -74000.0])


def random_loads(n, seed=0):
    """Fx, Fy in +-3 kN, Fz in +-8 kN, Mx, My in +-100 N*m (N, N*mm)."""
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.uniform(lo, hi, n) for lo, hi in
                            ((-3000, 3000), (-3000, 3000), (-8000, 8000), (-1e5, 1e5), (-1e5, 1e5))])


@pytest.fixture(scope="session")
def bearing():
    return BEARING


@njit
def repeat_kernel(q, balls, n):
    """n kernel evaluations inside compiled code: no dispatch overhead in the figure."""
    f = np.empty(5)
    K = np.empty((5, 5))
    acc = 0.0
    for i in range(n):
        q[0] += 1e-15  # defeat loop-invariant hoisting
        ball_loop(q, balls, f, K, None, None)
        acc += K[0, 0]
    return acc
