"""The exact event-driven 2D stepper (issue 3, DESIGN §5-6): real physics, closed forms."""
import math

import numpy as np
import pytest

from rbimpact.laws import Law
from rbimpact.scene import Scene2D
from rbimpact.shapes import Box, Disk, Polygon, Rod
from rbimpact.simulation import Simulation

G0 = 9.80665


def drop_ball(e=0.8, h=1.0, g=G0, r=0.05, mu=0.0, vx=0.0, law="kane_levinson"):
    scene = Scene2D(gravity=(0.0, -g))
    scene.add_floor(0.0)
    scene.add_body(Disk(r), 1.0, (0.0, h + r), velocity=(vx, 0.0))
    return Simulation(scene, Law(law, e=e, mu=mu))


def exact_bounce_times(n, e, h, g):
    t1 = math.sqrt(2 * h / g)
    t = [t1]
    for k in range(1, n):
        t.append(t[-1] + 2 * e ** k * math.sqrt(2 * g * h) / g)
    return np.array(t)


# ---------------------------------------------------------------- bouncing ball (Zeno)

def test_bouncing_ball_times_accumulation_and_rest():
    e, h = 0.8, 1.0
    res = drop_ball(e, h).run(6.0)
    ev = res.events
    imp = ev[ev["kind"] == "impact"]
    exact = exact_bounce_times(30, e, h, G0)
    assert np.max(np.abs(imp["t"][:30] - exact) / exact) < 1e-10
    # each impact reverses the normal velocity with ratio e exactly
    np.testing.assert_allclose(imp["v_f"][:30, 0], -e * imp["v_i"][:30, 0], rtol=1e-12)
    # one switch to persistent contact, at the accumulation point t_inf = t1 (1+e)/(1-e)
    sw = ev[ev["kind"] != "impact"]
    assert list(sw["kind"]) == ["contact"]
    t_inf = math.sqrt(2 * h / G0) * (1 + e) / (1 - e)
    assert abs(t_inf - 4.064406802) < 1e-9
    assert abs(sw["t"][0] - t_inf) < 1e-6
    assert sw["mode"][0] == 3                     # rest
    assert np.all(imp["t"] < sw["t"][0])
    assert -1e-8 < sw["dE"][0] <= 0.0             # the snap removes at most m g rest_length
    s = res.sample(np.array([t_inf + 1e-6, 5.0, 6.0]))
    np.testing.assert_allclose(s["y"][:, 0], 0.05, atol=1e-12)
    np.testing.assert_allclose(s["vy"][:, 0], 0.0, atol=1e-12)
    assert res.status == "done" and res.t_end == 6.0


def test_zeno_jump_holds_the_ball_on_the_floor():
    """From the last impact to the accumulation time the ball is held on the floor (no
    free flight through it: 4 h / (1 - e)^2 = 3.9e-6 m before), its horizontal motion
    exact, and the energy never increases; the "contact" event at t_inf carries the
    accumulated impulse m v (1 + e) / (1 - e) and the energy removed."""
    e, h, r, vx = 0.99, 1.0, 0.05, 0.3
    res = drop_ball(e, h, r=r, vx=vx).run(400.0)
    ev = res.events
    imp = ev[ev["kind"] == "impact"]
    sw = ev[ev["kind"] == "contact"]
    t_inf = math.sqrt(2 * h / G0) * (1 + e) / (1 - e)
    assert len(sw) == 1 and abs(sw["t"][0] - t_inf) < 1e-9 * t_inf
    t_last = imp["t"][-1]
    # dense sampling across the jump and around t_inf
    t = np.concatenate([np.linspace(imp["t"][-50], t_inf + 1e-3, 20001),
                        t_inf + np.linspace(-1e-6, 1e-6, 2001)])
    s = res.sample(np.sort(t))
    assert float(np.min(s["y"][:, 0] - r)) >= -1e-12
    held = (np.sort(t) > t_last) & (np.sort(t) < t_inf)
    assert held.sum() > 1000
    np.testing.assert_allclose(s["vy"][held, 0], 0.0, atol=0.0)
    np.testing.assert_allclose(s["x"][:, 0], vx * np.sort(t), rtol=1e-12)
    E = res.energy(np.sort(t))
    assert float(np.max(np.diff(E))) <= 1e-12 * float(np.max(np.abs(E)))
    # accumulated impulse and energy removed by the bounces after the last impact
    v = imp["v_f"][-1, 0]
    assert math.isclose(sw["P"][0, 0], v * (1 + e) / (1 - e), rel_tol=1e-6)
    assert math.isclose(sw["dE"][0], -0.5 * v * v, rel_tol=1e-6, abs_tol=1e-15)
    # honest accounting: the events' dE add up to the energy change of the run
    E0, E1 = res.energy(np.array([0.0, 400.0]))
    assert math.isclose(float(np.sum(ev["dE"])), E1 - E0, rel_tol=1e-9, abs_tol=1e-12)


def test_box_rest_face_is_the_least_inclined():
    """The face a tilted box would settle on is the one least inclined to the plane, not
    the one of the two lowest corners (a short steep face can end lower)."""
    from rbimpact.kernels.stepper2d import _rest_config
    a, b, th = 0.1, 0.05, 0.5467          # 0.2 x 0.1 box tilted by 31 degrees
    st = np.zeros((1, 9))
    st[0, 1] = b * math.cos(th) + a * math.sin(th)      # lowest corner on the floor
    st[0, 2] = th
    bint = np.array([[1, 0, 4]], np.int64)
    bflt = np.array([[1.0, (0.2 ** 2 + 0.1 ** 2) / 12, 0.0, 0.0, 0.0]])
    verts = np.array([[-a, -b], [a, -b], [a, b], [-a, b]])
    planes = np.array([[0.0, 1.0, 0.0]])
    grav = np.array([0.0, -G0])
    stable, f0, f1, hf, dth, eex = _rest_config(0, 0, st, bint, bflt, verts, planes, grav)
    assert {f0, f1} == {0, 1} and stable            # the long bottom face
    assert math.isclose(hf, b) and math.isclose(dth, -th)
    # its rest is below the centre of mass: snapping there removes m g (h_c - h_f)
    assert math.isclose(eex, G0 * (st[0, 1] - b), rel_tol=1e-12)


def test_flat_box_sequential_never_creates_energy():
    """Sequential flat landing of a 0.2 x 0.1 box (routh e=0.5 mu=0.3): after the corner
    impacts the box must not be snapped onto its short side (which lifts it: +0.039 J
    before); a corner then pivots (integrated contact) and the box ends on its long face,
    with the energy never increasing."""
    scene = Scene2D(gravity=(0.0, -9.81))
    scene.add_floor(0.0)
    scene.add_body(Box(0.2, 0.1), 1.0, (0.0, 0.55))
    sim = Simulation(scene, Law("routh", e=0.5, mu=0.3), policy="sequential")
    res = sim.run(2.0)       # the corner pivots (integrated) instead of chattering
    ev = res.events
    assert float(np.max(ev["dE"])) <= 1e-12
    t = np.linspace(0.0, res.t_end, 20001)
    E = res.energy(t)
    assert float(np.max(E - np.minimum.accumulate(E))) <= 1e-12 * float(np.max(np.abs(E)))
    for k in ev[ev["kind"] == "contact"]:
        ang = float(res.sample(np.array([k["t"]]))["angle"][0, 0])
        assert abs(math.remainder(ang, math.pi)) < 1e-9     # on a long face only


def test_sample_is_exact_flight_between_impacts():
    e, h, r = 0.8, 1.0, 0.05
    res = drop_ball(e, h, r=r).run(2.0)
    t = exact_bounce_times(3, e, h, G0)
    v1 = e * math.sqrt(2 * G0 * h)                 # speed leaving the first impact
    ts = np.linspace(t[0], t[1], 7)[1:-1]
    s = res.sample(ts)
    y = r + v1 * (ts - t[0]) - 0.5 * G0 * (ts - t[0]) ** 2
    np.testing.assert_allclose(s["y"][:, 0], y, rtol=0, atol=1e-12)
    np.testing.assert_allclose(s["vy"][:, 0], v1 - G0 * (ts - t[0]), atol=1e-12)
    # energy is constant in flight and drops by exactly the dE of each impact
    E = res.energy(np.array([0.0, 0.5 * (t[0] + t[1]), 0.5 * (t[1] + t[2])]))
    imp = res.events[res.events["kind"] == "impact"]
    np.testing.assert_allclose(np.diff(E), imp["dE"][:2], rtol=1e-9)
    with pytest.raises(ValueError):
        res.sample([3.0])


def test_elastic_ball_1e5_impacts_conserves_energy():
    sim = drop_ball(e=1.0, mu=0.0)
    period = 2 * math.sqrt(2 * 1.0 / G0)
    res = sim.run(1e5 * period - 0.25 * period)
    assert res.n_impacts == 100_000 and res.status == "done"
    E = res.energy(np.linspace(0.0, res.t_end, 2001))
    assert np.max(np.abs(E - E[0])) / E[0] < 1e-9
    t = res.events["t"]
    assert abs(t[-1] - (period / 2 + 99_999 * period)) / t[-1] < 1e-10


def test_max_events_stops_early_with_warning():
    sim = drop_ball(e=1.0)
    with pytest.warns(RuntimeWarning, match="max_events"):
        res = sim.run(100.0, max_events=10)
    assert res.status == "max_events" and len(res.events) == 10
    assert res.t_end < 100.0 and res.t_end == res.events["t"][-1]
    res.sample([res.t_end])


# ---------------------------------------------------------------- rods

def test_spinning_rod_first_touch():
    scene = Scene2D(gravity=(0.0, -9.81))
    scene.add_floor()
    scene.add_body(Rod(1.0), 1.0, (0.0, 1.0), angular_velocity=3.0)
    res = Simulation(scene, Law("kane_levinson", e=0.5, mu=0.3)).run(0.4)
    t1 = res.events["t"][0]
    assert abs(t1 - 0.341679324) < 1e-9
    # the gap of the touching end is zero there
    s = res.sample([t1])
    th, y = s["angle"][0, 0], s["y"][0, 0]
    assert abs(y - 0.5 * abs(math.sin(th))) < 1e-12


def flat_rod(policy, e=0.5, mu=0.0, h=0.5, L=1.0, t_end=0.35):
    scene = Scene2D(gravity=(0.0, -9.81))
    scene.add_floor()
    scene.add_body(Rod(L), 1.0, (0.0, h))
    return Simulation(scene, Law("kane_levinson", e=e, mu=mu), policy=policy), h


def test_flat_rod_simultaneous_symmetric():
    sim, h = flat_rod("simultaneous", e=0.5, mu=0.3)
    res = sim.run(3.0)
    assert res.policy == "simultaneous"
    t1 = math.sqrt(2 * h / 9.81)
    v = math.sqrt(2 * 9.81 * h)
    ev = res.events
    first = ev[:2]
    assert np.all(first["kind"] == "impact") and np.all(first["cluster"] == 2)
    np.testing.assert_allclose(first["t"], t1, rtol=1e-12)
    np.testing.assert_allclose(first["P"][:, 0], 0.5 * (1 + 0.5) * v, rtol=1e-10)
    np.testing.assert_allclose(first["P"][:, 1], 0.0, atol=1e-12)
    np.testing.assert_allclose(first["v_f"][:, 0], 0.5 * v, rtol=1e-10)
    s = res.sample([t1 + 1e-9])
    assert abs(s["omega"][0, 0]) < 1e-10 and abs(s["vy"][0, 0] - 0.5 * v) < 1e-8
    # it keeps landing flat and comes to rest at the accumulation point, lying flat
    # (a round-off tangential speed may slide it for a few nanoseconds first)
    sw = ev[ev["kind"] != "impact"]
    assert sw["kind"][0] == "contact" and sw["mode"][-1] == 3
    assert set(sw["kind"][1:]) <= {"rest"}
    assert np.all(np.abs(sw["t"] - t1 * (1 + 0.5) / (1 - 0.5)) < 1e-6)
    assert abs(sw["v_i"][0, 1]) < 1e-9
    s = res.sample([2.0, 3.0])
    np.testing.assert_allclose(s["y"][:, 0], 0.0, atol=1e-12)
    np.testing.assert_allclose(s["angle"][:, 0], 0.0, atol=1e-9)


def test_flat_rod_sequential_stated_outcome():
    e, L, m = 0.5, 1.0, 1.0
    sim, h = flat_rod("sequential", e=e, L=L)
    res = sim.run(0.35)
    assert res.policy == "sequential"
    t1 = math.sqrt(2 * h / 9.81)
    v = math.sqrt(2 * 9.81 * h)
    # the stated rule, replayed by hand: resolve the most approaching end (ties: end 0,
    # the first vertex at x = -L/2) alone with Newton restitution, until none approaches
    inertia = m * L * L / 12
    xs = np.array([-0.5 * L, 0.5 * L])
    vy, w = -v, 0.0
    expected = []
    while True:
        vn = vy + w * xs
        k = int(np.argmin(vn))
        if vn[k] >= 0:
            break
        P = -(1 + e) * vn[k] / (1 / m + xs[k] ** 2 / inertia)
        vy += P / m
        w += xs[k] * P / inertia
        expected.append((k, P))
    ev = res.events[np.isclose(res.events["t"], t1, rtol=1e-12)]
    assert len(ev) == len(expected) == 3
    assert np.all(ev["cluster"] == 2)
    got = [(0 if p[0] < 0 else 1, P[0]) for p, P in zip(ev["point"], ev["P"])]
    for (k, P), (kk, PP) in zip(expected, got):
        assert k == kk and abs(P - PP) < 1e-12
    s = res.sample([t1])
    assert abs(s["omega"][0, 0] - w) < 1e-12 and abs(s["vy"][0, 0] - vy) < 1e-12
    assert abs(w) > 0.1                                       # not symmetric: it spins
    assert np.sum(ev["dE"]) < 0


# ---------------------------------------------------------------- disks

def test_disk_disk_head_on_elastic_swaps_velocities():
    scene = Scene2D(gravity=(0.0, 0.0))
    scene.add_body(Disk(0.1), 2.0, (0.0, 0.0), velocity=(1.0, 0.0))
    scene.add_body(Disk(0.1), 2.0, (1.0, 0.0))
    res = Simulation(scene, Law("routh", e=1.0, mu=0.0)).run(2.0)
    ev = res.events
    assert len(ev) == 1 and ev["kind"][0] == "impact"
    assert abs(ev["t"][0] - 0.8) < 1e-14
    assert ev["a"][0] == 0 and ev["b"][0] == 1
    np.testing.assert_allclose(ev["normal"][0], (-1.0, 0.0))
    s = res.sample([1.0, 2.0])
    np.testing.assert_allclose(s["vx"], [[0.0, 1.0], [0.0, 1.0]], atol=1e-14)
    np.testing.assert_allclose(s["x"], [[0.8, 1.2], [0.8, 2.2]], atol=1e-14)


def test_disk_disks_under_gravity_collide_exactly():
    # equal gravity cancels in the relative motion: the contact time is a closed form
    scene = Scene2D(gravity=(0.0, -9.81))
    scene.add_body(Disk(0.1), 1.0, (0.0, 5.0), velocity=(2.0, 1.0))
    scene.add_body(Disk(0.15), 3.0, (1.0, 5.0), velocity=(-0.5, 1.0))
    res = Simulation(scene, Law("kane_levinson", e=0.9, mu=0.2)).run(0.5)
    ev = res.events
    assert len(ev) == 1
    assert abs(ev["t"][0] - 0.75 / 2.5) < 1e-14
    assert abs(ev["v_f"][0, 0] + 0.9 * ev["v_i"][0, 0]) < 1e-12


def test_spinning_disk_slides_then_rolls_exactly():
    g, r, m, mu, w0 = 9.81, 0.2, 2.0, 0.3, 12.0
    scene = Scene2D(gravity=(0.0, -g))
    scene.add_floor()
    scene.add_body(Disk(r), m, (0.0, r), angular_velocity=w0)
    res = Simulation(scene, Law("smith", e=0.5, mu=mu)).run(2.0)
    ev = res.events
    assert list(ev["kind"]) == ["contact", "roll"]
    assert ev["t"][0] == 0.0 and ev["mode"][0] == 1                  # slides from the start
    # solid disk (I = m r^2 / 2): slip speed w0 r decays at mu g (1 + m r^2 / I) = 3 mu g
    t_roll = w0 * r / (3 * mu * g)
    assert abs(ev["t"][1] - t_roll) < 1e-13
    s = res.sample(np.array([0.5 * t_roll, t_roll, 1.5, 2.0]))
    np.testing.assert_allclose(s["vx"][0, 0], -mu * g * 0.5 * t_roll, rtol=1e-12)
    np.testing.assert_allclose(s["omega"][0, 0], w0 - 2 * mu * g * 0.5 * t_roll / r,
                               rtol=1e-12)
    np.testing.assert_allclose(s["vx"][1:, 0], -w0 * r / 3, rtol=1e-12)
    np.testing.assert_allclose(s["omega"][1:, 0], w0 / 3, rtol=1e-12)
    np.testing.assert_allclose(s["vx"][:, 0] + s["omega"][:, 0] * r,
                               [w0 * r / 2, 0, 0, 0], atol=1e-12)        # v = -omega r
    np.testing.assert_allclose(s["y"][:, 0], r, atol=1e-15)


def test_box_slides_to_rest_on_floor():
    g, mu, v0 = 9.81, 0.4, 2.0
    scene = Scene2D(gravity=(0.0, -g))
    scene.add_floor(1.0)
    scene.add_body(Box(0.4, 0.2), 1.0, (0.0, 1.1), velocity=(v0, 0.0))
    res = Simulation(scene, Law("routh", e=0.3, mu=mu)).run(2.0)
    ev = res.events
    assert list(ev["kind"]) == ["contact", "rest"]
    t_stop = v0 / (mu * g)
    assert abs(ev["t"][1] - t_stop) < 1e-13
    s = res.sample([t_stop, 2.0])
    np.testing.assert_allclose(s["x"][:, 0], v0 * v0 / (2 * mu * g), rtol=1e-12)
    np.testing.assert_allclose(s["vx"][:, 0], 0.0, atol=1e-15)


# ---------------------------------------------------------------- invariance

def invariance_scene(mirror=False, shift=(0.0, 0.0)):
    sx = -1.0 if mirror else 1.0
    dx, dy = shift
    scene = Scene2D(gravity=(0.0, -9.81))
    scene.add_plane((0.0 + dx, 0.0 + dy), (0.0, 1.0))
    scene.add_plane((sx * -1.0 + dx, dy), (sx * 1.0, 0.0))
    scene.add_plane((sx * 1.5 + dx, dy), (sx * -1.0, 0.3))
    scene.add_body(Disk(0.1), 1.0, (sx * 0.2 + dx, 0.5 + dy), velocity=(sx * 3.0, 1.0),
                   angular_velocity=sx * 5.0)
    scene.add_body(Rod(0.6), 0.5, (sx * -0.3 + dx, 1.2 + dy), angle=sx * 0.4,
                   velocity=(sx * -1.0, 0.0), angular_velocity=sx * -2.0)
    triangle = Polygon([(0, 0), (sx * 0.3, 0), (sx * 0.1, 0.2)])      # mirrored shape too
    scene.add_body(triangle, 0.7, (sx * 0.6 + dx, 0.9 + dy),
                   angle=sx * 0.3, angular_velocity=sx * 1.0)
    # Routh: a unique answer for every contact (Kane & Levinson's slide branch can have two
    # valid slip directions when W_NT != 0, and its choice need not be mirror-symmetric)
    return Simulation(scene, Law("routh", e=0.6, mu=0.4), ignore_unsupported_pairs=True)


def test_translation_and_mirror_give_the_same_events():
    ref = invariance_scene().run(0.8).events
    assert len(ref) > 10 and len(set(ref["a"])) == 3
    shift = (3.7, -2.1)
    moved = invariance_scene(shift=shift).run(0.8).events
    mirr = invariance_scene(mirror=True).run(0.8).events
    for other in (moved, mirr):
        assert len(other) == len(ref)
        assert list(other["kind"]) == list(ref["kind"])
        np.testing.assert_array_equal(other["a"], ref["a"])
        np.testing.assert_array_equal(other["b"], ref["b"])
        np.testing.assert_array_equal(other["mode"], ref["mode"])
        np.testing.assert_allclose(other["t"], ref["t"], rtol=1e-9, atol=0)
    np.testing.assert_allclose(moved["point"], ref["point"] + shift, atol=1e-8)
    np.testing.assert_allclose(moved["normal"], ref["normal"], atol=1e-12)
    np.testing.assert_allclose(moved["v_i"], ref["v_i"], atol=1e-8)
    np.testing.assert_allclose(moved["P"], ref["P"], atol=1e-8)
    flip = np.array([-1.0, 1.0])
    np.testing.assert_allclose(mirr["point"], ref["point"] * flip, atol=1e-9)
    np.testing.assert_allclose(mirr["normal"], ref["normal"] * flip, atol=1e-12)
    tflip = np.array([1.0, -1.0])          # the tangent t = (n_y, -n_x) changes sign
    np.testing.assert_allclose(mirr["v_i"], ref["v_i"] * tflip, atol=1e-9)
    np.testing.assert_allclose(mirr["v_f"], ref["v_f"] * tflip, atol=1e-9)
    np.testing.assert_allclose(mirr["P"], ref["P"] * tflip, atol=1e-9)


# ---------------------------------------------------------------- errors

def test_bad_scenes_raise_clear_errors():
    law = Law("kane_levinson", e=0.5, mu=0.3)
    scene = Scene2D()
    with pytest.raises(ValueError, match="mass"):
        scene.add_body(Disk(0.1), -1.0, (0.0, 1.0))
    with pytest.raises(ValueError, match="radius"):
        Disk(-0.1)
    with pytest.raises(ValueError, match="convex"):
        Polygon([(0, 0), (2, 0), (1, 0.3), (2, 2), (0, 2)])
    with pytest.raises(ValueError, match="finite"):
        scene.add_body(Disk(0.1), 1.0, (float("nan"), 1.0))
    with pytest.raises(ValueError, match="finite"):
        scene.add_body(Disk(0.1), 1.0, (0.0, 1.0), velocity=(0.0, float("inf")))
    scene.add_floor()
    scene.add_body(Box(1.0, 1.0), 1.0, (0.0, 0.4))
    with pytest.raises(ValueError, match="starts inside plane 0"):
        Simulation(scene, law)
    scene = Scene2D()
    scene.add_body(Box(1.0, 1.0), 1.0, (0.0, 0.4))
    scene.add_body(Disk(0.1), 1.0, (0.55, 0.4))
    # every pair of shapes collides (issue 16): overlapping bodies are rejected
    with pytest.raises(ValueError, match=r"bodies 0 \(Box\) and 1 \(Disk\) overlap"):
        Simulation(scene, law)
    scene = Scene2D()
    scene.add_body(Box(1.0, 1.0), 1.0, (0.0, 0.4))
    scene.add_body(Disk(0.1), 1.0, (3.0, 0.4))
    Simulation(scene, law)
    Simulation(scene, law, ignore_unsupported_pairs=True)
    with pytest.raises(TypeError, match="unknown keyword"):
        Simulation(scene, law, ignore_unsupported_pairs=True, rest_lenght=1e-9)
    with pytest.raises(ValueError, match="policy"):
        Simulation(scene, law, ignore_unsupported_pairs=True, policy="magic")


def test_plastic_rod_end_pivots_lands_and_rests():
    """A plastic impact (e = 0) on one end of a tilted rod: the impacts accumulate at that
    end, which is then held on the floor (event "pivot", sticking at mu = 1) while the rod
    falls about it, until the other end lands; the rod ends at rest on the floor, and the
    energy never increases (it used to end with the single-point chatter error)."""
    scene = Scene2D(gravity=(0.0, -9.81))
    scene.add_floor()
    scene.add_body(Rod(1.0), 1.0, (0.0, 0.5), angle=0.5)
    res = Simulation(scene, Law("kane_levinson", e=0.0, mu=1.0)).run(1.0)
    ev = res.events
    kinds = list(ev["kind"])
    assert kinds[0] == "impact" and "pivot" in kinds and kinds[-1] == "contact"
    piv = ev[ev["kind"] == "pivot"][0]
    assert piv["mode"] == 2 and piv["dE"] <= 0.0                 # sticking, nothing gained
    s = res.sample([1.0])
    assert abs(s["angle"][0, 0] % math.pi) < 1e-9 or abs(s["angle"][0, 0] % math.pi
                                                         - math.pi) < 1e-9
    assert abs(s["y"][0, 0]) < 1e-12 and s["omega"][0, 0] == 0.0
    t = np.linspace(0.0, 1.0, 20001)
    E = res.energy(t)
    assert float(np.max(E - np.minimum.accumulate(E))) <= PIECE_E * float(np.max(np.abs(E)))
    assert float(np.max(ev["dE"])) <= 0.0


# ---------------------------------------------------------------- integrated pivot contact
#
# Reference: the same contact dynamics solved independently, as Newton-Euler with the
# contact acceleration constraint (unknowns a, alpha, lam, f), integrated by
# scipy.integrate.solve_ivp (DOP853) at rtol 1e-12.

A_BOX, B_BOX, G_BOX = 0.1, 0.05, 9.81
I_BOX = (0.2 ** 2 + 0.1 ** 2) / 12
CORNER = np.array([-A_BOX, -B_BOX])
#: energy fidelity of the recorded pivot pieces (pivot2d.PIECE_ETOL m V^2, V <= 3 m/s here)
PIECE_E = 2e-9


def _ref_accel(y, mu, sig):
    """(ax, ay, alpha, lam, f) of the box held by CORNER on the floor y = 0 (n = (0, 1),
    t = (1, 0)): sig 0 sticking, +-1 sliding along +-t with f = -mu sig lam."""
    x, yy, th, vx, vy, w = y
    c, s = math.cos(th), math.sin(th)
    r = np.array([c * CORNER[0] - s * CORNER[1], s * CORNER[0] + c * CORNER[1]])
    Jr = np.array([-r[1], r[0]])
    A = np.zeros((5, 5))
    b = np.zeros(5)
    A[0, 0], A[0, 4] = 1.0, -1.0                       # m ax = f
    A[1, 1], A[1, 3], b[1] = 1.0, -1.0, -G_BOX         # m ay = lam - m g
    A[2, 2], A[2, 3], A[2, 4] = I_BOX, -r[0], r[1]     # I alpha = r x (f, lam)
    A[3, 1], A[3, 2], b[3] = 1.0, Jr[1], w * w * r[1]  # normal contact acceleration 0
    if sig == 0:
        A[4, 0], A[4, 2], b[4] = 1.0, Jr[0], w * w * r[0]   # tangential too
    else:
        A[4, 4], A[4, 3] = 1.0, mu * sig
    return np.linalg.solve(A, b)


def _ref_run(y0, mu, sig, t1, events=()):
    from scipy.integrate import solve_ivp

    def rhs(t, y):
        z = _ref_accel(y, mu, sig)
        return [y[3], y[4], y[5], z[0], z[1], z[2]]
    return solve_ivp(rhs, (0.0, t1), y0, method="DOP853", rtol=1e-12, atol=1e-14,
                     dense_output=True, events=list(events))


def _box_on_corner(th0, vx0=0.0, w0=0.0):
    """State (x, y, angle, vx, vy, w) of the box with CORNER on the floor, its normal
    velocity zero."""
    c, s = math.cos(th0), math.sin(th0)
    r = np.array([c * CORNER[0] - s * CORNER[1], s * CORNER[0] + c * CORNER[1]])
    return [-r[0], -r[1], th0, vx0 + w0 * r[1], -w0 * r[0], w0]


def _box_sim(y0, mu, e=0.5):
    scene = Scene2D(gravity=(0.0, -G_BOX))
    scene.add_floor()
    scene.add_body(Box(0.2, 0.1), 1.0, (y0[0], y0[1]), angle=y0[2], velocity=(y0[3], y0[4]),
                   angular_velocity=y0[5])
    return Simulation(scene, Law("routh", e=e, mu=mu))


def _other_corner_lands(t, y, *args):
    th = y[2]
    c, s = math.cos(th), math.sin(th)
    return min(y[1] + s * qx + c * qy for qx, qy in [(0.1, -0.05), (0.1, 0.05), (-0.1, 0.05)])


_other_corner_lands.terminal = True
_other_corner_lands.direction = -1


def _no_null_impacts(ev):
    """The events without the round-off impact of a corner released on the floor while
    turning (the flight search finds it touching at t ~ 1e-15 s with v_N ~ 1e-14 m/s)."""
    return ev[~((ev["kind"] == "impact") & (np.abs(ev["v_i"][:, 0]) < 1e-12))]


def _corner_xy(s, th=None):
    th = s["angle"][:, 0] if th is None else th
    c, sn = np.cos(th), np.sin(th)
    return (s["x"][:, 0] + c * CORNER[0] - sn * CORNER[1],
            s["y"][:, 0] + sn * CORNER[0] + c * CORNER[1])


def test_pivot_frictionless_slides_conserving_energy_and_momentum():
    """mu = 0: the corner slides on the floor; the normal force does no work, so the
    energy is conserved, and no horizontal force acts, so the centre of mass moves only
    vertically; the angle follows the reference integration."""
    y0 = _box_on_corner(0.3)
    ref = _ref_run(y0, 0.0, 1, 0.2, [_other_corner_lands])
    t_land = float(ref.t_events[0][0])
    res = _box_sim(y0, mu=0.0).run(t_land - 1e-3)
    ev = _no_null_impacts(res.events)
    assert list(ev["kind"]) == ["pivot"] and ev["mode"][0] == 1       # sliding
    t = np.linspace(0.0, res.t_end, 4001)
    s = res.sample(t)
    np.testing.assert_allclose(s["x"][:, 0], y0[0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(s["vx"][:, 0], 0.0, rtol=0, atol=1e-10)
    np.testing.assert_allclose(s["angle"][:, 0], ref.sol(t)[2], rtol=0, atol=1e-9)
    # recorded velocities are interpolated within PIECE_VTOL V (V ~ 3 m/s, L ~ 0.11 m)
    np.testing.assert_allclose(s["omega"][:, 0], ref.sol(t)[5], rtol=0, atol=1e-7)
    cx, cy = _corner_xy(s)
    assert float(np.min(cy)) >= -1e-11 and float(np.max(cy)) <= 1e-11
    E = res.energy(t)
    E0 = float(E[0])
    assert float(np.max(np.abs(E - E0))) <= PIECE_E * abs(E0)
    # the integrated states (the start of every recorded piece): conserved to round-off
    seg_t, seg_s, start = res._segments()
    rows = seg_s[start[0]:start[1]]
    Erow = 0.5 * (rows[:, 3] ** 2 + rows[:, 4] ** 2) + 0.5 * I_BOX * rows[:, 5] ** 2 \
        + G_BOX * rows[:, 1]
    assert float(np.max(np.abs(Erow - E0))) <= 1e-11 * abs(E0)


def test_pivot_sticking_is_the_rigid_pendulum():
    """mu = 1 (the fall needs |f| / lam <= 0.62): the corner sticks and the box is a rigid
    pendulum about it until its other bottom corner lands: angle and angular velocity
    match the reference, the corner does not move, energy is conserved; the landing is an
    impact of that corner with the held corner in its cluster."""
    y0 = _box_on_corner(0.3)
    ref = _ref_run(y0, 1.0, 0, 0.2, [_other_corner_lands])
    t_land = float(ref.t_events[0][0])
    assert abs(t_land - 0.10997494) < 1e-7
    # closed form check of the reference: I_O w^2 / 2 = m g (drop of the centre of mass)
    yl = ref.y_events[0][0]
    I_O = I_BOX + CORNER @ CORNER
    assert math.isclose(0.5 * I_O * yl[5] ** 2, G_BOX * (y0[1] - yl[1]), rel_tol=1e-10)
    res = _box_sim(y0, mu=1.0).run(t_land + 1e-3)
    ev = _no_null_impacts(res.events)
    assert list(ev["kind"][:3]) == ["pivot", "impact", "impact"] or \
        list(ev["kind"][:2]) == ["pivot", "impact"]
    assert ev["mode"][0] == 2                                           # sticking
    imp = ev[ev["kind"] == "impact"]
    assert abs(imp["t"][0] - t_land) < 1e-10 and imp["cluster"][0] == 2
    t = np.linspace(0.0, t_land, 4001)[:-1]
    s = res.sample(t)
    np.testing.assert_allclose(s["angle"][:, 0], ref.sol(t)[2], rtol=0, atol=1e-9)
    # recorded velocities are interpolated within PIECE_VTOL V (V ~ 3 m/s, L ~ 0.11 m)
    np.testing.assert_allclose(s["omega"][:, 0], ref.sol(t)[5], rtol=0, atol=1e-7)
    cx, cy = _corner_xy(s)
    np.testing.assert_allclose(cx, cx[0], rtol=0, atol=1e-11)
    assert float(np.max(np.abs(cy))) <= 1e-11
    E = res.energy(t)
    assert float(np.max(np.abs(E - E[0]))) <= PIECE_E * abs(E[0])


def test_pivot_slip_stops_then_sticks():
    """The held corner starts sliding at 0.1 m/s (mu = 1): Coulomb friction stops it
    ("stick" event at the reference time), then the box falls as a pendulum; the energy
    never increases."""
    y0 = _box_on_corner(0.3, vx0=0.1)

    def slip(t, y, *args):
        return y[3] - y[5] * (math.sin(y[2]) * CORNER[0] + math.cos(y[2]) * CORNER[1])
    slip.terminal = True
    slip.direction = -1
    ref1 = _ref_run(y0, 1.0, 1, 0.2, [slip])
    t_stick = float(ref1.t_events[0][0])
    ref2 = _ref_run(list(ref1.y_events[0][0]), 1.0, 0, 0.2, [_other_corner_lands])
    t_land = t_stick + float(ref2.t_events[0][0])
    res = _box_sim(y0, mu=1.0).run(t_land - 1e-3)
    ev = _no_null_impacts(res.events)
    assert list(ev["kind"]) == ["pivot", "stick"]
    assert ev["mode"][0] == 1 and ev["mode"][1] == 2
    assert abs(ev["t"][1] - t_stick) < 1e-10
    assert abs(ev["v_i"][1, 1]) < 1e-9 and ev["v_f"][1, 1] == pytest.approx(0.0, abs=1e-15)
    assert ev["dE"][1] <= 0.0
    t = np.linspace(0.0, res.t_end, 4001)
    s = res.sample(t)
    th_ref = np.where(t < t_stick, ref1.sol(np.minimum(t, t_stick))[2],
                      ref2.sol(np.maximum(t - t_stick, 0.0))[2])
    np.testing.assert_allclose(s["angle"][:, 0], th_ref, rtol=0, atol=1e-8)
    E = res.energy(t)
    assert float(np.max(E - np.minimum.accumulate(E))) <= PIECE_E * abs(E[0])
    assert E[-1] < E[0]                                 # friction dissipated the slip


def test_pivot_lifts_off_when_the_normal_force_vanishes():
    """A box spun up over its corner (mu = 0, w0 = 10 rad/s): the normal force
    m I (w^2 eta + g) / (I + m xi^2) falls to zero at the reference time and the box
    leaves the floor ("release"), then flies freely (exact ballistic motion)."""
    y0 = _box_on_corner(0.3, w0=10.0)

    def lam(t, y, *args):
        return _ref_accel(y, 0.0, 1)[3]
    lam.terminal = True
    lam.direction = -1
    ref = _ref_run(y0, 0.0, 1, 0.2, [lam])
    t_lift = float(ref.t_events[0][0])
    assert abs(t_lift - 0.0474837) < 1e-6
    res = _box_sim(y0, mu=0.0).run(t_lift + 0.02)
    ev = _no_null_impacts(res.events)
    assert list(ev["kind"][:2]) == ["pivot", "release"]
    assert abs(ev["t"][1] - t_lift) < 1e-10
    ts = np.linspace(t_lift, res.t_end, 101)
    s = res.sample(ts)
    # flight: horizontal velocity constant, vertical velocity loses g per second, w const
    np.testing.assert_allclose(s["vy"][:, 0] - s["vy"][0, 0], -G_BOX * (ts - ts[0]),
                               atol=1e-12)
    np.testing.assert_allclose(s["omega"][:, 0], s["omega"][0, 0], atol=0)
    np.testing.assert_allclose(s["angle"][0, 0], ref.y_events[0][0][2], atol=1e-9)
    cx, cy = _corner_xy(s)
    assert float(np.min(cy[1:])) > 0.0                 # the released corner goes up
    t = np.linspace(0.0, res.t_end, 4001)
    E = res.energy(t)
    assert float(np.max(np.abs(E - E[0]))) <= PIECE_E * abs(E[0])


def test_pivot_events_record_no_energy_gain_on_a_flat_landing():
    """Sequential flat landing (routh e = 0.5, mu = 0.3, the stability scene): the box
    pivots on a corner (events "pivot"), rocks and comes to rest flat; every event's dE
    is <= 0."""
    scene = Scene2D(gravity=(0.0, -9.81))
    scene.add_floor(0.0)
    scene.add_body(Box(0.2, 0.1), 1.0, (0.0, 0.55))
    res = Simulation(scene, Law("routh", e=0.5, mu=0.3), policy="sequential").run(2.0)
    ev = res.events
    assert np.count_nonzero(ev["kind"] == "pivot") >= 1
    assert "contact" in list(ev["kind"]) and np.all(ev["dE"] <= 0.0)
    s = res.sample([2.0])
    assert s["omega"][0, 0] == 0.0 and abs(s["y"][0, 0] - 0.05) < 1e-12


def test_pair_laws_and_perforation():
    scene = Scene2D(gravity=(0.0, 0.0))
    barrier = scene.add_plane((1.0, 0.0), (-1.0, 0.0))
    scene.add_plane((3.0, 0.0), (-1.0, 0.0))
    scene.add_body(Disk(0.1), 1.0, (0.0, 0.0), velocity=(4.0, 0.0))
    sim = Simulation(scene, Law("kane_levinson", e=1.0, mu=0.0),
                     pair_laws={(0, barrier): Law("brach", e=-0.5, mu=0.0)})
    res = sim.run(2.0)
    ev = res.events
    assert list(ev["b"]) == [-1, -2]
    assert abs(ev["t"][0] - 0.9 / 4.0) < 1e-14
    np.testing.assert_allclose(ev["v_f"][0], (-2.0, 0.0), atol=1e-14)   # through, slower
    assert abs(ev["t"][1] - (0.9 / 4.0 + 2.0 / 2.0)) < 1e-14            # wall: elastic
    assert res.sample([2.0])["vx"][0, 0] == pytest.approx(-2.0)


def test_no_solution_is_raised_with_body_time_and_point():
    from rbimpact.errors import NoSolutionError

    class Jammed:                   # a law object whose kernel id has no law: mode -1
        name = "jammed"
        law_id = 99
        params = np.zeros(5)

    scene = Scene2D(gravity=(0.0, -9.81))
    scene.add_floor()
    scene.add_body(Disk(0.1), 1.0, (0.3, 0.6))
    where = r"body 0 \(Disk\) on plane 0.*t = 0\.319275428.*point \(0\.3, "
    with pytest.raises(NoSolutionError, match=where) as info:
        Simulation(scene, Jammed()).run(1.0)
    assert info.value.mode_code == -1 and info.value.result.n_impacts == 0


def test_exports_and_plot(tmp_path):
    import csv
    import json
    import sys
    res = drop_ball(e=0.5).run(1.5)
    res.to_csv(tmp_path / "ev.csv")
    rows = list(csv.DictReader(open(tmp_path / "ev.csv")))
    assert len(rows) == len(res.events) and rows[0]["kind"] == "impact"
    assert float(rows[0]["t"]) == res.events["t"][0]
    res.to_json(tmp_path / "ev.json")
    doc = json.load(open(tmp_path / "ev.json"))
    assert doc["status"] == "done" and doc["policy"] == "simultaneous"
    assert doc["events"][-1]["kind"] == "contact"
    assert doc["tolerances"]["rest_length"] == 1e-10
    if "matplotlib" not in sys.modules:
        pytest.importorskip("matplotlib")
    res.plot(tmp_path / "fig.png")
    assert (tmp_path / "fig.png").stat().st_size > 1000


# ---------------------------------------------------------------- near-elastic bounces

@pytest.mark.parametrize("law", ["kane_levinson", "routh", "chatterjee_ruina"])
def test_near_elastic_bounces_stop_with_a_clear_error(law):
    """e = 1 - 1e-6 (issue 13 item 5): the bounces would accumulate only after about
    ln(v / zeno_speed) / (1 - e) ~ 1.1e7 impacts; the run stops at the first impact with an
    error naming e and the count (it stepped 1.2e7 impacts before), whatever the friction
    (a disk's bounces are geometric: its normal impulse has no moment)."""
    from rbimpact.errors import SimulationError
    e = 1.0 - 1e-6
    sim = drop_ball(e=e, mu=0.3, vx=0.5, law=law)
    with pytest.raises(SimulationError, match=r"e = 0\.999999.*about 1\.1\de\+07 more impacts"
                       r".*max_accumulation_impacts = 1000000") as info:
        sim.run(1e9)
    res = info.value.result
    assert res.status == "far_accumulation"
    assert len(res.events) == 1 and res.events["kind"][0] == "impact"
    # a run that ends before the accumulation steps its bounces (h = 1 m: one per 0.9 s)
    res = sim.run(10.0)
    assert res.status == "done" and 10 <= len(res.events) <= 12
    # the limit is a tolerance: raised, the same scene steps on (not run here: 1e7 impacts)
    assert Simulation(sim.scene, sim.law,
                      max_accumulation_impacts=10**8).tolerances[
                          "max_accumulation_impacts"] == 10**8


def test_far_accumulation_count_is_exact_for_a_geometric_series():
    """impacts_before_rest against a direct count of the geometric bounces: the energy
    threshold branch and the t_end branch."""
    from rbimpact.kernels.decisions import impacts_before_rest
    g, m, v0, e = 9.80665, 1.0, 4.0, 0.99
    thr = 0.5 * m * 1e-4 ** 2
    n_thr = impacts_before_rest(e * v0, -v0, -g, 0.0, 1e30, 0.5 * m * (e * v0) ** 2, thr)
    v, k = e * v0, 0
    while 0.5 * m * v * v >= thr:
        v *= e
        k += 1
    assert abs(n_thr - k) < 1.0
    t_end = 5.0
    n_end = impacts_before_rest(e * v0, -v0, -g, 0.0, t_end, 0.5 * m * (e * v0) ** 2, thr)
    t, v, k = 0.0, e * v0, 0
    while t + 2 * v / g <= t_end:
        t += 2 * v / g
        v *= e
        k += 1
    assert abs(n_end - k) < 1.0
    assert impacts_before_rest(v0, -v0, -g, 0.0, t_end, 1.0, thr) == 0.0     # elastic


@pytest.mark.parametrize("v, r, t_end", [(1e-9, 0.05, 2.0), (1e4, 0.05, 2.0), (1.0, 1e-4, 2.0),
                                         (1.0, 1e3, 50.0), (0.0, 0.05, 1e4)])
def test_scale_free_elastic_bounces(v, r, t_end):
    """Issue 13 item 3: speeds 1e-9 to 1e4 m/s, sizes 1e-4 to 1e3 m, run times to 1e4 s
    (1.1e4 impacts): no false missed event, every impact at its closed-form time (the
    flight between two impacts of an elastic ball is 2 v_impact / g) and the energy kept
    to round-off (a random walk of about 1e-16 per impact)."""
    h = 1.0
    scene = Scene2D(gravity=(0.0, -G0))
    scene.add_floor(0.0)
    scene.add_body(Disk(r), 1.0, (0.0, h + r), velocity=(0.0, -v))
    res = Simulation(scene, Law("kane_levinson", e=1.0, mu=0.0)).run(t_end)
    assert res.status == "done" and res.t_end == t_end
    imp = res.events[res.events["kind"] == "impact"]
    vimp = math.sqrt(v * v + 2 * G0 * h)
    t1 = 2 * h / (vimp + v)
    k = np.arange(len(imp))
    np.testing.assert_allclose(imp["t"], t1 + k * 2 * vimp / G0, rtol=1e-10)
    # the impact speed drifts by round-off only (3.6e-16 of the energy per impact)
    np.testing.assert_allclose(imp["v_i"][:, 0], -vimp, rtol=1e-15 * max(len(imp), 10))
    assert len(imp) == int((t_end - t1) / (2 * vimp / G0)) + 1
