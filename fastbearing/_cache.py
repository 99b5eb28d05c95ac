"""Keep numba's on-disk cache consistent with the source.

numba invalidates a cached function only when its own file changes, not when
a kernel it calls (in another file) does. Before any kernel is imported we
hash the package's sources and drop the cached machine code if the hash
differs from the one it was built from.
"""

import hashlib
from pathlib import Path

_PACKAGE = Path(__file__).parent
#: Modules holding @njit code (and the constants it compiles in).
KERNEL_MODULES = ("config.py", "status.py", "kernel.py", "linalg.py", "solver.py", "sweep.py")
_STAMP = _PACKAGE / "__pycache__" / "fastbearing-numba-cache.stamp"


def source_hash() -> str:
    h = hashlib.sha256()
    for name in KERNEL_MODULES:
        h.update(name.encode())
        h.update((_PACKAGE / name).read_bytes())
    return h.hexdigest()


def ensure_fresh() -> None:
    """Delete stale numba cache files (.nbi/.nbc) when the sources changed."""
    try:
        digest = source_hash()
        if _STAMP.exists() and _STAMP.read_text() == digest:
            return
        for pattern in ("*.nbi", "*.nbc"):
            for stale in (_PACKAGE / "__pycache__").glob(pattern):
                stale.unlink(missing_ok=True)
        _STAMP.parent.mkdir(exist_ok=True)
        _STAMP.write_text(digest)
    except OSError:
        # read-only install: numba falls back to its own cache location rules
        pass
