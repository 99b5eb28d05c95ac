"""Load maps on a Dask LocalCluster: identical to a local run bit for bit, also when a worker is
killed mid-run, and resumable."""

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
    from fastbearing.distributed import client_for

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


def test_killed_worker_blocks_are_recomputed(client, tmp_path):
    """SIGKILL one worker process while blocks are out on it: the scheduler recomputes them
    (on the survivor or the restarted worker) and the file is still identical to a local run."""
    reference = fb.loadmap(BIG, tmp_path / "reference.h5", progress=False)
    pids = list(client.run(os.getpid).values())
    killed, finished = [], threading.Event()

    def kill_one_worker_mid_run():
        while not finished.is_set():
            if sum(len(v) for v in client.processing().values()) > 0:
                time.sleep(0.3)  # let some blocks finish first
                if not finished.is_set():
                    os.kill(pids[0], signal.SIGKILL)
                    killed.append(pids[0])
                return
            time.sleep(0.01)

    watcher = threading.Thread(target=kill_one_worker_mid_run)
    watcher.start()
    try:
        out = fb.loadmap(BIG, tmp_path / "killed.h5", progress=False, client=client, max_in_flight=4)
    finally:
        finished.set()
        watcher.join()
    assert killed, "the run finished before a worker could be killed"
    assert_identical(out, reference)
    client.wait_for_workers(2, timeout=60)  # the nanny restarts the killed worker


def test_resume_through_dask(client, local_map, tmp_path):
    """A local run killed half-way, resumed on the cluster: still identical."""
    from fastbearing import storage
    from fastbearing.grid import plan_blocks
    from fastbearing.loadmap import read_config, _create

    cfg = read_config(CONFIG)
    out = tmp_path / "resumed.h5"
    part = storage.part_path(out)
    blocks = plan_blocks(cfg.cases.shape, cfg.cases.line_length, cfg.chunk)
    _create(cfg, part, blocks)  # as left by a run killed before any block finished
    fb.loadmap(CONFIG, out, progress=False, client=client, resume=True)
    assert_identical(out, local_map)


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
    bad = subprocess.run([sys.executable, "-m", "fastbearing.cli", "loadmap", str(cfg), "--dask", "local:0",
                          "--overwrite"], capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert bad.returncode == 2 and "worker count N >= 1" in bad.stderr
