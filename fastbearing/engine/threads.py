"""The CPU drivers' threads: Python threads over one serial ``nogil`` kernel (engine/sweep.py).

A ``parallel=True`` loop compiles the whole solver a second time into its outlined body; a serial kernel that
releases the GIL, run by a few threads at once, compiles it once and runs as fast (bench/README, issue 45).
The kernel takes its items (blocks of cases, groups of runs) one at a time from a shared counter, so which
thread runs an item never changes what the item computes: results do not depend on the thread count.
"""

import os
import threading
from concurrent.futures import ThreadPoolExecutor, wait

import numba
import numpy as np

_pool = None
_pool_pid = None
_pool_lock = threading.Lock()


def _executor() -> ThreadPoolExecutor:
    """The process's pool (NUMBA_NUM_THREADS - 1 threads: the caller is one more), made again in a forked child,
    where the parent's threads do not exist."""
    global _pool, _pool_pid
    with _pool_lock:
        if _pool is None or _pool_pid != os.getpid():
            _pool = ThreadPoolExecutor(max(numba.config.NUMBA_NUM_THREADS - 1, 1), "fastbearing-sweep")
            _pool_pid = os.getpid()
        return _pool


def share(kernel, n_items: int, *args) -> None:
    """Run ``kernel(counter, *args)`` on min(numba.get_num_threads(), n_items) threads, this one among them,
    and return when every one has: ``counter`` (int64 array (1,), from 0) is how the kernel takes its next item
    (sweep._claim). The thread count is numba's for the calling thread (``--threads``, api.num_threads,
    NUMBA_NUM_THREADS). An exception in any thread is raised here, after all have ended: no thread writes into
    the results once this returns."""
    if n_items <= 0:
        return
    counter = np.zeros(1, np.int64)
    threads = min(numba.get_num_threads(), n_items)
    if threads == 1:
        kernel(counter, *args)
        return
    others = [_executor().submit(kernel, counter, *args) for _ in range(threads - 1)]
    try:
        kernel(counter, *args)
    finally:
        for other in others:
            other.cancel()  # not started yet (the pool busy with another caller's items): nothing left to take
        wait(others)
    for other in others:
        if not other.cancelled():
            other.result()
