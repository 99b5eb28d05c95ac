"""The ball element's row: Z balls at one axial place, one contact direction (docs/model.md, "A bearing is a set
of rows on one rigid inner ring"). Plain Python and validation; bearing.py turns rows into kernel tables.
Units: N, mm, rad, except the two angles a user types (``contact_angle``, ``first_ball_angle``), in degrees.
"""

from __future__ import annotations

import math
import sys
import warnings
from dataclasses import dataclass

import numpy as np

from .. import validate

#: Most balls a row may have (a sanity bound: real bearings have a few dozen).
MAX_BALLS = 10_000
#: Largest unloaded ball deflection a preload may set, as a fraction of A0: beyond it the contact is
#: no longer a small elastic one (A0 is about 5 % of the ball diameter).
PRELOAD_DEFLECTION_LIMIT = 0.1
#: Default validity limit of a ball's deflection without a geometry, as a fraction of A0: where steel
#: balls in grooves of the usual ratios (0.52, 0.53) reach a Hertz pressure of about 4200 N/mm^2
#: (6305: 0.145 A0; the SKF 32xx/33xx files: 0.16-0.17 A0).
VALIDITY_DEFLECTION = 0.15
#: Smallest plausible non-zero contact angle of an angular-contact ball row, degrees: below it (and not 0, a
#: deep-groove row) the angle was probably typed in radians (15 deg = 0.2618 rad).
SMALLEST_CONTACT_ANGLE = 1.0
#: How many distinct unit-slip warnings are remembered (each fires once: see :func:`unit_warning`).
_WARNED_LIMIT = 1000
_warned: dict[str, None] = {}


def unit_warning(message: str) -> None:
    """A ``UserWarning`` that a value looks typed in another unit than its field's (mm, degrees): plausible
    enough to compute with, so a warning, not an error.

    It fires once per distinct message (the field, its value and what was probably meant), however often the
    value is copied: a double row makes two rows of one table, a bearing file builds its rows more than once,
    ``Bearing.with_rows`` and a four-point row's contact pairs rebuild them. It points at the first caller
    outside fastbearing (the user's line)."""
    if message in _warned:
        return
    if len(_warned) >= _WARNED_LIMIT:
        _warned.pop(next(iter(_warned)))
    _warned[message] = None
    level, frame = 2, sys._getframe(1)
    while frame is not None and frame.f_globals.get("__name__", "").partition(".")[0] == "fastbearing":
        frame, level = frame.f_back, level + 1
    warnings.warn(message, UserWarning, stacklevel=level if frame is not None else 2)


def forget_unit_warnings() -> None:
    """Let every unit-slip warning fire again (tests; a long session that wants to see them anew)."""
    _warned.clear()


def check_contact_angle_unit(contact_angle: float) -> None:
    """Warn when a ball row's contact angle (degrees) is above 0 but below SMALLEST_CONTACT_ANGLE: probably
    radians."""
    if 0.0 < contact_angle < SMALLEST_CONTACT_ANGLE:
        unit_warning(f"contact_angle = {contact_angle:g} degrees is implausibly small for an angular-contact ball "
                     f"row (below {SMALLEST_CONTACT_ANGLE:g} degree): probably radians, i.e. "
                     f"{math.degrees(contact_angle):.4g} degrees; give it in degrees (0 for a deep-groove row)")


def free_contact_angle(groove_center_distance: float, contact_angle: float, radial_clearance: float) -> float:
    """a_f in rad: cos(a_f) = cos(a0) - rL/A0 for a row with radial play rL > 0 (a0 in rad; A0, rL in mm),
    a0 when rL <= 0. For a deep-groove row (a0 = 0): cos(a_f) = 1 - Pd/(2 A0)."""
    if radial_clearance <= 0:
        return contact_angle
    return math.acos(math.cos(contact_angle) - radial_clearance / groove_center_distance)


def _check_finite(name: str, value) -> float:
    """A finite number (not a bool or a string); ValueError naming ``name``."""
    return validate.number(value, name)


@dataclass(frozen=True)
class Row:
    """One row of balls (docs/model.md, "A bearing is a set of rows on one rigid inner ring").

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
        a0, unloaded contact angle in degrees, in [0, 90). A value above 0 but below 1 degree
        (SMALLEST_CONTACT_ANGLE) gives a UserWarning: probably radians.
    axial_offset : float
        z_r, signed axial position of the row centre from the bearing centre
        in mm (the paper's c1*e).
    contact_direction : int
        s_r, +1 or -1 (the paper's c3): the sign of the axial component of
        the contact line from inner to outer groove centre.
    exponent : float
        n, load-deflection exponent (1.5 for balls), > 1.
    radial_clearance : float
        rL, radial clearance per ball in mm (half the diametral clearance),
        < A0 cos(a0). Negative: a radial preload (interference); every ball is
        then loaded at q = 0, by a deflection of at most 10 % of A0.
    axial_preload : float
        d0, axial preload displacement of the row in mm, >= -A0 sin(a0) (a
        negative value is an axial clearance); not with rL > 0; its ball
        deflection at most 10 % of A0.
    first_ball_angle : float
        psi0, azimuth of the row's first ball in degrees.
    deflection_limit : float or None
        Largest ball deflection in mm for which the model (small elastic
        contacts) is taken as valid; a solution beyond it is flagged with
        the status warning ``beyond_validity``. None: 0.15 A0
        (VALIDITY_DEFLECTION), or for a row from catalogue geometry the
        deflection at which the Hertz pressure reaches the geometry's
        ``contact_pressure_limit`` (4200 N/mm^2 by default). > 0.
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
    deflection_limit: float | None = None

    def __post_init__(self):
        v = validate
        set_ = object.__setattr__
        set_(self, "n_balls", v.integer(self.n_balls, "n_balls", low=1, high=MAX_BALLS))
        if isinstance(self.contact_direction, bool) or self.contact_direction not in (1, -1):
            raise validate.FieldError("contact_direction", "must be +1 or -1", self.contact_direction)
        set_(self, "contact_direction", int(self.contact_direction))
        set_(self, "hertz_constant", v.number(self.hertz_constant, "hertz_constant", low=0, low_open=True,
                                              units="N/mm^n"))
        set_(self, "pitch_radius", v.number(self.pitch_radius, "pitch_radius", low=0, low_open=True, units="mm"))
        set_(self, "groove_center_distance", v.number(self.groove_center_distance, "groove_center_distance", low=0,
                                                      low_open=True, units="mm"))
        set_(self, "contact_angle", v.number(self.contact_angle, "contact_angle", low=0, high=90, high_open=True,
                                             units="degrees"))
        set_(self, "exponent", v.number(self.exponent, "exponent", low=1, high=3, low_open=True))
        for name in ("axial_offset", "first_ball_angle"):
            set_(self, name, v.number(getattr(self, name), name))
        set_(self, "radial_clearance", v.number(self.radial_clearance, "radial_clearance", units="mm"))
        set_(self, "axial_preload", v.number(self.axial_preload, "axial_preload", units="mm"))
        if self.deflection_limit is not None:
            set_(self, "deflection_limit", v.number(self.deflection_limit, "deflection_limit", low=0, low_open=True,
                                                    units="mm"))
        self._check_clearance_and_preload()
        check_contact_angle_unit(self.contact_angle)  # an accepted row only: no warning beside an error

    # -- what every element kind's row tells (rollers.RollerRow answers the same) --------------------------
    #: The element kind (a roller row's ``element`` key says its own).
    element = "ball"
    #: Its elements, in words (for reports and pictures).
    element_word = "balls"
    #: Where a local defect may sit (model/defects.py): either race, or a ball.
    defect_races = ("outer", "inner", "ball")

    @property
    def n_elements(self) -> int:
        return self.n_balls

    @property
    def deflection_scale(self) -> float:
        """A length that bounds the solver's early Newton steps, mm: A0."""
        return self.groove_center_distance

    def describe_line(self) -> str:
        """The row in one line, with units (reports and HDF5 provenance)."""
        return (f"z={self.axial_offset:g} mm, s={self.contact_direction:+d}, Z={self.n_balls}, "
                f"a0={self.contact_angle:g} deg, A0={self.groove_center_distance:g} mm, R={self.pitch_radius:g} mm, "
                f"Kn={self.hertz_constant:g} N/mm^{self.exponent:g}, rL={self.radial_clearance:g} mm, "
                f"d0={self.axial_preload:g} mm, psi0={self.first_ball_angle:g} deg")

    def report(self) -> dict:
        """The row's derived parameters, JSON-ready (lengths mm, angles deg and rad, Kn N/mm^n)."""
        af = self.free_contact_angle
        return {"axial_offset": self.axial_offset, "contact_direction": self.contact_direction,
                "n_balls": self.n_balls, "hertz_constant": self.hertz_constant, "exponent": self.exponent,
                "groove_center_distance": self.groove_center_distance, "pitch_radius": self.pitch_radius,
                "radial_clearance": self.radial_clearance, "contact_angle_deg": self.contact_angle,
                "free_contact_angle": af, "free_contact_angle_deg": math.degrees(af),
                "axial_preload": self.axial_preload, "rest_deflection": self.rest_deflection,
                "rest_contact_angle_deg": math.degrees(self.rest_contact_angle),
                "deflection_limit": self.validity_deflection}

    @property
    def validity_deflection(self) -> float:
        """The ball deflection in mm beyond which a solution is flagged ``beyond_validity``."""
        if self.deflection_limit is not None:
            return self.deflection_limit
        return VALIDITY_DEFLECTION * self.groove_center_distance

    @property
    def free_contact_angle(self) -> float:
        """a_f in rad: the contact angle once a pure axial load takes up the radial play (rL > 0):
        cos(a_f) = cos(a0) - rL/A0; a0 itself when there is no play (rL <= 0)."""
        return free_contact_angle(self.groove_center_distance, math.radians(self.contact_angle),
                                  self.radial_clearance)

    @property
    def rest_deflection(self) -> float:
        """delta0 in mm: each ball's deflection at q = 0 set by a preload (radial interference, axial
        preload); 0 without preload."""
        a0 = math.radians(self.contact_angle)
        u = math.hypot(self.groove_center_distance * math.cos(a0) - self.radial_clearance,
                       self.groove_center_distance * math.sin(a0) + self.axial_preload)
        return max(u - self.groove_center_distance, 0.0)

    @property
    def rest_contact_angle(self) -> float:
        """The contact angle in rad at q = 0 of a preloaded row (radial interference lowers it, an axial
        preload raises it); a0 without preload."""
        a0 = math.radians(self.contact_angle)
        return math.atan2(self.groove_center_distance * math.sin(a0) + self.axial_preload,
                          self.groove_center_distance * math.cos(a0) - self.radial_clearance)

    def groove_separations(self, radial_clearance, axial_preload):
        """(ur0, uz0, A^2 - A0^2 at q = 0) in mm, mm, mm^2 for a radial clearance rL and an axial preload d0
        (mm; floats or arrays): the ball table's UR0, UZ0 and GAP2, by one expression for the bearing's own
        table and a case's own values (:meth:`operating_columns`), so that both give the same bits.
        The gap in closed form (exactly 0 without clearance and preload): the kernel gets A^2 - A0^2 without
        cancellation."""
        A0, a0, s = self.groove_center_distance, math.radians(self.contact_angle), self.contact_direction
        rl, d0 = radial_clearance, axial_preload
        ur0 = A0 * math.cos(a0) - rl
        uz0 = s * (A0 * math.sin(a0) + d0)
        gap2 = -2.0 * A0 * rl * math.cos(a0) + rl * rl + 2.0 * A0 * d0 * math.sin(a0) + d0 * d0
        return ur0, uz0, gap2

    def operating_columns(self, radial_clearance, axial_preload) -> np.ndarray:
        """(n, schema.N_OPERATING) float64: the table's UR0, UZ0, GAP2 for each case's rL and d0 ((n,) arrays,
        mm; bearing.Bearing.operating_table)."""
        ur0, uz0, gap2 = self.groove_separations(np.asarray(radial_clearance, float), np.asarray(axial_preload, float))
        return np.stack(np.broadcast_arrays(ur0, uz0, gap2), axis=1)

    def in_model_range(self, radial_clearance, axial_preload) -> np.ndarray:
        """(n,) bool: where rL and d0 ((n,) arrays, mm) pass the row's own checks
        (:meth:`_check_clearance_and_preload`), vectorised."""
        A0, a0 = self.groove_center_distance, math.radians(self.contact_angle)
        rL, d0 = np.asarray(radial_clearance, float), np.asarray(axial_preload, float)
        radial, axial = A0 * math.cos(a0), A0 * math.sin(a0)
        with np.errstate(invalid="ignore"):
            return (np.isfinite(rL) & np.isfinite(d0) & (rL < radial) & (d0 >= -axial) & ~((d0 != 0) & (rL > 0))
                    & ~(np.hypot(radial - rL, axial + d0) - A0 > PRELOAD_DEFLECTION_LIMIT * A0))

    def _check_clearance_and_preload(self) -> None:
        """Keep the groove centres where the model holds (docs/model.md, "Per ball (row r, ball j at azimuth psi)"):
        on their own sides, and a preload (negative clearance, axial preload) that deflects each ball by at
        most 10 % of A0."""
        A0, a0 = self.groove_center_distance, math.radians(self.contact_angle)
        rL, d0 = self.radial_clearance, self.axial_preload
        radial, axial = A0 * math.cos(a0), A0 * math.sin(a0)
        if rL >= radial:
            raise validate.FieldError("radial_clearance", f"must be < A0 cos(a0) = {radial:.6g} mm (beyond it the "
                                      "inner and outer groove centres cross)", rL)
        if d0 < -axial:
            raise validate.FieldError("axial_preload", f"must be >= -A0 sin(a0) = {-axial:.6g} mm (an axial "
                                      "clearance beyond it turns the row's contact direction round)", d0)
        if d0 != 0 and rL > 0:
            raise validate.FieldError("axial_preload", "must be 0 when radial_clearance > 0 (an axial preload "
                                      f"needs zero or negative clearance; radial_clearance = {rL!r} mm)", d0)
        limit = PRELOAD_DEFLECTION_LIMIT * A0
        if math.hypot(radial - rL, axial + d0) - A0 > limit:
            # the bound on the key that set the preload, the other held at its value
            reach2 = (A0 + limit) ** 2
            if rL < 0 and reach2 > (axial + d0) ** 2:
                bound = radial - math.sqrt(reach2 - (axial + d0) ** 2)
                raise validate.FieldError("radial_clearance", f"must be >= {bound:.6g} mm: a radial preload "
                                          f"(negative clearance) may deflect each ball by at most "
                                          f"{PRELOAD_DEFLECTION_LIMIT:g} A0 = {limit:.6g} mm", rL)
            bound = math.sqrt(max(reach2 - (radial - rL) ** 2, 0.0)) - axial
            raise validate.FieldError("axial_preload", f"must be <= {bound:.6g} mm: an axial preload may deflect "
                                      f"each ball by at most {PRELOAD_DEFLECTION_LIMIT:g} A0 = {limit:.6g} mm", d0)
