"""Numerical settings shared by every kernel (one place, like stumpy's config).

fastmath stays off: results must be reproducible bit for bit across thread
counts and chunk sizes, and the solver's convergence test relies on IEEE
semantics for inf/nan.
"""

FASTMATH = False
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
