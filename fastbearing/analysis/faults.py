"""Bearing fault frequencies: the cage, ball-pass and ball-spin frequencies from the kinematics of rolling
without slip (docs/model.md, "Local defects and fault frequencies").

With gamma = (D/dm) cos(a) (D ball diameter, dm pitch diameter, a the contact angle) and f_r the shaft's
rotation frequency, the inner ring turning and the outer fixed:

    FTF  = f_r/2 (1 - gamma)                  cage (fundamental train)
    BPFO = Z f_r/2 (1 - gamma)                a ball passing a point of the outer race
    BPFI = Z f_r/2 (1 + gamma)                a ball passing a point of the inner race
    BSF  = dm/(2 D) f_r (1 - gamma^2)         a ball's spin about its own axis
    ball_defect = 2 BSF                       a point of a ball meeting either race

With the outer ring turning instead only the cage changes, FTF = f_r/2 (1 + gamma): the ball-pass frequencies
depend on the rings' relative speed alone (Z |f_o - f_c| = Z f_r/2 (1 - gamma) at the outer race, Z |f_i - f_c|
= Z f_r/2 (1 + gamma) at the inner), and so does the spin. Units: Hz; orders are
multiples of the shaft frequency (f_r = rpm / 60).
"""

from __future__ import annotations

import math

from .. import validate

#: The frequencies, in the order they are reported.
NAMES = ("FTF", "BPFO", "BPFI", "BSF", "ball_defect")


def fault_orders(ball_diameter: float, pitch_diameter: float, n_balls: int, contact_angle: float = 0.0,
                 rotating: str = "inner") -> dict[str, float]:
    """The fault frequencies as orders of the shaft speed (Hz per Hz of shaft rotation): ball diameter D and
    pitch diameter dm in mm, Z balls, contact angle in degrees (the loaded angle at an operating point, or
    the nominal one), the ring that turns ("inner" or "outer")."""
    D = validate.number(ball_diameter, "ball_diameter", low=0, low_open=True, units="mm")
    dm = validate.number(pitch_diameter, "pitch_diameter", low=D, low_open=True, units="mm")
    Z = validate.integer(n_balls, "n_balls", low=1)
    a = validate.number(contact_angle, "contact_angle", low=0, high=90, high_open=True, units="degrees")
    validate.choice(rotating, "rotating", ("inner", "outer"))
    gamma = D / dm * math.cos(math.radians(a))
    cage = 0.5 * (1.0 - gamma) if rotating == "inner" else 0.5 * (1.0 + gamma)
    bsf = dm / (2.0 * D) * (1.0 - gamma * gamma)
    outer_pass, inner_pass = (Z * 0.5 * (1.0 - gamma), Z * 0.5 * (1.0 + gamma))  # whichever ring turns
    return {"FTF": cage, "BPFO": outer_pass, "BPFI": inner_pass, "BSF": bsf, "ball_defect": 2.0 * bsf}


def fault_frequencies(ball_diameter: float, pitch_diameter: float, n_balls: int, shaft_speed: float,
                      contact_angle: float = 0.0, rotating: str = "inner") -> dict[str, dict[str, float]]:
    """{name: {"hz": ..., "order": ...}} for FTF, BPFO, BPFI, BSF and ball_defect at ``shaft_speed`` (rpm > 0),
    from :func:`fault_orders` (same arguments, mm and degrees)."""
    rpm = validate.number(shaft_speed, "speed", low=0, low_open=True, units="rpm")
    fr = rpm / 60.0
    return {k: {"hz": v * fr, "order": v} for k, v in fault_orders(ball_diameter, pitch_diameter, n_balls,
                                                                    contact_angle, rotating).items()}
