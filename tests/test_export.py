"""Exported stiffness matrices read back equal, in every format."""

import json
import warnings
from pathlib import Path

import numpy as np
import pytest

import fastbearing as fb
from fastbearing.report import export as ex

K = fb.solve(fb.Bearing.preset("gunduz2013", "DT"), [1000.0, 0.0, 3000.0, 0.0, -74000.0]).K


def test_csv_round_trip(tmp_path):
    Ks = np.stack([K, 2 * K])
    path = ex.write_csv(tmp_path / "k.csv", Ks)
    assert "units: N/mm" in path.read_text().splitlines()[0]
    np.testing.assert_array_equal(ex.read_csv(path), Ks)


def test_json_and_npz_round_trip(tmp_path):
    body = json.loads(ex.write_json(tmp_path / "k.json", K, extra={"status": "converged"}).read_text())
    assert body["dof"] == ["x", "y", "z", "tx", "ty"] and body["status"] == "converged"
    np.testing.assert_array_equal(np.array(body["K"]), K)
    data = np.load(ex.write_npz(tmp_path / "k.npz", K, q=np.arange(5.0)))
    np.testing.assert_array_equal(data["K"], K)
    assert list(data["dof"]) == ["x", "y", "z", "tx", "ty"] and "N/mm" in str(data["units"])


def test_dmig_round_trip_one_grid(tmp_path):
    path = ex.write_dmig(tmp_path / "k.dmig", K, grid=101, name="KBRG")
    lines = path.read_text().splitlines()
    assert lines[3].startswith("DMIG    KBRG           0       6       2       0")
    assert all(len(line) <= 80 for line in lines)
    entries = ex.read_dmig(path)
    back = np.zeros((5, 5))
    for (gi, ci, gj, cj), value in entries.items():
        assert gi == gj == 101 and ci <= cj
        back[ci - 1, cj - 1] = back[cj - 1, ci - 1] = value
    np.testing.assert_allclose(back, K, rtol=1e-9, atol=1e-9 * np.abs(K).max())


def test_dmig_keeps_every_entry_of_a_kb_at_speed(tmp_path):
    """Kb at shaft speed is not symmetric (the friction of the balls' gyroscopic moments): written as the
    whole square matrix (IFO = 1), nothing lost."""
    spindle = fb.load_bearing(Path(__file__).resolve().parents[1] / "data" / "bearings" / "7014C-DB.toml")
    K_speed = fb.solve(spindle, (500.0, 0.0, 1000.0, 0.0, 0.0), speed=18000.0).K
    assert not np.allclose(K_speed, K_speed.T, rtol=0, atol=1e-9 * np.abs(K_speed).max())
    path = ex.write_dmig(tmp_path / "k.dmig", K_speed, grid=7)
    assert path.read_text().splitlines()[3].startswith("DMIG    KBRG           0       1       2       0")
    back = np.zeros((5, 5))
    for (gi, ci, gj, cj), value in ex.read_dmig(path).items():
        back[ci - 1, cj - 1] = value
    np.testing.assert_allclose(back, K_speed, rtol=1e-9, atol=1e-9 * np.abs(K_speed).max())


def test_dmig_two_grids_is_a_spring_between_them(tmp_path):
    entries = ex.read_dmig(ex.write_dmig(tmp_path / "k.dmig", K, grid=1, ground_grid=2))
    assert entries[(1, 1, 1, 1)] == pytest.approx(K[0, 0], rel=1e-9)
    assert entries[(1, 1, 2, 1)] == pytest.approx(-K[0, 0], rel=1e-9)
    assert entries[(2, 3, 2, 5)] == pytest.approx(K[2, 4], rel=1e-9)


def test_ross_arguments_are_si_and_warn_about_dropped_terms(tmp_path):
    with pytest.warns(UserWarning, match="tilt stiffness and the translation-tilt coupling terms"):
        args = ex.ross_arguments(K, node=3)
    assert args["n"] == 3 and args["kxx"] == pytest.approx(K[0, 0] * 1e3) and args["kzz"] == pytest.approx(K[2, 2] * 1e3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        body = json.loads(ex.write_ross(tmp_path / "r.json", K).read_text())
    assert body["kyy"] == pytest.approx(K[1, 1] * 1e3)


def test_never_overwrites_and_rejects_bad_input(tmp_path):
    path = ex.write_csv(tmp_path / "k.csv", K)
    with pytest.raises(ValueError, match="exists; pass overwrite=True"):
        ex.write_csv(path, K)
    ex.write_csv(path, K, overwrite=True)
    with pytest.raises(ValueError, match="K must be 5x5"):
        ex.write_json(tmp_path / "x.json", np.ones((4, 4)))
    with pytest.raises(ValueError, match="grid must be a positive integer"):
        ex.write_dmig(tmp_path / "x.dmig", K, grid=0)
    with pytest.raises(ValueError, match="Nastran name"):
        ex.write_dmig(tmp_path / "x.dmig", K, grid=1, name="TOO_LONG_NAME")
    with pytest.raises(ValueError, match="one 5x5 matrix"):
        ex.write_dmig(tmp_path / "x.dmig", np.stack([K, K]), grid=1)


def test_export_cli_from_solve_json_and_from_a_map(tmp_path):
    from conftest import cli_run as cli

    p = cli("solve", "--preset", "gunduz2013", "--arrangement", "DT", "--load", "1000,0,3000,0,-74000", "--json")
    (tmp_path / "r.json").write_text(p.stdout)
    assert cli("export", str(tmp_path / "r.json"), "--format", "dmig", "-o", str(tmp_path / "k.dmig"),
               "--grid", "7").returncode == 0
    assert ex.read_dmig(tmp_path / "k.dmig")[(7, 3, 7, 3)] == pytest.approx(K[2, 2], rel=1e-9)
    r = cli("export", str(tmp_path / "r.json"), "--format", "ross", "-o", str(tmp_path / "r.ross"))
    assert r.returncode == 0 and "dropped" in r.stderr
    m = fb.loadmap({"bearing": {"preset": "gunduz2013", "arrangement": "DB"},
                    "loadmap": {"Fx": [500.0, 1000.0], "Fz": 2000.0}}, tmp_path / "m.h5", progress=False)
    assert cli("export", str(m), "--format", "npz", "-o", str(tmp_path / "m.npz")).returncode == 0
    np.testing.assert_array_equal(np.load(tmp_path / "m.npz")["K"], fb.open_dataset(m)["K"].values)
    one = cli("export", str(m), "--format", "dmig", "-o", str(tmp_path / "x.dmig"))
    assert one.returncode == 2 and "--case" in one.stderr
    assert cli("export", str(m), "--format", "dmig", "-o", str(tmp_path / "x.dmig"), "--case", "1").returncode == 0
    again = cli("export", str(m), "--format", "npz", "-o", str(tmp_path / "m.npz"))
    assert again.returncode == 2 and "exists" in again.stderr


@pytest.fixture(scope="module")
def grid_map(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("exp")
    return fb.loadmap({"bearing": {"preset": "gunduz2013", "arrangement": "DB"},
                       "loadmap": {"Fx": [500.0, 1000.0, 1500.0], "Fz": 2000.0,
                                   "My": {"start": -1.0e4, "stop": 1.0e4, "num": 4}}}, tmp / "m.h5", progress=False)


def test_exports_of_a_map_keep_each_case_inputs(tmp_path, grid_map):
    """CSV, JSON and npz carry Fx ... My (with units) beside every case, in the order of K."""
    from conftest import cli_run as cli

    ds = fb.open_dataset(grid_map)
    Fx, My = np.meshgrid(ds["Fx"].values, ds["My"].values, indexing="ij")
    for fmt in ("csv", "json", "npz"):
        assert cli("export", grid_map, "--format", fmt, "-o", tmp_path / f"m.{fmt}").returncode == 0
    lines = (tmp_path / "m.csv").read_text().splitlines()
    header = lines[1].split(",")
    assert header[:6] == ["case", "Fx [N]", "Fy [N]", "Fz [N]", "Mx [N*mm]", "My [N*mm]"]
    assert header[6] == "k_xx [N/mm]" and "k_txty [N*mm/rad]" in header and "k_xtx [N/rad]" in header
    rows = np.loadtxt(tmp_path / "m.csv", delimiter=",", skiprows=2, ndmin=2)
    np.testing.assert_array_equal(rows[:, 1], Fx.ravel())
    np.testing.assert_array_equal(rows[:, 3], 2000.0)
    np.testing.assert_array_equal(rows[:, 5], My.ravel())
    np.testing.assert_array_equal(ex.read_csv(tmp_path / "m.csv"), ds["K"].values.reshape(-1, 5, 5))
    body = json.loads((tmp_path / "m.json").read_text())
    assert body["cases"]["My"]["units"] == "N*mm" and body["cases"]["Fx"]["values"] == Fx.ravel().tolist()
    data = np.load(tmp_path / "m.npz")
    np.testing.assert_array_equal(data["My"], My.ravel())
    assert "Fz: N" in list(data["coordinate_units"])


def test_export_at_picks_the_nearest_grid_point_and_says_so(tmp_path, grid_map):
    from conftest import cli_run as cli

    ds = fb.open_dataset(grid_map)
    r = cli("export", grid_map, "--format", "json", "-o", tmp_path / "one.json", "--at", "Fx=990,My=3000")
    assert r.returncode == 0, r.stderr
    assert "Fx=1000 (nearest to 990)" in r.stderr and "case 6" in r.stderr
    body = json.loads((tmp_path / "one.json").read_text())
    expect = ds["K"].sel(Fx=1000.0, My=3000.0, method="nearest").values
    np.testing.assert_array_equal(np.array(body["K"]), expect)
    assert body["cases"]["Fx"]["values"] == 1000.0
    assert cli("export", grid_map, "--format", "dmig", "-o", tmp_path / "a.dmig", "--at",
               "Fx=1500,My=-1e4").returncode == 0
    for at, words in (("Fx=1000", "missing ['My']"), ("Fx=1000,My=0,Fz=3", "unknown ['Fz']"),
                      ("Fx=abc,My=0", "--at Fx must be a number"), ("Fx", "NAME=VALUE")):
        bad = cli("export", grid_map, "--format", "dmig", "-o", tmp_path / "b.dmig", "--at", at)
        assert bad.returncode == 2 and words in bad.stderr, bad.stderr
    both = cli("export", grid_map, "--format", "dmig", "-o", tmp_path / "b.dmig", "--at", "Fx=1,My=0", "--case", "1")
    assert both.returncode == 2 and "not both" in both.stderr


def test_passage_export_carries_point_inputs_and_cage_angle(tmp_path):
    from conftest import cli_run as cli

    out = fb.passage({"bearing": {"preset": "gunduz2013", "arrangement": "DB"},
                      "passage": {"given": "displacement", "points": [[0.05, 0, 0, 0, 0], [0.0, 0, 0.02, 0, 0]],
                                  "positions": 8}}, tmp_path / "p.h5", progress=False)
    assert cli("export", out, "--format", "npz", "-o", tmp_path / "p.npz").returncode == 0
    data = np.load(tmp_path / "p.npz")
    assert data["K"].shape == (16, 5, 5)
    np.testing.assert_array_equal(data["dx"], [0.05] * 8 + [0.0] * 8)
    np.testing.assert_array_equal(data["position"], list(range(8)) * 2)
    assert data["cage_angle"].shape == (16,)
    r = cli("export", out, "--format", "json", "-o", tmp_path / "one.json", "--at", "point=1,position=2")
    assert r.returncode == 0 and "case 10" in r.stderr
