"""The physics kernel: the one ball loop that turns q into f and Kb.

Everything (solver, sweeps, ball-passage tables, reports) calls
:func:`ball_loop`; there is no other loop over balls that evaluates contacts.
Units: q in mm and rad; f in N and N*mm; Kb in N/mm, N*mm/rad, N/rad.
"""

import math

from numba import njit

from .config import CACHE, FASTMATH


@njit(cache=CACHE, fastmath=FASTMATH, nogil=True)
def ball_loop(q, balls, f, K, with_stiffness, ball_load, contact_angle):
    """Fill f (5) and, if ``with_stiffness``, Kb (5x5) in place at displacement q.

    Per ball (MODEL.md): radial and axial approach of the groove centres, the
    loaded distance A = sqrt(ur^2 + uz^2), Hertz deflection delta = A - A0,
    ball load Q = Kn*delta^n. The ball adds Q*(ur*a + uz*b)/A to f and
    J^T H J to Kb, with J = [a; b] = d(ur, uz)/dq and the 2x2 contact
    Hessian H = (Q/A)(I - h h^T) + Q' h h^T, h = (ur, uz)/A, Q' = n*Q/delta.
    This compact form equals the paper's Eq. (15a-o) without dividing by ur.

    Parameters
    ----------
    q : (5,) float64
        (dx, dy, dz, bx, by) in mm and rad at the bearing centre.
    balls : (n_balls, 11) float64
        Per-ball table from :meth:`fastbearing.Bearing.ball_table`.
    f : (5,) float64, out
        (Fx, Fy, Fz, Mx, My) on the inner ring in N and N*mm.
    K : (5, 5) float64, out
        Kb = df/dq; left untouched when ``with_stiffness`` is False.
    with_stiffness : bool
        Skip the Kb update (secant solvers need only f).
    ball_load, contact_angle : (n_balls,) or (0,) float64, out
        Q_j in N and the loaded contact angle alpha_j in rad, signed so that
        it is positive on the row's own contact direction. Pass empty arrays
        to skip recording.

    Returns
    -------
    total_load : float
        Sum of ball loads in N (0 when no ball is loaded).
    n_loaded : int
        Number of loaded balls.
    n_reversed : int
        Loaded balls whose contact angle has the opposite sign to their
        row's contact direction.
    """
    dx = q[0]
    dy = q[1]
    dz = q[2]
    bx = q[3]
    by = q[4]
    record = ball_load.shape[0] > 0
    f0 = f1 = f2 = f3 = f4 = 0.0
    k00 = k01 = k02 = k03 = k04 = 0.0
    k11 = k12 = k13 = k14 = 0.0
    k22 = k23 = k24 = 0.0
    k33 = k34 = k44 = 0.0
    total = 0.0
    n_loaded = 0
    n_reversed = 0
    for j in range(balls.shape[0]):
        c = balls[j, 0]
        s = balls[j, 1]
        z = balls[j, 2]
        R = balls[j, 3]
        ur = (dx + z * by) * c + (dy - z * bx) * s + balls[j, 4]
        uz = dz + R * (bx * s - by * c) + balls[j, 5]
        A = math.sqrt(ur * ur + uz * uz)
        delta = A - balls[j, 6]
        if record:
            contact_angle[j] = math.atan2(balls[j, 10] * uz, ur)
            ball_load[j] = 0.0
        if delta <= 0.0:
            continue
        n = balls[j, 8]
        if n == 1.5:
            Q = balls[j, 7] * delta * math.sqrt(delta)  # sqrt is far cheaper than pow
        else:
            Q = balls[j, 7] * delta ** n
        if record:
            ball_load[j] = Q
        total += Q
        n_loaded += 1
        if balls[j, 10] * uz < 0.0:
            n_reversed += 1
        g = Q / A
        fr = g * ur
        fz = g * uz
        m = R * fz - z * fr
        f0 += fr * c
        f1 += fr * s
        f2 += fz
        f3 += m * s
        f4 -= m * c
        if with_stiffness:
            hr = ur / A
            hz = uz / A
            dq = n * Q / delta - g
            h11 = g + dq * hr * hr
            h12 = dq * hr * hz
            h22 = g + dq * hz * hz
            # Kb += a u^T + b w^T with u = H11 a + H12 b, w = H12 a + H22 b,
            # a = (c, s, 0, -z s, z c), b = (0, 0, 1, R s, -R c).
            p = R * h12 - z * h11
            r = R * h22 - z * h12
            t = R * r - z * p
            cc = c * c
            ss = s * s
            cs = c * s
            k00 += h11 * cc
            k01 += h11 * cs
            k02 += h12 * c
            k03 += cs * p
            k04 -= cc * p
            k11 += h11 * ss
            k12 += h12 * s
            k13 += ss * p
            k14 -= cs * p
            k22 += h22
            k23 += s * r
            k24 -= c * r
            k33 += ss * t
            k34 -= cs * t
            k44 += cc * t
    f[0] = f0
    f[1] = f1
    f[2] = f2
    f[3] = f3
    f[4] = f4
    if with_stiffness:
        K[0, 0] = k00
        K[0, 1] = K[1, 0] = k01
        K[0, 2] = K[2, 0] = k02
        K[0, 3] = K[3, 0] = k03
        K[0, 4] = K[4, 0] = k04
        K[1, 1] = k11
        K[1, 2] = K[2, 1] = k12
        K[1, 3] = K[3, 1] = k13
        K[1, 4] = K[4, 1] = k14
        K[2, 2] = k22
        K[2, 3] = K[3, 2] = k23
        K[2, 4] = K[4, 2] = k24
        K[3, 3] = k33
        K[3, 4] = K[4, 3] = k34
        K[4, 4] = k44
    return total, n_loaded, n_reversed
