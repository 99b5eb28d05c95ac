"""Ball-passage tables: the paper's Figs. 13 and 14, periodicity, Fourier
synthesis, staggered rows, load control, files."""

import csv
import math

import h5py
import numpy as np
import pytest
from conftest import cli_run

import fastbearing as fb
from fastbearing.jobs.passage import fourier, read_config
from fastbearing.report.export import K_COLUMNS, read_csv


def run(tmp_path, passage_body, bearing='preset = "gunduz2013"\narrangement = "DB"', name="p", **kw):
    cfg = tmp_path / f"{name}.toml"
    cfg.write_text(f"[bearing]\n{bearing}\n\n[passage]\n{passage_body}")
    return fb.passage(cfg, tmp_path / f"{name}.h5", **kw)


def load(path, *names):
    with h5py.File(path, "r") as fh:
        return [fh[n][...] for n in names]


def diag(a):
    return np.diagonal(a, axis1=-2, axis2=-1)


def paper_variation(K):
    """The paper's Fig. 13 measure for kxx, kzz, kthy: peak-to-peak normalised by the value at position 0."""
    d = diag(K)[..., [0, 2, 4]]
    return (d.max(axis=-2) - d.min(axis=-2)) / np.abs(d[..., 0, :]) * 100


@pytest.mark.parametrize("arrangement", ["DB", "DF", "DT"])
def test_fig13_fourteen_balls(tmp_path, arrangement):
    """Z = 14, dx = 0.05 mm: kzz varies about 6 %, kxx and kthy under 0.2 %."""
    out = run(tmp_path, "points = [[0.05, 0.0, 0.0, 0.0, 0.0]]\n",
              bearing=f'preset = "gunduz2013"\narrangement = "{arrangement}"')
    variation, = load(out, "K_variation")
    kxx, kzz, kty = diag(variation[0])[[0, 2, 4]]
    assert 5.0 < kzz < 8.0
    assert kxx < 0.2 and kty < 0.2


@pytest.mark.parametrize("arrangement", ["DB", "DF", "DT"])
def test_fig13_four_balls(tmp_path, arrangement):
    """Z = 4, dx = 0.05 mm: kzz about 70 %, kxx about 18 %, kthy about 16 % (paper's normalisation: by the
    value at position 0). The paper shows DB only; kthy is arrangement-specific, so it is checked on DB."""
    out = run(tmp_path, "points = [[0.05, 0.0, 0.0, 0.0, 0.0]]\npositions = 128\n",
              bearing=f'preset = "gunduz2013"\narrangement = "{arrangement}"\nn_balls = 4')
    K, = load(out, "K")
    kxx, kzz, kty = paper_variation(K[0])
    assert 60 < kzz < 77 and 15 < kxx < 21
    if arrangement == "DB":
        assert 13.5 < kty < 18.5


def test_fig14_tilt(tmp_path):
    """by = 0.03 rad, Z = 14: kxx, kzz and kthy vary by under 2 % for every arrangement."""
    for arrangement in ("DB", "DF", "DT"):
        out = run(tmp_path, "points = [[0.0, 0.0, 0.0, 0.0, 0.03]]\n", name=arrangement,
                  bearing=f'preset = "gunduz2013"\narrangement = "{arrangement}"')
        variation, = load(out, "K_variation")
        assert np.all(diag(variation[0])[[0, 2, 4]] < 2.0), arrangement


def test_table_is_periodic_and_position_zero_is_the_definition(tmp_path):
    out = run(tmp_path, "points = [[0.03, -0.01, 0.02, 1e-4, -3e-4]]\npositions = 16\n")
    K, = load(out, "K")
    bearing = fb.Bearing.preset("gunduz2013", "DB")
    q = np.array([0.03, -0.01, 0.02, 1e-4, -3e-4])
    np.testing.assert_array_equal(K[0, 0], fb.stiffness(bearing, q)[1])
    from fastbearing.engine.kernel import ball_loop
    f, K_period = np.empty(5), np.empty((5, 5))
    ball_loop(q, bearing.ball_set(cage_angle=2 * math.pi / 14), f, K_period, None, None)
    np.testing.assert_allclose(K_period, K[0, 0], rtol=1e-9, atol=1e-9 * np.abs(K[0, 0]).max())


def test_fourier_synthesis_reproduces_the_table(tmp_path):
    out = run(tmp_path, "points = [[0.05, 0.0, 0.01, 0.0, 0.0]]\npositions = 32\nharmonics = 16\n",
              bearing='preset = "gunduz2013"\narrangement = "DT"\nn_balls = 5')
    K, amp, phase = load(out, "K", "K_amplitude", "K_phase")
    k = np.arange(32)
    synth = sum(amp[0, h] * np.cos(h * 2 * np.pi * k[:, None, None] / 32 + phase[0, h]) for h in range(17))
    np.testing.assert_allclose(synth, K[0], rtol=1e-9, atol=1e-9 * np.abs(K).max())
    a, p = fourier(K, 3)
    np.testing.assert_array_equal(a, amp[:, :4])
    np.testing.assert_allclose(a[0, 0] * np.cos(p[0, 0]), K[0].mean(axis=0), rtol=1e-12, atol=1e-6)


def test_staggered_rows_halve_the_period(tmp_path):
    """DB rows staggered by half a ball pitch under pure radial displacement: kxx, kzz, kthy repeat every
    half pitch, so their odd harmonics vanish (without stagger they do not)."""
    rows = "".join(f"""
[[bearing.rows]]
axial_offset = {z}
contact_direction = {s}
first_ball_angle = {psi0}
""" for z, s, psi0 in ((-10.0, 1, 0.0), (10.0, -1, 360.0 / 14 / 2)))
    common = ("n_balls = 14\nhertz_constant = 395000.0\npitch_radius = 34.75\n"
              "groove_center_distance = 0.52\ncontact_angle = 30.0\n")
    out = run(tmp_path, "points = [[0.05, 0.0, 0.0, 0.0, 0.0]]\n", bearing=common + rows)
    amp, = load(out, "K_amplitude")
    for i in (0, 2, 4):
        assert amp[0, 1, i, i] < 1e-9 * amp[0, 0, i, i]
        assert amp[0, 2, i, i] > 1e-6 * amp[0, 0, i, i]
    plain = run(tmp_path, "points = [[0.05, 0.0, 0.0, 0.0, 0.0]]\n", name="plain")
    amp_plain, = load(plain, "K_amplitude")
    assert amp_plain[0, 1, 2, 2] > 1e-3 * amp_plain[0, 0, 2, 2]


def test_rows_with_different_ball_counts_use_the_common_period(tmp_path):
    """Rows of 14 and 12 balls repeat together only after a cage turn of 2*pi/gcd(14, 12) = pi."""
    config = {"bearing": {"preset": "gunduz2013", "rows": [
        {"axial_offset": -10.0, "contact_direction": 1, "n_balls": 14},
        {"axial_offset": 10.0, "contact_direction": -1, "n_balls": 12}]},
        "passage": {"points": [[0.05, 0, 0.01, 0, 0]], "positions": 12}}
    cfg = read_config(config)
    assert cfg.period_order == 2 and cfg.period == pytest.approx(math.pi)
    out = fb.passage(cfg, tmp_path / "mixed.h5")
    K, angle = load(out, "K", "cage_angle")
    np.testing.assert_allclose(angle, np.arange(12) * math.pi / 12)
    from fastbearing.engine.kernel import ball_loop
    f, K_end = np.empty(5), np.empty((5, 5))
    ball_loop(np.array([0.05, 0, 0.01, 0, 0]), cfg.bearing.ball_set(math.pi), f, K_end, None, None)
    np.testing.assert_allclose(K_end, K[0, 0], rtol=1e-9, atol=1e-9 * np.abs(K_end).max())
    # a quarter turn is not a period of this set
    assert np.abs(K[0, 6] - K[0, 0]).max() > 1e-6 * np.abs(K[0, 0]).max()


def test_load_controlled_table(tmp_path):
    load_point = [1000.0, 0.0, 3000.0, 0.0, -74000.0]
    out = run(tmp_path, f'given = "load"\npoints = [{load_point}]\npositions = 16\n')
    q, f, K, status = load(out, "q", "f", "K", "status")
    assert (status == 0).all()
    D = np.array([1, 1, 1, 1 / 34.75, 1 / 34.75])
    assert np.all(np.abs((f[0] - load_point) * D) <= 1e-10 * np.abs(np.array(load_point) * D).max())
    ref = fb.solve(fb.Bearing.preset("gunduz2013", "DB"), load_point)
    np.testing.assert_allclose(q[0, 0], ref.q, rtol=1e-9, atol=1e-12)
    assert np.ptp(q[0, :, 2]) > 0  # the ring moves as balls pass
    # position 0 is the paper's layout (first ball at psi = 0): Table 4, DB
    np.testing.assert_allclose(diag(K[0, 0]) / [1e3, 1e3, 1e3, 1e6, 1e6], [420, 346, 297, 345, 410], rtol=0.02)


def test_identical_for_one_and_two_threads(tmp_path):
    body = 'given = "load"\nFx = [500.0, 1000.0, 2000.0]\nFz = { start = 1000.0, stop = 4000.0, num = 3 }\n' \
           "positions = 8\n"
    a = run(tmp_path, body, name="one", threads=1)
    b = run(tmp_path, body, name="two", threads=2)
    for name in ("q", "K", "status", "K_amplitude"):
        np.testing.assert_array_equal(*load(a, name), *load(b, name))
    ds = fb.open_dataset(a)
    assert ds["K"].dims == ("Fx", "Fz", "position", "dof", "dof_col")
    assert ds["K"].sel(Fx=1000.0, Fz=2500.0).shape == (8, 5, 5)


def test_time_axis_csv_and_cli(tmp_path):
    cfg = tmp_path / "t.toml"
    cfg.write_text('[bearing]\npreset = "gunduz2013"\narrangement = "DB"\n\n[passage]\n'
                   "points = [[0.05, 0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.02, 0.0, 0.0]]\npositions = 8\n"
                   "shaft_speed = 3000.0\nball_diameter = 12.0\npitch_diameter = 70.0\n")
    p = cli_run("passage", cfg, "--csv")
    assert p.returncode == 0, p.stderr
    ds = fb.open_dataset(tmp_path / "t.h5")
    fc = 3000 / 60 / 2 * (1 - 12 * math.cos(math.radians(30)) / 70)
    assert ds.attrs["ball_pass_frequency_hz"] == pytest.approx(14 * fc)
    np.testing.assert_allclose(ds["time"].values, ds["cage_angle"].values / (2 * math.pi * fc))
    np.testing.assert_allclose(ds["frequency"].values, np.arange(9)[:5] * 14 * fc)
    with open(tmp_path / "t_point0001.csv") as fh:
        rows = list(csv.reader(fh))
    # the export's dialect (report/export.py's write_csv): the point's inputs, position, angle, time, status, 25 entries
    assert rows[0][:11] == ["case", "dx_mm", "dy_mm", "dz_mm", "bx_rad", "by_rad", "point", "position",
                            "cage_angle_rad", "time_s", "status"] and len(rows) == 9
    assert rows[0][11:] == [*K_COLUMNS, "status_name", "matrix"] and "ktyty_N_mm_per_rad" in rows[0]
    assert float(rows[3][rows[0].index("kzz_N_per_mm")]) == ds["K"].values[1, 2, 2, 2]
    assert rows[3][0] == "10" and float(rows[3][rows[0].index("dz_mm")]) == 0.02  # the file's flat case number
    np.testing.assert_array_equal(read_csv(tmp_path / "t_point0001.csv"), ds["K"].values[1])
    again = cli_run("passage", cfg, "--csv")
    assert again.returncode == 2 and "exists" in again.stderr


@pytest.mark.parametrize("body, words", [
    ("points = [[0.05, 0.0, 0.0]]\n", r"passage.points\[0\] must be a list of 5 items, got 3"),
    ("points = []\n", r"passage.points must hold at least 1 item\(s\)"),
    ('points = [[0.05, 0.0, 0.0, 0.0, "a"]]\n', r"passage.points\[0\]\[4\] must be a number, got 'a'"),
    ("points = [[0.05, 0, 0, 0, 0]]\nshaft_speed = 3000.0\n", "needs shaft_speed .* together"),
    ("points = [[0.05, 0, 0, 0, 0]]\nshaft_speed = 3000.0\nball_diameter = 80.0\npitch_diameter = 70.0\n",
     r"passage.pitch_diameter must be > 80 mm, got 70.0"),
    ("points = [[0.05, 0, 0, 0, 0]]\npositions = 1\n", r"passage.positions must be an integer in \[2, 100000\]"),
    ("points = [[0.05, 0, 0, 0, 0]]\npositions = 1000000000\n", r"passage.positions must be an integer in \[2, 100000\]"),
    ("points = [[0.05, 0, 0, 0, 0]]\nspeed = 1\n", r"passage.speed above 0 rpm needs the bearing.s geometry"),
    ("points = [[0.05, 0, 0, 0, 0]]\nsped = 1\n", "passage: unknown key 'sped'"),
    ("dx = 0.05\npoints = [[0.05, 0, 0, 0, 0]]\n", "passage.points replaces the grid axes"),
    ("positions = 8\n", "passage needs points"),
    ('given = "load"\nFx = 1.0\ndx = 0.1\n', "passage: unknown key 'dx' for given = 'load'"),
])
def test_bad_passage_configs(tmp_path, body, words):
    cfg = tmp_path / "bad.toml"
    cfg.write_text(f'[bearing]\npreset = "gunduz2013"\n\n[passage]\n{body}')
    with pytest.raises(ValueError, match=words):
        read_config(cfg)
