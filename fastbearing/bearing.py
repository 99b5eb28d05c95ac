"""Bearing definition: a set of ball rows on one rigid inner ring.

Plain Python (dataclasses) and validation; nothing here is jitted. A
:class:`Bearing` turns into flat float64 arrays (:meth:`Bearing.ball_table`)
that the njit kernels read. Units: N, mm, rad, except the two angles a user
types (``contact_angle``, ``first_ball_angle``), which are in degrees as in
catalogues and bearing files.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from .geometry import Geometry

ARRANGEMENTS = ("single", "DB", "DF", "DT")

#: Contact direction (the paper's c3) of (row at z = -e, row at z = +e).
_DOUBLE_ROW_DIRECTIONS = {"DB": (1, -1), "DF": (-1, 1), "DT": (1, 1)}

# Rows of the per-ball table the kernel reads (column j is ball j; rows are quantities).
COS_PSI, SIN_PSI, AXIAL_OFFSET, PITCH_RADIUS, UR0, UZ0, A0, KN, EXPONENT, ROW, DIRECTION, GAP2 = range(12)
N_BALL_COLUMNS = 12


def _check_finite(name: str, value) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(x):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return x


@dataclass(frozen=True)
class Row:
    """One row of balls (MODEL.md, "A bearing is a set of rows").

    Parameters
    ----------
    n_balls : int
        Z, number of balls in the row, >= 1.
    hertz_constant : float
        Kn, ball load-deflection constant in N/mm^n, > 0.
    pitch_radius : float
        R, radius of the inner groove-curvature-centre circle in mm, > 0.
    groove_center_distance : float
        A0, unloaded distance between inner and outer groove-curvature
        centres in mm, > 0.
    contact_angle : float
        a0, unloaded contact angle in degrees, in [0, 90).
    axial_offset : float
        z_r, signed axial position of the row centre from the bearing centre
        in mm (the paper's c1*e).
    contact_direction : int
        s_r, +1 or -1 (the paper's c3): the sign of the axial component of
        the contact line from inner to outer groove centre.
    exponent : float
        n, load-deflection exponent (1.5 for balls), > 1.
    radial_clearance : float
        rL, radial clearance per ball in mm (half the diametral clearance), >= 0.
    axial_preload : float
        d0, axial preload displacement of the row in mm; only with rL = 0.
    first_ball_angle : float
        psi0, azimuth of the row's first ball in degrees.
    """

    n_balls: int
    hertz_constant: float
    pitch_radius: float
    groove_center_distance: float
    contact_angle: float
    axial_offset: float = 0.0
    contact_direction: int = 1
    exponent: float = 1.5
    radial_clearance: float = 0.0
    axial_preload: float = 0.0
    first_ball_angle: float = 0.0

    def __post_init__(self):
        for f in fields(self):
            if f.name not in ("n_balls", "contact_direction"):
                object.__setattr__(self, f.name, _check_finite(f.name, getattr(self, f.name)))
        n = self.n_balls
        if isinstance(n, bool) or not isinstance(n, (int, np.integer, float)) or n != int(n) or n < 1:
            raise ValueError(f"n_balls must be an integer >= 1, got {n!r}")
        object.__setattr__(self, "n_balls", int(n))
        if self.contact_direction not in (1, -1) or isinstance(self.contact_direction, bool):
            raise ValueError(f"contact_direction must be +1 or -1, got {self.contact_direction!r}")
        object.__setattr__(self, "contact_direction", int(self.contact_direction))
        if self.hertz_constant <= 0:
            raise ValueError(f"hertz_constant must be > 0 N/mm^n, got {self.hertz_constant!r}")
        if self.pitch_radius <= 0:
            raise ValueError(f"pitch_radius must be > 0 mm, got {self.pitch_radius!r}")
        if self.groove_center_distance <= 0:
            raise ValueError(f"groove_center_distance must be > 0 mm, got {self.groove_center_distance!r}")
        if not 0.0 <= self.contact_angle < 90.0:
            raise ValueError(f"contact_angle must be in [0, 90) degrees, got {self.contact_angle!r}")
        if self.exponent <= 1.0:
            raise ValueError(f"exponent must be > 1, got {self.exponent!r}")
        if self.radial_clearance < 0:
            raise ValueError(f"radial_clearance must be >= 0 mm, got {self.radial_clearance!r}")
        if self.axial_preload != 0 and self.radial_clearance > 0:
            raise ValueError(
                "axial_preload must be 0 when radial_clearance > 0 (preload needs zero clearance), "
                f"got axial_preload={self.axial_preload!r}, radial_clearance={self.radial_clearance!r}"
            )


@dataclass(frozen=True)
class Bearing:
    """A bearing: one or more :class:`Row` on one rigid inner ring.

    The outer ring is fixed; the inner ring moves by q = (dx, dy, dz, bx, by)
    in mm and rad, measured at the bearing centre. Build one with
    :meth:`single`, :meth:`double`, :meth:`from_rows`, :meth:`preset` or
    :func:`fastbearing.load_bearing`.
    """

    rows: tuple[Row, ...]
    arrangement: str = "custom"
    name: str = ""
    #: Catalogue geometry the rows were derived from (fastbearing.geometry), or None.
    geometry: Geometry | None = None

    def __post_init__(self):
        rows = tuple(self.rows)
        if not rows:
            raise ValueError("rows must hold at least 1 row, got 0")
        for i, row in enumerate(rows):
            if not isinstance(row, Row):
                raise ValueError(f"rows[{i}] must be a fastbearing.Row, got {type(row).__name__}")
        object.__setattr__(self, "rows", rows)

    # -- constructors -------------------------------------------------------
    @classmethod
    def single(cls, *, name: str = "", **row) -> "Bearing":
        """Single-row bearing: one :class:`Row` at axial offset 0 (keywords as in Row)."""
        row.setdefault("axial_offset", 0.0)
        return cls((_row(row, "bearing"),), arrangement="single", name=name)

    @classmethod
    def double(cls, arrangement: str, row_offset: float, *, axial_preload=0.0, name: str = "", **row) -> "Bearing":
        """Double-row bearing: two identical rows at z = -e and z = +e.

        Parameters
        ----------
        arrangement : {"DB", "DF", "DT"}
            Back-to-back, face-to-face or tandem (MODEL.md table).
        row_offset : float
            e, half the row spacing in mm, >= 0.
        axial_preload : float or pair of float
            d0 per row in mm (one number for both rows, or one per row).
        **row
            The remaining :class:`Row` keywords, shared by both rows.
        """
        if arrangement not in _DOUBLE_ROW_DIRECTIONS:
            raise ValueError(f"arrangement must be one of 'DB', 'DF', 'DT' for a double row, got {arrangement!r}")
        e = _check_finite("row_offset", row_offset)
        if e < 0:
            raise ValueError(f"row_offset must be >= 0 mm, got {row_offset!r}")
        preloads = _per_row("axial_preload", axial_preload, 2)
        rows = []
        for i, (z, s) in enumerate(zip((-e, e), _DOUBLE_ROW_DIRECTIONS[arrangement])):
            rows.append(_row({**row, "axial_offset": z, "contact_direction": s, "axial_preload": preloads[i]}, f"rows[{i}]"))
        return cls(tuple(rows), arrangement=arrangement, name=name)

    @classmethod
    def from_rows(cls, rows, *, name: str = "") -> "Bearing":
        """General set of rows (duplex, triplex, quadruplex ...): Row objects or dicts of Row keywords."""
        built = tuple(r if isinstance(r, Row) else _row(dict(r), f"rows[{i}]") for i, r in enumerate(rows))
        return cls(built, arrangement="custom", name=name)

    @classmethod
    def preset(cls, name: str, arrangement: str = "DB", **overrides) -> "Bearing":
        """A shipped bearing, e.g. ``Bearing.preset("gunduz2013", "DT")``; keywords override its values."""
        from .bearing_file import preset_bearing

        return preset_bearing(name, arrangement, **overrides)

    # -- derived quantities ---------------------------------------------------
    @property
    def n_rows(self) -> int:
        return len(self.rows)

    @property
    def n_balls(self) -> int:
        """Total number of balls over all rows."""
        return sum(r.n_balls for r in self.rows)

    @property
    def length_scale(self) -> float:
        """Largest pitch radius in mm: converts moments to forces in the solver's scaled residual."""
        return max(r.pitch_radius for r in self.rows)

    @property
    def preload_force(self) -> float:
        """Sum over rows of Z*Kn*d0^n in N: the force scale of the preload alone (0 without preload)."""
        return float(sum(r.n_balls * r.hertz_constant * abs(r.axial_preload) ** r.exponent for r in self.rows))

    def with_rows(self, **changes) -> "Bearing":
        """Copy with the given Row fields replaced in every row."""
        return replace(self, rows=tuple(replace(r, **changes) for r in self.rows))

    def ball_table(self, cage_angle: float = 0.0) -> np.ndarray:
        """Per-ball float64 table (12, n_balls), one row per quantity (see the column constants).

        Column-major so the kernel reads each quantity contiguously and can
        vectorise over balls. ``cage_angle`` (rad) rotates every ball of every
        row (ball passage). Row geometry is folded into two constants per
        ball: the unloaded net radial and axial separations of the groove
        centres. The table at cage angle 0 is built once per bearing; treat
        it as read-only.
        """
        if cage_angle == 0.0:
            return self._ball_table_at_rest
        return self._build_ball_table(cage_angle)

    def ball_set(self, cage_angle: float = 0.0) -> tuple:
        """What the kernel reads: (ball table, per-ball exponents or None when every n is 1.5)."""
        return (self.ball_table(cage_angle), self.ball_exponents)

    @cached_property
    def ball_exponents(self):
        """None when every row is Hertzian (n = 1.5, the kernel's sqrt path), else (n_balls,) exponents."""
        if all(r.exponent == 1.5 for r in self.rows):
            return None
        return np.ascontiguousarray(self._ball_table_at_rest[EXPONENT])

    @cached_property
    def _ball_table_at_rest(self) -> np.ndarray:
        return self._build_ball_table(0.0)

    def _build_ball_table(self, cage_angle: float) -> np.ndarray:
        table = np.empty((N_BALL_COLUMNS, self.n_balls))
        k = 0
        for i, r in enumerate(self.rows):
            a0 = math.radians(r.contact_angle)
            j = np.arange(r.n_balls)
            psi = math.radians(r.first_ball_angle) + cage_angle + 2.0 * math.pi * j / r.n_balls
            sl = slice(k, k + r.n_balls)
            table[COS_PSI, sl] = np.cos(psi)
            table[SIN_PSI, sl] = np.sin(psi)
            table[AXIAL_OFFSET, sl] = r.axial_offset
            table[PITCH_RADIUS, sl] = r.pitch_radius
            table[UR0, sl] = r.groove_center_distance * math.cos(a0) - r.radial_clearance
            table[UZ0, sl] = r.contact_direction * (r.groove_center_distance * math.sin(a0) + r.axial_preload)
            table[A0, sl] = r.groove_center_distance
            table[KN, sl] = r.hertz_constant
            table[EXPONENT, sl] = r.exponent
            table[ROW, sl] = i
            table[DIRECTION, sl] = r.contact_direction
            # ur0^2 + uz0^2 - A0^2 in closed form (exactly 0 without clearance and preload),
            # so the kernel gets A^2 - A0^2 without cancellation
            rl, d0 = r.radial_clearance, r.axial_preload
            table[GAP2, sl] = (-2.0 * r.groove_center_distance * rl * math.cos(a0) + rl * rl
                               + 2.0 * r.groove_center_distance * d0 * math.sin(a0) + d0 * d0)
            k += r.n_balls
        return table

    def describe(self) -> str:
        """One line per row, for reports and HDF5 provenance."""
        lines = [f"{self.name or 'bearing'} ({self.arrangement}, {self.n_rows} rows)"]
        for i, r in enumerate(self.rows):
            lines.append(
                f"  row {i}: z={r.axial_offset:g} mm, s={r.contact_direction:+d}, Z={r.n_balls}, "
                f"a0={r.contact_angle:g} deg, A0={r.groove_center_distance:g} mm, R={r.pitch_radius:g} mm, "
                f"Kn={r.hertz_constant:g} N/mm^{r.exponent:g}, rL={r.radial_clearance:g} mm, "
                f"d0={r.axial_preload:g} mm, psi0={r.first_ball_angle:g} deg"
            )
        return "\n".join(lines)

    def to_dict(self) -> dict:
        """The bearing as a ``[bearing]`` table with explicit ``rows`` (round-trips through TOML)."""
        return {"name": self.name, "arrangement": self.arrangement,
                "rows": [{f.name: getattr(r, f.name) for f in fields(Row)} for r in self.rows]}


ROW_KEYS = tuple(f.name for f in fields(Row))


def check_keys(table: dict, allowed, where: str) -> None:
    """ValueError naming ``where`` when ``table`` has keys outside ``allowed`` (config files are strict)."""
    unknown = sorted(set(table) - set(allowed))
    if unknown:
        raise ValueError(f"{where}: unknown key(s) {unknown}; allowed: {sorted(allowed)}")


def _row(values: dict, where: str) -> Row:
    """Build a Row, naming where it came from in any error."""
    check_keys(values, ROW_KEYS, where)
    missing = [k for k in ("n_balls", "hertz_constant", "pitch_radius", "groove_center_distance", "contact_angle") if k not in values]
    if missing:
        raise ValueError(f"{where}: missing required key(s) {missing}")
    try:
        return Row(**values)
    except ValueError as err:
        raise ValueError(f"{where}.{err}") from None


def _per_row(name: str, value, n_rows: int) -> list[float]:
    """One number for every row, or a list of one number per row."""
    if isinstance(value, (list, tuple, np.ndarray)):
        if len(value) != n_rows:
            raise ValueError(f"{name} must be one number or a list of {n_rows} numbers (one per row), got {len(value)}")
        return [_check_finite(f"{name}[{i}]", v) for i, v in enumerate(value)]
    return [_check_finite(name, value)] * n_rows
