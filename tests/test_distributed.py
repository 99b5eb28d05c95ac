"""Jobs on a Dask LocalCluster: load maps and passage tables identical to a local run bit for bit, also
when a worker is killed mid-run, and resumable."""

import importlib
import importlib.util
import os
import signal
import threading
import time

import h5py
import numpy as np
import pytest

import fastbearing as fb

distributed = pytest.importorskip("distributed")

VARIABLES = ("q", "f", "K", "status", "iterations", "residual", "max_ball_load", "loaded_balls",
             "min_contact_angle", "max_contact_angle")
CONFIG = {"bearing": {"preset": "gunduz2013", "arrangement": "DB"},
          "loadmap": {"Fx": {"start": -2000.0, "stop": 2000.0, "num": 24}, "Fz": {"start": 500.0, "stop": 10000.0,
                      "num": 30}, "My": {"start": -1.0e5, "stop": 1.0e5, "num": 99}, "chunk": 3000}}


@pytest.fixture(scope="module")
def client():
    from fastbearing.jobs.distributed import client_for

    client, cluster = client_for("local:2")
    yield client
    client.close()
    cluster.close()


@pytest.fixture(scope="module")
def local_map(tmp_path_factory):
    return fb.loadmap(CONFIG, tmp_path_factory.mktemp("local") / "local.h5", progress=False)


def assert_identical(a, b):
    with h5py.File(a, "r") as fa, h5py.File(b, "r") as fb_:
        for name in VARIABLES:
            np.testing.assert_array_equal(fa[name][...], fb_[name][...], err_msg=name)
        for dim in ("Fx", "Fz", "My"):
            np.testing.assert_array_equal(fa[dim][...], fb_[dim][...])


def test_dask_map_equals_local_map(client, local_map, tmp_path):
    out = fb.loadmap(CONFIG, tmp_path / "dask.h5", progress=False, client=client, max_in_flight=3)
    assert_identical(out, local_map)
    ds = fb.open_dataset(out)
    assert ds.attrs["engine"] == "dask" and int(ds.attrs["dask_workers"]) == 2


BIG = {"bearing": CONFIG["bearing"], "loadmap": {**CONFIG["loadmap"], "Fx": {"start": -2000.0, "stop": 2000.0,
                                                                               "num": 80}}}


def killing_a_busy_worker(client, run):
    """``run()`` while a watcher SIGKILLs the first worker seen processing a block (it waits for a busy
    worker, not for a time, so it cannot miss the run); returns run()'s result once the nanny has
    restarted the worker."""
    pids = client.run(os.getpid)                               # worker address -> pid
    killed, finished = [], threading.Event()

    def kill_a_busy_worker():
        while not finished.is_set():
            busy = [addr for addr, keys in client.processing().items() if keys and addr in pids]
            if busy:
                os.kill(pids[busy[0]], signal.SIGKILL)
                killed.append(busy[0])
                return
            time.sleep(0.005)

    watcher = threading.Thread(target=kill_a_busy_worker)
    watcher.start()
    try:
        out = run()
    finally:
        finished.set()
        watcher.join()
    assert killed, "no worker was ever seen processing a block"
    client.wait_for_workers(2, timeout=60)  # the nanny restarts the killed worker
    return out


def test_killed_worker_blocks_are_recomputed(client, tmp_path):
    """SIGKILL a worker process while it holds blocks: the scheduler recomputes them (on the
    survivor or the restarted worker) and the file is still identical to a local run."""
    reference = fb.loadmap(BIG, tmp_path / "reference.h5", progress=False)
    out = killing_a_busy_worker(client, lambda: fb.loadmap(BIG, tmp_path / "killed.h5", progress=False,
                                                           client=client, max_in_flight=4))
    assert_identical(out, reference)


def test_resume_through_dask(client, local_map, tmp_path):
    """A local run interrupted after 3 blocks, resumed on the cluster: still identical."""
    from conftest import interrupted_after

    from fastbearing.jobs import runner as jobs

    module = importlib.import_module("fastbearing.jobs.loadmap")
    out = tmp_path / "resumed.h5"
    with pytest.raises(KeyboardInterrupt):
        jobs.run(interrupted_after(module.job(module.read_config(CONFIG)), 3), out, progress=False)
    fb.loadmap(CONFIG, out, progress=False, client=client, resume=True)
    assert_identical(out, local_map)


def test_passage_table_on_dask_equals_local(client, tmp_path):
    table = {"bearing": CONFIG["bearing"], "passage": {"given": "load", "Fx": {"start": 200.0, "stop": 3000.0,
             "num": 12}, "Fz": [500.0, 2000.0], "positions": 32, "chunk": 4}}
    local = fb.passage(table, tmp_path / "local.h5", progress=False)
    remote = fb.passage(table, tmp_path / "dask.h5", progress=False, client=client, max_in_flight=2)
    names = (*VARIABLES, "K_mean", "K_amplitude", "K_phase", "K_variation")
    with h5py.File(local, "r") as fa, h5py.File(remote, "r") as fb_:
        for name in names:
            np.testing.assert_array_equal(fa[name][...], fb_[name][...], err_msg=name)
        assert fb_.attrs["engine"] == "dask"
    if importlib.util.find_spec("zarr") is not None:        # and into a zarr store, written by the workers
        import zarr

        store = zarr.open_group(str(fb.passage(table, tmp_path / "dask.zarr", progress=False, client=client)), mode="r")
        with h5py.File(local, "r") as fa:
            for name in names:
                np.testing.assert_array_equal(store[name][...], fa[name][...], err_msg=name)
        assert store.attrs["dask_written_by"] == "workers"


def test_cli_dask_flag(tmp_path):
    import subprocess
    import sys

    cfg = tmp_path / "m.toml"
    cfg.write_text('[bearing]\npreset = "gunduz2013"\narrangement = "DB"\n[loadmap]\nFx = [500.0, 1000.0]\n'
                   "Fz = { start = 500.0, stop = 3000.0, num = 4 }\n")
    p = subprocess.run([sys.executable, "-m", "fastbearing.cli", "loadmap", str(cfg), "--dask", "local:2"],
                       capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    assert fb.open_dataset(tmp_path / "m.h5").attrs["engine"] == "dask"
    from conftest import cli_run

    bad = cli_run("loadmap", cfg, "--dask", "local:0", "--overwrite")
    assert bad.returncode == 2 and "worker count N >= 1" in bad.stderr


def test_a_block_the_scheduler_cancels_is_sent_again(client, local_map, tmp_path, monkeypatch):
    """A lost worker can leave a block's future cancelled ("already forgotten") instead of recomputed: the
    runner sends that block again under a new key, and the file is still identical to a local run."""
    submit = client.submit
    cancelled = []

    def submit_and_cancel_the_first(*args, **kwargs):
        future = submit(*args, **kwargs)
        if not cancelled:
            future.cancel()
            cancelled.append(kwargs["key"])
        return future

    monkeypatch.setattr(client, "submit", submit_and_cancel_the_first)
    out = fb.loadmap(CONFIG, tmp_path / "cancelled.h5", progress=False, client=client, max_in_flight=3)
    assert len(cancelled) == 1
    assert_identical(out, local_map)


# -- zarr stores written by the workers themselves (jobs/zarr_store.py) ------------------------------------

def _assert_store_equals(store, h5):
    import zarr

    g = zarr.open_group(str(store), mode="r")
    with h5py.File(h5, "r") as fh:
        for name in VARIABLES:
            np.testing.assert_array_equal(g[name][...], fh[name][...], err_msg=name)


def test_workers_write_the_zarr_store(client, local_map, tmp_path):
    """Into a zarr store the workers write their own blocks: the store equals the local run's file, and the
    client receives each block's status counts (2 kB) instead of its arrays."""
    pytest.importorskip("zarr")
    out = fb.loadmap(CONFIG, tmp_path / "dask.zarr", progress=False, client=client, max_in_flight=3)
    _assert_store_equals(out, local_map)
    ds = fb.open_map(out)
    assert ds.attrs["engine"] == "dask" and ds.attrs["dask_written_by"] == "workers"
    n_blocks = int(ds.attrs["n_blocks"])
    assert ds.attrs["dask_bytes_received"] == n_blocks * 256 * 8            # the counts, nothing else
    funnel = fb.open_map(fb.loadmap(CONFIG, tmp_path / "funnel.h5", progress=False, client=client))
    assert funnel.attrs["dask_written_by"] == "client"
    assert funnel.attrs["dask_bytes_received"] > 100 * ds.attrs["dask_bytes_received"]


def test_a_killed_workers_zarr_block_is_redone(client, tmp_path):
    """SIGKILL a worker while it computes (or writes) a block of a zarr store: the block is computed and
    written again, and the store equals a local run."""
    pytest.importorskip("zarr")
    reference = fb.loadmap(BIG, tmp_path / "reference.h5", progress=False)
    out = killing_a_busy_worker(client, lambda: fb.loadmap(BIG, tmp_path / "killed.zarr", progress=False,
                                                           client=client, max_in_flight=4))
    _assert_store_equals(out, reference)


def test_a_killed_client_resumes_the_zarr_store(client, tmp_path, capsys):
    """SIGKILL the client (the `fastbearing loadmap --dask` process) once a few blocks are recorded in the
    store: --resume (here on this test's cluster) computes only the rest, and the store equals a local run."""
    import subprocess
    import sys

    pytest.importorskip("zarr")
    cfg = tmp_path / "big.toml"
    cfg.write_text('[bearing]\npreset = "gunduz2013"\narrangement = "DB"\n[loadmap]\nchunk = 1000\n'
                   "Fx = { start = -2000.0, stop = 2000.0, num = 80 }\nFz = { start = 500.0, stop = 10000.0, num = 30 }\n"
                   "My = { start = -1.0e5, stop = 1.0e5, num = 99 }\n")
    out = tmp_path / "big.zarr"
    proc = subprocess.Popen([sys.executable, "-m", "fastbearing.cli", "loadmap", str(cfg), "-o", str(out),
                             "--dask", "local:2", "--in-flight", "2", "--no-progress"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    records = out / "block_counts" / "c"
    deadline = time.monotonic() + 240
    try:
        while time.monotonic() < deadline and proc.poll() is None:
            if records.is_dir() and sum(1 for _ in records.iterdir()) >= 3:
                break
            time.sleep(0.01)
    finally:
        proc.kill()
        proc.wait()
    assert proc.returncode == -signal.SIGKILL, proc.stderr.read()
    done = sum(1 for _ in records.iterdir())
    assert 3 <= done < 240
    with pytest.raises(ValueError, match="unfinished run exists"):
        fb.loadmap(str(cfg), out, progress=False)
    fb.loadmap(str(cfg), out, progress=False, client=client, resume=True)
    assert "computed in this run, the rest resumed" in capsys.readouterr().err
    reference = fb.loadmap(str(cfg), tmp_path / "reference.h5", progress=False)
    _assert_store_equals(out, reference)
