"""Ball-passage (time-varying) stiffness tables.

As the cage turns, balls move through the load zone and Kb varies
periodically. The whole ball set is rotated through one period in equal
steps: with q fixed (displacement given) Kb(psi) follows by substitution;
with f fixed (load given) q(psi) is re-solved at each position, warm-started
from the previous one. Every position is one call of the one physics kernel.
The period is 2*pi / gcd(Z_r) (one ball pitch when all rows have the same Z).
Units: N, mm, rad; time s; frequency Hz.
"""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import dataclass, field
from functools import partial, reduce
from pathlib import Path

import numpy as np

from . import runner as jobs

from . import storage

from .. import boundary, validate
from ..api import solver_settings
from ..model.bearing import Bearing, check_speed, check_speed_model
from ..model.bearing_file import read_job_config
from ..model.mounted import operating_attributes, operating_bearing
from ..dofs import AXES, K_UNITS, UNITS
from .grid import CaseSet, check_fixed_axes, fixed_mask, input_axes
from ..analysis.faults import fault_orders
from ..model.bearing import without_mirror_half
from ..model.defects import (Kinematics, element_depths, parse_defects, table_azimuths, with_ball_defects,
                             with_slice_defects, with_speed_defects)
from ..engine.contract import CaseBlock, Elements, PassageResults, Positions
from ..engine.sweep import passage_sweep

_PASSAGE_KEYS = {"defects", "revolutions", "element_loads", "fixed", "given", "points", "positions", "harmonics", "speed", "shaft_speed", "ball_diameter",
                 "pitch_diameter", "rotating", "method", "rtol", "max_iter", "chunk"}
#: Most cage positions per period (a sanity bound: 64 resolve the ball-pass harmonics well).
MAX_POSITIONS = 100_000


@dataclass(frozen=True)
class CageSpeed:
    """Cage kinematics: fc = fs/2 (1 -+ D cos(a0)/dm), - for the inner ring rotating, + for the outer."""

    shaft_speed: float  # rpm
    ball_diameter: float  # mm
    pitch_diameter: float  # mm
    contact_angle: float  # rad
    rotating: str  # "inner" or "outer"

    @property
    def cage_frequency(self) -> float:
        """fc in Hz (cage revolutions per second)."""
        sign = -1.0 if self.rotating == "inner" else 1.0
        ratio = self.ball_diameter * math.cos(self.contact_angle) / self.pitch_diameter
        return self.shaft_speed / 60.0 / 2.0 * (1.0 + sign * ratio)


@dataclass(frozen=True)
class PassageConfig:
    bearing: Bearing
    cases: CaseSet
    positions: int
    harmonics: int
    speed: CageSpeed | None  # the time axis
    method: str
    rtol: float | None
    max_iter: int | None
    chunk: int
    text: str
    source: Path | None
    fingerprint: str
    model_speed: float = 0.0  # rpm: above 0 the high-speed balls (fastbearing.engine.high_speed)
    fixed: int = 0  # degrees of freedom given as displacements (boundary.Fixed.mask)
    #: Over shaft revolutions (``revolutions`` of them, ``positions`` per revolution) instead of one ball-pass
    #: period: with local defects (model/defects.py) the table repeats only after many revolutions.
    revolutions: int | None = None
    defects: tuple = ()
    kinematics: object = None  # defects.Kinematics where the table runs over revolutions
    element_loads: bool = False  # store each element's load at every position
    #: A bearing with [bearing.mounting]: its operating clearance and preload as file attributes (mm, rpm).
    operating: dict = field(default_factory=dict)

    @property
    def n_positions(self) -> int:
        """The table's positions: ``positions`` over one period, or per revolution times ``revolutions``."""
        return self.positions * (self.revolutions or 1)

    @property
    def shaft_angles(self) -> np.ndarray:
        """The shaft's rotation at each position from position 0, rad (over revolutions only)."""
        return np.arange(self.n_positions) * 2.0 * math.pi / self.positions

    @property
    def period_order(self) -> int:
        """gcd of the rows' ball counts: the table repeats after a cage turn of 2*pi/period_order."""
        return reduce(math.gcd, (r.n_elements for r in self.bearing.rows))

    @property
    def period(self) -> float:
        """Cage-angle period of the table, rad."""
        return 2.0 * math.pi / self.period_order

    @property
    def cage_angles(self) -> np.ndarray:
        """Cage angle of each position, rad; position 0 is the bearing definition's own layout. Over
        revolutions the cage turns at the FTF order of the shaft (analysis/faults.py)."""
        if self.revolutions:
            return self.shaft_angles * self.kinematics.cage_order
        return np.arange(self.positions) * self.period / self.positions


def read_config(config) -> PassageConfig:
    """Parse a ``[bearing]`` + ``[passage]`` config from a TOML path or a dict; ValueError names the field."""
    bearing, spec, text, source = read_job_config(config, "passage")
    given = validate.choice(spec.get("given", "displacement"), "passage.given", ("displacement", "load"))
    names = AXES[given]
    for key in spec:
        if key not in names and key not in _PASSAGE_KEYS:
            raise ValueError(f"passage: unknown key {key!r} for given = {given!r}; allowed: "
                             f"{sorted(_PASSAGE_KEYS | set(names))}")
    positions = validate.integer(spec.get("positions", 64), "passage.positions", low=2, high=MAX_POSITIONS)
    harmonics = validate.integer(spec.get("harmonics", 8), "passage.harmonics", low=0, high=MAX_POSITIONS // 2)
    chunk = validate.integer(spec.get("chunk", 4096), "passage.chunk", low=1, high=10_000_000)
    method = spec.get("method", "newton")
    try:
        solver_settings(bearing, method, spec.get("rtol"), spec.get("max_iter"))
    except validate.FieldError as err:
        raise err.within("passage") from None
    axes_given = [k for k in spec if k in names or k == "fixed"]
    fixed = fixed_mask(spec, given, names, "passage")
    if "points" in spec:
        if fixed:
            raise ValueError("passage.fixed goes with grid axes (points hold loads only); give the fixed values "
                             "in [passage] fixed, each a number or an axis, and the loads as axes")
        if axes_given:
            raise ValueError(f"passage.points replaces the grid axes; remove {axes_given}")
        points = validate.array(spec["points"], "passage.points", min_length=1)
        table = np.array([validate.numbers_list(p, f"passage.points[{i}]", 5) for i, p in enumerate(points)])
        cases = CaseSet(given, table=table, table_dim="point")
    elif axes_given:
        axes = input_axes(spec, names, UNITS[given], fixed, "passage")
        check_fixed_axes(bearing, axes, fixed, "passage")
        cases = CaseSet(given, axes=axes, table_dim="point")
        if not cases.dims:  # constants only: one operating point
            cases = CaseSet(given, table=cases.inputs(0, 1), table_dim="point")
    else:
        raise ValueError(f"passage needs points = [[...], ...] or grid axes ({', '.join(names)})")
    cases.check_size("passage")
    model_speed = check_speed(spec.get("speed", 0.0), "passage.speed")
    if model_speed > 0:
        try:
            check_speed_model(bearing, model_speed)
        except validate.FieldError as err:
            raise err.within("passage") from None
    speed = None
    speed_keys = [k for k in ("shaft_speed", "ball_diameter", "pitch_diameter") if k in spec]
    kinematics = _element_kinematics(spec, bearing) if speed_keys else None
    if speed_keys:
        if "shaft_speed" not in spec or kinematics is None:
            raise ValueError("passage: the time axis needs shaft_speed (rpm), ball_diameter and pitch_diameter "
                             f"(mm) together (or shaft_speed alone for a bearing with [bearing.geometry]); got "
                             f"only {speed_keys}")
        D, dm, rotating = kinematics
        rpm = validate.number(spec["shaft_speed"], "passage.shaft_speed", low=0, low_open=True, units="rpm")
        if model_speed > 0 and rpm != model_speed:
            raise validate.FieldError("passage.shaft_speed", f"must equal passage.speed ({model_speed:g} rpm) "
                                      "when both are given (or leave it out: the speed gives the time axis)", rpm)
        speed = CageSpeed(rpm, D, dm, math.radians(bearing.rows[0].contact_angle), rotating)
    elif "rotating" in spec:
        raise ValueError("passage.rotating needs shaft_speed, ball_diameter and pitch_diameter (or speed with "
                         "[bearing.geometry], whose rotating key says which ring turns)")
    elif model_speed > 0:  # the time axis from the bearing's own geometry
        g = bearing.geometry
        speed = CageSpeed(model_speed, g.ball_diameter, g.pitch_diameter,
                          math.radians(bearing.rows[0].contact_angle), g.rotating)
    operating_attrs = {}
    if bearing.mounting is not None:  # the bearing as it runs at its one speed (the model's, else the time axis')
        bearing, budget = operating_bearing(bearing, model_speed or (speed.shaft_speed if speed else 0.0))
        operating_attrs = operating_attributes(budget)
    revolutions, defects, kinematics = _revolutions(spec, bearing, positions)
    element_loads = validate.boolean(spec.get("element_loads", False), "passage.element_loads")
    digest = hashlib.sha256(text.encode()).hexdigest()
    return PassageConfig(bearing, cases, positions, harmonics, speed, method, spec.get("rtol"),
                         spec.get("max_iter"), chunk, text, source, digest, model_speed, fixed, revolutions,
                         defects, kinematics, element_loads, operating_attrs)


def _element_kinematics(spec: dict, bearing: Bearing):
    """(ball or mean roller diameter D in mm, pitch diameter dm in mm, the rotating ring) that place the
    cage: a bearing with [bearing.geometry] gives them (a passage.ball_diameter or pitch_diameter that
    differs is refused), else passage.ball_diameter, pitch_diameter and rotating; None when neither has them."""
    g = bearing.geometry
    element_diameter = getattr(g, "ball_diameter", None) or getattr(g, "roller_diameter", None)
    if element_diameter is not None:
        for key, value in (("ball_diameter", element_diameter), ("pitch_diameter", g.pitch_diameter)):
            if key in spec:
                given = validate.number(spec[key], f"passage.{key}", low=0, low_open=True, units="mm")
                if not math.isclose(given, value, rel_tol=1e-12):
                    raise validate.FieldError(f"passage.{key}", f"differs from [bearing.geometry]'s {value:g} mm: "
                                              "leave it out (the bearing's geometry gives it)", given)
        rotating = validate.choice(spec.get("rotating", getattr(g, "rotating", "inner")), "passage.rotating",
                                   ("inner", "outer"))
        return element_diameter, g.pitch_diameter, rotating
    if "ball_diameter" not in spec or "pitch_diameter" not in spec:
        return None
    D = validate.number(spec["ball_diameter"], "passage.ball_diameter", low=0, low_open=True, units="mm")
    dm = validate.number(spec["pitch_diameter"], "passage.pitch_diameter", low=D, low_open=True, units="mm")
    return D, dm, validate.choice(spec.get("rotating", "inner"), "passage.rotating", ("inner", "outer"))


def _revolutions(spec: dict, bearing: Bearing, positions: int):
    """(revolutions, defects, kinematics) of a table over shaft revolutions: ``revolutions`` (default 1 with
    defects) and ``[[passage.defects]]``; the kinematics from [bearing.geometry] or the passage's
    ball_diameter, pitch_diameter and rotating. (None, (), None) for a table over one ball-pass period."""
    if "defects" not in spec and "revolutions" not in spec:
        return None, (), None
    revolutions = validate.integer(spec.get("revolutions", 1), "passage.revolutions", low=1,
                                   high=MAX_POSITIONS // positions)
    defects = parse_defects(spec["defects"], bearing) if "defects" in spec else ()
    kinematics = _element_kinematics(spec, bearing)
    if kinematics is None:
        raise ValueError("passage.revolutions and passage.defects need the ball's kinematics: [bearing.geometry] "
                         "(ball_diameter, pitch_diameter) or passage.ball_diameter and passage.pitch_diameter (mm)")
    D, dm, rotating = kinematics
    angle = bearing.rows[0].contact_angle
    orders = fault_orders(D, dm, 1, angle, rotating)
    kin = Kinematics(D, dm, math.radians(angle), rotating, orders["FTF"], orders["BSF"])
    return revolutions, defects, kin


def fourier(K: np.ndarray, harmonics: int) -> tuple[np.ndarray, np.ndarray]:
    """Amplitude and phase (rad) of K(theta) = sum_h A_h cos(h*2*pi*k/P + phi_h), harmonics 0..H.

    K has the positions on axis -3 (..., P, 5, 5). A_0 is the mean; for
    0 < h < P/2, A_h = 2|c_h|; the Nyquist term (h = P/2) keeps |c_h|.
    """
    P = K.shape[-3]
    H = min(harmonics, P // 2)
    c = np.fft.rfft(K, axis=-3)[..., :H + 1, :, :] / P
    amplitude = np.abs(c)
    amplitude[..., 1:, :, :] *= 2.0
    if P % 2 == 0 and H == P // 2:
        amplitude[..., H, :, :] /= 2.0
    return amplitude, np.angle(c)


def variation_summary(K: np.ndarray) -> dict[str, np.ndarray]:
    """Mean, min, max over positions (axis -3) and peak-to-peak in % of |mean| (nan where the mean is ~0)."""
    mean, lo, hi = K.mean(axis=-3), K.min(axis=-3), K.max(axis=-3)
    diag = np.abs(np.diagonal(mean, axis1=-2, axis2=-1))
    scale = np.sqrt(diag[..., :, None] * diag[..., None, :])
    with np.errstate(divide="ignore", invalid="ignore"):
        variation = np.where(np.abs(mean) > 1e-9 * scale, (hi - lo) / np.abs(mean) * 100.0, np.nan)
    return {"K_mean": mean, "K_min": lo, "K_max": hi, "K_variation": variation}


def _variables(cfg: PassageConfig) -> list[storage.Variable]:
    """Per point: the per-position results and the summaries over the period (and each element's load at every
    position where asked: ``element_loads``)."""
    V = storage.Variable
    loads = [V("element_load", ("position", "element"), "f8", "N", "each element's load at every position (the "
               "balls' inner contact, each roller's total), in the bearing's element order")] if cfg.element_loads else []
    return storage.result_variables(cfg.cases.given, inner=("position",)) + loads + [
        V("K_mean", ("dof", "dof_col"), "f8", K_UNITS, "mean of Kb over one period"),
        V("K_min", ("dof", "dof_col"), "f8", K_UNITS, "minimum of Kb over one period"),
        V("K_max", ("dof", "dof_col"), "f8", K_UNITS, "maximum of Kb over one period"),
        V("K_variation", ("dof", "dof_col"), "f8", "%",
          "peak-to-peak variation of Kb over one period in % of |mean| (nan where the mean is ~0)"),
        V("K_amplitude", ("harmonic", "dof", "dof_col"), "f8", K_UNITS,
          "Fourier amplitude A_h of Kb: K = sum_h A_h cos(h*2*pi*position/positions + phi_h)"),
        V("K_phase", ("harmonic", "dof", "dof_col"), "f8", "rad", "Fourier phase phi_h of Kb"),
    ]


def compute_block(tables: np.ndarray, slice_tables: np.ndarray | None, balls, ball_row: np.ndarray, given_load: bool,
                  settings, harmonics: int, speed_tables: np.ndarray | None, inputs: np.ndarray, res: dict,
                  first: int, stop: np.ndarray, device: str = "cpu") -> None:
    """Fill one block's results ``res``: every point of ``inputs`` at every cage position, then the
    summaries over the period (mean, min, max, variation, Fourier). The work unit of a table, here or on Dask.
    ``balls`` the bearing's element set at cage angle 0 (Bearing.ball_set: quasi-static, or at the table's
    speed), ``speed_tables`` its high-speed tables per position where defects change them (else None).
    ``first`` (the block's first point) is unused: every point starts cold. ``stop[0] != 0`` ends early."""
    element_loads = res["element_load"] if "element_load" in res else np.empty((0, 0, 0))
    sweep = passage_sweep
    if device == "cuda":                          # the same kernels through numba-cuda (engine/gpu.py)
        from ..engine.gpu import passage_sweep_cuda as sweep
    results = PassageResults(res["q"], res["f"], res["K"], res["status"], res["iterations"], res["residual"],
                             res["max_ball_load"], res["loaded_balls"], res["min_contact_angle"],
                             res["max_contact_angle"], element_loads)
    elements = Elements(balls, ball_row, np.empty((0, 8)), 0.0)
    cases = CaseBlock(inputs, np.zeros(0, np.int64), np.zeros(0), None, None, results)
    sweep(elements, Positions(tables, slice_tables, speed_tables), cases, given_load, settings, stop)
    if stop[0] != 0:
        return  # incomplete: the runner discards the block
    for name, values in variation_summary(res["K"]).items():
        res[name][...] = values
    res["K_amplitude"][...], res["K_phase"][...] = fourier(res["K"], harmonics)


def position_tables(cfg: PassageConfig, spinning: bool):
    """The kernel's tables at every position: ball tables (P, N_BALL_COLUMNS, n_balls), slice tables or None
    (no roller rows: no roller code compiled), and at speed with defects the high-speed tables per position
    (else None: the bearing's one), each element's defect depth folded in (model/defects.py)."""
    b = cfg.bearing
    tables = [b.ball_table(a) for a in cfg.cage_angles]
    slices = [b.slice_table(a) for a in cfg.cage_angles] if b.roller_rows else None
    speed = None
    if cfg.defects:
        speed = [] if spinning else None
        for p, shaft in enumerate(cfg.shaft_angles):
            psi = table_azimuths(tables[p], slices[p] if slices else None, b.n_elements)
            inner, outer = element_depths(cfg.defects, cfg.kinematics, psi, shaft)
            n = b.n_balls
            if spinning:
                speed.append(with_speed_defects(b.speed_table, inner[:n], outer[:n]))
                if np.any(inner[:n]) or np.any(outer[:n]):
                    tables[p] = without_mirror_half(tables[p])
            else:
                tables[p] = with_ball_defects(tables[p], inner[:n] + outer[:n])
            if slices:
                slices[p] = with_slice_defects(slices[p], inner + outer, n)
    stack = np.ascontiguousarray
    return (stack(np.stack(tables)), stack(np.stack(slices)) if slices else None,
            stack(np.stack(speed)) if speed else None)


def job(cfg: PassageConfig, device: str = "cpu") -> jobs.Job:
    """The ball-passage table as a job for the runner; ``device`` "cuda" computes its blocks on the GPU."""
    C = storage.Coordinate
    P = cfg.n_positions
    H = min(cfg.harmonics, P // 2)
    if cfg.revolutions:  # over shaft revolutions: harmonic h is the order h / revolutions of the shaft speed
        own = (C("position", np.arange(P), "1", f"position over {cfg.revolutions} shaft revolution(s), "
                 f"{cfg.positions} per revolution"),
               C("harmonic", np.arange(H + 1), "1", "harmonic of the table's period (revolutions shaft turns)"))
        aux = [(C("cage_angle", cfg.cage_angles, "rad", "cage rotation from the first ball's azimuth"), "position"),
               (C("shaft_angle", cfg.shaft_angles, "rad", "shaft rotation from position 0"), "position"),
               (C("order", np.arange(H + 1) / cfg.revolutions, "1", "order of the shaft speed of each harmonic"),
                "harmonic")]
    else:
        own = (C("position", np.arange(P), "1", "cage position within one period"),
               C("harmonic", np.arange(H + 1), "1", "harmonic order of the ball-pass frequency"))
        aux = [(C("cage_angle", cfg.cage_angles, "rad", "cage rotation from the first ball's azimuth"), "position")]
    if cfg.element_loads:
        own += (C("element", np.arange(cfg.bearing.n_elements), "1", "element (ball or roller) number in the "
                  "bearing's element order"),)
    attrs = {"period_rad": cfg.period, "period_order": cfg.period_order, "positions": cfg.positions,
             "n_points": cfg.cases.n_cases, "speed_rpm": cfg.model_speed, **cfg.operating}
    if cfg.fixed:
        attrs.update(fixed_dofs=", ".join(boundary.names(cfg.fixed)),
                     fixed_note="the degrees of freedom in fixed_dofs are given as displacements (their axes, mm "
                                "or rad); f holds the reactions there (N, N*mm)")
    if cfg.revolutions:
        k = cfg.kinematics
        row0 = cfg.bearing.rows[0]
        attrs.update(revolutions=cfg.revolutions, positions_per_revolution=cfg.positions, rotating_ring=k.rotating,
                     first_element_angle_deg=getattr(row0, "first_ball_angle", getattr(row0, "first_element_angle", 0.0)),
                     defects=json.dumps([vars(d) for d in cfg.defects]),
                     defects_units="angle deg (at position 0, from +x; a ball's from its outer contact), width mm, "
                                   "depth mm")
        n_balls = cfg.bearing.rows[0].n_elements
        for name, order in fault_orders(k.ball_diameter, k.pitch_diameter, n_balls, math.degrees(k.contact_angle),
                                        k.rotating).items():
            attrs[f"fault_frequency_{name}_order"] = order
    if cfg.speed is not None:
        fc = cfg.speed.cage_frequency
        aux.append((C("time", cfg.cage_angles / (2 * math.pi * fc), "s", "time from position 0"), "position"))
        if cfg.revolutions:
            fr = cfg.speed.shaft_speed / 60.0
            aux.append((C("frequency", np.arange(H + 1) / cfg.revolutions * fr, "Hz", "frequency of each harmonic"),
                        "harmonic"))
            for name in ("FTF", "BPFO", "BPFI", "BSF", "ball_defect"):
                attrs[f"fault_frequency_{name}_hz"] = attrs[f"fault_frequency_{name}_order"] * fr
        else:
            aux.append((C("frequency", np.arange(H + 1) * cfg.period_order * fc, "Hz", "frequency of each harmonic"),
                        "harmonic"))
        attrs.update(shaft_speed_rpm=cfg.speed.shaft_speed, rotating_ring=cfg.speed.rotating,
                     ball_diameter_mm=cfg.speed.ball_diameter, pitch_diameter_mm=cfg.speed.pitch_diameter,
                     cage_frequency_hz=fc, ball_pass_frequency_hz=cfg.period_order * fc)
    spinning = cfg.model_speed > 0
    tables, slice_tables, speed_tables = position_tables(cfg, spinning)
    settings = solver_settings(cfg.bearing, cfg.method, cfg.rtol, cfg.max_iter, cfg.fixed)
    compute = partial(compute_block, tables, slice_tables,
                      cfg.bearing.ball_set(speed=cfg.model_speed if spinning else None),
                      cfg.bearing.element_rows, cfg.cases.given == "load", settings, cfg.harmonics, speed_tables,
                      device=device)
    sizes = {"dof": 5, "dof_col": 5, "row": cfg.bearing.n_rows, "position": P, "harmonic": H + 1,
             "element": cfg.bearing.n_elements}
    return jobs.Job(
        kind="ball-passage table", bearing=cfg.bearing, cases=cfg.cases, variables=tuple(_variables(cfg)),
        sizes=sizes, compute=compute, settings=settings, method=cfg.method, chunk=cfg.chunk, text=cfg.text,
        source=cfg.source, fingerprint=cfg.fingerprint, own_dims=own, aux_coords=tuple(aux), attrs=attrs,
        solves_per_case=P, case_word="point",
        kernel="engine.gpu.passage_sweep_cuda" if device == "cuda" else "engine.sweep.passage_sweep")


def passage(config, output=None, *, threads=None, resume=False, overwrite=False, csv_files=False, progress=None,
            as_dataset=False, client=None, max_in_flight=None, device="cpu"):
    """Compute ball-passage stiffness tables and write them to HDF5 or a zarr store (and optionally CSV).

    Runs through the same job runner as a load map: resumable, Ctrl-C safe,
    with a progress bar and an optional Dask cluster.

    Parameters
    ----------
    config : str, Path or dict
        A TOML config with ``[bearing]`` and ``[passage]`` tables, or the same as a dict.
    output : str or Path, optional
        Output file (default: the config's name with suffix .h5, in the
        current folder); never replaced unless ``overwrite``.
    threads : int, optional
        Numba threads; results do not depend on it.
    resume : bool
        Continue an interrupted run from ``OUTPUT.part`` (same config only).
    overwrite : bool
        Replace existing output files or discard an unfinished run.
    csv_files : bool
        Also write ``OUTPUT_point0000.csv`` ... (named after the output): one per operating point, from the
        finished file, in the dialect of ``fastbearing export --format csv``: the point's inputs (N, N*mm or
        mm, rad), position, cage angle (rad), time (s, if a speed is given), status, all 25 Kb entries (N/mm,
        N*mm/rad, N/rad), status name and matrix.
    progress : bool, optional
        Progress bar on stderr (default: only when stderr is a terminal).
    as_dataset : bool
        Return an ``xarray.Dataset`` instead of the path.
    client : dask.distributed.Client, optional
        Run the blocks on a Dask cluster; the output is identical to a local run.
    max_in_flight : int, optional
        With ``client``: blocks out on the cluster at once (default: 2 per worker thread).
    device : {"cpu", "cuda"}
        Where the blocks are computed (default "cpu"); "cuda": on the GPU, one operating point per GPU thread,
        with the same kernels (numba-cuda). Without numba-cuda, a CUDA driver or a GPU,
        fastbearing.engine.device.CudaUnavailable names what is missing before any work is done.

    Returns
    -------
    pathlib.Path or xarray.Dataset
        The absolute path of the finished HDF5 file (netCDF4-compatible), or
        with ``as_dataset`` that file opened as an ``xarray.Dataset``. Its
        case dimensions (written ``...`` below) are ``point`` for
        ``points``, or one per grid axis (e.g. ``dx``, ``dz``); then
        ``position`` (cage positions in one period), ``harmonic``, ``row``
        and ``dof``, ``dof_col`` (5 each). Per case and position: ``q``
        (..., position, 5) in mm and rad, ``f`` (..., position, 5) in N and
        N*mm, ``K`` (..., position, 5, 5) in N/mm, N*mm/rad, N/rad,
        ``status``, ``iterations``, ``residual`` (..., position), and per
        row ``max_ball_load`` (N), ``loaded_balls``, ``min_contact_angle``
        and ``max_contact_angle`` (rad) (..., position, row). Per case over
        the period: ``K_mean``, ``K_min``, ``K_max`` (..., 5, 5) in Kb's
        units, ``K_variation`` (..., 5, 5) in %, ``K_amplitude`` (...,
        harmonic, 5, 5) in Kb's units and ``K_phase`` in rad. Coordinates:
        ``cage_angle`` (position) in rad and, with a shaft speed, ``time``
        (position) in s and ``frequency`` (harmonic) in Hz. With
        ``csv_files`` the CSV files are written beside it.
    """
    cfg = config if isinstance(config, PassageConfig) else read_config(config)
    if as_dataset:
        jobs.require_xarray()
    device = jobs.check_device(device, client)
    out = jobs.output_path(output, cfg.source)
    if csv_files and not isinstance(out, Path):
        raise ValueError(f"csv_files (--csv) writes beside a local output; {out} is a URL")
    csv_paths = [out.with_name(f"{out.stem}_point{i:04d}.csv") for i in range(cfg.cases.n_cases)] if csv_files else []
    existing = [p for p in csv_paths if p.exists()]
    if existing and not overwrite:
        raise ValueError(f"{existing[0]} exists; pass --overwrite to replace it")
    out = jobs.run(job(cfg, device), out, threads=threads, resume=resume, overwrite=overwrite, progress=progress,
                   client=client, max_in_flight=max_in_flight)
    if csv_paths:
        _write_csv_files(out, cfg, csv_paths, overwrite)
    return jobs.open_dataset(out) if as_dataset else out


def _write_csv_files(h5: Path, cfg: PassageConfig, paths: list[Path], overwrite: bool = False) -> None:
    """One CSV per operating point, read point by point from the finished file (memory: one point), in the
    export's dialect (:func:`fastbearing.jobs.csv_table.write_csv`, the writer `fastbearing export
    --format csv` uses): case, the point's inputs (Fx_N ... My_N_mm or dx_mm ... by_rad), position,
    cage_angle_rad (and time_s, shaft_angle_rad where the table has them), status, all 25 Kb entries
    (kxx_N_per_mm ...), status_name and matrix."""
    from .csv_table import case_coordinates, write_csv
    from .storage import ResultFile

    with ResultFile(h5) as rf:
        shape = rf.shape("K")[:-2]
        n = int(np.prod(shape[:-1]))          # operating points; the last dim is the position
        per = shape[-1]
        coords = case_coordinates(rf)         # every case's coordinates, flat over (points..., position)
        coords.setdefault("position", (np.tile(np.arange(per, dtype=float), n), "1"))
        for i, path in enumerate(paths):
            index = np.unravel_index(i, shape[:-1])
            cases = slice(i * per, (i + 1) * per)
            status = rf.read("status", index).reshape(-1) if rf.has("status") else None
            write_csv(path, rf.read("K", index), overwrite=overwrite, status=status,
                      coords={name: (values[cases], units) for name, (values, units) in coords.items()},
                      first_case=i * per)
