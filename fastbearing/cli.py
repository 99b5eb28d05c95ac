"""Command line: ``fastbearing solve | bearing | loadmap | passage | plot | paper ...``.

Bad input gives a one-line error on stderr and exit code 2, never a traceback.
"""

from __future__ import annotations

import argparse
import errno
import importlib.util
import json
import math
import sys
import warnings

import numpy as np

from .boundary import parse_fix_option
from .validate import FieldError
from .model.bearing import ARRANGEMENTS, preset_names
from .model.bearing_file import load_bearing, preset_bearing
from .model.mounted import operating_bearing
from .config import METHODS
from .dofs import DISPLACEMENT_NAMES, LOAD_NAMES
from .report.export import FORMATS as EXPORT_FORMATS
from .files import DiskFull, OutputExists
from .jobs.warmup import FAMILIES as WARMUP_FAMILIES
from .report.plot import NORMALISE, PASSAGE_X

EXIT_USAGE = 2

_BEARING_HELP = "a shipped bearing by name (fastbearing bearings lists them) or a bearing file"

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


def _finite_or_none(value):
    """JSON has no nan or inf: write them as null."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _finite_or_none(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite_or_none(v) for v in value]
    return value


def json_text(obj) -> str:
    """Strict JSON (non-finite numbers as null) for every --json output."""
    return json.dumps(_finite_or_none(obj), allow_nan=False)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="fastbearing", description=(
        "Stiffness matrices (5x5 Kb) of rolling bearings: deep-groove, angular contact (single, DB, DF, DT) and "
        "four-point ball bearings, cylindrical and tapered roller bearings (TDO, TDI), at rest and at shaft speed; "
        "load maps of millions of cases, ball-passage tables, defects and fault frequencies, ISO 281 life, shafts "
        "on several bearings, mounting, and exports to Nastran DMIG, ROSS and CSV. Units: N, mm, rad."))
    from . import __version__

    parser.add_argument("--version", action="version", version=f"fastbearing {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser,
                                title="commands (fastbearing COMMAND --help for each)")
    p = sub.add_parser("solve", help="Kb at one load or displacement", description=(
        "Full 5x5 stiffness matrix Kb at one operating point, given the load (solved for the displacement) "
        "or the displacement (direct substitution). Units: N, mm, rad. A value list that starts with a minus "
        "sign must be attached with '=': --load=-1000,0,3000,0,0"))
    which = p.add_mutually_exclusive_group(required=True)
    which.add_argument("--preset", choices=preset_names(), help="a shipped bearing (with --arrangement)")
    which.add_argument("--bearing", metavar="NAME|FILE.toml", help=_BEARING_HELP)
    p.add_argument("--arrangement", choices=ARRANGEMENTS,
                   help="arrangement for --preset (default: the preset's own, DB for gunduz2013)")
    given = p.add_mutually_exclusive_group(required=True)
    given.add_argument("--load", metavar="Fx,Fy,Fz,Mx,My",
                       help="load on the inner ring at the bearing centre: N, N, N, N*mm, N*mm "
                            "(negative first value: --load=-1000,0,3000,0,0)")
    given.add_argument("--displacement", metavar="dx,dy,dz,bx,by",
                       help="inner-ring displacement at the bearing centre: mm, mm, mm, rad, rad "
                            "(negative first value: --displacement=-0.01,0,0.02,0,0)")
    p.add_argument("--fix", metavar="NAME=VALUE,...",
                   help="with --load, degrees of freedom given as displacements, e.g. bx=0,by=0 (dx, dy, dz in mm; "
                   "bx, by in rad): the ring is held there and the load entries there, which must be 0, become "
                   "the reactions (reported in f); any subset but all five")
    p.add_argument("--method", choices=list(METHODS), default="newton",
                   help="solver for --load (default newton)")
    p.add_argument("--json", action="store_true", help="print one JSON object (q, f, K, status, converged, "
                   "iterations, residual; with --balls also balls) on stdout")
    p.add_argument("--balls", action="store_true", help="also report every ball: azimuth, deflection, load Q, "
                   "contact angle and, for a bearing with [bearing.geometry], the maximum Hertz pressure and "
                   "contact-ellipse semi-axes at the inner and outer race")
    p.add_argument("--life", action="store_true", help="also the rating life (needs [bearing.geometry]): C, P, "
                   "L10 (ISO 281) and L10r (ISO/TS 16281, from the load distribution) per row and for the "
                   "bearing, in million revolutions; static safety S0")
    p.add_argument("--speed", type=float, metavar="RPM", default=0.0,
                   help="shaft speed in rpm (default 0): above 0 the high-speed model (centrifugal force, "
                   "gyroscopic moment; needs [bearing.geometry]) and, with --balls, each ball's inner and outer "
                   "contact angle (rad) and load (N), centrifugal force (N), gyroscopic moment (N*mm) and "
                   "orbital speed (rad/s); with --life, lives also in hours")
    p.add_argument("--rotating", choices=["inner", "outer"], default="inner",
                   help="the ring rotating relative to the load, for --life (default inner)")
    p.add_argument("--kappa", type=float, metavar="K", help="viscosity ratio kappa in [0.1, 4] for --life: "
                   "adds the ISO 281 life-modification factor a_ISO and L_nmr = a_ISO L10r")
    p.add_argument("--contamination", type=float, metavar="EC", default=1.0,
                   help="contamination factor e_C in [0, 1] for --kappa (default 1: very clean)")
    b = sub.add_parser("bearing", help="derived model parameters of a bearing file (Kn, A0, R, rL, ...)",
                       description=(
                           "Print a bearing file's model parameters with units: Hertz constant Kn, groove-centre "
                           "distance A0, inner groove-centre radius R, radial clearance rL, unloaded and free "
                           "contact angles, load-centre spread E of double rows, and for a [bearing.geometry] "
                           "table the catalogue inputs and both race contacts. With --speed, also the fault "
                           "frequencies (FTF, BPFO, BPFI, BSF, ball defect = 2 BSF) in Hz and as orders of the "
                           "shaft speed, from the geometry's ball and pitch diameters and contact angle."))
    b.add_argument("file", metavar="NAME|FILE.toml", help=_BEARING_HELP)
    b.add_argument("--json", action="store_true", help="print one JSON object on stdout (with --speed: the fault "
                   "frequencies under fault_frequencies, name -> {hz, order}, and what they assume under "
                   "fault_frequency_conditions)")
    b.add_argument("--speed", type=float, metavar="RPM", help="shaft speed in rpm (> 0): add the fault frequencies "
                   "(Hz, and orders of the shaft frequency rpm/60); needs [bearing.geometry]; the ring that turns is "
                   "the geometry's rotating key (default inner); with [bearing.mounting], the clearance budget at this "
                   "speed (mm, N/mm^2, deg C; default 0 rpm)")
    b.add_argument("--load", metavar="Fx,Fy,Fz,Mx,My", help="with --speed: use the loaded contact angle at this load "
                   "on the inner ring (N, N, N, N*mm, N*mm; the mean over the loaded balls of a quasi-static solve) "
                   "instead of the nominal one")
    c = sub.add_parser("bearings", help="the shipped bearings: type, d x D x B (mm), C, C0 (N) and where each "
                       "comes from", description=(
                           "List the bearings shipped with fastbearing (fastbearing/catalogue/NAME.toml): name, "
                           "type, nominal contact angle (deg), boundary dimensions d x D x B (mm), basic load "
                           "ratings C and C0 (N), and where each number comes from (the catalogue, or ISO 281 / "
                           "ISO 76 from the file's geometry). Give a NAME wherever a bearing file is asked for: "
                           "--bearing NAME, fastbearing bearing NAME, bearing = \"NAME\" in a config."))
    c.add_argument("--json", action="store_true", help="print one JSON list, an object per bearing (name, type, "
                   "element, arrangement, contact_angle_deg, bore, outer_diameter, width in mm, C, C0 in N, "
                   "sources, units, file)")
    m = sub.add_parser("loadmap", help="Kb over a grid or table of loads or displacements, to HDF5 or zarr",
                       description=(
                           "Compute a load map: Kb (and q, f, status, load distribution) at every case of the "
                           "[loadmap] grid of CONFIG.toml, streamed block by block into an HDF5 file that "
                           "xarray opens (engine h5netcdf), or into a zarr v3 store (-o OUT.zarr or a URL; "
                           "xarray.open_zarr). Units: N, mm, rad; moments N*mm. An interrupted run "
                           "(Ctrl-C, kill) keeps its finished blocks (in OUT.h5.part, or in the store): continue "
                           "with --resume."))
    m.add_argument("config", metavar="CONFIG.toml", help="config with [bearing] and [loadmap] tables")
    _add_job_arguments(m)
    mc = sub.add_parser("montecarlo", help="tolerance zones sampled: every sample's operating clearance and Kb, "
                        "to HDF5 or zarr, with percentiles and sensitivities",
                        description=(
                            "Draw the tolerance zones of the [bearing.mounting] of CONFIG.toml (shaft and housing "
                            "fit classes: ISO 286-2 shaft and housing deviations, ISO 492 Normal ring bore and OD; "
                            "a clearance group or range) uniformly and independently, [montecarlo] samples of "
                            "them, and solve each sample at its own operating clearance and preload under the "
                            "[montecarlo] load (Fx, Fy, Fz in N; Mx, My in N*mm), speed (rpm) and temperatures "
                            "(deg C). Stores each sample's inputs (mm), operating_diametral_clearance and "
                            "operating_axial_preload (mm), q, f, Kb, status and lives; prints the percentiles "
                            "(1, 5, 50, 95, 99) of the operating clearance, kxx, kzz and L10r, P(operating "
                            "clearance < 0) and the rank correlation of each input with each output. The same "
                            "seed gives the same file bit for bit; an interrupted run continues with --resume."))
    mc.add_argument("config", metavar="CONFIG.toml", help="config with [bearing] (and [bearing.mounting]) and "
                    "[montecarlo] tables")
    _add_job_arguments(mc)
    mc.add_argument("--json", action="store_true", help="print the summary as one JSON object (units in the keys)")
    p = sub.add_parser("passage", help="ball-passage (time-varying) stiffness tables, to HDF5 or zarr (and CSV)",
                       description=(
                           "Rotate the ball set through one ball-pass period and tabulate Kb (and q) at every "
                           "cage position for each operating point of the [passage] table of CONFIG.toml, with the "
                           "mean, min, max, peak-to-peak variation (% of mean) and Fourier harmonics of every "
                           "entry, into an HDF5 file or a zarr v3 store (-o OUT.zarr or a URL). Units: N, mm, rad; "
                           "time s; frequency Hz. An interrupted run (Ctrl-C, kill) keeps its finished blocks (in "
                           "OUT.h5.part, or in the store): continue with --resume."))
    p.add_argument("config", metavar="CONFIG.toml", help="config with [bearing] and [passage] tables")
    _add_job_arguments(p)
    p.add_argument("--csv", action="store_true", help="also write OUT_point0000.csv ... beside the output and "
                   "named after it, one per operating point, as export --format csv writes them: the point's inputs "
                   "(N, N*mm or mm, rad), position, cage angle (rad), time (s) with a speed, status, all 25 Kb "
                   "entries (kxx_N_per_mm ...)")
    _add_plot_parsers(sub)
    r = sub.add_parser("paper", help="recompute Gunduz & Singh (2013): Figs. 6-14 (PNG) and a report",
                       description=(
                           "Recompute the paper's Figs. 6-14 and Tables 2-4 with fastbearing and write "
                           "fig06.png ... fig14.png and report.md (the paper's tables beside fastbearing's, "
                           "with % differences and notes where the paper is wrong) into DIR. Needs matplotlib "
                           "(pip install 'fastbearing[plot]')."))
    r.add_argument("--out", required=True, metavar="DIR", help="output folder (created if missing)")
    r.add_argument("--overwrite", action="store_true", help="replace existing figures and report")

    sh = sub.add_parser("shaft", help="a rigid shaft on several bearings: equilibrium, K_system, frequencies",
                        description=(
                            "Solve the statically indeterminate equilibrium of a rigid shaft on the bearings of "
                            "the [shaft] table of CONFIG.toml under its loads; print the shaft displacement and "
                            "system stiffness at the reference point, and each bearing's reaction, displacement "
                            "and Kb about its centre. With [shaft.mass], also the natural frequencies with the "
                            "full Kb and with its diagonal only. Units: N, mm, rad; kg, kg*mm^2; Hz."))
    sh.add_argument("config", metavar="CONFIG.toml", help="config with a [shaft] table")
    sh.add_argument("--json", action="store_true", help="print one JSON object (q, K_system, bearings, "
                    "frequencies)")
    sh.add_argument("--method", choices=list(METHODS), default="newton", help="solver (default newton)")
    sh.add_argument("--life", action="store_true", help="each bearing's rating life at its reaction and the "
                    "system's (weakest link), million revolutions; needs [bearing.geometry] in every bearing")
    sh.add_argument("--speed", type=float, metavar="RPM", help="shaft speed in rpm (default: [shaft] speed, else "
                    "0): above 0 every bearing's balls run the high-speed model (centrifugal force, gyroscopic "
                    "moment; needs [bearing.geometry]); with --life the lives in hours too")
    ex = sub.add_parser("export", help="write Kb for other tools: csv, json, npz, Nastran DMIG, ROSS",
                        description=(
                            "Export Kb from a `solve --json` or `shaft --json` output (.json) or from a load map "
                            "or ball-passage file (.h5). DOF order x, y, z, tx, ty (z: the shaft axis); units N, mm, "
                            "rad: Kb in N/mm, N*mm/rad, N/rad (ROSS: SI, N/m). A shaft's output holds several "
                            "matrices: pick one bearing's Kb with --bearing or the shaft's K_system with --system; "
                            "every output says which matrix it holds. csv/json/npz take every case of a file, "
                            "each with its coordinates (Fx ... My or dx ... by, with units) and status (code and "
                            "name), a map's lives and a solve's load and speed; CSV column names end in their "
                            "units (Fx_N, kxx_N_per_mm, L10r_million_revolutions) under one header row. dmig and "
                            "ross take one case (--case, the flat case index, or --at, the nearest grid point) and "
                            "record it with the source file; --over AXIS takes a map's Kb along one axis (ross: "
                            "--over speed, ROSS's coefficients over frequency in rad/s)."))
    ex.add_argument("source", metavar="SOURCE", help="a .json from solve/shaft --json, or a .h5 map or table, or a .zarr store")
    ex.add_argument("--format", required=True, choices=EXPORT_FORMATS, help="output format")
    ex.add_argument("-o", "--output", required=True, metavar="OUT", help="output file")
    ex.add_argument("--case", type=int, default=None, metavar="N", help="flat case index in a .h5 source")
    ex.add_argument("--at", metavar="AXIS=VALUE,...", default=None,
                    help="the case of a .h5 source nearest to these coordinates, every varying axis named in "
                         "its units (N, N*mm; mm, rad), e.g. --at Fx=1000,Fz=3000,My=0; a table's own dims "
                         "by index: --at point=3,position=0; a value outside an axis' range is refused")
    ex.add_argument("--over", metavar="AXIS", default=None,
                    help="a map (.h5, .zarr): Kb along this axis, every other varying axis fixed with --at in "
                         "its units; --format ross takes --over speed: kxx, kxy, kyx, kyy, kzz (N/m) as lists over "
                         "frequency (the speeds in rad/s), ROSS's frequency-dependent BearingElement; csv, json "
                         "and npz take any axis")
    ex.add_argument("--bearing", default=None, metavar="NAME|N",
                    help="shaft --json source: export this bearing's own Kb (about its centre; N/mm, N*mm/rad, "
                         "N/rad), by its name or its index in the JSON's bearings list")
    ex.add_argument("--system", action="store_true",
                    help="shaft --json source: export the shaft's system stiffness K_system at its reference "
                         "point (N/mm, N*mm/rad, N/rad) instead of one bearing's Kb")
    ex.add_argument("--grid", type=int, default=1, metavar="ID",
                    help="DMIG: grid of the inner ring (default 1); it must sit at the bearing centre (for "
                         "--system: the shaft's reference point) with z along the shaft axis")
    ex.add_argument("--ground-grid", type=int, default=None, metavar="ID",
                    help="DMIG: second grid (outer ring); writes the 10x10 spring between the two, which holds "
                         "only for coincident grids")
    ex.add_argument("--name", default="KBRG", help="DMIG matrix name (default KBRG)")
    ex.add_argument("--node", type=int, default=0, metavar="N", help="ROSS: shaft node of the bearing")
    ex.add_argument("--overwrite", action="store_true", help="replace an existing output file")
    w = sub.add_parser("warmup", help="compile the kernels now, so that later commands load them from the cache",
                       description=(
                           "Compile every kernel family the command line and the API reach (or those of --kinds) "
                           "into numba's cache, on tiny inputs built into the package, showing each family and "
                           "the time elapsed; later commands and Dask workers on this machine (or image) then "
                           "load instead of compiling. --portable LEVEL --into DIR builds the cache for a CPU "
                           "level (e.g. x86-64-v3) in DIR, for processes run with NUMBA_CPU_NAME=LEVEL, "
                           "NUMBA_CPU_FEATURES= and NUMBA_CACHE_DIR=DIR. Units: N, mm, rad."))
    w.add_argument("--kinds", metavar="FAMILY,...", default=None, help="only these kernel families (comma-separated; "
                   "default all): " + ", ".join(WARMUP_FAMILIES))
    w.add_argument("--portable", metavar="LEVEL", default=None, help="compile for this CPU level (an LLVM CPU name: "
                   "x86-64-v3 needs AVX2 and FMA, x86-64-v4 AVX-512) instead of this machine's CPU; needs --into")
    w.add_argument("--into", metavar="DIR", default=None, help="with --portable: the cache folder to build")
    return parser


def _add_job_arguments(parser) -> None:
    """The options every job (loadmap, passage) shares: output and its format, threads, resume, Dask."""
    parser.add_argument("-o", "--output", metavar="OUT.h5",
                        help="output: an HDF5 file, or a zarr v3 store for a name ending in .zarr or any fsspec URL "
                        "(s3://bucket/map.zarr ...; needs pip install 'fastbearing[zarr]') (default: CONFIG's name "
                        "with suffix .h5, or .zarr with --format zarr, in the current folder)")
    parser.add_argument("--format", choices=("hdf5", "zarr"), help="output format (default: from -o's name; "
                        "HDF5 without -o); with --dask, zarr stores are written by the workers themselves")
    parser.add_argument("--threads", type=int, metavar="N",
                        help="worker threads (default: NUMBA_NUM_THREADS, all cores); results do not depend on it")
    parser.add_argument("--resume", action="store_true", help="continue an interrupted run of the same config")
    parser.add_argument("--overwrite", action="store_true", help="replace existing output or an unfinished run")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar even on a terminal")
    parser.add_argument("--dask", metavar="SPEC", help="run the blocks on Dask: local:N (a LocalCluster of N "
                        "single-threaded worker processes) or tcp://HOST:PORT (a running scheduler); the output is "
                        "identical to a local run (needs pip install 'fastbearing[dask]')")
    parser.add_argument("--in-flight", type=int, metavar="N", help="with --dask: blocks out on the cluster at once "
                        "(default 2 per worker thread)")
    parser.add_argument("--device", choices=("cpu", "cuda"), default="cpu",
                        help="where the blocks are computed: cpu (default, all cores) or cuda (one NVIDIA GPU, the "
                        "same kernels through numba-cuda; needs pip install 'fastbearing[cuda]')")


def _run_job(run, args, **extra) -> int:
    """Run a job function (loadmap, passage) with the shared options; Ctrl-C is exit 130."""
    from .api import check_threads
    from .jobs.runner import check_in_flight

    check_threads(args.threads)
    check_in_flight(args.in_flight, "--in-flight")
    client = cluster = None
    if args.dask:
        if args.threads is not None:
            raise ValueError("--threads is for local runs; with --dask each worker task uses one thread")
        from .jobs.distributed import client_for

        client, cluster = client_for(args.dask)
    elif args.in_flight is not None:
        raise ValueError("--in-flight goes with --dask")
    output = _job_output(args)
    try:
        run(args.config, output, threads=args.threads, resume=args.resume, overwrite=args.overwrite,
            progress=False if args.no_progress else None, client=client, max_in_flight=args.in_flight, **extra)
    except KeyboardInterrupt:
        return 130
    finally:
        if client is not None:
            client.close()
        if cluster is not None:
            cluster.close()
    return 0


def _job_output(args):
    """-o as given, checked against --format; without -o and with --format zarr, CONFIG's name with .zarr."""
    from .jobs.zarr_store import is_zarr_location

    if args.format is None:
        return args.output
    if args.output is None:
        from pathlib import Path

        return Path(Path(args.config).name).with_suffix(".zarr") if args.format == "zarr" else None
    if (args.format == "zarr") != is_zarr_location(args.output):
        raise ValueError(f"--format {args.format} does not match -o {args.output}: a zarr store's name ends in .zarr "
                         "(or is a URL); an HDF5 file's does not")
    return args.output


def _size(text: str) -> tuple[int, int]:
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise ValueError(f"--size must be WIDTHxHEIGHT in pixels, e.g. 800x560, got {text!r}") from None
    return w, h


def _at(text: str | None) -> dict:
    """--at Fz=1000,My=0 -> {"Fz": 1000.0, "My": 0.0}."""
    out = {}
    for part in _names(text or ""):
        name, _, value = part.partition("=")
        try:
            out[name.strip()] = float(value)
        except ValueError:
            raise ValueError(f"--at needs NAME=VALUE pairs separated by commas (e.g. Fz=1000,My=0), "
                             f"got {text!r}") from None
        if not math.isfinite(out[name.strip()]):
            raise ValueError(f"--at values must be finite, got {text!r}")
    return out


def _names(text: str) -> list[str]:
    return [n.strip() for n in text.split(",") if n.strip()]


def _add_plot_parsers(sub) -> None:
    p = sub.add_parser("plot", help="pictures of load maps, ball-passage tables and load zones (PNG, SVG, PDF)",
                       description=(
                           "Plot a load map (map, line), a ball-passage table (passage, spectrum) or the ball "
                           "loads of one operating point (loadzone). The format follows the output's extension "
                           "(.png, .svg, .pdf). Variables: Kb entries k + two of x, y, z, tx, ty (kxx, kzz, kxty, "
                           "ktyty ...), q components dx ... by, f components Fx ... My, max_ball_load, "
                           "loaded_balls, min_contact_angle, max_contact_angle. Units: N, mm, rad, shown with "
                           "k/M/G or m prefixes unless --base-units. Needs matplotlib "
                           "(pip install 'fastbearing[plot]')."))
    kinds = p.add_subparsers(dest="picture", required=True, metavar="PICTURE", parser_class=_Parser,
                             title="pictures (fastbearing plot PICTURE --help for each)")

    def common(q, file=True):
        if file:
            q.add_argument("file", metavar="FILE.h5", help="a finished fastbearing file")
        q.add_argument("-o", "--output", required=True, metavar="OUT.png", help="picture file: .png, .svg or .pdf")
        q.add_argument("--overwrite", action="store_true", help="replace an existing picture")
        q.add_argument("--size", type=str, metavar="WxH", help="width x height in pixels (default 800x560)")
        q.add_argument("--dpi", type=int, default=100, help="pixels per inch (default 100)")
        if file:
            q.add_argument("--at", metavar="NAME=VALUE,...", help="fix the other axes at the nearest grid values "
                           "(default: the middle value for maps, the first operating point for passage tables); "
                           "a value beyond an axis' first or last grid value is refused")
            q.add_argument("--base-units", action="store_true", help="label in N, mm, rad without prefixes")

    m = kinds.add_parser("map", help="contour or heat map of one variable over two axes of a load map")
    common(m)
    m.add_argument("--var", required=True, help="any stored variable with a unit, e.g. kzz, ktyty, kxty, dz, max_ball_load, L10r_hours")
    m.add_argument("--x", required=True, help="horizontal axis, e.g. Fx")
    m.add_argument("--y", required=True, help="vertical axis, e.g. My")
    m.add_argument("--kind", dest="kind_of_map", choices=["contour", "heatmap"], default="contour",
                   help="filled contours (default) or a heat map of the grid cells")
    m.add_argument("--row", type=int, help="row of a per-row variable (default: all rows: total, smallest or largest)")
    line = kinds.add_parser("line", help="variables of a load map along one axis")
    common(line)
    line.add_argument("--var", required=True, help="comma-separated stored variables, one panel each, e.g. kxx,kzz,L10_hours")
    line.add_argument("--x", required=True, help="axis along the lines, e.g. Fz")
    line.add_argument("--series", help="another axis: one line per value of it (at most 12)")
    line.add_argument("--row", type=int, help="row of a per-row variable (default: one line per row)")
    ps = kinds.add_parser("passage", help="Kb entries over one ball-pass period of a passage table")
    common(ps)
    ps.add_argument("--var", default="kxx,kzz,ktyty", help="comma-separated entries (default kxx,kzz,ktyty)")
    ps.add_argument("--x", choices=PASSAGE_X, default="angle",
                    help="cage angle (deg in the picture; --base-units: rad), fraction of the period, or time (s; needs a shaft speed)")
    ps.add_argument("--normalise", choices=NORMALISE, default="none",
                    help="divide by the value at position 0 (the paper's Fig. 13) or by the mean (default none)")
    sp = kinds.add_parser("spectrum", help="harmonic amplitudes of Kb entries of a passage table")
    common(sp)
    sp.add_argument("--var", default="kxx,kzz,ktyty", help="comma-separated Kb entries (default kxx,kzz,ktyty)")
    sp.add_argument("--normalise", choices=["none", "mean"], default="mean",
                    help="amplitudes in %% of the mean (default) or in the entry's units")
    sp.add_argument("--linear", action="store_true", help="linear instead of logarithmic amplitude axis")
    sp.add_argument("--orders", action="store_true", help="a table over shaft revolutions: the horizontal axis in "
                    "orders of the shaft speed (default: Hz where the table has a speed)")
    z = kinds.add_parser("loadzone", help="polar plot of the ball loads of one operating point, per row")
    common(z, file=False)
    which = z.add_mutually_exclusive_group(required=True)
    which.add_argument("--preset", choices=preset_names(), help="a shipped bearing (with --arrangement)")
    which.add_argument("--bearing", metavar="NAME|FILE.toml", help=_BEARING_HELP)
    z.add_argument("--arrangement", choices=ARRANGEMENTS, help="arrangement for --preset")
    given = z.add_mutually_exclusive_group(required=True)
    given.add_argument("--load", metavar="Fx,Fy,Fz,Mx,My", help="load: N, N, N, N*mm, N*mm (solved for q)")
    given.add_argument("--displacement", metavar="dx,dy,dz,bx,by", help="displacement: mm, mm, mm, rad, rad")


def _optional(run):
    """Run a command that needs the plot extra: a missing matplotlib or xarray is one line and exit 2."""
    def command(args) -> int:
        try:
            return run(args)
        except ImportError:
            missing = [m for m in ("matplotlib", "xarray", "h5netcdf") if importlib.util.find_spec(m) is None]
            raise ValueError(f"fastbearing {args.command} needs the plot extra ({', '.join(missing) or 'matplotlib'} "
                             "missing): pip install \".[plot]\" in the repository's folder (as the README "
                             "installs it)") from None
    return command


@_optional
def _plot(args) -> int:
    from .report import plot
    from .api import solve

    size = _size(args.size) if args.size else None
    opts = dict(out=args.output, overwrite=args.overwrite, size=size, dpi=args.dpi)
    if args.picture == "loadzone":
        bearing = _bearing(args)
        code = 0
        if args.load is not None:
            result = solve(bearing, _five_numbers(args.load, "--load"))
            q, code = result.q, 0 if result.converged else 1
            title = None if result.converged else f"NOT CONVERGED ({result.status_name}): last iterate shown"
        else:
            q, title = _five_numbers(args.displacement, "--displacement"), None
        plot.plot_load_zone(bearing, q, title=title, **opts)
        return code
    opts.update(at=_at(args.at), base_units=args.base_units)
    if args.picture == "map":
        plot.plot_map(args.file, args.var, args.x, args.y, kind=args.kind_of_map, row=args.row, **opts)
    elif args.picture == "line":
        plot.plot_lines(args.file, _names(args.var), args.x, series=args.series, row=args.row, **opts)
    elif args.picture == "passage":
        plot.plot_passage(args.file, _names(args.var), x=args.x, normalise=args.normalise, **opts)
    else:
        plot.plot_spectrum(args.file, _names(args.var), normalise=args.normalise, log=not args.linear,
                           orders=args.orders, **opts)
    return 0


@_optional
def _paper(args) -> int:
    from .report.paper import paper

    paper(args.out, overwrite=args.overwrite)
    return 0


def _passage(args) -> int:
    from .jobs.passage import passage

    return _run_job(passage, args, csv_files=args.csv, device=args.device)


def _shaft(args) -> int:
    from .analysis.shaft import natural_frequencies, read_shaft, solve_shaft

    shaft = read_shaft(args.config)
    speed, life_speed = _shaft_speed(args, shaft)
    result = solve_shaft(shaft, method=args.method, speed=speed)
    out = result.to_dict()
    if args.life and result.solution.converged:
        from .analysis.life import LifeSettings
        from .analysis.shaft import shaft_life

        life = shaft_life(shaft, result, LifeSettings(speed=life_speed or None, balls_at_speed=speed > 0))
        for b, lf in zip(out["bearings"], life["bearings"]):
            b["life"] = lf
        out["system_L10r"], out["system_L10r_hours"] = life["system_L10r"], life["system_L10r_hours"]
    if shaft.inertia is not None:
        M = shaft.inertia.matrix(shaft.reference)
        out["frequencies_hz"] = natural_frequencies(result.K_system, M).frequencies.tolist()
        out["frequencies_diagonal_only_hz"] = natural_frequencies(result.K_system, M, True).frequencies.tolist()
    if args.json:
        print(json_text(out))
        return 0 if result.solution.converged else 1
    print(f"shaft: status {out['status']}; reference z = {shaft.reference:g} mm"
          + (f"; speed {speed:g} rpm" if speed > 0 else ""))
    print("q at the reference (mm, mm, mm, rad, rad): " + "  ".join(f"{v:.6g}" for v in out["q"]))
    if out.get("fixed"):
        print(f"fixed at the reference: {', '.join(out['fixed'])}; the holder's reaction there (N, N, N, N*mm, N*mm) "
              + "  ".join(f"{v:.6g}" for v in out["holder_reaction"]))
    from .report.export import noise_as_zero

    print(_matrix("K_system at the reference", result.K_system))
    for i, b in enumerate(result.bearings):
        name = shaft.bearings[i].name or f"bearing {i}"
        print(f"{name} at z = {b.position:g} mm: reaction (N, N, N, N*mm, N*mm) "
              + "  ".join(f"{v:.6g}" for v in b.reaction))
        print("  q (mm, rad): " + "  ".join(f"{v:.6g}" for v in b.q))
        print("  Kb diagonal (N/mm, N/mm, N/mm, N*mm/rad, N*mm/rad): " + "  ".join(f"{v:.6g}" for v in np.diag(noise_as_zero(b.K))))
        if "life" in out["bearings"][i]:
            lf = out["bearings"][i]["life"]
            print(f"  life: L10r = {lf['L10r']:.6g} million revolutions (ISO/TS 16281); L10 = "
                  + ("-" if lf["L10"] is None else f"{lf['L10']:.6g}") + " (ISO 281)"
                  + (f"; C: {lf['C_source']}" if lf.get("C_source") else ""))
    if "system_L10r" in out:
        hours = "" if out["system_L10r_hours"] is None else f" ({out['system_L10r_hours']:.6g} h)"
        print(f"system life (weakest link of the bearings' L10r): {out['system_L10r']:.6g} million revolutions{hours}")
    if "frequencies_hz" in out:
        print("natural frequencies (Hz), full Kb:      " + "  ".join(f"{v:.1f}" for v in out["frequencies_hz"]))
        print("natural frequencies (Hz), diagonal only: "
              + "  ".join(f"{v:.1f}" for v in out["frequencies_diagonal_only_hz"]))
    return 0 if result.solution.converged else 1


def _matrix(title, K) -> str:
    labels = ("x", "y", "z", "tx", "ty")
    lines = [f"{title} ({_K_UNITS}):", "      " + "".join(f"{n:>14s}" for n in labels)]
    from .report.export import noise_as_zero

    # round-off (an entry below 1e-12 of its row's largest) shows as 0, and an exact zero as 0, not -0
    for name, row in zip(labels, noise_as_zero(K)):
        lines.append(f"{name:>4s}  " + "".join(f"{v:14.6g}" for v in row))
    return "\n".join(lines)


def _export(args) -> int:
    from pathlib import Path

    from .report import export

    from .jobs import storage

    out = Path(args.output)
    storage.check_output_path(out)
    if out.exists() and not args.overwrite:
        raise ValueError(f"{out} exists; pass --overwrite to replace it")
    if args.format != "dmig" and (args.grid != 1 or args.ground_grid is not None or args.name != "KBRG"):
        raise ValueError("--grid, --ground-grid and --name go with --format dmig")
    if args.format != "ross" and args.node != 0:
        raise ValueError("--node goes with --format ross")
    at = None if args.at is None else export.parse_at(args.at)
    if args.over is not None:
        if args.format == "dmig":
            raise ValueError("--over goes with --format ross, csv, json or npz (a DMIG matrix holds one case)")
        if args.format == "ross" and args.over != "speed":
            raise ValueError(f"--format ross takes --over speed (ROSS's coefficients run over frequency), got "
                             f"--over {args.over}")
        if args.case is not None or args.bearing is not None or args.system:
            raise ValueError("--over picks its cases itself: --case, --bearing and --system do not go with it")
        source = export.read_series(args.source, args.over, at)
    else:
        source = export.read_source(args.source, args.case, at, bearing=args.bearing, system=args.system)
    if source.picked:
        print(f"fastbearing: {source.picked}", file=sys.stderr)
    K = source.K[0] if source.K.ndim == 3 and len(source.K) == 1 else source.K
    if not np.isfinite(K).all():
        raise ValueError(f"{args.source}: K is not finite (a case that did not solve)")
    bad = source.unconverged
    if args.format in ("dmig", "ross"):
        if np.ndim(K) == 3 and args.over is None:
            raise ValueError(f"--format {args.format} takes one matrix: pick a case of {Path(args.source).name} "
                             "with --case N or --at AXIS=VALUE,...")
        if bad:
            raise ValueError(f"{args.source}: " + (f"the case's solve did not converge (status {source.status[0]})"
                             if args.over is None else f"{len(bad)} of the {len(source.status)} cases along "
                             f"{args.over} did not converge (first: {source.status[bad[0]]})")
                             + f"; a {args.format} model would take its Kb as true")
    elif bad:
        print(f"fastbearing: warning: {len(bad)} of {len(source.status)} cases did not converge "
              f"(first: case {bad[0]}, {source.status[bad[0]]}); their Kb is written as computed",
              file=sys.stderr)
    codes = None if source.codes is None else (source.codes[0] if np.ndim(K) == 2 else source.codes)
    if args.format == "csv":
        export.write_csv(out, K, overwrite=args.overwrite, coords=source.coords, status=codes,
                         matrix=source.matrix, results=source.results)
    elif args.format == "json":
        export.write_json(out, K, overwrite=args.overwrite, extra=source.extra, coords=source.coords,
                          status=codes, matrix=source.matrix, results=source.results)
    elif args.format == "npz":
        export.write_npz(out, K, overwrite=args.overwrite, coords=source.coords, status=codes,
                         matrix=source.matrix, results=source.results)
    elif args.format == "dmig":
        if args.grid < 1 or (args.ground_grid is not None and (args.ground_grid < 1 or args.ground_grid == args.grid)):
            raise ValueError("--grid and --ground-grid must be different positive grid ids")
        export.write_dmig(out, K, grid=args.grid, name=args.name, ground_grid=args.ground_grid,
                          overwrite=args.overwrite, matrix=source.matrix, centre=source.centre,
                          source=args.source, case=source.case)
    else:
        if args.node < 0:
            raise ValueError(f"--node must be a shaft node number >= 0, got {args.node}")
        import warnings

        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            export.write_ross(out, K, node=args.node, overwrite=args.overwrite, matrix=source.matrix,
                              source=args.source, case=source.case,
                              speeds_rpm=None if args.over is None else source.coords["speed"][0])
        for w in caught:
            print(f"fastbearing: warning: {w.message}", file=sys.stderr)
    print(f"fastbearing: wrote {out} ({source.matrix})", file=sys.stderr)
    return 0


def _warmup(args) -> int:
    from .jobs.warmup import check_kinds, warmup, warmup_portable

    kinds = check_kinds(_names(args.kinds)) if args.kinds else None
    if (args.portable is None) != (args.into is None):
        raise ValueError("--portable LEVEL and --into DIR go together")
    if args.portable is not None:
        return warmup_portable(args.portable, args.into, kinds)
    warmup(kinds)
    return 0


def _loadmap(args) -> int:
    from .jobs.loadmap import loadmap

    return _run_job(loadmap, args, device=args.device)


def _montecarlo(args) -> int:
    import json

    from .jobs.montecarlo import montecarlo, summary_text

    result = {}

    def run(*a, **kw):
        result["out"], result["summary"] = montecarlo(*a, **kw)

    code = _run_job(run, args, device=args.device)
    if code == 0:
        summary = result["summary"]
        print(json.dumps(summary) if args.json else summary_text(summary))
    return code


def _bearing(args):
    if args.bearing:
        if args.arrangement:
            raise ValueError("--arrangement goes with --preset; a bearing file sets its own arrangement")
        return load_bearing(args.bearing)
    return preset_bearing(args.preset, args.arrangement)


def _bearing_command(args) -> int:
    from .report.bearing_report import (bearing_report, bearing_report_text, fault_frequency_report,
                                        fault_frequency_text)
    from .validate import number

    if args.load is not None and args.speed is None:
        raise ValueError("--load goes with --speed (it sets the contact angle of the fault frequencies)")
    speed = None if args.speed is None else number(args.speed, "--speed", low=0, low_open=True, units="rpm")
    load = None if args.load is None else _five_numbers(args.load, "--load")
    bearing = load_bearing(args.file)
    rep = bearing_report(bearing, speed)
    try:
        faults = None if speed is None else fault_frequency_report(bearing, speed, load)
    except ValueError as err:  # the API's "load", as the command line spells it
        text = str(err)
        raise ValueError("--" + text if text.startswith(("load ", "speed ")) else text) from None
    if args.json:
        if faults is not None:
            rep["fault_frequencies"] = faults.pop("fault_frequencies")
            rep["fault_frequency_conditions"] = faults
        print(json_text(rep))
    else:
        print(bearing_report_text(rep, bearing))
        if faults is not None:
            print(fault_frequency_text(faults))
    return 0


def _bearings(args) -> int:
    """`fastbearing bearings [--json]`: the shipped bearings (fastbearing/catalogue/*.toml)."""
    from .report.catalogue import shipped_bearings, shipped_bearings_text

    entries = shipped_bearings()
    print(json_text(entries) if args.json else shipped_bearings_text(entries))
    return 0


def _balls_text(records: list[dict]) -> str:
    contacts = records and "inner_max_pressure" in records[0]
    head = f"{'row':>3s} {'ball':>4s} {'psi(deg)':>9s} {'delta(mm)':>11s} {'Q(N)':>11s} {'alpha(deg)':>10s}"
    if contacts:
        head += (f" {'p_in(MPa)':>10s} {'a_in(mm)':>9s} {'b_in(mm)':>9s}"
                 f" {'p_out(MPa)':>10s} {'a_out(mm)':>9s} {'b_out(mm)':>9s}")
    lines = ["balls (psi azimuth, delta deflection, Q load, alpha loaded contact angle"
             + ("; max Hertz pressure p (MPa = N/mm^2) and ellipse semi-axes a, b at the inner and outer race"
                if contacts else
                "; no [bearing.geometry]: no contact stresses") + "):", head]
    for r in records:
        line = (f"{r['row']:3d} {r['ball']:4d} {math.degrees(r['azimuth']):9.3f} {r['deflection']:11.5g} "
                f"{r['load']:11.6g} {math.degrees(r['contact_angle']):10.4f}")
        if contacts:
            line += (f" {r['inner_max_pressure']:10.1f} {r['inner_semi_major']:9.4f} {r['inner_semi_minor']:9.4f}"
                     f" {r['outer_max_pressure']:10.1f} {r['outer_semi_major']:9.4f} {r['outer_semi_minor']:9.4f}")
        lines.append(line)
    if records and "outer_load" in records[0]:
        lines += ["balls at speed (Q, alpha above: the inner contact; the outer contact's alpha_o and Q_o, "
                  "centrifugal force F_c, gyroscopic moment M_g, orbital speed omega_m):",
                  f"{'row':>3s} {'ball':>4s} {'alpha_i(deg)':>12s} {'alpha_o(deg)':>12s} {'Q_i(N)':>11s} "
                  f"{'Q_o(N)':>11s} {'F_c(N)':>10s} {'M_g(N*mm)':>10s} {'omega_m(rad/s)':>14s}"]
        for r in records:
            lines.append(f"{r['row']:3d} {r['ball']:4d} {math.degrees(r['inner_contact_angle']):12.4f} "
                         f"{math.degrees(r['outer_contact_angle']):12.4f} {r['inner_load']:11.6g} "
                         f"{r['outer_load']:11.6g} {r['centrifugal_force']:10.4g} {r['gyroscopic_moment']:10.4g} "
                         f"{r['orbital_speed']:14.6g}")
    return "\n".join(lines)


def _rollers_text(records: list[dict]) -> str:
    pressures = records and "inner_max_pressure" in records[0]
    head = f"{'row':>3s} {'roller':>6s} {'psi(deg)':>9s} {'Q(N)':>11s} {'q_max(N)':>11s} {'x(mm)':>8s}"
    if pressures:
        head += f" {'p_in(MPa)':>10s} {'p_out(MPa)':>10s}"
    lines = ["rollers (psi azimuth, Q total load, q_max the largest slice load and x its place from the roller's "
             "middle" + ("; largest Hertz line-contact pressure p (MPa = N/mm^2) at the inner and outer raceway"
                         if pressures else "; no [bearing.geometry]: no contact pressures") + "):", head]
    for r in records:
        loaded = r["load"] > 0  # an unloaded roller has no largest slice load: no place to print (not an edge)
        line = (f"{r['row']:3d} {r['roller']:6d} {math.degrees(r['azimuth']):9.3f} {r['load']:11.6g} "
                + (f"{r['max_slice_load']:11.5g} {r['max_slice_position']:8.3f}" if loaded else f"{'':11s} {'':8s}"))
        if pressures:
            line += f" {r['inner_max_pressure']:10.1f} {r['outer_max_pressure']:10.1f}"
        lines.append(line)
    return "\n".join(lines)


def _table(result: dict) -> str:
    lines = [f"status: {result['status']}  iterations: {result['iterations']}  residual: {result['residual']:.2e}"
             + (f"  speed: {result['speed']:g} rpm (high-speed model)" if result.get("speed") else "")]
    if result.get("note"):
        lines.append(result["note"])
    if result.get("fixed"):
        held = [n for n in DISPLACEMENT_NAMES if n in result["fixed"]]
        lines.append("fixed (given as displacements): " + ", ".join(held) + "; f there is the reaction")
    if not result["converged"]:
        if result.get("note"):  # the model has no answer here: no numbers that could pass for one
            return "\n".join(lines)
        lines.append("NOT A SOLUTION: the last iterate, shown for diagnosis only")
    lines += ["q (mm, mm, mm, rad, rad): " + "  ".join(f"{n}={v:.6g}" for n, v in zip(DISPLACEMENT_NAMES, result["q"])),
              "f (N, N, N, N*mm, N*mm): " + "  ".join(f"{n}={v:.6g}" for n, v in zip(LOAD_NAMES, result["f"])),
              _matrix("Kb", result["K"])]
    if "beyond_validity" in str(result["status"]):
        lines.append("warning: beyond_validity: a ball's deflection exceeds its row's validity limit (the Hertz "
                     "pressure limit, 4200 N/mm^2 by default, or 0.15 A0); the equations are solved, but small "
                     "elastic contacts no longer describe this bearing")
    return "\n".join(lines)


def _solve(args) -> int:
    from . import status as status_codes
    from .api import direct, solve
    from .analysis.contacts import ball_contacts

    bearing = _bearing(args)
    if not args.life and (args.kappa is not None or args.rotating != "inner" or args.contamination != 1.0):
        raise ValueError("--rotating, --kappa and --contamination go with --life")
    if args.contamination != 1.0 and args.kappa is None:
        raise ValueError("--contamination goes with --kappa (e_C enters only a_ISO, which needs the viscosity "
                         "ratio kappa in [0.1, 4])")
    from .model.bearing import check_speed_model

    def check_model(speed):
        try:
            check_speed_model(bearing, speed, "--speed")
        except ValueError as err:
            raise ValueError(str(err).replace("speed above", "--speed above", 1)) from None

    speed, life_speed = _speed_option(args.speed, args.life, bool(bearing.roller_rows), check_model)
    # a bearing with [bearing.mounting] solves as it runs: the operating clearance and preload at this speed
    bearing, budget = operating_bearing(bearing, life_speed)
    settings = None
    if args.life:
        from .analysis.life import LifeSettings, ratings

        settings = LifeSettings(rotating=args.rotating, speed=life_speed or None, kappa=args.kappa,
                                contamination=args.contamination, balls_at_speed=speed > 0)
        ratings(bearing)  # a bearing without geometry is refused before the solve
    if args.fix is not None and args.load is None:
        raise ValueError("--fix goes with --load (with --displacement every degree of freedom is given)")
    fixed = parse_fix_option(args.fix) if args.fix is not None else None
    if args.load is not None:
        try:
            result = solve(bearing, _five_numbers(args.load, "--load"), method=args.method, speed=speed,
                           fixed=fixed).to_dict()
        except FieldError as err:  # the API's names, as the command line spells them
            raise ValueError(str(err).replace("fixed.", "--fix ", 1).replace("fixed fixes", "--fix fixes", 1)
                             .replace("f.", "--load ", 1) if err.field.split(".")[0] in ("fixed", "f")
                             else str(err)) from None
    else:
        q = _five_numbers(args.displacement, "--displacement")
        try:
            f, K, status = direct(bearing, q, speed=speed)
        except ValueError:
            raise ValueError(f"--displacement {args.displacement} is too large: f or Kb overflow float64") from None
        unsettled = status_codes.outcome(status) == status_codes.BALL_EQUILIBRIUM
        result = {"q": [float(v) for v in q], "f": f.tolist(), "K": K.tolist(),
                  "status": status_codes.describe(status) if unsettled else "direct", "converged": not unsettled,
                  "iterations": 0, "residual": 0.0}
        if unsettled:
            result["note"] = (f"at {speed:g} rpm some balls have no equilibrium of their own at this displacement: "
                              "f and Kb there are not the model's (solve --balls shows each ball's residual)")
    result["speed"] = speed
    if budget is not None:
        result["operating"] = _operating_summary(budget)
    if args.balls:
        result["balls"] = ball_contacts(bearing, result["q"], speed).to_records()[:bearing.n_balls]
        if bearing.roller_rows:
            from .analysis.contacts import roller_contacts

            result["rollers"] = roller_contacts(bearing, result["q"]).to_records()
    if settings is not None and result["converged"]:
        from .analysis.life import life

        given = args.load is not None and not fixed  # else f holds the reactions: the load the ring carries
        result["life"] = life(bearing, _five_numbers(args.load, "--load") if given else result["f"],
                              result["q"], settings).to_dict()
    if args.json:
        print(json_text(result))
    else:
        if budget is not None:
            print("\n".join([budget["line"], *(f"  note: {n}" for n in budget["notes"])]))
        print(_table(result))
        if args.balls and result["balls"]:
            print(_balls_text(result["balls"]))
        if args.balls and "rollers" in result:
            print(_rollers_text(result["rollers"]))
        if "life" in result:
            print(_life_text(result["life"]))
    return 0 if result["converged"] else 1


def _operating_summary(budget: dict) -> dict:
    """The --json field of a mounted bearing's run: per row the operating and unmounted diametral clearance
    and axial preload (mm), the line the text prints, and the budget's notes."""
    rows = budget["rows"]
    return {"line": budget["line"], "speed": budget["speed"],
            "operating_diametral_clearance": [r["operating_diametral_clearance"] for r in rows],
            "unmounted_diametral_clearance": [r["unmounted_diametral_clearance"] for r in rows],
            "operating_axial_preload": [r["operating_axial_preload"] for r in rows],
            "notes": list(budget["notes"])}


def _shaft_speed(args, shaft) -> tuple[float, float]:
    """(the model's speed, the speed for lives in hours) of ``shaft``: --speed (as :func:`_speed_option`),
    else [shaft] speed."""
    if args.speed is None:
        return shaft.speed, shaft.speed
    return _speed_option(args.speed, args.life, any(mb.bearing.roller_rows for mb in shaft.bearings),
                         shaft.check_speed_model, "a bearing on this shaft has")


def _speed_option(value, life: bool, rollers: bool, check_model, subject: str = "this bearing has"):
    """--speed in rpm, checked before any kernel runs (finite, >= 0; above 0 only where ``check_model(speed)``
    passes): (the model's speed, the speed for lives in hours). With roller rows (``rollers``) and --life
    the solve stays quasi-static and the speed gives the lives in hours only (said on stderr)."""
    from .model.bearing import check_speed

    speed = check_speed(value, "--speed")
    if speed > 0 and rollers and life:
        print(f"fastbearing: note: the high-speed model covers ball rows; {subject} roller rows, so it is "
              "solved quasi-statically and --speed gives the lives in hours", file=sys.stderr)
        return 0.0, speed
    if speed > 0:
        check_model(speed)
    return speed, speed


def _life_text(life: dict) -> str:
    """The life block of ``solve --life``: loads N, lives in million revolutions (and hours)."""
    def g(v, unit=""):
        return "-" if v is None else f"{v:.6g}{unit}"

    def hours(v):
        return "" if v is None or life["speed"] is None else f" ({v * 1e6 / (60.0 * life['speed']):.6g} h)"

    lines = ["life (N; million revolutions" + (f"; hours at {life['speed']:g} rpm" if life["speed"] else "") + "):"]
    for k, L in enumerate(life["L10r_row"]):
        lines.append(f"  row {k}: C = {g(life['C_row'][k])}  Q_ci = {g(life['Q_ci'][k])}  Q_ce = {g(life['Q_ce'][k])}"
                     f"  Q_ei = {g(life['Q_ei'][k])}  Q_ee = {g(life['Q_ee'][k])}  L10r = {g(L)}{hours(L)}")
    lines.append(f"  bearing: C = {g(life['C'])}  C0 = {g(life['C0'])}  P = {g(life['P'])}  P0 = {g(life['P0'])}"
                 f"  S0 = {g(life['static_safety'])}")
    if life.get("C_source"):
        lines.append(f"  C: {life['C_source']}; C0: {life['C0_source']}")
    lines.append(f"  L10 (ISO 281) = {g(life['L10'])}{hours(life['L10'])}  L10r (ISO/TS 16281) = {g(life['L10r'])}"
                 f"{hours(life['L10r'])}")
    if life["max_contact_pressure"] is not None:
        lines.append(f"  largest contact pressure {life['max_contact_pressure']:.6g} N/mm^2 (limit {life['pressure_limit']:g})")
    if life["a_iso"] is not None:
        lines.append(f"  a_ISO = {life['a_iso']:.4g}  L_nmr = {g(life['L_nmr'])}{hours(life['L_nmr'])}")
    lines += [f"  note: {n}" for n in life["notes"]]
    return "\n".join(lines)


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """A warning on the command line: one line, as fastbearing says everything else (not Python's format)."""
    print(f"fastbearing: warning: {message}", file=sys.stderr)


def main(argv=None) -> int:
    parser = build_parser()
    argv = sys.argv[1:] if argv is None else list(argv)
    if not argv:
        parser.print_help()
        return 0
    try:
        args = parser.parse_args(argv)
        if args.command is None:
            raise _UsageError("fastbearing: give a command: " + ", ".join(sorted(_COMMANDS)))
        from ._cache import COMPILE_NOTICE, CompileWatch

        # a command that starts compiling says so before the wait, whatever it runs; a unit warning is one line
        notice = None if args.command == "warmup" else COMPILE_NOTICE  # the warm-up says its own
        with CompileWatch(notice), warnings.catch_warnings():
            warnings.showwarning = _show_warning
            return {"solve": _solve, "bearing": _bearing_command, "loadmap": _loadmap, "montecarlo": _montecarlo,
                    "passage": _passage,
                    "plot": _plot, "paper": _paper, "shaft": _shaft, "export": _export,
                    "bearings": _bearings, "warmup": _warmup}[args.command](args)
    except DiskFull as err:
        print(str(err), file=sys.stderr)
        return 1
    except OSError as err:
        if err.errno != errno.ENOSPC:
            raise
        # export, plots, CSV: written under a temporary name, so nothing half-written is left
        print(f"fastbearing: the disk is full ({err.filename or 'output'}): nothing was written; free some space "
              "and run again", file=sys.stderr)
        return 1
    except OutputExists as err:
        print(f"fastbearing: error: {err.cli_message()}", file=sys.stderr)
        return EXIT_USAGE
    except (_UsageError, ValueError) as err:
        print(f"fastbearing: error: {err}" if not str(err).startswith("fastbearing") else str(err),
              file=sys.stderr)
        return EXIT_USAGE
    except RuntimeError as err:
        from .engine.device import CudaUnavailable  # loads no numba

        if not isinstance(err, CudaUnavailable):
            raise
        print(f"fastbearing: error: {err}", file=sys.stderr)   # --device cuda without numba-cuda, driver or GPU
        return EXIT_USAGE


_COMMANDS = ("solve", "bearing", "bearings", "loadmap", "montecarlo", "passage", "plot", "paper", "shaft", "export",
             "warmup")


#: The commands that run kernels (and so start numba's compiler contexts).
_KERNEL_COMMANDS = ("solve", "loadmap", "montecarlo", "passage", "plot", "paper", "shaft", "warmup")


def start_numba_without_blas() -> None:
    """Start numba's compiler contexts with ``scipy.linalg`` hidden: in a command's own process only.

    When they start, numba looks for a BLAS (for ``np.dot`` and ``np.linalg`` in jitted code) by importing
    scipy.linalg, which costs 0.13 s here and pulls in another 0.06 s of numpy.f2py through scipy's
    array-API layer: a sixth of the main job's whole process. No fastbearing kernel calls a BLAS (the
    5x5 solves are linalg.py's own), so a command process starts numba without it; scipy.linalg imports
    as usual afterwards (the shaft's eigenvalues use it). A library user's process is left alone.
    """
    if "scipy.linalg" in sys.modules:
        return  # already imported: nothing to save
    sys.modules["scipy.linalg"] = None  # "import scipy.linalg..." raises ImportError: numba takes "no BLAS"
    try:
        from numba.core.registry import cpu_target

        cpu_target.target_context.refresh()  # loads its registries: numba.np.arraymath looks for the BLAS
    finally:
        del sys.modules["scipy.linalg"]


def entry_point() -> int:
    """main(), quiet when a reader closes the pipe early (``fastbearing solve ... | head -3``)."""
    import gc
    import os

    if len(sys.argv) > 1 and sys.argv[1] in _KERNEL_COMMANDS and "-h" not in sys.argv and "--help" not in sys.argv:
        start_numba_without_blas()
    try:
        code = main()
        sys.stdout.flush()
        # the interpreter's last collections would walk numba's whole object graph (0.13 s of the main
        # job's process): the work is done and its files closed, so the objects alive now are left out
        gc.freeze()
        return code
    except BrokenPipeError:
        # the reader is gone: nothing more to say to it, and no traceback at interpreter exit
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 141


if __name__ == "__main__":
    sys.exit(entry_point())
