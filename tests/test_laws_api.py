"""The public law API: DESIGN §5 reference cases, energy in body space, batch, errors, njit use."""
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from numba import njit

import rbimpact
from rbimpact import Law, NoSolutionError, resolve
from rbimpact.laws import LAWS

ROD = np.array([[2.5, -1.5], [-1.5, 2.5]])
SPHERE2 = np.diag([1.0, 3.5])
SPHERE3 = np.diag([1.0, 3.5, 3.5])
SWERVE_W = np.array([[5.0, 1.0, -1.0], [1.0, 8.0, -2.0], [-1.0, -2.0, 3.0]])
SWERVE_V = np.array([-4.0, -2.0, 1.0])
ALL_LAWS = [("kane_levinson", {}), ("brach", {}), ("smith", {}),
            ("routh", {"restitution": "energetic"}), ("routh", {"restitution": "poisson"}),
            ("routh", {"restitution": "newton"}), ("chatterjee_ruina", {})]
NEVER_GAIN = [("smith", {}), ("chatterjee_ruina", {}), ("chatterjee_ruina", {"e_t": 1.0}),
              ("chatterjee_ruina", {"e_t": -1.0}), ("routh", {"restitution": "energetic"}),
              ("routh", {"restitution": "poisson"})]

# (law, params, v, W, expected P or None, expected v_f or None, expected dE or None)
REFERENCE = [
    *[(name, {**p, "e": 0.5, "mu": 0.3}, [-1, 0], ROD, [0.731707, 0.219512], [0.5, -0.548780],
       -0.243159) for name, p in ALL_LAWS if p.get("restitution") != "newton"],
    *[(name, {"e": 0.5, "mu": 0.8}, [-1, 0], ROD, [0.9375, 0.5625], [0.5, 0.0], None)
      for name in ("routh", "kane_levinson", "brach")],
    ("chatterjee_ruina", {"e": 0.5, "mu": 0.8}, [-1, 0], ROD, None, [0.5, -0.3], None),
    ("kane_levinson", {"e": 1, "mu": 0.3}, [-1, 1], ROD, [0.875, 0.125], [1, 0], 0.0625),
    ("routh", {"e": 1, "mu": 0.3}, [-1, 1], ROD, None, [0.851143, -0.197573], -0.074474),
    ("routh", {"e": 1, "mu": 0.3, "restitution": "poisson"}, [-1, 1], ROD, None,
     [0.789831, -0.175141], None),
    ("smith", {"e": 1, "mu": 0.3}, [-1, 1], ROD, None, [1, -0.433678], None),
    ("chatterjee_ruina", {"e": 1, "mu": 0.3}, [-1, 1], ROD, None, [1, -0.525424], None),
    *[(name, {**p, "e": 0.5, "mu": 0.1}, v, W, P, None, None)
      for name, p in [*ALL_LAWS, ("chatterjee_ruina", {"e_t": 1.0})]
      if p.get("restitution") != "newton"
      for v, W, P in (([-1, 1], SPHERE2, [1.5, -0.15]), ([-1, 1, 0], SPHERE3, [1.5, -0.15, 0]))],
    *[(name, {"e": 0.5, "mu": 0.5}, v, W, None, vf, None)
      for name in ("kane_levinson", "routh", "brach")
      for v, W, vf in (([-1, 1], SPHERE2, [0.5, 0]), ([-1, 1, 0], SPHERE3, [0.5, 0, 0]))],
    ("smith", {"e": 0.5, "mu": 0.5}, [-1, 1], SPHERE2, None, [0.5, -0.517160], None),
    ("chatterjee_ruina", {"e": 0.5, "mu": 0.5, "e_t": 1.0}, [-1, 1], SPHERE2, None, [0.5, -1.0],
     None),
    ("routh", {"e": 0.2, "mu": 0.2}, SWERVE_V, SWERVE_W, None, [0.763128, 0.039953, -0.203942],
     None),
    ("routh", {"e": 0.2, "mu": 0.2, "restitution": "poisson"}, SWERVE_V, SWERVE_W, None,
     [0.735528, 0.038188, -0.202000], None),
    ("kane_levinson", {"e": 0.2, "mu": 0.2}, SWERVE_V, SWERVE_W, None, [0.8, 0, 0], None),
]


@pytest.mark.parametrize("name,params,v,W,P,v_f,dE", REFERENCE)
def test_design_reference_cases(name, params, v, W, P, v_f, dE):
    imp = resolve(name, v, W, **params)
    if P is not None:
        np.testing.assert_allclose(imp.P, P, atol=1e-6)
    if v_f is not None:
        np.testing.assert_allclose(imp.v_f, v_f, atol=1e-6)
    if dE is not None:
        assert imp.dE == pytest.approx(dE, abs=1e-6)
    np.testing.assert_allclose(imp.v_f, np.asarray(v, float) + np.asarray(W) @ imp.P,
                               atol=1e-14)


def test_case_1b_energy_gain_is_reported():
    imp = resolve("kane_levinson", [-1, 1], ROD, e=1, mu=0.3)
    assert imp.mode == "stick" and imp.energy_gain and imp.dE == pytest.approx(0.0625)
    for name, p in NEVER_GAIN:
        assert not resolve(name, [-1, 1], ROD, e=1, mu=0.3, **p).energy_gain


def test_routh_phases():
    assert resolve("routh", [-1, 0], ROD, e=0.5, mu=0.8).phases == ("stick",)
    assert resolve("routh", [-1, 0.1], ROD, e=0.5, mu=0.8).phases == ("slip", "stick")
    assert resolve("routh", [-1, 1], SPHERE2, e=0.5, mu=0.5).phases == ("slip", "stick")
    assert resolve("routh", [-1, 1], SPHERE2, e=0.5, mu=0.1).phases == ("slip",)
    sep = resolve("routh", [0.5, 1], ROD, e=0.5, mu=0.3)
    assert sep.mode == "separating" and not sep.P.any() and sep.dE == 0.0


# ---- energy identity in body space ------------------------------------------------------

def _cross2(a, b):
    return a[0] * b[1] - a[1] * b[0]


def random_two_bodies_2d(rng):
    """Two rigid bodies in contact (B static or not): W and v from body quantities."""
    phi = rng.uniform(0, 2 * np.pi)
    n = np.array([np.cos(phi), np.sin(phi)])
    basis = [n, np.array([n[1], -n[0]])]
    bodies = []
    for sign in (1.0, -1.0):
        if sign < 0 and rng.random() < 0.3:
            break  # B static
        m = 10 ** rng.uniform(-1, 1)
        bodies.append(dict(sign=sign, m=m, I=m * 10 ** rng.uniform(-2, 0),
                           r=rng.uniform(-1, 1, 2), vel=rng.normal(size=2),
                           w=rng.normal()))
    J = [np.array([[b["sign"] * e[0], b["sign"] * e[1], b["sign"] * _cross2(b["r"], e)]
                   for e in basis]) for b in bodies]
    W = sum(j @ np.diag([1 / b["m"], 1 / b["m"], 1 / b["I"]]) @ j.T for j, b in zip(J, bodies))
    v = sum(j @ np.r_[b["vel"], b["w"]] for j, b in zip(J, bodies))
    return bodies, basis, J, W, v


def kinetic_2d(bodies, q):
    return sum(0.5 * b["m"] * qi[:2] @ qi[:2] + 0.5 * b["I"] * qi[2] ** 2 for b, qi in zip(bodies, q))


@pytest.mark.parametrize("name,params", ALL_LAWS)
def test_energy_identity_in_body_space_2d(name, params):
    rng = np.random.default_rng(7)
    checked = 0
    for _ in range(200):
        bodies, basis, J, W, v = random_two_bodies_2d(rng)
        if v[0] >= 0:  # v is linear in the body velocities: reverse them all to approach
            for b in bodies:
                b["vel"], b["w"] = -b["vel"], -b["w"]
            v = -v
        law = Law(name, e=rng.uniform(0, 1), mu=rng.uniform(0, 1.5), **params)
        try:
            imp = law.resolve(v, W)
        except NoSolutionError:
            continue
        q0 = [np.r_[b["vel"], b["w"]] for b in bodies]
        q1 = [q + np.diag([1 / b["m"], 1 / b["m"], 1 / b["I"]]) @ j.T @ imp.P
              for q, j, b in zip(q0, J, bodies)]
        dK = kinetic_2d(bodies, q1) - kinetic_2d(bodies, q0)
        scale = kinetic_2d(bodies, q0) + kinetic_2d(bodies, q1)
        assert imp.dE == pytest.approx(dK, abs=1e-10 * scale)
        np.testing.assert_allclose(sum(j @ q for j, q in zip(J, q1)), imp.v_f,
                                   atol=1e-10 * (1 + np.abs(v).max()))
        checked += 1
    assert checked > 150


def random_spd(rng, d, decades=2.0):
    A = rng.normal(size=(d, d))
    Q, _ = np.linalg.qr(A)
    return Q @ np.diag(10 ** rng.uniform(-decades / 2, decades / 2, d)) @ Q.T


@pytest.mark.parametrize("name,params", ALL_LAWS)
def test_energy_identity_3d_and_rotation_invariance(name, params):
    """3D: dE = P.(v+v_f)/2 = the change of (1/2) v^T W^-1 v along v_f = v + W P (the
    contact-space kinetic energy), and every law is isotropic in the tangent plane."""
    rng = np.random.default_rng(11)
    checked = 0
    for _ in range(60):
        W = random_spd(rng, 3)
        v = rng.normal(size=3)
        v[0] = -abs(v[0]) - 0.05
        law = Law(name, e=rng.uniform(0, 1), mu=rng.uniform(0, 1.5), **params)
        try:
            imp = law.resolve(v, W)
        except NoSolutionError:
            continue
        M = np.linalg.inv(W)
        K = lambda u: 0.5 * u @ M @ u  # noqa: E731 (relative KE minus a constant shift)
        # dE equals the change of the kinetic energy of relative motion measured by M
        assert imp.dE == pytest.approx(K(imp.v_f) - K(v), abs=1e-9 * (K(v) + K(imp.v_f)))
        a = rng.uniform(0, 2 * np.pi)
        R = np.eye(3)
        R[1:, 1:] = [[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]]
        rot = law.resolve(R @ v, R @ W @ R.T)
        np.testing.assert_allclose(rot.P, R @ imp.P, atol=1e-7 * (1 + np.abs(imp.P).max()))
        assert rot.mode_code == imp.mode_code
        checked += 1
    assert checked > 40


@settings(max_examples=150, deadline=None)
@given(st.integers(0, len(NEVER_GAIN) - 1), st.integers(2, 3), st.integers(0, 2 ** 32 - 1),
       st.floats(0, 1), st.floats(0, 3))
def test_never_creates_energy(k, d, seed, e, mu):
    name, params = NEVER_GAIN[k]
    rng = np.random.default_rng(seed)
    W = random_spd(rng, d, decades=3)
    v = rng.normal(size=d) * 10 ** rng.uniform(-2, 2)
    v[0] = -abs(v[0]) - 1e-3
    try:
        imp = Law(name, e=e, mu=mu, **params).resolve(v, W)
    except NoSolutionError:
        return
    assert not imp.energy_gain, (name, params, imp)
    assert np.all(np.isfinite(imp.P))


# ---- batch ------------------------------------------------------------------------------

@pytest.mark.parametrize("d", [2, 3])
@pytest.mark.parametrize("name,params", ALL_LAWS)
def test_batch_equals_single(name, params, d):
    rng = np.random.default_rng(3)
    n = 64
    W = np.array([random_spd(rng, d) for _ in range(n)])
    v = rng.normal(size=(n, d))
    v[:5, 0] = np.abs(v[:5, 0])  # a few separating contacts
    mu = rng.uniform(0, 1, n)
    law = Law(name, e=0.6, mu=0.0, **params)
    batch = law.resolve_batch(v, W, mu=mu, on_failure="flag")
    for i in range(n):
        one = Law(name, e=0.6, mu=mu[i], **params)
        try:
            imp = one.resolve(v[i], W[i])
        except NoSolutionError as exc:
            assert batch.mode[i] == exc.mode_code
            continue
        np.testing.assert_array_equal(batch.P[i], imp.P)
        assert batch.mode[i] == imp.mode_code
        assert batch.dE[i] == pytest.approx(imp.dE, rel=1e-12, abs=1e-15)
        assert batch.energy_gain[i] == imp.energy_gain
    assert batch.mode_names[0] == "separating"


def test_batch_raises_on_failure_by_default():
    v = np.array([[-1.0, 1.0]])
    W = ROD[None]
    batch = Law("routh", e=0.5, mu=0.3).resolve_batch(v, W)
    assert batch.mode[0] == 4 and batch.mode_names == ["slip"]  # slip, then reversed slip
    with pytest.raises(ValueError, match="shape"):
        Law("routh", e=0.5).resolve_batch(v, W, mu=np.ones(3))
    with pytest.raises(ValueError, match="'mu'"):
        Law("routh", e=0.5).resolve_batch(v, W, mu=np.array([-1.0]))


# ---- errors -----------------------------------------------------------------------------

@pytest.mark.parametrize("args,kwargs,match", [
    (("nope",), {"e": 0.5}, "unknown law"),
    (("smith",), {"e": 0.5, "e_t": 0.1}, "takes no parameter 'e_t'"),
    (("smith",), {"mu": 0.1}, "'e' is required"),
    (("kane_levinson",), {"e": 1.5}, r"'e' must be finite and in \[0, 1\]"),
    (("kane_levinson",), {"e": -0.5}, r"\[0, 1\]"),
    (("brach",), {"e": -1.5}, r"\[-1, 1\]"),
    (("brach",), {"e": 0.5, "e_t": 2}, "'e_t'"),
    (("routh",), {"e": 0.5, "mu": -0.1}, "'mu'"),
    (("routh",), {"e": 0.5, "mu": np.inf}, "'mu'"),
    (("routh",), {"e": np.nan}, "'e'"),
    (("routh",), {"e": 0.5, "restitution": "plastic"}, "restitution must be one of"),
    (("routh",), {"e": 0.5, "tol": 0.0}, "'tol'"),
    (("routh",), {"e": "x"}, "real number"),
])
def test_bad_parameters(args, kwargs, match):
    with pytest.raises(ValueError, match=match):
        Law(*args, **kwargs)


@pytest.mark.parametrize("v,W,match", [
    ([-1, 0, 0, 0], np.eye(4), "length 2"),
    ([-1, 0], np.eye(3), r"shape \(2, 2\)"),
    ([-1, np.nan], ROD, "finite"),
    ([-1, 0], [[1, np.inf], [np.inf, 1]], "finite"),
    ([-1, 0], [[1, 0.5], [0.2, 1]], "symmetric"),
    ([-1, 0], [[1, 2], [2, 1]], "positive definite"),
    ([-1, 0], [[0, 0], [0, 0]], "positive definite"),
])
def test_bad_contacts(v, W, match):
    with pytest.raises(ValueError, match=match):
        resolve("kane_levinson", v, W, e=0.5, mu=0.3)


def test_routh_no_solution_raises():
    """A strongly coupled 3D contact: with mu = 7.5 the normal velocity, while sliding,
    falls back to zero during restitution (a second compression), which Routh's kernel
    reports as no solution (kernels/routh.py); with mu = 3 it resolves. (A positive
    definite W never jams Routh in compression: see the kernel's docstring.)"""
    W = np.array([[0.178, -0.179, -0.096], [-0.179, 0.217, 0.084], [-0.096, 0.084, 0.062]])
    v = np.array([-0.5, 1.0, -0.4])
    assert Law("routh", e=0.5, mu=3.0).resolve(v, W).P[0] > 0
    law = Law("routh", e=0.5, mu=7.5)
    with pytest.raises(NoSolutionError, match="no solution") as info:
        law.resolve(v, W)
    assert info.value.mode_code == -1
    flagged = law.resolve_batch(v[None], W[None], on_failure="flag")
    assert flagged.mode[0] == -1 and not flagged.P.any()
    np.testing.assert_array_equal(flagged.v_f[0], v)
    with pytest.raises(NoSolutionError, match="1 of 1 contacts failed"):
        law.resolve_batch(v[None], W[None])


# ---- use from a user's njit code ----------------------------------------------------------

def test_kernel_in_user_njit_loop():
    law = Law("chatterjee_ruina", e=0.5, mu=0.3, e_t=0.2)
    kernel, params = law.kernel, law.params

    @njit
    def user_loop(vs, W, out):
        P = np.zeros(2)
        modes = 0
        for i in range(vs.shape[0]):
            modes += kernel(vs[i], W, params, P)
            out[i, 0] = P[0]
            out[i, 1] = P[1]
        return modes

    rng = np.random.default_rng(1)
    vs = rng.normal(size=(50, 2))
    vs[:, 0] = -np.abs(vs[:, 0])
    out = np.empty((50, 2))
    user_loop(vs, ROD, out)
    for i in range(50):
        np.testing.assert_array_equal(out[i], law.resolve(vs[i], ROD).P)


def test_import_is_light():
    code = ("import sys, rbimpact; rbimpact.Law('smith', e=0.5);"
            "print(any(m in sys.modules for m in ('pymunk', 'matplotlib', 'numba')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
    assert set(rbimpact.__all__) >= {"Law", "resolve", "NoSolutionError"}
    assert set(LAWS) == {"kane_levinson", "brach", "smith", "routh", "chatterjee_ruina"}
