"""An independent, slow reference for a four-point contact ball row at shaft speed (numpy + scipy, ball by ball).

Written for tests to check a compiled kernel against: plain Python, one ball at a time, no vectorisation and
nothing from fastbearing's engine. It takes a ``fastbearing.Geometry`` and rows (``Bearing.rows``) only for
their public fields. Units throughout: forces N, lengths and displacements mm, angles rad (the rows' and the
geometry's angles are in degrees, as they are given), moments N*mm, speeds rpm outside and rad/s inside.

The model
---------
Each ball touches two contact pairs, a = +1 and a = -1: pair a is an inner arc and an outer arc whose
groove-curvature centres I_a, O_a lie on a line at the nominal angle a0, mirrored for a = -1. Every pair has
its own frame (radial r, axial z_a = a z), the mirrored frame of the Jones-Harris reference
(tests/test_high_speed.py, ``_jones_harris_ball``) for a row of contact direction a. In pair a's frame,
from O_a, written (axial, radial) as Harris writes X1, X2:

    inner groove centre  u_a = (A1_a, A2),  A1_a = a dzb + A0 sin a0,  A2 = dr - rL + A0 cos a0
    ball centre          B_+ = (X1, X2),    B_- = (2 ro sin a0 - X1, X2)

with dr = (dx + z by) cos psi + (dy - z bx) sin psi and dzb = dz + R (bx sin psi - by cos psi) (z the row's
axial offset, R its pitch radius, rL its radial clearance). The ball centre is one point; the two outer arcs'
centres sit 2 ro sin a0 apart axially. A pair is exactly one Jones-Harris ball: its contact deflections and
angles, its loads Q = K max(delta, 0)^1.5, and its own kinematics (rolling without slip at both contacts
about the spin axis at beta; race control per ``geometry.race_control``) giving its orbital speed om_a and
gyroscopic moment Mg_a. The pairs share them by load: w_a = P_a / (P_+ + P_-), P_a = Qi_a + Qo_a (1/2 each
when both are 0); the ball orbits at om = w_+ om_+ + w_- om_- and carries Fc = m (dm/2) om^2 outward, and
pair a's races carry w_a Mg_a by friction as in the reference (lambda_i, lambda_o). The ball's equilibrium
(two equations in X1, X2) adds the pairs' contact and friction terms in pair +'s frame (pair -'s axial term
flips sign) and Fc once. The ring's share of pair a (only where Qi_a > 0) is the reference's
F = Qi n_i + lambda_i (w_a Mg_a / D) t_i and m = lambda_i f_i w_a Mg_a, taken back to the bearing frame with
its axial component and moment times a. No free-ball rule: a ball clear of the inner races rests on the
outer arcs under Fc and gives the inner ring nothing.

Both pairs' inner groove centres are taken at the row's axial offset z (the tilt moves them as it moves
that point, and the ring's moment takes the force there), as the model above writes dr and dzb.
"""

import math
import warnings

import numpy as np
from scipy.optimize import fsolve

#: (lambda_i, lambda_o): the share of the gyroscopic moment carried by friction at each race
RACE_CONTROL_FACTORS = {"outer": (0.0, 2.0), "inner": (1.0, 1.0), "none": (0.0, 0.0)}


class RowConstants:
    """The constants of one ball of a row (all balls of a row alike).

    D mm; ri = (fi - 1/2) D, ro = (fo - 1/2) D, A0 = ri + ro = (fi + fo - 1) D in mm; a0 rad; Ki, Ko the
    race contacts' constants at a0 in N/mm^1.5; mass_radius = m dm/2 in kg*m (Fc in N for om in rad/s);
    J = m D^2/10 in N*mm*s^2 (Mg in N*mm); gamma = D/dm; li, lo the race-control factors; inner_control
    whether the inner race controls the spin; w_i, w_o the rings' speeds in rad/s."""

    def __init__(self, geometry, row, speed):
        g = geometry
        D, dm = g.ball_diameter, g.pitch_diameter
        self.D, self.fi = D, g.inner_groove_ratio
        self.ri = (g.inner_groove_ratio - 0.5) * D
        self.ro = (g.outer_groove_ratio - 0.5) * D
        self.A0 = (g.inner_groove_ratio + g.outer_groove_ratio - 1.0) * D
        self.a0 = math.radians(row.contact_angle)
        inner, outer = g.contacts(self.a0)
        self.Ki, self.Ko = inner.constant, outer.constant
        mass = g.density * math.pi * (D * 1e-3) ** 3 / 6  # kg
        self.mass_radius = mass * dm / 2 * 1e-3
        self.J = mass * D * D / 10 * 1e-3
        self.gamma = D / dm
        self.li, self.lo = RACE_CONTROL_FACTORS[g.race_control]
        self.inner_control = g.race_control == "inner"
        omega = speed * math.pi / 30
        self.w_i, self.w_o = (omega, 0.0) if g.rotating == "inner" else (0.0, omega)


# -- one contact pair: exactly the Jones-Harris ball's `parts`, in the pair's own frame ------------------------
def pair_state(X1, X2, A1, A2, c):
    """Contact pair state for ball centre (X1 axial, X2 radial) and inner groove centre (A1, A2), both in mm
    from the pair's outer groove centre in the pair's frame. Returns a dict: deflections di, do (mm), loads
    Qi, Qo (N), contact angles' sin/cos (sin_i, cos_i, sin_o, cos_o; n_i = (sin_i, cos_i) points from the
    ball centre to the inner groove centre, n_o = (sin_o, cos_o) from the outer groove centre to the ball
    centre), and the pair's Jones-Harris kinematics: spin-axis angle beta (rad), orbital speed om and ball
    spin oR (rad/s), gyroscopic moment Mg (N*mm)."""
    Lo, Li = math.hypot(X1, X2), math.hypot(A1 - X1, A2 - X2)
    do, di = Lo - c.ro, Li - c.ri
    sin_o, cos_o = X1 / Lo, X2 / Lo
    sin_i, cos_i = (A1 - X1) / Li, (A2 - X2) / Li
    g = c.gamma
    # spin axis at beta: rolling without slip at the controlling race's contact
    tan_b = sin_i / (cos_i - g) if c.inner_control else sin_o / (cos_o + g)
    beta = math.atan(tan_b)
    X_i = (1 - g * cos_i) / (cos_i + tan_b * sin_i)  # race speed over ball speed at each contact
    X_o = (1 + g * cos_o) / (cos_o + tan_b * sin_o)
    om = (c.w_i * X_i + c.w_o * X_o) / (X_i + X_o)
    oR = -(om - c.w_o) * X_o / (g * math.cos(beta))
    Mg = c.J * oR * om * math.sin(beta)
    Qi, Qo = c.Ki * max(di, 0.0) ** 1.5, c.Ko * max(do, 0.0) ** 1.5
    return dict(di=di, do=do, Qi=Qi, Qo=Qo, sin_i=sin_i, cos_i=cos_i, sin_o=sin_o, cos_o=cos_o,
                beta=beta, om=om, oR=oR, Mg=Mg)


def pair_terms(p, w, c):
    """The pair's contact and friction forces on the ball (axial, radial) in N, in the pair's frame, with the
    gyroscopic moment it carries w * Mg (the Jones-Harris residual's terms less F_c)."""
    T = w * p["Mg"] / c.D
    axial = p["Qi"] * p["sin_i"] - p["Qo"] * p["sin_o"] - c.li * T * p["cos_i"] + c.lo * T * p["cos_o"]
    radial = p["Qi"] * p["cos_i"] - p["Qo"] * p["cos_o"] + c.li * T * p["sin_i"] - c.lo * T * p["sin_o"]
    return axial, radial


# -- one ball: two pairs, one centre -------------------------------------------------------------------------
def ball_state(x, A1p, A1m, A2, c):
    """The ball at centre x = (X1, X2) (mm from O_+, pair +'s frame) with inner groove centres (A1p, A2) in
    pair +'s frame and (A1m, A2) in pair -'s. Returns a dict: the two pairs' states ``plus``, ``minus``
    (:func:`pair_state`), their weights ``w_plus``, ``w_minus``, the orbital speed ``om`` (rad/s), the
    centrifugal force ``Fc`` (N) and the equilibrium ``residual`` (axial, radial) in N, pair +'s frame."""
    X1, X2 = x
    plus = pair_state(X1, X2, A1p, A2, c)
    minus = pair_state(2 * c.ro * math.sin(c.a0) - X1, X2, A1m, A2, c)  # the same point from O_-, mirrored
    P_plus, P_minus = plus["Qi"] + plus["Qo"], minus["Qi"] + minus["Qo"]
    w_plus = 0.5 if P_plus + P_minus == 0 else P_plus / (P_plus + P_minus)
    w_minus = 1.0 - w_plus
    om = w_plus * plus["om"] + w_minus * minus["om"]
    Fc = c.mass_radius * om * om
    ap, rp = pair_terms(plus, w_plus, c)
    am, rm = pair_terms(minus, w_minus, c)
    residual = (ap - am, rp + rm + Fc)  # pair -'s axial direction is pair +'s reversed
    return dict(plus=plus, minus=minus, w_plus=w_plus, w_minus=w_minus, om=om, Fc=Fc, residual=residual)


def _crossing(A1, A2, c, Fc0):
    """A start for a pair carrying the ball (the Jones-Harris reference's wedged start): where the circles
    about O (radius ro + delta_o) and I = (A1, A2) (radius ri + delta_i) cross on the outer side, with
    Q_o = Q_i + Fc0 and Q_i = Fc0/4 or the pair's load at rest. (X1, X2) in mm, the pair's frame."""
    A = math.hypot(A1, A2)
    Q_rest = (c.Ki ** (-2 / 3) + c.Ko ** (-2 / 3)) ** -1.5 * max(A - c.ri - c.ro, 0.0) ** 1.5
    Qi0 = max(Q_rest, Fc0 / 4)
    Ro, Ri = c.ro + ((Qi0 + Fc0) / c.Ko) ** (2 / 3), c.ri + (Qi0 / c.Ki) ** (2 / 3)
    along = (A * A + Ro * Ro - Ri * Ri) / (2 * A)
    across = math.sqrt(max(Ro * Ro - along * along, 0.0))
    side = 1.0 if A1 >= 0 else -1.0  # the crossing at the larger radius (X2)
    return (along * A1 - side * across * A2) / A, (along * A2 + side * across * A1) / A


def starts(A1p, A1m, A2, c):
    """Starting points (X1, X2) for a ball, pair +'s frame, most likely first: the Jones-Harris wedged start
    of the pair pressed harder (its inner groove centre farther from its outer one), then the other's, their
    midpoint, the ball resting on both outer arcs under F_c at the nominal orbital speed, and the nominal
    centre (ro sin a0, ro cos a0)."""
    s0, c0 = math.sin(c.a0), math.cos(c.a0)
    wm = 0.5 * (c.w_i * (1 - c.gamma * c0) + c.w_o * (1 + c.gamma * c0))
    Fc0 = c.mass_radius * wm * wm
    p = _crossing(A1p, A2, c, Fc0)
    m1, m2 = _crossing(A1m, A2, c, Fc0)
    m = (2 * c.ro * s0 - m1, m2)
    first = [p, m] if math.hypot(A1p, A2) >= math.hypot(A1m, A2) else [m, p]
    rest = c.ro * c0 + (Fc0 / (2 * c.Ko * c0)) ** (2 / 3) / c0  # each outer arc carries Fc0 / (2 cos a0)
    return first + [(0.5 * (p[0] + m[0]), 0.5 * (p[1] + m[1])), (c.ro * s0, rest), (c.ro * s0, c.ro * c0)]


def converged(state):
    """Whether a ball state is in equilibrium: |residual| <= 1e-9 (sum of contact loads + F_c + 1 N)."""
    plus, minus = state["plus"], state["minus"]
    scale = plus["Qi"] + plus["Qo"] + minus["Qi"] + minus["Qo"] + state["Fc"] + 1.0
    return max(abs(r) for r in state["residual"]) <= 1e-9 * scale


def solve_ball(A1p, A1m, A2, c, all_starts=False):
    """The ball's centre (X1, X2) in mm (pair +'s frame) in equilibrium, by scipy's fsolve from
    :func:`starts` in turn (xtol 1e-15); the first that converges (:func:`converged`). Returns
    (x, state). With ``all_starts`` returns the list of (x, state) of every start that converges instead
    (for checking that they agree). Raises AssertionError if none does."""
    found = []
    for x0 in starts(A1p, A1m, A2, c):
        with warnings.catch_warnings():  # a failed try is judged by its residual
            warnings.simplefilter("ignore", RuntimeWarning)
            x = fsolve(lambda y: ball_state(y, A1p, A1m, A2, c)["residual"], x0, xtol=1e-15)
        state = ball_state(x, A1p, A1m, A2, c)
        if converged(state):
            if not all_starts:
                return x, state
            found.append((x, state))
    assert found, ("no start settled the ball", A1p, A1m, A2)
    return found


def ring_share(state, c):
    """The inner ring's load from one ball in the bearing's (radial, axial) directions at the inner groove
    centre: (Fr, Fz) in N and the moment m in N*mm about the tangential axis (the inner friction's lever
    f_i D about the inner groove centre); pair a adds nothing unless Qi_a > 0."""
    Fr = Fz = m = 0.0
    for a, p, w in ((1, state["plus"], state["w_plus"]), (-1, state["minus"], state["w_minus"])):
        if p["Qi"] <= 0:
            continue
        T = w * p["Mg"] / c.D
        Fr += p["Qi"] * p["cos_i"] + c.li * T * p["sin_i"]
        Fz += a * (p["Qi"] * p["sin_i"] - c.li * T * p["cos_i"])
        m += a * c.li * c.fi * w * p["Mg"]
    return Fr, Fz, m


def four_point_load(geometry, rows, q, speed, states=False):
    """f = (Fx, Fy, Fz, Mx, My) in N and N*mm on the inner ring of four-point ball rows at shaft speed
    `speed` (rpm), q = (dx, dy, dz, bx, by) in mm and rad. With states=True also return a list of per-ball dicts
    (Qi_plus, Qo_plus, Qi_minus, Qo_minus in N, br, bz in mm, residual).

    ``geometry``: a fastbearing.Geometry (D, dm, fi, fo, density, race_control, rotating, contacts(a0)).
    ``rows``: objects with n_balls, first_ball_angle (deg), axial_offset z (mm), pitch_radius R (mm),
    radial_clearance rL (mm), contact_angle a0 (deg) (``Bearing.rows``). In the states, balls run row by
    row; br, bz are the ball centre (radial, axial) in mm from pair +'s outer groove centre O_+ in pair +'s
    frame (Harris's X2, X1; for a = +1 that frame's axial is the bearing's z), residual the ball's
    equilibrium residual (axial, radial) in N; also given: the pairs' contact angles alpha_* (rad, atan2 of
    the pair-frame sin, cos), deflections (mm), weights w_plus, w_minus, orbital speed om (rad/s), Fc (N),
    Mg_plus, Mg_minus (N*mm), the row index and psi (rad). At zero speed a ball touching nothing is in
    equilibrium anywhere in its room: its br, bz are then wherever the solver stopped (it gives nothing)."""
    dx, dy, dz, bx, by = (float(v) for v in q)
    f = np.zeros(5)
    out = []
    for k, row in enumerate(rows):
        c = RowConstants(geometry, row, speed)
        z, R, rL = row.axial_offset, row.pitch_radius, row.radial_clearance
        for j in range(row.n_balls):
            psi = math.radians(row.first_ball_angle) + 2 * math.pi * j / row.n_balls
            cp, sp = math.cos(psi), math.sin(psi)
            dr = (dx + z * by) * cp + (dy - z * bx) * sp
            dzb = dz + R * (bx * sp - by * cp)
            A2 = dr - rL + c.A0 * math.cos(c.a0)
            A1p = dzb + c.A0 * math.sin(c.a0)
            A1m = -dzb + c.A0 * math.sin(c.a0)
            x, s = solve_ball(A1p, A1m, A2, c)
            Fr, Fz, m = ring_share(s, c)
            mo = R * Fz - z * Fr + m
            f += (Fr * cp, Fr * sp, Fz, mo * sp, -mo * cp)
            if states:
                P, M = s["plus"], s["minus"]
                out.append(dict(row=k, psi=psi, Qi_plus=P["Qi"], Qo_plus=P["Qo"], Qi_minus=M["Qi"],
                                Qo_minus=M["Qo"], br=float(x[1]), bz=float(x[0]), residual=s["residual"],
                                alpha_i_plus=math.atan2(P["sin_i"], P["cos_i"]),
                                alpha_o_plus=math.atan2(P["sin_o"], P["cos_o"]),
                                alpha_i_minus=math.atan2(M["sin_i"], M["cos_i"]),
                                alpha_o_minus=math.atan2(M["sin_o"], M["cos_o"]),
                                di_plus=P["di"], do_plus=P["do"], di_minus=M["di"], do_minus=M["do"],
                                w_plus=s["w_plus"], w_minus=s["w_minus"], om=s["om"], Fc=s["Fc"],
                                Mg_plus=P["Mg"], Mg_minus=M["Mg"]))
    return (f, out) if states else f
