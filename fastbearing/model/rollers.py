"""Roller rows: cylindrical and tapered rollers as sliced line contacts with a fixed normal.

A roller row has Z rollers at azimuths psi_j = psi0 + 2 pi j / Z, a constant contact angle a (0 for
cylindrical rollers, the cup angle for tapered ones), an axial offset and a contact direction s, as a
ball row. Each roller is cut into ``slices`` laminae of width w = l/slices along its effective length l;
slice k sits at x_k (from the roller's middle) along the generatrix t = (-s sin a, cos a) in the
(radial, axial) plane. Its approach along the fixed normal n = (cos a, s sin a) is

    delta_k = n . (dr_k, dz_k) + d0 sin(a) - rL cos(a) - c(x_k)

with (dr_k, dz_k) the inner ring's radial and axial displacement at the slice (the ball loop's rigid-ring
expressions at the slice's radius and axial position), d0 the axial preload, rL the radial clearance and
c(x) the crown drop. A preload presses the row whatever its contact direction: d0 moves the rings
together along the row's own axial direction, s d0 on the axial approach as a ball row's, whose
projection on n is d0 sin(a) for either s (both rows of a TDO or TDI pair are preloaded). Its load is
q_k = (w/l) K max(delta_k, 0)^(10/9), K the whole roller's line-contact constant (inner and outer raceway
in series), so an evenly loaded uncrowned roller carries K delta^(10/9) whatever the slice count. The
kernel (kernel.py) sums the slices like the balls. Roller-rib contact and the tapered roller's own
equilibrium between cone and cup are not modelled (the cup angle carries the normal), as in Lim & Singh
(1990).

Units: N, mm; angles in degrees in the definition, rad in the kernel.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import validate
from ..engine.schema import (N_OPERATING, N_SLICE_COLUMNS, OP_APPROACH, S_ANGLE, S_AXIAL, S_COS_PSI, S_COUNT, S_NORMAL_R, S_NORMAL_Z,  # noqa: F401
                     S_CROWN, S_OFFSET, S_POSITION, S_RADIUS, S_ROLLER, S_ROW, S_SCALE, S_SIN_PSI, S_STIFFNESS)

ELEMENTS = ("ball", "cylindrical_roller", "tapered_roller")
ROLLER_ELEMENTS = ELEMENTS[1:]
CROWNS = ("none", "circular", "logarithmic")
#: Line-contact load-deflection exponent (Palmgren): Q = K delta^(10/9).
LINE_EXPONENT = 10.0 / 9.0
MAX_SLICES = 1000
MAX_ROLLERS = 10_000
#: E' = E/(1 - nu^2) of steel (E = 207 000 N/mm^2, nu = 0.3), N/mm^2: the default of the logarithmic crown.
STEEL_REDUCED_MODULUS = 207000.0 / (1.0 - 0.3 ** 2)

#: A roller row's deflection scale as a fraction of its effective length (the solver's step and smoothing
#: scale, as A0 is a ball row's): 0.02 l, e.g. 0.2 mm for a 10 mm roller.
DEFLECTION_SCALE = 0.02
#: Largest unloaded approach d0 sin(a) - rL cos(a) a preload or an interference may set, as a fraction of the
#: roller's effective length l: about the approach at which a steel roller of usual proportions reaches the
#: ~4000 N/mm^2 contact pressure of its static rating (ISO 76). Palmgren's K and Hertz's line contact at the
#: inner raceway put that approach at 0.0183 (R/l)^0.9 l, R = Dw (1 - g)/2: 0.0052 l for l = 1.7 Dw (the
#: 30206), 0.0086 l for l = 0.93 Dw (the NU 205); shorter rollers are bounded on the safe side.
PRELOAD_APPROACH_LIMIT = 0.005


@dataclass(frozen=True)
class RollerRow:
    """One row of rollers (docs/rollers.md).

    Parameters
    ----------
    element : {"cylindrical_roller", "tapered_roller"}
    n_rollers : int
        Z, rollers in the row, >= 1.
    hertz_constant : float
        K, the whole roller's line-contact constant, inner and outer raceway in series, N/mm^(10/9), > 0.
    pitch_radius : float
        Radius of the roller centres in mm, > 0.
    roller_effective_length : float
        l, effective (straight) length of the roller in mm, > 0.
    contact_angle : float
        a in degrees: 0 for cylindrical rollers; the cup angle of tapered rollers, in (0, 60].
    axial_offset : float
        Axial position of the roller centres in mm.
    contact_direction : int
        s, +1 or -1: the sign of the axial component of the contact normal (as a ball row's).
    radial_clearance : float
        rL, radial clearance per roller in mm (negative: interference).
    axial_preload : float
        d0, axial preload of the row in mm (tapered rows), pressing the row whatever its contact direction
        (negative: an axial clearance). The unloaded approach d0 sin(a) - rL cos(a) is at most 0.005 l
        (PRELOAD_APPROACH_LIMIT).
    first_element_angle : float
        Azimuth of the row's first roller in degrees.
    slices : int
        Laminae per roller, in [1, 1000] (default 30).
    crown : {"none", "circular", "logarithmic"}
        Profile of the roller: none, a circular arc of ``crown_radius`` (mm, > l/2), or Lundberg's
        logarithmic profile for ``crown_design_load`` (N) with ``reduced_modulus`` E' (N/mm^2).
    """

    element: str
    n_rollers: int
    hertz_constant: float
    pitch_radius: float
    roller_effective_length: float
    contact_angle: float = 0.0
    axial_offset: float = 0.0
    contact_direction: int = 1
    radial_clearance: float = 0.0
    axial_preload: float = 0.0
    first_element_angle: float = 0.0
    slices: int = 30
    crown: str = "none"
    crown_radius: float | None = None
    crown_design_load: float | None = None
    reduced_modulus: float = STEEL_REDUCED_MODULUS

    def __post_init__(self):
        v = validate
        set_ = object.__setattr__
        v.choice(self.element, "element", ROLLER_ELEMENTS)
        set_(self, "n_rollers", v.integer(self.n_rollers, "n_rollers", low=1, high=MAX_ROLLERS))
        if isinstance(self.contact_direction, bool) or self.contact_direction not in (1, -1):
            raise v.FieldError("contact_direction", "must be +1 or -1", self.contact_direction)
        set_(self, "contact_direction", int(self.contact_direction))
        set_(self, "hertz_constant", v.number(self.hertz_constant, "hertz_constant", low=0, low_open=True,
                                              units="N/mm^(10/9)"))
        set_(self, "pitch_radius", v.number(self.pitch_radius, "pitch_radius", low=0, low_open=True, units="mm"))
        length = v.number(self.roller_effective_length, "roller_effective_length", low=0, low_open=True, units="mm")
        if length > 2.0 * self.pitch_radius:
            raise v.FieldError("roller_effective_length", f"must be <= 2 pitch_radius ({2 * self.pitch_radius:g} mm)",
                               length)
        set_(self, "roller_effective_length", length)
        if self.element == "cylindrical_roller":
            set_(self, "contact_angle", v.number(self.contact_angle, "contact_angle", low=0, high=0,
                                                 units="degrees (cylindrical rollers: 0)"))
        else:
            set_(self, "contact_angle", v.number(self.contact_angle, "contact_angle", low=0, high=60, low_open=True,
                                                 units="degrees"))
        for name in ("axial_offset", "first_element_angle", "radial_clearance", "axial_preload"):
            set_(self, name, v.number(getattr(self, name), name))
        set_(self, "slices", v.integer(self.slices, "slices", low=1, high=MAX_SLICES))
        v.choice(self.crown, "crown", CROWNS)
        set_(self, "reduced_modulus", v.number(self.reduced_modulus, "reduced_modulus", low=0, low_open=True,
                                               units="N/mm^2"))
        if self.crown == "circular":
            if self.crown_radius is None:
                raise v.FieldError("crown_radius", "is required with crown = \"circular\" (mm, > l/2)",
                                   show_value=False)
            set_(self, "crown_radius", v.number(self.crown_radius, "crown_radius", low=length / 2, low_open=True,
                                                units="mm (more than half the roller length)"))
        elif self.crown_radius is not None:
            raise v.FieldError("crown_radius", "goes with crown = \"circular\"", self.crown_radius)
        if self.crown == "logarithmic":
            if self.crown_design_load is None:
                raise v.FieldError("crown_design_load", "is required with crown = \"logarithmic\" (N, > 0)",
                                   show_value=False)
            set_(self, "crown_design_load", v.number(self.crown_design_load, "crown_design_load", low=0,
                                                     low_open=True, units="N"))
        elif self.crown_design_load is not None:
            raise v.FieldError("crown_design_load", "goes with crown = \"logarithmic\"", self.crown_design_load)
        if self.element == "cylindrical_roller" and self.axial_preload != 0.0:
            raise v.FieldError("axial_preload", "has no effect on a cylindrical roller row (its normal is radial)",
                               self.axial_preload)
        self._check_preload()

    def _check_preload(self) -> None:
        """Keep the unloaded approach d0 sin(a) - rL cos(a) (mm) within PRELOAD_APPROACH_LIMIT l, naming the key
        that set the preload with its bound, the other held at its value (as a ball row's check). An axial
        clearance (d0 < 0) is not bounded: the normal is fixed, so no contact direction can turn round."""
        limit = self.preload_approach_limit
        if self.unloaded_approach <= limit:
            return
        a = math.radians(self.contact_angle)
        rL, d0 = self.radial_clearance, self.axial_preload
        if rL < 0 and d0 * math.sin(a) <= limit:
            bound = radial_clearance_floor(self.contact_angle, limit, d0)
            raise validate.FieldError("radial_clearance", f"must be >= {bound:.6g} mm (a diametral clearance >= "
                                      f"{2 * bound:.6g} mm): an interference may press each roller by at most "
                                      f"{PRELOAD_APPROACH_LIMIT:g} l = {limit:.6g} mm", rL)
        bound = (limit + rL * math.cos(a)) / math.sin(a)
        raise validate.FieldError("axial_preload", f"must be <= {bound:.6g} mm: an axial preload may press each "
                                  f"roller by at most {PRELOAD_APPROACH_LIMIT:g} l = {limit:.6g} mm", d0)

    # -- what every element kind's row tells (bearing.Row answers the same) -----------------------------------
    #: Its elements, in words (for reports and pictures).
    element_word = "rollers"
    #: Where a local defect may sit (model/defects.py): either race (a roller's own defect is not modelled).
    defect_races = ("outer", "inner")

    @property
    def n_elements(self) -> int:
        return self.n_rollers

    def describe_line(self) -> str:
        """The row in one line, with units (reports and HDF5 provenance)."""
        return (f"{self.element}, z={self.axial_offset:g} mm, s={self.contact_direction:+d}, Z={self.n_rollers}, "
                f"a={self.contact_angle:g} deg, l={self.roller_effective_length:g} mm, R={self.pitch_radius:g} mm, "
                f"K={self.hertz_constant:g} N/mm^(10/9), {self.slices} slices, crown {self.crown}, "
                f"rL={self.radial_clearance:g} mm, d0={self.axial_preload:g} mm")

    def report(self) -> dict:
        """The row's derived parameters, JSON-ready (lengths mm, angles deg, K N/mm^(10/9))."""
        return {"element": self.element, "axial_offset": self.axial_offset,
                "contact_direction": self.contact_direction, "n_rollers": self.n_rollers,
                "hertz_constant": self.hertz_constant, "pitch_radius": self.pitch_radius,
                "roller_effective_length": self.roller_effective_length, "contact_angle_deg": self.contact_angle,
                "slices": self.slices, "slice_width": self.roller_effective_length / self.slices,
                "crown": self.crown, "crown_drop_at_ends": float(self.crown_drop(self.slice_positions[[0]])[0]),
                "radial_clearance": self.radial_clearance, "axial_preload": self.axial_preload}

    @property
    def deflection_scale(self) -> float:
        """A length that bounds the solver's early Newton steps and its smoothing, mm: 0.02 l."""
        return DEFLECTION_SCALE * self.roller_effective_length

    @property
    def unloaded_approach(self) -> float:
        """d0 sin(a) - rL cos(a) in mm: the approach of every roller's middle at q = 0 (> 0: preloaded)."""
        return float(self.approach_at(self.radial_clearance, self.axial_preload))

    def approach_at(self, radial_clearance, axial_preload):
        """d0 sin(a) - rL cos(a) in mm for a radial clearance rL and an axial preload d0 (mm; floats or arrays):
        the one expression the slice table and a case's own values (:meth:`operating_columns`) share."""
        a = math.radians(self.contact_angle)
        return axial_preload * math.sin(a) - radial_clearance * math.cos(a)

    def operating_columns(self, radial_clearance, axial_preload) -> np.ndarray:
        """(n, schema.N_OPERATING) float64: what rL and d0 ((n,) arrays, mm) set in the kernel's tables for each
        case (schema OP_APPROACH: the unloaded approach; bearing.Bearing.operating_table)."""
        out = np.zeros((np.shape(radial_clearance)[0], N_OPERATING))
        out[:, OP_APPROACH] = self.approach_at(np.asarray(radial_clearance, float), np.asarray(axial_preload, float))
        return out

    def in_model_range(self, radial_clearance, axial_preload) -> np.ndarray:
        """(n,) bool: where rL and d0 ((n,) arrays, mm) pass the row's own checks (the unloaded approach at most
        PRELOAD_APPROACH_LIMIT l; a cylindrical row takes no axial preload)."""
        rL, d0 = np.asarray(radial_clearance, float), np.asarray(axial_preload, float)
        ok = np.isfinite(rL) & np.isfinite(d0) & (self.approach_at(rL, d0) <= self.preload_approach_limit)
        if self.element == "cylindrical_roller":
            ok &= d0 == 0.0
        return ok

    @property
    def preload_approach_limit(self) -> float:
        """The largest unloaded approach a preload may set, mm: PRELOAD_APPROACH_LIMIT l."""
        return PRELOAD_APPROACH_LIMIT * self.roller_effective_length

    @property
    def slice_positions(self) -> np.ndarray:
        """x_k in mm: the slice centres along the roller, from its middle."""
        w = self.roller_effective_length / self.slices
        return -0.5 * self.roller_effective_length + (np.arange(self.slices) + 0.5) * w

    def crown_drop(self, x) -> np.ndarray:
        """c(x) in mm at positions x (mm from the roller's middle, |x| < l/2).

        circular: Rc - sqrt(Rc^2 - x^2). logarithmic: Lundberg's profile for the design load Q,
        c(x) = (2 Q / (pi l E')) ln(1 / (1 - (2x/l)^2)) (Lundberg 1939; Harris & Kotzalas, Essential
        Concepts of Bearing Technology, 5th ed., ch. 6), which keeps the pressure along the roller even
        at Q.
        """
        x = np.asarray(x, float)
        if self.crown == "circular":
            Rc = self.crown_radius
            # Rc - sqrt(Rc^2 - x^2) without the cancellation: it lost about log10(Rc^2/x^2) digits
            return x * x / (Rc + np.sqrt(Rc * Rc - x * x))
        if self.crown == "logarithmic":
            l = self.roller_effective_length
            # ln(1/(1 - u)) = -log1p(-u): 1 - u rounds away the digits of a small u (slices near the middle)
            return (2.0 * self.crown_design_load / (math.pi * l * self.reduced_modulus)
                    * -np.log1p(-(2.0 * x / l) ** 2))
        return np.zeros_like(x)


def radial_load_note(rows, load) -> str:
    """Why roller rows ``rows`` may not hold ``load`` (N, N*mm), in one line ("" if they may): tapered rows all
    facing one way (a single row, a tandem) turn a radial load Fr into an axial one through their fixed
    contact normal, so they hold Fr only with an axial load of at least Fr tan(a) on their contact side."""
    directions = {r.contact_direction for r in rows}
    if not rows or len(directions) != 1 or min(r.contact_angle for r in rows) <= 0.0:
        return ""
    s = directions.pop()
    Fr = float(math.hypot(load[0], load[1]))
    need = Fr * math.tan(math.radians(min(r.contact_angle for r in rows)))
    if Fr == 0.0 or s * load[2] >= need:
        return ""
    side = "+z" if s > 0 else "-z"
    return (f"no solution: a tapered roller row's fixed contact normal turns the radial load Fr = {Fr:g} N into an "
            f"axial one, so it holds Fr only with an axial load of at least Fr tan(a) = {need:g} N on its contact "
            f"side ({side}); Fz = {float(load[2]):g} N. Give the axial load the mounting carries (the other "
            "bearing's reaction), or hold the axial displacement: --fix dz=0 (Python: fixed={'dz': 0.0}) finds the "
            "axial reaction")


def radial_clearance_floor(contact_angle: float, limit: float, axial_preload: float = 0.0) -> float:
    """The smallest radial clearance rL in mm (most interference) that keeps d0 sin(a) - rL cos(a) <= limit
    (mm), a in degrees."""
    a = math.radians(contact_angle)
    return (axial_preload * math.sin(a) - limit) / math.cos(a)


def slice_table(rows, first_roller: int, cage_angle: float = 0.0) -> np.ndarray:
    """The kernel's per-slice table (N_SLICE_COLUMNS, n_slices) of the roller rows ``rows`` (pairs of
    (bearing row index, RollerRow)); rollers are numbered from ``first_roller`` in the element record."""
    n = sum(r.n_rollers * r.slices for _, r in rows)
    table = np.empty((N_SLICE_COLUMNS, n))
    k = 0
    roller = first_roller
    for index, r in rows:
        a = math.radians(r.contact_angle)
        s = r.contact_direction
        x = r.slice_positions
        crown = r.crown_drop(x)
        offset = r.unloaded_approach - crown
        for j in range(r.n_rollers):
            psi = math.radians(r.first_element_angle) + cage_angle + 2.0 * math.pi * j / r.n_rollers
            sl = slice(k, k + r.slices)
            table[S_COS_PSI, sl] = math.cos(psi)
            table[S_SIN_PSI, sl] = math.sin(psi)
            table[S_AXIAL, sl] = r.axial_offset  # the roller's centre; slice k is x_k further along t
            table[S_RADIUS, sl] = r.pitch_radius
            table[S_NORMAL_R, sl] = math.cos(a)
            table[S_NORMAL_Z, sl] = s * math.sin(a)
            table[S_OFFSET, sl] = offset
            table[S_STIFFNESS, sl] = r.hertz_constant / r.slices
            table[S_ROW, sl] = index
            table[S_ROLLER, sl] = roller
            table[S_ANGLE, sl] = a
            table[S_SCALE, sl] = r.deflection_scale
            table[S_POSITION, sl] = x
            table[S_COUNT, sl] = r.slices
            table[S_CROWN, sl] = crown
            k += r.slices
            roller += 1
    return table


ROLLER_KEYS = tuple(f for f in RollerRow.__dataclass_fields__)
REQUIRED_ROLLER_KEYS = ("element", "n_rollers", "hertz_constant", "pitch_radius", "roller_effective_length")
