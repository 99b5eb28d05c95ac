"""The platform tag of a wheel that carries prebuilt kernels (the release build, fastbearing_build.py): kept
apart from setuptools so that the tests can check it wherever setuptools is old."""

import sysconfig
from importlib import metadata


def prebuilt_platform() -> str:
    """The platform tag of a wheel with prebuilt kernels: the platform tags that the building numba's and
    llvmlite's own wheels share (e.g. ``manylinux_2_27_x86_64.manylinux_2_28_x86_64``). The cached machine code
    calls only into numba's and llvmlite's runtimes and the C maths library, so it runs wherever their wheels
    run, and pip installs it there (a plain ``linux_x86_64`` tag would be refused by package indexes). Where
    numba or llvmlite did not come from a wheel (a conda or source build), this platform's own tag."""
    shared = sorted(wheel_platforms("numba") & wheel_platforms("llvmlite"))
    if not shared or any(p.startswith(("linux", "any")) for p in shared):
        return sysconfig.get_platform().replace("-", "_").replace(".", "_")
    return ".".join(shared)


def wheel_platforms(name: str) -> set:
    """The platform tags of the installed distribution ``name``'s wheel (its WHEEL file's Tag lines); empty
    where it was not installed from a wheel."""
    try:
        text = metadata.distribution(name).read_text("WHEEL") or ""
    except metadata.PackageNotFoundError:
        return set()
    return {line.split("-")[-1].strip() for line in text.splitlines() if line.startswith("Tag:")}
