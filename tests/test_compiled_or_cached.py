"""The same bits whether the kernels were compiled in the process or loaded from numba's cache (issue 45,
item 4), and the hook that makes it so (_cache.self_contained_linking)."""

import importlib
import os
import subprocess
import sys
import textwrap

import numpy as np

#: A small map at speed with life (7014C-DB, two speeds, 2 x 4 loads): the solver at speed, the map sweep and
#: the life columns, compiled in the first process and loaded from the cache in the second.
MAP_AT_SPEED = textwrap.dedent("""
    import sys
    import h5py
    import numpy as np
    import fastbearing as fb

    config = {"bearing": "7014C-DB", "loadmap": {"given": "load", "speed": [6000.0, 12000.0], "life": True,
              "Fx": [0.0, 500.0], "Fz": {"start": 500.0, "stop": 2000.0, "num": 4}}}
    out = fb.loadmap(config, sys.argv[1], threads=1, progress=False, overwrite=True)
    with h5py.File(out) as f:
        arrays = {name: f[name][()] for name in ("K", "q", "f", "residual", "L10r", "max_ball_load")}
    np.savez(sys.argv[2], **arrays)
""")


def test_a_map_at_speed_with_life_is_the_same_compiled_or_cached(tmp_path):
    """A process that compiles ran other copies of the callees than one that loads from the cache (the JIT
    took the first weak definition it had loaded), and K differed by about 4e-11 relative at speed: the
    bit-for-bit promises (HDF5 against zarr, --resume) broke between the two."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba-cache")}
    script = tmp_path / "map_at_speed.py"
    script.write_text(MAP_AT_SPEED)
    results = []
    for name in ("compiled", "cached"):
        run = subprocess.run([sys.executable, str(script), str(tmp_path / f"{name}.h5"), str(tmp_path / f"{name}.npz")],
                             env=env, capture_output=True, text=True, timeout=900)
        assert run.returncode == 0, run.stderr
        results.append((np.load(tmp_path / f"{name}.npz"), run.stderr))
    (compiled, said_first), (cached, said_second) = results
    assert "compiling" in said_first and "compiling" not in said_second  # the first compiled, the second did not
    for name in compiled.files:
        assert np.array_equal(compiled[name], cached[name], equal_nan=True), name


def test_the_linking_hook_is_in_place(monkeypatch):
    """Fails loudly when numba renames or drops the internal the hook wraps (codegen.CPUCodeLibrary.
    _finalize_final_module), instead of silently losing item 4."""
    importlib.import_module("fastbearing.engine.kernel")  # looks up config.CACHE: installs the hook
    from numba.core import codegen

    from fastbearing import _cache

    assert _cache.self_contained_linking()
    assert hasattr(codegen.CPUCodeLibrary._finalize_final_module, "__wrapped__")
    before = _cache.source_hash()
    monkeypatch.setattr(_cache, "LINKING", "linked another way")
    assert _cache.source_hash() != before  # a cache linked the other way is dropped (the stamp differs)
