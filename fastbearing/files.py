"""Writing files so that a half-written one never appears under its final name.

A leaf module: every writer (export, plots, the paper report, passage CSVs)
goes through :func:`publish`.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Callable


class DiskFull(RuntimeError):
    """The output's file system filled up during a run; what was finished is kept (see the message)."""


class OutputExists(ValueError):
    """An output exists and replacing it was not asked for. The message names the Python keyword; the
    command line says ``--overwrite`` instead (:meth:`cli_message`)."""

    def __init__(self, path):
        self.path = path if "://" in str(path) else Path(path)   # a store's URL stays a URL in the message
        super().__init__(f"{self.path} exists; pass overwrite=True to replace it")

    def cli_message(self) -> str:
        return f"{self.path} exists; pass --overwrite to replace it"


def refuse_overwrite(path, overwrite: bool) -> None:
    """OutputExists unless ``path`` is free or ``overwrite``: nothing replaces a user's file untold."""
    if Path(path).exists() and not overwrite:
        raise OutputExists(path)


def publish(path: Path, write: Callable[[Path], object]) -> Path:
    """Run ``write(tmp)`` on a temporary name beside ``path``, then rename it onto ``path``.

    The rename is atomic on one file system, so a reader sees the old file or
    the whole new one; on any failure (or Ctrl-C) the temporary file is
    removed and ``path`` is untouched.
    """
    path = Path(path)
    tmp = path.with_name(path.name + ".part")
    try:
        write(tmp)
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)
    return path


def publish_text(path: Path, text: str) -> Path:
    """:func:`publish` of a UTF-8 text."""
    return publish(path, lambda tmp: Path(tmp).write_text(text, encoding="utf-8"))
