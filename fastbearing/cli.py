"""Command line: ``fastbearing solve ...``.

Bad input gives a one-line error on stderr and exit code 2, never a traceback.
"""

from __future__ import annotations

import argparse
import json
import sys

import numpy as np

from .api import DISPLACEMENT_NAMES, LOAD_NAMES, solve, stiffness
from .bearing_file import load_bearing, preset_bearing, preset_names

EXIT_USAGE = 2

_K_UNITS = "N/mm among x, y, z; N*mm/rad among tx, ty; N/rad between the two"


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        if "expected one argument" in message:
            message += " (a value that starts with '-' must be attached with '=': --load=-1000,0,3000,0,0)"
        raise _UsageError(f"{self.prog}: {message}")


class _UsageError(Exception):
    pass


def _five_numbers(text: str, what: str) -> list[float]:
    parts = [p for p in text.replace(";", ",").split(",")]
    if len(parts) != 5:
        raise ValueError(f"{what} needs 5 comma-separated numbers, got {text!r}")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise ValueError(f"{what} needs 5 comma-separated numbers, got {text!r}") from None
    if not all(np.isfinite(values)):
        raise ValueError(f"{what} must be finite, got {text!r}")
    return values


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="fastbearing", description="Stiffness matrices of angular contact ball bearings "
                     "(Gunduz & Singh 2013). Units: N, mm, rad.")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    p = sub.add_parser("solve", help="Kb at one load or displacement", description=(
        "Full 5x5 stiffness matrix Kb at one operating point, given the load (solved for the displacement) "
        "or the displacement (direct substitution). Units: N, mm, rad. A value list that starts with a minus "
        "sign must be attached with '=': --load=-1000,0,3000,0,0"))
    which = p.add_mutually_exclusive_group(required=True)
    which.add_argument("--preset", choices=preset_names(), help="a shipped bearing (with --arrangement)")
    which.add_argument("--bearing", metavar="FILE.toml", help="a bearing file with a [bearing] table")
    p.add_argument("--arrangement", choices=["single", "DB", "DF", "DT"],
                   help="arrangement for --preset (default: the preset's own, DB for gunduz2013)")
    given = p.add_mutually_exclusive_group(required=True)
    given.add_argument("--load", metavar="Fx,Fy,Fz,Mx,My",
                       help="load on the inner ring at the bearing centre: N, N, N, N*mm, N*mm "
                            "(negative first value: --load=-1000,0,3000,0,0)")
    given.add_argument("--displacement", metavar="dx,dy,dz,bx,by",
                       help="inner-ring displacement at the bearing centre: mm, mm, mm, rad, rad "
                            "(negative first value: --displacement=-0.01,0,0.02,0,0)")
    p.add_argument("--method", choices=["newton", "broyden"], default="newton",
                   help="solver for --load (default newton)")
    p.add_argument("--json", action="store_true", help="print one JSON object (q, f, K, status, converged, "
                   "iterations, residual) on stdout")
    m = sub.add_parser("loadmap", help="Kb over a grid or table of loads or displacements, to HDF5",
                       description=(
                           "Compute a load map: Kb (and q, f, status, load distribution) at every case of the "
                           "[loadmap] grid of CONFIG.toml, streamed block by block into an HDF5 file that "
                           "xarray opens (engine h5netcdf). Units: N, mm, rad; moments N*mm. An interrupted run "
                           "(Ctrl-C, kill) keeps its finished blocks in OUT.h5.part: continue with --resume."))
    m.add_argument("config", metavar="CONFIG.toml", help="config with [bearing] and [loadmap] tables")
    m.add_argument("-o", "--output", metavar="OUT.h5", help="output file (default: CONFIG with suffix .h5)")
    m.add_argument("--threads", type=int, metavar="N",
                   help="worker threads (default: NUMBA_NUM_THREADS, all cores); results do not depend on it")
    m.add_argument("--resume", action="store_true", help="continue an interrupted run of the same config")
    m.add_argument("--overwrite", action="store_true", help="replace an existing output or unfinished run")
    m.add_argument("--no-progress", action="store_true", help="no progress bar even on a terminal")
    p = sub.add_parser("passage", help="ball-passage (time-varying) stiffness tables, to HDF5 (and CSV)",
                       description=(
                           "Rotate the ball set through one ball-pass period and tabulate Kb (and q) at every "
                           "cage position for each operating point of the [passage] table of CONFIG.toml, with the "
                           "mean, min, max, peak-to-peak variation (%% of mean) and Fourier harmonics of every "
                           "entry. Units: N, mm, rad; time s; frequency Hz."))
    p.add_argument("config", metavar="CONFIG.toml", help="config with [bearing] and [passage] tables")
    p.add_argument("-o", "--output", metavar="OUT.h5", help="output file (default: CONFIG with suffix .h5)")
    p.add_argument("--threads", type=int, metavar="N", help="worker threads (default: NUMBA_NUM_THREADS)")
    p.add_argument("--overwrite", action="store_true", help="replace existing output files")
    p.add_argument("--csv", action="store_true", help="also write OUT_point0000.csv ... (one per operating "
                   "point: cage angle in rad, time in s if a speed is given, the 15 independent Kb entries)")
    return parser


def _passage(args) -> int:
    from .passage import passage

    passage(args.config, args.output, threads=args.threads, overwrite=args.overwrite, csv_files=args.csv)
    return 0


def _loadmap(args) -> int:
    from .loadmap import loadmap

    try:
        loadmap(args.config, args.output, threads=args.threads, resume=args.resume, overwrite=args.overwrite,
                progress=False if args.no_progress else None)
    except KeyboardInterrupt:
        return 130
    return 0


def _bearing(args):
    if args.bearing:
        if args.arrangement:
            raise ValueError("--arrangement goes with --preset; a bearing file sets its own arrangement")
        return load_bearing(args.bearing)
    return preset_bearing(args.preset, args.arrangement)


def _table(result: dict) -> str:
    labels = ("x", "y", "z", "tx", "ty")
    K = np.asarray(result["K"])
    lines = [f"status: {result['status']}  iterations: {result['iterations']}  residual: {result['residual']:.2e}",
             "q (mm, mm, mm, rad, rad): " + "  ".join(f"{n}={v:.6g}" for n, v in zip(DISPLACEMENT_NAMES, result["q"])),
             "f (N, N, N, N*mm, N*mm): " + "  ".join(f"{n}={v:.6g}" for n, v in zip(LOAD_NAMES, result["f"])),
             "Kb (" + _K_UNITS + "):",
             "      " + "".join(f"{name:>14s}" for name in labels)]
    for name, row in zip(labels, K):
        lines.append(f"{name:>4s}  " + "".join(f"{v:14.6g}" for v in row))
    return "\n".join(lines)


def _solve(args) -> int:
    bearing = _bearing(args)
    if args.load is not None:
        result = solve(bearing, _five_numbers(args.load, "--load"), method=args.method).to_dict()
    else:
        q = _five_numbers(args.displacement, "--displacement")
        f, K = stiffness(bearing, q)
        result = {"q": [float(v) for v in q], "f": f.tolist(), "K": K.tolist(), "status": "direct",
                  "converged": True, "iterations": 0, "residual": 0.0}
    if args.json:
        print(json.dumps(result))
    else:
        print(_table(result))
    return 0 if result["converged"] else 1


def main(argv=None) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        return {"solve": _solve, "loadmap": _loadmap, "passage": _passage}[args.command](args)
    except (_UsageError, ValueError) as err:
        print(f"fastbearing: error: {err}" if not str(err).startswith("fastbearing") else str(err),
              file=sys.stderr)
        return EXIT_USAGE


if __name__ == "__main__":
    sys.exit(main())
