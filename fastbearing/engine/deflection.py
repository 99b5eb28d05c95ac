"""A contact's deflection from its signed approach d (mm): the contact law's max(d, 0), or the solver's
smooth form (d + sqrt(d^2 + eps^2))/2, which its fallback uses to remove the kink at first contact
(every contact then carries a little load, so Kb is never singular; eps -> 0 recovers max(d, 0)).

One definition for every element model: the quasi-static ball loop and the roller slices
(kernel.clamped_deflection, which picks the form by the smoothing's type, so the exact loop has no
branch) and the high-speed ball's races (eps as a number, 0 for the exact law).
"""

import math

from numba import njit

from ..config import ERROR_MODEL, KERNEL_FASTMATH


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def smoothed_deflection(d, eps):
    """(delta, d(delta)/dd) = ((d + sqrt(d^2 + eps^2))/2, (1 + d/sqrt(d^2 + eps^2))/2) for eps > 0 (mm)."""
    root = math.sqrt(d * d + eps * eps)
    return 0.5 * (d + root), 0.5 * (1.0 + d / root)


@njit(inline="always", fastmath=KERNEL_FASTMATH, error_model=ERROR_MODEL)
def deflection(d, eps):
    """(delta, d(delta)/dd): max(d, 0) and 1 for eps = 0 (the exact law), else :func:`smoothed_deflection`."""
    if eps > 0.0:
        return smoothed_deflection(d, eps)
    return max(d, 0.0), 1.0
