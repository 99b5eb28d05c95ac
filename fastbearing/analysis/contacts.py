"""Per-ball results at one operating point: load, deflection, contact angle and the Hertz contact.

Above the API: it reads the ball loads from :func:`fastbearing.ball_loads`
(the one ball loop) and, for a bearing with catalogue geometry, evaluates
each loaded ball's inner and outer race contact with
:mod:`fastbearing.model.geometry`. Units: N, mm, rad; pressures in N/mm^2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

from ..engine import high_speed as hs
from ..engine import schema
from ..engine.kernel import balls_at_speed, balls_stand_still
from ..api import _as_vector, ball_loads, speed_ball_set
from ..model.bearing import COS_PSI, EXPONENT, KN, SIN_PSI, Bearing, check_speed
from ..model.geometry import HertzContact


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
    inner_contact_angle, outer_contact_angle, inner_load, outer_load : ndarray or None
        At shaft speed (else None): each race's contact angle (rad, signed on the row's direction) and
        load (N); ``load`` and ``contact_angle`` are then the inner contact's, ``deflection`` the sum of
        both contacts'.
    centrifugal_force, gyroscopic_moment, orbital_speed : ndarray or None
        At speed: F_c (N), M_g (N*mm; negative with Harris's sign of the ball spin) and the ball's
        orbital (cage) speed omega_m (rad/s).
    equilibrium_residual : ndarray or None
        At speed: the ball's equilibrium residual relative to its largest force.
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
    inner_contact_angle: np.ndarray | None = None
    outer_contact_angle: np.ndarray | None = None
    inner_load: np.ndarray | None = None
    outer_load: np.ndarray | None = None
    centrifugal_force: np.ndarray | None = None
    gyroscopic_moment: np.ndarray | None = None
    orbital_speed: np.ndarray | None = None
    equilibrium_residual: np.ndarray | None = None

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
        return _records(self, ("row", "ball"))


@dataclass(frozen=True)
class RollerContacts:
    """Per roller at a displacement: its row, number in the row, azimuth (rad), total load (N), the largest
    slice load (N), where that slice sits along the roller (x, mm from its middle) and, with a catalogue
    geometry, the largest Hertz line-contact pressure of the inner and outer raceway (N/mm^2)."""

    row: np.ndarray
    roller: np.ndarray
    azimuth: np.ndarray
    load: np.ndarray
    max_slice_load: np.ndarray
    max_slice_position: np.ndarray
    inner_max_pressure: np.ndarray | None = None
    outer_max_pressure: np.ndarray | None = None

    def to_records(self) -> list[dict]:
        """One JSON-ready dict per roller (lengths mm, angles rad, loads N, pressures N/mm^2)."""
        return _records(self, ("row", "roller"))


def _records(arrays, integers) -> list[dict]:
    """A dataclass of per-element arrays as one dict per element; None fields left out."""
    names = [f.name for f in fields(arrays) if getattr(arrays, f.name) is not None]
    return [{n: int(getattr(arrays, n)[i]) if n in integers else float(getattr(arrays, n)[i]) for n in names}
            for i in range(len(arrays.load))]


def slice_loads(bearing: Bearing, q) -> tuple[np.ndarray, list[np.ndarray]]:
    """Every roller's total load (N, by element after the balls) and each roller row's slice loads as a
    (Z, slices) array (N), at displacement q (mm, rad): one evaluation of the one kernel with its
    per-slice record."""
    from ..engine.kernel import ball_loop

    slices = bearing.slice_table()
    n_el, n_sl = bearing.n_elements, slices.shape[1]
    load = np.empty(n_el + n_sl)
    angle = np.empty(n_el + n_sl)
    ball_loop(np.asarray(q, float), bearing.ball_set(), np.empty(5), None, load, angle)
    per_row, k = [], n_el
    for _, r in bearing.roller_rows:
        per_row.append(load[k:k + r.n_rollers * r.slices].reshape(r.n_rollers, r.slices))
        k += r.n_rollers * r.slices
    return load[bearing.n_balls:n_el], per_row


def roller_contacts(bearing: Bearing, q) -> RollerContacts:
    """Per-roller loads and their slices at displacement q (mm, rad), from the one kernel's record.

    The line-contact pressure of a slice carrying q over its width w is Hertz's p = sqrt((q/w) E' / (2 pi
    R)) with R the reduced radius in the rolling direction, Dw (1 - g)/2 at the inner and Dw (1 + g)/2 at
    the outer raceway (g = Dw cos a / dm; Harris & Kotzalas, Essential Concepts, ch. 6).
    """
    from ..api import _as_vector, _operating

    bearing = _operating(bearing, 0.0)  # a mounted bearing: the operating one (rollers: quasi-static)
    q = _as_vector(q, "q", "dx, dy, dz in mm; bx, by in rad")
    return rollers_from_slices(bearing, *slice_loads(bearing, q))


def rollers_from_slices(bearing: Bearing, totals, per_row) -> RollerContacts:
    """:func:`roller_contacts` from the output of :func:`slice_loads` (no further kernel evaluation)."""
    rows, numbers, azimuth, peak, where, widths = [], [], [], [], [], []
    g = bearing.geometry if bearing.geometry is not None and bearing.geometry.element != "ball" else None
    for (i, r), loads in zip(bearing.roller_rows, per_row):
        x = r.slice_positions
        for j in range(r.n_rollers):
            rows.append(i)
            numbers.append(j)
            azimuth.append((math.radians(r.first_element_angle) + 2 * math.pi * j / r.n_rollers) % (2 * math.pi))
            m = int(np.argmax(loads[j]))
            peak.append(loads[j, m])
            where.append(x[m])
            widths.append(r.roller_effective_length / r.slices)
    out = dict(row=np.array(rows, np.int64), roller=np.array(numbers, np.int64), azimuth=np.array(azimuth),
               load=totals, max_slice_load=np.array(peak), max_slice_position=np.array(where))
    if g is not None:
        gam = g.roller_diameter * math.cos(math.radians(g.contact_angle)) / g.pitch_diameter
        per_length = np.array(peak) / np.array(widths)
        for side, R in (("inner", g.roller_diameter * (1 - gam) / 2), ("outer", g.roller_diameter * (1 + gam) / 2)):
            out[f"{side}_max_pressure"] = np.sqrt(per_length * g.reduced_modulus / (2 * math.pi * R))
    return RollerContacts(**out)


def ball_contacts(bearing: Bearing, q, speed=0.0) -> BallContacts:
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
    speed : float
        Shaft speed in rpm (>= 0); above 0 each ball's two contacts, centrifugal force and gyroscopic
        moment are reported too (fastbearing.engine.high_speed), and each race's Hertz contact uses its own
        load and angle.

    Returns
    -------
    BallContacts
    """
    from ..api import _operating

    bearing = _operating(bearing, speed)  # a mounted bearing: the operating one at this speed
    if check_speed(speed) > 0.0:
        return _spinning_contacts(bearing, q, speed)
    Q, alpha = ball_loads(bearing, q)
    table = bearing.ball_table()                 # what the kernel read: one column per ball
    row = bearing.element_rows
    ball = np.concatenate([np.arange(r.n_elements) for _, r in (*bearing.ball_rows, *bearing.roller_rows)])
    rollers = [(math.radians(r.first_element_angle) + 2.0 * math.pi * np.arange(r.n_rollers) / r.n_rollers)
               for _, r in bearing.roller_rows]
    azimuth = np.mod(np.concatenate([np.arctan2(table[SIN_PSI], table[COS_PSI]), *rollers]), 2.0 * math.pi)
    nb = bearing.n_balls
    # a ball's deflection from its load; a roller's total load has no one deflection (its slices differ): nan
    delta = np.concatenate([(np.maximum(Q[:nb], 0.0) / table[KN]) ** (1.0 / table[EXPONENT]),
                            np.full(len(Q) - nb, np.nan)])
    base = dict(row=row, ball=ball, azimuth=azimuth, deflection=delta, load=Q, contact_angle=alpha)
    geometry = getattr(bearing, "geometry", None)
    if geometry is None or geometry.element != "ball":  # no ball geometry: no race contacts to report
        return BallContacts(**base)
    out = {k: np.zeros(len(Q)) for k in ("inner_max_pressure", "inner_semi_major", "inner_semi_minor",
                                          "outer_max_pressure", "outer_semi_major", "outer_semi_minor")}
    cache: dict[float, tuple[HertzContact, HertzContact]] = {}
    for i in np.flatnonzero(Q > 0):
        a = abs(float(alpha[i]))
        if a not in cache:
            cache[a] = geometry.contacts(a)
        for side, contact in zip(("inner", "outer"), cache[a]):
            _fill_contact(out, side, i, contact, Q[i])
    return BallContacts(**base, **out)


def _fill_contact(out: dict, side: str, i: int, contact: HertzContact, load: float) -> None:
    """Ball i's Hertz contact at one race under ``load`` (N): maximum pressure and ellipse semi-axes."""
    major, minor = contact.semi_axes(load)
    out[f"{side}_max_pressure"][i] = contact.max_pressure(load)
    out[f"{side}_semi_major"][i] = major
    out[f"{side}_semi_minor"][i] = minor


def _spinning_contacts(bearing: Bearing, q, speed) -> BallContacts:
    """:func:`ball_contacts` at speed: every ball's settled state from the one high-speed element."""
    q = _as_vector(q, "q", "dx, dy, dz in mm; bx, by in rad")
    balls = speed_ball_set(bearing, speed)
    table, speed_table, omega = balls.balls, balls.speed_table, balls.omega
    n = bearing.n_balls
    states = np.empty((n, schema.N_STATE))
    Q = np.empty(n)
    alpha = np.empty(n)
    if balls_stand_still(speed_table, omega):  # as the kernel takes it: the balls at rest (no F_c, no M_g)
        omega = 0.0
    balls_at_speed(q, table, speed_table, omega, 0.0, np.empty(5), None, Q, alpha, states, hs.new_warm(n),
                   balls.four_point)
    Qo = states[:, schema.STATE_OUTER_LOAD]
    geometry = bearing.geometry
    # each contact's deflection from its own load and Hertz constant
    delta = ((Q / speed_table[schema.K_INNER]) ** (2.0 / 3.0) + (Qo / speed_table[schema.K_OUTER]) ** (2.0 / 3.0))
    out = {k: np.zeros(n) for k in ("inner_max_pressure", "inner_semi_major", "inner_semi_minor",
                                     "outer_max_pressure", "outer_semi_major", "outer_semi_minor")}
    for side, loads, angles in (("inner", Q, states[:, schema.STATE_INNER_ANGLE]),
                                ("outer", Qo, states[:, schema.STATE_OUTER_ANGLE])):
        for i in np.flatnonzero(loads > 0):
            contact = geometry.contacts(abs(float(angles[i])))[0 if side == "inner" else 1]
            _fill_contact(out, side, i, contact, loads[i])
    azimuth = np.mod(np.arctan2(table[SIN_PSI], table[COS_PSI]), 2.0 * math.pi)
    ball = np.concatenate([np.arange(r.n_balls) for _, r in bearing.ball_rows])
    return BallContacts(row=bearing.element_rows, ball=ball, azimuth=azimuth, deflection=delta, load=Q,
                        contact_angle=alpha, **out,
                        inner_contact_angle=states[:, schema.STATE_INNER_ANGLE].copy(),
                        outer_contact_angle=states[:, schema.STATE_OUTER_ANGLE].copy(),
                        inner_load=Q.copy(), outer_load=Qo.copy(),
                        centrifugal_force=states[:, schema.STATE_CENTRIFUGAL].copy(),
                        gyroscopic_moment=states[:, schema.STATE_GYROSCOPIC].copy(),
                        orbital_speed=states[:, schema.STATE_ORBITAL_SPEED].copy(),
                        equilibrium_residual=states[:, schema.STATE_RESIDUAL].copy())
