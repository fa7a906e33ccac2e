"""Rest on several points in 3D: the static-equilibrium test of a body held at K >= 3
contact points on one or more planes (a box with an edge on one groove plane and a corner
on the other, a face on one and an edge on the other; a capsule with its axis on one plane
and a cap on the other), DESIGN §6a "rest on a face / several points"; the 3D analogue of
``wedge2d``.

A body of mass ``m`` under gravity ``g`` touches planes at contact points with arms ``r_k``
(contact point minus centre of mass, m), unit normals ``n_k`` (into the body) and friction
coefficients ``mu_k``. It can rest there iff contact forces ``f_k`` (N) exist with

    sum_k f_k + m g = 0,   sum_k r_k x f_k = 0,   f_k in C_k = {|f_k - (n_k . f_k) n_k| <= mu_k n_k . f_k}

(Coulomb cones; ``mu_k = 0``: the ray ``f_k = N_k n_k``, ``N_k >= 0``). The six equations
leave a ``3K - 6`` dimensional affine set ``A`` of force vectors (``G f = b``, ``G`` the
6 x 3K wrench map of full rank when the points are not collinear); the test is whether
``A`` meets the product of the cones, a convex feasibility problem with no closed form
for K >= 3. It is decided by alternating projections (von Neumann; for two closed convex
sets that intersect they converge to a point of the intersection): the projection onto
``A`` is ``f - G^T (G G^T)^-1 (G f - b)`` (one 6 x 6 Cholesky factor), onto a cone the
closed form ``_cone_project``. The iterates are projected onto cones shrunk by
``REST_SHRINK`` so that, when the true cones hold a strictly feasible point, an iterate of
``A`` (an exact equilibrium, up to round-off) lands strictly inside the true cones; it is
accepted when every cone is met within ``REST_CONE_RTOL m |g|`` (round-off). A rest that
is only feasible on the boundary of the cones (frictionless contacts, a rest exactly at the
onset of slip) is accepted when the iteration reaches that tolerance within ``REST_ITER``
iterations. No accepted answer is a sound "no": the stepper then refuses the state
(``ERR_UNSUPPORTED``) rather than resting a body that would slide or tip.

Collinear points (a capsule on its side, a box on an edge) leave the moment about their
line to gravity alone: ``line_rest`` (the lever rule) decides them.

Arrays in and out (``arms``, ``normals`` float64[K, 3], ``mu`` float64[K], ``f`` float64[K,
3] the forces found, ``work`` float64[rest_work_size(K)]), no allocation.
"""
import math

from numba import njit

REST_CONE_RTOL = 1e-12
"""A force is in its cone when ``mu N - |T| >= -REST_CONE_RTOL m |g|`` and ``N >=
-REST_CONE_RTOL m |g|``, and the equilibrium residual is below the same (N: round-off of
the force balance; the residual's moments, N m, divided by the body's longest arm)."""
REST_SHRINK = 1e-6
"""The iterates are projected onto the cones ``mu (1 - REST_SHRINK)`` shifted inwards by
``REST_SHRINK m |g| / K`` along the normal (dimensionless): a strictly feasible rest is
then found exactly inside the true cones."""
REST_ITER = 20000
"""Alternating projections at most (each O(K) after one 6 x 6 factorisation)."""
RANK_RTOL = 1e-12
"""The wrench map is degenerate (collinear points: a corner held on two planes is one
point) when a Cholesky pivot of ``G G^T`` falls below this times its largest diagonal
(scaled to the body's arm length)."""


@njit(cache=True)
def rest_work_size(K):
    """Length of the ``work`` array ``rest_forces`` needs for K contacts."""
    return 36 + 6 + 6 + 3 * K


@njit(cache=True, inline="always")
def _cone_project(fx, fy, fz, nx, ny, nz, mu, shift):
    """Euclidean projection of the force (fx, fy, fz) onto the Coulomb cone of axis n and
    coefficient mu whose apex is moved ``shift`` (N) along n (``mu = 0``: the ray)."""
    fn = fx * nx + fy * ny + fz * nz - shift
    tx = fx - (fn + shift) * nx
    ty = fy - (fn + shift) * ny
    tz = fz - (fn + shift) * nz
    ft = math.sqrt(tx * tx + ty * ty + tz * tz)
    if ft <= mu * fn:
        return fx, fy, fz
    if mu * ft <= -fn:          # in the polar cone: the apex
        return shift * nx, shift * ny, shift * nz
    pn = (fn + mu * ft) / (1.0 + mu * mu)
    s = mu * pn / ft if ft > 0.0 else 0.0
    pn += shift
    return pn * nx + s * tx, pn * ny + s * ty, pn * nz + s * tz


@njit(cache=True)
def _affine(K, arms, f, work, bx, by, bz, L):
    """Project f (in place) onto the equilibrium set G f = b (b = (bx, by, bz, 0, 0, 0));
    work[0:36] holds the Cholesky factor of G G^T. Returns the residual before, in N: the
    force residual and the moment residual (N m) divided by ``L`` (m, the longest arm)."""
    y = work[36:42]
    # residual G f - b
    for j in range(6):
        y[j] = 0.0
    for k in range(K):
        rx, ry, rz = arms[k, 0], arms[k, 1], arms[k, 2]
        fx, fy, fz = f[k, 0], f[k, 1], f[k, 2]
        y[0] += fx
        y[1] += fy
        y[2] += fz
        y[3] += ry * fz - rz * fy
        y[4] += rz * fx - rx * fz
        y[5] += rx * fy - ry * fx
    y[0] -= bx
    y[1] -= by
    y[2] -= bz
    res = y[0] * y[0] + y[1] * y[1] + y[2] * y[2]
    for j in range(3, 6):
        res += (y[j] / L) ** 2
    # solve (L L^T) z = y
    for r in range(6):
        s = y[r]
        for c in range(r):
            s -= work[6 * r + c] * y[c]
        y[r] = s / work[6 * r + r]
    for r in range(5, -1, -1):
        s = y[r]
        for c in range(r + 1, 6):
            s -= work[6 * c + r] * y[c]
        y[r] = s / work[6 * r + r]
    # f -= G^T z: force part z[0:3], moment part m = z[3:6] gives r x ... transposed:
    # (G^T z)_k = z_F + z_M x r_k
    for k in range(K):
        rx, ry, rz = arms[k, 0], arms[k, 1], arms[k, 2]
        f[k, 0] -= y[0] + (y[4] * rz - y[5] * ry)
        f[k, 1] -= y[1] + (y[5] * rx - y[3] * rz)
        f[k, 2] -= y[2] + (y[3] * ry - y[4] * rx)
    return math.sqrt(res)


@njit(cache=True)
def rest_forces(K, arms, normals, mu, m, gx, gy, gz, f, work):
    """Contact forces f[0:K] (N) holding the body at rest (see the module docstring).
    Returns (code, margin): code 0 a rest (f in the cones within ``REST_CONE_RTOL m |g|``,
    ``margin`` the smallest ``mu N - |T|`` and ``N`` over the contacts, N), 1 none found,
    2 a degenerate wrench map (collinear points). Units: m (kg), g (m/s^2), arms (m)."""
    fs = m * math.sqrt(gx * gx + gy * gy + gz * gz)
    L = 0.0
    for k in range(K):
        L = max(L, math.sqrt(arms[k, 0] ** 2 + arms[k, 1] ** 2 + arms[k, 2] ** 2))
    if not (fs > 0.0 and L > 0.0 and K >= 1):
        return 2, 0.0
    # G G^T in units where arms are scaled by L (kept exact: the scale only enters the
    # rank test); A = sum_k sum_j c c^T with c = (e_j, r_k x e_j)
    A = work[0:36]
    for j in range(36):
        A[j] = 0.0
    for k in range(K):
        rx, ry, rz = arms[k, 0], arms[k, 1], arms[k, 2]
        for j in range(3):
            ex = 1.0 if j == 0 else 0.0
            ey = 1.0 if j == 1 else 0.0
            ez = 1.0 if j == 2 else 0.0
            c = work[42:48]
            c[0] = ex
            c[1] = ey
            c[2] = ez
            c[3] = ry * ez - rz * ey
            c[4] = rz * ex - rx * ez
            c[5] = rx * ey - ry * ex
            for a in range(6):
                for b in range(6):
                    A[6 * a + b] += c[a] * c[b]
    # Cholesky (lower, in place in the lower triangle)
    dmax = 0.0
    for a in range(6):
        dmax = max(dmax, A[6 * a + a] / (L * L if a >= 3 else 1.0))
    for r in range(6):
        for c in range(r + 1):
            s = A[6 * r + c]
            for p in range(c):
                s -= A[6 * r + p] * A[6 * c + p]
            if r == c:
                sc = L * L if r >= 3 else 1.0
                if not s > RANK_RTOL * dmax * sc:
                    return 2, 0.0
                A[6 * r + r] = math.sqrt(s)
            else:
                A[6 * r + c] = s / A[6 * c + c]
    bx, by, bz = -m * gx, -m * gy, -m * gz
    tol = REST_CONE_RTOL * fs
    shift = REST_SHRINK * fs / K
    for k in range(K):
        f[k, 0] = 0.0
        f[k, 1] = 0.0
        f[k, 2] = 0.0
    _affine(K, arms, f, work, bx, by, bz, L)
    margin = -math.inf
    for it in range(REST_ITER + 1):
        # f is an equilibrium (to round-off): in the true cones?
        margin = math.inf
        for k in range(K):
            nx, ny, nz = normals[k, 0], normals[k, 1], normals[k, 2]
            fn = f[k, 0] * nx + f[k, 1] * ny + f[k, 2] * nz
            tx = f[k, 0] - fn * nx
            ty = f[k, 1] - fn * ny
            tz = f[k, 2] - fn * nz
            mg = min(fn, mu[k] * fn - math.sqrt(tx * tx + ty * ty + tz * tz))
            margin = min(margin, mg)
        if margin >= -tol:
            # confirm the balance of the accepted forces
            sv = work[48:48 + 3 * K]
            for k in range(K):
                sv[3 * k] = f[k, 0]
                sv[3 * k + 1] = f[k, 1]
                sv[3 * k + 2] = f[k, 2]
            res = _affine(K, arms, f, work, bx, by, bz, L)
            for k in range(K):
                f[k, 0] = sv[3 * k]
                f[k, 1] = sv[3 * k + 1]
                f[k, 2] = sv[3 * k + 2]
            if res <= tol:
                return 0, margin
        if it == REST_ITER:
            break
        for k in range(K):
            f[k, 0], f[k, 1], f[k, 2] = _cone_project(
                f[k, 0], f[k, 1], f[k, 2], normals[k, 0], normals[k, 1], normals[k, 2],
                mu[k] * (1.0 - REST_SHRINK), shift)
        _affine(K, arms, f, work, bx, by, bz, L)
    return 1, margin


@njit(cache=True)
def line_rest(K, arms, normals, mu, gx, gy, gz):
    """Rest on collinear contact points (``rest_forces``' code 2: a capsule on its side,
    a box on an edge): gravity's line through the centre of mass must meet the segment
    between the two outermost points ``a``, ``b``, which then carry the parallel loads
    ``-m g (1 - s)`` and ``-m g s`` (the lever rule, ``s`` the meeting point's parameter
    along ``a -> b``; the points between carry none). Returns ``(miss, margin)``: ``miss``
    (m) the distance between gravity's line and the nearest point of the segment (the
    moment left is ``m |g| miss``), ``margin`` the smallest ``mu N - |T|`` of the two loads
    per unit weight (dimensionless, negative when ``-g`` leaves a loaded point's cone).
    A line along gravity holds nothing: ``miss`` is infinite. Arrays as ``rest_forces``."""
    ka = 0
    kb = 0
    best = 0.0
    for a in range(K):
        for b in range(a + 1, K):
            d2 = ((arms[b, 0] - arms[a, 0]) ** 2 + (arms[b, 1] - arms[a, 1]) ** 2
                  + (arms[b, 2] - arms[a, 2]) ** 2)
            if d2 > best:
                best = d2
                ka = a
                kb = b
    gn = math.sqrt(gx * gx + gy * gy + gz * gz)
    if not (best > 0.0 and gn > 0.0):
        return math.inf, 0.0
    ux = gx / gn
    uy = gy / gn
    uz = gz / gn
    ax, ay, az = arms[ka, 0], arms[ka, 1], arms[ka, 2]
    dx = arms[kb, 0] - ax
    dy = arms[kb, 1] - ay
    dz = arms[kb, 2] - az
    # the segment a + s d nearest to the line through the origin along u: minimise the
    # part of a + s d across u, |(a + s d) - ((a + s d) . u) u|^2
    du = dx * ux + dy * uy + dz * uz
    au = ax * ux + ay * uy + az * uz
    dd = best - du * du             # |d across u|^2
    if not dd > 0.0:
        return math.inf, 0.0
    s = -((ax * dx + ay * dy + az * dz) - au * du) / dd
    s = min(max(s, 0.0), 1.0)
    px = ax + s * dx
    py = ay + s * dy
    pz = az + s * dz
    pu = px * ux + py * uy + pz * uz
    miss = math.sqrt(max((px - pu * ux) ** 2 + (py - pu * uy) ** 2 + (pz - pu * uz) ** 2,
                         0.0))
    margin = math.inf
    for k, load in ((ka, 1.0 - s), (kb, s)):
        # the load -g (per unit weight) at contact k: normal part and tangential part
        fn = -(ux * normals[k, 0] + uy * normals[k, 1] + uz * normals[k, 2])
        ft = math.sqrt(max(1.0 - fn * fn, 0.0))
        margin = min(margin, load * (mu[k] * fn - ft), load * fn)
    return miss, margin
