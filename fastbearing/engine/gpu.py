"""The engine on CUDA: the CPU's own kernels compiled as numba-cuda device functions, thin drivers around them.

Nothing here is physics. numba-cuda compiles any ``@njit`` function (and every ``@overload`` of the
generic target) that a CUDA kernel calls as a device function from the same Python source, so the two
kernels below call :func:`fastbearing.engine.solver.solve_case` (one case per thread, as
:func:`fastbearing.engine.sweep.solve_sweep` does per case) and :func:`fastbearing.engine.sweep.map_runs`
(one continuation run of a map per thread, as :func:`fastbearing.engine.sweep.map_sweep` does per group):
statuses, warm starts, the tangent/curved predictors along a map line, the high-speed balls, roller rows and
the life variables are the CPU's code. Scratch: the solver's and the predictor's as ``cuda.local.array``,
the per-element record and the balls' warm starts as one row per thread of a device array.

This module is imported only when a caller asks for ``device="cuda"``; :func:`require_cuda` says in one
sentence what is missing (numba-cuda, a CUDA driver or a GPU). Under numba's CUDA simulator
(``NUMBA_ENABLE_CUDASIM=1`` before numba.cuda is first imported) the same drivers run in Python threads
calling the CPU-compiled kernels: what the tests use on machines without a GPU.

Differences from the CPU path, said plainly (docs/gpu.md, "Precision"): the device code is IEEE double
precision. numba-cuda (0.30) takes the contact loops' fast-math request (on the CPU: reassoc, contract, nsz,
arcp) as a flag that only swaps float32 libdevice functions; it writes no fast-math flags on the instructions,
and the NVVM options ftz, prec_div and prec_sqrt act on float32 alone. So no finite-math assumption: the NaN
and inf guards (isfinite tests, the selects over non-finite summaries) hold on the GPU as on the CPU. What
differs is rounding order: NVVM contracts a multiply and an add into one FMA and sums in program order, where
the CPU's ball loop reassociates (vectorised sums). Converged q and Kb then differ by about the solver's rtol
times the conditioning, not bit for bit, and a status decided by an exact threshold (the rounding floor's
PRECISION_LIMIT, DEFLECTION_LIMIT and contact-reversal warnings, a ball exactly at Q = 0, standing still)
may flip on a few cases of many. The simulator runs the CPU's compiled code, so there the two agree exactly;
the tolerances real hardware is held to are in bench/gpu_bench.py (OUTCOME_FLIPS, Q_TOLERANCE). A map's
Ctrl-C (``stop``) is seen between blocks, not between cases. Units: N, mm, rad; shaft speeds rad/s.
"""

from __future__ import annotations

import numpy as np

from numba import njit

from collections import namedtuple

from ..config import CACHE, ERROR_MODEL, REFCOUNT
from .contract import CaseBlock, Elements, Positions, Scratch, ScratchShape, scratch_shape
from .high_speed import warm_rows
from .schema import ElementSet
from .solver import WORK_ROWS
from .sweep import PREDICTOR_ROWS, at_speed, map_runs, passage_point, solve_into
from .device import CudaUnavailable, describe, import_cuda, require_cuda, simulated  # noqa: F401 (re-exported)

#: Threads per block of both kernels (each thread runs a whole solve: register-heavy code).
THREADS_PER_BLOCK = 128
#: Most threads of the cold-solve kernel; more cases loop (grid stride), so scratch stays bounded.
MAX_THREADS = 1 << 20
#: Device memory the per-thread scratch of one launch may take (bytes): bounds the threads at speed.
SCRATCH_BYTES = 1 << 30


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def map_run(run, elements, cases, given_load, settings, stop, scratch):
    """Continuation run ``run`` of a map block: :func:`fastbearing.engine.sweep.map_runs` on that run alone, with the
    same arguments (one thread's scratch)."""
    map_runs(range(run, run + 1), elements, cases, given_load, settings, stop, scratch)


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def solve_one(cases, balls, i, settings, warm, work):
    """Case i of :func:`fastbearing.engine.sweep.solve_sweep` (its balls at ``cases.speeds[i]`` rad/s with a speed
    table, their warm starts ``balls.warm`` fresh) into ``cases.results``: sweep.solve_into, the CPU's per-case
    body. An njit function, not kernel code, so that the simulator runs it compiled (it calls the sweep's
    typing-time choice at_speed)."""
    solve_into(cases, i, at_speed(balls, cases.speeds, i, balls.warm, True), settings, warm, work)


@njit(inline="always")
def thread_scratch(work, predictor, rows, t, spin):
    """Thread t's contract.Scratch: its local ``work`` and ``predictor`` arrays, its rows of the launch's
    ThreadRows ``rows`` and its balls' warm starts ``spin`` (None quasi-static)."""
    return Scratch(work, predictor, rows.ball_load[t], rows.contact_angle[t], rows.sums[t], spin, rows.outer_load[t],
                   rows.outer_count[t])


#: numba.cuda once imported (:func:`_cuda`): a module global, which the kernels name (the simulator swaps it).
cuda = None


def _cuda():
    """numba.cuda (fastbearing.engine.device.import_cuda), kept as this module's global for the kernels."""
    global cuda
    if cuda is None:
        cuda = import_cuda()
    return cuda


if simulated():
    def native(x):
        """The simulator's device array as the NumPy array it wraps, which the CPU-compiled kernels take; a record
        (namedtuple) field by field."""
        if isinstance(x, tuple) and hasattr(x, "_fields"):
            return type(x)(*(native(v) for v in x))
        return getattr(x, "_ary", x)
else:
    @njit(inline="always")
    def native(x):
        """On the GPU a device array (or a record of them, which numba-cuda flattens) is the kernels' own
        argument: nothing to do."""
        return x


# -- kernels: one per combination of the element set's optional parts (None compiles no code for a part) --------

_KERNELS = {}


def _parts(balls: ElementSet) -> tuple[bool, bool, bool, bool]:
    """Which optional parts the element set has: per-ball exponents, roller slices, speed table, four-point."""
    return (balls.exponents is not None, balls.slices is not None, balls.speed_table is not None,
            balls.four_point is not None)


def _kernel(kind: str, parts: tuple[bool, ...]):
    key = (kind, parts)
    if key not in _KERNELS:
        _cuda()
        _KERNELS[key] = {"solve": _make_solve, "map": _make_map, "passage": _make_passage}[kind](*parts)
    return _KERNELS[key]


def _element_set_maker(has_exponents, has_slices, has_speed, has_four_point):
    """The kernels' ElementSet from its device form (:func:`device_elements`: every part an array, a placeholder
    where the bearing has none): a part the bearing lacks is None again (the branches test the closure's
    constants and are pruned while typing, so no code is compiled for it), and a bearing at speed takes thread
    t's row of the balls' warm starts ``spin_all``. One function for every kernel."""

    @njit(inline="always")
    def element_set(tables, spin_all, t):
        if has_exponents:
            exps = tables.exponents
        else:
            exps = None
        if has_slices:
            sl = tables.slices
        else:
            sl = None
        if has_speed:
            st = tables.speed_table
            spin = spin_all[t]
        else:
            st = None
            spin = None
        if has_four_point:
            fp = tables.four_point
        else:
            fp = None
        return ElementSet(tables.balls, exps, tables.smoothing, sl, st, tables.omega, spin, fp)

    return element_set


def _make_solve(has_exponents, has_slices, has_speed, has_four_point):
    """The cold/warm solve of every case of a CaseBlock (its results a contract.Solutions), one case per thread
    (grid stride), as sweep.solve_sweep: case i at ``speeds[i]`` rad/s with a speed table, its balls' warm
    starts fresh."""
    element_set = _element_set_maker(has_exponents, has_slices, has_speed, has_four_point)
    from numba import float64

    @cuda.jit
    def solve(tables, cases, spin_all, settings, warm):
        t = cuda.grid(1)
        n_threads = cuda.gridsize(1)
        work = cuda.local.array((WORK_ROWS, 5), float64)
        tables, cases, spin_all = native(tables), native(cases), native(spin_all)
        balls = element_set(tables, spin_all, t)
        for i in range(t, cases.inputs.shape[0], n_threads):
            solve_one(cases, balls, i, settings, warm, work)

    return solve


def _make_map(has_exponents, has_slices, has_speed, has_four_point):
    """One block of a load or displacement map, one continuation run per thread: sweep.map_runs itself
    (cold start, tangent and curved predictors along the run, per-row summaries, life)."""
    element_set = _element_set_maker(has_exponents, has_slices, has_speed, has_four_point)
    from numba import float64

    @cuda.jit
    def map_block(elements, cases, given_load, settings, stop, rows):
        t = cuda.grid(1)
        n_threads = cuda.gridsize(1)
        work = cuda.local.array((WORK_ROWS, 5), float64)
        predictor = cuda.local.array((PREDICTOR_ROWS, 5), float64)
        elements, cases, stop, rows = native(elements), native(cases), native(stop), native(rows)
        balls = element_set(elements.balls, rows.spin, t)
        mine = Elements(balls, elements.ball_row, elements.life, elements.C0)
        scratch = thread_scratch(work, predictor, rows, t, balls.warm)
        for run in range(t, cases.segments.shape[0] - 1, n_threads):
            map_run(run, mine, cases, given_load, settings, stop, scratch)

    return map_block


def _make_passage(has_exponents, has_slices, has_speed, has_four_point, has_slice_tables, has_speed_tables):
    """Ball-passage tables, one operating point per thread (grid stride): sweep.passage_point itself, every cage
    position from the previous one's converged q. ``has_slice_tables``, ``has_speed_tables``: roller slice
    tables and high-speed tables per position (defects at speed)."""
    element_set = _element_set_maker(has_exponents, has_slices, has_speed, has_four_point)
    from numba import float64

    @cuda.jit
    def passage_block(elements, positions, cases, given_load, settings, rows):
        t = cuda.grid(1)
        n_threads = cuda.gridsize(1)
        work = cuda.local.array((WORK_ROWS, 5), float64)
        elements, positions, cases, rows = native(elements), native(positions), native(cases), native(rows)
        balls = element_set(elements.balls, rows.spin, t)
        mine = Elements(balls, elements.ball_row, elements.life, elements.C0)
        if has_slice_tables:                      # the stacks per position, None where absent (as element_set)
            sl_tables = positions.slices
        else:
            sl_tables = None
        if has_speed_tables:
            st_tables = positions.speed_tables
        else:
            st_tables = None
        at = Positions(positions.tables, sl_tables, st_tables)
        scratch = thread_scratch(work, work, rows, t, balls.warm)   # no predictor in a passage table
        for i in range(t, cases.inputs.shape[0], n_threads):
            passage_point(i, mine, at, cases, given_load, settings, scratch)

    return passage_block


# -- host side -------------------------------------------------------------------------------------------------------

#: One launch's per-thread scratch in device memory, a row per thread (contract.Scratch's arrays but the solver's
#: and the predictor's, which are each thread's local arrays): sized from contract.scratch_shape.
ThreadRows = namedtuple("ThreadRows", "ball_load contact_angle sums spin outer_load outer_count")


def thread_bytes(shape: ScratchShape, with_speed: bool) -> int:
    """Device memory of one thread's ThreadRows (bytes) for a Scratch of ``shape``."""
    warm = shape.warm_rows * shape.n_balls if with_speed else 0
    return 8 * (2 * shape.record + 2 * shape.life_rows + warm + 2 * shape.rows)


def thread_rows(put, alloc, shape: ScratchShape, n_threads: int, counts_dtype, with_speed: bool) -> ThreadRows:
    """The ThreadRows of ``n_threads`` threads (the balls' warm starts zeroed: every ball cold, new_warm)."""
    T = n_threads
    spin = np.zeros((T, shape.warm_rows, shape.n_balls) if with_speed else (1, 1, 1))
    return ThreadRows(alloc((T, shape.record), np.float64), alloc((T, shape.record), np.float64),
                      alloc((T, shape.life_rows, 2), np.float64), put(spin), alloc((T, shape.rows), np.float64),
                      alloc((T, shape.rows), counts_dtype))


def _launch(n_work: int, per_thread_bytes: int, cap: int = MAX_THREADS) -> tuple[int, int]:
    """(blocks, threads) for n_work items with ``per_thread_bytes`` of device scratch per thread."""
    n_threads = max(1, min(n_work, cap, SCRATCH_BYTES // max(per_thread_bytes, 1)))
    tpb = min(THREADS_PER_BLOCK, n_threads)
    blocks = (n_threads + tpb - 1) // tpb
    return blocks, tpb


def _placeholder(a, ndim: int) -> np.ndarray:
    """``a`` as a contiguous array, or a one-element float64 array of ``ndim`` dims for a part that is None
    (numba-cuda passes arrays and scalars, not None)."""
    return np.ascontiguousarray(a if a is not None else np.zeros((1,) * ndim))


def device_elements(put, balls: ElementSet) -> ElementSet:
    """The element set as a kernel argument: every part through ``put`` (to the device), a one-element placeholder
    for a part it lacks and for the warm starts (each thread's are its ThreadRows row); the kernels' element_set
    makes the parts None again."""
    return ElementSet(put(_placeholder(balls.balls, 2)), put(_placeholder(balls.exponents, 1)),
                      float(balls.smoothing), put(_placeholder(balls.slices, 2)),
                      put(_placeholder(balls.speed_table, 2)), float(balls.omega), put(_placeholder(None, 3)),
                      put(_placeholder(balls.four_point, 2)))


def _inputs(put, cases: CaseBlock, results):
    """``cases`` with its inputs, segments and speeds through ``put`` and ``results`` in place of its own."""
    return CaseBlock(put(np.ascontiguousarray(cases.inputs)), put(np.ascontiguousarray(cases.segments)),
                     put(np.ascontiguousarray(cases.speeds, dtype=np.float64)), results)


def _outputs(alloc, results):
    """A results record's device arrays (not copied there: the kernels write every case's)."""
    return type(results)(*(alloc(a.shape, a.dtype) for a in results))


#: One launch: thread blocks, threads per block and the device memory it holds (bytes: the element tables, the
#: block's inputs and results, every thread's scratch rows).
LaunchPlan = namedtuple("LaunchPlan", "blocks threads_per_block device_bytes")


def nbytes(record) -> int:
    """Bytes of every array in a record (namedtuple, nested), None and scalars counting nothing."""
    if isinstance(record, tuple):
        return sum(nbytes(x) for x in record)
    return int(getattr(record, "nbytes", 0))


def solve_plan(balls, cases) -> LaunchPlan:
    """The solve kernel's launch for ``cases``: one case per thread (grid stride beyond MAX_THREADS), each at speed
    with its balls' warm starts in device memory."""
    spinning = balls.speed_table is not None
    n_balls = max(balls.balls.shape[1], 1)
    per_thread = warm_rows(n_balls) * n_balls * 8 if spinning else 0
    blocks, tpb = _launch(cases.inputs.shape[0], per_thread)
    return LaunchPlan(blocks, tpb, nbytes(balls) + nbytes(cases) + blocks * tpb * per_thread)


def map_plan(elements, cases) -> LaunchPlan:
    """The map kernel's launch for the block ``cases``: one thread per continuation run, each with the scratch
    rows contract.scratch_shape sizes (hosts can plan a device run from this without a GPU:
    bench/gpu_bench.py --plan)."""
    shape = scratch_shape(elements, cases)
    per_thread = thread_bytes(shape, elements.balls.speed_table is not None)
    blocks, tpb = _launch(max(cases.segments.shape[0] - 1, 1), per_thread)
    return LaunchPlan(blocks, tpb, nbytes(elements) + nbytes(cases) + blocks * tpb * per_thread)


def _solve_args(put, alloc, balls, cases, settings, warm):
    """(blocks, threads per block, the solve kernel's arguments, the device results); ``put`` copies a host array
    to the device, ``alloc(shape, dtype)`` allocates there."""
    n_balls = max(balls.balls.shape[1], 1)
    spinning = balls.speed_table is not None
    rows = warm_rows(n_balls) if spinning else 1
    blocks, tpb, _ = solve_plan(balls, cases)
    spin_all = put(np.zeros((blocks * tpb, rows, n_balls) if spinning else (1, 1, 1)))  # every ball cold (new_warm)
    outs = _outputs(alloc, cases.results)._replace(q=put(np.ascontiguousarray(cases.results.q)))  # the warm starts
    args = (device_elements(put, balls), _inputs(put, cases, outs), spin_all, settings, bool(warm))
    return blocks, tpb, args, outs


def _map_args(put, alloc, elements, cases, given_load, settings):
    """(blocks, threads per block, the map kernel's arguments, the device results): one thread per continuation
    run, each with its ThreadRows row."""
    shape = scratch_shape(elements, cases)
    with_speed = elements.balls.speed_table is not None
    blocks, tpb, _ = map_plan(elements, cases)
    outs = _outputs(alloc, cases.results)
    dev_elements = Elements(device_elements(put, elements.balls), put(np.ascontiguousarray(elements.ball_row)),
                            put(np.ascontiguousarray(elements.life)), float(elements.C0))
    rows = thread_rows(put, alloc, shape, blocks * tpb, cases.results.n_loaded.dtype, with_speed)
    args = (dev_elements, _inputs(put, cases, outs), bool(given_load), settings, put(np.zeros(1, np.int64)), rows)
    return blocks, tpb, args, outs


def _copy_back(host, dev) -> None:
    """Every device array of the results record ``dev`` into its host twin in ``host``."""
    for h, d in zip(host, dev):
        d.copy_to_host(h)


def solve_sweep_cuda(balls, cases, settings, warm):
    """sweep.solve_sweep on the GPU, in place (the same arguments but the block size): every row of
    ``cases.inputs`` (N, 5; N, N*mm) solved into ``cases.results`` (contract.Solutions: q (N, 5; mm, rad; warm
    starts there when ``warm``), f, Kb (N/mm, N*mm/rad, N/rad), status, iterations, relative residual and kernel
    evaluations); with a speed table case i runs at ``cases.speeds[i]`` rad/s. CudaUnavailable without a usable
    GPU."""
    cuda = require_cuda()
    if cases.inputs.shape[0] == 0:
        return
    blocks, tpb, args, outs = _solve_args(cuda.to_device, cuda.device_array, balls, cases, settings, warm)
    _kernel("solve", _parts(balls))[blocks, tpb](*args)
    _copy_back(cases.results, outs)


def map_sweep_cuda(elements, cases, given_load, settings, stop):
    """sweep.map_sweep on the GPU, in place, with the same arguments and results (contract.Elements, a
    contract.CaseBlock of contract.Results): one thread per continuation run (``cases.segments``; loads in N,
    N*mm or displacements in mm, rad; speeds rad/s). ``stop[0] != 0`` before the launch leaves the block
    untouched (incomplete); Ctrl-C during a launch is seen at the next block. CudaUnavailable without a usable
    GPU."""
    cuda = require_cuda()
    if cases.segments.shape[0] <= 1 or stop[0] != 0:
        return
    blocks, tpb, args, outs = _map_args(cuda.to_device, cuda.device_array, elements, cases, given_load, settings)
    _kernel("map", _parts(elements.balls))[blocks, tpb](*args)
    _copy_back(cases.results, outs)


def passage_sweep_cuda(elements, positions, cases, given_load, settings, stop):
    """sweep.passage_sweep on the GPU, in place, with the same arguments and results (contract.Elements,
    contract.Positions, a contract.CaseBlock of contract.PassageResults): one thread per operating point (loads in
    N, N*mm or displacements in mm, rad), its cage positions in turn. ``stop[0] != 0`` before the launch leaves
    the block untouched (incomplete); Ctrl-C during a launch is seen at the next block. CudaUnavailable without a
    usable GPU."""
    cuda = require_cuda()
    n = cases.inputs.shape[0]
    if n == 0 or stop[0] != 0:
        return
    put, alloc = cuda.to_device, cuda.device_array
    shape = scratch_shape(elements, cases)
    with_speed = elements.balls.speed_table is not None
    blocks, tpb = _launch(n, thread_bytes(shape, with_speed))
    outs = _outputs(alloc, cases.results)
    dev_elements = Elements(device_elements(put, elements.balls), put(np.ascontiguousarray(elements.ball_row)),
                            put(np.ascontiguousarray(elements.life)), float(elements.C0))
    dev_positions = Positions(put(np.ascontiguousarray(positions.tables)), put(_placeholder(positions.slices, 3)),
                              put(_placeholder(positions.speed_tables, 3)))
    rows = thread_rows(put, alloc, shape, blocks * tpb, cases.results.n_loaded.dtype, with_speed)
    parts = _parts(elements.balls) + (positions.slices is not None, positions.speed_tables is not None)
    _kernel("passage", parts)[blocks, tpb](dev_elements, dev_positions, _inputs(put, cases, outs), bool(given_load),
                                           settings, rows)
    _copy_back(cases.results, outs)


def compile_ptx(kind: str, example_args: tuple, cc=(9, 0)) -> str:
    """The PTX of the ``kind`` ("solve" or "map") kernel, typed from the host records ``example_args``
    (solve_sweep_cuda's or map_sweep_cuda's arguments), for compute capability ``cc``: a check that the engine
    lowers for the real CUDA target. Needs numba-cuda with libnvvm (a CUDA toolkit or the
    nvidia-cuda-nvcc/nvrtc wheels); the device functions it calls are compiled for the current device, so on a
    machine without a GPU the caller must provide one's compute capability (tests/test_cuda.py)."""
    import numba

    _cuda()
    host_put = np.ascontiguousarray
    if kind == "solve":
        balls = example_args[0]
        args = _solve_args(host_put, np.empty, *example_args)[2]
    else:
        balls = example_args[0].balls
        args = _map_args(host_put, np.empty, *example_args[:4])[2]
    sig = tuple(numba.typeof(a) for a in args)
    kernel = _make_solve(*_parts(balls)) if kind == "solve" else _make_map(*_parts(balls))
    ptx, _ = cuda.compile_ptx(kernel.py_func, sig, cc=cc)
    return ptx
