"""Gap, normal, witness points and features of an ellipse against an ellipse or a rounded
convex polygon (disk, capsule, polygon) in 2D.

Separating-axis formulation. For convex bodies A, B and a unit axis ``n(psi) = (cos psi,
sin psi)`` (from B into A) the separation ``sigma(psi) = min_A n . a - max_B n . b`` is at
most the signed distance ``g`` (the distance when disjoint, minus the penetration depth
otherwise), with equality at the optimal axis: ``g = max_psi sigma``. Two ellipses (or an
ellipse and a point, ``M_B = 0``) centred at ``cA``, ``cB``:
``sigma(psi) = n . (cA - cB) - sqrt(n^T M_A n) - sqrt(n^T M_B n)``, smooth in ``psi``.

Why the maximum is found: ``f(n) = min_A n . a - max_B n . b`` is concave on R^2 and
positively homogeneous, so when the bodies are disjoint every local maximum of ``sigma``
on the circle with ``sigma > 0`` is the global one (along the chord to a better axis,
``f`` rises and dividing by ``|n| < 1`` rises it further). ``sigma`` is sampled at
``N_PSI`` axes; every discrete local maximum of the samples is refined by safeguarded
Newton on ``sigma'(psi) = 0`` (``pair2d_shape.quad_h_derivs``; bisection when a Newton
step leaves the bracket of the neighbouring samples), converging quadratically; the best
refined axis is kept. Limit: a maximum whose basin is narrower than two sample spacings
(``2 * 2 pi / N_PSI``) can be missed; none was found with aspect ratios up to 100
(150 poses each against the brute force of ``tests/test_pair2d.py``, which runs 10).

Ellipse A against a rounded polygon B (core vertices ``v_k``, radius ``rB``): the optimal
axis is either an edge normal of B's core (edge against the ellipse) or the optimal axis
of one vertex against the ellipse (in that vertex's normal cone). Both candidate sets are
evaluated with the full separation (all of B's vertices), so every candidate is a lower
bound and the largest is exact when the bodies are disjoint.

Overlap: the same maximum is minus the penetration depth of the smooth shapes near
contact; far inside it is a lower bound of the signed distance (a first-order estimate,
more overlap than the true minimum translation, never less).

Witness points: A's support point along ``-n`` (``cA - M_A n / h_A``) and B's along ``n``;
for an edge of B, ``pB = pA - g n``. Coordinates relative to A's centre.
"""
import math

import numpy as np
from numba import njit

from .cache_guard import guard

guard(__name__, __file__)

from .pair2d_shape import (FT_CURVE, FT_EDGE, FT_VERTEX, n_edges, quad_h,  # noqa: E402
                           quad_h_derivs, vertex_at)

N_PSI = 64              # axis samples of the circle before the Newton refinement
REFINE_MAX = 4          # discrete local maxima refined (the best ones first)
NEWTON_MAXIT = 80       # iterations of one refinement (bisection alone needs ~50)
PSI_TOL = 1e-15         # rad: a Newton step below this ends a refinement

_DPSI = 2.0 * math.pi / N_PSI
_COS = np.array([math.cos(k * _DPSI) for k in range(N_PSI)])
_SIN = np.array([math.sin(k * _DPSI) for k in range(N_PSI)])


@njit(cache=True, _nrt=False, inline="always")
def _sig(ux, uy, dx, dy, axx, axy, ayy, bxx, bxy, byy):
    return ux * dx + uy * dy - quad_h(axx, axy, ayy, ux, uy) - quad_h(bxx, bxy, byy, ux, uy)


@njit(cache=True, _nrt=False)
def _refine(c0, s0, dx, dy, axx, axy, ayy, bxx, bxy, byy):
    """Newton on ``sigma' = 0`` for the offset ``t`` from the sample axis ``(c0, s0)``,
    bracketed in ``[-dpsi, dpsi]``. Returns ``(sigma, ux, uy)`` at the final iterate."""
    lo = -_DPSI
    hi = _DPSI
    t = 0.0
    ux = c0
    uy = s0
    for _ in range(NEWTON_MAXIT):
        ct = math.cos(t)
        st = math.sin(t)
        ux = c0 * ct - s0 * st
        uy = s0 * ct + c0 * st
        _, a1, a2 = quad_h_derivs(axx, axy, ayy, ux, uy)
        _, b1, b2 = quad_h_derivs(bxx, bxy, byy, ux, uy)
        d1 = -uy * dx + ux * dy - a1 - b1
        d2 = -(ux * dx + uy * dy) - a2 - b2
        if d1 > 0.0:
            lo = t
        else:
            hi = t
        tn = t - d1 / d2 if d2 < 0.0 else 0.5 * (lo + hi)
        if not (lo < tn < hi):
            tn = 0.5 * (lo + hi)
        step = tn - t
        t = tn
        if abs(step) <= PSI_TOL or hi - lo <= PSI_TOL:
            break
    ct = math.cos(t)
    st = math.sin(t)
    ux = c0 * ct - s0 * st
    uy = s0 * ct + c0 * st
    return _sig(ux, uy, dx, dy, axx, axy, ayy, bxx, bxy, byy), ux, uy


@njit(cache=True, _nrt=False)
def sep_max(dx, dy, axx, axy, ayy, bxx, bxy, byy):
    """``max_psi sigma(psi)`` for ``sigma = n . d - sqrt(n^T M_A n) - sqrt(n^T M_B n)``
    (``d = cA - cB``; ``M`` components ``xx, xy, yy``; a point has ``M = 0``).
    Returns ``(sigma, nx, ny)``; see the module docstring."""
    # samples (rolling three values: no array)
    s_first = _sig(_COS[0], _SIN[0], dx, dy, axx, axy, ayy, bxx, bxy, byy)
    s_last = _sig(_COS[N_PSI - 1], _SIN[N_PSI - 1], dx, dy, axx, axy, ayy, bxx, bxy, byy)
    # pass 1: the REFINE_MAX best discrete local maxima (kept sorted, best first)
    k1 = k2 = k3 = k4 = -1
    v1 = v2 = v3 = v4 = -math.inf
    prev = s_last
    cur = s_first
    for k in range(N_PSI):
        if k + 1 < N_PSI:
            nxt = _sig(_COS[k + 1], _SIN[k + 1], dx, dy, axx, axy, ayy, bxx, bxy, byy)
        else:
            nxt = s_first
        if cur >= prev and cur >= nxt:
            if cur > v1:
                k4, v4, k3, v3, k2, v2, k1, v1 = k3, v3, k2, v2, k1, v1, k, cur
            elif cur > v2:
                k4, v4, k3, v3, k2, v2 = k3, v3, k2, v2, k, cur
            elif cur > v3:
                k4, v4, k3, v3 = k3, v3, k, cur
            elif cur > v4:
                k4, v4 = k, cur
        prev = cur
        cur = nxt
    best = -math.inf
    bx = 1.0
    by = 0.0
    for j in range(REFINE_MAX):
        k = k1 if j == 0 else (k2 if j == 1 else (k3 if j == 2 else k4))
        if k < 0:
            break
        sg, ux, uy = _refine(_COS[k], _SIN[k], dx, dy, axx, axy, ayy, bxx, bxy, byy)
        if sg > best:
            best, bx, by = sg, ux, uy
    return best, bx, by


@njit(cache=True, _nrt=False)
def ellipse_ellipse_frame(axx, axy, ayy, xB, yB, bxx, bxy, byy):
    """Gap and frame of ellipse A (at the origin, world matrix ``M_A``) and ellipse B
    (centre ``(xB, yB)`` relative to A, matrix ``M_B``). Returns ``(g, nx, ny, pAx, pAy,
    pBx, pBy, fa, ia, fb, ib)`` as ``pair2d_rounded.rounded_frame``."""
    g, nx, ny = sep_max(-xB, -yB, axx, axy, ayy, bxx, bxy, byy)
    ha = quad_h(axx, axy, ayy, nx, ny)
    hb = quad_h(bxx, bxy, byy, nx, ny)
    pax = -(axx * nx + axy * ny) / ha
    pay = -(axy * nx + ayy * ny) / ha
    pbx = xB + (bxx * nx + bxy * ny) / hb
    pby = yB + (bxy * nx + byy * ny) / hb
    return g, nx, ny, pax, pay, pbx, pby, FT_CURVE, 0, FT_CURVE, 0


@njit(cache=True, _nrt=False)
def _full_sep(axx, axy, ayy, VB, iB, nB, xB, yB, cB, sB, ux, uy):
    """Separation of the ellipse A (at the origin) and B's core along ``u``: ``(sigma, l)``
    with ``l`` B's supporting vertex."""
    hi = -math.inf
    lb = 0
    for l in range(nB):
        px, py = vertex_at(VB, iB, nB, l, xB, yB, cB, sB)
        d = ux * px + uy * py
        if d > hi:
            hi = d
            lb = l
    return -quad_h(axx, axy, ayy, ux, uy) - hi, lb


@njit(cache=True, _nrt=False)
def ellipse_rounded_frame(axx, axy, ayy, VB, iB, nB, rB, xB, yB, cB, sB):
    """Gap and frame of ellipse A (at the origin, world matrix ``M_A``) and the rounded
    convex polygon B (core ``VB[iB:iB+nB]``, radius ``rB``, centre ``(xB, yB)`` relative to
    A, angle cosine/sine ``cB, sB``). Returns ``(g, nx, ny, pAx, pAy, pBx, pBy, fa, ia, fb,
    ib)`` as ``pair2d_rounded.rounded_frame``."""
    best = -math.inf
    bnx = 1.0
    bny = 0.0
    bf = FT_VERTEX
    bi = 0
    for k in range(nB):     # each vertex against the ellipse
        px, py = vertex_at(VB, iB, nB, k, xB, yB, cB, sB)
        _, ux, uy = sep_max(-px, -py, axx, axy, ayy, 0.0, 0.0, 0.0)
        sg, l = _full_sep(axx, axy, ayy, VB, iB, nB, xB, yB, cB, sB, ux, uy)
        if sg > best:
            best, bnx, bny, bf, bi = sg, ux, uy, FT_VERTEX, l
    for e in range(n_edges(nB)):    # each edge normal (both signs)
        ax, ay = vertex_at(VB, iB, nB, e, xB, yB, cB, sB)
        bx, by = vertex_at(VB, iB, nB, e + 1, xB, yB, cB, sB)
        ex = bx - ax
        ey = by - ay
        L = math.sqrt(ex * ex + ey * ey)
        if not L > 0.0:
            continue
        for sgn in (1.0, -1.0):
            ux = sgn * ey / L
            uy = -sgn * ex / L
            sg, l = _full_sep(axx, axy, ayy, VB, iB, nB, xB, yB, cB, sB, ux, uy)
            if sg > best:
                best, bnx, bny, bf, bi = sg, ux, uy, FT_EDGE, e
    g = best - rB
    ha = quad_h(axx, axy, ayy, bnx, bny)
    pax = -(axx * bnx + axy * bny) / ha
    pay = -(axy * bnx + ayy * bny) / ha
    if bf == FT_VERTEX:
        qx, qy = vertex_at(VB, iB, nB, bi, xB, yB, cB, sB)
        return g, bnx, bny, pax, pay, qx + rB * bnx, qy + rB * bny, FT_CURVE, 0, FT_VERTEX, bi
    return g, bnx, bny, pax, pay, pax - g * bnx, pay - g * bny, FT_CURVE, 0, FT_EDGE, bi
