"""The balls' warm starts at speed as a strided view (issue 46, item 2).

On the GPU each thread's warm starts are its column ``spin[:, :, t]`` of an element-major array, so that the
threads of a warp touch neighbouring addresses (engine/gpu.py, ThreadRows). The kernels at speed index that
scratch by row and column only; here the CPU's kernels take such a view and must give, evaluation after
evaluation, what a contiguous scratch gives (to rounding), touching no other thread's column.
"""

from pathlib import Path

import numpy as np
import pytest

import fastbearing as fb
from fastbearing.engine.high_speed import new_warm, warm_rows
from fastbearing.engine.kernel import balls_at_speed
from fastbearing.engine.schema import WARM_LINEARISE

DATA = Path(fb.__file__).parent / "catalogue"


def _history(balls, qs, linearise):
    """f (N, N*mm) and Kb (N/mm, N*mm/rad, N/rad) and the warning bits at each q of ``qs`` (mm, rad), in order,
    with the ball set's own warm scratch carried from one evaluation to the next."""
    out = []
    balls.warm[WARM_LINEARISE, 0] = 1.0 if linearise else 0.0
    for q in qs:
        f, K = np.empty(5), np.empty((5, 5))
        warnings = balls_at_speed(q, balls.balls, balls.speed_table, balls.omega, balls.smoothing, f, K, None, None,
                                  None, balls.warm, balls.four_point)[2]
        out.append((f, K, warnings))
    return out


@pytest.mark.parametrize("name, speed, load", [("7014C-DB", 12000.0, [500.0, 0.0, 1000.0, 0.0, 0.0]),
                                               ("QJ210", 15000.0, [3000.0, 0.0, 2000.0, 0.0, 0.0])])
@pytest.mark.parametrize("linearise", [False, True])
def test_a_strided_warm_scratch_gives_the_contiguous_ones_results(name, speed, load, linearise):
    bearing = fb.load_bearing(DATA / f"{name}.toml")
    q = fb.solve(bearing, load, speed=speed).q
    rng = np.random.default_rng(3)
    qs = [q * (1.0 + 0.02 * rng.normal(size=5)) for _ in range(5)] + [q]  # a solve's iterates, then its answer
    plain = bearing.ball_set(speed=speed)
    n = plain.balls.shape[1]
    assert plain.warm.shape == (warm_rows(n), n) and plain.warm.flags.c_contiguous
    spin = np.zeros((warm_rows(n), n, 3))  # three threads' warm starts, element-major
    strided = plain._replace(warm=spin[:, :, 1])
    assert not strided.warm.flags.c_contiguous
    expected = _history(plain._replace(warm=new_warm(n)), qs, linearise)
    got = _history(strided, qs, linearise)
    for (f0, K0, w0), (f1, K1, w1) in zip(expected, got):
        # to rounding, not bit for bit: numba compiles the strided view's loops without the vector code of the
        # contiguous one (other rounding, as the GPU's), so only the last digits may move
        assert w0 == w1
        assert np.allclose(f1, f0, rtol=0.0, atol=1e-12 * np.abs(f0).max())
        assert np.allclose(K1, K0, rtol=0.0, atol=1e-12 * np.abs(K0).max())
    assert np.isfinite(got[-1][1]).all() and np.abs(got[-1][0] - load).max() < 1e-6 * max(map(abs, load))
    assert spin[:, :, 1].any() and not spin[:, :, 0].any() and not spin[:, :, 2].any()
