"""Bounded memory (issue 15): with recording off, the peak memory of a run does not grow
with its number of events, in the few-body stepper and in the many-body gas; with every
event recorded it grows in proportion (``rbimpact bench memory``)."""
from rbimpact.bench_memory import bench_memory


def test_memory_is_flat_with_recording_off():
    # at least one fixed buffer of events (_recording.DRAIN_ROWS) in the smaller run
    rows = bench_memory(n_stepper=50_000, n_gas=40_000, gas_bodies=64)
    growth = {(r["engine"].split()[0], r["record"]): r["growth"] for r in rows if "growth" in r}
    for engine in ("Simulation.run", "run_gas"):
        assert growth[(engine, "none")] < 1.05, growth
        assert growth[(engine, "all")] > 5.0, growth
