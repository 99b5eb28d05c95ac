"""Where a run's output goes: its folder, the disk's room, and one run per output at a time.

A leaf module shared by the HDF5 store (storage.py) and the zarr store (zarr_store.py).
"""

from __future__ import annotations

import os
from pathlib import Path


#: The attribute that marks a finished file or store (1; 0 while a run writes it).
COMPLETE = "fastbearing_complete"


def is_url(output) -> bool:
    """An fsspec URL (s3://, gcs://, memory:// ...): a zarr store's location, never a local path."""
    return "://" in str(output)


def slab_shape(shape: tuple[int, ...], slab: tuple) -> tuple[int, ...]:
    """The shape of ``array[slab]`` for an array of ``shape``: a block's hyperslab (ints drop their axis)."""
    out = []
    for n, s in zip(shape, slab):
        if isinstance(s, slice):
            out.append(len(range(*s.indices(n))))
    return tuple(out) + tuple(shape[len(slab):])


def check_folder(out: Path) -> None:
    """One-line ValueError unless the folder ``out`` goes into exists and is writable."""
    folder = out.parent if str(out.parent) else Path(".")
    if not folder.is_dir():
        raise ValueError(f"output folder {folder} does not exist (create it first, or choose another -o)")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise ValueError(f"output folder {folder} is not writable")


def check_disk_space(out: Path, n_bytes: int, what: str) -> None:
    """Refuse, before creating anything, a file that cannot fit on the output's disk."""
    import shutil

    folder = out.parent if str(out.parent) else Path(".")
    free = shutil.disk_usage(folder).free
    if n_bytes > free:
        raise ValueError(f"{what} needs about {human_size(n_bytes)} but {folder} has {human_size(free)} free; make the grid "
                         "smaller or write elsewhere (-o)")


def human_size(n: float) -> str:
    """Bytes as text in SI units: 3.45e8 -> "345 MB"."""
    for unit in ("B", "kB", "MB", "GB", "TB", "PB"):
        if n < 1000 or unit == "PB":
            return f"{n:.3g} {unit}"
        n /= 1000.0
    return f"{n:.3g} PB"


class RunLock:
    """``OUT.h5.lock``, created with O_EXCL and holding the pid: one run per output at a time, whatever
    HDF5's own file locking does (it is often off on NFS and Lustre). A lock left by a run that no
    longer exists (killed) is taken over."""

    def __init__(self, output: Path):
        self.path = output.with_name(output.name + ".lock")
        self._held = False

    def __enter__(self):
        for _ in range(2):
            try:
                fd = os.open(self.path, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
            except FileExistsError:
                pid = self._owner()
                if pid is not None and alive(pid):
                    raise ValueError(f"another run (pid {pid}) is writing {self.path.with_suffix('')}; wait for "
                                     f"it or stop it (if it is gone, delete {self.path})") from None
                self.path.unlink(missing_ok=True)        # its run is gone: a stale lock
                continue
            with os.fdopen(fd, "w") as fh:
                fh.write(str(os.getpid()))
            self._held = True
            return self
        raise ValueError(f"cannot take the lock {self.path}; delete it if no run is writing this output")

    def _owner(self) -> int | None:
        try:
            return int(self.path.read_text().strip() or "x")
        except (OSError, ValueError):
            return None

    def __exit__(self, *exc):
        if self._held:
            self.path.unlink(missing_ok=True)
            self._held = False


def alive(pid: int) -> bool:
    """Whether a process of this id runs (one owned by another user counts). A zombie (killed, e.g. by
    ``kill -9``, but not yet reaped by its parent) does not: os.kill(pid, 0) still reaches it, so where
    /proc exists its state letter is read, and 'Z' (zombie) or 'X' (dead) count as gone."""
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        pass
    return not _zombie(pid)


def _zombie(pid: int) -> bool:
    """True where /proc/PID/stat says the process is a zombie or dead; False where it cannot be read (no
    /proc: macOS, Windows) or the process runs."""
    try:
        with open(f"/proc/{int(pid)}/stat", "rb") as fh:
            stat = fh.read()
    except OSError:
        return False
    # "pid (comm) S ...": comm may hold spaces and parentheses, so the state follows the last ')'
    state = stat[stat.rfind(b")") + 1:].split()[:1]
    return state in ([b"Z"], [b"X"])
