"""granular_gas: N disks (2D) or spheres (3D) in a box, run by the many-body engine
(``rbimpact.manybody``), checked against kinetic theory (``rbimpact.gas_stats``)."""
import math
import time
from dataclasses import dataclass, field
import typing

import numpy as np

from . import ALL_LAWS, LAW_PARAMS, positive, nonnegative, register

DESCRIPTION = """\
A granular gas: `n` disks (dim = 2) or spheres (dim = 3) of radius `radius` (m) and mass
`mass` (kg) at random non-overlapping positions in a square (cubic) box sized for the
packing fraction `packing`, with Maxwellian velocities of temperature `temperature` (J,
k_B = 1: kinetic energy dim T / 2 per body) and zero total momentum (`start=equal_speeds`:
the same speeds, every body at sqrt(dim T / m), in the same random directions: a
non-Maxwellian start that relaxes). Body-body impacts use the law with `e` (and `mu`,
`e_t` for rough bodies), and so do the impacts on the box walls. The run is a many-body
event-driven run (rbimpact.manybody.run_gas), not the single-body stepper; it lasts about
`collisions` body-body collisions per particle (predicted by the Enskog frequency and, for
e < 1, Haff's law), or `--t-end`.

Printed: impacts (body-body collisions and wall hits), the collision frequency per
particle 2 C / (N t) against the Enskog value integrated over the measured T(t)
(Henderson's g(sigma) for disks, Carnahan-Starling for spheres; the density is N / V of
the whole box, so walls bias it by a few per cent), energy at start and end; for e = 1 the
Maxwell-Boltzmann test of the velocities of the second half of the run (snapshots at least
2 collision times apart), for e < 1 Haff's time tau fitted to T(t) against its theory
1/tau = (1 - e^2) omega_E(T0) / (2 dim) (smooth particles: mu = 0), also with the walls'
dissipation (a wall hit loses (1 - e^2) T on average, as a pair collision: 1/tau times
1 + wall hits / collisions); the fit covers the first `fit_collisions` collisions per
particle, before clusters form, with T0 measured. Inelastic collapse: the engine's TC model.
With `gravity` > 0 the gas settles into a bed on the floor and, with `sleep` (default), its
bodies at rest fall asleep (static, no event: run_gas(sleep=True)); the summary counts
them. `--plot`: the speed
distribution against Maxwell-Boltzmann, and T(t) against Haff's law (e < 1) or the excess
kurtosis of the velocities against time (e = 1). `--out`: the series t, T(t) as CSV."""

#: snapshots of a run (the series T(t) and the samples of the velocity distribution)
N_SNAPSHOTS = 200
#: snapshot memory cap: at most this many floats in snap_v (80 MB)
SNAP_FLOATS = 10_000_000
#: velocity samples of the Maxwell-Boltzmann test are this many collision times apart
MB_SPACING = 2.0


@dataclass(frozen=True)
class GasScenario:
    """A built granular gas, ready to run with ``rbimpact.manybody``.

    ``name``, ``description``, ``params`` (the values used), ``laws``, ``t_end`` (s, from
    ``collisions``), ``law_params`` (what the law takes), ``theory``: number density
    ``n`` (1/m^dim), diameter ``sigma`` (m), ``T0`` (J), Enskog frequency ``omega0`` (1/s)
    at T0 and Haff's ``tau`` (s, inf for e = 1).
    """

    name: str
    description: str
    params: typing.Mapping
    laws: tuple
    t_end: float
    law_params: typing.Mapping
    theory: typing.Mapping = field(default_factory=dict)

    def make_state(self):
        """The initial ``GasState`` (``manybody.random_gas``; equal speeds if asked)."""
        from rbimpact import manybody
        p = self.params
        state = manybody.random_gas(
            p["n"], dim=p["dim"], packing=p["packing"], radius=p["radius"],
            mass=p["mass"], law=p["law"], seed=p["seed"], temperature=p["temperature"],
            gravity=p["gravity"], rough=p["rough"], **self.law_params)
        if p["start"] == "equal_speeds":
            v = np.asarray(state.v)
            s = np.linalg.norm(v, axis=1, keepdims=True)
            v[:] = v / np.where(s > 0, s, 1.0) * math.sqrt(p["dim"] * p["temperature"]
                                                          / p["mass"])
        return state

    def run_options(self):
        """Keywords of ``manybody.run_gas`` set by the scenario: ``sleep`` (bodies at rest
        sleep when asked and gravity > 0)."""
        return dict(sleep=bool(self.params["sleep"]) and self.params["gravity"] > 0)

    def simulate(self, t_end=None, **run_kwargs):
        """Run the gas to ``t_end`` (s, default ``self.t_end``); returns the ``GasResult``.
        Keywords go to ``manybody.run_gas`` (over ``run_options``)."""
        from rbimpact import manybody
        kw = dict(self.run_options(), **run_kwargs)
        return manybody.run_gas(self.make_state(),
                                t_end=self.t_end if t_end is None else t_end, **kw)

    def report(self, t_end=None, out=None, plot=None):
        """Run with snapshots and return the summary text of ``rbimpact run``; ``out``:
        write t, T(t) (CSV), ``plot``: the figure (needs matplotlib)."""
        from rbimpact import manybody
        t_end = self.t_end if t_end is None else float(t_end)
        state = self.make_state()
        e0 = state.kinetic_energy()
        n, dim = np.shape(state.v)
        ns = max(10, min(N_SNAPSHOTS, SNAP_FLOATS // (n * dim)))
        t0 = time.perf_counter()
        res = manybody.run_gas(state, t_end=t_end, record="none", snapshot_dt=t_end / ns,
                               **self.run_options())
        wall = time.perf_counter() - t0
        a = analyse(self, state, res, e0)
        lines = [summary_text(self, res, a, wall, t_end)]
        unwritten = []      # as rbimpact.run: the summary survives a failed write
        for what, path, write, done in (
                ("out", out, write_series, "series t, T(t) written to {}"),
                ("plot", plot, lambda f, a: plot_gas(f, self, a), "plot written to {}")):
            if path:
                try:
                    write(path, a)
                    lines.append(done.format(path))
                except OSError as exc:
                    unwritten.append((what, path, exc))
        text = "\n".join(lines)
        if unwritten:
            from rbimpact.errors import OutputError
            raise OutputError("; ".join(f"could not write {w} {str(p)!r}: "
                                        f"{exc.strerror or exc}" for w, p, exc in unwritten),
                              summary=text, paths=[p for _, p, _ in unwritten])
        return text


def _series(state, res):
    """Snapshot times and velocities, with the initial state first if it is missing."""
    t = np.asarray(getattr(res, "snap_t", np.zeros(0)), dtype=float)
    v = np.asarray(getattr(res, "snap_v", np.zeros((0,) + np.shape(state.v))), dtype=float)
    if t.size == 0 or t[0] > 0.0:
        t = np.concatenate([[0.0], t])
        v = np.concatenate([np.asarray(state.v, dtype=float)[None], v])
    return t, v


def analyse(sc, state, res, e0):
    """Kinetic-theory figures of a run (dict): temperatures, collision frequency against
    Enskog, Maxwell-Boltzmann test (e = 1), Haff fit (e < 1)."""
    from rbimpact import gas_stats as gs
    p, th = sc.params, sc.theory
    m, dim, N = p["mass"], p["dim"], p["n"]
    t, V = _series(state, res)
    T = np.array([gs.temperature(vk, m) for vk in V])
    t_run = float(res.t)
    n_coll = int(res.n_collisions)
    # Enskog prediction over the measured T(t): N/2 int omega_E(T(t)) dt
    om = np.array([gs.enskog_frequency(th["n"], th["sigma"], Tk, m, dim) for Tk in T])
    keep = t <= t_run
    tk, omk = t[keep], om[keep]
    if tk[-1] < t_run:      # the last piece to t_run at the last temperature
        tk, omk = np.append(tk, t_run), np.append(omk, omk[-1])
    predicted = 0.5 * N * float(np.trapezoid(omk, tk))
    a = dict(t=t, T=T, t_run=t_run, n_collisions=n_coll, n_wall=int(res.n_wall),
             box=np.asarray(state.box, dtype=float), e0=e0, e1=res.state.kinetic_energy(),
             omega=gs.collision_frequency(n_coll, N, t_run) if t_run > 0 else math.nan,
             omega_enskog=2.0 * predicted / (N * t_run) if t_run > 0 else math.nan,
             ratio=n_coll / predicted if predicted > 0 else math.nan,
             V=V, mb=None, haff=None,
             kurtosis=np.array([gs.excess_kurtosis(vk).mean() if Tk > 0 else math.nan
                                for vk, Tk in zip(V, T)]))
    # velocity samples: second half of the run, MB_SPACING collision times apart, each
    # snapshot scaled to unit temperature (the gas cools when e < 1)
    # (snapshots where nothing moves, a bed asleep under gravity, have no velocities to
    # test)
    tc = 1.0 / th["omega0"]
    pick, last = [], -math.inf
    for k, tk_ in enumerate(t):
        if (T[k] > 0 and tk_ >= 0.5 * t_run
                and tk_ - last >= MB_SPACING * tc * math.sqrt(T[0] / T[k])):
            pick.append(k)
            last = tk_
    if not pick:
        pick = [k for k in range(1, len(t)) if T[k] > 0][-1:]   # not the start itself
    a["sample_t"] = t[pick]
    a["samples"] = np.zeros((0, dim))
    if pick:
        scaled = np.concatenate([V[k] / math.sqrt(T[k] / m) for k in pick])
        a["samples"] = scaled
        # scaled components have unit variance: temperature m (J) for mass m
        a["mb"] = gs.maxwell_boltzmann_test(scaled, mass=m, T=m)
    if p["e"] < 1.0:
        # the homogeneous phase: the first `fit_collisions` collisions per particle
        # (Haff's clock: omega0 tau ln(1 + t/tau) of them by time t); T0 is measured
        t_fit = th["tau"] * math.expm1(p["fit_collisions"] / (th["omega0"] * th["tau"]))
        win = t <= t_fit * (1.0 + 1e-12)
        a["t_fit"] = float(t[win][-1])
        if np.count_nonzero(win) >= 3:
            a["haff"] = gs.fit_haff(t[win], T[win], T0=T[0])
    return a


def summary_text(sc, res, a, wall, t_end):
    p, th = sc.params, sc.theory
    from rbimpact.scenarios import spec
    defaults = spec("granular_gas").params
    changed = {k: v for k, v in p.items() if k != "law" and v != defaults[k].default}
    law_text = ", ".join(f"{k}={v!r}" if isinstance(v, str) else f"{k}={v:g}"
                         for k, v in sc.law_params.items())
    shape = "disks" if p["dim"] == 2 else "spheres"
    box = np.asarray(a["box"])
    lines = [
        "scenario: granular_gas: " + spec("granular_gas").summary,
        f"law: {p['law']} ({law_text}); many-body engine rbimpact.manybody"
        + (f"; inelastic collapse: TC model (Luding & McNamara 1998), tc = {res.tc:.3g} s, "
           f"{res.n_tc} impacts made elastic" if res.collapse == "tc" else
           f"; inelastic collapse: {res.collapse}"),
    ]
    if changed:
        lines.append("settings: " + ", ".join(f"{k}={v}" for k, v in changed.items()))
    lines += [
        f"gas: {p['n']} {shape} (dim {p['dim']}), radius {p['radius']:g} m, packing "
        f"{p['packing']:g} in a box " + " x ".join(f"{b:.4g}" for b in box) + " m, "
        f"T0 = {a['T'][0]:.6g} J, start {p['start']}, seed {p['seed']}",
        f"status: ran to t = {a['t_run']:.6g} s of {t_end:.6g} s (stop: {res.stop})",
        f"impacts: {a['n_collisions']} body-body collisions "
        f"({2 * a['n_collisions'] / p['n']:.1f} per particle), {a['n_wall']} wall hits",
        f"collision frequency per particle: {a['omega']:.6g} /s measured, Enskog "
        f"{a['omega_enskog']:.6g} /s (ratio {a['ratio']:.4f}; g(sigma) = {th['g']:.5f}, "
        f"n = N/V of the whole box, over the measured T(t))",
        f"energy: start {a['e0']:.6g} J, end {a['e1']:.6g} J (change "
        f"{a['e1'] - a['e0']:+.6g} J, relative {(a['e1'] - a['e0']) / a['e0']:+.3g})",
    ]
    mb = a["mb"]
    what = ("Maxwell-Boltzmann test" if p["e"] >= 1.0 else
            "velocities scaled by sqrt(T(t)) against Maxwell-Boltzmann (the homogeneous "
            "cooling state deviates slightly)")
    if mb is None:
        lines.append(f"{what}: none (no snapshot with a moving body)")
    else:
        lines.append(f"{what}: p = {mb.p_value:.3g} (KS components p = "
                     + ", ".join(f"{x:.3g}" for x in mb.component_p)
                     + f"; speeds p = {mb.speed_p:.3g}); excess kurtosis "
                     + ", ".join(f"{k:+.3f}" for k in mb.kurtosis)
                     + f" (+-{mb.kurtosis_se:.3f}); {mb.n} samples from "
                     f"{len(a['sample_t'])} snapshots, t >= {a['sample_t'][0]:.4g} s")
    if a["haff"] is not None:
        h = a["haff"]
        walls = 1.0 + a["n_wall"] / max(a["n_collisions"], 1)
        lines.append(
            f"Haff's law: tau fitted {h.tau:.6g} s over t <= {a['t_fit']:.4g} s (T0 "
            f"measured; +-{h.tau_se:.2g}, rms log residual {h.rms:.3g}); theory {th['tau']:.6g} s (ratio {h.tau / th['tau']:.4f}), with "
            f"the walls' dissipation (1/tau x (1 + wall hits / collisions)) "
            f"{th['tau'] / walls:.6g} s (ratio {h.tau * walls / th['tau']:.4f}); smooth "
            f"particles{'' if p['mu'] == 0 else ', mu > 0 also dissipates'}; "
            f"T(end)/T0 = {a['T'][-1] / a['T'][0]:.4g}")
    if getattr(res, "sleep", False):
        lines.append(f"sleep: {res.n_asleep} of {p['n']} bodies asleep at the end "
                     f"({res.n_sleeps} fell asleep, {res.n_wakes} woken, {res.n_absorbed} "
                     f"impacts held by sleepers; sleep speed {res.sleep_speed:.3g} m/s, "
                     f"{res.sleep_impacts} slow impacts; kinetic energy put to sleep "
                     f"{res.energy_slept:.6g} J)")
    rate = (a["n_collisions"] + a["n_wall"]) / wall if wall > 0 else math.nan
    lines.append(f"run time: {wall:.3g} s ({rate:.3g} impacts/s, includes any compilation)")
    return "\n".join(lines)


def write_series(path, a):
    with open(path, "w") as f:
        f.write("t_s,T_J\n")
        for tk, Tk in zip(a["t"], a["T"]):
            f.write(f"{tk!r},{Tk!r}\n")


def plot_gas(path, sc, a):
    """Speed distribution against Maxwell-Boltzmann; T(t) against Haff (e < 1) or the
    excess kurtosis of the velocities against time (e = 1)."""
    from rbimpact import gas_stats as gs
    from rbimpact.result_base import pyplot
    plt = pyplot("rbimpact run granular_gas --plot")
    p, th = sc.params, sc.theory
    m, dim = p["mass"], p["dim"]
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    s = np.linalg.norm(a["samples"], axis=1)
    s0 = np.linalg.norm(a["V"][0] / math.sqrt(a["T"][0] / m), axis=1)
    edges = np.linspace(0.0, max(s.max() if s.size else 0.0, s0.max()) * 1.02,
                        int(np.clip(np.sqrt(s.size) / 2.0, 15, 80)) + 1)
    if s.size:
        ax1.hist(s, bins=edges, density=True, alpha=0.6,
                 label=f"{s.size} speeds (scaled to T)")
    x = np.linspace(0, edges[-1], 400)
    f = gs.speed_pdf(x, m, m, dim)
    ax1.plot(x, f, "k-",
             label="Maxwell-Boltzmann (" + ("Rayleigh" if dim == 2 else "Maxwell") + ")")
    ax1.hist(s0, bins=edges, density=True, histtype="step", color="tab:red", label="t = 0")
    ax1.set_ylim(0.0, 1.6 * f.max())
    ax1.set_xlabel("speed / sqrt(T/m)")
    ax1.set_ylabel("probability density")
    ax1.set_title("Maxwell-Boltzmann test: " + (f"p = {a['mb'].p_value:.3g}" if a["mb"]
                                                 else "no moving body"))
    ax1.legend(fontsize=8)
    t, T = a["t"], a["T"]
    if a["haff"] is not None:
        ok = t > 0
        ax2.loglog(t[ok], T[ok], "o", ms=3, label="simulation")
        ax2.loglog(t[ok], gs.haff_temperature(t[ok], T[0], th["tau"]), "k-",
                   label=f"Haff, theory tau = {th['tau']:.4g} s")
        walls = 1.0 + a["n_wall"] / max(a["n_collisions"], 1)
        ax2.loglog(t[ok], gs.haff_temperature(t[ok], T[0], th["tau"] / walls), "k:",
                   label=f"Haff with the walls' dissipation, tau = {th['tau'] / walls:.4g} s")
        ax2.axvline(a["t_fit"], color="0.6", lw=0.8)
        ax2.loglog(t[ok], gs.haff_temperature(t[ok], a["haff"].T0, a["haff"].tau), "r--",
                   label=f"Haff, fitted tau = {a['haff'].tau:.4g} s (t <= {a['t_fit']:.3g} s)")
        ax2.set_ylabel("T (J)")
    else:
        ax2.plot(t, a["kurtosis"], ".", ms=3, label="mean over components")
        ax2.axhline(0.0, color="k", lw=1, label="Maxwell-Boltzmann")
        ax2.set_ylabel("excess kurtosis of the velocity components")
    ax2.set_xlabel("t (s)")
    ax2.legend(fontsize=8)
    fig.suptitle(f"granular_gas: N = {p['n']}, dim {dim}, packing {p['packing']:g}, "
                 f"{p['law']} e = {p['e']:g}, collision ratio to Enskog {a['ratio']:.4f}")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


@register("granular_gas", laws=ALL_LAWS,
          summary="a granular gas of disks or spheres in a box (many-body engine) against "
                  "Maxwell-Boltzmann, Enskog and Haff",
          help={"n": "number of bodies, >= 2",
                "dim": "2 (disks) or 3 (spheres)",
                "packing": "packing fraction (-), in (0, 0.5)",
                "radius": "body radius (m), > 0",
                "mass": "body mass (kg), > 0",
                "temperature": "initial temperature T0 (J, k_B = 1), > 0",
                "seed": "random seed of positions and velocities, >= 0",
                "gravity": "gravity (m/s^2) along -y (2D) or -z (3D), >= 0",
                "rough": "rough bodies: friction couples rotation (mu, e_t)",
                "sleep": "with gravity > 0: bodies at rest sleep (static, no event) and "
                         "wake when touched",
                "start": "initial velocities: maxwellian or equal_speeds",
                "collisions": "run length in body-body collisions per particle (Enskog, "
                              "Haff), > 0",
                "fit_collisions": "e < 1: Haff's tau is fitted over the first this many "
                                  "collisions per particle (the homogeneous phase), > 0"},
          choices={"start": ("maxwellian", "equal_speeds")})
def build(law: str = "kane_levinson", e: float = 1.0, mu: float = 0.0, e_t: float = 0.0,
          restitution: str = "energetic", n: int = 1024, dim: int = 2,
          packing: float = 0.15, radius: float = 0.5, mass: float = 1.0,
          temperature: float = 1.0, seed: int = 0, gravity: float = 0.0,
          rough: bool = False, start: str = "maxwellian", collisions: float = 50.0,
          fit_collisions: float = 20.0, sleep: bool = True):
    from rbimpact import gas_stats as gs
    from rbimpact.laws import LAWS
    positive("granular_gas", radius=radius, mass=mass, temperature=temperature,
             collisions=collisions, fit_collisions=fit_collisions)
    nonnegative("granular_gas", gravity=gravity, seed=seed)
    if n < 2:
        raise ValueError(f"scenario 'granular_gas': n must be >= 2, got {n}")
    if dim not in (2, 3):
        raise ValueError(f"scenario 'granular_gas': dim must be 2 or 3, got {dim}")
    if not 0.0 < packing < 0.5:
        raise ValueError(f"scenario 'granular_gas': packing must be in (0, 0.5), got "
                         f"{packing}")
    values = dict(law=law, e=e, mu=mu, e_t=e_t, restitution=restitution, n=n, dim=dim,
                  packing=packing, radius=radius, mass=mass, temperature=temperature,
                  seed=seed, gravity=gravity, rough=rough, start=start,
                  collisions=collisions, fit_collisions=fit_collisions, sleep=sleep)
    takes = LAWS[law].params
    lp = {k: values[k] for k in LAW_PARAMS if k in takes}
    sigma = 2.0 * radius
    dens = gs.number_density(packing, sigma, dim)
    box_side = (n / dens) ** (1.0 / dim)
    omega0 = gs.enskog_frequency(dens, sigma, temperature, mass, dim)
    tau = gs.haff_tau(min(max(e, 0.0), 1.0), dens, sigma, temperature, mass, dim)
    # t_end: `collisions` per particle; with Haff cooling int omega dt = omega0 tau ln(1+t/tau)
    if math.isinf(tau):
        t_end = collisions / omega0
    else:
        x = collisions / (omega0 * tau)
        t_end = tau * math.expm1(x) if x < 700 else math.inf
        if not math.isfinite(t_end):
            raise ValueError(f"scenario 'granular_gas': {collisions} collisions per particle "
                             f"take longer than any time at e = {e}; ask for fewer")
    theory = dict(n=dens, sigma=sigma, T0=temperature, omega0=omega0, tau=tau,
                  g=gs.contact_value(packing, dim), box=(box_side,) * dim)
    return GasScenario("granular_gas", DESCRIPTION, values, ALL_LAWS, t_end, lp, theory)
