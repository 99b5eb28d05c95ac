"""The CUDA kernels of engine/gpu.py: module-level ``cuda.jit(cache=True)``, so numba-cuda keeps their PTX and
cubin in numba's cache beside the CPU kernels' (engine/__pycache__), once per machine and signature, and a later
process loads them instead of compiling (minutes for the balls at speed).

Imported only by :func:`fastbearing.engine.gpu.kernel`, after numba.cuda is known to be usable (it imports
numba.cuda). The kernels are specialised by their arguments' types alone, no closure constants: an element kind
the bearing lacks arrives as contract.ABSENT (a one-element bool array, a type no real table has), which
:func:`present` turns back into None while typing, so no code is compiled for it, as on the CPU. The drivers'
own bodies are the CPU's (sweep.solve_into, sweep.map_runs, sweep.passage_point). Units: N, mm, rad; rad/s.
"""

import numpy as np
from numba import float64, njit, types
from numba.extending import overload

from ..config import CACHE, ERROR_MODEL, REFCOUNT
from .contract import CaseBlock, Elements, Positions, Scratch
from .device import import_cuda, simulated
from .schema import ElementSet
from .solver import WORK_ROWS
from .sweep import PREDICTOR_ROWS, at_speed, map_runs, passage_point, solve_into

cuda = import_cuda()

def _absent(part) -> bool:
    return isinstance(part, np.ndarray) and part.dtype == np.bool_


def present(part):
    """``part``, or None where it is contract.ABSENT (chosen while typing; this body runs in the simulator's
    Python kernels)."""
    return None if _absent(part) else part


@overload(present, inline="always")
def _present(part):
    if isinstance(part, types.Array) and part.dtype == types.boolean:
        return lambda part: None
    return lambda part: part


def kept_if(part, value):
    """``value``, or None where ``part`` is contract.ABSENT (chosen while typing): a quasi-static bearing's balls
    have no warm starts."""
    return None if _absent(part) else value


@overload(kept_if, inline="always")
def _kept_if(part, value):
    if isinstance(part, types.Array) and part.dtype == types.boolean:
        return lambda part, value: None
    return lambda part, value: value


def _host_array(x):
    """The simulator's device array as the NumPy array it wraps, which the CPU-compiled kernels take; a record
    (namedtuple) field by field. (Its own name, not ``native``'s: a plain-Python call must never resolve to the
    uncached njit ``native`` of a real GPU; tests/test_layers.py checks every call.)"""
    if isinstance(x, tuple) and hasattr(x, "_fields"):
        return type(x)(*(_host_array(v) for v in x))
    return getattr(x, "_ary", x)


if simulated():
    native = _host_array
else:
    @njit(inline="always")
    def native(x):
        """On the GPU a device array (or a record of them, which numba-cuda flattens) is the kernels' own
        argument: nothing to do."""
        return x


@njit(inline="always")
def element_set(tables, spin_all, t):
    """The kernels' ElementSet from its device form (gpu.device_elements: every part an array, ABSENT where the
    bearing has none), the parts it lacks None again, and thread t's warm starts (column t of ``spin_all``,
    element-major: a strided view)."""
    spin = spin_all[:, t]
    return ElementSet(tables.balls, present(tables.exponents), tables.smoothing, present(tables.slices),
                      present(tables.speed_table), tables.omega, kept_if(tables.speed_table, spin),
                      present(tables.four_point))


@njit(inline="always")
def thread_scratch(work, predictor, rows, t, balls):
    """Thread t's contract.Scratch: its local ``work`` and ``predictor`` arrays, its column of the launch's
    element-major gpu.ThreadRows ``rows`` (strided views: neighbouring threads, neighbouring addresses), its
    balls' warm starts (``balls.warm``, None quasi-static) and, in a block whose cases carry their own operating
    values, its own copies of the ball and slice tables (rows.table[t], rows.slices[t], filled from ``balls``';
    None where ABSENT)."""
    return Scratch(work, predictor, rows.ball_load[:, t], rows.contact_angle[:, t], rows.sums[:, :, t], balls.warm,
                   rows.outer_load[:, t], rows.outer_count[:, t], own_copy(rows.table, t, balls.balls),
                   own_copy(rows.slices, t, balls.slices))


def own_copy(part, t, base):
    """Thread t's own copy of the table ``base`` (``part[t]``, filled from it), or None where ``part`` is
    contract.ABSENT (chosen while typing; this body runs in the simulator's Python kernels)."""
    if _absent(part):
        return None
    part[t][...] = base
    return part[t]


@overload(own_copy, inline="always")
def _own_copy(part, t, base):
    if isinstance(part, types.Array) and part.dtype == types.boolean:
        return lambda part, t, base: None

    def copy(part, t, base):
        mine = part[t]
        for i in range(base.shape[0]):
            for j in range(base.shape[1]):
                mine[i, j] = base[i, j]
        return mine
    return copy


@njit(inline="always")
def case_block(cases):
    """The kernels' CaseBlock from its device form: ``operating``, ``ball_sizes`` None again where ABSENT."""
    return CaseBlock(cases.inputs, cases.segments, cases.speeds, present(cases.operating), present(cases.ball_sizes),
                     cases.results)


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def solve_one(cases, balls, i, settings, warm, work):
    """Case i of :func:`fastbearing.engine.sweep.solve_sweep` (its balls at ``cases.speeds[i]`` rad/s with a speed
    table, their warm starts ``balls.warm`` fresh) into ``cases.results``: sweep.solve_into, the CPU's per-case
    body. An njit function, not kernel code, so that the simulator runs it compiled (it calls the sweep's
    typing-time choice at_speed)."""
    solve_into(cases, i, at_speed(balls, cases.speeds, i, balls.warm, True), settings, warm, work)


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def map_run(run, elements, cases, given_load, settings, stop, scratch):
    """Continuation run ``run`` of a map block: :func:`fastbearing.engine.sweep.map_runs` on that run alone, with the
    same arguments (one thread's scratch)."""
    map_runs(range(run, run + 1), elements, cases, given_load, settings, stop, scratch)


if simulated():
    # the simulator runs the kernels' bodies in Python: their helpers too, in plain Python (present, kept_if and
    # own_copy have plain forms for this). Called as njit dispatchers from Python they were compiled, uncached,
    # in every simulated process (about 11 s of each; the GPU inlines them, so they carry no cache of their own).
    element_set, thread_scratch, case_block = element_set.py_func, thread_scratch.py_func, case_block.py_func


@cuda.jit(cache=True)
def solve_kernel(tables, cases, spin_all, settings, warm):
    """Every case of a CaseBlock (its results a contract.Solutions), one case per thread (grid stride), as
    sweep.solve_sweep: case i at ``speeds[i]`` rad/s with a speed table, its balls' warm starts fresh."""
    t = cuda.grid(1)
    n_threads = cuda.gridsize(1)
    work = cuda.local.array((WORK_ROWS, 5), float64)
    tables, cases, spin_all = native(tables), case_block(native(cases)), native(spin_all)
    balls = element_set(tables, spin_all, t)
    for i in range(t, cases.inputs.shape[0], n_threads):
        solve_one(cases, balls, i, settings, warm, work)


@cuda.jit(cache=True)
def map_kernel(elements, cases, given_load, settings, stop, rows):
    """A launch of a map block (gpu.map_parts), one continuation segment of ``cases.segments`` per thread (the GPU's:
    runs cut to at most gpu.SEGMENT_CASES cases): sweep.map_runs itself (cold start, tangent and curved predictors
    along the segment, per-row summaries, life), its scratch column t of the launch's element-major ``rows``."""
    t = cuda.grid(1)
    n_threads = cuda.gridsize(1)
    work = cuda.local.array((WORK_ROWS, 5), float64)
    predictor = cuda.local.array((PREDICTOR_ROWS, 5), float64)
    elements, cases, stop, rows = native(elements), case_block(native(cases)), native(stop), native(rows)
    balls = element_set(elements.balls, rows.spin, t)
    mine = Elements(balls, elements.ball_row, elements.life, elements.C0)
    scratch = thread_scratch(work, predictor, rows, t, balls)
    for run in range(t, cases.segments.shape[0] - 1, n_threads):
        map_run(run, mine, cases, given_load, settings, stop, scratch)


@cuda.jit(cache=True)
def passage_kernel(elements, positions, cases, given_load, settings, rows):
    """Ball-passage tables, one operating point per thread (grid stride): sweep.passage_point itself, every cage
    position from the previous one's converged q; the slice and speed stacks ABSENT where the table has none."""
    t = cuda.grid(1)
    n_threads = cuda.gridsize(1)
    work = cuda.local.array((WORK_ROWS, 5), float64)
    elements, positions, cases, rows = native(elements), native(positions), case_block(native(cases)), native(rows)
    balls = element_set(elements.balls, rows.spin, t)
    mine = Elements(balls, elements.ball_row, elements.life, elements.C0)
    at = Positions(positions.tables, present(positions.slices), present(positions.speed_tables))
    scratch = thread_scratch(work, work, rows, t, balls)   # no predictor in a passage table
    for i in range(t, cases.inputs.shape[0], n_threads):
        passage_point(i, mine, at, cases, given_load, settings, scratch)


@cuda.jit(cache=True)
def narrow_kernel(src, dst):
    """``dst[i] = src[i]`` in dst's dtype (float64 to float32 for a map stored in float32: rounded to nearest, as
    numpy casts; +-inf beyond float32's range), grid stride over the 1-D views (engine/gpu.py's narrow)."""
    for i in range(cuda.grid(1), src.shape[0], cuda.gridsize(1)):
        dst[i] = src[i]
