"""Bearing files (TOML ``[bearing]`` tables) and shipped presets.

The ``[bearing]`` table is the public format: either the compact form
(``arrangement`` plus the row keys shared by all rows) or a general set of
``[[bearing.rows]]``. ``preset = "NAME"`` starts from a shipped bearing and
any other key overrides it. A ``[bearing.geometry]`` sub-table defines the
rows from catalogue geometry instead (:mod:`fastbearing.geometry`).
"""

from __future__ import annotations

import tomllib
from dataclasses import replace
from importlib import resources
from pathlib import Path

from .bearing import ARRANGEMENTS, ROW_KEYS, Bearing, check_keys, _per_row, _row
from .geometry import geometry_from_table

_SHARED_KEYS = ("n_balls", "hertz_constant", "pitch_radius", "groove_center_distance", "contact_angle",
                "exponent", "radial_clearance", "first_ball_angle")
_TABLE_KEYS = set(_SHARED_KEYS) | {"arrangement", "row_offset", "axial_preload", "preset", "name", "rows", "geometry"}
#: Keys a [bearing.geometry] table derives; giving them in [bearing] too would be ambiguous.
_GEOMETRY_DERIVED = ("n_balls", "hertz_constant", "pitch_radius", "groove_center_distance", "contact_angle",
                     "exponent", "radial_clearance", "row_offset")
#: Row keys that stay per row when the rows share one geometry.
_GEOMETRY_ROW_KEYS = ("axial_offset", "contact_direction", "axial_preload", "first_ball_angle")


def preset_names() -> list[str]:
    """Names of the shipped presets."""
    return sorted(p.name[:-5] for p in resources.files("fastbearing.presets").iterdir() if p.name.endswith(".toml"))


def _preset_table(name: str) -> dict:
    if name not in preset_names():
        raise ValueError(f"preset must be one of {preset_names()}, got {name!r}")
    text = resources.files("fastbearing.presets").joinpath(f"{name}.toml").read_text()
    return tomllib.loads(text)["bearing"]


def preset_bearing(name: str, arrangement: str | None = None, **overrides) -> Bearing:
    """A shipped bearing with its arrangement chosen by the caller and any key overridden."""
    table = dict(_preset_table(name))
    if arrangement is not None:
        table["arrangement"] = arrangement
    table.update(overrides)
    return bearing_from_table(table)


def bearing_from_table(table: dict, where: str = "bearing") -> Bearing:
    """Build a :class:`Bearing` from a parsed ``[bearing]`` table; ValueError names the offending key."""
    if not isinstance(table, dict):
        raise ValueError(f"{where} must be a table, got {type(table).__name__}")
    check_keys(table, _TABLE_KEYS, where)
    table = dict(table)
    if "geometry" in table:
        return _geometry_bearing(table, where)
    if "preset" in table:
        base = dict(_preset_table(table.pop("preset")))
        if "rows" in table:
            # the preset's per-row values become defaults for every given row
            base = {k: v for k, v in base.items() if k in _SHARED_KEYS or k in ("name", "axial_preload")}
        base.update(table)
        table = base
    name = str(table.pop("name", ""))
    if "rows" in table:
        return _rows_bearing(table, where, name)
    arrangement = table.pop("arrangement", "single")
    if arrangement not in ARRANGEMENTS:
        raise ValueError(f"{where}.arrangement must be one of {list(ARRANGEMENTS)}, got {arrangement!r}")
    row = {k: table[k] for k in _SHARED_KEYS if k in table}
    preload = table.get("axial_preload", 0.0)
    if arrangement == "single":
        try:
            row["axial_preload"] = _per_row(f"{where}.axial_preload", preload, 1)[0]
            return Bearing.single(name=name, **row)
        except ValueError as err:
            raise ValueError(_prefixed(where, err)) from None
    if "row_offset" not in table:
        raise ValueError(f"{where}.row_offset (e, mm, >= 0) is required for arrangement {arrangement!r}")
    _row(row, where)  # the shared keys were typed once: report them as bearing.KEY, not per row
    try:
        return Bearing.double(arrangement, table["row_offset"], axial_preload=preload, name=name, **row)
    except ValueError as err:
        raise ValueError(_prefixed(where, err)) from None


def _rows_bearing(table: dict, where: str, name: str) -> Bearing:
    rows = table.pop("rows")
    if not isinstance(rows, list) or not rows:
        raise ValueError(f"{where}.rows must be a non-empty array of tables")
    table.pop("arrangement", None)
    if "row_offset" in table:
        raise ValueError(f"{where}.row_offset is not used with rows; give each row its axial_offset")
    defaults = {k: table[k] for k in _SHARED_KEYS if k in table}
    preloads = _per_row(f"{where}.axial_preload", table.get("axial_preload", 0.0), len(rows))
    built = []
    for i, r in enumerate(rows):
        if not isinstance(r, dict):
            raise ValueError(f"{where}.rows[{i}] must be a table")
        check_keys(r, ROW_KEYS, f"{where}.rows[{i}]")
        built.append({**defaults, "axial_preload": preloads[i], **r})
    try:
        return Bearing.from_rows(built, name=name)
    except ValueError as err:
        raise ValueError(_prefixed(where, err)) from None


def _geometry_bearing(table: dict, where: str) -> Bearing:
    """A bearing whose rows come from a ``[bearing.geometry]`` table (catalogue dimensions and materials)."""
    if "preset" in table:
        raise ValueError(f"{where}.geometry cannot be combined with {where}.preset; use one or the other")
    clash = [k for k in _GEOMETRY_DERIVED if k in table]
    if clash:
        raise ValueError(f"{where}: {clash} are derived from [{where}.geometry]; remove them from [{where}] "
                         "(or drop the geometry table and give the model parameters directly)")
    geometry = geometry_from_table(table.pop("geometry"), f"{where}.geometry")
    name = str(table.pop("name", ""))
    row = {**geometry.row_keywords(), **{k: table[k] for k in ("first_ball_angle",) if k in table}}
    preload = table.get("axial_preload", 0.0)
    n_given = len(preload) if isinstance(preload, (list, tuple)) else 1
    if geometry.diametral_clearance > 0 and any(_per_row(f"{where}.axial_preload", preload, n_given)):
        raise ValueError(f"{where}.axial_preload must be 0 when {where}.geometry.diametral_clearance > 0 "
                         f"(preload needs zero clearance), got {preload!r}")
    if "rows" in table:
        rows = table.pop("rows")
        if not isinstance(rows, list) or not rows:
            raise ValueError(f"{where}.rows must be a non-empty array of tables")
        if geometry.row_spacing is not None:
            raise ValueError(f"{where}.geometry.row_spacing is not used with rows; give each row its axial_offset")
        preloads = _per_row(f"{where}.axial_preload", preload, len(rows))
        built = []
        for i, r in enumerate(rows):
            if not isinstance(r, dict):
                raise ValueError(f"{where}.rows[{i}] must be a table")
            unknown = sorted(set(r) - set(_GEOMETRY_ROW_KEYS))
            if unknown:
                raise ValueError(f"{where}.rows[{i}]: key(s) {unknown} not allowed with [{where}.geometry]; "
                                 f"allowed per row: {list(_GEOMETRY_ROW_KEYS)}")
            built.append({**row, "axial_preload": preloads[i], **r})
        try:
            bearing = Bearing.from_rows(built, name=name)
        except ValueError as err:
            raise ValueError(_prefixed(where, err)) from None
        return replace(bearing, geometry=geometry)
    arrangement = table.pop("arrangement", "single")
    if arrangement not in ARRANGEMENTS:
        raise ValueError(f"{where}.arrangement must be one of {list(ARRANGEMENTS)}, got {arrangement!r}")
    if arrangement != "single" and geometry.row_spacing is None:
        raise ValueError(f"{where}.geometry.row_spacing (2e, mm, >= 0) is required for arrangement {arrangement!r}")
    try:
        if arrangement == "single":
            row["axial_preload"] = _per_row(f"{where}.axial_preload", preload, 1)[0]
            bearing = Bearing.single(name=name, **row)
        else:
            bearing = Bearing.double(arrangement, geometry.row_offset, axial_preload=preload, name=name, **row)
    except ValueError as err:
        raise ValueError(_prefixed(where, err)) from None
    return replace(bearing, geometry=geometry)


def _prefixed(where: str, err: ValueError) -> str:
    msg = str(err)
    return msg if msg.startswith(where) else f"{where}.{msg}"


def read_toml(path) -> dict:
    """Parse a TOML file; a missing file or a syntax error becomes a ValueError naming the file."""
    path = Path(path)
    try:
        with path.open("rb") as fh:
            return tomllib.load(fh)
    except FileNotFoundError:
        raise ValueError(f"file not found: {path}") from None
    except tomllib.TOMLDecodeError as err:
        raise ValueError(f"{path}: not valid TOML: {err}") from None


def load_bearing(path) -> Bearing:
    """Read a bearing file: a TOML file with one ``[bearing]`` table (units N, mm, degrees)."""
    doc = read_toml(path)
    unknown = sorted(set(doc) - {"bearing"})
    if unknown:
        raise ValueError(f"{path}: unknown top-level key(s) {unknown}; a bearing file holds one [bearing] table")
    if "bearing" not in doc:
        raise ValueError(f"{path}: missing the [bearing] table")
    return bearing_from_table(doc["bearing"])


def read_job_config(config, job: str):
    """A ``[bearing]`` + ``[JOB]`` config (TOML path or parsed dict), checked the same way for every job.

    Returns (bearing, the job's table, the config text, the source path or None).
    """
    import json

    source = None
    if isinstance(config, dict):
        doc, text = config, json.dumps(config, sort_keys=True, default=str)
    else:
        source = Path(config)
        doc, text = read_toml(source), source.read_text()
    unknown = sorted(set(doc) - {"bearing", job})
    if unknown:
        raise ValueError(f"unknown top-level key(s) {unknown}; a {job} config holds [bearing] and [{job}]")
    for table in ("bearing", job):
        if table not in doc:
            raise ValueError(f"missing the [{table}] table")
    if not isinstance(doc[job], dict):
        raise ValueError(f"{job} must be a table")
    return bearing_from_table(doc["bearing"]), doc[job], text, source
