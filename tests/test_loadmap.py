"""Load maps: configs, identity across threads and chunk sizes, agreement with
solve, HDF5/xarray layout, and safety (overwrite, kill and resume, Ctrl-C; memory in bench/)."""

import json
import re
import signal
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import h5py
import numpy as np
import pytest

import fastbearing as fb
from fastbearing.jobs.grid import LINE_SEGMENT, plan_blocks, segment_starts
from fastbearing.jobs.loadmap import loadmap, open_dataset, read_config

ROOT = Path(__file__).resolve().parents[1]
VARIABLES = ("q", "f", "K", "status", "iterations", "residual", "max_ball_load", "loaded_balls",
             "min_contact_angle", "max_contact_angle")
D = np.array([1, 1, 1, 1 / 34.75, 1 / 34.75])


def config(tmp_path, body, bearing='preset = "gunduz2013"\narrangement = "DB"', name="map.toml"):
    path = tmp_path / name
    path.write_text(f"[bearing]\n{bearing}\n\n[loadmap]\n{textwrap.dedent(body)}")
    return path


SMALL = """
given = "load"
Fx = { start = -2000.0, stop = 2000.0, num = 6 }
Fz = { start = 500.0, stop = 10000.0, num = 5 }
My = { start = -1.0e5, stop = 1.0e5, num = 7 }
"""


def read_all(path):
    with h5py.File(path, "r") as fh:
        return {name: fh[name][...] for name in VARIABLES}


def assert_identical(a, b):
    for name in VARIABLES:
        np.testing.assert_array_equal(a[name], b[name], err_msg=name)


# -- configs ------------------------------------------------------------------

@pytest.mark.parametrize("body, words", [
    ("Fx = 1.0\nFoo = 2.0\n", "unknown key 'Foo'"),
    ("Fx = []\n", "loadmap.Fx is an empty list"),
    ("Fx = { start = 0.0, stop = 1.0, num = 0 }\n", r"loadmap.Fx.num must be an integer in \[1, 1e\+07\]"),
    ("Fx = { start = 0.0, stop = 1.0, num = 1000000000000 }\n", r"loadmap.Fx.num must be an integer in \[1, 1e\+07\]"),
    ("Fx = { start = 0.0, stop = 1.0, num = 100000 }\nFz = { start = 0.0, stop = 1.0, num = 100000 }\n"
     "My = { start = 0.0, stop = 1.0, num = 100000 }\n", "1e\\+15 cases is more than one map may hold"),
    ("Fx = true\n", "loadmap.Fx must be a number, got True"),
    ("Fx = { start = 0.0, stop = nan, num = 3 }\n", "loadmap.Fx.stop must be finite"),
    ("Fx = [1.0, inf]\n", r"loadmap.Fx\[1\] must be finite"),
    ("Fx = { start = 0.0, num = 3 }\n", r"missing \['stop'\]"),
    ('given = "force"\n', r"loadmap.given must be one of \['load', 'displacement'\], got 'force'"),
    ('given = "displacement"\nFx = 1.0\n', "loadmap.Fx is not an axis for given = 'displacement'"),
    ("chunk = 0\n", r"loadmap.chunk must be an integer in \[1, 4e\+06\], got 0"),
    ('compression = "zip"\n', "loadmap.compression must be one of"),
    ('method = "secant"\n', "method must be one of"),
    ('cases = "missing.npy"\n', "case file not found"),
    ('cases = "c.npy"\nFx = 1.0\n', r"loadmap.cases replaces the grid axes; remove \['Fx'\]"),
])
def test_bad_configs_are_rejected_before_any_work(tmp_path, body, words):
    np.save(tmp_path / "c.npy", np.ones((3, 5)))
    with pytest.raises(ValueError, match=words):
        read_config(config(tmp_path, body))


def test_bad_bearing_and_tables_in_config(tmp_path):
    with pytest.raises(ValueError, match="bearing.hertz_constant must be > 0"):
        read_config(config(tmp_path, SMALL, bearing='preset = "gunduz2013"\nhertz_constant = -1.0'))
    path = tmp_path / "x.toml"
    path.write_text("[loadmap]\nFx = 1.0\n")
    with pytest.raises(ValueError, match=r"missing the \[bearing\] table"):
        read_config(path)
    path.write_text('[bearing]\npreset = "gunduz2013"\n[loadmap]\n[other]\n')
    with pytest.raises(ValueError, match="unknown top-level key"):
        read_config(path)


@pytest.mark.parametrize("shape, chunk", [((6, 5, 7), 1), ((6, 5, 7), 10), ((6, 5, 7), 35), ((6, 5, 7), 100),
                                          ((6, 5, 7), 10_000), ((4, 9), 20), ((50,), 7)])
def test_blocks_are_hyperslabs_of_whole_lines(shape, chunk):
    line = shape[-1] if len(shape) > 1 else 1
    cover = np.zeros(shape, int)
    flat = np.arange(int(np.prod(shape))).reshape(shape)
    for b in plan_blocks(shape, line, chunk):
        cover[b.slab] += 1
        np.testing.assert_array_equal(flat[b.slab].ravel(), np.arange(b.start, b.stop))
        assert b.size % line == 0 and (b.size <= max(chunk, line))
    assert (cover == 1).all()


@pytest.mark.parametrize("shape, chunk", [((3 * LINE_SEGMENT + 5,), 1), ((3 * LINE_SEGMENT + 5,), LINE_SEGMENT + 1),
                                          ((3 * LINE_SEGMENT + 5,), 2 * LINE_SEGMENT),
                                          ((3, 2 * LINE_SEGMENT + 7), 3 * LINE_SEGMENT),
                                          ((2, 3, LINE_SEGMENT + 1), 100)])
def test_long_lines_split_between_segments(shape, chunk):
    """A line longer than the chunk is cut into blocks, only where continuation restarts anyway."""
    line = shape[-1]
    cover = np.zeros(shape, int)
    flat = np.arange(int(np.prod(shape))).reshape(shape)
    blocks = plan_blocks(shape, line, chunk)
    for b in blocks:
        cover[b.slab] += 1
        np.testing.assert_array_equal(flat[b.slab].ravel(), np.arange(b.start, b.stop))
        assert b.start % line % LINE_SEGMENT == 0 and (b.stop % line == 0 or b.stop % line % LINE_SEGMENT == 0)
        assert b.size <= max(chunk, LINE_SEGMENT)
    assert (cover == 1).all() and len(blocks) > 1
    # segments: every line start and every LINE_SEGMENT cases along a line, whatever the block cut
    starts = np.concatenate([b.start + segment_starts(b.start, b.stop, line)[:-1] for b in blocks])
    expect = [i for i in range(int(np.prod(shape))) if i % line % LINE_SEGMENT == 0]
    np.testing.assert_array_equal(starts, expect)


# -- results ------------------------------------------------------------------

@pytest.fixture(scope="module")
def small_map(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("map")
    return loadmap(config(tmp, SMALL), tmp / "map.h5", progress=False)


def test_identical_for_any_thread_count_and_chunk_size(tmp_path, small_map):
    reference = read_all(small_map)
    for threads, chunk in ((1, 1), (2, 7), (1, 35), (2, 64), (2, 100_000)):
        out = loadmap(config(tmp_path, SMALL + f"chunk = {chunk}\n"), tmp_path / f"m{threads}-{chunk}.h5",
                      threads=threads, progress=False)
        assert_identical(read_all(out), reference)


LONG_LINE = f"""
given = "load"
Fz = {{ start = 500.0, stop = 10000.0, num = {2 * LINE_SEGMENT + 100} }}
Fx = 300.0
My = -2.0e4
"""


def test_long_lines_identical_for_any_chunk_and_thread_count(tmp_path):
    """A 1-D line longer than LINE_SEGMENT, cut into blocks of several sizes: bit for bit the same."""
    results = []
    for threads, chunk in ((1, 1_000_000), (2, 1), (1, LINE_SEGMENT), (2, LINE_SEGMENT + 3), (2, 2 * LINE_SEGMENT)):
        out = loadmap(config(tmp_path, LONG_LINE + f"chunk = {chunk}\n"), tmp_path / f"l{threads}-{chunk}.h5",
                      threads=threads, progress=False)
        with h5py.File(out, "r") as fh:
            assert fh.attrs["n_blocks"] == (1 if chunk == 1_000_000 else 3 if chunk < 2 * LINE_SEGMENT else 2)
        results.append(read_all(out))
    for r in results[1:]:
        assert_identical(r, results[0])
    assert (results[0]["status"] == 0).all()
    # continuation restarts cold at each segment, so a segment's first case takes more iterations
    it = results[0]["iterations"]
    assert it[LINE_SEGMENT] > np.median(it) and it[2 * LINE_SEGMENT] > np.median(it)


def test_cases_agree_with_solve(small_map):
    data = read_all(small_map)
    with h5py.File(small_map, "r") as fh:
        Fx, Fz, My = fh["Fx"][...], fh["Fz"][...], fh["My"][...]
    bearing = fb.Bearing.preset("gunduz2013", "DB")
    assert (data["status"] == 0).all()
    rng = np.random.default_rng(3)
    for _ in range(12):
        i, j, k = rng.integers(0, 6), rng.integers(0, 5), rng.integers(0, 7)
        r = fb.solve(bearing, [Fx[i], 0.0, Fz[j], 0.0, My[k]])
        np.testing.assert_allclose(data["q"][i, j, k], r.q, rtol=1e-9, atol=1e-9 * np.abs(r.q).max())
        np.testing.assert_allclose(data["K"][i, j, k], r.K, rtol=1e-9, atol=1e-9 * np.abs(r.K).max())
        Q, alpha = fb.ball_loads(bearing, data["q"][i, j, k])
        assert data["max_ball_load"][i, j, k, 0] == pytest.approx(Q[:14].max(), rel=1e-12)
        assert data["loaded_balls"][i, j, k, 1] == (Q[14:] > 0).sum()


def test_continuation_saves_iterations(small_map):
    it = read_all(small_map)["iterations"]
    assert it[..., 1:].mean() < it[..., 0].mean()


def test_displacement_map_equals_stiffness_many(tmp_path):
    out = loadmap(config(tmp_path, """
        given = "displacement"
        dx = { start = -0.02, stop = 0.02, num = 5 }
        dz = [0.0, 0.01, 0.03]
        by = 0.0005
    """), progress=False)
    data = read_all(out)
    dx, dz = np.meshgrid(np.linspace(-0.02, 0.02, 5), [0.0, 0.01, 0.03], indexing="ij")
    q = np.column_stack([dx.ravel(), 0 * dx.ravel(), dz.ravel(), 0 * dx.ravel(), 0.0005 + 0 * dx.ravel()])
    f, K = fb.stiffness_many(fb.Bearing.preset("gunduz2013", "DB"), q)
    np.testing.assert_array_equal(data["K"].reshape(-1, 5, 5), K)
    np.testing.assert_array_equal(data["f"].reshape(-1, 5), f)


@pytest.mark.parametrize("suffix", [".npy", ".csv", ".h5"])
def test_case_files(tmp_path, suffix):
    rng = np.random.default_rng(5)
    cases = np.column_stack([rng.uniform(-2000, 2000, 20), rng.uniform(-2000, 2000, 20),
                             rng.uniform(500, 5000, 20), rng.uniform(-5e4, 5e4, 20), rng.uniform(-5e4, 5e4, 20)])
    path = tmp_path / f"cases{suffix}"
    if suffix == ".npy":
        np.save(path, cases)
    elif suffix == ".csv":
        np.savetxt(path, cases, delimiter=",", header="Fx,Fy,Fz,Mx,My", comments="")
    else:
        with h5py.File(path, "w") as fh:
            fh["cases"] = cases
    out = loadmap(config(tmp_path, f'cases = "{path.name}"\nchunk = 6\n'), progress=False)
    data = read_all(out)
    ref = fb.solve_many(fb.Bearing.preset("gunduz2013", "DB"), cases)
    np.testing.assert_array_equal(data["q"], ref.q)
    ds = open_dataset(out)
    np.testing.assert_array_equal(ds["Fx"].values, cases[:, 0])


def test_a_case_file_names_the_column_that_is_not_finite(tmp_path):
    """A NaN in the speed column is named as the speed (issue 33), as one in a load column is named so."""
    from fastbearing.jobs.grid import read_case_file

    cases = np.array([[1000.0, 0, 2000.0, 0, 0, 3000.0], [1000.0, 0, 2000.0, 0, 0, np.nan]])
    path = tmp_path / "cases.csv"
    np.savetxt(path, cases, delimiter=",", header="Fx,Fy,Fz,Mx,My,speed", comments="")
    with pytest.raises(ValueError, match=r"case 1 column 5 \(speed \(rpm\)\) is not finite \(nan\)"):
        read_case_file(path, "loadmap.cases")
    cases[1, 5], cases[0, 2] = 0.0, np.inf
    np.savetxt(path, cases, delimiter=",")
    with pytest.raises(ValueError, match=r"case 0 column 2 \(Fz or dz \(N or mm\)\) is not finite \(inf\)"):
        read_case_file(path, "loadmap.cases")


def test_xarray_layout_units_and_provenance(small_map):
    ds = open_dataset(small_map)
    K = ds["K"].sel(Fx=-1200.0, Fz=500.0, My=1.0e5 / 3, method="nearest")
    assert K.shape == (5, 5)
    assert float(ds["Fy"]) == 0.0 and list(ds["dof"].values) == ["x", "y", "z", "tx", "ty"]
    for name in (*VARIABLES, "Fx", "Fz", "My", "Fy", "Mx"):
        assert ds[name].attrs["units"] and ds[name].attrs["long_name"], name
    assert ds["Fx"].attrs["units"] == "N" and ds["My"].attrs["units"] == "N*mm"
    # one units string each (CF); Kb's, q's and f's entries that differ say so in units_per_entry
    assert ds["K"].attrs["units"] == "N/mm" and ds["q"].attrs["units"] == "mm" and ds["f"].attrs["units"] == "N"
    per_entry = np.array(ds["K"].attrs["units_per_entry"]).reshape(5, 5)   # row-major over (dof, dof_col)
    assert per_entry[0, 2] == "N/mm" and per_entry[3, 4] == "N*mm/rad" and per_entry[1, 3] == per_entry[4, 0] == "N/rad"
    assert list(ds["q"].attrs["units_per_entry"]) == ["mm", "mm", "mm", "rad", "rad"]
    assert list(ds["f"].attrs["units_per_entry"]) == ["N", "N", "N", "N*mm", "N*mm"]
    for key in ("fastbearing_version", "numba_version", "h5py_version", "config", "bearing", "solver_rtol",
                "created"):
        assert key in ds.attrs
    assert json.loads(ds.attrs["status_counts"]) == {"converged": 210}
    # the status key names every outcome the solver can return (CF flag_values / flag_meanings)
    from fastbearing import status as st
    meanings = ds["status"].attrs["flag_meanings"].split()
    assert dict(zip(ds["status"].attrs["flag_values"].tolist(), meanings)) == st.NAMES


@pytest.mark.parametrize("compression", ["lzf", "gzip"])
def test_compression_keeps_values(tmp_path, small_map, compression, capsys):
    out = loadmap(config(tmp_path, SMALL + f'compression = "{compression}"\nchunk = 35\n'), progress=False)
    # the summary tells the repack apart from the computing and gives the total
    assert re.search(rf"[\d.]+ s computing \+ [\d.]+ s {compression} repack = [\d.]+ s wall", capsys.readouterr().err)
    assert_identical(read_all(out), read_all(small_map))
    with h5py.File(out, "r") as fh:
        assert fh["K"].compression == compression
    assert open_dataset(out)["K"].shape == (6, 5, 7, 5, 5)
    assert not Path(str(out) + ".part").exists()


# -- safety ---------------------------------------------------------------------

def test_never_overwrites_without_being_told(tmp_path):
    cfg = config(tmp_path, SMALL)
    out = loadmap(cfg, progress=False)
    stamp = out.stat().st_mtime_ns
    with pytest.raises(ValueError, match="exists; pass overwrite=True"):
        loadmap(cfg, progress=False)
    assert out.stat().st_mtime_ns == stamp
    loadmap(cfg, overwrite=True, progress=False)
    (tmp_path / "map.h5.part").write_bytes(b"unfinished")
    with pytest.raises(ValueError, match="an unfinished run exists"):
        loadmap(cfg, tmp_path / "map.h5", progress=False)
    with pytest.raises(ValueError, match="not a readable partial run"):
        loadmap(cfg, resume=True, progress=False)


def test_unfinished_file_is_never_taken_for_finished(tmp_path):
    (tmp_path / "x.h5").write_bytes(b"")
    with pytest.raises(ValueError, match="not a finished fastbearing file"):
        open_dataset(tmp_path / "x.h5")


KILL_MAP = """
given = "load"
Fx = { start = -2000.0, stop = 2000.0, num = 60 }
Fz = { start = 500.0, stop = 10000.0, num = 40 }
My = { start = -1.0e5, stop = 1.0e5, num = 50 }
chunk = 2000
"""


def blocks_done(part):
    try:
        with h5py.File(part, "r", locking=False) as fh:
            return int(fh["block_done"][...].sum()), len(fh["block_done"])
    except (OSError, KeyError):
        return 0, 1


def start_cli(cfg, out):
    return subprocess.Popen([sys.executable, "-m", "fastbearing.cli", "loadmap", str(cfg), "-o", str(out),
                             "--threads", "1"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def wait_for_blocks(part, proc, at_least=3):
    deadline = time.time() + 120
    while time.time() < deadline and proc.poll() is None:
        done, total = blocks_done(part)
        if done >= at_least:
            return done, total
        time.sleep(0.02)
    pytest.fail(f"the run ended or stalled before {at_least} blocks were done")


def test_sigkill_then_resume_is_identical_to_uninterrupted(tmp_path):
    cfg = config(tmp_path, KILL_MAP)
    reference = loadmap(cfg, tmp_path / "reference.h5", progress=False)
    out, part = tmp_path / "killed.h5", tmp_path / "killed.h5.part"
    proc = start_cli(cfg, out)
    done, total = wait_for_blocks(part, proc)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    assert not out.exists() and part.exists()
    finished, total = blocks_done(part)
    assert 0 < finished < total
    with pytest.raises(ValueError, match="an unfinished run exists"):
        loadmap(cfg, out, progress=False)
    resumed = subprocess.run([sys.executable, "-m", "fastbearing.cli", "loadmap", str(cfg), "-o", str(out),
                              "--resume"], capture_output=True, text=True, timeout=300)
    assert resumed.returncode == 0, resumed.stderr
    assert_identical(read_all(out), read_all(reference))
    assert not part.exists()
    # the resumed run computed only what was missing
    rate_line = resumed.stderr.strip().splitlines()[-1]
    assert "100.00 % converged" in rate_line


HARD_MAP = """
Fx = { start = -1.0, stop = 1.0, num = 40 }
Fz = { start = -1.0, stop = 1.0, num = 40 }
My = { start = -30.0, stop = 30.0, num = 200 }
chunk = 400000
"""
HARD_BEARING = 'preset = "gunduz2013"\narrangement = "single"\nradial_clearance = 0.01'


@pytest.mark.parametrize("threads", [1, 2])
def test_ctrl_c_stops_inside_a_long_block(tmp_path, threads):
    """Loads of about 1 N on a single row with clearance, all in one block of about two seconds: a real
    SIGINT stops the sweep inside the block (cases of it are left uncomputed), not after it, and the cut
    block is not kept as done; on two threads too (the second is a pool thread that reads the same flag).
    How fast it stops is measured in bench/test_jobs.py, not asserted here."""
    import dataclasses
    import importlib

    from fastbearing.jobs import runner as jobs

    loadmap(config(tmp_path, "Fx = [0.5, 1.0]\nFz = 0.5\n", bearing=HARD_BEARING), tmp_path / "warm.h5",
            progress=False)  # compiled first: the signal must find the sweep running
    module = importlib.import_module("fastbearing.jobs.loadmap")
    job = module.job(read_config(config(tmp_path, HARD_MAP, bearing=HARD_BEARING)))
    left = []

    def compute(inputs, res, first, stop):
        res["status"][...] = -1                   # not a status: marks cases the sweep never reached
        job.compute(inputs, res, first, stop)
        left.append(int((res["status"] == -1).sum()))

    timer = threading.Timer(0.5, signal.raise_signal, (signal.SIGINT,))
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        # the block takes about 1.8 s here on one thread (0.9 s on two), well past the signal at 0.5 s
        jobs.run(dataclasses.replace(job, compute=compute), tmp_path / "hard.h5", progress=False, threads=threads)
    timer.join()
    assert len(left) == 1 and 0 < left[0] < job.cases.n_cases, left   # stopped part way through the block
    with h5py.File(tmp_path / "hard.h5.part", "r") as fh:
        assert fh["block_done"][...].tolist() == [0]     # the cut block is not kept as done


def test_ctrl_c_stops_quickly_and_leaves_a_resumable_file(tmp_path):
    cfg = config(tmp_path, KILL_MAP)
    out, part = tmp_path / "int.h5", tmp_path / "int.h5.part"
    proc = start_cli(cfg, out)
    wait_for_blocks(part, proc, at_least=2)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)     # how fast it stops is measured in bench/test_jobs.py
    assert proc.returncode == 130 and "--resume" in err and "Traceback" not in err
    assert not out.exists()
    loadmap(cfg, out, resume=True, progress=False)
    assert open_dataset(out)["status"].size == 60 * 40 * 50


def test_curved_predictors_are_one_and_two_orders_better_than_the_tangent():
    """Along a line of loads the map starts each case from its neighbours: the tangent start's error
    falls as h^2 with the load step h, the parabola's (sweep.curved_predictor without the earlier slope)
    as h^3 and the cubic's (with the slope the previous case's tangent step gives) as h^4. Where every ball
    stays loaded (q(F) smooth; a ball entering contact is where all lose an order)."""
    from fastbearing.engine.sweep import PREDICTOR_ROWS, curved_predictor, tangent_predictor

    bearing = fb.Bearing.preset("gunduz2013", "single")
    base, line = np.array([300.0, 0.0, 5000.0, 0.0, -2000.0]), np.array([0.0, 0.0, 0.0, 0.0, 1.0])
    errors = {"tangent": [], "parabola": [], "cubic": []}
    scratch = np.empty((PREDICTOR_ROWS, 5))
    for h in (4000.0, 2000.0, 1000.0, 500.0):
        loads = [base + k * h * line for k in range(3)]
        solved = [fb.solve(bearing, F, rtol=1e-13) for F in loads]
        assert all((fb.ball_loads(bearing, r.q)[0] > 0).all() for r in solved)
        q, slope = np.empty(5), np.empty(5)
        assert tangent_predictor(True, loads[1], solved[0].q, solved[0].f, solved[0].K, slope, scratch, 0)
        slope -= solved[0].q  # the tangent step case 1 took from case 0
        assert tangent_predictor(True, loads[2], solved[1].q, solved[1].f, solved[1].K, q, scratch, 0)
        errors["tangent"].append(np.abs((q - solved[2].q) * D).max())
        for name, known in (("parabola", False), ("cubic", True)):
            bent = q.copy()
            curved_predictor(loads[2], loads[1], loads[0], solved[1].q, solved[0].q, bent, slope, known)
            errors[name].append(np.abs((bent - solved[2].q) * D).max())
    rates = {name: np.log2(np.array(e[:-1]) / np.array(e[1:])) for name, e in errors.items()}
    assert (np.abs(rates["tangent"] - 2.0) < 0.35).all(), rates
    assert (np.abs(rates["parabola"][1:] - 3.0) < 0.35).all(), rates
    assert (np.abs(rates["cubic"][1:] - 4.0) < 0.45).all(), rates
    assert errors["parabola"][-1] < 0.05 * errors["tangent"][-1]
    assert errors["cubic"][-1] < 0.2 * errors["parabola"][-1]


def test_row_summary_against_numpy():
    """sweep.row_summary (the map's per-row max ball load, loaded count, contact angle range) against numpy
    over random records: rows consecutive or interleaved, unloaded balls, a row with none loaded, nan."""
    from fastbearing.engine.sweep import row_summary

    rng = np.random.default_rng(7)
    for trial in range(200):
        n_rows = int(rng.integers(1, 4))
        rows = np.sort(rng.integers(0, n_rows, 30)) if trial % 2 else rng.integers(0, n_rows, 30)
        load = np.where(rng.random(30) < 0.5, rng.uniform(0.0, 900.0, 30), 0.0)
        load[rows == n_rows - 1] *= trial % 3 != 0  # every third trial: the last row carries nothing
        angle = rng.uniform(-1.0, 1.0, 30)
        if trial % 7 == 0:
            load[int(rng.integers(0, 30))] = np.nan
        out = np.empty(n_rows), np.empty(n_rows, np.int64), np.empty(n_rows), np.empty(n_rows)
        row_summary(load, angle, rows.astype(np.int64), *out)
        for r in range(n_rows):
            mine, on = load[rows == r], (load > 0) & (rows == r)
            assert np.array_equal(out[0][r], np.nan if np.isnan(mine).any() else max(mine.max(initial=0.0), 0.0),
                                  equal_nan=True)
            assert out[1][r] == on.sum()
            assert np.array_equal(out[2][r], angle[on].min() if on.any() else np.nan, equal_nan=True)
            assert np.array_equal(out[3][r], angle[on].max() if on.any() else np.nan, equal_nan=True)
