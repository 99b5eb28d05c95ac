"""Solver status codes (int8), shared by the njit solver and the Python layer.

The low 4 bits hold the outcome; bit 4 is a warning flag that may be set on
top of a converged outcome. Failure to converge is data, never an exception.
"""

CONVERGED = 0
#: f = 0 without preload: q = 0, f = 0, Kb = 0 is the exact answer.
UNLOADED = 1
ITERATION_LIMIT = 2
#: Kb has no usable direction (no loaded ball) and no progress is possible.
SINGULAR = 3
NONFINITE_INPUT = 4
#: The line search could not reduce the residual any further.
STALLED = 5

#: Warning bit: at the solution a loaded ball's contact angle has the opposite
#: sign to its row's contact direction (the ring may have no shoulder there).
CONTACT_REVERSED = 16

OUTCOME_MASK = 15

NAMES = {
    CONVERGED: "converged",
    UNLOADED: "unloaded",
    ITERATION_LIMIT: "iteration_limit",
    SINGULAR: "singular",
    NONFINITE_INPUT: "nonfinite_input",
    STALLED: "stalled",
}


def outcome(status: int) -> int:
    """The outcome code with warning bits removed."""
    return int(status) & OUTCOME_MASK


def is_converged(status: int) -> bool:
    """True for a converged or exactly unloaded solve (warnings allowed)."""
    return outcome(status) in (CONVERGED, UNLOADED)


def describe(status: int) -> str:
    """Readable name, e.g. ``"converged+contact_reversed"``."""
    name = NAMES.get(outcome(status), f"unknown({outcome(status)})")
    if int(status) & CONTACT_REVERSED:
        name += "+contact_reversed"
    return name
