"""Parallel drivers: thin ``prange`` loops over blocks of cases.

Each block allocates its scratch once and calls the serial kernels case by
case, so a case's result never depends on the thread count or on which
thread ran it.
"""

import numpy as np
from numba import njit, prange

from .config import CACHE
from .kernel import ball_loop
from .solver import WORK_ROWS, solve_case


@njit(parallel=True, cache=CACHE)
def solve_sweep(f_targets, q, f, K, status, iterations, residual, evaluations, balls, method, warm, rtol,
                max_iter, length_scale, force_floor, max_step, block):
    """Solve every row of ``f_targets`` (N, 5); q (N, 5) holds warm starts when ``warm``."""
    n = f_targets.shape[0]
    n_blocks = (n + block - 1) // block
    for b in prange(n_blocks):
        work = np.empty((WORK_ROWS, 5))
        for i in range(b * block, min(n, (b + 1) * block)):
            st, it, res, ev = solve_case(f_targets[i], q[i], f[i], K[i], balls, method, warm, rtol, max_iter,
                                         length_scale, force_floor, max_step, work)
            status[i] = st
            iterations[i] = it
            residual[i] = res
            evaluations[i] = ev


@njit(parallel=True, cache=CACHE)
def stiffness_sweep(q, f, K, balls, block):
    """f and Kb at every row of q (N, 5) by direct substitution."""
    n = q.shape[0]
    n_blocks = (n + block - 1) // block
    empty = np.empty(0)
    for b in prange(n_blocks):
        for i in range(b * block, min(n, (b + 1) * block)):
            ball_loop(q[i], balls, f[i], K[i], True, empty, empty)
