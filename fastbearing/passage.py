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

import csv
import hashlib
import json
import math
import sys
import time
from dataclasses import dataclass
from functools import reduce
from pathlib import Path

import numpy as np

from . import storage, validate
from .api import check_threads, num_threads, solver_settings
from .bearing import ROW, Bearing
from .bearing_file import read_job_config
from .grid import AXES, LONG_NAMES, UNITS, Axis, CaseSet, parse_axis, plan_blocks
from .sweep import passage_sweep

_PASSAGE_KEYS = {"given", "points", "positions", "harmonics", "shaft_speed", "ball_diameter", "pitch_diameter",
                 "rotating", "method", "rtol", "max_iter", "chunk"}
#: Most cage positions per period (a sanity bound: 64 resolve the ball-pass harmonics well).
MAX_POSITIONS = 100_000
#: The 15 independent entries of Kb, as (row, column, CSV column name with units).
K_ENTRIES = [(i, j, f"k{a}{b}_{u}") for i, a in enumerate(("x", "y", "z", "tx", "ty"))
             for j, b in enumerate(("x", "y", "z", "tx", "ty")) if j >= i
             for u in ["N/mm" if i < 3 and j < 3 else "N*mm/rad" if i >= 3 and j >= 3 else "N/rad"]]


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
    speed: CageSpeed | None
    method: str
    rtol: float | None
    max_iter: int | None
    chunk: int
    text: str
    source: Path | None
    fingerprint: str

    @property
    def period_order(self) -> int:
        """gcd of the rows' ball counts: the table repeats after a cage turn of 2*pi/period_order."""
        return reduce(math.gcd, (r.n_balls for r in self.bearing.rows))

    @property
    def period(self) -> float:
        """Cage-angle period of the table, rad."""
        return 2.0 * math.pi / self.period_order

    @property
    def cage_angles(self) -> np.ndarray:
        """Cage angle of each position, rad; position 0 is the bearing definition's own layout."""
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
    axes_given = [k for k in spec if k in names]
    if "points" in spec:
        if axes_given:
            raise ValueError(f"passage.points replaces the grid axes; remove {axes_given}")
        points = validate.array(spec["points"], "passage.points", min_length=1)
        table = np.array([validate.numbers_list(p, f"passage.points[{i}]", 5) for i, p in enumerate(points)])
        cases = CaseSet(given, table=table, table_dim="point")
    elif axes_given:
        axes = []
        for name, units in zip(names, UNITS[given]):
            values, is_dim = parse_axis(name, spec.get(name, 0.0), "passage")
            axes.append(Axis(name, values, units, is_dim))
        cases = CaseSet(given, axes=tuple(axes), table_dim="point")
        if not cases.dims:  # constants only: one operating point
            cases = CaseSet(given, table=cases.inputs(0, 1), table_dim="point")
    else:
        raise ValueError(f"passage needs points = [[...], ...] or grid axes ({', '.join(names)})")
    cases.check_size("passage")
    speed = None
    speed_keys = [k for k in ("shaft_speed", "ball_diameter", "pitch_diameter") if k in spec]
    if speed_keys:
        if len(speed_keys) != 3:
            raise ValueError("passage: the time axis needs shaft_speed (rpm), ball_diameter and pitch_diameter "
                             f"(mm) together; got only {speed_keys}")
        D = validate.number(spec["ball_diameter"], "passage.ball_diameter", low=0, low_open=True, units="mm")
        dm = validate.number(spec["pitch_diameter"], "passage.pitch_diameter", low=D, low_open=True, units="mm")
        rotating = validate.choice(spec.get("rotating", "inner"), "passage.rotating", ("inner", "outer"))
        rpm = validate.number(spec["shaft_speed"], "passage.shaft_speed", low=0, low_open=True, units="rpm")
        speed = CageSpeed(rpm, D, dm, math.radians(bearing.rows[0].contact_angle), rotating)
    elif "rotating" in spec:
        raise ValueError("passage.rotating needs shaft_speed, ball_diameter and pitch_diameter")
    digest = hashlib.sha256(text.encode()).hexdigest()
    return PassageConfig(bearing, cases, positions, harmonics, speed, method, spec.get("rtol"),
                         spec.get("max_iter"), chunk, text, source, digest)


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
    """Per point: the per-position results and the summaries over the period."""
    V = storage.Variable
    K_units = "N/mm, N*mm/rad, N/rad"
    return storage.result_variables(cfg.cases.given, inner=("position",)) + [
        V("K_mean", ("dof", "dof_col"), "f8", K_units, "mean of Kb over one period"),
        V("K_min", ("dof", "dof_col"), "f8", K_units, "minimum of Kb over one period"),
        V("K_max", ("dof", "dof_col"), "f8", K_units, "maximum of Kb over one period"),
        V("K_variation", ("dof", "dof_col"), "f8", "%",
          "peak-to-peak variation of Kb over one period in % of |mean| (nan where the mean is ~0)"),
        V("K_amplitude", ("harmonic", "dof", "dof_col"), "f8", K_units,
          "Fourier amplitude A_h of Kb: K = sum_h A_h cos(h*2*pi*position/positions + phi_h)"),
        V("K_phase", ("harmonic", "dof", "dof_col"), "f8", "rad", "Fourier phase phi_h of Kb"),
    ]


def _create(cfg: PassageConfig, part: Path, blocks) -> list[storage.Variable]:
    import h5py

    C = storage.Coordinate
    cases = cfg.cases
    aux = []
    if cases.table is not None:
        case_dims = [C("point", np.arange(cases.n_cases), "1", "operating point number")]
        aux += [(C(n, cases.table[:, i], u, LONG_NAMES[n]), "point")
                for i, (n, u) in enumerate(zip(AXES[cases.given], UNITS[cases.given]))]
        scalars = []
    else:
        case_dims = [C(a.name, a.values, a.units, LONG_NAMES[a.name]) for a in cases.dims]
        scalars = [C(a.name, a.values, a.units, LONG_NAMES[a.name], False) for a in cases.axes if not a.is_dim]
    H = min(cfg.harmonics, cfg.positions // 2)
    labels = np.array(storage.DOF_LABELS, dtype=h5py.string_dtype())
    extra = [C("position", np.arange(cfg.positions), "1", "cage position within one period"),
             C("harmonic", np.arange(H + 1), "1", "harmonic order of the ball-pass frequency"),
             C("dof", labels, "1", "degree of freedom: x, y, z translations; tx, ty tilts"),
             C("dof_col", labels, "1", "degree of freedom (column of K)"),
             C("row", np.arange(cfg.bearing.n_rows), "1", "bearing row (as in the bearing definition)")]
    aux.append((C("cage_angle", cfg.cage_angles, "rad",
                  "cage rotation from the bearing definition's first-ball azimuth"), "position"))
    attrs = {"period_rad": cfg.period, "period_order": cfg.period_order}
    if cfg.speed is not None:
        fc = cfg.speed.cage_frequency
        aux.append((C("time", cfg.cage_angles / (2 * math.pi * fc), "s", "time from position 0"), "position"))
        aux.append((C("frequency", np.arange(H + 1) * cfg.period_order * fc, "Hz",
                      "frequency of each harmonic"), "harmonic"))
        attrs.update(shaft_speed_rpm=cfg.speed.shaft_speed, rotating_ring=cfg.speed.rotating,
                     ball_diameter_mm=cfg.speed.ball_diameter, pitch_diameter_mm=cfg.speed.pitch_diameter,
                     cage_frequency_hz=fc, ball_pass_frequency_hz=cfg.period_order * fc)
    variables = _variables(cfg)
    opts = solver_settings(cfg.bearing, cfg.method, cfg.rtol, cfg.max_iter)
    attrs.update({
        "title": "fastbearing ball-passage stiffness table", "Conventions": "CF-1.8", "given": cases.given,
        "units_convention": "N, mm, rad; moments N*mm; stiffness N/mm, N*mm/rad, N/rad; time s",
        "config": cfg.text, "config_source": str(cfg.source or ""), "config_fingerprint": cfg.fingerprint,
        "bearing": cfg.bearing.describe(), "bearing_json": json.dumps(cfg.bearing.to_dict()),
        "solver_method": cfg.method, "solver_rtol": opts.rtol, "solver_max_iter": opts.max_iter,
        "positions": cfg.positions, "n_points": cases.n_cases, **storage.versions()})
    storage.create(part, case_dims, extra, scalars, variables, attrs, len(blocks), aux)
    return variables


def passage(config, output=None, *, threads=None, overwrite=False, csv_files=False, as_dataset=False):
    """Compute ball-passage stiffness tables and write them to HDF5 (and optionally CSV).

    Parameters
    ----------
    config : str, Path or dict
        A TOML config with ``[bearing]`` and ``[passage]`` tables, or the same as a dict.
    output : str or Path, optional
        Output file (default: the config's path with suffix .h5); never
        replaced unless ``overwrite``.
    threads : int, optional
        Numba threads; results do not depend on it.
    csv_files : bool
        Also write ``OUTPUT_point0000.csv`` ...: one per operating point, with
        cage angle (rad), time (s, if a speed is given) and the 15
        independent Kb entries.
    as_dataset : bool
        Return an ``xarray.Dataset`` instead of the path.
    """
    cfg = config if isinstance(config, PassageConfig) else read_config(config)
    check_threads(threads)
    if as_dataset:
        from .loadmap import _require_xarray

        _require_xarray()
    if output is None:
        if cfg.source is None:
            raise ValueError("output is required when the config is not a file")
        output = Path(cfg.source.name).with_suffix(".h5")  # in the current folder, like every other output
    out = Path(output)
    storage.check_output_path(out)
    H = min(cfg.harmonics, cfg.positions // 2)
    sizes = {"dof": 5, "dof_col": 5, "row": cfg.bearing.n_rows, "position": cfg.positions, "harmonic": H + 1}
    storage.check_disk_space(out, cfg.cases.n_cases * storage.bytes_per_case(_variables(cfg), sizes),
                             f"this table ({cfg.cases.n_cases} points x {cfg.positions} positions)")
    csv_paths = [out.with_name(f"{out.stem}_point{i:04d}.csv") for i in range(cfg.cases.n_cases)] if csv_files else []
    existing = [p for p in csv_paths if p.exists()]
    if existing and not overwrite:
        raise ValueError(f"{existing[0]} exists; pass --overwrite to replace it")
    out, part, _ = storage.prepare_output(out, cfg.fingerprint, False, overwrite)
    cases = cfg.cases
    blocks = plan_blocks(cases.shape, 1, cfg.chunk)
    variables = _create(cfg, part, blocks)
    tables = np.ascontiguousarray(np.stack([cfg.bearing.ball_table(a) for a in cfg.cage_angles]))
    ball_row = tables[0, ROW].astype(np.int64)
    opts = solver_settings(cfg.bearing, cfg.method, cfg.rtol, cfg.max_iter)
    started = time.perf_counter()
    pf = storage.PartFile(part)
    n_rows, P = cfg.bearing.n_rows, cfg.positions
    counts: dict[int, int] = {}
    with num_threads(threads):
        for block in blocks:
            n = block.size
            res = {"q": np.empty((n, P, 5)), "f": np.empty((n, P, 5)), "K": np.empty((n, P, 5, 5)),
                   "status": np.empty((n, P), np.int8), "iterations": np.empty((n, P), np.int32),
                   "residual": np.empty((n, P)), "max_ball_load": np.empty((n, P, n_rows)),
                   "loaded_balls": np.empty((n, P, n_rows), np.int16), "min_contact_angle": np.empty((n, P, n_rows)),
                   "max_contact_angle": np.empty((n, P, n_rows))}
            passage_sweep(cases.inputs(block.start, block.stop), cases.given == "load", tables,
                          cfg.bearing.ball_exponents, res["q"], res["f"],
                          res["K"], res["status"], res["iterations"], res["residual"], res["max_ball_load"],
                          res["loaded_balls"], res["min_contact_angle"], res["max_contact_angle"], ball_row, opts)
            res.update(variation_summary(res["K"]))
            res["K_amplitude"], res["K_phase"] = fourier(res["K"], cfg.harmonics)
            pf.write(block.slab, res)
            pf.mark_done(block.index)
            for code, k in zip(*np.unique(res["status"], return_counts=True)):
                counts[int(code)] = counts.get(int(code), 0) + int(k)
            for i, path in enumerate(csv_paths[block.start:block.stop]):
                _write_csv(path, cfg, res["K"][i])
    pf.close()
    wall = time.perf_counter() - started
    from . import status as st

    storage.finish(part, out, "none", blocks, {"wall_time_s": wall, "status_counts": json.dumps(
        {st.describe(c): k for c, k in counts.items()})}, [v.name for v in variables])
    total = cases.n_cases * P
    ok = sum(k for c, k in counts.items() if st.is_converged(c))
    print(f"fastbearing: {cases.n_cases} points x {P} positions, {100.0 * ok / total:.2f} % converged; "
          f"{wall:.2f} s wall", file=sys.stderr)
    if as_dataset:
        from .loadmap import open_dataset

        return open_dataset(out)
    return out.absolute()


def _write_csv(path: Path, cfg: PassageConfig, K: np.ndarray) -> None:
    """One operating point: position, cage angle (rad), time (s) if known, then the 15 Kb entries."""
    header = ["position", "cage_angle_rad"] + (["time_s"] if cfg.speed else []) + [e[2] for e in K_ENTRIES]
    angles = cfg.cage_angles
    times = angles / (2 * math.pi * cfg.speed.cage_frequency) if cfg.speed else None
    tmp = path.with_name(path.name + ".part")
    with tmp.open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        for p in range(K.shape[0]):
            row = [p, repr(float(angles[p]))] + ([repr(float(times[p]))] if times is not None else [])
            w.writerow(row + [repr(float(K[p, i, j])) for i, j, _ in K_ENTRIES])
    tmp.replace(path)
