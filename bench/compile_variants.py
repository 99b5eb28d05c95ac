"""Compile time and cached variants of a newcomer's first four commands, from an empty numba cache (issue 35).

Not a timing benchmark: each step runs in one fresh process (so that numba's cache is the only thing
carried between them) with NUMBA_CACHE_DIR pointed at an empty folder, and the script reports each
step's wall time (almost all compilation) and, at the end, the compiled variants numba cached (.nbc
files) and their size. The steps, in order:

1. the first quasi-static solve (the paper's DB bearing, one load);
2. the first solve at speed (the shipped 7014C-DB spindle pair, 12 000 rpm);
3. the first load map of the shipped 1M example (its config, on a 3 x 3 x 3 grid: the same kernels);
4. the first roller solve (the shipped 30206 TDO pair);
5. the first ball-passage table (the shipped gunduz2013-passage example, 16 positions).

Each step's CPU time (user + system of its process) is printed beside the wall time: on a shared machine it
is the steadier figure (numba compiles on one thread). ``--warmup`` runs ``fastbearing warmup`` first (its
time printed on a line of its own): the steps after it should compile nothing (issue 45). ``--signatures``
lists, at the end, the package's functions that numba compiled in more than one signature over the steps
(numba's compile events, each with its CPU seconds including its callees'): the candidates for fewer
specialised variants (a literal beside a plain bool, None beside an array, int beside float ...).

    python bench/compile_variants.py [--warmup] [--signatures]
"""

import collections
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

STEPS = {
    "first quasi-static solve": (
        "import fastbearing as fb; "
        "assert fb.solve(fb.Bearing.preset('gunduz2013', 'DB'), [1000.0, 0, 3000.0, 0, -74000.0]).converged"),
    "first solve at speed": (
        f"import fastbearing as fb; b = fb.load_bearing({str(ROOT / 'fastbearing/catalogue/7014C-DB.toml')!r}); "
        "assert fb.solve(b, [500.0, 0, 1000.0, 0, 0], speed=12000.0).converged"),
    "first load map (the 1M example's kernels)": (
        "import tomllib, tempfile, pathlib, fastbearing as fb; "
        f"doc = tomllib.loads(pathlib.Path({str(ROOT / 'data/examples/gunduz2013-db-1M.toml')!r}).read_text()); "
        "doc['loadmap'].update({k: {'start': -1.0, 'stop': 1.0, 'num': 3} for k in ('Fx', 'My')}); "
        "doc['loadmap']['Fz'] = {'start': 100.0, 'stop': 1000.0, 'num': 3}; "
        "d = tempfile.mkdtemp(); fb.loadmap(doc, pathlib.Path(d) / 'm.h5', progress=False)"),
    "first roller solve": (
        f"import fastbearing as fb; b = fb.load_bearing({str(ROOT / 'fastbearing/catalogue/30206-TDO.toml')!r}); "
        "assert fb.solve(b, [3000.0, 0, 1000.0, 0, 0]).converged"),
    "first passage table": (
        "import tomllib, tempfile, pathlib, fastbearing as fb; "
        f"doc = tomllib.loads(pathlib.Path({str(ROOT / 'data/examples/gunduz2013-passage.toml')!r}).read_text()); "
        "doc['passage']['positions'] = 16; doc['passage']['harmonics'] = 4; "
        "d = tempfile.mkdtemp(); fb.passage(doc, pathlib.Path(d) / 'p.h5', progress=False)"),
}


#: Put before each step's code with --signatures: every compilation's function, argument types and CPU seconds
#: (callees included) appended to the file COMPILE_SIGNATURES names, at the process's exit.
LISTEN = """
import atexit, json, os, time
from numba.core import event

_started, _done = [], []


class _Listen(event.Listener):
    def on_start(self, ev):
        _started.append(time.process_time())

    def on_end(self, ev):
        f = ev.data["dispatcher"].py_func
        _done.append((f.__module__ + "." + f.__qualname__, str(ev.data["args"]), time.process_time() - _started.pop()))


event.register("numba:compile", _Listen())
atexit.register(lambda: open(os.environ["COMPILE_SIGNATURES"], "a").write("".join(json.dumps(d) + "\\n" for d in _done)))
"""


def print_signatures(path: Path) -> None:
    """The package's functions compiled in more than one signature, each signature with its CPU seconds (an
    inlined overload compiled again in each step's process, in one signature, is not listed)."""
    seen = collections.defaultdict(dict)
    for line in path.read_text().splitlines():
        name, args, cpu = json.loads(line)
        seen[name][args] = seen[name].get(args, 0.0) + cpu
    several = {name: list(sigs.items()) for name, sigs in seen.items()
               if name.startswith("fastbearing.") and len(sigs) > 1}
    print(f"\nfunctions compiled in more than one signature: {len(several)}")
    for name, sigs in sorted(several.items(), key=lambda kv: -sum(cpu for _, cpu in kv[1])):
        print(f"{name}: {len(sigs)}")
        for args, cpu in sigs:
            print(f"  {cpu:6.2f} s  {args}")


def _children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def main() -> None:
    cache = Path(tempfile.mkdtemp(prefix="numba-cache-"))
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache)}
    listen = "--signatures" in sys.argv[1:]
    if listen:
        env["COMPILE_SIGNATURES"] = str(cache / "signatures.jsonl")
    if "--warmup" in sys.argv[1:]:
        t, cpu = time.perf_counter(), _children_cpu()
        subprocess.run([sys.executable, "-m", "fastbearing.cli", "warmup"], env=env, check=True, timeout=3600)
        print(f"{'fastbearing warmup':45s} {time.perf_counter() - t:6.1f} s   CPU {_children_cpu() - cpu:6.1f} s   "
              f"cached variants: {len(list(cache.rglob('*.nbc')))}")
    total = total_cpu = 0.0
    for name, code in STEPS.items():
        t, cpu = time.perf_counter(), _children_cpu()
        subprocess.run([sys.executable, "-c", (LISTEN if listen else "") + code], env=env, check=True, timeout=900)
        dt, dcpu = time.perf_counter() - t, _children_cpu() - cpu
        total += dt
        total_cpu += dcpu
        variants = list(cache.rglob("*.nbc"))
        print(f"{name:45s} {dt:6.1f} s   CPU {dcpu:6.1f} s   cached variants so far: {len(variants)}")
    size = sum(p.stat().st_size for p in cache.rglob("*.nb[ci]"))
    print(f"{'all steps':45s} {total:6.1f} s   CPU {total_cpu:6.1f} s   {len(list(cache.rglob('*.nbc')))} variants, "
          f"{size / 1e6:.1f} MB")
    if listen:
        print_signatures(cache / "signatures.jsonl")


if __name__ == "__main__":
    main()
