"""The engine on CUDA: the CPU's own kernels compiled as numba-cuda device functions, thin drivers around them.

Nothing here is physics. numba-cuda compiles any ``@njit`` function (and every ``@overload`` of the
generic target) that a CUDA kernel calls as a device function from the same Python source, so the three
kernels (engine/cuda_kernels.py: module-level, cached on disk) call the CPU's per-case bodies:
:func:`fastbearing.engine.sweep.solve_into` (one case per thread, as sweep.solve_sweep does per case),
:func:`fastbearing.engine.sweep.map_runs` (one GPU segment of a map per thread: a continuation run cut short,
:func:`device_segments`; sweep.map_sweep runs whole runs per group) and
:func:`fastbearing.engine.sweep.passage_point` (one operating point per thread): statuses, warm starts, the
tangent/curved predictors along a map line, the high-speed balls, roller rows and the life variables are the
CPU's code. The drivers here take and pass the same records as the CPU's (engine/contract.py); a
thread's scratch is sized by the same contract.scratch_shape: the solver's and the predictor's as
``cuda.local.array``, the per-element record, life sums, the outer contacts' summary and the balls' warm starts
element-major (thread t's are column t of device arrays, :data:`ThreadRows`). A map's
continuation runs are cut into GPU segments of at most :data:`SEGMENT_CASES` cases, one per thread, in blocks
sized for the device (:func:`device_segments`, :func:`device_chunk`; docs/gpu.md).

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
from .high_speed import warm_size
from .schema import ElementSet
from .device import CudaUnavailable, describe, import_cuda, require_cuda, simulated  # noqa: F401 (re-exported)

#: Threads per block of both kernels (each thread runs a whole solve: register-heavy code).
THREADS_PER_BLOCK = 128
#: Most threads of the cold-solve kernel; more cases loop (grid stride), so scratch stays bounded.
MAX_THREADS = 1 << 20
#: Device memory the per-thread scratch of one launch may take (bytes): bounds the threads at speed.
SCRATCH_BYTES = 1 << 30
#: Longest continuation segment one GPU thread runs in a map (cases): the CPU's runs (grid.segment_starts: a line,
#: or LINE_SEGMENT cases of one) are cut into near-equal pieces of at most this many, each starting cold
#: (:func:`device_segments`). Measured on the CPU (bench/gpu_segments.py, docs/gpu.md): pieces of 8 take 1.89 Newton
#: iterations a case against 1.34 on the CPU's runs of 99 (about 1.2x the time; one case per thread, all cold:
#: 5.09) and give the 1M example 131 300 threads (10: 1.75 and 101 000).
SEGMENT_CASES = 8
#: Threads of one map launch at least, where a block has more runs: a block's runs are split into launches of at
#: least this many threads (at most MAX_PARTS), each on its own stream, so that one launch's copies back overlap
#: the next one's compute. About four times the threads an H100/H200 keeps resident for this register-heavy code.
PART_THREADS = 1 << 17
#: Most launches (and streams) a map block is split into.
MAX_PARTS = 4
#: Cases per block of a map on the GPU at least (the config's chunk where larger): the 1M example in one block.
DEVICE_CHUNK = 1 << 20


#: numba.cuda once imported (:func:`_cuda`).
cuda = None


def _cuda():
    """numba.cuda (fastbearing.engine.device.import_cuda), kept as this module's global."""
    global cuda
    if cuda is None:
        cuda = import_cuda()
    return cuda


def kernel(kind: str):
    """The CUDA kernel of ``kind`` ("solve", "map", "passage" or "narrow"): engine/cuda_kernels.py's module-level
    kernels, cached on disk by numba-cuda (imported here: it imports numba.cuda)."""
    _cuda()
    from . import cuda_kernels

    return {"solve": cuda_kernels.solve_kernel, "map": cuda_kernels.map_kernel,
            "passage": cuda_kernels.passage_kernel, "narrow": cuda_kernels.narrow_kernel}[kind]


# -- host side -------------------------------------------------------------------------------------------------------

#: One launch's per-thread scratch in device memory (contract.Scratch's arrays but the solver's and the predictor's,
#: which are each thread's local arrays): sized from contract.scratch_shape. Element-major, the thread last, so that
#: neighbouring threads touching the same element touch neighbouring addresses (the per-element record, written
#: at every kernel evaluation, the life sums, the outer contacts' summary): ``ball_load``, ``contact_angle``
#: (record, T), ``sums`` (life_rows, 2, T), ``outer_load``, ``outer_count`` (rows, T), the balls' warm starts
#: ``spin`` (high_speed.warm_size, T: each thread's flat warm scratch a column); thread t's are ``[..., t]``.
#: ``table`` (T, N_BALL_COLUMNS, n_balls) and ``slices`` (T, N_SLICE_COLUMNS, n_slices): each thread's own copies
#: of the element tables where a block's cases carry their own operating values (CaseBlock.operating; the kernel
#: fills them from the shared tables, then sweep.with_operating writes each case's values), contract.ABSENT else.
ThreadRows = namedtuple("ThreadRows", "ball_load contact_angle sums spin outer_load outer_count table slices")


def own_table_bytes(balls, cases) -> int:
    """Device memory of one thread's own tables (bytes): the ball and slice tables where ``cases`` carry their
    own operating values, else 0."""
    if cases.operating is None:
        return 0
    return balls.balls.nbytes + (balls.slices.nbytes if balls.slices is not None else 0)


def thread_bytes(shape: ScratchShape, with_speed: bool, own: int = 0) -> int:
    """Device memory of one thread's ThreadRows (bytes) for a Scratch of ``shape`` (``own``: its own tables')."""
    warm = shape.warm_size if with_speed else 0
    return 8 * (2 * shape.record + 2 * shape.life_rows + warm + 2 * shape.rows) + own


def thread_rows(mem, shape: ScratchShape, n_threads: int, counts_dtype, with_speed: bool, part: int = 0,
                own=None) -> ThreadRows:
    """The ThreadRows of ``n_threads`` threads in ``mem`` (:class:`DeviceMemory`), launch ``part``'s own (each
    launch of a block its own buffers, kept across blocks: concurrent launches never share a thread's scratch,
    and every launch gets C-contiguous arrays, so one kernel specialisation serves them all); the balls' warm
    starts zeroed: every ball cold, new_warm. ``own``: None, or the element set whose ball and slice tables each
    thread copies (a block whose cases carry their own operating values)."""
    T = n_threads
    spin = np.zeros((shape.warm_size if with_speed else 1, T))
    role = f"rows{part}."
    table = slices = mem.table(ABSENT)
    if own is not None:
        table = mem.buffer(role + "table", (T,) + own.balls.shape)
        if own.slices is not None:
            slices = mem.buffer(role + "slices", (T,) + own.slices.shape)
    return ThreadRows(mem.buffer(role + "ball_load", (shape.record, T)),
                      mem.buffer(role + "contact_angle", (shape.record, T)),
                      mem.buffer(role + "sums", (shape.life_rows, 2, T)), mem.data(spin),
                      mem.buffer(role + "outer_load", (shape.rows, T)),
                      mem.buffer(role + "outer_count", (shape.rows, T), counts_dtype), table, slices)


class DeviceMemory:
    """Where a launch's arrays live, kept across blocks (issue 46 item 2): ``table`` uploads a read-only table
    once per content (the element tables of a job, whichever block asks); ``buffer`` allocates a result or
    scratch array once per role, shape and dtype and hands the same one to the next block (the kernels write
    every entry they read back, so nothing is copied there); ``data`` copies a block's own inputs each time;
    ``pin`` page-locks a host array the results are copied into, once per array (``pin_host``: None where
    there is nothing to lock, as in the simulator), so that a copy on a stream is asynchronous; ``streams``
    hands out the same CUDA streams block after block. One per process (:func:`device_memory`): at most one
    buffer per role, :data:`MAX_TABLES` tables, and at most :data:`MAX_PINNED` locked host arrays of
    :data:`PINNED_BYTES` together (the oldest let go first; :func:`release_device_memory` lets go of all)."""

    def __init__(self, put, alloc, pin_host=None, new_stream=None):
        self.put, self.alloc, self.pin_host, self.new_stream = put, alloc, pin_host, new_stream
        self.tables, self.buffers, self.pinned, self.held_streams = {}, {}, {}, []

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

    def pin(self, a: np.ndarray) -> None:
        """Page-lock the host array ``a`` is a view of (the runner's block buffers: views of arrays it keeps for
        the whole job), once; where locking fails the copies are merely synchronous."""
        if self.pin_host is None:
            return
        base = a
        while isinstance(base.base, np.ndarray):
            base = base.base
        key = (base.__array_interface__["data"][0], base.nbytes)
        if key in self.pinned or not base.flags.c_contiguous or not 0 < base.nbytes <= PINNED_BYTES:
            return
        while self.pinned and (len(self.pinned) >= MAX_PINNED
                               or sum(k[1] for k in self.pinned) + base.nbytes > PINNED_BYTES):
            self.pinned.pop(next(iter(self.pinned)))   # unlocked when its last reference goes
        try:
            self.pinned[key] = self.pin_host(base)
        except Exception:  # noqa: BLE001 - e.g. already registered by the caller: pageable, still right
            self.pinned[key] = None

    def streams(self, n: int) -> list:
        """``n`` CUDA streams, the same ones for every block (0, the default stream, without ``new_stream``)."""
        if self.new_stream is None:
            return [0] * n
        while len(self.held_streams) < n:
            self.held_streams.append(self.new_stream())
        return self.held_streams[:n]


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
#: Most host arrays one process keeps page-locked (two block buffers of a job's 20-odd variables fit).
MAX_PINNED = 64
#: Most host memory one process keeps page-locked (bytes): the 1M map's two block buffers take 0.7 GB.
PINNED_BYTES = 1 << 33
_MEMORY = None


def device_memory() -> DeviceMemory:
    """This process's DeviceMemory (numba.cuda's to_device and device_array)."""
    global _MEMORY
    if _MEMORY is None:
        cuda = _cuda()
        pin = None if simulated() else _page_lock
        _MEMORY = DeviceMemory(cuda.to_device, cuda.device_array, pin, cuda.stream)
    return _MEMORY


def _page_lock(a: np.ndarray):
    """numba-cuda's registration of the host array ``a`` as page-locked memory (undone when it is dropped)."""
    return cuda.current_context().mempin(a, a.ctypes.data, a.nbytes, mapped=False)


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


def device_segments(segments: np.ndarray, longest: int = SEGMENT_CASES) -> np.ndarray:
    """The GPU's continuation segments of a map block: every run of ``segments`` (grid.segment_starts: offsets of
    the runs' first cases, then the block's size) cut into the fewest near-equal pieces of at most ``longest``
    cases (a run of 99 into 13 of 7 or 8). Each piece is one GPU thread's and starts cold. A run is cut by its own
    length alone, so the GPU's results do not depend on the block size either; the CPU keeps ``segments``."""
    segments = np.asarray(segments, np.int64)
    starts, lengths = segments[:-1], np.diff(segments)
    pieces = np.maximum(-(-lengths // longest), 1)
    run = np.repeat(np.arange(starts.shape[0]), pieces)
    k = np.arange(run.shape[0]) - np.repeat(np.cumsum(pieces) - pieces, pieces)
    return np.append(starts[run] + k * lengths[run] // pieces[run], segments[-1]).astype(np.int64)


def device_chunk(chunk: int) -> int:
    """A map's block size on the GPU (cases) for the config's ``chunk``: at least DEVICE_CHUNK (blocks sized for
    the device: enough runs for PART_THREADS threads and more, results and inputs of a few 100 MB)."""
    return max(int(chunk), DEVICE_CHUNK)


def _part(a) -> np.ndarray:
    """``a`` as a contiguous array, or contract.ABSENT for a part that is None."""
    return ABSENT if a is None else np.ascontiguousarray(a)


def device_elements(mem, balls: ElementSet) -> ElementSet:
    """The element set as a kernel argument: every part a table in ``mem`` (on the device once per job),
    contract.ABSENT for a part it lacks and for the warm starts (each thread's are its column of the launch's warm
    starts); the kernels make those None again (cuda_kernels.element_set)."""
    return ElementSet(mem.table(_part(balls.balls)), mem.table(_part(balls.exponents)), float(balls.smoothing),
                      mem.table(_part(balls.slices)), mem.table(_part(balls.speed_table)), float(balls.omega),
                      mem.table(ABSENT), mem.table(_part(balls.four_point)))


def device_tables(mem, elements) -> Elements:
    """contract.Elements with every table in ``mem`` (on the device once per job)."""
    return Elements(device_elements(mem, elements.balls), mem.table(elements.ball_row), mem.table(elements.life),
                    float(elements.C0))


def warm_starts(balls: ElementSet, n_threads: int) -> np.ndarray:
    """Every thread's warm starts for the balls at speed, zeroed (every ball cold, high_speed.new_warm), thread
    t's flat warm scratch column t (element-major); a (1, n_threads) stand-in for a quasi-static bearing
    (indexed, never read)."""
    if balls.speed_table is None:
        return np.zeros((1, n_threads))
    n_balls = max(balls.balls.shape[1], 1)
    return np.zeros((warm_size(n_balls), n_threads))


def _inputs(mem, cases: CaseBlock, results):
    """``cases`` with its inputs, segments, speeds and own operating values (ABSENT where None) copied into
    ``mem`` and ``results`` in place of its own."""
    return CaseBlock(mem.data(cases.inputs), mem.data(cases.segments), mem.data(np.asarray(cases.speeds, np.float64)),
                     mem.data(_part(cases.operating)), mem.data(_part(cases.ball_sizes)), results)


def device_dtype(dtype) -> np.dtype:
    """The kernels' dtype of a result the host holds in ``dtype``: float64 for every real value (a map stored in
    float32 gets its float32 copy made on the device, :func:`_copy_back`), the host's own otherwise."""
    dtype = np.dtype(dtype)
    return np.dtype(np.float64) if dtype.kind == "f" else dtype


def _outputs(mem, results):
    """A results record's device arrays, kept across blocks (not copied there: the kernels write every case's)."""
    return type(results)(*(mem.buffer(f"results.{name}", a.shape, device_dtype(a.dtype))
                           for name, a in zip(results._fields, results)))


#: A block's launch: thread blocks, threads per block and the device memory it holds (bytes: the element tables,
#: the block's inputs and results, every thread's scratch rows), and how many such launches the block makes (a
#: map block with more than 2 x PART_THREADS threads: its parts, each on its own stream; ``blocks`` is then the
#: largest part's).
LaunchPlan = namedtuple("LaunchPlan", "blocks threads_per_block device_bytes launches", defaults=(1,))


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
    per_thread = warm_size(n_balls) * 8 if spinning else 0
    blocks, tpb = _launch(cases.inputs.shape[0], per_thread)
    return LaunchPlan(blocks, tpb, nbytes(balls) + nbytes(cases) + blocks * tpb * per_thread)


#: A map block on the GPU (:func:`map_parts`): the GPU's continuation segments (:func:`device_segments`), every
#: thread's scratch shape and bytes, and its launches, each (thread blocks, threads per block, first segment,
#: end segment); each launch has its own scratch (:func:`thread_rows`).
MapParts = namedtuple("MapParts", "segments shape per_thread launches")


def map_parts(elements, cases) -> MapParts:
    """How the map kernel runs the block ``cases``: its runs cut into GPU segments (one per thread), the
    segments split into at most MAX_PARTS launches of at least PART_THREADS threads each (consecutive segments:
    a launch's cases are one range of the block), each thread with its own scratch rows. The one place both
    :func:`map_plan` and :func:`map_sweep_cuda` size a block."""
    segments = device_segments(cases.segments)
    shape = scratch_shape(elements, cases)
    per_thread = thread_bytes(shape, elements.balls.speed_table is not None, own_table_bytes(elements.balls, cases))
    n_segments = max(segments.shape[0] - 1, 1)
    n_parts = min(max(n_segments // PART_THREADS, 1), MAX_PARTS)
    bounds = np.arange(n_parts + 1) * n_segments // n_parts
    launches = []
    for a, b in zip(bounds[:-1], bounds[1:]):
        blocks, tpb = _launch(int(b - a), per_thread * n_parts)   # the parts share SCRATCH_BYTES
        launches.append((blocks, tpb, int(a), int(b)))
    return MapParts(segments, shape, per_thread, launches)


def map_plan(elements, cases) -> LaunchPlan:
    """The map kernel's launches for the block ``cases`` (:func:`map_parts`; hosts can plan a device run from this
    without a GPU: bench/gpu_bench.py --plan): the largest launch's thread blocks, the device memory of the
    block (element tables, inputs, GPU segments, results in the kernels' dtypes and their float32 copies,
    every thread's scratch rows) and the number of launches."""
    parts = map_parts(elements, cases)
    results = cases.results
    device_results = sum(a.size * device_dtype(a.dtype).itemsize for a in results)
    narrowed = sum(a.nbytes for a in results if device_dtype(a.dtype) != a.dtype)
    rows = sum(blocks * tpb for blocks, tpb, *_ in parts.launches)
    blocks, tpb = max((p[:2] for p in parts.launches), key=lambda p: p[0] * p[1])
    return LaunchPlan(blocks, tpb, nbytes(elements) + nbytes(cases[:-1]) + parts.segments.nbytes + device_results
                      + narrowed + rows * parts.per_thread, len(parts.launches))


def _solve_args(mem, balls, cases, settings, warm):
    """(blocks, threads per block, the solve kernel's arguments, the device results) in ``mem``."""
    if cases.operating is not None or cases.ball_sizes is not None:
        raise ValueError("device='cuda': solve_many with each case's own clearance, preload or temperatures runs on "
                         "the CPU for now (load maps and montecarlo take them on the GPU); use device='cpu'")
    blocks, tpb = solve_plan(balls, cases)[:2]
    spin_all = mem.data(warm_starts(balls, blocks * tpb))
    outs = _outputs(mem, cases.results)._replace(q=mem.data(cases.results.q))  # the warm starts
    args = (device_elements(mem, balls), _inputs(mem, cases, outs), spin_all, settings, bool(warm))
    return blocks, tpb, args, outs


def _map_launches(mem, elements, cases, given_load, settings):
    """([(thread blocks, threads per block, the map kernel's arguments, (first case, end case))] one per launch
    of :func:`map_parts`, the device results) in ``mem``: each launch gets its own range of the GPU's segments
    and its own scratch (:func:`thread_rows` of its part), the rest is the block's."""
    parts = map_parts(elements, cases)
    with_speed = elements.balls.speed_table is not None
    outs = _outputs(mem, cases.results)
    dev_cases = _inputs(mem, cases._replace(segments=parts.segments), outs)
    tables, stop = device_tables(mem, elements), mem.data(np.zeros(1, np.int64))
    launches = []
    for part, (blocks, tpb, a, b) in enumerate(parts.launches):
        mine = thread_rows(mem, parts.shape, blocks * tpb, cases.results.n_loaded.dtype, with_speed, part,
                           elements.balls if cases.operating is not None else None)
        args = (tables, dev_cases._replace(segments=dev_cases.segments[a:b + 1]), bool(given_load), settings, stop,
                mine)
        launches.append((blocks, tpb, args, (int(parts.segments[a]), int(parts.segments[b]))))
    return launches, outs


def _copy_back(mem, host, dev, span, stream, wanted=None) -> None:
    """Cases ``span`` (first, end) of every device array of the results record ``dev`` into its host twin in
    ``host``, queued on ``stream``; with ``wanted`` (a record of bools of the same fields) only those (the stored
    variables: issue 46 item 2). A host array in float32 (a map stored so: the runner's buffers are) gets the
    device's float32 copy, made there (:func:`narrow`). A placeholder (a (1, ...) output the map does not
    keep) is not copied."""
    first, end = span
    n = dev.status.shape[0]
    for i, (name, h, d) in enumerate(zip(host._fields, host, dev)):
        if (wanted is not None and not wanted[i]) or h.shape[0] != n or end <= first:
            continue
        if h.dtype != d.dtype:
            d = narrow(mem, name, d, h.dtype, span, stream)
        mem.pin(h)
        d[first:end].copy_to_host(h[first:end], stream=stream)


def narrow(mem, name: str, d, dtype, span, stream):
    """The device array ``d`` (float64) with cases ``span`` converted to ``dtype`` (float32) on the device, in a
    buffer kept for ``name``, queued on ``stream``: round to nearest like numpy's cast, so the file holds the
    same bits whichever side converts; beyond float32's range +-inf, as the cast."""
    first, end = span
    out = mem.buffer(f"narrow.{name}", d.shape, dtype)
    size = (end - first) * int(np.prod(d.shape[1:], dtype=np.int64))
    src, dst = d[first:end].reshape(size), out[first:end].reshape(size)
    blocks = min((src.shape[0] + THREADS_PER_BLOCK - 1) // THREADS_PER_BLOCK, 4096)
    kernel("narrow")[max(blocks, 1), THREADS_PER_BLOCK, stream](src, dst)
    return out


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
    for h, d in zip(cases.results, outs):
        d.copy_to_host(h)


def map_sweep_cuda(elements, cases, given_load, settings, stop, wanted=None):
    """sweep.map_sweep on the GPU, in place, with the same arguments and results (contract.Elements, a
    contract.CaseBlock of contract.Results; loads in N, N*mm or displacements in mm, rad; speeds rad/s), but its
    own segmentation: the CPU's continuation runs (``cases.segments``) cut into GPU segments of at most
    SEGMENT_CASES cases, one per thread, each starting cold (:func:`device_segments`), in one launch or, with
    more than 2 x PART_THREADS segments, a few on their own streams, each launch's copies back queued behind it
    (so they overlap the next launch's compute). ``stop[0] != 0`` before the launch leaves the block untouched
    (incomplete); Ctrl-C during a launch is seen at the next block. ``wanted`` (a contract.Results of bools; None:
    all) names the outputs copied back; the others stay as they were on the host; a float32 host array gets
    float32 made on the device. CudaUnavailable without a usable GPU."""
    require_cuda()
    if cases.segments.shape[0] <= 1 or stop[0] != 0:
        return
    mem = device_memory()
    launches, outs = _map_launches(mem, elements, cases, given_load, settings)
    streams = mem.streams(len(launches))
    for (blocks, tpb, args, span), stream in zip(launches, streams):
        kernel("map")[blocks, tpb, stream](*args)
        _copy_back(mem, cases.results, outs, span, stream, wanted)
    _cuda().synchronize()   # every launch and copy of the block, whichever stream


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
    for h, d in zip(cases.results, outs):
        d.copy_to_host(h)


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
        args = _map_launches(HostMemory(), *example_args[:4])[0][0][2]
    sig = tuple(numba.typeof(a) for a in args)
    ptx, _ = cuda.compile_ptx(kernel(kind).py_func, sig, cc=cc)
    return ptx
