"""Smith's law kernels (kernels/smith.py): reference values, independent references,
physical properties, invariances and the set-valued a = 0 case.

Independent references are written here in plain NumPy/SciPy from the law's equations
(DESIGN §4): 2D by a dense scan of the residual over the final slip b refined with brentq;
3D by fsolve from many starts, keeping roots with P_N > 0 and taking the smallest P_N.
"""
import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.optimize import brentq, fsolve

from rbimpact.kernels.common import (MODE_NO_SOLUTION, MODE_SEPARATING, MODE_SLIP,
                                     MODE_STICK, N_PARAMS, P_E, P_MU)
from rbimpact.kernels.smith import _unique_certificate, smith, smith_2d, smith_3d

ROD = [[2.5, -1.5], [-1.5, 2.5]]


def run(v, W, e, mu):
    v = np.asarray(v, dtype=np.float64)
    W = np.asarray(W, dtype=np.float64)
    params = np.zeros(N_PARAMS)
    params[P_E] = e
    params[P_MU] = mu
    P = np.full(v.shape[0], np.nan)
    mode = smith(v, W, params, P)
    return int(mode), P, v + W @ P


# ---- independent reference: the residual written directly from the law -----------------------
def residual(b, v, W, e, mu):
    """F(b) = v_T + W_TN P_N + W_TT P_T - b with P_N(b), P_T(b) from Smith's formula."""
    a = np.atleast_1d(v[1:]).astype(float)
    b = np.atleast_1d(b).astype(float)
    na, nb = np.linalg.norm(a), np.linalg.norm(b)
    g = (na * a + nb * b) / (na ** 2 + nb ** 2)
    D = W[0, 0] - mu * W[0, 1:] @ g
    PN = -(1 + e) * v[0] / D
    PT = -mu * PN * g
    return a + W[1:, 0] * PN + W[1:, 1:] @ PT - b, PN, D


def ref_2d(v, W, e, mu, n=2001):
    """All physical roots (P_N > 0) by a dense scan of F over |b| <= energy bound."""
    K = v @ np.linalg.solve(W, v)
    bnd = 1.01 * math.sqrt(K * W[1, 1]) + 1e-9
    a, c = v[1], -(1 + e) * v[0]

    def Dof(b):
        g = (abs(a) * a + np.abs(b) * b) / (a * a + b * b)
        return W[0, 0] - mu * W[0, 1] * g

    bs = np.linspace(-bnd, bnd, n)
    # refine the grid geometrically around b = 0 (scale |a|) and around the pole D = 0
    near = np.geomspace(1e-12, 1.0, 300)
    extra = [abs(a) * near * s for s in (-100, 100)]
    D = Dof(bs)
    for i in np.flatnonzero(D[:-1] * D[1:] < 0):
        bp = brentq(Dof, bs[i], bs[i + 1], xtol=1e-16, rtol=1e-15)
        extra += [bp + bnd * near, bp - bnd * near]
    bs = np.unique(np.concatenate([bs] + extra))
    bs = bs[np.abs(bs) <= bnd]
    n = bs.size
    g = (abs(a) * a + np.abs(bs) * bs) / (a * a + bs * bs)
    D = W[0, 0] - mu * W[0, 1] * g
    F = a + c * (W[1, 0] - mu * W[1, 1] * g) / D - bs
    roots = []
    for i in range(n - 1):
        if D[i] > 0 and D[i + 1] > 0 and F[i] * F[i + 1] <= 0:
            b = brentq(lambda x: residual(x, v, W, e, mu)[0][0], bs[i], bs[i + 1],
                       xtol=1e-15, rtol=1e-15)
            if residual(b, v, W, e, mu)[1] > 0:
                roots.append(b)
    return roots


def ref_3d(v, W, e, mu):
    """Physical roots found by fsolve from many starts; returns (roots, P_Ns)."""
    K = v @ np.linalg.solve(W, v)
    bnd = math.sqrt(K * np.linalg.eigvalsh(W[1:, 1:]).max())
    a, c = v[1:], -(1 + e) * v[0]
    grid = np.linspace(-bnd, bnd, 3)
    starts = [a, a + c * W[1:, 0] / W[0, 0], -a, np.zeros(2) + 1e-3 * a]
    starts += [np.array([x, y]) for x in grid for y in grid]
    roots, pns = [], []
    for b0 in starts:
        if not residual(b0, v, W, e, mu)[2] > 0:
            continue
        b, info, ier, msg = fsolve(lambda x: residual(x, v, W, e, mu)[0], b0, xtol=1e-13,
                                   full_output=True)
        r, PN, D = residual(b, v, W, e, mu)
        if np.linalg.norm(r) < 1e-10 * (1 + np.linalg.norm(v)) and PN > 0:
            if all(np.linalg.norm(b - q) > 1e-7 * (1 + np.linalg.norm(b)) for q in roots):
                roots.append(b)
                pns.append(PN)
    return roots, pns


def random_spd(rng, d, cond_max=1e3):
    while True:
        L = rng.normal(size=(d, d))
        W = L @ L.T + 0.05 * np.eye(d)
        if np.linalg.cond(W) < cond_max:
            return W * math.exp(rng.uniform(-2, 2))


def random_v(rng, d):
    v = rng.normal(size=d) * math.exp(rng.uniform(-3, 3))
    v[0] = -abs(v[0])
    return v


# ---- DESIGN §5 reference cases ----------------------------------------------------------------
def test_rod_case_1a():
    mode, P, vf = run([-1, 0], ROD, 0.5, 0.3)
    assert mode == MODE_SLIP         # v_T = 0 and no stable stick (mu < 0.6): slides
    assert P == pytest.approx([0.731707, 0.219512], abs=1e-6)
    assert vf == pytest.approx([0.5, -0.548780], abs=1e-6)
    assert 0.5 * P @ ([-1, 0] + vf) == pytest.approx(-0.243159, abs=1e-6)


def test_rod_case_1a_prime_sticks_at_zero_slip():
    # a = 0 and |W_TN| <= mu W_TT: the set-valued case sticks, like K&L / Routh (DESIGN §5 1a')
    mode, P, vf = run([-1, 0], ROD, 0.5, 0.8)
    assert mode == MODE_STICK
    assert P == pytest.approx([0.9375, 0.5625], abs=1e-12)
    assert vf == pytest.approx([0.5, 0.0], abs=1e-12)


def test_rod_case_1b():
    mode, P, vf = run([-1, 1], ROD, 1.0, 0.3)
    assert mode == MODE_SLIP
    assert vf == pytest.approx([1.0, -0.433678], abs=1e-6)


@pytest.mark.parametrize("d", [2, 3])
@pytest.mark.parametrize("mu, P_ref, vfT", [(0.1, (1.5, -0.15), 0.475),
                                             (0.5, None, -0.517160)])
def test_sphere(d, mu, P_ref, vfT):
    W = np.diag([1.0, 3.5, 3.5][:d])
    v = [-1.0, 1.0, 0.0][:d]
    mode, P, vf = run(v, W, 0.5, mu)
    assert mode == MODE_SLIP
    assert vf[1] == pytest.approx(vfT, abs=1e-6)
    assert vf[0] == pytest.approx(0.5, abs=1e-12)
    if P_ref is not None:
        assert P[:2] == pytest.approx(P_ref, abs=1e-6)
    if d == 3:
        assert abs(P[2]) < 1e-15 and abs(vf[2]) < 1e-15


def test_swerve_case_is_a_root():
    # DESIGN §5 3D swerve input: Smith's result satisfies its own equations
    v, W = np.array([-4.0, -2.0, 1.0]), np.array([[5, 1, -1], [1, 8, -2], [-1, -2, 3.0]])
    mode, P, vf = run(v, W, 0.2, 0.2)
    assert mode == MODE_SLIP
    r, PN, D = residual(vf[1:], v, W, 0.2, 0.2)
    assert np.abs(r).max() < 1e-12 and PN == pytest.approx(P[0], rel=1e-12)


# ---- independent references -------------------------------------------------------------------
def test_2d_matches_dense_scan_reference():
    rng = np.random.default_rng(12345)
    worst = 0.0
    for i in range(300):
        W = random_spd(rng, 2, cond_max=1e4)
        v = random_v(rng, 2)
        e = rng.uniform()
        mu = [rng.uniform(0, 1), rng.uniform(0, 5), rng.uniform(0, 30)][i % 3]
        roots = ref_2d(v, W, e, mu)
        assert len(roots) == 1, (v, W, e, mu, roots)     # 2D: exactly one physical root
        mode, P, vf = run(v, W, e, mu)
        assert mode == MODE_SLIP
        err = abs(vf[1] - roots[0]) / np.linalg.norm(v)
        worst = max(worst, err)
        r, PN, D = residual(roots[0], v, W, e, mu)
        assert P[0] == pytest.approx(PN, rel=1e-8)
    assert worst < 1e-8


def test_3d_matches_multistart_reference():
    rng = np.random.default_rng(2024)
    n_cmp = 0
    for i in range(120):
        W = random_spd(rng, 3, cond_max=1e3)
        v = random_v(rng, 3)
        e = rng.uniform()
        mu = rng.uniform(0, 1.0) if i % 2 else rng.uniform(0, 3.0)
        roots, pns = ref_3d(v, W, e, mu)
        mode, P, vf = run(v, W, e, mu)
        assert mode == MODE_SLIP
        if not roots:
            continue
        n_cmp += 1
        b_ref = roots[int(np.argmin(pns))]
        scale = np.linalg.norm(v) + np.linalg.norm(b_ref)
        assert np.linalg.norm(vf[1:] - b_ref) < 1e-8 * scale, (v, W, e, mu, roots, pns, P)
        assert P[0] == pytest.approx(min(pns), rel=1e-8)
    assert n_cmp >= 110


# Two 3D contacts with three physical roots each (found by an angle scan of the residual);
# the kernel must return the smallest P_N. Seeds are polished here with fsolve.
MULTI = [
    (np.array([-0.10472438829820227, -0.23214025952759257, -1.802141866893796]),
     np.array([[9.524309066376905, 3.1213710991200307, 0.5107975154729547],
               [3.1213710991200307, 3.5808821657084806, 1.5812498454720814],
               [0.5107975154729547, 1.5812498454720814, 0.8751961117256528]]),
     0.45926438315347073, 19.454806613825994,
     [(0.018396729943, -1.674725778750), (1.288367396986, -0.800801653688),
      (1.152144411488, 0.772244120250)]),
    (np.array([-0.01225184336812925, -0.848378760763195, 0.887109444953769]),
     np.array([[2.9692747544134774, -1.5261435165939103, -1.0804655920724733],
               [-1.5261435165939103, 0.9150182745954482, 1.142109713180128],
               [-1.0804655920724733, 1.142109713180128, 3.7869095423859234]]),
     0.8134766846030478, 4.223468025485072,
     [(-0.242111929844, -0.905442278202), (-0.879804696204, 0.755442344463),
      (-0.962985338419, 0.213225804182)]),
]


@pytest.mark.parametrize("case", range(len(MULTI)))
def test_3d_several_roots_takes_smallest_normal_impulse(case):
    v, W, e, mu, seeds = MULTI[case]
    roots, pns = [], []
    for s in seeds:
        b = fsolve(lambda x: residual(x, v, W, e, mu)[0], np.array(s), xtol=1e-13)
        r, PN, D = residual(b, v, W, e, mu)
        assert np.abs(r).max() < 1e-9 and PN > 0        # three distinct physical roots
        roots.append(b)
        pns.append(PN)
    assert min(np.linalg.norm(roots[i] - roots[j]) for i in range(3) for j in range(i)) > 0.1
    assert not _unique_certificate(W[0, 0], W[0, 1], W[0, 2], W[1, 1], W[1, 2], W[2, 2], mu)
    mode, P, vf = run(v, W, e, mu)
    assert mode == MODE_SLIP
    k = int(np.argmin(pns))
    assert np.linalg.norm(vf[1:] - roots[k]) < 1e-9
    assert P[0] == pytest.approx(pns[k], rel=1e-9)


def test_uniqueness_certificate_against_direction_scan():
    # certificate: d^T S d > mu |d . T J w| for all unit d (S = Wnn T - w w^T)
    rng = np.random.default_rng(7)
    phis = np.linspace(0, np.pi, 4001)
    Z = np.stack([np.cos(phis), np.sin(phis)])
    for i in range(300):
        W = random_spd(rng, 3)
        mu = rng.uniform(0, 2)
        Wnn, w, T = W[0, 0], W[0, 1:], W[1:, 1:]
        S = Wnn * T - np.outer(w, w)
        x = T @ np.array([w[1], -w[0]])
        margin = np.min(np.einsum('in,ij,jn->n', Z, S, Z) - mu * np.abs(x @ Z)) / np.trace(S)
        cert = _unique_certificate(Wnn, w[0], w[1], T[0, 0], T[0, 1], T[1, 1], mu)
        if margin < -1e-6:
            assert not cert                      # never certifies a case it must not
        if margin > 1e-3:
            assert cert                          # and is not needlessly conservative


# ---- properties (hypothesis) ------------------------------------------------------------------
finite = st.floats(-10, 10, allow_nan=False, allow_infinity=False)


@st.composite
def contacts(draw, d):
    L = np.array([[draw(finite) for j in range(d)] for i in range(d)])
    W = L @ L.T + draw(st.floats(1e-3, 3)) * np.eye(d)
    v = np.array([draw(finite) for i in range(d)])
    v[0] = -abs(v[0]) - draw(st.floats(1e-6, 1))
    e = draw(st.floats(0, 1))
    mu = draw(st.floats(0, 3))
    return v, W, e, mu


def check_physics(v, W, e, mu):
    mode, P, vf = run(v, W, e, mu)
    assert mode in (MODE_SLIP, MODE_STICK)
    assert np.all(np.isfinite(P)) and P[0] > 0
    assert abs(vf[0] + e * v[0]) <= 1e-12 * (abs(v[0]) + np.abs(W).max() * np.abs(P).sum())
    assert math.hypot(*P[1:]) <= mu * P[0] * (1 + 1e-12)   # (hypot: no subnormal loss)
    dE = 0.5 * P @ (v + vf)
    scale = np.abs(P) @ np.abs(v) + np.abs(P) @ np.abs(W) @ np.abs(P)
    assert dE <= 1e-12 * scale
    return mode, P, vf


def tolerance(v, W, e, mu, P):
    """Relative agreement to expect between two exact-in-theory evaluations: 1e-9, plus an
    allowance for the conditioning of P_N = c / D (D = W_NN - mu W_NT.g loses
    (W_NN + mu |W_NT|) / D digits by cancellation near the pole of grazing contacts)."""
    kappa = (W[0, 0] + mu * np.linalg.norm(W[0, 1:])) * P[0] / (-(1 + e) * v[0])
    return 1e-9 + 1e-13 * kappa


@settings(max_examples=150, deadline=None)
@given(contacts(2))
def test_2d_properties(c):
    check_physics(*c)


@settings(max_examples=150, deadline=None)
@given(contacts(3))
def test_3d_properties(c):
    check_physics(*c)


@settings(max_examples=100, deadline=None)
@given(contacts(3), st.floats(0, 2 * math.pi))
def test_3d_tangent_rotation_invariance(c, theta):
    v, W, e, mu = c
    R = np.eye(3)
    R[1:, 1:] = [[math.cos(theta), -math.sin(theta)], [math.sin(theta), math.cos(theta)]]
    m1, P1, vf1 = run(v, W, e, mu)
    m2, P2, vf2 = run(R @ v, R @ W @ R.T, e, mu)
    assert m1 == m2
    assert np.linalg.norm(P2 - R @ P1) <= tolerance(v, W, e, mu, P1) * np.linalg.norm(P1)


@settings(max_examples=100, deadline=None)
@given(contacts(2), st.floats(0.01, 10))
def test_3d_reproduces_2d_for_planar_motion(c, w33):
    v, W, e, mu = c
    W3 = np.zeros((3, 3))
    W3[:2, :2] = W
    W3[2, 2] = w33
    m2, P2, vf2 = run(v, W, e, mu)
    m3, P3, vf3 = run(np.r_[v, 0.0], W3, e, mu)
    assert m2 == m3
    assert P3[2] == 0.0
    assert np.abs(P3[:2] - P2).max() <= tolerance(v, W, e, mu, P2) * np.abs(P2).max()


@settings(max_examples=100, deadline=None)
@given(contacts(2), st.floats(0.01, 10), st.floats(0.1, 6.0))
def test_3d_reproduces_2d_for_planar_motion_in_a_rotated_basis(c, w33, theta):
    # same planar contact seen in a rotated tangent basis: exercises the general 3D solver
    v, W, e, mu = c
    W3 = np.zeros((3, 3))
    W3[:2, :2] = W
    W3[2, 2] = w33
    R = np.eye(3)
    R[1:, 1:] = [[math.cos(theta), -math.sin(theta)], [math.sin(theta), math.cos(theta)]]
    m2, P2, vf2 = run(v, W, e, mu)
    m3, P3, vf3 = run(R @ np.r_[v, 0.0], R @ W3 @ R.T, e, mu)
    assert m2 == m3
    tol = tolerance(v, W, e, mu, P2)
    assert np.abs(R.T @ P3 - np.r_[P2, 0.0]).max() <= tol * np.abs(P2).max()


# ---- set-valued a = 0, tiny slip, modes -------------------------------------------------------
@pytest.mark.parametrize("Wnt, mu, expect", [(-1.5, 0.8, MODE_STICK), (-1.5, 0.3, MODE_SLIP),
                                             (1.5, 0.3, MODE_SLIP), (0.0, 0.3, MODE_STICK)])
def test_2d_zero_slip_is_coulomb_inclusion(Wnt, mu, expect):
    W = np.array([[2.5, Wnt], [Wnt, 2.5]])
    mode, P, vf = run([-1.0, 0.0], W, 0.5, mu)
    assert (mode == MODE_STICK) == (expect == MODE_STICK)
    assert vf[0] == pytest.approx(0.5, abs=1e-14)
    if expect == MODE_STICK:
        assert vf[1] == 0.0 and abs(P[1]) <= mu * P[0]
    else:   # slides along the direction the normal impulse drives, friction opposite
        assert np.sign(vf[1]) == np.sign(Wnt) and P[1] == pytest.approx(-mu * P[0] * np.sign(Wnt))
    for a in (5e-324, 1e-310, 1e-200, -1e-40):   # tiny / subnormal slip: the same (limit)
        m2, P2, vf2 = run([-1.0, a], W, 0.5, mu)
        assert m2 == mode and np.all(np.isfinite(P2))
        assert P2 == pytest.approx(P, rel=1e-12, abs=1e-300)
    for a in (1e-9, -1e-9):                       # continuous: small slip is close
        m2, P2, vf2 = run([-1.0, a], W, 0.5, mu)
        assert m2 == MODE_SLIP and np.abs(P2 - P).max() < 1e-4


@pytest.mark.parametrize("mu", [0.1, 0.3, 2.0])
def test_3d_zero_slip(mu):
    W = np.array([[2.0, 0.6, -0.4], [0.6, 1.5, 0.2], [-0.4, 0.2, 1.0]])
    v = np.array([-1.0, 0.0, 0.0])
    mode, P, vf = run(v, W, 0.3, mu)
    y = np.linalg.solve(W[1:, 1:], W[1:, 0])
    assert (mode == MODE_STICK) == (np.linalg.norm(y) <= mu)
    assert vf[0] == pytest.approx(0.3, abs=1e-14)
    if mode == MODE_STICK:
        assert np.abs(vf[1:]).max() < 1e-15 and np.linalg.norm(P[1:]) <= mu * P[0]
    else:   # Coulomb along the final slip
        u = vf[1:] / np.linalg.norm(vf[1:])
        assert P[1:] == pytest.approx(-mu * P[0] * u, abs=1e-12)
    for a in ([5e-324, 0.0], [1e-200, -3e-201], [0.0, -1e-35]):
        m2, P2, vf2 = run(np.r_[-1.0, a], W, 0.3, mu)
        assert m2 == mode and P2 == pytest.approx(P, rel=1e-12, abs=1e-300)
    m2, P2, vf2 = run([-1.0, 1e-9, 2e-9], W, 0.3, mu)   # continuity
    assert np.abs(P2 - P).max() < 1e-4


def test_modes_and_failures():
    params = np.zeros(N_PARAMS)
    params[P_E], params[P_MU] = 0.5, 0.3
    for v, W in (([0.0, 1.0], ROD), ([1.0, -2.0, 0.5], np.eye(3))):
        mode, P, vf = run(v, W, 0.5, 0.3)
        assert mode == MODE_SEPARATING and not P.any()
    mode, P, vf = run([-2.0, 1.0], ROD, 0.5, 0.0)
    assert mode == MODE_SLIP and P == pytest.approx([3.0 / 2.5, 0.0])
    bad = [([-1.0, 0.3], [[1.0, 2.0], [2.0, 1.0]]),          # not positive definite
           ([-1.0, np.nan], ROD), ([-np.inf, 0.1], ROD),
           ([-1.0, 0.3, 0.1], [[1, 0, 0], [0, 1, 2.0], [0, 2.0, 1]]),
           ([-1.0, 0.3, np.inf], np.eye(3))]
    for v, W in bad:
        mode, P, vf = run(v, W, 0.5, 0.3)
        assert mode == MODE_NO_SOLUTION and not P.any() and not np.isnan(P).any()
    mode, P, vf = run([-1.0, 0.3], ROD, 0.5, -0.1)
    assert mode == MODE_NO_SOLUTION and not P.any()
    # the 2D/3D entry points are the dispatcher's
    P2 = np.zeros(2)
    assert smith_2d(np.array([-1.0, 0.0]), np.array(ROD), params, P2) == MODE_SLIP
    P3 = np.zeros(3)
    assert smith_3d(np.array([-1.0, 1.0, 0.0]), np.diag([1.0, 3.5, 3.5]), params, P3) == MODE_SLIP


def test_friction_opposes_sliding_and_never_truly_sticks():
    # the seed's sign error would push along the slip: check P_T opposes a when b and a agree
    mode, P, vf = run([-1.0, 2.0], np.diag([1.0, 3.5]), 0.5, 0.1)
    assert P[1] < 0 < vf[1] < 2.0
    # as mu grows the final slip tends to -a (never exactly 0)
    prev = None
    for mu in (1.0, 10.0, 100.0, 1e4):
        mode, P, vf = run([-1.0, 1.0], np.diag([1.0, 3.5]), 0.5, mu)
        assert mode == MODE_SLIP and vf[1] < 0
        if prev is not None:
            assert abs(vf[1] + 1.0) < abs(prev + 1.0)
        prev = vf[1]
    assert abs(prev + 1.0) < 1e-3
