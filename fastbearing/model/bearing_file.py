"""Bearing files (TOML ``[bearing]`` tables), the shipped ones by name, and presets.

The ``[bearing]`` table is the public format: either the compact form
(``arrangement`` plus the row keys shared by all rows) or a general set of
``[[bearing.rows]]``. ``preset = "NAME"`` starts from a shipped bearing and
any other key overrides it. A ``[bearing.geometry]`` sub-table defines the
rows from catalogue geometry instead (:mod:`fastbearing.model.geometry`).
Wherever a bearing file is asked for, the name of a shipped one (``"6205"``;
:mod:`fastbearing.model.catalogue`) does as well.
"""

from __future__ import annotations

import tomllib
from dataclasses import replace
from pathlib import Path

from .. import validate
from .bearing import SHARED_ROW_KEYS, Bearing, preset_names, preset_table
from .catalogue import catalogue_names, find_bearing_file
from .geometry import geometry_from_table
from .mounted import Mounting, clearance_spec, mounting_from_table
from .four_point import ELEMENT as FOUR_POINT
from .rollers import ROLLER_ELEMENTS, ROLLER_KEYS

_TABLE_KEYS = set(SHARED_ROW_KEYS) | set(ROLLER_KEYS) | {"arrangement", "row_offset", "axial_preload", "preset", "name", "rows", "geometry", "mounting"}
#: Keys a [bearing.geometry] table derives; giving them in [bearing] too would be ambiguous.
_GEOMETRY_DERIVED = ("n_balls", "hertz_constant", "pitch_radius", "groove_center_distance", "contact_angle",
                     "exponent", "radial_clearance", "row_offset", "deflection_limit")
#: Row keys that stay per row when the rows share one geometry.
_GEOMETRY_ROW_KEYS = ("axial_offset", "contact_direction", "axial_preload", "first_ball_angle", "first_element_angle")

__all__ = ["bearing_from_table", "catalogue_names", "load_bearing", "preset_bearing", "preset_names", "read_job_config",
           "read_toml"]


def preset_bearing(name: str, arrangement: str | None = None, **overrides) -> Bearing:
    """A shipped bearing with its arrangement chosen by the caller and any key overridden."""
    return Bearing.preset(name, arrangement, **overrides)


def bearing_from_table(table, where: str = "bearing") -> Bearing:
    """Build a :class:`Bearing` from a parsed ``[bearing]`` table; ValueError names the offending key.

    Beyond :meth:`Bearing.from_table` (model parameters) a file's table may
    start from a shipped bearing (``preset = "NAME"``, any other key
    overrides it) or derive its rows from ``[bearing.geometry]``.
    """
    validate.table(table, where, _TABLE_KEYS)
    table = dict(table)
    if "mounting" in table and "geometry" not in table:
        raise validate.FieldError(f"{where}.mounting", f"needs [{where}.geometry] with the boundary dimensions "
                                  "bore and outer_diameter (mm)", show_value=False)
    if "geometry" in table:
        return _geometry_bearing(table, where)
    if "preset" in table:
        try:
            base = preset_table(table.pop("preset"))
        except validate.FieldError as err:
            raise err.within(where) from None
        if "rows" in table:
            # the preset's per-row values become defaults for every given row
            base = {k: v for k, v in base.items() if k in SHARED_ROW_KEYS or k in ("name", "axial_preload")}
        table = {**base, **table}
    return Bearing.from_table(table, where)


def _geometry_bearing(table: dict, where: str) -> Bearing:
    """A bearing whose rows come from a ``[bearing.geometry]`` table (catalogue dimensions and materials)."""
    if "preset" in table:
        raise validate.FieldError(f"{where}.geometry", f"cannot be combined with {where}.preset; use one or the "
                                  "other", show_value=False)
    clash = [k for k in _GEOMETRY_DERIVED if k in table]
    if clash:
        raise validate.FieldError(f"{where}.{clash[0]}", f"is derived from [{where}.geometry]; remove it from "
                                  f"[{where}] (or drop the geometry table and give the model parameters directly)",
                                  show_value=False)
    spec = table.pop("geometry")
    mounting_table = table.pop("mounting", None)
    group = clearance_range = None
    if isinstance(spec, dict) and isinstance(spec.get("diametral_clearance"), (str, list, tuple)):
        # an ISO 5753-1 group or a [min, max] range: the geometry solves the mean, the report keeps the range
        spec = dict(spec)
        spec["diametral_clearance"], group, clearance_range = clearance_spec(spec["diametral_clearance"], spec,
                                                                              f"{where}.geometry")
    if isinstance(spec, dict) and "element" in spec and spec["element"] not in ROLLER_ELEMENTS:
        # a ball geometry has no element key: four-point rows say so in [bearing] (as QJ210.toml does)
        rollers = f"[{where}.geometry] takes element only for a roller geometry, {list(ROLLER_ELEMENTS)}"
        four_point = f'element = "{FOUR_POINT}" in the [{where}] table'
        if spec["element"] == FOUR_POINT:
            say = (f"belongs in the [{where}] table (beside arrangement), not in [{where}.geometry]: "
                   f"{four_point} makes the geometry's ball rows four-point rows; {rollers}")
        elif spec["element"] == "ball":
            say = (f"is not needed: a ball geometry makes ball rows (leave element out; {four_point} makes "
                   f"them four-point rows); {rollers}")
        else:
            say = (f"must be one of {list(ROLLER_ELEMENTS)} (a roller geometry); for ball rows leave it out, "
                   f"for four-point rows give {four_point}")
        raise validate.FieldError(f"{where}.geometry.element", say, spec["element"])
    if isinstance(spec, dict) and "element" in spec:
        from .roller_geometry import roller_geometry_from_table

        clash = [k for k in ("element", "n_rollers", "roller_effective_length", "slices", "crown", "crown_radius",
                             "crown_design_load") if k in table]
        if clash:
            raise validate.FieldError(f"{where}.{clash[0]}", f"is set by [{where}.geometry]; remove it from "
                                      f"[{where}]", show_value=False)
        geometry = roller_geometry_from_table(spec, f"{where}.geometry")
    else:
        geometry = geometry_from_table(spec, f"{where}.geometry")
    model = {**table, **geometry.row_keywords()}
    if "rows" in table:
        rows = validate.array(table["rows"], f"{where}.rows", min_length=1)
        if geometry.row_spacing is not None:
            raise validate.FieldError(f"{where}.geometry.row_spacing", "is not used with rows; give each row its "
                                      "axial_offset", geometry.row_spacing)
        for i, r in enumerate(rows):
            validate.table(r, f"{where}.rows[{i}]", _GEOMETRY_ROW_KEYS)
    elif model.get("arrangement", "single") != "single":
        if geometry.row_spacing is None:
            raise validate.FieldError(f"{where}.geometry.row_spacing", f"(2e, mm, >= 0) is required for arrangement "
                                      f"{model['arrangement']!r}", show_value=False)
        model["row_offset"] = geometry.row_offset
    try:
        built = Bearing.from_table(model, where)
    except validate.FieldError as err:  # a key the geometry derived: name where the user typed it
        key = err.field.rpartition(".")[2]
        if err.field == f"{where}.{key}" and key in geometry.row_keywords() and key not in table:
            raise validate.FieldError(f"{where}.geometry.{key}", err.rule, err.value,
                                      show_value=err.show_value) from None
        raise
    if mounting_table is not None:
        mounting = mounting_from_table(mounting_table, geometry, f"{where}.mounting", group=group,
                                       clearance_range=clearance_range)
    elif clearance_range is not None:
        mounting = Mounting(given=False, clearance_group=group, clearance_range=clearance_range)
    else:
        mounting = None
    return replace(built, geometry=geometry, mounting=mounting)


def read_toml(path) -> dict:
    """Parse a TOML file; a missing, unreadable or malformed file becomes a ValueError naming the file."""
    path = Path(path)
    try:
        with path.open("rb") as fh:
            return tomllib.load(fh)
    except FileNotFoundError:
        raise ValueError(f"file not found: {path}") from None
    except IsADirectoryError:
        raise ValueError(f"{path} is a directory, not a TOML file") from None
    except OSError as err:
        raise ValueError(f"cannot read {path}: {err.strerror or err}") from None
    except UnicodeDecodeError:
        raise ValueError(f"{path}: not a TOML file (not UTF-8 text)") from None
    except tomllib.TOMLDecodeError as err:
        raise ValueError(f"{path}: not valid TOML: {err}") from None


def load_bearing(path) -> Bearing:
    """Read a bearing file: a TOML file with one ``[bearing]`` table (units N, mm, degrees), given by its path
    or, for a shipped one, by name (``load_bearing("6205")``; :func:`catalogue_names` lists them). A path
    that exists wins over a shipped name; neither: ValueError listing the shipped names."""
    path = find_bearing_file(path)
    doc = read_toml(path)
    unknown = sorted(set(doc) - {"bearing"})
    if unknown:
        raise ValueError(f"{path}: unknown top-level key(s) {unknown}; a bearing file holds one [bearing] table")
    if "bearing" not in doc:
        raise ValueError(f"{path}: missing the [bearing] table")
    return bearing_from_table(doc["bearing"])


def read_job_config(config, job: str):
    """A ``[bearing]`` + ``[JOB]`` config (TOML path or parsed dict), checked the same way for every job.
    ``bearing`` may instead name a bearing file (``bearing = "my-bearing.toml"``), relative to the config's
    folder (to the current folder for a dict), or a shipped one by name (``bearing = "7014C-DB"``); its text
    joins the config's in the provenance.

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
    if isinstance(doc["bearing"], str):  # bearing = "FILE.toml" (relative to the config) or a shipped NAME
        path = find_bearing_file(doc["bearing"], None if source is None else source.parent)
        return load_bearing(path), doc[job], text + "\n# bearing file " + str(path) + "\n" + path.read_text(), source
    return bearing_from_table(doc["bearing"]), doc[job], text, source
