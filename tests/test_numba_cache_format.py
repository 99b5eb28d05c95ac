"""numba's private on-disk cache format, as fastbearing/_numba_cache.py reads and writes it (issue 45, item 3).

The release wheel's prebuilt kernels rely on these facts; each test fails loudly, naming what changed,
when a numba upgrade changes one. Then _numba_cache.py (and only it) needs a look."""

import hashlib
import importlib.util
import pickle
import re
import sys

import numba
import pytest
from numba.core import config

from fastbearing import _numba_cache as nc

MODULE = '''from numba import njit


@njit(cache=True)
def plus_one(x):
    return x + 1
'''


@pytest.fixture
def cached_function(tmp_path, monkeypatch):
    """A one-function module in tmp_path, compiled for a float and an int into a cache folder of its own
    (NUMBA_CACHE_DIR): (the dispatcher, its source file)."""
    monkeypatch.setattr(config, "CACHE_DIR", str(tmp_path / "cache"))
    source = tmp_path / "fb_format_probe.py"
    source.write_text(MODULE)
    spec = importlib.util.spec_from_file_location("fb_format_probe", source)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert module.plus_one(1.5) == 2.5 and module.plus_one(2) == 3
    return module.plus_one, source


def test_the_cache_folder_and_source_stamp_are_numbas(cached_function):
    dispatcher, source = cached_function
    folder, stamp = nc.locate(source)
    assert folder == type(folder)(dispatcher._cache.cache_path), "numba's locators choose another folder"
    # a content hash (numba >= 0.68), so a cache survives a reinstall of the same files
    assert stamp == hashlib.sha256(source.read_bytes()).digest(), f"numba's source stamp changed: {stamp!r}"


def test_the_index_file_layout(cached_function):
    dispatcher, source = cached_function
    folder, stamp = nc.locate(source)
    indexes = nc.index_files(folder, source.stem)
    assert [p.name for p in indexes] == [f"fb_format_probe.plus_one-4.{nc.PY_TAG}.nbi"], \
        f"numba names its index files otherwise: {sorted(p.name for p in folder.iterdir())}"
    with open(indexes[0], "rb") as f:
        assert pickle.load(f) == numba.__version__, "the index no longer starts with numba's version"
        found_stamp, overloads = pickle.loads(f.read())
    assert found_stamp == stamp
    assert nc.read_index(indexes[0]) == (numba.__version__, stamp, overloads)
    assert len(overloads) == 2
    for key, data in overloads.items():
        sig, target, hashes = key  # the key is (signature, target, hashes)
        assert isinstance(sig, tuple) and len(sig) == 1, f"signature part changed: {sig!r}"
        assert target == nc.process_target(), f"the target part is not (triple, cpu, features): {target!r}"
        assert len(hashes) == 2 and all(re.fullmatch(r"[0-9a-f]{64}", h) for h in hashes), hashes
        assert re.fullmatch(rf"fb_format_probe\.plus_one-4\.{nc.PY_TAG}\.[12]\.nbc", data), data
        assert (folder / data).is_file()


def test_the_target_part_is_the_codegens_magic_tuple():
    from numba.core.registry import cpu_target

    assert nc.process_target() == cpu_target.target_context.codegen().magic_tuple()
    assert nc.level_target("x86-64-v3") == (nc.process_target()[0], "x86-64-v3", "")


def test_retarget_copies_entries_under_the_new_target_and_keeps_what_is_there(cached_function, tmp_path):
    """What the prebuilt copy does: entries of one target keyed for another, data copied byte for byte,
    an entry already in the destination kept; numba then reads the result as its own index."""
    dispatcher, source = cached_function
    folder, stamp = nc.locate(source)
    index = nc.index_files(folder, source.stem)[0]
    here = nc.process_target()
    other = (here[0], "x86-64-v3", "")
    dst = tmp_path / "dst"
    dst.mkdir()
    assert nc.retarget(index, dst, stamp, here, other) == 2
    version, got_stamp, overloads = nc.read_index(dst / index.name)
    assert version == numba.__version__ and got_stamp == stamp
    source_overloads = nc.read_index(index)[2]
    for (sig, target, hashes), name in source_overloads.items():
        copied = overloads[(sig, other, hashes)]
        assert (dst / copied).read_bytes() == (folder / name).read_bytes()
    assert nc.retarget(index, dst, stamp, here, other) == 0  # already there: kept
    assert nc.retarget(index, dst, stamp, other, here) == 0  # no entry of that target
    assert nc.retarget(index, dst, b"another source", here, other) == 0  # another source: numba would not read it
    (dst / "broken.nbi").write_bytes(b"not a pickle")
    with pytest.raises(ValueError, match="not an index file numba"):
        nc.retarget(dst / "broken.nbi", tmp_path, stamp, here, other)


def test_the_py_tag_is_this_interpreters():
    assert nc.PY_TAG == f"py{sys.version_info[0]}{sys.version_info[1]}{getattr(sys, 'abiflags', '')}"
