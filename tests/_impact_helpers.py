"""Shared helpers of the law-kernel tests (Kane & Levinson, Brach, Chatterjee & Ruina).

Conventions: DESIGN.md §3 (normal first, ``v_f = v + W P``, ``P`` the impulse on body A).
"""
import numpy as np

from rbimpact.kernels.common import N_PARAMS, P_E, P_ET, P_MU

ROD = np.array([[2.5, -1.5], [-1.5, 2.5]])
SPHERE_2D = np.diag([1.0, 3.5])
SPHERE_3D = np.diag([1.0, 3.5, 3.5])
SWERVE_W = np.array([[5.0, 1.0, -1.0], [1.0, 8.0, -2.0], [-1.0, -2.0, 3.0]])
SWERVE_V = np.array([-4.0, -2.0, 1.0])


def params(e=0.0, mu=0.0, et=0.0):
    p = np.zeros(N_PARAMS)
    p[P_E] = e
    p[P_MU] = mu
    p[P_ET] = et
    return p


def run(kernel, v, W, p):
    """Call ``kernel``; returns (mode, P, v_f, dE) with ``dE = P . (v + v_f) / 2``."""
    v = np.ascontiguousarray(v, dtype=float)
    W = np.ascontiguousarray(W, dtype=float)
    P = np.full(v.shape[0], 123.0)          # garbage: the kernel must overwrite it
    mode = kernel(v, W, p, P)
    vf = v + W @ P
    return mode, P, vf, 0.5 * P @ (v + vf)


def random_spd(rng, d, coupling=1.0, floor=0.05):
    """A random SPD matrix; ``coupling`` scales the normal row (strong W_NT when large)."""
    A = rng.normal(size=(d, d))
    A[0] *= coupling
    return A @ A.T + floor * np.eye(d)


def random_contact(rng, d, coupling=1.0):
    W = random_spd(rng, d, coupling)
    v = rng.normal(size=d)
    v[0] = -abs(v[0]) - 1e-3
    return v, W


def rot2(phi):
    c, s = np.cos(phi), np.sin(phi)
    return np.array([[c, -s], [s, c]])


def tangent_rotation(phi):
    """R = diag(1, rot2(phi)): rotates the tangent basis of a 3D contact."""
    R = np.eye(3)
    R[1:, 1:] = rot2(phi)
    return R


# ---- random rigid bodies: W built from m, I, arm r; energy computed in body space ----------

def _cross2(r, d):
    return r[0] * d[1] - r[1] * d[0]


def rigid_contact_2d(rng, two_bodies=True):
    """Two planar rigid bodies (B may be static) touching at one point.

    Returns (v, W, energy) where ``energy(P)`` returns (the kinetic energy change computed
    from the body velocities after applying P, the contact velocity v_f read from the
    bodies, the kinetic energy before)."""
    phi = rng.uniform(0, 2 * np.pi)
    n = np.array([np.cos(phi), np.sin(phi)])
    t = np.array([n[1], -n[0]])
    dirs = (n, t)
    bodies = []
    for k in range(2 if two_bodies else 1):
        m = rng.uniform(0.2, 5.0)
        inertia = rng.uniform(0.02, 2.0)
        r = rng.normal(size=2)
        q = rng.normal(size=3)                  # (vx, vy, omega)
        J = np.array([[d[0], d[1], _cross2(r, d)] for d in dirs])
        Minv = np.diag([1 / m, 1 / m, 1 / inertia])
        M = np.diag([m, m, inertia])
        bodies.append((J, Minv, M, q, 1.0 if k == 0 else -1.0))
    v = sum(sgn * J @ q for J, _, _, q, sgn in bodies)
    if v[0] > 0:                                # make it an approach: reverse all motion
        bodies = [(J, Mi, M, -q, sgn) for J, Mi, M, q, sgn in bodies]
        v = -v
    W = sum(J @ Mi @ J.T for J, Mi, _, _, _ in bodies)

    def energy(P):
        dE, E0 = 0.0, 0.0
        vf = np.zeros(2)
        for J, Mi, M, q, sgn in bodies:
            qf = q + sgn * Mi @ J.T @ P
            dE += 0.5 * qf @ M @ qf - 0.5 * q @ M @ q
            E0 += 0.5 * q @ M @ q
            vf += sgn * J @ qf
        return dE, vf, E0

    return v, W, energy


def _orthonormal_tangents(n):
    a = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    t1 = np.cross(n, a)
    t1 /= np.linalg.norm(t1)
    return t1, np.cross(n, t1)


def rigid_contact_3d(rng, two_bodies=True):
    """Two 3D rigid bodies (random world-frame inertia tensors); same return as 2D."""
    n = rng.normal(size=3)
    n /= np.linalg.norm(n)
    t1, t2 = _orthonormal_tangents(n)
    dirs = (n, t1, t2)
    bodies = []
    for k in range(2 if two_bodies else 1):
        m = rng.uniform(0.2, 5.0)
        Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        Ib = Q @ np.diag(rng.uniform(0.02, 2.0, size=3)) @ Q.T
        r = rng.normal(size=3)
        q = rng.normal(size=6)                  # (velocity, angular velocity)
        J = np.array([np.concatenate([d, np.cross(r, d)]) for d in dirs])
        M = np.zeros((6, 6))
        M[:3, :3] = m * np.eye(3)
        M[3:, 3:] = Ib
        Minv = np.linalg.inv(M)
        bodies.append((J, Minv, M, q, 1.0 if k == 0 else -1.0))
    v = sum(sgn * J @ q for J, _, _, q, sgn in bodies)
    if v[0] > 0:
        bodies = [(J, Mi, M, -q, sgn) for J, Mi, M, q, sgn in bodies]
        v = -v
    W = sum(J @ Mi @ J.T for J, Mi, _, _, _ in bodies)
    W = 0.5 * (W + W.T)

    def energy(P):
        dE, E0 = 0.0, 0.0
        vf = np.zeros(3)
        for J, Mi, M, q, sgn in bodies:
            qf = q + sgn * Mi @ J.T @ P
            dE += 0.5 * qf @ M @ qf - 0.5 * q @ M @ q
            E0 += 0.5 * q @ M @ q
            vf += sgn * J @ qf
        return dE, vf, E0

    return v, W, energy


def check_energy_identity(kernel, rng, dim, n_cases, e_range, mu_max, et_range=(0.0, 0.0)):
    """dE = P.(v + v_f)/2 equals the kinetic energy change of the bodies, and the contact
    velocity of the bodies after the impulse equals v + W P. Returns the number of impacts."""
    make = rigid_contact_2d if dim == 2 else rigid_contact_3d
    n_imp = 0
    for k in range(n_cases):
        v, W, energy = make(rng, two_bodies=bool(k % 2))
        p = params(rng.uniform(*e_range), rng.uniform(0, mu_max), rng.uniform(*et_range))
        mode, P, vf, dE = run(kernel, v, W, p)
        assert mode >= 0
        dE_bodies, vf_bodies, E0 = energy(P)
        assert abs(dE - dE_bodies) <= 1e-10 * (E0 + abs(dE))
        np.testing.assert_allclose(vf, vf_bodies, rtol=1e-9, atol=1e-9 * np.abs(v).max())
        n_imp += mode != 0
    return n_imp


# ---- exact (rational) references for the ill-conditioned regression tests ------------------
from fractions import Fraction  # noqa: E402

EPS = np.finfo(float).eps
W_THIN_ROD = np.array([[50000001.00000001, -50000000.0],      # rod with I = 1e-8 m r^2
                       [-50000000.0, 50000000.999999985]])      # (cond 1e8)
W_SPD_CANCELS = np.array([  # SPD (cond 5.6e9), det3 by plain cofactors is -7.9e-6
    [5373.253418896723, 2793.1580554897914, 12198.128893487266],
    [2793.1580554897914, 1451.956825583143, 6340.907357175057],
    [12198.128893487266, 6340.907357175057, 27691.66801277434]])
W_COND_7E11 = np.array([  # cond 6.7e11: the plain cofactor solve misses v_fT = 0 by 2e-7 s
    [1.5224270311101227, 2.0461907181712737, -1.985885176336621],
    [2.0461907181712737, 2.7501458986920353, -2.6690933183829935],
    [-1.985885176336621, -2.6690933183829935, 2.590429528825504]])


def exact_solve(W, r):
    """W^-1 r in exact rational arithmetic from the float entries (Gaussian elimination):
    a list of Fractions."""
    n = len(r)
    A = [[Fraction(float(W[i][j])) for j in range(n)] + [Fraction(float(r[i]))]
         for i in range(n)]
    for k in range(n):
        p = next(i for i in range(k, n) if A[i][k] != 0)
        A[k], A[p] = A[p], A[k]
        for i in range(k + 1, n):
            m = A[i][k] / A[k][k]
            A[i] = [x - m * y for x, y in zip(A[i], A[k])]
    x = [Fraction(0)] * n
    for k in reversed(range(n)):
        x[k] = (A[k][n] - sum(A[k][j] * x[j] for j in range(k + 1, n))) / A[k][k]
    return x


def exact_minors(W):
    """Leading principal minors of W in exact rational arithmetic (Sylvester: W is SPD iff
    all are positive)."""
    F = [[Fraction(float(x)) for x in row] for row in W]
    out = [F[0][0]]
    if len(W) >= 2:
        out.append(F[0][0] * F[1][1] - F[0][1] * F[1][0])
    if len(W) == 3:
        out.append(F[0][0] * (F[1][1] * F[2][2] - F[1][2] * F[2][1])
                   - F[0][1] * (F[1][0] * F[2][2] - F[1][2] * F[2][0])
                   + F[0][2] * (F[1][0] * F[2][1] - F[1][1] * F[2][0]))
    return out


def exact_dE(v, W, P):
    """dE = P.v + P.W.P / 2 (J), exact from the float inputs (judges P, not the rounding of
    the energy formula)."""
    Pf = [Fraction(float(x)) for x in P]
    q = sum(Pf[i] * Fraction(float(W[i][j])) * Pf[j] for i in range(len(P))
            for j in range(len(P)))
    return float(sum(p * Fraction(float(x)) for p, x in zip(Pf, v)) + q / 2)


def exact_vf(v, W, P):
    """v + W P evaluated exactly, rounded once (m/s)."""
    return np.array([float(Fraction(float(v[i])) + sum(Fraction(float(W[i][j]))
                                                       * Fraction(float(P[j]))
                                                       for j in range(len(P))))
                     for i in range(len(v))])


def ill_conditioned_spd(rng, d, log_cond):
    """Random SPD W = Q diag(1, .., 10^-log_cond) Q^T times a random scale, symmetrized,
    kept only if exactly SPD (rational leading minors) — else redrawn."""
    while True:
        Q, _ = np.linalg.qr(rng.normal(size=(d, d)))
        lam = np.concatenate([[1.0], 10.0 ** -rng.uniform(0, log_cond, d - 2),
                              [10.0 ** -log_cond]])
        W = (Q * lam) @ Q.T * 10.0 ** rng.uniform(-3, 3)
        W = 0.5 * (W + W.T)
        if all(m > 0 for m in exact_minors(W)):
            return W


def rel_err(x, xref):
    """max_i |x_i - xref_i| / max_i |xref_i| (normwise, exact reference as Fractions)."""
    scale = max(abs(float(r)) for r in xref)
    return max(abs(float(Fraction(float(a)) - r)) for a, r in zip(x, xref)) / scale
