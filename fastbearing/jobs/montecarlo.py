"""Tolerance zones sampled (issue 44 item 6): ``fastbearing montecarlo CONFIG -o OUT.h5|.zarr``.

Each sample draws the shaft diameter, the ring bore and OD, the housing bore and the unmounted clearance
uniformly and independently within their zones (model/tolerance_samples.py), gets its operating clearance
and preload from its fits at the case's speed and temperatures, and is solved under the case's load by the
map kernels with its own operating values (contract.CaseBlock.operating). The file holds, per sample, the
sampled inputs, ``operating_diametral_clearance`` and ``operating_axial_preload`` (sample, row), q, f, Kb,
status and (with ``life``) the lives; :func:`summarize` gives percentiles, P(operating clearance < 0) and a
rank-correlation sensitivity ranking, which the run writes into the file's attributes.

Reproducible: sample i is drawn from the generator of its draw block (seed, i // DRAW_BLOCK), and the job's
blocks are the draw blocks whatever ``chunk`` a user would choose, so the same seed gives the same file bit
for bit, resumed or not, on any thread count or Dask cluster. Each continuation run steps from one sample to
the next (the same load, another bearing). Units: N, mm, rad; rpm; deg C.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass, replace
from functools import partial
from pathlib import Path

import numpy as np

from . import runner as jobs
from . import storage
from .. import status as st
from .. import validate
from ..api import solver_settings
from ..dofs import LOAD_NAMES, LOAD_UNITS
from ..engine.sweep import map_sweep
from ..model.bearing import Bearing, check_speed, check_speed_model
from ..model.bearing_file import read_job_config
from ..model.mounted import CASE_TEMPERATURES, preload_shifts
from ..model.tolerance_samples import (DRAW_BLOCK, ZONE_NAMES, Zone, ball_zone, clearance_budget, draw,
                                        interferences, tolerance_zones)
from ..analysis.life import life_table, rating_sources, ratings
from .grid import Axis, CaseSet
from .loadmap import _flag_outside, _iso_lives, block_records, operating_variables, read_life

#: Most samples one run may have.
MAX_SAMPLES = 100_000_000
_KEYS = {"samples", "seed", "speed", "life", "compression", "method", "rtol", "max_iter", "variables", "dtype",
         "ball_diameter_variation"} \
    | set(LOAD_NAMES) | set(CASE_TEMPERATURES)
#: The percentiles of the summary.
PERCENTILES = (1, 5, 50, 95, 99)
#: What a zone's value is, for the file.
ZONE_LONG_NAMES = {"shaft_diameter_deviation": "shaft diameter deviation from the nominal bore",
                   "bore_deviation": "ring bore deviation", "outer_diameter_deviation": "ring outer diameter deviation",
                   "housing_bore_deviation": "housing bore deviation from the nominal outer diameter",
                   "unmounted_diametral_clearance": "unmounted diametral clearance",
                   "ball_diameter_deviation": "ball diameter deviation from the nominal"}


@dataclass(frozen=True)
class MonteCarloConfig:
    """A parsed ``[montecarlo]`` config: the mounted bearing at the case's temperatures, the case (loads in N,
    N*mm; speed in rpm), the zones and how to run."""

    bearing: Bearing
    samples: int
    seed: int
    loads: tuple
    speed: float
    zones: tuple
    life: object
    compression: str
    method: str
    rtol: float | None
    max_iter: int | None
    text: str
    source: Path | None
    fingerprint: str
    variables: tuple | None = None
    dtype: str = "float64"

    @property
    def cases(self) -> CaseSet:
        """One sample dimension; the load and speed constant (scalar coordinates); line length = samples."""
        axes = tuple(Axis(n, np.array([v]), u, False) for n, v, u in zip(LOAD_NAMES, self.loads, LOAD_UNITS))
        speed = Axis("speed", np.array([self.speed]), "rpm", False) if self.speed > 0 else None
        sample = Axis("sample", np.arange(self.samples), "1", True)
        return CaseSet("load", axes=axes, speed=speed, conditions=(sample,), table_dim="sample")


def read_config(config) -> MonteCarloConfig:
    """Parse a Monte Carlo config from a TOML path or a dict; ValueError naming the field."""
    bearing, spec, text, source = read_job_config(config, "montecarlo")
    unknown = sorted(set(spec) - _KEYS)
    if unknown:
        raise ValueError(f"montecarlo: unknown key(s) {unknown}; allowed: {sorted(_KEYS)}")
    if bearing.mounting is None:
        raise validate.FieldError("bearing.mounting", "is needed by montecarlo: its fit classes (shaft_fit, "
                                  "housing_fit) and a clearance group or range are the tolerance zones sampled",
                                  show_value=False)
    samples = validate.integer(spec.get("samples", 10_000), "montecarlo.samples", low=1, high=MAX_SAMPLES)
    seed = validate.integer(spec.get("seed", 0), "montecarlo.seed", low=0)
    loads = []
    for name, unit in zip(LOAD_NAMES, LOAD_UNITS):
        value = spec.get(name, 0.0)
        if isinstance(value, (list, dict)):
            raise validate.FieldError(f"montecarlo.{name}", f"is one number ({unit}): a Monte Carlo run samples one "
                                      "case; run a load map for a grid", value)
        loads.append(validate.number(value, f"montecarlo.{name}", units=unit))
    speed = check_speed(spec.get("speed", 0.0), "montecarlo.speed")
    temperatures = {k: validate.number(spec[k], f"montecarlo.{k}", low=-273.15, units="deg C (absolute zero)")
                    for k in CASE_TEMPERATURES if k in spec}
    if temperatures:
        bearing = replace(bearing, mounting=replace(bearing.mounting, **temperatures))
    zones = tolerance_zones(bearing)
    if spec.get("ball_diameter_variation", 0.0) != 0.0:
        zones += (_ball_zone(bearing, spec["ball_diameter_variation"], speed),)
    if speed > 0:
        try:
            check_speed_model(bearing, speed)
        except validate.FieldError as err:
            raise err.within("montecarlo") from None
    method = spec.get("method", "newton")
    rtol, max_iter = spec.get("rtol"), spec.get("max_iter")
    try:
        solver_settings(bearing, method, rtol, max_iter)
    except validate.FieldError as err:
        raise err.within("montecarlo") from None
    life = read_life(spec.get("life"), "montecarlo.life")
    if life is not None:
        ratings(bearing)
    stored = None
    if "variables" in spec:
        names = validate.array(spec["variables"], "montecarlo.variables", min_length=1)
        stored = tuple(dict.fromkeys(names))
    dtype = validate.choice(spec.get("dtype", "float64"), "montecarlo.dtype", jobs.RESULT_DTYPES)
    compression = validate.choice(spec.get("compression", "none"), "montecarlo.compression", storage.COMPRESSIONS)
    fingerprint = hashlib.sha256(text.encode()).hexdigest()
    return MonteCarloConfig(bearing, samples, seed, tuple(loads), speed, zones, life, compression, method, rtol,
                            max_iter, text, source, fingerprint, stored, dtype)


def _ball_zone(bearing, variation, speed: float) -> Zone:
    """The per-ball diameter zone of ``[montecarlo] ball_diameter_variation`` (mm), where the model takes it."""
    where = "montecarlo.ball_diameter_variation"
    try:
        zone = ball_zone(bearing, variation)
    except validate.FieldError as err:
        raise err.within("montecarlo") from None
    if speed > 0:
        raise validate.FieldError(where, "needs speed = 0: at speed a ball's diameter also sets its mass and the "
                                  "high-speed model's contact radii, which are not varied per ball", variation)
    if any(row.element != "ball" for row in bearing.rows):  # each element kind says what it is
        raise validate.FieldError(where, "is for rows of plain balls (element = \"ball\"): four-point balls and "
                                  "rollers are not varied per element", variation)
    return zone


@dataclass(frozen=True)
class Sampler:
    """What each block needs to draw and budget its samples (picklable, for Dask workers): the zones, seed,
    the bearing unmounted (its tables), the clearance budget at the case's speed and temperatures, each row's
    unmounted preload and its axial shift (applied at an operating clearance <= 0, as operating_bearing does)."""

    zones: tuple
    seed: int
    mounted: Bearing
    base: Bearing
    speed: float

    def operating(self, first: int, n: int):
        """(samples dict (n,) mm, rL (n, rows) mm, d0 (n, rows) mm) of samples first .. first+n-1."""
        samples = draw(self.zones, n, self.seed, first)
        shaft, housing = interferences(self.mounted, samples)
        unmounted = samples.get("unmounted_diametral_clearance")
        if unmounted is None:
            unmounted = np.full(n, self.mounted.geometry.diametral_clearance)
        Pd = clearance_budget(self.mounted, self.speed).operating_clearance(unmounted, shaft, housing)
        rows = self.base.n_rows
        rL = np.repeat((0.5 * Pd)[:, None], rows, axis=1)
        base = np.array([r.axial_preload for r in self.base.rows])
        shift = np.array(preload_shifts(self.mounted))
        d0 = base + np.where((Pd <= 0.0)[:, None], shift, 0.0)
        return samples, rL, d0


def compute_block(sampler: Sampler, line_length: int, settings, life, spinning: bool, inputs: np.ndarray,
                  res: dict, first: int, stop: np.ndarray, device: str = "cpu") -> None:
    """One block of samples (first .. first + n - 1) into ``res``: drawn, budgeted and solved, each continuation
    run from one sample to the next (the load is the same: only the bearing changes). ``device`` "cuda":
    solved on the GPU (engine.gpu.map_sweep_cuda: its own shorter continuation segments, so results agree with
    the CPU's to the solver's tolerance, not bit for bit)."""
    n = inputs.shape[0]
    samples, rL, d0 = sampler.operating(first, n)
    for name, values in samples.items():
        if name in res:
            res[name][...] = values
    res["operating_diametral_clearance"][...] = 2.0 * rL
    res["operating_axial_preload"][...] = d0
    table, valid = sampler.base.operating_table(rL, d0)
    sizes = samples.get("ball_diameter_deviation")
    elements, cases = block_records(sampler.base, line_length, life, spinning, inputs, res, first,
                                    mirror=sizes is None)  # balls of their own sizes: no mirror images
    outside = ~valid
    # in sample order: each continuation run starts from its previous sample's q (solving in clearance order
    # halves the Newton iterations but measured slower at speed, and no faster at rest: bench/README.md)
    cases = cases._replace(inputs=np.where(outside[:, None], np.nan, cases.inputs), operating=table,
                           ball_sizes=None if sizes is None else np.ascontiguousarray(sizes))
    if device == "cuda":
        from ..engine.gpu import map_sweep_cuda  # numba.cuda is imported only here

        map_sweep_cuda(elements, cases, True, settings, stop)
    else:
        map_sweep(elements, cases, True, settings, stop)
    if stop[0] != 0:
        return
    if outside.any():
        _flag_outside(res, outside)
    if life is not None:
        _iso_lives(res, life[2], inputs[:, 5] if inputs.shape[1] == 6 else None)


def zone_variables(zones) -> list:
    """One stored input per sampled zone (mm), with its zone and source."""
    V = storage.Variable
    return [V(z.name, ("ball",) if z.count is not None else (), "f8", "mm", ZONE_LONG_NAMES[z.name],
              {"zone_low_mm": z.low, "zone_high_mm": z.high, "source": z.source,
               "comment": "drawn uniformly and independently within its zone"}) for z in zones]


def job(cfg: MonteCarloConfig, device: str = "cpu") -> jobs.Job:
    """The Monte Carlo run as a job for the runner (blocks = the draw blocks), on ``device``."""
    base = replace(cfg.bearing, mounting=None)
    settings = solver_settings(base, cfg.method, cfg.rtol, cfg.max_iter)
    cases = cfg.cases
    variables = storage.result_variables("load")
    if cfg.speed > 0 and not base.roller_rows:
        variables += storage.outer_angle_variables()
    variables += operating_variables() + zone_variables(cfg.zones)
    attrs = {"montecarlo_samples": cfg.samples, "montecarlo_seed": cfg.seed, "speed_rpm": cfg.speed,
             "montecarlo_note": "each sample's tolerances drawn uniformly and independently within their zones "
                                "(variables with zone_low_mm, zone_high_mm, source); its operating clearance and "
                                "preload from its fits at the case's speed and temperatures (mm)"}
    life = None
    if cfg.life is not None:
        r = ratings(base)
        life = (life_table(r, cfg.life), r.C0 if r.C0 is not None else float("nan"), r)
        variables += storage.life_variables(iso=r.C is not None, hours=cfg.speed > 0)
        attrs |= {"life_rotating_ring": cfg.life.rotating, "dynamic_load_rating_N": r.C or float("nan"),
                  "static_load_rating_N": r.C0 or float("nan"),
                  "dynamic_load_rating_source": rating_sources(base)["C"]}
    stored = jobs.check_stored(cfg.variables, variables, "montecarlo.variables")
    if stored is not None:  # the summary reads these
        stored = tuple(dict.fromkeys(stored + ("K", "operating_diametral_clearance")
                                     + tuple(z.name for z in cfg.zones) + (("L10r",) if life else ())))
    sampler = Sampler(cfg.zones, cfg.seed, cfg.bearing, base, cfg.speed)
    sizes, own_dims = {"dof": 5, "dof_col": 5, "row": base.n_rows}, ()
    if any(z.count is not None for z in cfg.zones):
        sizes["ball"] = base.n_balls
        own_dims = (storage.Coordinate("ball", np.arange(base.n_balls), "1", "ball number (row by row)"),)
    return jobs.Job(
        kind="Monte Carlo run", bearing=base, cases=cases, variables=tuple(variables), attrs=attrs,
        sizes=sizes, own_dims=own_dims,
        compute=partial(compute_block, sampler, cases.line_length, settings, life, cfg.speed > 0, device=device),
        settings=settings, method=cfg.method, chunk=DRAW_BLOCK, text=cfg.text, source=cfg.source,
        # a GPU's shorter segments give other (equally converged) bits: a run is resumed on the device it began on
        fingerprint=cfg.fingerprint + ("-gpu" if device == "cuda" else ""), compression=cfg.compression,
        line_length=cases.line_length, kernel="engine.gpu.map_sweep_cuda" if device == "cuda" else "engine.sweep.map_sweep",
        stored=stored, dtype=cfg.dtype, case_word="sample")


def montecarlo(config, output=None, *, threads=None, resume=False, overwrite=False, progress=None, client=None,
               max_in_flight=None, device="cpu"):
    """Sample the bearing's tolerance zones and solve every sample; returns (path of the result, summary dict).

    ``config``: a TOML path or dict with ``[bearing]`` (with ``[bearing.mounting]``) and ``[montecarlo]``
    (``samples``, ``seed``, the loads Fx..My in N and N*mm, ``speed`` in rpm, temperatures in deg C as
    ``[bearing.mounting]`` names them, ``life``). ``output`` .h5 or .zarr; nothing is overwritten unless
    ``overwrite``; ``resume`` continues a killed run. ``client``: a Dask client (the same file bit for bit).
    The summary (:func:`summarize`) is also written into the file's attributes (``summary_json``)."""
    cfg = config if isinstance(config, MonteCarloConfig) else read_config(config)
    device = jobs.check_device(device, client)
    out = jobs.run(job(cfg, device), jobs.output_path(output, cfg.source), threads=threads, resume=resume,
                   overwrite=overwrite, progress=progress, client=client, max_in_flight=max_in_flight)
    summary = summarize(out)
    storage.add_file_attributes(out, {"summary_json": json.dumps(summary)})
    return out, summary


def _unit_ranks(x: np.ndarray) -> np.ndarray | None:
    """x's ranks, centred and scaled to unit length (Spearman's rho is then a dot product), float32 (ranks of
    up to 1e8 samples are exact to 1e-7 relative, far below any rho worth reading); None for a constant x.
    Tied values (a plateau: kxx of the samples where the fits are lost alike) take their mean rank."""
    order = np.argsort(x)  # ties get their mean rank below: no stable sort needed
    xs = x[order]
    n = x.shape[0]
    # mean rank of each run of equal values: (first + last) / 2 of the run
    starts = np.flatnonzero(np.r_[True, xs[1:] != xs[:-1]])
    ends = np.r_[starts[1:], n] - 1
    ranks_sorted = np.repeat(0.5 * (starts + ends), ends - starts + 1)
    r = np.empty(n)
    r[order] = ranks_sorted
    r -= r.mean()
    norm = np.sqrt((r * r).sum())
    return (r / norm).astype(np.float32) if norm > 0 else None


def summarize(path) -> dict:
    """The summary of a finished Monte Carlo file: ``samples``, ``converged``, ``outside_model``;
    ``percentiles`` {output: {p: value}} of the operating diametral clearance (mm, all samples), kxx and kzz
    (N/mm) and L10r (million revolutions) over the converged samples; ``p_clearance_negative``, the share of
    samples with an operating clearance < 0; ``sensitivity`` {output: [[input, Spearman rank correlation],
    ...]} sorted by |rho|, largest first (inputs: the sampled zones)."""
    from .storage import ResultFile

    with ResultFile(path) as rf:
        status = rf.read("status")
        clearance = rf.read("operating_diametral_clearance", (slice(None), 0)).astype(float)
        outputs = {"operating_diametral_clearance_mm": clearance,
                   "kxx_N_per_mm": rf.read("K", (slice(None), 0, 0)).astype(float),
                   "kzz_N_per_mm": rf.read("K", (slice(None), 2, 2)).astype(float)}
        if rf.has("L10r"):
            outputs["L10r_million_revolutions"] = rf.read("L10r").astype(float)
        # the per-ball deviations (sample, ball) are not ranked: a ball's own size matters by where it sits
        inputs = {n: rf.read(n).astype(float) for n in ZONE_NAMES if rf.has(n) and rf.ndim(n) == 1}
    ok = st.converged_mask(status)
    summary = {"samples": int(status.shape[0]), "converged": int(ok.sum()),
               "outside_model": int(((status & st.OUTCOME_MASK) == st.OUTSIDE_MODEL).sum()),
               "p_clearance_negative": float((clearance < 0).mean()), "percentiles": {}, "sensitivity": {}}
    input_ranks = {n: _unit_ranks(x[ok]) for n, x in inputs.items()} if ok.sum() > 2 else {}
    for name, values in outputs.items():
        v = values if name.startswith("operating") else values[ok]
        v = v[np.isfinite(v)]
        summary["percentiles"][name] = ({str(p): float(x) for p, x in zip(PERCENTILES, np.percentile(v, PERCENTILES))}
                                        if v.size else {})
        if input_ranks:
            out = _unit_ranks(values[ok])
            ranking = [[n, float(np.dot(r, out)) if out is not None else float("nan")]
                       for n, r in input_ranks.items() if r is not None]
            summary["sensitivity"][name] = sorted(ranking, key=lambda t: -abs(t[1]) if t[1] == t[1] else 0.0)
    return summary


def summary_text(summary: dict) -> str:
    """The summary in lines, units in the names."""
    lines = [f"{summary['samples']} samples: {summary['converged']} converged, {summary['outside_model']} outside "
             f"the model; P(operating clearance < 0) = {summary['p_clearance_negative']:.4g}",
             "percentiles " + "  ".join(f"p{p:>2}" for p in PERCENTILES)]
    for name, values in summary["percentiles"].items():
        scale, label = (1000.0, name.replace("clearance_mm", "clearance_um")) if name.endswith("clearance_mm") \
            else (1.0, name)
        lines.append(f"  {label}: " + "  ".join(f"{scale * values[str(p)]:.4g}" for p in PERCENTILES if str(p) in values))
    lines.append("sensitivity (Spearman rank correlation, largest first):")
    for name, ranking in summary["sensitivity"].items():
        lines.append(f"  {name}: " + ", ".join(f"{n} {rho:+.3f}" for n, rho in ranking))
    return "\n".join(lines)


__all__ = ["MonteCarloConfig", "read_config", "job", "montecarlo", "summarize", "summary_text", "Zone"]
