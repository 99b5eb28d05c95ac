"""Jobs on a Dask cluster (dask.distributed): the same blocks, the same kernels, the same file or store.

The client plans the blocks exactly as a local run does. Into a zarr store
(zarr_store.py), each worker computes a block from the job's cases (sent
once to every worker) and writes it into the store itself: the client only
plans and counts, receiving a block's status counts (2 kB), so its memory and
traffic do not grow with the map. Into an HDF5 file (one writer), the worker
sends the block's arrays back and the client writes them through the same
crash-safe writer as a local run (storage.py). A worker runs the job's own
compute function on one numba thread, so cores are used by Dask worker
threads and never oversubscribed (numba threads x Dask threads per worker =
1 x threads). A bounded number of blocks is in flight, so the client's
memory stays bounded too. A killed worker's blocks are recomputed by the
scheduler; results are identical because every block is computed
independently of where it runs (on machines of the same CPU architecture;
the kernel's vectorised sums may round differently on another SIMD width).
Load maps and ball-passage tables both run here.

Needs ``pip install 'fastbearing[dask]'``. Units: N, mm, rad.
"""

from __future__ import annotations

import os
import uuid

import numpy as np


def _worker_block(job, inputs, first):
    """Runs on a worker: one block with one numba thread; returns the result arrays the file keeps."""
    import numba

    from .storage import allocate

    numba.set_num_threads(1)
    res = allocate(list(job.variables), job.sizes, inputs.shape[0])
    job.compute(inputs, res, first, np.zeros(1, np.int64))  # Ctrl-C is the client's: it cancels the futures
    return job.kept(res)


def _worker_block_to_store(job, block, sink):
    """Runs on a worker: computes one block from the job's cases and writes it into the zarr store itself;
    returns only the block's status counts."""
    from .zarr_store import write_on_worker

    res = _worker_block(job, job.cases.inputs(block.start, block.stop), block.start)
    return write_on_worker(sink, block, res)


class _Tally:
    """The client's side of blocks that workers wrote themselves: progress, and nothing to write."""

    def __init__(self, on_written):
        self.on_written = on_written

    def buffer(self):
        return None

    def submit(self, block, counts, buf) -> None:
        if self.on_written is not None:
            self.on_written(block)

    def close(self) -> None:
        pass


def _worker_threads(client) -> int:
    info = client.scheduler_info()
    return max(1, sum(w.get("nthreads", 1) for w in info.get("workers", {}).values()))


#: How often a block the scheduler cancelled (a lost worker) is sent again before the run fails.
MAX_RESUBMITS = 3


def run_blocks(client, job, pending, part, sink, on_written, interrupt, max_in_flight=None) -> dict:
    """Compute the ``pending`` blocks of ``job`` on the cluster.

    With a ``sink`` (a zarr store's ZarrStore.worker_sink) the workers write their blocks into the store;
    without one their arrays come back and are written into ``part`` (the HDF5 working file) here.
    ``on_written(block)`` is called as each block is done. ``max_in_flight`` (checked by the runner) bounds
    the blocks out at once; default 2 per worker thread. Returns provenance attributes (engine, workers,
    scheduler, and the bytes of results the client received).
    """
    from concurrent.futures import CancelledError

    from distributed import as_completed

    from .storage import BlockWriter

    threads = _worker_threads(client)
    limit = 2 * threads if max_in_flight is None else max_in_flight
    # the job (bearing, settings, the cases: a grid's axes or a case table) travels once to every worker
    shipped = client.scatter(job, broadcast=True)
    writer = _Tally(on_written) if sink is not None else BlockWriter(part, [object() for _ in range(4)], on_written)
    queue = iter(pending)
    futures = {}
    retries = {}
    received = 0
    # task keys unique to this run: a key the scheduler still holds from an earlier run in this process (the
    # same block index, pid and retry count) would hand back that run's result, e.g. a zarr run's status
    # counts to an HDF5 run's writer
    run = uuid.uuid4().hex[:12]

    def submit_next(block=None):
        block = next(queue, None) if block is None else block
        if block is None:
            return None
        key = f"fastbearing-block-{run}-{block.index}-{os.getpid()}-{retries.get(block.index, 0)}"
        if sink is not None:
            future = client.submit(_worker_block_to_store, shipped, block, sink, pure=False, key=key)
        else:
            inputs = job.cases.inputs(block.start, block.stop)
            future = client.submit(_worker_block, shipped, inputs, block.start, pure=False, key=key)
        futures[future] = block
        return future

    try:
        running = as_completed()
        for _ in range(limit):
            future = submit_next()
            if future is None:
                break
            running.add(future)
        for future in running:
            block = futures.pop(future)
            try:
                res = future.result()
            except CancelledError:
                # a worker killed at the wrong moment can leave the scheduler forgetting the block
                # ("already forgotten") rather than recomputing it: send it again, a few times at most
                retries[block.index] = retries.get(block.index, 0) + 1
                if retries[block.index] > MAX_RESUBMITS:
                    raise
                shipped = client.scatter(job, broadcast=True)  # its copy may have gone too
                running.add(submit_next(block))
                continue
            future.release()
            received += res.nbytes if isinstance(res, np.ndarray) else sum(a.nbytes for a in res.values())
            writer.submit(block, res, writer.buffer())
            if interrupt.requested:
                raise KeyboardInterrupt
            nxt = submit_next()
            if nxt is not None:
                running.add(nxt)
    finally:
        for future in futures:
            future.cancel()
        writer.close()
    return {"engine": "dask", "dask_workers": len(client.scheduler_info().get("workers", {})),
            "dask_worker_threads": threads, "dask_scheduler": str(client.scheduler.address),
            "dask_written_by": "workers" if sink is not None else "client",
            "dask_bytes_received": received}


def client_for(spec: str):
    """A Client for ``--dask``: ``local:N`` starts a LocalCluster of N single-threaded worker
    processes; ``tcp://HOST:PORT`` connects to a running scheduler. Returns (client, cluster or None)."""
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        raise ValueError("--dask needs dask.distributed: pip install 'fastbearing[dask]'") from None
    if spec.startswith("local:"):
        try:
            n = int(spec.split(":", 1)[1])
        except ValueError:
            n = 0
        if n < 1:
            raise ValueError(f"--dask local:N needs a worker count N >= 1, got {spec!r}")
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None)
        return Client(cluster), cluster
    if spec.startswith("tcp://"):
        return Client(spec), None
    raise ValueError(f"--dask must be local:N or tcp://HOST:PORT, got {spec!r}")
