"""Load-map benchmarks: end to end including HDF5 writing.

The full one-million-case example is measured from the command line (see
bench/README.md); here a 100 000-case slice of it, so the suite stays short.
"""

import tomllib
from pathlib import Path

import pytest

import fastbearing as fb

EXAMPLE = Path(__file__).resolve().parents[1] / "data" / "examples" / "gunduz2013-db-1M.toml"


def example_config(num_fx, compression="none"):
    doc = tomllib.loads(EXAMPLE.read_text())
    doc["loadmap"]["Fx"]["num"] = num_fx
    doc["loadmap"]["compression"] = compression
    return doc


@pytest.mark.parametrize("compression", ["none", "lzf"])
@pytest.mark.parametrize("threads", [1, 2])
@pytest.mark.benchmark(group="load map, 10 x 100 x 99 = 99 000 load-given cases, to HDF5")
def test_loadmap_end_to_end(benchmark, tmp_path, threads, compression):
    cfg = example_config(10, compression)
    fb.loadmap(cfg, tmp_path / "warm.h5", threads=threads, progress=False)  # compile outside the timing
    counter = iter(range(100))
    out = benchmark.pedantic(lambda: fb.loadmap(cfg, tmp_path / f"m{next(counter)}.h5", threads=threads,
                                                progress=False), rounds=3)
    assert fb.open_dataset(out)["status"].size == 99_000
    benchmark.extra_info["cases_per_s"] = 99_000 / benchmark.stats.stats.median
