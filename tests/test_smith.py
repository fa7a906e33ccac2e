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


# ================================================================================================
# Stability regressions (issue 6): compared with exact rational or 100-digit decimal references
# ================================================================================================
from decimal import Decimal, localcontext  # noqa: E402
from fractions import Fraction  # noqa: E402

from rbimpact.kernels.smith import smith_2d_scalar, smith_3d_scalar  # noqa: E402


def _dec_2d(v, W, e, mu, digits=100, iters=500):
    """Smith 2D in 100-digit decimal arithmetic: bisection on b = v_fT over the physical
    interval (D > 0), where F(b) = a + c N(g)/D(g) - b is strictly decreasing (DESIGN §4);
    the interval ends at the pole b_p of P_N when |W_NN / (mu W_NT)| < 1."""
    with localcontext() as ctx:
        ctx.prec = digits
        vn, a = Decimal(v[0]), Decimal(v[1])
        Wnn, Wnt, Wtt = Decimal(W[0][0]), Decimal(W[0][1]), Decimal(W[1][1])
        e, mu = Decimal(e), Decimal(mu)
        sg = -1 if a < 0 else 1
        a, Wnt = sg * a, sg * Wnt
        c = -(1 + e) * vn

        def g(b):
            return (a * a + abs(b) * b) / (a * a + b * b)

        def F(b):
            gg = g(b)
            D = Wnn - mu * Wnt * gg
            assert D > 0
            return a + c * (Wnt - mu * Wtt * gg) / D - b
        lo = hi = None
        if Wnt != 0:
            gp = Wnn / (mu * Wnt)
            if -1 < gp < 1:
                bp = -a * ((1 - gp) / (1 + gp)).sqrt()
                if Wnt > 0:
                    hi = bp
                else:
                    lo = bp
        if hi is None:
            hi = abs(a) + 1 if lo is None else abs(lo) + abs(a) + 1
            while F(hi) > 0:
                hi *= 2
        if lo is None:
            lo = -(abs(hi) + abs(a) + 1)
            while F(lo) < 0:
                lo *= 2
        for _ in range(iters):
            m = (lo + hi) / 2
            if F(m) > 0:
                lo = m
            else:
                hi = m
        gg = g((lo + hi) / 2)
        PN = c / (Wnn - mu * Wnt * gg)
        return np.array([float(PN), float(-sg * mu * PN * gg)])


def _exact_dE(v, W, P):
    """dE = P.v + P.W.P / 2 in rational arithmetic from the floats."""
    Pf = [Fraction(x) for x in P]
    q = sum(Pf[i] * Fraction(W[i][j]) * Pf[j] for i in range(len(P)) for j in range(len(P)))
    return sum(Pf[i] * Fraction(v[i]) for i in range(len(P))) + q / 2


def _rational_stick(v, W, e):
    """The stick impulse W^-1 ((-e v_N, 0, ..) - v), solved exactly in rationals."""
    d = len(v)
    A = [[Fraction(W[i][j]) for j in range(d)] + [Fraction(-e * v[0] if i == 0 else 0.0)
                                                  - Fraction(v[i])] for i in range(d)]
    for k in range(d):                       # Gauss-Jordan, exact
        p = next(r for r in range(k, d) if A[r][k] != 0)
        A[k], A[p] = A[p], A[k]
        for r in range(d):
            if r != k:
                f = A[r][k] / A[k][k]
                A[r] = [x - f * y for x, y in zip(A[r], A[k])]
    return np.array([float(A[i][d] / A[i][i]) for i in range(d)])


def _smith2(v, W, e, mu):
    return smith_2d_scalar(v[0], v[1], W[0][0], W[0][1], W[1][1], e, mu)


def _smith3(v, W, e, mu):
    return smith_3d_scalar(v[0], v[1], v[2], W[0][0], W[0][1], W[0][2], W[1][1], W[1][2],
                           W[2][2], e, mu)


def test_2d_root_next_to_pole_matches_decimal():
    """Near-singular W (det 4.6e-11): the root lies 1.2e-17 above the pole of P_N(b) (exact
    P_N = 8.197e9). It used to return NOT_CONVERGED; solved in D it is exact to round-off."""
    v = [-3.517878566115149e-09, -2.2180756715305785]
    W = [[0.008713034641120995, -0.0929360942974978],
         [-0.0929360942974978, 0.9912869654044664]]
    e, mu = 0.449490114439265, 0.4587491405715202
    mode, PN, PT = _smith2(v, W, e, mu)
    ref = _dec_2d(v, W, e, mu)
    assert mode == MODE_SLIP
    assert abs(ref[0] - 8.197147140590180e9) < 1e-6 * ref[0]
    assert np.abs(np.array([PN, PT]) - ref).max() <= 1e-13 * np.abs(ref).max()
    assert _exact_dE(v, W, [PN, PT]) <= 0


def test_2d_near_singular_and_pole_cases_match_decimal():
    """Random near-singular W (cond up to 1e14), weak impacts and large slips, mu over seven
    decades: every case converges (the 2D kernel documents a solution for every SPD W) and
    agrees with the 100-digit reference to 1e-13 relative (before: NOT_CONVERGED on ~5% of
    these, at the pole of P_N)."""
    rng = np.random.default_rng(11)
    worst = 0.0
    for _ in range(40):
        th = rng.uniform(0, math.pi)
        Q = np.array([[math.cos(th), -math.sin(th)], [math.sin(th), math.cos(th)]])
        W = (Q * np.array([1.0, 10 ** rng.uniform(-14, 0)])) @ Q.T
        W = 0.5 * (W + W.T)
        if not W[1, 1] - W[0, 1] * (W[0, 1] / W[0, 0]) > 0:
            continue
        v = [-10 ** rng.uniform(-12, 2), rng.choice([-1, 1]) * 10 ** rng.uniform(-3, 3)]
        e, mu = rng.uniform(), 10 ** rng.uniform(-3, 4)
        mode, PN, PT = _smith2(v, W.tolist(), e, mu)
        assert mode == MODE_SLIP, (v, W.tolist(), e, mu)
        ref = _dec_2d(v, W.tolist(), e, mu)
        worst = max(worst, np.abs(np.array([PN, PT]) - ref).max() / np.abs(ref).max())
    assert worst <= 1e-13


@pytest.mark.parametrize("v, W, e, mu", [
    # the matrix's random 2D failure: a ~ 4e-113 |v_N| (set-valued), det W cancels
    ([-5418.9477068965925, -2.2406746946618817e-109],
     [[0.04211320191922464, -0.014275656435246063],
      [-0.014275656435246063, 0.004839203797766421]], 1.0, 196826.55264126335),
    # 3D, cond 3.1e10: the Schur complement by Cramer's rule gave P_N = -983 N s
    ([-515.1831931990838, 1.4846866820938272e-93, 3.463512756076037e-196],
     [[3668340.860681912, -3624150.5111939665, -6954111.172863282],
      [-3624150.5111939665, 3580492.498268053, 6870339.078092478],
      [-6954111.172863282, 6870339.078092478, 13182979.459354883]], 1.0, 5176.209204024562),
    # 3D, cond 8e11 and 1e12 (stiff hypothesis property), elastic: c / schur3 was off by
    # 2.5e-12 and 2.7e-11 relative, an energy gain of 1e-11 and 1e-10 K0
    ([-30027032.982398365, 3.4471059823701624e-207, 0.0],
     [[0.15576229519142673, -0.29135751770525947, 0.21589626991086153],
      [-0.29135751770525947, 0.5449919896717814, -0.4038397178827082],
      [0.21589626991086153, -0.4038397178827082, 0.2992457153269424]], 1.0, 2.51188643150958),
    ([-819.7197766334237, 0.0, 0.0],
     [[0.274166886822623, 0.35156487371929757, -0.27459341681280397],
      [0.35156487371929757, 0.4508125028036599, -0.352111814180579],
      [-0.27459341681280397, -0.352111814180579, 0.27502061038115266]], 1.0,
     1.0000002744895709),
])
def test_set_valued_stick_near_singular_matches_rationals(v, W, e, mu):
    """a = 0 (below A_ZERO_REL) and |W_TT^-1 W_TN| <= mu: stick, P = W^-1 ((-e v_N, 0) - v).
    The compensated Schur complement (det W / det W_TT, 2D) or the refined compensated 3x3
    solve (3D) and the refined tangential solve give it to round-off against exact rational
    arithmetic, with P_N > 0 and no energy gain."""
    P = np.array((_smith2 if len(v) == 2 else _smith3)(v, W, e, mu)[1:])
    mode = (_smith2 if len(v) == 2 else _smith3)(v, W, e, mu)[0]
    ref = _rational_stick(v, W, e)
    assert mode == MODE_STICK
    assert P[0] > 0
    assert np.abs(P - ref).max() <= 1e-12 * np.abs(ref).max()
    scale = float(np.abs(P) @ (np.abs(v) + np.abs(np.asarray(v) + np.asarray(W) @ P))) / 2
    assert _exact_dE(v, W, P) <= 1e-12 * scale


def _dec_3d_root(v, W, e, mu, g0, digits=60, iters=60):
    """Smith 3D root in 60-digit decimal arithmetic: Newton on E(g) = g(a, b(g)) - g with
    b(g) = a + c N(g) / D(g) (finite-difference Jacobian), from g0. Returns P."""
    with localcontext() as ctx:
        ctx.prec = digits
        v = [Decimal(x) for x in v]
        W = [[Decimal(x) for x in r] for r in W]
        e, mu = Decimal(e), Decimal(mu)
        c = -(1 + e) * v[0]
        a = v[1:]
        na = (a[0] * a[0] + a[1] * a[1]).sqrt()

        def E(g):
            D = W[0][0] - mu * (W[0][1] * g[0] + W[0][2] * g[1])
            b = [a[i] + c * (W[0][i + 1] - mu * (W[i + 1][1] * g[0] + W[i + 1][2] * g[1])) / D
                 for i in range(2)]
            nb = (b[0] * b[0] + b[1] * b[1]).sqrt()
            Q = na * na + nb * nb
            return [(na * a[i] + nb * b[i]) / Q - g[i] for i in range(2)], D
        g = [Decimal(x) for x in g0]
        h = Decimal(10) ** -30
        for _ in range(iters):
            F, D = E(g)
            J = [[None, None], [None, None]]
            for j in range(2):
                gg = list(g)
                gg[j] += h
                Fj = E(gg)[0]
                for i in range(2):
                    J[i][j] = (Fj[i] - F[i]) / h
            det = J[0][0] * J[1][1] - J[0][1] * J[1][0]
            g = [g[0] - (J[1][1] * F[0] - J[0][1] * F[1]) / det,
                 g[1] - (J[0][0] * F[1] - J[1][0] * F[0]) / det]
        F, D = E(g)
        assert max(abs(F[0]), abs(F[1])) < Decimal(10) ** -40 and D > 0
        PN = c / D
        return np.array([float(PN), float(-mu * PN * g[0]), float(-mu * PN * g[1])])


@pytest.mark.parametrize("e, mu", [(1.0, 1e6), (0.5, 1e6), (0.0, 1e5), (1.0, 1e3)])
def test_3d_large_mu_near_stick_matches_decimal(e, mu):
    """Large mu: g ~ 1/mu, so g from b (|a| a + |b| b cancels, b ~ -a) had ~eps / |g|
    relative error and P_T = -mu P_N g was accurate only to ~mu 1e-14 (1.8e-9 at mu = 1e6).
    Polished in g itself, P is right to ~1e-16 against the 60-digit root."""
    v = [-4.0, -2.0, 1.0]
    W = [[5.0, 1.0, -1.0], [1.0, 8.0, -2.0], [-1.0, -2.0, 3.0]]
    mode, *P = _smith3(v, W, e, mu)
    P = np.array(P)
    assert mode == MODE_SLIP
    ref = _dec_3d_root(v, W, e, mu, -P[1:] / (mu * P[0]))
    assert np.abs(P - ref).max() <= 1e-14 * np.abs(ref).max()
    assert np.abs(P[1:] - ref[1:]).max() <= 1e-14 * np.abs(ref[1:]).max()


def _dec_set_valued_slip(v, W, e, mu, digits=60):
    """a = 0, slip: u with (s I + mu W_TT) u = W_TN, s > 0, |u| = 1 (bisection on s in 60-digit
    decimals), P_N = c / (W_NN - mu W_TN.u), P_T = -mu P_N u."""
    with localcontext() as ctx:
        ctx.prec = digits
        W = [[Decimal(x) for x in r] for r in W]
        mu = Decimal(mu)
        c = -(1 + Decimal(e)) * Decimal(v[0])
        w1, w2 = W[0][1], W[0][2]

        def u(s):
            a00, a01, a11 = s + mu * W[1][1], mu * W[1][2], s + mu * W[2][2]
            det = a00 * a11 - a01 * a01
            return (a11 * w1 - a01 * w2) / det, (a00 * w2 - a01 * w1) / det
        lo, hi = Decimal(0), Decimal(1)
        while sum(x * x for x in u(hi)) > 1:
            hi *= 2
        for _ in range(220):
            m = (lo + hi) / 2
            if sum(x * x for x in u(m)) > 1:
                lo = m
            else:
                hi = m
        u1, u2 = u((lo + hi) / 2)
        PN = c / (W[0][0] - mu * (w1 * u1 + w2 * u2))
        return np.array([float(PN), float(-mu * PN * u1), float(-mu * PN * u2)])


def test_3d_set_valued_slip_next_to_pole_matches_decimal():
    """a = 0 with slip, cond(W) = 2.6e10, D = 7.8e-9 << W_NN = 0.55: D = W_NN - mu w.u
    cancelled (P_N off by a factor 3 before). u from the unscaled, refined secular solve and
    D compensated for it: the impulse matches the 60-digit solution of the set-valued law to
    the problem's conditioning, and creates no energy."""
    v = [-7.051250018138865e-10, -1.4381654586267054e-159, 1.4914113280770005e-201]
    W = [[0.5489196268517875, -0.2946450659835369, -0.5562145832440545],
         [-0.2946450659835369, 0.15815743204449567, 0.2985608087508817],
         [-0.5562145832440545, 0.2985608087508817, 0.5636065004485512]]
    e, mu = 1.0, 3.439648360278264
    mode, *P = _smith3(v, W, e, mu)
    P = np.array(P)
    ref = _dec_set_valued_slip(v, W, e, mu)
    assert mode == MODE_SLIP
    # the problem itself amplifies the ~eps error of u by ~W_NN / D = 7e7 (before: 0.68)
    assert np.abs(P - ref).max() <= 1e-7 * np.abs(ref).max()
    scale = float(np.abs(P) @ (np.abs(v) + np.abs(np.asarray(v) + np.asarray(W) @ P))) / 2
    assert _exact_dE(v, W, P) <= 1e-12 * scale


# ---- tiny couplings, tiny mu, tiny slips, huge ratios (exponent range) --------------------------
def _embed(v, W, slot):
    """The planar 2D contact as a 3D one, its tangent in slot 1 or 2 (the other axis decoupled)."""
    i = 1 if slot == 1 else 2
    j = 3 - i
    v3 = np.zeros(3)
    W3 = np.zeros((3, 3))
    v3[0], v3[i] = v
    W3[0, 0], W3[0, i], W3[i, 0], W3[i, i] = W[0][0], W[0][1], W[1][0], W[1][1]
    W3[j, j] = 1.7 * W[1][1]
    return v3, W3, i


@pytest.mark.parametrize("Wnn, Wtt", [(1.0, 1.0), (100.0, 0.7), (0.3, 2.5)])
@pytest.mark.parametrize("wnt", [1.53594937e-195, -1e-310, 5e-323, -1e-100, 3e-8])
def test_zero_slip_with_tiny_coupling_and_tiny_mu(Wnn, Wtt, wnt):
    """a = 0 (or below A_ZERO_REL), tiny or subnormal W_TN and mu: the set-valued law decides
    slip iff |W_TN| > mu W_TT (decided here in exact rationals), then P_N = c / (W_NN - mu |W_TN|)
    and P_T = -mu P_N sign(W_TN), else stick (P = W^-1 ((-e v_N, 0) - v), exact rationals).
    3D (tangent in either slot) must reproduce 2D. Regression: hypothesis found W_TN = 1.5e-195,
    mu = 1.8e-219 -> NOT_CONVERGED in 3D (det(sigma I + mu T) ~ |W_TN|^2 underflowed to 0)."""
    e = 0.4
    SUB = 2e-323        # a subnormal P_T (mu ~ 5e-324) keeps only its last bits
    for mu in (1.8402233205268046e-219, 5e-324, 1e-300, 1e-30, 1e-9, 0.5):
        for a in (0.0, 5e-324, -1e-310):
            v = [-1.0, a]
            W = [[Wnn, wnt], [wnt, Wtt]]
            slip = abs(Fraction(wnt)) > Fraction(mu) * Fraction(Wtt)
            m2, PN, PT = _smith2(v, W, e, mu)
            P2 = np.array([PN, PT])
            if slip:
                assert m2 == MODE_SLIP, (mu, a)
                D = Wnn - mu * abs(wnt)
                assert PN == pytest.approx(1.4 / D, rel=1e-15)
                assert PT == pytest.approx(-mu * PN * np.sign(wnt), rel=1e-15, abs=SUB)
            else:
                assert m2 == MODE_STICK, (mu, a)
                ref = _rational_stick([-1.0, 0.0], W, e)
                assert np.abs(P2 - ref).max() <= 1e-15 * np.abs(ref).max()
                assert PT == pytest.approx(ref[1], rel=1e-14, abs=SUB)
            assert _exact_dE(v, W, P2) <= 0
            for slot in (1, 2):
                v3, W3, i = _embed(v, W, slot)
                m3, *P3 = _smith3(v3, W3, e, mu)
                P3 = np.array(P3)
                assert m3 == m2, (mu, a, slot)
                assert P3[3 - i] == 0.0
                assert P3[0] == pytest.approx(PN, rel=1e-15)
                assert P3[i] == pytest.approx(PT, rel=1e-14, abs=SUB)


@pytest.mark.parametrize("theta", [0.3, 2.0])
@pytest.mark.parametrize("a, wnt, Wtt, mu", [
    (4.161468365471424e-21, -6e-199, 1.5e-6, 1e8),      # b-root was noise: |v_fT| ~ 1e6 |a|
    (1e-29, -1e-97, 1.06e6, 1e100),                      # g off by 1e86: P_T = 2e52 N s
    (1e-29, -1e-8, 1.0, 1e8),                            # |a| below the reach of g: stick-like
    (1e-20, 0.3, 1.0, 1e6),
])
def test_tiny_slip_huge_mu_matches_2d_in_a_rotated_basis(theta, a, wnt, Wtt, mu):
    """Near stick with |a| far below eps c mu |W_TT| / D (the b-residual's round-off): the 3D
    kernel in a rotated tangent basis (general path) must reproduce the 2D law, keep
    v_fN = -e v_N, and create no energy (exact rationals)."""
    e = 0.0
    v, W = [-1.0, a], [[1.0, wnt], [wnt, Wtt]]
    m2, PN, PT = _smith2(v, W, e, mu)
    assert m2 == MODE_SLIP
    v3, W3, i = _embed(v, W, 1)
    R = np.eye(3)
    R[1:, 1:] = [[math.cos(theta), -math.sin(theta)], [math.sin(theta), math.cos(theta)]]
    v3, W3 = R @ v3, R @ W3 @ R.T
    m3, *P3 = _smith3(v3, W3, e, mu)
    P3 = np.array(P3)
    assert m3 == MODE_SLIP
    assert np.abs(R.T @ P3 - [PN, PT, 0.0]).max() <= 1e-12 * abs(PN)
    assert abs(P3[1:] @ R[1:, 1:] @ [1.0, 0.0] - PT) <= 1e-9 * abs(PT)
    assert abs(v3[0] + W3[0] @ P3) <= 1e-14
    assert _exact_dE(v3.tolist(), W3.tolist(), P3.tolist()) <= 0


@pytest.mark.parametrize("v, W, mu", [
    ([-1.0, 1e-29], [[1.0, -1e-8], [-1e-8, 1.0]], 1e100),
    ([-1.0, 1.0], [[1.0, 0.3], [0.3, 1.0]], 1e100),
    ([-1.0, 1.0], [[0.97, 0.291], [0.291, 0.97]], 1e100),
])
def test_2d_huge_mu_coupling_root_far_from_pole_matches_decimal(v, W, mu):
    """mu |W_NT| >= 1e92 W_NN: the pole of P_N lies within 1e-92 of g = 0 and t = -b/a of the
    root rounds to 1. The cubic's sign test at t(D = W_NN/64) picked the pole solver (P_N = 64,
    D at the bracket end, energy gain), and one polish step in g could not get below eps:
    P = (1, -0.0), (8e-71, +3.3) (friction along the slip) or NOT_CONVERGED. Decided by Phi(D)
    and polished in g to quadratic convergence, the root (g = -1e-108, 1.4e-100) matches a
    250-digit reference (and, for the second, the mu = 1e20 solution: only mu g matters)."""
    e = 0.0
    mode, PN, PT = _smith2(v, W, e, mu)
    assert mode == MODE_SLIP
    ref = _dec_2d(v, W, e, mu, digits=250, iters=900)
    assert PN == pytest.approx(ref[0], rel=1e-14)
    assert PT == pytest.approx(ref[1], rel=1e-12)
    assert _exact_dE(v, W, [PN, PT]) <= 0


@pytest.mark.parametrize("a, wnt, mu", [
    ((-95533648.9125606, -29552020.666133955), (-0.8598028402130454, -0.2659681859952056), 1e20),
    ((41614683.65471424, -90929742.68256816), (0.3744839700180553, -0.8183676841431135), 1e100),
    ((9.55336489125606e+29, 2.9552020666133957e+29), (286.6009467376818, 88.65606199840187), 5.0),
    ((-4.161468365471424e+29, 9.092974268256817e+29), (-0.1248, 0.2728), 1e8),
])
def test_weak_impact_huge_slip_is_never_silently_wrong(a, wnt, mu):
    """|a| = 1e8..1e30 |v_N| with mu |W_TN| >> W_NN (the roots lie within round-off of the
    pole of P_N): the kernel may report MODE_NOT_CONVERGED, but a returned impulse must satisfy
    the law's normal equation v_fN = -e v_N and the cone. (These returned P_N from the scan
    with an unphysical g: v_fN off by up to 1e16 m/s. The energy is not checked: next to the
    pole P carries ~eps W_NN / D relative error, and dE = P.v + P.W.P/2 cancels ~1e17 J.)"""
    T = [[1.0611325347816125, -0.1976248656882623], [-0.1976248656882623, 1.6388674652183872]]
    W = [[1.0, wnt[0], wnt[1]], [wnt[0]] + T[0], [wnt[1]] + T[1]]
    v = [-1.0, a[0], a[1]]
    for e in (0.0, 0.7):
        mode, *P = _smith3(v, W, e, mu)
        if mode < 0:
            assert P == [0.0, 0.0, 0.0]
            continue
        P = np.array(P)
        vf = np.array(v) + np.array(W) @ P
        assert abs(vf[0] - e) <= 1e-9 * (1 + np.abs(W).max() * np.abs(P).sum())
        assert math.hypot(P[1], P[2]) <= mu * P[0] * (1 + 1e-12)


def test_subnormal_mu_keeps_the_impulse_in_the_friction_cone():
    """mu = 5e-324 .. 1e-320: P_T = -mu P_N g is subnormal, where one ulp is a large relative
    error; |P_T| <= mu P_N (part of the law) must still hold (it failed for W_NN = 0.3:
    |P_T| = 2.8e-323 > mu P_N = 2.5e-323), and v_fN = -e v_N."""
    Ws = ([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[6, 0.5, 0.2], [0.5, 3, 0.1], [0.2, 0.1, 2]],
          [[0.3, 0.1, 0], [0.1, 0.7, 0.05], [0, 0.05, 0.9]])
    for W in Ws:
        for a in ((0.6, 0.8), (-0.3, 0.1), (1e-5, -2.0)):
            for mu in (5e-324, 1e-323, 2.5e-323, 1e-320):
                v = [-1.0, a[0], a[1]]
                mode, PN, P1, P2 = _smith3(v, W, 0.5, mu)
                assert mode == MODE_SLIP
                assert math.hypot(P1, P2) <= mu * PN * (1 + 1e-12), (W, a, mu)
                assert v[0] + np.array(W[0]) @ [PN, P1, P2] == pytest.approx(0.5, abs=1e-15)
    for W in Ws:                              # 2D likewise
        for mu in (5e-324, 1.5e-323):
            mode, PN, PT = _smith2([-1.0, 0.3], [[W[0][0], W[0][1]], [W[1][0], W[1][1]]], 0.5,
                                   mu)
            assert mode == MODE_SLIP and abs(PT) <= mu * PN


# ---- 3D roots next to the pole of P_N / ill-conditioned W (caller-frame polish) ---------------
# Found by the stability suite (random 3D cell and the stiff hypothesis property): cond(W) from
# 1e7 to 4e10, D = W_NN - mu W_TN.g down to 6e-9 W_NN. Before the (P_N, d) polish the returned
# impulse was off by up to a factor 7 (residuals 1e-10..0.4, energy gains up to 0.03 E).
POLE_CASES = [
    ([-1036.9590984213548, 0.08664642602372336, 7.02584433689821e-234],
     [[5373.253418896723, 2793.1580554897914, 12198.128893487266],
      [2793.1580554897914, 1451.956825583143, 6340.907357175057],
      [12198.128893487266, 6340.907357175057, 27691.66801277434]],
     0.8628907711700844, 5.364817111350297),
    ([-1.86593265617055e-07, 1.684824913961347e-31, 1.8932209560703653e-173],   # tiny slip,
     [[1.4245776344439076e-08, 7.409205277696231e-08, 2.3022842595604092e-07],   # elastic:
      [7.409205277696231e-08, 1.102274587873207e-06, 1.684322727435279e-06],     # energy
      [2.3022842595604092e-07, 1.684322727435279e-06, 4.05145169746513e-06]],    # gain
     1.0, 5077.359000789295),
    ([-1.7946853651000038e-07, 2.430299212587539e-10, -1.72862177826927e-172],
     [[2728.5611102326666, -291.75411905334454, -1261.442571199067],
      [-291.75411905334454, 31.196105866183366, 134.88100485538945],
      [-1261.442571199067, 134.88100485538945, 583.1782037498592]],
     0.7783405705509394, 14.799389162116015),
    ([-1.0, 1.0000002744895709, 1.0000002744895709],     # not a pole: cond(W_TT) 4e9, rotated
     [[96.88297739699654, -175.15987322394523, 4.71093874289355e-306],
      [-175.15987322394523, 337.4289444021446, -9.354909486215284e-306],
      [4.71093874289355e-306, -9.354909486215284e-306, 8.913063414739685e-08]],
     0.1916866597268006, 837261.2279182739),
    ([-3.1975564499771905e-09, 0.0, -1.0],
     [[0.43890633457042777, 0.1076531313745235, -0.4543323190980145],
      [0.1076531313745235, 0.4229239052146257, -0.19577273229458478],
      [-0.4543323190980145, -0.19577273229458478, 0.4882379708753924]],
     0.0, 1.0),
    ([-1.0, -1.0, 0.0],                                  # pole and near stick, mu = 4e5
     [[0.61890837500555, -0.366071705277992, -0.3191430790810067],
      [-0.366071705277992, 0.648356236096532, -0.306564730171005],
      [-0.3191430790810067, -0.306564730171005, 0.7327353889585233]],
     1.0186100959733191e-29, 435265.18523315864),
    ([-1.0, 1.0, 0.0],                                   # needs the Deuflhard damping
     [[0.5782228673107993, -0.26685384162682146, -0.4155360398331686],
      [-0.26685384162682146, 0.12315489697955574, 0.191772721390121],
      [-0.4155360398331686, 0.191772721390121, 0.29862231555535534]],
     0.6734427273539513, 201905.98445812342),
]


@pytest.mark.parametrize("v, W, e, mu", POLE_CASES)
def test_3d_pole_and_ill_conditioned_pass_the_stability_checks(v, W, e, mu):
    from rbimpact import stability as S
    ev = S.check_impact("smith", v, W, dict(e=e, mu=mu), iterations=False, timing=False)
    assert ev.status == "OK", ev.note


@pytest.mark.parametrize("case, P_ref", [
    (0, [58986509.60051163, -73101817.76310112, -9244412.178022297]),
    (2, [0.0309866783220492, 0.01329156037063231, 0.06395152616596453]),
])
def test_3d_pole_root_matches_high_precision_reference(case, P_ref):
    """P_ref: the root of R(p) = p D(g(b(p))) - c bisected in 90-digit decimal arithmetic
    (b(p) the unique tangential solution, itself bisected), rounded to float. The returned
    impulse was off by a factor 7 (case 0) and 3000 (case 2) before."""
    v, W, e, mu = POLE_CASES[case]
    mode, P, vf = run(v, W, e, mu)
    assert mode == MODE_SLIP
    assert np.linalg.norm(P - P_ref) <= 1e-13 * np.linalg.norm(P_ref)


# ---- 3D scan path: large normal impulses with an ill-conditioned W (stick-slope form of R) ----
# Found by the stiff hypothesis property (cond(W) 2e11..1e12, mu |W_TN| up to 3e5 W_NN, the
# root's D down to ~1e-12 W_NN): at p |W| >> |v| the tangential solution b(p) carries
# eps p (|W_TN| + mu |W_TT|), which the direct form p D(g(b)) - c of R amplified into a sign
# change far from the root. The kernel returned P_N off by factors 1e5..1e11 (residuals 3e-8
# to 2e-5). P_ref: the smallest root of R(p) = p D(g(b(p))) - c in 60-digit decimal arithmetic
# (b(p) bisected through the exact one-scalar reduction, R scanned at ratio 1.02 from
# c / (W_NN + mu |W_TN|) and bisected), rounded to float.
SCAN_CASES = [
    ([-2.6198794343694523e-08, -2.6198794343694523e-08, -2.0060844137333498e-49],
     [[1346851.4863439354, -2341198.894534239, 566463.3257130905],
      [-2341198.894534239, 4069648.5985751855, -984669.3012706386],
      [566463.3257130905, -984669.3012706386, 238245.04977564406]], 0.0, 4987.274025703433,
     [0.0018680294880167702, 0.0011480808472769998, 0.0003035100601101144]),
    ([-1.0, 3.548133892335755, 3.548133892335755],
     [[2203.3507487365873, 3016.1693803573025, -4156.85732361795],
      [3016.1693803573025, 4128.837742531347, -5690.3267832159345],
      [-4156.85732361795, -5690.3267832159345, 7842.356837443571]], 0.11804507014489832,
     163524.81808888202, [17224973.85715088, -96965833.49236104, -61227196.187470675]),
    ([-15.848931924611133, 7.162067144987e-287, 1.0],
     [[0.10894686325130573, 0.1619154612818725, 0.2661969713014989],
      [0.1619154612818725, 0.24063672712055145, 0.3956185990289939],
      [0.2661969713014989, 0.3956185990289939, 0.6504164100702393]], 0.7796221995157868,
     278191.0843308712, [18314813061943.895, -13376755112966.05, 640736217365.6709]),
    ([-0.27955779515183493, -3.9810717055349722, 0.0],
     [[372174.9043531996, 1227896.6198242796, 7325060.474943573],
      [1227896.6198242796, 4051133.202984648, 24167177.60140221],
      [7325060.474943573, 24167177.60140221, 144170148.0044357]], 0.0, 1000000.0,
     [1969.647574645879, 4939.538421486648, -928.0873450688837]),
    ([-7.405978001234067, 1.0000000000000004, -1.0],
     [[4.163721293731986e-09, 4.213224679656416e-09, -6.454611720317449e-09],
      [4.213224679656416e-09, 4.263316622233853e-09, -6.53135199971446e-09],
      [-6.454611720317449e-09, -6.53135199971446e-09, 1.000595609634068e-08]], 0.0,
     282144.26910738717, [7.388465644628184e+19, -5.148105055112977e+19, 1.4057218084208488e+19]),
    ([-0.0019630940798075745, 10.0, 10.0],
     [[222.00206879140822, 236.1114424541433, -0.681350772872417],
      [236.1114424541433, 251.11753946415817, -0.7246541200628812],
      [-0.681350772872417, -0.7246541200628812, 0.0020911470962906263]], 0.5508219615071318,
     4499.610633079292, [280347134.89105046, -380654257.7570105, -40565275699.68767]),
]


@pytest.mark.parametrize("v, W, e, mu, P_ref", SCAN_CASES)
def test_3d_scan_large_impulse_matches_high_precision_reference(v, W, e, mu, P_ref):
    """The scan evaluates R in its stick-slope form where that is the less sensitive to the
    round-off of b(p) (kernels.smith._stick_form): the smallest root is found, and the
    caller-frame polish brings P to round-off of the 60-digit root; the stability checks
    (residual, energy) pass."""
    from rbimpact import stability as S
    mode, P, vf = run(v, W, e, mu)
    assert mode == MODE_SLIP
    assert np.linalg.norm(P - P_ref) <= 1e-13 * np.linalg.norm(P_ref)
    ev = S.check_impact("smith", v, W, dict(e=e, mu=mu), iterations=False, timing=False)
    assert ev.status == "OK", ev.note
