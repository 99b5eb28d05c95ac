"""fastbearing montecarlo (issue 44 item 6): tolerance zones sampled, every sample solved at its own operating
clearance; reproducible by seed, resumable, summarised (percentiles against the closed form of a linear case,
rank-correlation sensitivities)."""

import json
from dataclasses import replace

import h5py
import numpy as np
import pytest

import fastbearing as fb
from fastbearing.jobs import montecarlo as mc
from fastbearing.jobs import runner as jobs
from fastbearing.model.mounted import operating_bearing
from fastbearing.model.tolerance_samples import DRAW_BLOCK, draw, operating_clearances

from conftest import cli_run
from test_mounting import TOML_6205

#: The shipped example's case (3000 rpm, warm rings) with few samples: the map kernels at speed with per-case values.
CASE = """
[montecarlo]
samples = {samples}
seed = 7
Fx = 2000.0
Fz = 300.0
speed = 3000.0
life = true
"""


def config(tmp_path, samples=400, text=TOML_6205, case=CASE):
    path = tmp_path / "mc.toml"
    path.write_text(text + case.format(samples=samples))
    return path


def _datasets(path):
    with h5py.File(path, "r") as fh:
        return {k: fh[k][()] for k in fh if isinstance(fh[k], h5py.Dataset)}


def test_each_sample_is_its_drawn_operating_clearance_solved(tmp_path):
    cfg = mc.read_config(config(tmp_path))
    out, summary = mc.montecarlo(cfg, tmp_path / "mc.h5", progress=False)
    data = _datasets(out)
    samples = draw(cfg.zones, cfg.samples, cfg.seed)
    for name, values in samples.items():
        assert np.array_equal(data[name], values), name
    Pd = operating_clearances(cfg.bearing, samples, cfg.speed)
    assert np.array_equal(data["operating_diametral_clearance"][:, 0], Pd)
    assert fb.status.converged_mask(data["status"]).all() and summary["converged"] == cfg.samples
    # a sample is the bearing with its operating clearance, solved (to the solver's tolerance: samples are
    # continuation runs, a single solve starts cold)
    op = operating_bearing(cfg.bearing, cfg.speed)[0]
    for i in (0, 17, 211, 399):
        twin = op.with_rows(radial_clearance=0.5 * Pd[i])
        r = fb.solve(twin, list(cfg.loads), speed=cfg.speed)
        assert np.allclose(data["K"][i], r.K, rtol=1e-7, atol=1e-3 * np.abs(r.K).max() * 1e-6)
        assert np.allclose(data["q"][i], r.q, rtol=1e-8, atol=1e-12)


def test_the_api_names_it_beside_loadmap():
    assert fb.montecarlo is mc.montecarlo and "montecarlo" in dir(fb)


def test_the_same_seed_gives_the_same_file_on_any_thread_count(tmp_path):
    path = config(tmp_path)
    a = _datasets(mc.montecarlo(path, tmp_path / "a.h5", progress=False, threads=1)[0])
    b = _datasets(mc.montecarlo(path, tmp_path / "b.h5", progress=False, threads=2)[0])
    assert a.keys() == b.keys()
    for k in a:
        assert np.array_equal(a[k], b[k], equal_nan=a[k].dtype.kind == "f"), k
    other = config(tmp_path, case=CASE.replace("seed = 7", "seed = 8"))
    c = _datasets(mc.montecarlo(other, tmp_path / "c.h5", progress=False)[0])
    assert not np.array_equal(a["bore_deviation"], c["bore_deviation"])


def test_an_interrupted_run_resumes_to_the_same_file(tmp_path):
    cfg = mc.read_config(config(tmp_path, samples=2 * DRAW_BLOCK + 100))
    reference = _datasets(mc.montecarlo(cfg, tmp_path / "ref.h5", progress=False)[0])
    job = mc.job(cfg)
    calls = []

    def interrupted(inputs, res, first, stop):
        if first > 0:
            raise KeyboardInterrupt
        calls.append(first)
        job.compute(inputs, res, first, stop)

    out = tmp_path / "run.h5"
    with pytest.raises(KeyboardInterrupt):
        jobs.run(replace(job, compute=interrupted), out, threads=1, progress=False)
    assert calls == [0] and not out.exists()
    resumed = _datasets(mc.montecarlo(cfg, out, resume=True, progress=False)[0])
    for k in reference:
        assert np.array_equal(reference[k], resumed[k], equal_nan=reference[k].dtype.kind == "f"), k


# A clearance range and typed interferences: the operating clearance is the drawn one shifted by the fits'
# fixed share, so its percentiles are the uniform distribution's (closed form) and its rank correlation 1.
LINEAR = TOML_6205.replace('diametral_clearance = "CN"', "diametral_clearance = [0.004, 0.024]").replace(
    'shaft_fit = "k5"\nhousing_fit = "H7"', "shaft_interference = 0.01\nhousing_interference = 0.0")


def test_percentiles_of_a_linear_case_match_the_closed_form(tmp_path):
    n = 4000
    cfg = mc.read_config(config(tmp_path, samples=n, text=LINEAR))
    assert [z.name for z in cfg.zones] == ["unmounted_diametral_clearance"]
    out, summary = mc.montecarlo(cfg, tmp_path / "lin.h5", progress=False)
    op, budget = operating_bearing(cfg.bearing, cfg.speed)
    shift = budget["rows"][0]["unmounted_diametral_clearance"] - budget["rows"][0]["operating_diametral_clearance"]
    lo, hi = 0.004 - shift, 0.024 - shift
    se = (hi - lo) * 0.5 / np.sqrt(n)  # the largest standard error of a sample quantile of U(lo, hi)
    for p, value in summary["percentiles"]["operating_diametral_clearance_mm"].items():
        assert abs(value - (lo + float(p) / 100.0 * (hi - lo))) < 4.0 * se, p
    assert abs(summary["p_clearance_negative"] - np.clip(-lo / (hi - lo), 0.0, 1.0)) < 4.0 * np.sqrt(0.25 / n)
    (name, rho), = summary["sensitivity"]["operating_diametral_clearance_mm"]
    assert name == "unmounted_diametral_clearance" and rho == pytest.approx(1.0, abs=1e-6)
    # under Fz = 300 N more clearance means larger contact angles: kzz rises with it, monotonically (rho = 1)
    assert summary["sensitivity"]["kzz_N_per_mm"][0][1] > 0.99
    with h5py.File(out, "r") as fh:
        assert json.loads(fh.attrs["summary_json"]) == summary


def test_cli_prints_the_summary_and_json(tmp_path):
    path = config(tmp_path, samples=300)
    run = cli_run("montecarlo", str(path), "-o", str(tmp_path / "cli.h5"), "--no-progress")
    assert run.returncode == 0, run.stderr
    assert "300 samples: 300 converged" in run.stdout and "P(operating clearance < 0)" in run.stdout
    assert "sensitivity (Spearman rank correlation" in run.stdout
    again = cli_run("montecarlo", str(path), "-o", str(tmp_path / "cli.h5"), "--no-progress", "--json",
                    "--overwrite")
    summary = json.loads(again.stdout)
    assert set(summary["percentiles"]) == {"operating_diametral_clearance_mm", "kxx_N_per_mm", "kzz_N_per_mm",
                                           "L10r_million_revolutions"}
    refused = cli_run("montecarlo", str(path), "-o", str(tmp_path / "cli.h5"), "--no-progress")
    assert refused.returncode == 2 and "exists" in refused.stderr


@pytest.mark.parametrize("case, message", [
    (CASE.replace("samples = {samples}", "samples = 0"), r"montecarlo.samples must be"),
    (CASE.replace("Fx = 2000.0", "Fx = [1.0, 2.0]"), r"montecarlo.Fx is one number \(N\)"),
    (CASE + "colour = 1\n", r"unknown key\(s\) \['colour'\]"),
    (CASE + "inner_ring_temperature = -300.0\n", r"montecarlo.inner_ring_temperature must be >= -273.15"),
])
def test_bad_config_names_the_field(tmp_path, case, message):
    with pytest.raises(ValueError, match=message):
        mc.read_config(config(tmp_path, case=case))


def test_a_bearing_without_mounting_or_zones_is_refused(tmp_path):
    plain = TOML_6205.split("[bearing.mounting]")[0].replace('"CN"', "0.01")
    with pytest.raises(ValueError, match=r"bearing.mounting is needed by montecarlo"):
        mc.read_config(config(tmp_path, text=plain))
    typed = LINEAR.replace("[0.004, 0.024]", "0.01")
    with pytest.raises(ValueError, match="has no tolerance zone to sample"):
        mc.read_config(config(tmp_path, text=typed))


def test_cuda_without_a_gpu_says_what_is_missing_before_any_work(tmp_path, monkeypatch):
    from fastbearing.engine import device

    monkeypatch.delenv("NUMBA_ENABLE_CUDASIM", raising=False)
    try:
        device.require_cuda()
        pytest.skip("a usable GPU: montecarlo runs there (tests/cuda_simulated.py checks it against the CPU)")
    except device.CudaUnavailable:
        pass
    with pytest.raises(device.CudaUnavailable):
        mc.montecarlo(config(tmp_path), tmp_path / "x.h5", device="cuda", progress=False)
    assert not (tmp_path / "x.h5").exists() and not (tmp_path / "x.h5.part").exists()
    with pytest.raises(ValueError, match="a Dask run on GPU workers is not built"):
        mc.montecarlo(config(tmp_path), tmp_path / "x.h5", device="cuda", progress=False, client=object())


def test_a_dask_run_gives_the_local_file_and_the_job_pickles(tmp_path):
    import pickle

    distributed = pytest.importorskip("distributed")
    path = config(tmp_path)
    job = mc.job(mc.read_config(path))
    assert pickle.loads(pickle.dumps(job.compute)).args[0] == job.compute.args[0]  # what Dask sends the workers
    local = _datasets(mc.montecarlo(path, tmp_path / "local.h5", progress=False)[0])
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        remote, summary = mc.montecarlo(path, tmp_path / "dask.h5", progress=False, client=client)
    remote = _datasets(remote)
    for k in local:
        assert np.array_equal(local[k], remote[k], equal_nan=local[k].dtype.kind == "f"), k
    assert summary["converged"] == 400


def test_a_zarr_store_holds_the_samples_and_the_summary(tmp_path):
    zarr = pytest.importorskip("zarr")
    path = config(tmp_path, samples=100)
    local = _datasets(mc.montecarlo(path, tmp_path / "local.h5", progress=False)[0])
    store, summary = mc.montecarlo(path, tmp_path / "mc.zarr", progress=False)
    group = zarr.open_group(str(store), mode="r")
    assert json.loads(group.attrs["summary_json"]) == summary
    assert np.array_equal(group["operating_diametral_clearance"][...], local["operating_diametral_clearance"])
    assert np.array_equal(group["K"][...], local["K"])


def test_each_ball_takes_its_own_diameter(tmp_path):
    from fastbearing.engine.kernel import ball_loop
    from fastbearing.engine.schema import A0, GAP2
    from fastbearing.model.bearing import without_mirror_half

    case = CASE.replace("speed = 3000.0", "speed = 0.0") + "ball_diameter_variation = 0.002\n"
    cfg = mc.read_config(config(tmp_path, samples=60, case=case))
    out, summary = mc.montecarlo(cfg, tmp_path / "balls.h5", progress=False)
    data = _datasets(out)
    sizes = data["ball_diameter_deviation"]
    assert sizes.shape == (60, 9) and np.abs(sizes).max() <= 0.001 and np.ptp(sizes) > 0.0015
    assert np.array_equal(sizes, draw(cfg.zones, 60, cfg.seed)["ball_diameter_deviation"])
    assert fb.status.converged_mask(data["status"]).all()
    op = operating_bearing(cfg.bearing, 0.0)[0]
    for i in (0, 31, 59):
        # at each sample's q, a ball table made here from the rule (the groove centres are the rings': a ball
        # bigger by s has A0 - s) carries the load, with the file's Kb
        b = op.with_rows(radial_clearance=0.5 * data["operating_diametral_clearance"][i, 0])
        table = without_mirror_half(b.ball_table()).copy()
        a0, s = table[A0].copy(), sizes[i]
        table[A0] = a0 - s
        table[GAP2] = table[GAP2] + s * (2.0 * a0 - s)
        f, K = np.empty(5), np.empty((5, 5))
        ball_loop(data["q"][i], b.ball_set(mirror=False)._replace(balls=table), f, K, None, None)
        assert np.allclose(f, cfg.loads, rtol=0.0, atol=1e-6 * 2000.0), (i, f)
        assert np.allclose(K, data["K"][i], rtol=1e-9, atol=1e-9 * np.abs(K).max())
    # the balls' sizes move the answer: the same samples with nominal balls give another Kb
    plain = _datasets(mc.montecarlo(config(tmp_path, samples=60, case=case.replace("0.002", "0.0")),
                                    tmp_path / "plain.h5", progress=False)[0])
    assert "ball_diameter_deviation" not in plain
    assert np.array_equal(plain["operating_diametral_clearance"], data["operating_diametral_clearance"])
    assert not np.allclose(plain["K"], data["K"], rtol=1e-4)


@pytest.mark.parametrize("case, message", [
    (CASE + "ball_diameter_variation = 0.001\n", r"ball_diameter_variation needs speed = 0"),
    (CASE + "ball_diameter_variation = -0.001\n", r"montecarlo.ball_diameter_variation must be >= 0"),
])
def test_ball_diameter_variation_refusals(tmp_path, case, message):
    with pytest.raises(ValueError, match=message):
        mc.read_config(config(tmp_path, case=case))
