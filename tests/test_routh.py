"""Routh's law kernels (kernels/routh.py): reference cases, an independent scipy reference,
energy, invariance and convergence. Conventions: DESIGN.md §3-5 (normal first)."""
import numpy as np
import pytest
from hypothesis import given, settings, HealthCheck, strategies as st
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from rbimpact.kernels.common import (
    N_PARAMS, P_E, P_MU, P_REST, P_TOL,
    REST_ENERGETIC, REST_POISSON, REST_NEWTON,
    MODE_SEPARATING, MODE_STICK, MODE_SLIP, MODE_SLIP_STICK, MODE_SLIP_REVERSE,
    MODE_NO_SOLUTION,
)
from rbimpact.kernels.routh import routh, routh_2d, routh_3d, routh_2d_scalar, routh_3d_scalar

ROD = [[2.5, -1.5], [-1.5, 2.5]]
SWERVE_W = [[5.0, 1.0, -1.0], [1.0, 8.0, -2.0], [-1.0, -2.0, 3.0]]
SWERVE_V = [-4.0, -2.0, 1.0]
KINDS = (REST_ENERGETIC, REST_POISSON, REST_NEWTON)


def params(e, mu, rest=REST_ENERGETIC, tol=1e-10):
    pr = np.zeros(N_PARAMS)
    pr[P_E], pr[P_MU], pr[P_REST], pr[P_TOL] = e, mu, rest, tol
    return pr


def run(v, W, e, mu, rest=REST_ENERGETIC, tol=1e-10, kernel=routh):
    v = np.asarray(v, float)
    W = np.asarray(W, float)
    P = np.full(v.shape[0], np.nan)
    mode = kernel(v, W, params(e, mu, rest, tol), P)
    with np.errstate(invalid='ignore'):                  # non-finite inputs in contract tests
        vf = v + W @ P
        return mode, P, vf, P @ (v + vf) / 2


def embed(W2, v2, d=1.0):
    """Planar contact as a 3D one: T2 decoupled with W_T2T2 = d, v_T2 = 0."""
    W3 = np.zeros((3, 3))
    W3[:2, :2] = W2
    W3[2, 2] = d
    return W3, np.r_[v2, 0.0]


def rot3(t):
    c, s = np.cos(t), np.sin(t)
    return np.array([[1.0, 0, 0], [0, c, -s], [0, s, c]])


# ------------------------------------------------------------------------------------------
# independent reference: scipy solve_ivp in p on the state (P_T, int v_N dp), with events
# ------------------------------------------------------------------------------------------
def ref_routh(v, W, e, mu, rest, rtol=1e-11):
    """Returns (status, P); status 'ok', 'jam' (v_N never reaches 0 in compression) or
    'recomp' (v_N back to 0 before termination). |v_T| -> 0 is cut at 1e-9 |v0|, then the
    exact stick or diverging-ray motion (ray found by a fine angle scan + brentq)."""
    v = np.asarray(v, float)
    W = np.asarray(W, float)
    d = len(v)
    vN0 = v[0]
    vs = np.linalg.norm(v)
    w, C = W[1:, 0], W[1:, 1:]
    z = np.linalg.solve(C, w)
    stable = np.linalg.norm(z) <= mu
    ps = abs(vN0) / W[0, 0]
    atol = 1e-14 * np.r_[np.full(d - 1, ps), vs * ps]
    eps = 1e-9 * vs

    def vel(p, y):
        return v + W @ np.r_[p, y[:-1]]

    def diverging():
        if d == 2:
            return np.sign(w)

        def F(t):
            u = np.array([np.cos(t), np.sin(t)])
            f = w - mu * C @ u
            return u[0] * f[1] - u[1] * f[0]
        ts = np.linspace(0.0, 2 * np.pi, 3601)
        Fs = np.array([F(t) for t in ts])
        rays = []
        for i in range(len(ts) - 1):
            if Fs[i] * Fs[i + 1] < 0 or Fs[i] == 0:
                t = ts[i] if Fs[i] == 0 else brentq(F, ts[i], ts[i + 1], xtol=1e-15)
                u = np.array([np.cos(t), np.sin(t)])
                if u @ (w - mu * C @ u) > 0:
                    rays.append(u)
        assert len(rays) == 1, rays
        return rays[0]

    kind = 'slide' if np.linalg.norm(v[1:]) > 0 else ('stick' if stable else 'ray')
    u_ray = diverging() if kind == 'ray' else None
    p, y, comp, pc, Wc = 0.0, np.zeros(d), True, None, None
    for _ in range(10):
        def rhs(p, y, kind=kind, u_ray=u_ray):
            vv = vel(p, y)
            if kind == 'slide':
                dPT = -mu * vv[1:] / np.linalg.norm(vv[1:])
            elif kind == 'stick':
                dPT = -z
            else:
                dPT = -mu * u_ray
            return np.r_[dPT, vv[0]]

        evs = []

        def ev(name, fun, direction):
            fun.terminal, fun.direction = True, direction
            evs.append((name, fun))
        if comp:
            ev('comp', lambda p, y: vel(p, y)[0], 1)
        else:
            if rest == REST_ENERGETIC:
                ev('term', lambda p, y: y[-1] - (1 - e * e) * Wc, 1)
            elif rest == REST_NEWTON:
                ev('term', lambda p, y: vel(p, y)[0] + e * vN0, 1)
            ev('recomp', lambda p, y: vel(p, y)[0], -1)
        if kind == 'slide':
            ev('zero', lambda p, y: np.linalg.norm(vel(p, y)[1:]) - eps, -1)
        t_end = (1 + e) * pc if (not comp and rest == REST_POISSON) else p + 1e3 * ps
        sol = solve_ivp(rhs, (p, t_end), y, method='DOP853', rtol=rtol, atol=atol,
                        events=[f for _, f in evs])
        first = None
        for (name, _), te, ye in zip(evs, sol.t_events, sol.y_events):
            if len(te) and (first is None or te[0] < first[1]):
                first = (name, te[0], ye[0])
        if first is None:
            if not comp and rest == REST_POISSON:
                return 'ok', np.r_[sol.t[-1], sol.y[:-1, -1]]
            return ('jam' if comp else 'recomp'), None
        name, p, y = first
        if name == 'term' or (name == 'comp' and e == 0):
            return 'ok', np.r_[p, y[:-1]]
        if name == 'comp':
            comp, pc, Wc = False, p, y[-1]
        elif name == 'recomp':
            return 'recomp', None
        else:
            kind = 'stick' if stable else 'ray'
            u_ray = None if stable else diverging()
    raise RuntimeError('reference: too many segments')


def random_case(rng, d):
    L = rng.normal(size=(d, d))
    W = L @ L.T + 0.1 * np.eye(d)
    v = rng.normal(size=d)
    v[0] = -abs(v[0]) - 0.05
    if rng.random() < 0.1:
        v[1:] = 0.0                               # starts with v_T = 0 exactly
    return W, v, rng.uniform(0.0, 1.5), rng.uniform(0.0, 1.0), int(rng.integers(3))


# ------------------------------------------------------------------------------------------
# DESIGN §5 reference values
# ------------------------------------------------------------------------------------------
@pytest.mark.parametrize('rest', KINDS)                 # slip throughout: all kinds agree
@pytest.mark.parametrize('embed3', [False, True])
def test_rod_1a(rest, embed3):
    W, v = np.array(ROD), np.array([-1.0, 0.0])
    if embed3:
        W, v = embed(W, v)
    mode, P, vf, dE = run(v, W, 0.5, 0.3, rest)
    assert mode == MODE_SLIP                             # v_T = 0, sticking unstable (mu < 0.6)
    np.testing.assert_allclose(P[:2], [0.731707, 0.219512], atol=1e-6)
    np.testing.assert_allclose(vf[:2], [0.5, -0.548780], atol=1e-6)
    assert dE == pytest.approx(-0.243159, abs=1e-6)


@pytest.mark.parametrize('rest', KINDS)
@pytest.mark.parametrize('embed3', [False, True])
def test_rod_1a_prime_sticks(rest, embed3):
    W, v = np.array(ROD), np.array([-1.0, 0.0])
    if embed3:
        W, v = embed(W, v)
    mode, P, vf, dE = run(v, W, 0.5, 0.8, rest)
    assert mode == MODE_STICK
    np.testing.assert_allclose(P[:2], [0.9375, 0.5625], atol=1e-6)
    np.testing.assert_allclose(vf[:2], [0.5, 0.0], atol=1e-6)


@pytest.mark.parametrize('embed3', [False, True])
def test_rod_1b(embed3):
    W, v = np.array(ROD), np.array([-1.0, 1.0])
    if embed3:
        W, v = embed(W, v)
    mode, P, vf, dE = run(v, W, 1.0, 0.3, REST_ENERGETIC)
    assert mode == MODE_SLIP_REVERSE
    np.testing.assert_allclose(vf[:2], [0.851143, -0.197573], atol=1e-6)
    assert dE == pytest.approx(-0.074474, abs=1e-6)
    mode, P, vf, dE = run(v, W, 1.0, 0.3, REST_POISSON)
    assert mode == MODE_SLIP_REVERSE
    np.testing.assert_allclose(vf[:2], [0.789831, -0.175141], atol=1e-6)
    assert dE < 0


@pytest.mark.parametrize('rest', KINDS)                 # no normal-tangential coupling
@pytest.mark.parametrize('d', [2, 3])
def test_sphere(rest, d):
    W = np.diag([1.0, 3.5, 3.5][:d])
    v = np.array([-1.0, 1.0, 0.0][:d])
    mode, P, vf, dE = run(v, W, 0.5, 0.1, rest)
    assert mode == MODE_SLIP
    np.testing.assert_allclose(P[:2], [1.5, -0.15], atol=1e-6)
    assert vf[1] == pytest.approx(0.475, abs=1e-6)
    mode, P, vf, dE = run(v, W, 0.5, 0.5, rest)
    assert mode == MODE_SLIP_STICK
    assert P[1] == pytest.approx(-0.285714, abs=1e-6)
    assert vf[1] == pytest.approx(0.0, abs=1e-6)
    if d == 3:
        assert P[2] == pytest.approx(0.0, abs=1e-12)


def test_swerve_3d():
    v, W = np.array(SWERVE_V), np.array(SWERVE_W)
    mode, P, vf, dE = run(v, W, 0.2, 0.2, REST_ENERGETIC, tol=1e-10, kernel=routh_3d)
    assert mode == MODE_SLIP                              # never sticks
    np.testing.assert_allclose(vf, [0.763128, 0.039953, -0.203942], atol=1e-6)
    assert dE < 0
    mode, P, vf, dE = run(v, W, 0.2, 0.2, REST_POISSON, tol=1e-10, kernel=routh_3d)
    assert mode == MODE_SLIP
    np.testing.assert_allclose(vf, [0.735528, 0.038188, -0.202000], atol=1e-6)
    # slip direction swerves from about 153 to about -79 degrees
    assert np.degrees(np.arctan2(v[2], v[1])) == pytest.approx(153.4, abs=0.5)
    assert np.degrees(np.arctan2(vf[2], vf[1])) == pytest.approx(-79.0, abs=1.0)


def test_dE_formula_is_kinetic_energy_change():
    rng = np.random.default_rng(5)
    for _ in range(20):
        W, v, mu, e, rest = random_case(rng, 3)
        mode, P, vf, dE = run(v, W, e, mu, rest)
        M = np.linalg.inv(W)                              # contact-space mass matrix
        assert dE == pytest.approx(0.5 * vf @ M @ vf - 0.5 * v @ M @ v, rel=1e-9, abs=1e-12)


# ------------------------------------------------------------------------------------------
# contract: modes, fast paths, failures never NaN
# ------------------------------------------------------------------------------------------
def test_contract_separating_frictionless_invalid():
    for v, W in (([0.0, 1.0], ROD), ([0.3, -1.0, 2.0], SWERVE_W)):
        mode, P, vf, dE = run(v, W, 0.5, 0.3)
        assert mode == MODE_SEPARATING and not P.any()
    for v, W in (([-1.0, 1.0], ROD), (SWERVE_V, SWERVE_W)):
        for rest in KINDS:                                # mu = 0: P_N = -(1+e) v_N / W_NN
            mode, P, vf, dE = run(v, W, 0.6, 0.0, rest)
            assert mode == MODE_SLIP
            np.testing.assert_allclose(P, np.r_[1.6 * -v[0] / W[0][0], np.zeros(len(v) - 1)])
        for e, mu, rest in ((1.5, 0.3, 0), (-0.1, 0.3, 0), (0.5, -1.0, 0), (0.5, 0.3, 7),
                            (np.nan, 0.3, 0), (0.5, np.nan, 0)):
            mode, P, vf, dE = run(v, W, e, mu, rest)
            assert mode == MODE_NO_SOLUTION and not P.any()
    for v in ([np.nan, 1.0, 0.0], [-1.0, np.nan, 0.0], [-1.0, 1.0, np.inf]):
        for kernel in (routh, routh_3d):
            mode, P, vf, dE = run(v, SWERVE_W, 0.5, 0.3, kernel=kernel)
            assert mode == MODE_NO_SOLUTION and not P.any()
    for v in ([np.nan, 1.0], [-1.0, np.nan], [-1.0, -np.inf]):
        for kernel in (routh, routh_2d):
            mode, P, vf, dE = run(v, ROD, 0.5, 0.3, kernel=kernel)
            assert mode == MODE_NO_SOLUTION and not P.any()
    # tol <= 0 or NaN falls back to TOL_DEFAULT instead of failing
    _, P1, _, _ = run(SWERVE_V, SWERVE_W, 0.2, 0.2, tol=np.nan)
    _, P2, _, _ = run(SWERVE_V, SWERVE_W, 0.2, 0.2, tol=0.0)
    np.testing.assert_allclose(P1, P2)


def test_scalar_cores_match_array_kernels():
    m2, *P2 = routh_2d_scalar(-1.0, 1.0, 2.5, -1.5, 2.5, 1.0, 0.3, 0.0)
    assert m2 == MODE_SLIP_REVERSE
    np.testing.assert_allclose(P2, run([-1, 1], ROD, 1.0, 0.3, kernel=routh_2d)[1])
    W = np.array(SWERVE_W)
    m3, *P3 = routh_3d_scalar(-4.0, -2.0, 1.0, W[0, 0], W[1, 0], W[2, 0], W[1, 1], W[2, 1],
                              W[2, 2], 0.2, 0.2, 0.0, 1e-10)
    np.testing.assert_allclose(P3, run(SWERVE_V, W, 0.2, 0.2, kernel=routh_3d)[1])


def test_jam_no_solution_agrees_with_reference():
    # For SPD W compression always ends (stick slope 1/(W^-1)_NN > 0; on the diverging ray
    # W_NN - mu w.u > lambda^2 u.C^-1 u + mu lambda > 0). A Painleve-type jam needs an
    # indefinite W: accelerating slip (|W_TN| > mu W_TT) with W_NN - mu |W_TN| < 0.
    W2 = np.array([[1.0, 2.0], [2.0, 1.5]])
    v2 = np.array([-1.0, 0.5])
    W3, v3 = embed(W2, v2)
    for W, v in ((W2, v2), (W3, v3)):
        mode, P, vf, dE = run(v, W, 0.5, 0.8)
        assert mode == MODE_NO_SOLUTION and not P.any()
        assert ref_routh(v, W, 0.5, 0.8, REST_ENERGETIC)[0] == 'jam'
    # a 3D jam reached while the slip still swerves
    W3r = rot3(0.3) @ W3 @ rot3(0.3).T
    v3r = np.array([-1.0, 0.4, 0.3])
    mode, P, vf, dE = run(v3r, W3r, 0.5, 0.8)
    assert mode == MODE_NO_SOLUTION
    assert ref_routh(v3r, W3r, 0.5, 0.8, REST_ENERGETIC)[0] == 'jam'


# ------------------------------------------------------------------------------------------
# independent reference on random cases
# ------------------------------------------------------------------------------------------
@pytest.mark.parametrize('d, n, seed', [(3, 200, 11), (2, 100, 12)])
def test_against_scipy_reference(d, n, seed):
    rng = np.random.default_rng(seed)
    modes = set()
    for _ in range(n):
        W, v, mu, e, rest = random_case(rng, d)
        status, Pref = ref_routh(v, W, e, mu, rest)
        mode, P, vf, dE = run(v, W, e, mu, rest, tol=1e-10)
        modes.add(mode)
        if status != 'ok':                                # both must call it a failure
            assert mode == MODE_NO_SOLUTION, (status, mode, v, W, mu, e, rest)
            continue
        assert mode > 0, (mode, v, W, mu, e, rest)
        err = np.linalg.norm(W @ (P - Pref)) / np.linalg.norm(v)
        assert err < 1e-7, (err, mode, v, W, mu, e, rest)
    assert {MODE_SLIP, MODE_SLIP_STICK, MODE_STICK} <= modes   # the phases were exercised


# ------------------------------------------------------------------------------------------
# energy
# ------------------------------------------------------------------------------------------
def _spd(entries, d):
    L = np.array(entries[: d * d]).reshape(d, d)
    return L @ L.T + 0.05 * np.eye(d)


_num = st.floats(-2.0, 2.0, allow_nan=False)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from([2, 3]), st.lists(_num, min_size=9, max_size=9),
       st.lists(_num, min_size=3, max_size=3), st.floats(0.0, 1.0), st.floats(0.0, 2.0),
       st.sampled_from([REST_ENERGETIC, REST_POISSON]))
def test_energetic_and_poisson_never_create_energy(d, Ls, vs, e, mu, rest):
    W = _spd(Ls, d)
    v = np.array(vs[:d])
    v[0] = -abs(v[0]) - 1e-3
    mode, P, vf, dE = run(v, W, e, mu, rest)
    assert mode > 0
    E0 = 0.5 * v @ np.linalg.solve(W, v)
    assert dE <= 1e-9 * E0
    if rest == REST_ENERGETIC and mu == 0.0:
        assert dE == pytest.approx(-(1 - e * e) * v[0] ** 2 / (2 * W[0, 0]), rel=1e-9)


def test_newton_termination_creates_energy_on_slip_reversal():
    # rod, v = (-1, 0.5), e = 1, mu = 0.5: slip stops at p = 2/11, sticking is unstable
    # (1.5 > 0.5 * 2.5), slip reverses with a smaller normal slope (1.75 instead of 3.25);
    # Newton's v_fN = 1 then needs p_f = 76/77 and the impact creates energy.
    v = np.array([-1.0, 0.5])
    mode, P, vf, dE = run(v, ROD, 1.0, 0.5, REST_NEWTON)
    assert mode == MODE_SLIP_REVERSE
    np.testing.assert_allclose(P, [76 / 77, 0.5 * (76 / 77 - 4 / 11)], atol=1e-12)
    assert vf[0] == pytest.approx(1.0)
    assert dE > 0.04
    for rest in (REST_ENERGETIC, REST_POISSON):
        assert run(v, ROD, 1.0, 0.5, rest)[3] < 0
    W3, v3 = embed(ROD, v)
    assert run(v3, W3, 1.0, 0.5, REST_NEWTON)[3] == pytest.approx(dE, abs=1e-8)


# ------------------------------------------------------------------------------------------
# symmetry, planar limit, convergence
# ------------------------------------------------------------------------------------------
def test_rotation_of_tangent_basis():
    rng = np.random.default_rng(3)
    cases = [(np.array(SWERVE_W), np.array(SWERVE_V), 0.2, 0.2, REST_ENERGETIC)]
    cases += [random_case(rng, 3) for _ in range(15)]
    for W, v, mu, e, rest in cases:
        mode, P, vf, dE = run(v, W, e, mu, rest)
        for t in (0.4, 2.0, -2.9):
            R = rot3(t)
            mode_r, P_r, vf_r, dE_r = run(R @ v, R @ W @ R.T, e, mu, rest)
            assert mode_r == mode
            np.testing.assert_allclose(vf_r, R @ vf, atol=1e-8 * np.linalg.norm(v))


def test_3d_reproduces_2d_for_planar_motion():
    rng = np.random.default_rng(4)
    modes = set()
    for _ in range(60):
        W2, v2, mu, e, rest = random_case(rng, 2)
        m2, P2, vf2, dE2 = run(v2, W2, e, mu, rest, kernel=routh_2d)
        W3, v3 = embed(W2, v2, d=rng.uniform(0.2, 3.0))
        m3, P3, vf3, dE3 = run(v3, W3, e, mu, rest, kernel=routh_3d)
        modes.add(m2)
        assert m3 == m2
        np.testing.assert_allclose(P3[:2], P2, atol=1e-8 * np.linalg.norm(P2) + 1e-14)
        assert abs(P3[2]) <= 1e-12 * np.linalg.norm(P2)
    assert {MODE_SLIP, MODE_SLIP_STICK, MODE_SLIP_REVERSE, MODE_STICK} <= modes


@pytest.mark.parametrize('rest', KINDS)
def test_convergence_with_tol(rest):
    cases = [(SWERVE_V, SWERVE_W, 0.2, 0.2)]
    W, v, _, _, _ = random_case(np.random.default_rng(8), 3)
    cases.append((v, W, 0.7, 0.6))
    for v, W, e, mu in cases:
        v = np.asarray(v, float)
        vs = np.linalg.norm(v)
        best = run(v, W, e, mu, rest, tol=1e-13)[2]
        errs = []
        for tol in (1e-3, 1e-6, 1e-9, 1e-12):
            errs.append(np.linalg.norm(run(v, W, e, mu, rest, tol=tol)[2] - best) / vs)
            assert errs[-1] <= 10 * tol
        assert errs[3] < errs[2] < errs[1] < errs[0]
