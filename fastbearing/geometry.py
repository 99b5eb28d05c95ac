"""Bearings from catalogue geometry: Hertz point contacts and the model parameters.

Engineers know a bearing's dimensions, not its Hertz constant. This module
turns ball diameter D, pitch diameter dm, groove curvature ratios fi and fo,
contact angle a0, diametral clearance Pd, row spacing and the materials into
the model parameters of :class:`fastbearing.Row` (MODEL.md, last section):

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
from dataclasses import dataclass, fields, replace

import numpy as np

from .bearing import Bearing, _check_finite, check_keys

ELLIPTICITY_METHODS = ("exact", "hamrock-brewe")

#: Contact-direction coefficient c2 of the load-centre spread E = 2(e + c2 R tan a0) (MODEL.md).
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
    """

    name: str
    youngs_modulus: float
    poisson_ratio: float

    def __post_init__(self):
        E = _check_finite("youngs_modulus", self.youngs_modulus)
        nu = _check_finite("poisson_ratio", self.poisson_ratio)
        if E <= 0:
            raise ValueError(f"youngs_modulus must be > 0 N/mm^2, got {self.youngs_modulus!r}")
        if not 0.0 <= nu < 0.5:
            raise ValueError(f"poisson_ratio must be in [0, 0.5), got {self.poisson_ratio!r}")
        object.__setattr__(self, "youngs_modulus", E)
        object.__setattr__(self, "poisson_ratio", nu)


#: Through-hardened bearing steel (AISI 52100 / 100Cr6): E = 208 000 N/mm^2, nu = 0.3
#: (Harris & Kotzalas use 2.075e5 N/mm^2; catalogues quote 200-210 GPa).
STEEL = Material("steel", 208000.0, 0.3)
#: Bearing-grade silicon nitride (Si3N4) balls of hybrid bearings: E = 310 000 N/mm^2, nu = 0.26.
SILICON_NITRIDE = Material("silicon-nitride", 310000.0, 0.26)
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


# -- a bearing's geometry ------------------------------------------------------------
@dataclass(frozen=True)
class Geometry:
    """Catalogue geometry and materials of the rows of a ball bearing (all rows alike).

    Parameters
    ----------
    n_balls : int
        Z, balls per row, >= 1 and few enough not to overlap on the pitch circle.
    ball_diameter : float
        D, mm, > 0.
    pitch_diameter : float
        dm, diameter of the ball-centre circle, mm, > D.
    inner_groove_ratio, outer_groove_ratio : float
        fi, fo: groove radius over D, in (0.5, 1); typically 0.515-0.53.
    contact_angle : float
        a0, unloaded contact angle in **degrees**, in [0, 90): the angle of
        the line through the groove-curvature centres with the play taken up
        (0 for a deep-groove bearing, the catalogue angle for an angular
        contact one). Independent of the clearance.
    diametral_clearance : float
        Pd, radial play in mm, >= 0 and < 2 A0 cos(a0); radial_clearance rL = Pd/2 per ball.
    row_spacing : float or None
        2e, axial distance between the two rows of a double-row bearing, mm, >= 0.
    ball_material, ring_material : Material
        Steel (E = 208 000 N/mm^2, nu = 0.3) by default.
    ellipticity : {"exact", "hamrock-brewe"}
        Route to the contact ellipticity (:func:`ellipticity`).

    Notes
    -----
    Derived model parameters (MODEL.md): ``groove_center_distance``
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

    def __post_init__(self):
        for f in fields(self):
            if f.name in ("n_balls", "ball_material", "ring_material", "ellipticity"):
                continue
            value = getattr(self, f.name)
            if f.name == "row_spacing" and value is None:
                continue
            object.__setattr__(self, f.name, _check_finite(f.name, value))
        n = self.n_balls
        if isinstance(n, bool) or not isinstance(n, (int, np.integer, float)) or n != int(n) or n < 1:
            raise ValueError(f"n_balls must be an integer >= 1, got {n!r}")
        object.__setattr__(self, "n_balls", int(n))
        D, dm = self.ball_diameter, self.pitch_diameter
        if D <= 0:
            raise ValueError(f"ball_diameter must be > 0 mm, got {D!r}")
        if dm <= D:
            raise ValueError(f"pitch_diameter must be > ball_diameter ({D!r} mm), got {dm!r}")
        z_max = int(math.pi / math.asin(D / dm) + 1e-9)
        if self.n_balls > z_max:
            raise ValueError(f"n_balls must be <= {z_max} for ball_diameter {D!r} mm on pitch_diameter {dm!r} mm "
                             f"(more would overlap), got {self.n_balls}")
        for name in ("inner_groove_ratio", "outer_groove_ratio"):
            f_ = getattr(self, name)
            if not 0.5 < f_ < 1.0:
                raise ValueError(f"{name} must be in (0.5, 1) (groove radius over ball diameter), got {f_!r}")
        if not 0.0 <= self.contact_angle < 90.0:
            raise ValueError(f"contact_angle must be in [0, 90) degrees, got {self.contact_angle!r}")
        if self.diametral_clearance < 0:
            raise ValueError(f"diametral_clearance must be >= 0 mm, got {self.diametral_clearance!r}")
        limit = 2.0 * self.groove_center_distance * math.cos(math.radians(self.contact_angle))
        if self.diametral_clearance >= limit:
            raise ValueError(f"diametral_clearance must be < 2 A0 cos(a0) = {limit:.6g} mm (A0 = (fi + fo - 1) D), "
                             f"got {self.diametral_clearance!r}")
        if self.row_spacing is not None and self.row_spacing < 0:
            raise ValueError(f"row_spacing must be >= 0 mm, got {self.row_spacing!r}")
        for name in ("ball_material", "ring_material"):
            if not isinstance(getattr(self, name), Material):
                raise ValueError(f"{name} must be a fastbearing.geometry.Material, got {getattr(self, name)!r}")
        if self.ellipticity not in ELLIPTICITY_METHODS:
            raise ValueError(f"ellipticity must be one of {list(ELLIPTICITY_METHODS)}, got {self.ellipticity!r}")

    # -- derived model parameters (MODEL.md) -------------------------------------------
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
        cos(a_f) = 1 - Pd/(2 A0). Equals a0 when Pd = 0.
        """
        return math.acos(math.cos(math.radians(self.contact_angle))
                         - self.diametral_clearance / (2.0 * self.groove_center_distance))

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

    def row_keywords(self) -> dict:
        """The :class:`fastbearing.Row` keywords this geometry fixes (angles in degrees, as Row takes them)."""
        return dict(n_balls=self.n_balls, hertz_constant=self.hertz_constant, pitch_radius=self.pitch_radius,
                    groove_center_distance=self.groove_center_distance, contact_angle=self.contact_angle,
                    exponent=1.5, radial_clearance=self.radial_clearance)

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
    """E = 2 (e + c2 R tan a0) in mm, c2 = +1 DB, -1 DF, 0 DT (paper, MODEL.md); a0 in rad."""
    return 2.0 * (row_offset + _SPREAD_SIGN[arrangement] * pitch_radius * math.tan(contact_angle))


# -- bearing-file table ----------------------------------------------------------------
GEOMETRY_KEYS = ("n_balls", "ball_diameter", "pitch_diameter", "inner_groove_ratio", "outer_groove_ratio",
                 "contact_angle", "diametral_clearance", "row_spacing", "youngs_modulus", "poisson_ratio",
                 "ball_youngs_modulus", "ring_youngs_modulus", "ball_poisson_ratio", "ring_poisson_ratio",
                 "material", "ellipticity")
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
        name = table["material"]
        if name not in MATERIALS:
            raise ValueError(f"{where}.material must be one of {sorted(MATERIALS)} (for the balls), got {name!r}")
        m = MATERIALS[name]
        ball = {"name": m.name, "youngs_modulus": m.youngs_modulus, "poisson_ratio": m.poisson_ratio}
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
        except ValueError as err:
            msg = str(err)
            prop = msg.split(" ", 1)[0]
            source = next((k for k in (f"{body}_{prop}", prop) if k in table), prop)
            raise ValueError(f"{where}.{source}{msg[len(prop):]}") from None
    return out[0], out[1]


def geometry_from_table(table: dict, where: str = "bearing.geometry") -> Geometry:
    """Build a :class:`Geometry` from a parsed ``[bearing.geometry]`` table (angles in degrees).

    Keys: n_balls, ball_diameter (mm), pitch_diameter (mm), inner_groove_ratio,
    outer_groove_ratio (required); contact_angle (deg, default 0),
    diametral_clearance (mm, default 0), row_spacing (mm, double rows),
    youngs_modulus (N/mm^2), poisson_ratio (balls and rings), ball_/ring_
    variants of both (one body), material ("steel" | "silicon-nitride", the
    balls), ellipticity ("exact" | "hamrock-brewe"). A ValueError names the key.
    """
    if not isinstance(table, dict):
        raise ValueError(f"{where} must be a table, got {type(table).__name__}")
    check_keys(table, GEOMETRY_KEYS, where)
    missing = [k for k in _REQUIRED if k not in table]
    if missing:
        raise ValueError(f"{where}: missing required key(s) {missing}")
    ball, ring = _material_values(table, where)
    values = {k: table[k] for k in _REQUIRED + ("contact_angle", "diametral_clearance", "row_spacing", "ellipticity")
              if k in table}
    try:
        return Geometry(**values, ball_material=ball, ring_material=ring)
    except ValueError as err:
        raise ValueError(f"{where}.{err}") from None


# -- per-ball contact results ----------------------------------------------------------
@dataclass(frozen=True)
class BallContacts:
    """What happens at every ball of a bearing at one displacement q.

    Arrays of length n_balls, ordered row by row, each row from its first
    ball (as :func:`fastbearing.ball_loads`). The contact fields are None
    when the bearing has no catalogue geometry.

    Attributes
    ----------
    row, ball : ndarray of int
        Row index and ball index within the row.
    azimuth : ndarray
        psi, ball azimuth in rad, in [0, 2 pi).
    deflection : ndarray
        delta = (Q/Kn)^(1/n), total elastic approach of the ball (both contacts), mm.
    load : ndarray
        Q, ball load in N.
    contact_angle : ndarray
        alpha, loaded contact angle in rad, signed on the row's contact direction.
    inner_max_pressure, outer_max_pressure : ndarray or None
        Maximum Hertz pressure at the inner / outer race, N/mm^2 (MPa).
    inner_semi_major, inner_semi_minor, outer_semi_major, outer_semi_minor : ndarray or None
        Contact-ellipse semi-axes a (across the groove) and b (rolling direction), mm.
    """

    row: np.ndarray
    ball: np.ndarray
    azimuth: np.ndarray
    deflection: np.ndarray
    load: np.ndarray
    contact_angle: np.ndarray
    inner_max_pressure: np.ndarray | None = None
    inner_semi_major: np.ndarray | None = None
    inner_semi_minor: np.ndarray | None = None
    outer_max_pressure: np.ndarray | None = None
    outer_semi_major: np.ndarray | None = None
    outer_semi_minor: np.ndarray | None = None

    @property
    def has_contacts(self) -> bool:
        return self.inner_max_pressure is not None

    def max_pressure_per_row(self) -> np.ndarray | None:
        """Largest contact pressure of each row over both races, N/mm^2 (None without geometry)."""
        if not self.has_contacts:
            return None
        worst = np.maximum(self.inner_max_pressure, self.outer_max_pressure)
        return np.array([worst[self.row == r].max(initial=0.0) for r in range(int(self.row.max()) + 1)])

    def to_records(self) -> list[dict]:
        """One JSON-ready dict per ball (lengths mm, angles rad, loads N, pressures N/mm^2)."""
        names = [f.name for f in fields(self) if getattr(self, f.name) is not None]
        records = []
        for i in range(len(self.load)):
            rec = {}
            for n in names:
                v = getattr(self, n)[i]
                rec[n] = int(v) if n in ("row", "ball") else float(v)
            records.append(rec)
        return records


def ball_contacts(bearing: Bearing, q) -> BallContacts:
    """Per-ball load, deflection, contact angle and (with geometry) Hertz contact at displacement q.

    Ball loads and loaded contact angles come from :func:`fastbearing.ball_loads`
    (the one ball loop); the deflection is delta = (Q/Kn)^(1/n). With a
    catalogue geometry (``bearing.geometry``), each loaded ball's inner and
    outer contacts are evaluated at its own loaded contact angle (the
    rolling-plane curvature depends on it through gamma = D cos(alpha)/dm),
    giving the maximum pressure and the ellipse semi-axes.

    Parameters
    ----------
    bearing : Bearing
    q : sequence of 5 floats
        (dx, dy, dz, bx, by) in mm and rad, e.g. ``solve(bearing, f).q``.

    Returns
    -------
    BallContacts
    """
    from .api import ball_loads

    Q, alpha = ball_loads(bearing, q)
    rows, balls, psi, kn, n = [], [], [], [], []
    for i, r in enumerate(bearing.rows):
        j = np.arange(r.n_balls)
        rows.append(np.full(r.n_balls, i))
        balls.append(j)
        psi.append(np.mod(math.radians(r.first_ball_angle) + 2.0 * math.pi * j / r.n_balls, 2.0 * math.pi))
        kn.append(np.full(r.n_balls, r.hertz_constant))
        n.append(np.full(r.n_balls, r.exponent))
    kn, n = np.concatenate(kn), np.concatenate(n)
    delta = (np.maximum(Q, 0.0) / kn) ** (1.0 / n)
    base = dict(row=np.concatenate(rows), ball=np.concatenate(balls), azimuth=np.concatenate(psi),
                deflection=delta, load=Q, contact_angle=alpha)
    geometry = getattr(bearing, "geometry", None)
    if geometry is None:
        return BallContacts(**base)
    out = {k: np.zeros(len(Q)) for k in ("inner_max_pressure", "inner_semi_major", "inner_semi_minor",
                                          "outer_max_pressure", "outer_semi_major", "outer_semi_minor")}
    cache: dict[float, tuple[HertzContact, HertzContact]] = {}
    for i in np.flatnonzero(Q > 0):
        a = abs(float(alpha[i]))
        if a not in cache:
            cache[a] = geometry.contacts(a)
        for side, contact in zip(("inner", "outer"), cache[a]):
            major, minor = contact.semi_axes(Q[i])
            out[f"{side}_max_pressure"][i] = contact.max_pressure(Q[i])
            out[f"{side}_semi_major"][i] = major
            out[f"{side}_semi_minor"][i] = minor
    return BallContacts(**base, **out)
