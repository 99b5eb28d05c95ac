"""The shipped bearings (fastbearing/catalogue/*.toml): package data found by name from any folder, a path
still winning; their listing (what `fastbearing bearings` prints) agrees with the files and the docs; a
four-point `element` typed in [bearing.geometry] is told where it belongs."""

import json
import re
import tomllib
from pathlib import Path

import pytest

import fastbearing as fb
from fastbearing.model.bearing_file import bearing_from_table, read_job_config
from fastbearing.model.catalogue import catalogue_file, catalogue_folder, catalogue_names, find_bearing_file
from fastbearing.report.catalogue import shipped_bearings, shipped_bearings_text

ROOT = Path(__file__).resolve().parents[1]
#: The catalogue of the fastbearing under test: the installed package's (the README's test command) or a
#: source tree's.
FOLDER = Path(fb.__file__).parent / "catalogue"
FILES = sorted(FOLDER.glob("*.toml"))


def test_the_catalogue_is_the_package_folder_and_every_file_is_named():
    assert catalogue_folder().resolve() == FOLDER.resolve()
    assert len(FILES) == 14
    assert sorted(catalogue_names()) == sorted(p.stem for p in FILES)
    assert not (ROOT / "data" / "bearings").exists()  # one copy of each file: no second folder to drift
    assert not any(p.is_symlink() for p in FILES)


def test_pyproject_ships_the_catalogue_as_package_data():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert "catalogue/*.toml" in project["tool"]["setuptools"]["package-data"]["fastbearing"]


def test_a_name_finds_the_shipped_file_from_any_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    for path in FILES:
        assert fb.load_bearing(path.stem) == fb.load_bearing(path)
    # any case, and with the .toml suffix
    assert fb.load_bearing("7014c-db") == fb.load_bearing(FOLDER / "7014C-DB.toml")
    assert fb.load_bearing("QJ210.toml") == fb.load_bearing(FOLDER / "QJ210.toml")
    assert catalogue_file("nu205") == FOLDER / "NU205.toml"


def test_a_path_that_exists_wins_over_a_shipped_name(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "6205").write_text('[bearing]\npreset = "gunduz2013"\narrangement = "single"\n')
    mine = fb.load_bearing("6205")
    assert mine.arrangement == "single" and mine.name == "gunduz2013" and mine.geometry is None
    # a path with a folder part is only ever a path
    with pytest.raises(ValueError, match=r"no bearing file at elsewhere/6205"):
        fb.load_bearing("elsewhere/6205")


def test_an_unknown_name_lists_the_shipped_ones(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ValueError) as err:
        fb.load_bearing("6206")
    text = str(err.value)
    assert "bearing = '6206'" in text and "file not found" in text and "fastbearing bearings" in text
    assert all(name in text for name in catalogue_names())
    with pytest.raises(ValueError, match=r"no shipped bearing named '6206'; shipped bearings: 30206, "):
        catalogue_file("6206")


def test_configs_and_shafts_name_a_shipped_bearing(tmp_path):
    folder = tmp_path / "configs"
    folder.mkdir()
    config = folder / "map.toml"
    config.write_text('bearing = "6205"\n\n[loadmap]\nFx = 1000.0\n')
    bearing, job, text, source = read_job_config(config, "loadmap")
    assert bearing == fb.load_bearing(FOLDER / "6205.toml") and source == config
    assert "# bearing file " in text and "CWRU" in text  # the shipped file's text joins the provenance
    # a file of that name beside the config wins
    (folder / "6205").write_text('[bearing]\npreset = "gunduz2013"\n')
    assert read_job_config(config, "loadmap")[0].geometry is None
    config.write_text('bearing = "nowhere"\n\n[loadmap]\nFx = 1000.0\n')
    with pytest.raises(ValueError, match=r"bearing = 'nowhere': no bearing file at .*relative to the config.*"
                                         r"shipped bearings: 30206"):
        read_job_config(config, "loadmap")

    from fastbearing.analysis.shaft import read_shaft

    shaft = folder / "shaft.toml"
    shaft.write_text('[shaft]\n[[shaft.bearings]]\nposition = -40.0\nbearing = "NU205"\n'
                     '[[shaft.bearings]]\nposition = 40.0\nbearing = "6305"\n')
    s = read_shaft(shaft)
    assert [b.bearing for b in s.bearings] == [fb.load_bearing("NU205"), fb.load_bearing("6305")]
    shaft.write_text('[shaft]\n[[shaft.bearings]]\nposition = 0.0\nbearing = "6206"\n')
    with pytest.raises(ValueError, match=r"shaft\.bearings\[0\]\.bearing = '6206': .*shipped bearings"):
        read_shaft(shaft)


def test_the_examples_name_the_shipped_bearings():
    """Every example config that names a bearing file names a shipped one, and reads from any folder."""
    named = 0
    for path in sorted((ROOT / "data" / "examples").glob("*.toml")):
        text = path.read_text()
        for name in re.findall(r'^bearing = "([^"]+)"', text, re.M):
            assert name in catalogue_names(), (path.name, name)
            named += 1
    assert named >= 7


def test_the_command_line_takes_a_name(tmp_path):
    from conftest import cli_run

    out = cli_run("solve", "--bearing", "6205", "--load", "1000,0,0,0,0", "--json", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout)["status"] == "converged"
    bad = cli_run("solve", "--bearing", "6206", "--load", "1000,0,0,0,0", cwd=tmp_path)
    assert bad.returncode == 2 and "shipped bearings: 30206" in bad.stderr
    rep = cli_run("bearing", "QJ210", cwd=tmp_path)
    assert rep.returncode == 0 and "QJ210" in rep.stdout


def test_presets_are_the_catalogue_files_given_by_model_parameters():
    assert fb.preset_names() == ["gunduz2013"]
    assert fb.Bearing.preset("gunduz2013") == fb.load_bearing("gunduz2013")
    for name in catalogue_names():
        has_geometry = "geometry" in tomllib.loads(catalogue_file(name).read_text())["bearing"]
        assert (name in fb.preset_names()) != has_geometry, name


# -- the listing ------------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def listing():
    return shipped_bearings()


def test_the_listing_holds_every_file_with_its_numbers(listing):
    assert [e["name"] for e in listing] == catalogue_names()
    for e in listing:
        table = tomllib.loads(catalogue_file(e["name"]).read_text())["bearing"]
        geo = table.get("geometry", {})
        assert e["bearing_name"] == table["name"]
        assert Path(e["file"]) == catalogue_file(e["name"])
        for key in ("bore", "outer_diameter", "width"):
            assert e[key] == geo.get(key), (e["name"], key)
        for key, field in (("C", "dynamic_load_rating"), ("C0", "static_load_rating")):
            if field in geo:
                assert e[key] == geo[field], (e["name"], key)
                assert "catalogue" in e["sources"][key], (e["name"], key)
        assert e["units"] == {"contact_angle_deg": "deg", "bore": "mm", "outer_diameter": "mm", "width": "mm",
                              "C": "N", "C0": "N"}
        assert all(e["sources"][k] for k in ("dimensions", "C", "C0"))
    json.dumps(listing)  # JSON-ready


def test_the_listing_rates_as_life_does_and_says_where_each_number_comes_from(listing):
    from fastbearing.analysis.life import ratings

    by = {e["name"]: e for e in listing}
    for name in ("30206-TDO", "7014C-DB", "QJ210"):  # no catalogue rating in the file: ISO from the geometry
        r = ratings(fb.load_bearing(name))
        assert by[name]["C"] == pytest.approx(r.C, rel=1e-12) and by[name]["C0"] == pytest.approx(r.C0, rel=1e-12)
        assert by[name]["sources"]["C"].startswith("ISO 281") and by[name]["sources"]["C0"].startswith("ISO 76")
    assert by["6205"]["sources"] == {"dimensions": "published: SKF 6205; ISO 15 series 02", "C": "SKF catalogue",
                                     "C0": "SKF catalogue"}
    assert by["6205"]["C"] == 14800.0 and by["6205"]["C0"] == 7800.0
    assert by["gunduz2013"]["C"] is None and by["gunduz2013"]["bore"] is None
    assert "each bearing of the pair" in by["7014C-DB"]["sources"]["dimensions"]
    types = {n: by[n]["type"] for n in ("6205", "3206", "QJ210", "30206", "30206-TDO", "NU205")}
    assert types == {"6205": "deep-groove ball, single row", "3206": "angular contact ball, 2 rows DB (back to back)",
                     "QJ210": "four-point contact ball, single row", "30206": "tapered roller, single row",
                     "30206-TDO": "tapered roller, 2 rows TDO (back to back)", "NU205": "cylindrical roller, single row"}


def test_the_text_table_shows_every_bearing(listing):
    text = shipped_bearings_text(listing)
    lines = text.splitlines()
    for e in listing:
        row = next(line for line in lines if line.split()[:1] == [e["name"]])
        assert e["type"] in row
        if e["C"] is not None:
            assert f"{e['C']:.0f}" in row and f"{e['C0']:.0f}" in row
            assert f"{e['bore']:g} x {e['outer_diameter']:g} x {e['width']:g}" in row
        assert any(line.strip().startswith(f"{e['name']}: d x D x B: ") for line in lines)


def test_the_docs_table_is_the_listing(listing):
    """docs/geometry.md's table of the shipped bearings says what the listing says, one row per file."""
    text = (ROOT / "docs" / "geometry.md").read_text()
    rows = {}
    for line in text.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if line.startswith("| ") and len(cells) == 7 and cells[0] in catalogue_names():
            rows[cells[0]] = cells
    assert sorted(rows) == sorted(catalogue_names())
    for e in listing:
        name, kind, angle, dims, C, C0, _ = rows[e["name"]]
        assert kind == e["type"] and float(angle) == e["contact_angle_deg"]
        if e["C"] is None:
            assert (dims, C, C0) == ("-", "-", "-")
        else:
            assert dims == f"{e['bore']:g} x {e['outer_diameter']:g} x {e['width']:g}"
            assert (C, C0) == (f"{e['C']:.0f}", f"{e['C0']:.0f}")


# -- a four-point element in the geometry table -----------------------------------------------------------

def _qj210_with_element_in_geometry(element):
    table = tomllib.loads((FOLDER / "QJ210.toml").read_text())["bearing"]
    del table["element"]
    table["geometry"]["element"] = element
    return table


def test_a_four_point_element_in_the_geometry_table_is_pointed_to_bearing():
    with pytest.raises(ValueError, match=r"^bearing\.geometry\.element belongs in the \[bearing\] table "
                                         r"\(beside arrangement\), not in \[bearing\.geometry\]") as err:
        bearing_from_table(_qj210_with_element_in_geometry("four_point_ball"))
    assert "n_rollers" not in str(err.value)  # no list of roller keys
    with pytest.raises(ValueError, match=r"bearing\.geometry\.element is not needed: a ball geometry makes ball"):
        bearing_from_table(_qj210_with_element_in_geometry("ball"))
    with pytest.raises(ValueError, match=r"bearing\.geometry\.element must be one of \['cylindrical_roller', "
                                         r"'tapered_roller'\].*element = \"four_point_ball\" in the \[bearing\] "
                                         r"table, got 'bogus'"):
        bearing_from_table(_qj210_with_element_in_geometry("bogus"))
    # where it belongs, the file as shipped
    assert fb.load_bearing("QJ210").rows[0].element == "four_point_ball"


def test_find_bearing_file_refuses_a_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "6205").mkdir()  # a folder is no bearing file: the shipped name is meant
    assert find_bearing_file("6205") == FOLDER / "6205.toml"
    (tmp_path / "mine").mkdir()
    with pytest.raises(ValueError, match="is a directory"):
        find_bearing_file("mine")


def test_a_non_editable_install_finds_the_shipped_bearings_from_any_folder(tmp_path):
    """Issue 48, done means: installed (not editable) into a folder outside the clone, the package lists its
    bearings and reads one by name from another folder, so the bearing files really are package data."""
    import json
    import os
    import subprocess
    import sys

    root = Path(__file__).resolve().parents[1]
    target = tmp_path / "site"
    build = subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-deps", "--target", str(target),
                            str(root)], capture_output=True, text=True, cwd=tmp_path)
    assert build.returncode == 0, build.stderr
    assert (target / "fastbearing" / "catalogue" / "6205.toml").is_file()
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    env = {**os.environ, "PYTHONPATH": str(target)}
    script = ("import fastbearing as fb, json; b = fb.load_bearing('6205'); "
              "print(json.dumps([fb.__file__, b.n_elements, [e['name'] for e in fb.shipped_bearings()]]))")
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, cwd=elsewhere, env=env)
    assert run.returncode == 0, run.stderr
    where, n_balls, names = json.loads(run.stdout.strip().splitlines()[-1])
    assert Path(where).resolve().is_relative_to(target.resolve())
    assert n_balls == 9 and "6205" in names and "QJ210" in names and len(names) == 14
