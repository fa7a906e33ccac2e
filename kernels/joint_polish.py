"""Exact polish of the simultaneous frictional impact problem, in 2D or 3D contact space.

The simultaneous policy (``stepper3d._joint``, ``stepper2d._joint``) solves, for K contacts
with Delassus matrix ``W`` (bs K x bs K, 1/kg, block size bs = 3 in 3D: each contact's
block ordered normal, tangent 1, tangent 2; bs = 2 in 2D: normal, tangent), initial
contact velocities ``v0``
(m/s), restitution targets ``tb`` (``-e min(v0_N, 0)``, m/s) and friction coefficients
``mu``, the impulses ``P`` (N s) with ``u = v0 + W P`` such that for each contact

    0 <= P_N  _|_  u_N - tb_N >= 0,
    |P_T| <= mu P_N,  and  P_T = -mu P_N u_T / |u_T|  where  u_T != 0

(Newton restitution with Coulomb friction; Moreau's impact law). Projected (block)
Gauss-Seidel converges to it only linearly, and very slowly -- or cycles -- with redundant
contacts (three corners of a box face: 9 unknowns for 6 degrees of freedom; a 2D body on two
planes of a groove or corner: 4 unknowns for 3) and large mu.

This module finishes from PGS's last iterate with a semismooth Newton method on the
Alart-Curnier equations (Alart & Curnier, CMAME 92, 1991; e.g. Acary & Brogliato,
*Numerical Methods for Nonsmooth Dynamical Systems*, 2008, ch. 13):

    F_N = P_N - max(0, P_N - r (u_N - tb_N)) = 0,
    F_T = P_T - proj_{disk(mu max(P_N, 0))}(P_T - r u_T) = 0,

(in 2D the disk is the interval ``[-mu P_N, mu P_N]``) with ``r = 1 / max_k W_kk`` per
contact (N s per m/s). Each step solves the Levenberg-Marquardt equations
``(J^T J + lam I) d = -J^T F`` (Cholesky; ``lam`` from ``LM_REG`` times the largest
diagonal keeps redundant contacts regular -- their impulses are not unique, the velocities
are -- and grows when no step decreases ``|F|``), with a backtracking line search on
``|F|``. Converged when ``|F|_inf <= tol_p`` (N s, the caller's velocity tolerance times
``r``). ``polish`` is the 3D entry, ``polish2d`` the 2D one; both run ``polish_blocks``.
"""
import math

import numpy as np
from numba import njit

from .minnorm import minnorm_solve

LM_REG = 1e-13       # Levenberg-Marquardt regularisation, relative to max diag(J^T J) (-),
LM_MAX = 1e6         # ... raised by LM_UP while no step decreases |F| (up to LM_MAX), and
LM_UP = 100.0        # lowered by LM_DOWN after each successful step
LM_DOWN = 0.1
MAX_NEWTON = 60      # Newton iterations at most
MAX_HALVING = 40     # line-search halvings at most per iteration


@njit(cache=True, _nrt=False)
def _residual(W, v0, tb, mu, P, r, n, F, J, want_j, bs):
    """Alart-Curnier residual F (and, if want_j, its generalized Jacobian J) at P, for
    contact blocks of size bs (2: normal, tangent; 3: normal, two tangents). Returns
    |F|_inf."""
    K = n // bs
    fmax = 0.0
    for a in range(K):
        i0 = bs * a
        uN = v0[i0]
        u1 = v0[i0 + 1]
        u2 = v0[i0 + 2] if bs == 3 else 0.0
        for k in range(n):
            uN += W[i0, k] * P[k]
            u1 += W[i0 + 1, k] * P[k]
            if bs == 3:
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
        # tangential rows (in 2D the second tangent is absent: z2 = 0, h2 = 0)
        pn = max(P[i0], 0.0)
        rho = mu[a] * pn
        z1 = P[i0 + 1] - ra * u1
        z2 = P[i0 + 2] - ra * u2 if bs == 3 else 0.0
        zn = math.sqrt(z1 * z1 + z2 * z2)
        if zn <= rho:
            F[i0 + 1] = ra * u1
            if bs == 3:
                F[i0 + 2] = ra * u2
            if want_j:
                for k in range(n):
                    J[i0 + 1, k] = ra * W[i0 + 1, k]
                    if bs == 3:
                        J[i0 + 2, k] = ra * W[i0 + 2, k]
        else:
            h1 = z1 / zn
            h2 = z2 / zn
            F[i0 + 1] = P[i0 + 1] - rho * h1
            if bs == 3:
                F[i0 + 2] = P[i0 + 2] - rho * h2
            if want_j:
                # bs(rho z/|z|) = rho/|z| (I - h h^T) dz + h mu dP_N [P_N > 0],
                # dz = dP_T - r W_T dP (in 2D, I - h h^T = 0: the clamp's slope)
                s = rho / zn
                m11 = s * (1.0 - h1 * h1)
                m12 = -s * h1 * h2
                m22 = s * (1.0 - h2 * h2)
                for k in range(n):
                    dz1 = -ra * W[i0 + 1, k]
                    dz2 = -ra * W[i0 + 2, k] if bs == 3 else 0.0
                    if k == i0 + 1:
                        dz1 += 1.0
                    if bs == 3 and k == i0 + 2:
                        dz2 += 1.0
                    J[i0 + 1, k] = -(m11 * dz1 + m12 * dz2)
                    if bs == 3:
                        J[i0 + 2, k] = -(m12 * dz1 + m22 * dz2)
                J[i0 + 1, i0 + 1] += 1.0
                if bs == 3:
                    J[i0 + 2, i0 + 2] += 1.0
                if P[i0] > 0.0:
                    J[i0 + 1, i0] -= h1 * mu[a]
                    if bs == 3:
                        J[i0 + 2, i0] -= h2 * mu[a]
        fmax = max(fmax, abs(F[i0]), abs(F[i0 + 1]))
        if bs == 3:
            fmax = max(fmax, abs(F[i0 + 2]))
    return fmax


@njit(cache=True, _nrt=False)
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


@njit(cache=True, _nrt=False)
def polish_ws(W, v0, tb, mu, P, K, vtol, bs, r, F, F2, g, d, X, Y, J, A, N):
    """Polish the impulses ``P`` (float64[>= bs K], N s, PGS's iterate in, the solution out)
    of the simultaneous impact problem above, contact blocks of size ``bs`` (2 or 3).
    ``W`` float64[>= bs K, >= bs K] (1/kg), ``v0``, ``tb`` float64[>= bs K] (m/s), ``mu``
    float64[>= K]; ``vtol`` (m/s) the velocity tolerance. Returns True when
    ``|F|_inf <= r vtol`` for every contact (P updated), False otherwise (P unchanged).
    Allocation-free: the workspace is float64 ``r[>= K]``, ``F, F2, g, d, X, Y[>= bs K]``
    and ``J, A, N[>= bs K, >= bs K]`` (views of a caller's scratch in the 2D stepper)."""
    n = bs * K
    for a in range(K):
        i0 = bs * a
        wmax = max(W[i0, i0], W[i0 + 1, i0 + 1])
        if bs == 3:
            wmax = max(wmax, W[i0 + 2, i0 + 2])
        r[a] = 1.0 / wmax
    rmin = r[0]
    for a in range(1, K):
        rmin = min(rmin, r[a])
    tol_p = vtol * rmin
    for k in range(n):
        X[k] = P[k]
    f = _residual(W, v0, tb, mu, X, r, n, F, J, True, bs)
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
                    fy = _residual(W, v0, tb, mu, Y, r, n, F2, J, False, bs)
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
        f = _residual(W, v0, tb, mu, X, r, n, F, J, True, bs)
    if f <= tol_p:
        for k in range(n):
            P[k] = X[k]
        return True
    return False


@njit(cache=True)
def polish_blocks(W, v0, tb, mu, P, K, vtol, bs):
    """``polish_ws`` with its workspace allocated: a fallback, not a hot path."""
    n = bs * K
    return polish_ws(W, v0, tb, mu, P, K, vtol, bs, np.empty(K), np.empty(n), np.empty(n),
                     np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty((n, n)),
                     np.empty((n, n)), np.empty((n, n)))


@njit(cache=True)
def polish(W, v0, tb, mu, P, K, vtol):
    """``polish_blocks`` in 3D contact space (blocks normal, tangent 1, tangent 2)."""
    return polish_blocks(W, v0, tb, mu, P, K, vtol, 3)


@njit(cache=True)
def polish2d(W, v0, tb, mu, P, K, vtol):
    """``polish_blocks`` in 2D contact space (blocks normal, tangent)."""
    return polish_blocks(W, v0, tb, mu, P, K, vtol, 2)


# ---------------------------------------------------------------- 2D: exact active sets
#: enumerate2d: a pivot below ENUM_SING_RTOL times the largest entry of its column block is
#: zero (dimensionless: the combination's equations are then rank-deficient)
ENUM_SING_RTOL = 1e-12
#: enumerate2d handles at most ENUM_MAX_K contacts (4^K combinations)
ENUM_MAX_K = 4


@njit(cache=True, _nrt=False)
def _enum_solve(M, n, x):
    """Solve the augmented system M[:n, :n+1] by Gaussian elimination with partial
    pivoting (M overwritten); a column without a pivot (below ENUM_SING_RTOL of its
    largest entry) leaves its unknown at 0. Returns the rank."""
    amax = 0.0
    for i in range(n):
        for j in range(n):
            amax = max(amax, abs(M[i, j]))
    row = 0
    for col in range(n):
        x[col] = 0.0
    rank = 0
    for col in range(n):
        if row >= n:
            break
        best = row
        for i in range(row + 1, n):
            if abs(M[i, col]) > abs(M[best, col]):
                best = i
        if not abs(M[best, col]) > ENUM_SING_RTOL * amax:
            continue
        if best != row:
            for j in range(n + 1):
                tmp = M[row, j]
                M[row, j] = M[best, j]
                M[best, j] = tmp
        for i in range(row + 1, n):
            f = M[i, col] / M[row, col]
            if f != 0.0:
                for j in range(col, n + 1):
                    M[i, j] -= f * M[row, j]
        row += 1
        rank += 1
    # back substitution over the pivot rows (pivot column: first nonzero of the row)
    for i in range(rank - 1, -1, -1):
        c = 0
        while not abs(M[i, c]) > ENUM_SING_RTOL * amax:
            c += 1
        s = M[i, n]
        for j in range(c + 1, n):
            s -= M[i, j] * x[j]
        x[c] = s / M[i, c]
    return rank


@njit(cache=True, _nrt=False)
def enumerate2d(W, v0, tb, mu, K, vtol, vref, P, M, x):
    """Every solution of the 2D simultaneous impact problem above (blocks normal, tangent)
    by its active sets: each contact lifts off (``P = 0``, ``u_N >= tb_N``), sticks
    (``u = (tb_N, 0)``, ``|P_T| <= mu P_N``) or slides either way (``u_N = tb_N``,
    ``P_T = -s mu P_N``, ``s u_T >= 0``), 4^K linear systems (K <= ENUM_MAX_K). The
    inequalities are checked to ``vtol`` (m/s; impulses as the speeds ``W_NN P``). Writes
    into ``P`` (float64[>= 2K], N s) the solution whose velocities are nearest ``vref``
    (m/s, max norm; ties: the first in enumeration order). Workspace ``M`` float64[>= 2K,
    >= 2K + 1], ``x`` float64[>= 2K]. Returns ``(found, undecided)``: the number of
    solutions, and of rank-deficient consistent combinations whose least solution fails
    an inequality (a family of impulses this test does not search: a redundant pair of
    sticking contacts). ``found == undecided == 0`` certifies that no solution exists."""
    n = 2 * K
    found = 0
    undecided = 0
    best = np.inf
    for code in range(4 ** K):
        for a in range(K):
            m = (code >> (2 * a)) & 3
            iN = 2 * a
            iT = iN + 1
            for j in range(n + 1):
                M[iN, j] = 0.0
                M[iT, j] = 0.0
            if m == 0:              # lift-off
                M[iN, iN] = 1.0
                M[iT, iT] = 1.0
            else:
                for j in range(n):
                    M[iN, j] = W[iN, j]
                M[iN, n] = tb[iN] - v0[iN]
                if m == 1:          # stick
                    for j in range(n):
                        M[iT, j] = W[iT, j]
                    M[iT, n] = -v0[iT]
                else:               # slide along s: P_T + s mu P_N = 0
                    M[iT, iT] = 1.0
                    M[iT, iN] = mu[a] if m == 2 else -mu[a]
        rank = _enum_solve(M, n, x)
        # the equations, checked on the original rows (consistency of a singular system)
        ok = True
        dev = 0.0
        for a in range(K):
            m = (code >> (2 * a)) & 3
            iN = 2 * a
            iT = iN + 1
            uN = v0[iN]
            uT = v0[iT]
            for j in range(n):
                uN += W[iN, j] * x[j]
                uT += W[iT, j] * x[j]
            wN = W[iN, iN]
            if m == 0:
                if abs(x[iN]) * wN > vtol or abs(x[iT]) * wN > vtol:
                    ok = False          # inconsistent
                if uN < tb[iN] - vtol:
                    dev = np.inf
            else:
                if abs(uN - tb[iN]) > vtol:
                    ok = False
                if m == 1:
                    if abs(uT) > vtol:
                        ok = False
                    if (abs(x[iT]) - mu[a] * x[iN]) * wN > vtol:
                        dev = np.inf
                else:
                    s = 1.0 if m == 2 else -1.0
                    if abs(x[iT] + s * mu[a] * x[iN]) * wN > vtol:
                        ok = False
                    if s * uT < -vtol:
                        dev = np.inf
                if x[iN] * wN < -vtol:
                    dev = np.inf
            dev = max(dev, abs(uN - vref[iN]), abs(uT - vref[iT]))
        if not ok:
            continue
        if dev == np.inf:
            if rank < n:
                undecided += 1
            continue
        found += 1
        if dev < best:
            best = dev
            for j in range(n):
                P[j] = x[j]
    return found, undecided


# ------------------------------------------------- 3D: sticking sets, when polish fails
#: stick_sets tries the 2^K - 1 sets of sticking contacts for at most this many contacts
STICK_MAX_K = 6
#: stick_sets: a singular value below MINNORM_RTOL times the largest is zero (dimensionless:
#: redundant contacts' directions, whose impulses split by minimum norm)
MINNORM_RTOL = 1e-12
#: stick_sets: one-sided Jacobi sweeps at most (``minnorm``; converges quadratically)
MINNORM_SWEEPS = 60


@njit(cache=True)
def stick_sets(W, v0, tb, mu, P, K, vtol):
    """The 3D simultaneous impact problem (module docstring) when PGS and ``polish`` fail:
    for each set S of the K contacts (all of them first; K <= ``STICK_MAX_K``), the
    minimum-norm impulses on S that make S stick (``minnorm``; ``u = tb`` on S's rows:
    normal target, zero slip), the others free (``P = 0``). A candidate whose
    Alart-Curnier residual is within ``r vtol`` (``polish``'s test: impulses in their
    cones, no normal impulse pulling, the free contacts not approaching) is a solution;
    else ``polish`` starts from it (a sliding contact's impulse on its cone). Redundant
    contacts (a singular ``W_SS``) get the minimum-norm split, the case where PGS drifts
    along the null space. Returns True with ``P`` (float64[>= 3 K], N s) the solution,
    False when no candidate leads to one (``P`` unchanged). Arguments as ``polish``.
    Allocates (a fallback, not a hot path)."""
    if K > STICK_MAX_K:
        return False
    n = 3 * K
    r = np.empty(K)
    for a in range(K):
        i0 = 3 * a
        r[a] = 1.0 / max(W[i0, i0], W[i0 + 1, i0 + 1], W[i0 + 2, i0 + 2])
    tol_p = vtol * r.min()
    # the sticking set's system in one flat array (minnorm): A, U, V (stride n), rhs, x
    la = np.empty(3 * n * n + 2 * n)
    A0 = 0
    U0 = n * n
    V0 = 2 * n * n
    R0 = 3 * n * n
    X0 = R0 + n
    idx = np.empty(n, np.int64)
    Q = np.empty(n)
    F = np.empty(n)
    J = np.empty((n, n))
    for mask in range((1 << K) - 1, 0, -1):
        m = 0
        for a in range(K):
            if mask & (1 << a):
                for j in range(3):
                    idx[m] = 3 * a + j
                    m += 1
        for i in range(m):
            for j in range(m):
                la[A0 + i * n + j] = W[idx[i], idx[j]]
            la[R0 + i] = tb[idx[i]] - v0[idx[i]]
        minnorm_solve(la, A0, R0, X0, U0, V0, m, n, MINNORM_RTOL, MINNORM_SWEEPS)
        res = 0.0
        for i in range(m):
            s = -la[R0 + i]
            for j in range(m):
                s += la[A0 + i * n + j] * la[X0 + j]
            res = max(res, abs(s))
        if not res <= vtol:
            continue    # S cannot stick: contradictory (over-determined) constraints
        for k in range(n):
            Q[k] = 0.0
        for i in range(m):
            Q[idx[i]] = la[X0 + i]
        if _residual(W, v0, tb, mu, Q, r, n, F, J, False, 3) <= tol_p or \
                polish_blocks(W, v0, tb, mu, Q, K, vtol, 3):
            for k in range(n):
                P[k] = Q[k]
            return True
    return False
