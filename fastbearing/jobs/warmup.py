"""Compile the kernels before first use: ``fastbearing warmup`` (issue 45).

numba compiles each kind of run once and keeps the machine code in its on-disk cache (NUMBA_CACHE_DIR, or
``__pycache__`` beside the sources). A warm-up runs every kernel family the command line and the API reach
on tiny inputs built in here (the package's own bearings; nothing read from the repository's data/), so
that a user's first command loads instead of compiling: in an install step, a container image or a cluster
node. ``--portable LEVEL --into DIR`` builds the cache for a portable CPU level (NUMBA_CPU_NAME, e.g.
x86-64-v3) in a fresh process, for machines with at least that level's features; a process uses it with
the same NUMBA_CPU_NAME (and ``NUMBA_CPU_FEATURES`` empty) and ``NUMBA_CACHE_DIR=DIR``.

Units: N, mm, rad; speeds in rpm.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

# The CPU levels a portable cache is built for and the features each needs (one table with the release
# wheel's level choice): the warm-up runs the code it compiles, so a host without them is refused first.
from .._prebuilt import LEVELS, host_features

#: Load (Fx, Fy, Fz, Mx, My; N, N*mm) of the paper's Table 4: the quasi-static families' operating point.
_PAPER_LOAD = [1000.0, 0.0, 3000.0, 0.0, -74000.0]
#: A spindle load (N) and speed (rpm) for the 7014C-DB pair at speed.
_SPINDLE_LOAD = [500.0, 0.0, 1000.0, 0.0, 0.0]
_SPINDLE_SPEED = 12000.0


def _quasi_static(folder: Path) -> None:
    from ..analysis.contacts import ball_contacts
    from ..api import direct, solve
    from ..model.bearing import Bearing

    bearing = Bearing.preset("gunduz2013", "DB")
    result = solve(bearing, _PAPER_LOAD)
    direct(bearing, result.q)
    ball_contacts(bearing, result.q)
    solve(Bearing.preset("gunduz2013", "single"), [1000.0, 0.0, 3000.0, 0.0, 0.0])


def _speed(folder: Path) -> None:
    from ..analysis.contacts import ball_contacts
    from ..api import direct, solve
    from ..model.bearing_file import load_bearing

    bearing = load_bearing("7014C-DB")
    result = solve(bearing, _SPINDLE_LOAD, speed=_SPINDLE_SPEED)
    direct(bearing, result.q, speed=_SPINDLE_SPEED)
    ball_contacts(bearing, result.q, _SPINDLE_SPEED)


def _four_point(folder: Path) -> None:
    from ..api import direct, solve
    from ..model.bearing_file import load_bearing

    bearing = load_bearing("QJ210")
    result = solve(bearing, [2000.0, 0.0, 1000.0, 0.0, 0.0])
    direct(bearing, result.q)
    solve(bearing, [2000.0, 0.0, 1000.0, 0.0, 0.0], speed=3000.0)


def _roller(folder: Path) -> None:
    from ..analysis.contacts import roller_contacts
    from ..api import direct, solve
    from ..model.bearing_file import load_bearing

    for name, load in (("NU205", [3000.0, 0.0, 0.0, 0.0, 0.0]), ("30206-TDO", [4000.0, 0.0, 1500.0, 0.0, 0.0])):
        bearing = load_bearing(name)
        result = solve(bearing, load)
        direct(bearing, result.q)
        roller_contacts(bearing, result.q)


def _life(folder: Path) -> None:
    from ..analysis.life import rating_life
    from ..model.bearing_file import load_bearing

    rating_life(load_bearing("6205"), [2000.0, 0.0, 500.0, 0.0, 0.0], speed=1500.0)
    rating_life(load_bearing("7014C-DB"), _SPINDLE_LOAD, speed=_SPINDLE_SPEED)
    rating_life(load_bearing("NU205"), [3000.0, 0.0, 0.0, 0.0, 0.0], speed=1500.0)


def _batches(folder: Path) -> None:
    import numpy as np

    from ..api import solve_many, stiffness_many
    from ..model.bearing import Bearing
    from ..model.bearing_file import load_bearing

    bearing = Bearing.preset("gunduz2013", "DB")
    loads = np.array([_PAPER_LOAD, [500.0, 0.0, 2000.0, 0.0, 0.0]])
    result = solve_many(bearing, loads, threads=1)
    stiffness_many(bearing, result.q, threads=1)
    # each element kind's batch has its own element set: at speed, rollers, four-point balls at speed
    for name, load, speed in (("7014C-DB", _SPINDLE_LOAD, _SPINDLE_SPEED),
                              ("30206-TDO", [4000.0, 0.0, 1500.0, 0.0, 0.0], 0.0),
                              ("QJ210", [2000.0, 0.0, 1000.0, 0.0, 0.0], 3000.0)):
        bearing = load_bearing(name)
        result = solve_many(bearing, np.array([load, load]), threads=1, speed=speed)
        stiffness_many(bearing, result.q, threads=1, speed=speed)


def _maps(folder: Path) -> None:
    from .loadmap import loadmap

    # the README's main job (data/examples/gunduz2013-db-1M.toml) on a 3 x 3 x 3 grid, then a map over speed
    # with life (data/examples/spindle-7014-speed.toml's kind)
    loadmap({"bearing": {"preset": "gunduz2013", "arrangement": "DB"},
             "loadmap": {"given": "load", "Fx": {"start": -2000.0, "stop": 2000.0, "num": 3}, "Fy": 0.0,
                         "Fz": {"start": 500.0, "stop": 10000.0, "num": 3}, "Mx": 0.0,
                         "My": {"start": -1.0e5, "stop": 1.0e5, "num": 3}, "chunk": 65536, "compression": "none"}},
            folder / "map.h5", threads=1, progress=False, overwrite=True)
    loadmap({"bearing": "7014C-DB",
             "loadmap": {"given": "load", "speed": [0.0, 12000.0], "Fx": [0.0, 500.0], "life": True,
                         "Fz": {"start": 0.0, "stop": 2000.0, "num": 3}}},
            folder / "speed-map.h5", threads=1, progress=False, overwrite=True)


def _passage(folder: Path) -> None:
    from .passage import passage

    # data/examples/gunduz2013-passage.toml and 6205-outer-spall.toml, shortened
    passage({"bearing": {"preset": "gunduz2013", "arrangement": "DB"},
             "passage": {"given": "displacement", "points": [[0.05, 0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0, 0.03]],
                         "positions": 16, "harmonics": 4, "shaft_speed": 3000.0, "ball_diameter": 12.0,
                         "pitch_diameter": 70.0}},
            folder / "passage.h5", threads=1, progress=False, overwrite=True)
    passage({"bearing": "6205",
             "passage": {"given": "load", "Fx": 2200.0, "speed": 1797.0, "revolutions": 1, "positions": 32,
                         "harmonics": 8, "element_loads": True,
                         "defects": [{"race": "outer", "angle": 0.0, "width": 0.53, "depth": 0.05,
                                      "profile": "rectangular"}]}},
            folder / "spall.h5", threads=1, progress=False, overwrite=True)


def _shafts(folder: Path) -> None:
    from ..analysis.life import LifeSettings
    from ..analysis.shaft import read_shaft, shaft_life, solve_shaft

    # data/examples/shaft-cylindrical-and-ball.toml and spindle-shaft-speed.toml
    shaft = read_shaft({"shaft": {"reference": 0.0,
                                  "bearings": [{"position": -60.0, "bearing": "NU205"},
                                               {"position": 60.0, "bearing": "6305"}],
                                  "loads": [{"position": -20.0, "force": [3000.0, 0.0, 500.0], "moment": [0.0, 0.0]}]}})
    shaft_life(shaft, solve_shaft(shaft), LifeSettings())
    spindle = read_shaft({"shaft": {"reference": 0.0, "speed": _SPINDLE_SPEED,
                                    "bearings": [{"position": 0.0, "bearing": "7014C-DB"},
                                                 {"position": 250.0, "bearing": "7014C-DB"}],
                                    "loads": [{"position": -120.0, "force": [800.0, 300.0, 400.0]}]}})
    result = solve_shaft(spindle, speed=_SPINDLE_SPEED)
    shaft_life(spindle, result, LifeSettings(speed=_SPINDLE_SPEED, balls_at_speed=True))


def _mounted(folder: Path) -> None:
    import numpy as np

    from ..api import solve_many
    from ..model.bearing import Bearing
    from ..model.bearing_file import read_toml
    from ..model.catalogue import catalogue_folder
    from .loadmap import loadmap
    from .montecarlo import montecarlo

    # cases that vary the bearing: data/examples/spindle-7014-thermal.toml and 6205-k5-montecarlo.toml, shortened
    doc = read_toml(catalogue_folder() / "7014C-DB.toml")
    doc["bearing"]["mounting"] = {"shaft_fit": "js5", "housing_fit": "JS7", "outer_ring_temperature": 25.0}
    doc["loadmap"] = {"inner_ring_temperature": [25.0, 40.0], "speed": [0.0, _SPINDLE_SPEED],
                      "Fz": {"start": 0.0, "stop": 1000.0, "num": 3}}
    loadmap(doc, folder / "thermal.h5", threads=1, progress=False, overwrite=True)
    deep_groove = {"name": "6205", "arrangement": "single",
                   "geometry": {"n_balls": 9, "ball_diameter": 7.938, "pitch_diameter": 38.5, "inner_groove_ratio": 0.52,
                                "outer_groove_ratio": 0.53, "diametral_clearance": "CN", "bore": 25.0,
                                "outer_diameter": 52.0, "width": 15.0},
                   "mounting": {"shaft_fit": "k5", "housing_fit": "H7"}}
    for case in ({"speed": 3000.0}, {"speed": 0.0}, {"speed": 0.0, "ball_diameter_variation": 0.001}):
        montecarlo({"bearing": deep_groove, "montecarlo": {"samples": 64, "Fx": 2000.0, "life": True, **case}},
                   folder / "montecarlo.h5", threads=1, progress=False, overwrite=True)
    bearing = Bearing.preset("gunduz2013", "DB")
    loads = np.array([_PAPER_LOAD, [500.0, 0.0, 2000.0, 0.0, 0.0]])
    solve_many(bearing, loads, threads=1, radial_clearance=[[0.0, 0.0], [-0.002, -0.002]])


#: What a warm-up says when numba starts compiling (then, while it lasts, how far it is: _cache.CompileWatch).
WARMUP_NOTICE = "fastbearing: compiling the kernels into numba's cache"

#: The kernel families, in the order a warm-up compiles them: name -> (what it covers, the function).
FAMILIES = {
    "quasi-static": ("ball bearings at rest: solve, Kb at a displacement, each ball's contact", _quasi_static),
    "speed": ("ball bearings at shaft speed (centrifugal force, gyroscopic moment)", _speed),
    "four-point": ("four-point contact balls, at rest and at speed", _four_point),
    "roller": ("cylindrical and tapered roller rows", _roller),
    "life": ("ISO 281 and ISO/TS 16281 rating life, at rest and at speed", _life),
    "batches": ("solve_many and stiffness_many (the API's parallel sweeps), at rest, at speed, rollers, four-point",
                _batches),
    "maps": ("load maps: the README's main job and a map over speed with life", _maps),
    "passage": ("ball-passage tables, with a defect", _passage),
    "shafts": ("rigid shafts on several bearings, at rest and at speed, with life", _shafts),
    "mounted": ("cases that vary the bearing: maps over temperatures and speed, montecarlo, per-case clearances",
                _mounted),
}


def check_kinds(kinds) -> list[str]:
    """The families named in ``kinds`` (None: all), in the warm-up's order; ValueError names an unknown one."""
    if kinds is None:
        return list(FAMILIES)
    unknown = [k for k in kinds if k not in FAMILIES]
    if unknown:
        raise ValueError(f"--kinds: unknown kernel family {', '.join(unknown)}; the families are "
                         + ", ".join(FAMILIES))
    return [k for k in FAMILIES if k in kinds]


def warmup(kinds=None, *, say=None) -> dict:
    """Compile (or load from numba's cache) the kernels of the families ``kinds`` (None: all, see
    :data:`FAMILIES`) in this process. ``say`` receives one progress line per family (default: stderr).

    Returns {family: seconds} and, under ``"compiled"``, how many compilations numba ran.
    """
    from .._cache import CompileWatch

    names = check_kinds(kinds)
    say = say or (lambda line: print(line, file=sys.stderr, flush=True))
    seconds = {}
    started = time.perf_counter()
    # the watch counts numba's compilations (``compiled``) as it says how far they are: no second listener
    with tempfile.TemporaryDirectory(prefix="fastbearing-warmup-") as tmp, CompileWatch(WARMUP_NOTICE) as watch:
        for i, name in enumerate(names, 1):
            what = FAMILIES[name][0]
            say(f"fastbearing warmup: kernel family {i} of {len(names)}: {name} ({what}); "
                f"{time.perf_counter() - started:.0f} s elapsed")
            t = time.perf_counter()
            before = watch.compiled
            FAMILIES[name][1](Path(tmp))
            seconds[name] = time.perf_counter() - t
            said = "compiled" if watch.compiled > before else "loaded from the cache"
            say(f"fastbearing warmup: {name} {said} in {seconds[name]:.1f} s")
    total = time.perf_counter() - started
    say(f"fastbearing warmup: {len(names)} kernel families ready in {total:.1f} s ({watch.compiled} compilations); "
        "later runs load them from numba's cache")
    return {**seconds, "compiled": watch.compiled}


def portable_environment(level: str, into) -> dict:
    """The environment of a process that compiles for (or runs from) a cache of the CPU level ``level``
    (``x86-64-v3``: AVX2, FMA; ``x86-64-v4``: AVX-512; see :data:`LEVELS`) in the folder ``into``.
    ValueError for an unknown level."""
    if level not in LEVELS:
        raise ValueError(f"--portable: a CPU level, one of {', '.join(LEVELS)}; not {level!r}")
    return {**os.environ, "NUMBA_CPU_NAME": level, "NUMBA_CPU_FEATURES": "",
            "NUMBA_CACHE_DIR": str(Path(into).resolve())}


def warmup_portable(level: str, into, kinds=None) -> int:
    """Build the cache of ``kinds`` for the CPU level ``level`` in the folder ``into``: a fresh process
    (numba reads NUMBA_CPU_NAME when it starts) runs :func:`warmup`. Its progress goes to stderr; returns
    its exit status. ValueError when this machine lacks a feature of the level (checked before anything
    runs)."""
    check_kinds(kinds)
    env = portable_environment(level, into)
    _check_host_runs(level)
    Path(into).mkdir(parents=True, exist_ok=True)
    code = ("import sys; from fastbearing.jobs.warmup import warmup; "
            "warmup(sys.argv[1].split(',') if sys.argv[1] else None)")
    return subprocess.run([sys.executable, "-P", "-c", code, ",".join(kinds or ())],
                          env=_same_package(env)).returncode


def _same_package(env=None) -> dict:
    """``env`` (default this process's) for a child process that imports this very fastbearing, run with
    ``python -P``: numba keys its cache by the source files' paths, so a child that imported a clone's
    source from its working folder instead of the installed package would fill a cache no later run reads."""
    env = dict(os.environ if env is None else env)
    here = str(Path(__file__).resolve().parents[2])
    env["PYTHONPATH"] = os.pathsep.join(p for p in (here, env.get("PYTHONPATH")) if p)
    return env


def _check_host_runs(level: str) -> None:
    """ValueError when this machine lacks a CPU feature of ``level`` (the warm-up runs what it compiles)."""
    features = host_features()
    if not features:
        raise ValueError(f"--portable {level}: llvmlite cannot tell this machine's CPU features (is llvmlite, numba's "
                         "compiler, importable here?), so the level cannot be checked")
    missing = sorted(set(LEVELS[level]) - features)
    if missing:
        raise ValueError(f"--portable {level}: this machine lacks {', '.join(missing)}, so it cannot run the code it "
                         "would compile (the warm-up runs it); build that level's cache on a machine that has them")


def prebuild(levels, into, kinds=None) -> int:
    """The release build's step (``FASTBEARING_PREBUILD``, build_backend/): for each CPU level of ``levels``,
    compile the kernel families ``kinds`` (None: all) in a fresh process for that level, into a temporary
    cache folder, and copy the package's entries to ``into/LEVEL/``; then write ``into/manifest.json``
    (what they were built by, :mod:`fastbearing._prebuilt`). Returns 0, or the exit status of the process
    of the level that failed (no manifest then). ValueError for an unknown level or one this machine
    cannot run, before anything runs."""
    levels = list(dict.fromkeys(levels))
    check_kinds(kinds)
    for level in levels:
        portable_environment(level, into)
        _check_host_runs(level)
    Path(into).mkdir(parents=True, exist_ok=True)
    code = ("import sys; from fastbearing.jobs.warmup import warmup; from fastbearing._prebuilt import export_level; "
            "warmup(sys.argv[1].split(',') if sys.argv[1] else None); "
            "n = export_level(sys.argv[2], sys.argv[3]); "
            "print(f'fastbearing prebuild: {sys.argv[2]}: {n} cached functions', file=sys.stderr)")
    for level in levels:
        with tempfile.TemporaryDirectory(prefix=f"fastbearing-prebuild-{level}-") as cache:
            run = subprocess.run([sys.executable, "-c", code, ",".join(kinds or ()), level, str(Path(into).resolve())],
                                 env=portable_environment(level, cache))
        if run.returncode:
            return run.returncode
    from .._prebuilt import write_manifest

    write_manifest(into, levels)
    return 0
