"""The engine on CUDA: the CPU's own kernels compiled as numba-cuda device functions, thin drivers around them.

Nothing here is physics. numba-cuda compiles any ``@njit`` function (and every ``@overload`` of the
generic target) that a CUDA kernel calls as a device function from the same Python source, so the three
kernels (engine/cuda_kernels.py: module-level, cached on disk) call the CPU's per-case bodies:
:func:`fastbearing.engine.sweep.solve_into` (one case per thread, as sweep.solve_sweep does per case),
:func:`fastbearing.engine.sweep.map_runs` (one continuation run of a map per thread, as sweep.map_sweep does per
group) and :func:`fastbearing.engine.sweep.passage_point` (one operating point per thread): statuses, warm
starts, the tangent/curved predictors along a map line, the high-speed balls, roller rows and the life variables
are the CPU's code. The drivers here take and pass the same records as the CPU's (engine/contract.py); a
thread's scratch is sized by the same contract.scratch_shape: the solver's and the predictor's as
``cuda.local.array``, the per-element record, life sums and the balls' warm starts as one row per thread of a
device array (:data:`ThreadRows`).

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

import hashlib
from collections import namedtuple

from .contract import ABSENT, CaseBlock, Elements, Positions, ScratchShape, scratch_shape
from .high_speed import warm_rows
from .schema import ElementSet
from .device import CudaUnavailable, describe, import_cuda, require_cuda, simulated  # noqa: F401 (re-exported)

#: Threads per block of both kernels (each thread runs a whole solve: register-heavy code).
THREADS_PER_BLOCK = 128
#: Most threads of the cold-solve kernel; more cases loop (grid stride), so scratch stays bounded.
MAX_THREADS = 1 << 20
#: Device memory the per-thread scratch of one launch may take (bytes): bounds the threads at speed.
SCRATCH_BYTES = 1 << 30


#: numba.cuda once imported (:func:`_cuda`).
cuda = None


def _cuda():
    """numba.cuda (fastbearing.engine.device.import_cuda), kept as this module's global."""
    global cuda
    if cuda is None:
        cuda = import_cuda()
    return cuda


def kernel(kind: str):
    """The CUDA kernel of ``kind`` ("solve", "map" or "passage"): engine/cuda_kernels.py's module-level kernels,
    cached on disk by numba-cuda (imported here: it imports numba.cuda)."""
    _cuda()
    from . import cuda_kernels

    return {"solve": cuda_kernels.solve_kernel, "map": cuda_kernels.map_kernel,
            "passage": cuda_kernels.passage_kernel}[kind]


# -- host side -------------------------------------------------------------------------------------------------------

#: One launch's per-thread scratch in device memory, a row per thread (contract.Scratch's arrays but the solver's
#: and the predictor's, which are each thread's local arrays): sized from contract.scratch_shape.
ThreadRows = namedtuple("ThreadRows", "ball_load contact_angle sums spin outer_load outer_count")


def thread_bytes(shape: ScratchShape, with_speed: bool) -> int:
    """Device memory of one thread's ThreadRows (bytes) for a Scratch of ``shape``."""
    warm = shape.warm_rows * shape.n_balls if with_speed else 0
    return 8 * (2 * shape.record + 2 * shape.life_rows + warm + 2 * shape.rows)


def thread_rows(mem, shape: ScratchShape, n_threads: int, counts_dtype, with_speed: bool) -> ThreadRows:
    """The ThreadRows of ``n_threads`` threads in ``mem`` (:class:`DeviceMemory`; the balls' warm starts zeroed:
    every ball cold, new_warm)."""
    T = n_threads
    spin = np.zeros((T, shape.warm_rows, shape.n_balls) if with_speed else (T, 1, 1))
    return ThreadRows(mem.buffer("ball_load", (T, shape.record)), mem.buffer("contact_angle", (T, shape.record)),
                      mem.buffer("sums", (T, shape.life_rows, 2)), mem.data(spin),
                      mem.buffer("outer_load", (T, shape.rows)), mem.buffer("outer_count", (T, shape.rows),
                                                                            counts_dtype))


class DeviceMemory:
    """Where a launch's arrays live, kept across blocks (issue 46 item 2): ``table`` uploads a read-only table
    once per content (the element tables of a job, whichever block asks); ``buffer`` allocates a result or
    scratch array once per role, shape and dtype and hands the same one to the next block (the kernels write
    every entry they read back, so nothing is copied there); ``data`` copies a block's own inputs each time.
    One per process (:func:`device_memory`): at most one buffer per role and :data:`MAX_TABLES` tables."""

    def __init__(self, put, alloc):
        self.put, self.alloc = put, alloc
        self.tables, self.buffers = {}, {}

    def table(self, a: np.ndarray):
        a = np.ascontiguousarray(a)
        key = (a.shape, a.dtype.str, hashlib.blake2b(a.tobytes(), digest_size=16).digest())
        if key not in self.tables:
            if len(self.tables) >= MAX_TABLES:
                self.tables.pop(next(iter(self.tables)))
            self.tables[key] = self.put(a)
        return self.tables[key]

    def buffer(self, role: str, shape, dtype=np.float64):
        key = (tuple(shape), np.dtype(dtype).str)
        held = self.buffers.get(role)
        if held is None or held[0] != key:
            self.buffers[role] = (key, self.alloc(tuple(shape), np.dtype(dtype)))
        return self.buffers[role][1]

    def data(self, a: np.ndarray):
        return self.put(np.ascontiguousarray(a))


class HostMemory(DeviceMemory):
    """The same roles as plain host arrays, nothing kept: what :func:`compile_ptx` types the kernels from."""

    def __init__(self):
        super().__init__(np.ascontiguousarray, np.empty)

    def table(self, a):
        return np.ascontiguousarray(a)

    def buffer(self, role, shape, dtype=np.float64):
        return np.empty(tuple(shape), dtype)


#: Most element tables one process keeps on the device (the oldest goes first).
MAX_TABLES = 64
_MEMORY = None


def device_memory() -> DeviceMemory:
    """This process's DeviceMemory (numba.cuda's to_device and device_array)."""
    global _MEMORY
    if _MEMORY is None:
        _MEMORY = DeviceMemory(_cuda().to_device, _cuda().device_array)
    return _MEMORY


def release_device_memory() -> None:
    """Let go of every table and buffer kept on the device (a long-lived process done with GPU work)."""
    global _MEMORY
    _MEMORY = None


def _launch(n_work: int, per_thread_bytes: int, cap: int = MAX_THREADS) -> tuple[int, int]:
    """(blocks, threads) for n_work items with ``per_thread_bytes`` of device scratch per thread."""
    n_threads = max(1, min(n_work, cap, SCRATCH_BYTES // max(per_thread_bytes, 1)))
    tpb = min(THREADS_PER_BLOCK, n_threads)
    blocks = (n_threads + tpb - 1) // tpb
    return blocks, tpb


def _part(a) -> np.ndarray:
    """``a`` as a contiguous array, or contract.ABSENT for a part that is None."""
    return ABSENT if a is None else np.ascontiguousarray(a)


def device_elements(mem, balls: ElementSet) -> ElementSet:
    """The element set as a kernel argument: every part a table in ``mem`` (on the device once per job),
    contract.ABSENT for a part it lacks and for the warm starts (each thread's are its row of the launch's warm
    starts); the kernels make those None again (cuda_kernels.element_set)."""
    return ElementSet(mem.table(_part(balls.balls)), mem.table(_part(balls.exponents)), float(balls.smoothing),
                      mem.table(_part(balls.slices)), mem.table(_part(balls.speed_table)), float(balls.omega),
                      mem.table(ABSENT), mem.table(_part(balls.four_point)))


def device_tables(mem, elements) -> Elements:
    """contract.Elements with every table in ``mem`` (on the device once per job)."""
    return Elements(device_elements(mem, elements.balls), mem.table(elements.ball_row), mem.table(elements.life),
                    float(elements.C0))


def warm_starts(balls: ElementSet, n_threads: int) -> np.ndarray:
    """Every thread's warm starts for the balls at speed, zeroed (every ball cold, high_speed.new_warm); a
    (n_threads, 1, 1) stand-in for a quasi-static bearing (indexed, never read)."""
    if balls.speed_table is None:
        return np.zeros((n_threads, 1, 1))
    n_balls = max(balls.balls.shape[1], 1)
    return np.zeros((n_threads, warm_rows(n_balls), n_balls))


def _inputs(mem, cases: CaseBlock, results):
    """``cases`` with its inputs, segments and speeds copied into ``mem`` and ``results`` in place of its own."""
    if cases.operating is not None or cases.ball_sizes is not None:
        raise ValueError("device='cuda': cases with their own operating clearance and preload (a mounted bearing "
                         "over temperatures or speeds, montecarlo) run on the CPU for now; use device='cpu'")
    return CaseBlock(mem.data(cases.inputs), mem.data(cases.segments), mem.data(np.asarray(cases.speeds, np.float64)),
                     ABSENT, ABSENT, results)


def _outputs(mem, results):
    """A results record's device arrays, kept across blocks (not copied there: the kernels write every case's)."""
    return type(results)(*(mem.buffer(f"results.{name}", a.shape, a.dtype) for name, a in zip(results._fields,
                                                                                              results)))


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


def _solve_args(mem, balls, cases, settings, warm):
    """(blocks, threads per block, the solve kernel's arguments, the device results) in ``mem``."""
    blocks, tpb, _ = solve_plan(balls, cases)
    spin_all = mem.data(warm_starts(balls, blocks * tpb))
    outs = _outputs(mem, cases.results)._replace(q=mem.data(cases.results.q))  # the warm starts
    args = (device_elements(mem, balls), _inputs(mem, cases, outs), spin_all, settings, bool(warm))
    return blocks, tpb, args, outs


def _map_args(mem, elements, cases, given_load, settings):
    """(blocks, threads per block, the map kernel's arguments, the device results) in ``mem``: one thread per
    continuation run, each with its ThreadRows row."""
    shape = scratch_shape(elements, cases)
    with_speed = elements.balls.speed_table is not None
    blocks, tpb, _ = map_plan(elements, cases)
    outs = _outputs(mem, cases.results)
    rows = thread_rows(mem, shape, blocks * tpb, cases.results.n_loaded.dtype, with_speed)
    args = (device_tables(mem, elements), _inputs(mem, cases, outs), bool(given_load), settings,
            mem.data(np.zeros(1, np.int64)), rows)
    return blocks, tpb, args, outs


def _copy_back(host, dev, wanted=None) -> None:
    """Every device array of the results record ``dev`` into its host twin in ``host``; with ``wanted`` (a record
    of bools of the same fields) only those (the stored variables: issue 46 item 2)."""
    for i, (h, d) in enumerate(zip(host, dev)):
        if wanted is None or wanted[i]:
            d.copy_to_host(h)


def solve_sweep_cuda(balls, cases, settings, warm):
    """sweep.solve_sweep on the GPU, in place (the same arguments but the block size): every row of
    ``cases.inputs`` (N, 5; N, N*mm) solved into ``cases.results`` (contract.Solutions: q (N, 5; mm, rad; warm
    starts there when ``warm``), f, Kb (N/mm, N*mm/rad, N/rad), status, iterations, relative residual and kernel
    evaluations); with a speed table case i runs at ``cases.speeds[i]`` rad/s. CudaUnavailable without a usable
    GPU."""
    require_cuda()
    if cases.inputs.shape[0] == 0:
        return
    blocks, tpb, args, outs = _solve_args(device_memory(), balls, cases, settings, warm)
    kernel("solve")[blocks, tpb](*args)
    _copy_back(cases.results, outs)


def map_sweep_cuda(elements, cases, given_load, settings, stop, wanted=None):
    """sweep.map_sweep on the GPU, in place, with the same arguments and results (contract.Elements, a
    contract.CaseBlock of contract.Results): one thread per continuation run (``cases.segments``; loads in N,
    N*mm or displacements in mm, rad; speeds rad/s). ``stop[0] != 0`` before the launch leaves the block
    untouched (incomplete); Ctrl-C during a launch is seen at the next block. ``wanted`` (a contract.Results of
    bools; None: all) names the outputs copied back; the others stay as they were on the host. CudaUnavailable
    without a usable GPU."""
    require_cuda()
    if cases.segments.shape[0] <= 1 or stop[0] != 0:
        return
    blocks, tpb, args, outs = _map_args(device_memory(), elements, cases, given_load, settings)
    kernel("map")[blocks, tpb](*args)
    _copy_back(cases.results, outs, wanted)


def passage_sweep_cuda(elements, positions, cases, given_load, settings, stop):
    """sweep.passage_sweep on the GPU, in place, with the same arguments and results (contract.Elements,
    contract.Positions, a contract.CaseBlock of contract.PassageResults): one thread per operating point (loads in
    N, N*mm or displacements in mm, rad), its cage positions in turn. ``stop[0] != 0`` before the launch leaves
    the block untouched (incomplete); Ctrl-C during a launch is seen at the next block. CudaUnavailable without a
    usable GPU."""
    require_cuda()
    n = cases.inputs.shape[0]
    if n == 0 or stop[0] != 0:
        return
    mem = device_memory()
    shape = scratch_shape(elements, cases)
    with_speed = elements.balls.speed_table is not None
    blocks, tpb = _launch(n, thread_bytes(shape, with_speed))
    outs = _outputs(mem, cases.results)
    dev_positions = Positions(mem.table(_part(positions.tables)), mem.table(_part(positions.slices)),
                              mem.table(_part(positions.speed_tables)))
    rows = thread_rows(mem, shape, blocks * tpb, cases.results.n_loaded.dtype, with_speed)
    kernel("passage")[blocks, tpb](device_tables(mem, elements), dev_positions, _inputs(mem, cases, outs),
                                   bool(given_load), settings, rows)
    _copy_back(cases.results, outs)


def compile_ptx(kind: str, example_args: tuple, cc=(9, 0)) -> str:
    """The PTX of the ``kind`` ("solve" or "map") kernel, typed from the host records ``example_args``
    (solve_sweep_cuda's or map_sweep_cuda's arguments), for compute capability ``cc``: a check that the engine
    lowers for the real CUDA target. Needs numba-cuda with libnvvm (a CUDA toolkit or the
    nvidia-cuda-nvcc/nvrtc wheels); the device functions it calls are compiled for the current device, so on a
    machine without a GPU the caller must provide one's compute capability (tests/test_cuda.py)."""
    import numba

    _cuda()
    if kind == "solve":
        args = _solve_args(HostMemory(), *example_args)[2]
    else:
        args = _map_args(HostMemory(), *example_args[:4])[2]
    sig = tuple(numba.typeof(a) for a in args)
    ptx, _ = cuda.compile_ptx(kernel(kind).py_func, sig, cc=cc)
    return ptx
