"""Kane & Levinson's collision law: Newton restitution plus Coulomb friction along the
*final* slip direction (Kane & Levinson, *Dynamics: Theory and Applications*, 1985).

Contact-space conventions (DESIGN §3): normal first ``v = (v_N, v_T[, v_T2])`` (m/s),
``W`` the Delassus matrix (1/kg), ``P`` the impulse on body A (N s), ``v_f = v + W P``.
Parameters read from ``params``: ``P_E`` (e in [0, 1]) and ``P_MU`` (mu >= 0).

Equations (DESIGN §4), with ``a = -(1 + e) v_N > 0``:

1. Stick trial: ``P* = W^-1 ((-e v_N, 0[, 0]) - v)``, accepted when ``P*_N >= 0`` and
   ``|P*_T| <= mu P*_N`` (``MODE_STICK``; the final tangential velocity is zero).
2. Else slide: ``P_T = -mu P_N u`` with ``u`` the unit *final* slip direction and
   ``v_fN = -e v_N``, hence ``P_N = a / (W_NN - mu W_NT . u)`` (the denominator must be
   positive) and ``v_fT = v_T + P_N (W_TN - mu W_TT u)`` must equal ``lambda u``,
   ``lambda > 0`` (``MODE_SLIP``).

2D: ``u = s = +-1``. With both denominators positive at most one sign is consistent
(both would require ``W_NT**2 > W_NN W_TT``), and then exactly one of stick, slip(+),
slip(-) holds; with one denominator non-positive (Painleve-type coupling
``mu |W_NT| >= W_NN``) only the other sign is a candidate. In both cases the consistent
sign is the one that puts ``P_T`` along ``P*_T`` of the failed stick trial (so the 2D law
equals Brach's with ``e_t = 0``). The kernel tries that sign first and accepts it if
``s v_fT > 0`` down to minus 8 ulp of its terms (rounding at the stick/slip boundary);
only if that fails is the other sign tried (strictly). This order is the choice rule:
two consistent signs are impossible in exact arithmetic.

3D: ``u = (cos th, sin th)`` in the (T1, T2) basis. ``g(th) = D(th) (u x v_fT(th))`` with
``D = W_NN - mu W_NT . u`` is a trigonometric polynomial of degree 2 (at most 4 roots),
free of the pole of ``P_N``. It is sampled on ``N_SCAN`` points; every sign change, and
every pair of roots hidden inside one interval (detected through a sign change of
``g'``), is bracketed and polished by safeguarded Newton/bisection to machine precision.
Physical roots have ``D > 0`` (so ``P_N > 0``) and ``lambda > 0``. Choice rule when several
are physical: the largest ``u . v_T`` (final slip closest to the initial slip direction,
the 3D form of the 2D rule), ties (e.g. ``v_T = 0``) to the smaller ``P_N``. In planar
motion the out-of-plane roots always have ``lambda < 0``, so 3D reproduces 2D.

Numerics. 2D: the stick trial is Cramer's rule with every determinant by Kahan's FMA
algorithm (``common.det2k``, within 2 ulps even under cancellation), so ``P*`` is correct
to a few ulps componentwise for any SPD ``W`` (plain Cramer's rule left ``v_fT`` at
``eps cond(W)``), the SPD test ``det W > 0`` is exact, and the stick/slip decision is taken
on the numerators (no division before it). 3D: ``common.spd3_solve`` decides positive
definiteness (Sylvester, compensated minors: every SPD ``W`` up to cond ~1e15 accepted)
and solves the stick trial backward stably (plain cofactors when ``W`` is well
conditioned, else double-double cofactors plus one refinement step). In the slip branch
the final ``P_N`` is the least-squares solution of the normal and the tangential
equations at the polished angle, which keeps both residuals at round-off when ``D`` is
small (``a / D`` alone amplified the angle's rounding by ``P_N D' / D``).

Failures (``P_out`` zeroed): ``MODE_NO_SOLUTION`` when no stick and no consistent slip
exists, when ``W`` is not positive definite, or when the result is not finite. For SPD
``W`` the 2D law always has a solution (with ``c = -P_T / (mu P_N)`` in [-1, 1],
``v_fT(c)`` decreases where ``W_NN - mu c W_NT > 0``, and runs to -infinity or +infinity
at a pole in the Painleve case), and none was found
missing in 3D on 10^5 random strongly coupled cases. ``MODE_NOT_CONVERGED`` if a root
polish exceeds its iteration limit (not observed: it falls back to bisection).
``mu == 0`` takes the frictionless path ``P = (a / W_NN, 0)`` and reports ``MODE_SLIP``
(the impulse is on the degenerate cone ``|P_T| <= 0``).

This law can *create* kinetic energy (stick with coupling and e near 1, e.g. DESIGN §5
case 1b, dE = +0.0625): that is the law, not a bug; callers report dE.

Each law has a scalar twin (``kane_levinson_2d_scalar``, ``kane_levinson_3d_scalar``) that
takes and returns plain floats; the array kernels are thin wrappers around it.
Batch loops should call the scalar twins on ``v[i, 0]``, ``W[i, 0, 1]``... directly: the views
``v[i]``, ``W[i]``, ``P[i]`` passed to a kernel that LLVM does not inline entirely keep
their NRT reference counting (atomic increments and decrements), which costs far more
than the law itself (measured: ~12 M contacts/s through views against ~42 M/s through
the scalar twin, one thread).
"""
import math

import numpy as np
from numba import njit

from .cache_guard import guard

# flush stale compiled code before the kernel modules below are imported (cache_guard)
guard(__name__, __file__)

from .common import (
    MODE_NOT_CONVERGED,
    MODE_NO_SOLUTION,
    MODE_SEPARATING,
    MODE_SLIP,
    MODE_STICK,
    P_E,
    P_MU,
    det2k,
    finite3,
    spd3_solve,
    store3,
)

N_SCAN = 64          # samples of the slip-direction circle in 3D
_MAXIT = 100         # iteration limit of one root polish (bisection alone needs ~55)
_EPS = 2.220446049250313e-16
_TWO_PI = 2.0 * math.pi
_TOL_ULP = 8.0 * _EPS   # 2D slip consistency accepted down to -8 ulp of its terms


@njit(cache=True, error_model="numpy")
def kane_levinson_2d_scalar(vn, vt, wnn, wnt, wtt, e, mu):
    """Scalar twin of ``kane_levinson_2d``: returns ``(mode, P_N, P_T)``.

    Inputs: ``v = (vn, vt)`` (m/s), ``W = [[wnn, wnt], [wnt, wtt]]`` (1/kg), ``e``, ``mu``.
    Scalars only, so a caller's loop pays no reference counting. Failures return zeros."""
    if vn >= 0.0:
        return MODE_SEPARATING, 0.0, 0.0
    a = -(1.0 + e) * vn
    if mu == 0.0:
        pn = a / wnn
        if wnn > 0.0 and pn - pn == 0.0:
            return MODE_SLIP, pn, 0.0
        return MODE_NO_SOLUTION, 0.0, 0.0
    det = det2k(wnn, wtt, wnt, wnt)        # within 2 ulps: its sign is exact
    if not (det > 0.0 and wnn > 0.0):
        return MODE_NO_SOLUTION, 0.0, 0.0
    # stick trial W P* = (a, -v_T) by Cramer's rule with Kahan's FMA determinants:
    # det P*_N = a W_TT + W_NT v_T and det P*_T = -(W_NN v_T + W_NT a), each within
    # 2 ulps, so P* is correct to a few ulps componentwise (backward stable). The test
    # P*_N >= 0, |P*_T| <= mu P*_N is made on these numerators (det > 0): no division.
    nn = det2k(a, wtt, -wnt, vt)
    nt = -det2k(wnn, vt, -wnt, a)
    if nn >= 0.0 and abs(nt) <= mu * nn:
        mode = MODE_STICK
        pn = nn / det
        pt = nt / det
    else:
        # slip, P_T = r P_N, r = -mu s, first with r along P*_T: the consistent sign
        mode = MODE_SLIP
        r = mu if nt > 0.0 else -mu
        den = wnn + wnt * r
        pn = a / den
        q = wnt + wtt * r
        # consistency: the final slip v_fT = v_T + P_N q opposes P_T, up to 8 ulp
        if not (den > 0.0 and (vt + pn * q) * r < _TOL_ULP * mu * (abs(vt) + pn * abs(q))):
            r = -r
            den = wnn + wnt * r
            pn = a / den
            if not (den > 0.0 and (vt + pn * (wnt + wtt * r)) * r < 0.0):
                return MODE_NO_SOLUTION, 0.0, 0.0
        pt = r * pn
    if pn - pn == 0.0 and pt - pt == 0.0:
        return mode, pn, pt
    return MODE_NO_SOLUTION, 0.0, 0.0


@njit(cache=True, error_model="numpy")
def kane_levinson_2d(v, W, params, P_out):
    """Kane & Levinson law, 2D contact: ``mode = kane_levinson_2d(v, W, params, P_out)``.

    ``v`` (2,) m/s, ``W`` (2, 2) 1/kg, ``params`` (N_PARAMS,) with P_E, P_MU; writes the
    impulse on A (N s) into ``P_out`` (2,). See the module docstring."""
    mode, pn, pt = kane_levinson_2d_scalar(v[0], v[1], W[0, 0], W[0, 1], W[1, 1],
                                           params[P_E], params[P_MU])
    P_out[0] = pn
    P_out[1] = pt
    return mode


# cos and sin of the scan angles k 2 pi / N_SCAN, k = 0..N_SCAN (constants: the scan then
# costs no trigonometric call)
_SCAN_COS = np.array([math.cos(k * (_TWO_PI / N_SCAN)) for k in range(N_SCAN + 1)])
_SCAN_SIN = np.array([math.sin(k * (_TWO_PI / N_SCAN)) for k in range(N_SCAN + 1)])


@njit(cache=True, error_model="numpy")
def _g(c, s, A0, A1, B1, A2, B2):
    """g(th) = A0 + A1 cos th + B1 sin th + A2 cos 2th + B2 sin 2th and g'(th), given
    ``c = cos th``, ``s = sin th``."""
    c2 = c * c - s * s
    s2 = 2.0 * s * c
    g = A0 + A1 * c + B1 * s + A2 * c2 + B2 * s2
    dg = B1 * c - A1 * s + 2.0 * (B2 * c2 - A2 * s2)
    return g, dg


@njit(cache=True, error_model="numpy")
def _dg(th, A1, B1, A2, B2):
    c = math.cos(th)
    s = math.sin(th)
    return B1 * c - A1 * s + 2.0 * (B2 * (c * c - s * s) - A2 * 2.0 * s * c)


@njit(cache=True, error_model="numpy")
def _polish(lo, hi, glo, gtol, A0, A1, B1, A2, B2):
    """Root of g in [lo, hi] where g(lo) = glo and g(hi) have opposite signs.

    Safeguarded Newton (rtsafe: the Newton step is kept only inside the bracket and when
    it shrinks fast enough, else bisection). Returns (theta, converged)."""
    if glo < 0.0:
        xl = lo
        xh = hi
    else:
        xl = hi
        xh = lo
    x = 0.5 * (lo + hi)
    dxold = abs(hi - lo)
    dx = dxold
    g, dg = _g(math.cos(x), math.sin(x), A0, A1, B1, A2, B2)
    for _ in range(_MAXIT):
        if abs(g) <= gtol:
            return x, True
        if (((x - xh) * dg - g) * ((x - xl) * dg - g) > 0.0) or (abs(2.0 * g) > abs(dxold * dg)):
            dxold = dx
            dx = 0.5 * (xh - xl)
            x = xl + dx
        else:
            dxold = dx
            dx = g / dg
            x = x - dx
        if abs(dx) <= 4.0 * _EPS:
            return x, True
        g, dg = _g(math.cos(x), math.sin(x), A0, A1, B1, A2, B2)
        if g < 0.0:
            xl = x
        else:
            xh = x
    return x, False


@njit(cache=True, error_model="numpy")
def _extremum(lo, hi, dglo, A1, B1, A2, B2):
    """Zero of g' in [lo, hi] (g'(lo) = dglo and g'(hi) of opposite signs), by bisection."""
    for _ in range(_MAXIT):
        mid = 0.5 * (lo + hi)
        if hi - lo <= 4.0 * _EPS:
            return mid
        d = _dg(mid, A1, B1, A2, B2)
        if d == 0.0:
            return mid
        if (d < 0.0) == (dglo < 0.0):
            lo = mid
            dglo = d
        else:
            hi = mid
    return 0.5 * (lo + hi)


@njit(cache=True, error_model="numpy")
def _kl3_slip(v1, v2, wnn, w1, w2, t11, t12, t22, a, mu):
    """3D sliding branch: returns (mode, P_N, P_T1, P_T2)."""
    # g(th) = D (u x v_T) + a (u x W_TN) - a mu (u x W_TT u), u = (c, s), D = W_NN - mu W_NT.u
    A0 = -0.5 * mu * (w1 * v2 - w2 * v1)
    A1 = wnn * v2 + a * w2
    B1 = -(wnn * v1 + a * w1)
    A2 = -0.5 * mu * (w1 * v2 + w2 * v1) - a * mu * t12
    B2 = -0.5 * mu * (w2 * v2 - w1 * v1) - 0.5 * a * mu * (t22 - t11)
    gscale = abs(A0) + abs(A1) + abs(B1) + abs(A2) + abs(B2)
    if not (gscale > 0.0):
        return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
    gtol = 16.0 * _EPS * gscale
    dgbound = abs(A1) + abs(B1) + 2.0 * (abs(A2) + abs(B2))   # bound of |g'|
    vtscale = abs(v1) + abs(v2)
    tscale = abs(t11) + abs(t12) + abs(t22)
    h = _TWO_PI / N_SCAN
    best_th = 0.0
    best_score = -math.inf
    best_pn = math.inf
    found = False
    converged = True
    g0, dg0 = _g(1.0, 0.0, A0, A1, B1, A2, B2)
    ga = g0
    dga = dg0
    tha = 0.0
    for k in range(N_SCAN):
        if k == N_SCAN - 1:
            thb = _TWO_PI
            gb = g0
            dgb = dg0
        else:
            thb = (k + 1) * h
            gb, dgb = _g(_SCAN_COS[k + 1], _SCAN_SIN[k + 1], A0, A1, B1, A2, B2)
        # up to two roots in [tha, thb); a root exactly at thb is counted with the next interval
        n_r = 0
        r0 = 0.0
        r1 = 0.0
        if ga == 0.0:
            n_r = 1
            r0 = tha
        elif ga * gb < 0.0:
            r0, ok = _polish(tha, thb, ga, gtol, A0, A1, B1, A2, B2)
            converged = converged and ok
            n_r = 1
        elif (gb != 0.0 and dga * dgb < 0.0 and abs(ga) <= dgbound * h
              and abs(gb) <= dgbound * h):
            # same sign at both ends and an extremum inside: two roots may hide there
            thm = _extremum(tha, thb, dga, A1, B1, A2, B2)
            gm, _d = _g(math.cos(thm), math.sin(thm), A0, A1, B1, A2, B2)
            if abs(gm) <= gtol:
                n_r = 1
                r0 = thm
            elif (gm < 0.0) != (ga < 0.0):
                r0, ok0 = _polish(tha, thm, ga, gtol, A0, A1, B1, A2, B2)
                r1, ok1 = _polish(thm, thb, gm, gtol, A0, A1, B1, A2, B2)
                converged = converged and ok0 and ok1
                n_r = 2
        for j in range(n_r):
            th = r0 if j == 0 else r1
            c = math.cos(th)
            s = math.sin(th)
            den = wnn - mu * (w1 * c + w2 * s)
            if den > 0.0:
                pn = a / den
                vf1 = v1 + pn * (w1 - mu * (t11 * c + t12 * s))
                vf2 = v2 + pn * (w2 - mu * (t12 * c + t22 * s))
                lam = c * vf1 + s * vf2
                lamtol = 16.0 * _EPS * (vtscale + pn * (abs(w1) + abs(w2) + mu * tscale))
                if lam > -lamtol:
                    score = c * v1 + s * v2
                    if score > best_score or (score == best_score and pn < best_pn):
                        best_score = score
                        best_pn = pn
                        best_th = th
                        found = True
        tha = thb
        ga = gb
        dga = dgb
    if not converged:
        return MODE_NOT_CONVERGED, 0.0, 0.0, 0.0
    if not found:
        return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
    c = math.cos(best_th)
    s = math.sin(best_th)
    # P_N from both equations at th: D P_N = a (normal) and u x (v_T + P_N q) = 0
    # (tangential). They agree at the exact root (their inconsistency is g(th)); at a
    # rounded th the least-squares P_N keeps both residuals at round-off, where a / D alone
    # is off by a (dD/dth) dth / D^2 when D is small (near-Painleve coupling: P_N huge).
    den = wnn - mu * (w1 * c + w2 * s)
    uq = c * (w2 - mu * (t12 * c + t22 * s)) - s * (w1 - mu * (t11 * c + t12 * s))
    pn = (a * den - uq * (c * v2 - s * v1)) / (den * den + uq * uq)
    if not (pn > 0.0):
        pn = a / den
    return MODE_SLIP, pn, -mu * pn * c, -mu * pn * s


@njit(cache=True, error_model="numpy")
def kane_levinson_3d_scalar(vn, v1, v2, wnn, w1, w2, t11, t12, t22, e, mu):
    """Scalar twin of ``kane_levinson_3d``: returns ``(mode, P_N, P_T1, P_T2)``.

    Inputs: ``v = (vn, v1, v2)`` (m/s); the upper triangle of the symmetric ``W`` (1/kg):
    ``wnn = W[0,0], w1 = W[0,1], w2 = W[0,2], t11 = W[1,1], t12 = W[1,2], t22 = W[2,2]``;
    ``e``, ``mu``. Scalars only (no reference counting in a caller's loop). Failures
    return zeros."""
    if vn >= 0.0:
        return MODE_SEPARATING, 0.0, 0.0, 0.0
    a = -(1.0 + e) * vn
    if mu == 0.0:
        pn = a / wnn
        if wnn > 0.0 and pn - pn == 0.0:
            return MODE_SLIP, pn, 0.0, 0.0
        return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
    # positive-definiteness test and stick trial W P* = (a, -v_T1, -v_T2), both
    # compensated (common.spd3_solve): P* to a few ulps, SPD decided exactly
    spd, p0, p1, p2 = spd3_solve(wnn, w1, w2, t11, t12, t22, a, -v1, -v2)
    if not spd:
        return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
    if p0 >= 0.0 and math.sqrt(p1 * p1 + p2 * p2) <= mu * p0:
        mode = MODE_STICK
    else:
        mode, p0, p1, p2 = _kl3_slip(v1, v2, wnn, w1, w2, t11, t12, t22, a, mu)
    return finite3(mode, p0, p1, p2)


@njit(cache=True, error_model="numpy")
def kane_levinson_3d(v, W, params, P_out):
    """Kane & Levinson law, 3D contact: ``mode = kane_levinson_3d(v, W, params, P_out)``.

    ``v`` (3,) m/s, ``W`` (3, 3) symmetric 1/kg (upper triangle read), ``params`` with
    P_E, P_MU; writes the impulse on A (N s) into ``P_out`` (3,). See the module docstring."""
    mode, p0, p1, p2 = kane_levinson_3d_scalar(
        v[0], v[1], v[2], W[0, 0], W[0, 1], W[0, 2], W[1, 1], W[1, 2], W[2, 2],
        params[P_E], params[P_MU])
    return store3(P_out, mode, p0, p1, p2)


@njit(cache=True, error_model="numpy")
def kane_levinson(v, W, params, P_out):
    """Kane & Levinson law, dispatching on the dimension ``v.shape[0]`` (2 or 3)."""
    if v.shape[0] == 2:
        return kane_levinson_2d(v, W, params, P_out)
    return kane_levinson_3d(v, W, params, P_out)
