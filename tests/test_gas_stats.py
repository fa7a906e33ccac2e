"""rbimpact.gas_stats alone: Maxwell-Boltzmann laws and test, Enskog collision frequency,
Haff's law and its fit, each checked on synthetic samples or by Monte Carlo."""
import math

import numpy as np
import pytest
from scipy import integrate, stats

from rbimpact import gas_stats as gs

#: significance of the Maxwell-Boltzmann test in these tests
ALPHA = 0.01
#: Monte Carlo checks agree within this many standard errors
N_SE = 4.0


# ------------------------------------------------------------------ Maxwell-Boltzmann

@pytest.mark.parametrize("dim", [2, 3])
def test_speed_pdf_is_rayleigh_or_maxwell_and_normalised(dim):
    T, m = 1.7, 0.6
    a = math.sqrt(T / m)
    s = np.linspace(0, 8 * a, 2001)
    ref = (stats.rayleigh(scale=a) if dim == 2 else stats.maxwell(scale=a)).pdf(s)
    np.testing.assert_allclose(gs.speed_pdf(s, T, m, dim), ref, rtol=1e-12, atol=1e-300)
    assert integrate.quad(lambda x: gs.speed_pdf(x, T, m, dim), 0, np.inf)[0] == \
        pytest.approx(1.0, rel=1e-10)
    cdf = gs.speed_cdf(s, T, m, dim)
    ref_cdf = (stats.rayleigh(scale=a) if dim == 2 else stats.maxwell(scale=a)).cdf(s)
    np.testing.assert_allclose(cdf, ref_cdf, rtol=1e-10, atol=1e-14)
    # <m s^2> / dim = T
    assert integrate.quad(lambda x: m * x * x * gs.speed_pdf(x, T, m, dim), 0, np.inf)[0] \
        / dim == pytest.approx(T, rel=1e-10)


def test_component_pdf_and_temperature():
    T, m = 0.3, 2.0
    assert integrate.quad(lambda u: gs.component_pdf(u, T, m), -np.inf, np.inf)[0] == \
        pytest.approx(1.0, rel=1e-10)
    v = np.array([[1.0, 0.0], [-1.0, 0.0], [0.0, 2.0], [0.0, -2.0]])
    assert gs.temperature(v, mass=m) == pytest.approx(m * (1 + 1 + 4 + 4) / 4 / 2)
    # a drift is not temperature; snapshots (ns, n, dim) are pooled
    assert gs.temperature(v + 5.0, mass=m) == pytest.approx(gs.temperature(v, mass=m))
    assert gs.temperature(np.stack([v, v]), mass=m) == pytest.approx(gs.temperature(v, m))


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_maxwellian_samples_pass(dim, seed):
    rng = np.random.default_rng(seed)
    T, m = 2.5, 0.7
    v = rng.normal(scale=math.sqrt(T / m), size=(20000, dim))
    r = gs.maxwell_boltzmann_test(v, mass=m)
    assert r.passed(ALPHA), r.summary()
    assert r.T == pytest.approx(T, rel=0.03)
    assert np.all(np.abs(r.kurtosis) < N_SE * r.kurtosis_se)
    # against the true temperature as well
    assert gs.maxwell_boltzmann_test(v, mass=m, T=T).passed(ALPHA)


def test_false_rejections_are_rare():
    """Under the hypothesis the (Bonferroni, fitted-variance) test rejects at most about
    alpha of the time: over 100 Maxwellian samples, at most 5 at alpha = 0.05."""
    rng = np.random.default_rng(7)
    p = [gs.maxwell_boltzmann_test(rng.normal(size=(2000, 2))).p_value for _ in range(100)]
    assert sum(x < 0.05 for x in p) <= 5


@pytest.mark.parametrize("dim", [2, 3])
def test_non_maxwellian_samples_fail(dim):
    rng = np.random.default_rng(3)
    n = 20000
    uniform = rng.uniform(-1, 1, size=(n, dim))
    r = gs.maxwell_boltzmann_test(uniform)
    assert not r.passed(ALPHA) and r.p_value < 1e-10
    assert np.allclose(r.kurtosis, -1.2, atol=N_SE * r.kurtosis_se)
    # equal speeds in random directions (the start of a relaxation run)
    d = rng.normal(size=(n, dim))
    ring = d / np.linalg.norm(d, axis=1, keepdims=True)
    assert gs.maxwell_boltzmann_test(ring).p_value < 1e-10
    # a Maxwellian at the wrong temperature, when the temperature is given
    v = rng.normal(size=(n, dim))
    assert not gs.maxwell_boltzmann_test(v, T=1.1).passed(ALPHA)
    # a small admixture of a hot population (heavy tails)
    hot = np.where(rng.uniform(size=(n, 1)) < 0.1, 3.0, 1.0) * v
    assert not gs.maxwell_boltzmann_test(hot).passed(ALPHA)


def test_kurtosis_of_known_laws():
    rng = np.random.default_rng(4)
    n = 200000
    se = math.sqrt(24.0 / n)
    assert np.all(np.abs(gs.excess_kurtosis(rng.normal(size=(n, 3)))) < N_SE * se)
    ang = rng.uniform(0, 2 * np.pi, n)
    k = gs.excess_kurtosis(np.c_[np.cos(ang), np.sin(ang)])
    np.testing.assert_allclose(k, -1.5, atol=0.02)


# ------------------------------------------------------------------ collision frequency

@pytest.mark.parametrize("dim", [2, 3])
def test_mean_relative_speed_monte_carlo(dim):
    rng = np.random.default_rng(5)
    T, m, n = 1.3, 0.8, 400000
    sd = math.sqrt(T / m)
    g = np.linalg.norm(rng.normal(scale=sd, size=(n, dim)) - rng.normal(scale=sd, size=(n, dim)),
                       axis=1)
    assert abs(g.mean() - gs.mean_relative_speed(T, m, dim)) < N_SE * g.std() / math.sqrt(n)
    closed = math.sqrt(math.pi * T / m) if dim == 2 else 4.0 * math.sqrt(T / (math.pi * m))
    assert gs.mean_relative_speed(T, m, dim) == pytest.approx(closed, rel=1e-14)


@pytest.mark.parametrize("dim", [2, 3])
def test_boltzmann_frequency_closed_forms(dim):
    n, sigma, T, m = 0.05, 1.3, 2.0, 1.7
    closed = (2 * n * sigma * math.sqrt(math.pi * T / m) if dim == 2
              else 4 * n * sigma ** 2 * math.sqrt(math.pi * T / m))
    assert gs.boltzmann_frequency(n, sigma, T, m, dim) == pytest.approx(closed, rel=1e-14)
    # van Noije & Ernst (1998) eq. 2.7: Omega_d / sqrt(2 pi) n sigma^(d-1) v0, v0 = sqrt(2T/m)
    omega_d = 2 * math.pi ** (dim / 2) / math.gamma(dim / 2)
    vne = omega_d / math.sqrt(2 * math.pi) * n * sigma ** (dim - 1) * math.sqrt(2 * T / m)
    assert gs.boltzmann_frequency(n, sigma, T, m, dim) == pytest.approx(vne, rel=1e-14)


@pytest.mark.parametrize("dim", [2, 3])
def test_boltzmann_frequency_monte_carlo_ideal_gas(dim):
    """Count first contacts (centre distance dropping below sigma) of non-interacting
    Maxwellian particles in a periodic box over a short time: the dilute collision rate
    per particle is (N - 1)/V * cross-section * <|g|>, the Boltzmann frequency."""
    rng = np.random.default_rng(11 + dim)
    N, L, sigma, T, m, dt, trials = 1500, 60.0 if dim == 2 else 25.0, 1.0, 1.0, 1.0, 3.0, 8
    count = 0
    iu = np.triu_indices(N, 1)
    for _ in range(trials):
        x = rng.uniform(0, L, size=(N, dim))
        v = rng.normal(scale=math.sqrt(T / m), size=(N, dim))
        r = x[iu[1]] - x[iu[0]]
        r -= L * np.round(r / L)                           # minimum image
        g = v[iu[1]] - v[iu[0]]
        ts = np.clip(-np.sum(r * g, axis=1) / np.sum(g * g, axis=1), 0.0, dt)
        dmin2 = np.sum((r + g * ts[:, None]) ** 2, axis=1)
        count += int(np.count_nonzero((np.sum(r * r, axis=1) > sigma ** 2)
                                      & (dmin2 < sigma ** 2)))
    measured = gs.collision_frequency(count, N, trials * dt)
    expect = gs.boltzmann_frequency((N - 1) / L ** dim, sigma, T, m, dim)
    assert abs(measured / expect - 1.0) < N_SE / math.sqrt(count), (measured, expect, count)


def test_contact_values_and_dilute_limit():
    # eta -> 0: Enskog is Boltzmann
    for dim in (2, 3):
        assert gs.contact_value(0.0, dim) == 1.0
        n = gs.number_density(1e-9, 1.0, dim)
        assert gs.enskog_frequency(n, 1.0, 1.0, 1.0, dim) == pytest.approx(
            gs.boltzmann_frequency(n, 1.0, 1.0, 1.0, dim), rel=1e-8)
        assert gs.packing_fraction(gs.number_density(0.15, 0.7, dim), 0.7, dim) == \
            pytest.approx(0.15, rel=1e-14)
    # slopes at eta = 0 against the exact virial series (2D: B3 of hard disks,
    # Z = 1 + 2 eta + 4 (4/3 - sqrt(3)/pi) eta^2, so g = 1 + 2 (4/3 - sqrt(3)/pi) eta;
    # 3D: Z = 1 + 4 eta + 10 eta^2 + 18.365 eta^3, g = 1 + 2.5 eta + 4.591 eta^2)
    h = 1e-6
    slope2 = (gs.contact_value(h, 2) - 1) / h
    assert slope2 == pytest.approx(2 * (4 / 3 - math.sqrt(3) / math.pi), rel=2e-3)
    slope3 = (gs.contact_value(h, 3) - 1) / h
    assert slope3 == pytest.approx(2.5, rel=1e-5)
    # the formulas at eta = 0.15
    assert gs.contact_value(0.15, 2) == pytest.approx((1 - 7 * 0.15 / 16) / 0.85 ** 2)
    assert gs.contact_value(0.15, 3) == pytest.approx((1 - 0.15 / 2) / 0.85 ** 3)
    with pytest.raises(ValueError):
        gs.contact_value(1.0, 2)
    with pytest.raises(ValueError):
        gs.contact_value(0.1, 4)


def test_bulk_collision_frequency_counts_the_bulk_only():
    box = np.array([10.0, 10.0])
    pos = np.array([[[1.0, 1.0], [5.0, 5.0], [6.0, 6.0], [9.5, 5.0]]])   # 2 of 4 in bulk
    contacts = np.array([[5.5, 5.5], [0.5, 0.5], [7.0, 3.0]])           # 2 of 3 in bulk
    omega, omega_e, n_bulk, count = gs.bulk_collision_frequency(
        contacts, pos, box, 2.0, 4.0, 1.0, 1.0)
    assert count == 2 and n_bulk == pytest.approx(2 / 36)
    assert omega == pytest.approx(2 * 2 / (2 * 4.0))
    assert omega_e == pytest.approx(gs.enskog_frequency(2 / 36, 1.0, 1.0))


# ------------------------------------------------------------------ Haff's law

@pytest.mark.parametrize("dim", [2, 3])
def test_energy_loss_per_collision_is_one_minus_e2_times_T(dim):
    """Monte Carlo over the collision kernel (pairs weighted by their approach speed
    g_n = -g.n > 0): <(1 - e^2) m g_n^2 / 4> = (1 - e^2) T, the factor in Haff's tau."""
    rng = np.random.default_rng(21)
    T, m, e, n = 0.9, 1.4, 0.8, 400000
    sd = math.sqrt(T / m)
    g = rng.normal(scale=sd, size=(n, dim)) - rng.normal(scale=sd, size=(n, dim))
    k = rng.normal(size=(n, dim))
    k /= np.linalg.norm(k, axis=1, keepdims=True)
    gn = np.maximum(-np.sum(g * k, axis=1), 0.0)          # the rate weight
    loss = (1 - e * e) * m * gn ** 2 / 4.0
    mean = np.sum(gn * loss) / np.sum(gn)
    assert mean == pytest.approx((1 - e * e) * T, rel=0.01)


def test_haff_tau_and_law_solve_the_cooling_equation():
    """T(t) = T0/(1 + t/tau)^2 solves dT/dt = -(1 - e^2) omega_E(T) T / dim."""
    e, n, sigma, T0, m = 0.9, 0.1, 1.0, 2.0, 1.0
    for dim in (2, 3):
        tau = gs.haff_tau(e, n, sigma, T0, m, dim)
        sol = integrate.solve_ivp(
            lambda t, y: [-(1 - e * e) * gs.enskog_frequency(n, sigma, y[0], m, dim)
                          * y[0] / dim], (0, 5 * tau), [T0], rtol=1e-11, atol=1e-14,
            dense_output=True)
        t = np.linspace(0, 5 * tau, 50)
        np.testing.assert_allclose(sol.sol(t)[0], gs.haff_temperature(t, T0, tau),
                                   rtol=1e-8)
    assert gs.haff_tau(1.0, n, sigma, T0) == math.inf
    with pytest.raises(ValueError):
        gs.haff_tau(1.2, n, sigma, T0)


@pytest.mark.parametrize("fix_T0", [False, True])
def test_fit_haff_recovers_tau(fix_T0):
    rng = np.random.default_rng(8)
    T0, tau = 3.0, 12.5
    t = np.linspace(0, 8 * tau, 300)
    noise = 0.02    # relative, as ~sqrt(2/(dim N)) for N ~ 2500 disks
    T = gs.haff_temperature(t, T0, tau) * np.exp(rng.normal(0, noise, t.size))
    fit = gs.fit_haff(t, T, T0=T0 if fix_T0 else None)
    assert fit.tau == pytest.approx(tau, rel=0.02)
    assert abs(fit.tau - tau) < N_SE * fit.tau_se
    assert fit.T0 == pytest.approx(T0, rel=0.02)
    assert fit.rms == pytest.approx(noise, rel=0.2)
    # exact data: exact tau
    exact = gs.fit_haff(t, gs.haff_temperature(t, T0, tau))
    assert exact.tau == pytest.approx(tau, rel=1e-8)
    assert exact.T0 == pytest.approx(T0, rel=1e-8)
