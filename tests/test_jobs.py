"""The one job runner: load maps and ball-passage tables get the same resume, Ctrl-C, progress,
summary and checks, because they run through the same code (jobs.py)."""

import signal
import subprocess
import sys
import time

import h5py
import numpy as np
import pytest
from conftest import cli_run, interrupted_after

import importlib

import fastbearing as fb
from fastbearing.jobs import runner as jobs
from fastbearing.jobs import storage

# the modules, not the functions of the same name that the package exports
loadmap_module = importlib.import_module("fastbearing.jobs.loadmap")
passage_module = importlib.import_module("fastbearing.jobs.passage")

BEARING = {"preset": "gunduz2013", "arrangement": "DB"}
MAP = {"bearing": BEARING, "loadmap": {"Fx": {"start": -2000.0, "stop": 2000.0, "num": 8},
                                       "Fz": {"start": 500.0, "stop": 6000.0, "num": 12}, "chunk": 16}}
TABLE = {"bearing": BEARING, "passage": {"given": "load", "Fx": {"start": 200.0, "stop": 3000.0, "num": 9},
                                         "Fz": 1500.0, "positions": 16, "chunk": 2}}
KINDS = {"loadmap": (MAP, loadmap_module, fb.loadmap), "passage": (TABLE, passage_module, fb.passage)}


def read_all(path):
    """Every dataset of a finished file but the provenance, as arrays."""
    with h5py.File(path, "r") as fh:
        return {name: fh[name][...] for name in fh}


def assert_identical(a, b):
    da, db = read_all(a), read_all(b)
    assert set(da) == set(db)
    for name in da:
        np.testing.assert_array_equal(da[name], db[name], err_msg=name)


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_interrupted_run_resumes_bit_identical(tmp_path, kind):
    config, module, run = KINDS[kind]
    reference = run(config, tmp_path / "reference.h5", progress=False)
    job = module.job(module.read_config(config))
    out = tmp_path / "out.h5"
    with pytest.raises(KeyboardInterrupt):
        jobs.run(interrupted_after(job, 3), out, progress=False)
    part = tmp_path / "out.h5.part"
    assert part.exists() and not out.exists()
    with h5py.File(part, "r") as fh:
        assert fh["block_done"][...].tolist()[:4] == [1, 1, 1, 0]       # finished blocks kept, nothing more
    with pytest.raises(ValueError, match=r"an unfinished run exists .*--resume"):
        run(config, out, progress=False)
    run(config, out, resume=True, progress=False)
    assert_identical(out, reference)
    assert not part.exists()


def test_passage_resume_refuses_a_changed_config(tmp_path):
    job = passage_module.job(passage_module.read_config(TABLE))
    with pytest.raises(KeyboardInterrupt):
        jobs.run(interrupted_after(job, 1), tmp_path / "t.h5", progress=False)
    changed = {"bearing": BEARING, "passage": {**TABLE["passage"], "positions": 32}}
    with pytest.raises(ValueError, match="different config"):
        fb.passage(changed, tmp_path / "t.h5", resume=True, progress=False)


def test_passage_cli_resume_and_summary(tmp_path):
    cfg = tmp_path / "t.toml"
    cfg.write_text('[bearing]\npreset = "gunduz2013"\narrangement = "DB"\n\n[passage]\ngiven = "load"\n'
                   "Fx = { start = 200.0, stop = 3000.0, num = 9 }\nFz = 1500.0\npositions = 16\nchunk = 2\n")
    job = passage_module.job(passage_module.read_config(cfg))
    with pytest.raises(KeyboardInterrupt):
        jobs.run(interrupted_after(job, 2), tmp_path / "t.h5", progress=False)
    p = cli_run("passage", cfg, "-o", tmp_path / "t.h5", "--resume", "--csv")
    assert p.returncode == 0, p.stderr
    assert "9 points x 16 positions (5 computed in this run, the rest resumed), 100.00 % converged" in p.stderr
    assert len(list(tmp_path.glob("t_point*.csv"))) == 9
    reference = fb.passage(cfg, tmp_path / "ref.h5", progress=False)
    assert_identical(tmp_path / "t.h5", reference)


def test_passage_ctrl_c_exits_130_and_keeps_finished_blocks(tmp_path):
    """A real SIGINT to a running passage: exit 130, one line saying how to resume, blocks kept."""
    cfg = tmp_path / "big.toml"
    cfg.write_text('[bearing]\npreset = "gunduz2013"\narrangement = "DB"\n\n[passage]\ngiven = "load"\n'
                   "Fx = { start = 200.0, stop = 3000.0, num = 400 }\nFz = { start = 500.0, stop = 5000.0, num = 20 }"
                   "\npositions = 64\nchunk = 100\n")
    part = tmp_path / "big.h5.part"
    proc = subprocess.Popen([sys.executable, "-m", "fastbearing.cli", "passage", str(cfg), "--threads", "1"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tmp_path)
    deadline = time.time() + 120
    while time.time() < deadline and proc.poll() is None and _blocks_done(part) < 2:
        time.sleep(0.02)
    assert proc.poll() is None, "the run ended before it could be interrupted"
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130 and "--resume" in err and "Traceback" not in err
    assert part.exists() and _blocks_done(part) >= 2 and not (tmp_path / "big.h5").exists()


def _blocks_done(part):
    try:
        with h5py.File(part, "r", locking=False) as fh:     # the writer holds HDF5's lock
            return int(fh["block_done"][...].sum())
    except (OSError, KeyError):
        return 0


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_progress_bar_counts_every_case(tmp_path, kind, capsys):
    config, _, run = KINDS[kind]
    run(config, tmp_path / "p.h5", progress=True)
    err = capsys.readouterr().err
    n = 96 if kind == "loadmap" else 9
    word = "case" if kind == "loadmap" else "point"
    import re

    assert re.search(rf"100%.*\b{n}(\.0+)?/{n}(\.0+)? .*{word}/s", err), err
    assert "% converged" in err.splitlines()[-1]


def test_compiling_is_announced_when_it_happens_for_any_signature(monkeypatch, capsys):
    """A run says it compiles when numba starts (a new signature of a cached kernel too: a map at speed after
    a quasi-static one once compiled 61 s in silence), once per process, and times it; a compiled kernel:
    silence and no time."""
    from numba import njit

    from fastbearing import _cache

    monkeypatch.setattr(_cache, "_told", False)
    add = njit(lambda x: x + 1)
    add(1)
    with _cache.CompileWatch() as watch:
        add(2)
    assert watch.seconds == 0.0 and "compiling" not in capsys.readouterr().err
    with _cache.CompileWatch() as watch:
        add(2.5)  # another signature: compiles
    assert watch.seconds > 0.0 and "compiling the kernels" in capsys.readouterr().err
    with _cache.CompileWatch() as watch:
        add(1j)
    assert watch.seconds > 0.0 and "compiling" not in capsys.readouterr().err  # said once


def test_the_summary_keeps_compiling_apart_and_says_what_a_resumed_run_computed():
    from fastbearing.jobs import loadmap

    job = loadmap.job(loadmap.read_config(MAP))
    n = job.cases.n_cases
    text = jobs._summary(job, {0: n}, 12.0, n, 0.0, 10.0)
    compile_line, line = text.splitlines()
    assert compile_line.startswith("fastbearing: compiling took 10.0 s")
    assert "; 2.00 s wall" in line and f"{n / 2.0:,.0f} solves/s" in line
    line = jobs._summary(job, {0: n}, 2.0, n // 4, 0.0, 0.0)
    assert f"({n // 4} computed in this run, the rest resumed)" in line and f"{(n // 4) / 2.0:,.0f} solves/s" in line


def test_one_description_of_the_variables_allocates_and_writes(tmp_path):
    """The arrays the runner allocates are exactly the datasets the file holds (names, shapes, dtypes)."""
    for config, module, run in KINDS.values():
        job = module.job(module.read_config(config))
        arrays = storage.allocate(job.variables, job.sizes, job.cases.n_cases)
        out = run(config, tmp_path / f"{module.__name__}.h5", progress=False)
        with h5py.File(out, "r") as fh:
            for name, a in arrays.items():
                ds = fh[name]
                assert ds.dtype == a.dtype, name
                assert ds.shape == job.cases.shape + a.shape[1:], name


@pytest.mark.parametrize("args, words", [
    (["--in-flight", "0", "--dask", "local:1"], "--in-flight must be an integer in [1, 10000], got 0"),
    (["--in-flight", "2"], "--in-flight goes with --dask"),
    (["--threads", "0"], "threads"),
])
@pytest.mark.parametrize("command", ["loadmap", "passage"])
def test_job_options_are_checked_before_anything_starts(tmp_path, command, args, words):
    cfg = tmp_path / "c.toml"
    table = "loadmap" if command == "loadmap" else "passage"
    cfg.write_text(f'[bearing]\npreset = "gunduz2013"\n\n[{table}]\nFx = [100.0, 200.0]\n')
    p = cli_run(command, cfg, *args)
    assert p.returncode == 2 and words in p.stderr and "Traceback" not in p.stderr, p.stderr
    assert sorted(x.name for x in tmp_path.iterdir()) == ["c.toml"]


# -- finishing, locking, resuming the wrong thing (issue 18) ------------------------------------------

def test_resume_of_a_complete_file_with_another_config_is_refused(tmp_path):
    fb.loadmap(MAP, tmp_path / "m.h5", progress=False)
    changed = {"bearing": BEARING, "loadmap": {**MAP["loadmap"], "Fz": 700.0}}
    with pytest.raises(ValueError, match="complete but was made from a different config"):
        fb.loadmap(changed, tmp_path / "m.h5", resume=True, progress=False)
    fb.loadmap(MAP, tmp_path / "m.h5", resume=True, progress=False)          # the same config: nothing to do


@pytest.mark.parametrize("compression", ["none", "lzf"])
def test_a_run_killed_while_finishing_is_completed_by_resume(tmp_path, monkeypatch, compression):
    """Every block computed, then killed inside finish (after the file was marked complete, before the
    rename or half-way through the repack): --resume completes it, nothing recomputed or lost."""
    from fastbearing.jobs import storage

    config = {"bearing": BEARING, "loadmap": {**MAP["loadmap"], "compression": compression}}
    reference = fb.loadmap(config, tmp_path / "ref.h5", progress=False)
    real_replace = storage.os.replace

    def killed(src, dst):
        raise KeyboardInterrupt                   # as if the process died here

    monkeypatch.setattr(storage.os, "replace", killed)
    with pytest.raises(KeyboardInterrupt):
        fb.loadmap(config, tmp_path / "m.h5", progress=False)
    monkeypatch.setattr(storage.os, "replace", real_replace)
    part = tmp_path / "m.h5.part"
    assert part.exists() and storage.is_complete(part) and not (tmp_path / "m.h5").exists()
    with pytest.raises(ValueError, match="an unfinished run exists"):
        fb.loadmap(config, tmp_path / "m.h5", progress=False)
    fb.loadmap(config, tmp_path / "m.h5", resume=True, progress=False)
    assert_identical(tmp_path / "m.h5", reference)
    assert not part.exists() and not list(tmp_path.glob("*.packing"))


def test_a_live_run_holds_the_output_and_a_dead_ones_lock_is_taken_over(tmp_path):
    import os

    lock = tmp_path / "m.h5.lock"
    lock.write_text(str(os.getpid()))                        # a live process holds it
    with pytest.raises(ValueError, match=rf"another run \(pid {os.getpid()}\) is writing"):
        fb.loadmap(MAP, tmp_path / "m.h5", progress=False)
    assert not (tmp_path / "m.h5.part").exists()
    gone = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    lock.write_text(gone.stdout.strip())                      # that process has exited: a stale lock
    fb.loadmap(MAP, tmp_path / "m.h5", progress=False)
    assert (tmp_path / "m.h5").exists() and not lock.exists()


@pytest.fixture
def small_disk(tmp_path):
    """A 2 MB file system (tmpfs), where the machine lets us mount one (root); else skipped."""
    import shutil

    mount = tmp_path / "small"
    mount.mkdir()
    if shutil.which("mount") is None:
        pytest.skip("no mount command: cannot make a small file system here")
    made = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=2m", "tmpfs", str(mount)], capture_output=True)
    if made.returncode != 0:
        pytest.skip(f"cannot mount a small tmpfs here ({made.stderr.decode().strip() or 'not root'})")
    yield mount
    subprocess.run(["umount", "-l", str(mount)], capture_output=True)


@pytest.mark.parametrize("compression", ["none", "gzip"])
def test_a_full_disk_is_one_line_and_keeps_the_finished_blocks(small_disk, monkeypatch, compression):
    """The up-front space check passes (another writer fills the disk later, say: here the check is
    switched off), then the disk fills during the block writes or the repack: one line, exit 1, the
    finished blocks kept, no .packing left, no crash by a signal."""
    from fastbearing.jobs import storage

    monkeypatch.setattr(storage, "check_disk_space", lambda *a: None)
    cfg = small_disk / "m.toml"
    size = 3 if compression == "none" else 1        # 3 x 8 000 cases ~ 8 MB; 1 x 4 000 fits, gzip copy does not
    cfg.write_text('[bearing]\npreset = "gunduz2013"\narrangement = "DB"\n\n[loadmap]\n'
                   f"Fx = {{ start = 100.0, stop = 2000.0, num = {size} }}\n"
                   "Fz = { start = 500.0, stop = 6000.0, num = 4000 }\nchunk = 4000\n"
                   f'compression = "{compression}"\n')
    if compression == "gzip":
        (small_disk / "ballast").write_bytes(b"\0" * 600_000)   # leave room for the map but not its copy
    p = cli_run("loadmap", cfg, "-o", small_disk / "m.h5")
    assert p.returncode == 1, p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and "the disk is full" in lines[0] and "--resume" in lines[0]
    assert (small_disk / "m.h5.part").exists() and not (small_disk / "m.h5").exists()
    assert not list(small_disk.glob("*.packing")) and not (small_disk / "m.h5.lock").exists()
