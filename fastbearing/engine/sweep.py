"""Parallel drivers: serial ``nogil`` kernels over blocks of cases, run by a few Python threads (engine/threads.py).

Each block allocates its scratch once and calls the serial kernels case by
case, so a case's result never depends on the thread count or on which
thread ran it.
"""

import math

import numpy as np
from numba import njit, types
from numba.core.cpu import CPUContext
from numba.extending import intrinsic, overload

from ..config import CACHE, ERROR_MODEL, REFCOUNT
from .kernel import at_position, ball_loop, forget_warm, warm_scratch
from .linalg import stiffness_solve
from .roots import cube_root
from .schema import (A0, GAP2, HALF_COUNT, MIRROR_HALF, OP_APPROACH, OP_GAP2, OP_UR0, OP_UZ0, ROW, S_CROWN,
                     S_OFFSET, S_ROW, UR0, UZ0)
from .schema import LIFE_CE, LIFE_CI, LIFE_FIRST, LIFE_INNER, LIFE_SLICES, LIFE_X0, LIFE_Y0, LIFE_Z
from .solver import WORK_ROWS, solve_case, with_warnings
from .contract import Scratch, scratch_shape
from .threads import share
from ..status import BALL_UNSETTLED, CONVERGED, NONFINITE_RESULT, OUTCOME_MASK, UNLOADED


@intrinsic
def _load_flag(typingctx, flag):
    """flag[0] of an int64 array, as an atomic load: the compiler may not hoist it out of a loop,
    so a sweep sees a flag set by another thread (Ctrl-C) at its next read."""
    if not (isinstance(flag, types.Array) and flag.dtype == types.int64 and flag.ndim == 1):
        return None

    def codegen(context, builder, signature, args):
        data = context.make_array(signature.args[0])(context, builder, args[0]).data
        if isinstance(context, CPUContext):
            return builder.load_atomic(data, "monotonic", 8)
        # NVVM (numba-cuda's target, engine/gpu.py) rejects an atomic load, and on the GPU nothing sets the flag
        # during a launch (Ctrl-C is seen between blocks): a plain load, not a write by every thread to one word
        return builder.load(data)

    return types.int64(flag), codegen


@intrinsic
def _claim(typingctx, counter):
    """counter[0] += 1 as one atomic step, returning the old value: the next item (block, group) of the threads
    that share ``counter`` (threads.share), each item taken by exactly one of them. CPU only."""
    if not (isinstance(counter, types.Array) and counter.dtype == types.int64 and counter.ndim == 1):
        return None

    def codegen(context, builder, signature, args):
        data = context.make_array(signature.args[0])(context, builder, args[0]).data
        return builder.atomic_rmw("add", data, context.get_constant(types.int64, 1), "monotonic")

    return types.int64(counter), codegen


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def stop_requested(stop):
    """True once ``stop[0]`` is non-zero (set by the runner's Ctrl-C handler)."""
    return _load_flag(stop) != 0


def at_speed(balls, speeds, i, warm, fresh):
    """The ball set of case i: ``balls`` itself when it has no spin (quasi-static), else with the spin's
    omega replaced by ``speeds[i]`` (rad/s) and the block's warm-start scratch ``warm``
    (:func:`warm_scratch`), emptied first when ``fresh``. Chosen while typing, so the quasi-static sweeps
    are unchanged."""


# inlined: it returns arrays, which a caller without reference counting (map_runs) must not get from a counted call
@overload(at_speed, inline="always")
def _at_speed(balls, speeds, i, warm, fresh):
    if isinstance(balls.types[balls.fields.index("speed_table")], types.NoneType):
        return lambda balls, speeds, i, warm, fresh: balls

    def spinning(balls, speeds, i, warm, fresh):
        # one basic block, the branch in a call: numba-cuda cannot inline an overload whose body branches
        forget_if(warm, fresh)
        return at_position(balls, balls.balls, balls.slices, speeds[i], warm, balls.speed_table)
    return spinning


def with_operating(balls, cases, i, table, slices):
    """The element set of case i with its own operating clearance and preload: ``balls`` itself when
    ``cases.operating`` is None (chosen while typing: no code for it), else ``balls`` with the thread's own
    copies ``table`` and ``slices`` (of balls.balls and balls.slices; slices None without roller rows) holding
    row by row ``cases.operating[i]`` and, with ``cases.ball_sizes``, each ball's own diameter (contract.CaseBlock;
    :func:`set_operating`)."""


@overload(with_operating, inline="always")
def _with_operating(balls, cases, i, table, slices):
    if isinstance(cases.types[cases.fields.index("operating")], types.NoneType):
        return lambda balls, cases, i, table, slices: balls
    if isinstance(cases.types[cases.fields.index("ball_sizes")], types.NoneType):
        def own(balls, cases, i, table, slices):
            set_operating(cases.operating[i], None, balls.balls, table, slices)
            return at_position(balls, table, slices, balls.omega, balls.warm, balls.speed_table)
        return own

    def own_sizes(balls, cases, i, table, slices):
        set_operating(cases.operating[i], cases.ball_sizes[i], balls.balls, table, slices)
        return at_position(balls, table, slices, balls.omega, balls.warm, balls.speed_table)
    return own_sizes


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def set_operating(rows, sizes, base, table, slices):
    """Write one case's operating values ``rows`` (n_rows, schema.N_OPERATING; bearing.Bearing.operating_table)
    into a ball table (its UR0, UZ0, GAP2, the mirror half's too) and a slice table (None without roller rows:
    S_OFFSET = the row's unloaded approach - the slice's crown drop, as rollers.slice_table sets it).
    ``sizes`` None, or each ball's diameter minus the nominal (mm; a table without its mirror half): the groove
    curvature centres are the rings', so a ball bigger by s has A0 - s (the shared table ``base`` holds A0) and
    A^2 - A0^2 at q = 0 grows by s (2 A0 - s), as a defect's depth changes them (model/defects.py)."""
    for j in range(table.shape[1]):
        r = int(table[ROW, j])
        table[UR0, j] = rows[r, OP_UR0]
        table[UZ0, j] = rows[r, OP_UZ0]
        table[GAP2, j] = rows[r, OP_GAP2]
    if sizes is not None:
        for j in range(table.shape[1]):
            s = sizes[j]
            table[A0, j] = base[A0, j] - s
            table[GAP2, j] += s * (2.0 * base[A0, j] - s)
    half = int(table[HALF_COUNT, 0]) if table.shape[1] > 0 else 0
    for c in range(half):
        r = int(table[MIRROR_HALF + ROW, c])
        table[MIRROR_HALF + UR0, c] = rows[r, OP_UR0]
        table[MIRROR_HALF + UZ0, c] = rows[r, OP_UZ0]
        table[MIRROR_HALF + GAP2, c] = rows[r, OP_GAP2]
    if slices is not None:
        for k in range(slices.shape[1]):
            slices[S_OFFSET, k] = rows[int(slices[S_ROW, k]), OP_APPROACH] - slices[S_CROWN, k]


def own_tables(balls, operating):
    """A thread's own copies of the ball and slice tables (slices None without roller rows) for
    :func:`with_operating`, or (None, None) when ``operating`` is None (chosen while typing)."""


@overload(own_tables, inline="always", jit_options={"_nrt": True})
def _own_tables(balls, operating):
    if isinstance(operating, types.NoneType):
        return lambda balls, operating: (None, None)
    if isinstance(balls.types[balls.fields.index("slices")], types.NoneType):
        return lambda balls, operating: (balls.balls.copy(), None)
    return lambda balls, operating: (balls.balls.copy(), balls.slices.copy())


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def forget_if(warm, fresh):
    """:func:`forget_warm` (the balls' warm starts dropped) when ``fresh``, else nothing."""
    if fresh:
        forget_warm(warm)


def solve_sweep(balls, cases, settings, warm, block):
    """Solve every row of ``cases.inputs`` (N, 5; N, N*mm) into ``cases.results`` (a contract.Solutions); its q
    holds warm starts when ``warm``; with a spinning ball set, case i runs at ``cases.speeds[i]`` rad/s
    (:func:`at_speed`), and with ``cases.operating`` at its own clearance and preload (:func:`with_operating`).
    Blocks of ``block`` cases, each with its own scratch, shared among numba's thread count of threads."""
    n = cases.inputs.shape[0]
    share(solve_blocks, (n + block - 1) // block, balls, cases, settings, warm, block)


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True)
def solve_blocks(claimed, balls, cases, settings, warm, block):
    """One thread's part of :func:`solve_sweep`: blocks taken from the counter ``claimed`` (:func:`_claim`)
    until none is left."""
    n = cases.inputs.shape[0]
    n_blocks = (n + block - 1) // block
    b = _claim(claimed)
    while b < n_blocks:
        work = np.empty((WORK_ROWS, 5))
        spin = warm_scratch(balls.speed_table)
        table, slices = own_tables(balls, cases.operating)
        for i in range(b * block, min(n, (b + 1) * block)):
            mine = with_operating(balls, cases, i, table, slices)
            solve_into(cases, i, at_speed(mine, cases.speeds, i, spin, True), settings, warm, work)
        b = _claim(claimed)


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def solve_into(cases, i, balls, settings, warm, work):
    """Case i of a batch solved with the element set ``balls``, written into ``cases.results``
    (contract.Solutions): the CPU's and the GPU's per-case body."""
    out = cases.results
    solved = solve_case(cases.inputs[i], out.q[i], out.f[i], out.K[i], balls, settings, warm, work, None, None)
    out.status[i] = solved.status
    out.iterations[i] = solved.iterations
    out.residual[i] = solved.residual
    out.evaluations[i] = solved.evaluations


def stiffness_sweep(q, f, K, balls, speeds, block, unsettled):
    """f and Kb at every row of q (N, 5) by direct substitution (case i at ``speeds[i]`` rad/s with a
    spinning ball set); ``unsettled[i]`` True where at speed some ball's own equilibrium did not settle
    (f and Kb there are not the model's). Blocks of ``block`` cases shared among threads, as solve_sweep's."""
    share(stiffness_blocks, (q.shape[0] + block - 1) // block, q, f, K, balls, speeds, block, unsettled)


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True)
def stiffness_blocks(claimed, q, f, K, balls, speeds, block, unsettled):
    """One thread's part of :func:`stiffness_sweep`: blocks taken from the counter ``claimed``."""
    n = q.shape[0]
    n_blocks = (n + block - 1) // block
    b = _claim(claimed)
    while b < n_blocks:
        spin = warm_scratch(balls.speed_table)
        for i in range(b * block, min(n, (b + 1) * block)):
            warnings = ball_loop(q[i], at_speed(balls, speeds, i, spin, True), f[i], K[i], None, None)[2]
            unsettled[i] = (warnings & BALL_UNSETTLED) != 0
        b = _claim(claimed)


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def row_summary(ball_load, contact_angle, ball_row, max_load, n_loaded, min_angle, max_angle):
    """Per-row load distribution from one evaluation's per-ball record.

    Largest ball load (N; nan where a ball's load is nan: no valid solution), loaded-ball count, smallest
    and largest contact angle of the loaded balls (rad; nan for a row with no loaded ball). A row's balls
    are summed in registers, with selects, and merged into its entries where the row changes (the rows'
    balls are consecutive in a ball set; any order gives the same answer).
    """
    for r in range(max_load.shape[0]):
        max_load[r] = 0.0
        n_loaded[r] = 0
        min_angle[r] = np.inf
        max_angle[r] = -np.inf
    n = ball_row.shape[0]  # the elements; a longer record's slices follow them
    j = 0
    while j < n:
        r = ball_row[j]
        top = max_load[r]
        count = 0
        low = min_angle[r]
        high = max_angle[r]
        invalid = False
        while j < n and ball_row[j] == r:
            Q = ball_load[j]
            angle = contact_angle[j]
            loaded = Q > 0.0
            top = Q if loaded and Q > top else top
            count += loaded
            low = angle if loaded and angle < low else low
            high = angle if loaded and angle > high else high
            invalid |= Q != Q
            j += 1
        max_load[r] = np.nan if invalid or max_load[r] != max_load[r] else top
        n_loaded[r] += count
        min_angle[r] = low
        max_angle[r] = high
    for r in range(max_load.shape[0]):
        if n_loaded[r] == 0:
            min_angle[r] = np.nan
            max_angle[r] = np.nan



@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def case_life(ball_load, outer_load, ball_row, life, sums, L_row):
    """ISO/TS 16281 L10r (million revolutions) of one case from its ball loads (N); fills ``L_row`` per row.
    ``ball_load`` are the inner contacts' loads and ``outer_load`` the outer contacts' at speed, where the
    centrifugal force loads the outer race more (each ring's mean then comes from its own contacts), or
    None at rest (one load per ball: one loop, one cube per ball).

    With Q_ei, Q_ee the cubic and 10/3 means over a row's Z balls (rotating and stationary ring),
    (Q_c/Q_e)^(-10/3) is Q_c^(-10/3) (S3/Z)^(10/9) for the cubic mean and Q_c^(-10/3) S10/Z for the other
    (S3, S10: sums of Q^3, Q^(10/3)), so a row costs two powers; and since rows combine with exponent
    10/9 = 1/0.9, the bearing's L10r is (sum over rows of the rows' brackets)^(-0.9): one more.
    ``life[r, LIFE_CI]``, ``[LIFE_CE]`` hold Q_ci^(-10/3), Q_ce^(-10/3); ``sums`` (rows, 2) is scratch.
    """
    n_rows = sums.shape[0]
    for r in range(n_rows):
        sums[r, 0] = 0.0
        sums[r, 1] = 0.0
    if outer_load is None:
        for j in range(ball_row.shape[0]):
            Q = ball_load[j]
            if Q > 0.0:
                cube = Q * Q * Q
                sums[ball_row[j], 0] += cube
                sums[ball_row[j], 1] += cube * cube_root(Q)
    else:
        for j in range(ball_row.shape[0]):
            r = ball_row[j]
            # the rotating ring's loads take the cubic mean, the stationary ring's the 10/3 mean
            inner_rotates = life[r, LIFE_INNER] != 0.0
            Qr = ball_load[j] if inner_rotates else outer_load[j]
            Qs = outer_load[j] if inner_rotates else ball_load[j]
            if Qr > 0.0:
                sums[r, 0] += Qr * Qr * Qr
            if Qs > 0.0:
                sums[r, 1] += Qs * Qs * Qs * cube_root(Qs)
    total = 0.0
    for r in range(n_rows):
        cubic = (sums[r, 0] / life[r, LIFE_Z]) ** (10.0 / 9.0)
        ten = sums[r, 1] / life[r, LIFE_Z]
        if life[r, LIFE_INNER] != 0.0:
            bracket = life[r, LIFE_CI] * cubic + life[r, LIFE_CE] * ten
        else:
            bracket = life[r, LIFE_CI] * ten + life[r, LIFE_CE] * cubic
        L_row[r] = bracket ** -0.9 if bracket > 0.0 else np.inf
        total += bracket
    return total ** -0.9 if total > 0.0 else np.inf


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def roller_case_life(record, n_elements, life, L_row):
    """ISO/TS 16281 L10r (million revolutions) of one case of a roller bearing from its slice loads (N, the
    kernel's per-slice record after the ``n_elements`` elements); fills ``L_row`` per row.

    Per lamina k the rotating ring sees the 4th-power mean over the Z rollers and the stationary ring the
    9/2-power mean, so (q_e/q_c)^(9/2) is q_c^(-9/2) (S4/Z)^(9/8) or q_c^(-9/2) S9/Z (S4, S9: sums of
    q^4, q^(9/2) = q^4 sqrt(q)): one power per lamina; a row's L10r is its bracket^(-8/9) and, rows
    combining with the Weibull slope 9/8, the bearing's is (sum of the rows' brackets)^(-8/9).
    ``life[r, LIFE_CI]``, ``[LIFE_CE]`` hold the laminae's q_ci^(-9/2), q_ce^(-9/2).
    """
    total = 0.0
    for r in range(life.shape[0]):
        ns = int(life[r, LIFE_SLICES])
        Z = int(life[r, LIFE_Z])
        first = n_elements + int(life[r, LIFE_FIRST])
        inner = life[r, LIFE_INNER] != 0.0
        bracket = 0.0
        for k in range(ns):
            s4 = 0.0
            s9 = 0.0
            for j in range(Z):
                qk = record[first + j * ns + k]
                if qk > 0.0:
                    q4 = qk * qk * qk * qk
                    s4 += q4
                    s9 += q4 * math.sqrt(qk)
            if s4 > 0.0:
                fourth = (s4 / Z) ** (9.0 / 8.0)
                nine = s9 / Z
                bracket += (life[r, LIFE_CI] * fourth + life[r, LIFE_CE] * nine if inner
                            else life[r, LIFE_CI] * nine + life[r, LIFE_CE] * fourth)
        L_row[r] = bracket ** (-8.0 / 9.0) if bracket > 0.0 else np.inf
        total += bracket
    return total ** (-8.0 / 9.0) if total > 0.0 else np.inf


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def static_safety(load, life, C0):
    """ISO 76 S0 = C0 / max(X0 Fr + Y0 Fa, Fr) under ``load`` (N); inf without load."""
    Fr = math.hypot(load[0], load[1])
    P0 = max(life[0, LIFE_X0] * Fr + life[0, LIFE_Y0] * abs(load[2]), Fr)
    return C0 / P0 if P0 > 0.0 else np.inf


#: Lines of a block are shared among this many scratch groups, a fixed number,
#: so the work a case sees never depends on the thread count.
MAP_GROUPS = 64


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def operating_point(given_load, inputs, warm, q, f, K, balls, settings, scratch):
    """One case of a map or a ball-passage table: solve for q (load given) or substitute q.

    Returns (status, iterations, residual); fills q, f, K and the per-element record (``scratch``'s
    ball_load, contact_angle; the solver works in its ``work``).
    A substitution whose f or Kb is not finite gets NONFINITE_RESULT; a finite one carries the kernel's
    warning bits (contact_reversed, beyond_validity) like a solve.
    """
    if given_load:
        out = solve_case(inputs, q, f, K, balls, settings, warm, scratch.work, scratch.ball_load,
                         scratch.contact_angle)
        return out.status, out.iterations, out.residual
    for d in range(5):
        q[d] = inputs[d]
    warnings = ball_loop(q, balls, f, K, scratch.ball_load, scratch.contact_angle)[2]
    status = substitution_status(f, K)
    return (with_warnings(status, warnings) if status == CONVERGED else status), 0, 0.0


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def substitution_status(f, K):
    """CONVERGED for a finite f and Kb from direct substitution, NONFINITE_RESULT otherwise."""
    for i in range(5):
        if not math.isfinite(f[i]):
            return NONFINITE_RESULT
        for j in range(5):
            if not math.isfinite(K[i, j]):
                return NONFINITE_RESULT
    return CONVERGED


#: Rows of the predictor scratch (PREDICTOR_ROWS, 5) of a map's group: the tangent's right-hand side and
#: step, the 5x5 factor and permutation, and the previous case's tangent step (the earlier slope).
PREDICTOR_ROWS = 14
_RHS, _STEP, _FACTOR, _PERM, _SLOPE, _REDUCED = 0, 1, 2, 7, 8, 9


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def tangent_predictor(given_load, target, q_prev, f_prev, K_prev, q, scratch, fixed):
    """Start for the next case of a line: q_prev + Kb^-1 (f_target - f_prev); True where that step was taken.
    With ``fixed`` degrees of freedom (a bitmask; their target entries hold the displacements, mm or rad) the
    reduced system's: the free steps solve K_ff dq_f = df_f - K_fi dq_i (rows _REDUCED.. hold that K).

    The neighbour's Kb is already computed, so this Euler step along the line
    costs one 5x5 solve and no kernel evaluation; it is second-order accurate
    in the load step. Falls back to q_prev where Kb is singular. ``scratch``
    is (PREDICTOR_ROWS, 5); the step stays in its row 1 (:func:`keep_slope`).
    """
    for d in range(5):
        q[d] = q_prev[d]
    if not given_load:
        return False
    rhs = scratch[_RHS]
    step = scratch[_STEP]
    for d in range(5):
        rhs[d] = target[d] - f_prev[d]
    K_step = K_prev
    if fixed != 0:
        K_step = scratch[_REDUCED:_REDUCED + 5]
        big = 0.0
        for d in range(5):
            for e in range(5):
                K_step[d, e] = K_prev[d, e]
            if not (fixed >> d) & 1:
                big = max(big, abs(K_prev[d, d]))
        for d in range(5):
            if (fixed >> d) & 1:
                dv = target[d] - q_prev[d]
                for e in range(5):
                    if not (fixed >> e) & 1:
                        rhs[e] -= K_prev[e, d] * dv
                    K_step[d, e] = 0.0
                    K_step[e, d] = 0.0
                K_step[d, d] = big if big > 0.0 else 1.0
                rhs[d] = K_step[d, d] * dv
    if not stiffness_solve(K_step, 0.0, rhs, step, scratch[_FACTOR:_PERM], scratch[_PERM]):
        return False
    for d in range(5):
        if not math.isfinite(step[d]):
            return False
    for d in range(5):
        q[d] += step[d]
    return True


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def keep_slope(scratch):
    """Keep the last tangent step (row 1) as the earlier slope (row 8) before the next case's replaces it."""
    for d in range(5):
        scratch[_SLOPE, d] = scratch[_STEP, d]


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def curved_predictor(target, load_prev, load_prev2, q_prev, q_prev2, q, slope_prev2, slope_known):
    """Bend the tangent start q (from :func:`tangent_predictor`) onto a curve through the line's two last
    solutions: the cubic that also has the earlier solution's slope where ``slope_known``, else the
    parabola. Third (cubic) or second (parabola) order in the load step where the tangent is first order.

    Along a grid line the loads are collinear; with s the load step's fraction (s = 1 at ``target``,
    0 at ``load_prev``, -r at ``load_prev2``) the curve is p(s) = q_prev + v s + c2 s^2 + c3 s^3, v = q -
    q_prev the tangent step. With a = q_prev2 - q_prev + v r (p(-r) = q_prev2) and, for the cubic, b =
    w / r - v (p'(-r) = w / r, w = ``slope_prev2``: the tangent step the previous case took from q_prev2,
    Kb(q_prev2)^-1 (load_prev - f(q_prev2))): c2 = (3 a + r b) / r^2, c3 = (2 a + r b) / r^3; the
    parabola has c2 = a / r^2, c3 = 0. q becomes p(1). Warm map cases of the shipped example take 1.35
    Newton iterations (1.47 on the parabola, 2.08 on the tangent). Leaves q alone where the correction is
    not finite or exceeds the tangent step (a contact opened or closed between the points: no curve is
    better there).
    """
    step2 = 0.0
    prev2 = 0.0
    for d in range(5):
        step2 += (target[d] - load_prev[d]) ** 2
        prev2 += (load_prev[d] - load_prev2[d]) ** 2
    if not (step2 > 0.0 and prev2 > 0.0):
        return
    r = math.sqrt(prev2 / step2)
    # c2 + c3 = (3 a + r b) / r^2 + (2 a + r b) / r^3 (cubic) or a / r^2 (parabola): the divisions once
    inv_r = 1.0 / r
    inv_r2 = inv_r * inv_r
    tangent = 0.0
    bend = 0.0
    for d in range(5):
        v = q[d] - q_prev[d]
        tangent = max(tangent, abs(v))
        bend = max(bend, abs(_bend(v, q_prev2[d] - q_prev[d], slope_prev2[d], r, inv_r, inv_r2, slope_known)))
    if not bend <= tangent:
        return
    for d in range(5):
        q[d] += _bend(q[d] - q_prev[d], q_prev2[d] - q_prev[d], slope_prev2[d], r, inv_r, inv_r2, slope_known)


@njit(inline="always", error_model=ERROR_MODEL)
def _bend(v, back, w, r, inv_r, inv_r2, cubic):
    """c2 + c3 of :func:`curved_predictor` for one component: tangent step v, q_prev2 - q_prev ``back``,
    earlier slope w (used when ``cubic``), step ratio r (and 1/r, 1/r^2)."""
    a = back + v * r
    if not cubic:
        return a * inv_r2
    b = w * inv_r - v
    return ((3.0 * a + r * b) + (2.0 * a + r * b) * inv_r) * inv_r2


def map_sweep(elements, cases, given_load, settings, stop):
    """One block of a load or displacement map, in place: ``cases`` (contract.CaseBlock, its results a
    contract.Results) of the bearing's ``elements`` (contract.Elements).

    With a speed table in ``elements.balls``, case i runs at ``cases.speeds[i]`` rad/s (:func:`at_speed`).
    ``cases.inputs`` (N, 5) are loads (N, N*mm) when ``given_load`` else displacements (mm, rad).
    ``cases.segments`` (grid.segment_starts) cuts the block into continuation runs along the fastest grid
    axis: each run starts cold and each later case starts from its neighbour's converged q by the tangent
    predictor (bent through the one before, :func:`curved_predictor`), falling back to a cold start inside
    the solver when that fails. ``stop[0] != 0`` (set by Ctrl-C from another thread) ends the sweep at the
    next case; the block is then incomplete. With a life table (``elements.life``, rows > 0;
    life.life_table) L10r, L10r_row and the static safety (with ``elements.C0`` in N; nan where a case did
    not converge) are filled too (else they may be (1, ...) arrays, untouched). The outer contact angles
    (smallest, largest loaded outer contact angle per row, rad) are filled in a map at speed (else (1, rows),
    untouched). The per-thread scratch is sized by contract.scratch_shape, as on the GPU.
    """
    n_runs = cases.segments.shape[0] - 1
    share(map_groups, min(n_runs, MAP_GROUPS), elements, cases, scratch_shape(elements, cases), given_load, settings,
          stop)


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True)
def map_groups(claimed, elements, cases, shape, given_load, settings, stop):
    """One thread's part of :func:`map_sweep`'s block: the block's runs fall in min(runs, MAP_GROUPS) groups
    (group g: runs g, g + groups, ...), taken from the counter ``claimed`` (:func:`_claim`) until none is left,
    each with a Scratch of ``shape`` (contract.ScratchShape) of its own."""
    n_runs = cases.segments.shape[0] - 1
    groups = min(n_runs, MAP_GROUPS)
    g = _claim(claimed)
    while g < groups:
        scratch = new_scratch(shape, elements.balls, cases.operating, cases.results.n_loaded)
        map_runs(range(g, n_runs, groups), elements, cases, given_load, settings, stop, scratch)
        g = _claim(claimed)


@njit(inline="always")
def new_scratch(shape, balls, operating, counts):
    """A CPU thread's contract.Scratch of ``shape`` for the element set ``balls`` (the warm starts from its
    speed table, None without one; its own tables with a block's ``operating``, :func:`own_tables`; the outer
    counts in ``counts``' dtype)."""
    table, slices = own_tables(balls, operating)
    return Scratch(np.empty((WORK_ROWS, 5)), np.empty((PREDICTOR_ROWS, 5)), np.empty(shape.record),
                   np.empty(shape.record), np.empty((shape.life_rows, 2)), warm_scratch(balls.speed_table),
                   np.empty(shape.rows), np.empty(shape.rows, counts.dtype), table, slices)


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def map_runs(runs, elements, cases, given_load, settings, stop, scratch):
    """The continuation runs ``runs`` (a range) of :func:`map_sweep`'s block, one after another, with one
    thread's ``scratch`` (contract.Scratch): a CPU group's or a GPU thread's.
    Serial and without reference counting: the results' rows are views of arrays both threads write."""
    inputs, segments, out = cases.inputs, cases.segments, cases.results
    predictor = scratch.predictor
    for run in runs:
        if stop_requested(stop):
            break
        # whether predictor[_SLOPE] holds the tangent step of case i - 1; np.bool_, not the literal False: numba
        # compiled curved_predictor once for Literal[bool](False) (its first guess of the type) and again for bool
        slope_known = np.bool_(False)
        for i in range(segments[run], segments[run + 1]):
            if stop_requested(stop):
                break
            warm = i > segments[run] and (out.status[i - 1] & OUTCOME_MASK) == CONVERGED
            if warm:
                keep_slope(predictor)  # the previous case's tangent step: the earlier solution's slope
                took_tangent = tangent_predictor(given_load, inputs[i], out.q[i - 1], out.f[i - 1], out.K[i - 1],
                                                 out.q[i], predictor, settings.fixed)
                if given_load and i - 1 > segments[run] and (out.status[i - 2] & OUTCOME_MASK) == CONVERGED:
                    curved_predictor(inputs[i], inputs[i - 1], inputs[i - 2], out.q[i - 1], out.q[i - 2], out.q[i],
                                     predictor[_SLOPE], slope_known)
                slope_known = took_tangent
            else:
                slope_known = np.bool_(False)
            out.status[i], out.iterations[i], out.residual[i] = operating_point(
                given_load, inputs[i], warm, out.q[i], out.f[i], out.K[i],
                at_speed(with_operating(elements.balls, cases, i, scratch.table, scratch.slices),
                         cases.speeds, i, scratch.spin, not warm), settings, scratch)
            write_case(elements, cases, i, given_load, settings, scratch)


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def write_case(elements, cases, i, given_load, settings, scratch):
    """Case i's outputs beyond q, f, Kb and the solve's own (contract.Results): the per-row summaries of
    its element record, at speed the outer contacts' angles, and with a life table L10r, L10r_row and the
    static safety (nan where the case did not converge). A new per-case output is written here."""
    out, life, ball_row = cases.results, elements.life, elements.ball_row
    n_elements = ball_row.shape[0]
    ball_load, contact_angle = scratch.ball_load, scratch.contact_angle
    spinning = cases.speeds.shape[0] > 0
    row_summary(ball_load, contact_angle, ball_row, out.max_load[i], out.n_loaded[i], out.min_angle[i],
                out.max_angle[i])
    if spinning:  # the outer contacts' angles (their loads are the life's)
        row_summary(ball_load[n_elements:], contact_angle[n_elements:], ball_row, scratch.outer_load,
                    scratch.outer_count, out.min_outer[i], out.max_outer[i])
    if life.shape[0] == 0:
        return
    outcome = out.status[i] & OUTCOME_MASK
    if outcome == CONVERGED or outcome == UNLOADED:
        if life[0, LIFE_SLICES] > 0.0:
            out.L10r[i] = roller_case_life(ball_load, n_elements, life, out.L10r_row[i])
        elif spinning and cases.speeds[i] > 0.0:
            out.L10r[i] = case_life(ball_load, ball_load[n_elements:], ball_row, life, scratch.sums, out.L10r_row[i])
        else:
            out.L10r[i] = case_life(ball_load, None, ball_row, life, scratch.sums, out.L10r_row[i])
        # the reached load: with fixed degrees of freedom the inputs hold displacements there
        load = cases.inputs[i] if given_load and settings.fixed == 0 else out.f[i]
        out.safety[i] = static_safety(load, life, elements.C0)
    else:
        out.L10r[i] = np.nan
        out.safety[i] = np.nan
        for r in range(out.L10r_row.shape[1]):
            out.L10r_row[i, r] = np.nan


def slices_at(slice_tables, p, default=None):
    """The table at cage position p of a stack, or ``default`` when the stack is None (no roller rows; no
    per-position speed tables). Chosen while typing."""


# inlined into the caller's IR: it returns a view, which passage_point (no reference counting) may not receive
# from a call; an overload, so that a None stack read from a record (contract.Positions) is pruned by its type
@overload(slices_at, inline="always", jit_options={"_nrt": True})
def _slices_at(slice_tables, p, default=None):
    if isinstance(slice_tables, types.NoneType):
        return lambda slice_tables, p, default=None: default
    return lambda slice_tables, p, default=None: slice_tables[p]


def passage_sweep(elements, positions, cases, given_load, settings, stop):
    """Ball-passage tables, in place: every operating point of ``cases`` (contract.CaseBlock, its results a
    contract.PassageResults) at every cage position of ``positions`` (contract.Positions).

    ``positions.tables`` (P, N_BALL_COLUMNS, n_balls) and ``positions.slices`` (P, N_SLICE_COLUMNS, n_slices;
    None without roller rows) hold the ball and roller-slice tables at each of P cage angles,
    ``elements.balls`` the bearing's element set at cage angle 0 (its exponents, speed parts and shaft speed),
    ``positions.speed_tables`` (P, ...) its high-speed tables per position (local defects) or None; outputs
    are (N, P, ...), ``element_loads`` (N, P, n_elements) each element's load where it has rows (else
    (0, 0, 0): not stored). Along the positions of one point each solve starts from the previous position's
    converged q. ``stop[0] != 0`` ends the sweep early, as in map_sweep. Its cases are the bearing as its
    tables hold it (``cases.operating`` None).
    """
    if cases.operating is not None or cases.ball_sizes is not None:
        raise ValueError("cases.operating: a passage table's cases take the bearing's own clearance and preload "
                         "(None); per-case operating values are for maps and batches")
    n_points = cases.inputs.shape[0]
    share(passage_groups, min(n_points, MAP_GROUPS), elements, positions, cases, scratch_shape(elements, cases),
          given_load, settings, stop)


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True)
def passage_groups(claimed, elements, positions, cases, shape, given_load, settings, stop):
    """One thread's part of :func:`passage_sweep`: the points fall in min(points, MAP_GROUPS) groups (group g:
    points g, g + groups, ...), taken from the counter ``claimed`` until none is left, each with a Scratch of
    ``shape`` of its own."""
    n_points = cases.inputs.shape[0]
    groups = min(n_points, MAP_GROUPS)
    g = _claim(claimed)
    while g < groups:
        # a passage table's cases are the bearing as its tables hold it: no operating values of their own
        scratch = new_scratch(shape, elements.balls, None, cases.results.n_loaded)
        for i in range(g, n_points, groups):
            if stop_requested(stop):
                break
            passage_point(i, elements, positions, cases, given_load, settings, scratch)
        g = _claim(claimed)


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def passage_point(i, elements, positions, cases, given_load, settings, scratch):
    """Operating point i of :func:`passage_sweep` at every cage position, in place in ``cases.results``
    (contract.PassageResults), each position starting from the previous one's converged q. The ``scratch``
    (contract.Scratch) is the caller's: a CPU thread's or a GPU thread's."""
    out, balls = cases.results, elements.balls
    n_elements = elements.ball_row.shape[0]
    spin = scratch.spin
    for p in range(positions.tables.shape[0]):
        warm = p > 0 and (out.status[i, p - 1] & OUTCOME_MASK) == CONVERGED
        forget_if(spin, not warm)
        if warm:
            for d in range(5):
                out.q[i, p, d] = out.q[i, p - 1, d]
        out.status[i, p], out.iterations[i, p], out.residual[i, p] = operating_point(
            given_load, cases.inputs[i], warm, out.q[i, p], out.f[i, p], out.K[i, p],
            at_position(balls, positions.tables[p], slices_at(positions.slices, p), balls.omega, spin,
                        slices_at(positions.speed_tables, p, balls.speed_table)), settings, scratch)
        row_summary(scratch.ball_load, scratch.contact_angle, elements.ball_row, out.max_load[i, p],
                    out.n_loaded[i, p], out.min_angle[i, p], out.max_angle[i, p])
        if out.element_loads.shape[0] > 0:
            for e in range(n_elements):
                out.element_loads[i, p, e] = scratch.ball_load[e]
