"""Rigid shafts on several bearings: equilibrium, system stiffness, natural frequencies.

A rigid shaft moves by Q = (dx, dy, dz, bx, by) at a reference point z_ref
(mm, rad). A point at axial position z moves by T(d) Q with d = z - z_ref
and T(d) = [dx + d*by, dy - d*bx, dz, bx, by]: the same rigid-body map that
makes a double row the sum of its rows (docs/model.md, "Checks"). So a
shaft on several bearings *is* one bearing whose rows are all the bearings'
rows moved by their bearing's d; the one kernel and solver give Q and the
system stiffness K_system = sum_i T_i^T K_i T_i at z_ref directly. Units: N,
mm, rad; masses in kg and inertias in kg*mm^2 (converted to t and t*mm^2 for
the N-mm-s system).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from .. import boundary
from ..api import SolveResult, direct, solve
from ..dofs import DISPLACEMENT_NAMES
from .. import validate
from ..model.bearing import Bearing, check_speed, check_speed_model
from ..model.bearing_file import bearing_from_table, load_bearing, read_toml
from ..model.catalogue import find_bearing_file
from ..model.mounted import operating


def transfer(d: float) -> np.ndarray:
    """T(d): displacement at the reference -> displacement of a point d mm further along z (5x5)."""
    T = np.eye(5)
    T[0, 4] = d
    T[1, 3] = -d
    return T


def load_at_reference(force, moment, d: float) -> np.ndarray:
    """A force (Fx, Fy, Fz) in N and moment (Mx, My) in N*mm applied d mm from the reference, as a
    load (Fx, Fy, Fz, Mx, My) at the reference: T(d)^T f (Fx at d < 0 gives My = Fx*d < 0)."""
    f = np.array([*force, *moment], dtype=float)
    return transfer(d).T @ f


@dataclass(frozen=True)
class MountedBearing:
    """A bearing on the shaft: its centre at axial ``position`` (mm)."""

    position: float
    bearing: Bearing
    name: str = ""


@dataclass(frozen=True)
class PointLoad:
    """External force (N) and moment (N*mm) on the shaft at axial ``position`` (mm)."""

    position: float
    force: tuple[float, float, float]
    moment: tuple[float, float] = (0.0, 0.0)


@dataclass(frozen=True)
class Inertia:
    """Rigid-shaft mass properties: mass (kg), transverse inertias about x and y through the centre of
    mass (kg*mm^2), centre of mass at axial position ``center`` (mm)."""

    mass: float
    inertia_x: float
    inertia_y: float
    center: float

    def matrix(self, reference: float) -> np.ndarray:
        """5x5 mass matrix at the reference point in t and t*mm^2 (consistent with N, mm, s)."""
        M = np.diag([self.mass, self.mass, self.mass, self.inertia_x, self.inertia_y]) * 1e-3
        T = transfer(self.center - reference)
        return T.T @ M @ T


@dataclass(frozen=True)
class _RowsAtSpeed:
    """The high-speed constants of a shaft's rows, each from its own bearing's geometry
    (Bearing.speed_table reads them row by row)."""

    columns: tuple  # per row of the shaft's bearing: its speed columns (None for a roller row)
    #: Not one element kind's catalogue geometry: the rows keep their own bearings' (no race contacts here).
    element = "mixed"

    def row_speed_columns(self, row: int):
        return self.columns[row]


@dataclass(frozen=True)
class Shaft:
    """A rigid shaft with bearings, external loads, (optionally) mass properties and its speed in rpm."""

    reference: float
    bearings: tuple[MountedBearing, ...]
    loads: tuple[PointLoad, ...] = ()
    inertia: Inertia | None = None
    speed: float = 0.0  # rpm: above 0 every bearing's balls run the high-speed model
    #: Degrees of freedom of the shaft held at the reference ({name: mm or rad}; boundary.py): a coupling or
    #: a guide takes the external load there, and reports its reaction.
    fixed: dict | None = None

    def __post_init__(self):
        if not self.bearings:
            raise ValueError("shaft.bearings must list at least one bearing")
        if not math.isfinite(self.reference):
            raise ValueError(f"shaft.reference must be finite (mm), got {self.reference!r}")
        check_speed(self.speed, "shaft.speed")

    def check_speed_model(self, speed: float = 0.0) -> None:
        """ValueError naming ``shaft.bearings[i].speed`` unless every bearing can run at speed (ball rows
        from catalogue geometry), at ``speed`` (rpm) within its speed limit (bearing.speed_limit)."""
        for i, mb in enumerate(self.bearings):
            try:
                check_speed_model(mb.bearing, speed)
            except validate.FieldError as err:
                raise err.within(f"shaft.bearings[{i}]") from None

    def as_bearing(self, at_speed: bool = False) -> Bearing:
        """All rows of all bearings, moved to their axial positions relative to the reference; with
        ``at_speed`` each row keeps its own bearing's high-speed constants (every bearing needs its
        geometry: :meth:`check_speed_model`)."""
        if at_speed:
            self.check_speed_model()
        rows = []
        columns = []
        for mb in self.bearings:
            d = mb.position - self.reference
            rows += [replace(r, axial_offset=r.axial_offset + d) for r in mb.bearing.rows]
            if at_speed:
                g = mb.bearing.geometry
                columns += [g.row_speed_columns(i) if hasattr(g, "row_speed_columns")
                            else g.speed_columns(r.contact_angle) for i, r in enumerate(mb.bearing.rows)]
        if not at_speed:
            return Bearing.from_rows(rows, name="shaft")
        return replace(Bearing.from_rows(rows, name="shaft"), geometry=_RowsAtSpeed(tuple(columns)))

    def external_load(self) -> np.ndarray:
        """Sum of the external loads at the reference (N, N*mm)."""
        total = np.zeros(5)
        for p in self.loads:
            total += load_at_reference(p.force, p.moment, p.position - self.reference)
        return total


@dataclass(frozen=True)
class BearingState:
    """One bearing at the shaft's solution: local displacement, reaction and Kb about its centre."""

    position: float
    q: np.ndarray
    reaction: np.ndarray
    K: np.ndarray
    name: str = ""


@dataclass(frozen=True)
class ShaftResult:
    """Equilibrium of a shaft: Q and K_system at the reference, each bearing's state."""

    solution: SolveResult
    K_system: np.ndarray
    bearings: tuple[BearingState, ...]
    reference: float
    speed: float = 0.0  # rpm
    #: The load the shaft puts on what holds its fixed degrees of freedom (N, N*mm at the reference; 0 at the
    #: free ones): with the bearings' reactions it adds up to the external load.
    holder_reaction: np.ndarray | None = None

    @property
    def q(self) -> np.ndarray:
        return self.solution.q

    def to_dict(self) -> dict:
        """JSON-ready: q, K_system, status, converged and per bearing position, reaction, q, K."""
        out = {"reference": self.reference, "speed": self.speed, "q": self.q.tolist(),
               "K_system": self.K_system.tolist(),
                "status": self.solution.status_name, "converged": self.solution.converged,
               "bearings": [{"name": b.name, "position": b.position, "reaction": b.reaction.tolist(),
                             "q": b.q.tolist(), "K": b.K.tolist()} for b in self.bearings]}
        if self.solution.fixed:
            out["fixed"] = list(self.solution.fixed)
            out["holder_reaction"] = self.holder_reaction.tolist()
        return out


def solve_shaft(shaft: Shaft, method: str = "newton", speed: float | None = None) -> ShaftResult:
    """Statically indeterminate equilibrium of the rigid shaft under its external loads.

    The reaction of each bearing is the load (Fx, Fy, Fz, Mx, My) the shaft
    puts on its inner ring, about the bearing's centre; the reactions,
    carried to the reference, add up to the external load. ``speed`` (rpm;
    default the shaft's own) above 0 runs every bearing's balls at that speed
    (fastbearing.engine.high_speed; K_system is then not quite symmetric).
    """
    speed = shaft.speed if speed is None else check_speed(speed, "speed")
    if speed > 0:
        shaft.check_speed_model(speed)
    if any(mb.bearing.mounting is not None for mb in shaft.bearings):
        # a bearing with [bearing.mounting] sits on the shaft as it runs: its operating clearance and preload
        shaft = replace(shaft, bearings=tuple(replace(mb, bearing=operating(mb.bearing, speed))
                                              for mb in shaft.bearings))
    combined = shaft.as_bearing(at_speed=speed > 0)
    external = shaft.external_load()
    held = boundary.parse_fixed(shaft.fixed, where="shaft.fixed")
    load = external.copy()
    for name in held.names:  # the holder takes the external load there: the bearings see what the solve finds
        load[DISPLACEMENT_NAMES.index(name)] = 0.0
    result = solve(combined, load, method=method, speed=speed, fixed=shaft.fixed)
    states = []
    for mb in shaft.bearings:
        q_local = transfer(mb.position - shaft.reference) @ result.q
        # direct, not stiffness: a solve that did not converge still returns its last iterate, with its status
        f, K, _ = direct(mb.bearing, q_local, speed=speed)
        states.append(BearingState(mb.position, q_local, f, K, mb.name))
    holder = np.zeros(5)
    for name in held.names:  # the bearings' reaction there against the external load: the holder's share
        i = DISPLACEMENT_NAMES.index(name)
        holder[i] = external[i] - result.f[i]
    return ShaftResult(result, result.K, tuple(states), shaft.reference, speed, holder)


def shaft_life(shaft: Shaft, result: ShaftResult, settings=None) -> dict:
    """Each bearing's rating life at its own reaction and the system's (weakest link: the L with
    sum (L/L_i)^(e_i) = 1 over the bearings' L10r, e_i = 10/9 for ball and 9/8 for roller bearings, i.e.
    (sum L^(-10/9))^(-0.9) for ball bearings alone), million revolutions; needs [bearing.geometry] in
    every bearing."""
    from .life import LifeSettings, combine_series, life

    settings = settings or LifeSettings()
    lives = []
    for i, (mb, state) in enumerate(zip(shaft.bearings, result.bearings)):
        if getattr(mb.bearing, "geometry", None) is None:
            raise ValueError(f"shaft.bearings[{i}]: life needs the bearing's geometry ([bearing.geometry])")
        lives.append(life(operating(mb.bearing, result.speed), state.reaction, state.q, settings).to_dict())
    system = combine_series([b["L10r"] for b in lives], [b["weibull_slope"] for b in lives])
    return {"bearings": lives, "system_L10r": system,
            "system_L10r_hours": None if settings.speed is None else system * 1e6 / (60.0 * settings.speed)}


def stiffness_at(result: ShaftResult, position: float) -> np.ndarray:
    """The system stiffness seen at another axial position (mm): T^-T K T^-1."""
    T_inv = transfer(-(position - result.reference))
    return T_inv.T @ result.K_system @ T_inv


@dataclass(frozen=True)
class Modes:
    """Natural frequencies (Hz, ascending) and mass-normalised mode shapes (columns, at the reference)."""

    frequencies: np.ndarray
    shapes: np.ndarray
    diagonal_only: bool


def natural_frequencies(K: np.ndarray, M: np.ndarray, diagonal_only: bool = False) -> Modes:
    """Undamped natural frequencies of the rigid shaft: K phi = omega^2 M phi (scipy.linalg.eigh).

    K in N/mm, N*mm/rad, N/rad and M in t, t*mm^2 give omega in rad/s.
    ``diagonal_only`` keeps only Kb's diagonal, to show what the coupling
    terms change. Polar inertia and gyroscopic terms are not included; nor is the skew part of a Kb at
    speed (about 1e-4 of it, from the friction that carries the balls' gyroscopic moment): the modes are
    those of the symmetric part (K + K^T)/2.
    """
    from scipy.linalg import eigh

    K = np.asarray(K)
    K = np.diag(np.diag(K)) if diagonal_only else 0.5 * (K + K.T)
    w2, shapes = eigh(K, M)
    w2 = np.clip(w2, 0.0, None)  # a rigid-body direction the bearings do not hold gives 0 Hz
    return Modes(np.sqrt(w2) / (2 * math.pi), shapes, diagonal_only)


# -- config files -------------------------------------------------------------------

_SHAFT_KEYS = {"reference", "bearings", "loads", "mass", "speed", "fixed"}
_BEARING_KEYS = {"position", "bearing", "mirrored", "name"}
_LOAD_KEYS = {"position", "force", "moment"}
_MASS_KEYS = {"mass", "inertia_x", "inertia_y", "center"}


def mirrored(bearing: Bearing) -> Bearing:
    """The same bearing mounted the other way round: axial offsets and contact directions flip (a row kind
    that is its own mirror image puts itself back in order: Bearing's rows)."""
    return replace(bearing, rows=tuple(replace(r, axial_offset=-r.axial_offset,
                                               contact_direction=-r.contact_direction) for r in bearing.rows))


def read_shaft(config) -> Shaft:
    """A shaft from a TOML file (or parsed dict) with a ``[shaft]`` table; bearing files are found
    relative to the config. ValueError names the offending field."""
    v = validate
    base = None
    if not isinstance(config, dict):
        base = Path(config).parent
        config = read_toml(config)
    v.table(config, "the shaft config", {"shaft"}, ("shaft",))
    spec = v.table(config["shaft"], "shaft", _SHAFT_KEYS)
    reference = v.number(spec.get("reference", 0.0), "shaft.reference", units="mm")
    bearings = []
    for i, b in enumerate(v.array(spec.get("bearings", []), "shaft.bearings")):
        where = f"shaft.bearings[{i}]"
        v.table(b, where, _BEARING_KEYS, ("position", "bearing"))
        source = b["bearing"]
        if isinstance(source, str):  # a bearing file (relative to the config) or a shipped bearing's name
            bearing = load_bearing(find_bearing_file(source, base, f"{where}.bearing"))
        elif isinstance(source, dict):
            bearing = bearing_from_table(source, where=f"{where}.bearing")
        else:
            raise v.FieldError(f"{where}.bearing", "must be a bearing file name or a [bearing] table", source)
        if v.boolean(b.get("mirrored", False), f"{where}.mirrored"):
            bearing = mirrored(bearing)
        bearings.append(MountedBearing(v.number(b["position"], f"{where}.position", units="mm"), bearing,
                                       v.text(b.get("name", ""), f"{where}.name")))
    loads = []
    for i, p in enumerate(v.array(spec.get("loads", []), "shaft.loads")):
        where = f"shaft.loads[{i}]"
        v.table(p, where, _LOAD_KEYS)
        loads.append(PointLoad(v.number(p.get("position", 0.0), f"{where}.position", units="mm"),
                               tuple(v.numbers_list(p.get("force", [0.0, 0.0, 0.0]), f"{where}.force", 3)),
                               tuple(v.numbers_list(p.get("moment", [0.0, 0.0]), f"{where}.moment", 2))))
    inertia = None
    if "mass" in spec:
        m = v.table(spec["mass"], "shaft.mass", _MASS_KEYS, ("mass", "inertia_x", "inertia_y"))
        values = {k: v.number(m[k], f"shaft.mass.{k}", low=0, low_open=True, units=units)
                  for k, units in (("mass", "kg"), ("inertia_x", "kg*mm^2"), ("inertia_y", "kg*mm^2"))}
        inertia = Inertia(values["mass"], values["inertia_x"], values["inertia_y"],
                          v.number(m.get("center", reference), "shaft.mass.center", units="mm"))
    if not bearings:
        raise v.FieldError("shaft.bearings", "must list at least one bearing ([[shaft.bearings]] with position "
                           "and bearing)", show_value=False)
    speed = check_speed(spec.get("speed", 0.0), "shaft.speed")
    fixed = spec.get("fixed")
    boundary.parse_fixed(fixed, where="shaft.fixed")  # checked before anything runs
    shaft = Shaft(reference, tuple(bearings), tuple(loads), inertia, speed, fixed)
    if speed > 0:
        shaft.check_speed_model(speed)
    return shaft
