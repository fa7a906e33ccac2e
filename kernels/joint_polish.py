"""Exact polish of the simultaneous frictional impact problem in 3D contact space.

The simultaneous policy (``stepper3d._joint``) solves, for K contacts with Delassus matrix
``W`` (3K x 3K, 1/kg, each contact's block ordered normal, tangent 1, tangent 2), initial
contact velocities ``v0`` (m/s), restitution targets ``tb`` (``-e min(v0_N, 0)``, m/s) and
friction coefficients ``mu``, the impulses ``P`` (N s) with ``u = v0 + W P`` such that for
each contact

    0 <= P_N  _|_  u_N - tb_N >= 0,
    |P_T| <= mu P_N,  and  P_T = -mu P_N u_T / |u_T|  where  u_T != 0

(Newton restitution with Coulomb friction; Moreau's impact law). Projected block
Gauss-Seidel converges to it only linearly, and very slowly with redundant contacts (three
corners of a box face: 9 unknowns for 6 degrees of freedom) and large mu.

This module finishes from PGS's last iterate with a semismooth Newton method on the
Alart-Curnier equations (Alart & Curnier, CMAME 92, 1991; e.g. Acary & Brogliato,
*Numerical Methods for Nonsmooth Dynamical Systems*, 2008, ch. 13):

    F_N = P_N - max(0, P_N - r (u_N - tb_N)) = 0,
    F_T = P_T - proj_{disk(mu max(P_N, 0))}(P_T - r u_T) = 0,

with ``r = 1 / max_k W_kk`` per contact (N s per m/s). Each step solves the
Levenberg-Marquardt equations ``(J^T J + lam I) d = -J^T F`` (Cholesky; ``lam`` from
``LM_REG`` times the largest diagonal keeps redundant contacts regular -- their impulses
are not unique, the velocities are -- and grows when no step decreases ``|F|``), with a
backtracking line search on ``|F|``. Converged when
``|F|_inf <= tol_p`` (N s, the caller's velocity tolerance times ``r``).
"""
import math

import numpy as np
from numba import njit

LM_REG = 1e-13       # Levenberg-Marquardt regularisation, relative to max diag(J^T J) (-),
LM_MAX = 1e6         # ... raised by LM_UP while no step decreases |F| (up to LM_MAX), and
LM_UP = 100.0        # lowered by LM_DOWN after each successful step
LM_DOWN = 0.1
MAX_NEWTON = 60      # Newton iterations at most
MAX_HALVING = 40     # line-search halvings at most per iteration


@njit(cache=True)
def _residual(W, v0, tb, mu, P, r, n, F, J, want_j):
    """Alart-Curnier residual F (and, if want_j, its generalized Jacobian J) at P.
    Returns |F|_inf."""
    K = n // 3
    fmax = 0.0
    for a in range(K):
        i0 = 3 * a
        uN = v0[i0]
        u1 = v0[i0 + 1]
        u2 = v0[i0 + 2]
        for k in range(n):
            uN += W[i0, k] * P[k]
            u1 += W[i0 + 1, k] * P[k]
            u2 += W[i0 + 2, k] * P[k]
        ra = r[a]
        # normal row
        xN = P[i0] - ra * (uN - tb[i0])
        if xN > 0.0:
            F[i0] = ra * (uN - tb[i0])
            if want_j:
                for k in range(n):
                    J[i0, k] = ra * W[i0, k]
        else:
            F[i0] = P[i0]
            if want_j:
                for k in range(n):
                    J[i0, k] = 0.0
                J[i0, i0] = 1.0
        # tangential rows
        pn = max(P[i0], 0.0)
        rho = mu[a] * pn
        z1 = P[i0 + 1] - ra * u1
        z2 = P[i0 + 2] - ra * u2
        zn = math.sqrt(z1 * z1 + z2 * z2)
        if zn <= rho:
            F[i0 + 1] = ra * u1
            F[i0 + 2] = ra * u2
            if want_j:
                for k in range(n):
                    J[i0 + 1, k] = ra * W[i0 + 1, k]
                    J[i0 + 2, k] = ra * W[i0 + 2, k]
        else:
            h1 = z1 / zn
            h2 = z2 / zn
            F[i0 + 1] = P[i0 + 1] - rho * h1
            F[i0 + 2] = P[i0 + 2] - rho * h2
            if want_j:
                # d(rho z/|z|) = rho/|z| (I - h h^T) dz + h mu dP_N [P_N > 0],
                # dz = dP_T - r W_T dP
                s = rho / zn
                m11 = s * (1.0 - h1 * h1)
                m12 = -s * h1 * h2
                m22 = s * (1.0 - h2 * h2)
                for k in range(n):
                    dz1 = -ra * W[i0 + 1, k]
                    dz2 = -ra * W[i0 + 2, k]
                    if k == i0 + 1:
                        dz1 += 1.0
                    if k == i0 + 2:
                        dz2 += 1.0
                    J[i0 + 1, k] = -(m11 * dz1 + m12 * dz2)
                    J[i0 + 2, k] = -(m12 * dz1 + m22 * dz2)
                J[i0 + 1, i0 + 1] += 1.0
                J[i0 + 2, i0 + 2] += 1.0
                if P[i0] > 0.0:
                    J[i0 + 1, i0] -= h1 * mu[a]
                    J[i0 + 2, i0] -= h2 * mu[a]
        fmax = max(fmax, abs(F[i0]), abs(F[i0 + 1]), abs(F[i0 + 2]))
    return fmax


@njit(cache=True)
def _chol_solve(A, b, n, x):
    """Solve the SPD system A x = b (n x n, A overwritten by its Cholesky factor).
    Returns False if A is not numerically positive definite."""
    for j in range(n):
        s = A[j, j]
        for k in range(j):
            s -= A[j, k] * A[j, k]
        if not s > 0.0:
            return False
        d = math.sqrt(s)
        A[j, j] = d
        for i in range(j + 1, n):
            s = A[i, j]
            for k in range(j):
                s -= A[i, k] * A[j, k]
            A[i, j] = s / d
    for i in range(n):
        s = b[i]
        for k in range(i):
            s -= A[i, k] * x[k]
        x[i] = s / A[i, i]
    for i in range(n - 1, -1, -1):
        s = x[i]
        for k in range(i + 1, n):
            s -= A[k, i] * x[k]
        x[i] = s / A[i, i]
    return True


@njit(cache=True)
def polish(W, v0, tb, mu, P, K, vtol):
    """Polish the impulses ``P`` (float64[>= 3K], N s, PGS's iterate in, the solution out)
    of the simultaneous impact problem above. ``W`` float64[>= 3K, >= 3K] (1/kg), ``v0``,
    ``tb`` float64[>= 3K] (m/s), ``mu`` float64[>= K]; ``vtol`` (m/s) the velocity
    tolerance. Returns True when ``|F|_inf <= r vtol`` for every contact (P updated), False
    otherwise (P unchanged). Allocates its workspace: a fallback, not a hot path."""
    n = 3 * K
    r = np.empty(K)
    for a in range(K):
        i0 = 3 * a
        r[a] = 1.0 / max(W[i0, i0], W[i0 + 1, i0 + 1], W[i0 + 2, i0 + 2])
    rmin = r.min()
    tol_p = vtol * rmin
    F = np.empty(n)
    F2 = np.empty(n)
    J = np.empty((n, n))
    A = np.empty((n, n))
    N = np.empty((n, n))
    g = np.empty(n)
    d = np.empty(n)
    X = P[:n].copy()
    Y = np.empty(n)
    f = _residual(W, v0, tb, mu, X, r, n, F, J, True)
    lam = LM_REG
    for it in range(MAX_NEWTON):
        if f <= tol_p:
            break
        # Gauss-Newton normal equations J^T J d = -J^T F
        for i in range(n):
            s = 0.0
            for k in range(n):
                s += J[k, i] * F[k]
            g[i] = -s
            for j in range(i + 1):
                s = 0.0
                for k in range(n):
                    s += J[k, i] * J[k, j]
                N[i, j] = s
                N[j, i] = s
        dmax = 0.0
        for i in range(n):
            dmax = max(dmax, N[i, i])
        f2 = 0.0
        for k in range(n):
            f2 += F[k] * F[k]
        moved = False
        while lam <= LM_MAX and not moved:
            # Levenberg-Marquardt: a larger lam shortens and turns the step toward -grad
            for i in range(n):
                for j in range(n):
                    A[i, j] = N[i, j]
                A[i, i] += lam * dmax + 1e-300
            if _chol_solve(A, g, n, d):
                step = 1.0
                for h in range(MAX_HALVING):
                    for k in range(n):
                        Y[k] = X[k] + step * d[k]
                    fy = _residual(W, v0, tb, mu, Y, r, n, F2, J, False)
                    s2 = 0.0
                    for k in range(n):
                        s2 += F2[k] * F2[k]
                    if s2 < (1.0 - 1e-4 * step) * f2 or fy <= tol_p:
                        moved = True
                        break
                    step *= 0.5
            if not moved:
                lam *= LM_UP
        if not moved:
            return False
        lam = max(LM_REG, lam * LM_DOWN)
        for k in range(n):
            X[k] = Y[k]
        f = _residual(W, v0, tb, mu, X, r, n, F, J, True)
    if f <= tol_p:
        for k in range(n):
            P[k] = X[k]
        return True
    return False
