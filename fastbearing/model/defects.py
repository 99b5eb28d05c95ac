"""Local defects (spalls) on a race or a ball, for ball-passage tables over shaft revolutions (docs/model.md,
"Local defects and fault frequencies").

A defect is a pit of a given depth and width (mm, along the raceway or the ball's surface) centred at an
angle. An element whose contact lies in it loses the profile's depth from its approach at that race: a ball
of the quasi-static model (its two contacts in series) has its groove-centre distance A0 grown by the depth
(and A^2 - A0^2 by -d (2 A0 + d), so that a depth of 0 leaves the table bit for bit), a roller slice its
approach offset shrunk by it. Where any element carries a defect the table's mirror half is switched off.
The element sees the defect per position of the table: the positions run over shaft revolutions, the cage
turning at the FTF order of the shaft (analysis/faults.py), an inner-race defect with the inner ring, an
outer-race one with the outer, a ball's with the ball's spin (it meets the outer race when its spin angle
is the defect's angle, the inner half a turn later). Units: mm, degrees as typed, rad inside.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import validate
from ..engine.schema import (A0, COS_PSI, GAP2, HALF_COUNT, INNER_RADIUS, OUTER_RADIUS, S_COS_PSI, S_OFFSET,
                             S_ROLLER, S_SIN_PSI, SIN_PSI)

RACES = ("outer", "inner", "ball")
PROFILES = ("rectangular", "half_sine")
_DEFECT_KEYS = ("race", "angle", "width", "depth", "profile", "element")
#: Largest defect ``angle`` either way, degrees: one turn covers every place (beyond it a typo, or radians
#: taken for a huge number, and 1e300 deg loses every digit when wrapped).
MAX_ANGLE = 360.0


@dataclass(frozen=True)
class Defect:
    """One local defect: ``race`` ("outer", "inner" or "ball": the ball number ``element`` in the bearing's
    element record), ``angle`` (deg, in [-360, 360]: where its centre is at position 0, from +x on a race; on a
    ball from its outer contact point), ``width`` (mm along the raceway or the ball's surface, > 0), ``depth`` (mm,
    >= 0), ``profile`` ("rectangular" or "half_sine": depth cos(pi x / width) across it)."""

    race: str
    angle: float
    width: float
    depth: float
    profile: str = "rectangular"
    element: int | None = None

    def profile_depth(self, x: np.ndarray) -> np.ndarray:
        """The depth (mm) at the distances ``x`` (mm) from the defect's centre along its surface."""
        inside = np.abs(x) < 0.5 * self.width
        if self.profile == "half_sine":
            return np.where(inside, self.depth * np.cos(np.pi * x / self.width), 0.0)
        return np.where(inside, self.depth, 0.0)


def parse_defects(spec, bearing, where: str = "passage.defects") -> tuple[Defect, ...]:
    """The ``[[passage.defects]]`` tables as Defects; FieldError naming the field and its allowed values."""
    items = validate.array(spec, where, min_length=1)
    out = []
    for i, d in enumerate(items):
        at = f"{where}[{i}]"
        validate.table(d, at, _DEFECT_KEYS, ("race", "width", "depth"))
        race = validate.choice(d["race"], f"{at}.race", RACES)
        for r in bearing.rows:  # each element kind says where its defects are modelled
            if race not in r.defect_races:
                where = ", ".join(r.defect_races) if r.defect_races else "no local defects yet"
                raise validate.FieldError(f"{at}.race", f"is not modelled on rows of {r.element} elements "
                                          f"({r.element_word}): they take {where}", race)
        element = None
        if race == "ball":
            if "element" not in d:
                raise validate.FieldError(f"{at}.element", "is required for a ball defect: the ball's number in the "
                                          f"bearing's element record (0 .. {bearing.n_balls - 1})", show_value=False)
            element = validate.integer(d["element"], f"{at}.element", low=0, high=bearing.n_balls - 1)
        elif "element" in d:
            raise validate.FieldError(f"{at}.element", "goes with race = \"ball\" only", d["element"])
        out.append(Defect(race, validate.number(d.get("angle", 0.0), f"{at}.angle", low=-MAX_ANGLE, high=MAX_ANGLE,
                                                units="degrees"),
                          validate.number(d["width"], f"{at}.width", low=0, low_open=True, units="mm"),
                          validate.number(d["depth"], f"{at}.depth", low=0, units="mm"),
                          validate.choice(d.get("profile", "rectangular"), f"{at}.profile", PROFILES), element))
    return tuple(out)


@dataclass(frozen=True)
class Kinematics:
    """What places the defects: ball diameter D and pitch diameter dm (mm), the contact angle (rad), the
    ring that turns, and the orders of the shaft speed of the cage (FTF) and of a ball's spin (BSF)."""

    ball_diameter: float
    pitch_diameter: float
    contact_angle: float
    rotating: str
    cage_order: float
    spin_order: float


def _wrap(angle):
    """Angles to (-pi, pi]."""
    return np.pi - np.mod(np.pi - angle, 2.0 * np.pi)


def element_depths(defects, kin: Kinematics, azimuths: np.ndarray, shaft_angle: float):
    """Each element's defect depth (mm) at one position at its inner and its outer contact, (inner, outer):
    ``azimuths`` (rad) of the elements there, the shaft turned by ``shaft_angle`` (rad) from position 0.
    Race defects reach every element over them; a ball defect its ball alone, at the race it meets."""
    inner = np.zeros(azimuths.shape[0])
    outer = np.zeros(azimuths.shape[0])
    D, dm, cos_a = kin.ball_diameter, kin.pitch_diameter, math.cos(kin.contact_angle)
    for d in defects:
        a0 = math.radians(d.angle)
        if d.race in ("outer", "inner"):
            turns = (d.race == "inner") == (kin.rotating == "inner")  # the race turns with the shaft
            centre = a0 + (shaft_angle if turns else 0.0)
            radius = 0.5 * dm + (0.5 if d.race == "outer" else -0.5) * D * cos_a  # the contact's track
            depth = d.profile_depth(_wrap(azimuths - centre) * radius)
            if d.race == "outer":
                outer += depth
            else:
                inner += depth
        else:
            spin = kin.spin_order * shaft_angle  # the ball's spin since position 0, rad
            outer[d.element] += float(d.profile_depth(_wrap(spin - a0) * 0.5 * D))
            inner[d.element] += float(d.profile_depth(_wrap(spin - a0 - math.pi) * 0.5 * D))
    return inner, outer


def with_speed_defects(speed_table: np.ndarray, inner: np.ndarray, outer: np.ndarray) -> np.ndarray:
    """A high-speed table whose balls' grooves are deeper by the defect depths (mm) at their inner and outer
    contacts: (f - 1/2) D + d, so that a ball touches the race d later. Unchanged without."""
    if not (np.any(inner) or np.any(outer)):
        return speed_table
    out = speed_table.copy()
    out[INNER_RADIUS] = speed_table[INNER_RADIUS] + inner
    out[OUTER_RADIUS] = speed_table[OUTER_RADIUS] + outer
    return out


def with_ball_defects(table: np.ndarray, depth: np.ndarray) -> np.ndarray:
    """A ball table whose balls lose ``depth`` (mm per column) of approach: A0 + d, and A^2 - A0^2 at q = 0
    by -d (2 A0 + d); the mirror half off where any depth is non-zero. Unchanged (the same array) without."""
    if not np.any(depth):
        return table
    out = table.copy()
    out[GAP2] = table[GAP2] - depth * (2.0 * table[A0] + depth)
    out[A0] = table[A0] + depth
    out[HALF_COUNT] = 0.0
    return out


def with_slice_defects(slices: np.ndarray, depth_of_roller: np.ndarray, n_balls: int) -> np.ndarray:
    """A slice table whose rollers lose their defect depth (mm; ``depth_of_roller`` per element of the
    record, the rollers after the ``n_balls`` balls) from every slice's approach offset."""
    if slices.shape[1] == 0:
        return slices
    d = depth_of_roller[slices[S_ROLLER].astype(np.int64)]
    if not np.any(d):
        return slices
    out = slices.copy()
    out[S_OFFSET] = slices[S_OFFSET] - d
    return out


def table_azimuths(table: np.ndarray, slices: np.ndarray, n_elements: int) -> np.ndarray:
    """Each element's azimuth (rad) at a position: the balls' from the ball table, each roller's from its
    first slice."""
    psi = np.zeros(n_elements)
    n_balls = table.shape[1]
    psi[:n_balls] = np.arctan2(table[SIN_PSI], table[COS_PSI])
    if slices is not None and slices.shape[1]:
        rollers = slices[S_ROLLER].astype(np.int64)
        psi[rollers] = np.arctan2(slices[S_SIN_PSI], slices[S_COS_PSI])
    return psi
