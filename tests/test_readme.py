"""The README is executable documentation: every example in it runs as written, and the numbers it
prints are the numbers fastbearing gives.

The README is read top to bottom, as a newcomer follows it, in one temporary folder holding copies of
the repository's ``data/`` and ``docs/`` (so commands run "from the repository root"):

- ```` ```sh ```` blocks: each line is a command. Of a line of ``&&``-joined steps, the ``fastbearing``
  steps run; environment steps (venv, activate, pip, pytest) are what this test environment already
  did. Every command must exit 0.
- blocks whose lines start with ``$ fastbearing``: the command runs and its output (stdout, then
  stderr) is compared with the lines below it: text exactly (whitespace collapsed), numbers to the
  printed digits (relative 2e-5; within a line, magnitudes below 1e-9 of the line's largest are
  rounding noise and compare as such). ``…`` stands for a number that varies (a timing).
- ```` ```python ```` blocks run in one namespace, in order. A line ``expression  # value`` whose
  comment starts with a literal (a number, a string, a list of numbers) is checked: numbers to the
  printed decimals.
- ```` ```toml ```` blocks are read by the reader of their tables (bearing, loadmap, passage), so
  every documented key exists and every example value is accepted.
- ```` ```text ```` blocks (synopses, file listings) are not run. A block preceded by
  ``<!-- readme: skip (REASON) -->`` is not run either; the reason is required.
"""

from __future__ import annotations

import ast
import contextlib
import io
import re
import shlex
import shutil
import textwrap
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from conftest import cli_run

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
#: The documentation site's guide pages (mkdocs.yml), run after the README in the order a reader meets their
#: examples (a page may use a file an earlier one made: the quick start's map, a solve's JSON).
GUIDE = ("index.md", "solve.md", "boundary-conditions.md", "load-maps.md", "passage.md", "defects.md",
         "geometry.md", "life.md", "mounting.md", "high-speed.md",
         "pictures.md", "shafts-and-export.md", "scale-out.md", "gpu.md", "reliability.md", "units.md", "bearings.md",
         "four-point.md", "rollers.md", "assumptions.md", "speed.md", "layout.md")
DOCUMENTS = (README, *(ROOT / "docs" / name for name in GUIDE))
SKIP = re.compile(r"<!--\s*readme:\s*skip\s*\((?P<why>[^)]+)\)\s*-->")
ENVIRONMENT_STEPS = ("python3 -m venv", ". .venv/bin/activate", "pip install", "python -m pytest", "python -P -m pytest")


@dataclass
class Block:
    lang: str
    text: str
    line: int           # 1-based line of the opening fence
    skip: str | None    # the reason, when marked skip


def readme_blocks(text: str) -> list[Block]:
    blocks, lines, i = [], text.splitlines(), 0
    while i < len(lines):
        m = re.match(r"^```(\w*)\s*$", lines[i])
        if not m:
            i += 1
            continue
        start, body = i, []
        i += 1
        while i < len(lines) and not lines[i].startswith("```"):
            body.append(lines[i])
            i += 1
        before = next((lines[k] for k in range(start - 1, -1, -1) if lines[k].strip()), "")
        skip = SKIP.search(before)
        blocks.append(Block(m.group(1), "\n".join(body) + "\n", start + 1, skip.group("why") if skip else None))
        i += 1
    return blocks


# -- comparing printed output --------------------------------------------------------------------

NUMBER = re.compile(r"(?<![\w.])[-+]?(?:\d{1,3}(?:,\d{3})+(?:\.\d+)?|\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|…")


def tokens(line: str) -> list:
    """A line as text pieces (whitespace collapsed) and numbers (float; None for the wildcard …)."""
    out, pos = [], 0
    for m in NUMBER.finditer(line):
        text = " ".join(line[pos:m.start()].split())
        if text:
            out.append(text)
        out.append(None if m.group() == "…" else (float(m.group().replace(",", "")), m.group()))
        pos = m.end()
    text = " ".join(line[pos:].split())
    if text:
        out.append(text)
    return out


def same_line(expected: str, actual: str) -> str | None:
    """None when ``actual`` prints what ``expected`` does; else why not."""
    e, a = tokens(expected), tokens(actual)
    if len(e) != len(a):
        return "different shape"
    scale = max([abs(t[0]) for t in e if isinstance(t, tuple)] or [0.0])
    for te, ta in zip(e, a):
        if te is None:
            if not isinstance(ta, tuple):
                return f"a number expected for …, got {ta!r}"
            continue
        if isinstance(te, str) or isinstance(ta, str) or ta is None:
            if te != ta:
                return f"{te!r} != {ta!r}"
            continue
        (x, _), (y, _) = te, ta
        if abs(x - y) > max(2e-5 * abs(x), 1e-9 * scale, 1e-300):
            return f"{te[1]} != {ta[1]}"
    return None


def check_output(expected: list[str], actual: str, where: str) -> None:
    # the one-time compile notice depends on the cache, not on the example
    got = [line for line in actual.splitlines() if line.strip() and not line.startswith("fastbearing: compiling")]
    want = [line for line in expected if line.strip()]
    assert len(got) == len(want), f"{where}: {len(want)} lines in the README, {len(got)} printed:\n{actual}"
    for k, (w, g) in enumerate(zip(want, got)):
        why = same_line(w, g)
        assert why is None, f"{where}, output line {k + 1}: {why}\n  README: {w}\n  prints: {g}"


# -- running -------------------------------------------------------------------------------------

def fastbearing_steps(line: str) -> list[str]:
    """The fastbearing commands of one shell line (environment steps joined by && are left out)."""
    steps = [s.strip() for s in line.split("&&")]
    unknown = [s for s in steps if not s.startswith("fastbearing") and not s.startswith(ENVIRONMENT_STEPS)]
    assert not unknown, f"the README runner does not know how to run {unknown}"
    return [s for s in steps if s.startswith("fastbearing")]


def run_command(command: str, where: str):
    args = shlex.split(command)
    assert args[0] == "fastbearing"
    result = cli_run(*args[1:])
    assert result.returncode == 0, f"{where}: `{command}` exited {result.returncode}:\n{result.stderr}"
    return result


def run_sh(block: Block, page: str = "README") -> None:
    for k, line in enumerate(block.text.splitlines()):
        if line.strip() and not line.lstrip().startswith("#"):
            for step in fastbearing_steps(line.split(" #")[0]):
                run_command(step, f"{page} line {block.line + k + 1}")


def run_transcript(block: Block, page: str = "README") -> int:
    """Blocks of ``$ command`` lines followed by their output; returns how many commands ran."""
    lines = block.text.splitlines()
    starts = [k for k, line in enumerate(lines) if line.startswith("$ ")]
    for n, k in enumerate(starts):
        end = starts[n + 1] if n + 1 < len(starts) else len(lines)
        where = f"{page} line {block.line + k + 1}"
        result = run_command(lines[k][2:], where)
        check_output(lines[k + 1:end], result.stdout + result.stderr, where)
    return len(starts)


LITERAL = re.compile(r"^\s*(?P<value>'[^']*'|\"[^\"]*\"|\[[^\]]*\]|[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)")


def decimals(text: str) -> int:
    mantissa = text.lower().split("e")[0]
    return len(mantissa.split(".")[1]) if "." in mantissa else 0


def check_value(value, shown: str, where: str) -> None:
    """``value`` printed as ``shown`` (a literal from the README's comment)."""
    literal = ast.literal_eval(shown)
    if isinstance(literal, str):
        assert value == literal, f"{where}: {value!r}, README says {shown}"
        return
    shown_items = re.findall(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?", shown)
    values = np.atleast_1d(np.asarray(value, dtype=float))
    assert values.size == len(shown_items), f"{where}: {values.size} values, README shows {len(shown_items)}"
    for v, s in zip(values, shown_items):
        exponent = int(s.lower().split("e")[1]) if "e" in s.lower() else 0
        tol = 0.5 * 10.0 ** (exponent - decimals(s)) * (1 + 1e-9)
        assert abs(v - float(s)) <= tol, f"{where}: {v!r}, README says {s}"


def run_python(block: Block, namespace: dict, page: str = "README") -> None:
    code = textwrap.dedent(block.text)
    tree = ast.parse(code)
    lines = code.splitlines()
    for node in tree.body:
        where = f"{page} line {block.line + node.lineno}"
        if isinstance(node, ast.Expr):
            value = eval(compile(ast.Expression(node.value), where, "eval"), namespace)
            comment = lines[node.end_lineno - 1][node.end_col_offset:].strip()
            if comment.startswith("#"):
                m = LITERAL.match(comment[1:])
                if m:
                    check_value(value, m.group("value"), where)
        else:
            exec(compile(ast.Module([node], []), where, "exec"), namespace)


def check_toml(block: Block, folder: Path, page: str = "README") -> None:
    """A TOML example is accepted by the reader of its tables."""
    from fastbearing.model.bearing_file import load_bearing

    where = f"{page} line {block.line}"
    body = tomllib.loads(block.text)
    path = folder / f"{Path(page).stem}-{block.line}.toml"
    path.write_text(block.text)
    if "loadmap" in body:
        from fastbearing.jobs.loadmap import read_config
    elif "passage" in body:
        from fastbearing.jobs.passage import read_config
    else:
        assert "bearing" in body, f"{where}: a TOML example without a [bearing], [loadmap] or [passage] table"
        load_bearing(path)
        return
    read_config(path)


def test_the_guide_runs_every_page_of_the_site():
    """Every guide page of mkdocs.yml's nav is run here (and none the nav lacks), so no example goes untested."""
    nav = re.findall(r"^\s+- [^:]+: ([\w.-]+\.md)\s*$", (ROOT / "mkdocs.yml").read_text(), re.M)
    assert sorted(nav) == sorted((*GUIDE, "model.md")), nav


def test_every_readme_and_guide_example_runs_as_written(tmp_path, monkeypatch):
    for name in ("data", "docs"):
        shutil.copytree(ROOT / name, tmp_path / name, ignore=shutil.ignore_patterns("*.h5", "*.part"))
    monkeypatch.chdir(tmp_path)
    namespace: dict = {"__name__": "readme"}
    ran = {"sh": 0, "transcript": 0, "python": 0, "toml": 0}
    for document in DOCUMENTS:
        page = document.relative_to(ROOT).as_posix()
        for block in readme_blocks(document.read_text()):
            if block.skip is not None:
                assert block.skip.strip(), f"{page} line {block.line}: a skip needs its reason"
                continue
            if block.lang == "sh":
                run_sh(block, page)
                ran["sh"] += 1
            elif block.lang in ("", "console") and block.text.startswith("$ "):
                ran["transcript"] += run_transcript(block, page)
            elif block.lang == "python":
                with contextlib.redirect_stdout(io.StringIO()):
                    run_python(block, namespace, page)
                ran["python"] += 1
            elif block.lang == "toml":
                check_toml(block, tmp_path, page)
                ran["toml"] += 1
            else:
                assert block.lang == "text", (f"{page} line {block.line}: a ```{block.lang} block: mark it sh, "
                                              "python, toml or text, or start it with `$ fastbearing`")
    assert min(ran.values()) > 0, ran


def test_the_output_comparison_itself():
    """What the runner accepts and refuses: numbers to their digits, noise, wildcards, text exactly."""
    assert same_line("dx=-0.00836059  dy=2.29e-17", "dx=-0.00836059  dy=-9.1e-19") is None
    assert same_line("dx=-0.00836059", "dx=-0.00836159") is not None
    assert same_line("iterations: 6  residual: 4.19e-15", "iterations: 5  residual: 3.97e-13") is not None
    assert same_line("0.45 s wall, 283 solves/s", "12.5 s wall, 9 solves/s") is not None
    assert same_line("… s wall, … solves/s", "12.5 s wall, 9,283 solves/s") is None
    assert same_line("status: converged", "status: stalled") is not None
    check_value(313.44, "313.4", "t")
    with pytest.raises(AssertionError):
        check_value(313.46, "313.4", "t")
    check_value([1.0, 2.04], "[1.0, 2.0]", "t")
    check_value("converged", "'converged'", "t")
    assert [b.lang for b in readme_blocks("a\n```sh\nx\n```\n<!-- readme: skip (why) -->\n```text\ny\n```\n")] == [
        "sh", "text"]
