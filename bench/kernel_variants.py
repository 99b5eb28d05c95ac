"""Not a benchmark: the quasi-static kernel's cost per evaluation of the paper's 28-ball DB bearing in
each of the variants the solvers call: f and Kb, f and Kb with the per-ball record, f alone, f with the
record (ns, after a warm-up; quoted in bench/README.md, issue 16), at a planar q (the kernel sums the
mirror half) and at an off-plane one (every ball).

    python bench/kernel_variants.py
"""

import time

import numpy as np
from numba import njit

import fastbearing as fb
from fastbearing.engine.kernel import ball_loop

VARIANTS = ("f and Kb", "f, Kb and the record", "f alone", "f and the record")


@njit(_nrt=False)
def _evaluate(q, balls, f, K, ball_load, contact_angle, variant, reps):
    total = 0.0
    for _ in range(reps):
        q[0] += 1e-12  # a new point each time
        if variant == 0:
            out = ball_loop(q, balls, f, K, None, None)
        elif variant == 1:
            out = ball_loop(q, balls, f, K, ball_load, contact_angle)
        elif variant == 2:
            out = ball_loop(q, balls, f, None, None, None)
        else:
            out = ball_loop(q, balls, f, None, ball_load, contact_angle)
        total += out[0]
    return total


def main(reps=200_000):
    bearing = fb.Bearing.preset("gunduz2013", "DB")
    balls = bearing.ball_set()
    planar = fb.solve(bearing, [500.0, 0.0, 3000.0, 0.0, 2e4]).q.copy()
    off_plane = fb.solve(bearing, [500.0, 300.0, 3000.0, 5e3, 2e4]).q.copy()
    n = balls.balls.shape[1]
    f, K, ball_load, contact_angle = np.zeros(5), np.zeros((5, 5)), np.zeros(n), np.zeros(n)
    for where, q in (("planar q (the mirror half)", planar), ("off-plane q (every ball)", off_plane)):
        print(where)
        for v in range(4):
            _evaluate(q, balls, f, K, ball_load, contact_angle, v, 10)
        for v, name in enumerate(VARIANTS):
            t = time.perf_counter()
            _evaluate(q, balls, f, K, ball_load, contact_angle, v, reps)
            print(f"  {name:22s} {(time.perf_counter() - t) / reps * 1e9:6.1f} ns per evaluation ({n} balls)")


if __name__ == "__main__":
    main()
