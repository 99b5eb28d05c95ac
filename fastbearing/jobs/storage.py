"""HDF5 storage of result grids (load maps and ball-passage tables), via h5py.

One schema, netCDF4-compatible: every dimension is an HDF5 dimension scale,
every variable carries ``units`` and ``long_name`` (attributes.cf_attributes:
one unit string, a name of at most 60 characters, each entry's units in
``units_per_entry`` where the entries of q, f or Kb differ), so
``xarray.open_dataset(path, engine="h5netcdf")`` opens a file as a labelled
Dataset whose automatic plot labels read ``long_name [units]``, and h5py or
HDFView read it as plain HDF5. Units: N, mm, rad.

Crash safety: a run writes ``OUT.h5.part``, whose datasets are contiguous and
allocated when created, so writing a block changes raw data only, never HDF5
metadata; a block is marked done (``block_done``) only after its data is
flushed. A killed run therefore leaves a readable ``.part`` from which
``resume`` continues. ``finish`` drops the bookkeeping, marks the file
complete and renames it to its final name (repacking it with compression if
asked), so a file under the final name is always complete.
"""

from __future__ import annotations

import errno
import os
import queue
import threading
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path

import h5py
import numpy as np

from .. import status as st
from ..dofs import DISPLACEMENT_UNITS, K_UNITS, LOAD_UNITS
from ..files import refuse_overwrite
from .attributes import cf_attributes
from .locations import (COMPLETE, RunLock, check_disk_space, check_folder, human_size,  # noqa: F401 (the runner's too)
                        slab_shape as _slab_shape)

#: Compressions a config may name: HDF5 takes none, lzf, gzip; a zarr store none, gzip, zstd (zarr_store.py).
COMPRESSIONS = ("none", "lzf", "gzip", "zstd")
HDF5_COMPRESSIONS = ("none", "lzf", "gzip")


@dataclass
class Variable:
    """A result variable: trailing (per-case) dims after the case dims."""

    name: str
    trailing: tuple[str, ...]
    dtype: str
    units: str
    long_name: str
    extra: dict = field(default_factory=dict)


@dataclass
class Coordinate:
    """A dimension with values (``is_dim``) or a scalar coordinate."""

    name: str
    values: np.ndarray
    units: str
    long_name: str
    is_dim: bool = True


def _inner_variable(inner):
    def make(name, trailing, dtype, units, long_name, extra=None):
        return Variable(name, tuple(inner) + tuple(trailing), dtype, units, long_name, extra or {})
    return make


def result_variables(given: str, inner: tuple[str, ...] = ()) -> list[Variable]:
    """The per-case result variables; ``inner`` dims (e.g. ("position",)) come between the case dims and
    each variable's own trailing dims."""
    V = _inner_variable(inner)
    codes = sorted(st.NAMES)                     # every outcome, so the file's key never lags the solver
    flag = {"flag_values": np.array(codes, np.int8),
            "flag_meanings": " ".join(st.NAMES[c] for c in codes),
            "comment": f"low 4 bits: outcome; +{st.CONTACT_REVERSED}: warning contact_reversed (a loaded ball's "
                       f"contact angle crossed zero against its row's contact direction); +{st.BEYOND_VALIDITY}: "
                       "warning beyond_validity (a ball's deflection exceeds its row's deflection_limit: the "
                       "Hertz pressure limit or 0.15 A0)"}
    return [
        V("q", ("dof",), "f8", DISPLACEMENT_UNITS[0], "inner-ring displacement (tilts bx, by in rad)",
          {"units_per_entry": list(DISPLACEMENT_UNITS),
           "comment": "q = (dx, dy, dz, bx, by) of the inner ring at the bearing centre"}),
        V("f", ("dof",), "f8", LOAD_UNITS[0], "load on the inner ring at q (moments Mx, My in N*mm)",
          {"units_per_entry": list(LOAD_UNITS), "comment": "f = (Fx, Fy, Fz, Mx, My) on the inner ring at q"}),
        V("K", ("dof", "dof_col"), "f8", K_UNITS, "stiffness Kb (tx, ty entries: N/rad, N*mm/rad)",
          {"comment": "Kb = df/dq: N/mm among x, y, z; N*mm/rad among tx, ty; N/rad between"}),
        V("status", (), "i1", "1", "solver status" if given == "load" else "status (0: direct substitution)",
          flag),
        V("iterations", (), "i4", "1", "solver iterations"),
        V("residual", (), "f8", "1", "relative residual of the solve",
          {"comment": "max|f(q) - f_target| / max|f_target|, moments / R"}),
        V("max_ball_load", ("row",), "f8", "N", "largest element load per row",
          {"comment": "a ball's load, or a roller's total"}),
        V("loaded_balls", ("row",), "i2", "1", "number of loaded elements (balls or rollers) per row"),
        V("min_contact_angle", ("row",), "f8", "rad", "smallest loaded contact angle per row",
          {"comment": "on the row's contact direction; nan if no ball is loaded"}),
        V("max_contact_angle", ("row",), "f8", "rad", "largest loaded contact angle per row"),
    ]


def life_variables(iso: bool = True, hours: bool = False) -> list[Variable]:
    """The rating-life variables of a map with ``life = true`` (fastbearing.analysis.life): L10r, per row,
    S0; with ``iso`` (the bearing is rated as a unit) ISO 281's L10; with ``hours`` (the map has a shaft
    speed) both lives in hours too."""
    V = _inner_variable(())
    out = [
        V("L10r", (), "f8", "million revolutions", "modified reference rating life L10r (ISO/TS 16281)",
          {"comment": "of the bearing; nan where the case did not converge, inf where nothing is loaded"}),
        V("L10r_row", ("row",), "f8", "million revolutions", "modified reference rating life L10r of each row"),
        V("static_safety", (), "f8", "1", "static safety factor S0 = C0/P0 (ISO 76)",
          {"comment": "of the bearing as a unit"}),
    ]
    if iso:
        out.append(V("L10", (), "f8", "million revolutions", "basic rating life L10 = (C/P)^p (ISO 281)",
                     {"comment": "P from the radial and axial load the ring carries; nan where the case did not "
                                 "converge"}))
    if hours:
        out.append(V("L10r_hours", (), "f8", "h", "L10r in hours at the case's shaft speed",
                     {"comment": "inf at 0 rpm"}))
        if iso:
            out.append(V("L10_hours", (), "f8", "h", "L10 in hours at the case's shaft speed",
                         {"comment": "inf at 0 rpm"}))
    return out


def outer_angle_variables() -> list[Variable]:
    """At speed the inner and outer contact angles differ: the outer contacts' extremes per row."""
    V = _inner_variable(())
    return [
        V("min_outer_contact_angle", ("row",), "f8", "rad", "smallest loaded outer-race contact angle per row",
          {"comment": "on the row's contact direction; at speed the outer angle falls below the inner one"}),
        V("max_outer_contact_angle", ("row",), "f8", "rad", "largest loaded outer-race contact angle per row"),
    ]


def allocate(variables: list[Variable], sizes: dict[str, int], n: int) -> dict[str, np.ndarray]:
    """Result arrays for ``n`` cases from the one description of the variables (``sizes``: length of
    each trailing dim by name): what a block computes into, here or on a Dask worker."""
    return {v.name: np.empty((n, *(sizes[d] for d in v.trailing)), v.dtype) for v in variables}


def check_output_path(out: Path) -> None:
    """One-line ValueError unless ``out`` can be written: its folder exists and is writable, and it is
    not itself a folder. Called before anything is computed or created."""
    if out.is_dir():
        raise ValueError(f"output {out} is a directory; give a file name such as {out / 'map.h5'}")
    check_folder(out)


def bytes_per_case(variables: list[Variable], sizes: dict[str, int]) -> int:
    """Bytes one case takes in the file: every variable with its trailing dims (``sizes`` by dim name)."""
    total = 0
    for v in variables:
        n = np.dtype(v.dtype).itemsize
        for d in v.trailing:
            n *= sizes[d]
        total += n
    return total


def prepare_output(out: Path, fingerprint: str, resume: bool, overwrite: bool) -> tuple[Path, Path, bool]:
    """Final path, working path, and whether to resume; refuses to clobber anything unasked."""
    check_output_path(out)
    part = part_path(out)
    if resume and overwrite:
        raise ValueError("choose one of resume and overwrite")
    if part.exists():
        if resume:
            try:
                with h5py.File(part, "r") as fh:
                    same = fh.attrs.get("config_fingerprint") == fingerprint
            except OSError:
                raise ValueError(f"{part} is not a readable partial run; start again with --overwrite (Python: "
                                 "overwrite=True)") from None
            if not same:
                raise ValueError(f"{part} was started from a different config (or case file); "
                                 "resume needs the same config, or start again with --overwrite (Python: "
                                 "overwrite=True)")
            return out, part, True
        if not overwrite:
            raise ValueError(f"an unfinished run exists at {part}: resume it (--resume) or start again "
                             "(--overwrite)")
        part.unlink()
    elif resume and not out.exists():
        raise ValueError(f"nothing to resume: {part} does not exist")
    elif resume:
        if _fingerprint(out) != fingerprint:
            raise ValueError(f"{out} is complete but was made from a different config (or case file); "
                             "--resume continues only the same config: choose another -o, or --overwrite")
    if not resume:
        refuse_overwrite(out, overwrite)
    return out, part, False


def _fingerprint(path: Path) -> str | None:
    try:
        with h5py.File(path, "r") as fh:
            value = fh.attrs.get("config_fingerprint")
    except OSError:
        return None
    return value.decode() if isinstance(value, bytes) else value


def part_path(path: Path) -> Path:
    return path.with_name(path.name + ".part")


def _early_dcpl() -> h5py.h5p.PropDCID:
    # allocate the whole dataset at creation and never write fill values:
    # later block writes then only touch raw data (crash safety, see module doc)
    dcpl = h5py.h5p.create(h5py.h5p.DATASET_CREATE)
    dcpl.set_alloc_time(h5py.h5d.ALLOC_TIME_EARLY)
    dcpl.set_fill_time(h5py.h5d.FILL_TIME_NEVER)
    return dcpl


def _set_attrs(ds, attrs: dict) -> None:
    """Write ``attrs`` on an HDF5 dataset; a list of texts as HDF5 variable-length strings (netCDF's NC_STRING)."""
    for k, val in attrs.items():
        if isinstance(val, list) and all(isinstance(x, str) for x in val):
            val = np.array(val, dtype=h5py.string_dtype())
        ds.attrs[k] = val


def create(path: Path, case_dims: list[Coordinate], extra_dims: list[Coordinate], scalars: list[Coordinate],
           variables: list[Variable], attrs: dict, n_blocks: int, aux_coords=()) -> None:
    """Create the working file ``path`` (a ``.part``) with every dataset allocated.

    ``aux_coords`` are (Coordinate, dim name) pairs: coordinates along a
    dimension that are not its index, e.g. Fx(case) or cage_angle(position).
    """
    shape = tuple(len(c.values) for c in case_dims)
    with h5py.File(path, "w", track_order=True) as fh:
        for c in (*case_dims, *extra_dims):
            values = np.asarray(c.values)
            # text labels (the dof names) as HDF5's variable-length strings, which netCDF readers take
            ds = fh.create_dataset(c.name, data=values.astype(h5py.string_dtype()) if values.dtype.kind in "UO"
                                   else values)
            ds.make_scale(c.name)
            _set_attrs(ds, cf_attributes(None if values.dtype.kind in "UO" else c.units, c.long_name))
        dims = {c.name: fh[c.name] for c in (*case_dims, *extra_dims)}
        coord_names = [c.name for c in scalars] + [c.name for c, _ in aux_coords]
        for c in scalars:
            ds = fh.create_dataset(c.name, data=np.float64(c.values[0]))
            _set_attrs(ds, cf_attributes(c.units, c.long_name))
        for c, dim in aux_coords:
            ds = fh.create_dataset(c.name, data=c.values)
            ds.dims[0].attach_scale(dims[dim])
            _set_attrs(ds, cf_attributes(c.units, c.long_name))
        for v in variables:
            vshape = shape + tuple(len(dims[t]) for t in v.trailing)
            ds = fh.create_dataset(v.name, shape=vshape, dtype=v.dtype, dcpl=_early_dcpl())
            for axis, name in enumerate([c.name for c in case_dims] + list(v.trailing)):
                ds.dims[axis].attach_scale(dims[name])
            _set_attrs(ds, cf_attributes(v.units, v.long_name, v.trailing, v.extra))
            if coord_names:
                ds.attrs["coordinates"] = " ".join(coord_names)
        blocks = fh.create_dataset("block", data=np.arange(n_blocks, dtype=np.int64))
        blocks.make_scale("block")
        done = fh.create_dataset("block_done", shape=(n_blocks,), dtype="u1", dcpl=_early_dcpl())
        done[...] = 0
        done.dims[0].attach_scale(blocks)
        for k, val in attrs.items():
            fh.attrs[k] = val
        fh.attrs[COMPLETE] = 0


class PartFile:
    """An open working file: write blocks, mark them done."""

    def __init__(self, path: Path):
        self.path = path
        self.fh = h5py.File(path, "r+")

    def done_mask(self) -> np.ndarray:
        return self.fh["block_done"][...].astype(bool)

    def write(self, slab: tuple, arrays: dict[str, np.ndarray]) -> None:
        for name, values in arrays.items():
            ds = self.fh[name]
            ds[slab] = values.reshape(_slab_shape(ds.shape, slab))

    def write_block(self, block, arrays: dict[str, np.ndarray]) -> None:
        """Write a finished block, then mark it done."""
        self.write(block.slab, arrays)
        self.mark_done(block.index)

    def mark_done(self, index: int) -> None:
        # data first, then the mark: a kill in between only redoes the block
        self.fh.flush()
        self.fh["block_done"][index] = 1
        self.fh.flush()

    def update_attrs(self, attrs: dict) -> None:
        """File attributes added or replaced (e.g. a distributed run's provenance)."""
        self.fh.attrs.update(attrs)

    def value_counts(self, name: str) -> dict[int, int]:
        """How often each value occurs in the integer variable ``name`` (status codes), read in slices so
        that memory stays bounded whatever the file's size."""
        counts: dict[int, int] = {}
        ds = self.fh[name]
        step = max(1, 4_000_000 // max(1, int(np.prod(ds.shape[1:]))))
        for a in range(0, ds.shape[0], step):
            codes, n = np.unique(ds[a:a + step], return_counts=True)
            for c, k in zip(codes.tolist(), n.tolist()):
                counts[c] = counts.get(c, 0) + k
        return counts

    def close(self) -> None:
        self.fh.close()


def finished_blocks(part: Path) -> int:
    """How many blocks a working file holds finished (0 where it cannot be read: a message must still come
    out of a full disk, whatever the file's state)."""
    try:
        with h5py.File(part, "r") as fh:
            return int(fh["block_done"][...].sum())
    except Exception:  # noqa: BLE001
        return 0


class ResultFile:
    """A result store opened for reading, by variable name: what the readers (export, passage CSV, case
    tables) need of a file, without an HDF5 handle of their own. ValueError for a file that cannot be read.

    ``names()`` the variables and coordinates; ``has(name)``; ``shape``, ``dtype``, ``ndim`` of one;
    ``dims(name)`` the dimension name of each axis ('' where none); ``attrs(name)`` its attributes (text
    decoded) and ``file_attrs`` the file's; ``read(name, index)`` its values (all, or ``index``).
    """

    def __new__(cls, path):
        from .zarr_store import ZarrReader, is_zarr_location

        if is_zarr_location(path):                # the same reading methods on a zarr store
            return ZarrReader(path)
        return super().__new__(cls)

    def __init__(self, path: Path):
        self.path = Path(path)
        try:
            self._fh = h5py.File(self.path, "r")
        except OSError:
            raise ValueError(f"{self.path} is not a readable HDF5 file") from None
        self.file_attrs = _decoded(self._fh.attrs)

    def __enter__(self) -> "ResultFile":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        self._fh.close()

    def names(self) -> list[str]:
        return [k for k, v in self._fh.items() if isinstance(v, h5py.Dataset)]

    def has(self, name: str) -> bool:
        return isinstance(self._fh.get(name), h5py.Dataset)

    def shape(self, name: str) -> tuple[int, ...]:
        return self._fh[name].shape

    def ndim(self, name: str) -> int:
        return self._fh[name].ndim

    def dtype(self, name: str) -> np.dtype:
        return self._fh[name].dtype

    def dims(self, name: str) -> list[str]:
        out = []
        for d in self._fh[name].dims:
            scales = list(d.keys())
            out.append(scales[0] if scales else "")
        return out

    def attrs(self, name: str) -> dict:
        return _decoded(self._fh[name].attrs)

    def read(self, name: str, index=()) -> np.ndarray:
        try:
            return self._fh[name][index]
        except OSError:
            raise ValueError(f"{self.path}: {name} cannot be read (a damaged HDF5 file?)") from None


def _decoded(attrs) -> dict:
    """An HDF5 attribute set as a dict, bytes decoded to text."""
    return {k: (v.decode() if isinstance(v, bytes) else v) for k, v in attrs.items()}


class BlockWriter:
    """Writes finished blocks on a background thread while the next block computes.

    The kernels release the GIL, so computing block k+1 overlaps writing
    block k (the disk is as slow as the compute here). Each block is written,
    flushed, then marked done, in order, exactly as in the serial path. The
    caller owns a fixed set of buffers and gets one back with
    :meth:`buffer` once it has been written out: memory stays bounded.
    """

    def __init__(self, part_file: PartFile, buffers: list, on_written=None):
        self.part_file = part_file
        self.on_written = on_written
        self.error: BaseException | None = None
        self._free: queue.Queue = queue.Queue()
        for b in buffers:
            self._free.put(b)
        self._todo: queue.Queue = queue.Queue()
        self._thread = threading.Thread(target=self._run, name="fastbearing-writer", daemon=True)
        self._thread.start()

    def buffer(self):
        """A buffer that is free to fill (waits while all are being written)."""
        buf = self._free.get()
        self._raise()
        return buf

    def submit(self, block, arrays: dict, buf) -> None:
        """Queue ``arrays`` (views into ``buf``) to be written as ``block``."""
        self._raise()
        self._todo.put((block, arrays, buf))

    def close(self) -> None:
        """Wait until every submitted block is written and marked done."""
        self._todo.put(None)
        self._thread.join()
        self._raise()

    def _run(self):
        while True:
            item = self._todo.get()
            if item is None:
                return
            block, arrays, buf = item
            try:
                if self.error is None:
                    self.part_file.write_block(block, arrays)
                    if self.on_written is not None:
                        self.on_written(block)
            except BaseException as err:  # handed to the caller's thread
                self.error = err
            finally:
                self._free.put(buf)

    def _raise(self):
        if self.error is not None:
            raise self.error


def finish(part: Path, final: Path, compression: str, blocks, attrs: dict, variables: list[str]) -> None:
    """Mark ``part`` complete and move it to ``final`` (repacked with compression if asked).

    Every step can be repeated: a run killed anywhere in here leaves a
    complete ``.part`` (or the final file), and ``resume`` calls this again.
    """
    with h5py.File(part, "r+") as fh:
        for k, val in attrs.items():
            fh.attrs[k] = val
        fh.attrs[COMPLETE] = 1
        fh.attrs["completed"] = datetime.now(timezone.utc).isoformat(timespec="seconds")
    if compression == "none":
        _drop_bookkeeping(part)
        os.replace(part, final)
        return
    packed = final.with_name(final.name + ".packing")
    # the compressed copy is at most as large as the data: refuse before HDF5 meets a full disk, which it
    # does not survive gracefully (errors from object destructors, or worse)
    import shutil

    if shutil.disk_usage(final.parent if str(final.parent) else ".").free < os.path.getsize(part):
        raise OSError(errno.ENOSPC, f"No space left on device to write the compressed copy of {part}")
    _repack(part, packed, compression, blocks, variables)
    os.replace(packed, final)
    part.unlink()


def _drop_bookkeeping(path: Path) -> None:
    with h5py.File(path, "r+") as fh:
        for name in ("block_done", "block"):    # a finish killed half-way may have dropped them already
            if name in fh:
                del fh[name]


_SCALE_ATTRS = ("DIMENSION_LIST", "REFERENCE_LIST", "CLASS", "NAME", "_Netcdf4Dimid", "_Netcdf4Coordinates")


def _repack(src: Path, dst: Path, compression: str, blocks, big: list[str]) -> None:
    """Copy src to dst with the data variables chunked by block and compressed, one block at a time."""
    chunk_slab = blocks[0].slab
    with h5py.File(src, "r") as fi, h5py.File(dst, "w", track_order=True) as fo:
        names = [n for n in fi if n not in ("block", "block_done")]
        for name in names:
            ds = fi[name]
            if name in big:
                out = fo.create_dataset(name, shape=ds.shape, dtype=ds.dtype, chunks=_slab_shape(ds.shape, chunk_slab),
                                        compression=compression, shuffle=True)
            else:
                out = fo.create_dataset(name, data=ds[()])
            for k, val in ds.attrs.items():
                if k not in _SCALE_ATTRS:
                    out.attrs[k] = val
            if h5py.h5ds.is_scale(ds.id):
                out.make_scale(name)
        for name in names:
            for axis, dim in enumerate(fi[name].dims):
                for scale in dim.values():
                    scale_name = scale.name.lstrip("/")
                    if scale_name != name:
                        fo[name].dims[axis].attach_scale(fo[scale_name])
        for k, val in fi.attrs.items():
            fo.attrs[k] = val
        for name in big:
            for b in blocks:
                fo[name][b.slab] = fi[name][b.slab]


class Hdf5Store:
    """One HDF5 file as the runner (runner.py) sees a store: a working ``OUT.h5.part`` renamed to ``OUT.h5``
    when finished. Its twin for zarr stores is zarr_store.ZarrStore."""

    format = "hdf5"

    def __init__(self, output):
        self.out = Path(output)
        self.part = part_path(self.out)

    @property
    def part_name(self) -> str:
        return str(self.part)

    def result(self) -> Path:
        return self.out.absolute()

    def check(self, compression: str) -> None:
        check_output_path(self.out)
        if compression not in HDF5_COMPRESSIONS:
            raise ValueError(f"compression = {compression!r} is for zarr stores; an HDF5 file takes one of "
                             f"{', '.join(HDF5_COMPRESSIONS)}")

    def check_space(self, n_bytes: int, what: str) -> None:
        check_disk_space(self.out, n_bytes, what)

    def lock(self) -> "RunLock":
        return RunLock(self.out)

    def unfinished(self) -> bool:
        return self.part.exists()

    def prepare(self, fingerprint: str, resume: bool, overwrite: bool) -> str:
        """'new', 'resume' or 'done' (complete, same config, resume asked); see prepare_output."""
        _, _, resuming = prepare_output(self.out, fingerprint, resume, overwrite)
        if resume and not self.part.exists():
            return "done"
        return "resume" if resuming else "new"

    def all_done(self) -> bool:
        """The working file was marked complete (a run killed while finishing)."""
        return is_complete(self.part)

    def tasks(self, blocks, shape, resuming: bool = False):
        return blocks

    def create(self, case_dims, extra_dims, scalars, variables, attrs, blocks, tasks, compression,
               aux_coords=()) -> None:
        create(self.part, case_dims, extra_dims, scalars, variables, attrs, len(tasks), aux_coords)

    def open_part(self) -> PartFile:
        return PartFile(self.part)

    def worker_sink(self):
        """None: Dask workers send their blocks back and this process writes them (one HDF5 writer)."""
        return None

    def finished_blocks(self) -> int:
        return finished_blocks(self.part)

    def finish(self, compression: str, blocks, attrs: dict, variables: list[str]) -> None:
        finish(self.part, self.out, compression, blocks, attrs, variables)


def add_file_attributes(output, attrs: dict) -> None:
    """Add attributes to a finished result (an HDF5 file, or a zarr store: its root group; consolidated
    metadata is written again), e.g. a summary computed from the whole file. Repeating it is harmless."""
    from .zarr_store import is_zarr_location

    if is_zarr_location(output):
        from .zarr_store import add_attributes

        add_attributes(output, attrs)
        return
    with h5py.File(output, "r+") as fh:
        for k, v in attrs.items():
            fh.attrs[k] = v


def store_for(output):
    """The store an output names: a zarr store for ``*.zarr`` and URLs, else an HDF5 file."""
    from .zarr_store import ZarrStore, is_zarr_location

    return ZarrStore(output) if is_zarr_location(output) else Hdf5Store(output)


def is_complete(path: Path) -> bool:
    try:
        with h5py.File(path, "r") as fh:
            return int(fh.attrs.get(COMPLETE, 0)) == 1
    except OSError:
        return False


def versions() -> dict:
    """Provenance: versions of the packages that made a file."""
    import numba

    from .. import __version__

    return {"fastbearing_version": __version__, "numba_version": numba.__version__, "h5py_version": h5py.__version__,
            "numpy_version": np.__version__, "hdf5_version": h5py.version.hdf5_version,
            "created": datetime.now(timezone.utc).isoformat(timespec="seconds")}
