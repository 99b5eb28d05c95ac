"""The command line as a user runs it: JSON on stdout, exit codes, one-line errors. Most commands run
in process (conftest.cli_run); the first test and the refused-run tests are real subprocesses."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import cli_run

ROOT = Path(__file__).resolve().parents[1]
CLI = [sys.executable, "-m", "fastbearing.cli"]


def run(*args):
    return cli_run(*args)


def test_solve_json_matches_paper_table3_tandem():
    p = subprocess.run([*CLI, "solve", "--preset", "gunduz2013", "--arrangement", "DT", "--load", "1000,0,0,0,-74000", "--json"],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout)
    assert set(out) == {"q", "f", "K", "status", "converged", "iterations", "residual", "speed"}
    assert out["speed"] == 0.0  # rpm: the quasi-static model
    assert out["converged"] and out["status"].startswith("converged")
    diag = np.diag(np.array(out["K"])) / [1e3, 1e3, 1e3, 1e6, 1e6]
    np.testing.assert_allclose(diag, [313, 38, 51, 18, 159], rtol=0.02)


def test_a_command_process_starts_numba_without_scipy_linalg():
    """cli.start_numba_without_blas: a command's process skips the 0.2 s of scipy.linalg that numba imports to
    look for a BLAS (no kernel uses one), answers as before, and can still import scipy.linalg after."""
    p = subprocess.run([sys.executable, "-X", "importtime", *CLI[1:], "solve", "--preset", "gunduz2013",
                        "--arrangement", "DT", "--load", "1000,0,0,0,-74000", "--json"],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    imported = {line.split("|")[-1].strip() for line in p.stderr.splitlines() if line.startswith("import time:")}
    assert "numba.np.arraymath" in imported and "scipy.linalg" not in imported and "numpy.f2py" not in imported
    assert json.loads(p.stdout)["converged"]
    code = ("import fastbearing.cli as c, numba.np.arraymath as m; c.start_numba_without_blas(); "
            "import scipy.linalg; print(m._HAVE_BLAS, scipy.linalg.eigh([[2.0]])[0][0])")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0 and p.stdout.split() == ["True", "2.0"], p.stderr  # numba already started: no change
    code = ("import fastbearing.cli as c; c.start_numba_without_blas(); import numba.np.arraymath as m, scipy.linalg; "
            "print(m._HAVE_BLAS, scipy.linalg.eigh([[2.0]])[0][0])")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0 and p.stdout.split() == ["False", "2.0"], p.stderr


def test_negative_first_component_and_table_output(tmp_path):
    p = run("solve", "--preset", "gunduz2013", "--arrangement", "DB", "--load=-1000,0,3000,0,0")
    assert p.returncode == 0, p.stderr
    assert "status: converged" in p.stdout and "N/mm" in p.stdout and "Fx=-1000" in p.stdout


def test_displacement_given(tmp_path):
    p = run("solve", "--bearing", f"{ROOT}/fastbearing/catalogue/gunduz2013.toml", "--displacement", "0.05,0,0,0,0", "--json")
    out = json.loads(p.stdout)
    assert out["status"] == "direct" and 15e3 < out["f"][0] < 25e3


@pytest.mark.parametrize("args, words", [
    (["solve", "--preset", "gunduz2013", "--load", "1,2"], "--load needs 5"),
    (["solve", "--preset", "gunduz2013", "--load", "-1000,0,3000,0,0"], "must be attached"),
    (["solve", "--preset", "gunduz2013", "--load", "1,0,0,0,nan"], "must be finite"),
    (["solve", "--bearing", "missing.toml", "--load", "1,0,0,0,0"], "file not found"),
    (["solve", "--preset", "gunduz2013", "--arrangement", "XX", "--load", "1,0,0,0,0"], "invalid choice"),
    (["solve", "--load", "1,0,0,0,0"], "required"),
])
def test_bad_input_is_one_line_and_exit_2(args, words):
    p = run(*args)
    assert p.returncode == 2
    assert words in p.stderr
    assert "Traceback" not in p.stderr and len(p.stderr.strip().splitlines()) == 1


def test_help_says_how_to_write_negative_values():
    p = run("solve", "--help")
    assert p.returncode == 0 and "--load=-1000" in p.stdout and "N*mm" in p.stdout


# -- issue 12: every argument is checked before any file is created ---------------------------
SMALL_MAP = '[bearing]\npreset = "gunduz2013"\n\n[loadmap]\nFx = { start = 100.0, stop = 1000.0, num = 3 }\nFz = 500.0\n'


@pytest.mark.parametrize("extra, words", [
    (["-o", "no/such/dir/out.h5"], "output folder"),
    (["--threads", "0"], "threads"),
])
def test_refused_loadmap_leaves_no_file(tmp_path, extra, words):
    (tmp_path / "map.toml").write_text(SMALL_MAP)
    before = set(tmp_path.rglob("*"))
    args = ["loadmap", str(tmp_path / "map.toml")]
    if "-o" not in extra:
        args += ["-o", str(tmp_path / "out.h5")]
    p = subprocess.run([*CLI, *args, *[e if not e.startswith("no/") else str(tmp_path / e) for e in extra]],
                       capture_output=True, text=True, timeout=120, cwd=tmp_path)
    assert p.returncode == 2, p.stderr
    assert words in p.stderr and "Traceback" not in p.stderr
    assert len(p.stderr.strip().splitlines()) == 1
    assert set(tmp_path.rglob("*")) == before          # no .h5, no .h5.part, no folder


def test_absurd_grid_is_refused_with_what_it_would_need(tmp_path):
    body = SMALL_MAP.replace("num = 3", "num = 1000000000000")
    (tmp_path / "map.toml").write_text(body)
    p = run("loadmap", str(tmp_path / "map.toml"), "-o", str(tmp_path / "out.h5"))
    assert p.returncode == 2 and "Traceback" not in p.stderr
    assert "loadmap.Fx.num must be an integer in [1, 1e+07]" in p.stderr
    big = SMALL_MAP.replace("Fz = 500.0", "Fz = { start = 0.0, stop = 1.0, num = 100000 }\n"
                                          "My = { start = 0.0, stop = 1.0, num = 100000 }")
    (tmp_path / "map.toml").write_text(big)
    p = run("loadmap", str(tmp_path / "map.toml"), "-o", str(tmp_path / "out.h5"))
    assert p.returncode == 2 and "Traceback" not in p.stderr and "cases" in p.stderr
    assert not list(tmp_path.glob("out.h5*"))


def test_a_reader_closing_the_pipe_is_not_a_traceback():
    """``fastbearing solve ... | head -3``: exit 141 (as a shell reports SIGPIPE), nothing on stderr."""
    code = ("import sys, fastbearing.cli as c\n"
            "def main():\n    raise BrokenPipeError\n"
            "c.main = main\nsys.exit(c.entry_point())")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert p.returncode == 141 and p.stderr == ""


def test_a_displacement_too_large_for_float64_is_refused_or_flagged(tmp_path):
    """--displacement 1e300: f and Kb overflow. One solve refuses it (exit 2, one line); in a map the
    case is stored with status nonfinite_result, never as converged."""
    p = cli_run("solve", "--preset", "gunduz2013", "--arrangement", "DB", "--displacement", "1e300,0,0,0,0", "--json")
    assert p.returncode == 2 and "overflow" in p.stderr and p.stdout == ""
    import fastbearing as fb
    from fastbearing import status as st

    out = fb.loadmap({"bearing": {"preset": "gunduz2013", "arrangement": "DB"},
                      "loadmap": {"given": "displacement", "dx": [0.01, 1e300]}}, tmp_path / "d.h5", progress=False)
    status = fb.open_dataset(out)["status"].values
    assert status.tolist() == [st.CONVERGED, st.NONFINITE_RESULT]


def test_version_usage_and_overwrite_wording(tmp_path):
    """--version; no arguments prints the usage; the CLI says --overwrite, Python says overwrite=True."""
    from conftest import cli_run as cli

    import fastbearing as fb

    v = cli("--version")
    assert v.returncode == 0 and v.stdout.strip() == f"fastbearing {fb.__version__}"
    bare = cli()
    assert bare.returncode == 0 and "usage: fastbearing" in bare.stdout and "loadmap" in bare.stdout
    assert "%%" not in cli("passage", "--help").stdout
    plot = cli("plot")
    assert plot.returncode == 2 and "PICTURE" in plot.stderr
    cfg = tmp_path / "m.toml"
    cfg.write_text('[bearing]\npreset = "gunduz2013"\n\n[loadmap]\nFx = [100.0, 200.0]\nFz = 500.0\n')
    assert cli("loadmap", cfg).returncode == 0
    again = cli("loadmap", cfg)
    assert again.returncode == 2 and "m.h5 exists; pass --overwrite to replace it" in again.stderr
    assert "overwrite=True" not in again.stderr
    with pytest.raises(ValueError, match="exists; pass overwrite=True"):
        fb.loadmap(cfg, "m.h5", progress=False)


def test_the_bearing_report_is_reachable_from_python_and_gives_the_speed_limit():
    """`fastbearing bearing FILE --json` is fb.bearing_report (the report lives outside the command line),
    with the bearing's speed limit where it can run at speed (bearing.speed_limit), none for roller rows."""
    import json as _json
    from pathlib import Path

    from conftest import cli_run

    import fastbearing as fb

    data = Path(__file__).parents[1] / "fastbearing" / "catalogue"
    for name in ("7014C-DB.toml", "NU205.toml", "6305.toml"):
        b = fb.load_bearing(data / name)
        body = _json.loads(cli_run("bearing", data / name, "--json").stdout)
        assert body == _json.loads(_json.dumps(fb.bearing_report(b)))
        assert ("speed_limit" in body) == (name != "NU205.toml")
    assert fb.bearing_report(fb.load_bearing(data / "7014C-DB.toml"))["speed_limit"] == pytest.approx(134291.28, rel=1e-6)


def test_loadmap_device_cuda_without_a_gpu_is_one_line_exit_2(tmp_path):
    """--device cuda where no GPU can run (here: numba-cuda without a driver) is one line and exit 2, and
    nothing is created."""
    import os

    pytest.importorskip("numba_cuda")
    cfg = tmp_path / "m.toml"
    cfg.write_text('[bearing]\npreset = "gunduz2013"\narrangement = "DB"\n[loadmap]\nFx = [0.0, 500.0]\nFz = 1000.0\n')
    run = subprocess.run([*CLI, "loadmap", str(cfg), "-o", str(tmp_path / "m.h5"), "--device", "cuda"],
                         capture_output=True, text=True,
                         env={k: v for k, v in os.environ.items() if k != "NUMBA_ENABLE_CUDASIM"})
    if run.returncode == 0:
        pytest.skip("a GPU is present")
    assert run.returncode == 2
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and "device 'cuda'" in lines[0], run.stderr
    assert not (tmp_path / "m.h5").exists()
