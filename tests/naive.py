"""Slow, obviously-correct reference for the test-suite.

Written straight from the PRINTED equations of Gunduz & Singh (2013),
J. Sound Vib. 332, 5898-5916: Eqs. (3), (4a,b), (7a,b), (9)-(11) per ball,
Eq. (12) for the load vector and Eqs. (15a)-(15o) for the stiffness matrix,
ball by ball, in plain Python + math (numpy only to build the output arrays).
It deliberately does NOT use the compact J^T H J form (docs/model.md,
"Stiffness matrix Kb = df/dq (paper Eq. 14-15)"), so the two can be checked
against each other.

Notation (per ball): dr, dz  Eq. (4a,b); dnr = ur, dnz = uz  Eq. (7a,b);
A  Eq. (9); delta = A - A0  Eq. (3); Q = Kn delta^n  Eq. (10);
tan(alpha) = uz/ur  Eq. (11).  The paper's c1*e is the signed row offset
z_r ("axial_offset") and its e^2 is z_r^2; c3 is "contact_direction".

Printed typos found.  Every entry was checked against a central finite
difference of this file's own Eq. (12) (`_check_against_fd` below) on 2884
random cases: 1-3 rows of 1-20 balls, z_r in {0, U(-30,30)} mm, c3 = +-1,
a0 in 5-80 deg, clearance or preload (rL = 0) or neither, n = 1.5 or
U(1.1, 2), random small q loading some balls.  With the fixes below the worst
error is 1.3e-7 relative to sqrt(|K_ii K_jj|) (1.7e-6 relative to the entry
itself for entries above 1e-3 of that scale): finite-difference noise.
Results also agree with the compact J^T H J form (docs/model.md, "Stiffness
matrix Kb = df/dq (paper Eq. 14-15)") to ~1e-16.
As printed, the entries listed below fail in every case where they can
(15d,e,h,i whenever a loaded row has z_r != 0; 15g, 15l always):

  (15d) k_x_thx, (15e) k_x_thy, (15h) k_y_thx, (15i) k_y_thy:
      the second bracket is printed  (R*dnz*dnr - c1*e*dnz^2);
      correct is                     (R*dnz*dnr + c1*e*dnz^2)
      (sign of the c1*e*dnz^2 term).  Derivation: Fx = (Q/A)*dnr*cos(psi) and
      d(dnr)/d(bx) = -c1*e*sin(psi) by Eq. (4a), so the (Q/A)(1 - dnr^2/A^2)
      part of dFx/dbx is -c1*e*sin*cos*dnz^2/A^3*Kn*delta^n: written as
      "-(R dnz dnr + c1 e dnz^2)" it needs the plus.  The printed error
      vanishes only for e = 0 (single row), which is presumably why it went
      unnoticed.  FD of Eq. (12) confirms the corrected sign for z_r != 0.
  (15g) k_yz: printed factor (1 - nA/(A-A0)); correct is (nA/(A-A0) - 1),
      the same as k_xz (15c) with cos -> sin.  As printed k_yz has the wrong
      sign: FD of Fy w.r.t. dz and of Fz w.r.t. dy (which agree with each
      other, f being the gradient of the contact energy) both give the
      corrected sign.
  (15l) k_z_thy: the last factor is printed  (nA/A - A0)  without the
      parentheses that every other entry has; correct is nA/(A - A0).
      (Likely a typesetting slip; literal reading is dimensionally wrong.)

All other entries (15a,b,c,f,j,k,m,n,o) are correct as printed.

Division by dnr = ur: the printed forms (15k), (15l), (15m), (15n), (15o)
contain dnz^3/dnr and A^2*dnz/dnr.  These terms combine algebraically to
dnz*dnr (e.g. -uz^3/ur + A^2 uz/ur = uz*ur), but as printed they divide by
ur = dr + A0*cos(a0), which -> 0 as a0 -> 90 deg (pure thrust contact) and
for balls whose radial approach cancels A0*cos(a0).  This is the origin of
the "numerical issues around a0 = 90 deg" the paper mentions; the compact
form (docs/model.md, "Stiffness matrix Kb = df/dq (paper Eq. 14-15)") has no
such division.  This reference keeps the printed division (it is the point of
the reference): a loaded ball with ur == 0 exactly raises ZeroDivisionError,
and for z_r != 0 cancellation costs accuracy as ur -> 0 (seen: ~1e-8 relative
at ur = 1e-12 mm).

Note for the test-suite: with rL = 0, d0 = 0 the model is NOT exactly
homogeneous in q (A = |u0 + J q| with |u0| = A0, so delta = A - A0 is only
approximately linear in q); Kb.q = n f holds only to first order (errors of
a few % at q ~ 0.01-0.05 mm were observed).  Do not test it tightly.
"""

import math

import numpy as np

_DOFS = ("x", "y", "z", "thx", "thy")


# --------------------------------------------------------------------------
# per-ball kinematics: Eqs. (4a,b), (7a,b), (9), (3), (10), (11)
# --------------------------------------------------------------------------
def _ball_state(q, row, psi):
    dx, dy, dz, bx, by = (float(v) for v in q)
    c1e = float(row["axial_offset"])
    c3 = float(row["contact_direction"])
    a0 = float(row["contact_angle"])
    A0 = float(row["groove_center_distance"])
    R = float(row["pitch_radius"])
    rL = float(row["radial_clearance"])
    d0 = float(row["axial_preload"])
    # Eq. (4a): radial approach
    dr = (dx + c1e * by) * math.cos(psi) + (dy - c1e * bx) * math.sin(psi) - rL
    # Eq. (4b): axial approach
    dzb = dz + R * (bx * math.sin(psi) - by * math.cos(psi))
    # Eq. (7a,b): net radial / axial
    ur = dr + A0 * math.cos(a0)
    uz = dzb + c3 * (A0 * math.sin(a0) + d0)
    # Eq. (9)
    A = math.sqrt(ur * ur + uz * uz)
    # Eq. (3)
    delta = A - A0
    return ur, uz, A, delta


def _balls(row):
    Z = int(row["n_balls"])
    psi0 = float(row["first_ball_angle"])
    for j in range(Z):
        yield psi0 + 2.0 * math.pi * j / Z


# --------------------------------------------------------------------------
# Eq. (12): load vector, alpha form
# --------------------------------------------------------------------------
def naive_load(q, rows):
    """f (5,) from Eq. (12), ball by ball (N, N*mm)."""
    f = [0.0] * 5
    for row in rows:
        Kn = float(row["hertz_constant"])
        n = float(row["exponent"])
        R = float(row["pitch_radius"])
        c1e = float(row["axial_offset"])
        for psi in _balls(row):
            ur, uz, A, delta = _ball_state(q, row, psi)
            if delta <= 0.0:
                continue
            Q = Kn * delta ** n                       # Eq. (10)
            alpha = math.atan2(uz, ur)                # Eq. (11)
            ca, sa = math.cos(alpha), math.sin(alpha)
            cp, sp = math.cos(psi), math.sin(psi)
            f[0] += Q * ca * cp
            f[1] += Q * ca * sp
            f[2] += Q * sa
            f[3] += Q * (R * sa - c1e * ca) * sp
            f[4] += Q * (-R * sa + c1e * ca) * cp
    return np.array(f, dtype=np.float64)


# --------------------------------------------------------------------------
# Eqs. (15a)-(15o): one ball's contribution (without the sum)
# --------------------------------------------------------------------------
def _ball_stiffness_printed(ur, uz, A, delta, psi, c1e, R, A0, Kn, n,
                            literal=False):
    """Dict of the 15 independent entries for one loaded ball.

    literal=False: corrected entries (see module docstring).
    literal=True : (15d,e,g,h,i,l) exactly as printed, typos included; kept
                   only to document the typos (tests can show they fail FD).
    """
    e2 = c1e * c1e                      # paper's e^2 (c1^2 = 1)
    sp, cp = math.sin(psi), math.cos(psi)
    s2, c2, sc = sp * sp, cp * cp, sp * cp
    dn = delta ** n                     # (delta_j^i)^n
    A3 = A ** 3
    m = n * A / (A - A0)                # the recurring n A / (A - A0)
    pre = Kn * dn / A3

    k = {}
    # (15a)
    k["x", "x"] = pre * c2 * (m * ur * ur + uz * uz)
    # (15b)
    k["x", "y"] = pre * sc * (m * ur * ur + uz * uz)
    # (15c)
    k["x", "z"] = pre * ur * uz * cp * (m - 1.0)

    # (15d),(15e),(15h),(15i): common brackets
    P = R * uz * ur - c1e * ur * ur     # (R dnz dnr - c1 e dnr^2), as printed
    if literal:
        S = R * uz * ur - c1e * uz * uz  # as printed (typo)
    else:
        # FIX: printed "- c1 e dnz^2", correct "+ c1 e dnz^2" (FD-verified)
        S = R * uz * ur + c1e * uz * uz
    # (15d)
    k["x", "thx"] = pre * sc * (m * P - S)
    # (15e)
    k["x", "thy"] = pre * c2 * (-m * P + S)
    # (15f)
    k["y", "y"] = pre * s2 * (m * ur * ur + uz * uz)
    # (15g)
    if literal:
        k["y", "z"] = pre * ur * uz * sp * (1.0 - m)   # as printed (typo)
    else:
        # FIX: printed (1 - nA/(A-A0)), correct (nA/(A-A0) - 1) (FD-verified)
        k["y", "z"] = pre * ur * uz * sp * (m - 1.0)
    # (15h)
    k["y", "thx"] = pre * s2 * (m * P - S)
    # (15i)
    k["y", "thy"] = pre * sc * (-m * P + S)
    # (15j)
    k["z", "z"] = pre * (m * uz * uz + ur * ur)
    # (15k)  -- divides by dnr = ur
    k["z", "thx"] = pre * sp * (
        R * A * A - (R * uz * uz + c1e * uz ** 3 / ur)
        + c1e * (uz / ur) * A * A
        + (R * uz * uz - c1e * uz * ur) * m)
    # (15l)  -- divides by dnr = ur
    if literal:
        m_l = n * A / A - A0            # printed "(nA/A - Ao)" (typo)
    else:
        # FIX: missing parentheses, correct nA/(A - A0) (FD-verified)
        m_l = m
    k["z", "thy"] = pre * cp * (
        (-R * A * A + R * uz * uz + c1e * uz ** 3 / ur)
        - c1e * (uz / ur) * A * A
        - (R * uz * uz - c1e * uz * ur) * m_l)
    # (15m),(15n),(15o): common bracket -- divides by dnr = ur
    T = (R * R * A * A
         + c1e * R * (ur * uz - uz ** 3 / ur + A * A * (uz / ur))
         + (e2 - R * R) * uz * uz
         + m * (R * uz - c1e * ur) ** 2)
    # (15m)
    k["thx", "thx"] = pre * s2 * T
    # (15n)  (printed with every term negated, i.e. -T)
    k["thx", "thy"] = pre * sc * (-T)
    # (15o)
    k["thy", "thy"] = pre * c2 * T
    return k


def naive_load_stiffness(q, rows):
    """f (5,) and Kb (5,5) from the paper's Eq. (12) and Eq. (15a-o), ball by ball.
    q = (dx, dy, dz, bx, by) in mm and rad.
    rows: list of dicts, one per row, keys:
      n_balls (int Z), first_ball_angle (rad, psi0; ball j at psi0 + 2*pi*j/Z),
      axial_offset (mm, signed z_r = c1*e of the paper), contact_direction (+1/-1, c3),
      contact_angle (rad, a0), groove_center_distance (mm, A0), pitch_radius (mm, R),
      hertz_constant (Kn, N/mm^n), exponent (n), radial_clearance (mm, rL), axial_preload (mm, d0).
    Returns (f, K) as numpy float64 arrays, N / N*mm and N/mm, N*mm/rad, N/rad."""
    return _load_stiffness(q, rows, literal=False)


def naive_load_stiffness_as_printed(q, rows):
    """Same as naive_load_stiffness but with (15d,e,g,h,i,l) exactly as printed,
    typos included.  Documentation only: the result is WRONG whenever a row has
    z_r != 0 (15d,e,h,i) or a loaded ball has dnr*dnz != 0 (15g, 15l)."""
    return _load_stiffness(q, rows, literal=True)


def _load_stiffness(q, rows, literal):
    f = naive_load(q, rows)
    K = [[0.0] * 5 for _ in range(5)]
    idx = {name: i for i, name in enumerate(_DOFS)}
    for row in rows:
        Kn = float(row["hertz_constant"])
        n = float(row["exponent"])
        R = float(row["pitch_radius"])
        A0 = float(row["groove_center_distance"])
        c1e = float(row["axial_offset"])
        for psi in _balls(row):
            ur, uz, A, delta = _ball_state(q, row, psi)
            if delta <= 0.0:                  # Eq. (3): unloaded ball
                continue
            kb = _ball_stiffness_printed(ur, uz, A, delta, psi, c1e, R, A0,
                                         Kn, n, literal=literal)
            for (p, s), v in kb.items():
                K[idx[p]][idx[s]] += v
    # (15p)-(15y): symmetric rest
    for i in range(5):
        for j in range(i):
            K[i][j] = K[j][i]
    return f, np.array(K, dtype=np.float64)


# --------------------------------------------------------------------------
# Table 1 example bearing
# --------------------------------------------------------------------------
def paper_row_dicts(arrangement, **overrides):
    """Row dicts of the paper's Table 1 bearing.

    arrangement: "DB" (+1,-1), "DF" (-1,+1), "DT" (+1,+1) -> two rows at
    axial_offset -10 (row 1, c1=-1) and +10 (row 2, c1=+1); "single" -> one
    row at axial_offset 0, direction +1.  **overrides replace keys in every row.
    """
    base = dict(
        n_balls=14,
        first_ball_angle=0.0,
        contact_angle=math.radians(30.0),
        groove_center_distance=0.52,
        pitch_radius=34.75,
        hertz_constant=395000.0,
        exponent=1.5,
        radial_clearance=0.0,
        axial_preload=0.0,
    )
    e = 10.0
    dirs = {"DB": (1, -1), "DF": (-1, 1), "DT": (1, 1)}
    key = arrangement if arrangement == "single" else arrangement.upper()
    if key == "single":
        specs = [(0.0, 1)]
    elif key in dirs:
        specs = [(-e, dirs[key][0]), (e, dirs[key][1])]
    else:
        raise ValueError(f"unknown arrangement {arrangement!r}")
    rows = []
    for z, c3 in specs:
        r = dict(base, axial_offset=z, contact_direction=c3)
        r.update(overrides)
        rows.append(r)
    return rows


def _check_against_fd(q, rows, h=None, literal=False):
    """Max relative error of Kb vs a central finite difference of Eq. (12) f.

    Relative to max|Kb| scaled per block (unit consistency: each entry is
    compared to sqrt(|K_ii K_jj|)).  Returns (err, K, K_fd)."""
    _, K = _load_stiffness(q, rows, literal)
    Kfd = np.zeros((5, 5))
    steps = h if h is not None else (1e-7, 1e-7, 1e-7, 1e-9, 1e-9)
    for j in range(5):
        qp = list(map(float, q)); qm = list(map(float, q))
        qp[j] += steps[j]; qm[j] -= steps[j]
        Kfd[:, j] = (naive_load(qp, rows) - naive_load(qm, rows)) / (2 * steps[j])
    d = np.sqrt(np.abs(np.outer(np.diag(Kfd), np.diag(Kfd)))) + 1e-300
    return float(np.max(np.abs(K - Kfd) / d)), K, Kfd


# --------------------------------------------------------------------------
# Eq. (12) in extended precision: the independent residual check
# --------------------------------------------------------------------------
#: pi to 80-bit precision (numpy's longdouble: 64-bit mantissa on x86-64 Linux, eps 1.1e-19).
_PI_LD = np.longdouble("3.14159265358979323846264338327950288")


def bearing_row_dicts(bearing):
    """The ball rows of a fastbearing.Bearing as this module's row dicts, angles in radians as np.longdouble
    (converted from the bearing's degrees in extended precision, not through float64)."""
    deg = _PI_LD / 180
    return [dict(n_balls=r.n_balls, first_ball_angle=np.longdouble(r.first_ball_angle) * deg,
                 axial_offset=r.axial_offset, contact_direction=r.contact_direction,
                 contact_angle=np.longdouble(r.contact_angle) * deg, groove_center_distance=r.groove_center_distance,
                 pitch_radius=r.pitch_radius, hertz_constant=r.hertz_constant, exponent=r.exponent,
                 radial_clearance=r.radial_clearance, axial_preload=r.axial_preload) for _, r in bearing.ball_rows]


def load_extended(q, rows):
    """f (5,) from Eq. (12) in np.longdouble (about 3 more decimal digits than float64; N, N*mm).

    Written from Eqs. (4a,b), (7a,b), (9), (3), (10) and (12) with the alpha
    of Eq. (11) eliminated (cos alpha = ur/A, sin alpha = uz/A), vectorised
    over the balls of each row; ball azimuths psi0 + 2 pi j / Z and the
    contact angle are formed in extended precision. Used to check, more
    precisely than the solver itself computes it, that a q reported as
    converged really carries the target load.
    """
    q = np.asarray(q, dtype=np.float64).astype(np.longdouble)
    dx, dy, dz, bx, by = q
    f = np.zeros(5, dtype=np.longdouble)
    for row in rows:
        Z = int(row["n_balls"])
        psi = np.longdouble(row["first_ball_angle"]) + 2 * _PI_LD * np.arange(Z, dtype=np.longdouble) / Z
        c, s = np.cos(psi), np.sin(psi)
        z, R = np.longdouble(row["axial_offset"]), np.longdouble(row["pitch_radius"])
        a0, A0 = np.longdouble(row["contact_angle"]), np.longdouble(row["groove_center_distance"])
        dr = (dx + z * by) * c + (dy - z * bx) * s - np.longdouble(row["radial_clearance"])     # Eq. (4a)
        dzb = dz + R * (bx * s - by * c)                                                      # Eq. (4b)
        ur = dr + A0 * np.cos(a0)                                                             # Eq. (7a)
        uz = dzb + row["contact_direction"] * (A0 * np.sin(a0) + np.longdouble(row["axial_preload"]))  # (7b)
        A = np.sqrt(ur * ur + uz * uz)                                                        # Eq. (9)
        delta = np.maximum(A - A0, 0)                                                         # Eq. (3)
        Q = np.longdouble(row["hertz_constant"]) * delta ** np.longdouble(row["exponent"])    # Eq. (10)
        fr, fz = Q * ur / A, Q * uz / A
        m = R * fz - z * fr
        f += [np.sum(fr * c), np.sum(fr * s), np.sum(fz), np.sum(m * s), -np.sum(m * c)]     # Eq. (12)
    return f


# --------------------------------------------------------------------------
# Roller slices in extended precision (docs/model.md, "Roller slices (cylindrical and tapered roller rows)")
# --------------------------------------------------------------------------
def crown_drop_extended(row, x):
    """c(x) in mm of a fastbearing.RollerRow at slice positions x (np.longdouble, mm from the roller's
    middle), formed in extended precision from crown_radius / crown_design_load: circular
    Rc - sqrt(Rc^2 - x^2), written x^2 / (Rc + sqrt(Rc^2 - x^2)) (the same number without the
    cancellation); logarithmic (2 Q / (pi l E')) ln(1 / (1 - (2x/l)^2)) = -(...) log1p(-(2x/l)^2)."""
    if row.crown == "circular":
        Rc = np.longdouble(row.crown_radius)
        return x * x / (Rc + np.sqrt(Rc * Rc - x * x))
    if row.crown == "logarithmic":
        l = np.longdouble(row.roller_effective_length)
        scale = 2 * np.longdouble(row.crown_design_load) / (_PI_LD * l * np.longdouble(row.reduced_modulus))
        return -scale * np.log1p(-(2 * x / l) ** 2)
    return np.zeros_like(x)


def roller_load_extended(q, bearing):
    """f (5,) of a fastbearing.Bearing's roller rows in np.longdouble (N, N*mm), slice by slice.

    Written from docs/model.md, "Roller slices (cylindrical and tapered roller rows)": slice k of a roller at
    azimuth psi sits at x_k = -l/2 + (k + 1/2) w (w = l/S), radius R_k = R - s x_k sin a and axial place z_k = z_r + x_k cos a;
    its approach along n = (cos a, s sin a) is n . (dr_k, dz_k) + d0 sin a - rL cos a - c(x_k) (an axial
    preload d0 presses the row whatever its contact direction s, as a ball row's s d0 on the axial
    approach does), its load q_k = (w/l) K max(delta_k, 0)^(10/9), and it adds q_k g_k to f with
    g_k = cos a J_r + s sin a J_z. Azimuths, the contact angle, the slice positions and the crown
    are formed in extended precision from the row's public fields (not from the kernel's table).
    """
    q = np.asarray(q, dtype=np.float64).astype(np.longdouble)
    dx, dy, dz, bx, by = q
    deg = _PI_LD / 180
    f = np.zeros(5, dtype=np.longdouble)
    for _, r in bearing.roller_rows:
        Z, S, s = r.n_rollers, r.slices, r.contact_direction
        l = np.longdouble(r.roller_effective_length)
        x = -l / 2 + (np.arange(S, dtype=np.longdouble) + np.longdouble(0.5)) * (l / S)          # (S,)
        psi = (np.longdouble(r.first_element_angle) * deg
               + 2 * _PI_LD * np.arange(Z, dtype=np.longdouble) / Z)[:, None]                  # (Z, 1)
        c, sn = np.cos(psi), np.sin(psi)
        a = np.longdouble(r.contact_angle) * deg
        nr, nz = np.cos(a), s * np.sin(a)
        Rk = np.longdouble(r.pitch_radius) - s * x * np.sin(a)
        zk = np.longdouble(r.axial_offset) + x * np.cos(a)
        dr = (dx + zk * by) * c + (dy - zk * bx) * sn                                        # ring at the slice
        dzk = dz + Rk * (bx * sn - by * c)
        delta = (nr * dr + nz * dzk + np.longdouble(r.axial_preload) * np.sin(a)
                 - np.longdouble(r.radial_clearance) * np.cos(a) - crown_drop_extended(r, x))
        load = (np.longdouble(r.hertz_constant) / S) * np.maximum(delta, 0) ** (np.longdouble(10) / 9)
        m = nz * Rk - nr * zk                                                                 # lever of g_k
        f += [np.sum(load * nr * c), np.sum(load * nr * sn), np.sum(load) * nz, np.sum(load * m * sn),
              -np.sum(load * m * c)]
    return f


def bearing_load_extended(q, bearing):
    """f (5,) of every row of a fastbearing.Bearing in np.longdouble: its ball rows by Eq. (12)
    (:func:`load_extended`) and its roller rows slice by slice (:func:`roller_load_extended`)."""
    return load_extended(q, bearing_row_dicts(bearing)) + roller_load_extended(q, bearing)
