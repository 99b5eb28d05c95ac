"""The one CSV dialect of Kb tables (``fastbearing export --format csv``, ``passage --csv``): one row per
matrix under one header row that pandas and numpy.genfromtxt read as it is; every numeric column's name ends
in its units (Fx_N, My_N_mm, dx_mm, kxx_N_per_mm, kxtx_N_per_rad, ktxty_N_mm_per_rad). It sits in the jobs
layer so that the passage job writes its CSV files with the same writer the export uses."""

from __future__ import annotations

import csv
import re
from pathlib import Path

import numpy as np

from ..dofs import AXES, k_entry_units
from ..dofs import DOF_LABELS as DOF
from ..files import publish as _publish
from ..files import refuse_overwrite

#: What a bearing's own Kb is called in every output's header/metadata (a shaft's matrices say more).
KB = "bearing stiffness Kb"


def units_suffix(units: str) -> str:
    """A unit as a column-name suffix that pandas and numpy.genfromtxt(names=True) keep as it is:
    "N*mm/rad" -> "_N_mm_per_rad", "N" -> "_N"; "1" or "" (a count or an index) -> ""."""
    units = str(units).strip()
    if units in ("", "1"):
        return ""
    text = re.sub(r"[^A-Za-z0-9]+", "_", units.replace("/", "_per_").replace("^", ""))
    return "_" + re.sub("_+", "_", text).strip("_")


#: The 25 CSV column names of Kb's entries in row-major DOF order, e.g. "kxx_N_per_mm", "kxtx_N_per_rad".
K_COLUMNS = tuple(f"k{a}{b}{units_suffix(k_entry_units(i, j))}" for i, a in enumerate(DOF) for j, b in enumerate(DOF))


def case_coordinates(rf) -> dict:
    """Every case's coordinates, flattened in C order over K's leading dims: the five inputs (grid dims,
    constants or a table's columns) first, then the other coordinates along those dims (position,
    cage_angle, time ...); name -> (values (N,), units). A case table's ``case`` number is the flat index
    itself and is not repeated. ``rf``: a storage.ResultFile."""
    lead_dims = rf.dims("K")[:-2]
    shape = rf.shape("K")[:-2]
    given = str(rf.file_attrs.get("given", "load"))
    names = AXES.get(given, AXES["load"])
    out = {}

    def broadcast(values, axis):
        view = [1] * len(shape)
        view[axis] = len(values)
        return np.broadcast_to(np.asarray(values, float).reshape(view), shape).reshape(-1)

    others = str(rf.attrs("K").get("coordinates", "")).split()  # CF: scalar and aux coords
    for name in (*names, *lead_dims, *others):
        if name == "case" or not rf.has(name) or name in out or rf.dtype(name).kind not in "fiu":
            continue
        units = str(rf.attrs(name).get("units", "1"))
        if rf.ndim(name) == 0:
            out[name] = (np.full(int(np.prod(shape)), float(rf.read(name))), units)
            continue
        if rf.ndim(name) != 1:
            continue
        dim = name if name in lead_dims else rf.dims(name)[0]
        if dim in lead_dims and rf.shape(name)[0] == shape[lead_dims.index(dim)]:
            out[name] = (broadcast(rf.read(name), lead_dims.index(dim)), units)
    return out


def as_matrices(K) -> np.ndarray:
    K = np.asarray(K, dtype=float)
    if K.shape[-2:] != (5, 5):
        raise ValueError(f"K must be 5x5 (or N x 5 x 5), got shape {K.shape}")
    if not np.isfinite(K).all():
        raise ValueError("K must be finite")
    return K.reshape(-1, 5, 5)


def coordinate_columns(coords: dict | None, n: int) -> list[tuple[str, np.ndarray, str]]:
    out = []
    for name, (values, units) in (coords or {}).items():
        values = np.asarray(values, float).reshape(-1)
        if len(values) != n:
            raise ValueError(f"coordinate {name} has {len(values)} values for {n} matrices")
        out.append((name, values, units))
    return out


def status_columns(status, n: int) -> tuple[np.ndarray, list[str]] | None:
    """(codes, names) of ``status`` (integer fastbearing.status codes, one per matrix) or None."""
    if status is None:
        return None
    from .. import status as st

    codes = np.asarray(status).reshape(-1)
    if len(codes) != n or codes.dtype.kind not in "iu":
        raise ValueError(f"status must be {n} integer status codes (fastbearing.status), one per matrix")
    return codes.astype(np.int64), [st.describe(int(c)) for c in codes]


def plain_text(text: str) -> str:
    """``text`` without what would split or end a CSV field for numpy.genfromtxt (commas, quotes, '#')."""
    return str(text).replace(",", ";").replace('"', "'").replace("#", "no.").replace("\n", " ")


def csv_header(coords: dict | None = None, status: bool = False, results: dict | None = None) -> list[str]:
    """The CSV column names :func:`write_csv` writes: case, each coordinate with its units (Fx_N ... My_N_mm,
    dx_mm ... by_rad, position, cage_angle_rad ...), status (the integer code) if given, each result with its
    units (L10r_million_revolutions, L10r_hours_h, speed_rpm ...), the 25 K entries (:data:`K_COLUMNS`), then
    the text columns status_name (if given) and matrix."""
    names = ["case"] + [f"{name}{units_suffix(units)}" for name, (_, units) in (coords or {}).items()]
    names += ["status"] if status else []
    names += [f"{name}{units_suffix(units)}" for name, (_, units) in (results or {}).items()]
    return names + list(K_COLUMNS) + (["status_name"] if status else []) + ["matrix"]


def write_csv(path, K, overwrite=False, coords: dict | None = None, status=None, matrix: str = KB,
              first_case: int = 0, results: dict | None = None) -> Path:
    """One row per matrix, under a single header row that ``pandas.read_csv(path)`` and
    ``numpy.genfromtxt(path, delimiter=",", names=True, dtype=None)`` read as it is (no comment line): the
    case index, what the case is (``coords``: name -> (values, units), e.g. Fx ... My), the case's integer
    ``status`` code (fastbearing.status, if given), the 25 entries K_ij in row-major DOF order (x, y, z, tx,
    ty), then the status names (e.g. "converged+beyond_validity") and ``matrix`` (which matrix this is).
    Every numeric column's name ends in its units: Fx_N, My_N_mm, dx_mm, bx_rad, kxx_N_per_mm (N/mm),
    kxtx_N_per_rad (N/rad), ktxty_N_mm_per_rad (N*mm/rad). ``results`` (name -> (values, units): a map's
    lives, a solve's load and speed) follow the status, before the K entries. ``first_case``: the case index of the first row
    (a part of a file's cases keeps the file's flat case numbers, as `export --case` takes them)."""
    path = Path(path)
    refuse_overwrite(path, overwrite)
    Ks = as_matrices(K)
    columns = coordinate_columns(coords, len(Ks))
    states = status_columns(status, len(Ks))
    computed = coordinate_columns(results, len(Ks))
    header = csv_header({name: (v, units) for name, v, units in columns}, states is not None,
                        {name: (v, units) for name, v, units in computed})
    if len(set(header)) != len(header):
        raise ValueError(f"coordinate names clash with the CSV's own columns: {header}")
    label = plain_text(matrix)

    def write(tmp):
        with tmp.open("w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(header)
            for i, k in enumerate(Ks):
                row = [first_case + i] + [repr(float(v[i])) for _, v, _ in columns]
                row += [int(states[0][i])] if states else []
                row += [repr(float(v[i])) for _, v, _ in computed]
                row += [repr(float(v)) for v in k.ravel()]
                row += [states[1][i]] if states else []
                w.writerow(row + [label])
    return _publish(path, write)


def read_csv(path) -> np.ndarray:
    """The (N, 5, 5) Kb of a CSV from :func:`write_csv` (columns found by their names, :data:`K_COLUMNS`;
    leading ``#`` lines, as older versions wrote, are skipped)."""
    with open(path, newline="") as fh:
        rows = [r for r in csv.reader(line for line in fh if not line.startswith("#")) if r]
    header, body = rows[0], rows[1:]
    old = [f"k_{a}{b} [{k_entry_units(i, j)}]" for i, a in enumerate(DOF) for j, b in enumerate(DOF)]
    names = K_COLUMNS if K_COLUMNS[0] in header else old
    missing = [n for n in names if n not in header]
    if missing:
        raise ValueError(f"{path} has no column {missing[0]}: not a CSV from fastbearing export")
    cols = [header.index(n) for n in names]
    return np.array([[float(r[c]) for c in cols] for r in body], dtype=float).reshape(-1, 5, 5)
