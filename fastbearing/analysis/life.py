"""Rating life beside Kb: ISO 281 load ratings and basic life, ISO/TS 16281 modified reference rating
life L10r from the solved load distribution, static safety.

Units: loads N, lengths mm, lives in million revolutions (hours with a shaft speed in rpm), pressures
N/mm^2. Every row is rated as a single-row bearing of its geometry (i = 1); a double row or a tandem
pair is the sum of its rows, as ISO 281 treats a pair mounted as a unit; so is a four-point row, whose two
contact pairs are a double-row angular contact bearing's two rows (i = 2 and the double-row X, Y, X0, Y0,
as the makers' QJ tables: docs/life.md, "Four-point contact ball bearings").

Sources (the standards' formulas as transcribed in public code, checked against each other; the
standards themselves are not public):

- ISO 281:2007 Eq. (1)-(2) (C_r = b_m f_c (i cos a)^0.7 Z^(2/3) Dw^1.8, b_m = 1.3), Table 2 column 1
  (f_c), Table 3 (X, Y, e); ISO 76:2006 (C_0r = f_0 i Z Dw^2 cos a, f_0, X_0, Y_0);
- ISO/TS 16281:2008 for balls: the raceway-contact ratings Q_ci, Q_ce from the row's C_r, the
  equivalent contact loads (cubic mean on the rotating ring, 10/3 mean on the stationary one, over all
  Z balls), L10r = ((Q_ci/Q_ei)^(-10/3) + (Q_ce/Q_ee)^(-10/3))^(-0.9), rows combined as
  (sum L^(-10/9))^(-0.9); as implemented in github.com/minzhun/ISO16281 (BallBearing.py, commit
  1b0e9ded), whose reference results tests/test_life.py reproduces;
- roller rows: ISO 281 Eq. (6)-(7) (C_r = b_m f_c (i l cos a)^(7/9) Z^(3/4) Dw^(29/27), b_m = 1.1, f_c from
  its closed form behind Table 7 with lambda nu = 0.83), Table 8 (X, Y, e = 1.5 tan a) and the roller
  a_ISO (Eq. 18-20, C_u ~ C0/8.2); ISO 76 (C_0r = 44 (1 - g) i Z l Dw cos a, X_0 = 0.5, Y_0 = 0.22 cot a);
  ISO/TS 16281 sliced: roller ratings Q_ci, Q_ce from C_r, lamina ratings q_c = Q_c n_s^(-7/9), per
  lamina k the equivalent loads over the Z rollers (4th-power mean on the rotating ring, 9/2-power mean on
  the stationary one) and L10r = (sum_k (q_ei,k/q_ci)^(9/2) + (q_ee,k/q_ce)^(9/2))^(-8/9), rows combined
  with the Weibull slope 9/8; as implemented in github.com/minzhun/ISO16281 (RollerBearing.py, commit
  220b2feb), checked in tests/test_life.py.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from .. import validate
from ..model.mounted import operating
from ..engine.schema import (LIFE_CE, LIFE_CI, LIFE_FIRST, LIFE_INNER, LIFE_SLICES, LIFE_X0, LIFE_Y0, LIFE_Z, N_LIFE_COLUMNS,
                     ROW)

#: ISO 281 Table 2, column 1 (single-row radial and single- or double-row angular contact ball
#: bearings): f_c at gamma = Dw cos(a)/Dpw = 0.01, 0.02 ... 0.40 (interpolated linearly).
FC_GAMMA = np.arange(1, 41) / 100.0
FC = np.array([29.1, 35.8, 40.3, 43.8, 46.7, 49.1, 51.1, 52.8, 54.3, 55.5, 56.6, 57.5, 58.2, 58.8, 59.3, 59.6,
               59.8, 59.9, 60.0, 59.9, 59.8, 59.6, 59.3, 59.0, 58.6, 58.2, 57.7, 57.1, 56.6, 56.0, 55.3, 54.6,
               53.9, 53.2, 52.4, 51.7, 50.9, 50.0, 49.2, 48.4])
#: ISO 76 f_0 of radial ball bearings at gamma = 0.00, 0.01 ... 0.40.
F0_GAMMA = np.arange(0, 41) / 100.0
F0 = np.array([14.7, 14.9, 15.1, 15.3, 15.5, 15.7, 15.9, 16.1, 16.3, 16.5, 16.4, 16.1, 15.9, 15.6, 15.4, 15.2,
               14.9, 14.7, 14.4, 14.2, 14.0, 13.7, 13.5, 13.2, 13.0, 12.8, 12.5, 12.3, 12.1, 11.8, 11.6, 11.4,
               11.2, 10.9, 10.7, 10.5, 10.3, 10.0, 9.8, 9.6, 9.4])
B_M = 1.3
#: ISO 281 life exponent of ball bearings, and the exponent combining rows (Weibull slope 10/9).
LIFE_EXPONENT = 3.0
ROW_EXPONENT = 10.0 / 9.0

# ISO 281 Table 3: relative axial load f0 Fa / C0r, and per contact angle (deg) the factors.
_RELATIVE_AXIAL = np.array([0.172, 0.345, 0.689, 1.03, 1.38, 2.07, 3.45, 5.17, 6.89])
_E_SMALL = {0: [0.19, 0.22, 0.26, 0.28, 0.30, 0.34, 0.38, 0.42, 0.44],
            10: [0.29, 0.32, 0.36, 0.38, 0.40, 0.44, 0.49, 0.54, 0.54],
            15: [0.38, 0.40, 0.43, 0.46, 0.47, 0.50, 0.55, 0.56, 0.56]}
_Y_SINGLE_SMALL = {0: (0.56, [2.30, 1.99, 1.71, 1.55, 1.45, 1.31, 1.15, 1.04, 1.00]),
                   10: (0.46, [1.88, 1.71, 1.52, 1.41, 1.34, 1.23, 1.10, 1.01, 1.00]),
                   15: (0.44, [1.47, 1.40, 1.30, 1.23, 1.19, 1.12, 1.02, 1.00, 1.00])}
_Y_DOUBLE_SMALL = {0: ([0.0] * 9, 0.56, [2.30, 1.99, 1.71, 1.55, 1.45, 1.31, 1.15, 1.04, 1.00]),
                   10: ([2.18, 1.98, 1.76, 1.63, 1.55, 1.42, 1.27, 1.17, 1.16], 0.75,
                        [3.06, 2.78, 2.47, 2.29, 2.18, 2.00, 1.79, 1.64, 1.63]),
                   15: ([1.65, 1.57, 1.46, 1.38, 1.34, 1.26, 1.14, 1.12, 1.12], 0.72,
                        [2.39, 2.28, 2.11, 2.00, 1.93, 1.82, 1.66, 1.63, 1.63])}
#: alpha (deg) -> (X, Y, e) of a single row, Fa/Fr > e; and of a double row: (Y at Fa/Fr <= e, X, Y, e).
_SINGLE_FIXED = {20: (0.43, 1.00, 0.57), 25: (0.41, 0.87, 0.68), 30: (0.39, 0.76, 0.80), 35: (0.37, 0.66, 0.95),
                 40: (0.35, 0.57, 1.14), 45: (0.33, 0.50, 1.34)}
_DOUBLE_FIXED = {20: (1.09, 0.70, 1.63, 0.57), 25: (0.92, 0.67, 1.41, 0.68), 30: (0.78, 0.63, 1.24, 0.80),
                 35: (0.66, 0.60, 1.07, 0.95), 40: (0.55, 0.57, 0.93, 1.14), 45: (0.47, 0.54, 0.81, 1.34)}
#: ISO 76 Y_0 of a single angular contact row (X_0 = 0.5); a double row has X_0 = 1 and twice Y_0.
_Y0_SINGLE = {0: 0.5, 5: 0.52, 10: 0.50, 15: 0.46, 20: 0.42, 25: 0.38, 30: 0.33, 35: 0.29, 40: 0.26, 45: 0.22}
#: Contact pressure limit for ball bearings (ISO 76: C0 corresponds to 4200 N/mm^2), N/mm^2.
PRESSURE_LIMIT = 4200.0
#: ... and for roller bearings (line contact, ISO 76: 4000 N/mm^2), N/mm^2.
ROLLER_PRESSURE_LIMIT = 4000.0
ROTATING = ("inner", "outer")


def _interp(x, xs, ys) -> float:
    return float(np.interp(x, xs, ys))


def _by_angle(table: dict, alpha_deg: float):
    """A table keyed by contact angle (deg), interpolated linearly between its angles, clamped at its ends."""
    keys = sorted(table)
    a = min(max(alpha_deg, keys[0]), keys[-1])
    lo = max(k for k in keys if k <= a)
    hi = min(k for k in keys if k >= a)
    if lo == hi:
        return table[lo]
    w = (a - lo) / (hi - lo)
    return tuple(np.asarray(table[lo], float) * (1 - w) + np.asarray(table[hi], float) * w) \
        if isinstance(table[lo], tuple) else float(table[lo] * (1 - w) + table[hi] * w)


# -- load ratings of one row (i = 1) ---------------------------------------------------------------

def gamma(geometry) -> float:
    """gamma = Dw cos(a0)/Dpw of a geometry (a0 its nominal contact angle)."""
    return geometry.ball_diameter * math.cos(math.radians(geometry.contact_angle)) / geometry.pitch_diameter


def iso_dynamic_rating(geometry, rows: int = 1) -> float:
    """ISO 281 basic dynamic radial load rating C_r in N of ``rows`` rows of this geometry as a unit
    (b_m f_c (i cos a)^0.7 Z^(2/3) Dw^1.8; 3.647 b_m f_c (i cos a)^0.7 Z^(2/3) Dw^1.4 above Dw = 25.4 mm)."""
    g = gamma(geometry)
    if not FC_GAMMA[0] <= g <= FC_GAMMA[-1]:
        raise ValueError(f"bearing.geometry: Dw cos(a0)/Dpw = {g:.4g} is outside ISO 281's table (0.01 to 0.40); "
                         "give dynamic_load_rating (N)")
    fc = _interp(g, FC_GAMMA, FC)
    D = geometry.ball_diameter
    cos_a = math.cos(math.radians(geometry.contact_angle))
    size = D ** 1.8 if D <= 25.4 else 3.647 * D ** 1.4
    return B_M * fc * (rows * cos_a) ** 0.7 * geometry.n_balls ** (2.0 / 3.0) * size


def iso_static_rating(geometry, rows: int = 1) -> float:
    """ISO 76 basic static radial load rating C_0r = f_0 i Z Dw^2 cos(a) in N."""
    f0 = _interp(gamma(geometry), F0_GAMMA, F0)
    return f0 * rows * geometry.n_balls * geometry.ball_diameter ** 2 * math.cos(math.radians(geometry.contact_angle))


def row_ratings(geometry, rows: int = 1) -> tuple[float, float]:
    """(C, C0) of one row in N, for a bearing of ``rows`` identical rows rated as a unit: the catalogue's
    unit ratings where the geometry gives them (a row gets C / rows^0.7 and C0 / rows, as ISO 281 and
    ISO 76 build a unit from its rows), else ISO 281 / ISO 76 of one row."""
    C = (geometry.dynamic_load_rating / rows ** 0.7 if geometry.dynamic_load_rating is not None
         else iso_dynamic_rating(geometry))
    C0 = geometry.static_load_rating / rows if geometry.static_load_rating is not None else iso_static_rating(geometry)
    return C, C0


def contact_ratings(geometry, C_row: float) -> tuple[float, float]:
    """ISO/TS 16281 basic dynamic load ratings Q_ci, Q_ce (N) of the inner and outer raceway contacts of a
    row whose rating is C_row: Q_ci = C/(0.407 Z cos a) (1 + T^(10/3))^0.3, Q_ce = C/(0.389 Z cos a)
    (1 + T^(-10/3))^0.3, T = 1.044 ((1 - g)/(1 + g))^1.72 R^0.41, R = (fi/fo)(2 fo - 1)/(2 fi - 1)."""
    g = gamma(geometry)
    fi, fo = geometry.inner_groove_ratio, geometry.outer_groove_ratio
    R = (fi / fo) * (2.0 * fo - 1.0) / (2.0 * fi - 1.0)
    T = 1.044 * ((1.0 - g) / (1.0 + g)) ** 1.72 * R ** 0.41
    zc = geometry.n_balls * math.cos(math.radians(geometry.contact_angle))
    return C_row / (0.407 * zc) * (1.0 + T ** (10.0 / 3.0)) ** 0.3, C_row / (0.389 * zc) * (1.0 + T ** (-10.0 / 3.0)) ** 0.3


# -- roller rows ----------------------------------------------------------------------------------

B_M_ROLLER = 1.1
#: ISO 281 life exponent of roller bearings, and the Weibull slope combining roller rows.
ROLLER_LIFE_EXPONENT = 10.0 / 3.0
ROLLER_ROW_EXPONENT = 9.0 / 8.0
#: lambda nu of radial roller bearings (ISO 281 f_c, ISO/TS 16281 Q_c).
LAMBDA_NU_ROLLER = 0.83


def roller_gamma(geometry) -> float:
    """gamma = Dw cos(a)/Dpw of a roller geometry."""
    return geometry.roller_diameter * math.cos(math.radians(geometry.contact_angle)) / geometry.pitch_diameter


def roller_fc(g: float) -> float:
    """ISO 281 f_c of radial roller bearings at gamma = Dw cos(a)/Dpw: the closed form behind Table 7,
    207.9 lambda nu g^(2/9) (1 - g)^(29/27) (1 + g)^(-1/4) (1 + (1.04 ((1 - g)/(1 + g))^(143/108))^(9/2))^(-2/9)."""
    t = (1.04 * ((1.0 - g) / (1.0 + g)) ** (143.0 / 108.0)) ** 4.5
    return (207.9 * LAMBDA_NU_ROLLER * g ** (2.0 / 9.0) * (1.0 - g) ** (29.0 / 27.0) * (1.0 + g) ** -0.25
            * (1.0 + t) ** (-2.0 / 9.0))


def iso_roller_dynamic_rating(geometry, rows: int = 1) -> float:
    """ISO 281 C_r (N) of ``rows`` rows of a roller geometry as a unit: b_m f_c (i l cos a)^(7/9) Z^(3/4)
    Dw^(29/27), b_m = 1.1, l the effective length (mm)."""
    cos_a = math.cos(math.radians(geometry.contact_angle))
    return (B_M_ROLLER * roller_fc(roller_gamma(geometry))
            * (rows * geometry.roller_effective_length * cos_a) ** (7.0 / 9.0)
            * geometry.n_rollers ** 0.75 * geometry.roller_diameter ** (29.0 / 27.0))


def iso_roller_static_rating(geometry, rows: int = 1) -> float:
    """ISO 76 C_0r = 44 (1 - g) i Z l Dw cos(a) (N) of a roller geometry (4000 N/mm^2 at the centre)."""
    cos_a = math.cos(math.radians(geometry.contact_angle))
    return (44.0 * (1.0 - roller_gamma(geometry)) * rows * geometry.n_rollers * geometry.roller_effective_length
            * geometry.roller_diameter * cos_a)


def roller_row_ratings(geometry, rows: int = 1) -> tuple[float, float]:
    """(C, C0) of one roller row in N: the catalogue's unit ratings over rows^(7/9) and rows, else ISO's."""
    C = (geometry.dynamic_load_rating / rows ** (7.0 / 9.0) if geometry.dynamic_load_rating is not None
         else iso_roller_dynamic_rating(geometry))
    C0 = (geometry.static_load_rating / rows if geometry.static_load_rating is not None
          else iso_roller_static_rating(geometry))
    return C, C0


def roller_contact_ratings(geometry, C_row: float) -> tuple[float, float]:
    """ISO/TS 16281 dynamic load ratings Q_ci, Q_ce (N) of a whole roller on the inner and outer raceway of a
    row rated C_row: Q_ci = C/(0.378 lambda nu Z cos a) (1 + (1.038 T)^(9/2))^(2/9), Q_ce = C/(0.364 lambda nu
    Z cos a) (1 + (1.038 T)^(-9/2))^(2/9), T = ((1 - g)/(1 + g))^(143/108)."""
    g = roller_gamma(geometry)
    T = 1.038 * ((1.0 - g) / (1.0 + g)) ** (143.0 / 108.0)
    zc = LAMBDA_NU_ROLLER * geometry.n_rollers * math.cos(math.radians(geometry.contact_angle))
    return C_row / (0.378 * zc) * (1.0 + T ** 4.5) ** (2.0 / 9.0), C_row / (0.364 * zc) * (1.0 + T ** -4.5) ** (2.0 / 9.0)


def roller_equivalent_load(Fr, Fa, alpha_deg: float, unit_rows: bool):
    """ISO 281 Table 8 P = X Fr + Y Fa (N) of a roller bearing: cylindrical (a = 0) P = Fr; tapered
    e = 1.5 tan a, single row X = 0.4, Y = 0.4 cot a above e (1, 0 below); a double row 0.67, 0.67 cot a
    above e (1, 0.45 cot a below)."""
    Fr, Fa = np.asarray(Fr, float), np.asarray(Fa, float)
    if alpha_deg == 0.0:
        return Fr
    t = math.tan(math.radians(alpha_deg))
    below = _at_most(Fr, Fa, 1.5 * t)
    if unit_rows:
        return np.where(below, Fr + 0.45 / t * Fa, 0.67 * Fr + 0.67 / t * Fa)
    return np.where(below, Fr, 0.4 * Fr + 0.4 / t * Fa)


def _at_most(Fr, Fa, e):
    """Fa/Fr <= e (ISO 281's choice of X, Y), as Fa <= e Fr: no division, so Fr = 0 (a pure axial load, above
    every e) needs no stand-in divisor. Fr, Fa >= 0 in N, e >= 0; arrays broadcast."""
    return Fa <= e * Fr


def roller_static_factors(alpha_deg: float, unit_rows: bool) -> tuple[float, float]:
    """ISO 76 (X0, Y0) of roller bearings: a = 0: (1, 0); else single row (0.5, 0.22 cot a), double (1, 0.44 cot a)."""
    if alpha_deg == 0.0:
        return 1.0, 0.0
    cot = 1.0 / math.tan(math.radians(alpha_deg))
    return (1.0, 0.44 * cot) if unit_rows else (0.5, 0.22 * cot)


# -- L10r from the load distribution ---------------------------------------------------------------

def combine(lives, exponent: float = ROW_EXPONENT):
    """The life of parts in series, (sum L^(-e))^(-1/e), along the last axis (inf lives drop out)."""
    lives = np.asarray(lives, float)
    with np.errstate(divide="ignore"):
        s = np.sum(lives ** -exponent, axis=-1)
        return np.where(s > 0, s ** (-1.0 / exponent), np.inf)


def combine_series(lives, slopes) -> float:
    """The 90 % life of parts in series with their own Weibull slopes (balls 10/9, rollers 9/8): the L with
    sum (L/L_i)^(e_i) = 1 (each part survives with exp(ln 0.9 (L/L_i)^e_i)); with one slope it is
    :func:`combine`. Million revolutions; inf lives drop out."""
    lives, slopes = np.asarray(lives, float), np.asarray(slopes, float)
    keep = np.isfinite(lives)
    lives, slopes = lives[keep], slopes[keep]
    if lives.size == 0:
        return math.inf
    if np.all(slopes == slopes[0]):
        return float(combine(lives, float(slopes[0])))
    lo, hi = math.log(lives.min()) - 10.0, math.log(lives.min())  # the sum is >= 1 at the weakest part's life
    for _ in range(200):  # bisection in log L: the sum rises monotonically with L
        mid = 0.5 * (lo + hi)
        if np.sum(np.exp(slopes * (mid - np.log(lives)))) > 1.0:
            hi = mid
        else:
            lo = mid
    return math.exp(0.5 * (lo + hi))


# -- ISO 281 equivalent loads ----------------------------------------------------------------------

def equivalent_load(Fr, Fa, alpha_deg: float, f0: float, C0r: float, unit_rows: bool):
    """ISO 281 P = X Fr + Y Fa (N) of a bearing at contact angle alpha (deg); ``unit_rows``: the
    double-row factors (a DB or DF pair as a unit); below 17.5 deg Y and e follow the relative axial load
    f0 Fa / C0r. Fr, Fa >= 0 in N (arrays broadcast)."""
    Fr, Fa = np.asarray(Fr, float), np.asarray(Fa, float)
    if alpha_deg < 17.5:  # the f0 Fa / C0r tables (0, 10, 15 deg; 5 deg as radial contact)
        key = 0 if alpha_deg < 7.5 else (10 if alpha_deg < 12.5 else 15)
        rel = np.clip(f0 * Fa / C0r, _RELATIVE_AXIAL[0], _RELATIVE_AXIAL[-1])
        e = np.interp(rel, _RELATIVE_AXIAL, _E_SMALL[key])
        if unit_rows:
            y_below, X, Ys = _Y_DOUBLE_SMALL[key]
            Yb, Ya = np.interp(rel, _RELATIVE_AXIAL, y_below), np.interp(rel, _RELATIVE_AXIAL, Ys)
            return np.where(_at_most(Fr, Fa, e), Fr + Yb * Fa, X * Fr + Ya * Fa)
        X, Ys = _Y_SINGLE_SMALL[key]
        return np.where(_at_most(Fr, Fa, e), Fr, X * Fr + np.interp(rel, _RELATIVE_AXIAL, Ys) * Fa)
    if unit_rows:  # a DB or DF pair, or a four-point row (its two contact pairs: docs/life.md)
        y_below, X, Y, e = _by_angle(_DOUBLE_FIXED, alpha_deg)
        return np.where(_at_most(Fr, Fa, e), Fr + y_below * Fa, X * Fr + Y * Fa)
    X, Y, e = _by_angle(_SINGLE_FIXED, alpha_deg)
    return np.where(_at_most(Fr, Fa, e), Fr, X * Fr + Y * Fa)


def iso_life(r, Fr, Fa):
    """ISO 281 (P, L10) of a bearing with ratings ``r`` (BearingRatings; its unit C) under radial and axial
    loads Fr, Fa >= 0 (N; arrays broadcast): P = X Fr + Y Fa in N, L10 = (C/P)^p in million revolutions (inf
    without load). The one formula of ``fb.rating_life`` and the maps' L10."""
    if r.rollers:
        P = roller_equivalent_load(Fr, Fa, r.contact_angle, r.double_row)
    else:
        P = equivalent_load(Fr, Fa, r.contact_angle, r.f0, r.C0, r.double_row)
    P = np.asarray(P, float)
    ratio = np.divide(r.C, P, out=np.full(P.shape, np.inf), where=P > 0)  # no load: an infinite life
    with np.errstate(over="ignore"):  # C/P beyond 1e102 (a load of ~1e-98 N): a life past float range is inf
        return P, ratio ** r.life_exponent


def static_equivalent_load(Fr, Fa, alpha_deg: float, unit_rows: bool, rollers: bool = False):
    """ISO 76 P_0 = max(X_0 Fr + Y_0 Fa, Fr) (N); deep groove X_0 = 0.6, Y_0 = 0.5; angular contact
    X_0 = 0.5 and Y_0 by angle; a double row X_0 = 1 and twice Y_0; roller rows
    :func:`roller_static_factors`."""
    Fr, Fa = np.asarray(Fr, float), np.asarray(Fa, float)
    X0, Y0 = roller_static_factors(alpha_deg, unit_rows) if rollers else static_factors(alpha_deg, unit_rows)
    return np.maximum(X0 * Fr + Y0 * Fa, Fr)


def static_factors(alpha_deg: float, unit_rows: bool) -> tuple[float, float]:
    """ISO 76 (X0, Y0): deep groove 0.6, 0.5; angular contact 0.5 and Y0 by angle; a double row 1 and 2 Y0."""
    if alpha_deg < 2.5:
        return 0.6, 0.5
    Y0 = _by_angle(_Y0_SINGLE, alpha_deg)
    return (1.0, 2.0 * Y0) if unit_rows else (0.5, Y0)


# -- the whole bearing ----------------------------------------------------------------------------

@dataclass(frozen=True)
class LifeSettings:
    """How life is computed: which ring rotates, the shaft speed for hours, and the optional ISO 281
    life-modification factor a_ISO (off unless ``kappa`` is given).

    rotating : {"inner", "outer"}
        The ring that rotates relative to the load (its contacts see the cubic-mean load).
    speed : float or None
        Shaft speed in rpm (> 0) for lives in hours.
    kappa : float or None
        Viscosity ratio kappa = nu/nu1 of the lubricant, in [0.1, 4] (ISO 281 clamps beyond).
    contamination : float
        Contamination factor e_C in [0, 1] (1: very clean).
    balls_at_speed : bool
        The displacement was solved with the high-speed model at ``speed`` (solve --speed): the races'
        ball loads then differ, and each ring's equivalent load comes from its own contacts (inner Q_i,
        outer Q_o, fastbearing.engine.high_speed).
    """

    rotating: str = "inner"
    speed: float | None = None
    kappa: float | None = None
    contamination: float = 1.0
    balls_at_speed: bool = False

    def __post_init__(self):
        validate.choice(self.rotating, "rotating", ROTATING)
        if self.speed is not None:
            object.__setattr__(self, "speed", validate.number(self.speed, "speed", low=0, low_open=True,
                                                              units="rpm"))
        if self.kappa is not None:
            object.__setattr__(self, "kappa", validate.number(self.kappa, "kappa", low=0.1, high=4.0))
        object.__setattr__(self, "contamination", validate.number(self.contamination, "contamination", low=0.0,
                                                                  high=1.0))
        if self.kappa is None and self.contamination != 1.0:  # e_C enters only a_ISO, which needs kappa
            raise validate.FieldError("contamination", "goes with kappa (e_C enters only a_ISO, which needs the "
                                      "viscosity ratio kappa in [0.1, 4])", self.contamination)


@dataclass(frozen=True)
class BearingRatings:
    """Everything life needs that does not depend on the load: per row C, C0, Q_ci, Q_ce, Z; the unit's
    C, C0, contact angle and whether ISO 281 treats it as a double row (DB, DF) or single rows (single,
    DT tandem: single-row factors)."""

    C_row: np.ndarray
    C0_row: np.ndarray
    f0: float
    Q_ci: np.ndarray
    Q_ce: np.ndarray
    n_balls: np.ndarray
    C: float | None
    C0: float | None
    contact_angle: float
    double_row: bool
    pitch_diameter: float
    notes: tuple = field(default_factory=tuple)
    element: str = "ball"
    slices: np.ndarray | None = None        # roller rows: laminae per roller
    slice_first: np.ndarray | None = None   # roller rows: where each row's slices start in the slice record
    four_point: bool = False                # one four-point row: its two contact pairs are ISO's two rows (i = 2)

    @property
    def rollers(self) -> bool:
        return self.element != "ball"

    @property
    def life_exponent(self) -> float:
        """ISO 281's p: 3 for balls, 10/3 for rollers."""
        return ROLLER_LIFE_EXPONENT if self.rollers else LIFE_EXPONENT

    @property
    def row_exponent(self) -> float:
        """The Weibull slope that combines rows and bearings: 10/9 for balls, 9/8 for rollers."""
        return ROLLER_ROW_EXPONENT if self.rollers else ROW_EXPONENT


#: Where a bearing's C and C0 come from, as every life output says it (:func:`rating_sources`).
CATALOGUE_C = "catalogue value: the bearing file's dynamic_load_rating"
CATALOGUE_C0 = "catalogue value: the bearing file's static_load_rating"
ISO_C = "ISO 281 formula from the geometry"
ISO_C0 = "ISO 76 formula from the geometry"


def rating_sources(bearing) -> dict:
    """{"C": ..., "C0": ...}: where :func:`ratings` takes the bearing's basic dynamic and static load ratings
    from: the catalogue values the bearing file gives (``dynamic_load_rating``, ``static_load_rating`` in
    ``[bearing.geometry]``, N), else ISO 281's and ISO 76's formulas from the geometry (ball or roller count,
    diameter, length, contact angle, pitch diameter). None for a bearing without geometry (no rating)."""
    g = getattr(bearing, "geometry", None)
    if g is None:
        return {"C": None, "C0": None}
    return {"C": CATALOGUE_C if g.dynamic_load_rating is not None else ISO_C,
            "C0": CATALOGUE_C0 if g.static_load_rating is not None else ISO_C0}


def ratings(bearing) -> BearingRatings:
    """The load ratings of a bearing with ``[bearing.geometry]``; ValueError naming what is missing."""
    g = getattr(bearing, "geometry", None)
    if g is None:
        raise ValueError("life needs the bearing's geometry ([bearing.geometry]: ball_diameter, pitch_diameter, "
                         "groove ratios), from which the load ratings and contact ratings follow; a bearing given "
                         "by model parameters (Kn, A0, R) alone has no rating")
    if g.element != "ball":
        return _roller_ratings(bearing, g)
    if bearing.roller_rows:
        raise ValueError("life needs one geometry for the whole bearing; ball and roller rows mixed in one "
                         "bearing have none (rate them as separate bearings)")
    if g.contact_angle > 45.0:
        raise ValueError(f"bearing.geometry.contact_angle: life covers radial and angular contact ball rows "
                         f"(contact angle <= 45 deg); thrust ball rows ({g.contact_angle:g} deg) are not rated yet")
    four_point = is_four_point(bearing)
    unit = bearing.arrangement in ("single", "DB", "DF", "DT")
    rows = 2 if four_point or (unit and bearing.arrangement != "single") else 1
    C_row, C0_row = row_ratings(g, rows)
    Qci, Qce = contact_ratings(g, C_row)
    n = bearing.n_rows
    C, C0 = (C_row * rows ** 0.7, C0_row * rows) if unit else (None, None)
    return BearingRatings(np.full(n, C_row), np.full(n, C0_row), _interp(gamma(g), F0_GAMMA, F0), np.full(n, Qci), np.full(n, Qce),
                          np.array([r.n_balls for r in bearing.rows], float), C, C0, g.contact_angle,
                          four_point or bearing.arrangement in ("DB", "DF"), g.pitch_diameter, four_point=four_point)


def is_four_point(bearing) -> bool:
    """True for a bearing of one four-point contact ball row (QJ type; held as its two contact pairs, rows +a0
    and -a0), which life rates as ISO 281's and ISO 76's double-row angular contact bearing (docs/life.md,
    "Four-point contact ball bearings"): i = 2 in C and C0, Table 3's double-row X, Y, e and ISO 76's
    X0 = 1, Y0 = 2 Y0(single row). Several four-point rows, or mixed with other rows, are no ISO unit: False,
    and their arrangement decides as for any other set of rows."""
    from ..model.four_point import ELEMENT

    return (bearing.arrangement == "single" and bearing.n_rows == 2
            and all(getattr(r, "element", None) == ELEMENT for r in bearing.rows))


def _roller_ratings(bearing, g) -> BearingRatings:
    unit = bearing.arrangement in ("single", "DB", "DF", "DT", "TDO", "TDI")
    rows = 1 if bearing.arrangement == "single" or not unit else 2
    C_row, C0_row = roller_row_ratings(g, rows)
    Qci, Qce = roller_contact_ratings(g, C_row)
    n = bearing.n_rows
    C, C0 = (C_row * rows ** (7.0 / 9.0), C0_row * rows) if unit else (None, None)
    per_row = [r.n_rollers * r.slices for _, r in bearing.roller_rows]
    return BearingRatings(np.full(n, C_row), np.full(n, C0_row), math.nan, np.full(n, Qci), np.full(n, Qce),
                          np.array([r.n_rollers for _, r in bearing.roller_rows], float), C, C0, g.contact_angle,
                          bearing.arrangement in ("DB", "DF", "TDO", "TDI"), g.pitch_diameter, element=g.element,
                          slices=np.array([r.slices for _, r in bearing.roller_rows], float),
                          slice_first=np.concatenate([[0], np.cumsum(per_row)[:-1]]).astype(float))


def life_table(r: BearingRatings, settings: LifeSettings) -> np.ndarray:
    """What a map's sweep reads (sweep.case_life, sweep.static_safety), per row: the contact ratings'
    powers (ball rows Q_ci^(-10/3), Q_ce^(-10/3); roller rows the laminae's q_ci^(-9/2), q_ce^(-9/2)), Z,
    inner-ring rotating (1/0), the bearing's ISO 76 X0, Y0, and for roller rows the laminae per roller
    and where the row's slices start in the kernel's slice record (0, 0 for ball rows)."""
    t = np.zeros((len(r.C_row), N_LIFE_COLUMNS))
    if r.rollers:
        ns = r.slices
        t[:, LIFE_CI] = (r.Q_ci * ns ** (-7.0 / 9.0)) ** -4.5
        t[:, LIFE_CE] = (r.Q_ce * ns ** (-7.0 / 9.0)) ** -4.5
        t[:, LIFE_SLICES], t[:, LIFE_FIRST] = ns, r.slice_first
        X0, Y0 = roller_static_factors(r.contact_angle, r.double_row)
    else:
        t[:, LIFE_CI] = r.Q_ci ** (-10.0 / 3.0)
        t[:, LIFE_CE] = r.Q_ce ** (-10.0 / 3.0)
        X0, Y0 = static_factors(r.contact_angle, r.double_row)
    t[:, LIFE_Z] = r.n_balls
    t[:, LIFE_INNER] = 1.0 if settings.rotating == "inner" else 0.0
    t[:, LIFE_X0], t[:, LIFE_Y0] = X0, Y0
    return t


#: ISO 281:2007 Eq. (15)-(20): a_ISO = 0.1 (1 - (c - d/kappa^m)^0.83 (e_C C_u/P)^w)^v; (c, d below
#: kappa 0.4, d above, w, v) for ball and radial roller bearings.
_A_ISO = {"ball": (2.5671, 2.2649, 1.9987, 1.0 / 3.0, -9.3), "roller": (1.5859, 1.3993, 1.2348, 0.4, -9.185)}


def a_iso(kappa: float, contamination: float, fatigue_limit: float, P, element: str = "ball") -> np.ndarray:
    """ISO 281:2007 Eq. (15)-(20): a_ISO of ball (``element`` "ball") or radial roller bearings from kappa
    (clamped to [0.1, 4]), e_C and C_u/P, capped at 50."""
    c, d_low, d, w, v = _A_ISO["ball" if element == "ball" else "roller"]
    k = min(max(kappa, 0.1), 4.0)
    if k < 0.4:
        inner = c - d_low / k ** 0.054
    elif k < 1.0:
        inner = c - d / k ** 0.19
    else:
        inner = c - d / k ** 0.071
    x = contamination * fatigue_limit / np.maximum(np.asarray(P, float), 1e-300)
    with np.errstate(invalid="ignore", over="ignore"):
        a = 0.1 * (1.0 - inner ** 0.83 * x ** w) ** v
    return np.where(np.isfinite(a) & (a > 0), np.minimum(a, 50.0), 50.0)


def fatigue_load_limit(C0: float, pitch_diameter: float, element: str = "ball") -> float:
    """ISO 281:2007 Annex B approximation of C_u (N): balls C0/27, times (100/Dpw)^0.5 above Dpw = 100 mm;
    rollers C0/8.2, times (100/Dpw)^0.3."""
    if element == "ball":
        return C0 / 27.0 * (1.0 if pitch_diameter <= 100.0 else (100.0 / pitch_diameter) ** 0.5)
    return C0 / 8.2 * (1.0 if pitch_diameter <= 100.0 else (100.0 / pitch_diameter) ** 0.3)


@dataclass(frozen=True)
class LifeResult:
    """Rating life at one operating point. Loads N; lives in million revolutions; hours when a speed is
    given; None where a quantity is not defined (see ``notes``)."""

    C: float | None
    C0: float | None
    P: float | None
    P0: float | None
    L10: float | None
    L10r: float
    L10r_row: list
    C_row: list
    Q_ci: list
    Q_ce: list
    Q_ei: list
    Q_ee: list
    static_safety: float | None
    max_contact_pressure: float | None
    a_iso: float | None
    L_nmr: float | None
    speed: float | None
    notes: list
    weibull_slope: float = ROW_EXPONENT
    C_source: str | None = None     # where C (and each row's C_row) comes from: rating_sources
    C0_source: str | None = None

    def hours(self, life):
        return None if life is None or self.speed is None else life * 1e6 / (60.0 * self.speed)

    def to_dict(self) -> dict:
        out = {k: getattr(self, k) for k in ("C", "C0", "P", "P0", "L10", "L10r", "L10r_row", "C_row", "Q_ci", "Q_ce",
                                              "Q_ei", "Q_ee", "static_safety", "max_contact_pressure", "a_iso",
                                              "L_nmr", "speed", "notes", "weibull_slope", "C_source",
                                              "C0_source")}
        out["L10_hours"], out["L10r_hours"] = self.hours(self.L10), self.hours(self.L10r)
        out["pressure_limit"] = ROLLER_PRESSURE_LIMIT if self.weibull_slope == ROLLER_ROW_EXPONENT else PRESSURE_LIMIT
        out["units"] = {"C": "N", "P": "N", "L10": "million revolutions", "L10_hours": "h", "speed": "rpm",
                        "max_contact_pressure": "N/mm^2", "Q_ci": "N"}
        return out


#: How closely a given q must carry the load for :func:`rating_life` to rate it: the largest scaled
#: residual (moments divided by the bearing's length scale) relative to the load's largest component. Any
#: q that a solve reports converged (default rtol 1e-10) passes; a q from another load does not.
Q_LOAD_RTOL = 1e-6


def rating_life(bearing, load, *, q=None, rotating: str = "inner", speed=None, kappa=None,
                contamination: float = 1.0, fixed=None) -> LifeResult:
    """Rating life of ``bearing`` under ``load`` (Fx, Fy, Fz, Mx, My in N, N*mm): ISO 281 C, P, L10,
    ISO/TS 16281 L10r per row and of the bearing (million revolutions; hours with ``speed``), static
    safety and, with ``kappa``, a_ISO and L_nmr. Needs ``[bearing.geometry]``; ValueError names any bad
    field.

    ``speed`` (rpm, > 0) is the shaft speed, one answer with ``fastbearing solve --life --speed``: ball
    rows are solved with the high-speed model at it (centrifugal force, gyroscopic moment), each ring
    rated from its own contacts; roller rows have no high-speed model, so they are solved quasi-statically
    (said in ``notes``). Lives in hours at that speed too. ``q`` (mm, rad) is the displacement solved at
    that speed; solved here when not given, and refused unless it is finite and carries ``load`` (within
    Q_LOAD_RTOL). ``fixed`` (as in :func:`fastbearing.solve`, e.g. {"bx": 0.0, "by": 0.0}) holds those
    degrees of freedom where the shaft holds them: ``load``'s entries there must be 0, and the life is that
    of the load the ring then carries (the reactions included)."""
    from ..api import _as_vector

    load = _as_vector(load, "load", "N, N*mm")
    settings = LifeSettings(rotating=rotating, speed=speed, kappa=kappa, contamination=contamination)
    ratings(bearing)
    notes = []
    model_speed = 0.0
    if settings.speed is not None:
        if bearing.roller_rows:
            notes.append("the high-speed model covers ball rows; roller rows are solved quasi-statically and "
                         "the speed gives the lives in hours")
        else:
            from ..model.bearing import check_speed, check_speed_model

            check_speed_model(bearing, check_speed(settings.speed))
            model_speed = settings.speed
            settings = replace(settings, balls_at_speed=True)
    if fixed is not None and q is not None:
        raise ValueError("give q or fixed, not both (q is the displacement of a solve; fixed asks for one)")
    if q is None:
        from ..api import solve

        result = solve(bearing, load, speed=model_speed, fixed=fixed)
        if not result.converged:
            raise ValueError(f"the load did not solve (status {result.status_name}); no load distribution, no life")
        q = result.q
        if result.fixed:
            load = result.f  # the reactions at the held degrees of freedom: the load the ring carries
    else:
        q = _checked_displacement(bearing, load, q, model_speed)
    out = life(bearing, load, q, settings)
    out.notes[:0] = notes
    return out


def _checked_displacement(bearing, load, q, speed: float) -> np.ndarray:
    """``q`` (mm, rad) if it is five finite numbers whose f(q) at ``speed`` (rpm) carries ``load`` within
    Q_LOAD_RTOL; ValueError naming q otherwise (a life from another load's distribution would look right)."""
    from ..api import _as_vector, stiffness

    q = _as_vector(q, "q", "mm, rad")
    f, _ = stiffness(bearing, q, speed=speed)
    D = np.array([1.0, 1.0, 1.0, 1.0 / bearing.length_scale, 1.0 / bearing.length_scale])
    scale = max(float(np.abs(np.asarray(load) * D).max()), 1.0)
    residual = float(np.abs((f - load) * D).max()) / scale
    if not residual <= Q_LOAD_RTOL:
        raise validate.FieldError("q", f"must carry the load (f(q) = load within {Q_LOAD_RTOL:g} of its largest "
                                  f"component{' at the given speed' if speed else ''}): f(q) = "
                                  f"{_plain(f)} N, N*mm, off by {residual:.3g}; leave q out to have it solved",
                                  show_value=False)
    return q


def _plain(values) -> str:
    """Numbers as plain floats for a message, not np.float64(...)."""
    return "(" + ", ".join(f"{float(v):.6g}" for v in values) + ")"


def life(bearing, load, q, settings: LifeSettings | None = None) -> LifeResult:
    """Rating life of ``bearing`` under ``load`` (Fx, Fy, Fz, Mx, My; N, N*mm) with the solved
    displacement ``q`` (mm, rad): ISO 281 L10 of the bearing as a unit (radial load hypot(Fx, Fy), axial
    |Fz|; moments are not in ISO 281's P) and ISO/TS 16281 L10r from the ball loads at q (moments,
    clearance, preload and every arrangement included). A bearing with [bearing.mounting] is taken as it runs
    at the speed ``q`` was solved at (``settings.speed`` with ``balls_at_speed``, else 0 rpm), as solve took it."""
    settings = settings or LifeSettings()
    # a mounted bearing: the operating one at the speed q was solved at (settings.speed with balls_at_speed)
    bearing = operating(bearing, settings.speed if settings.balls_at_speed and settings.speed else 0.0)
    r = ratings(bearing)
    if r.rollers:
        L_rows, Q_ei, Q_ee, pressure = _roller_lives(bearing, q, r, settings)
    else:
        L_rows, Q_ei, Q_ee, pressure = _ball_lives(bearing, q, r, settings)
    L10r = float(combine(L_rows, r.row_exponent))
    Fr, Fa = math.hypot(load[0], load[1]), abs(load[2])
    notes = []
    P = P0 = L10 = S0 = None
    if r.C is not None:
        P, L10 = (float(v) for v in iso_life(r, Fr, Fa))
        P0 = float(static_equivalent_load(Fr, Fa, r.contact_angle, r.double_row, r.rollers))
        S0 = r.C0 / P0 if P0 > 0 else math.inf
        if load[3] or load[4]:
            notes.append("ISO 281's P has no moment: L10 ignores Mx, My; L10r includes them")
        if r.rollers and r.contact_angle == 0.0 and Fa > 0:
            notes.append("ISO 281's P of a cylindrical roller bearing is Fr alone: L10 ignores Fz")
        if r.four_point:
            notes.append("a four-point row is rated as a double row of its two contact pairs (ISO 281 i = 2, "
                         "Table 3's double-row X, Y; ISO 76 X0 = 1): C = 2^0.7 C_row, C0 = 2 C0_row")
    else:
        notes.append(f"ISO 281 rates single rows and pairs as a unit, not a {bearing.arrangement} set: "
                     "L10 and S0 are given per row only through L10r")
    a = L_nmr = None
    if settings.kappa is not None:
        C0 = r.C0 if r.C0 is not None else float(r.C0_row.sum())
        C = r.C if r.C is not None else float(r.C_row.sum())
        Pref = C / L10r ** (1 / r.life_exponent) if math.isfinite(L10r) else 0.0
        a = float(a_iso(settings.kappa, settings.contamination, fatigue_load_limit(C0, r.pitch_diameter, r.element),
                        Pref, r.element))
        L_nmr = a * L10r
    return LifeResult(r.C, r.C0, P, P0, L10, L10r, L_rows.tolist(), r.C_row.tolist(), r.Q_ci.tolist(),
                      r.Q_ce.tolist(), Q_ei.tolist(), Q_ee.tolist(), S0,
                      None if pressure is None else float(pressure), a, L_nmr, settings.speed, notes,
                      r.row_exponent, **{f"{k}_source": v for k, v in rating_sources(bearing).items()})


def _ball_lives(bearing, q, r: BearingRatings, settings: LifeSettings):
    """Rows' L10r, equivalent contact loads Q_ei, Q_ee and the largest contact pressure, ball rows."""
    from .contacts import ball_contacts
    from ..engine.sweep import case_life

    at_speed = settings.balls_at_speed and bool(settings.speed)
    contacts = ball_contacts(bearing, q, settings.speed if at_speed else 0.0)  # one evaluation: loads, pressures
    inner = outer = contacts.load
    if at_speed:  # each ring its own contacts: the centrifugal force loads the outer race more
        inner, outer = contacts.inner_load, contacts.outer_load
    rows = bearing.ball_table()[ROW].astype(np.int64)
    # the life itself by the maps' one implementation (sweep.case_life), from each ring's own contacts
    L_rows = np.empty(bearing.n_rows)
    case_life(np.ascontiguousarray(inner), np.ascontiguousarray(outer) if at_speed else None, rows,
              life_table(r, settings), np.empty((bearing.n_rows, 2)), L_rows)
    # the equivalent contact loads, for the report
    rotating, standing = (inner, outer) if settings.rotating == "inner" else (outer, inner)
    cube = np.bincount(rows, rotating ** 3, minlength=bearing.n_rows)
    ten = np.bincount(rows, standing ** (10.0 / 3.0), minlength=bearing.n_rows)
    mean3, mean10 = (cube / r.n_balls) ** (1 / 3), (ten / r.n_balls) ** 0.3
    Q_ei, Q_ee = (mean3, mean10) if settings.rotating == "inner" else (mean10, mean3)
    pressure = contacts.max_pressure_per_row()
    return L_rows, Q_ei, Q_ee, None if pressure is None else pressure.max()


def _roller_lives(bearing, q, r: BearingRatings, settings: LifeSettings):
    """Rows' L10r from the slice loads (ISO/TS 16281 sliced), the whole rollers' equivalent loads (the
    4th- and 9/2-power means of the roller loads) and the largest line-contact pressure."""
    from .contacts import rollers_from_slices, slice_loads
    from ..engine.sweep import roller_case_life

    roller_loads, per_row = slice_loads(bearing, q)  # one kernel evaluation: slice loads and pressures
    # the life by the maps' one implementation (sweep.roller_case_life), from a record laid out as the
    # kernel's: the elements, then every slice row by row, roller by roller
    record = np.concatenate([np.zeros(bearing.n_elements), *(loads.ravel() for loads in per_row)])
    L_rows = np.empty(bearing.n_rows)
    roller_case_life(record, bearing.n_elements, life_table(r, settings), L_rows)
    totals = [loads.sum(axis=1) for loads in per_row]
    mean4 = np.array([np.mean(t ** 4) ** 0.25 for t in totals])
    mean45 = np.array([np.mean(t ** 4.5) ** (1 / 4.5) for t in totals])
    Q_ei, Q_ee = (mean4, mean45) if settings.rotating == "inner" else (mean45, mean4)
    contacts = rollers_from_slices(bearing, roller_loads, per_row)
    pressure = max(float(contacts.inner_max_pressure.max()), float(contacts.outer_max_pressure.max()))
    return L_rows, Q_ei, Q_ee, pressure
