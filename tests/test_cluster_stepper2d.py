"""Persistent contact between 2D bodies in the stepper (issue 16 item 2, first wiring):
``stepper2d`` enters ``PM_CLUSTER`` (``kernels/cluster2d.py``) when the impacts of two disks
accumulate, integrates the cluster (its disks, their planes), dissolves it when no body-body
contact is left, and freezes it at rest.

Real physics that can fail: the lift-off angle of a disk rolling off a disk against an
independent scipy integration of the two-disk system (and the closed form cos = 2/3 cos
theta0 for a fixed lower disk), energy conserved while in frictionless contact and never
created, no overlap at densely sampled times (gaps from ``pair2d.frame_rel``), rest
detected and held, and the campaign's touching-layout scenes that used to stop with the
refusal of persistent body-body contact.
"""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from rbimpact import Disk, Law, Scene2D, Simulation
from rbimpact.errors import SimulationError
from rbimpact.kernels.pair2d import frame_rel

G = 9.81


def disk_on_disk(M, m=1.0, R=0.1, r=0.1, theta0=1e-3, mu=0.0, e=0.0):
    """A disk (radius r, mass m) at angle theta0 from the top of a disk (R, M) resting on
    the floor, both at rest, touching."""
    sc = Scene2D(gravity=(0.0, -G))
    sc.add_floor()
    sc.add_body(Disk(R), M, (0.0, R))
    rho = R + r
    sc.add_body(Disk(r), m, (rho * math.sin(theta0), R + rho * math.cos(theta0)))
    return Simulation(sc, Law("kane_levinson", e=e, mu=mu))


def energy(sim, s, skip_potential=()):
    """Kinetic plus potential energy (heights from the first sample), without the potential
    of the bodies in ``skip_potential`` (a very heavy body on the floor: its round-off
    height times M g would swamp the scale of the light one; checked separately)."""
    E = 0.0
    for i, b in enumerate(sim.scene.bodies):
        E = E + 0.5 * b.mass * (s["vx"][:, i] ** 2 + s["vy"][:, i] ** 2) \
            + 0.5 * sim._moments[i] * s["omega"][:, i] ** 2
        if i not in skip_potential:
            E = E + b.mass * G * (s["y"][:, i] - s["y"][0, i])
    return E


def pair_gap(sim, s, k, i=0, j=1):
    V = sim._verts
    bint, bflt = sim._bint, sim._bflt
    return frame_rel(int(bint[i, 0]), bflt[i, 2], bflt[i, 3], bflt[i, 4], V, int(bint[i, 1]),
                     int(bint[i, 2]), s["angle"][k, i], int(bint[j, 0]), bflt[j, 2],
                     bflt[j, 3], bflt[j, 4], V, int(bint[j, 1]), int(bint[j, 2]),
                     s["x"][k, j] - s["x"][k, i], s["y"][k, j] - s["y"][k, i],
                     s["angle"][k, j])[0]


def reference_release(M, m, R, r, theta0):
    """Frictionless: the lower disk slides on the floor (x), the upper one keeps touching it
    at angle theta from the vertical until the contact force N = m (x'' sin - rho th'^2 +
    g cos) vanishes (Lagrange; independent of the stepper and of cluster2d)."""
    rho = R + r

    def acc(th, w):
        s, c = math.sin(th), math.cos(th)
        # unknowns x'', th'': (M + m) x'' + m rho (c th'' - s w^2) = 0;
        # m (x'' c + rho th'') = m g s  (tangential equation of the upper disk)
        A = np.array([[M + m, m * rho * c], [c, rho]])
        b = np.array([m * rho * s * w * w, G * s])
        return np.linalg.solve(A, b)

    def f(t, y):
        xdd, thdd = acc(y[1], y[3])
        return [y[2], y[3], xdd, thdd]

    def N(t, y):
        xdd, thdd = acc(y[1], y[3])
        return xdd * math.sin(y[1]) - rho * y[3] ** 2 + G * math.cos(y[1])
    N.terminal = True
    N.direction = -1
    sol = solve_ivp(f, (0.0, 10.0), [0.0, theta0, 0.0, 0.0], events=N, rtol=1e-12,
                    atol=1e-14, method="DOP853")
    return sol.t_events[0][0], sol.y_events[0][0][1]


def release_event(res):
    ev = res.events
    rel = ev[(ev["kind"] == "release") & (ev["b"] >= 0)]
    assert len(rel) == 1, ev
    return float(rel["t"][0])


@pytest.mark.parametrize("M", [1e6, 1.0])
def test_disk_rolls_off_a_disk_frictionless(M):
    """The upper disk slides off the lower one (frictionless), leaves it at the angle of
    the reference integration (cos = 2/3 cos theta0 for a fixed lower disk), lands: energy
    conserved to 1e-10 m g L while in contact, never created; no overlap beyond 1e-9 L."""
    R = r = 0.1
    m = 1.0
    th0 = 1e-3
    sim = disk_on_disk(M, m, R, r, th0)
    res = sim.run(1.6)
    assert res.status == "done"
    ev = res.events
    assert any((ev["kind"] == "contact") & (ev["mode"] == 6))      # PM_CLUSTER entered
    t_rel = release_event(res)
    s = res.sample([t_rel])
    th = math.atan2(s["x"][0, 1] - s["x"][0, 0], s["y"][0, 1] - s["y"][0, 0])
    t_ref, th_ref = reference_release(M, m, R, r, th0)
    assert abs(th - th_ref) <= 1e-7, (th, th_ref)
    assert abs(t_rel - t_ref) <= 1e-6 * t_ref, (t_rel, t_ref)
    if M == 1e6:
        assert abs(math.cos(th) - 2.0 / 3.0 * math.cos(th0)) <= 1e-5
    # energy while in contact (after the entry, which removes a round-off approach)
    t_in = float(ev["t"][(ev["kind"] == "contact") & (ev["mode"] == 6)][0])
    ts = np.linspace(t_in, t_rel, 4001)
    s = res.sample(ts)
    skip = (0,) if M > 1e3 else ()
    E = energy(sim, s, skip)
    # the scale: (m + M) g L for equal masses; for the heavy lower disk the light disk's
    # m g L, to 1e-9 (the recorded pieces hold energy to PIECE_ETOL M_free V^2, M_free
    # dominated by the heavy disk: 3.2e-10 m g L measured)
    scale = (m + M) * G * (R + r) if M < 1e3 else m * G * (R + r)
    etol = 1e-10 if M < 1e3 else 1e-9
    assert np.max(np.abs(s["y"][:, 0] - R)) <= 1e-15
    assert np.max(np.abs(E - E[0])) <= etol * scale, np.max(np.abs(E - E[0])) / scale
    # never created over the run; no overlap with the floor or between the disks
    ts = np.union1d(np.linspace(0.0, res.t_end, 6001), ev["t"])
    s = res.sample(ts)
    E = energy(sim, s, skip)
    E0 = E[0]
    assert np.max(E - E0) <= etol * scale
    L = 2 * R
    assert np.min(s["y"][:, 0] - R) >= -1e-9 * L
    assert np.min(s["y"][:, 1] - r) >= -1e-9 * L
    gaps = np.array([pair_gap(sim, s, k) for k in range(len(ts))])
    assert gaps.min() >= -1e-9 * L, gaps.min()
    # it left the lower disk and landed on the floor beside it
    assert s["x"][-1, 1] - s["x"][-1, 0] >= R + r - 1e-9


def test_disk_exactly_on_top_of_a_disk_rests():
    """A disk exactly on top of a disk on the floor, at rest, with friction: an equilibrium;
    the cluster detects rest and nothing moves for 10 s."""
    sim = disk_on_disk(1.0, 0.5, 0.1, 0.07, theta0=0.0, mu=0.5)
    res = sim.run(10.0)
    assert res.status == "done"
    ev = res.events
    assert any((ev["kind"] == "rest") & (ev["mode"] == 6))
    s0 = res.sample([0.0])
    s = res.sample(np.linspace(0.0, 10.0, 1001))
    for key in ("x", "y", "angle"):
        assert np.max(np.abs(s[key] - s0[key])) <= 1e-9, key
    assert np.max(np.abs(s["vx"])) == 0.0 or np.max(np.abs(s["vx"])) <= 1e-12


def test_disk_rolls_off_a_disk_with_friction():
    """Rough contacts (mu = 0.8 everywhere): the upper disk rolls on the lower one, which
    rolls away on the floor, then leaves it (or slides first); energy never created, no
    overlap; the run ends 'done'."""
    sim = disk_on_disk(2.0, 1.0, 0.1, 0.08, theta0=0.05, mu=0.8)
    res = sim.run(3.0)
    assert res.status == "done"
    ev = res.events
    assert any((ev["kind"] == "contact") & (ev["mode"] == 6))
    ts = np.union1d(np.linspace(0.0, res.t_end, 6001), ev["t"])
    s = res.sample(ts)
    E = energy(sim, s)
    scale = 3.0 * G * 0.2
    assert np.max(np.diff(E)) <= 1e-10 * scale
    gaps = np.array([pair_gap(sim, s, k) for k in range(len(ts))])
    assert gaps.min() >= -1e-9 * 0.2
    assert np.min(s["y"][:, 0] - 0.1) >= -1e-9 * 0.2
    assert np.min(s["y"][:, 1] - 0.08) >= -1e-9 * 0.2


def test_two_disks_side_by_side_rest():
    """Two disks touching side by side on the floor, at rest: nothing moves for 10 s."""
    sc = Scene2D(gravity=(0.0, -G))
    sc.add_floor()
    sc.add_body(Disk(0.1), 1.0, (0.0, 0.1))
    sc.add_body(Disk(0.1), 1.0, (0.2, 0.1))
    sim = Simulation(sc, Law("kane_levinson", e=0.3, mu=0.5))
    res = sim.run(10.0)
    assert res.status == "done"
    s = res.sample(np.linspace(0.0, 10.0, 101))
    assert np.max(np.abs(s["x"] - [0.0, 0.2])) <= 1e-12
    assert np.max(np.abs(s["y"] - 0.1)) <= 1e-12


#: campaign scenes (``rbimpact stability --scenes 300 --dim 2``, seed 0; layout "touching")
#: that stopped before this wiring with the refusal of persistent body-body contact (5 of
#: them) or the disk-on-disk ERR_CHATTER of the same accumulation (8)
TOUCHING_SEEDS = [3276648838, 360519305, 145448507, 1455818033, 1159475767, 2744056958,
                  4221115390, 1152666252, 2245518037, 183055972, 1863458657,
                  2298760360]   # (refused until session 30's struck-support rule, below)
#: ... and those that now end with another named reason: no consistent stick/slip/lift
#: mode found for the cluster (693027722 at its entry: a spinning disk, mu = 10; 1950292482
#: later in its motion since the merge with main's touching-rate rule: open, issue 16).
#: 2298760360 (two disks rolling side by side, mu = 1) was refused here as a Painleve jam
#: when one stopped slipping; since session 30 a disk held on the floor and struck by the
#: other takes its floor contact into the impact (``stepper2d._held_into_instant``) and the
#: scene ends OK (in TOUCHING_SEEDS)
TOUCHING_REFUSED = {693027722: "no consistent stick/slip/lift-off mode",
                    1950292482: "no consistent stick/slip/lift-off mode"}


@pytest.mark.parametrize("seed", TOUCHING_SEEDS)
def test_campaign_touching_scenes_pass(seed):
    from rbimpact.campaign import run_drop
    row = run_drop(2, seed)
    assert row.layout == "touching"
    assert row.verdict == "OK", row.note
    assert row.penetration <= row.pen_tol


@pytest.mark.parametrize("seed", sorted(TOUCHING_REFUSED))
def test_campaign_touching_scene_refused_by_another_name(seed):
    from rbimpact.campaign import run_drop
    row = run_drop(2, seed)
    assert row.status == "SimulationError"
    assert TOUCHING_REFUSED[seed] in row.note, row.note
    assert row.verdict == "REFUSED"
    assert row.penetration <= row.pen_tol
    assert row.energy_gain <= 1e-9


def test_disk_rolling_into_a_resting_disk_plastically():
    """A disk rolling on the floor hits a resting one plastically (e = 0, mu = 0.5): they
    ride together (a cluster entered, then dissolved when the contact force is zero), no
    overlap, energy never created, both end rolling at one speed."""
    sc = Scene2D(gravity=(0.0, -G))
    sc.add_floor()
    sc.add_body(Disk(0.1), 1.0, (0.0, 0.1), velocity=(1.0, 0.0), angular_velocity=-10.0)
    sc.add_body(Disk(0.1), 1.0, (0.5, 0.1))
    sim = Simulation(sc, Law("kane_levinson", e=0.0, mu=0.5))
    res = sim.run(3.0)
    assert res.status == "done"
    ts = np.union1d(np.linspace(0.0, 3.0, 3001), res.events["t"])
    s = res.sample(ts)
    gaps = np.array([pair_gap(sim, s, k) for k in range(len(ts))])
    assert gaps.min() >= -1e-9 * 0.2
    assert np.min(s["y"] - 0.1) >= -1e-9 * 0.2
    E = energy(sim, s)
    assert np.max(E - np.minimum.accumulate(E)) <= 1e-10 * 2.0 * G * 0.2
    assert s["vx"][-1, 0] == pytest.approx(s["vx"][-1, 1], abs=1e-9)
    assert s["vx"][-1, 0] > 0.0


def test_disk_dropped_into_the_groove_of_two_disks_rests():
    """Two disks touching on the floor, a third dropped onto both (mu = 0.5, e = 0): the
    three-body cluster (two disk-disk and two floor contacts) comes to rest as a pyramid,
    symmetric, no overlap, nothing moving afterwards."""
    sc = Scene2D(gravity=(0.0, -G))
    sc.add_floor()
    sc.add_body(Disk(0.1), 1.0, (-0.1, 0.1))
    sc.add_body(Disk(0.1), 1.0, (0.1, 0.1))
    h = 0.1 + 0.2 * math.sin(math.pi / 3)
    sc.add_body(Disk(0.1), 1.0, (0.0, h + 0.05))
    sim = Simulation(sc, Law("kane_levinson", e=0.0, mu=0.5))
    res = sim.run(2.0)
    assert res.status == "done"
    ev = res.events
    assert any((ev["kind"] == "rest") & (ev["mode"] == 6) & (ev["cluster"] == 3))
    ts = np.union1d(np.linspace(0.0, 2.0, 4001), ev["t"])
    s = res.sample(ts)
    for i, j in ((0, 1), (0, 2), (1, 2)):
        assert np.array([pair_gap(sim, s, k, i, j) for k in range(len(ts))]).min() >= -2e-10
    assert np.min(s["y"] - 0.1) >= -2e-10
    np.testing.assert_allclose(s["x"][-1], [-0.1, 0.1, 0.0], atol=1e-7)
    assert s["y"][-1, 2] == pytest.approx(h, abs=1e-9)
    late = ts > 1.0
    assert np.max(np.abs(s["vx"][late])) == 0.0 and np.max(np.abs(s["vy"][late])) == 0.0
