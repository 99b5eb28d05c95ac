"""The command line as a user runs it: real subprocesses, JSON on stdout, exit codes."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
CLI = [sys.executable, "-m", "fastbearing.cli"]


def run(*args):
    return subprocess.run([*CLI, *args], capture_output=True, text=True, timeout=120)


def test_solve_json_matches_paper_table3_tandem():
    p = run("solve", "--preset", "gunduz2013", "--arrangement", "DT", "--load", "1000,0,0,0,-74000", "--json")
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout)
    assert set(out) == {"q", "f", "K", "status", "converged", "iterations", "residual"}
    assert out["converged"] and out["status"].startswith("converged")
    diag = np.diag(np.array(out["K"])) / [1e3, 1e3, 1e3, 1e6, 1e6]
    np.testing.assert_allclose(diag, [313, 38, 51, 18, 159], rtol=0.02)


def test_negative_first_component_and_table_output(tmp_path):
    p = run("solve", "--preset", "gunduz2013", "--arrangement", "DB", "--load=-1000,0,3000,0,0")
    assert p.returncode == 0, p.stderr
    assert "status: converged" in p.stdout and "N/mm" in p.stdout and "Fx=-1000" in p.stdout


def test_displacement_given(tmp_path):
    p = run("solve", "--bearing", f"{ROOT}/data/bearings/gunduz2013.toml", "--displacement", "0.05,0,0,0,0", "--json")
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
