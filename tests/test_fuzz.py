"""Fuzz every command: mutated bearing files, configs, case tables, shaft configs, export inputs and
command lines (hypothesis). Each run ends in success (exit 0, or 1 where a solve did not converge) or
in exit 2 with one line on stderr that names what is wrong; never a traceback, and a refused run leaves
no file behind.

Commands run in process through ``fastbearing.cli.main`` (a traceback is an exception escaping it);
inputs stay tiny so every accepted map or table takes milliseconds.
"""

import contextlib
import copy
import io
import json
import math
import os
import tempfile
from pathlib import Path

import h5py
import pytest
import numpy as np
from hypothesis import HealthCheck, given, settings, strategies as st

from fastbearing import cli

SETTINGS = settings(max_examples=40, deadline=None, derandomize=True,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


# -- a tiny TOML writer (tomllib only reads) -----------------------------------------------------
def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf") if math.isinf(v) else repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{json.dumps(str(k))} = {_toml_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(type(v))


def to_toml(doc: dict) -> str:
    """Top-level keys whose values are tables become [sections]; everything below is inline."""
    lines = [f"{json.dumps(str(k))} = {_toml_value(v)}" for k, v in doc.items() if not isinstance(v, dict)]
    for k, v in doc.items():
        if isinstance(v, dict):
            lines.append(f"[{json.dumps(str(k))}]")
            lines += [f"{json.dumps(str(kk))} = {_toml_value(vv)}" for kk, vv in v.items()]
    return "\n".join(lines) + "\n"


# -- mutations ------------------------------------------------------------------------------------
_JUNK = st.one_of(
    st.sampled_from([0, 1, 2, -1, 3, 10 ** 12, 2 ** 63 - 1, 0.0, -0.0, 1.5, -2.5, 1e300, 1e-300,
                     math.nan, math.inf, -math.inf, True, False, "", "x", "12", "1e3", "DB", "none",
                     "gzip", "load", "displacement", [], [1], [1.0, 2.0], [[1, 2, 3, 4, 5]], {}, {"num": 3},
                     {"start": 0, "stop": 1, "num": 2}, {"start": 0, "stop": 1, "num": 0}]),
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(-5, 5),
    st.text(max_size=4),
)
JUNK = _JUNK.map(copy.deepcopy)  # sampled lists and dicts are shared objects: never mutate those
KEYS = st.sampled_from(["bogus", "num", "n_balls", "rows", "geometry", "preset", "Fx", "dx", "speed", "cases",
                        "position", "bearing", "mass", "force", "points"])


def _paths(doc, prefix=()):
    """Every (path, value) in a nested dict/list document."""
    yield prefix, doc
    if isinstance(doc, dict):
        for k, v in doc.items():
            yield from _paths(v, prefix + (k,))
    elif isinstance(doc, list):
        for i, v in enumerate(doc):
            yield from _paths(v, prefix + (i,))



# junk values reach the fields whose implausible units only warn (ball_row.unit_warning): the fuzz checks errors
pytestmark = pytest.mark.filterwarnings("ignore::UserWarning")

@st.composite
def mutated(draw, base: dict, n_max: int = 3) -> dict:
    doc = json.loads(json.dumps(base))
    for _ in range(draw(st.integers(1, n_max))):
        paths = list(_paths(doc))
        path, node = draw(st.sampled_from(paths))
        op = draw(st.sampled_from(["replace", "delete", "add"]))
        if op == "add" and isinstance(node, (dict, list)):
            if isinstance(node, dict):
                node[draw(KEYS)] = draw(JUNK)
            else:
                node.append(draw(JUNK))
            continue
        if not path:
            continue
        parent = doc
        for p in path[:-1]:
            parent = parent[p]
        if op == "delete":
            del parent[path[-1]]
        else:
            parent[path[-1]] = draw(JUNK)
    return doc


# -- running a command ------------------------------------------------------------------------------
def run_cli(argv, folder: Path, inputs) -> tuple[int, str]:
    """Run the CLI in ``folder``; check the contract; return (exit code, stdout)."""
    before = set(os.listdir(folder))
    out, err = io.StringIO(), io.StringIO()
    cwd = os.getcwd()
    os.chdir(folder)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = cli.main([str(a) for a in argv])
    finally:
        os.chdir(cwd)
    assert code in (0, 1, 2), (argv, code, err.getvalue())
    if code == 2:
        lines = err.getvalue().strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("fastbearing"), (argv, err.getvalue())
        left = set(os.listdir(folder)) - before
        assert not left, (argv, "a refused run left", left)
    return code, out.getvalue()


def write(folder: Path, name: str, text: str) -> Path:
    path = folder / name
    path.write_text(text)
    return path


PRESET = {"preset": "gunduz2013", "arrangement": "DB"}
COMPACT = {"arrangement": "DF", "n_balls": 12, "hertz_constant": 395000.0, "pitch_radius": 34.75,
           "groove_center_distance": 0.52, "contact_angle": 25.0, "row_offset": 10.0, "axial_preload": [0.0, 0.0]}
ROWS = {"rows": [{"axial_offset": -5.0, "contact_direction": 1, "n_balls": 9, "hertz_constant": 3e5,
                  "pitch_radius": 30.0, "groove_center_distance": 0.5, "contact_angle": 20.0},
                 {"axial_offset": 5.0, "contact_direction": -1, "n_balls": 9, "hertz_constant": 3e5,
                  "pitch_radius": 30.0, "groove_center_distance": 0.5, "contact_angle": 20.0,
                  "radial_clearance": -0.002}]}
GEOMETRY = {"arrangement": "DB", "axial_preload": 0.001,
            "geometry": {"n_balls": 7, "ball_diameter": 11.5, "pitch_diameter": 43.5, "inner_groove_ratio": 0.52,
                         "outer_groove_ratio": 0.53, "contact_angle": 25.0, "row_spacing": 20.0,
                         "material": "silicon-nitride"}}
ROLLERS = {"arrangement": "TDO", "element": "tapered_roller", "n_rollers": 17, "hertz_constant": 3.6e5,
           "pitch_radius": 24.0, "roller_effective_length": 13.0, "contact_angle": 14.0, "row_offset": 9.0,
           "slices": 8, "crown": "circular", "crown_radius": 1500.0, "axial_preload": 0.005}
ROLLER_GEOMETRY = {"arrangement": "single",
                   "geometry": {"element": "cylindrical_roller", "n_rollers": 13, "roller_diameter": 7.5,
                                "roller_effective_length": 7.0, "pitch_diameter": 39.0, "slices": 6,
                                "crown": "logarithmic", "crown_design_load": 5000.0}}
MIXED = {"rows": [ROWS["rows"][0], {"element": "cylindrical_roller", "n_rollers": 14, "hertz_constant": 3e5,
                                    "pitch_radius": 35.0, "roller_effective_length": 11.0, "axial_offset": 20.0,
                                    "slices": 5}]}
BEARINGS = st.sampled_from([PRESET, COMPACT, ROWS, GEOMETRY, ROLLERS, ROLLER_GEOMETRY, MIXED])


@SETTINGS
@given(st.data())
def test_fuzz_bearing_files_through_bearing_and_solve(data):
    doc = data.draw(mutated({"bearing": data.draw(BEARINGS)}))
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        path = write(folder, "b.toml", to_toml(doc))
        run_cli(["bearing", path, *data.draw(st.sampled_from([[], ["--json"]]))], folder, [path])
        run_cli(["solve", "--bearing", path, "--load", "800,-200,1500,3000,-20000", "--json"], folder, [path])


MAP = {"bearing": PRESET, "loadmap": {"Fx": {"start": 0.0, "stop": 1000.0, "num": 3}, "Fz": [500.0, 2000.0],
                                      "My": 0.0, "chunk": 2, "method": "newton", "rtol": 1e-9}}
DISPLACEMENT_MAP = {"bearing": ROWS, "loadmap": {"given": "displacement", "dx": [0.0, 0.01], "dz": 0.005,
                                                 "by": {"start": -1e-4, "stop": 1e-4, "num": 2}}}


@SETTINGS
@given(st.data())
def test_fuzz_loadmap_configs(data):
    doc = data.draw(mutated(data.draw(st.sampled_from([MAP, DISPLACEMENT_MAP]))))
    extra = data.draw(st.sampled_from([[], ["--threads", "0"], ["--threads", "1"], ["--resume"], ["--overwrite"],
                                       ["--threads", "x"], ["--in-flight", "0"], ["--dask", "local:0"]]))
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        cfg = write(folder, "m.toml", to_toml(doc))
        code, _ = run_cli(["loadmap", cfg, "-o", folder / "m.h5", "--no-progress", *extra], folder, [cfg])
        if code == 0:
            assert (folder / "m.h5").exists()


@SETTINGS
@given(st.data())
def test_fuzz_case_tables(data):
    kind = data.draw(st.sampled_from(["npy", "csv", "h5"]))
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        name = f"cases.{kind}"
        if kind == "npy":
            table = data.draw(st.sampled_from([
                np.ones((3, 5)), np.ones((3, 4)), np.ones(5), np.zeros((0, 5)), np.full((2, 5), np.nan),
                np.ones((2, 5), dtype=complex), np.array([(1.0, 2)], dtype=[("a", "f8"), ("b", "i4")]),
                np.array([["1", "2", "3", "4", "5"]]), np.ones((2, 5), dtype=bool), np.ones((2, 5, 1))]))
            np.save(folder / name, table)
        elif kind == "csv":
            text = data.draw(st.sampled_from([
                "Fx,Fy,Fz,Mx,My\n1000,0,3000,0,-74000\n", "1;2;3;4;5\n", "1,2,3,4\n", "a,b,c,d,e\nx,1,2,3,4\n",
                "", "1,2,3,4,5\n1,2,3,4,inf\n", "\x00\x01binary", "1,2,3,4,5,6\n"]))
            write(folder, name, text)
        else:
            with h5py.File(folder / name, "w") as fh:
                what = data.draw(st.sampled_from(["ok", "group", "wrong", "missing", "text"]))
                if what == "ok":
                    fh["cases"] = np.ones((2, 5)) * 500.0
                elif what == "group":
                    fh.create_group("cases")
                elif what == "wrong":
                    fh["cases"] = np.ones((2, 3))
                elif what == "text":
                    fh["cases"] = np.array([b"abc"])
                else:
                    fh["other"] = np.ones((2, 5))
        cfg = write(folder, "m.toml", to_toml({"bearing": PRESET, "loadmap": {"cases": name}}))
        run_cli(["loadmap", cfg, "-o", folder / "m.h5", "--no-progress"], folder, [cfg, folder / name])


PASSAGE = {"bearing": PRESET, "passage": {"points": [[0.02, 0.0, 0.0, 0.0, 0.0]], "positions": 8, "harmonics": 2}}
PASSAGE_LOAD = {"bearing": COMPACT, "passage": {"given": "load", "Fx": [500.0, 1000.0], "positions": 6,
                                                "shaft_speed": 3000.0, "ball_diameter": 12.0,
                                                "pitch_diameter": 70.0}}


@SETTINGS
@given(st.data())
def test_fuzz_passage_configs(data):
    doc = data.draw(mutated(data.draw(st.sampled_from([PASSAGE, PASSAGE_LOAD]))))
    extra = data.draw(st.sampled_from([[], ["--csv"], ["--threads", "0"], ["--overwrite"]]))
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        cfg = write(folder, "p.toml", to_toml(doc))
        run_cli(["passage", cfg, "-o", folder / "p.h5", *extra], folder, [cfg])


SHAFT = {"shaft": {"reference": 74.0,
                   "bearings": [{"position": 64.0, "bearing": {"preset": "gunduz2013", "arrangement": "single"}},
                                {"position": 84.0, "mirrored": True, "name": "b",
                                 "bearing": {"preset": "gunduz2013", "arrangement": "single"}}],
                   "loads": [{"position": 0.0, "force": [1000.0, 0.0, 3000.0], "moment": [0.0, 0.0]}],
                   "mass": {"mass": 3.0, "inertia_x": 2000.0, "inertia_y": 2000.0, "center": 74.0}}}


@SETTINGS
@given(st.data())
def test_fuzz_shaft_configs(data):
    doc = data.draw(mutated(SHAFT, n_max=2))
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        cfg = write(folder, "s.toml", to_toml(doc))
        run_cli(["shaft", cfg, *data.draw(st.sampled_from([[], ["--json"]]))], folder, [cfg])


SOLVE_JSON = {"q": [0.0] * 5, "f": [0.0] * 5, "K": np.eye(5).tolist(), "status": "converged", "converged": True}


@SETTINGS
@given(st.data())
def test_fuzz_export_inputs(data):
    fmt = data.draw(st.sampled_from(["csv", "json", "npz", "dmig", "ross"]))
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        if data.draw(st.booleans()):
            body = data.draw(st.one_of(mutated(SOLVE_JSON, n_max=2), JUNK))
            src = write(folder, "r.json", json.dumps(body))
        else:
            src = folder / "m.h5"
            with h5py.File(src, "w") as fh:
                what = data.draw(st.sampled_from(["K", "group", "wrong", "none", "part"]))
                if what in ("K", "part"):
                    fh["K"] = np.tile(np.eye(5), (3, 1, 1))
                    fh.attrs["fastbearing_complete"] = int(what == "K")
                elif what == "group":
                    fh.create_group("K")
                elif what == "wrong":
                    fh["K"] = np.ones((3, 4))
        extra = data.draw(st.sampled_from([[], ["--case", "0"], ["--case", "99"], ["--case", "-1"],
                                           ["--node=-4"], ["--grid", "0"], ["--ground-grid", "1"]]))
        run_cli(["export", src, "--format", fmt, "-o", folder / f"out.{fmt}", *extra], folder, [src])


OPTIONS = st.sampled_from([
    ["--preset", "gunduz2013"], ["--preset", "nope"], ["--bearing", "missing.toml"], ["--bearing", "."],
    ["--arrangement", "DT"], ["--arrangement", "XX"], ["--load", "1000,0,3000,0,-74000"], ["--load", "1,2"],
    ["--load=-1000,0,0,0,0"], ["--load", "1e300,0,0,0,0"], ["--load", "nan,0,0,0,0"], ["--load", "a,b,c,d,e"],
    ["--displacement", "0.01,0,0,0,0"], ["--displacement", "1e300,0,0,0,0"], ["--method", "broyden"],
    ["--method", "x"], ["--json"], ["--balls"], ["-o", "nodir/x.h5"], ["--threads", "0"], ["--overwrite"],
    ["--format", "csv"], ["--var", "kzz"], ["--x", "Fx"], ["--y", "My"], ["--case", "0"], ["--size", "10x"],
])


@SETTINGS
@given(st.sampled_from(["solve", "bearing", "loadmap", "passage", "shaft", "export", "plot", "paper", "bogus"]),
       st.lists(OPTIONS, max_size=4))
def test_fuzz_command_lines(command, options):
    with tempfile.TemporaryDirectory() as tmp:
        argv = [command] + [a for opt in options for a in opt]
        run_cli(argv, Path(tmp), [])
