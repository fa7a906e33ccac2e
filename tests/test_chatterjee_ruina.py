"""Chatterjee & Ruina kernels (kernels/chatterjee_ruina.py): DESIGN §5 reference cases,
the law's equations against an independent NumPy evaluation, no energy creation
(hypothesis), energy bookkeeping against rigid bodies, invariance, planar reduction.
Conventions: DESIGN.md §3 (normal first)."""
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from _impact_helpers import (EPS, ROD, SPHERE_2D, SPHERE_3D, SWERVE_V, SWERVE_W,
                             W_SPD_CANCELS, check_energy_identity, exact_dE, exact_minors,
                             ill_conditioned_spd, params, random_contact, rel_err, run,
                             tangent_rotation)
from rbimpact.kernels.chatterjee_ruina import (chatterjee_ruina, chatterjee_ruina_2d,
                                               chatterjee_ruina_2d_scalar,
                                               chatterjee_ruina_3d,
                                               chatterjee_ruina_3d_scalar)
from rbimpact.kernels.common import (MODE_NO_SOLUTION, MODE_SEPARATING, MODE_SLIP,
                                     MODE_STICK)

TOL = 1e-6


def embed(W2, w22=1.9):
    W = np.zeros((3, 3))
    W[:2, :2] = W2
    W[2, 2] = w22
    return W


# ---- DESIGN §5 reference cases -----------------------------------------------------------

CASES = [  # (name, W, v, e, mu, e_t, mode, P or None, v_f)
    ("rod 1a", ROD, [-1.0, 0.0], 0.5, 0.3, 0.0, MODE_SLIP, [0.731707, 0.219512],
     [0.5, -0.548780]),
    ("rod 1a'", ROD, [-1.0, 0.0], 0.5, 0.8, 0.0, MODE_STICK, None, [0.5, -0.3]),
    ("rod 1b", ROD, [-1.0, 1.0], 1.0, 0.3, 0.0, MODE_SLIP, None, [1.0, -0.525424]),
    ("sphere mu 0.1 e_t 1", SPHERE_2D, [-1.0, 1.0], 0.5, 0.1, 1.0, MODE_SLIP, [1.5, -0.15],
     [0.5, 0.475]),
    ("sphere mu 0.1 e_t 0", SPHERE_2D, [-1.0, 1.0], 0.5, 0.1, 0.0, MODE_SLIP, [1.5, -0.15],
     [0.5, 0.475]),
    ("superball mu 0.5 e_t 1", SPHERE_2D, [-1.0, 1.0], 0.5, 0.5, 1.0, MODE_STICK, None,
     [0.5, -1.0]),
]


@pytest.mark.parametrize("name,W,v,e,mu,et,mode,P,vf", CASES, ids=[c[0] for c in CASES])
def test_reference_cases_2d_and_3d(name, W, v, e, mu, et, mode, P, vf):
    m, P2, vf2, _ = run(chatterjee_ruina_2d, v, W, params(e, mu, et))
    assert m == mode
    np.testing.assert_allclose(vf2, vf, atol=TOL)
    if P is not None:
        np.testing.assert_allclose(P2, P, atol=TOL)
    W3 = SPHERE_3D if W is SPHERE_2D else embed(W)
    m3, P3, vf3, _ = run(chatterjee_ruina_3d, v + [0.0], W3, params(e, mu, et))
    assert m3 == mode
    np.testing.assert_allclose(P3, np.r_[P2, 0.0], atol=1e-12)
    np.testing.assert_allclose(vf3, vf + [0.0], atol=TOL)


def test_rod_case_1a_energy():
    _, _, _, dE = run(chatterjee_ruina_2d, [-1.0, 0.0], ROD, params(0.5, 0.3, 0.0))
    assert dE == pytest.approx(-0.243159, abs=TOL)


def test_swerve_contact_restitution_and_dissipation():
    m, P, vf, dE = run(chatterjee_ruina_3d, SWERVE_V, SWERVE_W, params(0.2, 0.2, 0.0))
    assert m >= 0
    assert vf[0] == pytest.approx(0.8, abs=1e-12)
    assert dE < 0.0


# ---- the law's equations against an independent evaluation -------------------------------

def _expected(v, W, e, mu, et):
    """DESIGN §4 evaluated literally: P_I, P_II = -W^-1 v, D = P_II - P_I, P^, clamp."""
    PI = np.zeros_like(v)
    PI[0] = -v[0] / W[0, 0]
    PII = -np.linalg.solve(W, v)
    D = PII - PI
    Ph = (1 + e) * PI + (1 + et) * D
    if np.linalg.norm(Ph[1:]) <= mu * Ph[0]:
        return MODE_STICK, Ph
    k = mu * (1 + e) * PI[0] / (np.linalg.norm(D[1:]) - mu * D[0])
    return MODE_SLIP, (1 + e) * PI + k * D


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("coupling", [1.0, 4.0])
def test_equations_against_independent_evaluation(dim, coupling):
    rng = np.random.default_rng(40 + dim)
    kernel = chatterjee_ruina_2d if dim == 2 else chatterjee_ruina_3d
    seen = set()
    for _ in range(500):
        v, W = random_contact(rng, dim, coupling)
        e, mu, et = rng.uniform(), rng.uniform(0.01, 3.0), rng.uniform(-1, 1)
        m, P, vf, _ = run(kernel, v, W, params(e, mu, et))
        m_ref, P_ref = _expected(v, W, e, mu, et)
        assert m == m_ref
        np.testing.assert_allclose(P, P_ref, rtol=1e-8, atol=1e-10 * np.abs(P_ref).max())
        assert vf[0] == pytest.approx(-e * v[0], abs=1e-10 * np.abs(v).max())
        assert np.linalg.norm(P[1:]) <= mu * P[0] * (1 + 1e-12)     # inside the cone
        if m == MODE_SLIP:
            assert np.linalg.norm(P[1:]) == pytest.approx(mu * P[0], rel=1e-12)
        seen.add(m)
    assert seen == {MODE_STICK, MODE_SLIP}


def test_tangential_restitution_minus_one_is_frictionless():
    rng = np.random.default_rng(43)
    for dim, kernel in ((2, chatterjee_ruina_2d), (3, chatterjee_ruina_3d)):
        for _ in range(100):
            v, W = random_contact(rng, dim, 3.0)
            e = rng.uniform()
            m, P, _, _ = run(kernel, v, W, params(e, rng.uniform(0.01, 2.0), -1.0))
            assert m == MODE_STICK
            np.testing.assert_allclose(P, np.r_[-(1 + e) * v[0] / W[0, 0], np.zeros(dim - 1)],
                                       rtol=1e-12, atol=1e-15)


# ---- never creates energy ----------------------------------------------------------------

_f = st.floats(-2.0, 2.0, allow_nan=False, allow_infinity=False)


def _energy_gain(dim, A, vals, e, et, mu):
    A = np.array(A).reshape(dim, dim)
    W = A @ A.T + 0.05 * np.eye(dim)
    v = np.array(vals)
    v[0] = -abs(v[0]) - 1e-3
    kernel = chatterjee_ruina_2d if dim == 2 else chatterjee_ruina_3d
    m, P, vf, dE = run(kernel, v, W, params(e, mu, et))
    assert m in (MODE_STICK, MODE_SLIP)
    E_avail = 0.5 * v @ np.linalg.solve(W, v)     # what a plastic sticking impact removes
    return dE, E_avail


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(A=st.lists(_f, min_size=4, max_size=4), vals=st.lists(_f, min_size=2, max_size=2),
       e=st.floats(0.0, 1.0), et=st.floats(-1.0, 1.0), mu=st.floats(0.0, 5.0))
def test_never_creates_energy_2d(A, vals, e, et, mu):
    dE, E_avail = _energy_gain(2, A, vals, e, et, mu)
    assert dE <= 1e-12 * E_avail
    assert dE >= -E_avail * (1 + 1e-12)              # and never removes more than plastic


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(A=st.lists(_f, min_size=9, max_size=9), vals=st.lists(_f, min_size=3, max_size=3),
       e=st.floats(0.0, 1.0), et=st.floats(-1.0, 1.0), mu=st.floats(0.0, 5.0))
def test_never_creates_energy_3d(A, vals, e, et, mu):
    dE, E_avail = _energy_gain(3, A, vals, e, et, mu)
    assert dE <= 1e-12 * E_avail
    assert dE >= -E_avail * (1 + 1e-12)


# ---- contract: separation, frictionless, dispatch, scalar twins, bad input ---------------

@pytest.mark.parametrize("kernel,d", [(chatterjee_ruina_2d, 2), (chatterjee_ruina_3d, 3),
                                      (chatterjee_ruina, 2), (chatterjee_ruina, 3)])
def test_separating_contact_gets_no_impulse(kernel, d):
    for vn in (0.0, 0.4):
        m, P, _, _ = run(kernel, np.r_[vn, np.ones(d - 1)], 2.0 * np.eye(d), params(0.5, 0.3, 0.5))
        assert m == MODE_SEPARATING and np.all(P == 0.0)


def test_frictionless_path_and_scalar_twins():
    rng = np.random.default_rng(44)
    for _ in range(100):
        e, et = rng.uniform(), rng.uniform(-1, 1)
        for d, kernel in ((2, chatterjee_ruina_2d), (3, chatterjee_ruina_3d)):
            v, W = random_contact(rng, d, 3.0)
            m, P, _, _ = run(kernel, v, W, params(e, 0.0, et))
            assert m == MODE_SLIP and np.all(P[1:] == 0.0)
            assert P[0] == pytest.approx(-(1 + e) * v[0] / W[0, 0], rel=1e-14)
        p = params(e, rng.uniform(0, 2), et)
        v, W = random_contact(rng, 2, 2.0)
        _, P, _, _ = run(chatterjee_ruina_2d, v, W, p)
        _, Pd, _, _ = run(chatterjee_ruina, v, W, p)
        _, pn, pt = chatterjee_ruina_2d_scalar(v[0], v[1], W[0, 0], W[0, 1], W[1, 1],
                                               p[0], p[1], p[2])
        assert np.array_equal(P, Pd) and np.array_equal(P, [pn, pt])
        v, W = random_contact(rng, 3, 2.0)
        _, P, _, _ = run(chatterjee_ruina_3d, v, W, p)
        _, Pd, _, _ = run(chatterjee_ruina, v, W, p)
        _, *Ps = chatterjee_ruina_3d_scalar(v[0], v[1], v[2], W[0, 0], W[0, 1], W[0, 2],
                                            W[1, 1], W[1, 2], W[2, 2], p[0], p[1], p[2])
        assert np.array_equal(P, Pd) and np.array_equal(P, Ps)


@pytest.mark.parametrize("v,W", [
    ([np.nan, 1.0], np.eye(2)), ([-1.0, np.nan], np.eye(2)), ([-np.inf, 1.0], np.eye(2)),
    ([-1.0, 1.0], [[1.0, 2.0], [2.0, 1.0]]), ([-1.0, 1.0], [[-1.0, 0.0], [0.0, -1.0]]),
    ([-1.0, 1.0], [[1.0, 1.0], [1.0, 1.0]]),
])
def test_bad_input_is_no_solution_never_nan(v, W):
    W2 = np.array(W, dtype=float)
    for kernel, vv, WW in ((chatterjee_ruina_2d, np.array(v, dtype=float), W2),
                           (chatterjee_ruina_3d, np.array(list(v) + [0.0]), embed(W2))):
        P = np.full(vv.shape[0], 123.0)
        assert kernel(vv, WW, params(0.5, 0.4, 0.3), P) == MODE_NO_SOLUTION
        assert np.all(P == 0.0)


# ---- invariance, planar reduction, energy bookkeeping ------------------------------------

def test_3d_invariant_under_rotation_of_tangent_basis():
    rng = np.random.default_rng(45)
    for _ in range(300):
        v, W = random_contact(rng, 3, 2.0)
        p = params(rng.uniform(), rng.uniform(0.05, 2.0), rng.uniform(-1, 1))
        R = tangent_rotation(rng.uniform(0, 2 * np.pi))
        m, P, _, _ = run(chatterjee_ruina_3d, v, W, p)
        mr, Pr, _, _ = run(chatterjee_ruina_3d, R @ v, R @ W @ R.T, p)
        assert mr == m
        np.testing.assert_allclose(Pr, R @ P, rtol=1e-9, atol=1e-11 * np.abs(P).max())


def test_3d_reproduces_2d_for_planar_motion():
    rng = np.random.default_rng(46)
    for _ in range(500):
        v, W2 = random_contact(rng, 2, rng.choice([1.0, 4.0]))
        p = params(rng.uniform(), rng.uniform(0.0, 3.0), rng.uniform(-1, 1))
        m2, P2, _, _ = run(chatterjee_ruina_2d, v, W2, p)
        m3, P3, _, _ = run(chatterjee_ruina_3d, np.r_[v, 0.0], embed(W2, rng.uniform(0.1, 3)), p)
        assert m3 == m2
        np.testing.assert_allclose(P3, np.r_[P2, 0.0], rtol=1e-12, atol=1e-14 * np.abs(P2).max())


@pytest.mark.parametrize("dim,kernel", [(2, chatterjee_ruina_2d), (3, chatterjee_ruina_3d)])
def test_energy_identity_with_rigid_bodies(dim, kernel):
    rng = np.random.default_rng(47 + dim)
    n = check_energy_identity(kernel, rng, dim, 200, (0.0, 1.0), 2.0, (-1.0, 1.0))
    assert n == 200


# ---- backward-stable solves (stability issue 6): regression against rational arithmetic ----

def _exact_cr(v, W, e, mu, et):
    """The law of the module docstring in rational arithmetic: (stick?, P as Fractions)."""
    from fractions import Fraction as F
    d = len(v)
    pi = -F(float(v[0])) / F(float(W[0][0]))
    vTI = [F(float(v[i])) + F(float(W[i][0])) * pi for i in range(1, d)]
    # D = -W^-1 (0, v_T^I), with the rational right-hand side
    A = [[F(float(W[i][j])) for j in range(d)] + [F(0) if i == 0 else -vTI[i - 1]]
         for i in range(d)]
    for k in range(d):
        for i in range(k + 1, d):
            m = A[i][k] / A[k][k]
            A[i] = [x - m * y for x, y in zip(A[i], A[k])]
    D = [F(0)] * d
    for k in reversed(range(d)):
        D[k] = (A[k][d] - sum(A[k][j] * D[j] for j in range(k + 1, d))) / A[k][k]
    base = (1 + F(e)) * pi
    k = 1 + F(et)
    Ph = [base + k * D[0]] + [k * x for x in D[1:]]
    nT = sum(float(x) ** 2 for x in Ph[1:]) ** 0.5
    if nT <= mu * float(Ph[0]):
        return True, Ph
    nD = sum(float(x) ** 2 for x in D[1:]) ** 0.5
    kk = F(mu) * base / (F(nD) - F(mu) * D[0])
    return False, [base + kk * D[0]] + [kk * x for x in D[1:]]


@pytest.mark.parametrize("dim", [2, 3])
def test_slip_on_the_cone_equals_the_papers_formula(dim):
    """The kernels place the slip impulse as P_T = mu P_N D_T/|D_T|, P_N = a/(W_NN + W_NT.r)
    (the tail shared with Brach): the same point as (1 + e) P_I + k D with
    k = mu (1 + e) P_I,N / (|D_T| - mu D_N), evaluated here in rational arithmetic."""
    rng = np.random.default_rng(11 + dim)
    kernel = chatterjee_ruina_2d if dim == 2 else chatterjee_ruina_3d
    n_slip = 0
    for _ in range(60):
        v, W = random_contact(rng, dim, coupling=float(rng.choice([0.3, 1.0, 3.0])))
        e, et, mu = rng.uniform(0, 1), rng.uniform(-1, 1), rng.uniform(0.01, 1.0)
        stick, ref = _exact_cr(v, W, e, mu, et)
        mode, P, _, _ = run(kernel, v, W, params(e, mu, et))
        assert mode == (MODE_STICK if stick else MODE_SLIP)
        assert rel_err(P, ref) <= 1e-13
        n_slip += not stick
    assert n_slip >= 10


@pytest.mark.parametrize("dim, log_cond", [(2, 8.0), (2, 14.0), (3, 8.0), (3, 12.0)])
def test_elastic_stick_conserves_energy_ill_conditioned(dim, log_cond):
    """e = e_t = 1 inside the cone reverses v (v_f = -v): dE = 0 in exact arithmetic and the
    computed P may not create more than round-off of energy (exact dE of the kernel's P) even
    for cond(W) up to 1e14 (2D) / 1e12 (3D) — the stability suite found 2e-6 E_scale."""
    rng = np.random.default_rng(int(log_cond) + 10 * dim)
    kernel = chatterjee_ruina_2d if dim == 2 else chatterjee_ruina_3d
    n_stick = 0
    for _ in range(40):
        W = ill_conditioned_spd(rng, dim, log_cond)
        v = rng.normal(size=dim) * 10.0 ** rng.uniform(-3, 3, size=dim)
        v[0] = -abs(v[0])
        mode, P, vf, _ = run(kernel, v, W, params(1.0, 1e12, 1.0))
        assert mode in (MODE_STICK, MODE_SLIP)     # slip where P^_N < 0
        n_stick += mode == MODE_STICK
        escale = 0.5 * float(np.sum(np.abs(P) * (np.abs(v) + np.abs(vf))))
        assert exact_dE(v, W, P) <= 16 * EPS * escale
    assert n_stick >= 10


def test_2d_stability_reproducer_energy():
    """Stability reproducer (random cell): dE/E_scale was +2e-6 with the Cramer D."""
    v = np.array([-5418.9477068965925, -2.2406746946618817e-109])
    W = np.array([[0.04211320191922464, -0.014275656435246063],
                  [-0.014275656435246063, 0.004839203797766421]])
    mode, P, vf, _ = run(chatterjee_ruina_2d, v, W, params(1.0, 196826.55264126335, 1.0))
    escale = 0.5 * float(np.sum(np.abs(P) * (np.abs(v) + np.abs(vf))))
    assert mode == MODE_STICK and exact_dE(v, W, P) <= 16 * EPS * escale


def test_3d_spd_with_cancelling_cofactor_determinant_is_accepted():
    """SPD W of cond 5.6e9 whose plain cofactor determinant is -7.9e-6 (used to raise
    NoSolutionError); the same W made indefinite is rejected."""
    v = np.array([-1036.9590984213548, 0.08664642602372336, 0.0])
    mode, P, vf, _ = run(chatterjee_ruina_3d, v, W_SPD_CANCELS, params(0.86, 5.36, 1.0))
    assert mode in (MODE_STICK, MODE_SLIP)
    escale = 0.5 * float(np.sum(np.abs(P) * (np.abs(v) + np.abs(vf))))
    assert exact_dE(v, W_SPD_CANCELS, P) <= 16 * EPS * escale
    Wb = W_SPD_CANCELS.copy()
    Wb[2, 2] -= 1e-3
    assert exact_minors(Wb)[2] < 0
    mode, P, _, _ = run(chatterjee_ruina_3d, v, Wb, params(0.86, 5.36, 1.0))
    assert mode == MODE_NO_SOLUTION and np.all(P == 0.0)
