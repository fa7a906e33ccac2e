"""Kane & Levinson kernels (kernels/kane_levinson.py) and the NumPy baseline
(rbimpact/numpy_laws.py): DESIGN §5 reference cases, the law's equations on random
contacts, energy bookkeeping against rigid bodies, 3D root choice against an independent
dense scan, invariance, planar reduction. Conventions: DESIGN.md §3 (normal first)."""
import numpy as np
import pytest
from numba import njit
from scipy.optimize import brentq

from _impact_helpers import (EPS, ROD, SPHERE_2D, SPHERE_3D, SWERVE_V, SWERVE_W,
                             W_SPD_CANCELS, W_THIN_ROD, check_energy_identity, exact_minors,
                             exact_solve, exact_vf, ill_conditioned_spd, params,
                             random_contact, rel_err, run, tangent_rotation)
from rbimpact.kernels.common import (MODE_NO_SOLUTION, MODE_SEPARATING, MODE_SLIP,
                                     MODE_STICK, det2k, fma, spd3_solve)
from rbimpact.kernels.kane_levinson import (kane_levinson, kane_levinson_2d,
                                            kane_levinson_2d_scalar, kane_levinson_3d,
                                            kane_levinson_3d_scalar)
from rbimpact.numpy_laws import kane_levinson_2d_numpy

TOL = 1e-6


def embed(W2, w22=1.7):
    """3D Delassus matrix of a planar contact: the T2 row decoupled."""
    W = np.zeros((3, 3))
    W[:2, :2] = W2
    W[2, 2] = w22
    return W


# ---- DESIGN §5 reference cases -----------------------------------------------------------

ROD_CASES = [  # (name, v, e, mu, mode, P, v_f, dE)
    ("1a", [-1.0, 0.0], 0.5, 0.3, MODE_SLIP, [0.731707, 0.219512], [0.5, -0.548780], -0.243159),
    ("1a'", [-1.0, 0.0], 0.5, 0.8, MODE_STICK, [0.9375, 0.5625], [0.5, 0.0], None),
    ("1b", [-1.0, 1.0], 1.0, 0.3, MODE_STICK, [0.875, 0.125], [1.0, 0.0], +0.0625),
]


@pytest.mark.parametrize("name,v,e,mu,mode,P,vf,dE", ROD_CASES, ids=[c[0] for c in ROD_CASES])
def test_rod_reference_cases_2d_and_planar_3d(name, v, e, mu, mode, P, vf, dE):
    m, P2, vf2, dE2 = run(kane_levinson_2d, v, ROD, params(e, mu))
    assert m == mode
    np.testing.assert_allclose(P2, P, atol=TOL)
    np.testing.assert_allclose(vf2, vf, atol=TOL)
    if dE is not None:
        assert dE2 == pytest.approx(dE, abs=TOL)
    m3, P3, vf3, dE3 = run(kane_levinson_3d, v + [0.0], embed(ROD), params(e, mu))
    assert m3 == mode
    np.testing.assert_allclose(P3, P + [0.0], atol=TOL)
    assert dE3 == pytest.approx(dE2, abs=1e-12)


def test_case_1b_creates_energy_and_reports_it():
    m, P, vf, dE = run(kane_levinson_2d, [-1.0, 1.0], ROD, params(1.0, 0.3))
    assert m == MODE_STICK
    assert dE == pytest.approx(0.0625, abs=1e-12)     # energy created: the law, not a bug
    assert vf[0] == pytest.approx(1.0, abs=1e-12)      # Newton restitution still holds


@pytest.mark.parametrize("mu,mode,PT,vfT", [(0.1, MODE_SLIP, -0.15, 0.475),
                                             (0.5, MODE_STICK, -0.285714, 0.0)])
def test_sphere_reference_cases(mu, mode, PT, vfT):
    m, P, vf, _ = run(kane_levinson_2d, [-1.0, 1.0], SPHERE_2D, params(0.5, mu))
    assert m == mode
    np.testing.assert_allclose(P, [1.5, PT], atol=TOL)
    assert vf[1] == pytest.approx(vfT, abs=TOL)
    m, P, vf, _ = run(kane_levinson_3d, [-1.0, 1.0, 0.0], SPHERE_3D, params(0.5, mu))
    assert m == mode
    np.testing.assert_allclose(P, [1.5, PT, 0.0], atol=TOL)
    np.testing.assert_allclose(vf[1:], [vfT, 0.0], atol=TOL)


def test_swerve_case_3d_sticks():
    m, P, vf, _ = run(kane_levinson_3d, SWERVE_V, SWERVE_W, params(0.2, 0.2))
    assert m == MODE_STICK
    np.testing.assert_allclose(vf, [0.8, 0.0, 0.0], atol=TOL)
    assert np.hypot(P[1], P[2]) <= 0.2 * P[0]


# ---- contract: separation, frictionless path, dispatch, bad input ------------------------

@pytest.mark.parametrize("kernel,d", [(kane_levinson_2d, 2), (kane_levinson_3d, 3),
                                      (kane_levinson, 2), (kane_levinson, 3)])
def test_separating_contact_gets_no_impulse(kernel, d):
    for vn in (0.0, 0.7):
        v = np.r_[vn, np.ones(d - 1)]
        m, P, _, _ = run(kernel, v, np.eye(d) * 2.0, params(0.5, 0.3))
        assert m == MODE_SEPARATING
        assert np.all(P == 0.0)


def test_frictionless_path():
    rng = np.random.default_rng(1)
    for d, kernel in ((2, kane_levinson_2d), (3, kane_levinson_3d)):
        for _ in range(50):
            v, W = random_contact(rng, d, coupling=3.0)
            e = rng.uniform()
            m, P, vf, _ = run(kernel, v, W, params(e, 0.0))
            assert m == MODE_SLIP
            assert P[0] == pytest.approx(-(1 + e) * v[0] / W[0, 0], rel=1e-14)
            assert np.all(P[1:] == 0.0)
            assert vf[0] == pytest.approx(-e * v[0], rel=1e-12, abs=1e-14)


def test_dispatch_and_scalar_twins_match_kernels():
    rng = np.random.default_rng(2)
    for _ in range(100):
        p = params(rng.uniform(), rng.uniform(0, 2))
        v, W = random_contact(rng, 2, coupling=2.0)
        _, P, _, _ = run(kane_levinson_2d, v, W, p)
        _, Pd, _, _ = run(kane_levinson, v, W, p)
        ms, pn, pt = kane_levinson_2d_scalar(v[0], v[1], W[0, 0], W[0, 1], W[1, 1], p[0], p[1])
        assert np.array_equal(P, Pd) and np.array_equal(P, [pn, pt])
        v, W = random_contact(rng, 3, coupling=2.0)
        _, P, _, _ = run(kane_levinson_3d, v, W, p)
        _, Pd, _, _ = run(kane_levinson, v, W, p)
        ms, *Ps = kane_levinson_3d_scalar(v[0], v[1], v[2], W[0, 0], W[0, 1], W[0, 2],
                                          W[1, 1], W[1, 2], W[2, 2], p[0], p[1])
        assert np.array_equal(P, Pd) and np.array_equal(P, Ps)


BAD = [
    ("nan v_N", [np.nan, 1.0], np.eye(2)),
    ("nan v_T", [-1.0, np.nan], np.eye(2)),
    ("inf v_N", [-np.inf, 1.0], np.eye(2)),
    ("nan W", [-1.0, 1.0], [[1.0, np.nan], [np.nan, 1.0]]),
    ("indefinite W", [-1.0, 1.0], [[1.0, 2.0], [2.0, 1.0]]),
    ("W_NN <= 0", [-1.0, 1.0], [[-1.0, 0.0], [0.0, -1.0]]),
    ("singular W", [-1.0, 1.0], [[1.0, 1.0], [1.0, 1.0]]),
]


@pytest.mark.parametrize("name,v,W", BAD, ids=[b[0] for b in BAD])
@pytest.mark.parametrize("mu", [0.0, 0.4])
def test_bad_input_is_a_mode_never_nan(name, v, W, mu):
    W2 = np.array(W, dtype=float)
    for kernel, vv, WW in ((kane_levinson_2d, np.array(v, dtype=float), W2),
                           (kane_levinson_3d, np.array(list(v) + [0.0]), embed(W2))):
        P = np.full(vv.shape[0], 123.0)
        m = kernel(vv, WW, params(0.5, mu), P)
        if mu == 0.0 and name in ("indefinite W", "singular W", "nan v_T", "nan W"):
            # the frictionless path reads v_N and W_NN only: these inputs are valid for it
            assert m == MODE_SLIP and np.all(np.isfinite(P))
        else:
            assert m == MODE_NO_SOLUTION
            assert np.all(P == 0.0)


# ---- the law's equations on random contacts ----------------------------------------------

def _check_law(v, W, e, mu, m, P, vf):
    """Stick: v_fT = 0 and |P_T| <= mu P_N; slip: |P_T| = mu P_N and P_T = -mu P_N u with
    u the unit final slip. Always v_fN = -e v_N and P_N > 0."""
    scale = np.abs(v).max() + np.abs(W).max() * np.abs(P).max()
    assert m in (MODE_STICK, MODE_SLIP)
    assert P[0] > 0.0
    assert vf[0] == pytest.approx(-e * v[0], abs=1e-11 * scale)
    PT, vfT = P[1:], vf[1:]
    if m == MODE_STICK:
        np.testing.assert_allclose(vfT, 0.0, atol=1e-11 * scale)
        assert np.linalg.norm(PT) <= mu * P[0] * (1 + 1e-12)
    else:
        assert np.linalg.norm(PT) == pytest.approx(mu * P[0], rel=1e-12)
        u = -PT / (mu * P[0])
        lam = u @ vfT
        assert lam >= -1e-11 * scale                         # slides along u
        np.testing.assert_allclose(vfT, lam * u, atol=1e-9 * scale)


@pytest.mark.parametrize("coupling", [1.0, 4.0])
def test_2d_equations_hold_and_a_solution_always_exists(coupling):
    rng = np.random.default_rng(3)
    modes = set()
    for _ in range(500):
        v, W = random_contact(rng, 2, coupling)
        e, mu = rng.uniform(), rng.uniform(0.01, 3.0)
        m, P, vf, _ = run(kane_levinson_2d, v, W, params(e, mu))
        _check_law(v, W, e, mu, m, P, vf)        # includes m >= 0: SPD W always has one
        modes.add(m)
    assert modes == {MODE_STICK, MODE_SLIP}


@pytest.mark.parametrize("coupling", [1.0, 4.0])
def test_3d_equations_hold(coupling):
    rng = np.random.default_rng(4)
    modes = set()
    for _ in range(400):
        v, W = random_contact(rng, 3, coupling)
        e, mu = rng.uniform(), rng.uniform(0.01, 3.0)
        m, P, vf, _ = run(kane_levinson_3d, v, W, params(e, mu))
        _check_law(v, W, e, mu, m, P, vf)
        modes.add(m)
    assert modes == {MODE_STICK, MODE_SLIP}


def test_2d_slip_sign_is_the_only_consistent_one():
    """Exactly one of stick, slip(+), slip(-) satisfies the law (DESIGN §4, 2D)."""
    rng = np.random.default_rng(5)
    for _ in range(500):
        v, W = random_contact(rng, 2, coupling=4.0)
        e, mu = rng.uniform(), rng.uniform(0.01, 3.0)
        a = -(1 + e) * v[0]
        Ps = np.linalg.solve(W, [a, -v[1]])
        n_ok = int(Ps[0] >= 0 and abs(Ps[1]) <= mu * Ps[0])
        for s in (1.0, -1.0):
            den = W[0, 0] - mu * s * W[0, 1]
            if den > 0:
                pn = a / den
                n_ok += s * (v[1] + W[1, 0] * pn - mu * s * W[1, 1] * pn) > 0
        assert n_ok == 1


# ---- 3D root choice against an independent dense scan ------------------------------------

def _physical_roots(v, W, e, mu, n=2048):
    """All (theta, P_N, u.v_T) with v_fT = lambda u, lambda > 0, P_N > 0: a dense scan of
    g(theta) = D u x (D v_fT), refined with brentq. Independent of the kernel's algorithm."""
    a = -(1 + e) * v[0]

    def parts(th):
        u = np.array([np.cos(th), np.sin(th)])
        D = W[0, 0] - mu * W[0, 1:] @ u
        x = D * v[1:] + a * (W[1:, 0] - mu * W[1:, 1:] @ u)      # D v_fT
        return u, D, x

    def g(th):
        u, _, x = parts(th)
        return u[0] * x[1] - u[1] * x[0]

    th = np.linspace(0.0, 2 * np.pi, n + 1)
    u = np.stack([np.cos(th), np.sin(th)], axis=1)
    D = W[0, 0] - mu * u @ W[0, 1:]
    x = D[:, None] * v[1:] + a * (W[1:, 0] - mu * u @ W[1:, 1:])
    gv = u[:, 0] * x[:, 1] - u[:, 1] * x[:, 0]
    out = []
    for i in range(n):
        if gv[i] == 0.0 or gv[i] * gv[i + 1] < 0.0:
            r = th[i] if gv[i] == 0.0 else brentq(g, th[i], th[i + 1], xtol=1e-14)
            ur, Dr, xr = parts(r)
            if Dr > 0 and ur @ xr > 0:
                out.append((r, a / Dr, ur @ v[1:]))
    return out


# A strongly coupled contact with three physical slip solutions (found by a random search).
MULTI_ROOT = dict(
    v=[-0.2603293468058841, 0.011763444484923708, 0.31024721342857225],
    W=[[23.347465955907534, 6.198864069553867, 1.084116158322876],
       [6.198864069553867, 1.704933510794242, 0.4374515015349196],
       [1.084116158322876, 0.4374515015349196, 0.6238443319916253]],
    e=0.581956844006622, mu=3.5268987430124747)


def test_3d_multiple_roots_choice_rule():
    v, W = np.array(MULTI_ROOT["v"]), np.array(MULTI_ROOT["W"])
    e, mu = MULTI_ROOT["e"], MULTI_ROOT["mu"]
    roots = _physical_roots(v, W, e, mu)
    assert len(roots) >= 2
    m, P, vf, _ = run(kane_levinson_3d, v, W, params(e, mu))
    assert m == MODE_SLIP
    _check_law(v, W, e, mu, m, P, vf)
    best = max(roots, key=lambda r: r[2])               # largest u . v_T
    assert P[0] == pytest.approx(best[1], rel=1e-9)
    u = -P[1:] / (mu * P[0])
    assert np.arctan2(u[1], u[0]) % (2 * np.pi) == pytest.approx(best[0] % (2 * np.pi), abs=1e-9)


def test_3d_root_choice_matches_dense_scan():
    rng = np.random.default_rng(6)
    n_slip = n_multi = 0
    for _ in range(150):
        v, W = random_contact(rng, 3, coupling=3.0)
        e, mu = rng.uniform(), rng.uniform(0.1, 4.0)
        m, P, _, _ = run(kane_levinson_3d, v, W, params(e, mu))
        if m != MODE_SLIP:
            continue
        n_slip += 1
        roots = _physical_roots(v, W, e, mu)
        assert roots, "kernel slid where the scan finds no solution"
        n_multi += len(roots) > 1
        best = max(roots, key=lambda r: r[2])
        assert P[0] == pytest.approx(best[1], rel=1e-8)
    assert n_slip > 50


# ---- invariance and planar reduction -----------------------------------------------------

def test_3d_invariant_under_rotation_of_tangent_basis():
    rng = np.random.default_rng(7)
    modes = set()
    for _ in range(200):
        v, W = random_contact(rng, 3, coupling=2.0)
        p = params(rng.uniform(), rng.uniform(0.05, 2.0))
        R = tangent_rotation(rng.uniform(0, 2 * np.pi))
        m, P, _, _ = run(kane_levinson_3d, v, W, p)
        mr, Pr, _, _ = run(kane_levinson_3d, R @ v, R @ W @ R.T, p)
        assert mr == m
        np.testing.assert_allclose(Pr, R @ P, rtol=1e-8, atol=1e-10 * np.abs(P).max())
        modes.add(m)
    assert modes == {MODE_STICK, MODE_SLIP}


def test_3d_reproduces_2d_for_planar_motion():
    rng = np.random.default_rng(8)
    for _ in range(500):
        v, W2 = random_contact(rng, 2, coupling=rng.choice([1.0, 4.0]))
        p = params(rng.uniform(), rng.uniform(0.0, 3.0))
        m2, P2, _, _ = run(kane_levinson_2d, v, W2, p)
        m3, P3, _, _ = run(kane_levinson_3d, np.r_[v, 0.0], embed(W2, rng.uniform(0.1, 3)), p)
        assert m3 == m2
        np.testing.assert_allclose(P3[:2], P2, rtol=1e-10, atol=1e-12 * np.abs(P2).max())
        assert abs(P3[2]) <= 1e-12 * np.abs(P2).max()


# ---- energy bookkeeping against rigid bodies ---------------------------------------------

@pytest.mark.parametrize("dim,kernel", [(2, kane_levinson_2d), (3, kane_levinson_3d)])
def test_energy_identity_with_rigid_bodies(dim, kernel):
    rng = np.random.default_rng(9 + dim)
    assert check_energy_identity(kernel, rng, dim, 200, (0.0, 1.0), 2.0) == 200


# ---- NumPy baseline ----------------------------------------------------------------------

@pytest.mark.parametrize("mu", [0.0, 0.3, 1.5])
def test_numpy_version_agrees_with_kernel(mu):
    rng = np.random.default_rng(10)
    n = 1000
    A = rng.normal(size=(n, 2, 2))
    A[:, 0] *= rng.uniform(0.2, 4.0, size=(n, 1))
    W = A @ A.transpose(0, 2, 1) + 0.05 * np.eye(2)
    v = rng.normal(size=(n, 2))
    v[: n // 10, 0] = np.abs(v[: n // 10, 0])           # some separating contacts
    P_np = kane_levinson_2d_numpy(v, W, 0.6, mu)
    P_k = np.empty_like(v)
    p = params(0.6, mu)
    modes = np.array([kane_levinson_2d(v[i], W[i], p, P_k[i]) for i in range(n)])
    np.testing.assert_allclose(P_np, P_k, rtol=1e-12, atol=1e-14)
    assert np.all(P_np[modes == MODE_SEPARATING] == 0.0)
    assert set(modes) >= ({MODE_SEPARATING, MODE_SLIP} | ({MODE_STICK} if mu else set()))


def test_numpy_version_mirror_symmetry():
    """A check of the baseline on its own: flipping the tangent (t -> -t) mirrors P_T."""
    rng = np.random.default_rng(11)
    n = 300
    A = rng.normal(size=(n, 2, 2))
    W = A @ A.transpose(0, 2, 1) + 0.05 * np.eye(2)
    v = rng.normal(size=(n, 2))
    v[:, 0] = -np.abs(v[:, 0])
    F = np.diag([1.0, -1.0])
    P = kane_levinson_2d_numpy(v, W, 0.4, 0.5)
    Pm = kane_levinson_2d_numpy(v @ F, F @ W @ F, 0.4, 0.5)
    np.testing.assert_allclose(Pm, P @ F, rtol=1e-12, atol=1e-14)


# ---- backward-stable solves (stability issue 6): regression against rational arithmetic ----

def test_2d_stick_trial_thin_rod_is_exact():
    """Thin rod (I = 1e-8 m r^2, cond 1e8): Cramer's rule left v_fT = 4.5e-10 s; the Kahan
    determinants give P* to a few ulps and v_fT = 0 to round-off of the exact v + W P."""
    v = np.array([-1.0, 1.0])
    mode, P, _, _ = run(kane_levinson_2d, v, W_THIN_ROD, params(0.0, 5.0))
    ref = exact_solve(W_THIN_ROD, [1.0, -1.0])
    assert mode == MODE_STICK
    for x, r in zip(P, ref):
        assert abs(x - float(r)) <= 4 * EPS * abs(float(r))
    s = np.linalg.norm(v) + np.linalg.norm(W_THIN_ROD, 2) * np.linalg.norm(P)
    assert np.all(np.abs(exact_vf(v, W_THIN_ROD, P) - [0.0, 0.0]) <= 4 * EPS * s)


@pytest.mark.parametrize("log_cond", [4.0, 8.0, 12.0, 15.0])
def test_2d_stick_trial_componentwise_exact(log_cond):
    """Stick trial on random SPD W up to cond 1e15: each component of P* within a few ulps
    of the rational solution of W P* = (a, -v_T)."""
    rng = np.random.default_rng(int(log_cond))
    n_stick = 0
    for _ in range(40):
        W = ill_conditioned_spd(rng, 2, log_cond)
        v = rng.normal(size=2)
        v[0] = -abs(v[0])
        e = float(rng.choice([0.0, 0.5, 1.0]))
        ref = [float(x) for x in exact_solve(W, [-(1.0 + e) * v[0], -v[1]])]
        if ref[0] <= 0:
            continue
        mu = 2.0 * abs(ref[1]) / ref[0] + 1.0          # inside the cone: stick
        mode, P, _, _ = run(kane_levinson_2d, v, W, params(e, mu))
        assert mode == MODE_STICK
        for x, r in zip(P, ref):
            assert abs(x - r) <= 8 * EPS * abs(r)
        n_stick += 1
    assert n_stick >= 10


@njit
def _fma_jit(a, b, c):
    return fma(a, b, c)


def test_det2k_sign_and_accuracy():
    """Kahan's FMA determinant: within 2 ulps of a d - b c (rational reference) even under
    total cancellation, where the plain formula has the wrong sign; the Python fallback of
    fma is the correctly rounded a b + c."""
    from fractions import Fraction as F
    rng = np.random.default_rng(5)
    for _ in range(300):
        a, b = rng.normal(size=2)
        d = (b * b + rng.normal() * 1e-13) / a          # a d ~ b^2: cancels
        exact = F(a) * F(d) - F(b) * F(b)
        got = det2k(a, d, b, b)
        assert abs(F(got) - exact) <= 2 * EPS * abs(exact)
        assert (got > 0) == (exact > 0)
        x, y, z = rng.normal(size=3)
        assert fma(x, y, z) == float(F(x) * F(y) + F(z)) == _fma_jit(x, y, z)


def _backward_error(W, r, x):
    """max_i |r - W x|_i / (|r| + |W| |x|)_i with the residual in rational arithmetic."""
    from fractions import Fraction as F
    res = [F(float(r[i])) - sum(F(float(W[i][j])) * F(float(x[j])) for j in range(3))
           for i in range(3)]
    return max(abs(float(res[i])) / (abs(r[i]) + np.abs(W[i]) @ np.abs(x)) for i in range(3))


@pytest.mark.parametrize("log_cond", [1.0, 6.0, 10.0, 13.0, 15.0])
def test_spd3_solve_against_rational(log_cond):
    """common.spd3_solve: accepts every exactly-SPD W up to cond 1e15 (Sylvester with
    rational minors as the reference) and rejects it made indefinite by a hair; the solve is
    componentwise backward stable (|r - W x| <= 4 eps (|r| + |W||x|) row by row, exact
    residual), and forward accurate to a few ulps normwise up to cond 1e13."""
    rng = np.random.default_rng(100 + int(log_cond))
    for _ in range(30):
        W = ill_conditioned_spd(rng, 3, log_cond)
        r = rng.normal(size=3) * 10.0 ** rng.uniform(-3, 3, size=3)
        ok, *x = spd3_solve(W[0, 0], W[0, 1], W[0, 2], W[1, 1], W[1, 2], W[2, 2], *r)
        assert ok
        assert _backward_error(W, r, x) <= 4 * EPS
        if log_cond <= 13.0:
            assert rel_err(x, exact_solve(W, r)) <= 16 * EPS
        # indefinite by a hair: lower W_22 by twice the last Cholesky pivot
        Wb = W.copy()
        minors = exact_minors(W)
        Wb[2, 2] -= 2.0 * float(minors[2] / minors[1])
        if not all(m > 0 for m in exact_minors(Wb)):
            ok, *x = spd3_solve(Wb[0, 0], Wb[0, 1], Wb[0, 2], Wb[1, 1], Wb[1, 2], Wb[2, 2],
                                *r)
            assert not ok and x == [0.0, 0.0, 0.0]


def test_3d_spd_with_cancelling_cofactor_determinant_is_accepted():
    """SPD W of cond 5.6e9 whose plain cofactor determinant is -7.9e-6: used to raise
    NoSolutionError; now resolved, and the same W made indefinite is still rejected."""
    v = np.array([-1036.9590984213548, 0.08664642602372336, 0.0])
    mode, P, vf, _ = run(kane_levinson_3d, v, W_SPD_CANCELS, params(0.86, 5.36))
    assert mode in (MODE_STICK, MODE_SLIP)
    s = np.linalg.norm(v) + np.linalg.norm(W_SPD_CANCELS, 2) * np.linalg.norm(P)
    assert abs(exact_vf(v, W_SPD_CANCELS, P)[0] - 0.86 * 1036.9590984213548) <= 1e-14 * s
    Wb = W_SPD_CANCELS.copy()
    Wb[2, 2] -= 1e-3                                    # det becomes negative (exactly)
    assert exact_minors(Wb)[2] < 0
    mode, P, _, _ = run(kane_levinson_3d, v, Wb, params(0.86, 5.36))
    assert mode == MODE_NO_SOLUTION and np.all(P == 0.0)


@pytest.mark.parametrize("log_cond", [8.0, 12.0])
def test_3d_stick_trial_residual_at_round_off(log_cond):
    """3D stick trial on ill-conditioned W (cond up to 1e12): v_f = (-e v_N, 0, 0) to a few
    ulps of s = |v| + ||W|| |P| for the exact v + W P (the cofactor solve missed it by
    ~eps cond)."""
    rng = np.random.default_rng(7 + int(log_cond))
    n_stick = 0
    for _ in range(30):
        W = ill_conditioned_spd(rng, 3, log_cond)
        v = rng.normal(size=3)
        v[0] = -abs(v[0])
        ref = [float(x) for x in exact_solve(W, [-v[0], -v[1], -v[2]])]
        if ref[0] <= 0:
            continue
        mu = 2.0 * np.hypot(ref[1], ref[2]) / ref[0] + 1.0
        mode, P, _, _ = run(kane_levinson_3d, v, W, params(0.0, mu))
        assert mode == MODE_STICK
        s = np.linalg.norm(v) + np.linalg.norm(W, 2) * np.linalg.norm(P)
        assert np.all(np.abs(exact_vf(v, W, P)) <= 16 * EPS * s)
        n_stick += 1
    assert n_stick >= 5


# near-Painleve 3D slip (W_NN < mu |W_NT|, tiny v_N): P_N = a / D with D ~ 1e-15 ||W||
KL3_NEAR_PAINLEVE = [
    ([-3.826876022838944e-09, 2.332721390631426e-09, -4405.841143638487],
     [[3.992874106840114e-05, 3.0171555156973024e-05, -9.893088753349557e-06],
      [3.0171555156973024e-05, 0.00016549392649138614, -0.00010903170756023525],
      [-9.893088753349557e-06, -0.00010903170756023525, 7.489982190202088e-05]],
     0.0, 5.513800536036348),
    ([-2.99289221876759e-08, 6.050812960988013e-290, 556.0364400993321],
     [[1.907301739650419e-08, 9.187225736826713e-08, 6.117636703470964e-08],
      [9.187225736826713e-08, 4.425389349726186e-07, 2.946808059407338e-07],
      [6.117636703470964e-08, 2.946808059407338e-07, 1.962244599861841e-07]],
     1.0, 0.40293729381681426),
]


@pytest.mark.parametrize("v, W, e, mu", KL3_NEAR_PAINLEVE)
def test_3d_slip_near_painleve_residual_at_round_off(v, W, e, mu):
    """Slip with a tiny denominator D: P_N = a / D at the rounded angle left v_fT off the
    slip direction by 2.5e-6 s; the least-squares P_N of the normal and tangential
    equations keeps v_fN = -e v_N and v_fT = lambda u (lambda > 0, u = -P_T/|P_T|) to a few
    ulps of s = |v| + ||W|| |P| (exact v + W P)."""
    v, W = np.array(v), np.array(W)
    mode, P, _, _ = run(kane_levinson_3d, v, W, params(e, mu))
    assert mode == MODE_SLIP
    s = np.linalg.norm(v) + np.linalg.norm(W, 2) * np.linalg.norm(P)
    vf = exact_vf(v, W, P)
    u = -P[1:] / np.linalg.norm(P[1:])
    assert np.linalg.norm(P[1:]) == pytest.approx(mu * P[0], rel=4 * EPS)
    assert abs(vf[0] + e * v[0]) <= 16 * EPS * s
    lam = vf[1:] @ u
    assert lam > 0 and np.linalg.norm(vf[1:] - lam * u) <= 16 * EPS * s
