"""The kernels' fast roots (roots.py) against numpy's, to a few ulp over the whole range they meet."""

import numpy as np
from numba import njit

from fastbearing.engine.roots import cube_root, ninth_root


@njit
def _cube_roots(x):
    return np.array([cube_root(v) for v in x])


@njit
def _ninth_roots(x):
    out = np.empty_like(x)
    for i in range(x.shape[0]):  # the kernel's vectorised form of the loop
        out[i] = ninth_root(x[i])
    return out


def test_cube_root_is_exact_to_a_few_ulp():
    x = np.geomspace(1e-12, 1e12, 2001)
    np.testing.assert_allclose(_cube_roots(x), np.cbrt(x), rtol=1e-15, atol=0)  # within about 4 ulp


def test_ninth_root_is_exact_to_a_few_ulp_from_1e_minus_40_to_1e20():
    """Deflections in mm from the solver's smoothing floor to absurd: random decades and every power of 2
    (the guess's worst cases sit at the mantissa's ends)."""
    rng = np.random.default_rng(0)
    x = np.concatenate([10.0 ** rng.uniform(-40, 20, 200_000), 2.0 ** np.arange(-130, 66),
                        np.nextafter(2.0 ** np.arange(-130, 66), 0)])
    np.testing.assert_allclose(_ninth_roots(x), x ** (1.0 / 9.0), rtol=1.2e-15, atol=0)
