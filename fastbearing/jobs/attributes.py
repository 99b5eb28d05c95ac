"""The attributes of a stored variable or coordinate, CF-friendly, for the HDF5 file and the zarr store alike
(storage.py, zarr_store.py): one ``units`` string each, a ``long_name`` of at most :data:`LONG_NAME_MAX`
characters (a longer text whole in ``comment``), and ``units_per_entry`` where the entries of one variable
differ in units (q: mm and rad; f: N and N*mm; Kb: N/mm, N/rad, N*mm/rad). Units: N, mm, rad.

A leaf of jobs/: it imports only the DOF names and units (dofs.py), so both stores take it without importing
each other.
"""

from __future__ import annotations

import re

from ..dofs import K_UNITS, K_UNITS_PER_ENTRY


#: The longest ``long_name`` a variable or coordinate carries: xarray's automatic plot labels read
#: ``long_name [units]`` wrapped at 30 characters, and a longer name runs to more lines than an axis has room
#: for. A longer text goes whole in ``comment``.
LONG_NAME_MAX = 60


def short_long_name(text: str) -> tuple[str, bool]:
    """``text`` as a long_name of at most LONG_NAME_MAX characters, and whether it was shortened: the text
    without its parentheses where that fits, else the part before its first colon, semicolon or comma, else
    cut at a word with "..."."""
    if len(text) <= LONG_NAME_MAX:
        return text, False
    bare = " ".join(re.sub(r"\s+\([^()]*\)", "", text).split())     # " (...)": not a formula's cos(...)
    if len(bare) <= LONG_NAME_MAX:
        return bare, True
    for sep in (": ", "; ", ", "):
        head = bare.split(sep, 1)[0].strip()
        if head and len(head) <= LONG_NAME_MAX:
            return head, True
    return bare[:LONG_NAME_MAX - 3].rsplit(" ", 1)[0] + "...", True


def entry_units(units: str, trailing=(), extra=None) -> list[str] | None:
    """The units of each entry of a variable whose entries differ (q, f, Kb and its passage summaries), or
    None: the ``units_per_entry`` its definition gives, else Kb's (:data:`~fastbearing.dofs.K_UNITS_PER_ENTRY`)
    for a variable in Kb's units over (..., dof, dof_col)."""
    given = (extra or {}).get("units_per_entry")
    if given is not None:
        return [str(u) for u in given]
    if units == K_UNITS and tuple(trailing[-2:]) == ("dof", "dof_col"):
        return list(K_UNITS_PER_ENTRY)
    return None


def cf_attributes(units: str | None, long_name: str, trailing=(), extra=None) -> dict:
    """The attributes of a variable or coordinate in a store, HDF5 and zarr alike (CF-friendly).

    ``units``: one unit string (N, mm, rad; "1" where dimensionless); None for a coordinate of text labels
    (dof, dof_col), which is no quantity and has none (CF). ``long_name``: at most
    LONG_NAME_MAX characters (:func:`short_long_name`; a longer text is kept whole in ``comment``).
    ``units_per_entry`` where the entries' units differ (:func:`entry_units`): one unit per entry along the
    variable's dof dims, row-major (q and f: 5, by dof; K: 25, entry [i, j] at 5 i + j), and ``units``
    is then the translation entries' (mm, N, N/mm), which ``comment`` says. Then ``extra`` (flags ...),
    its own ``comment`` joined to the others.
    """
    extra = dict(extra or {})
    per_entry = entry_units(units, trailing, extra)
    extra.pop("units_per_entry", None)
    short, shortened = short_long_name(long_name)
    comments = [long_name] if shortened else []
    if "comment" in extra:
        comments.append(str(extra.pop("comment")))
    attrs = {"long_name": short} if units is None else {"units": str(units), "long_name": short}
    if per_entry is not None:
        attrs["units_per_entry"] = per_entry
        by = "dof and dof_col, row-major (entry [i, j] at 5 i + j)" if len(per_entry) == 25 else "dof"
        comments.append(f"units is that of the x, y, z entries ({units}); units_per_entry gives each entry's, "
                        f"along {by}")
    if comments:
        attrs["comment"] = ". ".join(comments)
    attrs.update(extra)
    return attrs
