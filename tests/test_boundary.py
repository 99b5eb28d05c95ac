"""Mixed boundary conditions (fastbearing/boundary.py; docs/model.md, "Mixed boundary conditions: the reduced
system"): any degree of freedom given as a displacement, the rest as loads, the reactions found; checked
against references written from the equations (tests/naive.py solved by scipy on the free degrees of freedom),
the all-load solve it must reproduce, single solves against maps and passage tables, life, the command
line, and bad input."""

import json
import math
from pathlib import Path

import h5py
import numpy as np
import pytest
from scipy.optimize import fsolve

import fastbearing as fb
from naive import bearing_load_extended

DATA = Path(__file__).parent.parent / "fastbearing" / "catalogue"
BALL = fb.load_bearing(DATA / "6305.toml")
TAPERED = fb.load_bearing(DATA / "30206.toml")
DB = fb.Bearing.preset("gunduz2013", "DB")


def _reference(bearing, load, fixed):
    """q and f from the equations: scipy's fsolve on the free degrees of freedom of naive.bearing_load_extended
    (f in extended precision, ball by ball and slice by slice), the fixed ones held at their values."""
    names = ("dx", "dy", "dz", "bx", "by")
    free = [i for i, n in enumerate(names) if n not in fixed]
    q0 = fb.solve(bearing, load, fixed=fixed).q  # a start near the answer: fsolve only polishes

    def full(x):
        q = np.array([fixed.get(n, 0.0) for n in names], dtype=float)
        q[free] = x
        return q

    L = bearing.length_scale
    scale = np.array([1, 1, 1, 1 / L, 1 / L])
    x = fsolve(lambda x: ((bearing_load_extended(full(x), bearing).astype(float) - load) * scale)[free],
               q0[free], xtol=1e-14)
    q = full(x)
    return q, bearing_load_extended(q, bearing).astype(float)


def test_a_single_ball_row_with_its_tilt_fixed_matches_the_equations():
    """6305 under (Fx, Fz) with bx = by = 0: q and the reaction moments against the reference, 1e-8."""
    load = [3000.0, 0.0, 1000.0, 0.0, 0.0]
    r = fb.solve(BALL, load, fixed={"bx": 0.0, "by": 0.0})
    assert r.converged and r.fixed == ("bx", "by")
    assert r.q[3] == 0.0 and r.q[4] == 0.0
    q_ref, f_ref = _reference(BALL, np.array(load), {"bx": 0.0, "by": 0.0})
    assert np.abs(r.q - q_ref).max() <= 1e-8 * np.abs(q_ref).max()
    assert np.abs(r.f - f_ref).max() <= 1e-8 * np.abs(f_ref).max()
    assert abs(r.f[4]) > 1000.0  # the shaft holds a real moment
    assert np.allclose(r.f[:3], load[:3], rtol=1e-10, atol=1e-9)


def test_a_single_tapered_row_under_a_radial_load_solves_with_its_axial_displacement_fixed():
    """Without an axial load a tapered row has no solution (its contact normal turns a radial load
    axial); with dz = 0 held it converges, and its axial reaction is the slice equations'."""
    load = [5000.0, 0.0, 0.0, 0.0, 0.0]
    assert not fb.solve(TAPERED, load).converged
    for fixed in ({"dz": 0.0}, {"dz": 0.0, "bx": 0.0, "by": 0.0}):
        r = fb.solve(TAPERED, load, fixed=fixed)
        assert r.converged
        q_ref, f_ref = _reference(TAPERED, np.array(load), fixed)
        assert np.abs(r.q - q_ref).max() <= 1e-8 * np.abs(q_ref).max()
        assert r.f[2] == pytest.approx(f_ref[2], rel=1e-8) and r.f[2] > 1000.0


def test_fixing_the_values_the_all_load_solve_found_reproduces_it():
    """Fix bx, by (and then dz) at the all-load solution: the same q (the fixed entries exactly), Kb, and the
    moments as reactions."""
    load = [1000.0, 500.0, 3000.0, 2e4, -7.4e4]
    a = fb.solve(DB, load)
    for names in (("bx", "by"), ("dz",), ("dx", "by")):
        fixed = {n: float(a.q[("dx", "dy", "dz", "bx", "by").index(n)]) for n in names}
        given = [0.0 if ("dx", "dy", "dz", "bx", "by")[i] in names else v for i, v in enumerate(load)]
        r = fb.solve(DB, given, fixed=fixed)
        assert r.converged
        for n, v in fixed.items():
            assert r.q[("dx", "dy", "dz", "bx", "by").index(n)] == v
        # the same solution, reached on the reduced system: to rounding (measured at most 4.4e-13)
        assert np.abs(r.q - a.q).max() <= 1e-11 * np.abs(a.q).max()
        assert np.abs(r.K - a.K).max() <= 1e-11 * np.abs(a.K).max()
        assert np.abs(r.f - load).max() <= 1e-11 * np.abs(load).max()


def test_broyden_and_solve_many_with_per_case_values_agree_with_single_newton_solves():
    loads = np.array([[1000.0, 0, 3000.0, 0, 0]] * 4)
    tilts = [0.0, 1e-4, -2e-4, 3e-4]
    many = fb.solve_many(DB, loads, fixed={"by": tilts, "bx": 0.0})
    for i, b in enumerate(tilts):
        one = fb.solve(DB, loads[i], fixed={"by": b, "bx": 0.0})
        broyden = fb.solve(DB, loads[i], fixed={"by": b, "bx": 0.0}, method="broyden")
        assert many.converged[i] and one.converged and broyden.converged
        assert np.abs(many.q[i] - one.q).max() <= 1e-9 * np.abs(one.q).max()
        assert np.abs(broyden.q - one.q).max() <= 1e-8 * np.abs(one.q).max()
        assert many.q[i, 4] == b


def test_at_speed_a_fixed_tilt_holds_the_spindle_pair():
    b = fb.load_bearing(DATA / "7014C-DB.toml")
    r = fb.solve(b, [800.0, 0, 500.0, 0, 0], speed=12000.0, fixed={"bx": 0.0, "by": 0.0})
    assert r.converged and r.q[3] == 0.0 and r.q[4] == 0.0
    f_fresh, _ = fb.stiffness(b, r.q, speed=12000.0)
    assert np.allclose(f_fresh, r.f, rtol=1e-9, atol=1e-6)


def test_a_free_tilt_is_said_and_how_to_fix_it():
    r = fb.solve(TAPERED, [5000.0, 0, 2000.0, 0, 0])
    assert r.converged and "tilted freely" in r.note and "--fix bx=0,by=0" in r.note
    assert "tilted" not in fb.solve(TAPERED, [5000.0, 0, 2000.0, 0, 0], fixed={"bx": 0.0, "by": 0.0}).note
    assert "tilted" not in fb.solve(DB, [5000.0, 0, 2000.0, 0, 0]).note  # a pair holds its tilt


def test_life_with_the_tilt_fixed():
    """30206 under (5 kN, 0, 2 kN): free to tilt, the ring tilts 5.7 mrad and L10r is far below ISO 281's L10;
    held, L10r is the load distribution's life of the held ring (its reaction moment included)."""
    load = [5000.0, 0, 2000.0, 0, 0]
    free = fb.rating_life(TAPERED, load)
    held = fb.rating_life(TAPERED, load, fixed={"bx": 0.0, "by": 0.0})
    assert free.L10r < 0.5 * free.L10 < held.L10r
    r = fb.solve(TAPERED, load, fixed={"bx": 0.0, "by": 0.0})
    assert held.L10r == pytest.approx(fb.rating_life(TAPERED, r.f, q=r.q).L10r, rel=1e-12)


def test_a_map_over_a_misalignment_axis_equals_single_solves(tmp_path):
    cfg = {"bearing": {"preset": "gunduz2013", "arrangement": "DB"},
           "loadmap": {"Fx": {"start": 500.0, "stop": 3000.0, "num": 4}, "Fz": 2000.0,
                       "fixed": {"bx": 0.0, "by": {"start": -1e-3, "stop": 1e-3, "num": 5}}}}
    out = fb.loadmap(cfg, tmp_path / "m.h5", progress=False)
    with h5py.File(out) as h:
        assert h.attrs["fixed_dofs"] == "bx, by" and h["by"].attrs["units"] == "rad"
        q, f, K, Fx, by = h["q"][...], h["f"][...], h["K"][...], h["Fx"][...], h["by"][...]
        assert (h["status"][...] == 0).all()
    for i, fx in enumerate(Fx):
        for j, b in enumerate(by):
            s = fb.solve(DB, [fx, 0, 2000.0, 0, 0], fixed={"bx": 0.0, "by": b})
            assert q[i, j, 4] == b
            assert np.abs(s.q - q[i, j]).max() <= 1e-9 * np.abs(s.q).max()
            assert np.abs(s.f - f[i, j]).max() <= 1e-8 * np.abs(s.f).max()
            assert np.abs(s.K - K[i, j]).max() <= 1e-8 * np.abs(s.K).max()


def test_a_passage_table_with_the_tilt_fixed_keeps_it_at_every_position(tmp_path):
    cfg = {"bearing": {"preset": "gunduz2013", "arrangement": "DB"},
           "passage": {"given": "load", "Fx": 3000.0, "Fz": 1000.0, "fixed": {"bx": 0.0, "by": 0.0}, "positions": 6}}
    out = fb.passage(cfg, tmp_path / "p.h5", progress=False)
    with h5py.File(out) as h:
        q, f = h["q"][...].reshape(-1, 5), h["f"][...].reshape(-1, 5)
        assert h.attrs["fixed_dofs"] == "bx, by" and (h["status"][...] == 0).all()
    assert (q[:, 3:] == 0.0).all()
    one = fb.solve(DB, [3000.0, 0, 1000.0, 0, 0], fixed={"bx": 0.0, "by": 0.0})
    assert np.abs(q[0] - one.q).max() <= 1e-9 * np.abs(one.q).max()


def test_the_command_line_fixes_and_reports_the_reactions(capsys):
    from fastbearing.cli import main

    assert main(["solve", "--bearing", str(DATA / "30206.toml"), "--load", "5000,0,2000,0,0", "--fix", "bx=0,by=0",
                 "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["fixed"] == ["bx", "by"] and out["q"][3:] == [0.0, 0.0] and abs(out["f"][4]) > 1000
    assert main(["solve", "--bearing", str(DATA / "30206.toml"), "--load", "5000,0,2000,0,0", "--fix", "bx=0,by=0"]) == 0
    assert "fixed (given as displacements): bx, by; f there is the reaction" in capsys.readouterr().out


@pytest.mark.parametrize("args,message", [
    (["--fix", "bz=0"], r"--fix bz is not a degree of freedom"),
    (["--fix", "by=0", "--load", "5000,0,2000,0,7"], r"--load My must be 0 where by is fixed"),
    (["--fix", "dx=0,dy=0,dz=0,bx=0,by=0"], r"all five degrees of freedom.*--displacement"),
    (["--fix", "by"], r"--fix must be NAME=VALUE"),
])
def test_bad_fixes_get_one_line(args, message, capsys):
    from fastbearing.cli import main

    base = ["solve", "--bearing", str(DATA / "30206.toml")]
    if "--load" not in args:
        base += ["--load", "5000,0,2000,0,0"]
    assert main(base + args) != 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and __import__("re").search(message, err[0]), err


def test_bad_fixed_input_is_refused_naming_the_field(tmp_path):
    with pytest.raises(ValueError, match=r"fixed\.by must be finite"):
        fb.solve(DB, [1000.0, 0, 0, 0, 0], fixed={"by": math.nan})
    with pytest.raises(ValueError, match=r"f\[1\]\.Mx must be 0 where bx is fixed"):
        fb.solve_many(DB, [[1000.0, 0, 0, 0, 0], [1000.0, 0, 0, 5.0, 0]], fixed={"bx": 0.0})
    with pytest.raises(ValueError, match=r"fixed\.by must be one number or one per case \(2\)"):
        fb.solve_many(DB, [[1000.0, 0, 0, 0, 0]] * 2, fixed={"by": [0.0, 1.0, 2.0]})
    cfg = {"bearing": {"preset": "gunduz2013"}, "loadmap": {"Fx": 1000.0, "My": 5.0, "fixed": {"by": 0.0}}}
    with pytest.raises(ValueError, match=r"loadmap\.My must be absent where by is fixed"):
        fb.loadmap(cfg, tmp_path / "x.h5", progress=False)
    cfg["loadmap"] = {"given": "displacement", "dx": 0.01, "fixed": {"by": 0.0}}
    with pytest.raises(ValueError, match=r"loadmap\.fixed goes with given = \"load\""):
        fb.loadmap(cfg, tmp_path / "x.h5", progress=False)
    assert not (tmp_path / "x.h5").exists()


def test_a_shaft_held_square_at_its_reference_balances_with_the_holder(tmp_path):
    """[shaft] fixed: the gearbox shaft with its tilt held at the reference; the bearings' reactions carried
    to the reference plus the holder's add up to the external load, and the command line reports both."""
    from fastbearing.analysis.shaft import read_shaft, solve_shaft, transfer
    from fastbearing.cli import main

    text = (Path(__file__).parents[1] / "data" / "examples" / "gearbox-tapered-pair.toml").read_text()
    text = text.replace(
        "reference = 0.0 ", "fixed = { bx = 0.0, by = 0.0 }\nreference = 0.0 ")
    path = tmp_path / "held.toml"
    path.write_text(text)
    shaft = read_shaft(path)
    r = solve_shaft(shaft)
    assert r.solution.converged and r.q[3] == 0.0 and r.q[4] == 0.0
    total = r.holder_reaction.copy()
    for b in r.bearings:
        total += transfer(b.position - shaft.reference).T @ b.reaction
    assert np.allclose(total, shaft.external_load(), rtol=1e-9, atol=1e-6)
    assert abs(r.holder_reaction[4]) > 1000.0 and r.holder_reaction[:3].tolist() == [0.0, 0.0, 0.0]
    assert main(["shaft", str(path), "--json"]) == 0
    bad = text.replace("fixed = { bx = 0.0, by = 0.0 }", "fixed = { tilt = 0.0 }")
    path.write_text(bad)
    with pytest.raises(ValueError, match=r"shaft\.fixed\.tilt is not a degree of freedom"):
        read_shaft(path)
