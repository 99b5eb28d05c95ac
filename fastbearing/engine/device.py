"""Where the many-case drivers run: "cpu" (the default) or "cuda" (one GPU through numba-cuda, engine/gpu.py).

Light on purpose: the command line imports it to name the error without loading numba; numba.cuda is imported
only by :func:`require_cuda`, i.e. only when a caller asks for the GPU.
"""

from __future__ import annotations

import importlib.util
import os

#: The devices a caller may ask for.
DEVICES = ("cpu", "cuda")


class CudaUnavailable(RuntimeError):
    """``device="cuda"`` was asked for and cannot run here; the message (one line) names what is missing:
    numba-cuda, a CUDA driver or a GPU."""


def simulated() -> bool:
    """True under numba's CUDA simulator (NUMBA_ENABLE_CUDASIM=1): kernels run in Python, on the CPU."""
    return os.environ.get("NUMBA_ENABLE_CUDASIM", "0") not in ("", "0")


def import_cuda():
    """numba.cuda. numba-cuda (0.30 at least) registers an overload for ``np.row_stack`` at import, which numpy 2.5
    removed: the alias is put back first (the one place that knows)."""
    import numpy as np

    if not hasattr(np, "row_stack"):
        np.row_stack = np.vstack
    from numba import cuda

    return cuda


def require_cuda():
    """numba.cuda, ready to launch kernels; CudaUnavailable naming what is missing otherwise (numba-cuda not
    installed, no CUDA driver, no GPU). The simulator counts as usable."""
    if importlib.util.find_spec("numba_cuda") is None:
        raise CudaUnavailable("device 'cuda' needs numba-cuda, which is not installed "
                              "(pip install \"fastbearing[cuda]\")")
    try:
        cuda = import_cuda()
    except Exception as err:  # a broken install: say what failed to import
        reason = " ".join(str(err).split())    # one line, whatever the CUDA bindings printed
        raise CudaUnavailable(f"device 'cuda': numba-cuda failed to import ({type(err).__name__}: {reason})") from None
    if simulated():
        return cuda
    try:
        cuda.current_context()
    except Exception as err:
        reason = " ".join(str(err).split())
        if "driver" in reason.lower():
            what = "no CUDA driver"
        elif "no cuda" in reason.lower() or "device" in reason.lower():
            what = "no CUDA GPU"
        else:
            what = "no usable CUDA GPU"
        raise CudaUnavailable(f"device 'cuda': {what} ({reason})") from None
    return cuda


def describe() -> str:
    """One line: the GPU, its driver's CUDA version and numba-cuda's version (or that it is the simulator)."""
    from importlib.metadata import version

    cuda = require_cuda()
    nc = version("numba-cuda")
    if simulated():
        return f"CUDA simulator (NUMBA_ENABLE_CUDASIM=1, no GPU), numba-cuda {nc}"
    dev = cuda.get_current_device()
    major, minor = cuda.cudadrv.driver.driver.get_version()
    name = dev.name.decode() if isinstance(dev.name, bytes) else dev.name
    return (f"{name} (compute capability {dev.compute_capability[0]}.{dev.compute_capability[1]}), "
            f"driver CUDA {major}.{minor}, numba-cuda {nc}")
