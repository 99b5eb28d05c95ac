"""The one job runner: load maps and ball-passage tables are both jobs.

A job is a bearing, its cases (a grid or a table of loads or displacements),
the result variables of one case (with the lengths of their own dims), a
compute function that fills the results of a block of cases, and the
attributes and fingerprint that describe it. The runner owns everything
else, once for every kind of job:

- checks before anything is created: threads, output folder, disk space;
- the working file ``OUT.h5.part`` (storage.py), block planning, resume of an
  interrupted run of the same config, never overwriting without being told;
- the blocks computed here (a background writer overlaps HDF5 with the next
  block) or on a Dask cluster (distributed.py), identical either way;
- Ctrl-C within a case (a second one stops at once), the progress bar, the
  final status counts and summary line.

Units: N, mm, rad throughout (see dofs.py).
"""

from __future__ import annotations

import dataclasses
import errno
import json
import signal
import sys
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from .. import status as st

from . import storage

from .. import validate
from ..api import check_threads, num_threads
from ..model.bearing import Bearing
from ..dofs import AXES, DOF_LABELS, LONG_NAMES, UNITS, UNITS_CONVENTION
from .._cache import CompileWatch
from ..files import DiskFull
from .grid import CaseSet, plan_blocks
from .locations import is_url
from ..engine.solver import SolverSettings

def check_device(device, client) -> str:
    """A job's ``device`` ("cpu" or "cuda"), checked before anything is created: a ValueError naming the field,
    a Dask run on the GPU refused, and CudaUnavailable (saying what is missing) where "cuda" cannot run."""
    from ..engine.device import DEVICES, require_cuda

    device = validate.choice(device, "device", DEVICES)
    if device == "cuda" and client is not None:
        raise ValueError("device = 'cuda' runs on this machine's GPU; a Dask run on GPU workers is not built yet "
                         "(run --device cuda without --dask, or the CPU workers with --dask)")
    if device == "cuda":
        require_cuda()
    return device


#: Most blocks a Dask run may have out on the cluster at once.
MAX_IN_FLIGHT = 10_000
#: What a job's real-valued results may be stored as (``[loadmap] dtype``): float32 halves a K-only map.
RESULT_DTYPES = ("float64", "float32")


def _disk_full(err: BaseException) -> bool:
    """ENOSPC, however it arrives (h5py raises OSError or RuntimeError with HDF5's text)."""
    text = str(err)
    return isinstance(err, (OSError, RuntimeError)) and (getattr(err, "errno", None) == errno.ENOSPC
                                                         or "No space left" in text or "errno = 28" in text)


@dataclass(frozen=True)
class Job:
    """Everything the runner needs to compute a kind of job and write it to HDF5.

    ``compute(inputs, results, first, stop)`` fills ``results`` (a dict of
    arrays, one per variable, leading dim the block's cases) for the (n, 5)
    ``inputs`` of a block whose first flat case is ``first``, and returns
    early (the block incomplete) once ``stop[0] != 0``; it must be picklable for Dask (a module-level function or a
    ``functools.partial`` of one) and its results must not depend on where
    or on how many threads it runs.
    """

    kind: str                                # "load map", "ball-passage table": in messages and the title
    bearing: Bearing
    cases: CaseSet
    variables: tuple[storage.Variable, ...]
    sizes: dict[str, int]                    # length of every non-case dim the variables use
    compute: Callable[[np.ndarray, dict, int, np.ndarray], None]
    settings: SolverSettings
    method: str
    chunk: int
    text: str                                # the config as written
    source: Path | None
    fingerprint: str
    compression: str = "none"
    line_length: int = 1                     # cases per grid line (blocks cut lines only between segments)
    own_dims: tuple[storage.Coordinate, ...] = ()    # the job's own non-case dims (e.g. position, harmonic)
    aux_coords: tuple = ()                   # (Coordinate, dim name): e.g. cage_angle(position)
    attrs: dict = field(default_factory=dict)
    solves_per_case: int = 1                 # e.g. cage positions per operating point
    case_word: str = "case"                  # "case" or "point", in the summary and progress bar
    kernel: str = ""                         # the sweep compute runs, "engine.sweep.map_sweep": to tell of compiling
    stored: tuple[str, ...] | None = None    # the variables the file keeps (None: all); compute fills them all
    dtype: str = "float64"                   # the stored dtype of the real-valued variables
    narrow: tuple[str, ...] = ()             # variables compute fills in their stored dtype (the GPU, on the device)

    @property
    def buffer_variables(self) -> tuple[storage.Variable, ...]:
        """The variables as a block's buffers hold them: ``narrow`` ones in their stored dtype (compute fills them
        so, and kept() passes them on uncast), the others as computed."""
        stored = {v.name: v for v in self.stored_variables}
        return tuple(stored[v.name] if v.name in self.narrow else v for v in self.variables)

    @property
    def stored_variables(self) -> tuple[storage.Variable, ...]:
        """The variables as the file holds them: the kept ones, real values in ``dtype``."""
        out = []
        for v in self.variables:
            if self.stored is None or v.name in self.stored:
                real = v.dtype.startswith("f") and self.dtype == "float32"
                out.append(dataclasses.replace(v, dtype="f4") if real else v)
        return tuple(out)

    def kept(self, res: dict) -> dict:
        """A block's results as the file stores them (the kept variables, cast to their stored dtype)."""
        if self.stored is None and self.dtype == "float64":
            return res
        # a number beyond float32's range is stored as +-inf, as the cast leaves it (a life of 1e52 million
        # revolutions under a noise-level load): said nowhere else, so numpy's context-free "overflow
        # encountered in cast" would be the only word of it
        with np.errstate(over="ignore"):
            return {v.name: res[v.name].astype(v.dtype, copy=False) for v in self.stored_variables}

    def bytes_needed(self) -> int:
        return self.cases.n_cases * storage.bytes_per_case(list(self.stored_variables), self.sizes)


def check_stored(names, variables, where: str) -> tuple[str, ...] | None:
    """The stored subset ``names`` of ``variables``, with status always kept (a case's outcome travels with its
    results); ValueError naming the unknown ones and what this job has. None: all."""
    if names is None:
        return None
    have = [v.name for v in variables]
    unknown = [n for n in names if n not in have]
    if unknown:
        raise ValueError(f"{where}: {', '.join(map(repr, unknown))} {'is' if len(unknown) == 1 else 'are'} not "
                         f"variables of this map; it has {', '.join(have)}")
    return tuple(n for n in have if n in names or n == "status")


# -- result arrays ---------------------------------------------------------------------------------

class Buffers:
    """Result arrays of the largest block, allocated once and reused for every block."""

    def __init__(self, variables, sizes: dict[str, int], n: int):
        self.arrays = storage.allocate(variables, sizes, n)

    def view(self, n: int) -> dict[str, np.ndarray]:
        return {k: v[:n] for k, v in self.arrays.items()}


# -- the file's coordinates and attributes ----------------------------------------------------------

def case_coordinates(cases: CaseSet):
    """(case dims, scalar coordinates, auxiliary coordinates) of a grid or a case table."""
    C = storage.Coordinate
    names, units = AXES[cases.given], UNITS[cases.given]
    dim = cases.table_dim
    if cases.table is not None:
        case_dims = [C(dim, np.arange(cases.n_cases), "1", f"{dim} number")]
        aux = [(C(n, cases.table[:, i], u, LONG_NAMES[n]), dim) for i, (n, u) in enumerate(zip(names, units))]
        if cases.has_speed:
            aux.append((C("speed", cases.table[:, 5], "rpm", LONG_NAMES["speed"]), dim))
        return case_dims, [], aux
    if cases.dims:
        case_dims = [C(a.name, a.values, a.units, LONG_NAMES[a.name]) for a in cases.dims]
    else:
        case_dims = [C(dim, np.arange(1), "1", f"the single {dim}")]
    scalars = [C(a.name, a.values, a.units, LONG_NAMES[a.name], False) for a in cases.all_axes if not a.is_dim]
    return case_dims, scalars, []


def _dof_dims(bearing: Bearing) -> list[storage.Coordinate]:
    C = storage.Coordinate
    labels = np.array(DOF_LABELS)
    return [C("dof", labels, "1", "degree of freedom: x, y, z translations; tx, ty tilts"),
            C("dof_col", labels, "1", "degree of freedom (column of K)"),
            C("row", np.arange(bearing.n_rows), "1", "bearing row (as in the bearing definition)")]


def _attributes(job: Job, n_blocks: int) -> dict:
    return {
        "title": f"fastbearing {job.kind}", "Conventions": "CF-1.8", "given": job.cases.given,
        "units_convention": UNITS_CONVENTION,
        "config": job.text, "config_source": str(job.source or ""), "config_fingerprint": job.fingerprint,
        "bearing": job.bearing.describe(), "bearing_json": json.dumps(job.bearing.to_dict()),
        "solver_method": job.method, "solver_rtol": job.settings.rtol, "solver_max_iter": job.settings.max_iter,
        "chunk": job.chunk, "compression": job.compression, "n_cases": job.cases.n_cases, "n_blocks": n_blocks,
        **({"stored_variables": ", ".join(v.name for v in job.stored_variables)} if job.stored is not None else {}),
        "result_dtype": job.dtype, **job.attrs, **storage.versions(),
    }


def _create(job: Job, store, blocks, tasks) -> None:
    case_dims, scalars, aux = case_coordinates(job.cases)
    store.create(case_dims, [*job.own_dims, *_dof_dims(job.bearing)], scalars, list(job.stored_variables),
                 _attributes(job, len(tasks)), blocks, tasks, job.compression, [*aux, *job.aux_coords])


# -- running ---------------------------------------------------------------------------------------

class _Interrupt:
    """Ctrl-C sets ``stop[0]``, which the running sweep reads between cases (it runs in a worker
    thread, so this handler runs at once); a second Ctrl-C stops at once."""

    def __init__(self):
        self.stop = np.zeros(1, np.int64)
        self._old = None

    @property
    def requested(self) -> bool:
        return bool(self.stop[0])

    def __enter__(self):
        if threading.current_thread() is threading.main_thread():
            self._old = signal.signal(signal.SIGINT, self._handle)
        return self

    def _handle(self, signum, frame):
        if self.requested:
            raise KeyboardInterrupt
        self.stop[0] = 1

    def __exit__(self, *exc):
        if self._old is not None:
            signal.signal(signal.SIGINT, self._old)


class _Progress:
    """The progress bar, started when the first block is written: its rate and ETA then measure
    computing, not the one-time compilation before it."""

    def __init__(self, total: int, initial: int, unit: str):
        self.total, self.done, self.unit = total, initial, unit
        self.bar = None

    def __call__(self, block) -> None:
        self.done += block.size
        if self.bar is None:
            from tqdm import tqdm

            self.bar = tqdm(total=self.total, initial=self.done, unit=self.unit, unit_scale=True,
                            dynamic_ncols=True, smoothing=0.1)
        else:
            self.bar.update(block.size)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def _progress(total: int, initial: int, show, unit: str):
    show = sys.stderr.isatty() if show is None else show
    return _Progress(total, initial, unit) if show else None


def check_in_flight(max_in_flight, name: str = "max_in_flight") -> int | None:
    """None (the default: 2 per worker thread) or an integer in [1, MAX_IN_FLIGHT]."""
    if max_in_flight is None:
        return None
    return validate.integer(max_in_flight, name, low=1, high=MAX_IN_FLIGHT)


def output_path(output, source: Path | None):
    """The output: as given (a path, or a zarr store's URL), or the config's name with suffix .h5 in the
    current folder."""
    if output is not None:
        return output if is_url(output) else Path(output)
    if source is None:
        raise ValueError("output is required when the config is not a file")
    return Path(source.name).with_suffix(".h5")


def run(job: Job, output, *, threads=None, resume=False, overwrite=False, progress=None, client=None,
        max_in_flight=None):
    """Compute ``job`` into ``output``; returns the absolute path of the finished file or store (a URL as given).

    ``output`` ending in ``.zarr``, or any fsspec URL, is a zarr v3 store (zarr_store.py), else an HDF5 file.
    Every argument is checked before anything is created. A killed or
    interrupted run keeps its finished blocks (in ``output.part``, or in the zarr store itself); ``resume``
    continues it (same config only) and the result is identical bit for bit
    to an uninterrupted run. Nothing is overwritten unless ``overwrite``.
    """
    check_threads(threads)
    max_in_flight = check_in_flight(max_in_flight)
    store = storage.store_for(output)
    store.check(job.compression)
    if not (resume and store.unfinished()):
        store.check_space(job.bytes_needed(), f"this {job.kind} ({job.cases.n_cases} {job.case_word}s)")
    with store.lock():
        state = store.prepare(job.fingerprint, resume, overwrite)
        if state == "done":
            print(f"fastbearing: {output} is already complete; nothing to resume", file=sys.stderr)
            return store.result()
        blocks = plan_blocks(job.cases.shape, job.line_length, job.chunk)
        tasks = store.tasks(blocks, job.cases.shape, resuming=state == "resume")
        if state == "resume" and store.all_done():
            # killed while finishing: every block is there, only the finishing step is repeated
            store.finish(job.compression, tasks, {}, [v.name for v in job.stored_variables])
            print(f"fastbearing: finished {output} (all blocks were already computed)", file=sys.stderr)
            return store.result()
        if state == "new":
            _create(job, store, blocks, tasks)
        _compute(job, store, tasks, threads, progress, client, max_in_flight)
    return store.result()


def _compute(job: Job, store, blocks, threads, progress, client, max_in_flight) -> None:
    """Compute the blocks not yet done into the store, then finish it."""
    pf = store.open_part()
    started = time.perf_counter()
    done = pf.done_mask()
    pending = [b for b in blocks if not done[b.index]]
    bar = _progress(job.cases.n_cases, sum(b.size for b in blocks if done[b.index]), progress, job.case_word)
    on_written = bar
    watch = CompileWatch()  # says so when numba starts compiling (any signature), and times it
    try:
        with _Interrupt() as interrupt, watch:
            if client is None:
                size = max(b.size for b in blocks)
                # two buffer sets: one being computed, one being written
                writer = storage.BlockWriter(pf, [Buffers(job.buffer_variables, job.sizes, size) for _ in range(2)],
                                             on_written)
                _run_here(job, pending, writer, interrupt, threads)
            else:
                from .distributed import run_blocks

                pf.update_attrs(run_blocks(client, job, pending, pf, store.worker_sink(), on_written, interrupt,
                                           max_in_flight))
        if bar is not None:
            bar.close()
    except KeyboardInterrupt:
        pf.close()
        print(f"\nfastbearing: interrupted; finished blocks are kept in {store.part_name}; continue with --resume",
              file=sys.stderr)
        raise
    except BaseException as err:
        _close_quietly(pf)
        if _disk_full(err):
            raise _full(store, job) from None
        raise
    missing = int((~pf.done_mask()).sum())
    if missing:  # workers that wrote elsewhere (a path they see otherwise), or a block lost without an error
        pf.close()
        raise ValueError(f"{missing} blocks were not recorded in {store.part_name}; nothing was marked finished "
                         "(do the workers see the same location?); continue with --resume")
    computed = sum(b.size for b in pending)
    counts = _status_counts(pf)
    pf.close()
    wall = time.perf_counter() - started
    finishing = time.perf_counter()
    try:
        store.finish(job.compression, blocks, {"wall_time_s": wall, "compile_time_s": watch.seconds,
                     "status_counts": json.dumps({st.describe(c): k for c, k in counts.items()})},
                     [v.name for v in job.stored_variables])
    except (OSError, RuntimeError) as err:
        if _disk_full(err):
            if store.format == "hdf5":
                store.out.with_name(store.out.name + ".packing").unlink(missing_ok=True)
            raise _full(store, job, "while finishing") from None
        raise
    repacked = store.format == "hdf5" and job.compression != "none"
    print(_summary(job, counts, wall, computed, time.perf_counter() - finishing, watch.seconds, repacked),
          file=sys.stderr)


def _close_quietly(pf: storage.PartFile) -> None:
    try:
        pf.close()
    except OSError:  # closing flushes, and a full disk refuses that too; the blocks marked done are safe
        pass


def _full(store, job: Job, when: str = "") -> DiskFull:
    import shutil

    done = store.finished_blocks()
    need = storage.human_size(job.bytes_needed())
    local = Path(store.part_name) if not is_url(store.part_name) else None
    free = f" ({storage.human_size(shutil.disk_usage(local.parent).free)} free now)" if local is not None else ""
    return DiskFull(f"fastbearing: the disk is full{' ' + when if when else ''}: {done} finished blocks are "
                    f"kept in {store.part_name}; the whole {job.kind} needs about {need}{free}; free some space "
                    "and continue with --resume")


def _run_here(job: Job, pending, writer, interrupt, threads) -> None:
    """Compute blocks in this process, overlapping each block's HDF5 write with the next block's compute.

    The blocks run in a worker thread while this (main) thread waits, so that a Ctrl-C reaches the
    handler at once and the sweep stops within a case; the block it cuts short is discarded (it is
    recomputed on --resume), the finished ones are written.
    """
    failure: list[BaseException] = []

    def compute_blocks():
        try:
            with num_threads(threads):  # numba's thread count is per calling thread
                buf, inputs = _next(job, pending, 0, writer)
                for k, block in enumerate(pending):
                    res = buf.view(block.size)
                    job.compute(inputs, res, block.start, interrupt.stop)
                    if interrupt.requested:
                        break
                    # the next block's buffer and inputs before this block goes to the writer, whose HDF5
                    # calls hold the GIL: then the next compute starts at once
                    following = _next(job, pending, k + 1, writer)
                    writer.submit(block, job.kept(res), buf)
                    buf, inputs = following
        except BaseException as err:  # noqa: BLE001 - handed to the main thread
            failure.append(err)

    worker = threading.Thread(target=compute_blocks, name="fastbearing-compute", daemon=True)
    try:
        worker.start()
        while worker.is_alive():
            worker.join(0.05)
    finally:
        writer.close()  # also on Ctrl-C: the block in flight is written and kept for --resume
    if failure:
        raise failure[0]
    if interrupt.requested:
        raise KeyboardInterrupt


def _next(job: Job, pending, k: int, writer):
    """A free buffer and the inputs of ``pending[k]`` ((None, None) past the last block)."""
    if k >= len(pending):
        return None, None
    return writer.buffer(), job.cases.inputs(pending[k].start, pending[k].stop)


def _status_counts(pf: storage.PartFile) -> dict[int, int]:
    """Solves per status code (read in slices, so memory stays bounded)."""
    return pf.value_counts("status")


def _summary(job: Job, counts: dict[int, int], wall: float, computed: int, finish: float = 0.0,
             compiling: float = 0.0, repacked: bool = False) -> str:
    """One line: how many (and how many of them this run computed, when it resumed), what share converged and
    by status, how long (computing, then compressing; the time spent compiling on a line of its own before
    it), and the rate over this run's cases and computing time alone."""
    total = sum(counts.values())
    ok = sum(k for code, k in counts.items() if st.is_converged(code))
    by_status = ", ".join(f"{st.describe(code)} {k}" for code, k in sorted(counts.items(), key=lambda x: -x[1]))
    what = f"{job.cases.n_cases} {job.case_word}{'' if job.cases.n_cases == 1 else 's'}"
    if job.solves_per_case > 1:
        what += f" x {job.solves_per_case} positions"
    if computed < job.cases.n_cases:
        what += f" ({computed} computed in this run, the rest resumed)"
    compiling = min(compiling, wall) if compiling > 0.5 else 0.0  # below that: loading from the cache
    work = wall - compiling
    rate = computed * job.solves_per_case / work if work > 0 else float("inf")
    took = f"{work:.2f} s wall"
    if repacked:
        took = f"{work:.2f} s computing + {finish:.2f} s {job.compression} repack = {work + finish:.2f} s wall"
    said = ""
    if compiling:  # a line of its own, so that the summary reads alike with and without it
        said = (f"fastbearing: compiling took {compiling:.1f} s (once for this kind of run; later runs load the "
                "kernels from numba's cache)\n")
    return (f"{said}fastbearing: {what}, {100.0 * ok / max(total, 1):.2f} % converged ({by_status}); "
            f"{took}, {rate:,.0f} solves/s")


# -- opening results -------------------------------------------------------------------------------

def require_xarray():
    """Check for xarray and h5netcdf before any work is done, not after."""
    try:
        import h5netcdf  # noqa: F401
        import xarray  # noqa: F401
    except ImportError:
        raise ImportError("as_dataset needs xarray and h5netcdf: pip install 'fastbearing[xarray]'") from None


def open_dataset(path):
    """Open a finished map or table as an ``xarray.Dataset``: an HDF5 file (engine h5netcdf) or a zarr store
    (``xr.open_zarr``, lazy); refuses unfinished ones."""
    from . import zarr_store

    if zarr_store.is_zarr_location(path):
        if not zarr_store.is_complete(path):
            raise ValueError(f"{path} is not a finished fastbearing zarr store")
        return zarr_store.open_dataset(path)
    path = Path(path)
    if not storage.is_complete(path):
        raise ValueError(f"{path} is not a finished fastbearing file")
    require_xarray()
    import xarray as xr

    return xr.open_dataset(path, engine="h5netcdf")


#: The same: a finished load map or passage table, HDF5 or zarr, as an ``xarray.Dataset``.
open_map = open_dataset
