"""Hand Kb to downstream tools: CSV, JSON, NumPy .npz, Nastran DMIG, ROSS bearing arguments.

Every format states its DOF order (x, y, z, tx, ty: translations along and
tilts about x and y; z is the shaft axis) and units. fastbearing's units are
N, mm, rad: Kb in N/mm (translations), N*mm/rad (tilts), N/rad (coupling).
"""

from __future__ import annotations

import csv
import json
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .dofs import DOF_LABELS as DOF
from .files import publish as _publish

UNITS = "N/mm among x, y, z; N*mm/rad among tx, ty; N/rad between translations and tilts"
FORMATS = ("csv", "json", "npz", "dmig", "ross")
#: Nastran component numbers of the DOF order above (1-3 translations, 4-5 rotations).
NASTRAN_COMPONENTS = (1, 2, 3, 4, 5)


@dataclass(frozen=True)
class Source:
    """Kb read from a solve/shaft JSON or a finished map or table: ``K`` (5, 5) or (N, 5, 5), each case's
    ``status`` name, and ``extra`` fields (q, f of a solve) to carry into JSON exports."""

    K: np.ndarray
    status: list[str]
    extra: dict

    @property
    def unconverged(self) -> list[int]:
        """Indices of cases whose solve did not converge (status not converged/unloaded/direct)."""
        return [i for i, s in enumerate(self.status) if not _usable(s)]


def _usable(status: str) -> bool:
    return status.split("+")[0] in ("converged", "unloaded", "direct")


def read_source(path, case: int | None = None) -> Source:
    """Kb from ``fastbearing solve --json`` / ``shaft --json`` output (.json) or a finished .h5 file.

    ``case`` picks one case (flat index) of a .h5 map or table; it is refused for a .json source,
    which holds one matrix. An unfinished file (a ``.part``, however named) is refused.
    """
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"file not found: {path}" if not path.exists() else f"{path} is not a file")
    suffix = path.suffix.lower()
    if suffix == ".json":
        if case is not None:
            raise ValueError("--case picks a case of a .h5 map or table; a .json source holds one matrix")
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
    import h5py

    try:
        with h5py.File(path, "r") as fh:
            if int(fh.attrs.get("fastbearing_complete", 0)) != 1:
                raise ValueError(f"{path} is not a finished fastbearing file (an interrupted run's .part?); "
                                 "finish it with --resume first")
            node = fh.get("K")
            if not isinstance(node, h5py.Dataset) or node.shape[-2:] != (5, 5) or node.dtype.kind != "f":
                raise ValueError(f"{path} is not a fastbearing map or table (no 5 x 5 variable K)")
            n = int(np.prod(node.shape[:-2]))
            codes = fh["status"][()].reshape(-1) if "status" in fh else np.zeros(n, np.int8)
            if case is not None:
                if not 0 <= case < n:
                    raise ValueError(f"--case must be in [0, {n - 1}] (the flat case index), got {case}")
                K = node[np.unravel_index(case, node.shape[:-2])]
                codes = codes[case:case + 1]
            else:
                K = node[()].reshape(-1, 5, 5)
    except OSError:
        raise ValueError(f"{path} is not a readable HDF5 file") from None
    from . import status as st

    return Source(np.asarray(K, dtype=float), [st.describe(int(c)) for c in codes], {})


def _matrix_field(value, name: str) -> np.ndarray:
    try:
        K = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a 5 x 5 matrix of numbers") from None
    if K.shape[-2:] != (5, 5) or K.ndim not in (2, 3):
        raise ValueError(f"{name} must be a 5 x 5 matrix of numbers, got shape {K.shape}")
    return K


def _check_output(path: Path, overwrite: bool) -> None:
    if path.exists() and not overwrite:
        raise ValueError(f"{path} exists; pass --overwrite (overwrite=True) to replace it")


def _as_matrices(K) -> np.ndarray:
    K = np.asarray(K, dtype=float)
    if K.shape[-2:] != (5, 5):
        raise ValueError(f"K must be 5x5 (or N x 5 x 5), got shape {K.shape}")
    if not np.isfinite(K).all():
        raise ValueError("K must be finite")
    return K.reshape(-1, 5, 5)


def write_csv(path, K, overwrite=False) -> Path:
    """One row per matrix: index then the 25 entries K_ij in row-major DOF order, units in the header."""
    path = Path(path)
    _check_output(path, overwrite)
    Ks = _as_matrices(K)
    header = ["case"] + [f"k_{a}{b}" for a in DOF for b in DOF]

    def write(tmp):
        with tmp.open("w", newline="") as fh:
            fh.write(f"# fastbearing Kb, DOF order {', '.join(DOF)}; units: {UNITS}\n")
            w = csv.writer(fh)
            w.writerow(header)
            for i, k in enumerate(Ks):
                w.writerow([i] + [repr(float(v)) for v in k.ravel()])
    return _publish(path, write)


def read_csv(path) -> np.ndarray:
    rows = np.loadtxt(path, delimiter=",", comments="#", skiprows=2, ndmin=2)
    return rows[:, 1:].reshape(-1, 5, 5)


def write_json(path, K, overwrite=False, extra: dict | None = None) -> Path:
    """{"dof": [...], "units": ..., "K": 5x5 or a list of them}, plus ``extra`` (e.g. q, f, status)."""
    path = Path(path)
    _check_output(path, overwrite)
    Ks = _as_matrices(K)
    body = {"dof": list(DOF), "units": UNITS, "K": Ks[0].tolist() if np.ndim(K) == 2 else Ks.tolist()}
    body.update(extra or {})
    return _publish(path, lambda tmp: tmp.write_text(json.dumps(body, indent=1)))


def write_npz(path, K, overwrite=False, **arrays) -> Path:
    """NumPy .npz with K, dof (names) and units (text), plus any other arrays given."""
    path = Path(path)
    _check_output(path, overwrite)
    def write(tmp):
        with tmp.open("wb") as fh:
            np.savez(fh, K=np.asarray(K, dtype=float), dof=np.array(DOF), units=np.array(UNITS), **arrays)
    return _publish(path, write)


def _dmig_real(value: float) -> str:
    """A 16-character Nastran double-precision real, e.g. ' 1.234567890D+05'."""
    text = f"{value:.9E}".replace("E", "D")
    return f"{text:>16s}"


def write_dmig(path, K, grid: int, name: str = "KBRG", ground_grid: int | None = None, overwrite=False) -> Path:
    """Nastran DMIG bulk data (large field, symmetric, real double precision) for one 5x5 Kb.

    Units: fastbearing's N, mm, rad are Nastran's consistent N-mm-t-s system,
    so Kb goes in unchanged (N/mm, N*mm/rad, N/rad). The matrix acts on
    components 1-5 of ``grid`` (the inner ring / shaft node, outer ring
    grounded); with ``ground_grid`` it is written as the 10x10 spring
    [[K, -K], [-K, K]] between the two grids. Reference it in case control
    as K2GG = NAME. Only the upper triangle is written (IFO = 6).
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
    dofs = [(grid, c) for c in NASTRAN_COMPONENTS]
    big = k
    if ground_grid is not None:
        dofs += [(ground_grid, c) for c in NASTRAN_COMPONENTS]
        big = np.block([[k, -k], [-k, k]])
    lines = [f"$ fastbearing bearing stiffness Kb, DOF order {', '.join(DOF)} -> components 1-5",
             "$ units (Nastran N-mm-t-s system): N/mm among x, y, z; N*mm/rad among",
             "$ tx, ty; N/rad between translations and tilts",
             f"DMIG    {name:<8s}       0       6       2       0"]
    for j, (gj, cj) in enumerate(dofs):
        entries = [(gi, ci, big[i, j]) for i, (gi, ci) in enumerate(dofs) if i <= j and big[i, j] != 0.0]
        if not entries:
            continue
        # large-field cards; a blank field 10 and a leading "*" mark each continuation line
        lines.append(f"DMIG*   {name:<16s}{gj:>16d}{cj:>16d}")
        for gi, ci, a in entries:
            lines.append(f"*       {gi:>16d}{ci:>16d}{_dmig_real(a)}")
    return _publish(path, lambda tmp: tmp.write_text("\n".join(lines) + "\n"))


def read_dmig(path) -> dict:
    """Parse what :func:`write_dmig` writes: {(grid_i, comp_i, grid_j, comp_j): value}, upper triangle."""
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
