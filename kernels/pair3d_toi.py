"""Time of impact of two bodies in 3D flight (every pair kind of ``pair3d``): the earliest
``s`` in ``[0, S]`` with ``g(s) = 0`` and ``g'(s) < 0``, never passing a root (grazing and
fast-spinning bodies included), polished to round-off. The 3D twin of ``pair2d_toi``.

Each body moves by its ``flight3d`` state row ``st`` valid at ``t0`` (``s = t - t0``):
quadratic centre, torque-free rotation as ``flight3d.pose_at`` integrates it (closed form
for spherical and axisymmetric inertia, Dormand-Prince with error control ``rot_tol``
otherwise; its workspace ``ws`` is reset here, so the trajectory is the one the stepper
replays). ``g`` is the signed gap of ``pair3d`` (exact distance when disjoint).

Lower bound (conservative advancement; Mirtich, *Impulse-based dynamic simulation of rigid
body systems*, PhD thesis, Berkeley 1996, ch. 5, in its second-order form). For any unit
axis path ``n(s)`` the separation ``sigma(n(s), s) = min_A n . a - max_B n . b`` is at most
``g(s)`` (separating-axis inequality), with equality at ``s0`` for the frame's normal.
``sigma`` is the minimum over pairs of core vertices ``(k, l)`` (``pair3d_shape``: sphere
centre, capsule ends, box corners) of smooth terms ``g_kl(s) = n . (a_k - b_l) - rA - rB``,
so ``g(s0 + h) >= min_kl [g_kl(s0) + g_kl'(s0) h] - M h^2 / 2`` with ``M`` a bound of every
``|g_kl''|`` over the window, and stepping to the first zero of that bound never passes a
root of ``g``, whatever features realise the distance later: no smoothness of ``g`` is
assumed.

The axis turns at an angular velocity ``w_n`` chosen from the closest features at ``s0``
so that the tied terms share their rate (then the bound is tangent to ``g`` and the steps
converge quadratically near a transversal root):

* ``AX_A`` (A's feature a face, else an edge against a vertex): fixed in A, ``w_n = w_A(s)``;
  A's support along the axis is then one body-fixed term (``k*``) for all ``s``;
* ``AX_B`` likewise fixed in B;
* ``AX_EDGE`` (two edges, or a capsule's side against an edge or side): the constant
  ``w_n = c`` with ``(w_A - c) . (e_A x n) = 0`` and ``(w_B - c) . (e_B x n) = 0``, ``c`` in the
  plane normal to ``n`` (both edges' end terms then move alike); when the edges are within
  ``EDGE_AXIS_SIN`` (sine) of parallel ``AX_A`` is used instead;
* ``AX_WORLD`` otherwise (``w_n = 0``).

Bound. With ``D = x_A - x_B``, ``r = R p`` a core vertex's offset (``|r| <= K``, the body's
reach, ``pair3d_shape.body_reach``), ``W_i = w_i - w_n``, ``n' = w_n x n`` and
``d/ds (n . r) = n . (W_i x r)``, so ``d2/ds2 (n . r) = (w_n x n) . (W_i x r) + n . (W_i' x r)
+ (n x W_i) . (w_i x r)``:

    |g_kl''| <= |D''| + 2 X_n |D'| + (|w_n| X_n + |w_n'|) |D|
                + sum_i K_i (X_n |W_i| + |n x W_i| |w_i| + |W_i'|),     X_n = |n x w_n|,

anisotropic in the spin (a body spinning about the normal adds nothing), every factor
bounded over the window ``[s0, s0 + H]``: ``|w_i|``, ``|w_i'|`` by
``flight3d.rotation_bounds`` (times ``1 + toi3d.GENERAL_BOUND_SLACK`` for integrated
rotation), ``|W_i| <= min(|w_i| + |w_n|, |W_i(s0)| + (|w_i'| + |w_n'|) H)``, the cross
products from their value at ``s0`` and a bound of their rate
(``|d/ds (n x W)| <= X_n |W| + |W'|``), ``|D'| <= |D'(s0)| + |D''| H``,
``|D| <= |D(s0)| + |D'(s0)| H + |D''| H^2 / 2``. In free flight with a world axis
``M = |a_A - a_B| + sum K_i |n x w_i| |w_i|`` (at most ``toi3d``'s ``K |w|^2``).
``closing_speed_bound`` gives Mirtich's linear bound ``|g'| <= V`` (kept for a broad phase).
A body resting or sliding on a face at a gap ``g`` far below ``M S^2`` (spinning about a
tilted axis, or with a varying ``w``) advances by about ``sqrt(2 g / M)`` per step and may end
``TOI_NOT_CONVERGED``; such contacts are the contact modes' (DESIGN §6a).

Windows, termination, tangency and polish as ``pair2d_toi`` (``POLISH_IT`` Newton steps on
the gap, each within ``POLISH_REACH`` time tolerances). Return ``(s, code)`` (``toi2d``,
``toi3d``): ``TOI_OK`` (``s = inf``: none in ``[0, S]``), ``TOI_MISSED`` (the gap at ``s = 0``
is below ``-gap_tol``: the bodies overlap; ``s = 0``), ``TOI_NOT_CONVERGED`` (``maxit`` steps,
or an unknown pair of kinds, ``s`` NaN), ``toi3d.TOI_ROT_FAILED`` (the rotation integrator
hit ``rot_max`` steps). Two spheres: ``toi3d.sphere_sphere_toi`` (closed form when the
accelerations are equal).
"""
import math

from numba import njit

from .cache_guard import guard

guard(__name__, __file__)

from .flight3d import RK_OK, ROT_GENERAL, WS_MODE, pose_at, rotation_bounds  # noqa: E402
from .pair3d import PK_NONE, PK_SPHERE_SPHERE, frame_rel, pair_kind, point_rate  # noqa: E402
from .pair3d_shape import (FT_EDGE, FT_FACE, SH_BOX, body_reach, core_vertex,  # noqa: E402
                           n_core, quat_matrix)
from .toi2d import INF, TOI_MISSED, TOI_NOT_CONVERGED, TOI_OK, _safe_step  # noqa: E402
from .toi3d import GENERAL_BOUND_SLACK, TOI_ROT_FAILED, sphere_sphere_toi  # noqa: E402

AX_WORLD = 0        # axis fixed in the world
AX_A = 1            # axis turning with A
AX_B = 2            # axis turning with B
AX_EDGE = 3         # axis turning at the constant rate that keeps two edges' ends tied
EDGE_AXIS_SIN = 0.1  # edges closer to parallel than this sine use AX_A instead (-)
POLISH_IT = 3       # Newton steps of the final polish
POLISH_REACH = 64.0  # a polish step longer than this many time tolerances is refused


@njit(cache=True, _nrt=False, inline="always")
def _rel(stA, stB, s):
    """B's centre relative to A's at ``s`` from the differences of the rows (no
    cancellation of large common coordinates)."""
    h = 0.5 * s * s
    return ((stB[0] - stA[0]) + (stB[7] - stA[7]) * s + (stB[13] - stA[13]) * h,
            (stB[1] - stA[1]) + (stB[8] - stA[8]) * s + (stB[14] - stA[14]) * h,
            (stB[2] - stA[2]) + (stB[9] - stA[9]) * s + (stB[15] - stA[15]) * h)


@njit(cache=True, _nrt=False, inline="always")
def _feature_dir(kind, f, idx, pose):
    """World unit direction of an edge feature (box edge ``idx``, or a capsule's axis)."""
    i = idx // 4 if kind == SH_BOX else 2
    R = quat_matrix(pose[3], pose[4], pose[5], pose[6])
    return R[i], R[3 + i], R[6 + i]


@njit(cache=True, _nrt=False)
def _eval(kA, rA, hxA, hyA, hzA, stA, kB, rB, hxB, hyB, hzB, stB, s, pA, pB):
    """Frame at ``s`` (poses ``pA``, ``pB`` already at ``s``): ``(g, g', n, fa, ia, fb, ib)``."""
    dx, dy, dz = _rel(stA, stB, s)
    g, nx, ny, nz, pax, pay, paz, pbx, pby, pbz, fa, ia, fb, ib = frame_rel(
        kA, rA, hxA, hyA, hzA, pA[3], pA[4], pA[5], pA[6],
        kB, rB, hxB, hyB, hzB, pB[3], pB[4], pB[5], pB[6], dx, dy, dz)
    gd = point_rate(nx, ny, nz, pax, pay, paz, pbx - dx, pby - dy, pbz - dz,
                    pA[7], pA[8], pA[9], pA[10], pA[11], pA[12],
                    pB[7], pB[8], pB[9], pB[10], pB[11], pB[12])
    return g, gd, nx, ny, nz, fa, ia, fb, ib


@njit(cache=True, _nrt=False)
def closing_speed_bound(stA, stB, rhoA, rhoB, WA, AA, WB, AB, H):
    """Mirtich's bound ``V >= |g'|`` over ``[0, H]`` (m/s): ``|v_B - v_A| + |a_B - a_A| H +
    sum_i (W_i + A_i H) rho_i`` with ``rho_i`` the largest distance of a surface point of
    body ``i`` from its centre of mass (m, reach plus radius) and ``W_i``, ``A_i`` bounds of
    its ``|w|`` and ``|w'|`` (``flight3d.rotation_bounds``). ``g(s + h) >= g(s) - V h``: the
    linear form of the advancement, for a broad phase."""
    dvx = stB[7] - stA[7]
    dvy = stB[8] - stA[8]
    dvz = stB[9] - stA[9]
    dax = stB[13] - stA[13]
    day = stB[14] - stA[14]
    daz = stB[15] - stA[15]
    return (math.sqrt(dvx * dvx + dvy * dvy + dvz * dvz)
            + math.sqrt(dax * dax + day * day + daz * daz) * H
            + (WA + AA * H) * rhoA + (WB + AB * H) * rhoB)


@njit(cache=True, _nrt=False)
def axis_rate(mode, kA, kB, fa, ia, fb, ib, nx, ny, nz, pA, pB):
    """The axis's angular velocity ``c`` at ``s0`` for ``mode`` (``AX_*``), and the mode
    actually used (``AX_EDGE`` falls back to ``AX_A`` for near-parallel edges)."""
    if mode == AX_A:
        return AX_A, pA[10], pA[11], pA[12]
    if mode == AX_B:
        return AX_B, pB[10], pB[11], pB[12]
    if mode == AX_WORLD:
        return AX_WORLD, 0.0, 0.0, 0.0
    ex, ey, ez = _feature_dir(kA, fa, ia, pA)
    fx, fy, fz = _feature_dir(kB, fb, ib, pB)
    # uA = eA x n, uB = eB x n (unit when the edges are normal to n)
    ax = ey * nz - ez * ny
    ay = ez * nx - ex * nz
    az = ex * ny - ey * nx
    bx = fy * nz - fz * ny
    by = fz * nx - fx * nz
    bz = fx * ny - fy * nx
    la = math.sqrt(ax * ax + ay * ay + az * az)
    lb = math.sqrt(bx * bx + by * by + bz * bz)
    if not (la > 0.5 and lb > 0.5):
        return AX_A, pA[10], pA[11], pA[12]
    ax /= la
    ay /= la
    az /= la
    bx /= lb
    by /= lb
    bz /= lb
    k = ax * bx + ay * by + az * bz
    det = 1.0 - k * k
    if not det > EDGE_AXIS_SIN * EDGE_AXIS_SIN:
        return AX_A, pA[10], pA[11], pA[12]
    a = pA[10] * ax + pA[11] * ay + pA[12] * az
    b = pB[10] * bx + pB[11] * by + pB[12] * bz
    x = (a - k * b) / det
    y = (b - k * a) / det
    return AX_EDGE, x * ax + y * bx, x * ay + y * by, x * az + y * bz


@njit(cache=True, _nrt=False, inline="always")
def _cross_norm(ax, ay, az, bx, by, bz):
    """``|a x b|``."""
    x = ay * bz - az * by
    y = az * bx - ax * bz
    z = ax * by - ay * bx
    return math.sqrt(x * x + y * y + z * z)


@njit(cache=True, _nrt=False)
def axis_bound(mode, cx, cy, cz, nx, ny, nz, stA, stB, s, H, pA, pB, KA, WA, AA, KB, WB, AB):
    """Bound ``M`` (m/s^2) of ``|g_kl''|`` over ``[s, s + H]`` for the axis ``n`` (at ``s``)
    turning at ``c`` (``mode`` ``AX_*``); ``K`` reaches (m), ``W`` bounds of ``|w|`` (rad/s),
    ``A`` of ``|w'|`` (rad/s^2); see the module docstring."""
    dx, dy, dz = _rel(stA, stB, s)
    dD = math.sqrt(dx * dx + dy * dy + dz * dz)
    vx = pB[7] - pA[7]
    vy = pB[8] - pA[8]
    vz = pB[9] - pA[9]
    dV = math.sqrt(vx * vx + vy * vy + vz * vz)
    dA = math.sqrt((stB[13] - stA[13]) ** 2 + (stB[14] - stA[14]) ** 2
                   + (stB[15] - stA[15]) ** 2)
    if mode == AX_A:
        Wn = WA
        An = AA
    elif mode == AX_B:
        Wn = WB
        An = AB
    else:
        Wn = math.sqrt(cx * cx + cy * cy + cz * cz)
        An = 0.0
    # |n x w_n| over the window: d/ds (n x w_n) = (w_n x n) x w_n + n x w_n'
    Xn = min(Wn, _cross_norm(nx, ny, nz, cx, cy, cz) + (Wn * Wn + An) * H)
    M = dA
    if Xn > 0.0 or An > 0.0:
        vDm = dV + dA * H
        dDm = dD + dV * H + 0.5 * dA * H * H
        M += 2.0 * Xn * vDm + (Wn * Xn + An) * dDm
    for b in range(2):
        if (b == 0 and mode == AX_A) or (b == 1 and mode == AX_B):
            continue
        K = KA if b == 0 else KB
        if not K > 0.0:
            continue
        p = pA if b == 0 else pB
        W = WA if b == 0 else WB
        A = AA if b == 0 else AB
        ox = p[10] - cx
        oy = p[11] - cy
        oz = p[12] - cz
        O = min(W + Wn, math.sqrt(ox * ox + oy * oy + oz * oz) + (A + An) * H)
        Od = A + An
        # |n x (w_i - w_n)| over the window: its rate is at most Xn O + Od
        XO = min(O, _cross_norm(nx, ny, nz, ox, oy, oz) + (Xn * O + Od) * H)
        M += K * (Xn * O + XO * W + Od)
    return M


@njit(cache=True, _nrt=False)
def safe_step(mode, cx, cy, cz, kA, rA, hxA, hyA, hzA, stA, kB, rB, hxB, hyB, hzB, stB, s,
              nx, ny, nz, M, pA, pB):
    """First zero ``h >= 0`` of ``min_kl [g_kl + g_kl' h] - M h^2 / 2`` along ``n`` at ``s``
    for the axis turning at ``c`` (``inf`` if none): no root of the gap lies in
    ``(s, s + h)``. ``AX_A`` (``AX_B``): only A's (B's) supporting vertex enters."""
    dx, dy, dz = _rel(stA, stB, s)
    RA = quat_matrix(pA[3], pA[4], pA[5], pA[6])
    RB = quat_matrix(pB[3], pB[4], pB[5], pB[6])
    # w_n x n
    qx = cy * nz - cz * ny
    qy = cz * nx - cx * nz
    qz = cx * ny - cy * nx
    mA = n_core(kA)
    mB = n_core(kB)
    kstar = -1
    lstar = -1
    if mode == AX_A and mA > 1:
        lo = math.inf
        for k in range(mA):
            px, py, pz = core_vertex(kA, hxA, hyA, hzA, k)
            v = nx * (RA[0] * px + RA[1] * py + RA[2] * pz) + ny * (
                RA[3] * px + RA[4] * py + RA[5] * pz) + nz * (RA[6] * px + RA[7] * py
                                                              + RA[8] * pz)
            if v < lo:
                lo = v
                kstar = k
    if mode == AX_B and mB > 1:
        hi = -math.inf
        for l in range(mB):
            px, py, pz = core_vertex(kB, hxB, hyB, hzB, l)
            v = nx * (RB[0] * px + RB[1] * py + RB[2] * pz) + ny * (
                RB[3] * px + RB[4] * py + RB[5] * pz) + nz * (RB[6] * px + RB[7] * py
                                                              + RB[8] * pz)
            if v > hi:
                hi = v
                lstar = l
    h = INF
    for k in range(mA):
        if kstar >= 0 and k != kstar:
            continue
        px, py, pz = core_vertex(kA, hxA, hyA, hzA, k)
        ax = RA[0] * px + RA[1] * py + RA[2] * pz
        ay = RA[3] * px + RA[4] * py + RA[5] * pz
        az = RA[6] * px + RA[7] * py + RA[8] * pz
        # velocity of the vertex: v_A + w_A x a
        uax = pA[7] + pA[11] * az - pA[12] * ay
        uay = pA[8] + pA[12] * ax - pA[10] * az
        uaz = pA[9] + pA[10] * ay - pA[11] * ax
        for l in range(mB):
            if lstar >= 0 and l != lstar:
                continue
            px, py, pz = core_vertex(kB, hxB, hyB, hzB, l)
            rx = RB[0] * px + RB[1] * py + RB[2] * pz
            ry = RB[3] * px + RB[4] * py + RB[5] * pz
            rz = RB[6] * px + RB[7] * py + RB[8] * pz
            ubx = pB[7] + pB[11] * rz - pB[12] * ry
            uby = pB[8] + pB[12] * rx - pB[10] * rz
            ubz = pB[9] + pB[10] * ry - pB[11] * rx
            wx = ax - dx - rx
            wy = ay - dy - ry
            wz = az - dz - rz
            val = nx * wx + ny * wy + nz * wz - rA - rB
            rate = (qx * wx + qy * wy + qz * wz
                    + nx * (uax - ubx) + ny * (uay - uby) + nz * (uaz - ubz))
            hk = _safe_step(max(val, 0.0), rate, M)
            if hk < h:
                h = hk
    return h


@njit(cache=True, _nrt=False)
def _poses(stA, rkA, axA, IA1, IA2, IA3, wsA, stB, rkB, axB, IB1, IB2, IB3, wsB, s,
           rot_tol, rot_max, pA, pB):
    rc = pose_at(stA, rkA, axA, IA1, IA2, IA3, wsA, s, rot_tol, rot_max, pA)
    if rc != RK_OK:
        return rc
    return pose_at(stB, rkB, axB, IB1, IB2, IB3, wsB, s, rot_tol, rot_max, pB)


@njit(cache=True, _nrt=False)
def _polish(kA, rA, hxA, hyA, hzA, stA, rkA, axA, IA1, IA2, IA3, wsA, kB, rB, hxB, hyB,
            hzB, stB, rkB, axB, IB1, IB2, IB3, wsB, s, tol, rot_tol, rot_max, pA, pB):
    """Newton on the gap from ``s`` (``POLISH_IT`` steps, each at most ``POLISH_REACH * tol``
    s long), keeping the iterate of least ``|g|`` among those with ``g' < 0``."""
    best = s
    gbest = INF
    for _ in range(POLISH_IT):
        if _poses(stA, rkA, axA, IA1, IA2, IA3, wsA, stB, rkB, axB, IB1, IB2, IB3, wsB, s,
                  rot_tol, rot_max, pA, pB) != RK_OK:
            break
        g, gd, _, _, _, _, _, _, _ = _eval(kA, rA, hxA, hyA, hzA, stA, kB, rB, hxB, hyB,
                                           hzB, stB, s, pA, pB)
        if not gd < 0.0:
            break
        if abs(g) < gbest:
            gbest = abs(g)
            best = s
        if g == 0.0 or abs(g) > POLISH_REACH * tol * -gd:
            break
        s = s - g / gd
    return best


@njit(cache=True, _nrt=False)
def pair_toi(kA, rA, hxA, hyA, hzA, stA, rkA, axA, IA1, IA2, IA3, wsA,
             kB, rB, hxB, hyB, hzB, stB, rkB, axB, IB1, IB2, IB3, wsB,
             t0, S, rtol, atol, gap_tol, maxit, rot_tol, rot_max, pA, pB):
    """Earliest impact ``s`` in ``[0, S]`` (s after ``t0``) of bodies A and B.

    Each body: ``kind, rad, hx, hy, hz`` (``pair3d_shape``), its ``flight3d`` state row ``st``
    at ``t0``, rotation kind ``rk`` and symmetry axis ``ax``, principal moments ``I1..I3``
    (kg m^2) and integrator workspace ``ws`` (float64[flight3d.N_WS]). ``rtol`` (-), ``atol``
    (s), ``gap_tol`` (m), ``maxit``; ``rot_tol``, ``rot_max`` as ``flight3d.pose_at``;
    ``pA``, ``pB`` float64[19] scratch. Returns ``(s, code)``; see the module docstring."""
    pk, _ = pair_kind(kA, kB)
    if pk == PK_NONE:
        return math.nan, TOI_NOT_CONVERGED
    if pk == PK_SPHERE_SPHERE:
        return sphere_sphere_toi(stA[0] - stB[0], stA[1] - stB[1], stA[2] - stB[2],
                                 stA[7] - stB[7], stA[8] - stB[8], stA[9] - stB[9],
                                 stA[13] - stB[13], stA[14] - stB[14], stA[15] - stB[15],
                                 rA + rB, t0, S, rtol, atol, gap_tol, maxit)
    wsA[WS_MODE] = -1.0
    wsB[WS_MODE] = -1.0
    KA = body_reach(kA, hxA, hyA, hzA)
    KB = body_reach(kB, hxB, hyB, hzB)
    WA, AA = rotation_bounds(stA, IA1, IA2, IA3, rkA, axA, S)
    WB, AB = rotation_bounds(stB, IB1, IB2, IB3, rkB, axB, S)
    if rkA == ROT_GENERAL:
        WA *= 1.0 + GENERAL_BOUND_SLACK
        AA *= 1.0 + GENERAL_BOUND_SLACK
    if rkB == ROT_GENERAL:
        WB *= 1.0 + GENERAL_BOUND_SLACK
        AB *= 1.0 + GENERAL_BOUND_SLACK
    s = 0.0
    if _poses(stA, rkA, axA, IA1, IA2, IA3, wsA, stB, rkB, axB, IB1, IB2, IB3, wsB, s,
              rot_tol, rot_max, pA, pB) != RK_OK:
        return s, TOI_ROT_FAILED
    g, gd, nx, ny, nz, fa, ia, fb, ib = _eval(kA, rA, hxA, hyA, hzA, stA, kB, rB, hxB, hyB,
                                              hzB, stB, s, pA, pB)
    if g <= 0.0:
        code = TOI_MISSED if g < -gap_tol else TOI_OK
        if gd < 0.0 or code == TOI_MISSED:
            return 0.0, code
    H = S
    for _ in range(maxit):
        if fa == FT_FACE:
            mode = AX_A
        elif fb == FT_FACE:
            mode = AX_B
        elif fa == FT_EDGE and fb == FT_EDGE:
            mode = AX_EDGE
        elif fa == FT_EDGE:
            mode = AX_A
        elif fb == FT_EDGE:
            mode = AX_B
        else:
            mode = AX_WORLD
        mode, cx, cy, cz = axis_rate(mode, kA, kB, fa, ia, fb, ib, nx, ny, nz, pA, pB)
        Hw = min(H, S - s)
        M = axis_bound(mode, cx, cy, cz, nx, ny, nz, stA, stB, s, Hw, pA, pB, KA, WA, AA, KB,
                       WB, AB)
        h = safe_step(mode, cx, cy, cz, kA, rA, hxA, hyA, hzA, stA, kB, rB, hxB, hyB, hzB,
                      stB, s, nx, ny, nz, M, pA, pB)
        tol = atol + rtol * abs(t0 + s)
        if h >= Hw:
            h = Hw
            H = 2.0 * H
        else:
            if h <= tol:
                if gd < 0.0:
                    r = _polish(kA, rA, hxA, hyA, hzA, stA, rkA, axA, IA1, IA2, IA3, wsA,
                                kB, rB, hxB, hyB, hzB, stB, rkB, axB, IB1, IB2, IB3, wsB,
                                s + h, tol, rot_tol, rot_max, pA, pB)
                    return (r if r <= S else INF), TOI_OK
                h = tol     # tangency (grazing without crossing): step past it
            H = 4.0 * h
        s += h
        if s >= S:
            return INF, TOI_OK
        if _poses(stA, rkA, axA, IA1, IA2, IA3, wsA, stB, rkB, axB, IB1, IB2, IB3, wsB, s,
                  rot_tol, rot_max, pA, pB) != RK_OK:
            return s, TOI_ROT_FAILED
        g, gd, nx, ny, nz, fa, ia, fb, ib = _eval(kA, rA, hxA, hyA, hzA, stA, kB, rB, hxB,
                                                  hyB, hzB, stB, s, pA, pB)
        if g <= 0.0 and gd < 0.0:
            r = _polish(kA, rA, hxA, hyA, hzA, stA, rkA, axA, IA1, IA2, IA3, wsA, kB, rB,
                        hxB, hyB, hzB, stB, rkB, axB, IB1, IB2, IB3, wsB, s,
                        atol + rtol * abs(t0 + s), rot_tol, rot_max, pA, pB)
            return (r if r <= S else INF), TOI_OK
    return s, TOI_NOT_CONVERGED
