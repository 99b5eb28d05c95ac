"""Zarr stores written by the workers (issue 38): the 1M-case example into a zarr store locally, and on Dask
with 1 and with 2 single-threaded workers (the workers write their own blocks); beside them today's funnel
(workers send their arrays back, the client writes HDF5). Same machine, same process; ratios, not times.

extra_info: ``wall_vs_1_worker`` (2 workers against 1, the target is <= 0.6) and ``client_bytes_per_case``
(bytes of results the client received per case: 0.03 with zarr, ~345 through the HDF5 funnel).
"""

import tomllib
from pathlib import Path

import pytest

import fastbearing as fb

pytest.importorskip("distributed")
pytest.importorskip("zarr")
EXAMPLE = Path(__file__).resolve().parents[1] / "data" / "examples" / "gunduz2013-db-1M.toml"
N_CASES = 999_900
_times = {}


@pytest.fixture(scope="module")
def clusters():
    from fastbearing.jobs.distributed import client_for

    made = {n: client_for(f"local:{n}") for n in (1, 2)}
    yield {n: client for n, (client, _) in made.items()}
    for client, cluster in made.values():
        client.close()
        cluster.close()


#: Where the outputs go: the test's temporary folder (this machine's disk, about 300-400 MB/s for these
#: writes), and memory (/dev/shm, tmpfs) to take the disk out and see what the workers themselves scale to.
WHERE = {"disk": None, "memory": Path("/dev/shm")}


@pytest.mark.parametrize("where", list(WHERE))
@pytest.mark.parametrize("engine", ["local zarr", "dask 1 worker zarr", "dask 2 workers zarr",
                                    "dask 2 workers hdf5 (funnel)"])
@pytest.mark.benchmark(group="1M-case example: zarr written by the workers")
def test_zarr_scale_out(benchmark, tmp_path, clusters, engine, where):
    import shutil
    import tempfile

    if WHERE[where] is not None and not WHERE[where].is_dir():
        pytest.skip(f"no {WHERE[where]} here")
    folder = Path(tempfile.mkdtemp(dir=WHERE[where] or tmp_path))
    doc = tomllib.loads(EXAMPLE.read_text())
    kw = {"threads": 1} if engine.startswith("local") else {"client": clusters[1 if "1 worker" in engine else 2]}
    suffix = ".h5" if "hdf5" in engine else ".zarr"
    # small blocks, so that every worker gets some and loads the kernels before the timed run
    warm = {**doc, "loadmap": {**doc["loadmap"], "Fx": {**doc["loadmap"]["Fx"], "num": 2}, "chunk": 990}}
    fb.loadmap(warm, folder / f"warm{suffix}", progress=False, **kw)
    counter = iter(range(10))
    attrs = {}

    def run():
        out = fb.loadmap(doc, folder / f"run{next(counter)}{suffix}", progress=False, **kw)
        attrs.update(fb.open_map(out).attrs)
        shutil.rmtree(out) if suffix == ".zarr" else out.unlink()   # rounds do not fill the disk or memory

    try:
        benchmark.pedantic(run, rounds=3, iterations=1)
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    if "dask_bytes_received" in attrs:
        benchmark.extra_info["client_bytes_per_case"] = int(attrs["dask_bytes_received"]) / N_CASES
    if not benchmark.disabled:  # --benchmark-disable: a smoke run, no figures
        key = (engine, where)
        _times[key] = benchmark.stats.stats.median
        benchmark.extra_info["cases_per_s"] = N_CASES / _times[key]
        if engine == "dask 2 workers zarr" and ("dask 1 worker zarr", where) in _times:
            benchmark.extra_info["wall_vs_1_worker"] = _times[key] / _times[("dask 1 worker zarr", where)]
