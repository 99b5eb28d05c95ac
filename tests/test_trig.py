"""The kernels' fast arc tangent (trig.py) against libm's, to 3 ulp over every quadrant and scale."""

import math

import numpy as np
import pytest
from numba import njit

from fastbearing.engine.trig import atan2


@njit
def _angles(y, x):
    out = np.empty_like(y)
    for i in range(y.shape[0]):  # the kernel's vectorised form of the loop
        out[i] = atan2(y[i], x[i])
    return out


def test_within_3_ulp_of_libm_in_every_quadrant_and_scale():
    rng = np.random.default_rng(0)
    n = 400_000
    y = rng.normal(size=n) * 10.0 ** rng.uniform(-8, 8, n)
    x = rng.normal(size=n) * 10.0 ** rng.uniform(-8, 8, n)
    # the reduction's seams: |y/x| near tan(pi/8), 1 and 1/tan(pi/8)
    seams = np.tan(np.pi / 8) * np.array([1.0, -1.0]), np.array([1.0, -1.0]), 1.0 / np.tan(np.pi / 8) * np.ones(2)
    s = np.concatenate(seams)[:, None] * (1.0 + np.linspace(-1e-12, 1e-12, 101))[None, :]
    y = np.concatenate([y, s.ravel(), -s.ravel()])
    x = np.concatenate([x, np.ones(s.size), -np.ones(s.size)])
    ref = np.arctan2(y, x)
    ulp = np.abs(_angles(y, x) - ref) / np.spacing(np.abs(ref))
    assert ulp.max() <= 3.0


@pytest.mark.parametrize("y, x", [(0.0, 1.0), (0.0, -1.0), (-0.0, -1.0), (1.0, 0.0), (-1.0, 0.0), (0.0, 0.0),
                                  (1.0, 1.0), (-1.0, -1.0), (1.0, -1.0), (1e-300, 1.0), (1.0, 1e-300)])
def test_special_points_are_exact(y, x):
    assert _angles(np.array([y]), np.array([x]))[0] == math.atan2(y, x)
