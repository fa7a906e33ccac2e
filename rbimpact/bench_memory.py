"""``rbimpact bench memory``: peak memory of a run against its number of events, with
every event recorded and with recording off (issue 15: "a run with recording off uses
memory that does not grow with the number of events").

Two engines: the few-body stepper (``Simulation.run``, the elastic bouncing ball, one
impact per bounce) and the many-body gas (``run_gas``, 1024 elastic disks at packing 0.15).
Each is run for ``n`` and ``10 n`` events; the peak is the largest memory NumPy and Python
held during the run (``tracemalloc``, after a warm-up run so that nothing compiles).
``growth`` is peak(10 n) / peak(n) in the same run: about 10 with ``record="all"``, about 1
with ``record="none"``.
"""
import tracemalloc
import warnings


def _peak(fn):
    tracemalloc.start()
    tracemalloc.reset_peak()
    try:
        fn()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def bench_memory(n_stepper=100_000, n_gas=200_000, gas_bodies=1024):
    """Rows ``{engine, record, events, peak_bytes, bytes_per_event}`` for ``n`` and ``10 n``
    events, plus a ``growth`` entry per engine and record."""
    from . import scenarios
    from .manybody import random_gas, run_gas

    sim = scenarios.get("bouncing_ball", elastic=True).simulation()

    def stepper(n, rec):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return sim.run(1e9, max_events=n, record=rec)

    gas = random_gas(gas_bodies, dim=2, packing=0.15, seed=0)
    gas = run_gas(gas, max_impacts=5 * gas_bodies).state

    def gas_run(n, rec):
        return run_gas(gas, max_impacts=n, record=rec)

    rows = []
    for engine, fn, n in (("Simulation.run (bouncing ball)", stepper, n_stepper),
                          (f"run_gas ({gas_bodies} disks)", gas_run, n_gas)):
        fn(1000, "all")                                 # warm: load the compiled code
        for rec in ("all", "none"):
            peaks = []
            for m in (n, 10 * n):
                p = _peak(lambda: fn(m, rec))
                peaks.append(p)
                rows.append(dict(engine=engine, record=rec, events=m, peak_bytes=p,
                                 bytes_per_event=p / m))
            rows.append(dict(engine=engine, record=rec, growth=peaks[1] / peaks[0]))
    return rows


def print_memory(rows):
    print("Peak memory of a run (tracemalloc) against its number of events")
    print(f"{'engine':<34}{'record':>7}{'events':>10}{'peak MB':>10}{'B/event':>9}")
    for r in rows:
        if "growth" in r:
            print(f"{r['engine']:<34}{r['record']:>7}  peak(10 n) / peak(n) = "
                  f"{r['growth']:.2f}")
            continue
        print(f"{r['engine']:<34}{r['record']:>7}{r['events']:>10}"
              f"{r['peak_bytes'] / 1e6:>10.2f}{r['bytes_per_event']:>9.1f}")
