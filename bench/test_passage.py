"""Ball-passage benchmark: load-controlled tables (q re-solved at every cage position)."""

import pytest

import fastbearing as fb


def config(n_fx, n_fz):
    return {"bearing": {"preset": "gunduz2013", "arrangement": "DB"},
            "passage": {"given": "load", "Fx": {"start": 200.0, "stop": 5000.0, "num": n_fx},
                        "Fz": {"start": 500.0, "stop": 5000.0, "num": n_fz}, "My": -74000.0, "positions": 64}}


@pytest.mark.parametrize("points", [(10, 10), (40, 25)], ids=["100-points", "1000-points"])
@pytest.mark.benchmark(group="ball passage, load-controlled, 64 positions, to HDF5, 2 threads")
def test_passage_load_controlled(benchmark, tmp_path, points):
    fb.passage(config(2, 2), tmp_path / "warm.h5", threads=2)  # compile outside the timing
    counter = iter(range(100))
    out = benchmark.pedantic(lambda: fb.passage(config(*points), tmp_path / f"p{next(counter)}.h5", threads=2),
                             rounds=3)
    assert fb.open_dataset(out)["status"].shape == (*points, 64)
    if not benchmark.disabled:  # --benchmark-disable: a smoke run, no figures
        benchmark.extra_info["solves_per_s"] = points[0] * points[1] * 64 / benchmark.stats.stats.median
