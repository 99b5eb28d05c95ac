"""The ``[bearing.mounting]`` table and the operating bearing (issue 44, items 2, 4 and 8).

Parsing and wiring only; the physics is :mod:`fastbearing.model.mounting` (Lame fits, thermal and centrifugal
growth, the pairs' axial preload change) and the tables are :mod:`fastbearing.model.tolerances`. Units: mm
(diametral interferences and clearances), N/mm^2, deg C, rpm.

``[bearing.mounting]`` needs ``[bearing.geometry]`` with the boundary dimensions ``bore`` and
``outer_diameter``. A fit class (``shaft_fit = "k5"``) gives an interference range; a single operating point
uses the range's mean (the report keeps the range). ``[bearing.geometry] diametral_clearance`` may be an
ISO 5753-1 group ("C2", "CN", "C3", "C4", "C5"; deep-groove ball bearings only) or a range ``[min, max]``:
again the mean is solved and the range reported.

:func:`operating_bearing` gives the bearing as it runs at one speed: each row's ``radial_clearance`` is
Pd_op/2, each row's ``axial_preload`` changed by :func:`fastbearing.model.mounting.axial_preload_changes`, and
``mounting`` None. Solving it is exactly what a mounted bearing's solve does.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from .. import validate
from ..validate import FieldError
from . import tolerances
from .mounting import ABSOLUTE_ZERO, BodyMaterial, axial_preload_changes, body_material, mount_row

#: Keys of ``[bearing.mounting]`` (issue 44 item 2).
MOUNTING_KEYS = ("shaft_interference", "housing_interference", "shaft_fit", "housing_fit", "shaft_bore",
                 "housing_outer_diameter", "shaft_material", "housing_material", "inner_ring_temperature",
                 "outer_ring_temperature", "ball_temperature", "shaft_temperature", "housing_temperature",
                 "assembly_temperature")
_TEMPERATURES = ("inner_ring_temperature", "outer_ring_temperature", "ball_temperature", "shaft_temperature",
                 "housing_temperature")


@dataclass(frozen=True)
class Mounting:
    """A parsed ``[bearing.mounting]`` (lengths mm, diametral; temperatures deg C).

    given : False when there is no ``[bearing.mounting]`` table and the record only keeps a clearance
        group or range (the bearing then solves its mean clearance, nothing else changes).
    shaft_interference, housing_interference : the nominal interference solved (a fit class: its mean).
    shaft_interference_range, housing_interference_range : (min, max) of a fit class, else None.
    clearance_group : the ISO 5753-1 group typed, or None; clearance_range : (min, max) mm or None.
    """

    given: bool = True
    shaft_interference: float = 0.0
    housing_interference: float = 0.0
    shaft_fit: str | None = None
    housing_fit: str | None = None
    shaft_interference_range: tuple | None = None
    housing_interference_range: tuple | None = None
    shaft_bore: float = 0.0
    housing_outer_diameter: float | None = None
    shaft_material: BodyMaterial | None = None
    housing_material: BodyMaterial | None = None
    assembly_temperature: float = 20.0
    inner_ring_temperature: float | None = None
    outer_ring_temperature: float | None = None
    ball_temperature: float | None = None
    shaft_temperature: float | None = None
    housing_temperature: float | None = None
    clearance_group: str | None = None
    clearance_range: tuple | None = None

    def to_dict(self) -> dict:
        """The ``[bearing.mounting]`` table back (materials as tables), for to_dict round trips."""
        out = {}
        if self.shaft_fit is not None:
            out["shaft_fit"] = self.shaft_fit
        else:
            out["shaft_interference"] = self.shaft_interference
        if self.housing_fit is not None:
            out["housing_fit"] = self.housing_fit
        else:
            out["housing_interference"] = self.housing_interference
        out["shaft_bore"] = self.shaft_bore
        if self.housing_outer_diameter is not None:
            out["housing_outer_diameter"] = self.housing_outer_diameter
        for key in ("shaft_material", "housing_material"):
            out[key] = getattr(self, key).as_dict()
        out["assembly_temperature"] = self.assembly_temperature
        for key in _TEMPERATURES:
            if getattr(self, key) is not None:
                out[key] = getattr(self, key)
        return out


def clearance_spec(value, geometry_table: dict, where: str):
    """``diametral_clearance`` as typed: a number (returned as is), a group string or a [min, max] range.
    Returns (the number to solve, the group or None, the (min, max) range or None)."""
    field = f"{where}.diametral_clearance"
    if isinstance(value, str):
        element = geometry_table.get("element", "ball")
        angle = geometry_table.get("contact_angle", 0.0)
        if element != "ball" or angle != 0:
            raise FieldError(field, "may be an ISO 5753-1 group only for a deep-groove ball bearing (element "
                             "ball, contact_angle 0): give a number or a range [min, max] in mm", value)
        if "bore" not in geometry_table:
            raise FieldError(field, f"as an ISO 5753-1 group needs {where}.bore (mm): the groups go by bore", value)
        lo, hi = tolerances.clearance_group(value, geometry_table["bore"], field=field, size_field=f"{where}.bore")
        return 0.5 * (lo + hi), value, (lo, hi)
    if isinstance(value, (list, tuple)):
        if len(value) != 2:
            raise FieldError(field, "as a range must be [min, max] in mm", value)
        lo = validate.number(value[0], f"{field}[0]", units="mm")
        hi = validate.number(value[1], f"{field}[1]", units="mm")
        if not lo <= hi:
            raise FieldError(field, "as a range must be [min, max] with min <= max, in mm", list(value))
        return 0.5 * (lo + hi), None, (lo, hi)
    return value, None, None


def _check_temperature(table, key, where):
    if key in table:
        return validate.number(table[key], f"{where}.{key}", low=ABSOLUTE_ZERO, units="deg C (absolute zero)")
    return None


def mounting_from_table(table, geometry, where: str = "bearing.mounting", *, group=None, clearance_range=None
                        ) -> Mounting:
    """A :class:`Mounting` from a parsed ``[bearing.mounting]`` table and the bearing's Geometry or
    RollerGeometry; every refusal is a FieldError naming ``where.KEY``."""
    validate.table(table, where, MOUNTING_KEYS)
    if geometry is None:
        raise FieldError(where, "needs [bearing.geometry] (the ring and ball dimensions)", show_value=False)
    for a, b in (("shaft_interference", "shaft_fit"), ("housing_interference", "housing_fit")):
        if a in table and b in table:
            raise FieldError(f"{where}.{b}", f"and {where}.{a} are alternatives: give one", show_value=False)
    geo = where.rpartition(".")[0] + ".geometry"
    for key in ("bore", "outer_diameter"):
        if getattr(geometry, key, None) is None:
            raise FieldError(f"{where}", f"needs the boundary dimensions {geo}.bore and {geo}.outer_diameter "
                             f"(mm, from the maker's catalogue); {geo}.{key} is missing", show_value=False)
    values = {}
    for fit, key, lookup, size in (("shaft_fit", "shaft_interference", tolerances.interference_range, "bore"),
                                   ("housing_fit", "housing_interference", tolerances.housing_interference_range,
                                    "outer_diameter")):
        if fit in table:
            rng = lookup(table[fit], getattr(geometry, size), fit_field=f"{where}.{fit}", size_field=f"{geo}.{size}")
            values[fit] = table[fit]
            values[f"{key}_range"] = rng
            values[key] = 0.5 * (rng[0] + rng[1])  # a single operating point solves the range's mean
        elif key in table:
            values[key] = validate.number(table[key], f"{where}.{key}", units="mm (diametral, > 0 interference)")
    d, D = geometry.bore, geometry.outer_diameter
    if "shaft_bore" in table:
        values["shaft_bore"] = validate.number(table["shaft_bore"], f"{where}.shaft_bore", low=0.0, units="mm")
        if not values["shaft_bore"] < d:
            raise FieldError(f"{where}.shaft_bore", f"must be < the bore d = {d:g} mm (0 for a solid shaft)",
                             values["shaft_bore"])
    if "housing_outer_diameter" in table:
        Dh = validate.number(table["housing_outer_diameter"], f"{where}.housing_outer_diameter", units="mm")
        if not Dh > D:
            raise FieldError(f"{where}.housing_outer_diameter", f"must be > the ring's outer diameter D = {D:g} mm "
                             "(omit it for an infinitely thick housing)", Dh)
        values["housing_outer_diameter"] = Dh
    for key in ("shaft_material", "housing_material"):
        try:
            values[key] = body_material(table.get(key, "steel"), key)
        except FieldError as err:
            raise err.within(where) from None
    values["assembly_temperature"] = _check_temperature(table, "assembly_temperature", where)
    if values["assembly_temperature"] is None:
        values["assembly_temperature"] = 20.0
    for key in _TEMPERATURES:
        values[key] = _check_temperature(table, key, where)
    mounting = Mounting(given=True, clearance_group=group, clearance_range=clearance_range, **values)
    try:  # the ring sections and the materials, checked now: before any kernel runs, not at the first solve
        _mount(mounting, geometry, 0.0, warn=False)
    except FieldError as err:
        raise err.within(where) from None
    return mounting


def _element_diameter(geometry) -> float:
    return geometry.ball_diameter if geometry.element == "ball" else geometry.roller_diameter


def _mount(mounting: Mounting, geometry, speed: float, warn: bool = True):
    """The MountedRow of the bearing's rows (all rows share one geometry) at ``speed`` rpm."""
    ball = geometry.ball_material if geometry.element == "ball" else geometry.roller_material
    ring = geometry.ring_material
    # fastbearing.Material has no thermal expansion: bearing steel's 12.5e-6 /K (NSK E1102e eq. 9.6), silicon
    # nitride's 3.2e-6 /K (a typical hot-pressed Si3N4 value, as the makers of hybrid bearings list it)
    def body(m, density):
        alpha = 3.2e-6 if "nitride" in m.name else 12.5e-6
        return BodyMaterial(m.name, m.youngs_modulus, m.poisson_ratio, density or m.density, alpha)

    ring_m = body(ring, None)
    ball_m = body(ball, getattr(geometry, "ball_density", None))
    return mount_row(bore=geometry.bore, outer_diameter=geometry.outer_diameter,
                     pitch_diameter=geometry.pitch_diameter, element_diameter=_element_diameter(geometry),
                     unmounted_diametral_clearance=geometry.diametral_clearance,
                     shaft_interference=mounting.shaft_interference,
                     housing_interference=mounting.housing_interference, shaft_bore=mounting.shaft_bore,
                     housing_outer_diameter=mounting.housing_outer_diameter,
                     shaft_material=mounting.shaft_material, housing_material=mounting.housing_material,
                     inner_ring_material=ring_m, outer_ring_material=ring_m, ball_material=ball_m,
                     assembly_temperature=mounting.assembly_temperature,
                     inner_ring_temperature=mounting.inner_ring_temperature,
                     outer_ring_temperature=mounting.outer_ring_temperature,
                     ball_temperature=mounting.ball_temperature, shaft_temperature=mounting.shaft_temperature,
                     housing_temperature=mounting.housing_temperature, speed=speed,
                     rotating=getattr(geometry, "rotating", "inner"), warn=warn)


def _um(values) -> str:
    return ", ".join(f"{1000.0 * v:.4g}" for v in values)


def operating_bearing(bearing, speed: float = 0.0):
    """(the bearing as it runs at ``speed`` rpm, its budget dict), or (bearing, None) without mounting.

    The operating bearing has each row's radial_clearance = Pd_op/2, geometry.diametral_clearance = Pd_op,
    each row's axial_preload changed by the inner and outer sides' axial growth (pairs and sets), and
    mounting None. A value outside the model's range is a ValueError naming bearing.mounting.
    Budget: ``speed`` (rpm), ``rows`` (one dict per row, mm and N/mm^2: MountedRow.as_dict() plus
    operating_axial_preload, unmounted_axial_preload and the ranges), ``materials``, ``notes``, ``line``."""
    mounting = getattr(bearing, "mounting", None)
    if mounting is None:
        return bearing, None
    speed = validate.number(speed, "speed", low=0.0, units="rpm")
    geometry = bearing.geometry
    n = bearing.n_rows
    base = [r.axial_preload for r in bearing.rows]
    if not mounting.given:  # a clearance group or range alone: the mean is already in the rows
        Pd = geometry.diametral_clearance
        rows = [{"unmounted_diametral_clearance": Pd, "operating_diametral_clearance": Pd,
                 "unmounted_diametral_clearance_range": list(mounting.clearance_range),
                 "operating_axial_preload": d0} for d0 in base]
        line = f"clearance {1000.0 * Pd:.4g} um, the mean of {_range_text(mounting)}"
        return replace(bearing, mounting=None), {"speed": speed, "rows": rows, "materials": {}, "notes": [],
                                                  "line": line}
    if any(r.radial_clearance != 0.5 * geometry.diametral_clearance for r in bearing.rows):
        # the budget starts from the geometry's clearance: rows changed since (with_rows) would be ignored
        raise FieldError("bearing.mounting", "needs every row's radial_clearance to be the geometry's "
                         f"diametral_clearance / 2 = {0.5 * geometry.diametral_clearance:.6g} mm (change the geometry's "
                         "diametral_clearance instead of the rows')", show_value=False)
    mounted = _mount(mounting, geometry, speed)
    Pd_op = mounted.operating_diametral_clearance
    changes = preload_shifts(bearing)
    notes = list(mounted.notes)
    if Pd_op > 0.0 and any(c != 0.0 for c in changes):
        # Row takes an axial preload only at zero or negative clearance: the rows' axial shift changes their
        # axial play instead, which the radial clearance does not hold
        notes.append(f"the rows' axial shift ({_um(changes)} um) is not modelled: the operating clearance is "
                     "> 0 (an axial preload needs zero or negative clearance)")
        changes = (0.0,) * n
    preloads = [d0 + c for d0, c in zip(base, changes)]
    try:
        rows = tuple(replace(r, radial_clearance=0.5 * Pd_op, axial_preload=p) for r, p in zip(bearing.rows, preloads))
        geo = replace(geometry, diametral_clearance=Pd_op)
    except FieldError as err:
        raise FieldError("bearing.mounting", f"gives an operating bearing outside the model's range at {speed:g} "
                         f"rpm: operating diametral clearance {Pd_op:.6g} mm, axial preload per row "
                         f"{[round(p, 9) for p in preloads]} mm: {err}", show_value=False) from None
    operating = replace(bearing, rows=rows, geometry=geo, mounting=None)
    out_rows = []
    for i, r in enumerate(bearing.rows):
        row = mounted.as_dict()
        row.pop("materials")
        row.pop("notes")
        row["operating_axial_preload"] = preloads[i]
        row["unmounted_axial_preload"] = base[i]
        if mounting.clearance_range is not None:
            row["unmounted_diametral_clearance_range"] = list(mounting.clearance_range)
        if mounting.shaft_interference_range is not None:
            row["shaft_interference_range"] = list(mounting.shaft_interference_range)
        if mounting.housing_interference_range is not None:
            row["housing_interference_range"] = list(mounting.housing_interference_range)
        out_rows.append(row)
    line = f"operating clearance {1000.0 * Pd_op:.4g} um (unmounted {1000.0 * geometry.diametral_clearance:.4g} um)"
    if any(c != 0.0 for c in changes):
        line += f"; axial preload per row {_um(preloads)} um (unmounted {_um(base)} um)"
    if speed > 0.0:
        line += f" at {speed:g} rpm"
    budget = {"speed": speed, "rows": out_rows,
              "materials": {body: m.as_dict() for body, m in mounted.materials.items()},
              "shaft_fit": mounting.shaft_fit, "housing_fit": mounting.housing_fit, "notes": notes, "line": line}
    return operating, budget


def preload_shifts(bearing) -> tuple:
    """Each row's axial preload change (mm) from the inner side's (shaft, at the shaft temperature) and the
    outer side's (housing) axial growth between the rows (model.mounting.axial_preload_changes; (0.0,) for a
    single row). It applies where the operating clearance is <= 0 (:func:`operating_bearing`)."""
    mounting = bearing.mounting
    if bearing.n_rows == 1:
        return (0.0,)
    T0 = mounting.assembly_temperature
    Ti = mounting.inner_ring_temperature if mounting.inner_ring_temperature is not None else T0
    To = mounting.outer_ring_temperature if mounting.outer_ring_temperature is not None else T0
    Ts = mounting.shaft_temperature if mounting.shaft_temperature is not None else Ti
    Th = mounting.housing_temperature if mounting.housing_temperature is not None else To
    eps_i = mounting.shaft_material.thermal_expansion * (Ts - T0)
    eps_o = mounting.housing_material.thermal_expansion * (Th - T0)
    return tuple(axial_preload_changes([r.axial_offset for r in bearing.rows], [r.contact_direction for r in bearing.rows],
                                       inner_side_strain=eps_i, outer_side_strain=eps_o))


def _range_text(mounting: Mounting) -> str:
    lo, hi = mounting.clearance_range
    group = f"{mounting.clearance_group} " if mounting.clearance_group else ""
    return f"{group}{1000.0 * lo:.4g} to {1000.0 * hi:.4g} um"


def operating(bearing, speed=0.0):
    """The operating bearing alone (see :func:`operating_bearing`); a bearing without mounting unchanged."""
    if getattr(bearing, "mounting", None) is None:
        return bearing
    return _cached(bearing, float(speed))


_CACHE: dict = {}


def _cached(bearing, speed):
    # one mount per (bearing, speed): a loop of solves neither repeats the Lame sums nor warns again
    try:
        key = (bearing, speed)
        hit = _CACHE.get(key)
    except TypeError:  # an unhashable field: no cache
        return operating_bearing(bearing, speed)[0]
    if hit is None:
        if len(_CACHE) > 64:
            _CACHE.clear()
        hit = _CACHE[key] = operating_bearing(bearing, speed)[0]
    return hit


def refuse_speed_cases(bearing, speeds, what: str = "speed") -> float:
    """The one speed (rpm) of a mounted bearing's cases, or a ValueError, where a path takes one operating
    bearing for all its cases (stiffness_many; solve_many and load maps take each case's own: operating_rows)."""
    import numpy as np

    values = np.unique(np.asarray(speeds, dtype=float).ravel())
    if values.size > 1:
        raise ValueError(f"{what}: several speeds on a bearing with [bearing.mounting] are not supported here (the "
                         "operating clearance varies with speed); run one speed per call, or use solve_many or a "
                         "load map, which take each case's own operating clearance")
    return float(values[0]) if values.size else 0.0


#: The temperatures a case may set (deg C), as ``[bearing.mounting]`` names them.
CASE_TEMPERATURES = _TEMPERATURES + ("assembly_temperature",)


def operating_rows(bearing, speeds, temperatures=None):
    """Each case's operating clearance and preload: (rL, d0, notes) for a mounted bearing's cases at ``speeds``
    ((N,) rpm) and, optionally, ``temperatures`` {key: (N,) deg C} in place of ``[bearing.mounting]``'s (keys
    of :data:`CASE_TEMPERATURES`). rL and d0 are (N, n_rows) mm, each row's radial clearance (Pd_op / 2) and
    axial preload as :func:`operating_bearing` gives them; NaN in a case whose operating bearing is outside
    the model's range (that case is flagged, not solved: api.solve_many, the jobs). ``notes``: the distinct
    notes and warnings of the mounts (fits lost, hoop stress), each once. One mount per distinct
    (speed, temperatures): a map's axes repeat them."""
    import warnings

    import numpy as np

    speeds = np.asarray(speeds, dtype=float).ravel()
    n = speeds.shape[0]
    keys = sorted(temperatures or {})
    for key in keys:
        if key not in CASE_TEMPERATURES:
            raise FieldError("temperatures", f"may set {', '.join(CASE_TEMPERATURES)} (deg C); got {key!r}",
                             show_value=False)
    columns = [speeds] + [np.broadcast_to(np.asarray(temperatures[k], dtype=float).ravel(), (n,)) for k in keys]
    combos, inverse = np.unique(np.stack(columns, axis=1), axis=0, return_inverse=True)
    rL = np.full((len(combos), bearing.n_rows), np.nan)
    d0 = np.full((len(combos), bearing.n_rows), np.nan)
    notes = []
    for c, combo in enumerate(combos):
        case = bearing
        if keys:
            case = replace(bearing, mounting=replace(bearing.mounting, **dict(zip(keys, map(float, combo[1:])))))
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                op, budget = operating_bearing(case, float(combo[0]))
            except FieldError as err:
                notes.append(str(err))
                continue
        notes += [str(w.message) for w in caught] + list(budget["notes"] if budget else ())
        rL[c] = [r.radial_clearance for r in op.rows]
        d0[c] = [r.axial_preload for r in op.rows]
    inverse = inverse.ravel()
    return rL[inverse], d0[inverse], list(dict.fromkeys(notes))


def operating_attributes(budget: dict) -> dict:
    """A mounted bearing's operating point as file attributes (units in the names): per row the operating and
    unmounted diametral clearance and the operating axial preload (mm), the speed (rpm) and the run line."""
    rows = budget["rows"]
    return {"operating_diametral_clearance_mm": [r["operating_diametral_clearance"] for r in rows],
            "unmounted_diametral_clearance_mm": [r["unmounted_diametral_clearance"] for r in rows],
            "operating_axial_preload_mm": [r["operating_axial_preload"] for r in rows],
            "operating_speed_rpm": budget["speed"], "operating_note": budget["line"]}
