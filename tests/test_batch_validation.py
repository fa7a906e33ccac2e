"""The batch kernels' fused validation and energy flags (kernels/batch.py, Law.resolve_batch).

Reference values: NumPy (eigenvalues for positive definiteness, the dE and energy-gain
formulas of DESIGN §3) and the single-contact ``Law.resolve``. No timing is tested."""
import os
import subprocess
import sys

import numpy as np
import pytest

from rbimpact import Law, NoSolutionError
from rbimpact.laws import ENERGY_GAIN_RTOL, SYMMETRY_RTOL

ROD = np.array([[2.5, -1.5], [-1.5, 2.5]])
SPD_MARGIN = 1e-6      # relative eigenvalue margin kept away from the PD boundary (-)


def _spd(rng, d, n, decades=2.0):
    """n random SPD matrices (eigenvalues over ``decades`` decades, random rotations)."""
    out = np.empty((n, d, d))
    for k in range(n):
        Q, _ = np.linalg.qr(rng.normal(size=(d, d)))
        out[k] = Q @ np.diag(10 ** rng.uniform(-decades / 2, decades / 2, d)) @ Q.T
    return 0.5 * (out + np.swapaxes(out, 1, 2))


def _contacts(d, n=40, seed=0):
    rng = np.random.default_rng(seed)
    v = rng.normal(size=(n, d))
    v[:, 0] = -np.abs(v[:, 0]) - 0.1
    return v, _spd(rng, d, n)


@pytest.mark.parametrize("d", [2, 3])
@pytest.mark.parametrize("what,match", [
    ("v_nan", "v must be finite; contact 7"),
    ("W_inf", "W must be finite; contact 7"),
    ("asym", r"W must be symmetric .* contact 7 has asymmetry"),
    ("indefinite", "W must be positive definite; contact 7 has smallest eigenvalue -"),
    ("zero", "W must be positive definite; contact 7"),
])
def test_refused_contact_is_named(d, what, match):
    v, W = _contacts(d)
    if what == "v_nan":
        v[7, 1] = np.nan
    elif what == "W_inf":
        W[7, d - 1, d - 1] = np.inf
    elif what == "asym":
        W[7, 0, 1] += 1e-6 * np.abs(W[7]).max()
    elif what == "indefinite":
        W[7] = np.diag([1.0] + [-0.5] * (d - 1))
    else:
        W[7] = 0.0
    for law in (Law("kane_levinson", e=0.5, mu=0.3), Law("routh", e=0.5, mu=0.3)):
        with pytest.raises(ValueError, match=match):
            law.resolve_batch(v, W)


def test_first_refused_contact_is_reported():
    v, W = _contacts(2)
    W[12] = [[1.0, 2.0], [2.0, 1.0]]
    v[30, 0] = np.inf
    with pytest.raises(ValueError, match="contact 12"):
        Law("brach", e=0.5, mu=0.3).resolve_batch(v, W)


def test_3d_indefinite_with_positive_leading_2x2_minor():
    """W_NN > 0 and the leading 2x2 minor > 0 but det W < 0: refused (third pivot)."""
    W = np.array([[1.0, 0.0, 0.9], [0.0, 1.0, 0.9], [0.9, 0.9, 1.0]])
    assert np.linalg.eigvalsh(W)[0] < 0 and np.linalg.det(W[:2, :2]) > 0
    v, Ws = _contacts(3, n=5)
    Ws[3] = W
    with pytest.raises(ValueError, match="positive definite; contact 3"):
        Law("chatterjee_ruina", e=0.5, mu=0.3).resolve_batch(v, Ws)


@pytest.mark.parametrize("d", [2, 3])
def test_positive_definite_decision_matches_eigenvalues(d):
    """Symmetric W with eigenvalues of both signs: the kernel refuses exactly those whose
    smallest eigenvalue is negative (kept SPD_MARGIN away from 0 relative to the largest)."""
    from rbimpact.kernels.batch import BAD_SPD, kernel_for
    rng = np.random.default_rng(5)
    n = 400
    Q = np.linalg.qr(rng.normal(size=(n, d, d)))[0]
    lam = rng.uniform(-1.0, 1.0, (n, d)) * 10 ** rng.uniform(-3, 3, (n, 1))
    small = np.abs(lam).min(axis=1) < SPD_MARGIN * np.abs(lam).max(axis=1)
    lam[small, 0] = np.abs(lam[small]).max(axis=1)       # away from the boundary
    W = np.einsum("nij,nj,nkj->nik", Q, lam, Q)
    W = 0.5 * (W + np.swapaxes(W, 1, 2))
    v = np.tile(np.r_[-1.0, np.zeros(d - 1)], (n, 1))
    law = Law("kane_levinson", e=0.5, mu=0.3)
    P, vf = np.empty((n, d)), np.empty((n, d))
    dE, gain, mode = np.empty(n), np.empty(n, bool), np.empty(n, np.int64)
    nbad, first, _, _ = kernel_for(law.law_id, d)(
        v, W, law.params[None], law._lo, law._hi, True, SYMMETRY_RTOL, ENERGY_GAIN_RTOL,
        P, vf, dE, gain, mode)
    indefinite = np.linalg.eigvalsh(W)[:, 0] < 0
    assert 0.2 < indefinite.mean() < 0.95
    np.testing.assert_array_equal(mode == BAD_SPD, indefinite)
    assert nbad == indefinite.sum() and first == np.argmax(indefinite)


@pytest.mark.parametrize("d", [2, 3])
@pytest.mark.parametrize("name", ["kane_levinson", "brach", "chatterjee_ruina", "smith"])
def test_dE_and_energy_flags_match_numpy(d, name):
    """dE = P.(v + v_f)/2 and the gain flag dE > ENERGY_GAIN_RTOL * sum |P|(|v|+|v_f|)/2,
    against NumPy on the kernel's P; Kane & Levinson creates energy on some contacts."""
    v, W = _contacts(d, n=300, seed=2)
    v[:, 1:] *= 3.0
    law = Law(name, e=1.0, mu=0.3)
    b = law.resolve_batch(v, W, on_failure="flag")
    ok = b.mode >= 0
    vf = v + np.einsum("nij,nj->ni", W, b.P)
    np.testing.assert_allclose(b.v_f[ok], vf[ok], rtol=0, atol=1e-12 * np.abs(vf).max())
    dE = 0.5 * np.einsum("ni,ni->n", b.P, v + b.v_f)
    np.testing.assert_allclose(b.dE, dE, rtol=1e-12, atol=1e-15)
    gain = dE > ENERGY_GAIN_RTOL * 0.5 * np.sum(np.abs(b.P) * (np.abs(v) + np.abs(b.v_f)), -1)
    np.testing.assert_array_equal(b.energy_gain, gain)
    if name == "kane_levinson":
        assert b.energy_gain.any() and not b.energy_gain.all()
    elif name in ("smith", "chatterjee_ruina"):
        assert not b.energy_gain.any()


def test_validate_false_reads_the_upper_triangle():
    v, W = _contacts(3, n=20, seed=3)
    Wa = W.copy()
    Wa[:, 1, 0] += 0.3                      # lower triangle garbage: not read
    law = Law("routh", e=0.5, mu=0.3)
    with pytest.raises(ValueError, match="symmetric"):
        law.resolve_batch(v, Wa)
    a = law.resolve_batch(v, Wa, validate=False)
    b = law.resolve_batch(v, W)
    np.testing.assert_array_equal(a.P, b.P)


def test_symmetrised_W_matches_single_resolve():
    """An asymmetry within SYMMETRY_RTOL: batch and single resolve use the same (W+W^T)/2."""
    v, W = _contacts(2, n=10, seed=4)
    W[:, 0, 1] *= 1 + 0.5 * SYMMETRY_RTOL
    law = Law("kane_levinson", e=0.5, mu=0.3)
    b = law.resolve_batch(v, W)
    for i in range(10):
        np.testing.assert_array_equal(b.P[i], law.resolve(v[i], W[i]).P)


@pytest.mark.parametrize("name,key,values,match", [
    ("kane_levinson", "mu", (0.3, -1.0), r"contact 5: law 'kane_levinson': parameter 'mu'"),
    ("kane_levinson", "mu", (0.3, np.inf), r"contact 5: .*'mu' must be finite"),
    ("kane_levinson", "e", (0.5, 1.5), r"contact 5: .*'e' must be finite and in \[0, 1\]"),
    ("brach", "e", (-0.5, -1.5), r"contact 5: .*'e' .*\[-1, 1\]"),
    ("routh", "tol", (1e-10, 0.0), r"contact 5: .*'tol'"),
    ("chatterjee_ruina", "e_t", (0.2, np.nan), r"contact 5: .*'e_t'"),
])
def test_per_contact_parameters_checked_in_the_loop(name, key, values, match):
    v, W = _contacts(2, n=9)
    x = np.full(9, values[0])
    law = Law(name, e=0.5, mu=0.3)
    law.resolve_batch(v, W, **{key: x})     # in range: resolves
    x[5] = values[1]
    with pytest.raises(ValueError, match=match):
        law.resolve_batch(v, W, **{key: x})


def test_per_contact_parameters_equal_single_resolves():
    v, W = _contacts(3, n=30, seed=6)
    rng = np.random.default_rng(6)
    e, mu = rng.uniform(0, 1, 30), rng.uniform(0, 1.2, 30)
    rest = np.array(["energetic", "poisson", "newton"])[rng.integers(0, 3, 30)]
    b = Law("routh", e=0.5).resolve_batch(v, W, e=e, mu=mu, restitution=rest,
                                          on_failure="flag")
    for i in range(30):
        try:
            imp = Law("routh", e=e[i], mu=mu[i], restitution=rest[i]).resolve(v[i], W[i])
        except NoSolutionError as exc:
            assert b.mode[i] == exc.mode_code
            continue
        np.testing.assert_array_equal(b.P[i], imp.P)
        assert b.mode[i] == imp.mode_code


_CACHE_SCRIPT = """
import numpy as np
from rbimpact import Law
v = np.array([[-1.0, 0.5], [-0.5, -0.2]])
W = np.array([[[2.5, -1.5], [-1.5, 2.5]]] * 2)
Law("chatterjee_ruina", e=0.5, mu=0.3).resolve_batch(v, W)
"""


def test_batch_entry_compiles_one_law_and_loads_from_disk_cache(tmp_path):
    """A new process resolving a Chatterjee & Ruina 2D batch touches only that law's entry,
    and a second new process loads it from Numba's on-disk cache instead of compiling."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path), NUMBA_DEBUG_CACHE="1")
    if env.get("NUMBA_DISABLE_JIT") == "1":
        pytest.skip("JIT disabled: nothing is cached")
    runs = [subprocess.run([sys.executable, "-c", _CACHE_SCRIPT], env=env, capture_output=True,
                           text=True, check=True).stdout for _ in range(2)]
    for out in runs:
        touched = {line.split("batch.")[1].split("-")[0] for line in out.splitlines()
                   if "batch.batch_" in line}
        assert touched == {"batch_2d_chatterjee_ruina"}, touched
    assert "data saved" in runs[0] and "batch.batch_2d_chatterjee_ruina" in runs[0]
    loaded = [line for line in runs[1].splitlines() if "batch.batch_2d_chatterjee_ruina" in line]
    assert any("data loaded" in line for line in loaded)
    assert not any("data saved" in line for line in loaded)
