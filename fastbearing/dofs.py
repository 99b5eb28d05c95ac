"""The five degrees of freedom: names, units and the units of every Kb entry.

A leaf module (it imports nothing of fastbearing), read by the API, the grid,
the HDF5 schema, export, plots and the command line, so a name or a unit is
written once.

q = (dx, dy, dz, bx, by): inner-ring displacement, mm and rad.
f = (Fx, Fy, Fz, Mx, My): load on the inner ring, N and N*mm.
Kb = df/dq: N/mm among translations, N*mm/rad among tilts, N/rad between.
"""

#: Short labels of the five DOFs (HDF5 ``dof`` coordinate, CSV column names).
DOF_LABELS = ("x", "y", "z", "tx", "ty")
LOAD_NAMES = ("Fx", "Fy", "Fz", "Mx", "My")
DISPLACEMENT_NAMES = ("dx", "dy", "dz", "bx", "by")
LOAD_UNITS = ("N", "N", "N", "N*mm", "N*mm")
DISPLACEMENT_UNITS = ("mm", "mm", "mm", "rad", "rad")
#: The ``units`` attribute of Kb in a store: one unit string, as CF asks of every variable, and Kb mixes three.
#: It is the translation block's (x, y, z rows and columns: the radial and axial stiffnesses); each entry's own
#: unit is in the ``units_per_entry`` attribute (:data:`K_UNITS_PER_ENTRY`).
K_UNITS = "N/mm"
#: The file-wide units statement of every output.
UNITS_CONVENTION = "N, mm, rad; moments N*mm; stiffness N/mm, N*mm/rad, N/rad"

#: Grid inputs by what is given.
AXES = {"load": LOAD_NAMES, "displacement": DISPLACEMENT_NAMES}
UNITS = {"load": LOAD_UNITS, "displacement": DISPLACEMENT_UNITS}
LONG_NAMES = {
    "speed": "shaft speed",
    "Fx": "radial force x on the inner ring", "Fy": "radial force y on the inner ring",
    "Fz": "axial force on the inner ring", "Mx": "moment about x on the inner ring",
    "My": "moment about y on the inner ring",
    "dx": "inner-ring displacement x", "dy": "inner-ring displacement y", "dz": "inner-ring axial displacement",
    "bx": "inner-ring tilt about x", "by": "inner-ring tilt about y",
    "inner_ring_temperature": "inner ring temperature", "outer_ring_temperature": "outer ring temperature",
    "ball_temperature": "rolling element temperature", "shaft_temperature": "shaft temperature",
    "housing_temperature": "housing temperature", "assembly_temperature": "assembly temperature",
    "sample": "Monte Carlo sample number",
}
#: Units of a temperature axis (CF/UDUNITS spelling).
TEMPERATURE_UNITS = "degC"


def k_entry_units(i: int, j: int) -> str:
    """Units of Kb[i, j]: N/mm (both translations), N*mm/rad (both tilts), N/rad (one of each)."""
    tilt_i, tilt_j = i >= 3, j >= 3
    return "N*mm/rad" if tilt_i and tilt_j else "N/rad" if tilt_i or tilt_j else "N/mm"


#: The units of each Kb entry, row-major (entry [i, j] at 5 i + j): a store's ``units_per_entry`` of K.
K_UNITS_PER_ENTRY = tuple(k_entry_units(i, j) for i in range(5) for j in range(5))

#: The 15 independent entries of the symmetric Kb: (row, column, name with units), e.g. "kxz_N/mm".
K_ENTRIES = tuple((i, j, f"k{DOF_LABELS[i]}{DOF_LABELS[j]}_{k_entry_units(i, j)}")
                  for i in range(5) for j in range(i, 5))
