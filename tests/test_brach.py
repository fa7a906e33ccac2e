"""Brach's impulse-ratio kernels (kernels/brach.py): DESIGN §5 reference cases, the law's
equations against an independent NumPy solve, equality with Kane & Levinson in 2D for
e_t = 0, perforation, energy bookkeeping against rigid bodies, invariance, planar
reduction. Conventions: DESIGN.md §3 (normal first)."""
import numpy as np
import pytest

from _impact_helpers import (EPS, ROD, SPHERE_2D, SPHERE_3D, W_COND_7E11, W_SPD_CANCELS,
                             W_THIN_ROD, check_energy_identity, exact_minors, exact_solve,
                             exact_vf, ill_conditioned_spd, params, random_contact, run,
                             tangent_rotation)
from rbimpact.kernels.brach import (brach, brach_2d, brach_2d_scalar, brach_3d,
                                    brach_3d_scalar)
from rbimpact.kernels.common import (MODE_NO_SOLUTION, MODE_SEPARATING, MODE_SLIP,
                                     MODE_STICK)
from rbimpact.kernels.kane_levinson import kane_levinson_2d

TOL = 1e-6


def embed(W2, w22=2.3):
    W = np.zeros((3, 3))
    W[:2, :2] = W2
    W[2, 2] = w22
    return W


# ---- DESIGN §5 reference cases (e_t = 0) -------------------------------------------------

CASES = [  # (name, W, v, e, mu, mode, P, v_f)
    ("rod 1a", ROD, [-1.0, 0.0], 0.5, 0.3, MODE_SLIP, [0.731707, 0.219512], [0.5, -0.548780]),
    ("rod 1a'", ROD, [-1.0, 0.0], 0.5, 0.8, MODE_STICK, [0.9375, 0.5625], [0.5, 0.0]),
    ("rod 1b", ROD, [-1.0, 1.0], 1.0, 0.3, MODE_STICK, [0.875, 0.125], [1.0, 0.0]),
    ("sphere mu 0.1", SPHERE_2D, [-1.0, 1.0], 0.5, 0.1, MODE_SLIP, [1.5, -0.15], [0.5, 0.475]),
    ("sphere mu 0.5", SPHERE_2D, [-1.0, 1.0], 0.5, 0.5, MODE_STICK, [1.5, -0.285714],
     [0.5, 0.0]),
]


@pytest.mark.parametrize("name,W,v,e,mu,mode,P,vf", CASES, ids=[c[0] for c in CASES])
def test_reference_cases_2d_and_3d(name, W, v, e, mu, mode, P, vf):
    m, P2, vf2, _ = run(brach_2d, v, W, params(e, mu, 0.0))
    assert m == mode
    np.testing.assert_allclose(P2, P, atol=TOL)
    np.testing.assert_allclose(vf2, vf, atol=TOL)
    W3 = SPHERE_3D if W is SPHERE_2D else embed(W)
    m3, P3, vf3, _ = run(brach_3d, v + [0.0], W3, params(e, mu, 0.0))
    assert m3 == mode
    np.testing.assert_allclose(P3, P + [0.0], atol=TOL)
    np.testing.assert_allclose(vf3, vf + [0.0], atol=TOL)


def test_rod_case_1a_energy():
    _, _, _, dE = run(brach_2d, [-1.0, 0.0], ROD, params(0.5, 0.3, 0.0))
    assert dE == pytest.approx(-0.243159, abs=TOL)


# ---- the law's equations against an independent solve -----------------------------------

def _expected(v, W, e, mu, et):
    """Brach's law written directly from DESIGN §4 with numpy.linalg.solve."""
    target = np.r_[-e * v[0], -et * v[1:]]
    Ps = np.linalg.solve(W, target - v)
    nT = np.linalg.norm(Ps[1:])
    if Ps[0] >= 0 and nT <= mu * Ps[0]:
        return MODE_STICK, Ps
    r = mu * Ps[1:] / nT                       # direction of P*_T (= sign of r0 if P*_N > 0)
    pn = -(1 + e) * v[0] / (W[0, 0] + W[0, 1:] @ r)
    return MODE_SLIP, np.r_[pn, r * pn]


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("coupling", [1.0, 4.0])
def test_equations_and_a_solution_always_exists(dim, coupling):
    rng = np.random.default_rng(20 + dim)
    kernel = brach_2d if dim == 2 else brach_3d
    seen = set()
    negative_target = 0
    for _ in range(600):
        v, W = random_contact(rng, dim, coupling)
        e, mu, et = rng.uniform(-1, 1), rng.uniform(0.01, 3.0), rng.uniform(-1, 1)
        m, P, vf, _ = run(kernel, v, W, params(e, mu, et))
        assert m in (MODE_STICK, MODE_SLIP)      # SPD W: never NO_SOLUTION (module docstring)
        m_ref, P_ref = _expected(v, W, e, mu, et)
        assert m == m_ref
        scale = np.abs(P_ref).max() + 1e-300
        np.testing.assert_allclose(P, P_ref, rtol=1e-9, atol=1e-12 * scale)
        assert vf[0] == pytest.approx(-e * v[0], abs=1e-10 * (abs(v[0]) + np.abs(vf).max()))
        assert P[0] >= 0.0
        if m == MODE_STICK:                       # target reached
            np.testing.assert_allclose(vf[1:], -et * v[1:], atol=1e-10 * np.abs(v).max())
        else:                                     # ratio clamped on the cone
            assert np.linalg.norm(P[1:]) == pytest.approx(mu * P[0], rel=1e-12, abs=1e-300)
        seen.add(m)
        target_pn = np.linalg.solve(W, np.r_[-e * v[0], -et * v[1:]] - v)[0]
        negative_target += target_pn < 0
    assert seen == {MODE_STICK, MODE_SLIP}
    assert negative_target > 0        # the P*_N < 0 branch was exercised


def test_2d_with_zero_tangential_restitution_equals_kane_levinson():
    rng = np.random.default_rng(23)
    modes = set()
    for k in range(1500):
        v, W = random_contact(rng, 2, coupling=(1.0, 3.0, 8.0)[k % 3])
        p = params(rng.uniform(), rng.uniform(0.0, 4.0), 0.0)
        m_b, P_b, _, _ = run(brach_2d, v, W, p)
        m_k, P_k, _, _ = run(kane_levinson_2d, v, W, p)
        assert m_b == m_k
        np.testing.assert_allclose(P_b, P_k, rtol=1e-13, atol=1e-15 * np.abs(P_k).max())
        modes.add(m_b)
    assert modes == {MODE_STICK, MODE_SLIP}


# ---- perforation (negative e) -----------------------------------------------------------

def test_perforation_keeps_the_sign_of_the_normal_velocity():
    rng = np.random.default_rng(24)
    for dim, kernel in ((2, brach_2d), (3, brach_3d)):
        for _ in range(200):
            v, W = random_contact(rng, dim)
            e = rng.uniform(-1.0, -0.01)
            m, P, vf, dE = run(kernel, v, W, params(e, 0.0, 0.0))
            assert m == MODE_SLIP
            assert vf[0] == pytest.approx(-e * v[0], rel=1e-12)
            assert vf[0] < 0.0                     # still moving into the barrier
            assert dE <= 1e-14                     # frictionless perforation loses energy
        # e = -1: the body goes through without any normal impulse
        v, W = random_contact(rng, dim)
        m, P, vf, _ = run(kernel, v, W, params(-1.0, 0.7, 0.0))
        assert m >= 0 and P[0] == 0.0


# ---- contract: separation, frictionless, dispatch, scalar twins, bad input ---------------

@pytest.mark.parametrize("kernel,d", [(brach_2d, 2), (brach_3d, 3), (brach, 2), (brach, 3)])
def test_separating_contact_gets_no_impulse(kernel, d):
    for vn in (0.0, 1.3):
        m, P, _, _ = run(kernel, np.r_[vn, np.ones(d - 1)], 2.0 * np.eye(d), params(0.5, 0.3, 0.2))
        assert m == MODE_SEPARATING and np.all(P == 0.0)


def test_frictionless_path_and_scalar_twins():
    rng = np.random.default_rng(25)
    for _ in range(100):
        e, et = rng.uniform(-1, 1), rng.uniform(-1, 1)
        for d, kernel in ((2, brach_2d), (3, brach_3d)):
            v, W = random_contact(rng, d, 3.0)
            m, P, _, _ = run(kernel, v, W, params(e, 0.0, et))
            assert m == MODE_SLIP and np.all(P[1:] == 0.0)
            assert P[0] == pytest.approx(-(1 + e) * v[0] / W[0, 0], rel=1e-14)
        p = params(e, rng.uniform(0, 2), et)
        v, W = random_contact(rng, 2, 2.0)
        _, P, _, _ = run(brach_2d, v, W, p)
        _, Pd, _, _ = run(brach, v, W, p)
        _, pn, pt = brach_2d_scalar(v[0], v[1], W[0, 0], W[0, 1], W[1, 1], p[0], p[1], p[2])
        assert np.array_equal(P, Pd) and np.array_equal(P, [pn, pt])
        v, W = random_contact(rng, 3, 2.0)
        _, P, _, _ = run(brach_3d, v, W, p)
        _, Pd, _, _ = run(brach, v, W, p)
        _, *Ps = brach_3d_scalar(v[0], v[1], v[2], W[0, 0], W[0, 1], W[0, 2], W[1, 1],
                                 W[1, 2], W[2, 2], p[0], p[1], p[2])
        assert np.array_equal(P, Pd) and np.array_equal(P, Ps)


@pytest.mark.parametrize("v,W", [
    ([np.nan, 1.0], np.eye(2)), ([-1.0, np.nan], np.eye(2)), ([-np.inf, 1.0], np.eye(2)),
    ([-1.0, 1.0], [[1.0, 2.0], [2.0, 1.0]]), ([-1.0, 1.0], [[-1.0, 0.0], [0.0, -1.0]]),
    ([-1.0, 1.0], [[1.0, 1.0], [1.0, 1.0]]),
])
def test_bad_input_is_no_solution_never_nan(v, W):
    W2 = np.array(W, dtype=float)
    for kernel, vv, WW in ((brach_2d, np.array(v, dtype=float), W2),
                           (brach_3d, np.array(list(v) + [0.0]), embed(W2))):
        P = np.full(vv.shape[0], 123.0)
        assert kernel(vv, WW, params(0.5, 0.4, 0.3), P) == MODE_NO_SOLUTION
        assert np.all(P == 0.0)


# ---- invariance, planar reduction, energy bookkeeping ------------------------------------

def test_3d_invariant_under_rotation_of_tangent_basis():
    rng = np.random.default_rng(26)
    for _ in range(300):
        v, W = random_contact(rng, 3, 2.0)
        p = params(rng.uniform(-1, 1), rng.uniform(0.05, 2.0), rng.uniform(-1, 1))
        R = tangent_rotation(rng.uniform(0, 2 * np.pi))
        m, P, _, _ = run(brach_3d, v, W, p)
        mr, Pr, _, _ = run(brach_3d, R @ v, R @ W @ R.T, p)
        assert mr == m
        np.testing.assert_allclose(Pr, R @ P, rtol=1e-9, atol=1e-11 * np.abs(P).max())


def test_3d_reproduces_2d_for_planar_motion():
    rng = np.random.default_rng(27)
    for _ in range(500):
        v, W2 = random_contact(rng, 2, rng.choice([1.0, 4.0]))
        p = params(rng.uniform(-1, 1), rng.uniform(0.0, 3.0), rng.uniform(-1, 1))
        m2, P2, _, _ = run(brach_2d, v, W2, p)
        m3, P3, _, _ = run(brach_3d, np.r_[v, 0.0], embed(W2, rng.uniform(0.1, 3)), p)
        assert m3 == m2
        np.testing.assert_allclose(P3, np.r_[P2, 0.0], rtol=1e-12, atol=1e-14 * np.abs(P2).max())


@pytest.mark.parametrize("dim,kernel", [(2, brach_2d), (3, brach_3d)])
def test_energy_identity_with_rigid_bodies(dim, kernel):
    rng = np.random.default_rng(28 + dim)
    assert check_energy_identity(kernel, rng, dim, 200, (-1.0, 1.0), 2.0, (-1.0, 1.0)) == 200


# ---- backward-stable solves (stability issue 6): regression against rational arithmetic ----

@pytest.mark.parametrize("et", [0.0, -0.5, -1.0])
def test_2d_target_thin_rod_at_round_off(et):
    """Thin rod (cond 1e8): the target v_fT = -e_t v_T is met to a few ulps of s for the
    exact v + W P (Cramer's rule missed it by 4.5e-10 s)."""
    v = np.array([-1.0, 1.0])
    mode, P, _, _ = run(brach_2d, v, W_THIN_ROD, params(0.0, 1e4, et))
    ref = exact_solve(W_THIN_ROD, [1.0, -(1.0 + et) * 1.0])
    assert mode == MODE_STICK
    for x, r in zip(P, ref):
        assert abs(x - float(r)) <= 4 * EPS * abs(float(r))
    s = np.linalg.norm(v) + np.linalg.norm(W_THIN_ROD, 2) * np.linalg.norm(P)
    assert np.all(np.abs(exact_vf(v, W_THIN_ROD, P) - [0.0, -et]) <= 4 * EPS * s)


def test_3d_target_cond_7e11_at_round_off():
    """Stability reproducer (cond 6.7e11, mu = 54525): the cofactor solve missed v_fT = 0
    by (8849, -8588) m/s = 1.9e-7 s; now within a few ulps of s (exact v + W P)."""
    v = np.array([-6583.876388369971, 0.0, 0.0])
    et = -0.25008103118059777
    mode, P, _, _ = run(brach_3d, v, W_COND_7E11, params(0.0, 54525.22602201105, et))
    assert mode == MODE_STICK
    s = np.linalg.norm(v) + np.linalg.norm(W_COND_7E11, 2) * np.linalg.norm(P)
    vf = exact_vf(v, W_COND_7E11, P)
    assert np.all(np.abs(vf) <= 8 * EPS * s)            # target (0, -e_t 0, -e_t 0)


@pytest.mark.parametrize("log_cond", [8.0, 12.0, 15.0])
def test_3d_spd_accepted_and_target_at_round_off(log_cond):
    """Every exactly-SPD W up to cond 1e15 is accepted (no NoSolutionError), the stick
    target v_fT = -e_t v_T holds to a few ulps of s, and the slip branch lies on the cone
    along P*_T (rational P*) with v_fN = -e v_N."""
    rng = np.random.default_rng(30 + int(log_cond))
    for k in range(30):
        W = ill_conditioned_spd(rng, 3, log_cond)
        v = rng.normal(size=3)
        v[0] = -abs(v[0])
        e, et = rng.uniform(-1, 1), rng.uniform(-1, 1)
        mu = 10.0 ** rng.uniform(-2, 6)
        mode, P, _, _ = run(brach_3d, v, W, params(e, mu, et))
        assert mode in (MODE_STICK, MODE_SLIP)
        s = np.linalg.norm(v) + np.linalg.norm(W, 2) * np.linalg.norm(P)
        vf = exact_vf(v, W, P)
        assert abs(vf[0] + e * v[0]) <= 16 * EPS * s
        if mode == MODE_STICK:
            assert np.all(np.abs(vf[1:] + et * v[1:]) <= 16 * EPS * s)
        else:
            Ps = [float(x) for x in exact_solve(W, [-(1 + e) * v[0], -(1 + et) * v[1],
                                                     -(1 + et) * v[2]])]
            u = np.array(Ps[1:]) / np.hypot(*Ps[1:])
            assert np.hypot(*P[1:]) == pytest.approx(mu * P[0], rel=4 * EPS)
            if np.linalg.norm(W, 2) * np.linalg.norm(Ps) < 1e6 * s:   # P* direction known
                assert np.allclose(P[1:] / np.hypot(*P[1:]), u, atol=1e-9)


def test_3d_spd_with_cancelling_cofactor_determinant_is_accepted():
    """SPD W of cond 5.6e9 whose plain cofactor determinant is -7.9e-6 (used to raise
    NoSolutionError); the same W made indefinite is rejected."""
    v = np.array([-1036.9590984213548, 0.08664642602372336, 0.0])
    mode, P, _, _ = run(brach_3d, v, W_SPD_CANCELS, params(0.86, 5.36, 0.3))
    assert mode in (MODE_STICK, MODE_SLIP)
    Wb = W_SPD_CANCELS.copy()
    Wb[2, 2] -= 1e-3
    assert exact_minors(Wb)[2] < 0
    mode, P, _, _ = run(brach_3d, v, Wb, params(0.86, 5.36, 0.3))
    assert mode == MODE_NO_SOLUTION and np.all(P == 0.0)
