"""Python API: check and prepare inputs, then call the njit kernels.

Units everywhere: N, mm, rad. q = (dx, dy, dz, bx, by) in mm and rad;
f = (Fx, Fy, Fz, Mx, My) in N and N*mm; Kb in N/mm (translations),
N*mm/rad (tilts) and N/rad (coupling), all at the bearing centre.
"""

from __future__ import annotations

import contextlib
from collections import namedtuple
from dataclasses import dataclass, replace

import numba
import numpy as np

from . import config

from . import status as st

from . import validate
from .model.bearing import Bearing, check_speed, check_speed_model
from .model.mounted import operating, operating_rows, refuse_speed_cases
from .dofs import DISPLACEMENT_NAMES, DISPLACEMENT_UNITS, LOAD_NAMES, LOAD_UNITS  # noqa: F401 (public names)
from .engine.kernel import ball_loop
from .config import METHODS, NEWTON
from . import boundary
from .engine.solver import WORK_ROWS, SolverSettings, solve_case
from .engine.contract import CaseBlock, Solutions
from .engine.sweep import solve_sweep, stiffness_sweep
from .engine.device import DEVICES



@dataclass(frozen=True)
class SolveResult:
    """Outcome of a load-given solve.

    Attributes
    ----------
    q : ndarray (5,)
        Displacement (dx, dy, dz, bx, by) in mm and rad.
    f : ndarray (5,)
        Load at q (Fx, Fy, Fz, Mx, My) in N and N*mm.
    K : ndarray (5, 5)
        Kb at q: N/mm, N*mm/rad, N/rad.
    status : int
        Code from :mod:`fastbearing.status`; ``status_name`` spells it.
    iterations : int
        Solver iterations.
    residual : float
        Relative residual: max|f(q) - f_target| over max|f_target| with
        moments divided by the largest pitch radius.
    evaluations : int
        Kernel evaluations (each is one pass over all balls).
    note : str
        Where the model has no answer for this load, why, in one line (empty otherwise): e.g. a tapered
        row under a radial load with too little axial load to hold it; or where a bearing whose rows all sit
        at one axial place (a single row, a four-point row's two contact pairs) took a combined load with its
        tilt free, that it tilted and how to fix the tilt.
    fixed : tuple of str
        The degrees of freedom given as displacements (``fixed=``): q holds their values, f the reactions.
    """

    q: np.ndarray
    f: np.ndarray
    K: np.ndarray
    status: int
    iterations: int
    residual: float
    evaluations: int
    note: str = ""
    fixed: tuple = ()

    @property
    def converged(self) -> bool:
        return st.is_converged(self.status)

    @property
    def status_name(self) -> str:
        return st.describe(self.status)

    def to_dict(self) -> dict:
        """JSON-ready dict (keys q, f, K, status, converged, iterations, residual; note where there is one)."""
        out = {"q": self.q.tolist(), "f": self.f.tolist(), "K": self.K.tolist(), "status": self.status_name,
               "converged": self.converged, "iterations": int(self.iterations), "residual": float(self.residual)}
        if self.note:
            out["note"] = self.note
        if self.fixed:
            out["fixed"] = list(self.fixed)
        return out


def _check_bearing(bearing) -> Bearing:
    if not isinstance(bearing, Bearing):
        raise ValueError(f"bearing must be a fastbearing.Bearing, got {type(bearing).__name__}")
    return bearing


def _operating(bearing, speed, many: bool = False) -> Bearing:
    """The bearing as it runs: a bearing with [bearing.mounting] becomes its operating bearing at ``speed``
    (rpm; fastbearing.model.mounted.operating_bearing); any other bearing is returned as it is."""
    bearing = _check_bearing(bearing)
    if bearing.mounting is None:
        return bearing
    if many:
        speed = refuse_speed_cases(bearing, speed)
    return operating(bearing, check_speed(speed))


def as_cases(values, name: str, units: str) -> np.ndarray:
    """(N, 5) float64 C-contiguous copy of ``values``; ValueError names the field.

    Numbers only, as everywhere in fastbearing: strings (even numeric ones), booleans and complex
    values are refused, not converted."""
    try:
        raw = np.asarray(values)
        if raw.dtype.kind == "O" or not isinstance(values, np.ndarray):
            # a list may mix types that numpy would coerce (True -> 1, "12" -> 12.0): look at each item
            items = np.asarray(values, dtype=object).ravel()
            if any(isinstance(x, (bool, np.bool_, str, bytes, complex, np.complexfloating)) for x in items):
                raise TypeError
        if raw.dtype.kind not in "iufO":
            raise TypeError
        arr = np.array(raw, dtype=np.float64, order="C", ndmin=2)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be numbers ({units}), got {values!r}") from None
    if arr.ndim != 2 or arr.shape[1] != 5:
        raise ValueError(f"{name} must have 5 components ({units}) per case, got shape {np.shape(values)}")
    bad = ~np.isfinite(arr)
    if bad.any():
        i, j = np.argwhere(bad)[0]
        raise ValueError(f"{name} must be finite; case {i} component {j} is {arr[i, j]!r}")
    return arr


def _as_vector(values, name: str, units: str) -> np.ndarray:
    arr = as_cases(values, name, units)
    if arr.shape[0] != 1:
        raise ValueError(f"{name} must be 5 numbers ({units}), got shape {np.shape(values)}")
    return arr[0]


def _method(method: str) -> int:
    return METHODS[validate.choice(method, "method", sorted(METHODS))]


def solver_settings(bearing: Bearing, method: str = "newton", rtol=None, max_iter=None,
                    fixed: int = 0) -> SolverSettings:
    """Checked solver settings shared by :func:`solve` and the sweeps.

    ``rtol`` (relative residual, default 1e-10) must lie in
    [1e-14, 1e-3]; ``max_iter`` (iterations per solver phase) is an integer
    in [1, 10000]; ``fixed`` the bitmask of degrees of freedom given as
    displacements (boundary.Fixed.mask).
    """
    m = _method(method)
    default_iter = config.MAX_ITER_NEWTON if m == NEWTON else config.MAX_ITER_BROYDEN
    return SolverSettings(
        method=m,
        rtol=config.RTOL if rtol is None else validate.number(rtol, "rtol", low=config.RTOL_RANGE[0],
                                                               high=config.RTOL_RANGE[1]),
        max_iter=default_iter if max_iter is None else validate.integer(
            max_iter, "max_iter", low=config.MAX_ITER_RANGE[0], high=config.MAX_ITER_RANGE[1]),
        length_scale=bearing.length_scale,
        # one fast-phase step may move at most half the smallest groove-centre distance
        max_step=0.5 * min(r.deflection_scale for r in bearing.rows),
        fixed=int(fixed),
    )


def stiffness(bearing: Bearing, q, speed=0.0) -> tuple[np.ndarray, np.ndarray]:
    """Load f and stiffness Kb at a given displacement (direct substitution).

    Parameters
    ----------
    bearing : Bearing
    q : sequence of 5 floats
        (dx, dy, dz, bx, by) in mm and rad at the bearing centre.
    speed : float
        Shaft speed in rpm, >= 0 (see :func:`solve`).

    Returns
    -------
    f : ndarray (5,)
        (Fx, Fy, Fz, Mx, My) in N and N*mm.
    K : ndarray (5, 5)
        Kb in N/mm, N*mm/rad, N/rad; symmetric at speed 0.

    Raises
    ------
    ValueError
        If q is not 5 finite numbers, or so large that f or Kb overflow float64; at speed, if some ball's
        own equilibrium does not settle at q (status ball_equilibrium: f and Kb there are not the model's).
    """
    f, K, status = direct(bearing, q, speed)
    if st.outcome(status) == st.BALL_EQUILIBRIUM:
        raise ValueError(f"q: at {float(speed):g} rpm some balls have no equilibrium of their own at this "
                         "displacement (status ball_equilibrium), so f and Kb there are not the model's")
    return f, K


def direct(bearing: Bearing, q, speed=0.0) -> tuple[np.ndarray, np.ndarray, int]:
    """f (N, N*mm), Kb and the status code of the displacement ``q`` (mm, rad) at ``speed`` (rpm): CONVERGED
    with the warning bits (contact_reversed, beyond_validity), or BALL_EQUILIBRIUM where at speed some
    ball's own equilibrium did not settle (as a displacement-given map flags it). ValueError for a bad q or
    an f or Kb that overflows float64."""
    bearing = _operating(bearing, speed)
    q = _as_vector(q, "q", "dx, dy, dz in mm; bx, by in rad")
    balls = speed_ball_set(bearing, speed)
    f = np.empty(5)
    K = np.empty((5, 5))
    _, _, warnings = ball_loop(q, balls, f, K, None, None)
    if warnings & st.BALL_UNSETTLED:  # said before any overflow: an unsettled ball may leave Kb non-finite
        return f, K, st.BALL_EQUILIBRIUM | (warnings & st.WARNING_MASK)
    _check_finite_result(f, K, "q")
    return f, K, st.CONVERGED | (warnings & st.WARNING_MASK)


def speed_ball_set(bearing: Bearing, speed) -> tuple:
    """The kernel's ball set at shaft ``speed`` (rpm, checked: finite, >= 0): quasi-static at 0, the
    high-speed balls above (which need the bearing's geometry; ValueError naming ``speed`` otherwise)."""
    speed = check_speed(speed)
    if speed == 0.0:
        return bearing.ball_set()
    check_speed_model(bearing, speed)
    return bearing.ball_set(speed=speed)


def case_speeds(speed, n: int) -> np.ndarray:
    """(n,) rpm from one number or one per case, each checked (FieldError naming ``speed[i]``)."""
    values = np.asarray(speed, dtype=object)
    if values.ndim == 0:
        return np.full(n, check_speed(speed))
    if values.ndim == 1 and values.shape[0] == n:
        return np.array([check_speed(v, f"speed[{i}]") for i, v in enumerate(values)], dtype=float)
    raise validate.FieldError("speed", f"must be one number or one per case ({n}), rpm >= 0", show_value=False)


def speed_cases(bearing: Bearing, speed, n: int) -> tuple[tuple, np.ndarray]:
    """(ball set, per-case omega in rad/s) for n cases at ``speed`` (rpm: one number, or N numbers):
    the quasi-static set and no speeds when every speed is 0."""
    values = np.asarray(speed, dtype=object)
    speeds = case_speeds(speed, n)
    if not speeds.any():
        return bearing.ball_set(), np.zeros(0)
    fastest = int(np.argmax(speeds))
    check_speed_model(bearing, speeds[fastest], "speed" if values.ndim == 0 else f"speed[{fastest}]")
    return bearing.ball_set(speed=0.0), speeds * np.pi / 30.0  # as rpm_to_rad_s rounds it: solve_many and stiffness bit for bit


def _check_finite_result(f, K, name: str) -> None:
    bad = ~(np.isfinite(f).all(axis=-1) & np.isfinite(K).all(axis=(-2, -1)))
    if np.any(bad):
        where = f" (case {int(np.flatnonzero(bad)[0])})" if np.ndim(bad) else ""
        raise ValueError(f"{name}{where} is too large: f or Kb overflow float64 (displacements must be small "
                         "against the groove-centre distance A0, mm)")


def ball_loads(bearing: Bearing, q, speed=0.0) -> tuple[np.ndarray, np.ndarray]:
    """Per-ball load Q (N) and contact angle alpha (rad, signed on the row's contact direction) at q; at
    ``speed`` (rpm) > 0 the inner contact's load and angle.

    Balls are ordered row by row, each row from its first ball.
    """
    bearing = _operating(bearing, speed)
    q = _as_vector(q, "q", "dx, dy, dz in mm; bx, by in rad")
    Q = np.empty(bearing.n_elements)
    alpha = np.empty(bearing.n_elements)
    ball_loop(q, speed_ball_set(bearing, speed), np.empty(5), None, Q, alpha)
    return Q, alpha


def solve(bearing: Bearing, f, q0=None, method: str = "newton", rtol=None, max_iter=None,
          speed=0.0, fixed=None) -> SolveResult:
    """Displacement q and stiffness Kb under a given load f (paper Eq. 16).

    Parameters
    ----------
    bearing : Bearing
    f : sequence of 5 floats
        (Fx, Fy, Fz, Mx, My) in N and N*mm, applied to the inner ring at the
        bearing centre.
    q0 : sequence of 5 floats, optional
        Warm start (mm, rad); a cold start is used if it fails.
    method : {"newton", "broyden"}
        Damped Newton with the analytic Kb, or Broyden's secant method.
    rtol : float, optional
        Relative residual tolerance (default 1e-10).
    max_iter : int, optional
        Iterations per attempt.
    speed : float
        Shaft speed in rpm, >= 0 (default 0: the quasi-static model). Above 0 every ball is held in
        equilibrium under its centrifugal force and gyroscopic moment (fastbearing.engine.high_speed; the
        bearing needs its geometry), and Kb is the exact derivative with the balls re-settled: not
        symmetric in general.
    fixed : dict, optional
        Degrees of freedom given as displacements, e.g. ``{"bx": 0.0, "by": 0.0}`` (dx, dy, dz in mm; bx, by
        in rad): the ring is held there and the load entries at those degrees of freedom, which must be 0,
        are the unknown reactions (returned in ``f``). Any subset but all five (that is :func:`stiffness`).
        Each value at most 2 element reaches (A0 of a ball row) in mm, a tilt that reach over the largest
        pitch radius in rad (:func:`fastbearing.boundary.fixed_bounds`).

    Returns
    -------
    SolveResult
        ``q`` (5,) in mm and rad, ``f`` (5,) the load reached at q in N and
        N*mm, ``K`` (5, 5) Kb at q in N/mm, N*mm/rad, N/rad, ``status``,
        ``iterations``, ``residual`` (relative) and ``evaluations``. Check
        ``result.converged`` (or ``status_name``) before using q and K.

    Raises
    ------
    ValueError
        Bad input, before any kernel runs; the message names the field and
        its allowed range: ``bearing`` not a :class:`Bearing`; ``f`` or
        ``q0`` not 5 finite numbers (strings, booleans and complex values
        are refused, not converted); ``method`` not "newton" or "broyden";
        ``rtol`` outside [1e-14, 1e-3]; ``max_iter`` not an integer in
        [1, 10000]; a ``fixed`` value beyond its bound. Non-convergence is never raised: it is reported in
        ``status`` (iteration_limit, singular, stalled, precision_limit,
        nonfinite_result ..., see :mod:`fastbearing.status`), with
        ``result.converged`` False.
    """
    bearing = _operating(bearing, speed)
    load = _as_vector(f, "f", "Fx, Fy, Fz in N; Mx, My in N*mm")
    held = boundary.parse_fixed(fixed, bearing=bearing)
    f_target = boundary.targets(load, held)
    opts = solver_settings(bearing, method, rtol, max_iter, held.mask)
    balls = speed_ball_set(bearing, speed)
    warm = q0 is not None
    q = _as_vector(q0, "q0", "mm, rad").copy() if warm else np.zeros(5)
    f_out = np.empty(5)
    K = np.empty((5, 5))
    work = np.empty((WORK_ROWS, 5))
    out = solve_case(f_target, q, f_out, K, balls, opts, warm, work, None, None)
    status = int(out.status)
    if st.is_converged(status):
        note = "" if held else boundary.free_tilt_note(bearing, load, q)
    else:
        note = no_solution_note(bearing, load, status, speed)
    return SolveResult(q, f_out, K, status, int(out.iterations), float(out.residual), int(out.evaluations), note,
                       tuple(held.names))


def no_solution_note(bearing: Bearing, load, status: int, speed: float = 0.0) -> str:
    """Why a load that did not solve has no solution in the model, in one line, where the bearing's element
    kinds know the cause (:meth:`Bearing.no_solution_note`); "" for a converged case or an unknown cause."""
    if st.outcome(status) not in (st.SINGULAR, st.STALLED, st.ITERATION_LIMIT):
        return ""
    return bearing.no_solution_note(load, speed)


def check_threads(n):
    """None, or an integer in [1, NUMBA_NUM_THREADS]; ValueError otherwise (call before creating anything)."""
    if n is None:
        return None
    return validate.integer(n, "threads", low=1, high=numba.config.NUMBA_NUM_THREADS)


@contextlib.contextmanager
def num_threads(n):
    """Run the sweeps on ``n`` threads inside the block (numba's thread count, which engine.threads.share reads;
    None: leave as is)."""
    n = check_threads(n)
    if n is None:
        yield
        return
    old = numba.get_num_threads()
    numba.set_num_threads(int(n))
    try:
        yield
    finally:
        numba.set_num_threads(old)


@dataclass(frozen=True)
class SolveManyResult:
    """Arrays from :func:`solve_many`: q (N,5) mm/rad, f (N,5) N/N*mm, K (N,5,5), status (N,) int8,
    iterations (N,) int32, residual (N,) relative, evaluations (N,) int32."""

    q: np.ndarray
    f: np.ndarray
    K: np.ndarray
    status: np.ndarray
    iterations: np.ndarray
    residual: np.ndarray
    evaluations: np.ndarray

    @property
    def converged(self) -> np.ndarray:
        return st.converged_mask(self.status)


#: :func:`case_operating`'s answer: ``bearing`` whose tables the cases start from; ``table`` None or (n, rows,
#: schema.N_OPERATING), contract.CaseBlock.operating; ``outside`` None or (n,) bool; ``notes``; and each case's
#: ``radial_clearance`` and ``axial_preload`` (n, rows) mm (nan where a mount is outside the model; None with
#: table None).
CaseOperating = namedtuple("CaseOperating", "bearing table outside notes radial_clearance axial_preload")


def case_operating(bearing: Bearing, n: int, speed=0.0, radial_clearance=None, axial_preload=None,
                   temperatures=None, per_case: bool = False) -> CaseOperating:
    """What n cases that vary the bearing give the kernels (a :data:`CaseOperating`).

    - A bearing without ``[bearing.mounting]``: each case's own ``radial_clearance`` rL and ``axial_preload``
      d0 (mm; None: the rows' own; one number, one per row (rows,), or one per case and row (n, rows)).
    - A mounted bearing: each case's operating clearance and preload from its ``speed`` (rpm, one or (n,)) and
      ``temperatures`` ({key: deg C, one or (n,)}, keys of model.mounted.CASE_TEMPERATURES), one mount per
      distinct (speed, temperatures) (model.mounted.operating_rows). One speed and no temperatures: the
      operating bearing itself (operating None), bit for bit as :func:`solve`, unless ``per_case`` (a map's
      block whose cases happen to share them).
    ``outside``: the cases whose values fail the rows' own checks (status outside_model, not solved); None
    when every case passes. ``notes``: the mounts' notes (fits lost, hoop stress), each once."""
    bearing = _check_bearing(bearing)
    if bearing.mounting is not None:
        if radial_clearance is not None or axial_preload is not None:
            raise validate.FieldError("radial_clearance", "is set by [bearing.mounting] (fits, temperatures, "
                                      "speed) for a mounted bearing: give a bearing without mounting to set it "
                                      "per case", show_value=False)
        speeds = np.broadcast_to(np.asarray(speed, dtype=float), (n,))
        if not per_case and not temperatures and np.unique(speeds).size <= 1:
            return CaseOperating(_operating(bearing, speeds[0] if n else 0.0), None, None, [], None, None)
        rL, d0, notes = operating_rows(bearing, speeds, temperatures)
        base = replace(bearing, mounting=None)  # the tables' other entries do not depend on the clearance
    else:
        if temperatures:
            raise validate.FieldError("temperatures", "need [bearing.mounting] (fits, materials) to act on the "
                                      "bearing", show_value=False)
        if radial_clearance is None and axial_preload is None:
            return CaseOperating(bearing, None, None, [], None, None)
        rL = _per_case_row(radial_clearance, [r.radial_clearance for r in bearing.rows], n, "radial_clearance")
        d0 = _per_case_row(axial_preload, [r.axial_preload for r in bearing.rows], n, "axial_preload")
        base, notes = bearing, []
    outside = ~np.all(np.isfinite(rL) & np.isfinite(d0), axis=1)
    own_rL = np.array([r.radial_clearance for r in base.rows])
    own_d0 = np.array([r.axial_preload for r in base.rows])
    # a case outside the model is not solved: any valid values in its tables
    table, valid = base.operating_table(np.where(outside[:, None], own_rL, rL), np.where(outside[:, None], own_d0, d0))
    outside |= ~valid
    return CaseOperating(base, table, (outside if outside.any() else None), notes, rL, d0)


def _per_case_row(value, own, n: int, name: str) -> np.ndarray:
    """(n, rows) float64 mm from one number, one per row or one per case and row (None: ``own``, the rows')."""
    rows = len(own)
    if value is None:
        return np.broadcast_to(np.asarray(own, dtype=float), (n, rows)).copy()
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0:
        arr = np.full((n, rows), float(arr))
    elif arr.ndim == 1 and arr.shape[0] == rows and not (n == rows and rows > 1):
        arr = np.broadcast_to(arr, (n, rows)).copy()
    elif arr.ndim == 1 and arr.shape[0] == n and rows == 1:
        arr = arr[:, None].copy()
    if arr.shape != (n, rows):
        raise validate.FieldError(name, f"must be one number, one per row ({rows}) or one per case and row "
                                  f"({n}, {rows}), in mm", show_value=False)
    if not np.all(np.isfinite(arr)):
        raise validate.FieldError(name, "must be finite numbers (mm)", show_value=False)
    return arr


def solve_many(bearing: Bearing, f, q0=None, method: str = "newton", rtol=None, max_iter=None,
               threads=None, speed=0.0, fixed=None, device: str = "cpu", radial_clearance=None,
               axial_preload=None, temperatures=None) -> SolveManyResult:
    """Solve many independent load cases in parallel.

    Parameters
    ----------
    f : array_like (N, 5)
        Loads (Fx, Fy, Fz, Mx, My) in N and N*mm.
    q0 : array_like (N, 5), optional
        Warm starts in mm and rad.
    threads : int, optional
        Numba threads for this call (default: NUMBA_NUM_THREADS).
    speed : float or array_like (N,)
        Shaft speed in rpm, one for all cases or one per case (default 0), as in :func:`solve`.
    fixed : dict, optional
        Degrees of freedom given as displacements, as in :func:`solve`; a value may be one number or N
        (one per case). f's entries there must be 0; the result's f holds the reactions.
    device : {"cpu", "cuda"}
        Where the cases run (default "cpu"). "cuda": the same kernels compiled for the GPU by numba-cuda,
        one case per GPU thread (fastbearing.engine.gpu; ``threads`` is then ignored); the results agree
        with the CPU's to rounding. Without numba-cuda, a CUDA driver or a GPU:
        fastbearing.engine.device.CudaUnavailable (a RuntimeError) naming what is missing.
    radial_clearance, axial_preload : float, (rows,) or (N, rows), optional
        Each case's own radial clearance rL and axial preload d0 per row in mm (a bearing without
        ``[bearing.mounting]``; None: the rows' own). A mounted bearing takes its cases' operating values from
        its fits at each case's ``speed`` and ``temperatures`` ({key: deg C, one or (N,)}: the
        ``[bearing.mounting]`` temperature keys). A case whose values fail the rows' checks gets the status
        ``outside_model`` and nan (:func:`case_operating`). CPU only for now.

    ``bearing``, ``method``, ``rtol`` and ``max_iter`` are as in :func:`solve`.
    Results do not depend on the thread count.

    Returns
    -------
    SolveManyResult
        Arrays over the N cases, in the order of ``f``: ``q`` (N, 5) in mm
        and rad; ``f`` (N, 5) the load reached at q in N and N*mm; ``K``
        (N, 5, 5) Kb in N/mm, N*mm/rad, N/rad; ``status`` (N,) int8 codes of
        :mod:`fastbearing.status`; ``iterations`` (N,) int32; ``residual``
        (N,) relative; ``evaluations`` (N,) int32 kernel calls; and
        ``converged`` (N,) bool. A case that does not converge is reported
        in ``status``, never raised; bad input raises ValueError as in
        :func:`solve` (and when ``q0`` has another number of cases than ``f``).
    """
    device = validate.choice(device, "device", DEVICES)
    loads = as_cases(f, "f", "Fx, Fy, Fz in N; Mx, My in N*mm")
    n = loads.shape[0]
    bearing, operating, outside = case_operating(bearing, n, case_speeds(speed, n), radial_clearance, axial_preload,
                                                 temperatures)[:3]
    held = boundary.parse_fixed(fixed, n, bearing=bearing)
    f_targets = boundary.targets(loads, held)
    opts = solver_settings(bearing, method, rtol, max_iter, held.mask)
    balls, speeds = speed_cases(bearing, speed, n)
    warm = q0 is not None
    if warm:
        q = as_cases(q0, "q0", "mm, rad")
        if q.shape[0] != n:
            raise ValueError(f"q0 must have the same number of cases as f ({n}), got {q.shape[0]}")
    else:
        q = np.zeros((n, 5))
    out = SolveManyResult(q, np.empty((n, 5)), np.empty((n, 5, 5)), np.empty(n, np.int8), np.empty(n, np.int32),
                          np.empty(n), np.empty(n, np.int32))
    solutions = Solutions(out.q, out.f, out.K, out.status, out.iterations, out.residual, out.evaluations)
    if outside is not None:
        f_targets = f_targets.copy()
        f_targets[outside] = np.nan  # not solved (nonfinite_input at once), then flagged below
    cases = CaseBlock(f_targets, np.zeros(0, np.int64), speeds, operating, None, solutions)
    if device == "cuda":
        from .engine.gpu import solve_sweep_cuda  # numba.cuda is imported only here

        solve_sweep_cuda(balls, cases, opts, warm)
        return out
    with num_threads(threads):
        solve_sweep(balls, cases, opts, warm, config.SWEEP_BLOCK)
    if outside is not None:
        out.status[outside] = st.OUTSIDE_MODEL
        out.q[outside] = out.f[outside] = out.K[outside] = np.nan
    return out


def stiffness_many(bearing: Bearing, q, threads=None, speed=0.0) -> tuple[np.ndarray, np.ndarray]:
    """f (N, 5) and Kb (N, 5, 5) at many displacements q (N, 5) in mm and rad, in parallel, at shaft
    ``speed`` (rpm, one or one per case). ValueError as :func:`stiffness` (naming the first such case)."""
    bearing = _operating(bearing, speed, many=True)
    q = as_cases(q, "q", "dx, dy, dz in mm; bx, by in rad")
    n = q.shape[0]
    balls, speeds = speed_cases(bearing, speed, n)
    f = np.empty((n, 5))
    K = np.empty((n, 5, 5))
    unsettled = np.zeros(n, dtype=np.bool_)
    with num_threads(threads):
        stiffness_sweep(q, f, K, balls, speeds, config.SWEEP_BLOCK, unsettled)
    if unsettled.any():  # said before any overflow: an unsettled ball may leave Kb non-finite
        i = int(np.flatnonzero(unsettled)[0])
        raise ValueError(f"q (case {i}): at {float(np.broadcast_to(speed, (n,))[i]):g} rpm some balls have no "
                         "equilibrium of their own at this displacement (status ball_equilibrium), so f and Kb "
                         "there are not the model's; a displacement-given load map flags such cases instead")
    _check_finite_result(f, K, "q")
    return f, K

