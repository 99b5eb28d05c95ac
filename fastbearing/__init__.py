"""fastbearing: stiffness matrices of rolling bearings, fast.

The full 5x5 stiffness matrix Kb, given the displacement q or the load f, of
deep-groove, angular contact (single, DB, DF, DT), four-point contact ball,
cylindrical and tapered roller (single, TDO, TDI) bearings and any set of
rows, at rest and (ball bearings) at speed; from the Gunduz & Singh (2013)
double-row angular contact ball bearing model. Also load maps, ball-passage
tables, defects and fault frequencies, rating life, shafts, mounting and
exports; 14 shipped bearings by name (:func:`shipped_bearings`).

Units: N, mm, rad. q = (dx, dy, dz, bx, by); f = (Fx, Fy, Fz, Mx, My).

The public names below are imported on first use (PEP 562), so that
``import fastbearing`` and ``fastbearing --help`` do not load numba, scipy
or h5py before a command needs them.
"""

from importlib import import_module
from importlib.metadata import PackageNotFoundError, version

from . import status

#: Public name -> the module that defines it.
_PUBLIC = {
    **dict.fromkeys(("SolveManyResult", "SolveResult", "ball_loads", "num_threads", "solve", "solve_many",
                     "stiffness", "stiffness_many"), "api"),
    **dict.fromkeys(("ARRANGEMENTS", "Bearing", "Row", "preset_names"), "model.bearing"),
    "FourPointRow": "model.four_point",
    **dict.fromkeys(("bearing_from_table", "load_bearing"), "model.bearing_file"),
    **dict.fromkeys(("BallContacts", "ball_contacts"), "analysis.contacts"),
    **dict.fromkeys(("MATERIALS", "SILICON_NITRIDE", "STEEL", "Geometry", "HertzContact", "Material",
                     "geometry_from_table", "hertz_contact", "race_contacts"), "model.geometry"),
    **dict.fromkeys(("LifeResult", "rating_life"), "analysis.life"),
    **dict.fromkeys(("loadmap", "open_dataset"), "jobs.loadmap"),
    "open_map": "jobs.runner",
    **dict.fromkeys(("bearing_report", "bearing_report_text", "fault_frequency_report"), "report.bearing_report"),
    **dict.fromkeys(("fault_frequencies", "fault_orders"), "analysis.faults"),
    "passage": "jobs.passage",
    "montecarlo": "jobs.montecarlo",
    "operating_bearing": "model.mounted",
    "catalogue_names": "model.catalogue",
    **dict.fromkeys(("shipped_bearings", "shipped_bearings_text"), "report.catalogue"),
}

try:
    __version__ = version("fastbearing")
except PackageNotFoundError:  # running from a source tree
    __version__ = "0+unknown"

__all__ = ["status", *_PUBLIC]


def __getattr__(name):
    module = _PUBLIC.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_PUBLIC))
