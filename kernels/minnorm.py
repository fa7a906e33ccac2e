"""Minimum-norm least-squares solution of a small square system by a one-sided Jacobi SVD
(Hestenes 1958; e.g. Demmel & Veselic, SIAM J. Matrix Anal. Appl. 13, 1992): the solver of
redundant contact systems, whose solution is not unique but whose minimum-norm one splits
the forces or impulses of redundant contacts evenly (``cluster2d``'s force and projection
systems, ``joint_polish.stick_sets``' sticking impulses).

One flat float64 array ``w`` holds the matrix, the right-hand side, the solution and the
scratch, each at its own offset, matrices row-major with row stride ``stride`` (so that a
caller's workspace layout is used as it is). No allocation.
"""
import math

from numba import njit

#: a column pair is orthogonal (no rotation) when |u_p . u_q| <= ORTHO_RTOL |u_p| |u_q|
#: (dimensionless: the round-off of the dot products)
ORTHO_RTOL = 1e-16


@njit(cache=True, _nrt=False)
def minnorm_solve(w, a0, r0, x0, u0, v0, n, stride, rtol, sweeps):
    """x = A^+ r for the n x n matrix A at ``w[a0:]`` and r at ``w[r0:]`` (x into
    ``w[x0:]``), n x n scratch U and V at ``w[u0:]`` and ``w[v0:]``. Jacobi rotations
    orthogonalise the columns of U = A V (at most ``sweeps`` sweeps; converges
    quadratically); singular values below ``rtol`` times the largest are zero (the
    directions of redundant equations, dropped: the minimum-norm solution). The caller
    checks the residual (contradictory equations leave it large)."""
    for i in range(n):
        for j in range(n):
            w[u0 + i * stride + j] = w[a0 + i * stride + j]
            w[v0 + i * stride + j] = 1.0 if i == j else 0.0
    for sweep in range(sweeps):
        rot = False
        for p in range(n - 1):
            for q in range(p + 1, n):
                al = 0.0
                be = 0.0
                ga = 0.0
                for i in range(n):
                    up = w[u0 + i * stride + p]
                    uq = w[u0 + i * stride + q]
                    al += up * up
                    be += uq * uq
                    ga += up * uq
                if ga == 0.0 or abs(ga) <= ORTHO_RTOL * math.sqrt(al * be):
                    continue
                rot = True
                ze = (be - al) / (2.0 * ga)
                tt = (1.0 if ze >= 0.0 else -1.0) / (abs(ze) + math.hypot(1.0, ze))
                cs = 1.0 / math.hypot(1.0, tt)
                sn = cs * tt
                for i in range(n):
                    up = w[u0 + i * stride + p]
                    uq = w[u0 + i * stride + q]
                    w[u0 + i * stride + p] = cs * up - sn * uq
                    w[u0 + i * stride + q] = sn * up + cs * uq
                    vp = w[v0 + i * stride + p]
                    vq = w[v0 + i * stride + q]
                    w[v0 + i * stride + p] = cs * vp - sn * vq
                    w[v0 + i * stride + q] = sn * vp + cs * vq
        if not rot:
            break
    smax = 0.0
    for j in range(n):
        s2 = 0.0
        for i in range(n):
            s2 += w[u0 + i * stride + j] ** 2
        smax = max(smax, s2)
    for i in range(n):
        w[x0 + i] = 0.0
    for j in range(n):
        s2 = 0.0
        ur = 0.0
        for i in range(n):
            u = w[u0 + i * stride + j]
            s2 += u * u
            ur += u * w[r0 + i]
        if not s2 > rtol * rtol * smax:
            continue
        f = ur / s2
        for i in range(n):
            w[x0 + i] += w[v0 + i * stride + j] * f
