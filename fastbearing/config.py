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

#: numba's reference counting (its ``_nrt`` option) in the serial kernels: off. With it on, every array
#: argument and every view such as ``work[_G]`` is counted with an atomic add and a call, 23 % of a load
#: map case's time, on counters the two threads share. A function compiled with it off must neither
#: allocate nor return an array (tests/test_layers.py checks both); the parallel sweeps, which allocate
#: the per-block scratch, keep it on.
REFCOUNT = False


def __getattr__(name):
    # CACHE (numba's on-disk cache: on) is what every module with cached kernels imports from here, so
    # looking it up is the moment to drop machine code built from other sources (_cache.ensure_fresh):
    # before the first cached kernel can load. Modules without kernels (the command line's parser) import
    # this file without paying for numba.
    if name == "CACHE":
        from ._cache import ensure_fresh, self_contained_linking
        from ._numba_cache import serialise_compiles
        from ._prebuilt import use_prebuilt

        self_contained_linking()  # before any kernel compiles or loads: the same bits either way
        serialise_compiles()  # processes started together compile each function once, not once each
        digest = ensure_fresh()
        # set before the prebuilt copy: unpickling its signatures imports kernel modules, which look it up
        globals()["CACHE"] = True
        use_prebuilt(digest)  # a release wheel's kernels for this CPU level, where they apply
        return True
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


#: The load-given solvers by name (solver.py: damped Newton, or Broyden's secant updates).
NEWTON = 0
BROYDEN = 1
METHODS = {"newton": NEWTON, "broyden": BROYDEN}

#: Relative residual at which a load-given solve is declared converged, and its allowed range.
RTOL = 1e-10
RTOL_RANGE = (1e-14, 1e-3)
#: Iterations per solver phase (each costs one kernel evaluation, or a few when
#: the line search backtracks), and the allowed range of a user's max_iter.
MAX_ITER_NEWTON = 60
MAX_ITER_BROYDEN = 300
MAX_ITER_RANGE = (1, 10_000)
#: The fast phase hands a case to the fallback after this many iterations
#: without halving the residual.
STAGNATION_ITERATIONS = 12
#: A solution farther than this many element reaches (A0, or a roller row's deflection scale) from rest
#: is a load the bearing does not hold (e.g. an axial load on cylindrical rollers): SINGULAR, not a
#: rounding limit.
DIVERGED_REACH = 1000.0
#: Fallback line search: trials per direction, and its acceptance |phi'(t)| <= SEARCH_CURVATURE |phi'(0)|
#: on the descending side.
SEARCH_TRIALS = 40
SEARCH_CURVATURE = 0.5
#: Fallback smoothing continuation: eps from SMOOTHING_FIRST * A0 down by SMOOTHING_RATIO per level to
#: SMOOTHING_LAST * A0, each level solved to SMOOTHING_RTOL, then the exact contact law.
SMOOTHING_FIRST = 1.0
SMOOTHING_RATIO = 0.1
SMOOTHING_LAST = 1e-7
SMOOTHING_RTOL = 1e-6
#: A cold solve at speed first solves the balls standing still (the quasi-static loop, a tenth of the
#: cost) to this relative residual and starts the spinning balls from there: 20 % faster cold solves.
STILL_START_RTOL = 0.1
#: A Newton trial carries the per-ball record (so that no evaluation is spent on it after convergence)
#: where the residual it starts from predicts convergence: Newton's next residual is about rmax^2 / scale,
#: and the trial records when that is within RECORD_AHEAD x tol (at speed every trial records).
RECORD_AHEAD = 1.0
#: Cases per block in parallel sweeps: per-block scratch is allocated once.
SWEEP_BLOCK = 64
