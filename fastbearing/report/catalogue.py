"""The shipped bearings (fastbearing/catalogue/*.toml) as a list: what `fastbearing bearings` prints.

:func:`shipped_bearings` gives one dict per file (JSON-ready, for ``--json``): its name (what
``--bearing NAME``, ``fb.load_bearing("NAME")`` and ``bearing = "NAME"`` take), its type, nominal contact
angle, boundary dimensions d x D x B, basic load ratings C and C0, and where each of these numbers comes
from. :func:`shipped_bearings_text` prints them as a table.

Units: mm for the dimensions, N for the ratings, degrees for the contact angle.

The sources are read from the files themselves: a value's source is the comment on its line
(``bore = 25.0  # d, mm: boundary dimensions (published: SKF 6205; ISO 15 series 02)``,
``dynamic_load_rating = 14800.0  # C, N: SKF catalogue``). A file that gives no ``dynamic_load_rating``
or ``static_load_rating`` is rated by ISO 281 / ISO 76 from its geometry, as life rates it
(:func:`fastbearing.analysis.life.ratings`), and says so.
"""

from __future__ import annotations

import re
import textwrap

from ..model.catalogue import catalogue_file, catalogue_names

__all__ = ["shipped_bearing", "shipped_bearings", "shipped_bearings_text"]

#: The units of the numbers in each entry.
UNITS = {"contact_angle_deg": "deg", "bore": "mm", "outer_diameter": "mm", "width": "mm", "C": "N", "C0": "N"}

_ASSIGNMENT = re.compile(r"^\s*([A-Za-z_][\w-]*)\s*=\s*[^#]*#\s*(?P<comment>.*?)\s*$")
_TABLE = re.compile(r"^\s*\[+\s*([\w.-]+)\s*\]+")
_ARRANGEMENT_WORDS = {"DB": "back to back", "DF": "face to face", "DT": "tandem",
                      "TDO": "back to back", "TDI": "face to face"}


def _line_comments(text: str) -> dict[tuple[str, str], str]:
    """{(table, key): the comment on the key's line} of a TOML file's text."""
    out, table = {}, ""
    for line in text.splitlines():
        m = _TABLE.match(line)
        if m:
            table = m.group(1)
            continue
        m = _ASSIGNMENT.match(line)
        if m:
            out[(table, m.group(1))] = m.group("comment")
    return out


def _dimensions_source(comment: str | None) -> str:
    """``d, mm: boundary dimensions (published: SKF 6205; ISO 15 series 02)`` -> ``published: SKF 6205; ...``."""
    if not comment:
        return "the file (no source on the bore line)"
    m = re.search(r"boundary dimensions\s*\((.*)\)\s*$", comment)
    return m.group(1) if m else comment


def _rating_source(comment: str | None) -> str:
    """``C, N: SKF catalogue`` or ``C, N (SKF catalogue)`` -> ``SKF catalogue``."""
    if not comment:
        return "the file (no source on its line)"
    rest = re.sub(r"^C0?\s*,\s*N\s*", "", comment)
    if rest.startswith(":"):
        return rest[1:].strip()
    if rest.startswith("(") and rest.endswith(")"):
        return rest[1:-1].strip()
    return rest or comment


def _type(bearing, element: str, contact_angle: float | None) -> str:
    """The bearing's type in words: element, row count and arrangement."""
    arrangement = bearing.arrangement
    if element == "four_point_ball":
        kind = "four-point contact ball"
    elif element == "tapered_roller":
        kind = "tapered roller"
    elif element == "cylindrical_roller":
        kind = "cylindrical roller"
    elif contact_angle == 0.0:
        kind = "deep-groove ball"
    else:
        kind = "angular contact ball"
    if arrangement == "single":
        return f"{kind}, single row"
    words = _ARRANGEMENT_WORDS.get(arrangement)
    rows = bearing.n_rows // 2 if element == "four_point_ball" else bearing.n_rows
    return f"{kind}, {rows} rows {arrangement}" + (f" ({words})" if words else "")


def shipped_bearing(name: str) -> dict:
    """One shipped bearing's entry of :func:`shipped_bearings`; ValueError listing the names for an unknown one."""
    from ..analysis.life import ISO_C, ISO_C0, rating_sources, ratings
    from ..model.bearing_file import load_bearing, read_toml

    path = catalogue_file(name)
    text = path.read_text(encoding="utf-8")
    table = read_toml(path)["bearing"]
    comments = _line_comments(text)
    bearing = load_bearing(path)
    g = bearing.geometry
    row = bearing.rows[0]
    # a roller geometry names its element; a ball geometry's rows say whether they are four-point ones
    element = g.element if g is not None and g.element != "ball" else getattr(row, "element", "ball")
    contact_angle = float(g.contact_angle if g is not None else row.contact_angle)
    entry = {"name": path.stem, "bearing_name": bearing.name, "file": str(path),
             "type": _type(bearing, element, contact_angle), "element": element,
             "arrangement": bearing.arrangement, "contact_angle_deg": contact_angle}
    geo = table.get("geometry", {})
    dims = {k: geo.get(k) for k in ("bore", "outer_diameter", "width")}
    entry.update({k: None if v is None else float(v) for k, v in dims.items()})
    sources = {}
    if all(v is None for v in dims.values()):
        sources["dimensions"] = "not given: the file gives model parameters (Kn, A0, R), no geometry"
    else:
        sources["dimensions"] = _dimensions_source(comments.get(("bearing.geometry", "bore")))
    if g is None:
        entry["C"] = entry["C0"] = None
        sources["C"] = sources["C0"] = "none: no geometry to rate"
    else:
        r = ratings(bearing)
        entry["C"] = None if r.C is None else float(r.C)
        entry["C0"] = None if r.C0 is None else float(r.C0)
        kinds = rating_sources(bearing)  # catalogue value or formula: the one rule life follows
        for key, field, standard in (("C", "dynamic_load_rating", "ISO 281"), ("C0", "static_load_rating", "ISO 76")):
            if kinds[key] not in (ISO_C, ISO_C0):
                sources[key] = _rating_source(comments.get(("bearing.geometry", field)))
            elif entry[key] is None:
                sources[key] = "none: these rows are not rated as one unit"
            else:
                sources[key] = f"{standard} from the file's geometry (its internal dimensions estimated, as the file says)"
    entry["sources"] = sources
    entry["units"] = dict(UNITS)
    return entry


def shipped_bearings() -> list[dict]:
    """Every shipped bearing (fastbearing/catalogue/*.toml), in name order, as JSON-ready dicts:

    ``name`` (what ``--bearing``, ``fb.load_bearing`` and ``bearing = "..."`` take), ``bearing_name`` (the
    file's own ``name``), ``file`` (its path in the installed package), ``type`` (in words, e.g.
    "angular contact ball, 2 rows DB (back to back)"), ``element``, ``arrangement``, ``contact_angle_deg``
    (nominal, deg), ``bore``, ``outer_diameter``, ``width`` (d, D, B in mm; None where the file has none;
    for a pair, each bearing's), ``C``, ``C0`` (basic dynamic and static load ratings of the bearing as one
    unit, N; None where it has no rating), ``sources`` ({"dimensions", "C", "C0"}: where each number comes
    from, as the file says) and ``units``."""
    return [shipped_bearing(name) for name in catalogue_names()]


def _number(value, digits: str = "g") -> str:
    return "-" if value is None else format(value, digits)


def shipped_bearings_text(entries: list[dict] | None = None, width: int = 110) -> str:
    """The shipped bearings as `fastbearing bearings` prints them: one line each (name, type, contact angle,
    d x D x B, C, C0), then where each bearing's numbers come from. ``entries``: :func:`shipped_bearings`'s
    (default: computed here)."""
    entries = shipped_bearings() if entries is None else entries
    head = ("name", "type", "a0 (deg)", "d x D x B (mm)", "C (N)", "C0 (N)")
    rows = []
    for e in entries:
        dims = ("-" if e["bore"] is None else
                " x ".join(_number(e[k]) for k in ("bore", "outer_diameter", "width")))
        rows.append((e["name"], e["type"], _number(e["contact_angle_deg"]), dims,
                     _number(e["C"], ".0f"), _number(e["C0"], ".0f")))
    widths = [max(len(str(r[i])) for r in (head, *rows)) for i in range(len(head))]
    align = ("<", "<", ">", "<", ">", ">")

    def line(cells):
        return "  ".join(f"{c:{a}{w}}" for c, a, w in zip(cells, align, widths)).rstrip()

    out = ["Shipped bearings (fastbearing/catalogue/NAME.toml): give the NAME wherever a bearing file is asked",
           'for: --bearing NAME, fb.load_bearing("NAME"), bearing = "NAME" in a config. C and C0 rate the',
           "bearing as one unit (a pair's two rows together); a pair's d x D x B is each bearing's.", "",
           line(head), *(line(r) for r in rows), "", "Where the numbers come from:"]
    for e in entries:
        s = e["sources"]
        if s["C"] == s["C0"]:
            ratings = f"C and C0: {s['C']}"
        elif s["C"] == s["C0"].replace("ISO 76", "ISO 281"):  # both computed from the geometry
            ratings = f"C and C0: {s['C'].replace('ISO 281', 'ISO 281 and ISO 76')}"
        else:
            ratings = f"C: {s['C']}. C0: {s['C0']}"
        said = f"{e['name']}: d x D x B: {s['dimensions']}. {ratings}."
        out += textwrap.wrap(said, width, initial_indent="  ", subsequent_indent="      ")
    return "\n".join(out)
