"""Roller rows from catalogue dimensions: ``[bearing.geometry]`` with ``element`` a roller.

The whole roller's line-contact constant K of both raceways in series follows from Palmgren's steel
line contact, delta = 3.84e-5 Q^0.9 / l^0.8 (mm, N) per raceway (Palmgren, Ball and Roller Bearing
Engineering, 3rd ed., 1959; Harris & Kotzalas, Essential Concepts of Bearing Technology, 5th ed.,
ch. 6): K_contact = (1/3.84e-5)^(10/9) l^(8/9) = 80 590 l^(8/9), and two equal contacts in series,
K = K_contact 2^(-10/9) = 37 310 l^(8/9) N/mm^(10/9) (l in mm). Other materials scale K by E'/E'_steel
(E' = 2/((1 - nu1^2)/E1 + (1 - nu2^2)/E2); E'_steel from E = 207 000 N/mm^2, nu = 0.3, Palmgren's steel).
The roller centres lie on the pitch circle (pitch radius dm/2); the radial clearance per roller is half
the diametral clearance. Units: N, mm, degrees.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from .. import validate
from .bearing import Bearing
from .geometry import MATERIALS, STEEL, Material, check_boundary_dimensions, reduced_modulus
from .rollers import CROWNS, MAX_ROLLERS, MAX_SLICES, PRELOAD_APPROACH_LIMIT, ROLLER_ELEMENTS, radial_clearance_floor

#: Palmgren's line contact per raceway, delta = PALMGREN * Q^0.9 / l^0.8 (mm, N).
PALMGREN = 3.84e-5
#: E' of Palmgren's steel (E = 207 000 N/mm^2, nu = 0.3), N/mm^2.
PALMGREN_REDUCED_MODULUS = 207000.0 / (1.0 - 0.3 ** 2)
DOUBLE = {"DB": 1, "DF": 1, "DT": 1, "TDO": 1, "TDI": 1}


def line_constant(length: float, modulus_ratio: float = 1.0) -> float:
    """K of a whole roller, both raceways in series, N/mm^(10/9): (1/3.84e-5)^(10/9) l^(8/9) 2^(-10/9),
    times E'/E'_steel."""
    per_raceway = (1.0 / PALMGREN) ** (10.0 / 9.0) * length ** (8.0 / 9.0)
    return per_raceway * 2.0 ** (-10.0 / 9.0) * modulus_ratio


@dataclass(frozen=True)
class RollerGeometry:
    """Catalogue dimensions of a roller row (each row of a double row alike).

    Parameters
    ----------
    element : {"cylindrical_roller", "tapered_roller"}
    n_rollers : int
        Z per row.
    roller_diameter : float
        Dw, mean roller diameter in mm (< pitch_diameter).
    roller_effective_length : float
        l, effective length in mm (> 0).
    pitch_diameter : float
        dm, diameter of the roller centres in mm.
    contact_angle : float
        Degrees: 0 for cylindrical rollers; the cup angle of tapered rollers (e.g. atan(e/1.5) from a
        catalogue's calculation factor e).
    diametral_clearance : float
        Pd in mm (radial clearance per roller Pd/2); a negative Pd (interference) may press each roller
        by at most 0.005 l (rollers.PRELOAD_APPROACH_LIMIT).
    row_spacing : float or None
        2e in mm between the two rows' roller centres (double rows).
    roller_material, ring_material : Material
    slices, crown, crown_radius, crown_design_load
        As :class:`fastbearing.RollerRow`.
    dynamic_load_rating, static_load_rating : float or None
        The catalogue's C and C0 (N), kept with the bearing.
    bore, outer_diameter, width : float or None
        The boundary dimensions d, D and the width (a tapered bearing's total width T) in mm (ISO 15,
        ISO 355), from the maker's catalogue: optional, needed for fits (d < dm - Dw, D > dm + Dw).
    """

    element: str
    n_rollers: int
    roller_diameter: float
    roller_effective_length: float
    pitch_diameter: float
    contact_angle: float = 0.0
    diametral_clearance: float = 0.0
    row_spacing: float | None = None
    roller_material: Material = STEEL
    ring_material: Material = STEEL
    slices: int = 30
    crown: str = "none"
    crown_radius: float | None = None
    crown_design_load: float | None = None
    dynamic_load_rating: float | None = None
    static_load_rating: float | None = None
    bore: float | None = None
    outer_diameter: float | None = None
    width: float | None = None

    def __post_init__(self):
        v = validate
        set_ = object.__setattr__
        v.choice(self.element, "element", ROLLER_ELEMENTS)
        set_(self, "n_rollers", v.integer(self.n_rollers, "n_rollers", low=1, high=MAX_ROLLERS))
        D = v.number(self.roller_diameter, "roller_diameter", low=0, low_open=True, units="mm")
        set_(self, "roller_diameter", D)
        dm = v.number(self.pitch_diameter, "pitch_diameter", low=D, low_open=True,
                      units="mm (more than roller_diameter)")
        set_(self, "pitch_diameter", dm)
        z_max = int(math.pi / math.asin(D / dm) + 1e-9)
        if self.n_rollers > z_max:
            raise v.FieldError("n_rollers", f"must be <= {z_max} for roller_diameter {D!r} mm on pitch_diameter "
                               f"{dm!r} mm (more would overlap)", self.n_rollers)
        set_(self, "roller_effective_length", v.number(self.roller_effective_length, "roller_effective_length", low=0,
                                                       low_open=True, high=dm, units="mm"))
        set_(self, "diametral_clearance", v.number(self.diametral_clearance, "diametral_clearance", units="mm"))
        if self.row_spacing is not None:
            set_(self, "row_spacing", v.number(self.row_spacing, "row_spacing", low=0, units="mm"))
        for name in ("roller_material", "ring_material"):
            if not isinstance(getattr(self, name), Material):
                raise v.FieldError(name, "must be a fastbearing.Material", getattr(self, name))
        for name in ("dynamic_load_rating", "static_load_rating"):
            if getattr(self, name) is not None:
                set_(self, name, v.number(getattr(self, name), name, low=0, low_open=True, units="N"))
        check_boundary_dimensions(self, D)
        set_(self, "slices", v.integer(self.slices, "slices", low=1, high=MAX_SLICES))
        v.choice(self.crown, "crown", CROWNS)
        try:
            self.row_keywords()  # the row's own checks (contact angle, crown) under the same names
        except v.FieldError as err:
            if err.field != "radial_clearance":
                raise
            self._interference_error()

    def _interference_error(self):
        """The row's interference bound under the key the user typed: diametral_clearance (mm), Pd = 2 rL."""
        limit = PRELOAD_APPROACH_LIMIT * self.roller_effective_length
        bound = 2.0 * radial_clearance_floor(self.contact_angle, limit)
        raise validate.FieldError("diametral_clearance", f"must be >= {bound:.6g} mm: an interference may press "
                                  f"each roller by at most {PRELOAD_APPROACH_LIMIT:g} l = {limit:.6g} mm",
                                  self.diametral_clearance) from None

    @property
    def reduced_modulus(self) -> float:
        """E' = 2/((1-nu_r^2)/E_r + (1-nu_ring^2)/E_ring) in N/mm^2."""
        return reduced_modulus(self.roller_material, self.ring_material)

    @property
    def hertz_constant(self) -> float:
        """K of a whole roller, both raceways in series, N/mm^(10/9)."""
        return line_constant(self.roller_effective_length, self.reduced_modulus / PALMGREN_REDUCED_MODULUS)

    @property
    def row_offset(self) -> float | None:
        return None if self.row_spacing is None else self.row_spacing / 2.0

    def row_keywords(self) -> dict:
        """The :class:`fastbearing.RollerRow` keywords this geometry fixes."""
        from .rollers import RollerRow

        kw = dict(element=self.element, n_rollers=self.n_rollers, hertz_constant=self.hertz_constant,
                  pitch_radius=self.pitch_diameter / 2.0, roller_effective_length=self.roller_effective_length,
                  contact_angle=self.contact_angle, radial_clearance=self.diametral_clearance / 2.0,
                  slices=self.slices, crown=self.crown, crown_radius=self.crown_radius,
                  crown_design_load=self.crown_design_load, reduced_modulus=self.reduced_modulus)
        RollerRow(**kw)  # raises a FieldError naming the key
        return kw

    def bearing(self, arrangement: str = "single", *, name: str = "", axial_preload=0.0,
                first_element_angle: float = 0.0) -> Bearing:
        """A :class:`fastbearing.Bearing` of this geometry, carrying it in ``bearing.geometry``."""
        row = {**self.row_keywords(), "first_element_angle": first_element_angle}
        if arrangement == "single":
            b = Bearing.single(name=name, axial_preload=axial_preload, **row)
        elif arrangement in DOUBLE:
            if self.row_spacing is None:
                raise ValueError(f"row_spacing (2e, mm, >= 0) is required for arrangement {arrangement!r}")
            b = Bearing.double(arrangement, self.row_offset, axial_preload=axial_preload, name=name, **row)
        else:
            raise ValueError(f"arrangement must be one of ['single', {', '.join(repr(a) for a in DOUBLE)}], "
                             f"got {arrangement!r}")
        return replace(b, geometry=self)

    def describe(self) -> str:
        spacing = "" if self.row_spacing is None else f", row spacing 2e={self.row_spacing:g} mm"
        return (f"{self.element.replace('_', ' ')}s: Z={self.n_rollers}, Dw={self.roller_diameter:g} mm, "
                f"l={self.roller_effective_length:g} mm, dm={self.pitch_diameter:g} mm, a={self.contact_angle:g} deg, "
                f"Pd={self.diametral_clearance:g} mm{spacing}")


ROLLER_GEOMETRY_KEYS = ("element", "n_rollers", "roller_diameter", "roller_effective_length", "pitch_diameter",
                        "contact_angle", "diametral_clearance", "row_spacing", "youngs_modulus", "poisson_ratio",
                        "material", "slices", "crown", "crown_radius", "crown_design_load", "dynamic_load_rating",
                        "static_load_rating", "bore", "outer_diameter", "width")
_REQUIRED = ("element", "n_rollers", "roller_diameter", "roller_effective_length", "pitch_diameter")


def roller_geometry_from_table(table: dict, where: str = "bearing.geometry") -> RollerGeometry:
    """A :class:`RollerGeometry` from a parsed ``[bearing.geometry]`` table (angles in degrees); a
    ValueError names the key. ``youngs_modulus``/``poisson_ratio`` set rollers and rings alike;
    ``material`` names the rollers' (steel by default)."""
    validate.table(table, where, ROLLER_GEOMETRY_KEYS, _REQUIRED)
    values = {k: table[k] for k in ROLLER_GEOMETRY_KEYS if k in table and k not in
              ("youngs_modulus", "poisson_ratio", "material")}
    try:
        ring = STEEL if not ({"youngs_modulus", "poisson_ratio"} & set(table)) else Material(
            "custom", table.get("youngs_modulus", STEEL.youngs_modulus), table.get("poisson_ratio", STEEL.poisson_ratio))
        roller = MATERIALS[validate.choice(table["material"], "material", sorted(MATERIALS))] \
            if "material" in table else ring
        return RollerGeometry(**values, roller_material=roller, ring_material=ring)
    except validate.FieldError as err:
        raise err.within(where) from None
