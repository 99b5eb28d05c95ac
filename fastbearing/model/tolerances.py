"""Fit and ring tolerance tables: ISO 286-2 limit deviations of shaft and housing seats, the
ISO 492 Normal tolerance class of radial bearing rings, and the ISO 5753-1 radial internal
clearance groups of deep-groove ball bearings.

Units: the tables hold micrometres, as the standards and catalogues print them; every lookup
returns millimetres, the package's unit. A size range is "over a incl. b" as in all three
standards: a nominal size of exactly 30 mm belongs to "over 18 incl. 30", 30.001 mm to the next
range. Values are deviations from the nominal size (upper, lower) or clearance limits (min, max).

Sources (each table says more where it is defined):

- ISO 286-1:2010 standard tolerance grades (Table 1) and fundamental deviations (Tables 2 and 3),
  from which the ISO 286-2 classes are built exactly as ISO 286-2 builds its tables;
  the j and J classes are not formula-based and are taken from the published ISO 286-2 tables.
- ISO 492:2014 Normal class, as reproduced in NSK CAT. E1102m Table 8.2 and NTN CAT. 2202
  Table 5.1 ("class 0"), the SKF catalogue "Normal tolerances" table and maker sheets.
- ISO 5753-1:2009 Table 1 (deep-groove ball bearings), as reproduced in NTN "Ball and Roller
  Bearings" pp. A-58/A-59 and NSK CAT. E1102m Table 9.9.

Leaf module: imports only numpy and :mod:`fastbearing.validate`.
"""

from __future__ import annotations

import numpy as np

from fastbearing import validate

# --------------------------------------------------------------------------------------------
# ISO 286: size steps, standard tolerance grades, fundamental deviations (micrometres)
# --------------------------------------------------------------------------------------------

#: ISO 286 main size steps (mm); row i is "over STEPS[i] incl. STEPS[i+1]". For the classes
#: held here the intermediate steps (10-14/14-18, ..., 450-500) carry the same deviations as
#: their main step: ISO 286-1 subdivides only for the fundamental deviations a-c, r-zc and
#: A-C, R-ZC (and p-zc shafts / P-ZC holes above IT7, which are not held), so main steps suffice.
ISO286_STEPS_MM = (3.0, 6.0, 10.0, 18.0, 30.0, 50.0, 80.0, 120.0, 180.0, 250.0, 315.0, 400.0, 500.0)

# Standard tolerance grades, ISO 286-1:2010 Table 1, um, one value per main step above.
# Cross-checked against the h5-h8 columns of the BIG DAISHOWA shaft table (catalog p. 139).
_IT = {
    5: (5, 6, 8, 9, 11, 13, 15, 18, 20, 23, 25, 27),
    6: (8, 9, 11, 13, 16, 19, 22, 25, 29, 32, 36, 40),
    7: (12, 15, 18, 21, 25, 30, 35, 40, 46, 52, 57, 63),
    8: (18, 22, 27, 33, 39, 46, 54, 63, 72, 81, 89, 97),
}

# Shaft fundamental (lower) deviations ei, ISO 286-1:2010 Table 3, um. Read in "Machine Drawing"
# (Narayana et al.) Table 15.2 (issuhub pp. 238-239: k to 500 mm, m, n, p to 180 mm) and, above
# 180 mm, as the mirrored hole deviations of its Table 15.3 (pp. 242, 244: M -17 -20 -21 -23,
# N -31 -34 -37 -40, P -50 -56 -62 -68, each + Delta), which ISO 286-1 defines as -ei.
_EI_K = (1, 1, 1, 2, 2, 2, 3, 3, 4, 4, 4, 5)            # k, grades IT4 to IT7
_EI_M = (4, 6, 7, 8, 9, 11, 13, 15, 17, 20, 21, 23)     # m, all grades
_EI_N = (8, 10, 12, 15, 17, 20, 23, 27, 31, 34, 37, 40)  # n, all grades
_EI_P = (12, 15, 18, 22, 26, 32, 37, 43, 50, 56, 62, 68)  # p, all grades
# j for grades IT5 and IT6 (the same ei for both): a tabulated value, not a formula. ISO 286-1
# Table 3 column "j, IT5 and IT6"; read in the SKF j5/j6 shaft table (3-250 mm), the gbbco.cn
# j5/j6 fit table (3-120 mm) and "Machine Drawing" Table 15.2 (issuhub p. 238, 180-500 mm).
_EI_J56 = (-2, -2, -3, -4, -5, -7, -9, -11, -13, -16, -18, -20)

# Hole fundamental (lower) deviation EI of G, ISO 286-1 Table 2 (the mirror of g's es), um;
# G7 read in the Miki Pulley JIS B 0401 hole table (3-315 mm), G in "Machine Drawing" Table 15.3
# (120-500 mm).
_EI_G = (4, 5, 6, 7, 9, 10, 12, 14, 15, 17, 18, 20)
# Upper deviation ES of J7: tabulated in ISO 286-1 Table 2 (J column), not formula-based. Read in
# the SKF housing table (J7, 6-250 mm), the DME "Tables for Determining Metric Tolerances" Table 6
# (3-6 mm) and "Machine Drawing" Table 15.3 (issuhub p. 242: J7 +26 +30 +36 +39 +43, 120-500 mm).
_ES_J7 = (6, 8, 10, 12, 14, 18, 22, 26, 30, 36, 39, 43)


def _shaft(ei, grade):
    """(es, ei) rows: es = ei + IT, ISO 286-1 clause 5 (lower deviation is the fundamental one)."""
    return np.array([(e + it, e) for e, it in zip(ei, _IT[grade])], dtype=float)


def _symmetric(grade):
    """js/JS: +-IT/2, unrounded, as the ISO 286-2 tables print them (e.g. JS7 18-30 = +-10.5)."""
    return np.array([(it / 2.0, -it / 2.0) for it in _IT[grade]], dtype=float)


def _hole_delta(es_shaft_ei, grade):
    """K, M, N up to IT8 and P..ZC up to IT7: ES = -ei(same-letter shaft) + Delta, with
    Delta = IT(grade) - IT(grade - 1) (ISO 286-1:2010 Table 2, the "Delta" rule); EI = ES - IT."""
    rows = []
    for ei, it, it_below in zip(es_shaft_ei, _IT[grade], _IT[grade - 1]):
        es = -ei + (it - it_below)
        rows.append((es, es - it))
    return np.array(rows, dtype=float)


#: Shaft classes: (upper es, lower ei) in um per ISO286_STEPS_MM row.
SHAFT_DEVIATIONS_UM = {
    "j5": _shaft(_EI_J56, 5),
    "j6": _shaft(_EI_J56, 6),
    "js5": _symmetric(5),
    "js6": _symmetric(6),
    "k5": _shaft(_EI_K, 5),
    "k6": _shaft(_EI_K, 6),
    "m5": _shaft(_EI_M, 5),
    "m6": _shaft(_EI_M, 6),
    "n6": _shaft(_EI_N, 6),
    "p6": _shaft(_EI_P, 6),
}

#: Housing (hole) classes: (upper ES, lower EI) in um per ISO286_STEPS_MM row.
HOUSING_DEVIATIONS_UM = {
    "G7": np.array([(e + it, e) for e, it in zip(_EI_G, _IT[7])], dtype=float),
    "H7": np.array([(it, 0) for it in _IT[7]], dtype=float),
    "H8": np.array([(it, 0) for it in _IT[8]], dtype=float),
    "J7": np.array([(es, es - it) for es, it in zip(_ES_J7, _IT[7])], dtype=float),
    "JS7": _symmetric(7),
    "K7": _hole_delta(_EI_K, 7),
    "M7": _hole_delta(_EI_M, 7),
    "N7": _hole_delta(_EI_N, 7),
    "P7": _hole_delta(_EI_P, 7),
}

for _table in (*SHAFT_DEVIATIONS_UM.values(), *HOUSING_DEVIATIONS_UM.values()):
    _table.setflags(write=False)  # shared module data: a caller must not edit the standard

SHAFT_FITS = tuple(SHAFT_DEVIATIONS_UM)
HOUSING_FITS = tuple(HOUSING_DEVIATIONS_UM)

# --------------------------------------------------------------------------------------------
# ISO 492 Normal tolerance class, radial bearings except tapered roller bearings (micrometres)
# --------------------------------------------------------------------------------------------

#: Bore d steps (mm) for the inner ring's mean bore deviation; row i is "over [i] incl. [i+1]".
BORE_STEPS_MM = (2.5, 10.0, 18.0, 30.0, 50.0, 80.0, 120.0, 180.0, 250.0, 315.0, 400.0, 500.0, 630.0)
# Delta_dmp lower limit (the upper limit is 0), um. ISO 492 Normal class; read in NTN CAT. 2202
# Table 5.1 (class 0: -8 -8 -8 -10 -12 -15 -20 -25 -25 -30 -35 -40 -45 -50, the 120-150 and 150-180
# rows being equal), NSK CAT. E1102m Table 8.2.1, gld-bearing.com (to 250), SKF "Normal tolerances".
_BORE_LOWER_UM = (-8, -8, -10, -12, -15, -20, -25, -30, -35, -40, -45, -50)

#: Outside diameter D steps (mm) for the outer ring's mean OD deviation.
OD_STEPS_MM = (6.0, 18.0, 30.0, 50.0, 80.0, 120.0, 150.0, 180.0, 250.0, 315.0, 400.0, 500.0, 630.0)
# Delta_Dmp lower limit (upper 0), um. ISO 492 Normal class; read in the Rajkot (SRS) deep-groove
# Normal-class table (18-400 mm), consbrgs.com ABEC-1 table in inches (6-630 mm: .0003 .00035 .0004
# .0005 .0006 .0007 .0010 .0012 .0014 .0016 .0018 .0020 in), NSK CAT. E1102m Table 8.5.2 (6-50 mm).
_OD_LOWER_UM = (-8, -9, -11, -13, -15, -18, -25, -30, -35, -40, -45, -50)

# --------------------------------------------------------------------------------------------
# ISO 5753-1 radial internal clearance of deep-groove ball bearings (micrometres)
# --------------------------------------------------------------------------------------------

CLEARANCE_GROUPS = ("C2", "CN", "C3", "C4", "C5")
#: Bore d steps (mm) of ISO 5753-1 Table 1; row i is "over [i] incl. [i+1]".
CLEARANCE_STEPS_MM = (2.5, 6.0, 10.0, 18.0, 24.0, 30.0, 40.0, 50.0, 65.0, 80.0, 100.0,
                      120.0, 140.0, 160.0, 180.0, 200.0, 225.0, 250.0, 280.0, 315.0, 355.0,
                      400.0, 450.0, 500.0, 560.0, 630.0)
# (min, max) per group C2, CN, C3, C4, C5; None where the standard defines no group.
# Read in NTN "Ball and Roller Bearings" pp., radial internal clearance of deep-groove
# ball bearings (all rows, 2.5-630 mm), and cross-checked up to 100 mm with NSK CAT. E1102m
# Table 9.9 (p. A94; it merges 2.5-10 into one "10 only" row, which omits that C4/C5 start at 6),
# shjfbearing.com and ktaiballbearing.com; CN 100-120 also with tritanpt.com. The 24-30 row is
# the research file's NSK reading. (bmzbearings.com prints C2 0-8 up to 18 mm: a misprint, NTN and
# NSK both give 0-7, 0-7, 0-9.)
_CLEARANCE_UM = (
    ((0, 7), (2, 13), (8, 23), None, None),            # 2.5-6
    ((0, 7), (2, 13), (8, 23), (14, 29), (20, 37)),    # 6-10
    ((0, 9), (3, 18), (11, 25), (18, 33), (25, 45)),   # 10-18
    ((0, 10), (5, 20), (13, 28), (20, 36), (28, 48)),  # 18-24
    ((1, 11), (5, 20), (13, 28), (23, 41), (30, 53)),  # 24-30
    ((1, 11), (6, 20), (15, 33), (28, 46), (40, 64)),  # 30-40
    ((1, 11), (6, 23), (18, 36), (30, 51), (45, 73)),  # 40-50
    ((1, 15), (8, 28), (23, 43), (38, 61), (55, 90)),  # 50-65
    ((1, 15), (10, 30), (25, 51), (46, 71), (65, 105)),  # 65-80
    ((1, 18), (12, 36), (30, 58), (53, 84), (75, 120)),  # 80-100
    ((2, 20), (15, 41), (36, 66), (61, 97), (90, 140)),  # 100-120
    ((2, 23), (18, 48), (41, 81), (71, 114), (105, 160)),  # 120-140
    ((2, 23), (18, 53), (46, 91), (81, 130), (120, 180)),  # 140-160
    ((2, 25), (20, 61), (53, 102), (91, 147), (135, 200)),  # 160-180
    ((2, 30), (25, 71), (63, 117), (107, 163), (150, 230)),  # 180-200
    ((2, 35), (25, 85), (75, 140), (125, 195), (175, 265)),  # 200-225
    ((2, 40), (30, 95), (85, 160), (145, 225), (205, 300)),  # 225-250
    ((2, 45), (35, 105), (90, 170), (155, 245), (225, 340)),  # 250-280
    ((2, 55), (40, 115), (100, 190), (175, 270), (245, 370)),  # 280-315
    ((3, 60), (45, 125), (110, 210), (195, 300), (275, 410)),  # 315-355
    ((3, 70), (55, 145), (130, 240), (225, 340), (315, 460)),  # 355-400
    ((3, 80), (60, 170), (150, 270), (250, 380), (350, 510)),  # 400-450
    ((3, 90), (70, 190), (170, 300), (280, 420), (390, 570)),  # 450-500
    ((10, 100), (80, 210), (190, 330), (310, 470), (440, 630)),  # 500-560
    ((10, 110), (90, 230), (210, 360), (340, 520), (490, 690)),  # 560-630
)


# --------------------------------------------------------------------------------------------
# Lookups (millimetres in, millimetres out)
# --------------------------------------------------------------------------------------------

def _row(steps, size, field, standard) -> int:
    """Index of the "over steps[i] incl. steps[i+1]" row holding ``size``; refuses sizes outside."""
    x = validate.number(size, field, low=steps[0], high=steps[-1], low_open=True,
                        units=f"mm ({standard} table range)")
    # side="left": a size equal to a step's upper bound stays in that step ("incl.")
    return int(np.searchsorted(steps, x, side="left")) - 1


def _fit(fit, field, table, other, kind) -> np.ndarray:
    if isinstance(fit, str) and fit in table:
        return table[fit]
    hint = ""
    if isinstance(fit, str) and fit in other:
        hint = f" ({fit!r} is a {'housing' if kind == 'shaft' else 'shaft'} class: ISO 286 writes " \
               f"shafts in lower case, holes in upper case)"
    raise validate.FieldError(field, f"must be an ISO 286 {kind} class held here, one of {list(table)}{hint}", fit)


def _mm(pair) -> tuple[float, float]:
    return float(pair[0]) / 1000.0, float(pair[1]) / 1000.0


def _shaft_um(fit, diameter_mm, fit_field, size_field) -> np.ndarray:
    table = _fit(fit, fit_field, SHAFT_DEVIATIONS_UM, HOUSING_DEVIATIONS_UM, "shaft")
    return table[_row(ISO286_STEPS_MM, diameter_mm, size_field, "ISO 286")]


def _housing_um(fit, diameter_mm, fit_field, size_field) -> np.ndarray:
    table = _fit(fit, fit_field, HOUSING_DEVIATIONS_UM, SHAFT_DEVIATIONS_UM, "housing")
    return table[_row(ISO286_STEPS_MM, diameter_mm, size_field, "ISO 286")]


def _bore_um(d_mm, field) -> tuple[float, float]:
    return 0.0, float(_BORE_LOWER_UM[_row(BORE_STEPS_MM, d_mm, field, "ISO 492 Normal")])


def _od_um(D_mm, field) -> tuple[float, float]:
    return 0.0, float(_OD_LOWER_UM[_row(OD_STEPS_MM, D_mm, field, "ISO 492 Normal")])


def shaft_deviation(fit: str, diameter_mm, *, fit_field: str = "shaft_fit",
                    size_field: str = "diameter") -> tuple[float, float]:
    """(upper, lower) deviation in mm of ISO 286-2 shaft class ``fit`` at nominal ``diameter_mm``.

    ``fit`` is one of :data:`SHAFT_FITS`; the diameter must be over 3 and at most 500 mm.
    ``fit_field`` and ``size_field`` name the inputs in the error a bad value raises.
    """
    return _mm(_shaft_um(fit, diameter_mm, fit_field, size_field))


def housing_deviation(fit: str, diameter_mm, *, fit_field: str = "housing_fit",
                      size_field: str = "diameter") -> tuple[float, float]:
    """(upper, lower) deviation in mm of ISO 286-2 hole class ``fit`` at nominal ``diameter_mm``.

    ``fit`` is one of :data:`HOUSING_FITS`; the diameter must be over 3 and at most 500 mm.
    """
    return _mm(_housing_um(fit, diameter_mm, fit_field, size_field))


def bore_tolerance(d_mm, *, field: str = "bore") -> tuple[float, float]:
    """(upper, lower) mean bore deviation Delta_dmp in mm, ISO 492 Normal class, d over 2.5 incl. 630."""
    return _mm(_bore_um(d_mm, field))


def outer_diameter_tolerance(D_mm, *, field: str = "outer_diameter") -> tuple[float, float]:
    """(upper, lower) mean outside-diameter deviation Delta_Dmp in mm, ISO 492 Normal class,
    D over 6 incl. 630."""
    return _mm(_od_um(D_mm, field))


def interference_range(shaft_fit: str, d_mm, *, fit_field: str = "shaft_fit",
                       size_field: str = "bore") -> tuple[float, float]:
    """(min, max) diametral interference in mm of an ISO 286 shaft class on a Normal-class bore.

    Positive is an interference, negative a clearance: min = shaft lower - bore upper,
    max = shaft upper - bore lower. E.g. k5 on a 25 mm bore: (0.002, 0.021).
    """
    s_up, s_lo = _shaft_um(shaft_fit, d_mm, fit_field, size_field)
    b_up, b_lo = _bore_um(d_mm, size_field)
    return _mm((s_lo - b_up, s_up - b_lo))  # differences taken in um: exact on the 0.5 um grid


def housing_interference_range(housing_fit: str, D_mm, *, fit_field: str = "housing_fit",
                               size_field: str = "outer_diameter") -> tuple[float, float]:
    """(min, max) diametral interference in mm of a Normal-class ring OD in an ISO 286 housing class.

    Positive is an interference (the ring OD larger than the housing bore):
    min = OD lower - housing upper, max = OD upper - housing lower.
    """
    h_up, h_lo = _housing_um(housing_fit, D_mm, fit_field, size_field)
    o_up, o_lo = _od_um(D_mm, size_field)
    return _mm((o_lo - h_up, o_up - h_lo))


def clearance_group(group: str, d_mm, *, field: str = "diametral_clearance",
                    size_field: str = "bore") -> tuple[float, float]:
    """(min, max) radial internal (diametral) clearance in mm of an unmounted deep-groove ball
    bearing of ISO 5753-1 group ``group`` (C2, CN, C3, C4, C5) and bore ``d_mm`` (over 2.5 incl. 630)."""
    if not isinstance(group, str) or group not in CLEARANCE_GROUPS:
        raise validate.FieldError(field, f"must be an ISO 5753-1 clearance group, one of {list(CLEARANCE_GROUPS)}",
                                  group)
    i = _row(CLEARANCE_STEPS_MM, d_mm, size_field, "ISO 5753-1 deep-groove ball bearing")
    limits = _CLEARANCE_UM[i][CLEARANCE_GROUPS.index(group)]
    if limits is None:
        lo, hi = CLEARANCE_STEPS_MM[i], CLEARANCE_STEPS_MM[i + 1]
        raise validate.FieldError(field, f"{group} is not defined by ISO 5753-1 for bores over {lo:g} incl. "
                                         f"{hi:g} mm; groups there: "
                                         f"{[g for g, v in zip(CLEARANCE_GROUPS, _CLEARANCE_UM[i]) if v]}", group)
    return _mm(limits)
