"""Local defects in ball-passage tables over shaft revolutions (model/defects.py, jobs/passage.py; docs/model.md,
"Local defects and fault frequencies"): a defect of depth 0 is no defect, bit for bit; an element centred in a
defect deeper than its approach carries nothing; an inner-race defect puts a line at BPFI into the spectrum of
kxx (absent without it) and an outer-race one strengthens BPFO; at speed and on roller rows too; the thread
count changes nothing; bad defects are refused naming the field."""

import math
from pathlib import Path

import h5py
import numpy as np
import pytest

import fastbearing as fb
from fastbearing.model.defects import Defect, Kinematics, element_depths

DATA = Path(__file__).parents[1] / "fastbearing" / "catalogue"
BALL = str(DATA / "6305.toml")


def _table(tmp_path, defects=None, name="t", bearing=BALL, threads=None, **passage):
    spec = {"given": "load", "Fx": 2000.0, "positions": 64, "revolutions": 4, "harmonics": 40, "element_loads": True,
            **passage}
    if defects is not None:
        spec["defects"] = defects
    out = fb.passage({"bearing": bearing, "passage": spec}, tmp_path / f"{name}.h5", progress=False, threads=threads)
    with h5py.File(out) as h:
        return {k: h[k][...] for k in ("K", "q", "status", "element_load", "K_amplitude", "order")}, dict(h.attrs)


def test_a_defect_of_depth_zero_is_no_defect_bit_for_bit(tmp_path):
    none, _ = _table(tmp_path)
    for race, extra in (("outer", {}), ("inner", {}), ("ball", {"element": 3})):
        zero, _ = _table(tmp_path, [{"race": race, "angle": 10.0, "width": 3.0, "depth": 0.0, **extra}], race)
        for key in ("K", "q", "element_load"):
            assert np.array_equal(zero[key], none[key]), (race, key)


def test_an_element_centred_in_a_deep_defect_carries_nothing(tmp_path):
    """An outer-race spall at 0 deg deeper than any ball's approach: the ball at 0 deg at position 0 (the 6305's
    ball 0) carries 0 N, while without the defect it carries the most."""
    none, _ = _table(tmp_path)
    deep, _ = _table(tmp_path, [{"race": "outer", "angle": 0.0, "width": 2.0, "depth": 0.2}], "deep")
    assert none["element_load"][0, 0, 0] == none["element_load"][0, 0].max() > 0
    assert deep["element_load"][0, 0, 0] == 0.0
    assert (deep["status"] == 0).all()


def test_race_defects_put_their_pass_frequency_into_the_spectrum_of_kxx(tmp_path):
    """Over 4 revolutions harmonic h is order h/4. An inner-race spall: a line at BPFI (4.43 for the 6305) that
    the defect-free table does not have; an outer-race spall: BPFO (2.57), already a line of the passing balls,
    grows many times."""
    none, attrs = _table(tmp_path)
    inner, _ = _table(tmp_path, [{"race": "inner", "angle": 0.0, "width": 2.0, "depth": 0.05}], "inner")
    outer, _ = _table(tmp_path, [{"race": "outer", "angle": 0.0, "width": 2.0, "depth": 0.05}], "outer")

    def line(result, name):
        k = int(round(attrs[f"fault_frequency_{name}_order"] * 4))
        assert abs(result["order"][k] - attrs[f"fault_frequency_{name}_order"]) <= 0.125
        return result["K_amplitude"][0, k - 1:k + 2, 0, 0].max()

    assert line(inner, "BPFI") > 20 * line(none, "BPFI")
    assert line(outer, "BPFO") > 5 * line(none, "BPFO")


def test_defects_at_speed_and_on_roller_rows(tmp_path):
    spindle = str(DATA / "7014C-DB.toml")
    none, _ = _table(tmp_path, bearing=spindle, name="s0", Fz=500.0, speed=12000.0, positions=16, revolutions=1)
    ball, _ = _table(tmp_path, [{"race": "ball", "element": 0, "angle": 0.0, "width": 2.0, "depth": 0.02}],
                     bearing=spindle, name="s1", Fz=500.0, speed=12000.0, positions=16, revolutions=1)
    assert (ball["status"] == 0).all()
    assert ball["element_load"][0, 0, 0] < none["element_load"][0, 0, 0]  # ball 0 meets its spall at position 0
    roller = str(DATA / "NU205.toml")
    r0, _ = _table(tmp_path, bearing=roller, name="r0", positions=16, revolutions=1)
    r1, _ = _table(tmp_path, [{"race": "outer", "angle": 0.0, "width": 4.0, "depth": 0.1}], bearing=roller,
                   name="r1", positions=16, revolutions=1)
    assert r0["element_load"][0, 0, 0] > 0 and r1["element_load"][0, 0, 0] == 0.0


def test_a_table_with_defects_does_not_depend_on_the_thread_count(tmp_path):
    defects = [{"race": "inner", "angle": 30.0, "width": 1.5, "depth": 0.03, "profile": "half_sine"}]
    one, _ = _table(tmp_path, defects, "one", threads=1)
    two, _ = _table(tmp_path, defects, "two", threads=2)
    assert np.array_equal(one["K"], two["K"]) and np.array_equal(one["element_load"], two["element_load"])


def test_where_a_defect_sits_follows_its_ring_and_its_ball():
    """An outer-race defect stays put with the inner ring turning; an inner-race one turns with the shaft; a
    ball's meets the outer race at its spin angle and the inner half a spin later; the half-sine profile."""
    kin = Kinematics(10.0, 50.0, 0.0, "inner", 0.4, 2.4)
    psi = np.array([0.0, math.pi / 2])
    outer = Defect("outer", 0.0, 2.0, 0.01)
    inner = Defect("inner", 0.0, 2.0, 0.01)
    assert element_depths((outer,), kin, psi, 1.0)[1].tolist() == [0.01, 0.0]
    assert element_depths((inner,), kin, psi, math.pi / 2)[0].tolist() == [0.0, 0.01]
    ball = Defect("ball", 0.0, 2.0, 0.01, element=1)
    half_spin = math.pi / kin.spin_order
    assert element_depths((ball,), kin, psi, 0.0)[1].tolist() == [0.0, 0.01]
    assert element_depths((ball,), kin, psi, half_spin)[0].tolist() == [0.0, 0.01]
    bump = Defect("outer", 0.0, 2.0, 0.01, "half_sine")
    assert bump.profile_depth(np.array([0.0, 0.5, 1.0])) == pytest.approx([0.01, 0.01 * math.cos(math.pi / 4), 0.0])


@pytest.mark.parametrize("defect,message", [
    ({"race": "cage", "width": 1.0, "depth": 0.01}, r"defects\[0\]\.race"),
    ({"race": "outer", "width": 0.0, "depth": 0.01}, r"defects\[0\]\.width"),
    ({"race": "outer", "width": 1.0, "depth": -0.01}, r"defects\[0\]\.depth"),
    ({"race": "ball", "width": 1.0, "depth": 0.01}, r"defects\[0\]\.element is required"),
    ({"race": "ball", "element": 99, "width": 1.0, "depth": 0.01}, r"defects\[0\]\.element"),
    ({"race": "outer", "width": 1.0, "depth": 0.01, "profile": "square"}, r"defects\[0\]\.profile"),
])
def test_bad_defects_are_refused_naming_the_field(tmp_path, defect, message):
    with pytest.raises(ValueError, match=message):
        _table(tmp_path, [defect], "bad")
    assert not (tmp_path / "bad.h5").exists()


def test_the_pictures_mark_the_defect_passes_and_the_spectrum_reads_in_orders(tmp_path):
    """The passage picture over revolutions marks each pass of an outer-race spall, every 1/BPFO revolutions
    (the first where a ball first reaches it); the spectrum takes orders of the shaft speed with a speed too."""
    pytest.importorskip("matplotlib")
    from fastbearing.report import plot

    spec = {"given": "load", "Fx": 2000.0, "positions": 64, "revolutions": 2, "speed": 1800.0, "harmonics": 40,
            "defects": [{"race": "outer", "angle": 10.0, "width": 1.0, "depth": 0.05}]}
    out = fb.passage({"bearing": BALL, "passage": spec}, tmp_path / "m.h5", progress=False)
    ds = fb.open_dataset(out)
    (label, turns), = plot.defect_passes(ds)
    bpfo = float(ds.attrs["fault_frequency_BPFO_order"])
    assert label == "outer-race defect passed" and np.allclose(np.diff(turns), 1 / bpfo)
    z = 7  # the 6305's balls, the first at 0 deg: it reaches the spall at 10 deg after 10 deg of cage travel
    assert turns[0] == pytest.approx(math.radians(10.0) / (2 * math.pi / z) / bpfo)
    fig = plot.plot_passage(out, "kxx", x="revolutions")
    assert any(t.get_text() == label for t in fig.axes[0].get_legend().get_texts())
    fig = plot.plot_spectrum(out, "kxx", normalise="none", orders=True)
    assert "order of the shaft speed" in fig.axes[-1].get_xlabel()


def test_defects_on_four_point_rows_are_refused_for_now(tmp_path):
    """Each four-point ball meets a race on two contact pairs: not modelled yet, so refused in one line (at
    speed a defect on pair -'s column was silently dropped)."""
    with pytest.raises(ValueError,
                       match=r"defects\[0\]\.race is not modelled on rows of four_point_ball elements .*no local defects"):
        _table(tmp_path, [{"race": "outer", "width": 1.0, "depth": 0.01}], "qj", bearing=str(DATA / "QJ210.toml"))


def test_a_ball_defect_on_a_roller_bearing_is_refused_naming_the_rows(tmp_path):
    with pytest.raises(ValueError, match=r"defects\[0\]\.race is not modelled on rows of cylindrical_roller"):
        _table(tmp_path, [{"race": "ball", "element": 0, "width": 1.0, "depth": 0.01}], "r",
               bearing=str(DATA / "NU205.toml"))
