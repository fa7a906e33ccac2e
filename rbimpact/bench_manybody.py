"""``rbimpact bench manybody``: impacts per second of the many-body engine against N.

Cases (issue 15): 2D smooth elastic disks (Kane & Levinson, e = 1, mu = 0), 2D rough
disks (Chatterjee & Ruina, e = 1, e_t = 0, mu = 0.3; spinning, W with r^2/I terms),
3D smooth elastic spheres (Kane & Levinson); packing fraction 0.15, closed box, no
gravity, one thread; the law is called on every impact (body-body and wall). For each N
the gas is first relaxed (``WARM_PER_BODY`` impacts per body, which also loads or
compiles the code), then ``max(MIN_IMPACTS, IMPACTS_PER_BODY * N)`` impacts are timed,
with recording off and with every impact recorded. Impacts count body-body and wall
impacts, not cell crossings or stale predictions. Rates are wall-clock (median of
``repeat`` runs) and, beside them, per CPU second of this process (the machine may be
shared). ``ratio`` is rate(4096) / rate(64) in the same run.

Then the ``bed`` rows (``bench_bed``): a settling bed, ``BED["n"]`` inelastic disks
dropped under gravity from a dilute random start, run to the same ``t_end`` with and
without sleep (``run_gas(sleep=...)``): impacts and CPU seconds. The TC model's ``tc`` is
given (``BED["tc"]``, far above the default) so that the run without sleep reaches
``t_end`` at all: a resting body costs one impact per ``tc`` without sleep.

Then the ``polygons`` rows (``bench_polygons``, issue 16): the exact 2D stepper
(``rbimpact.Simulation``, every body pair collides with exact time of impact) on a gas of
N random convex polygons (scenario ``polygon_gas``) in a box of four walls, no gravity,
for N in ``POLY_SIZES``: events/s (wall clock, median of ``repeat`` runs; and per CPU
second), impacts, and the ratio to the disk gas of the same N at the same packing, once
against the many-body engine (``run_gas``, 2D smooth elastic disks, as above) and once
against the same stepper running ``polygon_gas`` with ``shapes=disks`` (closed-form disk
times of impact; the ratio that isolates the cost of the polygon searches). Each run
lasts ``POLY_CROSSINGS`` box crossings (L / v_rms), recording off; the code is loaded or
compiled by a short untimed run first. Persistent body-body contact is not built: a
dissipative gas may end early with status "persistent_pair" (printed, rate of the part
that ran). A fit of log(time per event) against log N gives the scaling exponent.
"""
import math
import time

import numpy as np

SIZES = (64, 256, 1024, 4096, 16384, 65536)
CASES = (
    ("2D smooth elastic disks (kane_levinson e=1)", dict(dim=2, law="kane_levinson", e=1.0)),
    ("2D rough disks (chatterjee_ruina e=1 mu=0.3)",
     dict(dim=2, law="chatterjee_ruina", e=1.0, mu=0.3, rough=True)),
    ("3D smooth elastic spheres (kane_levinson e=1)", dict(dim=3, law="kane_levinson", e=1.0)),
)
PACKING = 0.15
MIN_IMPACTS = 200_000       # timed impacts per run at least
IMPACTS_PER_BODY = 10       # ... and at least this many per body
WARM_PER_BODY = 5           # relaxation before timing (impacts per body, at least 20000)
TARGETS = {  # issue 15, impacts/s at N = 4096, recording off
    "2D smooth elastic disks (kane_levinson e=1)": 1.0e6,
    "2D rough disks (chatterjee_ruina e=1 mu=0.3)": 0.5e6,
    "3D smooth elastic spheres (kane_levinson e=1)": 0.4e6,
}
RATIO_TARGET = 0.5          # rate(4096) / rate(64), 2D smooth
# the settling bed (bench_bed): 2D smooth disks, Kane & Levinson e = 0.7, r = 0.5 m,
# g = 1 m/s^2 (sqrt(r / g) = 0.7 s), dilute start (packing 0.1 of the square box); the
# bed is asleep by t ~ 20 s
BED = dict(n=200, dim=2, law="kane_levinson", e=0.7, gravity=1.0, packing=0.1, seed=0,
           t_end=40.0, tc=1e-3)

# the polygon gas (bench_polygons): rbimpact.Simulation on scenario polygon_gas
POLY_SIZES = (4, 8, 16, 32, 64)
POLY_CROSSINGS = 10.0      # run length in box crossings L / v_rms (impacts ~ 20 N here)
POLY_CASES = (
    ("2D polygons smooth elastic (kane_levinson e=1)",
     dict(shapes="polygons", law="kane_levinson", e=1.0, mu=0.0)),
    ("2D polygons rough (kane_levinson e=0.9 mu=0.3)",
     dict(shapes="polygons", law="kane_levinson", e=0.9, mu=0.3)),
    ("2D mixed polygons/disks/capsules (kane_levinson e=1)",
     dict(shapes="mixed", law="kane_levinson", e=1.0, mu=0.0)),
)
POLY_DISK_IMPACTS = 100_000   # timed impacts of the run_gas disk gas of the same N


def bench_manybody(repeat=1, sizes=SIZES, cases=None, records=("none", "all"),
                   min_impacts=MIN_IMPACTS, seed=0, bed=True, polygons=None):
    """Rows ``{case, n, record, impacts, run_s, impacts_per_s, impacts_per_cpu_s,
    collisions, wall, crossings, stale}`` plus one ``ratio`` row per case and record,
    then (``polygons``; default: when ``cases`` is not given) the rows of
    ``bench_polygons``, then (``bed``) the two rows of ``bench_bed``."""
    from .manybody import random_gas, run_gas
    rows = []
    for name, kw in (cases or CASES):
        kw = dict(kw)
        dim = kw.pop("dim")
        law = kw.pop("law")
        rough = kw.pop("rough", False)
        for n in sizes:
            s = random_gas(n, dim=dim, packing=PACKING, law=law, seed=seed, rough=rough, **kw)
            warm = run_gas(s, max_impacts=max(20_000, WARM_PER_BODY * n))
            m = max(min_impacts, IMPACTS_PER_BODY * n)
            for rec in records:
                walls, cpus, res = [], [], None
                for _ in range(repeat):
                    t0, c0 = time.perf_counter(), time.process_time()
                    res = run_gas(warm.state, max_impacts=m, record=rec)
                    walls.append(time.perf_counter() - t0)
                    cpus.append(time.process_time() - c0)
                    if rec == "all":
                        assert len(res.events["t"]) == m
                    del res.events
                wall, cpu = float(np.median(walls)), float(np.median(cpus))
                rows.append(dict(case=name, n=n, record=rec, impacts=m, run_s=wall,
                                 impacts_per_s=m / wall, impacts_per_cpu_s=m / max(cpu, 1e-9),
                                 collisions=res.n_collisions, wall=res.n_wall,
                                 crossings=res.n_crossings, stale=res.n_stale))
        for rec in records:
            by_n = {r["n"]: r for r in rows if r["case"] == name and r["record"] == rec
                    and "n" in r}
            if 64 in by_n and 4096 in by_n:
                rows.append(dict(case=name, record=rec, ratio=by_n[4096]["impacts_per_s"]
                                 / by_n[64]["impacts_per_s"],
                                 ratio_cpu=by_n[4096]["impacts_per_cpu_s"]
                                 / by_n[64]["impacts_per_cpu_s"]))
    if polygons is None:
        polygons = cases is None
    if polygons:
        rows += bench_polygons(repeat=repeat, seed=seed)
    if bed:
        rows += bench_bed()
    return rows


def _time_sim(sim, t_end, repeat):
    """Median wall and CPU seconds of ``sim.run(t_end, record="none")`` and the last
    result (a run that ends with a ``SimulationError`` counts up to where it stopped)."""
    from .errors import SimulationError
    walls, cpus, res = [], [], None
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        try:
            res = sim.run(t_end, record="none", max_events=10**9)
        except SimulationError as exc:
            res = exc.result
        walls.append(time.perf_counter() - t0)
        cpus.append(time.process_time() - c0)
    return float(np.median(walls)), float(np.median(cpus)), res


def bench_polygons(repeat=1, sizes=POLY_SIZES, cases=POLY_CASES, crossings=POLY_CROSSINGS,
                   disk_impacts=POLY_DISK_IMPACTS, seed=0):
    """The polygon gas (``POLY_CASES``) through ``rbimpact.Simulation`` against N: rows
    ``{poly: True, case, n, t_end, status, events, impacts, run_s, events_per_s,
    events_per_cpu_s, us_per_event, gas_disks_per_s, sim_disks_per_s, ratio_gas,
    ratio_sim}`` (``ratio_gas``: events/s over the impacts/s of ``run_gas``'s disk gas of
    the same N; ``ratio_sim``: over the events/s of the same stepper on ``polygon_gas``
    with disks), then one ``{poly: True, case, slope}`` row per case: the exponent ``p`` of
    time per event ~ N^p (least squares on log-log over the sizes that ran to the end)."""
    from .manybody import random_gas, run_gas
    from .scenarios import get
    gas_rate, sim_rate = {}, {}
    for n in sizes:
        s = random_gas(n, dim=2, packing=PACKING, law="kane_levinson", e=1.0, seed=seed)
        warm = run_gas(s, max_impacts=max(20_000, WARM_PER_BODY * n))
        walls = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            run_gas(warm.state, max_impacts=disk_impacts)
            walls.append(time.perf_counter() - t0)
        gas_rate[n] = disk_impacts / float(np.median(walls))
        sc = get("polygon_gas", n=n, shapes="disks", packing=PACKING, crossings=crossings,
                 seed=seed)
        sim = sc.simulation()
        sim.run(0.01 * sc.t_end, record="none")          # load / compile
        wall, _, res = _time_sim(sim, sc.t_end, repeat)
        sim_rate[n] = res.n_events / wall
    rows = []
    for name, kw in cases:
        for n in sizes:
            sc = get("polygon_gas", n=n, packing=PACKING, crossings=crossings, seed=seed, **kw)
            sim = sc.simulation()
            _time_sim(sim, 0.01 * sc.t_end, 1)            # load / compile
            wall, cpu, res = _time_sim(sim, sc.t_end, repeat)
            ev = res.n_events
            rate = ev / wall
            rows.append(dict(poly=True, case=name, n=n, t_end=sc.t_end, status=res.status,
                             t=res.t_end, events=ev, impacts=res.n_impacts, run_s=wall,
                             events_per_s=rate, events_per_cpu_s=ev / max(cpu, 1e-9),
                             us_per_event=1e6 * wall / max(ev, 1),
                             gas_disks_per_s=gas_rate[n], sim_disks_per_s=sim_rate[n],
                             ratio_gas=rate / gas_rate[n], ratio_sim=rate / sim_rate[n]))
        done = [r for r in rows if r["case"] == name and r["status"] == "done"
                and r["events"] > 0]
        slope = math.nan
        if len(done) >= 2:
            slope = float(np.polyfit(np.log([r["n"] for r in done]),
                                     np.log([r["us_per_event"] for r in done]), 1)[0])
        rows.append(dict(poly=True, case=name, slope=slope,
                         sizes=[r["n"] for r in done]))
    return rows


def bench_bed(**over):
    """The settling bed (``BED``, keywords override it) run to ``t_end`` with sleep and
    without: rows ``{bed: True, sleep, n, dim, t_end, tc, impacts, cpu_s, run_s, asleep,
    sleeps, wakes}`` (the code is loaded or compiled by a short run first, untimed)."""
    from .manybody import random_gas, run_gas
    p = dict(BED, **over)
    s = random_gas(p["n"], dim=p["dim"], packing=p["packing"], law=p["law"], seed=p["seed"],
                   gravity=p["gravity"], e=p["e"])
    rows = []
    for sleep in (True, False):
        run_gas(s, max_impacts=1000, tc=p["tc"], sleep=sleep)       # load / compile
        t0, c0 = time.perf_counter(), time.process_time()
        res = run_gas(s, t_end=p["t_end"], tc=p["tc"], sleep=sleep)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        rows.append(dict(bed=True, sleep=sleep, n=p["n"], dim=p["dim"], t_end=p["t_end"],
                         tc=p["tc"], t=res.t, impacts=res.n_impacts, cpu_s=cpu, run_s=wall,
                         asleep=res.n_asleep, sleeps=res.n_sleeps, wakes=res.n_wakes))
    return rows


def print_manybody(rows):
    if any(not (r.get("poly") or r.get("bed")) for r in rows):
        print(f"Many bodies: impacts/s (body-body + wall, the law on every impact) against "
              f"N, packing {PACKING}, one thread; median wall-clock rate and rate per CPU "
              f"second")
        print(f"{'case':<48}{'record':>7}{'N':>7}{'impacts':>9}{'M/s':>8}{'M/s cpu':>9}"
              f"{'coll':>9}{'wall':>7}{'cross/imp':>10}")
    poly_head = False
    for r in rows:
        if r.get("poly"):
            if not poly_head:
                poly_head = True
                print(f"polygons: rbimpact.Simulation (exact 2D stepper, every pair of shapes "
                      f"collides) on scenario polygon_gas, packing {PACKING}, box of 4 walls, "
                      f"no gravity, {POLY_CROSSINGS:g} box crossings, recording off; ratio = "
                      f"events/s over the disk gas of the same N: 'gas' run_gas (2D smooth "
                      f"elastic disks), 'sim' the same stepper on polygon_gas shapes=disks")
                print(f"{'case':<54}{'N':>5}{'events':>8}{'impacts':>8}{'ev/s':>10}"
                      f"{'ev/s cpu':>10}{'us/ev':>8}{'disks gas/s':>12}{'ratio':>9}"
                      f"{'disks sim/s':>12}{'ratio':>8}  status")
            if "slope" in r:
                print(f"{r['case']:<54}  time per event ~ N^{r['slope']:.2f} (fit over N = "
                      f"{', '.join(map(str, r['sizes']))})")
                continue
            print(f"{r['case']:<54}{r['n']:>5}{r['events']:>8}{r['impacts']:>8}"
                  f"{r['events_per_s']:>10.0f}{r['events_per_cpu_s']:>10.0f}"
                  f"{r['us_per_event']:>8.1f}{r['gas_disks_per_s']:>12.0f}"
                  f"{r['ratio_gas']:>9.2g}{r['sim_disks_per_s']:>12.0f}"
                  f"{r['ratio_sim']:>8.2g}  {r['status']}"
                  + (f" at t = {r['t']:.4g} s of {r['t_end']:.4g} s"
                     if r["status"] != "done" else ""))
            continue
        if r.get("bed"):
            if r["sleep"]:
                print(f"bed: {r['n']} disks (dim {r['dim']}) kane_levinson e = {BED['e']}, "
                      f"g = {BED['gravity']} m/s^2, r = 0.5 m, settling from packing "
                      f"{BED['packing']} to t_end = {r['t_end']:g} s, tc = {r['tc']:g} s")
            print(f"  bed {'with sleep   ' if r['sleep'] else 'without sleep'}"
                  f"{r['impacts']:>11} impacts {r['cpu_s']:>8.2f} s cpu {r['run_s']:>8.2f} s wall"
                  f"   asleep at the end {r['asleep']:>4}, sleeps {r['sleeps']}, wakes "
                  f"{r['wakes']}")
            continue
        if "ratio" in r:
            tgt = f"  (target >= {RATIO_TARGET})" if r["case"].startswith("2D smooth") else ""
            print(f"{r['case']:<48}{r['record']:>7}  rate(4096)/rate(64) = {r['ratio']:.2f}"
                  f" (cpu {r['ratio_cpu']:.2f}){tgt}")
            continue
        tgt = ""
        if r["n"] == 4096 and r["record"] == "none" and r["case"] in TARGETS:
            tgt = f"  (target {TARGETS[r['case']] / 1e6:.1f} M/s)"
        print(f"{r['case']:<48}{r['record']:>7}{r['n']:>7}{r['impacts']:>9}"
              f"{r['impacts_per_s'] / 1e6:>8.3f}{r['impacts_per_cpu_s'] / 1e6:>9.3f}"
              f"{r['collisions']:>9}{r['wall']:>7}"
              f"{r['crossings'] / max(1, r['impacts']):>10.2f}{tgt}")
