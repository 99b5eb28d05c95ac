"""The bearing as mounted and running: fits, temperatures and speed -> operating clearance (issue 44, item 3).

Physics only (no file parsing, no change to :class:`fastbearing.Bearing`). Plain Python; every length is in
mm, every stress and modulus in N/mm^2 (= MPa), temperatures in deg C (differences in K), thermal expansion
in 1/K, density in kg/m^3, speed in rpm (converted here to rad/s, omega = 2 pi n / 60).

Bodies are plane-stress Lame annuli of their own material (docs: "Mounting, temperature and tolerances";
shared/research/mounting-and-tolerances.md section 1.1):

    shaft        annulus d0/2 .. d/2           (d0 = shaft_bore; d0 = 0: a solid disc)
    inner ring   annulus d/2  .. Di/2          Di = dm - Dw (balls; rollers: Dw = the roller diameter at its
                                               mid-length and dm the pitch diameter there)
    outer ring   annulus De/2 .. D/2           De = dm + Dw
    housing      annulus D/2  .. Dh/2          (Dh = housing_outer_diameter; None: infinitely thick)

Lame, an annulus a < r < b under inner pressure p_i and outer pressure p_o (Timoshenko & Goodier, Theory of
Elasticity, 3rd ed., sect. 28; plane stress):

    u(r)       = [ (1-nu)(p_i a^2 - p_o b^2) r + (1+nu) a^2 b^2 (p_i - p_o) / r ] / (E (b^2 - a^2))
    sigma_t(r) = (p_i a^2 - p_o b^2)/(b^2 - a^2) + (p_i - p_o) a^2 b^2 / ((b^2 - a^2) r^2)

Spinning annulus and solid disc, plane stress (Timoshenko & Goodier sect. 32; research 1.1(e)), with rho in
N s^2/mm^4 (= tonne/mm^3 = 1e-12 x kg/m^3) and omega in rad/s:

    u(r) = rho w^2 r/(8E) [ (3+nu)(1-nu)(a^2+b^2) + (3+nu)(1+nu) a^2 b^2/r^2 - (1-nu^2) r^2 ]   annulus
    u(r) = rho w^2 r (1-nu)/(8E) [ (3+nu) b^2 - (1+nu) r^2 ]                                  solid disc
    sigma_t(r) = rho w^2/8 [ (3+nu)(a^2 + b^2 + a^2 b^2/r^2) - (1+3nu) r^2 ]                  annulus

Free thermal growth of a body at T, assembled at T0: u(r) = alpha (T - T0) r.

A fit between an inner part A (outer surface at r_f) and an outer part B (inner surface at r_f), nominal
diametral interference delta (> 0 interference), superposes linearly:

    delta_op = delta + 2 (uA_free(r_f) - uB_free(r_f))           free = thermal + centrifugal
    p        = delta_op / (2 (cB + cA))  if delta_op > 0 else 0  (the fit is lost: p = 0)
    cB = uB(r_f) under unit inner pressure,  cA = -uA(r_f) under unit outer pressure

which is research 1.1(b)'s compliance sum delta = p d [ (1/E_r)((1+k^2)/(1-k^2) + nu_r)
+ (1/E_s)((1+k0^2)/(1-k0^2) - nu_s) ] (k = d/Di, k0 = d0/d) for the shaft, and its analogue for the
housing. Each raceway then moves by its ring's free growth plus the growth the fit pressure causes (inner
raceway grows, outer raceway contracts), and per row

    Pd_op = Pd0 - dDi - dDe_contraction - 2 dDw,     dDw = alpha_b (T_b - T0) Dw.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
import warnings

from .. import validate
from ..validate import FieldError
from .geometry import Material

#: Lowest temperature a user may give, deg C (absolute zero).
ABSOLUTE_ZERO = -273.15

#: Default limit of the tensile hoop stress at a ring's bore from fit and speed, N/mm^2. Basis: NSK, Rolling
#: Bearings CAT. No. E1102e, sect. 9.2 (research 1.1(c)) keeps the maximum interference below about 7/10 000
#: of d; with NSK's Table 15.1 solid-shaft formula sigma_t,max = (E/2)(delta/d)(1 + k^2) (E = 208 000 N/mm^2)
#: that is 108 / 119 / 132 N/mm^2 at k = d/Di = 0.7 / 0.8 / 0.9, so 120 N/mm^2 at a typical k = 0.8. A maker's
#: explicit stress limit was searched for and not found; the value is derived, not quoted.
HOOP_STRESS_LIMIT = 120.0

ROTATING = ("inner", "outer")


# -- materials ------------------------------------------------------------------
@dataclass(frozen=True)
class BodyMaterial(Material):
    """The material of a mounted body (shaft, ring, ball, housing): a :class:`fastbearing.Material` (E in
    N/mm^2 > 0, nu in [0, 0.5), rho in kg/m^3 > 0, checked there) with its thermal expansion.

    Parameters
    ----------
    thermal_expansion : float
        alpha in 1/K, |alpha| < 1e-4 (steel 12.5e-6; a value such as 12.5 was typed in 1e-6/K).
    """

    thermal_expansion: float = 12.5e-6

    def __post_init__(self):
        object.__setattr__(self, "name", validate.text(self.name, "name"))
        super().__post_init__()
        object.__setattr__(self, "thermal_expansion", validate.number(
            self.thermal_expansion, "thermal_expansion", low=-1e-4, high=1e-4, low_open=True, high_open=True,
            units="1/K (steel: 12.5e-6)"))

    def as_dict(self) -> dict:
        """name, youngs_modulus (N/mm^2), poisson_ratio, density (kg/m^3), thermal_expansion (1/K)."""
        return {"name": self.name, "youngs_modulus": self.youngs_modulus, "poisson_ratio": self.poisson_ratio,
                "density": self.density, "thermal_expansion": self.thermal_expansion}


#: Through-hardened bearing steel (100Cr6 / AISI 52100), also the default shaft and housing steel:
#: E = 208 000 N/mm^2 and nu = 0.3 as NSK CAT. E1102e Table 15.1 and fastbearing.model.geometry.STEEL;
#: rho = 7850 kg/m^3 (geometry.STEEL); alpha = 12.5e-6 /K as NSK E1102e eq. (9.6) (NTN and IKO use the same).
STEEL = BodyMaterial("steel", 208000.0, 0.3, 7850.0, 12.5e-6)
#: Grey cast iron EN-GJL-250 (a usual housing iron): E = 110 000 N/mm^2, the middle of the 103-118 kN/mm^2
#: EN 1561 gives for this grade (informative annex, from memory of the standard: check before relying);
#: nu = 0.26 (same source); rho = 7200 kg/m^3 (EN 1561; makeitfrom.com grey iron 7.2 g/cm^3);
#: alpha = 11e-6 /K (makeitfrom.com, ISO 250 / EN-JL 1040 grey cast iron, 11 um/m-K).
CAST_IRON = BodyMaterial("cast_iron", 110000.0, 0.26, 7200.0, 11.0e-6)
#: Wrought aluminium alloy EN AW-6082 (a usual machined housing alloy): E = 70 000 N/mm^2, rho = 2700 kg/m^3,
#: alpha = 23.4e-6 /K (EN AW-6082 alloy data sheet, physical properties at about 20 deg C, after EN 573-3 /
#: EN 755-2); nu = 0.33 (matmatch.com, typical of wrought 6000-series alloys). Cast AlSi alloys expand less
#: (about 21e-6 /K): give a table for them.
ALUMINIUM = BodyMaterial("aluminium", 70000.0, 0.33, 2700.0, 23.4e-6)
#: Named materials accepted by ``shaft_material = "..."`` and ``housing_material = "..."``.
BODY_MATERIALS = {"steel": STEEL, "cast_iron": CAST_IRON, "aluminium": ALUMINIUM}
_MATERIAL_KEYS = ("youngs_modulus", "poisson_ratio", "density", "thermal_expansion")


def body_material(value, field_name: str) -> BodyMaterial:
    """A :class:`BodyMaterial` from a name in BODY_MATERIALS, a table with youngs_modulus (N/mm^2),
    poisson_ratio, density (kg/m^3) and thermal_expansion (1/K) (and an optional name), or a BodyMaterial."""
    if isinstance(value, BodyMaterial):
        return value
    if isinstance(value, str):
        return BODY_MATERIALS[validate.choice(value, field_name, tuple(BODY_MATERIALS))]
    if isinstance(value, dict):
        validate.table(value, field_name, allowed=("name", *_MATERIAL_KEYS), required=_MATERIAL_KEYS)
        try:
            return BodyMaterial(value.get("name", "custom"), *(value[k] for k in _MATERIAL_KEYS))
        except FieldError as error:
            raise error.within(field_name) from None
    raise FieldError(field_name, f"must be one of {list(BODY_MATERIALS)} or a table with keys "
                     f"{list(_MATERIAL_KEYS)}", value)


# -- plane-stress Lame annulus ---------------------------------------------------------
def _per_rpm(speed: float) -> float:
    """omega in rad/s from n in rpm."""
    return 2.0 * math.pi * speed / 60.0


def pressure_displacement(r: float, a: float, b: float | None, E: float, nu: float, *,
                          p_inner: float = 0.0, p_outer: float = 0.0) -> float:
    """Radial displacement u(r) in mm of a plane-stress annulus a <= r <= b (mm) under inner and outer
    pressure (N/mm^2, > 0 compressing the surface they act on); E in N/mm^2.

    a = 0 is a solid disc (then p_inner is ignored); b = None an infinitely thick body (then p_outer must be
    0). u > 0 outwards."""
    if b is None:
        if p_outer:
            raise ValueError("an infinitely thick body takes no outer pressure")
        return (1.0 + nu) * p_inner * a * a / (E * r)
    if a == 0.0:
        return -(1.0 - nu) * p_outer * r / E
    b2a2 = b * b - a * a
    return ((1.0 - nu) * (p_inner * a * a - p_outer * b * b) * r
            + (1.0 + nu) * a * a * b * b * (p_inner - p_outer) / r) / (E * b2a2)


def pressure_hoop_stress(r: float, a: float, b: float | None, *, p_inner: float = 0.0,
                         p_outer: float = 0.0) -> float:
    """Hoop stress sigma_t(r) in N/mm^2 (> 0 tension) of an annulus a <= r <= b (mm) under inner and outer
    pressure (N/mm^2); a = 0 solid disc, b = None infinitely thick (no outer pressure). Independent of E."""
    if b is None:
        return p_inner * a * a / (r * r)
    if a == 0.0:
        return -p_outer
    b2a2 = b * b - a * a
    return (p_inner * a * a - p_outer * b * b) / b2a2 + (p_inner - p_outer) * a * a * b * b / (b2a2 * r * r)


def centrifugal_displacement(r: float, a: float, b: float, material: BodyMaterial, speed: float) -> float:
    """Radial displacement u(r) in mm of an annulus a <= r <= b (mm; a = 0: a solid disc) spinning freely at
    ``speed`` rpm, plane stress (research 1.1(e)); rho from kg/m^3 to N s^2/mm^4 by 1e-12."""
    E, nu = material.youngs_modulus, material.poisson_ratio
    rw2 = 1e-12 * material.density * _per_rpm(speed) ** 2
    if a == 0.0:
        return rw2 * r * (1.0 - nu) / (8.0 * E) * ((3.0 + nu) * b * b - (1.0 + nu) * r * r)
    return rw2 * r / (8.0 * E) * ((3.0 + nu) * (1.0 - nu) * (a * a + b * b)
                                 + (3.0 + nu) * (1.0 + nu) * a * a * b * b / (r * r) - (1.0 - nu * nu) * r * r)


def centrifugal_hoop_stress(r: float, a: float, b: float, material: BodyMaterial, speed: float) -> float:
    """Hoop stress sigma_t(r) in N/mm^2 of an annulus a <= r <= b (mm; a = 0 solid disc) spinning at
    ``speed`` rpm (Timoshenko & Goodier sect. 32): rho w^2/8 [(3+nu)(a^2 + b^2 + a^2 b^2/r^2) - (1+3nu) r^2]."""
    nu = material.poisson_ratio
    rw2 = 1e-12 * material.density * _per_rpm(speed) ** 2
    inner = a * a * b * b / (r * r) if a > 0.0 else 0.0
    return rw2 / 8.0 * ((3.0 + nu) * (a * a + b * b + inner) - (1.0 + 3.0 * nu) * r * r)


def thermal_displacement(r: float, material: BodyMaterial, temperature_rise: float) -> float:
    """Free thermal radial growth alpha dT r in mm (r in mm, dT in K from the assembly temperature)."""
    return material.thermal_expansion * temperature_rise * r


def ball_spin_growth(ball_diameter: float, pitch_diameter: float, material: BodyMaterial, speed: float,
                     contact_angle: float = 0.0) -> float:
    """An upper estimate in mm of a ball's diametral centrifugal growth, neglected in the clearance budget.

    The ball spins about its own axis at w_B = (dm/(2 Dw)) (1 - gamma^2) w (gamma = Dw cos(a)/dm, inner ring
    at ``speed`` rpm, outer ring still; Harris & Kotzalas, Rolling Bearing Analysis, ch. 7, pure rolling).
    Its equator then grows by at most the plane-stress solid disc's rim value 2 u(R) = rho w_B^2 R^3
    (1-nu)/(2E) (plane stress over-estimates a sphere). For a 6205 (Dw 7.94, dm 39.04 mm) at 30 000 rpm this
    is about 0.05 um, 2.5 % of the inner raceway's 1.98 um centrifugal growth and far below clearance
    tolerances. ``contact_angle`` in degrees."""
    gamma = ball_diameter * math.cos(math.radians(contact_angle)) / pitch_diameter
    spin = pitch_diameter / (2.0 * ball_diameter) * (1.0 - gamma * gamma) * speed
    R = 0.5 * ball_diameter
    return 2.0 * centrifugal_displacement(R, 0.0, R, material, spin)


# -- bodies and fits ----------------------------------------------------------------
@dataclass(frozen=True)
class _Body:
    """An annulus inner_radius..outer_radius (mm; outer None: infinitely thick) of one material at a temperature
    rise (K) from assembly, spinning at ``speed`` rpm."""

    inner_radius: float
    outer_radius: float | None
    material: BodyMaterial
    temperature_rise: float
    speed: float

    def free(self, r: float) -> float:
        """Free radial growth in mm at r: thermal + centrifugal."""
        return self.thermal(r) + self.centrifugal(r)

    def thermal(self, r: float) -> float:
        return thermal_displacement(r, self.material, self.temperature_rise)

    def centrifugal(self, r: float) -> float:
        if self.speed == 0.0:
            return 0.0
        return centrifugal_displacement(r, self.inner_radius, self.outer_radius, self.material, self.speed)

    def spin_hoop(self, r: float) -> float:
        if self.speed == 0.0:
            return 0.0
        return centrifugal_hoop_stress(r, self.inner_radius, self.outer_radius, self.material, self.speed)

    def pressed(self, r: float, *, p_inner: float = 0.0, p_outer: float = 0.0) -> float:
        """u(r) in mm from surface pressures in N/mm^2."""
        m = self.material
        return pressure_displacement(r, self.inner_radius, self.outer_radius, m.youngs_modulus, m.poisson_ratio,
                                     p_inner=p_inner, p_outer=p_outer)


@dataclass(frozen=True)
class Fit:
    """One interface: diametral interferences in mm (> 0 interference), pressures in N/mm^2.

    nominal_interference : as made, at the assembly temperature, standing still.
    operating_interference : the nominal one plus twice the free (thermal + centrifugal) radial growth of the
        inner part's mating surface minus the outer part's.
    pressure, mounted_pressure : the fit pressure running and as mounted (0 when the fit is lost).
    lost : operating_interference <= 0.
    loss_speed : rpm at which the operating interference reaches 0 with the temperatures held; None when it is
        already <= 0 standing still (or a spinning infinitely thick housing makes it unknowable), math.inf when
        speed does not loosen this fit (neither part spins, or the inner part grows faster).
    loss_temperature_rise : K by which the outer part (ring for the shaft fit, housing for the housing fit)
        may warm further, the rest held, before the fit is lost; None when lost already or alpha <= 0.
    compliance : (cA + cB), mm of radial interference per N/mm^2 of pressure.
    """

    nominal_interference: float
    operating_interference: float
    pressure: float
    mounted_pressure: float
    lost: bool
    loss_speed: float | None
    loss_temperature_rise: float | None
    compliance: float


def _fit(inner: _Body, outer: _Body, radius: float, nominal: float, loss_per_rpm2: float | None) -> Fit:
    """Solve one interface at ``radius`` (mm) between the inner part and the outer part; ``loss_per_rpm2`` is
    the diametral interference (mm) speed takes per rpm^2 (None: not computable)."""
    compliance = outer.pressed(radius, p_inner=1.0) - inner.pressed(radius, p_outer=1.0)  # both terms > 0
    thermal = nominal + 2.0 * (inner.thermal(radius) - outer.thermal(radius))
    spin = 2.0 * (inner.centrifugal(radius) - outer.centrifugal(radius))  # ~ n^2; < 0 loosens
    operating = thermal + spin
    pressure = operating / (2.0 * compliance) if operating > 0.0 else 0.0
    mounted = nominal / (2.0 * compliance) if nominal > 0.0 else 0.0
    if thermal <= 0.0 or loss_per_rpm2 is None:
        loss_speed = None
    else:  # thermal - loss_per_rpm2 n^2 = 0
        loss_speed = math.sqrt(thermal / loss_per_rpm2) if loss_per_rpm2 > 0.0 else math.inf
    alpha = outer.material.thermal_expansion
    rise = operating / (2.0 * alpha * radius) if operating > 0.0 and alpha > 0.0 else None
    return Fit(nominal, operating, pressure, mounted, operating <= 0.0, loss_speed, rise, compliance)


def _loss_per_rpm2(inner: _Body, outer: _Body, radius: float) -> float | None:
    """Diametral interference in mm lost per rpm^2, from the two bodies with their rotating ones at 1 rpm
    (None: an infinitely thick body would spin)."""
    if any(body.speed > 0.0 and body.outer_radius is None for body in (inner, outer)):
        return None
    return -2.0 * (inner.centrifugal(radius) - outer.centrifugal(radius))


# -- a mounted row ------------------------------------------------------------------
@dataclass(frozen=True)
class MountedRow:
    """The clearance budget of one row as mounted and running. Lengths in mm (diametral), pressures and
    stresses in N/mm^2 (hoop stresses > 0 tension), speeds in rpm, temperature rises in K.

    unmounted_diametral_clearance : Pd0, as made.
    mounted_diametral_clearance : after the fits, at the assembly temperature, standing still.
    operating_diametral_clearance : Pd0 - inner_raceway_growth - outer_raceway_contraction
        - inner_raceway_free_growth - outer_raceway_free_contraction - 2 ball_growth.
    shaft_interference, housing_interference : operating diametral interferences (<= 0: lost).
    shaft_fit_pressure, housing_fit_pressure : operating fit pressures.
    inner_raceway_growth, outer_raceway_contraction : the fits' share of the raceway diameter changes, running.
    inner_raceway_free_growth, outer_raceway_free_contraction : the rings' own thermal and centrifugal share
        (a warmer outer ring gives a negative contraction).
    ball_growth : a ball's diametral thermal growth alpha_b (T_b - T0) Dw (centrifugal growth neglected,
        see :func:`ball_spin_growth`).
    inner_ring_hoop_stress, outer_ring_hoop_stress : at each ring's bore (inner ring at d, outer ring at its
        raceway De, where fit stresses peak), fit + spin, running; mounted_* the same as mounted.
    shaft_fit, housing_fit : the :class:`Fit` of each interface.
    materials : the BodyMaterial of each body: shaft, inner_ring, outer_ring, balls, housing.
    notes : one line each: fits lost and the speed or temperature at which they are lost, stress warnings.
    """

    unmounted_diametral_clearance: float
    mounted_diametral_clearance: float
    operating_diametral_clearance: float
    shaft_interference: float
    housing_interference: float
    shaft_fit_pressure: float
    housing_fit_pressure: float
    inner_raceway_growth: float
    outer_raceway_contraction: float
    inner_raceway_free_growth: float
    outer_raceway_free_contraction: float
    ball_growth: float
    inner_ring_hoop_stress: float
    outer_ring_hoop_stress: float
    mounted_inner_ring_hoop_stress: float
    mounted_outer_ring_hoop_stress: float
    shaft_fit: Fit
    housing_fit: Fit
    materials: dict = field(default_factory=dict)
    notes: tuple[str, ...] = field(default=())

    @property
    def clearance_reductions(self) -> dict[str, float]:
        """Each reduction of the diametral clearance, mm, summing to unmounted - operating."""
        return {"inner_raceway_growth": self.inner_raceway_growth,
                "outer_raceway_contraction": self.outer_raceway_contraction,
                "inner_raceway_free_growth": self.inner_raceway_free_growth,
                "outer_raceway_free_contraction": self.outer_raceway_free_contraction,
                "ball_growth": 2.0 * self.ball_growth}

    def as_dict(self) -> dict:
        """The report's keys (issue 44 item 4), mm and N/mm^2."""
        keys = ("unmounted_diametral_clearance", "mounted_diametral_clearance", "operating_diametral_clearance",
                "shaft_interference", "housing_interference", "shaft_fit_pressure", "housing_fit_pressure",
                "inner_raceway_growth", "outer_raceway_contraction", "inner_raceway_free_growth",
                "outer_raceway_free_contraction", "ball_growth", "inner_ring_hoop_stress", "outer_ring_hoop_stress",
                "mounted_inner_ring_hoop_stress", "mounted_outer_ring_hoop_stress")
        out = {k: getattr(self, k) for k in keys}
        out["materials"] = {body: material.as_dict() for body, material in self.materials.items()}
        out["notes"] = list(self.notes)
        return out


def _temperature(value, field_name: str, default: float) -> float:
    if value is None:
        return default
    return validate.number(value, field_name, low=ABSOLUTE_ZERO, units="deg C")


def _length(value, field_name: str, *, low=0.0, low_open=True) -> float:
    return validate.number(value, field_name, low=low, low_open=low_open, units="mm")


def mount_row(*, bore, outer_diameter, pitch_diameter, element_diameter, unmounted_diametral_clearance=0.0,
              shaft_interference=0.0, housing_interference=0.0, shaft_bore=0.0, housing_outer_diameter=None,
              shaft_material="steel", housing_material="steel", inner_ring_material=STEEL,
              outer_ring_material=STEEL, ball_material=STEEL, assembly_temperature=20.0,
              inner_ring_temperature=None, outer_ring_temperature=None, ball_temperature=None,
              shaft_temperature=None, housing_temperature=None, speed=0.0, rotating="inner",
              inner_raceway_diameter=None, outer_raceway_diameter=None,
              hoop_stress_limit=HOOP_STRESS_LIMIT, warn=True) -> MountedRow:
    """The operating clearance of one row from its fits, temperatures and speed.

    Parameters (lengths in mm, diametral; temperatures in deg C; speed in rpm)
    ----------
    bore, outer_diameter : d and D, the ring's boundary dimensions.
    pitch_diameter, element_diameter : dm and Dw; the raceways are Di = dm - Dw, De = dm + Dw unless
        ``inner_raceway_diameter`` / ``outer_raceway_diameter`` are given (rollers: Dw the roller diameter
        at its mid-length, dm the pitch diameter there).
    unmounted_diametral_clearance : Pd0 (negative: a preload as made).
    shaft_interference, housing_interference : nominal diametral interference, > 0 tight, < 0 loose.
    shaft_bore : d0, 0 for a solid shaft, < d.
    housing_outer_diameter : Dh > D, or None for an infinitely thick housing.
    shaft_material, housing_material : "steel", "cast_iron", "aluminium", a table or a BodyMaterial.
    inner_ring_material, outer_ring_material, ball_material : BodyMaterial or name (steel by default).
    assembly_temperature : T0, default 20.
    inner_ring_temperature, outer_ring_temperature : default T0.
    ball_temperature, shaft_temperature : default the inner ring's.
    housing_temperature : default the outer ring's.
    speed : n >= 0 of the rotating ring; ``rotating`` "inner" (shaft and inner ring turn) or "outer" (outer
        ring and housing turn, shaft stands: needs a finite housing).
    hoop_stress_limit : N/mm^2; a tensile ring hoop stress beyond it gives a note and (``warn``) a
        UserWarning naming the stress.
    """
    d = _length(bore, "bore")
    D = _length(outer_diameter, "outer_diameter")
    dm = _length(pitch_diameter, "pitch_diameter")
    Dw = _length(element_diameter, "element_diameter")
    Di = dm - Dw if inner_raceway_diameter is None else _length(inner_raceway_diameter, "inner_raceway_diameter")
    De = dm + Dw if outer_raceway_diameter is None else _length(outer_raceway_diameter, "outer_raceway_diameter")
    if not d < Di:
        raise FieldError("bore", f"must be < the inner raceway diameter Di = {Di:g} mm", d)
    if not De < D:
        raise FieldError("outer_diameter", f"must be > the outer raceway diameter De = {De:g} mm", D)
    if not Di < De:
        raise FieldError("inner_raceway_diameter", f"must be < the outer raceway diameter {De:g} mm", Di)
    d0 = validate.number(shaft_bore, "shaft_bore", low=0.0, units="mm")
    if not d0 < d:
        raise FieldError("shaft_bore", f"must be < the bore d = {d:g} mm (0 for a solid shaft)", d0)
    if housing_outer_diameter is None:
        Dh = None
    else:
        Dh = validate.number(housing_outer_diameter, "housing_outer_diameter", units="mm")
        if not Dh > D:
            raise FieldError("housing_outer_diameter", f"must be > the ring's outer diameter D = {D:g} mm "
                             "(omit it for an infinitely thick housing)", Dh)
    Pd0 = validate.number(unmounted_diametral_clearance, "unmounted_diametral_clearance", units="mm")
    delta_s = validate.number(shaft_interference, "shaft_interference", units="mm")
    delta_h = validate.number(housing_interference, "housing_interference", units="mm")
    m_shaft = body_material(shaft_material, "shaft_material")
    m_housing = body_material(housing_material, "housing_material")
    m_ir = body_material(inner_ring_material, "inner_ring_material")
    m_or = body_material(outer_ring_material, "outer_ring_material")
    m_ball = body_material(ball_material, "ball_material")
    T0 = validate.number(assembly_temperature, "assembly_temperature", low=ABSOLUTE_ZERO, units="deg C")
    Ti = _temperature(inner_ring_temperature, "inner_ring_temperature", T0)
    To = _temperature(outer_ring_temperature, "outer_ring_temperature", T0)
    Tb = _temperature(ball_temperature, "ball_temperature", Ti)
    Ts = _temperature(shaft_temperature, "shaft_temperature", Ti)
    Th = _temperature(housing_temperature, "housing_temperature", To)
    n = validate.number(speed, "speed", low=0.0, units="rpm")
    validate.choice(rotating, "rotating", ROTATING)
    if rotating == "outer" and n > 0.0 and Dh is None:
        raise FieldError("housing_outer_diameter", "must be given when the outer ring rotates (an infinitely "
                         "thick housing cannot spin)", None)
    limit = validate.number(hoop_stress_limit, "hoop_stress_limit", low=0.0, low_open=True, units="N/mm^2")

    def bodies(speed):
        n_in, n_out = (speed, 0.0) if rotating == "inner" else (0.0, speed)
        return (_Body(0.5 * d0, 0.5 * d, m_shaft, Ts - T0, n_in), _Body(0.5 * d, 0.5 * Di, m_ir, Ti - T0, n_in),
                _Body(0.5 * De, 0.5 * D, m_or, To - T0, n_out),
                _Body(0.5 * D, None if Dh is None else 0.5 * Dh, m_housing, Th - T0, n_out))

    shaft, ring_i, ring_o, housing = bodies(n)
    unit = bodies(1.0)  # the loss speed: centrifugal growth scales with n^2
    fs = _fit(shaft, ring_i, 0.5 * d, delta_s, _loss_per_rpm2(unit[0], unit[1], 0.5 * d))
    fh = _fit(ring_o, housing, 0.5 * D, delta_h, _loss_per_rpm2(unit[2], unit[3], 0.5 * D))

    ri, ro = 0.5 * Di, 0.5 * De
    grow_i = 2.0 * ring_i.pressed(ri, p_inner=fs.pressure)
    shrink_o = 0.0 - 2.0 * ring_o.pressed(ro, p_outer=fh.pressure)  # 0.0 -: no -0.0 in a report
    free_i = 2.0 * ring_i.free(ri)
    free_o = 0.0 - 2.0 * ring_o.free(ro)
    ball = m_ball.thermal_expansion * (Tb - T0) * Dw
    operating = Pd0 - grow_i - shrink_o - free_i - free_o - 2.0 * ball
    mounted = (Pd0 - 2.0 * ring_i.pressed(ri, p_inner=fs.mounted_pressure)
               + 2.0 * ring_o.pressed(ro, p_outer=fh.mounted_pressure))

    hoop = _hoops(ring_i, ring_o, fs, fh)
    notes = _notes(fs, fh, hoop, limit, warn)
    return MountedRow(Pd0, mounted, operating, fs.operating_interference, fh.operating_interference, fs.pressure,
                      fh.pressure, grow_i, shrink_o, free_i, free_o, ball, hoop["inner ring"], hoop["outer ring"],
                      hoop["mounted inner ring"], hoop["mounted outer ring"], fs, fh,
                      {"shaft": m_shaft, "inner_ring": m_ir, "outer_ring": m_or, "balls": m_ball,
                       "housing": m_housing}, tuple(notes))


def _hoops(ring_i: _Body, ring_o: _Body, fs: Fit, fh: Fit) -> dict[str, float]:
    """Hoop stresses in N/mm^2 at the inner ring's bore and the outer ring's raceway (its bore)."""
    a_i, b_i = ring_i.inner_radius, ring_i.outer_radius
    a_o, b_o = ring_o.inner_radius, ring_o.outer_radius
    return {"inner ring": pressure_hoop_stress(a_i, a_i, b_i, p_inner=fs.pressure) + ring_i.spin_hoop(a_i),
            "outer ring": pressure_hoop_stress(a_o, a_o, b_o, p_outer=fh.pressure) + ring_o.spin_hoop(a_o),
            "mounted inner ring": pressure_hoop_stress(a_i, a_i, b_i, p_inner=fs.mounted_pressure),
            "mounted outer ring": pressure_hoop_stress(a_o, a_o, b_o, p_outer=fh.mounted_pressure)}


def _notes(fs: Fit, fh: Fit, hoop: dict, limit: float, warn: bool) -> list[str]:
    notes = []
    for name, fit, part in (("shaft", fs, "inner ring"), ("housing", fh, "housing")):
        if fit.nominal_interference <= 0.0 and fit.operating_interference <= 0.0:
            continue  # a loose fit by design
        if fit.lost:
            notes.append(f"the {name} fit is lost: operating interference {fit.operating_interference * 1e3:.3g} um")
            continue
        if fit.loss_speed is not None and math.isfinite(fit.loss_speed):
            notes.append(f"the {name} fit is lost above {fit.loss_speed:,.0f} rpm".replace(",", " "))
        if fit.loss_temperature_rise is not None:
            notes.append(f"the {name} fit is lost if the {part} warms by a further "
                         f"{fit.loss_temperature_rise:.3g} K")
    for ring in ("inner ring", "outer ring"):  # tension cracks a hardened ring; the larger state is named
        state, stress = max((("as mounted", hoop[f"mounted {ring}"]), ("running", hoop[ring])), key=lambda x: x[1])
        if stress > limit:
            text = (f"the {ring} hoop stress {stress:.4g} N/mm^2 ({state}) exceeds the limit "
                    f"{limit:g} N/mm^2 (ring cracking risk)")
            notes.append("warning: " + text)
            if warn:
                warnings.warn(text, UserWarning, stacklevel=3)
    return notes


# -- axial effects of pairs and sets ---------------------------------------------------------
#: Contact direction s_r of each row of a pair (row 1 at z = -e, row 2 at z = +e; docs/model.md).
PAIR_DIRECTIONS = {"DB": (1, -1), "DF": (-1, 1), "DT": (1, 1)}


def axial_preload_changes(axial_offsets, contact_directions, *, inner_side_strain: float,
                          outer_side_strain: float) -> tuple[float, ...]:
    """The change of each row's axial preload offset d0 (mm, > 0 more preload) from the axial growth of the
    inner side (shaft, inner rings, spacers) and the outer side (housing, outer rings, spacers).

    ``axial_offsets``: z_r in mm, each row's ball-centre position (fastbearing's Row.axial_offset);
    ``contact_directions``: s_r = +1/-1 as the rows of fastbearing.Bearing; strains eps = alpha (T - T0)
    (dimensionless) of each side.

    Derivation: the engine's axial approach uz is measured between the inner and outer groove-curvature
    centres (docs/model.md, Eq. 7b: uz = dz + s_r (A0 sin a0 + d0)), which lie on the contact line within
    (f - 0.5) Dw of the ball centre, so the lever is the ball-centre position z_r (the contact points, Dw
    sin(a0)/2 away, and the pressure centres on the axis are not: the ball sits between the groove centres).
    The inner side moves the inner groove centre by eps_i z_r, the outer side the outer one by eps_o z_r; an
    inner-ring axial displacement w adds w to uz, i.e. s_r w to d0. So d0 changes by
    s_r (eps_i - eps_o)(z_r - z_mean): a common shift is the shaft's rigid axial displacement, which the solver
    finds (z_mean removes it). Neglected: (eps_i + eps_o)/2 A0 sin(a0), the groove geometry's own scaling
    (with the balls' growth, the clearance model's part). For a DB pair (s = +1, -1 at z = -e, +e) each row's
    d0 falls by (eps_i - eps_o) e; DF rises by as much; a tandem pair shifts load from one row to the other
    and keeps its sum."""
    z = [validate.number(v, f"axial_offsets[{i}]", units="mm") for i, v in enumerate(axial_offsets)]
    s = [validate.integer(v, f"contact_directions[{i}]", low=-1, high=1) for i, v in enumerate(contact_directions)]
    for i, sr in enumerate(s):
        if sr == 0:
            raise FieldError(f"contact_directions[{i}]", "must be +1 or -1", sr)
    if len(z) != len(s) or not z:
        raise FieldError("contact_directions", f"must give one direction per row ({len(z)} rows)", len(s))
    eps = validate.number(inner_side_strain, "inner_side_strain") - validate.number(outer_side_strain,
                                                                                      "outer_side_strain")
    z_mean = sum(z) / len(z)
    return tuple(sr * eps * (zr - z_mean) for zr, sr in zip(z, s))


def pair_axial_interference_change(arrangement: str, row_spacing: float, *, inner_side_strain: float,
                                   outer_side_strain: float) -> float:
    """The change in mm of a pair's axial interference (the sum of its rows' d0; > 0 more preload) from the
    inner side growing by eps_i = alpha_i (T_shaft - T0) and the outer side by eps_o = alpha_o
    (T_housing - T0) over the ball-centre spacing 2e (``row_spacing``, mm; see :func:`axial_preload_changes`
    for why not the pressure-centre spread): -(eps_i - eps_o) 2e for DB, +(eps_i - eps_o) 2e for DF, 0 for DT
    (a tandem pair shares its load differently instead: :func:`axial_preload_changes`)."""
    validate.choice(arrangement, "arrangement", tuple(PAIR_DIRECTIONS))
    L = validate.number(row_spacing, "row_spacing", low=0.0, units="mm")
    rows = axial_preload_changes((-0.5 * L, 0.5 * L), PAIR_DIRECTIONS[arrangement],
                                 inner_side_strain=inner_side_strain, outer_side_strain=outer_side_strain)
    return sum(rows)


def axial_equivalent_of_clearance_change(clearance_change: float, contact_angle: float) -> float:
    """The first-order axial preload change in mm of one angular contact row equivalent to a diametral
    clearance change dPd (mm, > 0 more clearance): -dPd / (2 tan a), a in degrees (> 0).

    From the loaded groove-centre distance A of docs/model.md Eq. 9, dA = cos(a) d(ur) + sin(a) d(uz): a
    radial approach dPd/2 equals an axial one dPd/(2 tan a); the same follows from differentiating the axial
    play Pe = 2 A0 sin(a_f), cos(a_f) = 1 - Pd/(2 A0) (Harris & Kotzalas, Rolling Bearing Analysis, ch. 2),
    dPe = dPd / tan(a_f) for both directions. For reporting only: the engine takes the operating clearance as
    rL = Pd_op/2 (negative: radial preload, allowed with d0) and the thermal axial change in d0, exactly."""
    a = validate.number(contact_angle, "contact_angle", low=0.0, high=90.0, low_open=True, high_open=True,
                        units="deg")
    return -validate.number(clearance_change, "clearance_change", units="mm") / (2.0 * math.tan(math.radians(a)))
