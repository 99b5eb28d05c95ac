"""Numerical settings shared by every kernel (one place, like stumpy's config).

fastmath stays off in the solver: its convergence test relies on IEEE
semantics for inf/nan. The ball loop alone allows reassociation and
contraction (no nnan/ninf), so LLVM can vectorise the sum over balls: that
changes results by about 1e-15 relative (summation order), identically for
every thread count and chunk size.

error_model "numpy": a float division by zero gives inf/nan instead of a
Python exception, so nothing can raise inside njit code, and the division
needs no branch (which would also block vectorisation).
"""

FASTMATH = False
KERNEL_FASTMATH = {"reassoc", "contract", "nsz", "arcp"}
ERROR_MODEL = "numpy"
CACHE = True

#: Relative residual at which a load-given solve is declared converged.
RTOL = 1e-10
#: Newton iterations per attempt (each costs one kernel evaluation or a few
#: when the line search backtracks).
MAX_ITER_NEWTON = 60
#: Broyden iterations per attempt (secant steps are cheaper but slower to converge).
MAX_ITER_BROYDEN = 300
#: Cases per block in parallel sweeps: per-block scratch is allocated once.
SWEEP_BLOCK = 64
