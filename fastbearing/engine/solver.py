"""Load-given solve f(q) = f_target for one case (njit, returns status codes).

Two phases, one kernel. The fast phase is a damped Newton on the analytic
Kb (or Broyden's secant method) with a backtracking line search on a scaled
residual (moments divided by a length L, tilts multiplied by L, so every
component is in N and mm), from a warm start or a cold start along the load.
It settles almost every case in a few kernel evaluations.

When it fails (no loaded ball, a stall, or no progress), the fallback uses
what makes the problem well posed: f is the gradient of the bearing's
potential energy

    Pi(q) = sum_j Kn delta_j^(n+1) / (n+1) - f_target . q,

which is convex (each delta_j = |u0 + J_j q| - A0 is convex in q) and, with
three or more balls per row, grows without bound in every direction, so it
has a minimum and the load a solution. The fallback minimises Pi with the
kink of max(delta, 0) smoothed away and the smoothing taken to zero level by
level (:func:`_smoothing_continuation`), so it crosses the regions where no
ball is loaded and the narrow valleys of contact reversal where Newton on
the residual stalls.

Convergence means a residual within rtol of the target. A residual is only
as good as the rounding of the ball forces it sums and the resolution of q,
so every test compares it with that rounding floor (:func:`_rounding_floor`);
a case whose floor lies above rtol * |f_target| (tiny loads on a preloaded
bearing, say) ends as ``PRECISION_LIMIT`` once it reaches the floor, never as
``CONVERGED``. Nothing raises: the outcome is a status from
:mod:`fastbearing.status`.
"""

import math
from collections import namedtuple

from numba import njit, types
from numba.extending import overload

from ..config import (CACHE, DIVERGED_REACH, ERROR_MODEL, FASTMATH, NEWTON, RECORD_AHEAD, REFCOUNT,
                     SEARCH_CURVATURE, SEARCH_TRIALS, SMOOTHING_FIRST, SMOOTHING_LAST, SMOOTHING_RATIO, SMOOTHING_RTOL, STAGNATION_ITERATIONS,
                     STILL_START_RTOL)
from .schema import A0, AXIAL_OFFSET, EXPONENT
from .kernel import (SETTLE_PASSES, ball_loop, forget_warm, settled_loop, slice_reach, take_linearised, with_omega,
                     with_smoothing)
from .linalg import ldl_solve, lu_solve, stiffness_solve
from ..status import (BALL_EQUILIBRIUM, BALL_LINEARISED, BALL_UNSETTLED, CONVERGED, ITERATION_LIMIT, NONFINITE_INPUT,
                     NONFINITE_RESULT, PRECISION_LIMIT, SINGULAR, STALLED, UNLOADED, WARNING_MASK)

#: The solver's settings, one record: ``method`` (NEWTON or BROYDEN), ``rtol`` (relative residual),
#: ``max_iter`` (iterations per phase), ``length_scale`` (L in mm: moments are divided by it in the
#: residual) and ``max_step`` (largest fast-phase step in scaled units, mm).
SolverSettings = namedtuple("SolverSettings", "method rtol max_iter length_scale max_step fixed")

#: What one solve reports: ``status`` (:mod:`fastbearing.status`), ``iterations`` (over all phases),
#: ``residual`` (relative, see :func:`solve_case`) and ``evaluations`` (kernel calls).
SolveOutcome = namedtuple("SolveOutcome", "status iterations residual evaluations")

#: Rows of the (WORK_ROWS, 5) scratch array a caller hands to :func:`solve_case`.
WORK_ROWS = 34
_KS, _B, _KT, _LU = 0, 5, 10, 15  # 5x5 blocks: scaled Kb, Broyden matrix, trial Kb, factor
_G, _STEP, _QT, _FT, _GT, _RHS, _D, _PERM, _BEST, _FLOOR = range(20, 30)
_TARGET, _SAVED, _KEPT = 30, 31, 32  # the load continuation's scaled load, its last solution, the fallback's q

#: The load continuation at speed (:func:`_load_continuation`): doublings of the load tried for a first
#: solution, and the ratio of a step back towards the target past which it gives up.
LOAD_DOUBLINGS = 12
LOAD_RATIO_LIMIT = 0.99

_ARMIJO = 1e-4
_HALVINGS = 30
#: Relative rounding of one float64 operation, and the factor that turns it into the floor of a
#: computed residual (calibrated against an 80-bit evaluation: the error never exceeded 0.19 x eps x
#: the floor's sum on 4000 random bearings and displacements).
_EPS = 2.220446049250313e-16
_FLOOR_FACTOR = 1.0


@njit(cache=CACHE, fastmath=FASTMATH, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def _scaled_residual(f, f_target, D, g):
    """g = D (f - f_target); returns (max |g_i|, sum g_i^2); (inf, inf) if not finite."""
    rmax = 0.0
    r2 = 0.0
    for i in range(5):
        g[i] = (f[i] - f_target[i]) * D[i]
        rmax = max(rmax, abs(g[i]))
        r2 += g[i] * g[i]
    if not math.isfinite(r2):
        return math.inf, math.inf
    return rmax, r2


@njit(inline="always")
def _impose(q, f_target, D):
    """The prescribed displacements: q_i = f_target_i at each fixed degree of freedom (D_i = 0: the target
    holds its value, mm or rad, and the residual does not see it; docs/model.md, "Mixed boundary
    conditions: the reduced system")."""
    for i in range(5):
        if D[i] == 0.0:
            q[i] = f_target[i]


@njit(inline="always")
def _scale(K, D, Ks):
    """Ks = D Kb D, the solver's scaled stiffness; a fixed degree of freedom (D_i = 0) gets the largest free
    diagonal on its diagonal, so that its row of every step solve says "no step" (its residual is 0)."""
    big = 0.0
    for i in range(5):
        for j in range(5):
            Ks[i, j] = K[i, j] * D[i] * D[j]
        if D[i] != 0.0:
            big = max(big, abs(Ks[i, i]))
    for i in range(5):
        if D[i] == 0.0:
            for j in range(5):
                Ks[i, j] = 0.0
                Ks[j, i] = 0.0
            Ks[i, i] = big if big > 0.0 else 1.0


@njit(inline="always")
def _scaled_size(q, D):
    """max |q_i / D_i| over the free degrees of freedom (mm)."""
    size = 0.0
    for i in range(5):
        if D[i] != 0.0:
            size = max(size, abs(q[i] / D[i]))
    return size


@njit(cache=CACHE, fastmath=FASTMATH, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def _rounding_floor(total, Ks, q, D, arm, reach):
    """How far a computed scaled residual can be from the true one at q (N).

    Two sources: the sum of ball forces (total = sum Q in N, moment arms up
    to ``arm`` = 1 + |z|max/L) and the deflections, computed from lengths of
    size A0 + |displacement| (``reach`` = the largest A0 in mm), which carry
    Kb (``Ks``, scaled: D Kb D) times that times eps into f. The second is
    also the resolution of q itself: Kb times one ulp of q.
    """
    trace = 0.0
    for i in range(5):
        if D[i] != 0.0:
            trace += abs(Ks[i, i])
    size = _scaled_size(q, D)
    return _FLOOR_FACTOR * _EPS * (total * arm + trace * (reach + size))


@njit(cache=CACHE, fastmath=FASTMATH, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def _cold_start(f_target, q, f, K, balls, D, max_step):
    """A first q along the load direction, sized so the balls carry about the load.

    Starts small (so balls engage; at speed the balls standing still), then
    rescales with the Hertz exponent using the load's projection; never
    q = 0, where Kb = 0 without preload.
    Leaves f and Kb evaluated at the returned q. Returns (evaluations,
    total load, loaded contacts, warning bits) of that evaluation.
    """
    norm2 = 0.0
    for i in range(5):
        norm2 += (f_target[i] * D[i]) ** 2
    if norm2 == 0.0:
        for i in range(5):
            q[i] = 0.0
        _impose(q, f_target, D)
        total, n_loaded, warn = ball_loop(q, balls, f, K, None, None)
        return 1, total, n_loaded, warn
    norm = math.sqrt(norm2)
    size = 0.02 * max_step
    # the first element's exponent sets the rescale (exact for a uniform n): a ball's, else a slice's 10/9
    n_exp = balls.balls[EXPONENT, 0] if balls.balls.shape[1] > 0 else 10.0 / 9.0
    evals = 0
    # the size is a guess: at speed take it from the balls standing still (omega 0: the quasi-static loop,
    # a tenth of the cost, and nothing for the high-speed balls' warm starts to forget)
    still = with_omega(balls, 0.0)
    for attempt in range(40):
        for i in range(5):
            q[i] = size * f_target[i] * D[i] * D[i] / norm
        _impose(q, f_target, D)
        total, n_loaded, warn = ball_loop(q, still, f, None, None, None)
        evals += 1
        if n_loaded > 0:
            break
        size *= 1.5
    # rescale once with the Hertz exponent from the load's projection; this
    # evaluation also gives Kb, so the solver starts from it directly
    proj = 0.0
    for i in range(5):
        proj += f[i] * D[i] * f_target[i] * D[i]
    proj /= norm2
    factor = min(max(proj ** (-1.0 / n_exp), 0.05), 20.0) if proj > 0.0 else 1.0
    for i in range(5):
        q[i] *= factor
    _impose(q, f_target, D)
    total, n_loaded, warn = ball_loop(q, balls, f, K, None, None)
    if n_loaded == 0:
        # shrunk back inside the clearance: keep the guess that loads balls
        for i in range(5):
            q[i] /= factor
        _impose(q, f_target, D)
        total, n_loaded, warn = ball_loop(q, balls, f, K, None, None)
        evals += 1
    return evals + 1, total, n_loaded, warn


@njit(inline="always", fastmath=FASTMATH, error_model=ERROR_MODEL)
def _evaluate(x, balls, fx, Kx, newton, record, ball_load, contact_angle):
    """One evaluation of the fast phase at x into fx (and Kx for Newton; Broyden needs f alone), with the
    per-ball record when ``record``."""
    if record:
        return ball_loop(x, balls, fx, Kx, ball_load, contact_angle)
    if newton:
        return ball_loop(x, balls, fx, Kx, None, None)
    return ball_loop(x, balls, fx, None, None, None)


@njit(cache=CACHE, fastmath=FASTMATH, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def _descend(f_target, q, f, K, total, n_loaded, warn, balls, settings, tol, arm, reach, D, work, ball_load,
             contact_angle):
    """The fast phase: Newton or Broyden from q; f, K, total, n_loaded, warn are the kernel's values at q.

    Stops when the scaled residual is within max(tol, rounding floor). On
    return f holds the values at the returned q and work[_FLOOR, 0] the
    rounding floor there; so does K for Newton, except after STALLED (it may
    then hold a rejected trial's: every later phase evaluates q again). Returns (status, iterations,
    residual max-norm, evaluations, total load, the kernel's warning bits,
    recorded); any status but CONVERGED sends the case to the fallback.
    Newton writes the per-ball record (``ball_load``, ``contact_angle``,
    None: none) on the trials expected to converge (RECORD_AHEAD; at speed
    on every trial), and ``recorded`` says that the returned q's is there:
    the record then costs a fraction of the evaluation it would otherwise
    take after convergence.
    """
    g = work[_G]
    dp = work[_STEP]
    qt = work[_QT]
    ft = work[_FT]
    gt = work[_GT]
    rhs = work[_RHS]
    Ks = work[_KS:_KS + 5]
    B = work[_B:_B + 5]
    Kt = work[_KT:_KT + 5]
    LU = work[_LU:_LU + 5]
    perm = work[_PERM]
    newton = settings.method == NEWTON
    max_step = settings.max_step
    evals = 0
    rmax, r2 = _scaled_residual(f, f_target, D, g)
    best = rmax
    since_best = 0
    lam = 0.0
    fresh_jacobian = True
    if not newton:
        _scale(K, D, B)
    passes = 0
    record_trials = newton and balls.omega != 0.0
    # the residual (squared) from which a quasi-static Newton trial is expected to converge (RECORD_AHEAD)
    record_from = RECORD_AHEAD * tol * tol / settings.rtol if newton and ball_load is not None else -1.0
    recorded = False
    for it in range(settings.max_iter + 1):
        while True:
            if newton:
                _scale(K, D, Ks)
            floor = _rounding_floor(total, Ks if newton else B, q, D, arm, reach)
            work[_FLOOR, 0] = floor
            if not (rmax <= max(tol, floor) and warn & BALL_LINEARISED and passes < SETTLE_PASSES):
                break
            # within tolerance, but on balls at speed linearised: evaluate at q again (each pass squares
            # their error) so that a converged answer is the model's
            passes += 1
            total, n_loaded, warn = _evaluate(q, balls, f, K, newton, record_trials, ball_load, contact_angle)
            recorded = record_trials
            evals += 1
            rmax, r2 = _scaled_residual(f, f_target, D, g)
        if rmax <= max(tol, floor) and not warn & BALL_LINEARISED:
            return CONVERGED, it, rmax, evals, total, warn, recorded
        if it == settings.max_iter or since_best >= STAGNATION_ITERATIONS:
            break
        if n_loaded == 0:
            return SINGULAR, it, rmax, evals, total, warn, False
        for i in range(5):
            rhs[i] = -g[i]
        diag = 0.0
        for i in range(5):
            diag = max(diag, Ks[i, i] if newton else abs(B[i, i]))
        if not diag > 0.0:
            return SINGULAR, it, rmax, evals, total, warn, False
        accepted = False
        lam = lam * 0.1 if lam > 1e-12 else 0.0
        for attempt in range(12):
            if newton:
                ok = stiffness_solve(Ks, lam * diag, rhs, dp, LU, perm)
            else:
                ok = lu_solve(B, rhs, dp, LU, perm, 0.0)
            if not ok:
                if not newton:
                    # singular secant matrix: regularise it once, then retry
                    for i in range(5):
                        B[i, i] += max(lam, 1e-10) * diag
                lam = max(lam * 10.0, 1e-12)
                continue
            # Hertz contacts stiffen as they load, so a Newton step from a light
            # state overshoots: let one step at most double the displacement
            # (scaled, mm), and never exceed max_step
            big = 0.0
            for i in range(5):
                big = max(big, abs(dp[i]))
            size = _scaled_size(q, D)
            cap = min(max_step, max(size, 0.05 * max_step))
            if big > cap:
                for i in range(5):
                    dp[i] *= cap / big
            t = 1.0
            record = record_trials or rmax * rmax <= record_from
            for h in range(_HALVINGS):
                for i in range(5):
                    qt[i] = q[i] + t * dp[i] * D[i]
                # Newton's trial Kb goes straight into K: the step solves use Ks, K at q is not read again
                tot_t, nl_t, nr_t = _evaluate(qt, balls, ft, K, newton, record, ball_load, contact_angle)
                if record:
                    recorded = False  # q's record, if any, is overwritten: it is the trial's until accepted
                evals += 1
                rmax_t, r2_t = _scaled_residual(ft, f_target, D, gt)
                # an unloaded trial point has Kb = 0: no information to go on from
                if nl_t > 0 and r2_t <= (1.0 - _ARMIJO * t) * r2:
                    accepted = True
                    recorded = record
                    break
                t *= 0.5
            if accepted:
                break
            if newton:
                lam = max(lam * 100.0, 1e-8)
            elif not fresh_jacobian:
                # secant matrix went stale: restart it from the analytic Kb at q
                ball_loop(q, balls, ft, Kt, None, None)
                evals += 1
                _scale(Kt, D, B)
                fresh_jacobian = True
            else:
                lam = max(lam * 100.0, 1e-8)
                for i in range(5):
                    B[i, i] += lam * diag
        if not accepted:
            return STALLED, it, rmax, evals, total, warn, False
        if not newton:
            # good Broyden update: B += (y - B s) s^T / (s^T s), y = g_t - g, s = t*dp
            ss = 0.0
            for i in range(5):
                dp[i] *= t
                ss += dp[i] * dp[i]
            if ss > 0.0:
                for i in range(5):
                    bs = 0.0
                    for j in range(5):
                        bs += B[i, j] * dp[j]
                    rhs[i] = (gt[i] - g[i] - bs) / ss
                for i in range(5):
                    for j in range(5):
                        B[i, j] += rhs[i] * dp[j]
            fresh_jacobian = False
        for i in range(5):
            q[i] = qt[i]
            f[i] = ft[i]
            g[i] = gt[i]
        total = tot_t
        n_loaded = nl_t
        warn = nr_t
        rmax = rmax_t
        r2 = r2_t
        if rmax < 0.5 * best:
            best = rmax
            since_best = 0
        else:
            since_best += 1
    return ITERATION_LIMIT, settings.max_iter, rmax, evals, total, warn, False


@njit(cache=CACHE, fastmath=FASTMATH, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def _minimise_energy(f_target, q, f, K, balls, settings, tol, arm, reach, D, work):
    """Minimise Pi(q) = sum_j E(delta_j) - f_target . q from q (f, K evaluated there on entry).

    Newton directions on Kb (Pi's Hessian), bounded by a trust radius: past
    it (or where Kb is singular) the Levenberg step with shift |g|/radius,
    which where no ball is loaded is the gradient step. Along each direction
    a line search on phi'(t) = (f(q + t p) - f_target) . p, which rises
    monotonically through 0 at the line's minimum (Pi is convex): bracket
    it geometrically, refine by regula falsi, keep a point where Pi has
    fallen. ``balls`` may carry a smoothing eps. Returns (status,
    iterations, residual max-norm, evaluations, total, warning bits).
    """
    g = work[_G]
    dp = work[_STEP]
    qt = work[_QT]
    ft = work[_FT]
    gt = work[_GT]
    rhs = work[_RHS]
    Ks = work[_KS:_KS + 5]
    Kt = work[_KT:_KT + 5]
    keep = work[_BEST]
    evals = 1
    total, n_loaded, warn = ball_loop(q, balls, f, K, None, None)
    rmax, r2 = _scaled_residual(f, f_target, D, g)
    radius = max(2.0 * _scaled_size(q, D), 0.05 * settings.max_step)
    passes = 0
    for it in range(settings.max_iter + 1):
        while True:
            _scale(K, D, Ks)
            floor = _rounding_floor(total, Ks, q, D, arm, reach)
            work[_FLOOR, 0] = floor
            if not (rmax <= max(tol, floor) and warn & BALL_LINEARISED and passes < SETTLE_PASSES):
                break
            passes += 1  # balls at speed linearised: evaluate at q again (as in _descend)
            total, n_loaded, warn = ball_loop(q, balls, f, K, None, None)
            evals += 1
            rmax, r2 = _scaled_residual(f, f_target, D, g)
        if rmax <= max(tol, floor) and not warn & BALL_LINEARISED:
            return CONVERGED, it, rmax, evals, total, warn
        gnorm = 0.0
        for i in range(5):
            rhs[i] = -g[i]
            gnorm += g[i] * g[i]
        gnorm = math.sqrt(gnorm)
        if it == settings.max_iter:
            break
        ok = ldl_solve(Ks, 0.0, rhs, dp)
        if ok:
            size = 0.0
            for i in range(5):
                size += dp[i] * dp[i]
            ok = math.sqrt(size) <= radius
        if not ok:
            # (Kb + lam I) >= lam I bounds this step by the radius
            ldl_solve(Ks, gnorm / radius, rhs, dp)
        dphi0 = 0.0
        for i in range(5):
            dphi0 += g[i] * dp[i]
        if not dphi0 < 0.0:
            return STALLED, it, rmax, evals, total, warn
        t = 1.0
        t_lo = 0.0
        d_lo = dphi0
        t_hi = -1.0
        d_hi = 0.0
        refinements = 0
        accepted = False
        for h in range(SEARCH_TRIALS):
            for i in range(5):
                qt[i] = q[i] + t * dp[i] * D[i]
            tot_t, nl_t, nr_t = ball_loop(qt, balls, ft, Kt, None, None)
            evals += 1
            rmax_t, r2_t = _scaled_residual(ft, f_target, D, gt)
            dphi = 0.0
            for i in range(5):
                dphi += gt[i] * dp[i]
            if not math.isfinite(dphi):
                dphi = math.inf
            if (rmax_t <= tol or abs(dphi) <= 1e-3 * abs(dphi0)
                    or (dphi <= 0.0 and dphi >= SEARCH_CURVATURE * dphi0)):
                accepted = True
                break
            if dphi < 0.0:
                t_lo = t
                d_lo = dphi
                for i in range(5):
                    keep[i] = qt[i]
            else:
                t_hi = t
                d_hi = dphi
            if t_hi < 0.0:
                t *= 4.0
            elif t_lo == 0.0 and (d_hi > -16.0 * dphi0 or not math.isfinite(d_hi)):
                t *= 0.25
            elif refinements < 2:
                refinements += 1
                t = t_lo - d_lo * (t_hi - t_lo) / (d_hi - d_lo)
            else:
                break
        if not accepted:
            if t_lo == 0.0:
                return STALLED, it, rmax, evals, total, warn
            if t_hi < 0.0:
                # Pi kept falling along the line as far as it was followed: the load has a
                # direction no ball holds (a row of fewer than three balls)
                return SINGULAR, it, rmax, evals, total, warn
            t = t_lo
            for i in range(5):
                qt[i] = keep[i]
            tot_t, nl_t, nr_t = ball_loop(qt, balls, ft, Kt, None, None)
            evals += 1
            rmax_t, r2_t = _scaled_residual(ft, f_target, D, gt)
        step = 0.0
        for i in range(5):
            step += (t * dp[i]) ** 2
        step = math.sqrt(step)
        size = _scaled_size(q, D)
        if not step > _EPS * size:
            return STALLED, it, rmax, evals, total, warn
        radius = max(2.0 * step, 0.05 * settings.max_step)
        for i in range(5):
            q[i] = qt[i]
            f[i] = ft[i]
            g[i] = gt[i]
            for j in range(5):
                K[i, j] = Kt[i, j]
        total = tot_t
        warn = nr_t
        rmax = rmax_t
    return ITERATION_LIMIT, settings.max_iter, rmax, evals, total, warn


@njit(cache=CACHE, fastmath=FASTMATH, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def _smoothing_continuation(f_target, q, f, K, balls, settings, tol, arm, reach, D, work):
    """The fallback: :func:`_minimise_energy` with the contact law smoothed, eps -> 0.

    With every ball carrying a little load (:func:`fastbearing.engine.kernel.clamped_deflection`)
    the energy is smooth and strictly convex, so Newton goes straight to its
    minimum; each smaller eps starts from the last solution, and the exact
    contact law from the smallest. Returns what :func:`_minimise_energy`
    does, with iterations and evaluations summed over the levels.
    """
    eps = SMOOTHING_FIRST * reach
    iterations = 0
    evals = 0
    while eps > SMOOTHING_LAST * reach:
        level_tol = max(tol, SMOOTHING_RTOL * tol / settings.rtol)
        smoothed = with_smoothing(balls, eps)
        st, it, rmax, ev, total, warn = _minimise_energy(f_target, q, f, K, smoothed, settings, level_tol, arm,
                                                          reach, D, work)
        iterations += it
        evals += ev
        if st == SINGULAR:
            return st, iterations, rmax, evals, total, warn
        eps *= SMOOTHING_RATIO
    st, it, rmax, ev, total, warn = _minimise_energy(f_target, q, f, K, balls, settings, tol, arm, reach, D, work)
    return st, iterations + it, rmax, evals + ev, total, warn


@njit(cache=CACHE, fastmath=FASTMATH, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def _load_continuation(f_target, q, f, K, balls, settings, tol, arm, reach, D, work, ball_load, contact_angle):
    """The last fallback at speed: the load doubled until a cold solve converges, then taken back to the
    target, each step from the last solution (a step that fails is shortened: its ratio square-rooted,
    until LOAD_RATIO_LIMIT). Light loads at 70 000 rpm and above need it (issue 47): the balls ride the
    outer arcs under their centrifugal force, one to three carry the ring, Kb is nearly singular along a
    tilt, and Newton from a cold start stalls where from a heavier load's solution it converges. Fixed
    degrees of freedom keep their displacements. Returns (status, iterations, residual max-norm,
    evaluations, total load, warning bits) as :func:`_descend`."""
    target = work[_TARGET]
    saved = work[_SAVED]
    iterations = 0
    evals = 0
    s = 1.0
    status = STALLED
    rmax = math.inf
    total = 0.0
    warn = 0
    for _ in range(LOAD_DOUBLINGS):
        s *= 2.0
        for i in range(5):
            target[i] = s * f_target[i] if D[i] != 0.0 else f_target[i]
        ev, total, n_loaded, warn = _cold_start(target, q, f, K, balls, D, settings.max_step)
        status, it, rmax, ev2, total, warn, _ = _descend(target, q, f, K, total, n_loaded, warn, balls, settings,
                                                         s * tol, arm, reach, D, work, ball_load, contact_angle)
        iterations += it
        evals += ev + ev2
        if status == CONVERGED:
            break
    if status != CONVERGED:
        return status, iterations, rmax, evals, total, warn
    ratio = 0.5
    while s > 1.0:
        for i in range(5):
            saved[i] = q[i]
        step = max(1.0, s * ratio)
        for i in range(5):
            target[i] = step * f_target[i] if D[i] != 0.0 else f_target[i]
        total, n_loaded, warn = ball_loop(q, balls, f, K, None, None)
        status, it, rmax, ev, total, warn, _ = _descend(target, q, f, K, total, n_loaded, warn, balls, settings,
                                                        step * tol, arm, reach, D, work, ball_load, contact_angle)
        iterations += it
        evals += ev + 1
        if status == CONVERGED:
            s = step
        else:
            for i in range(5):
                q[i] = saved[i]
            ratio = math.sqrt(ratio)
            if ratio > LOAD_RATIO_LIMIT:
                return status, iterations, rmax, evals, total, warn
    return status, iterations, rmax, evals, total, warn


@njit(cache=CACHE, fastmath=FASTMATH, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def _still_start(f_target, q, f, K, balls, settings, tol, arm, reach, D, work, ball_load, contact_angle):
    """q solving the load to ``tol`` with the balls standing still (omega 0: the quasi-static loop).
    Returns (evaluations, iterations, whether q is a start worth taking). The record arrays are only
    passed on (nothing is recorded standing still), so that _descend compiles once per solve_case."""
    still = with_omega(balls, 0.0)
    ev, total, n_loaded, warn = _cold_start(f_target, q, f, K, still, D, settings.max_step)
    status, it, rmax, ev2, total, warn, _ = _descend(f_target, q, f, K, total, n_loaded, warn, still, settings, tol,
                                                     arm, reach, D, work, ball_load, contact_angle)
    return ev + ev2, it, status == CONVERGED


def still_start(f_target, q, f, K, balls, settings, tol, arm, reach, D, work, ball_load, contact_angle):
    """:func:`_still_start` for an element set at speed; for a quasi-static one (no speed table) nothing:
    chosen while typing, so that a quasi-static solve does not compile the standing-still start (the solver
    reaches it only at speed)."""


@overload(still_start)
def _still_start_choice(f_target, q, f, K, balls, settings, tol, arm, reach, D, work, ball_load, contact_angle):
    if isinstance(balls.types[balls.fields.index("speed_table")], types.NoneType):
        return lambda f_target, q, f, K, balls, settings, tol, arm, reach, D, work, ball_load, contact_angle: \
            (0, 0, False)

    def at_speed(f_target, q, f, K, balls, settings, tol, arm, reach, D, work, ball_load, contact_angle):
        return _still_start(f_target, q, f, K, balls, settings, tol, arm, reach, D, work, ball_load, contact_angle)
    return at_speed


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def with_warnings(status, warn):
    """A converged outcome with the kernel's warning bits on top; a ball at speed that did not settle
    (BALL_UNSETTLED) makes it BALL_EQUILIBRIUM: f and Kb there are not the model's."""
    if warn & BALL_UNSETTLED:
        return BALL_EQUILIBRIUM | (warn & WARNING_MASK)
    return status | (warn & WARNING_MASK)


@njit(cache=CACHE, fastmath=FASTMATH, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def _all_finite(q, f, K):
    ok = True
    for i in range(5):
        ok = ok and math.isfinite(q[i]) and math.isfinite(f[i])
        for j in range(5):
            ok = ok and math.isfinite(K[i, j])
    return ok


@njit(cache=CACHE, fastmath=FASTMATH, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def solve_case(f_target, q, f, K, balls, settings, warm, work, ball_load, contact_angle):
    """Find q with f(q) = f_target; fill q (5), f (5) and Kb (5x5) in place.

    Parameters
    ----------
    f_target : (5,) float64
        (Fx, Fy, Fz, Mx, My) in N and N*mm.
    q : (5,) float64, in/out
        Start when ``warm`` is True; the solution (mm, rad) on return.
    f, K : out
        Load at the returned q (N, N*mm) and Kb there (N/mm, N*mm/rad, N/rad).
    balls : tuple
        Ball set of the bearing (:meth:`fastbearing.Bearing.ball_set`).
    settings : SolverSettings
        Method, rtol, max_iter (per phase), length scale L (mm), max_step (mm).
    warm : bool
        Use the incoming q as the first guess (a cold start follows if it fails).
    work : (WORK_ROWS, 5) float64
        Scratch.
    ball_load, contact_angle : (n_balls,) float64 or None, out
        Per-ball load (N) and contact angle (rad) at the returned q, as in
        :func:`fastbearing.engine.kernel.ball_loop`; None skips recording.

    Returns
    -------
    SolveOutcome
        ``status`` (:mod:`fastbearing.status`), ``iterations`` over all
        phases, ``residual`` = max_i |D_i (f_i(q) - f_target_i)| / max_i
        |D_i f_target_i| with D = (1, 1, 1, 1/L, 1/L) (for f_target = 0:
        over the sum of ball loads), ``evaluations`` of the kernel.

    Balls at speed are linearised while it runs (high_speed.LINEAR_RTOL); the answer is the model's.
    """
    D = work[_D]
    D[0] = D[1] = D[2] = 1.0
    D[3] = D[4] = 1.0 / settings.length_scale
    for i in range(5):
        if (settings.fixed >> i) & 1:
            D[i] = 0.0  # a fixed degree of freedom: f_target holds its displacement, the residual skips it
    finite = True
    for i in range(5):
        finite = finite and math.isfinite(f_target[i]) and (not warm or math.isfinite(q[i]))
    if not finite:
        if ball_load is not None:
            for j in range(ball_load.shape[0]):
                ball_load[j] = math.nan
                contact_angle[j] = math.nan
        for i in range(5):
            q[i] = math.nan
            f[i] = math.nan
            for j in range(5):
                K[i, j] = math.nan
        return SolveOutcome(NONFINITE_INPUT, 0, math.nan, 0)
    # geometry of the rounding floor: moment arms and the largest groove-centre distance
    table = balls.balls
    reach = 0.0
    zmax = 0.0
    for j in range(table.shape[1]):
        reach = max(reach, table[A0, j])
        zmax = max(zmax, abs(table[AXIAL_OFFSET, j]))
    reach, zmax = slice_reach(balls.slices, reach, zmax)
    arm = 1.0 + zmax / settings.length_scale
    scale = 0.0
    for i in range(5):
        scale = max(scale, abs(f_target[i] * D[i]))
    tol = settings.rtol * scale

    iterations = 0
    evals = 0
    status = STALLED
    recorded = False
    spin = balls.warm
    take_linearised(spin, True)  # cleared again on every return below
    if not warm and balls.omega != 0.0 and scale > 0.0:
        # spinning and no start given: start from the balls standing still, roughly solved (a continuation
        # in speed from 0); the spinning solve's own cold start stays the second attempt
        ev, it, warm = still_start(f_target, q, f, K, balls, settings, max(tol, STILL_START_RTOL * scale), arm,
                                    reach, D, work, ball_load, contact_angle)
        evals += ev
        iterations += it
    for attempt in range(2):
        if warm and attempt == 0:
            _impose(q, f_target, D)
            total, n_loaded, warn = ball_loop(q, balls, f, K, None, None)
            ev = 1
        elif attempt == 1 and not warm:
            break
        else:
            ev, total, n_loaded, warn = _cold_start(f_target, q, f, K, balls, D, settings.max_step)
        evals += ev
        if scale == 0.0 and total == 0.0:
            # no load and no ball loaded at rest (no preload): q = 0, f = 0, Kb = 0 exactly
            for i in range(5):
                q[i] = 0.0
            _impose(q, f_target, D)
            settled_loop(q, balls, f, K, ball_load, contact_angle)
            take_linearised(spin, False)
            return SolveOutcome(UNLOADED, 0, 0.0, evals + 1)
        status, it, rmax, ev, total, warn, recorded = _descend(f_target, q, f, K, total, n_loaded, warn, balls,
                                                                settings, tol, arm, reach, D, work, ball_load,
                                                                contact_angle)
        iterations += it
        evals += ev
        if status == CONVERGED:
            break
    if status != CONVERGED and balls.omega != 0.0 and scale > 0.0:
        # spinning: from the balls standing still, solved to the tolerance (the rough start above can leave a
        # light load far off along a soft direction): at low speeds the answer is next to it
        forget_warm(spin)  # the failed attempts' ball centres are no start
        ev, it, still = still_start(f_target, q, f, K, balls, settings, tol, arm, reach, D, work, ball_load,
                                     contact_angle)
        evals += ev
        iterations += it
        if still and _all_finite(q, f, K):
            total, n_loaded, warn = ball_loop(q, balls, f, K, None, None)
            status, it, rmax, ev, total, warn, recorded = _descend(f_target, q, f, K, total, n_loaded, warn, balls,
                                                                    settings, tol, arm, reach, D, work, ball_load,
                                                                    contact_angle)
            iterations += it
            evals += ev + 1
    if status != CONVERGED:
        status, it, rmax, ev, total, warn = _smoothing_continuation(f_target, q, f, K, balls, settings, tol, arm,
                                                                     reach, D, work)
        iterations += it
        evals += ev
    if status != CONVERGED and balls.omega != 0.0 and scale > 0.0:
        kept = work[_KEPT]
        for i in range(5):
            kept[i] = q[i]
        forget_warm(spin)
        st, it, r, ev, t, w = _load_continuation(f_target, q, f, K, balls, settings, tol, arm, reach, D, work,
                                                 ball_load, contact_angle)
        iterations += it
        evals += ev
        if st == CONVERGED:
            status, rmax, total, warn = st, r, t, w
            recorded = False
        else:  # the fallback's answer stands (evaluated again below)
            for i in range(5):
                q[i] = kept[i]
    floor = work[_FLOOR, 0]
    newton_done = settings.method == NEWTON and status == CONVERGED
    if not newton_done or (ball_load is not None and not recorded):
        if newton_done:
            # Newton's last accepted step already left f and Kb at q: the record alone (Kb would cost a third)
            total, n_loaded, warn = settled_loop(q, balls, f, None, ball_load, contact_angle)
        else:
            total, n_loaded, warn = settled_loop(q, balls, f, K, ball_load, contact_angle)
        evals += 1
        rmax, r2 = _scaled_residual(f, f_target, D, work[_G])
    take_linearised(spin, False)
    if not _all_finite(q, f, K):
        return SolveOutcome(NONFINITE_RESULT, iterations, math.nan, evals)
    if status == CONVERGED and floor > tol and scale > 0.0:
        status = PRECISION_LIMIT  # as close as float64 gets, but not within rtol of the target
    if status == PRECISION_LIMIT or status == CONVERGED:
        travel = max(abs(q[0]), abs(q[1]), abs(q[2]), settings.length_scale * max(abs(q[3]), abs(q[4])))
        if travel > DIVERGED_REACH * reach:
            status = SINGULAR  # ran off along a direction the bearing does not hold
    if status == CONVERGED:
        status = with_warnings(status, warn)  # the kernel's warning bits at the solution
    residual = rmax / scale if scale > 0.0 else rmax / max(total, 1e-300)
    return SolveOutcome(status, iterations, residual, evals)
