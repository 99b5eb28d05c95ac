"""The high-speed ball: each ball in equilibrium under its two contacts, its centrifugal force and its
gyroscopic moment (Jones-Harris quasi-static model; docs/model.md, "High speed").

At shaft speed the ball centre leaves the line through the groove-curvature centres: the centrifugal
force F_c = 0.5 m d_m omega_m^2 presses it outward, the outer contact angle alpha_o falls below the inner
alpha_i, and the contacts' loads Q_i, Q_o differ. Per ball (in its azimuth's radial-axial plane, frame
mirrored so that the row's contact direction is +z) the ball centre B, measured from the outer
groove-curvature centre O, solves the 2x2 equilibrium

    g(B) = Q_i n_i - Q_o n_o + F_c e_r + (M_g / D) (lambda_i t_i - lambda_o t_o) = 0,

with n_o = B/|B|, n_i = (u - B)/|u - B| (u: the inner groove centre I seen from O, the quasi-static
kernel's (ur, uz)), delta_o = |B| - (f_o - 1/2) D, delta_i = |u - B| - (f_i - 1/2) D, Q = K delta^1.5 with
each race's own Hertz constant, t = (sin a, -cos a) the contact tangent that carries the friction of the
gyroscopic moment (race control: lambda_i, lambda_o = 0, 2 for outer-raceway control, 1, 1 for inner,
0, 0 for none). Kinematics from the contact angles (Harris & Kotzalas, *Advanced Concepts of Bearing
Technology*, 5th ed., ch. 3; rolling without slip at both contacts, the spin axis at beta set by the race
that controls): with C = cos(alpha_i - alpha_o) and gamma' = D/d_m,

    outer control: omega_m = (w_i (1 - gamma' cos a_i) + w_o (C + gamma' cos a_i)) / (1 + C)
                   M_g = J (w_o - w_i)/gamma' * omega_m (1 - gamma' cos a_i) sin a_o / (1 + C)
    inner control: omega_m = (w_i (C - gamma' cos a_o) + w_o (1 + gamma' cos a_o)) / (1 + C)
                   M_g = J (w_o - w_i)/gamma' * omega_m (1 + gamma' cos a_o) sin a_i / (1 + C)

(w_i, w_o: ring speeds, rad/s; M_g = J omega_R omega_m sin(beta) written out, negative with Harris's sign
of omega_R; J = m D^2/10). The ring feels the inner contact: F = Q_i n_i + lambda_i (M_g/D) t_i, plus the
moment lambda_i f_i M_g of the friction's lever about I. Kb is the exact derivative with every ball kept
in equilibrium: per ball dF/du = F_u - F_B G_B^-1 G_u (the ball's two unknowns condensed out), all
analytic. It is not symmetric in general: the friction of the gyroscopic moment and the angle-dependent
orbital speed are not conservative.

Units: mm, N, N*mm, rad, rad/s; ball mass and inertia enter through the table's kg*m and N*mm*s^2
columns so that F_c comes out in N and M_g in N*mm.
"""

import math

import numpy as np
from numba import njit, types
from numba.extending import overload

from ..config import CACHE, ERROR_MODEL, KERNEL_FASTMATH, REFCOUNT
from .deflection import deflection
from .roots import cube_root
from .schema import (AXIAL_OFFSET, BS_CI, BS_CO, BS_DI, BS_DO, BS_FB_RR, BS_FB_RZ, BS_FB_ZR, BS_FB_ZZ, BS_FC, BS_FR,
                     BS_FU_RR, BS_FU_RZ, BS_FU_ZR, BS_FU_ZZ, BS_FZ, BS_GB_RR, BS_GB_RZ, BS_GB_ZR, BS_GB_ZZ, BS_GR,
                     BS_GU_RR, BS_GU_RZ, BS_GU_ZR, BS_GU_ZZ, BS_GZ, BS_M, BS_MB_R, BS_MB_Z, BS_MG, BS_MU_R, BS_MU_Z,
                     BS_QI, BS_QO, BS_SI, BS_SO, BS_WM, CHUNK, COS_NOMINAL, COS_PSI, DEFLECTION_LIMIT, DIAMETER,
                     DIRECTION, GAMMA, INERTIA, INNER_ARM, INNER_CONTROL, INNER_RADIUS, K_INNER, K_OUTER,
                     LAMBDA_INNER, LAMBDA_OUTER, MASS_RADIUS, N_SUMMARY, N_WARM,
                     OUTER_RADIUS, OUTER_ROTATES, OUTER_SHARE, PARTNER, PITCH_RADIUS, SIN_PSI, SM_BR, SM_BZ, SM_CI, SM_CO,
                     SM_DBR, SM_DBZ, SM_DI, SM_DO, SM_EXACT, SM_FC, SM_FR, SM_FZ, SM_GR, SM_GZ, SM_K00, SM_K01,
                     SM_K10, SM_K11, SM_LOADED, SM_M, SM_M0, SM_M1, SM_MG, SM_QI, SM_QO, SM_SI, SM_SO, SM_UR, SM_UZ,
                     SM_VERDICT, SM_WM, SM_X00, SM_X01, SM_X10, SM_X11, STATE_CENTRIFUGAL, STATE_GYROSCOPIC,
                     STATE_INNER_ANGLE, STATE_INNER_LOAD, STATE_ITERATIONS, STATE_ORBITAL_SPEED, STATE_OUTER_ANGLE,
                     STATE_OUTER_LOAD, STATE_RESIDUAL, UR0, UZ0, WARM_BR, WARM_BZ, WARM_LINEARISE, WARM_UR, WARM_UZ,
                     WARM_VALID, WARM_X00, WARM_X01, WARM_X10, WARM_X11)
from .trig import atan2

#: Newton iterations allowed per ball, and the relative residual at which a ball is in equilibrium.
BALL_ITERATIONS = 40
BALL_RTOL = 1e-13
#: Inside a solve (a warm-start scratch and no record) a ball stops at the first Newton step dB shorter than
#: LINEAR_REACH of its contacts' deflections (along each normal) and hands the ring its first-order
#: corrected force F + F_B dB (error about Q (dB/delta)^2, under 1 %): one ball state per ball and evaluation.
#: The correction counts as exact when dB is within LINEAR_RTOL of the deflections (F then errs by
#: 1e-22 relative, Kb by about 1e-11); otherwise the kernel flags the evaluation (BALL_LINEARISED) and the
#: solver evaluates again before it declares convergence.
LINEAR_REACH = 0.1
LINEAR_RTOL = 1e-11

#: Newton iterations a warm start gets before the ball is settled again from :func:`start_position`.
WARM_ITERATIONS = 12
#: Below the speed at which every ball's centrifugal force would deflect its outer contact by this much (mm)
#: the balls stand still (:func:`standing_still`): their loads from it, K_o delta^1.5 ~ 1e-13 N, are far
#: below any load the solver resolves, while the balls' own equilibrium (F_c ~ omega^2) sinks below float64's
#: resolution of their positions and the solves failed (issue 33: stalled at 0.001 rpm, iteration_limit at
#: 1e-9 rpm). So the answer is continuous as the speed goes to 0.
STILL_DEFLECTION = 1e-12

#: Cells after a ball set's warm starts: one chunk's summaries (and a four-point ball's 6 x 4 condensed stiffness).
WARM_TAIL = N_SUMMARY * CHUNK


@njit(cache=CACHE)
def warm_size(n_balls):
    """Cells of a ball set's warm scratch for ``n_balls`` balls: the N_WARM rows of warm starts, row r of ball j
    at r * n_balls + j (one flat vector: a GPU thread's is a strided column of an element-major array), and
    WARM_TAIL cells of flat scratch after them."""
    return N_WARM * n_balls + WARM_TAIL


@njit(inline="always")
def warm_cell(row, n, j):
    """The cell of ball j's ``row`` (schema WARM_*) in a warm scratch of n balls: row * n + j, unsigned, so that
    numba adds no negative-index test (which kept the chunk pass from loading its balls' starts contiguously)."""
    return np.uint64(row * n + j)


@njit(inline="always")
def warm_x(warm, n, j):
    """Ball j's (column j's) X = G_B^-1 G_u of its last settle from a warm scratch of n balls: (X00, X01, X10, X11)."""
    return (warm[warm_cell(WARM_X00, n, j)], warm[warm_cell(WARM_X01, n, j)], warm[warm_cell(WARM_X10, n, j)],
            warm[warm_cell(WARM_X11, n, j)])


@njit(inline="always")
def warm_balls(warm):
    """The ball count of a warm scratch of :func:`warm_size` cells."""
    return (warm.size - WARM_TAIL) // N_WARM


def warm_scratch(speed_table):
    """A fresh warm scratch for the balls of ``speed_table`` inside njit code (None without a speed table)."""


@overload(warm_scratch)
def _warm_scratch(speed_table):
    if isinstance(speed_table, types.NoneType):
        return lambda speed_table: None
    return lambda speed_table: np.zeros(warm_size(speed_table.shape[1]))


def forget_warm(warm):
    """Drop every ball's warm start (a case that starts cold starts its balls cold too, so that its result
    depends on its own run alone, never on which block or thread ran it before); None: nothing to drop."""


@overload(forget_warm)
def _forget_warm(warm):
    if isinstance(warm, types.NoneType):
        return lambda warm: None

    def forget(warm):
        n = warm_balls(warm)
        for j in range(n):
            warm[warm_cell(WARM_VALID, n, j)] = 0.0
    return forget


def take_linearised(warm, allowed):
    """Tell the balls at speed (warm scratch ``warm``; None without speed: nothing) whether the solve under
    way takes linearised balls: the solver's tests see BALL_LINEARISED and evaluate again before they
    converge."""


@overload(take_linearised)
def _take_linearised(warm, allowed):
    if isinstance(warm, types.NoneType):
        return lambda warm, allowed: None

    def take(warm, allowed):
        n = warm_balls(warm)
        if n > 0:
            warm[warm_cell(WARM_LINEARISE, n, 0)] = 1.0 if allowed else 0.0
    return take


def new_warm(n_balls):
    """An empty warm scratch for ``n_balls`` balls (no warm starts: every ball starts from its cold guess)."""
    return np.zeros(warm_size(n_balls))


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _race(L, r0, k, smoothing_eps):
    """A race contact from the centre distance L (mm): (delta, Q, dQ/dL) with Q = k delta^1.5; a positive
    ``smoothing_eps`` (mm) uses the solver's smooth (d + sqrt(d^2 + eps^2))/2 for max(d, 0)."""
    delta, slope = deflection(L - r0, smoothing_eps)
    sq = math.sqrt(delta)
    return delta, k * delta * sq, 1.5 * k * sq * slope


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _hertz_deflection(Q, k):
    """The deflection (Q/k)^(2/3) (mm) of a Hertz contact carrying Q >= 0 (N): a cube root squared
    (libm's pow cost a free ball's every evaluation about 40 ns)."""
    if Q <= 0.0:
        return 0.0
    c = cube_root(Q / k)
    return c * c


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def standing_still(speed_table, omega):
    """Whether at the shaft speed ``omega`` (rad/s) every ball's centrifugal force at its nominal orbital
    speed deflects its outer contact by less than STILL_DEFLECTION: then the quasi-static balls are the
    model to far below the solver's resolution."""
    for j in range(speed_table.shape[1]):
        outer = speed_table[OUTER_ROTATES, j]
        cage = 0.5 * (1.0 + (2.0 * outer - 1.0) * speed_table[GAMMA, j] * speed_table[COS_NOMINAL, j])
        wm = omega * cage
        limit = speed_table[K_OUTER, j] * STILL_DEFLECTION * math.sqrt(STILL_DEFLECTION)
        if speed_table[MASS_RADIUS, j] * wm * wm >= limit:
            return False
    return True


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def kinematics(ci, si, co, so, w_i, w_o, gamma, inner_control):
    """Orbital speed omega_m (rad/s) and the spin factor S (M_g = J (w_o - w_i)/gamma' S) from the unit
    contact normals n_i = (ci, si), n_o = (co, so), with their gradients with respect to (ci, si, co, so).

    Returns (omega_m, dm_ci, dm_si, dm_co, dm_so, S, dS_ci, dS_si, dS_co, dS_so). Identities of unit
    vectors are used freely: the callers project the gradients onto the circle.
    """
    C = ci * co + si * so
    den = 1.0 + C
    if inner_control:
        b = 1.0 + gamma * co
        N = w_i * (C - gamma * co) + w_o * b
        n_ci, n_si, n_co, n_so = w_i * co, w_i * so, w_i * (ci - gamma) + w_o * gamma, w_i * si
        wm = N / den
        m_ci = (n_ci - wm * co) / den
        m_si = (n_si - wm * so) / den
        m_co = (n_co - wm * ci) / den
        m_so = (n_so - wm * si) / den
        S = wm * b * si / den
        s_ci = (m_ci * b * si) / den - S * co / den
        s_si = (m_si * b * si + wm * b) / den - S * so / den
        s_co = (m_co * b * si + wm * gamma * si) / den - S * ci / den
        s_so = (m_so * b * si) / den - S * si / den
        return wm, m_ci, m_si, m_co, m_so, S, s_ci, s_si, s_co, s_so
    a = 1.0 - gamma * ci
    N = w_i * a + w_o * (C + gamma * ci)
    n_ci, n_si, n_co, n_so = -w_i * gamma + w_o * (co + gamma), w_o * so, w_o * ci, w_o * si
    wm = N / den
    m_ci = (n_ci - wm * co) / den
    m_si = (n_si - wm * so) / den
    m_co = (n_co - wm * ci) / den
    m_so = (n_so - wm * si) / den
    S = wm * a * so / den
    s_ci = (m_ci * a * so - wm * gamma * so) / den - S * co / den
    s_si = (m_si * a * so) / den - S * so / den
    s_co = (m_co * a * so) / den - S * ci / den
    s_so = (m_so * a * so + wm * a) / den - S * si / den
    return wm, m_ci, m_si, m_co, m_so, S, s_ci, s_si, s_co, s_so


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def contact_hessian(dQ, g, c, s):
    """One contact's force Hessian H = Q' n n^T + (Q/L)(I - n n^T) (N/mm; entries rr, rz, zz) from Q' = dQ/ddelta
    (N/mm), g = Q/L (the load over the centres' distance, N/mm) and its normal n = (c, s)."""
    return dQ * c * c + g * s * s, (dQ - g) * c * s, dQ * s * s + g * c * c


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def ball_state(ur, uz, br, bz, p, w_i, w_o, smoothing_eps):
    """Everything about one ball at centre B = (br, bz) (mm from O, mirrored frame) for the inner groove
    centre at u = (ur, uz): the residual g, its Jacobian G_B, G_u = dg/du, the ring force F and moment m
    with their partial derivatives. ``p`` is the ball's column of the high-speed table (a tuple).

    Returns (g_r, g_z, GB_rr, GB_rz, GB_zr, GB_zz, GU_rr, GU_rz, GU_zr, GU_zz, F_r, F_z, FU_rr, FU_rz,
    FU_zr, FU_zz, FB_rr, FB_rz, FB_zr, FB_zz, m, mu_r, mu_z, mb_r, mb_z, Q_i, Q_o, ci, si, co, so,
    F_c, M_g, omega_m, delta_i, delta_o).
    """
    (ri, ro, Ki, Ko, mass_radius, inertia, gamma, li, lo, inner_control, outer_rotates, arm, D, _, _) = p
    Lo = math.sqrt(br * br + bz * bz)
    co = br / Lo
    so = bz / Lo
    vr = ur - br
    vz = uz - bz
    Li = math.sqrt(vr * vr + vz * vz)
    ci = vr / Li
    si = vz / Li
    delta_o, Qo, dQo = _race(Lo, ro, Ko, smoothing_eps)
    delta_i, Qi, dQi = _race(Li, ri, Ki, smoothing_eps)
    wm, m_ci, m_si, m_co, m_so, S, s_ci, s_si, s_co, s_so = kinematics(ci, si, co, so, w_i, w_o, gamma,
                                                                      inner_control != 0.0)
    Fc = mass_radius * wm * wm
    jc = inertia * (w_o - w_i) / gamma
    Mg = jc * S
    # projections P = I - n n^T of the two normals, divided by the centre distances
    por, poc, poz = so * so / Lo, -co * so / Lo, co * co / Lo
    pir, pic, piz = si * si / Li, -ci * si / Li, ci * ci / Li
    # gradients of a function of (n_i, n_o): d/du = n_i part, d/dB = n_o part - d/du
    fci, fsi, fco, fso = 2.0 * mass_radius * wm * m_ci, 2.0 * mass_radius * wm * m_si, \
        2.0 * mass_radius * wm * m_co, 2.0 * mass_radius * wm * m_so
    Fc_ur = fci * pir + fsi * pic
    Fc_uz = fci * pic + fsi * piz
    Fc_br = fco * por + fso * poc - Fc_ur
    Fc_bz = fco * poc + fso * poz - Fc_uz
    Mg_ur = jc * (s_ci * pir + s_si * pic)
    Mg_uz = jc * (s_ci * pic + s_si * piz)
    Mg_br = jc * (s_co * por + s_so * poc) - Mg_ur
    Mg_bz = jc * (s_co * poc + s_so * poz) - Mg_uz
    # contact Hessians H = Q' n n^T + (Q/L) P
    gi = Qi / Li
    go = Qo / Lo
    hi_rr, hi_rz, hi_zz = contact_hessian(dQi, gi, ci, si)
    ho_rr, ho_rz, ho_zz = contact_hessian(dQo, go, co, so)
    # friction of the gyroscopic moment: (M_g/D) T, T = li t_i - lo t_o, t = (sin a, -cos a);
    # dt_i/du = R P_i/L_i, dt_i/dB = -R P_i/L_i, dt_o/dB = R P_o/L_o with R (x, y) = (y, -x)
    Tr = li * si - lo * so
    Tz = -li * ci + lo * co
    inv_D = 1.0 / D
    mgd = Mg * inv_D
    g_r = Qi * ci - Qo * co + Fc + mgd * Tr
    g_z = Qi * si - Qo * so + mgd * Tz
    # dT/dB
    dTr_br = -li * pic - lo * poc
    dTr_bz = -li * piz - lo * poz
    dTz_br = li * pir + lo * por
    dTz_bz = li * pic + lo * poc
    GB_rr = -hi_rr - ho_rr + Fc_br + inv_D * (Tr * Mg_br + Mg * dTr_br)
    GB_rz = -hi_rz - ho_rz + Fc_bz + inv_D * (Tr * Mg_bz + Mg * dTr_bz)
    GB_zr = -hi_rz - ho_rz + inv_D * (Tz * Mg_br + Mg * dTz_br)
    GB_zz = -hi_zz - ho_zz + inv_D * (Tz * Mg_bz + Mg * dTz_bz)
    # dT/du = li R P_i / L_i
    GU_rr = hi_rr + Fc_ur + inv_D * (Tr * Mg_ur + Mg * li * pic)
    GU_rz = hi_rz + Fc_uz + inv_D * (Tr * Mg_uz + Mg * li * piz)
    GU_zr = hi_rz + inv_D * (Tz * Mg_ur - Mg * li * pir)
    GU_zz = hi_zz + inv_D * (Tz * Mg_uz - Mg * li * pic)
    # the ring's share: F = Q_i n_i + li (M_g/D) t_i at I, and the moment about I of that friction force,
    # which acts at the contact, f_i D from I: m = li (M_g/D) f_i D = li f_i M_g
    lid = li * inv_D
    F_r = Qi * ci + lid * Mg * si
    F_z = Qi * si - lid * Mg * ci
    FU_rr = hi_rr + lid * (si * Mg_ur + Mg * pic)
    FU_rz = hi_rz + lid * (si * Mg_uz + Mg * piz)
    FU_zr = hi_rz + lid * (-ci * Mg_ur - Mg * pir)
    FU_zz = hi_zz + lid * (-ci * Mg_uz - Mg * pic)
    FB_rr = -hi_rr + lid * (si * Mg_br - Mg * pic)
    FB_rz = -hi_rz + lid * (si * Mg_bz - Mg * piz)
    FB_zr = -hi_rz + lid * (-ci * Mg_br + Mg * pir)
    FB_zz = -hi_zz + lid * (-ci * Mg_bz + Mg * pic)
    la = lid * arm  # arm = f_i D (mm)
    return (g_r, g_z, GB_rr, GB_rz, GB_zr, GB_zz, GU_rr, GU_rz, GU_zr, GU_zz, F_r, F_z, FU_rr, FU_rz, FU_zr,
            FU_zz, FB_rr, FB_rz, FB_zr, FB_zz, la * Mg, la * Mg_ur, la * Mg_uz, la * Mg_br, la * Mg_bz,
            Qi, Qo, ci, si, co, so, Fc, Mg, wm, delta_i, delta_o)


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def free_position(ur, uz, p, w_i, w_o, smoothing_eps):
    """Where a ball would sit free of the inner race, and whether the rings leave it room there: on the
    bottom of the outer groove, B_f = ((f_o - 1/2) D + delta_o(F_c0), 0) under its centrifugal force F_c0 at
    the nominal orbital speed, clear of the inner race when |u - B_f| <= (f_i - 1/2) D. Whatever the rings'
    approach at rest: at speed the outer contact's deflection may let a ball out that the rings pinch at
    rest. Returns (B_f's radial coordinate in mm, room); never room standing still or with the solver's
    smoothing (its contact law never opens)."""
    ri, ro = p[INNER_RADIUS], p[OUTER_RADIUS]
    gamma = p[GAMMA]
    cos_a = p[COS_NOMINAL]
    wm = 0.5 * (w_i * (1.0 - gamma * cos_a) + w_o * (1.0 + gamma * cos_a))
    Fc = p[MASS_RADIUS] * wm * wm
    br = ro + _hertz_deflection(Fc, p[K_OUTER])
    vr = ur - br
    return br, Fc > 0.0 and smoothing_eps == 0.0 and vr * vr + uz * uz <= ri * ri


@njit(cache=CACHE, fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL, _nrt=REFCOUNT)
def start_position(ur, uz, p, w_i, w_o, smoothing_eps, free_test=True):
    """First guess of the ball centre B (mm from O, mirrored frame) and whether it is taken touching the
    inner race.

    With ``free_test``, a ball the rings leave room for (:func:`free_position`) starts there, free (returns
    inner_loaded False; :func:`settle_ball` then finds its own equilibrium on the outer race). Otherwise the
    guess loads the inner contact with Q_i0 = max(Q, F_c0/4) and the outer with Q_i0 + F_c0 (Q: the
    quasi-static ball load) and puts B where the two contacts' circles about O and I, of radii
    (f_o - 1/2) D + delta_o0 and (f_i - 1/2) D + delta_i0, cross on the outer side; at zero speed that is
    the quasi-static position on the line O-I exactly (or, out of contact, on that line touching the outer
    race).
    """
    ri, ro, Ki, Ko = p[INNER_RADIUS], p[OUTER_RADIUS], p[K_INNER], p[K_OUTER]
    A = math.sqrt(ur * ur + uz * uz)
    delta = deflection(A - ri - ro, smoothing_eps)[0]
    gamma = p[GAMMA]
    cos_a = p[COS_NOMINAL]
    wm = 0.5 * (w_i * (1.0 - gamma * cos_a) + w_o * (1.0 + gamma * cos_a))
    Fc = p[MASS_RADIUS] * wm * wm
    if free_test:
        br, room = free_position(ur, uz, p, w_i, w_o, smoothing_eps)
        if room:
            return br, 0.0, False
    if delta <= 0.0 and Fc == 0.0:  # standing still, out of contact: on the line O-I, touching the outer race
        return ro * ur / A, ro * uz / A, False
    d_o = p[OUTER_SHARE] * max(delta, 0.0)
    Q = Ko * d_o * math.sqrt(d_o)
    Qi = max(Q, 0.25 * Fc)
    Ro = ro + _hertz_deflection(Qi + Fc, Ko)
    Ri = ri + _hertz_deflection(Qi, Ki)
    er = ur / A
    ez = uz / A
    if A >= Ro + Ri or A <= abs(Ro - Ri):  # the circles do not cross: on the line O-I
        return Ro * er, Ro * ez, True
    x = (A * A + Ro * Ro - Ri * Ri) / (2.0 * A)
    h = math.sqrt(max(Ro * Ro - x * x, 0.0))
    # the crossing on the outer side (F_c pushes the ball outward)
    pr, pz = (ez, -er) if ez >= 0.0 else (-ez, er)
    return x * er + h * pr, x * ez + h * pz, True


@njit(inline="always")
def free_constants(p):
    """A ball's column of the speed table as it is free of the inner race: no inner contact (K_i = 0) and
    so no friction there; the outer race alone carries the gyroscopic moment (lambda_o = lambda_i +
    lambda_o: 2, or 0 with race control "none") and sets the spin axis (outer control)."""
    return (p[INNER_RADIUS], p[OUTER_RADIUS], 0.0, p[K_OUTER], p[MASS_RADIUS], p[INERTIA], p[GAMMA], 0.0, p[LAMBDA_INNER] + p[LAMBDA_OUTER], 0.0, p[OUTER_ROTATES], p[INNER_ARM],
            p[DIAMETER], p[OUTER_SHARE], p[COS_NOMINAL])


#: start_position inlined, for the loop over a chunk of cold balls (a call would keep it scalar)
_start_inline = njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)(start_position.py_func)


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _tolerance(st, reach):
    """The residual (N) at which a ball is settled: BALL_RTOL of its largest force, or the rounding floor
    of its position (the contact stiffness times a few ulps of the centre distances ``reach``, mm) for
    the lightest contacts, whose deflections are a few ulps of the centre distances."""
    scale = st[BS_QI] + st[BS_QO] + abs(st[BS_FC])
    stiffness = abs(st[BS_GB_RR]) + abs(st[BS_GB_RZ]) + abs(st[BS_GB_ZR]) + abs(st[BS_GB_ZZ])
    return max(BALL_RTOL * scale, 8.0 * 2.220446049250313e-16 * reach * stiffness)


#: What :func:`_judge` makes of a ball state.
SETTLED, LINEARISED, STEP = 0, 1, 2


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _judge(st, reach, linearise):
    """One look at a ball's state: (SETTLED, 0, 0, True) when its residual is within the ball's tolerance;
    with ``linearise`` (LINEARISED, dB_r, dB_z, exact) when the Newton step dB is short against both
    deflections (LINEAR_REACH; ``exact`` within LINEAR_RTOL); else (STEP, s_r, s_z, False) with the Newton
    step s = G_B^-1 g (B - s is the next iterate). ``reach`` (mm) scales the ball's rounding floor."""
    g_r, g_z, a, b, c, d = st[BS_GR], st[BS_GZ], st[BS_GB_RR], st[BS_GB_RZ], st[BS_GB_ZR], st[BS_GB_ZZ]
    if max(abs(g_r), abs(g_z)) <= _tolerance(st, reach):
        return SETTLED, 0.0, 0.0, True
    det = a * d - b * c
    step_r = (d * g_r - b * g_z) / det
    step_z = (a * g_z - c * g_r) / det
    if linearise and st[BS_DI] > 0.0 and st[BS_DO] > 0.0:
        moved_o = abs(st[BS_CO] * step_r + st[BS_SO] * step_z) / st[BS_DO]
        moved_i = abs(st[BS_CI] * step_r + st[BS_SI] * step_z) / st[BS_DI]
        if moved_o <= LINEAR_REACH and moved_i <= LINEAR_REACH:
            swing = math.sqrt(step_r * step_r + step_z * step_z)  # the tangential part: against |B| ~ D
            exact = max(moved_o, moved_i) <= LINEAR_RTOL and swing <= LINEAR_RTOL * reach
            return LINEARISED, -step_r, -step_z, exact
    return STEP, step_r, step_z, False


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _step_length(st, step_r, step_z, reach, ri):
    """The fraction t of the Newton step s (B - t s is the next iterate) a ball takes from state ``st``:
    at most halving either deflection (Hertz contacts soften to nothing as they unload), but swinging
    the ball round its contacts freely (the soft tangential direction)."""
    shrink_o = st[BS_CO] * step_r + st[BS_SO] * step_z  # delta_o falls by n_o . step
    shrink_i = -(st[BS_CI] * step_r + st[BS_SI] * step_z)  # delta_i falls by -n_i . step
    t = 1.0
    if shrink_o > 0.5 * st[BS_DO] + 1e-15 * reach:
        t = min(t, (0.5 * st[BS_DO] + 1e-15 * reach) / shrink_o)
    # ... except when the inner contact has all but opened (1e-6 of its reach): then the ball may leave it
    # (its equilibrium on the outer race alone lies there), and Newton re-enters if it must
    if shrink_i > 0.5 * st[BS_DI] + 1e-15 * reach and st[BS_DI] > 1e-6 * ri:
        t = min(t, (0.5 * st[BS_DI] + 1e-15 * reach) / shrink_i)
    return t


@njit(cache=CACHE, fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL, _nrt=REFCOUNT)
def _newton(ur, uz, br, bz, p, w_i, w_o, smoothing_eps, max_iterations, linearise):
    """Newton on one ball's equilibrium g(B) = 0 from B = (br, bz); returns (state, br, bz, iterations,
    settled, dB_r, dB_z, exact).

    Settled with dB = 0 and exact: the residual is within the ball's tolerance at B. With ``linearise``, also
    settled where the next Newton step dB is short (LINEAR_REACH): the caller corrects the state's forces to
    first order with dB, which is ``exact`` when dB is within LINEAR_RTOL of the deflections.
    """
    reach = p[INNER_RADIUS] + p[OUTER_RADIUS] + abs(ur) + abs(uz)
    ri = p[INNER_RADIUS]
    it = 0
    while True:
        # one call site: ball_state is inlined, and each site costs its whole body in compile time
        st = ball_state(ur, uz, br, bz, p, w_i, w_o, smoothing_eps)
        verdict, step_r, step_z, exact = _judge(st, reach, linearise)
        if verdict != STEP:
            return st, br, bz, it, True, step_r, step_z, exact
        if it == max_iterations:
            return st, br, bz, it, False, 0.0, 0.0, False
        t = _step_length(st, step_r, step_z, reach, ri)
        br -= step_r * t
        bz -= step_z * t
        it += 1


@njit(cache=CACHE, fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL, _nrt=REFCOUNT)
def settle_ball(ur, uz, p, w_i, w_o, smoothing_eps, warm_br=0.0, warm_bz=0.0, warm=False, linearise=False):
    """Settle one ball, by one rule whatever the history (a warm start only shortens the way):

    1. Where the rings leave it room (:func:`free_position`), the ball's own equilibrium on the outer race
       alone (:func:`free_constants`: Newton from B_f). If that clears the inner race, the ball is free:
       returns iterations -1, settled, with its state there (Q_i = 0: nothing for the ring).
    2. Otherwise the ball is wedged between the races: Newton on g(B) = 0 from the warm start (warm_br,
       warm_bz) when ``warm`` (kept if it settles with both contacts closed within WARM_ITERATIONS), else
       from :func:`start_position`'s wedged guess; with ``linearise``, to the first short step
       (:func:`_newton`).

    Returns (state tuple of :func:`ball_state` at B, br, bz, iterations, settled, dB_r, dB_z, exact): the
    solution is B + dB (dB = 0 unless linearised).
    """
    brf, room = free_position(ur, uz, p, w_i, w_o, smoothing_eps)
    if room:
        # the iteration limits typed as int64 and the flag as bool, not literals: numba would compile _newton
        # (and the ball state inlined in it) once per literal, about 1.7-2.5 s each
        st, br, bz, it, settled, _, _, _ = _newton(ur, uz, brf, 0.0, free_constants(p), w_i, w_o, smoothing_eps,
                                                   np.int64(BALL_ITERATIONS), np.bool_(False))
        if settled and st[BS_DI] <= 0.0:
            return st, br, bz, -1, True, 0.0, 0.0, True
    if warm:
        st, wbr, wbz, it, settled, db_r, db_z, exact = _newton(ur, uz, warm_br, warm_bz, p, w_i, w_o,
                                                               smoothing_eps, np.int64(WARM_ITERATIONS), linearise)
        if settled and st[BS_DI] > 0.0 and st[BS_DO] > 0.0:
            return st, wbr, wbz, it, True, db_r, db_z, exact
    br, bz, _ = start_position(ur, uz, p, w_i, w_o, smoothing_eps, False)
    return _newton(ur, uz, br, bz, p, w_i, w_o, smoothing_eps, np.int64(BALL_ITERATIONS), linearise)


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def sensitivity(st):
    """X = G_B^-1 G_u (2x2, row-major): how the settled centre B moves with the inner groove centre u,
    dB = -X du."""
    a, b, c, d = st[BS_GB_RR], st[BS_GB_RZ], st[BS_GB_ZR], st[BS_GB_ZZ]
    det = a * d - b * c
    return ((d * st[BS_GU_RR] - b * st[BS_GU_ZR]) / det, (d * st[BS_GU_RZ] - b * st[BS_GU_ZZ]) / det,
            (a * st[BS_GU_ZR] - c * st[BS_GU_RR]) / det, (a * st[BS_GU_ZZ] - c * st[BS_GU_RZ]) / det)


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def condensed(st, x00, x01, x10, x11):
    """The ball's condensed stiffness: dF/du = F_u - F_B X (2x2, mirrored frame) and dm/du = m_u - m_B X
    (2), from a :func:`ball_state` tuple and its :func:`sensitivity` X = G_B^-1 G_u."""
    k00 = st[BS_FU_RR] - (st[BS_FB_RR] * x00 + st[BS_FB_RZ] * x10)
    k01 = st[BS_FU_RZ] - (st[BS_FB_RR] * x01 + st[BS_FB_RZ] * x11)
    k10 = st[BS_FU_ZR] - (st[BS_FB_ZR] * x00 + st[BS_FB_ZZ] * x10)
    k11 = st[BS_FU_ZZ] - (st[BS_FB_ZR] * x01 + st[BS_FB_ZZ] * x11)
    m0 = st[BS_MU_R] - (st[BS_MB_R] * x00 + st[BS_MB_Z] * x10)
    m1 = st[BS_MU_Z] - (st[BS_MB_R] * x01 + st[BS_MB_Z] * x11)
    return k00, k01, k10, k11, m0, m1


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _add_column(acc, c, s, z, R, k00, k01, k10, k11, m0, m1, a, b):
    """A column of Kb plus one ball's J^T (dF/du) J + w (dm/du) J for the column (a, b) of J."""
    ra = k00 * a + k01 * b
    rb = k10 * a + k11 * b
    rm = R * rb - z * ra + m0 * a + m1 * b  # moment row: d(R Fz - z Fr + m)/dq
    return (acc[0] + c * ra, acc[1] + s * ra, acc[2] + rb, acc[3] + s * rm, acc[4] - c * rm)


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _summary(st, db_r, db_z):
    """What the ring loop needs of a ball state (mirrored frame): the residual, the loads, normals, F_c, M_g,
    omega_m and deflections of the state, its sensitivity X, the ring force (F_r, F_z) and moment m to
    first order at B + dB, and the condensed stiffness (dF/du 2x2, dm/du 2); fields SM_GR..SM_M1."""
    x00, x01, x10, x11 = sensitivity(st)
    k00, k01, k10, k11, m0, m1 = condensed(st, x00, x01, x10, x11)
    return (st[BS_GR], st[BS_GZ], st[BS_QI], st[BS_QO], st[BS_CI], st[BS_SI], st[BS_CO], st[BS_SO], st[BS_FC], st[BS_MG], st[BS_WM], st[BS_DI], st[BS_DO],
            x00, x01, x10, x11,
            st[BS_FR] + (st[BS_FB_RR] * db_r + st[BS_FB_RZ] * db_z), st[BS_FZ] + (st[BS_FB_ZR] * db_r + st[BS_FB_ZZ] * db_z),
            st[BS_M] + (st[BS_MB_R] * db_r + st[BS_MB_Z] * db_z), k00, k01, k10, k11, m0, m1)


@njit(inline="always")
def _write_summary(out, i, sm):
    """Store a :func:`_summary` as ball i of a chunk (field k at k*CHUNK + i: one store stream)."""
    out[SM_GR * CHUNK + i] = sm[SM_GR]
    out[SM_GZ * CHUNK + i] = sm[SM_GZ]
    out[SM_QI * CHUNK + i] = sm[SM_QI]
    out[SM_QO * CHUNK + i] = sm[SM_QO]
    out[SM_CI * CHUNK + i] = sm[SM_CI]
    out[SM_SI * CHUNK + i] = sm[SM_SI]
    out[SM_CO * CHUNK + i] = sm[SM_CO]
    out[SM_SO * CHUNK + i] = sm[SM_SO]
    out[SM_FC * CHUNK + i] = sm[SM_FC]
    out[SM_MG * CHUNK + i] = sm[SM_MG]
    out[SM_WM * CHUNK + i] = sm[SM_WM]
    out[SM_DI * CHUNK + i] = sm[SM_DI]
    out[SM_DO * CHUNK + i] = sm[SM_DO]
    out[SM_X00 * CHUNK + i] = sm[SM_X00]
    out[SM_X01 * CHUNK + i] = sm[SM_X01]
    out[SM_X10 * CHUNK + i] = sm[SM_X10]
    out[SM_X11 * CHUNK + i] = sm[SM_X11]
    out[SM_FR * CHUNK + i] = sm[SM_FR]
    out[SM_FZ * CHUNK + i] = sm[SM_FZ]
    out[SM_M * CHUNK + i] = sm[SM_M]
    out[SM_K00 * CHUNK + i] = sm[SM_K00]
    out[SM_K01 * CHUNK + i] = sm[SM_K01]
    out[SM_K10 * CHUNK + i] = sm[SM_K10]
    out[SM_K11 * CHUNK + i] = sm[SM_K11]
    out[SM_M0 * CHUNK + i] = sm[SM_M0]
    out[SM_M1 * CHUNK + i] = sm[SM_M1]


@njit(inline="always")
def _read_summary(out, i):
    """Ball i of a chunk: its :func:`_summary`, the centre B taken (br, bz; the next Newton iterate where
    the verdict of :func:`_judge` is STEP), the linearised step (db_r, db_z), whether that is exact, and
    the verdict."""
    sm = (out[SM_GR * CHUNK + i], out[SM_GZ * CHUNK + i], out[SM_QI * CHUNK + i], out[SM_QO * CHUNK + i],
          out[SM_CI * CHUNK + i], out[SM_SI * CHUNK + i], out[SM_CO * CHUNK + i], out[SM_SO * CHUNK + i],
          out[SM_FC * CHUNK + i], out[SM_MG * CHUNK + i], out[SM_WM * CHUNK + i], out[SM_DI * CHUNK + i],
          out[SM_DO * CHUNK + i], out[SM_X00 * CHUNK + i], out[SM_X01 * CHUNK + i], out[SM_X10 * CHUNK + i],
          out[SM_X11 * CHUNK + i], out[SM_FR * CHUNK + i], out[SM_FZ * CHUNK + i], out[SM_M * CHUNK + i],
          out[SM_K00 * CHUNK + i], out[SM_K01 * CHUNK + i], out[SM_K10 * CHUNK + i], out[SM_K11 * CHUNK + i],
          out[SM_M0 * CHUNK + i], out[SM_M1 * CHUNK + i])
    return (sm, out[SM_BR * CHUNK + i], out[SM_BZ * CHUNK + i], out[SM_DBR * CHUNK + i], out[SM_DBZ * CHUNK + i],
            out[SM_EXACT * CHUNK + i] != 0.0, out[SM_VERDICT * CHUNK + i])


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _inner_centre(q, table, j):
    """The inner groove centre u = (ur, uz) of ball j (mm from its outer groove centre, mirrored frame) at
    the ring displacement q."""
    c = table[COS_PSI, j]
    s = table[SIN_PSI, j]
    z = table[AXIAL_OFFSET, j]
    R = table[PITCH_RADIUS, j]
    dr = (q[0] + z * q[4]) * c + (q[1] - z * q[3]) * s
    dzb = q[2] + R * (q[3] * s - q[4] * c)
    return dr + table[UR0, j], table[DIRECTION, j] * (dzb + table[UZ0, j])  # mirrored: the row's contact direction is +z


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _ball_constants(speed_table, j, omega):
    """Ball j's column of the high-speed table as a tuple, and its ring speeds (w_i, w_o) in rad/s."""
    p = (speed_table[INNER_RADIUS, j], speed_table[OUTER_RADIUS, j], speed_table[K_INNER, j], speed_table[K_OUTER, j], speed_table[MASS_RADIUS, j],
         speed_table[INERTIA, j], speed_table[GAMMA, j], speed_table[LAMBDA_INNER, j], speed_table[LAMBDA_OUTER, j], speed_table[INNER_CONTROL, j],
         speed_table[OUTER_ROTATES, j], speed_table[INNER_ARM, j], speed_table[DIAMETER, j], speed_table[OUTER_SHARE, j], speed_table[COS_NOMINAL, j])
    outer = speed_table[OUTER_ROTATES, j]
    return p, omega * (1.0 - outer), omega * outer


@njit(inline="always")
def _all_cold(warm, n, j0, m):
    """Whether no ball of j0 .. j0+m-1 (of n) has a warm start (a function: its result is typed bool, never a
    literal, so that _predicted_chunk compiles once)."""
    for j in range(j0, j0 + m):
        if warm[warm_cell(WARM_VALID, n, j)] != 0.0:
            return False
    return True


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _prediction(warm, n, j, ur, uz):
    """Ball j's (of n) first-order start B - X (u' - u) from its warm start (mm, mirrored frame)."""
    du_r = ur - warm[warm_cell(WARM_UR, n, j)]
    du_z = uz - warm[warm_cell(WARM_UZ, n, j)]
    x00, x01, x10, x11 = warm_x(warm, n, j)
    return (warm[warm_cell(WARM_BR, n, j)] - (x00 * du_r + x01 * du_z),
            warm[warm_cell(WARM_BZ, n, j)] - (x10 * du_r + x11 * du_z))


@njit(cache=CACHE, fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL, _nrt=REFCOUNT)
def _predicted_chunk(q, table, speed_table, omega, eps, warm, out, j0, m, linearise, cold):
    """Balls j0 .. j0+m-1 at their first-order predictions from ``warm`` (``cold``: at their cold guesses,
    :func:`start_position`; SM_LOADED 0 where the rings leave the ball room to be free): state, judgement
    (:func:`_judge`; where it says STEP, the step's end as the centre) and :func:`_summary` into ``out``
    (flat, field k of ball j0+i at k*CHUNK + i).
    Branch-free passes over the balls, so that they vectorise; a ball without a warm start in a warm
    chunk gets a meaningless summary, which the caller does not read."""
    n = table.shape[1]
    if cold:
        for i in range(m):
            ur, uz = _inner_centre(q, table, j0 + i)
            p, w_i, w_o = _ball_constants(speed_table, j0 + i, omega)
            br, bz, _ = _start_inline(ur, uz, p, w_i, w_o, eps)
            out[SM_BR * CHUNK + i] = br
            out[SM_BZ * CHUNK + i] = bz
    for i in range(m):
        j = j0 + i
        ur, uz = _inner_centre(q, table, j)
        p, w_i, w_o = _ball_constants(speed_table, j, omega)
        br, bz = _prediction(warm, n, j, ur, uz)
        if cold:
            br = out[SM_BR * CHUNK + i]
            bz = out[SM_BZ * CHUNK + i]
        # room to be free (warm or cold alike: the ball's state must not depend on the history)
        out[SM_LOADED * CHUNK + i] = 0.0 if free_position(ur, uz, p, w_i, w_o, eps)[1] else 1.0
        st = ball_state(ur, uz, br, bz, p, w_i, w_o, eps)
        reach = p[INNER_RADIUS] + p[OUTER_RADIUS] + abs(ur) + abs(uz)
        verdict, db_r, db_z, exact = _judge(st, reach, linearise)
        sm = _summary(st, db_r, db_z)
        if verdict == STEP:  # a step to take: the caller settles the ball from its next iterate
            t = _step_length(st, db_r, db_z, reach, p[INNER_RADIUS])
            br -= db_r * t
            bz -= db_z * t
        _write_summary(out, i, sm)
        out[SM_BR * CHUNK + i] = br
        out[SM_BZ * CHUNK + i] = bz
        out[SM_VERDICT * CHUNK + i] = verdict
        out[SM_EXACT * CHUNK + i] = 1.0 if exact else 0.0
        out[SM_DBR * CHUNK + i] = db_r
        out[SM_DBZ * CHUNK + i] = db_z
        out[SM_UR * CHUNK + i] = ur
        out[SM_UZ * CHUNK + i] = uz


#: The ring sums' start: f and the five columns of Kb.
_NO_SUMS = ((0.0,) * 5,) * 6


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _ring_add(sums, sm, table, j, eps, ordinary):
    """``sums`` (f, then Kb's columns) plus ball j's share from its :func:`_summary`, in the bearing's
    frame (the axial components take the row's sign). An unloaded ball adds nothing (selects, not a
    branch: the loop over a chunk vectorises, and an unloaded ball's summary may hold inf or NaN)."""
    c = table[COS_PSI, j]
    s = table[SIN_PSI, j]
    z = table[AXIAL_OFFSET, j]
    R = table[PITCH_RADIUS, j]
    sgn = table[DIRECTION, j]
    on = (sm[SM_QI] > 0.0 or eps != 0.0) and ordinary
    Fr = sm[SM_FR] if on else 0.0
    Fz = sgn * sm[SM_FZ] if on else 0.0
    mo = R * Fz - z * Fr + (sgn * sm[SM_M] if on else 0.0)
    fs, acc0, acc1, acc2, acc3, acc4 = sums
    fs = (fs[0] + Fr * c, fs[1] + Fr * s, fs[2] + Fz, fs[3] + mo * s, fs[4] - mo * c)
    k00 = sm[SM_K00] if on else 0.0
    k01 = sgn * sm[SM_K01] if on else 0.0
    k10 = sgn * sm[SM_K10] if on else 0.0
    k11 = sm[SM_K11] if on else 0.0
    m0 = sgn * sm[SM_M0] if on else 0.0
    m1 = sm[SM_M1] if on else 0.0
    # columns of J: a = d(ur)/dq, b = d(uz)/dq (bearing frame); the sums stay in registers
    return (fs, _add_column(acc0, c, s, z, R, k00, k01, k10, k11, m0, m1, c, 0.0),
            _add_column(acc1, c, s, z, R, k00, k01, k10, k11, m0, m1, s, 0.0),
            _add_column(acc2, c, s, z, R, k00, k01, k10, k11, m0, m1, 0.0, 1.0),
            _add_column(acc3, c, s, z, R, k00, k01, k10, k11, m0, m1, -z * s, R * s),
            _add_column(acc4, c, s, z, R, k00, k01, k10, k11, m0, m1, z * c, -R * c))


@njit(cache=CACHE, fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL, _nrt=REFCOUNT)
def _ring_sums(sums, table, speed_table, out, j0, m, eps):
    """``sums`` plus the shares of balls j0 .. j0+m-1 from their summaries in the chunk ``out`` (none from a
    four-point ball's pairs, which engine/four_point.py adds): loads and sums only, so that it vectorises."""
    for i in range(m):
        sums = _ring_add(sums, _read_summary(out, i)[0], table, j0 + i, eps, speed_table[PARTNER, j0 + i] < 0.0)
    return sums


@njit(inline="always")
def write_contacts(ball_load, contact_angle, n, j, Qi, Qo, ci, si, co, so):
    """Column j's contacts into the per-element record: the inner one's load (N) and angle (rad) at j and, in a
    record with room for them (2 n), the outer one's at n + j (a map's life at speed reads them)."""
    ball_load[j] = Qi
    contact_angle[j] = atan2(si, ci)
    if ball_load.shape[0] >= 2 * n:
        ball_load[n + j] = Qo
        contact_angle[n + j] = atan2(so, co)


@njit(inline="always")
def write_state(states, j, Qi, Qo, ci, si, co, so, Fc, Mg, wm, iterations, residual):
    """Column j's row of the ball-state record (schema STATE_*: loads N, angles rad, F_c N, M_g N*mm, omega_m
    rad/s, the settle's iterations and its relative residual)."""
    states[j, STATE_INNER_LOAD] = Qi
    states[j, STATE_OUTER_LOAD] = Qo
    states[j, STATE_INNER_ANGLE] = atan2(si, ci)
    states[j, STATE_OUTER_ANGLE] = atan2(so, co)
    states[j, STATE_CENTRIFUGAL] = Fc
    states[j, STATE_GYROSCOPIC] = Mg
    states[j, STATE_ORBITAL_SPEED] = wm
    states[j, STATE_ITERATIONS] = iterations
    states[j, STATE_RESIDUAL] = residual


@njit(cache=CACHE, fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL, _nrt=REFCOUNT)
def _ball_pass(q, table, speed_table, omega, eps, ball_load, contact_angle, states, warm):
    """:func:`spinning_balls`' work, Kb or not (one compiled loop for both): returns (the ring sums,
    sum of Q_i in N, loaded balls, warning bits)."""
    n = table.shape[1]
    sums = _NO_SUMS
    total = 0.0
    n_loaded = 0
    flags = 0
    linearise = n > 0 and states is None and warm[warm_cell(WARM_LINEARISE, n, 0)] != 0.0
    out = warm[N_WARM * n:]  # the scratch's tail
    for j0 in range(0, n, CHUNK):
        m = min(CHUNK, n - j0)
        # a chunk with no warm start at all (a case's first evaluation) starts from the cold guesses
        cold = _all_cold(warm, n, j0, m)
        _predicted_chunk(q, table, speed_table, omega, eps, warm, out, j0, m, linearise, cold)
        for i in range(m):
            j = j0 + i
            if speed_table[PARTNER, j] >= 0.0:  # a four-point ball's pair: engine/four_point.py settles it
                continue
            ur, uz = out[SM_UR * CHUNK + i], out[SM_UZ * CHUNK + i]  # the pass's inner groove centre
            sm, br, bz, db_r, db_z, exact, verdict = _read_summary(out, i)
            iterations = 0
            settled = True
            start = False  # (br, bz) is a start for a settle: the prediction
            room = out[SM_LOADED * CHUNK + i] == 0.0
            if cold:
                # settled or linearised at the cold guess: what settle_ball would return (a ball that needs a
                # step is settled by it from the step's end, its next iterate); room to be free: settle_ball
                # decides, from its free equilibrium
                resettle = verdict == STEP or room
                start = verdict == STEP and not room
            elif warm[warm_cell(WARM_VALID, n, j)] != 0.0:
                start = True
                # both contacts closed at a settled or nearly settled centre, and no room to be free: the ball's
                # one equilibrium (its potential is convex where it touches a race); a step to take, a contact
                # open or room to be free: settle
                resettle = verdict == STEP or not (sm[SM_DI] > 0.0 and sm[SM_DO] > 0.0) or room
            else:
                resettle = True  # no warm start (free at the last evaluation): from the cold guess
            if resettle:
                p, w_i, w_o = _ball_constants(speed_table, j, omega)
                st, br, bz, iterations, settled, db_r, db_z, exact = settle_ball(ur, uz, p, w_i, w_o, eps, br, bz,
                                                                                 start, linearise)
                sm = _summary(st, db_r, db_z)
                _write_summary(out, i, sm)  # for the ring sums
            _, _, Qi, Qo, ci, si, co, so, Fc, Mg, wm, d_i, d_o = sm[:SM_X00]
            if not exact:
                flags |= 8
            warm[warm_cell(WARM_BR, n, j)] = br + db_r
            warm[warm_cell(WARM_BZ, n, j)] = bz + db_z
            warm[warm_cell(WARM_UR, n, j)] = ur
            warm[warm_cell(WARM_UZ, n, j)] = uz
            warm[warm_cell(WARM_X00, n, j)] = sm[SM_X00]
            warm[warm_cell(WARM_X01, n, j)] = sm[SM_X01]
            warm[warm_cell(WARM_X10, n, j)] = sm[SM_X10]
            warm[warm_cell(WARM_X11, n, j)] = sm[SM_X11]
            warm[warm_cell(WARM_VALID, n, j)] = 1.0 if settled and iterations >= 0 else 0.0
            loaded = d_i > 0.0
            n_loaded += loaded
            if not settled:
                flags |= 4
            if loaded and si < 0.0 and table[UZ0, j] != 0.0:  # a level row (a0 = 0) has no direction to reverse
                flags |= 1
            if loaded and ci * table[UR0, j] < 0.0:  # groove centres crossed over radially (kernel.ball_sums)
                flags |= 1
            if d_i + d_o > table[DEFLECTION_LIMIT, j]:
                flags |= 2
            total += Qi
            if ball_load is not None:
                write_contacts(ball_load, contact_angle, n, j, Qi, Qo, ci, si, co, so)
            if states is not None:
                # the equilibrium residual relative to the ball's largest force (a free ball's on the outer race)
                write_state(states, j, Qi, Qo, ci, si, co, so, Fc, Mg, wm, iterations,
                            max(abs(sm[SM_GR]), abs(sm[SM_GZ])) / max(Qi + Qo + abs(Fc), 1e-300))
        sums = _ring_sums(sums, table, speed_table, out, j0, m, eps)
    return sums, total, n_loaded, flags


@njit(inline="always")
def _any_ordinary(speed_table):
    """Whether any column is an angular contact ball (not a four-point ball's pair, PARTNER < 0)."""
    for j in range(speed_table.shape[1]):
        if speed_table[PARTNER, j] < 0.0:
            return True
    return False


@njit(cache=CACHE, fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL, _nrt=REFCOUNT)
def spinning_balls(q, table, speed_table, omega, eps, f, K, ball_load, contact_angle, states, warm):
    """Write f (5) and, unless ``K`` is None, Kb (5x5, not symmetric) of the ball rows at shaft speed.

    ``table`` is the quasi-static ball table (bearing.ball_table), ``speed_table`` (N_SPEED_COLUMNS,
    n_balls) the balls' high-speed constants, ``omega`` the shaft speed in rad/s, ``eps`` the solver's
    smoothing (mm; 0: the exact contact law). Each ball's centre is settled; the ring gets its inner
    contact's force (and the friction's moment) through the same J = [a; b] as the quasi-static ball,
    and Kb += J^T (dF/du) J + w (dm/du) J per ball with w = (0, 0, 0, sin psi, -cos psi).
    ``ball_load``/``contact_angle`` record Q_i (N) and alpha_i (rad, positive on the row's direction), and
    in a record of 2 n_balls Q_o and alpha_o after them (a load map's life at speed); ``states``
    (n_balls, N_STATE) or None records the whole ball.

    ``warm`` (:func:`warm_size` (n_balls) cells; :func:`new_warm`): each ball starts from its last settled
    centre moved by the first-order prediction (rows WARM_*; none in a fresh scratch: the cold guess) and
    leaves its new one there (a scratch of another size returns NaN with bit 4). CHUNK balls at a time,
    one vectorised pass (:func:`_predicted_chunk`) takes every ball's state at its prediction (at its cold
    guess in a chunk with no warm start at all) into the scratch's tail; the loop then takes each summary
    that will do and settles the others one by one (:func:`settle_ball`). Inside a solve (``warm`` row
    WARM_LINEARISE set) and without ``states`` the balls are linearised (:func:`_judge`: one ball state each
    where the prediction is good; a record is then taken at B, within LINEAR_RTOL of the model's when the
    evaluation is not flagged 8). Returns (sum of Q_i in N, loaded balls, warning bits: 1 contact reversed,
    2 beyond validity, 4 a ball not settled, 8 a ball linearised with a step beyond LINEAR_RTOL: f and Kb
    first-order close, evaluate again for the model's).
    """
    n = table.shape[1]
    if warm.size != warm_size(n):  # not this ball set's scratch: a caller's error, reported as such
        f[:] = math.nan
        if K is not None:
            K[:, :] = math.nan
        return math.nan, 0, 4
    if not _any_ordinary(speed_table):
        # only four-point balls (engine/four_point.py settles them): the pass would take every column's state
        # and use none of them (issue 47 item 6: a sixth of a QJ 210 case at speed); f and Kb as it leaves them
        for i in range(5):
            f[i] = 0.0
            if K is not None:
                for k in range(5):
                    K[i, k] = 0.0
        return 0.0, 0, 0
    sums, total, n_loaded, flags = _ball_pass(q, table, speed_table, omega, eps, ball_load, contact_angle, states,
                                              warm)
    fs, acc0, acc1, acc2, acc3, acc4 = sums
    if K is not None:
        for i in range(5):
            K[i, 0] = acc0[i]
            K[i, 1] = acc1[i]
            K[i, 2] = acc2[i]
            K[i, 3] = acc3[i]
            K[i, 4] = acc4[i]
    for i in range(5):
        f[i] = fs[i]
    return total, n_loaded, flags
