"""Solver status codes (int8), shared by the njit solver and the Python layer.

The low 4 bits hold the outcome; bits 4 and 5 are warning flags that may be
set on top of a converged outcome. Failure to converge is data, never an exception.
"""

CONVERGED = 0
#: f = 0 without preload: q = 0, f = 0, Kb = 0 is the exact answer.
UNLOADED = 1
ITERATION_LIMIT = 2
#: The load has a direction the bearing does not hold (a row of fewer than
#: three balls can leave one): the energy falls without end along it.
SINGULAR = 3
NONFINITE_INPUT = 4
#: The line search could not reduce the residual any further.
STALLED = 5
#: The residual reached the rounding floor of this case (the float64 sum of
#: the ball forces, or the resolution of q), which lies above rtol times the
#: target: q is as accurate as float64 allows, but not to rtol (tiny loads on
#: a preloaded bearing, say). Not converged; the residual says how close.
PRECISION_LIMIT = 6
#: f or Kb came out inf or nan (a displacement or load too large for float64).
NONFINITE_RESULT = 7
#: At speed: some ball's own equilibrium (centrifugal force, gyroscopic moment) did not settle at the
#: returned q, so f and Kb there are not the model's (high_speed.settle_ball).
BALL_EQUILIBRIUM = 8
#: A case that varies the bearing (its own fits, temperatures, speed or sampled tolerances) whose operating
#: clearance or preload falls outside the model's range (the rows' own checks: groove centres crossed, a
#: preload deflecting each ball by more than 10 % of A0): not solved, q, f and Kb nan.
OUTSIDE_MODEL = 9

#: Warning bit: at the solution a loaded ball's contact angle has the opposite
#: sign to its row's contact direction (the ring may have no shoulder there).
CONTACT_REVERSED = 16
#: Warning bit: at the solution a ball's deflection exceeds its row's ``deflection_limit`` (by default
#: where the Hertz pressure reaches 4200 N/mm^2 for a bearing given by its geometry, else 0.15 A0): the
#: equations are solved, but the model (small elastic contacts) no longer describes the bearing.
BEYOND_VALIDITY = 32
#: Both warning bits.
WARNING_MASK = CONTACT_REVERSED | BEYOND_VALIDITY
#: Kernel flag (never in a stored status): a ball at speed did not settle; the solver and the sweeps turn
#: it into the outcome BALL_EQUILIBRIUM.
BALL_UNSETTLED = 64
#: Kernel flag (never in a stored status): a ball at speed was linearised (high_speed.LINEAR_RTOL) inside a
#: solve, so f and Kb are first-order close to the model's; the solver evaluates again before converging.
BALL_LINEARISED = 128

OUTCOME_MASK = 15

NAMES = {
    CONVERGED: "converged",
    UNLOADED: "unloaded",
    ITERATION_LIMIT: "iteration_limit",
    SINGULAR: "singular",
    NONFINITE_INPUT: "nonfinite_input",
    STALLED: "stalled",
    PRECISION_LIMIT: "precision_limit",
    NONFINITE_RESULT: "nonfinite_result",
    BALL_EQUILIBRIUM: "ball_equilibrium",
    OUTSIDE_MODEL: "outside_model",
}


def outcome(status: int) -> int:
    """The outcome code with warning bits removed."""
    return int(status) & OUTCOME_MASK


#: Outcomes whose q, f and Kb are the answer (warning bits allowed on top).
CONVERGED_OUTCOMES = (CONVERGED, UNLOADED)


def is_converged(status: int) -> bool:
    """True for a converged or exactly unloaded solve (warnings allowed)."""
    return outcome(status) in CONVERGED_OUTCOMES


def converged_mask(status):
    """:func:`is_converged` of every element of an integer array of status codes."""
    import numpy as np

    return np.isin(np.asarray(status) & OUTCOME_MASK, CONVERGED_OUTCOMES)


def describe(status: int) -> str:
    """Readable name, e.g. ``"converged+contact_reversed"``."""
    name = NAMES.get(outcome(status), f"unknown({outcome(status)})")
    if int(status) & CONTACT_REVERSED:
        name += "+contact_reversed"
    if int(status) & BEYOND_VALIDITY:
        name += "+beyond_validity"
    return name
