"""The compiled event loop of the exact 3D event-driven stepper (DESIGN §6, issue 5).

The 3D counterpart of ``stepper2d``, with the same structure, tolerances, event kinds,
policies and error codes (plus a few of its own). Everything is ``@njit(cache=True)``,
works on preallocated arrays and never allocates in the per-event path.
``rbimpact.simulation3d`` packs a scene, calls ``init_run`` once and the loop
``loop_for(law)`` compiled for the scene's law until it returns ``RC_DONE`` or
``RC_MAX_EVENTS`` (``RC_BUFFER_FULL``: the Python side doubles the event/segment buffers
and calls again). Negative return codes are errors (``ERR_*``, details in ``err``). Codes,
modes and event kinds are shared with 2D (``codes``); table columns are named
(``layout``, ``flight3d``'s state offsets ``SX, SQ, SV, SW, SA, SAL``, the ``B_*``
below). As in 2D, the law is a compile-time constant of ``loop_for`` and the loop's last
arguments are the feature switches ``pivot``, ``pair``, ``pgen``, ``joint``
(``scene_features``): a sphere on a floor compiles no point/edge contact, pair or joint
code, and spheres colliding compile no ``pair3d`` code.

Scene arrays (constant during a run)
------------------------------------
``bint`` int64[nb, 5]      ``B_KIND`` shape kind (``SH_*``), ``B_FIRST`` first feature row,
                           ``B_COUNT`` feature count, ``B_ROT`` rotation kind
                           (``flight3d.ROT_*``), ``B_AXIS`` symmetry axis (0, 1, 2)
``bflt`` float64[nb, 8]    ``B_MASS`` (kg), ``B_I1 + k`` principal moments about the body
                           axes (kg m^2), ``B_RADIUS`` feature radius (m: sphere radius,
                           capsule radius, 0 for a box), ``B_HALF + k`` half extents (m: box
                           half edges; capsule (0, 0, L/2))
``feats`` float64[nf, 3]   body-frame contact features (sphere: its centre)
``planes`` float64[np, 4]  ``(nx, ny, nz, d)``: half-space ``n . y >= d`` is free space
``grav`` float64[3]        gravity (m/s^2)
``law_ids``, ``law_par``   the law table; ``bp_law`` int64[nb, np]; ``pairs`` int64[npr, 3]
                           body pairs ``(a, b, law row)`` (any shapes, issue 16)
``tolf``, ``toli``         tolerances (``TF_*``, ``TI_*`` slots)

Dynamic state
-------------
``st`` float64[nb, 19] state rows at ``tref`` (``flight3d`` layout); ``ws`` float64[nb,
N_WS] integrator workspaces (``ws[i, 0] < 0``: not started for the current segment);
``pm`` int64[nb, 3] persistent contact (``M_MODE`` mode ``PM_*``, ``M_PLANE`` plane,
``M_FEAT`` face); ``tz``/``zp`` pending
accumulation point and its plane; ``ttr`` next persistent-mode transition; ``bt``/``bpl``
/``bft`` next body-plane impact time, plane and feature; ``bp_off`` body-plane pairs
disabled after a perforating impact; ``pr_t``/``pr_off`` the same for body pairs
(``codes.PR_*``: ``PR_HIT`` marks a pair that had an impact at the instant just resolved);
``glob[0]`` the current time; ``cnt`` = (events, segments, consecutive events at one
instant); integrated point/edge contact (``PM_PIVOT``): ``pv`` float64[nb, N_CP] its
contact parameters, ``pw`` float64[nb, N_PW] its integrator, ``pk`` int64[nb, 2] its
next event (kind ``pivot3d.PE_*``, index), due at ``ttr``.

Output: events ``ev_t`` (s), ``ev_i`` (kind ``EV_*``, a, b, mode, cluster), ``ev_f`` (point
xyz, normal xyz, tangent t1 xyz, v_i (N, T1, T2), v_f, P, dE); segments ``seg_t``,
``seg_b``, ``seg_s`` (body ``seg_b`` moves from ``seg_t`` with state row ``seg_s[:19]``;
``seg_s[19] == 1`` marks an integrated-contact segment whose parameters are
``seg_s[20:]``).

Persistent contact and accumulation (the 3D version of ``stepper2d``'s rules):

* Sphere: as the 2D disk. After an impact on a plane pushing it (``g_n = n . g < 0``), when
  ``E_ex = m v_N^2 / 2 + m |g_n| (h - r) < m zeno_speed^2 / 2`` the run jumps to the
  accumulation point and the sphere then slides with Coulomb friction (slip direction
  fixed when the plane is level or the slip is along the slope: closed form) until its
  contact point stops ("roll"), then rolls (or rests). A slip that curves (slope not
  along the slip, mu > 0) has no closed form: the sphere enters integrated contact
  (``_integrate_slide``: ``pivot3d`` with one contact at its centre) until the slip
  stops, then rolls in closed form again (``_sphere_rolls``). Requires spherical inertia.
* Sphere held by two planes (``PM_WEDGED``, ``_groove_enter``): when its impacts
  accumulate on two planes at once (a groove, a corner) and both contact points move
  slower than the accumulation speed, it rolls on both contacts along the groove axis
  (closed form, constant acceleration), slides along it without friction, or rests;
  rolling needs a squeeze that puts both contact forces in their cones, else (or while
  it slips faster) the run stops (``ERR_UNSUPPORTED``: slipping along a groove).
  Where neither holds it (it bounces on the other plane, or spins in the corner of three
  planes) it is held on the pressed plane in integrated contact with the planes it
  touches as wall candidates (``_sphere_held``).
* Box (on the face most aligned with the plane) and capsule (on its side):
  ``E_ex = m v_N^2 / 2 + w . I w / 2 + m |g_n| (h - h_rest)``; when below the threshold
  and consistent (``_rest_consistent``: the snap does not lift the body, ``SNAP_RTOL``,
  and a box's centre of mass is over that face) the run jumps to the accumulation point,
  snaps the body onto the face (rotation to the face, normal velocity and rotation
  removed: event "contact") and it then rests or slides without rotating (closed form
  while the slip is along the slope or the plane is level; a slip across a slope curves,
  as a puck's: the face's corners or the capsule's caps are held and the motion
  integrated, ``_integrate_slide``). The face must carry the friction moment (the
  pressure centre ``-h F / N`` inside it), else the box tips over the edge or the corner
  the pressure centre passed (``_tip``: integrated contact on those corners, as
  ``stepper2d._tip``; ``ERR_TIPPING`` only where no pivot state is consistent or the box
  starts so); a capsule whose friction turns it about its axis (it rolls) or whose
  pressure centre passes a cap is held on both caps and integrated (``_integrate_slide``).
* During an accumulation jump (last impact to ``t_inf``) the reported trajectory and the
  other candidate events use the held motion (``_held_into``: height of the last impact,
  no normal velocity, tangential motion exact, a box or capsule not rotating), so the
  body never dips below the plane; ``st`` keeps the free-flight row, so that the
  "contact" event reports the accumulated impulse and the energy removed.
* Integrated point and edge contact (``PM_PIVOT``, ``kernels/pivot3d.py``): when, after
  the impacts of an instant, one or two features of a box or capsule touch a plane with a
  normal speed below ``sqrt(2 |g''| rest_length)`` (or ``zeno_speed``) while their gap
  accelerates into it, the impacts would accumulate there (a corner or an edge the body
  tumbles over, a cap it rocks on; or one feature on each of two planes, in a groove or
  a corner, or a corner or cap held on the floor with another against a wall that
  gravity does not press, ``_second_plane``; or one or two on walls alone, when no plane
  gravity presses has a candidate). Their tiny normal velocities are removed by
  normal impulses (event "pivot", ``dE`` reported) and the body moves with those features
  held on their planes, each sticking or sliding under Coulomb friction, integrated with
  error control (``contact_tol``) until a feature lifts off ("release"), a contact starts or
  stops slipping ("slide", "stick"), or another feature hits a plane (an impact, with the
  held features in its cluster). Sliding contacts whose slip falls to ``slip_eps`` stick.
* One corner in the crease of two frictionless planes: held on both (two sliding
  contacts at one point, each with its own normal; with friction both would stick at
  once, a pinned point that the two-contact stick does not build: ``ERR_UNSUPPORTED``).
* A box or capsule held on a face or side (or at rest on two planes) that hits another
  plane takes the features touching its held plane into the impact and is in flight
  after it: what persists is decided as for any body after an impact (a box sliding on
  one groove plane into the crease ends held on its face and edge).
* The same at three to eight features on two planes (a box's edge or face on one groove
  plane and a corner or an edge on the other, a capsule's caps on both, a corner in the crease
  counted once per plane; ``_rest_or_gathered``) when no rest holds the body (below):
  ``pivot3d`` with up to ``KMAX`` = 8 contacts (dependent ones share their force by
  minimum norm). A third contact that sticks while two others do stops the body
  (``_pv_still``); it then rests there when forces in the cones hold it (``_pv_rests``,
  event "rest", mode ``PM_WEDGED``), else the first consistent state with two or fewer
  sticking contacts moves it on (``_pv_unstick``). More than eight: ``ERR_UNSUPPORTED``.
* Rest on several points of two planes (``PM_WEDGED`` for a box or capsule,
  ``_wedge_rest``): when the impacts accumulate at three or more features on two planes
  (a box with an edge on one groove plane and a corner on the other; or one corner on
  both), or on a face of one plane while touching another (a face and an edge), with a
  kinetic energy below the accumulation energy of the planes it touches, the body rests
  there if contact forces in the Coulomb cones
  hold it in static equilibrium (``groove3d.rest_forces``); its velocities are removed
  (events "contact", ``dE`` <= 0, and "rest"). An impulse on it releases it to flight.
  Otherwise (still moving) it is held at those points as above, or, with more than eight
  or no consistent state, the run stops with ``ERR_UNSUPPORTED``.
* Three or more features of a box chattering on one plane (a face landing while spinning
  about the normal, or sliding): the body is snapped onto the face as above; when the
  energy removed exceeds the accumulation threshold (its spin) the event is "capture"
  (``capture=True``, the default) -- a spinning box on a face has no closed form here --
  else the run fails (``capture=False``: ``ERR_CHATTER``).
* Two spheres whose impacts accumulate (after an impact of the pair its re-contact is
  within a rise of rest_length, ``decisions.pair_persistence``; or the accumulation rule at
  the instant): persistent contact, ``PM_CLUSTER`` (``kernels/cluster3d.py``, issue 16
  item 2; stepper2d's design): the spheres touching them and their planes are integrated
  together, with stick, slip and lift-off of every contact, until the cluster dissolves
  (its last sphere-sphere contact lifts: each sphere settles on its plane or flies), an
  outside gap closes (an impact at that instant with the cluster's contacts), or it rests
  (frozen until hit). See "Persistent sphere contact" below the instant's code.

Body pairs of other shapes than two spheres (issue 16; the switch ``pgen``): the time of
impact of ``pair3d_toi`` from both rows at the search's start, no further than either
body's next scheduled event (``_general_pair``); the contact points of
``pair3d_manifold`` at the impact (``_pair_contacts``), in the instant's clusters with the
plane contacts. After an impact of the pair its next search decides whether the bodies
stay in contact (``decisions.pair_persistence``, shared with 2D): persistent contact
between such bodies is not built, so ``ERR_PERSISTENT_PAIR`` names the pair
(``codes.PP_*`` reason), as it does when a body held by an integrated contact or in a
moving cluster has such a partner.
"""
import functools
import math

import numpy as np
from numba import njit

from .cache_guard import guard

# flush stale compiled callers before any kernel module below is imported (cache_guard)
guard(__name__, __file__)

from . import evbuf
from .joint_polish import polish as joint_polish, stick_sets
from .instant import (CI_A, CI_B, CI_FEAT, CI_LAW, CI_OFF, CI_TYPE, N_CI,  # noqa: F401
                      cluster_contacts, cluster_members)
from .layout import (B_AXIS, B_COUNT, B_FIRST, B_KIND, B_MASS, B_ROT, CL_CHAT, CL_CHAT_MAX,
                     CL_CHAT_RTOL, CL_EV, CL_FROZEN, CL_HDR, CL_IDX, CL_LEAD, CL_N, CL_NC,
                     CL_NK, CL_PEND, M_AUX, M_FEAT, M_MODE, M_PLANE, NCAND)
from .codes import (ERR_CHATTER, ERR_CONTACT_STEPS, ERR_FAR_ACCUMULATION, ERR_JOINT_E,
                   ERR_MISSED, ERR_NONFINITE, ERR_NOT_COMPILED, ERR_NO_SOLUTION, ERR_PAINLEVE,
                   ERR_PGS, ERR_ROT, ERR_SEQ, ERR_STALL, ERR_TIPPING, ERR_IDLE,
                   ERR_TOI, ERR_TOO_MANY, ERR_UNSUPPORTED, EVENT_KINDS, EV_CAPTURE,
                   EV_CONTACT, EV_IMPACT, EV_IWC, EV_PIVOT, EV_RELEASE, EV_REST, EV_SLIDE,
                   EV_STICK, PAINLEVE_IMPACT,
                   FEATURES, FEATURE_JOINT, FEATURE_PAIR, FEATURE_PIVOT, PM_FLIGHT, PM_PIVOT,
                   PM_REST, PM_ROLL, PM_SLIDE, PM_WEDGED, POL_SIMULTANEOUS, RC_BUFFER_FULL, RC_DONE,
                   RC_MAX_EVENTS, ERR_PERSISTENT_PAIR, PP_CHATTER, PP_HELD,  # noqa: F401
                   PP_TOGETHER, PM_CLUSTER, PP_CLUSTER, PP_NO_MODE, PP_SHAPES, PP_SPLIT,
                   PP_STICK_SLIP, PP_TWO, PR_CHECK, PR_HIT, PR_OFF, PR_ON, PR_REL)
from .common import MODE_NO_SOLUTION, P_E, P_MU, P_TOL, REST_POISSON, spd3_solve
from . import cluster3d as cl
from .decisions import (REL_S0, accumulation_time, impacts_before_rest, pair_accel_bound,
                        pair_persistence, pair_zero_speed, perforates, touching_accel,
                        touching_rate)
from .dispatch import resolve_3d_as
from .routh import routh_3d_scalar
from .groove3d import line_rest, rest_forces, rest_work_size
from .minnorm import minnorm_solve
from .flight3d import (RK_OK, ROT_SPHERICAL, SA, SAL, SQ, SV, SW, SX, WS_MODE, pose_at, qmul,
                       qnormalize, qrot, qrot_inv)
from .pivot3d import (CP_D, CP_EPS, CP_F, CP_G, CP_I, CP_K, CP_L, CP_M, CP_MU, CP_N, CP_P,
                      CP_PLANE, CP_RAD, CP_S, CP_U, FORCE_ARM, FW_A, FW_AL, FW_B, FW_C, FW_F,
                      FW_LAM, FW_MARG, KMAX, N_CP, PE_GAP, PE_JAM, PE_LIFT, PE_NONE, PE_SLIP,
                      PE_STOP, PI_FORCES, PI_OK, PI_TOO_MANY_STEPS, PV_OK, PV_PAINLEVE,
                      PV_STUCK, PW_JAM, PW_S0, PW_WHY, PW_Y, cone_interval, contact_accel,
                      contact_mu, contact_normal, contact_plane, pivot_eval, pivot_forces,
                      pivot_next_event, pivot_start, point_accel, slip_growth)
from .toi2d import TOI_MISSED, TOI_NOT_CONVERGED, TOI_OK
from .toi3d import TOI_ROT_FAILED, body_planes_toi, sphere_sphere_toi, tangent_basis
from .pair3d import FR_NX, FR_PAX, FR_PBX, FR_RATE, N_FE, pair_frame  # noqa: F401
from .pair3d_manifold import (MAX_MF, MF_PAX, MF_PBX, N_MF, manifold_slab,  # noqa: F401
                               pair_manifold)
from .pair3d_shape import body_reach
from .pair3d_toi import pair_toi

INF = math.inf
# Compile time: callees are never passed int or bool literals (Numba compiles a separate
# copy of a function for every literal value it is called with); small helpers are
# inlined. Numba caches a compiled function by the stamp of its own file only: the
# cache_guard call above flushes this module's cache when a kernel it calls changed.

# shape kinds
# bflt columns (B_MASS and the bint columns: kernels/layout.py)
B_I1 = 1         # principal moments I1, I2, I3 about the body axes (kg m^2): B_I1 + k
B_RADIUS = 4     # feature radius (m): a sphere's or a capsule's radius, 0 for a box
B_HALF = 5       # half extents (m): B_HALF + k (box half edges; capsule (0, 0, L/2))

SH_SPHERE = 0
SH_BOX = 1
SH_CAPSULE = 2

# persistent modes (pm[:, 0])

# event kinds (ev_i[:, 0]); a persistent mode m is logged as kind m + 1


# tolerance slots
TF_REST_LENGTH = 0
TF_ZENO_SPEED = 1
TF_GAP_TOL = 2
TF_TOI_RTOL = 3
TF_TOI_ATOL = 4
TF_SIMUL_TIME = 5
TF_SIMUL_TOL = 6
TF_SEQ_VTOL = 7
TF_T_END = 8
TF_ROT_TOL = 9
TF_CONTACT_TOL = 10
TF_SLIP_EPS = 11
TF_PAINLEVE = 12       # PAINLEVE_ERROR or PAINLEVE_IMPACT (codes.py), as a float
N_TF = 13
TI_TOI_MAXIT = 0
TI_SIMUL_MAXIT = 1
TI_SEQ_MAXSTEPS = 2
TI_STALL = 3
TI_POLICY = 4
TI_MAX_EVENTS = 5
TI_ROT_MAX_STEPS = 6
TI_CAPTURE = 7
TI_ACC_MAX = 8         # max_accumulation_impacts
TI_IDLE = 9            # idle_passes
N_TI = 10


#: a slip is "along the slope" when the sine of the angle between the slip and the
#: tangential gravity is below this (dimensionless)
PARALLEL_RTOL = 1e-12
#: pm[i, M_AUX] of a sphere whose slip curves across a slope (no closed form): its
#: persistent contact is integrated (pivot3d, one contact at its centre) from ttr on
AUX_INTEGRATE = 1
#: a sphere held by two planes (PM_WEDGED): the planes form a groove when the sine of the
#: angle between their normals exceeds GROOVE_SIN (dimensionless); rolling is consistent
#: when some squeeze puts both contact forces in their friction cones, up to GROOVE_RTOL
#: m |g| (N, the round-off of the force balance)
GROOVE_SIN = 1e-9
GROOVE_RTOL = 1e-12
#: _groove_enter's answer when the sphere slips on the groove's planes (integrate it)
GROOVE_SLIPS = 2
#: _persist_setup's answer when a box's face cannot hold it (the pressure centre of its
#: friction moment outside the face): it tips over that side's edge or corner (``_tip``)
RC_TIP = 3
#: rest on several points on two or more planes (``_wedge_rest``, ``groove3d``): at most
#: this many touching features are gathered (a box has 8 vertices, on two planes 16)
WEDGE_MAXK = 16
#: a sphere's contact point is at rest (it rolls) when its slip is below ROLL_RTOL times
#: |v_T| + r |w| (dimensionless: the round-off of the slip, exactly zero in 2D)
ROLL_RTOL = 1e-12
#: joint solve: a sweep has converged when no velocity changes by more than
#: simul_tol + SIMUL_RTOL * max |v_i| (m/s); the relative part absorbs round-off. When the
#: sweeps cycle (redundant contacts with friction) and simul_max_iter is reached, the
#: solve is accepted if the last sweep changed no velocity by more than
#: simul_tol + SIMUL_ACCEPT_RTOL * V, V the larger of max |v_i| and the speed scale
#: |v| + |w| L + sqrt(|g| L) of the bodies in the cluster (a slow landing of a spinning box
#: is judged against the box's motion, not the landing speed; a box coming to rest against
#: the speed its integrated contact is controlled on, pivot3d), else the run fails (ERR_PGS)
SIMUL_RTOL = 1e-12
SIMUL_ACCEPT_RTOL = 1e-9
#: integrated contact: a slip direction u is consistent when the slip's acceleration along
#: it, u . a_T, exceeds SLIP_ACC_TOL |g| (dimensionless): the slip then grows. When no
#: direction is (the stick force only touched its cone), the contact keeps sticking.
SLIP_ACC_TOL = 1e-9
#: ... except at a continuous onset: a contact whose sticking force has just left its cone
#: (by the event arm pivot3d.FORCE_ARM m |g|) starts to slip opposite to that force with an
#: acceleration that is still O(FORCE_ARM |g|) and can be below SLIP_ACC_TOL |g| (a corner
#: pivoting with mu = 10 under a small normal force: u . a_T = 2.4e-9 m/s^2). The
#: consistent direction within SLIP_ONSET_ANGLE (rad) of the opposite of the friction force
#: is taken when u . a_T > -SLIP_ACC_TOL |g| (zero to within the acceptance band)
SLIP_ONSET_ANGLE = 1e-4
#: integrated contact: angular scan steps over the tangent plane when looking for the
#: consistent direction in which a contact starts to slip
N_SLIP_SCAN = 72
#: integrated contact: when no stick/slip state is consistent, a sliding contact whose slip
#: is at most STICK_RESCUE slip_eps (its direction is still blending, pivot3d.SLIP_BLEND)
#: sticks -- its slip removed by an impulse (dissipative, at most m STICK_RESCUE slip_eps)
#: -- and the state is checked again (dimensionless)
STICK_RESCUE = 10.0
#: integrated contact: three or more sticking points hold the body still unless they lie on
#: one line: within STILL_LINE_RTOL of the body's size L (dimensionless round-off
#: allowance), the body keeps turning about that line (``_pv_still``); a turn about the
#: line of two sticking points is blocked by another held contact whose normal speed per
#: radian exceeds STILL_LINE_RTOL L (``_pv_stick_edge``)
STILL_LINE_RTOL = 1e-9
#: integrated contact: at most WALLS_MAX wall candidates (``_second_plane``) join a held
#: motion at its entry, as the (plane, feature row) pairs of one int tuple (its length is
#: 2 WALLS_MAX; -1 unused); NO_WALLS, none
WALLS_MAX = 2
NO_WALLS = (-1, -1, -1, -1)
#: integrated contact at three or more points: the normal impulses that zero their normal
#: velocities solve W_NN dP = -v_N by a minimum-norm least-squares solve (``minnorm``):
#: singular values below ZERO_NORMALS_RTOL times the largest are zero (dependent contacts,
#: dimensionless), in at most ZERO_NORMALS_SWEEPS Jacobi sweeps
ZERO_NORMALS_RTOL = 1e-12
ZERO_NORMALS_SWEEPS = 60
#: a body stopped on three or more sticking points (its kinetic energy removed by their
#: impulses) rests when the best rest forces leave their Coulomb cones by at most
#: HELD_REST_RTOL m |g| (dimensionless; ``_pv_rests``). Not round-off: such a body would
#: creep off with an acceleration of at most HELD_REST_RTOL |g|, which is neglected, as a
#: slip below slip_eps is (3:3210509315: 1.6e-8)
HELD_REST_RTOL = 1e-7
#: three or more contacts still and not at rest: some start to slide (``_pv_unstick``);
#: their start directions are iterated at most SLIDE_ALL_ITER times until no direction
#: turns by more than SLIDE_ALL_RTOL (1 - cos of the turn, dimensionless)
SLIDE_ALL_ITER = 30
SLIDE_ALL_RTOL = 1e-12
#: a face holds the friction moment when the pressure centre stays inside it by this
#: fraction of the face's half extent (dimensionless round-off allowance)
FACE_RTOL = 1e-12
#: accumulation onto a rest is accepted only if the snap lifts the centre of mass by at
#: most SNAP_RTOL times the rest height (dimensionless round-off allowance), i.e. if
#: E_ex >= -m |g_n| SNAP_RTOL h_rest: a rest above the body would create energy
SNAP_RTOL = 1e-12
#: Painleve jam inside an integrated slide (pivot3d.PE_JAM): the phase stops within
#: pivot3d.STAGE_HMIN of its largest step before the point where the sliding contact's
#: normal-force coefficient A = W_NN - mu u . W_TN reaches 0. The impact without collision
#: starts there; the last stretch to A = 0 (the slip turning by dA/dP under the unbounded
#: normal force) is taken to first order in impulse (``_jam_approach``) when it turns the
#: slip by at most JAM_TURN (rad); a larger turn is not a jam and stays an error
JAM_TURN = 1e-3

MAXC = 24          # contacts resolved at one instant
N_CF = 25
CF_N, CF_T1, CF_T2, CF_P, CF_RA, CF_RB, CF_VI, CF_PI, CF_VCMN = 0, 3, 6, 9, 12, 15, 18, 21, 24
N_EF = 19
N_SEG = 20 + N_CP   # segment row: state (19), integrated-contact flag, contact parameters
N_ERR = 20          # err: t, a, b, xyz, x1, x2, x3, |v_T|, v (3), W (6 upper entries)


def event_margin(toli, nb):
    """Free event rows the loop needs before it handles one more instant (evbuf)."""
    return int(evbuf.event_margin_py(int(toli[TI_SEQ_MAXSTEPS]), MAXC, nb))


def segment_margin(nb):
    """Free segment rows the loop needs before it handles one more instant (evbuf), plus
    the pieces of one cluster pass (``cluster3d.PIECE_BUDGET``)."""
    return int(evbuf.segment_margin_py(MAXC, nb)) + cl.PIECE_BUDGET


# ------------------------------------------------------------------ small helpers


@njit(cache=True, inline="always")
def _log(ev_t, ev_i, ev_f, cnt, t, kind, a, b, mode, cluster, c_f, c, vi0, vi1, vi2,
         vf0, vf1, vf2, P0, P1, P2, dE):
    """Log an event whose point and frame are row c of c_f."""
    k = cnt[evbuf.CN_EVENTS]
    ev_t[k] = t
    ev_i[k, 0] = kind
    ev_i[k, 1] = a
    ev_i[k, 2] = b
    ev_i[k, 3] = mode
    ev_i[k, 4] = cluster
    for j in range(3):
        ev_f[k, j] = c_f[c, CF_P + j]
        ev_f[k, 3 + j] = c_f[c, CF_N + j]
        ev_f[k, 6 + j] = c_f[c, CF_T1 + j]
    ev_f[k, 9] = vi0
    ev_f[k, 10] = vi1
    ev_f[k, 11] = vi2
    ev_f[k, 12] = vf0
    ev_f[k, 13] = vf1
    ev_f[k, 14] = vf2
    ev_f[k, 15] = P0
    ev_f[k, 16] = P1
    ev_f[k, 17] = P2
    ev_f[k, 18] = dE
    cnt[evbuf.CN_EVENTS] = k + 1
    cnt[evbuf.CN_IDLE] = 0


@njit(cache=True)
def _push_seg(seg_t, seg_b, seg_s, cnt, st, tref, i, pm, pv):
    k = cnt[evbuf.CN_SEGS]
    seg_t[k] = tref[i]
    seg_b[k] = i
    for j in range(19):
        seg_s[k, j] = st[i, j]
    if pm[i, M_MODE] == PM_PIVOT:
        seg_s[k, 19] = 1.0
        for j in range(N_CP):
            seg_s[k, 20 + j] = pv[i, j]
    else:
        seg_s[k, 19] = 0.0
    cnt[evbuf.CN_SEGS] = k + 1


@njit(cache=True)
def _held_into(src, kind, nx, ny, nz, out):
    """The motion of a body during a pending accumulation (Zeno) jump on the plane with
    normal n: ``out[:19]`` = the state row ``src`` with its normal velocity and normal
    acceleration removed and (not for a sphere) its rotation stopped. From the last impact
    to the accumulation time the body then stays at the height of that impact while its
    tangential motion is the exact free flight; the reported trajectory never dips below
    the plane. ``src`` may be ``out``. ``st`` keeps the true free-flight row, so that the
    "contact" event at the accumulation time reports the accumulated impulse and the
    energy removed; this row is used for the trajectory and the other candidate events."""
    for j in range(19):
        out[j] = src[j]
    vN = nx * out[7] + ny * out[8] + nz * out[9]
    aN = nx * out[13] + ny * out[14] + nz * out[15]
    out[7] -= vN * nx
    out[8] -= vN * ny
    out[9] -= vN * nz
    out[13] -= aN * nx
    out[14] -= aN * ny
    out[15] -= aN * nz
    if kind != SH_SPHERE:
        for j in range(3):
            out[10 + j] = 0.0
            out[16 + j] = 0.0


@njit(cache=True)
def _push_held(seg_t, seg_b, seg_s, cnt, st, tref, i, bint, planes, p):
    """Log body i's held motion during a pending accumulation jump on plane p."""
    k = cnt[evbuf.CN_SEGS]
    seg_t[k] = tref[i]
    seg_b[k] = i
    _held_into(st[i], bint[i, B_KIND], planes[p, 0], planes[p, 1], planes[p, 2], seg_s[k])
    seg_s[k, 19] = 0.0
    cnt[evbuf.CN_SEGS] = k + 1


@njit(cache=True, inline="always")
def _set_err(err, t, a, b, px, py, pz, x1, x2, x3):
    err[0] = t
    err[1] = a
    err[2] = b
    err[3] = px
    err[4] = py
    err[5] = pz
    err[6] = x1
    err[7] = x2
    err[8] = x3


@njit(cache=True, inline="always")
def _finite(st, i):
    for j in range(19):
        if not math.isfinite(st[i, j]):
            return False
    return True


@njit(cache=True, inline="always")
def _vz2(tolf, gabs):
    """Squared accumulation speed (m^2/s^2) for a normal acceleration magnitude gabs."""
    z = tolf[TF_ZENO_SPEED]
    if z >= 0.0:
        return z * z
    return 2.0 * gabs * tolf[TF_REST_LENGTH]


@njit(cache=True)
def _bring(i, t, st, tref, bint, bflt, ws, tolf, toli, pose, pm, pv, pw, fw, err):
    """Advance body i's state row to time t (a new segment starts there). Returns 0,
    ERR_ROT, ERR_CONTACT_STEPS or ERR_PAINLEVE."""
    s = t - tref[i]
    if s != 0.0 and pm[i, M_MODE] == PM_PIVOT:
        rc = pivot_eval(pw[i], pv[i], fw, s, pose)
        if rc != PI_OK:
            _set_err(err, t, i, -1 - int(pv[i, CP_PLANE]), st[i, SX], st[i, SX + 1],
                     st[i, SX + 2], pw[i, PW_WHY], pv[i, CP_MU], pv[i, CP_K])
            return ERR_CONTACT_STEPS if rc == PI_TOO_MANY_STEPS else ERR_PAINLEVE
        for j in range(13):
            st[i, j] = pose[j]
    elif s != 0.0:
        rc = pose_at(st[i], bint[i, B_ROT], bint[i, B_AXIS], bflt[i, B_I1], bflt[i, B_I1 + 1],
                     bflt[i, B_I1 + 2], ws[i], s, tolf[TF_ROT_TOL], toli[TI_ROT_MAX_STEPS],
                     pose)
        if rc != RK_OK:
            _set_err(err, t, i, -1, st[i, SX], st[i, SX + 1], st[i, SX + 2], 0.0, 0.0, 0.0)
            return ERR_ROT
        for j in range(19):
            st[i, j] = pose[j]
    tref[i] = t
    ws[i, WS_MODE] = -1.0
    return 0


@njit(cache=True)
def _iinv(st, i, bflt, Ii):
    """World inverse inertia tensor of body i at its current orientation into Ii (3x3)."""
    w, x, y, z = st[i, SQ], st[i, SQ + 1], st[i, SQ + 2], st[i, SQ + 3]
    r00 = 1.0 - 2.0 * (y * y + z * z)
    r01 = 2.0 * (x * y - w * z)
    r02 = 2.0 * (x * z + w * y)
    r10 = 2.0 * (x * y + w * z)
    r11 = 1.0 - 2.0 * (x * x + z * z)
    r12 = 2.0 * (y * z - w * x)
    r20 = 2.0 * (x * z - w * y)
    r21 = 2.0 * (y * z + w * x)
    r22 = 1.0 - 2.0 * (x * x + y * y)
    a = 1.0 / bflt[i, B_I1]
    b = 1.0 / bflt[i, B_I1 + 1]
    c = 1.0 / bflt[i, B_I1 + 2]
    Ii[0, 0] = r00 * r00 * a + r01 * r01 * b + r02 * r02 * c
    Ii[0, 1] = r00 * r10 * a + r01 * r11 * b + r02 * r12 * c
    Ii[0, 2] = r00 * r20 * a + r01 * r21 * b + r02 * r22 * c
    Ii[1, 1] = r10 * r10 * a + r11 * r11 * b + r12 * r12 * c
    Ii[1, 2] = r10 * r20 * a + r11 * r21 * b + r12 * r22 * c
    Ii[2, 2] = r20 * r20 * a + r21 * r21 * b + r22 * r22 * c
    Ii[1, 0] = Ii[0, 1]
    Ii[2, 0] = Ii[0, 2]
    Ii[2, 1] = Ii[1, 2]


@njit(cache=True)
def _rot_energy(st, i, bflt):
    """Rotational kinetic energy (J) of body i."""
    bx, by, bz = qrot_inv(st[i, SQ], st[i, SQ + 1], st[i, SQ + 2], st[i, SQ + 3], st[i, SW],
                          st[i, SW + 1], st[i, SW + 2])
    return 0.5 * (bflt[i, B_I1] * bx * bx + bflt[i, B_I1 + 1] * by * by + bflt[i, B_I1 + 2] *
                  bz * bz)


@njit(cache=True)
def _energy(st, bflt, grav, i):
    m = bflt[i, B_MASS]
    return (0.5 * m * (st[i, SV] ** 2 + st[i, SV + 1] ** 2 + st[i, SV + 2] ** 2) +
            _rot_energy(st, i, bflt) - m * (grav[0] * st[i, SX] + grav[1] * st[i, SX + 1] +
            grav[2] * st[i, SX + 2]))


# ------------------------------------------------------------------ contact geometry


@njit(cache=True, inline="always")
def _frame(c_f, c, nx, ny, nz):
    a0, a1, a2, b0, b1, b2 = tangent_basis(nx, ny, nz)
    c_f[c, CF_N] = nx
    c_f[c, CF_N + 1] = ny
    c_f[c, CF_N + 2] = nz
    c_f[c, CF_T1] = a0
    c_f[c, CF_T1 + 1] = a1
    c_f[c, CF_T1 + 2] = a2
    c_f[c, CF_T2] = b0
    c_f[c, CF_T2 + 1] = b1
    c_f[c, CF_T2 + 2] = b2


@njit(cache=True, inline="always")
def _point_vel(st, i, rx, ry, rz):
    """Velocity (m/s) of the material point at arm r of body i."""
    wx, wy, wz = st[i, SW], st[i, SW + 1], st[i, SW + 2]
    return (st[i, SV] + wy * rz - wz * ry, st[i, SV + 1] + wz * rx - wx * rz,
            st[i, SV + 2] + wx * ry - wy * rx)


@njit(cache=True)
def _contact_velocity(st, c_i, c_f, c):
    """(v_N, v_T1, v_T2) of A's contact point minus B's (m/s)."""
    a = c_i[c, CI_A]
    ux, uy, uz = _point_vel(st, a, c_f[c, CF_RA], c_f[c, CF_RA + 1], c_f[c, CF_RA + 2])
    if c_i[c, CI_TYPE] == 1:
        wx, wy, wz = _point_vel(st, c_i[c, CI_B], c_f[c, CF_RB], c_f[c, CF_RB + 1],
                                c_f[c, CF_RB + 2])
        ux -= wx
        uy -= wy
        uz -= wz
    vn = ux * c_f[c, CF_N] + uy * c_f[c, CF_N + 1] + uz * c_f[c, CF_N + 2]
    v1 = ux * c_f[c, CF_T1] + uy * c_f[c, CF_T1 + 1] + uz * c_f[c, CF_T1 + 2]
    v2 = ux * c_f[c, CF_T2] + uy * c_f[c, CF_T2 + 1] + uz * c_f[c, CF_T2 + 2]
    return vn, v1, v2


@njit(cache=True, inline="always")
def _arm_cross(c_f, c, roff, k):
    """r x e_k with r = c_f[c, roff:roff+3] and e_k the k-th contact basis vector."""
    rx = c_f[c, roff]
    ry = c_f[c, roff + 1]
    rz = c_f[c, roff + 2]
    ex = c_f[c, 3 * k]
    ey = c_f[c, 3 * k + 1]
    ez = c_f[c, 3 * k + 2]
    return ry * ez - rz * ey, rz * ex - rx * ez, rx * ey - ry * ex


@njit(cache=True)
def _block(c, d, j, sc, sd, st, bflt, c_f, Ii, out, o0, o1):
    """Add the coupling of contacts c and d through body j (arm slots sc, sd: CF_RA or
    CF_RB; the sign is applied by the caller) to out[o0:o0+3, o1:o1+3]."""
    _iinv(st, j, bflt, Ii)
    im = 1.0 / bflt[j, B_MASS]
    sgn = (1.0 if sc == CF_RA else -1.0) * (1.0 if sd == CF_RA else -1.0)
    for a in range(3):
        ax, ay, az = _arm_cross(c_f, c, sc, a)
        ea0 = c_f[c, 3 * a]
        ea1 = c_f[c, 3 * a + 1]
        ea2 = c_f[c, 3 * a + 2]
        for b in range(3):
            bx, by, bz = _arm_cross(c_f, d, sd, b)
            lin = (ea0 * c_f[d, 3 * b] + ea1 * c_f[d, 3 * b + 1] + ea2 * c_f[d, 3 * b + 2]) * im
            ang = (ax * (Ii[0, 0] * bx + Ii[0, 1] * by + Ii[0, 2] * bz)
                   + ay * (Ii[1, 0] * bx + Ii[1, 1] * by + Ii[1, 2] * bz)
                   + az * (Ii[2, 0] * bx + Ii[2, 1] * by + Ii[2, 2] * bz))
            out[o0 + a, o1 + b] += sgn * (lin + ang)


@njit(cache=True)
def _contact_W(st, bflt, c_i, c_f, c, W3, Ii):
    """Delassus matrix (1/kg) of contact c (DESIGN §3) into W3 (3x3)."""
    for a in range(3):
        for b in range(3):
            W3[a, b] = 0.0
    _block(c, c, c_i[c, CI_A], CF_RA, CF_RA, st, bflt, c_f, Ii, W3, 0, 0)
    if c_i[c, CI_TYPE] == 1:
        _block(c, c, c_i[c, CI_B], CF_RB, CF_RB, st, bflt, c_f, Ii, W3, 0, 0)
    # exact symmetry
    for a in range(3):
        for b in range(a + 1, 3):
            m = 0.5 * (W3[a, b] + W3[b, a])
            W3[a, b] = m
            W3[b, a] = m


@njit(cache=True)
def _apply_body(st, bflt, i, rx, ry, rz, jx, jy, jz, Ii):
    m = bflt[i, B_MASS]
    st[i, SV] += jx / m
    st[i, SV + 1] += jy / m
    st[i, SV + 2] += jz / m
    cx = ry * jz - rz * jy
    cy = rz * jx - rx * jz
    cz = rx * jy - ry * jx
    _iinv(st, i, bflt, Ii)
    st[i, SW] += Ii[0, 0] * cx + Ii[0, 1] * cy + Ii[0, 2] * cz
    st[i, SW + 1] += Ii[1, 0] * cx + Ii[1, 1] * cy + Ii[1, 2] * cz
    st[i, SW + 2] += Ii[2, 0] * cx + Ii[2, 1] * cy + Ii[2, 2] * cz


@njit(cache=True)
def _apply(st, bflt, c_i, c_f, c, P0, P1, P2, Ii):
    """Apply the contact-space impulse (P_N, P_T1, P_T2) to A and its opposite to B."""
    jx = P0 * c_f[c, CF_N] + P1 * c_f[c, CF_T1] + P2 * c_f[c, CF_T2]
    jy = P0 * c_f[c, CF_N + 1] + P1 * c_f[c, CF_T1 + 1] + P2 * c_f[c, CF_T2 + 1]
    jz = P0 * c_f[c, CF_N + 2] + P1 * c_f[c, CF_T1 + 2] + P2 * c_f[c, CF_T2 + 2]
    _apply_body(st, bflt, c_i[c, CI_A], c_f[c, CF_RA], c_f[c, CF_RA + 1],
                c_f[c, CF_RA + 2], jx, jy, jz, Ii)
    if c_i[c, CI_TYPE] == 1:
        _apply_body(st, bflt, c_i[c, CI_B], c_f[c, CF_RB], c_f[c, CF_RB + 1],
                    c_f[c, CF_RB + 2], -jx, -jy, -jz, Ii)


@njit(cache=True, inline="always")
def _bcode(c_i, c):
    if c_i[c, CI_TYPE] == 0:
        return -1 - c_i[c, CI_B]
    return c_i[c, CI_B]


@njit(cache=True)
def _free_alpha(st, i, bflt):
    """Torque-free angular acceleration (rad/s^2, world) of body i: I^-1 ((I w) x w)."""
    q0, q1, q2, q3 = st[i, SQ], st[i, SQ + 1], st[i, SQ + 2], st[i, SQ + 3]
    bx, by, bz = qrot_inv(q0, q1, q2, q3, st[i, SW], st[i, SW + 1], st[i, SW + 2])
    I1, I2, I3 = bflt[i, B_I1], bflt[i, B_I1 + 1], bflt[i, B_I1 + 2]
    return qrot(q0, q1, q2, q3, (I2 - I3) * by * bz / I1, (I3 - I1) * bz * bx / I2,
                (I1 - I2) * bx * by / I3)


@njit(cache=True)
def _gap_accel(st, bflt, c_i, c_f, c):
    """Second time derivative (m/s^2) of the contact's gap in free flight, now."""
    nx = c_f[c, CF_N]
    ny = c_f[c, CF_N + 1]
    nz = c_f[c, CF_N + 2]
    a = c_i[c, CI_A]
    if c_i[c, CI_TYPE] == 1:
        b = c_i[c, CI_B]
        dvx = st[a, SV] - st[b, SV]
        dvy = st[a, SV + 1] - st[b, SV + 1]
        dvz = st[a, SV + 2] - st[b, SV + 2]
        vn = dvx * nx + dvy * ny + dvz * nz
        vt2 = dvx * dvx + dvy * dvy + dvz * dvz - vn * vn
        R = bflt[a, B_RADIUS] + bflt[b, B_RADIUS]
        return (nx * (st[a, SA] - st[b, SA]) + ny * (st[a, SA + 1] - st[b, SA + 1])
                + nz * (st[a, SA + 2] - st[b, SA + 2]) + max(vt2, 0.0) / R)
    rad = bflt[a, B_RADIUS]
    # arm of the feature centre
    rx = c_f[c, CF_RA] + rad * nx
    ry = c_f[c, CF_RA + 1] + rad * ny
    rz = c_f[c, CF_RA + 2] + rad * nz
    wx, wy, wz = st[a, SW], st[a, SW + 1], st[a, SW + 2]
    alx, aly, alz = _free_alpha(st, a, bflt)
    acc = nx * st[a, SA] + ny * st[a, SA + 1] + nz * st[a, SA + 2]
    # n . (al x r)
    acc += nx * (aly * rz - alz * ry) + ny * (alz * rx - alx * rz) + nz * (alx * ry - aly * rx)
    # n . (w x (w x r)) = (n.w)(w.r) - (n.r)|w|^2
    acc += ((nx * wx + ny * wy + nz * wz) * (wx * rx + wy * ry + wz * rz)
            - (nx * rx + ny * ry + nz * rz) * (wx * wx + wy * wy + wz * wz))
    return acc


# ------------------------------------------------------------------ candidates


@njit(cache=True, inline="always")
def _holds(pm, i, p):
    """Is body i in persistent contact with plane p (its plane; or either plane of a
    groove, PM_WEDGED)?"""
    m = pm[i, M_MODE]
    if m == PM_FLIGHT:
        return False
    return pm[i, M_PLANE] == p or (m == PM_WEDGED and pm[i, M_FEAT] == p)


@njit(cache=True)
def _recompute_planes(i, t_now, st, tref, bint, bflt, feats, planes, pm, tz, zp, bt, bpl,
                      bft, bp_off, ws, tolf, toli, skip, pose, hrow, err):
    """Next impact time of body i (state at t_now = tref[i]) against every plane (during
    a pending accumulation jump: of its held motion, built in the scratch row ``hrow``;
    the integrator workspace is then reset, as it belongs to the free-flight row)."""
    npl = planes.shape[0]
    for p in range(npl):
        skip[p] = 0
        if bp_off[i, p] != 0 or _holds(pm, i, p) or (tz[i] < INF and zp[i] == p):
            skip[p] = 1
    S = tolf[TF_T_END] - t_now
    row = st[i]
    held = tz[i] < INF
    if held:
        zq = zp[i]
        _held_into(st[i], bint[i, B_KIND], planes[zq, 0], planes[zq, 1], planes[zq, 2], hrow)
        row = hrow
        ws[i, WS_MODE] = -1.0
    s, p, k, code = body_planes_toi(row, bint[i, B_ROT], bint[i, B_AXIS], bflt[i, B_I1],
                                    bflt[i, B_I1 + 1], bflt[i, B_I1 + 2], ws[i], feats, bint[i,
                                    B_FIRST], bint[i, B_COUNT], bflt[i, B_RADIUS], planes,
                                    skip, t_now, S, tolf[TF_TOI_RTOL], tolf[TF_TOI_ATOL],
                                    tolf[TF_GAP_TOL], toli[TI_TOI_MAXIT], tolf[TF_ROT_TOL],
                                    toli[TI_ROT_MAX_STEPS], pose)
    if held:
        ws[i, WS_MODE] = -1.0
    if code == TOI_MISSED:
        _set_err(err, t_now + s, i, -1 - p, st[i, SX], st[i, SX + 1], st[i, SX + 2], k, 0.0,
                 0.0)
        return ERR_MISSED
    if code == TOI_NOT_CONVERGED:
        _set_err(err, t_now, i, -1, st[i, SX], st[i, SX + 1], st[i, SX + 2], s, 0.0, 0.0)
        return ERR_TOI
    if code == TOI_ROT_FAILED:
        _set_err(err, t_now + s, i, -1, st[i, SX], st[i, SX + 1], st[i, SX + 2], 0.0, 0.0, 0.0)
        return ERR_ROT
    bt[i] = t_now + s
    bpl[i] = p
    bft[i] = k
    return 0


@njit(cache=True, inline="always")
def _centre_motion(st, tref, i, t, tz, zp, planes):
    """Centre of mass of body i at t: position, velocity, acceleration (9 scalars); during
    a pending accumulation jump its held motion (see ``_held_into``)."""
    s = t - tref[i]
    h = 0.5 * s * s
    v0, v1, v2 = st[i, SV], st[i, SV + 1], st[i, SV + 2]
    a0, a1, a2 = st[i, SA], st[i, SA + 1], st[i, SA + 2]
    if tz[i] < INF:
        p = zp[i]
        nx, ny, nz = planes[p, 0], planes[p, 1], planes[p, 2]
        vN = nx * v0 + ny * v1 + nz * v2
        aN = nx * a0 + ny * a1 + nz * a2
        v0, v1, v2 = v0 - vN * nx, v1 - vN * ny, v2 - vN * nz
        a0, a1, a2 = a0 - aN * nx, a1 - aN * ny, a2 - aN * nz
    return (st[i, SX] + v0 * s + a0 * h, st[i, SX + 1] + v1 * s + a1 * h,
            st[i, SX + 2] + v2 * s + a2 * h, v0 + a0 * s, v1 + a1 * s, v2 + a2 * s, a0, a1, a2)


@njit(cache=True)
def _recompute_pair(pgen, q, t_now, st, tref, bint, bflt, planes, grav, pairs, pm, tz, zp, ttr,
                    bt, pr_t, pr_off, ws, pv, pw, fw, tolf, toli, pscr, pfe, err, cid):
    """Next impact time of body pair q (states at t_now). Two spheres: closed form
    (``toi3d.sphere_sphere_toi``, over the rest of the run); right after an impact of the
    pair (``PR_HIT``) its re-contact is checked by ``decisions.pair_persistence``: impacts
    that accumulate mark the pair for persistent contact (``cid[CL_PEND]``, a cluster at
    the next pass); a pair just released from it (``PR_REL``) is searched past the
    tangency (``_released_s0``). Any other pair of shapes (``pgen``: the general pair
    switch, True, or None in a loop compiled for sphere pairs only): ``_general_pair``.
    A pair inside the cluster is its contact or candidate (no search); a pair with one
    body in a moving cluster has no closed-form motion to search (``PP_HELD``); a frozen
    cluster's bodies are at rest."""
    if pr_off[q] == PR_OFF:
        pr_t[q] = INF
        return 0
    a = pairs[q, 0]
    b = pairs[q, 1]
    ina = pm[a, M_MODE] == PM_CLUSTER
    inb = pm[b, M_MODE] == PM_CLUSTER
    if ina and inb:
        pr_t[q] = INF
        return 0
    if (ina or inb) and cid[CL_FROZEN] == 0:
        i = a if ina else b
        _set_err(err, t_now, a, b, st[i, SX], st[i, SX + 1], st[i, SX + 2], PP_HELD, float(i),
                 0.0)
        return ERR_PERSISTENT_PAIR
    if not (bint[a, B_KIND] == SH_SPHERE and bint[b, B_KIND] == SH_SPHERE):
        if pgen is None:    # pruned by type: a loop for sphere pairs compiles no pair3d code
            return _not_compiled(err, t_now, a, FEATURE_PAIR)
        return _general_pair(q, t_now, st, tref, bint, bflt, planes, grav, pairs, pm, tz, zp,
                             ttr, bt, pr_t, pr_off, ws, pv, pw, fw, tolf, toli, pscr, pfe, err)
    hit = pr_off[q] == PR_HIT
    rel = pr_off[q] == PR_REL
    pr_off[q] = PR_ON
    xa, ya, za, ua, va, wa, aa, ba, ca = _centre_motion(st, tref, a, t_now, tz, zp, planes)
    xb, yb, zb, ub, vb, wb, ab, bb, cb = _centre_motion(st, tref, b, t_now, tz, zp, planes)
    d0 = xa - xb
    d1 = ya - yb
    d2 = za - zb
    u0 = ua - ub
    u1 = va - vb
    u2 = wa - wb
    e0 = aa - ab
    e1 = ba - bb
    e2 = ca - cb
    R = bflt[a, B_RADIUS] + bflt[b, B_RADIUS]
    S = tolf[TF_T_END] - t_now
    s0 = 0.0
    if rel:
        s0 = _released_s0(d0, d1, d2, u0, u1, u2, e0, e1, e2, R, S, tolf[TF_GAP_TOL])
        h = 0.5 * s0 * s0
        d0 += u0 * s0 + e0 * h
        d1 += u1 * s0 + e1 * h
        d2 += u2 * s0 + e2 * h
        u0 += e0 * s0
        u1 += e1 * s0
        u2 += e2 * s0
    dist = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
    un = (d0 * u0 + d1 * u1 + d2 * u2) / dist
    sp = math.sqrt(ua * ua + va * va + wa * wa) + math.sqrt(ub * ub + vb * vb + wb * wb)
    v = un
    if dist - R <= tolf[TF_GAP_TOL] and un != 0.0 and touching_rate(un, sp) == 0.0:
        # touching at a normal rate that is round-off: zero (decisions.TOUCH_RTOL)
        u0 -= un * d0 / dist
        u1 -= un * d1 / dist
        u2 -= un * d2 / dist
    s, code = sphere_sphere_toi(d0, d1, d2, u0, u1, u2, e0, e1, e2, R, t_now + s0, S - s0,
                                tolf[TF_TOI_RTOL], tolf[TF_TOI_ATOL], tolf[TF_GAP_TOL],
                                toli[TI_TOI_MAXIT])
    s += s0
    if hit and code == TOI_OK and s < INF:
        # the pair's re-contact rule (stepper2d's): a re-contact within a rise of
        # rest_length (s = 0: a round-off approach left by a plastic impact) is the spheres
        # staying in contact (one contact only: no other contact of the pair to tell apart,
        # so no bound of g'')
        sp += (bflt[a, B_RADIUS] * math.sqrt(st[a, SW] ** 2 + st[a, SW + 1] ** 2
                                             + st[a, SW + 2] ** 2)
               + bflt[b, B_RADIUS] * math.sqrt(st[b, SW] ** 2 + st[b, SW + 1] ** 2
                                               + st[b, SW + 2] ** 2))
        vz = pair_zero_speed(sp, tolf[TF_SIMUL_TOL])
        if pair_persistence(v, s, True, vz, INF, tolf[TF_REST_LENGTH]) == PP_CHATTER:
            if cid[CL_PEND] < 0 or cid[CL_PEND] == q:
                cid[CL_PEND] = q
                pr_t[q] = INF
                return 0
            _set_err(err, t_now, a, b, xb + bflt[b, B_RADIUS] * d0 / dist,
                     yb + bflt[b, B_RADIUS] * d1 / dist, zb + bflt[b, B_RADIUS] * d2 / dist,
                     PP_CHATTER, v, s)
            return ERR_PERSISTENT_PAIR
    return _pair_found(q, a, b, t_now, s, code, st, pr_t, err)


@njit(cache=True)
def _released_s0(d0, d1, d2, u0, u1, u2, e0, e1, e2, R, S, gtol):
    """Offset s0 (s) from which to search a pair of spheres just released from persistent
    contact (relative centre offset d, velocity u, acceleration e at the release; R the sum
    of the radii): the first of ``REL_S0 T 2^k`` (``T = sqrt(R / |e|)``, or R / |u|) where
    the gap exceeds gap_tol and grows, at most S (``decisions.REL_S0``)."""
    ea = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
    ua = math.sqrt(u0 * u0 + u1 * u1 + u2 * u2)
    T = math.sqrt(R / ea) if ea > 0.0 else (R / ua if ua > 0.0 else S)
    s = REL_S0 * T
    for _ in range(60):
        if s >= S:
            return S
        h = 0.5 * s * s
        x0 = d0 + u0 * s + e0 * h
        x1 = d1 + u1 * s + e1 * h
        x2 = d2 + u2 * s + e2 * h
        w0 = u0 + e0 * s
        w1 = u1 + e1 * s
        w2 = u2 + e2 * s
        if (math.sqrt(x0 * x0 + x1 * x1 + x2 * x2) - R > gtol
                and x0 * w0 + x1 * w1 + x2 * w2 > 0.0):
            return s
        s *= 2.0
    return s


@njit(cache=True, inline="always")
def _pair_found(q, a, b, t_now, s, code, st, pr_t, err):
    """Store pair q's time-of-impact result ``(s, code)`` found from t_now, or the error of
    its code (``TOI_MISSED``, ``TOI_ROT_FAILED``, ``TOI_NOT_CONVERGED``)."""
    if code == TOI_MISSED:
        _set_err(err, t_now, a, b, st[a, SX], st[a, SX + 1], st[a, SX + 2], 0.0, 0.0, 0.0)
        return ERR_MISSED
    if code == TOI_ROT_FAILED:
        _set_err(err, t_now, a, -1, st[a, SX], st[a, SX + 1], st[a, SX + 2], 0.0, 0.0, 0.0)
        return ERR_ROT
    if code == TOI_NOT_CONVERGED:
        _set_err(err, t_now, a, b, st[a, SX], st[a, SX + 1], st[a, SX + 2], s, 0.0, 0.0)
        return ERR_TOI
    pr_t[q] = t_now + s
    return 0


# scratch rows of ``pscr`` (float64[N_PSCR, flight3d.N_WS]) for the general pair search
PS_A = 0        # the pair's two state rows at the search's start (flight3d layout)
PS_HELD = 2     # two rows: the held motion of a body in a pending accumulation jump;
                # then the first holds the pair's frame row (pair3d.FR_*) at the start
PS_WS = 4       # two rows: rotation-integrator workspaces of pair_toi's trajectories
PS_POSE = 6     # two rows: pair_toi's pose scratch; the first also _pair_contacts' frame
N_PSCR = 8


@njit(cache=True)
def _row_at(i, t_now, st, tref, bint, bflt, planes, tz, zp, ws, tolf, toli, held, out):
    """Body i's state row at t_now into ``out`` (float64[19]): its segment from ``tref``
    (``pose_at`` with the body's own rotation workspace, so the trajectory is the one the
    stepper replays), or the held motion of a pending accumulation jump (``_held_into``,
    through the scratch row ``held``). Returns RK_OK or the rotation integrator's code."""
    src = st[i]
    if tz[i] < INF:
        p = zp[i]
        _held_into(st[i], bint[i, B_KIND], planes[p, 0], planes[p, 1], planes[p, 2], held)
        src = held
    return pose_at(src, bint[i, B_ROT], bint[i, B_AXIS], bflt[i, B_I1], bflt[i, B_I1 + 1],
                   bflt[i, B_I1 + 2], ws[i], t_now - tref[i], tolf[TF_ROT_TOL],
                   toli[TI_ROT_MAX_STEPS], out)


@njit(cache=True)
def _general_pair(q, t_now, st, tref, bint, bflt, planes, grav, pairs, pm, tz, zp, ttr, bt,
                  pr_t, pr_off, ws, pv, pw, fw, tolf, toli, pscr, pfe, err):
    """Next impact time of pair q of any shapes but two spheres (issue 16):
    ``pair3d_toi.pair_toi`` from both bodies' rows at t_now, searched no further than the
    next scheduled event of either body (a plane impact, an accumulation point, a
    transition: that event marks the body and the pair is searched again from there; the
    rows of persistent modes are exact motions too). Right after an impact of the pair
    (``pr_off[q] == PR_HIT``) ``decisions.pair_persistence`` decides whether the bodies
    stay in contact: persistent body-body contact is not built (``ERR_PERSISTENT_PAIR``).
    A body held by an integrated contact (``PM_PIVOT``) has no closed-form motion to
    search: ``_held_pair``. A general rotation is integrated afresh from t_now by the
    search (``rot_tol``): the impact time is that trajectory's."""
    hit = pr_off[q] == PR_HIT
    pr_off[q] = PR_ON
    a = pairs[q, 0]
    b = pairs[q, 1]
    tl = tolf[TF_T_END]
    for j in range(2):
        i = a if j == 0 else b
        if t_now < tz[i] < tl:
            tl = tz[i]
        if t_now < ttr[i] < tl:
            tl = ttr[i]
        if t_now < bt[i] < tl:
            tl = bt[i]
    if pm[a, M_MODE] == PM_PIVOT or pm[b, M_MODE] == PM_PIVOT:
        return _held_pair(q, a, b, t_now, tl, st, tref, bint, bflt, planes, grav, tz, zp,
                          pr_t, pr_off, pm, pv, pw, fw, pscr, err)
    for j in range(2):
        i = a if j == 0 else b
        if _row_at(i, t_now, st, tref, bint, bflt, planes, tz, zp, ws, tolf, toli,
                   pscr[PS_HELD + j], pscr[PS_A + j]) != RK_OK:
            _set_err(err, t_now, i, -1, st[i, SX], st[i, SX + 1], st[i, SX + 2], 0.0, 0.0,
                     0.0)
            return ERR_ROT
    rA = pscr[PS_A]
    rB = pscr[PS_A + 1]
    fr = pscr[PS_HELD]      # the frame at t_now (the held rows are no longer needed)
    g0 = pair_frame(bint[a, B_KIND], bflt[a, B_RADIUS], bflt[a, B_HALF], bflt[a, B_HALF + 1],
                    bflt[a, B_HALF + 2], rA, bint[b, B_KIND], bflt[b, B_RADIUS],
                    bflt[b, B_HALF], bflt[b, B_HALF + 1], bflt[b, B_HALF + 2], rB, fr, pfe)
    v = fr[FR_RATE]
    # speed scale |v_A - v_B| + |w_A| |r_A| + |w_B| |r_B| (arms to the witness points) and
    # a bound of the contact's |g''| (decisions.pair_accel_bound)
    vs = 0.0
    va = 0.0
    vb = 0.0
    da = 0.0
    la = 0.0
    lb = 0.0
    wa = 0.0
    wb = 0.0
    aa = 0.0
    ab = 0.0
    for j in range(3):
        vs += (rA[SV + j] - rB[SV + j]) ** 2
        va += rA[SV + j] ** 2
        vb += rB[SV + j] ** 2
        da += (rA[SA + j] - rB[SA + j]) ** 2
        la += (fr[FR_PAX + j] - rA[SX + j]) ** 2
        lb += (fr[FR_PBX + j] - rB[SX + j]) ** 2
        wa += rA[SW + j] ** 2
        wb += rB[SW + j] ** 2
        aa += rA[SAL + j] ** 2
        ab += rB[SAL + j] ** 2
    la = math.sqrt(la)
    lb = math.sqrt(lb)
    wa = math.sqrt(wa)
    wb = math.sqrt(wb)
    vs = math.sqrt(vs) + wa * la + wb * lb
    vz = pair_zero_speed(math.sqrt(va) + math.sqrt(vb) + wa * la + wb * lb,
                         tolf[TF_SIMUL_TOL])
    if abs(g0) <= tolf[TF_GAP_TOL] and v != 0.0 and abs(v) <= vz:
        # touching at a normal rate that is round-off (or the joint solve's residual):
        # zero for the search (B's searched row takes it; the state keeps its velocity)
        v = 0.0
        for j in range(3):
            rB[SV + j] += fr[FR_RATE] * fr[FR_NX + j]
    s, code = pair_toi(bint[a, B_KIND], bflt[a, B_RADIUS], bflt[a, B_HALF], bflt[a, B_HALF + 1],
                       bflt[a, B_HALF + 2], rA, bint[a, B_ROT], bint[a, B_AXIS], bflt[a, B_I1],
                       bflt[a, B_I1 + 1], bflt[a, B_I1 + 2], pscr[PS_WS],
                       bint[b, B_KIND], bflt[b, B_RADIUS], bflt[b, B_HALF], bflt[b, B_HALF + 1],
                       bflt[b, B_HALF + 2], rB, bint[b, B_ROT], bint[b, B_AXIS], bflt[b, B_I1],
                       bflt[b, B_I1 + 1], bflt[b, B_I1 + 2], pscr[PS_WS + 1],
                       t_now, tl - t_now, tolf[TF_TOI_RTOL], tolf[TF_TOI_ATOL],
                       tolf[TF_GAP_TOL], toli[TI_TOI_MAXIT], tolf[TF_ROT_TOL],
                       toli[TI_ROT_MAX_STEPS], pscr[PS_POSE], pscr[PS_POSE + 1])
    if hit and code != TOI_MISSED and code != TOI_ROT_FAILED:
        G = pair_accel_bound(math.sqrt(da), math.sqrt(aa), la, math.sqrt(ab), lb, wa, wb, vs)
        why = pair_persistence(v, s, code == TOI_OK, vz, G, tolf[TF_REST_LENGTH])
        if why != 0.0:
            _set_err(err, t_now, a, b, 0.5 * (fr[FR_PAX] + fr[FR_PBX]),
                     0.5 * (fr[FR_PAX + 1] + fr[FR_PBX + 1]),
                     0.5 * (fr[FR_PAX + 2] + fr[FR_PBX + 2]), why, v, s)
            return ERR_PERSISTENT_PAIR
    return _pair_found(q, a, b, t_now, s, code, st, pr_t, err)


#: a pair with a body held by an integrated contact is searched again after HELD_CHECK
#: of the time its bounding spheres surely stay apart (dimensionless, < 1: the bound is
#: renewed from the states there), and refused when that bound's distance falls to
#: HELD_NEAR times the sum of the bounding radii (dimensionless)
HELD_CHECK = 0.5
HELD_NEAR = 1e-3


@njit(cache=True)
def _held_pair(q, a, b, t_now, tl, st, tref, bint, bflt, planes, grav, tz, zp, pr_t, pr_off,
               pm, pv, pw, fw, pscr, err):
    """Pair q with a body held by an integrated contact (``PM_PIVOT``, no closed-form
    motion to search): a distance bound. Each body stays within its bounding sphere (radius
    ``R`` = core reach + radius) about its centre, whose displacement after ``s`` is at
    most ``u s + c s^2 / 2``: a body in a closed-form row ``u = |v|``, ``c = |a|``; a held
    body ``u = sqrt(2 K / m)``, ``c = |g|`` (its kinetic energy K can only grow by the work
    of gravity, ``dK/dt <= m |g| |v| <= m |g| sqrt(2 K / m)``, so ``sqrt(2 K / m)`` grows by at
    most ``|g| s``; the plane's normal force does no work and friction only dissipates). If
    the spheres stay apart until ``tl`` (either body's next event, where the pair is
    searched again) nothing is due; else the pair is checked again (``PR_CHECK``) at
    ``HELD_CHECK`` of that time, and refused by name (``PP_HELD``: persistent or integrated
    contact with a partner is not built) when the spheres come within ``HELD_NEAR`` of
    each other."""
    d0 = 0.0
    u = 0.0
    c = 0.0
    R = 0.0
    g = math.sqrt(grav[0] * grav[0] + grav[1] * grav[1] + grav[2] * grav[2])
    for j in range(2):
        i = a if j == 0 else b
        R += bflt[i, B_RADIUS] + body_reach(bint[i, B_KIND], bflt[i, B_HALF],
                                            bflt[i, B_HALF + 1], bflt[i, B_HALF + 2])
        row = pscr[PS_A + j]
        if pm[i, M_MODE] == PM_PIVOT:
            rc = pivot_eval(pw[i], pv[i], fw, t_now - tref[i], row)
            if rc != PI_OK:
                _set_err(err, t_now, i, -1 - int(pv[i, CP_PLANE]), st[i, SX], st[i, SX + 1],
                         st[i, SX + 2], pw[i, PW_WHY], pv[i, CP_MU], pv[i, CP_K])
                return ERR_CONTACT_STEPS if rc == PI_TOO_MANY_STEPS else ERR_PAINLEVE
            bx, by, bz = qrot_inv(row[3], row[4], row[5], row[6], row[10], row[11], row[12])
            K = (bflt[i, B_MASS] * (row[7] * row[7] + row[8] * row[8] + row[9] * row[9])
                 + bflt[i, B_I1] * bx * bx + bflt[i, B_I1 + 1] * by * by
                 + bflt[i, B_I1 + 2] * bz * bz)         # twice the kinetic energy
            u += math.sqrt(K / bflt[i, B_MASS])
            c += g
        else:
            x0, x1, x2, v0, v1, v2, a0, a1, a2 = _centre_motion(st, tref, i, t_now, tz, zp,
                                                                planes)
            row[0] = x0
            row[1] = x1
            row[2] = x2
            u += math.sqrt(v0 * v0 + v1 * v1 + v2 * v2)
            c += math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
    dx = pscr[PS_A, 0] - pscr[PS_A + 1, 0]
    dy = pscr[PS_A, 1] - pscr[PS_A + 1, 1]
    dz = pscr[PS_A, 2] - pscr[PS_A + 1, 2]
    d0 = math.sqrt(dx * dx + dy * dy + dz * dz) - R
    if not d0 > HELD_NEAR * R:
        i = a if pm[a, M_MODE] == PM_PIVOT else b
        _set_err(err, t_now, a, b, st[i, SX], st[i, SX + 1], st[i, SX + 2], PP_HELD,
                 float(i), 0.0)
        return ERR_PERSISTENT_PAIR
    # the first s >= 0 with u s + c s^2 / 2 = d0 (cancellation-free root)
    s = 2.0 * d0 / (u + math.sqrt(u * u + 2.0 * c * d0)) if u + c > 0.0 else INF
    if t_now + s >= tl:
        pr_t[q] = INF
    else:
        pr_t[q] = t_now + HELD_CHECK * s
        pr_off[q] = PR_CHECK
    return 0


@njit(cache=True)
def _pair_contacts(q, nc, t, st, bint, bflt, pairs, ws, tolf, toli, c_i, c_f, pscr, pmf, pfe,
                   err):
    """The contact rows of pair q of any shapes but two spheres (bodies at t) from
    ``nc`` on: the points of ``pair3d_manifold.pair_manifold`` (a face, an edge or a
    capsule lying on a face, capsules side by side: up to ``MAX_MF`` points with one
    normal, within its slab ``manifold_slab``, ``SLAB_REL`` of the bodies' sizes; else the
    witness pair), each with the normal from B into A and each body's arm to its own
    point, so that ``W`` and ``v`` are those of the pair's frame. When the frame's single
    contact separates, the pair's impact is another contact tied with it to round-off
    (the far end of an edge just resolved: the search found it ``1e-17`` s later, the same
    instant in floating point): it is the frame of the bodies' rows ``simul_time`` later,
    where it is the deeper (the impact cluster's own time window). Returns the new number
    of contacts (or an error code)."""
    a = pairs[q, 0]
    b = pairs[q, 1]
    kA = bint[a, B_KIND]
    kB = bint[b, B_KIND]
    slab = manifold_slab(kA, bflt[a, B_RADIUS], bflt[a, B_HALF], bflt[a, B_HALF + 1],
                         bflt[a, B_HALF + 2], kB, bflt[b, B_RADIUS], bflt[b, B_HALF],
                         bflt[b, B_HALF + 1], bflt[b, B_HALF + 2])
    fr = pscr[PS_POSE]
    m = pair_manifold(kA, bflt[a, B_RADIUS], bflt[a, B_HALF], bflt[a, B_HALF + 1],
                      bflt[a, B_HALF + 2], st[a], kB, bflt[b, B_RADIUS], bflt[b, B_HALF],
                      bflt[b, B_HALF + 1], bflt[b, B_HALF + 2], st[b], slab, fr, pfe, pmf)
    nx = fr[FR_NX]
    ny = fr[FR_NX + 1]
    nz = fr[FR_NX + 2]
    if m < 1 or not (math.isfinite(nx) and math.isfinite(ny) and math.isfinite(nz)):
        _set_err(err, t, a, b, st[a, SX], st[a, SX + 1], st[a, SX + 2], 0.0, 0.0, 0.0)
        return ERR_NONFINITE
    ca = st[a]
    cb = st[b]
    if m == 1 and fr[FR_RATE] >= 0.0:
        for j in range(2):
            i = a if j == 0 else b
            if pose_at(st[i], bint[i, B_ROT], bint[i, B_AXIS], bflt[i, B_I1],
                       bflt[i, B_I1 + 1], bflt[i, B_I1 + 2], ws[i], tolf[TF_SIMUL_TIME],
                       tolf[TF_ROT_TOL], toli[TI_ROT_MAX_STEPS], pscr[PS_A + j]) != RK_OK:
                _set_err(err, t, i, -1, st[i, SX], st[i, SX + 1], st[i, SX + 2], 0.0, 0.0,
                         0.0)
                return ERR_ROT
        f2 = pscr[PS_HELD]
        pair_frame(kA, bflt[a, B_RADIUS], bflt[a, B_HALF], bflt[a, B_HALF + 1],
                   bflt[a, B_HALF + 2], pscr[PS_A], kB, bflt[b, B_RADIUS], bflt[b, B_HALF],
                   bflt[b, B_HALF + 1], bflt[b, B_HALF + 2], pscr[PS_A + 1], f2, pfe)
        if f2[FR_RATE] < 0.0:
            ca = pscr[PS_A]
            cb = pscr[PS_A + 1]
            nx = f2[FR_NX]
            ny = f2[FR_NX + 1]
            nz = f2[FR_NX + 2]
            for j in range(3):
                pmf[0, MF_PAX + j] = f2[FR_PAX + j]
                pmf[0, MF_PBX + j] = f2[FR_PBX + j]
    for k in range(m):
        if nc >= MAXC - 1:
            _set_err(err, t, a, b, st[a, SX], st[a, SX + 1], st[a, SX + 2], MAXC - 1, 0.0,
                     0.0)
            return ERR_TOO_MANY
        c_i[nc, CI_TYPE] = 1
        c_i[nc, CI_A] = a
        c_i[nc, CI_B] = b
        c_i[nc, CI_FEAT] = -1
        c_i[nc, CI_LAW] = pairs[q, 2]
        c_i[nc, CI_OFF] = 0
        _frame(c_f, nc, nx, ny, nz)
        for j in range(3):
            c_f[nc, CF_RA + j] = pmf[k, MF_PAX + j] - ca[SX + j]
            c_f[nc, CF_RB + j] = pmf[k, MF_PBX + j] - cb[SX + j]
            c_f[nc, CF_P + j] = st[a, SX + j] + c_f[nc, CF_RA + j]
        nc += 1
    return nc


# ------------------------------------------------------------------ integrated point/edge contact


@njit(cache=True)
def _recompute_pivot(i, t_now, st, bint, planes, feats, bp_off, bt, ttr, pk, pv, pw, fw,
                     tolf, toli, skip, ybuf, vals, vals0, vfl, err):
    """Next event of body i in integrated point/edge contact (state at t_now)."""
    bt[i] = INF
    for p in range(planes.shape[0]):
        skip[p] = 1 if bp_off[i, p] != 0 else 0
    pivot_start(pw[i], st[i], pv[i], tolf[TF_CONTACT_TOL], toli[TI_ROT_MAX_STEPS])
    S = tolf[TF_T_END] - t_now
    s, kind, idx, code = pivot_next_event(pw[i], pv[i], fw, feats, bint[i, B_FIRST], bint[i,
                                          B_COUNT], planes, skip, S, t_now, tolf[TF_TOI_RTOL],
                                          tolf[TF_TOI_ATOL], ybuf, vals, vals0, vfl)
    if (code == PI_FORCES and pw[i, PW_WHY] == PV_PAINLEVE and pv[i, CP_K] == 1.0
            and pv[i, CP_S] == 0.0 and tolf[TF_PAINLEVE] == PAINLEVE_IMPACT):
        # the slide runs into a Painleve jam: an impact without collision there (PE_JAM;
        # the state where the step gave up is kept, pivot_eval would not reach past it)
        for j in range(13):
            pw[i, PW_JAM + j] = pw[i, PW_Y + j]
        ttr[i] = t_now + s
        pk[i, 0] = PE_JAM
        pk[i, 1] = 0
        return 0
    if code != PI_OK:
        # the force system failed inside the phase: say why (pivot_forces' PV_* code) at
        # the state where it failed (a sliding contact's normal-force coefficient reaching
        # 0 on the way is the Painleve paradox)
        _set_err(err, t_now + pw[i, PW_S0], i, -1 - int(pv[i, CP_PLANE]), pw[i, PW_Y + SX],
                 pw[i, PW_Y + SX + 1], pw[i, PW_Y + SX + 2], pw[i, PW_WHY], pv[i, CP_MU],
                 pv[i, CP_K])
        return ERR_CONTACT_STEPS if code == PI_TOO_MANY_STEPS else ERR_PAINLEVE
    if kind == PE_NONE:
        ttr[i] = INF
    else:
        ttr[i] = t_now + s
    pk[i, 0] = kind
    pk[i, 1] = idx
    return 0


@njit(cache=True)
def _recompute_motion(i, t_now, st, tref, bint, bflt, feats, planes, pm, tz, zp, bt, bpl, bft,
                      bp_off, ws, tolf, toli, skip, pose, err, ttr, pk, pv, pw, fw, ybuf, vals,
                      vals0, vfl, hrow, pivot):
    """The candidate events of body i's own motion (state at t_now): its planes, or its
    integrated contact's events (none for a cluster member: its cluster's). ``pivot``:
    feature switch."""
    if pm[i, M_MODE] == PM_CLUSTER:
        bt[i] = INF
        return 0
    if pm[i, M_MODE] == PM_PIVOT:
        if pivot is None:
            return _not_compiled(err, t_now, i, FEATURE_PIVOT)
        return _recompute_pivot(i, t_now, st, bint, planes, feats, bp_off, bt, ttr, pk, pv,
                                pw, fw, tolf, toli, skip, ybuf, vals, vals0, vfl, err)
    return _recompute_planes(i, t_now, st, tref, bint, bflt, feats, planes, pm, tz, zp, bt,
                             bpl, bft, bp_off, ws, tolf, toli, skip, pose, hrow, err)


@njit(cache=True)
def _recompute_pairs(t_now, st, tref, bint, bflt, planes, grav, pairs, pm, tz, zp, ttr, bt,
                     pr_t, pr_off, ws, pv, pw, fw, tolf, toli, pscr, pfe, bmark, err, pair,
                     pgen, cid):
    """Recompute every pair with a marked body (``bmark``), after the planes of every
    marked body (a general pair's search stops at either body's next scheduled event).
    ``pair``, ``pgen``: feature switches (any pair; pairs of other shapes than spheres)."""
    for q in range(pairs.shape[0]):
        if bmark[pairs[q, 0]] == 0 and bmark[pairs[q, 1]] == 0:
            continue
        if pair is None:
            return _not_compiled(err, t_now, pairs[q, 0], FEATURE_PAIR)
        rc = _recompute_pair(pgen, q, t_now, st, tref, bint, bflt, planes, grav, pairs, pm, tz,
                             zp, ttr, bt, pr_t, pr_off, ws, pv, pw, fw, tolf, toli, pscr, pfe,
                             err, cid)
        if rc < 0:
            return rc
    return 0


@njit(cache=True, inline="always")
def _pv_arm(st, i, pv, k):
    """Arm (contact point minus centre of mass) of integrated contact k of body i."""
    po = CP_P + 3 * k
    sx, sy, sz = qrot(st[i, SQ], st[i, SQ + 1], st[i, SQ + 2], st[i, SQ + 3], pv[i, po], pv[i,
                      po + 1], pv[i, po + 2])
    rad = pv[i, CP_RAD]
    nx, ny, nz = contact_normal(pv[i], k)
    return (sx - rad * nx, sy - rad * ny, sz - rad * nz)


@njit(cache=True)
def _pv_frame(c_f, cw, st, i, pv, k):
    """Frame row cw: the frame of contact k's plane at integrated contact k of body i."""
    rx, ry, rz = _pv_arm(st, i, pv, k)
    nx, ny, nz = contact_normal(pv[i], k)
    _frame(c_f, cw, nx, ny, nz)
    c_f[cw, CF_RA] = rx
    c_f[cw, CF_RA + 1] = ry
    c_f[cw, CF_RA + 2] = rz
    for j in range(3):
        c_f[cw, CF_P + j] = st[i, j] + c_f[cw, CF_RA + j]
        c_f[cw, CF_RB + j] = 0.0


@njit(cache=True)
def _pv_drop(pv, i, k):
    """Remove integrated contact k of body i (the later ones move down one slot)."""
    K = int(pv[i, CP_K])
    for c in range(k, K - 1):
        for j in range(3):
            pv[i, CP_P + 3 * c + j] = pv[i, CP_P + 3 * c + 3 + j]
            pv[i, CP_U + 3 * c + j] = pv[i, CP_U + 3 * c + 3 + j]
            pv[i, CP_N + 3 * c + j] = pv[i, CP_N + 3 * c + 3 + j]
        pv[i, CP_D + c] = pv[i, CP_D + c + 1]
        pv[i, CP_MU + c] = pv[i, CP_MU + c + 1]
        pv[i, CP_PLANE + c] = pv[i, CP_PLANE + c + 1]
        pv[i, CP_S + c] = pv[i, CP_S + c + 1]
        pv[i, CP_F + c] = pv[i, CP_F + c + 1]
    pv[i, CP_K] = K - 1


@njit(cache=True, inline="always")
def _pv_sticking(pv, i):
    """(number of sticking integrated contacts of body i, first, second) (-1: none)."""
    n = 0
    ka = -1
    kb = -1
    for k in range(int(pv[i, CP_K])):
        if pv[i, CP_S + k] == 1.0:
            n += 1
            if ka < 0:
                ka = k
            elif kb < 0:
                kb = k
    return n, ka, kb


@njit(cache=True, inline="always")
def _pv_tangential_accel(st, i, pv, fw, k):
    """Tangential part (m/s^2) of integrated contact k's acceleration under the forces in
    fw (``pivot_forces``)."""
    nx, ny, nz = contact_normal(pv[i], k)
    ax, ay, az = contact_accel(st[i], fw, k)
    an = ax * nx + ay * ny + az * nz
    return ax - an * nx, ay - an * ny, az - an * nz


@njit(cache=True)
def _slip_F(st, i, pv, k, fw, phi, t1x, t1y, t1z, t2x, t2y, t2z):
    """For contact k sliding along u(phi) (the others as they are): (F, D, lam) with
    F = n . (u x a_T), D = u . a_T the slip's acceleration across and along u and lam the
    normal force."""
    c = math.cos(phi)
    s = math.sin(phi)
    ux = c * t1x + s * t2x
    uy = c * t1y + s * t2y
    uz = c * t1z + s * t2z
    uo = CP_U + 3 * k
    pv[i, uo] = ux
    pv[i, uo + 1] = uy
    pv[i, uo + 2] = uz
    rc = pivot_forces(st[i], pv[i], fw)
    if rc != PV_OK:
        return 0.0, -math.inf, -1.0
    nx, ny, nz = contact_normal(pv[i], k)
    ax, ay, az = _pv_tangential_accel(st, i, pv, fw, k)
    F = nx * (uy * az - uz * ay) + ny * (uz * ax - ux * az) + nz * (ux * ay - uy * ax)
    D = ux * ax + uy * ay + uz * az
    return F, D, fw[FW_LAM + k]


@njit(cache=True)
def _pv_slide(st, i, pv, k, fw):
    """Contact k starts sliding: in the consistent direction u (the slip's acceleration
    a_T is along +u: ``u x a_T = 0``, ``u . a_T > SLIP_ACC_TOL |g|``, with a positive
    normal force), the one closest to the direction opposite to the tangential part of
    its current (sticking) force; failing that, a continuous onset (``SLIP_ONSET_ANGLE``).
    When no direction is consistent, the contact is set back to sticking and False is
    returned (fw is then stale)."""
    nx, ny, nz = contact_normal(pv[i], k)
    fo = FW_F + 3 * k
    lam = fw[FW_LAM + k]
    fx = fw[fo] - lam * nx
    fy = fw[fo + 1] - lam * ny
    fz = fw[fo + 2] - lam * nz
    f = math.sqrt(fx * fx + fy * fy + fz * fz)
    t1x, t1y, t1z, t2x, t2y, t2z = tangent_basis(nx, ny, nz)
    if f > 0.0:
        phi0 = math.atan2(-(fx * t2x + fy * t2y + fz * t2z), -(fx * t1x + fy * t1y + fz * t1z))
    else:
        phi0 = 0.0
    pv[i, CP_S + k] = 0.0
    gsc = SLIP_ACC_TOL * math.sqrt(pv[i, CP_G] ** 2 + pv[i, CP_G + 1] ** 2
                                   + pv[i, CP_G + 2] ** 2)
    best = math.inf
    bphi = phi0
    onset = math.inf                # the continuous onset (SLIP_ONSET_ANGLE) as a fallback
    ophi = phi0
    dphi = 2.0 * math.pi / N_SLIP_SCAN
    # the scan starts at phi0, where a continuous onset's root lies (F(phi0) is zero up to
    # round-off, exactly zero in a symmetric scene) and closes on the same value: the
    # angle phi0 + 2 pi, evaluated again, can give F of the other sign by round-off, and
    # the root would then be in no bracket (a capsule falling over, its end starting to
    # slip: "no consistent stick/slip/lift-off state")
    F0, D0, L0 = _slip_F(st, i, pv, k, fw, phi0, t1x, t1y, t1z, t2x, t2y, t2z)
    Fa = F0
    pa = phi0
    for j in range(1, N_SLIP_SCAN + 1):
        pb = phi0 + j * dphi
        if j < N_SLIP_SCAN:
            Fb, Db, Lb = _slip_F(st, i, pv, k, fw, pb, t1x, t1y, t1z, t2x, t2y, t2z)
        else:
            Fb = F0
        if Fa == 0.0:
            r = pa          # a root at the bracket's end (not a sign change to bisect)
        elif Fb != 0.0 and (Fa > 0.0) != (Fb > 0.0):
            # bisection keeping F(lo) of Fa's sign (F(hi) of the other, or zero); a zero
            # Fb is the next bracket's Fa == 0 root
            pos = Fa > 0.0
            lo = pa
            hi = pb
            for it in range(60):
                mid = 0.5 * (lo + hi)
                Fm, Dm, Lm = _slip_F(st, i, pv, k, fw, mid, t1x, t1y, t1z, t2x, t2y, t2z)
                if Fm == 0.0:
                    lo = mid
                    hi = mid
                    break
                if (Fm > 0.0) == pos:
                    lo = mid
                else:
                    hi = mid
            r = 0.5 * (lo + hi)
        else:
            r = math.nan
        if r == r:
            Fr, Dr, Lr = _slip_F(st, i, pv, k, fw, r, t1x, t1y, t1z, t2x, t2y, t2z)
            d = abs(math.atan2(math.sin(r - phi0), math.cos(r - phi0)))
            if Dr > gsc and Lr > 0.0:
                if d < best:
                    best = d
                    bphi = r
            elif Dr > -gsc and Lr > 0.0 and d <= SLIP_ONSET_ANGLE and d < onset:
                onset = d
                ophi = r
        pa = pb
        Fa = Fb
    if best == math.inf and onset < math.inf:
        best = onset
        bphi = ophi
    if best == math.inf:
        pv[i, CP_S + k] = 1.0
        return False
    _slip_F(st, i, pv, k, fw, bphi, t1x, t1y, t1z, t2x, t2y, t2z)
    return True


@njit(cache=True)
def _pv_stick_edge(st, i, bflt, pv, ka, kb):
    """Integrated contacts ka and kb of body i stick: the body may only turn about the
    axis ``a`` through their two contact points. Its velocity becomes the kinetic-energy-metric
    projection of the current one onto that motion -- the result of the impulses at the
    two points that zero both contact velocities (the impulsive constraint keeps the
    angular momentum about the axis): ``w = s a``, ``v = -s a x r_1``,
    ``s = (m (r_1 x a) . v + a . I_w w) / (m |a x r_1|^2 + a . I_w a)`` (``r_1`` the arm
    of contact 1). Sticking one contact by a single-point impulse left the other with a
    slip of up to ``slip_eps``, which the sticking forces then kept (zero acceleration)
    and worked on. When that turn moves another held contact along its normal (by more
    than ``STILL_LINE_RTOL`` of the body's size per radian), the contact blocks it: the
    body stops, and that contact sticks if it has friction (3:1137567058: a capsule on
    both caps against a wall kept a turn into the wall, 8e-7 m/s, and went 6e-6 m
    through it while its forces held the gap's acceleration at zero)."""
    ax, ay, az = _pv_arm(st, i, pv, ka)
    bx, by, bz = _pv_arm(st, i, pv, kb)
    dx = bx - ax
    dy = by - ay
    dz = bz - az
    dl = math.sqrt(dx * dx + dy * dy + dz * dz)
    if not dl > 0.0:
        return      # one point held twice: _persist_candidates never enters this
    dx /= dl
    dy /= dl
    dz /= dl
    # xi = (-(a x r1), a): the unit twist about the axis through contact 1
    ex = -(dy * az - dz * ay)
    ey = -(dz * ax - dx * az)
    ez = -(dx * ay - dy * ax)
    q0, q1, q2, q3 = st[i, SQ], st[i, SQ + 1], st[i, SQ + 2], st[i, SQ + 3]
    # a and w in the body frame, where I_w is diag(I1, I2, I3)
    a0, a1, a2 = qrot_inv(q0, q1, q2, q3, dx, dy, dz)
    w0, w1, w2 = qrot_inv(q0, q1, q2, q3, st[i, SW], st[i, SW + 1], st[i, SW + 2])
    I1 = bflt[i, B_I1]
    I2 = bflt[i, B_I1 + 1]
    I3 = bflt[i, B_I1 + 2]
    m = bflt[i, B_MASS]
    num = (m * (ex * st[i, SV] + ey * st[i, SV + 1] + ez * st[i, SV + 2])
           + I1 * a0 * w0 + I2 * a1 * w1 + I3 * a2 * w2)
    den = m * (ex * ex + ey * ey + ez * ez) + I1 * a0 * a0 + I2 * a1 * a1 + I3 * a2 * a2
    sp = num / den
    blocked = False
    for c in range(int(pv[i, CP_K])):
        if c == ka or c == kb:
            continue
        # the normal speed of contact c per unit turn: n_c . (a x (r_c - r_1)) (m)
        cx, cy, cz = _pv_arm(st, i, pv, c)
        nx, ny, nz = contact_normal(pv[i], c)
        rx = cx - ax
        ry = cy - ay
        rz = cz - az
        g = nx * (dy * rz - dz * ry) + ny * (dz * rx - dx * rz) + nz * (dx * ry - dy * rx)
        if abs(g) > STILL_LINE_RTOL * pv[i, CP_L]:
            blocked = True
            if contact_mu(pv[i], c) > 0.0:
                pv[i, CP_S + c] = 1.0
    if blocked:
        sp = 0.0
    st[i, SV] = sp * ex
    st[i, SV + 1] = sp * ey
    st[i, SV + 2] = sp * ez
    st[i, SW] = sp * dx
    st[i, SW + 1] = sp * dy
    st[i, SW + 2] = sp * dz


@njit(cache=True)
def _pv_w(st, i, bflt, c_f, cw, Ii):
    """Delassus matrix W (1/kg) of body i alone at the contact frame c_f[cw] (arm CF_RA,
    axes N, T1, T2): ``W = I_3 / m + [r]^T I^-1 [r]`` (DESIGN §3), as (w00, w01, w02, w11,
    w12, w22); Ii receives the world inverse inertia."""
    _iinv(st, i, bflt, Ii)
    m = bflt[i, B_MASS]
    w00 = 1.0 / m
    w11 = 1.0 / m
    w22 = 1.0 / m
    w01 = 0.0
    w02 = 0.0
    w12 = 0.0
    a0, a1, a2 = _arm_cross(c_f, cw, CF_RA, 0)
    b0, b1, b2 = _arm_cross(c_f, cw, CF_RA, 1)
    d0, d1, d2 = _arm_cross(c_f, cw, CF_RA, 2)
    ia0 = Ii[0, 0] * a0 + Ii[0, 1] * a1 + Ii[0, 2] * a2
    ia1 = Ii[1, 0] * a0 + Ii[1, 1] * a1 + Ii[1, 2] * a2
    ia2 = Ii[2, 0] * a0 + Ii[2, 1] * a1 + Ii[2, 2] * a2
    ib0 = Ii[0, 0] * b0 + Ii[0, 1] * b1 + Ii[0, 2] * b2
    ib1 = Ii[1, 0] * b0 + Ii[1, 1] * b1 + Ii[1, 2] * b2
    ib2 = Ii[2, 0] * b0 + Ii[2, 1] * b1 + Ii[2, 2] * b2
    id0 = Ii[0, 0] * d0 + Ii[0, 1] * d1 + Ii[0, 2] * d2
    id1 = Ii[1, 0] * d0 + Ii[1, 1] * d1 + Ii[1, 2] * d2
    id2 = Ii[2, 0] * d0 + Ii[2, 1] * d1 + Ii[2, 2] * d2
    w00 += a0 * ia0 + a1 * ia1 + a2 * ia2
    w01 += a0 * ib0 + a1 * ib1 + a2 * ib2
    w02 += a0 * id0 + a1 * id1 + a2 * id2
    w11 += b0 * ib0 + b1 * ib1 + b2 * ib2
    w12 += b0 * id0 + b1 * id1 + b2 * id2
    w22 += d0 * id0 + d1 * id1 + d2 * id2
    return w00, w01, w02, w11, w12, w22


@njit(cache=True)
def _pv_unslip(st, i, bflt, pv, k, c_f, cw, Ii):
    """Remove the slip (and any normal velocity) of integrated contact k of body i by an
    impulse at that contact (W P = -v), then zero the normal velocities of all the
    integrated contacts again (the impulse couples into the others). When one other
    contact sticks, both contact velocities are zeroed together (``_pv_stick_edge``); when
    two or more others stick, the body is held still (``_pv_still``)."""
    nst = 0
    ko = -1
    for c in range(int(pv[i, CP_K])):
        if c != k and pv[i, CP_S + c] == 1.0:
            nst += 1
            ko = c
    if nst >= 2:
        _pv_still(st, i, bflt, pv, k)
        return
    if nst == 1:
        _pv_stick_edge(st, i, bflt, pv, min(k, ko), max(k, ko))
        return
    _pv_frame(c_f, cw, st, i, pv, k)
    v0, v1, v2 = _contact_velocity_row(st, i, c_f, cw)
    w00, w01, w02, w11, w12, w22 = _pv_w(st, i, bflt, c_f, cw, Ii)
    # W P = -v, backward stable (a single body's W is SPD: ok is always True here)
    _spd, p0, p1, p2 = spd3_solve(w00, w01, w02, w11, w12, w22, -v0, -v1, -v2)
    jx = p0 * c_f[cw, CF_N] + p1 * c_f[cw, CF_T1] + p2 * c_f[cw, CF_T2]
    jy = p0 * c_f[cw, CF_N + 1] + p1 * c_f[cw, CF_T1 + 1] + p2 * c_f[cw, CF_T2 + 1]
    jz = p0 * c_f[cw, CF_N + 2] + p1 * c_f[cw, CF_T1 + 2] + p2 * c_f[cw, CF_T2 + 2]
    _apply_body(st, bflt, i, c_f[cw, CF_RA], c_f[cw, CF_RA + 1], c_f[cw, CF_RA + 2], jx, jy,
                jz, Ii)
    if pv[i, CP_K] >= 2.0:
        _pv_zero_normals(st, i, bflt, pv, Ii)


@njit(cache=True)
def _pv_still(st, i, bflt, pv, k):
    """Contact k of body i sticks while two or more of its other integrated contacts
    stick: three sticking points not on one line leave the body no motion, so the
    impulses that zero their contact velocities stop it (v = w = 0; kinetic energy
    removed, none created). Points on one line (within ``STILL_LINE_RTOL`` of the body's
    size) leave the turn about that line (``_pv_stick_edge`` on the two farthest)."""
    K = int(pv[i, CP_K])
    best = 0.0
    ka = -1
    kb = -1
    for a in range(K):
        if a != k and pv[i, CP_S + a] != 1.0:
            continue
        ax, ay, az = _pv_arm(st, i, pv, a)
        for b in range(a + 1, K):
            if b != k and pv[i, CP_S + b] != 1.0:
                continue
            bx, by, bz = _pv_arm(st, i, pv, b)
            d = (bx - ax) ** 2 + (by - ay) ** 2 + (bz - az) ** 2
            if d > best:
                best = d
                ka = a
                kb = b
    ax, ay, az = _pv_arm(st, i, pv, ka)
    bx, by, bz = _pv_arm(st, i, pv, kb)
    dx = bx - ax
    dy = by - ay
    dz = bz - az
    off = 0.0       # the largest distance of another sticking point from the line ka-kb
    for c in range(K):
        if c == ka or c == kb or (c != k and pv[i, CP_S + c] != 1.0):
            continue
        cx, cy, cz = _pv_arm(st, i, pv, c)
        ex = cx - ax
        ey = cy - ay
        ez = cz - az
        px = ey * dz - ez * dy
        py = ez * dx - ex * dz
        pz = ex * dy - ey * dx
        off = max(off, math.sqrt((px * px + py * py + pz * pz) / best))
    if off <= STILL_LINE_RTOL * pv[i, CP_L]:
        _pv_stick_edge(st, i, bflt, pv, ka, kb)
        return
    for j in range(3):
        st[i, SV + j] = 0.0
        st[i, SW + j] = 0.0


@njit(cache=True)
def _pv_zero_normals(st, i, bflt, pv, Ii):
    """Normal impulses at the integrated contacts of body i (each along its own plane's
    normal ``n_k``) making their normal velocities zero (W_NN dP = -v_N, K x K, with
    ``W_kl = n_k . n_l / m + (r_k x n_k) . I^-1 (r_l x n_l)``); K = 1, 2 in closed form,
    three or more by ``_pv_zero_normals_many``."""
    nx, ny, nz = contact_normal(pv[i], 0)
    m = bflt[i, B_MASS]
    K = int(pv[i, CP_K])
    _iinv(st, i, bflt, Ii)
    if K >= 3:
        _pv_zero_normals_many(st, i, bflt, pv, Ii, K)
        return
    ax, ay, az = _pv_arm(st, i, pv, 0)
    cx1 = ay * nz - az * ny
    cy1 = az * nx - ax * nz
    cz1 = ax * ny - ay * nx
    u1x, u1y, u1z = _point_vel(st, i, ax, ay, az)
    v1n = u1x * nx + u1y * ny + u1z * nz
    i1x = Ii[0, 0] * cx1 + Ii[0, 1] * cy1 + Ii[0, 2] * cz1
    i1y = Ii[1, 0] * cx1 + Ii[1, 1] * cy1 + Ii[1, 2] * cz1
    i1z = Ii[2, 0] * cx1 + Ii[2, 1] * cy1 + Ii[2, 2] * cz1
    w11 = 1.0 / m + cx1 * i1x + cy1 * i1y + cz1 * i1z
    if K == 1:
        d1 = -v1n / w11
        _apply_body(st, bflt, i, ax, ay, az, d1 * nx, d1 * ny, d1 * nz, Ii)
        return
    mx, my, mz = contact_normal(pv[i], 1)
    bx, by, bz = _pv_arm(st, i, pv, 1)
    cx2 = by * mz - bz * my
    cy2 = bz * mx - bx * mz
    cz2 = bx * my - by * mx
    u2x, u2y, u2z = _point_vel(st, i, bx, by, bz)
    v2n = u2x * mx + u2y * my + u2z * mz
    w12 = (nx * mx + ny * my + nz * mz) / m + cx2 * i1x + cy2 * i1y + cz2 * i1z
    i2x = Ii[0, 0] * cx2 + Ii[0, 1] * cy2 + Ii[0, 2] * cz2
    i2y = Ii[1, 0] * cx2 + Ii[1, 1] * cy2 + Ii[1, 2] * cz2
    i2z = Ii[2, 0] * cx2 + Ii[2, 1] * cy2 + Ii[2, 2] * cz2
    w22 = 1.0 / m + cx2 * i2x + cy2 * i2y + cz2 * i2z
    det = w11 * w22 - w12 * w12
    if abs(det) > 1e-12 * w11 * w22:
        d1 = -(w22 * v1n - w12 * v2n) / det
        d2 = -(w11 * v2n - w12 * v1n) / det
    else:
        d1 = -0.5 * (v1n + v2n) / w11
        d2 = d1
    _apply_body(st, bflt, i, ax, ay, az, d1 * nx, d1 * ny, d1 * nz, Ii)
    _apply_body(st, bflt, i, bx, by, bz, d2 * mx, d2 * my, d2 * mz, Ii)


@njit(cache=True, inline="always")
def _pv_normal_moment(st, i, pv, k):
    """Integrated contact k of body i: its normal n, arm r and normal moment r x n."""
    nx, ny, nz = contact_normal(pv[i], k)
    ax, ay, az = _pv_arm(st, i, pv, k)
    return nx, ny, nz, ax, ay, az, ay * nz - az * ny, az * nx - ax * nz, ax * ny - ay * nx


@njit(cache=True)
def _pv_zero_normals_many(st, i, bflt, pv, Ii, K):
    """``_pv_zero_normals`` for K >= 3 contacts (``Ii`` already the world inverse inertia):
    W_NN dP = -v_N by the minimum-norm solve (``minnorm``, ``ZERO_NORMALS_RTOL``:
    dependent contacts share their impulse). Allocates its K x K workspace (an entry into
    or a change of a held motion at three or more points, not the integration)."""
    m = bflt[i, B_MASS]
    w = np.zeros(4 * K * K + 2 * K)
    A = 0
    r = K * K
    x = r + K
    u = x + K
    v = u + K * K
    for a in range(K):
        nx, ny, nz, ax, ay, az, cx, cy, cz = _pv_normal_moment(st, i, pv, a)
        ux, uy, uz = _point_vel(st, i, ax, ay, az)
        w[r + a] = -(ux * nx + uy * ny + uz * nz)
        ix = Ii[0, 0] * cx + Ii[0, 1] * cy + Ii[0, 2] * cz
        iy = Ii[1, 0] * cx + Ii[1, 1] * cy + Ii[1, 2] * cz
        iz = Ii[2, 0] * cx + Ii[2, 1] * cy + Ii[2, 2] * cz
        for b in range(K):
            mx, my, mz, bx, by, bz, dx, dy, dz = _pv_normal_moment(st, i, pv, b)
            w[A + K * a + b] = (nx * mx + ny * my + nz * mz) / m + dx * ix + dy * iy + dz * iz
    minnorm_solve(w, A, r, x, u, v, K, K, ZERO_NORMALS_RTOL, ZERO_NORMALS_SWEEPS)
    for a in range(K):
        nx, ny, nz = contact_normal(pv[i], a)
        ax, ay, az = _pv_arm(st, i, pv, a)
        d = w[x + a]
        _apply_body(st, bflt, i, ax, ay, az, d * nx, d * ny, d * nz, Ii)


@njit(cache=True)
def _pv_stick_slowest(st, i, bflt, pv, c_f, cw, Ii, vmax):
    """Stick the sliding integrated contact of body i with the smallest slip speed, if that
    speed is at most ``vmax`` (m/s), by the impulse removing its slip (``_pv_unslip``).
    Returns whether a contact was stuck."""
    kmin = -1
    cmin = vmax
    for k in range(int(pv[i, CP_K])):
        if pv[i, CP_S + k] != 0.0 or contact_mu(pv[i], k) == 0.0:
            continue
        _pv_frame(c_f, cw, st, i, pv, k)
        vn, v1, v2 = _contact_velocity_row(st, i, c_f, cw)
        c = math.sqrt(v1 * v1 + v2 * v2)
        if c <= cmin:
            cmin = c
            kmin = k
    if kmin < 0:
        return False
    _pv_unslip(st, i, bflt, pv, kmin, c_f, cw, Ii)
    pv[i, CP_S + kmin] = 1.0
    for j in range(3):
        pv[i, CP_U + 3 * kmin + j] = 0.0
    return True


PV_HELD_STILL = 3   # _pv_validate: the body rests on its held points (_pv_rest)


@njit(cache=True)
def _pv_rests(st, i, pv):
    """Body i (still, every integrated contact at zero velocity) rests on its K contacts:
    contact forces in their Coulomb cones hold it against gravity
    (``groove3d.rest_forces``), or the best forces leave their cones by at most
    ``HELD_REST_RTOL m |g|`` (a balance on a knife's edge, 3:3210509315: a capsule stopped
    on three points of a groove, its best rest forces out of the cones by 1.6e-8 m |g|, the
    slip of the one state that would move it growing by less than SLIP_ACC_TOL |g|). A
    rest in which one contact carries no force is tried too, on the others (3:332093779: a
    capsule stopped on both caps against a wall rests on the floor alone; the iteration's
    shrunk cones ask the wall for a force that nothing balances). Collinear points rest
    by the lever rule (``groove3d.line_rest``) with gravity's line at most
    ``HELD_REST_RTOL L`` from their segment. Allocates its small arrays (a mode change)."""
    K = int(pv[i, CP_K])
    arms = np.empty((K, 3))
    nrm = np.empty((K, 3))
    mus = np.empty(K)
    for k in range(K):
        arms[k, 0], arms[k, 1], arms[k, 2] = _pv_arm(st, i, pv, k)
        nrm[k, 0], nrm[k, 1], nrm[k, 2] = contact_normal(pv[i], k)
        mus[k] = contact_mu(pv[i], k)
    if _rests_on(K, arms, nrm, mus, pv[i]):
        return True
    if K < 3:
        return False
    sa = np.empty((K - 1, 3))
    sn = np.empty((K - 1, 3))
    sm = np.empty(K - 1)
    for skip in range(K):
        j = 0
        for k in range(K):
            if k == skip:
                continue
            for c in range(3):
                sa[j, c] = arms[k, c]
                sn[j, c] = nrm[k, c]
            sm[j] = mus[k]
            j += 1
        if _rests_on(K - 1, sa, sn, sm, pv[i]):
            return True
    return False


@njit(cache=True)
def _rests_on(K, arms, nrm, mus, pvi):
    """``_pv_rests`` on the K contacts given (arms from the centre of mass, normals, mu;
    ``pvi`` the body's integrated-contact row: mass, gravity, size)."""
    m = pvi[CP_M]
    gabs = math.sqrt(pvi[CP_G] ** 2 + pvi[CP_G + 1] ** 2 + pvi[CP_G + 2] ** 2)
    f = np.empty((K, 3))
    work = np.empty(rest_work_size(K))
    code, margin = rest_forces(K, arms, nrm, mus, m, pvi[CP_G], pvi[CP_G + 1], pvi[CP_G + 2],
                               f, work)
    if code == 0:
        return True
    if code == 1:
        return margin >= -HELD_REST_RTOL * m * gabs
    miss, lm = line_rest(K, arms, nrm, mus, pvi[CP_G], pvi[CP_G + 1], pvi[CP_G + 2])
    return miss <= HELD_REST_RTOL * pvi[CP_L] and lm >= -HELD_REST_RTOL


@njit(cache=True)
def _pv_unstick(st, i, pv, fw):
    """Body i is still on three or more sticking points and no rest holds it: the first
    consistent stick/slip state with at most two sticking contacts (the force system's
    limit; a third would hold it still), trying those with the most sticking contacts
    first and, among them, in the order of the contacts. A sliding contact starts along
    the direction its contact point then accelerates in (friction opposes it), found by
    fixed-point iteration (``SLIDE_ALL_ITER`` at most, from the frictionless
    accelerations; converged to ``SLIDE_ALL_RTOL``) and stored as its start direction.
    Consistent: every sliding contact's slip grows (``u . a_T > SLIP_ACC_TOL |g|``), every
    sticking force is in its cone and every normal force is positive (within
    ``FORCE_ARM m |g|``); failing that, the first state consistent but for normal forces
    (the validation then lifts the most negative). Returns whether one was found (else
    the statuses are as they were)."""
    K = int(pv[i, CP_K])
    gabs = math.sqrt(pv[i, CP_G] ** 2 + pv[i, CP_G + 1] ** 2 + pv[i, CP_G + 2] ** 2)
    gsc = SLIP_ACC_TOL * gabs
    farm = FORCE_ARM * pv[i, CP_M] * gabs
    stuck = 0
    for k in range(K):
        if pv[i, CP_S + k] == 1.0:
            stuck |= 1 << k
    for strict in (True, False):
        for nst in range(2, -1, -1):
            for mask in range(1 << K):
                cnt = 0
                for k in range(K):
                    cnt += (mask >> k) & 1
                if cnt != nst:
                    continue
                for k in range(K):
                    pv[i, CP_S + k] = float((mask >> k) & 1)
                    for j in range(3):
                        pv[i, CP_U + 3 * k + j] = 0.0
                if _pv_start_slips(st, i, pv, fw, gsc, farm, strict):
                    return True
    for k in range(K):
        pv[i, CP_S + k] = 1.0 if (stuck >> k) & 1 else 0.0
        for j in range(3):
            pv[i, CP_U + 3 * k + j] = 0.0
    return False


@njit(cache=True)
def _pv_start_slips(st, i, pv, fw, gsc, farm, strict):
    """``_pv_unstick``'s test of one stick/slip state of body i (statuses set, start
    directions zero): iterate the sliding contacts' start directions to their contact
    points' tangential accelerations; True when they converge and the state is
    consistent (normal forces checked when ``strict``)."""
    K = int(pv[i, CP_K])
    for it in range(SLIDE_ALL_ITER):
        if pivot_forces(st[i], pv[i], fw) != PV_OK:
            return False
        moved = 0.0
        good = True
        for k in range(K):
            if strict and fw[FW_LAM + k] < -farm:
                good = False
            if pv[i, CP_S + k] == 1.0:
                good = good and fw[FW_MARG + k] >= -farm
                continue
            ax, ay, az = _pv_tangential_accel(st, i, pv, fw, k)
            a = math.sqrt(ax * ax + ay * ay + az * az)
            uo = CP_U + 3 * k
            ua = ax * pv[i, uo] + ay * pv[i, uo + 1] + az * pv[i, uo + 2]
            if it > 0:
                good = good and ua > gsc
            if not a > 0.0:
                return False
            moved = max(moved, abs(1.0 - ua / a) if it > 0 else 1.0)
            pv[i, uo] = ax / a
            pv[i, uo + 1] = ay / a
            pv[i, uo + 2] = az / a
        if it > 0 and moved <= SLIDE_ALL_RTOL:
            return good
    return False


@njit(cache=True, inline="always")
def _wedged_still(i, st, pm, ttr, p1, p2):
    """Body i rests on planes p1 and p2 (mode PM_WEDGED): no motion, no event of its own."""
    for j in range(3):
        st[i, SV + j] = 0.0
        st[i, SW + j] = 0.0
        st[i, SA + j] = 0.0
        st[i, SAL + j] = 0.0
    pm[i, M_MODE] = PM_WEDGED
    pm[i, M_PLANE] = p1
    pm[i, M_FEAT] = p2
    pm[i, M_AUX] = 0
    ttr[i] = INF


@njit(cache=True)
def _pv_rest(i, t, st, pm, ttr, pv, ev_t, ev_i, ev_f, cnt, c_f, cw):
    """Body i rests on its integrated contacts (``PV_HELD_STILL``): mode PM_WEDGED on the
    planes of its first contact and of another (the same when it has one plane), no
    motion (event "rest"; the kinetic energy was removed by the sticking impulses)."""
    p1 = int(pv[i, CP_PLANE])
    p2 = p1
    for k in range(int(pv[i, CP_K])):
        if int(pv[i, CP_PLANE + k]) != p1:
            p2 = int(pv[i, CP_PLANE + k])
    _wedged_still(i, st, pm, ttr, p1, p2)
    _pv_frame(c_f, cw, st, i, pv, 0)
    _log(ev_t, ev_i, ev_f, cnt, t, EV_REST, i, -1 - p1, PM_WEDGED, 0, c_f, cw, 0.0, 0.0, 0.0,
         0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


@njit(cache=True)
def _pv_validate(i, t, st, bflt, pv, fw, c_f, cw, Ii, err):
    """Make the integrated contacts of body i consistent: contacts whose normal force
    would be negative are dropped (most negative first), sticking contacts outside their
    friction cone slide (opposite to their friction force), slips started from sticking
    that are still below slip_eps and no longer grow stick again; three or more sticking
    points (the body still) rest (``_pv_rests``) or some slide (``_pv_unstick``).
    Returns 0, 1 (no contact left), ``PV_HELD_STILL`` (a rest: ``_pv_rest``) or
    ERR_PAINLEVE."""
    farm = FORCE_ARM * pv[i, CP_M] * math.sqrt(pv[i, CP_G] ** 2 + pv[i, CP_G + 1] ** 2
                                                + pv[i, CP_G + 2] ** 2)
    # a sliding contact (without a stored start direction) whose slip is at most slip_eps
    # -- e.g. after an impulse at the other contact -- sticks
    for k in range(int(pv[i, CP_K])):
        uo = CP_U + 3 * k
        if pv[i, CP_S + k] == 0.0 and pv[i, uo] == 0.0 and pv[i, uo + 1] == 0.0 \
                and pv[i, uo + 2] == 0.0 and contact_mu(pv[i], k) != 0.0:
            _pv_frame(c_f, cw, st, i, pv, k)
            vn, v1, v2 = _contact_velocity_row(st, i, c_f, cw)
            if v1 * v1 + v2 * v2 <= pv[i, CP_EPS] ** 2:
                _pv_unslip(st, i, bflt, pv, k, c_f, cw, Ii)
                pv[i, CP_S + k] = 1.0
    restick = 0     # contacts stuck again below (bit k: contact k)
    for attempt in range(8):
        K = int(pv[i, CP_K])
        if K == 0:
            return 1
        rc = pivot_forces(st[i], pv[i], fw)
        if rc == PV_STUCK:
            # three or more sticking points: the body is still (_pv_still); it rests there
            # when forces in the cones hold it, else some contacts start to slide
            if _pv_rests(st, i, pv):
                return PV_HELD_STILL
            if _pv_unstick(st, i, pv, fw):
                continue
        if rc != PV_OK:
            _set_err(err, t, i, -1 - int(pv[i, CP_PLANE]), st[i, SX], st[i, SX + 1], st[i, SX +
                     2], rc, pv[i, CP_MU], K)
            return ERR_PAINLEVE
        kneg = -1
        lmin = -farm
        for k in range(K):
            if fw[FW_LAM + k] < lmin:
                lmin = fw[FW_LAM + k]
                kneg = k
        if kneg >= 0:
            if K == 1 and pv[i, CP_S] == 1.0:
                # sticking would pull (lam < 0); lifting off is consistent only if the
                # contact's free normal acceleration points out of the plane; if it points
                # in, the contact slides (a consistent direction with lam > 0), or no
                # state is consistent (Painleve)
                bn = (fw[FW_B] * pv[i, CP_N] + fw[FW_B + 1] * pv[i, CP_N + 1]
                      + fw[FW_B + 2] * pv[i, CP_N + 2])
                if bn < 0.0:
                    if _pv_slide(st, i, pv, 0, fw):
                        continue
                    _set_err(err, t, i, -1 - int(pv[i, CP_PLANE]), st[i, SX], st[i, SX + 1],
                             st[i, SX + 2], 3.0, pv[i, CP_MU], K)
                    return ERR_PAINLEVE
            _pv_drop(pv, i, kneg)
            continue
        changed = False
        two = _pv_sticking(pv, i)[0] == 2
        for k in range(K):
            if pv[i, CP_S + k] == 1.0 and fw[FW_MARG + k] < -farm:
                changed = True
        if changed:
            moved = False
            for k in range(K):
                if pv[i, CP_S + k] == 1.0 and (two or fw[FW_MARG + k] < -farm):
                    pivot_forces(st[i], pv[i], fw)
                    if _pv_slide(st, i, pv, k, fw):
                        moved = True
            if not moved and _pv_stick_slowest(st, i, bflt, pv, c_f, cw, Ii,
                                               STICK_RESCUE * pv[i, CP_EPS]):
                continue
            if not moved:
                # sticking is outside the cone and no slip direction is consistent
                _set_err(err, t, i, -1 - int(pv[i, CP_PLANE]), st[i, SX], st[i, SX + 1],
                         st[i, SX + 2], 3.0, pv[i, CP_MU], K)
                return ERR_PAINLEVE
            continue
        # a slip started from sticking, still below slip_eps, that no longer grows along
        # its friction direction sticks again (each contact once per call): its growth
        # event arms only while the growth is positive, so a phase that begins with it
        # decelerating would keep it sliding, the friction along its blended start
        # direction no longer opposing the slip (positive work; 3:2990834751)
        restuck = False
        for k in range(K):
            uo = CP_U + 3 * k
            if pv[i, CP_S + k] != 0.0 or (restick >> k) & 1 or (
                    pv[i, uo] == 0.0 and pv[i, uo + 1] == 0.0 and pv[i, uo + 2] == 0.0):
                continue
            co = FW_C + 3 * k
            c2 = fw[co] ** 2 + fw[co + 1] ** 2 + fw[co + 2] ** 2
            if c2 < pv[i, CP_EPS] ** 2 and slip_growth(st[i], pv[i], fw, k) <= 0.0:
                restick |= 1 << k
                _pv_unslip(st, i, bflt, pv, k, c_f, cw, Ii)
                pv[i, CP_S + k] = 1.0
                restuck = True
        if restuck:
            continue
        return 0
    _set_err(err, t, i, -1 - int(pv[i, CP_PLANE]), st[i, SX], st[i, SX + 1], st[i, SX + 2],
             3.0, pv[i, CP_MU], pv[i, CP_K])
    return ERR_PAINLEVE


@njit(cache=True)
def _jam_approach(a, w1, w2, c00, c01, c11, mu, x1, x2):
    """Where a contact sliding at v_N = 0 with slip ``x = (x1, x2)`` (m/s) stands before a
    Painleve jam: the approach speed (m/s, <= 0) from which Routh's integration in the
    normal impulse P gives the impact without collision of the jam. With ``W`` (1/kg) as in
    ``routh_3d_scalar`` (a = W_NN, w = W_TN, C = W_TT), u = x/|x|, the coefficient
    ``A = a - mu w . u`` and, under the normal force, ``dx/dP = w - mu C u`` (Routh's
    sliding equations): A <= 0 gives 0 (the jam is here); A > 0 falling at
    ``dA/dP = -mu w . (dx/dP)_perp / |x|`` reaches 0 at ``P1 = A / |dA/dP|`` (first order in
    P1), v_N held at 0 meanwhile by the unbounded normal force. Integrated from v_N = 0,
    v_N would rise by ``A P1 / 2`` by then; from ``-A P1 / 2`` it would touch 0 at the jam
    (a double root: the compression's end then decided by round-off), so the integration
    starts at ``-A P1`` and passes the jam at ``-A P1 / 2``, an error of that size in v_N
    (1e-14 to 1e-13 m/s in the drop campaign, against slips of 1e-6 to 0.4 m/s). NaN when
    A > 0 does not fall, or the slip would turn by more than JAM_TURN on the way."""
    xn = math.sqrt(x1 * x1 + x2 * x2)
    if not xn > 0.0:
        return math.nan
    u1 = x1 / xn
    u2 = x2 / xn
    A = a - mu * (w1 * u1 + w2 * u2)
    if A <= 0.0:
        return 0.0
    g1 = w1 - mu * (c00 * u1 + c01 * u2)
    g2 = w2 - mu * (c01 * u1 + c11 * u2)
    gp = -u2 * g1 + u1 * g2             # dx/dP across u
    turn = gp / xn                      # d(angle of u)/dP (rad per N s)
    dA = -mu * (-w1 * u2 + w2 * u1) * turn
    if not dA < 0.0:
        return math.nan
    P1 = A / -dA
    if not abs(turn) * P1 <= JAM_TURN:
        return math.nan
    return -A * P1


@njit(cache=True)
def _pv_iwc(i, p, t, st, bflt, pv, law_par, bp_law, grav, c_f, cw, Ii, ev_t, ev_i, ev_f,
            cnt, jam):
    """Impact without collision (Painleve) at body i's one integrated contact, on plane p,
    sliding at v_N = 0 where sliding has no consistent force (its normal force coefficient
    ``W_NN - mu u . W_TN <= 0``, u the slip direction: v_N would fall under any normal
    force), or, when ``jam`` is True, just before the point of the slide where that
    coefficient reaches 0 (``_jam_approach``). The impulse is Darboux-Keller's integration
    in the normal impulse from v_N = 0 (``routh_3d_scalar``) with the pair's mu and e
    (``max(e, 0)``) and Poisson's termination, whatever the pair's law (the laws are
    functions of an approach velocity, zero here). Genot & Brogliato, Eur. J. Mech. A 18
    (1999) 653; Stewart, SIAM Review 42 (2000) 3; Nordmark, Dankowicz & Champneys, Int. J.
    Non-Linear Mech. 44 (2009) 1011. Logged as event "painleve". Returns True when an
    impulse was applied."""
    _pv_frame(c_f, cw, st, i, pv, 0)
    v0, v1, v2 = _contact_velocity_row(st, i, c_f, cw)
    w00, w01, w02, w11, w12, w22 = _pv_w(st, i, bflt, c_f, cw, Ii)
    row = bp_law[i, p]
    mu = law_par[row, P_MU]
    vn0 = _jam_approach(w00, w01, w02, w11, w12, w22, mu, v1, v2) if jam else 0.0
    if not vn0 <= 0.0:
        return False
    mode, p0, p1, p2 = routh_3d_scalar(vn0, v1, v2, w00, w01, w02, w11, w12, w22,
                                       max(law_par[row, P_E], 0.0), mu,
                                       float(REST_POISSON), law_par[row, P_TOL])
    if mode == MODE_NO_SOLUTION or not p0 > 0.0:
        return False
    e0 = _energy(st, bflt, grav, i)
    jx = p0 * c_f[cw, CF_N] + p1 * c_f[cw, CF_T1] + p2 * c_f[cw, CF_T2]
    jy = p0 * c_f[cw, CF_N + 1] + p1 * c_f[cw, CF_T1 + 1] + p2 * c_f[cw, CF_T2 + 1]
    jz = p0 * c_f[cw, CF_N + 2] + p1 * c_f[cw, CF_T1 + 2] + p2 * c_f[cw, CF_T2 + 2]
    _apply_body(st, bflt, i, c_f[cw, CF_RA], c_f[cw, CF_RA + 1], c_f[cw, CF_RA + 2], jx, jy,
                jz, Ii)
    u0, u1, u2 = _contact_velocity_row(st, i, c_f, cw)
    _log(ev_t, ev_i, ev_f, cnt, t, EV_IWC, i, -1 - p, int(mode), 0, c_f, cw, 0.0, v1, v2, u0,
         u1, u2, p0, p1, p2, _energy(st, bflt, grav, i) - e0)
    return True


@njit(cache=True)
def _pv_after_iwc(i, t, st, bflt, grav, pm, ttr, tz, tolf, pv, fw, c_f, cw, Ii, err):
    """After an impact without collision at body i's one integrated contact: the body flies
    off when its contact leaves faster than the accumulation speed (return 2: flight from
    t), else it is held again, sticking or sliding (``_pv_validate``'s return)."""
    _pv_frame(c_f, cw, st, i, pv, 0)
    vn, v1, v2 = _contact_velocity_row(st, i, c_f, cw)
    gn = pv[i, CP_N] * grav[0] + pv[i, CP_N + 1] * grav[1] + pv[i, CP_N + 2] * grav[2]
    if vn > 0.0 and vn * vn > _vz2(tolf, abs(gn)):
        pm[i, M_MODE] = PM_FLIGHT
        for j in range(3):
            st[i, SA + j] = grav[j]
            st[i, SAL + j] = 0.0
        tz[i] = INF
        ttr[i] = INF
        return 2
    _pv_zero_normals(st, i, bflt, pv, Ii)
    _pv_stick_or_slip(st, i, bflt, pv, c_f, cw, Ii)
    return _pv_validate(i, t, st, bflt, pv, fw, c_f, cw, Ii, err)


@njit(cache=True)
def _pv_stick_or_slip(st, i, bflt, pv, c_f, cw, Ii):
    """Each held contact of body i slides along its own slip (no stored direction) when
    that slip exceeds slip_eps, else sticks, its slip removed by ``_pv_unslip``; decided
    in order (``_pv_unslip`` reads the statuses already set). A frictionless contact
    (mu = 0) always slides: it has no sticking state (its force is normal whatever the
    slip; sticking would add a tangential constraint no force can hold)."""
    K = int(pv[i, CP_K])
    for k in range(K):
        pv[i, CP_S + k] = 0.0
    for k in range(K):
        _pv_stick_or_slip_one(st, i, bflt, pv, k, c_f, cw, Ii)


@njit(cache=True)
def _pv_stick_or_slip_one(st, i, bflt, pv, k, c_f, cw, Ii):
    """Held contact k of body i (status sliding on entry) sticks when its slip is at most
    slip_eps and it has friction, its slip removed by ``_pv_unslip``; else it slides."""
    if contact_mu(pv[i], k) == 0.0:
        return
    _pv_frame(c_f, cw, st, i, pv, k)
    vn, v1, v2 = _contact_velocity_row(st, i, c_f, cw)
    c = math.sqrt(v1 * v1 + v2 * v2)
    if c <= pv[i, CP_EPS]:
        pv[i, CP_S + k] = 1.0
        if c > 0.0:
            _pv_unslip(st, i, bflt, pv, k, c_f, cw, Ii)


@njit(cache=True, inline="always")
def _pv_set_contact(pv, i, k, q, kq, feats, planes, law_par, bp_law):
    """Contact k of body i's integrated contact: feature row kq on plane q (its normal,
    offset and mu; sliding, no stored slip direction). kq = -1: the slot is unused."""
    for j in range(3):
        pv[i, CP_N + 3 * k + j] = planes[q, j]
        pv[i, CP_P + 3 * k + j] = feats[kq, j] if kq >= 0 else 0.0
        pv[i, CP_U + 3 * k + j] = 0.0
    pv[i, CP_D + k] = planes[q, 3]
    pv[i, CP_MU + k] = law_par[bp_law[i, q], P_MU]
    pv[i, CP_PLANE + k] = q
    pv[i, CP_F + k] = kq
    pv[i, CP_S + k] = 0.0


@njit(cache=True)
def _pv_add_wall(i, q, kq, st, bflt, feats, planes, law_par, bp_law, pv, fw, c_f, cw, Ii):
    """Body i held at K contacts (``pv``, validated; K < KMAX); feature row kq touches
    plane q (a wall candidate of ``_second_plane``). When the held
    motion accelerates that feature's gap into q (beyond round-off,
    ``decisions.touching_accel``), q holds it too, as contact K: its normal velocity is
    removed with the others' (``_pv_zero_normals``), it sticks or slides. Returns whether
    it was added (then validate again)."""
    K = int(pv[i, CP_K])
    if K >= KMAX:
        return False
    for k in range(K):
        if int(pv[i, CP_PLANE + k]) == q and int(pv[i, CP_F + k]) == kq:
            return False        # (already held there)
    pivot_forces(st[i], pv[i], fw)
    sx, sy, sz = qrot(st[i, SQ], st[i, SQ + 1], st[i, SQ + 2], st[i, SQ + 3], feats[kq, 0],
                      feats[kq, 1], feats[kq, 2])
    # the feature centre's acceleration (its contact point's normal part is the same)
    ax, ay, az = point_accel(st[i], fw, sx, sy, sz, sx, sy, sz)
    acc = planes[q, 0] * ax + planes[q, 1] * ay + planes[q, 2] * az
    reach = math.sqrt(sx * sx + sy * sy + sz * sz)
    # the scale of the terms acc is computed from: |a_cm| + |alpha| reach (+ w^2 reach)
    body = (math.sqrt(fw[FW_A] ** 2 + fw[FW_A + 1] ** 2 + fw[FW_A + 2] ** 2)
            + math.sqrt(fw[FW_AL] ** 2 + fw[FW_AL + 1] ** 2 + fw[FW_AL + 2] ** 2) * reach)
    w = math.sqrt(st[i, SW] ** 2 + st[i, SW + 1] ** 2 + st[i, SW + 2] ** 2)
    if not touching_accel(acc, body, w, reach) < 0.0:
        return False
    _pv_set_contact(pv, i, K, q, kq, feats, planes, law_par, bp_law)
    pv[i, CP_K] = K + 1
    _pv_zero_normals(st, i, bflt, pv, Ii)
    _pv_stick_or_slip_one(st, i, bflt, pv, K, c_f, cw, Ii)
    return True


@njit(cache=True, inline="always")
def _pv_set_body(pv, i, bflt, grav, tolf):
    """The body part of body i's integrated-contact parameters (mass, inertia, gravity,
    radius, slip_eps, size)."""
    pv[i, CP_M] = bflt[i, B_MASS]
    for j in range(3):
        pv[i, CP_I + j] = bflt[i, 1 + j]
        pv[i, CP_G + j] = grav[j]
    pv[i, CP_RAD] = bflt[i, B_RADIUS]
    pv[i, CP_EPS] = tolf[TF_SLIP_EPS]
    pv[i, CP_L] = math.sqrt(bflt[i, B_HALF] ** 2 + bflt[i, B_HALF + 1] ** 2 + bflt[i, B_HALF +
                            2] ** 2) + bflt[i, B_RADIUS]


@njit(cache=True)
def _pivot_enter(i, p, kf1, p2, kf2, K, walls, t, st, bint, bflt, feats, planes, grav,
                 law_par, bp_law, pm, ttr, tz, tolf, pv, fw, ev_t, ev_i, ev_f, cnt, c_f, cw,
                 Ii, err, iwc):
    """Body i keeps feature kf1 on plane p (and kf2 on plane p2 when K == 2: the same
    plane, or the other plane of a groove or a corner; feature rows) and enters integrated
    contact there (``_pivot_hold``). ``walls``: wall candidates (``_second_plane``, or
    ``NO_WALLS``), each held too when the motion on the others drives it into its plane
    (``_pv_add_wall``). Returns as ``_pivot_hold``."""
    _pv_set_body(pv, i, bflt, grav, tolf)
    _pv_set_contact(pv, i, 0, p, kf1, feats, planes, law_par, bp_law)
    _pv_set_contact(pv, i, 1, p2 if K == 2 else p, kf2 if K == 2 else -1, feats, planes,
                    law_par, bp_law)
    pv[i, CP_K] = K
    return _pivot_hold(i, walls, t, st, bint, bflt, feats, planes, grav, law_par,
                       bp_law, pm, ttr, tz, tolf, pv, fw, ev_t, ev_i, ev_f, cnt, c_f, cw, Ii,
                       err, iwc)


@njit(cache=True)
def _pivot_hold(i, walls, t, st, bint, bflt, feats, planes, grav, law_par, bp_law, pm,
                ttr, tz, tolf, pv, fw, ev_t, ev_i, ev_f, cnt, c_f, cw, Ii, err, iwc):
    """Body i keeps the features set in ``pv[i]`` on their planes: remove their (tiny)
    normal velocities with normal impulses, choose stick or slip, and enter integrated
    contact (event "pivot"). One sliding contact with no consistent force (Painleve) takes
    an impact without collision (``_pv_iwc``) when ``iwc`` is PAINLEVE_IMPACT (a float):
    the body then flies off (return 2) or, leaving slower than the accumulation speed, is
    held again (once). ``walls``: wall candidates ``(q1, k1, q2, k2)`` (planes, feature rows;
    -1 unused), each held too when the motion on the held contacts drives it in
    (``_pv_add_wall``, in order); a body stopped on three
    or more sticking points rests there (``_pv_rest``). Returns 0, 1 (no contact can
    persist), 2 or an error."""
    p = int(pv[i, CP_PLANE])
    e0 = _energy(st, bflt, grav, i)
    m = bflt[i, B_MASS]
    vx0 = st[i, SV]
    vy0 = st[i, SV + 1]
    vz0 = st[i, SV + 2]
    _pv_frame(c_f, cw, st, i, pv, 0)
    vi0, vi1, vi2 = _contact_velocity_row(st, i, c_f, cw)
    # normal velocities to zero: W_NN (K x K) dP = -v_N
    _pv_zero_normals(st, i, bflt, pv, Ii)
    _pv_stick_or_slip(st, i, bflt, pv, c_f, cw, Ii)
    rc = _pv_validate(i, t, st, bflt, pv, fw, c_f, cw, Ii, err)
    if (rc == ERR_PAINLEVE and err[6] == PV_PAINLEVE and pv[i, CP_K] == 1.0
            and pv[i, CP_S] == 0.0 and iwc == PAINLEVE_IMPACT
            and _pv_iwc(i, int(pv[i, CP_PLANE]), t, st, bflt, pv, law_par, bp_law, grav, c_f,
                        cw, Ii, ev_t, ev_i, ev_f, cnt, False)):
        # (validation may have dropped one of two contacts: the one left is contact 0)
        rc = _pv_after_iwc(i, t, st, bflt, grav, pm, ttr, tz, tolf, pv, fw, c_f, cw, Ii, err)
    for j in range(WALLS_MAX):
        if rc == 0 and walls[2 * j + 1] >= 0 and _pv_add_wall(
                i, walls[2 * j], walls[2 * j + 1], st, bflt, feats, planes, law_par, bp_law,
                pv, fw, c_f, cw, Ii):
            rc = _pv_validate(i, t, st, bflt, pv, fw, c_f, cw, Ii, err)
    still = rc == PV_HELD_STILL
    if still:
        rc = 0
    if rc != 0:
        return rc
    pm[i, M_MODE] = PM_PIVOT
    pm[i, M_PLANE] = p
    ttr[i] = INF
    tz[i] = INF
    for j in range(6):
        st[i, SA + j] = 0.0
    _pv_frame(c_f, cw, st, i, pv, 0)
    vf0, vf1, vf2 = _contact_velocity_row(st, i, c_f, cw)
    dvx = m * (st[i, SV] - vx0)
    dvy = m * (st[i, SV + 1] - vy0)
    dvz = m * (st[i, SV + 2] - vz0)
    P0 = dvx * c_f[cw, CF_N] + dvy * c_f[cw, CF_N + 1] + dvz * c_f[cw, CF_N + 2]
    P1 = dvx * c_f[cw, CF_T1] + dvy * c_f[cw, CF_T1 + 1] + dvz * c_f[cw, CF_T1 + 2]
    P2 = dvx * c_f[cw, CF_T2] + dvy * c_f[cw, CF_T2 + 1] + dvz * c_f[cw, CF_T2 + 2]
    _log(ev_t, ev_i, ev_f, cnt, t, EV_PIVOT, i, -1 - p, int(pv[i, CP_K]), 0, c_f, cw, vi0,
         vi1, vi2, vf0, vf1, vf2, P0, P1, P2, _energy(st, bflt, grav, i) - e0)
    if still:
        _pv_rest(i, t, st, pm, ttr, pv, ev_t, ev_i, ev_f, cnt, c_f, cw)
    return 0


@njit(cache=True)
def _pivot_leave(i, t, st, grav, pm, ttr, pv, ev_t, ev_i, ev_f, cnt, c_f, cw, k):
    """The last integrated contact (k) lifts off: free flight (event "release")."""
    _pv_frame(c_f, cw, st, i, pv, k)
    v0, v1, v2 = _contact_velocity_row(st, i, c_f, cw)
    pm[i, M_MODE] = PM_FLIGHT
    for j in range(3):
        st[i, SA + j] = grav[j]
        st[i, SAL + j] = 0.0
    ttr[i] = INF
    _log(ev_t, ev_i, ev_f, cnt, t, EV_RELEASE, i, -1 - int(pv[i, CP_PLANE]), 0, 0, c_f, cw,
         v0, v1, v2, v0, v1, v2, 0.0, 0.0, 0.0, 0.0)


@njit(cache=True)
def _pivot_jam(i, t, st, tref, bflt, grav, law_par, bp_law, pm, ttr, tz, pv, pw, fw, ws, tolf,
               ev_t, ev_i, ev_f, cnt, c_f, cw, Ii, err):
    """Body i's slide reached a Painleve jam (PE_JAM, painleve="impact"): from the state
    kept in PW_JAM, the impact without collision of the jam (``_pv_iwc``); the body then
    flies off or is held again. Returns (rc, recompute) as ``_pivot_event``."""
    for j in range(13):
        st[i, j] = pw[i, PW_JAM + j]
    tref[i] = t
    ws[i, WS_MODE] = -1.0
    p = int(pv[i, CP_PLANE])
    if not _pv_iwc(i, p, t, st, bflt, pv, law_par, bp_law, grav, c_f, cw, Ii, ev_t, ev_i,
                   ev_f, cnt, True):
        _set_err(err, t, i, -1 - p, st[i, SX], st[i, SX + 1], st[i, SX + 2], PV_PAINLEVE,
                 pv[i, CP_MU], pv[i, CP_K])
        return ERR_PAINLEVE, False
    rc = _pv_after_iwc(i, t, st, bflt, grav, pm, ttr, tz, tolf, pv, fw, c_f, cw, Ii, err)
    return _pivot_settled(rc, i, t, st, grav, pm, ttr, pv, ev_t, ev_i, ev_f, cnt, c_f, cw)


@njit(cache=True, inline="always")
def _pivot_settled(rc, i, t, st, grav, pm, ttr, pv, ev_t, ev_i, ev_f, cnt, c_f, cw):
    """The end of a pivot event: an error code passes on, 1 (no contact left) releases the
    body into flight, ``PV_HELD_STILL`` puts it to rest (``_pv_rest``); returns (rc,
    recompute) as ``_pivot_event``."""
    if rc < 0:
        return rc, False
    if rc == 1:
        _pivot_leave(i, t, st, grav, pm, ttr, pv, ev_t, ev_i, ev_f, cnt, c_f, cw, 0)
    elif rc == PV_HELD_STILL:
        _pv_rest(i, t, st, pm, ttr, pv, ev_t, ev_i, ev_f, cnt, c_f, cw)
    return 0, True


@njit(cache=True)
def _pivot_event(i, t, st, tref, bint, bflt, grav, law_par, bp_law, pm, ttr, tz, bt, bpl, bft,
                 pk, pv, pw, fw, ws, tolf, toli, pose, ev_t, ev_i, ev_f, cnt, c_f, cw, Ii,
                 err):
    """Handle the scheduled event of body i in integrated contact. Returns (rc, recompute):
    recompute is False when the event is an impact left to the impact step."""
    kind = pk[i, 0]
    idx = pk[i, 1]
    if kind == PE_JAM:
        ttr[i] = INF
        return _pivot_jam(i, t, st, tref, bflt, grav, law_par, bp_law, pm, ttr, tz, pv, pw,
                          fw, ws, tolf, ev_t, ev_i, ev_f, cnt, c_f, cw, Ii, err)
    rc = _bring(i, t, st, tref, bint, bflt, ws, tolf, toli, pose, pm, pv, pw, fw, err)
    if rc < 0:
        return rc, False
    ttr[i] = INF
    if kind == PE_GAP:
        bt[i] = t
        bpl[i] = idx // 1000
        bft[i] = idx % 1000
        return 0, False
    K = int(pv[i, CP_K])
    p = int(pv[i, CP_PLANE])
    if kind == PE_LIFT:
        if K == 1:
            _pivot_leave(i, t, st, grav, pm, ttr, pv, ev_t, ev_i, ev_f, cnt, c_f, cw, 0)
            return 0, True
        _pv_frame(c_f, cw, st, i, pv, idx)
        v0, v1, v2 = _contact_velocity_row(st, i, c_f, cw)
        _log(ev_t, ev_i, ev_f, cnt, t, EV_RELEASE, i, -1 - contact_plane(pv[i], idx), 1, 0,
             c_f, cw, v0, v1, v2, v0, v1, v2, 0.0, 0.0, 0.0, 0.0)
        _pv_drop(pv, i, idx)
        pm[i, M_PLANE] = int(pv[i, CP_PLANE])
    elif kind == PE_SLIP:
        rc = pivot_forces(st[i], pv[i], fw)
        if rc != PV_OK:
            _set_err(err, t, i, -1 - p, st[i, SX], st[i, SX + 1], st[i, SX + 2], rc, pv[i,
                     CP_MU], K)
            return ERR_PAINLEVE, False
        two = _pv_sticking(pv, i)[0] == 2
        for k in range(K):
            if k == idx or (two and pv[i, CP_S + k] == 1.0):
                pivot_forces(st[i], pv[i], fw)
                if not _pv_slide(st, i, pv, k, fw):
                    continue    # the cone was only touched: it keeps sticking
                _pv_frame(c_f, cw, st, i, pv, k)
                v0, v1, v2 = _contact_velocity_row(st, i, c_f, cw)
                _log(ev_t, ev_i, ev_f, cnt, t, EV_SLIDE, i, -1 - contact_plane(pv[i], k), 1, 0,
                     c_f, cw, v0, v1, v2, v0, v1, v2, 0.0, 0.0, 0.0, 0.0)
    elif kind == PE_STOP:
        _pv_frame(c_f, cw, st, i, pv, idx)
        v0, v1, v2 = _contact_velocity_row(st, i, c_f, cw)
        _pv_unslip(st, i, bflt, pv, idx, c_f, cw, Ii)
        pv[i, CP_S + idx] = 1.0
        _pv_frame(c_f, cw, st, i, pv, idx)
        u0, u1, u2 = _contact_velocity_row(st, i, c_f, cw)
        _log(ev_t, ev_i, ev_f, cnt, t, EV_STICK, i, -1 - p, 2, 0, c_f, cw, v0, v1, v2, u0, u1,
             u2, 0.0, 0.0, 0.0, 0.0)
    rc = _pv_validate(i, t, st, bflt, pv, fw, c_f, cw, Ii, err)
    return _pivot_settled(rc, i, t, st, grav, pm, ttr, pv, ev_t, ev_i, ev_f, cnt, c_f, cw)


@njit(cache=True, inline="always")
def _feature_contact(st, i, feats, f, planes, p, rad):
    """Feature row f of body i (radius rad, m) against plane p: (gap (m), world arm of the
    feature centre (m, 3 values), normal velocity of that point (m/s))."""
    rx, ry, rz = qrot(st[i, SQ], st[i, SQ + 1], st[i, SQ + 2], st[i, SQ + 3], feats[f, 0],
                      feats[f, 1], feats[f, 2])
    nx = planes[p, 0]
    ny = planes[p, 1]
    nz = planes[p, 2]
    g = (nx * (st[i, SX] + rx) + ny * (st[i, SX + 1] + ry) + nz * (st[i, SX + 2] + rz)
         - planes[p, 3] - rad)
    ux, uy, uz = _point_vel(st, i, rx, ry, rz)
    return g, rx, ry, rz, nx * ux + ny * uy + nz * uz


@njit(cache=True, inline="always")
def _accumulates(i, st, feats, f, planes, p, rad, alx, aly, alz, tolf):
    """The gap acceleration (m/s^2) of feature row f of body i (in flight, angular
    acceleration ``al``) on plane p when impacts would accumulate there: within gap_tol,
    its gap accelerating into p with a normal speed below the accumulation speed
    (``_vz2``); else 0.0."""
    g, rx, ry, rz, vn = _feature_contact(st, i, feats, f, planes, p, rad)
    if g > tolf[TF_GAP_TOL]:
        return 0.0
    nx = planes[p, 0]
    ny = planes[p, 1]
    nz = planes[p, 2]
    wx, wy, wz = st[i, SW], st[i, SW + 1], st[i, SW + 2]
    acc = nx * st[i, SA] + ny * st[i, SA + 1] + nz * st[i, SA + 2]
    acc += (nx * (aly * rz - alz * ry) + ny * (alz * rx - alx * rz)
            + nz * (alx * ry - aly * rx))
    acc += ((nx * wx + ny * wy + nz * wz) * (wx * rx + wy * ry + wz * rz)
            - (nx * rx + ny * ry + nz * rz) * (wx * wx + wy * wy + wz * wz))
    if not (acc < 0.0 and vn * vn < _vz2(tolf, -acc)):
        return 0.0
    return acc


@njit(cache=True)
def _pv_gather(i, st, bint, bflt, feats, planes, grav, law_par, bp_law, bp_off, tolf, pv):
    """Every feature of body i (in flight) at which impacts accumulate on any plane
    (``_accumulates``) into ``pv[i]``'s contacts, for a held motion at three or more
    points (a box's edge on one groove plane and a corner or an edge on the other, a
    capsule's caps on both; a corner in the groove's crease is one contact on each
    plane). Returns their number K, or -1 when there are more than ``KMAX``."""
    f0 = bint[i, B_FIRST]
    nf = bint[i, B_COUNT]
    rad = bflt[i, B_RADIUS]
    alx, aly, alz = _free_alpha(st, i, bflt)
    _pv_set_body(pv, i, bflt, grav, tolf)
    K = 0
    for p in range(planes.shape[0]):
        if bp_off[i, p] != 0:
            continue
        for k in range(nf):
            if not _accumulates(i, st, feats, f0 + k, planes, p, rad, alx, aly, alz,
                                tolf) < 0.0:
                continue
            if K == KMAX:
                return -1
            _pv_set_contact(pv, i, K, p, f0 + k, feats, planes, law_par, bp_law)
            K += 1
    pv[i, CP_K] = K
    return K


@njit(cache=True)
def _persist_candidates(i, st, bint, bflt, feats, planes, grav, bp_off, tolf):
    """Features of body i (in flight) that touch a plane pushing it with a normal speed
    below the accumulation speed while their gap accelerates into it: impacts would
    accumulate there. Returns (plane, count, first feature row, plane of the second,
    second feature row, several?, walls): one plane with any count, or two features on
    two planes (a groove, a corner); more features on two or more planes, or one sharp
    corner on two planes (a single point held twice), are "several" (``_after_impact``:
    a rest, a held motion at three or more points, or the corner held on both planes when
    both are frictionless; else unsupported). With one feature,
    or two on one plane (a capsule on both caps), ``walls`` holds the wall candidates
    (``_second_plane``), else ``NO_WALLS``.
    Planes gravity does not press (walls) are searched only when no pressed plane has a
    candidate: a box that lands plastically on a wall alone while turning into it is held
    there at one or two features (3:45036680 ended "impacts accumulate at a single contact
    point"); a face or a capsule's side on walls has none (count 0: the face rests and
    slides only on a plane gravity presses)."""
    f0 = bint[i, B_FIRST]
    nf = bint[i, B_COUNT]
    rad = bflt[i, B_RADIUS]
    alx, aly, alz = _free_alpha(st, i, bflt)
    bp = -1
    bp2 = -1
    cnt = 0
    k1 = -1
    k2 = -1
    acc1 = 0.0
    multi = False
    for sweep in range(2):
        # 0: the planes gravity presses; 1: the others (walls), when those have none
        if sweep == 1 and cnt > 0:
            break
        for p in range(planes.shape[0]):
            if bp_off[i, p] != 0:
                continue
            nx = planes[p, 0]
            ny = planes[p, 1]
            nz = planes[p, 2]
            if (nx * grav[0] + ny * grav[1] + nz * grav[2] < 0.0) != (sweep == 0):
                continue
            for k in range(nf):
                acc = _accumulates(i, st, feats, f0 + k, planes, p, rad, alx, aly, alz, tolf)
                if not acc < 0.0:
                    continue
                if cnt == 0:
                    bp = p
                    k1 = f0 + k
                    acc1 = acc
                elif cnt == 1:
                    bp2 = p
                    k2 = f0 + k
                elif p != bp or bp2 != bp:
                    multi = True
                cnt += 1
    walls = NO_WALLS
    if cnt < 2:
        bp2 = bp
    elif cnt == 2 and k2 == k1 and rad == 0.0:
        multi = True        # one corner on both planes (the groove's edge): one point
    if cnt == 1 or (cnt == 2 and bp2 == bp and not multi):
        # wall candidates (or NO_WALLS): each held by _pivot_hold if the held motion
        # drives it in
        # (3:2212146841: a capsule sliding on both caps rubbed one against a wall and took
        # an impact on each every 4e-7 s)
        walls = _second_plane(i, st, bint, bflt, feats, planes, bp, acc1, bp_off, tolf)
    if cnt > 0:
        gb = planes[bp, 0] * grav[0] + planes[bp, 1] * grav[1] + planes[bp, 2] * grav[2]
        face = cnt >= 3 or multi or (cnt == 2 and bp2 == bp and bint[i, B_KIND] == SH_CAPSULE)
        if gb >= 0.0 and face:
            return bp, 0, -1, bp, -1, False, NO_WALLS   # a face or a side on a wall
    return bp, cnt, k1, bp2, k2, multi, walls


@njit(cache=True)
def _touches_another(i, p, st, bint, bflt, feats, planes, grav, bp_off, tolf):
    """Does a feature of body i touch (within gap_tol) another plane than p that gravity
    presses (the other plane of a groove; a wall is left to the face rest's own tests)?"""
    f0 = bint[i, B_FIRST]
    rad = bflt[i, B_RADIUS]
    for q in range(planes.shape[0]):
        if q == p or bp_off[i, q] != 0:
            continue
        if not planes[q, 0] * grav[0] + planes[q, 1] * grav[1] + planes[q, 2] * grav[2] < 0.0:
            continue
        for k in range(bint[i, B_COUNT]):
            if _feature_contact(st, i, feats, f0 + k, planes, q, rad)[0] <= tolf[TF_GAP_TOL]:
                return True
    return False


@njit(cache=True)
def _second_plane(i, st, bint, bflt, feats, planes, p, acc1, bp_off, tolf):
    """Wall candidates of body i while features of it are held on plane p: features
    touching a plane other than p (gravity need not press it) within gap_tol, with a normal
    speed below the accumulation speed of the held contact (``_vz2`` of ``acc1``, the held
    feature's gap acceleration in m/s^2). Returns ``(q1, k1, q2, k2)`` (planes and feature
    rows, -1 when unused): at most ``WALLS_MAX`` = 2 candidates (a cap in the vertical
    corner of two walls touches both, 3:388087898); with more, none. Their free gap
    acceleration is not asked for: the held contact's force is what drives a corner or a
    cap into a wall while the body pivots (3:2681066003: a capsule rocking on the floor
    against a wall took an impact on each every 1e-6 s). Whether each is held is the held
    motion's decision (``_pv_add_wall``)."""
    f0 = bint[i, B_FIRST]
    nf = bint[i, B_COUNT]
    rad = bflt[i, B_RADIUS]
    vz2 = _vz2(tolf, -acc1)
    q1 = -1
    k1 = -1
    q2 = -1
    k2 = -1
    for q in range(planes.shape[0]):
        if q == p or bp_off[i, q] != 0:
            continue
        for k in range(nf):
            g, rx, ry, rz, vn = _feature_contact(st, i, feats, f0 + k, planes, q, rad)
            if g > tolf[TF_GAP_TOL]:
                continue
            if not vn * vn < vz2:
                continue
            if k2 >= 0:
                return NO_WALLS     # more than WALLS_MAX: not a held motion we build
            if k1 < 0:
                q1 = q
                k1 = f0 + k
            else:
                q2 = q
                k2 = f0 + k
    return (q1, k1, q2, k2)


# ------------------------------------------------------------------ rest configurations


@njit(cache=True)
def _rest_face(i, p, st, bint, bflt, planes):
    """Nearest resting configuration of body i on plane p: (face, h_rest, ux, uy, uz)
    with ``u`` the world direction that must become ``-n`` at rest (box: outward normal
    of the face most aligned with -n, face = 2 axis + (0 if +axis else 1); capsule: its
    axis projected... returned as the axis itself, face -1; sphere: face -1)."""
    kind = bint[i, B_KIND]
    nx = planes[p, 0]
    ny = planes[p, 1]
    nz = planes[p, 2]
    if kind == SH_SPHERE:
        return -1, bflt[i, B_RADIUS], -nx, -ny, -nz
    q0, q1, q2, q3 = st[i, SQ], st[i, SQ + 1], st[i, SQ + 2], st[i, SQ + 3]
    if kind == SH_CAPSULE:
        ax, ay, az = qrot(q0, q1, q2, q3, 0.0, 0.0, 1.0)
        return -1, bflt[i, B_RADIUS], ax, ay, az
    bx, by, bz = qrot_inv(q0, q1, q2, q3, nx, ny, nz)
    k = 0
    nb = bx
    if abs(by) > abs(nb):
        k = 1
        nb = by
    if abs(bz) > abs(nb):
        k = 2
        nb = bz
    sg = -1.0 if nb > 0.0 else 1.0
    ex = sg if k == 0 else 0.0
    ey = sg if k == 1 else 0.0
    ez = sg if k == 2 else 0.0
    ux, uy, uz = qrot(q0, q1, q2, q3, ex, ey, ez)
    return 2 * k + (0 if sg > 0.0 else 1), bflt[i, 5 + k], ux, uy, uz


@njit(cache=True)
def _excess(i, p, st, bint, bflt, planes, grav, hrest):
    """(E_ex, E_above) of body i over its rest on plane p (J): E_ex the energy of the
    normal motion, of the rotation (not for a sphere) and of the height above the rest;
    E_above all the kinetic energy plus the height above the rest."""
    nx = planes[p, 0]
    ny = planes[p, 1]
    nz = planes[p, 2]
    g = -(nx * grav[0] + ny * grav[1] + nz * grav[2])
    m = bflt[i, B_MASS]
    vN = nx * st[i, SV] + ny * st[i, SV + 1] + nz * st[i, SV + 2]
    hc = nx * st[i, SX] + ny * st[i, SX + 1] + nz * st[i, SX + 2] - planes[p, 3]
    v2 = st[i, SV] ** 2 + st[i, SV + 1] ** 2 + st[i, SV + 2] ** 2
    erot = _rot_energy(st, i, bflt)
    if bint[i, B_KIND] == SH_SPHERE:
        return 0.5 * m * vN * vN + m * g * max(hc - hrest, 0.0), 0.5 * m * v2 + erot
    return (0.5 * m * vN * vN + erot + m * g * (hc - hrest),
            0.5 * m * v2 + erot + m * g * (hc - hrest))


@njit(cache=True)
def _rest_consistent(i, p, st, bint, bflt, planes, grav, face, hrest, eex):
    """May the accumulation of body i's bounces on plane p end on its rest (face, height
    hrest, excess energy eex)? Only if the snap onto it does not lift the body (create
    energy): ``E_ex >= -m |g_n| SNAP_RTOL h_rest``; and, for a box, if the vertical through
    the centre of mass meets that face now (else the body would fall over its edge)."""
    g = -(planes[p, 0] * grav[0] + planes[p, 1] * grav[1] + planes[p, 2] * grav[2])
    if not eex >= -bflt[i, B_MASS] * g * SNAP_RTOL * hrest:
        return False
    if bint[i, B_KIND] != SH_BOX:
        return True
    bx, by, bz = qrot_inv(st[i, SQ], st[i, SQ + 1], st[i, SQ + 2], st[i, SQ + 3], -planes[p,
                          0], -planes[p, 1], -planes[p, 2])
    k = face // 2
    nk = abs(bx if k == 0 else (by if k == 1 else bz))
    lam = bflt[i, 5 + k] / nk          # the ray from the centre along -n meets the face
    if k != 0 and abs(lam * bx) > bflt[i, B_HALF] * (1.0 + FACE_RTOL):
        return False
    if k != 1 and abs(lam * by) > bflt[i, B_HALF + 1] * (1.0 + FACE_RTOL):
        return False
    if k != 2 and abs(lam * bz) > bflt[i, B_HALF + 2] * (1.0 + FACE_RTOL):
        return False
    return True


@njit(cache=True)
def _snap(i, p, st, bint, bflt, planes, hrest, ux, uy, uz):
    """Rotate body i about its centre of mass so that u becomes -n (box) or u becomes
    parallel to the plane (capsule), then put it at height hrest above plane p."""
    nx = planes[p, 0]
    ny = planes[p, 1]
    nz = planes[p, 2]
    kind = bint[i, B_KIND]
    if kind != SH_SPHERE:
        if kind == SH_BOX:
            tx, ty, tz = -nx, -ny, -nz
        else:
            d = ux * nx + uy * ny + uz * nz
            tx = ux - d * nx
            ty = uy - d * ny
            tz = uz - d * nz
            k = math.sqrt(tx * tx + ty * ty + tz * tz)
            tx /= k
            ty /= k
            tz /= k
        # shortest rotation u -> t: quaternion (1 + u.t, u x t), normalised
        c = ux * tx + uy * ty + uz * tz
        r0, r1, r2, r3 = qnormalize(1.0 + c, uy * tz - uz * ty, uz * tx - ux * tz,
                                    ux * ty - uy * tx)
        a0, a1, a2, a3 = qmul(r0, r1, r2, r3, st[i, SQ], st[i, SQ + 1], st[i, SQ + 2], st[i, SQ
                              + 3])
        a0, a1, a2, a3 = qnormalize(a0, a1, a2, a3)
        st[i, SQ] = a0
        st[i, SQ + 1] = a1
        st[i, SQ + 2] = a2
        st[i, SQ + 3] = a3
    hc = nx * st[i, SX] + ny * st[i, SX + 1] + nz * st[i, SX + 2] - planes[p, 3]
    st[i, SX] += (hrest - hc) * nx
    st[i, SX + 1] += (hrest - hc) * ny
    st[i, SX + 2] += (hrest - hc) * nz


@njit(cache=True)
def _tip_side(k, bx, by, bz, hx, hy, hz):
    """Where the pressure centre (body frame offset (bx, by, bz) from the centre of mass's
    foot, m) leaves face axis k of a box of half edges (hx, hy, hz): ``sa + 3 sb`` for the
    two other axes a = k + 1, b = k + 2 (mod 3), each 0 (inside, within ``FACE_RTOL``),
    1 (beyond +half) or 2 (beyond -half). One side: the body tips over that edge; two: over
    that corner."""
    code = 0
    mult = 1
    for j in range(1, 3):
        a = (k + j) % 3
        d = bx if a == 0 else (by if a == 1 else bz)
        h = hx if a == 0 else (hy if a == 1 else hz)
        if abs(d) > h * (1.0 + FACE_RTOL):
            code += mult * (1 if d > 0.0 else 2)
        mult = 3
    return code


@njit(cache=True)
def _tip_features(i, face, side, bint, feats):
    """The corner rows of box i that it tips over (``_tip_side``'s ``side`` of ``face``,
    numbered as ``_rest_face``): (k1, k2), k2 = -1 for a single corner."""
    k = face // 2
    sg = 1.0 if face % 2 == 0 else -1.0
    f0 = bint[i, B_FIRST]
    k1 = -1
    k2 = -1
    for j in range(bint[i, B_COUNT]):
        c = f0 + j
        if not feats[c, k] * sg > 0.0:
            continue
        ok = True
        code = side
        for m in range(1, 3):
            s = code % 3
            code //= 3
            a = (k + m) % 3
            if (s == 1 and not feats[c, a] > 0.0) or (s == 2 and not feats[c, a] < 0.0):
                ok = False
        if ok:
            if k1 < 0:
                k1 = c
            elif k2 < 0:
                k2 = c
    return k1, k2


@njit(cache=True, inline="always")
def _slip_curves(ex, ey, ez, gtx, gty, gtz, gt, mu):
    """A slip along the unit vector e on a plane whose tangential gravity is g_t (m/s^2,
    |g_t| = gt) curves under friction mu > 0 unless g_t is parallel to e (to
    ``PARALLEL_RTOL``: |e x g_t| <= PARALLEL_RTOL |g_t|)."""
    if not (gt > 0.0 and mu > 0.0):
        return False
    sx = ey * gtz - ez * gty
    sy = ez * gtx - ex * gtz
    sz = ex * gty - ey * gtx
    return math.sqrt(sx * sx + sy * sy + sz * sz) > PARALLEL_RTOL * gt


@njit(cache=True)
def _persist_setup(i, p, t, st, bint, bflt, planes, grav, law_par, bp_law, pm, ttr, tolf,
                   err):
    """Choose the persistent mode of body i on plane p (normal velocity already zero;
    a box or capsule already without rotation) and set its constant accelerations and
    next transition time. Returns 0, 1 (the plane does not push: release), ``RC_TIP`` (a
    box's face, ``M_FEAT``, cannot hold the friction moment: it tips over the side
    ``M_AUX`` names, ``_tip_side``) or an error."""
    nx = planes[p, 0]
    ny = planes[p, 1]
    nz = planes[p, 2]
    gn = nx * grav[0] + ny * grav[1] + nz * grav[2]
    gtx = grav[0] - gn * nx
    gty = grav[1] - gn * ny
    gtz = grav[2] - gn * nz
    gt = math.sqrt(gtx * gtx + gty * gty + gtz * gtz)
    ttr[i] = INF
    if not gn < 0.0:
        return 1
    m = bflt[i, B_MASS]
    mu = law_par[bp_law[i, p], P_MU]
    N = -m * gn
    vN = nx * st[i, SV] + ny * st[i, SV + 1] + nz * st[i, SV + 2]
    vtx = st[i, SV] - vN * nx
    vty = st[i, SV + 1] - vN * ny
    vtz = st[i, SV + 2] - vN * nz
    kind = bint[i, B_KIND]
    for j in range(3):
        st[i, SAL + j] = 0.0
    mode = PM_REST
    pm[i, M_AUX] = 0
    if kind == SH_SPHERE:
        if bint[i, B_ROT] != ROT_SPHERICAL:
            _set_err(err, t, i, -1 - p, st[i, SX], st[i, SX + 1], st[i, SX + 2], 1.0, 0.0, 0.0)
            return ERR_UNSUPPORTED
        r = bflt[i, B_RADIUS]
        inertia = bflt[i, B_I1]
        kinv = 1.0 / m + r * r / inertia
        # slip of the contact point: v_T + w x (-r n)
        cx = vtx - r * (st[i, SW + 1] * nz - st[i, SW + 2] * ny)
        cy = vty - r * (st[i, SW + 2] * nx - st[i, SW] * nz)
        cz = vtz - r * (st[i, SW] * ny - st[i, SW + 1] * nx)
        c = math.sqrt(cx * cx + cy * cy + cz * cz)
        fx = 0.0
        fy = 0.0
        fz = 0.0
        vsc = math.sqrt(vtx * vtx + vty * vty + vtz * vtz) + r * math.sqrt(
            st[i, SW] ** 2 + st[i, SW + 1] ** 2 + st[i, SW + 2] ** 2)
        if c <= ROLL_RTOL * vsc:
            # rolling needs F = -m g_t / (m kinv)
            fx = -gtx / kinv
            fy = -gty / kinv
            fz = -gtz / kinv
            if gt / kinv <= mu * N:
                w2 = st[i, SW] ** 2 + st[i, SW + 1] ** 2 + st[i, SW + 2] ** 2
                v2 = vtx * vtx + vty * vty + vtz * vtz
                mode = PM_REST if (gt == 0.0 and v2 == 0.0 and w2 == 0.0) else PM_ROLL
            else:
                fx = -mu * N * gtx / gt
                fy = -mu * N * gty / gt
                fz = -mu * N * gtz / gt
                mode = PM_SLIDE
        else:
            ex = cx / c
            ey = cy / c
            ez = cz / c
            fx = -mu * N * ex
            fy = -mu * N * ey
            fz = -mu * N * ez
            mode = PM_SLIDE
            k = (ex * gtx + ey * gty + ez * gtz) - mu * N * kinv
            if k < 0.0 and mu > 0.0:     # without friction nothing stops the slip
                ttr[i] = t + c / (-k)
            # the slip keeps its direction only if the slope is along it; else it curves
            # (no closed form): the contact is integrated from now on (the loop's
            # scheduled switch at ttr = t, _integrate_slide); the accelerations set below
            # hold for that instant only
            if _slip_curves(ex, ey, ez, gtx, gty, gtz, gt, mu):
                pm[i, M_AUX] = AUX_INTEGRATE
                ttr[i] = t
        st[i, SA] = gtx + fx / m
        st[i, SA + 1] = gty + fy / m
        st[i, SA + 2] = gtz + fz / m
        # torque (-r n) x F
        st[i, SAL] = -r * (ny * fz - nz * fy) / inertia
        st[i, SAL + 1] = -r * (nz * fx - nx * fz) / inertia
        st[i, SAL + 2] = -r * (nx * fy - ny * fx) / inertia
    else:
        vt = math.sqrt(vtx * vtx + vty * vty + vtz * vtz)
        fx = 0.0
        fy = 0.0
        fz = 0.0
        if mu > 0.0 and vt > 0.0 and gt <= mu * (-gn) and vt * vt <= _vz2(tolf, -gn):
            # a slip slower than the accumulation speed with friction that holds the body:
            # it sticks (its energy, below m zeno_speed^2 / 2, is dissipated; as in 2D)
            st[i, SV] -= vtx
            st[i, SV + 1] -= vty
            st[i, SV + 2] -= vtz
            vt = 0.0
        if vt == 0.0:
            if gt <= mu * (-gn):
                mode = PM_REST
                fx = -m * gtx
                fy = -m * gty
                fz = -m * gtz
            else:
                fx = -mu * N * gtx / gt
                fy = -mu * N * gty / gt
                fz = -mu * N * gtz / gt
                mode = PM_SLIDE
        else:
            ex = vtx / vt
            ey = vty / vt
            ez = vtz / vt
            fx = -mu * N * ex
            fy = -mu * N * ey
            fz = -mu * N * ez
            mode = PM_SLIDE
            k = (ex * gtx + ey * gty + ez * gtz) - mu * N / m
            if k < 0.0 and mu > 0.0:     # without friction nothing stops the slip
                ttr[i] = t + vt / (-k)
            # across the slope the slip curves (a translation v' = g_t - mu |g_n| u: the
            # pressure centre moves along u, so friction has no moment about n and the
            # body does not start to spin); it is integrated with the face's features
            # held (_integrate_slide), from the loop's switch at ttr = t
            if _slip_curves(ex, ey, ez, gtx, gty, gtz, gt, mu):
                pm[i, M_AUX] = AUX_INTEGRATE
                ttr[i] = t
        if mode == PM_REST:
            st[i, SA] = 0.0
            st[i, SA + 1] = 0.0
            st[i, SA + 2] = 0.0
        else:
            st[i, SA] = gtx + fx / m
            st[i, SA + 1] = gty + fy / m
            st[i, SA + 2] = gtz + fz / m
        # the face must hold the friction moment: pressure centre offset d = -h F / N
        # (from the centre of mass's foot) inside the face (box) or on the contact
        # segment (capsule)
        h = nx * st[i, SX] + ny * st[i, SX + 1] + nz * st[i, SX + 2] - planes[p, 3]
        dx = -h * fx / N
        dy = -h * fy / N
        dz = -h * fz / N
        q0, q1, q2, q3 = st[i, SQ], st[i, SQ + 1], st[i, SQ + 2], st[i, SQ + 3]
        bx, by, bz = qrot_inv(q0, q1, q2, q3, dx, dy, dz)
        if kind == SH_BOX:
            k = pm[i, M_FEAT] // 2
            ok = True
            if k != 0 and abs(bx) > bflt[i, B_HALF] * (1.0 + FACE_RTOL):
                ok = False
            if k != 1 and abs(by) > bflt[i, B_HALF + 1] * (1.0 + FACE_RTOL):
                ok = False
            if k != 2 and abs(bz) > bflt[i, B_HALF + 2] * (1.0 + FACE_RTOL):
                ok = False
            if not ok:
                _set_err(err, t, i, -1 - p, st[i, SX], st[i, SX + 1], st[i, SX + 2],
                         math.sqrt(fx * fx + fy * fy + fz * fz), N, h)
                pm[i, M_AUX] = _tip_side(k, bx, by, bz, bflt[i, B_HALF], bflt[i, B_HALF + 1],
                                         bflt[i, B_HALF + 2])
                pm[i, M_PLANE] = p
                return RC_TIP
        else:
            dd = math.sqrt(dx * dx + dy * dy + dz * dz)
            if (math.sqrt(bx * bx + by * by) > FACE_RTOL * (dd + bflt[i, B_RADIUS])
                    or abs(bz) > bflt[i, B_HALF + 2] * (1.0 + FACE_RTOL)):
                # friction has a moment about the axis (the capsule rolls) or the pressure
                # centre lies beyond a cap (it tips onto that cap): both caps are held and
                # the motion integrated (_integrate_slide), from the loop's switch at t
                mode = PM_SLIDE
                pm[i, M_AUX] = AUX_INTEGRATE
                ttr[i] = t
    pm[i, M_MODE] = mode
    pm[i, M_PLANE] = p
    return 0


@njit(cache=True)
def _foot(c_f, c, st, i, planes, p):
    """Frame row c: the plane's frame at the foot of body i's centre of mass."""
    nx = planes[p, 0]
    ny = planes[p, 1]
    nz = planes[p, 2]
    hc = nx * st[i, SX] + ny * st[i, SX + 1] + nz * st[i, SX + 2] - planes[p, 3]
    _frame(c_f, c, nx, ny, nz)
    for j in range(3):
        c_f[c, CF_P + j] = st[i, j] - hc * planes[p, j]
        c_f[c, CF_RA + j] = -hc * planes[p, j]
        c_f[c, CF_RB + j] = 0.0


@njit(cache=True)
def _release(i, t, st, planes, grav, pm, ttr, ev_t, ev_i, ev_f, cnt, c_f, cw):
    p = pm[i, M_PLANE]
    _foot(c_f, cw, st, i, planes, p)
    pm[i, M_MODE] = PM_FLIGHT
    for j in range(3):
        st[i, SA + j] = grav[j]
        st[i, SAL + j] = 0.0
    ttr[i] = INF
    v0, v1, v2 = _contact_velocity_row(st, i, c_f, cw)
    _log(ev_t, ev_i, ev_f, cnt, t, EV_RELEASE, i, -1 - p, 0, 0, c_f, cw, v0, v1, v2, v0, v1,
         v2, 0.0, 0.0, 0.0, 0.0)


@njit(cache=True, inline="always")
def _contact_velocity_row(st, i, c_f, c):
    """Contact-space velocity of body i's material point at arm c_f[c, CF_RA] (plane)."""
    ux, uy, uz = _point_vel(st, i, c_f[c, CF_RA], c_f[c, CF_RA + 1], c_f[c, CF_RA + 2])
    return (ux * c_f[c, CF_N] + uy * c_f[c, CF_N + 1] + uz * c_f[c, CF_N + 2],
            ux * c_f[c, CF_T1] + uy * c_f[c, CF_T1 + 1] + uz * c_f[c, CF_T1 + 2],
            ux * c_f[c, CF_T2] + uy * c_f[c, CF_T2 + 1] + uz * c_f[c, CF_T2 + 2])


@njit(cache=True)
def _tip(i, t, st, bint, bflt, feats, planes, grav, law_par, bp_law, pm, ttr, tz, tolf, pv, fw,
         ev_t, ev_i, ev_f, cnt, c_f, cw, Ii, err, pivot):
    """Box i resting or sliding on a face tips over (``_persist_setup`` returned RC_TIP:
    face ``M_FEAT``, side ``M_AUX``, plane ``M_PLANE``): from t it pivots on that side's
    edge (two corners) or corner (mode table: rest/slide on a face -> pivot on an edge or
    a vertex; ``pivot3d``; ``stepper2d._tip`` in 2D). Returns 0 (pivoting, or flying off
    after an impact without collision) or an error (ERR_TIPPING when no pivot state is
    consistent either)."""
    if pivot is None:
        return _not_compiled(err, t, i, FEATURE_PIVOT)
    p = pm[i, M_PLANE]
    k1, k2 = _tip_features(i, pm[i, M_FEAT], pm[i, M_AUX], bint, feats)
    pm[i, M_MODE] = PM_FLIGHT
    pm[i, M_AUX] = 0
    for j in range(3):
        st[i, SA + j] = grav[j]
        st[i, SAL + j] = 0.0
    ttr[i] = INF
    if k1 < 0:
        return ERR_TIPPING      # err holds the face forces set by _persist_setup
    K = 1 if k2 < 0 else 2
    e6 = err[6]
    e7 = err[7]
    e8 = err[8]
    rc = _pivot_enter(i, p, k1, p, k2, K, NO_WALLS, t, st, bint, bflt, feats, planes, grav,
                      law_par, bp_law, pm, ttr, tz, tolf, pv, fw, ev_t, ev_i, ev_f, cnt, c_f,
                      cw, Ii, err, tolf[TF_PAINLEVE])
    if rc == 1:
        _set_err(err, t, i, -1 - p, st[i, SX], st[i, SX + 1], st[i, SX + 2], e6, e7, e8)
        return ERR_TIPPING
    if rc == 2:
        return 0
    return rc


@njit(cache=True)
def _settle(i, p, t, st, bint, bflt, planes, grav, law_par, bp_law, pm, ttr, capture, ev_t,
            ev_i, ev_f, cnt, c_f, cw, tolf, err):
    """Snap body i (state at t) onto its rest on plane p (rotation onto the face, normal
    velocity and, not for a sphere, rotation removed) and enter persistent contact: event
    "contact", or "capture" when ``capture`` (the same snap removing more than the
    accumulation threshold: a box's spin about the normal).
    Returns 0, 1 (the plane does not push: stays in flight) or an error code."""
    face, hr, ux, uy, uz = _rest_face(i, p, st, bint, bflt, planes)
    nx = planes[p, 0]
    ny = planes[p, 1]
    nz = planes[p, 2]
    m = bflt[i, B_MASS]
    e0 = _energy(st, bflt, grav, i)
    _foot(c_f, cw, st, i, planes, p)
    vi0, vi1, vi2 = _contact_velocity_row(st, i, c_f, cw)
    v0x = st[i, SV]
    v0y = st[i, SV + 1]
    v0z = st[i, SV + 2]
    _snap(i, p, st, bint, bflt, planes, hr, ux, uy, uz)
    vN = nx * st[i, SV] + ny * st[i, SV + 1] + nz * st[i, SV + 2]
    for j in range(3):
        st[i, SV + j] -= vN * planes[p, j]
        if bint[i, B_KIND] != SH_SPHERE:
            st[i, SW + j] = 0.0
    pm[i, M_FEAT] = face
    slip = (st[i, SV] * st[i, SV] + st[i, SV + 1] * st[i, SV + 1]
            + st[i, SV + 2] * st[i, SV + 2])
    rc = _persist_setup(i, p, t, st, bint, bflt, planes, grav, law_par, bp_law, pm, ttr,
                        tolf, err)
    if rc != 0 and rc != RC_TIP:
        return rc
    _foot(c_f, cw, st, i, planes, p)
    vf0, vf1, vf2 = _contact_velocity_row(st, i, c_f, cw)
    dvx = m * (st[i, SV] - v0x)
    dvy = m * (st[i, SV + 1] - v0y)
    dvz = m * (st[i, SV + 2] - v0z)
    P0 = dvx * c_f[cw, CF_N] + dvy * c_f[cw, CF_N + 1] + dvz * c_f[cw, CF_N + 2]
    P1 = dvx * c_f[cw, CF_T1] + dvy * c_f[cw, CF_T1 + 1] + dvz * c_f[cw, CF_T1 + 2]
    P2 = dvx * c_f[cw, CF_T2] + dvy * c_f[cw, CF_T2 + 1] + dvz * c_f[cw, CF_T2 + 2]
    _log(ev_t, ev_i, ev_f, cnt, t, EV_CAPTURE if capture else EV_CONTACT, i, -1 - p,
         PM_PIVOT if rc == RC_TIP else pm[i, M_MODE], 0, c_f, cw, vi0, vi1, vi2, vf0, vf1,
         vf2, P0, P1, P2, _energy(st, bflt, grav, i) - e0)
    if rc == RC_TIP:
        return RC_TIP
    if pm[i, M_MODE] == PM_REST and slip > 0.0:
        # its slow slip stuck at once (_persist_setup): it has come to rest
        _log(ev_t, ev_i, ev_f, cnt, t, EV_REST, i, -1 - p, PM_REST, 0, c_f, cw, vf0, vf1,
             vf2, vf0, vf1, vf2, 0.0, 0.0, 0.0, 0.0)
    return 0


@njit(cache=True)
def _log_mode(i, t, st, planes, pm, ev_t, ev_i, ev_f, cnt, c_f, cw, vi0, vi1, vi2):
    p = pm[i, M_PLANE]
    _foot(c_f, cw, st, i, planes, p)
    v0, v1, v2 = _contact_velocity_row(st, i, c_f, cw)
    _log(ev_t, ev_i, ev_f, cnt, t, pm[i, M_MODE] + 1, i, -1 - p, pm[i, M_MODE], 0, c_f, cw,
         vi0, vi1, vi2, v0, v1, v2, 0.0, 0.0, 0.0, 0.0)


@njit(cache=True, inline="always")
def _roll_exact(i, p, st, bflt, planes):
    """Sphere i on plane p: its contact point exactly at rest, ``w = (w.n) n + n x v_T / r``
    (the rolling the slip stopped into; the change of w is the slip's round-off)."""
    nx = planes[p, 0]
    ny = planes[p, 1]
    nz = planes[p, 2]
    vN = nx * st[i, SV] + ny * st[i, SV + 1] + nz * st[i, SV + 2]
    r = bflt[i, B_RADIUS]
    vtx = st[i, SV] - vN * nx
    vty = st[i, SV + 1] - vN * ny
    vtz = st[i, SV + 2] - vN * nz
    wn = st[i, SW] * nx + st[i, SW + 1] * ny + st[i, SW + 2] * nz
    st[i, SW] = wn * nx + (ny * vtz - nz * vty) / r
    st[i, SW + 1] = wn * ny + (nz * vtx - nx * vtz) / r
    st[i, SW + 2] = wn * nz + (nx * vty - ny * vtx) / r


@njit(cache=True)
def _integrate_slide(i, t, st, tref, bint, bflt, feats, planes, grav, law_par, bp_law, pm,
                     ttr, tz, ws, tolf, toli, pose, pv, pw, fw, ev_t, ev_i, ev_f, cnt, c_f, cw,
                     Ii, err):
    """Body i slides on plane p across the slope (``pm[i, M_AUX] == AUX_INTEGRATE``, set by
    ``_persist_setup``): its slip direction turns under gravity and friction, a motion with
    no closed form here. It enters integrated contact (``pivot3d``; event "pivot") with the
    features that touch p held: a sphere's centre (radius r; it leaves the integrator when
    the slip stops, ``_sphere_rolls``), a box face's corners or a capsule's two caps
    (within gap_tol: the face was just snapped onto p; dependent contacts share their
    force by minimum norm; the body rests when the slip stops and the cones hold it,
    ``_pv_still``) until the slip stops, it lifts off, tips, or another feature hits a
    plane. Returns 0 or an error code."""
    rc = _bring(i, t, st, tref, bint, bflt, ws, tolf, toli, pose, pm, pv, pw, fw, err)
    if rc < 0:
        return rc
    p = pm[i, M_PLANE]
    pm[i, M_AUX] = 0
    ttr[i] = INF
    if bint[i, B_KIND] == SH_SPHERE:
        rc = _pivot_enter(i, p, bint[i, B_FIRST], p, -1, 1, NO_WALLS, t, st, bint, bflt,
                          feats, planes, grav, law_par, bp_law, pm, ttr, tz, tolf, pv, fw,
                          ev_t, ev_i, ev_f, cnt, c_f, cw, Ii, err,
                          0.0)    # (no impact without collision here)
    else:
        # the face's features on p (the face was just snapped onto it: at least two)
        _pv_set_body(pv, i, bflt, grav, tolf)
        K = 0
        rad = bflt[i, B_RADIUS]
        for f in range(bint[i, B_FIRST], bint[i, B_FIRST] + bint[i, B_COUNT]):
            if K < KMAX and _feature_contact(st, i, feats, f, planes, p,
                                             rad)[0] <= tolf[TF_GAP_TOL]:
                _pv_set_contact(pv, i, K, p, f, feats, planes, law_par, bp_law)
                K += 1
        pv[i, CP_K] = K
        rc = _pivot_hold(i, NO_WALLS, t, st, bint, bflt, feats, planes, grav, law_par,
                         bp_law, pm, ttr, tz, tolf, pv, fw, ev_t, ev_i, ev_f, cnt, c_f, cw,
                         Ii, err, 0.0)
    if rc < 0:
        return rc
    if rc == 1:     # the plane no longer pushes
        _release(i, t, st, planes, grav, pm, ttr, ev_t, ev_i, ev_f, cnt, c_f, cw)
        return 0
    if _sphere_stuck(i, bint, pm, pv):
        return _sphere_rolls(i, t, st, bint, bflt, planes, grav, law_par, bp_law, pm, ttr,
                             pv, tolf, ev_t, ev_i, ev_f, cnt, c_f, cw, err)
    return 0


@njit(cache=True, inline="always")
def _sphere_stuck(i, bint, pm, pv):
    """Sphere i in integrated contact on one plane whose slip stuck (below slip_eps): it
    leaves the integrator and rolls in closed form (``_sphere_rolls``)."""
    return (pm[i, M_MODE] == PM_PIVOT and bint[i, B_KIND] == SH_SPHERE
            and pv[i, CP_K] == 1.0 and pv[i, CP_S] == 1.0)


@njit(cache=True)
def _sphere_held(i, p, t, st, bint, bflt, feats, planes, grav, law_par, bp_law, bp_off, pm,
                 ttr, tz, tolf, pv, fw, ev_t, ev_i, ev_f, cnt, c_f, cw, Ii, err, pivot):
    """Sphere i (in flight after the impacts at t) accumulates on plane p while touching
    other planes where no closed-form mode holds it (``_groove_enter`` found none: a
    bounce on the other plane, or a spin in a corner of three planes): it enters integrated
    contact on p (``pivot3d``, its centre held at distance r), with the planes it touches
    as wall candidates (``_second_plane``: each held too when the motion on p drives the
    sphere into it), until it lifts off, its contacts stick (one: ``_sphere_rolls``; two:
    ``_groove_enter``; three: a rest, ``_pv_still``) or it hits a plane. Returns 0, 1 (p
    does not push it: nothing changed) or an error code."""
    if pivot is None:
        return _not_compiled(err, t, i, FEATURE_PIVOT)
    gn = planes[p, 0] * grav[0] + planes[p, 1] * grav[1] + planes[p, 2] * grav[2]
    walls = _second_plane(i, st, bint, bflt, feats, planes, p, gn, bp_off, tolf)
    rc = _pivot_enter(i, p, bint[i, B_FIRST], p, -1, 1, walls, t, st, bint, bflt, feats,
                      planes, grav, law_par, bp_law, pm, ttr, tz, tolf, pv, fw, ev_t, ev_i,
                      ev_f, cnt, c_f, cw, Ii, err, tolf[TF_PAINLEVE])
    if rc == 2:         # flew off after an impact without collision
        return 0
    if rc == 0 and _sphere_stuck(i, bint, pm, pv):
        # its slip below slip_eps stuck at once: it rolls on p in closed form
        return _sphere_rolls(i, t, st, bint, bflt, planes, grav, law_par, bp_law, pm, ttr,
                             pv, tolf, ev_t, ev_i, ev_f, cnt, c_f, cw, err)
    return rc


@njit(cache=True)
def _sphere_rolls(i, t, st, bint, bflt, planes, grav, law_par, bp_law, pm, ttr, pv, tolf,
                  ev_t, ev_i, ev_f, cnt, c_f, cw, err):
    """Sphere i in integrated contact whose contact sticks (its slip stopped): it leaves
    the integrator for the closed-form modes (``_persist_setup``: roll, rest, or a slide
    along the slope), its normal velocity (the integrator's error, within contact_tol)
    removed and its contact point exactly at rest (event "roll", "rest" or "slide")."""
    p = int(pv[i, CP_PLANE])
    pm[i, M_PLANE] = p
    _foot(c_f, cw, st, i, planes, p)
    vi0, vi1, vi2 = _contact_velocity_row(st, i, c_f, cw)
    vN = planes[p, 0] * st[i, SV] + planes[p, 1] * st[i, SV + 1] + planes[p, 2] * st[i, SV + 2]
    for j in range(3):
        st[i, SV + j] -= vN * planes[p, j]
    _roll_exact(i, p, st, bflt, planes)
    for j in range(6):
        st[i, SA + j] = 0.0
    rc = _persist_setup(i, p, t, st, bint, bflt, planes, grav, law_par, bp_law, pm, ttr,
                        tolf, err)
    if rc < 0:
        return rc
    if rc == 1:
        _release(i, t, st, planes, grav, pm, ttr, ev_t, ev_i, ev_f, cnt, c_f, cw)
        return 0
    _log_mode(i, t, st, planes, pm, ev_t, ev_i, ev_f, cnt, c_f, cw, vi0, vi1, vi2)
    return 0


@njit(cache=True, inline="always")
def _cone_interval(Np, al, E, be, mu, fs):
    """The interval [lo, hi] of the squeeze s (N) for which a contact force with normal
    component ``Np + al s`` and tangential components ``(E, be s)`` lies in the Coulomb
    cone ``|T| <= mu N`` (``pivot3d.cone_interval`` with orthogonal ``T0`` and ``dt``;
    ``fs`` N: the force scale for round-off). Empty when lo > hi."""
    return cone_interval(Np, al, E * E, 0.0, be * be, mu, fs, GROOVE_RTOL)


@njit(cache=True)
def _groove_enter(i, p, q, t, st, bflt, planes, grav, law_par, bp_law, pm, ttr, tolf, ev_t,
                  ev_i, ev_f, cnt, c_f, cw, err):
    """Sphere i (radius r, mass m, inertia I) touching planes p and q at t, its impacts
    accumulating there: it is held by both (mode PM_WEDGED, ``M_PLANE`` p, ``M_FEAT`` q),
    moving along the groove axis ``e = n_p x n_q / |n_p x n_q|`` (closed form).

    With friction it rolls on both contacts: ``v = u e``, ``w = (u / rho) d`` with ``d =
    (n_p - n_q) / |n_p - n_q|`` and ``rho = r |n_p + n_q| / 2`` (the distance from the
    centre to the line through the contact points), so ``(m + I / rho^2) du/dt = m g.e``
    (no work by the contact forces); entering, ``u`` is the momentum projection ``(m v.e +
    I w.d / rho) / (m + I / rho^2)`` (both contacts stick: the kinetic energy of the
    other five velocity components is removed). Rolling holds while some squeeze ``s``
    (equal and opposite forces along d, which move nothing) puts both contact forces in
    their friction cones (``_cone_interval``); the forces are constant, so it holds until
    an impulse. Without friction on both planes (mu = 0) it slides: ``v = (v.e) e``,
    ``w`` unchanged, ``dv/dt = (g.e) e``, if both normal forces are >= 0.

    Entered when both contact points move slower than the accumulation speed
    (``zeno_speed``, for the gravity pressing into the groove): their normal velocities
    are an accumulating bounce and a slip that slow sticks (as on one plane; without
    friction only the normal velocities count, the slip stays); events "contact" (mode
    PM_WEDGED, ``dE`` the kinetic energy removed) and "rest" when u and g.e are 0.
    Returns 0, 1 (a normal speed above the accumulation speed: a bounce, the caller lets
    the body fly) or ``GROOVE_SLIPS`` (accumulating on both planes while slipping faster,
    or rolling needing more friction than mu: nothing is changed, the caller integrates
    the slide on both planes, ``_groove_slide``)."""
    n1x, n1y, n1z = planes[p, 0], planes[p, 1], planes[p, 2]
    n2x, n2y, n2z = planes[q, 0], planes[q, 1], planes[q, 2]
    ex = n1y * n2z - n1z * n2y
    ey = n1z * n2x - n1x * n2z
    ez = n1x * n2y - n1y * n2x
    sg = math.sqrt(ex * ex + ey * ey + ez * ez)
    if sg <= GROOVE_SIN:
        return 1
    ex /= sg
    ey /= sg
    ez /= sg
    dx, dy, dz = n1x - n2x, n1y - n2y, n1z - n2z
    dl = math.sqrt(dx * dx + dy * dy + dz * dz)
    dx /= dl
    dy /= dl
    dz /= dl
    cx, cy, cz = n1x + n2x, n1y + n2y, n1z + n2z
    cl = math.sqrt(cx * cx + cy * cy + cz * cz)
    cx /= cl
    cy /= cl
    cz /= cl
    r = bflt[i, B_RADIUS]
    rho = 0.5 * r * cl
    m = bflt[i, B_MASS]
    inertia = bflt[i, B_I1]
    mu1 = law_par[bp_law[i, p], P_MU]
    mu2 = law_par[bp_law[i, q], P_MU]
    gx, gy, gz = grav[0], grav[1], grav[2]
    ge = gx * ex + gy * ey + gz * ez
    gd = gx * dx + gy * dy + gz * dz
    gc = gx * cx + gy * cy + gz * cz
    gabs = math.sqrt(gx * gx + gy * gy + gz * gz)
    fs = m * gabs
    # normal forces with no tangential in-plane force: N1 n1 + N2 n2 = -m g_in (d, c axes)
    a11 = n1x * dx + n1y * dy + n1z * dz
    a12 = n2x * dx + n2y * dy + n2z * dz
    a21 = n1x * cx + n1y * cy + n1z * cz
    a22 = n2x * cx + n2y * cy + n2z * cz
    det = a11 * a22 - a12 * a21
    N1 = -m * (gd * a22 - a12 * gc) / det
    N2 = -m * (a11 * gc - gd * a21) / det
    smooth = mu1 == 0.0 and mu2 == 0.0
    vx, vy, vz = st[i, SV], st[i, SV + 1], st[i, SV + 2]
    wx, wy, wz = st[i, SW], st[i, SW + 1], st[i, SW + 2]
    ve = vx * ex + vy * ey + vz * ez
    e_before = 0.5 * m * (vx * vx + vy * vy + vz * vz) + 0.5 * inertia * (
        wx * wx + wy * wy + wz * wz)
    if smooth:
        if N1 < -GROOVE_RTOL * fs or N2 < -GROOVE_RTOL * fs:
            return 1        # gravity does not press the sphere into both planes
        u = ve
        nwx, nwy, nwz = wx, wy, wz
        acc = ge
        alx = aly = alz = 0.0
    else:
        meff = m + inertia / (rho * rho)
        u = (m * ve + inertia * (wx * dx + wy * dy + wz * dz) / rho) / meff
        nwx, nwy, nwz = u / rho * dx, u / rho * dy, u / rho * dz
        acc = m * ge / meff
        alx, aly, alz = acc / rho * dx, acc / rho * dy, acc / rho * dz
        # tangential forces along e from the torque I al = -r (n1 x f1 + n2 x f2), with
        # b_k = n_k x e: the in-plane torque -r (E1 b1 + E2 b2) = (I acc / rho) d
        b1x = n1y * ez - n1z * ey
        b1y = n1z * ex - n1x * ez
        b1z = n1x * ey - n1y * ex
        b2x = n2y * ez - n2z * ey
        b2y = n2z * ex - n2x * ez
        b2z = n2x * ey - n2y * ex
        m11 = b1x * dx + b1y * dy + b1z * dz
        m12 = b2x * dx + b2y * dy + b2z * dz
        m21 = b1x * cx + b1y * cy + b1z * cz
        m22 = b2x * cx + b2y * cy + b2z * cz
        rhs = -inertia * acc / (rho * r)
        dm = m11 * m22 - m12 * m21
        E1 = rhs * m22 / dm
        E2 = -rhs * m21 / dm
        # the squeeze s d on contact 1 and -s d on contact 2
        lo1, hi1 = _cone_interval(N1, a11, E1, m11, mu1, fs)
        lo2, hi2 = _cone_interval(N2, -a12, E2, -m12, mu2, fs)
        lo = max(lo1, lo2)
        hi = min(hi1, hi2)
        if not lo <= hi + GROOVE_RTOL * fs:
            return GROOVE_SLIPS     # rolling on both needs more friction: it slips
    e_after = 0.5 * m * u * u + 0.5 * inertia * (nwx * nwx + nwy * nwy + nwz * nwz)
    # both contact points slower than the accumulation speed (normal and slip: a slip
    # that slow sticks, as on one plane), else the impacts go on
    vz2 = _vz2(tolf, math.sqrt(gd * gd + gc * gc))
    for k in range(2):
        nx, ny, nz = (n1x, n1y, n1z) if k == 0 else (n2x, n2y, n2z)
        px = vx - r * (wy * nz - wz * ny)
        py = vy - r * (wz * nx - wx * nz)
        pz = vz - r * (wx * ny - wy * nx)
        pn = px * nx + py * ny + pz * nz
        if not pn * pn <= vz2:
            return 1        # a bounce, not yet an accumulation
        if not smooth and not px * px + py * py + pz * pz <= vz2:
            # accumulating on both planes while slipping: it slides along the groove with
            # friction on two contacts (integrated: _groove_slide)
            return GROOVE_SLIPS
    # held by both from here: the centre at distance r from both planes (an entry from
    # integrated contact, or from rolling on one plane into the other, is off by up to
    # contact_tol or gap_tol)
    _groove_snap(i, p, q, st, bflt, planes)
    _foot(c_f, cw, st, i, planes, p)
    vi0, vi1, vi2 = _contact_velocity_row(st, i, c_f, cw)
    st[i, SV] = u * ex
    st[i, SV + 1] = u * ey
    st[i, SV + 2] = u * ez
    st[i, SW] = nwx
    st[i, SW + 1] = nwy
    st[i, SW + 2] = nwz
    st[i, SA] = acc * ex
    st[i, SA + 1] = acc * ey
    st[i, SA + 2] = acc * ez
    st[i, SAL] = alx
    st[i, SAL + 1] = aly
    st[i, SAL + 2] = alz
    pm[i, M_MODE] = PM_WEDGED
    pm[i, M_PLANE] = p
    pm[i, M_FEAT] = q
    pm[i, M_AUX] = 0
    ttr[i] = INF
    vf0, vf1, vf2 = _contact_velocity_row(st, i, c_f, cw)
    P0 = m * ((u * ex - vx) * c_f[cw, CF_N] + (u * ey - vy) * c_f[cw, CF_N + 1]
              + (u * ez - vz) * c_f[cw, CF_N + 2])
    P1 = m * ((u * ex - vx) * c_f[cw, CF_T1] + (u * ey - vy) * c_f[cw, CF_T1 + 1]
              + (u * ez - vz) * c_f[cw, CF_T1 + 2])
    P2 = m * ((u * ex - vx) * c_f[cw, CF_T2] + (u * ey - vy) * c_f[cw, CF_T2 + 1]
              + (u * ez - vz) * c_f[cw, CF_T2 + 2])
    _log(ev_t, ev_i, ev_f, cnt, t, EV_CONTACT, i, -1 - p, PM_WEDGED, 0, c_f, cw, vi0, vi1, vi2,
         vf0, vf1, vf2, P0, P1, P2, e_after - e_before)
    if u == 0.0 and acc == 0.0:
        _log(ev_t, ev_i, ev_f, cnt, t, EV_REST, i, -1 - p, PM_WEDGED, 0, c_f, cw, vf0, vf1,
             vf2, vf0, vf1, vf2, 0.0, 0.0, 0.0, 0.0)
    return 0


@njit(cache=True)
def _pressed_plane(i, st, bflt, planes, bp_off, pm, tolf):
    """A plane other than body i's own (``M_PLANE``) that sphere i touches (gap within
    ``gap_tol``) with a normal speed below the accumulation speed while its acceleration
    presses into it: its impacts there would accumulate at once (a time-of-impact search
    starting at the root sees no crossing). Returns the plane, or -1."""
    r = bflt[i, B_RADIUS]
    for q in range(planes.shape[0]):
        if q == pm[i, M_PLANE] or bp_off[i, q] != 0:
            continue
        nx, ny, nz = planes[q, 0], planes[q, 1], planes[q, 2]
        g = nx * st[i, SX] + ny * st[i, SX + 1] + nz * st[i, SX + 2] - planes[q, 3] - r
        vn = nx * st[i, SV] + ny * st[i, SV + 1] + nz * st[i, SV + 2]
        an = nx * st[i, SA] + ny * st[i, SA + 1] + nz * st[i, SA + 2]
        if g <= tolf[TF_GAP_TOL] and an < 0.0 and vn * vn < _vz2(tolf, -an):
            return q
    return -1


@njit(cache=True)
def _groove_snap(i, p, q, st, bflt, planes):
    """Put sphere i's centre at distance r from planes p and q (the integrated contact's
    drift, within contact_tol): the smallest move, in the span of the two normals."""
    r = bflt[i, B_RADIUS]
    g1 = planes[p, 0] * st[i, SX] + planes[p, 1] * st[i, SX + 1] + planes[p, 2] * st[i, SX
                                                                                     + 2]
    g2 = planes[q, 0] * st[i, SX] + planes[q, 1] * st[i, SX + 1] + planes[q, 2] * st[i, SX
                                                                                     + 2]
    e1 = planes[p, 3] + r - g1
    e2 = planes[q, 3] + r - g2
    c = planes[p, 0] * planes[q, 0] + planes[p, 1] * planes[q, 1] + planes[p, 2] * planes[q, 2]
    den = 1.0 - c * c       # > GROOVE_SIN^2: the planes form a groove
    a = (e1 - c * e2) / den
    b = (e2 - c * e1) / den
    for j in range(3):
        st[i, SX + j] += a * planes[p, j] + b * planes[q, j]


@njit(cache=True)
def _groove_slide(i, p, q, t, st, bint, bflt, feats, planes, grav, law_par, bp_law, pm, ttr,
                  tz, tolf, pv, fw, ev_t, ev_i, ev_f, cnt, c_f, cw, Ii, err, pivot):
    """Sphere i held by planes p and q slips on them (``_groove_enter`` returned
    ``GROOVE_SLIPS``): integrated contact (``pivot3d``) with its centre feature (radius r)
    held on both planes, each contact sticking or sliding, until a contact lifts off, or
    both stick (then it rolls along the groove in closed form, ``_groove_enter``), or it
    hits another plane. Returns 0 or an error code (err code 4 when no contact persists)."""
    if pivot is None:
        return _not_compiled(err, t, i, FEATURE_PIVOT)
    f = bint[i, B_FIRST]
    rc = _pivot_enter(i, p, f, q, f, 2, NO_WALLS, t, st, bint, bflt, feats, planes, grav,
                      law_par, bp_law, pm, ttr, tz, tolf, pv, fw, ev_t, ev_i, ev_f, cnt, c_f,
                      cw, Ii, err,
                      0.0)    # (no impact without collision here)
    if rc == 1:
        _set_err(err, t, i, -1 - p, st[i, SX], st[i, SX + 1], st[i, SX + 2], 4.0, 0.0, 0.0)
        return ERR_UNSUPPORTED
    return rc


@njit(cache=True)
def _groove_from_impact(i, t, nc, c_i, st, bflt, planes, grav, law_par, bp_law, pm, ttr,
                        tolf, ev_t, ev_i, ev_f, cnt, c_f, cw, err):
    """Sphere i stays in persistent contact with its plane after an impact on another
    plane q at t: its impacts on q accumulate while it slides or rolls on the first, so it
    is held by both when that is consistent (``_groove_enter``; a bounce on q leaves it as
    it is and the next impacts decide). Returns (``_groove_enter``'s answer, q): the
    caller integrates a slip on both planes (``GROOVE_SLIPS``, ``_groove_slide``)."""
    for c in range(nc):
        if c_i[c, CI_TYPE] == 0 and c_i[c, CI_A] == i and c_i[c, CI_B] != pm[i, M_PLANE]:
            q = c_i[c, CI_B]
            rc = _groove_enter(i, pm[i, M_PLANE], q, t, st, bflt, planes, grav, law_par,
                               bp_law, pm, ttr, tolf, ev_t, ev_i, ev_f, cnt, c_f, cw, err)
            return rc, q
    return 0, -1


@njit(cache=True)
def _transition(i, t, st, tref, bint, bflt, planes, grav, law_par, bp_law, pm, ttr, ws, tolf,
                toli, ev_t, ev_i, ev_f, cnt, c_f, cw, pose, err, pv, pw, fw):
    """Slip of a persistent contact stops at t: roll, rest or slide on."""
    rc = _bring(i, t, st, tref, bint, bflt, ws, tolf, toli, pose, pm, pv, pw, fw, err)
    if rc < 0:
        return rc
    ttr[i] = INF
    p = pm[i, M_PLANE]
    _foot(c_f, cw, st, i, planes, p)
    vi0, vi1, vi2 = _contact_velocity_row(st, i, c_f, cw)
    nx = planes[p, 0]
    ny = planes[p, 1]
    nz = planes[p, 2]
    vN = nx * st[i, SV] + ny * st[i, SV + 1] + nz * st[i, SV + 2]
    if bint[i, B_KIND] == SH_SPHERE:
        _roll_exact(i, p, st, bflt, planes)
    else:
        for j in range(3):
            st[i, SV + j] = 0.0
    rc = _persist_setup(i, p, t, st, bint, bflt, planes, grav, law_par, bp_law, pm, ttr,
                        tolf, err)
    if rc < 0 or rc == RC_TIP:
        return rc
    _log_mode(i, t, st, planes, pm, ev_t, ev_i, ev_f, cnt, c_f, cw, vi0, vi1, vi2)
    return 0


@njit(cache=True)
def _reevaluate(i, t, st, bint, bflt, planes, grav, law_par, bp_law, pm, ttr, tolf, ev_t,
                ev_i, ev_f, cnt, c_f, cw, err):
    """A body in persistent contact received an impulse: keep the contact (zeroing the
    normal velocity and, not for a sphere, the rotation) when that motion carries less
    energy than the accumulation threshold, else release it to free flight. A sphere in a
    groove (PM_WEDGED) stays in it on the same rule (``_groove_enter``; ``GROOVE_SLIPS``
    is returned, nothing changed, when it now slips on the groove's planes)."""
    p = pm[i, M_PLANE]
    if pm[i, M_MODE] == PM_WEDGED and bint[i, B_KIND] != SH_SPHERE:
        # a box or capsule resting on several points of two planes (_wedge_rest) was hit:
        # it flies, and its accumulation is decided again (_after_impact)
        _release(i, t, st, planes, grav, pm, ttr, ev_t, ev_i, ev_f, cnt, c_f, cw)
        return 0
    if pm[i, M_MODE] == PM_WEDGED:
        rc = _groove_enter(i, p, pm[i, M_FEAT], t, st, bflt, planes, grav, law_par, bp_law,
                           pm, ttr, tolf, ev_t, ev_i, ev_f, cnt, c_f, cw, err)
        if rc != 1:
            return rc
        _release(i, t, st, planes, grav, pm, ttr, ev_t, ev_i, ev_f, cnt, c_f, cw)
        return 0
    nx = planes[p, 0]
    ny = planes[p, 1]
    nz = planes[p, 2]
    gn = nx * grav[0] + ny * grav[1] + nz * grav[2]
    m = bflt[i, B_MASS]
    vN = nx * st[i, SV] + ny * st[i, SV + 1] + nz * st[i, SV + 2]
    ex = 0.5 * m * vN * vN
    if bint[i, B_KIND] != SH_SPHERE:
        ex += _rot_energy(st, i, bflt)
    if gn < 0.0 and ex <= 0.5 * m * _vz2(tolf, -gn):
        _foot(c_f, cw, st, i, planes, p)
        vi0, vi1, vi2 = _contact_velocity_row(st, i, c_f, cw)
        for j in range(3):
            st[i, SV + j] -= vN * planes[p, j]
            if bint[i, B_KIND] != SH_SPHERE:
                st[i, SW + j] = 0.0
        old = pm[i, M_MODE]
        rc = _persist_setup(i, p, t, st, bint, bflt, planes, grav, law_par, bp_law, pm, ttr,
                            tolf, err)
        if rc < 0 or rc == RC_TIP:
            return rc
        if rc == 0:
            if pm[i, M_MODE] != old:
                _log_mode(i, t, st, planes, pm, ev_t, ev_i, ev_f, cnt, c_f, cw, vi0, vi1,
                          vi2)
            return 0
    _release(i, t, st, planes, grav, pm, ttr, ev_t, ev_i, ev_f, cnt, c_f, cw)
    return 0


# ------------------------------------------------------------------ impact resolution


@njit(cache=True, inline="always")
def _single(law, c, t, cluster, st, bflt, law_ids, law_par, c_i, c_f, v3, W3, P3, Ii, ev_t,
            ev_i, ev_f, cnt, err):
    """Resolve contact c with its pair law at its current velocity (``law``: the scene's one
    law, a compile-time constant of ``loop_for``, or ``LAW_ANY``). Returns (rc, v_fN)."""
    vi0, vi1, vi2 = _contact_velocity(st, c_i, c_f, c)
    v3[0] = vi0
    v3[1] = vi1
    v3[2] = vi2
    _contact_W(st, bflt, c_i, c_f, c, W3, Ii)
    li = c_i[c, CI_LAW]
    mode = resolve_3d_as(law, law_ids[li], v3, W3, law_par[li], P3)
    if mode < 0:
        _set_err(err, t, c_i[c, CI_A], _bcode(c_i, c), c_f[c, CF_P], c_f[c, CF_P + 1],
                 c_f[c, CF_P + 2], mode, vi0, c_i[c, CI_LAW])
        err[9] = math.sqrt(vi1 * vi1 + vi2 * vi2)
        err[10] = vi0
        err[11] = vi1
        err[12] = vi2
        err[13] = W3[0, 0]
        err[14] = W3[0, 1]
        err[15] = W3[0, 2]
        err[16] = W3[1, 1]
        err[17] = W3[1, 2]
        err[18] = W3[2, 2]
        return ERR_NO_SOLUTION, 0.0
    P0 = P3[0]
    P1 = P3[1]
    P2 = P3[2]
    _apply(st, bflt, c_i, c_f, c, P0, P1, P2, Ii)
    vf0, vf1, vf2 = _contact_velocity(st, c_i, c_f, c)
    c_f[c, CF_PI] += P0
    c_f[c, CF_PI + 1] += P1
    c_f[c, CF_PI + 2] += P2
    _log(ev_t, ev_i, ev_f, cnt, t, EV_IMPACT, c_i[c, CI_A], _bcode(c_i, c), mode, cluster,
         c_f, c, vi0, vi1, vi2, vf0, vf1, vf2, P0, P1, P2,
         0.5 * (P0 * (vi0 + vf0) + P1 * (vi1 + vf1) + P2 * (vi2 + vf2)))
    return 0, vf0


@njit(cache=True)
def _speed_scale(st, bflt, grav, j):
    """Speed scale of body j (m/s): ``|v| + |w| L + sqrt(|g| L)``, L its bounding radius
    (the scale of the integrated contact's error control, pivot3d: a body coming to rest
    keeps the speed gravity gives it over its own size)."""
    L = math.sqrt(bflt[j, B_HALF] ** 2 + bflt[j, B_HALF + 1] ** 2
                  + bflt[j, B_HALF + 2] ** 2) + bflt[j, B_RADIUS]
    v = math.sqrt(st[j, SV] ** 2 + st[j, SV + 1] ** 2 + st[j, SV + 2] ** 2)
    w = math.sqrt(st[j, SW] ** 2 + st[j, SW + 1] ** 2 + st[j, SW + 2] ** 2)
    g = math.sqrt(grav[0] ** 2 + grav[1] ** 2 + grav[2] ** 2)
    return v + w * L + math.sqrt(g * L)


@njit(cache=True)
def _joint_v0_mu(members, K, c_i, c_f, law_par):
    """The joint solve's pre-impact contact velocities (3 K, m/s: each contact's N, T1, T2)
    and friction coefficients (K) for its fallbacks (allocated: not the per-event path)."""
    v0 = np.empty(3 * K)
    mus = np.empty(K)
    for a in range(K):
        c = members[a]
        mus[a] = law_par[c_i[c, CI_LAW], P_MU]
        for j in range(3):
            v0[3 * a + j] = c_f[c, CF_VI + j]
    return v0, mus


@njit(cache=True)
def _joint(members, K, t, st, bflt, grav, law_par, c_i, c_f, Wb, Pb, vb, tb, Ii, tolf, toli,
           ev_t, ev_i, ev_f, cnt, err):
    """Simultaneous policy: Newton restitution + Coulomb friction solved jointly over the
    K contacts (projected block Gauss-Seidel on the stacked Delassus matrix; when it does
    not converge, ``joint_polish.polish`` and then ``joint_polish.stick_sets``)."""
    n3 = 3 * K
    for a in range(n3):
        for b in range(n3):
            Wb[a, b] = 0.0
    for a in range(K):
        c = members[a]
        vi0, vi1, vi2 = _contact_velocity(st, c_i, c_f, c)
        c_f[c, CF_VI] = vi0
        c_f[c, CF_VI + 1] = vi1
        c_f[c, CF_VI + 2] = vi2
        e = law_par[c_i[c, CI_LAW], P_E]
        if not (0.0 <= e <= 1.0):
            _set_err(err, t, c_i[c, CI_A], _bcode(c_i, c), c_f[c, CF_P], c_f[c, CF_P + 1],
                     c_f[c, CF_P + 2], e, 0.0, 0.0)
            return ERR_JOINT_E
        vb[3 * a] = vi0
        vb[3 * a + 1] = vi1
        vb[3 * a + 2] = vi2
        tb[3 * a] = -e * min(vi0, 0.0)
        Pb[3 * a] = 0.0
        Pb[3 * a + 1] = 0.0
        Pb[3 * a + 2] = 0.0
        for b in range(K):
            d = members[b]
            # shared bodies: A of c with A or B of d, B of c with A or B of d
            for sc in range(2):
                if sc == 1 and c_i[c, CI_TYPE] == 0:
                    continue
                jc = c_i[c, CI_A] if sc == 0 else c_i[c, CI_B]
                for sd in range(2):
                    if sd == 1 and c_i[d, CI_TYPE] == 0:
                        continue
                    jd = c_i[d, CI_A] if sd == 0 else c_i[d, CI_B]
                    if jd != jc:
                        continue
                    _block(c, d, jc, CF_RA if sc == 0 else CF_RB, CF_RA if sd == 0 else CF_RB,
                           st, bflt, c_f, Ii, Wb, 3 * a, 3 * b)
    for a in range(n3):
        for b in range(a + 1, n3):
            m = 0.5 * (Wb[a, b] + Wb[b, a])
            Wb[a, b] = m
            Wb[b, a] = m
    vsc = 0.0
    for a in range(n3):
        vsc = max(vsc, abs(vb[a]))
    tol = tolf[TF_SIMUL_TOL] + SIMUL_RTOL * vsc
    converged = False
    dmax = 0.0
    for it in range(toli[TI_SIMUL_MAXIT]):
        dmax = 0.0
        for a in range(K):
            mu = law_par[c_i[members[a], CI_LAW], P_MU]
            i0 = 3 * a
            # normal
            new = Pb[i0] - (vb[i0] - tb[i0]) / Wb[i0, i0]
            if new < 0.0:
                new = 0.0
            dp = new - Pb[i0]
            if dp != 0.0:
                Pb[i0] = new
                for k in range(n3):
                    vb[k] += Wb[k, i0] * dp
                dv = abs(dp) * Wb[i0, i0]
                if dv > dmax:
                    dmax = dv
            # tangential block: drive v_T to zero, then project on the friction disk
            w11 = Wb[i0 + 1, i0 + 1]
            w12 = Wb[i0 + 1, i0 + 2]
            w22 = Wb[i0 + 2, i0 + 2]
            det = w11 * w22 - w12 * w12
            d1 = -(w22 * vb[i0 + 1] - w12 * vb[i0 + 2]) / det
            d2 = -(w11 * vb[i0 + 2] - w12 * vb[i0 + 1]) / det
            n1 = Pb[i0 + 1] + d1
            n2 = Pb[i0 + 2] + d2
            lim = mu * Pb[i0]
            nt = math.sqrt(n1 * n1 + n2 * n2)
            if nt > lim:
                if nt > 0.0:
                    n1 *= lim / nt
                    n2 *= lim / nt
                else:
                    n1 = 0.0
                    n2 = 0.0
            dp1 = n1 - Pb[i0 + 1]
            dp2 = n2 - Pb[i0 + 2]
            if dp1 != 0.0 or dp2 != 0.0:
                Pb[i0 + 1] = n1
                Pb[i0 + 2] = n2
                for k in range(n3):
                    vb[k] += Wb[k, i0 + 1] * dp1 + Wb[k, i0 + 2] * dp2
                dv = abs(dp1) * w11 + abs(dp2) * w22
                if dv > dmax:
                    dmax = dv
        if dmax <= tol:
            converged = True
            break
    if not converged:
        # finish exactly: semismooth Newton on the Alart-Curnier equations from PGS's
        # iterate (joint_polish), else from each set of sticking contacts (stick_sets:
        # PGS drifts along the null space of redundant contacts); the velocities follow
        # from the polished impulses
        v0, mus = _joint_v0_mu(members, K, c_i, c_f, law_par)
        if joint_polish(Wb, v0, tb, mus, Pb, K, tol) or stick_sets(Wb, v0, tb, mus, Pb, K, tol):
            converged = True
            for a in range(n3):
                s = v0[a]
                for b in range(n3):
                    s += Wb[a, b] * Pb[b]
                vb[a] = s
    if not converged:
        # accept a sweep that cycles at round-off of the bodies' own motion (redundant
        # contacts with friction converge slowly in PGS): the scale is the largest speed
        # |v| + |w| L of a body in the cluster, or of a contact
        for a in range(K):
            c = members[a]
            for side in range(2):
                if side == 1 and c_i[c, CI_TYPE] == 0:
                    continue
                vsc = max(vsc, _speed_scale(st, bflt, grav, c_i[c, CI_A] if side == 0 else
                                            c_i[c, CI_B]))
    if not converged and not dmax <= tolf[TF_SIMUL_TOL] + SIMUL_ACCEPT_RTOL * vsc:
        # the plastic problem (no restitution target) of the same contacts: when it solves,
        # friction jams them (3:526051317, a box's corner in a groove's crease at mu = 10;
        # 3:1527272399, a capsule on the floor against a wall): Newton's restitution has
        # no solution there in general (2D proves it by enumeration, _joint's enumerate2d;
        # a Python enumeration of every stick/slip/lift-off mode of these two found none at
        # e = 0.3 and a continuum at e = 0). Reported (err[8] = 1), not decided here.
        jam = 0.0
        v0, mus = _joint_v0_mu(members, K, c_i, c_f, law_par)
        t0 = np.zeros(n3)
        P0 = np.zeros(n3)
        if joint_polish(Wb, v0, t0, mus, P0, K, tol) or stick_sets(Wb, v0, t0, mus, P0, K,
                                                                      tol):
            jam = 1.0
        c = members[0]
        _set_err(err, t, c_i[c, CI_A], _bcode(c_i, c), c_f[c, CF_P], c_f[c, CF_P + 1],
                 c_f[c, CF_P + 2], K, dmax, jam)
        return ERR_PGS
    for a in range(K):
        c = members[a]
        _apply(st, bflt, c_i, c_f, c, Pb[3 * a], Pb[3 * a + 1], Pb[3 * a + 2], Ii)
    for a in range(K):
        c = members[a]
        P0 = Pb[3 * a]
        P1 = Pb[3 * a + 1]
        P2 = Pb[3 * a + 2]
        vi0 = c_f[c, CF_VI]
        vi1 = c_f[c, CF_VI + 1]
        vi2 = c_f[c, CF_VI + 2]
        c_f[c, CF_PI] += P0
        c_f[c, CF_PI + 1] += P1
        c_f[c, CF_PI + 2] += P2
        if P0 == 0.0 and vi0 >= 0.0:
            continue
        vf0, vf1, vf2 = _contact_velocity(st, c_i, c_f, c)
        mu = law_par[c_i[c, CI_LAW], P_MU]
        if P0 == 0.0:
            mode = 0
        elif math.sqrt(P1 * P1 + P2 * P2) < mu * P0 * (1.0 - 1e-12):
            mode = 1
        else:
            mode = 2
        _log(ev_t, ev_i, ev_f, cnt, t, EV_IMPACT, c_i[c, CI_A], _bcode(c_i, c), mode, K,
             c_f, c, vi0, vi1, vi2, vf0, vf1, vf2, P0, P1, P2,
             0.5 * (P0 * (vi0 + vf0) + P1 * (vi1 + vf1) + P2 * (vi2 + vf2)))
    return 0


@njit(cache=True, inline="always")
def _sequential(law, members, K, t, st, bflt, law_ids, law_par, c_i, c_f, v3, W3, P3, Ii,
                tolf, toli, ev_t, ev_i, ev_f, cnt, err):
    """Sequential policy: repeatedly resolve, with its pair law, the contact that approaches
    fastest (ties: lowest contact index), until none approaches faster than seq_vtol."""
    vtol = tolf[TF_SEQ_VTOL]
    for step in range(toli[TI_SEQ_MAXSTEPS]):
        best = np.int64(-1)   # (not a literal: no per-constant specialisation)
        vbest = -vtol
        for a in range(K):
            c = members[a]
            if c_i[c, CI_OFF] != 0:
                continue
            vN, v1, v2 = _contact_velocity(st, c_i, c_f, c)
            if vN < vbest:
                vbest = vN
                best = c
        if best < 0:
            return 0
        rc, vfN = _single(law, best, t, K, st, bflt, law_ids, law_par, c_i, c_f, v3, W3, P3,
                          Ii, ev_t, ev_i, ev_f, cnt, err)
        if rc < 0:
            return rc
        if perforates(law_par[c_i[best, CI_LAW]], vfN):
            c_i[best, CI_OFF] = 1
    c = members[0]
    _set_err(err, t, c_i[c, CI_A], _bcode(c_i, c), c_f[c, CF_P], c_f[c, CF_P + 1],
             c_f[c, CF_P + 2], K, toli[TI_SEQ_MAXSTEPS], 0.0)
    return ERR_SEQ


# ------------------------------------------------------------------ the event loop


@njit(cache=True)
def init_run(bint, bflt, feats, planes, grav, law_ids, law_par, bp_law, pairs, tolf, toli,
             st, tref, pm, tz, zp, ttr, bt, bpl, bft, bp_off, pr_t, pr_off, ws, glob, cnt,
             pk, pv, pw, ev_t, ev_i, ev_f, seg_t, seg_b, seg_s, c_f, skip, pose, fw, ybuf,
             vals, vals0, vfl, pscr, pfe, cid, err, pair, pgen):
    """Start a run at glob[0]: settle bodies that start resting on a plane, log the first
    trajectory segments and compute every candidate event (``pair``, ``pgen``: feature
    switches, see ``run_loop``)."""
    nb = st.shape[0]
    t = glob[0]
    cw = MAXC - 1
    no_capture = tolf[TF_T_END] < -INF     # False, typed at run time (no literal copy)
    for i in range(nb):
        tref[i] = t
        ws[i, WS_MODE] = -1.0
        for j in range(3):
            st[i, SA + j] = grav[j]
            st[i, SAL + j] = 0.0
        if not _finite(st, i):
            _set_err(err, t, i, 0, st[i, SX], st[i, SX + 1], st[i, SX + 2], 0.0, 0.0, 0.0)
            return ERR_NONFINITE
    for i in range(nb):
        for p in range(planes.shape[0]):
            if pm[i, M_MODE] != PM_FLIGHT:
                break
            gn = planes[p, 0] * grav[0] + planes[p, 1] * grav[1] + planes[p, 2] * grav[2]
            if not gn < 0.0:
                continue
            face, hr, ux, uy, uz = _rest_face(i, p, st, bint, bflt, planes)
            hc = (planes[p, 0] * st[i, SX] + planes[p, 1] * st[i, SX + 1] + planes[p, 2] *
                  st[i, SX + 2] - planes[p, 3])
            if hc - hr > tolf[TF_GAP_TOL]:
                continue
            eex, eab = _excess(i, p, st, bint, bflt, planes, grav, hr)
            if (eex < 0.5 * bflt[i, B_MASS] * _vz2(tolf, -gn)
                    and _rest_consistent(i, p, st, bint, bflt, planes, grav, face, hr, eex)):
                rc = _settle(i, p, t, st, bint, bflt, planes, grav, law_par, bp_law, pm, ttr,
                             no_capture, ev_t, ev_i, ev_f, cnt, c_f, cw, tolf, err)
                if rc == RC_TIP:
                    return ERR_TIPPING      # a box starting on a face that cannot hold it
                if rc < 0:
                    return rc
    for i in range(nb):
        _push_seg(seg_t, seg_b, seg_s, cnt, st, tref, i, pm, pv)
    for i in range(nb):
        rc = _recompute_planes(i, t, st, tref, bint, bflt, feats, planes, pm, tz, zp, bt, bpl,
                               bft, bp_off, ws, tolf, toli, skip, pose, c_f[MAXC - 2], err)
        if rc < 0:
            return rc
    for q in range(pairs.shape[0]):
        if pair is None:
            return _not_compiled(err, t, pairs[q, 0], FEATURE_PAIR)
        rc = _recompute_pair(pgen, q, t, st, tref, bint, bflt, planes, grav, pairs, pm, tz, zp,
                             ttr, bt, pr_t, pr_off, ws, pv, pw, fw, tolf, toli, pscr, pfe, err,
                             cid)
        if rc < 0:
            return rc
    return 0


@njit(cache=True)
def _wedge_rest(i, t, st, bint, bflt, feats, planes, grav, law_par, bp_law, bp_off, pm, ttr,
                tolf, ev_t, ev_i, ev_f, cnt, c_f, cw):
    """Body i (a box or a capsule, in flight after the impacts at t) has impacts
    accumulating on two or more planes at three or more features (or at one corner on both
    planes): it rests there (mode PM_WEDGED, ``M_PLANE`` and ``M_FEAT`` the first two
    planes; events "contact", ``dE`` the kinetic energy removed, and "rest") when

    * its kinetic energy (all of it: the rest removes it) is below the accumulation energy
      ``m vz^2 / 2`` of the planes it touches (``_vz2`` of the smallest ``|n . g|`` among
      the planes that push a feature within ``gap_tol``; the criterion of the face rest's
      ``E_ex``, ``_excess``, where the whole motion is removed: a contact point that slips
      that slowly sticks), and
    * contact forces in their Coulomb cones hold it in static equilibrium at those points
      (``groove3d.rest_forces``, within ``groove3d.REST_CONE_RTOL m |g|``).

    Its velocities are then removed (never energy created; the pose is kept, every gap
    within ``gap_tol``: no snap). Returns 0 (resting) or 1 (no consistent rest found:
    nothing changed, the caller refuses the state). Allocates its small arrays (a mode
    entry, once per rest, not the per-event path)."""
    f0 = bint[i, B_FIRST]
    nf = bint[i, B_COUNT]
    rad = bflt[i, B_RADIUS]
    m = bflt[i, B_MASS]
    arms = np.empty((WEDGE_MAXK, 3))
    nrm = np.empty((WEDGE_MAXK, 3))
    mus = np.empty(WEDGE_MAXK)
    K = 0
    p1 = -1
    p2 = -1
    vz2 = INF
    for p in range(planes.shape[0]):
        if bp_off[i, p] != 0:
            continue
        nx = planes[p, 0]
        ny = planes[p, 1]
        nz = planes[p, 2]
        gn = nx * grav[0] + ny * grav[1] + nz * grav[2]
        if not gn < 0.0:
            continue
        for k in range(nf):
            g, rx, ry, rz, vn = _feature_contact(st, i, feats, f0 + k, planes, p, rad)
            if g > tolf[TF_GAP_TOL]:
                continue
            vz2 = min(vz2, _vz2(tolf, -gn))
            if K == WEDGE_MAXK:
                return 1
            arms[K, 0] = rx - rad * nx
            arms[K, 1] = ry - rad * ny
            arms[K, 2] = rz - rad * nz
            nrm[K, 0] = nx
            nrm[K, 1] = ny
            nrm[K, 2] = nz
            mus[K] = law_par[bp_law[i, p], P_MU]
            K += 1
            if p1 < 0:
                p1 = p
            elif p != p1 and p2 < 0:
                p2 = p
    if K < 3 or p2 < 0:
        return 1
    kinetic = (0.5 * m * (st[i, SV] ** 2 + st[i, SV + 1] ** 2 + st[i, SV + 2] ** 2)
               + _rot_energy(st, i, bflt))
    if not kinetic <= 0.5 * m * vz2:
        return 1        # still bouncing or slipping: not a rest
    f = np.empty((K, 3))
    work = np.empty(rest_work_size(K))
    code, margin = rest_forces(K, arms, nrm, mus, m, grav[0], grav[1], grav[2], f, work)
    if code != 0:
        return 1
    e0 = _energy(st, bflt, grav, i)
    _foot(c_f, cw, st, i, planes, p1)
    vi0, vi1, vi2 = _contact_velocity_row(st, i, c_f, cw)
    v0x = st[i, SV]
    v0y = st[i, SV + 1]
    v0z = st[i, SV + 2]
    _wedged_still(i, st, pm, ttr, p1, p2)
    P0 = -m * (v0x * c_f[cw, CF_N] + v0y * c_f[cw, CF_N + 1] + v0z * c_f[cw, CF_N + 2])
    P1 = -m * (v0x * c_f[cw, CF_T1] + v0y * c_f[cw, CF_T1 + 1] + v0z * c_f[cw, CF_T1 + 2])
    P2 = -m * (v0x * c_f[cw, CF_T2] + v0y * c_f[cw, CF_T2 + 1] + v0z * c_f[cw, CF_T2 + 2])
    _log(ev_t, ev_i, ev_f, cnt, t, EV_CONTACT, i, -1 - p1, PM_WEDGED, 0, c_f, cw, vi0, vi1,
         vi2, 0.0, 0.0, 0.0, P0, P1, P2, _energy(st, bflt, grav, i) - e0)
    _log(ev_t, ev_i, ev_f, cnt, t, EV_REST, i, -1 - p1, PM_WEDGED, 0, c_f, cw, 0.0, 0.0, 0.0,
         0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    return 0


@njit(cache=True)
def _rest_or_gathered(i, t, st, bint, bflt, feats, planes, grav, law_par, bp_law, bp_off, pm,
                      ttr, tz, tolf, pv, fw, ev_t, ev_i, ev_f, cnt, c_f, cw, Ii, err, pivot):
    """Body i (in flight after the impacts at t) has impacts accumulating at three or more
    features on two planes: it rests there (``_wedge_rest``), or, still moving, is held at
    all of them (``_pv_gather``, ``_pivot_hold``) when they are at most ``KMAX``. Returns
    ``_wedge_rest``'s or ``_pivot_hold``'s code, or 1 (neither: nothing changed)."""
    rc = _wedge_rest(i, t, st, bint, bflt, feats, planes, grav, law_par, bp_law, bp_off, pm,
                     ttr, tolf, ev_t, ev_i, ev_f, cnt, c_f, cw)
    if rc != 1:
        return rc
    if pivot is None:
        return _not_compiled(err, t, i, FEATURE_PIVOT)
    if _pv_gather(i, st, bint, bflt, feats, planes, grav, law_par, bp_law, bp_off, tolf,
                  pv) < 3:
        return 1
    return _pivot_hold(i, NO_WALLS, t, st, bint, bflt, feats, planes, grav, law_par, bp_law, pm,
                       ttr, tz, tolf, pv, fw, ev_t, ev_i, ev_f, cnt, c_f, cw, Ii, err,
                       tolf[TF_PAINLEVE])


@njit(cache=True)
def _after_impact(i, t, nc, st, bint, bflt, feats, planes, grav, law_par, bp_law, pm, ttr,
                  tz, zp, bp_off, c_i, c_f, tolf, capture_on, pv, fw, ev_t, ev_i, ev_f, cnt,
                  Ii, err, toli, pivot, pairs, cid):
    """Body i (in flight) took part in the impacts at t: schedule an accumulation point,
    enter integrated point/edge contact, snap onto a face, or leave it in flight. Two
    spheres whose impacts accumulate are marked for persistent contact (``cid[CL_PEND]``:
    a cluster at the next pass)."""
    q = cid[CL_PEND]
    if q >= 0 and (pairs[q, 0] == i or pairs[q, 1] == i):
        return 0    # it enters persistent contact with its pair (a cluster, run_loop)
    cw = MAXC - 1
    # accumulation of bounces on a face (Zeno): excess energy below the threshold
    for c in range(nc):
        if c_i[c, CI_TYPE] != 0 or c_i[c, CI_A] != i:
            continue
        p = c_i[c, CI_B]
        if bp_off[i, p] != 0:
            continue
        gn = planes[p, 0] * grav[0] + planes[p, 1] * grav[1] + planes[p, 2] * grav[2]
        if not gn < 0.0:
            continue
        face, hr, ux, uy, uz = _rest_face(i, p, st, bint, bflt, planes)
        eex, eab = _excess(i, p, st, bint, bflt, planes, grav, hr)
        thr = 0.5 * bflt[i, B_MASS] * _vz2(tolf, -gn)
        if not eex < thr:
            if bint[i, B_KIND] == SH_SPHERE:
                # near-elastic bounces: stop before stepping through millions of them
                vn = (planes[p, 0] * st[i, SV] + planes[p, 1] * st[i, SV + 1]
                      + planes[p, 2] * st[i, SV + 2])
                n = impacts_before_rest(vn, c_f[c, CF_VCMN], gn, t, tolf[TF_T_END], eex, thr)
                if n > toli[TI_ACC_MAX]:
                    _set_err(err, t, i, -1 - p, st[i, SX], st[i, SX + 1], st[i, SX + 2],
                             -vn / c_f[c, CF_VCMN], n, 0.0)
                    return ERR_FAR_ACCUMULATION
            continue
        if not _rest_consistent(i, p, st, bint, bflt, planes, grav, face, hr, eex):
            continue
        onto_p = True
        for d in range(nc):
            if c_i[d, CI_TYPE] == 0 and c_i[d, CI_A] == i and c_i[d, CI_B] != p:
                # touching a second plane at this instant: settling on p alone would ignore
                # it (a ball in a groove was snapped into the other plane, creating energy).
                # A sphere is held by both when that motion is consistent (PM_WEDGED)
                # (else, bouncing on q while accumulating on p, the run stops: flying on
                # would leave p with a normal speed of round-off size)
                if bint[i, B_KIND] == SH_SPHERE:
                    rc = _groove_enter(i, p, c_i[d, CI_B], t, st, bflt, planes, grav, law_par,
                                       bp_law, pm, ttr, tolf, ev_t, ev_i, ev_f, cnt, c_f, cw,
                                       err)
                    if rc == GROOVE_SLIPS:
                        return _groove_slide(i, p, c_i[d, CI_B], t, st, bint, bflt, feats,
                                             planes, grav, law_par, bp_law, pm, ttr, tz, tolf,
                                             pv, fw, ev_t, ev_i, ev_f, cnt, c_f, cw, Ii, err,
                                             pivot)
                    if rc != 1:
                        return rc
                    # not held by both in closed form (q is bounced on, or the sphere spins
                    # in a corner of three planes): held on p with q and the other planes
                    # it touches as wall candidates (integrated contact)
                    rc = _sphere_held(i, p, t, st, bint, bflt, feats, planes, grav, law_par,
                                      bp_law, bp_off, pm, ttr, tz, tolf, pv, fw, ev_t, ev_i,
                                      ev_f, cnt, c_f, cw, Ii, err, pivot)
                    if rc != 1:
                        return rc
                else:
                    # a box or capsule on a face or side of p touching q too (a face on one
                    # groove plane, an edge on the other): a rest on both when consistent;
                    # still moving (a capsule's side on p, a cap on q), held at all those
                    # points when they are at most KMAX (integrated contact)
                    rc = _rest_or_gathered(i, t, st, bint, bflt, feats, planes, grav, law_par,
                                           bp_law, bp_off, pm, ttr, tz, tolf, pv, fw, ev_t,
                                           ev_i, ev_f, cnt, c_f, cw, Ii, err, pivot)
                    if rc != 1:
                        return rc
                    # fewer than three features accumulate (the other plane's contacts part
                    # faster than the accumulation speed: a box jostling in a groove's
                    # crease, 3:944403545): decided feature by feature below
                    onto_p = False
                    break
                _set_err(err, t, i, -1 - p, st[i, SX], st[i, SX + 1], st[i, SX + 2], 3.0, 0.0,
                         0.0)
                return ERR_UNSUPPORTED
        if not onto_p:
            break
        after = (planes[p, 0] * st[i, SV] + planes[p, 1] * st[i, SV + 1]
                 + planes[p, 2] * st[i, SV + 2])
        tz[i] = t + accumulation_time(after, c_f[c, CF_VCMN], gn)
        zp[i] = p
        return 0
    # impacts accumulating at one or two features (a corner, an edge, a cap; or a face)
    if bint[i, B_KIND] != SH_SPHERE:
        p, K, k1, p2, k2, multi, walls = _persist_candidates(i, st, bint, bflt, feats,
                                                             planes, grav, bp_off, tolf)
        if multi:
            # a rest there, or, still moving, held at all those points (integrated contact)
            rc = _rest_or_gathered(i, t, st, bint, bflt, feats, planes, grav, law_par, bp_law,
                                   bp_off, pm, ttr, tz, tolf, pv, fw, ev_t, ev_i, ev_f, cnt,
                                   c_f, cw, Ii, err, pivot)
            if rc != 1:
                return rc
            if (K == 2 and k2 == k1 and p2 != p and law_par[bp_law[i, p], P_MU] == 0.0
                    and law_par[bp_law[i, p2], P_MU] == 0.0):
                # one corner in the crease of two frictionless planes: held on both (two
                # sliding contacts at one point, each with its own normal: W_NN is regular;
                # with friction both would stick at once, a pinned point pivot3d's
                # two-contact stick does not build). A box tumbling on a corner in a
                # groove's crease (3:3296689687)
                if pivot is None:
                    return _not_compiled(err, t, i, FEATURE_PIVOT)
                rc = _pivot_enter(i, p, k1, p2, k1, 2, NO_WALLS, t, st, bint, bflt, feats,
                                  planes, grav, law_par, bp_law, pm, ttr, tz, tolf, pv, fw,
                                  ev_t, ev_i, ev_f, cnt, c_f, cw, Ii, err, tolf[TF_PAINLEVE])
                if rc != 1:
                    return rc
            _set_err(err, t, i, -1 - p, st[i, SX], st[i, SX + 1], st[i, SX + 2], 5.0, 0.0, 0.0)
            return ERR_UNSUPPORTED
        if K >= 3 or (K == 2 and p2 == p and bint[i, B_KIND] == SH_CAPSULE):
            gn = planes[p, 0] * grav[0] + planes[p, 1] * grav[1] + planes[p, 2] * grav[2]
            face, hr, ux, uy, uz = _rest_face(i, p, st, bint, bflt, planes)
            eex, eab = _excess(i, p, st, bint, bflt, planes, grav, hr)
            small = eex < 0.5 * bflt[i, B_MASS] * _vz2(tolf, -gn)
            if (small or (K >= 3 and capture_on)) and _touches_another(
                    i, p, st, bint, bflt, feats, planes, grav, bp_off, tolf):
                # a face on p while touching the groove's other plane (at its crease): the
                # snap onto p alone would turn the body into that plane (3:3320154933 went
                # 1.2e-9 m into it, 'done'); it rests on both, or is held at all those
                # points, or the run stops
                rc = _rest_or_gathered(i, t, st, bint, bflt, feats, planes, grav, law_par,
                                       bp_law, bp_off, pm, ttr, tz, tolf, pv, fw, ev_t, ev_i,
                                       ev_f, cnt, c_f, cw, Ii, err, pivot)
                if rc != 1:
                    return rc
                _set_err(err, t, i, -1 - p, st[i, SX], st[i, SX + 1], st[i, SX + 2], 3.0, 0.0,
                         0.0)
                return ERR_UNSUPPORTED
            if small or (K >= 3 and capture_on):
                rc = _settle(i, p, t, st, bint, bflt, planes, grav, law_par, bp_law, pm, ttr,
                             not small, ev_t, ev_i, ev_f, cnt, c_f, cw, tolf, err)
                if rc == RC_TIP:
                    return _tip(i, t, st, bint, bflt, feats, planes, grav, law_par, bp_law, pm,
                                ttr, tz, tolf, pv, fw, ev_t, ev_i, ev_f, cnt, c_f, cw, Ii, err,
                                pivot)
                return rc
            if K >= 3:
                _set_err(err, t, i, -1 - p, st[i, SX], st[i, SX + 1], st[i, SX + 2], 0.0, 0.0,
                         0.0)
                return ERR_CHATTER
        if K >= 1:
            if pivot is None:
                return _not_compiled(err, t, i, FEATURE_PIVOT)
            rc = _pivot_enter(i, p, k1, p2, k2, K, walls, t, st, bint, bflt, feats, planes,
                              grav, law_par, bp_law, pm, ttr, tz, tolf, pv, fw, ev_t, ev_i,
                              ev_f, cnt, c_f, cw, Ii, err, tolf[TF_PAINLEVE])
            if rc == 1:
                _set_err(err, t, i, -1 - p, st[i, SX], st[i, SX + 1], st[i, SX + 2], 0.0, 0.0,
                         0.0)
                return ERR_CHATTER
            return rc
    # sphere pairs accumulating: persistent contact (a cluster of them, their planes and the
    # spheres touching them, entered at the next pass of run_loop); anything else is not
    # supported (a pair of other shapes is checked by its next search,
    # decisions.pair_persistence)
    for c in range(nc):
        if c_i[c, CI_A] != i and not (c_i[c, CI_TYPE] == 1 and c_i[c, CI_B] == i):
            continue
        if c_i[c, CI_OFF] != 0:
            continue
        if c_i[c, CI_TYPE] == 1 and not (bint[c_i[c, CI_A], B_KIND] == SH_SPHERE
                                         and bint[c_i[c, CI_B], B_KIND] == SH_SPHERE):
            continue
        vN, v1, v2 = _contact_velocity(st, c_i, c_f, c)
        acc = _gap_accel(st, bflt, c_i, c_f, c)
        if acc < 0.0 and vN * vN < _vz2(tolf, -acc):
            if c_i[c, CI_TYPE] == 1 and cid[CL_PEND] < 0:
                for q in range(pairs.shape[0]):
                    if ((pairs[q, 0] == c_i[c, CI_A] and pairs[q, 1] == c_i[c, CI_B])
                            or (pairs[q, 1] == c_i[c, CI_A] and pairs[q, 0] == c_i[c, CI_B])):
                        cid[CL_PEND] = q
                        return 0
            _set_err(err, t, c_i[c, CI_A], _bcode(c_i, c), c_f[c, CF_P], c_f[c, CF_P + 1],
                     c_f[c, CF_P + 2], vN, acc, 0.0)
            return ERR_CHATTER
    return 0


# ------------------------------------------------------------------ persistent sphere contact


# Persistent contact between spheres (issue 16 item 2, PM_CLUSTER; stepper2d's design,
# integrated by kernels/cluster3d.py): when the impacts of a pair of spheres accumulate
# (after an impact of the pair its re-contact is within a rise of rest_length,
# decisions.pair_persistence: PP_CHATTER; or at the instant, _after_impact's accumulation
# rule), the pair is marked (cid[CL_PEND]) and at the next pass enters a *cluster*
# (_cluster_enter): the spheres connected to it through sphere-sphere contacts within
# gap_tol and their planes within gap_tol, projected onto g = dg/dt = 0 with consistent
# modes (cluster3d.cluster_select_modes). One cluster at a time, stored in cbod (its body
# rows, cluster3d.CB_*), ccon (cluster3d.KMAX active contact rows, then NCAND candidates),
# cwk (cluster3d's la, then its w, then two spare slots: the last the time of the last
# mode event) and cid (header layout.CL_*). Its leader (the first member) carries the next
# pass in ttr (_cluster_pass: cluster_advance to its first event, recorded as segments
# with constant accelerations, which flight3d.pose_at replays); every member is
# PM_CLUSTER (its plane and pair searches are off; a pair with a body outside a moving
# cluster is refused, PP_HELD). Events: a contact leaving (CE_LEAVE: it becomes a
# candidate; with no sphere-sphere contact left the cluster dissolves, each member
# settling on a plane it still touches (_settle) or flying), stick/slip (CE_SLIP,
# CE_STOP: cluster_after_event), a candidate gap closing (CE_GAP: the cluster dissolves
# into flight at that instant, its active contacts in the instant's impact cluster with
# the closing one; the persistence rule then enters it again), rest (CS_REST: frozen,
# velocities zero, until a body outside hits it: then it dissolves into the instant as at
# CE_GAP). Requires spherical inertia (PP_SHAPES otherwise).


def cluster_sizes(nb):
    """``(cbod shape, ccon shape, cwk size, cid size)`` of a scene of nb bodies (cwk: la,
    w, the modes of the active contacts before a mode event (cluster3d.KMAX), a spare slot
    and the time of the last mode event)."""
    return ((nb, cl.N_CB), (cl.KMAX + NCAND, cl.N_CC),
            cl.N_LA + int(cl.work_size(nb, NCAND)) + cl.KMAX + 2,
            CL_HDR + nb + cl.KMAX + NCAND)


@njit(cache=True, inline="always")
def _cl_scale(cid, bflt):
    """The cluster's length scale L (m): the sum of its members' diameters."""
    L = 0.0
    for r in range(cid[CL_N]):
        L += 2.0 * bflt[cid[CL_HDR + r], B_RADIUS]
    return L


@njit(cache=True)
def _cl_row(ccon, cid, nb, k, kind, a, b, nx, ny, nz, d, mu, src):
    """Fill contact row k of ccon (a plane: its normal and offset; its stepper source
    ``src`` into cid)."""
    for j in range(cl.N_CC):
        ccon[k, j] = 0.0
    ccon[k, cl.CC_KIND] = kind
    ccon[k, cl.CC_A] = a
    ccon[k, cl.CC_B] = b
    ccon[k, cl.CC_NX] = nx
    ccon[k, cl.CC_NX + 1] = ny
    ccon[k, cl.CC_NX + 2] = nz
    ccon[k, cl.CC_D] = d
    ccon[k, cl.CC_MU] = mu
    ccon[k, cl.CC_MODE] = cl.MODE_SLIP  # until chosen: the entry's projection keeps slips
    cid[CL_HDR + nb + k] = src


@njit(cache=True, inline="always")
def _cl_copy(ccon, cid, nb, dst, src):
    for j in range(cl.N_CC):
        ccon[dst, j] = ccon[src, j]
    cid[CL_HDR + nb + dst] = cid[CL_HDR + nb + src]


@njit(cache=True)
def _cl_lift(ccon, cid, nb, k):
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


@njit(cache=True, inline="always")
def _cl_pairs_left(ccon, cid):
    """Active sphere-sphere contacts of the cluster."""
    c = 0
    for k in range(cid[CL_NK]):
        if ccon[k, cl.CC_KIND] != cl.KIND_PLANE:
            c += 1
    return c


@njit(cache=True)
def _cl_refuse(err, t, a, b, st, why, x1, x2):
    """A named refusal of persistent sphere contact (``ERR_PERSISTENT_PAIR``, reason
    ``why``, a ``PP_*``)."""
    _set_err(err, t, a, b, st[a, SX], st[a, SX + 1], st[a, SX + 2], why, x1, x2)
    return ERR_PERSISTENT_PAIR


@njit(cache=True, inline="always")
def _cl_energy(st, bflt, grav, cid):
    e = 0.0
    for r in range(cid[CL_N]):
        e += _energy(st, bflt, grav, cid[CL_HDR + r])
    return e


@njit(cache=True)
def _cl_log(ev_t, ev_i, ev_f, cnt, t, kind, a, b, n, c_f, cw, st, bflt, ccon, k, dE):
    """Log event ``kind`` of cluster contact row k between sphere a and sphere b (or plane
    -1 - b): its point ``x_a - r_a n`` and frame into row cw of c_f, the contact force (N;
    normal, t1, t2) in the impulse slots."""
    if ccon[k, cl.CC_KIND] == cl.KIND_PLANE:
        nx = ccon[k, cl.CC_NX]
        ny = ccon[k, cl.CC_NX + 1]
        nz = ccon[k, cl.CC_NX + 2]
    else:
        dx = st[a, SX] - st[b, SX]
        dy = st[a, SX + 1] - st[b, SX + 1]
        dz = st[a, SX + 2] - st[b, SX + 2]
        dd = math.sqrt(dx * dx + dy * dy + dz * dz)
        nx = dx / dd
        ny = dy / dd
        nz = dz / dd
    _frame(c_f, cw, nx, ny, nz)
    r = bflt[a, B_RADIUS]
    for j in range(3):
        c_f[cw, CF_P + j] = st[a, SX + j] - r * c_f[cw, CF_N + j]
    T1 = 0.0
    T2 = 0.0
    for j in range(3):
        T1 += ccon[k, cl.CC_TX + j] * c_f[cw, CF_T1 + j]
        T2 += ccon[k, cl.CC_TX + j] * c_f[cw, CF_T2 + j]
    _log(ev_t, ev_i, ev_f, cnt, t, kind, a, b, PM_CLUSTER, n, c_f, cw, 0.0, 0.0, 0.0, 0.0,
         0.0, 0.0, ccon[k, cl.CC_LAMN], T1, T2, dE)


@njit(cache=True)
def _cl_member_to(i, t, st, tref, bint, bflt, planes, grav, tz, zp, ws, tolf, toli, pose, pm,
                  pv, pw, fw, err):
    """Bring sphere i to t for a cluster (a pending accumulation jump is cancelled: its held
    motion, as the impact step does). Returns 0 or an error code."""
    if tz[i] < INF:
        p = zp[i]
        _held_into(st[i], bint[i, B_KIND], planes[p, 0], planes[p, 1], planes[p, 2], st[i])
        ws[i, WS_MODE] = -1.0
        tz[i] = INF
    rc = _bring(i, t, st, tref, bint, bflt, ws, tolf, toli, pose, pm, pv, pw, fw, err)
    if rc < 0:
        return rc
    for j in range(3):
        st[i, SA + j] = grav[j]
        st[i, SAL + j] = 0.0
    return 0


@njit(cache=True)
def _cluster_enter(t, st, tref, bint, bflt, planes, grav, law_par, bp_law, bp_off, pairs,
                   pr_off, pr_t, pm, tz, zp, ttr, bt, ws, tolf, toli, pose, pv, pw, fw, cbod,
                   ccon, cwk, cid, bmark, ev_t, ev_i, ev_f, cnt, c_f, err):
    """Enter persistent contact for pair ``cid[CL_PEND]`` (its impacts accumulate at t):
    gather the cluster, project it onto g = dg/dt = 0, select the modes
    (``cluster3d.cluster_select_modes``) and schedule its first pass at t. The members are
    marked (``bmark``). Returns 0 (a cluster, or none when every sphere-sphere contact
    lifts: the members fly or settle) or an error code (a named refusal,
    ``ERR_PERSISTENT_PAIR``)."""
    nb = st.shape[0]
    q = cid[CL_PEND]
    cid[CL_PEND] = -1
    a = pairs[q, 0]
    b = pairs[q, 1]
    if cid[CL_N] > 0:
        return _cl_refuse(err, t, a, b, st, PP_TWO, float(cid[CL_LEAD]), 0.0)
    gtol = tolf[TF_GAP_TOL]
    # members: the spheres connected through sphere-sphere contacts within gap_tol at t
    cid[CL_HDR] = a
    cid[CL_HDR + 1] = b
    n = 2
    head = 0
    while head < n:
        i = cid[CL_HDR + head]
        head += 1
        if bint[i, B_KIND] != SH_SPHERE or bint[i, B_ROT] != ROT_SPHERICAL:
            return _cl_refuse(err, t, a, b, st, PP_SHAPES, float(i), 0.0)
        if pm[i, M_MODE] == PM_PIVOT or pm[i, M_MODE] == PM_WEDGED:
            return _cl_refuse(err, t, a, b, st, PP_TWO, float(i), 0.0)
        rc = _cl_member_to(i, t, st, tref, bint, bflt, planes, grav, tz, zp, ws, tolf, toli,
                           pose, pm, pv, pw, fw, err)
        if rc < 0:
            return rc
        for q2 in range(pairs.shape[0]):
            if pr_off[q2] == PR_OFF:
                continue
            j = -1
            if pairs[q2, 0] == i:
                j = pairs[q2, 1]
            elif pairs[q2, 1] == i:
                j = pairs[q2, 0]
            if j < 0 or bint[j, B_KIND] != SH_SPHERE or pm[j, M_MODE] == PM_PIVOT:
                continue
            known = False
            for r in range(n):
                if cid[CL_HDR + r] == j:
                    known = True
            if known:
                continue
            xj, yj, zj, u0, u1, u2, a0, a1, a2 = _centre_motion(st, tref, j, t, tz, zp, planes)
            g = (math.sqrt((xj - st[i, SX]) ** 2 + (yj - st[i, SX + 1]) ** 2
                           + (zj - st[i, SX + 2]) ** 2) - bflt[i, B_RADIUS] - bflt[j, B_RADIUS])
            if g <= gtol and n < nb:
                cid[CL_HDR + n] = j
                n += 1
    cid[CL_N] = n
    ids = cid[CL_HDR:CL_HDR + n]
    for r in range(n):
        i = ids[r]
        for j in range(cl.NS):
            cbod[r, j] = st[i, j]
        cbod[r, cl.CB_M] = bflt[i, B_MASS]
        cbod[r, cl.CB_I] = bflt[i, B_I1]
        cbod[r, cl.CB_R] = bflt[i, B_RADIUS]
        cbod[r, cl.CB_FIXED] = 0.0
    # contacts (active within gap_tol) and candidates: the pairs among the members, then
    # the members' planes
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
        g = (math.sqrt((st[i, SX] - st[j, SX]) ** 2 + (st[i, SX + 1] - st[j, SX + 1]) ** 2
                       + (st[i, SX + 2] - st[j, SX + 2]) ** 2)
             - bflt[i, B_RADIUS] - bflt[j, B_RADIUS])
        k = nk if g <= gtol else cl.KMAX + nc
        if (g <= gtol and nk >= cl.KSEL_MAX) or (g > gtol and nc >= NCAND):
            cid[CL_N] = 0
            return _cl_refuse(err, t, a, b, st, PP_CLUSTER, float(cl.CS_TOO_MANY_CONTACTS),
                              0.0 if g <= gtol else 1.0)
        _cl_row(ccon, cid, nb, k, cl.KIND_SPHERE, ra, rb, 0.0, 0.0, 0.0, 0.0,
                law_par[pairs[q2, 2], P_MU], -2 - q2)
        if g <= gtol:
            nk += 1
        else:
            nc += 1
    for r in range(n):
        i = ids[r]
        for p in range(planes.shape[0]):
            if bp_off[i, p] != 0:
                continue
            g = (planes[p, 0] * st[i, SX] + planes[p, 1] * st[i, SX + 1]
                 + planes[p, 2] * st[i, SX + 2] - planes[p, 3] - bflt[i, B_RADIUS])
            k = nk if g <= gtol else cl.KMAX + nc
            if (g <= gtol and nk >= cl.KSEL_MAX) or (g > gtol and nc >= NCAND):
                cid[CL_N] = 0
                return _cl_refuse(err, t, a, b, st, PP_CLUSTER,
                                  float(cl.CS_TOO_MANY_CONTACTS), 0.0 if g <= gtol else 1.0)
            _cl_row(ccon, cid, nb, k, cl.KIND_PLANE, r, -1, planes[p, 0], planes[p, 1],
                    planes[p, 2], planes[p, 3], law_par[bp_law[i, p], P_MU], p)
            if g <= gtol:
                nk += 1
            else:
                nc += 1
    cid[CL_NK] = nk
    cid[CL_NC] = nc
    e0 = _cl_energy(st, bflt, grav, cid)
    L = _cl_scale(cid, bflt)
    la = cwk[:cl.N_LA]
    w = cwk[cl.N_LA:]
    bod = cbod[:n]
    con = ccon[:cl.KMAX]
    cs = cl.cluster_project(bod, con, nk, grav[0], grav[1], grav[2], L, w, la)
    if cs == cl.CS_OK:
        cs = cl.cluster_select_modes(bod, con, nk, grav[0], grav[1], grav[2], L, w, la)
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
            if _cl_lift(ccon, cid, nb, k) < 0:
                cid[CL_N] = 0
                return _cl_refuse(err, t, a, b, st, PP_CLUSTER,
                                  float(cl.CS_TOO_MANY_CONTACTS), 1.0)
        else:
            k += 1
    for r in range(n):
        i = ids[r]
        for j in range(cl.NS):
            st[i, j] = cbod[r, j]
        for j in range(3):
            st[i, SA + j] = 0.0
            st[i, SAL + j] = 0.0
        pm[i, M_MODE] = PM_CLUSTER
        pm[i, M_AUX] = 0
        tz[i] = INF
        ttr[i] = INF
        bt[i] = INF
        ws[i, WS_MODE] = -1.0
    for q2 in range(pairs.shape[0]):
        if pm[pairs[q2, 0], M_MODE] == PM_CLUSTER and pm[pairs[q2, 1], M_MODE] == PM_CLUSTER:
            pr_t[q2] = INF
            if pr_off[q2] == PR_HIT:
                pr_off[q2] = PR_ON
    cid[CL_LEAD] = ids[0]
    cid[CL_EV] = cl.CE_NONE
    cid[CL_FROZEN] = 0
    cid[CL_CHAT] = 0
    # the event names the pair's contact (its row, if still active, else row 0)
    kq = 0
    for kk in range(cid[CL_NK]):
        if cid[CL_HDR + nb + kk] == -2 - q:
            kq = kk
    _cl_log(ev_t, ev_i, ev_f, cnt, t, EV_CONTACT, a, b, n, c_f, MAXC - 1, st, bflt, ccon, kq,
            _cl_energy(st, bflt, grav, cid) - e0)
    for r in range(n):
        bmark[ids[r]] = 1
    if _cl_pairs_left(ccon, cid) == 0:
        # every sphere-sphere contact lifts at once: no cluster
        return _cluster_dissolve(True, t, st, tref, bint, bflt, planes, grav, law_par,
                                 bp_law, pm, tz, ttr, tolf, cbod, ccon, cid, bmark, ev_t, ev_i,
                                 ev_f, cnt, c_f, err)
    ttr[ids[0]] = t
    return 0


@njit(cache=True)
def _cl_members_fly(t, st, tref, grav, pm, tz, ttr, cbod, cid, bmark):
    """The cluster ends at t: every member takes its state from cbod and flies from t
    (marked); the cluster header is cleared. Returns the number of members."""
    n = cid[CL_N]
    for r in range(n):
        i = cid[CL_HDR + r]
        for j in range(cl.NS):
            st[i, j] = cbod[r, j]
        for j in range(3):
            st[i, SA + j] = grav[j]
            st[i, SAL + j] = 0.0
        tref[i] = t
        pm[i, M_MODE] = PM_FLIGHT
        pm[i, M_AUX] = 0
        tz[i] = INF
        ttr[i] = INF
        bmark[i] = 1
    cid[CL_N] = 0
    cid[CL_LEAD] = -1
    cid[CL_EV] = cl.CE_NONE
    cid[CL_FROZEN] = 0
    return n


@njit(cache=True)
def _cluster_dissolve(settle, t, st, tref, bint, bflt, planes, grav, law_par, bp_law, pm, tz,
                      ttr, tolf, cbod, ccon, cid, bmark, ev_t, ev_i, ev_f, cnt, c_f, err):
    """End the cluster at t (states in cbod): every member flies from t, or (``settle``)
    settles on a plane it still touches through an active contact (``_settle``: rest, roll
    or slide on it; the loop integrates a slide across a slope). Members marked; their
    segments are recorded by the caller. Returns 0 or an error code."""
    n = _cl_members_fly(t, st, tref, grav, pm, tz, ttr, cbod, cid, bmark)
    nb = st.shape[0]
    for r in range(n):
        i = cid[CL_HDR + r]
        if settle:
            for k in range(cid[CL_NK]):
                if (ccon[k, cl.CC_KIND] == cl.KIND_PLANE and int(ccon[k, cl.CC_A]) == r
                        and pm[i, M_MODE] == PM_FLIGHT):
                    p = cid[CL_HDR + nb + k]
                    rc = _settle(i, p, t, st, bint, bflt, planes, grav, law_par, bp_law, pm,
                                 ttr, False, ev_t, ev_i, ev_f, cnt, c_f, MAXC - 1, tolf, err)
                    if rc < 0:
                        return rc
                    if rc != 0:     # no rest there: it flies
                        pm[i, M_MODE] = PM_FLIGHT
                        for j in range(3):
                            st[i, SA + j] = grav[j]
                            st[i, SAL + j] = 0.0
                        ttr[i] = INF
        if not _finite(st, i):
            _set_err(err, t, i, 0, st[i, SX], st[i, SX + 1], st[i, SX + 2], 0.0, 0.0, 0.0)
            return ERR_NONFINITE
    return 0


@njit(cache=True)
def _cluster_to_instant(t, extra, st, tref, grav, pm, tz, ttr, bt, bpl, bft, pr_t, cbod, ccon,
                        cid, bmark):
    """The cluster dissolves into flight at t for an impact there: every member is due at t
    (``bt``), its plane contacts (and candidate ``extra`` >= 0, the closing one, named by
    ``bpl``/``bft``) and its pairs' (``pr_t``) in the instant, so that the impact step
    resolves them in one cluster (the closing contact with the held ones at v_N = 0)."""
    nb = st.shape[0]
    nk = cid[CL_NK]
    for r in range(cid[CL_N]):
        i = cid[CL_HDR + r]
        bt[i] = t
        bpl[i] = -1
        bft[i] = -1
    for kk in range(nk + 1):
        k = kk
        if kk == nk:
            if extra < 0:
                break
            k = cl.KMAX + extra
        src = cid[CL_HDR + nb + k]
        if src >= 0:
            i = cid[CL_HDR + int(ccon[k, cl.CC_A])]
            if bpl[i] < 0 or kk == nk:
                bpl[i] = src
                bft[i] = 0
        else:
            pr_t[-2 - src] = t
    _cl_members_fly(t, st, tref, grav, pm, tz, ttr, cbod, cid, bmark)


@njit(cache=True)
def _cluster_pass(t, st, tref, bint, bflt, planes, grav, law_par, bp_law, pm, tz, ttr, bt, bpl,
                  bft, pr_t, pr_off, tolf, cbod, ccon, cwk, cid, bmark, ev_t, ev_i, ev_f, seg_t,
                  seg_b, seg_s, cnt, c_f, err):
    """The cluster's event due at t (its leader's ttr), then its next integration pass
    (``cluster3d.cluster_advance``, recorded). Returns (rc, action): action 0 a pass ran
    (members marked), 1 the cluster dissolved or froze (members marked), 2 an impact is
    pending at t (the impact step)."""
    nb = st.shape[0]
    n = cid[CL_N]
    lead = cid[CL_LEAD]
    ttr[lead] = INF
    ev = cid[CL_EV]
    idx = cid[CL_IDX]
    cid[CL_EV] = cl.CE_NONE
    L = _cl_scale(cid, bflt)
    la = cwk[:cl.N_LA]
    w = cwk[cl.N_LA:]
    bod = cbod[:n]
    con = ccon[:cl.KMAX]
    cand = ccon[cl.KMAX:]
    ids = cid[CL_HDR:CL_HDR + n]
    gx = grav[0]
    gy = grav[1]
    gz = grav[2]
    cw = MAXC - 1
    if ev == cl.CE_GAP:
        _cluster_to_instant(t, idx, st, tref, grav, pm, tz, ttr, bt, bpl, bft, pr_t, cbod,
                            ccon, cid, bmark)
        return 0, 2
    if ev == cl.CE_LEAVE or ev == cl.CE_SLIP or ev == cl.CE_STOP:
        k = idx
        a = ids[int(ccon[k, cl.CC_A])]
        src = cid[CL_HDR + nb + k]
        b = -1 - src if src >= 0 else ids[int(ccon[k, cl.CC_B])]
        # stick-slip chatter: mode events closer than CL_CHAT_RTOL T apart (T =
        # sqrt(L / |g|)); from the third, the modes of every contact are chosen again;
        # CL_CHAT_MAX of them: refused (stepper2d's rule)
        gl = math.sqrt(gx * gx + gy * gy + gz * gz)
        vmax = 0.0
        for r in range(n):
            vmax = max(vmax, math.sqrt(bod[r, cl.CB_VX] ** 2 + bod[r, cl.CB_VX + 1] ** 2
                                       + bod[r, cl.CB_VX + 2] ** 2))
        T = math.sqrt(L / gl) if gl > 0.0 else L / max(vmax, 1e-300)
        ti = cwk.shape[0] - 1
        if cid[CL_CHAT] > 0 and t - cwk[ti] <= CL_CHAT_RTOL * T:
            cid[CL_CHAT] += 1
        else:
            cid[CL_CHAT] = 1
        cwk[ti] = t
        if cid[CL_CHAT] >= CL_CHAT_MAX:
            return _cl_refuse(err, t, a, b, st, PP_STICK_SLIP, float(cid[CL_CHAT]), t), 0
        mo = ti - 1 - cl.KMAX       # the modes before the event
        for kk in range(cid[CL_NK]):
            cwk[mo + kk] = ccon[kk, cl.CC_MODE]
        if cid[CL_CHAT] >= 3 and ev != cl.CE_LEAVE:
            cs = cl.cluster_select_modes(bod, con, cid[CL_NK], gx, gy, gz, L, w, la)
        else:
            cs = cl.cluster_after_event(bod, con, cid[CL_NK], ev, k, gx, gy, gz, L, w, la)
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
        for r in range(n):      # the members' states at t, for the event's point
            for j in range(cl.NS):
                st[ids[r], j] = cbod[r, j]
        _cl_log(ev_t, ev_i, ev_f, cnt, t, kind, a, b, n, c_f, cw, st, bflt, ccon, k, 0.0)
        # the other contacts whose mode the event changed (a slip stopping with it: stick;
        # lift-offs are logged below)
        for kk in range(cid[CL_NK]):
            mode = ccon[kk, cl.CC_MODE]
            if kk == k or mode == cwk[mo + kk] or mode == cl.MODE_LIFT:
                continue
            src = cid[CL_HDR + nb + kk]
            _cl_log(ev_t, ev_i, ev_f, cnt, t, EV_STICK if mode == cl.MODE_STICK else EV_SLIDE,
                    ids[int(ccon[kk, cl.CC_A])],
                    -1 - src if src >= 0 else ids[int(ccon[kk, cl.CC_B])], n, c_f, cw, st,
                    bflt, ccon, kk, 0.0)
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
            if kk != k:
                _cl_log(ev_t, ev_i, ev_f, cnt, t, EV_RELEASE, a2, b2, n, c_f, cw, st, bflt,
                        ccon, kk, 0.0)
            if src < 0:
                pr_off[-2 - src] = PR_REL
            if _cl_lift(ccon, cid, nb, kk) < 0:
                return _cl_refuse(err, t, a2, a2, st, PP_CLUSTER,
                                  float(cl.CS_TOO_MANY_CONTACTS), 1.0), 0
        if lifted:
            if _cl_pairs_left(ccon, cid) == 0:
                rc = _cluster_dissolve(True, t, st, tref, bint, bflt, planes, grav, law_par,
                                       bp_law, pm, tz, ttr, tolf, cbod, ccon, cid, bmark, ev_t,
                                       ev_i, ev_f, cnt, c_f, err)
                return rc, 1
            # a member with no active contact left would fly inside the cluster: not built
            for r in range(n):
                held = False
                for kk in range(cid[CL_NK]):
                    if int(ccon[kk, cl.CC_A]) == r or int(ccon[kk, cl.CC_B]) == r:
                        held = True
                if not held:
                    return _cl_refuse(err, t, ids[r], ids[r], st, PP_SPLIT, 0.0, 0.0), 0
    k0 = cnt[evbuf.CN_SEGS]
    cs, ev, idx, ts = cl.cluster_advance(bod, con, cid[CL_NK], cand, cid[CL_NC], gx, gy, gz, L,
                                         t, tolf[TF_T_END], w, la, seg_t, seg_b, seg_s, cnt,
                                         ids)
    for k in range(k0, cnt[evbuf.CN_SEGS]):
        seg_s[k, cl.N_ROW] = 0.0        # a closed-form row (flight3d.pose_at replays it)
    if cs == cl.CS_REST:
        # frozen: nothing moves until a body outside hits it
        for r in range(n):
            i = ids[r]
            for j in range(3):
                st[i, SX + j] = cbod[r, cl.CB_X + j]
            for j in range(4):
                st[i, SQ + j] = cbod[r, cl.CB_QW + j]
            for j in range(SV, 19):
                st[i, j] = 0.0
            for j in range(3):
                cbod[r, cl.CB_VX + j] = 0.0
                cbod[r, cl.CB_WX + j] = 0.0
            tref[i] = t
            bmark[i] = 1
        if cid[CL_FROZEN] == 0:
            i = ids[0]
            _cl_log(ev_t, ev_i, ev_f, cnt, t, EV_REST, i, ids[1], n, c_f, cw, st, bflt, ccon,
                    0, 0.0)
        cid[CL_FROZEN] = 1
        return 0, 1
    if cs != cl.CS_OK:
        return _cl_refuse(err, t, lead, lead, st, PP_CLUSTER, float(cs), 0.0), 0
    for r in range(n):
        i = ids[r]
        for j in range(cl.NS):
            st[i, j] = cbod[r, j]
        if not _finite(st, i):
            _set_err(err, ts, i, 0, st[i, SX], st[i, SX + 1], st[i, SX + 2], 0.0, 0.0, 0.0)
            return ERR_NONFINITE, 0
        tref[i] = ts
    cid[CL_EV] = ev
    cid[CL_IDX] = idx
    ttr[lead] = INF if (ev == cl.CE_NONE and ts >= tolf[TF_T_END]) else ts
    return 0, 0


@njit(cache=True)
def _cluster_hit(t, st, tref, grav, pairs, pm, tz, ttr, bt, bpl, bft, pr_t, tolf, cbod, ccon,
                 cid, bmark):
    """A body outside a frozen cluster meets a member within this instant: the cluster
    dissolves into the instant (``_cluster_to_instant``)."""
    tw = t + tolf[TF_SIMUL_TIME]
    for q in range(pairs.shape[0]):
        if pr_t[q] <= tw and (pm[pairs[q, 0], M_MODE] == PM_CLUSTER
                              or pm[pairs[q, 1], M_MODE] == PM_CLUSTER):
            _cluster_to_instant(t, -1, st, tref, grav, pm, tz, ttr, bt, bpl, bft, pr_t, cbod,
                                ccon, cid, bmark)
            return


def scene_features(bint, planes, grav, n_pairs):
    """The feature switches ``(pivot, pair, pgen, joint)`` of a scene (True, or None when
    the scene cannot reach that mode; ``codes.FEATURES``): a box or a capsule can be held
    on a point or an edge (pivot3d), and a sphere on a plane that gravity does not meet
    square-on (its slip can curve across the slope: integrated contact); boxes and
    capsules touch with several points at once; body pairs (``pair``), with a pair of other
    shapes than two spheres (``pgen``: ``pair3d``, ``pair3d_toi``, ``pair3d_manifold``);
    several contacts at one instant (joint solve) with boxes, capsules, two planes or
    pairs. ``planes`` float64[np, 4] (unit normal, offset), ``grav`` float64[3] (m/s^2)."""
    kinds = {int(k) for k in bint[:, 0]}
    n_planes = len(planes)
    g = np.asarray(grav, float)
    sloped = any(np.any(np.cross(np.asarray(pl[:3], float), g) != 0.0) for pl in planes)
    pivot = SH_BOX in kinds or SH_CAPSULE in kinds or (SH_SPHERE in kinds and sloped)
    pair = n_pairs > 0
    pgen = pair and kinds != {SH_SPHERE}
    joint = pivot or pair or n_planes >= 2
    return tuple(True if on else None for on in (pivot, pair, pgen, joint))


#: the feature switches of the general loop, every mode compiled (``scene_features``)
ALL_FEATURES = (True, True, True, True)


@njit(cache=True)
def _not_compiled(err, t, i, feature):
    """A handler of ``feature`` reached in a loop compiled without it (``scene_features``
    is wrong: a bug, reported, never skipped)."""
    _set_err(err, t, i, 0, float(feature), 0.0, 0.0, 0.0, 0.0, 0.0)
    return ERR_NOT_COMPILED


@functools.lru_cache(maxsize=None)
def loop_for(law):
    """The event loop compiled for one law (a ``LAW_*`` of ``common``, or ``LAW_ANY`` for a
    scene with several laws: dispatched per contact). The law is a plain int closed over:
    Numba prunes the other laws before typing and caches each law's loop on disk under its
    own key (issue 14)."""
    law = int(law)

    @njit(cache=True)
    def run_loop(bint, bflt, feats, planes, grav, law_ids, law_par, bp_law, pairs, tolf,
                 toli, st, tref, pm, tz, zp, ttr, bt, bpl, bft, bp_off, pr_t, pr_off, ws,
                 glob, cnt, pk, pv, pw, ev_t, ev_i, ev_f, seg_t, seg_b, seg_s, c_i, c_f, Wb,
                 Pb, vb, tb, comp, bmark, v3, W3, P3, Ii, skip, pose, fw, ybuf, vals, vals0,
                 vfl, pscr, pmf, pfe, cbod, ccon, cwk, cid, err, pivot, pair, pgen, joint):
        """Advance from glob[0] to tolf[TF_T_END]; see the module docstring for the
        contract. ``pivot``, ``pair``, ``pgen``, ``joint``: the scene's feature switches
        (``scene_features``; ``pgen``: pairs of other shapes than two spheres)."""
        nb = st.shape[0]
        npl = planes.shape[0]
        npr = pairs.shape[0]
        t_end = tolf[TF_T_END]
        max_events = toli[TI_MAX_EVENTS]
        margin_e = evbuf.event_margin(toli[TI_SEQ_MAXSTEPS], MAXC, nb)
        margin_s = evbuf.segment_margin(MAXC, nb) + cl.PIECE_BUDGET
        cap_e = ev_t.shape[0]
        cap_s = seg_t.shape[0]
        policy = toli[TI_POLICY]
        capture_on = toli[TI_CAPTURE] != 0
        no_capture = tolf[TF_T_END] < -INF     # False, typed at run time (no literal copy)
        cw = MAXC - 1   # scratch row of c_f for persistent-contact events
        while True:
            t_now = glob[0]
            tmin = INF
            for i in range(nb):
                if tz[i] < tmin:
                    tmin = tz[i]
                if ttr[i] < tmin:
                    tmin = ttr[i]
                if bt[i] < tmin:
                    tmin = bt[i]
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
                _set_err(err, t_now, -1, 0, 0.0, 0.0, 0.0, cnt[evbuf.CN_IDLE], 0.0, 0.0)
                return ERR_IDLE
            if tmin <= t_now:
                tmin = t_now
                cnt[evbuf.CN_STALL] += 1
                if cnt[evbuf.CN_STALL] > toli[TI_STALL]:
                    _set_err(err, t_now, -1, 0, 0.0, 0.0, 0.0, cnt[evbuf.CN_STALL], 0.0, 0.0)
                    return ERR_STALL
            else:
                cnt[evbuf.CN_STALL] = 0
            t = tmin
            glob[0] = t

            # ---- persistent sphere contact (a cluster): entry, its passes, a hit when frozen
            cact = -1
            if pair is not None:
                if cid[CL_PEND] >= 0:
                    for i in range(nb):
                        bmark[i] = 0
                    rc = _cluster_enter(t, st, tref, bint, bflt, planes, grav, law_par, bp_law,
                                        bp_off, pairs, pr_off, pr_t, pm, tz, zp, ttr, bt, ws,
                                        tolf, toli, pose, pv, pw, fw, cbod, ccon, cwk, cid,
                                        bmark, ev_t, ev_i, ev_f, cnt, c_f, err)
                    if rc < 0:
                        return rc
                    cact = 1 if cid[CL_N] == 0 else 0   # dissolved at once: record, search
                elif cid[CL_N] > 0 and ttr[cid[CL_LEAD]] <= t:
                    for i in range(nb):
                        bmark[i] = 0
                    rc, cact = _cluster_pass(t, st, tref, bint, bflt, planes, grav, law_par,
                                             bp_law, pm, tz, ttr, bt, bpl, bft, pr_t, pr_off,
                                             tolf, cbod, ccon, cwk, cid, bmark, ev_t, ev_i,
                                             ev_f, seg_t, seg_b, seg_s, cnt, c_f, err)
                    if rc < 0:
                        return rc
                    if cact == 0:
                        continue    # a pass ran (recorded): nothing else changed
                elif cid[CL_N] > 0 and cid[CL_FROZEN] != 0:
                    # (no bmark reset: a hit dissolves it into the impact step, which marks
                    # the bodies due at t itself)
                    _cluster_hit(t, st, tref, grav, pairs, pm, tz, ttr, bt, bpl, bft, pr_t,
                                 tolf, cbod, ccon, cid, bmark)
            if cact == 0 or cact == 1:
                # entered (members' passes record their motion from t), or dissolved or
                # frozen (segments from t); then the members' planes and pairs
                for i in range(nb):
                    if bmark[i] == 0:
                        continue
                    if cact == 1 or pm[i, M_MODE] != PM_CLUSTER:
                        ws[i, WS_MODE] = -1.0
                        _push_seg(seg_t, seg_b, seg_s, cnt, st, tref, i, pm, pv)
                    rc = _recompute_motion(i, t, st, tref, bint, bflt, feats, planes, pm, tz,
                                           zp, bt, bpl, bft, bp_off, ws, tolf, toli, skip,
                                           pose, err, ttr, pk, pv, pw, fw, ybuf, vals, vals0,
                                           vfl, c_f[MAXC - 2], pivot)
                    if rc < 0:
                        return rc
                rc = _recompute_pairs(t, st, tref, bint, bflt, planes, grav, pairs, pm, tz, zp,
                                      ttr, bt, pr_t, pr_off, ws, pv, pw, fw, tolf, toli, pscr,
                                      pfe, bmark, err, pair, pgen, cid)
                if rc < 0:
                    return rc
                continue

            # ---- scheduled switches: accumulation points, end of slip, integrated contacts
            did = False
            for i in range(nb):
                recompute = True
                if pm[i, M_MODE] == PM_CLUSTER:
                    continue        # its cluster's passes (above)
                if tz[i] <= t:
                    p = zp[i]
                    tz[i] = INF
                    rc = _bring(i, t, st, tref, bint, bflt, ws, tolf, toli, pose, pm, pv, pw,
                                fw, err)
                    if rc < 0:
                        return rc
                    rc = _settle(i, p, t, st, bint, bflt, planes, grav, law_par, bp_law, pm,
                                 ttr, no_capture, ev_t, ev_i, ev_f, cnt, c_f, cw, tolf, err)
                    if rc == RC_TIP:
                        rc = _tip(i, t, st, bint, bflt, feats, planes, grav, law_par, bp_law,
                                  pm, ttr, tz, tolf, pv, fw, ev_t, ev_i, ev_f, cnt, c_f, cw,
                                  Ii, err, pivot)
                    if rc < 0:
                        return rc
                elif ttr[i] <= t and pm[i, M_MODE] == PM_PIVOT:
                    if pivot is None:
                        return _not_compiled(err, t, i, FEATURE_PIVOT)
                    rc, recompute = _pivot_event(i, t, st, tref, bint, bflt, grav, law_par,
                                                 bp_law, pm, ttr, tz, bt, bpl, bft, pk, pv,
                                                 pw, fw, ws, tolf, toli, pose, ev_t, ev_i,
                                                 ev_f, cnt, c_f, cw, Ii, err)
                    if rc < 0:
                        return rc
                    if recompute and _sphere_stuck(i, bint, pm, pv):
                        rc = _sphere_rolls(i, t, st, bint, bflt, planes, grav, law_par,
                                           bp_law, pm, ttr, pv, tolf, ev_t, ev_i, ev_f,
                                           cnt, c_f, cw, err)
                        q = -1 if rc != 0 else _pressed_plane(i, st, bflt, planes,
                                                               bp_off, pm, tolf)
                        if q >= 0:
                            # rolling on its plane presses it into another it touches
                            # (the groove's other plane): held by both
                            rc = _groove_enter(i, pm[i, M_PLANE], q, t, st, bflt, planes,
                                               grav, law_par, bp_law, pm, ttr, tolf, ev_t,
                                               ev_i, ev_f, cnt, c_f, cw, err)
                            if rc == GROOVE_SLIPS:
                                rc = _groove_slide(i, pm[i, M_PLANE], q, t, st, bint, bflt,
                                                   feats, planes, grav, law_par, bp_law,
                                                   pm, ttr, tz, tolf, pv, fw, ev_t, ev_i,
                                                   ev_f, cnt, c_f, cw, Ii, err, pivot)
                            elif rc == 1:
                                _set_err(err, t, i, -1 - q, st[i, SX], st[i, SX + 1],
                                         st[i, SX + 2], 3.0, 0.0, 0.0)
                                rc = ERR_UNSUPPORTED
                        if rc < 0:
                            return rc
                    elif (recompute and pm[i, M_MODE] == PM_PIVOT
                          and bint[i, B_KIND] == SH_SPHERE and pv[i, CP_S] == 1.0
                          and pv[i, (CP_S + 1)] == 1.0):
                        # both contacts of a sphere in a groove stick: it rolls along
                        # the groove in closed form (or keeps integrating if not)
                        rc = _groove_enter(i, int(pv[i, CP_PLANE]), int(pv[i, (CP_PLANE + 1)]),
                                           t, st, bflt, planes, grav, law_par, bp_law, pm,
                                           ttr, tolf, ev_t, ev_i, ev_f, cnt, c_f, cw, err)
                        if rc > 0:
                            rc = 0
                        if rc < 0:
                            return rc
                elif (ttr[i] <= t and pm[i, M_MODE] == PM_SLIDE
                      and pm[i, M_AUX] == AUX_INTEGRATE):
                    if pivot is None:
                        return _not_compiled(err, t, i, FEATURE_PIVOT)
                    rc = _integrate_slide(i, t, st, tref, bint, bflt, feats, planes, grav,
                                          law_par, bp_law, pm, ttr, tz, ws, tolf, toli, pose,
                                          pv, pw, fw, ev_t, ev_i, ev_f, cnt, c_f, cw, Ii, err)
                    if rc < 0:
                        return rc
                elif ttr[i] <= t:
                    rc = _transition(i, t, st, tref, bint, bflt, planes, grav, law_par, bp_law,
                                     pm, ttr, ws, tolf, toli, ev_t, ev_i, ev_f, cnt, c_f, cw,
                                     pose, err, pv, pw, fw)
                    if rc == RC_TIP:
                        rc = _tip(i, t, st, bint, bflt, feats, planes, grav, law_par, bp_law,
                                  pm, ttr, tz, tolf, pv, fw, ev_t, ev_i, ev_f, cnt, c_f, cw,
                                  Ii, err, pivot)
                    if rc < 0:
                        return rc
                else:
                    continue
                if not _finite(st, i):
                    _set_err(err, t, i, 0, st[i, SX], st[i, SX + 1], st[i, SX + 2], 0.0, 0.0,
                             0.0)
                    return ERR_NONFINITE
                if not recompute:
                    continue
                did = True
                ws[i, WS_MODE] = -1.0
                _push_seg(seg_t, seg_b, seg_s, cnt, st, tref, i, pm, pv)
                rc = _recompute_motion(i, t, st, tref, bint, bflt, feats, planes, pm, tz, zp,
                                       bt, bpl, bft, bp_off, ws, tolf, toli, skip, pose, err,
                                       ttr, pk, pv, pw, fw, ybuf, vals, vals0, vfl,
                                       c_f[MAXC - 2], pivot)
                if rc < 0:
                    return rc
                if npr > 0:
                    for j in range(nb):
                        bmark[j] = 0
                    bmark[i] = 1
                    rc = _recompute_pairs(t, st, tref, bint, bflt, planes, grav, pairs, pm, tz,
                                          zp, ttr, bt, pr_t, pr_off, ws, pv, pw, fw, tolf,
                                          toli, pscr, pfe, bmark, err, pair, pgen, cid)
                    if rc < 0:
                        return rc
            if did:
                continue

            # ---- impacts: gather every contact touching within [t, t + simul_time]
            tw = t + tolf[TF_SIMUL_TIME]
            nc = np.int64(0)
            for i in range(nb):
                bmark[i] = 0
                if bt[i] <= tw:
                    bmark[i] = 1
            for q in range(npr):
                if pr_t[q] <= tw and pr_off[q] == PR_CHECK:
                    # a held body's pair is due for its distance check, not an impact
                    rc = _recompute_pair(pgen, q, t, st, tref, bint, bflt, planes, grav,
                                         pairs, pm, tz, zp, ttr, bt, pr_t, pr_off, ws, pv,
                                         pw, fw, tolf, toli, pscr, pfe, err, cid)
                    if rc < 0:
                        return rc
                elif pr_t[q] <= tw:
                    bmark[pairs[q, 0]] = 1
                    bmark[pairs[q, 1]] = 1
            # bring the bodies involved to t; a pending accumulation point is cancelled: the
            # body continues from its held motion (the normal energy of the unfinished
            # accumulation, below the threshold m zeno_speed^2 / 2, is dropped without event)
            for i in range(nb):
                if bmark[i] != 0:
                    held = tz[i] < INF
                    if held:
                        zq = zp[i]
                        _held_into(st[i], bint[i, B_KIND], planes[zq, 0], planes[zq, 1],
                                   planes[zq, 2], st[i])
                        ws[i, WS_MODE] = -1.0
                    rc = _bring(i, t, st, tref, bint, bflt, ws, tolf, toli, pose, pm, pv, pw,
                                fw, err)
                    if rc < 0:
                        return rc
                    if held:
                        # in flight again from t, under gravity: the held row lacks the
                        # normal part of its acceleration (kept, a sphere bounced off a
                        # wall in a corner flew on without gravity, rising 9e-6 m off the
                        # floor and gaining 5e-3 J, 'done'; the 2D twin: stepper2d._gather)
                        for j in range(3):
                            st[i, SA + j] = grav[j]
                            st[i, SAL + j] = 0.0
                    tz[i] = INF
            for i in range(nb):
                if bt[i] > tw:
                    continue
                f0 = bint[i, B_FIRST]
                nf = bint[i, B_COUNT]
                rad = bflt[i, B_RADIUS]
                q0, q1, q2, q3 = st[i, SQ], st[i, SQ + 1], st[i, SQ + 2], st[i, SQ + 3]
                piv = pm[i, M_MODE] == PM_PIVOT
                # a box or capsule held on a face or a side (or at rest on two planes) that
                # hits another plane: the features touching its held plane take part in the
                # impact (sweep 1), and it is in flight after it (_after_impact decides
                # what persists, as below for a pivot). Resolved alone, the hit let the
                # held mode's projection (_reevaluate) drive the edge back into the other
                # plane at once: a box sliding into a groove's crease took 1500 impacts at
                # one instant, decaying by 0.62 each, and stalled (3:944403545).
                face = (not piv and bint[i, B_KIND] != SH_SPHERE
                        and (pm[i, M_MODE] == PM_SLIDE or pm[i, M_MODE] == PM_ROLL
                             or pm[i, M_MODE] == PM_REST or pm[i, M_MODE] == PM_WEDGED))
                n0 = nc
                for sweep in range(2):
                    if sweep == 1 and not (face and nc > n0):
                        break
                    for p in range(npl):
                        if bp_off[i, p] != 0:
                            continue
                        if (not piv and _holds(pm, i, p)) != (sweep == 1):
                            continue
                        nx = planes[p, 0]
                        ny = planes[p, 1]
                        nz = planes[p, 2]
                        for k in range(nf):
                            rx, ry, rz = qrot(q0, q1, q2, q3, feats[f0 + k, 0],
                                              feats[f0 + k, 1], feats[f0 + k, 2])
                            g = (nx * (st[i, SX] + rx) + ny * (st[i, SX + 1] + ry)
                                 + nz * (st[i, SX + 2] + rz) - planes[p, 3] - rad)
                            if sweep == 1:
                                take = g <= tolf[TF_GAP_TOL]
                            else:
                                ux, uy, uz = _point_vel(st, i, rx, ry, rz)
                                gd = nx * ux + ny * uy + nz * uz
                                take = gd < 0.0 and g + gd * (tw - t) <= 0.0
                                if p == bpl[i] and k == bft[i]:
                                    take = True
                            if piv:
                                for c in range(int(pv[i, CP_K])):
                                    if (p == int(pv[i, CP_PLANE + c])
                                            and f0 + k == int(pv[i, CP_F + c])):
                                        take = True
                            if not take:
                                continue
                            if nc >= MAXC - 1:
                                _set_err(err, t, i, -1 - p, st[i, SX], st[i, SX + 1],
                                         st[i, SX + 2], MAXC - 1, 0.0, 0.0)
                                return ERR_TOO_MANY
                            c_i[nc, CI_TYPE] = 0
                            c_i[nc, CI_A] = i
                            c_i[nc, CI_B] = p
                            c_i[nc, CI_FEAT] = f0 + k
                            c_i[nc, CI_LAW] = bp_law[i, p]
                            c_i[nc, CI_OFF] = 0
                            _frame(c_f, nc, nx, ny, nz)
                            for j in range(3):
                                r = (rx, ry, rz)[j] - rad * planes[p, j]
                                c_f[nc, CF_RA + j] = r
                                c_f[nc, CF_RB + j] = 0.0
                                c_f[nc, CF_P + j] = st[i, j] + r
                            nc += 1
                if piv or (face and nc > n0):
                    # the integrated or held contact ends with the impact: the body is in
                    # flight at t (after the impacts, _after_impact decides what persists)
                    pm[i, M_MODE] = PM_FLIGHT
                    ttr[i] = INF
                    for j in range(3):
                        st[i, SA + j] = grav[j]
                        st[i, SAL + j] = 0.0
            for q in range(npr):
                if pr_t[q] > tw or pr_off[q] == PR_CHECK:
                    continue
                if nc >= MAXC - 1:
                    _set_err(err, t, pairs[q, 0], pairs[q, 1], 0.0, 0.0, 0.0, MAXC - 1, 0.0,
                             0.0)
                    return ERR_TOO_MANY
                a = pairs[q, 0]
                b = pairs[q, 1]
                if not (bint[a, B_KIND] == SH_SPHERE and bint[b, B_KIND] == SH_SPHERE):
                    if pgen is None:
                        return _not_compiled(err, t, a, FEATURE_PAIR)
                    nc = _pair_contacts(q, nc, t, st, bint, bflt, pairs, ws, tolf, toli, c_i,
                                        c_f, pscr, pmf, pfe, err)
                    if nc < 0:
                        return nc
                    continue
                c_i[nc, CI_TYPE] = 1
                c_i[nc, CI_A] = a
                c_i[nc, CI_B] = b
                c_i[nc, CI_FEAT] = -1
                c_i[nc, CI_LAW] = pairs[q, 2]
                c_i[nc, CI_OFF] = 0
                dx = st[a, SX] - st[b, SX]
                dy = st[a, SX + 1] - st[b, SX + 1]
                dz = st[a, SX + 2] - st[b, SX + 2]
                dist = math.sqrt(dx * dx + dy * dy + dz * dz)
                _frame(c_f, nc, dx / dist, dy / dist, dz / dist)
                ra = bflt[a, B_RADIUS]
                rb = bflt[b, B_RADIUS]
                for j in range(3):
                    nj = c_f[nc, CF_N + j]
                    c_f[nc, CF_RA + j] = -ra * nj
                    c_f[nc, CF_RB + j] = rb * nj
                    c_f[nc, CF_P + j] = st[b, j] + rb * nj
                nc += 1
            for c in range(nc):
                a = c_i[c, CI_A]
                c_f[c, CF_PI] = 0.0
                c_f[c, CF_PI + 1] = 0.0
                c_f[c, CF_PI + 2] = 0.0
                c_f[c, CF_VCMN] = (c_f[c, CF_N] * st[a, SV] + c_f[c, CF_N + 1] * st[a, SV + 1]
                                   + c_f[c, CF_N + 2] * st[a, SV + 2])
            # clusters: contacts sharing a body
            cluster_contacts(nc, c_i, comp)
            for root in range(nc):
                K = cluster_members(nc, comp, root, MAXC)
                if K == 0:
                    continue
                members = comp[MAXC:MAXC + K]
                if K == 1:
                    c = members[0]
                    viN, vi1, vi2 = _contact_velocity(st, c_i, c_f, c)
                    if viN >= 0.0:
                        continue
                    rc, vfN = _single(law, c, t, K, st, bflt, law_ids, law_par, c_i, c_f, v3,
                                      W3, P3, Ii, ev_t, ev_i, ev_f, cnt, err)
                    if rc < 0:
                        return rc
                    if perforates(law_par[c_i[c, CI_LAW]], vfN):
                        c_i[c, CI_OFF] = 1
                elif policy == POL_SIMULTANEOUS:
                    if joint is None:
                        return _not_compiled(err, t, c_i[members[0], CI_A], FEATURE_JOINT)
                    rc = _joint(members, K, t, st, bflt, grav, law_par, c_i, c_f, Wb, Pb, vb, tb,
                                Ii, tolf, toli, ev_t, ev_i, ev_f, cnt, err)
                    if rc < 0:
                        return rc
                else:
                    rc = _sequential(law, members, K, t, st, bflt, law_ids, law_par, c_i, c_f,
                                     v3, W3, P3, Ii, tolf, toli, ev_t, ev_i, ev_f, cnt, err)
                    if rc < 0:
                        return rc
            # perforating impacts disable their pair for good; the pairs in an impact now
            # are marked PR_HIT (their next search checks whether they stay in contact)
            for c in range(nc):
                if c_i[c, CI_OFF] != 0 and c_i[c, CI_TYPE] == 0:
                    bp_off[c_i[c, CI_A], c_i[c, CI_B]] = 1
                elif c_i[c, CI_TYPE] == 1:
                    for q in range(npr):
                        if ((pairs[q, 0] == c_i[c, CI_A] and pairs[q, 1] == c_i[c, CI_B]) or
                                (pairs[q, 1] == c_i[c, CI_A] and pairs[q, 0] == c_i[c, CI_B])):
                            if c_i[c, CI_OFF] != 0:
                                pr_off[q] = PR_OFF
                            elif pr_off[q] == PR_ON:
                                pr_off[q] = PR_HIT
            # persistent contacts, accumulation (Zeno) points, integrated contacts
            for i in range(nb):
                if bmark[i] == 0:
                    continue
                if pm[i, M_MODE] != PM_FLIGHT:
                    rc = _reevaluate(i, t, st, bint, bflt, planes, grav, law_par, bp_law, pm,
                                     ttr, tolf, ev_t, ev_i, ev_f, cnt, c_f, cw, err)
                    if rc == RC_TIP:
                        rc = _tip(i, t, st, bint, bflt, feats, planes, grav, law_par, bp_law,
                                  pm, ttr, tz, tolf, pv, fw, ev_t, ev_i, ev_f, cnt, c_f, cw,
                                  Ii, err, pivot)
                    if rc == GROOVE_SLIPS:
                        rc = _groove_slide(i, pm[i, M_PLANE], pm[i, M_FEAT], t, st, bint,
                                           bflt, feats, planes, grav, law_par, bp_law, pm,
                                           ttr, tz, tolf, pv, fw, ev_t, ev_i, ev_f, cnt, c_f,
                                           cw, Ii, err, pivot)
                    if rc < 0:
                        return rc
                    if pm[i, M_MODE] != PM_FLIGHT:
                        if bint[i, B_KIND] == SH_SPHERE and pm[i, M_MODE] != PM_WEDGED:
                            rc, q = _groove_from_impact(i, t, nc, c_i, st, bflt, planes,
                                                        grav, law_par, bp_law, pm, ttr, tolf,
                                                        ev_t, ev_i, ev_f, cnt, c_f, cw, err)
                            if rc == GROOVE_SLIPS:
                                rc = _groove_slide(i, pm[i, M_PLANE], q, t, st, bint, bflt,
                                                   feats, planes, grav, law_par, bp_law, pm,
                                                   ttr, tz, tolf, pv, fw, ev_t, ev_i, ev_f,
                                                   cnt, c_f, cw, Ii, err, pivot)
                            if rc < 0:
                                return rc
                        continue
                    # released by an impact on another plane: its impacts there may
                    # accumulate at once (a sphere rolling into the second plane of a
                    # groove), decided below as for any body in flight
                rc = _after_impact(i, t, nc, st, bint, bflt, feats, planes, grav, law_par,
                                   bp_law, pm, ttr, tz, zp, bp_off, c_i, c_f, tolf, capture_on,
                                   pv, fw, ev_t, ev_i, ev_f, cnt, Ii, err, toli, pivot,
                                   pairs, cid)
                if rc < 0:
                    return rc
            for i in range(nb):
                if bmark[i] == 0:
                    continue
                if not _finite(st, i):
                    _set_err(err, t, i, 0, st[i, SX], st[i, SX + 1], st[i, SX + 2], 0.0, 0.0,
                             0.0)
                    return ERR_NONFINITE
                ws[i, WS_MODE] = -1.0
                bt[i] = INF
                if tz[i] < INF:
                    # accumulation jump pending: the trajectory holds the body on the plane
                    _push_held(seg_t, seg_b, seg_s, cnt, st, tref, i, bint, planes, zp[i])
                else:
                    _push_seg(seg_t, seg_b, seg_s, cnt, st, tref, i, pm, pv)
            for i in range(nb):
                if bmark[i] == 0:
                    continue
                rc = _recompute_motion(i, t, st, tref, bint, bflt, feats, planes, pm, tz, zp,
                                       bt, bpl, bft, bp_off, ws, tolf, toli, skip, pose, err,
                                       ttr, pk, pv, pw, fw, ybuf, vals, vals0, vfl,
                                       c_f[MAXC - 2], pivot)
                if rc < 0:
                    return rc
            rc = _recompute_pairs(t, st, tref, bint, bflt, planes, grav, pairs, pm, tz, zp, ttr,
                                  bt, pr_t, pr_off, ws, pv, pw, fw, tolf, toli, pscr, pfe,
                                  bmark, err, pair, pgen, cid)
            if rc < 0:
                return rc
    return run_loop
