"""The records that cross the line between jobs, drivers and kernels, split by lifetime (docs/layout.md).

The same records go to the CPU sweeps (engine/sweep.py) and the GPU launches (engine/gpu.py); numba types a
namedtuple field by field (a None part compiles no code for it) and numba-cuda flattens one into its fields,
device arrays included, so neither side has a positional list of arrays.

- :data:`Elements`: read-only, the same for every case of a job (on the GPU uploaded once per job).
- :data:`CaseBlock`: a block of cases, its inputs and its outputs (a :data:`Results` record, or a passage
  table's :data:`PassageResults`, or a batch's :data:`Solutions`).
- :data:`Scratch`: one thread's work space, sized by :func:`scratch_shape` for the CPU and the GPU alike.

Units: N, mm, rad; shaft speeds rad/s.
"""

from collections import namedtuple

import numpy as np

from .high_speed import warm_size
from .schema import LIFE_SLICES

#: A job's read-only tables. ``balls`` the element set (schema.ElementSet: the tables of every element kind,
#: a None part for a kind the bearing lacks; its ``omega`` and ``warm`` are set per case by the drivers);
#: ``ball_row`` (n_elements,) int64, each element's bearing row; ``life`` (rows, N_LIFE_COLUMNS) float64, the
#: life table (analysis/life.life_table), (0, N_LIFE_COLUMNS) without life; ``C0`` the static load rating (N).
Elements = namedtuple("Elements", "balls ball_row life C0")

#: One block of cases. ``inputs`` (N, 5): loads (N, N*mm) or displacements (mm, rad); ``segments`` the
#: continuation runs (grid.segment_starts; a batch's or a passage table's may be empty); ``speeds`` (N,) shaft
#: speed per case (rad/s), empty for a quasi-static block; ``operating`` None (every case the bearing as its
#: tables hold it) or (N, rows, schema.N_OPERATING) float64, each case's own operating clearance and preload
#: per row as the tables take them (bearing.Bearing.operating_table; written into a thread's own copy of the
#: tables where the case's element set is made, sweep.with_operating); ``ball_sizes`` None or (N, n_balls)
#: float64, each ball's diameter minus the nominal in each case (mm; with ``operating``, on a ball table without
#: its mirror half); ``results`` the block's outputs. Per-case bearing values join here, beside ``speeds``.
CaseBlock = namedtuple("CaseBlock", "inputs segments speeds operating ball_sizes results")

#: A map's outputs, leading dim the block's cases: q (N, 5) mm, rad; f (N, 5) N, N*mm; K (N, 5, 5) N/mm,
#: N*mm/rad, N/rad; status int8; iterations int32; residual (relative); per row (N, rows): max_load (N),
#: n_loaded, min_angle and max_angle (rad, loaded elements), min_outer and max_outer (rad, the outer
#: contacts at speed; else (1, rows), untouched); L10r (N,) and L10r_row (N, rows) million revolutions and
#: safety (N,) ISO 76 S0 with life (else (1,) and (1, rows), untouched). Filled by sweep.operating_point and
#: sweep.write_case: a new per-case output is a field here and a line there.
Results = namedtuple("Results", "q f K status iterations residual max_load n_loaded min_angle max_angle min_outer "
                                "max_outer L10r L10r_row safety")

#: A ball-passage table's outputs, dims (N points, P positions, ...): as Results' first ten, and
#: element_loads (N, P, n_elements) N, each element's load, or (0, 0, 0) where not stored.
PassageResults = namedtuple("PassageResults", "q f K status iterations residual max_load n_loaded min_angle "
                                              "max_angle element_loads")

#: A batch of independent solves' outputs (api.solve_many): q f K status iterations residual as Results',
#: evaluations (N,) int32 kernel calls.
Solutions = namedtuple("Solutions", "q f K status iterations residual evaluations")

#: A passage table's per-position tables, read-only like Elements: ``tables`` (P, N_BALL_COLUMNS, n_balls),
#: ``slices`` (P, N_SLICE_COLUMNS, n_slices) or None without roller rows, ``speed_tables`` (P, N_SPEED_COLUMNS,
#: n_balls) at speed with defects or None.
Positions = namedtuple("Positions", "tables slices speed_tables")

#: One thread's work space: the solver's ``work`` (WORK_ROWS, 5) and the map predictor's ``predictor``
#: (PREDICTOR_ROWS, 5); the per-element record ``ball_load`` (N) and ``contact_angle`` (rad), each
#: ScratchShape.record long; ``sums`` (life_rows, 2) the life sums; ``spin`` the balls' warm starts
#: (high_speed.warm_size cells, flat; None quasi-static); ``outer_load``, ``outer_count`` (rows,) the outer
#: contacts' row summary at speed; ``table`` and ``slices`` the thread's own copies of the ball and slice tables,
#: where each case's operating values are written (None without CaseBlock.operating; ``slices`` None without
#: roller rows).
Scratch = namedtuple("Scratch", "work predictor ball_load contact_angle sums spin outer_load outer_count table "
                                "slices")

#: The GPU's stand-in for a part a record lacks (numba-cuda passes arrays and scalars to a kernel, not None): a
#: one-element bool array, a type no real table has, which the kernels turn back into None while typing
#: (engine/cuda_kernels.py), so no code is compiled for the part.
ABSENT = np.zeros(1, np.bool_)

#: The sizes of a Scratch (:func:`scratch_shape`): the record's length, the life sums' rows, the bearing's
#: rows, the warm starts' cells (1 without a speed table) and the balls' count.
ScratchShape = namedtuple("ScratchShape", "record life_rows rows warm_size n_balls")


def scratch_shape(elements, cases) -> ScratchShape:
    """The sizes of one thread's Scratch for ``cases`` (a CaseBlock) of ``elements``: the one place both
    drivers size it (a GPU writing past a record sized otherwise would write out of bounds).

    The record holds every element's load and contact angle; a roller bearing's life adds every slice's
    load after them, and a block at speed (``cases.speeds`` not empty) the outer contacts' after those.
    """
    balls, life = elements.balls, elements.life
    n_elements = elements.ball_row.shape[0]
    roller_life = life.shape[0] > 0 and life[0, LIFE_SLICES] > 0.0
    n_slices = balls.slices.shape[1] if balls.slices is not None else 0
    spinning = cases.speeds.shape[0] > 0
    record = n_elements + (n_slices if roller_life else 0) + (n_elements if spinning else 0)
    n_balls = max(balls.balls.shape[1], 1)
    warm = warm_size(n_balls) if balls.speed_table is not None else 1
    return ScratchShape(record, max(life.shape[0], 1), cases.results.max_load.shape[-1], warm, n_balls)
