"""Text reports of a bearing: its derived model parameters, for `fastbearing bearing FILE` and for Python
(``fb.bearing_report(bearing)``), and its fault frequencies at a shaft speed (`fastbearing bearing FILE
--speed RPM`, :func:`fault_frequency_report`).

Units: lengths mm, angles deg (and rad where said), Hertz constants N/mm^n, moduli N/mm^2, speeds rpm,
loads N and N*mm, frequencies Hz (orders: multiples of the shaft frequency).
"""

from __future__ import annotations

import math

import numpy as np

from .. import status as status_codes
from .. import validate
from ..analysis.faults import NAMES as FAULT_NAMES
from ..analysis.faults import fault_frequencies
from ..model.bearing import MAX_SPEED, check_speed_model, speed_limit
from ..model.four_point import ELEMENT as FOUR_POINT
from ..model.geometry import load_centre_spread
from ..model.mounted import operating_bearing

#: What each fault frequency is, in words (the text report's second column).
FAULT_WORDS = {"FTF": "cage (fundamental train)", "BPFO": "ball pass, outer race", "BPFI": "ball pass, inner race",
               "BSF": "ball spin", "ball_defect": "ball defect (2 BSF)"}


def bearing_report(bearing, speed=None) -> dict:
    """A bearing's derived model parameters, JSON-ready (what `fastbearing bearing FILE --json` prints): every
    row's (lengths mm, angles deg and rad, Kn N/mm^n; a four-point row as its two contact pairs, each with
    ``element`` "four_point_ball" and ``pair`` +1 or -1, and ``four_point_rows`` the pairs' row indices), the
    load-centre spread of a double row (mm), the catalogue geometry's and both race contacts' where the
    bearing has one, with its load ratings (``load_ratings``: C, C0, C_row, C0_row in N and where C and C0
    come from; None where life does not rate it), and its speed limit (rpm) where it can run at speed."""
    rows = [r.report() for r in bearing.rows]  # each element kind reports its own row
    out = {"name": bearing.name, "arrangement": bearing.arrangement, "rows": rows}
    pairs = [i for i, r in enumerate(rows) if r.get("element") == FOUR_POINT and r["pair"] == 1]
    if pairs:  # each four-point row is held as its two contact pairs, +a0 then -a0
        out["four_point_rows"] = [[i, i + 1] for i in pairs]
    if bearing.arrangement in ("DB", "DF", "DT") and not bearing.roller_rows:
        r = bearing.rows[1]
        out["load_centre_spread"] = load_centre_spread(bearing.arrangement, r.axial_offset, r.pitch_radius,
                                                       math.radians(r.contact_angle))
    g = bearing.geometry
    if g is not None and g.element != "ball":
        out["roller_geometry"] = {
            "element": g.element, "n_rollers": g.n_rollers, "roller_diameter": g.roller_diameter,
            "roller_effective_length": g.roller_effective_length, "pitch_diameter": g.pitch_diameter,
            "contact_angle_deg": g.contact_angle, "diametral_clearance": g.diametral_clearance,
            "row_spacing": g.row_spacing, "roller_material": vars(g.roller_material),
            "ring_material": vars(g.ring_material), "reduced_modulus": g.reduced_modulus,
            "hertz_constant": g.hertz_constant}
    elif g is not None:
        inner, outer = g.contacts()
        out["geometry"] = {
            "n_balls": g.n_balls, "ball_diameter": g.ball_diameter, "pitch_diameter": g.pitch_diameter,
            "inner_groove_ratio": g.inner_groove_ratio, "outer_groove_ratio": g.outer_groove_ratio,
            "contact_angle_deg": g.contact_angle, "diametral_clearance": g.diametral_clearance,
            "row_spacing": g.row_spacing, "ellipticity_method": g.ellipticity,
            "ball_material": vars(g.ball_material), "ring_material": vars(g.ring_material),
            "reduced_modulus": g.reduced_modulus, "contact_pressure_limit": g.contact_pressure_limit,
            "contacts": {side: {"hertz_constant": c.constant, "ellipticity": c.ellipticity,
                                "curvature_sum": c.curvature_sum, "curvature_ratio": max(c.curvature_x, c.curvature_y)
                                / min(c.curvature_x, c.curvature_y)}
                         for side, c in (("inner", inner), ("outer", outer))}}
    if g is not None:
        out["load_ratings"] = _load_ratings(bearing)
    try:
        check_speed_model(bearing)
    except ValueError:  # roller rows, or no geometry: no high-speed model, no speed limit
        pass
    else:
        out["speed_limit"] = speed_limit(bearing)
    if getattr(bearing, "mounting", None) is not None:
        # [bearing.mounting] (or a clearance group or range): the clearance budget at ``speed`` rpm (default 0)
        _, budget = operating_bearing(bearing, 0.0 if speed is None else speed)
        out["mounting"] = budget
    return out


def _load_ratings(bearing) -> dict | None:
    """The basic load ratings life uses (N): the bearing's C and C0 as a unit (None for a set ISO does not rate
    as one), one row's C_row and C0_row, and where C and C0 come from (catalogue value or ISO formula,
    :func:`fastbearing.analysis.life.rating_sources`); None where the bearing is not rated (life refuses it)."""
    from ..analysis.life import rating_sources, ratings

    try:
        r = ratings(bearing)
    except ValueError:
        return None
    sources = rating_sources(bearing)
    return {"C": r.C, "C0": r.C0, "C_row": float(r.C_row[0]), "C0_row": float(r.C0_row[0]),
            "C_source": sources["C"], "C0_source": sources["C0"], "units": "N"}


def _load_ratings_text(lr: dict) -> list[str]:
    if lr["C"] is not None:
        return [f"load ratings: C = {lr['C']:.6g} N ({lr['C_source']}), C0 = {lr['C0']:.6g} N ({lr['C0_source']})"]
    return [f"load ratings (rows, not rated as one unit): C_row = {lr['C_row']:.6g} N ({lr['C_source']}), "
            f"C0_row = {lr['C0_row']:.6g} N ({lr['C0_source']})"]


def bearing_report_text(rep: dict, bearing) -> str:
    """The report of :func:`bearing_report` as `fastbearing bearing FILE` prints it (units beside every value)."""
    pairs = sum(r.get("element") == FOUR_POINT for r in rep["rows"])
    if pairs:  # a four-point row is held as its two contact pairs: say so, and what the rows below are
        held = "; ".join(f"rows {a} (+a0) and {b} (-a0)" for a, b in rep["four_point_rows"])
        lines = [f"{rep['name'] or 'bearing'}: {rep['arrangement']}, {len(rep['rows']) - pairs // 2} row(s), "
                 f"{pairs // 2} of them four-point contact ball, each held as its two contact pairs: {held} below"]
    else:
        lines = [f"{rep['name'] or 'bearing'}: {rep['arrangement']}, {len(rep['rows'])} row(s)"]
    rg = rep.get("roller_geometry")
    if rg is not None:
        lines += ["catalogue geometry:",
                  f"  rollers per row      Z  = {rg['n_rollers']} ({rg['element'].replace('_', ' ')}s)",
                  f"  roller diameter      Dw = {rg['roller_diameter']:g} mm",
                  f"  effective length     l  = {rg['roller_effective_length']:g} mm",
                  f"  pitch diameter       dm = {rg['pitch_diameter']:g} mm",
                  f"  contact angle        a  = {rg['contact_angle_deg']:g} deg",
                  f"  diametral clearance  Pd = {rg['diametral_clearance']:g} mm",
                  f"  reduced modulus      E' = {rg['reduced_modulus']:.6g} N/mm^2",
                  f"  line contact (Palmgren, both raceways in series): K = 37 310 l^(8/9) E'/E'_steel = "
                  f"{rg['hertz_constant']:.6g} N/mm^(10/9)"]
    g = rep.get("geometry")
    if g is not None:
        geo = bearing.geometry
        lines += ["catalogue geometry:",
                  f"  balls per row        Z  = {g['n_balls']}",
                  f"  ball diameter        D  = {g['ball_diameter']:g} mm",
                  f"  pitch diameter       dm = {g['pitch_diameter']:g} mm",
                  f"  groove ratios        fi = {g['inner_groove_ratio']:g}, fo = {g['outer_groove_ratio']:g}",
                  f"  contact angle        a0 = {g['contact_angle_deg']:g} deg"
                  + (" (each contact pair of the four-point row: +a0 and -a0)" if pairs else ""),
                  f"  diametral clearance  Pd = {g['diametral_clearance']:g} mm"]
        if g["row_spacing"] is not None:
            lines.append(f"  row spacing          2e = {g['row_spacing']:g} mm")
        for body in ("ball", "ring"):
            m = g[f"{body}_material"]
            lines.append(f"  {body} material        {m['name']}: E = {m['youngs_modulus']:g} N/mm^2, "
                         f"nu = {m['poisson_ratio']:g}")
        lines.append(f"  reduced modulus      E' = {g['reduced_modulus']:.6g} N/mm^2; ellipticity: {geo.ellipticity}")
        for side in ("inner", "outer"):
            c = g["contacts"][side]
            lines.append(f"  {side} contact        K = {c['hertz_constant']:.6g} N/mm^1.5, k = a/b = "
                         f"{c['ellipticity']:.4g}, Ry/Rx = {c['curvature_ratio']:.4g}, "
                         f"sum rho = {c['curvature_sum']:.5g} 1/mm")
    if rep.get("load_ratings"):
        lines += _load_ratings_text(rep["load_ratings"])
    lines.append("model parameters:")
    for i, r in enumerate(rep["rows"]):
        if "element" in r and r["element"] != FOUR_POINT:  # a roller row
            lines += [f"  row {i}: {r['element'].replace('_', ' ')}s, z = {r['axial_offset']:g} mm, contact direction "
                      f"{r['contact_direction']:+d}, Z = {r['n_rollers']}",
                      f"    line-contact constant      K  = {r['hertz_constant']:.6g} N/mm^(10/9) (whole roller)",
                      f"    pitch radius               R  = {r['pitch_radius']:.6g} mm",
                      f"    effective length           l  = {r['roller_effective_length']:.6g} mm, {r['slices']} slices "
                      f"of {r['slice_width']:.4g} mm",
                      f"    contact angle              a  = {r['contact_angle_deg']:.6g} deg",
                      f"    crown                      {r['crown']}" + (f", drop {r['crown_drop_at_ends'] * 1e3:.4g} um at "
                                                                         "the end slices" if r["crown"] != "none" else ""),
                      f"    radial clearance           rL = {r['radial_clearance']:.6g} mm"]
            if r["axial_preload"]:
                lines.append(f"    axial preload              d0 = {r['axial_preload']:.6g} mm")
            continue
        pair = (f"four-point balls, contact pair {'+' if r['pair'] > 0 else '-'}a0 (with row "
                f"{i + 1 if r['pair'] > 0 else i - 1}: one four-point row, the same balls), "
                if r.get("element") == FOUR_POINT else "")
        lines += [f"  row {i}: {pair}z = {r['axial_offset']:g} mm, contact direction {r['contact_direction']:+d}, "
                  f"Z = {r['n_balls']}",
                  f"    Hertz constant             Kn = {r['hertz_constant']:.6g} N/mm^{r['exponent']:g}",
                  f"    groove-centre distance     A0 = {r['groove_center_distance']:.6g} mm",
                  f"    inner groove-centre radius R  = {r['pitch_radius']:.6g} mm",
                  f"    radial clearance           rL = {r['radial_clearance']:.6g} mm",
                  f"    contact angle              a0 = {r['contact_angle_deg']:.6g} deg",
                  f"    free contact angle         af = {r['free_contact_angle_deg']:.6g} deg "
                  f"({r['free_contact_angle']:.6g} rad)",
                  f"    validity: ball deflection <= {r['deflection_limit']:.6g} mm "
                  + (f"(Hertz pressure {g['contact_pressure_limit']:g} N/mm^2)" if g is not None
                     else f"({r['deflection_limit'] / r['groove_center_distance']:.3g} A0)")]
        if r["axial_preload"]:
            lines.append(f"    axial preload              d0 = {r['axial_preload']:.6g} mm")
        if r["rest_deflection"] > 0:
            lines.append(f"    preload ball deflection    delta0 = {r['rest_deflection']:.6g} mm at q = 0, "
                         f"contact angle {r['rest_contact_angle_deg']:.6g} deg")
    if "load_centre_spread" in rep:
        lines.append(f"load-centre spread ({rep['arrangement']}): E = 2(e + c2 R tan a0) = "
                     f"{rep['load_centre_spread']:.6g} mm")
    if "speed_limit" in rep:
        lines.append(f"speed limit: {rep['speed_limit']:.6g} rpm (above it the centrifugal force alone takes a ball "
                     "beyond the validity limit)")
    if "mounting" in rep:
        lines += mounting_text(rep["mounting"])
    return "\n".join(lines)


def mounting_text(budget: dict) -> list[str]:
    """The short mounting block of the text report: the run line, then row 0's budget in um and N/mm^2 (every
    row shares the rings' fits; a pair's rows differ only in their axial preload, which the line gives)."""
    def um(v):
        return f"{1000.0 * v:.4g} um"

    def rng(r, key):
        return f" (range {um(r[key][0])} to {um(r[key][1])})" if key in r else ""

    lines = [f"mounting: {budget['line']}" + ("" if budget["speed"] > 0 else " at rest (--speed RPM: running)")]
    r = budget["rows"][0]
    if "shaft_fit_pressure" in r:
        fits = [f"shaft {budget['shaft_fit']}" if budget.get("shaft_fit") else "",
                f"housing {budget['housing_fit']}" if budget.get("housing_fit") else ""]
        lines += [
            f"  unmounted diametral clearance  {um(r['unmounted_diametral_clearance'])}"
            f"{rng(r, 'unmounted_diametral_clearance_range')}",
            f"  shaft interference             {um(r['shaft_interference'])} operating{rng(r, 'shaft_interference_range')}"
            f", fit pressure {r['shaft_fit_pressure']:.4g} N/mm^2",
            f"  housing interference           {um(r['housing_interference'])} operating"
            f"{rng(r, 'housing_interference_range')}, fit pressure {r['housing_fit_pressure']:.4g} N/mm^2",
            f"  mounted diametral clearance    {um(r['mounted_diametral_clearance'])} (fits, at assembly, standing)",
            f"  raceways: inner grows {um(r['inner_raceway_growth'])} (fit) + {um(r['inner_raceway_free_growth'])}"
            f" (free), outer contracts {um(r['outer_raceway_contraction'])} (fit) + "
            f"{um(r['outer_raceway_free_contraction'])} (free); balls grow {um(2.0 * r['ball_growth'])}",
            f"  operating diametral clearance  {um(r['operating_diametral_clearance'])}",
            f"  ring hoop stress at the bore   inner {r['inner_ring_hoop_stress']:.4g} N/mm^2, outer "
            f"{r['outer_ring_hoop_stress']:.4g} N/mm^2"]
        named = [f for f in fits if f]
        if named:
            lines[1:1] = ["  fits: " + ", ".join(named) + " (ISO 286 on ISO 492 Normal rings; the solve uses each "
                          "range's mean)"]
    lines += [f"  note: {n}" for n in budget["notes"]]
    return lines




def fault_frequency_report(bearing, speed, load=None) -> dict:
    """The bearing's fault frequencies at shaft speed ``speed`` (rpm > 0), JSON-ready (what `fastbearing bearing
    FILE --speed RPM` adds to its report).

    The kinematics of rolling without slip (:mod:`fastbearing.analysis.faults`) from the bearing's catalogue
    geometry: ball (or roller) diameter D and pitch diameter dm in mm, Z elements per row, and the contact
    angle: the geometry's nominal one (degrees) or, with ``load`` (Fx, Fy, Fz in N, Mx, My in N*mm on the inner
    ring at the bearing centre), the loaded one at that operating point: the bearing is solved quasi-statically
    (:func:`fastbearing.solve`) and the angle is the mean loaded contact angle of the loaded balls
    (:func:`fastbearing.analysis.contacts.ball_contacts`, rad, converted to degrees). The rotating ring is the
    geometry's ``rotating`` key where it has one, else the inner ring.

    Returns a dict: ``speed_rpm``, ``shaft_frequency_hz`` (f_r = rpm/60), ``rotating`` ("inner" | "outer"),
    ``element`` ("ball" | "roller"), ``contact_angle_deg``, ``contact_angle_source`` ("nominal" | "loaded"),
    ``load`` (the 5 numbers, or None), ``loaded_contacts`` (how many ball contacts carry load; 0 without
    ``load``) and ``fault_frequencies``:
    {name: {"hz": ..., "order": ...}} for FTF, BPFO, BPFI, BSF and ball_defect (= 2 BSF), order in multiples
    of f_r.

    Where the solve at ``load`` flags ``beyond_validity`` (a ball's deflection past its row's validity limit,
    the 4200 N/mm^2 Hertz pressure by default: about C0), the dict also holds ``warning``, a line that says
    the loaded contact angle is outside the model's validity (the text report prints it).

    Raises ValueError (one line) for a speed that is not finite and > 0 or above the bearing's speed limit
    (:func:`fastbearing.model.bearing.speed_limit`, rpm; MAX_SPEED, 2e6 rpm, where it has no high-speed
    model) (naming ``speed``), a load larger than MAX_LOAD_OVER_C0 (10) times the bearing's static load
    rating C0 (:func:`load_size`; naming ``load``; before the solve), a bearing without
    catalogue geometry (naming what is missing), a load that is not 5 finite numbers (naming ``load``), does
    not solve, or leaves every ball unloaded. Roller bearings: D is the mean roller diameter, and a roller
    row's contact angle does not change with load.
    """
    rpm = validate.number(speed, "speed", low=0, low_open=True, units="rpm")
    _check_report_speed(bearing, rpm)
    g = bearing.geometry
    if g is None:
        raise ValueError(f"{bearing.name or 'this bearing'} has no [bearing.geometry] table: fault frequencies need "
                         "its ball diameter, pitch diameter (mm) and number of balls")
    if g.element == "ball":
        D, Z = g.ball_diameter, g.n_balls
    else:
        D, Z = g.roller_diameter, g.n_rollers
    rotating = getattr(g, "rotating", "inner")
    element = "ball" if g.element == "ball" else "roller"
    angle, source, loaded, f = float(g.contact_angle), "nominal", 0, None
    if load is not None:
        from ..analysis.contacts import ball_contacts
        from ..api import _as_vector, solve

        f = [float(v) for v in _as_vector(load, "load", "Fx, Fy, Fz in N; Mx, My in N*mm")]
        _check_report_load(bearing, f)
        result = solve(bearing, f)
        if not result.converged:
            raise ValueError(f"load {_load_text(f)}: the bearing has no solution there ({result.status_name})"
                             + (f": {result.note}" if result.note else ""))
        beyond = bool(int(result.status) & status_codes.BEYOND_VALIDITY)
        c = ball_contacts(bearing, result.q)
        on = c.load > 0
        loaded = int(on.sum())
        if loaded == 0:
            raise ValueError(f"load {_load_text(f)}: no {element} carries load there, so there is no loaded contact "
                             "angle (leave the load out for the nominal one)")
        angle, source = math.degrees(float(abs(c.contact_angle[on]).mean())), "loaded"
    out = {"speed_rpm": rpm, "shaft_frequency_hz": rpm / 60.0, "element": element, "rotating": rotating,
           "contact_angle_deg": angle, "contact_angle_source": source, "load": f, "loaded_contacts": loaded,
           "fault_frequencies": fault_frequencies(D, g.pitch_diameter, Z, rpm, angle, rotating)}
    if load is not None and beyond:
        out["warning"] = (f"beyond_validity: at this load a {element}'s deflection exceeds its row's validity "
                          "limit (the Hertz pressure limit, 4200 N/mm^2 by default: about the static load rating "
                          "C0); the loaded contact angle, and the frequencies from it, are outside the model's "
                          "validity")
    return out


#: Largest load `fastbearing bearing --speed --load` takes, in multiples of the bearing's static load rating C0
#: (ISO 76): at C0 the most loaded contact already reaches 4200 N/mm^2 (ball) or 4000 N/mm^2 (roller), the
#: model's validity limit; no catalogue rates a bearing beyond S0 = C0/P0 = 0.5, and a static equivalent load
#: P0 is at least about a quarter of the load's size in any direction, so 10 C0 is past every rated use.
MAX_LOAD_OVER_C0 = 10.0


def load_size(bearing, f) -> float:
    """A load's size in N: |(Fx, Fy, Fz)| + |(Mx, My)| / r, r (mm) the largest pitch radius plus axial offset
    of the bearing's rows (a moment as the force at the rows' reach)."""
    arm = max(r.pitch_radius + abs(r.axial_offset) for r in bearing.rows)
    return math.hypot(f[0], f[1], f[2]) + math.hypot(f[3], f[4]) / arm


def _check_report_load(bearing, f) -> None:
    """FieldError ``load`` when its size (:func:`load_size`) exceeds MAX_LOAD_OVER_C0 times the bearing's C0
    (N); no check where the bearing has no rating (life.ratings refuses it)."""
    from ..analysis.life import ratings

    try:
        r = ratings(bearing)
    except ValueError:
        return
    C0 = r.C0 if r.C0 is not None else float(np.sum(r.C0_row))
    size = load_size(bearing, f)
    if C0 > 0 and size > MAX_LOAD_OVER_C0 * C0:
        raise validate.FieldError("load", f"{_load_text(f)} is {size / C0:.3g} x the static load rating C0 = "
                                  f"{C0:.6g} N of {bearing.name or 'this bearing'}: it must be <= "
                                  f"{MAX_LOAD_OVER_C0:g} C0 (size |F| + |M|/r, r = "
                                  f"{max(r_.pitch_radius + abs(r_.axial_offset) for r_ in bearing.rows):.6g} mm); "
                                  "beyond it no contact model holds", show_value=False)


def _check_report_speed(bearing, rpm: float) -> None:
    """The speed rule of `fastbearing solve`: at most MAX_SPEED (2e6 rpm), and at most the bearing's
    :func:`speed_limit` (rpm) where it has the high-speed model; FieldError ``speed``."""
    validate.number(rpm, "speed", low=0, high=MAX_SPEED, low_open=True, units="rpm")
    try:
        check_speed_model(bearing)
    except ValueError:  # roller rows, no geometry: the sanity bound alone
        return
    check_speed_model(bearing, rpm, "speed")


def _load_text(f, brackets: bool = True) -> str:
    text = f"Fx, Fy, Fz = {f[0]:g}, {f[1]:g}, {f[2]:g} N; Mx, My = {f[3]:g}, {f[4]:g} N*mm"
    return f"({text})" if brackets else text


def fault_frequency_text(ff: dict) -> str:
    """The report of :func:`fault_frequency_report` as `fastbearing bearing FILE --speed RPM` prints it: one line
    per frequency, in Hz and as an order of the shaft frequency f_r."""
    if ff["contact_angle_source"] == "loaded":
        angle = (f"loaded contact angle {ff['contact_angle_deg']:.4g} deg (mean of {ff['loaded_contacts']} loaded "
                 f"{ff.get('element', 'ball')} contacts at {_load_text(ff['load'], False)}"
                 + ("; OUTSIDE THE MODEL'S VALIDITY" if "warning" in ff else "") + ")")
    else:
        angle = f"nominal contact angle {ff['contact_angle_deg']:g} deg"
    lines = [f"fault frequencies at {ff['speed_rpm']:g} rpm (shaft f_r = {ff['shaft_frequency_hz']:.6g} Hz), "
             f"{ff['rotating']} ring rotating, {angle}:"]
    for name in FAULT_NAMES:
        v = ff["fault_frequencies"][name]
        lines.append(f"  {name:<12s} {FAULT_WORDS[name]:<25s} {v['hz']:10.4f} Hz  {v['order']:8.5f} x f_r")
    if "warning" in ff:
        lines.append(f"warning: {ff['warning']}")
    return "\n".join(lines)
