"""The one module that knows numba's private on-disk cache format (numba.core.caching, checked on 0.68).

What it relies on (tests/test_numba_cache_format.py checks each fact against the installed numba and fails
loudly when numba changes one):

- numba picks a cache folder per source file with the first of ``CacheImpl._locator_classes`` that applies
  (NUMBA_CACHE_DIR, a writable ``__pycache__`` beside the source, a user-wide folder);
- an index file ``<module>.<qualname>-<first line>.py<XY><abiflags>.nbi`` holds ``pickle(numba.__version__)``
  followed by ``pickle((source stamp, {key: data file name}))``;
- the source stamp is what the locator's ``get_source_stamp()`` gives (from numba 0.68 the SHA-256 digest of
  the source file's bytes, so it survives a reinstall of the same files);
- a key is ``(signature, (target triple, CPU name, CPU features), (bytecode hash, closure hash))``; the middle
  part is ``codegen.magic_tuple()``: ``NUMBA_CPU_NAME``/``NUMBA_CPU_FEATURES`` when set, else the host's;
- data files ``<same base>.<n>.nbc`` (n from 1) hold the compiled library; they are copied byte for byte.

Nothing here runs compiled code: it moves files and rewrites the target part of index keys.
"""

from __future__ import annotations

import contextlib
import os
import pickle
import sys
import uuid
from pathlib import Path

#: What the file names of this interpreter's caches end with (numba's ``get_filename_base``).
PY_TAG = "py%d%d%s" % (sys.version_info[0], sys.version_info[1], getattr(sys, "abiflags", ""))


def _probe():
    pass


def locate(source: Path):
    """numba's cache folder for the functions of the source file ``source`` and that file's source stamp,
    as numba itself finds them (the first locator that applies), or (None, None) where none does."""
    from numba.core import caching

    for locator in caching.CacheImpl._locator_classes:
        found = locator.from_function(_probe, str(source))
        if found is not None:
            return Path(found.get_cache_path()), found.get_source_stamp()
    return None, None


def process_target() -> tuple[str, str, str]:
    """The target part of the index keys this process's CPU code gets (numba's ``magic_tuple``), found the
    way numba's JIT codegen finds it, without starting numba's compiler contexts."""
    from llvmlite import binding as ll
    from numba.core import codegen, config

    name = ll.get_host_cpu_name() if config.CPU_NAME is None else config.CPU_NAME
    features = codegen.get_host_cpu_features() if config.CPU_FEATURES is None else config.CPU_FEATURES
    return ll.get_process_triple(), name, features


def level_target(level: str) -> tuple[str, str, str]:
    """The target part of the keys of a cache built with NUMBA_CPU_NAME=level and NUMBA_CPU_FEATURES=""."""
    from llvmlite import binding as ll

    return ll.get_process_triple(), level, ""


def read_index(path: Path):
    """(numba version, source stamp, {key: data file name}) of an index file; None when it is missing or
    unreadable. The rest is unpickled only for this numba's own version (as numba does: another version's
    types may not unpickle)."""
    import numba

    try:
        with open(path, "rb") as f:
            version = pickle.load(f)
            if version != numba.__version__:
                return version, None, {}
            stamp, overloads = pickle.loads(f.read())
    except (OSError, EOFError, pickle.UnpicklingError, AttributeError, ImportError, TypeError, ValueError):
        return None
    return version, stamp, overloads


@contextlib.contextmanager
def _write_atomically(path: Path):
    """Write beside ``path`` and rename over it, as numba does, so a reader never sees half a file."""
    tmp = path.with_name(f"{path.name}.tmp.{uuid.uuid4().hex[:16]}")
    try:
        with open(tmp, "wb") as f:
            yield f
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def write_index(path: Path, stamp, overloads: dict) -> None:
    """Write an index file for this numba version (numba's own layout, see the module docstring)."""
    import numba
    from numba.core.serialize import dumps

    with _write_atomically(path) as f:
        pickle.dump(numba.__version__, f, protocol=-1)
        f.write(dumps((stamp, overloads)))


def index_files(folder: Path, module_stem: str) -> list[Path]:
    """The index files of the module ``module_stem``'s functions for this interpreter in ``folder``."""
    return sorted(folder.glob(f"{module_stem}.*.{PY_TAG}.nbi"))


def retarget(src_index: Path, dst_folder: Path, stamp, old: tuple, new: tuple) -> int:
    """Add the entries of ``src_index`` (an index beside its data files) whose target is ``old`` to the
    index of the same name in ``dst_folder``, keyed for the target ``new``, copying their data files under
    free numbers. Entries already there win (code compiled on this machine); an index of another numba
    version or another source stamp counts as empty, as numba reads it. Returns how many were added; 0
    when ``src_index`` is of another version or stamp; ValueError when it cannot be read."""
    import numba

    found = read_index(src_index)
    if found is None:
        raise ValueError(f"{src_index.name}: not an index file numba {numba.__version__} can read")
    if found[0] != numba.__version__ or found[1] != stamp:
        return 0
    dst_index = dst_folder / src_index.name
    here = read_index(dst_index)
    overloads = dict(here[2]) if here is not None and here[0] == numba.__version__ and here[1] == stamp else {}
    base = src_index.name[: -len(".nbi")]
    used = set(overloads.values())
    added = 0
    for (sig, target, hashes), name in found[2].items():
        key = (sig, tuple(new), hashes)
        if tuple(target) != tuple(old) or key in overloads:
            continue
        number = 1
        while f"{base}.{number}.nbc" in used:
            number += 1
        data = f"{base}.{number}.nbc"
        with _write_atomically(dst_folder / data) as f:
            f.write((src_index.parent / name).read_bytes())
        used.add(data)
        overloads[key] = data
        added += 1
    if added:
        write_index(dst_index, stamp, overloads)  # after its data files: numba never reads a missing one
    return added


def targets_in(index: Path) -> set:
    """The targets (triple, CPU name, features) of an index file's entries (empty when unreadable)."""
    found = read_index(index)
    return {tuple(key[1]) for key in found[2]} if found else set()


# -- one compiler per function across processes -------------------------------------------------------------
# numba's cache has no lock: processes that start together on an empty cache (pytest-xdist's workers, a Dask
# cluster's, `fastbearing` commands run side by side) each compile every function themselves, and two that save
# entries of one function at once race on its index (``IndexDataCacheFile.save`` reads the index, adds its key
# with the first free data file number, writes it back): one entry is lost, or an index entry names a data file
# the other process wrote for another signature. Here a process that misses the cache for one of the package's
# functions takes that function's lock file (beside its index, ``<index>.lock``, ``flock``) before it compiles,
# and holds it until its entry is saved; a process that finds the lock held waits, then loads what the holder
# saved. The lock is per function (all its signatures), re-entrant within a process, released when the
# process ends whatever happens, and never waited on longer than LOCK_PATIENCE.

#: The longest a process waits for another one compiling the same function before it compiles it itself (s).
LOCK_PATIENCE = 900.0
#: After this many seconds of waiting a process says so, then every WAIT_EVERY seconds.
WAIT_FIRST = 2.0
WAIT_EVERY = 10.0
_PACKAGE_PREFIX = "fastbearing."
_held: dict = {}  # lock file path -> [file descriptor, depth]
_locks_installed = False


def _lock_path(cache) -> str | None:
    """The lock file of a numba FunctionCache ``cache`` of one of the package's functions, else None."""
    module = getattr(getattr(cache, "_py_func", None), "__module__", "") or ""
    index = getattr(getattr(cache, "_cache_file", None), "_index_path", None)
    return index + ".lock" if index and module.startswith(_PACKAGE_PREFIX) else None


def _acquire(path: str, name: str, say) -> bool:
    """Take the lock file ``path`` (re-entrant); False when it could not be opened or waiting ran out."""
    import fcntl
    import time

    if path in _held:
        _held[path][1] += 1
        return True
    try:
        fd = os.open(path, os.O_CREAT | os.O_RDWR, 0o644)
    except OSError:  # a read-only cache folder: numba does not save there either
        return False
    started = time.monotonic()
    told = WAIT_FIRST
    while True:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            _held[path] = [fd, 1]
            return True
        except BlockingIOError:
            waited = time.monotonic() - started
            if waited >= LOCK_PATIENCE:
                os.close(fd)
                return False
            if waited >= told:
                say(f"fastbearing: another process is compiling {name}; waiting for numba's cache, "
                    f"{waited:.0f} s so far")
                told += WAIT_EVERY
            time.sleep(0.05)
        except OSError:  # a file system without flock
            os.close(fd)
            return False


def _release(path: str | None) -> None:
    """Give back one hold of the lock file ``path`` (the last one unlocks it)."""
    held = _held.get(path)
    if held is None:
        return
    held[1] -= 1
    if held[1] <= 0:
        del _held[path]
        os.close(held[0])  # closing the descriptor drops its flock


def compile_failed(ev) -> bool:
    """Whether a numba END event carries an exception (its compilation raised). Not ``Event.is_failed``: in numba
    0.68 that returns ``_exc_details is None``, True for every compilation that succeeded, and the lock was
    given back when a compilation ended, before its entry was saved: a process waiting on it could load nothing,
    compile the function too (tests/test_compile_lock.py, about one run in four). A numba without the attribute
    never counts a compilation failed: its lock then stays held until the process ends, and waiters wait."""
    return getattr(ev, "_exc_details", None) is not None


def serialise_compiles(say=None) -> bool:
    """Install the per-function compile lock (above) on numba's FunctionCache, once per process; ``say``
    receives the waiting lines (default: stderr). Returns whether it is in place (False: a numba without
    these internals or a system without ``fcntl``, which then compiles as before)."""
    global _locks_installed
    if _locks_installed:
        return True
    import importlib.util

    if importlib.util.find_spec("fcntl") is None:  # POSIX only
        return False
    try:
        from numba.core import caching, event
        cache_class = caching.FunctionCache
        load_overload, save_overload = cache_class.load_overload, cache_class.save_overload
    except (ImportError, AttributeError):
        return False
    say = say or (lambda line: print(line, file=sys.stderr, flush=True))

    def load(self, sig, target_context):
        found = load_overload(self, sig, target_context)
        path = _lock_path(self)
        if found is not None or path is None:
            return found
        if not _acquire(path, getattr(self._py_func, "__qualname__", "a kernel"), say):
            return None
        again = load_overload(self, sig, target_context)  # what a process that held the lock saved meanwhile
        if again is not None:
            _release(path)
        return again

    def save(self, sig, data):
        try:
            return save_overload(self, sig, data)
        finally:
            _release(_lock_path(self))

    class _Failed(event.Listener):  # a compilation that raised saves nothing: give its lock back
        def on_start(self, ev):
            pass

        def on_end(self, ev):
            if compile_failed(ev) and ev.data:
                cache = getattr(ev.data.get("dispatcher"), "_cache", None)
                _release(_lock_path(cache))

    load.__wrapped__ = load_overload
    save.__wrapped__ = save_overload
    cache_class.load_overload = load
    cache_class.save_overload = save
    event.register("numba:compile", _Failed())
    _locks_installed = True
    return True
