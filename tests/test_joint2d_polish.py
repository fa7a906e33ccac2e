"""The finish of the 2D simultaneous joint solve (stepper2d._joint_finish): the shared
semismooth Newton polish (kernels/joint_polish.py, block size 2) and the exact active sets
(enumerate2d). A box corner pair in a V-groove with mu = 10: the Delassus matrix of the two
contacts has rank 3, its squeeze lies in both friction cones, Gauss-Seidel drifts along it;
with e = 0 a solution exists (checked against a brute-force enumeration with numpy), with
e > 0 none does (a jam: a named refusal in the stepper)."""
import itertools

import numpy as np
import pytest

from rbimpact.kernels.joint_polish import enumerate2d, polish, polish2d, polish_blocks


def _groove_case(half_angle=np.radians(40), mu=10.0, e=0.0, seed=0):
    """A box (m, I) touching both planes of a V-groove with two corners; returns the
    contact Jacobian J (4 x 3, normal-first per contact), M^-1, W, v0, tb, mu."""
    rng = np.random.default_rng(seed)
    m, I = 1.3, 0.2
    Minv = np.diag([1 / m, 1 / m, 1 / I])
    rows = []
    for sgn, r in ((1, np.array([-0.4, -0.3])), (-1, np.array([0.4, -0.3]))):
        n = np.array([sgn * np.cos(half_angle), np.sin(half_angle)])
        t = np.array([n[1], -n[0]])
        for d in (n, t):
            rows.append([d[0], d[1], r[0] * d[1] - r[1] * d[0]])
    J = np.array(rows)
    W = J @ Minv @ J.T
    vb = np.array([0.1, -1.0, 0.0]) + 0.2 * rng.normal(size=3)
    v0 = J @ vb
    tb = np.zeros(4)
    tb[0::2] = -e * np.minimum(v0[0::2], 0.0)
    return J, Minv, W, v0, tb, np.full(2, mu), vb


def _brute(W, v0, tb, mu):
    """All solutions by active sets (numpy lstsq), the squeeze family of a singular
    stick-stick system searched along its null vector."""
    sols = []
    z = np.linalg.eigh(W)[1][:, 0]
    for modes in itertools.product(range(4), repeat=2):
        A, b = [], []
        for a, md in enumerate(modes):
            iN, iT = 2 * a, 2 * a + 1
            if md == 0:
                A += [np.eye(4)[iN], np.eye(4)[iT]]
                b += [0, 0]
            else:
                A.append(W[iN])
                b.append(tb[iN] - v0[iN])
                if md == 1:
                    A.append(W[iT])
                    b.append(-v0[iT])
                else:
                    row = np.eye(4)[iT] + (mu[a] if md == 2 else -mu[a]) * np.eye(4)[iN]
                    A.append(row)
                    b.append(0)
        A, b = np.array(A), np.array(b)
        P = np.linalg.lstsq(A, b, rcond=None)[0]
        if np.abs(A @ P - b).max() > 1e-12:
            continue
        family = np.abs(A @ z).max() <= 1e-12 * np.abs(A).max()   # singular: P + s z
        for s in (0.0, *(np.geomspace(1e-3, 1e3, 61) if family else ())):
            Q = P + s * z * np.sign(z[0])
            u = v0 + W @ Q
            ok = all(Q[2 * a] >= -1e-13 and abs(Q[2 * a + 1]) <= mu[a] * Q[2 * a] + 1e-13
                     and u[2 * a] >= tb[2 * a] - 1e-13
                     and (modes[a] < 2 or (1 if modes[a] == 2 else -1) * u[2 * a + 1] >= -1e-13)
                     for a in range(2))
            if ok:
                sols.append(u)
                break
    return sols


def _pgs(W, v0, tb, mu, sweeps):
    P = np.zeros(4)
    v = v0.copy()
    for _ in range(sweeps):
        for i in range(4):
            if i % 2 == 0:
                new = max(P[i] - (v[i] - tb[i]) / W[i, i], 0.0)
            else:
                lim = mu[i // 2] * P[i - 1]
                new = min(max(P[i] - v[i] / W[i, i], -lim), lim)
            v += W[:, i] * (new - P[i])
            P[i] = new
    return P, v


def test_groove_is_redundant_and_squeeze_inside_cones():
    J, Minv, W, v0, tb, mu, vb = _groove_case()
    ev, vec = np.linalg.eigh(W)
    assert ev[0] < 1e-14 * ev[-1]                       # rank 3: the squeeze
    z = vec[:, 0] * np.sign(vec[0, 0])
    assert z[0] > 0 and z[2] > 0
    assert abs(z[1]) < mu[0] * z[0] and abs(z[3]) < mu[1] * z[2]


def test_gauss_seidel_drifts_along_the_squeeze_in_a_jam():
    J, Minv, W, v0, tb, mu, vb = _groove_case(e=0.5)
    P1, _ = _pgs(W, v0, tb, mu, 100)
    P2, _ = _pgs(W, v0, tb, mu, 1000)
    assert np.linalg.norm(P2) > 5 * np.linalg.norm(P1)   # impulses grow without bound


@pytest.mark.parametrize("seed", range(6))
def test_polish2d_e0_matches_brute_force(seed):
    J, Minv, W, v0, tb, mu, vb = _groove_case(e=0.0, seed=seed)
    sols = _brute(W, v0, tb, mu)
    assert sols
    P0, _ = _pgs(W, v0, tb, mu, 200)
    P = P0.copy()
    sc = np.abs(v0).max()
    ok = polish2d(W, v0, tb, mu, P, 2, 1e-14 * sc)
    if not ok:                                           # the stepper's second stage
        P = np.zeros(4)
        found, und = enumerate2d(W, v0, tb, mu, 2, 1e-9 * sc, v0 + W @ P0, P,
                                 np.zeros((4, 5)), np.zeros(4))
        assert found >= 1
    u = v0 + W @ P
    assert min(np.abs(u - s).max() for s in sols) <= 1e-12 * sc
    # the law's own conditions
    for a in range(2):
        assert P[2 * a] >= -1e-12 * sc / W[0, 0]
        assert u[2 * a] >= tb[2 * a] - 1e-12 * sc
        assert abs(P[2 * a + 1]) <= mu[a] * P[2 * a] + 1e-12 * sc / W[0, 0]
    # no energy created (e = 0: P.u = sum P_T u_T <= 0)
    dE = 0.5 * P @ (v0 + u)
    assert dE <= 1e-12 * 0.5 * vb @ np.linalg.solve(Minv, vb)
    # bookkeeping: the impulses at the two points reproduce the body's velocity change
    dvb = Minv @ J.T @ P
    np.testing.assert_allclose(J @ (vb + dvb), u, rtol=0, atol=1e-12 * sc)


@pytest.mark.parametrize("e", [0.3, 0.8, 1.0])
def test_jam_with_restitution_has_no_solution(e):
    J, Minv, W, v0, tb, mu, vb = _groove_case(e=e)
    assert not _brute(W, v0, tb, mu)
    P = np.zeros(4)
    P0, v = _pgs(W, v0, tb, mu, 300)
    assert not polish2d(W, v0, tb, mu, P0.copy(), 2, 1e-14 * np.abs(v0).max())
    found, und = enumerate2d(W, v0, tb, mu, 2, 1e-9 * np.abs(v0).max(), v, P,
                             np.zeros((4, 5)), np.zeros(4))
    assert (found, und) == (0, 0)


def test_enumerate2d_against_brute_force_random():
    rng = np.random.default_rng(7)
    for k in range(200):
        ang = rng.uniform(0.2, 1.4)
        J, Minv, W, v0, tb, mu, vb = _groove_case(ang, mu=rng.choice([0.1, 0.5, 1.0, 10.0]),
                                                  e=rng.choice([0.0, 0.5]), seed=k)
        sc = np.abs(v0).max()
        P = np.zeros(4)
        found, und = enumerate2d(W, v0, tb, mu, 2, 1e-9 * sc, v0, P, np.zeros((4, 5)),
                                 np.zeros(4))
        brute = _brute(W, v0, tb, mu)
        if found:
            assert brute
            u = v0 + W @ P
            assert min(np.abs(u - s).max() for s in brute) <= 1e-9 * sc
        elif und == 0:
            assert not brute


def test_polish_3d_entry_unchanged():
    """The 3D entry is polish_blocks with block size 3 (one shared core)."""
    rng = np.random.default_rng(3)
    W = rng.normal(size=(3, 3))
    W = W @ W.T + 3 * np.eye(3)
    v0 = np.array([-1.0, 0.3, -0.2])
    tb = np.array([0.5, 0.0, 0.0])
    P1, P2 = np.zeros(3), np.zeros(3)
    assert polish(W, v0, tb, np.array([0.5]), P1, 1, 1e-13)
    assert polish_blocks(W, v0, tb, np.array([0.5]), P2, 1, 1e-13, 3)
    np.testing.assert_array_equal(P1, P2)


# the 15 campaign seeds of the simultaneous-policy failures: each ends 'done' or with the
# named refusal (no solution of the joint problem), never a FAIL
SEEDS = [4072990479, 4077301673, 2993034395, 2013800454, 1403178550, 2993842006, 3883007404,
         2226452308, 2578521408, 2887359224, 2541587082, 469870883, 3025119876, 3653058037,
         3471957551]
SOLVED = {2993842006, 3025119876}


@pytest.mark.parametrize("seed", SEEDS)
def test_campaign_seed_not_fail(seed):
    from rbimpact import campaign as c
    row = c.run_drop(2, seed)
    assert row.verdict != "FAIL", row.note
    if seed in SOLVED:
        assert row.verdict == "OK" and row.status == "done"
    else:
        assert row.verdict == "REFUSED" and "Painleve-type jam" in row.note
