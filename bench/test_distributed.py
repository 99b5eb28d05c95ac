"""Overhead of the Dask path against the local engine: the 1M-case example, 2 workers x 1 thread
against the local engine on 2 threads, same machine, same process."""

import tomllib
from pathlib import Path

import pytest

import fastbearing as fb

pytest.importorskip("distributed")
EXAMPLE = Path(__file__).resolve().parents[1] / "data" / "examples" / "gunduz2013-db-1M.toml"
_times = {}


@pytest.fixture(scope="module")
def client():
    from fastbearing.jobs.distributed import client_for

    client, cluster = client_for("local:2")
    yield client
    client.close()
    cluster.close()


@pytest.mark.parametrize("engine", ["local", "dask"])
@pytest.mark.benchmark(group="1M-case example map: local engine vs Dask local:2")
def test_engine_overhead(benchmark, tmp_path, client, engine):
    doc = tomllib.loads(EXAMPLE.read_text())
    kw = {"client": client} if engine == "dask" else {"threads": 2}
    # small blocks, so that every worker gets some and loads the kernels before the timed run
    warm = {**doc, "loadmap": {**doc["loadmap"], "Fx": {**doc["loadmap"]["Fx"], "num": 2}, "chunk": 990}}
    fb.loadmap(warm, tmp_path / "warm.h5", progress=False, **kw)  # compile / load kernels everywhere
    counter = iter(range(10))
    benchmark.pedantic(lambda: fb.loadmap(doc, tmp_path / f"{engine}{next(counter)}.h5", progress=False, **kw),
                       rounds=1, iterations=1)
    if not benchmark.disabled:  # --benchmark-disable: a smoke run, no figures
        _times[engine] = benchmark.stats.stats.median
        benchmark.extra_info["cases_per_s"] = 999_900 / _times[engine]
        if engine == "dask" and "local" in _times:
            benchmark.extra_info["overhead_vs_local"] = _times["dask"] / _times["local"]
