"""Persistent point and edge contact in 3D: a body pivoting, rolling or sliding on one to
``KMAX`` (8) of its features, each held on a plane (the same plane, or different planes: a
groove, a corner; every contact has its own normal, offset and mu), integrated with error
control.

When impacts accumulate at a corner or an edge of a box, or at a cap of a capsule (the
impact sequence has a finite accumulation point, after which the contact persists), the
body moves with one or two features held on a plane: a constrained rigid-body motion with
no closed form. This module integrates it exactly in the sense of the other integrated
motions of rbimpact: to a stated tolerance.

Model (Newton-Euler with unilateral contacts and Coulomb friction; e.g. Pfeiffer & Glocker,
*Multibody Dynamics with Unilateral Contacts*, 1996, ch. 6). For the body (mass ``m``,
world inertia ``I_w``) with contact forces ``f_k`` at arms ``r_k`` (contact point minus
centre of mass; a feature of radius ``rad`` touches at its centre minus ``rad n``):
``m a = m g + sum f_k``, ``I_w al = sum r_k x f_k - w x I_w w``. Each contact ``k`` is

* **sliding** (slip velocity ``c_k`` of the material contact point, tangential, non-zero):
  ``f_k = lam_k (n - mu u_k)``, ``u_k = c_k/|c_k|``, and the normal acceleration of the
  contact is zero: ``n . (a + al x r_k + w x (w x s_k)) = 0`` (``s_k`` the feature centre's
  arm). A non-positive coefficient of ``lam_k`` is the Painleve paradox: error.
* **sticking** (``c_k = 0``): the whole contact acceleration ``a + al x r_k + w x (w x s_k)``
  is zero, ``f_k`` free. Two sticking contacts on one body leave one internal force
  ``s d`` (``d`` along the line through them) undetermined; the motion is not: sticking
  holds while some ``s`` puts both forces in their friction cones (on two planes ``s d``
  has a normal part on each, so both normal forces depend on ``s``: ``cone_interval``).
  The other contacts' forces do not depend on ``s`` (``s d`` has no net force or moment).
  Three sticking points not on one line hold the body still: a rest, not a motion
  (``PV_STUCK``; the stepper stops the body there, ``stepper3d._pv_still``).

Events (each a function that must stay positive; the phase ends at its first root, located
on the integrator's dense output): a normal force ``lam_k`` reaching 0 (the contact lifts
off); a sticking force reaching its friction cone (slip starts opposite to the friction
force at that instant, i.e. continuously); the slip speed of a sliding contact falling to
``slip_eps`` (m/s: it then sticks, its remaining slip removed by a tangential impulse of
at most ``m slip_eps``, or slides on when sticking is infeasible); the gap of any other
feature to any plane reaching 0 (an impact). A sliding contact whose coefficient of
``lam_k`` falls to 0 while ``lam_k`` grows without bound (a dynamic Painleve jam: the
swerving slip turns ``u_k`` towards the cone where sliding has no consistent force) stops
the integration where the steps shrink below ``STAGE_HMIN``; the stepper continues from
that state by an impact without collision (``PE_JAM``), or refuses under
``painleve="error"``.

Integration: the state ``y = (x, q, v, w)`` (13 numbers, world angular velocity) by the
Dormand-Prince RK5(4) pair with its 4th-order dense output (as ``flight3d``), steps
accepted when every component of the error estimate is within ``tol`` times its scale
(``L`` for x, 1 for q, ``V`` for v, ``V/L`` for w, with ``L`` the body's size and
``V = |v| + |w| L + sqrt(|g| L)``), and at most ``MAX_ANGLE`` (rad) of rotation per step so
that event functions, which change with the rotation, are sampled finely enough to see
every sign change. A gap that dips below zero and comes back within one step (a grazing
feature: positive at both step ends) is caught by its rate ``n . (v + w x r)``: when the
rate goes from negative to positive over a step, the gap's minimum is located on the
dense output (root of the rate) and tested. Unlike conservative advancement in flight,
this cannot rule out a force or slip event with two roots inside one step, nor a gap
whose rate changes sign more than once in a step: a stated limitation.
"""
import math

from numba import njit

from .cache_guard import guard

# flush stale compiled callers before any kernel module below is imported (cache_guard)
guard(__name__, __file__)

from .dopri5 import dense_out, dopri5_step
from .flight3d import pose_at, qmul, qnormalize, qrot, qrot_inv
from .minnorm import minnorm_solve

# ---- contact parameters cp (float64[N_CP]) ----------------------------------------------
# Per-contact fields are arrays of KMAX slots (contact k at base + k, or base + 3 k for a
# vector); contacts 0 .. K-1 are in use.
KMAX = 8        # contacts held at once at most (a box's face on the floor and another
#                 on a wall: 8, the corners of their common edge counted on both)
CP_M = 0        # mass (kg)
CP_I = 1        # 1:4 principal moments (kg m^2)
CP_G = 4        # 4:7 gravity (m/s^2)
CP_K = 7        # number of contacts (1 .. KMAX)
CP_RAD = 8      # feature radius (m)
CP_EPS = 9      # slip_eps (m/s)
CP_L = 10       # body size L (m): bounding radius
CP_N = 11       # + 3 k: unit normal of contact k's plane (each contact has its own plane)
CP_D = CP_N + 3 * KMAX      # + k: offset of that plane (m)
CP_MU = CP_D + KMAX         # + k: friction coefficient of contact k
CP_PLANE = CP_MU + KMAX     # + k: plane index of contact k (float)
CP_P = CP_PLANE + KMAX      # + 3 k: body-frame feature centre of contact k (m)
CP_S = CP_P + 3 * KMAX      # + k: status of contact k: 0 sliding, 1 sticking
CP_U = CP_S + KMAX          # + 3 k: start direction of a slip that started from sticking
#                             (zero: none)
CP_F = CP_U + 3 * KMAX      # + k: feature row of contact k (float)
N_CP = CP_F + KMAX

# ---- force workspace fw (float64[N_FW]) --------------------------------------------------
NSYS = 3 * KMAX             # unknowns of the force system at most (all sticking)
FW_R = 0        # 0:9 rotation matrix (row-major)
FW_II = 9       # 9:18 world inverse inertia
FW_ARM = 18                 # + 3 k: contact arms r_k (m)
FW_SARM = FW_ARM + NSYS     # + 3 k: feature-centre arms s_k (m)
FW_F = FW_SARM + NSYS       # + 3 k: contact forces f_k (N)
FW_LAM = FW_F + NSYS        # + k: normal forces lam_k (N)
FW_C = FW_LAM + KMAX        # + 3 k: slip velocities c_k (m/s, tangential)
FW_B = FW_C + NSYS          # + 3 k: free contact accelerations b_k (m/s^2)
FW_MARG = FW_B + NSYS       # + k: stick margins (N): mu lam - |f_T| (or, for two sticking
#                             contacts, the length of their internal force's interval, in N,
#                             stored in both)
FW_COL = FW_MARG + KMAX     # + k: first unknown of contact k in the force system (float)
FW_A = FW_COL + KMAX        # 3: acceleration (m/s^2)
FW_AL = FW_A + 3            # 3: angular acceleration (rad/s^2)
FW_G = FW_AL + 3            # 9: a 3x3 block
FW_SSTAR = FW_G + 9         # internal force chosen for two sticking contacts (N)
FW_MAT = FW_SSTAR + 1       # NSYS x NSYS system (row-major, stride NSYS)
FW_RHS = FW_MAT + NSYS * NSYS   # NSYS
# three or more contacts: a copy of the system, solved by minimum norm when it is singular
# (dependent contacts: a box's corners on one plane and an edge on the other)
FW_MAT0 = FW_RHS + NSYS     # NSYS x NSYS
FW_RHS0 = FW_MAT0 + NSYS * NSYS     # NSYS
FW_X = FW_RHS0 + NSYS       # NSYS: the minimum-norm solution
FW_SVU = FW_X + NSYS        # NSYS x NSYS: the SVD's U
FW_SVV = FW_SVU + NSYS * NSYS   # NSYS x NSYS: the SVD's V
N_FW = FW_SVV + NSYS * NSYS

PV_OK = 0
PV_PAINLEVE = 1     # a sliding contact's normal force coefficient is <= 0
PV_SINGULAR = 2     # singular force system
#   (3: no consistent stick/slip/lift-off state, set by the stepper's validation)
PV_STUCK = 4        # three or more sticking contacts: the body is held still (a rest, which
#                     the integrated contact does not build)

# ---- integrator workspace pw (float64[N_PW]) ---------------------------------------------
NY = 13
PW_TOL = 0
PW_SC = 1           # 1:14 error scales per component
PW_S0 = 14
PW_H = 15
PW_HNEXT = 16
PW_HMAX = 17
PW_NSTEP = 18
PW_MAXSTEP = 19
PW_YSTART = 20      # 20:33
PW_Y = 33           # 33:46
PW_Y1 = 46          # 46:59
PW_YT = 59          # 59:72
PW_K = 72           # 72:163 seven stages
PW_RC = 163         # 163:228 dense output, 5 x 13
PW_WHY = 228        # the pivot_forces code (PV_*) of the last force failure
PW_E0 = 229         # energy (J) a conservative phase keeps (NaN: the phase dissipates)
PW_JAM = 230        # 230:243 the state where the phase reached a Painleve jam (PE_JAM)
N_PW = 243

PI_OK = 0
PI_TOO_MANY_STEPS = 1
PI_FORCES = 2       # the force system failed (Painleve or singular)
STAGE_SHRINK = 0.25  # a step whose inner stage has no consistent contact force is retried
#                      this much shorter (the stage lies past a stick/slip/lift-off change
#                      that the event search locates between accepted steps) ...
STAGE_HMIN = 1e-12   # ... down to this fraction of the largest step; then PI_FORCES

MAX_ANGLE = 0.05    # rad of rotation (or of sqrt(|g|/L) time) per step at most
SLIP_BLEND = 10.0     # a slip started from sticking blends from its start direction to its
                      #   own direction while |c| < SLIP_BLEND slip_eps (see _slipdir)
GAP_ARM = 1e-12       # a gap event fires below min(0, g(0)) - GAP_ARM L (dimensionless)
FORCE_ARM = 1e-9      # a normal force or stick margin starting below FORCE_ARM m |g| (a
                      #   tangency) fires below min(0, start) - FORCE_ARM m |g| (-)
EVENT_ITER = 200    # bisection/secant iterations locating an event on the dense output
DEPENDENT_RTOL = 1e-12  # three or more contacts with a singular force system: singular
#                       values below DEPENDENT_RTOL times the largest are zero (dependent
#                       constraints, minimum-norm forces) ...
DEPENDENT_RES_RTOL = 1e-9   # ... and the equations must then hold to this fraction of the
#                       largest term (else they contradict each other: PV_SINGULAR)
DEPENDENT_SWEEPS = 60   # Jacobi sweeps of that minimum-norm solve at most (minnorm)
CONE_RTOL = 1e-12   # two sticking contacts on two planes: a squeeze interval of zero
                    #   length is accepted within CONE_RTOL m |g| (round-off of the forces)
ENERGY_FIX_MAX = 1e-6  # a conservative rolling phase's velocities are rescaled to its
                    #   energy after each accepted step when the kinetic energy's relative
                    #   correction is at most this (integration error); a larger one is left

# event kinds
PE_NONE = 0
PE_LIFT = 1         # index: the contact (0 .. K-1)
PE_SLIP = 2         # a sticking contact reaches its cone (index: the contact)
PE_STOP = 3         # a sliding contact's slip falls to slip_eps (index: contact)
PE_GAP = 4          # another feature reaches a plane (index: plane * 1000 + feature)
PE_JAM = 5          # one sliding contact reaches a Painleve jam: its normal-force coefficient
                    #   W_NN - mu u . W_TN falls to 0 under a normal force growing without
                    #   bound (the step shrank to STAGE_HMIN at the state kept in PW_JAM);
                    #   scheduled by the stepper only under painleve="impact"

# event values (``_event_values``): [0:KMAX] normal forces, [KMAX:2 KMAX] stick margins,
# [2 KMAX:3 KMAX] slip speeds, then the gaps of every feature to every plane
NEV_CONTACT = 3 * KMAX

# Dormand-Prince RK5(4)7M, the step loop shared with pivot2d and the clusters: kernels/dopri5.py


# ------------------------------------------------------------------ linear algebra


@njit(cache=True)
def _solve(fw, n):
    """Solve fw[FW_MAT] (n x n, row-major, stride NSYS) x = fw[FW_RHS:FW_RHS+n] in place
    (Gaussian elimination, partial pivoting). Returns False if singular."""
    M = FW_MAT
    B = FW_RHS
    scale = 0.0
    for i in range(n):
        for j in range(n):
            scale = max(scale, abs(fw[M + NSYS * i + j]))
    if not scale > 0.0:
        return False
    for col in range(n):
        piv = col
        best = abs(fw[M + NSYS * col + col])
        for r in range(col + 1, n):
            v = abs(fw[M + NSYS * r + col])
            if v > best:
                best = v
                piv = r
        if not best > 1e-13 * scale:
            return False
        if piv != col:
            for j in range(n):
                tmp = fw[M + NSYS * col + j]
                fw[M + NSYS * col + j] = fw[M + NSYS * piv + j]
                fw[M + NSYS * piv + j] = tmp
            tmp = fw[B + col]
            fw[B + col] = fw[B + piv]
            fw[B + piv] = tmp
        d = fw[M + NSYS * col + col]
        for r in range(col + 1, n):
            f = fw[M + NSYS * r + col] / d
            if f != 0.0:
                for j in range(col, n):
                    fw[M + NSYS * r + j] -= f * fw[M + NSYS * col + j]
                fw[B + r] -= f * fw[B + col]
    for i in range(n - 1, -1, -1):
        s = fw[B + i]
        for j in range(i + 1, n):
            s -= fw[M + NSYS * i + j] * fw[B + j]
        fw[B + i] = s / fw[M + NSYS * i + i]
    return True


@njit(cache=True)
def _solve_dependent(fw, n):
    """The singular system kept in fw[FW_MAT0], fw[FW_RHS0] (n x n) by minimum norm
    (``minnorm``, ``DEPENDENT_RTOL``) into fw[FW_RHS]: dependent contacts share their
    force. Returns False when the equations contradict each other (residual above
    ``DEPENDENT_RES_RTOL`` times the largest term)."""
    minnorm_solve(fw, FW_MAT0, FW_RHS0, FW_X, FW_SVU, FW_SVV, n, NSYS, DEPENDENT_RTOL,
                  DEPENDENT_SWEEPS)
    worst = 0.0
    scale = 0.0
    for r in range(n):
        res = -fw[FW_RHS0 + r]
        for c in range(n):
            a = fw[FW_MAT0 + NSYS * r + c] * fw[FW_X + c]
            res += a
            scale = max(scale, abs(a))
        scale = max(scale, abs(fw[FW_RHS0 + r]))
        worst = max(worst, abs(res))
    if not worst <= DEPENDENT_RES_RTOL * scale:
        return False
    for r in range(n):
        fw[FW_RHS + r] = fw[FW_X + r]
    return True


@njit(cache=True)
def _G(fw, ra, rb, m):
    """fw[FW_G] = I/m - [r_a]x Iinv [r_b]x: acceleration of contact a per unit force at b."""
    Ii = FW_II
    ax, ay, az = fw[ra], fw[ra + 1], fw[ra + 2]
    bx, by, bz = fw[rb], fw[rb + 1], fw[rb + 2]
    for j in range(3):
        # column j: f = e_j ; t = r_b x e_j
        if j == 0:
            tx, ty, tz = 0.0, bz, -by
        elif j == 1:
            tx, ty, tz = -bz, 0.0, bx
        else:
            tx, ty, tz = by, -bx, 0.0
        ux = fw[Ii] * tx + fw[Ii + 1] * ty + fw[Ii + 2] * tz
        uy = fw[Ii + 3] * tx + fw[Ii + 4] * ty + fw[Ii + 5] * tz
        uz = fw[Ii + 6] * tx + fw[Ii + 7] * ty + fw[Ii + 8] * tz
        # - r_a x u = u x r_a
        fw[FW_G + j] = (uy * az - uz * ay) + (1.0 / m if j == 0 else 0.0)
        fw[FW_G + 3 + j] = (uz * ax - ux * az) + (1.0 / m if j == 1 else 0.0)
        fw[FW_G + 6 + j] = (ux * ay - uy * ax) + (1.0 / m if j == 2 else 0.0)


@njit(cache=True)
def _slipdir(fw, cp, k):
    """Unit friction direction of sliding contact k: c_k/|c_k|; for a slip that started
    from sticking along the stored direction u_k, the direction of
    ``c_k + slip_eps u_k max(0, 1 - |c_k| / (SLIP_BLEND slip_eps))``, continuous in c_k,
    equal to u_k at c_k = 0 and to c_k/|c_k| once |c_k| >= SLIP_BLEND slip_eps."""
    co = FW_C + 3 * k
    cx, cy, cz = fw[co], fw[co + 1], fw[co + 2]
    c = math.sqrt(cx * cx + cy * cy + cz * cz)
    uo = CP_U + 3 * k
    eps = cp[CP_EPS]
    wgt = eps * max(0.0, 1.0 - c / (SLIP_BLEND * eps))
    wx = cx + wgt * cp[uo]
    wy = cy + wgt * cp[uo + 1]
    wz = cz + wgt * cp[uo + 2]
    w = math.sqrt(wx * wx + wy * wy + wz * wz)
    if w == 0.0:
        return 0.0, 0.0, 0.0
    return wx / w, wy / w, wz / w


@njit(cache=True, inline="always")
def contact_normal(cp, k):
    """Unit normal of the plane of contact k (each contact has its own plane)."""
    o = CP_N + 3 * k
    return cp[o], cp[o + 1], cp[o + 2]


@njit(cache=True, inline="always")
def contact_mu(cp, k):
    """Friction coefficient of contact k (the law of its body-plane pair)."""
    return cp[CP_MU + k]


@njit(cache=True, inline="always")
def contact_plane(cp, k):
    """Plane index of contact k."""
    return int(cp[CP_PLANE + k])


@njit(cache=True)
def cone_interval(N0, dn, TT, Td, dd, mu, fs, rtol):
    """The interval [lo, hi] of the scalar s for which the contact force with normal
    component ``N0 + dn s`` and tangential part ``T0 + s dt`` lies in the Coulomb cone
    ``|T| <= mu N`` (a line meets a convex cone in an interval). ``TT = |T0|^2``,
    ``Td = T0 . dt``, ``dd = |dt|^2``; ``fs`` (N) the force scale and ``rtol`` the
    relative round-off allowed on it. Empty when lo > hi (then ``(inf, -inf)``).
    Squaring gives ``A s^2 + B s + C >= 0`` with ``A = mu^2 dn^2 - dd``,
    ``B = 2 (mu^2 N0 dn - Td)``, ``C = mu^2 N0^2 - TT``, on the nappe ``N >= 0``."""
    A = mu * mu * dn * dn - dd
    B = 2.0 * (mu * mu * N0 * dn - Td)
    C = mu * mu * N0 * N0 - TT
    if abs(A) <= 1e-15 * (mu * mu * dn * dn + dd):
        if abs(B) <= 1e-300:
            if C >= -(rtol * fs) ** 2 and N0 >= -rtol * fs:
                return -math.inf, math.inf
            return math.inf, -math.inf
        r0 = -C / B
        return (r0, math.inf) if B > 0.0 else (-math.inf, r0)
    disc = B * B - 4.0 * A * C
    if A > 0.0:
        # the direction (dn, dt) lies inside the cone: feasible on the nappe N >= 0
        n0 = -N0 / dn
        if disc <= 0.0:
            return (n0, math.inf) if dn > 0.0 else (-math.inf, n0)
        q = -0.5 * (B + math.copysign(math.sqrt(disc), B))
        r1 = q / A
        r2 = C / q if q != 0.0 else r1
        lo = min(r1, r2)
        hi = max(r1, r2)
        return (max(hi, n0), math.inf) if dn > 0.0 else (-math.inf, min(lo, n0))
    if disc < 0.0:
        return math.inf, -math.inf
    q = -0.5 * (B + math.copysign(math.sqrt(disc), B))
    if q == 0.0:
        lo = hi = 0.0
    else:
        r1 = q / A
        r2 = C / q
        lo = min(r1, r2)
        hi = max(r1, r2)
    if N0 + dn * 0.5 * (lo + hi) < 0.0:
        return math.inf, -math.inf    # the segment lies on the nappe N < 0
    return lo, hi


# ------------------------------------------------------------------ forces


@njit(cache=True)
def pivot_forces(y, cp, fw):
    """Contact forces, accelerations, slip velocities and margins at state ``y`` (13) into
    ``fw``. Returns PV_OK, PV_PAINLEVE or PV_SINGULAR."""
    m = cp[CP_M]
    I1, I2, I3 = cp[CP_I], cp[CP_I + 1], cp[CP_I + 2]
    gx, gy, gz = cp[CP_G], cp[CP_G + 1], cp[CP_G + 2]
    K = int(cp[CP_K])
    rad = cp[CP_RAD]
    w, x, yq, z = y[3], y[4], y[5], y[6]
    R = FW_R
    fw[R] = 1.0 - 2.0 * (yq * yq + z * z)
    fw[R + 1] = 2.0 * (x * yq - w * z)
    fw[R + 2] = 2.0 * (x * z + w * yq)
    fw[R + 3] = 2.0 * (x * yq + w * z)
    fw[R + 4] = 1.0 - 2.0 * (x * x + z * z)
    fw[R + 5] = 2.0 * (yq * z - w * x)
    fw[R + 6] = 2.0 * (x * z - w * yq)
    fw[R + 7] = 2.0 * (yq * z + w * x)
    fw[R + 8] = 1.0 - 2.0 * (x * x + yq * yq)
    for a in range(3):
        for b in range(3):
            fw[FW_II + 3 * a + b] = (fw[R + 3 * a] * fw[R + 3 * b] / I1
                                     + fw[R + 3 * a + 1] * fw[R + 3 * b + 1] / I2
                                     + fw[R + 3 * a + 2] * fw[R + 3 * b + 2] / I3)
    wx, wy, wz = y[10], y[11], y[12]
    # gyroscopic: al0 = -Iinv (w x I_w w); I_w w = R diag(I) R^T w
    bx = fw[R] * wx + fw[R + 3] * wy + fw[R + 6] * wz
    by = fw[R + 1] * wx + fw[R + 4] * wy + fw[R + 7] * wz
    bz = fw[R + 2] * wx + fw[R + 5] * wy + fw[R + 8] * wz
    Lx = fw[R] * I1 * bx + fw[R + 1] * I2 * by + fw[R + 2] * I3 * bz
    Ly = fw[R + 3] * I1 * bx + fw[R + 4] * I2 * by + fw[R + 5] * I3 * bz
    Lz = fw[R + 6] * I1 * bx + fw[R + 7] * I2 * by + fw[R + 8] * I3 * bz
    tx = -(wy * Lz - wz * Ly)
    ty = -(wz * Lx - wx * Lz)
    tz = -(wx * Ly - wy * Lx)
    Ii = FW_II
    a0x = fw[Ii] * tx + fw[Ii + 1] * ty + fw[Ii + 2] * tz
    a0y = fw[Ii + 3] * tx + fw[Ii + 4] * ty + fw[Ii + 5] * tz
    a0z = fw[Ii + 6] * tx + fw[Ii + 7] * ty + fw[Ii + 8] * tz
    for k in range(K):
        nx, ny, nz = contact_normal(cp, k)
        po = CP_P + 3 * k
        px, py, pz = cp[po], cp[po + 1], cp[po + 2]
        sx = fw[R] * px + fw[R + 1] * py + fw[R + 2] * pz
        sy = fw[R + 3] * px + fw[R + 4] * py + fw[R + 5] * pz
        sz = fw[R + 6] * px + fw[R + 7] * py + fw[R + 8] * pz
        so = FW_SARM + 3 * k
        ro = FW_ARM + 3 * k
        fw[so] = sx
        fw[so + 1] = sy
        fw[so + 2] = sz
        rx = sx - rad * nx
        ry = sy - rad * ny
        rz = sz - rad * nz
        fw[ro] = rx
        fw[ro + 1] = ry
        fw[ro + 2] = rz
        # slip velocity (tangential part of v + w x r)
        ux = y[7] + wy * rz - wz * ry
        uy = y[8] + wz * rx - wx * rz
        uz = y[9] + wx * ry - wy * rx
        un = ux * nx + uy * ny + uz * nz
        co = FW_C + 3 * k
        fw[co] = ux - un * nx
        fw[co + 1] = uy - un * ny
        fw[co + 2] = uz - un * nz
        # free acceleration b = g + al0 x r + w x (w x s)
        ws = wx * sx + wy * sy + wz * sz
        w2 = wx * wx + wy * wy + wz * wz
        bo = FW_B + 3 * k
        fw[bo] = gx + (a0y * rz - a0z * ry) + wx * ws - sx * w2
        fw[bo + 1] = gy + (a0z * rx - a0x * rz) + wy * ws - sy * w2
        fw[bo + 2] = gz + (a0x * ry - a0y * rx) + wz * ws - sz * w2
    # unknown layout: contact k sliding: 1 unknown lam_k; sticking: 3 unknowns f_k
    ntot = 0
    nstick = 0
    ka = -1             # the two sticking contacts, when exactly two stick
    kb = -1
    for k in range(K):
        fw[FW_COL + k] = ntot
        if cp[CP_S + k] == 1.0:
            ntot += 3
            nstick += 1
            if ka < 0:
                ka = k
            else:
                kb = k
        else:
            ntot += 1
    if nstick >= 3:
        return PV_STUCK
    for r in range(ntot):
        for c in range(ntot):
            fw[FW_MAT + NSYS * r + c] = 0.0
    # columns: effect of each unknown on each contact acceleration
    for kc in range(K):          # the contact whose force the unknowns describe
        stc = int(cp[CP_S + kc])
        col0 = int(fw[FW_COL + kc])
        ec0 = 0.0
        ec1 = 0.0
        ec2 = 0.0
        if stc == 0:
            nx, ny, nz = contact_normal(cp, kc)
            mu = contact_mu(cp, kc)
            u0, u1, u2 = _slipdir(fw, cp, kc)
            ec0 = nx - mu * u0
            ec1 = ny - mu * u1
            ec2 = nz - mu * u2
        for kr in range(K):      # the contact whose acceleration the rows constrain
            str_ = int(cp[CP_S + kr])
            row0 = int(fw[FW_COL + kr])
            mx, my, mz = contact_normal(cp, kr)
            _G(fw, FW_ARM + 3 * kr, FW_ARM + 3 * kc, m)
            # block (3 x 3) G_rc; reduce columns (sliding: times e) and rows (sliding: n.)
            for a in range(3 if str_ == 1 else 1):
                for b in range(3 if stc == 1 else 1):
                    if str_ == 1:
                        ga0 = fw[FW_G + 3 * a]
                        ga1 = fw[FW_G + 3 * a + 1]
                        ga2 = fw[FW_G + 3 * a + 2]
                    else:
                        ga0 = mx * fw[FW_G] + my * fw[FW_G + 3] + mz * fw[FW_G + 6]
                        ga1 = mx * fw[FW_G + 1] + my * fw[FW_G + 4] + mz * fw[FW_G + 7]
                        ga2 = mx * fw[FW_G + 2] + my * fw[FW_G + 5] + mz * fw[FW_G + 8]
                    if stc == 1:
                        val = ga0 if b == 0 else (ga1 if b == 1 else ga2)
                    else:
                        val = ga0 * ec0 + ga1 * ec1 + ga2 * ec2
                    fw[FW_MAT + NSYS * (row0 + a) + col0 + b] = val
        bo = FW_B + 3 * kc
        rowc = col0
        nx, ny, nz = contact_normal(cp, kc)
        if stc == 1:
            fw[FW_RHS + rowc] = -fw[bo]
            fw[FW_RHS + rowc + 1] = -fw[bo + 1]
            fw[FW_RHS + rowc + 2] = -fw[bo + 2]
        else:
            fw[FW_RHS + rowc] = -(nx * fw[bo] + ny * fw[bo + 1] + nz * fw[bo + 2])
    two_stick = nstick == 2
    dx = 0.0
    dy = 0.0
    dz = 0.0
    if two_stick:
        # null space: internal force s d at contact ka, -s d at contact kb (d along
        # r_kb - r_ka; no net force or moment, so no other unknown changes); add
        # v v^T (v = (d, -d) / sqrt 2 on their columns) to make the system regular
        # (minimum-norm split)
        dx = fw[FW_ARM + 3 * kb] - fw[FW_ARM + 3 * ka]
        dy = fw[FW_ARM + 3 * kb + 1] - fw[FW_ARM + 3 * ka + 1]
        dz = fw[FW_ARM + 3 * kb + 2] - fw[FW_ARM + 3 * ka + 2]
        dl = math.sqrt(dx * dx + dy * dy + dz * dz)
        if not dl > 0.0:
            return PV_SINGULAR      # one point held twice (the stepper never asks this)
        dx /= dl
        dy /= dl
        dz /= dl
        scale = 0.0
        for i in range(ntot):
            scale = max(scale, abs(fw[FW_MAT + (NSYS + 1) * i]))
        ca = int(fw[FW_COL + ka])
        cb = int(fw[FW_COL + kb])
        for i in range(6):
            vi = (dx, dy, dz, -dx, -dy, -dz)[i]
            ri = ca + i if i < 3 else cb + i - 3
            for j in range(6):
                vj = (dx, dy, dz, -dx, -dy, -dz)[j]
                rj = ca + j if j < 3 else cb + j - 3
                fw[FW_MAT + NSYS * ri + rj] += 0.5 * scale * vi * vj
    elif ntot == 1:
        den = fw[FW_MAT]
        if not den > 0.0:
            return PV_PAINLEVE
    if K >= 3:
        for r in range(ntot):
            fw[FW_RHS0 + r] = fw[FW_RHS + r]
            for c in range(ntot):
                fw[FW_MAT0 + NSYS * r + c] = fw[FW_MAT + NSYS * r + c]
    if not _solve(fw, ntot):
        if K < 3 or not _solve_dependent(fw, ntot):
            return PV_SINGULAR
    # forces
    for kc in range(K):
        stc = int(cp[CP_S + kc])
        col0 = int(fw[FW_COL + kc])
        fo = FW_F + 3 * kc
        nx, ny, nz = contact_normal(cp, kc)
        mu = contact_mu(cp, kc)
        if stc == 1:
            f0 = fw[FW_RHS + col0]
            f1 = fw[FW_RHS + col0 + 1]
            f2 = fw[FW_RHS + col0 + 2]
            fw[FW_LAM + kc] = f0 * nx + f1 * ny + f2 * nz
        else:
            lam = fw[FW_RHS + col0]
            u0, u1, u2 = _slipdir(fw, cp, kc)
            f0 = lam * (nx - mu * u0)
            f1 = lam * (ny - mu * u1)
            f2 = lam * (nz - mu * u2)
            fw[FW_LAM + kc] = lam
        fw[fo] = f0
        fw[fo + 1] = f1
        fw[fo + 2] = f2
    # sliding with a single unknown in a coupled system: Painleve when the normal-force
    # coefficient of its own row is <= 0 is checked above for ntot == 1; for K >= 2 the
    # force signs are checked by the lift-off events.
    # stick margins (a sliding contact has none: inf)
    fw[FW_SSTAR] = 0.0
    for kc in range(K):
        fw[FW_MARG + kc] = math.inf
    if two_stick and contact_plane(cp, ka) != contact_plane(cp, kb):
        # two planes: the internal force s d has a normal part on each plane, so each
        # contact's normal force depends on s too; each cone gives an interval of s
        fs = m * math.sqrt(gx * gx + gy * gy + gz * gz)     # force scale (N)
        lo = -math.inf
        hi = math.inf
        for kc in (ka, kb):
            fo = FW_F + 3 * kc
            sg = 1.0 if kc == ka else -1.0
            nx, ny, nz = contact_normal(cp, kc)
            lam = fw[FW_LAM + kc]
            ax = fw[fo] - lam * nx
            ay = fw[fo + 1] - lam * ny
            az = fw[fo + 2] - lam * nz
            dn = sg * (dx * nx + dy * ny + dz * nz)
            tx_ = sg * dx - dn * nx
            ty_ = sg * dy - dn * ny
            tz_ = sg * dz - dn * nz
            l1, h1 = cone_interval(lam, dn, ax * ax + ay * ay + az * az,
                                   ax * tx_ + ay * ty_ + az * tz_,
                                   tx_ * tx_ + ty_ * ty_ + tz_ * tz_, contact_mu(cp, kc),
                                   fs, CONE_RTOL)
            lo = max(lo, l1)
            hi = min(hi, h1)
        marg = hi - lo
        fw[FW_MARG + ka] = marg
        fw[FW_MARG + kb] = marg
        if marg >= 0.0:
            if lo > -math.inf and hi < math.inf:
                s = 0.5 * (lo + hi)
            elif hi < math.inf:
                s = hi - fs
            elif lo > -math.inf:
                s = lo + fs
            else:
                s = 0.0
            fw[FW_SSTAR] = s
            for kc in (ka, kb):
                sg = 1.0 if kc == ka else -1.0
                nx, ny, nz = contact_normal(cp, kc)
                fo = FW_F + 3 * kc
                fw[fo] += sg * s * dx
                fw[fo + 1] += sg * s * dy
                fw[fo + 2] += sg * s * dz
                fw[FW_LAM + kc] += sg * s * (dx * nx + dy * ny + dz * nz)
    elif two_stick:
        lo = -math.inf
        hi = math.inf
        ok = True
        for kc in (ka, kb):
            fo = FW_F + 3 * kc
            sg = 1.0 if kc == ka else -1.0
            nx, ny, nz = contact_normal(cp, kc)
            mu = contact_mu(cp, kc)
            lam = fw[FW_LAM + kc]
            ax = fw[fo] - lam * nx
            ay = fw[fo + 1] - lam * ny
            az = fw[fo + 2] - lam * nz
            # |a + sg s d|^2 <= (mu lam)^2
            ad = (ax * dx + ay * dy + az * dz) * sg
            c = ax * ax + ay * ay + az * az - (mu * lam) ** 2
            disc = ad * ad - c
            if disc < 0.0 or lam < 0.0:
                ok = False
                lo = 0.0
                hi = -math.sqrt(max(-disc, 0.0))
                break
            sq = math.sqrt(disc)
            lo = max(lo, -ad - sq)
            hi = min(hi, -ad + sq)
        marg = hi - lo
        fw[FW_MARG + ka] = marg
        fw[FW_MARG + kb] = marg
        if ok and marg >= 0.0:
            s = 0.5 * (lo + hi)
            fw[FW_SSTAR] = s
            fa = FW_F + 3 * ka
            fb = FW_F + 3 * kb
            fw[fa] += s * dx
            fw[fa + 1] += s * dy
            fw[fa + 2] += s * dz
            fw[fb] -= s * dx
            fw[fb + 1] -= s * dy
            fw[fb + 2] -= s * dz
    else:
        for kc in range(K):
            if cp[CP_S + kc] == 1.0:
                fo = FW_F + 3 * kc
                nx, ny, nz = contact_normal(cp, kc)
                mu = contact_mu(cp, kc)
                lam = fw[FW_LAM + kc]
                ax = fw[fo] - lam * nx
                ay = fw[fo + 1] - lam * ny
                az = fw[fo + 2] - lam * nz
                fw[FW_MARG + kc] = mu * lam - math.sqrt(ax * ax + ay * ay + az * az)
    # accelerations
    Fx = 0.0
    Fy = 0.0
    Fz = 0.0
    Tx = tx
    Ty = ty
    Tz = tz
    for kc in range(K):
        fo = FW_F + 3 * kc
        ro = FW_ARM + 3 * kc
        f0, f1, f2 = fw[fo], fw[fo + 1], fw[fo + 2]
        Fx += f0
        Fy += f1
        Fz += f2
        Tx += fw[ro + 1] * f2 - fw[ro + 2] * f1
        Ty += fw[ro + 2] * f0 - fw[ro] * f2
        Tz += fw[ro] * f1 - fw[ro + 1] * f0
    fw[FW_A] = gx + Fx / m
    fw[FW_A + 1] = gy + Fy / m
    fw[FW_A + 2] = gz + Fz / m
    fw[FW_AL] = fw[Ii] * Tx + fw[Ii + 1] * Ty + fw[Ii + 2] * Tz
    fw[FW_AL + 1] = fw[Ii + 3] * Tx + fw[Ii + 4] * Ty + fw[Ii + 5] * Tz
    fw[FW_AL + 2] = fw[Ii + 6] * Tx + fw[Ii + 7] * Ty + fw[Ii + 8] * Tz
    return PV_OK


@njit(cache=True)
def _rhs(y, cp, fw, k):
    """dy/ds at y (float64[13]) into k (float64[13]); returns the pivot_forces code."""
    rc = pivot_forces(y, cp, fw)
    for j in range(3):
        k[j] = y[7 + j]
        k[7 + j] = fw[FW_A + j]
        k[10 + j] = fw[FW_AL + j]
    d0, d1, d2, d3 = qmul(0.0, y[10], y[11], y[12], y[3], y[4], y[5], y[6])
    k[3] = 0.5 * d0
    k[4] = 0.5 * d1
    k[5] = 0.5 * d2
    k[6] = 0.5 * d3
    return rc


# ------------------------------------------------------------------ integrator


@njit(cache=True)
def pivot_start(pw, y0, cp, tol, max_steps):
    """Initialise the workspace for a phase starting at state y0 (float64[13])."""
    L = cp[CP_L]
    gl = math.sqrt(cp[CP_G] ** 2 + cp[CP_G + 1] ** 2 + cp[CP_G + 2] ** 2)
    vv = math.sqrt(y0[7] ** 2 + y0[8] ** 2 + y0[9] ** 2)
    ww = math.sqrt(y0[10] ** 2 + y0[11] ** 2 + y0[12] ** 2)
    V = vv + ww * L + math.sqrt(gl * L)
    pw[PW_TOL] = tol
    for j in range(NY):
        if j < 3:
            sc = L
        elif j < 7:
            sc = 1.0
        elif j < 10:
            sc = V
        else:
            sc = V / L
        pw[PW_SC + j] = sc
        pw[PW_YSTART + j] = y0[j]
    # rotation per step at most MAX_ANGLE: bound the angular speed by its energy scale
    wcap = V / L
    pw[PW_HMAX] = MAX_ANGLE / wcap
    pw[PW_MAXSTEP] = max_steps
    # a rolling phase on round features keeps its energy by projection (_keep_energy): it
    # has no end of its own (a capsule rolls on its cap for ever), so the integrator's
    # local errors would accumulate without bound; a pivot on a corner or an edge (radius
    # 0) ends when the body falls, and is left to the integrator alone
    conservative = cp[CP_RAD] > 0.0
    for k in range(int(cp[CP_K])):
        if cp[CP_S + k] != 1.0 and contact_mu(cp, k) != 0.0:
            conservative = False        # a contact slides with friction
    pw[PW_E0] = _kinetic(y0, cp) + _potential(y0, cp) if conservative else math.nan
    pivot_reset(pw)


@njit(cache=True, inline="always")
def _kinetic(y, cp):
    """Kinetic energy (J) of state y: m |v|^2 / 2 + sum_k I_k w_k^2 / 2 (body axes)."""
    b0, b1, b2 = qrot_inv(y[3], y[4], y[5], y[6], y[10], y[11], y[12])
    return 0.5 * (cp[CP_M] * (y[7] * y[7] + y[8] * y[8] + y[9] * y[9])
                  + cp[CP_I] * b0 * b0 + cp[CP_I + 1] * b1 * b1 + cp[CP_I + 2] * b2 * b2)


@njit(cache=True, inline="always")
def _potential(y, cp):
    """Gravitational potential energy (J) of state y: -m g . x."""
    return -cp[CP_M] * (cp[CP_G] * y[0] + cp[CP_G + 1] * y[1] + cp[CP_G + 2] * y[2])


@njit(cache=True)
def _keep_energy(pw, cp):
    """Projection of the step's state ``pw[PW_Y]`` onto the energy of a conservative
    rolling phase (round features; every contact sticks, or slides without friction: the
    contact forces do no work): v and w are scaled by one factor, which keeps every
    contact velocity (linear in v and w) at zero. Hairer, Lubich & Wanner, Geometric
    Numerical Integration, 2nd ed., section IV.4 (standard projection). Without it the energy of a long rolling or
    rocking phase drifts by the integrator's local errors (a capsule rolling 6 s on its
    cap: +4e-10 J of 0.4 J, 3:3045601098)."""
    E0 = pw[PW_E0]
    if E0 != E0:
        return
    y = pw[PW_Y:PW_Y + NY]
    T = _kinetic(y, cp)
    if not T > 0.0:
        return
    s2 = (E0 - _potential(y, cp)) / T
    if abs(s2 - 1.0) > ENERGY_FIX_MAX:
        return
    f = math.sqrt(s2)
    for j in range(7, NY):
        pw[PW_Y + j] *= f


@njit(cache=True)
def pivot_reset(pw):
    for j in range(NY):
        pw[PW_Y + j] = pw[PW_YSTART + j]
    pw[PW_S0] = 0.0
    pw[PW_H] = 0.0
    pw[PW_NSTEP] = 0.0
    pw[PW_HNEXT] = pw[PW_HMAX] * pw[PW_TOL] ** 0.2 * 10.0
    if pw[PW_HNEXT] > pw[PW_HMAX]:
        pw[PW_HNEXT] = pw[PW_HMAX]


@njit(cache=True, inline="always")
def _failed(pw, rc):
    """Record a pivot_forces code in pw[PW_WHY]; True when it is a failure."""
    if rc != PV_OK:
        pw[PW_WHY] = rc
        return True
    return False


@njit(cache=True)
def _stage(cp, fw, pw, yo, ko):
    """The right-hand side of ``dopri5_step``: ``_rhs`` at pw[yo:yo+NY] into pw[ko:ko+NY];
    PI_OK, or PI_FORCES with the pivot_forces code in pw[PW_WHY]."""
    if _failed(pw, _rhs(pw[yo:yo + NY], cp, fw, pw[ko:ko + NY])):
        return PI_FORCES
    return PI_OK


@njit(cache=True)
def pivot_step(pw, cp, fw):
    """Take one accepted step after the current one (or the first). Returns PI_*."""
    if pw[PW_H] > 0.0:
        q0, q1, q2, q3 = qnormalize(pw[PW_Y1 + 3], pw[PW_Y1 + 4], pw[PW_Y1 + 5],
                                    pw[PW_Y1 + 6])
        for j in range(NY):
            pw[PW_Y + j] = pw[PW_Y1 + j]
        pw[PW_Y + 3] = q0
        pw[PW_Y + 4] = q1
        pw[PW_Y + 5] = q2
        pw[PW_Y + 6] = q3
        _keep_energy(pw, cp)
        pw[PW_S0] = pw[PW_S0] + pw[PW_H]
    h = min(pw[PW_HNEXT], pw[PW_HMAX])
    if _stage(cp, fw, pw, PW_Y, PW_K) != PI_OK:
        return PI_FORCES
    # a stage beyond a mode change (no consistent contact force) shortens the step
    code, att = dopri5_step(_stage, (cp, fw), pw, NY, PW_Y, PW_YT, PW_Y1, PW_K, PW_RC, PW_SC,
                            PW_H, PW_HNEXT, pw[PW_TOL], h, pw[PW_MAXSTEP] - pw[PW_NSTEP],
                            False, STAGE_SHRINK, STAGE_HMIN * pw[PW_HMAX], PI_TOO_MANY_STEPS)
    pw[PW_NSTEP] += att
    return code


@njit(cache=True)
def pivot_dense(pw, s, out):
    """State at s (within the current step) into out[0:13], quaternion normalised."""
    dense_out(pw, NY, PW_RC, PW_S0, PW_H, s, out, 0)
    q0, q1, q2, q3 = qnormalize(out[3], out[4], out[5], out[6])
    out[3] = q0
    out[4] = q1
    out[5] = q2
    out[6] = q3


@njit(cache=True)
def pivot_eval(pw, cp, fw, s, out):
    """State at s >= 0 of the phase into out[0:13] (stepping forward as needed, restarting
    from the phase start when s lies before the current step). Returns PI_*."""
    if s < pw[PW_S0]:
        pivot_reset(pw)
    if s == 0.0 and pw[PW_H] == 0.0:
        for j in range(NY):
            out[j] = pw[PW_YSTART + j]
        return PI_OK
    while pw[PW_H] == 0.0 or s > pw[PW_S0] + pw[PW_H]:
        rc = pivot_step(pw, cp, fw)
        if rc != PI_OK:
            return rc
    pivot_dense(pw, s, out)
    return PI_OK


@njit(cache=True, inline="always")
def contact_accel(y, fw, k):
    """Acceleration (m/s^2, world) of the material point at contact k of the body in state
    ``y`` under the forces in ``fw`` (``pivot_forces``): ``a_cm + alpha x r + w x (w x s)``,
    with ``w x (w x s) = w (w.s) - s |w|^2``."""
    ro = FW_ARM + 3 * k
    so = FW_SARM + 3 * k
    return point_accel(y, fw, fw[ro], fw[ro + 1], fw[ro + 2], fw[so], fw[so + 1], fw[so + 2])


@njit(cache=True, inline="always")
def point_accel(y, fw, rx, ry, rz, sx, sy, sz):
    """Acceleration (m/s^2, world) of the material point at arm ``r`` (m) of the body in
    state ``y`` under the forces in ``fw``: ``a_cm + alpha x r + w x (w x s)``, ``s`` the
    arm whose centripetal term applies (a feature centre; ``r`` its contact point)."""
    wx, wy, wz = y[10], y[11], y[12]
    alx, aly, alz = fw[FW_AL], fw[FW_AL + 1], fw[FW_AL + 2]
    ws = wx * sx + wy * sy + wz * sz
    w2 = wx * wx + wy * wy + wz * wz
    ax = fw[FW_A] + aly * rz - alz * ry + wx * ws - sx * w2
    ay = fw[FW_A + 1] + alz * rx - alx * rz + wy * ws - sy * w2
    az = fw[FW_A + 2] + alx * ry - aly * rx + wz * ws - sz * w2
    return ax, ay, az


@njit(cache=True)
def slip_growth(y, cp, fw, k):
    """u . a_c (m/s^2): acceleration of contact k's slip along its friction direction u."""
    ax, ay, az = contact_accel(y, fw, k)
    ux, uy, uz = _slipdir(fw, cp, k)
    return ux * ax + uy * ay + uz * az


@njit(cache=True)
def _event_values(y, cp, fw, feats, f0, nf, planes, skip, vals, vfl):
    """Event functions at state y into vals (layout ``NEV_CONTACT``): [k] lift (lam_k),
    [KMAX + k] stick margins, [2 KMAX + k] slip speed minus slip_eps (for a slip started
    from sticking and still below slip_eps: its growth rate, so that a slip that stops
    growing sticks again), [NEV_CONTACT + p nf + j] gaps minus their floors ``vfl``
    (a feature touching at the start -- gap <= 0 -- is armed too: it fires when its gap
    goes below its starting value by GAP_ARM L). Returns the force code."""
    rc = pivot_forces(y, cp, fw)
    K = int(cp[CP_K])
    for k in range(NEV_CONTACT):
        vals[k] = math.inf
    for k in range(K):
        vals[k] = fw[FW_LAM + k] - vfl[k]
        st = int(cp[CP_S + k])
        if st == 1:
            vals[KMAX + k] = fw[FW_MARG + k] - vfl[KMAX + k]
        elif contact_mu(cp, k) != 0.0:
            # (a frictionless contact slides for ever: no stop event)
            co = FW_C + 3 * k
            c = math.sqrt(fw[co] ** 2 + fw[co + 1] ** 2 + fw[co + 2] ** 2)
            vals[2 * KMAX + k] = c - cp[CP_EPS]
            uo = CP_U + 3 * k
            if c < cp[CP_EPS] and (cp[uo] != 0.0 or cp[uo + 1] != 0.0 or cp[uo + 2] != 0.0):
                # a slip started from sticking, still below slip_eps: it must keep growing
                # (its acceleration along the friction direction stays positive)
                vals[2 * KMAX + k] = slip_growth(y, cp, fw, k)
    rad = cp[CP_RAD]
    for p in range(planes.shape[0]):
        for j in range(nf):
            idx = NEV_CONTACT + p * nf + j
            held = skip[p] != 0
            for k in range(K):
                if p == int(cp[CP_PLANE + k]) and f0 + j == int(cp[CP_F + k]):
                    held = True
            if held:
                vals[idx] = math.inf
                continue
            vals[idx] = _gap(y, feats, f0 + j, planes, p, rad) - vfl[idx]
    return rc


@njit(cache=True, inline="always")
def _gap(y, feats, f, planes, p, rad):
    """Gap (m) of feature row f (body frame) of the body in state y to plane p."""
    rx, ry, rz = qrot(y[3], y[4], y[5], y[6], feats[f, 0], feats[f, 1], feats[f, 2])
    return (planes[p, 0] * (y[0] + rx) + planes[p, 1] * (y[1] + ry)
            + planes[p, 2] * (y[2] + rz) - planes[p, 3] - rad)


@njit(cache=True, inline="always")
def _gap_rate(y, feats, f, planes, p):
    """Rate (m/s) of ``_gap``: ``n . (v + w x r)``, r the feature's arm (world)."""
    rx, ry, rz = qrot(y[3], y[4], y[5], y[6], feats[f, 0], feats[f, 1], feats[f, 2])
    wx, wy, wz = y[10], y[11], y[12]
    return (planes[p, 0] * (y[7] + wy * rz - wz * ry) + planes[p, 1] * (y[8] + wz * rx - wx * rz)
            + planes[p, 2] * (y[9] + wx * ry - wy * rx))


@njit(cache=True)
def _gap_dip(pw, feats, f, planes, p, rad, floor, t0, rtol, atol, ybuf):
    """A gap positive at both ends of the current step (``s0 = pw[PW_S0]``, ``s1 = s0 +
    pw[PW_H]``) whose rate goes from negative to positive has a minimum inside: locate it
    (root of the rate on the dense output, bisection to the event precision) and return
    ``(s_min, gap_min - floor)``; ``(s1, inf)`` when the rate does not change sign.
    ``ybuf`` holds the state at s1 on entry and again on return."""
    s0 = pw[PW_S0]
    s1 = s0 + pw[PW_H]
    if not _gap_rate(pw[PW_Y:PW_Y + NY], feats, f, planes, p) < 0.0:
        return s1, math.inf
    if _gap_rate(ybuf, feats, f, planes, p) < 0.0:
        return s1, math.inf
    lo = s0
    hi = s1
    for it in range(EVENT_ITER):
        if hi - lo <= atol + rtol * abs(t0 + hi):
            break
        mid = 0.5 * (lo + hi)
        pivot_dense(pw, mid, ybuf)
        if _gap_rate(ybuf, feats, f, planes, p) < 0.0:
            lo = mid
        else:
            hi = mid
    pivot_dense(pw, hi, ybuf)
    gmin = _gap(ybuf, feats, f, planes, p, rad) - floor
    pivot_dense(pw, s1, ybuf)
    return hi, gmin


@njit(cache=True)
def pivot_next_event(pw, cp, fw, feats, f0, nf, planes, skip, S, t0, rtol, atol, ybuf,
                     vals, vals0, vfl):
    """Integrate the phase from its start until the first event or ``S`` (s). Returns
    ``(s, kind, index, code)``: kind ``PE_*`` (``PE_NONE`` when ``S`` is reached), code
    ``PI_*``. ``ybuf`` float64[13], ``vals``/``vals0``/``vfl`` float64[NEV_CONTACT + np nf]
    are scratch."""
    pivot_reset(pw)
    nv = NEV_CONTACT + planes.shape[0] * nf
    for j in range(NY):
        ybuf[j] = pw[PW_YSTART + j]
    for e in range(nv):
        vfl[e] = 0.0
    rc = _event_values(ybuf, cp, fw, feats, f0, nf, planes, skip, vals0, vfl)
    farm = FORCE_ARM * cp[CP_M] * math.sqrt(cp[CP_G] ** 2 + cp[CP_G + 1] ** 2
                                            + cp[CP_G + 2] ** 2)
    for e in range(2 * KMAX):
        if vals0[e] < farm:
            vfl[e] = min(0.0, vals0[e]) - farm
            vals0[e] -= vfl[e]
    arm = GAP_ARM * cp[CP_L]
    for e in range(NEV_CONTACT, nv):
        if vals0[e] < math.inf:
            vfl[e] = min(0.0, vals0[e]) - arm
            vals0[e] -= vfl[e]
    if _failed(pw, rc):
        return 0.0, PE_NONE, 0, PI_FORCES
    while True:
        rc = pivot_step(pw, cp, fw)
        if rc != PI_OK:
            return pw[PW_S0], PE_NONE, 0, rc
        s1 = pw[PW_S0] + pw[PW_H]
        pivot_dense(pw, s1, ybuf)
        rc = _event_values(ybuf, cp, fw, feats, f0, nf, planes, skip, vals, vfl)
        if _failed(pw, rc):
            return pw[PW_S0], PE_NONE, 0, PI_FORCES
        # earliest crossing from > 0 to <= 0 in this step
        best = math.inf
        bk = -1
        for e in range(nv):
            sb = s1
            fb = vals[e]
            if e >= NEV_CONTACT and vals0[e] > 0.0 and fb > 0.0 and fb < math.inf:
                # a gap positive at both ends may dip through the plane in between
                g = e - NEV_CONTACT
                sb, fb = _gap_dip(pw, feats, f0 + g % nf, planes, g // nf, cp[CP_RAD],
                                  vfl[e], t0, rtol, atol, ybuf)
            if vals0[e] > 0.0 and fb <= 0.0:
                sa = pw[PW_S0]
                fa = vals0[e]
                for it in range(EVENT_ITER):
                    if sb - sa <= atol + rtol * abs(t0 + sb):
                        break
                    # Illinois-free safeguarded secant: midpoint when the secant stalls
                    sm = sb - fb * (sb - sa) / (fb - fa) if fb != fa else 0.5 * (sa + sb)
                    if not (sa < sm < sb) or it % 3 == 2:
                        sm = 0.5 * (sa + sb)
                    pivot_dense(pw, sm, ybuf)
                    _event_values(ybuf, cp, fw, feats, f0, nf, planes, skip, vals, vfl)
                    fm = vals[e]
                    if fm > 0.0:
                        sa = sm
                        fa = fm
                    else:
                        sb = sm
                        fb = fm
                if sb < best:
                    best = sb
                    bk = e
                # restore the step-end values
                pivot_dense(pw, s1, ybuf)
                _event_values(ybuf, cp, fw, feats, f0, nf, planes, skip, vals, vfl)
        if bk >= 0 and best <= S:
            if bk < KMAX:
                return best, PE_LIFT, bk, PI_OK
            if bk < 2 * KMAX:
                return best, PE_SLIP, bk - KMAX, PI_OK
            if bk < NEV_CONTACT:
                return best, PE_STOP, bk - 2 * KMAX, PI_OK
            g = bk - NEV_CONTACT
            return best, PE_GAP, (g // nf) * 1000 + (g % nf), PI_OK
        if s1 >= S:
            return S, PE_NONE, 0, PI_OK
        for e in range(nv):
            vals0[e] = vals[e]


@njit(cache=True)
def sample_segments(seg_t, seg_s, start, stop, rk, axis, I1, I2, I3, rot_tol, contact_tol,
                    max_steps, times, order, out, col, ws, pw, pwck, fw, pose, curbox):
    """Evaluate one body's piecewise motion at ``times[order]`` (``order`` sorts them) into
    ``out[k, col, 0:13]`` (x, q, v, w): closed-form or integrated flight segments
    (``flight3d.pose_at``) and integrated-contact segments (``seg_s[r, 19] == 1``, contact
    parameters in ``seg_s[r, 20:]``), each re-integrated from its start exactly as in the
    run. ``fw`` and ``pose`` are scratch; ``ws`` and ``pw`` are the integrators of segment
    row ``curbox[0]`` (-1: none) and are kept from one call to the next: a later time in
    the same segment steps on from where the last call stopped. ``pwck`` keeps the
    integrated contact's state at the step of the time evaluated before the last forward
    move (``pwck[PW_H] <= 0``: none): an earlier time at or after that step resumes from
    it (a minimiser's probes go back and forth within a small bracket), an earlier one
    restarts the segment. The steps do not depend on the times asked, so the values are
    the same bit for bit. Returns 0, or 1 on integrator failure."""
    n = stop - start
    cur = curbox[0]
    for kk in range(times.shape[0]):
        k = order[kk]
        t = times[k]
        lo = 0
        hi = n - 1
        if seg_t[start] > t:
            j = 0
        else:
            while lo < hi:
                mid = (lo + hi + 1) // 2
                if seg_t[start + mid] <= t:
                    lo = mid
                else:
                    hi = mid - 1
            j = lo
        r = start + j
        s = t - seg_t[r]
        if seg_s[r, 19] == 1.0:
            cp = seg_s[r, 20:]
            if r != cur:
                pivot_start(pw, seg_s[r], cp, contact_tol, max_steps)
                pwck[PW_H] = 0.0
                cur = r
                curbox[0] = r
            if s < pw[PW_S0]:
                if pwck[PW_H] > 0.0 and s >= pwck[PW_S0]:
                    for j in range(N_PW):
                        pw[j] = pwck[j]
            elif pw[PW_H] > 0.0 and s > pw[PW_S0] + pw[PW_H]:
                for j in range(N_PW):
                    pwck[j] = pw[j]
            rc = pivot_eval(pw, cp, fw, s, pose)
            if rc != PI_OK:
                curbox[0] = -1
                return 1
        else:
            if r != cur:
                ws[0] = -1.0
                cur = r
                curbox[0] = r
            rc = pose_at(seg_s[r], rk, axis, I1, I2, I3, ws, s, rot_tol, max_steps, pose)
            if rc != 0:
                curbox[0] = -1
                return 1
        for m in range(13):
            out[k, col, m] = pose[m]
    return 0
