"""Bearings from catalogue geometry: Hertz point contacts and the model parameters.

Engineers know a bearing's dimensions, not its Hertz constant. This module
turns ball diameter D, pitch diameter dm, groove curvature ratios fi and fo,
contact angle a0, diametral clearance Pd, row spacing and the materials into
the model parameters of :class:`fastbearing.Row` (docs/model.md, "Hertz constant from geometry (for bearings
given by catalogue dimensions)"):

    A0 = (fi + fo - 1) * D                      groove-centre distance, mm
    R  = dm/2 + (fi - 0.5) * D * cos(a0)        inner groove-centre radius, mm
    rL = Pd / 2                                 radial clearance per ball, mm
    Kn = (Ki^(-2/3) + Ko^(-2/3))^(-3/2)         N/mm^1.5, inner and outer contacts in series

and reports, for a solved case, the Hertz contact (maximum pressure and
ellipse semi-axes) of every ball at both races. Plain Python and scipy; no
numba. Units: N, mm, rad; pressures and moduli in N/mm^2 (= MPa). The
``contact_angle`` a user types is in degrees, as everywhere in fastbearing.

Hertz theory (Harris & Kotzalas, *Rolling Bearing Analysis*, 5th ed., ch. 6;
Hamrock & Brewe, J. Lubr. Technol. 105 (1983) 171-177): two bodies touching
at a point with curvature sums 1/Rx and 1/Ry in the two principal planes
(convex positive), effective radius R' = 1/(1/Rx + 1/Ry), ratio
alpha_r = Ry/Rx >= 1, reduced modulus E' = 2/((1-nu1^2)/E1 + (1-nu2^2)/E2).
The ellipticity k = a/b solves (exactly)

    alpha_r = (k^2 * Ecal(m) - Kcal(m)) / (Kcal(m) - Ecal(m)),   m = 1 - 1/k^2

with Kcal, Ecal the complete elliptic integrals of the first and second kind
(scipy.special.ellipk/ellipe, parameter m). Then, for a normal load Q:

    a = (6 k^2 Ecal Q R' / (pi E'))^(1/3)          semi-major axis, mm
    b = (6 Ecal Q R' / (pi k E'))^(1/3)            semi-minor axis, mm
    delta = Kcal (9/(2 Ecal R') (Q/(pi k E'))^2)^(1/3)     approach, mm
    p_max = 3 Q / (2 pi a b)                       maximum pressure, N/mm^2
    Q = Kc delta^1.5,  Kc = pi k E' sqrt(2 Ecal R' / (9 Kcal^3))

The Hamrock-Brewe closed form replaces k, Kcal, Ecal by
k = 1.0339 alpha_r^0.6360, Ecal = 1.0003 + 0.5968/alpha_r,
Kcal = 1.5277 + 0.6023 ln(alpha_r). Against the exact route it is within
1 % (k, Kcal, Ecal, delta, a, b, p_max) for 3 <= alpha_r <= 25. Ball-race
contacts reach alpha_r of 30-35 at the inner race with fi = 0.52; there Kn and
p_max stay within 1 % but k is off by up to 1.9 % (shipped bearings), and the
error grows with closer conformity (alpha_r = 50: k 3 %, Kn 3 %).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..engine import schema

from .. import validate
from .ball_row import check_contact_angle_unit, unit_warning
from .bearing import PRELOAD_DEFLECTION_LIMIT, Bearing, _check_finite, free_contact_angle

ELLIPTICITY_METHODS = ("exact", "hamrock-brewe")
#: Race-control hypotheses of the high-speed model, and the ring that may turn.
RACE_CONTROLS = ("outer", "inner", "none")
ROTATING_RINGS = ("inner", "outer")
#: Default validity limit of the Hertz contact pressure, N/mm^2: the usual static limit of ball bearings
#: (ISO 76 bases C0 on 4200 N/mm^2 at the most loaded contact of radial ball bearings).
CONTACT_PRESSURE_LIMIT = 4200.0
#: Plausible ball diameters, mm: outside them a ball diameter was probably typed in another unit (metres,
#: inches, micrometres) and gets a UserWarning (the smallest catalogue balls are about 0.6 mm, the largest
#: slewing-ring balls about 200 mm).
BALL_DIAMETER_RANGE = (0.5, 300.0)
#: Units a length may have been typed in, with their size in mm.
_LENGTH_UNITS = (("metres", "m", 1000.0), ("inches", "in", 25.4), ("micrometres", "um", 1e-3))


def _probable_units(value: float, low: float, high: float) -> list[str]:
    """'metres (0.012 m = 12 mm)' ... for every unit that would put ``value`` in [low, high] mm."""
    return [f"{name} ({value:g} {short} = {value * mm:.4g} mm)" for name, short, mm in _LENGTH_UNITS
            if low <= value * mm <= high]


def check_ball_diameter_unit(ball_diameter: float) -> None:
    """Warn when a ball diameter (mm) lies outside BALL_DIAMETER_RANGE: probably metres, inches or
    micrometres."""
    low, high = BALL_DIAMETER_RANGE
    D = ball_diameter
    if low <= D <= high:
        return
    guesses = _probable_units(D, low, high)
    meant = f"probably {' or '.join(guesses)}; give it in mm" if guesses else "check its unit: it is in mm"
    unit_warning(f"ball_diameter = {D:g} mm is implausible for a bearing ball ({'below' if D < low else 'above'} "
                 f"{low if D < low else high:g} mm): {meant}")

#: Contact-direction coefficient c2 of the load-centre spread E = 2(e + c2 R tan a0)
#: (docs/model.md, "A bearing is a set of rows on one rigid inner ring")
_SPREAD_SIGN = {"DB": 1, "DF": -1, "DT": 0}


# -- materials ------------------------------------------------------------------
@dataclass(frozen=True)
class Material:
    """An elastic material of balls or rings.

    Parameters
    ----------
    name : str
    youngs_modulus : float
        E in N/mm^2 (MPa), > 0.
    poisson_ratio : float
        nu, in [0, 0.5).
    density : float
        rho in kg/m^3, > 0 (the balls' mass at speed: centrifugal force, gyroscopic moment).
    """

    name: str
    youngs_modulus: float
    poisson_ratio: float
    density: float = 7850.0

    def __post_init__(self):
        object.__setattr__(self, "youngs_modulus", validate.number(self.youngs_modulus, "youngs_modulus", low=0,
                                                                   low_open=True, units="N/mm^2"))
        object.__setattr__(self, "poisson_ratio", validate.number(self.poisson_ratio, "poisson_ratio", low=0, high=0.5,
                                                                  high_open=True))
        object.__setattr__(self, "density", validate.number(self.density, "density", low=0, low_open=True,
                                                            units="kg/m^3"))


#: Through-hardened bearing steel (AISI 52100 / 100Cr6): E = 208 000 N/mm^2, nu = 0.3, rho = 7850 kg/m^3
#: (Harris & Kotzalas use 2.075e5 N/mm^2; catalogues quote 200-210 GPa).
STEEL = Material("steel", 208000.0, 0.3, 7850.0)
#: Bearing-grade silicon nitride (Si3N4) balls of hybrid bearings: E = 310 000 N/mm^2, nu = 0.26,
#: rho = 3200 kg/m^3 (about 40 % of steel's: the point of hybrid spindle bearings).
SILICON_NITRIDE = Material("silicon-nitride", 310000.0, 0.26, 3200.0)
#: Named materials accepted by ``material = "..."`` in a bearing file (for the balls).
MATERIALS = {"steel": STEEL, "silicon-nitride": SILICON_NITRIDE}


def reduced_modulus(ball: Material, ring: Material) -> float:
    """E' = 2 / ((1 - nu_b^2)/E_b + (1 - nu_r^2)/E_r) in N/mm^2 (Hamrock's convention)."""
    return 2.0 / ((1.0 - ball.poisson_ratio ** 2) / ball.youngs_modulus
                  + (1.0 - ring.poisson_ratio ** 2) / ring.youngs_modulus)


# -- ellipticity -----------------------------------------------------------------
def _alpha_of_t(t: float) -> float:
    """Curvature ratio Ry/Rx of ellipticity k = exp(t) (exact Hertz relation)."""
    from scipy.special import ellipe, ellipkm1  # scipy loads only when a geometry is used (start-up time)

    p = math.exp(-2.0 * t)          # 1 - m = 1/k^2; ellipkm1 keeps K accurate as m -> 1
    K, E = float(ellipkm1(p)), float(ellipe(1.0 - p))
    return (E / p - K) / (K - E)


def ellipticity(ratio: float, method: str = "exact") -> tuple[float, float, float]:
    """Contact-ellipse ellipticity and complete elliptic integrals for a curvature ratio.

    Parameters
    ----------
    ratio : float
        alpha_r = Ry/Rx >= 1, the ratio of the effective radii of curvature
        in the two principal planes (the larger over the smaller).
    method : {"exact", "hamrock-brewe"}
        "exact" solves alpha_r = (k^2 Ecal - Kcal)/(Kcal - Ecal) for k with a
        1-D root solve (Brent) on ln k; "hamrock-brewe" uses the closed-form fits.

    Returns
    -------
    k : float
        a/b >= 1, semi-major over semi-minor axis.
    Kcal, Ecal : float
        Complete elliptic integrals of the first and second kind at m = 1 - 1/k^2.
    """
    ratio = float(ratio)
    if not (math.isfinite(ratio) and ratio >= 1.0):
        raise ValueError(f"curvature ratio Ry/Rx must be a finite number >= 1, got {ratio!r}")
    if method == "hamrock-brewe":
        return 1.0339 * ratio ** 0.6360, 1.5277 + 0.6023 * math.log(ratio), 1.0003 + 0.5968 / ratio
    if method != "exact":
        raise ValueError(f"ellipticity method must be one of {list(ELLIPTICITY_METHODS)}, got {method!r}")
    from scipy.optimize import brentq  # scipy loads only when a geometry is used (start-up time)
    from scipy.special import ellipe, ellipk, ellipkm1

    excess = ratio - 1.0
    if excess < 1e-6:
        # near a circle alpha_r - 1 = 1.5 ln k + O(ln^2 k): k = alpha_r^(2/3) to ~1e-12
        k = ratio ** (2.0 / 3.0)
        m = 1.0 - 1.0 / k ** 2
        return k, float(ellipk(m)), float(ellipe(m))
    # alpha_r(t) rises from 1 (slope 1.5 at t = 0); it exceeds ratio by t = ln(ratio) + 1
    t_lo = excess / 3.0 if excess < 1e-3 else 1e-4
    t_hi = math.log(ratio) + 1.0
    t = brentq(lambda s: _alpha_of_t(s) - ratio, t_lo, t_hi, xtol=1e-15, rtol=4 * np.finfo(float).eps, maxiter=200)
    p = math.exp(-2.0 * t)
    return math.exp(t), float(ellipkm1(p)), float(ellipe(1.0 - p))


# -- one contact -----------------------------------------------------------------
@dataclass(frozen=True)
class HertzContact:
    """A Hertzian point contact: curvature, ellipticity and elastic constants.

    Build with :func:`hertz_contact` or :func:`race_contacts`. Loads Q in N;
    lengths in mm; pressures in N/mm^2. Methods accept scalars or arrays.

    Attributes
    ----------
    curvature_x, curvature_y : float
        1/Rx and 1/Ry, curvature sums of the two bodies in the two principal
        planes, 1/mm (x: rolling direction; y: across the groove).
    reduced_modulus : float
        E' = 2/((1-nu1^2)/E1 + (1-nu2^2)/E2), N/mm^2.
    ellipticity : float
        k = a/b >= 1.
    ellint_first, ellint_second : float
        Complete elliptic integrals Kcal and Ecal of the contact.
    method : str
        "exact" or "hamrock-brewe".
    """

    curvature_x: float
    curvature_y: float
    reduced_modulus: float
    ellipticity: float
    ellint_first: float
    ellint_second: float
    method: str = "exact"

    @property
    def curvature_sum(self) -> float:
        """Sum of curvatures 1/R' = 1/Rx + 1/Ry in 1/mm (Harris: sum rho)."""
        return self.curvature_x + self.curvature_y

    @property
    def curvature_difference(self) -> float:
        """F(rho) = |1/Rx - 1/Ry| / (1/Rx + 1/Ry), dimensionless (Harris)."""
        return abs(self.curvature_x - self.curvature_y) / self.curvature_sum

    @property
    def effective_radius(self) -> float:
        """R' = 1/(1/Rx + 1/Ry) in mm."""
        return 1.0 / self.curvature_sum

    @property
    def constant(self) -> float:
        """Kc of Q = Kc * delta^1.5, N/mm^1.5: pi k E' sqrt(2 Ecal R' / (9 Kcal^3))."""
        k, K, E = self.ellipticity, self.ellint_first, self.ellint_second
        return math.pi * k * self.reduced_modulus * math.sqrt(2.0 * E * self.effective_radius / (9.0 * K ** 3))

    def deflection(self, load):
        """Elastic approach delta in mm under normal load Q in N (>= 0)."""
        return (np.maximum(load, 0.0) / self.constant) ** (2.0 / 3.0)

    def semi_axes(self, load):
        """Contact-ellipse semi-axes (a, b) in mm under Q in N; a >= b (a across the groove for a ball race)."""
        k, E = self.ellipticity, self.ellint_second
        base = 6.0 * E * np.maximum(load, 0.0) * self.effective_radius / (math.pi * self.reduced_modulus)
        return np.cbrt(base * k ** 2), np.cbrt(base / k)

    def max_pressure(self, load):
        """Maximum Hertz contact pressure p_max = 3Q/(2 pi a b) in N/mm^2 under Q in N (0 where Q = 0)."""
        q = np.maximum(load, 0.0)
        a, b = self.semi_axes(q)
        with np.errstate(invalid="ignore", divide="ignore"):
            p = np.where(q > 0, 1.5 * q / (math.pi * a * b), 0.0)
        return p if np.ndim(p) else float(p)


def hertz_contact(curvature_x: float, curvature_y: float, reduced_modulus: float,
                  method: str = "exact") -> HertzContact:
    """Hertz point contact from the curvature sums in the two principal planes.

    Parameters
    ----------
    curvature_x, curvature_y : float
        1/Rx and 1/Ry in 1/mm: in each principal plane the sum of the two
        bodies' curvatures, convex positive, concave negative (a groove of
        radius r contributes -1/r). Both sums must be > 0.
    reduced_modulus : float
        E' in N/mm^2 (see :func:`reduced_modulus`).
    method : {"exact", "hamrock-brewe"}
        Route to the ellipticity and elliptic integrals (:func:`ellipticity`).

    Returns
    -------
    HertzContact
    """
    cx = _check_finite("curvature_x", curvature_x)
    cy = _check_finite("curvature_y", curvature_y)
    Ep = _check_finite("reduced_modulus", reduced_modulus)
    if cx <= 0 or cy <= 0:
        raise ValueError(f"curvature sums must be > 0 1/mm in both planes (non-conforming contact), "
                         f"got 1/Rx={cx!r}, 1/Ry={cy!r}")
    if Ep <= 0:
        raise ValueError(f"reduced_modulus must be > 0 N/mm^2, got {reduced_modulus!r}")
    k, K, E = ellipticity(max(cx, cy) / min(cx, cy), method)
    return HertzContact(cx, cy, Ep, k, K, E, method)


def race_contacts(ball_diameter: float, pitch_diameter: float, inner_groove_ratio: float,
                  outer_groove_ratio: float, contact_angle: float, reduced_modulus: float,
                  method: str = "exact") -> tuple[HertzContact, HertzContact]:
    """The ball's contacts with the inner and outer race (Harris & Kotzalas, ch. 2 and 6).

    With gamma = D cos(a)/dm, in the rolling plane (x) the ball (2/D) meets
    the inner race (convex, 2 gamma/(D (1 - gamma))) and the outer race
    (concave, -2 gamma/(D (1 + gamma))); across the groove (y) the ball meets
    the groove (concave, -1/(f D)):

        inner: 1/Rx = 2/(D (1 - gamma)),  1/Ry = (2 fi - 1)/(fi D)
        outer: 1/Rx = 2/(D (1 + gamma)),  1/Ry = (2 fo - 1)/(fo D)

    Parameters
    ----------
    ball_diameter, pitch_diameter : float
        D and dm in mm.
    inner_groove_ratio, outer_groove_ratio : float
        fi, fo: groove radius over D, > 0.5.
    contact_angle : float
        a in **rad** (the unloaded a0 for Kn, a ball's loaded angle for its stress).
    reduced_modulus : float
        E' in N/mm^2.
    method : {"exact", "hamrock-brewe"}

    Returns
    -------
    inner, outer : HertzContact
    """
    D, dm = float(ball_diameter), float(pitch_diameter)
    gamma = D * math.cos(contact_angle) / dm
    fi, fo = float(inner_groove_ratio), float(outer_groove_ratio)
    inner = hertz_contact(2.0 / (D * (1.0 - gamma)), (2.0 * fi - 1.0) / (fi * D), reduced_modulus, method)
    outer = hertz_contact(2.0 / (D * (1.0 + gamma)), (2.0 * fo - 1.0) / (fo * D), reduced_modulus, method)
    return inner, outer


def series_constant(inner: float, outer: float) -> float:
    """Kn of two contacts in series, N/mm^1.5: (Ki^(-2/3) + Ko^(-2/3))^(-3/2) (deflections add)."""
    return (inner ** (-2.0 / 3.0) + outer ** (-2.0 / 3.0)) ** -1.5


#: The race-control factors (lambda_i, lambda_o) that share the gyroscopic moment's friction between the
#: races (Harris): outer-raceway control puts it all on the outer race, inner control shares it, none drops it.
RACE_CONTROL_FACTORS = {"outer": (0.0, 2.0), "inner": (1.0, 1.0), "none": (0.0, 0.0)}


# -- a bearing's geometry ------------------------------------------------------------
def check_boundary_dimensions(body, element_diameter: float) -> None:
    """Validate ``body``'s optional boundary dimensions (ISO 15 / ISO 355: ``bore`` d, ``outer_diameter`` D,
    ``width`` B, all mm) in place against its rolling elements: d < dm - Dw (the inner raceway Di) and
    D > dm + Dw (the outer raceway De), so that each ring has a section; width > 0. Needed for fits
    (issue 44, docs/geometry.md); absent (None) they change nothing."""
    v = validate
    dm = body.pitch_diameter
    for name in ("bore", "outer_diameter", "width"):
        if getattr(body, name) is not None:
            object.__setattr__(body, name, v.number(getattr(body, name), name, low=0, low_open=True, units="mm"))
    if body.bore is not None and not body.bore < dm - element_diameter:
        raise v.FieldError("bore", f"must be < the inner raceway diameter pitch_diameter - {ELEMENT_WORD[body.element]}"
                           f" = {dm - element_diameter:.6g} mm (the inner ring needs a section)", body.bore)
    if body.outer_diameter is not None and not body.outer_diameter > dm + element_diameter:
        raise v.FieldError("outer_diameter", f"must be > the outer raceway diameter pitch_diameter + "
                           f"{ELEMENT_WORD[body.element]} = {dm + element_diameter:.6g} mm (the outer ring needs a "
                           "section)", body.outer_diameter)


#: The element diameter's key in each geometry, for the boundary dimensions' messages.
ELEMENT_WORD = {"ball": "ball_diameter", "cylindrical_roller": "roller_diameter", "tapered_roller": "roller_diameter"}


@dataclass(frozen=True)
class Geometry:
    """Catalogue geometry and materials of the rows of a ball bearing (all rows alike).

    Parameters
    ----------
    n_balls : int
        Z, balls per row, >= 1 and few enough not to overlap on the pitch circle.
    ball_diameter : float
        D, mm, > 0. Outside 0.5-300 mm (BALL_DIAMETER_RANGE) a UserWarning says which unit it looks like
        (metres, inches, micrometres).
    pitch_diameter : float
        dm, diameter of the ball-centre circle, mm, > D (an error otherwise, which says when dm looks like
        metres or inches).
    inner_groove_ratio, outer_groove_ratio : float
        fi, fo: groove radius over D, in (0.5, 1); typically 0.515-0.53.
    contact_angle : float
        a0, unloaded contact angle in **degrees**, in [0, 90): the angle of
        the line through the groove-curvature centres with the play taken up
        (0 for a deep-groove bearing, the catalogue angle for an angular
        contact one). Independent of the clearance. Above 0 but below 1 degree: a UserWarning
        (probably radians).
    diametral_clearance : float
        Pd, radial play in mm, < 2 A0 cos(a0); radial_clearance rL = Pd/2 per
        ball. Negative: an interference (radial preload) that deflects each
        ball by at most 10 % of A0.
    row_spacing : float or None
        2e, axial distance between the two rows of a double-row bearing, mm, >= 0.
    ball_material, ring_material : Material
        Steel (E = 208 000 N/mm^2, nu = 0.3) by default.
    ellipticity : {"exact", "hamrock-brewe"}
        Route to the contact ellipticity (:func:`ellipticity`).
    contact_pressure_limit : float
        Largest Hertz contact pressure in N/mm^2 for which a solution is
        taken as valid (default 4200, the usual static limit of ball
        bearings, ISO 76); the rows' ``deflection_limit`` is the ball
        deflection at which the more loaded race contact reaches it at a0.
        > 0.
    ball_density : float or None
        rho of the balls in kg/m^3, > 0; None: the ball material's (7850 steel, 3200 silicon nitride).
        Only the high-speed model uses it (centrifugal force, gyroscopic moment).
    race_control : {"outer", "inner", "none"}
        Which raceway controls the balls' spin at speed (Harris): "outer" (the usual assumption for
        spindle bearings; the gyroscopic moment is carried at the outer race, lambda_i, lambda_o = 0, 2),
        "inner" (lambda = 1, 1) or "none" (no gyroscopic moment; orbital speed as for outer control).
    rotating : {"inner", "outer"}
        The ring that turns at the shaft speed (the other stands still).
    bore, outer_diameter, width : float or None
        The boundary dimensions d, D, B in mm (ISO 15), from the maker's catalogue: optional, needed for
        fits (:func:`check_boundary_dimensions`: d < dm - D, D > dm + D).
    dynamic_load_rating, static_load_rating : float or None
        The catalogue's C and C0 of the bearing as listed, N (> 0): a single row's, or a double row's
        (DB, DF, DT) as a unit, whose rows then get C / 2^0.7 and C0 / 2 (ISO 281, ISO 76); for rows of
        your own (``rows``), each row's. None: ISO 281 / ISO 76 from this geometry
        (:mod:`fastbearing.analysis.life`).

    Notes
    -----
    Derived model parameters (docs/model.md, "Hertz constant from geometry (for bearings given by
    catalogue dimensions)"): ``groove_center_distance``
    A0 = (fi + fo - 1) D; ``pitch_radius`` R = dm/2 + (fi - 0.5) D cos(a0):
    the inner groove's cross-section circle (radius fi D) touches the ball
    at the inner contact point, which lies D/2 inside the ball centre (at
    radius dm/2) along the contact line, so the circle's centre lies
    fi D - D/2 beyond the ball centre, on the outer side, along the same
    line; its radial component is (fi - 0.5) D cos(a0). (The outer groove
    centre sits at dm/2 - (fo - 0.5) D cos(a0); the two are A0 apart.)
    ``hertz_constant`` Kn combines the inner and outer contacts at a0 in
    series.
    """

    n_balls: int
    ball_diameter: float
    pitch_diameter: float
    inner_groove_ratio: float
    outer_groove_ratio: float
    contact_angle: float = 0.0
    diametral_clearance: float = 0.0
    row_spacing: float | None = None
    ball_material: Material = STEEL
    ring_material: Material = STEEL
    ellipticity: str = "exact"
    contact_pressure_limit: float = CONTACT_PRESSURE_LIMIT
    dynamic_load_rating: float | None = None
    static_load_rating: float | None = None
    ball_density: float | None = None
    race_control: str = "outer"
    rotating: str = "inner"
    bore: float | None = None
    outer_diameter: float | None = None
    width: float | None = None
    #: The element kind of the rows it makes (a roller geometry's ``element`` says its own).
    element = "ball"

    def __post_init__(self):
        v = validate
        set_ = object.__setattr__
        set_(self, "n_balls", v.integer(self.n_balls, "n_balls", low=1))
        if self.ball_density is not None:
            set_(self, "ball_density", v.number(self.ball_density, "ball_density", low=0, low_open=True,
                                                units="kg/m^3"))
        v.choice(self.race_control, "race_control", RACE_CONTROLS)
        v.choice(self.rotating, "rotating", ROTATING_RINGS)
        D = v.number(self.ball_diameter, "ball_diameter", low=0, low_open=True, units="mm")
        set_(self, "ball_diameter", D)
        if not (validate._is_number(self.pitch_diameter) and math.isfinite(self.pitch_diameter)
                and self.pitch_diameter > D):
            hint = ""
            if validate._is_number(self.pitch_diameter) and 0 < self.pitch_diameter < 0.5 * D:
                # far below D: a unit slip (dm / D of real bearings is about 2.5 to 10, a slewing ring's a few dozen)
                guesses = [g for g in _probable_units(float(self.pitch_diameter), 2.0 * D, 60.0 * D)
                           if not g.startswith("micro")]
                hint = f": it looks like {' or '.join(guesses)}" if guesses else ""
            raise v.FieldError("pitch_diameter", f"must be > ball_diameter ({D!r} mm){hint}", self.pitch_diameter)
        dm = float(self.pitch_diameter)
        set_(self, "pitch_diameter", dm)
        z_max = int(math.pi / math.asin(D / dm) + 1e-9)
        if self.n_balls > z_max:
            raise v.FieldError("n_balls", f"must be <= {z_max} for ball_diameter {D!r} mm on pitch_diameter {dm!r} "
                               "mm (more would overlap)", self.n_balls)
        for name in ("inner_groove_ratio", "outer_groove_ratio"):
            set_(self, name, v.number(getattr(self, name), name, low=0.5, high=1.0, low_open=True, high_open=True))
        set_(self, "contact_angle", v.number(self.contact_angle, "contact_angle", low=0, high=90, high_open=True,
                                             units="degrees"))
        a0 = math.radians(self.contact_angle)
        limit = 2.0 * self.groove_center_distance * math.cos(a0)
        # a negative clearance preloads the balls radially: the same 10 % of A0 bound as Row's
        A0 = self.groove_center_distance
        floor = -2.0 * (math.sqrt(((1 + PRELOAD_DEFLECTION_LIMIT) * A0) ** 2 - (A0 * math.sin(a0)) ** 2)
                        - A0 * math.cos(a0))
        set_(self, "diametral_clearance", v.number(self.diametral_clearance, "diametral_clearance", units="mm"))
        if self.diametral_clearance >= limit:
            raise v.FieldError("diametral_clearance", f"must be < 2 A0 cos(a0) = {limit:.6g} mm "
                               "(A0 = (fi + fo - 1) D)", self.diametral_clearance)
        if self.diametral_clearance < floor:
            raise v.FieldError("diametral_clearance", f"must be >= {floor:.6g} mm: a negative clearance (radial "
                               f"preload) may deflect each ball by at most {PRELOAD_DEFLECTION_LIMIT:g} A0",
                               self.diametral_clearance)
        if self.row_spacing is not None:
            set_(self, "row_spacing", v.number(self.row_spacing, "row_spacing", low=0, units="mm"))
        for name in ("ball_material", "ring_material"):
            if not isinstance(getattr(self, name), Material):
                raise v.FieldError(name, "must be a fastbearing.Material", getattr(self, name))
        v.choice(self.ellipticity, "ellipticity", ELLIPTICITY_METHODS)
        set_(self, "contact_pressure_limit", v.number(self.contact_pressure_limit, "contact_pressure_limit", low=0,
                                                      low_open=True, units="N/mm^2"))
        for name in ("dynamic_load_rating", "static_load_rating"):
            if getattr(self, name) is not None:
                set_(self, name, v.number(getattr(self, name), name, low=0, low_open=True, units="N"))
        check_boundary_dimensions(self, D)
        # an accepted geometry only: no warning beside an error (its rows' check says the same, once)
        check_ball_diameter_unit(self.ball_diameter)
        check_contact_angle_unit(self.contact_angle)

    # -- derived model parameters ------------------------------------------------------
    # (docs/model.md, "Hertz constant from geometry (for bearings given by catalogue dimensions)")
    @property
    def groove_center_distance(self) -> float:
        """A0 = (fi + fo - 1) D in mm."""
        return (self.inner_groove_ratio + self.outer_groove_ratio - 1.0) * self.ball_diameter

    @property
    def pitch_radius(self) -> float:
        """R = dm/2 + (fi - 0.5) D cos(a0) in mm: radius of the inner groove-curvature-centre circle."""
        a0 = math.radians(self.contact_angle)
        return 0.5 * self.pitch_diameter + (self.inner_groove_ratio - 0.5) * self.ball_diameter * math.cos(a0)

    @property
    def radial_clearance(self) -> float:
        """rL = Pd/2 in mm, per ball."""
        return 0.5 * self.diametral_clearance

    @property
    def row_offset(self) -> float | None:
        """e = row_spacing/2 in mm (None when no row spacing is given)."""
        return None if self.row_spacing is None else 0.5 * self.row_spacing

    @property
    def free_contact_angle(self) -> float:
        """a_f in rad: the contact angle once pure axial load takes up the clearance.

        cos(a_f) = cos(a0) - Pd/(2 A0); for a deep-groove bearing (a0 = 0)
        cos(a_f) = 1 - Pd/(2 A0). Equals a0 when Pd <= 0.
        """
        return free_contact_angle(self.groove_center_distance, math.radians(self.contact_angle),
                                  self.radial_clearance)

    @property
    def reduced_modulus(self) -> float:
        """E' = 2/((1-nu_b^2)/E_b + (1-nu_r^2)/E_r) in N/mm^2."""
        return reduced_modulus(self.ball_material, self.ring_material)

    def contacts(self, contact_angle: float | None = None) -> tuple[HertzContact, HertzContact]:
        """Inner and outer race contacts at ``contact_angle`` (rad; default the unloaded a0)."""
        a = math.radians(self.contact_angle) if contact_angle is None else float(contact_angle)
        return race_contacts(self.ball_diameter, self.pitch_diameter, self.inner_groove_ratio,
                             self.outer_groove_ratio, a, self.reduced_modulus, self.ellipticity)

    @property
    def hertz_constant(self) -> float:
        """Kn in N/mm^1.5: the inner and outer contacts at a0 in series."""
        inner, outer = self.contacts()
        return series_constant(inner.constant, outer.constant)

    def load_centre_spread(self, arrangement: str) -> float | None:
        """E = 2 (e + c2 R tan a0) in mm for a double row (c2 = +1 DB, -1 DF, 0 DT); None otherwise."""
        if arrangement not in _SPREAD_SIGN or self.row_offset is None:
            return None
        return load_centre_spread(arrangement, self.row_offset, self.pitch_radius, math.radians(self.contact_angle))

    @property
    def deflection_limit(self) -> float:
        """The ball deflection in mm (inner and outer contacts in series) at which the more loaded race
        contact reaches ``contact_pressure_limit`` at a0: p_max grows as Q^(1/3), so the limit load is
        Q = (p_limit / p_max(1 N))^3 and the deflection (Q/Kn)^(2/3)."""
        inner, outer = self.contacts()
        per_newton = max(inner.max_pressure(1.0), outer.max_pressure(1.0))
        load = (self.contact_pressure_limit / per_newton) ** 3
        return (load / self.hertz_constant) ** (2.0 / 3.0)

    @property
    def density(self) -> float:
        """rho of the balls in kg/m^3: ``ball_density``, else the ball material's."""
        return self.ball_density if self.ball_density is not None else self.ball_material.density

    def speed_columns(self, contact_angle: float) -> np.ndarray:
        """The high-speed constants of a ball of this geometry in a row of unloaded contact angle
        ``contact_angle`` (degrees): one column of the speed table, its rows named in schema.py ((f_i - 1/2) D,
        (f_o - 1/2) D in mm; K_i, K_o in N/mm^1.5, the race contacts at a0; m d_m/2 in kg*m, so that F_c is
        in N for omega in rad/s; J = m D^2/10 in N*mm*s^2, so that M_g is in N*mm; gamma' = D/d_m; the
        race-control factors; inner control and the outer ring turning, 0/1; f_i D and D in mm; the outer
        contact's share of the quasi-static deflection; cos a0; PARTNER -1)."""
        D, dm = self.ball_diameter, self.pitch_diameter
        inner, outer = self.contacts(math.radians(contact_angle))
        Ki, Ko = inner.constant, outer.constant
        mass = self.density * math.pi * (D * 1e-3) ** 3 / 6.0  # kg
        ratio = (Ki / Ko) ** (2.0 / 3.0)  # delta_o / delta_i with Q_i = Q_o
        c = np.empty(schema.N_SPEED_COLUMNS)
        c[schema.INNER_RADIUS] = (self.inner_groove_ratio - 0.5) * D
        c[schema.OUTER_RADIUS] = (self.outer_groove_ratio - 0.5) * D
        c[schema.K_INNER], c[schema.K_OUTER] = Ki, Ko
        c[schema.MASS_RADIUS] = mass * 0.5 * dm * 1e-3
        c[schema.INERTIA] = mass * D * D / 10.0 * 1e-3
        c[schema.GAMMA] = D / dm
        c[schema.LAMBDA_INNER], c[schema.LAMBDA_OUTER] = RACE_CONTROL_FACTORS[self.race_control]
        c[schema.INNER_CONTROL] = float(self.race_control == "inner")
        c[schema.OUTER_ROTATES] = float(self.rotating == "outer")
        c[schema.INNER_ARM] = self.inner_groove_ratio * D
        c[schema.DIAMETER] = D
        c[schema.OUTER_SHARE] = ratio / (1.0 + ratio)
        c[schema.COS_NOMINAL] = math.cos(math.radians(contact_angle))
        c[schema.PARTNER] = -1.0  # the bearing pairs a four-point ball's columns (Bearing.speed_table)
        return c

    def no_solution_note(self, speed: float) -> str:
        """Why a load at ``speed`` (rpm) may have no solution under this geometry's race control ("" if
        nothing is known): under inner-race control the inner friction carrying the gyroscopic moment does
        not fall with the inner contact's load, so f jumps where balls leave the inner race (docs/model.md,
        "High speed")."""
        if self.race_control != "inner":
            return ""
        return (f"no solution found: under inner-race control at {float(speed):g} rpm the inner race's friction, "
                "which carries the gyroscopic moment, does not fall with the inner contact load, so f jumps where "
                "balls leave the inner race, and this load may lie in that jump; outer-race control (the default) "
                "has no such jump")

    def row_keywords(self) -> dict:
        """The :class:`fastbearing.Row` keywords this geometry fixes (angles in degrees, as Row takes them)."""
        return dict(n_balls=self.n_balls, hertz_constant=self.hertz_constant, pitch_radius=self.pitch_radius,
                    groove_center_distance=self.groove_center_distance, contact_angle=self.contact_angle,
                    exponent=1.5, radial_clearance=self.radial_clearance, deflection_limit=self.deflection_limit)

    def bearing(self, arrangement: str = "single", *, name: str = "", axial_preload=0.0,
                first_ball_angle: float = 0.0) -> Bearing:
        """A :class:`fastbearing.Bearing` of this geometry, carrying it in ``bearing.geometry``.

        Parameters
        ----------
        arrangement : {"single", "DB", "DF", "DT"}
            Double rows need ``row_spacing``.
        axial_preload : float or pair of float
            d0 per row in mm; only with zero clearance.
        first_ball_angle : float
            psi0 in degrees.
        """
        row = {**self.row_keywords(), "first_ball_angle": first_ball_angle}
        if arrangement == "single":
            b = Bearing.single(name=name, axial_preload=axial_preload, **row)
        elif arrangement in _SPREAD_SIGN:
            if self.row_spacing is None:
                raise ValueError(f"row_spacing (2e, mm, >= 0) is required for arrangement {arrangement!r}")
            b = Bearing.double(arrangement, self.row_offset, axial_preload=axial_preload, name=name, **row)
        else:
            raise ValueError(f"arrangement must be one of ['single', 'DB', 'DF', 'DT'], got {arrangement!r}")
        return replace(b, geometry=self)

    def describe(self) -> str:
        """One line of the inputs, with units."""
        mats = (f"balls {self.ball_material.name} (E={self.ball_material.youngs_modulus:g} N/mm^2, "
                f"nu={self.ball_material.poisson_ratio:g}), rings {self.ring_material.name} "
                f"(E={self.ring_material.youngs_modulus:g} N/mm^2, nu={self.ring_material.poisson_ratio:g})")
        spacing = "" if self.row_spacing is None else f", row spacing 2e={self.row_spacing:g} mm"
        return (f"Z={self.n_balls}, D={self.ball_diameter:g} mm, dm={self.pitch_diameter:g} mm, "
                f"fi={self.inner_groove_ratio:g}, fo={self.outer_groove_ratio:g}, a0={self.contact_angle:g} deg, "
                f"Pd={self.diametral_clearance:g} mm{spacing}; {mats}")


def load_centre_spread(arrangement: str, row_offset: float, pitch_radius: float, contact_angle: float) -> float:
    """E = 2 (e + c2 R tan a0) in mm, c2 = +1 DB, -1 DF, 0 DT (paper Eq. 6; docs/model.md,
    "A bearing is a set of rows on one rigid inner ring"); a0 in rad."""
    return 2.0 * (row_offset + _SPREAD_SIGN[arrangement] * pitch_radius * math.tan(contact_angle))


# -- bearing-file table ----------------------------------------------------------------
GEOMETRY_KEYS = ("n_balls", "ball_diameter", "pitch_diameter", "inner_groove_ratio", "outer_groove_ratio",
                 "contact_angle", "diametral_clearance", "row_spacing", "youngs_modulus", "poisson_ratio",
                 "ball_youngs_modulus", "ring_youngs_modulus", "ball_poisson_ratio", "ring_poisson_ratio",
                 "material", "ellipticity", "contact_pressure_limit", "dynamic_load_rating", "static_load_rating",
                 "ball_density", "race_control", "rotating", "bore", "outer_diameter", "width")
_REQUIRED = ("n_balls", "ball_diameter", "pitch_diameter", "inner_groove_ratio", "outer_groove_ratio")


def _material_values(table: dict, where: str) -> tuple[Material, Material]:
    """Ball and ring materials: per-body keys > ``material`` (balls) > shared keys > steel."""
    ball = {"name": STEEL.name, "youngs_modulus": STEEL.youngs_modulus, "poisson_ratio": STEEL.poisson_ratio}
    ring = dict(ball)
    for prop in ("youngs_modulus", "poisson_ratio"):
        if prop in table:
            ball[prop] = ring[prop] = table[prop]
            ball["name"] = ring["name"] = "custom"
    if "material" in table:
        m = MATERIALS[validate.choice(table["material"], f"{where}.material", sorted(MATERIALS))]
        ball = {"name": m.name, "youngs_modulus": m.youngs_modulus, "poisson_ratio": m.poisson_ratio,
                "density": m.density}
    for body, values in (("ball", ball), ("ring", ring)):
        for prop in ("youngs_modulus", "poisson_ratio"):
            key = f"{body}_{prop}"
            if key in table:
                values[prop] = table[key]
                values["name"] = "custom"
    out = []
    for body, values in (("ball", ball), ("ring", ring)):
        try:
            out.append(Material(**values))
        except validate.FieldError as err:
            source = next((k for k in (f"{body}_{err.field}", err.field) if k in table), err.field)
            raise validate.FieldError(f"{where}.{source}", err.rule, err.value) from None
    return out[0], out[1]


def geometry_from_table(table: dict, where: str = "bearing.geometry") -> Geometry:
    """Build a :class:`Geometry` from a parsed ``[bearing.geometry]`` table (angles in degrees).

    Keys: n_balls, ball_diameter (mm), pitch_diameter (mm), inner_groove_ratio,
    outer_groove_ratio (required); contact_angle (deg, default 0),
    diametral_clearance (mm, default 0), row_spacing (mm, double rows),
    youngs_modulus (N/mm^2), poisson_ratio (balls and rings), ball_/ring_
    variants of both (one body), material ("steel" | "silicon-nitride", the
    balls), ellipticity ("exact" | "hamrock-brewe"); for the high-speed model
    ball_density (kg/m^3), race_control ("outer" | "inner" | "none") and
    rotating ("inner" | "outer"). A ValueError names the key.
    """
    validate.table(table, where, GEOMETRY_KEYS, _REQUIRED)
    ball, ring = _material_values(table, where)
    values = {k: table[k] for k in _REQUIRED + ("contact_angle", "diametral_clearance", "row_spacing", "ellipticity",
                                                "contact_pressure_limit", "dynamic_load_rating",
                                                "static_load_rating", "ball_density", "race_control",
                                                "rotating", "bore", "outer_diameter", "width") if k in table}
    try:
        return Geometry(**values, ball_material=ball, ring_material=ring)
    except validate.FieldError as err:
        raise err.within(where) from None
