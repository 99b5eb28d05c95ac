"""The release wheel's prebuilt kernels (issue 45, item 3): which CPU level a machine gets, the fallback
to JIT when anything differs (faked CPU features and versions: code of a level is never keyed for a
machine without all its features), and a real prebuilt cache, built and used in fresh processes."""

import json
import os
import subprocess
import sys
import textwrap
import zipfile
from pathlib import Path

import numpy as np
import pytest

from fastbearing import _numba_cache as nc
from fastbearing import _prebuilt
from fastbearing._cache import source_hash
from fastbearing._prebuilt import LEVELS, choose_level
from conftest import COUNT_COMPILATIONS

V3 = set(LEVELS["x86-64-v3"])
V4 = set(LEVELS["x86-64-v4"])
HERE = {"python": "3.11", "implementation": "cpython", "numba": "0.68.1", "llvmlite": "0.50.0",
        "triple": "x86_64-unknown-linux-gnu"}
MANIFEST = {"format": _prebuilt.FORMAT, "build": "b1", **HERE, "source_hash": "abc", "folders": ["engine"],
            "levels": {"x86-64-v3": {}, "x86-64-v4": {}}}


def test_the_best_level_the_cpu_has_is_chosen():
    assert choose_level(MANIFEST, V4 | {"avx512vnni"}, HERE, "abc")[0] == "x86-64-v4"
    assert choose_level(MANIFEST, V3, HERE, "abc")[0] == "x86-64-v3"  # AVX2 but no AVX-512
    only_v4 = {**MANIFEST, "levels": {"x86-64-v4": {}}}
    level, why = choose_level(only_v4, V3, HERE, "abc")
    assert level is None and "lacks avx512bw, avx512cd, avx512dq, avx512f, avx512vl (x86-64-v4)" in why
    level, why = choose_level(MANIFEST, V3 - {"fma"}, HERE, "abc")  # one feature short of v3: nothing
    assert level is None and "lacks fma (x86-64-v4)" not in why and "fma" in why
    assert choose_level(MANIFEST, set(), HERE, "abc")[0] is None  # llvmlite could not tell: nothing


@pytest.mark.parametrize("name, value", [("numba", "0.69.0"), ("llvmlite", "0.51.0"), ("python", "3.12"),
                                         ("implementation", "pypy"), ("triple", "aarch64-unknown-linux-gnu")])
def test_another_numba_llvmlite_python_or_platform_gets_no_prebuilt_code(name, value):
    level, why = choose_level(MANIFEST, V4, {**HERE, name: value}, "abc")
    assert level is None and f"prebuilt for {name} {HERE[name]}, this is {value}" == why


def test_other_kernel_sources_or_format_get_no_prebuilt_code():
    assert choose_level(MANIFEST, V4, HERE, "edited")[0] is None
    assert choose_level({**MANIFEST, "format": 99}, V4, HERE, "abc")[0] is None
    assert choose_level({**MANIFEST, "levels": {"pentium4": {}}}, V4, HERE, "abc") == (None, "no prebuilt level")


def test_without_prebuilt_caches_nothing_happens(monkeypatch, tmp_path):
    monkeypatch.setenv("FASTBEARING_PREBUILT", str(tmp_path / "none"))
    assert _prebuilt.use_prebuilt() is None
    assert _prebuilt.STATUS == (None, "no prebuilt caches in this install")


#: Builds the kernels of one direct stiffness (Kb at a displacement: a few functions, about 6 s) for the
#: level NUMBA_CPU_NAME names and exports them as the release build does (jobs.warmup.prebuild runs the
#: whole warm-up in place of the one call).
BUILD = textwrap.dedent("""
    import sys
    import fastbearing as fb
    from fastbearing._prebuilt import export_level

    fb.stiffness(fb.Bearing.preset("gunduz2013", "DB"), [0.01, 0.0, 0.02, 0.0, 1e-4])
    print("exported", export_level(sys.argv[1], sys.argv[2]))
""")

#: The same stiffness in a fresh process, counting numba's compilations.
USE = COUNT_COMPILATIONS + textwrap.dedent("""
    import numpy as np
    import fastbearing as fb
    from fastbearing import _prebuilt

    f, K = fb.stiffness(fb.Bearing.preset("gunduz2013", "DB"), [0.01, 0.0, 0.02, 0.0, 1e-4])
    np.save(sys.argv[1], K)
    print("level:", _prebuilt.STATUS[0], "compilations:", count[0], file=sys.stderr)
""")


def _runs_v3() -> bool:
    return V3 <= _prebuilt.host_features()


@pytest.fixture(scope="module")
def prebuilt_v3(tmp_path_factory):
    """A prebuilt folder as a release wheel carries it, for x86-64-v3, with the stiffness kernels."""
    from fastbearing.jobs.warmup import portable_environment

    root = tmp_path_factory.mktemp("prebuilt")
    into = root / "prebuilt"
    run = subprocess.run([sys.executable, "-c", BUILD, "x86-64-v3", str(into)], capture_output=True, text=True,
                         env=portable_environment("x86-64-v3", root / "build-cache"), timeout=600)
    assert run.returncode == 0, run.stderr
    assert "exported 3" in run.stdout  # _store, ball_loop, ball_sums
    _prebuilt.write_manifest(into, ["x86-64-v3"])
    return into


@pytest.mark.skipif(not _runs_v3(), reason="this CPU cannot run x86-64-v3 code (AVX2, FMA ...)")
def test_a_prebuilt_level_loads_in_a_fresh_process_and_compiles_nothing(prebuilt_v3, tmp_path):
    """End to end: the manifest, the level's choice, the copy keyed for this machine, numba loading it
    (0 compilations), the same Kb as the JIT code to rounding; a second process finds it copied."""
    manifest = json.loads((prebuilt_v3 / "manifest.json").read_text())
    assert manifest["source_hash"] == source_hash() and list(manifest["levels"]) == ["x86-64-v3"]
    env = {**os.environ, "FASTBEARING_PREBUILT": str(prebuilt_v3), "NUMBA_CACHE_DIR": str(tmp_path / "user")}
    for k in ("NUMBA_CPU_NAME", "NUMBA_CPU_FEATURES"):
        env.pop(k, None)
    first = subprocess.run([sys.executable, "-c", USE, str(tmp_path / "K.npy")], env=env, capture_output=True,
                           text=True, timeout=300)
    assert first.returncode == 0, first.stderr
    assert "level: x86-64-v3 compilations: 0" in first.stderr and "compiling" not in first.stderr
    import fastbearing as fb

    _, K = fb.stiffness(fb.Bearing.preset("gunduz2013", "DB"), [0.01, 0.0, 0.02, 0.0, 1e-4])
    np.testing.assert_allclose(np.load(tmp_path / "K.npy"), K, rtol=1e-13, atol=1e-6)  # v3 against host code
    (folder,) = {p.parent for p in (tmp_path / "user").rglob("*.nbi")}
    marker = folder / _prebuilt.MARKER
    assert json.loads(marker.read_text())["level"] == "x86-64-v3"
    for index in folder.glob("*.nbi"):  # keyed for this process's target, nothing else
        assert nc.targets_in(index) == {nc.process_target()}
    copied = {p.name: p.stat().st_mtime_ns for p in folder.iterdir()}
    again = subprocess.run([sys.executable, "-c", USE, str(tmp_path / "K2.npy")], env=env, capture_output=True,
                           text=True, timeout=300)
    assert "level: x86-64-v3 compilations: 0" in again.stderr, again.stderr
    assert {p.name: p.stat().st_mtime_ns for p in folder.iterdir()} == copied  # not copied again
    assert np.array_equal(np.load(tmp_path / "K2.npy"), np.load(tmp_path / "K.npy"))


@pytest.mark.parametrize("fake", ["features", "numba", "user target"])
def test_a_machine_or_numba_that_does_not_match_copies_nothing(prebuilt_v3, tmp_path, monkeypatch, fake):
    """A host without AVX2 (faked: llvmlite's answer replaced), another numba (faked), or a user's own
    NUMBA_CPU_NAME: nothing reaches numba's cache folder, so numba cannot load the level's code and compiles
    as without the wheel (with the usual notice)."""
    from numba.core import config

    monkeypatch.setenv("FASTBEARING_PREBUILT", str(prebuilt_v3))
    monkeypatch.setattr(config, "CACHE_DIR", str(tmp_path / "user"))
    if fake == "features":
        monkeypatch.setattr(_prebuilt, "host_features", lambda: set(LEVELS["x86-64-v2"]))
    elif fake == "numba":
        real = _prebuilt.runtime()
        monkeypatch.setattr(_prebuilt, "runtime", lambda: {**real, "numba": "0.99.0"})
    else:
        monkeypatch.setattr(config, "CPU_NAME", "x86-64-v3")
    monkeypatch.setattr(_prebuilt, "_install_in_a_fresh_process", lambda *a: pytest.fail("nothing may be copied"))
    assert _prebuilt.use_prebuilt() is None
    why = _prebuilt.STATUS[1]
    assert {"features": "this machine lacks avx, avx2, bmi, bmi2, f16c, fma, lzcnt, movbe, xsave (x86-64-v3)",
            "numba": "prebuilt for numba", "user target": "NUMBA_CPU_NAME is set"}[fake] in why
    assert not list((tmp_path / "user").rglob("*.nbi"))


@pytest.mark.skipif(bool(os.environ.get("CI")), reason="builds a wheel in an isolated environment from the package "
                    "index (about 1 min on 2 cores); run by hand for a release")
@pytest.mark.skipif(not _runs_v3(), reason="this CPU cannot run x86-64-v3 code")
def test_the_release_build_puts_the_prebuilt_caches_in_the_wheel(tmp_path):
    import importlib.util

    spec = importlib.util.find_spec("build")
    if spec is None or spec.origin is None:  # not installed (a build/ folder of a setuptools run is no package)
        pytest.skip("needs pypa's build (pip install build)")
    repo = Path(__file__).resolve().parents[1]
    # without the suite's PYTHONPATH (conftest.py): pip would take its packages as the isolated build's own
    env = {**{k: v for k, v in os.environ.items() if k != "PYTHONPATH"}, "FASTBEARING_PREBUILD": "x86-64-v3",
           "FASTBEARING_PREBUILD_KINDS": "quasi-static"}
    run = subprocess.run([sys.executable, "-m", "build", "--wheel", "--outdir", str(tmp_path), str(repo)], env=env,
                         capture_output=True, text=True, timeout=900)
    assert run.returncode == 0, run.stderr[-3000:]
    tag = f"cp{sys.version_info[0]}{sys.version_info[1]}-none-{_wheel_tags().prebuilt_platform()}"
    (wheel,) = tmp_path.glob(f"fastbearing-*-{tag}.whl")
    with zipfile.ZipFile(wheel) as z:
        names = z.namelist()
        manifest = json.loads(z.read("fastbearing/_prebuilt/manifest.json"))
    assert list(manifest["levels"]) == ["x86-64-v3"] and manifest["source_hash"] == source_hash()
    assert any(n.startswith("fastbearing/_prebuilt/x86-64-v3/engine/solver.solve_case") for n in names)


def _wheel_tags():
    """build_backend/wheel_tags.py, the release build's tag rule (imported by path: no package)."""
    import importlib.util

    path = Path(__file__).resolve().parents[1] / "build_backend" / "wheel_tags.py"
    spec = importlib.util.spec_from_file_location("wheel_tags", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_a_prebuilt_wheel_is_tagged_for_the_platforms_numba_and_llvmlite_wheels_run_on(monkeypatch):
    """Package indexes refuse a plain linux_x86_64 tag: the prebuilt wheel takes the manylinux tags that numba's
    and llvmlite's own wheels share (the cached code calls into nothing else but the C maths library), and
    this platform's tag only where they did not come from wheels."""
    tags = _wheel_tags()
    wheels = {"numba": {"manylinux_2_27_x86_64", "manylinux_2_28_x86_64"},
              "llvmlite": {"manylinux_2_17_x86_64", "manylinux_2_27_x86_64", "manylinux_2_28_x86_64"}}
    monkeypatch.setattr(tags, "wheel_platforms", lambda name: wheels[name])
    assert tags.prebuilt_platform() == "manylinux_2_27_x86_64.manylinux_2_28_x86_64"
    wheels["numba"] = set()  # a conda numba
    assert tags.prebuilt_platform() == tags.sysconfig.get_platform().replace("-", "_").replace(".", "_")
    wheels["numba"] = {"linux_x86_64"}  # built from source here
    assert tags.prebuilt_platform().startswith("linux")
    monkeypatch.undo()
    import importlib.metadata

    numba_wheel = importlib.metadata.distribution("numba").read_text("WHEEL") or ""
    if "manylinux" in numba_wheel:  # this environment's numba from a wheel: its real tags
        assert "manylinux" in tags.prebuilt_platform()
