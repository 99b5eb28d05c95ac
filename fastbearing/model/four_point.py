"""The four-point contact ball element (split-ring, gothic-arch, QJ type): its row and the row's two contact pairs.

Each ball of a four-point row touches each ring's two arcs, on the two diagonals at +a0 and -a0: two contact
pairs. A user gives one row (``element = "four_point_ball"``, the keys of a ball row, ``contact_angle`` the
nominal angle of each pair); the bearing holds it as its two :class:`ContactPair` rows, pair +1 and pair -1,
each an angular contact row of the same balls at the same axial place (docs/model.md, "Four-point contact
balls"). Quasi-statically that is the whole model: each pair acts as an angular contact row, so a four-point
row is a DB pair of its geometry with zero row spacing. At speed the two pairs share each ball, which is in
equilibrium under its (up to) four contacts, its centrifugal force and gyroscopic moment: the kernel
(engine/four_point.py) settles the pairs together, told by the speed table's PARTNER row
(:func:`partner_columns`). Units: N, mm, rad; angles a user types in degrees.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from .. import validate
from .ball_row import Row

ELEMENT = "four_point_ball"


def check_contact_angle(contact_angle) -> None:
    """FieldError unless a four-point row's ``contact_angle`` a0 is in (0, 90) degrees.

    At a0 = 0 the two arcs of each ring are one groove: the row's two contact pairs would be the same contact
    counted twice (every ball twice: kxx about 1.56 and L10r about 3.5 times the plain row's). Such a bearing
    is a deep-groove ball row (element = "ball", contact_angle = 0). No larger fixed minimum: whether a
    ring's two contact ellipses, at +a0 and -a0 on the ball, stay apart depends on the load as well (each
    spans about 2a/D rad either side of its contact point, a its semi-major axis, D the ball diameter), and a
    row above 0 but below 1 degree already warns that it was probably typed in radians."""
    if validate._is_number(contact_angle) and float(contact_angle) == 0.0:
        raise validate.FieldError("contact_angle", f"must be in (0, 90) degrees for a four-point row (element = "
                                  f"'{ELEMENT}'): at 0 its two arcs on each ring are one groove and every ball "
                                  "would count twice; give a ball row (element = 'ball', contact_angle = 0) for a "
                                  "deep-groove bearing", contact_angle)


@dataclass(frozen=True)
class FourPointRow(Row):
    """A four-point contact ball row as a user gives it: the keys of :class:`fastbearing.Row`, with
    ``contact_angle`` a0 (deg) the nominal angle of each contact pair. ``contact_direction`` is both (+1 and
    -1) and not given; ``axial_preload`` is 0 (a four-point row is preloaded by a negative
    ``radial_clearance``, which presses all four contacts). A :class:`fastbearing.Bearing` holds it as its
    :meth:`pairs`."""

    #: Not given: a four-point row's balls touch on both diagonals (None; any value given is refused).
    contact_direction: int | None = None

    element = ELEMENT
    element_word = "balls"
    defect_races = ()  # as its contact pairs'

    def __post_init__(self):
        if self.contact_direction is not None:  # also an explicit +1: the key has no meaning here
            raise validate.FieldError("contact_direction", "is not given for a four-point row (element = "
                                      f"'{ELEMENT}'): its balls touch on both diagonals, +a0 and -a0; remove the "
                                      "key", self.contact_direction)
        if self.axial_preload != 0:
            raise validate.FieldError("axial_preload", f"must be 0 for a four-point row (element = '{ELEMENT}'): "
                                      "preload it with a negative radial_clearance, which presses all four "
                                      "contacts", self.axial_preload)
        check_contact_angle(self.contact_angle)
        object.__setattr__(self, "contact_direction", 1)  # the ball row's checks, then back to "not given"
        try:
            super().__post_init__()
        finally:
            object.__setattr__(self, "contact_direction", None)

    def describe_line(self) -> str:
        return "four-point balls, pairs +a0 and -a0: " + ", ".join(
            part for part in self.pairs()[0].describe_line().partition(": ")[2].split(", ")
            if not part.startswith("s="))

    def report(self) -> dict:
        return {**self.pairs()[0].report(), "pair": None, "contact_direction": None}

    def pairs(self) -> tuple["ContactPair", "ContactPair"]:
        """The row's two contact pairs, +a0 (contact direction +1) then -a0 (-1)."""
        values = {f.name: getattr(self, f.name) for f in fields(Row)}
        return (ContactPair(**{**values, "contact_direction": 1}),
                ContactPair(**{**values, "contact_direction": -1}))


@dataclass(frozen=True)
class ContactPair(Row):
    """One contact pair of a four-point row (``contact_direction`` +1: the pair at +a0, -1: at -a0): to the
    quasi-static kernel an angular contact row; its ``n_balls`` are the row's balls, each counted once per
    pair (the per-element record holds each ball's contact of this pair)."""

    element = ELEMENT
    element_word = "balls (one contact pair)"
    #: Where a local defect may sit (model/defects.py): not modelled yet on four-point balls, which meet a race
    #: at two points.
    defect_races = ()

    def __post_init__(self):
        if self.axial_preload != 0:  # with_rows or a hand-built pair: the row's rule holds for its pairs
            raise validate.FieldError("axial_preload", f"must be 0 for a four-point row (element = '{ELEMENT}'): "
                                      "preload it with a negative radial_clearance", self.axial_preload)
        check_contact_angle(self.contact_angle)
        super().__post_init__()

    def describe_line(self) -> str:
        return f"four-point balls, pair {'+' if self.contact_direction > 0 else '-'}a0: {super().describe_line()}"

    def report(self) -> dict:
        return {"element": ELEMENT, "pair": self.contact_direction, **super().report()}


def expand(rows) -> tuple:
    """The rows as the bearing holds them: each :class:`FourPointRow` replaced by its two pairs, in place, and
    two neighbouring pairs -a0, +a0 (a mirrored row: contact directions flipped) put back as +a0, -a0."""
    out = []
    for r in rows:
        out.extend(r.pairs() if isinstance(r, FourPointRow) else (r,))
    i = 0
    while i < len(out) - 1:  # pair by pair: row k's pair - and row k+1's pair + are no pair
        a, b = out[i], out[i + 1]
        if isinstance(a, ContactPair) and isinstance(b, ContactPair) and _partners(a, b):
            if a.contact_direction == -1:
                out[i], out[i + 1] = b, a
            i += 2
        else:
            i += 1
    return tuple(out)


def _partners(a: "ContactPair", b: "ContactPair") -> bool:
    """Whether two contact pairs are one four-point row's: opposite directions, alike in every other key."""
    return (a.contact_direction == -b.contact_direction
            and all(getattr(a, f.name) == getattr(b, f.name) for f in fields(Row) if f.name != "contact_direction"))


def check_pairs(rows) -> None:
    """FieldError unless every :class:`ContactPair` stands next to its partner (pair + then pair -, alike in
    every other key), as :meth:`FourPointRow.pairs` leaves them: the kernel at speed pairs them by place."""
    i = 0
    while i < len(rows):
        if isinstance(rows[i], ContactPair):
            a, b = rows[i], rows[i + 1] if i + 1 < len(rows) else None
            same = (isinstance(b, ContactPair) and a.contact_direction == 1 and b.contact_direction == -1
                    and all(getattr(a, f.name) == getattr(b, f.name) for f in fields(Row)
                            if f.name != "contact_direction"))
            if not same:
                raise validate.FieldError(f"rows[{i}]", "is a four-point contact pair without its partner; give "
                                          f"the row as one FourPointRow (element = '{ELEMENT}')", show_value=False)
            i += 2
        else:
            i += 1


def merged(rows) -> list[dict]:
    """The rows as ``[bearing]`` row tables, each pair of contact pairs one four-point row again."""
    out = []
    skip = False
    for r in rows:
        if skip:
            skip = False
            continue
        values = {f.name: getattr(r, f.name) for f in fields(r) if getattr(r, f.name) is not None}
        if isinstance(r, ContactPair):
            values.pop("contact_direction")
            values.pop("axial_preload")
            values["element"] = ELEMENT
            skip = True
        out.append(values)
    return out


def partner_columns(rows) -> np.ndarray:
    """For the ball table's columns (ball rows in order, Z columns each): the column of the same ball's other
    contact pair, -1 for a ball of an ordinary row (float64: a row of the speed table)."""
    ball_rows = [r for r in rows if isinstance(r, Row)]
    partner = np.full(sum(r.n_balls for r in ball_rows), -1.0)
    k = 0
    i = 0
    while i < len(ball_rows):
        n = ball_rows[i].n_balls
        if isinstance(ball_rows[i], ContactPair):
            partner[k:k + n] = np.arange(k + n, k + 2 * n)
            partner[k + n:k + 2 * n] = np.arange(k, k + n)
            k += 2 * n
            i += 2
        else:
            k += n
            i += 1
    return partner
