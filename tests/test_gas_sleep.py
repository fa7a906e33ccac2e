"""Sleep and wake in the many-body engine (run_gas(sleep=...)) and the observer: beds of
inelastic disks and spheres settle under gravity and fall asleep, time then advances at
no cost, a ball dropped on a sleeping bed wakes it and the impacts resolve; energy
(kinetic + potential) never rises and its change is the recorded dE (slept energy
included); the awake-sleeper time of impact (a quartic) against an exact-arithmetic
bisection of the motion; sleep=False is the previous engine bit for bit; observer chunks
are the recorded events. Real physics, no timing."""
import hashlib
import math
from dataclasses import replace
from fractions import Fraction

import numpy as np
import pytest

from rbimpact import manybody
from rbimpact.kernels.gas_core import sleeper_toi
from rbimpact.manybody import random_gas, run_gas

# Named tolerances (relative; see each use)
OVERLAP_RTOL = 1e-11       # centre distance >= 2r (1 - OVERLAP_RTOL) for every pair
FLOOR_RTOL = 1e-11         # centre height >= r (1 - FLOOR_RTOL)
ENERGY_RTOL = 1e-10        # energy change against the summed dE, relative to E(0)
DE_RTOL = 1e-12            # no event adds more than this fraction of E(0)
TOI_RTOL = 1e-12           # quartic time of impact against the exact reference, relative
ASLEEP_FRACTION = 0.9      # a settled bed: at least this fraction of the bodies asleep
QUIET_IMPACTS_PER_BODY = 2  # impacts per body allowed once the bed is settled


def _energy(st):
    return st.kinetic_energy() + st.potential_energy()


def _min_separation(x):
    d2 = np.sum((x[:, None, :] - x[None, :, :]) ** 2, axis=-1)
    np.fill_diagonal(d2, np.inf)
    return math.sqrt(d2.min())


def _check_geometry(st):
    r = st.radius
    assert _min_separation(st.x) >= 2 * r * (1 - OVERLAP_RTOL)
    assert np.all(st.x[:, -1] >= r * (1 - FLOOR_RTOL))
    assert np.all(st.x >= r * (1 - FLOOR_RTOL)) and np.all(st.x <= st.box - r * (1 - FLOOR_RTOL))


def _settle(state, t_ends):
    """Run in segments with every event recorded; check energy at each. Returns the
    results."""
    e0 = _energy(state)
    out, st = [], state
    for t_end in t_ends:
        res = run_gas(st, t_end=t_end, record="all")
        e_a, e_b = _energy(st), _energy(res.state)
        dE = res.events["dE"]
        # the energy change is the sum of the impacts' dE (slept energy included) ...
        assert abs((e_b - e_a) - float(dE.sum())) <= ENERGY_RTOL * e0
        # ... and no event adds energy: it never increases
        assert dE.size == 0 or dE.max() <= DE_RTOL * e0
        assert e_b <= e_a + ENERGY_RTOL * e0
        assert e_a - e_b >= res.energy_slept - ENERGY_RTOL * e0 and res.energy_slept >= 0
        np.testing.assert_array_equal(res.state.asleep, res.asleep)
        assert np.all(res.v[res.asleep] == 0.0)
        _check_geometry(res.state)
        out.append(res)
        st = res.state
    return out


@pytest.fixture(scope="module")
def bed2d():
    s = random_gas(150, dim=2, packing=0.1, law="kane_levinson", e=0.7, gravity=1.0, seed=1)
    return s, _settle(s, (5.0, 10.0, 15.0, 20.0, 30.0, 45.0, 60.0))


def test_bed_of_disks_settles_and_sleeps(bed2d):
    s, runs = bed2d
    last = runs[-1]
    assert all(r.sleep for r in runs) and runs[0].sleep_speed == pytest.approx(
        manybody.SLEEP_SPEED_REL * math.sqrt(s.gravity * s.radius))
    assert sum(r.n_sleeps for r in runs) > 0
    assert last.n_asleep >= ASLEEP_FRACTION * s.n
    # settled: the bed sits in the bottom of the box
    assert last.x[:, -1].max() < 0.5 * s.box[-1]
    # time then advances to a large t_end at almost no cost
    quiet = run_gas(last.state, t_end=1e4)
    assert quiet.t == 1e4 and quiet.n_impacts <= QUIET_IMPACTS_PER_BODY * s.n
    assert quiet.n_asleep >= ASLEEP_FRACTION * s.n
    _check_geometry(quiet.state)
    assert _energy(quiet.state) <= _energy(last.state) * (1 + ENERGY_RTOL)


def test_ball_dropped_on_the_sleeping_bed_wakes_it(bed2d):
    s, runs = bed2d
    st = runs[-1].state
    x, v, asleep = st.x.copy(), st.v.copy(), st.asleep.copy()
    k = int(np.argmax(x[:, -1]))
    x[k, -1] = st.box[-1] - 2 * s.radius          # lifted to the top of the empty box
    v[k] = (0.0, -1.0)
    asleep[k] = False
    drop = replace(st, x=x, v=v, asleep=asleep)
    others = np.delete(x, k, axis=0)
    assert np.min(np.linalg.norm(others - x[k], axis=1)) > 4 * s.radius   # clear of the bed
    runs2 = _settle(drop, (st.t + 10.0, st.t + 40.0, st.t + 80.0))
    first = runs2[0]
    # it lands at ~sqrt(1 + 2 g h) ~ 6 m/s, far above the sleep speed: the bed wakes
    assert first.n_wakes > 0 and first.n_collisions > 0
    touched = {int(b) for a, b in zip(first.events["a"], first.events["b"]) if a == k and b >= 0}
    assert touched
    assert runs2[-1].n_asleep >= ASLEEP_FRACTION * s.n


def test_bed_of_spheres_settles_and_sleeps():
    s = random_gas(100, dim=3, packing=0.1, law="kane_levinson", e=0.7, gravity=1.0, seed=3)
    runs = _settle(s, (10.0, 20.0, 40.0, 60.0))
    assert runs[-1].n_asleep >= ASLEEP_FRACTION * s.n
    quiet = run_gas(runs[-1].state, t_end=1e4)
    assert quiet.t == 1e4 and quiet.n_impacts <= QUIET_IMPACTS_PER_BODY * s.n
    _check_geometry(quiet.state)


def test_bed_of_rough_disks_settles_and_sleeps():
    """Friction and spin: sleepers also need r |w| below the sleep speed. (Kane & Levinson,
    whose gas entries the suite compiles anyway: a third law's entry cost CI 70 s.)"""
    s = random_gas(100, dim=2, packing=0.1, law="kane_levinson", e=0.7, mu=0.3,
                   rough=True, gravity=1.0, seed=4)
    runs = _settle(s, (10.0, 20.0, 40.0, 60.0))
    last = runs[-1]
    assert last.n_asleep >= ASLEEP_FRACTION * s.n
    assert np.all(last.w[last.asleep] == 0.0)


# ---- the awake-sleeper time of impact -----------------------------------------------------

def _f_exact(s, d, u, g, sig2):
    """|d(s)|^2 - sigma^2 in exact rational arithmetic (d(s) = d + u s - g s^2 / 2 e_z)."""
    p = [d[a] + u[a] * s for a in range(3)]
    p[2] -= g * s * s / 2
    return sum(q * q for q in p) - sig2


def _reference_toi(d, u, g, sig2, H, grid=20000):
    """Brute force: scan [0, H] on a fine grid for the first point where f goes from > 0
    to <= 0, then bisect in exact arithmetic (the motion itself, no quartic)."""
    d = [Fraction(float(q)) for q in d]
    u = [Fraction(float(q)) for q in u]
    g, sig2 = Fraction(float(g)), Fraction(float(sig2))
    f0 = _f_exact(Fraction(0), d, u, g, sig2)
    if f0 <= 0 and sum(a * b for a, b in zip(d, u)) < 0:
        return 0.0
    # the grid in floats (fast), the bracket checked exactly
    s = np.linspace(0.0, H, grid + 1)
    df, uf = np.array([float(q) for q in d]), np.array([float(q) for q in u])
    P = df[None, :] + uf[None, :] * s[:, None]
    P[:, 2] -= 0.5 * float(g) * s * s
    F = np.sum(P * P, axis=1) - float(sig2)
    for k in np.nonzero((F[1:] <= 0) & (F[:-1] > 0))[0]:
        lo, hi = Fraction(float(s[k])), Fraction(float(s[k + 1]))
        if _f_exact(lo, d, u, g, sig2) > 0 >= _f_exact(hi, d, u, g, sig2):
            break
    else:
        return math.inf
    while hi - lo > Fraction(1, 10 ** 20) * hi:
        m = (lo + hi) / 2
        if _f_exact(m, d, u, g, sig2) > 0:
            lo = m
        else:
            hi = m
    return float(hi)


def _toi(d, u, g, sig2, H):
    return sleeper_toi(d[0], d[1], d[2], u[0], u[1], u[2], g, sig2, H, 0.0)


def _grazing_case(rng, depth, dim):
    """A falling body whose path passes a sleeper at distance sigma (1 - depth) near time
    s_star (depth > 0: a shallow impact, < 0: a near miss)."""
    g, sigma = 9.81, 1.0
    u = rng.normal(0.0, 2.0, 3)
    if dim == 2:
        u[1] = 0.0
    s_star = rng.uniform(0.2, 0.6)
    pos = u * s_star
    pos[2] -= 0.5 * g * s_star ** 2
    vel = u.copy()
    vel[2] -= g * s_star
    # a unit normal to the path at s_star, in the plane of motion (2D: the x-z plane)
    nrm = np.array([-vel[2], 0.0, vel[0]]) if dim == 2 else np.cross(vel, rng.normal(size=3))
    nrm /= np.linalg.norm(nrm)
    if nrm[2] < 0:          # the path then curves away from the sleeper: a true minimum
        nrm = -nrm
    c = pos + sigma * (1.0 - depth) * nrm
    return -c, u, g, sigma * sigma, 2.0 * s_star      # d0 = body - sleeper at s = 0


@pytest.mark.parametrize("dim", [2, 3])
def test_sleeper_time_of_impact_against_exact_motion(dim):
    rng = np.random.default_rng(11 + dim)
    hits = misses = 0
    for _ in range(120):
        d = rng.normal(0.0, 1.5, 3)
        u = rng.normal(0.0, 2.0, 3)
        if dim == 2:
            d[1] = u[1] = 0.0
        if d @ d <= 1.0:
            continue
        H = rng.uniform(0.1, 2.0)
        ref = _reference_toi(d, u, 9.81, 1.0, H)
        got = _toi(d, u, 9.81, 1.0, H)
        if math.isinf(ref):
            assert math.isinf(got)
            misses += 1
        else:
            assert abs(got - ref) <= TOI_RTOL * ref
            hits += 1
    assert hits >= 10 and misses >= 10
    # grazing: shallow impacts are found (to the time), near misses are not
    for depth in (1e-3, 1e-6, -1e-6, -1e-3):
        for _ in range(4):
            d, u, g, sig2, H = _grazing_case(rng, depth, dim)
            ref = _reference_toi(d, u, g, sig2, H, grid=200000)
            got = _toi(d, u, g, sig2, H)
            if depth < 0:
                assert math.isinf(ref) and math.isinf(got)
            else:
                assert math.isfinite(ref) and abs(got - ref) <= TOI_RTOL * ref


def test_sleeper_time_of_impact_special_cases():
    g, sig2 = 1.0, 1.0
    # resting on top, at rest: in contact and pressed in by gravity: an impact now
    assert _toi((0.0, 0.0, 1.0), (0.0, 0.0, 0.0), g, sig2, 1.0) == 0.0
    # just bounced off the top (overlap by round-off, separating): back after 2 v / g
    s = _toi((0.0, 0.0, 1.0 - 1e-16), (0.0, 0.0, 0.01), g, sig2, 1.0)
    assert s == pytest.approx(0.02, rel=1e-9)
    # a body under the sleeper, falling away: never
    assert math.isinf(_toi((0.0, 0.0, -1.5), (0.0, 0.0, -1.0), g, sig2, 10.0))
    # beside it, passing: no impact within the horizon
    assert math.isinf(_toi((3.0, 0.0, 0.0), (0.0, 0.0, 0.0), g, sig2, 10.0))
    # a horizon before the impact: none (the caller rescans after its next event)
    assert math.isinf(_toi((0.0, 0.0, 3.0), (0.0, 0.0, 0.0), g, sig2, 1.0))
    assert _toi((0.0, 0.0, 3.0), (0.0, 0.0, 0.0), g, sig2, 3.0) == pytest.approx(2.0)


# ---- sleep off is the previous engine, bit for bit -------------------------------------------

def _fingerprint(res):
    h = hashlib.sha256()
    for a in (res.x, res.v, res.w):
        h.update(np.ascontiguousarray(a).tobytes())
    for k in sorted(res.events):
        h.update(np.ascontiguousarray(res.events[k]).tobytes())
    return (res.n_collisions, res.n_wall, res.n_tc, float(res.t).hex(), h.hexdigest()[:20])


# (collisions, wall impacts, TC impacts, final time, hash of state and events) of the
# same runs by the engine before sleep existed (commit 3ad339b), on x86-64
BEFORE_SLEEP = {
    2: (3094, 46906, 45916, "0x1.0493f08e2347ep+3", "5a741d2cec4b18cd12fc"),
    3: (1667, 28333, 27301, "0x1.db3035cda4f19p+2", "cb744a59794101923037"),
}


def _inelastic_under_gravity(dim):
    if dim == 2:
        s = random_gas(150, dim=2, packing=0.1, law="kane_levinson", e=0.7, gravity=1.0, seed=1)
        return s, 50000
    s = random_gas(100, dim=3, packing=0.1, law="kane_levinson", e=0.8, gravity=1.0, seed=2)
    return s, 30000


@pytest.mark.parametrize("dim", [2, 3])
def test_sleep_off_reproduces_the_engine_before_sleep(dim):
    s, m = _inelastic_under_gravity(dim)
    res = run_gas(s, max_impacts=m, record="all", sleep=False)
    assert res.n_sleeps == res.n_wakes == 0 and res.energy_slept == 0.0
    assert _fingerprint(res) == BEFORE_SLEEP[dim]


def test_sleep_code_changes_nothing_while_nobody_rests():
    """The loop compiled with sleep, on an elastic gas under gravity (no body comes to
    rest, so none sleeps and no rebound on the floor is below the TC hop g tc / 2, the one
    thing sleep changes in an impact): the same run, bit for bit."""
    s = random_gas(150, dim=2, packing=0.1, law="kane_levinson", e=1.0, gravity=1.0, seed=1)
    off = run_gas(s, max_impacts=30000, record="all", sleep=False)
    on = run_gas(s, max_impacts=30000, record="all", sleep=True)
    assert on.sleep and on.n_sleeps == 0 and on.n_wall > 1000
    assert _fingerprint(on) == _fingerprint(off)


# ---- observer --------------------------------------------------------------------------------

def test_observer_chunks_are_the_recorded_events(monkeypatch):
    monkeypatch.setattr(manybody, "REC_CHUNK", 1000)
    monkeypatch.setattr(manybody, "SNAP_CHUNK", 7)
    s = random_gas(80, dim=2, packing=0.1, law="kane_levinson", e=0.7, gravity=1.0, seed=5)
    full = run_gas(s, t_end=20.0, record="all", snapshot_dt=0.5)
    got = {"events": [], "snapshots": []}

    def observer(kind, chunk):
        got[kind].append(chunk)

    res = run_gas(s, t_end=20.0, record="all", snapshot_dt=0.5, observer=observer)
    assert res.events is None and res.snap_t.size == 0          # handed over, not kept
    assert len(got["events"]) > 2 and all(len(c["t"]) <= 1000 for c in got["events"])
    assert all(len(c["t"]) > 0 for c in got["events"])
    for key in full.events:
        np.testing.assert_array_equal(np.concatenate([c[key] for c in got["events"]]),
                                      full.events[key])
    assert len(got["snapshots"]) > 2
    for key, ref in (("t", full.snap_t), ("v", full.snap_v), ("w", full.snap_w)):
        np.testing.assert_array_equal(np.concatenate([c[key] for c in got["snapshots"]]), ref)
    np.testing.assert_array_equal(res.x, full.x)
    # keep=True: handed over and kept
    seen = []
    both = run_gas(s, t_end=20.0, record="all", observer=lambda k, c: seen.append(c), keep=True)
    np.testing.assert_array_equal(both.events["t"], full.events["t"])
    np.testing.assert_array_equal(np.concatenate([c["t"] for c in seen]), full.events["t"])


def test_observer_keeps_memory_flat():
    import tracemalloc
    s = random_gas(200, dim=2, law="kane_levinson", e=1.0, seed=2)
    count = [0]

    def observer(kind, chunk):
        count[0] += len(chunk["t"])

    run_gas(s, max_impacts=100, record="all", observer=observer)     # compile outside
    peaks = []
    for m in (100_000, 400_000):
        tracemalloc.start()
        run_gas(s, max_impacts=m, record="all", observer=observer)
        peaks.append(tracemalloc.get_traced_memory()[1])
        tracemalloc.stop()
    # one record buffer and one chunk at a time, whatever the number of events
    assert peaks[1] <= peaks[0] * 1.1 + 4096
    assert count[0] == 100 + 100_000 + 400_000


# ---- arguments -------------------------------------------------------------------------------

def test_sleep_and_observer_bad_input():
    s = random_gas(20, dim=2, seed=0, gravity=1.0)
    flat = random_gas(20, dim=2, seed=0)
    for state, kwargs, match in [
        (s, dict(sleep="yes"), "sleep must be True or False"),
        (flat, dict(sleep=True), "sleep needs gravity > 0"),
        (s, dict(sleep_speed=-1.0), "sleep_speed must be > 0"),
        (s, dict(sleep_speed=float("nan")), "sleep_speed"),
        (s, dict(sleep_impacts=0), "sleep_impacts must be"),
        (s, dict(sleep_impacts=2.5), "sleep_impacts"),
        (s, dict(wake_gap=-0.1), "wake_gap must be >= 0"),
        (s, dict(sleep=False, sleep_speed=0.1), "sleep_speed given but sleep is off"),
        (flat, dict(wake_gap=0.1), "wake_gap given but sleep is off"),
        (s, dict(observer=3), "observer must be callable"),
        (s, dict(observer=print, keep="no"), "keep must be True or False"),
    ]:
        with pytest.raises(ValueError, match=match):
            run_gas(state, t_end=1.0, **kwargs)
    with pytest.raises(ValueError, match="state.asleep must be None or a"):
        run_gas(replace(s, asleep=np.zeros(3, bool)), t_end=1.0)
    asleep = np.zeros(20, bool)
    asleep[4] = True
    with pytest.raises(ValueError, match="body 4 is asleep .* but moves"):
        run_gas(replace(s, asleep=asleep), t_end=1.0)


def test_sleepers_in_the_state_and_sleep_off():
    """A body flagged asleep stays put with sleep on (nothing touches it) and falls with
    sleep off (the flags are then ignored)."""
    s = random_gas(2, dim=2, packing=0.01, seed=0, gravity=1.0)
    x = np.array([[0.3 * s.box[0], 0.5 * s.box[1]], [0.7 * s.box[0], 0.5 * s.box[1]]])
    st = replace(s, x=x, v=np.zeros((2, 2)), w=np.zeros(2), asleep=np.array([True, True]))
    on = run_gas(st, t_end=5.0)
    assert on.stop == "no event left" and on.t == 5.0 and on.n_impacts == 0
    np.testing.assert_array_equal(on.x, x)
    assert on.n_asleep == 2 and list(on.state.asleep) == [True, True]
    off = run_gas(st, t_end=5.0, sleep=False)
    assert np.all(off.x[:, 1] < x[:, 1]) and off.state.asleep is None and off.n_asleep == 0
