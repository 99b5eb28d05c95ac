"""Hand Kb to downstream tools: CSV, JSON, NumPy .npz, Nastran DMIG, ROSS bearing arguments.

Every format states its DOF order (x, y, z, tx, ty: translations along and
tilts about x and y; z is the shaft axis), its units and which matrix it
holds (a bearing's Kb, one bearing of a shaft, or a shaft's K_system).
fastbearing's units are N, mm, rad: Kb in N/mm (translations), N*mm/rad
(tilts), N/rad (coupling).

CSV files have one header row, read as it is by ``pandas.read_csv(path)``
and ``numpy.genfromtxt(path, delimiter=",", names=True, dtype=None)``: each
column name ends in its units (``Fx_N``, ``My_N_mm``, ``dx_mm``,
``kxx_N_per_mm``, ``kxtx_N_per_rad``, ``ktxty_N_mm_per_rad``; ``*`` is
written ``_`` and ``/`` ``_per_``); the numeric columns come first, the text
columns ``status_name`` and ``matrix`` last.
"""

from __future__ import annotations

import json
import re
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..dofs import DOF_LABELS as DOF
from ..files import publish as _publish
from ..files import refuse_overwrite
# the CSV dialect lives in jobs/csv_table.py (the passage job writes it too); its functions are re-exported here
from ..jobs.csv_table import (K_COLUMNS, KB, as_matrices as _as_matrices, case_coordinates as _case_coordinates,
                               coordinate_columns as _coordinate_columns, csv_header, read_csv,
                               status_columns as _status_columns, units_suffix, write_csv)

UNITS = "N/mm among x, y, z; N*mm/rad among tx, ty; N/rad between translations and tilts"
FORMATS = ("csv", "json", "npz", "dmig", "ross")
#: Nastran component numbers of the DOF order above (1-3 translations, 4-5 rotations).
NASTRAN_COMPONENTS = (1, 2, 3, 4, 5)
#: Where a bearing's Kb acts (DMIG placement note).
KB_CENTRE = "the bearing centre"
#: The keys of a ROSS export that are fastbearing's notes, not BearingElement arguments.
ROSS_NOTES = ("units", "matrix", "dropped", "source", "case")


#: An entry below this fraction of its row's largest |entry| is round-off noise (an exact zero computed as
#: 1e-26, say): printed as 0 and not reported as a coupling ROSS drops.
NOISE = 1e-12


def noise_as_zero(K, rel: float = NOISE) -> np.ndarray:
    """A copy of ``K`` (5x5, or N x 5 x 5; any units) with every entry whose magnitude is below ``rel`` times
    the largest magnitude of its row set to 0 (and -0 to 0): the matrix as printed. A row that is all zero
    stays so; non-finite entries are kept as they are."""
    K = np.array(K, dtype=float)
    finite = np.isfinite(K)
    scale = np.max(np.where(finite, np.abs(K), 0.0), axis=-1, keepdims=True)
    K[finite & (np.abs(K) < rel * scale)] = 0.0
    return K + 0.0


@dataclass(frozen=True)
class Source:
    """Kb read from a solve/shaft JSON or a finished map or table: ``K`` (5, 5) or (N, 5, 5), each case's
    ``status`` name, ``coords`` (what each case is: name -> (values (N,), units), the five inputs Fx ... My
    or dx ... by first, then e.g. position, cage_angle), and ``extra`` fields (q, f of a solve) to carry into
    JSON exports. ``picked`` describes the case chosen by ``--at`` (empty otherwise). ``codes``: each case's
    integer status code (fastbearing.status) where the source stores them (a .h5 file), else None.
    ``matrix`` says which matrix K is (e.g. "bearing stiffness Kb", a shaft bearing's Kb, a shaft's
    K_system) and ``centre`` where it acts (the point a DMIG grid must sit at). ``results``: what the source
    computed beside K for each case, name -> (values (N,), units): a map's rating lives (L10r, L10r_row0 ...,
    static_safety, L10, L10r_hours, L10_hours) where it has them, a solve's load f (Fx ... My) and speed.
    ``case``: which case K is and where it comes from, in words (the source file, and the --case index or
    --at values), for the files that hold one case (DMIG, ROSS)."""

    K: np.ndarray
    status: list[str]
    extra: dict
    coords: dict = field(default_factory=dict)
    picked: str = ""
    codes: np.ndarray | None = None
    matrix: str = KB
    centre: str = KB_CENTRE
    results: dict = field(default_factory=dict)
    case: str = ""

    @property
    def unconverged(self) -> list[int]:
        """Indices of cases whose solve did not converge (status not converged/unloaded/direct)."""
        return [i for i, s in enumerate(self.status) if not _usable(s)]


def _usable(status: str) -> bool:
    return status.split("+")[0] in ("converged", "unloaded", "direct")


def parse_at(text: str) -> dict[str, float]:
    """``"Fx=1000,Fz=3000,My=0"`` as {"Fx": 1000.0, ...}; ValueError names what is wrong."""
    out = {}
    for item in text.split(","):
        name, sep, value = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise ValueError(f"--at takes NAME=VALUE pairs separated by commas (e.g. Fx=1000,Fz=3000), got {item!r}")
        try:
            number = float(value)
        except ValueError:
            raise ValueError(f"--at {name} must be a number, got {value.strip()!r}") from None
        if not np.isfinite(number):
            raise ValueError(f"--at {name} must be finite, got {value.strip()!r}")
        if name in out:
            raise ValueError(f"--at names {name} twice")
        out[name] = number
    return out


def read_source(path, case: int | None = None, at: dict | None = None, bearing: str | int | None = None,
                system: bool = False) -> Source:
    """Kb from ``fastbearing solve --json`` / ``shaft --json`` output (.json), a finished .h5 file or a
    finished zarr store (a .zarr folder or URL).

    ``case`` picks one case (flat index) of a .h5 map or table, ``at`` the grid point nearest to
    given coordinates (e.g. {"Fx": 1000.0, "Fz": 3000.0, "My": 0.0}: every varying axis, values in the
    axis' units (N, N*mm; mm, rad); a case table's or passage table's own dims by index, e.g.
    {"point": 3, "position": 0}; a value beyond an axis' first or last grid value is refused); both are
    refused for a .json source, which holds one matrix. An unfinished file (a ``.part``, however named) is
    refused.

    A ``shaft --json`` output holds several matrices: ``bearing`` picks one bearing's own Kb (about its
    centre; the bearing's ``name`` where the JSON carries names, or its index in the JSON's ``bearings``
    list), ``system`` the shaft's K_system at the reference point; one of the two is required there, and
    both are refused for any other source.
    """
    from ..jobs.locations import is_url
    from ..jobs.zarr_store import is_zarr_location

    store = is_zarr_location(path)                 # a zarr store: a folder, or a URL
    path = path if is_url(path) else Path(path)
    if not store and not path.is_file():
        raise ValueError(f"file not found: {path}" if not path.exists() else f"{path} is not a file")
    if store and isinstance(path, Path) and not path.is_dir():
        raise ValueError(f"zarr store not found: {path}")
    if case is not None and at is not None:
        raise ValueError("give --case or --at, not both")
    if bearing is not None and system:
        raise ValueError("give --bearing or --system, not both")
    suffix = ".zarr" if store else path.suffix.lower()
    if suffix == ".json":
        if case is not None or at is not None:
            raise ValueError(f"--{'case' if case is not None else 'at'} picks a case of a .h5 map or table; "
                             "a .json source holds one matrix")
        try:
            body = json.loads(path.read_text())
        except (ValueError, UnicodeDecodeError):
            raise ValueError(f"{path} is not JSON from `fastbearing solve --json` or `shaft --json`") from None
        if not isinstance(body, dict) or not ({"K", "K_system"} & set(body)):
            raise ValueError(f"{path} has no K or K_system: use the output of `solve --json` or `shaft --json`")
        status = body.get("status", "converged")
        status = status if isinstance(status, str) else "unknown"
        if "K_system" in body and "K" not in body:
            from dataclasses import replace

            picked = _shaft_source(path, body, status, bearing, system)
            return replace(picked, case=f"{picked.matrix}, from {path.name} (shaft --json)")
        if bearing is not None or system:
            raise ValueError(f"--{'bearing' if bearing is not None else 'system'} picks a matrix of a "
                             f"`shaft --json` output; {path.name} is a single bearing's (solve --json)")
        K = _matrix_field(body["K"], f"{path.name}: K")
        results = _solve_results(body)
        point = ", ".join(f"{name} = {v[0]:g} {units}" for name, (v, units) in results.items())
        return Source(K, [status], {k: body[k] for k in ("q", "f", "status") if k in body}, results=results,
                      case=f"the operating point of {path.name} (solve --json)" + (f": {point}" if point else ""))
    if suffix not in (".h5", ".hdf5", ".zarr"):
        raise ValueError(f"SOURCE must be a .json or .h5 file or a .zarr store, got {path.name!r}")
    if bearing is not None or system:
        raise ValueError(f"--{'bearing' if bearing is not None else 'system'} picks a matrix of a "
                         f"`shaft --json` output; {Path(str(path)).name} is a map or table of one bearing")
    from ..jobs.storage import COMPLETE, ResultFile

    with ResultFile(path) as rf:
        if int(rf.file_attrs.get(COMPLETE, 0)) != 1:
            raise ValueError(f"{path} is not a finished fastbearing file (an interrupted run's .part?); "
                             "finish it with --resume first")
        if not rf.has("K") or rf.shape("K")[-2:] != (5, 5) or rf.dtype("K").kind != "f":
            raise ValueError(f"{path} is not a fastbearing map or table (no 5 x 5 variable K)")
        lead = rf.shape("K")[:-2]
        n = int(np.prod(lead))
        coords = _case_coordinates(rf)
        results = _life_columns(rf)
        picked = ""
        if at is not None:
            case, picked = _nearest_case(rf, at)
        codes = rf.read("status").reshape(-1) if rf.has("status") else np.zeros(n, np.int8)
        if case is not None:
            if not 0 <= case < n:
                raise ValueError(f"--case must be in [0, {n - 1}] (the flat case index), got {case}")
            K = rf.read("K", np.unravel_index(case, lead))
            codes = codes[case:case + 1]
            coords = {k: (v[case:case + 1], u) for k, (v, u) in coords.items()}
            results = {k: (v[case:case + 1], u) for k, (v, u) in results.items()}
        else:
            K = rf.read("K").reshape(-1, 5, 5)
    from .. import status as st

    codes = np.asarray(codes).astype(np.int64)
    said = ""
    if case is not None:
        where = ", ".join(f"{name} = {v[0]:g}" + ("" if u in ("", "1") else f" {u}") for name, (v, u) in coords.items())
        said = (f"case {case} of {Path(str(path)).name}" + (f" (--at picked {picked.split('picked ', 1)[1]})"
                if picked else " (--case)") + (f": {where}" if where else ""))
    return Source(np.asarray(K, dtype=float), [st.describe(int(c)) for c in codes], {}, coords, picked,
                  codes=codes, results=results, case=said)


def read_series(path, over: str, at: dict | None = None) -> Source:
    """Kb of a finished map (.h5 file or zarr store) along one of its axes: ``over`` names the axis (e.g.
    "speed"), ``at`` the value of every other varying axis in its units (N, N*mm; mm, rad; rpm), the
    nearest grid value taken as :func:`read_source` takes it (an axis of one value needs none). The Source
    holds K (n, 5, 5) in the axis' order, each case's coordinates (the axis' values among them), status
    and lives, and ``case`` in words. ValueError names a missing or unknown axis."""
    from ..jobs.locations import is_url
    from ..jobs.storage import COMPLETE, ResultFile
    from ..jobs.zarr_store import is_zarr_location

    store = is_zarr_location(path)
    path = path if is_url(path) else Path(path)
    if not store and (Path(str(path)).suffix.lower() not in (".h5", ".hdf5") or not Path(path).is_file()):
        raise ValueError(f"--over takes a finished map (.h5 file or .zarr store), got {path}")
    at = dict(at or {})
    with ResultFile(path) as rf:
        if int(rf.file_attrs.get(COMPLETE, 0)) != 1:
            raise ValueError(f"{path} is not a finished fastbearing file (an interrupted run's .part?); "
                             "finish it with --resume first")
        lead = rf.dims("K")[:-2]
        shape = rf.shape("K")[:-2]
        if over not in lead:
            raise ValueError(f"--over must be one of this file's axes: {', '.join(lead)}; got {over!r}")
        if over in at:
            raise ValueError(f"--at names {over}, the axis --over runs along: name only the other axes")
        for dim, size in zip(lead, shape):  # an axis of one value: nothing to choose
            if dim != over and dim not in at and size == 1:
                at[dim] = float(np.asarray(rf.read(dim), float).reshape(-1)[0]) if rf.has(dim) else 0.0
        values = np.asarray(rf.read(over), float).reshape(-1) if rf.has(over) else np.arange(shape[lead.index(over)])
        cases, picked = [], ""
        for v in values:
            flat, said = _nearest_case(rf, {**at, over: float(v)})
            cases.append(flat)
            picked = picked or said
        K = np.stack([rf.read("K", np.unravel_index(c, shape)) for c in cases])
        coords = {k: (v[cases], u) for k, (v, u) in _case_coordinates(rf).items()}
        results = {k: (v[cases], u) for k, (v, u) in _life_columns(rf).items()}
        codes = (rf.read("status").reshape(-1)[cases] if rf.has("status") else np.zeros(len(cases), np.int8))
    from .. import status as st

    codes = np.asarray(codes).astype(np.int64)
    fixed = ", ".join(part for part in picked.replace("--at picked ", "").rsplit(":", 1)[0].split(", ")
                      if not part.startswith(f"{over}="))
    case = (f"cases {', '.join(map(str, cases))} of {Path(str(path)).name}: Kb over {over} "
            f"({values[0]:g} to {values[-1]:g}, {len(values)} values)" + (f" at {fixed}" if fixed else ""))
    return Source(K, [st.describe(int(c)) for c in codes], {}, coords, picked="", codes=codes, results=results,
                  case=case)


def _solve_results(body: dict) -> dict:
    """A solve's load f (Fx ... My: the load on the inner ring, N and N*mm; with --fix the reactions there)
    and shaft speed (rpm) as one-case results, where its JSON has them."""
    from ..dofs import LOAD_NAMES
    from ..dofs import UNITS as DOF_UNITS

    out = {}
    f = body.get("f")
    if isinstance(f, list) and len(f) == 5 and all(isinstance(v, (int, float)) for v in f):
        out.update({name: (np.array([float(v)]), units) for name, v, units in zip(LOAD_NAMES, f, DOF_UNITS["load"])})
    if isinstance(body.get("speed"), (int, float)):
        out["speed"] = (np.array([float(body["speed"])]), "rpm")
    return out


def _shaft_source(path: Path, body: dict, status: str, bearing, system: bool) -> Source:
    """One matrix of a ``shaft --json`` output: bearing ``bearing``'s own Kb or (``system``) K_system."""
    reference = body.get("reference")
    where = f" z = {reference:g} mm" if isinstance(reference, (int, float)) else ""
    bearings = body.get("bearings") if isinstance(body.get("bearings"), list) else []
    if not all(isinstance(b, dict) and "K" in b for b in bearings):
        raise ValueError(f"{path.name}: bearings must be a list of objects with K (`shaft --json` output)")
    names = [str(b.get("name") or "") for b in bearings]

    def label(i):
        pos = bearings[i].get("position")
        return (f"bearing {i}" + (f" {names[i]!r}" if names[i] else "")
                + (f" at z = {pos:g} mm" if isinstance(pos, (int, float)) else ""))

    listing = "; ".join(label(i) for i in range(len(bearings))) or "none listed"
    if bearing is None and not system:
        raise ValueError(f"{path.name} is a shaft's output: pick its matrix with --bearing NAME|N (its bearings: "
                         f"{listing}) or --system (K_system at the reference{where})")
    if system:
        K = _matrix_field(body["K_system"], f"{path.name}: K_system")
        extra = {k: body[k] for k in ("q", "status", "reference") if k in body}
        point = f"the shaft's reference point (z = {reference:g} mm)" if where else "the shaft's reference point"
        return Source(K, [status], extra, matrix=f"shaft system stiffness K_system at the reference{where}",
                      centre=point)
    text = str(bearing).strip()
    if text in names and text:
        i = names.index(text)
    elif re.fullmatch(r"[0-9]+", text) and int(text) < len(bearings):
        i = int(text)
    else:
        hint = "" if any(names) else " (this JSON carries no bearing names: give the index)"
        raise ValueError(f"--bearing {text!r} is no bearing of {path.name}: give a name or an index 0 to "
                         f"{len(bearings) - 1} (its bearings: {listing}){hint}")
    b = bearings[i]
    K = _matrix_field(b["K"], f"{path.name}: bearings[{i}].K")
    if K.ndim != 2:
        raise ValueError(f"{path.name}: bearings[{i}].K must be a 5 x 5 matrix of numbers")
    extra = {k: b[k] for k in ("name", "position", "q", "reaction") if k in b}
    if "status" in body:
        extra["status"] = body["status"]
    pos = b.get("position")
    at_pos = f" (z = {pos:g} mm on the shaft)" if isinstance(pos, (int, float)) else ""
    return Source(K, [status], extra, matrix=f"{KB} of shaft {label(i)} about its own centre",
                  centre=f"the centre of shaft bearing {i}{at_pos}")


#: A map's life variables (storage.life_variables) that the CSV, JSON and npz exports carry per case.
LIFE_COLUMNS = ("L10r", "L10r_row", "static_safety", "L10", "L10r_hours", "L10_hours")


def _life_columns(rf) -> dict:
    """Each case's rating lives where a map stores them, flattened as :func:`_case_coordinates`:
    name -> (values (N,), units); a per-row variable (L10r_row) as one column per row (L10r_row0 ...).
    {} for a file without life. ``rf``: a storage.ResultFile."""
    lead_dims = rf.dims("K")[:-2]
    n = int(np.prod(rf.shape("K")[:-2]))
    out = {}
    for name in LIFE_COLUMNS:
        if not rf.has(name) or tuple(rf.dims(name)[:len(lead_dims)]) != tuple(lead_dims):
            continue
        units = str(rf.attrs(name).get("units", "1"))
        values = np.asarray(rf.read(name), float).reshape(n, -1)
        if values.shape[1] == 1 and rf.ndim(name) == len(lead_dims):
            out[name] = (values[:, 0], units)
        else:
            for k in range(values.shape[1]):
                out[f"{name}{k}"] = (values[:, k], units)
    return out


def _nearest_case(rf, at: dict) -> tuple[int, str]:
    """The flat index of the case nearest to ``at`` along every leading dim of K (``rf``: a
    storage.ResultFile), and a line saying which. A value beyond an axis' first or last grid value (by more
    than 1e-9 of the grid spacing) is refused, naming the axis and its range: nearest is for points between
    grid values, not for extrapolation."""
    lead_dims = rf.dims("K")[:-2]
    shape = rf.shape("K")[:-2]
    unknown = sorted(set(at) - set(lead_dims))
    missing = [d for d in lead_dims if d not in at]
    if unknown or missing:
        wrong = "; ".join(part for part in (f"not an axis: {', '.join(unknown)}" if unknown else "",
                                            f"missing: {', '.join(missing)}" if missing else "") if part)
        raise ValueError(f"--at must name each varying axis of this file once: {', '.join(lead_dims)} ({wrong})")
    index, said = [], []
    for axis, dim in enumerate(lead_dims):
        values = rf.read(dim) if rf.has(dim) else np.arange(shape[axis])
        values = np.asarray(values, float).reshape(-1)
        low, high = float(values.min()), float(values.max())
        spacing = (high - low) / (len(values) - 1) if len(values) > 1 else 0.0
        tol = 1e-9 * (spacing or max(abs(low), abs(high), 1.0))
        if not low - tol <= at[dim] <= high + tol:
            units = str(rf.attrs(dim).get("units", "1")) if rf.has(dim) else "1"
            units = "" if units in ("", "1") else f" {units}"
            span = f"[{low:g}, {high:g}]" if len(values) > 1 else f"{low:g} only"
            raise ValueError(f"--at {dim}={at[dim]:g} is outside the grid's {dim} axis {span}{units} "
                             f"({len(values)} values): give a value within it")
        k = int(np.argmin(np.abs(values - at[dim])))
        index.append(k)
        exact = values[k] == at[dim]
        said.append(f"{dim}={values[k]:g}" + ("" if exact else f" (nearest to {at[dim]:g})"))
    flat = int(np.ravel_multi_index(index, shape))
    return flat, f"--at picked {', '.join(said)}: case {flat}"


def _matrix_field(value, name: str) -> np.ndarray:
    try:
        K = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a 5 x 5 matrix of numbers") from None
    if K.shape[-2:] != (5, 5) or K.ndim not in (2, 3):
        raise ValueError(f"{name} must be a 5 x 5 matrix of numbers, got shape {K.shape}")
    return K


def _check_output(path: Path, overwrite: bool) -> None:
    refuse_overwrite(path, overwrite)


def write_json(path, K, overwrite=False, extra: dict | None = None, coords: dict | None = None, status=None,
               matrix: str = KB, results: dict | None = None) -> Path:
    """{"matrix": which matrix, "dof": [...], "units": ..., "K": 5x5 or a list of them, "cases": {name:
    {"units", "values"}}}, with the integer ``status`` codes given (fastbearing.status) as "status_code"
    and their names as "status" (one value for one matrix, else a list), ``results`` (a map's lives, a
    solve's load and speed) as "results": {name: {"units", "values"}}, plus ``extra`` (e.g. q, f, status of
    a solve). Units: N, mm, rad (K: N/mm, N*mm/rad, N/rad)."""
    path = Path(path)
    _check_output(path, overwrite)
    Ks = _as_matrices(K)
    one = np.ndim(K) == 2
    body = {"matrix": matrix, "dof": list(DOF), "units": UNITS, "K": Ks[0].tolist() if one else Ks.tolist()}
    columns = _coordinate_columns(coords, len(Ks))
    if columns:
        body["cases"] = {name: {"units": units, "values": float(v[0]) if one else v.tolist()}
                         for name, v, units in columns}
    computed = _coordinate_columns(results, len(Ks))
    if computed:
        body["results"] = {name: {"units": units, "values": float(v[0]) if one else v.tolist()}
                           for name, v, units in computed}
    states = _status_columns(status, len(Ks))
    if states:
        body["status"] = states[1][0] if one else states[1]
        body["status_code"] = int(states[0][0]) if one else states[0].tolist()
    body.update(extra or {})
    return _publish(path, lambda tmp: tmp.write_text(json.dumps(body, indent=1)))


def write_npz(path, K, overwrite=False, coords: dict | None = None, status=None, matrix: str = KB,
              results: dict | None = None, **arrays) -> Path:
    """NumPy .npz with K, dof (names), units (text) and matrix (which matrix K is, text), each coordinate of
    ``coords`` as an array of its own name with its units in ``coordinate_units`` ("Fx: N", ...), the
    integer ``status`` codes given (fastbearing.status) as status and their names as status_name, each of
    ``results`` (a map's lives, a solve's load and speed) as an array of its own name with its units in
    ``result_units``, plus any other arrays given. Units: N, mm, rad (K: N/mm, N*mm/rad, N/rad)."""
    path = Path(path)
    _check_output(path, overwrite)
    Ks = _as_matrices(K)
    columns = _coordinate_columns(coords, len(Ks))
    named = {name: v for name, v, _ in columns}
    if columns:
        named["coordinate_units"] = np.array([f"{name}: {units}" for name, _, units in columns])
    computed = _coordinate_columns(results, len(Ks))
    named.update({name: v for name, v, _ in computed})
    if computed:
        named["result_units"] = np.array([f"{name}: {units}" for name, _, units in computed])
    clash = sorted(set(named) & {"K", "dof", "units", "matrix", "status", "status_name"})
    if clash:
        raise ValueError(f"coordinate names {clash} clash with the npz's own arrays")
    states = _status_columns(status, len(Ks))
    if states:
        named["status"], named["status_name"] = states[0], np.array(states[1])

    def write(tmp):
        with tmp.open("wb") as fh:
            np.savez(fh, K=np.asarray(K, dtype=float), dof=np.array(DOF), units=np.array(UNITS),
                     matrix=np.array(matrix), **named, **arrays)
    return _publish(path, write)


def _dmig_real(value: float) -> str:
    """A 16-character Nastran double-precision real, e.g. ' 1.234567890D+05'."""
    text = f"{value:.9E}".replace("E", "D")
    return f"{text:>16s}"


def _comment(text: str, width: int = 80) -> list[str]:
    """``text`` as Nastran comment lines ("$ ..."), each at most ``width`` characters."""
    import textwrap

    return ["$ " + line for line in textwrap.wrap(text, width - 2, break_on_hyphens=False)]


def write_dmig(path, K, grid: int, name: str = "KBRG", ground_grid: int | None = None, overwrite=False,
               matrix: str = KB, centre: str = KB_CENTRE, source: str | None = None, case: str = "") -> Path:
    """Nastran DMIG bulk data (large field, real double precision) for one 5x5 Kb.

    Units: fastbearing's N, mm, rad are Nastran's consistent N-mm-t-s system,
    so Kb goes in unchanged (N/mm, N*mm/rad, N/rad). The matrix acts on
    components 1-5 of ``grid`` (the inner ring / shaft node, outer ring
    grounded); with ``ground_grid`` it is written as the 10x10 spring
    [[K, -K], [-K, K]] between the two grids. Reference it in case control
    as K2GG = NAME. A symmetric Kb is written as its upper triangle (IFO = 6); a Kb that is not (at
    shaft speed: the friction of the balls' gyroscopic moments) as the whole square matrix (IFO = 1),
    so nothing of it is lost.

    Placement, said in the file's comment lines too: ``grid`` must sit at ``centre`` (the bearing centre
    for a bearing's Kb) with its output coordinate system's z along the shaft axis (fastbearing's x, y, z,
    tx, ty are components 1-5 there; a model whose shaft runs along x needs such a coordinate system on
    that grid, GRID's CD field); the ``ground_grid`` spring holds only when the two grids coincide (same
    point, same output system); an unsymmetric Kb needs a solution sequence that accepts an unsymmetric
    stiffness. ``matrix`` (which matrix K is) heads the comment lines; ``source`` (the file K was read
    from) and ``case`` (which of its cases, e.g. the --at values or the --case index) follow it as
    "$ source: ..." and "$ case: ..." lines.
    """
    path = Path(path)
    _check_output(path, overwrite)
    Ks = _as_matrices(K)
    if Ks.shape[0] != 1:
        raise ValueError("DMIG export takes one 5x5 matrix; pick a case of the map")
    if not (isinstance(name, str) and 1 <= len(name) <= 8 and name[0].isalpha() and name.isalnum()):
        raise ValueError(f"name must be 1-8 letters/digits starting with a letter (a Nastran name), got {name!r}")
    for label, g in (("grid", grid), ("ground_grid", ground_grid)):
        if g is not None and (isinstance(g, bool) or not isinstance(g, (int, np.integer)) or g < 1):
            raise ValueError(f"{label} must be a positive integer grid id, got {g!r}")
    k = Ks[0]
    symmetric = np.array_equal(k, k.T) or np.abs(k - k.T).max() <= 1e-13 * np.abs(k).max()
    dofs = [(grid, c) for c in NASTRAN_COMPONENTS]
    big = k
    if ground_grid is not None:
        dofs += [(ground_grid, c) for c in NASTRAN_COMPONENTS]
        big = np.block([[k, -k], [-k, k]])
    lines = _comment(f"fastbearing {matrix}; DOF order {', '.join(DOF)} -> components 1-5 of grid {grid}"
                     + (f" and of grid {ground_grid}" if ground_grid is not None else "")
                     + "; use it in case control as K2GG = " + name)
    if source:
        lines += _comment(f"source: {source}")
    if case:
        lines += _comment(f"case: {case}")
    lines += _comment("units (Nastran N-mm-t-s system): N/mm among x, y, z; N*mm/rad among tx, ty; N/rad "
                      "between translations and tilts")
    lines += _comment(f"placement: grid {grid} must sit at {centre}, its output coordinate system (GRID CD) "
                      "with z along the shaft axis and x, y across it as in fastbearing; a model whose shaft "
                      "runs along x (or any axis but z) needs such a coordinate system on that grid")
    if ground_grid is None:
        lines += _comment("the outer ring is taken as grounded (the matrix acts on one grid only)")
    else:
        lines += _comment(f"the spring [[K, -K], [-K, K]] between grids {grid} and {ground_grid} holds only "
                          "for coincident grids (same point, same output coordinate system); grids at "
                          "different points need K carried by the offset, which this file does not do")
    if symmetric:
        lines += _comment("K is symmetric: its upper triangle is written (IFO = 6); an unsymmetric Kb (a "
                          "bearing at speed) is written whole (IFO = 1) and needs a solution sequence that "
                          "accepts an unsymmetric stiffness")
    else:
        lines += _comment("K is NOT symmetric (a bearing at speed): written whole (IFO = 1); it needs a "
                          "solution sequence that accepts an unsymmetric stiffness matrix (K2GG)")
    lines.append(f"DMIG    {name:<8s}       0{6 if symmetric else 1:>8d}       2       0")
    for j, (gj, cj) in enumerate(dofs):
        entries = [(gi, ci, big[i, j]) for i, (gi, ci) in enumerate(dofs)
                   if (i <= j or not symmetric) and big[i, j] != 0.0]
        if not entries:
            continue
        # large-field cards; a blank field 10 and a leading "*" mark each continuation line
        lines.append(f"DMIG*   {name:<16s}{gj:>16d}{cj:>16d}")
        for gi, ci, a in entries:
            lines.append(f"*       {gi:>16d}{ci:>16d}{_dmig_real(a)}")
    return _publish(path, lambda tmp: tmp.write_text("\n".join(lines) + "\n"))


def read_dmig(path) -> dict:
    """Parse what :func:`write_dmig` writes: {(grid_i, comp_i, grid_j, comp_j): value} (the upper triangle
    of a symmetric matrix, every entry of another)."""
    out = {}
    column = None
    for line in Path(path).read_text().splitlines():
        if line.startswith("DMIG*"):
            column = (int(line[24:40]), int(line[40:56]))
        elif line.startswith("*") and column is not None:
            gi, ci = int(line[8:24]), int(line[24:40])
            out[(gi, ci, *column)] = float(line[40:56].replace("D", "E"))
    return out


def _k_name(i: int, j: int) -> str:
    return f"k{DOF[i]}{DOF[j]}"


#: Kb entries ROSS's BearingElement keeps (as kxx, kxy, kyx, kyy, kzz), and the three groups it drops.
ROSS_KEPT = ((0, 0), (0, 1), (1, 0), (1, 1), (2, 2))
ROSS_DROPPED_AXIAL = ((0, 2), (2, 0), (1, 2), (2, 1))
ROSS_DROPPED_TILT = ((3, 3), (3, 4), (4, 3), (4, 4))
ROSS_DROPPED_COUPLING = tuple((i, j) for i in range(5) for j in range(5) if (i < 3) != (j < 3))


def ross_dropped(K) -> tuple[str, bool]:
    """What ROSS's BearingElement drops of one 5x5 Kb (N, mm, rad), in words with sizes, and whether any
    dropped entry is non-zero: the couplings to the axial dof z (kxz, kzx, kyz, kzy; largest |k| in N/mm
    and in % of the largest kept diagonal kxx, kyy, kzz), the tilt stiffness (ktxtx ... ktyty; largest |k|
    in N*mm/rad) and the 12 translation-tilt couplings (kxtx ... ktyz; largest |k| in N/rad and, as a
    dimensionless size, the largest |k_ij| / sqrt(k_ii k_jj) in %). An entry below :data:`NOISE` times its
    row's largest |entry| counts as 0 (:func:`noise_as_zero`): round-off is not a dropped coupling."""
    k = noise_as_zero(_as_matrices(K)[0])  # round-off couplings (1e-12 of their row's largest) are zeros

    def largest(entries):
        values = [abs(k[i, j]) for i, j in entries]
        return max(values), entries[int(np.argmax(values))]

    diag, (di, dj) = largest(ROSS_KEPT[0:1] + ROSS_KEPT[3:])
    axial, (ai, aj) = largest(ROSS_DROPPED_AXIAL)
    tilt, _ = largest(ROSS_DROPPED_TILT)
    coupling, (ci, cj) = largest(ROSS_DROPPED_COUPLING)
    ratios = [abs(k[i, j]) / np.sqrt(k[i, i] * k[j, j]) for i, j in ROSS_DROPPED_COUPLING
              if k[i, i] * k[j, j] > 0]

    def names(entries):
        return ", ".join(_k_name(i, j) for i, j in entries)

    share = f", {100 * axial / diag:.3g}% of the largest kept diagonal {_k_name(di, dj)}" if diag > 0 else ""
    size = f", largest |k_ij|/sqrt(k_ii*k_jj) {100 * max(ratios):.3g}%" if ratios else ""
    text = (f"ROSS BearingElement keeps {names(ROSS_KEPT)} only; dropped: the couplings to the axial dof z "
            f"{names(ROSS_DROPPED_AXIAL)} (largest |{_k_name(ai, aj)}| = {axial:.4g} N/mm{share}), the tilt "
            f"stiffness {names(ROSS_DROPPED_TILT)} (largest |k| = {tilt:.4g} N*mm/rad) and the translation-tilt "
            f"couplings {names(ROSS_DROPPED_COUPLING)} (largest |{_k_name(ci, cj)}| = {coupling:.4g} N/rad{size})")
    return text, bool(axial > 0 or tilt > 0 or coupling > 0)


def ross_arguments(K, node: int = 0) -> dict:
    """Keyword arguments of ROSS's ``BearingElement`` (SI units: N/m) from one Kb (N/mm), plus a "units" note.

    ROSS's bearing element holds kxx, kxy, kyx, kyy and kzz only: the couplings to the axial dof z
    (kxz, kzx, kyz, kzy), the tilt stiffness and the translation-tilt couplings are dropped, with a
    warning that names them and their sizes (:func:`ross_dropped`); for an angular contact bearing under
    moment or combined load that changes natural frequencies (the paper's Table 5 lesson).
    """
    Ks = _as_matrices(K)
    if Ks.shape[0] != 1:
        raise ValueError("ROSS export takes one 5x5 matrix; pick a case of the map")
    if isinstance(node, bool) or not isinstance(node, (int, np.integer)) or node < 0:
        raise ValueError(f"node must be a shaft node number >= 0, got {node!r}")
    k = Ks[0] * 1e3  # N/mm -> N/m
    text, dropped = ross_dropped(Ks[0])
    if dropped:
        warnings.warn(text, stacklevel=2)
    return {"n": int(node), "kxx": float(k[0, 0]), "kxy": float(k[0, 1]), "kyx": float(k[1, 0]),
            "kyy": float(k[1, 1]), "kzz": float(k[2, 2]), "cxx": 0.0,
            "units": "N/m (SI, as ROSS expects); damping not modelled by fastbearing (cxx = 0)"}


def ross_speed_arguments(K, speeds_rpm, node: int = 0) -> dict:
    """Keyword arguments of ROSS's frequency-dependent ``BearingElement`` from Kb over shaft speed: kxx, kxy,
    kyx, kyy, kzz as lists in N/m (SI) over ``frequency``, the speeds in rad/s (``speeds_rpm`` in rpm, one
    per matrix of K (n, 5, 5), n >= 2, increasing), cxx zeros (no damping), plus a "units" note. ROSS
    drops the same entries as for one matrix (:func:`ross_dropped`): a warning names them at the speed of the
    largest tilt stiffness (the file's "dropped" says them at every speed)."""
    Ks = _as_matrices(K)
    rpm = np.asarray(speeds_rpm, float).reshape(-1)
    if len(rpm) != len(Ks) or len(Ks) < 2:
        raise ValueError(f"ROSS over speed needs one speed per matrix and at least 2, got {len(rpm)} speeds "
                         f"for {len(Ks)} matrices")
    if not np.all(np.isfinite(rpm)) or np.any(rpm < 0) or np.any(np.diff(rpm) <= 0):
        raise ValueError("speed must be finite, >= 0 rpm and increasing along --over")
    if isinstance(node, bool) or not isinstance(node, (int, np.integer)) or node < 0:
        raise ValueError(f"node must be a shaft node number >= 0, got {node!r}")
    dropped = [ross_dropped(k) for k in Ks]
    if any(d[1] for d in dropped):
        sizes = [max(abs(noise_as_zero(k)[i, j]) for i, j in ROSS_DROPPED_TILT) for k in Ks]  # N*mm/rad
        worst = int(np.argmax(sizes))
        warnings.warn(f"at {rpm[worst]:g} rpm (of {len(rpm)} speeds): {dropped[worst][0]}", stacklevel=2)
    k = Ks * 1e3  # N/mm -> N/m
    out = {"n": int(node)}
    for name, (i, j) in zip(("kxx", "kxy", "kyx", "kyy", "kzz"), ROSS_KEPT):
        out[name] = [float(v) for v in k[:, i, j]]
    out["cxx"] = [0.0] * len(Ks)
    out["frequency"] = [float(v) for v in rpm * 2.0 * np.pi / 60.0]
    out["units"] = ("N/m (SI, as ROSS expects) over frequency in rad/s (the shaft speed); damping not modelled "
                    "by fastbearing (cxx = 0)")
    return out


def write_ross(path, K, node: int = 0, overwrite=False, matrix: str = KB, source: str | None = None,
               case: str = "", speeds_rpm=None) -> Path:
    """The :func:`ross_arguments` as JSON, for ``ross.BearingElement(**args)`` once fastbearing's notes
    (:data:`ROSS_NOTES`: "units"; "matrix", which matrix this is; "dropped", what ROSS drops of it;
    "source", the file K was read from, and "case", which of its cases, where given) are removed. With
    ``speeds_rpm`` (one per matrix of K (n, 5, 5)): the frequency-dependent element of
    :func:`ross_speed_arguments`, "dropped" then said at each speed."""
    path = Path(path)
    _check_output(path, overwrite)
    if speeds_rpm is None:
        args = ross_arguments(K, node)
        args["dropped"] = ross_dropped(K)[0]
    else:
        args = ross_speed_arguments(K, speeds_rpm, node)
        args["dropped"] = [ross_dropped(k)[0] for k in _as_matrices(K)]
    args["matrix"] = matrix
    if source:
        args["source"] = str(source)
    if case:
        args["case"] = case
    return _publish(path, lambda tmp: tmp.write_text(json.dumps(args, indent=1)))
