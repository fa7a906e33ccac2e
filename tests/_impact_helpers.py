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
