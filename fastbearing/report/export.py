"""Hand Kb to downstream tools: CSV, JSON, NumPy .npz, Nastran DMIG, ROSS bearing arguments.

Every format states its DOF order (x, y, z, tx, ty: translations along and
tilts about x and y; z is the shaft axis) and units. fastbearing's units are
N, mm, rad: Kb in N/mm (translations), N*mm/rad (tilts), N/rad (coupling).
"""

from __future__ import annotations

import csv
import json
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..dofs import AXES, k_entry_units
from ..dofs import DOF_LABELS as DOF
from ..files import publish as _publish
from ..files import refuse_overwrite

UNITS = "N/mm among x, y, z; N*mm/rad among tx, ty; N/rad between translations and tilts"
FORMATS = ("csv", "json", "npz", "dmig", "ross")
#: Nastran component numbers of the DOF order above (1-3 translations, 4-5 rotations).
NASTRAN_COMPONENTS = (1, 2, 3, 4, 5)


@dataclass(frozen=True)
class Source:
    """Kb read from a solve/shaft JSON or a finished map or table: ``K`` (5, 5) or (N, 5, 5), each case's
    ``status`` name, ``coords`` (what each case is: name -> (values (N,), units), the five inputs Fx ... My
    or dx ... by first, then e.g. position, cage_angle), and ``extra`` fields (q, f of a solve) to carry into
    JSON exports. ``picked`` describes the case chosen by ``--at`` (empty otherwise)."""

    K: np.ndarray
    status: list[str]
    extra: dict
    coords: dict = field(default_factory=dict)
    picked: str = ""

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


def read_source(path, case: int | None = None, at: dict | None = None) -> Source:
    """Kb from ``fastbearing solve --json`` / ``shaft --json`` output (.json) or a finished .h5 file.

    ``case`` picks one case (flat index) of a .h5 map or table, ``at`` the grid point nearest to
    given coordinates (e.g. {"Fx": 1000.0, "Fz": 3000.0, "My": 0.0}: every varying axis, values in the
    axis' units; a case table's or passage table's own dims by index, e.g. {"point": 3, "position": 0});
    both are refused for a .json source, which holds one matrix. An unfinished file (a ``.part``, however
    named) is refused.
    """
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"file not found: {path}" if not path.exists() else f"{path} is not a file")
    if case is not None and at is not None:
        raise ValueError("give --case or --at, not both")
    suffix = path.suffix.lower()
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
        key = "K" if "K" in body else "K_system"
        K = _matrix_field(body[key], f"{path.name}: {key}")
        status = body.get("status", "converged")
        status = status if isinstance(status, str) else "unknown"
        return Source(K, [status], {k: body[k] for k in ("q", "f", "status") if k in body})
    if suffix not in (".h5", ".hdf5"):
        raise ValueError(f"SOURCE must be a .json or .h5 file, got {path.name!r}")
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
        else:
            K = rf.read("K").reshape(-1, 5, 5)
    from .. import status as st

    return Source(np.asarray(K, dtype=float), [st.describe(int(c)) for c in codes], {}, coords, picked)


def _case_coordinates(rf) -> dict:
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


def _nearest_case(rf, at: dict) -> tuple[int, str]:
    """The flat index of the case nearest to ``at`` along every leading dim of K (``rf``: a
    storage.ResultFile), and a line saying which."""
    lead_dims = rf.dims("K")[:-2]
    shape = rf.shape("K")[:-2]
    unknown = sorted(set(at) - set(lead_dims))
    missing = [d for d in lead_dims if d not in at]
    if unknown or missing:
        raise ValueError(f"--at must name each varying axis of this file once: {', '.join(lead_dims)} "
                         f"(unknown {unknown}, missing {missing})")
    index, said = [], []
    for axis, dim in enumerate(lead_dims):
        values = rf.read(dim) if rf.has(dim) else np.arange(shape[axis])
        values = np.asarray(values, float)
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


def _as_matrices(K) -> np.ndarray:
    K = np.asarray(K, dtype=float)
    if K.shape[-2:] != (5, 5):
        raise ValueError(f"K must be 5x5 (or N x 5 x 5), got shape {K.shape}")
    if not np.isfinite(K).all():
        raise ValueError("K must be finite")
    return K.reshape(-1, 5, 5)


def _coordinate_columns(coords: dict | None, n: int) -> list[tuple[str, np.ndarray, str]]:
    out = []
    for name, (values, units) in (coords or {}).items():
        values = np.asarray(values, float).reshape(-1)
        if len(values) != n:
            raise ValueError(f"coordinate {name} has {len(values)} values for {n} matrices")
        out.append((name, values, units))
    return out


def write_csv(path, K, overwrite=False, coords: dict | None = None) -> Path:
    """One row per matrix: the case index, what the case is (``coords``: name -> (values, units), e.g.
    Fx ... My), then the 25 entries K_ij in row-major DOF order; every header names its units."""
    path = Path(path)
    _check_output(path, overwrite)
    Ks = _as_matrices(K)
    columns = _coordinate_columns(coords, len(Ks))
    header = (["case"] + [f"{name} [{units}]" for name, _, units in columns]
              + [f"k_{a}{b} [{k_entry_units(i, j)}]" for i, a in enumerate(DOF) for j, b in enumerate(DOF)])

    def write(tmp):
        with tmp.open("w", newline="") as fh:
            fh.write(f"# fastbearing Kb, DOF order {', '.join(DOF)}; units: {UNITS}\n")
            w = csv.writer(fh)
            w.writerow(header)
            for i, k in enumerate(Ks):
                w.writerow([i] + [repr(float(v[i])) for _, v, _ in columns] + [repr(float(v)) for v in k.ravel()])
    return _publish(path, write)


def read_csv(path) -> np.ndarray:
    """The (N, 5, 5) Kb of a CSV from :func:`write_csv` (columns found by their k_ names)."""
    with open(path, newline="") as fh:
        fh.readline()
        header = next(csv.reader(fh))
    cols = [i for i, h in enumerate(header) if h.startswith("k_")]
    rows = np.loadtxt(path, delimiter=",", comments="#", skiprows=2, ndmin=2)
    return rows[:, cols].reshape(-1, 5, 5)


def write_json(path, K, overwrite=False, extra: dict | None = None, coords: dict | None = None) -> Path:
    """{"dof": [...], "units": ..., "K": 5x5 or a list of them, "cases": {name: {"units", "values"}}},
    plus ``extra`` (e.g. q, f, status)."""
    path = Path(path)
    _check_output(path, overwrite)
    Ks = _as_matrices(K)
    body = {"dof": list(DOF), "units": UNITS, "K": Ks[0].tolist() if np.ndim(K) == 2 else Ks.tolist()}
    columns = _coordinate_columns(coords, len(Ks))
    if columns:
        one = np.ndim(K) == 2
        body["cases"] = {name: {"units": units, "values": float(v[0]) if one else v.tolist()}
                         for name, v, units in columns}
    body.update(extra or {})
    return _publish(path, lambda tmp: tmp.write_text(json.dumps(body, indent=1)))


def write_npz(path, K, overwrite=False, coords: dict | None = None, **arrays) -> Path:
    """NumPy .npz with K, dof (names) and units (text), each coordinate of ``coords`` as an array of its
    own name with its units in ``coordinate_units`` ("Fx: N", ...), plus any other arrays given."""
    path = Path(path)
    _check_output(path, overwrite)
    Ks = _as_matrices(K)
    columns = _coordinate_columns(coords, len(Ks))
    named = {name: v for name, v, _ in columns}
    if columns:
        named["coordinate_units"] = np.array([f"{name}: {units}" for name, _, units in columns])
    clash = sorted(set(named) & {"K", "dof", "units"})
    if clash:
        raise ValueError(f"coordinate names {clash} clash with the npz's own arrays")

    def write(tmp):
        with tmp.open("wb") as fh:
            np.savez(fh, K=np.asarray(K, dtype=float), dof=np.array(DOF), units=np.array(UNITS), **named, **arrays)
    return _publish(path, write)


def _dmig_real(value: float) -> str:
    """A 16-character Nastran double-precision real, e.g. ' 1.234567890D+05'."""
    text = f"{value:.9E}".replace("E", "D")
    return f"{text:>16s}"


def write_dmig(path, K, grid: int, name: str = "KBRG", ground_grid: int | None = None, overwrite=False) -> Path:
    """Nastran DMIG bulk data (large field, real double precision) for one 5x5 Kb.

    Units: fastbearing's N, mm, rad are Nastran's consistent N-mm-t-s system,
    so Kb goes in unchanged (N/mm, N*mm/rad, N/rad). The matrix acts on
    components 1-5 of ``grid`` (the inner ring / shaft node, outer ring
    grounded); with ``ground_grid`` it is written as the 10x10 spring
    [[K, -K], [-K, K]] between the two grids. Reference it in case control
    as K2GG = NAME. A symmetric Kb is written as its upper triangle (IFO = 6); a Kb that is not (at
    shaft speed: the friction of the balls' gyroscopic moments) as the whole square matrix (IFO = 1),
    so nothing of it is lost.
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
    lines = [f"$ fastbearing bearing stiffness Kb, DOF order {', '.join(DOF)} -> components 1-5",
             "$ units (Nastran N-mm-t-s system): N/mm among x, y, z; N*mm/rad among",
             "$ tx, ty; N/rad between translations and tilts",
             f"DMIG    {name:<8s}       0{6 if symmetric else 1:>8d}       2       0"]
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


def ross_arguments(K, node: int = 0) -> dict:
    """Keyword arguments of ROSS's ``BearingElement`` (SI units: N/m) from one Kb.

    ROSS's bearing element has no tilt stiffness and no translation-tilt
    coupling: those terms are dropped, with a warning, which for an angular
    contact bearing under moment or combined load changes natural
    frequencies (the paper's Table 5 lesson).
    """
    Ks = _as_matrices(K)
    if Ks.shape[0] != 1:
        raise ValueError("ROSS export takes one 5x5 matrix; pick a case of the map")
    if isinstance(node, bool) or not isinstance(node, (int, np.integer)) or node < 0:
        raise ValueError(f"node must be a shaft node number >= 0, got {node!r}")
    k = Ks[0] * 1e3  # N/mm -> N/m
    dropped = np.abs(Ks[0][:3, 3:]).max(initial=0.0) > 0 or np.abs(Ks[0][3:, 3:]).max(initial=0.0) > 0
    if dropped:
        warnings.warn("ROSS BearingElement keeps kxx, kxy, kyx, kyy, kzz only: the tilt stiffness and the "
                      "translation-tilt coupling terms of Kb are dropped", stacklevel=2)
    return {"n": int(node), "kxx": float(k[0, 0]), "kxy": float(k[0, 1]), "kyx": float(k[1, 0]),
            "kyy": float(k[1, 1]), "kzz": float(k[2, 2]), "cxx": 0.0,
            "units": "N/m (SI, as ROSS expects); damping not modelled by fastbearing (cxx = 0)"}


def write_ross(path, K, node: int = 0, overwrite=False) -> Path:
    """The :func:`ross_arguments` as JSON, for ``ross.BearingElement(**args)`` (drop the units key)."""
    path = Path(path)
    _check_output(path, overwrite)
    args = ross_arguments(K, node)
    return _publish(path, lambda tmp: tmp.write_text(json.dumps(args, indent=1)))
