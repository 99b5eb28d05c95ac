"""Shared fixtures: the paper's bearing, random bearings in both the
fastbearing and the naive-reference form."""

import math
import os
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))

import fastbearing as fb  # noqa: E402
from hypothesis import settings  # noqa: E402

# Subprocesses (the real command line, killed and resumed runs, README examples) import the same fastbearing
# as this process, not an installed copy elsewhere: they test the same code and share its numba cache (an
# installed copy is other files to numba, so every subprocess compiled the kernels again: 1-2 min of CI).
os.environ["PYTHONPATH"] = os.pathsep.join(
    p for p in (str(Path(fb.__file__).resolve().parents[1]), os.environ.get("PYTHONPATH")) if p)


def pytest_report_header(config):
    """Which fastbearing the run tests: the installed package (the README's `python -P -m pytest`, which keeps
    the clone's folder off sys.path) or a source tree."""
    return f"fastbearing {fb.__version__} from {Path(fb.__file__).resolve().parent}"


# Property tests draw the same examples on every run and machine: a CI result can be reproduced, and a
# failure is a property of the code, not of the day's random seed.
settings.register_profile("fastbearing", derandomize=True, database=None)
settings.load_profile("fastbearing")

PAPER_LOADS = {"table3": (1000.0, 0.0, 0.0, 0.0, -74000.0), "table4": (1000.0, 0.0, 3000.0, 0.0, -74000.0)}


def to_row(d: dict) -> fb.Row:
    """A naive-reference row dict (angles in rad) as a fastbearing Row (angles in degrees)."""
    return fb.Row(n_balls=d["n_balls"], hertz_constant=d["hertz_constant"], pitch_radius=d["pitch_radius"],
                  groove_center_distance=d["groove_center_distance"], contact_angle=math.degrees(d["contact_angle"]),
                  axial_offset=d["axial_offset"], contact_direction=d["contact_direction"], exponent=d["exponent"],
                  radial_clearance=d["radial_clearance"], axial_preload=d["axial_preload"],
                  first_ball_angle=math.degrees(d["first_ball_angle"]))


def random_rows(rng, n_rows=None, exponent=None) -> list[dict]:
    """Random but physical rows: clearance or preload or neither, both contact directions."""
    n_rows = n_rows or int(rng.integers(1, 4))
    rows = []
    for _ in range(n_rows):
        A0 = rng.uniform(0.2, 1.0)
        kind = rng.integers(0, 3)
        rows.append(dict(
            n_balls=int(rng.integers(3, 20)), first_ball_angle=rng.uniform(0, 2 * math.pi),
            axial_offset=float(rng.choice([0.0, rng.uniform(-30, 30)])), contact_direction=int(rng.choice([-1, 1])),
            contact_angle=math.radians(rng.uniform(5, 80)), groove_center_distance=A0,
            pitch_radius=rng.uniform(10, 80), hertz_constant=rng.uniform(1e5, 1e6),
            exponent=exponent if exponent is not None else float(rng.choice([1.5, rng.uniform(1.1, 2.0)])),
            radial_clearance=rng.uniform(0, 0.02) if kind == 1 else 0.0,
            axial_preload=rng.uniform(0, 0.02) if kind == 2 else 0.0))
    return rows


def random_q(rng, scale=0.03):
    """Random small displacement: mm for translations, rad for tilts."""
    return np.concatenate([rng.uniform(-scale, scale, 3), rng.uniform(-scale / 40, scale / 40, 2)])


@pytest.fixture(params=["DB", "DF", "DT"])
def paper_double(request):
    return fb.Bearing.preset("gunduz2013", request.param)


@pytest.fixture(autouse=True)
def _run_in_a_temporary_folder(tmp_path, monkeypatch):
    """Every test runs in its own folder: outputs that default to the current folder never reach the checkout."""
    monkeypatch.chdir(tmp_path)


@pytest.fixture
def rng():
    return np.random.default_rng(20131122)


def interrupted_after(job, n_blocks):
    """The same job (jobs.Job), but Ctrl-C arrives as block ``n_blocks`` (0-based) starts: its sweep
    sees the stop flag set, as after a real SIGINT; a deterministic interruption, no timing involved."""
    import dataclasses

    calls = []

    def compute(inputs, res, first, stop):
        if len(calls) == n_blocks:
            stop[0] = 1
        calls.append(1)
        job.compute(inputs, res, first, stop)

    return dataclasses.replace(job, compute=compute)


class CliResult:
    """What a command-line run gave: exit code, stdout and stderr (like subprocess.CompletedProcess)."""

    def __init__(self, returncode: int, stdout: str, stderr: str):
        self.returncode, self.stdout, self.stderr = returncode, stdout, stderr


#: The start of a child process's script that counts numba's compilations in ``count[0]`` (tests/test_warmup.py,
#: tests/test_prebuilt.py: a cached or prebuilt kernel must compile nothing).
COUNT_COMPILATIONS = """
import sys
from numba.core import event

count = [0]


class Count(event.Listener):
    def on_start(self, ev):
        count[0] += 1

    def on_end(self, ev):
        pass


event.register("numba:compile", Count())
"""


def cli_run(*args, cwd=None) -> CliResult:
    """``fastbearing ARGS`` in this process through ``cli.main`` (a subprocess costs ~1 s of start-up;
    a few smoke tests still run the real thing). An exception escaping main is a traceback: it fails."""
    import contextlib
    import io

    from fastbearing import cli

    out, err = io.StringIO(), io.StringIO()
    with contextlib.ExitStack() as stack:
        if cwd is not None:
            stack.enter_context(contextlib.chdir(cwd))
        stack.enter_context(contextlib.redirect_stdout(out))
        stack.enter_context(contextlib.redirect_stderr(err))
        try:
            code = cli.main([str(a) for a in args])
        except SystemExit as exc:  # argparse: --help (0) and usage errors (2)
            code = exc.code if isinstance(exc.code, int) else 1
    return CliResult(code, out.getvalue(), err.getvalue())
