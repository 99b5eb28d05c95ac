"""Ball-passage benchmark: load-controlled tables (q re-solved at every cage position)."""

import pytest

import fastbearing as fb


def config(n_fx, n_fz):
    return {"bearing": {"preset": "gunduz2013", "arrangement": "DB"},
            "passage": {"given": "load", "Fx": {"start": 200.0, "stop": 5000.0, "num": n_fx},
                        "Fz": {"start": 500.0, "stop": 5000.0, "num": n_fz}, "My": -74000.0, "positions": 64}}


@pytest.mark.parametrize("threads", [1, 2])
@pytest.mark.benchmark(group="ball passage, 1000 points x 64 positions, load-controlled, to HDF5")
def test_passage_load_controlled(benchmark, tmp_path, threads):
    fb.passage(config(2, 2), tmp_path / "warm.h5", threads=threads)  # compile outside the timing
    counter = iter(range(100))
    out = benchmark.pedantic(lambda: fb.passage(config(40, 25), tmp_path / f"p{next(counter)}.h5",
                                                threads=threads), rounds=3)
    assert fb.open_dataset(out)["status"].shape == (40, 25, 64)
    benchmark.extra_info["solves_per_s"] = 64_000 / benchmark.stats.stats.median
