"""Tiny dense solves for the 5x5 systems of the solver (njit, allocation-free).

Both write into caller-provided scratch and return False instead of raising
when the matrix is not usable.
"""

import math

from numba import njit

from .config import CACHE, ERROR_MODEL, FASTMATH, REFCOUNT


@njit(cache=CACHE, fastmath=FASTMATH, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def cholesky_solve(A, shift, b, x, L):
    """Solve (A + shift*I) x = b for symmetric 5x5 A via Cholesky; False if not positive definite.

    The fixed size lets LLVM unroll the loops; the diagonal of L is stored
    as reciprocals so the whole solve needs 5 divisions.
    """
    n = 5
    for i in range(n):
        for j in range(i + 1):
            s = A[i, j]
            for k in range(j):
                s -= L[i, k] * L[j, k]
            if i == j:
                s += shift
                if not s > 0.0:  # also catches nan
                    return False
                L[i, i] = 1.0 / math.sqrt(s)  # reciprocal of the diagonal
            else:
                L[i, j] = s * L[j, j]
    for i in range(n):
        s = b[i]
        for k in range(i):
            s -= L[i, k] * x[k]
        x[i] = s * L[i, i]
    for i in range(n - 1, -1, -1):
        s = x[i]
        for k in range(i + 1, n):
            s -= L[k, i] * x[k]
        x[i] = s * L[i, i]
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
    """Solve (A + shift*I) x = b for a 5x5 stiffness A: Cholesky where A is exactly symmetric (Kb of the
    quasi-static model, whose kernel mirrors its entries), else LU with partial pivoting (Kb at speed is
    not symmetric: the gyroscopic moment's friction; its lower triangle alone would make Newton's
    convergence linear). False where Cholesky finds A + shift*I not positive definite, or LU singular."""
    for i in range(5):
        for j in range(i):
            if A[i, j] != A[j, i]:
                return lu_solve(A, b, x, LU, perm, shift)
    return cholesky_solve(A, shift, b, x, LU)
