"""Mixed boundary conditions: degrees of freedom given as displacements, the rest as loads.

A leaf module. A solve takes ``fixed``, a mapping of displacement names (dx, dy, dz in mm; bx, by in rad)
to their prescribed values; the loads at those degrees of freedom are the unknown reactions, so their
entries in the load must be 0. The solver (engine/solver.py) reads the choice as a bitmask in its settings
and the prescribed values from the target vector's fixed entries (docs/model.md, "Mixed boundary
conditions: the reduced system"): this module turns one into the other and checks the input first.
"""

from __future__ import annotations

import numpy as np

from . import validate
from .dofs import DISPLACEMENT_NAMES, DISPLACEMENT_UNITS, LOAD_NAMES

__all__ = ["Fixed", "parse_fixed", "parse_fix_option", "names", "targets", "free_tilt_note", "fixed_bounds",
           "check_fixed_range"]


class Fixed:
    """A checked choice of fixed degrees of freedom: ``mask`` (bit i: degree of freedom i fixed), ``names``
    and ``values`` {name: float, or (N,) float64 per case} in mm and rad."""

    def __init__(self, mask: int, values: dict):
        self.mask = mask
        self.values = values

    @property
    def names(self) -> list[str]:
        return names(self.mask)

    def __bool__(self) -> bool:
        return self.mask != 0


def names(mask: int) -> list[str]:
    """The displacement names of a bitmask, in dof order."""
    return [n for i, n in enumerate(DISPLACEMENT_NAMES) if (mask >> i) & 1]


def parse_fixed(fixed, n: int | None = None, where: str = "fixed", bearing=None) -> Fixed:
    """Check ``fixed`` (None, or {name: value}) and return a :class:`Fixed`; ``n`` cases allow a value of n
    numbers (one per case). ValueError (FieldError) naming the field: a name that is not a degree of
    freedom, a value that is not a finite number, all five fixed (that is a displacement given), and with
    ``bearing`` a value beyond :func:`fixed_bounds` (:func:`check_fixed_range`)."""
    if fixed is None:
        return Fixed(0, {})
    if not isinstance(fixed, dict):
        raise validate.FieldError(where, "must be a table of displacements, e.g. {bx = 0.0, by = 0.0} (dx, dy, dz "
                                  "in mm; bx, by in rad)", fixed)
    mask = 0
    values = {}
    for name, value in fixed.items():
        if name not in DISPLACEMENT_NAMES:
            raise validate.FieldError(f"{where}.{name}", f"is not a degree of freedom; fix any of "
                                      f"{list(DISPLACEMENT_NAMES)} (mm, mm, mm, rad, rad)", show_value=False)
        i = DISPLACEMENT_NAMES.index(name)
        units = DISPLACEMENT_UNITS[i]
        if n is not None and isinstance(value, (list, tuple, np.ndarray)):
            arr = np.asarray(value, dtype=object)
            if arr.ndim != 1 or arr.shape[0] != n:
                raise validate.FieldError(f"{where}.{name}", f"must be one number or one per case ({n}), {units}",
                                          show_value=False)
            values[name] = np.array([validate.number(v, f"{where}.{name}[{k}]", units=units)
                                     for k, v in enumerate(arr)], dtype=float)
        else:
            values[name] = validate.number(value, f"{where}.{name}", units=units)
        mask |= 1 << i
    if mask == 0b11111:
        raise validate.FieldError(where, "fixes all five degrees of freedom: that is a displacement given, not a "
                                  "solve (fb.stiffness, or solve --displacement on the command line)",
                                  show_value=False)
    held = Fixed(mask, values)
    if bearing is not None:
        check_fixed_range(bearing, held, where)
    return held


def parse_fix_option(text: str, where: str = "--fix") -> dict:
    """``"bx=0,by=0"`` (the command line's --fix) as {name: float}; ValueError naming the option."""
    out = {}
    for part in str(text).split(","):
        if not part.strip():
            continue
        name, sep, value = part.partition("=")
        name = name.strip()
        if not sep:
            raise validate.FieldError(where, f"must be NAME=VALUE pairs, e.g. bx=0,by=0 (names {list(DISPLACEMENT_NAMES)};"
                                      " mm and rad)", text)
        try:
            number = float(value)
        except ValueError:
            raise validate.FieldError(f"{where} {name}", "must be a number (mm for dx, dy, dz; rad for bx, by)",
                                      value.strip()) from None
        if name in out:  # the last would win silently
            raise validate.FieldError(f"{where} {name}", f"is given twice ({out[name]:g} and {number:g}); give each "
                                      "degree of freedom once", show_value=False)
        out[name] = number
    if not out:
        raise validate.FieldError(where, "names no degree of freedom, e.g. bx=0,by=0", text)
    return out


def targets(loads: np.ndarray, fixed: Fixed, where: str = "f") -> np.ndarray:
    """The solver's targets: ``loads`` ((5,) or (N, 5), N and N*mm) with each fixed entry replaced by its
    displacement. A fixed degree of freedom's load entry must be 0 (it is the unknown reaction): a
    FieldError naming it otherwise."""
    out = np.array(loads, dtype=float, copy=True)
    cases = out.reshape(-1, 5)
    for name in fixed.names:
        i = DISPLACEMENT_NAMES.index(name)
        bad = np.flatnonzero(cases[:, i] != 0.0)
        if bad.size:
            at = f"[{int(bad[0])}]" if out.ndim == 2 else ""
            raise validate.FieldError(f"{where}{at}.{LOAD_NAMES[i]}", f"must be 0 where {name} is fixed (the "
                                      f"{LOAD_NAMES[i]} there is the reaction the solve finds)", cases[bad[0], i])
        cases[:, i] = fixed.values[name]
    return out


def free_tilt_note(bearing, load, q) -> str:
    """One line where a bearing that cannot hold a moment by itself (its rows all at one axial place: a single
    ball row, a single tapered row, a four-point row's two contact pairs) took a combined radial and axial
    load with every degree of freedom free: the ring tilted freely, and how to hold it ("" otherwise)."""
    load = np.asarray(load, float)
    if len({r.axial_offset for r in bearing.rows}) != 1 or not (np.hypot(load[0], load[1]) > 0 and load[2] != 0):
        return ""
    tilt = float(np.hypot(q[3], q[4]))
    if bearing.n_rows == 1:
        why = "a single row carries a combined load with a tilt"
    elif bearing.n_rows == 2 and all(r.element == "four_point_ball" for r in bearing.rows):
        why = "a four-point row, like a single row, carries a combined load with a tilt"
    else:
        why = "its rows sit at one axial place: like a single row they carry a combined load with a tilt"
    return (f"the ring tilted freely by {tilt * 1e3:.3g} mrad ({why}); "
            "where the shaft holds it, fix the tilt: --fix bx=0,by=0 (Python: fixed={'bx': 0.0, 'by': 0.0})")


#: Largest fixed displacement, in element reaches (the bearing's largest ``deflection_scale``: A0 of a ball
#: row, about 0.05-0.1 of the ball diameter; 0.02 l of a roller row): at one reach a ball is pressed about 7
#: times past its validity limit (0.15 A0), so two reaches are past any bearing the model describes, yet keep
#: f and Kb finite; a tilt's bound is the same travel at the largest pitch radius.
MAX_FIXED_REACH = 2.0


def fixed_bounds(bearing) -> tuple[float, float]:
    """(the largest |dx|, |dy|, |dz| in mm, the largest |bx|, |by| in rad) a fixed degree of freedom may be
    given for ``bearing``: MAX_FIXED_REACH element reaches, the tilt that reach at the largest pitch radius."""
    reach = max(r.deflection_scale for r in bearing.rows)
    length = bearing.length_scale
    return MAX_FIXED_REACH * reach, MAX_FIXED_REACH * reach / length


def check_fixed_range(bearing, fixed: "Fixed", where: str = "fixed") -> None:
    """FieldError naming ``where.NAME`` where a fixed displacement lies beyond :func:`fixed_bounds` (a tilt
    of 1 rad, a displacement of 1e300 mm: singular or nonfinite in the kernel), before any kernel runs."""
    length, tilt = fixed_bounds(bearing)
    for name, value in fixed.values.items():
        i = DISPLACEMENT_NAMES.index(name)
        bound = length if i < 3 else tilt
        worst = float(np.max(np.abs(value)))
        if worst > bound:
            what = (f"{MAX_FIXED_REACH:g} element reaches (the largest A0 or roller deflection scale, "
                    f"{bound / MAX_FIXED_REACH:.4g} mm)" if i < 3 else
                    f"{MAX_FIXED_REACH:g} element reaches ({bound * bearing.length_scale / MAX_FIXED_REACH:.4g} mm) "
                    f"at the largest pitch radius ({bearing.length_scale:.6g} mm)")
            raise validate.FieldError(f"{where}.{name}", f"must be in [{-bound:.4g}, {bound:.4g}] "
                                      f"{DISPLACEMENT_UNITS[i]} for {bearing.name or 'this bearing'}: at most {what}; "
                                      "beyond it no contact model holds", value if np.ndim(value) == 0 else worst)
