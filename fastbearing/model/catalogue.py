"""The shipped bearing files: fastbearing/catalogue/NAME.toml, package data found by name from any folder.

``--bearing 6205``, ``fb.load_bearing("6205")`` and ``bearing = "6205"`` in a config read
``fastbearing/catalogue/6205.toml`` (:func:`find_bearing_file`); a path to a file of your own still works
and wins when it exists. The files are the one copy of each bearing: the presets (``--preset``,
``Bearing.preset``, ``preset = "NAME"``) are the catalogue's model-parameter files (those without a
``[bearing.geometry]`` table), read from the same folder. `fastbearing bearings`
(:mod:`fastbearing.report.catalogue`) lists them with their type, dimensions, ratings and sources.
"""

from __future__ import annotations

import tomllib
from functools import lru_cache
from importlib import resources
from pathlib import Path

__all__ = ["catalogue_file", "catalogue_folder", "catalogue_names", "catalogue_table", "find_bearing_file",
           "preset_names"]


def catalogue_folder() -> Path:
    """The folder of the shipped bearing files (inside the installed package)."""
    return Path(str(resources.files("fastbearing").joinpath("catalogue")))


@lru_cache(maxsize=1)
def _names() -> tuple[str, ...]:
    return tuple(sorted((p.stem for p in catalogue_folder().glob("*.toml")), key=str.lower))


def catalogue_names() -> list[str]:
    """Names of the shipped bearings (their file names without ``.toml``), e.g. ``"6205"``, ``"7014C-DB"``."""
    return list(_names())


def _lookup(name: str) -> str | None:
    """The shipped name ``name`` means (case-insensitive; ``NAME.toml`` accepted), or None."""
    key = name[:-5] if name.lower().endswith(".toml") else name
    for n in _names():
        if n.lower() == key.lower():
            return n
    return None


def catalogue_file(name: str) -> Path:
    """The file of a shipped bearing; ValueError listing the shipped names when there is none."""
    found = _lookup(name) if isinstance(name, str) else None
    if found is None:
        raise ValueError(f"no shipped bearing named {name!r}; shipped bearings: {', '.join(_names())} "
                         "(`fastbearing bearings` lists them)")
    return catalogue_folder() / f"{found}.toml"


def catalogue_table(name: str) -> dict:
    """A copy of a shipped bearing file's ``[bearing]`` table."""
    return dict(tomllib.loads(catalogue_file(name).read_text(encoding="utf-8"))["bearing"])


def preset_names() -> list[str]:
    """Names of the shipped presets: the catalogue's files given by model parameters (no
    ``[bearing.geometry]``), which ``preset = "NAME"`` and ``--preset NAME`` start from."""
    return list(_preset_names())


@lru_cache(maxsize=1)
def _preset_names() -> tuple[str, ...]:
    return tuple(n for n in _names() if "geometry" not in catalogue_table(n))


def find_bearing_file(name_or_path, base=None, field: str = "bearing") -> Path:
    """The bearing file that ``name_or_path`` means: a path (relative to ``base`` when given and the path is
    relative) where that file exists, else a shipped bearing of that name (``"6205"``). ValueError naming
    ``field``, the path tried and the shipped names when it is neither."""
    path = Path(name_or_path)
    if base is not None and not path.is_absolute():
        path = Path(base) / path
    if path.is_file():
        return path
    text = str(name_or_path)
    # a bare name (no folder part) may be a shipped bearing; a path with folders is only ever a path
    if Path(text).name == text:
        found = _lookup(text)
        if found is not None:
            return catalogue_folder() / f"{found}.toml"
    if path.is_dir():
        raise ValueError(f"{field} = {text!r}: {path} is a directory, not a bearing file")
    where = f" (a path is taken relative to the config's folder, {base})" if base is not None else ""
    raise ValueError(f"{field} = {text!r}: no bearing file at {path}{where} (file not found), and no shipped "
                     f"bearing of that name; shipped bearings: {', '.join(_names())} (`fastbearing bearings` "
                     "lists them)")
