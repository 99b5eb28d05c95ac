"""Load maps: Kb at every case of a grid (or table) of loads or displacements, streamed to HDF5.

This module reads a ``[loadmap]`` config into a job (the cases, the result
variables, the block compute function) for the one runner in jobs.py, which
owns blocks, the HDF5 writer, resume, Ctrl-C, progress and Dask.
Units: N, mm, rad.
"""

from __future__ import annotations

import hashlib
from collections import namedtuple
import sys
from dataclasses import dataclass, field, replace
from functools import partial
from pathlib import Path

import numpy as np

from . import runner as jobs

from . import storage

from .. import validate
from ..api import case_operating, solver_settings
from ..model.bearing import Bearing, check_speed, check_speed_model
from ..model.mounted import CASE_TEMPERATURES, operating_attributes, operating_bearing
from ..model.bearing_file import read_job_config
from .. import boundary
from ..dofs import AXES, TEMPERATURE_UNITS, UNITS
from .grid import Axis, CaseSet, check_fixed_axes, fixed_mask, input_axes, parse_axis, read_case_file, segment_starts
from .runner import open_dataset  # noqa: F401 (public: fb.open_dataset)
from ..analysis.life import LifeSettings, iso_life, life_table, rating_sources, ratings
from ..engine.contract import CaseBlock, Elements, Results
from ..engine.sweep import map_sweep
from .. import status as st

DEFAULT_CHUNK = 65536
#: Largest block: one block's results are in memory at once (about 400 bytes a case).
MAX_CHUNK = 4_000_000
_LOADMAP_KEYS = {"given", "cases", "chunk", "compression", "method", "rtol", "max_iter", "life", "speed", "fixed",
                 "variables", "dtype"} | set(CASE_TEMPERATURES)


@dataclass(frozen=True)
class LoadMapConfig:
    """A parsed load-map config: the bearing, the cases and how to run them."""

    bearing: Bearing
    cases: CaseSet
    chunk: int
    compression: str
    method: str
    rtol: float | None
    max_iter: int | None
    text: str
    source: Path | None
    fingerprint: str
    life: LifeSettings | None = None
    #: Degrees of freedom given as displacements (boundary.Fixed.mask; 0: every load given).
    fixed: int = 0
    #: The variables the file keeps (None: all; status always), and the dtype of its real-valued ones.
    variables: tuple[str, ...] | None = None
    dtype: str = "float64"
    #: A bearing with [bearing.mounting]: its operating clearance and preload as file attributes (mm, rpm).
    operating: dict = field(default_factory=dict)
    #: The mounted bearing when the cases vary it (several speeds, temperature axes): each case then gets its
    #: own operating clearance and preload (the map's ``bearing`` is the same bearing unmounted); else None.
    mounted: Bearing | None = None


def read_life(spec, where: str) -> LifeSettings | None:
    """``life = true`` (inner ring rotating) or ``life = { rotating = "outer" }``; false or absent: None."""
    if spec is None or spec is False:
        return None
    if spec is True:
        return LifeSettings()
    if isinstance(spec, dict):
        validate.table(spec, where, ("rotating",))
        try:
            return LifeSettings(rotating=spec.get("rotating", "inner"))
        except validate.FieldError as err:
            raise err.within(where) from None
    raise validate.FieldError(where, "must be true, false or a table { rotating = \"inner\" | \"outer\" }", spec)


def read_config(config) -> LoadMapConfig:
    """Parse a load-map config from a TOML path or an already-parsed dict; ValueError names the field."""
    bearing, spec, text, source = read_job_config(config, "loadmap")
    given = validate.choice(spec.get("given", "load"), "loadmap.given", tuple(AXES))
    names = AXES[given]
    other = AXES["displacement" if given == "load" else "load"]
    for key in spec:
        if key in other:
            raise ValueError(f"loadmap.{key} is not an axis for given = {given!r}; its axes are {list(names)}")
        if key not in names and key not in _LOADMAP_KEYS:
            raise ValueError(f"loadmap: unknown key {key!r}; allowed: {sorted(_LOADMAP_KEYS | set(names))}")
    chunk = validate.integer(spec.get("chunk", DEFAULT_CHUNK), "loadmap.chunk", low=1, high=MAX_CHUNK)
    compression = validate.choice(spec.get("compression", "none"), "loadmap.compression", storage.COMPRESSIONS)
    method = spec.get("method", "newton")
    rtol, max_iter = spec.get("rtol"), spec.get("max_iter")
    try:
        solver_settings(bearing, method, rtol, max_iter)  # validates method, rtol, max_iter
    except validate.FieldError as err:
        raise err.within("loadmap") from None
    digest = hashlib.sha256(text.encode())
    fixed = fixed_mask(spec, given, names, "loadmap")
    if "cases" in spec:
        if fixed:
            raise ValueError("loadmap.fixed goes with grid axes (a case table holds loads only); give the fixed "
                             "values in [loadmap] fixed, each a number or an axis")
        axes_given = [k for k in spec if k in names or k == "speed"]
        axes_given += [k for k in spec if k in CASE_TEMPERATURES]
        if axes_given:
            raise ValueError(f"loadmap.cases replaces the grid axes; remove {axes_given}")
        if not isinstance(spec["cases"], str):
            raise ValueError(f"loadmap.cases must be a file name (.npy, .csv or .h5), got {spec['cases']!r}")
        path = Path(spec["cases"])
        if source is not None and not path.is_absolute():
            path = source.parent / path
        table = read_case_file(path, "loadmap.cases")
        digest.update(table.tobytes())
        cases = CaseSet(given, table=table)
    else:
        axes = list(input_axes(spec, names, UNITS[given], fixed, "loadmap"))
        check_fixed_axes(bearing, axes, fixed, "loadmap")
        speed = None
        if "speed" in spec:
            values, is_dim = parse_axis("speed", spec["speed"], "loadmap")
            for i, v in enumerate(values):
                check_speed(v, f"loadmap.speed[{i}]" if is_dim else "loadmap.speed")
            speed = Axis("speed", values, "rpm", is_dim)
        cases = CaseSet(given, axes=tuple(axes), speed=speed, conditions=condition_axes(bearing, spec))
    cases.check_size("loadmap")
    operating_attrs = {}
    mounted = None
    if bearing.mounting is not None:
        speeds = (cases.table[:, 5] if cases.table is not None and cases.table.shape[1] == 6
                  else cases.speed.values if cases.speed is not None else [0.0])
        if cases.conditions or np.unique(speeds).size > 1:
            # the cases vary the bearing: each its own operating clearance and preload (compute_block)
            mounted, bearing = bearing, replace(bearing, mounting=None)
        else:
            bearing, budget = operating_bearing(bearing, float(speeds[0]))
            operating_attrs = operating_attributes(budget)
    if cases.max_speed > 0:
        try:
            check_speed_model(bearing, cases.max_speed)
        except validate.FieldError as err:
            raise err.within("loadmap") from None
    life_settings = read_life(spec.get("life"), "loadmap.life")
    if life_settings is not None:
        ratings(bearing)  # a bearing without geometry has no rating: said before anything runs
    stored = None
    if "variables" in spec:
        names_given = validate.array(spec["variables"], "loadmap.variables", min_length=1)
        if not all(isinstance(n, str) for n in names_given):
            raise validate.FieldError("loadmap.variables", "must be a list of variable names, e.g. [\"K\"]",
                                      spec["variables"])
        stored = tuple(dict.fromkeys(names_given))    # checked against the map's variables by job()
    dtype = validate.choice(spec.get("dtype", "float64"), "loadmap.dtype", jobs.RESULT_DTYPES)
    return LoadMapConfig(bearing, cases, chunk, compression, method, rtol, max_iter, text, source,
                         digest.hexdigest(), life_settings, fixed, stored, dtype, operating_attrs, mounted)


def condition_axes(bearing, spec: dict) -> tuple[Axis, ...]:
    """The temperature axes of a ``[loadmap]`` (keys of model.mounted.CASE_TEMPERATURES, deg C, each a number
    or an axis), in that order; they need ``[bearing.mounting]``. ValueError naming the field."""
    keys = [k for k in CASE_TEMPERATURES if k in spec]
    if keys and bearing.mounting is None:
        raise validate.FieldError(f"loadmap.{keys[0]}", "needs [bearing.mounting] (fits, materials): a temperature "
                                  "acts on the bearing through its mounting", show_value=False)
    out = []
    for key in keys:
        values, is_dim = parse_axis(key, spec[key], "loadmap")
        for i, v in enumerate(values):
            validate.number(v, f"loadmap.{key}[{i}]" if is_dim else f"loadmap.{key}", low=-273.15,
                            units="deg C (absolute zero)")
        out.append(Axis(key, values, TEMPERATURE_UNITS, is_dim))
    return tuple(out)


def operating_variables() -> list:
    """A map whose cases vary the bearing keeps each case's operating clearance and preload per row."""
    V = storage.Variable
    return [V("operating_diametral_clearance", ("row",), "f8", "mm", "operating diametral clearance per row",
              {"comment": "Pd_op = 2 rL of the case, from its fits, temperatures and speed; nan: outside the model"}),
            V("operating_axial_preload", ("row",), "f8", "mm", "operating axial preload per row",
              {"comment": "d0 of the case (pairs and sets: changed by the shaft's and housing's axial growth)"})]



#: What every block of a map is computed with (:func:`compute_block`; picklable for Dask workers): the bearing,
#: whether loads are given, the cases per grid line, the solver settings, the life tables (or None), whether
#: some case spins, the device, the stored variables (None: all) and the cases' own bearing (or None).
MapWork = namedtuple("MapWork", "bearing given_load line_length settings life spinning device stored varying",
                     defaults=("cpu", None, None))


def compute_block(work: MapWork, inputs: np.ndarray, res: dict, first: int, stop: np.ndarray) -> None:
    """Fill the result arrays ``res`` (one block's, see :func:`variables`) for ``inputs`` (n, 5), the
    flat cases from ``first`` on, as ``work`` (:data:`MapWork`) says; ``stop[0] != 0`` (Ctrl-C) ends it early,
    leaving the block incomplete.

    The work unit of a map: local runs and Dask workers both call it, on the
    same blocks, which is why their outputs are identical bit for bit.
    ``life``: None, or (LifeSettings, BearingRatings) for the life variables. ``spinning``: some case of
    the map runs above 0 rpm (inputs (n, 6), the speed last): every block takes the high-speed ball set
    (one compiled sweep for the map; a case at 0 rpm is the quasi-static model exactly). ``device`` "cuda": the
    block on the GPU (engine.gpu.map_sweep_cuda: the same kernels and the same records, engine/contract.py), which
    copies back only the ``stored`` variables (None: all) and what the lives need; the others are left as they
    were in ``res``. ``varying``: None, or (the mounted bearing, the map's CaseSet) when the cases vary the
    bearing: each case then runs at its own operating clearance and preload (api.case_operating), stored in
    ``res``; a case outside the model gets the status outside_model, not a solve.
    """
    bearing, given_load, line_length, settings, life, spinning, device, stored, varying = work
    elements, cases = block_records(bearing, line_length, life, spinning, inputs, res, first)
    outside = None
    if varying is not None:
        cases, outside = _vary(cases, varying, inputs, res, first)
    if device == "cuda":
        from ..engine.gpu import map_sweep_cuda  # numba.cuda is imported only here

        map_sweep_cuda(elements, cases, given_load, settings, stop, wanted_results(stored, life))
    else:
        map_sweep(elements, cases, given_load, settings, stop)
    if outside is not None:
        _flag_outside(res, outside)
    if life is not None:
        _iso_lives(res, life[2], inputs[:, 5] if inputs.shape[1] == 6 else None)


def _vary(cases: CaseBlock, varying, inputs: np.ndarray, res: dict, first: int):
    """The block's CaseBlock with each case's operating values (and its inputs nan where a case is outside the
    model: not solved), and the outside mask (None: none)."""
    mounted, case_set = varying
    n = inputs.shape[0]
    rpm = inputs[:, 5] if inputs.shape[1] == 6 else np.zeros(n)
    values = case_operating(mounted, n, rpm, temperatures=case_set.condition_values(first, first + n), per_case=True)
    if "operating_diametral_clearance" in res:
        res["operating_diametral_clearance"][...] = 2.0 * values.radial_clearance
        res["operating_axial_preload"][...] = values.axial_preload
    cases = cases._replace(operating=values.table)
    if values.outside is not None:
        cases = cases._replace(inputs=np.where(values.outside[:, None], np.nan, cases.inputs))
    return cases, values.outside


def mount_summary(mounted: Bearing, cases: CaseSet, most: int = 4096) -> tuple[str, list[str]]:
    """(one line: the operating diametral clearance's range over the map, in um; the distinct notes of its
    mounts: fits lost, hoop stress, operating values outside the model), over every (speed, temperatures) of
    its axes (at most ``most`` of them)."""
    import itertools

    speeds = cases.speed.values if cases.speed is not None else (cases.table[:, 5] if cases.table is not None
                                                                 and cases.table.shape[1] == 6 else [0.0])
    axes = [np.unique(np.asarray(speeds, float))] + [a.values for a in cases.conditions]
    points = list(itertools.islice(itertools.product(*axes), most))
    columns = np.array(points, dtype=float)
    temperatures = {a.name: columns[:, k + 1] for k, a in enumerate(cases.conditions)}
    values = case_operating(mounted, len(points), columns[:, 0], temperatures=temperatures, per_case=True)
    Pd = 2000.0 * values.radial_clearance[:, 0]
    inside = Pd[np.isfinite(Pd)]
    line = ("each case at its own operating clearance: "
            + (f"{inside.min():.4g} to {inside.max():.4g} um" if inside.size else "none inside the model")
            + f" (unmounted {1000.0 * mounted.geometry.diametral_clearance:.4g} um) over {len(points)} speeds and "
            "temperatures")
    if values.outside is not None:
        line += f"; {int(values.outside.sum())} of them outside the model (status outside_model)"
    return line, values.notes


def _flag_outside(res: dict, outside: np.ndarray) -> None:
    """Cases outside the model: status outside_model, every real result nan (they were not solved)."""
    for name, a in res.items():
        if name == "status":
            a[outside] = st.OUTSIDE_MODEL
        elif name.startswith("operating_"):
            continue
        elif a.dtype.kind == "f":
            a[outside] = np.nan


def block_records(bearing: Bearing, line_length: int, life, spinning: bool, inputs: np.ndarray, res: dict,
                  first: int, mirror: bool = True):
    """(Elements, CaseBlock) of one block (engine/contract.py): the bearing's element set (at speed when
    ``spinning``; without its mirror half unless ``mirror``: cases whose balls differ), its rows and life table,
    and the block's inputs (n, 5), continuation segments, speeds (rad/s, from the inputs' sixth column in rpm)
    and results (:func:`map_results` of ``res``)."""
    balls, speeds = bearing.ball_set(mirror=mirror), np.zeros(0)
    if inputs.shape[1] == 6:  # the shaft speed (rpm) per case
        if spinning:
            balls, speeds = bearing.ball_set(speed=0.0, mirror=mirror), inputs[:, 5] * np.pi / 30.0
        inputs = np.ascontiguousarray(inputs[:, :5])
    table, C0 = (np.empty((0, 8)), 0.0) if life is None else life[:2]
    elements = Elements(balls, bearing.element_rows, table, C0)
    segments = segment_starts(first, first + inputs.shape[0], line_length)
    return elements, CaseBlock(inputs, segments, speeds, None, None, map_results(res, bearing.n_rows))


#: The engine's Results field of each map variable (the file's names are the engineer's, the record's short).
RESULT_FIELDS = {"q": "q", "f": "f", "K": "K", "status": "status", "iterations": "iterations",
                 "residual": "residual", "max_ball_load": "max_load", "loaded_balls": "n_loaded",
                 "min_contact_angle": "min_angle", "max_contact_angle": "max_angle",
                 "min_outer_contact_angle": "min_outer", "max_outer_contact_angle": "max_outer", "L10r": "L10r",
                 "L10r_row": "L10r_row", "static_safety": "safety"}


def map_results(res: dict, n_rows: int) -> Results:
    """A block's result arrays (by variable name) as the engine's Results record; an output the map does not
    keep (life, the outer contact angles) gets a one-case placeholder the sweep leaves untouched."""
    rows = (1, n_rows)
    placeholders = {"min_outer": np.empty(rows), "max_outer": np.empty(rows), "L10r": np.empty(1),
                    "L10r_row": np.empty(rows), "safety": np.empty(1)}
    fields = {field: res[name] if name in res else placeholders[field] for name, field in RESULT_FIELDS.items()}
    return Results(**fields)


def wanted_results(stored, life) -> Results | None:
    """Which Results fields a block's caller reads (a Results of bools), for a GPU that copies back only
    those: the stored variables (None: all), status, and with life the L10r and f the ISO lives are made from."""
    if stored is None:
        return None
    names = set(stored) | {"status"} | ({"L10r", "f"} if life is not None else set())
    return Results(**{field: name in names for name, field in RESULT_FIELDS.items()})


def _iso_lives(res: dict, r, rpm) -> None:
    """ISO 281's L10 of each case from the load the ring carries (f: the given load, or with fixed degrees of
    freedom the reactions there; nan where L10r is: no solution), and both lives in hours at each case's
    shaft speed ``rpm`` (None: the map has no speed column)."""
    solved = np.isfinite(res["L10r"])
    if "L10" in res:
        f = res["f"]
        _, L10 = iso_life(r, np.hypot(f[:, 0], f[:, 1]), np.abs(f[:, 2]))
        res["L10"][...] = np.where(solved, L10, np.nan)
    if "L10r_hours" in res:
        per_hour = 60.0 * rpm / 1e6  # million revolutions per hour
        for name in ("L10r", "L10"):
            if f"{name}_hours" in res:
                # a case at standstill lasts for ever (inf h); divided only where the shaft turns (dividing
                # every case, by a 1e-300 stand-in at 0 rpm, overflowed: numpy's "overflow in divide")
                hours = res[f"{name}_hours"]
                hours[...] = np.inf
                np.divide(res[name], per_hour, out=hours, where=per_hour > 0)


def job(cfg: LoadMapConfig, device: str = "cpu") -> jobs.Job:
    """The load map as a job for the runner; ``device`` "cuda" computes its blocks on the GPU."""
    settings = solver_settings(cfg.bearing, cfg.method, cfg.rtol, cfg.max_iter, cfg.fixed)
    given_load = cfg.cases.given == "load"
    variables = storage.result_variables(cfg.cases.given)
    life = None
    attrs = dict(cfg.operating)
    if cfg.fixed:
        attrs["fixed_dofs"] = ", ".join(boundary.names(cfg.fixed))
        attrs["fixed_note"] = ("the degrees of freedom in fixed_dofs are given as displacements (their grid axes, "
                               "mm or rad); f holds the reactions there (N, N*mm)")
    if cfg.cases.max_speed > 0 and not cfg.bearing.roller_rows:
        variables += storage.outer_angle_variables()
    varying = None
    if cfg.mounted is not None:
        variables += operating_variables()
        varying = (cfg.mounted, cfg.cases)
        attrs["operating_note"] = ("each case runs at its own operating clearance and preload from [bearing.mounting] "
                                   "at its speed and temperatures: variables operating_diametral_clearance and "
                                   "operating_axial_preload (mm)")
        line, notes = mount_summary(cfg.mounted, cfg.cases)
        attrs["operating_line"] = line
        if notes:
            attrs["operating_notes"] = "; ".join(notes)
    if cfg.life is not None:
        r = ratings(cfg.bearing)
        life = (life_table(r, cfg.life), r.C0 if r.C0 is not None else float("nan"), r)
        variables += storage.life_variables(iso=r.C is not None, hours=cfg.cases.has_speed)
        attrs |= {"life_rotating_ring": cfg.life.rotating, "dynamic_load_rating_N": r.C or float("nan"),
                 "static_load_rating_N": r.C0 or float("nan"),
                 "dynamic_load_rating_source": rating_sources(cfg.bearing)["C"],
                 "static_load_rating_source": rating_sources(cfg.bearing)["C0"],
                 "row_dynamic_load_rating_N": r.C_row, "contact_rating_inner_N": r.Q_ci,
                 "contact_rating_outer_N": r.Q_ce}
    stored = jobs.check_stored(cfg.variables, variables, "loadmap.variables")
    chunk, fingerprint, narrow = cfg.chunk, cfg.fingerprint, ()
    if device == "cuda":
        chunk, fingerprint, narrow = _device_blocks(cfg, variables, stored, life is not None)
    return jobs.Job(
        kind="load map", bearing=cfg.bearing, cases=cfg.cases,
        variables=tuple(variables), attrs=attrs,
        sizes={"dof": 5, "dof_col": 5, "row": cfg.bearing.n_rows},
        compute=partial(compute_block, MapWork(cfg.bearing, given_load, cfg.cases.line_length, settings, life,
                                               cfg.cases.max_speed > 0, device, stored, varying)),
        settings=settings, method=cfg.method, chunk=chunk, text=cfg.text, source=cfg.source,
        fingerprint=fingerprint, compression=cfg.compression, line_length=cfg.cases.line_length,
        kernel="engine.gpu.map_sweep_cuda" if device == "cuda" else "engine.sweep.map_sweep",
        stored=stored, dtype=cfg.dtype, narrow=narrow)


def _device_blocks(cfg: LoadMapConfig, variables, stored, life: bool):
    """The GPU's (chunk, fingerprint, narrow) of a map: blocks sized for the device (engine.gpu.device_chunk),
    a fingerprint that tells them from the CPU's blocks where they differ (a run is resumed only with the same
    blocks: --resume on the other device is refused as another config), and the stored float32 variables the GPU
    converts itself (the engine's outputs the host does not read again: with life, f and L10r make the ISO
    lives in float64)."""
    from ..engine.gpu import device_chunk  # no numba.cuda import: the sizes only

    chunk = device_chunk(cfg.chunk)
    fingerprint = cfg.fingerprint if chunk == cfg.chunk else f"{cfg.fingerprint}-gpu-chunk-{chunk}"
    narrow = ()
    if cfg.dtype == "float32":
        kept = {v.name for v in variables if v.dtype.startswith("f") and (stored is None or v.name in stored)}
        narrow = tuple(n for n in RESULT_FIELDS if n in kept and not (life and n in ("f", "L10r")))
    return chunk, fingerprint, narrow


def loadmap(config, output=None, *, threads=None, resume=False, overwrite=False, progress=None,
            as_dataset=False, client=None, max_in_flight=None, device="cpu"):
    """Compute a load map and write it to HDF5 or a zarr store.

    Parameters
    ----------
    config : str, Path or dict
        A TOML config file with ``[bearing]`` and ``[loadmap]`` tables, or the same as a dict.
    output : str or Path, optional
        Output: an HDF5 file, or a zarr v3 store for a name ending in ``.zarr`` or any fsspec URL
        (``s3://bucket/map.zarr``; jobs/zarr_store.py) (default: the config's name with suffix .h5, in the
        current folder). An existing file is never replaced unless ``overwrite``.
    threads : int, optional
        Numba threads (default: NUMBA_NUM_THREADS). Results do not depend on it.
    resume : bool
        Continue an interrupted run from ``OUTPUT.part`` (same config only).
    overwrite : bool
        Replace an existing output or discard an unfinished run.
    progress : bool, optional
        Progress bar on stderr (default: only when stderr is a terminal).
    as_dataset : bool
        Return an ``xarray.Dataset`` (needs xarray and h5netcdf) instead of the path.
    client : dask.distributed.Client, optional
        Run the blocks on a Dask cluster (see :mod:`fastbearing.jobs.distributed`);
        the output is identical to a local run.
    max_in_flight : int, optional
        Blocks out on the cluster at once (default: 2 per worker thread).
    device : {"cpu", "cuda"}
        Where the blocks are computed (default "cpu"); "cuda": on the GPU with the same kernels (numba-cuda).
        Without numba-cuda, a CUDA driver or a GPU, fastbearing.engine.device.CudaUnavailable names what is missing
        before any work is done.

    Returns
    -------
    Path or xarray.Dataset
    """
    cfg = config if isinstance(config, LoadMapConfig) else read_config(config)
    if as_dataset:
        jobs.require_xarray()
    device = jobs.check_device(device, client)
    the_job = job(cfg, device)
    if "operating_line" in the_job.attrs:  # a run says which clearance it solved, in one line
        print(f"fastbearing: {the_job.attrs['operating_line']}", file=sys.stderr)
    out = jobs.run(the_job, jobs.output_path(output, cfg.source), threads=threads, resume=resume,
                   overwrite=overwrite, progress=progress, client=client, max_in_flight=max_in_flight)
    return open_dataset(out) if as_dataset else out
