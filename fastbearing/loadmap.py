"""Load maps: Kb at every case of a grid (or table) of loads or displacements, streamed to HDF5.

Flow: config (TOML) -> bearing + cases -> blocks -> parallel sweep per block
-> HDF5 block by block. Memory is bounded by one block; a killed run resumes
from its ``.part`` file; nothing is overwritten without ``overwrite=True``.
Units: N, mm, rad.
"""

from __future__ import annotations

import hashlib
import json
import signal
import sys
import threading
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from . import status as st, storage, validate
from .api import check_threads, num_threads, solver_settings
from .bearing import ROW, Bearing
from .bearing_file import read_job_config
from .grid import AXES, LONG_NAMES, UNITS, Axis, CaseSet, parse_axis, plan_blocks, read_case_file
from .sweep import map_sweep

DEFAULT_CHUNK = 65536
#: Largest block: one block's results are in memory at once (about 400 bytes a case).
MAX_CHUNK = 4_000_000
_LOADMAP_KEYS = {"given", "cases", "chunk", "compression", "method", "rtol", "max_iter"}


@dataclass(frozen=True)
class LoadMapConfig:
    """A parsed load-map config: the bearing, the cases and how to run them."""

    bearing: Bearing
    cases: CaseSet
    chunk: int
    compression: str
    method: str
    rtol: float | None
    max_iter: int | None
    text: str
    source: Path | None
    fingerprint: str


def read_config(config) -> LoadMapConfig:
    """Parse a load-map config from a TOML path or an already-parsed dict; ValueError names the field."""
    bearing, spec, text, source = read_job_config(config, "loadmap")
    given = validate.choice(spec.get("given", "load"), "loadmap.given", tuple(AXES))
    names = AXES[given]
    other = AXES["displacement" if given == "load" else "load"]
    for key in spec:
        if key in other:
            raise ValueError(f"loadmap.{key} is not an axis for given = {given!r}; its axes are {list(names)}")
        if key not in names and key not in _LOADMAP_KEYS:
            raise ValueError(f"loadmap: unknown key {key!r}; allowed: {sorted(_LOADMAP_KEYS | set(names))}")
    chunk = validate.integer(spec.get("chunk", DEFAULT_CHUNK), "loadmap.chunk", low=1, high=MAX_CHUNK)
    compression = validate.choice(spec.get("compression", "none"), "loadmap.compression", storage.COMPRESSIONS)
    method = spec.get("method", "newton")
    rtol, max_iter = spec.get("rtol"), spec.get("max_iter")
    try:
        solver_settings(bearing, method, rtol, max_iter)  # validates method, rtol, max_iter
    except validate.FieldError as err:
        raise err.within("loadmap") from None
    digest = hashlib.sha256(text.encode())
    if "cases" in spec:
        axes_given = [k for k in spec if k in names]
        if axes_given:
            raise ValueError(f"loadmap.cases replaces the grid axes; remove {axes_given}")
        if not isinstance(spec["cases"], str):
            raise ValueError(f"loadmap.cases must be a file name (.npy, .csv or .h5), got {spec['cases']!r}")
        path = Path(spec["cases"])
        if source is not None and not path.is_absolute():
            path = source.parent / path
        table = read_case_file(path, "loadmap.cases")
        digest.update(table.tobytes())
        cases = CaseSet(given, table=table)
    else:
        axes = []
        for name, units in zip(names, UNITS[given]):
            values, is_dim = parse_axis(name, spec.get(name, 0.0), "loadmap")
            axes.append(Axis(name, values, units, is_dim))
        cases = CaseSet(given, axes=tuple(axes))
    cases.check_size("loadmap")
    return LoadMapConfig(bearing, cases, chunk, compression, method, rtol, max_iter, text, source,
                         digest.hexdigest())


def compute_block(bearing: Bearing, given_load: bool, line_length: int, inputs: np.ndarray, solver: dict,
                  res: dict) -> None:
    """Fill the result arrays ``res`` (views of one block) for ``inputs``: the work unit of a map.

    Local runs and Dask workers both call this, on the same blocks, which is
    why their outputs are identical bit for bit.
    """
    balls = bearing.ball_set()
    ball_row = balls[0][ROW].astype(np.int64)
    map_sweep(inputs, given_load, line_length, res["q"], res["f"], res["K"], res["status"], res["iterations"],
              res["residual"], res["max_ball_load"], res["loaded_balls"], res["min_contact_angle"],
              res["max_contact_angle"], balls, ball_row, solver)


class _Buffers:
    """Per-block result arrays, allocated once for the largest block and reused."""

    def __init__(self, size: int, n_rows: int):
        self.q = np.empty((size, 5))
        self.f = np.empty((size, 5))
        self.K = np.empty((size, 5, 5))
        self.status = np.empty(size, np.int8)
        self.iterations = np.empty(size, np.int32)
        self.residual = np.empty(size)
        self.max_ball_load = np.empty((size, n_rows))
        self.loaded_balls = np.empty((size, n_rows), np.int16)
        self.min_contact_angle = np.empty((size, n_rows))
        self.max_contact_angle = np.empty((size, n_rows))

    def view(self, n: int) -> dict[str, np.ndarray]:
        return {k: v[:n] for k, v in vars(self).items()}


class _Interrupt:
    """Ctrl-C sets a flag checked between blocks; a second Ctrl-C stops at once."""

    def __init__(self):
        self.requested = False
        self._old = None

    def __enter__(self):
        if threading.current_thread() is threading.main_thread():
            self._old = signal.signal(signal.SIGINT, self._handle)
        return self

    def _handle(self, signum, frame):
        if self.requested:
            raise KeyboardInterrupt
        self.requested = True

    def __exit__(self, *exc):
        if self._old is not None:
            signal.signal(signal.SIGINT, self._old)


def _create(cfg: LoadMapConfig, part: Path, blocks) -> None:
    cases = cfg.cases
    C = storage.Coordinate
    if cases.table is not None:
        case_dims = [C("case", np.arange(cases.n_cases), "1", "case number in the case file")]
        case_coords = [(C(n, cases.table[:, i], u, LONG_NAMES[n]), "case")
                       for i, (n, u) in enumerate(zip(AXES[cases.given], UNITS[cases.given]))]
        scalars = []
    elif cases.dims:
        case_dims = [C(a.name, a.values, a.units, LONG_NAMES[a.name]) for a in cases.dims]
        case_coords = []
        scalars = [C(a.name, a.values, a.units, LONG_NAMES[a.name], False) for a in cases.axes if not a.is_dim]
    else:
        case_dims = [C("case", np.arange(1), "1", "the single case")]
        case_coords = []
        scalars = [C(a.name, a.values, a.units, LONG_NAMES[a.name], False) for a in cases.axes]
    import h5py

    labels = np.array(storage.DOF_LABELS, dtype=h5py.string_dtype())
    extra_dims = [C("dof", labels, "1", "degree of freedom: x, y, z translations; tx, ty tilts"),
                  C("dof_col", labels, "1", "degree of freedom (column of K)"),
                  C("row", np.arange(cfg.bearing.n_rows), "1", "bearing row (as in the bearing definition)")]
    opts = solver_settings(cfg.bearing, cfg.method, cfg.rtol, cfg.max_iter)
    attrs = {
        "title": "fastbearing load map", "Conventions": "CF-1.8", "given": cases.given,
        "units_convention": "N, mm, rad; moments N*mm; stiffness N/mm, N*mm/rad, N/rad",
        "config": cfg.text, "config_source": str(cfg.source or ""), "config_fingerprint": cfg.fingerprint,
        "bearing": cfg.bearing.describe(), "bearing_json": json.dumps(cfg.bearing.to_dict()),
        "solver_method": cfg.method, "solver_rtol": opts.rtol, "solver_max_iter": opts.max_iter,
        "chunk": cfg.chunk, "compression": cfg.compression, "n_cases": cases.n_cases, "n_blocks": len(blocks),
        **storage.versions(),
    }
    storage.create(part, case_dims, extra_dims, scalars, storage.result_variables(cases.given), attrs, len(blocks),
                   case_coords)


def _progress(total: int, initial: int, show):
    show = sys.stderr.isatty() if show is None else show
    if not show:
        return None
    from tqdm import tqdm

    return tqdm(total=total, initial=initial, unit="case", unit_scale=True, dynamic_ncols=True, smoothing=0.1)


def loadmap(config, output=None, *, threads=None, resume=False, overwrite=False, progress=None,
            as_dataset=False, client=None, max_in_flight=None):
    """Compute a load map and write it to HDF5.

    Parameters
    ----------
    config : str, Path or dict
        A TOML config file with ``[bearing]`` and ``[loadmap]`` tables, or the same as a dict.
    output : str or Path, optional
        Output file (default: the config's path with suffix .h5). An existing
        file is never replaced unless ``overwrite``.
    threads : int, optional
        Numba threads (default: NUMBA_NUM_THREADS). Results do not depend on it.
    resume : bool
        Continue an interrupted run from ``OUTPUT.part`` (same config only).
    overwrite : bool
        Replace an existing output or discard an unfinished run.
    progress : bool, optional
        Progress bar on stderr (default: only when stderr is a terminal).
    as_dataset : bool
        Return an ``xarray.Dataset`` (needs xarray and h5netcdf) instead of the path.
    client : dask.distributed.Client, optional
        Run the blocks on a Dask cluster (see :mod:`fastbearing.distributed`);
        the output is identical to a local run.
    max_in_flight : int, optional
        Blocks out on the cluster at once (default: 2 per worker thread).

    Returns
    -------
    Path or xarray.Dataset
    """
    cfg = config if isinstance(config, LoadMapConfig) else read_config(config)
    check_threads(threads)
    if as_dataset:
        _require_xarray()
    if output is None:
        if cfg.source is None:
            raise ValueError("output is required when the config is not a file")
        output = Path(cfg.source.name).with_suffix(".h5")  # in the current folder, like every other output
    output = Path(output)
    storage.check_output_path(output)
    if not (resume and not storage.part_path(output).exists()):
        sizes = {"dof": 5, "dof_col": 5, "row": cfg.bearing.n_rows}
        storage.check_disk_space(output, cfg.cases.n_cases * storage.bytes_per_case(
            storage.result_variables(cfg.cases.given), sizes), f"this map ({cfg.cases.n_cases} cases)")
    out, part, resuming = storage.prepare_output(output, cfg.fingerprint, resume, overwrite)
    if resume and not part.exists():
        print(f"fastbearing: {out} is already complete; nothing to resume", file=sys.stderr)
        return open_dataset(out) if as_dataset else out.absolute()
    cases = cfg.cases
    blocks = plan_blocks(cases.shape, cases.line_length, cfg.chunk)
    if not resuming:
        _create(cfg, part, blocks)
    opts = solver_settings(cfg.bearing, cfg.method, cfg.rtol, cfg.max_iter)
    size = max(b.size for b in blocks)
    given_load = cases.given == "load"
    pf = storage.PartFile(part)
    started = time.perf_counter()
    done = pf.done_mask()
    pending = [b for b in blocks if not done[b.index]]
    bar = _progress(cases.n_cases, sum(b.size for b in blocks if done[b.index]), progress)
    on_written = (lambda b: bar.update(b.size)) if bar is not None else None
    try:
        with _Interrupt() as interrupt:
            if client is None:
                # two buffer sets: one being computed, one being written
                writer = storage.BlockWriter(pf, [_Buffers(size, cfg.bearing.n_rows) for _ in range(2)], on_written)
                with num_threads(threads):
                    _run_local(cfg, pending, given_load, opts, writer, interrupt)
            else:
                from .distributed import run_blocks

                writer = storage.BlockWriter(pf, [object() for _ in range(4)], on_written)
                engine = run_blocks(client, cfg, pending, given_load, opts, writer, interrupt, compute_block,
                                    max_in_flight)
                pf.fh.attrs.update(engine)
        if bar is not None:
            bar.close()
    except KeyboardInterrupt:
        pf.close()
        print(f"\nfastbearing: interrupted; finished blocks are kept in {part}; continue with --resume",
              file=sys.stderr)
        raise
    except BaseException:
        pf.close()
        raise
    computed = sum(b.size for b in pending)
    counts = _status_counts(pf)
    pf.close()
    wall = time.perf_counter() - started
    storage.finish(part, out, cfg.compression, blocks, {"wall_time_s": wall,
                   "status_counts": json.dumps({st.describe(c): k for c, k in counts.items()})},
                   [v.name for v in storage.result_variables(cases.given)])
    _summary(cases.n_cases, counts, wall, computed)
    return open_dataset(out) if as_dataset else out.absolute()


def _run_local(cfg, pending, given_load, opts, writer, interrupt) -> None:
    """Compute blocks here, overlapping each block's HDF5 write with the next block's compute."""
    try:
        for block in pending:
            buf = writer.buffer()
            res = buf.view(block.size)
            compute_block(cfg.bearing, given_load, cfg.cases.line_length, cfg.cases.inputs(block.start, block.stop),
                          opts, res)
            writer.submit(block, res, buf)
            if interrupt.requested:
                raise KeyboardInterrupt
    finally:
        writer.close()  # also on Ctrl-C: the block in flight is written and kept for --resume


def _status_counts(pf: storage.PartFile) -> dict[int, int]:
    """Cases per status code, read in slices so memory stays bounded."""
    counts: dict[int, int] = {}
    ds = pf.fh["status"]
    step = max(1, 4_000_000 // max(1, int(np.prod(ds.shape[1:]))))
    for a in range(0, ds.shape[0], step):
        codes, n = np.unique(ds[a:a + step], return_counts=True)
        for c, k in zip(codes.tolist(), n.tolist()):
            counts[c] = counts.get(c, 0) + k
    return counts


def _summary(n_cases: int, counts: dict[int, int], wall: float, computed: int) -> None:
    ok = sum(k for code, k in counts.items() if st.is_converged(code))
    by_status = ", ".join(f"{st.describe(code)} {k}" for code, k in sorted(counts.items(), key=lambda x: -x[1]))
    rate = computed / wall if wall > 0 else float("inf")
    print(f"fastbearing: {n_cases} cases, {100.0 * ok / n_cases:.2f} % converged ({by_status}); "
          f"{wall:.2f} s wall, {rate:,.0f} cases/s", file=sys.stderr)


def _require_xarray():
    """Check for xarray and h5netcdf before any work is done, not after."""
    try:
        import h5netcdf  # noqa: F401
        import xarray  # noqa: F401
    except ImportError:
        raise ImportError("as_dataset needs xarray and h5netcdf: pip install 'fastbearing[xarray]'") from None


def open_dataset(path):
    """Open a finished map as an ``xarray.Dataset`` (engine h5netcdf); refuses unfinished files."""
    path = Path(path)
    if not storage.is_complete(path):
        raise ValueError(f"{path} is not a finished fastbearing file")
    _require_xarray()
    import xarray as xr

    return xr.open_dataset(path, engine="h5netcdf")
