"""The physics kernel: the one ball loop that turns q into f and Kb.

Everything (solver, sweeps, ball-passage tables, reports) calls
:func:`ball_loop`; there is no other loop over balls that evaluates contacts.
Units: q in mm and rad; f in N and N*mm; Kb in N/mm, N*mm/rad, N/rad.

The loop body is branch-free (an unloaded ball has delta clamped to 0 and so
contributes exactly nothing), which lets LLVM vectorise it across balls.
Optional work is chosen by argument types, so numba compiles a separate,
specialised loop for each use from this one source: ``K=None`` skips the
stiffness, ``ball_load=None`` skips the per-ball record, and an exponent of
``None`` in the ball set means every ball is Hertzian (n = 1.5, sqrt instead
of pow).
"""

import math

from numba import njit, types
from numba.extending import overload

from .schema import (ElementSet, A0, AXIAL_OFFSET, BALL_OF, COS_PSI, DEFLECTION_LIMIT, DIRECTION, EXPONENT, GAP2, HALF_COUNT, KN,
                     MIRROR_HALF, MIRROR_OF, PITCH_RADIUS, SHARE, SIN_PSI, S_ANGLE, S_AXIAL,
                     S_COS_PSI, S_COUNT, S_NORMAL_R, S_NORMAL_Z, S_OFFSET, S_POSITION, S_RADIUS, S_ROLLER, S_SCALE,
                     S_SIN_PSI, S_STIFFNESS, UR0, UZ0, WEIGHT)
from ..config import CACHE, ERROR_MODEL, KERNEL_FASTMATH, REFCOUNT
from .deflection import smoothed_deflection
from .four_point import four_point_balls
from .high_speed import forget_warm, spinning_balls, standing_still, take_linearised, warm_scratch  # noqa: F401
from .roots import ninth_root
from ..status import BALL_LINEARISED, BALL_UNSETTLED, BEYOND_VALIDITY, CONTACT_REVERSED
from .trig import atan2

#: The running sums of f (5) and the 14 independent Kb entries, at zero.
ZERO_SUMS = (0.0,) * 19


def contact_law(delta, kn, exponent, n):
    """Ball load Q = Kn*delta^n and its slope dQ/d(delta) (N, N/mm): n = 1.5 (a sqrt) where ``exponent`` is
    None (every ball Hertzian), else the ball's own exponent ``n``."""


def clamped_deflection(d, smoothing):
    """Deflection delta >= 0 from the signed approach d (mm), and d(delta)/dd.

    ``smoothing`` None: the contact law's own max(d, 0). A float eps (mm):
    the smooth (d + sqrt(d^2 + eps^2))/2, which the solver's continuation
    uses to remove the kink at first contact (every ball carries a little
    load, so Kb is never singular); eps -> 0 recovers max(d, 0).
    """


@overload(clamped_deflection, fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _clamped_deflection(d, smoothing):
    if isinstance(smoothing, types.NoneType):
        def exact(d, smoothing):
            return max(d, 0.0), 1.0
        return exact

    def smooth(d, smoothing):
        return smoothed_deflection(d, smoothing)
    return smooth


@overload(contact_law, fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _contact_law(delta, kn, exponent, n):
    # chosen while typing, from the exponent's type: no branch in the ball loop
    if isinstance(exponent, types.NoneType):
        def hertz(delta, kn, exponent, n):
            root = math.sqrt(delta)  # n = 1.5: sqrt instead of pow
            return kn * delta * root, 1.5 * kn * root
        return hertz

    def power_law(delta, kn, exponent, n):
        return kn * delta ** n, n * kn * delta ** (n - 1.0)
    return power_law


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _add_contact(acc, c, s, z, R, fr, fz, h11, h12, h22):
    """One contact's share of f and Kb added to the running sums ``acc`` (f0..f4, then the 14 independent
    Kb entries), shared by balls and roller slices. The contact at azimuth (c, s) = (cos psi, sin psi),
    axial position z and radius R pushes fr radially and fz axially and has the 2x2 (radial, axial)
    stiffness H = [[h11, h12], [h12, h22]]: f += J^T (fr, fz) and Kb += J^T H J with the rows
    a = (c, s, 0, -z s, z c) and b = (0, 0, 1, R s, -R c) of J (k14 = -k03 by symmetry).
    Inlined: the sums stay scalars in registers, which LLVM vectorises across contacts."""
    (f0, f1, f2, f3, f4, k00, k01, k02, k03, k04, k11, k12, k13, k22, k23, k24, k33, k34, k44) = acc
    m = R * fz - z * fr
    p = R * h12 - z * h11
    r = R * h22 - z * h12
    t = R * r - z * p
    cc = c * c
    ss = s * s
    cs = c * s
    return (f0 + fr * c, f1 + fr * s, f2 + fz, f3 + m * s, f4 - m * c,
            k00 + h11 * cc, k01 + h11 * cs, k02 + h12 * c, k03 + cs * p, k04 - cc * p,
            k11 + h11 * ss, k12 + h12 * s, k13 + ss * p,
            k22 + h22, k23 + s * r, k24 - c * r,
            k33 + ss * t, k34 - cs * t, k44 + cc * t)


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _add_load(acc, c, s, z, R, fr, fz):
    """:func:`_add_contact` without the stiffness (K is None: secant solvers, line-search trials)."""
    (f0, f1, f2, f3, f4, k00, k01, k02, k03, k04, k11, k12, k13, k22, k23, k24, k33, k34, k44) = acc
    m = R * fz - z * fr
    return (f0 + fr * c, f1 + fr * s, f2 + fz, f3 + m * s, f4 - m * c,
            k00, k01, k02, k03, k04, k11, k12, k13, k22, k23, k24, k33, k34, k44)


@njit(cache=CACHE, error_model=ERROR_MODEL, _nrt=REFCOUNT)
def _store(acc, f, K, add):
    """Write (or, with ``add``, add) the sums of :func:`_add_contact` into f and, unless None, Kb.

    Not inlined by numba (LLVM inlines it): numba-level inlining re-types the body at every call site,
    which cost seconds of compilation per kernel variant; and the 25 entries are written out (a helper
    called with literal (i, j) pairs was compiled once for each pair)."""
    (f0, f1, f2, f3, f4, k00, k01, k02, k03, k04, k11, k12, k13, k22, k23, k24, k33, k34, k44) = acc
    for i, v in enumerate((f0, f1, f2, f3, f4)):
        f[i] = f[i] + v if add else v
    if K is not None:
        if add:  # both entries: Kb at speed need not be symmetric
            K[0, 0] += k00; K[0, 1] += k01; K[0, 2] += k02; K[0, 3] += k03; K[0, 4] += k04
            K[1, 0] += k01; K[1, 1] += k11; K[1, 2] += k12; K[1, 3] += k13; K[1, 4] += -k03
            K[2, 0] += k02; K[2, 1] += k12; K[2, 2] += k22; K[2, 3] += k23; K[2, 4] += k24
            K[3, 0] += k03; K[3, 1] += k13; K[3, 2] += k23; K[3, 3] += k33; K[3, 4] += k34
            K[4, 0] += k04; K[4, 1] += -k03; K[4, 2] += k24; K[4, 3] += k34; K[4, 4] += k44
        else:
            K[0, 0] = k00; K[0, 1] = k01; K[0, 2] = k02; K[0, 3] = k03; K[0, 4] = k04
            K[1, 0] = k01; K[1, 1] = k11; K[1, 2] = k12; K[1, 3] = k13; K[1, 4] = -k03
            K[2, 0] = k02; K[2, 1] = k12; K[2, 2] = k22; K[2, 3] = k23; K[2, 4] = k24
            K[3, 0] = k03; K[3, 1] = k13; K[3, 2] = k23; K[3, 3] = k33; K[3, 4] = k34
            K[4, 0] = k04; K[4, 1] = -k03; K[4, 2] = k24; K[4, 3] = k34; K[4, 4] = k44


@njit(cache=CACHE, fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def ball_loop(q, balls, f, K, ball_load, contact_angle):
    """Fill f (5) and, unless ``K`` is None, Kb (5x5) in place at displacement q.

    Per ball (docs/model.md, "Per ball (row r, ball j at azimuth psi)"):
    radial and axial approach of the groove centres, the loaded distance
    A = sqrt(ur^2 + uz^2), Hertz deflection delta = A - A0 (evaluated as
    (A^2 - A0^2)/(A + A0), free of cancellation), ball load Q = Kn*delta^n.
    The ball adds Q*(ur*a + uz*b)/A to f and J^T H J to Kb, with
    J = [a; b] = d(ur, uz)/dq and the 2x2 contact Hessian
    H = (Q/A)(I - h h^T) + Q' h h^T, h = (ur, uz)/A, Q' = dQ/d(delta).
    This compact form equals the paper's Eq. (15a-o) without dividing by ur
    (docs/model.md, "Stiffness matrix Kb = df/dq (paper Eq. 14-15)").

    Parameters
    ----------
    q : (5,) float64
        (dx, dy, dz, bx, by) in mm and rad at the bearing centre.
    balls : schema.ElementSet (balls, exponents, smoothing, slices, speed_table, omega, warm)
        ``balls`` (schema.N_BALL_COLUMNS, n_balls) float64, column-major per-ball data from
        :meth:`fastbearing.Bearing.ball_set`; ``exponents`` None (all balls
        n = 1.5) or (n_balls,) float64 per-ball exponents (which picks the
        power law; the loop reads each column's n from the table); ``smoothing``
        eps in mm, 0.0 for the exact contact law (a number whatever its value,
        so the callers compile once; see :func:`clamped_deflection` and
        :func:`_ball_block`); ``slices`` (14, n_slices) the roller
        slices (rollers.slice_table; None for a ball bearing), added
        by :func:`slice_loop`; ``speed_table`` None (the quasi-static model) or
        the per-ball constants of the high-speed model (bearing.speed_table)
        with the shaft speed ``omega`` in rad/s (at 0 the quasi-static loop runs)
        and ``warm`` (high_speed.warm_size(n_balls) cells) the balls' warm
        starts and the loop's scratch (None without a speed table).
    f : (5,) float64, out
        (Fx, Fy, Fz, Mx, My) on the inner ring in N and N*mm.
    K : (5, 5) float64 or None, out
        Kb = df/dq; None skips it (secant solvers need only f).
    ball_load, contact_angle : (n_elements,) float64 or None, out
        Q_j in N and the loaded contact angle alpha_j in rad, signed so that
        it is positive on the row's own contact direction, of every ball and
        then every roller (its total load); None skips them.

    Returns
    -------
    total_load : float
        Sum of ball loads in N (0 when no ball is loaded).
    n_loaded : int
        Number of loaded balls.
    warnings : int
        Status warning bits (status.py): CONTACT_REVERSED when a loaded
        ball's contact angle has the opposite sign to its row's contact
        direction, BEYOND_VALIDITY when a ball's deflection exceeds its
        row's deflection limit (table row DEFLECTION_LIMIT); at speed the
        kernel flags BALL_UNSETTLED and, inside a solve (the warm starts'
        WARM_LINEARISE set by solver.solve_case), BALL_LINEARISED (f and Kb
        first-order close: see :func:`settled_loop`).
    """
    table, exponent, smoothing, slices, speed_table, omega, warm, four_point = balls
    total, n_loaded, warnings = ball_rows(q, table, exponent, smoothing, speed_table, omega, warm, four_point, f, K,
                                          ball_load, contact_angle)
    t, n = roller_rows(q, slices, smoothing, f, K, ball_load, contact_angle)
    return total + t, n_loaded + n, warnings


def roller_rows(q, slices, smoothing, f, K, ball_load, contact_angle):
    """The roller rows' f and Kb added to the balls' (:func:`slice_loop`); (total slice load N, loaded
    slices). Chosen while typing: ``slices`` None (a ball bearing) compiles no roller code at all."""


@overload(roller_rows, fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _roller_rows(q, slices, smoothing, f, K, ball_load, contact_angle):
    if isinstance(slices, types.NoneType):
        return lambda q, slices, smoothing, f, K, ball_load, contact_angle: (0.0, 0)

    def rollers(q, slices, smoothing, f, K, ball_load, contact_angle):
        if slices.shape[1] == 0:
            return 0.0, 0
        eps = smoothing_eps(smoothing)
        if eps > 0.0:  # the solver's fallback; the exact law compiles without the smoothing's arithmetic
            return slice_loop(q, slices, eps, f, K, ball_load, contact_angle)
        return slice_loop(q, slices, None, f, K, ball_load, contact_angle)
    return rollers


def slice_reach(slices, reach, zmax):
    """(reach, zmax) widened by the roller slices: each slice's row deflection scale (mm) and its axial
    place (centre and position along the roller, mm); unchanged for None (no roller rows)."""


@overload(slice_reach)
def _slice_reach(slices, reach, zmax):
    if isinstance(slices, types.NoneType):
        return lambda slices, reach, zmax: (reach, zmax)

    def widen(slices, reach, zmax):
        for k in range(slices.shape[1]):
            reach = max(reach, slices[S_SCALE, k])
            zmax = max(zmax, abs(slices[S_AXIAL, k]) + abs(slices[S_POSITION, k]))
        return reach, zmax
    return widen


def slice_count(slices):
    """The number of roller slices of a ball set's slice table (0 for None: no roller rows)."""


@overload(slice_count)
def _slice_count(slices):
    if isinstance(slices, types.NoneType):
        return lambda slices: 0
    return lambda slices: slices.shape[1]


def ball_rows(q, table, exponent, smoothing, speed_table, omega, warm, four_point, f, K, ball_load, contact_angle):
    """The ball rows' f and Kb (written, not added) and (total load, loaded balls, warning bits): the
    quasi-static loop, or with a ``speed_table`` and omega (rad/s) > 0 the high-speed balls
    (high_speed.spinning_balls). Chosen while typing: ``speed_table`` None compiles the quasi-static
    loop alone."""


@overload(ball_rows, fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _ball_rows(q, table, exponent, smoothing, speed_table, omega, warm, four_point, f, K, ball_load, contact_angle):
    if isinstance(speed_table, types.NoneType):
        def quasi_static(q, table, exponent, smoothing, speed_table, omega, warm, four_point, f, K, ball_load,
                         contact_angle):
            return quasi_static_balls(q, table, exponent, smoothing, f, K, ball_load, contact_angle)
        return quasi_static

    def at_speed(q, table, exponent, smoothing, speed_table, omega, warm, four_point, f, K, ball_load, contact_angle):
        if omega == 0.0 or standing_still(speed_table, omega):  # the quasi-static balls exactly (below
            # high_speed.STILL_DEFLECTION the centrifugal force is far below the solver's resolution)
            out = quasi_static_balls(q, table, exponent, smoothing, f, K, ball_load, contact_angle)
            _outer_record_at_rest(table.shape[1], ball_load, contact_angle)
            return out
        total, n_loaded, flags = balls_at_speed(q, table, speed_table, omega, smoothing_eps(smoothing), f, K,
                                                ball_load, contact_angle, None, warm, four_point)
        warnings = ((CONTACT_REVERSED if flags & 1 else 0) | (BEYOND_VALIDITY if flags & 2 else 0)
                    | (BALL_UNSETTLED if flags & 4 else 0) | (BALL_LINEARISED if flags & 8 else 0))
        return total, n_loaded, warnings
    return at_speed


@njit(cache=CACHE, fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def balls_at_speed(q, table, speed_table, omega, eps, f, K, ball_load, contact_angle, states, warm, four_point):
    """Every ball row at shaft speed omega (rad/s): the angular contact balls (high_speed.spinning_balls, which
    writes f and Kb), then, with ``four_point`` (schema.ElementSet), the four-point balls
    (four_point.four_point_balls, which add theirs); the arguments and the returns as spinning_balls'."""
    total, n_loaded, flags = spinning_balls(q, table, speed_table, omega, eps, f, K, ball_load, contact_angle,
                                            states, warm)
    t, n, more = four_point_share(q, table, speed_table, omega, eps, f, K, ball_load, contact_angle, states, warm,
                                  four_point)
    return total + t, n_loaded + n, flags | more


@njit(cache=CACHE, fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def balls_stand_still(speed_table, omega):
    """high_speed.standing_still for callers in Python (analysis.contacts): whether at the shaft speed
    ``omega`` (rad/s) the balls count as standing still, exactly as the kernel takes it. That function is
    inlined into the kernels and so not cached; called from Python it compiled again in every process."""
    return standing_still(speed_table, omega)


def four_point_share(q, table, speed_table, omega, eps, f, K, ball_load, contact_angle, states, warm, four_point):
    """The four-point balls' share added at speed (four_point.four_point_balls): (load N, loaded pairs, bits).
    Chosen while typing: ``four_point`` None compiles no four-point code."""


@overload(four_point_share)
def _four_point_share(q, table, speed_table, omega, eps, f, K, ball_load, contact_angle, states, warm, four_point):
    if isinstance(four_point, types.NoneType):
        return lambda q, table, speed_table, omega, eps, f, K, ball_load, contact_angle, states, warm, four_point: \
            (0.0, 0, 0)

    def add(q, table, speed_table, omega, eps, f, K, ball_load, contact_angle, states, warm, four_point):
        return four_point_balls(q, table, speed_table, omega, eps, f, K, ball_load, contact_angle, states, warm,
                                four_point)
    return add


@njit(inline="always")
def with_omega(balls, omega):
    """The element set at shaft speed ``omega`` (rad/s; 0: the balls standing still), all else kept."""
    return ElementSet(balls.balls, balls.exponents, balls.smoothing, balls.slices, balls.speed_table, omega,
                      balls.warm, balls.four_point)


@njit(inline="always")
def with_smoothing(balls, eps):
    """The element set with the solver's smoothing ``eps`` (mm; 0.0: the exact contact law)."""
    return ElementSet(balls.balls, balls.exponents, eps, balls.slices, balls.speed_table, balls.omega, balls.warm,
                      balls.four_point)


@njit(inline="always")
def at_position(balls, table, slices, omega, warm, speed_table):
    """The element set at one cage position: its ball and slice tables, shaft speed (rad/s), warm starts and
    high-speed table (the bearing's, or one with a position's local defects)."""
    return ElementSet(table, balls.exponents, balls.smoothing, slices, speed_table, omega, warm,
                      balls.four_point)


def _outer_record_at_rest(n, ball_load, contact_angle):
    """In a record with room for the outer contacts (2 n entries: a life map at speed reads them), the balls
    standing still put each outer contact's load and angle beside the inner one's, which they equal."""


@overload(_outer_record_at_rest)
def _outer_record_at_rest_impl(n, ball_load, contact_angle):
    if isinstance(ball_load, types.NoneType):
        return lambda n, ball_load, contact_angle: None

    def copy(n, ball_load, contact_angle):
        if ball_load.shape[0] >= 2 * n:
            for j in range(n):
                ball_load[n + j] = ball_load[j]
                contact_angle[n + j] = contact_angle[j]
    return copy


def smoothing_eps(smoothing):
    """The smoothing eps in mm as a float (0.0 for None: the exact contact law)."""


@overload(smoothing_eps)
def _smoothing_eps(smoothing):
    if isinstance(smoothing, types.NoneType):
        return lambda smoothing: 0.0
    return lambda smoothing: smoothing


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def quasi_static_balls(q, table, exponent, smoothing, f, K, ball_load, contact_angle):
    """The quasi-static ball loop (docs/model.md, "Per ball (row r, ball j at azimuth psi)"): writes f
    and Kb, returns (total load N, loaded balls, warning bits).

    Under a planar displacement (dy = bx = 0, the loads Fx, Fz, My alone) a ball set that is its own mirror
    image across the xz-plane loads a ball and its mirror image alike: the loop then sums the table's mirror
    half (bearing.MIRROR_HALF: each pair once with its load doubled) and the terms odd in y (Fy, Mx and the
    Kb entries coupling y, tx to x, z, ty) are exactly zero, as the symmetry makes them. 16 of the
    example's 28 balls, for the same answer to rounding."""
    n_half = int(table[HALF_COUNT, 0]) if table.shape[1] > 0 else 0
    eps = smoothing_eps(smoothing)
    half = n_half > 0 and q[1] == 0.0 and q[3] == 0.0
    # one call with the block's row and count as run-time numbers: ball_sums compiles once for either block
    base = MIRROR_HALF if half else 0
    n = n_half if half else table.shape[1]
    acc, total, n_loaded, warnings = _ball_block(q, table, base, n, exponent, eps, K, ball_load, contact_angle)
    if half:
        (f0, f1, f2, f3, f4, k00, k01, k02, k03, k04, k11, k12, k13, k22, k23, k24, k33, k34, k44) = acc
        acc = (f0, 0.0, f2, 0.0, f4, k00, 0.0, k02, 0.0, k04, k11, 0.0, k13, k22, 0.0, k24, k33, 0.0, k44)
        if ball_load is not None:
            spread_mirror_record(table, n_half, ball_load, contact_angle)
    _store(acc, f, K, False)
    return total, n_loaded, warnings


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _ball_block(q, table, base, n, exponent, eps, K, ball_load, contact_angle):
    """:func:`ball_sums` with the smoothing eps (mm) as a number, chosen at run time: the exact law (eps 0,
    every evaluation but the solver's fallback) runs the loop compiled without the smoothing's arithmetic,
    while the callers compile once for either (the smoothing is not a type that multiplies them)."""
    if eps > 0.0:
        return ball_sums(q, table, base, n, exponent, eps, K, ball_load, contact_angle)
    return ball_sums(q, table, base, n, exponent, None, K, ball_load, contact_angle)


@njit(cache=CACHE, fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def ball_sums(q, table, base, n, exponent, smoothing, K, ball_load, contact_angle):
    """The ball loop over columns 0 .. n-1 of the table's block at row ``base`` (0: every ball; MIRROR_HALF:
    the mirror half, whose columns stand for WEIGHT balls each; ``exponent`` None: every ball Hertzian, else
    the block's EXPONENT row is read): (the sums of f and Kb as
    :func:`_add_contact` keeps them, total load N, loaded balls, warning bits). The record (``ball_load``
    not None) goes to the columns' places, one ball's load each (SHARE of the column's)."""
    cos_psi = table[base + COS_PSI]
    sin_psi = table[base + SIN_PSI]
    offset = table[base + AXIAL_OFFSET]
    radius = table[base + PITCH_RADIUS]
    ur0 = table[base + UR0]
    uz0 = table[base + UZ0]
    a0 = table[base + A0]
    kn = table[base + KN]
    direction = table[base + DIRECTION]
    gap = table[base + GAP2]
    limit = table[base + DEFLECTION_LIMIT]
    weight = table[base + WEIGHT]
    share = table[base + SHARE]
    power = table[base + EXPONENT]
    dx = q[0]
    dy = q[1]
    dz = q[2]
    bx = q[3]
    by = q[4]
    acc = ZERO_SUMS
    total = 0.0
    count = 0.0
    n_reversed = 0
    n_beyond = 0
    for j in range(n):
        c = cos_psi[j]
        s = sin_psi[j]
        z = offset[j]
        R = radius[j]
        dr = (dx + z * by) * c + (dy - z * bx) * s  # radial approach
        dzb = dz + R * (bx * s - by * c)  # axial approach
        ur = dr + ur0[j]
        uz = dzb + uz0[j]
        A = math.sqrt(ur * ur + uz * uz)
        # delta = A - A0 written as (A^2 - A0^2)/(A + A0): no cancellation for
        # light contacts, and exactly 0 at q = 0 without clearance and preload
        gap2 = gap[j] + dr * (2.0 * ur0[j] + dr) + dzb * (2.0 * uz0[j] + dzb)
        A_plus = A + a0[j]
        inv = 1.0 / max(A * A_plus, 1e-300)  # one division gives both 1/A and 1/(A + A0)
        delta, slope = clamped_deflection(gap2 * (A * inv), smoothing)
        Q, dQ = contact_law(delta, kn[j], exponent, power[j])
        dQ *= slope
        loaded = delta > 0.0
        count += weight[j] * loaded
        # a row whose groove centres sit level at rest (a0 = 0, no axial preload: deep groove) has no
        # contact direction to reverse: its balls take either shoulder
        n_reversed += loaded & (direction[j] * uz < 0.0) & (uz0[j] != 0.0)
        # ... and any row's ball loaded with its groove centres crossed over radially (ur against ur0: the
        # ring has passed through the ball, the contact angle beyond 90 deg; e.g. one ball under a load
        # away from it), a geometry |A| - A0 counts as a contact but no ring can have
        n_reversed += loaded & (ur * ur0[j] < 0.0)
        n_beyond += delta > limit[j]
        if ball_load is not None:
            ball_load[j] = Q * share[j]
            contact_angle[j] = atan2(direction[j] * uz, ur)
        total += Q
        inv_a = A_plus * inv
        g = Q * inv_a
        if K is not None:
            # the 2x2 contact Hessian H = (Q/A)(I - h h^T) + Q' h h^T, h = (ur, uz)/A
            hr = ur * inv_a
            hz = uz * inv_a
            dq = dQ - g
            acc = _add_contact(acc, c, s, z, R, g * ur, g * uz, g + dq * hr * hr, dq * hr * hz, g + dq * hz * hz)
        else:
            acc = _add_load(acc, c, s, z, R, g * ur, g * uz)
    warnings = (CONTACT_REVERSED if n_reversed > 0 else 0) | (BEYOND_VALIDITY if n_beyond > 0 else 0)
    return acc, total, int(count), warnings


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def spread_mirror_record(table, n_half, ball_load, contact_angle):
    """Move the record of the mirror half's columns (written at places 0 .. n_half-1) to their balls and
    the balls' mirror images (MIRROR_OF; a ball on the plane is its own). From the last column down: a
    column's ball and image are never below its own place, so nothing unread is overwritten."""
    for k in range(n_half - 1, -1, -1):
        Q = ball_load[k]
        angle = contact_angle[k]
        j = int(table[BALL_OF, k])
        m = int(table[MIRROR_OF, k])
        ball_load[j] = Q
        contact_angle[j] = angle
        ball_load[m] = Q  # a ball on the plane is its own image: the same place again
        contact_angle[m] = angle


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _slice_contact(approach, k, smoothing):
    """A slice's (delta, delta^(1/9), load Q = k delta^(10/9), Q' = dQ/d(approach)) from its approach (mm)."""
    delta, slope = clamped_deflection(approach, smoothing)
    # floored: an unloaded slice's root of 0 would start from a subnormal guess (slow), then zeroed
    root = ninth_root(max(delta, 1e-200)) * (delta > 0.0)
    return delta, root, k * delta * root, (10.0 / 9.0) * k * root * slope


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def _add_roller(acc, c, s, nr, nz, F0, G, T0, T1, T2):
    """One roller's share of f and Kb added to the running sums ``acc`` (as :func:`_add_contact`) from the
    moments of its slices. Slice k at x_k along the roller has the gradient v_k = d(delta_k)/dq =
    (nr c, nr s, nz, m_k s, -m_k c) with the lever m_k = nz R_k - nr z_k, so f += sum Q_k v_k and
    Kb += sum Q'_k v_k v_k^T need only F0 = sum Q_k, G = sum Q_k m_k, T0 = sum Q'_k, T1 = sum Q'_k m_k
    and T2 = sum Q'_k m_k^2."""
    (f0, f1, f2, f3, f4, k00, k01, k02, k03, k04, k11, k12, k13, k22, k23, k24, k33, k34, k44) = acc
    cc = c * c
    ss = s * s
    cs = c * s
    a = T0 * nr * nr
    b = T0 * nr * nz
    d = T1 * nr
    e = T1 * nz
    return (f0 + F0 * nr * c, f1 + F0 * nr * s, f2 + F0 * nz, f3 + G * s, f4 - G * c,
            k00 + a * cc, k01 + a * cs, k02 + b * c, k03 + d * cs, k04 - d * cc,
            k11 + a * ss, k12 + b * s, k13 + d * ss,
            k22 + T0 * nz * nz, k23 + e * s, k24 - e * c,
            k33 + T2 * ss, k34 - T2 * cs, k44 + T2 * cc)


@njit(cache=CACHE, fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def slice_loop(q, slices, smoothing, f, K, element_load, element_angle):
    """Add the roller slices' contacts to f (5) and, unless ``K`` is None, Kb (5x5), in place.

    Per slice (rollers.py): the rigid-ring approach at the slice along the fixed normal n = (nr, nz),
    d = n . (dr_k, dz_k) + offset_k, delta = max(d, 0) (or the solver's smoothed form), load
    Q = k delta^(10/9) with k = K/slices; it adds Q n mapped by J^T to f and Q' J^T n n^T J to Kb
    (a fixed normal has no geometric stiffness). Along a roller the approach is linear in x_k (the ring is
    rigid): d_k = d_c + g x_k + offset_k with d_c the approach at the roller's centre and
    g = by cos(psi) - bx sin(psi) the ring's tilt across it, so the inner loop over a roller's slices is
    one ninth root (roots.py) and five sums (:func:`_add_roller`), not a rigid-ring map per slice.
    ``element_load`` (when not None) receives each roller's total load at its place in the record (the
    slice table's roller column, after the balls), ``element_angle``
    the contact angle (rad); a record longer than that also takes every slice's load, after the rollers.
    Returns (total slice load N, loaded slices).
    """
    cos_psi = slices[S_COS_PSI]
    sin_psi = slices[S_SIN_PSI]
    axial = slices[S_AXIAL]
    radius = slices[S_RADIUS]
    nr = slices[S_NORMAL_R]
    nz = slices[S_NORMAL_Z]
    offset = slices[S_OFFSET]
    stiffness = slices[S_STIFFNESS]
    roller = slices[S_ROLLER]
    angle = slices[S_ANGLE]
    position = slices[S_POSITION]
    count = slices[S_COUNT]
    dx = q[0]
    dy = q[1]
    dz = q[2]
    bx = q[3]
    by = q[4]
    n_slices = slices.shape[1]
    slice_base = int(roller[n_slices - 1]) + 1
    per_slice = element_load is not None and element_load.shape[0] >= slice_base + n_slices
    acc = ZERO_SUMS
    total = 0.0
    n_loaded = 0
    start = 0
    while start < n_slices:
        stop = start + int(count[start])
        c = cos_psi[start]
        s = sin_psi[start]
        z = axial[start]
        R = radius[start]
        a = nr[start]
        b = nz[start]
        k = stiffness[start]
        d_c = a * ((dx + z * by) * c + (dy - z * bx) * s) + b * (dz + R * (bx * s - by * c))
        g = by * c - bx * s
        m_c = b * R - a * z
        F0 = 0.0
        G = 0.0
        T0 = 0.0
        T1 = 0.0
        T2 = 0.0
        loaded = 0
        for i in range(start, stop):  # no stores in here: the loop vectorises
            x = position[i]
            delta, root, Q, dQ = _slice_contact(d_c + g * x + offset[i], k, smoothing)
            m = m_c - x
            F0 += Q
            G += Q * m
            loaded += delta > 0.0
            if K is not None:
                T0 += dQ
                T1 += dQ * m
                T2 += dQ * m * m
        if per_slice:  # solve --balls: every slice's load, again, apart from the fast loop
            for i in range(start, stop):
                element_load[slice_base + i] = _slice_contact(d_c + g * position[i] + offset[i], k, smoothing)[2]
                element_angle[slice_base + i] = angle[i]
        if element_load is not None:
            j = int(roller[start])  # the roller's place in the element record (after the balls)
            element_load[j] = F0
            element_angle[j] = angle[start]
        total += F0
        n_loaded += loaded
        acc = _add_roller(acc, c, s, a, b, F0, G, T0, T1, T2)
        start = stop
    _store(acc, f, K, True)
    return total, n_loaded


#: Evaluations :func:`settled_loop` allows: each takes every linearised ball one Newton step on (the
#: linearisation's error squares), so two nearly always suffice.
SETTLE_PASSES = 6


@njit(cache=CACHE, fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def settled_loop(q, balls, f, K, ball_load, contact_angle):
    """:func:`ball_loop` evaluated until no ball at speed is left linearised (BALL_LINEARISED): the
    model's f and Kb at q for the solver's last word (its record or unloaded evaluation). Outside a
    solve, or without speed, one evaluation. Still linearised after SETTLE_PASSES: BALL_UNSETTLED."""
    total, n_loaded, warnings = ball_loop(q, balls, f, K, ball_load, contact_angle)
    for _ in range(SETTLE_PASSES - 1):
        if not warnings & BALL_LINEARISED:
            return total, n_loaded, warnings
        total, n_loaded, warnings = ball_loop(q, balls, f, K, ball_load, contact_angle)
    if warnings & BALL_LINEARISED:
        warnings = (warnings & ~BALL_LINEARISED) | BALL_UNSETTLED
    return total, n_loaded, warnings
