"""One compiler per function across processes (_numba_cache.serialise_compiles): processes started together on
an empty cache compile each of the package's functions once, the others wait and load it; the lock is
re-entrant, gives up after its patience, and says when a wait lasts."""

import os
import subprocess
import sys
import textwrap
import time

import pytest

from fastbearing import _numba_cache as nc

fcntl = pytest.importorskip("fcntl")

#: A process that, once ``go`` names a file, runs one small package kernel and reports its compilations.
KERNEL = textwrap.dedent("""
    import sys, pathlib
    import numpy as np
    from numba.core import event
    from fastbearing.engine.sweep import static_safety

    count = [0]

    class Count(event.Listener):
        def on_start(self, ev):
            count[0] += ev.data["dispatcher"] is static_safety

        def on_end(self, ev):
            pass

    event.register("numba:compile", Count())
    if sys.argv[1] == "hold":  # stand in for another process compiling: hold the function's lock
        import fcntl, time
        cache = static_safety._cache
        fd = open(cache._cache_file._index_path + ".lock", "w")
        fcntl.flock(fd, fcntl.LOCK_EX)
        print("held", flush=True)
        ready = [pathlib.Path(p) for p in sys.argv[2:]]
        end = time.monotonic() + 120
        while not all(p.exists() for p in ready) and time.monotonic() < end:
            time.sleep(0.05)
        time.sleep(5.0)  # both are waiting by now (numba's set-up done), and said so
        sys.exit(0)
    import fastbearing._numba_cache as nc
    from numba import njit

    nc.WAIT_FIRST = 0.2  # say so soon
    njit(lambda x: x + 1)(1)  # numba's compiler set up (seconds on a loaded machine) before the flag
    pathlib.Path(sys.argv[2]).touch()
    S0 = static_safety(np.array([1000.0, 0, 500.0, 0, 0]), np.full((1, 16), 0.5), 20000.0)
    print("compilations", count[0], "S0", repr(S0), flush=True)
""")


def test_processes_started_together_compile_a_function_once(tmp_path):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    flags = [tmp_path / "a", tmp_path / "b"]
    holder = subprocess.Popen([sys.executable, "-c", KERNEL, "hold", *map(str, flags)], env=env, text=True,
                              stdout=subprocess.PIPE)
    assert holder.stdout.readline().strip() == "held"
    runs = [subprocess.Popen([sys.executable, "-c", KERNEL, "run", str(flag)], env=env, text=True,
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE) for flag in flags]
    outs = [run.communicate(timeout=300) for run in runs]
    assert holder.wait(timeout=60) == 0
    for run, (out, err) in zip(runs, outs):
        assert run.returncode == 0, err
        assert "another process is compiling static_safety; waiting for numba's cache" in err, (out, err)
    counts = [int(out.split()[1]) for out, _ in outs]
    assert sorted(counts) == [0, 1]  # one compiled it (the holder saved nothing), the other loaded that
    assert outs[0][0].split()[3] == outs[1][0].split()[3]


def test_the_lock_is_reentrant_says_when_it_waits_and_gives_up_after_its_patience(tmp_path, monkeypatch):
    path = str(tmp_path / "f.nbi.lock")
    said = []
    assert nc._acquire(path, "f", said.append)
    assert nc._acquire(path, "f", said.append)  # the same process again (a nested compilation)
    assert nc._held[path][1] == 2
    nc._release(path)
    assert path in nc._held
    nc._release(path)
    assert path not in nc._held
    other = open(path, "w")  # another holder: another open file description
    fcntl.flock(other, fcntl.LOCK_EX)
    monkeypatch.setattr(nc, "LOCK_PATIENCE", 0.6)
    monkeypatch.setattr(nc, "WAIT_FIRST", 0.2)
    started = time.monotonic()
    assert not nc._acquire(path, "f", said.append)  # ran out of patience: compile without the lock
    assert time.monotonic() - started >= 0.6  # it waited its patience out
    assert said and said[0].startswith("fastbearing: another process is compiling f; waiting")
    fcntl.flock(other, fcntl.LOCK_UN)
    assert nc._acquire(path, "f", said.append)
    nc._release(path)
    other.close()


def test_the_lock_is_in_place_and_only_for_the_package(tmp_path):
    """numba's internals the lock wraps (FunctionCache.load_overload/save_overload, the index path) are still
    there: a numba that changes them fails here, loudly, rather than compile without the lock."""
    from numba import njit
    from numba.core import caching

    from fastbearing.engine.sweep import static_safety

    assert nc.serialise_compiles()
    assert caching.FunctionCache.load_overload.__wrapped__ is not None
    assert caching.FunctionCache.save_overload.__wrapped__ is not None
    path = nc._lock_path(static_safety._cache)
    assert path.endswith(".nbi.lock") and "static_safety" in path

    @njit(cache=True)
    def not_ours(x):
        return x

    assert nc._lock_path(not_ours._cache) is None


def test_only_a_compilation_that_raised_gives_its_lock_back_before_the_save():
    """numba's Event.is_failed is True for a compilation that succeeded (numba 0.68): the lock went back when the
    compilation ended, before its entry was saved, and a waiting process compiled the function too (one run in
    four of the test above). compile_failed reads the exception itself; this fails loudly if numba changes it."""
    from numba.core import event

    def end(exc_details):
        return event.Event("numba:compile", event.EventStatus.END, data={}, exc_details=exc_details)

    assert not nc.compile_failed(end((None, None, None)))  # what a `with` block that ended normally passes
    assert not nc.compile_failed(end(None))
    error = ValueError("typing failed")
    assert nc.compile_failed(end((ValueError, error, None)))
