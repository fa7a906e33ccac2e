"""Persistent contact between several 2D bodies (a *cluster*): bodies held together by a
set of active unilateral contacts with Coulomb friction, integrated in maximal
coordinates with error control, projection onto the constraints and event location
(issue 16 item 2, first piece: the standalone kernel a later session wires into
``stepper2d`` as a new persistent mode; the integrated-mode house style is ``pivot2d``).

Model (Newton-Euler with unilateral contacts and Coulomb friction in maximal
coordinates; Pfeiffer & Glocker, *Multibody Dynamics with Unilateral Contacts*, 1996,
ch. 5-6; Haug, *Computer-Aided Kinematics and Dynamics of Mechanical Systems*, 1989,
ch. 11 for the acceleration form of the constraints; Glocker, Multibody Syst. Dyn. 2013
for the contact kinematics). Conventions: DESIGN §3.

Bodies ``i`` (rows of ``bodies``, columns ``CB_*``): state ``(x, y, angle, vx, vy, omega)``
(the ``flight2d`` names ``X ... OMEGA``), mass ``m``, moment ``I`` about the centre of mass.
A *fixed* body (``CB_FIXED != 0``) has infinite mass: it keeps its velocity (a support at
rest, or moving uniformly) and takes any force. Gravity ``g = (gx, gy)`` acts on the others.
``J`` is the quarter turn ``J r = (-r_y, r_x)`` (``omega x r`` in 2D); ``a x b = a_x b_y -
a_y b_x``. The velocity of the material point of body X at the world point p is
``v_X(p) = v_X + omega_X J (p - x_X)``, its acceleration
``a_X(p) = a_X + alpha_X J (p - x_X) - omega_X^2 (p - x_X)``.

Contacts ``k`` (rows of ``contacts``, columns ``CC_*``) between body A and body B, or
between body A and a fixed plane ``n . q >= d`` (``CC_B = -1``). Each has a point feature
on A: the body-frame point ``pA`` with radius ``rA`` (a disk centre, a capsule end centre,
a polygon vertex with ``rA = 0``); its world centre ``cA = x_A + R(angle_A) pA``,
``rhoA = cA - x_A``, ``dcA/dt = v_A + omega_A J rhoA``. The normal n points from B into A
and ``t = (n_y, -n_x)`` (DESIGN §3). Kinds (``CC_KIND``):

* ``KIND_ROUND`` (round-round): a point feature ``pB, rB`` on B. ``D = cA - cB``,
  ``g = |D| - rA - rB``, ``n = D / |D|``. ``dg/dt = n . dD/dt``, ``dn/dt = (t . dD/dt) t / |D|``,
  so ``g'' = n . (d2cA/dt2 - d2cB/dt2) + (t . dD/dt)^2 / |D|`` (the tangential part of the
  relative velocity of the centres, squared, over the distance).
* ``KIND_FACE`` (point-face): a flat face of B, the line through the material point
  ``fB = x_B + R(angle_B) pB`` with the outward unit normal ``n = R(angle_B) nB`` (``nB`` in
  ``CC_NX, CC_NY``, body frame), offset by B's radius ``rB`` (a capsule side; 0 for a
  polygon face). ``d = cA - fB``, ``g = n . d - rA - rB``, ``dn/dt = omega_B J n``,
  ``dg/dt = n . dd/dt + omega_B (J n) . d``,
  ``g'' = n . d2d/dt2 + alpha_B (J n) . d - omega_B^2 n . d + 2 omega_B (J n) . dd/dt``.
  The mirror (a point of B against a face of A) is the same contact with A and B swapped:
  the contact is then listed with the point's body as A (its normal is the face's
  outward normal, from the face body into the point body, as DESIGN §3 asks).
* ``KIND_PLANE`` (feature-plane): ``n = (CC_NX, CC_NY)`` world, unit; ``g = n . cA - d - rA``
  with ``d = CC_D``; ``g'' = n . d2cA/dt2``.

An ellipse's boundary (``CC_AEA, CC_AEB`` for A, ``CC_BEA, CC_BEB`` for B in a round-round
row) is not a material circle: its contact point moves along the curve. At every state the
kernel replaces it by its osculating circle at the contact (``feature_circles``: centre of
curvature as ``pA`` or ``pB``, radius of curvature as ``rA`` or ``rB``), found from the
known normal (plane, face) or by the common-normal iteration (round-round). The circle has
the ellipse's support function, and its first two derivatives in the normal's angle, so
the gap, ``JN`` and ``g''`` below are the ellipse's exactly (the gap of two convex bodies is
a maximum over the axis of their support functions, so by the envelope theorem its first
two derivatives in the poses need only those; ``dp/dt`` too, so ``bT`` is exact). An
ellipse's normal cone is the whole circle: no feature event.

The contact point is ``p = cA - rA n`` (on A's surface; at ``g = 0`` also on B's). Its arms
are ``aA = p - x_A``, ``aB = p - x_B``. For every kind the gap rate is exactly
``dg/dt = n . (v_A(p) - v_B(p)) = JN . dq/dt`` with the row ``JN = (n, aA x n | -n, -aB x n)``
(the terms of ``dn/dt`` and of ``p - cA || n`` drop out; e.g. point-face:
``n . v_B(p) = n . dfB/dt - omega_B (J n) . (p - fB)``), so ``JN`` is the gradient of ``g``
(the Gauss-Newton projection below is Newton's method) and the normal force ``lam_N n`` at
p is ``JN^T lam_N`` (virtual work). With ``q''`` the accelerations,
``g'' = JN q'' + bN``, where ``JN q''`` is ``n . (a_A(p) - a_B(p))`` without its centripetal
parts, and (``rhoB = cB - x_B`` or ``fB - x_B``, ``w = omega``):

* round-round: ``bN = -wA^2 n . rhoA + wB^2 n . rhoB + (t . dD/dt)^2 / |D|``;
* point-face:  ``bN = n . (-wA^2 rhoA + wB^2 rhoB) - wB^2 n . d + 2 wB (J n) . dd/dt``;
* plane:       ``bN = -wA^2 n . rhoA``.

At ``g = 0`` these are the forms of the issue: point-face
``g'' = n . (a_A(p) - a_B(p)) + 2 wB (J n) . (v_A(p) - v_B(p)) - rA (wA - wB)^2`` (the last
term, zero for a vertex, is the rounded feature's: ``n . a_A(p) = n . d2cA/dt2 + wA^2 rA``),
round-round ``g'' = n . (a_cA - a_cB) + |v_rel,T|^2 / |cA - cB|``. The kernel uses the
general forms above (valid at any g), so its ``g''`` is the exact second derivative of the
exact gap (tested against finite differences for every kind, ``cluster_rates``).

Tangential: the slip ``vT = t . (v_A(p) - v_B(p)) = JT . dq/dt`` with
``JT = (t, aA x t | -t, -aB x t)``. Its rate ``dvT/dt = JT q'' + bT`` with
``bT = (dt/dt) . (v_A(p) - v_B(p)) + t . J (wA (dp/dt - v_A) - wB (dp/dt - v_B))``,
``dt/dt = (dn_y/dt, -dn_x/dt)``, ``dp/dt = dcA/dt - rA dn/dt``. A STICK contact keeps
``dvT/dt = 0`` (the rolling constraint is a velocity constraint: not projected at
position level).

Forces: ``lam_N n + lam_T t`` on A at p, the opposite on B. Each active contact's mode
(``CC_MODE``) is fixed for the phase: ``MODE_STICK`` (unknown ``lam_T``, equation
``dvT/dt = 0``), ``MODE_SLIP_POS`` / ``MODE_SLIP_NEG`` (sliding along ``sig t``,
``sig = +-1``: ``lam_T = -mu sig lam_N``, the force column ``JN^T - mu sig JT^T``), and
``MODE_LIFT`` (inactive; used by the mode selection). ``mu = 0`` is frictionless in any
mode (``lam_T = 0``); ``mu = inf`` sticks for ever (a perfectly rough contact). The
unknowns ``lam`` (normal for every active contact, tangential for the sticking ones, at
most ``2 KMAX``) solve ``A lam = r``, ``A_ij = row_i M^-1 col_j``,
``r_i = -(row_i q''_free + b_i)`` with ``q''_free`` gravity (``_forces``). ``A`` is solved by a
one-sided Jacobi SVD (Hestenes) and its pseudo-inverse: redundant contacts (two sticking
points on one face: identical tangential rows) get the minimum-norm split of the forces
(equal tangential forces); the accelerations are the unique ones. A system whose
residual is not at round-off after that (contradictory constraints, e.g. two fixed bodies
turning against each other) is ``CS_SINGULAR``; a sliding contact whose own effective
normal mass ``JN M^-1 (JN - mu sig JT)^T`` is not positive is ``CS_PAINLEVE`` (the 2D
Painleve criterion ``W_NN - mu sig W_NT <= 0``). Never NaN.

Integration: Dormand-Prince RK5(4) with dense output (``dopri5``) on the ``6 n`` maximal
coordinates, component scales ``(L, L, 1 rad, V, V, V/L)`` per body (``L`` the cluster's size,
given by the caller; ``V = max_i (|v_i| + |omega_i| L) + sqrt(|g| L)`` at the start of the
call) and tolerance ``CLUSTER_TOL``. After every accepted step the state is projected back
onto the active constraints (``_project``; mass-weighted least squares, the metric
``M = diag(m, m, I)``): the positions by Gauss-Newton ``dq = M^-1 JN^T (JN M^-1 JN^T)^+ (-g)``
until ``|g| <= PROJ_LTOL L`` (at most ``PROJ_ITER`` iterations: round-off ends it), then the
velocities ``dv = -M^-1 J^T (J M^-1 J^T)^+ J v`` onto ``dg/dt = 0`` (every contact) and ``vT = 0``
(sticking contacts), twice. The velocity projection is an M-orthogonal projection: it
only removes kinetic energy (of the order of the squared drift).

Events (functions that must stay positive; the phase ends at the first root, located on
the dense output by secant/bisection to ``EVENT_RTOL |t| + EVENT_ATOL L / V``, as
``pivot2d._locate``): ``lam_N`` of an active contact reaching 0 (``CE_LEAVE``), a sticking
force reaching its cone ``mu lam_N - |lam_T| = 0`` (``CE_SLIP``), a sliding contact's slip
``sig vT`` reaching 0 (``CE_STOP``: it sticks or reverses; not for ``mu = 0``) and the gap of
each inactive candidate contact (table ``cands``, same columns, same kinds) reaching 0
(``CE_GAP``: an impact), and the contact point leaving a feature's range (``CE_FEATURE``,
index ``4 k + FR_*``): a polygon vertex's or a capsule end's normal cone (``CC_ALO,
CC_AHI`` for A's feature, ``CC_BLO, CC_BHI`` for B's in a round-round contact: the outward
normal of the feature at the contact, ``-n`` for A and ``n`` for B, must stay within those
body-frame angles, a cone narrower than pi; margins are the sines of the angles to the
bounds), and a face's extent (``CC_BLO, CC_BHI`` of a point-face contact: the coordinate
``s = t . (p - fB)`` of the contact point along the face, m). At a feature event the
stepper swaps the contact for the one on the next feature (a face's end: the vertex,
round-round; a vertex cone's bound: the adjacent face, point-face). A function starting
below its arm (``FORCE_ARM F``, ``SLIP_ARM V``, ``GAP_ARM L``; a cone margin ``GAP_ARM``)
fires below ``-arm`` instead, or below ``start - arm`` when it starts below ``-arm`` (a phase
that starts on an event's root does not end at once; a fixed floor, not one taken again
from each step's start, so that a function falling slowly over many short passes fires). Force and slip
events are returned on the far side of the root (the new mode is consistent there), gaps
on the near side (the feature not yet through). Events are sampled at step ends, and
steps turn no body by more than ``MAX_ANGLE``: two roots of one function within one step
are not seen (a stated limitation, as in ``pivot2d`` and ``pivot3d``).

Mode selection (``cluster_select_modes``, at the start of a phase, with every contact at
``g = dg/dt = 0``): an enumeration of the Coulomb LCP's modes, for at most ``KSEL_MAX``
contacts (beyond, up to ``KMAX``, a local search: the combinations that change at most
``DSEL_MAX`` contacts from the first option of each, ``_search_near``; a stack of five boxes
at rest is its base combination, every contact sticking), in a fixed order: each contact's options are, when it slips (``|vT| > STICK_VTOL
V``), slip along its slip then lift-off; when it does not, stick, slip +t, slip -t,
lift-off (``mu = 0``: frictionless contact, lift-off); the combinations run
lexicographically with the first contact's option varying slowest (after an event:
ordered first by the number of contacts whose mode changes), and the first
consistent one is returned (a sliding contact whose slip its current mode stops within
``STOP_RTOL sqrt(L / |g|)`` counts as not slipping: near-simultaneous stops are one):
every active ``lam_N >= -FORCE_TOL F``, every sticking force
inside its cone (``|lam_T| <= mu lam_N + FORCE_TOL F``), every contact that starts to slip
from ``vT = 0`` accelerating along its slip (``sig dvT/dt > ACC_TOL |g|``), every lifted
contact not approaching (``g'' >= -ACC_TOL |g|``), with ``F = sum m |g|``. None:
``CS_NO_MODE`` (a Painleve-type inconsistency; the stepper's impact without collision).
So stick is preferred whenever it is consistent. The enumeration is blind to the trend:
at the point of a stick-slip or slip-stop event both modes are consistent to the
tolerances (the force on the cone, or the slip and its acceleration zero), and it would
keep the old one; after an event, ``cluster_after_event`` takes the mode the trend calls
for (slip opposite the sticking force; stick, or reversed slip, after a stop).

Rest (``cluster_advance``): when every free body's ``|v| + |omega| L <= REST_VTOL
sqrt(|g| L)``, every active contact is sticking (or frictionless) with ``lam_N >
FORCE_TOL F`` and strictly inside its cone, and every acceleration is below
``REST_ATOL |g|`` (``|a| + |alpha| L``), the cluster is at rest: ``CS_REST`` is returned
with no integration (the stepper freezes it). A fixed body that moves (a conveyor) is
never at rest.

Energy: normal forces do no work (``dg/dt = 0``), sticking forces do none (``vT = 0``),
sliding forces work ``lam_T vT = -mu lam_N |vT| <= 0``: a frictionless or rolling phase
conserves energy, friction never creates it (tested).

Arrays (no allocation in the hot path; sizes from ``work_size``):

* ``bodies`` float64[nb, N_CB]; the state columns are updated in place by
  ``cluster_advance`` and ``cluster_project``;
* ``contacts`` float64[>= nk, N_CC] (active), ``cands`` float64[>= nc, N_CC] (inactive
  candidates; their ``CC_MODE`` is ignored); the force columns ``CC_LAMN``, ``CC_LAMT`` of the
  active ones are written (forces at the returned state). A contact in ``MODE_LIFT`` is
  ignored by ``cluster_advance`` (no force, no event): the stepper moves it to the
  candidates;
* ``w`` float64[work_size(nb, nc)]: the integrator (header ``H_*``, blocks of ``6 nb``, the
  event values, three piece rows per body);
* ``la`` float64[N_LA]: the contact rows and the linear algebra (fixed size: ``KMAX``);
* recording (``cluster_advance``): ``seg_t`` float64[m], ``seg_b`` int64[m], ``seg_s``
  float64[m, 9], ``cnt`` int64[>= 2] (``cnt[CNT_SEG]`` rows used), ``ids`` int64[nb] (the
  stepper's body index of each row of ``bodies``); empty ``seg_t``: no recording.

Not here: entering the mode, moving a lifted contact to the candidates and the impact at
``CE_GAP`` (``stepper2d``); the tables built from the scene's shapes and the switch of a
contact at ``CE_FEATURE`` (``cluster2d_rows``), and a complete mode selection for more
than ``KSEL_MAX`` contacts (an LCP pivoting method instead of the local search).
"""
import math

from numba import njit

from .cache_guard import guard

# flush stale compiled callers before any kernel module below is imported (cache_guard)
guard(__name__, __file__)

from .dopri5 import MAX_TRIES, dense_out, dopri5_step
from .flight2d import ANGLE, OMEGA, VX, VY, X, Y
from .minnorm import minnorm_solve

# ---- bodies table (float64[nb, N_CB]) ------------------------------------------------------
CB_X = X            # centre of mass x (m)
CB_Y = Y            # centre of mass y (m)
CB_ANGLE = ANGLE    # angle (rad)
CB_VX = VX          # velocity (m/s)
CB_VY = VY
CB_OMEGA = OMEGA    # angular velocity (rad/s)
CB_M = 6            # mass (kg; ignored for a fixed body)
CB_I = 7            # moment of inertia about the centre of mass (kg m^2)
CB_FIXED = 8        # != 0: infinite mass (keeps its velocity, takes any force)
N_CB = 9
NS = 6              # state components per body (x, y, angle, vx, vy, omega)

# ---- contacts table (float64[nk, N_CC]; the same columns for candidates) --------------------
CC_KIND = 0         # KIND_ROUND, KIND_FACE or KIND_PLANE
CC_A = 1            # body A (the point feature)
CC_B = 2            # body B (a point feature or the face); -1: a fixed plane
CC_PAX = 3          # A's point feature, body frame (m)
CC_PAY = 4
CC_RA = 5           # its radius (m)
CC_PBX = 6          # B's point feature (KIND_ROUND) or a point of B's face line (KIND_FACE),
CC_PBY = 7          # body frame (m)
CC_RB = 8           # B's radius (m): the point feature's, or the face's offset (capsule)
CC_NX = 9           # KIND_FACE: the face's outward unit normal, B's body frame;
CC_NY = 10          # KIND_PLANE: the plane's unit normal, world
CC_D = 11           # KIND_PLANE: plane offset d (m): n . q >= d
CC_MU = 12          # friction coefficient (0: frictionless; inf: never slips)
CC_MODE = 13        # MODE_* (active contacts)
CC_LAMN = 14        # output: normal force on A (N)
CC_LAMT = 15        # output: tangential force on A along t (N)
CC_ALO = 16         # A's feature's normal cone: its outward normal at the contact, -n, must
CC_AHI = 17         # stay within the angles [ALO, AHI] of A's body frame (a polygon vertex:
#                     between its faces' normals; -inf, inf: any, e.g. a disk)
CC_BLO = 18         # KIND_ROUND: B's feature's normal cone (n within the angles [BLO, BHI] of
CC_BHI = 19         # B's frame); KIND_FACE: the face's extent, the contact point's coordinate
#                     s = t . (p - fB) within [BLO, BHI] (m); -inf, inf: unbounded
CC_AEA = 20         # A's feature is an ellipse when > 0: its semi-axes on A's body x axis
CC_AEB = 21         # (AEA) and y axis (AEB), centred on A's origin (m); CC_PAX, CC_PAY, CC_RA
#                     are then ignored (its osculating circle at the contact: module docstring)
CC_BEA = 22         # the same for B's feature (KIND_ROUND only)
CC_BEB = 23
CC_PSI = 24         # KIND_ROUND with an ellipse: the world angle of n at the last evaluation
#                     (rad; the warm start of the common-normal iteration, written by _kin)
N_CC = 25

KIND_ROUND = 0
KIND_FACE = 1
KIND_PLANE = 2

MODE_STICK = 0
MODE_SLIP_POS = 1   # sliding along +t (sig = +1): lam_T = -mu lam_N
MODE_SLIP_NEG = -1  # sliding along -t
MODE_LIFT = 2       # not active (mode selection's lift-off)

# ---- sizes --------------------------------------------------------------------------------
KMAX = 24           # active contacts at most (a stack of five boxes: 10; a chain of eight
#                     dominoes leaning on each other: about 20)
NMAX = 2 * KMAX     # force unknowns at most
KSEL_MAX = 6        # contacts the full mode enumeration handles (4^6 combinations)
DSEL_MAX = 2        # beyond KSEL_MAX: combinations that change at most DSEL_MAX (1 or 2) contacts
#                     from the first option of each (module docstring, "Mode selection")

# ---- status codes -------------------------------------------------------------------------
CS_OK = 0
CS_REST = 1             # at rest: nothing integrated
CS_SINGULAR = 2         # the force system has no solution (contradictory constraints)
CS_PAINLEVE = 3         # a sliding contact's effective normal mass <= 0
CS_TOO_MANY_STEPS = 4   # MAX_ATTEMPTS step attempts, or a step that cannot be taken
CS_NO_MODE = 5          # mode selection: no consistent stick/slip/lift-off combination
CS_TOO_MANY_CONTACTS = 6  # more than KMAX active
CS_INCONSISTENT = 7     # cluster_advance called with modes whose forces are not consistent
#                         at the start (a pulling normal force, a sticking force outside its
#                         cone, friction along the slip): integrating them could create
#                         energy; the caller's mode choice is wrong (a bug, never physics)

# ---- event kinds --------------------------------------------------------------------------
CE_NONE = 0         # t_max reached (or a failure: see the status)
CE_LEAVE = 1        # lam_N of active contact `index` reaches 0
CE_SLIP = 2         # the sticking force of contact `index` reaches its cone
CE_STOP = 3         # the slip of sliding contact `index` reaches 0
CE_GAP = 4          # the gap of candidate `index` reaches 0
CE_FEATURE = 5      # the contact point leaves a feature's range: index 4 k + FR_* (contact k)

# which end of a feature range (CE_FEATURE index = 4 k + FR_*)
FR_ALO = 0          # A's normal cone, lower angle
FR_AHI = 1          # A's normal cone, upper angle
FR_BLO = 2          # B's normal cone (KIND_ROUND) or the face's extent (KIND_FACE), lower
FR_BHI = 3          # upper
N_EVK = 6           # event functions per active contact: lam_N, cone/slip, 4 ranges

# ---- tolerances (named; dimensionless, relative to the scales stated) ---------------------
CLUSTER_TOL = 1e-12     # RK error per step, relative to the scales (L, L, 1, V, V, V/L)
MAX_ANGLE = 0.05        # rad turned by any body (or sqrt(|g|/L) time) per step at most
PROJ_LTOL = 1e-15       # position projection stops at |g_k| <= PROJ_LTOL L (round-off)
PROJ_ITER = 4           # Gauss-Newton iterations of the position projection at most
SVD_RTOL = 1e-10        # singular values below SVD_RTOL sigma_max are redundancy (zero)
SVD_SWEEPS = 40         # Jacobi sweeps at most (quadratic convergence: ~6-8 used)
SOLVE_RTOL = 1e-8       # a solve whose residual exceeds SOLVE_RTOL (|A| |x| + |r|) plus
#                         SOLVE_RTOL times the scale of r (forces: max|A| F; projections:
#                         L, V) has contradictory equations (CS_SINGULAR)
PAINLEVE_RTOL = 1e-12   # slip's JN M^-1 (JN - mu sig JT) <= PAINLEVE_RTOL JN M^-1 JN: Painleve
FORCE_TOL = 1e-10       # force consistency of a mode / rest, relative to F = sum m |g|
ACC_TOL = 1e-10         # acceleration consistency of a mode, relative to |g|
STICK_VTOL = 1e-9       # a slip |vT| <= STICK_VTOL V is zero (mode selection)
SPLIT_RTOL = 1e-12      # tangential rows equal to SPLIT_RTOL (1 + L) in every entry share
#                         their friction (_split_friction; the entries are round-off apart)
STOP_RTOL = 1e-6        # a slip that its current mode's deceleration stops within
#                         STOP_RTOL T (T = sqrt(L / |g|), or L / V without gravity) stops
#                         now for the mode selection (its residual slip, <= |dvT/dt|
#                         STOP_RTOL T, is removed by the velocity projection: kinetic energy
#                         only taken away): the stops of a symmetric cluster, apart by the
#                         round-off of their event times, are one transition
REST_VTOL = 1e-10       # rest: |v| + |omega| L <= REST_VTOL sqrt(|g| L) for every body
REST_ATOL = 1e-10       # rest: |a| + |alpha| L <= REST_ATOL |g| for every body
FORCE_ARM = 1e-9        # force events starting below FORCE_ARM F are armed (module doc)
SLIP_ARM = 1e-12        # slip events armed below SLIP_ARM V
GAP_ARM = 1e-12         # gap events armed below GAP_ARM L
EVENT_RTOL = 4e-16      # event time located to EVENT_RTOL |t| + EVENT_ATOL L / V
EVENT_ATOL = 1e-15
EVENT_ITER = 200        # secant/bisection iterations locating an event
MAX_ATTEMPTS = 200_000  # RK step attempts per call at most (CS_TOO_MANY_STEPS)
PIECE_ETOL = 1e-11      # energy deviation of a recorded piece, relative to the energy scale
#                         E (H_E: kinetic energy at the call's start plus M |g| L; M V^2,
#                         V a bound of every point's speed, over-states a spinning body's
#                         energy 20-1000 times): pivot2d's PIECE_ETOL_CURVED, not its 1e-13,
#                         for the same reason: a cluster may stay held for a long time
#                         (rocking, rolling) and the pieces grow as PIECE_ETOL^-1/2 (a box
#                         rocking at 0.5 rad/s: pieces of ~2e-6 s at 1e-13, ~2e-5 s at 1e-11)
PIECE_LTOL = 1e-10      # point deviation of a recorded piece, relative to L
PIECE_VTOL = 1e-9       # point velocity deviation of a recorded piece, relative to V
PIECE_BUDGET = 512      # recorded rows per call of cluster_advance at most (buffer margin)
PIECE_ITER = 60         # shrinks of one piece at most (then it is accepted as is)
CNT_SEG = 1             # cnt[CNT_SEG]: rows recorded in seg_* (stepper2d's counter layout)

# ---- workspace w: header, then blocks of 6 nb -----------------------------------------------
H_TOL = 0           # RK tolerance
H_H = 1             # accepted step (s)
H_HNEXT = 2         # next step (s)
H_HMAX = 3          # largest step (s)
H_S0 = 4            # step start (s from t0)
H_L = 5             # length scale L (m)
H_V = 6             # velocity scale V (m/s)
H_F = 7             # force scale F (N)
H_GX = 8            # gravity (m/s^2)
H_GY = 9
H_G = 10            # |g| (m/s^2)
H_T0 = 11           # t0 (s)
H_M = 12            # free mass M (kg)
H_E = 13            # energy scale E (J): the free bodies' kinetic energy at the call's start
#                     plus M |g| L (M V^2 when both are zero)
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
N_ROWS = 3          # then three state rows (9 per body) for the recorded pieces

# ---- la: per-contact rows, then the linear algebra ----------------------------------------
LK_NA = 0           # JN entries of A (3) and B (3)
LK_NB = 3
LK_TA = 6           # JT entries of A (3) and B (3)
LK_TB = 9
LK_BN = 12          # bN (m/s^2)
LK_BT = 13          # bT (m/s^2)
LK_G = 14           # gap (m)
LK_GD = 15          # gap rate (m/s)
LK_VT = 16          # slip vT (m/s)
LK_IN = 17          # index of the unknown lam_N (-1: lifted)
LK_IT = 18          # index of the unknown lam_T (-1: none)
LK_LN = 19          # lam_N (N)
LK_LT = 20          # lam_T (N)
LK_GDD = 21         # g'' at the solved accelerations (m/s^2)
LK_AT = 22          # dvT/dt at the solved accelerations (m/s^2)
LK_PX = 23          # contact point p (m)
LK_PY = 24
LK_GRP = 25         # first contact of its group of interchangeable sticking rows (-1: none)
LK_S = 26           # stride
LA_K = 0
LA_A = LA_K + (KMAX + 1) * LK_S    # one extra slot: a candidate's rows
LA_U = LA_A + NMAX * NMAX
LA_V = LA_U + NMAX * NMAX
LA_R = LA_V + NMAX * NMAX
LA_X = LA_R + NMAX
LA_EQ = LA_X + NMAX         # contact of each unknown (float)
LA_ET = LA_EQ + NMAX        # 0: normal unknown, 1: tangential
N_LA = LA_ET + NMAX


@njit(cache=True, _nrt=False)
def work_size(nb, nc):
    """Length of ``w`` for ``nb`` bodies and ``nc`` candidates."""
    return N_H + N_BLK * NS * nb + N_EVW * (N_EVK * KMAX + nc) + N_ROWS * 9 * nb


# ------------------------------------------------------------------ kinematics

PSI_TOL = 1e-15     # rad: the common-normal iteration of an ellipse stops below this step
PSI_ITER = 8        # its iterations at most (quadratic from a warm start: 1-3 are used; the
#                     last iterate is kept: its error is the round-off of D's direction)


@njit(cache=True, _nrt=False, inline="always")
def osculating(ea, eb, th, ux, uy):
    """The osculating circle of the ellipse ``x^2 / ea^2 + y^2 / eb^2 = 1`` (body frame,
    body angle th, m) where its outward unit normal is the world vector u: its centre (body
    frame, m) and radius (m). With ``u' = R(-th) u`` and the support function
    ``h = sqrt(ea^2 u'_x^2 + eb^2 u'_y^2)``, the point is ``p = (ea^2 u'_x, eb^2 u'_y) / h``,
    the radius of curvature ``rho = h + h'' = ea^2 eb^2 / h^3`` (``pivot2d.ellipse_support3``)
    and the centre ``p - rho u'``."""
    c = math.cos(th)
    s = math.sin(th)
    u0 = c * ux + s * uy
    u1 = -s * ux + c * uy
    a2 = ea * ea
    b2 = eb * eb
    h = math.sqrt(a2 * u0 * u0 + b2 * u1 * u1)
    rho = a2 * b2 / (h * h * h)
    return a2 * u0 / h - rho * u0, b2 * u1 / h - rho * u1, rho


@njit(cache=True, _nrt=False)
def feature_circles(c, k, xa, ya, tha, xb, yb, thb):
    """The point features of row k of table c as circles: ``(pAx, pAy, rA, pBx, pBy,
    rB)``, centres in their bodies' frames (m), at the poses (xa, ya, tha) of A and
    (xb, yb, thb) of B (unused for a plane). A round feature is the table's; an ellipse
    (``CC_AEA > 0``, ``CC_BEA > 0``) is its osculating circle at the contact (``osculating``),
    where its outward normal is ``-n`` (A) or ``n`` (B). For a plane or a face n is known;
    for a round-round row it is the common normal, the fixed point of ``psi <- angle(D)``
    (``D = cA - cB``, the circles' centres at the normal angle psi): the centres of curvature
    move along n as psi turns (the evolute is normal to the curve), so the map's derivative
    is 0 at its fixed point and the iteration converges quadratically from ``CC_PSI``, which
    is rewritten. The circle has the ellipse's support function to second order in the
    normal's angle, so the gap, its gradient JN and its second derivative (``bN``) of the
    row are the ellipse's exactly (module docstring)."""
    pax = c[k, CC_PAX]
    pay = c[k, CC_PAY]
    rA = c[k, CC_RA]
    pbx = c[k, CC_PBX]
    pby = c[k, CC_PBY]
    rB = c[k, CC_RB]
    eaa = c[k, CC_AEA]
    eab = c[k, CC_BEA]
    if eaa == 0.0 and eab == 0.0:
        return pax, pay, rA, pbx, pby, rB
    kind = c[k, CC_KIND]
    if kind == KIND_PLANE:
        pax, pay, rA = osculating(eaa, c[k, CC_AEB], tha, -c[k, CC_NX], -c[k, CC_NY])
        return pax, pay, rA, pbx, pby, rB
    cb = math.cos(thb)
    sb = math.sin(thb)
    if kind == KIND_FACE:
        nx = cb * c[k, CC_NX] - sb * c[k, CC_NY]
        ny = sb * c[k, CC_NX] + cb * c[k, CC_NY]
        pax, pay, rA = osculating(eaa, c[k, CC_AEB], tha, -nx, -ny)
        return pax, pay, rA, pbx, pby, rB
    ca = math.cos(tha)
    sa = math.sin(tha)
    psi = c[k, CC_PSI]
    for _ in range(PSI_ITER):
        nx = math.cos(psi)
        ny = math.sin(psi)
        if eaa > 0.0:
            pax, pay, rA = osculating(eaa, c[k, CC_AEB], tha, -nx, -ny)
        if eab > 0.0:
            pbx, pby, rB = osculating(eab, c[k, CC_BEB], thb, nx, ny)
        dx = xa + ca * pax - sa * pay - xb - cb * pbx + sb * pby
        dy = ya + sa * pax + ca * pay - yb - sb * pbx - cb * pby
        p2 = math.atan2(dy, dx)
        d = p2 - psi
        d -= 2.0 * math.pi * math.floor((d + math.pi) / (2.0 * math.pi))
        if abs(d) <= PSI_TOL:
            break
        psi = p2
    c[k, CC_PSI] = psi
    return pax, pay, rA, pbx, pby, rB


@njit(cache=True, _nrt=False)
def _kin(c, k, w, yo):
    """Kinematics of contact row k of table c at the state w[yo:yo + 6 nb] (module
    docstring). Returns (g, dg/dt, nx, ny, aAx, aAy, aBx, aBy, bN, vT, bT)."""
    kind = int(c[k, CC_KIND])
    a = int(c[k, CC_A])
    b = int(c[k, CC_B])
    oa = yo + NS * a
    xa = w[oa]
    ya = w[oa + 1]
    tha = w[oa + 2]
    vxa = w[oa + 3]
    vya = w[oa + 4]
    wa = w[oa + 5]
    xb = 0.0
    yb = 0.0
    thb = 0.0
    vxb = 0.0
    vyb = 0.0
    wb = 0.0
    if kind != KIND_PLANE:
        ob = yo + NS * b
        xb = w[ob]
        yb = w[ob + 1]
        thb = w[ob + 2]
        vxb = w[ob + 3]
        vyb = w[ob + 4]
        wb = w[ob + 5]
    pax, pay, rA, pbx, pby, rB = feature_circles(c, k, xa, ya, tha, xb, yb, thb)
    ca = math.cos(tha)
    sa = math.sin(tha)
    rax = ca * pax - sa * pay                          # rhoA = cA - xA
    ray = sa * pax + ca * pay
    cax = xa + rax
    cay = ya + ray
    cdax = vxa - wa * ray                              # dcA/dt
    cday = vya + wa * rax
    if kind == KIND_PLANE:
        nx = c[k, CC_NX]
        ny = c[k, CC_NY]
        g = nx * cax + ny * cay - c[k, CC_D] - rA
        gd = nx * cdax + ny * cday
        ndx = 0.0
        ndy = 0.0
        bn = -wa * wa * (nx * rax + ny * ray)
    else:
        cb = math.cos(thb)
        sb = math.sin(thb)
        rbx = cb * pbx - sb * pby                      # rhoB = cB - xB (or fB - xB)
        rby = sb * pbx + cb * pby
        dx = xa + rax - xb - rbx                       # D = cA - cB (or d = cA - fB)
        dy = ya + ray - yb - rby
        ddx = cdax - (vxb - wb * rby)                  # dD/dt
        ddy = cday - (vyb + wb * rbx)
        if kind == KIND_ROUND:
            dist = math.hypot(dx, dy)
            nx = dx / dist
            ny = dy / dist
            g = dist - rA - rB
            gd = nx * ddx + ny * ddy
            dT = ny * ddx - nx * ddy                   # t . dD/dt
            ndx = dT / dist * ny                       # dn/dt = (t . dD/dt) t / |D|
            ndy = -dT / dist * nx
            bn = (-wa * wa * (nx * rax + ny * ray) + wb * wb * (nx * rbx + ny * rby)
                  + dT * dT / dist)
        else:
            nx = cb * c[k, CC_NX] - sb * c[k, CC_NY]
            ny = sb * c[k, CC_NX] + cb * c[k, CC_NY]
            nd = nx * dx + ny * dy
            g = nd - rA - rB
            ndx = -wb * ny                             # dn/dt = wB J n
            ndy = wb * nx
            gd = nx * ddx + ny * ddy + ndx * dx + ndy * dy
            bn = (nx * (-wa * wa * rax + wb * wb * rbx) + ny * (-wa * wa * ray + wb * wb * rby)
                  - wb * wb * nd + 2.0 * wb * (-ny * ddx + nx * ddy))
    px = cax - rA * nx                                 # contact point and its rate
    py = cay - rA * ny
    pdx = cdax - rA * ndx
    pdy = cday - rA * ndy
    tx = ny
    ty = -nx
    tdx = ndy
    tdy = -ndx
    aax = px - xa
    aay = py - ya
    if kind == KIND_PLANE:
        abx = 0.0
        aby = 0.0
    else:
        abx = px - xb
        aby = py - yb
    dvx = (vxa - wa * aay) - (vxb - wb * aby)          # v_A(p) - v_B(p)
    dvy = (vya + wa * aax) - (vyb + wb * abx)
    vt = tx * dvx + ty * dvy
    qx = wa * (pdx - vxa) - wb * (pdx - vxb)
    qy = wa * (pdy - vya) - wb * (pdy - vyb)
    bt = tdx * dvx + tdy * dvy + (ty * qx - tx * qy)   # + t . J q
    return g, gd, nx, ny, aax, aay, abx, aby, bn, vt, bt


@njit(cache=True, _nrt=False, inline="always")
def _minv(bodies, i):
    """Inverse mass and inverse inertia of body i (0 for a fixed body)."""
    if bodies[i, CB_FIXED] != 0.0:
        return 0.0, 0.0
    return 1.0 / bodies[i, CB_M], 1.0 / bodies[i, CB_I]


@njit(cache=True, _nrt=False)
def _fill(c, k, w, yo, la, slot):
    """Rows, biases, gap, slip of contact k of table c into la slot ``slot``."""
    g, gd, nx, ny, aax, aay, abx, aby, bn, vt, bt = _kin(c, k, w, yo)
    o = LA_K + slot * LK_S
    tx = ny
    ty = -nx
    la[o + LK_NA] = nx
    la[o + LK_NA + 1] = ny
    la[o + LK_NA + 2] = aax * ny - aay * nx
    la[o + LK_NB] = -nx
    la[o + LK_NB + 1] = -ny
    la[o + LK_NB + 2] = -(abx * ny - aby * nx)
    la[o + LK_TA] = tx
    la[o + LK_TA + 1] = ty
    la[o + LK_TA + 2] = aax * ty - aay * tx
    la[o + LK_TB] = -tx
    la[o + LK_TB + 1] = -ty
    la[o + LK_TB + 2] = -(abx * ty - aby * tx)
    la[o + LK_BN] = bn
    la[o + LK_BT] = bt
    la[o + LK_G] = g
    la[o + LK_GD] = gd
    la[o + LK_VT] = vt
    la[o + LK_PX] = aax + w[yo + NS * int(c[k, CC_A])]
    la[o + LK_PY] = aay + w[yo + NS * int(c[k, CC_A]) + 1]


@njit(cache=True, _nrt=False, inline="always")
def _coef(c, la, j, kj, tj):
    """Force column of unknown j: (offset of its contact slot, weight of the JN part,
    weight of the JT part)."""
    o = LA_K + kj * LK_S
    if tj == 1:
        return o, 0.0, 1.0
    mode = c[kj, CC_MODE]
    mu = c[kj, CC_MU]
    if mode == MODE_STICK or mu == 0.0:
        return o, 1.0, 0.0
    return o, 1.0, -mu * mode


@njit(cache=True, _nrt=False)
def _rowmcol(bodies, c, la, ki, ri, kj, cn, ct):
    """row ri (LK_NA: normal, LK_TA: tangential) of contact ki times M^-1 times the column
    cn JN_kj + ct JT_kj."""
    oi = LA_K + ki * LK_S
    oj = LA_K + kj * LK_S
    s = 0.0
    for si in range(2):
        bi = int(c[ki, CC_A]) if si == 0 else int(c[ki, CC_B])
        if bi < 0:
            continue
        im, ii = _minv(bodies, bi)
        if im == 0.0:
            continue
        ro = oi + ri + 3 * si
        for sj in range(2):
            bj = int(c[kj, CC_A]) if sj == 0 else int(c[kj, CC_B])
            if bj != bi:
                continue
            no = oj + LK_NA + 3 * sj
            to = oj + LK_TA + 3 * sj
            for q in range(3):
                col = cn * la[no + q] + ct * la[to + q]
                s += la[ro + q] * (im if q < 2 else ii) * col
    return s


# ------------------------------------------------------------------ linear algebra


@njit(cache=True, _nrt=False)
def _solve(la, n, floor):
    """Minimum-norm solution of A x = r (A at LA_A, stride NMAX, r at LA_R) into LA_X by a
    one-sided Jacobi SVD (Hestenes; ``minnorm.minnorm_solve``, ``SVD_RTOL``,
    ``SVD_SWEEPS``). Returns False when the residual exceeds
    ``SOLVE_RTOL (|A| |x| + |r|) + floor`` (contradictory equations; ``floor`` the round-off
    of r's own scale)."""
    minnorm_solve(la, LA_A, LA_R, LA_X, LA_U, LA_V, n, NMAX, SVD_RTOL, SVD_SWEEPS)
    # residual check
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
    if not (res <= SOLVE_RTOL * sc + floor):
        return False
    return True


# ------------------------------------------------------------------ forces


@njit(cache=True, _nrt=False)
def _forces(bodies, c, nk, w, yo, la, ko):
    """Contact forces and accelerations at the state w[yo:yo + 6 nb] for the modes
    c[:nk, CC_MODE]; dy/dt into w[ko:ko + 6 nb]; lam, g'', dvT/dt into la. Returns CS_*."""
    nb = bodies.shape[0]
    gx = w[H_GX]
    gy = w[H_GY]
    n = 0
    for k in range(nk):
        _fill(c, k, w, yo, la, k)
        o = LA_K + k * LK_S
        if c[k, CC_MODE] == MODE_LIFT:
            la[o + LK_IN] = -1.0
            la[o + LK_IT] = -1.0
            continue
        if n >= NMAX:
            return CS_TOO_MANY_CONTACTS
        la[o + LK_IN] = n
        la[LA_EQ + n] = k
        la[LA_ET + n] = 0.0
        n += 1
        if c[k, CC_MODE] == MODE_STICK and c[k, CC_MU] != 0.0:
            la[o + LK_IT] = n
            la[LA_EQ + n] = k
            la[LA_ET + n] = 1.0
            n += 1
        else:
            la[o + LK_IT] = -1.0
    # the system A lam = r
    for i in range(n):
        ki = int(la[LA_EQ + i])
        ti = int(la[LA_ET + i])
        ri = LK_TA if ti == 1 else LK_NA
        oi = LA_K + ki * LK_S
        # r_i = -(row_i q''_free + b_i)
        rr = la[oi + (LK_BT if ti == 1 else LK_BN)]
        for si in range(2):
            bi = int(c[ki, CC_A]) if si == 0 else int(c[ki, CC_B])
            if bi < 0 or bodies[bi, CB_FIXED] != 0.0:
                continue
            rr += la[oi + ri + 3 * si] * gx + la[oi + ri + 3 * si + 1] * gy
        la[LA_R + i] = -rr
        for j in range(n):
            kj = int(la[LA_EQ + j])
            tj = int(la[LA_ET + j])
            oj, cn, ct = _coef(c, la, j, kj, tj)
            la[LA_A + i * NMAX + j] = _rowmcol(bodies, c, la, ki, ri, kj, cn, ct)
    # Painleve: a sliding contact's own effective normal mass
    for k in range(nk):
        o = LA_K + k * LK_S
        i = int(la[o + LK_IN])
        if i < 0 or c[k, CC_MODE] == MODE_STICK or c[k, CC_MU] == 0.0:
            continue
        wnn = _rowmcol(bodies, c, la, k, LK_NA, k, 1.0, 0.0)
        if not la[LA_A + i * NMAX + i] > PAINLEVE_RTOL * wnn:
            return CS_PAINLEVE
    if n > 0:
        amax = 0.0
        for i in range(n):
            for j in range(n):
                amax = max(amax, abs(la[LA_A + i * NMAX + j]))
        if not _solve(la, n, SOLVE_RTOL * amax * w[H_F]):
            return CS_SINGULAR
    # accelerations
    for i in range(nb):
        o = yo + NS * i
        d = ko + NS * i
        w[d] = w[o + 3]
        w[d + 1] = w[o + 4]
        w[d + 2] = w[o + 5]
        if bodies[i, CB_FIXED] != 0.0:
            w[d + 3] = 0.0
            w[d + 4] = 0.0
        else:
            w[d + 3] = gx
            w[d + 4] = gy
        w[d + 5] = 0.0
    for j in range(n):
        kj = int(la[LA_EQ + j])
        tj = int(la[LA_ET + j])
        oj, cn, ct = _coef(c, la, j, kj, tj)
        lam = la[LA_X + j]
        for sj in range(2):
            bj = int(c[kj, CC_A]) if sj == 0 else int(c[kj, CC_B])
            if bj < 0:
                continue
            im, ii = _minv(bodies, bj)
            if im == 0.0:
                continue
            no = oj + LK_NA + 3 * sj
            to = oj + LK_TA + 3 * sj
            d = ko + NS * bj
            w[d + 3] += im * lam * (cn * la[no] + ct * la[to])
            w[d + 4] += im * lam * (cn * la[no + 1] + ct * la[to + 1])
            w[d + 5] += ii * lam * (cn * la[no + 2] + ct * la[to + 2])
    # forces, g'' and dvT/dt per contact
    for k in range(nk):
        o = LA_K + k * LK_S
        i = int(la[o + LK_IN])
        it = int(la[o + LK_IT])
        if i < 0:
            ln = 0.0
            lt = 0.0
        else:
            ln = la[LA_X + i]
            if it >= 0:
                lt = la[LA_X + it]
            elif c[k, CC_MODE] == MODE_STICK or c[k, CC_MU] == 0.0:
                lt = 0.0
            else:
                lt = -c[k, CC_MU] * c[k, CC_MODE] * ln
        la[o + LK_LN] = ln
        la[o + LK_LT] = lt
        gdd = la[o + LK_BN]
        at = la[o + LK_BT]
        for si in range(2):
            bi = int(c[k, CC_A]) if si == 0 else int(c[k, CC_B])
            if bi < 0:
                continue
            d = ko + NS * bi
            for q in range(3):
                gdd += la[o + LK_NA + 3 * si + q] * w[d + 3 + q]
                at += la[o + LK_TA + 3 * si + q] * w[d + 3 + q]
        la[o + LK_GDD] = gdd
        la[o + LK_AT] = at
    _split_friction(c, nk, la, w[H_L])
    return CS_OK


@njit(cache=True, _nrt=False)
def _same_tangent(c, la, j, k, tol):
    """+1 or -1 when sticking contacts j and k join the same two bodies (either way round,
    or the same body and a plane each) with tangential rows ``JT_k = s JT_j`` to ``tol``
    in every entry; 0 otherwise. Their tangential forces are then interchangeable: any
    split with the same sum ``lam_T,j + s lam_T,k`` gives the same accelerations."""
    aj = c[j, CC_A]
    bj = c[j, CC_B]
    ak = c[k, CC_A]
    bk = c[k, CC_B]
    oj = LA_K + j * LK_S
    ok = LA_K + k * LK_S
    if aj == ak and bj == bk:
        for sg in (1.0, -1.0):
            same = True
            for q in range(6 if bj >= 0.0 else 3):
                if abs(la[ok + LK_TA + q] - sg * la[oj + LK_TA + q]) > tol:
                    same = False
            if same:
                return sg
    elif bj >= 0.0 and aj == bk and bj == ak:
        for sg in (1.0, -1.0):
            same = True
            for q in range(3):
                if (abs(la[ok + LK_TB + q] - sg * la[oj + LK_TA + q]) > tol
                        or abs(la[ok + LK_TA + q] - sg * la[oj + LK_TB + q]) > tol):
                    same = False
            if same:
                return sg
    return 0.0


@njit(cache=True, _nrt=False)
def _split_friction(c, nk, la, L):
    """Sticking contacts with interchangeable tangential rows (``_same_tangent``: the two
    ends of a face held on a face or a plane) carry a sum of tangential forces that the
    dynamics fixes and a split that it does not; the minimum-norm solve splits it equally,
    which can put the lightly loaded end outside its cone while the face as a whole holds.
    The split is set proportional to each contact's cone ``mu_k lam_N,k`` (every end then
    at the same fraction of its cone: the face slips as one, when the sum reaches
    ``sum mu_k lam_N,k``). Accelerations unchanged. Rows equal to ``SPLIT_RTOL (1 + L)``."""
    tol = SPLIT_RTOL * (1.0 + L)
    for k in range(nk):
        la[LA_K + k * LK_S + LK_GRP] = -1.0
    for j in range(nk):
        oj = LA_K + j * LK_S
        if la[oj + LK_IT] < 0.0 or la[oj + LK_GRP] >= 0.0 or c[j, CC_MU] == math.inf:
            continue
        la[oj + LK_GRP] = j
        tot = la[oj + LK_LT]
        cone = c[j, CC_MU] * la[oj + LK_LN]
        m = 1
        for k in range(j + 1, nk):
            ok = LA_K + k * LK_S
            if la[ok + LK_IT] < 0.0 or la[ok + LK_GRP] >= 0.0 or c[k, CC_MU] == math.inf:
                continue
            sg = _same_tangent(c, la, j, k, tol)
            if sg == 0.0:
                continue
            la[ok + LK_GRP] = j
            tot += sg * la[ok + LK_LT]
            cone += c[k, CC_MU] * la[ok + LK_LN]
            m += 1
        if m < 2 or not cone > 0.0:
            continue
        for k in range(j, nk):
            ok = LA_K + k * LK_S
            if la[ok + LK_GRP] != j:
                continue
            sg = 1.0 if k == j else _same_tangent(c, la, j, k, tol)
            la[ok + LK_LT] = sg * tot * (c[k, CC_MU] * la[ok + LK_LN]) / cone


# ------------------------------------------------------------------ projection


@njit(cache=True, _nrt=False)
def _project(bodies, c, nk, w, yo, la):
    """Project the state w[yo:yo + 6 nb] onto the active constraints (module docstring).
    Returns CS_OK or CS_SINGULAR."""
    L = w[H_L]
    for it in range(PROJ_ITER + 1):
        n = 0
        gm = 0.0
        for k in range(nk):
            _fill(c, k, w, yo, la, k)
            if c[k, CC_MODE] == MODE_LIFT:
                continue
            la[LA_EQ + n] = k
            la[LA_ET + n] = 0.0     # a normal row (_apply reads LA_ET: not the velocity
            #                         projection's stale tangential flags)
            la[LA_R + n] = -la[LA_K + k * LK_S + LK_G]
            gm = max(gm, abs(la[LA_K + k * LK_S + LK_G]))
            n += 1
        if n == 0 or gm <= PROJ_LTOL * L or it == PROJ_ITER:
            break
        for i in range(n):
            ki = int(la[LA_EQ + i])
            for j in range(n):
                kj = int(la[LA_EQ + j])
                la[LA_A + i * NMAX + j] = _rowmcol(bodies, c, la, ki, LK_NA, kj, 1.0, 0.0)
        if not _solve(la, n, SOLVE_RTOL * L):
            return CS_SINGULAR
        _apply(bodies, c, w, yo, la, n, 0)
    for rep in range(2):
        n = 0
        for k in range(nk):
            _fill(c, k, w, yo, la, k)
            if c[k, CC_MODE] == MODE_LIFT:
                continue
            o = LA_K + k * LK_S
            la[LA_EQ + n] = k
            la[LA_ET + n] = 0.0
            la[LA_R + n] = -la[o + LK_GD]
            n += 1
            if c[k, CC_MODE] == MODE_STICK and c[k, CC_MU] != 0.0:
                la[LA_EQ + n] = k
                la[LA_ET + n] = 1.0
                la[LA_R + n] = -la[o + LK_VT]
                n += 1
        if n == 0:
            break
        for i in range(n):
            ki = int(la[LA_EQ + i])
            ri = LK_TA if la[LA_ET + i] == 1.0 else LK_NA
            for j in range(n):
                kj = int(la[LA_EQ + j])
                tj = la[LA_ET + j] == 1.0
                la[LA_A + i * NMAX + j] = _rowmcol(bodies, c, la, ki, ri, kj,
                                                   0.0 if tj else 1.0, 1.0 if tj else 0.0)
        if not _solve(la, n, SOLVE_RTOL * w[H_V]):
            return CS_SINGULAR
        _apply(bodies, c, w, yo, la, n, 3)
    return CS_OK


@njit(cache=True, _nrt=False)
def _apply(bodies, c, w, yo, la, n, off):
    """w[yo + 6 i + off + (0, 1, 2)] += M^-1 J^T x for the unknowns x at LA_X (rows as
    listed in LA_EQ / LA_ET)."""
    for j in range(n):
        kj = int(la[LA_EQ + j])
        ro = LA_K + kj * LK_S + (LK_TA if la[LA_ET + j] == 1.0 else LK_NA)
        x = la[LA_X + j]
        for sj in range(2):
            bj = int(c[kj, CC_A]) if sj == 0 else int(c[kj, CC_B])
            if bj < 0:
                continue
            im, ii = _minv(bodies, bj)
            if im == 0.0:
                continue
            d = yo + NS * bj + off
            w[d] += im * x * la[ro + 3 * sj]
            w[d + 1] += im * x * la[ro + 3 * sj + 1]
            w[d + 2] += ii * x * la[ro + 3 * sj + 2]


# ------------------------------------------------------------------ setup helpers


@njit(cache=True, _nrt=False)
def _setup(bodies, gx, gy, L, w):
    """Header of w: gravity, scales; the bodies' state into block B_Y."""
    nb = bodies.shape[0]
    NY = NS * nb
    gl = math.hypot(gx, gy)
    w[H_GX] = gx
    w[H_GY] = gy
    w[H_G] = gl
    w[H_L] = L
    vmax = 0.0
    F = 0.0
    msum = 0.0
    for i in range(nb):
        if bodies[i, CB_FIXED] != 0.0:
            continue
        vmax = max(vmax, math.hypot(bodies[i, CB_VX], bodies[i, CB_VY])
                   + abs(bodies[i, CB_OMEGA]) * L)
        msum += bodies[i, CB_M]
    V = vmax + math.sqrt(gl * L)
    if not V > 0.0:
        V = 1.0 * L     # no gravity, no motion: any positive scale (1/s times L)
    w[H_V] = V
    w[H_M] = msum
    F = msum * gl
    if not F > 0.0:
        F = msum * V * V / L
    w[H_F] = F
    E = msum * gl * L
    for i in range(nb):
        if bodies[i, CB_FIXED] == 0.0:
            E += 0.5 * (bodies[i, CB_M] * (bodies[i, CB_VX] ** 2 + bodies[i, CB_VY] ** 2)
                        + bodies[i, CB_I] * bodies[i, CB_OMEGA] ** 2)
    w[H_E] = E if E > 0.0 else msum * V * V
    w[H_TOL] = CLUSTER_TOL
    yo = N_H + B_Y * NY
    for i in range(nb):
        for j in range(NS):
            w[yo + NS * i + j] = bodies[i, j]
    so = N_H + B_SC * NY
    for i in range(nb):
        w[so + NS * i] = L
        w[so + NS * i + 1] = L
        w[so + NS * i + 2] = 1.0
        w[so + NS * i + 3] = V
        w[so + NS * i + 4] = V
        w[so + NS * i + 5] = V / L


@njit(cache=True, _nrt=False, inline="always")
def _store_forces(contacts, nk, la):
    """The solved forces (la) into the contact table's CC_LAMN, CC_LAMT."""
    for k in range(nk):
        contacts[k, CC_LAMN] = la[LA_K + k * LK_S + LK_LN]
        contacts[k, CC_LAMT] = la[LA_K + k * LK_S + LK_LT]


@njit(cache=True, _nrt=False)
def _store(bodies, c, nk, w, yo, la):
    """State w[yo:...] into the bodies table; the forces of la into the contact table."""
    nb = bodies.shape[0]
    for i in range(nb):
        for j in range(NS):
            bodies[i, j] = w[yo + NS * i + j]
    _store_forces(c, nk, la)


# ------------------------------------------------------------------ public: forces, rates


@njit(cache=True, _nrt=False)
def _forces_table(bodies, contacts, nk, gx, gy, L, w, la):
    """_forces for the state of ``bodies``; the forces into the contact table, the
    derivative into block B_YC. Returns CS_*."""
    if nk > KMAX:
        return CS_TOO_MANY_CONTACTS
    nb = bodies.shape[0]
    NY = NS * nb
    _setup(bodies, gx, gy, L, w)
    st = _forces(bodies, contacts, nk, w, N_H + B_Y * NY, la, N_H + B_YC * NY)
    if st != CS_OK:
        return st
    _store_forces(contacts, nk, la)
    return CS_OK


@njit(cache=True, _nrt=False)
def cluster_forces(bodies, contacts, nk, gx, gy, L, w, la, acc):
    """Contact forces (into ``contacts[:nk, CC_LAMN / CC_LAMT]``) and accelerations (into
    ``acc``, float64[nb, 3]: ax, ay, alpha) for the state of ``bodies`` and the modes
    ``contacts[:nk, CC_MODE]``. Returns CS_*."""
    st = _forces_table(bodies, contacts, nk, gx, gy, L, w, la)
    if st != CS_OK:
        return st
    ko = N_H + B_YC * NS * bodies.shape[0]
    for i in range(bodies.shape[0]):
        for q in range(3):
            acc[i, q] = w[ko + NS * i + 3 + q]
    return CS_OK


@njit(cache=True, _nrt=False)
def cluster_rates(bodies, c, k, acc, w, out):
    """Kinematics of contact row k of table c for the state of ``bodies`` and the
    accelerations ``acc`` (float64[nb, 3]): ``out[:]`` = (g, dg/dt, g'', vT, dvT/dt, nx, ny)."""
    nb = bodies.shape[0]
    for i in range(nb):
        for j in range(NS):
            w[N_H + NS * i + j] = bodies[i, j]
    g, gd, nx, ny, aax, aay, abx, aby, bn, vt, bt = _kin(c, k, w, N_H)
    tx = ny
    ty = -nx
    a = int(c[k, CC_A])
    b = int(c[k, CC_B])
    gdd = bn + nx * acc[a, 0] + ny * acc[a, 1] + (aax * ny - aay * nx) * acc[a, 2]
    at = bt + tx * acc[a, 0] + ty * acc[a, 1] + (aax * ty - aay * tx) * acc[a, 2]
    if b >= 0:
        gdd -= nx * acc[b, 0] + ny * acc[b, 1] + (abx * ny - aby * nx) * acc[b, 2]
        at -= tx * acc[b, 0] + ty * acc[b, 1] + (abx * ty - aby * tx) * acc[b, 2]
    out[0] = g
    out[1] = gd
    out[2] = gdd
    out[3] = vt
    out[4] = at
    out[5] = nx
    out[6] = ny


@njit(cache=True, _nrt=False)
def cluster_energy(bodies, gx, gy):
    """Kinetic plus gravitational energy (J) of the free bodies (potential 0 at x = 0)."""
    e = 0.0
    for i in range(bodies.shape[0]):
        if bodies[i, CB_FIXED] != 0.0:
            continue
        m = bodies[i, CB_M]
        e += (0.5 * m * (bodies[i, CB_VX] ** 2 + bodies[i, CB_VY] ** 2)
              + 0.5 * bodies[i, CB_I] * bodies[i, CB_OMEGA] ** 2
              - m * (gx * bodies[i, CB_X] + gy * bodies[i, CB_Y]))
    return e


@njit(cache=True, _nrt=False)
def cluster_project(bodies, contacts, nk, gx, gy, L, w, la):
    """Project the state of ``bodies`` onto the active contacts (positions: g = 0; velocities:
    dg/dt = 0, and vT = 0 where sticking), in place. Returns CS_*."""
    if nk > KMAX:
        return CS_TOO_MANY_CONTACTS
    nb = bodies.shape[0]
    NY = NS * nb
    _setup(bodies, gx, gy, L, w)
    yo = N_H + B_Y * NY
    st = _project(bodies, contacts, nk, w, yo, la)
    for i in range(nb):
        for j in range(NS):
            bodies[i, j] = w[yo + NS * i + j]
    return st


# ------------------------------------------------------------------ mode selection


@njit(cache=True, _nrt=False)
def _consistent(c, nk, w, la, nopt, boundary):
    """The solved forces (la) consistent with the modes c[:nk, CC_MODE] (module doc)?
    ``w[nopt + k]``: the number of options of contact k (4: it starts at vT = 0).
    ``boundary``: a slip option from vT = 0 whose slip acceleration is zero (to ACC_TOL
    |g|) is consistent too: a stick with its force on the cone's boundary (``_enumerate``'s
    second pass)."""
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
            if abs(la[o + LK_LT]) > mu * ln + FORCE_TOL * F:
                return False
        elif w[nopt + k] == 4.0:
            # starts to slip from vT = 0: it must accelerate along its slip
            if not (mode * la[o + LK_AT] > atol
                    or (boundary and mode * la[o + LK_AT] >= -atol)):
                return False
    return True


@njit(cache=True, _nrt=False, inline="always")
def _option_mode(w, sv, nopt, k, opt):
    """The mode of option ``opt`` of contact k in the enumeration (``_enumerate``)."""
    no = int(w[nopt + k])
    if no == 1:
        return w[sv + k]
    if no == 2:
        return w[sv + k] if opt == 0 else MODE_LIFT
    if opt == 0:
        return MODE_STICK
    if opt == 1:
        return MODE_SLIP_POS
    if opt == 2:
        return MODE_SLIP_NEG
    return MODE_LIFT


@njit(cache=True, _nrt=False)
def _try_modes(bodies, contacts, nk, w, la, yo, ko, nopt, boundary):
    """Solve the forces in the modes of the table; consistent (``_consistent``): forces
    written, True."""
    if _forces(bodies, contacts, nk, w, yo, la, ko) != CS_OK:
        return False
    if not _consistent(contacts, nk, w, la, nopt, boundary):
        return False
    _store_forces(contacts, nk, la)
    return True


@njit(cache=True, _nrt=False)
def _search_near(bodies, contacts, nk, w, la, yo, ko, sv, nopt, cur, kfix, prefer,
                 boundary):
    """``_enumerate`` beyond ``KSEL_MAX`` contacts: from the base combination (each
    contact's current mode when ``prefer`` and it is one of its options, else its first
    option: stick, or slip along its slip), the combinations that change one contact, then
    two (``DSEL_MAX``), in the fixed order; the first consistent one. A local search, not
    the full LCP: a cluster of many contacts whose consistent modes differ from the base in
    more than two contacts is refused (CS_NO_MODE)."""
    base = N_H + B_YT * bodies.shape[0] * NS    # per contact: the index of its base option
    for k in range(nk):
        no = int(w[nopt + k])
        w[base + k] = 0.0
        if prefer:
            for o in range(no):
                if _option_mode(w, sv, nopt, k, o) == w[cur + k]:
                    w[base + k] = o
                    break
        contacts[k, CC_MODE] = _option_mode(w, sv, nopt, k, int(w[base + k]))
    if _try_modes(bodies, contacts, nk, w, la, yo, ko, nopt, boundary):
        return CS_OK
    for d in range(1, min(DSEL_MAX, 2) + 1):
        # d contacts changed: k1 alone, then k1 with every later k2
        for k1 in range(nk):
            b1 = int(w[base + k1])
            for o1 in range(int(w[nopt + k1])):
                if o1 == b1:
                    continue
                contacts[k1, CC_MODE] = _option_mode(w, sv, nopt, k1, o1)
                if d == 1:
                    if _try_modes(bodies, contacts, nk, w, la, yo, ko, nopt, boundary):
                        return CS_OK
                    continue
                for k2 in range(k1 + 1, nk):
                    b2 = int(w[base + k2])
                    for o2 in range(int(w[nopt + k2])):
                        if o2 == b2:
                            continue
                        contacts[k2, CC_MODE] = _option_mode(w, sv, nopt, k2, o2)
                        if _try_modes(bodies, contacts, nk, w, la, yo, ko, nopt, boundary):
                            return CS_OK
                    contacts[k2, CC_MODE] = _option_mode(w, sv, nopt, k2, b2)
            contacts[k1, CC_MODE] = _option_mode(w, sv, nopt, k1, b1)
    return CS_NO_MODE


@njit(cache=True, _nrt=False)
def _enumerate(bodies, contacts, nk, gx, gy, L, w, la, kfix, mfix, prefer):
    """The enumeration of ``cluster_select_modes`` with contact ``kfix`` held in mode
    ``mfix`` (its only option, no trend check: the caller's event rule chose it; ``kfix``
    -1: every contact free). ``prefer``: the combinations are tried in order of the number
    of contacts whose mode differs from the table's current one (then in the fixed order):
    after an event the modes that stay consistent are kept. Returns CS_OK (modes and
    forces written), CS_NO_MODE or CS_TOO_MANY_CONTACTS."""
    nb = bodies.shape[0]
    NY = NS * nb
    if nk > KMAX or nk > NY:
        return CS_TOO_MANY_CONTACTS
    _setup(bodies, gx, gy, L, w)
    yo = N_H + B_Y * NY
    ko = N_H + B_YC * NY
    sv = N_H + B_YA * NY        # per contact: its slip sign at the start (0: not slipping)
    nopt = N_H + B_YB * NY      # per contact: its number of options
    cur = N_H + B_Y1 * NY       # per contact: its mode on entry
    V = w[H_V]
    gl = w[H_G]
    window = STOP_RTOL * (math.sqrt(L / gl) if gl > 0.0 else L / V)
    # the slip accelerations in the current modes: a slip that stops within the window
    # stops now (near-simultaneous stops of a symmetric cluster, module docstring)
    rated = _forces(bodies, contacts, nk, w, yo, la, ko) == CS_OK
    total = 1
    for k in range(nk):
        o = LA_K + k * LK_S
        at = la[o + LK_AT] if rated else 0.0     # (_fill does not write LK_AT)
        _fill(contacts, k, w, yo, la, k)
        vt = la[o + LK_VT]
        w[cur + k] = contacts[k, CC_MODE]
        mode = contacts[k, CC_MODE]
        stopping = ((mode == MODE_SLIP_POS or mode == MODE_SLIP_NEG) and mode * vt > 0.0
                    and vt * at < 0.0 and abs(vt) <= abs(at) * window)
        if k == kfix:
            w[sv + k] = mfix
            w[nopt + k] = 1.0
        elif contacts[k, CC_MU] == 0.0:
            w[sv + k] = 1.0     # frictionless: "slip" (lam_T = 0) or lift
            w[nopt + k] = 2.0
        elif abs(vt) > STICK_VTOL * V and not stopping:
            w[sv + k] = 1.0 if vt > 0.0 else -1.0
            w[nopt + k] = 2.0
        else:
            w[sv + k] = 0.0
            w[nopt + k] = 4.0
        total *= int(w[nopt + k])
    # a second pass accepts boundary sticks (_consistent): where the sticking contacts are
    # statically indeterminate (a chain of dominoes coming to rest, each leaning on the
    # next) the minimum-norm forces can put one outside its cone while a split inside
    # every cone exists (_split_friction covers only the two ends of one face); a slip
    # option with zero slip acceleration fixes that contact's friction on its cone
    for boundary in (False, True):
        if nk > KSEL_MAX:
            cs = _search_near(bodies, contacts, nk, w, la, yo, ko, sv, nopt, cur, kfix,
                              prefer, boundary)
            if cs == CS_OK:
                return CS_OK
            continue
        for d in range(nk + 1 if prefer else 1):
            for combo in range(total):
                r = combo
                diff = 0
                for kk in range(nk):
                    k = nk - 1 - kk            # the last contact varies fastest
                    no = int(w[nopt + k])
                    mode = _option_mode(w, sv, nopt, k, r % no)
                    r //= no
                    if mode != w[cur + k] and k != kfix:
                        diff += 1
                    contacts[k, CC_MODE] = mode
                if prefer and diff != d:
                    continue
                if _try_modes(bodies, contacts, nk, w, la, yo, ko, nopt, boundary):
                    return CS_OK
    return CS_NO_MODE


@njit(cache=True, _nrt=False)
def cluster_select_modes(bodies, contacts, nk, gx, gy, L, w, la):
    """Choose a consistent mode for each of ``contacts[:nk]`` (every one at g = dg/dt = 0)
    by the enumeration of the module docstring; the modes go to ``CC_MODE`` (``MODE_LIFT``
    for the contacts that leave), the forces to ``CC_LAMN / CC_LAMT``. Returns CS_OK or
    CS_NO_MODE (modes left as the last tried) or CS_TOO_MANY_CONTACTS."""
    return _enumerate(bodies, contacts, nk, gx, gy, L, w, la, -1, 0.0, False)


@njit(cache=True, _nrt=False, inline="always")
def _same_pair(c, j, k):
    """Contacts j and k join the same two bodies (either way round), or the same body and
    the same plane."""
    aj = c[j, CC_A]
    bj = c[j, CC_B]
    ak = c[k, CC_A]
    bk = c[k, CC_B]
    if bj < 0.0 or bk < 0.0:
        return (aj == ak and bj == bk and c[j, CC_NX] == c[k, CC_NX]
                and c[j, CC_NY] == c[k, CC_NY] and c[j, CC_D] == c[k, CC_D])
    return (aj == ak and bj == bk) or (aj == bk and bj == ak)


@njit(cache=True, _nrt=False)
def cluster_after_event(bodies, contacts, nk, ev, k, gx, gy, L, w, la):
    """The modes after ``cluster_advance`` returned event ``ev`` at contact k (the state and
    forces as returned). Contact k takes the mode the trend calls for: ``CE_LEAVE`` ->
    ``MODE_LIFT`` (the stepper moves it to the candidates); ``CE_SLIP`` -> slip opposite to
    the sticking force, ``sig = -sign(lam_T)``; ``CE_STOP`` -> stick if its force is inside
    the cone, else slip reverses (``sig = -sign(lam_T)`` of the sticking trial, in which the
    other sliding contacts between the same bodies whose slip is zero to ``STICK_VTOL V``
    stick too: they stop at the same instant). At an event
    the new mode is the one the trend calls for: the enumeration of
    ``cluster_select_modes``, blind to the trend, would keep a force on its cone sticking.
    The other contacts keep their modes if that is consistent; else they are chosen again
    by the enumeration with contact k held, changing as few modes as possible (a contact
    stopping can pull its neighbours' normal forces below zero: they lift); if no
    combination is consistent with k's trend mode, by the full enumeration; none:
    CS_NO_MODE. ``CE_GAP`` (an impact) and ``CE_FEATURE`` (the contact moves to another
    feature): nothing, the stepper's. Returns the status (forces written as by
    ``cluster_forces``)."""
    if ev != CE_LEAVE and ev != CE_SLIP and ev != CE_STOP:
        return _forces_table(bodies, contacts, nk, gx, gy, L, w, la)
    if ev == CE_LEAVE:
        mode = MODE_LIFT
    elif ev == CE_SLIP:
        mode = MODE_SLIP_NEG if contacts[k, CC_LAMT] > 0.0 else MODE_SLIP_POS
    else:
        # the sliding contacts between the same two bodies (or the same body and plane)
        # whose slip is zero too (to STICK_VTOL V: the other end of a face sliding on a
        # face stops at the same instant) stick in the trial with k: held sliding there,
        # their friction would push k's force out of its cone
        NY = NS * bodies.shape[0]
        _setup(bodies, gx, gy, L, w)
        for j in range(nk):
            mj = contacts[j, CC_MODE]
            if j != k and _same_pair(contacts, j, k) and contacts[j, CC_MU] != 0.0 and (
                    mj == MODE_SLIP_POS or mj == MODE_SLIP_NEG):
                _fill(contacts, j, w, N_H + B_Y * NY, la, j)
                if abs(la[LA_K + j * LK_S + LK_VT]) <= STICK_VTOL * w[H_V]:
                    contacts[j, CC_MODE] = MODE_STICK
        contacts[k, CC_MODE] = MODE_STICK
        st = _forces_table(bodies, contacts, nk, gx, gy, L, w, la)
        if st != CS_OK and st != CS_SINGULAR and st != CS_PAINLEVE:
            return st
        lt = contacts[k, CC_LAMT]
        mode = MODE_STICK
        if st == CS_OK and abs(lt) > contacts[k, CC_MU] * contacts[k, CC_LAMN]:
            mode = MODE_SLIP_NEG if lt > 0.0 else MODE_SLIP_POS
    st = _enumerate(bodies, contacts, nk, gx, gy, L, w, la, k, mode, True)
    if st == CS_NO_MODE:
        st = _enumerate(bodies, contacts, nk, gx, gy, L, w, la, -1, 0.0, True)
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


@njit(cache=True, _nrt=False, inline="always")
def _cone(th, lo, hi, mx, my):
    """Margins (sin of the angles) of the unit vector m inside the cone of angles
    [th + lo, th + hi] (inf for an open cone, lo = -inf)."""
    if lo == -math.inf:
        return math.inf, math.inf
    a = th + lo
    b = th + hi
    return (math.cos(a) * my - math.sin(a) * mx, mx * math.sin(b) - my * math.cos(b))


@njit(cache=True, _nrt=False)
def _events(bodies, c, nk, cands, nc, w, la, NY, yo, eo):
    """Every event function at the state w[yo:yo + NY] into w[eo:eo + N_EVK KMAX + nc] (inf
    where it does not apply): for active contact k at N_EVK k: lam_N (N); its cone margin
    mu lam_N - |lam_T| (N) or its slip sig vT (m/s); then (at 2 + FR_*) A's normal cone
    margins (sin of the angles to its bounds), B's cone margins or the face's extent
    margins (m); at N_EVK KMAX + j the gap of candidate j (m). Returns the force status."""
    st = _forces(bodies, c, nk, w, yo, la, N_H + B_YC * NY)
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
        if mu != 0.0 and mu != math.inf:
            if mode == MODE_STICK:
                w[e0 + 1] = mu * la[o + LK_LN] - abs(la[o + LK_LT])
            else:
                w[e0 + 1] = mode * la[o + LK_VT]
        nx = la[o + LK_NA]
        ny = la[o + LK_NA + 1]
        tha = w[yo + NS * int(c[k, CC_A]) + 2]
        lo, hi = _cone(tha, c[k, CC_ALO], c[k, CC_AHI], -nx, -ny)
        w[e0 + 2 + FR_ALO] = lo
        w[e0 + 2 + FR_AHI] = hi
        kind = c[k, CC_KIND]
        if kind == KIND_PLANE:
            continue
        b = int(c[k, CC_B])
        thb = w[yo + NS * b + 2]
        if kind == KIND_ROUND:
            lo, hi = _cone(thb, c[k, CC_BLO], c[k, CC_BHI], nx, ny)
        else:
            cb = math.cos(thb)
            sb = math.sin(thb)
            fx = w[yo + NS * b] + cb * c[k, CC_PBX] - sb * c[k, CC_PBY]
            fy = w[yo + NS * b + 1] + sb * c[k, CC_PBX] + cb * c[k, CC_PBY]
            sp = ny * (la[o + LK_PX] - fx) - nx * (la[o + LK_PY] - fy)
            lo = sp - c[k, CC_BLO]
            hi = c[k, CC_BHI] - sp
        w[e0 + 2 + FR_BLO] = lo
        w[e0 + 2 + FR_BHI] = hi
    for j in range(nc):
        _fill(cands, j, w, yo, la, KMAX)
        w[eo + N_EVK * KMAX + j] = la[LA_K + KMAX * LK_S + LK_G]
    return st


@njit(cache=True, _nrt=False)
def _arm(w, c, nk, e, v):
    """Firing level of event e for a step starting at value v: a function starting below
    its arm fires below -arm, or below v - arm when it starts below -arm."""
    if e >= N_EVK * KMAX:
        arm = GAP_ARM * w[H_L]
    else:
        k = e // N_EVK
        j = e % N_EVK
        if j == 0 or (j == 1 and c[k, CC_MODE] == MODE_STICK):
            arm = FORCE_ARM * w[H_F]
        elif j == 1:
            arm = SLIP_ARM * w[H_V]
        elif j >= 4 and c[k, CC_KIND] == KIND_FACE:
            arm = GAP_ARM * w[H_L]
        else:
            arm = GAP_ARM       # a cone margin (sin of an angle)
    if v > arm:
        return 0.0
    if v >= -arm:
        return -arm     # a fixed floor: a function that starts near its root and falls
    #                     slowly over many short passes (capped by a body outside) fires
    #                     at -arm; re-armed from each pass's start it crept through its
    #                     root (a candidate corner 1.9e-9 m inside, session 30)
    return v - arm


@njit(cache=True, _nrt=False)
def _one_event(bodies, c, nk, cands, nc, w, la, NY, yo, e):
    """Event function e at w[yo:...] (see _events)."""
    eo = N_H + N_BLK * NY + 3 * (N_EVK * KMAX + nc)   # the fourth event block: scratch
    _events(bodies, c, nk, cands, nc, w, la, NY, yo, eo)
    return w[eo + e]


@njit(cache=True, _nrt=False)
def _locate(bodies, c, nk, cands, nc, w, la, NY, e, fl, sa, sb, tt):
    """First root of event e minus its floor fl in (sa, sb] on the dense output (value > 0
    at sa, <= 0 at sb). Returns the far side for a force or slip event, the near side for
    a gap."""
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
    return sa if (e >= N_EVK * KMAX or e % N_EVK >= 2) else sb


@njit(cache=True, _nrt=False)
def _at_rest(bodies, c, nk, w, la):
    """The rest test of the module docstring at block B_Y (forces solved into la)."""
    nb = bodies.shape[0]
    NY = NS * nb
    L = w[H_L]
    gl = w[H_G]
    vr = REST_VTOL * math.sqrt(gl * L)
    yo = N_H + B_Y * NY
    ko = N_H + B_YC * NY
    for i in range(nb):
        if bodies[i, CB_FIXED] != 0.0:
            if (w[yo + NS * i + 3] != 0.0 or w[yo + NS * i + 4] != 0.0
                    or w[yo + NS * i + 5] != 0.0):
                return False    # a moving support
            continue
        if math.hypot(w[yo + NS * i + 3], w[yo + NS * i + 4]) + abs(w[yo + NS * i + 5]) * L > vr:
            return False
    if _forces(bodies, c, nk, w, yo, la, ko) != CS_OK:
        return False
    F = w[H_F]
    for k in range(nk):
        o = LA_K + k * LK_S
        mode = c[k, CC_MODE]
        if mode == MODE_LIFT:
            continue
        mu = c[k, CC_MU]
        ln = la[o + LK_LN]
        if not ln > FORCE_TOL * F:
            return False
        # a slip mode at rest (no slip, no acceleration below) is a boundary stick
        # (_consistent), its force on the cone by construction
        if mode == MODE_STICK and mu != 0.0 and not abs(la[o + LK_LT]) < mu * ln:
            return False
    for i in range(nb):
        if bodies[i, CB_FIXED] != 0.0:
            continue
        if math.hypot(w[ko + NS * i + 3], w[ko + NS * i + 4]) + abs(w[ko + NS * i + 5]) * L > \
                REST_ATOL * gl:
            return False
    return True


# ------------------------------------------------------------------ recorded pieces


@njit(cache=True, _nrt=False, inline="always")
def _rows_off(NY, nc):
    """Offset of the three piece rows in w."""
    return N_H + N_BLK * NY + N_EVW * (N_EVK * KMAX + nc)


@njit(cache=True, _nrt=False)
def _dense_rows(bodies, w, NY, s, ro):
    """The dense state at s as rows (x, y, angle, vx, vy, omega, 0, 0, 0) at w[ro + 9 i]."""
    YA = N_H + B_YA * NY
    _dense(w, NY, s, YA)
    for i in range(bodies.shape[0]):
        for j in range(NS):
            w[ro + 9 * i + j] = w[YA + NS * i + j]
        for j in range(3):
            w[ro + 9 * i + 6 + j] = 0.0


@njit(cache=True, _nrt=False)
def _piece_dev(bodies, w, NY, nc, sa, h):
    """Deviation of the velocity-interpolating piece over [sa, sa + h] from the dense
    solution, for every free body together: (energy deviation / (PIECE_ETOL M V^2),
    max(point deviation / (PIECE_LTOL L), velocity deviation / (PIECE_VTOL V))), the larger
    at h/2 and h. The piece's rows (start state, constant accelerations) are left in the
    first row block."""
    nb = bodies.shape[0]
    R0 = _rows_off(NY, nc)
    R1 = R0 + 9 * nb
    L = w[H_L]
    V = w[H_V]
    gx = w[H_GX]
    gy = w[H_GY]
    _dense_rows(bodies, w, NY, sa, R0)
    _dense_rows(bodies, w, NY, sa + h, R1)
    for i in range(nb):
        for j in range(3):
            w[R0 + 9 * i + 6 + j] = (w[R1 + 9 * i + 3 + j] - w[R0 + 9 * i + 3 + j]) / h
    de = 0.0
    dp = 0.0
    for smp in range(2):
        sx = h if smp == 0 else 0.5 * h
        if smp == 1:
            _dense_rows(bodies, w, NY, sa + sx, R1)
        hh = 0.5 * sx * sx
        ep = 0.0
        ei = 0.0
        for i in range(nb):
            if bodies[i, CB_FIXED] != 0.0:
                continue
            o = R0 + 9 * i
            x = w[o] + w[o + 3] * sx + w[o + 6] * hh
            y = w[o + 1] + w[o + 4] * sx + w[o + 7] * hh
            a = w[o + 2] + w[o + 5] * sx + w[o + 8] * hh
            vx = w[o + 3] + w[o + 6] * sx
            vy = w[o + 4] + w[o + 7] * sx
            om = w[o + 5] + w[o + 8] * sx
            q = R1 + 9 * i
            m = bodies[i, CB_M]
            ep += (0.5 * m * (vx * vx + vy * vy) + 0.5 * bodies[i, CB_I] * om * om
                   - m * (gx * x + gy * y))
            ei += (0.5 * m * (w[q + 3] ** 2 + w[q + 4] ** 2)
                   + 0.5 * bodies[i, CB_I] * w[q + 5] ** 2 - m * (gx * w[q] + gy * w[q + 1]))
            dp = max(dp, (math.hypot(x - w[q], y - w[q + 1]) + L * abs(a - w[q + 2]))
                     / (PIECE_LTOL * L),
                     (math.hypot(vx - w[q + 3], vy - w[q + 4]) + L * abs(om - w[q + 5]))
                     / (PIECE_VTOL * V))
        de = max(de, abs(ep - ei) / (PIECE_ETOL * w[H_E]))
    return de, dp


@njit(cache=True, _nrt=False)
def _emit(bodies, w, NY, nc, sa, sb, hp, budget, t0, seg_t, seg_b, seg_s, cnt, ids):
    """Record [sa, sb] (within the current step) as pieces, one row per free body each, at
    most ``budget`` rows. Returns (s reached, next piece length guess, rows written)."""
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
            for j in range(9):
                seg_s[k, j] = w[R0 + 9 * i + j]
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
    """The forces just solved (la) consistent with the modes a
    phase starts in: every active ``lam_N >= -FORCE_ARM F``, every sticking force within
    ``FORCE_ARM F`` of its cone, every sliding contact's friction against its slip
    (``sig vT >= -STICK_VTOL V``), or a slip that the mode reverses within the stop window
    of the mode selection (``STOP_RTOL sqrt(L / |g|)``: it counted as stopping there, and
    its acceleration along sig turns it within that window; the friction's work meanwhile
    is below ``mu lam_N vT^2 / (2 |aT|)``). The arms are the event functions' own: a phase
    that starts beyond them would never see its event (an armed function fires only below
    its start) and would integrate pulling or driving forces."""
    F = w[H_F]
    V = w[H_V]
    gl = w[H_G]
    L = w[H_L]
    window = STOP_RTOL * (math.sqrt(L / gl) if gl > 0.0 else L / V)
    for k in range(nk):
        mode = c[k, CC_MODE]
        if mode == MODE_LIFT:
            continue
        o = LA_K + k * LK_S
        ln = la[o + LK_LN]
        if not ln >= -FORCE_ARM * F:
            return False
        mu = c[k, CC_MU]
        if mu == 0.0:
            continue
        if mode == MODE_STICK:
            if abs(la[o + LK_LT]) > mu * ln + FORCE_ARM * F:     # (mu = inf: never)
                return False
        elif not mode * la[o + LK_VT] >= -STICK_VTOL * V:
            vt = la[o + LK_VT]
            at = la[o + LK_AT]
            if not (mode * at > 0.0 and abs(vt) <= abs(at) * window):
                return False
    return True


@njit(cache=True, _nrt=False)
def cluster_advance(bodies, contacts, nk, cands, nc, gx, gy, L, t0, t_max, w, la, seg_t,
                    seg_b, seg_s, cnt, ids):
    """Integrate the cluster (state ``bodies``, active ``contacts[:nk]`` in their modes
    ``CC_MODE``, inactive candidates ``cands[:nc]``) from ``t0`` until the first event or
    ``t_max``. The state is projected onto the constraints first. On return ``bodies``
    holds the (projected) state at the returned time and ``contacts[:nk, CC_LAMN /
    CC_LAMT]`` the forces there. Returns ``(status CS_*, event CE_*, index, t)``: index the
    contact (CE_LEAVE, CE_SLIP, CE_STOP), the candidate (CE_GAP) or 4 k + FR_*
    (CE_FEATURE). ``CS_REST``: the cluster is at rest (nothing integrated, t = t0).

    Recording (when ``seg_t`` is not empty): the motion from ``t0`` as
    velocity-interpolating quadratic pieces (``pivot2d``'s, module docstring there: each
    piece starts at the integrated state with the constant accelerations that make its
    velocities agree at both ends; its length keeps the energy of the free bodies within
    ``PIECE_ETOL M V^2``, their points within ``PIECE_LTOL L`` and velocities within
    ``PIECE_VTOL V`` of the integrated solution), one row ``(x, y, angle, vx, vy, omega, ax,
    ay, alpha)`` per free body and piece into ``seg_t[k]`` (start time), ``seg_b[k]`` (the
    body's id ``ids[i]``), ``seg_s[k]``, ``k = cnt[CNT_SEG]`` counting up. At most
    ``PIECE_BUDGET`` rows (or the buffer's end) per call: the call then ends early with
    ``CE_NONE`` at the time reached (the caller calls again)."""
    if nk > KMAX:
        return CS_TOO_MANY_CONTACTS, CE_NONE, -1, t0
    nb = bodies.shape[0]
    NY = NS * nb
    _setup(bodies, gx, gy, L, w)
    w[H_T0] = t0
    Y = N_H + B_Y * NY
    Y1 = N_H + B_Y1 * NY
    K = N_H + B_K * NY
    YA = N_H + B_YA * NY
    E0 = N_H + N_BLK * NY                 # event values at the step start
    EF = E0 + (N_EVK * KMAX + nc)         # their floors
    ne = N_EVK * KMAX + nc
    V = w[H_V]
    S = t_max - t0
    st = _project(bodies, contacts, nk, w, Y, la)
    if st != CS_OK:
        return st, CE_NONE, -1, t0
    if _at_rest(bodies, contacts, nk, w, la):
        _store(bodies, contacts, nk, w, Y, la)
        return CS_REST, CE_NONE, -1, t0
    hmax = MAX_ANGLE * L / V
    w[H_HMAX] = hmax
    h = min(hmax, hmax * CLUSTER_TOL ** 0.2 * 10.0)
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
            om = max(om, abs(w[Y + NS * i + 5]))
        hcap = hmax
        if om * hcap > MAX_ANGLE:
            hcap = MAX_ANGLE / om
        h = min(h, hcap, S - w[H_S0])
        if not h > 0.0:
            h = S - w[H_S0]
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
        E1 = EF + ne
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
            sr, hp, n = _emit(bodies, w, NY, nc, s0, send, hp, PIECE_BUDGET - rows, t0, seg_t,
                              seg_b, seg_s, cnt, ids)
            rows += n
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
            j = be % N_EVK
            if j >= 2:
                return CS_OK, CE_FEATURE, 4 * k + j - 2, t0 + send
            if j == 0:
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


def validate_cluster(bodies, contacts, nk, cands=None, nc=0, L=1.0):
    """Check the tables before a kernel call (plain Python; the stepper's own scene checks
    make this redundant there). Raises ValueError naming the first problem."""
    import numpy as np
    bodies = np.asarray(bodies)
    if bodies.ndim != 2 or bodies.shape[1] != N_CB or bodies.dtype != np.float64:
        raise ValueError(f"bodies must be float64[nb, {N_CB}], got {bodies.dtype}{bodies.shape}")
    nb = bodies.shape[0]
    if not np.all(np.isfinite(bodies[:, :NS])):
        raise ValueError("bodies: non-finite state")
    for i in range(nb):
        if bodies[i, CB_FIXED] == 0.0 and not (bodies[i, CB_M] > 0.0 and bodies[i, CB_I] > 0.0
                                                and np.isfinite(bodies[i, CB_M])
                                                and np.isfinite(bodies[i, CB_I])):
            raise ValueError(f"body {i}: mass and inertia must be positive and finite")
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
            if kind not in (KIND_ROUND, KIND_FACE, KIND_PLANE):
                raise ValueError(f"{name} {k}: unknown kind {kind}")
            a = r[CC_A]
            b = r[CC_B]
            if a != int(a) or not 0 <= a < nb:
                raise ValueError(f"{name} {k}: body A = {a} out of range")
            if kind == KIND_PLANE:
                if b != -1:
                    raise ValueError(f"{name} {k}: a plane contact has CC_B = -1")
            elif b != int(b) or not 0 <= b < nb or b == a:
                raise ValueError(f"{name} {k}: body B = {b} out of range or equal to A")
            if kind != KIND_ROUND and abs(math.hypot(r[CC_NX], r[CC_NY]) - 1.0) > 1e-12:
                raise ValueError(f"{name} {k}: the normal (CC_NX, CC_NY) must be a unit vector")
            if r[CC_RA] < 0.0 or r[CC_RB] < 0.0:
                raise ValueError(f"{name} {k}: negative radius")
            if not (r[CC_MU] >= 0.0):
                raise ValueError(f"{name} {k}: mu must be >= 0")
            if name == "contact":
                if r[CC_MODE] not in (MODE_STICK, MODE_SLIP_POS, MODE_SLIP_NEG, MODE_LIFT):
                    raise ValueError(f"contact {k}: unknown mode {r[CC_MODE]}")
                if r[CC_MU] == math.inf and r[CC_MODE] in (MODE_SLIP_POS, MODE_SLIP_NEG):
                    raise ValueError(f"contact {k}: a contact with mu = inf cannot slip")
            fa = kind == KIND_PLANE or bodies[int(b), CB_FIXED] != 0.0
            if bodies[int(a), CB_FIXED] != 0.0 and fa:
                raise ValueError(f"{name} {k}: both sides fixed")
            for lo, hi, what in ((r[CC_ALO], r[CC_AHI], "A's normal cone"),
                                 (r[CC_BLO], r[CC_BHI], "B's range")):
                if math.isnan(lo) or math.isnan(hi) or not lo <= hi:
                    raise ValueError(f"{name} {k}: {what} needs lo <= hi")
                if lo == -math.inf and hi != math.inf:
                    raise ValueError(f"{name} {k}: {what}: -inf opens the range, hi must be inf")
            for lo, hi, what in ((r[CC_ALO], r[CC_AHI], "A's normal cone"),
                                 (r[CC_BLO], r[CC_BHI], "B's normal cone")):
                if what[0] == "B" and kind != KIND_ROUND:
                    continue
                if lo != -math.inf and not hi - lo < math.pi:
                    raise ValueError(f"{name} {k}: {what} must be narrower than pi")
            for ea, eb, what in ((r[CC_AEA], r[CC_AEB], "A"), (r[CC_BEA], r[CC_BEB], "B")):
                if not (ea >= 0.0 and math.isfinite(ea)) or (ea > 0.0) != (eb > 0.0):
                    raise ValueError(f"{name} {k}: {what}'s ellipse semi-axes must be both 0 "
                                     f"(a round feature) or both positive and finite")
            if r[CC_BEA] > 0.0 and kind != KIND_ROUND:
                raise ValueError(f"{name} {k}: B's feature is an ellipse only in KIND_ROUND")
            if (r[CC_AEA] > 0.0 or r[CC_BEA] > 0.0) and not math.isfinite(r[CC_PSI]):
                raise ValueError(f"{name} {k}: CC_PSI (the normal's angle) must be finite")
            g = [r[CC_PAX], r[CC_PAY], r[CC_PBX], r[CC_PBY], r[CC_D]]
            if not np.all(np.isfinite(g)):
                raise ValueError(f"{name} {k}: non-finite geometry")
