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

import numpy as np

from .. import validate
# the ball table's layout, re-exported where the table is built
from ..engine.schema import (A0, AXIAL_OFFSET, BALL_OF, COS_NOMINAL, COS_PSI, DEFLECTION_LIMIT, DIRECTION, EXPONENT,  # noqa: F401
                     GAMMA, GAP2, HALF_COUNT, KN, MASS_RADIUS, MIRROR_HALF, MIRROR_OF, N_BALL_COLUMNS, N_BALL_FIELDS,
                     N_OPERATING, N_SPEED_COLUMNS, OUTER_ROTATES, PARTNER, PITCH_RADIUS, ROW, SHARE, SIN_PSI, UR0, UZ0, WEIGHT,
                     ElementSet)
from .ball_row import (MAX_BALLS, PRELOAD_DEFLECTION_LIMIT, VALIDITY_DEFLECTION, Row, _check_finite,  # noqa: F401
                       free_contact_angle)
from .four_point import ELEMENT as FOUR_POINT, FourPointRow, check_pairs, expand, merged, partner_columns
from .catalogue import catalogue_table, preset_names  # noqa: F401 (preset_names is public here)
from .rollers import (N_SLICE_COLUMNS, REQUIRED_ROLLER_KEYS, ROLLER_ELEMENTS, ROLLER_KEYS, RollerRow,
                      radial_load_note, slice_table)

ARRANGEMENTS = ("single", "DB", "DF", "DT", "TDO", "TDI")
#: Tapered-roller names of the double-row arrangements: TDO back to back (as DB), TDI face to face (as DF).
ARRANGEMENT_ALIASES = {"TDO": "DB", "TDI": "DF"}

#: Contact direction (the paper's c3) of (row at z = -e, row at z = +e).
_DOUBLE_ROW_DIRECTIONS = {"DB": (1, -1), "DF": (-1, 1), "DT": (1, 1)}

#: How close (rad) a row's first ball must sit to a multiple of pi / Z for the row to be its own mirror image.
MIRROR_ANGLE_TOL = 1e-9


#: Largest shaft speed a user may ask for, rpm (a sanity bound: 2 million rpm is beyond any ball bearing).
MAX_SPEED = 2.0e6


def rpm_to_rad_s(speed: float) -> float:
    """Shaft speed in rad/s from rpm."""
    return float(speed) * math.pi / 30.0


def check_speed(speed, name: str = "speed") -> float:
    """A shaft speed in rpm: finite, in [0, MAX_SPEED]; ValueError naming ``name`` otherwise."""
    return validate.number(speed, name, low=0, high=MAX_SPEED, units="rpm")


def check_speed_model(bearing, speed: float = 0.0, name: str = "speed") -> None:
    """ValueError unless ``bearing`` can run at speed: ball rows from catalogue geometry (the high-speed
    model needs the ball diameter, pitch diameter, groove ratios and density), Hertzian (n = 1.5); and,
    with ``speed`` (rpm), unless it is within the bearing's :func:`speed_limit` (``name`` the field)."""
    if bearing.roller_rows:
        raise validate.FieldError("speed", "above 0 rpm needs ball rows: the high-speed model (centrifugal force, "
                                  "gyroscopic moment) is not implemented for roller rows; give speed = 0",
                                  show_value=False)
    if bearing.geometry is None or not (hasattr(bearing.geometry, "speed_columns")
                                        or hasattr(bearing.geometry, "row_speed_columns")):
        raise validate.FieldError("speed", f"above 0 rpm needs the bearing's geometry: {bearing.name or 'this bearing'} "
                                  "is given by model parameters only; define it with [bearing.geometry] "
                                  "(ball_diameter, pitch_diameter, inner_groove_ratio, outer_groove_ratio, ...) so "
                                  "the balls' mass and both race contacts are known", show_value=False)
    if any(r.exponent != 1.5 for _, r in bearing.ball_rows):
        raise validate.FieldError("speed", "above 0 rpm needs Hertzian balls (exponent 1.5)", show_value=False)
    limit = speed_limit(bearing) if speed > 0.0 else math.inf
    if speed > limit:
        raise validate.FieldError(name, f"must be <= {limit:.6g} rpm for {bearing.name or 'this bearing'}: above "
                                  "it the centrifugal force alone presses a ball into its outer race beyond the "
                                  "model's validity limit (the row's deflection_limit, by default the 4200 N/mm^2 "
                                  "Hertz pressure)", speed)


def speed_limit(bearing) -> float:
    """The largest shaft speed in rpm at which no ball's centrifugal force alone, 0.5 m d_m omega_m^2 at the
    nominal orbital speed, exceeds the load Kn delta_lim^1.5 that takes its contacts to the row's
    ``deflection_limit`` (by default the 4200 N/mm^2 Hertz pressure of the model's validity): beyond it
    the balls crush their outer race whatever the load, and the contact model (and float64, near 1e6 rpm)
    no longer holds. Needs the speed model (:func:`check_speed_model`)."""
    p = bearing.speed_table
    table = bearing.ball_table()
    load = table[KN] * table[DEFLECTION_LIMIT] ** 1.5
    # omega_m = omega (1 - gamma cos a0)/2 with the inner ring turning, omega (1 + gamma cos a0)/2 the outer
    cage = 0.5 * (1.0 + np.where(p[OUTER_ROTATES] != 0.0, 1.0, -1.0) * p[GAMMA] * p[COS_NOMINAL])
    omega = np.sqrt(load / p[MASS_RADIUS]) / cage
    return float(omega.min() * 30.0 / math.pi) if omega.size else math.inf


@dataclass(frozen=True)
class Bearing:
    """A bearing: one or more :class:`Row` on one rigid inner ring.

    The outer ring is fixed; the inner ring moves by q = (dx, dy, dz, bx, by)
    in mm and rad, measured at the bearing centre. Build one with
    :meth:`single`, :meth:`double`, :meth:`from_rows`, :meth:`preset` or
    :func:`fastbearing.load_bearing`.

    Arrangements (``ARRANGEMENTS``; double rows at z = -e and +e, contact
    directions c3 of the two rows in brackets; docs/model.md, "A bearing is a
    set of rows on one rigid inner ring"):

    ``"single"``
        One row at the bearing centre (z = 0).
    ``"DB"``
        Back-to-back ("O"), (+1, -1): the load lines meet outside the
        bearing; the stiffest in tilt.
    ``"DF"``
        Face-to-face ("X"), (-1, +1): the load lines meet towards the bore;
        the softest in tilt.
    ``"DT"``
        Tandem, (+1, +1): parallel load lines; both rows carry Fz > 0 (an
        Fz < 0 turns their contacts round: status warning contact_reversed).

    A bearing built from rows of your own (:meth:`from_rows`: duplex,
    triplex, quadruplex sets) has ``arrangement == "custom"``.

    Presets (:meth:`preset`; :func:`fastbearing.preset_names` lists them):
    the shipped bearing files given by model parameters (fastbearing/catalogue/).

    ``"gunduz2013"``
        The example double-row bearing of Gunduz & Singh (2013), Table 1:
        Z = 14 per row, Kn = 395 000 N/mm^1.5, R = 34.75 mm, A0 = 0.52 mm,
        e = 10 mm, a0 = 30 deg, no clearance or preload; DB unless another
        arrangement is given.

    Every shipped bearing file, the presets included, is read by name with
    :func:`fastbearing.load_bearing` (``fb.load_bearing("6205")``) from any
    folder; the others are given by catalogue geometry
    (:class:`fastbearing.Geometry`), and each file says which internal
    dimensions are published and which are estimated or assumed.
    `fastbearing bearings` (:func:`fastbearing.shipped_bearings`) lists them.
    """

    rows: tuple[Row, ...]
    arrangement: str = "custom"
    name: str = ""
    #: Catalogue geometry the rows were derived from (a fastbearing.Geometry), or None.
    geometry: object = None
    #: The fits and temperatures of ``[bearing.mounting]`` (a fastbearing.model.mounted.Mounting), or None:
    #: the solves then use :func:`fastbearing.model.mounted.operating_bearing` at their speed.
    mounting: object = None

    def __post_init__(self):
        rows = tuple(validate.array(self.rows, "rows", min_length=1))
        for i, row in enumerate(rows):
            if not isinstance(row, (Row, RollerRow)):
                raise validate.FieldError(f"rows[{i}]", f"must be a fastbearing.Row, FourPointRow or RollerRow, not "
                                          f"{type(row).__name__}", show_value=False)
        rows = expand(rows)  # a four-point row is held as its two contact pairs
        check_pairs(rows)
        object.__setattr__(self, "rows", rows)

    # -- constructors -------------------------------------------------------
    @classmethod
    def single(cls, *, name: str = "", **row) -> "Bearing":
        """Single-row bearing: one :class:`Row` at axial offset 0 (keywords as in Row)."""
        row.setdefault("axial_offset", 0.0)
        return cls((_row(row, ""),), arrangement="single", name=name)

    @classmethod
    def double(cls, arrangement: str, row_offset: float, *, axial_preload=0.0, name: str = "", **row) -> "Bearing":
        """Double-row bearing: two identical rows at z = -e and z = +e.

        Parameters
        ----------
        arrangement : {"DB", "DF", "DT"}
            Back-to-back, face-to-face or tandem (docs/model.md, "A bearing is a set of rows on one
            rigid inner ring").
        row_offset : float
            e, half the row spacing in mm, >= 0.
        axial_preload : float or pair of float
            d0 per row in mm (one number for both rows, or one per row).
        **row
            The remaining :class:`Row` keywords, shared by both rows.
        """
        validate.choice(arrangement, "arrangement", (*_DOUBLE_ROW_DIRECTIONS, *ARRANGEMENT_ALIASES))
        e = validate.number(row_offset, "row_offset", low=0, units="mm")
        fixed = sorted({"axial_offset", "contact_direction"} & set(row))
        if fixed:
            raise validate.FieldError(fixed[0], f"is set by the arrangement of a double row ({arrangement}: rows at "
                                      "z = -e and +e); use Bearing.from_rows for rows of your own", row[fixed[0]])
        preloads = _per_row("axial_preload", axial_preload, 2)
        rows = []
        directions = _DOUBLE_ROW_DIRECTIONS[ARRANGEMENT_ALIASES.get(arrangement, arrangement)]
        for i, (z, s) in enumerate(zip((-e, e), directions)):
            rows.append(_row({**row, "axial_offset": z, "contact_direction": s, "axial_preload": preloads[i]}, f"rows[{i}]"))
        if arrangement in ARRANGEMENT_ALIASES and not all(isinstance(r, RollerRow) for r in rows):
            plain = ARRANGEMENT_ALIASES[arrangement]
            raise validate.FieldError("arrangement", "is for tapered roller pairs (TDO back to back, TDI face to "
                                      f"face); a ball double row so arranged is {plain}", arrangement)
        return cls(tuple(rows), arrangement=arrangement, name=name)

    @classmethod
    def from_rows(cls, rows, *, name: str = "") -> "Bearing":
        """General set of rows (duplex, triplex, quadruplex ...): Row objects or dicts of Row keywords."""
        rows = validate.array(rows, "rows", min_length=1)
        built = tuple(r if isinstance(r, (Row, RollerRow)) else _row(r, f"rows[{i}]") for i, r in enumerate(rows))
        return cls(built, arrangement="custom", name=name)

    @classmethod
    def from_table(cls, table, where: str = "bearing") -> "Bearing":
        """A bearing from model parameters as a ``[bearing]`` table (units N, mm, degrees).

        Either the compact form, ``arrangement`` ("single", "DB", "DF", "DT")
        with ``row_offset`` (e, mm) for double rows and the row keys shared by
        both rows, or a general set ``rows = [{...}, ...]`` of Row tables
        (keys given beside ``rows`` are defaults for every row).
        ``axial_preload`` is one number or one per row. A FieldError names
        the offending key under ``where``.
        """
        validate.table(table, where, _COMPACT_KEYS | {"rows"})
        table = dict(table)
        name = validate.text(table.pop("name", ""), f"{where}.name")
        if "rows" in table:
            rows = validate.array(table.pop("rows"), f"{where}.rows", min_length=1)
            table.pop("arrangement", None)
            if "row_offset" in table:
                raise validate.FieldError(f"{where}.row_offset", "is not used with rows; give each row its "
                                          "axial_offset", table["row_offset"])
            preloads = _per_row(f"{where}.axial_preload", table.pop("axial_preload", 0.0), len(rows))
            built = []
            for i, r in enumerate(rows):
                validate.table(r, f"{where}.rows[{i}]", ALL_ROW_KEYS)
                built.append(_row({**table, "axial_preload": preloads[i], **r}, f"{where}.rows[{i}]"))
            return cls(tuple(built), arrangement="custom", name=name)
        arrangement = validate.choice(table.pop("arrangement", "single"), f"{where}.arrangement", ARRANGEMENTS)
        preload = table.pop("axial_preload", 0.0)
        try:
            if arrangement == "single":
                if "row_offset" in table:  # ignored for a single row (a preset may carry it for its double rows)
                    validate.number(table.pop("row_offset"), "row_offset", low=0, units="mm")
                return cls.single(name=name, axial_preload=_per_row("axial_preload", preload, 1)[0], **table)
            if "row_offset" not in table:
                raise validate.FieldError("row_offset", f"(e, mm, >= 0) is required for arrangement {arrangement!r}",
                                          show_value=False)
            e = table.pop("row_offset")
            _row({**table, "axial_preload": 0.0}, "")  # the shared keys were typed once: report them as bearing.KEY
            return cls.double(arrangement, e, axial_preload=preload, name=name, **table)
        except validate.FieldError as err:
            field = err.field.split(".", 1)[1] if err.field.startswith("rows[") else err.field
            raise validate.FieldError(field, err.rule, err.value, show_value=err.show_value).within(where) from None

    @classmethod
    def preset(cls, name: str, arrangement: str | None = None, **overrides) -> "Bearing":
        """A shipped bearing, e.g. ``Bearing.preset("gunduz2013", "DT")``; keywords override its values.

        Presets: see :func:`preset_names` (``"gunduz2013"``: the paper's Table 1
        bearing); arrangements "single", "DB", "DF", "DT" (default: the preset's own).
        """
        table = preset_table(name)
        if arrangement is not None:
            table["arrangement"] = arrangement
        table.update(overrides)
        return cls.from_table(table)

    # -- derived quantities ---------------------------------------------------
    @property
    def n_rows(self) -> int:
        return len(self.rows)

    @property
    def ball_rows(self) -> list:
        """(row index, Row) of the ball rows."""
        return [(i, r) for i, r in enumerate(self.rows) if isinstance(r, Row)]

    @property
    def roller_rows(self) -> list:
        """(row index, RollerRow) of the roller rows."""
        return [(i, r) for i, r in enumerate(self.rows) if isinstance(r, RollerRow)]

    @property
    def n_balls(self) -> int:
        """Total number of balls over all ball rows."""
        return sum(r.n_balls for _, r in self.ball_rows)

    @property
    def n_elements(self) -> int:
        """Balls and rollers over all rows: the length of the per-element record."""
        return sum(r.n_elements for r in self.rows)

    @cached_property
    def element_rows(self) -> np.ndarray:
        """Row index of every element of the record (int64): the balls, then the rollers."""
        balls = [np.full(r.n_balls, i) for i, r in self.ball_rows]
        rollers = [np.full(r.n_rollers, i) for i, r in self.roller_rows]
        return np.concatenate([*balls, *rollers, np.zeros(0)]).astype(np.int64)

    @property
    def length_scale(self) -> float:
        """Largest pitch radius in mm: converts moments to forces in the solver's scaled residual."""
        return max(r.pitch_radius for r in self.rows)

    @property
    def preload_force(self) -> float:
        """Sum over rows of Z*Kn*d0^n in N: the force scale of the preload alone (0 without preload)."""
        return float(sum(r.n_balls * r.hertz_constant * abs(r.axial_preload) ** r.exponent for _, r in self.ball_rows)
                     + sum(r.n_rollers * r.hertz_constant * abs(r.axial_preload) ** (10 / 9)
                           for _, r in self.roller_rows))

    def with_rows(self, **changes) -> "Bearing":
        """Copy with the given Row fields replaced in every row."""
        return replace(self, rows=tuple(replace(r, **changes) for r in self.rows))

    def ball_table(self, cage_angle: float = 0.0) -> np.ndarray:
        """Per-ball float64 table (N_BALL_COLUMNS, n_balls), one row per quantity (see the row constants),
        then the set's mirror half (MIRROR_HALF: what a planar displacement needs).

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

    def no_solution_note(self, load, speed: float = 0.0) -> str:
        """Why ``load`` (N, N*mm) at ``speed`` (rpm) may have no solution, in one line, as the element kinds
        know it ("" where none does): the high-speed balls' race control (the geometry's
        :meth:`~fastbearing.model.geometry.Geometry.no_solution_note`), tapered roller rows short of axial
        load (:func:`fastbearing.model.rollers.radial_load_note`)."""
        if speed > 0 and self.ball_rows and hasattr(self.geometry, "no_solution_note"):
            note = self.geometry.no_solution_note(speed)
            if note:
                return note
        if self.ball_rows:  # balls can roll to 0 deg and carry a radial load alone
            return ""
        return radial_load_note([r for _, r in self.roller_rows], load)

    @property
    def mirror_symmetric(self) -> bool:
        """Whether the ball set at rest is its own mirror image across the xz-plane (every row, every ball
        like its image), so that the kernel may sum its mirror half under a planar displacement."""
        return self.n_balls > 0 and self.ball_table()[HALF_COUNT, 0] > 0

    def ball_set(self, cage_angle: float = 0.0, speed: float | None = None, mirror: bool = True) -> ElementSet:
        """What the kernel reads (schema.ElementSet): the ball table, per-ball exponents or None when every n
        is 1.5, smoothing 0.0 (the exact contact law), the slice table or None without roller rows, speed
        table, omega, warm starts.
        ``speed`` (rpm) None: no speed table, the quasi-static model; a number (0 included): the
        high-speed constants, omega in rad/s and a fresh scratch for the balls' warm starts
        (fastbearing.engine.high_speed; at 0 rpm the kernel takes the quasi-static loop). A ball set at speed
        belongs to one thread. ``mirror`` False switches the mirror half off (:func:`without_mirror_half`):
        what a per-element feature kept outside the table must ask for."""
        # no roller rows: None, so that the kernels compile no roller code for a ball bearing
        slices = self.slice_table(cage_angle) if self.roller_rows else None
        if not mirror:  # a per-element feature outside the table switches the mirror half off
            return self.ball_set(cage_angle, speed)._replace(balls=without_mirror_half(self.ball_table(cage_angle)))
        if speed is None:
            return ElementSet(self.ball_table(cage_angle), self.ball_exponents, 0.0, slices, None, 0.0, None, None)
        from ..engine.high_speed import new_warm

        return ElementSet(self.ball_table(cage_angle), self.ball_exponents, 0.0, slices, self.speed_table,
                          rpm_to_rad_s(speed), new_warm(self.n_balls), self.four_point_columns)

    @cached_property
    def four_point_columns(self):
        """None without four-point rows, else the ball table's columns of each four-point ball's pair +a0 and
        pair -a0, (2, n) float64: what the kernel at speed settles as one ball (schema.ElementSet)."""
        partner = partner_columns(self.rows)
        lead = np.flatnonzero(partner > np.arange(partner.size))
        return np.ascontiguousarray([lead, partner[lead]], dtype=float) if lead.size else None

    @cached_property
    def speed_table(self) -> np.ndarray:
        """Per-ball constants of the high-speed model, (high_speed.N_SPEED_COLUMNS, n_balls), from the
        bearing's geometry (Geometry.speed_columns); ValueError when the bearing has none."""
        check_speed_model(self)
        table = np.empty((N_SPEED_COLUMNS, self.n_balls))
        # a geometry may give each row's constants itself (a shaft's rows come from several bearings)
        per_row = getattr(self.geometry, "row_speed_columns", None)
        k = 0
        for i, r in self.ball_rows:
            columns = per_row(i) if per_row is not None else self.geometry.speed_columns(r.contact_angle)
            table[:, k:k + r.n_balls] = np.asarray(columns)[:, None]
            k += r.n_balls
        table[PARTNER] = partner_columns(self.rows)  # the high-speed pass leaves these balls to four_point
        return table

    def slice_table(self, cage_angle: float = 0.0) -> np.ndarray:
        """The kernel's per-slice table of the roller rows (rollers.slice_table; no columns without rollers)."""
        if cage_angle == 0.0:
            return self._slice_table_at_rest
        return slice_table(self.roller_rows, self.n_balls, cage_angle)

    @cached_property
    def _slice_table_at_rest(self) -> np.ndarray:
        if not self.roller_rows:
            return np.empty((N_SLICE_COLUMNS, 0))
        return slice_table(self.roller_rows, self.n_balls)

    @cached_property
    def ball_exponents(self):
        """None when every row is Hertzian (n = 1.5, the kernel's sqrt path), else (n_balls,) exponents."""
        if all(r.exponent == 1.5 for _, r in self.ball_rows):
            return None
        return np.ascontiguousarray(self._ball_table_at_rest[EXPONENT])

    @cached_property
    def _ball_table_at_rest(self) -> np.ndarray:
        return self._build_ball_table(0.0)

    def _build_ball_table(self, cage_angle: float) -> np.ndarray:
        table = np.empty((N_BALL_COLUMNS, self.n_balls))
        azimuths = self._ball_azimuths(cage_angle)
        k = 0
        for (i, r), psi in zip(self.ball_rows, azimuths):
            sl = slice(k, k + r.n_balls)
            table[COS_PSI, sl] = np.cos(psi)
            table[SIN_PSI, sl] = np.sin(psi)
            table[AXIAL_OFFSET, sl] = r.axial_offset
            table[PITCH_RADIUS, sl] = r.pitch_radius
            table[UR0, sl], table[UZ0, sl], table[GAP2, sl] = r.groove_separations(r.radial_clearance,
                                                                                  r.axial_preload)
            table[A0, sl] = r.groove_center_distance
            table[KN, sl] = r.hertz_constant
            table[EXPONENT, sl] = r.exponent
            table[ROW, sl] = i
            table[DIRECTION, sl] = r.contact_direction
            table[DEFLECTION_LIMIT, sl] = r.validity_deflection
            k += r.n_balls
        table[WEIGHT] = 1.0
        table[SHARE] = 1.0
        _fill_mirror_half(table, azimuths)
        return table

    def operating_table(self, radial_clearance, axial_preload) -> tuple[np.ndarray, np.ndarray]:
        """Each case's own operating clearance and preload as the kernels take them (contract.CaseBlock.operating).

        ``radial_clearance`` rL and ``axial_preload`` d0: (N, n_rows) mm, each row's values in each case (a ball
        row's as Row's fields, a roller row's as RollerRow's). Returns (operating, valid): operating (N, n_rows,
        schema.N_OPERATING) float64, what each row's element kind sets in its tables (Row.operating_columns,
        RollerRow.operating_columns: the same expressions as the bearing's own tables, so a case with the
        bearing's own rL and d0 gives its results bit for bit); valid (N,) bool, False where a row's values
        fail its own checks (Row.in_model_range): such a case is not the model's and must not be solved."""
        rL = np.asarray(radial_clearance, dtype=float)
        d0 = np.asarray(axial_preload, dtype=float)
        if rL.ndim != 2 or rL.shape[1] != self.n_rows or d0.shape != rL.shape:
            raise ValueError(f"radial_clearance and axial_preload must be (N, {self.n_rows}) arrays in mm (one "
                             f"column per bearing row), got {rL.shape} and {d0.shape}")
        operating = np.empty((rL.shape[0], self.n_rows, N_OPERATING))
        valid = np.ones(rL.shape[0], dtype=bool)
        for i, r in enumerate(self.rows):
            operating[:, i] = r.operating_columns(rL[:, i], d0[:, i])
            valid &= r.in_model_range(rL[:, i], d0[:, i])
        return operating, valid

    def _ball_azimuths(self, cage_angle: float) -> list[np.ndarray]:
        """Each ball row's azimuths psi (rad), as the table places them."""
        return [math.radians(r.first_ball_angle) + cage_angle + 2.0 * math.pi * np.arange(r.n_balls) / r.n_balls
                for _, r in self.ball_rows]

    def describe(self) -> str:
        """One line per row, for reports and HDF5 provenance."""
        lines = [f"{self.name or 'bearing'} ({self.arrangement}, {self.n_rows} rows)"]
        for i, r in enumerate(self.rows):
            lines.append(f"  row {i}: {r.describe_line()}")
        return "\n".join(lines)

    def to_dict(self) -> dict:
        """The bearing as a ``[bearing]`` table with explicit ``rows`` (round-trips through TOML)."""
        return {"name": self.name, "arrangement": self.arrangement, "rows": merged(self.rows)}


def _fill_mirror_half(table: np.ndarray, azimuths: list[np.ndarray]) -> None:
    """Fill the table's mirror half (rows MIRROR_HALF + field, BALL_OF, MIRROR_OF, HALF_COUNT) from its full
    rows: every ball row must map onto itself under psi -> -psi, and every ball's column must equal its
    image's in every field but the azimuth's sine, else HALF_COUNT is 0 and the kernel always sums every
    ball. The second condition is what the element set states by itself: any per-element property kept in
    the table (a ball of its own) switches the half off where it breaks the symmetry, never silently
    summed wrong.

    A row's balls sit at psi_j = theta + 2 pi j / Z; -psi_j is a ball's place exactly when theta is a
    multiple k pi / Z, and then it is ball m = -(j + k) mod Z's (O(Z), for rows of any size)."""
    table[MIRROR_HALF:] = 0.0
    columns = []  # (ball, its image: itself on the plane)
    start = 0
    for psi in azimuths:
        n = psi.shape[0]
        if n == 0:
            continue
        theta = float(psi[0])
        k = round(theta * n / math.pi)
        if abs(theta - k * math.pi / n) > MIRROR_ANGLE_TOL:
            return  # this row is not its own mirror image: no symmetry to use
        for j in range(n):
            m = (-(j + k)) % n
            if j <= m:
                columns.append((start + j, start + m))
        start += n
    if not all(_mirror_images(table, j, m) for j, m in columns):
        return  # a ball unlike its image (a per-element property): no symmetry to use
    for c, (j, m) in enumerate(columns):
        table[MIRROR_HALF:MIRROR_HALF + N_BALL_FIELDS, c] = table[:N_BALL_FIELDS, j]
        if m == j:  # on the plane: exactly, so that the y-odd terms vanish
            table[MIRROR_HALF + COS_PSI, c] = math.copysign(1.0, table[COS_PSI, j])
            table[MIRROR_HALF + SIN_PSI, c] = 0.0
        else:
            table[MIRROR_HALF + KN, c] *= 2.0
            table[MIRROR_HALF + WEIGHT, c] = 2.0
            table[MIRROR_HALF + SHARE, c] = 0.5
        table[BALL_OF, c] = j
        table[MIRROR_OF, c] = m
    table[HALF_COUNT] = len(columns)


def without_mirror_half(table: np.ndarray) -> np.ndarray:
    """A copy of a ball table with its mirror half switched off (HALF_COUNT 0): the kernel sums every ball."""
    table = table.copy()
    table[HALF_COUNT] = 0.0
    return table


def _mirror_images(table: np.ndarray, j: int, m: int) -> bool:
    """Whether ball m's column is ball j's mirrored across the xz-plane: every field equal, but the sine of
    the azimuth opposite (both to MIRROR_ANGLE_TOL, as the azimuths are)."""
    others = [f for f in range(N_BALL_FIELDS) if f not in (COS_PSI, SIN_PSI)]
    return (bool(np.array_equal(table[others, j], table[others, m]))
            and abs(table[COS_PSI, j] - table[COS_PSI, m]) <= MIRROR_ANGLE_TOL
            and abs(table[SIN_PSI, j] + table[SIN_PSI, m]) <= MIRROR_ANGLE_TOL)


ROW_KEYS = tuple(f.name for f in fields(Row))
#: Row keys a compact [bearing] table shares between its rows.
SHARED_ROW_KEYS = ("n_balls", "hertz_constant", "pitch_radius", "groove_center_distance", "contact_angle", "exponent",
                   "radial_clearance", "first_ball_angle", "deflection_limit")
_COMPACT_KEYS = set(SHARED_ROW_KEYS) | set(ROLLER_KEYS) | {"arrangement", "row_offset", "axial_preload", "name"}
#: Keys a row table may hold: a ball row's or a roller row's (``element`` says which).
ALL_ROW_KEYS = tuple(sorted(set(ROW_KEYS) | set(ROLLER_KEYS)))


def preset_table(name: str) -> dict:
    """A copy of a shipped preset's ``[bearing]`` table (a catalogue file given by model parameters)."""
    validate.choice(name, "preset", preset_names())
    return catalogue_table(name)


def check_keys(table: dict, allowed, where: str) -> None:
    """FieldError naming ``where`` when ``table`` is not a table or has keys outside ``allowed``."""
    validate.table(table, where, allowed)


#: Keys every row must give.
REQUIRED_ROW_KEYS = ("n_balls", "hertz_constant", "pitch_radius", "groove_center_distance", "contact_angle")


def _row(values, where: str):
    """Build a Row (``element`` "ball" or absent) or a RollerRow from a table of keywords, naming where it
    came from in any error."""
    if not isinstance(values, dict):
        validate.table(values, where, ROW_KEYS)  # says what a row must be
    element = values.get("element", "ball")
    if element in ("ball", FOUR_POINT):
        values = {k: v for k, v in values.items() if k != "element"}
        validate.table(values, where, ROW_KEYS, REQUIRED_ROW_KEYS)
        cls = Row if element == "ball" else FourPointRow
    else:
        validate.choice(element, f"{where}.element" if where else "element", ("ball", FOUR_POINT, *ROLLER_ELEMENTS))
        values = dict(values)
        if "first_ball_angle" in values:
            values["first_element_angle"] = values.pop("first_ball_angle")
        validate.table(values, where, ROLLER_KEYS, REQUIRED_ROLLER_KEYS)
        cls = RollerRow
    try:
        return cls(**values)
    except validate.FieldError as err:
        raise err.within(where) from None


def _per_row(name: str, value, n_rows: int) -> list[float]:
    """One number for every row, or a list of one number per row."""
    if isinstance(value, (list, tuple, np.ndarray)):
        if len(value) != n_rows:
            raise validate.FieldError(name, f"must be one number or a list of {n_rows} numbers (one per row), "
                                      f"got {len(value)} numbers", show_value=False)
        return [validate.number(v, f"{name}[{i}]") for i, v in enumerate(value)]
    return [validate.number(value, name)] * n_rows
