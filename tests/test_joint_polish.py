"""The exact polish of the 3D simultaneous impact problem (kernels/joint_polish.py):
Newton restitution with Coulomb friction over K contacts of one body on a floor, started
from a few projected Gauss-Seidel sweeps. Every solution it returns satisfies the
complementarity and friction conditions to round-off; it finds one from PGS's iterate for
nearly every contact set with mu <= 1 (a body on its face, edge or corners)."""
import numpy as np
import pytest

from rbimpact.kernels.joint_polish import polish


def _frame(n):
    t1 = np.cross(n, [1.0, 0, 0]) if abs(n[0]) < 0.9 else np.cross(n, [0, 1.0, 0])
    t1 /= np.linalg.norm(t1)
    return np.array([n, t1, np.cross(n, t1)])


def _case(rng, K, mu):
    """One rigid body (mass, principal inertia), K contact points on the floor z = 0."""
    m = rng.uniform(0.1, 2.0)
    Minv = np.zeros((6, 6))
    Minv[:3, :3] = np.eye(3) / m
    Minv[3:, 3:] = np.linalg.inv(np.diag(rng.uniform(0.01, 1.0, 3)) * m)
    Fr = _frame(np.array([0, 0, 1.0]))
    rows = []
    for _ in range(K):
        r = rng.uniform(-1, 1, 3)
        r[2] = -abs(r[2])                       # below the centre of mass
        rows += [np.concatenate([d, np.cross(r, d)]) for d in Fr]
    Jc = np.array(rows)
    W = Jc @ Minv @ Jc.T
    v0 = Jc @ rng.normal(size=6)
    v0[0::3] = -np.abs(v0[0::3])
    tb = np.zeros(3 * K)
    tb[0::3] = -rng.uniform(0, 1) * v0[0::3]
    return W, v0, tb, np.full(K, mu)


def _pgs(W, v0, tb, mu, K, sweeps):
    P = np.zeros(3 * K)
    v = v0.copy()
    for _ in range(sweeps):
        for a in range(K):
            i = 3 * a
            new = max(P[i] - (v[i] - tb[i]) / W[i, i], 0.0)
            v += W[:, i] * (new - P[i])
            P[i] = new
            nt = P[i + 1:i + 3] - np.linalg.solve(W[i + 1:i + 3, i + 1:i + 3], v[i + 1:i + 3])
            nn = np.linalg.norm(nt)
            if nn > mu[a] * P[i]:
                nt = nt * (mu[a] * P[i] / nn) if nn > 0 else 0 * nt
            v += W[:, i + 1:i + 3] @ (nt - P[i + 1:i + 3])
            P[i + 1:i + 3] = nt
    return P


def _violation(W, v0, tb, mu, P, K):
    """Largest violation of the impact conditions, in units of the initial speed."""
    u = v0 + W @ P
    sc = np.abs(v0).max()
    worst = 0.0
    for a in range(K):
        i = 3 * a
        pn = P[i] * W[i, i] / sc                  # impulse as a speed
        gap = (u[i] - tb[i]) / sc
        worst = max(worst, -pn, -gap, min(pn, abs(gap)) if P[i] > 0 else 0.0)
        pt, ut = P[i + 1:i + 3], u[i + 1:i + 3]
        worst = max(worst, (np.linalg.norm(pt) - mu[a] * P[i]) * W[i, i] / sc)
        if np.linalg.norm(ut) > 1e-9 * sc:       # sliding: friction opposes the slip
            worst = max(worst, np.linalg.norm(pt + mu[a] * P[i] * ut / np.linalg.norm(ut))
                        * W[i, i] / sc)
    return worst


@pytest.mark.parametrize("K", [1, 2, 3, 4, 6])
@pytest.mark.parametrize("mu", [0.0, 0.3, 1.0, 10.0])
def test_polished_impulses_satisfy_the_impact_law(K, mu):
    rng = np.random.default_rng(100 * K + int(10 * mu))
    found = 0
    for _ in range(20):
        W, v0, tb, m = _case(rng, K, mu)
        P = _pgs(W, v0, tb, m, K, 300)
        before = P.copy()
        if polish(W, v0, tb, m, P, K, 1e-13 * np.abs(v0).max()):
            found += 1
            assert _violation(W, v0, tb, m, P, K) < 1e-9
        else:
            np.testing.assert_array_equal(P, before)   # a failure leaves P as it was
    if mu <= 1.0:
        assert found >= 18
