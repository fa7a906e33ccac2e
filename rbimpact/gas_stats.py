"""Kinetic theory of hard-disk (2D) and hard-sphere (3D) gases, for checking many-body runs.

Pure NumPy/SciPy (``scipy.stats`` and ``scipy.optimize`` are imported inside the functions
that use them, so importing this module is cheap). Units are SI-like but arbitrary: lengths
in m, masses in kg, time in s, with Boltzmann's constant k_B = 1, so a temperature is an
energy (J) and, for bodies of mass m,

    T = m <|v - <v>|^2> / dim          (granular temperature; kinetic energy dim T / 2 per body)

**Maxwell-Boltzmann** (equilibrium of an elastic gas). Every velocity component is normal
with mean 0 and variance T/m; the speed s = |v| follows a chi distribution with ``dim``
degrees of freedom and scale a = sqrt(T/m): Rayleigh in 2D, f(s) = (s/a^2) exp(-s^2/2a^2),
and Maxwell in 3D, f(s) = sqrt(2/pi) (s^2/a^3) exp(-s^2/2a^2) (e.g. Reif, *Fundamentals of
statistical and thermal physics*, 1965, sec. 7.10). ``maxwell_boltzmann_test`` is a
Kolmogorov-Smirnov test of each component and of the speeds against these laws at the
measured temperature, with the excess kurtosis of the components (0 for a normal).

**Collision frequency.** Per particle, for identical smooth hard particles of diameter
sigma at number density n (Chapman & Cowling, *The mathematical theory of non-uniform
gases*, 3rd ed. 1970, sec. 5.21 and 16.3; in d dimensions: van Noije & Ernst, Granular
Matter 1, 57 (1998), eq. 2.7, omega = Omega_d / sqrt(2 pi) n sigma^(d-1) chi v0 with
v0 = sqrt(2T/m) and Omega_d = 2 pi^(d/2) / Gamma(d/2)):

    Boltzmann (dilute):  omega_B = n * S * <|g|>,  g = v_1 - v_2 the relative velocity,
        S the collision cross-section: 2 sigma (a length) for disks, pi sigma^2 for
        spheres; <|g|> = sqrt(pi T/m) in 2D (g is normal with variance 2T/m per
        component: Rayleigh with scale sqrt(2T/m)), 4 sqrt(T/(pi m)) in 3D, hence
            2D: omega_B = 2 n sigma sqrt(pi T/m),  3D: omega_B = 4 n sigma^2 sqrt(pi T/m)
    Enskog (dense):      omega_E = g(sigma) * omega_B,
        g(sigma) the pair correlation at contact at packing fraction eta:
            2D (Henderson, Mol. Phys. 30, 971 (1975)): g = (1 - 7 eta/16) / (1 - eta)^2
            3D (Carnahan & Starling, J. Chem. Phys. 51, 635 (1969)): g = (1 - eta/2)/(1 - eta)^3
        eta = n pi sigma^2 / 4 (2D), n pi sigma^3 / 6 (3D).

In equilibrium the Enskog frequency is exact given the exact g(sigma) (the collision rate
is the Maxwellian flux through contact), so its only approximation is g: Henderson and
Carnahan-Starling reproduce the exact second virial term of g (2D: 1 + 1.5625 eta against
the exact 1 + 1.5640 eta; 3D: 1 + 2.5 eta + 4.5 eta^2 against 1 + 2.5 eta + 4.59 eta^2).
In a simulation: omega = 2 * (body-body collisions) / (N * t); wall hits are not counted,
and walls raise the density next to them and lower it in the bulk, so compare in the bulk
(``bulk_collision_frequency``) or with a density measured where the collisions are counted.

**Haff's law** (P. K. Haff, J. Fluid Mech. 134, 401 (1983); Brilliantov & Poeschel,
*Kinetic theory of granular gases*, Oxford 2004, ch. 6-7). In a homogeneous gas of smooth
particles with constant restitution e, a collision with normal relative speed g_n loses
(1 - e^2) m g_n^2 / 4 (reduced mass m/2). Collisions sample g_n weighted by g_n itself:
for a Maxwellian, g_n is then Rayleigh with scale sqrt(2T/m), so <g_n^2>_coll = 4T/m and a
collision loses (1 - e^2) T on average, in any dimension. With N omega / 2 collisions per
unit time and energy N dim T / 2:

    dT/dt = -(1 - e^2) omega(T) T / dim,   omega(T) = omega_E(T0) sqrt(T/T0)
    =>  T(t) = T0 / (1 + t/tau)^2,          1/tau = (1 - e^2) omega_E(T0) / (2 dim)

(van Noije & Ernst 1998: dT/dt = -2 gamma0 omega T with gamma0 = (1 - e^2)/(2d), the same).
The second Sonine correction a2 of the homogeneous cooling state changes the rate by
(1 + 3 a2 / 16), below 1 % for e >= 0.8 (|a2| < 0.03); it is neglected here. Haff's law
holds until clusters and vortices form (the homogeneous cooling state is unstable in
systems larger than a length that grows as 1/sqrt(1 - e^2) mean free paths).
"""
import math
from dataclasses import dataclass

import numpy as np

__all__ = ["temperature", "speeds", "speed_pdf", "speed_cdf", "component_pdf",
           "excess_kurtosis", "maxwell_boltzmann_test", "MBTest",
           "packing_fraction", "number_density", "contact_value",
           "boltzmann_frequency", "enskog_frequency", "collision_frequency",
           "bulk_collision_frequency", "replay_contacts", "mean_relative_speed",
           "haff_tau", "haff_temperature", "fit_haff", "HaffFit"]

#: significance level used by ``MBTest.passed`` unless told otherwise
MB_ALPHA = 0.01


# ------------------------------------------------------------------ Maxwell-Boltzmann

def _velocities(v):
    v = np.asarray(v, dtype=float)
    if v.ndim == 3:                        # snapshots (ns, n, dim): pool them
        v = v.reshape(-1, v.shape[-1])
    if v.ndim != 2 or v.shape[1] not in (1, 2, 3):
        raise ValueError(f"velocities must be an (n, dim) or (ns, n, dim) array with dim "
                         f"1, 2 or 3; got shape {np.shape(v)}")
    if v.shape[0] < 2:
        raise ValueError("need at least 2 velocities")
    return v


def _masses(mass, n):
    m = np.broadcast_to(np.asarray(mass, dtype=float), (n,)) if np.ndim(mass) else None
    return float(mass) if m is None else m


def temperature(v, mass=1.0, subtract_mean=True):
    """Granular temperature T = m <|v - <v>|^2> / dim (J, k_B = 1) of velocities ``v``
    (m/s; (n, dim), or snapshots (ns, n, dim) pooled); ``mass`` (kg) a scalar or one per
    row. ``subtract_mean``: measure velocities relative to their mean (the gas's drift)."""
    v = _velocities(v)
    if subtract_mean:
        v = v - v.mean(axis=0)
    m = _masses(mass, v.shape[0])
    return float(np.mean(m * np.sum(v * v, axis=1)) / v.shape[1])


def speeds(v):
    """|v| of each row (m/s)."""
    return np.sqrt(np.sum(np.square(_velocities(v)), axis=1))


def speed_pdf(s, T, mass=1.0, dim=2):
    """Maxwell-Boltzmann density of the speed s (m/s) at temperature T (J), per m/s:
    chi distribution with ``dim`` degrees of freedom and scale sqrt(T/m) (Rayleigh in 2D,
    Maxwell in 3D)."""
    s = np.asarray(s, dtype=float)
    a2 = T / mass
    c = 2.0 / (math.gamma(dim / 2.0) * (2.0 * a2) ** (dim / 2.0))
    return np.where(s >= 0, c * np.abs(s) ** (dim - 1) * np.exp(-s * s / (2.0 * a2)), 0.0)


def speed_cdf(s, T, mass=1.0, dim=2):
    """Cumulative distribution of the Maxwell-Boltzmann speed: P(|v| <= s) =
    P(dim/2, m s^2 / 2T) (regularised lower incomplete gamma function)."""
    from scipy.special import gammainc
    s = np.asarray(s, dtype=float)
    return np.where(s > 0, gammainc(dim / 2.0, mass * s * s / (2.0 * T)), 0.0)


def component_pdf(u, T, mass=1.0):
    """Density of one velocity component u (m/s): normal, mean 0, variance T/m."""
    u = np.asarray(u, dtype=float)
    return np.exp(-mass * u * u / (2.0 * T)) / math.sqrt(2.0 * math.pi * T / mass)


def excess_kurtosis(v):
    """Excess kurtosis <u^4>/<u^2>^2 - 3 of each velocity component (about its mean),
    shape (dim,): 0 for Maxwell-Boltzmann, -1.2 for a uniform distribution, -1.5 for equal
    speeds in random directions in 2D (u = cos of a uniform angle). Its standard error for n normal samples is sqrt(24/n)."""
    v = _velocities(v)
    u = v - v.mean(axis=0)
    m2 = np.mean(u * u, axis=0)
    return np.mean(u ** 4, axis=0) / (m2 * m2) - 3.0


@dataclass(frozen=True)
class MBTest:
    """Result of ``maxwell_boltzmann_test``.

    ``T`` (J) the temperature tested against, ``n`` samples, ``dim``; ``component_stat``,
    ``component_p`` (dim,): Kolmogorov-Smirnov statistic and p-value of each velocity
    component against N(0, T/m); ``speed_stat``, ``speed_p``: the same for the speeds
    against the chi (Rayleigh/Maxwell) law; ``kurtosis`` (dim,) the excess kurtosis of the
    components and ``kurtosis_se`` its standard error sqrt(24/n) under the hypothesis;
    ``p_value``: Bonferroni combination min(1, (dim + 1) * min p) of the dim + 1 KS tests,
    valid although they are dependent.
    """

    T: float
    n: int
    dim: int
    component_stat: np.ndarray
    component_p: np.ndarray
    speed_stat: float
    speed_p: float
    kurtosis: np.ndarray
    kurtosis_se: float
    p_value: float

    def passed(self, alpha=MB_ALPHA):
        """True when Maxwell-Boltzmann is not rejected at significance ``alpha``."""
        return bool(self.p_value >= alpha)

    def summary(self):
        comp = ", ".join(f"{p:.3g}" for p in self.component_p)
        kurt = ", ".join(f"{k:+.3f}" for k in self.kurtosis)
        return (f"Maxwell-Boltzmann test ({self.n} samples, T = {self.T:.6g}): p = "
                f"{self.p_value:.3g} (KS components p = {comp}; speeds p = "
                f"{self.speed_p:.3g}); excess kurtosis {kurt} (+-{self.kurtosis_se:.3f})")


def maxwell_boltzmann_test(v, mass=1.0, T=None, subtract_mean=True):
    """Test velocities ``v`` (m/s; (n, dim) or snapshots (ns, n, dim), pooled) against
    Maxwell-Boltzmann at temperature ``T`` (J; default: measured, ``temperature``).

    Kolmogorov-Smirnov tests of each component against N(0, T/m) and of the speeds against
    the chi law with dim degrees of freedom (``speed_cdf``); returns an ``MBTest``. The KS
    test assumes independent samples: pool snapshots a few mean free times apart (velocities
    decorrelate in about one collision per particle). With T measured from the same sample
    the p-values are conservative (the Lilliefors effect: a fitted variance matches the
    sample better than the true one would). ``mass`` (kg): scalar (velocities of unequal
    masses have different widths: pass their scaled velocities sqrt(m_i/m) v_i instead).
    """
    from scipy import stats
    v = _velocities(v)
    if np.ndim(mass):
        raise ValueError("maxwell_boltzmann_test takes one mass; scale velocities of "
                         "unequal masses by sqrt(m_i / m) first")
    if subtract_mean:
        v = v - v.mean(axis=0)
    n, dim = v.shape
    if T is None:
        T = temperature(v, mass, subtract_mean=False)
    if not T > 0:
        raise ValueError(f"temperature must be > 0, got {T!r}")
    sd = math.sqrt(T / mass)
    cs, cp = [], []
    for k in range(dim):
        r = stats.kstest(v[:, k], stats.norm(loc=0.0, scale=sd).cdf)
        cs.append(r.statistic)
        cp.append(r.pvalue)
    s = np.sqrt(np.sum(v * v, axis=1))
    rs = stats.kstest(s, lambda x: speed_cdf(x, T, mass, dim))
    p = min(1.0, (dim + 1) * min(min(cp), rs.pvalue))
    return MBTest(float(T), int(n), int(dim), np.array(cs), np.array(cp),
                  float(rs.statistic), float(rs.pvalue), excess_kurtosis(v),
                  math.sqrt(24.0 / n), float(p))


# ------------------------------------------------------------------ collision frequency

def _dim(dim):
    if dim not in (2, 3):
        raise ValueError(f"dim must be 2 (disks) or 3 (spheres), got {dim!r}")
    return dim


def packing_fraction(n, sigma, dim=2):
    """Packing fraction eta of number density ``n`` (1/m^dim) of particles of diameter
    ``sigma`` (m): n pi sigma^2 / 4 (2D), n pi sigma^3 / 6 (3D)."""
    _dim(dim)
    return n * math.pi * sigma ** 2 / 4.0 if dim == 2 else n * math.pi * sigma ** 3 / 6.0


def number_density(eta, sigma, dim=2):
    """Number density (1/m^dim) at packing fraction ``eta`` for diameter ``sigma`` (m)."""
    return eta / packing_fraction(1.0, sigma, dim)


def contact_value(eta, dim=2):
    """Pair correlation at contact g(sigma) at packing fraction ``eta`` (-): Henderson
    (1975) for disks, (1 - 7 eta/16)/(1 - eta)^2; Carnahan-Starling (1969) for spheres,
    (1 - eta/2)/(1 - eta)^3. Both are 1 at eta = 0."""
    _dim(dim)
    eta = np.asarray(eta, dtype=float)
    if np.any(eta < 0) or np.any(eta >= 1):
        raise ValueError(f"packing fraction must be in [0, 1), got {eta!r}")
    g = (1.0 - 7.0 * eta / 16.0) / (1.0 - eta) ** 2 if dim == 2 else \
        (1.0 - eta / 2.0) / (1.0 - eta) ** 3
    return float(g) if g.ndim == 0 else g


def mean_relative_speed(T, mass=1.0, dim=2):
    """<|v_1 - v_2|> (m/s) of two independent Maxwellian particles of mass ``mass`` (kg) at
    temperature ``T`` (J): sqrt(pi T/m) in 2D, 4 sqrt(T/(pi m)) in 3D (chi law with dim
    degrees of freedom and scale sqrt(2T/m): mean sqrt(2) scale Gamma((d+1)/2)/Gamma(d/2))."""
    _dim(dim)
    return math.sqrt(2.0 * 2.0 * T / mass) * math.gamma((dim + 1) / 2.0) / math.gamma(dim / 2.0)


def boltzmann_frequency(n, sigma, T, mass=1.0, dim=2):
    """Dilute-gas (Boltzmann) collision frequency per particle (1/s) at number density
    ``n`` (1/m^dim), diameter ``sigma`` (m), temperature ``T`` (J), mass (kg):
    2 n sigma sqrt(pi T/m) for disks, 4 n sigma^2 sqrt(pi T/m) for spheres
    (cross-section 2 sigma or pi sigma^2 times ``mean_relative_speed``)."""
    cross = 2.0 * sigma if _dim(dim) == 2 else math.pi * sigma * sigma
    return n * cross * mean_relative_speed(T, mass, dim)


def enskog_frequency(n, sigma, T, mass=1.0, dim=2):
    """Enskog collision frequency per particle (1/s): ``contact_value``(eta) times
    ``boltzmann_frequency``; 2D: 2 n sigma g sqrt(pi T/m), 3D: 4 n sigma^2 g sqrt(pi T/m)."""
    eta = packing_fraction(n, sigma, dim)
    return contact_value(eta, dim) * boltzmann_frequency(n, sigma, T, mass, dim)


def collision_frequency(n_collisions, n_bodies, t):
    """Measured collision frequency per particle (1/s): every body-body collision involves
    two particles, so 2 * n_collisions / (n_bodies * t). Wall hits must not be counted."""
    return 2.0 * n_collisions / (n_bodies * t)


def bulk_collision_frequency(contacts, positions, box, margin, duration, sigma, T,
                             mass=1.0):
    """Collision frequency per particle and its Enskog value in the bulk of a box.

    ``contacts`` (k, dim): positions (m) of the body-body collisions (contact points or
    pair midpoints) over ``duration`` (s); ``positions`` (ns, n, dim): body positions at
    ns instants spread over that time (to measure the bulk density); ``box`` (dim,) the
    box size (m, walls at 0 and box); ``margin`` (m): the bulk is the box shrunk by margin
    on every side. A collision counts when its point lies in the bulk, so the rate is
    2 * count / (<N_bulk> * duration), unbiased in a homogeneous bulk; the Enskog value
    uses the bulk density <N_bulk> / V_bulk. Returns (omega, omega_E, n_bulk, count).
    """
    contacts = np.asarray(contacts, dtype=float)
    positions = np.asarray(positions, dtype=float)
    box = np.asarray(box, dtype=float)
    dim = box.size
    lo, hi = margin, box - margin
    if np.any(hi <= lo):
        raise ValueError(f"margin {margin} leaves no bulk in a box {box}")
    inside = np.all((contacts >= lo) & (contacts < hi), axis=1)
    count = int(np.count_nonzero(inside))
    n_in = np.all((positions >= lo) & (positions < hi), axis=-1).sum(axis=-1).mean()
    vol = float(np.prod(hi - lo))
    n_bulk = n_in / vol
    omega = 2.0 * count / (n_in * duration)
    return omega, enskog_frequency(n_bulk, sigma, T, mass, dim), n_bulk, count


def replay_contacts(x0, v0, t0, events, mass):
    """Where the recorded impacts of a run happened, rebuilt from its start and events.

    ``x0``, ``v0`` (n, dim): positions (m) and velocities (m/s) at time ``t0`` (s);
    ``events``: a dict of arrays in time order (``rbimpact.manybody.GasResult.events``):
    ``t`` (s), ``a``, ``b`` (bodies; ``b < 0`` a wall), ``n`` (k, dim) the unit normal
    from B into A (a wall's inward normal), ``P`` (k, dim) the impulse on A in contact
    space, normal first (N s); ``mass`` (kg, one for all bodies). Between impacts bodies fly
    straight (no gravity) and an impact changes A's velocity by P_n n / m and B's by
    -P_n n / m: this holds for smooth bodies (the tangential impulse is 0; it is checked)
    and every impact must be recorded. Vectorised: the impacts are sorted by body and the
    flights summed per body.

    Returns ``(pair, a_pos, b_pos, x_end, v_end)``: ``pair`` the indices of the body-body
    events, ``a_pos``, ``b_pos`` (k_pair, dim) the centres of A and B at those impacts (m),
    and positions and velocities of every body after its last impact, advanced to the last
    event time (to compare with the run's final state).
    """
    x0 = np.asarray(x0, dtype=float)
    v0 = np.asarray(v0, dtype=float)
    t = np.asarray(events["t"], dtype=float)
    a = np.asarray(events["a"], dtype=np.int64)
    b = np.asarray(events["b"], dtype=np.int64)
    nrm = np.asarray(events["n"], dtype=float)
    P = np.asarray(events["P"], dtype=float)
    n, dim = x0.shape
    k = t.size
    if P.shape[1] > 1 and k and np.max(np.abs(P[:, 1:])) > 1e-12 * max(
            float(np.max(np.abs(P[:, 0]))), 1e-300):
        raise ValueError("replay_contacts: tangential impulses: only smooth bodies replay")
    dv = P[:, :1] * nrm / mass                      # velocity change of A (m/s)
    pair = np.flatnonzero(b >= 0)
    # one entry per body and impact: (body, time, dv, event)
    body = np.concatenate([a, b[pair]])
    tt = np.concatenate([t, t[pair]])
    dd = np.concatenate([dv, -dv[pair]])
    ev = np.concatenate([np.arange(k), pair])
    order = np.lexsort((ev, body))                  # by body, then chronologically
    body, tt, dd, ev = body[order], tt[order], dd[order], ev[order]
    first = np.ones(body.size, dtype=bool)
    first[1:] = body[1:] != body[:-1]
    # velocity before each entry: v0 + the changes of the body's earlier entries
    cum = np.cumsum(dd, axis=0)
    start = np.maximum.accumulate(np.where(first, np.arange(body.size), 0))
    before = cum - dd - (cum[start] - dd[start])    # sum of the body's earlier dd
    vel = v0[body] + before
    tprev = np.empty_like(tt)
    tprev[1:] = tt[:-1]
    tprev[first] = t0
    step = vel * (tt - tprev)[:, None]
    cs = np.cumsum(step, axis=0)
    pos = x0[body] + cs - (cs[start] - step[start])
    # the position of each event's A and B
    where = np.empty((k, 2), dtype=np.int64)
    where.fill(-1)
    is_a = np.zeros(body.size, dtype=bool)
    # the first entry of an event in body order belongs to whichever body sorts first;
    # identify A's entry as the one whose body is the event's a
    is_a[:] = body == a[ev]
    where[ev[is_a], 0] = np.flatnonzero(is_a)
    other = ~is_a
    where[ev[other], 1] = np.flatnonzero(other)
    a_pos = pos[where[pair, 0]]
    b_pos = pos[where[pair, 1]]
    # final state: after each body's last entry, advanced to the last event time
    x_end, v_end = x0.copy(), v0.copy()
    last = np.ones(body.size, dtype=bool)
    last[:-1] = body[:-1] != body[1:]
    t_last = t[-1] if k else t0
    lb = body[last]
    v_end[lb] = vel[last] + dd[last]
    x_end[lb] = pos[last] + v_end[lb] * (t_last - tt[last])[:, None]
    untouched = np.setdiff1d(np.arange(n), lb)
    x_end[untouched] += v0[untouched] * (t_last - t0)
    return pair, a_pos, b_pos, x_end, v_end


# ------------------------------------------------------------------ Haff's law

def haff_tau(e, n, sigma, T0, mass=1.0, dim=2):
    """Haff's time (s): 1/tau = (1 - e^2) omega_E(T0) / (2 dim), for a homogeneous gas of
    smooth particles with restitution ``e`` at number density ``n`` (1/m^dim), diameter
    ``sigma`` (m), initial temperature ``T0`` (J), mass (kg). Infinite for e = 1."""
    if not 0.0 <= e <= 1.0:
        raise ValueError(f"restitution must be in [0, 1], got {e!r}")
    rate = (1.0 - e * e) * enskog_frequency(n, sigma, T0, mass, dim) / (2.0 * dim)
    return math.inf if rate == 0.0 else 1.0 / rate


def haff_temperature(t, T0, tau):
    """Haff's law T(t) = T0 / (1 + t/tau)^2 (J) at times ``t`` (s)."""
    return T0 / (1.0 + np.asarray(t, dtype=float) / tau) ** 2


@dataclass(frozen=True)
class HaffFit:
    """Fit of T(t) = T0 / (1 + t/tau)^2: ``tau`` (s), ``T0`` (J), ``tau_se`` (s, the
    least-squares standard error, which assumes uncorrelated residuals and so
    underestimates the error of a correlated time series), ``rms`` the rms residual of
    log T (-), ``n`` points."""

    tau: float
    T0: float
    tau_se: float
    rms: float
    n: int


def fit_haff(t, T, T0=None):
    """Fit Haff's law to a temperature series ``T`` (J) at times ``t`` (s).

    Least squares on log T (fluctuations of a temperature measured over N bodies are
    relative, ~sqrt(2/(dim N))), started from the straight line T^(-1/2) = T0^(-1/2)
    (1 + t/tau). ``T0``: fixed initial temperature (J); None fits it as well. Returns a
    ``HaffFit``."""
    from scipy.optimize import least_squares
    t = np.asarray(t, dtype=float)
    T = np.asarray(T, dtype=float)
    ok = np.isfinite(t) & np.isfinite(T) & (T > 0)
    t, T = t[ok], T[ok]
    if t.size < 3:
        raise ValueError("fit_haff needs at least 3 positive temperatures")
    y = T ** -0.5
    b, a = np.polyfit(t, y, 1)                  # y = a + b t, a = T0^-1/2, b = a / tau
    if T0 is not None:
        a = T0 ** -0.5
        b = np.sum((y - a) * t) / np.sum(t * t)
    tau0 = a / b if b > 0 else (t[-1] - t[0]) * 10.0 + 1.0
    lT = np.log(T)
    if T0 is None:
        def res(p):
            return p[0] - 2.0 * np.log1p(t / p[1]) - lT
        x0 = [math.log(1.0 / (a * a)), tau0]
    else:
        def res(p):
            return math.log(T0) - 2.0 * np.log1p(t / p[0]) - lT
        x0 = [tau0]
    lo = [-np.inf, 1e-300] if T0 is None else [1e-300]
    sol = least_squares(res, x0, bounds=(lo, np.inf), x_scale="jac")
    r = sol.fun
    dof = max(t.size - len(x0), 1)
    s2 = float(r @ r) / dof
    try:
        cov = np.linalg.inv(sol.jac.T @ sol.jac) * s2
        tau_se = float(math.sqrt(cov[-1, -1]))
    except np.linalg.LinAlgError:
        tau_se = math.inf
    tau = float(sol.x[-1])
    T0_fit = float(math.exp(sol.x[0])) if T0 is None else float(T0)
    return HaffFit(tau, T0_fit, tau_se, float(math.sqrt(np.mean(r * r))), int(t.size))
