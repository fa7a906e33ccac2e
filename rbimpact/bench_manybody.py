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
"""
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


def bench_manybody(repeat=1, sizes=SIZES, cases=None, records=("none", "all"),
                   min_impacts=MIN_IMPACTS, seed=0):
    """Rows ``{case, n, record, impacts, run_s, impacts_per_s, impacts_per_cpu_s,
    collisions, wall, crossings, stale}`` plus one ``ratio`` row per case and record."""
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
    return rows


def print_manybody(rows):
    print(f"Many bodies: impacts/s (body-body + wall, the law on every impact) against N, "
          f"packing {PACKING}, one thread; median wall-clock rate and rate per CPU second")
    print(f"{'case':<48}{'record':>7}{'N':>7}{'impacts':>9}{'M/s':>8}{'M/s cpu':>9}"
          f"{'coll':>9}{'wall':>7}{'cross/imp':>10}")
    for r in rows:
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
