"""The reference peer: what a careful engineer writes without fastbearing.

scipy.optimize.root(method="hybr") (MINPACK's Powell hybrid method) with the
analytic Jacobian, and the residual f(q) - f_target vectorised over balls
with numpy. Same physics as fastbearing (docs/model.md, "Per ball (row r,
ball j at azimuth psi)"), written independently from the ball table. This is
a speed baseline, not a correctness reference; the benchmark checks that its
answers agree with fastbearing's. Units: N, mm, rad.
"""

import numpy as np
from scipy.optimize import root


def load_and_stiffness(q, table):
    """f (5,) and Kb (5,5) at q, vectorised over the balls of a column-major ball table."""
    c, s, z, R, ur0, uz0, A0, Kn, n = table[:9]
    ur = (q[0] + z * q[4]) * c + (q[1] - z * q[3]) * s + ur0
    uz = q[2] + R * (q[3] * s - q[4] * c) + uz0
    A = np.hypot(ur, uz)
    delta = np.maximum(A - A0, 0.0)
    Q = Kn * delta ** n
    dQ = n * Kn * delta ** (n - 1.0)
    zeros = np.zeros_like(c)
    a = np.stack([c, s, zeros, -z * s, z * c], 1)  # d(ur)/dq
    b = np.stack([zeros, zeros, np.ones_like(c), R * s, -R * c], 1)  # d(uz)/dq
    g = Q / A
    f = (g * ur) @ a + (g * uz) @ b
    hr, hz = ur / A, uz / A
    h11, h12, h22 = g + (dQ - g) * hr * hr, (dQ - g) * hr * hz, g + (dQ - g) * hz * hz
    K = (a.T * h11) @ a + (a.T * h12) @ b + (b.T * h12) @ a + (b.T * h22) @ b
    return f, K


def solve(table, f_target, length_scale, q0=None):
    """q with f(q) = f_target via scipy's hybr on a residual scaled like fastbearing's (moments / R).

    Starts from a small displacement along the load (q = 0 gives Kb = 0).
    Returns (q, converged).
    """
    D = np.array([1.0, 1.0, 1.0, 1.0 / length_scale, 1.0 / length_scale])
    f_target = np.asarray(f_target, dtype=float)

    def residual(p):
        f, K = load_and_stiffness(p * D, table)
        return (f - f_target) * D, (K * D[:, None] * D[None, :])

    if q0 is None:
        direction = f_target * D / np.abs(f_target * D).max()
        p0 = 0.01 * direction
    else:
        p0 = np.asarray(q0) / D
    sol = root(residual, p0, jac=True, method="hybr", options={"xtol": 1e-12})
    return sol.x * D, bool(sol.success)
