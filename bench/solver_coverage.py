"""Solver coverage on hard random loads: how many cases end converged, at the precision limit, or not at all.

Not a timing benchmark: a measurement of the solver's reach, quoted in the
README. Uses the test suite's hard-load generator (tests/test_hard_loads.py)
on every arrangement of the paper's bearing with clearance, axial and radial
preload, 85 degree contact angles and the line-contact exponent 10/9.

    python bench/solver_coverage.py [cases_per_config]      # default 2000
"""

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from test_hard_loads import hard_loads  # noqa: E402

import fastbearing as fb  # noqa: E402
from fastbearing import status as st  # noqa: E402

VARIANTS = {"plain": {}, "clearance 0.01 mm": {"radial_clearance": 0.01},
            "radial preload -0.005 mm": {"radial_clearance": -0.005},
            "axial preload 0.01 mm": {"axial_preload": 0.01}, "85 deg": {"contact_angle": 85.0},
            "n = 10/9": {"exponent": 10 / 9}}


def main(n: int) -> None:
    rng = np.random.default_rng(2026)
    totals: dict[str, int] = {}
    print("| arrangement | variant | cases | converged | precision_limit | other | largest precision_limit load (N) "
          "| mean iterations | us/case |")
    print("|---|---|---|---|---|---|---|---|---|")
    for arrangement in ("single", "DB", "DF", "DT"):
        for name, extra in VARIANTS.items():
            if arrangement == "single" and "axial preload" in name:
                continue
            bearing = fb.Bearing.preset("gunduz2013", arrangement, **extra)
            loads = hard_loads(rng, n)
            fb.solve_many(bearing, loads[:2])                       # compile outside the timing
            t = time.perf_counter()
            r = fb.solve_many(bearing, loads, threads=1)
            dt = time.perf_counter() - t
            outcome = r.status & st.OUTCOME_MASK
            conv = int(np.sum(outcome == st.CONVERGED))
            prec = int(np.sum(outcome == st.PRECISION_LIMIT))
            other = n - conv - prec
            for key, v in (("cases", n), ("converged", conv), ("precision_limit", prec), ("other", other)):
                totals[key] = totals.get(key, 0) + v
            D = np.array([1, 1, 1, 1 / bearing.length_scale, 1 / bearing.length_scale])
            scale = np.abs(loads * D).max(axis=1)                 # the load, moments as forces at length_scale
            worst = scale[outcome == st.PRECISION_LIMIT].max(initial=0.0)
            print(f"| {arrangement} | {name} | {n} | {conv} | {prec} | {other} | {worst:.3g} | "
                  f"{r.iterations.mean():.1f} | {dt / n * 1e6:.1f} |")
    c = totals["cases"]
    print(f"\nall: {c} cases, converged {totals['converged'] / c:.2%}, precision_limit "
          f"{totals['precision_limit'] / c:.2%}, other {totals['other']}")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 2000)
