"""Pictures: every plot command renders a non-empty image of the asked size from a small file; the
plotted numbers are the file's; bad input is a ValueError (API) or one line and exit 2 (CLI)."""

import math

import numpy as np
import pytest

pytest.importorskip("matplotlib")

import matplotlib.image as mpimg  # noqa: E402

import fastbearing as fb  # noqa: E402
from fastbearing import cli, plot  # noqa: E402


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
    x, y, xl, yl, _ = plot.passage_curve(ds, "ktyty", x="angle")
    assert x[-1] == pytest.approx(2 * math.pi / 14) and yl.endswith("(MN·mm/rad)") and xl.endswith("(rad)")
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
