"""The layout of every table the kernels read or write, in one place: named rows, never literal numbers.

A kernel table is a float64 array whose rows are quantities and whose columns are elements (balls,
roller slices) or fields of a record. The Python side fills them (bearing.py, rollers.py,
geometry.speed_columns, life.life_table), the njit side reads them by these names; a module-level int
is a compile-time constant to numba, so a name costs nothing. This module imports nothing: every layer
may depend on it.

Units: the rows' own (mm, N, rad, N/mm^n, kg*m, N*mm*s^2), said beside each group.
"""

from collections import namedtuple

#: What the kernels read of a bearing (bearing.Bearing.ball_set), by name: ``balls`` the ball table
#: (N_BALL_COLUMNS, n_balls); ``exponents`` None (every ball Hertzian, n = 1.5) or the per-ball n;
#: ``smoothing`` the solver's smoothing eps (mm; 0.0: the exact contact law); ``slices`` None (no roller
#: rows) or the slice table (N_SLICE_COLUMNS, n_slices); ``speed_table`` None (the quasi-static model) or the
#: balls' high-speed constants (N_SPEED_COLUMNS, n_balls) with ``omega`` the shaft speed (rad/s) and
#: ``warm`` the balls' warm-start scratch (high_speed.new_warm); ``four_point`` None (no four-point balls, or the
#: quasi-static model) or the columns of each four-point ball's two contact pairs at speed, (2, n_four_point)
#: float64 (model/four_point.py). A None part compiles no code for it. Kernels that change a part go through
#: kernel.with_omega, kernel.with_smoothing and kernel.at_position, never listing the fields.
ElementSet = namedtuple("ElementSet", "balls exponents smoothing slices speed_table omega warm four_point")

# -- ball table (bearing.Bearing.ball_table): column j is ball j ---------------------------------------------
#: cos/sin of the azimuth psi; the row's axial offset z_r and the radius R of the inner groove-curvature
#: centres (mm); the unloaded net radial and axial groove-centre separations (mm; UZ0 carries the row's
#: contact direction); A0 (mm); Kn (N/mm^n); the exponent n; the row index; the contact direction s (+-1);
#: A^2 - A0^2 at q = 0 (mm^2, exactly 0 without clearance and preload); the deflection of the validity limit
#: (mm); WEIGHT how many balls a column stands for (1, or 2 in the mirror half) and SHARE its inverse.
(COS_PSI, SIN_PSI, AXIAL_OFFSET, PITCH_RADIUS, UR0, UZ0, A0, KN, EXPONENT, ROW, DIRECTION, GAP2,
 DEFLECTION_LIMIT, WEIGHT, SHARE) = range(15)
N_BALL_FIELDS = 15
#: The mirror half of the ball set (rows MIRROR_HALF + field, columns 0 .. count - 1): where every row's balls
#: pair up across the xz-plane (psi -> -psi), one column per pair (its lower ball index, WEIGHT 2, Kn doubled)
#: and per ball on the plane (WEIGHT 1); BALL_OF and MIRROR_OF give each column's ball and its image (the
#: ball itself on the plane), HALF_COUNT (in every column) the number of columns, 0 where the set has no
#: such symmetry. Under a planar displacement (dy = bx = 0) a pair's balls carry the same load, so the
#: kernel sums this half.
MIRROR_HALF = N_BALL_FIELDS
BALL_OF, MIRROR_OF, HALF_COUNT = 2 * N_BALL_FIELDS, 2 * N_BALL_FIELDS + 1, 2 * N_BALL_FIELDS + 2
N_BALL_COLUMNS = 2 * N_BALL_FIELDS + 3

# -- slice table (rollers.slice_table): column k is slice k ---------------------------------------------------
#: A roller's slices are contiguous and share its azimuth, centre (S_AXIAL, S_RADIUS; mm), normal
#: (S_NORMAL_R, S_NORMAL_Z), unloaded approach offset at the slice (S_OFFSET, mm), stiffness per slice
#: (S_STIFFNESS, N/mm^(10/9)), row, roller number in the element record, contact angle (rad), deflection
#: scale (mm) and slice count; S_POSITION is x_k along the roller (mm); S_CROWN the crown drop c(x_k) (mm), so
#: that S_OFFSET = the row's unloaded approach - S_CROWN can be set again for a case's own clearance and preload.
(S_COS_PSI, S_SIN_PSI, S_AXIAL, S_RADIUS, S_NORMAL_R, S_NORMAL_Z, S_OFFSET, S_STIFFNESS, S_ROW, S_ROLLER,
 S_ANGLE, S_SCALE, S_POSITION, S_COUNT, S_CROWN) = range(15)
N_SLICE_COLUMNS = 15

# -- a case's own operating clearance and preload (contract.CaseBlock.operating): (rows, N_OPERATING) per case ----
#: What a row's clearance rL and preload d0 set in the tables (bearing.Bearing.operating_table): a ball row's
#: UR0, UZ0 and GAP2 (mm, mm, mm^2; every ball of the row alike), a roller row's unloaded approach
#: d0 sin(a) - rL cos(a) (mm, in OP_UR0; the other two 0).
OP_UR0, OP_UZ0, OP_GAP2 = range(3)
OP_APPROACH = OP_UR0
N_OPERATING = 3

# -- speed table (bearing.Bearing.speed_table, geometry.speed_columns): column j is ball j ----------------------
#: (f_i - 1/2) D, (f_o - 1/2) D (mm); each race's Hertz constant at a0 (N/mm^1.5); m d_m/2 (kg*m: F_c in N
#: for omega in rad/s); J = m D^2/10 (N*mm*s^2: M_g in N*mm); gamma' = D/d_m; the race-control factors
#: lambda_i, lambda_o; inner control (0/1); the outer ring turning (0/1); f_i D, the inner friction's
#: lever about the inner groove centre (mm); D (mm); the outer contact's share of the quasi-static
#: deflection; cos a0; PARTNER the column of the same ball's other contact pair (a four-point ball:
#: model/four_point.py, engine/four_point.py), -1 for a ball of an ordinary row.
(INNER_RADIUS, OUTER_RADIUS, K_INNER, K_OUTER, MASS_RADIUS, INERTIA, GAMMA, LAMBDA_INNER, LAMBDA_OUTER,
 INNER_CONTROL, OUTER_ROTATES, INNER_ARM, DIAMETER, OUTER_SHARE, COS_NOMINAL, PARTNER) = range(16)
N_SPEED_COLUMNS = 16

# -- a high-speed ball's state record (solve --balls at speed): row j of an (n_balls, N_STATE) array -------------
STATE_INNER_LOAD, STATE_OUTER_LOAD, STATE_INNER_ANGLE, STATE_OUTER_ANGLE, STATE_CENTRIFUGAL, STATE_GYROSCOPIC, \
    STATE_ORBITAL_SPEED, STATE_ITERATIONS, STATE_RESIDUAL = range(9)  # iterations -1: a free ball
N_STATE = 9

# -- the balls' warm-start scratch at speed (high_speed.new_warm): one flat vector, row r of ball j at r * n + j ---
#: Each ball's settled centre B (mm), the inner groove centre u it was settled for (mm) and X = G_B^-1 G_u
#: there, so that the next evaluation starts from the first-order prediction B - X (u' - u); WARM_VALID 0:
#: no start stored (a free or unsettled ball). WARM_LINEARISE (its first cell only, WARM_LINEARISE * n): set by
#: the solver for the length of a solve, which takes linearised balls.
(WARM_BR, WARM_BZ, WARM_UR, WARM_UZ, WARM_X00, WARM_X01, WARM_X10, WARM_X11, WARM_VALID, WARM_LINEARISE) = range(10)
N_WARM = 10

# -- a high-speed ball's state tuple (high_speed.ball_state) ---------------------------------------------------------
#: The residual g (N), its Jacobian G_B (N/mm) and G_u = dg/du, the ring force F (N) with dF/du and dF/dB, the
#: friction's moment m (N*mm) with its derivatives, the loads Q_i, Q_o (N), the unit normals (cos, sin) of
#: the inner and outer contacts, F_c (N), M_g (N*mm), omega_m (rad/s) and the deflections (mm).
(BS_GR, BS_GZ, BS_GB_RR, BS_GB_RZ, BS_GB_ZR, BS_GB_ZZ, BS_GU_RR, BS_GU_RZ, BS_GU_ZR, BS_GU_ZZ, BS_FR, BS_FZ,
 BS_FU_RR, BS_FU_RZ, BS_FU_ZR, BS_FU_ZZ, BS_FB_RR, BS_FB_RZ, BS_FB_ZR, BS_FB_ZZ, BS_M, BS_MU_R, BS_MU_Z, BS_MB_R,
 BS_MB_Z, BS_QI, BS_QO, BS_CI, BS_SI, BS_CO, BS_SO, BS_FC, BS_MG, BS_WM, BS_DI, BS_DO) = range(36)

# -- the predicted balls' summaries (high_speed._summary), a chunk at a time, in the warm scratch's tail -----------
#: Field k of ball i of a chunk at k * CHUNK + i (one store stream per field). SM_GR .. SM_M1 are the
#: summary proper; the rest is the vectorised pass's bookkeeping.
CHUNK = 32
(SM_GR, SM_GZ, SM_QI, SM_QO, SM_CI, SM_SI, SM_CO, SM_SO, SM_FC, SM_MG, SM_WM, SM_DI, SM_DO, SM_X00, SM_X01, SM_X10,
 SM_X11, SM_FR, SM_FZ, SM_M, SM_K00, SM_K01, SM_K10, SM_K11, SM_M0, SM_M1, SM_BR, SM_BZ, SM_VERDICT, SM_EXACT,
 SM_DBR, SM_DBZ, SM_LOADED, SM_UR, SM_UZ) = range(35)
N_SUMMARY = 35

# -- the life table of a map with life (life.life_table): row r is bearing row r ---------------------------------
#: The raceway ratings (balls: Q_ci^(-10/3), Q_ce^(-10/3); rollers: the laminae's q_ci^(-9/2), q_ce^(-9/2)),
#: the element count Z, whether the inner ring rotates (0/1), ISO 76's X0, Y0, a roller row's slice count
#: (0 for balls) and its first slice in the record.
LIFE_CI, LIFE_CE, LIFE_Z, LIFE_INNER, LIFE_X0, LIFE_Y0, LIFE_SLICES, LIFE_FIRST = range(8)
N_LIFE_COLUMNS = 8
