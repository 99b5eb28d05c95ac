"""Pictures: every plot command renders a non-empty image of the asked size from a small file; the
plotted numbers are the file's; bad input is a ValueError (API) or one line and exit 2 (CLI)."""

import math
import re

import numpy as np
import pytest

pytest.importorskip("matplotlib")

import matplotlib.image as mpimg  # noqa: E402

import fastbearing as fb  # noqa: E402
from fastbearing import cli  # noqa: E402
from fastbearing.report import plot  # noqa: E402


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """A small load map (Fx x Fz x My) and a small passage table (2 points, 8 positions, with a speed)."""
    d = tmp_path_factory.mktemp("plots")
    lm = fb.loadmap({"bearing": {"preset": "gunduz2013", "arrangement": "DB"},
                     "loadmap": {"given": "load", "Fx": {"start": -2000.0, "stop": 2000.0, "num": 5},
                                 "Fz": [500.0, 1000.0, 3000.0], "My": [-74000.0, 0.0, 74000.0]}}, d / "map.h5")
    ps = fb.passage({"bearing": {"preset": "gunduz2013", "arrangement": "DB"},
                     "passage": {"points": [[0.05, 0, 0, 0, 0], [0, 0, 0, 0, 0.03]], "positions": 8,
                                 "harmonics": 4, "shaft_speed": 3000.0, "ball_diameter": 12.0,
                                 "pitch_diameter": 70.0}}, d / "passage.h5")
    return {"map": lm, "passage": ps, "dir": d}


def image(path, size):
    """The PNG at path has size (width, height) pixels and is not blank."""
    pixels = mpimg.imread(path)
    assert pixels.shape[:2] == (size[1], size[0])
    assert pixels[..., :3].std() > 0.05
    return pixels


def run_cli(capsys, *args):
    code = cli.main(list(args))
    err = capsys.readouterr().err
    return code, err


@pytest.mark.parametrize("args, size", [
    (["map", "{map}", "--var", "kzz", "--x", "Fx", "--y", "My"], plot.DEFAULT_SIZE),
    (["map", "{map}", "--var", "max_ball_load", "--x", "Fx", "--y", "Fz", "--kind", "heatmap", "--at", "My=-74000",
      "--size", "640x400"], (640, 400)),
    (["map", "{map}", "--var", "kxty", "--x", "Fz", "--y", "My", "--base-units", "--row", "1"], plot.DEFAULT_SIZE),
    (["line", "{map}", "--var", "kxx,ktyty,max_ball_load", "--x", "Fx", "--series", "Fz", "--size", "700x900"],
     (700, 900)),
    (["passage", "{passage}"], plot.DEFAULT_SIZE),
    (["passage", "{passage}", "--x", "time", "--normalise", "first", "--at", "point=1"], plot.DEFAULT_SIZE),
    (["spectrum", "{passage}", "--dpi", "80", "--size", "480x360"], (480, 360)),
    (["spectrum", "{passage}", "--normalise", "none", "--linear"], plot.DEFAULT_SIZE),
    (["loadzone", "--preset", "gunduz2013", "--arrangement", "DB", "--load", "1000,0,3000,0,-74000",
      "--size", "800x520"], (800, 520)),
])
def test_every_plot_command_renders(files, capsys, args, size):
    out = files["dir"] / f"{args[0]}_{abs(hash(tuple(args)))}.png"
    args = [a.format(**files) for a in args]
    code, err = run_cli(capsys, "plot", *args, "-o", str(out))
    assert code == 0, err
    image(out, size)


def test_svg_and_pdf_follow_the_extension(files, capsys):
    for ext, head in ((".svg", b"<?xml"), (".pdf", b"%PDF")):
        out = files["dir"] / f"lines{ext}"
        code, err = run_cli(capsys, "plot", "line", str(files["map"]), "--var", "kzz", "--x", "Fz", "-o", str(out))
        assert code == 0, err
        assert out.read_bytes().startswith(head)


def test_load_zone_default_size_and_loads(files):
    bearing = fb.Bearing.preset("gunduz2013", "DT")
    q = fb.solve(bearing, [1000.0, 0.0, 3000.0, 0.0, -74000.0]).q
    out = files["dir"] / "zone.png"
    fig = plot.plot_load_zone(bearing, q, out=out)
    width, height = (fig.get_size_inches() * fig.dpi).round().astype(int)
    image(out, (width, height))
    Q, _ = fb.ball_loads(bearing, q)
    polar = [ax for ax in fig.axes if ax.name == "polar"]
    assert len(polar) == 2
    for r, ax in enumerate(polar):  # the envelope through every ball's load, closed: Z + 1 points
        radii = ax.lines[0].get_ydata()
        assert len(radii) == 15
        np.testing.assert_allclose(sorted(radii[:-1]), sorted(Q[14 * r:14 * (r + 1)]))


def test_line_plot_shows_the_files_numbers(files):
    ds = fb.open_dataset(files["map"])
    fig = plot.plot_lines(ds, ["kzz", "ktyty"], "Fz", at={"Fx": 900.0, "My": -70000.0})
    kzz, ktyty = (ax.lines[0].get_ydata() for ax in fig.axes)
    K = ds["K"].sel(Fx=1000.0, My=-74000.0).values  # the nearest grid values
    np.testing.assert_allclose(kzz, K[:, 2, 2] / 1e3)  # kN/mm
    np.testing.assert_allclose(ktyty, K[:, 4, 4] / 1e6)  # MN*mm/rad
    assert fig.axes[0].get_ylabel() == "$k_{zz}$ (kN/mm)"
    assert fig.axes[1].get_ylabel() == r"$k_{\theta_y\theta_y}$ (MN·mm/rad)"
    assert fig.axes[1].get_xlabel() == "$F_z$ (kN)"
    assert "Fx = 1 kN" in fig.axes[0].get_title() and "My = -74 kN·mm" in fig.axes[0].get_title()
    ref = fb.solve(fb.Bearing.preset("gunduz2013", "DB"), [1000.0, 0.0, 3000.0, 0.0, -74000.0])
    assert kzz[-1] == pytest.approx(ref.K[2, 2] / 1e3, rel=1e-8)
    ds.close()


def test_map_data_and_labels(files):
    ds = fb.open_dataset(files["map"])
    fig = plot.plot_map(ds, "kzz", "Fx", "My", kind="heatmap", at={"Fz": 3000.0})
    mesh = fig.axes[0].collections[0]
    z = np.asarray(mesh.get_array()).reshape(3, 5)  # (My, Fx)
    np.testing.assert_allclose(z, ds["K"].sel(Fz=3000.0).values[:, :, 2, 2].T / 1e3)
    assert fig.axes[0].get_xlabel() == "$F_x$ (kN)" and fig.axes[0].get_ylabel() == "$M_y$ (kN·mm)"
    assert fig.axes[1].get_ylabel() == "$k_{zz}$ (kN/mm)"  # the colour bar
    ds.close()


def test_passage_curve_normalisations(files):
    ds = fb.open_dataset(files["passage"])
    K = ds["K"].values[0, :, 2, 2]
    x, y, xl, yl, where = plot.passage_curve(ds, "kzz", normalise="first", x="period")
    np.testing.assert_allclose(y, np.append(K, K[0]) / K[0])
    np.testing.assert_allclose(x, np.arange(9) / 8)
    assert xl == "ball passage period (-)" and where[:2] == ["point 0", "dx = 0.05 mm"]
    x, y, xl, _, _ = plot.passage_curve(ds, "kzz", normalise="mean", x="time")
    np.testing.assert_allclose(y, np.append(K, K[0]) / K.mean())
    period = 1 / ds.attrs["ball_pass_frequency_hz"]
    assert xl == "time (ms)" and x[-1] == pytest.approx(period * 1e3)
    x, y, xl, yl, _ = plot.passage_curve(ds, "ktyty", x="angle")  # an angle: in degrees (issue 39)
    assert x[-1] == pytest.approx(360 / 14) and yl.endswith("(MN·mm/rad)") and xl.endswith("(deg)")
    x, _, xl, _, _ = plot.passage_curve(ds, "ktyty", x="angle", base_units=True)
    assert x[-1] == pytest.approx(2 * math.pi / 14) and xl.endswith("(rad)")
    ds.close()


def test_spectrum_is_the_stored_amplitude(files):
    ds = fb.open_dataset(files["passage"])
    fig = plot.plot_spectrum(ds, ["kzz"], normalise="mean", log=False)
    heights = [p.get_height() for p in fig.axes[0].patches]
    amp = ds["K_amplitude"].values[0, :, 2, 2]
    np.testing.assert_allclose(heights, amp[1:] / amp[0] * 100)
    assert fig.axes[0].get_xlabel() == "frequency (Hz)"
    ds.close()


def test_overwrite_is_refused_and_the_file_kept(files, capsys):
    out = files["dir"] / "keep.png"
    out.write_bytes(b"not an image")
    code, err = run_cli(capsys, "plot", "passage", str(files["passage"]), "-o", str(out))
    assert code == 2 and "exists" in err and "--overwrite" in err
    assert out.read_bytes() == b"not an image"
    code, err = run_cli(capsys, "plot", "passage", str(files["passage"]), "-o", str(out), "--overwrite")
    assert code == 0, err
    image(out, plot.DEFAULT_SIZE)
    assert not list(files["dir"].glob("*.part"))


@pytest.mark.parametrize("args, words", [
    (["map", "{map}", "--var", "kzq", "--x", "Fx", "--y", "My"], "unknown variable 'kzq'"),
    (["map", "{map}", "--var", "kzz", "--x", "Fx", "--y", "Mz"], "unknown axis 'Mz'"),
    (["map", "{map}", "--var", "kzz", "--x", "Fx", "--y", "Fx"], "two different axes"),
    (["map", "{map}", "--var", "kzz", "--x", "Fx", "--y", "My", "--at", "Mz=3"], "unknown axis 'Mz' in at"),
    (["map", "{map}", "--var", "kzz", "--x", "Fx", "--y", "My", "--at", "Fz"], "--at needs NAME=VALUE"),
    (["map", "{map}", "--var", "max_ball_load", "--x", "Fx", "--y", "My", "--row", "2"], "row must be"),
    (["line", "{map}", "--var", "kzz", "--x", "dz"], "unknown axis 'dz'"),
    (["map", "{passage}", "--var", "kzz", "--x", "Fx", "--y", "My"], "ball-passage table"),
    (["passage", "{map}"], "not a ball-passage table"),
    (["passage", "{passage}", "--var", "kxx,max_ball_load"], "per row"),
    (["spectrum", "{passage}", "--var", "dz"], "unknown variable 'dz' for a spectrum"),
    (["passage", "{dir}/missing.h5"], "file not found"),
    (["passage", "{dir}/junk.h5"], "not a finished fastbearing file"),
    (["passage", "{passage}", "--normalise", "max"], "invalid choice"),
    (["passage", "{passage}", "--size", "big"], "--size must be WIDTHxHEIGHT"),
    (["loadzone", "--preset", "gunduz2013", "--load", "1,2"], "--load needs 5"),
])
def test_bad_input_is_one_line_and_exit_2(files, capsys, args, words):
    (files["dir"] / "junk.h5").write_text("not HDF5")
    out = files["dir"] / "bad.png"
    code, err = run_cli(capsys, "plot", *[a.format(**files) for a in args], "-o", str(out))
    assert code == 2 and words in err, err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert not out.exists()


def test_bad_output_name_and_api_errors(files, capsys):
    code, err = run_cli(capsys, "plot", "passage", str(files["passage"]), "-o", str(files["dir"] / "p.jpg"))
    assert code == 2 and ".png, .svg or .pdf" in err
    with pytest.raises(ValueError, match="kind must be"):
        plot.plot_map(files["map"], "kzz", "Fx", "My", kind="surface")
    with pytest.raises(ValueError, match="normalise must be"):
        plot.plot_passage(files["passage"], normalise="max")
    with pytest.raises(ValueError, match="at.Fz must be a finite number"):
        plot.plot_lines(files["map"], "kzz", "Fx", at={"Fz": float("nan")})
    with pytest.raises(ValueError, match="is plotted"):
        plot.plot_lines(files["map"], "kzz", "Fx", at={"Fx": 0.0})
    with pytest.raises(ValueError, match="output folder"):
        plot.plot_passage(files["passage"], out=files["dir"] / "nowhere" / "p.png")


def test_package_imports_without_matplotlib():
    """matplotlib is imported on the first plot, not with the package."""
    import subprocess
    import sys

    code = "import sys, fastbearing; assert 'matplotlib' not in sys.modules; print('ok')"
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0 and p.stdout.strip() == "ok", p.stderr


# -- the pictures' reported problems ------------------------------------------------------

def test_coincident_is_numeric_and_relative_to_the_panel():
    x = np.linspace(0.0, 1.0, 50)
    a, far = np.sin(x), np.sin(x) + 0.1
    near = a + 1e-4 * np.ptp(np.r_[a, far])  # well under COINCIDE_RTOL of the panel's range
    assert plot.coincident([a, far, near, a.copy()]) == [None, None, 0, 0]
    assert plot.coincident([a, far]) == [None, None]
    gap = a.copy()
    gap[3] = np.nan
    assert plot.coincident([a, gap]) == [None, None]  # different gaps: not the same curve
    assert plot.coincident([np.zeros(4), np.zeros(4)]) == [None, 0]
    # numbers at rounding level beside a real curve coincide (zero by symmetry, e.g. DB and DF kxz)
    assert plot.coincident([1e-12 * np.cos(x), -1e-12 * np.cos(x), x]) == [None, 0, None]


def test_draw_curves_keeps_coinciding_curves_visible():
    fig = plot.new_figure((400, 300))
    ax = fig.add_subplot()
    x = np.linspace(0.0, 1.0, 60)
    lines = plot.draw_curves(ax, x, [("a", x ** 2, {"marker": "o"}), ("b", x, {"marker": "s"}),
                                     ("c", x ** 2, {"marker": "^"}), ("d", x ** 2, {"marker": "x"})])
    labels = [ln.get_label() for ln in lines]
    assert labels == ["a", "b", "c (coincides with a)", "d (coincides with a)"]
    styles = {ln.get_linestyle() for ln in (lines[0], lines[2], lines[3])}
    assert len(styles) == 3  # solid, dashed, dotted
    assert lines[0].get_zorder() < lines[2].get_zorder() < lines[3].get_zorder()
    # 60 points: sparse markers, and those of the curves drawn over shifted between the first one's
    starts = [ln.get_markevery()[0] for ln in (lines[0], lines[2], lines[3])]
    assert len(set(starts)) == 3


@pytest.mark.parametrize("normalise", ["first", "mean"])
def test_normalised_passage_says_kxx_and_ktyty_coincide(files, normalise):
    fig = plot.plot_passage(files["passage"], normalise=normalise)
    ax = fig.axes[0]
    texts = [t.get_text() for t in ax.get_legend().get_texts()]
    assert texts == ["$k_{xx}$", "$k_{zz}$", r"$k_{\theta_y\theta_y}$ (coincides with $k_{xx}$)"]
    kxx, kzz, ktyty = ax.lines
    assert kxx.get_linestyle() == "-" and ktyty.get_linestyle() != "-"
    assert ktyty.get_zorder() > kxx.get_zorder()
    assert ktyty.get_markersize() > kxx.get_markersize()  # a ring around kxx's marker
    # at the tilted point they differ by about 8 % of the range: no such claim
    fig = plot.plot_passage(files["passage"], normalise=normalise, at={"point": 1})
    assert not any("coincide" in t.get_text() for t in fig.axes[0].get_legend().get_texts())


def test_passage_counts_its_points_right(files):
    """8 cage positions: 8 markers (the closing point repeats position 0), and the title says how many
    operating points the file has and how to pick another."""
    fig = plot.plot_passage(files["passage"], "kzz")
    line = fig.axes[0].lines[0]
    assert len(line.get_xdata()) == 9
    assert len(np.arange(9)[line.get_markevery()]) == 8
    title = fig.axes[0].get_title()
    assert "8 cage positions" in title and "at point 0, dx = 0.05 mm" in title
    assert "1 of 2 operating points" in title and "--at point=0..1" in title
    fig = plot.plot_spectrum(files["passage"], "kzz", at={"point": 1})
    assert "at point 1, by = 30 mrad" in fig.axes[0].get_title() and "1 of 2" in fig.axes[0].get_title()


def test_base_units_reach_the_titles(files):
    ds = fb.open_dataset(files["map"])
    titles = [plot.plot_lines(ds, "kzz", "Fz", at={"Fx": 1000.0, "My": -74000.0}, base_units=True).axes[0].get_title(),
              plot.plot_map(ds, "kzz", "Fx", "My", at={"Fz": 3000.0}, base_units=True).axes[0].get_title()]
    ds.close()
    assert "Fx = 1000 N" in titles[0] and "My = -7.4e+04 N·mm" in titles[0]
    assert "Fz = 3000 N" in titles[1]
    for base in (False, True):
        fig = plot.plot_passage(files["passage"], at={"point": 1}, base_units=base)
        titles.append(fig.axes[0].get_title())
        assert ("by = 0.03 rad" if base else "by = 30 mrad") in titles[-1]
    titles.append(plot.plot_spectrum(files["passage"], normalise="none", base_units=True).axes[0].get_title())
    assert "dx = 0.05 mm" in titles[-1]
    for title in titles[:2] + titles[3:]:
        assert "kN" not in title and "mrad" not in title, title


def test_load_zone_legend_names_the_grey_dots():
    bearing = fb.Bearing.preset("gunduz2013", "DB")
    q = fb.solve(bearing, [1000.0, 0.0, 3000.0, 0.0, -74000.0]).q
    fig = plot.plot_load_zone(bearing, q, size=(600, 400))
    (legend,) = fig.legends
    entries = dict(zip((t.get_text() for t in legend.get_texts()), legend.legend_handles
                       if hasattr(legend, "legend_handles") else legend.legendHandles))
    grey = [h for h in entries.values() if h.get_color() == "0.6"]
    assert len(grey) == 1 and grey[0].get_marker() == "o"
    text = next(t for t, h in entries.items() if h is grey[0])
    assert "ball positions" in text and "every ball" in text
    assert any("loaded ball" in t for t in entries)
    for ax in fig.axes:  # the grey dots: one per ball of the row, on the rim
        dots = [ln for ln in ax.lines if ln.get_color() == "0.6"]
        assert len(dots) == 1 and len(dots[0].get_xdata()) == 14


def test_the_load_zone_of_a_roller_bearing_speaks_of_rollers():
    """Each row says its own elements' word (the element kind's ``element_word``): the picture of a roller
    bearing once called its rollers balls (issue 39)."""
    from pathlib import Path

    bearing = fb.load_bearing(Path(__file__).parents[1] / "fastbearing" / "catalogue" / "NU205.toml")
    q = fb.solve(bearing, [3000.0, 0.0, 0.0, 0.0, 0.0]).q
    fig = plot.plot_load_zone(bearing, q, size=(600, 400))
    texts = [t.get_text() for t in fig.legends[0].get_texts()]
    texts += [ax.get_title() for ax in fig.axes] + [ax.get_xlabel() for ax in fig.axes]
    assert all("ball" not in t for t in texts), texts
    assert any("loaded roller" in t for t in texts) and any("rollers loaded" in t for t in texts)


def _svg_texts(fig, path) -> str:
    """Every text the picture shows, as its SVG file keeps it (svg.fonttype 'none': text stays text)."""
    import matplotlib as mpl

    with mpl.rc_context({"svg.fonttype": "none"}):
        fig.savefig(path, format="svg")
    return path.read_text()


def test_every_text_of_a_roller_load_zone_speaks_of_rollers_and_degrees(tmp_path):
    """Title, panel titles, axis labels, tick labels and legend of a roller bearing's load zone: rollers, never
    balls, and the azimuth in degrees (issue 39, item 6)."""
    from pathlib import Path

    bearing = fb.load_bearing(Path(__file__).parents[1] / "fastbearing" / "catalogue" / "NU205.toml")
    fig = plot.plot_load_zone(bearing, fb.solve(bearing, [3000.0, 0.0, 0.0, 0.0, 0.0]).q)
    texts = [t.get_text() for t in fig.findobj(lambda a: hasattr(a, "get_text"))]
    texts += [t.get_text() for ax in fig.axes for t in ax.get_xticklabels() + ax.get_yticklabels()]
    assert texts and all("ball" not in t.lower() for t in texts), texts
    assert fig.get_suptitle().startswith("Load zone of NU205")
    (ax,) = fig.axes
    assert "(deg)" in ax.get_xlabel() and "(rad)" not in ax.get_xlabel()
    assert [t.get_text() for t in ax.get_xticklabels()] == [f"{d}\u00b0" for d in range(0, 360, 45)]
    svg = _svg_texts(fig, tmp_path / "zone.svg")
    assert "roller" in svg and "ball" not in svg.lower() and "315\u00b0" in svg and "\u03c0" not in svg


def test_a_four_point_load_zone_names_its_balls():
    """A four-point row's contact pairs say "balls (one contact pair)": its singular is still "ball"."""
    from pathlib import Path

    bearing = fb.load_bearing(Path(__file__).parents[1] / "fastbearing" / "catalogue" / "QJ210.toml")
    fig = plot.plot_load_zone(bearing, fb.solve(bearing, [3000.0, 0.0, 1000.0, 0.0, 0.0]).q, size=(800, 520))
    texts = [t.get_text() for t in fig.legends[0].get_texts()]
    assert texts[0].startswith("loaded ball (") and texts[1].startswith("ball positions: every ball of")


def test_contact_angles_are_drawn_in_degrees_and_long_labels_do_not_overlap(files):
    """The speed picture's layout (kxx, kzz, min_contact_angle stacked, one line per series value): the
    contact angle reads in degrees, and its long label is wrapped so that it keeps clear of kzz's (issue 39)."""
    ds = fb.open_dataset(files["map"])
    fig = plot.plot_lines(ds, ["kxx", "kzz", "min_contact_angle"], "Fx", series="Fz", at={"My": 0.0})
    angle = fig.axes[2].lines[0].get_ydata()
    stored = ds["min_contact_angle"].sel(My=0.0, Fz=500.0).isel(row=0).values
    np.testing.assert_allclose(angle, np.degrees(stored))
    assert fig.axes[2].get_ylabel().replace("\n", " ") == "smallest loaded contact angle (deg)"
    fig.draw_without_rendering()
    boxes = [ax.yaxis.label.get_window_extent() for ax in fig.axes[:3]]
    for upper, lower in zip(boxes, boxes[1:]):
        assert lower.y1 < upper.y0, (upper, lower)
    for ax, box in zip(fig.axes[:3], boxes):  # each label within its own panel's height
        panel = ax.get_window_extent()
        assert panel.y0 - 1 <= box.y0 and box.y1 <= panel.y1 + 1
    fig = plot.plot_map(ds, "max_contact_angle", "Fx", "My", at={"Fz": 1000.0})
    assert fig.axes[1].get_ylabel() == "largest loaded contact angle (deg)"
    assert plot.plot_map(ds, "max_contact_angle", "Fx", "My", base_units=True).axes[1].get_ylabel().endswith("(rad)")
    ds.close()


def test_a_log_colour_bar_labels_more_than_its_decades(files):
    """L10r over a map spanning about one and a half decades: the colour bar labels 1, 2, 5 x 10^n, not just
    the one or two decades (issue 39, item 6)."""
    ds = fb.open_dataset(files["map"])
    kzz = ds["K"].isel(dof=2, dof_col=2)
    ds["L10r"] = 1e9 / kzz ** 1.5 * (1 + 0 * ds["Fx"])  # positive, one to two decades: a stand-in life
    span = float(np.log10(ds["L10r"].max() / ds["L10r"].min()))
    assert 0.3 < span < 3
    for kind in ("contour", "heatmap"):
        fig = plot.plot_map(ds, "L10r", "Fx", "My", kind=kind, at={"Fz": 1000.0})
        fig.draw_without_rendering()
        bar = fig.axes[1]
        low, high = bar.get_ylim()
        labels = [t.get_text() for t in bar.get_yticklabels() if low <= t.get_position()[1] <= high]
        assert sum(bool(t) for t in labels) >= 3, (kind, labels)
    ds.close()


def test_at_beyond_an_axis_is_refused_not_snapped(files, capsys):
    """--at Fx=1e6 on a map whose Fx runs to 2 kN once drew the edge's point silently (issue 39, item 4)."""
    ds = fb.open_dataset(files["map"])
    with pytest.raises(ValueError) as err:
        plot.plot_lines(ds, "kzz", "Fz", at={"Fx": 1e6, "My": 0.0})
    assert str(err.value) == ("at Fx=1e+06 is outside the file's Fx axis [-2000, 2000] N (5 values): give a value "
                              "within it")
    with pytest.raises(ValueError, match=re.escape("at My=-80000 is outside the file's My axis [-74000, 74000] N*mm")):
        plot.plot_map(ds, "kzz", "Fx", "Fz", at={"My": -80000.0})
    # in range, and at the edges to rounding: the nearest grid point, as before
    fig = plot.plot_lines(ds, "kzz", "Fz", at={"Fx": 2000.0 * (1 + 1e-12), "My": -73000.0})
    assert "Fx = 2 kN" in fig.axes[0].get_title() and "My = -74 kN·mm" in fig.axes[0].get_title()
    ds.close()
    # a table's own dims are indices: one beyond the last is refused too
    with pytest.raises(ValueError, match=re.escape("at point=2 is outside the file's point axis [0, 1] (2 values)")):
        plot.plot_passage(files["passage"], at={"point": 2})
    out = files["dir"] / "beyond.png"
    code, err = run_cli(capsys, "plot", "map", str(files["map"]), "--var", "kzz", "--x", "Fx", "--y", "My",
                        "--at", "Fz=1e6", "-o", str(out))
    assert code == 2 and "at Fz=1e+06 is outside the file's Fz axis [500, 3000] N" in err, err
    assert len(err.strip().splitlines()) == 1 and not out.exists()
