"""One set of checks for every value a user gives: config files, bearing files, the API, the CLI.

Each check returns the clean value or raises :class:`FieldError`, a
``ValueError`` that carries the field's path (``bearing.rows[1].n_balls``)
as data and the rule it broke, so callers add context with :meth:`FieldError.within`
instead of editing message strings. The rules are the same everywhere:

- a number is an int or a float (a TOML/JSON number, a numpy scalar);
  strings are refused even when they spell a number, and so are booleans;
- an integer may be given as an integral float (``14.0``), never as 2.5;
- every number must be finite and inside the range the field states.

Leaf module: imports nothing from fastbearing.
"""

from __future__ import annotations

import math
import numbers


class FieldError(ValueError):
    """A bad value: ``field`` is its path, ``rule`` what it must be, ``value`` what it was."""

    def __init__(self, field: str, rule: str, value=None, *, show_value: bool = True):
        self.field = field
        self.rule = rule
        self.value = value
        self.show_value = show_value
        super().__init__(self._text())

    def _text(self) -> str:
        value = self.value
        if type(value).__module__ == "numpy" and hasattr(value, "item") and getattr(value, "ndim", 1) == 0:
            value = value.item()  # 5000.0, not np.float64(5000.0)
        got = f", got {value!r}" if self.show_value else ""
        return f"{self.field} {self.rule}{got}" if self.field else f"{self.rule}{got}"

    def within(self, prefix: str) -> "FieldError":
        """The same error one level down: ``prefix.field`` (``prefix[0]`` when field is an index)."""
        if not prefix:
            return self
        if not self.field:
            field = prefix
        elif self.field.startswith("["):
            field = prefix + self.field
        else:
            field = f"{prefix}.{self.field}"
        return FieldError(field, self.rule, self.value, show_value=self.show_value)


def _is_number(value) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def number(value, field: str, *, low=None, high=None, low_open=False, high_open=False, units: str = "") -> float:
    """A finite float in the given range (bounds included unless ``*_open``); units go into the message."""
    unit = f" {units}" if units else ""
    if not _is_number(value):
        raise FieldError(field, f"must be a number{_range(low, high, low_open, high_open, unit)}", value)
    x = float(value)
    if not math.isfinite(x):
        raise FieldError(field, f"must be finite{_range(low, high, low_open, high_open, unit)}", value)
    if low is not None and (x < low or (low_open and x == low)):
        raise FieldError(field, f"must be{_range(low, high, low_open, high_open, unit)}", value)
    if high is not None and (x > high or (high_open and x == high)):
        raise FieldError(field, f"must be{_range(low, high, low_open, high_open, unit)}", value)
    return x


def integer(value, field: str, *, low=None, high=None) -> int:
    """An integer in [low, high]; an integral float such as 14.0 is accepted, 2.5 is not."""
    span = _range(low, high, False, False, "")
    if not _is_number(value) or not math.isfinite(float(value)) or float(value) != math.floor(float(value)):
        raise FieldError(field, f"must be an integer{span}", value)
    n = int(value)
    if (low is not None and n < low) or (high is not None and n > high):
        raise FieldError(field, f"must be an integer{span}", value)
    return n


def boolean(value, field: str) -> bool:
    """true or false (not a string, not a number)."""
    if not isinstance(value, bool):
        raise FieldError(field, "must be true or false", value)
    return value


def choice(value, field: str, options) -> str:
    """One of ``options`` (compared as given)."""
    if not isinstance(value, str) or value not in options:
        raise FieldError(field, f"must be one of {list(options)}", value)
    return value


def text(value, field: str) -> str:
    """A string."""
    if not isinstance(value, str):
        raise FieldError(field, "must be a string", value)
    return value


def table(value, field: str, allowed=None, required=()) -> dict:
    """A table (dict); with ``allowed``, unknown keys are refused; ``required`` keys must be present."""
    if not isinstance(value, dict):
        raise FieldError(field, f"must be a table, not {type(value).__name__}", show_value=False)
    if allowed is not None:
        unknown = sorted(set(value) - set(allowed))
        if unknown:
            raise FieldError(field, f"has unknown key(s) {unknown}; allowed: {sorted(allowed)}", show_value=False)
    missing = [k for k in required if k not in value]
    if missing:
        raise FieldError(field, f"is missing required key(s) {missing}", show_value=False)
    return value


def array(value, field: str, *, length=None, min_length=0) -> list:
    """A list (or tuple); with ``length``, exactly that many items; at least ``min_length``."""
    if not isinstance(value, (list, tuple)):
        what = f"a list of {length}" if length is not None else "a list"
        raise FieldError(field, f"must be {what}, not {type(value).__name__}", show_value=False)
    if length is not None and len(value) != length:
        raise FieldError(field, f"must be a list of {length} items, got {len(value)}", show_value=False)
    if len(value) < min_length:
        raise FieldError(field, f"must hold at least {min_length} item(s), got {len(value)}", show_value=False)
    return list(value)


def numbers_list(value, field: str, length: int, **bounds) -> list[float]:
    """A list of exactly ``length`` numbers, each checked by :func:`number`."""
    items = array(value, field, length=length)
    return [number(v, f"{field}[{i}]", **bounds) for i, v in enumerate(items)]


def _range(low, high, low_open, high_open, unit) -> str:
    if low is None and high is None:
        return ""
    if high is None:
        return f" {'>' if low_open else '>='} {low:g}{unit}"
    if low is None:
        return f" {'<' if high_open else '<='} {high:g}{unit}"
    left = "(" if low_open else "["
    right = ")" if high_open else "]"
    return f" in {left}{low:g}, {high:g}{right}{unit}"
