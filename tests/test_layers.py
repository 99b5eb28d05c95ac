"""The package's imports run one way: no module imports, directly or through others, one that imports it.

Every ``from .x import`` / ``import fastbearing.x`` is counted, including the
ones inside functions (a lazy import still ties the two modules together).
"""

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "fastbearing"


def _module_name(path: Path) -> str:
    rel = path.relative_to(PACKAGE).with_suffix("")
    parts = [p for p in rel.parts if p != "__init__"]
    return ".".join(parts) or "__init__"


def import_graph() -> dict[str, set[str]]:
    modules = {_module_name(p): p for p in PACKAGE.rglob("*.py")}
    graph = {}
    for name, path in modules.items():
        package = name.rsplit(".", 1)[0] if path.name != "__init__.py" and "." in name else (
            name if path.name == "__init__.py" else "")
        targets = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.level > 0:
                base = package.split(".")[: len(package.split(".")) - (node.level - 1)] if package else []
                base = ".".join(p for p in base if p and p != "__init__")
                mod = ".".join(p for p in (base, node.module or "") if p)
                candidates = [mod] if mod else []
                candidates += [".".join(p for p in (mod, a.name) if p) for a in node.names]
                targets |= {c for c in candidates if c in modules}
            elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("fastbearing."):
                mod = node.module[len("fastbearing."):]
                targets |= {c for c in [mod] + [f"{mod}.{a.name}" for a in node.names] if c in modules}
            elif isinstance(node, ast.Import):
                targets |= {a.name[len("fastbearing."):] for a in node.names
                            if a.name.startswith("fastbearing.") and a.name[len("fastbearing."):] in modules}
        graph[name] = targets - {name, "__init__"}
    return graph


def find_cycle(graph):
    state = {}
    stack = []

    def visit(node):
        state[node] = "open"
        stack.append(node)
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == "open":
                return stack[stack.index(nxt):] + [nxt]
            if nxt not in state:
                cycle = visit(nxt)
                if cycle:
                    return cycle
        stack.pop()
        state[node] = "done"
        return None

    for node in sorted(graph):
        if node not in state:
            cycle = visit(node)
            if cycle:
                return cycle
    return None


#: The layers, lowest first: a module may import from its own layer and the ones below, never above.
#: Leaves every layer reads (units, status codes, settings, validation, files) sit below the engine;
#: ``api`` (solve, stiffness) is what analysis builds on; the command line is on top.
LAYERS = (("config", "status", "dofs", "validate", "files", "_cache", "_numba_cache", "_prebuilt", "boundary"), ("engine",), ("model",), ("api",),
          ("analysis",), ("jobs",), ("report",), ("cli", "__init__"))


def _layer(module: str) -> int:
    top = module.split(".")[0]
    return next(i for i, names in enumerate(LAYERS) if top in names)


def test_the_layers_import_downwards_only():
    """engine/ (kernels, solver, sweeps) < model/ (bearings, geometry) < api < analysis/ (life, contacts,
    shaft) < jobs/ (runner, storage, grid, maps, passage tables) < report/ (pictures, paper, export, text
    reports) < the command line: the layout shows the layers, and the imports keep to them (issue 35)."""
    graph = import_graph()
    upward = sorted(f"{a} -> {b}" for a, targets in graph.items() for b in targets if _layer(b) > _layer(a))
    assert not upward, upward


def test_no_import_circles():
    graph = import_graph()
    assert "api" in graph and "model.bearing" in graph["api"]  # the parser sees the package's imports
    cycle = find_cycle(graph)
    assert cycle is None, " -> ".join(cycle)


def test_only_the_storage_module_touches_an_hdf5_handle():
    """The stores are reached through storage.py (PartFile, ResultFile, create, finish): no other module of
    the package imports h5py, so a second store (zarr) is added in one place (issue 35)."""
    graph_sources = {path.name: path.read_text() for path in PACKAGE.rglob("*.py")}
    users = sorted(name for name, text in graph_sources.items()
                   if name != "storage.py" and any(line.strip().startswith(("import h5py", "from h5py"))
                                                    for line in text.splitlines()))
    assert not users, users


def test_every_module_with_kernels_is_in_the_cache_hash():
    """A module whose @njit code (or a constant compiled into it) is not hashed would leave its callers'
    cached machine code stale when it changes (numba tracks a function's own file only). The hashed set is
    found from the sources; here it is checked against the import graph, independently: every module with
    kernel code and every package module it imports, transitively (schema.py's table rows among them)."""
    import re

    from fastbearing import _cache

    graph = import_graph()
    jitted = {_module_name(path) for path in PACKAGE.rglob("*.py") if path.name != "_cache.py"
              and re.search(r"^\s*@(njit|overload|intrinsic|generated_jit)\b", path.read_text(), re.M)}
    needed, todo = set(jitted), list(jitted)
    while todo:
        for imported in graph.get(todo.pop(), ()):
            if imported not in needed:
                needed.add(imported)
                todo.append(imported)
    hashed = {name[:-3].replace("/", ".") for name in _cache.kernel_modules()}
    needed -= {"_cache", "engine"}  # the hasher itself (config.py starts it); the layer's empty __init__
    assert needed <= hashed, sorted(needed - hashed)
    assert {"engine.schema", "engine.kernel", "engine.high_speed", "engine.solver", "engine.sweep"} <= hashed
    assert "cli" not in hashed and not any(name.startswith(("model", "jobs")) for name in hashed)


def test_every_kernel_a_caller_can_reach_is_cached_on_disk():
    """A kernel compiled without numba's cache is compiled again in every process that calls it from
    Python: the high-speed ball pass once cost 11-16 s on every `solve --balls --speed` (issue 33)."""
    import importlib
    import importlib.util

    from numba.core.registry import CPUDispatcher

    from fastbearing import _cache

    uncached = []
    for name in _cache.kernel_modules():
        if name == "engine/cuda_kernels.py" and importlib.util.find_spec("numba_cuda") is None:
            continue  # the CUDA kernels' module imports numba.cuda (engine.gpu imports it only for device="cuda")
        module = importlib.import_module(f"fastbearing.{name[:-3].replace('/', '.')}")
        for attr, obj in vars(module).items():
            if (isinstance(obj, CPUDispatcher) and obj.__module__ == module.__name__
                    and obj.targetoptions.get("inline", "never") != "always"
                    and type(obj._cache).__name__ == "NullCache"):
                uncached.append(f"{name}:{attr}")
    assert not uncached, uncached


def test_no_python_code_calls_an_uncached_kernel():
    """An ``inline="always"`` kernel is not cached (numba inlines it into its callers, which are); called from
    Python it is compiled on its own, again in every process: `solve --speed --life` and `--balls` said they
    were compiling on every run (analysis/contacts.py called high_speed.standing_still; issue 45). Every call
    in plain Python code (outside @njit, @overload, @intrinsic and CUDA kernels) to a function that resolves
    to an uncached dispatcher is reported."""
    import ast
    import importlib

    from numba.core.registry import CPUDispatcher

    def uncached(obj):
        return isinstance(obj, CPUDispatcher) and type(obj._cache).__name__ == "NullCache"

    compiled_code = ("jit", "overload", "intrinsic", "vectorize")
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        name = _module_name(path)
        module = importlib.import_module("fastbearing" if name == "__init__" else f"fastbearing.{name}")
        names = vars(module)

        def visit(node, in_kernel):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)) and not in_kernel:
                decorators = [ast.unparse(d) for d in getattr(node, "decorator_list", ())]
                in_kernel = any(mark in d for d in decorators for mark in compiled_code)
            if isinstance(node, ast.Call) and not in_kernel:
                f, target = node.func, None
                if isinstance(f, ast.Name):
                    target = names.get(f.id)
                elif isinstance(f, ast.Attribute) and isinstance(f.value, ast.Name) and f.value.id in names:
                    target = getattr(names[f.value.id], f.attr, None)
                if uncached(target):
                    found.append(f"{name}:{node.lineno} {ast.unparse(f)}")
            for child in ast.iter_child_nodes(node):
                visit(child, in_kernel)

        visit(ast.parse(path.read_text()), False)
    assert not found, found


def test_stale_kernel_cache_is_dropped_also_under_numba_cache_dir(tmp_path):
    """A changed kernel source must never run old machine code, wherever numba keeps its cache."""
    import os
    import subprocess
    import sys

    script = ("from fastbearing import _cache; import sys; f = _cache.cache_folder(); "
              "print(f); (f / 'kernel.ball_loop-1.py311.nbi').write_text('stale') if sys.argv[1] == 'plant' else None; "
              "(f / _cache._STAMP_NAME).write_text('old hash') if sys.argv[1] == 'plant' else None")
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    folder = subprocess.run([sys.executable, "-c", "import fastbearing; " + script, "plant"], env=env,
                            capture_output=True, text=True, check=True).stdout.strip()
    from pathlib import Path

    folder = Path(folder)
    assert folder.is_relative_to(tmp_path / "cache")
    assert (folder / "kernel.ball_loop-1.py311.nbi").exists()
    subprocess.run([sys.executable, "-c", "import fastbearing.engine.kernel"], env=env, check=True)  # the first kernel
    assert not (folder / "kernel.ball_loop-1.py311.nbi").exists()
    from fastbearing import _cache

    assert (folder / "fastbearing-numba-cache.stamp").read_text() == _cache.source_hash()


def test_kernels_without_reference_counting_never_return_arrays(tmp_path):
    """A function compiled with numba's reference counting off (config.REFCOUNT) hands out arrays without
    counting them: a counted caller would later release a reference it never got and free live memory.
    Allocation fails to compile there; a returned array (or a tuple holding one) is checked here, over
    every signature the quasi-static, high-speed, roller and map paths compiled."""
    from numba.core import types
    from numba.core.registry import CPUDispatcher

    import fastbearing as fb
    from fastbearing.engine import high_speed
    from fastbearing.engine import kernel
    from fastbearing.engine import linalg
    from fastbearing.engine import solver
    from fastbearing.engine import sweep

    bearings = PACKAGE.parent / "fastbearing" / "catalogue"
    fb.solve(fb.Bearing.preset("gunduz2013", "DB"), [100.0, 0.0, 500.0, 0.0, 1e3])
    fb.solve(fb.load_bearing(bearings / "7014C-DB.toml"), [100.0, 0.0, 500.0, 0.0, 1e3], speed=12000.0)
    fb.solve(fb.load_bearing(bearings / "30206-TDO.toml"), [1000.0, 0.0, 500.0, 0.0, 0.0])
    import tomllib

    spindle = tomllib.loads((PACKAGE.parent / "data" / "examples" / "spindle-7014-speed.toml").read_text())
    spindle["loadmap"] = {"given": "load", "speed": [0.0, 12000.0], "Fx": 500.0,
                          "Fz": {"start": 400.0, "stop": 600.0, "num": 3}, "life": True}
    fb.loadmap(spindle, tmp_path / "map.h5", progress=False)

    def holds_array(t):
        if isinstance(t, types.ArrayCompatible):
            return True
        return isinstance(t, types.BaseTuple) and any(holds_array(x) for x in t)

    uncounted = []
    for module in (high_speed, kernel, linalg, solver, sweep):
        for name, obj in vars(module).items():
            if isinstance(obj, CPUDispatcher) and obj.targetoptions.get("_nrt") is False:
                uncounted.append(name)
                for sig, cres in obj.overloads.items():
                    assert not holds_array(cres.signature.return_type), (module.__name__, name, sig)
    assert {"solve_case", "ball_loop", "map_runs", "ldl_solve"} <= set(uncounted)
