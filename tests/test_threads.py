"""The CPU drivers' threads (engine/threads.py): every item once, numba's thread count, errors raised after all
threads have ended. The sweeps' results for any thread count: test_loadmap, test_passage, test_solver."""

import threading

import numba
import numpy as np
import pytest
from numba import njit

from fastbearing.engine.sweep import _claim
from fastbearing.engine.threads import share


@njit(nogil=True)
def _take_all(counter, n_items, taken):
    """Each item claimed adds 1 at its index: every entry 1 when each item ran exactly once."""
    item = _claim(counter)
    while item < n_items:
        taken[item] += 1
        item = _claim(counter)


@pytest.mark.parametrize("threads", [1, 2])
@pytest.mark.parametrize("n_items", [1, 3, 1000])
def test_every_item_runs_exactly_once(threads, n_items):
    taken = np.zeros(n_items, np.int64)
    old = numba.get_num_threads()
    numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
    try:
        share(_take_all, n_items, n_items, taken)
    finally:
        numba.set_num_threads(old)
    assert (taken == 1).all()


def test_numba_thread_count_is_the_number_of_threads():
    seen = set()
    lock = threading.Lock()

    def kernel(counter, n_items):
        with lock:
            seen.add(threading.get_ident())

    old = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        share(kernel, 64, 64)
    finally:
        numba.set_num_threads(old)
    assert seen == {threading.get_ident()}  # one thread: the caller's, no pool
    seen.clear()
    share(kernel, 1, 1)  # one item: one thread, whatever the count
    assert len(seen) == 1


def test_an_error_in_a_thread_is_raised_once_every_thread_has_ended():
    ended = []
    started = threading.Event()

    def kernel(counter, n_items):
        if threading.current_thread() is not threading.main_thread():
            started.set()
            raise ValueError("from a pool thread")
        started.wait(10.0)  # the pool's task running, so not cancelled: its error must reach the caller
        ended.append(True)

    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("one numba thread: no pool thread")
    with pytest.raises(ValueError, match="pool thread"):
        share(kernel, 2, 2)
    assert ended == [True]


def test_two_callers_at_once_each_get_every_item():
    """Two threads sharing at once: the pool's threads may be busy with the other caller's items, and each
    caller then takes its own items alone (the tasks it queued are cancelled, never waited for)."""
    results = [np.zeros(500, np.int64), np.zeros(500, np.int64)]
    callers = [threading.Thread(target=share, args=(_take_all, 500, 500, taken)) for taken in results]
    for caller in callers:
        caller.start()
    for caller in callers:
        caller.join()
    assert all((taken == 1).all() for taken in results)


def test_no_items_runs_nothing():
    share(lambda *args: pytest.fail("called"), 0)
