"""Cases that vary the bearing (issue 44 item 5): each case's own operating clearance and preload, taken by the
kernels through contract.CaseBlock.operating (engine/sweep.with_operating), give what a bearing built with
those values gives, bit for bit; a mounted bearing's cases get theirs from their own speed and temperatures."""

from dataclasses import replace

import numpy as np
import pytest

import fastbearing as fb
from fastbearing.model.mounted import operating_bearing, operating_rows

from test_mounting import ROOT, bearing_6205, bearing_7014


def _loads(n, seed, scale=3000.0, moments=False):
    rng = np.random.default_rng(seed)
    out = np.zeros((n, 5))
    out[:, :3] = rng.uniform(-scale, scale, (n, 3))
    if moments:
        out[:, 3:] = rng.uniform(-scale, scale, (n, 2)) * 10.0
    return out


def _assert_case_equals(r, i, single):
    assert r.status[i] == single.status[0]
    for name in ("q", "f", "K"):
        assert np.array_equal(getattr(r, name)[i], getattr(single, name)[0]), (name, i)


def test_each_case_equals_the_bearing_built_with_its_clearance_and_preload():
    b = fb.Bearing.preset("gunduz2013", "DB")
    n = 10
    loads = _loads(n, 1, moments=True)
    rng = np.random.default_rng(2)
    rL = np.repeat(rng.uniform(-0.006, 0.0, (n, 1)), b.n_rows, axis=1)  # an axial preload needs rL <= 0
    d0 = rng.uniform(0.0, 0.004, (n, b.n_rows))
    r = fb.solve_many(b, loads, radial_clearance=rL, axial_preload=d0)
    assert fb.status.converged_mask(r.status).all()
    for i in range(n):
        rows = tuple(replace(row, radial_clearance=rL[i, k], axial_preload=d0[i, k]) for k, row in enumerate(b.rows))
        _assert_case_equals(r, i, fb.solve_many(replace(b, rows=rows), loads[i:i + 1]))


def test_the_bearing_own_values_change_nothing():
    b = fb.Bearing.preset("gunduz2013", "DB")
    loads = _loads(16, 3)
    plain = fb.solve_many(b, loads)
    own = fb.solve_many(b, loads, radial_clearance=[r.radial_clearance for r in b.rows],
                        axial_preload=[r.axial_preload for r in b.rows])
    for name in ("q", "f", "K", "status", "iterations"):
        assert np.array_equal(getattr(plain, name), getattr(own, name)), name


def test_roller_rows_take_each_case_approach():
    b = fb.load_bearing("30206-TDO")
    n = 4
    loads = _loads(n, 4, scale=4000.0)
    d0 = np.linspace(0.0, 0.003, n)[:, None] * np.ones((1, b.n_rows))
    r = fb.solve_many(b, loads, axial_preload=d0)
    for i in range(n):
        _assert_case_equals(r, i, fb.solve_many(b.with_rows(axial_preload=float(d0[i, 0])), loads[i:i + 1]))


def test_balls_at_speed_take_each_case_clearance():
    b = fb.load_bearing("7014C-DB")
    n = 3
    loads = np.array([[1000.0, 0, 800.0, 0, 0], [500.0, 200.0, -300.0, 0, 0], [2000.0, 0, 0, 0, 0]])
    rL = np.array([[-0.002, -0.002], [0.0, 0.0], [-0.004, -0.004]])
    r = fb.solve_many(b, loads, speed=12000.0, radial_clearance=rL)
    for i in range(n):
        _assert_case_equals(r, i, fb.solve_many(b.with_rows(radial_clearance=float(rL[i, 0])), loads[i:i + 1],
                                                speed=12000.0))


def test_a_case_outside_the_model_is_flagged_not_solved():
    b = fb.Bearing.preset("gunduz2013", "DB")
    A0cos = b.rows[0].groove_center_distance * np.cos(np.radians(b.rows[0].contact_angle))
    rL = np.array([[0.001, 0.001], [A0cos, A0cos], [-0.2, -0.2]])  # fine, centres crossed, preload beyond 10 % A0
    r = fb.solve_many(b, _loads(3, 5), radial_clearance=rL)
    assert [fb.status.describe(s) for s in r.status] == ["converged", "outside_model", "outside_model"]
    assert np.isnan(r.K[1:]).all() and np.isfinite(r.K[0]).all()


def test_a_mounted_bearing_takes_each_case_speed():
    b = bearing_7014("DB", {"shaft_interference": 0.005, "inner_ring_temperature": 45.0,
                            "outer_ring_temperature": 35.0})
    speeds = np.array([0.0, 6000.0, 12000.0, 6000.0])
    loads = _loads(4, 6, scale=1500.0)
    r = fb.solve_many(b, loads, speed=speeds)
    assert fb.status.converged_mask(r.status).all()
    for i, s in enumerate(speeds):
        _assert_case_equals(r, i, fb.solve_many(operating_bearing(b, s)[0], loads[i:i + 1], speed=s))
    assert not np.array_equal(r.K[0], r.K[2])  # the clearance moved with speed


def test_a_mounted_bearing_takes_each_case_temperatures():
    b = bearing_6205()
    inner = np.array([20.0, 50.0, 80.0])
    loads = np.array([[2000.0, 0, 0, 0, 0]] * 3)
    r = fb.solve_many(b, loads, temperatures={"inner_ring_temperature": inner})
    for i, t in enumerate(inner):
        twin = replace(b, mounting=replace(b.mounting, inner_ring_temperature=float(t)))
        _assert_case_equals(r, i, fb.solve_many(operating_bearing(twin, 0.0)[0], loads[i:i + 1]))
    assert r.K[2, 0, 0] > r.K[1, 0, 0] > r.K[0, 0, 0]  # a warmer inner ring takes up clearance: stiffer


def test_operating_rows_mounts_each_distinct_point_once_and_marks_the_impossible():
    b = bearing_6205()
    rL, d0, notes = operating_rows(b, [0.0, 0.0, 3000.0], {"inner_ring_temperature": [50.0, 50.0, 50.0]})
    assert rL.shape == (3, 1) and np.array_equal(rL[0], rL[1]) and rL[0, 0] != rL[2, 0]
    op = operating_bearing(b, 3000.0)[0]
    assert rL[2, 0] == op.rows[0].radial_clearance and d0[2, 0] == op.rows[0].axial_preload
    hot, _, notes = operating_rows(b, [0.0], {"inner_ring_temperature": [400.0]})  # a hot ring: a big interference
    assert np.isnan(hot).all() and any("bearing.mounting" in n for n in notes)


@pytest.mark.parametrize("kwargs, message", [
    ({"radial_clearance": np.zeros((3, 3))}, r"radial_clearance must be one number, one per row \(2\)"),
    ({"radial_clearance": [np.nan, 0.0]}, "radial_clearance must be finite"),
    ({"temperatures": {"inner_ring_temperature": 50.0}}, r"temperatures need \[bearing.mounting\]"),
])
def test_bad_per_case_values_name_the_field(kwargs, message):
    with pytest.raises(ValueError, match=message):
        fb.solve_many(fb.Bearing.preset("gunduz2013", "DB"), _loads(4, 7), **kwargs)


def test_a_mounted_bearing_refuses_a_typed_clearance():
    with pytest.raises(ValueError, match=r"radial_clearance is set by \[bearing.mounting\]"):
        fb.solve_many(bearing_6205(), _loads(2, 8), radial_clearance=0.0)


# -- load maps whose cases vary the bearing ----------------------------------------------------------------------
def _thermal_config(loadmap_spec):
    from fastbearing.model.bearing_file import read_toml

    doc = read_toml(ROOT / "fastbearing/catalogue/7014C-DB.toml")
    doc["bearing"]["mounting"] = {"shaft_fit": "js5", "housing_fit": "H7", "outer_ring_temperature": 25.0}
    doc["loadmap"] = loadmap_spec
    return doc


def test_a_map_over_speed_and_temperature_is_each_operating_bearing_line_by_line(tmp_path):
    import h5py

    spec = {"speed": [0.0, 12000.0], "inner_ring_temperature": [25.0, 45.0], "Fx": 300.0,
            "Fz": {"start": 0.0, "stop": 1500.0, "num": 4}}
    out = fb.loadmap(_thermal_config(spec), tmp_path / "thermal.h5", progress=False)
    with h5py.File(out, "r") as fh:
        assert list(fh["K"].dims[0].keys()) == ["inner_ring_temperature"]
        assert fh["inner_ring_temperature"].attrs["units"] == "degC"
        assert fh.attrs["operating_line"].startswith("each case at its own operating clearance: ")
        assert fh.attrs["operating_line"].endswith("over 4 speeds and temperatures")
        data = {k: fh[k][()] for k in ("K", "q", "status", "operating_diametral_clearance", "operating_axial_preload")}
    assert data["K"].shape == (2, 2, 4, 5, 5) and fb.status.converged_mask(data["status"]).all()
    from fastbearing.jobs.loadmap import read_config

    mounted = read_config(_thermal_config(spec)).mounted
    for t, temperature in enumerate((25.0, 45.0)):
        for s, speed in enumerate((0.0, 12000.0)):
            twin = replace(mounted, mounting=replace(mounted.mounting, inner_ring_temperature=temperature))
            op = operating_bearing(twin, speed)[0]
            assert np.all(data["operating_diametral_clearance"][t, s] == 2.0 * op.rows[0].radial_clearance)
            assert list(data["operating_axial_preload"][t, s, 0]) == [r.axial_preload for r in op.rows]
    # one line (a continuation run along Fz) against a map of that operating bearing: bit for bit
    twin = replace(mounted, mounting=replace(mounted.mounting, inner_ring_temperature=45.0))
    line = {"speed": 12000.0, "Fx": 300.0, "Fz": {"start": 0.0, "stop": 1500.0, "num": 4}}
    doc = _thermal_config(line)
    doc["bearing"]["mounting"]["inner_ring_temperature"] = 45.0
    single = fb.loadmap(doc, tmp_path / "line.h5", progress=False)
    with h5py.File(single, "r") as fh:
        assert np.array_equal(fh["K"][()], data["K"][1, 1]) and np.array_equal(fh["q"][()], data["q"][1, 1])
    # a warmer inner ring takes up clearance: the pair is stiffer axially at no load
    assert data["K"][1, 0, 0, 2, 2] > data["K"][0, 0, 0, 2, 2]


def test_a_temperature_axis_needs_mounting_and_a_grid(tmp_path):
    from fastbearing.model.bearing_file import read_toml

    doc = read_toml(ROOT / "fastbearing/catalogue/7014C-DB.toml")
    doc["loadmap"] = {"inner_ring_temperature": [20.0, 40.0], "Fz": 100.0}
    with pytest.raises(ValueError, match=r"loadmap.inner_ring_temperature needs \[bearing.mounting\]"):
        fb.loadmap(doc, tmp_path / "x.h5", progress=False)
    doc = _thermal_config({"inner_ring_temperature": [20.0, -300.0], "Fz": 100.0})
    with pytest.raises(ValueError, match=r"loadmap.inner_ring_temperature\[1\] must be >= -273.15"):
        fb.loadmap(doc, tmp_path / "x.h5", progress=False)
