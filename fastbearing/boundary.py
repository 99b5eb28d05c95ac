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

__all__ = ["Fixed", "parse_fixed", "parse_fix_option", "names", "targets", "free_tilt_note"]


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


def parse_fixed(fixed, n: int | None = None, where: str = "fixed") -> Fixed:
    """Check ``fixed`` (None, or {name: value}) and return a :class:`Fixed`; ``n`` cases allow a value of n
    numbers (one per case). ValueError (FieldError) naming the field: a name that is not a degree of
    freedom, a value that is not a finite number, all five fixed (that is a displacement given)."""
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
    return Fixed(mask, values)


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
            out[name] = float(value)
        except ValueError:
            raise validate.FieldError(f"{where} {name}", "must be a number (mm for dx, dy, dz; rad for bx, by)",
                                      value.strip()) from None
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
    """One line where a bearing that cannot hold a moment by itself (a single ball row, a single tapered
    row) took a combined radial and axial load with every degree of freedom free: the ring tilted freely, and
    how to hold it ("" otherwise)."""
    load = np.asarray(load, float)
    if bearing.n_rows != 1 or not (np.hypot(load[0], load[1]) > 0 and load[2] != 0):
        return ""
    tilt = float(np.hypot(q[3], q[4]))
    return (f"the ring tilted freely by {tilt * 1e3:.3g} mrad (a single row carries a combined load with a tilt); "
            "where the shaft holds it, fix the tilt: --fix bx=0,by=0 (Python: fixed={'bx': 0.0, 'by': 0.0})")
