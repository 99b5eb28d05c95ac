"""Jobs on a Dask cluster (dask.distributed): the same blocks, the same kernels, the same file.

The client plans the blocks exactly as a local run does, sends each block's
inputs to a worker, and writes the returned arrays into the same HDF5 layout
through the same crash-safe writer (jobs.py). A worker runs the job's own
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

import numpy as np


def _worker_block(compute, variables, sizes, inputs, first):
    """Runs on a worker: one block with one numba thread; returns the result arrays."""
    import numba

    from .storage import allocate

    numba.set_num_threads(1)
    res = allocate(variables, sizes, inputs.shape[0])
    compute(inputs, res, first, np.zeros(1, np.int64))  # Ctrl-C is the client's: it cancels the futures
    return res


def _worker_threads(client) -> int:
    info = client.scheduler_info()
    return max(1, sum(w.get("nthreads", 1) for w in info.get("workers", {}).values()))


#: How often a block the scheduler cancelled (a lost worker) is sent again before the run fails.
MAX_RESUBMITS = 3


def run_blocks(client, job, pending, writer, interrupt, max_in_flight=None) -> dict:
    """Compute the ``pending`` blocks of ``job`` on the cluster and hand each result to ``writer``.

    ``max_in_flight`` (checked by the runner) bounds the blocks out at once;
    default 2 per worker thread. Returns provenance attributes (engine,
    workers, scheduler).
    """
    from concurrent.futures import CancelledError

    from distributed import as_completed

    threads = _worker_threads(client)
    limit = 2 * threads if max_in_flight is None else max_in_flight
    compute = client.scatter(job.compute, broadcast=True)     # the bearing and settings travel once
    variables = list(job.variables)
    queue = iter(pending)
    futures = {}
    retries = {}

    def submit_next(block=None):
        block = next(queue, None) if block is None else block
        if block is None:
            return None
        inputs = job.cases.inputs(block.start, block.stop)
        future = client.submit(_worker_block, compute, variables, job.sizes, inputs, block.start, pure=False,
                               key=f"fastbearing-block-{block.index}-{os.getpid()}-{retries.get(block.index, 0)}")
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
                compute = client.scatter(job.compute, broadcast=True)  # its copy may have gone too
                running.add(submit_next(block))
                continue
            future.release()
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
            "dask_worker_threads": threads, "dask_scheduler": str(client.scheduler.address)}


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
