"""Issue 44, item 1: the boundary dimensions (bore d, outer_diameter D, width B, mm) in [bearing.geometry]:
optional, checked against the rolling elements, and given in every shipped catalogue file with its source."""

from pathlib import Path

import pytest

import fastbearing as fb
from fastbearing.model.geometry import geometry_from_table
from fastbearing.model.roller_geometry import roller_geometry_from_table

DATA = Path(__file__).parents[1] / "fastbearing" / "catalogue"
#: (d, D, B) in mm as the files' headers and the makers' catalogues give them (ISO 15 / ISO 355).
PUBLISHED = {"6205": (25, 52, 15), "6203": (17, 40, 12), "6305": (25, 62, 17), "7014C-DB": (70, 110, 20),
             "QJ210": (50, 90, 20), "3206": (30, 62, 23.8), "3208": (40, 80, 30.2), "3210": (50, 90, 30.2),
             "3306": (30, 72, 30.2), "3310": (50, 110, 44.4), "30206": (30, 62, 17.25),
             "30206-TDO": (30, 62, 17.25), "NU205": (25, 52, 15)}
BALL = dict(n_balls=9, ball_diameter=7.94, pitch_diameter=39.04, inner_groove_ratio=0.52, outer_groove_ratio=0.53)
ROLLER = dict(element="cylindrical_roller", n_rollers=13, roller_diameter=7.5, roller_effective_length=7.8,
              pitch_diameter=39.0)


def test_every_shipped_catalogue_file_has_its_boundary_dimensions_with_a_source():
    files = {p.stem for p in DATA.glob("*.toml")} - set(fb.preset_names())  # the presets have no geometry
    assert files == set(PUBLISHED)
    for name, dims in PUBLISHED.items():
        g = fb.load_bearing(DATA / f"{name}.toml").geometry
        assert (g.bore, g.outer_diameter, g.width) == tuple(float(x) for x in dims), name
        text = (DATA / f"{name}.toml").read_text()
        assert "bore = " in text and "(published" in text, name


@pytest.mark.parametrize("build, table", [(geometry_from_table, BALL), (roller_geometry_from_table, ROLLER)])
def test_boundary_dimensions_are_optional_and_checked_against_the_elements(build, table):
    """Absent: None, the geometry as before. d must leave the inner ring a section (d < dm - Dw), D the outer
    ring (D > dm + Dw); each > 0; a ValueError names the key under [bearing.geometry]."""
    plain = build(dict(table))
    assert (plain.bore, plain.outer_diameter, plain.width) == (None, None, None)
    ok = build({**table, "bore": 25.0, "outer_diameter": 52.0, "width": 15.0})
    assert (ok.bore, ok.outer_diameter, ok.width) == (25.0, 52.0, 15.0)
    inner = table["pitch_diameter"] - table.get("ball_diameter", table.get("roller_diameter"))
    with pytest.raises(ValueError, match=r"bearing\.geometry\.bore must be < the inner raceway diameter"):
        build({**table, "bore": inner})
    with pytest.raises(ValueError, match=r"bearing\.geometry\.outer_diameter must be > the outer raceway diameter"):
        build({**table, "outer_diameter": 45.0})
    with pytest.raises(ValueError, match=r"bearing\.geometry\.width must be > 0 mm"):
        build({**table, "width": 0.0})
