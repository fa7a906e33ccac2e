"""Time of impact of two bodies in 2D flight (every pair kind of ``pair2d``): the earliest
``s`` in ``[0, S]`` with ``g(s) = 0`` and ``g'(s) < 0``, never passing a root (grazing and
fast-spinning bodies included), polished to round-off.

Each body moves by its ``flight2d`` state row ``st = (x, y, angle, vx, vy, omega, ax, ay,
alpha)`` valid at ``t0`` (``s = t - t0``): quadratic centre, quadratic angle (``alpha = 0``
in free flight). ``g`` is the signed gap of ``pair2d`` (exact distance when disjoint).

Lower bound (conservative advancement). For any unit axis ``n(s)`` the separation
``sigma(n(s), s) = min_A n . a - max_B n . b`` is at most ``g(s)`` (separating-axis
inequality, ``pair2d_ellipse``), with equality at ``s0`` for the optimal axis ``n(s0)``.
``sigma`` is the minimum, over pairs of *support elements* (a core vertex with its
radius, or an ellipse's support), of smooth terms ``g_kl(s) = n . (a_k - b_l) - rA - rB``
(an ellipse element contributes ``-/+ sqrt(n^T M n)`` about its centre). So
``g(s0 + h) >= min_kl [g_kl(s0) + g_kl'(s0) h] - M h^2 / 2`` with ``M`` a bound of every
``|g_kl''|`` over the window, and stepping to the first zero of that bound never passes
a root of ``g``, whatever features realise the distance later (a corner that becomes the
closest, a switch from vertex to edge): no smoothness of ``g`` is assumed.

The axis follows the closest features at ``s0`` so that the active term is tangent to
``g`` (quadratic convergence near a transversal root, like ``toi2d``): fixed in B when
B's feature is an edge (then B's support is one body-fixed term), fixed in A when A's is,
fixed in the world otherwise (vertex, curve: ``g' = d sigma/ds`` there by the envelope
theorem). With the axis turning at ``w_n`` (0, ``omega_A`` or ``omega_B``) and ``D`` the
centre offset ``xA - xB``:

    |g_kl''| <= |D''| + 2 |w_n| |D'| + (w_n^2 + |alpha_n|) |D|
                + sum over bodies i of K2_i (omega_i - w_n)^2 + K1_i |alpha_i - alpha_n|

(differentiate ``n(s) . D(s)`` with ``n' = w_n J n``, ``n'' = alpha_n J n - w_n^2 n``, and
each element's offset ``n . R(angle_i) p`` as a function of the relative angle;
``pair2d_shape.body_reach`` gives ``K1``, ``K2``), every factor bounded over the window
``[s0, s0 + H]`` (``|omega| + |alpha| H``, ``|D'| + |D''| H``, ``|D| + |D'| H + |D''| H^2/2``).
In free flight ``D'' = 0`` and ``alpha = 0``: with a world axis ``M = sum K2_i omega_i^2``.
This is the quadratic form of Mirtich's conservative advancement (``closing_speed_bound``
gives his linear bound ``|g'| <= V``, always valid and kept for the stepper's use).

Windows as ``toi2d.window_step``: the bound is taken over ``H`` (start ``S``), doubled when
a step reaches it, else set to 4 steps. The search stops when a step is below
``atol + rtol * |t0 + s|`` (s) with ``g' < 0``; a smaller step with ``g' >= 0`` is a
tangency (grazing without crossing) and is stepped past. Polish: up to ``POLISH_IT``
Newton steps ``s -= g / g'`` on the gap (the gap of the fixed closest feature pair there),
each shorter than ``POLISH_REACH`` time tolerances, keeping the iterate of smallest ``|g|``.

Return ``(s, code)`` (``toi2d``): ``TOI_OK`` (``s = inf``: none in ``[0, S]``), ``TOI_MISSED``
(the gap at ``s = 0`` is below ``-gap_tol``: the bodies overlap; ``s = 0``),
``TOI_NOT_CONVERGED`` (``maxit`` steps, or an unknown pair of shape kinds, ``s`` NaN).
Tolerances: ``rtol`` (-), ``atol`` (s), ``gap_tol`` (m); ``t0`` (s) only scales ``rtol``.
"""
import math

from numba import njit

from .cache_guard import guard

guard(__name__, __file__)

from .flight2d import ALPHA, ANGLE, AX, AY, OMEGA, VX, VY, X, Y  # noqa: E402
from .pair2d import PK_DISK_DISK, PK_NONE, frame_rel, pair_kind, point_rate  # noqa: E402
from .pair2d_shape import (FT_EDGE, SH_ELLIPSE, body_reach, ellipse_matrix,  # noqa: E402
                           quad_h_derivs)
from .toi2d import (INF, TOI_MISSED, TOI_NOT_CONVERGED, TOI_OK, _safe_step,  # noqa: E402
                    disk_disk_toi)

AX_WORLD = 0        # axis fixed in the world
AX_A = 1            # axis turning with A (A's feature is an edge)
AX_B = 2            # axis turning with B (B's feature is an edge)
POLISH_IT = 3       # Newton steps of the final polish
POLISH_REACH = 64.0  # a polish step longer than this many time tolerances is refused


@njit(cache=True, _nrt=False, inline="always")
def _rel(stA, stB, s):
    """B's centre relative to A's at ``s`` and the relative velocity (B minus A), from the
    differences of the rows (no cancellation of large common coordinates)."""
    h = 0.5 * s * s
    dx = (stB[X] - stA[X]) + (stB[VX] - stA[VX]) * s + (stB[AX] - stA[AX]) * h
    dy = (stB[Y] - stA[Y]) + (stB[VY] - stA[VY]) * s + (stB[AY] - stA[AY]) * h
    return dx, dy


@njit(cache=True, _nrt=False, inline="always")
def _at(st, s):
    """Angle, centre velocity and angular velocity of a row at ``s``."""
    return (st[ANGLE] + st[OMEGA] * s + 0.5 * st[ALPHA] * s * s, st[VX] + st[AX] * s,
            st[VY] + st[AY] * s, st[OMEGA] + st[ALPHA] * s)


@njit(cache=True, _nrt=False)
def _eval(kA, rA, eaA, ebA, VA, iA, nA, stA, kB, rB, eaB, ebB, VB, iB, nB, stB, s):
    """Frame at ``s`` (A's centre at the origin) and the gap rate."""
    thA, vax, vay, wa = _at(stA, s)
    thB, vbx, vby, wb = _at(stB, s)
    dx, dy = _rel(stA, stB, s)
    g, nx, ny, pax, pay, pbx, pby, fa, ia, fb, ib = frame_rel(
        kA, rA, eaA, ebA, VA, iA, nA, thA, kB, rB, eaB, ebB, VB, iB, nB, dx, dy, thB)
    gd = point_rate(nx, ny, pax, pay, pbx - dx, pby - dy, vax, vay, wa, vbx, vby, wb)
    return g, gd, nx, ny, fa, fb


@njit(cache=True, _nrt=False)
def closing_speed_bound(stA, stB, rhoA, rhoB, H):
    """Mirtich's bound ``V >= |g'|`` over ``[0, H]`` (m/s): ``|v_rel| + |a_rel| H +
    sum_i (|omega_i| + |alpha_i| H) rho_i`` with ``rho_i`` the largest distance of a boundary
    point of body ``i`` from its centre of mass (m). ``g(s + h) >= g(s) - V h``."""
    dvx = stA[VX] - stB[VX]
    dvy = stA[VY] - stB[VY]
    dax = stA[AX] - stB[AX]
    day = stA[AY] - stB[AY]
    return (math.sqrt(dvx * dvx + dvy * dvy) + math.sqrt(dax * dax + day * day) * H
            + (abs(stA[OMEGA]) + abs(stA[ALPHA]) * H) * rhoA
            + (abs(stB[OMEGA]) + abs(stB[ALPHA]) * H) * rhoB)


@njit(cache=True, _nrt=False)
def axis_bound(mode, stA, stB, s, H, K1A, K2A, K1B, K2B):
    """Bound ``M`` (m/s^2) of ``|g_kl''|`` over ``[s, s + H]`` for the axis ``mode``
    (``AX_*``); see the module docstring."""
    dx, dy = _rel(stA, stB, s)
    _, vax, vay, wa = _at(stA, s)
    _, vbx, vby, wb = _at(stB, s)
    aa = stA[ALPHA]
    ab = stB[ALPHA]
    daD = math.sqrt((stA[AX] - stB[AX]) ** 2 + (stA[AY] - stB[AY]) ** 2)
    dvD = math.sqrt((vax - vbx) ** 2 + (vay - vby) ** 2)
    dD = math.sqrt(dx * dx + dy * dy)
    if mode == AX_A:
        wn = wa
        an = aa
    elif mode == AX_B:
        wn = wb
        an = ab
    else:
        wn = 0.0
        an = 0.0
    wnm = abs(wn) + abs(an) * H
    vDm = dvD + daD * H
    dDm = dD + dvD * H + 0.5 * daD * H * H
    OA = abs(wa - wn) + abs(aa - an) * H
    OB = abs(wb - wn) + abs(ab - an) * H
    M = daD
    if mode != AX_WORLD:
        M += 2.0 * wnm * vDm + (wnm * wnm + abs(an)) * dDm
    return M + K2A * OA * OA + K1A * abs(aa - an) + K2B * OB * OB + K1B * abs(ab - an)


@njit(cache=True, _nrt=False, inline="always")
def _elem_A(kA, rA, V, i0, k, c, s, axx, axy, ayy, nx, ny, vx, vy, w, wn):
    """A's element ``k`` along ``n``: value ``n . a_k - rA`` (or ``-h_A(n)``) and its rate
    for an axis turning at ``wn`` (A's centre at the origin)."""
    if kA == SH_ELLIPSE:
        h, h1, _ = quad_h_derivs(axx, axy, ayy, nx, ny)
        return -h, nx * vx + ny * vy - (wn - w) * h1
    j = i0 + k
    px = c * V[j, 0] - s * V[j, 1]
    py = s * V[j, 0] + c * V[j, 1]
    val = nx * px + ny * py - rA
    rate = wn * (-ny * px + nx * py) + nx * (vx - w * py) + ny * (vy + w * px)
    return val, rate


@njit(cache=True, _nrt=False, inline="always")
def _elem_B(kB, rB, V, i0, l, c, s, bxx, bxy, byy, nx, ny, dx, dy, vx, vy, w, wn):
    """B's element ``l`` along ``n``: value ``n . b_l + rB`` (or ``n . c_B + h_B(n)``) and its
    rate (B's centre at ``(dx, dy)``)."""
    if kB == SH_ELLIPSE:
        h, h1, _ = quad_h_derivs(bxx, bxy, byy, nx, ny)
        return (nx * dx + ny * dy + h,
                wn * (-ny * dx + nx * dy) + nx * vx + ny * vy + (wn - w) * h1)
    j = i0 + l
    px = c * V[j, 0] - s * V[j, 1]
    py = s * V[j, 0] + c * V[j, 1]
    bx = dx + px
    by = dy + py
    val = nx * bx + ny * by + rB
    rate = wn * (-ny * bx + nx * by) + nx * (vx - w * py) + ny * (vy + w * px)
    return val, rate


@njit(cache=True, _nrt=False)
def safe_step(mode, kA, rA, eaA, ebA, VA, iA, nA, stA, kB, rB, eaB, ebB, VB, iB, nB, stB,
              s, nx, ny, M):
    """First zero ``h >= 0`` of ``min_kl [g_kl + g_kl' h] - M h^2 / 2`` along the axis ``n``
    at ``s`` for the axis ``mode`` (``inf`` if none): no root of the gap lies in
    ``(s, s + h)``. In ``AX_A`` (``AX_B``) only A's (B's) supporting element enters, its
    support along the body-fixed axis being that one element for all ``s``."""
    thA, vax, vay, wa = _at(stA, s)
    thB, vbx, vby, wb = _at(stB, s)
    dx, dy = _rel(stA, stB, s)
    cA = math.cos(thA)
    sA = math.sin(thA)
    cB = math.cos(thB)
    sB = math.sin(thB)
    axx, axy, ayy = ellipse_matrix(eaA, ebA, cA, sA)
    bxx, bxy, byy = ellipse_matrix(eaB, ebB, cB, sB)
    wn = wa if mode == AX_A else (wb if mode == AX_B else 0.0)
    mA = 1 if kA == SH_ELLIPSE else nA
    mB = 1 if kB == SH_ELLIPSE else nB
    kstar = -1
    lstar = -1
    if mode == AX_A and mA > 1:     # A's support along -n: its lowest element
        lo = math.inf
        for k in range(mA):
            v, _ = _elem_A(kA, rA, VA, iA, k, cA, sA, axx, axy, ayy, nx, ny, vax, vay, wa, wn)
            if v < lo:
                lo = v
                kstar = k
    if mode == AX_B and mB > 1:     # B's support along n: its highest element
        hi = -math.inf
        for l in range(mB):
            v, _ = _elem_B(kB, rB, VB, iB, l, cB, sB, bxx, bxy, byy, nx, ny, dx, dy, vbx,
                           vby, wb, wn)
            if v > hi:
                hi = v
                lstar = l
    h = INF
    for k in range(mA):
        if kstar >= 0 and k != kstar:
            continue
        va, ra = _elem_A(kA, rA, VA, iA, k, cA, sA, axx, axy, ayy, nx, ny, vax, vay, wa, wn)
        for l in range(mB):
            if lstar >= 0 and l != lstar:
                continue
            vb, rb = _elem_B(kB, rB, VB, iB, l, cB, sB, bxx, bxy, byy, nx, ny, dx, dy, vbx,
                             vby, wb, wn)
            hk = _safe_step(max(va - vb, 0.0), ra - rb, M)
            if hk < h:
                h = hk
    return h


@njit(cache=True, _nrt=False)
def _polish(kA, rA, eaA, ebA, VA, iA, nA, stA, kB, rB, eaB, ebB, VB, iB, nB, stB, s, tol):
    """Newton on the gap from ``s`` (``POLISH_IT`` steps, each at most ``POLISH_REACH * tol``
    s long, so that it cannot reach another root), keeping the iterate of least ``|g|``
    among those with ``g' < 0``."""
    best = s
    gbest = INF
    for _ in range(POLISH_IT):
        g, gd, _, _, _, _ = _eval(kA, rA, eaA, ebA, VA, iA, nA, stA, kB, rB, eaB, ebB, VB,
                                  iB, nB, stB, s)
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
def _circle_window(stA, stB, R, S, gap_tol):
    """The window ``[s_in, s_out]`` (clipped to ``[0, S]``) in which the circumcircles of
    two bodies in free flight with equal accelerations (relative motion linear), radii
    summing to ``R`` (m), overlap: outside it the gap is positive. ``s_in > S``: none."""
    R = R * (1.0 + 1e-9) + gap_tol
    dx = stB[X] - stA[X]
    dy = stB[Y] - stA[Y]
    ux = stB[VX] - stA[VX]
    uy = stB[VY] - stA[VY]
    a = ux * ux + uy * uy
    b = 2.0 * (dx * ux + dy * uy)
    dist = math.sqrt(dx * dx + dy * dy)
    c = (dist - R) * (dist + R)
    if c > 0.0:                 # apart now: they overlap between the two roots, if any
        if b >= 0.0 or a == 0.0:
            return INF, S
        disc = b * b - 4.0 * a * c
        if disc <= 0.0:
            return INF, S
        q = -0.5 * (b - math.sqrt(disc))        # > 0
        return c / q, min(S, q / a)
    if a == 0.0:                # overlapping for ever
        return 0.0, S
    disc = b * b - 4.0 * a * c  # >= b^2
    sq = math.sqrt(disc)
    s_out = (sq - b) / (2.0 * a) if b <= 0.0 else (-2.0 * c) / (b + sq)
    return 0.0, min(S, s_out)


@njit(cache=True, _nrt=False)
def pair_toi(kA, rA, eaA, ebA, VA, iA, nA, stA, kB, rB, eaB, ebB, VB, iB, nB, stB, t0, S,
             rtol, atol, gap_tol, maxit):
    """Earliest impact ``s`` in ``[0, S]`` (s after ``t0``) of bodies A and B (``pair2d_shape``
    encoding; state rows ``stA``, ``stB`` at ``t0``). Returns ``(s, code)``; see the module
    docstring."""
    pk, _ = pair_kind(kA, kB)
    if pk == PK_NONE:
        return math.nan, TOI_NOT_CONVERGED
    if (pk == PK_DISK_DISK and VA[iA, 0] == 0.0 and VA[iA, 1] == 0.0 and VB[iB, 0] == 0.0
            and VB[iB, 1] == 0.0):
        return disk_disk_toi(stA[X] - stB[X], stA[Y] - stB[Y], stA[VX] - stB[VX],
                             stA[VY] - stB[VY], stA[AX] - stB[AX], stA[AY] - stB[AY],
                             rA + rB, t0, S, rtol, atol, gap_tol, maxit)
    K1A, K2A = body_reach(kA, rA, eaA, ebA, VA, iA, nA)
    K1B, K2B = body_reach(kB, rB, eaB, ebB, VB, iB, nB)
    s0 = 0.0
    if stA[AX] == stB[AX] and stA[AY] == stB[AY]:
        s0, S = _circle_window(stA, stB, K1A + rA + K1B + rB, S, gap_tol)
        if s0 > S:
            return INF, TOI_OK
    s = 0.0
    g, gd, nx, ny, fa, fb = _eval(kA, rA, eaA, ebA, VA, iA, nA, stA, kB, rB, eaB, ebB, VB,
                                  iB, nB, stB, s)
    if g <= 0.0:
        code = TOI_MISSED if g < -gap_tol else TOI_OK
        if gd < 0.0 or code == TOI_MISSED:
            return 0.0, code
    if s0 > 0.0:
        s = s0
        g, gd, nx, ny, fa, fb = _eval(kA, rA, eaA, ebA, VA, iA, nA, stA, kB, rB, eaB, ebB,
                                      VB, iB, nB, stB, s)
        if g <= 0.0 and gd < 0.0:
            r = _polish(kA, rA, eaA, ebA, VA, iA, nA, stA, kB, rB, eaB, ebB, VB, iB, nB,
                        stB, s, atol + rtol * abs(t0 + s))
            return (r if r <= S else INF), TOI_OK
    H = S
    for _ in range(maxit):
        mode = AX_B if fb == FT_EDGE else (AX_A if fa == FT_EDGE else AX_WORLD)
        Hw = min(H, S - s)
        M = axis_bound(mode, stA, stB, s, Hw, K1A, K2A, K1B, K2B)
        h = safe_step(mode, kA, rA, eaA, ebA, VA, iA, nA, stA, kB, rB, eaB, ebB, VB, iB, nB,
                      stB, s, nx, ny, M)
        tol = atol + rtol * abs(t0 + s)
        if h >= Hw:
            h = Hw
            H = 2.0 * H
        else:
            if h <= tol:
                if gd < 0.0:
                    r = _polish(kA, rA, eaA, ebA, VA, iA, nA, stA, kB, rB, eaB, ebB, VB, iB,
                                nB, stB, s + h, tol)
                    return (r if r <= S else INF), TOI_OK
                h = tol     # tangency (grazing without crossing): step past it
            H = 4.0 * h
        s += h
        if s >= S:
            return INF, TOI_OK
        g, gd, nx, ny, fa, fb = _eval(kA, rA, eaA, ebA, VA, iA, nA, stA, kB, rB, eaB, ebB,
                                      VB, iB, nB, stB, s)
        if g <= 0.0 and gd < 0.0:
            r = _polish(kA, rA, eaA, ebA, VA, iA, nA, stA, kB, rB, eaB, ebB, VB, iB, nB,
                        stB, s, atol + rtol * abs(t0 + s))
            return (r if r <= S else INF), TOI_OK
    return s, TOI_NOT_CONVERGED
