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

Differences from the CPU path, said plainly: numba-cuda turns any fastmath request into all of LLVM's
fast-math flags, so the contact loops (compiled on the CPU with reassoc, contract, nsz and arcp only) also
assume finite values on the GPU, and NVVM contracts to FMA: results agree with the CPU's to rounding
(compare with a tolerance, not bit for bit). A map's Ctrl-C (``stop``) is seen between blocks, not
between cases. Units: N, mm, rad; shaft speeds rad/s.
"""

from __future__ import annotations

import numpy as np

from numba import njit

from ..config import CACHE, ERROR_MODEL, REFCOUNT
from .high_speed import warm_rows
from .schema import LIFE_SLICES, ElementSet
from .solver import WORK_ROWS, solve_case
from .sweep import PREDICTOR_ROWS, at_speed, map_runs, passage_point
from .device import CudaUnavailable, describe, import_cuda, require_cuda, simulated  # noqa: F401 (re-exported)

#: Threads per block of both kernels (each thread runs a whole solve: register-heavy code).
THREADS_PER_BLOCK = 128
#: Most threads of the cold-solve kernel; more cases loop (grid stride), so scratch stays bounded.
MAX_THREADS = 1 << 20
#: Device memory the per-thread scratch of one launch may take (bytes): bounds the threads at speed.
SCRATCH_BYTES = 1 << 30


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def solve_one(f_targets, q, f, K, balls, speeds, i, spin, settings, warm, work):
    """Case i of :func:`fastbearing.engine.sweep.solve_sweep` (its balls at ``speeds[i]`` rad/s with a speed table,
    their warm starts ``spin`` fresh): solver.solve_case's SolveOutcome. An njit function, not kernel code, so that
    the simulator runs it compiled (it calls the sweep's typing-time choice at_speed)."""
    return solve_case(f_targets[i], q[i], f[i], K[i], at_speed(balls, speeds, i, spin, True), settings, warm, work,
                      None, None)


@njit(cache=CACHE, error_model=ERROR_MODEL, nogil=True, _nrt=REFCOUNT)
def map_run(run, inputs, given_load, segments, results, balls, speeds, ball_row, settings, stop, life, C0,
            life_results, scratch):
    """Continuation run ``run`` of a map block: :func:`fastbearing.engine.sweep.map_runs` on that run alone, with the
    same arguments (one thread's scratch)."""
    map_runs(range(run, run + 1), inputs, given_load, segments, results, balls, speeds, ball_row, settings, stop,
             life, C0, life_results, scratch)


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
        """The simulator's device array as the NumPy array it wraps, which the CPU-compiled kernels take."""
        return getattr(x, "_ary", x)
else:
    @njit(inline="always")
    def native(x):
        """On the GPU a device array is the kernels' own argument: nothing to do."""
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
    """The kernels' ElementSet from their arguments: a part the bearing lacks is None (the branches test the
    closure's constants and are pruned while typing, so no code is compiled for it), and a bearing at speed takes
    thread t's row of the balls' warm starts ``spin_all``. One function for every kernel."""

    @njit(inline="always")
    def element_set(table, exponents, smoothing, slices, speed_table, omega, spin_all, t, four_point):
        if has_exponents:
            exps = exponents
        else:
            exps = None
        if has_slices:
            sl = slices
        else:
            sl = None
        if has_speed:
            st = speed_table
            spin = spin_all[t]
        else:
            st = None
            spin = None
        if has_four_point:
            fp = four_point
        else:
            fp = None
        return ElementSet(table, exps, smoothing, sl, st, omega, spin, fp)

    return element_set


def _make_solve(has_exponents, has_slices, has_speed, has_four_point):
    """The cold/warm solve of every row of f_targets, one case per thread (grid stride), as
    sweep.solve_sweep: case i at ``speeds[i]`` rad/s with a speed table, its balls' warm starts fresh."""
    element_set = _element_set_maker(has_exponents, has_slices, has_speed, has_four_point)
    from numba import float64

    @cuda.jit
    def solve(f_targets, q, f, K, status, iterations, residual, evaluations, table, exponents, slices,
              speed_table, four_point, speeds, spin_all, settings, warm):
        t = cuda.grid(1)
        n_threads = cuda.gridsize(1)
        work = cuda.local.array((WORK_ROWS, 5), float64)
        f_targets, q, f, K, speeds = native(f_targets), native(q), native(f), native(K), native(speeds)
        table, exponents, slices = native(table), native(exponents), native(slices)
        speed_table, four_point, spin_all = native(speed_table), native(four_point), native(spin_all)
        balls = element_set(table, exponents, 0.0, slices, speed_table, 0.0, spin_all, t, four_point)
        spin = balls.warm
        for i in range(t, f_targets.shape[0], n_threads):
            out = solve_one(f_targets, q, f, K, balls, speeds, i, spin, settings, warm, work)
            status[i] = out.status
            iterations[i] = out.iterations
            residual[i] = out.residual
            evaluations[i] = out.evaluations

    return solve


def _make_map(has_exponents, has_slices, has_speed, has_four_point):
    """One block of a load or displacement map, one continuation run per thread: sweep.map_runs itself
    (cold start, tangent and curved predictors along the run, per-row summaries, life)."""
    element_set = _element_set_maker(has_exponents, has_slices, has_speed, has_four_point)
    from numba import float64

    @cuda.jit
    def map_block(inputs, given_load, segments, q, f, K, status, iterations, residual, max_load, n_loaded,
                  min_angle, max_angle, min_outer, max_outer, table, exponents, slices, speed_table, four_point,
                  speeds, ball_row, settings, stop, life, C0, L10r, L10r_row, safety, ball_load_all,
                  contact_angle_all, sums_all, spin_all, outer_load_all, outer_count_all):
        t = cuda.grid(1)
        n_threads = cuda.gridsize(1)
        work = cuda.local.array((WORK_ROWS, 5), float64)
        predictor = cuda.local.array((PREDICTOR_ROWS, 5), float64)
        inputs, segments, q, f, K = native(inputs), native(segments), native(q), native(f), native(K)
        status, iterations, residual = native(status), native(iterations), native(residual)
        max_load, n_loaded, min_angle, max_angle = native(max_load), native(n_loaded), native(min_angle), native(max_angle)
        min_outer, max_outer, speeds, ball_row = native(min_outer), native(max_outer), native(speeds), native(ball_row)
        table, exponents, slices = native(table), native(exponents), native(slices)
        speed_table, four_point, spin_all = native(speed_table), native(four_point), native(spin_all)
        stop, life, L10r, L10r_row, safety = native(stop), native(life), native(L10r), native(L10r_row), native(safety)
        ball_load_all, contact_angle_all = native(ball_load_all), native(contact_angle_all)
        sums_all, outer_load_all, outer_count_all = native(sums_all), native(outer_load_all), native(outer_count_all)
        balls = element_set(table, exponents, 0.0, slices, speed_table, 0.0, spin_all, t, four_point)
        spin = balls.warm
        results = (q, f, K, status, iterations, residual, max_load, n_loaded, min_angle, max_angle, min_outer,
                   max_outer)
        scratch = (work, predictor, ball_load_all[t], contact_angle_all[t], sums_all[t], spin, outer_load_all[t],
                   outer_count_all[t])
        for run in range(t, segments.shape[0] - 1, n_threads):
            map_run(run, inputs, given_load, segments, results, balls, speeds, ball_row, settings, stop, life, C0,
                    (L10r, L10r_row, safety), scratch)

    return map_block


def _make_passage(has_exponents, has_slices, has_speed, has_four_point, has_speed_tables):
    """Ball-passage tables, one operating point per thread (grid stride): sweep.passage_point itself, every cage
    position from the previous one's converged q. ``has_speed_tables``: high-speed tables per position (defects)."""
    element_set = _element_set_maker(has_exponents, has_slices, has_speed, has_four_point)
    from numba import float64

    @cuda.jit
    def passage_block(inputs, given_load, tables, slice_tables, speed_tables, exponents, slices, speed_table,
                      four_point, smoothing, omega, q, f, K, status, iterations, residual, max_load, n_loaded,
                      min_angle, max_angle, element_loads, ball_row, settings, ball_load_all, contact_angle_all,
                      spin_all):
        t = cuda.grid(1)
        n_threads = cuda.gridsize(1)
        work = cuda.local.array((WORK_ROWS, 5), float64)
        inputs, tables, slice_tables, speed_tables = native(inputs), native(tables), native(slice_tables), native(
            speed_tables)
        exponents, slices, speed_table, four_point = native(exponents), native(slices), native(speed_table), native(
            four_point)
        q, f, K, status, iterations, residual = native(q), native(f), native(K), native(status), native(
            iterations), native(residual)
        max_load, n_loaded, min_angle, max_angle = native(max_load), native(n_loaded), native(min_angle), native(
            max_angle)
        element_loads, ball_row, spin_all = native(element_loads), native(ball_row), native(spin_all)
        ball_load_all, contact_angle_all = native(ball_load_all), native(contact_angle_all)
        balls = element_set(tables[0], exponents, smoothing, slices, speed_table, omega, spin_all, t, four_point)
        spin = balls.warm
        if has_slices:                            # the stacks per position, None where absent (as element_set)
            sl_tables = slice_tables
        else:
            sl_tables = None
        if has_speed_tables:
            st_tables = speed_tables
        else:
            st_tables = None
        results = (q, f, K, status, iterations, residual, max_load, n_loaded, min_angle, max_angle, element_loads)
        for i in range(t, inputs.shape[0], n_threads):
            passage_point(i, inputs, given_load, tables, sl_tables, st_tables, balls, results, ball_row, settings,
                          work, ball_load_all[t], contact_angle_all[t], spin)

    return passage_block


# -- host side -------------------------------------------------------------------------------------------------------

def _launch(n_work: int, per_thread_bytes: int, cap: int = MAX_THREADS) -> tuple[int, int]:
    """(blocks, threads) for n_work items with ``per_thread_bytes`` of device scratch per thread."""
    n_threads = max(1, min(n_work, cap, SCRATCH_BYTES // max(per_thread_bytes, 1)))
    tpb = min(THREADS_PER_BLOCK, n_threads)
    blocks = (n_threads + tpb - 1) // tpb
    return blocks, tpb


def _element_parts(put, balls: ElementSet):
    """The element set's arrays through ``put`` (to the device), a one-element placeholder for a part it lacks."""
    def part(a, ndim=2):
        return put(np.ascontiguousarray(a if a is not None else np.zeros((1,) * ndim)))

    return (part(balls.balls), part(balls.exponents, 1), part(balls.slices), part(balls.speed_table),
            part(balls.four_point))


def _solve_args(put, alloc, f_targets, q, f, K, status, iterations, residual, evaluations, balls, speeds, settings,
                warm):
    """(blocks, threads per block, the solve kernel's arguments, the device outputs q, f, K, status, iterations,
    residual, evaluations); ``put`` copies a host array to the device, ``alloc(shape, dtype)`` allocates there."""
    n = f_targets.shape[0]
    n_balls = max(balls.balls.shape[1], 1)
    spinning = balls.speed_table is not None
    rows = warm_rows(n_balls) if spinning else 1
    blocks, tpb = _launch(n, rows * n_balls * 8 if spinning else 0)
    spin_all = put(np.zeros((blocks * tpb, rows, n_balls) if spinning else (1, 1, 1)))  # every ball cold (new_warm)
    outs = [put(np.ascontiguousarray(q))] + [alloc(a.shape, a.dtype) for a in (f, K, status, iterations, residual,
                                                                                evaluations)]
    args = (put(np.ascontiguousarray(f_targets)), *outs, *_element_parts(put, balls),
            put(np.ascontiguousarray(speeds, dtype=np.float64)), spin_all, settings, bool(warm))
    return blocks, tpb, args, outs


def _map_args(put, alloc, inputs, given_load, segments, q, f, K, status, iterations, residual, max_load, n_loaded,
              min_angle, max_angle, outer_angles, balls, speeds, ball_row, settings, life, C0, L10r, L10r_row, safety):
    """(blocks, threads per block, the map kernel's arguments, the host result arrays, their device copies)."""
    n_runs = segments.shape[0] - 1
    n_elements = ball_row.shape[0]
    n_rows = max_load.shape[1]
    roller_life = life.shape[0] > 0 and life[0, LIFE_SLICES] > 0.0
    spinning = speeds.shape[0] > 0
    n_slices = balls.slices.shape[1] if balls.slices is not None else 0
    # the per-element record as sweep.map_sweep sizes it
    n_record = n_elements + (n_slices if roller_life else 0) + (n_elements if spinning else 0)
    n_balls = max(balls.balls.shape[1], 1)
    with_speed = balls.speed_table is not None
    rows = warm_rows(n_balls) if with_speed else 1
    sums_rows = max(life.shape[0], 1)
    per_thread = 8 * (2 * n_record + 2 * sums_rows + (rows * n_balls if with_speed else 0) + 2 * n_rows)
    blocks, tpb = _launch(max(n_runs, 1), per_thread)
    T = blocks * tpb
    host = (q, f, K, status, iterations, residual, max_load, n_loaded, min_angle, max_angle, outer_angles[0],
            outer_angles[1], L10r, L10r_row, safety)
    dev = [put(np.ascontiguousarray(a)) for a in host]
    args = (put(np.ascontiguousarray(inputs)), bool(given_load), put(np.ascontiguousarray(segments)), *dev[:12],
            *_element_parts(put, balls), put(np.ascontiguousarray(speeds, dtype=np.float64)),
            put(np.ascontiguousarray(ball_row)), settings, put(np.zeros(1, np.int64)),
            put(np.ascontiguousarray(life)), float(C0), *dev[12:], alloc((T, n_record), np.float64),
            alloc((T, n_record), np.float64), alloc((T, sums_rows, 2), np.float64),
            put(np.zeros((T, rows, n_balls) if with_speed else (1, 1, 1))), alloc((T, n_rows), np.float64),
            alloc((T, n_rows), n_loaded.dtype))
    return blocks, tpb, args, host, dev


def solve_sweep_cuda(f_targets, q, f, K, status, iterations, residual, evaluations, balls, speeds, settings, warm):
    """sweep.solve_sweep on the GPU, in place (the same arguments but the block size): every row of
    ``f_targets`` (N, 5; N, N*mm) solved for q (N, 5; mm, rad; warm starts there when ``warm``), f, Kb
    (N/mm, N*mm/rad, N/rad), status, iterations, relative residual and kernel evaluations; with a speed
    table case i runs at ``speeds[i]`` rad/s. CudaUnavailable without a usable GPU."""
    cuda = require_cuda()
    if f_targets.shape[0] == 0:
        return
    blocks, tpb, args, outs = _solve_args(cuda.to_device, cuda.device_array, f_targets, q, f, K, status, iterations,
                                          residual, evaluations, balls, speeds, settings, warm)
    _kernel("solve", _parts(balls))[blocks, tpb](*args)
    for host, dev in zip((q, f, K, status, iterations, residual, evaluations), outs):
        dev.copy_to_host(host)


def map_sweep_cuda(inputs, given_load, segments, q, f, K, status, iterations, residual, max_load, n_loaded,
                   min_angle, max_angle, outer_angles, balls, speeds, ball_row, settings, stop, life, C0, L10r,
                   L10r_row, safety):
    """sweep.map_sweep on the GPU, in place, with the same arguments and results: one thread per continuation
    run (``segments``; loads in N, N*mm or displacements in mm, rad; speeds rad/s). ``stop[0] != 0`` before the
    launch leaves the block untouched (incomplete); Ctrl-C during a launch is seen at the next block.
    CudaUnavailable without a usable GPU."""
    cuda = require_cuda()
    if segments.shape[0] <= 1 or stop[0] != 0:
        return
    blocks, tpb, args, host, dev = _map_args(cuda.to_device, cuda.device_array, inputs, given_load, segments, q, f,
                                             K, status, iterations, residual, max_load, n_loaded, min_angle,
                                             max_angle, outer_angles, balls, speeds, ball_row, settings, life, C0,
                                             L10r, L10r_row, safety)
    _kernel("map", _parts(balls))[blocks, tpb](*args)
    for h, d in zip(host, dev):
        d.copy_to_host(h)


def passage_sweep_cuda(inputs, given_load, tables, slice_tables, speed_tables, balls, q, f, K, status, iterations,
                       residual, max_load, n_loaded, min_angle, max_angle, element_loads, ball_row, settings, stop):
    """sweep.passage_sweep on the GPU, in place, with the same arguments and results: one thread per operating
    point (loads in N, N*mm or displacements in mm, rad), its cage positions in turn. ``stop[0] != 0`` before the
    launch leaves the block untouched (incomplete); Ctrl-C during a launch is seen at the next block.
    CudaUnavailable without a usable GPU."""
    cuda = require_cuda()
    n = inputs.shape[0]
    if n == 0 or stop[0] != 0:
        return
    put, alloc = cuda.to_device, cuda.device_array
    n_elements = ball_row.shape[0]
    n_balls = max(balls.balls.shape[1], 1)
    with_speed = balls.speed_table is not None
    rows = warm_rows(n_balls) if with_speed else 1
    blocks, tpb = _launch(n, 8 * (2 * n_elements + (rows * n_balls if with_speed else 0)))
    T = blocks * tpb
    host = (q, f, K, status, iterations, residual, max_load, n_loaded, min_angle, max_angle, element_loads)
    dev = [put(np.ascontiguousarray(a)) for a in host]
    parts = _parts(balls) + (speed_tables is not None,)

    def table(a, ndim):
        return put(np.ascontiguousarray(a if a is not None else np.zeros((1,) * ndim)))

    _, exponents, slices, speed_table, four_point = _element_parts(put, balls)
    _kernel("passage", parts)[blocks, tpb](
        put(np.ascontiguousarray(inputs)), bool(given_load), put(np.ascontiguousarray(tables)), table(slice_tables, 3),
        table(speed_tables, 3), exponents, slices, speed_table, four_point, float(balls.smoothing), float(balls.omega),
        *dev, put(np.ascontiguousarray(ball_row)), settings, alloc((T, n_elements), np.float64),
        alloc((T, n_elements), np.float64), put(np.zeros((T, rows, n_balls) if with_speed else (1, 1, 1))))
    for h, d in zip(host, dev):
        d.copy_to_host(h)


def compile_ptx(kind: str, example_args: tuple, cc=(9, 0)) -> str:
    """The PTX of the ``kind`` ("solve" or "map") kernel, typed from the host arrays
    ``example_args`` (solve_sweep_cuda's or map_sweep_cuda's arguments), for compute capability ``cc``: a check
    that the engine lowers for the real CUDA target. Needs numba-cuda with libnvvm (a CUDA toolkit or the
    nvidia-cuda-nvcc/nvrtc wheels); the device functions it calls are compiled for the current device, so on a
    machine without a GPU the caller must provide one's compute capability (tests/test_cuda.py)."""
    import numba

    _cuda()
    host_put = np.ascontiguousarray
    build = _solve_args if kind == "solve" else _map_args
    if kind == "solve":
        balls = example_args[8]
        args = build(host_put, np.empty, *example_args)[2]
    else:
        balls = example_args[14]
        args = build(host_put, np.empty, *example_args[:18], *example_args[19:])[2]  # no stop flag
    sig = tuple(numba.typeof(a) for a in args)
    kernel = _make_solve(*_parts(balls)) if kind == "solve" else _make_map(*_parts(balls))
    ptx, _ = cuda.compile_ptx(kernel.py_func, sig, cc=cc)
    return ptx
