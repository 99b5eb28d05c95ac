"""Tiny dense solves for the 5x5 systems of the solver (njit, allocation-free).

Both write into caller-provided scratch and return False instead of raising
when the matrix is not usable.
"""

from numba import njit

from ..config import CACHE, ERROR_MODEL, FASTMATH, REFCOUNT


@njit(cache=CACHE, fastmath=FASTMATH, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def ldl_solve(A, shift, b, x):
    """Solve (A + shift*I) x = b for symmetric 5x5 A (its lower triangle is read) by the square-root-free
    Cholesky factorisation A + shift*I = L D L^T; False if not positive definite (a pivot d_i <= 0 or nan).

    Written out in scalars: the factor lives in registers, five divisions and no square root (a loop
    over a stored factor with reciprocal square roots took 2-3x as long). W_ij = L_ij d_j.
    """
    a00 = A[0, 0] + shift
    a10 = A[1, 0]
    a11 = A[1, 1] + shift
    a20 = A[2, 0]
    a21 = A[2, 1]
    a22 = A[2, 2] + shift
    a30 = A[3, 0]
    a31 = A[3, 1]
    a32 = A[3, 2]
    a33 = A[3, 3] + shift
    a40 = A[4, 0]
    a41 = A[4, 1]
    a42 = A[4, 2]
    a43 = A[4, 3]
    a44 = A[4, 4] + shift
    if a10 == 0.0 and a30 == 0.0 and a21 == 0.0 and a41 == 0.0 and a32 == 0.0 and a43 == 0.0:
        return _split_ldl_solve(a00, a11, a20, a22, a31, a33, a40, a42, a44, b, x)
    if not a00 > 0.0:
        return False
    i0 = 1.0 / a00
    l10 = a10 * i0
    d1 = a11 - a10 * l10
    if not d1 > 0.0:
        return False
    i1 = 1.0 / d1
    l20 = a20 * i0
    w21 = a21 - a20 * l10
    l21 = w21 * i1
    d2 = a22 - a20 * l20 - w21 * l21
    if not d2 > 0.0:
        return False
    i2 = 1.0 / d2
    l30 = a30 * i0
    w31 = a31 - a30 * l10
    l31 = w31 * i1
    w32 = a32 - a30 * l20 - w31 * l21
    l32 = w32 * i2
    d3 = a33 - a30 * l30 - w31 * l31 - w32 * l32
    if not d3 > 0.0:
        return False
    i3 = 1.0 / d3
    l40 = a40 * i0
    w41 = a41 - a40 * l10
    l41 = w41 * i1
    w42 = a42 - a40 * l20 - w41 * l21
    l42 = w42 * i2
    w43 = a43 - a40 * l30 - w41 * l31 - w42 * l32
    l43 = w43 * i3
    d4 = a44 - a40 * l40 - w41 * l41 - w42 * l42 - w43 * l43
    if not d4 > 0.0:
        return False
    i4 = 1.0 / d4
    # L y = b, then D z = y, then L^T x = z
    y0 = b[0]
    y1 = b[1] - l10 * y0
    y2 = b[2] - l20 * y0 - l21 * y1
    y3 = b[3] - l30 * y0 - l31 * y1 - l32 * y2
    y4 = b[4] - l40 * y0 - l41 * y1 - l42 * y2 - l43 * y3
    x4 = y4 * i4
    x3 = y3 * i3 - l43 * x4
    x2 = y2 * i2 - l32 * x3 - l42 * x4
    x1 = y1 * i1 - l21 * x2 - l31 * x3 - l41 * x4
    x0 = y0 * i0 - l10 * x1 - l20 * x2 - l30 * x3 - l40 * x4
    x[0] = x0
    x[1] = x1
    x[2] = x2
    x[3] = x3
    x[4] = x4
    return True


@njit(inline="always", fastmath=FASTMATH, error_model=ERROR_MODEL)
def _split_ldl_solve(a00, a11, a20, a22, a31, a33, a40, a42, a44, b, x):
    """:func:`ldl_solve` of a Kb without the entries that couple (y, tx) to (x, z, ty) (a planar
    displacement of a mirror-symmetric ball set, kernel.quasi_static_balls): two independent factors, of
    three and two pivots, whose division chains overlap instead of running one after the other. The
    same operations as the 5x5 factor less its products with exact zeros (x - 0 * y is x for a finite y),
    so the same x. Written out like ldl_solve, for the same reason: the factor stays in registers."""
    if not (a00 > 0.0 and a11 > 0.0):
        return False
    i0 = 1.0 / a00
    i1 = 1.0 / a11
    l20 = a20 * i0
    d2 = a22 - a20 * l20
    l31 = a31 * i1
    d3 = a33 - a31 * l31
    if not (d2 > 0.0 and d3 > 0.0):
        return False
    i2 = 1.0 / d2
    i3 = 1.0 / d3
    l40 = a40 * i0
    w42 = a42 - a40 * l20
    l42 = w42 * i2
    d4 = a44 - a40 * l40 - w42 * l42
    if not d4 > 0.0:
        return False
    i4 = 1.0 / d4
    y0 = b[0]
    y1 = b[1]
    y2 = b[2] - l20 * y0
    y3 = b[3] - l31 * y1
    y4 = b[4] - l40 * y0 - l42 * y2
    x4 = y4 * i4
    x3 = y3 * i3
    x2 = y2 * i2 - l42 * x4
    x1 = y1 * i1 - l31 * x3
    x0 = y0 * i0 - l20 * x2 - l40 * x4
    x[0] = x0
    x[1] = x1
    x[2] = x2
    x[3] = x3
    x[4] = x4
    return True


@njit(cache=CACHE, fastmath=FASTMATH, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def lu_solve(A, b, x, LU, perm, shift):
    """Solve (A + shift*I) x = b by LU with partial pivoting (A unchanged); False if singular."""
    n = A.shape[0]
    for i in range(n):
        perm[i] = i
        for j in range(n):
            LU[i, j] = A[i, j]
        LU[i, i] += shift
    scale = 0.0
    for i in range(n):
        for j in range(n):
            scale = max(scale, abs(A[i, j]))
    if not scale > 0.0:
        return False
    for k in range(n):
        p = k
        for i in range(k + 1, n):
            if abs(LU[i, k]) > abs(LU[p, k]):
                p = i
        if abs(LU[p, k]) <= 1e-14 * scale:
            return False
        if p != k:
            for j in range(n):
                LU[k, j], LU[p, j] = LU[p, j], LU[k, j]
            perm[k], perm[p] = perm[p], perm[k]
        for i in range(k + 1, n):
            LU[i, k] /= LU[k, k]
            for j in range(k + 1, n):
                LU[i, j] -= LU[i, k] * LU[k, j]
    for i in range(n):
        s = b[int(perm[i])]
        for k in range(i):
            s -= LU[i, k] * x[k]
        x[i] = s
    for i in range(n - 1, -1, -1):
        s = x[i]
        for k in range(i + 1, n):
            s -= LU[i, k] * x[k]
        x[i] = s / LU[i, i]
    return True



@njit(cache=CACHE, fastmath=FASTMATH, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def stiffness_solve(A, shift, b, x, LU, perm):
    """Solve (A + shift*I) x = b for a 5x5 stiffness A: LDL^T where A is exactly symmetric (Kb of the
    quasi-static model, whose kernel mirrors its entries), else LU with partial pivoting (Kb at speed is
    not symmetric: the gyroscopic moment's friction; its lower triangle alone would make Newton's
    convergence linear). False where LDL^T finds A + shift*I not positive definite, or LU singular."""
    for i in range(5):
        for j in range(i):
            if A[i, j] != A[j, i]:
                return lu_solve(A, b, x, LU, perm, shift)
    return ldl_solve(A, shift, b, x)
