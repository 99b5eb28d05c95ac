"""Four-point contact balls at shaft speed: one ball, up to four contacts (docs/model.md, "Four-point contact balls").

The ball table holds a four-point row as its two contact pairs (model/four_point.py): columns j (pair +a0) and
PARTNER j (pair -a0) are the same ball. Standing still each pair is an angular contact row (the quasi-static
loop); at speed the ball's centre B is one point in both pairs' frames and settles under all four contacts,
its centrifugal force F_c and gyroscopic moment M_g. In pair a's frame (its outer groove centre O_a at the
origin, axial axis along the pair's contact direction, as high_speed.ball_state's) the contacts, loads and
rolling kinematics are the angular contact ball's; B in pair -'s frame is (B_r, 2 r_o sin a0 - B_z), the two
outer arcs' centres sitting 2 r_o sin a0 apart, r_o = (f_o - 1/2) D. The pairs share the ball's motion by
their loads: with w_a = (Q_i,a + Q_o,a) / sum, the orbital speed is sum w_a omega_m,a (so F_c = m d_m/2
omega_m^2), and pair a's races carry w_a M_g,a by its own race control. A ball whose pair - carries nothing
is exactly the angular contact ball of pair +.

f is the model's; the derivatives (the ball's Newton Jacobian and Kb, condensed over B as the angular contact
ball's: dF/du = F_u - F_B G_B^-1 G_u) are exact to rounding, real arithmetic: Kb's six columns and a moved
ball's look (:func:`ball_jacobian`) take each pair's contacts, angles and kinematics in closed form
(high_speed.ball_state's terms) and combine the pairs in dual numbers; the settle's Newton steps take dG/dB in
dual numbers of two derivatives; the all-dual six-column pass stays as :func:`dual_jacobian`, an oracle. The complex step it replaced
(:func:`_derivative`, d y/dx = Im y(x + i h)/h, h = 1e-20 mm) stays as the tests' oracle. Which of several
roots a ball takes is a property of q alone (:func:`canonical_settle`). Units: mm, N, N*mm, rad, rad/s.
"""

import cmath
import math

import numpy as np
from numba import njit, types
from numba.extending import overload

from ..config import CACHE, ERROR_MODEL, KERNEL_FASTMATH, REFCOUNT
from .deflection import deflection
from .high_speed import (BALL_RTOL, LINEAR_REACH, _ball_constants, _inner_centre, contact_hessian, kinematics,
                         start_position, warm_cell, warm_x, write_contacts, write_state)
from .schema import (AXIAL_OFFSET, COS_NOMINAL, COS_PSI, DEFLECTION_LIMIT, DIAMETER, DIRECTION, GAMMA, INERTIA,
                     INNER_ARM, INNER_CONTROL, INNER_RADIUS, K_INNER, K_OUTER, LAMBDA_INNER, LAMBDA_OUTER,
                     MASS_RADIUS, N_WARM, OUTER_RADIUS, PITCH_RADIUS, SIN_PSI, WARM_BR, WARM_BZ,
                     WARM_LINEARISE, WARM_UR, WARM_UZ, WARM_VALID, WARM_X00, WARM_X01, WARM_X10, WARM_X11)

#: The Jacobian's stand-in where neither Kb nor a warm start needs it (an f-only evaluation or a record).
_NO_JACOBIAN = ((1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0), (0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)) + \
    ((0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0),) * 4
#: The complex step (mm): far below any length of the model, far above underflow.
STEP = 1e-20
#: Newton iterations a four-point ball may take to settle.
ITERATIONS = 60
#: Halvings of a Newton step that does not lower the residual.
HALVINGS = 40
#: The canonical root's continuation in speed (:func:`canonical_settle`): its steps, and the halvings of a
#: step that does not settle allowed in all.
SPEED_STEPS = 8
SPEED_HALVINGS = 12


def root(x):
    """sqrt of a float or of a complex (the complex step's)."""


@overload(root, inline="always")
def _root(x):
    if isinstance(x, types.Complex):
        return lambda x: cmath.sqrt(x)
    return lambda x: math.sqrt(x)


def quotient(a, b):
    """a / b of floats or complexes; a complex 0 divisor gives NaN (numba's complex division raises
    ZeroDivisionError whatever the error model, and nothing may raise in a kernel: issue 47, a one-ball
    bearing's wild Newton trial put a ball centre on a groove centre)."""


@overload(quotient, inline="always")
def _quotient(a, b):
    if isinstance(b, types.Complex):
        def complex_quotient(a, b):
            if b.real == 0.0 and b.imag == 0.0:
                return complex(math.nan, math.nan)
            return a / b
        return complex_quotient
    return lambda a, b: a / b


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _orbit(ci, si, co, so, w_i, w_o, gamma, inner_control):
    """(omega_m rad/s, S) of high_speed.kinematics (its values, not its gradients), float or complex, with
    :func:`quotient`'s division."""
    C = ci * co + si * so
    den = 1.0 + C
    if inner_control:
        b = 1.0 + gamma * co
        wm = quotient(w_i * (C - gamma * co) + w_o * b, den)
        return wm, quotient(wm * b * si, den)
    a = 1.0 - gamma * ci
    wm = quotient(w_i * a + w_o * (C + gamma * ci), den)
    return wm, quotient(wm * a * so, den)


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _contact(L, r0, k, eps):
    """(deflection, load) of a race contact at centre distance L (mm) from a groove of radius r0, Hertz
    constant k (N/mm^1.5): delta = L - r0 clamped (or, with the solver's eps > 0, smoothed), Q = k delta^1.5.
    The clamp reads the real part: the complex step passes through a loaded contact and stops at an open one."""
    d = L - r0
    if eps > 0.0:
        delta = 0.5 * (d + root(d * d + eps * eps))
    elif d.real > 0.0:
        delta = d
    else:
        delta = 0.0 * d
    return delta, k * delta * root(delta)


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _pair(ur, uz, br, bz, p, w_i, w_o, eps):
    """One contact pair in its frame: inner groove centre u, ball centre B (mm from the pair's outer groove
    centre). Returns (Q_i, Q_o, ci, si, co, so, omega_m, S, delta_i, delta_o) as high_speed.ball_state
    takes them (M_g = J (w_o - w_i)/gamma' S)."""
    Lo = root(br * br + bz * bz)
    co = quotient(br, Lo)
    so = quotient(bz, Lo)
    vr = ur - br
    vz = uz - bz
    Li = root(vr * vr + vz * vz)
    ci = quotient(vr, Li)
    si = quotient(vz, Li)
    d_o, Qo = _contact(Lo, p[OUTER_RADIUS], p[K_OUTER], eps)
    d_i, Qi = _contact(Li, p[INNER_RADIUS], p[K_INNER], eps)
    wm, S = _orbit(ci, si, co, so, w_i, w_o, p[GAMMA], p[INNER_CONTROL] != 0.0)
    return Qi, Qo, ci, si, co, so, wm, S, d_i, d_o


@njit(cache=CACHE, fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL, _nrt=REFCOUNT)
def four_point_ball(br, bz, u1r, u1z, u2r, u2z, p, w_i, w_o, eps):
    """A four-point ball at centre B = (br, bz) (mm, pair +'s frame) between the inner groove centres u1 (pair
    +'s frame) and u2 (pair -'s): its residual g (N, pair +'s frame), each pair's ring share (F_r, F_z in N,
    m in N*mm, in the pair's frame; nothing where the pair's inner contact is open) and what a record needs.
    Float or complex throughout (complex: the tests' complex-step oracle, :func:`_derivative`); not inlined,
    so that it compiles once per type, not once per caller."""
    s0 = math.sqrt(1.0 - p[COS_NOMINAL] * p[COS_NOMINAL])
    Qi1, Qo1, ci1, si1, co1, so1, wm1, S1, di1, do1 = _pair(u1r, u1z, br, bz, p, w_i, w_o, eps)
    Qi2, Qo2, ci2, si2, co2, so2, wm2, S2, di2, do2 = _pair(u2r, u2z, br, 2.0 * p[OUTER_RADIUS] * s0 - bz, p,
                                                            w_i, w_o, eps)
    P1 = Qi1 + Qo1
    total = P1 + Qi2 + Qo2
    w1 = quotient(P1, total) if total.real > 0.0 else 0.5 + 0.0 * total
    w2 = 1.0 - w1
    wm = w1 * wm1 + w2 * wm2
    Fc = p[MASS_RADIUS] * wm * wm
    jc = p[INERTIA] * (w_o - w_i) / p[GAMMA]
    f1 = w1 * jc * S1 / p[DIAMETER]  # the friction force w_a M_g,a / D of each pair's races
    f2 = w2 * jc * S2 / p[DIAMETER]
    li = p[LAMBDA_INNER]
    lo = p[LAMBDA_OUTER]
    g1r = Qi1 * ci1 - Qo1 * co1 + f1 * (li * si1 - lo * so1)
    g1z = Qi1 * si1 - Qo1 * so1 + f1 * (lo * co1 - li * ci1)
    g2r = Qi2 * ci2 - Qo2 * co2 + f2 * (li * si2 - lo * so2)
    g2z = Qi2 * si2 - Qo2 * so2 + f2 * (lo * co2 - li * ci2)
    on1 = Qi1.real > 0.0 or eps != 0.0
    on2 = Qi2.real > 0.0 or eps != 0.0
    zero = 0.0 * total
    arm = li * p[INNER_ARM]  # the inner friction's moment about the inner groove centre: li f_i D (M_g/D)
    return ((g1r + g2r + Fc, g1z - g2z,
             Qi1 * ci1 + li * f1 * si1 if on1 else zero, Qi1 * si1 - li * f1 * ci1 if on1 else zero,
             arm * f1 if on1 else zero,
             Qi2 * ci2 + li * f2 * si2 if on2 else zero, Qi2 * si2 - li * f2 * ci2 if on2 else zero,
             arm * f2 if on2 else zero),
            (Qi1, Qo1, Qi2, Qo2, ci1, si1, co1, so1, ci2, si2, co2, so2, Fc, w1 * jc * S1 + w2 * jc * S2, wm,
             di1, do1, di2, do2))


@njit(cache=CACHE, fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL, _nrt=REFCOUNT)
def _derivative(x, k, p, w_i, w_o, eps):
    """d(g, F_1, m_1, F_2, m_2)/dx_k (8 values) at x = (br, bz, u1r, u1z, u2r, u2z) by complex step: the oracle
    of :func:`ball_jacobian` in the tests (the kernel does not call it)."""
    h = STEP
    y = four_point_ball(complex(x[0], h if k == 0 else 0.0), complex(x[1], h if k == 1 else 0.0),
                        complex(x[2], h if k == 2 else 0.0), complex(x[3], h if k == 3 else 0.0),
                        complex(x[4], h if k == 4 else 0.0), complex(x[5], h if k == 5 else 0.0),
                        p, w_i, w_o, eps)[0]
    return (y[0].imag / h, y[1].imag / h, y[2].imag / h, y[3].imag / h, y[4].imag / h, y[5].imag / h,
            y[6].imag / h, y[7].imag / h)


# -- forward-mode dual numbers: (value, its derivatives along 6 inputs (br, bz, u1r, u1z, u2r, u2z) or 2 (br, bz))

def _width(t):
    """The number of derivatives a dual number of numba type ``t`` carries (its length less one)."""
    return len(t.types) - 1 if isinstance(t, types.BaseTuple) else -1


def dconst(c, like):
    """The constant c as a dual number of ``like``'s width (its derivatives 0)."""


@overload(dconst, inline="always")
def _dconst(c, like):
    if _width(like) == 2:
        def impl2(c, like):
            return (c, 0.0, 0.0)
        return impl2
    if _width(like) == 6:
        def impl6(c, like):
            return (c, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
        return impl6


def dadd(a, b):
    """a + b."""


@overload(dadd, inline="always")
def _dadd(a, b):
    if _width(a) == 2:
        def impl2(a, b):
            return (a[0] + b[0], a[1] + b[1], a[2] + b[2])
        return impl2
    if _width(a) == 6:
        def impl6(a, b):
            return (a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3], a[4] + b[4], a[5] + b[5], a[6] + b[6])
        return impl6


def dsub(a, b):
    """a - b."""


@overload(dsub, inline="always")
def _dsub(a, b):
    if _width(a) == 2:
        def impl2(a, b):
            return (a[0] - b[0], a[1] - b[1], a[2] - b[2])
        return impl2
    if _width(a) == 6:
        def impl6(a, b):
            return (a[0] - b[0], a[1] - b[1], a[2] - b[2], a[3] - b[3], a[4] - b[4], a[5] - b[5], a[6] - b[6])
        return impl6


def dshift(a, c):
    """a + c, c a float."""


@overload(dshift, inline="always")
def _dshift(a, c):
    if _width(a) == 2:
        def impl2(a, c):
            return (a[0] + c, a[1], a[2])
        return impl2
    if _width(a) == 6:
        def impl6(a, c):
            return (a[0] + c, a[1], a[2], a[3], a[4], a[5], a[6])
        return impl6


def dscale(c, a):
    """c a, c a float."""


@overload(dscale, inline="always")
def _dscale(c, a):
    if _width(a) == 2:
        def impl2(c, a):
            return (c * a[0], c * a[1], c * a[2])
        return impl2
    if _width(a) == 6:
        def impl6(c, a):
            return (c * a[0], c * a[1], c * a[2], c * a[3], c * a[4], c * a[5], c * a[6])
        return impl6


def dmul(a, b):
    """a b."""


@overload(dmul, inline="always")
def _dmul(a, b):
    if _width(a) == 2:
        def impl2(a, b):
            return (a[0] * b[0], a[0] * b[1] + a[1] * b[0], a[0] * b[2] + a[2] * b[0])
        return impl2
    if _width(a) == 6:
        def impl6(a, b):
            return (a[0] * b[0], a[0] * b[1] + a[1] * b[0], a[0] * b[2] + a[2] * b[0], a[0] * b[3] + a[3] * b[0],
                    a[0] * b[4] + a[4] * b[0], a[0] * b[5] + a[5] * b[0],
                    a[0] * b[6] + a[6] * b[0])
        return impl6


def ddiv(a, b):
    """a / b (a zero b: inf or NaN under the numpy error model, never an exception)."""


@overload(ddiv, inline="always")
def _ddiv(a, b):
    if _width(a) == 2:
        def impl2(a, b):
            v = a[0] / b[0]
            return (v, (a[1] - v * b[1]) / b[0], (a[2] - v * b[2]) / b[0])
        return impl2
    if _width(a) == 6:
        def impl6(a, b):
            v = a[0] / b[0]
            return (v, (a[1] - v * b[1]) / b[0], (a[2] - v * b[2]) / b[0], (a[3] - v * b[3]) / b[0],
                    (a[4] - v * b[4]) / b[0], (a[5] - v * b[5]) / b[0], (a[6] - v * b[6]) / b[0])
        return impl6


def dsqrt(a):
    """sqrt(a), a > 0."""


@overload(dsqrt, inline="always")
def _dsqrt(a):
    if _width(a) == 2:
        def impl2(a):
            v = math.sqrt(a[0])
            h = 0.5 / v
            return (v, h * a[1], h * a[2])
        return impl2
    if _width(a) == 6:
        def impl6(a):
            v = math.sqrt(a[0])
            h = 0.5 / v
            return (v, h * a[1], h * a[2], h * a[3], h * a[4], h * a[5], h * a[6])
        return impl6


def dhertz(delta, k):
    """k delta^1.5 of a deflection delta >= 0: its derivative 1.5 k delta^0.5 delta' (0 at delta = 0,
    where the chain rule through a sqrt would give inf times 0)."""


@overload(dhertz, inline="always")
def _dhertz(delta, k):
    if _width(delta) == 2:
        def impl2(delta, k):
            sq = math.sqrt(delta[0])
            h = 1.5 * k * sq
            return (k * delta[0] * sq, h * delta[1], h * delta[2])
        return impl2
    if _width(delta) == 6:
        def impl6(delta, k):
            sq = math.sqrt(delta[0])
            h = 1.5 * k * sq
            return (k * delta[0] * sq, h * delta[1], h * delta[2], h * delta[3], h * delta[4], h * delta[5],
                    h * delta[6])
        return impl6


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _dual_contact(L, r0, k, eps):
    """:func:`_contact` of a dual number L: (deflection, load)."""
    d = dshift(L, -r0)
    if eps > 0.0:
        delta = dscale(0.5, dadd(d, dsqrt(dshift(dmul(d, d), eps * eps))))
    elif d[0] > 0.0:
        delta = d
    else:
        delta = dconst(0.0, L)
    return delta, dhertz(delta, k)


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _dual_orbit(ci, si, co, so, w_i, w_o, gamma, inner_control):
    """:func:`_orbit` of dual numbers: (omega_m, S)."""
    C = dadd(dmul(ci, co), dmul(si, so))
    den = dshift(C, 1.0)
    if inner_control:
        b = dshift(dscale(gamma, co), 1.0)
        wm = ddiv(dadd(dscale(w_i, dsub(C, dscale(gamma, co))), dscale(w_o, b)), den)
        return wm, ddiv(dmul(dmul(wm, b), si), den)
    a = dshift(dscale(-gamma, ci), 1.0)
    wm = ddiv(dadd(dscale(w_i, a), dscale(w_o, dadd(C, dscale(gamma, ci)))), den)
    return wm, ddiv(dmul(dmul(wm, a), so), den)


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _dual_pair(ur, uz, br, bz, p, w_i, w_o, eps):
    """:func:`_pair` of dual numbers: (Q_i, Q_o, ci, si, co, so, omega_m, S)."""
    Lo = dsqrt(dadd(dmul(br, br), dmul(bz, bz)))
    co = ddiv(br, Lo)
    so = ddiv(bz, Lo)
    vr = dsub(ur, br)
    vz = dsub(uz, bz)
    Li = dsqrt(dadd(dmul(vr, vr), dmul(vz, vz)))
    ci = ddiv(vr, Li)
    si = ddiv(vz, Li)
    _, Qo = _dual_contact(Lo, p[OUTER_RADIUS], p[K_OUTER], eps)
    _, Qi = _dual_contact(Li, p[INNER_RADIUS], p[K_INNER], eps)
    wm, S = _dual_orbit(ci, si, co, so, w_i, w_o, p[GAMMA], p[INNER_CONTROL] != 0.0)
    return Qi, Qo, ci, si, co, so, wm, S


@njit(inline="always")
def _column(y0, y1, y2, y3, y4, y5, y6, y7, i):
    """Component i of the eight dual numbers."""
    return (y0[i], y1[i], y2[i], y3[i], y4[i], y5[i], y6[i], y7[i])


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _pairs_shared(P1, P2, wm1, wm2, S1, S2, p, w_i, w_o, like):
    """What the ball's two contact pairs share, in dual numbers of ``like``'s width, from each pair's contact
    load sum P (N), orbital speed wm (rad/s) and spin factor S: each pair weighted by its load (w1 = P1 / (P1 +
    P2), half each when both are unloaded), the ball's omega_m = w1 wm1 + w2 wm2, its centrifugal force F_c (N)
    and each pair's gyroscopic friction factor f = J (w_o - w_i) / (gamma' D) w S (N). Returns (F_c, f1, f2)."""
    total = dadd(P1, P2)
    w1 = ddiv(P1, total) if total[0] > 0.0 else dconst(0.5, like)
    w2 = dsub(dconst(1.0, like), w1)
    wm = dadd(dmul(w1, wm1), dmul(w2, wm2))
    Fc = dscale(p[MASS_RADIUS], dmul(wm, wm))
    jd = p[INERTIA] * (w_o - w_i) / p[GAMMA] / p[DIAMETER]
    return Fc, dscale(jd, dmul(w1, S1)), dscale(jd, dmul(w2, S2))


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _dual_ball(br, bz, u1r, u1z, u2r, u2z, p, w_i, w_o, eps):
    """:func:`four_point_ball`'s first output, (g_r, g_z, F_1, m_1, F_2, m_2), in dual numbers of any width."""
    s0 = math.sqrt(1.0 - p[COS_NOMINAL] * p[COS_NOMINAL])
    Qi1, Qo1, ci1, si1, co1, so1, wm1, S1 = _dual_pair(u1r, u1z, br, bz, p, w_i, w_o, eps)
    bz2 = dsub(dconst(2.0 * p[OUTER_RADIUS] * s0, br), bz)  # B from O_-, in pair -'s frame
    Qi2, Qo2, ci2, si2, co2, so2, wm2, S2 = _dual_pair(u2r, u2z, br, bz2, p, w_i, w_o, eps)
    Fc, f1, f2 = _pairs_shared(dadd(Qi1, Qo1), dadd(Qi2, Qo2), wm1, wm2, S1, S2, p, w_i, w_o, br)
    li = p[LAMBDA_INNER]
    lo = p[LAMBDA_OUTER]
    g1r = dadd(dsub(dmul(Qi1, ci1), dmul(Qo1, co1)), dmul(f1, dsub(dscale(li, si1), dscale(lo, so1))))
    g1z = dadd(dsub(dmul(Qi1, si1), dmul(Qo1, so1)), dmul(f1, dsub(dscale(lo, co1), dscale(li, ci1))))
    g2r = dadd(dsub(dmul(Qi2, ci2), dmul(Qo2, co2)), dmul(f2, dsub(dscale(li, si2), dscale(lo, so2))))
    g2z = dadd(dsub(dmul(Qi2, si2), dmul(Qo2, so2)), dmul(f2, dsub(dscale(lo, co2), dscale(li, ci2))))
    on1 = Qi1[0] > 0.0 or eps != 0.0
    on2 = Qi2[0] > 0.0 or eps != 0.0
    zero = dconst(0.0, br)
    arm = li * p[INNER_ARM]
    y0 = dadd(dadd(g1r, g2r), Fc)
    y1 = dsub(g1z, g2z)
    y2 = dadd(dmul(Qi1, ci1), dscale(li, dmul(f1, si1))) if on1 else zero
    y3 = dsub(dmul(Qi1, si1), dscale(li, dmul(f1, ci1))) if on1 else zero
    y4 = dscale(arm, f1) if on1 else zero
    y5 = dadd(dmul(Qi2, ci2), dscale(li, dmul(f2, si2))) if on2 else zero
    y6 = dsub(dmul(Qi2, si2), dscale(li, dmul(f2, ci2))) if on2 else zero
    y7 = dscale(arm, f2) if on2 else zero
    return y0, y1, y2, y3, y4, y5, y6, y7


@njit(cache=CACHE, fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL, _nrt=REFCOUNT)
def dual_jacobian(x, p, w_i, w_o, eps):
    """:func:`ball_jacobian` in forward-mode dual numbers throughout (each quantity carried with its six partial
    derivatives, real arithmetic, exact to rounding as the complex step, :func:`_derivative`): the hand-written
    Jacobian's oracle in the tests (the kernel does not call it)."""
    z6 = 0.0
    y0, y1, y2, y3, y4, y5, y6, y7 = _dual_ball((x[0], 1.0, z6, z6, z6, z6, z6), (x[1], z6, 1.0, z6, z6, z6, z6),
                                                (x[2], z6, z6, 1.0, z6, z6, z6), (x[3], z6, z6, z6, 1.0, z6, z6),
                                                (x[4], z6, z6, z6, z6, 1.0, z6), (x[5], z6, z6, z6, z6, z6, 1.0),
                                                p, w_i, w_o, eps)
    return (_column(y0, y1, y2, y3, y4, y5, y6, y7, 1), _column(y0, y1, y2, y3, y4, y5, y6, y7, 2),
            _column(y0, y1, y2, y3, y4, y5, y6, y7, 3), _column(y0, y1, y2, y3, y4, y5, y6, y7, 4),
            _column(y0, y1, y2, y3, y4, y5, y6, y7, 5), _column(y0, y1, y2, y3, y4, y5, y6, y7, 6))


# -- the Jacobian by hand (issue 47 item 6): each pair's contacts, angles and kinematics differentiated in closed
# form (high_speed.ball_state's terms: dQ n/dB = Q' n n^T + (Q/L)(I - n n^T) per contact, the angles through the
# projections (I - n n^T)/L), lifted into dual numbers only where the pairs combine (the load weights, omega_m,
# F_c and the friction forces): about a third of the dual pass's arithmetic, no six-wide division per angle.

def dlift(val, b_r, b_z, u_r, u_z, second, like):
    """A pair's quantity as a dual number of ``like``'s width: its value and its gradients along the pair's own
    B (b_r, b_z) and inner groove centre u (u_r, u_z), pair - (``second``) mirrored in B_z (its B_z is
    2 r_o sin a0 - bz) and placed in u2's columns; at width 2 only the B columns."""


@overload(dlift, inline="always")
def _dlift(val, b_r, b_z, u_r, u_z, second, like):
    if _width(like) == 2:
        def impl2(val, b_r, b_z, u_r, u_z, second, like):
            return (val, b_r, -b_z if second else b_z)
        return impl2
    if _width(like) == 6:
        def impl6(val, b_r, b_z, u_r, u_z, second, like):
            if second:
                return (val, b_r, -b_z, 0.0, 0.0, u_r, u_z)
            return (val, b_r, b_z, u_r, u_z, 0.0, 0.0)
        return impl6


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _hand_pair(ur, uz, br, bz, p, w_i, w_o, eps, second, like):
    """One contact pair (:func:`_pair`'s arguments, floats) as dual numbers of ``like``'s width, their derivatives
    in closed form: (P = Q_i + Q_o, omega_m, S, c_r, c_z (the contact part of g: Q_i n_i - Q_o n_o), T_r, T_z (the
    friction's direction li t_i - lo t_o, t = (sin a, -cos a)), Q_i n_i, t_i, Q_i > 0)."""
    Lo = math.sqrt(br * br + bz * bz)
    inv_o = 1.0 / Lo
    co = br * inv_o
    so = bz * inv_o
    vr = ur - br
    vz = uz - bz
    Li = math.sqrt(vr * vr + vz * vz)
    inv_i = 1.0 / Li
    ci = vr * inv_i
    si = vz * inv_i
    d_o, slope_o = deflection(Lo - p[OUTER_RADIUS], eps)
    d_i, slope_i = deflection(Li - p[INNER_RADIUS], eps)
    sq_o = math.sqrt(d_o)
    sq_i = math.sqrt(d_i)
    Qo = p[K_OUTER] * d_o * sq_o
    Qi = p[K_INNER] * d_i * sq_i
    dQo = 1.5 * p[K_OUTER] * sq_o * slope_o
    dQi = 1.5 * p[K_INNER] * sq_i * slope_i
    wm, m_ci, m_si, m_co, m_so, S, s_ci, s_si, s_co, s_so = kinematics(ci, si, co, so, w_i, w_o, p[GAMMA],
                                                                      p[INNER_CONTROL] != 0.0)
    # the projections (I - n n^T)/L: d n/dB of the outer normal, d n/du (= -d n/dB) of the inner one
    por, poc, poz = so * so * inv_o, -co * so * inv_o, co * co * inv_o
    pir, pic, piz = si * si * inv_i, -ci * si * inv_i, ci * ci * inv_i
    wm_ur = m_ci * pir + m_si * pic
    wm_uz = m_ci * pic + m_si * piz
    S_ur = s_ci * pir + s_si * pic
    S_uz = s_ci * pic + s_si * piz
    # the contact Hessians H = Q' n n^T + (Q/L)(I - n n^T)
    gi = Qi * inv_i
    go = Qo * inv_o
    hi_rr, hi_rz, hi_zz = contact_hessian(dQi, gi, ci, si)
    ho_rr, ho_rz, ho_zz = contact_hessian(dQo, go, co, so)
    li = p[LAMBDA_INNER]
    lo = p[LAMBDA_OUTER]
    P = dlift(Qi + Qo, dQo * co - dQi * ci, dQo * so - dQi * si, dQi * ci, dQi * si, second, like)
    wmd = dlift(wm, m_co * por + m_so * poc - wm_ur, m_co * poc + m_so * poz - wm_uz, wm_ur, wm_uz, second, like)
    Sd = dlift(S, s_co * por + s_so * poc - S_ur, s_co * poc + s_so * poz - S_uz, S_ur, S_uz, second, like)
    c_r = dlift(Qi * ci - Qo * co, -hi_rr - ho_rr, -hi_rz - ho_rz, hi_rr, hi_rz, second, like)
    c_z = dlift(Qi * si - Qo * so, -hi_rz - ho_rz, -hi_zz - ho_zz, hi_rz, hi_zz, second, like)
    T_r = dlift(li * si - lo * so, -li * pic - lo * poc, -li * piz - lo * poz, li * pic, li * piz, second, like)
    T_z = dlift(lo * co - li * ci, li * pir + lo * por, li * pic + lo * poc, -li * pir, -li * pic, second, like)
    F_r = dlift(Qi * ci, -hi_rr, -hi_rz, hi_rr, hi_rz, second, like)
    F_z = dlift(Qi * si, -hi_rz, -hi_zz, hi_rz, hi_zz, second, like)
    t_r = dlift(si, -pic, -piz, pic, piz, second, like)
    t_z = dlift(-ci, pir, pic, -pir, -pic, second, like)
    return P, wmd, Sd, c_r, c_z, T_r, T_z, F_r, F_z, t_r, t_z, Qi > 0.0


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _hand_ball(x, p, w_i, w_o, eps, like):
    """:func:`_dual_ball` at x = (br, bz, u1r, u1z, u2r, u2z) (floats), its derivatives from :func:`_hand_pair`,
    as dual numbers of ``like``'s width (6: all of x; 2: B alone)."""
    s0 = math.sqrt(1.0 - p[COS_NOMINAL] * p[COS_NOMINAL])
    P1, wm1, S1, c1r, c1z, T1r, T1z, F1r, F1z, t1r, t1z, on1 = _hand_pair(x[2], x[3], x[0], x[1], p, w_i, w_o, eps,
                                                                          False, like)
    P2, wm2, S2, c2r, c2z, T2r, T2z, F2r, F2z, t2r, t2z, on2 = _hand_pair(x[4], x[5], x[0],
                                                                          2.0 * p[OUTER_RADIUS] * s0 - x[1], p,
                                                                          w_i, w_o, eps, True, like)
    Fc, f1, f2 = _pairs_shared(P1, P2, wm1, wm2, S1, S2, p, w_i, w_o, like)
    li = p[LAMBDA_INNER]
    on1 = on1 or eps != 0.0
    on2 = on2 or eps != 0.0
    zero = dconst(0.0, like)
    arm = li * p[INNER_ARM]
    y0 = dadd(dadd(dadd(c1r, dmul(f1, T1r)), dadd(c2r, dmul(f2, T2r))), Fc)
    y1 = dsub(dadd(c1z, dmul(f1, T1z)), dadd(c2z, dmul(f2, T2z)))
    y2 = dadd(F1r, dscale(li, dmul(f1, t1r))) if on1 else zero
    y3 = dadd(F1z, dscale(li, dmul(f1, t1z))) if on1 else zero
    y4 = dscale(arm, f1) if on1 else zero
    y5 = dadd(F2r, dscale(li, dmul(f2, t2r))) if on2 else zero
    y6 = dadd(F2z, dscale(li, dmul(f2, t2z))) if on2 else zero
    y7 = dscale(arm, f2) if on2 else zero
    return y0, y1, y2, y3, y4, y5, y6, y7


@njit(cache=CACHE, fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL, _nrt=REFCOUNT)
def ball_jacobian(x, p, w_i, w_o, eps):
    """d(g, F_1, m_1, F_2, m_2)/dx (six columns of 8 values, column k along x_k) at x = (br, bz, u1r, u1z, u2r,
    u2z) (mm; g, F in N, m in N*mm): each pair's derivatives in closed form (:func:`_hand_pair`), combined in
    dual numbers (:func:`_hand_ball`); real arithmetic, exact to rounding (the tests hold it to the all-dual
    :func:`dual_jacobian` and the complex step, :func:`_derivative`)."""
    y0, y1, y2, y3, y4, y5, y6, y7 = _hand_ball(x, p, w_i, w_o, eps, (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0))
    return (_column(y0, y1, y2, y3, y4, y5, y6, y7, 1), _column(y0, y1, y2, y3, y4, y5, y6, y7, 2),
            _column(y0, y1, y2, y3, y4, y5, y6, y7, 3), _column(y0, y1, y2, y3, y4, y5, y6, y7, 4),
            _column(y0, y1, y2, y3, y4, y5, y6, y7, 5), _column(y0, y1, y2, y3, y4, y5, y6, y7, 6))


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _newton_jacobian(br, bz, u, p, w_i, w_o, eps):
    """dg/dB alone, ((dg_r, dg_z)/dB_r, (dg_r, dg_z)/dB_z), in dual numbers of two derivatives (the settle's
    iterations; the ring's outputs, unused, fall away when this is compiled inline). Left in dual numbers: the
    hand-written pass (:func:`_hand_ball`) costs the same here (0.086 us a call, the cost being the square
    roots and divisions both share) and, inlined, rounds one ulp differently in another caller, so that a
    settle called directly and one inside :func:`canonical_settle` would no longer agree bit for bit."""
    y0, y1, _, _, _, _, _, _ = _dual_ball((br, 1.0, 0.0), (bz, 0.0, 1.0), (u[2], 0.0, 0.0), (u[3], 0.0, 0.0),
                                          (u[4], 0.0, 0.0), (u[5], 0.0, 0.0), p, w_i, w_o, eps)
    return (y0[1], y1[1]), (y0[2], y1[2])


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _residual(br, bz, u, p, w_i, w_o, eps):
    """(largest residual component N, force scale N, and the ball's evaluation (y, st)) at B."""
    y, st = four_point_ball(br, bz, u[2], u[3], u[4], u[5], p, w_i, w_o, eps)
    return max(abs(y[0]), abs(y[1])), st[0] + st[1] + st[2] + st[3] + abs(st[12]), y, st


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _cold_guess(u, p, w_i, w_o):
    """A first centre B (mm, pair +'s frame), from u alone: each loaded pair's angular contact start
    (high_speed.start_position: the inner contact loaded with max(Q, F_c0/4), the outer with that plus F_c0,
    B where the two contacts' circles cross on the outer side; Q the quasi-static load), the mean of the
    loaded pairs; with neither loaded, at the bottom of the outer arcs pressed out by the centrifugal force
    at the nominal orbital speed. (Issue 47 item 6: the quasi-static share it replaced, blind to F_c, left
    Newton 4.4 residual halvings a ball and 2 % of the balls on a fold, for the continuation in speed.)"""
    ro = p[OUTER_RADIUS]
    A0 = p[INNER_RADIUS] + ro
    c0 = p[COS_NOMINAL]
    s0 = math.sqrt(1.0 - c0 * c0)
    d1 = math.sqrt(u[2] * u[2] + u[3] * u[3]) - A0
    d2 = math.sqrt(u[4] * u[4] + u[5] * u[5]) - A0
    if d1 > 0.0 and d2 > 0.0:
        b1r, b1z, _ = start_position(u[2], u[3], p, w_i, w_o, 0.0, False)
        b2r, b2z, _ = start_position(u[4], u[5], p, w_i, w_o, 0.0, False)
        return 0.5 * (b1r + b2r), 0.5 * (b1z + 2.0 * ro * s0 - b2z)
    if d1 > 0.0:
        b1r, b1z, _ = start_position(u[2], u[3], p, w_i, w_o, 0.0, False)
        return b1r, b1z
    if d2 > 0.0:
        b2r, b2z, _ = start_position(u[4], u[5], p, w_i, w_o, 0.0, False)
        return b2r, 2.0 * ro * s0 - b2z
    wm = 0.5 * (w_i * (1.0 - p[GAMMA] * c0) + w_o * (1.0 + p[GAMMA] * c0))
    Fc = p[MASS_RADIUS] * wm * wm
    push = (0.5 * Fc / (p[K_OUTER] * c0)) ** (2.0 / 3.0)  # each outer arc's share of F_c, along its normal
    return (ro + push) * c0, ro * s0


@njit(cache=CACHE, fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL, _nrt=REFCOUNT)
def settle_four_point(u, p, w_i, w_o, eps, br, bz, linear_reach):
    """The ball's centre B (mm, pair +'s frame) where its residual vanishes, by damped Newton from (br, bz)
    with the analytic Jacobian (:func:`ball_jacobian`; u: the inner groove centres as its x[2:]). Settled
    within BALL_RTOL of its largest force, or (the lightest contacts) within the rounding floor of its
    position, as high_speed's balls. Returns (br, bz, iterations, settled, and at B the ball's evaluation y,
    st); the caller takes :func:`ball_jacobian` at B where it needs Kb or the warm start's X. With ``linear_reach`` > 0
    (inside a solve: LINEAR_REACH; else 0, a float whatever its value so that one variant compiles) it also
    stops, "settled", where its Newton step is short (:func:`_short`), for :func:`linear_look` at B."""
    longest = 0.05 * p[DIAMETER]  # the longest step: a twentieth of the ball
    reach = p[INNER_RADIUS] + p[OUTER_RADIUS] + abs(u[2]) + abs(u[3]) + abs(u[4]) + abs(u[5])
    res, scale, y, st = _residual(br, bz, u, p, w_i, w_o, eps)
    for it in range(ITERATIONS + 1):
        if res <= BALL_RTOL * scale:  # settled whatever the rounding floor: no Jacobian needed to say so
            return br, bz, it, True, y, st
        a, b = _newton_jacobian(br, bz, u, p, w_i, w_o, eps)
        floor = 8.0 * 2.220446049250313e-16 * reach * (abs(a[0]) + abs(a[1]) + abs(b[0]) + abs(b[1]))
        if res <= max(BALL_RTOL * scale, floor):
            return br, bz, it, True, y, st
        det = a[0] * b[1] - b[0] * a[1]
        if it == ITERATIONS or det == 0.0 or not math.isfinite(det):
            return br, bz, it, False, y, st
        step_r = (b[1] * y[0] - b[0] * y[1]) / det
        step_z = (a[0] * y[1] - a[1] * y[0]) / det
        if linear_reach > 0.0 and _short(u, p, br, bz, step_r, step_z, linear_reach):
            return br, bz, it, True, y, st  # for :func:`linear_look`, which takes the step to first order
        t = min(1.0, longest / max(math.sqrt(step_r * step_r + step_z * step_z), 1e-300))
        for _ in range(HALVINGS):
            trial, trial_scale, y_t, st_t = _residual(br - t * step_r, bz - t * step_z, u, p, w_i, w_o, eps)
            if trial < res:
                break
            t *= 0.5
        if not trial < res:  # no step lowers the residual: as settled as float64 gets, or stuck
            return br, bz, it, res <= max(BALL_RTOL * scale, 4.0 * floor), y, st
        br -= t * step_r
        bz -= t * step_z
        res, scale, y, st = trial, trial_scale, y_t, st_t
    return br, bz, ITERATIONS, False, y, st  # not reached: the last pass returns


@njit(cache=CACHE, fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL, _nrt=REFCOUNT)
def canonical_settle(u, p, w_i, w_o, eps):
    """The ball's canonical root at u (a property of u, so of q, alone; docs/model.md): Newton from the cold
    guess (:func:`_cold_guess`) and, where that does not settle, the root continued in speed from standing
    still, at the same u: settled at SPEED_STEPS fractions of (w_i, w_o), each from the last (a fraction that
    does not settle is halved, at most SPEED_HALVINGS times in all). Near its speed limit the cold guess can
    sit on a fold of the residual (Newton stops where its Jacobian is singular, not at a root: issue 47);
    the continuation goes round it. Returns :func:`settle_four_point`'s tuple, its iterations summed."""
    br, bz = _cold_guess(u, p, w_i, w_o)
    first = settle_four_point(u, p, w_i, w_o, eps, br, bz, 0.0)
    if first[3]:
        return first
    iterations = first[2]
    done = 0.0
    step = 1.0 / SPEED_STEPS
    br, bz = _cold_guess(u, p, w_i * step, w_o * step)
    halvings = 0
    while True:
        s = min(1.0, done + step)
        out = settle_four_point(u, p, w_i * s, w_o * s, eps, br, bz, 0.0)
        iterations += out[2]
        if out[3]:
            done = s
            br, bz = out[0], out[1]
            if done >= 1.0:
                return out[0], out[1], iterations, True, out[4], out[5]
            # a step that settles lets the next one grow back to the first's length: a single hard stretch
            # of the way (a fold) costs its halvings there, not all the way to full speed (issue 47 item 6:
            # one ball took 17 000 Newton steps at a constant 1/32 768 of the speed)
            step = min(2.0 * step, 1.0 / SPEED_STEPS)
        else:
            halvings += 1
            if halvings > SPEED_HALVINGS:
                return first[0], first[1], iterations, False, first[4], first[5]
            step *= 0.5


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _short(u, p, br, bz, s_r, s_z, reach):
    """Whether the Newton step s (B' = B - s) moves no contact's centre distance by more than ``reach`` of its
    deflection (an open contact: of its gap); False for a NaN step."""
    ro = p[OUTER_RADIUS]
    ri = p[INNER_RADIUS]
    bz2 = 2.0 * ro * math.sqrt(1.0 - p[COS_NOMINAL] * p[COS_NOMINAL]) - bz  # pair -'s frame mirrors B_z
    Lo1 = math.sqrt(br * br + bz * bz)
    Lo2 = math.sqrt(br * br + bz2 * bz2)
    vr1, vz1, vr2, vz2 = u[2] - br, u[3] - bz, u[4] - br, u[5] - bz2
    Li1 = math.sqrt(vr1 * vr1 + vz1 * vz1)
    Li2 = math.sqrt(vr2 * vr2 + vz2 * vz2)
    return (abs(br * s_r + bz * s_z) <= reach * abs(Lo1 - ro) * Lo1
            and abs(br * s_r - bz2 * s_z) <= reach * abs(Lo2 - ro) * Lo2
            and abs(vr1 * s_r + vz1 * s_z) <= reach * abs(Li1 - ri) * Li1
            and abs(vr2 * s_r - vz2 * s_z) <= reach * abs(Li2 - ri) * Li2)


@njit(cache=CACHE, fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL, _nrt=REFCOUNT)
def linear_look(u, p, w_i, w_o, eps, br, bz):
    """A moved ball's one look at its prediction B (inside a solve): the ball's evaluation (y, st) and its six
    Jacobian columns J (:func:`ball_jacobian`) at B, and what to make of them, as the angular contact ball's
    ``_judge``. Returns (br, bz, settled, stepped, y, st, J):

    - settled at B (the residual within BALL_RTOL of its largest force, the test :func:`settle_four_point`
      makes first): B, y, st and J as a settle from B and :func:`ball_jacobian` give them (to rounding:
      compiled here, fastmath may contract them otherwise; inside a solve, where the evaluation is flagged);
    - else, where the Newton step s = G_B^-1 g moves no contact's centre distance by more than LINEAR_REACH
      of its deflection (open contacts: of their gap), linearised: the centre B - s, and y's ring outputs
      moved to first order, y + Y_B (-s) (st stays B's: loads and angles for the trial's record, which the
      solver's last, canonical evaluation writes again); J stays B's (Kb and the next prediction);
    - else ``stepped``: the caller settles the ball from B (y, st, J then of no use).

    The evaluation is flagged 8 by the caller either way: a linearised ball is first-order close, and the
    canonical root is taken at the solve's answer."""
    y, st = four_point_ball(br, bz, u[2], u[3], u[4], u[5], p, w_i, w_o, eps)
    J = ball_jacobian((br, bz, u[2], u[3], u[4], u[5]), p, w_i, w_o, eps)
    scale = st[0] + st[1] + st[2] + st[3] + abs(st[12])
    if max(abs(y[0]), abs(y[1])) <= BALL_RTOL * scale:
        return br, bz, True, False, y, st, J
    a = J[0]
    b = J[1]
    det = a[0] * b[1] - b[0] * a[1]
    s_r = (b[1] * y[0] - b[0] * y[1]) / det
    s_z = (a[0] * y[1] - a[1] * y[0]) / det
    if not _short(u, p, br, bz, s_r, s_z, LINEAR_REACH):  # also a NaN step (det 0)
        return br, bz, False, True, y, st, J
    y = (y[0], y[1], y[2] - (a[2] * s_r + b[2] * s_z), y[3] - (a[3] * s_r + b[3] * s_z),
         y[4] - (a[4] * s_r + b[4] * s_z), y[5] - (a[5] * s_r + b[5] * s_z), y[6] - (a[6] * s_r + b[6] * s_z),
         y[7] - (a[7] * s_r + b[7] * s_z))
    return br - s_r, bz - s_z, True, False, y, st, J


@njit(cache=CACHE, fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL, _nrt=REFCOUNT)
def four_point_balls(q, table, speed_table, omega, eps, f, K, ball_load, contact_angle, states, warm, pairs):
    """Add the four-point balls' share to f (5) and, unless ``K`` is None, Kb (5x5), in place; the arguments
    as high_speed.spinning_balls', which has written the other balls' share; ``pairs`` (2, n) the columns of each
    ball's pair + and pair - (schema.ElementSet.four_point). Each ball (column j of pair +, m of pair -) is
    settled at its canonical root (:func:`canonical_settle`), or inside a solve (``warm`` row WARM_LINEARISE),
    where its u moved since its last evaluation, from its last centre (WARM_BR, WARM_BZ where WARM_VALID; its
    u in WARM_UR, WARM_UZ of both columns) moved by the first-order prediction (X in WARM_X*), flagged 8; it is
    never linearised. It adds through each pair's column J = [a; b] (its contact direction's sign on b)
    f += J^T F + w m and Kb += sum over both pairs' J^T (dF/du) J'. Records as spinning_balls: Q_i and
    alpha_i of each pair at its column, Q_o and alpha_o after them in a record of 2 n_balls, the whole ball in
    ``states``. Returns (sum of Q_i N, loaded contact pairs, warning bits:
    2 beyond validity, 4 a ball not settled, 8 a ball settled from its last centre: evaluate again for the
    canonical root)."""
    n = table.shape[1]
    total = 0.0
    n_loaded = 0
    flags = 0
    scratch = warm[N_WARM * n:]  # 6 x 4 condensed stiffness, after the ball pass's use
    linearise = n > 0 and states is None and warm[warm_cell(WARM_LINEARISE, n, 0)] != 0.0
    for b in range(pairs.shape[1]):
        j = int(pairs[0, b])
        m_col = int(pairs[1, b])
        p, w_i, w_o = _ball_constants(speed_table, j, omega)
        u1r, u1z = _inner_centre(q, table, j)
        u2r, u2z = _inner_centre(q, table, m_col)
        u = (0.0, 0.0, u1r, u1z, u2r, u2z)
        # inside a solve a ball moved since its last evaluation starts from its last centre and is flagged
        # BALL_LINEARISED (bit 8): the solver evaluates at its answer's q again before it converges, and that
        # evaluation (the same u, bit for bit) and every other one take the canonical root, a property of q
        # alone (:func:`canonical_settle`), so that stiffness(q), ball_contacts(q) and the records repeat it
        settled = False
        have_jacobian = False
        J = _NO_JACOBIAN
        if (linearise and warm[warm_cell(WARM_VALID, n, j)] != 0.0
                and not (warm[warm_cell(WARM_UR, n, j)] == u1r and warm[warm_cell(WARM_UZ, n, j)] == u1z
                         and warm[warm_cell(WARM_UR, n, m_col)] == u2r and warm[warm_cell(WARM_UZ, n, m_col)] == u2z)):
            # the first-order prediction B - X (u - u_last), X = G_B^-1 G_u (2 x 4) of the last settle
            du1r = u1r - warm[warm_cell(WARM_UR, n, j)]
            du1z = u1z - warm[warm_cell(WARM_UZ, n, j)]
            du2r = u2r - warm[warm_cell(WARM_UR, n, m_col)]
            du2z = u2z - warm[warm_cell(WARM_UZ, n, m_col)]
            x1 = warm_x(warm, n, j)
            x2 = warm_x(warm, n, m_col)
            br = warm[warm_cell(WARM_BR, n, j)] - (x1[0] * du1r + x1[1] * du1z + x2[0] * du2r + x2[1] * du2z)
            bz = warm[warm_cell(WARM_BZ, n, j)] - (x1[2] * du1r + x1[3] * du1z + x2[2] * du2r + x2[3] * du2z)
            # one look at the prediction (:func:`linear_look`): settled there, or a Newton step short against
            # every contact's deflection, taken to first order (the ball's forces and centre), or a settle
            br, bz, settled, stepped, y, st, J = linear_look(u, p, w_i, w_o, eps, br, bz)
            have_jacobian = settled and not stepped
            if stepped:
                br, bz, iterations, settled, y, st = settle_four_point(u, p, w_i, w_o, eps, br, bz, 0.0)
            else:
                iterations = 0
            if settled:
                flags |= 8
        elif linearise and warm[warm_cell(WARM_VALID, n, j)] == 0.0:
            # a ball's first evaluation inside a solve (no warm start; a ball that has not moved takes its
            # canonical root, so that the solver's last evaluation at its answer is the model's): Newton from the cold guess to its first
            # short step, taken to first order (:func:`linear_look`), flagged 8 as a warm one; where that does
            # not reach a short step, the canonical settle below
            br, bz = _cold_guess(u, p, w_i, w_o)
            br, bz, iterations, ready, y, st = settle_four_point(u, p, w_i, w_o, eps, br, bz, LINEAR_REACH)
            if ready:
                br, bz, settled, stepped, y, st, J = linear_look(u, p, w_i, w_o, eps, br, bz)
                have_jacobian = settled
                if settled:
                    flags |= 8
        if not settled:
            have_jacobian = False
            br, bz, iterations, settled, y, st = canonical_settle(u, p, w_i, w_o, eps)
        warm[warm_cell(WARM_BR, n, j)] = br
        warm[warm_cell(WARM_BZ, n, j)] = bz
        warm[warm_cell(WARM_UR, n, j)] = u1r
        warm[warm_cell(WARM_UZ, n, j)] = u1z
        warm[warm_cell(WARM_UR, n, m_col)] = u2r
        warm[warm_cell(WARM_UZ, n, m_col)] = u2z
        x = (br, bz, u1r, u1z, u2r, u2z)
        if not have_jacobian and (K is not None or linearise):
            J = ball_jacobian(x, p, w_i, w_o, eps)
        det = J[0][0] * J[1][1] - J[1][0] * J[0][1]
        for col, k in ((j, 2), (m_col, 4)):  # X = G_B^-1 G_u: its u1 columns at j, its u2 columns at m
            gr0, gz0, gr1, gz1 = J[k][0], J[k][1], J[k + 1][0], J[k + 1][1]
            warm[warm_cell(WARM_X00, n, col)] = (J[1][1] * gr0 - J[1][0] * gz0) / det
            warm[warm_cell(WARM_X10, n, col)] = (J[0][0] * gz0 - J[0][1] * gr0) / det
            warm[warm_cell(WARM_X01, n, col)] = (J[1][1] * gr1 - J[1][0] * gz1) / det
            warm[warm_cell(WARM_X11, n, col)] = (J[0][0] * gz1 - J[0][1] * gr1) / det
        good = settled and (math.isfinite(det) and det != 0.0 or not linearise)
        warm[warm_cell(WARM_VALID, n, j)] = 1.0 if good else 0.0
        if not settled:
            flags |= 4
        Qi1, Qo1, Qi2, Qo2, ci1, si1, co1, so1, ci2, si2, co2, so2, Fc, Mg, wm, di1, do1, di2, do2 = st
        total += Qi1 + Qi2
        n_loaded += (di1 > 0.0) + (di2 > 0.0)
        if di1 + do1 > table[DEFLECTION_LIMIT, j] or di2 + do2 > table[DEFLECTION_LIMIT, m_col]:
            flags |= 2
        c = table[COS_PSI, j]
        s = table[SIN_PSI, j]
        z = table[AXIAL_OFFSET, j]
        R = table[PITCH_RADIUS, j]
        s1 = table[DIRECTION, j]
        s2 = table[DIRECTION, m_col]
        for a in range(2):  # f: each pair's ring share through its column
            sgn = s1 if a == 0 else s2
            Fr = y[2 + 3 * a]
            Fz = sgn * y[3 + 3 * a]
            mo = R * Fz - z * Fr + sgn * y[4 + 3 * a]
            f[0] += Fr * c
            f[1] += Fr * s
            f[2] += Fz
            f[3] += mo * s
            f[4] -= mo * c
        if ball_load is not None:
            write_contacts(ball_load, contact_angle, n, j, Qi1, Qo1, ci1, si1, co1, so1)
            write_contacts(ball_load, contact_angle, n, m_col, Qi2, Qo2, ci2, si2, co2, so2)
        if states is not None:
            residual = max(abs(y[0]), abs(y[1])) / max(Qi1 + Qo1 + Qi2 + Qo2 + abs(Fc), 1e-300)
            write_state(states, j, Qi1, Qo1, ci1, si1, co1, so1, Fc, Mg, wm, iterations, residual)
            write_state(states, m_col, Qi2, Qo2, ci2, si2, co2, so2, Fc, Mg, wm, iterations, residual)
        if K is not None:
            _add_stiffness(K, scratch, J, c, s, z, R, s1, s2)
    return total, n_loaded, flags


@njit(inline="always")
def _dot(scratch, row, du):
    """Row ``row`` (its first cell) of the 6 x 4 condensed stiffness times du (4)."""
    return scratch[row] * du[0] + scratch[row + 1] * du[1] + scratch[row + 2] * du[2] + scratch[row + 3] * du[3]


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _add_stiffness(K, scratch, J, c, s, z, R, s1, s2):
    """Kb += one four-point ball's share: the condensed dY/du = Y_u - Y_B G_B^-1 G_u (Y = (F_1, m_1, F_2, m_2),
    u = (u1, u2); 6 x 4 in ``scratch``) mapped through both pairs' columns; J the six columns of
    :func:`ball_jacobian` at the ball's B (the settle's last, at this very B)."""
    dB0 = J[0]
    dB1 = J[1]
    det = dB0[0] * dB1[1] - dB1[0] * dB0[1]
    for m in range(4):
        du = J[2 + m]
        x0 = (dB1[1] * du[0] - dB1[0] * du[1]) / det  # X = G_B^-1 G_u, column m
        x1 = (dB0[0] * du[1] - dB0[1] * du[0]) / det
        for i in range(6):
            scratch[4 * i + m] = du[2 + i] - (dB0[2 + i] * x0 + dB1[2 + i] * x1)
    for k in range(5):  # column k of Kb: q moves along e_k
        jr = (c, s, 0.0, -z * s, z * c)[k]  # d(u_r)/dq_k, alike for both pairs
        jz = (0.0, 0.0, 1.0, R * s, -R * c)[k]  # d(u_z)/dq_k in the bearing frame
        du = (jr, s1 * jz, jr, s2 * jz)
        for a in range(2):
            sgn = s1 if a == 0 else s2
            dFr = _dot(scratch, 4 * (3 * a), du)
            dFz = sgn * _dot(scratch, 4 * (3 * a + 1), du)
            dmo = R * dFz - z * dFr + sgn * _dot(scratch, 4 * (3 * a + 2), du)
            K[0, k] += dFr * c
            K[1, k] += dFr * s
            K[2, k] += dFz
            K[3, k] += dmo * s
            K[4, k] -= dmo * c
