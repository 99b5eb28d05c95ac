"""Zarr v3 stores of result grids: the HDF5 file's twin, written block by block by whoever computed the block.

The same variables, coordinates, units and status flags as storage.py's
HDF5 layout (the same attributes: attributes.cf_attributes), as one zarr v3
group: every array names its dimensions (``dimension_names``), so ``xarray.open_zarr(path)`` opens a finished store
as the same labelled Dataset as ``xarray.open_dataset(file.h5)``.

The grid is chunked along the case dimensions exactly as the runner cuts it
into blocks (grid.plan_blocks), so every block is whole chunks and a block is
written by one writer with no lock, here or on a Dask worker. A map of more
than ``MAX_UNSHARDED_BLOCKS`` blocks groups consecutive blocks into shards
(one object per shard and variable, not per block), and a shard becomes the
unit of work: a 1e9-case map is a few thousand objects, not millions.

Crash safety without renames (which object stores do not have): a block is
recorded done in the bookkeeping array ``block_counts`` (its status counts)
only after its data is written; a killed run, client or worker, leaves the
store with ``fastbearing_complete = 0`` and ``--resume`` redoes only the
blocks not recorded. ``finish`` drops the bookkeeping, marks the store
complete and consolidates the metadata; readers refuse an unfinished store.

Locations: a local path (``map.zarr``) or any fsspec URL (``s3://bucket/map.zarr``,
``gcs://``, ``abfs://``, ``file://``) with the user's usual credentials.
Needs ``pip install 'fastbearing[zarr]'`` (zarr >= 3, fsspec). Units: N, mm, rad.
"""

from __future__ import annotations

import os
import socket
import uuid
import warnings
from dataclasses import replace
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

from ..files import OutputExists
from .locations import COMPLETE, RunLock, alive, check_disk_space, check_folder, is_url, slab_shape
from .attributes import cf_attributes

#: The runner's blocks (grid.Block: index, start, stop, slab), named in annotations only: this module makes
#: none of its own, and grid reads stores (case files), so importing it here would close a circle.
Block = "grid.Block"

CREATED = "fastbearing_created"             # set once every array exists: a store cut off while created is not resumed
RUN_ID = "fastbearing_run_id"               # unique to one creation: workers write only into the store they were sent
BOOKKEEPING = "block_counts"
COMPRESSIONS = ("none", "gzip", "zstd")
#: Up to this many blocks, one chunk (one object per variable) per block; beyond it, shards of several blocks.
MAX_UNSHARDED_BLOCKS = 512
#: The most cases one shard (one unit of work) may hold: its buffers then take about 90 MB a set at the
#: 1M example's 345 bytes a case (a local run holds two sets, a worker one).
MAX_SHARD_CASES = 262_144
#: Status codes are int8: a block's counts are kept for all 256 values (index = code + 128).
N_CODES = 256


def is_zarr_location(output) -> bool:
    """True for a zarr store: a name ending in .zarr (any case), or any URL (fsspec), which HDF5 cannot write."""
    text = str(output).rstrip("/")
    return text.lower().endswith(".zarr") or is_url(text)


def require_zarr():
    """The zarr module, or one line saying how to install it."""
    try:
        import zarr
    except ImportError:
        raise ValueError("a zarr store needs zarr 3: pip install 'fastbearing[zarr]'") from None
    if int(zarr.__version__.split(".")[0]) < 3:
        raise ValueError(f"a zarr store needs zarr >= 3 (found {zarr.__version__}): pip install 'fastbearing[zarr]'")
    return zarr


def _fs(where: str):
    """(fsspec filesystem, path) of a URL; one-line ValueError for an unknown protocol or a missing driver."""
    try:
        import fsspec
    except ImportError:
        raise ValueError(f"{where}: a URL location needs fsspec: pip install 'fastbearing[zarr]'") from None
    try:
        return fsspec.core.url_to_fs(where)
    except ImportError as err:
        raise ValueError(f"{where}: {str(err).splitlines()[0]}") from None
    except ValueError as err:                       # "Protocol not known: foo"
        raise ValueError(f"{where}: not a location fsspec knows ({err})") from None


def _jsonable(value):
    """An attribute value as JSON takes it (numpy scalars and arrays become numbers and lists)."""
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, bytes):
        return value.decode()
    return value                                  # inf and nan too: zarr writes them as JSON's Infinity and NaN


def _codecs(compression: str):
    from zarr.codecs import BloscCodec, GzipCodec

    return {"none": None, "gzip": GzipCodec(level=4),
            "zstd": BloscCodec(cname="zstd", clevel=3, shuffle="shuffle")}[compression]


# -- chunks and shards from the runner's blocks -------------------------------------------------------------

def chunk_shape(blocks: list[Block], shape: tuple[int, ...]) -> tuple[int, ...]:
    """The chunk along the case dimensions: the first block's hyperslab (plan_blocks tiles the grid regularly)."""
    out = []
    for n, s in zip(shape, blocks[0].slab):
        out.append(1 if isinstance(s, (int, np.integer)) else len(range(*s.indices(n))))
    return tuple(out) + tuple(shape[len(blocks[0].slab):])


def _blocking_dim(blocks: list[Block]) -> int | None:
    """The dimension along which consecutive blocks follow each other: the first block's one ranged slice
    (plan_blocks: fixed leading indices, a range, whole trailing dims); None for a single block."""
    if len(blocks) < 2:
        return None
    return next((d for d, s in enumerate(blocks[0].slab) if isinstance(s, slice) and s != slice(None)), None)


def shard_tasks(blocks: list[Block], shape: tuple[int, ...]) -> tuple[list[Block], tuple[int, ...] | None]:
    """Group consecutive blocks into shards where there are too many blocks for one object each.

    Returns (tasks, shard shape or None): each task is one block or the union of consecutive blocks along
    the blocking dimension (a hyperslab again, contiguous in C order), which whole shards cover. Results do
    not change: blocks never cut a continuation segment, and neither does their union.
    """
    d = _blocking_dim(blocks)
    chunk = chunk_shape(blocks, shape)
    if len(blocks) <= MAX_UNSHARDED_BLOCKS or d is None:
        return blocks, None
    per_block = int(np.prod(chunk))
    along = -(-shape[d] // chunk[d])
    group = min(-(-len(blocks) // MAX_UNSHARDED_BLOCKS), max(1, MAX_SHARD_CASES // per_block), along)
    if group < 2:
        return blocks, None
    step = chunk[d] * group
    tasks: list[Block] = []
    for b in blocks:
        s = b.slab[d]
        key = b.slab[:d] + (s.start // step,)
        if tasks and tasks[-1].slab[:d] + (tasks[-1].slab[d].start // step,) == key:
            last = tasks[-1]
            slab = last.slab[:d] + (slice(last.slab[d].start, s.stop),) + last.slab[d + 1:]
            tasks[-1] = replace(last, stop=b.stop, slab=slab)
        else:
            tasks.append(replace(b, index=len(tasks)))
    shard = chunk[:d] + (step,) + chunk[d + 1:]
    return tasks, shard


def layout(chunk, shard, n_tasks: int) -> dict:
    """The attributes that say how a store is cut: its chunk and shard shapes and its number of units of work."""
    return {"zarr_chunk": list(chunk), "zarr_shard": list(shard) if shard else "none", "zarr_tasks": n_tasks}


# -- the store ------------------------------------------------------------------------------------------

class ZarrStore:
    """A zarr v3 store at a local path or an fsspec URL, seen by the runner (runner.py) as HDF5's twin."""

    format = "zarr"

    def __init__(self, output):
        self.where = str(output).rstrip("/")
        if self.where.startswith("file://"):        # a local path written as a URL: the same store
            from urllib.parse import unquote, urlparse

            self.where = unquote(urlparse(self.where).path)
        if is_url(self.where) and not self.where.lower().endswith(".zarr"):
            raise ValueError(f"{self.where}: a URL output is written as a zarr store; name it ....zarr (an HDF5 "
                             "file needs a local path)")
        # workers open the store by this name: a local one by its absolute path (their folders differ)
        self.local = None if is_url(self.where) else Path(self.where).absolute()
        if self.local is not None:
            self.where = str(self.local)
        self._zarr = require_zarr()

    # what messages call it: the store itself holds the finished blocks (no separate working name)
    @property
    def part_name(self) -> str:
        return self.where

    def result(self):
        """What a finished run returns: the absolute path, or the URL."""
        return self.local.absolute() if self.local is not None else self.where

    # -- checks before anything is created
    def check(self, compression: str) -> None:
        if compression not in COMPRESSIONS:
            raise ValueError(f"compression = {compression!r} is HDF5's; a zarr store takes one of "
                             f"{', '.join(COMPRESSIONS)}")
        if self.local is not None:
            check_folder(self.local)
            if self.local.exists() and not self.local.is_dir():
                raise ValueError(f"{self.local} is a file, not a zarr store; choose another -o")
            return
        fs, path = _fs(self.where)
        parent = path.rsplit("/", 1)[0] if "/" in path else path
        try:
            fs.exists(parent)
        except Exception as err:  # noqa: BLE001 - any driver's failure (credentials, network) becomes one line
            raise ValueError(f"{self.where}: cannot reach the location ({type(err).__name__}: "
                             f"{str(err).splitlines()[0] if str(err) else 'no detail'})") from None

    def check_space(self, n_bytes: int, what: str) -> None:
        if self.local is not None:
            check_disk_space(self.local, n_bytes, what)

    def lock(self):
        return RunLock(self.local) if self.local is not None else _UrlLock(self.where)

    # -- state
    def _group(self, mode="r"):
        return self._zarr.open_group(store=self.where, mode=mode, zarr_format=3)

    def _exists(self) -> bool:
        if self.local is not None:
            return self.local.exists()
        fs, path = _fs(self.where)
        return fs.exists(path)

    def _attrs(self) -> dict | None:
        """The root attributes, or None where the location holds no zarr v3 group."""
        try:
            return dict(self._group().attrs)
        except Exception:  # noqa: BLE001 - not a store (or not ours)
            return None

    def unfinished(self) -> bool:
        attrs = self._attrs() if self._exists() else None
        return attrs is not None and int(attrs.get(COMPLETE, 1)) == 0

    def prepare(self, fingerprint: str, resume: bool, overwrite: bool) -> str:
        """'new', 'resume' or 'done' (complete, same config, resume asked); refuses to clobber anything unasked."""
        if resume and overwrite:
            raise ValueError("choose one of resume and overwrite")
        if not self._exists():
            if resume:
                raise ValueError(f"nothing to resume: {self.where} does not exist")
            return "new"
        attrs = self._attrs()
        if attrs is None or "config_fingerprint" not in attrs:
            raise ValueError(f"{self.where} exists and is not a fastbearing zarr store; choose another -o")
        same = attrs.get("config_fingerprint") == fingerprint
        if int(attrs.get(COMPLETE, 0)) == 0:
            if resume:
                if not same:
                    raise ValueError(f"{self.where} was started from a different config (or case file); resume "
                                     "needs the same config, or start again with --overwrite (Python: overwrite=True)")
                if int(attrs.get(CREATED, 0)) != 1:
                    raise ValueError(f"{self.where} was cut off while being created; start again with --overwrite")
                return "resume"
            if not overwrite:
                raise ValueError(f"an unfinished run exists at {self.where}: resume it (--resume) or start again "
                                 "(--overwrite)")
        elif resume:
            if not same:
                raise ValueError(f"{self.where} is complete but was made from a different config (or case file); "
                                 "--resume continues only the same config: choose another -o, or --overwrite")
            return "done"
        elif not overwrite:
            raise OutputExists(self.where)
        self._delete()
        return "new"

    def _delete(self) -> None:
        if self.local is not None:
            import shutil

            shutil.rmtree(self.local)
        else:
            fs, path = _fs(self.where)
            fs.rm(path, recursive=True)

    def all_done(self) -> bool:
        """Every block recorded (a run killed while finishing)."""
        return bool(self.open_part().done_mask().all())

    # -- creating
    def tasks(self, blocks: list[Block], shape: tuple[int, ...], resuming: bool = False) -> list[Block]:
        """The units of work: the blocks, or shards of consecutive blocks (shard_tasks). Resuming, the store's
        own cut must be the one computed now (else its records would name other blocks)."""
        tasks, shard = shard_tasks(blocks, shape)
        if resuming:
            attrs = self._attrs() or {}
            now = layout(chunk_shape(blocks, shape), shard, len(tasks))
            if any(attrs.get(k) != v for k, v in now.items()):
                raise ValueError(f"{self.where} was cut into chunks and shards otherwise than this version cuts the "
                                 "same config; start again with --overwrite")
        return tasks

    def create(self, case_dims, extra_dims, scalars, variables, attrs: dict, blocks: list[Block],
               tasks: list[Block], compression: str, aux_coords=()) -> None:
        """Create the group with every array (no data yet), the bookkeeping, and the attributes."""
        zarr = self._zarr
        shape = tuple(len(c.values) for c in case_dims)
        chunk = chunk_shape(blocks, shape)
        _, shard = shard_tasks(blocks, shape)
        # the root and its identity in one object: a store cut off after this is ours (--overwrite replaces it)
        identity = {k: _jsonable(v) for k, v in attrs.items()} | {
            COMPLETE: 0, CREATED: 0, RUN_ID: uuid.uuid4().hex, **layout(chunk, shard, len(tasks))}
        g = zarr.open_group(store=self.where, mode="w-", zarr_format=3, attributes=identity)
        counts = g.create_array(BOOKKEEPING, shape=(len(tasks), N_CODES), dtype="i8", chunks=(1, N_CODES),
                                dimension_names=["block", "status_code"], fill_value=0)
        counts.attrs.update(cf_attributes("1", "solves per status code of each finished block",
                                          extra={"comment": "index = code + 128; dropped when the store is "
                                                            "finished"}))
        lengths = {}
        for c in (*case_dims, *extra_dims):
            values = np.asarray(c.values)
            lengths[c.name] = len(values)
            a = g.create_array(c.name, shape=values.shape, dtype=str if values.dtype.kind in "UO" else values.dtype,
                               dimension_names=[c.name], compressors=None)
            a[...] = values.astype(str) if values.dtype.kind in "UO" else values
            units = None if values.dtype.kind in "UO" else c.units     # text labels (dof): no quantity, no units
            a.attrs.update({k: _jsonable(val) for k, val in cf_attributes(units, c.long_name).items()})
        coord_names = [c.name for c in scalars] + [c.name for c, _ in aux_coords]
        for c in scalars:
            a = g.create_array(c.name, shape=(), dtype="f8", dimension_names=[], compressors=None)
            a[...] = np.float64(c.values[0])
            a.attrs.update({k: _jsonable(val) for k, val in cf_attributes(c.units, c.long_name).items()})
        for c, dim in aux_coords:
            values = np.asarray(c.values)
            a = g.create_array(c.name, shape=values.shape, dtype=values.dtype, dimension_names=[dim],
                               compressors=None)
            a[...] = values
            a.attrs.update({k: _jsonable(val) for k, val in cf_attributes(c.units, c.long_name).items()})
        codecs = _codecs(compression)
        for v in variables:
            trailing = tuple(lengths[t] for t in v.trailing)
            kw = {"chunks": chunk + trailing}
            if shard is not None:
                kw["shards"] = shard + trailing
            a = g.create_array(v.name, shape=shape + trailing, dtype=v.dtype, compressors=codecs, fill_value=0,
                               dimension_names=[c.name for c in case_dims] + list(v.trailing), **kw)
            a.attrs.update({**{k: _jsonable(val) for k, val in cf_attributes(v.units, v.long_name, v.trailing,
                                                                             v.extra).items()},
                            **({"coordinates": " ".join(coord_names)} if coord_names else {})})
        g.attrs[CREATED] = 1

    # -- writing
    def open_part(self) -> "ZarrPart":
        return ZarrPart(self.where)

    def worker_sink(self) -> dict:
        """What a Dask worker needs to write its own blocks: the location (absolute) and the store's run id."""
        return {"where": self.where, "run_id": (self._attrs() or {}).get(RUN_ID, "")}

    def finished_blocks(self) -> int:
        try:
            return int(self.open_part().done_mask().sum())
        except Exception:  # noqa: BLE001 - a message must still come out, whatever the store's state
            return 0

    def finish(self, compression: str, blocks, attrs: dict, variables: list[str]) -> None:
        """Record the run's attributes, drop the bookkeeping, mark the store complete, consolidate its metadata.
        Each step may be repeated: a run killed in here finishes on --resume."""
        g = self._group("r+")
        g.attrs.update({k: _jsonable(v) for k, v in attrs.items()})
        if BOOKKEEPING in g:                         # every block is done (a cut-off finish: see done_mask)
            del g[BOOKKEEPING]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")         # "consolidated metadata is not part of the v3 spec": xarray reads it
            self._zarr.consolidate_metadata(self.where)
        # last: the mark (root attributes written through a handle opened after consolidating keep it)
        final = self._group("r+").attrs
        final.update({COMPLETE: 1, "completed": datetime.now(timezone.utc).isoformat(timespec="seconds")})
        final.pop(CREATED, None)                     # bookkeeping, as the HDF5 file drops its own


def add_attributes(where, attrs: dict) -> None:
    """Add attributes to a finished store's root group and consolidate its metadata again (storage.add_file_attributes)."""
    zarr = require_zarr()
    where = str(where)
    zarr.open_group(store=where, mode="r+", zarr_format=3).attrs.update({k: _jsonable(v) for k, v in attrs.items()})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        zarr.consolidate_metadata(where)


class ZarrPart:
    """An open unfinished store: write blocks (data, then the block's status counts), read what is done."""

    def __init__(self, where: str):
        zarr = require_zarr()
        self.where = where
        self.group = zarr.open_group(store=where, mode="r+", zarr_format=3)
        self._arrays: dict = {}

    def _array(self, name):
        if name not in self._arrays:
            # every chunk is written as computed: no scan for chunks that equal the fill value (a third of a write)
            self._arrays[name] = self.group[name].with_config({"write_empty_chunks": True})
        return self._arrays[name]

    def run_id(self) -> str:
        """The run id the store holds now (read afresh: a small read of the root's metadata)."""
        zarr = require_zarr()
        return zarr.open_group(store=self.where, mode="r", zarr_format=3).attrs.get(RUN_ID, "")

    def done_mask(self) -> np.ndarray:
        if BOOKKEEPING not in self.group:            # dropped by a finish that was cut off: every block was done
            return np.ones(int(self.group.attrs["n_blocks"]), bool)
        return self._array(BOOKKEEPING)[...].sum(axis=1) > 0

    def write_block(self, block: Block, arrays: dict[str, np.ndarray]) -> np.ndarray:
        """Write one block's arrays into its chunks, then record it done; returns its status counts."""
        for name, values in arrays.items():
            a = self._array(name)
            a[block.slab] = values.reshape(slab_shape(a.shape, block.slab))
        counts = status_counts(arrays["status"])
        self._array(BOOKKEEPING)[block.index] = counts      # the record last: a kill before it redoes the block
        return counts

    def update_attrs(self, attrs: dict) -> None:
        self.group.attrs.update({k: _jsonable(v) for k, v in attrs.items()})

    def value_counts(self, name: str) -> dict[int, int]:
        """Solves per status code, from the blocks' records (``name`` is always "status" here)."""
        totals = self._array(BOOKKEEPING)[...].sum(axis=0)
        return {int(i) - 128: int(k) for i, k in enumerate(totals) if k}

    def close(self) -> None:
        self._arrays.clear()


def status_counts(status: np.ndarray) -> np.ndarray:
    """How often each int8 status code occurs in a block (index = code + 128)."""
    return np.bincount(status.reshape(-1).astype(np.int64) + 128, minlength=N_CODES)


_OPEN: dict = {}


def write_on_worker(sink: dict, block: Block, arrays: dict[str, np.ndarray]) -> np.ndarray:
    """A Dask worker writes its block into the store itself (opened once per worker and run), after checking that
    the store at that location is still the one of this run (not one an --overwrite made since, nor another store
    of the same name on this worker's own disk). Any failure is one line naming the worker and the store."""
    try:
        key = (sink["where"], sink["run_id"])
        part = _OPEN.get(key)
        if part is None:
            _OPEN.clear()
            part = _OPEN[key] = ZarrPart(sink["where"])
        if part.run_id() != sink["run_id"]:
            _OPEN.clear()
            raise ValueError("the store there is not this run's (replaced since, or another store of the same "
                             "name that this worker sees)")
        return part.write_block(block, arrays)
    except Exception as err:  # noqa: BLE001 - a worker's failure travels to the client as one line
        text = " ".join(str(err).split()) or type(err).__name__
        raise ValueError(f"worker {socket.gethostname()} cannot write block {block.index} into {sink['where']}: "
                         f"{text} (do the workers see the same location?)") from None


class _UrlLock:
    """One run per store at a URL: a small object ``STORE.lock`` holding 'host pid'. Object stores have no
    exclusive create, so two runs started in the same instant may both pass; a lock left by a dead run on
    this host is taken over, one from another host must be deleted by hand."""

    def __init__(self, where: str):
        self.where = where + ".lock"
        self._held = False

    def __enter__(self):
        fs, path = _fs(self.where)
        me = f"{socket.gethostname()} {os.getpid()}"
        if fs.exists(path):
            owner = fs.cat_file(path).decode(errors="replace").split()
            mine = len(owner) == 2 and owner[0] == socket.gethostname() and owner[1].isdigit()
            if not (mine and not alive(int(owner[1]))):
                raise ValueError(f"another run ({' '.join(owner) or 'unknown'}) is writing {self.where[:-5]}; "
                                 f"wait for it or stop it (if it is gone, delete {self.where})")
        fs.pipe_file(path, me.encode())
        self._held = True
        return self

    def __exit__(self, *exc):
        if self._held:
            fs, path = _fs(self.where)
            try:
                fs.rm(path)
            except FileNotFoundError:
                pass
            self._held = False


# -- reading --------------------------------------------------------------------------------------------

class ZarrReader:
    """storage.ResultFile's methods on a zarr store (export, passage CSVs)."""

    def __init__(self, where: str):
        zarr = require_zarr()
        try:
            self.group = zarr.open_group(store=str(where), mode="r", zarr_format=3)
        except Exception:  # noqa: BLE001
            raise ValueError(f"{where} is not a readable zarr store") from None
        self.file_attrs = dict(self.group.attrs)

    def __enter__(self) -> "ZarrReader":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        pass

    def names(self) -> list[str]:
        return [k for k, _ in self.group.arrays()]

    def has(self, name: str) -> bool:
        return name in self.group and hasattr(self.group[name], "shape")

    def shape(self, name: str):
        return self.group[name].shape

    def ndim(self, name: str) -> int:
        return self.group[name].ndim

    def dtype(self, name: str):
        return np.dtype(self.group[name].dtype)

    def dims(self, name: str) -> list[str]:
        return [d or "" for d in (self.group[name].metadata.dimension_names or ())]

    def attrs(self, name: str) -> dict:
        return dict(self.group[name].attrs)

    def read(self, name: str, index=()):
        try:
            return np.asarray(self.group[name][index if index != () else ...])
        except Exception:  # noqa: BLE001
            raise ValueError(f"{self.group.store}: {name} cannot be read (a damaged store?)") from None


def is_complete(where) -> bool:
    try:
        return int(require_zarr().open_group(store=str(where), mode="r", zarr_format=3).attrs.get(COMPLETE, 0)) == 1
    except Exception:  # noqa: BLE001
        return False


def open_dataset(where):
    """A finished store as an xarray Dataset (lazy, dask-backed where dask is installed)."""
    import xarray as xr

    return xr.open_zarr(str(where), consolidated=True, zarr_format=3)
