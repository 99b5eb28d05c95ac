"""Zarr v3 stores (jobs/zarr_store.py): the HDF5 file's twin value for value, resumable, sharded when large,
at fsspec URLs, read by open_map, export and plot; bad locations and missing extras are one line.
The Dask side (workers writing their own blocks) is in test_distributed.py."""

import json
import os

import numpy as np
import pytest

import fastbearing as fb

zarr = pytest.importorskip("zarr")
xr = pytest.importorskip("xarray")

from fastbearing.jobs import zarr_store  # noqa: E402

from pathlib import Path  # noqa: E402

#: A bearing with geometry, so that the map carries the life variables too.
BEARING = str(Path(__file__).resolve().parents[1] / "fastbearing" / "catalogue" / "7014C-DB.toml")
CONFIG = {"bearing": BEARING,
          "loadmap": {"Fx": {"start": -2000.0, "stop": 2000.0, "num": 12}, "Fz": {"start": 500.0, "stop": 10000.0,
                      "num": 10}, "My": {"start": -1.0e5, "stop": 1.0e5, "num": 33}, "chunk": 600, "life": True}}
#: Attributes that say when and how fast a file was made, or how a store is chunked: not the results.
PROVENANCE = {"created", "completed", "wall_time_s", "compile_time_s", "zarr_chunk", "zarr_shard", "zarr_tasks",
              zarr_store.RUN_ID}


def _values(a):
    if a.dtype.kind not in "biufc":               # dof labels: HDF5 gives objects, zarr numpy's StringDType
        return np.array([str(x) for x in a.tolist()])
    return a


def _same_attr(a, b) -> bool:
    """Equal as values: text as text, numbers as numbers (nan equal to nan), HDF5's arrays as zarr's lists."""
    if isinstance(a, (str, bytes)) or isinstance(b, (str, bytes)):
        return isinstance(a, str) and isinstance(b, str) and a == b
    if any(isinstance(x, str) for x in np.asarray(a, dtype=object).ravel()):   # units_per_entry: lists of text
        return [str(x) for x in np.asarray(a).ravel()] == [str(x) for x in np.asarray(b).ravel()]
    return np.array_equal(np.asarray(a, dtype=float), np.asarray(b, dtype=float), equal_nan=True)


def assert_same_dataset(h5, store, ignore=()):
    """Every variable and coordinate (values, dims, dtype, attributes) and every file attribute but the
    provenance times equal between an HDF5 file and a zarr store."""
    a, b = fb.open_map(h5), fb.open_map(store)
    assert set(a.variables) == set(b.variables)
    for name in a.variables:
        va, vb = a[name], b[name]
        assert va.dims == vb.dims, name
        if va.dtype.kind in "biufc":
            assert va.dtype == vb.dtype, name
        np.testing.assert_array_equal(_values(va.values), _values(vb.values), err_msg=name)
        assert set(va.attrs) == set(vb.attrs), name
        for k in va.attrs:
            assert _same_attr(va.attrs[k], vb.attrs[k]), (name, k)
    keys = (set(a.attrs) | set(b.attrs)) - PROVENANCE - set(ignore)
    for k in keys:
        assert k in a.attrs and k in b.attrs, k
        assert _same_attr(a.attrs[k], b.attrs[k]), k


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    return fb.loadmap(CONFIG, tmp_path_factory.mktemp("h5") / "map.h5", progress=False)


def test_zarr_map_equals_hdf5_map(reference, tmp_path):
    out = fb.loadmap(CONFIG, tmp_path / "map.zarr", progress=False)
    assert out == (tmp_path / "map.zarr").absolute()
    assert_same_dataset(reference, out)
    ds = xr.open_zarr(out)                         # the plain xarray call users know
    assert ds["K"].attrs["units"].startswith("N/mm") and ds.attrs["fastbearing_complete"] == 1
    assert json.loads(ds.attrs["status_counts"])
    assert zarr_store.BOOKKEEPING not in zarr.open_group(str(out), mode="r")   # dropped when finished
    assert ds["K"].encoding["chunks"][:3] == (1, 10, 33)       # one chunk per block along the cases


def test_passage_table_to_zarr_equals_hdf5(tmp_path):
    table = {"bearing": BEARING, "passage": {"given": "load", "Fx": [200.0, 3000.0], "Fz": [500.0, 2000.0],
             "positions": 16, "speed": 6000.0, "chunk": 2}}
    h5 = fb.passage(table, tmp_path / "t.h5", progress=False)
    store = fb.passage(table, tmp_path / "t.zarr", progress=False)
    assert_same_dataset(h5, store)


def test_a_large_map_is_sharded_and_unchanged(reference, tmp_path, monkeypatch):
    """Beyond MAX_UNSHARDED_BLOCKS blocks, consecutive blocks share one shard (one object per shard and
    variable) and a shard is the unit of work: fewer objects, the same values."""
    monkeypatch.setattr(zarr_store, "MAX_UNSHARDED_BLOCKS", 3)
    out = fb.loadmap(CONFIG, tmp_path / "sharded.zarr", progress=False)
    assert_same_dataset(reference, out, ignore=("n_blocks",))
    ds = fb.open_map(out)
    # 12 blocks of one Fx value each; shards of 4 blocks: 3 units of work, 3 objects per variable
    assert ds.attrs["zarr_chunk"] == [1, 10, 33] and ds.attrs["zarr_shard"] == [4, 10, 33]
    assert int(ds.attrs["n_blocks"]) == 3
    assert len([p for p in (out / "K" / "c").rglob("*") if p.is_file()]) == 3


def test_interrupted_run_resumes_to_the_same_store(reference, tmp_path, capsys):
    """Ctrl-C after 3 blocks leaves the store unfinished (refused by readers and by a second run without
    --resume); --resume computes only the rest and gives the uninterrupted store; a finished store is
    not replaced untold."""
    from conftest import interrupted_after

    from fastbearing.jobs import loadmap as lm
    from fastbearing.jobs import runner

    out = tmp_path / "resumed.zarr"
    with pytest.raises(KeyboardInterrupt):
        runner.run(interrupted_after(lm.job(lm.read_config(CONFIG)), 3), out, progress=False)
    assert "continue with --resume" in capsys.readouterr().err
    with pytest.raises(ValueError, match="not a finished"):
        fb.open_map(out)
    with pytest.raises(ValueError, match="unfinished run exists"):
        fb.loadmap(CONFIG, out, progress=False)
    fb.loadmap(CONFIG, out, progress=False, resume=True)
    assert "the rest resumed" in capsys.readouterr().err
    assert_same_dataset(reference, out)
    with pytest.raises(ValueError, match="exists; pass overwrite=True"):
        fb.loadmap(CONFIG, out, progress=False)
    fb.loadmap(CONFIG, out, progress=False, resume=True)
    assert "already complete" in capsys.readouterr().err
    other = {**CONFIG, "loadmap": {**CONFIG["loadmap"], "chunk": 700}}
    with pytest.raises(ValueError, match="different config"):
        fb.loadmap(other, out, progress=False, resume=True)
    fb.loadmap(other, out, progress=False, overwrite=True)
    assert int(fb.open_map(out).attrs["chunk"]) == 700


@pytest.mark.parametrize("step", ["delete", "consolidate_metadata", "mark"])
def test_a_finish_cut_off_is_completed_by_resume(reference, tmp_path, monkeypatch, step):
    """Killed inside finish (before dropping the bookkeeping, before consolidating, before the mark): the store
    stays unfinished and --resume finishes it without computing a block again."""
    import zarr.core.group as zgroup

    out = tmp_path / "cut.zarr"

    def killed(*args, **kwargs):
        raise KeyboardInterrupt

    if step == "delete":
        monkeypatch.setattr(zgroup.Group, "__delitem__", killed)
    elif step == "consolidate_metadata":
        monkeypatch.setattr(zarr, "consolidate_metadata", killed)
    else:
        monkeypatch.setattr(zarr_store, "datetime", None)     # the mark's timestamp: the last step fails
    with pytest.raises((KeyboardInterrupt, AttributeError)):
        fb.loadmap(CONFIG, out, progress=False)
    monkeypatch.undo()
    assert not zarr_store.is_complete(out)
    with pytest.raises(ValueError, match="not a finished"):
        fb.open_map(out)
    fb.loadmap(CONFIG, out, progress=False, resume=True)
    assert_same_dataset(reference, out)


def test_a_store_cut_off_while_created_is_replaced_by_overwrite(tmp_path):
    """The root is written with its identity in one object: a store killed right after it is this program's
    (refused by --resume, replaced by --overwrite)."""
    from fastbearing.jobs import loadmap as lm
    from fastbearing.jobs import runner

    out = tmp_path / "cut.zarr"
    job = lm.job(lm.read_config(CONFIG))
    store = zarr_store.ZarrStore(out)

    def killed(*args, **kwargs):
        raise KeyboardInterrupt

    original = zarr.Group.create_array
    zarr.Group.create_array = killed
    try:
        with pytest.raises(KeyboardInterrupt):
            runner.run(job, out, progress=False)
    finally:
        zarr.Group.create_array = original
    assert store.unfinished()
    with pytest.raises(ValueError, match="cut off while being created"):
        fb.loadmap(CONFIG, out, progress=False, resume=True)
    fb.loadmap(CONFIG, out, progress=False, overwrite=True)
    assert zarr_store.is_complete(out)


def test_a_worker_writes_only_into_its_own_runs_store(tmp_path):
    """A block sent for one run (a task still running after Ctrl-C, a worker that sees another store of the same
    name) is refused once the store there is another run's: one line, nothing written."""
    from fastbearing.jobs import loadmap as lm
    from fastbearing.jobs import runner
    from fastbearing.jobs.grid import plan_blocks

    out = tmp_path / "m.zarr"
    fb.loadmap(CONFIG, out, progress=False)
    job = lm.job(lm.read_config(CONFIG))
    block = plan_blocks(job.cases.shape, job.line_length, job.chunk)[0]
    stale = {"where": str(out), "run_id": "an earlier run"}
    res = runner.storage.allocate(list(job.variables), job.sizes, block.size)
    with pytest.raises(ValueError, match=r"cannot write block 0 into .*not this run's") as err:
        zarr_store.write_on_worker(stale, block, res)
    assert "\n" not in str(err.value)


def test_resume_refuses_a_store_cut_otherwise(tmp_path, monkeypatch):
    """The store's chunks and shards are checked on --resume: a version that cuts the same config otherwise
    would record other blocks."""
    from conftest import interrupted_after

    from fastbearing.jobs import loadmap as lm
    from fastbearing.jobs import runner

    out = tmp_path / "r.zarr"
    with pytest.raises(KeyboardInterrupt):
        runner.run(interrupted_after(lm.job(lm.read_config(CONFIG)), 2), out, progress=False)
    monkeypatch.setattr(zarr_store, "MAX_UNSHARDED_BLOCKS", 3)
    with pytest.raises(ValueError, match="cut into chunks and shards otherwise"):
        fb.loadmap(CONFIG, out, progress=False, resume=True)


def test_an_fsspec_url_is_a_store(reference, tmp_path):
    """Any fsspec URL: fsspec's in-memory file system stands in for s3:// or gcs:// here (the same FsspecStore
    path, the lock as an object beside the store); file:// is the local path."""
    url = "memory://fastbearing-test/map.zarr"
    out = fb.loadmap(CONFIG, url, progress=False)
    assert out == url
    assert_same_dataset(reference, url)
    import fsspec

    assert not fsspec.filesystem("memory").exists("/fastbearing-test/map.zarr.lock")
    with pytest.raises(ValueError, match="^memory://fastbearing-test/map.zarr exists; pass overwrite=True"):
        fb.loadmap(CONFIG, url, progress=False)
    local = (tmp_path / "url.zarr").absolute()
    assert fb.loadmap(CONFIG, local.as_uri(), progress=False) == local
    assert_same_dataset(reference, local)


def test_export_and_plot_read_a_store(reference, tmp_path):
    from conftest import cli_run

    store = fb.loadmap(CONFIG, tmp_path / "m.zarr", progress=False)
    for src, name in ((reference, "h5.csv"), (store, "zarr.csv")):
        r = cli_run("export", src, "--format", "csv", "-o", tmp_path / name)
        assert r.returncode == 0, r.stderr
    assert (tmp_path / "h5.csv").read_text() == (tmp_path / "zarr.csv").read_text()
    pytest.importorskip("matplotlib")
    r = cli_run("plot", "map", store, "--var", "kzz", "--x", "Fz", "--y", "My", "--at", "Fx=0", "-o", tmp_path / "kzz.png")
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "kzz.png").stat().st_size > 1000


def test_cli_format_option(tmp_path):
    from conftest import cli_run

    cfg = tmp_path / "small.toml"
    cfg.write_text('[bearing]\npreset = "gunduz2013"\narrangement = "DB"\n[loadmap]\nFx = [500.0, 1000.0]\n'
                   "Fz = { start = 500.0, stop = 3000.0, num = 4 }\n")
    r = cli_run("loadmap", cfg, "--format", "zarr", "--no-progress", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert zarr_store.is_complete(tmp_path / "small.zarr")
    r = cli_run("loadmap", cfg, "--format", "zarr", "-o", tmp_path / "x.h5")
    assert r.returncode == 2 and "does not match" in r.stderr


@pytest.mark.parametrize("where, said", [
    ("missing/folder/m.zarr", "does not exist"),
    ("nosuchprotocol://bucket/m.zarr", "not a location fsspec knows"),
    ("memory://bucket/m.h5", "a URL output is written as a zarr store"),
])
def test_bad_locations_are_one_line(tmp_path, where, said):
    from conftest import cli_run

    cfg = tmp_path / "small.toml"
    cfg.write_text('[bearing]\npreset = "gunduz2013"\narrangement = "DB"\n[loadmap]\nFx = [500.0, 1000.0]\n')
    r = cli_run("loadmap", cfg, "-o", where, cwd=tmp_path)
    assert r.returncode == 2 and said in r.stderr and len(r.stderr.strip().splitlines()) == 1, r.stderr


def test_a_missing_cloud_driver_is_one_line(tmp_path):
    try:
        import s3fs  # noqa: F401
        pytest.skip("s3fs is installed here")
    except ImportError:
        pass
    with pytest.raises(ValueError, match="s3fs") as err:
        fb.loadmap(CONFIG, "s3://some-bucket/map.zarr", progress=False)
    assert "\n" not in str(err.value)


def test_what_a_store_refuses(tmp_path, monkeypatch):
    lzf = {**CONFIG, "loadmap": {**CONFIG["loadmap"], "compression": "lzf"}}
    with pytest.raises(ValueError, match="HDF5's; a zarr store takes one of none, gzip, zstd"):
        fb.loadmap(lzf, tmp_path / "m.zarr", progress=False)
    zstd = {**CONFIG, "loadmap": {**CONFIG["loadmap"], "compression": "zstd"}}
    with pytest.raises(ValueError, match="for zarr stores; an HDF5 file takes"):
        fb.loadmap(zstd, tmp_path / "m.h5", progress=False)
    (tmp_path / "plain.zarr").mkdir()
    (tmp_path / "plain.zarr" / "mine.txt").write_text("a user's folder")
    with pytest.raises(ValueError, match="not a fastbearing zarr store"):
        fb.loadmap(CONFIG, tmp_path / "plain.zarr", progress=False, overwrite=True)
    assert (tmp_path / "plain.zarr" / "mine.txt").exists()
    monkeypatch.setitem(__import__("sys").modules, "zarr", None)
    with pytest.raises(ValueError, match=r"pip install 'fastbearing\[zarr\]'"):
        fb.loadmap(CONFIG, tmp_path / "n.zarr", progress=False)


def test_compressed_store_equals(reference, tmp_path):
    small = {**CONFIG, "loadmap": {**CONFIG["loadmap"], "compression": "zstd"}}
    out = fb.loadmap(small, tmp_path / "z.zarr", progress=False)
    a, b = fb.open_map(reference), fb.open_map(out)
    for name in ("q", "K", "status", "L10r"):
        np.testing.assert_array_equal(a[name].values, b[name].values)


@pytest.mark.parametrize("suffix", [".h5", ".zarr"])
def test_only_some_variables_in_float32(reference, tmp_path, suffix):
    """``variables = ["K"]`` and ``dtype = "float32"``: the file keeps K (and status, always) in float32, equal
    to the full map's values rounded to float32, and is a third of the size; unknown names are refused."""
    small = {**CONFIG, "loadmap": {**CONFIG["loadmap"], "variables": ["K"], "dtype": "float32"}}
    out = fb.loadmap(small, tmp_path / f"k{suffix}", progress=False)
    ds, full = fb.open_map(out), fb.open_map(reference)
    assert set(ds.data_vars) == {"K", "status"}
    assert ds["K"].dtype == np.float32 and ds.attrs["result_dtype"] == "float32"
    assert ds.attrs["stored_variables"] == "K, status"
    np.testing.assert_array_equal(ds["K"].values, full["K"].values.astype(np.float32))
    np.testing.assert_array_equal(ds["status"].values, full["status"].values)
    bad = {**CONFIG, "loadmap": {**CONFIG["loadmap"], "variables": ["K", "Kxx"]}}
    with pytest.raises(ValueError, match="'Kxx' is not .*variables of this map; it has q, f, K"):
        fb.loadmap(bad, tmp_path / f"bad{suffix}", progress=False)
    with pytest.raises(ValueError, match="loadmap.dtype"):
        fb.loadmap({**CONFIG, "loadmap": {**CONFIG["loadmap"], "dtype": "float16"}}, tmp_path / f"b{suffix}",
                   progress=False)


def test_blocks_not_recorded_are_never_finished(tmp_path, monkeypatch):
    """Blocks that no writer recorded (workers that wrote elsewhere) leave the store unfinished, said in one line."""
    monkeypatch.setattr(zarr_store.ZarrPart, "write_block", lambda self, block, arrays: None)
    out = tmp_path / "lost.zarr"
    with pytest.raises(ValueError, match=r"12 blocks were not recorded in .*lost.zarr; nothing was marked finished"):
        fb.loadmap(CONFIG, out, progress=False)
    assert not zarr_store.is_complete(out)
