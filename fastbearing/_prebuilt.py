"""Prebuilt kernels for portable CPU levels, shipped in a release wheel (issue 45, item 3).

A wheel built with ``FASTBEARING_PREBUILD=x86-64-v3,x86-64-v4`` carries, under ``fastbearing/_prebuilt/``,
numba's cache of every kernel family compiled for each level (``NUMBA_CPU_NAME=LEVEL``, no extra
features) and a ``manifest.json`` with what they were built by: CPython version, numba, llvmlite, the
target triple and the hash of the kernel sources (:func:`fastbearing._cache.source_hash`).

Before the first kernel loads (``config.CACHE``), :func:`use_prebuilt` picks the best level whose every
CPU feature this machine has (llvmlite's ``get_host_cpu_features``) and copies that level's entries into
the cache folder numba uses for the package on this machine (``NUMBA_CACHE_DIR`` when the user set it; the
``__pycache__`` beside the installed sources when writable; else numba's user-wide folder, so a read-only
site-packages works), keyed for this machine's CPU: numba then loads them as its own. It does so once per
cache folder and machine (a marker file) and leaves anything numba compiled there alone.

Anything that does not match (another CPython, numba or llvmlite, other sources, a machine lacking one
of the level's features, ``NUMBA_CPU_NAME``/``NUMBA_CPU_FEATURES``/``NUMBA_DISABLE_AVX`` set by the user)
copies nothing: numba compiles as without the wheel's caches, with the usual notice. Code of a level is
only ever keyed for a machine that has all of that level's features, so it cannot raise an illegal
instruction. The numba file format is handled in :mod:`fastbearing._numba_cache` alone.
"""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path

_PACKAGE = Path(__file__).parent
#: Where the wheel keeps the prebuilt caches; FASTBEARING_PREBUILT names another folder of the same layout
#: (tests, or an image that keeps them outside the package).
PREBUILT = _PACKAGE / "_prebuilt"
MANIFEST = "manifest.json"
FORMAT = 1
#: The marker, in the cache folder, of the prebuilt caches copied there: build, level, this machine's target.
MARKER = "fastbearing-prebuilt.json"

#: The x86-64 micro-architecture levels (psABI; LLVM's CPU names), with the CPU features each needs as
#: llvmlite's ``get_host_cpu_features`` names them. The levels' code uses only these; a machine missing
#: one of them never gets that level's code.
_V1 = ("64bit", "cmov", "cx8", "fxsr", "mmx", "sse", "sse2")
_V2 = _V1 + ("cx16", "crc32", "popcnt", "sahf", "sse3", "sse4.1", "sse4.2", "ssse3")
_V3 = _V2 + ("avx", "avx2", "bmi", "bmi2", "f16c", "fma", "lzcnt", "movbe", "xsave")
LEVELS = {"x86-64-v2": _V2, "x86-64-v3": _V3,
          "x86-64-v4": _V3 + ("avx512f", "avx512bw", "avx512cd", "avx512dq", "avx512vl")}

#: What the last :func:`use_prebuilt` decided: (level or None, why).
STATUS: tuple[str | None, str] = (None, "not looked at yet")
_BUSY = "copying the prebuilt caches"


def host_features() -> set[str]:
    """The CPU features of this machine, as LLVM names them (empty where llvmlite cannot tell)."""
    try:
        from llvmlite import binding as ll

        return {name for name, on in ll.get_host_cpu_features().items() if on}
    except Exception:  # not x86, or an llvmlite without it
        return set()


def runtime() -> dict:
    """What a prebuilt cache must match here: the interpreter, numba, llvmlite and the target triple."""
    import llvmlite
    import numba
    from llvmlite import binding as ll

    return {"python": "%d.%d%s" % (sys.version_info[0], sys.version_info[1], getattr(sys, "abiflags", "")),
            "implementation": sys.implementation.name, "numba": numba.__version__,
            "llvmlite": llvmlite.__version__, "triple": ll.get_process_triple()}


def _user_target() -> str | None:
    """The numba setting that fixes the CPU target this process compiles for, if the user set one."""
    from numba.core import config

    if config.CPU_NAME is not None:
        return "NUMBA_CPU_NAME"
    if config.CPU_FEATURES is not None:
        return "NUMBA_CPU_FEATURES"
    if not config.ENABLE_AVX:
        return "NUMBA_DISABLE_AVX"
    return None


def choose_level(manifest: dict, features: set[str], here: dict, source_digest: str) -> tuple[str | None, str]:
    """The best level of ``manifest`` that this machine can run (``features``: its CPU features) with the
    versions ``here`` (:func:`runtime`) and the kernel sources of hash ``source_digest``; (None, why) when
    none applies."""
    if manifest.get("format") != FORMAT:
        return None, f"prebuilt caches of format {manifest.get('format')!r}, this package reads {FORMAT}"
    for name in ("implementation", "python", "numba", "llvmlite", "triple"):
        if manifest.get(name) != here[name]:
            return None, f"prebuilt for {name} {manifest.get(name)}, this is {here[name]}"
    if manifest.get("source_hash") != source_digest:
        return None, "prebuilt from other kernel sources than these"
    missing = {}
    for level in reversed(LEVELS):  # the best first
        if level not in manifest.get("levels", {}):
            continue
        lacks = sorted(set(LEVELS[level]) - features)
        if not lacks:
            return level, f"{level}: this machine has its CPU features"
        missing[level] = lacks
    if not missing:
        return None, "no prebuilt level"
    return None, "this machine lacks " + "; ".join(f"{', '.join(lacks)} ({level})" for level, lacks in missing.items())


def _prebuilt_folder() -> Path:
    return Path(os.environ.get("FASTBEARING_PREBUILT") or PREBUILT)


def use_prebuilt(source_digest: str | None = None) -> str | None:
    """Put the prebuilt caches of the best level this machine runs into numba's cache folder for the
    package (see the module docstring); returns the level, or None when they do not apply (:data:`STATUS`
    says why). Once done it costs a few file reads; never raises for a cache it cannot use."""
    global STATUS
    if STATUS[1] == _BUSY:  # inside the copying process
        return None
    folder = _prebuilt_folder()
    try:
        manifest = json.loads((folder / MANIFEST).read_text())
    except FileNotFoundError:
        STATUS = (None, "no prebuilt caches in this install")
        return None
    except (OSError, ValueError) as err:
        STATUS = (None, f"unreadable prebuilt manifest: {err}")
        return None
    user = _user_target()
    if user is not None:
        STATUS = (None, f"{user} is set: numba compiles for the target it names")
        return None
    if source_digest is None:
        from ._cache import source_hash

        source_digest = source_hash()
    level, why = choose_level(manifest, host_features(), runtime(), source_digest)
    if level is None:
        STATUS = (None, why)
        return None
    try:
        if not _installed(manifest, level):
            _install_in_a_fresh_process(folder, level)
    except Exception as err:  # a cache folder it cannot write, a file numba changed: numba compiles instead
        STATUS = (None, f"could not install the prebuilt {level} caches: {err}")
        return None
    STATUS = (level, why)
    return level


def _marker(manifest: dict, level: str) -> str:
    """What the marker of ``level``'s copy for this machine's target says."""
    from ._numba_cache import process_target

    return json.dumps({"build": manifest["build"], "level": level, "target": list(process_target())},
                      sort_keys=True)


def _cache_folders(manifest: dict) -> dict:
    """{subpackage: (numba's cache folder for it, {module stem: source file})}."""
    from ._numba_cache import locate

    out = {}
    for sub in manifest["folders"]:
        sources = {path.stem: path for path in sorted((_PACKAGE / sub).glob("*.py"))}
        cache, _ = locate(next(iter(sources.values())))
        if cache is None:
            raise OSError(f"numba has no writable cache folder for {sub}/")
        out[sub] = cache, sources
    return out


def _installed(manifest: dict, level: str) -> bool:
    """Whether ``level``'s entries are already in numba's cache folders, keyed for this machine."""
    marker = _marker(manifest, level)
    for cache, _ in _cache_folders(manifest).values():
        try:
            if (cache / MARKER).read_text() != marker:
                return False
        except OSError:
            return False
    return True


def _install_in_a_fresh_process(folder: Path, level: str) -> None:
    """Copy in a fresh process: reading an index unpickles its signatures, whose types import the kernel
    modules, and this process may be half-way through importing one of them (the lookup of config.CACHE
    that called us runs at a kernel's decorator). RuntimeError when the copy fails."""
    import subprocess

    code = ("import sys; from fastbearing import _prebuilt as p; p.STATUS = (None, p._BUSY); "
            "p._install(p.Path(sys.argv[1]), sys.argv[2])")
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in (str(_PACKAGE.parent), os.environ.get("PYTHONPATH"))
                                                       if p)}  # this very package
    run = subprocess.run([sys.executable, "-c", code, str(folder), level], env=env, capture_output=True, text=True,
                         timeout=300)
    if run.returncode:
        raise RuntimeError((run.stderr.strip().splitlines() or ["exit %d" % run.returncode])[-1])


def _install(folder: Path, level: str) -> None:
    """Copy ``level``'s entries into numba's cache folders for the package, keyed for this machine, once
    per cache folder (the marker), under a lock so that processes starting together (Dask workers) copy
    once."""
    from . import _numba_cache as nc

    manifest = json.loads((folder / MANIFEST).read_text())
    marker = _marker(manifest, level)
    target = nc.process_target()
    for sub, (cache, sources) in _cache_folders(manifest).items():
        with _locked(cache / (MARKER + ".lock")):
            if (cache / MARKER).exists() and (cache / MARKER).read_text() == marker:
                continue
            failed = []
            for index in sorted((folder / level / sub).glob(f"*.{nc.PY_TAG}.nbi")):
                source = sources.get(index.name.split(".", 1)[0])
                if source is None:
                    continue
                _, source_stamp = nc.locate(source)
                try:
                    nc.retarget(index, cache, source_stamp, nc.level_target(level), target)
                except (OSError, ValueError) as err:
                    failed.append(str(err))
            # even after a failure: the next process loads what was copied rather than copying again
            (cache / MARKER).write_text(marker)
        if failed:
            raise ValueError(f"{len(failed)} prebuilt index files not copied, e.g. {failed[0]}")


class _locked:
    """An exclusive lock on a file (POSIX); elsewhere no lock (the copies are atomic renames anyway)."""

    def __init__(self, path: Path):
        self.path = path

    def __enter__(self):
        try:
            import fcntl
        except ImportError:
            self.f = None
            return self
        self.f = open(self.path, "a")
        fcntl.flock(self.f, fcntl.LOCK_EX)
        return self

    def __exit__(self, *exc):
        if self.f is not None:
            self.f.close()  # releases the lock


# ---- building (run by the release build: build_backend/, or `fastbearing warmup --portable`) ----

def export_level(level: str, into) -> int:
    """In a process built for ``level`` (NUMBA_CPU_NAME=level, NUMBA_CPU_FEATURES="", NUMBA_CACHE_DIR), copy
    the package's cached kernels of that target to ``into/level/<subpackage>/``; returns how many index
    files. ValueError when this process does not compile for ``level``."""
    import shutil

    from . import _numba_cache as nc

    if nc.process_target() != nc.level_target(level):
        raise ValueError(f"export of {level}: this process compiles for {nc.process_target()[1:]}, not {level}")
    count = 0
    for sub in _kernel_folders():
        sources = sorted((_PACKAGE / sub).glob("*.py"))
        cache, _ = nc.locate(sources[0])
        out = Path(into) / level / sub
        out.mkdir(parents=True, exist_ok=True)
        for source in sources:
            for index in nc.index_files(cache, source.stem):
                found = nc.read_index(index)
                if not found or not found[2]:
                    continue
                if nc.targets_in(index) != {nc.level_target(level)}:
                    raise ValueError(f"{index} holds code of another target: {nc.targets_in(index)}")
                shutil.copyfile(index, out / index.name)
                for name in found[2].values():
                    shutil.copyfile(cache / name, out / name)
                count += 1
    return count


def _kernel_folders() -> list[str]:
    """The package's folders holding cached kernels (the numba cache is kept per source folder)."""
    from ._cache import kernel_modules

    return sorted({str(Path(m).parent) for m in kernel_modules() if Path(m).parent != Path(".")})


def write_manifest(into, levels) -> dict:
    """Write ``into/manifest.json`` for the levels built there (after all of them: a folder without it is
    never used); its ``build`` is a hash of the files, so that a changed build is copied again."""
    import hashlib

    from ._cache import source_hash

    h = hashlib.sha256()
    for path in sorted(p for p in Path(into).rglob("*") if p.is_file() and p.name != MANIFEST):
        h.update(path.relative_to(into).as_posix().encode())
        h.update(path.read_bytes())
    manifest = {"format": FORMAT, "build": h.hexdigest()[:32], **runtime(), "source_hash": source_hash(),
                "folders": _kernel_folders(),
                "levels": {level: {"features": list(LEVELS[level]),
                                   "files": sum(1 for _ in (Path(into) / level).rglob("*.nbi"))}
                           for level in levels}}
    (Path(into) / MANIFEST).write_text(json.dumps(manifest, indent=1) + "\n")
    return manifest
