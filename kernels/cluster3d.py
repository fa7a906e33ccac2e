"""Persistent contact between several spheres in 3D (a *cluster*): spheres held together,
and against fixed planes, by a set of active unilateral contacts with Coulomb friction,
integrated in maximal coordinates with error control, projection onto the constraints and
event location (the 3D counterpart of ``cluster2d``, for spheres; the standalone kernel a
later session wires into ``stepper3d`` as ``stepper2d`` wires ``cluster2d``).

Model (Newton-Euler with unilateral contacts and Coulomb friction in maximal
coordinates; Pfeiffer & Glocker, *Multibody Dynamics with Unilateral Contacts*, 1996,
ch. 5-6; Haug, *Computer-Aided Kinematics and Dynamics of Mechanical Systems*, 1989,
ch. 11 for the acceleration form of the constraints). Conventions: DESIGN §3 (the normal
n from B into A, the tangent basis ``(t1, t2) = toi3d.tangent_basis(n)``, forces on A).

Bodies ``i`` (rows of ``bodies``, columns ``CB_*``): spheres of radius ``r``, mass ``m``
and spherical inertia (scalar moment ``I`` about the centre). State
``(x (3), q (4: w x y z, unit), v (3), omega (3, world))``; the contact geometry depends
only on the centres, so the orientation ``q`` is carried for output only
(``q' = 0.5 (0, omega) (x) q``, renormalised at every projection). A *fixed* sphere
(``CB_FIXED != 0``) has infinite mass: it keeps its velocity and takes any force.
Gravity ``g`` acts on the others. The material point of sphere X at the world point p
moves with ``v_X(p) = v_X + omega_X x (p - x_X)``.

Contacts ``k`` (rows of ``contacts``, columns ``CC_*``) between sphere A and sphere B, or
between sphere A and a fixed plane ``n . x >= d`` (``CC_B = -1``). Kinds (``CC_KIND``):

* ``KIND_SPHERE``: ``D = x_A - x_B``, ``g = |D| - rA - rB``, ``n = D / |D|``,
  ``dg/dt = n . dD/dt``, ``dn/dt = (dD/dt)_perp / |D|`` (``_perp``: the part normal to
  n), so ``g'' = n . (a_A - a_B) + |(dD/dt)_perp|^2 / |D|`` (the centripetal term: the
  relative velocity of the centres across the normal, squared, over their distance).
* ``KIND_PLANE``: ``n = CC_NX..CC_NX+2`` (world, unit), ``g = n . x_A - d - rA``, ``g'' = n . a_A``.

The contact point is ``p = x_A - rA n``; the arms ``ρA = p - x_A = -rA n`` and
``ρB = p - x_B = (rB + g) n`` are parallel to n, so the normal force exerts no moment and
``dg/dt = n . (v_A(p) - v_B(p)) = JN . u`` with the row ``JN = (n, 0 | -n, 0)`` on the
body velocities ``u = (v, omega)`` (the gradient of g: the position projection below is
Newton's method). ``g'' = JN u' + bN`` with ``bN = |(dD/dt)_perp|^2 / |D|`` (0 for a plane).

Tangential: the relative velocity of the material contact points
``w = v_A(p) - v_B(p)``, its slip ``c = w - (n . w) n`` (components ``vT1, vT2``). Its rate
``dw/dt = a_A + alpha_A x ρA - a_B - alpha_B x ρB + b`` with
``b = omega_A x (dp/dt - v_A) - omega_B x (dp/dt - v_B)``, ``dp/dt = v_A - rA dn/dt``: the
row of direction e is ``(e, ρA x e | -e, -ρB x e)``. A STICK contact keeps
``t_i . dw/dt = 0`` (i = 1, 2; on the constraint ``w = 0`` this is ``d(t_i . w)/dt = 0``, the
``dt_i/dt . w`` term vanishing; ``w = 0`` is a velocity constraint: not projected at
position level). Point contact: the spin about the normal is free (no drilling or
rolling resistance).

Forces: ``lam_N n + T`` on A at p, the opposite on B (``T . n = 0``). Modes
(``CC_MODE``): ``MODE_STICK`` (unknowns ``lam_N, T1, T2``; equations ``g'' = 0,
t_i . dw/dt = 0``; ``mu = 0``: ``T = 0``, no tangential unknowns, frictionless contact),
``MODE_SLIP`` (``T = -mu lam_N s``, ``s`` the friction direction (``_fill``): ``c/|c|``,
or for a slip that started from sticking, the blend of ``c`` with its start direction
``CC_SX..`` that ``pivot3d._slipdir`` uses, continuous and equal to ``CC_SX..`` at ``c = 0``;
the force column is ``n - mu s``), ``MODE_LIFT`` (inactive). The unknowns (at most
``NMAX = 3 KMAX``) solve ``A lam = r``, ``A_ij = row_i M^-1 col_j``,
``r_i = -(row_i u'_free + b_i)``, by ``minnorm.minnorm_solve`` (one-sided Jacobi SVD):
redundant contacts (a sphere on three spheres, a pyramid) get the minimum-norm split of
the forces, unless that split leaves a cone (below): then the split inside the cones.
Residual not at round-off: ``CS_SINGULAR``. A sliding contact whose own
effective normal mass ``n M^-1 (n - mu s)`` is not positive: ``CS_PAINLEVE``
(the criterion of ``pivot3d``; for spheres the arms are parallel to n, so this is
``sum 1/m > 0``: never, the check guards the force system's form). Never NaN.

Integration: Dormand-Prince RK5(4) with dense output (``dopri5``) on the ``13 nb``
coordinates, component scales ``(L (3), 1 (4), V (3), V / L (3))`` per body, ``L`` the
cluster's length scale (the caller's), ``V = max_i (|v_i| + |omega_i| L) + sqrt(|g| L)`` at
the start of the call, tolerance ``CLUSTER_TOL``. After every accepted step the state is
projected (``_project``, metric ``M = diag(m, m, m, I, I, I)``): the centres by
Gauss-Newton on the active gaps until ``|g| <= PROJ_LTOL L``, the quaternions
renormalised, then the velocities (twice) onto ``dg/dt = 0`` (every active contact) and
``c = 0`` (sticking contacts): an M-orthogonal projection, it only removes kinetic energy.

Events (functions that must stay positive; located on the dense output by
secant/bisection to ``EVENT_RTOL |t| + EVENT_ATOL L / V``, ``cluster2d._locate``'s rule):
per active contact k at ``N_EVK k``: ``lam_N`` (``CE_LEAVE``); a sticking contact's cone
margin ``mu lam_N - |T|`` (``CE_SLIP``; both of the split ``_forces`` returns at each
evaluation: for a redundant sticking set, the split inside the cones of "Redundant
splits" below, so the event fires when no split holds every force in its cone, to
within ``FORCE_ARM F``, and names the contact whose margin the search left lowest); a sliding contact's ``|c| - SLIP_EPS V``
(``CE_STOP``; while a slip started from sticking is still below ``SLIP_EPS V``: its growth
``s . dc/dt``, as ``pivot3d``); and the gap of each candidate (``cands``: ``CE_GAP``).
A function starting below its arm (``FORCE_ARM F``, ``SLIP_ARM V``, ``GAP_ARM L``) fires
below ``min(0, start) - arm`` (``pivot2d``'s rule). Force and slip events are returned
on the far side of the root, gaps on the near side. Steps turn no body by more than
``MAX_ANGLE`` and last at most ``MAX_ANGLE L / V``.

Mode selection (``cluster_select_modes``, every contact at ``g = dg/dt = 0``): each
contact's options, in order: frictionless: active, lift; sliding (``|c| > STICK_VTOL V``):
slip, lift; otherwise stick, slip (along the direction opposite to its sticking force in
the trial with every non-sliding contact sticking; stored in ``CC_SX..``), lift. The
combinations run lexicographically (after an event: first by the number of changed
modes); the first consistent one is returned: every ``lam_N >= -FORCE_TOL F``, every
sticking force in its cone (``|T| <= mu lam_N + FORCE_TOL F``), every slip started from
``c = 0`` accelerating along its direction (``s . dc/dt > ACC_TOL |g|`` and
``|s x dc/dt| <= SLIPDIR_ATOL |dc/dt|``), every lifted
contact not approaching (``g'' >= -ACC_TOL |g|``), ``F = sum m |g|``. None:
``CS_NO_MODE``. A slip from ``c = 0`` starts along the direction opposite to its
sticking force in the all-stick trial; the combination's forces are then solved again
with each such direction turned, in its tangent plane, to where its slip acceleration is
along it (``s || dc/dt``, ``s . dc/dt > 0``: the Coulomb law at the start of a slip;
``_slip_fixed_point``: a scan and bisection of the angle per contact, Gauss-Seidel sweeps
over several such contacts, not guaranteed to converge for several coupled ones: after
``SLIPDIR_ITER`` sweeps the last directions are judged by the consistency test).

Redundant splits (``_best_split``, in ``_forces``, so selection, events and rest all see
it): when the force system is rank deficient (singular values below ``SVD_RTOL sigma_max``,
``minnorm``'s rule) its solutions are ``x0 + N z`` (x0 the min-norm one, N the null
right singular vectors), all giving the same motion. When the smallest margin of x0
(every ``lam_N``, and ``mu lam_N - |T|`` of every sticking contact; N) is below
``SPLIT_TARGET F``, z is searched for every margin ``>= SPLIT_TARGET F`` (a second-order
cone feasibility problem, 1-3 unknowns typically) by Polyak's subgradient projections
(Polyak 1969): each step projects onto the linearisation of the worst margin aimed at
``+SPLIT_TARGET F``, at most ``SPLIT_ITER`` steps; the best split found (largest worst
margin) is the one stored and judged (``FORCE_TOL F``). Null vectors with components on
slip normal unknowns above ``SPLIT_SLIP_TOL`` are not used (A is not symmetric there: A v
= 0 need not leave the motion unchanged). The split found is a feasible one near the
cones' boundary (margin ``SPLIT_TARGET F``), not the one maximising the smallest margin,
nor the physical one (rigid bodies leave it undetermined). The asymmetric groove at
mu = 0.5 and 0.2 sticks on such a split (the min-norm split leaves a cone); at mu = 0.1
no squeeze along the chord holds the second contact's force in its cone: it slips.

Rest (``cluster_advance``): every free sphere ``|v| + |omega| L <= REST_VTOL sqrt(|g| L)``,
every active contact sticking (or frictionless) with ``lam_N > FORCE_TOL F`` and strictly
inside its cone, every ``|a| + |alpha| L <= REST_ATOL |g|``: ``CS_REST``, nothing
integrated. Checked at the start of a call (the stepper's enter and after each event),
not as an event: with every contact sticking or frictionless the forces do no work
(energy conserved), and a state with zero velocity and zero acceleration is an
equilibrium, which the motion (unique, the forces being smooth while the modes hold)
reaches only asymptotically, never in finite time; a zero of the velocity alone is a
turning point, not rest. Dissipation needs a slip, and a slip ends at ``CE_STOP``, an
event: the call after it (``cluster_after_event``: stick) checks rest. At a stop where
every velocity vanishes with the slip (a sphere with backspin ``omega0 = v0 / (0.4 r)``:
zero angular momentum about the contact point, kept by friction and by the stick
projection, an impulse at the contact point) the remaining velocity is at round-off and
the next call returns ``CS_REST``. Not detected: a stop whose residual velocity (of order
``SLIP_EPS V``) the stick projection does not remove, above ``REST_VTOL``; and a rest
approached asymptotically (e.g. damped only by impacts, which are the stepper's).

Energy: normal forces do no work (``dg/dt = 0``), sticking ones none (``c = 0``), sliding
ones ``-mu lam_N |c| <= 0``.

Arrays (no allocation in the hot path): ``bodies`` float64[nb, N_CB] (state columns
updated in place); ``contacts`` float64[>= nk, N_CC] (forces ``CC_LAMN, CC_TX..`` written),
``cands`` float64[>= nc, N_CC]; ``w`` float64[work_size(nb, nc)]; ``la`` float64[N_LA].

Recording (``cluster_advance``'s ``seg_*``): velocity-interpolating pieces as
``cluster2d``'s, one row ``(x, q, v, omega, a, alpha)`` (``N_ROW``) per free sphere,
evaluated by ``piece_state``.

Tolerances are module constants, each relative to the cluster's scales: ``L`` (m),
``V`` (m/s), ``F = sum m |g|`` (N), ``|g|`` (m/s^2) and ``T = sqrt(L / |g|)`` (s). No decision
is taken on the sign of a round-off quantity: consistency tests carry ``FORCE_TOL`` /
``ACC_TOL`` margins, events that start at their root are armed.

Wiring (``stepper3d``, as ``stepper2d`` uses ``cluster2d``): on entering the mode (spheres
resting on or rolling against each other / the floor), build ``bodies`` and the active
``contacts`` (every touching pair at ``g = dg/dt = 0``), call ``cluster_project`` then
``cluster_select_modes`` (``MODE_LIFT`` ones go to ``cands``); at each pass
``cluster_advance`` to the next scheduled time (``CS_REST``: freeze the cluster); at
``CE_LEAVE / CE_SLIP / CE_STOP`` call ``cluster_after_event`` and move lifted contacts to the
candidates; at ``CE_GAP`` leave the mode for the impact law (then re-enter).

Not here: a rest *event* during a phase (why not: "Rest" above), shapes other than
spheres, and a mode selection beyond ``KSEL_MAX`` contacts. Limitations of the
redundant split: the search is a first-order method, so a feasible set thinner than
about ``SPLIT_TARGET F`` or needing more than ``SPLIT_ITER`` steps may be missed (the
selection then goes on to slip modes); the split is chosen afresh at each force
evaluation (continuous in time only where the search's path is), and slip contacts'
null components are not searched.
"""
import math

from numba import njit

from .cache_guard import guard

# flush stale compiled callers before any kernel module below is imported (cache_guard)
guard(__name__, __file__)

from .dopri5 import MAX_TRIES, dense_out, dopri5_step
from .minnorm import minnorm_solve
from .toi3d import tangent_basis

# ---- bodies table (float64[nb, N_CB]) ------------------------------------------------------
CB_X = 0            # centre x, y, z (m)
CB_QW = 3           # orientation quaternion w, x, y, z (unit; output only)
CB_VX = 7           # velocity of the centre (m/s)
CB_WX = 10          # angular velocity, world frame (rad/s)
CB_M = 13           # mass (kg; ignored for a fixed sphere)
CB_I = 14           # moment of inertia about the centre (kg m^2; spherical inertia)
CB_R = 15           # radius (m)
CB_FIXED = 16       # != 0: infinite mass (keeps its velocity, takes any force)
N_CB = 17
NS = 13             # state components per sphere (x 3, q 4, v 3, omega 3)
S_Q = 3             # offsets in a state row
S_V = 7
S_W = 10

# ---- contacts table (float64[n, N_CC]) ------------------------------------------------------
CC_KIND = 0         # KIND_SPHERE or KIND_PLANE
CC_A = 1            # sphere A
CC_B = 2            # sphere B; -1: a fixed plane
CC_NX = 3           # KIND_PLANE: the plane's unit normal, world (3)
CC_D = 6            # KIND_PLANE: offset d (m): n . x >= d
CC_MU = 7           # friction coefficient (0: frictionless; inf: never slips)
CC_MODE = 8         # MODE_* (active contacts)
CC_SX = 9           # MODE_SLIP: the slip's start direction (unit, world; 0: none)
CC_LAMN = 12        # output: normal force on A (N)
CC_TX = 13          # output: tangential force on A, world (N, 3)
N_CC = 16

KIND_SPHERE = 0
KIND_PLANE = 1

MODE_STICK = 0      # rolling/sticking: c = 0 (mu = 0: frictionless, T = 0)
MODE_SLIP = 1       # sliding: T = -mu lam_N s
MODE_LIFT = 2       # not active (mode selection's lift-off)

# ---- sizes -----------------------------------------------------------------------------------
KMAX = 12           # active contacts at most
NMAX = 3 * KMAX     # force unknowns at most
KSEL_MAX = 6        # contacts the mode enumeration handles (3^6 combinations)

# ---- status codes --------------------------------------------------------------------------
CS_OK = 0
CS_REST = 1             # at rest: nothing integrated
CS_SINGULAR = 2         # the force system has no solution (contradictory constraints)
CS_PAINLEVE = 3         # a sliding contact's effective normal mass <= 0
CS_TOO_MANY_STEPS = 4   # MAX_ATTEMPTS step attempts, or a step that cannot be taken
CS_NO_MODE = 5          # mode selection: no consistent stick/slip/lift-off combination
CS_TOO_MANY_CONTACTS = 6  # more than KMAX active (KSEL_MAX for the selection)
CS_INCONSISTENT = 7     # cluster_advance called with modes whose forces are not consistent

# ---- event codes ---------------------------------------------------------------------------
CE_NONE = 0         # t_max reached (or a failure: see the status)
CE_LEAVE = 1        # lam_N of active contact `index` reaches 0
CE_SLIP = 2         # the sticking force of contact `index` reaches its cone
CE_STOP = 3         # the slip of sliding contact `index` falls to SLIP_EPS V
CE_GAP = 4          # the gap of candidate `index` reaches 0
N_EVK = 2           # event functions per active contact: lam_N, cone margin / slip

# ---- tolerances (each relative to the scale named) ------------------------------------------
CLUSTER_TOL = 1e-12     # RK error per step, relative to the scales (L, 1, V, V/L)
MAX_ANGLE = 0.05        # rad turned by any sphere per step, and steps <= MAX_ANGLE L / V
PROJ_LTOL = 1e-15       # position projection stops at |g_k| <= PROJ_LTOL L (round-off)
PROJ_ITER = 4           # Gauss-Newton iterations of the position projection at most
SVD_RTOL = 1e-10        # singular values below SVD_RTOL sigma_max are redundancy (zero)
SVD_SWEEPS = 40         # Jacobi sweeps at most
SOLVE_RTOL = 1e-8       # residual above SOLVE_RTOL (|A| |x| + |r|) + floor: CS_SINGULAR
PAINLEVE_RTOL = 1e-12   # n M^-1 (n - mu s) <= PAINLEVE_RTOL n M^-1 n: Painleve
FORCE_TOL = 1e-10       # force consistency of a mode / rest, relative to F = sum m |g|
ACC_TOL = 1e-10         # acceleration consistency of a mode, relative to |g|
STICK_VTOL = 1e-9       # a slip |c| <= STICK_VTOL V is zero (mode selection)
SLIP_EPS = 1e-9         # a slip falling to SLIP_EPS V sticks (CE_STOP; pivot3d's slip_eps)
SLIP_BLEND = 10.0       # a slip from sticking blends its start direction up to SLIP_BLEND
#                         SLIP_EPS V (pivot3d._slipdir)
SLIPDIR_TOL = 1e-12     # a slip's start direction agrees with its acceleration's: the sine of
#                         the angle between them, and the bisection's bracket (rad)
SLIPDIR_ATOL = 1e-8     # consistency: a slip from c = 0 needs |s x dc/dt| <= SLIPDIR_ATOL |dc/dt|
#                         (sine of the angle, dimensionless; the located angles are at
#                         SLIPDIR_TOL, the margin keeps the decision off round-off)
SLIPDIR_ITER = 8        # sweeps over the contacts starting to slip at most
SLIPDIR_SCAN = 72       # samples of a slip's start angle around its tangent plane
SLIPDIR_BISECT = 80     # bisections of a start angle at most
SPLIT_ITER = 200        # projection steps of the redundant-split search at most (_best_split)
SPLIT_TARGET = 1e-9     # the split search aims each violated margin at +SPLIT_TARGET F (N:
#                         into the cones by more than FORCE_TOL F, so that it stops finitely)
SPLIT_SLIP_TOL = 1e-8   # a null vector of A whose slip-normal components exceed this (unit
#                         vector) would change the motion (A is not symmetric there): not used
STOP_RTOL = 1e-6        # a slip its mode stops within STOP_RTOL sqrt(L/|g|) counts as stopped
REST_VTOL = 1e-10       # rest: |v| + |omega| L <= REST_VTOL sqrt(|g| L) for every sphere
REST_ATOL = 1e-10       # rest: |a| + |alpha| L <= REST_ATOL |g| for every sphere
FORCE_ARM = 1e-9        # force events starting below FORCE_ARM F are armed (module doc)
SLIP_ARM = 1e-12        # slip events armed below SLIP_ARM V
GAP_ARM = 1e-12         # gap events armed below GAP_ARM L
EVENT_RTOL = 4e-16      # event time located to EVENT_RTOL |t| + EVENT_ATOL L / V
EVENT_ATOL = 1e-15
EVENT_ITER = 200        # secant/bisection iterations locating an event
MAX_ATTEMPTS = 200_000  # RK step attempts per call at most (CS_TOO_MANY_STEPS)
PIECE_ETOL = 1e-11      # energy deviation of a recorded piece, relative to M V^2 (M the
#                         cluster's free mass; cluster2d's value and reason)
PIECE_LTOL = 1e-10      # point deviation of a recorded piece (centre, and L times the
#                         orientation's angle), relative to L
PIECE_VTOL = 1e-9       # velocity deviation (|dv| + L |domega|) of a piece, relative to V
PIECE_BUDGET = 512      # recorded rows per call of cluster_advance at most (buffer margin)
PIECE_ITER = 60         # shrinks of one piece at most (then it is accepted as is)
CNT_SEG = 1             # cnt[CNT_SEG]: rows recorded in seg_* (stepper3d's counter layout)
N_ROW = 19              # a recorded row: x (3), q (4), v (3), omega (3), a (3), alpha (3)
R_A = 13                # offsets of a and alpha in a row
R_AL = 16

# ---- work array layout -----------------------------------------------------------------------
H_TOL = 0           # RK tolerance
H_H = 1             # accepted step (s)
H_HNEXT = 2         # next step (s)
H_S0 = 4            # step start, from t0 (s)
H_L = 5             # length scale L (m)
H_V = 6             # velocity scale V (m/s)
H_F = 7             # force scale F (N)
H_GX = 8            # gravity (m/s^2, 3)
H_G = 11            # |g| (m/s^2)
H_T0 = 12           # t0 (s)
N_H = 16
B_SC = 0            # error scales
B_Y = 1             # step start
B_YT = 2            # stage argument
B_Y1 = 3            # step end
B_K = 4             # 4..10: seven stages
B_RC = 11           # 11..15: dense output
B_YA = 16           # scratch states
B_YB = 17
B_YC = 18           # scratch derivative
N_BLK = 19
N_EVW = 4           # per event: value at the step start, its floor, value at the end, scratch
N_ROWS = 3          # then three piece rows (N_ROW per sphere) for the recording

# ---- per-contact rows of la ----------------------------------------------------------------
LK_N = 0            # n (3)
LK_T1 = 3           # t1 (3)
LK_T2 = 6           # t2 (3)
LK_RA = 9           # arm ρA = p - x_A (3)
LK_RB = 12          # arm ρB = p - x_B (3)
LK_SD = 15          # friction direction s (3; MODE_SLIP)
LK_BN = 18          # bN (m/s^2)
LK_B = 19           # b, the velocity part of dw/dt (3, m/s^2)
LK_G = 22           # gap (m)
LK_GD = 23          # gap rate (m/s)
LK_C = 24           # slip c (3, m/s)
LK_IN = 27          # index of the unknown lam_N (-1: lifted)
LK_IT = 28          # index of the unknown T1 (T2 next; -1: none)
LK_LN = 29          # lam_N (N)
LK_LT = 30          # T (3, world, N)
LK_GDD = 33         # g'' (m/s^2)
LK_AC = 34          # dc/dt tangential (3, m/s^2)
LK_S = 37           # stride
LA_K = 0
LA_A = LA_K + (KMAX + 1) * LK_S    # one extra slot: a candidate's rows
LA_U = LA_A + NMAX * NMAX
LA_V = LA_U + NMAX * NMAX
LA_R = LA_V + NMAX * NMAX
LA_X = LA_R + NMAX
LA_EQ = LA_X + NMAX         # contact of each unknown (float)
LA_ET = LA_EQ + NMAX        # 0: normal (column n or n - mu s), 1: t1, 2: t2
LA_NI = LA_ET + NMAX        # the split search: columns of V spanning the null space
LA_Z = LA_NI + NMAX         # the split search: squared singular values, then a null step
LA_XB = LA_Z + NMAX         # the split search: the best split found
N_LA = LA_XB + NMAX


@njit(cache=True, _nrt=False)
def work_size(nb, nc):
    """Length of ``w`` for ``nb`` spheres and ``nc`` candidates."""
    return N_H + N_BLK * NS * nb + N_EVW * (N_EVK * KMAX + nc) + N_ROWS * N_ROW * nb


# ------------------------------------------------------------------ kinematics


@njit(cache=True, _nrt=False, inline="always")
def _cross(ax, ay, az, bx, by, bz):
    return ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx


@njit(cache=True, _nrt=False)
def _fill(bodies, c, k, w, yo, la, slot):
    """Kinematics of contact row k of table c at the state w[yo:] into la slot ``slot``:
    n, t1, t2, the arms, the friction direction, bN, b, g, dg/dt, c (module docstring)."""
    o = LA_K + slot * LK_S
    a = int(c[k, CC_A])
    b = int(c[k, CC_B])
    pa = yo + NS * a
    ra = bodies[a, CB_R]
    vax = w[pa + S_V]
    vay = w[pa + S_V + 1]
    vaz = w[pa + S_V + 2]
    wax = w[pa + S_W]
    way = w[pa + S_W + 1]
    waz = w[pa + S_W + 2]
    if b < 0:
        nx = c[k, CC_NX]
        ny = c[k, CC_NX + 1]
        nz = c[k, CC_NX + 2]
        g = nx * w[pa] + ny * w[pa + 1] + nz * w[pa + 2] - c[k, CC_D] - ra
        dnx = 0.0
        dny = 0.0
        dnz = 0.0
        bn = 0.0
        vbx = 0.0
        vby = 0.0
        vbz = 0.0
        wbx = 0.0
        wby = 0.0
        wbz = 0.0
        rbl = 0.0
    else:
        pb = yo + NS * b
        dx = w[pa] - w[pb]
        dy = w[pa + 1] - w[pb + 1]
        dz = w[pa + 2] - w[pb + 2]
        dl = math.sqrt(dx * dx + dy * dy + dz * dz)
        nx = dx / dl
        ny = dy / dl
        nz = dz / dl
        g = dl - ra - bodies[b, CB_R]
        vbx = w[pb + S_V]
        vby = w[pb + S_V + 1]
        vbz = w[pb + S_V + 2]
        wbx = w[pb + S_W]
        wby = w[pb + S_W + 1]
        wbz = w[pb + S_W + 2]
        ddx = vax - vbx
        ddy = vay - vby
        ddz = vaz - vbz
        dn = nx * ddx + ny * ddy + nz * ddz
        px = ddx - dn * nx
        py = ddy - dn * ny
        pz = ddz - dn * nz
        dnx = px / dl
        dny = py / dl
        dnz = pz / dl
        bn = (px * px + py * py + pz * pz) / dl
        rbl = dl - ra        # |ρB| = rB + g
    t1x, t1y, t1z, t2x, t2y, t2z = tangent_basis(nx, ny, nz)
    la[o + LK_N] = nx
    la[o + LK_N + 1] = ny
    la[o + LK_N + 2] = nz
    la[o + LK_T1] = t1x
    la[o + LK_T1 + 1] = t1y
    la[o + LK_T1 + 2] = t1z
    la[o + LK_T2] = t2x
    la[o + LK_T2 + 1] = t2y
    la[o + LK_T2 + 2] = t2z
    la[o + LK_RA] = -ra * nx
    la[o + LK_RA + 1] = -ra * ny
    la[o + LK_RA + 2] = -ra * nz
    la[o + LK_RB] = rbl * nx
    la[o + LK_RB + 1] = rbl * ny
    la[o + LK_RB + 2] = rbl * nz
    la[o + LK_G] = g
    la[o + LK_BN] = bn
    # relative velocity of the material points at p
    cax, cay, caz = _cross(wax, way, waz, -ra * nx, -ra * ny, -ra * nz)
    cbx, cby, cbz = _cross(wbx, wby, wbz, rbl * nx, rbl * ny, rbl * nz)
    wx = vax + cax - vbx - cbx
    wy = vay + cay - vby - cby
    wz = vaz + caz - vbz - cbz
    wn = nx * wx + ny * wy + nz * wz
    la[o + LK_GD] = (nx * (vax - vbx) + ny * (vay - vby) + nz * (vaz - vbz))
    cx = wx - wn * nx
    cy = wy - wn * ny
    cz = wz - wn * nz
    la[o + LK_C] = cx
    la[o + LK_C + 1] = cy
    la[o + LK_C + 2] = cz
    # b = omega_A x (dp/dt - v_A) - omega_B x (dp/dt - v_B), dp/dt = v_A - rA dn/dt
    e1x, e1y, e1z = _cross(wax, way, waz, -ra * dnx, -ra * dny, -ra * dnz)
    e2x, e2y, e2z = _cross(wbx, wby, wbz, vax - vbx - ra * dnx, vay - vby - ra * dny,
                           vaz - vbz - ra * dnz)
    la[o + LK_B] = e1x - e2x
    la[o + LK_B + 1] = e1y - e2y
    la[o + LK_B + 2] = e1z - e2z
    # friction direction of a slip (pivot3d._slipdir's blend)
    sx = c[k, CC_SX]
    sy = c[k, CC_SX + 1]
    sz = c[k, CC_SX + 2]
    sn = nx * sx + ny * sy + nz * sz
    sx -= sn * nx
    sy -= sn * ny
    sz -= sn * nz
    sl = math.sqrt(sx * sx + sy * sy + sz * sz)
    cl = math.sqrt(cx * cx + cy * cy + cz * cz)
    eps = SLIP_EPS * w[H_V]
    wgt = eps * max(0.0, 1.0 - cl / (SLIP_BLEND * eps)) / sl if sl > 0.0 else 0.0
    ux = cx + wgt * sx
    uy = cy + wgt * sy
    uz = cz + wgt * sz
    ul = math.sqrt(ux * ux + uy * uy + uz * uz)
    if ul > 0.0:
        la[o + LK_SD] = ux / ul
        la[o + LK_SD + 1] = uy / ul
        la[o + LK_SD + 2] = uz / ul
    else:
        la[o + LK_SD] = 0.0
        la[o + LK_SD + 1] = 0.0
        la[o + LK_SD + 2] = 0.0


@njit(cache=True, _nrt=False, inline="always")
def _minv(bodies, i):
    """(1/m, 1/I) of sphere i; (0, 0) for a fixed sphere."""
    if bodies[i, CB_FIXED] != 0.0:
        return 0.0, 0.0
    return 1.0 / bodies[i, CB_M], 1.0 / bodies[i, CB_I]


@njit(cache=True, _nrt=False, inline="always")
def _dir(c, la, k, et):
    """Direction of unknown kind et (0 normal: n, or n - mu s sliding; 1: t1; 2: t2) of
    contact k: the force on A per unit of the unknown."""
    o = LA_K + k * LK_S
    if et == 1:
        return la[o + LK_T1], la[o + LK_T1 + 1], la[o + LK_T1 + 2]
    if et == 2:
        return la[o + LK_T2], la[o + LK_T2 + 1], la[o + LK_T2 + 2]
    ex = la[o + LK_N]
    ey = la[o + LK_N + 1]
    ez = la[o + LK_N + 2]
    if c[k, CC_MODE] == MODE_SLIP and c[k, CC_MU] != 0.0:
        mu = c[k, CC_MU]
        ex -= mu * la[o + LK_SD]
        ey -= mu * la[o + LK_SD + 1]
        ez -= mu * la[o + LK_SD + 2]
    return ex, ey, ez


@njit(cache=True, _nrt=False)
def _rowmcol(bodies, c, la, ki, ex, ey, ez, kj, fx, fy, fz):
    """(row of direction e at contact ki) M^-1 (column of force direction f at contact kj):
    the relative acceleration along e at ki per unit force along f at kj."""
    s = 0.0
    oi = LA_K + ki * LK_S
    oj = LA_K + kj * LK_S
    for si in range(2):
        bi = int(c[ki, CC_A]) if si == 0 else int(c[ki, CC_B])
        if bi < 0:
            continue
        im, ii = _minv(bodies, bi)
        if im == 0.0:
            continue
        ri = oi + (LK_RA if si == 0 else LK_RB)
        for sj in range(2):
            bj = int(c[kj, CC_A]) if sj == 0 else int(c[kj, CC_B])
            if bj != bi:
                continue
            rj = oj + (LK_RA if sj == 0 else LK_RB)
            sg = 1.0 if si == sj else -1.0
            ax, ay, az = _cross(la[ri], la[ri + 1], la[ri + 2], ex, ey, ez)
            bx, by, bz = _cross(la[rj], la[rj + 1], la[rj + 2], fx, fy, fz)
            s += sg * (im * (ex * fx + ey * fy + ez * fz) + ii * (ax * bx + ay * by + az * bz))
    return s


@njit(cache=True, _nrt=False)
def _solve(la, n, floor):
    """Minimum-norm solution of A x = r (LA_A, stride NMAX; LA_R) into LA_X
    (``minnorm.minnorm_solve``). False when the residual exceeds
    ``SOLVE_RTOL (|A| |x| + |r|) + floor``."""
    minnorm_solve(la, LA_A, LA_R, LA_X, LA_U, LA_V, n, NMAX, SVD_RTOL, SVD_SWEEPS)
    res = 0.0
    sc = 0.0
    for i in range(n):
        s = -la[LA_R + i]
        a = abs(la[LA_R + i])
        for j in range(n):
            t = la[LA_A + i * NMAX + j] * la[LA_X + j]
            s += t
            a += abs(t)
        res = max(res, abs(s))
        sc = max(sc, a)
    return res <= SOLVE_RTOL * sc + floor


# ------------------------------------------------------------------ forces


@njit(cache=True, _nrt=False)
def _worst_margin(c, la, n, x0):
    """The smallest force margin of the unknowns at ``la[x0:]`` (rows LA_EQ / LA_ET):
    ``lam_N`` of every normal unknown, ``mu lam_N - |T|`` of every sticking one (N), and the
    index of the normal unknown it belongs to (-1: none); the second index is 1 for a
    cone margin, 0 for a normal one."""
    worst = math.inf
    wi = -1
    wc = 0
    for i in range(n):
        if la[LA_ET + i] != 0.0:
            continue
        ln = la[x0 + i]
        if ln < worst:
            worst = ln
            wi = i
            wc = 0
        k = int(la[LA_EQ + i])
        mu = c[k, CC_MU]
        if (i + 1 < n and la[LA_EQ + i + 1] == k and la[LA_ET + i + 1] == 1.0
                and math.isfinite(mu)):
            m = mu * ln - math.hypot(la[x0 + i + 1], la[x0 + i + 2])
            if m < worst:
                worst = m
                wi = i
                wc = 1
    return worst, wi, wc


@njit(cache=True, _nrt=False)
def _best_split(c, la, n, F):
    """Redundant sticking contacts: the min-norm solution at LA_X (``_solve``; its SVD at
    LA_U / LA_V) is one split of forces among many, ``x0 + N z`` (N: the right singular
    vectors of singular values below ``SVD_RTOL sigma_max``, ``minnorm``'s rule), all giving
    the same motion. When some margin of x0 (``_worst_margin``: ``lam_N``, and
    ``mu lam_N - |T|`` of a sticking contact) is below ``SPLIT_TARGET F``, look for z putting every force in
    its cone: a second-order-cone feasibility problem in z, solved by Polyak's subgradient
    projections (Polyak, USSR Comput. Math. Math. Phys. 9, 1969; the cyclic projections of
    convex feasibility): each step projects onto the linearisation of the worst margin,
    aimed at ``+SPLIT_TARGET F``, ``SPLIT_ITER`` steps at most. The best split found (largest
    worst margin) replaces LA_X; the caller judges it (``FORCE_TOL F``). Null vectors with
    slip-normal components (``SPLIT_SLIP_TOL``) are not used: A is symmetric only on
    the sticking / frictionless unknowns, where ``A v = 0`` means ``J^T v = 0`` (no motion)."""
    target = SPLIT_TARGET * F
    worst, wi, wc = _worst_margin(c, la, n, LA_X)
    if not worst < target:
        return
    # the squared singular values (column norms of U = A V) at LA_Z until the search uses it
    smax = 0.0
    for j in range(n):
        s2 = 0.0
        for i in range(n):
            s2 += la[LA_U + i * NMAX + j] ** 2
        la[LA_Z + j] = s2
        smax = max(smax, s2)
    nd = 0
    for j in range(n):
        if la[LA_Z + j] > SVD_RTOL * SVD_RTOL * smax:
            continue
        ok = True
        for i in range(n):
            k = int(la[LA_EQ + i])
            if (c[k, CC_MODE] == MODE_SLIP and c[k, CC_MU] != 0.0
                    and abs(la[LA_V + i * NMAX + j]) > SPLIT_SLIP_TOL):
                ok = False
        if ok:
            la[LA_NI + nd] = j
            nd += 1
    if nd == 0:
        return
    best = worst
    for i in range(n):
        la[LA_XB + i] = la[LA_X + i]
    for it in range(SPLIT_ITER):
        # the subgradient of the worst margin in x, projected on the null space (LA_Z)
        g2 = 0.0
        for d in range(nd):
            j = int(la[LA_NI + d])
            gz = la[LA_V + wi * NMAX + j]
            if wc == 1:
                k = int(la[LA_EQ + wi])
                t1 = la[LA_X + wi + 1]
                t2 = la[LA_X + wi + 2]
                tl = math.hypot(t1, t2)
                gz *= c[k, CC_MU]
                if tl > 0.0:
                    gz -= (t1 * la[LA_V + (wi + 1) * NMAX + j]
                           + t2 * la[LA_V + (wi + 2) * NMAX + j]) / tl
            la[LA_Z + d] = gz
            g2 += gz * gz
        if not g2 > 0.0:
            break                  # the worst margin does not depend on the split
        beta = (target - worst) / g2
        for d in range(nd):
            j = int(la[LA_NI + d])
            f = beta * la[LA_Z + d]
            for i in range(n):
                la[LA_X + i] += f * la[LA_V + i * NMAX + j]
        worst, wi, wc = _worst_margin(c, la, n, LA_X)
        if worst > best:
            best = worst
            for i in range(n):
                la[LA_XB + i] = la[LA_X + i]
        if worst >= target:
            break
    for i in range(n):
        la[LA_X + i] = la[LA_XB + i]


@njit(cache=True, _nrt=False)
def _forces(bodies, c, nk, w, yo, la, ko):
    """Contact forces and accelerations at the state w[yo:yo + 13 nb] for the modes
    c[:nk, CC_MODE]; dy/dt into w[ko:ko + 13 nb]; lam, T, g'', dc/dt into la. Returns CS_*."""
    nb = bodies.shape[0]
    n = 0
    for k in range(nk):
        _fill(bodies, c, k, w, yo, la, k)
        o = LA_K + k * LK_S
        if c[k, CC_MODE] == MODE_LIFT:
            la[o + LK_IN] = -1.0
            la[o + LK_IT] = -1.0
            continue
        la[o + LK_IN] = n
        la[LA_EQ + n] = k
        la[LA_ET + n] = 0.0
        n += 1
        if c[k, CC_MODE] == MODE_STICK and c[k, CC_MU] != 0.0:
            la[o + LK_IT] = n
            for q in range(2):
                la[LA_EQ + n] = k
                la[LA_ET + n] = q + 1.0
                n += 1
        else:
            la[o + LK_IT] = -1.0
    for i in range(n):
        ki = int(la[LA_EQ + i])
        ti = int(la[LA_ET + i])
        oi = LA_K + ki * LK_S
        ex, ey, ez = _dir(c, la, ki, ti) if ti != 0 else (la[oi + LK_N], la[oi + LK_N + 1],
                                                         la[oi + LK_N + 2])
        # r_i = -(row_i u'_free + b_i); u'_free: gravity on the free spheres
        if ti == 0:
            rr = la[oi + LK_BN]
        else:
            rr = ex * la[oi + LK_B] + ey * la[oi + LK_B + 1] + ez * la[oi + LK_B + 2]
        for si in range(2):
            bi = int(c[ki, CC_A]) if si == 0 else int(c[ki, CC_B])
            if bi < 0 or bodies[bi, CB_FIXED] != 0.0:
                continue
            sg = 1.0 if si == 0 else -1.0
            rr += sg * (ex * w[H_GX] + ey * w[H_GX + 1] + ez * w[H_GX + 2])
        la[LA_R + i] = -rr
        for j in range(n):
            kj = int(la[LA_EQ + j])
            fx, fy, fz = _dir(c, la, kj, int(la[LA_ET + j]))
            la[LA_A + i * NMAX + j] = _rowmcol(bodies, c, la, ki, ex, ey, ez, kj, fx, fy, fz)
    # Painleve: a sliding contact's own effective normal mass
    for k in range(nk):
        o = LA_K + k * LK_S
        i = int(la[o + LK_IN])
        if i < 0 or c[k, CC_MODE] != MODE_SLIP or c[k, CC_MU] == 0.0:
            continue
        nx = la[o + LK_N]
        ny = la[o + LK_N + 1]
        nz = la[o + LK_N + 2]
        wnn = _rowmcol(bodies, c, la, k, nx, ny, nz, k, nx, ny, nz)
        if not la[LA_A + i * NMAX + i] > PAINLEVE_RTOL * wnn:
            return CS_PAINLEVE
    if n > 0:
        amax = 0.0
        for i in range(n):
            for j in range(n):
                amax = max(amax, abs(la[LA_A + i * NMAX + j]))
        if not _solve(la, n, SOLVE_RTOL * amax * w[H_F]):
            return CS_SINGULAR
        _best_split(c, la, n, w[H_F])
    # accelerations
    for i in range(nb):
        o = yo + NS * i
        d = ko + NS * i
        for q in range(3):
            w[d + q] = w[o + S_V + q]
        # q' = 0.5 (0, omega) (x) q
        qw = w[o + S_Q]
        qx = w[o + S_Q + 1]
        qy = w[o + S_Q + 2]
        qz = w[o + S_Q + 3]
        ox = w[o + S_W]
        oy = w[o + S_W + 1]
        oz = w[o + S_W + 2]
        cx, cy, cz = _cross(ox, oy, oz, qx, qy, qz)
        w[d + S_Q] = -0.5 * (ox * qx + oy * qy + oz * qz)
        w[d + S_Q + 1] = 0.5 * (qw * ox + cx)
        w[d + S_Q + 2] = 0.5 * (qw * oy + cy)
        w[d + S_Q + 3] = 0.5 * (qw * oz + cz)
        fixed = bodies[i, CB_FIXED] != 0.0
        for q in range(3):
            w[d + S_V + q] = 0.0 if fixed else w[H_GX + q]
            w[d + S_W + q] = 0.0
    for j in range(n):
        kj = int(la[LA_EQ + j])
        fx, fy, fz = _dir(c, la, kj, int(la[LA_ET + j]))
        lam = la[LA_X + j]
        oj = LA_K + kj * LK_S
        for sj in range(2):
            bj = int(c[kj, CC_A]) if sj == 0 else int(c[kj, CC_B])
            if bj < 0:
                continue
            im, ii = _minv(bodies, bj)
            if im == 0.0:
                continue
            sg = lam if sj == 0 else -lam
            ro = oj + (LK_RA if sj == 0 else LK_RB)
            mx, my, mz = _cross(la[ro], la[ro + 1], la[ro + 2], fx, fy, fz)
            d = ko + NS * bj
            w[d + S_V] += im * sg * fx
            w[d + S_V + 1] += im * sg * fy
            w[d + S_V + 2] += im * sg * fz
            w[d + S_W] += ii * sg * mx
            w[d + S_W + 1] += ii * sg * my
            w[d + S_W + 2] += ii * sg * mz
    # forces, g'' and dc/dt per contact
    for k in range(nk):
        o = LA_K + k * LK_S
        i = int(la[o + LK_IN])
        it = int(la[o + LK_IT])
        ln = 0.0
        tx = 0.0
        ty = 0.0
        tz = 0.0
        if i >= 0:
            ln = la[LA_X + i]
            if it >= 0:
                l1 = la[LA_X + it]
                l2 = la[LA_X + it + 1]
                tx = l1 * la[o + LK_T1] + l2 * la[o + LK_T2]
                ty = l1 * la[o + LK_T1 + 1] + l2 * la[o + LK_T2 + 1]
                tz = l1 * la[o + LK_T1 + 2] + l2 * la[o + LK_T2 + 2]
            elif c[k, CC_MODE] == MODE_SLIP and c[k, CC_MU] != 0.0:
                f = -c[k, CC_MU] * ln
                tx = f * la[o + LK_SD]
                ty = f * la[o + LK_SD + 1]
                tz = f * la[o + LK_SD + 2]
        la[o + LK_LN] = ln
        la[o + LK_LT] = tx
        la[o + LK_LT + 1] = ty
        la[o + LK_LT + 2] = tz
        nx = la[o + LK_N]
        ny = la[o + LK_N + 1]
        nz = la[o + LK_N + 2]
        gdd = la[o + LK_BN]
        ax = la[o + LK_B]
        ay = la[o + LK_B + 1]
        az = la[o + LK_B + 2]
        for si in range(2):
            bi = int(c[k, CC_A]) if si == 0 else int(c[k, CC_B])
            if bi < 0:
                continue
            d = ko + NS * bi
            sg = 1.0 if si == 0 else -1.0
            ro = o + (LK_RA if si == 0 else LK_RB)
            mx, my, mz = _cross(w[d + S_W], w[d + S_W + 1], w[d + S_W + 2],
                                la[ro], la[ro + 1], la[ro + 2])
            gdd += sg * (nx * w[d + S_V] + ny * w[d + S_V + 1] + nz * w[d + S_V + 2])
            ax += sg * (w[d + S_V] + mx)
            ay += sg * (w[d + S_V + 1] + my)
            az += sg * (w[d + S_V + 2] + mz)
        an = nx * ax + ny * ay + nz * az
        la[o + LK_GDD] = gdd
        la[o + LK_AC] = ax - an * nx
        la[o + LK_AC + 1] = ay - an * ny
        la[o + LK_AC + 2] = az - an * nz
    return CS_OK


# ------------------------------------------------------------------ projection


@njit(cache=True, _nrt=False)
def _apply(bodies, c, w, yo, la, n, vel):
    """Add M^-1 J^T x (the unknowns x at LA_X, rows LA_EQ / LA_ET) to the centres
    (``vel`` False; rows normal: no rotation) or to the velocities (``vel`` True)."""
    for j in range(n):
        kj = int(la[LA_EQ + j])
        et = int(la[LA_ET + j])
        oj = LA_K + kj * LK_S
        if et == 0:
            fx, fy, fz = la[oj + LK_N], la[oj + LK_N + 1], la[oj + LK_N + 2]
        else:
            fx, fy, fz = _dir(c, la, kj, et)
        x = la[LA_X + j]
        for sj in range(2):
            bj = int(c[kj, CC_A]) if sj == 0 else int(c[kj, CC_B])
            if bj < 0:
                continue
            im, ii = _minv(bodies, bj)
            if im == 0.0:
                continue
            sg = x if sj == 0 else -x
            d = yo + NS * bj
            if not vel:
                w[d] += im * sg * fx
                w[d + 1] += im * sg * fy
                w[d + 2] += im * sg * fz
                continue
            ro = oj + (LK_RA if sj == 0 else LK_RB)
            mx, my, mz = _cross(la[ro], la[ro + 1], la[ro + 2], fx, fy, fz)
            w[d + S_V] += im * sg * fx
            w[d + S_V + 1] += im * sg * fy
            w[d + S_V + 2] += im * sg * fz
            w[d + S_W] += ii * sg * mx
            w[d + S_W + 1] += ii * sg * my
            w[d + S_W + 2] += ii * sg * mz


@njit(cache=True, _nrt=False)
def _project(bodies, c, nk, w, yo, la):
    """Project the state w[yo:yo + 13 nb] onto the active constraints (module docstring).
    Returns CS_OK or CS_SINGULAR."""
    L = w[H_L]
    nb = bodies.shape[0]
    for i in range(nb):
        o = yo + NS * i + S_Q
        qn = math.sqrt(w[o] ** 2 + w[o + 1] ** 2 + w[o + 2] ** 2 + w[o + 3] ** 2)
        for q in range(4):
            w[o + q] /= qn
    for it in range(PROJ_ITER + 1):
        n = 0
        gm = 0.0
        for k in range(nk):
            _fill(bodies, c, k, w, yo, la, k)
            if c[k, CC_MODE] == MODE_LIFT:
                continue
            la[LA_EQ + n] = k
            la[LA_ET + n] = 0.0
            la[LA_R + n] = -la[LA_K + k * LK_S + LK_G]
            gm = max(gm, abs(la[LA_K + k * LK_S + LK_G]))
            n += 1
        if n == 0 or gm <= PROJ_LTOL * L or it == PROJ_ITER:
            break
        for i in range(n):
            oi = LA_K + int(la[LA_EQ + i]) * LK_S
            for j in range(n):
                oj = LA_K + int(la[LA_EQ + j]) * LK_S
                la[LA_A + i * NMAX + j] = _rowmcol(
                    bodies, c, la, int(la[LA_EQ + i]), la[oi + LK_N], la[oi + LK_N + 1],
                    la[oi + LK_N + 2], int(la[LA_EQ + j]), la[oj + LK_N], la[oj + LK_N + 1],
                    la[oj + LK_N + 2])
        if not _solve(la, n, SOLVE_RTOL * L):
            return CS_SINGULAR
        _apply(bodies, c, w, yo, la, n, False)
    for rep in range(2):
        n = 0
        for k in range(nk):
            _fill(bodies, c, k, w, yo, la, k)
            if c[k, CC_MODE] == MODE_LIFT:
                continue
            o = LA_K + k * LK_S
            la[LA_EQ + n] = k
            la[LA_ET + n] = 0.0
            la[LA_R + n] = -la[o + LK_GD]
            n += 1
            if c[k, CC_MODE] == MODE_STICK and c[k, CC_MU] != 0.0:
                for q in range(2):
                    to = o + (LK_T1 if q == 0 else LK_T2)
                    la[LA_EQ + n] = k
                    la[LA_ET + n] = q + 1.0
                    la[LA_R + n] = -(la[to] * la[o + LK_C] + la[to + 1] * la[o + LK_C + 1]
                                     + la[to + 2] * la[o + LK_C + 2])
                    n += 1
        if n == 0:
            break
        for i in range(n):
            ki = int(la[LA_EQ + i])
            ti = int(la[LA_ET + i])
            oi = LA_K + ki * LK_S
            if ti == 0:
                ex, ey, ez = la[oi + LK_N], la[oi + LK_N + 1], la[oi + LK_N + 2]
            else:
                ex, ey, ez = _dir(c, la, ki, ti)
            for j in range(n):
                kj = int(la[LA_EQ + j])
                tj = int(la[LA_ET + j])
                oj = LA_K + kj * LK_S
                if tj == 0:
                    fx, fy, fz = la[oj + LK_N], la[oj + LK_N + 1], la[oj + LK_N + 2]
                else:
                    fx, fy, fz = _dir(c, la, kj, tj)
                la[LA_A + i * NMAX + j] = _rowmcol(bodies, c, la, ki, ex, ey, ez, kj, fx, fy,
                                                   fz)
        if not _solve(la, n, SOLVE_RTOL * w[H_V]):
            return CS_SINGULAR
        _apply(bodies, c, w, yo, la, n, True)
    return CS_OK


# ------------------------------------------------------------------ setup helpers


@njit(cache=True, _nrt=False)
def _setup(bodies, gx, gy, gz, L, w):
    """Header of w: gravity, scales; the spheres' state into block B_Y."""
    nb = bodies.shape[0]
    NY = NS * nb
    gl = math.sqrt(gx * gx + gy * gy + gz * gz)
    w[H_GX] = gx
    w[H_GX + 1] = gy
    w[H_GX + 2] = gz
    w[H_G] = gl
    w[H_L] = L
    vmax = 0.0
    msum = 0.0
    for i in range(nb):
        if bodies[i, CB_FIXED] != 0.0:
            continue
        v = math.sqrt(bodies[i, CB_VX] ** 2 + bodies[i, CB_VX + 1] ** 2
                      + bodies[i, CB_VX + 2] ** 2)
        om = math.sqrt(bodies[i, CB_WX] ** 2 + bodies[i, CB_WX + 1] ** 2
                       + bodies[i, CB_WX + 2] ** 2)
        vmax = max(vmax, v + om * L)
        msum += bodies[i, CB_M]
    V = vmax + math.sqrt(gl * L)
    if not V > 0.0:
        V = 1.0 * L     # no gravity, no motion: any positive scale (1/s times L)
    w[H_V] = V
    F = msum * gl
    if not F > 0.0:
        F = msum * V * V / L
    w[H_F] = F
    w[H_TOL] = CLUSTER_TOL
    yo = N_H + B_Y * NY
    so = N_H + B_SC * NY
    for i in range(nb):
        for j in range(NS):
            w[yo + NS * i + j] = bodies[i, j]
            if j < S_Q:
                sc = L
            elif j < S_V:
                sc = 1.0
            elif j < S_W:
                sc = V
            else:
                sc = V / L
            w[so + NS * i + j] = sc


@njit(cache=True, _nrt=False)
def _store(bodies, c, nk, w, yo, la):
    """State w[yo:...] into the bodies table; the forces of la into the contact table."""
    nb = bodies.shape[0]
    for i in range(nb):
        for j in range(NS):
            bodies[i, j] = w[yo + NS * i + j]
    for k in range(nk):
        o = LA_K + k * LK_S
        c[k, CC_LAMN] = la[o + LK_LN]
        for q in range(3):
            c[k, CC_TX + q] = la[o + LK_LT + q]


# ------------------------------------------------------------------ public: forces, rates


@njit(cache=True, _nrt=False)
def _forces_table(bodies, contacts, nk, gx, gy, gz, L, w, la):
    """_forces for the state of ``bodies``; forces into the table, derivative into B_YC."""
    if nk > KMAX:
        return CS_TOO_MANY_CONTACTS
    NY = NS * bodies.shape[0]
    _setup(bodies, gx, gy, gz, L, w)
    st = _forces(bodies, contacts, nk, w, N_H + B_Y * NY, la, N_H + B_YC * NY)
    if st != CS_OK:
        return st
    for k in range(nk):
        o = LA_K + k * LK_S
        contacts[k, CC_LAMN] = la[o + LK_LN]
        for q in range(3):
            contacts[k, CC_TX + q] = la[o + LK_LT + q]
    return CS_OK


@njit(cache=True, _nrt=False)
def cluster_forces(bodies, contacts, nk, gx, gy, gz, L, w, la, acc):
    """Contact forces (into ``contacts[:nk, CC_LAMN / CC_TX..]``) and accelerations (into
    ``acc``, float64[nb, 6]: a (3), alpha (3)) for the state of ``bodies`` and the modes
    ``contacts[:nk, CC_MODE]``. Returns CS_*."""
    st = _forces_table(bodies, contacts, nk, gx, gy, gz, L, w, la)
    if st != CS_OK:
        return st
    ko = N_H + B_YC * NS * bodies.shape[0]
    for i in range(bodies.shape[0]):
        for q in range(3):
            acc[i, q] = w[ko + NS * i + S_V + q]
            acc[i, 3 + q] = w[ko + NS * i + S_W + q]
    return CS_OK


@njit(cache=True, _nrt=False)
def cluster_rates(bodies, c, k, acc, w, la, out):
    """Kinematics of contact row k of table c for the state of ``bodies`` and the
    accelerations ``acc`` (float64[nb, 6]): ``out[:]`` = (g, dg/dt, g'', c (3),
    dc/dt tangential part (3), n (3))."""
    nb = bodies.shape[0]
    for i in range(nb):
        for j in range(NS):
            w[N_H + NS * i + j] = bodies[i, j]
    w[H_V] = 1.0
    _fill(bodies, c, k, w, N_H, la, KMAX)
    o = LA_K + KMAX * LK_S
    nx = la[o + LK_N]
    ny = la[o + LK_N + 1]
    nz = la[o + LK_N + 2]
    gdd = la[o + LK_BN]
    ax = la[o + LK_B]
    ay = la[o + LK_B + 1]
    az = la[o + LK_B + 2]
    for si in range(2):
        bi = int(c[k, CC_A]) if si == 0 else int(c[k, CC_B])
        if bi < 0:
            continue
        sg = 1.0 if si == 0 else -1.0
        ro = o + (LK_RA if si == 0 else LK_RB)
        mx, my, mz = _cross(acc[bi, 3], acc[bi, 4], acc[bi, 5], la[ro], la[ro + 1], la[ro + 2])
        gdd += sg * (nx * acc[bi, 0] + ny * acc[bi, 1] + nz * acc[bi, 2])
        ax += sg * (acc[bi, 0] + mx)
        ay += sg * (acc[bi, 1] + my)
        az += sg * (acc[bi, 2] + mz)
    an = nx * ax + ny * ay + nz * az
    out[0] = la[o + LK_G]
    out[1] = la[o + LK_GD]
    out[2] = gdd
    for q in range(3):
        out[3 + q] = la[o + LK_C + q]
        out[9 + q] = la[o + LK_N + q]
    out[6] = ax - an * nx
    out[7] = ay - an * ny
    out[8] = az - an * nz


@njit(cache=True, _nrt=False)
def cluster_energy(bodies, gx, gy, gz):
    """Kinetic plus gravitational energy (J) of the free spheres (potential 0 at x = 0)."""
    e = 0.0
    for i in range(bodies.shape[0]):
        if bodies[i, CB_FIXED] != 0.0:
            continue
        m = bodies[i, CB_M]
        v2 = bodies[i, CB_VX] ** 2 + bodies[i, CB_VX + 1] ** 2 + bodies[i, CB_VX + 2] ** 2
        w2 = bodies[i, CB_WX] ** 2 + bodies[i, CB_WX + 1] ** 2 + bodies[i, CB_WX + 2] ** 2
        e += (0.5 * m * v2 + 0.5 * bodies[i, CB_I] * w2
              - m * (gx * bodies[i, CB_X] + gy * bodies[i, CB_X + 1] + gz * bodies[i, CB_X + 2]))
    return e


@njit(cache=True, _nrt=False)
def cluster_project(bodies, contacts, nk, gx, gy, gz, L, w, la):
    """Project the state of ``bodies`` onto the active contacts (centres: g = 0;
    velocities: dg/dt = 0, and c = 0 where sticking; unit quaternions), in place.
    Returns CS_*."""
    if nk > KMAX:
        return CS_TOO_MANY_CONTACTS
    nb = bodies.shape[0]
    NY = NS * nb
    _setup(bodies, gx, gy, gz, L, w)
    yo = N_H + B_Y * NY
    st = _project(bodies, contacts, nk, w, yo, la)
    for i in range(nb):
        for j in range(NS):
            bodies[i, j] = w[yo + NS * i + j]
    return st


# ------------------------------------------------------------------ mode selection


@njit(cache=True, _nrt=False)
def _consistent(c, nk, w, la, nopt):
    """The solved forces (la) consistent with the modes c[:nk, CC_MODE] (module doc)?
    ``w[nopt + k]``: the number of options of contact k (3: it starts at c = 0)."""
    F = w[H_F]
    gl = w[H_G]
    atol = ACC_TOL * (gl if gl > 0.0 else w[H_V] * w[H_V] / w[H_L])
    for k in range(nk):
        o = LA_K + k * LK_S
        mode = c[k, CC_MODE]
        if mode == MODE_LIFT:
            if la[o + LK_GDD] < -atol:
                return False
            continue
        ln = la[o + LK_LN]
        if ln < -FORCE_TOL * F:
            return False
        mu = c[k, CC_MU]
        if mu == 0.0:
            continue
        if mode == MODE_STICK:
            tl = math.sqrt(la[o + LK_LT] ** 2 + la[o + LK_LT + 1] ** 2 + la[o + LK_LT + 2] ** 2)
            if tl > mu * ln + FORCE_TOL * F:
                return False
        elif w[nopt + k] == 3.0:
            # starts to slip from c = 0: it must accelerate along its friction direction
            sx = la[o + LK_SD]
            sy = la[o + LK_SD + 1]
            sz = la[o + LK_SD + 2]
            ax = la[o + LK_AC]
            ay = la[o + LK_AC + 1]
            az = la[o + LK_AC + 2]
            if not sx * ax + sy * ay + sz * az > atol:
                return False
            # ... and along it (s || dc/dt: the Coulomb law at the slip's start)
            cx, cy, cz = _cross(sx, sy, sz, ax, ay, az)
            if (math.sqrt(cx * cx + cy * cy + cz * cz)
                    > SLIPDIR_ATOL * math.sqrt(ax * ax + ay * ay + az * az)):
                return False
    return True


@njit(cache=True, _nrt=False, inline="always")
def _option_mode(w, nopt, opt):
    """The mode of option ``opt`` of a contact with ``nopt`` options (``_enumerate``)."""
    if nopt == 1.0:
        return -1.0          # held: its table mode
    if nopt == 2.0:
        return -1.0 if opt == 0 else MODE_LIFT
    if opt == 0:
        return MODE_STICK
    if opt == 1:
        return MODE_SLIP
    return MODE_LIFT


@njit(cache=True, _nrt=False)
def _slip_start_dirs(bodies, contacts, nk, w, la, yo, ko, nopt, cur):
    """CC_SX.. of every contact that may start to slip from c = 0 (``w[nopt + k] == 3``): the
    direction opposite to its sticking force in the trial with those contacts sticking
    and the others in their modes (t1 if that force is zero or the trial fails)."""
    for k in range(nk):
        if w[nopt + k] == 3.0:
            contacts[k, CC_MODE] = MODE_STICK
    st = _forces(bodies, contacts, nk, w, yo, la, ko)
    for k in range(nk):
        if w[nopt + k] != 3.0:
            continue
        o = LA_K + k * LK_S
        tx = la[o + LK_LT] if st == CS_OK else 0.0
        ty = la[o + LK_LT + 1] if st == CS_OK else 0.0
        tz = la[o + LK_LT + 2] if st == CS_OK else 0.0
        tl = math.sqrt(tx * tx + ty * ty + tz * tz)
        if tl > 0.0:
            for q in range(3):
                contacts[k, CC_SX + q] = -la[o + LK_LT + q] / tl
        else:
            for q in range(3):
                contacts[k, CC_SX + q] = la[o + LK_T1 + q]
    for k in range(nk):
        contacts[k, CC_MODE] = w[cur + k]


@njit(cache=True, _nrt=False)
def _slip_rates(bodies, contacts, nk, w, la, yo, ko, k, th):
    """Contact k sliding from c = 0 along ``s = cos(th) t1 + sin(th) t2`` (written to
    ``CC_SX..``): the forces solved, returns (status, f, h) with ``f = (s x dc/dt) . n``
    (zero when the slip grows along s or against it) and ``h = s . dc/dt``."""
    o = LA_K + k * LK_S
    cs = math.cos(th)
    sn = math.sin(th)
    for q in range(3):
        contacts[k, CC_SX + q] = cs * la[o + LK_T1 + q] + sn * la[o + LK_T2 + q]
    st = _forces(bodies, contacts, nk, w, yo, la, ko)
    a1 = 0.0
    a2 = 0.0
    for q in range(3):
        a1 += la[o + LK_AC + q] * la[o + LK_T1 + q]
        a2 += la[o + LK_AC + q] * la[o + LK_T2 + q]
    return st, a2 * cs - a1 * sn, a1 * cs + a2 * sn


@njit(cache=True, _nrt=False)
def _slip_angle(bodies, contacts, nk, w, la, yo, ko, k):
    """The start direction of contact k's slip from c = 0, the others' modes and directions
    held: the angle th in its tangent plane where its slip acceleration is along s
    (``f = 0``, ``h > 0`` of ``_slip_rates``): ``SLIPDIR_SCAN`` samples, the bracket nearest
    the current direction, bisection to ``SLIPDIR_TOL``. None: the direction is left as
    it was. Returns True when a root was found."""
    o = LA_K + k * LK_S
    sx = contacts[k, CC_SX]
    sy = contacts[k, CC_SX + 1]
    sz = contacts[k, CC_SX + 2]
    th0 = math.atan2(sx * la[o + LK_T2] + sy * la[o + LK_T2 + 1] + sz * la[o + LK_T2 + 2],
                     sx * la[o + LK_T1] + sy * la[o + LK_T1 + 1] + sz * la[o + LK_T1 + 2])
    dth = 2.0 * math.pi / SLIPDIR_SCAN
    best = -1.0
    bd = math.inf
    st, fp, hp = _slip_rates(bodies, contacts, nk, w, la, yo, ko, k, th0)
    okp = st == CS_OK
    for i in range(1, SLIPDIR_SCAN + 1):
        th = th0 + dth * i        # once around, from the current direction
        st, f, h = _slip_rates(bodies, contacts, nk, w, la, yo, ko, k, th)
        ok = st == CS_OK
        if ok and okp and hp > 0.0 and h > 0.0 and (f <= 0.0) != (fp <= 0.0):
            lo = th - dth
            hi = th
            flo = fp
            for it in range(SLIPDIR_BISECT):
                if hi - lo <= SLIPDIR_TOL:
                    break
                mid = 0.5 * (lo + hi)
                st, fm, hm = _slip_rates(bodies, contacts, nk, w, la, yo, ko, k, mid)
                if (fm <= 0.0) == (flo <= 0.0):
                    lo = mid
                    flo = fm
                else:
                    hi = mid
            root = 0.5 * (lo + hi)
            dist = min(abs(root - th0), 2.0 * math.pi - abs(root - th0))
            if dist < bd:
                bd = dist
                best = root
        fp = f
        hp = h
        okp = ok
    if bd == math.inf:
        contacts[k, CC_SX] = sx
        contacts[k, CC_SX + 1] = sy
        contacts[k, CC_SX + 2] = sz
        return False
    cs = math.cos(best)
    sn = math.sin(best)
    for q in range(3):
        contacts[k, CC_SX + q] = cs * la[o + LK_T1 + q] + sn * la[o + LK_T2 + q]
    return True


@njit(cache=True, _nrt=False)
def _slip_fixed_point(bodies, contacts, nk, w, la, yo, ko, nopt):
    """Forces of the current combination, every contact that starts to slip from c = 0
    (``w[nopt + k] == 3``, in MODE_SLIP) along a direction its slip acceleration agrees
    with (the Coulomb law at a slip's start: the friction opposes the slip that grows
    along s): sweeps over those contacts, each one's direction found by ``_slip_angle``
    with the others held, until every one agrees to ``SLIPDIR_TOL`` (at most
    ``SLIPDIR_ITER`` sweeps; one sweep for a single such contact). Not converged: the last
    directions, the consistency test judges them. Returns the force status."""
    for sweep in range(SLIPDIR_ITER + 1):
        st = _forces(bodies, contacts, nk, w, yo, la, ko)
        if st != CS_OK or sweep == SLIPDIR_ITER:
            return st
        moved = False
        for k in range(nk):
            if w[nopt + k] != 3.0 or contacts[k, CC_MODE] != MODE_SLIP:
                continue
            o = LA_K + k * LK_S
            ax = la[o + LK_AC]
            ay = la[o + LK_AC + 1]
            az = la[o + LK_AC + 2]
            al = math.sqrt(ax * ax + ay * ay + az * az)
            if not al > 0.0:
                continue
            sx = la[o + LK_SD]
            sy = la[o + LK_SD + 1]
            sz = la[o + LK_SD + 2]
            cx, cy, cz = _cross(sx, sy, sz, ax / al, ay / al, az / al)
            if (sx * ax + sy * ay + sz * az > 0.0
                    and math.sqrt(cx * cx + cy * cy + cz * cz) <= SLIPDIR_TOL):
                continue
            if _slip_angle(bodies, contacts, nk, w, la, yo, ko, k):
                moved = True
            st = _forces(bodies, contacts, nk, w, yo, la, ko)
            if st != CS_OK:
                return st
        if not moved:
            return st
    return CS_OK


@njit(cache=True, _nrt=False)
def _enumerate(bodies, contacts, nk, gx, gy, gz, L, w, la, kfix, prefer):
    """The enumeration of ``cluster_select_modes`` with contact ``kfix`` held in its table
    mode (-1: none held). ``prefer``: combinations ordered by the number of contacts
    whose mode differs from the table's current one. Returns CS_OK (modes and forces
    written), CS_NO_MODE or CS_TOO_MANY_CONTACTS."""
    if nk > KSEL_MAX:
        return CS_TOO_MANY_CONTACTS
    nb = bodies.shape[0]
    NY = NS * nb
    _setup(bodies, gx, gy, gz, L, w)
    yo = N_H + B_Y * NY
    ko = N_H + B_YC * NY
    nopt = N_H + B_YB * NY      # per contact: its number of options
    cur = N_H + B_Y1 * NY       # per contact: its mode on entry
    V = w[H_V]
    gl = w[H_G]
    window = STOP_RTOL * (math.sqrt(L / gl) if gl > 0.0 else L / V)
    rated = _forces(bodies, contacts, nk, w, yo, la, ko) == CS_OK
    total = 1
    for k in range(nk):
        o = LA_K + k * LK_S
        cx = la[o + LK_C]
        cy = la[o + LK_C + 1]
        cz = la[o + LK_C + 2]
        cl = math.sqrt(cx * cx + cy * cy + cz * cz)
        ca = ((cx * la[o + LK_AC] + cy * la[o + LK_AC + 1] + cz * la[o + LK_AC + 2])
              if rated else 0.0)
        w[cur + k] = contacts[k, CC_MODE]
        mode = contacts[k, CC_MODE]
        # a slip its current mode stops within the window stops now (d|c|/dt = c.dc/dt/|c|):
        # sticking counts as its mode on entry (near-simultaneous stops are one: the other
        # slips of a symmetric cluster stop with the one whose event fired, whose own
        # events start below their arms and would not fire)
        stopping = mode == MODE_SLIP and ca < 0.0 and cl * cl <= -ca * window
        if stopping and k != kfix:
            w[cur + k] = MODE_STICK
        if k == kfix:
            w[nopt + k] = 1.0
        elif contacts[k, CC_MU] == 0.0:
            contacts[k, CC_MODE] = MODE_STICK      # frictionless: active or lift
            w[cur + k] = MODE_STICK if mode != MODE_LIFT else MODE_LIFT
            w[nopt + k] = 2.0
        elif cl > STICK_VTOL * V and not stopping:
            contacts[k, CC_MODE] = MODE_SLIP
            w[nopt + k] = 2.0
        else:
            w[nopt + k] = 3.0
        total *= int(w[nopt + k])
    _slip_start_dirs(bodies, contacts, nk, w, la, yo, ko, nopt, cur)
    held = N_H + B_YA * NY      # per contact: the mode of its first option
    for k in range(nk):
        held_mode = w[cur + k]
        if w[nopt + k] == 2.0:
            held_mode = MODE_STICK if contacts[k, CC_MU] == 0.0 else MODE_SLIP
        w[held + k] = held_mode
    for d in range(nk + 1 if prefer else 1):
        for combo in range(total):
            r = combo
            diff = 0
            for kk in range(nk):
                k = nk - 1 - kk            # the last contact varies fastest
                no = int(w[nopt + k])
                mode = _option_mode(w, w[nopt + k], r % no)
                r //= no
                if mode == -1.0:
                    mode = w[held + k]
                if mode != w[cur + k] and k != kfix:
                    diff += 1
                contacts[k, CC_MODE] = mode
            if prefer and diff != d:
                continue
            st = _slip_fixed_point(bodies, contacts, nk, w, la, yo, ko, nopt)
            if st != CS_OK:
                continue
            if _consistent(contacts, nk, w, la, nopt):
                for k in range(nk):
                    o = LA_K + k * LK_S
                    contacts[k, CC_LAMN] = la[o + LK_LN]
                    for q in range(3):
                        contacts[k, CC_TX + q] = la[o + LK_LT + q]
                return CS_OK
    return CS_NO_MODE


@njit(cache=True, _nrt=False)
def cluster_select_modes(bodies, contacts, nk, gx, gy, gz, L, w, la):
    """Choose a consistent mode for each of ``contacts[:nk]`` (every one at g = dg/dt = 0)
    by the enumeration of the module docstring; modes to ``CC_MODE`` (``MODE_LIFT`` for
    the contacts that leave; ``CC_SX..`` for a slip from rest), forces to ``CC_LAMN / CC_TX..``.
    Returns CS_OK, CS_NO_MODE (modes left as the last tried) or CS_TOO_MANY_CONTACTS."""
    return _enumerate(bodies, contacts, nk, gx, gy, gz, L, w, la, -1, False)


@njit(cache=True, _nrt=False)
def cluster_after_event(bodies, contacts, nk, ev, k, gx, gy, gz, L, w, la):
    """The modes after ``cluster_advance`` returned event ``ev`` at contact k (state and
    forces as returned). Contact k takes the mode the trend calls for: ``CE_LEAVE`` ->
    ``MODE_LIFT`` (the stepper moves it to the candidates); ``CE_SLIP`` -> slip, its start
    direction ``CC_SX..`` opposite to the sticking force at the event (``pivot3d``'s rule);
    ``CE_STOP`` -> stick if the sticking force is inside the cone, else slip on, along
    the direction opposite to that force. The others keep their modes if consistent,
    else are chosen again by the enumeration with k held, changing as few modes as
    possible; none: the full enumeration; none: CS_NO_MODE. ``CE_GAP``: nothing (the
    stepper's impact). Returns the status (forces written)."""
    if ev != CE_LEAVE and ev != CE_SLIP and ev != CE_STOP:
        return _forces_table(bodies, contacts, nk, gx, gy, gz, L, w, la)
    st = CS_OK
    if ev == CE_LEAVE:
        contacts[k, CC_MODE] = MODE_LIFT
    else:
        if ev == CE_STOP:
            contacts[k, CC_MODE] = MODE_STICK
            st = _forces_table(bodies, contacts, nk, gx, gy, gz, L, w, la)
            if st != CS_OK and st != CS_SINGULAR and st != CS_PAINLEVE:
                return st
        tx = contacts[k, CC_TX]
        ty = contacts[k, CC_TX + 1]
        tz = contacts[k, CC_TX + 2]
        tl = math.sqrt(tx * tx + ty * ty + tz * tz)
        inside = ev == CE_STOP and st == CS_OK and tl <= contacts[k, CC_MU] * contacts[k, CC_LAMN]
        if inside or not tl > 0.0:
            contacts[k, CC_MODE] = MODE_STICK
        else:
            contacts[k, CC_MODE] = MODE_SLIP
            contacts[k, CC_SX] = -tx / tl
            contacts[k, CC_SX + 1] = -ty / tl
            contacts[k, CC_SX + 2] = -tz / tl
    st = _enumerate(bodies, contacts, nk, gx, gy, gz, L, w, la, k, True)
    if st == CS_NO_MODE:
        st = _enumerate(bodies, contacts, nk, gx, gy, gz, L, w, la, -1, True)
    return st


# ------------------------------------------------------------------ integration


@njit(cache=True, _nrt=False)
def _stage(bodies, c, nk, la, w, yo, ko):
    """The right-hand side of ``dopri5_step``: ``_forces`` at w[yo:yo + NY] into w[ko:...]."""
    return _forces(bodies, c, nk, w, yo, la, ko)


@njit(cache=True, _nrt=False)
def _step(bodies, c, nk, w, la, NY, h):
    """One error-controlled DOPRI5 step from block B_Y (stage 1 at B_K). Returns
    (status, attempts); the accepted step length is w[H_H]."""
    return dopri5_step(_stage, (bodies, c, nk, la), w, NY, N_H + B_Y * NY, N_H + B_YT * NY,
                       N_H + B_Y1 * NY, N_H + B_K * NY, N_H + B_RC * NY, N_H + B_SC * NY,
                       H_H, H_HNEXT, w[H_TOL], h, MAX_TRIES, True, 0.0, 0.0,
                       CS_TOO_MANY_STEPS)


@njit(cache=True, _nrt=False, inline="always")
def _dense(w, NY, s, yo):
    """Dense output at s (within the current step) into w[yo:yo + NY]."""
    dense_out(w, NY, N_H + B_RC * NY, H_S0, H_H, s, w, yo)


@njit(cache=True, _nrt=False)
def _events(bodies, c, nk, cands, nc, w, la, NY, yo, eo):
    """Every event function at the state w[yo:yo + NY] into w[eo:eo + N_EVK KMAX + nc] (inf
    where it does not apply): for active contact k at N_EVK k: lam_N (N); its cone margin
    mu lam_N - |T| (N) or its slip |c| - SLIP_EPS V (m/s; for a slip from sticking still
    below SLIP_EPS V: its growth s . dc/dt times the time scale L / V, in m/s); at
    N_EVK KMAX + j the gap of candidate j (m). Returns the force status."""
    st = _forces(bodies, c, nk, w, yo, la, N_H + B_YC * NY)
    V = w[H_V]
    for k in range(KMAX):
        e0 = eo + N_EVK * k
        for j in range(N_EVK):
            w[e0 + j] = math.inf
        if k >= nk or st != CS_OK:
            continue
        o = LA_K + k * LK_S
        mode = c[k, CC_MODE]
        if mode == MODE_LIFT:
            continue
        w[e0] = la[o + LK_LN]
        mu = c[k, CC_MU]
        if mu == 0.0 or mu == math.inf:
            continue
        if mode == MODE_STICK:
            tl = math.sqrt(la[o + LK_LT] ** 2 + la[o + LK_LT + 1] ** 2 + la[o + LK_LT + 2] ** 2)
            w[e0 + 1] = mu * la[o + LK_LN] - tl
        else:
            cl = math.sqrt(la[o + LK_C] ** 2 + la[o + LK_C + 1] ** 2 + la[o + LK_C + 2] ** 2)
            w[e0 + 1] = cl - SLIP_EPS * V
            started = (c[k, CC_SX] != 0.0 or c[k, CC_SX + 1] != 0.0 or c[k, CC_SX + 2] != 0.0)
            if cl < SLIP_EPS * V and started:
                w[e0 + 1] = (la[o + LK_SD] * la[o + LK_AC] + la[o + LK_SD + 1] * la[o + LK_AC + 1]
                             + la[o + LK_SD + 2] * la[o + LK_AC + 2]) * w[H_L] / V
    for j in range(nc):
        _fill(bodies, cands, j, w, yo, la, KMAX)
        w[eo + N_EVK * KMAX + j] = la[LA_K + KMAX * LK_S + LK_G]
    return st


@njit(cache=True, _nrt=False)
def _arm(w, c, nk, e, v):
    """Firing level of event e for a step starting at value v: a function starting below
    its arm fires below min(0, v) - arm."""
    if e >= N_EVK * KMAX:
        arm = GAP_ARM * w[H_L]
    else:
        k = e // N_EVK
        j = e % N_EVK
        if j == 0 or c[k, CC_MODE] == MODE_STICK:
            arm = FORCE_ARM * w[H_F]
        else:
            arm = SLIP_ARM * w[H_V]
    if v > arm:
        return 0.0
    return min(0.0, v) - arm


@njit(cache=True, _nrt=False)
def _one_event(bodies, c, nk, cands, nc, w, la, NY, yo, e):
    """Event function e at w[yo:...] (see _events)."""
    eo = N_H + N_BLK * NY + 3 * (N_EVK * KMAX + nc)   # the fourth event block: scratch
    _events(bodies, c, nk, cands, nc, w, la, NY, yo, eo)
    return w[eo + e]


@njit(cache=True, _nrt=False)
def _locate(bodies, c, nk, cands, nc, w, la, NY, e, fl, sa, sb, tt):
    """First root of event e minus its floor fl in (sa, sb] on the dense output (value > 0
    at sa, <= 0 at sb; Illinois-safeguarded secant: every third step bisects). Returns
    the far side for a force or slip event, the near side for a gap."""
    YA = N_H + B_YA * NY
    _dense(w, NY, sa, YA)
    fa = _one_event(bodies, c, nk, cands, nc, w, la, NY, YA, e) - fl
    _dense(w, NY, sb, YA)
    fb = _one_event(bodies, c, nk, cands, nc, w, la, NY, YA, e) - fl
    t0 = w[H_T0]
    for it in range(EVENT_ITER):
        if sb - sa <= tt + EVENT_RTOL * abs(t0 + sb):
            break
        sm = sb - fb * (sb - sa) / (fb - fa) if fb != fa else 0.5 * (sa + sb)
        if not (sa < sm < sb) or it % 3 == 2:
            sm = 0.5 * (sa + sb)
        _dense(w, NY, sm, YA)
        fm = _one_event(bodies, c, nk, cands, nc, w, la, NY, YA, e) - fl
        if fm > 0.0:
            sa = sm
            fa = fm
        else:
            sb = sm
            fb = fm
    return sa if e >= N_EVK * KMAX else sb


@njit(cache=True, _nrt=False)
def _at_rest(bodies, c, nk, w, la):
    """The rest test of the module docstring at block B_Y (forces solved into la)."""
    nb = bodies.shape[0]
    NY = NS * nb
    L = w[H_L]
    gl = w[H_G]
    F = w[H_F]
    if not gl > 0.0:
        return False
    Y = N_H + B_Y * NY
    KO = N_H + B_YC * NY
    if _forces(bodies, c, nk, w, Y, la, KO) != CS_OK:
        return False
    for i in range(nb):
        o = Y + NS * i
        v = math.sqrt(w[o + S_V] ** 2 + w[o + S_V + 1] ** 2 + w[o + S_V + 2] ** 2)
        om = math.sqrt(w[o + S_W] ** 2 + w[o + S_W + 1] ** 2 + w[o + S_W + 2] ** 2)
        if bodies[i, CB_FIXED] != 0.0:
            if v + om * L > 0.0:
                return False
            continue
        if v + om * L > REST_VTOL * math.sqrt(gl * L):
            return False
        d = KO + NS * i
        a = math.sqrt(w[d + S_V] ** 2 + w[d + S_V + 1] ** 2 + w[d + S_V + 2] ** 2)
        al = math.sqrt(w[d + S_W] ** 2 + w[d + S_W + 1] ** 2 + w[d + S_W + 2] ** 2)
        if a + al * L > REST_ATOL * gl:
            return False
    for k in range(nk):
        mode = c[k, CC_MODE]
        if mode == MODE_LIFT:
            continue
        o = LA_K + k * LK_S
        mu = c[k, CC_MU]
        if mode != MODE_STICK and mu != 0.0:
            return False
        ln = la[o + LK_LN]
        if not ln > FORCE_TOL * F:
            return False
        tl = math.sqrt(la[o + LK_LT] ** 2 + la[o + LK_LT + 1] ** 2 + la[o + LK_LT + 2] ** 2)
        if mu != math.inf and not tl < mu * ln - FORCE_TOL * F and mu != 0.0:
            return False
    return True


@njit(cache=True, _nrt=False)
def piece_state(row, s, out):
    """State (x, q, v, omega: 13 values into ``out``) of a recorded piece ``row`` (float64
    [N_ROW]: start state and constant a, alpha) at ``s`` seconds after its start:
    ``x = x0 + v0 s + a s^2/2``, ``v = v0 + a s``, ``omega = omega0 + alpha s``, and
    ``q = exp(theta / 2) (x) q0`` with the rotation vector ``theta = omega0 s + alpha s^2/2``
    (exact for a fixed axis; the recording's piece lengths bound its error for any)."""
    hh = 0.5 * s * s
    for j in range(3):
        out[j] = row[j] + row[S_V + j] * s + row[R_A + j] * hh
        out[S_V + j] = row[S_V + j] + row[R_A + j] * s
        out[S_W + j] = row[S_W + j] + row[R_AL + j] * s
    tx = row[S_W] * s + row[R_AL] * hh
    ty = row[S_W + 1] * s + row[R_AL + 1] * hh
    tz = row[S_W + 2] * s + row[R_AL + 2] * hh
    th = math.sqrt(tx * tx + ty * ty + tz * tz)
    cw = math.cos(0.5 * th)
    sf = 0.5 if th == 0.0 else math.sin(0.5 * th) / th
    ex = sf * tx
    ey = sf * ty
    ez = sf * tz
    qw = row[S_Q]
    qx = row[S_Q + 1]
    qy = row[S_Q + 2]
    qz = row[S_Q + 3]
    cx, cy, cz = _cross(ex, ey, ez, qx, qy, qz)
    out[S_Q] = cw * qw - (ex * qx + ey * qy + ez * qz)
    out[S_Q + 1] = cw * qx + qw * ex + cx
    out[S_Q + 2] = cw * qy + qw * ey + cy
    out[S_Q + 3] = cw * qz + qw * ez + cz


@njit(cache=True, _nrt=False)
def _rows_off(NY, nc):
    """Offset of the three piece row blocks in w."""
    return N_H + N_BLK * NY + N_EVW * (N_EVK * KMAX + nc)


@njit(cache=True, _nrt=False)
def _dense_rows(bodies, w, NY, s, ro):
    """The dense state at s as rows (x, q unit, v, omega, 0, 0) at w[ro + N_ROW i]."""
    YA = N_H + B_YA * NY
    _dense(w, NY, s, YA)
    for i in range(bodies.shape[0]):
        o = ro + N_ROW * i
        for j in range(NS):
            w[o + j] = w[YA + NS * i + j]
        qn = math.sqrt(w[o + S_Q] ** 2 + w[o + S_Q + 1] ** 2 + w[o + S_Q + 2] ** 2
                       + w[o + S_Q + 3] ** 2)
        for j in range(4):
            w[o + S_Q + j] /= qn
        for j in range(6):
            w[o + R_A + j] = 0.0


@njit(cache=True, _nrt=False)
def _row_energy(bodies, i, w, o, g0, g1, g2):
    """Energy (J) of sphere i in the state row at w[o:]."""
    m = bodies[i, CB_M]
    return (0.5 * m * (w[o + S_V] ** 2 + w[o + S_V + 1] ** 2 + w[o + S_V + 2] ** 2)
            + 0.5 * bodies[i, CB_I] * (w[o + S_W] ** 2 + w[o + S_W + 1] ** 2
                                       + w[o + S_W + 2] ** 2)
            - m * (g0 * w[o] + g1 * w[o + 1] + g2 * w[o + 2]))


@njit(cache=True, _nrt=False)
def _piece_dev(bodies, w, NY, nc, sa, h):
    """Deviation of the velocity-interpolating piece over [sa, sa + h] from the dense
    solution, every free sphere together: (energy deviation / (PIECE_ETOL M V^2),
    max(point deviation / (PIECE_LTOL L), velocity deviation / (PIECE_VTOL V))), the larger
    at h/2 and h (points: the centre and L times the orientation's angle). The piece's
    rows (start state, constant accelerations) are left in the first row block."""
    nb = bodies.shape[0]
    R0 = _rows_off(NY, nc)
    R1 = R0 + N_ROW * nb
    R2 = R1 + N_ROW * nb
    L = w[H_L]
    V = w[H_V]
    _dense_rows(bodies, w, NY, sa, R0)
    _dense_rows(bodies, w, NY, sa + h, R1)
    for i in range(nb):
        for j in range(3):
            w[R0 + N_ROW * i + R_A + j] = (w[R1 + N_ROW * i + S_V + j]
                                           - w[R0 + N_ROW * i + S_V + j]) / h
            w[R0 + N_ROW * i + R_AL + j] = (w[R1 + N_ROW * i + S_W + j]
                                            - w[R0 + N_ROW * i + S_W + j]) / h
    de = 0.0
    dp = 0.0
    mtot = 0.0
    for smp in range(2):
        sx = h if smp == 0 else 0.5 * h
        if smp == 1:
            _dense_rows(bodies, w, NY, sa + sx, R1)
        ep = 0.0
        ei = 0.0
        for i in range(nb):
            if bodies[i, CB_FIXED] != 0.0:
                continue
            mtot += bodies[i, CB_M] if smp == 0 else 0.0
            o = R0 + N_ROW * i
            q = R1 + N_ROW * i
            p = R2 + N_ROW * i
            piece_state(w[o:o + N_ROW], sx, w[p:p + NS])
            ep += _row_energy(bodies, i, w, p, w[H_GX], w[H_GX + 1], w[H_GX + 2])
            ei += _row_energy(bodies, i, w, q, w[H_GX], w[H_GX + 1], w[H_GX + 2])
            # orientation: the vector part of q_piece (x) conj(q_dense), half the angle
            aw = w[p + S_Q]
            ax = w[p + S_Q + 1]
            ay = w[p + S_Q + 2]
            az = w[p + S_Q + 3]
            bw = w[q + S_Q]
            bx = -w[q + S_Q + 1]
            by = -w[q + S_Q + 2]
            bz = -w[q + S_Q + 3]
            cx, cy, cz = _cross(ax, ay, az, bx, by, bz)
            vx = aw * bx + bw * ax + cx
            vy = aw * by + bw * ay + cy
            vz = aw * bz + bw * az + cz
            ang = 2.0 * math.sqrt(vx * vx + vy * vy + vz * vz)
            dx = 0.0
            dv = 0.0
            dw = 0.0
            for j in range(3):
                dx += (w[p + j] - w[q + j]) ** 2
                dv += (w[p + S_V + j] - w[q + S_V + j]) ** 2
                dw += (w[p + S_W + j] - w[q + S_W + j]) ** 2
            dp = max(dp, (math.sqrt(dx) + L * ang) / (PIECE_LTOL * L),
                     (math.sqrt(dv) + L * math.sqrt(dw)) / (PIECE_VTOL * V))
        de = max(de, abs(ep - ei) / (PIECE_ETOL * max(mtot, 1e-300) * V * V))
    return de, dp


@njit(cache=True, _nrt=False)
def _emit(bodies, w, NY, nc, sa, sb, hp, budget, t0, seg_t, seg_b, seg_s, cnt, ids):
    """Record [sa, sb] (within the current step) as pieces, one row per free sphere each,
    at most ``budget`` rows (``cluster2d._emit``). Returns (s reached, next piece length
    guess, rows written)."""
    nb = bodies.shape[0]
    nf = 0
    for i in range(nb):
        if bodies[i, CB_FIXED] == 0.0:
            nf += 1
    R0 = _rows_off(NY, nc)
    s = sa
    n = 0
    while s < sb and n + nf <= budget and cnt[CNT_SEG] + nf <= seg_t.shape[0]:
        h = min(hp, sb - s)
        last = h == sb - s
        r = 0.0
        for it in range(PIECE_ITER):
            de, dp = _piece_dev(bodies, w, NY, nc, s, h)
            r = max(de, dp)
            if r <= 1.0:
                break
            # energy and velocity deviation ~ h^2, point deviation ~ h^3
            h = h * max(0.1, 0.8 / math.sqrt(r))
            last = False
        for i in range(nb):
            if bodies[i, CB_FIXED] != 0.0:
                continue
            k = cnt[CNT_SEG]
            seg_t[k] = t0 + s
            seg_b[k] = ids[i]
            for j in range(N_ROW):
                seg_s[k, j] = w[R0 + N_ROW * i + j]
            cnt[CNT_SEG] = k + 1
            n += 1
        if r < 0.25:
            hp = h * min(2.0, 0.9 / math.sqrt(max(r, 1e-6)))
        else:
            hp = h
        s = sb if last else s + h
    return s, hp, n


@njit(cache=True, _nrt=False)
def _phase_consistent(c, nk, w, la):
    """The forces just solved (la) consistent with the modes a phase starts in: every
    active ``lam_N >= -FORCE_ARM F``, every sticking force within ``FORCE_ARM F`` of its
    cone (the event functions' own arms: a phase starting beyond them would never see
    its event)."""
    F = w[H_F]
    for k in range(nk):
        mode = c[k, CC_MODE]
        if mode == MODE_LIFT:
            continue
        o = LA_K + k * LK_S
        ln = la[o + LK_LN]
        if not ln >= -FORCE_ARM * F:
            return False
        mu = c[k, CC_MU]
        if mode == MODE_STICK and mu != 0.0:
            tl = math.sqrt(la[o + LK_LT] ** 2 + la[o + LK_LT + 1] ** 2 + la[o + LK_LT + 2] ** 2)
            if tl > mu * ln + FORCE_ARM * F:     # (mu = inf: never)
                return False
    return True


@njit(cache=True, _nrt=False)
def cluster_advance(bodies, contacts, nk, cands, nc, gx, gy, gz, L, t0, t_max, w, la,
                    seg_t, seg_b, seg_s, cnt, ids):
    """Integrate the cluster (state ``bodies``, active ``contacts[:nk]`` in their modes
    ``CC_MODE``, inactive candidates ``cands[:nc]``) from ``t0`` until the first event or
    ``t_max``. The state is projected onto the constraints first. On return ``bodies``
    holds the (projected) state at the returned time and ``contacts[:nk, CC_LAMN /
    CC_TX..]`` the forces there. Returns ``(status CS_*, event CE_*, index, t)``: index the
    contact (CE_LEAVE, CE_SLIP, CE_STOP) or the candidate (CE_GAP). ``CS_REST``: at rest
    (nothing integrated, t = t0).

    Recording (when ``seg_t`` is not empty; ``cluster2d``'s scheme): the motion from ``t0``
    as velocity-interpolating pieces with constant a and alpha (``piece_state``), each
    starting at the integrated state, its length keeping the free spheres' energy within
    ``PIECE_ETOL M V^2``, their centres and orientations (times L) within ``PIECE_LTOL L``
    and velocities within ``PIECE_VTOL V`` of the integrated solution; one row
    float64[N_ROW] per free sphere and piece into ``seg_s[k]``, its start time into
    ``seg_t[k]``, the sphere's id ``ids[i]`` into ``seg_b[k]``, ``k = cnt[CNT_SEG]`` counting
    up. At most ``PIECE_BUDGET`` rows (or the buffer's end) per call: the call then ends
    early with ``CE_NONE`` at the time reached (the caller calls again)."""
    if nk > KMAX:
        return CS_TOO_MANY_CONTACTS, CE_NONE, -1, t0
    nb = bodies.shape[0]
    NY = NS * nb
    _setup(bodies, gx, gy, gz, L, w)
    w[H_T0] = t0
    Y = N_H + B_Y * NY
    Y1 = N_H + B_Y1 * NY
    K = N_H + B_K * NY
    YA = N_H + B_YA * NY
    ne = N_EVK * KMAX + nc
    E0 = N_H + N_BLK * NY                 # event values at the step start
    EF = E0 + ne                          # their floors
    E1 = EF + ne                          # values at the step end
    V = w[H_V]
    S = t_max - t0
    st = _project(bodies, contacts, nk, w, Y, la)
    if st != CS_OK:
        return st, CE_NONE, -1, t0
    if _at_rest(bodies, contacts, nk, w, la):
        _store(bodies, contacts, nk, w, Y, la)
        return CS_REST, CE_NONE, -1, t0
    hmax = MAX_ANGLE * L / V
    h = hmax * CLUSTER_TOL ** 0.2 * 10.0
    w[H_S0] = 0.0
    tt = EVENT_ATOL * L / V
    st = _forces(bodies, contacts, nk, w, Y, la, K)
    if st != CS_OK:
        _store(bodies, contacts, nk, w, Y, la)
        return st, CE_NONE, -1, t0
    if not _phase_consistent(contacts, nk, w, la):
        _store(bodies, contacts, nk, w, Y, la)
        return CS_INCONSISTENT, CE_NONE, -1, t0
    att = 0
    rec = seg_t.shape[0] > 0
    hp = math.inf
    rows = 0
    while True:
        om = 0.0
        for i in range(nb):
            o = Y + NS * i + S_W
            om = max(om, math.sqrt(w[o] ** 2 + w[o + 1] ** 2 + w[o + 2] ** 2))
        hcap = hmax
        if om * hcap > MAX_ANGLE:
            hcap = MAX_ANGLE / om
        h = min(h, hcap, S - w[H_S0])
        if not h > 0.0:
            _store(bodies, contacts, nk, w, Y, la)
            return CS_OK, CE_NONE, -1, t_max
        st, a = _step(bodies, contacts, nk, w, la, NY, h)
        att += a
        if st != CS_OK:
            _forces(bodies, contacts, nk, w, Y, la, N_H + B_YC * NY)
            _store(bodies, contacts, nk, w, Y, la)
            return st, CE_NONE, -1, t0 + w[H_S0]
        if att > MAX_ATTEMPTS:
            _store(bodies, contacts, nk, w, Y, la)
            return CS_TOO_MANY_STEPS, CE_NONE, -1, t0 + w[H_S0]
        s0 = w[H_S0]
        s1 = s0 + w[H_H]
        if s1 > S:
            s1 = S
        # events: values at the step start (floors), then at its end
        _dense(w, NY, s0, YA)
        _events(bodies, contacts, nk, cands, nc, w, la, NY, YA, E0)
        for e in range(ne):
            w[EF + e] = _arm(w, contacts, nk, e, w[E0 + e])
        _dense(w, NY, s1, YA)
        _events(bodies, contacts, nk, cands, nc, w, la, NY, YA, E1)
        best = math.inf
        be = -1
        for e in range(ne):
            if w[E0 + e] == math.inf:
                continue
            if w[E1 + e] - w[EF + e] <= 0.0:
                r = _locate(bodies, contacts, nk, cands, nc, w, la, NY, e, w[EF + e], s0, s1,
                            tt)
                if r < best:
                    best = r
                    be = e
        send = best if be >= 0 else s1
        if rec:
            if hp == math.inf:
                hp = w[H_H]
            sr, hp, nr = _emit(bodies, w, NY, nc, s0, send, hp, PIECE_BUDGET - rows, t0, seg_t,
                               seg_b, seg_s, cnt, ids)
            rows += nr
            if sr < send:
                # the piece budget (or the buffer) is used up inside the step: end there
                _dense(w, NY, sr, Y)
                _project(bodies, contacts, nk, w, Y, la)
                _forces(bodies, contacts, nk, w, Y, la, N_H + B_YC * NY)
                _store(bodies, contacts, nk, w, Y, la)
                return CS_OK, CE_NONE, -1, t0 + sr
        if be >= 0 or s1 >= S:
            send = best if be >= 0 else S
            _dense(w, NY, send, Y)
            _project(bodies, contacts, nk, w, Y, la)
            _forces(bodies, contacts, nk, w, Y, la, N_H + B_YC * NY)
            _store(bodies, contacts, nk, w, Y, la)
            if be < 0:
                return CS_OK, CE_NONE, -1, t_max
            if be >= N_EVK * KMAX:
                return CS_OK, CE_GAP, be - N_EVK * KMAX, t0 + send
            k = be // N_EVK
            if be % N_EVK == 0:
                return CS_OK, CE_LEAVE, k, t0 + send
            if contacts[k, CC_MODE] == MODE_STICK:
                return CS_OK, CE_SLIP, k, t0 + send
            return CS_OK, CE_STOP, k, t0 + send
        # accept: project the step end, restart from it
        st = _project(bodies, contacts, nk, w, Y1, la)
        if st != CS_OK:
            _store(bodies, contacts, nk, w, Y, la)
            return st, CE_NONE, -1, t0 + s0
        for j in range(NY):
            w[Y + j] = w[Y1 + j]
        st = _forces(bodies, contacts, nk, w, Y, la, K)
        if st != CS_OK:
            _store(bodies, contacts, nk, w, Y, la)
            return st, CE_NONE, -1, t0 + s1
        w[H_S0] = s1
        h = w[H_HNEXT]


# ------------------------------------------------------------------ Python-level validation


def validate_cluster3d(bodies, contacts, nk, cands=None, nc=0, L=1.0):
    """Check the tables before a kernel call (plain Python). Raises ValueError naming the
    first problem and what is allowed."""
    import numpy as np
    bodies = np.asarray(bodies)
    if bodies.ndim != 2 or bodies.shape[1] != N_CB or bodies.dtype != np.float64:
        raise ValueError(f"bodies must be float64[nb, {N_CB}], got {bodies.dtype}{bodies.shape}")
    nb = bodies.shape[0]
    if not np.all(np.isfinite(bodies[:, :NS])):
        raise ValueError("bodies: non-finite state (position, quaternion, velocities)")
    for i in range(nb):
        q = bodies[i, CB_QW:CB_QW + 4]
        if abs(np.linalg.norm(q) - 1.0) > 1e-9:
            raise ValueError(f"body {i}: the quaternion must be a unit quaternion "
                             f"(|q| = {np.linalg.norm(q)})")
        if not (bodies[i, CB_R] > 0.0 and np.isfinite(bodies[i, CB_R])):
            raise ValueError(f"body {i}: radius must be positive and finite, got {bodies[i, CB_R]}")
        if bodies[i, CB_FIXED] == 0.0 and not (bodies[i, CB_M] > 0.0 and bodies[i, CB_I] > 0.0
                                                and np.isfinite(bodies[i, CB_M])
                                                and np.isfinite(bodies[i, CB_I])):
            raise ValueError(f"body {i}: mass and moment of inertia must be positive and "
                             f"finite (or CB_FIXED != 0 for a fixed sphere)")
    if not (L > 0.0 and np.isfinite(L)):
        raise ValueError(f"L must be positive and finite, got {L}")
    if nk > KMAX:
        raise ValueError(f"{nk} active contacts: at most KMAX = {KMAX}")
    for name, tab, cnt in (("contact", contacts, nk), ("candidate", cands, nc)):
        if cnt == 0:
            continue
        tab = np.asarray(tab)
        if tab.ndim != 2 or tab.shape[1] != N_CC or tab.shape[0] < cnt or tab.dtype != np.float64:
            raise ValueError(f"{name}s must be float64[>= {cnt}, {N_CC}]")
        for k in range(cnt):
            r = tab[k]
            kind = r[CC_KIND]
            if kind not in (KIND_SPHERE, KIND_PLANE):
                raise ValueError(f"{name} {k}: unknown kind {kind} (KIND_SPHERE = {KIND_SPHERE}"
                                 f" or KIND_PLANE = {KIND_PLANE})")
            a = r[CC_A]
            b = r[CC_B]
            if a != int(a) or not 0 <= a < nb:
                raise ValueError(f"{name} {k}: body A = {a} out of range [0, {nb})")
            if kind == KIND_PLANE:
                if b != -1:
                    raise ValueError(f"{name} {k}: a plane contact has CC_B = -1, got {b}")
                nrm = r[CC_NX:CC_NX + 3]
                if not np.all(np.isfinite(nrm)) or abs(np.linalg.norm(nrm) - 1.0) > 1e-12:
                    raise ValueError(f"{name} {k}: the plane normal CC_NX..CC_NX+2 must be a "
                                     f"unit vector, got {nrm}")
                if not np.isfinite(r[CC_D]):
                    raise ValueError(f"{name} {k}: the plane offset CC_D must be finite")
            elif b != int(b) or not 0 <= b < nb or b == a:
                raise ValueError(f"{name} {k}: body B = {b} out of range [0, {nb}) or equal to A")
            if not (r[CC_MU] >= 0.0):
                raise ValueError(f"{name} {k}: mu must be >= 0 (inf: never slips), got "
                                 f"{r[CC_MU]}")
            if name == "contact":
                if r[CC_MODE] not in (MODE_STICK, MODE_SLIP, MODE_LIFT):
                    raise ValueError(f"contact {k}: unknown mode {r[CC_MODE]} (MODE_STICK, "
                                     f"MODE_SLIP or MODE_LIFT)")
                if r[CC_MU] == math.inf and r[CC_MODE] == MODE_SLIP:
                    raise ValueError(f"contact {k}: a contact with mu = inf cannot slip")
            fb = kind == KIND_PLANE or bodies[int(b), CB_FIXED] != 0.0
            if bodies[int(a), CB_FIXED] != 0.0 and fb:
                raise ValueError(f"{name} {k}: both sides fixed")
