"""Operating points: grids of loads or displacements, or cases from a file.

An axis is a constant, a list, or a linspace table ``{start, stop, num}``.
Lists and linspaces become grid dimensions in the canonical order
(Fx, Fy, Fz, Mx, My) or (dx, dy, dz, bx, by); constants are scalar
coordinates. Cases run in C order, so the last grid axis varies fastest and
a "line" is one run along it (the unit of continuation).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .. import boundary, validate
from ..dofs import DISPLACEMENT_NAMES, DISPLACEMENT_UNITS

#: Most values one axis may have, and most cases one map may have (about 3.5 TB of results): a bigger
#: map is refused before anything is allocated; split it into several maps.
MAX_AXIS_VALUES = 10_000_000
MAX_CASES = 10_000_000_000


@dataclass(frozen=True)
class Axis:
    """One of the five inputs: its values and whether it is a grid dimension."""

    name: str
    values: np.ndarray
    units: str
    is_dim: bool


def parse_axis(name: str, spec, where: str) -> tuple[np.ndarray, bool]:
    """Values of one axis from a constant, a list or ``{start, stop, num}``; ValueError names ``where.name``."""
    field = f"{where}.{name}"
    if isinstance(spec, dict):
        unknown = sorted(set(spec) - {"start", "stop", "num"})
        missing = sorted({"start", "stop", "num"} - set(spec))
        if unknown or missing:
            raise ValueError(f"{field} as a table needs exactly start, stop, num; "
                             f"unknown {unknown}, missing {missing}")
        num = validate.integer(spec["num"], f"{field}.num", low=1, high=MAX_AXIS_VALUES)
        start, stop = (validate.number(spec[k], f"{field}.{k}") for k in ("start", "stop"))
        return np.linspace(start, stop, num), True
    if isinstance(spec, list):
        if not spec:
            raise ValueError(f"{field} is an empty list; give at least one value")
        if len(spec) > MAX_AXIS_VALUES:
            raise validate.FieldError(field, f"must hold at most {MAX_AXIS_VALUES} values", show_value=False)
        return np.array([validate.number(v, f"{field}[{i}]") for i, v in enumerate(spec)]), True
    return np.array([validate.number(spec, field)]), False


@dataclass(frozen=True)
class CaseSet:
    """The cases of a map: a grid over axes, or an explicit (N, 5) table.

    Attributes
    ----------
    given : {"load", "displacement"}
    axes : tuple of Axis
        The five inputs in canonical order (grid); empty for a case table.
    table : ndarray (N, 5) or None
        Explicit cases (from a file).
    """

    given: str
    axes: tuple[Axis, ...] = ()
    table: np.ndarray | None = None
    table_dim: str = "case"
    #: Shaft speed in rpm: an axis placed before the load axes (grids), or a table's sixth column
    #: (``table`` (N, 6)); None: no speed (the quasi-static model, and no speed coordinate in the file).
    speed: Axis | None = None
    #: Operating conditions that vary the bearing, before the speed axis (grids only): temperatures in deg C
    #: named as [bearing.mounting]'s keys (model.mounted.CASE_TEMPERATURES). Not in :meth:`inputs`: each case's
    #: values come from :meth:`condition_values`.
    conditions: tuple[Axis, ...] = ()

    @property
    def all_axes(self) -> tuple[Axis, ...]:
        """The conditions, the speed axis (when given), then the five inputs: the order of the grid's dimensions."""
        return self.conditions + ((self.speed,) if self.speed is not None else ()) + self.axes

    @property
    def has_speed(self) -> bool:
        return self.speed is not None or (self.table is not None and self.table.shape[1] == 6)

    @property
    def max_speed(self) -> float:
        """The largest shaft speed of the cases, rpm (0 without speed)."""
        if self.table is not None:
            return float(self.table[:, 5].max()) if self.table.shape[1] == 6 else 0.0
        return float(self.speed.values.max()) if self.speed is not None else 0.0

    @property
    def dims(self) -> tuple[Axis, ...]:
        return tuple(a for a in self.all_axes if a.is_dim) if self.table is None else ()

    @property
    def shape(self) -> tuple[int, ...]:
        if self.table is not None:
            return (self.table.shape[0],)
        return tuple(len(a.values) for a in self.dims) or (1,)

    @property
    def dim_names(self) -> tuple[str, ...]:
        if self.table is not None:
            return (self.table_dim,)
        return tuple(a.name for a in self.dims) or (self.table_dim,)

    @property
    def n_cases(self) -> int:
        return math.prod(self.shape)  # exact integers: no float overflow for absurd grids

    def check_size(self, where: str) -> None:
        """Refuse a map of more than MAX_CASES cases before anything is allocated."""
        if self.n_cases > MAX_CASES:
            sizes = " x ".join(str(n) for n in self.shape)
            raise ValueError(f"{where}: {sizes} = {self.n_cases:.3g} cases is more than one map may hold "
                             f"({MAX_CASES:.0e} cases, about 3.5 TB); split it into several maps")

    @property
    def line_length(self) -> int:
        """Cases per continuation line: the fastest grid axis; 1 for a case table (each case cold)."""
        return 1 if self.table is not None or not self.dims else self.shape[-1]

    def inputs(self, start: int, stop: int) -> np.ndarray:
        """(stop - start, 5) inputs of the flat case range, C order over the grid; (stop - start, 6) with
        the shaft speed (rpm) last when the case set has speed."""
        if self.table is not None:
            return np.ascontiguousarray(self.table[start:stop])
        out = np.empty((stop - start, 6 if self.speed is not None else 5))
        index = np.unravel_index(np.arange(start, stop), self.shape) if self.dims else ()
        k = 0
        columns = [None] * len(self.conditions) + ([5] if self.speed is not None else []) + list(range(5))
        for d, axis in zip(columns, self.all_axes):
            if axis.is_dim:
                if d is not None:
                    out[:, d] = axis.values[index[k]]
                k += 1
            elif d is not None:
                out[:, d] = axis.values[0]
        return out

    def condition_values(self, start: int, stop: int) -> dict[str, np.ndarray]:
        """Each condition's (stop - start,) values (deg C) over the flat case range, C order over the grid."""
        if not self.conditions:
            return {}
        index = np.unravel_index(np.arange(start, stop), self.shape)
        dims = [a.name for a in self.dims]
        return {a.name: (a.values[index[dims.index(a.name)]] if a.is_dim else np.full(stop - start, a.values[0]))
                for a in self.conditions}


#: The columns of a case table, with units: the five loads (or displacements) and the shaft speed.
CASE_COLUMNS = ("Fx or dx (N or mm)", "Fy or dy (N or mm)", "Fz or dz (N or mm)", "Mx or bx (N*mm or rad)",
                "My or by (N*mm or rad)", "speed (rpm)")


def read_case_file(path: Path, where: str) -> np.ndarray:
    """N x 5 cases from .npy, .csv (comma separated, optional header line) or .h5 (dataset ``cases``);
    N x 6 when a sixth column gives each case's shaft speed (rpm, >= 0).

    Plain real numbers only: a structured, complex, text or boolean table is refused, as is anything
    not finite. ValueError names the field and the file.
    """
    if not path.exists():
        raise ValueError(f"{where}: case file not found: {path}")
    if not path.is_file():
        raise ValueError(f"{where}: {path} is not a file")
    suffix = path.suffix.lower()
    if suffix not in (".npy", ".csv", ".h5", ".hdf5"):
        raise ValueError(f"{where}: case file must be .npy, .csv or .h5, got {path.name!r}")
    try:
        if suffix == ".npy":
            table = np.load(path, allow_pickle=False)
        elif suffix == ".csv":
            table = _read_csv_cases(path, where)
        else:
            from .storage import ResultFile

            with ResultFile(path) as rf:
                if not rf.has("cases"):
                    raise ValueError(f"{where}: {path} has no dataset 'cases' (N x 5)")
                table = rf.read("cases")
    except ValueError as err:
        if str(err).startswith(where):
            raise
        raise ValueError(f"{where}: cannot read {path}: {err}") from None
    except (OSError, UnicodeDecodeError) as err:
        raise ValueError(f"{where}: cannot read {path}: {err}") from None
    table = np.asarray(table)
    if table.dtype.kind not in "iuf":
        raise ValueError(f"{where}: {path} must hold real numbers, got {table.dtype} values")
    table = table.astype(np.float64)
    if table.ndim != 2 or table.shape[1] not in (5, 6) or table.shape[0] < 1:
        raise ValueError(f"{where}: {path} must hold an N x 5 table (or N x 6 with the speed in rpm last) with "
                         f"N >= 1, got shape {table.shape}")
    bad = ~np.isfinite(table)
    if bad.any():
        i, j = np.argwhere(bad)[0]
        raise ValueError(f"{where}: {path} case {i} column {j} ({CASE_COLUMNS[j]}) is not finite "
                         f"({float(table[i, j])!r})")
    if table.shape[1] == 6 and (table[:, 5] < 0).any():
        i = int(np.flatnonzero(table[:, 5] < 0)[0])
        raise ValueError(f"{where}: {path} case {i} speed (column 5) must be >= 0 rpm, got {float(table[i, 5])!r}")
    return np.ascontiguousarray(table)


def _read_csv_cases(path: Path, where: str) -> np.ndarray:
    """Comma-separated numbers, one case per line, an optional header line first."""
    lines = [line.strip() for line in path.read_text().splitlines()]
    lines = [line for line in lines if line and not line.startswith("#")]
    if lines and not _is_numeric_row(lines[0]):
        lines = lines[1:]  # a header
    if not lines:
        raise ValueError(f"{where}: {path} has no lines of comma-separated numbers (5 a line: Fx,Fy,Fz,Mx,My "
                         "or dx,dy,dz,bx,by; ';' or tabs are not separators here)")
    rows = []
    for k, line in enumerate(lines):
        cells = line.split(",")
        try:
            rows.append([float(c) for c in cells])
        except ValueError:
            raise ValueError(f"{where}: {path} line {k + 1} is not comma-separated numbers: {line[:40]!r}") from None
        if len(rows[-1]) != len(rows[0]):
            raise ValueError(f"{where}: {path} line {k + 1} has {len(rows[-1])} numbers, the first has {len(rows[0])}")
    return np.array(rows, dtype=np.float64).reshape(len(rows), -1)


def _is_numeric_row(line: str) -> bool:
    try:
        [float(x) for x in line.split(",")]
        return True
    except ValueError:
        return False


@dataclass(frozen=True)
class Block:
    """A block of cases: a flat range and the same cases as a hyperslab of the grid."""

    index: int
    start: int
    stop: int
    slab: tuple[slice | int, ...]

    @property
    def size(self) -> int:
        return self.stop - self.start


#: Longest continuation run: a grid line longer than this is solved as consecutive segments of
#: LINE_SEGMENT cases, each starting cold. A fixed constant (never the chunk or the thread count), so
#: results are identical for any of them; long lines then split into blocks (bounded memory) and run
#: in parallel. A cold start costs about 6 kernel evaluations more than a warm one: 0.1 % of a segment.
LINE_SEGMENT = 4096


def segment_starts(start: int, stop: int, line_length: int) -> np.ndarray:
    """Offsets (from ``start``) where continuation restarts in the flat case range [start, stop), then ``stop - start``.

    A segment starts at every line start and every LINE_SEGMENT cases along a line; blocks from
    :func:`plan_blocks` begin and end on these boundaries.
    """
    line_length = max(1, line_length)
    if line_length == 1:
        return np.arange(stop - start + 1, dtype=np.int64)
    first_line, last_line = start // line_length, (stop - 1) // line_length
    offsets = np.arange(0, line_length, LINE_SEGMENT, dtype=np.int64)
    flat = (np.arange(first_line, last_line + 1, dtype=np.int64)[:, None] * line_length + offsets).ravel()
    flat = flat[(flat >= start) & (flat < stop)]
    return np.append(flat - start, stop - start)


def plan_blocks(shape: tuple[int, ...], line_length: int, chunk: int) -> list[Block]:
    """Split the grid into blocks of at most ``chunk`` cases, cut on continuation-segment boundaries.

    Each block is a hyperslab: fixed leading indices, a range along one
    dimension and every trailing dimension whole, so it is contiguous in C
    order and one HDF5 write. A block holds whole lines, or, where one line
    is longer than ``chunk``, whole segments of LINE_SEGMENT cases of one
    line (at least one segment, so a block may exceed a chunk smaller than
    LINE_SEGMENT). Blocks never cut a segment, which keeps results
    independent of ``chunk``; memory is bounded by max(chunk, LINE_SEGMENT)
    cases whatever the grid's shape.
    """
    if line_length == 1 and len(shape) == 1:
        return [Block(k, a, min(a + chunk, shape[0]), (slice(a, min(a + chunk, shape[0])),))
                for k, a in enumerate(range(0, shape[0], chunk))]
    m = len(shape)
    suffix = [int(np.prod(shape[j:])) for j in range(m)]
    j = next((j for j in range(m) if suffix[j] <= chunk), m)
    if j == m:
        return _split_lines(shape, chunk)
    unit = suffix[j]
    if j == 0:
        return [Block(0, 0, unit, tuple(slice(None) for _ in shape))]
    step = max(1, chunk // unit)
    blocks = []
    for lead in np.ndindex(*shape[:j - 1]):
        for a in range(0, shape[j - 1], step):
            b = min(a + step, shape[j - 1])
            start = int(np.ravel_multi_index(lead + (a,), shape[:j])) * unit
            slab = tuple(int(i) for i in lead) + (slice(a, b),) + tuple(slice(None) for _ in shape[j:])
            blocks.append(Block(len(blocks), start, start + (b - a) * unit, slab))
    return blocks


def _split_lines(shape: tuple[int, ...], chunk: int) -> list[Block]:
    """Blocks of whole LINE_SEGMENT segments along each line, for lines longer than ``chunk``."""
    n = shape[-1]
    step = max(1, chunk // LINE_SEGMENT) * LINE_SEGMENT
    blocks = []
    for lead in np.ndindex(*shape[:-1]):
        base = int(np.ravel_multi_index(lead, shape[:-1])) * n if lead else 0
        for a in range(0, n, step):
            b = min(a + step, n)
            blocks.append(Block(len(blocks), base + a, base + b, tuple(int(i) for i in lead) + (slice(a, b),)))
    return blocks


def fixed_mask(spec: dict, given: str, names, where: str) -> int:
    """A job table's ``fixed = { bx = 0.0, by = { start, stop, num } }``: the bitmask of the degrees of freedom
    held at given displacements (each a number or an axis, mm or rad; boundary.py); their load axes must be
    absent. 0 without ``fixed``. ValueError naming the field otherwise."""
    if "fixed" not in spec:
        return 0
    if given != "load":
        raise ValueError(f"{where}.fixed goes with given = \"load\" (with given = \"displacement\" every degree "
                         "of freedom is given)")
    table = spec["fixed"]
    if not isinstance(table, dict) or not table:
        raise validate.FieldError(f"{where}.fixed", "must be a table of displacements, e.g. { bx = 0.0, by = 0.0 } "
                                  "(dx, dy, dz in mm; bx, by in rad; each a number or an axis)", table)
    held = boundary.parse_fixed({k: 0.0 for k in table}, where=f"{where}.fixed")  # names, and not all five
    for name in held.names:
        load = names[DISPLACEMENT_NAMES.index(name)]
        if load in spec:
            raise ValueError(f"{where}.{load} must be absent where {name} is fixed (the {load} there is the "
                             "reaction the solve finds)")
    return held.mask


def check_fixed_axes(bearing, axes, fixed: int, where: str) -> None:
    """FieldError naming ``where.fixed.NAME`` where a job table's fixed displacement (a number or an axis)
    lies beyond what the bearing's contacts describe (boundary.fixed_bounds), before any kernel runs."""
    if fixed:
        held = {DISPLACEMENT_NAMES[i]: np.asarray(axes[i].values, float) for i in range(5) if (fixed >> i) & 1}
        boundary.check_fixed_range(bearing, boundary.Fixed(fixed, held), f"{where}.fixed")


def input_axes(spec: dict, names, units, fixed: int, where: str) -> tuple:
    """The five input axes of a grid (load or displacement names and units), each from ``spec`` (a number or
    an axis, absent: 0); a fixed degree of freedom's (bit i of ``fixed``) is its displacement from
    ``spec["fixed"]``, named and in units as a displacement (mm, rad): its column holds the solver's value."""
    axes = []
    for i, (name, unit) in enumerate(zip(names, units)):
        if (fixed >> i) & 1:
            held = DISPLACEMENT_NAMES[i]
            values, is_dim = parse_axis(held, spec["fixed"][held], f"{where}.fixed")
            axes.append(Axis(held, values, DISPLACEMENT_UNITS[i], is_dim))
        else:
            values, is_dim = parse_axis(name, spec.get(name, 0.0), where)
            axes.append(Axis(name, values, unit, is_dim))
    return tuple(axes)
