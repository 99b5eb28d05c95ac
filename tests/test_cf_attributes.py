"""CF-friendly attributes in HDF5 files and zarr stores (issue 48, item 6), and pictures of every stored variable
with a unit (item 3): one ``units`` string per variable, each entry's units of q, f and Kb in ``units_per_entry``,
a ``long_name`` of at most 60 characters, so that xarray's automatic plot labels read ``long_name [units]``
whole; ``fastbearing plot`` takes L10, L10_hours, L10r_hours, the outer contact angles ... with their units.
Units: N, mm, rad."""

from pathlib import Path

import numpy as np
import pytest

import fastbearing as fb
from fastbearing.dofs import k_entry_units
from fastbearing.jobs.attributes import LONG_NAME_MAX, cf_attributes, short_long_name

xr = pytest.importorskip("xarray")
pytest.importorskip("h5netcdf")
pytest.importorskip("matplotlib")

from fastbearing import cli  # noqa: E402
from fastbearing.report import plot  # noqa: E402

BEARING = str(Path(__file__).resolve().parents[1] / "fastbearing" / "catalogue" / "7014C-DB.toml")
#: A small map with life at two speeds and at rest: L10, L10r, both in hours, the outer contact angles.
MAP = {"bearing": BEARING, "loadmap": {"Fx": 600.0, "Fz": [500.0, 1000.0, 2000.0], "speed": [0.0, 6000.0, 12000.0],
                                       "life": True}}
#: A small passage table keeping each element's load (the longest texts of the passage variables).
PASSAGE = {"bearing": {"preset": "gunduz2013", "arrangement": "DB"},
           "passage": {"points": [[0.05, 0, 0, 0, 0]], "positions": 4, "harmonics": 2, "element_loads": True}}


@pytest.fixture(scope="module")
def stores(tmp_path_factory):
    d = tmp_path_factory.mktemp("cf")
    out = {f"map{ext}": fb.loadmap(MAP, d / f"map{ext}", progress=False) for ext in (".h5", ".zarr")}
    out.update({f"passage{ext}": fb.passage(PASSAGE, d / f"passage{ext}", progress=False) for ext in (".h5", ".zarr")})
    return out


def open_plain(path):
    """The store as a user opens it with xarray alone: h5netcdf for HDF5, open_zarr for zarr."""
    if str(path).endswith(".zarr"):
        return xr.open_zarr(str(path), zarr_format=3)
    return xr.open_dataset(path, engine="h5netcdf")


@pytest.mark.parametrize("name", ["map.h5", "map.zarr", "passage.h5", "passage.zarr"])
def test_every_variable_has_one_units_string_and_a_short_long_name(stores, name):
    ds = open_plain(stores[name])
    try:
        for key, v in ds.variables.items():
            long_name = v.attrs.get("long_name")
            assert isinstance(long_name, str) and 0 < len(long_name) <= LONG_NAME_MAX, (key, long_name)
            if v.dtype.kind in "OUT":                       # dof, dof_col: text labels, no quantity, no units
                assert "units" not in v.attrs, key
                continue
            units = v.attrs.get("units")
            assert isinstance(units, str) and units and "," not in units, (key, units)
            per_entry = v.attrs.get("units_per_entry")
            if per_entry is None:
                continue
            per_entry = [str(u) for u in np.asarray(per_entry).ravel()]
            n = int(np.prod([ds.sizes[d] for d in v.dims if d in ("dof", "dof_col")]))
            assert len(per_entry) == n and per_entry[0] == units, key
            assert "units_per_entry" in v.attrs["comment"], key
        assert [str(u) for u in ds["K"].attrs["units_per_entry"]] == [k_entry_units(i, j) for i in range(5)
                                                                      for j in range(5)]
        assert list(ds["q"].attrs["units_per_entry"]) == ["mm", "mm", "mm", "rad", "rad"]
        assert list(ds["f"].attrs["units_per_entry"]) == ["N", "N", "N", "N*mm", "N*mm"]
        assert ds["K"].attrs["units"] == "N/mm" and ds["q"].attrs["units"] == "mm" and ds["f"].attrs["units"] == "N"
        if name.startswith("map"):
            assert ds["L10_hours"].attrs["units"] == "h" and ds["L10"].attrs["units"] == "million revolutions"
        else:                                               # passage summaries of Kb: Kb's units by entry too
            assert ds["K_mean"].attrs["units"] == "N/mm" and len(ds["K_amplitude"].attrs["units_per_entry"]) == 25
            assert ds["K_variation"].attrs["units"] == "%" and "units_per_entry" not in ds["K_variation"].attrs
            # a text longer than a long_name is kept whole in the comment
            assert ds["element_load"].attrs["long_name"] == "each element's load at every position"
            assert ds["element_load"].attrs["comment"].startswith("each element's load at every position (the")
    finally:
        ds.close()


def test_a_long_text_becomes_a_short_long_name_and_a_comment():
    assert short_long_name("solver iterations") == ("solver iterations", False)
    text = "Fourier amplitude A_h of Kb: K = sum_h A_h cos(h*2*pi*position/positions + phi_h)"
    assert short_long_name(text) == ("Fourier amplitude A_h of Kb", True)    # a formula's cos(...) is kept whole
    assert short_long_name("element (ball or roller) number in the bearing's element order") == (
        "element number in the bearing's element order", True)              # an aside in parentheses goes first
    head, cut = short_long_name("word " * 30)
    assert cut and len(head) <= LONG_NAME_MAX and head.endswith("...")
    attrs = cf_attributes("1", text, extra={"comment": "more"})
    assert attrs == {"units": "1", "long_name": "Fourier amplitude A_h of Kb", "comment": f"{text}. more"}


def _label_fits(fig, label) -> bool:
    """The label, drawn with Agg, lies inside the figure (not cut at its edges). The figure lays itself out
    (constrained): matplotlib's fixed default margins cut any two-line label beside 5-digit ticks."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    box, page = label.get_window_extent(canvas.get_renderer()), fig.bbox
    return box.x0 >= 0 and box.y0 >= 0 and box.x1 <= page.x1 and box.y1 <= page.y1


@pytest.mark.parametrize("name", ["map.h5", "map.zarr"])
def test_xarray_automatic_labels_read_long_name_and_units_whole(stores, name):
    """``.plot()`` with no arguments labels its axes ``long_name [units]`` (xarray wraps lines at 30
    characters): Kb's label names the units of the tilt entries, q's its tilts' rad; none is clipped."""
    from matplotlib.figure import Figure

    ds = open_plain(stores[name])
    try:
        for da, units in ((ds["K"].sel(dof="z", dof_col="z"), "N/mm"), (ds["q"].sel(dof="z"), "mm"),
                          (ds["L10r_hours"].isel(speed=[1, 2]), "h"), (ds["L10"], "million revolutions")):
            fig = Figure(layout="constrained")
            ax = fig.add_subplot()
            if "speed" in da.dims and da.sizes["speed"] > 1 and da.ndim == 2 and da.name != "L10":
                da.plot(ax=ax, hue="speed")
                label = ax.yaxis.label
            else:
                da.plot(ax=ax)                       # L10 over (speed, Fz): a colour mesh, the label on its bar
                label = fig.axes[-1].yaxis.label if len(fig.axes) > 1 else ax.yaxis.label
            text = label.get_text().replace("\n", " ")
            assert text == f"{da.attrs['long_name']} [{units}]", text
            assert len(text) <= LONG_NAME_MAX + len(" [million revolutions]")
            assert _label_fits(fig, label), text
        assert ds["K"].attrs["long_name"] == "stiffness Kb (tx, ty entries: N/rad, N*mm/rad)"
        fig = Figure(layout="constrained")
        ds["K"].sel(dof="z", dof_col="z").plot(ax=fig.add_subplot(), hue="speed")
        assert fig.axes[0].get_ylabel() == "stiffness Kb (tx, ty entries:\nN/rad, N*mm/rad) [N/mm]"  # two lines
    finally:
        ds.close()


PLOTTED = {"L10": "(million revolutions)", "L10_hours": "(h)", "L10r_hours": "(h)", "L10r": "(million revolutions)",
           "static_safety": "(-)", "min_outer_contact_angle": "(deg)", "max_outer_contact_angle": "(deg)",
           "iterations": "(-)", "residual": "(-)", "max_ball_load": "N)", "loaded_balls": "(-)"}


def test_every_stored_variable_with_a_unit_can_be_plotted(stores):
    """Issue 48 item 3: life in hours, ISO L10, the outer contact angles, the solver's counts: every stored
    variable over the operating points is drawn with the unit of its file on the axis."""
    ds = fb.open_map(stores["map.h5"])
    try:
        assert set(plot.plottable(ds)) == set(ds.data_vars) - {"K", "q", "f", "status"}
        assert set(PLOTTED) <= set(plot.plottable(ds))
        for var, unit in PLOTTED.items():
            fig = plot.plot_lines(ds, var, "Fz", at={"speed": 6000.0})
            label = fig.axes[0].get_ylabel().replace("\n", " ")
            assert label.endswith(unit), (var, label)
        # lives on a log scale; at 0 rpm the life in hours is unbounded: a blank, said in the title
        assert plot.plot_lines(ds, "L10_hours", "Fz", at={"speed": 6000.0}).axes[0].get_yscale() == "log"
        fig = plot.plot_map(ds, "L10_hours", "Fz", "speed", kind="heatmap")
        assert fig.axes[1].get_ylabel() == "rating life L10 (ISO 281) (h)"
        assert "3 unloaded or 0 rpm case(s): unbounded life (blank)" in fig.axes[0].get_title()
        hours = plot.plot_lines(ds, "L10r_hours", "Fz", at={"speed": 12000.0}).axes[0].lines[0].get_ydata()
        np.testing.assert_allclose(hours, ds["L10r_hours"].sel(speed=12000.0).values, rtol=1e-12)
        with pytest.raises(ValueError, match=r"unknown variable 'L10_days'.*this file's variables: .*L10_hours"):
            plot.plot_lines(ds, "L10_days", "Fz")
    finally:
        ds.close()


def test_the_command_line_plots_life_in_hours(stores, tmp_path, capsys):
    out = tmp_path / "hours.png"
    code = cli.main(["plot", "map", str(stores["map.zarr"]), "--var", "L10r_hours", "--x", "Fz", "--y", "speed",
                     "-o", str(out)])
    assert code == 0, capsys.readouterr().err
    assert out.stat().st_size > 1000


def test_a_map_without_life_names_what_the_life_variable_needs(tmp_path):
    ds = fb.open_map(fb.loadmap({"bearing": BEARING, "loadmap": {"Fx": 600.0, "Fz": [500.0, 1000.0]}},
                                tmp_path / "plain.h5", progress=False))
    try:
        with pytest.raises(ValueError, match=r"L10_hours is not in this file: compute the map with life = true, "
                                             r"a speed and"):
            plot.plot_lines(ds, "L10_hours", "Fz")
    finally:
        ds.close()
