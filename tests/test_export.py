"""Exported stiffness matrices read back equal, in every format."""

import csv
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
    header = path.read_text().splitlines()[0].split(",")
    assert header[0] == "case" and header[1] == "kxx_N_per_mm" and header[-1] == "matrix"
    np.testing.assert_array_equal(ex.read_csv(path), Ks)


def test_json_and_npz_round_trip(tmp_path):
    body = json.loads(ex.write_json(tmp_path / "k.json", K, extra={"status": "converged"}).read_text())
    assert body["dof"] == ["x", "y", "z", "tx", "ty"] and body["status"] == "converged"
    np.testing.assert_array_equal(np.array(body["K"]), K)
    data = np.load(ex.write_npz(tmp_path / "k.npz", K, q=np.arange(5.0)))
    np.testing.assert_array_equal(data["K"], K)
    assert list(data["dof"]) == ["x", "y", "z", "tx", "ty"] and "N/mm" in str(data["units"])


def _dmig_header(lines):
    """The DMIG header card (after the "$" comment lines)."""
    return next(line for line in lines if line.startswith("DMIG "))


def test_dmig_round_trip_one_grid(tmp_path):
    path = ex.write_dmig(tmp_path / "k.dmig", K, grid=101, name="KBRG")
    lines = path.read_text().splitlines()
    assert _dmig_header(lines).startswith("DMIG    KBRG           0       6       2       0")
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
    spindle = fb.load_bearing(Path(__file__).resolve().parents[1] / "fastbearing" / "catalogue" / "7014C-DB.toml")
    K_speed = fb.solve(spindle, (500.0, 0.0, 1000.0, 0.0, 0.0), speed=18000.0).K
    assert not np.allclose(K_speed, K_speed.T, rtol=0, atol=1e-9 * np.abs(K_speed).max())
    path = ex.write_dmig(tmp_path / "k.dmig", K_speed, grid=7)
    assert _dmig_header(path.read_text().splitlines()).startswith("DMIG    KBRG           0       1       2       0")
    text = path.read_text()
    assert "K is NOT symmetric" in " ".join(text.split()) and "accepts an unsymmetric" in " ".join(text.split())
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
    with pytest.warns(UserWarning, match="the tilt stiffness .* and the translation-tilt couplings"):
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
    header = lines[0].split(",")
    assert header[:7] == ["case", "Fx_N", "Fy_N", "Fz_N", "Mx_N_mm", "My_N_mm", "status"]
    assert header[7] == "kxx_N_per_mm" and "ktxty_N_mm_per_rad" in header and "kxtx_N_per_rad" in header
    assert header[-2:] == ["status_name", "matrix"]
    rows = np.loadtxt(tmp_path / "m.csv", delimiter=",", skiprows=1, ndmin=2, usecols=range(len(header) - 2))
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
    for at, words in (("Fx=1000", "(missing: My)"), ("Fx=1000,My=0,Fz=3", "(not an axis: Fz)"),
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


EXAMPLES = Path(__file__).resolve().parents[1] / "data" / "examples"


@pytest.fixture(scope="module")
def shaft_json(tmp_path_factory):
    from conftest import cli_run as cli

    r = cli("shaft", EXAMPLES / "fig2-two-single-rows.toml", "--json")
    assert r.returncode == 0, r.stderr
    path = tmp_path_factory.mktemp("shaft") / "s.json"
    path.write_text(r.stdout)
    return path


def test_shaft_export_needs_a_bearing_or_the_system(tmp_path, shaft_json):
    """A shaft's output holds K_system and each bearing's Kb: export neither silently."""
    from conftest import cli_run as cli

    bad = cli("export", shaft_json, "--format", "ross", "-o", tmp_path / "r.json")
    assert bad.returncode == 2 and not (tmp_path / "r.json").exists()
    assert len(bad.stderr.strip().splitlines()) == 1
    for words in ("--bearing NAME|N", "--system", "bearing 0 'row 1' at z = 64 mm", "bearing 1 'row 2' at z = 84 mm"):
        assert words in bad.stderr, bad.stderr
    for args, words in ((("--bearing", "5"), "index 0 to 1"), (("--bearing", "row 9"), "is no bearing"),
                        (("--bearing", "0", "--system"), "not both")):
        r = cli("export", shaft_json, "--format", "json", "-o", tmp_path / "x.json", *args)
        assert r.returncode == 2 and words in r.stderr, r.stderr
    solve = tmp_path / "solve.json"
    solve.write_text(json.dumps({"K": K.tolist(), "status": "converged"}))
    r = cli("export", solve, "--format", "json", "-o", tmp_path / "x.json", "--system")
    assert r.returncode == 2 and "shaft --json" in r.stderr


def test_shaft_export_of_one_bearing_is_its_own_kb(tmp_path, shaft_json):
    from conftest import cli_run as cli

    body = json.loads(shaft_json.read_text())
    for i in (0, 1):
        r = cli("export", shaft_json, "--format", "json", "-o", tmp_path / f"b{i}.json", "--bearing", i)
        assert r.returncode == 0, r.stderr
        out = json.loads((tmp_path / f"b{i}.json").read_text())
        np.testing.assert_array_equal(np.array(out["K"]), np.array(body["bearings"][i]["K"]))
        assert f"Kb of shaft bearing {i}" in out["matrix"] and out["q"] == body["bearings"][i]["q"]
    # row 1 (not mirrored) is the example bearing's single row: its Kb at its own q
    q0 = np.array(body["bearings"][0]["q"])
    K0 = fb.stiffness(fb.Bearing.preset("gunduz2013", "single"), q0)[1]
    got = np.array(json.loads((tmp_path / "b0.json").read_text())["K"])
    np.testing.assert_allclose(got, K0, rtol=1e-9, atol=1e-9 * np.abs(K0).max())
    # the DMIG and ROSS files say which matrix they hold, and where the grid goes
    assert cli("export", shaft_json, "--format", "dmig", "-o", tmp_path / "b1.dmig", "--bearing", "1",
               "--grid", "4").returncode == 0
    text = " ".join((tmp_path / "b1.dmig").read_text().replace("$ ", "").split())
    assert "bearing stiffness Kb of shaft bearing 1 'row 2' at z = 84 mm" in text
    assert "grid 4 must sit at the centre of shaft bearing 1 (z = 84 mm on the shaft)" in text
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert cli("export", shaft_json, "--format", "ross", "-o", tmp_path / "b1.ross", "--bearing",
                   "1").returncode == 0
    ross = json.loads((tmp_path / "b1.ross").read_text())
    assert ross["kxx"] == pytest.approx(body["bearings"][1]["K"][0][0] * 1e3) and "shaft bearing 1" in ross["matrix"]
    # by name, where the JSON carries the bearings' names
    named = tmp_path / "named.json"
    for b, name in zip(body["bearings"], ("row 1", "row 2")):
        b["name"] = name
    named.write_text(json.dumps(body))
    assert cli("export", named, "--format", "npz", "-o", tmp_path / "n.npz", "--bearing", "row 2").returncode == 0
    data = np.load(tmp_path / "n.npz")
    np.testing.assert_array_equal(data["K"], np.array(body["bearings"][1]["K"]))
    assert "'row 2'" in str(data["matrix"])


def test_shaft_export_of_the_system_is_k_system(tmp_path, shaft_json):
    from conftest import cli_run as cli

    body = json.loads(shaft_json.read_text())
    assert cli("export", shaft_json, "--format", "npz", "-o", tmp_path / "s.npz", "--system").returncode == 0
    data = np.load(tmp_path / "s.npz")
    np.testing.assert_array_equal(data["K"], np.array(body["K_system"]))
    assert "K_system at the reference z = 74 mm" in str(data["matrix"])
    assert cli("export", shaft_json, "--format", "dmig", "-o", tmp_path / "s.dmig", "--system").returncode == 0
    text = " ".join((tmp_path / "s.dmig").read_text().replace("$ ", "").split())
    assert "shaft system stiffness K_system" in text and "the shaft's reference point (z = 74 mm)" in text


def test_ross_warning_names_every_dropped_entry_and_its_size():
    with pytest.warns(UserWarning) as caught:
        ex.ross_arguments(K)
    text = str(caught[0].message)
    for words in ("kxz, kzx, kyz, kzy", "ktxtx, ktxty, ktytx, ktyty", "kxtx, kxty, kytx, kyty, kztx, kzty",
                  "N/mm", "N*mm/rad", "N/rad"):
        assert words in text, text
    dropped = max(abs(K[0, 2]), abs(K[2, 0]), abs(K[1, 2]), abs(K[2, 1]))
    kept = max(abs(K[0, 0]), abs(K[1, 1]), abs(K[2, 2]))
    assert f"{100 * dropped / kept:.3g}% of the largest kept diagonal" in text
    with warnings.catch_warnings():  # nothing dropped, nothing said
        warnings.simplefilter("error")
        ex.ross_arguments(np.diag([1.0, 2.0, 3.0, 0.0, 0.0]))


def test_dmig_comments_say_where_the_grid_goes(tmp_path):
    lines = ex.write_dmig(tmp_path / "k.dmig", K, grid=11, ground_grid=12).read_text().splitlines()
    assert all(len(line) <= 80 for line in lines)
    text = " ".join(" ".join(line[2:] for line in lines if line.startswith("$ ")).split())
    for words in ("bearing stiffness Kb", "grid 11 must sit at the bearing centre", "z along the shaft axis",
                  "a model whose shaft runs along x", "coordinate system on that grid",
                  "holds only for coincident grids", "a solution sequence that accepts an unsymmetric stiffness",
                  "N/mm among x, y, z"):
        assert words in text, text


@pytest.fixture(scope="module")
def warned_map(tmp_path_factory):
    """Two cases, the second one far beyond the model's validity (and with a reversed contact)."""
    return fb.loadmap({"bearing": {"preset": "gunduz2013", "arrangement": "DB"},
                       "loadmap": {"Fx": 500.0, "Fz": [2000.0, 2.0e6]}},
                      tmp_path_factory.mktemp("warned") / "w.h5", progress=False)


def test_map_exports_carry_each_case_status(tmp_path, warned_map):
    from conftest import cli_run as cli

    from fastbearing import status as st

    codes = fb.open_dataset(warned_map)["status"].values.reshape(-1)
    assert codes[0] == 0 and codes[1] & st.BEYOND_VALIDITY
    names = [st.describe(int(c)) for c in codes]
    for fmt in ("csv", "json", "npz"):
        assert cli("export", warned_map, "--format", fmt, "-o", tmp_path / f"w.{fmt}").returncode == 0
    with open(tmp_path / "w.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [int(r["status"]) for r in rows] == codes.tolist()
    assert [r["status_name"] for r in rows] == names and "beyond_validity" in names[1]
    body = json.loads((tmp_path / "w.json").read_text())
    assert body["status_code"] == codes.tolist() and body["status"] == names
    data = np.load(tmp_path / "w.npz")
    assert data["status"].tolist() == codes.tolist() and data["status_name"].tolist() == names
    one = cli("export", warned_map, "--format", "json", "-o", tmp_path / "one.json", "--case", "1")
    assert one.returncode == 0
    body = json.loads((tmp_path / "one.json").read_text())
    assert body["status_code"] == int(codes[1]) and body["status"] == names[1]


def test_csv_default_reads_get_the_column_names(tmp_path, warned_map):
    """pandas' and numpy.genfromtxt's default reads take the one header row as it is."""
    from conftest import cli_run as cli

    assert cli("export", warned_map, "--format", "csv", "-o", tmp_path / "w.csv").returncode == 0
    expect = (["case", "Fx_N", "Fy_N", "Fz_N", "Mx_N_mm", "My_N_mm", "status"] + list(ex.K_COLUMNS)
              + ["status_name", "matrix"])
    table = np.genfromtxt(tmp_path / "w.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
    assert list(table.dtype.names) == expect
    np.testing.assert_array_equal(table["Fz_N"], [2000.0, 2.0e6])
    K_back = np.stack([table[name] for name in ex.K_COLUMNS], axis=-1).reshape(-1, 5, 5)
    np.testing.assert_array_equal(K_back, fb.open_dataset(warned_map)["K"].values.reshape(-1, 5, 5))
    pd = pytest.importorskip("pandas")
    frame = pd.read_csv(tmp_path / "w.csv")
    assert list(frame.columns) == expect and len(frame) == 2
    assert frame["kxx_N_per_mm"].dtype.kind == "f" and frame["matrix"].tolist() == ["bearing stiffness Kb"] * 2


def test_export_at_outside_the_grid_is_refused(tmp_path, grid_map):
    from conftest import cli_run as cli

    for at, words in (("Fx=2000,My=0", "--at Fx=2000 is outside the grid's Fx axis [500, 1500] N"),
                      ("Fx=1000,My=-2e4", "My axis [-10000, 10000] N*mm"),
                      ("Fx=499.9,My=0", "Fx axis [500, 1500]")):
        bad = cli("export", grid_map, "--format", "json", "-o", tmp_path / "b.json", "--at", at)
        assert bad.returncode == 2 and words in bad.stderr, bad.stderr
        assert len(bad.stderr.strip().splitlines()) == 1 and not (tmp_path / "b.json").exists()
    edge = cli("export", grid_map, "--format", "json", "-o", tmp_path / "e.json", "--at", "Fx=1500.0000001,My=1e4")
    assert edge.returncode == 0 and "case 11" in edge.stderr, edge.stderr
