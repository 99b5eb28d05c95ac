"""Load-given solve f(q) = f_target for one case (njit, returns status codes).

Damped Newton on the analytic Kb with a backtracking line search on a scaled
residual (moments divided by a length L, tilts multiplied by L, so every
component is in N and mm), Levenberg regularisation where Kb is singular, a
Broyden secant mode (the paper's choice) for comparison, a cold start that
never begins at q = 0, and load-stepping continuation as the fallback.
Nothing raises: the outcome is a status from :mod:`fastbearing.status`.
"""

import math

from numba import njit

from .config import CACHE, ERROR_MODEL, FASTMATH
from .kernel import ball_loop
from .linalg import cholesky_solve, lu_solve
from .status import CONTACT_REVERSED, CONVERGED, ITERATION_LIMIT, NONFINITE_INPUT, SINGULAR, STALLED, UNLOADED

NEWTON = 0
BROYDEN = 1

#: Rows of the (WORK_ROWS, 5) scratch array a caller hands to :func:`solve_case`.
WORK_ROWS = 40
_KS, _B, _KT, _LU = 0, 5, 10, 15  # 5x5 blocks: scaled Kb, Broyden matrix, trial Kb, factor
_G, _STEP, _QT, _FT, _GT, _TMP, _D, _Y, _FS, _PERM, _Q0, _FC = range(20, 32)

_ARMIJO = 1e-4
_MAX_HALVINGS = 30


@njit(cache=CACHE, fastmath=FASTMATH, error_model=ERROR_MODEL, nogil=True)
def _scaled_residual(f, f_target, D, g):
    """g = D (f - f_target); returns (max |g_i|, sum g_i^2)."""
    rmax = 0.0
    r2 = 0.0
    for i in range(5):
        g[i] = (f[i] - f_target[i]) * D[i]
        rmax = max(rmax, abs(g[i]))
        r2 += g[i] * g[i]
    if not math.isfinite(r2):
        return math.inf, math.inf
    return rmax, r2


@njit(cache=CACHE, fastmath=FASTMATH, error_model=ERROR_MODEL, nogil=True)
def _tolerance(rtol, scale, total_load):
    # rtol * (load or preload scale), but never below the rounding noise of a
    # sum of ball forces of total size total_load.
    return max(rtol * scale, 1e-13 * total_load)


@njit(cache=CACHE, fastmath=FASTMATH, error_model=ERROR_MODEL, nogil=True)
def _cold_start(f_target, q, f, K, balls, D, max_step, work):
    """A first q along the load direction, sized so the balls carry about the load.

    Starts small (so balls engage), then rescales with the Hertz exponent
    using the load's projection; never q = 0, where Kb = 0 without preload.
    Leaves f and Kb evaluated at the returned q. Returns (evaluations,
    total ball load, loaded balls, reversed balls) of that evaluation.
    """
    norm2 = 0.0
    for i in range(5):
        norm2 += (f_target[i] * D[i]) ** 2
    if norm2 == 0.0:
        for i in range(5):
            q[i] = 0.0
        total, n_loaded, n_rev = ball_loop(q, balls, f, K, None, None)
        return 1, total, n_loaded, n_rev
    norm = math.sqrt(norm2)
    size = 0.02 * max_step
    n_exp = balls[0][8, 0]  # the first ball's exponent sets the rescale (exact for a uniform n)
    evals = 0
    for attempt in range(40):
        for i in range(5):
            q[i] = size * f_target[i] * D[i] * D[i] / norm
        total, n_loaded, n_rev = ball_loop(q, balls, f, None, None, None)
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
    total, n_loaded, n_rev = ball_loop(q, balls, f, K, None, None)
    if n_loaded == 0:
        # shrunk back inside the clearance: keep the guess that loads balls
        for i in range(5):
            q[i] /= factor
        total, n_loaded, n_rev = ball_loop(q, balls, f, K, None, None)
        evals += 1
    return evals + 1, total, n_loaded, n_rev


@njit(cache=CACHE, fastmath=FASTMATH, error_model=ERROR_MODEL, nogil=True)
def _descend(f_target, q, f, K, total, n_loaded, n_rev, balls, method, tol_scale, rtol, max_iter, D, max_step,
             work):
    """Newton or Broyden from q; f, K, total, n_loaded, n_rev are the kernel's values at q.

    On return f (and, for Newton, K) hold the values at the returned q.
    Returns (status, iterations, residual max-norm, evaluations, total ball
    load, reversed balls).
    """
    g = work[_G]
    dp = work[_STEP]
    qt = work[_QT]
    ft = work[_FT]
    gt = work[_GT]
    rhs = work[_TMP]
    Ks = work[_KS:_KS + 5]
    B = work[_B:_B + 5]
    Kt = work[_KT:_KT + 5]
    LU = work[_LU:_LU + 5]
    perm = work[_PERM]
    newton = method == 0
    evals = 0
    rmax, r2 = _scaled_residual(f, f_target, D, g)
    lam = 0.0
    fresh_jacobian = True
    for i in range(5):
        for j in range(5):
            B[i, j] = K[i, j] * D[i] * D[j]
    for it in range(max_iter + 1):
        if rmax <= _tolerance(rtol, tol_scale, total):
            return CONVERGED, it, rmax, evals, total, n_rev
        if it == max_iter:
            break
        if n_loaded == 0:
            return SINGULAR, it, rmax, evals, total, n_rev
        for i in range(5):
            rhs[i] = -g[i]
        if newton:
            for i in range(5):
                for j in range(5):
                    Ks[i, j] = K[i, j] * D[i] * D[j]
        diag = 0.0
        for i in range(5):
            diag = max(diag, Ks[i, i] if newton else abs(B[i, i]))
        if not diag > 0.0:
            return SINGULAR, it, rmax, evals, total, n_rev
        accepted = False
        lam = lam * 0.1 if lam > 1e-12 else 0.0
        for attempt in range(12):
            if newton:
                ok = cholesky_solve(Ks, lam * diag, rhs, dp, LU)
            else:
                ok = lu_solve(B, rhs, dp, LU, perm)
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
            size = 0.0
            for i in range(5):
                big = max(big, abs(dp[i]))
                size = max(size, abs(q[i] / D[i]))
            cap = min(max_step, max(size, 0.05 * max_step))
            if big > cap:
                for i in range(5):
                    dp[i] *= cap / big
            t = 1.0
            for h in range(_MAX_HALVINGS):
                for i in range(5):
                    qt[i] = q[i] + t * dp[i] * D[i]
                if newton:
                    tot_t, nl_t, nr_t = ball_loop(qt, balls, ft, Kt, None, None)
                else:
                    tot_t, nl_t, nr_t = ball_loop(qt, balls, ft, None, None, None)
                evals += 1
                rmax_t, r2_t = _scaled_residual(ft, f_target, D, gt)
                # an unloaded trial point has Kb = 0: no information to go on from
                if nl_t > 0 and r2_t <= (1.0 - _ARMIJO * t) * r2:
                    accepted = True
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
                for i in range(5):
                    for j in range(5):
                        B[i, j] = Kt[i, j] * D[i] * D[j]
                fresh_jacobian = True
            else:
                lam = max(lam * 100.0, 1e-8)
                for i in range(5):
                    B[i, i] += lam * diag
        if not accepted:
            return STALLED, it, rmax, evals, total, n_rev
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
        if newton:
            for i in range(5):
                for j in range(5):
                    K[i, j] = Kt[i, j]
        total = tot_t
        n_loaded = nl_t
        n_rev = nr_t
        rmax = rmax_t
        r2 = r2_t
    return ITERATION_LIMIT, max_iter, rmax, evals, total, n_rev


@njit(cache=CACHE, fastmath=FASTMATH, error_model=ERROR_MODEL, nogil=True)
def solve_case(f_target, q, f, K, balls, method, warm, rtol, max_iter, length_scale, force_floor, max_step, work,
               ball_load, contact_angle):
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
    method : int
        0 Newton, 1 Broyden.
    warm : bool
        Use the incoming q as the first guess (a cold start follows if it fails).
    rtol : float
        Relative residual tolerance.
    max_iter : int
        Iterations per attempt.
    length_scale : float
        L in mm: moments are divided by it, tilts multiplied, in the residual.
    force_floor : float
        Force scale (N) used when f_target is small, e.g. the preload force.
    max_step : float
        Largest step per iteration in scaled units (mm).
    work : (WORK_ROWS, 5) float64
        Scratch.
    ball_load, contact_angle : (n_balls,) float64 or None, out
        Per-ball load (N) and contact angle (rad) at the returned q, as in
        :func:`fastbearing.kernel.ball_loop`; None skips recording.

    Returns
    -------
    status : int
        See :mod:`fastbearing.status`.
    iterations : int
        Total solver iterations over all attempts.
    residual : float
        max |D (f(q) - f_target)| / max(max |D f_target|, force_floor).
    evaluations : int
        Kernel evaluations.
    """
    D = work[_D]
    fc = work[_FC]
    D[0] = D[1] = D[2] = 1.0
    D[3] = D[4] = 1.0 / length_scale
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
        return NONFINITE_INPUT, 0, math.nan, 0
    fnorm = 0.0
    for i in range(5):
        fnorm = max(fnorm, abs(f_target[i] * D[i]))
    scale = max(fnorm, force_floor)
    if scale == 0.0:
        for i in range(5):
            q[i] = 0.0
        ball_loop(q, balls, f, K, ball_load, contact_angle)
        return UNLOADED, 0, 0.0, 1

    iterations = 0
    evals = 0
    status = STALLED
    for attempt in range(2):
        if warm and attempt == 0:
            total, n_loaded, n_rev = ball_loop(q, balls, f, K, None, None)
            ev = 1
        elif attempt == 1 and not warm:
            break
        else:
            ev, total, n_loaded, n_rev = _cold_start(f_target, q, f, K, balls, D, max_step, work)
        evals += ev
        status, it, rmax, ev, total, n_rev = _descend(f_target, q, f, K, total, n_loaded, n_rev, balls, method,
                                                      scale, rtol, max_iter, D, max_step, work)
        iterations += it
        evals += ev
        if status == CONVERGED:
            break
    if status != CONVERGED:
        status, it, rmax, ev, n_rev = _continuation(f_target, q, f, K, balls, method, scale, rtol, max_iter, D,
                                                    max_step, fc, work)
        iterations += it
        evals += ev
    if ball_load is not None or method != 0 or status != CONVERGED:
        # Newton's last accepted step already left f and Kb at q; otherwise evaluate once more
        total, n_loaded, n_rev = ball_loop(q, balls, f, K, ball_load, contact_angle)
        evals += 1
        rmax, r2 = _scaled_residual(f, f_target, D, work[_G])
    if status == CONVERGED and n_rev > 0:
        status |= CONTACT_REVERSED
    return status, iterations, rmax / scale, evals


@njit(cache=CACHE, fastmath=FASTMATH, error_model=ERROR_MODEL, nogil=True)
def _continuation(f_target, q, f, K, balls, method, scale, rtol, max_iter, D, max_step, fc, work):
    """Load stepping: solve for tau*f_target, tau rising to 1, each warm from the last.

    Helps where clearance or preload make the problem far from self-similar.
    Returns (status, iterations, residual, evaluations, reversed balls).
    """
    iterations = 0
    evals = 0
    tau = 0.1
    step = 0.1
    for i in range(5):
        fc[i] = tau * f_target[i]
    ev, total, n_loaded, n_rev = _cold_start(fc, q, f, K, balls, D, max_step, work)
    evals += ev
    status = STALLED
    rmax = math.inf
    for k in range(64):
        for i in range(5):
            fc[i] = tau * f_target[i]
        for i in range(5):
            work[_Q0, i] = q[i]
        status, it, rmax, ev, total, n_rev = _descend(fc, q, f, K, total, n_loaded, n_rev, balls, method, scale,
                                                      rtol, max_iter, D, max_step, work)
        iterations += it
        evals += ev
        if status == CONVERGED:
            if tau >= 1.0:
                return status, iterations, rmax, evals, n_rev
            step = min(step * 2.0, 1.0 - tau)
        else:
            for i in range(5):
                q[i] = work[_Q0, i]
            tau -= step
            step *= 0.25
            if step < 1e-4:
                return status, iterations, rmax, evals, n_rev
        tau = min(tau + step, 1.0)
        # the next load level starts from the last converged q: evaluate there
        total, n_loaded, n_rev = ball_loop(q, balls, f, K, None, None)
        evals += 1
    return status, iterations, rmax, evals, n_rev
