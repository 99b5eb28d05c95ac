"""Rigid shafts on several bearings: the paper's Fig. 2 / Table 2 set-up, equilibrium,
natural frequencies (Table 5's lesson), config files."""

import math

import numpy as np
import pytest

import fastbearing as fb
from fastbearing.analysis import shaft as sh

SINGLE = fb.Bearing.preset("gunduz2013", "single")
FIG2_LOAD = sh.PointLoad(0.0, (1000.0, 0.0, 3000.0))


def fig2_shaft(arrangement):
    """Two single rows at z = 64 and 84 mm whose contact directions make the given double row."""
    first, second = {"DB": (1, -1), "DF": (-1, 1), "DT": (1, 1)}[arrangement]
    rows = [SINGLE if d == 1 else sh.mirrored(SINGLE) for d in (first, second)]
    return sh.Shaft(74.0, (sh.MountedBearing(64.0, rows[0]), sh.MountedBearing(84.0, rows[1])), (FIG2_LOAD,))


@pytest.mark.parametrize("arrangement", ["DB", "DF", "DT"])
def test_fig2_two_single_rows_are_the_double_row(arrangement):
    """At the double row's centre the pair's K_system is exactly the double row's Kb (Table 4 load)."""
    result = sh.solve_shaft(fig2_shaft(arrangement))
    double = fb.solve(fb.Bearing.preset("gunduz2013", arrangement), [1000.0, 0.0, 3000.0, 0.0, -74000.0])
    assert result.solution.converged
    np.testing.assert_allclose(result.K_system, double.K, rtol=1e-12, atol=1e-9 * np.abs(double.K).max())
    np.testing.assert_allclose(result.q, double.q, rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("arrangement, tilt_ratio", [("DB", (1.5, 3.0)), ("DF", (0.2, 0.7))])
def test_table2_translation_terms_add_tilt_terms_do_not(arrangement, tilt_ratio):
    """Table 2's lesson: kxx, kyy, kzz of the pair are the sum of each row's own Kb; the tilt terms
    are not (DB about 2x the naive sum, DF about 0.4x), because the offsets enter the tilt."""
    result = sh.solve_shaft(fig2_shaft(arrangement))
    naive = sum(b.K for b in result.bearings)
    np.testing.assert_allclose(np.diag(result.K_system)[:3], np.diag(naive)[:3], rtol=1e-12)
    ratio = np.diag(result.K_system)[3:] / np.diag(naive)[3:]
    assert np.all((tilt_ratio[0] < ratio) & (ratio < tilt_ratio[1])), ratio


def test_equilibrium_reactions_balance_the_loads():
    """Three bearings, two loads: reactions carried to the reference add up to the external load."""
    db = fb.Bearing.preset("gunduz2013", "DB")
    shaft = sh.Shaft(50.0, (sh.MountedBearing(0.0, db), sh.MountedBearing(100.0, SINGLE),
                            sh.MountedBearing(180.0, sh.mirrored(SINGLE))),
                     (sh.PointLoad(40.0, (2000.0, -500.0, 1500.0), (1000.0, -3000.0)),
                      sh.PointLoad(140.0, (-800.0, 1200.0, 0.0))))
    result = sh.solve_shaft(shaft)
    assert result.solution.converged
    total = sum(sh.transfer(b.position - shaft.reference).T @ b.reaction for b in result.bearings)
    np.testing.assert_allclose(total, shaft.external_load(), rtol=1e-9, atol=1e-6)
    # each bearing's local displacement is the rigid-body motion of the shaft at its centre
    for b in result.bearings:
        np.testing.assert_allclose(b.q, sh.transfer(b.position - 50.0) @ result.q, rtol=1e-14, atol=1e-18)
    # and K_system is the sum of the transferred bearing stiffnesses
    K_sum = sum(sh.transfer(b.position - 50.0).T @ b.K @ sh.transfer(b.position - 50.0) for b in result.bearings)
    np.testing.assert_allclose(result.K_system, K_sum, rtol=1e-9, atol=1e-9 * np.abs(K_sum).max())
    # stiffness seen elsewhere is a congruence: T^T K_at(p) T = K_system
    K_p = sh.stiffness_at(result, 120.0)
    T = sh.transfer(120.0 - 50.0)
    np.testing.assert_allclose(T.T @ K_p @ T, result.K_system, rtol=1e-9, atol=1e-6 * np.abs(K_sum).max())


def test_load_transfer_sign_matches_the_paper():
    """Fx = 1 kN at 74 mm on the -z side of the bearing centre gives My = -74 000 N*mm."""
    np.testing.assert_allclose(sh.load_at_reference((1000.0, 0.0, 0.0), (0.0, 0.0), -74.0),
                               [1000.0, 0.0, 0.0, 0.0, -74000.0])


def test_two_dof_eigenvalues_by_hand():
    """A uniform rigid bar on two translational springs: the textbook bounce and pitch frequencies."""
    k1, k2, L, m = 2.0e5, 2.0e5, 300.0, 10.0  # N/mm, mm, kg
    J = m * L**2 / 12  # kg*mm^2 about the centre
    K = np.zeros((5, 5))
    for k, z in ((k1, -L / 2), (k2, L / 2)):
        Kb = np.zeros((5, 5))
        Kb[0, 0] = Kb[1, 1] = Kb[2, 2] = k
        T = sh.transfer(z)
        K += T.T @ Kb @ T
    M = sh.Inertia(m, J, J, 0.0).matrix(0.0)
    modes = sh.natural_frequencies(K, M)
    bounce = math.sqrt(2 * k / (m * 1e-3)) / (2 * math.pi)
    pitch = math.sqrt(k * L**2 / 2 / (J * 1e-3)) / (2 * math.pi)
    # two bounce modes (x, y), two pitch modes, one axial (2k along z)
    np.testing.assert_allclose(sorted(modes.frequencies), sorted([bounce, bounce, pitch, pitch, bounce]), rtol=1e-10)


def shaft_on_db(radial):
    db = fb.Bearing.preset("gunduz2013", "DB")
    return sh.Shaft(74.0, (sh.MountedBearing(74.0, db),), (sh.PointLoad(0.0, (radial, 0.0, 3000.0)),),
                    sh.Inertia(20.0, 3.0e5, 3.0e5, 74.0))


def test_table5_lesson_pairs_split_under_radial_load_and_coupling_matters():
    """No radial load: the x/y pairs coincide; a small radial load separates them; dropping Kb's
    coupling terms (diagonal only) moves the frequencies."""
    axial = sh.solve_shaft(shaft_on_db(0.0))
    M = shaft_on_db(0.0).inertia.matrix(74.0)
    f0 = sh.natural_frequencies(axial.K_system, M).frequencies
    assert f0[0] == pytest.approx(f0[1], rel=1e-8) and f0[3] == pytest.approx(f0[4], rel=1e-8)
    loaded = sh.solve_shaft(shaft_on_db(200.0))
    f1 = sh.natural_frequencies(loaded.K_system, M).frequencies
    assert abs(f1[1] - f1[0]) > 1e-3 * f1[0] or abs(f1[4] - f1[3]) > 1e-3 * f1[3]
    fd = sh.natural_frequencies(loaded.K_system, M, diagonal_only=True).frequencies
    assert np.max(np.abs(fd - f1) / f1) > 0.02


@pytest.mark.parametrize("body, words", [
    ("reference = 74.0\n", "at least one bearing"),
    ('reference = 74.0\nfoo = 1\n', r"shaft has unknown key\(s\) \['foo'\]"),
    ('[[shaft.bearings]]\nbearing = "x.toml"\n', r"shaft.bearings\[0\] is missing required key\(s\) \['position'\]"),
    ('[[shaft.bearings]]\nposition = 0.0\nbearing = 3\n', "must be a bearing file name or a \\[bearing\\] table"),
    ('bearings = [1, 2]\n', r"shaft.bearings\[0\] must be a table, not int"),
    ('reference = 0.0\nloads = [5]\n', r"shaft.loads\[0\] must be a table, not int"),
    ('[[shaft.bearings]]\nposition = 0.0\nmirrored = "false"\n[shaft.bearings.bearing]\npreset = "gunduz2013"\n',
     r"shaft.bearings\[0\].mirrored must be true or false, got 'false'"),
    ('[[shaft.bearings]]\nposition = 0.0\n[shaft.bearings.bearing]\npreset = "gunduz2013"\n[shaft]\n', "not valid TOML"),
    ('[[shaft.bearings]]\nposition = 0.0\nbearing = "missing.toml"\n', "file not found"),
    ('[[shaft.bearings]]\nposition = 0.0\n[shaft.bearings.bearing]\npreset = "gunduz2013"\n'
     '[[shaft.loads]]\nforce = [1.0, 2.0]\n', r"shaft.loads\[0\].force must be a list of 3 items, got 2"),
    ('[[shaft.bearings]]\nposition = 0.0\n[shaft.bearings.bearing]\npreset = "gunduz2013"\n'
     '[shaft.mass]\nmass = -1.0\ninertia_x = 1.0\ninertia_y = 1.0\n', "shaft.mass.mass must be > 0"),
])
def test_bad_shaft_configs(tmp_path, body, words):
    path = tmp_path / "shaft.toml"
    path.write_text("[shaft]\n" + body if not body.startswith("[[") else "[shaft]\nreference = 0.0\n" + body)
    with pytest.raises(ValueError, match=words):
        sh.read_shaft(path)


@pytest.mark.parametrize("text, words", [("shaft = 5\n", "shaft must be a table, not int"),
                                         ("[shaft]\nreference = 0.0\nmass = 5.0\n", "shaft.mass must be a table"),
                                         ("x = 1\n", r"the shaft config has unknown key\(s\) \['x'\]")])
def test_shaft_config_shapes(tmp_path, text, words):
    path = tmp_path / "shaft.toml"
    path.write_text(text)
    with pytest.raises(ValueError, match=words):
        sh.read_shaft(path)




def test_shaft_config_with_files_and_inline_bearings(tmp_path):
    (tmp_path / "row.toml").write_text('[bearing]\npreset = "gunduz2013"\narrangement = "single"\n')
    path = tmp_path / "shaft.toml"
    path.write_text('[shaft]\nreference = 74.0\n'
                    '[[shaft.bearings]]\nposition = 64.0\nbearing = "row.toml"\n'
                    '[[shaft.bearings]]\nposition = 84.0\nmirrored = true\n'
                    '[shaft.bearings.bearing]\npreset = "gunduz2013"\narrangement = "single"\n'
                    '[[shaft.loads]]\nposition = 0.0\nforce = [1000.0, 0.0, 3000.0]\n')
    shaft = sh.read_shaft(path)
    result = sh.solve_shaft(shaft)
    double = fb.solve(fb.Bearing.preset("gunduz2013", "DB"), [1000.0, 0.0, 3000.0, 0.0, -74000.0])
    np.testing.assert_allclose(result.K_system, double.K, rtol=1e-12, atol=1e-9 * np.abs(double.K).max())


def test_shaft_cli_json_on_the_shipped_example():
    import json
    from pathlib import Path

    from conftest import cli_run

    example = Path(__file__).resolve().parents[1] / "data" / "examples" / "fig2-two-single-rows.toml"
    p = cli_run("shaft", example, "--json")
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout)
    double = fb.solve(fb.Bearing.preset("gunduz2013", "DB"), [1000.0, 0.0, 3000.0, 0.0, -74000.0])
    np.testing.assert_allclose(out["K_system"], double.K, rtol=1e-12, atol=1e-9 * np.abs(double.K).max())
    assert [b["position"] for b in out["bearings"]] == [64.0, 84.0]
    assert len(out["frequencies_hz"]) == 5 and len(out["frequencies_diagonal_only_hz"]) == 5
    bad = cli_run("shaft", "missing.toml")
    assert bad.returncode == 2 and "file not found" in bad.stderr
