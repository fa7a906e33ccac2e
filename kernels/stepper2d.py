"""The compiled event loop of the exact 2D event-driven stepper (DESIGN §6, issue 3).

Everything here is ``@njit(cache=True, _nrt=False)``: no reference counting, because the
kernels only index preallocated arrays and never allocate (nothing is allocated per
event). ``rbimpact.simulation`` packs a scene into the arrays below and calls the loop
``loop_for(law, *switches)`` compiled for the scene's law and features (the first call
initialises the run) until it returns ``RC_DONE`` or ``RC_MAX_EVENTS`` (``RC_BUFFER_FULL``:
the Python side doubles the event/segment buffers and calls again; the loop resumes exactly
where it stopped).
Negative return codes are errors (``ERR_*``), with details in ``err``. Codes, modes and
event kinds are shared with 3D (``codes``); table columns are named (``layout``,
``flight2d``, the ``B_*`` below).

Compile only what a scene uses (issue 14): the law and the feature switches ``pivot``,
``wedge``, ``pair``, ``joint`` (``scene_features``: True, or None when the scene cannot
reach that mode) are constants closed over by ``loop_for(law, *switches)``, so Numba
prunes the other laws and the switched-off modes before inlining and typing (and, in the
handlers that are not inlined, which take the switch as an argument, by its type): a disk
bouncing on a floor compiles no pivot, wedge, pair or joint code. Each law and switch
pattern is its own entry in Numba's on-disk cache.

Scene arrays (constant during a run)
------------------------------------
``bint`` int64[nb, 3]      ``B_KIND`` shape kind (``SH_*``), ``B_FIRST`` first vertex row in
                           ``verts``, ``B_COUNT`` vertex count
``bflt`` float64[nb, 5]    ``B_MASS`` (kg), ``B_INERTIA`` (kg m^2), ``B_RADIUS`` rounding
                           radius (m; a disk's radius, a capsule's radius, 0 for polygons),
                           ``B_EA``, ``B_EB`` ellipse semi-axes (m)
``verts`` float64[nv, 2]   body-frame contact points (a disk and an ellipse have one, (0, 0))
``planes`` float64[np, 3]  ``(nx, ny, d)``: half-plane ``n . q >= d`` is free space
``grav`` float64[2]        gravity (m/s^2)
``law_ids`` int64[nl], ``law_par`` float64[nl, N_PARAMS]: the law table
``bp_law`` int64[nb, np]   law row of each body-plane contact
``pairs`` int64[npr, 3]    disk-disk pairs ``(a, b, law row)``
``tolf``, ``toli``         tolerances (``TF_*``, ``TI_*`` slots)

Dynamic state (kept between calls)
----------------------------------
``st`` float64[nb, 9] state rows at ``tref`` (columns ``X, Y, ANGLE, VX, VY, OMEGA, AX,
AY, ALPHA`` of ``flight2d``); ``pm`` int64[nb, N_PM] persistent contact (``M_MODE`` mode
``PM_*``, ``M_PLANE`` plane, ``M_FEAT`` face vertex 0, ``M_AUX`` face vertex 1;
``PM_PIVOT``: held vertex, contact status ``0`` sticking / ``+-1`` sliding along ``+-t``;
``M_PLANE2``, ``M_FEAT2``: the second held contact on two planes, else -1;
in flight ``pm[i, M_AUX] == REL_TANGENT`` marks a body just released tangentially from vertex
``pm[i, M_FEAT]`` on plane ``pm[i, M_PLANE]``, see ``_released_toi``); ``tz``/``zp`` pending
accumulation (Zeno) point and its plane (``PM_PIVOT``: ``zp`` holds the pivot event due at
``ttr``, ``pivot2d.PE_* + 8 index``); ``ttr`` next persistent-mode transition;
``bp_t``/``bp_off`` next impact time of each body-plane pair / pair disabled after a
perforating impact; ``pr_t``/``pr_off`` the same for disk pairs; ``glob[0]`` the current
time; ``cnt`` = (events logged, segments logged, consecutive events at one instant).

Output buffers
--------------
Events: ``ev_t`` (s), ``ev_i`` (kind ``EV_*``, a, b, mode, cluster size) and ``ev_f``
(point xy, normal xy, v_i (N, T), v_f (N, T), P (N, T), dE). ``b`` is a body index or
``-1 - plane`` for a plane. Segments: ``seg_t``, ``seg_b``, ``seg_s``: body ``seg_b`` moves
from ``seg_t`` with state row ``seg_s`` (exact piecewise-quadratic trajectories; an
integrated pivot phase is recorded as the velocity-interpolating pieces of ``pivot2d``,
within its stated energy and position tolerances of the integrated motion).

Accumulation (Zeno)
-------------------
After an impact on a plane pushing the body, when the energy of its motion normal to the
plane (and, not for a disk, of its rotation) plus its height above its rest falls below
``m zeno_speed^2 / 2``, the run jumps to the accumulation time ``t_inf`` and snaps the body
onto its rest there (event "contact"). The rest is the face least inclined to the plane
at the lowest corner; the accumulation is accepted only if it is consistent: the centre
of mass is over that face and the snap does not lift it (``SNAP_RTOL``), else the impacts
are stepped on. From the last impact to ``t_inf`` the body's reported trajectory (and
every other candidate event) is its held motion (``_held_into``: at the height of the
last impact, no normal velocity, tangential motion the exact free flight), so it never
dips below the plane; ``st`` keeps the free-flight row, so that the "contact" event
reports the accumulated impulse ``m v (1 + e) / (1 - e)`` and the energy removed. An
impact of another contact before ``t_inf`` cancels the jump: the body continues from its
held state (the unfinished normal energy, below the threshold, is dropped).

The contacts of an instant
--------------------------
``_gather`` takes every contact touching in ``[t, t + simul_time]`` (and closing corners
within ``simul_gap``; the held vertex of a pivoting body); under the simultaneous policy
every body of a body-body contact of the instant also brings the features it touches a
plane with (``_held_into_instant``: a body resting, sliding or rolling on a plane is in
flight from t), so that a struck body is supported by its plane in the same joint impact
(a domino struck on the floor turns on its far corner). The contacts sharing a body are
one cluster of the instant, solved jointly (simultaneous) or one by one (sequential).

Integrated pivot contact (``PM_PIVOT``, ``kernels/pivot2d.py``)
--------------------------------------------------------------
When, after the impacts of an instant, a vertex of a polygon (or a rod end), or the
boundary of an ellipse, touches a plane pushing the body with a normal speed ``v_N`` such
that ``v_N^2 < 2 |g''| rest_length`` (or ``zeno_speed^2``) while its free-flight gap
accelerates into the plane (``g'' < 0``), and the body is not accumulating onto a face (an
ellipse: onto its rest), its impacts would accumulate at that point while the body turns
about it (an ellipse: rolls or slides on its curved boundary, the contact point moving on
it). Instead, its tiny normal velocity is removed by a normal
impulse (and, when its slip is below the accumulation speed too and ``mu > 0``, its slip by
an impulse ``W P = -v``: both never add energy, ``dE = -v . W^-1 v / 2``), and the body moves
with that vertex held on the plane, sticking or sliding under Coulomb friction (event
"pivot", mode 2 sticking, 1 sliding; ``ERR_PAINLEVE`` when sliding has no solution). The
motion is integrated (``pivot2d``) in passes of at most ``PIECE_BUDGET`` recorded pieces
until: the normal force vanishes (event "release": free flight; the flight search of the
released vertex starts past its third-order tangency, ``_released_toi``); the sticking
force reaches the friction cone ("slide", slip opposite to it, when consistent); the slip
vanishes ("stick" after a slip-removing impulse of the integration's round-off, or "slide"
the other way); another vertex reaches a plane: an impact, resolved by the pair law with
the held vertex in its cluster (it is resolved too if the impact drives it into the plane),
after which the rules above apply again (a face landing below the accumulation energy
settles onto the face as before). An ellipse is held the same way (``pivot2d.KIND_ELLIPSE``;
``pm[i, M_FEAT] == 0``; its released flight search is ``_released_toi_ellipse``); a rough
ellipse that settles onto its rest while sliding faster than the accumulation speed (or on
a slope friction cannot hold) is held from there too (``_persist_setup`` returns ``RC_TIP``,
as a tipping face). A rough ellipse on a level plane then rocks for ever (rolling is
conservative). Impacts accumulating at a point of a disk (on a disk) remain
``ERR_CHATTER``.

Two held contacts (``PM_PIVOT`` with ``pm[i, M_PLANE2] >= 0``, ``pivot2d`` "Two contacts")
------------------------------------------------------------------------------------------
When impacts accumulate at a point on one plane (as above) while another point of the body
touches a second plane slower than the accumulation speed (a ladder's top on the wall, a
box's second corner in a groove, a spinning disk in a corner whose floor friction presses it
into the wall), both normal velocities are removed by the two contacts' normal impulses and
the body slides on both (``_two_enter``), if both normal forces of that motion are >= 0;
else it pivots on one as above. One degree of freedom is left (the angle); ``pm[i, M_AUX]``
is the sign of w. Events (``_two_event``): a normal force reaches 0 (event "release" on
that plane, the body pivots on the other); the slip of one contact reverses (event
"slide"); w reaches 0 (both slips vanish): rest when that is a static equilibrium (event
"rest", ``PM_WEDGED``), else the body slides the consistent way or, when neither way is
consistent, keeps the one contact that can hold it alone (``_two_drop``; ERR_TWO_PLANES
when none can); another vertex lands (an impact, with both held vertices in its cluster).
A polygon resting or sliding on a face whose corner lands on a second plane rests when the
face and the corner admit a static equilibrium (``wedge2d.three_contact_rest``).

Persistent contact between bodies (``PM_CLUSTER``, ``kernels/cluster2d.py``; issue 16 item 2)
-----------------------------------------------------------------------------------------------
When the impacts of two bodies accumulate (``decisions.pair_persistence`` says ``PP_CHATTER``
in ``_recompute_pair``, or, for two rounded polygons, ``PP_TOGETHER``; or ``_holding``
finds a disk pair's contact chattering), the pair is marked (``cid[CL_PEND]``) and, at the
next pass, enters a *cluster* (``_cluster_enter``): the bodies connected to it by contacts
within ``gap_tol`` (every shape) and the planes they touch. Its contact rows
(``kernels/cluster2d_rows.py``): two disks, round-round; an ellipse, one row with the
ellipse as A (on the other's vertex, face or ellipse; on a plane: one row, its osculating
circle at the contact in ``cluster2d``); any other pair, the features on the extreme
supports along the pair's normal (a vertex on a face, face on face as the two ends of the
overlap, two rounded vertices; two sharp corners take the face of greatest separation), a
contact
that separates faster than the pair's zero speed (``decisions.pair_zero_speed``) being a
candidate; a vertex on a face has its neighbours on the same face as candidates (the
face's landing); a body on a plane, one row per core vertex within ``gap_tol``, the others
candidates. A pair of members not touching at the entry has no row: after every pass
its gap is checked (an overlap beyond ``gap_tol``: ``PP_UNWATCHED``). The state is
projected onto g = dg/dt = 0 (an M-orthogonal projection: removes the round-off approach,
never adds energy) and the modes are chosen (``cluster_select_modes``; none:
``ERR_PERSISTENT_PAIR``, reason ``PP_NO_MODE``); event "contact", mode ``PM_CLUSTER``,
cluster size. Its members are ``PM_CLUSTER``; its leader's ``ttr`` is the next pass
(``_cluster_pass``: ``cluster_advance`` to its first event, pieces recorded as pivot2d's).
Events: a contact's force reaching zero (event "release"; it becomes a candidate; when no
body-body contact is left the cluster dissolves, each member settling on the plane it
still touches, ``_settle`` -- a polygon or rod only when held there at two points, else
it flies and the plane's search finds the contact -- or flying; the released pair is
searched past its tangency, ``PR_REL``), stick/slip ("stick", "slide":
``cluster_after_event``, which keeps the other contacts' modes when they stay consistent
and else changes as few as it can, lifting the contacts whose force would pull, each
logged "release"; none consistent: ``PP_NO_MODE``, worded as the Painleve inconsistency it
is; stick-slip chatter re-selects every mode, and ``CL_CHAT_MAX`` chattering events are
``PP_STICK_SLIP``), a contact point leaving its feature (``cluster2d_rows.switch_row``: a
face's end -> the point on the end vertex, or for two sharp corners the end corner on the
point body's face; a vertex's normal cone in a round-round contact -> the adjacent face;
the point's own cone on a face or a plane -> its adjacent face lands, an impact instant;
the modes are chosen again; a switch not found: the cluster is gathered again at that
instant, and three gatherings within ``CL_CHAT_RTOL sqrt(L / |g|)``: ``PP_FEATURE``), a
candidate's gap closing (the cluster dissolves into that impact instant, its contacts in
the instant's cluster at v_N = 0; the persistence rule then enters it again), rest
(``CS_REST``, event "rest": frozen, velocities zero, until a body outside hits it: then it
dissolves into that instant). One cluster at a time (``PP_TWO``); a pair with one body in
a moving cluster is bounded (``_held_cluster_pair``: the cluster's pass ends where the
bound must be taken again, so approaching the touch; touching and closing at a pass end:
the impact instant, the cluster dissolving into it), a pair with a body
held by one pivot contact is bounded at each of its passes (``_pivot_partners``, the same
bound; a body held on two planes is refused: ``PP_HELD``); a member
whose last contacts lift while others stay in contact leaves it, flying (``_cl_leave``);
several bodies held by pivot contacts at one instant join one cluster, touching or not
(members apart are bounded by the cluster's energy, ``_member_pair``, and watched by the
rows of their nearest features once close), and a moving cluster whose pass ends where a
pair outside accumulates is entered again with it. State: ``cbod``, ``ccon``, ``cw``, ``cid`` (``cluster_sizes``),
arguments of the loop after ``err``.
"""
import functools
import math

from numba import float64, int64, njit

# Explicit signatures for helpers called with literal constants, so that Numba compiles
# each of them once (not once per combination of literal arguments).
_A1 = float64[::1]
_A2 = float64[:, ::1]
_I1 = int64[::1]
_I2 = int64[:, ::1]
_f = float64
_i = int64
#: the options of the kernels called only from compiled code, never from Python: those of
#: ``njit(cache=True, _nrt=False)`` without the CPython and C wrappers Numba builds for calls
#: from Python (their compile time is saved, issue 14; such a kernel called from Python
#: would crash, so a kernel a test calls keeps the plain options)
_INNER = dict(cache=True, _nrt=False, no_cpython_wrapper=True, no_cfunc_wrapper=True)
_inner = njit(**_INNER)

from .cache_guard import guard

# flush stale compiled callers before any kernel module below is imported (cache_guard)
guard(__name__, __file__)

from . import evbuf
from .instant import (CI_A, CI_B, CI_FEAT, CI_LAW, CI_OFF, CI_TYPE, N_CI,  # noqa: F401
                      cluster_contacts, cluster_members)
from .layout import (CL_CHAT, CL_CHAT_MAX, CL_CHAT_RTOL, CL_EV, CL_FROZEN, CL_HDR,  # noqa: F401
                     CL_IDX, CL_LEAD, CL_N, CL_NC, CL_NK, CL_PEND, CL_REENTRY_HOLD,
                     CL_SWITCH, NCAND)
from .layout import (B_COUNT, B_FIRST, B_KIND, B_MASS, M_AUX, M_FEAT, M_FEAT2, M_MODE,  # noqa: F401
                     M_PLANE, M_PLANE2, N_PM)
from .codes import (ERR_CHATTER, ERR_CONTACT_STEPS, ERR_FAR_ACCUMULATION, ERR_JOINT_E,
                   ERR_MISSED, ERR_NONFINITE, ERR_NOT_COMPILED, ERR_NO_SOLUTION, ERR_PAINLEVE,
                   ERR_PERSISTENT_PAIR, ERR_PGS, ERR_SEQ, ERR_STALL, ERR_TIPPING, ERR_TOI,
                   ERR_TOO_MANY, ERR_IDLE,
                   ERR_TWO_PLANES, EVENT_KINDS, EV_CONTACT, EV_IMPACT, EV_IWC, EV_PIVOT,
                   EV_RELEASE, EV_REST, EV_SLIDE, EV_STICK, FEATURES, FEATURE_JOINT, FEATURE_PAIR,
                   FEATURE_PIVOT, PM_FLIGHT, PM_PIVOT, PM_REST, PM_ROLL, PM_SLIDE, PM_WEDGED,
                   PAINLEVE_IMPACT, POL_SIMULTANEOUS, PP_CHATTER, PP_HELD, PP_TOGETHER,  # noqa: F401
                   PM_CLUSTER, PP_CLUSTER, PP_CORNER, PP_FEATURE, PP_NO_MODE, PP_REENTRY, PP_UNWATCHED, PP_SHAPES, PP_SPLIT, PP_STICK_SLIP,
                   PP_TWO,
                   PR_HIT, PR_OFF, PR_ON, PR_REL, PR_WAIT, RC_BUFFER_FULL, RC_DONE, RC_MAX_EVENTS)
from .common import MODE_NO_SOLUTION, P_E, P_MU, REST_POISSON
from . import cluster2d as cl
from . import cluster2d_rows as clr
from .decisions import (PAIR_VN_RTOL, REL_S0, accumulation_time, impacts_before_rest,  # noqa: F401
                        pair_accel_bound, pair_crawl_chatters, pair_persistence,
                        pair_zero_speed, perforates, touching_accel, touching_rate)
from .dispatch import resolve_2d_as
from .joint_polish import ENUM_MAX_K, enumerate2d, polish_ws
from .routh import routh_2d_scalar
from .flight2d import (ALPHA, ANGLE, AX, AY, OMEGA, VX, VY, X, Y, body_energy, fly_into,
                       fly_row)
from .pivot2d import (CP_D, CP_D2, CP_DIR, CP_EA, CP_EB, CP_GN, CP_GT, CP_I, CP_K2, CP_KIND,
                      CP_L, CP_M, CP_MU, CP_MU2, CP_N2X, CP_N2Y, CP_NX, CP_NY, CP_P2X,
                      CP_P2Y, CP_PX, CP_PY, CP_Q2, CP_RAD, CP_SIG, CP_TWO, KIND_ELLIPSE,
                      KIND_VERTEX, N_W, PE_GAP, PE_LIFT, PE_NONE, PE_SLIP, PE_STOP, PE_TURN,
                      PI_OK, PI_TOO_MANY_STEPS, PIECE_BUDGET, PV_OK, W_ROW, W_YA,
                      ellipse_support3, pivot_advance, pivot_forces, pivot_reduce, pivot_row,
                      pivot_slip_rate, two_forces, two_slip_signs)
from .toi2d import (FEAT_ELLIPSE, FEAT_VERTEX, TOI_MISSED, TOI_NOT_CONVERGED, TOI_OK,
                    disk_disk_toi, disk_plane_toi, ellipse_support, feature_gap,
                    plane_feature_toi)
from .wedge2d import three_contact_rest, two_contact_rest
from .pair2d import frame_rel, point_rate
from .pair2d_shape import body_reach, vertex_at
from .pair2d_toi import pair_toi

INF = math.inf

# bflt columns (B_MASS and the bint columns: kernels/layout.py)
B_INERTIA = 1    # moment of inertia about the centre of mass (kg m^2)
B_RADIUS = 2     # rounding radius (m): a disk's or a capsule's radius, 0 for a polygon
B_EA = 3         # ellipse semi-axis along the body x axis (m)
B_EB = 4         # ellipse semi-axis along the body y axis (m)

# shape kinds
SH_DISK = 0
SH_POLY = 1
SH_ELLIPSE = 2

# return, error and event codes, modes and policies: kernels/codes.py (shared with 3D)
REL_TANGENT = -2     # pm[i, M_AUX] of a body just released tangentially (see _released_toi)

# tolerance slots
TF_REST_LENGTH = 0
TF_ZENO_SPEED = 1      # < 0: derived, sqrt(2 |g_n| rest_length)
TF_GAP_TOL = 2
TF_TOI_RTOL = 3
TF_TOI_ATOL = 4
TF_SIMUL_TIME = 5
TF_SIMUL_TOL = 6
TF_SEQ_VTOL = 7
TF_T_END = 8
TF_SIMUL_GAP = 9
TF_PAINLEVE = 10       # PAINLEVE_ERROR or PAINLEVE_IMPACT (codes.py), as a float
N_TF = 11
TI_TOI_MAXIT = 0
TI_SIMUL_MAXIT = 1
TI_SEQ_MAXSTEPS = 2
TI_STALL = 3
TI_POLICY = 4
TI_MAX_EVENTS = 5
TI_ACC_MAX = 6         # max_accumulation_impacts
TI_IDLE = 7            # idle_passes
N_TI = 8

RC_TIP = 2           # _persist_setup: the face would tip over; pivot on vertex pm[i, M_FEAT]
ROLL_RTOL = 8.0 * 2.220446049250313e-16
"""A disk's contact-point slip vT + w r below ROLL_RTOL (|vT| + |w r|) is the round-off of
that sum: the disk rolls (a slip that ended by friction otherwise restarts at 1e-17 m/s)."""
TIP_RTOL = 1e-12     # a face corner's normal force below -TIP_RTOL m |g_n| lifts it (tips)
# Feature switches (codes.FEATURES): ``loop_for`` takes ``pivot`` (a polygon, rod or
# ellipse: rest on a face, tipping, held vertex or boundary), ``wedge`` (two or more planes:
# rest on two contacts), ``pair`` (disk pairs) and ``joint`` (several contacts at one
# instant), each True or None (``scene_features``), as compile-time constants of the loop:
# a disk bouncing on a floor compiles no pivot, wedge, pair or joint code. A fifth switch,
# ``shapes`` (None when every body is a disk), prunes the polygon and ellipse branches of
# the persistent-contact and time-of-impact code (a disk rests, rolls or slides in closed
# form); a body other than a disk in such a loop is ERR_NOT_COMPILED (FEATURE_PIVOT, the
# switch every such body sets).
SWITCHES_IN_LOOP = True     # ``loop_for(law, *switches)``; run_loop does not take them

MAXC = 16            # contacts resolved at one instant (per call of the impact step)

# Body pairs (issue 16): ``pr_off`` codes PR_ON / PR_OFF / PR_HIT and the reasons PP_* of
# ERR_PERSISTENT_PAIR are shared with 3D (``codes``), and so is the rule that decides
# whether a pair stays in contact after an impact (``decisions.pair_persistence``).
#: face on face: two edges of rounded polygons (box, polygon, rod, capsule) touch along a
#: segment when the far vertex of each face lies within ``simul_gap + PAIR_FACE_RTOL * L``
#: of the extreme support along the contact normal (``L`` the distance of the body's
#: farthest core vertex from its centre, m): the corner-joins-the-cluster rule of a
#: landing on a plane (``simul_gap``), plus the round-off of rotated vertex positions
#: (about 1e-16 L; an angle of 1e-12 rad between the edges). The contact is then the two
#: ends of the overlap of the two edges (a cluster of two, resolved by the policy as a
#: flat landing on a plane); an overlap shorter than ``PAIR_FACE_RTOL * L`` is one point.
PAIR_FACE_RTOL = 1e-12
#: accumulation onto a rest is accepted only if the snap lifts the centre of mass by at
#: most SNAP_RTOL times the rest height (dimensionless round-off allowance), i.e. if
#: E_ex >= -m |g_n| SNAP_RTOL h_rest: a rest above the body would create energy
SNAP_RTOL = 1e-12
# the pivot integrator's scratch is the joint solve's workspace Wb (2 MAXC x 2 MAXC)
assert (2 * MAXC) ** 2 >= N_W
N_CF = 13            # columns of the contact workspace c_f

# c_i columns: kernels/instant.py (CI_FEAT: the vertex row in verts)
# c_f columns
CF_NX, CF_NY, CF_PX, CF_PY, CF_RAX, CF_RAY, CF_RBX, CF_RBY = 0, 1, 2, 3, 4, 5, 6, 7
CF_VIN, CF_VIT, CF_PN, CF_PT, CF_VCMN = 8, 9, 10, 11, 12


def event_margin(toli, nb):
    """Free event rows the loop needs before it handles one more instant (evbuf)."""
    return int(evbuf.event_margin_py(int(toli[TI_SEQ_MAXSTEPS]), MAXC, nb))


def segment_margin(nb):
    """Free segment rows the loop needs before it handles one more instant (evbuf), plus
    the pieces of one integrated pivot pass (``pivot2d.PIECE_BUDGET``)."""
    return int(evbuf.segment_margin_py(MAXC, nb)) + PIECE_BUDGET


# ------------------------------------------------------------------ small helpers


@njit((_A1, _I2, _A2, _I1, _f, _i, _i, _i, _i, _i, _f, _f, _f, _f, _f, _f, _f, _f, _f, _f,
       _f), **_INNER)
def _log(ev_t, ev_i, ev_f, cnt, t, kind, a, b, mode, cluster, px, py, nx, ny, viN, viT,
         vfN, vfT, PN, PT, dE):
    k = cnt[evbuf.CN_EVENTS]
    ev_t[k] = t
    ev_i[k, 0] = kind
    ev_i[k, 1] = a
    ev_i[k, 2] = b
    ev_i[k, 3] = mode
    ev_i[k, 4] = cluster
    ev_f[k, 0] = px
    ev_f[k, 1] = py
    ev_f[k, 2] = nx
    ev_f[k, 3] = ny
    ev_f[k, 4] = viN
    ev_f[k, 5] = viT
    ev_f[k, 6] = vfN
    ev_f[k, 7] = vfT
    ev_f[k, 8] = PN
    ev_f[k, 9] = PT
    ev_f[k, 10] = dE
    cnt[evbuf.CN_EVENTS] = k + 1
    cnt[evbuf.CN_IDLE] = 0


@njit(cache=True, _nrt=False, inline="always")
def _push_seg(seg_t, seg_b, seg_s, cnt, st, tref, i):
    k = cnt[evbuf.CN_SEGS]
    seg_t[k] = tref[i]
    seg_b[k] = i
    for j in range(9):
        seg_s[k, j] = st[i, j]
    cnt[evbuf.CN_SEGS] = k + 1


@njit(cache=True, _nrt=False, inline="always")
def _push_row(seg_t, seg_b, seg_s, cnt, row, t, i):
    k = cnt[evbuf.CN_SEGS]
    seg_t[k] = t
    seg_b[k] = i
    for j in range(9):
        seg_s[k, j] = row[j]
    cnt[evbuf.CN_SEGS] = k + 1


@_inner
def _held_into(src, kind, nx, ny, out):
    """The motion of a body during a pending accumulation (Zeno) jump on the plane with
    normal n: ``out`` = the state row ``src`` with its normal velocity and normal
    acceleration removed, and (not for a disk) its rotation stopped. From the last impact
    to the accumulation time the body then stays at the height of that impact while its
    tangential motion is the exact free flight (the bounces of the accumulation do not
    change it); the reported trajectory never dips below the plane. ``src`` may be
    ``out``. The stepper keeps the true free-flight row in ``st`` (so that the "contact"
    event at the accumulation time reports the accumulated impulse and the energy
    removed) and uses this row for the trajectory and for the other candidate events."""
    for j in range(9):
        out[j] = src[j]
    vN = nx * out[3] + ny * out[4]
    out[3] -= vN * nx
    out[4] -= vN * ny
    aN = nx * out[6] + ny * out[7]
    out[6] -= aN * nx
    out[7] -= aN * ny
    if kind != SH_DISK:
        out[5] = 0.0
        out[8] = 0.0


@njit((_A1, _f, _i, _i, _f, _f, _f, _f, _f), **_INNER)
def _set_err(err, t, a, b, px, py, x1, x2, x3):
    err[0] = t
    err[1] = a
    err[2] = b
    err[3] = px
    err[4] = py
    err[5] = x1
    err[6] = x2
    err[7] = x3


@njit(cache=True, _nrt=False, inline="always")
def _point_vel(st, i, rx, ry):
    return st[i, VX] - st[i, OMEGA] * ry, st[i, VY] + st[i, OMEGA] * rx


@njit(cache=True, _nrt=False, inline="always")
def _w_body(m, inertia, rx, ry, nx, ny):
    tx = ny
    ty = -nx
    cn = rx * ny - ry * nx
    ct = rx * ty - ry * tx
    im = 1.0 / m
    iI = 1.0 / inertia
    return im + cn * cn * iI, cn * ct * iI, im + ct * ct * iI


@njit(cache=True, _nrt=False, inline="always")
def _energy(st, bflt, grav, i):
    """Energy (J) of body i: ``flight2d.body_energy`` (inlined: one compiled function less)."""
    return body_energy(st[i], bflt[i, B_MASS], bflt[i, B_INERTIA], grav[0], grav[1])


@njit(cache=True, _nrt=False, inline="always")
def _vz2(tolf, gabs):
    """Squared accumulation speed (m^2/s^2) for a normal acceleration magnitude gabs."""
    z = tolf[TF_ZENO_SPEED]
    if z >= 0.0:
        return z * z
    return 2.0 * gabs * tolf[TF_REST_LENGTH]


@njit(cache=True, _nrt=False, inline="always")
def _finite(st, i):
    for j in range(9):
        if not math.isfinite(st[i, j]):
            return False
    return True


# ------------------------------------------------------------------ contact geometry


@_inner
def _plane_contact(st, i, bint, bflt, verts, feat, nx, ny, shapes):
    """Contact point and arm (point minus centre of mass) of feature ``feat`` of body i
    against a plane with normal n, at the body's current state (``shapes``: the shape
    switch, None for disks only; the pivot and wedge handlers pass True, the type of the
    loop's True: one compiled function)."""
    if shapes is None or bint[i, B_KIND] == SH_DISK:
        rad = bflt[i, B_RADIUS]
        return st[i, X] - rad * nx, st[i, Y] - rad * ny, -rad * nx, -rad * ny
    c = math.cos(st[i, ANGLE])
    s = math.sin(st[i, ANGLE])
    if bint[i, B_KIND] == SH_ELLIPSE:
        ea = bflt[i, B_EA]
        eb = bflt[i, B_EB]
        nbx = c * nx + s * ny
        nby = -s * nx + c * ny
        hh = math.sqrt(ea * ea * nbx * nbx + eb * eb * nby * nby)
        sbx = -ea * ea * nbx / hh
        sby = -eb * eb * nby / hh
        rx = c * sbx - s * sby
        ry = s * sbx + c * sby
    else:
        px = verts[feat, 0]
        py = verts[feat, 1]
        rad = bflt[i, B_RADIUS]
        rx = c * px - s * py - rad * nx
        ry = s * px + c * py - rad * ny
    return st[i, X] + rx, st[i, Y] + ry, rx, ry


@njit(cache=True, _nrt=False, inline="always")
def _contact_velocity(st, c_i, c_f, c):
    nx = c_f[c, CF_NX]
    ny = c_f[c, CF_NY]
    a = c_i[c, CI_A]
    ux, uy = _point_vel(st, a, c_f[c, CF_RAX], c_f[c, CF_RAY])
    if c_i[c, CI_TYPE] == 1:
        wx, wy = _point_vel(st, c_i[c, CI_B], c_f[c, CF_RBX], c_f[c, CF_RBY])
        ux -= wx
        uy -= wy
    return ux * nx + uy * ny, ux * ny - uy * nx


@njit(cache=True, _nrt=False, inline="always")
def _contact_W(bflt, c_i, c_f, c, W2):
    nx = c_f[c, CF_NX]
    ny = c_f[c, CF_NY]
    a = c_i[c, CI_A]
    wnn, wnt, wtt = _w_body(bflt[a, B_MASS], bflt[a, B_INERTIA], c_f[c, CF_RAX], c_f[c,
                            CF_RAY], nx, ny)
    if c_i[c, CI_TYPE] == 1:
        b = c_i[c, CI_B]
        bnn, bnt, btt = _w_body(bflt[b, B_MASS], bflt[b, B_INERTIA], c_f[c, CF_RBX], c_f[c,
                                CF_RBY], nx, ny)
        wnn += bnn
        wnt += bnt
        wtt += btt
    W2[0, 0] = wnn
    W2[0, 1] = wnt
    W2[1, 0] = wnt
    W2[1, 1] = wtt


@njit(cache=True, _nrt=False, inline="always")
def _apply(st, bflt, c_i, c_f, c, PN, PT):
    nx = c_f[c, CF_NX]
    ny = c_f[c, CF_NY]
    jx = PN * nx + PT * ny
    jy = PN * ny - PT * nx
    a = c_i[c, CI_A]
    m = bflt[a, B_MASS]
    st[a, VX] += jx / m
    st[a, VY] += jy / m
    st[a, OMEGA] += (c_f[c, CF_RAX] * jy - c_f[c, CF_RAY] * jx) / bflt[a, B_INERTIA]
    if c_i[c, CI_TYPE] == 1:
        b = c_i[c, CI_B]
        m = bflt[b, B_MASS]
        st[b, VX] -= jx / m
        st[b, VY] -= jy / m
        st[b, OMEGA] -= (c_f[c, CF_RBX] * jy - c_f[c, CF_RBY] * jx) / bflt[b, B_INERTIA]


@_inner
def _gap_accel(st, bint, bflt, c_i, c_f, c, verts, grav, shapes):
    """Second time derivative (m/s^2) of the contact's gap in free flight, now (``shapes``:
    the shape switch, None for disks only; True from ``_hold_two``, as ``_plane_contact``)."""
    nx = c_f[c, CF_NX]
    ny = c_f[c, CF_NY]
    a = c_i[c, CI_A]
    if c_i[c, CI_TYPE] == 1:
        b = c_i[c, CI_B]
        dvx = st[a, VX] - st[b, VX]
        dvy = st[a, VY] - st[b, VY]
        vt = dvx * ny - dvy * nx
        dist = bflt[a, B_RADIUS] + bflt[b, B_RADIUS]
        return nx * (st[a, AX] - st[b, AX]) + ny * (st[a, AY] - st[b, AY]) + vt * vt / dist
    gn = nx * st[a, AX] + ny * st[a, AY]
    w = st[a, OMEGA]
    if shapes is not None and bint[a, B_KIND] == SH_ELLIPSE:
        ea = bflt[a, B_EA]
        eb = bflt[a, B_EB]
        c = math.cos(st[a, ANGLE])
        s = math.sin(st[a, ANGLE])
        nbx = c * nx + s * ny
        nby = -s * nx + c * ny
        hh, dh = ellipse_support(st[a, ANGLE], ea, eb, nx, ny)
        d2h = (ea * ea - eb * eb) * (nby * nby - nbx * nbx) / hh - dh * dh / hh
        return gn - d2h * w * w
    rad = bflt[a, B_RADIUS]
    np_ = nx * c_f[c, CF_RAX] + ny * c_f[c, CF_RAY] + rad   # n . R p
    return gn - w * w * np_


@njit(cache=True, _nrt=False, inline="always")
def _reach(i, bint, bflt, c_f, c):
    """Reach (m) of body i's plane contact c from its centre: the arm to the contact point
    plus the rounding radius; an ellipse's larger semi-axis."""
    if bint[i, B_KIND] == SH_ELLIPSE:
        return max(bflt[i, B_EA], bflt[i, B_EB])
    return math.hypot(c_f[c, CF_RAX], c_f[c, CF_RAY]) + bflt[i, B_RADIUS]


@_inner
def _body_size(i, bint, bflt, verts):
    """Body i's reach (m): the farthest core vertex from its centre plus the rounding radius
    (``pair2d_shape.body_reach``; an ellipse: its larger semi-axis plus ``B_RADIUS``)."""
    K1, _ = body_reach(bint[i, B_KIND], bflt[i, B_RADIUS], bflt[i, B_EA], bflt[i, B_EB],
                       verts, bint[i, B_FIRST], bint[i, B_COUNT])
    return K1 + bflt[i, B_RADIUS]


@njit(cache=True, _nrt=False, inline="always")
def _body_zero_speed(i, row, bint, bflt, verts, tolf):
    """The zero speed (m/s) of a rate computed from body i's motion ``row`` alone:
    ``pair_zero_speed`` of its speed ``|v| + |omega| reach`` (2D ``simul_tol`` relative)."""
    sp = math.hypot(row[VX], row[VY]) + abs(row[OMEGA]) * _body_size(i, bint, bflt, verts)
    return pair_zero_speed(sp, tolf[TF_SIMUL_TOL] * sp)


@_inner
def _frame(i, thi, j, dx, dy, thj, bint, bflt, verts):
    """``pair2d.frame_rel`` of bodies i and j (angles thi, thj; j's centre at (dx, dy) from
    i's): ``(g, nx, ny, pAx, pAy, pBx, pBy, fa, ia, fb, ib)``, witness points relative to
    i's centre, the normal from j into i."""
    return frame_rel(bint[i, B_KIND], bflt[i, B_RADIUS], bflt[i, B_EA], bflt[i, B_EB], verts,
                     bint[i, B_FIRST], bint[i, B_COUNT], thi, bint[j, B_KIND],
                     bflt[j, B_RADIUS], bflt[j, B_EA], bflt[j, B_EB], verts, bint[j, B_FIRST],
                     bint[j, B_COUNT], dx, dy, thj)


# ------------------------------------------------------------------ candidates


@njit(cache=True, _nrt=False, inline="always")
def _recompute_planes(pivot, shapes, i, t_now, st, tref, bint, bflt, verts, planes, pm, tz, zp,
                      bp_t, bp_off, tolf, toli, tmp, err):
    """Next impact time of body i (state at t_now) against every plane (during a pending
    accumulation jump: of its held motion, see ``_held_into``; ``tmp[0]`` scratch).
    ``shapes`` None (disks only): the closed form of ``toi2d.disk_plane_toi``."""
    S = tolf[TF_T_END] - t_now
    kind = FEAT_ELLIPSE if bint[i, B_KIND] == SH_ELLIPSE else FEAT_VERTEX
    v0 = bint[i, B_FIRST]
    nv = bint[i, B_COUNT]
    rad = bflt[i, B_RADIUS]
    ea = bflt[i, B_EA]
    eb = bflt[i, B_EB]
    row = st[i]
    if pm[i, M_MODE] == PM_PIVOT or pm[i, M_MODE] == PM_WEDGED or pm[i, M_MODE] == PM_CLUSTER:
        # integrated contact: its impacts are events of the integration (ttr); a wedged
        # body does not move (a cluster: its candidates)
        for p in range(planes.shape[0]):
            bp_t[i, p] = INF
        return 0
    rel = pm[i, M_MODE] == PM_FLIGHT and pm[i, M_AUX] == REL_TANGENT
    if tz[i] < INF:
        _held_into(st[i], bint[i, B_KIND], planes[zp[i], 0], planes[zp[i], 1], tmp[0])
        row = tmp[0]
    for p in range(planes.shape[0]):
        if (bp_off[i, p] != 0 or (pm[i, M_MODE] != PM_FLIGHT and pm[i, M_PLANE] == p)
                or (tz[i] < INF and zp[i] == p)):
            bp_t[i, p] = INF
            continue
        nx = planes[p, 0]
        ny = planes[p, 1]
        d = planes[p, 2]
        best = INF
        for k in range(nv):
            if rel and p == pm[i, M_PLANE] and k == pm[i, M_FEAT]:
                # released from a held contact (only bodies that pivot are released so)
                if pivot is None:
                    return _not_compiled(err, t_now, i, FEATURE_PIVOT)
                if kind == FEAT_ELLIPSE:
                    s, code = _released_toi_ellipse(row, ea, eb, nx, ny, d, t_now, S, tolf,
                                                    toli, tmp[1])
                else:
                    s, code = _released_toi(row, verts[v0 + k, 0], verts[v0 + k, 1], rad,
                                            nx, ny, d, t_now, S, tolf, toli, tmp[1])
            elif shapes is None:
                s, code = disk_plane_toi(row, rad, nx, ny, d, S, tolf[TF_GAP_TOL])
            else:
                s, code = plane_feature_toi(kind, row, verts[v0 + k, 0], verts[v0 + k, 1],
                                            rad, ea, eb, nx, ny, d, t_now, S,
                                            tolf[TF_TOI_RTOL], tolf[TF_TOI_ATOL],
                                            tolf[TF_GAP_TOL], toli[TI_TOI_MAXIT])
            if code == TOI_MISSED:
                _set_err(err, t_now, i, -1 - p, st[i, X], st[i, Y], k, 0.0, 0.0)
                return ERR_MISSED
            if code == TOI_NOT_CONVERGED:
                _set_err(err, t_now, i, -1 - p, st[i, X], st[i, Y], k, s, 0.0)
                return ERR_TOI
            if s < best:
                best = s
        bp_t[i, p] = t_now + best
    if rel:
        pm[i, M_AUX] = -1
    return 0


@_inner
def _released_toi(row, px, py, rad, nx, ny, d, t0, S, tolf, toli, tmp):
    """Next impact (s after t0, code) of the vertex p (radius rad) of a body released from
    the plane (n, d) at t0 with its normal force vanishing: its free-flight gap starts at a
    third-order tangency, ``g(0) = g'(0) = g''(0) = 0`` (to round-off), where conservative
    advancement cannot leave zero. In flight ``g(s) = n.x(s) - d - rad + rho(s)`` with
    ``n.x`` exactly quadratic and ``rho(s) = n . R(angle0 + w s) p``, so
    ``g(s) >= g3 s^3 / 6 - M4 s^4 / 24`` (``g3 = -w^3 n.J R p``, ``M4 = w^4 |p|``) up to the
    round-off terms: the gap is positive on ``(0, s0]``, ``s0 = 2 g3 / M4`` (there the bound
    is ``g3 s0^3 / 12 > 0``), and the search starts at ``s0``. When ``g3 <= 0`` (no
    separation at third order) the ordinary search runs from 0."""
    c = math.cos(row[ANGLE])
    sn = math.sin(row[ANGLE])
    rx = c * px - sn * py
    ry = sn * px + c * py
    w = row[OMEGA]
    g3 = -w * w * w * (ny * rx - nx * ry)
    M4 = w * w * w * w * math.hypot(px, py)
    return _search_past(row, g3, M4, FEAT_VERTEX, px, py, rad, 0.0, 0.0, nx, ny, d, t0, S,
                        tolf, toli, tmp)


@_inner
def _released_toi_ellipse(row, ea, eb, nx, ny, d, t0, S, tolf, toli, tmp):
    """``_released_toi`` for an ellipse released from the plane (n, d) at t0 (its held
    contact's normal force vanished): in flight ``g(s) = n.x(s) - d - h(angle0 + w s)``
    (``h`` the support, ``pivot2d.ellipse_support3``) with ``n.x`` exactly quadratic and
    ``g(0) = g'(0) = g''(0) = 0`` (to round-off), so ``g(s) >= g3 s^3 / 6 - M4 s^4 / 24``
    with ``g3 = -h3 w^3``, ``M4 = w^4 B4`` and ``B4 >= |h4|`` over all angles (``hk`` the
    k-th derivative of ``h`` in the angle). The radius of curvature at the contact point is
    ``h + h2 = P / h^3``, ``P = a^2 b^2``, so ``h3 = -h1 (1 + 3 P / h^4)`` and
    ``h4 = -h2 (1 + 3 P / h^4) + 12 P h1^2 / h^5``; with ``hm = min(a, b) <= h <= hM =
    max(a, b)``: ``|h1| <= (hM^2 - hm^2) / (2 hm)``, ``|h2| <= (hM^2 - hm^2) / hm``. The
    search starts at ``s0 = 2 g3 / M4`` (the gap is positive on ``(0, s0]``); from 0 when
    ``g3 <= 0``."""
    w = row[OMEGA]
    h, h1, h2 = ellipse_support3(ea, eb, row[ANGLE], nx, ny)
    P = ea * ea * eb * eb
    hm = min(ea, eb)
    hM = max(ea, eb)
    g3 = w * w * w * h1 * (1.0 + 3.0 * P / (h * h * h * h))
    K1 = (hM * hM - hm * hm) / (2.0 * hm)
    K2 = (hM * hM - hm * hm) / hm
    hm4 = hm * hm * hm * hm
    B4 = K2 * (1.0 + 3.0 * P / hm4) + 12.0 * P * K1 * K1 / (hm4 * hm)
    M4 = w * w * w * w * B4
    return _search_past(row, g3, M4, FEAT_ELLIPSE, 0.0, 0.0, 0.0, ea, eb, nx, ny, d, t0, S,
                        tolf, toli, tmp)


@njit(cache=True, _nrt=False, inline="always")
def _search_past(row, g3, M4, kind, px, py, rad, ea, eb, nx, ny, d, t0, S, tolf, toli, tmp):
    """The flight search of a feature released at t0 with ``g(s) >= g3 s^3 / 6 - M4 s^4 /
    24``: from ``s0 = 2 g3 / M4`` (the gap is positive on ``(0, s0]``), from 0 when
    ``g3 <= 0``. Returns ``(s, code)`` as ``plane_feature_toi``."""
    s0 = 0.0
    src = row
    if g3 > 0.0 and M4 > 0.0:
        s0 = 2.0 * g3 / M4
        if s0 >= S:
            return INF, TOI_OK
        fly_into(row, s0, tmp)
        src = tmp
    # int64(kind): not the literal FEAT_* of the caller (one compiled plane_feature_toi, not
    # one per literal)
    s, code = plane_feature_toi(int64(kind), src, px, py, rad, ea, eb, nx, ny, d, t0 + s0,
                                S - s0, tolf[TF_TOI_RTOL], tolf[TF_TOI_ATOL], tolf[TF_GAP_TOL],
                                toli[TI_TOI_MAXIT])
    return s0 + s, code


@_inner
def _recompute_pair(pgen, q, t_now, st, tref, bint, bflt, verts, planes, pairs, pm, tz, zp,
                    ttr, bp_t, pr_t, pr_off, tolf, toli, tmp, err, cid, grav, cw, bmark, ccon,
                    law_par):
    """Next impact time of body pair q (states at t_now). Two disks: closed form
    (``toi2d.disk_disk_toi``); any other pair of shapes (``pgen``: the general pair switch,
    True, or None in a loop compiled for disk pairs only): ``pair2d_toi.pair_toi``; right
    after an impact of the pair (``pr_off[q] == PR_HIT``) the persistence check of
    ``_pair_persists`` (two disks: its re-contact rule, on the closed form). A pair with a
    body in integrated motion is not searched: a moving cluster's member by
    ``_held_cluster_pair``, a body held by one pivot contact at its passes
    (``_pivot_partners``); two held bodies, or one held on two planes: ``PP_HELD``."""
    if pr_off[q] == PR_OFF:
        pr_t[q] = INF
        return 0
    hit = pr_off[q] == PR_HIT or pr_off[q] == PR_WAIT
    rel = pr_off[q] == PR_REL
    pr_off[q] = PR_ON
    a = pairs[q, 0]
    b = pairs[q, 1]
    # persistent body-body contact (PM_CLUSTER): a pair inside the cluster is its
    # contact or candidate; a pair with one body in a moving cluster has no closed-form
    # motion to search (refused, PP_HELD); a frozen cluster's bodies are at rest
    ina = pm[a, M_MODE] == PM_CLUSTER
    inb = pm[b, M_MODE] == PM_CLUSTER
    if ina and inb:
        pr_t[q] = INF
        if cid[CL_FROZEN] == 0 and not _cl_watched(q, cid, st.shape[0]):
            return _member_pair(pgen, q, a, b, st, tref, bint, bflt, verts, pairs, pr_t, tolf,
                                cid, grav, cw, ccon, law_par)
        return 0
    if (ina or inb) and cid[CL_FROZEN] == 0:
        i = a if ina else b
        o = b if ina else a
        return _held_cluster_pair(pgen, q, i, o, bmark[o] != 0 and bmark[i] == 0, t_now, st,
                                  tref, bint, bflt, verts, planes, pairs, pm, tz, zp, ttr,
                                  bp_t, pr_t, pr_off, tolf, tmp, err, cid, grav, cw)
    disks = bint[a, B_KIND] == SH_DISK and bint[b, B_KIND] == SH_DISK
    if not disks:
        pa = pm[a, M_MODE] == PM_PIVOT
        pb = pm[b, M_MODE] == PM_PIVOT
        if pa or pb:
            # a body held by one pivot contact and a body in closed-form motion: bounded
            # at each of its passes (_pivot_partners), not searched; a body held on two
            # planes is refused (no safe bound on its motion), and so are two held bodies
            # unless their own impact left them touching (below: a cluster)
            i = a if pa else b
            o = b if pa else a
            both = pa and pb
            if (pm[i, M_PLANE2] >= 0 or pm[o, M_MODE] == PM_WEDGED
                    or (both and (pm[o, M_PLANE2] >= 0 or tref[o] != t_now))):
                _set_err(err, t_now, a, b, st[i, X], st[i, Y], PP_HELD, float(i), 0.0)
                return ERR_PERSISTENT_PAIR
            if hit and tref[i] == t_now:
                # the pair's impact just now, the body held again at t: touching with a
                # normal rate that is zero (pair_zero_speed: the impacts have accumulated
                # to round-off; a real bounce flies and meets again at a later pass), a
                # persistent contact: a cluster from the next pass (run_loop; the pivot
                # contact becomes its plane row; both pivot contacts when both bodies are
                # held at t, a domino falling onto the next one)
                fly_into(st[o], t_now - tref[o], tmp[1])
                g, nx, ny = _cl_gap(pgen, i, st[i], o, tmp[1], bint, bflt, verts)
                v = _cl_gap_rate(pgen, i, st[i], o, tmp[1], bint, bflt, verts, nx, ny)
                sp = (math.hypot(st[i, VX], st[i, VY]) + math.hypot(tmp[1, VX], tmp[1, VY])
                      + abs(st[i, OMEGA]) * _body_size(i, bint, bflt, verts)
                      + abs(tmp[1, OMEGA]) * _body_size(o, bint, bflt, verts))
                if (g <= tolf[TF_GAP_TOL]
                        and abs(v) <= pair_zero_speed(sp, tolf[TF_SIMUL_TOL] * sp)):
                    _pend(q, pr_t, pr_off, cid)
                    return 0
            if both:
                # two bodies held at t, apart or parting (a domino and the one after the
                # next, or two dominoes that this instant's impact parts): no bound on both
                # motions; a cluster entered at t may take both in, the pair one of its
                # candidates (else ``_recompute_pairs`` refuses)
                pr_off[q] = PR_WAIT
            pr_t[q] = INF
            if bmark[o] != 0 and bmark[i] == 0:
                # o's own event: the guard of a pass of i that ran ahead (_held_pair); the
                # bound itself is taken at i's next pass (_pivot_partners)
                m = bflt[i, B_MASS]
                K = 0.5 * (m * (st[i, VX] ** 2 + st[i, VY] ** 2)
                           + bflt[i, B_INERTIA] * st[i, OMEGA] ** 2)
                rc, meet, tn = _held_pair(pgen, i, o, True, t_now, K, m, st, tref, bint,
                                          bflt, verts, planes, pairs, pm, tz, zp, ttr, bp_t,
                                          pr_t, tolf, tmp, err, grav)
                return rc
            return 0
    # a body in a pending accumulation jump moves with its held motion
    for j in range(2):
        i = a if j == 0 else b
        if tz[i] < INF:
            _held_into(st[i], bint[i, B_KIND], planes[zp[i], 0], planes[zp[i], 1], tmp[j])
            fly_into(tmp[j], t_now - tref[i], tmp[j])
        else:
            fly_into(st[i], t_now - tref[i], tmp[j])
    # no search past the next scheduled event of either body after t_now (a plane impact,
    # an accumulation point, a transition): that event marks the body, and its pairs are
    # searched again from there (run_loop: planes first, then _recompute_pairs)
    tl = _next_event(b, t_now, _next_event(a, t_now, tolf[TF_T_END], tz, ttr, bp_t), tz, ttr,
                     bp_t)
    S = tl - t_now
    if disks:
        R = bflt[a, B_RADIUS] + bflt[b, B_RADIUS]
        s0 = 0.0
        if rel:
            # released from persistent contact at a tangency of order three: search from
            # the first s0 (doubling from REL_S0 sqrt(R / |g|)) where the gap and its rate
            # are both positive (a re-contact within s0 of the release is not seen)
            s0 = _released_pair_s0(tmp, R, S, tolf[TF_GAP_TOL])
        d0 = tmp[0, X] - tmp[1, X]
        d1 = tmp[0, Y] - tmp[1, Y]
        u0 = tmp[0, VX] - tmp[1, VX]
        u1 = tmp[0, VY] - tmp[1, VY]
        dist = math.sqrt(d0 * d0 + d1 * d1)
        un = (d0 * u0 + d1 * u1) / dist
        if dist - R <= tolf[TF_GAP_TOL] and un != 0.0 and touching_rate(un, math.hypot(
                tmp[0, VX], tmp[0, VY]) + math.hypot(tmp[1, VX], tmp[1, VY])) == 0.0:
            # touching at a normal rate that is round-off: zero (decisions.TOUCH_RTOL; the
            # rule of the 3D sphere pair): two disks that a sticking plastic impact left
            # touching part (their centres slide past each other), whatever the sign of
            # the rate's round-off
            u0 -= un * d0 / dist
            u1 -= un * d1 / dist
        s, code = disk_disk_toi(d0, d1, u0, u1, tmp[0, AX] - tmp[1, AX],
                                tmp[0, AY] - tmp[1, AY], R, t_now + s0, S - s0,
                                tolf[TF_TOI_RTOL], tolf[TF_TOI_ATOL], tolf[TF_GAP_TOL],
                                toli[TI_TOI_MAXIT])
        s += s0
        if hit and code == TOI_OK and s < INF:
            # the rule of _pair_persists on the closed form: a re-contact within a rise of
            # rest_length (s = 0: a round-off approach left by a plastic impact) is the
            # bodies staying in contact
            dx = tmp[0, X] - tmp[1, X]
            dy = tmp[0, Y] - tmp[1, Y]
            dist = math.sqrt(dx * dx + dy * dy)
            v = (dx * (tmp[0, VX] - tmp[1, VX]) + dy * (tmp[0, VY] - tmp[1, VY])) / dist
            sp = (math.hypot(tmp[0, VX], tmp[0, VY]) + math.hypot(tmp[1, VX], tmp[1, VY])
                  + abs(tmp[0, OMEGA]) * bflt[a, B_RADIUS]
                  + abs(tmp[1, OMEGA]) * bflt[b, B_RADIUS])
            vz = pair_zero_speed(sp, tolf[TF_SIMUL_TOL] * sp)
            if pair_persistence(v, s, True, vz, INF, tolf[TF_REST_LENGTH]) == PP_CHATTER:
                # the pair stays in contact: a cluster from the next pass (run_loop)
                _pend(q, pr_t, pr_off, cid)
                return 0
    elif pgen is None:      # pruned by type: a loop for disk pairs compiles no pair_toi
        return _not_compiled(err, t_now, a, FEATURE_PAIR)
    else:
        s0 = 0.0
        if rel:
            # released from persistent contact (a cluster contact lifted at g = g' = 0):
            # searched from where the gap exceeds gap_tol and grows, as two disks
            s0 = _released_general_s0(a, b, tmp, bint, bflt, verts, S, tolf[TF_GAP_TOL])
        s, code = pair_toi(bint[a, B_KIND], bflt[a, B_RADIUS], bflt[a, B_EA], bflt[a, B_EB],
                           verts, bint[a, B_FIRST], bint[a, B_COUNT], tmp[0],
                           bint[b, B_KIND], bflt[b, B_RADIUS], bflt[b, B_EA], bflt[b, B_EB],
                           verts, bint[b, B_FIRST], bint[b, B_COUNT], tmp[1], t_now + s0,
                           S - s0, tolf[TF_TOI_RTOL], tolf[TF_TOI_ATOL], tolf[TF_GAP_TOL],
                           toli[TI_TOI_MAXIT])
        s += s0
        touching = False
        if code == TOI_NOT_CONVERGED:
            # a search that crawls from a touching state (a pair that a near-plastic impact
            # left parting at ~1e-11 m/s while both spin, scheduled again at that rate):
            # an accumulation when decisions.pair_crawl_chatters says so (_pair_persists)
            touching = _frame(a, tmp[0, ANGLE], b, tmp[1, X] - tmp[0, X], tmp[1, Y] - tmp[0, Y],
                              tmp[1, ANGLE], bint, bflt, verts)[0] <= tolf[TF_GAP_TOL]
        # a joint accumulation: the pair's search ends, without an impact (or crawls from
        # touching), before one of its bodies' next events (a plane impact) within the
        # flight of a bounce that rises less than rest_length (the single point's rule,
        # 2 vz / |g|): the pair and that plane contact accumulate together (a box under a
        # box bouncing on the floor at round-off speeds: the pair's own motion, both in
        # free fall, shows no re-contact), judged on the pair's gap rate by the same speed
        gz = math.hypot(grav[0], grav[1])
        vz2 = _vz2(tolf, gz)
        joint = ((hit or touching) and gz > 0.0 and tl < tolf[TF_T_END]
                 and S * S * gz * gz <= 4.0 * vz2
                 and ((code == TOI_OK and s == INF) or code == TOI_NOT_CONVERGED))
        if hit or touching:
            rc = _pair_persists(a, b, t_now, s, code, bint, bflt, verts, tmp, tolf, err,
                                touching, joint, vz2)
            if rc < 0:
                if err[5] == PP_CHATTER or err[5] == PP_TOGETHER:
                    # bodies that stay in contact: a cluster from the next pass (run_loop)
                    _pend(q, pr_t, pr_off, cid)
                    return 0
                return rc
    if code == TOI_MISSED:
        _set_err(err, t_now, a, b, tmp[0, X], tmp[0, Y], 0.0, 0.0, 0.0)
        return ERR_MISSED
    if code == TOI_NOT_CONVERGED:
        _set_err(err, t_now, a, b, tmp[0, X], tmp[0, Y], 0.0, s, 0.0)
        return ERR_TOI
    pr_t[q] = t_now + s
    return 0


@_inner
def _next_event(i, t0, tl, tz, ttr, bp_t):
    """The earliest of tl and body i's scheduled events after t0 (its accumulation point,
    its transition or pass, its plane impacts), s."""
    if t0 < tz[i] < tl:
        tl = tz[i]
    if t0 < ttr[i] < tl:
        tl = ttr[i]
    for p in range(bp_t.shape[1]):
        if t0 < bp_t[i, p] < tl:
            tl = bp_t[i, p]
    return tl


@_inner
def _pend_joins(q, qp, pairs):
    """Pair q, whose impacts accumulate while pair qp's entry is pending, shares a body with
    it: the entry's gather (bodies touching within gap_tol, ``_cluster_enter``) takes q in
    too. (Apart, two clusters would be needed: not built, the caller refuses.)"""
    return (q == qp or pairs[q, 0] == pairs[qp, 0] or pairs[q, 0] == pairs[qp, 1]
            or pairs[q, 1] == pairs[qp, 0] or pairs[q, 1] == pairs[qp, 1])


@_inner
def _released_pair_s0(tmp, R, S, gtol):
    """Offset s0 (s) from which to search a pair of disks just released from persistent
    contact (rows tmp[0], tmp[1] at the release, moved to s0 in place): the first of
    ``REL_S0 T 2^k`` (``T = sqrt(R / |a|)``, a the relative acceleration, or R / |v|) where
    the gap exceeds gap_tol and grows, at most S (a tangency of order three: searched from
    a gap of zero, the conservative advancement would crawl)."""
    da = math.hypot(tmp[0, AX] - tmp[1, AX], tmp[0, AY] - tmp[1, AY])
    dv = math.hypot(tmp[0, VX] - tmp[1, VX], tmp[0, VY] - tmp[1, VY])
    T = math.sqrt(R / da) if da > 0.0 else (R / dv if dv > 0.0 else S)
    s = REL_S0 * T
    for _ in range(60):
        if s >= S:
            s = S
            break
        h = 0.5 * s * s
        dx = tmp[0, X] - tmp[1, X] + (tmp[0, VX] - tmp[1, VX]) * s + (tmp[0, AX] - tmp[1, AX]) * h
        dy = tmp[0, Y] - tmp[1, Y] + (tmp[0, VY] - tmp[1, VY]) * s + (tmp[0, AY] - tmp[1, AY]) * h
        ux = tmp[0, VX] - tmp[1, VX] + (tmp[0, AX] - tmp[1, AX]) * s
        uy = tmp[0, VY] - tmp[1, VY] + (tmp[0, AY] - tmp[1, AY]) * s
        if math.hypot(dx, dy) - R > gtol and dx * ux + dy * uy > 0.0:
            break
        s *= 2.0
    fly_into(tmp[0], s, tmp[0])
    fly_into(tmp[1], s, tmp[1])
    return s


#: a pair with one body in a moving cluster is searched again (the cluster's pass ends)
#: after this fraction of the time its distance bound guarantees (``_held_cluster_pair``)
HELD_CHECK = 0.5
#: ... and meets (an impact instant, the cluster dissolving into it) when, at a pass end,
#: its gap is below this fraction of the smaller body's size and closes: the advancement
#: stops short of the touch by that gap, so the impact time is early by at most
#: ``gap / closing speed`` (dimensionless)
HELD_TOUCH = 1e-11
#: ... and refused (``PP_HELD``) when the member's state is not at the pass end (another
#: body's event inside a pass that has run ahead) and the bound leaves less than this
#: fraction of the outside body's size between them
HELD_NEAR = 1e-3
#: two members of a moving cluster without rows closer than this fraction of the smaller
#: body's size are watched by the rows of their nearest features (``_member_pair``)
HELD_WATCH = 1e-3
HB_APART = 0    # _held_bound: apart, bounded
HB_IMPACT = 1   # ... touching and closing: an impact now
HB_REST = 2     # ... touching at a rate below the accumulation speed: persistent contact


@_inner
def _held_bound(pgen, i, o, K, M, st, tref, bint, bflt, verts, planes, pairs, tz, zp, ttr,
                bp_t, pr_t, tolf, tmp, grav):
    """Body i in integrated motion (a cluster member, or held by a pivot contact; its state
    at ``ti = tref[i]``, the end of its last pass) and body o in closed-form motion, brought
    to ti (``tmp[1]``): a distance bound (``stepper3d._held_pair``'s). K (J) is the kinetic
    energy of i's integrated system, M (kg) its mass: K can only grow by the work of
    gravity, ``dK/dt <= |g| sqrt(M 2K)`` (contact forces with planes do no work, friction
    dissipates, internal forces cancel), so ``sqrt(2K)`` grows by at most ``|g| sqrt(M)
    tau`` and every point of i moves slower than ``sqrt(2K) (1 / sqrt(m) + R / sqrt(I))``
    (R its reach). Body o's points move slower than ``|v| + |omega| R``, growing by
    ``|a| + |alpha| R``. While the sum of their displacements stays below the gap g0
    they cannot meet. Returns ``(kind, tn, g0, u, co, Ro)``: kind ``HB_IMPACT`` when they
    touch (g0 below ``HELD_TOUCH`` of the smaller size) and close, ``HB_REST`` when they
    touch at a rate below the accumulation speed, else ``HB_APART`` and tn, the time by
    which i's next pass must end: ``HELD_CHECK`` of the guaranteed time, and no later than
    o's next event (its motion changes there); u the sum of the speed bounds at ti (m/s),
    co o's growth (m/s^2), Ro its size (m)."""
    ti = tref[i]
    if tz[o] < INF:
        _held_into(st[o], bint[o, B_KIND], planes[zp[o], 0], planes[zp[o], 1], tmp[1])
        fly_into(tmp[1], ti - tref[o], tmp[1])
    else:
        fly_into(st[o], ti - tref[o], tmp[1])
    g0, nx, ny = _cl_gap(pgen, i, st[i], o, tmp[1], bint, bflt, verts)
    Ri = _body_size(i, bint, bflt, verts)
    Ro = _body_size(o, bint, bflt, verts)
    touch = HELD_TOUCH * min(Ri, Ro)
    if g0 <= touch:
        # touching: an impact if they close faster than the accumulation speed (the
        # single point's rule, _vz2), a persistent contact if they close slower or part
        # no faster than the rate's round-off (pair_zero_speed of the speeds it is
        # computed from); parting faster: apart (the next pass crosses the touch distance)
        v = _cl_gap_rate(pgen, i, st[i], o, tmp[1], bint, bflt, verts, nx, ny)
        sp = (math.hypot(st[i, VX], st[i, VY]) + math.hypot(tmp[1, VX], tmp[1, VY])
              + abs(st[i, OMEGA]) * Ri + abs(tmp[1, OMEGA]) * Ro)
        if v < 0.0 and v * v > _vz2(tolf, math.hypot(grav[0], grav[1])):
            return HB_IMPACT, ti, g0, 0.0, 0.0, Ro
        if v <= pair_zero_speed(sp, tolf[TF_SIMUL_TOL] * sp):
            return HB_REST, ti, g0, 0.0, 0.0, Ro
    beta = 1.0 / math.sqrt(bflt[i, B_MASS]) + Ri / math.sqrt(bflt[i, B_INERTIA])
    ui = math.sqrt(2.0 * K) * beta
    ci = math.hypot(grav[0], grav[1]) * math.sqrt(M) * beta
    uo = math.hypot(tmp[1, VX], tmp[1, VY]) + abs(tmp[1, OMEGA]) * Ro
    co = math.hypot(tmp[1, AX], tmp[1, AY]) + abs(tmp[1, ALPHA]) * Ro
    # touching and not closing (parting after their impact): the next pass is at least
    # as long as the time to cross the touch distance
    d = max(g0, touch)
    B = ui + uo
    C = ci + co
    sg = 2.0 * d / (B + math.sqrt(B * B + 2.0 * C * d)) if B + C > 0.0 else INF
    tn = _next_event(o, ti, ti + HELD_CHECK * sg, tz, ttr, bp_t)
    for q2 in range(pairs.shape[0]):
        if (pairs[q2, 0] == o or pairs[q2, 1] == o) and ti < pr_t[q2] < tn:
            tn = pr_t[q2]
    return HB_APART, tn, g0, ui + uo, co, Ro


@_inner
def _held_pair(pgen, i, o, moved, t_now, K, M, st, tref, bint, bflt, verts, planes, pairs,
               pm, tz, zp, ttr, bp_t, pr_t, tolf, tmp, err, grav):
    """Body i in integrated motion (a moving cluster's member, or held by a pivot contact)
    and body o outside it (``_held_bound``, with K and M those of i's system), at t_now
    (``moved``: o was marked by its own event, i was not). Returns ``(rc, kind, tn)``:
    rc 0 or ``ERR_PERSISTENT_PAIR`` (``PP_HELD``) when o is held by an integrated contact
    itself, or when o's motion changed inside a pass of i that had run ahead to tref[i]
    (not expected: passes end at o's known events) and the speed bounds over that stretch
    leave less than ``HELD_NEAR`` of o's size between them; kind: ``_held_bound``'s at
    tref[i]; tn: the end of i's next pass."""
    if pm[o, M_MODE] == PM_PIVOT or pm[o, M_MODE] == PM_WEDGED:
        _set_err(err, t_now, i, o, st[o, X], st[o, Y], PP_HELD, float(o), 0.0)
        return ERR_PERSISTENT_PAIR, HB_APART, INF
    kind, tn, g0, u, co, Ro = _held_bound(pgen, i, o, K, M, st, tref, bint, bflt, verts,
                                          planes, pairs, tz, zp, ttr, bp_t, pr_t, tolf, tmp,
                                          grav)
    tau = tref[i] - t_now
    if (kind == HB_APART and moved and tau > 0.0
            and not g0 - u * tau - 0.5 * co * tau * tau > HELD_NEAR * Ro):
        _set_err(err, t_now, i, o, st[i, X], st[i, Y], PP_HELD, float(i), 0.0)
        return ERR_PERSISTENT_PAIR, HB_APART, INF
    return 0, kind, tn


@_inner
def _held_cluster_pair(pgen, q, i, o, moved, t_now, st, tref, bint, bflt, verts, planes,
                       pairs, pm, tz, zp, ttr, bp_t, pr_t, pr_off, tolf, tmp, err, cid, grav,
                       cw):
    """Pair q of member i of a moving cluster and body o outside it (no closed-form motion
    to search), by ``_held_pair`` with the cluster's kinetic energy and mass: the cluster's
    next pass ends (``cw``'s check slot) where the pair must be bounded again, so the
    passes approach the touch without passing it (conservative advancement); at a pass
    end where they touch and close, the pair's impact is due there (``pr_t[q] = tref[i]``;
    ``_cluster_hit`` dissolves the cluster into that instant). Returns 0 or the error."""
    if (pm[o, M_MODE] == PM_PIVOT and pm[o, M_PLANE2] < 0 and tref[o] == t_now
            and tref[i] == t_now):
        # o became held at the cluster's pass end (its landing capped the pass): it joins
        # the cluster, entered again at t with it (_cluster_enter)
        _pend(q, pr_t, pr_off, cid)
        return 0
    K, M = _cl_kinetic(st, bflt, cid)
    rc, kind, tn = _held_pair(pgen, i, o, moved, t_now, K, M, st, tref, bint, bflt, verts,
                              planes, pairs, pm, tz, zp, ttr, bp_t, pr_t, tolf, tmp, err,
                              grav)
    if rc < 0:
        return rc
    if kind != HB_APART:
        # an impact, or a persistent contact: the instant, whose gather takes o into the
        # cluster entered again after it when they stay touching
        pr_t[q] = tref[i]
        return 0
    pr_t[q] = INF
    tc = cw.shape[0] - 5
    cw[tc] = min(cw[tc], tn)
    return 0


@_inner
def _cl_kinetic(st, bflt, cid):
    """Kinetic energy (J) and mass (kg) of the cluster's members."""
    K = 0.0
    M = 0.0
    for r in range(cid[CL_N]):
        j = cid[CL_HDR + r]
        M += bflt[j, B_MASS]
        K += 0.5 * (bflt[j, B_MASS] * (st[j, VX] ** 2 + st[j, VY] ** 2)
                    + bflt[j, B_INERTIA] * st[j, OMEGA] ** 2)
    return K, M


@_inner
def _member_pair(pgen, q, a, b, st, tref, bint, bflt, verts, pairs, pr_t, tolf, cid, grav, cw,
                 ccon, law_par):
    """Pair q of two members of a moving cluster without a contact or candidate row (apart
    at its entry: their features are not known in advance), states at the pass end
    ``tref[a] = tref[b]``: the distance bound of ``_held_bound`` with both motions
    integrated, each member's points slower than ``sqrt(2K) (1/sqrt(m) + R/sqrt(I))`` (K the
    cluster's kinetic energy, growing by at most the work of gravity). The cluster's next
    pass ends (``cw``'s check slot) by ``HELD_CHECK`` of the time they surely stay apart;
    at a pass end where they touch (gap below ``HELD_TOUCH`` of the smaller size) and do
    not part, the pair is due there (``pr_t[q]``; ``_cluster_hit`` dissolves the cluster
    into that instant, which resolves the pair with the cluster's contacts at v_N = 0 and
    enters it again). Within ``HELD_WATCH`` of the smaller size they are watched instead:
    the rows of their nearest features (``cluster2d_rows.pair_rows``) join the cluster's
    candidates, whose gaps are events of its integration (the bound alone crawls when they
    close much slower than it allows). Returns 0."""
    t = tref[a]
    K, M = _cl_kinetic(st, bflt, cid)
    g0, nx, ny = _cl_gap(pgen, a, st[a], b, st[b], bint, bflt, verts)
    Ra = _body_size(a, bint, bflt, verts)
    Rb = _body_size(b, bint, bflt, verts)
    touch = HELD_TOUCH * min(Ra, Rb)
    nc = cid[CL_NC]
    if (touch < g0 <= HELD_WATCH * min(Ra, Rb) and nc + 4 <= NCAND
            and bint[a, B_KIND] != SH_ELLIPSE and bint[b, B_KIND] != SH_ELLIPSE):
        nb = st.shape[0]
        ra = _cl_row_of(cid, a)
        rb = _cl_row_of(cid, b)
        o = cl.KMAX + nc
        ka, kc = clr.pair_rows(verts, bint[a, B_FIRST], bint[a, B_COUNT], bflt[a, B_RADIUS],
                               st[a], ra, bint[b, B_FIRST], bint[b, B_COUNT],
                               bflt[b, B_RADIUS], st[b], rb, nx, ny, tolf[TF_GAP_TOL],
                               law_par[pairs[q, 2], P_MU], ccon[o:], ccon[o + 2:])
        if ka >= 0 and ka + kc > 0:
            for r in range(kc):
                _cl_copy(ccon, cid, nb, o + ka + r, o + 2 + r)
            for r in range(ka + kc):
                cid[CL_HDR + nb + o + r] = -2 - q
            cid[CL_NC] = nc + ka + kc
            return 0
    if g0 <= touch:
        v = _cl_gap_rate(pgen, a, st[a], b, st[b], bint, bflt, verts, nx, ny)
        sp = (math.hypot(st[a, VX], st[a, VY]) + math.hypot(st[b, VX], st[b, VY])
              + abs(st[a, OMEGA]) * Ra + abs(st[b, OMEGA]) * Rb)
        if v <= pair_zero_speed(sp, tolf[TF_SIMUL_TOL] * sp):
            pr_t[q] = t
            return 0
    beta = (1.0 / math.sqrt(bflt[a, B_MASS]) + Ra / math.sqrt(bflt[a, B_INERTIA])
            + 1.0 / math.sqrt(bflt[b, B_MASS]) + Rb / math.sqrt(bflt[b, B_INERTIA]))
    u = math.sqrt(2.0 * K) * beta
    c = math.hypot(grav[0], grav[1]) * math.sqrt(M) * beta
    d = max(g0, touch)
    sg = 2.0 * d / (u + math.sqrt(u * u + 2.0 * c * d)) if u + c > 0.0 else INF
    tc = cw.shape[0] - 5
    cw[tc] = min(cw[tc], t + HELD_CHECK * sg)
    return 0


@_inner
def _pivot_partners(pgen, i, t, st, tref, bint, bflt, verts, planes, pairs, pm, tz, zp, ttr,
                    bp_t, pr_t, pr_off, tolf, tmp, err, grav, cid):
    """Body i held by one pivot contact (its state at t, the end of its last pass) and the
    bodies it may meet, each by ``_held_pair`` with i's own kinetic energy and mass.
    Returns ``(rc, q, tn, kind)``: q the pair that touches now (-1: none) and kind
    (``HB_IMPACT``: they close, ``HB_REST``: a persistent contact), else tn the time by
    which i's next pass must end (conservative advancement towards each partner).
    Partners in integrated motion themselves (a pivot, a moving cluster) are refused by
    their own pair rule (``_recompute_pair``)."""
    m = bflt[i, B_MASS]
    K = 0.5 * (m * (st[i, VX] ** 2 + st[i, VY] ** 2) + bflt[i, B_INERTIA] * st[i, OMEGA] ** 2)
    tn = INF
    for q in range(pairs.shape[0]):
        if pr_off[q] == PR_OFF or not (pairs[q, 0] == i or pairs[q, 1] == i):
            continue
        o = pairs[q, 1] if pairs[q, 0] == i else pairs[q, 0]
        if pm[o, M_MODE] == PM_CLUSTER and cid[CL_FROZEN] == 0:
            continue
        rc, kind, tq = _held_pair(pgen, i, o, False, t, K, m, st, tref, bint, bflt,
                                  verts, planes, pairs, pm, tz, zp, ttr, bp_t, pr_t, tolf,
                                  tmp, err, grav)
        if rc < 0:
            return rc, -1, INF, HB_APART
        if kind != HB_APART:
            return 0, q, t, kind
        tn = min(tn, tq)
    return 0, -1, tn, HB_APART


@_inner
def _pivot_to_instant(i, q, t, st, grav, pm, ttr, bp_t, pr_t, bmark):
    """Body i held by a pivot contact meets the other body of pair q at t (the end of its
    pass): it flies from t, its held contact and the pair scheduled at t, so that the
    impact step resolves them in one cluster of the instant (the held one at v_N = 0; the
    persistence rules then hold it again). Segments: logged by the impact step."""
    pm[i, M_MODE] = PM_FLIGHT
    pm[i, M_AUX] = -1
    st[i, AX] = grav[0]
    st[i, AY] = grav[1]
    st[i, ALPHA] = 0.0
    ttr[i] = INF
    bp_t[i, pm[i, M_PLANE]] = t
    pr_t[q] = t
    bmark[i] = 1


@_inner
def _others_due(t, i, pm, tz, ttr, bp_t, pr_t):
    """An event of another body than i (-1: any body outside the cluster) is due at t: a
    switch, a plane impact, a pair impact, not a pivot pass. It comes before i's pivot pass
    or the cluster's pass: a partner's new motion bounds that pass."""
    for j in range(pm.shape[0]):
        if j == i or pm[j, M_MODE] == PM_CLUSTER:
            continue
        if tz[j] <= t or (ttr[j] <= t and pm[j, M_MODE] != PM_PIVOT):
            return True
        for p in range(bp_t.shape[1]):
            if bp_t[j, p] <= t:
                return True
    for q in range(pr_t.shape[0]):
        if pr_t[q] <= t:
            return True
    return False


@_inner
def _released_general_s0(a, b, tmp, bint, bflt, verts, S, gtol):
    """Offset s0 (s) from which to search a pair of rounded polygons just released from
    persistent contact (rows tmp[0], tmp[1] at the release, moved to s0 in place): the
    first of ``REL_S0 T 2^k`` (``T = sqrt(R / |a|)`` with R the sum of the reaches and
    ``a`` the relative acceleration of the centres, or ``R / v`` with v the relative speed
    and spins) where the gap (``pair2d.frame_rel``) exceeds gap_tol and grows, at most S
    (``_released_pair_s0``'s rule for two disks)."""
    R = _body_size(a, bint, bflt, verts) + _body_size(b, bint, bflt, verts)
    da = (math.hypot(tmp[0, AX] - tmp[1, AX], tmp[0, AY] - tmp[1, AY])
          + (abs(tmp[0, ALPHA]) + abs(tmp[1, ALPHA])) * R)
    dv = (math.hypot(tmp[0, VX] - tmp[1, VX], tmp[0, VY] - tmp[1, VY])
          + (abs(tmp[0, OMEGA]) + abs(tmp[1, OMEGA])) * R)
    T = math.sqrt(R / da) if da > 0.0 else (R / dv if dv > 0.0 else S)
    s = REL_S0 * T
    s_prev = 0.0
    for _ in range(60):
        if s >= S:
            s = S
            break
        h = 0.5 * s * s
        dx = tmp[1, X] - tmp[0, X] + (tmp[1, VX] - tmp[0, VX]) * s + (tmp[1, AX] - tmp[0, AX]) * h
        dy = tmp[1, Y] - tmp[0, Y] + (tmp[1, VY] - tmp[0, VY]) * s + (tmp[1, AY] - tmp[0, AY]) * h
        tha = tmp[0, ANGLE] + tmp[0, OMEGA] * s + tmp[0, ALPHA] * h
        thb = tmp[1, ANGLE] + tmp[1, OMEGA] * s + tmp[1, ALPHA] * h
        g, nx, ny, pax, pay, pbx, pby, fa, ia, fb, ib = _frame(a, tha, b, dx, dy, thb,
                                                               bint, bflt, verts)
        v = point_rate(nx, ny, pax, pay, pbx - dx, pby - dy,
                       tmp[0, VX] + tmp[0, AX] * s, tmp[0, VY] + tmp[0, AY] * s,
                       tmp[0, OMEGA] + tmp[0, ALPHA] * s, tmp[1, VX] + tmp[1, AX] * s,
                       tmp[1, VY] + tmp[1, AY] * s, tmp[1, OMEGA] + tmp[1, ALPHA] * s)
        if g > gtol and v > 0.0:
            break
        if g < -gtol:
            # another contact of the pair closed meanwhile: searched from the last sample
            # before it (pair_toi finds it there)
            s = s_prev
            break
        s_prev = s
        s *= 2.0
    fly_into(tmp[0], s, tmp[0])
    fly_into(tmp[1], s, tmp[1])
    return s


@_inner
def _pair_persists(a, b, t_now, s, code, bint, bflt, verts, tmp, tolf, err, crawled=False,
                   joint=False, vz2=0.0):
    """Whether bodies a and b, which had an impact at t_now (states ``tmp[0]``, ``tmp[1]``
    there) stay in contact: ``ERR_PERSISTENT_PAIR`` with the reason (the caller enters a
    cluster on PP_CHATTER / PP_TOGETHER; 0: they part), by ``decisions.pair_persistence``
    with ``v`` the gap rate after the impact (``pair2d.frame_rel``) and ``s`` the pair's
    next time of impact (search result ``code``); ``joint``: the search ended at a body's
    imminent plane impact (``_recompute_pair``): touching (within gap_tol) with
    ``v^2 <= vz2`` (m^2/s^2), they stay together (``PP_TOGETHER``)."""
    dx = tmp[1, X] - tmp[0, X]
    dy = tmp[1, Y] - tmp[0, Y]
    g, nx, ny, pax, pay, pbx, pby, fa, ia, fb, ib = _frame(a, tmp[0, ANGLE], b, dx, dy,
                                                           tmp[1, ANGLE], bint, bflt, verts)
    v = point_rate(nx, ny, pax, pay, pbx - dx, pby - dy, tmp[0, VX], tmp[0, VY],
                   tmp[0, OMEGA], tmp[1, VX], tmp[1, VY], tmp[1, OMEGA])
    px = tmp[0, X] + 0.5 * (pax + pbx)
    py = tmp[0, Y] + 0.5 * (pay + pby)
    ra = math.hypot(pax, pay)
    rb = math.hypot(pbx - dx, pby - dy)
    wr = abs(tmp[0, OMEGA]) * ra + abs(tmp[1, OMEGA]) * rb
    sp = math.hypot(tmp[0, VX], tmp[0, VY]) + math.hypot(tmp[1, VX], tmp[1, VY]) + wr
    vz = pair_zero_speed(sp, tolf[TF_SIMUL_TOL] * sp)     # simul_tol is relative in 2D
    G = pair_accel_bound(math.hypot(tmp[0, AX] - tmp[1, AX], tmp[0, AY] - tmp[1, AY]),
                         abs(tmp[0, ALPHA]), ra, abs(tmp[1, ALPHA]), rb, abs(tmp[0, OMEGA]),
                         abs(tmp[1, OMEGA]),
                         math.hypot(tmp[0, VX] - tmp[1, VX], tmp[0, VY] - tmp[1, VY]) + wr)
    why = 0.0
    if code != TOI_MISSED:
        why = pair_persistence(v, s, code == TOI_OK, vz, G, tolf[TF_REST_LENGTH])
    if why == 0.0 and crawled:
        # touching, the search crawled: an accumulation (decisions.pair_crawl_chatters),
        # or bodies that ride together at one point while the frame's witness parts (a box
        # rocking on a box, the landing corner bouncing: the search crawls on the held
        # corner); in the cluster the mode selection lets the contacts that part lift
        why = PP_CHATTER if pair_crawl_chatters(v, G, tolf[TF_REST_LENGTH]) else PP_TOGETHER
    if why == 0.0 and joint and g <= tolf[TF_GAP_TOL] and v * v <= vz2:
        why = PP_TOGETHER
    if why != 0.0:
        _set_err(err, t_now, a, b, px, py, why, v, g if why == PP_TOGETHER else s)
        return ERR_PERSISTENT_PAIR
    return 0


@njit(cache=True, _nrt=False, inline="always")
def _recompute_pairs(pair, pgen, t_now, st, tref, bint, bflt, verts, planes, pairs, pm, tz,
                     zp, ttr, bp_t, pr_t, pr_off, tolf, toli, bmark, tmp, err, cid, grav, cw,
                     ccon, law_par):
    """Recompute the candidates of the pairs of every marked body (states at t_now), after
    those of its planes (run_loop: ``_recompute_planes`` of each marked body, then this;
    each inlined into it on its own, see ``_mark_pairs``). ``pair``, ``pgen``: those
    switches, see ``loop_for``."""
    wait = -1
    for q in range(pairs.shape[0]):
        if bmark[pairs[q, 0]] != 0 or bmark[pairs[q, 1]] != 0:
            if pair is not None:
                rc = _recompute_pair(pgen, q, t_now, st, tref, bint, bflt, verts, planes,
                                     pairs, pm, tz, zp, ttr, bp_t, pr_t, pr_off, tolf, toli,
                                     tmp, err, cid, grav, cw, bmark, ccon, law_par)
            else:
                rc = _not_compiled(err, t_now, pairs[q, 0], FEATURE_PAIR)
            if rc < 0:
                return rc
        if wait < 0 and pr_off[q] == PR_WAIT:
            wait = q
    if wait >= 0 and cid[CL_PEND] < 0:
        # two held bodies and no cluster entered at t that takes them in: one system of
        # their own (a cluster without body-body contact, _cluster_enter)
        cid[CL_PEND] = wait
    return 0


@_inner
def _pend(q, pr_t, pr_off, cid):
    """Pair q stays in contact (its impacts accumulate at t): a cluster entered from the
    next pass (run_loop, ``_cluster_enter``). While another pair's entry is pending, q waits
    for it (``PR_WAIT``): the entry takes q in when touching connects them, else q is
    searched again after it (and refused then: one cluster at a time, ``PP_TWO``)."""
    pr_t[q] = INF
    if cid[CL_PEND] < 0 or cid[CL_PEND] == q:
        cid[CL_PEND] = q
    else:
        pr_off[q] = PR_WAIT


# ------------------------------------------------------------------ persistent contact


@njit(cache=True, _nrt=False)
def _rest_config(i, p, st, bint, bflt, verts, planes, grav, shapes=True):
    """Nearest resting configuration of body i on plane p (``shapes``: the shape switch,
    None in a loop for disks only, ``scene_features``; last, so that a call without it is
    the general one).

    Returns (stable, face0, face1, h_rest, dangle, E_excess): the face (polygon vertex rows,
    -1 for a disk or an ellipse), the height (m) of the centre of mass above the plane at
    rest, the rotation (rad) onto that rest, and the energy (J) of the motion normal to the
    plane and of the rotation (not for a disk) plus the potential energy above that rest.
    """
    nx = planes[p, 0]
    ny = planes[p, 1]
    d = planes[p, 2]
    g = abs(nx * grav[0] + ny * grav[1])
    m = bflt[i, B_MASS]
    inertia = bflt[i, B_INERTIA]
    rad = bflt[i, B_RADIUS]
    vN = nx * st[i, VX] + ny * st[i, VY]
    w = st[i, OMEGA]
    hc = nx * st[i, X] + ny * st[i, Y] - d
    kind = bint[i, B_KIND]
    if shapes is None or kind == SH_DISK:
        return True, -1, -1, rad, 0.0, 0.5 * m * vN * vN + m * g * max(hc - rad, 0.0)
    c = math.cos(st[i, ANGLE])
    s = math.sin(st[i, ANGLE])
    erot = 0.5 * m * vN * vN + 0.5 * inertia * w * w
    if kind == SH_ELLIPSE:
        ea = bflt[i, B_EA]
        eb = bflt[i, B_EB]
        hf = min(ea, eb)
        dth = 0.0
        if ea != eb:
            if ea > eb:
                ex = -s
                ey = c
            else:
                ex = c
                ey = s
            phi = math.atan2(ex * ny - ey * nx, ex * nx + ey * ny)
            if phi > 0.5 * math.pi:
                phi -= math.pi
            elif phi < -0.5 * math.pi:
                phi += math.pi
            dth = phi
        return True, -1, -1, hf, dth, erot + m * g * (hc - hf)
    v0 = bint[i, B_FIRST]
    nv = bint[i, B_COUNT]
    k0 = 0
    gmin = INF
    for k in range(nv):
        wx = c * verts[v0 + k, 0] - s * verts[v0 + k, 1]
        wy = s * verts[v0 + k, 0] + c * verts[v0 + k, 1]
        gk = nx * wx + ny * wy
        if gk < gmin:
            gmin = gk
            k0 = k
    if nv == 2:
        f0 = k0
        f1 = 1 - k0
    else:
        # of the two faces at the lowest corner, the one least inclined to the plane
        # (its outward normal closest to -n): the smaller rise per unit length (not the
        # lower neighbour: a short steep face can end lower than a long flat one)
        kp = (k0 - 1) % nv
        kn = (k0 + 1) % nv
        gp = (nx * (c * verts[v0 + kp, 0] - s * verts[v0 + kp, 1])
              + ny * (s * verts[v0 + kp, 0] + c * verts[v0 + kp, 1]))
        gq = (nx * (c * verts[v0 + kn, 0] - s * verts[v0 + kn, 1])
              + ny * (s * verts[v0 + kn, 0] + c * verts[v0 + kn, 1]))
        lp = math.hypot(verts[v0 + kp, 0] - verts[v0 + k0, 0],
                        verts[v0 + kp, 1] - verts[v0 + k0, 1])
        lq = math.hypot(verts[v0 + kn, 0] - verts[v0 + k0, 0],
                        verts[v0 + kn, 1] - verts[v0 + k0, 1])
        if (gq - gmin) * lp <= (gp - gmin) * lq:
            f0 = k0
            f1 = kn
        else:
            f0 = kp
            f1 = k0
    a0x = c * verts[v0 + f0, 0] - s * verts[v0 + f0, 1]
    a0y = s * verts[v0 + f0, 0] + c * verts[v0 + f0, 1]
    a1x = c * verts[v0 + f1, 0] - s * verts[v0 + f1, 1]
    a1y = s * verts[v0 + f1, 0] + c * verts[v0 + f1, 1]
    ex = a1x - a0x
    ey = a1y - a0y
    L2 = ex * ex + ey * ey
    L = math.sqrt(L2)
    ux = ey / L
    uy = -ex / L
    if nv == 2 and ux * nx + uy * ny > 0.0:
        ux = -ux
        uy = -uy
    lam = -(a0x * ex + a0y * ey) / L2
    stable = lam > 1e-9 and lam < 1.0 - 1e-9
    hf = ux * a0x + uy * a0y + rad
    dth = math.atan2(-ux * ny + uy * nx, -(ux * nx + uy * ny))
    return stable, f0, f1, hf, dth, erot + m * g * (hc - hf)


@_inner
def _persist_setup(shapes, i, p, t, st, bint, bflt, verts, planes, grav, law_par, bp_law, pm,
                   ttr, tolf, err):
    """Choose the persistent mode of body i on plane p (normal velocity already zero) and
    set its constant accelerations and next transition time (``shapes``: the shape switch,
    None for disks only). Returns 0, 1 (the plane does not push: release) or an error
    code."""
    nx = planes[p, 0]
    ny = planes[p, 1]
    tx = ny
    ty = -nx
    gn = nx * grav[0] + ny * grav[1]
    gt = tx * grav[0] + ty * grav[1]
    ttr[i] = INF
    if not gn < 0.0:
        return 1
    m = bflt[i, B_MASS]
    inertia = bflt[i, B_INERTIA]
    rad = bflt[i, B_RADIUS]
    mu = law_par[bp_law[i, p], P_MU]
    N = -m * gn
    vT = tx * st[i, VX] + ty * st[i, VY]
    w = st[i, OMEGA]
    kind = bint[i, B_KIND]
    al = 0.0
    aT = 0.0
    mode = PM_REST
    if shapes is None or kind == SH_DISK:
        vc = vT + w * rad
        kinv = 1.0 / m + rad * rad / inertia
        sig = 0.0
        if abs(vc) <= ROLL_RTOL * (abs(vT) + abs(w * rad)):
            vc = 0.0        # rolling: the slip is the round-off of vT + w r
        if vc == 0.0:
            F = -gt / kinv
            if abs(F) <= mu * N:
                aT = gt + F / m
                al = rad * F / inertia
                mode = PM_REST if (gt == 0.0 and vT == 0.0 and w == 0.0) else PM_ROLL
            else:
                sig = 1.0 if gt > 0.0 else -1.0
        else:
            sig = 1.0 if vc > 0.0 else -1.0
        if sig != 0.0:
            F = -sig * mu * N
            aT = gt + F / m
            al = rad * F / inertia
            mode = PM_SLIDE
            k = gt + F * kinv
            if vc != 0.0 and sig * k < 0.0:
                ttr[i] = t - vc / k
    elif kind == SH_POLY:
        if mu > 0.0 and vT != 0.0 and abs(gt) <= -mu * gn and vT * vT <= _vz2(tolf, -gn):
            # a slip slower than the accumulation speed with friction that holds the body:
            # it sticks (the slip's energy, below m zeno_speed^2 / 2, is dissipated; no
            # decision on the sign of a round-off slip)
            st[i, VX] -= vT * tx
            st[i, VY] -= vT * ty
            vT = 0.0
        if vT == 0.0:
            if abs(gt) <= -mu * gn:
                mode = PM_REST
                FT = -m * gt
                aT = 0.0
            else:
                sig = 1.0 if gt > 0.0 else -1.0
                FT = -sig * mu * N
                aT = gt + FT / m
                mode = PM_SLIDE
        else:
            sig = 1.0 if vT > 0.0 else -1.0
            FT = -sig * mu * N
            aT = gt + FT / m
            mode = PM_SLIDE
            if sig * aT < 0.0:
                ttr[i] = t - vT / aT
        # no tipping: both face contacts must carry a non-negative normal force
        c = math.cos(st[i, ANGLE])
        s = math.sin(st[i, ANGLE])
        v0 = bint[i, B_FIRST]
        f0 = v0 + pm[i, M_FEAT]
        f1 = v0 + pm[i, M_AUX]
        r0x = c * verts[f0, 0] - s * verts[f0, 1] - rad * nx
        r0y = s * verts[f0, 0] + c * verts[f0, 1] - rad * ny
        r1x = c * verts[f1, 0] - s * verts[f1, 1] - rad * nx
        r1y = s * verts[f1, 0] + c * verts[f1, 1] - rad * ny
        xi0 = tx * r0x + ty * r0y
        xi1 = tx * r1x + ty * r1y
        h = -(nx * r0x + ny * r0y)
        N1 = (-h * FT - xi0 * N) / (xi1 - xi0)
        N0 = N - N1
        if N0 < -TIP_RTOL * N or N1 < -TIP_RTOL * N:
            # tipping: the face cannot hold the body; the loaded corner carries it from
            # here (integrated pivot contact, entered by the caller through RC_TIP)
            _set_err(err, t, i, -1 - p, st[i, X], st[i, Y], FT, N0, N1)
            pm[i, M_FEAT] = pm[i, M_AUX] if N0 < N1 else pm[i, M_FEAT]
            pm[i, M_PLANE] = p
            return RC_TIP
    else:
        if mu == 0.0:
            aT = gt
            mode = PM_REST if (vT == 0.0 and gt == 0.0) else PM_SLIDE
        else:
            vz = math.sqrt(_vz2(tolf, -gn))
            if abs(vT) <= vz and abs(gt) <= -mu * gn:
                st[i, VX] = 0.0
                st[i, VY] = 0.0
                aT = 0.0
                mode = PM_REST
            else:
                # a rough ellipse sliding (or on a slope friction cannot hold) rolls and
                # rocks: held on its boundary from here (integrated contact, entered by the
                # caller through RC_TIP, as from a tipping face)
                _set_err(err, t, i, -1 - p, st[i, X], st[i, Y], vT, gt, mu)
                pm[i, M_PLANE] = p
                pm[i, M_FEAT] = 0
                return RC_TIP
    st[i, AX] = aT * tx
    st[i, AY] = aT * ty
    st[i, ALPHA] = al
    pm[i, M_MODE] = mode
    pm[i, M_PLANE] = p
    return 0


@_inner
def _release(i, t, st, planes, grav, pm, ttr, ev_t, ev_i, ev_f, cnt):
    p = pm[i, M_PLANE]
    nx = planes[p, 0]
    ny = planes[p, 1]
    hc = nx * st[i, X] + ny * st[i, Y] - planes[p, 2]
    vN = nx * st[i, VX] + ny * st[i, VY]
    vT = ny * st[i, VX] - nx * st[i, VY]
    pm[i, M_MODE] = PM_FLIGHT
    st[i, AX] = grav[0]
    st[i, AY] = grav[1]
    st[i, ALPHA] = 0.0
    ttr[i] = INF
    _log(ev_t, ev_i, ev_f, cnt, t, EV_RELEASE, i, -1 - p, 0, 0, st[i, X] - hc * nx,
         st[i, Y] - hc * ny, nx, ny, vN, vT, vN, vT, 0.0, 0.0, 0.0)


@_inner
def _settle(shapes, i, p, t, st, bint, bflt, verts, planes, grav, law_par, bp_law, pm, ttr,
            tolf, ev_t, ev_i, ev_f, cnt, err):
    """Snap body i (state at t) onto its rest on plane p and enter persistent contact
    (``shapes``: the shape switch, None for disks only). Returns 0, 1 (no stable rest: stays
    in flight) or an error code."""
    stable, f0, f1, hf, dth, eex = _rest_config(i, p, st, bint, bflt, verts, planes, grav,
                                                shapes)
    if not stable:
        return 1
    nx = planes[p, 0]
    ny = planes[p, 1]
    tx = ny
    ty = -nx
    m = bflt[i, B_MASS]
    e0 = _energy(st, bflt, grav, i)
    hc = nx * st[i, X] + ny * st[i, Y] - planes[p, 2]
    # contact-space velocity of the material point at the contact, before
    ux, uy = _point_vel(st, i, -hc * nx, -hc * ny)
    viN = ux * nx + uy * ny
    viT = ux * tx + uy * ty
    vx0 = st[i, VX]
    vy0 = st[i, VY]
    st[i, ANGLE] += dth
    st[i, X] += (hf - hc) * nx
    st[i, Y] += (hf - hc) * ny
    vN = nx * st[i, VX] + ny * st[i, VY]
    st[i, VX] -= vN * nx
    st[i, VY] -= vN * ny
    if bint[i, B_KIND] != SH_DISK:
        st[i, OMEGA] = 0.0
    pm[i, M_FEAT] = f0
    pm[i, M_AUX] = f1
    slip = tx * st[i, VX] + ty * st[i, VY]
    rc = _persist_setup(shapes, i, p, t, st, bint, bflt, verts, planes, grav, law_par, bp_law, pm,
                        ttr, tolf, err)
    if rc < 0:
        return rc
    if rc == 1:
        return 1
    if rc == RC_TIP:
        pm[i, M_MODE] = PM_REST      # logged as landed on the face; the caller pivots it
    ux, uy = _point_vel(st, i, -hf * nx, -hf * ny)
    dvx = st[i, VX] - vx0
    dvy = st[i, VY] - vy0
    _log(ev_t, ev_i, ev_f, cnt, t, EV_CONTACT, i, -1 - p, pm[i, M_MODE], 0,
         st[i, X] - hf * nx, st[i, Y] - hf * ny, nx, ny, viN, viT, ux * nx + uy * ny,
         ux * tx + uy * ty, m * (dvx * nx + dvy * ny), m * (dvx * tx + dvy * ty),
         _energy(st, bflt, grav, i) - e0)
    if (shapes is not None and rc == 0 and pm[i, M_MODE] == PM_REST and slip != 0.0
            and bint[i, B_KIND] == SH_POLY):
        # its slow slip stuck at once (_persist_setup): it has come to rest
        vfN = ux * nx + uy * ny
        vfT = ux * tx + uy * ty
        _log(ev_t, ev_i, ev_f, cnt, t, EV_REST, i, -1 - p, PM_REST, 0, st[i, X] - hf * nx,
             st[i, Y] - hf * ny, nx, ny, vfN, vfT, vfN, vfT, 0.0, 0.0, 0.0)
    return rc


@_inner
def _log_mode(i, t, st, bflt, planes, pm, ev_t, ev_i, ev_f, cnt, viN, viT):
    p = pm[i, M_PLANE]
    nx = planes[p, 0]
    ny = planes[p, 1]
    hc = nx * st[i, X] + ny * st[i, Y] - planes[p, 2]
    ux, uy = _point_vel(st, i, -hc * nx, -hc * ny)
    _log(ev_t, ev_i, ev_f, cnt, t, pm[i, M_MODE] + 1, i, -1 - p, pm[i, M_MODE], 0,
         st[i, X] - hc * nx, st[i, Y] - hc * ny, nx, ny, viN, viT, ux * nx + uy * ny,
         ux * ny - uy * nx, 0.0, 0.0, 0.0)


@_inner
def _transition(shapes, i, t, st, tref, bint, bflt, verts, planes, grav, law_par, bp_law, pm,
                ttr, tolf, ev_t, ev_i, ev_f, cnt, err):
    """Slip of a persistent contact stops at t: roll, rest or slide the other way
    (``shapes``: the shape switch, None for disks only)."""
    fly_row(st, i, t - tref[i])
    tref[i] = t
    ttr[i] = INF
    p = pm[i, M_PLANE]
    nx = planes[p, 0]
    ny = planes[p, 1]
    hc = nx * st[i, X] + ny * st[i, Y] - planes[p, 2]
    ux, uy = _point_vel(st, i, -hc * nx, -hc * ny)
    viN = ux * nx + uy * ny
    viT = ux * ny - uy * nx
    vT = ny * st[i, VX] - nx * st[i, VY]
    if bint[i, B_KIND] == SH_DISK:
        st[i, OMEGA] = -vT / bflt[i, B_RADIUS]      # contact point velocity exactly zero
    else:
        st[i, VX] = 0.0
        st[i, VY] = 0.0
    rc = _persist_setup(shapes, i, p, t, st, bint, bflt, verts, planes, grav, law_par, bp_law, pm,
                        ttr, tolf, err)
    if rc < 0 or rc == RC_TIP:
        return rc
    _log_mode(i, t, st, bflt, planes, pm, ev_t, ev_i, ev_f, cnt, viN, viT)
    return 0


@_inner
def _reevaluate(shapes, i, t, st, bint, bflt, verts, planes, grav, law_par, bp_law, pm, ttr,
                tolf, ev_t, ev_i, ev_f, cnt, err):
    """A body in persistent contact received an impulse: keep the contact (zeroing the
    normal velocity, and the rotation of a non-disk) when that motion carries less energy
    than the accumulation threshold, else release it to free flight (``shapes``: the shape
    switch, None for disks only)."""
    p = pm[i, M_PLANE]
    if pm[i, M_MODE] == PM_WEDGED:
        # struck while wedged: free flight from here (its contacts are impacts again)
        _release(i, t, st, planes, grav, pm, ttr, ev_t, ev_i, ev_f, cnt)
        return 0
    nx = planes[p, 0]
    ny = planes[p, 1]
    gn = nx * grav[0] + ny * grav[1]
    m = bflt[i, B_MASS]
    vN = nx * st[i, VX] + ny * st[i, VY]
    ex = 0.5 * m * vN * vN
    if bint[i, B_KIND] != SH_DISK:
        ex += 0.5 * bflt[i, B_INERTIA] * st[i, OMEGA] * st[i, OMEGA]
    if gn < 0.0 and ex <= 0.5 * m * _vz2(tolf, -gn):
        hc = nx * st[i, X] + ny * st[i, Y] - planes[p, 2]
        ux, uy = _point_vel(st, i, -hc * nx, -hc * ny)
        st[i, VX] -= vN * nx
        st[i, VY] -= vN * ny
        if bint[i, B_KIND] != SH_DISK:
            st[i, OMEGA] = 0.0
        old = pm[i, M_MODE]
        rc = _persist_setup(shapes, i, p, t, st, bint, bflt, verts, planes, grav, law_par, bp_law,
                            pm, ttr, tolf, err)
        if rc < 0 or rc == RC_TIP:
            return rc
        if rc == 0:
            if pm[i, M_MODE] != old:
                _log_mode(i, t, st, bflt, planes, pm, ev_t, ev_i, ev_f, cnt,
                          ux * nx + uy * ny, ux * ny - uy * nx)
            return 0
    _release(i, t, st, planes, grav, pm, ttr, ev_t, ev_i, ev_f, cnt)
    return 0


# ------------------------------------------------------------------ integrated pivot contact


@_inner
def _pv_params(i, w, bint, bflt, verts, planes, grav, law_par, bp_law, pm):
    """Contact parameters (``pivot2d.CP_*``) of body i held by vertex pm[i, M_FEAT] on plane
    pm[i, M_PLANE] with contact status pm[i, M_AUX], into w."""
    p = pm[i, M_PLANE]
    v0 = bint[i, B_FIRST]
    nx = planes[p, 0]
    ny = planes[p, 1]
    rad = bflt[i, B_RADIUS]
    w[CP_M] = bflt[i, B_MASS]
    w[CP_I] = bflt[i, B_INERTIA]
    w[CP_GN] = nx * grav[0] + ny * grav[1]
    w[CP_GT] = ny * grav[0] - nx * grav[1]
    w[CP_NX] = nx
    w[CP_NY] = ny
    w[CP_D] = planes[p, 2]
    w[CP_RAD] = rad
    w[CP_PX] = verts[v0 + pm[i, M_FEAT], 0]
    w[CP_PY] = verts[v0 + pm[i, M_FEAT], 1]
    w[CP_MU] = law_par[bp_law[i, p], P_MU]
    w[CP_SIG] = float(pm[i, M_AUX])
    q = pm[i, M_PLANE2]
    w[CP_TWO] = 0.0
    if q >= 0:
        # held on two planes: pm[i, M_AUX] is the sign of w (pivot2d, "Two contacts")
        w[CP_TWO] = 1.0
        w[CP_N2X] = planes[q, 0]
        w[CP_N2Y] = planes[q, 1]
        w[CP_D2] = planes[q, 2]
        w[CP_Q2] = float(q)
        w[CP_K2] = float(pm[i, M_FEAT2])
        w[CP_P2X] = verts[v0 + pm[i, M_FEAT2], 0]
        w[CP_P2Y] = verts[v0 + pm[i, M_FEAT2], 1]
        w[CP_MU2] = law_par[bp_law[i, q], P_MU]
        w[CP_DIR] = float(pm[i, M_AUX])
    if bint[i, B_KIND] == SH_ELLIPSE:
        # held on its curved boundary (pivot2d, KIND_ELLIPSE)
        w[CP_KIND] = KIND_ELLIPSE
        w[CP_EA] = bflt[i, B_EA]
        w[CP_EB] = bflt[i, B_EB]
        w[CP_RAD] = 0.0
        w[CP_PX] = 0.0
        w[CP_PY] = 0.0
        w[CP_P2X] = 0.0
        w[CP_P2Y] = 0.0
        w[CP_L] = max(bflt[i, B_EA], bflt[i, B_EB])
        return
    w[CP_KIND] = KIND_VERTEX
    L = 0.0
    for k in range(bint[i, B_COUNT]):
        L = max(L, math.hypot(verts[v0 + k, 0], verts[v0 + k, 1]))
    w[CP_L] = L + rad


@_inner
def _pv_state(i, st, w):
    """Contact force and accelerations of body i (held, parameters in w) at its state:
    (code, lam (N), f (N), slip acceleration (m/s^2))."""
    y = w[W_YA:W_YA + 4]
    pivot_reduce(w, st[i], y)
    code, lam, f, ud, wd = pivot_forces(w, y[0], y[1], y[2], y[3])
    return code, lam, f, pivot_slip_rate(w, y[1], y[3], ud, wd)


@_inner
def _pv_contact(i, st, bint, bflt, verts, planes, pm):
    """Held contact of body i (its first, ``_two_contact``): (px, py, rx, ry, v_N, v_T) at
    its current state."""
    p, px, py, rx, ry, vN, vT = _two_contact(i, int64(0), st, bint, bflt, verts, planes, pm)
    return px, py, rx, ry, vN, vT


@_inner
def _pv_impulse(i, st, bflt, rx, ry, nx, ny, vN, vT, with_t):
    """Impulse at the contact arm r (normal n) removing the contact velocity (vN, vT)
    (``W P = -v``; ``with_t`` False: only vN, ``P_N = -vN / W_NN``). Never adds energy:
    ``dE = -v . W^-1 v / 2``. Returns (P_N, P_T)."""
    wnn, wnt, wtt = _w_body(bflt[i, B_MASS], bflt[i, B_INERTIA], rx, ry, nx, ny)
    if with_t:
        det = wnn * wtt - wnt * wnt
        PN = -(wtt * vN - wnt * vT) / det
        PT = -(wnn * vT - wnt * vN) / det
    else:
        PN = -vN / wnn
        PT = 0.0
    _pv_apply(i, st, bflt, rx, ry, nx, ny, PN, PT)
    return PN, PT


@njit(cache=True, _nrt=False, inline="always")
def _pv_apply(i, st, bflt, rx, ry, nx, ny, PN, PT):
    """Apply the contact impulse (P_N, P_T) (N s; tangent ``(n_y, -n_x)``) at arm r to body
    i's velocity and spin."""
    jx = PN * nx + PT * ny
    jy = PN * ny - PT * nx
    st[i, VX] += jx / bflt[i, B_MASS]
    st[i, VY] += jy / bflt[i, B_MASS]
    st[i, OMEGA] += (rx * jy - ry * jx) / bflt[i, B_INERTIA]


@_inner
def _pv_choose(i, st, w, pm):
    """Stick or slide for a held contact of body i with no slip (pm[i, M_AUX] == 0 on entry):
    stick when the sticking force is in the friction cone with lam >= 0, else slide
    opposite to it when that slip grows (consistent). Returns 0 (pm[i, M_AUX] set), 1 (no
    consistent contact: lam < 0) or ERR_PAINLEVE."""
    if w[CP_MU] == 0.0:
        # frictionless: the slip direction does not enter the forces
        pm[i, M_AUX] = 1
        w[CP_SIG] = 1.0
        code, lam, f, aT = _pv_state(i, st, w)
        if code != PV_OK:
            return ERR_PAINLEVE
        return 1 if lam < 0.0 else 0
    w[CP_SIG] = 0.0
    code, lam, f, aT = _pv_state(i, st, w)
    if lam >= 0.0 and abs(f) <= w[CP_MU] * lam:
        pm[i, M_AUX] = 0
        return 0
    sig = -1.0 if f > 0.0 else 1.0
    w[CP_SIG] = sig
    code, lam2, f2, aT2 = _pv_state(i, st, w)
    if code != PV_OK:
        return ERR_PAINLEVE
    if lam2 < 0.0 or sig * aT2 < 0.0:
        return 1
    pm[i, M_AUX] = int(sig)
    return 0


@_inner
def _pv_follow_slip(i, st, w, pm, vT):
    """Status of body i's held contact (parameters in w) from its slip vT (m/s): sliding
    along it when vT != 0, else stick or slide as ``_pv_choose`` decides (pm[i, M_AUX]
    set). Returns 0, 1 (lam < 0: the contact cannot hold the body) or ERR_PAINLEVE."""
    if vT == 0.0:
        pm[i, M_AUX] = 0
        return _pv_choose(i, st, w, pm)
    pm[i, M_AUX] = 1 if vT > 0.0 else -1
    w[CP_SIG] = float(pm[i, M_AUX])
    code, lam, f, aT = _pv_state(i, st, w)
    return ERR_PAINLEVE if code != PV_OK else (1 if lam < 0.0 else 0)


@_inner
def _pv_iwc(i, p, t, st, bint, bflt, verts, planes, grav, law_par, bp_law, pm, ev_t, ev_i,
            ev_f, cnt):
    """Impact without collision (Painleve): the held contact of body i on plane p slides at
    v_N = 0 where sliding has no consistent force (``W_NN - mu s W_NT <= 0``: v_N would
    fall under any normal force). The impulse is Darboux-Keller's integration in the
    normal impulse from v_N = 0 (``routh_2d_scalar``: v_N first falls along that negative
    slope; compression ends where it is back at 0 after the slip stopped or reversed) with
    the pair's mu and e (``max(e, 0)``) and Poisson's termination ``p_f = (1 + e) p_c``,
    whatever the pair's law: the collision laws are functions of an approach velocity,
    which is zero here. Genot & Brogliato, Eur. J. Mech. A 18 (1999) 653; Stewart, SIAM
    Review 42 (2000) 3; Nordmark, Dankowicz & Champneys, Int. J. Non-Linear Mech. 44 (2009)
    1011. Logged as event "painleve". Returns True when an impulse was
    applied."""
    nx = planes[p, 0]
    ny = planes[p, 1]
    px, py, rx, ry, vN, vT = _pv_contact(i, st, bint, bflt, verts, planes, pm)
    wnn, wnt, wtt = _w_body(bflt[i, B_MASS], bflt[i, B_INERTIA], rx, ry, nx, ny)
    row = bp_law[i, p]
    mode, PN, PT = routh_2d_scalar(0.0, vT, wnn, wnt, wtt, max(law_par[row, P_E], 0.0),
                                   law_par[row, P_MU], float(REST_POISSON))
    if mode == MODE_NO_SOLUTION or not PN > 0.0:
        return False
    e0 = _energy(st, bflt, grav, i)
    _pv_apply(i, st, bflt, rx, ry, nx, ny, PN, PT)
    px, py, rx, ry, vfN, vfT = _pv_contact(i, st, bint, bflt, verts, planes, pm)
    _log(ev_t, ev_i, ev_f, cnt, t, EV_IWC, i, -1 - p, int(mode), 0, px, py, nx, ny, 0.0, vT,
         vfN, vfT, PN, PT, _energy(st, bflt, grav, i) - e0)
    return True


@_inner
def _pivot_enter(i, p, k, t, st, bint, bflt, verts, planes, grav, law_par, bp_law, pm, tz,
                 zp, ttr, tolf, w, ev_t, ev_i, ev_f, cnt, err):
    """Body i (in flight at t) keeps vertex k (body-relative) on plane p: remove its tiny
    normal velocity (and a slip below the accumulation speed) by impulses, choose stick or
    slide, and schedule an integration pass at t (event "pivot"). A slide with no
    consistent force (Painleve) takes an impact without collision (``_pv_iwc``) when
    ``tolf[TF_PAINLEVE]`` is PAINLEVE_IMPACT: the body then flies off (return 2) or, when it
    leaves slower than the accumulation speed, is held again. Returns 0, 1 (no persistent
    contact is consistent), 2 (in flight after an impact without collision) or an error
    code."""
    nx = planes[p, 0]
    ny = planes[p, 1]
    gn = nx * grav[0] + ny * grav[1]
    # the normal acceleration that pushes the contact into the plane (m/s^2): gravity's;
    # an ellipse is also held on a plane gravity does not push (a wall) when its free gap
    # accelerates into it (its rotation: n . g - h'' w^2 < 0)
    gz = -gn
    if bint[i, B_KIND] == SH_ELLIPSE and not gn < 0.0:
        h, h1, h2 = ellipse_support3(bflt[i, B_EA], bflt[i, B_EB], st[i, ANGLE], nx, ny)
        gz = h2 * st[i, OMEGA] * st[i, OMEGA] - gn
    if not gz > 0.0:
        return 1
    pm[i, M_MODE] = PM_PIVOT
    pm[i, M_PLANE] = p
    pm[i, M_FEAT] = k
    pm[i, M_AUX] = 0
    pm[i, M_PLANE2] = -1
    e0 = _energy(st, bflt, grav, i)
    px, py, rx, ry, viN, viT = _pv_contact(i, st, bint, bflt, verts, planes, pm)
    _pv_params(i, w, bint, bflt, verts, planes, grav, law_par, bp_law, pm)
    mu = w[CP_MU]
    vz = math.sqrt(_vz2(tolf, gz))
    if mu > 0.0 and abs(viT) <= vz:
        PN, PT = _pv_impulse(i, st, bflt, rx, ry, nx, ny, viN, viT, True)
        rc = _pv_choose(i, st, w, pm)
    else:
        PN, PT = _pv_impulse(i, st, bflt, rx, ry, nx, ny, viN, viT, False)
        px, py, rx, ry, vN, vT = _pv_contact(i, st, bint, bflt, verts, planes, pm)
        rc = _pv_follow_slip(i, st, w, pm, vT)
        if (rc == ERR_PAINLEVE and tolf[TF_PAINLEVE] == PAINLEVE_IMPACT
                and _pv_iwc(i, p, t, st, bint, bflt, verts, planes, grav, law_par, bp_law,
                            pm, ev_t, ev_i, ev_f, cnt)):
            px, py, rx, ry, vN, vT = _pv_contact(i, st, bint, bflt, verts, planes, pm)
            if vN > vz:
                pm[i, M_MODE] = PM_FLIGHT     # it leaves the plane: flight from t
                tz[i] = INF
                return 2
            # it leaves slower than the accumulation speed: held again (sticking, or
            # sliding the other way; once: a second inconsistency is refused)
            if abs(vT) <= vz:
                _pv_impulse(i, st, bflt, rx, ry, nx, ny, vN, vT, True)
                pm[i, M_AUX] = 0
                rc = _pv_choose(i, st, w, pm)
            else:
                _pv_impulse(i, st, bflt, rx, ry, nx, ny, vN, vT, False)
                px, py, rx, ry, vN, vT = _pv_contact(i, st, bint, bflt, verts, planes, pm)
                rc = _pv_follow_slip(i, st, w, pm, vT)
    if rc != 0:
        pm[i, M_MODE] = PM_FLIGHT
        if rc == ERR_PAINLEVE:
            _set_err(err, t, i, -1 - p, st[i, X], st[i, Y], mu, viT, 0.0)
        return rc
    tz[i] = INF
    ttr[i] = t
    zp[i] = PE_NONE
    px, py, rx, ry, vfN, vfT = _pv_contact(i, st, bint, bflt, verts, planes, pm)
    _log(ev_t, ev_i, ev_f, cnt, t, EV_PIVOT, i, -1 - p, 2 if pm[i, M_AUX] == 0 else 1, 0, px,
         py, nx, ny, viN, viT, vfN, vfT, PN, PT, _energy(st, bflt, grav, i) - e0)
    return 0


@_inner
def _tip(i, t, st, bint, bflt, verts, planes, grav, law_par, bp_law, pm, tz, zp, ttr, tolf,
         w, ev_t, ev_i, ev_f, cnt, err):
    """Body i resting or sliding on a face tips over (``_persist_setup`` returned RC_TIP,
    with the loaded corner in pm[i, M_FEAT]): from t it pivots on that corner (mode table:
    rest/slide on a face -> pivot on a vertex; a corner that would slide with no
    consistent force takes an impact without collision and may fly off: then it is in
    flight on return). Returns 0 or an error code (ERR_TIPPING when no pivot state is
    consistent either)."""
    p = pm[i, M_PLANE]
    k = pm[i, M_FEAT]
    pm[i, M_MODE] = PM_FLIGHT
    st[i, AX] = grav[0]
    st[i, AY] = grav[1]
    st[i, ALPHA] = 0.0
    ttr[i] = INF
    rc = _pivot_enter(i, p, k, t, st, bint, bflt, verts, planes, grav, law_par, bp_law, pm,
                      tz, zp, ttr, tolf, w, ev_t, ev_i, ev_f, cnt, err)
    if rc == 1:
        return ERR_TIPPING      # err holds the face forces set by _persist_setup
    if rc == 2:
        return 0                # it flies off after an impact without collision
    return rc


@_inner
def _pivot_pass(i, t, st, tref, bint, bflt, verts, planes, grav, law_par, bp_law, bp_off,
                pm, zp, ttr, tolf, w, seg_t, seg_b, seg_s, cnt, err, t_cap):
    """One integration pass of body i held from t (``pivot2d.pivot_advance``) to its next
    event, ``t_cap`` at the latest (s: a partner's bound, ``_pivot_partners``): records its
    pieces, leaves st[i] at the pass end and schedules the next pass or event there."""
    _pv_params(i, w, bint, bflt, verts, planes, grav, law_par, bp_law, pm)
    S = min(tolf[TF_T_END], t_cap) - t
    p = pm[i, M_PLANE]
    s, kind, idx, code = pivot_advance(w, st[i], verts, bint[i, B_FIRST], bint[i, B_COUNT],
                                       planes, bp_off[i], p, pm[i, M_FEAT], t, S,
                                       tolf[TF_TOI_RTOL], tolf[TF_TOI_ATOL], seg_t, seg_b,
                                       seg_s, cnt, i)
    if code != PI_OK:
        _set_err(err, t + s, i, -1 - p, st[i, X], st[i, Y], w[CP_MU], float(code),
                 float(pm[i, M_AUX]))
        return ERR_CONTACT_STEPS if code == PI_TOO_MANY_STEPS else ERR_PAINLEVE
    tref[i] = t + s
    zp[i] = kind + 8 * idx
    ttr[i] = INF if (kind == PE_NONE and t + s >= tolf[TF_T_END]) else t + s
    return 0


@_inner
def _pivot_event(i, t, st, tref, bint, bflt, verts, planes, grav, law_par, bp_law, bp_off,
                 bp_t, pm, tz, zp, ttr, tolf, w, ev_t, ev_i, ev_f, seg_t, seg_b, seg_s, cnt,
                 err, t_cap):
    """The event due at t of body i in integrated pivot contact (st[i] is its state at t),
    then the next pass (ending by ``t_cap``, s). Returns (rc, action): action 0 a pass ran
    (its pieces are recorded), 1 the body was released to flight (log its segment,
    recompute), 2 an impact at t is pending (bp_t, left to the impact step)."""
    code = zp[i]
    kind = code % 8
    idx = code // 8
    ttr[i] = INF
    p = pm[i, M_PLANE]
    nx = planes[p, 0]
    ny = planes[p, 1]
    if kind == PE_GAP:
        bp_t[i, idx // bint[i, B_COUNT]] = t
        return 0, 2
    if pm[i, M_PLANE2] >= 0:
        return _two_event(i, kind, idx, t, st, tref, bint, bflt, verts, planes, grav, law_par,
                          bp_law, bp_off, pm, tz, zp, ttr, tolf, w, ev_t, ev_i, ev_f, seg_t,
                          seg_b, seg_s, cnt, err)
    _pv_params(i, w, bint, bflt, verts, planes, grav, law_par, bp_law, pm)
    px, py, rx, ry, viN, viT = _pv_contact(i, st, bint, bflt, verts, planes, pm)
    if kind == PE_LIFT:
        pm[i, M_MODE] = PM_FLIGHT
        pm[i, M_AUX] = REL_TANGENT
        st[i, AX] = grav[0]
        st[i, AY] = grav[1]
        st[i, ALPHA] = 0.0
        _log(ev_t, ev_i, ev_f, cnt, t, EV_RELEASE, i, -1 - p, 0, 0, px, py, nx, ny, viN, viT,
             viN, viT, 0.0, 0.0, 0.0)
        return 0, 1
    if kind == PE_SLIP:
        # the sticking force reached its cone: slip opposite to it, if that slip grows
        old = pm[i, M_AUX]
        rc = _pv_choose(i, st, w, pm)
        if rc == ERR_PAINLEVE:
            _set_err(err, t, i, -1 - p, px, py, w[CP_MU], viT, 0.0)
            return rc, 0
        if rc == 1:
            pm[i, M_AUX] = old      # lam < 0 either way: the lift-off event follows
        if pm[i, M_AUX] != old:
            _log(ev_t, ev_i, ev_f, cnt, t, EV_SLIDE, i, -1 - p, 1, 0, px, py, nx, ny, viN,
                 viT, viN, viT, 0.0, 0.0, 0.0)
    elif kind == PE_STOP:
        # the slip vanished: remove its round-off (and any normal velocity), then stick or
        # slide the other way
        e0 = _energy(st, bflt, grav, i)
        PN, PT = _pv_impulse(i, st, bflt, rx, ry, nx, ny, viN, viT, True)
        old = pm[i, M_AUX]
        pm[i, M_AUX] = 0
        rc = _pv_choose(i, st, w, pm)
        if rc == ERR_PAINLEVE:
            _set_err(err, t, i, -1 - p, px, py, w[CP_MU], viT, 0.0)
            return rc, 0
        if rc == 1:
            pm[i, M_AUX] = old
        px, py, rx, ry, vfN, vfT = _pv_contact(i, st, bint, bflt, verts, planes, pm)
        _log(ev_t, ev_i, ev_f, cnt, t, EV_STICK if pm[i, M_AUX] == 0 else EV_SLIDE, i, -1 - p,
             2 if pm[i, M_AUX] == 0 else 1, 0, px, py, nx, ny, viN, viT, vfN, vfT, PN, PT,
             _energy(st, bflt, grav, i) - e0)
    rc = _pivot_pass(i, t, st, tref, bint, bflt, verts, planes, grav, law_par, bp_law,
                     bp_off, pm, zp, ttr, tolf, w, seg_t, seg_b, seg_s, cnt, err, t_cap)
    return rc, 0


# ------------------------------------------------------------------ two held contacts


@_inner
def _two_contact(i, j, st, bint, bflt, verts, planes, pm):
    """Held contact j of body i on two planes (0: ``pm[i, M_PLANE]``, ``M_FEAT``; 1:
    ``M_PLANE2``, ``M_FEAT2``): (plane, px, py, rx, ry, v_N, v_T) at its current state
    (callers pass ``int64(0)``, ``int64(1)``: a literal j would compile it once per value)."""
    p = pm[i, M_PLANE] if j == 0 else pm[i, M_PLANE2]
    k = pm[i, M_FEAT] if j == 0 else pm[i, M_FEAT2]
    nx = planes[p, 0]
    ny = planes[p, 1]
    px, py, rx, ry = _plane_contact(st, i, bint, bflt, verts, bint[i, B_FIRST] + k, nx, ny,
                                    True)
    ux, uy = _point_vel(st, i, rx, ry)
    return p, px, py, rx, ry, ux * nx + uy * ny, ux * ny - uy * nx


@_inner
def _two_choose(i, st, w, pm):
    """Direction in which body i (on two planes, parameters in w, w = 0) starts to slide:
    ``s = +1`` or ``-1`` with ``s dw/dt > 0`` and both normal forces >= 0 (consistent), set
    in ``pm[i, M_AUX]``. Returns 0, 1 (neither direction is consistent) or ERR_PAINLEVE
    (neither has a solution)."""
    th = st[i, ANGLE]
    painleve = True
    for it in range(2):
        s = 1.0 if it == 0 else -1.0
        w[CP_DIR] = s
        two_slip_signs(w, th)
        code, lam1, lam2, wd, ax, ay = two_forces(w, th, 0.0)
        if code != PV_OK:
            continue
        painleve = False
        if s * wd > 0.0 and lam1 >= 0.0 and lam2 >= 0.0:
            pm[i, M_AUX] = int(s)
            return 0
    return ERR_PAINLEVE if painleve else 1


@_inner
def _two_enter(i, p1, k1, p2, k2, t, st, bint, bflt, verts, planes, grav, law_par, bp_law,
               pm, tz, zp, ttr, w, ev_t, ev_i, ev_f, cnt):
    """Body i (in flight at t) whose impacts accumulate at vertex k1 on plane p1 and at k2
    on another plane p2 slides on both (mode table, "two contacts"; ``pivot2d``, "Two
    contacts"). Both normal velocities (below the accumulation speed) are removed by the
    normal impulses ``W_NN P = -v_N`` of the two contacts (a projection: ``dE = -v_N .
    W_NN^-1 v_N / 2 <= 0``); the body then slides the way w turns (from w = 0: the
    consistent way, ``_two_choose``), held on both, when both normal forces are >= 0.
    Returns 0 (event "pivot" on each contact; a pass at t is scheduled) or 1 (no
    consistent two-contact motion: the state is left as it was)."""
    m = bflt[i, B_MASS]
    inertia = bflt[i, B_INERTIA]
    vx0 = st[i, VX]
    vy0 = st[i, VY]
    om0 = st[i, OMEGA]
    old_mode = pm[i, M_MODE]
    old_plane = pm[i, M_PLANE]
    old_feat = pm[i, M_FEAT]
    old_aux = pm[i, M_AUX]
    pm[i, M_MODE] = PM_PIVOT
    pm[i, M_PLANE] = p1
    pm[i, M_FEAT] = k1
    pm[i, M_PLANE2] = p2
    pm[i, M_FEAT2] = k2
    pm[i, M_AUX] = 1
    e0 = _energy(st, bflt, grav, i)
    q1, px1, py1, r1x, r1y, v1n, v1t = _two_contact(i, int64(0), st, bint, bflt, verts, planes, pm)
    q2, px2, py2, r2x, r2y, v2n, v2t = _two_contact(i, int64(1), st, bint, bflt, verts, planes, pm)
    n1x = planes[p1, 0]
    n1y = planes[p1, 1]
    n2x = planes[p2, 0]
    n2y = planes[p2, 1]
    c1 = r1x * n1y - r1y * n1x
    c2 = r2x * n2y - r2y * n2x
    a11 = 1.0 / m + c1 * c1 / inertia
    a12 = (n1x * n2x + n1y * n2y) / m + c1 * c2 / inertia
    a22 = 1.0 / m + c2 * c2 / inertia
    det = a11 * a22 - a12 * a12
    ok = det > 0.0
    P1 = 0.0
    P2 = 0.0
    if ok:
        P1 = -(a22 * v1n - a12 * v2n) / det
        P2 = -(a11 * v2n - a12 * v1n) / det
        st[i, VX] += (P1 * n1x + P2 * n2x) / m
        st[i, VY] += (P1 * n1y + P2 * n2y) / m
        st[i, OMEGA] += (c1 * P1 + c2 * P2) / inertia
        _pv_params(i, w, bint, bflt, verts, planes, grav, law_par, bp_law, pm)
        om = st[i, OMEGA]
        if om != 0.0:
            pm[i, M_AUX] = 1 if om > 0.0 else -1
            w[CP_DIR] = float(pm[i, M_AUX])
            two_slip_signs(w, st[i, ANGLE])
            code, lam1, lam2, wd, ax, ay = two_forces(w, st[i, ANGLE], om)
            ok = code == PV_OK and lam1 >= 0.0 and lam2 >= 0.0
        else:
            ok = _two_choose(i, st, w, pm) == 0
    if not ok:
        st[i, VX] = vx0
        st[i, VY] = vy0
        st[i, OMEGA] = om0
        pm[i, M_MODE] = old_mode
        pm[i, M_PLANE] = old_plane
        pm[i, M_FEAT] = old_feat
        pm[i, M_AUX] = old_aux
        pm[i, M_PLANE2] = -1
        return 1
    tz[i] = INF
    ttr[i] = t
    zp[i] = PE_NONE
    dE = _energy(st, bflt, grav, i) - e0
    q1, px1, py1, r1x, r1y, f1n, f1t = _two_contact(i, int64(0), st, bint, bflt, verts, planes, pm)
    q2, px2, py2, r2x, r2y, f2n, f2t = _two_contact(i, int64(1), st, bint, bflt, verts, planes, pm)
    _log(ev_t, ev_i, ev_f, cnt, t, EV_PIVOT, i, -1 - p1, 1, 0, px1, py1, n1x, n1y, v1n, v1t,
         f1n, f1t, P1, 0.0, dE)
    _log(ev_t, ev_i, ev_f, cnt, t, EV_PIVOT, i, -1 - p2, 1, 0, px2, py2, n2x, n2y, v2n, v2t,
         f2n, f2t, P2, 0.0, 0.0)
    return 0


@_inner
def _two_drop(i, t, st, bint, bflt, verts, planes, grav, law_par, bp_law, pm, w, ev_t, ev_i,
              ev_f, cnt):
    """Body i at rest (w = 0) on two planes that can neither rest nor slide on both: it
    keeps the contact j whose single held motion (``_pv_choose``) is consistent while the
    other contact's gap accelerates away from its plane (``n . (a + alpha J r) >= 0``), and
    lets the other go (event "release"). Returns 0, or 1 when neither contact can be kept
    (pm left as it was)."""
    p0 = pm[i, M_PLANE]
    k0 = pm[i, M_FEAT]
    p1 = pm[i, M_PLANE2]
    k1 = pm[i, M_FEAT2]
    aux = pm[i, M_AUX]
    row = w[W_ROW:W_ROW + 9]
    for j in range(2):
        pk, kk, pd, kd = (p0, k0, p1, k1) if j == 0 else (p1, k1, p0, k0)
        pm[i, M_PLANE] = pk
        pm[i, M_FEAT] = kk
        pm[i, M_PLANE2] = -1
        pm[i, M_AUX] = 0
        _pv_params(i, w, bint, bflt, verts, planes, grav, law_par, bp_law, pm)
        if _pv_choose(i, st, w, pm) != 0:
            continue
        y = w[W_YA:W_YA + 4]
        pivot_reduce(w, st[i], y)
        pivot_row(w, y[0], y[1], y[2], y[3], row)
        nx = planes[pd, 0]
        ny = planes[pd, 1]
        px, py, rx, ry = _plane_contact(st, i, bint, bflt, verts, bint[i, B_FIRST] + kd,
                                        nx, ny, True)
        if nx * (row[6] - row[8] * ry) + ny * (row[7] + row[8] * rx) < 0.0:
            continue
        _log(ev_t, ev_i, ev_f, cnt, t, EV_RELEASE, i, -1 - pd, 0, 0, px, py, nx, ny, 0.0, 0.0,
             0.0, 0.0, 0.0, 0.0, 0.0)
        return 0
    pm[i, M_PLANE] = p0
    pm[i, M_FEAT] = k0
    pm[i, M_PLANE2] = p1
    pm[i, M_FEAT2] = k1
    pm[i, M_AUX] = aux
    return 1


@_inner
def _two_event(i, kind, idx, t, st, tref, bint, bflt, verts, planes, grav, law_par, bp_law,
               bp_off, pm, tz, zp, ttr, tolf, w, ev_t, ev_i, ev_f, seg_t, seg_b, seg_s, cnt,
               err):
    """The event due at t of body i sliding on two planes (st[i] its state at t), then the
    next pass. ``PE_LIFT``: contact idx leaves (event "release" on its plane), the body
    pivots on the other one (or flies when that cannot hold it either); ``PE_STOP``: the
    slip of contact idx reverses while w does not (event "slide"); ``PE_TURN``: w reaches
    0, where ``v = A1 w`` vanishes: the integration's round-off is removed, then the body
    rests on both planes when that is a static equilibrium (``wedge2d``; event "rest",
    ``PM_WEDGED``), else slides the consistent way (event "slide"; ERR_TWO_PLANES when
    neither way is). Returns (rc, action) as ``_pivot_event``."""
    _pv_params(i, w, bint, bflt, verts, planes, grav, law_par, bp_law, pm)
    if kind == PE_LIFT:
        pg, px, py, rx, ry, vN, vT = _two_contact(i, idx, st, bint, bflt, verts, planes, pm)
        _log(ev_t, ev_i, ev_f, cnt, t, EV_RELEASE, i, -1 - pg, 0, 0, px, py, planes[pg, 0],
             planes[pg, 1], vN, vT, vN, vT, 0.0, 0.0, 0.0)
        if idx == 0:
            pm[i, M_PLANE] = pm[i, M_PLANE2]
            pm[i, M_FEAT] = pm[i, M_FEAT2]
        pm[i, M_PLANE2] = -1
        p = pm[i, M_PLANE]
        _pv_params(i, w, bint, bflt, verts, planes, grav, law_par, bp_law, pm)
        px, py, rx, ry, vN, vT = _pv_contact(i, st, bint, bflt, verts, planes, pm)
        rc = _pv_follow_slip(i, st, w, pm, vT)
        if rc == ERR_PAINLEVE:
            _set_err(err, t, i, -1 - p, px, py, w[CP_MU], vT, 0.0)
            return rc, 0
        if rc == 1:
            # the other contact cannot hold the body either: free flight
            pm[i, M_MODE] = PM_FLIGHT
            pm[i, M_AUX] = REL_TANGENT
            st[i, AX] = grav[0]
            st[i, AY] = grav[1]
            st[i, ALPHA] = 0.0
            _log(ev_t, ev_i, ev_f, cnt, t, EV_RELEASE, i, -1 - p, 0, 0, px, py, planes[p, 0],
                 planes[p, 1], vN, vT, vN, vT, 0.0, 0.0, 0.0)
            return 0, 1
    elif kind == PE_STOP:
        pg, px, py, rx, ry, vN, vT = _two_contact(i, idx, st, bint, bflt, verts, planes, pm)
        _log(ev_t, ev_i, ev_f, cnt, t, EV_SLIDE, i, -1 - pg, 1, 0, px, py, planes[pg, 0],
             planes[pg, 1], vN, vT, vN, vT, 0.0, 0.0, 0.0)
    elif kind == PE_TURN:
        p1 = pm[i, M_PLANE]
        p2 = pm[i, M_PLANE2]
        q1, px, py, r1x, r1y, vN, vT = _two_contact(i, int64(0), st, bint, bflt, verts, planes, pm)
        q2, px2, py2, r2x, r2y, vN2, vT2 = _two_contact(i, int64(1), st, bint, bflt, verts,
                                                        planes, pm)
        if two_contact_rest(bflt[i, B_MASS], grav[0], grav[1], r1x, r1y, planes[p1, 0],
                            planes[p1, 1], w[CP_MU], r2x, r2y, planes[p2, 0], planes[p2, 1],
                            w[CP_MU2]):
            pm[i, M_PLANE2] = -1
            _wedge(i, p1, t, st, bflt, grav, pm, tz, ttr, px, py, vN, vT, planes, ev_t, ev_i,
                   ev_f, cnt)
            return 0, 1
        e0 = _energy(st, bflt, grav, i)
        st[i, VX] = 0.0
        st[i, VY] = 0.0
        st[i, OMEGA] = 0.0
        mu1 = w[CP_MU]
        mu2 = w[CP_MU2]
        rc = _two_choose(i, st, w, pm)
        if rc == 0:
            _log(ev_t, ev_i, ev_f, cnt, t, EV_SLIDE, i, -1 - p1, 1, 0, px, py, planes[p1, 0],
                 planes[p1, 1], vN, vT, 0.0, 0.0, 0.0, 0.0, _energy(st, bflt, grav, i) - e0)
        elif _two_drop(i, t, st, bint, bflt, verts, planes, grav, law_par, bp_law, pm, w,
                       ev_t, ev_i, ev_f, cnt) != 0:
            _set_err(err, t, i, -1 - p1, px, py, float(p2), mu1, mu2)
            return (ERR_PAINLEVE if rc == ERR_PAINLEVE else ERR_TWO_PLANES), 0
    rc = _pivot_pass(i, t, st, tref, bint, bflt, verts, planes, grav, law_par, bp_law,
                     bp_off, pm, zp, ttr, tolf, w, seg_t, seg_b, seg_s, cnt, err, INF)
    return rc, 0


# ------------------------------------------------------------------ impact resolution


@njit(cache=True, inline="always", _nrt=False)
def _single(law, c, t, cluster, st, bflt, law_ids, law_par, c_i, c_f, v2, W2, P2, ev_t,
            ev_i, ev_f, cnt, err):
    """Resolve contact c with its pair law at its current velocity (``law``: the scene's
    one law, a compile-time constant, or ``LAW_ANY``). Returns (rc, v_fN)."""
    viN, viT = _contact_velocity(st, c_i, c_f, c)
    v2[0] = viN
    v2[1] = viT
    _contact_W(bflt, c_i, c_f, c, W2)
    li = c_i[c, CI_LAW]
    mode = resolve_2d_as(law, law_ids[li], v2, W2, law_par[li], P2)
    if mode < 0:
        _set_err(err, t, c_i[c, CI_A], _bcode(c_i, c), c_f[c, CF_PX], c_f[c, CF_PY], mode,
                 viN, viT)
        return ERR_NO_SOLUTION, 0.0
    PN = P2[0]
    PT = P2[1]
    _apply(st, bflt, c_i, c_f, c, PN, PT)
    vfN, vfT = _contact_velocity(st, c_i, c_f, c)
    c_f[c, CF_PN] += PN
    c_f[c, CF_PT] += PT
    _log(ev_t, ev_i, ev_f, cnt, t, EV_IMPACT, c_i[c, CI_A], _bcode(c_i, c), mode, cluster,
         c_f[c, CF_PX], c_f[c, CF_PY], c_f[c, CF_NX], c_f[c, CF_NY], viN, viT, vfN, vfT,
         PN, PT, 0.5 * (PN * (viN + vfN) + PT * (viT + vfT)))
    return 0, vfN


@njit(cache=True, _nrt=False, inline="always")
def _bcode(c_i, c):
    if c_i[c, CI_TYPE] == 0:
        return -1 - c_i[c, CI_B]
    return c_i[c, CI_B]


@_inner
def _jblock(c, d, bflt, c_i, c_f):
    """2x2 block of the stacked Delassus matrix coupling contacts c and d."""
    w00 = 0.0
    w01 = 0.0
    w10 = 0.0
    w11 = 0.0
    ncx = c_f[c, CF_NX]
    ncy = c_f[c, CF_NY]
    ndx = c_f[d, CF_NX]
    ndy = c_f[d, CF_NY]
    for sc in range(2):
        if sc == 1 and c_i[c, CI_TYPE] == 0:
            continue
        jc = c_i[c, CI_A] if sc == 0 else c_i[c, CI_B]
        rcx = c_f[c, CF_RAX] if sc == 0 else c_f[c, CF_RBX]
        rcy = c_f[c, CF_RAY] if sc == 0 else c_f[c, CF_RBY]
        scs = 1.0 if sc == 0 else -1.0
        for sd in range(2):
            if sd == 1 and c_i[d, CI_TYPE] == 0:
                continue
            jd = c_i[d, CI_A] if sd == 0 else c_i[d, CI_B]
            if jd != jc:
                continue
            rdx = c_f[d, CF_RAX] if sd == 0 else c_f[d, CF_RBX]
            rdy = c_f[d, CF_RAY] if sd == 0 else c_f[d, CF_RBY]
            sds = 1.0 if sd == 0 else -1.0
            im = 1.0 / bflt[jc, B_MASS]
            iI = 1.0 / bflt[jc, B_INERTIA]
            sg = scs * sds
            # directions: c normal (ncx, ncy), c tangent (ncy, -ncx); same for d
            cnc = rcx * ncy - rcy * ncx
            ctc = rcx * (-ncx) - rcy * ncy
            cnd = rdx * ndy - rdy * ndx
            ctd = rdx * (-ndx) - rdy * ndy
            w00 += sg * ((ncx * ndx + ncy * ndy) * im + cnc * cnd * iI)
            w01 += sg * ((ncx * ndy - ncy * ndx) * im + cnc * ctd * iI)
            w10 += sg * ((ncy * ndx - ncx * ndy) * im + ctc * cnd * iI)
            w11 += sg * ((ncy * ndy + ncx * ndx) * im + ctc * ctd * iI)
    return w00, w01, w10, w11


#: joint solve: with redundant frictional contacts (a rod lying on both ends: their
#: tangential impulses act along one line) the sweeps can cycle instead of converging; after
#: simul_max_iter sweeps the solve is accepted if the last sweep changed no contact velocity
#: by more than SIMUL_ACCEPT_RTOL times the largest pre-impact contact speed (as stepper3d),
#: else the run fails (ERR_PGS). A rod rocking to rest cycled at 1.3e-12 of it.
SIMUL_ACCEPT_RTOL = 1e-9


#: the finish of a joint solve whose sweeps cycle (_joint_finish): the semismooth Newton
#: polish (joint_polish.polish_ws) to simul_tol, then the exact active sets
#: (joint_polish.enumerate2d, at most ENUM_MAX_K contacts) checked to SIMUL_ACCEPT_RTOL
#: times the largest pre-impact contact speed. The polish's workspace is Wb beyond the
#: K contacts' W block: at most JOINT_FINISH_MAXK contacts (3 n <= 2 MAXC and
#: 2 n + 9 <= 2 MAXC rows, n = 2K).
JOINT_FINISH_MAXK = 5
assert 3 * 2 * JOINT_FINISH_MAXK <= 2 * MAXC and 4 * JOINT_FINISH_MAXK + 9 <= 2 * MAXC


@_inner
def _joint_finish(members, K, c_i, c_f, law_par, Wb, Pb, vb, tb, tol, atol, dmax):
    """Finish the joint solve of ``_joint`` when its Gauss-Seidel sweeps cycle. Gauss-Seidel
    cycles when the two contacts of a body on two planes (a groove, a corner, a wall) are
    redundant: W (4 x 4) has rank 3, its null vector z (a squeeze: impulses that change no
    velocity) lies in both friction cones with mu large, and each sweep pushes the impulses
    further along z without settling the velocities. Returns 1 (solved: ``Pb`` holds the
    impulses), 2 (no solution exists: every active set of the contacts checked, a jam of
    Newton restitution with Coulomb friction) or 0 (not decided). In order: the
    semismooth Newton polish from the sweeps' iterate to ``tol`` (m/s); the sweeps'
    own acceptance (their last change ``dmax`` <= ``atol``, m/s); the exact active sets
    (``enumerate2d``, inequalities to ``atol``; among several solutions the one whose
    velocities are nearest the sweeps' last ones)."""
    if K > JOINT_FINISH_MAXK:
        return 1 if dmax <= atol else 0
    n = 2 * K
    J = Wb[n:2 * n, 0:n]
    A = Wb[n:2 * n, n:2 * n]
    N = Wb[n:2 * n, 2 * n:3 * n]
    r = Wb[2 * n, 0:K]
    F = Wb[2 * n + 1, 0:n]
    F2 = Wb[2 * n + 2, 0:n]
    g = Wb[2 * n + 3, 0:n]
    d = Wb[2 * n + 4, 0:n]
    X = Wb[2 * n + 5, 0:n]
    Y = Wb[2 * n + 6, 0:n]
    v0 = Wb[2 * n + 7, 0:n]
    mus = Wb[2 * n + 8, 0:K]
    for a in range(K):
        c = members[a]
        v0[2 * a] = c_f[c, CF_VIN]
        v0[2 * a + 1] = c_f[c, CF_VIT]
        mus[a] = law_par[c_i[c, CI_LAW], P_MU]
    solved = polish_ws(Wb, v0, tb, mus, Pb, K, tol, 2, r, F, F2, g, d, X, Y, J, A, N)
    if not solved and dmax <= atol:
        return 1
    if not solved and K <= ENUM_MAX_K:
        M = Wb[n:2 * n, 0:n + 1]
        found, undecided = enumerate2d(Wb, v0, tb, mus, K, atol, vb, Pb, M, X)
        if found == 0:
            return 2 if undecided == 0 else 0
        solved = True
    if not solved:
        return 0
    # the impulses on their cones (the polish leaves round-off of tol outside)
    for a in range(K):
        pn = max(Pb[2 * a], 0.0)
        Pb[2 * a] = pn
        Pb[2 * a + 1] = min(max(Pb[2 * a + 1], -mus[a] * pn), mus[a] * pn)
    return 1


@_inner     # compiled on first use: only scenes with clusters
def _joint(members, K, t, st, bflt, law_par, c_i, c_f, Wb, Pb, vb, tb, tolf, toli, ev_t,
           ev_i, ev_f, cnt, err):
    """Simultaneous policy: Newton restitution + Coulomb friction solved jointly over the
    K contacts (projected Gauss-Seidel on the stacked Delassus matrix)."""
    for a in range(K):
        c = members[a]
        viN, viT = _contact_velocity(st, c_i, c_f, c)
        c_f[c, CF_VIN] = viN
        c_f[c, CF_VIT] = viT
        e = law_par[c_i[c, CI_LAW], P_E]
        if not (0.0 <= e <= 1.0):
            _set_err(err, t, c_i[c, CI_A], _bcode(c_i, c), c_f[c, CF_PX], c_f[c, CF_PY], e,
                     0.0, 0.0)
            return ERR_JOINT_E
        vb[2 * a] = viN
        vb[2 * a + 1] = viT
        tb[2 * a] = -e * min(viN, 0.0)
        Pb[2 * a] = 0.0
        Pb[2 * a + 1] = 0.0
        for b in range(K):
            w00, w01, w10, w11 = _jblock(c, members[b], bflt, c_i, c_f)
            Wb[2 * a, 2 * b] = w00
            Wb[2 * a, 2 * b + 1] = w01
            Wb[2 * a + 1, 2 * b] = w10
            Wb[2 * a + 1, 2 * b + 1] = w11
    n2 = 2 * K
    vmax = 0.0
    for k in range(n2):
        vmax = max(vmax, abs(vb[k]))
    tol = tolf[TF_SIMUL_TOL] * vmax
    converged = False
    for it in range(toli[TI_SIMUL_MAXIT]):
        dmax = 0.0
        for a in range(K):
            mu = law_par[c_i[members[a], CI_LAW], P_MU]
            for r in range(2):
                idx = 2 * a + r
                if r == 0:
                    new = Pb[idx] - (vb[idx] - tb[idx]) / Wb[idx, idx]
                    if new < 0.0:
                        new = 0.0
                else:
                    lim = mu * Pb[idx - 1]
                    new = Pb[idx] - vb[idx] / Wb[idx, idx]
                    if new > lim:
                        new = lim
                    elif new < -lim:
                        new = -lim
                dp = new - Pb[idx]
                if dp != 0.0:
                    Pb[idx] = new
                    for k in range(n2):
                        vb[k] += Wb[k, idx] * dp
                    dv = abs(dp) * Wb[idx, idx]
                    if dv > dmax:
                        dmax = dv
        if dmax <= tol:
            converged = True
            break
    jam = 0.0
    if not converged:
        rc = _joint_finish(members, K, c_i, c_f, law_par, Wb, Pb, vb, tb, tol,
                           SIMUL_ACCEPT_RTOL * vmax, dmax)
        converged = rc == 1
        jam = 1.0 if rc == 2 else 0.0
    if not converged:
        c = members[0]
        _set_err(err, t, c_i[c, CI_A], _bcode(c_i, c), c_f[c, CF_PX], c_f[c, CF_PY], K,
                 dmax, jam)
        return ERR_PGS
    for a in range(K):
        c = members[a]
        _apply(st, bflt, c_i, c_f, c, Pb[2 * a], Pb[2 * a + 1])
    for a in range(K):
        c = members[a]
        PN = Pb[2 * a]
        PT = Pb[2 * a + 1]
        viN = c_f[c, CF_VIN]
        viT = c_f[c, CF_VIT]
        c_f[c, CF_PN] += PN
        c_f[c, CF_PT] += PT
        if PN == 0.0 and viN >= 0.0:
            continue
        vfN, vfT = _contact_velocity(st, c_i, c_f, c)
        mu = law_par[c_i[c, CI_LAW], P_MU]
        if PN == 0.0:
            mode = 0
        elif abs(PT) < mu * PN * (1.0 - 1e-12):
            mode = 1
        else:
            mode = 2
        _log(ev_t, ev_i, ev_f, cnt, t, EV_IMPACT, c_i[c, CI_A], _bcode(c_i, c), mode, K,
             c_f[c, CF_PX], c_f[c, CF_PY], c_f[c, CF_NX], c_f[c, CF_NY], viN, viT, vfN, vfT,
             PN, PT, 0.5 * (PN * (viN + vfN) + PT * (viT + vfT)))
    return 0


@njit(cache=True, inline="always", _nrt=False)
def _sequential(law, members, K, vtol, t, st, bflt, law_ids, law_par, c_i, c_f, v2, W2, P2,
                toli, ev_t, ev_i, ev_f, cnt, err):
    """Sequential policy: repeatedly resolve, with its pair law, the contact that approaches
    fastest (ties: lowest contact index), until none approaches faster than vtol. A single
    contact goes through here too, with vtol = 0, and is resolved once if it approaches: the
    law's answer is final (a law that leaves v_N = -1.6e-18 m/s, the round-off of its
    impulse, gives the same answer again: 1000 resolutions and an error)."""
    steps = toli[TI_SEQ_MAXSTEPS] if K > 1 else 1
    for step in range(steps):
        best = -1
        vbest = -vtol
        for a in range(K):
            c = members[a]
            if c_i[c, CI_OFF] != 0:
                continue
            vN, vT = _contact_velocity(st, c_i, c_f, c)
            if vN < vbest:
                vbest = vN
                best = c
        if best < 0:
            return 0
        rc, vfN = _single(law, best, t, K, st, bflt, law_ids, law_par, c_i, c_f, v2, W2,
                          P2, ev_t, ev_i, ev_f, cnt, err)
        if rc < 0:
            return rc
        if perforates(law_par[c_i[best, CI_LAW]], vfN):
            c_i[best, CI_OFF] = 1
    if K == 1:
        return 0
    c = members[0]
    _set_err(err, t, c_i[c, CI_A], _bcode(c_i, c), c_f[c, CF_PX], c_f[c, CF_PY], K,
             toli[TI_SEQ_MAXSTEPS], 0.0)
    return ERR_SEQ


# ------------------------------------------------------------------ the event loop


@_inner
def _init(pivot, shapes, t, st, tref, bint, bflt, verts, planes, grav, law_par, bp_law, pm,
          tz, zp, ttr, tolf, w, ev_t, ev_i, ev_f, cnt, err):
    """Start of a run: settle the bodies that start at rest on a plane (or pivot those
    that start on a face that cannot hold them: tipping). ``pivot``, ``shapes``: those
    feature switches (``scene_features``); a body other than a disk in a loop compiled for
    disks only is ``ERR_NOT_COMPILED`` (the pivot feature, which such a body sets)."""
    nb = st.shape[0]
    for i in range(nb):
        tref[i] = t
        st[i, AX] = grav[0]
        st[i, AY] = grav[1]
        st[i, ALPHA] = 0.0
        if not _finite(st, i):
            _set_err(err, t, i, 0, st[i, X], st[i, Y], 0.0, 0.0, 0.0)
            return ERR_NONFINITE
        if shapes is None and bint[i, B_KIND] != SH_DISK:
            return _not_compiled(err, t, i, FEATURE_PIVOT)
    for i in range(nb):
        for p in range(planes.shape[0]):
            if pm[i, M_MODE] != PM_FLIGHT:
                break
            nx = planes[p, 0]
            ny = planes[p, 1]
            gn = nx * grav[0] + ny * grav[1]
            if not gn < 0.0:
                continue
            stable, f0, f1, hf, dth, eex = _rest_config(i, p, st, bint, bflt, verts, planes,
                                                        grav, shapes)
            hc = nx * st[i, X] + ny * st[i, Y] - planes[p, 2]
            if not stable or hc - hf > tolf[TF_GAP_TOL]:
                continue
            if (eex < 0.5 * bflt[i, B_MASS] * _vz2(tolf, -gn)
                    and eex >= -bflt[i, B_MASS] * (-gn) * SNAP_RTOL * hf):
                rc = _settle(shapes, i, p, t, st, bint, bflt, verts, planes, grav, law_par,
                             bp_law, pm, ttr, tolf, ev_t, ev_i, ev_f, cnt, err)
                if rc == RC_TIP:
                    rc = _tip_if(pivot, i, t, st, bint, bflt, verts, planes, grav, law_par,
                                 bp_law, pm, tz, zp, ttr, tolf, w, ev_t, ev_i, ev_f, cnt, err)
                if rc < 0:
                    return rc
    return 0


@_inner
def _vertex_in_instant(kind, row, px, py, bf, plane, t, t0, tw, tolf, toli):
    """Whether the vertex ``(px, py)`` of a body of several contact points (state ``row`` at
    ``t0``, ``bflt`` row ``bf``) belongs to the instant ``[t, tw]`` on ``plane``: it touches
    within it, or closes within ``simul_gap`` (not inlined: compiled only with the pivot
    switch, which every body of several contact points sets)."""
    s, code = plane_feature_toi(kind, row, px, py, bf[B_RADIUS], bf[B_EA], bf[B_EB], plane[0],
                                plane[1], plane[2], t0, tw - t0, tolf[TF_TOI_RTOL],
                                tolf[TF_TOI_ATOL], tolf[TF_GAP_TOL], toli[TI_TOI_MAXIT])
    g, gd = feature_gap(kind, row, px, py, bf[B_RADIUS], bf[B_EA], bf[B_EB], plane[0],
                        plane[1], plane[2], t - t0)
    if not (t0 + s <= tw):
        return g <= tolf[TF_SIMUL_GAP] and gd < 0.0
    # a root from the segment start that is not a touch now (the tangency a released
    # vertex starts from) is not in this instant
    return not g > tolf[TF_GAP_TOL]


@njit(cache=True, _nrt=False, inline="always")
def _gather(pivot, t, st, bint, bflt, verts, planes, grav, bp_law, pairs, pm, tolf, toli,
            tref, bp_t, pr_t, c_i, bmark, err):
    """Gather the contacts touching in [t, t + simul_time] (and closing corners within
    simul_gap; and the held vertex of a body in pivot contact) and mark their bodies; a
    body in pivot contact is in flight from t. Returns the number of contacts or an error
    code. ``pivot``: that feature switch (True or None). Then ``_bring_to_t`` and
    ``_frames`` (flat steps inlined into run_loop on their own, see ``_mark_pairs``)."""
    nb = st.shape[0]
    npl = planes.shape[0]
    npr = pairs.shape[0]
    # ---- impacts: gather every contact touching within [t, t + simul_time]
    tw = t + tolf[TF_SIMUL_TIME]
    nc = 0
    for i in range(nb):
        piv = False
        if pm[i, M_MODE] == PM_PIVOT:
            for p in range(npl):
                if bp_t[i, p] <= tw:
                    piv = True
        for p in range(npl):
            held = piv and p == pm[i, M_PLANE]
            held2 = piv and p == pm[i, M_PLANE2]
            if bp_t[i, p] > tw and not held and not held2:
                continue
            bmark[i] = 1
            kind = FEAT_ELLIPSE if bint[i, B_KIND] == SH_ELLIPSE else FEAT_VERTEX
            v0 = bint[i, B_FIRST]
            nv = bint[i, B_COUNT]
            for k in range(nv):
                if (held and k == pm[i, M_FEAT]) or (held2 and k == pm[i, M_FEAT2]):
                    pass    # a held vertex is in the cluster (at gap 0)
                elif nv > 1:
                    # several contact points: a polygon, rod or capsule (the pivot switch)
                    if pivot is None:
                        return _not_compiled(err, t, i, FEATURE_PIVOT)
                    if not _vertex_in_instant(kind, st[i], verts[v0 + k, 0], verts[v0 + k, 1],
                                              bflt[i], planes[p], t, tref[i], tw, tolf, toli):
                        continue
                nc = _add_plane_contact(c_i, nc, i, p, v0 + k, bp_law[i, p], t, st, err)
                if nc < 0:
                    return nc
        if piv:
            # the integrated contact ends with the impact: in flight at t (after the
            # impacts, _persisting and the steps after it decide what persists)
            _in_flight(i, st, pm, grav)
    for q in range(npr):
        if pr_t[q] > tw:
            continue
        if nc >= MAXC:
            _set_err(err, t, pairs[q, 0], pairs[q, 1], 0.0, 0.0, MAXC, 0.0, 0.0)
            return ERR_TOO_MANY
        bmark[pairs[q, 0]] = BM_PAIR
        bmark[pairs[q, 1]] = BM_PAIR
        c_i[nc, CI_TYPE] = 1
        c_i[nc, CI_A] = pairs[q, 0]
        c_i[nc, CI_B] = pairs[q, 1]
        c_i[nc, CI_FEAT] = -2 - q       # the pair's row (two disks: frame below; any
                                        # other pair: _pair_rows)
        c_i[nc, CI_LAW] = pairs[q, 2]
        c_i[nc, CI_OFF] = 0
        nc += 1
    return nc


BM_PAIR = 2     # bmark of a body marked by a body-body contact of the instant (else 1)


@njit(cache=True, _nrt=False, inline="always")
def _held_on_plane(mode):
    """Whether a body in ``mode`` is held on a plane in closed form (at rest, sliding or
    rolling on a face or its round boundary, at rest on two planes)."""
    return mode == PM_REST or mode == PM_SLIDE or mode == PM_ROLL or mode == PM_WEDGED


@_inner
def _held_into_instant(nc, t, st, bint, bflt, verts, planes, grav, bp_law, bp_off, pm, ttr,
                       tolf, c_i, bmark, err):
    """Simultaneous policy: every body of a body-body contact of the instant (marked
    ``BM_PAIR`` by ``_gather``, brought to t by ``_bring_to_t``) takes the features touching
    a plane at t (gap within ``gap_tol``) into it, unless they part faster than the body's
    zero speed (``pair_zero_speed``):
    the plane's reaction is impulsive too, so the joint solve sees the body supported (a
    domino struck on the floor pivots on its far corner; a disk struck from above on the
    floor stays and the one above rebounds). Without it a body held on a plane (rest, slide
    or roll: ``_held_on_plane``), or a member of a cluster dissolved into the instant whose
    pivot corner does not close (``_vertex_in_instant``), was first driven into its plane
    and hit it afterwards: the sequential policy's answer. A held body is in flight from t,
    as a pivoting body is (``_gather``); after the impacts ``_persisting`` and the steps
    after it decide what persists. A body alone whose feature hits another plane while it
    is held (a disk rolling down one side of a groove into the other) is not covered: its
    held contact is re-evaluated after the impact (``_reevaluate``), as before; taken into
    the impact, elastic and rough grooves of the 2D campaign chattered for 1e5 impacts.
    Returns the new contact count or an error code."""
    for i in range(st.shape[0]):
        if bmark[i] != BM_PAIR:
            continue
        held = _held_on_plane(pm[i, M_MODE])
        if not held and pm[i, M_MODE] != PM_FLIGHT:
            continue
        vz = INF if held else _body_zero_speed(i, st[i], bint, bflt, verts, tolf)
        nc = _held_features(i, nc, t, st, bint, bflt, verts, planes, bp_law, bp_off, tolf, vz,
                            c_i, err)
        if nc < 0:
            return nc
        if held:
            _in_flight(i, st, pm, grav)
            ttr[i] = INF
    return nc


@njit(cache=True, _nrt=False, inline="always")
def _in_flight(i, st, pm, grav):
    """Body i leaves its held contact at an impact instant: in flight under gravity."""
    pm[i, M_MODE] = PM_FLIGHT
    pm[i, M_PLANE2] = -1
    st[i, AX] = grav[0]
    st[i, AY] = grav[1]
    st[i, ALPHA] = 0.0


@njit(cache=True, _nrt=False, inline="always")
def _held_features(i, nc, t, st, bint, bflt, verts, planes, bp_law, bp_off, tolf, vz, c_i, err):
    """Append the features of body i (at t) touching a plane within ``gap_tol`` and parting
    at most at ``vz`` (m/s) that are not gathered yet to the instant's contacts (planes
    it perforated, ``bp_off``, excepted); returns the count or ERR_TOO_MANY."""
    kind = FEAT_ELLIPSE if bint[i, B_KIND] == SH_ELLIPSE else FEAT_VERTEX
    v0 = bint[i, B_FIRST]
    for p in range(planes.shape[0]):
        if bp_off[i, p] != 0:
            continue
        for k in range(bint[i, B_COUNT]):
            have = False
            for c in range(nc):
                if (c_i[c, CI_TYPE] == 0 and c_i[c, CI_A] == i and c_i[c, CI_B] == p
                        and c_i[c, CI_FEAT] == v0 + k):
                    have = True
                    break
            if have:
                continue
            g, gd = feature_gap(kind, st[i], verts[v0 + k, 0], verts[v0 + k, 1],
                                bflt[i, B_RADIUS], bflt[i, B_EA], bflt[i, B_EB], planes[p, 0],
                                planes[p, 1], planes[p, 2], 0.0)
            if not (g <= tolf[TF_GAP_TOL] and gd <= vz):
                continue
            nc = _add_plane_contact(c_i, nc, i, p, v0 + k, bp_law[i, p], t, st, err)
            if nc < 0:
                return nc
    return nc


@njit(cache=True, _nrt=False, inline="always")
def _add_plane_contact(c_i, nc, i, p, feat, law, t, st, err):
    """Append the contact of vertex ``feat`` of body i with plane p (law row ``law``) to the
    instant's contacts; returns the new count, or ERR_TOO_MANY beyond MAXC."""
    if nc >= MAXC:
        _set_err(err, t, i, -1 - p, st[i, X], st[i, Y], MAXC, 0.0, 0.0)
        return ERR_TOO_MANY
    c_i[nc, CI_TYPE] = 0
    c_i[nc, CI_A] = i
    c_i[nc, CI_B] = p
    c_i[nc, CI_FEAT] = feat
    c_i[nc, CI_LAW] = law
    c_i[nc, CI_OFF] = 0
    return nc + 1


@njit(cache=True, _nrt=False, inline="always")
def _bring_to_t(t, st, tref, bint, planes, grav, tz, zp, bmark):
    """Bring the bodies marked by ``_gather`` to t; a pending accumulation point is
    cancelled: the body continues from its held motion (on the plane, normal velocity zero;
    the normal energy of the unfinished accumulation, below the accumulation threshold
    m zeno_speed^2 / 2, is dropped without an event)."""
    for i in range(st.shape[0]):
        if bmark[i] != 0:
            held = tz[i] < INF
            if held:
                _held_into(st[i], bint[i, B_KIND], planes[zp[i], 0], planes[zp[i], 1], st[i])
                tz[i] = INF
            fly_row(st, i, t - tref[i])
            tref[i] = t
            if held:
                # in flight again from t: under gravity (the held row's acceleration lacked
                # its normal part; kept, it floated a disk bouncing between two groove walls
                # and the next accumulation gained 1e-9 J, 'done')
                st[i, AX] = grav[0]
                st[i, AY] = grav[1]


@njit(cache=True, _nrt=False, inline="always")
def _frames(pgen, shapes, nc, t, st, bint, bflt, verts, planes, tolf, c_i, c_f, err):
    """The contact frames of the ``nc`` gathered contacts (bodies at t). Returns the number
    of contacts (a face on face pair contact adds one: ``_pair_rows``) or an error code.
    ``pgen``, ``shapes``: the switches of the pairs of other shapes than two disks and of
    the shapes (True or None, ``loop_for``)."""
    nc0 = nc
    for c in range(nc0):
        a = c_i[c, CI_A]
        if c_i[c, CI_TYPE] == 1 and not (bint[a, B_KIND] == SH_DISK
                                         and bint[c_i[c, CI_B], B_KIND] == SH_DISK):
            # a pair of other shapes than two disks: one contact, or two (face on face)
            if pgen is None:
                return _not_compiled(err, t, a, FEATURE_PAIR)
            nc = _pair_rows(c, nc, t, st, bint, bflt, verts, tolf, c_i, c_f, err)
            if nc < 0:
                return nc
            continue
        if c_i[c, CI_TYPE] == 0:
            p = c_i[c, CI_B]
            nx = planes[p, 0]
            ny = planes[p, 1]
            px, py, rx, ry = _plane_contact(st, a, bint, bflt, verts, c_i[c, CI_FEAT],
                                            nx, ny, shapes)
            c_f[c, CF_RBX] = 0.0
            c_f[c, CF_RBY] = 0.0
        else:
            b = c_i[c, CI_B]
            dx = st[a, X] - st[b, X]
            dy = st[a, Y] - st[b, Y]
            dist = math.sqrt(dx * dx + dy * dy)
            nx = dx / dist
            ny = dy / dist
            rb = bflt[b, B_RADIUS]
            px = st[b, X] + rb * nx
            py = st[b, Y] + rb * ny
            rx = -bflt[a, B_RADIUS] * nx
            ry = -bflt[a, B_RADIUS] * ny
            c_f[c, CF_RBX] = rb * nx
            c_f[c, CF_RBY] = rb * ny
        c_f[c, CF_NX] = nx
        c_f[c, CF_NY] = ny
        c_f[c, CF_PX] = px
        c_f[c, CF_PY] = py
        c_f[c, CF_RAX] = rx
        c_f[c, CF_RAY] = ry
        c_f[c, CF_PN] = 0.0
        c_f[c, CF_PT] = 0.0
        c_f[c, CF_VCMN] = nx * st[a, VX] + ny * st[a, VY]
    return nc


@njit(cache=True, _nrt=False, inline="always")
def _face_support(V, v0, nv, c, s, ox, oy, nx, ny, sg, tol):
    """The core vertices of a body (rotation ``(c, s)``, centre at ``(ox, oy)``) on its
    extreme support along ``sg n`` (``sg = -1``: lowest along n, A's side; ``+1``: highest,
    B's side) within ``tol`` (m). Returns ``(d, count, tau_lo, tau_hi)``: the extreme
    ``n . p`` and the range of the tangential coordinates ``t . p`` (``t = (n_y, -n_x)``)
    of those vertices."""
    best = -INF
    for k in range(nv):
        px, py = vertex_at(V, v0, nv, k, ox, oy, c, s)
        d = sg * (nx * px + ny * py)
        if d > best:
            best = d
    cnt = 0
    lo = INF
    hi = -INF
    for k in range(nv):
        px, py = vertex_at(V, v0, nv, k, ox, oy, c, s)
        d = sg * (nx * px + ny * py)
        if d >= best - tol:
            cnt += 1
            tau = ny * px - nx * py
            lo = min(lo, tau)
            hi = max(hi, tau)
    return sg * best, cnt, lo, hi


@_inner
def _pair_rows(c, nc, t, st, bint, bflt, verts, tolf, c_i, c_f, err):
    """Contact frame of the pair contact c (bodies at t; not two disks): the gap's normal
    from B into A and witness points of ``pair2d.frame_rel``, the arms from each centre
    to its own witness point (so that ``W`` and ``v`` are those of the pair frame). Face
    on face (``PAIR_FACE_RTOL``): the two ends of the overlap of the two faces, row c and a
    new row nc (same bodies and law). Returns the new number of contacts (or an error)."""
    a = c_i[c, CI_A]
    b = c_i[c, CI_B]
    kA = bint[a, B_KIND]
    kB = bint[b, B_KIND]
    iA = bint[a, B_FIRST]
    nA = bint[a, B_COUNT]
    iB = bint[b, B_FIRST]
    nB = bint[b, B_COUNT]
    rA = bflt[a, B_RADIUS]
    rB = bflt[b, B_RADIUS]
    dx = st[b, X] - st[a, X]
    dy = st[b, Y] - st[a, Y]
    g, nx, ny, pax, pay, pbx, pby, fa, ia, fb, ib = frame_rel(
        kA, rA, bflt[a, B_EA], bflt[a, B_EB], verts, iA, nA, st[a, ANGLE], kB, rB,
        bflt[b, B_EA], bflt[b, B_EB], verts, iB, nB, dx, dy, st[b, ANGLE])
    if not (math.isfinite(g) and math.isfinite(nx) and math.isfinite(ny)):
        _set_err(err, t, a, b, st[a, X], st[a, Y], 0.0, 0.0, 0.0)
        return ERR_NONFINITE
    two = False
    tlo = 0.0
    thi = 0.0
    dA = 0.0
    dB = 0.0
    if kA == SH_POLY and kB == SH_POLY and nA >= 2 and nB >= 2:
        LA, _ = body_reach(kA, rA, 0.0, 0.0, verts, iA, nA)
        LB, _ = body_reach(kB, rB, 0.0, 0.0, verts, iB, nB)
        cA = math.cos(st[a, ANGLE])
        sA = math.sin(st[a, ANGLE])
        cB = math.cos(st[b, ANGLE])
        sB = math.sin(st[b, ANGLE])
        dA, kcA, loA, hiA = _face_support(verts, iA, nA, cA, sA, 0.0, 0.0, nx, ny, -1.0,
                                          tolf[TF_SIMUL_GAP] + PAIR_FACE_RTOL * LA)
        dB, kcB, loB, hiB = _face_support(verts, iB, nB, cB, sB, dx, dy, nx, ny, 1.0,
                                          tolf[TF_SIMUL_GAP] + PAIR_FACE_RTOL * LB)
        if kcA >= 2 and kcB >= 2:
            tlo = max(loA, loB)
            thi = min(hiA, hiB)
            two = thi - tlo > PAIR_FACE_RTOL * max(LA, LB)
    vcm = nx * st[a, VX] + ny * st[a, VY]
    if not two:
        _pair_row(c, st[a, X], st[a, Y], dx, dy, nx, ny, pax, pay, pbx - dx, pby - dy, vcm,
                  c_f)
        return nc
    if nc >= MAXC:
        _set_err(err, t, a, b, st[a, X], st[a, Y], MAXC, 0.0, 0.0)
        return ERR_TOO_MANY
    for j in range(N_CI):
        c_i[nc, j] = c_i[c, j]
    tx = ny
    ty = -nx
    for e in range(2):
        tau = tlo if e == 0 else thi
        row = c if e == 0 else nc
        # points of the faces' lines at tangential coordinate tau (relative to A's centre)
        qax = (dA - rA) * nx + tau * tx
        qay = (dA - rA) * ny + tau * ty
        qbx = (dB + rB) * nx + tau * tx
        qby = (dB + rB) * ny + tau * ty
        _pair_row(row, st[a, X], st[a, Y], dx, dy, nx, ny, qax, qay, qbx - dx, qby - dy,
                  vcm, c_f)
    return nc + 1


@njit(cache=True, _nrt=False, inline="always")
def _pair_row(c, xa, ya, dx, dy, nx, ny, rax, ray, rbx, rby, vcm, c_f):
    """Write the frame of pair contact c: normal, arms of A and B (m, from each centre; B's
    centre at ``(dx, dy)`` from A's ``(xa, ya)``), the logged point (the middle of the two
    witness points, world), no impulse yet."""
    c_f[c, CF_NX] = nx
    c_f[c, CF_NY] = ny
    c_f[c, CF_RAX] = rax
    c_f[c, CF_RAY] = ray
    c_f[c, CF_RBX] = rbx
    c_f[c, CF_RBY] = rby
    c_f[c, CF_PX] = xa + 0.5 * (rax + rbx + dx)
    c_f[c, CF_PY] = ya + 0.5 * (ray + rby + dy)
    c_f[c, CF_PN] = 0.0
    c_f[c, CF_PT] = 0.0
    c_f[c, CF_VCMN] = vcm


@njit(cache=True, _nrt=False, inline="always")
def _resolve(law, joint, nc, t, st, bflt, law_ids, law_par, c_i, c_f, Wb, Pb, vb, tb, comp,
             v2, W2, P2, tolf, toli, ev_t, ev_i, ev_f, cnt, err):
    """Group the gathered contacts into clusters sharing a body and resolve each one."""
    policy = toli[TI_POLICY]
    cluster_contacts(nc, c_i, comp)
    for root in range(nc):
        # members of this cluster, in contact order, stored in the tail of comp
        K = cluster_members(nc, comp, root, MAXC)
        if K == 0:
            continue
        members = comp[MAXC:MAXC + K]
        if K > 1 and policy == POL_SIMULTANEOUS:
            if joint is not None:
                rc = _joint(members, K, t, st, bflt, law_par, c_i, c_f, Wb, Pb, vb, tb, tolf,
                            toli, ev_t, ev_i, ev_f, cnt, err)
            else:
                rc = _not_compiled(err, t, c_i[members[0], CI_A], FEATURE_JOINT)
            if rc < 0:
                return rc
        else:
            vtol = tolf[TF_SEQ_VTOL] if K > 1 else 0.0
            rc = _sequential(law, members, K, vtol, t, st, bflt, law_ids, law_par, c_i, c_f,
                             v2, W2, P2, toli, ev_t, ev_i, ev_f, cnt, err)
            if rc < 0:
                return rc
    return 0


@njit(cache=True, _nrt=False, inline="always")
def _single_ready(c, t, st, c_i, c_f, err):
    """``_resolve`` for a loop compiled without the joint switch (``scene_features``: no
    polygon, one plane at most, no pairs), where no two contacts of an instant share a body:
    every contact is its own cluster, resolved once if it approaches (``_sequential`` with
    K = 1, the same events), without the cluster search; run_loop calls this, then
    ``_single`` (each inlined into it on its own, see ``_mark_pairs``), for each contact c
    in order. Returns 1 when contact c approaches (to resolve), 0 when not (or switched
    off), or ``ERR_NOT_COMPILED`` when it shares its body with an earlier contact (a bug of
    ``scene_features``)."""
    for d in range(c):
        if c_i[d, CI_A] == c_i[c, CI_A]:
            return _not_compiled(err, t, c_i[c, CI_A], FEATURE_JOINT)
    if c_i[c, CI_OFF] != 0:
        return 0
    vN, vT = _contact_velocity(st, c_i, c_f, c)
    return 1 if vN < 0.0 else 0


@_inner
def _try_wedge(i, nc, t, st, bint, bflt, verts, planes, grav, law_par, bp_law, pm, tz, ttr, tolf,
               c_i, c_f, ev_t, ev_i, ev_f, cnt):
    """Rest on several points (mode table): after the impacts of an instant, body i whose
    kinetic energy is below the accumulation threshold ``m zeno_speed^2 / 2`` and that
    touches two different planes (two contacts of this instant, or one and the
    plane it rolls, slides or rests on: a disk's point, a polygon's face; or three contacts
    of this instant on two or three planes) on which it can rest in static equilibrium with
    Coulomb friction (``wedge2d.two_contact_rest``, ``three_contact_rest``) comes to rest
    there: its remaining
    motion (below the threshold) is removed, event "rest" (mode ``PM_WEDGED``). Returns
    True when the body was wedged."""
    m = bflt[i, B_MASS]
    gabs = math.hypot(grav[0], grav[1])
    if not gabs > 0.0:
        return False
    ke = 0.5 * m * (st[i, VX] * st[i, VX] + st[i, VY] * st[i, VY]) \
        + 0.5 * bflt[i, B_INERTIA] * st[i, OMEGA] * st[i, OMEGA]
    if ke > 0.5 * m * _vz2(tolf, gabs):
        return False
    # candidate contacts: this instant's plane contacts of i, and a disk's persistent one
    first = -1
    for c in range(nc):
        if c_i[c, CI_TYPE] != 0 or c_i[c, CI_A] != i or c_i[c, CI_OFF] != 0:
            continue
        # pair c with a later contact d of this instant ...
        for d in range(c + 1, nc):
            if (c_i[d, CI_TYPE] != 0 or c_i[d, CI_A] != i or c_i[d, CI_OFF] != 0
                    or c_i[d, CI_B] == c_i[c, CI_B]):
                continue        # (two points of one plane: a face, see _rest_config)
            if two_contact_rest(m, grav[0], grav[1], c_f[c, CF_RAX], c_f[c, CF_RAY],
                                c_f[c, CF_NX], c_f[c, CF_NY], law_par[c_i[c, CI_LAW], P_MU],
                                c_f[d, CF_RAX], c_f[d, CF_RAY], c_f[d, CF_NX],
                                c_f[d, CF_NY], law_par[c_i[d, CI_LAW], P_MU]):
                first = c
                break
        if first >= 0:
            break
        # ... or with the face a polygon rests or slides on (its two corners: three
        # contacts)
        if ((pm[i, M_MODE] == PM_REST or pm[i, M_MODE] == PM_SLIDE)
                and bint[i, B_KIND] == SH_POLY and pm[i, M_PLANE] != c_i[c, CI_B]):
            q = pm[i, M_PLANE]
            nqx = planes[q, 0]
            nqy = planes[q, 1]
            mu_q = law_par[bp_law[i, q], P_MU]
            v0 = bint[i, B_FIRST]
            a0x, a0y, r0x, r0y = _plane_contact(st, i, bint, bflt, verts, v0 + pm[i, M_FEAT],
                                                nqx, nqy, True)
            a1x, a1y, r1x, r1y = _plane_contact(st, i, bint, bflt, verts, v0 + pm[i, M_AUX],
                                                nqx, nqy, True)
            if three_contact_rest(m, grav[0], grav[1],
                                  ((r0x, r0y, nqx, nqy, mu_q), (r1x, r1y, nqx, nqy, mu_q),
                                   (c_f[c, CF_RAX], c_f[c, CF_RAY], c_f[c, CF_NX],
                                    c_f[c, CF_NY], law_par[c_i[c, CI_LAW], P_MU]))):
                first = c
                break
        # ... or with the plane a disk rolls, slides or rests on
        if (bint[i, B_KIND] == SH_DISK and pm[i, M_MODE] != PM_FLIGHT
                and pm[i, M_MODE] != PM_WEDGED and pm[i, M_PLANE] != c_i[c, CI_B]):
            q = pm[i, M_PLANE]
            rad = bflt[i, B_RADIUS]
            mu_q = law_par[bp_law[i, q], P_MU]
            if two_contact_rest(m, grav[0], grav[1], c_f[c, CF_RAX], c_f[c, CF_RAY],
                                c_f[c, CF_NX], c_f[c, CF_NY], law_par[c_i[c, CI_LAW], P_MU],
                                -rad * planes[q, 0], -rad * planes[q, 1], planes[q, 0],
                                planes[q, 1], mu_q):
                first = c
                break
    if first < 0:
        # three of this instant's contacts on at least two planes (a capsule's end cap in
        # the bottom of a groove and its other cap on one wall)
        for c in range(nc):
            if c_i[c, CI_TYPE] != 0 or c_i[c, CI_A] != i or c_i[c, CI_OFF] != 0:
                continue
            for d in range(c + 1, nc):
                if c_i[d, CI_TYPE] != 0 or c_i[d, CI_A] != i or c_i[d, CI_OFF] != 0:
                    continue
                for e in range(d + 1, nc):
                    if (c_i[e, CI_TYPE] != 0 or c_i[e, CI_A] != i or c_i[e, CI_OFF] != 0
                            or (c_i[c, CI_B] == c_i[d, CI_B] and c_i[d, CI_B] == c_i[e, CI_B])):
                        continue
                    if three_contact_rest(
                            m, grav[0], grav[1],
                            ((c_f[c, CF_RAX], c_f[c, CF_RAY], c_f[c, CF_NX], c_f[c, CF_NY],
                              law_par[c_i[c, CI_LAW], P_MU]),
                             (c_f[d, CF_RAX], c_f[d, CF_RAY], c_f[d, CF_NX], c_f[d, CF_NY],
                              law_par[c_i[d, CI_LAW], P_MU]),
                             (c_f[e, CF_RAX], c_f[e, CF_RAY], c_f[e, CF_NX], c_f[e, CF_NY],
                              law_par[c_i[e, CI_LAW], P_MU]))):
                        first = c
                        break
                if first >= 0:
                    break
            if first >= 0:
                break
    if first < 0:
        return False
    viN, viT = _contact_velocity(st, c_i, c_f, first)
    _wedge(i, c_i[first, CI_B], t, st, bflt, grav, pm, tz, ttr, c_f[first, CF_PX],
           c_f[first, CF_PY], viN, viT, planes, ev_t, ev_i, ev_f, cnt)
    return True


@_inner
def _wedge(i, p, t, st, bflt, grav, pm, tz, ttr, px, py, viN, viT, planes, ev_t, ev_i, ev_f,
           cnt):
    """Body i comes to rest on two planes (PM_WEDGED, logged on plane p at the contact
    point (px, py) with the contact velocity (viN, viT) it had): its remaining motion is
    removed; event "rest" with the energy removed."""
    e0 = _energy(st, bflt, grav, i)
    for j in range(VX, ALPHA + 1):     # velocities and accelerations
        st[i, j] = 0.0
    pm[i, M_MODE] = PM_WEDGED
    pm[i, M_PLANE] = p
    tz[i] = INF
    ttr[i] = INF
    _log(ev_t, ev_i, ev_f, cnt, t, EV_REST, i, -1 - p, PM_WEDGED, 0, px, py, planes[p, 0],
         planes[p, 1], viN, viT, 0.0, 0.0, 0.0, 0.0, _energy(st, bflt, grav, i) - e0)


@_inner
def _disk_second_plane(i, p, t, st, bflt, planes, grav, law_par, bp_law, pm, tz, ttr, tolf,
                       ev_t, ev_i, ev_f, cnt, err):
    """Disk i's impacts accumulate on plane p: if it also touches another plane q (gap
    within gap_tol) and does not leave it, the accumulation on p alone would ignore q (a disk
    in a groove gained 1e-7 of the scene's energy, status 'done'). It rests on p and q when
    its kinetic energy (spin included) is below the accumulation threshold ``m
    zeno_speed^2 / 2`` and that is a static equilibrium (event "rest", PM_WEDGED; returns
    1), else returns 2 + q (it may spin or slide on both planes: ``_two_enter``). Returns 0
    when no second plane is touched."""
    rad = bflt[i, B_RADIUS]
    m = bflt[i, B_MASS]
    for q in range(planes.shape[0]):
        if q == p:
            continue
        nqx = planes[q, 0]
        nqy = planes[q, 1]
        g = nqx * st[i, X] + nqy * st[i, Y] - rad - planes[q, 2]
        if g > tolf[TF_GAP_TOL]:
            continue
        if g < -tolf[TF_GAP_TOL]:
            _set_err(err, t, i, -1 - q, st[i, X], st[i, Y], 0.0, 0.0, 0.0)
            return ERR_MISSED       # already inside q: never rest there
        vq = nqx * st[i, VX] + nqy * st[i, VY]
        if vq * vq > _vz2(tolf, math.hypot(grav[0], grav[1])) and vq > 0.0:
            continue        # leaving q
        npx = planes[p, 0]
        npy = planes[p, 1]
        ke = 0.5 * m * (st[i, VX] * st[i, VX] + st[i, VY] * st[i, VY]) \
            + 0.5 * bflt[i, B_INERTIA] * st[i, OMEGA] * st[i, OMEGA]
        static = two_contact_rest(m, grav[0], grav[1], -rad * npx, -rad * npy, npx, npy,
                                  law_par[bp_law[i, p], P_MU], -rad * nqx, -rad * nqy, nqx,
                                  nqy, law_par[bp_law[i, q], P_MU])
        if static and ke <= 0.5 * m * _vz2(tolf, math.hypot(grav[0], grav[1])):
            vN = npx * st[i, VX] + npy * st[i, VY]
            vT = npy * st[i, VX] - npx * st[i, VY] + st[i, OMEGA] * rad
            _wedge(i, p, t, st, bflt, grav, pm, tz, ttr, st[i, X] - rad * npx,
                   st[i, Y] - rad * npy, vN, vT, planes, ev_t, ev_i, ev_f, cnt)
            return 1
        return 2 + q
    return 0


# ---- wedge handlers after the impacts (_persisting, _accumulating, _holding; compiled
# only with the wedge switch: not inlined, so that a loop without it never copies their
# code; ``pivot``: that switch, True or None)


@_inner
def _wedge_or_spin(pivot, i, nc, t, st, bint, bflt, verts, planes, grav, law_par, bp_law, pm,
                   tz, zp, ttr, tolf, c_i, c_f, w, ev_t, ev_i, ev_f, cnt):
    """After the impacts of an instant, body i rests on two planes (``_try_wedge``), or, a
    disk rolling, sliding (or spinning frictionless) on plane q that this instant's impact
    leaves on a second plane p, spins on both when both push (a frictionless disk spinning
    in a groove slid through p). Returns True when one of them holds the body."""
    if _try_wedge(i, nc, t, st, bint, bflt, verts, planes, grav, law_par, bp_law, pm, tz,
                  ttr, tolf, c_i, c_f, ev_t, ev_i, ev_f, cnt):
        return True
    if (pivot is not None and bint[i, B_KIND] == SH_DISK
            and pm[i, M_MODE] != PM_FLIGHT and pm[i, M_MODE] != PM_WEDGED
            and pm[i, M_MODE] != PM_PIVOT):
        q = pm[i, M_PLANE]
        for c in range(nc):
            if (c_i[c, CI_TYPE] != 0 or c_i[c, CI_A] != i or c_i[c, CI_OFF] != 0
                    or c_i[c, CI_B] == q):
                continue
            vN, vT = _contact_velocity(st, c_i, c_f, c)
            if vN * vN >= _vz2(tolf, math.hypot(grav[0], grav[1])):
                continue
            if _two_enter(i, q, 0, c_i[c, CI_B], 0, t, st, bint, bflt, verts, planes, grav,
                          law_par, bp_law, pm, tz, zp, ttr, w, ev_t, ev_i, ev_f, cnt) == 0:
                return True
    return False


@_inner
def _disk_groove(pivot, i, p, t, st, bint, bflt, verts, planes, grav, law_par, bp_law, pm,
                 tz, zp, ttr, tolf, w, ev_t, ev_i, ev_f, cnt, err):
    """Disk i whose impacts accumulate on plane p and that touches a second plane q
    (``_disk_second_plane``): it rests on both, or spins (or slides) on both when it is
    pressed into both. Returns 1 when it is held so (settled), 0 when its accumulation on
    p goes on, or an error code."""
    rc = _disk_second_plane(i, p, t, st, bflt, planes, grav, law_par, bp_law, pm, tz, ttr,
                            tolf, ev_t, ev_i, ev_f, cnt, err)
    if rc < 0:
        return rc
    if rc >= 2:
        q = rc - 2
        if pivot is not None:
            rc2 = _two_enter(i, p, 0, q, 0, t, st, bint, bflt, verts, planes, grav, law_par,
                             bp_law, pm, tz, zp, ttr, w, ev_t, ev_i, ev_f, cnt)
        else:
            rc2 = _not_compiled(err, t, i, FEATURE_PIVOT)
        if rc2 < 0:
            return rc2
        if rc2 == 0:
            return 1
    if rc == 1:
        return 1        # wedged between p and a second plane
    return 0


@_inner
def _hold_two(pivot, i, hold, amin, nc, t, st, bint, bflt, verts, planes, grav, law_par,
              bp_law, pm, tz, zp, ttr, tolf, c_i, c_f, w, ev_t, ev_i, ev_f, cnt):
    """Impacts of body i accumulate at contact ``hold`` (gap acceleration ``amin``): a
    contact on a second plane, as slow on the scale of the first (its free gap need not
    accelerate into its plane: a ladder's top is pushed into the wall by the floor), holds
    it on both when that is consistent (``_two_enter``). Returns True when it is held so."""
    hold2 = -1
    amin2 = 0.0
    for c in range(nc):
        if (c_i[c, CI_TYPE] != 0 or c_i[c, CI_A] != i or c_i[c, CI_OFF] != 0
                or c_i[c, CI_B] == c_i[hold, CI_B]):
            continue
        vN, vT = _contact_velocity(st, c_i, c_f, c)
        acc = _gap_accel(st, bint, bflt, c_i, c_f, c, verts, grav, True)
        if vN * vN < _vz2(tolf, -amin) and (hold2 < 0 or acc < amin2):
            amin2 = acc
            hold2 = c
    if hold2 >= 0 and pivot is not None:
        return _two_enter(i, c_i[hold, CI_B], c_i[hold, CI_FEAT] - bint[i, B_FIRST],
                          c_i[hold2, CI_B], c_i[hold2, CI_FEAT] - bint[i, B_FIRST], t, st,
                          bint, bflt, verts, planes, grav, law_par, bp_law, pm, tz, zp, ttr, w,
                          ev_t, ev_i, ev_f, cnt) == 0
    return False


# After the impacts of an instant (run_loop, per marked body: _persisting, then
# _accumulating, then _holding). Flat steps, each inlined into run_loop on its own: Numba
# copies an inlined function's whole variable table once per block of it, so one large
# helper costs its blocks times its variables (issue 14: the single _after_impacts of
# before took 1.6 s of a cold compile to copy).


@njit(cache=True, _nrt=False, inline="always")
def _mark_pairs(nc, pairs, bp_off, pr_off, c_i):
    """After the impacts of an instant: perforating impacts disable their pair for good; the
    pairs in an impact now are marked ``PR_HIT`` (their next search checks whether they stay
    in contact: ``_pair_persists``; two disks: ``_recompute_pair``)."""
    npr = pairs.shape[0]
    for c in range(nc):
        if c_i[c, CI_OFF] == 0:
            continue
        if c_i[c, CI_TYPE] == 0:
            bp_off[c_i[c, CI_A], c_i[c, CI_B]] = 1
        else:
            for q in range(npr):
                if ((pairs[q, 0] == c_i[c, CI_A] and pairs[q, 1] == c_i[c, CI_B])
                        or (pairs[q, 1] == c_i[c, CI_A] and pairs[q, 0] == c_i[c, CI_B])):
                    pr_off[q] = PR_OFF
    for c in range(nc):
        if c_i[c, CI_TYPE] == 1:
            q = -2 - c_i[c, CI_FEAT]
            if pr_off[q] == PR_ON:
                pr_off[q] = PR_HIT


@njit(cache=True, _nrt=False, inline="always")
def _persisting(pivot, wedge, shapes, i, nc, t, st, bint, bflt, verts, planes, grav, law_par,
                bp_law, pm, sched, tolf, c_i, c_f, w, ev, cnt, err):
    """Body i (marked at this instant) after its impacts: at rest or spinning on two planes
    (``_wedge_or_spin``), or its persistent contact re-evaluated (``_reevaluate``; tipping:
    ``_tip_if``). Returns 1 when that settles its state, 0 when it is in flight (released by
    this instant's impact on another plane: its impacts there may accumulate, as for a body
    in flight: ``_accumulating``), or an error code. ``sched`` = (tz, zp, ttr), ``ev`` =
    (ev_t, ev_i, ev_f)."""
    ev_t, ev_i, ev_f = ev
    tz, zp, ttr = sched
    if wedge is not None:
        if _wedge_or_spin(pivot, i, nc, t, st, bint, bflt, verts, planes, grav, law_par,
                          bp_law, pm, tz, zp, ttr, tolf, c_i, c_f, w, ev_t, ev_i, ev_f, cnt):
            return 1
    if pm[i, M_MODE] != PM_FLIGHT:
        rc = _reevaluate(shapes, i, t, st, bint, bflt, verts, planes, grav, law_par, bp_law,
                         pm, ttr, tolf, ev_t, ev_i, ev_f, cnt, err)
        if rc == RC_TIP:
            rc = _tip_if(pivot, i, t, st, bint, bflt, verts, planes, grav, law_par, bp_law,
                         pm, tz, zp, ttr, tolf, w, ev_t, ev_i, ev_f, cnt, err)
        if rc < 0:
            return rc
        if pm[i, M_MODE] != PM_FLIGHT:
            return 1
    return 0


@njit(cache=True, _nrt=False, inline="always")
def _accumulating(pivot, wedge, shapes, i, nc, t, st, bint, bflt, verts, planes, grav,
                  law_par, bp_law, bp_off, pm, sched, tolf, toli, c_i, c_f, w, ev, cnt, err):
    """Body i in flight after its impacts on planes pushing it: its first impact whose
    rest is consistent (the centre of mass over the face, the motion left below the
    accumulation threshold, a snap that does not lift it) schedules the accumulation (Zeno)
    point ``tz[i]`` on that plane (a disk in a groove: ``_disk_groove``). Returns 1 when
    scheduled (or settled), 0 when not, or an error code (``ERR_FAR_ACCUMULATION``: a disk's
    near-elastic bounces too many to step). ``sched``, ``ev``: as ``_persisting``."""
    ev_t, ev_i, ev_f = ev
    tz, zp, ttr = sched
    for c in range(nc):
        if c_i[c, CI_TYPE] != 0 or c_i[c, CI_A] != i:
            continue
        p = c_i[c, CI_B]
        if bp_off[i, p] != 0:
            continue
        nx = planes[p, 0]
        ny = planes[p, 1]
        gn = nx * grav[0] + ny * grav[1]
        if not gn < 0.0:
            continue
        stable, f0, f1, hf, dth, eex = _rest_config(i, p, st, bint, bflt, verts, planes,
                                                    grav, shapes)
        # accumulation on that rest only when consistent: the centre of mass is over
        # the face (stable), the motion left is below the threshold, and the snap
        # onto the face does not lift the body (create energy)
        thr = 0.5 * bflt[i, B_MASS] * _vz2(tolf, -gn)
        if not (stable and eex < thr and eex >= -bflt[i, B_MASS] * (-gn) * SNAP_RTOL * hf):
            if bint[i, B_KIND] == SH_DISK:
                # near-elastic bounces: stop before stepping through millions of them
                vn = nx * st[i, VX] + ny * st[i, VY]
                n = impacts_before_rest(vn, c_f[c, CF_VCMN], gn, t, tolf[TF_T_END], eex,
                                        thr)
                if n > toli[TI_ACC_MAX]:
                    _set_err(err, t, i, -1 - p, st[i, X], st[i, Y],
                             -vn / c_f[c, CF_VCMN], n, 0.0)
                    return ERR_FAR_ACCUMULATION
            continue
        if wedge is not None and bint[i, B_KIND] == SH_DISK:
            rc = _disk_groove(pivot, i, p, t, st, bint, bflt, verts, planes, grav,
                              law_par, bp_law, pm, tz, zp, ttr, tolf, w, ev_t, ev_i, ev_f,
                              cnt, err)
            if rc < 0:
                return rc
            if rc == 1:
                return 1
        tz[i] = t + accumulation_time(nx * st[i, VX] + ny * st[i, VY], c_f[c, CF_VCMN], gn)
        zp[i] = p
        return 1
    return 0


@njit(cache=True, _nrt=False, inline="always")
def _holding(pivot, wedge, shapes, i, nc, t, st, bint, bflt, verts, planes, grav, law_par,
             bp_law, pm, sched, tolf, c_i, c_f, w, ev, cnt, err, pairs, cid):
    """Body i in flight whose impacts did not schedule an accumulation point: impacts
    accumulating at one point, a polygon (or rod) vertex, or an ellipse's boundary, on a
    plane, are held there (integrated pivot contact, ``_pivot_enter``); the most strongly
    pushed one if several; at points on two planes: held on both (``_hold_two``). A disk's
    (or a pair's) accumulating point is ``ERR_CHATTER``. Returns 0 or an error code.
    ``sched``, ``ev``: as ``_persisting``."""
    ev_t, ev_i, ev_f = ev
    tz, zp, ttr = sched
    q = cid[CL_PEND]
    if q >= 0 and (pairs[q, 0] == i or pairs[q, 1] == i):
        return 0    # it enters persistent contact with its pair (a cluster, run_loop)
    hold = -1
    amin = 0.0
    for c in range(nc):
        if c_i[c, CI_A] != i and not (c_i[c, CI_TYPE] == 1 and c_i[c, CI_B] == i):
            continue
        if c_i[c, CI_OFF] != 0:
            continue
        if c_i[c, CI_TYPE] == 1 and not (bint[c_i[c, CI_A], B_KIND] == SH_DISK
                                         and bint[c_i[c, CI_B], B_KIND] == SH_DISK):
            continue    # not two disks: checked by its next search (_pair_persists)
        vN, vT = _contact_velocity(st, c_i, c_f, c)
        acc = _gap_accel(st, bint, bflt, c_i, c_f, c, verts, grav, shapes)
        if c_i[c, CI_TYPE] == 0:
            # a plane contact's gap acceleration at its round-off is zero: not pushed
            # into the plane, not held (decisions.touching_accel)
            acc = touching_accel(acc, math.hypot(st[i, AX], st[i, AY]), st[i, OMEGA],
                                 _reach(i, bint, bflt, c_f, c))
        if acc < 0.0 and vN * vN < _vz2(tolf, -acc):
            if c_i[c, CI_TYPE] != 0 and cid[CL_PEND] < 0:
                # two disks whose impacts accumulate: persistent contact (a cluster of
                # them, their planes and the disks touching them, entered at the next
                # pass of run_loop)
                cid[CL_PEND] = -2 - c_i[c, CI_FEAT]
                return 0
            if c_i[c, CI_TYPE] != 0:
                _set_err(err, t, c_i[c, CI_A], _bcode(c_i, c), c_f[c, CF_PX],
                         c_f[c, CF_PY], vN, acc, 0.0)
                return ERR_CHATTER
            if acc < amin:
                amin = acc
                hold = c
    # ... and a contact on a second plane, as slow on the scale of the first (its free gap
    # need not accelerate into its plane: a ladder's top is pushed into the wall by the
    # floor): held on both when that is consistent (_two_enter)
    if (hold >= 0 and wedge is not None
            and _hold_two(pivot, i, hold, amin, nc, t, st, bint, bflt, verts, planes, grav,
                          law_par, bp_law, pm, tz, zp, ttr, tolf, c_i, c_f, w, ev_t, ev_i,
                          ev_f, cnt)):
        return 0    # its first pass (at t) records its motion
    if hold >= 0 and bint[i, B_KIND] == SH_DISK:
        c = hold
        vN, vT = _contact_velocity(st, c_i, c_f, c)
        _set_err(err, t, i, _bcode(c_i, c), c_f[c, CF_PX], c_f[c, CF_PY], vN, amin, 0.0)
        return ERR_CHATTER
    if hold >= 0:
        c = hold
        if pivot is not None:
            rc = _pivot_enter(i, c_i[c, CI_B], c_i[c, CI_FEAT] - bint[i, B_FIRST], t, st,
                              bint, bflt, verts, planes, grav, law_par, bp_law, pm, tz, zp,
                              ttr, tolf, w, ev_t, ev_i, ev_f, cnt, err)
        else:
            rc = _not_compiled(err, t, i, FEATURE_PIVOT)
        if rc == 1:
            vN, vT = _contact_velocity(st, c_i, c_f, c)
            _set_err(err, t, i, _bcode(c_i, c), c_f[c, CF_PX], c_f[c, CF_PY], vN, amin,
                     0.0)
            return ERR_CHATTER
        if rc < 0:
            return rc
    return 0


@njit(cache=True, _nrt=False, inline="always")
def _log_instant(t, st, tref, bint, planes, pm, tz, zp, bmark, seg, cnt, tmp, err):
    """The segments of the bodies marked at this instant, from t (a body held for a pending
    accumulation jump: its held motion; a body in pivot contact records its own motion in
    its first pass). Returns 0 or ``ERR_NONFINITE``. ``seg`` = (seg_t, seg_b, seg_s)."""
    seg_t, seg_b, seg_s = seg
    for i in range(st.shape[0]):
        if bmark[i] == 0:
            continue
        if not _finite(st, i):
            _set_err(err, t, i, 0, st[i, X], st[i, Y], 0.0, 0.0, 0.0)
            return ERR_NONFINITE
        if pm[i, M_MODE] == PM_PIVOT:
            continue    # its first pass (at t) records its motion
        if tz[i] < INF:
            # accumulation jump pending: the trajectory holds the body on the plane
            _held_into(st[i], bint[i, B_KIND], planes[zp[i], 0], planes[zp[i], 1], tmp[0])
            _push_row(seg_t, seg_b, seg_s, cnt, tmp[0], tref[i], i)
        else:
            _push_seg(seg_t, seg_b, seg_s, cnt, st, tref, i)
    return 0


# ------------------------------------------------------------------ persistent body-body contact


# Persistent contact between bodies (issue 16 item 2, PM_CLUSTER): when the impacts of a
# pair of disks accumulate (decisions.pair_persistence: PP_CHATTER), the bodies touching
# them (through disk-disk contacts within gap_tol) and their planes (within gap_tol) form
# a *cluster* integrated by ``kernels/cluster2d.py``: one cluster at a time, stored in
# ``cbod`` (its body rows), ``ccon`` (KMAX active contact rows, then NCAND candidates),
# ``cw`` (cluster2d's la, then its w) and ``cid`` (header CL_*, the stepper index of each
# cluster row, then the stepper source of each contact row: a plane p >= 0, or -2 - q for
# pair q). Its leader (the first member) carries the next pass time in ttr; every member
# is PM_CLUSTER (its plane and pair searches are off; a pair with a body outside a moving
# cluster is refused, PP_HELD). Events: a contact leaving (CE_LEAVE: it becomes a
# candidate; when no body-body contact is left the cluster dissolves, each member settling
# on its plane contact or flying), stick/slip (CE_SLIP, CE_STOP: cluster_after_event), a
# candidate gap closing (CE_GAP: the cluster dissolves into flight at that instant, its
# contacts in the instant's impact cluster with the closing one; the persistence rule then
# re-enters it), rest (CS_REST: frozen, velocities zero, until a body outside hits it:
# then it dissolves into the instant as at CE_GAP).


def cluster_sizes(nb):
    """``(cbod shape, ccon shape, cw size, cid size)`` of a scene of nb bodies (cw: la, w,
    then five spare slots; from the end: the time of the last mode event, of the last
    gathering at a feature switch, of the last entry, the count of entries closer than
    ``CL_CHAT_RTOL sqrt(L / |g|)`` to the one before, and the time by which the pass must
    end for a pair with a body outside, ``_held_cluster_pair``)."""
    return ((nb, cl.N_CB), (cl.KMAX + NCAND, cl.N_CC),
            cl.N_LA + int(cl.work_size(nb, NCAND)) + 5, CL_HDR + nb + cl.KMAX + NCAND)


@_inner
def _cl_speed(bod):
    v = 0.0
    for r in range(bod.shape[0]):
        v = max(v, math.hypot(bod[r, 3], bod[r, 4]))
    return v


@_inner
def _cl_time(L, gx, gy, bod):
    """The cluster's time scale T (s): ``sqrt(L / |g|)``, or ``L / V`` in zero gravity (V
    the fastest member's speed)."""
    gl = math.hypot(gx, gy)
    return math.sqrt(L / gl) if gl > 0.0 else L / max(_cl_speed(bod), 1e-300)


@_inner
def _cl_close(t, last, count, T):
    """The count of consecutive occurrences of a cluster event closer than
    ``CL_CHAT_RTOL T`` to the one before (at ``last``), with one more at t."""
    if count > 0 and t - last <= CL_CHAT_RTOL * T:
        return count + 1
    return 1


@_inner
def _cl_scale(cid, bint, bflt, verts):
    """The cluster's length scale L (m): the sum of its members' diameters (twice the core
    reach plus the radius, ``pair2d_shape.body_reach``; a disk's diameter)."""
    L = 0.0
    for r in range(cid[CL_N]):
        L += 2.0 * _body_size(cid[CL_HDR + r], bint, bflt, verts)
    return L


@_inner
def _cl_row(cbod, ccon, cid, nb, k, kind, a, b, ra, rb, nx, ny, d, mu, src):
    """Fill contact row k of ccon (round features at the centres, unbounded cones)."""
    clr.row_clear(ccon, k, kind, a, b, mu)
    ccon[k, cl.CC_RA] = ra
    ccon[k, cl.CC_RB] = rb
    ccon[k, cl.CC_NX] = nx
    ccon[k, cl.CC_NY] = ny
    ccon[k, cl.CC_D] = d
    cid[CL_HDR + nb + k] = src


@_inner
def _cl_copy(ccon, cid, nb, dst, src):
    for j in range(cl.N_CC):
        ccon[dst, j] = ccon[src, j]
    cid[CL_HDR + nb + dst] = cid[CL_HDR + nb + src]


@_inner
def _cl_lift_parting(ccon, cid, cbod, nb, k0, nk, nc, vz, vr, err):
    """Move the active rows k0 .. nk - 1 (built at a cluster's entry) whose gap rate exceeds
    both ``vz`` (m/s, the zero speed of their bodies' rates, ``pair_zero_speed``) and ``vr``
    (m/s, ``_cluster_enter``'s parting speed of an accumulation) to the candidates: they
    part, and held, the entry's projection would stop them. Returns the new ``(nk, nc)``,
    or ``(-1, -1)`` when no candidate row is left."""
    cid[CL_NK] = nk
    cid[CL_NC] = nc
    k = k0
    while k < cid[CL_NK]:
        rate = clr.row_rate(ccon, k, cbod[int(ccon[k, cl.CC_A])], cbod[int(ccon[k, cl.CC_B])])
        if rate > vz and rate > vr:
            if _cl_lift(ccon, cid, nb, k, err) < 0:
                return -1, -1
        else:
            k += 1
    return cid[CL_NK], cid[CL_NC]


@_inner
def _cl_lift(ccon, cid, nb, k, err):
    """Move active contact k to the candidates. Returns 0 or -1 (no candidate row left)."""
    nk = cid[CL_NK]
    nc = cid[CL_NC]
    if nc >= NCAND:
        return -1
    _cl_copy(ccon, cid, nb, cl.KMAX + nc, k)
    cid[CL_NC] = nc + 1
    if k != nk - 1:
        _cl_copy(ccon, cid, nb, k, nk - 1)
    cid[CL_NK] = nk - 1
    return 0


@_inner
def _cl_pairs_left(ccon, cid):
    """Active body-body contacts of the cluster."""
    c = 0
    for k in range(cid[CL_NK]):
        if ccon[k, cl.CC_KIND] != cl.KIND_PLANE:
            c += 1
    return c


@_inner
def _cl_refuse(err, t, a, b, st, why, x1, x2):
    _set_err(err, t, a, b, st[a, X], st[a, Y], why, x1, x2)
    return ERR_PERSISTENT_PAIR


@_inner
def _cl_energy(st, bflt, grav, cid):
    e = 0.0
    for r in range(cid[CL_N]):
        e += _energy(st, bflt, grav, cid[CL_HDR + r])
    return e


@_inner
def _cl_gap(shapes, i, si, j, sj, bint, bflt, verts):
    """Gap (m) of bodies i and j at the state rows si, sj and the unit normal from j into
    i: closed form for two disks, ``pair2d.frame_rel`` otherwise (``shapes``: the shape
    switch, None for disks only)."""
    if bint[i, B_KIND] == SH_DISK and bint[j, B_KIND] == SH_DISK:
        dx = si[X] - sj[X]
        dy = si[Y] - sj[Y]
        dist = math.hypot(dx, dy)
        return dist - bflt[i, B_RADIUS] - bflt[j, B_RADIUS], dx / dist, dy / dist
    if shapes is None:
        return INF, 0.0, 0.0
    g, nx, ny, pax, pay, pbx, pby, fa, ia, fb, ib = _frame(i, si[ANGLE], j, sj[X] - si[X],
                                                           sj[Y] - si[Y], sj[ANGLE], bint,
                                                           bflt, verts)
    return g, nx, ny


@_inner
def _cl_gap_rate(shapes, i, si, j, sj, bint, bflt, verts, nx, ny):
    """Rate (m/s) of the gap of ``_cl_gap`` (normal ``(nx, ny)`` from j into i, as it
    returned): ``n . (v_i(p_i) - v_j(p_j))`` at the witness points of ``pair2d.frame_rel``
    (the centres' line for two disks). Negative: they close."""
    if (bint[i, B_KIND] == SH_DISK and bint[j, B_KIND] == SH_DISK) or shapes is None:
        return nx * (si[VX] - sj[VX]) + ny * (si[VY] - sj[VY])
    dx = sj[X] - si[X]
    dy = sj[Y] - si[Y]
    g, nx, ny, pax, pay, pbx, pby, fa, ia, fb, ib = _frame(i, si[ANGLE], j, dx, dy,
                                                           sj[ANGLE], bint, bflt, verts)
    return point_rate(nx, ny, pax, pay, pbx - dx, pby - dy, si[VX], si[VY], si[OMEGA],
                      sj[VX], sj[VY], sj[OMEGA])


@_inner
def _cl_point(shapes, a, b, st, bint, bflt, verts):
    """The logged contact point (world, m) and normal (from b into a) of bodies a, b
    entering a cluster: on b's boundary along the centres' line for two disks, the middle
    of the witness points of ``pair2d.frame_rel`` otherwise."""
    if (bint[a, B_KIND] == SH_DISK and bint[b, B_KIND] == SH_DISK) or shapes is None:
        dx = st[a, X] - st[b, X]
        dy = st[a, Y] - st[b, Y]
        dist = math.hypot(dx, dy)
        nx = dx / dist
        ny = dy / dist
        rb_ = bflt[b, B_RADIUS]
        return st[b, X] + rb_ * nx, st[b, Y] + rb_ * ny, nx, ny
    g, nx, ny, pax, pay, pbx, pby, fa, ia, fb, ib = _frame(a, st[a, ANGLE], b,
                                                           st[b, X] - st[a, X],
                                                           st[b, Y] - st[a, Y], st[b, ANGLE],
                                                           bint, bflt, verts)
    return st[a, X] + 0.5 * (pax + pbx), st[a, Y] + 0.5 * (pay + pby), nx, ny


@_inner
def _cluster_enter(shapes, t, st, tref, bint, bflt, verts, planes, grav, law_par, bp_law, bp_off, pairs,
                   pr_off, pr_t, bp_t, pm, tz, zp, ttr, tolf, cbod, ccon, cw, cid, bmark, tmp,
                   ev_t, ev_i, ev_f, seg_t, seg_b, seg_s, cnt, err):
    """Enter persistent contact for pair ``cid[CL_PEND]`` (its impacts accumulate at t):
    gather the cluster, project it onto g = dg/dt = 0, select the modes
    (``cluster2d.cluster_select_modes``) and schedule its first pass at t. Returns 0 (a
    cluster, or none when every body-body contact lifts: the members fly or settle) or an
    error code (a named refusal, ``ERR_PERSISTENT_PAIR``)."""
    nb = st.shape[0]
    q = cid[CL_PEND]
    cid[CL_PEND] = -1
    a = pairs[q, 0]
    b = pairs[q, 1]
    if cid[CL_N] > 0:
        # a cluster in motion whose members' states are at t (its pass ended here: a body
        # outside became held, _held_cluster_pair, or an event outside capped it): entered
        # again at t, its members and the pair's bodies one system (two moving clusters
        # would need a bound between two integrations: not built)
        again = cid[CL_FROZEN] == 0 and cid[CL_EV] == cl.CE_NONE
        for r in range(cid[CL_N]):
            again = again and tref[cid[CL_HDR + r]] == t
        if not again:
            return _cl_refuse(err, t, a, b, st, PP_TWO, float(cid[CL_LEAD]), 0.0)
        cid[CL_N] = 0           # its members are gathered again below (PM_CLUSTER)
    cw[cw.shape[0] - 5] = INF       # no check time yet (_held_cluster_pair)
    gtol = tolf[TF_GAP_TOL]
    # members: the connected bodies through contacts within gap_tol at t
    cid[CL_HDR] = a
    cid[CL_HDR + 1] = b
    n = 2
    head = 0
    while head < n:
        i = cid[CL_HDR + head]
        head += 1
        if shapes is None and bint[i, B_KIND] != SH_DISK:
            return _cl_refuse(err, t, a, b, st, PP_SHAPES, float(i), 0.0)
        if not _can_join(i, t, pm, tref):
            return _cl_refuse(err, t, a, b, st, PP_TWO, float(i), 0.0)
        # bring it to t (a pending accumulation jump is cancelled: its held motion)
        if tz[i] < INF:
            _held_into(st[i], bint[i, B_KIND], planes[zp[i], 0], planes[zp[i], 1], st[i])
            tz[i] = INF
            fly_row(st, i, t - tref[i])
            st[i, AX] = grav[0]
            st[i, AY] = grav[1]
        else:
            fly_row(st, i, t - tref[i])
        tref[i] = t
        for q2 in range(pairs.shape[0]):
            if pr_off[q2] == PR_OFF:
                continue
            j = -1
            if pairs[q2, 0] == i:
                j = pairs[q2, 1]
            elif pairs[q2, 1] == i:
                j = pairs[q2, 0]
            if j < 0:
                continue
            known = False
            for r in range(n):
                if cid[CL_HDR + r] == j:
                    known = True
            if known or not _can_join(j, t, pm, tref):
                continue
            if shapes is None and bint[j, B_KIND] != SH_DISK:
                continue
            if tz[j] < INF:
                _held_into(st[j], bint[j, B_KIND], planes[zp[j], 0], planes[zp[j], 1], tmp[0])
                fly_into(tmp[0], t - tref[j], tmp[0])
            else:
                fly_into(st[j], t - tref[j], tmp[0])
            g, _, _ = _cl_gap(shapes, i, st[i], j, tmp[0], bint, bflt, verts)
            if g <= gtol or pm[j, M_MODE] == PM_PIVOT or pm[j, M_MODE] == PM_CLUSTER:
                # touching; or held by a pivot contact at t (its plane row holds it in
                # the cluster; apart from the members, the pair is bounded by the
                # cluster's passes, _member_pair: two integrated motions, one system); or
                # a member of the cluster entered again
                if n >= nb:
                    break
                cid[CL_HDR + n] = j
                n += 1
    cid[CL_N] = n
    ids = cid[CL_HDR:CL_HDR + n]
    for i in range(nb):
        if pm[i, M_MODE] == PM_CLUSTER and _cl_row_of(cid, i) < 0:
            # a member of the cluster entered again that the gather did not reach
            cid[CL_N] = 0
            return _cl_refuse(err, t, a, b, st, PP_TWO, float(i), 0.0)
    held = 0            # members held by a pivot contact (no bound between two of them)
    for r in range(n):
        if pm[ids[r], M_MODE] == PM_PIVOT:
            held += 1
    for r in range(n):
        i = ids[r]
        for j in range(6):
            cbod[r, j] = st[i, j]
        cbod[r, cl.CB_M] = bflt[i, B_MASS]
        cbod[r, cl.CB_I] = bflt[i, B_INERTIA]
        cbod[r, cl.CB_FIXED] = 0.0
    # entries closer than CL_CHAT_RTOL T apart (T = sqrt(L / |g|)): from the
    # CL_REENTRY_HOLD-th, every touching contact of the entering pair is held (the limit of
    # impacts or landings that accumulate: a rod rocking to rest on a face)
    te = cw.shape[0] - 3
    L = _cl_scale(cid, bint, bflt, verts)
    entries = _cl_close(t, cw[te], int(cw[te - 1]), _cl_time(L, grav[0], grav[1], cbod[:n]))
    hold = entries >= CL_REENTRY_HOLD
    # ... and at an entry that follows an earlier one, a touching contact parting slower than
    # vr (m/s) is held too: slower than the accumulation speed and rising less than
    # rest_length since that entry (v dt / 4: a rise under uniform acceleration, dt the time
    # since it), the limit of impacts that accumulate there (a corner bouncing at e > 0
    # under a rocking box came back every 3.2e-7 s at 1.5e-6 m/s, just outside the time
    # rule, and the run never ended)
    vr = 0.0
    if cw[te - 1] >= 1.0:
        vr = min(math.sqrt(_vz2(tolf, math.hypot(grav[0], grav[1]))),
                 4.0 * tolf[TF_REST_LENGTH] / max(t - cw[te], 1e-300))
    # contacts (active within gap_tol) and candidates
    nk = 0
    nc = 0
    for q2 in range(pairs.shape[0]):
        if pr_off[q2] == PR_OFF:
            continue
        ra = -1
        rb = -1
        for r in range(n):
            if ids[r] == pairs[q2, 0]:
                ra = r
            if ids[r] == pairs[q2, 1]:
                rb = r
        if ra < 0 or rb < 0:
            continue
        i = pairs[q2, 0]
        j = pairs[q2, 1]
        mu = law_par[pairs[q2, 2], P_MU]
        disks = bint[i, B_KIND] == SH_DISK and bint[j, B_KIND] == SH_DISK
        if disks:
            g = (math.hypot(st[i, X] - st[j, X], st[i, Y] - st[j, Y]) - bflt[i, B_RADIUS]
                 - bflt[j, B_RADIUS])
            if g <= gtol:
                if nk >= cl.KMAX:
                    cid[CL_N] = 0
                    return _cl_refuse(err, t, a, b, st, PP_CLUSTER,
                                      float(cl.CS_TOO_MANY_CONTACTS), 0.0)
                _cl_row(cbod, ccon, cid, nb, nk, cl.KIND_ROUND, ra, rb, bflt[i, B_RADIUS],
                        bflt[j, B_RADIUS], 0.0, 0.0, 0.0, mu, -2 - q2)
                nk += 1
            else:
                if nc >= NCAND:
                    cid[CL_N] = 0
                    return _cl_refuse(err, t, a, b, st, PP_CLUSTER,
                                      float(cl.CS_TOO_MANY_CONTACTS), 1.0)
                _cl_row(cbod, ccon, cid, nb, cl.KMAX + nc, cl.KIND_ROUND, ra, rb,
                        bflt[i, B_RADIUS], bflt[j, B_RADIUS], 0.0, 0.0, 0.0, mu, -2 - q2)
                nc += 1
        elif shapes is not None:
            # rounded polygons: the rows of their features (cluster2d_rows.pair_rows); a
            # pair not touching has no candidate row (its features are not known in
            # advance): _cl_check_gaps checks it after every pass
            g, nx, ny = _cl_gap(shapes, i, st[i], j, st[j], bint, bflt, verts)
            if g > gtol:
                continue
            if nk + 2 > cl.KMAX or nc + 2 > NCAND:
                cid[CL_N] = 0
                return _cl_refuse(err, t, a, b, st, PP_CLUSTER,
                                  float(cl.CS_TOO_MANY_CONTACTS), 0.0)
            if bint[i, B_KIND] == SH_ELLIPSE or bint[j, B_KIND] == SH_ELLIPSE:
                # an ellipse is the row's A (cluster2d_rows.ellipse_rows)
                e_, o_, re_, ro_, sg = i, j, ra, rb, 1.0
                if bint[i, B_KIND] != SH_ELLIPSE:
                    e_, o_, re_, ro_, sg = j, i, rb, ra, -1.0
                ka, kc = clr.ellipse_rows(bflt[e_, B_EA], bflt[e_, B_EB], re_, verts,
                                          bint[o_, B_FIRST], bint[o_, B_COUNT],
                                          bflt[o_, B_RADIUS], bflt[o_, B_EA], bflt[o_, B_EB],
                                          st[o_], ro_, sg * nx, sg * ny, gtol, mu,
                                          ccon[nk:])
            else:
                ka, kc = clr.pair_rows(verts, bint[i, B_FIRST], bint[i, B_COUNT],
                                       bflt[i, B_RADIUS], st[i], ra, bint[j, B_FIRST],
                                       bint[j, B_COUNT], bflt[j, B_RADIUS], st[j], rb, nx, ny,
                                       gtol, mu, ccon[nk:], ccon[cl.KMAX + nc:])
            if ka < 0:
                cid[CL_N] = 0
                return _cl_refuse(err, t, i, j, st, PP_CORNER, float(ka), 0.0)
            for k in range(ka):
                cid[CL_HDR + nb + nk + k] = -2 - q2
            for k in range(kc):
                cid[CL_HDR + nb + cl.KMAX + nc + k] = -2 - q2
            nk += ka
            nc += kc
            # a contact of the pair separating faster than the zero speed and than vr
            # (the far end of a face on a face turning away) is a candidate, not held; but
            # when the pair enters again right after its last entry (hold), its touching
            # contacts are held: the accumulation's limit (as candidates, they would
            # bounce and enter again, PP_REENTRY)
            if q2 == q and hold:
                continue
            sp = (math.hypot(st[i, VX], st[i, VY]) + math.hypot(st[j, VX], st[j, VY])
                  + abs(st[i, OMEGA]) * _body_size(i, bint, bflt, verts)
                  + abs(st[j, OMEGA]) * _body_size(j, bint, bflt, verts))
            nk, nc = _cl_lift_parting(ccon, cid, cbod, nb, nk - ka, nk, nc,
                                      pair_zero_speed(sp, tolf[TF_SIMUL_TOL] * sp), vr, err)
            if nk < 0:
                cid[CL_N] = 0
                return _cl_refuse(err, t, a, b, st, PP_CLUSTER,
                                  float(cl.CS_TOO_MANY_CONTACTS), 1.0)
    for r in range(n):
        i = ids[r]
        nk0 = nk
        for p in range(planes.shape[0]):
            if bp_off[i, p] != 0:
                continue
            nx = planes[p, 0]
            ny = planes[p, 1]
            mu = law_par[bp_law[i, p], P_MU]
            if bint[i, B_KIND] != SH_DISK:
                if bint[i, B_KIND] == SH_ELLIPSE:
                    ka, kc = clr.ellipse_plane_rows(bflt[i, B_EA], bflt[i, B_EB], st[i], r, nx,
                                                    ny, planes[p, 2], gtol, mu, ccon[nk:],
                                                    cl.KMAX - nk, ccon[cl.KMAX + nc:],
                                                    NCAND - nc)
                else:
                    ka, kc = clr.plane_rows(verts, bint[i, B_FIRST], bint[i, B_COUNT],
                                            bflt[i, B_RADIUS], st[i], r, nx, ny, planes[p, 2],
                                            gtol, mu, ccon[nk:], cl.KMAX - nk,
                                            ccon[cl.KMAX + nc:], NCAND - nc)
                if ka < 0:
                    cid[CL_N] = 0
                    return _cl_refuse(err, t, a, b, st, PP_CLUSTER,
                                      float(cl.CS_TOO_MANY_CONTACTS), 0.0)
                for k in range(ka):
                    cid[CL_HDR + nb + nk + k] = p
                for k in range(kc):
                    cid[CL_HDR + nb + cl.KMAX + nc + k] = p
                nk += ka
                nc += kc
                continue
            g = nx * st[i, X] + ny * st[i, Y] - planes[p, 2] - bflt[i, B_RADIUS]
            if g <= gtol:
                if nk >= cl.KMAX:
                    cid[CL_N] = 0
                    return _cl_refuse(err, t, a, b, st, PP_CLUSTER, float(cl.CS_TOO_MANY_CONTACTS), 0.0)
                _cl_row(cbod, ccon, cid, nb, nk, cl.KIND_PLANE, r, -1, bflt[i, B_RADIUS], 0.0,
                        nx, ny, planes[p, 2], mu, p)
                nk += 1
            else:
                if nc >= NCAND:
                    cid[CL_N] = 0
                    return _cl_refuse(err, t, a, b, st, PP_CLUSTER, float(cl.CS_TOO_MANY_CONTACTS), 1.0)
                _cl_row(cbod, ccon, cid, nb, cl.KMAX + nc, cl.KIND_PLANE, r, -1,
                        bflt[i, B_RADIUS], 0.0, nx, ny, planes[p, 2], mu, p)
                nc += 1
        if not hold and nk > nk0:
            # a feature on a plane parting faster than the zero speed and than vr (a domino
            # struck at this instant turning on its far corner) is a candidate, as a pair's
            # contact is: held, the projection below would stop it
            nk, nc = _cl_lift_parting(ccon, cid, cbod, nb, nk0, nk, nc,
                                      _body_zero_speed(i, st[i], bint, bflt, verts, tolf), vr,
                                      err)
            if nk < 0:
                cid[CL_N] = 0
                return _cl_refuse(err, t, a, b, st, PP_CLUSTER,
                                  float(cl.CS_TOO_MANY_CONTACTS), 1.0)
    cid[CL_NK] = nk
    cid[CL_NC] = nc
    e0 = _cl_energy(st, bflt, grav, cid)
    # entries closer than CL_CHAT_RTOL T apart: the contact ends and starts again with no
    # lasting mode; the CL_CHAT_MAX-th is refused (PP_REENTRY)
    cw[te - 1] = entries
    cw[te] = t
    if cw[te - 1] >= CL_CHAT_MAX:
        cid[CL_N] = 0
        return _cl_refuse(err, t, a, b, st, PP_REENTRY, cw[te - 1], 0.0)
    la = cw[:cl.N_LA]
    w = cw[cl.N_LA:]
    bod = cbod[:n]
    con = ccon[:cl.KMAX]
    cs = cl.cluster_project(bod, con, nk, grav[0], grav[1], L, w, la)
    if cs == cl.CS_OK:
        cs = cl.cluster_select_modes(bod, con, nk, grav[0], grav[1], L, w, la)
    if cs != cl.CS_OK:
        cid[CL_N] = 0
        return _cl_refuse(err, t, a, b, st, PP_NO_MODE if cs == cl.CS_NO_MODE else PP_CLUSTER,
                          float(cs), 0.0)
    k = 0
    while k < cid[CL_NK]:
        if ccon[k, cl.CC_MODE] == cl.MODE_LIFT:
            src = cid[CL_HDR + nb + k]
            if src < 0:
                pr_off[-2 - src] = PR_REL
            if _cl_lift(ccon, cid, nb, k, err) < 0:
                cid[CL_N] = 0
                return _cl_refuse(err, t, a, b, st, PP_CLUSTER, float(cl.CS_TOO_MANY_CONTACTS), 1.0)
        else:
            k += 1
    for r in range(n):
        i = ids[r]
        for j in range(6):
            st[i, j] = cbod[r, j]
        st[i, AX] = 0.0
        st[i, AY] = 0.0
        st[i, ALPHA] = 0.0
        pm[i, M_MODE] = PM_CLUSTER
        tz[i] = INF
        ttr[i] = INF
        for p in range(planes.shape[0]):
            bp_t[i, p] = INF
    for q2 in range(pairs.shape[0]):
        if pm[pairs[q2, 0], M_MODE] == PM_CLUSTER and pm[pairs[q2, 1], M_MODE] == PM_CLUSTER:
            pr_t[q2] = INF
            if pr_off[q2] == PR_HIT or pr_off[q2] == PR_WAIT:
                pr_off[q2] = PR_ON
    cid[CL_LEAD] = ids[0]
    cid[CL_EV] = cl.CE_NONE
    cid[CL_FROZEN] = 0
    cid[CL_CHAT] = 0
    px, py, nx, ny = _cl_point(shapes, a, b, st, bint, bflt, verts)
    _log(ev_t, ev_i, ev_f, cnt, t, EV_CONTACT, a, b, PM_CLUSTER, n, px, py, nx, ny, 0.0,
         0.0, 0.0, 0.0, 0.0, 0.0, _cl_energy(st, bflt, grav, cid) - e0)
    if _cl_pairs_left(ccon, cid) == 0 and held < 2:
        # every body-body contact lifts at once: no cluster (but two bodies held by pivot
        # contacts stay one system: their pair has no bound on two separate integrations)
        return _cluster_dissolve(shapes, True, t, st, tref, bint, bflt, verts, planes,
                                 grav, law_par, bp_law, pm, tz, ttr, tolf, cbod, ccon, cid,
                                 bmark, ev_t, ev_i, ev_f, seg_t, seg_b, seg_s, cnt, err)
    ttr[ids[0]] = t
    for r in range(n):
        bmark[ids[r]] = 1
    return 0


@_inner
def _can_join(i, t, pm, tref):
    """Body i can join a cluster entered at t: not wedged, and if held by a pivot contact,
    on one plane and with its state at t (its pass not yet run: the contact becomes the
    cluster's plane row)."""
    if pm[i, M_MODE] == PM_WEDGED:
        return False
    return not (pm[i, M_MODE] == PM_PIVOT and (pm[i, M_PLANE2] >= 0 or tref[i] != t))


@_inner
def _cl_member_flies(r, t, st, tref, grav, pm, tz, ttr, cbod, cid, bmark):
    """Member r takes its state from cbod and flies from t (marked). Returns its body."""
    i = cid[CL_HDR + r]
    for j in range(6):
        st[i, j] = cbod[r, j]
    st[i, AX] = grav[0]
    st[i, AY] = grav[1]
    st[i, ALPHA] = 0.0
    tref[i] = t
    pm[i, M_MODE] = PM_FLIGHT
    pm[i, M_AUX] = -1
    tz[i] = INF
    ttr[i] = INF
    bmark[i] = 1
    return i


@_inner
def _cl_members_fly(t, st, tref, grav, pm, tz, ttr, cbod, cid, bmark):
    """The cluster ends at t: every member takes its state from cbod and flies from t
    (marked); the cluster header is cleared. Returns the number of members."""
    n = cid[CL_N]
    for r in range(n):
        _cl_member_flies(r, t, st, tref, grav, pm, tz, ttr, cbod, cid, bmark)
    cid[CL_N] = 0
    cid[CL_LEAD] = -1
    cid[CL_EV] = cl.CE_NONE
    cid[CL_FROZEN] = 0
    return n


@_inner
def _cl_leave(r, t, st, tref, grav, pm, tz, ttr, cbod, ccon, cid, bmark, seg_t, seg_b, seg_s,
              cnt):
    """Member r of the cluster, with no active contact left (its last ones lifted at t),
    leaves it: it flies from its state at t (marked: its planes and pairs are searched
    again, its pairs with the members bounded as a body outside, ``_held_cluster_pair``);
    its candidate rows go, and the later members move down one row (the rows' member
    indices renumbered; a leader that leaves hands over to the first member)."""
    nb = st.shape[0]
    n = cid[CL_N]
    i = _cl_member_flies(r, t, st, tref, grav, pm, tz, ttr, cbod, cid, bmark)
    _push_seg(seg_t, seg_b, seg_s, cnt, st, tref, i)
    k = 0
    while k < cid[CL_NC]:
        row = cl.KMAX + k
        if int(ccon[row, cl.CC_A]) == r or int(ccon[row, cl.CC_B]) == r:
            last = cl.KMAX + cid[CL_NC] - 1
            if row != last:
                _cl_copy(ccon, cid, nb, row, last)
            cid[CL_NC] -= 1
        else:
            k += 1
    for rr in range(r, n - 1):
        cid[CL_HDR + rr] = cid[CL_HDR + rr + 1]
        for j in range(cbod.shape[1]):
            cbod[rr, j] = cbod[rr + 1, j]
    cid[CL_N] = n - 1
    for kk in range(cid[CL_NK] + cid[CL_NC]):
        row = kk if kk < cid[CL_NK] else cl.KMAX + kk - cid[CL_NK]
        if ccon[row, cl.CC_A] > r:
            ccon[row, cl.CC_A] -= 1.0
        if ccon[row, cl.CC_B] > r:
            ccon[row, cl.CC_B] -= 1.0
    if cid[CL_LEAD] == i:
        cid[CL_LEAD] = cid[CL_HDR]


@_inner
def _cluster_dissolve(shapes, settle, t, st, tref, bint, bflt, verts, planes, grav, law_par,
                      bp_law, pm, tz, ttr, tolf, cbod, ccon, cid, bmark, ev_t, ev_i, ev_f,
                      seg_t, seg_b, seg_s, cnt, err):
    """End the cluster at t (states in cbod): every member flies from t, or (``settle``)
    settles on a plane it still touches through an active contact (``_settle``: rest, roll
    or slide on it). Records their segments. Returns 0 or an error code."""
    n = _cl_members_fly(t, st, tref, grav, pm, tz, ttr, cbod, cid, bmark)
    nb = st.shape[0]
    for r in range(n):
        i = cid[CL_HDR + r]
        if settle:
            for k in range(cid[CL_NK]):
                if (ccon[k, cl.CC_KIND] == cl.KIND_PLANE and int(ccon[k, cl.CC_A]) == r
                        and pm[i, M_MODE] == PM_FLIGHT):
                    p = cid[CL_HDR + nb + k]
                    if bint[i, B_KIND] != SH_DISK:
                        # a polygon or rod settles on a face held at two points; on one
                        # point it flies (the plane's search finds the held contact)
                        m = 0
                        for k2 in range(cid[CL_NK]):
                            if (ccon[k2, cl.CC_KIND] == cl.KIND_PLANE
                                    and int(ccon[k2, cl.CC_A]) == r
                                    and cid[CL_HDR + nb + k2] == p):
                                m += 1
                        if m < 2:
                            continue
                    rc = _settle(shapes, i, p, t, st, bint, bflt, verts, planes, grav,
                                 law_par, bp_law, pm, ttr, tolf, ev_t, ev_i, ev_f, cnt, err)
                    if rc < 0:
                        return rc
                    if rc != 0:     # no rest there: it flies
                        pm[i, M_MODE] = PM_FLIGHT
                        st[i, AX] = grav[0]
                        st[i, AY] = grav[1]
                        st[i, ALPHA] = 0.0
                        ttr[i] = INF
        if not _finite(st, i):
            _set_err(err, t, i, 0, st[i, X], st[i, Y], 0.0, 0.0, 0.0)
            return ERR_NONFINITE
        _push_seg(seg_t, seg_b, seg_s, cnt, st, tref, i)
    return 0


@_inner
def _cluster_to_instant(t, extra, st, tref, grav, pm, tz, ttr, bp_t, pr_t, cbod, ccon, cid,
                        bmark):
    """The cluster dissolves into flight at t for an impact there: its active contacts
    (and candidate ``extra`` >= 0) are scheduled at t, so that the impact step resolves
    them in one cluster of the instant (the closing contact with the held ones at
    v_N = 0). Segments: logged by the impact step (every member is marked)."""
    _cl_members_fly(t, st, tref, grav, pm, tz, ttr, cbod, cid, bmark)
    nb = st.shape[0]
    for kk in range(cid[CL_NK] + 1):
        k = kk
        if kk == cid[CL_NK]:
            if extra < 0:
                break
            k = cl.KMAX + extra
        src = cid[CL_HDR + nb + k]
        if src >= 0:
            bp_t[cid[CL_HDR + int(ccon[k, cl.CC_A])], src] = t
        else:
            pr_t[-2 - src] = t


@_inner
def _cluster_pass(shapes, t, st, tref, bint, bflt, verts, planes, grav, law_par, bp_law, pm,
                  tz, ttr, bp_t, pairs, pr_t, pr_off, tolf, cbod, ccon, cw, cid, bmark, ev_t, ev_i, ev_f,
                  seg_t, seg_b, seg_s, cnt, err):
    """The cluster's event due at t (its leader's ttr), then its next integration pass
    (``cluster2d.cluster_advance``, recorded). Returns (rc, action): action 0 a pass ran,
    1 the cluster dissolved or froze (segments recorded, members marked), 2 an impact is
    pending at t (the impact step)."""
    nb = st.shape[0]
    n = cid[CL_N]
    lead = cid[CL_LEAD]
    ttr[lead] = INF
    ev = cid[CL_EV]
    idx = cid[CL_IDX]
    cid[CL_EV] = cl.CE_NONE
    L = _cl_scale(cid, bint, bflt, verts)
    la = cw[:cl.N_LA]
    w = cw[cl.N_LA:]
    bod = cbod[:n]
    con = ccon[:cl.KMAX]
    cand = ccon[cl.KMAX:]
    ids = cid[CL_HDR:CL_HDR + n]
    gx = grav[0]
    gy = grav[1]
    if ev == cl.CE_GAP:
        _cluster_to_instant(t, idx, st, tref, grav, pm, tz, ttr, bp_t, pr_t, cbod, ccon, cid,
                            bmark)
        return 0, 2
    modes = ev == cl.CE_LEAVE or ev == cl.CE_SLIP or ev == cl.CE_STOP
    a = -2
    b = -2
    if ev == cl.CE_FEATURE:
        # a contact point leaves its feature (a vertex's normal cone, a face's end): its row
        # moves to the next feature (cluster2d_rows.switch_row) and the modes are chosen
        # again; a face landing is an impact instant; else the cluster dissolves and is
        # gathered again at t from the geometry there, as at an entry (a second switch at
        # the same instant: refused)
        k = idx // 4
        ra_ = int(ccon[k, cl.CC_A])
        rb_ = int(ccon[k, cl.CC_B])
        ia = ids[ra_]
        ib = ids[rb_] if rb_ >= 0 else ia
        sw = clr.PR_GEOMETRY
        if shapes is not None:
            sw = clr.switch_row(verts, ccon, k, idx % 4, bint[ia, B_FIRST], bint[ia, B_COUNT],
                                bflt[ia, B_RADIUS], cbod[ra_], bint[ib, B_FIRST],
                                bint[ib, B_COUNT], bflt[ib, B_RADIUS],
                                cbod[rb_ if rb_ >= 0 else ra_])
        if sw == clr.SW_LANDING:
            _cluster_to_instant(t, -1, st, tref, grav, pm, tz, ttr, bp_t, pr_t, cbod, ccon,
                                cid, bmark)
            return 0, 2
        if sw == clr.SW_SWITCHED:
            cs = cl.cluster_project(bod, con, cid[CL_NK], gx, gy, L, w, la)
            if cs == cl.CS_OK:
                cs = cl.cluster_select_modes(bod, con, cid[CL_NK], gx, gy, L, w, la)
            if cs != cl.CS_OK:
                return _cl_refuse(err, t, ia, ib, st,
                                  PP_NO_MODE if cs == cl.CS_NO_MODE else PP_CLUSTER,
                                  float(cs), 0.0), 0
            modes = True
        else:
            q = -1
            src = cid[CL_HDR + nb + k]
            if src < 0:
                q = -2 - src
            else:
                for kk in range(cid[CL_NK]):
                    if cid[CL_HDR + nb + kk] < 0:
                        q = -2 - cid[CL_HDR + nb + kk]
                        break
            # gatherings closer than CL_CHAT_RTOL T apart (T = sqrt(L / |g|)) that find the
            # same features again: the third is refused
            ts_ = cw.shape[0] - 2
            cid[CL_SWITCH] = _cl_close(t, cw[ts_], cid[CL_SWITCH], _cl_time(L, gx, gy, bod))
            cw[ts_] = t
            if q < 0 or cid[CL_SWITCH] >= 3:
                return _cl_refuse(err, t, lead, lead, st, PP_FEATURE, float(idx), 0.0), 0
            rc = _cluster_dissolve(shapes, False, t, st, tref, bint, bflt, verts, planes, grav,
                                   law_par, bp_law, pm, tz, ttr, tolf, cbod, ccon, cid, bmark,
                                   ev_t, ev_i, ev_f, seg_t, seg_b, seg_s, cnt, err)
            if rc < 0:
                return rc, 0
            cid[CL_PEND] = q
            return 0, 1
    if ev == cl.CE_LEAVE or ev == cl.CE_SLIP or ev == cl.CE_STOP:
        k = idx
        a = ids[int(ccon[k, cl.CC_A])]
        src = cid[CL_HDR + nb + k]
        b = -1 - src if src >= 0 else ids[int(ccon[k, cl.CC_B])]
        # stick-slip chatter: mode events of the cluster closer than CL_CHAT_RTOL T apart
        # (T = sqrt(L / |g|)); from the third, the modes of every contact are chosen again
        # (cluster_select_modes: the event's own trend rule can flip one contact back and
        # forth while another one's mode is what changed); CL_CHAT_MAX of them: refused
        ti = cw.shape[0] - 1
        cid[CL_CHAT] = _cl_close(t, cw[ti], cid[CL_CHAT], _cl_time(L, gx, gy, bod))
        cw[ti] = t
        if cid[CL_CHAT] >= CL_CHAT_MAX:
            return _cl_refuse(err, t, a, a, st, PP_STICK_SLIP, float(cid[CL_CHAT]), t), 0
        if cid[CL_CHAT] >= 3 and ev != cl.CE_LEAVE:
            cs = cl.cluster_select_modes(bod, con, cid[CL_NK], gx, gy, L, w, la)
        else:
            cs = cl.cluster_after_event(bod, con, cid[CL_NK], ev, k, gx, gy, L, w, la)
        if cs != cl.CS_OK:
            return _cl_refuse(err, t, a, b, st,
                              PP_NO_MODE if cs == cl.CS_NO_MODE else PP_CLUSTER,
                              float(cs), 0.0), 0
        mode = ccon[k, cl.CC_MODE]
        kind = EV_SLIDE
        if mode == cl.MODE_LIFT:
            kind = EV_RELEASE
        elif mode == cl.MODE_STICK:
            kind = EV_STICK
        _log(ev_t, ev_i, ev_f, cnt, t, kind, a, b, PM_CLUSTER, n, 0.0, 0.0, 0.0, 0.0, 0.0,
             0.0, 0.0, 0.0, ccon[k, cl.CC_LAMN], ccon[k, cl.CC_LAMT], 0.0)
    if modes:
        # every contact the new modes lift leaves (the event's own, or a neighbour whose
        # normal force the new modes would make pulling)
        lifted = False
        kk = 0
        while kk < cid[CL_NK]:
            if ccon[kk, cl.CC_MODE] != cl.MODE_LIFT:
                kk += 1
                continue
            lifted = True
            src = cid[CL_HDR + nb + kk]
            a2 = ids[int(ccon[kk, cl.CC_A])]
            b2 = -1 - src if src >= 0 else ids[int(ccon[kk, cl.CC_B])]
            if not (a2 == a and b2 == b):
                _log(ev_t, ev_i, ev_f, cnt, t, EV_RELEASE, a2, b2, PM_CLUSTER, n, 0.0, 0.0,
                     0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
            if src < 0:
                pr_off[-2 - src] = PR_REL
            if _cl_lift(ccon, cid, nb, kk, err) < 0:
                return _cl_refuse(err, t, a2, b2, st, PP_CLUSTER,
                                  float(cl.CS_TOO_MANY_CONTACTS), 1.0), 0
        if lifted:
            if _cl_pairs_left(ccon, cid) == 0:
                rc = _cluster_dissolve(shapes, True, t, st, tref, bint, bflt, verts, planes,
                                       grav, law_par, bp_law, pm, tz, ttr, tolf, cbod, ccon,
                                       cid, bmark, ev_t, ev_i, ev_f, seg_t, seg_b, seg_s, cnt,
                                       err)
                return rc, 1
            # a member with no active contact left flies: it leaves the cluster
            r = 0
            while r < cid[CL_N]:
                held = False
                for kk in range(cid[CL_NK]):
                    if int(ccon[kk, cl.CC_A]) == r or int(ccon[kk, cl.CC_B]) == r:
                        held = True
                if held:
                    r += 1
                    continue
                _cl_leave(r, t, st, tref, grav, pm, tz, ttr, cbod, ccon, cid, bmark, seg_t,
                          seg_b, seg_s, cnt)
            n = cid[CL_N]
            bod = cbod[:n]
            ids = cid[CL_HDR:CL_HDR + n]
            lead = cid[CL_LEAD]
    # the pass ends by the check time of the pairs with a body outside (_held_cluster_pair)
    tc = cw.shape[0] - 5
    cs, ev, idx, ts = cl.cluster_advance(bod, con, cid[CL_NK], cand, cid[CL_NC], gx, gy, L,
                                         t, min(tolf[TF_T_END], cw[tc]), w, la, seg_t, seg_b,
                                         seg_s, cnt, ids)
    if cs == cl.CS_REST:
        # frozen: nothing moves until a body outside hits it
        for r in range(n):
            i = ids[r]
            for j in range(3):
                st[i, j] = cbod[r, j]
            for j in range(3, 9):
                st[i, j] = 0.0
            for j in range(3, 6):
                cbod[r, j] = 0.0
            tref[i] = t
            bmark[i] = 1
            _push_seg(seg_t, seg_b, seg_s, cnt, st, tref, i)
        if cid[CL_FROZEN] == 0:
            i = ids[0]
            _log(ev_t, ev_i, ev_f, cnt, t, EV_REST, i, ids[1] if n > 1 else i, PM_CLUSTER, n,
                 st[i, X], st[i, Y], 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
        cid[CL_FROZEN] = 1
        return 0, 1
    if cs != cl.CS_OK:
        return _cl_refuse(err, t, lead, lead, st, PP_CLUSTER, float(cs), 0.0), 0
    for r in range(n):
        i = ids[r]
        for j in range(6):
            st[i, j] = cbod[r, j]
        if not _finite(st, i):
            _set_err(err, ts, i, 0, st[i, X], st[i, Y], 0.0, 0.0, 0.0)
            return ERR_NONFINITE, 0
        tref[i] = ts
    if shapes is not None:
        rc = _cl_check_gaps(shapes, ts, st, bint, bflt, verts, pairs, pr_off, tolf, cid,
                            err)
        if rc < 0:
            return rc, 0
    if ev == cl.CE_NONE and ts >= cw[tc]:
        # the check time: the pairs with a body outside are bounded again from here
        cw[tc] = INF
        for r in range(n):
            bmark[ids[r]] = 1
    cid[CL_EV] = ev
    cid[CL_IDX] = idx
    ttr[lead] = INF if (ev == cl.CE_NONE and ts >= tolf[TF_T_END]) else ts
    return 0, 0


@_inner
def _cl_row_of(cid, i):
    """The cluster row of body i (its index among the members), -1 if not a member."""
    for r in range(cid[CL_N]):
        if cid[CL_HDR + r] == i:
            return r
    return -1


@_inner
def _cl_watched(q, cid, nb, cands=True):
    """Pair q has a contact row in the cluster, or (``cands``) a candidate row (its gap is
    an event of the cluster's integration)."""
    for k in range(cid[CL_NK]):
        if cid[CL_HDR + nb + k] == -2 - q:
            return True
    if cands:
        for k in range(cid[CL_NC]):
            if cid[CL_HDR + nb + cl.KMAX + k] == -2 - q:
                return True
    return False


@_inner
def _cl_check_gaps(shapes, t, st, bint, bflt, verts, pairs, pr_off, tolf, cid, err):
    """After a pass (states at t): every pair of members other than two disks that has
    no contact row (apart at the entry, bounded by ``_member_pair``, or watched by the
    candidate rows of the features nearest when they came close) must not overlap by more
    than gap_tol; else ``ERR_PERSISTENT_PAIR`` with ``PP_UNWATCHED`` (its meeting inside
    the pass is not located, or the watched features were not the ones that met). Returns
    0 or it."""
    nb = st.shape[0]
    for q in range(pairs.shape[0]):
        if pr_off[q] == PR_OFF:
            continue
        a = pairs[q, 0]
        b = pairs[q, 1]
        if bint[a, B_KIND] == SH_DISK and bint[b, B_KIND] == SH_DISK:
            continue
        if (_cl_row_of(cid, a) < 0 or _cl_row_of(cid, b) < 0
                or _cl_watched(q, cid, nb, False)):
            continue
        g, _, _ = _cl_gap(shapes, a, st[a], b, st[b], bint, bflt, verts)
        if g < -tolf[TF_GAP_TOL]:
            return _cl_refuse(err, t, a, b, st, PP_UNWATCHED, g, 0.0)
    return 0


@_inner
def _cluster_hit(t, st, tref, grav, pairs, pm, tz, ttr, bp_t, pr_t, tolf, cbod, ccon, cid,
                 bmark):
    """A body outside the cluster meets a member within this instant (frozen: its search;
    moving: at the pass end where ``_held_cluster_pair`` found them touching and closing;
    cbod holds the members' states at t): the cluster dissolves into the instant
    (``_cluster_to_instant``). Returns 1 if it did."""
    tw = t + tolf[TF_SIMUL_TIME]
    for q in range(pairs.shape[0]):
        if pr_t[q] <= tw and (pm[pairs[q, 0], M_MODE] == PM_CLUSTER
                              or pm[pairs[q, 1], M_MODE] == PM_CLUSTER):
            _cluster_to_instant(t, -1, st, tref, grav, pm, tz, ttr, bp_t, pr_t, cbod, ccon,
                                cid, bmark)
            return 1
    return 0


PAIR_DISKS = "disks"   # the pair switch of a scene whose body pairs are all two disks
PAIR_ALL = "all"       # ... of a scene with a pair of other shapes (pair2d, pair2d_toi)


def scene_features(bint, planes, grav, n_pairs):
    """The feature switches ``(pivot, wedge, pair, joint, shapes)`` of a scene (True, or
    None when the scene cannot reach that mode; ``pair`` says which pair kinds: None,
    ``PAIR_DISKS`` when every body is a disk, else ``PAIR_ALL``; ``shapes`` None when every
    body is a disk: the persistent-contact and time-of-impact code of polygons and ellipses
    is not compiled), from its shape kinds (``bint[:, 0]``), its planes (float64[np, 3])
    and its number of body pairs. ``grav`` (m/s^2; the signature of
    ``stepper3d.scene_features``): no 2D mode depends on it."""
    kinds = {int(k) for k in bint[:, 0]}
    n_planes = len(planes)
    wedge = n_planes >= 2
    # a disk pivots only on two planes (it spins on both: _two_enter)
    pivot = SH_POLY in kinds or SH_ELLIPSE in kinds or (SH_DISK in kinds and wedge)
    pair = None
    if n_pairs > 0:
        pair = PAIR_DISKS if kinds == {SH_DISK} else PAIR_ALL
    # several vertices of a polygon, several planes or a pair can touch at one instant
    joint = SH_POLY in kinds or wedge or pair is not None
    shapes = not kinds <= {SH_DISK}
    return (True if pivot else None, True if wedge else None, pair,
            True if joint else None, True if shapes else None)


#: the feature switches of the general loop, every mode compiled (``loop_for``)
ALL_FEATURES = (True, True, PAIR_ALL, True, True)


def loop_for(law, pivot=True, wedge=True, pair=True, joint=True, shapes=True):
    """The event loop compiled for one law (a ``LAW_*`` of ``common``, or ``LAW_ANY`` for a
    scene with several laws: dispatched per contact) and one pattern of the feature switches
    ``pivot``, ``wedge``, ``pair``, ``joint``, ``shapes`` (truthy when the scene can reach
    that mode, ``shapes`` when it has a body other than a disk; ``scene_features``). Law and switches are compile-time constants of the loop (issue 14):
    plain values closed over, so Numba prunes the other laws and the switched-off modes
    before inlining and typing, and caches each variant on disk under its own key (the cache
    key of a closure holds its cell values). ``pair``: None, ``PAIR_DISKS`` (only the disk
    pair code is compiled), or ``PAIR_ALL`` (also ``pair2d_toi`` and the pair frames of
    every shape; any other truthy value means ``PAIR_ALL``)."""
    pair = None if not pair else (PAIR_DISKS if pair == PAIR_DISKS else PAIR_ALL)
    return _loop_for(int(law), *(True if on else None for on in (pivot, wedge)), pair,
                     *(True if on else None for on in (joint, shapes)))


@functools.lru_cache(maxsize=None)
def _loop_for(law, pivot, wedge, pair, joint, shapes):
    """``loop_for`` with its switches normalised to True or None (``pair``: None,
    ``PAIR_DISKS`` or ``PAIR_ALL``, split here into ``pair`` and ``pgen``, the pairs of
    other shapes than two disks; each handler takes its switch as an argument: None prunes
    it by type in the functions that are not inlined)."""
    pgen = True if pair == PAIR_ALL else None
    pair = True if pair is not None else None

    @njit(cache=True, _nrt=False)
    def run_loop(bint, bflt, verts, planes, grav, law_ids, law_par, bp_law, pairs, tolf,
                 toli, st, tref, pm, tz, zp, ttr, bp_t, bp_off, pr_t, pr_off, glob, cnt,
                 ev_t, ev_i, ev_f, seg_t, seg_b, seg_s, c_i, c_f, Wb, Pb, vb, tb, comp,
                 bmark, v2, W2, P2, tmp, err, cbod, ccon, cw, cid):
        """Advance from glob[0] to tolf[TF_T_END]; see the module docstring for the
        contract. The first call (``cnt[CN_STARTED] == 0``) initialises the run at glob[0].
        Compile-time constants: ``law``, ``pivot``, ``wedge``, ``pair``, ``joint``,
        ``shapes`` (``loop_for``)."""
        nb = st.shape[0]
        npl = planes.shape[0]
        npr = pairs.shape[0]
        t_end = tolf[TF_T_END]
        max_events = toli[TI_MAX_EVENTS]
        margin_e = evbuf.event_margin(toli[TI_SEQ_MAXSTEPS], MAXC, nb)
        margin_s = evbuf.segment_margin(MAXC, nb) + PIECE_BUDGET
        # the pivot integrator's scratch: the joint solve's workspace (never in use during a
        # pivot pass, which runs among the scheduled switches, before any impact of an instant)
        w = Wb.reshape(Wb.size)
        cap_e = ev_t.shape[0]
        cap_s = seg_t.shape[0]
        # the candidates of the bodies marked at an instant are recomputed at the top of the
        # next pass (one call site, inlined: the per-impact path makes no large calls)
        pend = False
        while True:
            if pend:
                pend = False
                for i in range(nb):
                    if bmark[i] != 0:
                        rc = _recompute_planes(pivot, shapes, i, glob[0], st, tref, bint, bflt,
                                               verts, planes, pm, tz, zp, bp_t, bp_off, tolf,
                                               toli, tmp, err)
                        if rc < 0:
                            return rc
                rc = _recompute_pairs(pair, pgen, glob[0], st, tref, bint, bflt, verts, planes,
                                      pairs, pm, tz, zp, ttr, bp_t, pr_t, pr_off, tolf, toli,
                                      bmark, tmp, err, cid, grav, cw,
                                      ccon, law_par)
                if rc < 0:
                    return rc
            t_now = glob[0]
            if cnt[evbuf.CN_STARTED] == 0:
                # ---- start of the run
                if not evbuf.has_room(cnt, margin_e, margin_s + nb, cap_e, cap_s):
                    return RC_BUFFER_FULL
                rc = _init(pivot, shapes, t_now, st, tref, bint, bflt, verts, planes, grav,
                           law_par, bp_law, pm, tz, zp, ttr, tolf, w, ev_t, ev_i, ev_f, cnt,
                           err)
                if rc < 0:
                    return rc
                cnt[evbuf.CN_STARTED] = 1
                for i in range(nb):
                    bmark[i] = 1
                    if pm[i, M_MODE] != PM_PIVOT:    # a pivot pass at t records its own motion
                        _push_seg(seg_t, seg_b, seg_s, cnt, st, tref, i)
                pend = True
                continue
            tmin = INF
            for i in range(nb):
                if tz[i] < tmin:
                    tmin = tz[i]
                if ttr[i] < tmin:
                    tmin = ttr[i]
                for p in range(npl):
                    if bp_t[i, p] < tmin:
                        tmin = bp_t[i, p]
            for q in range(npr):
                if pr_t[q] < tmin:
                    tmin = pr_t[q]
            if pair is not None and cid[CL_PEND] >= 0:
                tmin = t_now        # a pair whose impacts accumulate enters a cluster now
            if tmin > t_end:
                glob[0] = t_end
                return RC_DONE
            if cnt[evbuf.CN_EVENTS] >= max_events:
                return RC_MAX_EVENTS
            if not evbuf.has_room(cnt, margin_e, margin_s, cap_e, cap_s):
                return RC_BUFFER_FULL
            cnt[evbuf.CN_IDLE] += 1         # passes since the last event (_log resets it)
            if cnt[evbuf.CN_IDLE] > toli[TI_IDLE]:
                _set_err(err, t_now, -1, 0, 0.0, 0.0, cnt[evbuf.CN_IDLE], 0.0, 0.0)
                return ERR_IDLE
            if tmin <= t_now:
                tmin = t_now
                cnt[evbuf.CN_STALL] += 1
                if cnt[evbuf.CN_STALL] > toli[TI_STALL]:
                    _set_err(err, t_now, -1, 0, 0.0, 0.0, cnt[evbuf.CN_STALL], 0.0, 0.0)
                    return ERR_STALL
            else:
                cnt[evbuf.CN_STALL] = 0
            t = tmin
            glob[0] = t
            for i in range(nb):
                bmark[i] = 0

            # ---- scheduled switches: accumulation points, the end of slip, pivot passes (at
            # most one per pass of this loop: its pieces fit the segment margin)
            did = False
            cact = -1
            if pair is not None:
                if cid[CL_PEND] >= 0:
                    rc = _cluster_enter(shapes, t, st, tref, bint, bflt, verts, planes, grav,
                                        law_par, bp_law, bp_off, pairs, pr_off, pr_t, bp_t,
                                        pm, tz, zp, ttr, tolf, cbod, ccon, cw, cid,
                                        bmark, tmp, ev_t, ev_i, ev_f, seg_t, seg_b, seg_s, cnt,
                                        err)
                    if rc < 0:
                        return rc
                    for q in range(npr):
                        if pr_off[q] == PR_WAIT:    # searched again (_pend), as just hit
                            bmark[pairs[q, 0]] = 1
                            bmark[pairs[q, 1]] = 1
                    pend = True
                    continue
                if (cid[CL_N] > 0 and cid[CL_FROZEN] == 0
                        and _cluster_hit(t, st, tref, grav, pairs, pm, tz, ttr, bp_t, pr_t,
                                         tolf, cbod, ccon, cid, bmark) == 1):
                    # a body outside meets a member at this pass end (_held_cluster_pair):
                    # the moving cluster dissolves into the impact instant
                    cact = 2
                elif (cid[CL_N] > 0 and ttr[cid[CL_LEAD]] <= t
                      and not _others_due(t, -1, pm, tz, ttr, bp_t, pr_t)):
                    # (an event of a body outside due at the same t comes first: its pairs
                    # with members are bounded from the new motion before the pass runs)
                    rc, cact = _cluster_pass(shapes, t, st, tref, bint, bflt, verts, planes,
                                             grav, law_par, bp_law, pm, tz, ttr, bp_t, pairs, pr_t,
                                             pr_off, tolf, cbod, ccon, cw, cid, bmark, ev_t, ev_i,
                                             ev_f, seg_t, seg_b, seg_s, cnt, err)
                    if rc < 0:
                        return rc
                    if cact != 2:
                        pend = cact == 1
                        if cact == 0:
                            # its pieces fill this pass's segment margin
                            pass
                        pend = True
                        continue
                elif cid[CL_N] > 0 and cid[CL_FROZEN] != 0:
                    _cluster_hit(t, st, tref, grav, pairs, pm, tz, ttr, bp_t, pr_t, tolf,
                                 cbod, ccon, cid, bmark)
            for i in range(nb):
                if cact == 2:
                    break
                if pm[i, M_MODE] == PM_CLUSTER:
                    continue        # the cluster's pass (its leader's ttr) is above
                if ttr[i] <= t and pm[i, M_MODE] == PM_PIVOT:
                    if pivot is not None:
                        tcap = INF
                        qh = -1
                        if pgen is not None and pm[i, M_PLANE2] < 0:
                            # partners in closed-form motion bound the next pass; their
                            # own events at t come first (they change that motion)
                            if _others_due(t, i, pm, tz, ttr, bp_t, pr_t):
                                continue
                            rc, qh, tcap, hk = _pivot_partners(pgen, i, t, st, tref, bint,
                                                               bflt, verts, planes, pairs, pm,
                                                               tz, zp, ttr, bp_t, pr_t, pr_off,
                                                               tolf, tmp, err, grav, cid)
                            if rc < 0:
                                return rc
                            if qh >= 0 and hk == HB_REST and (
                                    cid[CL_PEND] < 0 or _pend_joins(qh, cid[CL_PEND], pairs)):
                                # touching a partner at a rate below the accumulation
                                # speed: persistent contact, a cluster entered at t (the
                                # pivot contact its plane row; _cluster_enter)
                                if cid[CL_PEND] < 0:
                                    cid[CL_PEND] = qh
                                did = True
                                break
                        if qh >= 0:
                            # it meets a partner at this pass end: an impact instant (a
                            # frozen cluster hit dissolves into it)
                            _pivot_to_instant(i, qh, t, st, grav, pm, ttr, bp_t, pr_t,
                                              bmark)
                            if cid[CL_N] > 0 and cid[CL_FROZEN] != 0:
                                _cluster_hit(t, st, tref, grav, pairs, pm, tz, ttr, bp_t,
                                             pr_t, tolf, cbod, ccon, cid, bmark)
                            rc, act = 0, 2
                        else:
                            rc, act = _pivot_event(i, t, st, tref, bint, bflt, verts, planes,
                                                   grav, law_par, bp_law, bp_off, bp_t, pm, tz,
                                                   zp, ttr, tolf, w, ev_t, ev_i, ev_f, seg_t,
                                                   seg_b, seg_s, cnt, err, tcap)
                    else:
                        rc, act = _not_compiled(err, t, i, FEATURE_PIVOT), 0
                    if rc < 0:
                        return rc
                    if not _finite(st, i):
                        _set_err(err, t, i, 0, st[i, X], st[i, Y], 0.0, 0.0, 0.0)
                        return ERR_NONFINITE
                    if act == 2:
                        continue    # an impact at t: the impact step below
                    did = True
                    if act == 1:
                        bmark[i] = 1
                        _push_seg(seg_t, seg_b, seg_s, cnt, st, tref, i)
                        continue
                    break
                if tz[i] <= t:
                    p = zp[i]
                    tz[i] = INF
                    fly_row(st, i, t - tref[i])
                    tref[i] = t
                    rc = _settle(shapes, i, p, t, st, bint, bflt, verts, planes, grav, law_par,
                                 bp_law, pm, ttr, tolf, ev_t, ev_i, ev_f, cnt, err)
                elif ttr[i] <= t:
                    rc = _transition(shapes, i, t, st, tref, bint, bflt, verts, planes, grav,
                                     law_par, bp_law, pm, ttr, tolf, ev_t, ev_i, ev_f, cnt, err)
                else:
                    continue
                if rc == RC_TIP:
                    rc = _tip_if(pivot, i, t, st, bint, bflt, verts, planes, grav, law_par,
                                 bp_law, pm, tz, zp, ttr, tolf, w, ev_t, ev_i, ev_f, cnt, err)
                if rc < 0:
                    return rc
                did = True
                if pm[i, M_MODE] == PM_PIVOT:
                    if pgen is not None:
                        # its pairs are searched again: a body of several shapes' pair
                        # that pivots is refused (_recompute_pair, PP_HELD)
                        bmark[i] = 1
                    break       # its first integration pass (at t) records its motion
                bmark[i] = 1
                if not _finite(st, i):
                    _set_err(err, t, i, 0, st[i, X], st[i, Y], 0.0, 0.0, 0.0)
                    return ERR_NONFINITE
                _push_seg(seg_t, seg_b, seg_s, cnt, st, tref, i)
            if did:
                pend = True
                continue

            nc = _gather(pivot, t, st, bint, bflt, verts, planes, grav, bp_law, pairs, pm, tolf,
                         toli, tref, bp_t, pr_t, c_i, bmark, err)
            if nc < 0:
                return nc
            q_again = _pair_again(pgen, nc, t, tref, c_i)
            ev0 = cnt[evbuf.CN_EVENTS]
            _bring_to_t(t, st, tref, bint, planes, grav, tz, zp, bmark)
            if joint is not None and toli[TI_POLICY] == POL_SIMULTANEOUS:
                nc = _held_into_instant(nc, t, st, bint, bflt, verts, planes, grav, bp_law,
                                        bp_off, pm, ttr, tolf, c_i, bmark, err)
                if nc < 0:
                    return nc
            nc = _frames(pgen, shapes, nc, t, st, bint, bflt, verts, planes, tolf, c_i, c_f,
                         err)
            if nc < 0:
                return nc
            if joint is not None:
                rc = _resolve(law, joint, nc, t, st, bflt, law_ids, law_par, c_i, c_f, Wb, Pb,
                              vb, tb, comp, v2, W2, P2, tolf, toli, ev_t, ev_i, ev_f, cnt, err)
            else:
                # no joint switch: each contact its own cluster (_single_ready)
                rc = 0
                for c in range(nc):
                    rc = _single_ready(c, t, st, c_i, c_f, err)
                    if rc == 1:
                        rc, vfN = _single(law, c, t, 1, st, bflt, law_ids, law_par, c_i, c_f,
                                          v2, W2, P2, ev_t, ev_i, ev_f, cnt, err)
                        if rc == 0 and perforates(law_par[c_i[c, CI_LAW]], vfN):
                            c_i[c, CI_OFF] = 1
                    if rc < 0:
                        break
            if rc < 0:
                return rc
            if q_again >= 0 and cnt[evbuf.CN_EVENTS] == ev0 and cid[CL_PEND] < 0:
                # a pair due again at the instant of its own impact whose contact rows the
                # impact step found not approaching (its time of impact saw the closing
                # witness of a face on a face beyond their overlap): the bodies touch
                # without approaching, a persistent contact entered from the next pass
                # (searched again, it was due at once for ever: a stall)
                cid[CL_PEND] = q_again
            # ---- after the impacts: disable perforated pairs, re-evaluate persistent
            # contacts, schedule accumulation points, hold a vertex whose impacts accumulate
            # (integrated pivot contact; other single-point chatter is an error), log
            # segments (flat steps, see _mark_pairs)
            _mark_pairs(nc, pairs, bp_off, pr_off, c_i)
            for i in range(nb):
                if bmark[i] == 0:
                    continue
                rc = _persisting(pivot, wedge, shapes, i, nc, t, st, bint, bflt, verts, planes,
                                 grav, law_par, bp_law, pm, (tz, zp, ttr), tolf, c_i, c_f, w,
                                 (ev_t, ev_i, ev_f), cnt, err)
                if rc == 0:
                    rc = _accumulating(pivot, wedge, shapes, i, nc, t, st, bint, bflt, verts,
                                       planes, grav, law_par, bp_law, bp_off, pm,
                                       (tz, zp, ttr), tolf, toli, c_i, c_f, w,
                                       (ev_t, ev_i, ev_f), cnt, err)
                    if rc == 0:
                        rc = _holding(pivot, wedge, shapes, i, nc, t, st, bint, bflt, verts,
                                      planes, grav, law_par, bp_law, pm, (tz, zp, ttr), tolf,
                                      c_i, c_f, w, (ev_t, ev_i, ev_f), cnt, err, pairs, cid)
                if rc < 0:
                    return rc
            rc = _log_instant(t, st, tref, bint, planes, pm, tz, zp, bmark,
                              (seg_t, seg_b, seg_s), cnt, tmp, err)
            if rc < 0:
                return rc
            pend = True
    return run_loop


@_inner
def _pair_again(pgen, nc, t, tref, c_i):
    """The first pair among the nc contacts gathered at t whose two bodies already had an
    instant at t (``tref`` = t before this impact step: the pair is due again at the time
    of an impact just resolved), or -1 (also where the loop has no general pairs)."""
    if pgen is None:
        return -1
    for c in range(nc):
        if c_i[c, CI_TYPE] == 1 and tref[c_i[c, CI_A]] == t and tref[c_i[c, CI_B]] == t:
            return -2 - c_i[c, CI_FEAT]
    return -1


@njit((_A1, _f, _i, _i), **_INNER)   # one signature: each FEATURE_* literal compiled it again
def _not_compiled(err, t, i, feature):
    """A handler of ``feature`` reached in a loop compiled without it (``scene_features``
    is wrong: a bug, reported, never skipped)."""
    _set_err(err, t, i, 0, float(feature), 0.0, 0.0, 0.0, 0.0)
    return ERR_NOT_COMPILED


@njit(cache=True, _nrt=False, inline="always")
def _tip_if(pivot, i, t, st, bint, bflt, verts, planes, grav, law_par, bp_law, pm, tz, zp,
            ttr, tolf, w, ev_t, ev_i, ev_f, cnt, err):
    """``_tip`` (a face that cannot hold the body: pivot on its loaded corner) where the
    scene can pivot."""
    if pivot is not None:
        return _tip(i, t, st, bint, bflt, verts, planes, grav, law_par, bp_law, pm, tz, zp,
                    ttr, tolf, w, ev_t, ev_i, ev_f, cnt, err)
    return _not_compiled(err, t, i, FEATURE_PIVOT)
