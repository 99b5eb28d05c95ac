"""fastbearing's PEP 517 build backend: setuptools' own, plus the release build's prebuilt kernels.

``FASTBEARING_PREBUILD=x86-64-v3,x86-64-v4 python -m build --wheel`` makes a wheel that carries numba's
cache of every kernel family compiled for each of those CPU levels, under ``fastbearing/_prebuilt/``, with
a manifest of what built them (CPython, numba, llvmlite; fastbearing/_prebuilt.py picks a level at run
time, or none). The build runs ``fastbearing.jobs.warmup.prebuild`` on the package as built (build/lib),
one fresh process per level (minutes each), so the build needs the package's own dependencies: they are
added to the build requirements, and the machine that builds must have every CPU feature of each level
(the warm-up runs the code it compiles). ``FASTBEARING_PREBUILD_KINDS=quasi-static,...`` restricts the
kernel families (tests). Such a wheel is tagged for the building CPython and for the platforms that the
building numba's and llvmlite's wheels are tagged for (``cp311-none-manylinux_2_27_x86_64.manylinux_2_28_x86_64``
with today's numba 0.68 wheels; :func:`prebuilt_platform`), since its caches are only of use there.

Without ``FASTBEARING_PREBUILD`` everything is setuptools' as before: a pure wheel, no caches.
"""

import os
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import build_meta as _setuptools

from wheel_tags import prebuilt_platform
from setuptools.build_meta import (build_editable, build_sdist, build_wheel, get_requires_for_build_editable,
                                   get_requires_for_build_sdist, prepare_metadata_for_build_editable,
                                   prepare_metadata_for_build_wheel)
from setuptools.command.build_py import build_py as _build_py

try:
    from setuptools.command.bdist_wheel import bdist_wheel as _bdist_wheel
except ImportError:  # setuptools < 70.1
    from wheel.bdist_wheel import bdist_wheel as _bdist_wheel

#: The PEP 517 hooks: setuptools' own, but the wheel's build requirements (get_requires_for_build_wheel).
__all__ = ["build_editable", "build_sdist", "build_wheel", "get_requires_for_build_editable",
           "get_requires_for_build_sdist", "get_requires_for_build_wheel", "prepare_metadata_for_build_editable",
           "prepare_metadata_for_build_wheel"]

PREBUILD = "FASTBEARING_PREBUILD"
PREBUILD_KINDS = "FASTBEARING_PREBUILD_KINDS"


def prebuild_levels() -> list[str]:
    """The CPU levels FASTBEARING_PREBUILD names (comma-separated; empty: none)."""
    return [level.strip() for level in os.environ.get(PREBUILD, "").split(",") if level.strip()]


def get_requires_for_build_wheel(config_settings=None):
    requires = _setuptools.get_requires_for_build_wheel(config_settings)
    if prebuild_levels():  # the warm-up runs the package: its dependencies, in an isolated build too
        import tomllib

        with open("pyproject.toml", "rb") as f:
            requires = requires + tomllib.load(f)["project"]["dependencies"]
    return requires


class BuildPy(_build_py):
    """setuptools' build_py, then (with FASTBEARING_PREBUILD) the prebuilt caches into the built package."""

    def run(self):
        super().run()
        target = Path(self.build_lib) / "fastbearing" / "_prebuilt"
        shutil.rmtree(target, ignore_errors=True)  # a previous build's caches never ride along (build/ stays)
        levels = prebuild_levels()
        if not levels or getattr(self, "editable_mode", False):
            return
        kinds = os.environ.get(PREBUILD_KINDS, "").replace(" ", "")
        code = ("import sys; from fastbearing.jobs.warmup import prebuild; "
                "sys.exit(prebuild(sys.argv[1].split(','), sys.argv[2], sys.argv[3].split(',') if sys.argv[3] else None))")
        build_lib = str(Path(self.build_lib).resolve())
        env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in (build_lib, os.environ.get("PYTHONPATH")) if p)}
        # from build/lib (not the source tree), so the caches are of the files the wheel holds
        status = subprocess.run([sys.executable, "-c", code, ",".join(levels), str(target.resolve()), kinds],
                                env=env, cwd=build_lib).returncode
        if status:
            shutil.rmtree(target, ignore_errors=True)
            raise SystemExit(f"{PREBUILD}={','.join(levels)}: building the prebuilt kernels failed (exit {status})")


class BdistWheel(_bdist_wheel):
    """setuptools' bdist_wheel; a wheel with prebuilt caches is tagged for this CPython and platform (its
    files stay in the wheel's root, installed as pure Python is: no extension module)."""

    def get_tag(self):
        python, abi, platform = super().get_tag()
        if prebuild_levels():  # machine code for this interpreter and platform
            return f"cp{sys.version_info[0]}{sys.version_info[1]}", "none", prebuilt_platform()
        return python, abi, platform
