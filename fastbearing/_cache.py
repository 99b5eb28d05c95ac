"""Keep numba's on-disk cache consistent with the source.

numba invalidates a cached function only when its own file changes, not when
a kernel it calls (in another file) does. Before any kernel is imported we
hash the package's kernel sources and drop the cached machine code if the
hash differs from the one it was built from, in every folder where numba
may keep this package's cache: ``__pycache__`` beside the sources, the
user-wide fallback when that is read-only, or ``NUMBA_CACHE_DIR`` when set.
"""

import functools
import hashlib
import re
from pathlib import Path, PurePosixPath

_PACKAGE = Path(__file__).parent
_STAMP_NAME = "fastbearing-numba-cache.stamp"
#: A module holds kernels when it compiles any: njit, numba's overload or intrinsic (plain substrings: this
#: runs before every command's first kernel, and a regular expression over every source cost 15 ms).
_KERNEL_CODE = ("@njit", "njit(", "@overload", "@intrinsic", "@generated_jit")
#: ``from .x import``, ``from ..pkg.x import``, ``from . import x, y``: (dots, module path, imported names).
_RELATIVE_IMPORT = re.compile(r"^\s*from (\.+)([\w.]*) import \(?([\w, ]+)", re.M)


@functools.lru_cache(maxsize=1)
def kernel_modules() -> tuple[str, ...]:
    """The package's files whose change must drop the cached machine code, found from the sources (no hand
    list): every module with kernel code, and every package module those import from (constants such as
    schema.py's table rows are compiled into the kernels), transitively."""
    sources = {path.relative_to(_PACKAGE).as_posix(): path.read_text() for path in _PACKAGE.rglob("*.py")
               if path.name != "_cache.py"}
    found = {name for name, text in sources.items() if any(mark in text for mark in _KERNEL_CODE)}
    todo = list(found)
    while todo:
        name = todo.pop()
        for imported in _package_imports(name, sources[name]):
            if imported in sources and imported not in found:
                found.add(imported)
                todo.append(imported)
    return tuple(sorted(found))


def _package_imports(name: str, text: str) -> set[str]:
    """Package paths (posix, below the package) of the modules the source ``name`` imports relatively; a
    regular expression, not a parse: this runs before every command's first kernel."""
    folder = PurePosixPath(name).parent
    out = set()
    for dots, module, names in _RELATIVE_IMPORT.findall(text):
        base = folder
        for _ in range(len(dots) - 1):
            base = base.parent
        if module:
            out.add((base / (module.replace(".", "/") + ".py")).as_posix())
        else:
            out.update((base / (n.strip().split(" ")[0] + ".py")).as_posix() for n in names.split(",") if n.strip())
    return {path[2:] if path.startswith("./") else path for path in out}


def source_hash() -> str:
    """SHA-256 of the kernel modules' names and sources (:func:`kernel_modules`) and of how their machine
    code is linked (:data:`LINKING`)."""
    h = hashlib.sha256()
    h.update(LINKING.encode())
    for name in kernel_modules():
        h.update(name.encode())
        h.update((_PACKAGE / name).read_bytes())
    return h.hexdigest()


def cache_folder() -> Path:
    """Where numba keeps the cache of this package's kernels: numba's own choice (the first of its
    locators that applies, as numba itself picks), or the in-tree ``__pycache__`` if numba cannot say."""
    try:
        from ._numba_cache import locate

        found, _ = locate(_PACKAGE / "engine" / "kernel.py")
        if found is not None:
            return found
    except Exception:  # a numba without these internals: the default location
        pass
    return _PACKAGE / "engine" / "__pycache__"


#: How the package's machine code is linked (:func:`self_contained_linking`); part of the stamp, so that a
#: cache built the other way is dropped.
LINKING = "self-contained 2"
#: What the package's functions' mangled names contain (numba mangles the module path into them).
_MANGLED = "11fastbearing"
_linking_installed = False


def self_contained_linking() -> bool:
    """Make every compiled library holding the package's code call only its own copies of its callees, so
    that a result is bit-for-bit the same whether the kernels were compiled in this process or loaded from
    numba's cache, and whatever ran before in the process (issue 45, item 4).

    numba links each callee's optimised module into every caller's module as ``linkonce_odr`` (weak)
    functions and optimises the whole again there (codegen.CPUCodeLibrary.finalize). The JIT resolves a
    weak symbol to the first definition it loaded, so which copy of a callee a caller ran depended on the
    load order: in a process that compiles, the callee's own library (loaded first, optimised once); in a
    process that loads from the cache, the outermost caller's copy (optimised again inside it). With the
    kernels' reassociation and FMA contraction (config.KERNEL_FASTMATH) the copies differ in the last bits,
    and the solver carried that to about 1e-11 of K.

    Here the linked-in copies are made internal for the machine code only: after the module is optimised
    (as before: linkonce_odr, so LLVM inlines and compiles exactly as much as it did; made internal before
    the optimisation, the first solve's compile took 65 % longer) and back to linkonce_odr once the object
    code is emitted (the module that later callers link in is numba's usual one). The object code, cached
    or not, then calls only its own copies.

    Only libraries that hold the package's functions change; other numba code in the process links as
    before. Returns whether the hook is in place (False: a numba without these internals, which
    tests/test_compiled_or_cached.py reports).
    """
    global _linking_installed
    if _linking_installed:
        return True
    try:
        from llvmlite import binding as ll
        from numba.core import codegen

        library = codegen.CPUCodeLibrary
        finalize_module = library._finalize_final_module
    except (ImportError, AttributeError):
        return False

    def _finalize_final_module(self):
        module = self._final_module
        defined = [fn for fn in module.functions if not fn.is_declaration]
        private = []
        if any(_MANGLED in fn.name for fn in defined):
            private = [fn for fn in defined if fn.linkage == ll.Linkage.linkonce_odr]
        for fn in private:
            fn.linkage = "internal"
        try:
            return finalize_module(self)  # adds the module to the JIT and emits its object code
        finally:
            for fn in private:
                fn.linkage = "linkonce_odr"

    _finalize_final_module.__wrapped__ = finalize_module
    library._finalize_final_module = _finalize_final_module
    _linking_installed = True
    return True


def ensure_fresh() -> str:
    """Delete stale numba cache files (.nbi/.nbc) when the sources changed; returns the sources' hash
    (:func:`source_hash`)."""
    digest = source_hash()
    for folder in (cache_folder(),):
        stamp = folder / _STAMP_NAME
        try:
            if stamp.exists() and stamp.read_text() == digest:
                continue
            if folder.is_dir():
                for module in kernel_modules():
                    for stale in folder.glob(f"{Path(module).stem}.*.nb[ic]"):
                        stale.unlink(missing_ok=True)
            folder.mkdir(parents=True, exist_ok=True)
            stamp.write_text(digest)
        except OSError:
            # read-only location: numba does not write there either
            pass
    return digest


#: What a run that starts compiling says, once per process (the estimate: bench/README.md, compile times).
COMPILE_NOTICE = ("fastbearing: compiling the kernels for this kind of run (one time: about 15-60 s on 2 cores; "
                  "later runs load them from numba's cache; `fastbearing warmup` compiles them all ahead)")
#: While a compilation lasts, a progress line every this many seconds (the first one after PROGRESS_FIRST s):
#: a wait of more than 2 s is never silent (issue 45).
PROGRESS_FIRST = 2.0
PROGRESS_EVERY = 10.0
_told = False
_ticking = False


class CompileWatch:
    """While active, notices numba compiling (its compile events): the first compilation in the process says
    so on stderr before the wait (``notice``: the line; None: say nothing), a compilation that lasts says how
    far it is every PROGRESS_EVERY s (elapsed time, functions compiled, the one under way; only with a
    notice), and ``seconds`` sums the time spent compiling (outermost compilations only), so that a summary
    can report it apart from the work."""

    def __init__(self, notice: str | None = COMPILE_NOTICE):
        self.notice = notice
        self.seconds = 0.0
        self.compiled = 0
        self._depth = 0
        self._started = 0.0
        self._current = ""
        self._ticker = None
        self._stop = None

    def __enter__(self) -> "CompileWatch":
        from numba.core import event

        watch = self

        class _Listener(event.Listener):
            def on_start(self, ev):
                watch._start(ev)

            def on_end(self, ev):
                watch._end()

        self._listener = _Listener()
        event.register("numba:compile", self._listener)
        return self

    def __exit__(self, *exc) -> None:
        from numba.core import event

        global _ticking
        event.unregister("numba:compile", self._listener)
        if self._stop is not None:
            self._stop.set()
            self._ticker.join()
            _ticking = False

    def _start(self, ev=None) -> None:
        import sys
        import time

        global _told
        self.compiled += 1
        try:
            self._current = ev.data["dispatcher"].py_func.__qualname__
        except Exception:  # an event without a dispatcher (numba's own): keep the last name
            pass
        if self._depth == 0:
            self._started = time.perf_counter()
            if self.notice and not _told:
                _told = True
                print(self.notice, file=sys.stderr, flush=True)
            if self.notice and self._ticker is None and not _ticking:
                self._start_ticker()  # one progress line at a time: a command's watch holds a job's
        self._depth += 1

    def _end(self) -> None:
        import time

        self._depth -= 1
        if self._depth == 0:
            self.seconds += time.perf_counter() - self._started

    def _start_ticker(self) -> None:
        """A daemon thread that says how far compiling is while it lasts (numba's compiler releases the GIL
        often enough for it to run; a blocked thread only delays a line)."""
        import sys
        import threading
        import time

        global _ticking
        _ticking = True
        self._stop = threading.Event()

        def tick():
            said_at = None
            while not self._stop.wait(0.5):
                if self._depth <= 0:
                    said_at = None
                    continue
                now = time.perf_counter()
                elapsed = now - self._started
                due = PROGRESS_FIRST if said_at is None else PROGRESS_EVERY
                if now - (said_at or self._started) >= due:
                    said_at = now
                    print(f"fastbearing: compiling, {self.seconds + elapsed:.0f} s so far ({self.compiled} functions; "
                          f"now {self._current})", file=sys.stderr, flush=True)

        self._ticker = threading.Thread(target=tick, name="fastbearing-compile-progress", daemon=True)
        self._ticker.start()
