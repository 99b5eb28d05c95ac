"""The documentation a newcomer follows: every cited page and section exists, README links resolve.

Sources cite the model page as ``(docs/model.md, "Section heading")``; the
heading must exist in that file, word for word (line breaks inside the quotes
are allowed). The model page used to live outside the repository as a bare
upper-case model-file name; no file may cite that any more.
"""

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
SCANNED = ("fastbearing", "tests", "bench", "docs")
TEXT_SUFFIXES = {".py", ".md", ".toml", ".txt", ".cfg", ".ini", ".rst"}

DOC_PATH = re.compile(r"(?<![\w./-])docs/([\w.-]+\.md)\b")
#: ``docs/x.md, "Section"``; the section may run over lines (comment markers are dropped).
CITATION = re.compile(r'(?<![\w./-])docs/([\w.-]+\.md),\s*"([^"]+)"')
#: The old, out-of-tree model page (spelt in two parts so that this file does not cite it).
BARE_MODEL = re.compile(r"(?<![\w./-])" + "MODEL" + r"\.md\b")
FENCE = re.compile(r"^\s*(```|~~~)")
HEADING = re.compile(r"^ {0,3}(#{1,6})\s+(.*?)\s*#*\s*$")
LINK = re.compile(r"!?\[[^\]]*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")


def source_files():
    files = [ROOT / "README.md"]
    for folder in SCANNED:
        files += [p for p in sorted((ROOT / folder).rglob("*"))
                  if p.is_file() and p.suffix in TEXT_SUFFIXES and "__pycache__" not in p.parts]
    return [p for p in files if p.exists() and p.resolve() != Path(__file__).resolve()]


def rel(path: Path) -> str:
    return path.relative_to(ROOT).as_posix()


def outside_fences(text: str):
    """(line number, line) of the Markdown lines outside fenced code blocks."""
    fenced = False
    for number, line in enumerate(text.splitlines(), 1):
        if FENCE.match(line):
            fenced = not fenced
            continue
        if not fenced:
            yield number, line


def headings(path: Path) -> list[str]:
    return [m.group(2) for _, line in outside_fences(path.read_text(encoding="utf-8"))
            if (m := HEADING.match(line))]


def slug(heading: str) -> str:
    """GitHub's anchor for a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"[`*_]|<[^>]+>", "", heading).strip().lower()
    return re.sub(r"[^\w\- ]", "", text).replace(" ", "-")


def anchors(path: Path) -> set[str]:
    seen: dict[str, int] = {}
    out = set()
    for h in headings(path):
        s = slug(h)
        n = seen.get(s, 0)
        out.add(s if n == 0 else f"{s}-{n}")
        seen[s] = n + 1
    return out


def clean_section(name: str) -> str:
    """A cited heading as one line: line breaks, indentation and comment markers removed."""
    return re.sub(r"\s*\n\s*(?:#:?\s*)?", " ", name).strip()


def citations():
    for path in source_files():
        text = path.read_text(encoding="utf-8")
        for m in CITATION.finditer(text):
            yield path, text.count("\n", 0, m.start()) + 1, m.group(1), clean_section(m.group(2))


def test_the_model_page_exists_and_has_its_sections():
    page = ROOT / "docs" / "model.md"
    assert page.is_file()
    found = headings(page)
    for section in ("Units and coordinates", "A bearing is a set of rows on one rigid inner ring",
                    "Per ball (row r, ball j at azimuth psi)", "Checks", "Reference values from the paper",
                    "Where the paper is wrong"):
        assert section in found


def test_every_cited_doc_exists():
    missing = []
    for path in source_files():
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            missing += [f"{rel(path)}:{number}: docs/{name}" for name in DOC_PATH.findall(line)
                        if not (ROOT / "docs" / name).is_file()]
    assert not missing, "cited pages that do not exist:\n" + "\n".join(missing)


def test_every_cited_section_exists():
    found = list(citations())
    assert found, "no citation found: the pattern no longer matches how the sources cite"
    bad = [f"{rel(path)}:{number}: docs/{name}, \"{section}\"" for path, number, name, section in found
           if not (ROOT / "docs" / name).is_file() or section not in headings(ROOT / "docs" / name)]
    assert not bad, "citations of sections that do not exist:\n" + "\n".join(bad)


def test_no_file_cites_the_old_model_page():
    bad = [f"{rel(path)}:{number}" for path in source_files()
           for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
           if BARE_MODEL.search(line)]
    assert not bad, "cite docs/model.md with its section instead:\n" + "\n".join(bad)


@pytest.mark.parametrize("page", ["README.md", *(rel(p) for p in sorted((ROOT / "docs").glob("*.md")))])
def test_relative_links_resolve(page):
    path = ROOT / page
    problems = []
    for number, line in outside_fences(path.read_text(encoding="utf-8")):
        line = re.sub(r"`[^`]*\]\([^`]*`", "", line)  # a link written out in a code span is no link
        for target in LINK.findall(line):
            if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I):  # https:, mailto: ...
                continue
            file_part, _, anchor = target.partition("#")
            linked = (path.parent / file_part).resolve() if file_part else path
            if not linked.exists() or ROOT not in (linked, *linked.parents):
                problems.append(f"{page}:{number}: {target} (no such file in the repository)")
            elif anchor and linked.suffix == ".md" and anchor.lower() not in anchors(linked):
                problems.append(f"{page}:{number}: {target} (no such heading)")
    assert not problems, "\n".join(problems)
