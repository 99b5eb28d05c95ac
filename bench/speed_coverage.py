"""Honesty at speed on random cases: how many end converged, whether each converged case carries its load
evaluated afresh and by the independent Jones-Harris reference, and what the rest are (issue 33).

Not a timing benchmark: a measurement quoted in bench/README.md. Over the shipped 6305, 3306, 7014C and
3210 geometries as single rows and DB, DF, DT pairs (tests/test_high_speed.py's arrangements), every race
control and either ring turning: random loads from 10 N to 3 kN in any direction and moments to 30 N*m,
at speeds up to each bearing's speed limit (weighted towards it). The reference
(tests/test_high_speed.jones_harris_load, scipy ball by ball) checks about half the converged cases.

    python bench/speed_coverage.py [seed]      # default 0; about a minute
"""

import collections
import sys
import warnings
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from test_high_speed import _arrangements, jones_harris_load  # noqa: E402

import fastbearing as fb  # noqa: E402
from fastbearing import status as st  # noqa: E402
from fastbearing.model.bearing import speed_limit  # noqa: E402

DATA = Path(__file__).resolve().parents[1] / "fastbearing" / "catalogue"


def random_cases(rng, n):
    """(n, 5) loads: forces 10 N .. 3 kN (axial mostly positive), moments 100 N*mm .. 30 N*m."""
    return np.column_stack([rng.uniform(-1, 1, (n, 2)) * 10 ** rng.uniform(1, 3.5, (n, 1)),
                            rng.uniform(-0.3, 1, n) * 10 ** rng.uniform(1, 3.5, n),
                            rng.uniform(-1, 1, (n, 2)) * 10 ** rng.uniform(2, 4.5, (n, 1))])


def main(seed: int) -> None:
    warnings.simplefilter("ignore", RuntimeWarning)
    rng = np.random.default_rng(seed)
    counts = collections.Counter()
    wrong = []
    checked = 0
    for name in ("6305", "3306", "7014C-DB", "3210"):
        base = fb.load_bearing(DATA / f"{name}.toml").geometry
        for control in ("outer", "inner", "none"):
            for rotating in ("inner", "outer"):
                for arrangement, b in _arrangements(replace(base, race_control=control, rotating=rotating)).items():
                    loads = random_cases(rng, 6)
                    speeds = rng.uniform(0.0, 1.0, 6) ** 0.5 * speed_limit(b)
                    out = fb.solve_many(b, loads, speed=speeds, threads=2)
                    L = b.rows[0].pitch_radius
                    scale = np.array([1, 1, 1, 1 / L, 1 / L])
                    for i in range(6):
                        if not out.converged[i]:
                            note = bool(fb.solve(b, loads[i], speed=speeds[i]).note)
                            counts[f"{st.NAMES[out.status[i] & 15]} ({control} control{', noted' if note else ''})"] += 1
                            continue
                        counts["converged"] += 1
                        size = np.abs(loads[i] * scale).max()
                        afresh = np.abs((fb.stiffness(b, out.q[i], speed=speeds[i])[0] - loads[i]) * scale).max()
                        if afresh > 1e-8 * size:
                            wrong.append((name, control, rotating, arrangement, speeds[i], "afresh", afresh / size))
                        if rng.uniform() < 0.5:
                            checked += 1
                            ref = np.abs((jones_harris_load(b, out.q[i], speeds[i]) - loads[i]) * scale).max()
                            if ref > 1e-7 * size:
                                wrong.append((name, control, rotating, arrangement, speeds[i], "reference", ref / size))
    for key, n in sorted(counts.items()):
        print(f"{n:5d}  {key}")
    print(f"converged cases checked against the reference: {checked}; converged but off: {len(wrong)}")
    for w in wrong:
        print("  ", w)


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 0)
