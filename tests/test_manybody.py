"""Many-body engine (rbimpact.manybody, kernels/gas_core, kernels/scheduler): conservation,
no overlap, agreement with a brute-force O(N^2) event search, the law's impulse on a
recorded impact, recording modes, the collapse option and bad input. No timing."""
import math

import numpy as np
import pytest

from rbimpact.laws import Law
from rbimpact.manybody import GasState, contact_W, random_gas, run_gas

# Named tolerances (relative; see each use)
ENERGY_RTOL = 1e-12        # kinetic energy of an elastic gas, relative to itself
MOMENTUM_RTOL = 1e-12      # momentum balance, relative to the sum of |wall impulses|
OVERLAP_RTOL = 1e-11       # centre distance >= 2r (1 - OVERLAP_RTOL) for every pair
TIME_RTOL = 1e-12          # event times against the brute-force reference, relative to t
IMPULSE_RTOL = 1e-13       # recorded impulse against Law.resolve, relative to |P|


def _min_separation(x):
    d2 = np.sum((x[:, None, :] - x[None, :, :]) ** 2, axis=-1)
    np.fill_diagonal(d2, np.inf)
    return math.sqrt(d2.min())


def _world_impulse(events, k):
    """Impulse on A of recorded impact k in world coordinates (2D)."""
    n = events["n"][k]
    t = np.array([n[1], -n[0]])
    return events["P"][k, 0] * n + events["P"][k, 1] * t


def test_elastic_gas_conserves_energy_and_balances_momentum():
    s = random_gas(100, dim=2, packing=0.2, law="kane_levinson", e=1.0, seed=3)
    res = run_gas(s, max_impacts=60_000, record="all")
    assert res.n_collisions + res.n_wall == 60_000 and res.stop == "max_impacts"
    assert res.n_collisions > 40_000 and res.n_wall > 0
    e0, e1 = s.kinetic_energy(), res.state.kinetic_energy()
    assert abs(e1 / e0 - 1.0) <= ENERGY_RTOL
    ev = res.events
    assert np.all(np.diff(ev["t"]) >= 0.0)
    assert np.all(np.abs(ev["dE"]) <= 1e-12 * e0)
    # momentum changes only at the walls: p_final - p_initial = sum of wall impulses
    walls = np.nonzero(ev["b"] < 0)[0]
    Pw = np.array([_world_impulse(ev, k) for k in walls])
    dp = s.mass * (res.v.sum(axis=0) - s.v.sum(axis=0))
    scale = np.abs(Pw).sum()
    assert np.all(np.abs(dp - Pw.sum(axis=0)) <= MOMENTUM_RTOL * scale)
    assert _min_separation(res.x) >= 2 * s.radius * (1 - OVERLAP_RTOL)
    assert np.all(res.x >= s.radius * (1 - OVERLAP_RTOL))
    assert np.all(res.x <= s.box - s.radius * (1 - OVERLAP_RTOL))


def _brute_force(x, v, r, L, n_events):
    """Reference: O(N^2) search of the next event, exact elastic equal-mass impacts."""
    x, v = x.copy(), v.copy()
    n, dim = x.shape
    t, out = 0.0, []
    for _ in range(n_events):
        best, what = math.inf, None
        for i in range(n):
            for j in range(i + 1, n):
                dr, dv = x[i] - x[j], v[i] - v[j]
                b = dr @ dv
                if b < 0:
                    c = dr @ dr - 4 * r * r
                    disc = b * b - (dv @ dv) * c
                    if disc > 0:
                        s = c / (-b + math.sqrt(disc))
                        if s < best:
                            best, what = s, (i, j)
            for a in range(dim):
                if v[i, a] > 0:
                    s, wall = (L[a] - r - x[i, a]) / v[i, a], 2 * a + 1
                elif v[i, a] < 0:
                    s, wall = (r - x[i, a]) / v[i, a], 2 * a
                else:
                    continue
                if s < best:
                    best, what = s, (i, -1 - wall)
        x += v * best
        t += best
        i, j = what
        if j >= 0:
            d = x[i] - x[j]
            nrm = d / math.sqrt(d @ d)
            vn = (v[i] - v[j]) @ nrm
            v[i] -= vn * nrm
            v[j] += vn * nrm
        else:
            v[i, (-1 - j) // 2] *= -1.0
        out.append((t, i, j))
    return out


@pytest.mark.parametrize("dim", [2])
def test_event_times_match_brute_force(dim):
    s = random_gas(12, dim=dim, packing=0.25, law="kane_levinson", e=1.0, seed=5)
    # 40 impacts: the gas is chaotic, round-off differences (1e-16) grow by orders of
    # magnitude over a few dozen impacts (1e-12 reached near impact 50 for this seed)
    ref = _brute_force(s.x, s.v, s.radius, s.box, 40)
    res = run_gas(s, max_impacts=40, record="all")
    ev = res.events
    assert len(ev["t"]) == 40
    for k, (t, i, j) in enumerate(ref):
        assert abs(ev["t"][k] - t) <= TIME_RTOL * t
        got = (ev["a"][k], ev["b"][k])
        assert (got == (i, j)) or (j >= 0 and got == (j, i))


def test_recorded_impulse_is_the_law_on_that_contact():
    s = random_gas(60, dim=2, packing=0.2, law="kane_levinson", e=0.9, mu=0.3, rough=True,
                   seed=2)
    res = run_gas(s, max_impacts=2000, record="all", collapse="none")
    ev = res.events
    law = Law("kane_levinson", e=0.9, mu=0.3)
    modes = set()
    for k in range(len(ev["t"])):
        wall = ev["b"][k] < 0
        wnn, wtt = contact_W(s, wall=wall)
        imp = law.resolve(ev["v"][k], np.diag([wnn, wtt]))
        assert np.all(np.abs(imp.P - ev["P"][k]) <= IMPULSE_RTOL * np.abs(imp.P).max())
        assert imp.mode_code == ev["mode"][k]
        assert math.isclose(imp.dE, ev["dE"][k], rel_tol=1e-9, abs_tol=1e-15)
        modes.add(imp.mode)
    assert modes == {"stick", "slip"}        # both branches of the law were exercised
    assert res.state.kinetic_energy() < s.kinetic_energy()


@pytest.mark.parametrize("dim", [2, 3])
def test_rough_energy_balance_matches_the_laws_dE(dim):
    """The contact-space velocity and W handed to the law agree with the bodies' motion:
    the sum of the laws' dE equals the change of kinetic energy (spin included)."""
    s = random_gas(60, dim=dim, packing=0.2, law="kane_levinson", e=0.8, mu=0.5,
                   rough=True, seed=9)
    res = run_gas(s, max_impacts=5000, record="all", collapse="none")
    de = res.state.kinetic_energy() - s.kinetic_energy()
    assert de < -0.1 * s.kinetic_energy()
    assert abs(res.events["dE"].sum() - de) <= 1e-10 * s.kinetic_energy()
    assert np.any(res.w != 0.0)
    assert _min_separation(res.x) >= 2 * s.radius * (1 - OVERLAP_RTOL)


def test_bodies_at_rest_end_the_run_without_events():
    s = random_gas(10, seed=0)
    s.v[:] = 0.0
    res = run_gas(s, max_impacts=100)
    assert res.n_impacts == 0 and res.stop == "no event left"
    res = run_gas(s, t_end=3.0)
    assert res.t == 3.0 and res.stop in ("t_end", "no event left")
    np.testing.assert_array_equal(res.x, s.x)


def test_memory_with_recording_off_does_not_grow_with_events():
    import tracemalloc
    s = random_gas(200, dim=2, law="kane_levinson", e=1.0, seed=2)
    run_gas(s, max_impacts=100)                 # compile/load outside the measurement
    peaks = []
    for m in (2_000, 100_000):
        tracemalloc.start()
        run_gas(s, max_impacts=m)
        peaks.append(tracemalloc.get_traced_memory()[1])
        tracemalloc.stop()
    assert peaks[1] <= peaks[0] + 4096            # bytes: same arrays, whatever the events
    assert peaks[0] < 200 * 1024                  # ~ state, cells and queue: < 1 kB per body


def test_recording_modes_and_snapshots():
    s = random_gas(50, dim=2, law="kane_levinson", e=1.0, seed=1)
    full = run_gas(s, t_end=5.0, record="all", snapshot_dt=1.0)
    none = run_gas(s, t_end=5.0)
    some = run_gas(s, t_end=5.0, record=np.array([3, 7]))
    assert none.events is None and full.t == none.t == some.t == 5.0
    assert full.n_collisions == none.n_collisions == some.n_collisions
    np.testing.assert_array_equal(full.x, none.x)
    sel = (full.events["a"] == 3) | (full.events["a"] == 7) | (full.events["b"] == 3) | (
        full.events["b"] == 7)
    np.testing.assert_array_equal(some.events["t"], full.events["t"][sel])
    np.testing.assert_array_equal(full.snap_t, [0.0, 1.0, 2.0, 3.0, 4.0, 5.0])
    assert full.snap_v.shape == (6, 50, 2) and full.snap_w.shape == (6, 50)
    np.testing.assert_array_equal(full.snap_v[0], s.v)
    # kinetic energy of every snapshot is the initial one (elastic)
    ke = 0.5 * s.mass * np.sum(full.snap_v ** 2, axis=(1, 2))
    assert np.all(np.abs(ke / s.kinetic_energy() - 1) <= ENERGY_RTOL)
    # continuing from the final state gives the same as one run
    half = run_gas(s, t_end=2.5)
    rest = run_gas(half.state, t_end=5.0)
    assert rest.n_collisions + half.n_collisions == none.n_collisions
    np.testing.assert_allclose(rest.x, none.x, rtol=0, atol=1e-9)


def test_gravity_conserves_total_energy():
    s = random_gas(80, dim=2, packing=0.1, law="kane_levinson", e=1.0, gravity=0.5, seed=4)
    res = run_gas(s, max_impacts=20_000)

    def total(st):
        return st.kinetic_energy() + st.mass * st.gravity * float(np.sum(st.x[:, -1]))
    e0 = total(s)
    assert abs(total(res.state) / e0 - 1.0) <= 1e-10
    assert _min_separation(res.x) >= 2 * s.radius * (1 - OVERLAP_RTOL)
    assert np.all(res.x[:, -1] >= s.radius * (1 - OVERLAP_RTOL))


def test_inelastic_gas_with_tc_never_stalls():
    s = random_gas(200, dim=2, packing=0.3, law="kane_levinson", e=0.3, seed=6)
    res = run_gas(s, max_impacts=100_000, collapse="tc")
    assert res.n_impacts == 100_000 and res.collapse == "tc" and res.tc > 0
    assert res.state.kinetic_energy() < 0.5 * s.kinetic_energy()
    assert _min_separation(res.x) >= 2 * s.radius * (1 - OVERLAP_RTOL)


def test_3d_elastic_spheres():
    s = random_gas(64, dim=3, packing=0.15, law="kane_levinson", e=1.0, seed=7)
    res = run_gas(s, max_impacts=20_000)
    assert abs(res.state.kinetic_energy() / s.kinetic_energy() - 1.0) <= ENERGY_RTOL
    assert _min_separation(res.x) >= 2 * s.radius * (1 - OVERLAP_RTOL)
    assert res.w.shape == (64, 3)


@pytest.mark.parametrize("kwargs, match", [
    (dict(n=1), "n must be"),
    (dict(n=10, dim=4), "dim must be 2"),
    (dict(n=10, packing=0.9), "packing must be in"),
    (dict(n=10, packing=-0.1), "packing must be in"),
    (dict(n=10, radius=0.0), "radius must be > 0"),
    (dict(n=10, law="newton"), "law must be one of"),
    (dict(n=10, e=2.0), "parameter 'e'"),
    (dict(n=10, gravity=-1.0), "gravity must be >= 0"),
    (dict(n=10, rough="yes"), "rough must be True or False"),
    (dict(n=10, seed=-1), "seed must be"),
    (dict(n=10, temperature=float("nan")), "temperature"),
])
def test_random_gas_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        random_gas(**kwargs)


def test_run_gas_bad_input():
    s = random_gas(10, seed=0)
    for kwargs, match in [
        (dict(), "give t_end"),
        (dict(t_end=-1.0), "t_end must be >="),
        (dict(max_impacts=-5), "max_impacts must be"),
        (dict(t_end=1.0, record="some"), "record must be"),
        (dict(t_end=1.0, record=np.array([0, 10])), "record indices"),
        (dict(t_end=1.0, record=np.array([0.5])), "record must be"),
        (dict(t_end=1.0, collapse="luding"), "collapse must be one of"),
        (dict(t_end=1.0, tc=0.0), "tc must be > 0"),
        (dict(t_end=1.0, snapshot_dt=-1.0), "snapshot_dt must be > 0"),
    ]:
        with pytest.raises(ValueError, match=match):
            run_gas(s, **kwargs)
    with pytest.raises(ValueError, match="GasState"):
        run_gas("gas", t_end=1.0)
    bad = GasState(**{**s.__dict__, "x": s.x[:, :1]})
    with pytest.raises(ValueError, match="state.x"):
        run_gas(bad, t_end=1.0)
    bad = GasState(**{**s.__dict__, "v": np.full_like(s.v, np.nan)})
    with pytest.raises(ValueError, match="non-finite"):
        run_gas(bad, t_end=1.0)
    bad = GasState(**{**s.__dict__, "x": s.x + s.box[0]})
    with pytest.raises(ValueError, match="centre"):
        run_gas(bad, t_end=1.0)
    bad = GasState(**{**s.__dict__, "law_params": {"e": 1.0, "e_t": 0.5}})
    with pytest.raises(ValueError, match="takes no parameter"):
        run_gas(bad, t_end=1.0)


def test_scheduler_orders_like_a_sort():
    from rbimpact.kernels import scheduler as sch
    rng = np.random.default_rng(0)
    n = 500
    q = sch.q_alloc(n, 64)
    qkey, qlink, qheap, qhead, qs, qdt = q
    sch.q_init(qkey, qlink, qheap, qhead, qs, qdt, 64, 0.01, 0.0)
    keys = rng.exponential(1.0, n)
    keys[::50] = np.inf
    for i in range(n):
        sch.q_push_k(i, keys[i], *q)
    for i in range(0, n, 7):                  # move some bodies
        keys[i] = rng.exponential(2.0)
        sch.q_update_k(i, keys[i], *q)
    sch.q_remove_k(3, qkey, qlink, qheap, qhead, qs)
    order = [sch.q_pop_k(*q) for _ in range(n - 1)]
    assert sch.q_pop_k(*q) == -1
    expect = [i for i in np.argsort(keys, kind="stable") if i != 3]
    assert [keys[i] for i in order] == [keys[i] for i in expect]


def test_bench_manybody_rows_on_a_tiny_size():
    """Structure of the bench rows (no timing thresholds: timings are not tested)."""
    from rbimpact import bench_manybody as bm
    rows = bm.bench_manybody(sizes=(64, 4096), cases=bm.CASES[:1], min_impacts=2000,
                             bed=False)
    runs = [r for r in rows if "n" in r]
    assert [(r["n"], r["record"]) for r in runs] == [(64, "none"), (64, "all"),
                                                     (4096, "none"), (4096, "all")]
    for r in runs:
        assert r["impacts"] == max(2000, bm.IMPACTS_PER_BODY * r["n"])
        assert r["collisions"] + r["wall"] == r["impacts"] and r["impacts_per_s"] > 0
    ratio = {r["record"]: r for r in rows if "ratio" in r}
    assert set(ratio) == {"none", "all"}
    by = {(r["n"], r["record"]): r["impacts_per_s"] for r in runs}
    assert math.isclose(ratio["none"]["ratio"], by[(4096, "none")] / by[(64, "none")])


def test_bench_bed_rows_on_a_small_bed():
    """The settling bed with and without sleep (structure only, no timing thresholds)."""
    from rbimpact import bench_manybody as bm
    rows = bm.bench_bed(n=30, t_end=15.0)
    assert [r["sleep"] for r in rows] == [True, False]
    for r in rows:
        assert r["bed"] and r["t"] == 15.0 and r["impacts"] > 0 and r["cpu_s"] >= 0
    assert rows[1]["asleep"] == rows[1]["sleeps"] == 0 and rows[0]["sleeps"] > 0
    assert rows[0]["impacts"] < rows[1]["impacts"]


_CACHE_SCRIPT = """
from rbimpact.manybody import random_gas, run_gas
run_gas(random_gas(20, dim=2, law="kane_levinson", e=0.5, seed=0), max_impacts=100,
        sleep=False)
"""


def test_gas_entry_compiles_one_law_and_loads_from_disk_cache():
    """Two new processes run a 2D Kane & Levinson gas (Numba's cache as configured): the
    first compiles, if the cache is cold, no other law and no 3D code; the second compiles
    nothing and loads the run entry (a closure of ``gas_entries``) from the disk cache.
    (The suite's own law: a Smith gas entry cost CI 56 s of compilation for this test.)"""
    import os
    import subprocess
    import sys
    if os.environ.get("NUMBA_DISABLE_JIT") == "1":
        pytest.skip("JIT disabled: nothing is cached")
    env = dict(os.environ, NUMBA_DEBUG_CACHE="1")
    runs = [subprocess.run([sys.executable, "-c", _CACHE_SCRIPT], env=env, check=True,
                           capture_output=True, text=True).stdout.splitlines()
            for _ in range(2)]

    def files(lines, what):       # cache file names (module.function-line...) of the lines
        return [ln.rstrip("'").rsplit("/", 1)[1] for ln in lines if what in ln]
    others = ("smith.", "brach.", "routh.", "chatterjee_ruina.")
    assert not [f for f in files(runs[0], "data saved") if "3d" in f or f.startswith(others)]
    assert files(runs[1], "data saved") == []
    assert [f for f in files(runs[1], "data loaded") if f.startswith("gas_entries._run_for")]


def test_gas_entries_bad_input():
    from rbimpact.kernels.gas_entries import entries_for
    with pytest.raises(ValueError, match="D must be 2 or 3"):
        entries_for(4, 0, False)
    with pytest.raises(ValueError, match="law must be one of"):
        entries_for(2, 7, False)
    assert entries_for(2, 2, False) is not entries_for(3, 2, False)
    assert entries_for(2, 2, 0)[1] is entries_for(2, 2, False)[1]
