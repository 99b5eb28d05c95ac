"""fastbearing: stiffness matrices of rolling bearings, fast.

Gunduz & Singh (2013) double-row angular contact ball bearing model: the
full 5x5 stiffness matrix Kb of single-row, double-row (DB, DF, DT) and
general sets of rows, given the displacement q or the load f.

Units: N, mm, rad. q = (dx, dy, dz, bx, by); f = (Fx, Fy, Fz, Mx, My).
"""

from importlib.metadata import PackageNotFoundError, version

from ._cache import ensure_fresh

ensure_fresh()

# isort: split

from . import status
from .api import (SolveManyResult, SolveResult, ball_loads, num_threads, solve, solve_many, stiffness,
                  stiffness_many)
from .bearing import ARRANGEMENTS, Bearing, Row, preset_names
from .bearing_file import bearing_from_table, load_bearing
from .contacts import BallContacts, ball_contacts
from .geometry import (MATERIALS, SILICON_NITRIDE, STEEL, Geometry, HertzContact, Material, geometry_from_table,
                       hertz_contact, race_contacts)
from .life import LifeResult, rating_life
from .loadmap import loadmap, open_dataset
from .passage import passage

try:
    __version__ = version("fastbearing")
except PackageNotFoundError:  # running from a source tree
    __version__ = "0+unknown"

__all__ = ["ARRANGEMENTS", "Bearing", "Row", "SolveManyResult", "SolveResult", "ball_loads", "bearing_from_table",
           "load_bearing", "loadmap", "num_threads", "open_dataset", "passage", "preset_names", "solve", "solve_many", "status", "stiffness",
           "stiffness_many", "MATERIALS", "STEEL", "SILICON_NITRIDE", "BallContacts", "Geometry", "HertzContact",
           "Material", "ball_contacts", "geometry_from_table", "hertz_contact", "race_contacts", "LifeResult",
           "rating_life"]
