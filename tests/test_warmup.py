"""`fastbearing warmup` (issue 45): after it, a new process's first command compiles nothing; its progress;
the portable cache for a CPU level; and the compile notice's progress lines."""

import os
import subprocess
import sys
import textwrap

import pytest

from conftest import COUNT_COMPILATIONS

#: A process that runs one command through the command line's main() and reports numba's compilations.
COUNT_COMPILES = COUNT_COMPILATIONS + textwrap.dedent("""
    from fastbearing import cli

    code = cli.main(sys.argv[1:])
    print("compilations:", count[0], file=sys.stderr)
    sys.exit(code)
""")

SOLVE = ["solve", "--preset", "gunduz2013", "--arrangement", "DB", "--load", "1000,0,3000,0,-74000"]


def _run(args, env, script=None):
    command = [sys.executable, "-c", script, *args] if script else [sys.executable, "-m", "fastbearing.cli", *args]
    return subprocess.run(command, env=env, capture_output=True, text=True, timeout=900)


def test_after_warmup_the_first_solve_compiles_nothing(tmp_path):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    warm = _run(["warmup", "--kinds", "quasi-static"], env)
    assert warm.returncode == 0, warm.stderr
    assert "kernel family 1 of 1: quasi-static" in warm.stderr and "s elapsed" in warm.stderr
    assert "quasi-static compiled in" in warm.stderr
    assert "fastbearing: compiling the kernels into numba's cache" in warm.stderr  # said once, when numba starts
    assert warm.stderr.count("compiling the kernels") == 1
    first = _run(SOLVE, env, COUNT_COMPILES)
    assert first.returncode == 0, first.stderr
    assert "compilations: 0" in first.stderr and "compiling" not in first.stderr
    assert "status: converged" in first.stdout
    again = _run(["warmup", "--kinds", "quasi-static"], env)  # a second warm-up loads what the first built
    assert "quasi-static loaded from the cache" in again.stderr and "(0 compilations)" in again.stderr


def _has_avx2() -> bool:
    try:
        from llvmlite import binding as ll

        features = ll.get_host_cpu_features()
        return bool(features.get("avx2")) and bool(features.get("fma"))
    except Exception:
        return False


@pytest.mark.skipif(not _has_avx2(), reason="x86-64-v3 code needs AVX2 and FMA on this CPU")
def test_a_portable_cache_for_a_cpu_level_is_used_by_a_process_of_that_level(tmp_path):
    """--portable x86-64-v3 --into DIR builds in a fresh process with NUMBA_CPU_NAME; a process started with the
    same level and cache folder compiles nothing, while the host's own target ignores it (numba keys the cache
    by CPU name and features)."""
    from fastbearing.jobs.warmup import portable_environment

    cache = tmp_path / "v3"
    build = _run(["warmup", "--kinds", "quasi-static", "--portable", "x86-64-v3", "--into", str(cache)],
                 dict(os.environ))
    assert build.returncode == 0, build.stderr
    assert any(cache.rglob("*.nbi"))
    portable = _run(SOLVE, portable_environment("x86-64-v3", cache), COUNT_COMPILES)
    assert portable.returncode == 0, portable.stderr
    assert "compilations: 0" in portable.stderr


def test_warmup_refuses_unknown_families_and_half_a_portable_request(capsys):
    from fastbearing import cli

    assert cli.main(["warmup", "--kinds", "quasi-static,warp-drive"]) == 2
    assert "unknown kernel family warp-drive" in capsys.readouterr().err
    assert cli.main(["warmup", "--portable", "x86-64-v3"]) == 2
    assert "--portable LEVEL and --into DIR go together" in capsys.readouterr().err


def test_a_long_compilation_says_how_far_it_is(monkeypatch, capsys):
    """The notice comes first; a compilation that lasts says how far it is every few seconds, so a wait of
    more than 2 s is never silent (issue 45, item 1)."""
    import time

    from numba import njit

    from fastbearing import _cache

    monkeypatch.setattr(_cache, "_told", False)
    monkeypatch.setattr(_cache, "PROGRESS_FIRST", 0.2)

    @njit
    def slow_to_compile(x):
        return x + 1

    from numba.core import event

    with _cache.CompileWatch():  # a compilation of 1.5 s, as numba's compile event announces it
        with event.trigger_event("numba:compile", data={"dispatcher": slow_to_compile, "args": (), "return_type": None}):
            time.sleep(1.5)
    err = capsys.readouterr().err
    assert err.startswith("fastbearing: compiling the kernels")
    assert "fastbearing: compiling, " in err and "s so far" in err and "slow_to_compile" in err


#: A Dask run of the README's main job's kind (the 1M example's config on a small grid) on one local worker
#: process, counting numba's compilations inside the worker.
DASK_MAP = textwrap.dedent("""
    import sys
    import fastbearing as fb
    from fastbearing.jobs.distributed import client_for

    def count_compiles():
        from numba.core import event

        class Count(event.Listener):
            def on_start(self, ev):
                event.fastbearing_test_compiles += 1

            def on_end(self, ev):
                pass

        event.fastbearing_test_compiles = 0
        event.register("numba:compile", Count())

    def compiles():
        from numba.core import event

        return event.fastbearing_test_compiles

    if __name__ == "__main__":
        client, cluster = client_for("local:1")
        try:
            client.run(count_compiles)
            config = {"bearing": {"preset": "gunduz2013", "arrangement": "DB"},
                      "loadmap": {"given": "load", "Fx": {"start": -2000.0, "stop": 2000.0, "num": 4}, "Fy": 0.0,
                                  "Fz": {"start": 500.0, "stop": 10000.0, "num": 3}, "Mx": 0.0,
                                  "My": {"start": -1.0e5, "stop": 1.0e5, "num": 5}, "chunk": 65536,
                                  "compression": "none"}}
            fb.loadmap(config, sys.argv[1], client=client, progress=False)
            print("worker compilations:", sum(client.run(compiles).values()), file=sys.stderr)
        finally:
            client.close()
            cluster.close()
""")


def test_dask_workers_on_a_warmed_cache_compile_nothing(tmp_path):
    """The workers of a cluster whose cache a warm-up built (an image, a node) load the kernels: a map
    through a LocalCluster compiles nothing in its worker (numba's compile events counted there)."""
    pytest.importorskip("distributed")
    # the suite's own cache (not a fresh folder): the warm-up then compiles only what the other map tests
    # would compile anyway, where a fresh folder cost this test 156 s of its own; the claim is the same
    env = dict(os.environ)
    warm = _run(["warmup", "--kinds", "maps"], env)
    assert warm.returncode == 0, warm.stderr
    script = tmp_path / "dask_map.py"
    script.write_text(DASK_MAP)
    run = subprocess.run([sys.executable, str(script), str(tmp_path / "map.h5")], env=env, capture_output=True,
                         text=True, timeout=900, cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    assert "worker compilations: 0" in run.stderr, run.stderr[-2000:]


def test_a_portable_level_the_host_cannot_run_is_refused_before_anything_runs(monkeypatch, tmp_path, capsys):
    """The warm-up runs what it compiles: x86-64-v4 code on a machine without AVX-512 would die of an illegal
    instruction, so the level's features are checked first (here faked: a host without avx512f)."""
    from fastbearing import cli
    from fastbearing.jobs import warmup

    v3_only = set(warmup.LEVELS["x86-64-v3"])
    monkeypatch.setattr(warmup, "host_features", lambda: v3_only)
    monkeypatch.setattr(warmup.subprocess, "run", lambda *a, **k: pytest.fail("nothing may run"))
    assert cli.main(["warmup", "--portable", "x86-64-v4", "--into", str(tmp_path / "v4")]) == 2
    err = capsys.readouterr().err
    assert "this machine lacks avx512bw, avx512cd, avx512dq, avx512f, avx512vl" in err
    assert not (tmp_path / "v4").exists()
    assert cli.main(["warmup", "--portable", "pentium4", "--into", str(tmp_path / "p4")]) == 2
    assert "one of x86-64-v2, x86-64-v3, x86-64-v4" in capsys.readouterr().err


def test_the_warmup_processes_import_this_fastbearing_not_a_clone_in_the_working_folder(tmp_path, monkeypatch):
    """A portable warm-up's process runs ``python -P`` with this package first on PYTHONPATH: started in a
    clone's folder, it still compiles the installed package's files (numba keys its cache by them). The
    command and environment are the ones warmup_portable builds, run here with a decoy package in the
    working folder."""
    from fastbearing.jobs import warmup as w

    started = []
    run = subprocess.run
    monkeypatch.setattr(w, "_check_host_runs", lambda level: None)
    monkeypatch.setattr(w.subprocess, "run", lambda command, env: started.append((command, env))
                        or subprocess.CompletedProcess(command, 0))
    assert w.warmup_portable("x86-64-v2", tmp_path / "into", ["shafts"]) == 0
    (command, env), = started
    flags = command[1:command.index("-c")]
    assert env["NUMBA_CPU_NAME"] == "x86-64-v2"
    decoy = tmp_path / "fastbearing"
    decoy.mkdir()
    (decoy / "__init__.py").write_text("raise SystemExit('imported the decoy')\n")
    out = run([command[0], *flags, "-c", "import fastbearing; print(fastbearing.__file__)"], env=env,
                         cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    import fastbearing

    assert out.stdout.strip() == fastbearing.__file__
