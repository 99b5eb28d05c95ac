"""Keep numba's on-disk cache consistent with the source.

numba invalidates a cached function only when its own file changes, not when
a kernel it calls (in another file) does. Before any kernel is imported we
hash the package's kernel sources and drop the cached machine code if the
hash differs from the one it was built from, in every folder where numba
may keep this package's cache: ``__pycache__`` beside the sources, the
user-wide fallback when that is read-only, or ``NUMBA_CACHE_DIR`` when set.
"""

import hashlib
from pathlib import Path

_PACKAGE = Path(__file__).parent
#: Modules holding @njit code (and the constants it compiles in: bearing.py's ball-table rows).
KERNEL_MODULES = ("config.py", "status.py", "roots.py", "trig.py", "deflection.py", "high_speed.py", "kernel.py",
                  "linalg.py", "solver.py", "sweep.py", "bearing.py")
_STAMP_NAME = "fastbearing-numba-cache.stamp"


def source_hash() -> str:
    h = hashlib.sha256()
    for name in KERNEL_MODULES:
        h.update(name.encode())
        h.update((_PACKAGE / name).read_bytes())
    return h.hexdigest()


def cache_folder() -> Path:
    """Where numba keeps the cache of this package's kernels: numba's own choice (the first of its
    locators that applies, as numba itself picks), or the in-tree ``__pycache__`` if numba cannot say."""
    try:
        from numba.core import caching

        def probe():
            pass

        for locator in caching.CacheImpl._locator_classes:
            found = locator.from_function(probe, str(_PACKAGE / "kernel.py"))
            if found is not None:
                return Path(found.get_cache_path())
    except Exception:  # a numba without these internals: the default location
        pass
    return _PACKAGE / "__pycache__"


def ensure_fresh() -> None:
    """Delete stale numba cache files (.nbi/.nbc) when the sources changed."""
    digest = source_hash()
    for folder in (cache_folder(),):
        stamp = folder / _STAMP_NAME
        try:
            if stamp.exists() and stamp.read_text() == digest:
                continue
            if folder.is_dir():
                for module in KERNEL_MODULES:
                    for stale in folder.glob(f"{Path(module).stem}.*.nb[ic]"):
                        stale.unlink(missing_ok=True)
            folder.mkdir(parents=True, exist_ok=True)
            stamp.write_text(digest)
        except OSError:
            # read-only location: numba does not write there either
            pass
