"""A body held on two planes at once in 2D (mode table: "two contacts"; ``kernels/pivot2d.py``,
section "Two contacts"): one degree of freedom, both contacts sliding, until a normal force
vanishes (the body pivots on the other plane), w reaches 0 (rest when that is a static
equilibrium), or another vertex lands. Checked against classical closed forms: the
frictionless ladder leaves the wall at 2/3 of its initial height, a disk spinning in a corner
or a V-groove stops after ``I w0 / |torque|`` with the friction forces of its two contacts."""
import math

import numpy as np
import pytest

from rbimpact.laws import Law
from rbimpact.scene import Scene2D
from rbimpact.shapes import Box, Disk, Rod
from rbimpact.simulation import Simulation

G = 9.81
DROP = 1e-9     # every body starts this far (m) above its planes: it lands on them at once


def _ladder(phi0, law="kane_levinson", mu=0.0, length=1.0, mass=1.0):
    """A segment rod leaning on a wall (plane x >= 0) from the floor, at phi0 (rad) to the
    floor, at rest."""
    scene = Scene2D(gravity=(0.0, -G))
    scene.add_floor(0.0)
    scene.add_plane((0.0, 0.0), (1.0, 0.0))
    c = (0.5 * length * math.cos(phi0), 0.5 * length * math.sin(phi0) + DROP)
    scene.add_body(Rod(length), mass, c, angle=math.pi - phi0)
    return Simulation(scene, Law(law, e=0.0, mu=mu))


@pytest.mark.parametrize("phi0", [0.7, 1.2, 1.45])
def test_frictionless_ladder_leaves_the_wall_at_two_thirds_of_its_height(phi0):
    """Classical result (e.g. Goldstein's ladder problem): a frictionless ladder released
    from rest at phi0 keeps both ends on the floor and the wall until sin(phi) = (2/3)
    sin(phi0), where the wall's force vanishes (event "release" on the wall). Between, the
    energy is conserved (the normal forces do no work) and both ends stay on their
    planes."""
    L = 1.0
    res = _ladder(phi0).run(1.5)
    ev = res.events
    assert res.status == "done"
    piv = ev[ev["kind"] == "pivot"]
    assert set(piv["b"]) >= {-1, -2}                   # held on the floor and the wall
    rel = ev[(ev["kind"] == "release") & (ev["b"] == -2)]
    assert len(rel) == 1
    t0 = float(piv["t"][-1])
    t1 = float(rel["t"][0])
    phi1 = math.pi - float(res.sample([t1])["angle"][0, 0])
    # the entry state carries the drop's speed ~ sqrt(2 g DROP): a 1e-9 relative shift
    assert math.sin(phi1) / math.sin(phi0) == pytest.approx(2.0 / 3.0, abs=1e-8)
    t = np.linspace(t0, t1, 2001)
    s = res.sample(t)
    th = s["angle"][:, 0]
    x, y = s["x"][:, 0], s["y"][:, 0]
    top_x = x + 0.5 * L * np.cos(th)        # the end on the wall (angle = pi - phi)
    bottom_y = y - 0.5 * L * np.sin(th)
    assert float(np.max(np.abs(top_x))) <= 1e-9 * L
    assert float(np.max(np.abs(bottom_y))) <= 1e-9 * L
    E = 0.5 * (s["vx"][:, 0] ** 2 + s["vy"][:, 0] ** 2) + L * L / 24.0 * s["omega"][:, 0] ** 2 \
        + G * y
    assert float(np.max(np.abs(E - E[0]))) <= 1e-9 * G * L


def _corner_disk(mu, w0, law="kane_levinson", R=0.1, M=2.0):
    scene = Scene2D(gravity=(0.0, -G))
    scene.add_floor(0.0)
    scene.add_plane((0.0, 0.0), (1.0, 0.0))
    scene.add_body(Disk(R), M, (R, R + DROP), angular_velocity=w0)
    return Simulation(scene, Law(law, e=0.0, mu=mu))


@pytest.mark.parametrize("law", ["kane_levinson", "routh", "brach"])
@pytest.mark.parametrize("mu", [0.1, 0.3, 1.0])
def test_disk_spinning_into_a_corner_stops_at_the_closed_form_time(law, mu):
    """A disk spinning towards the wall (counter-clockwise, wall on its left) in a corner:
    the floor's friction presses it into the wall, ``lam_w = mu lam_f``, ``lam_f + mu lam_w
    = m g``, and ``I dw/dt = -mu R (lam_f + lam_w)``: it stops after ``T = I w (1 + mu^2) /
    (mu R m g (1 + mu))`` with its centre fixed, then rests (event "rest")."""
    R, M = 0.1, 2.0
    res = _corner_disk(mu, 20.0, law, R, M).run(3.0)
    ev = res.events
    assert res.status == "done"
    piv = ev[ev["kind"] == "pivot"]
    assert set(piv["b"]) == {-1, -2}
    te = float(piv["t"][-1])
    s = res.sample([te])
    we = float(s["omega"][0, 0])
    T = (M * R * R / 2) * we * (1 + mu * mu) / (mu * R * M * G * (1 + mu))
    rest = ev[ev["kind"] == "rest"]
    assert len(rest) == 1
    assert float(rest["t"][0]) - te == pytest.approx(T, rel=1e-12)
    # the centre does not move while it spins, and the spin falls linearly
    t = np.linspace(te, te + T, 101)
    s = res.sample(t)
    assert np.all(np.abs(s["x"][:, 0] - R) <= 1e-9 * R)
    assert np.allclose(s["omega"][:, 0], we * (1 - (t - te) / T), atol=1e-9 * we)
    fin = res.sample([3.0])
    assert fin["omega"][0, 0] == 0.0 and fin["vx"][0, 0] == 0.0


def test_disk_spinning_away_from_the_wall_rolls_away():
    """Spinning the other way the floor's friction pulls the disk off the wall: no contact
    on two planes (the wall's force would be negative); it slides, then rolls away."""
    res = _corner_disk(0.3, -20.0).run(1.0)
    assert res.status == "done"
    ev = res.events
    assert not np.any((ev["kind"] == "pivot") & (ev["b"] == -2))
    assert float(res.sample([1.0])["x"][0, 0]) > 0.1 + 0.01


def _independent_groove_decel(mu, alpha, M, R):
    """dw/dt of a disk spinning counter-clockwise in a symmetric V-groove of wall angle
    alpha (rad from the horizontal), from the force balance of its two sliding contacts
    (numpy solve; independent of the stepper's formula)."""
    n1 = np.array([-math.sin(alpha), math.cos(alpha)])    # right wall (normal up-left)
    n2 = np.array([math.sin(alpha), math.cos(alpha)])     # left wall
    I = 0.5 * M * R * R
    cols = []
    for n in (n1, n2):
        t = np.array([n[1], -n[0]])
        r = -R * n
        v_point = np.array([-r[1], r[0]])                  # w z x r per unit w
        sig = math.copysign(1.0, v_point @ t)
        cols.append(n - mu * sig * t)
    lam = np.linalg.solve(np.array(cols).T, np.array([0.0, M * G]))
    assert np.all(lam > 0)
    torque = sum(-mu * l * R for l in lam)                # friction opposes the spin
    return torque / I


def _groove_disk(alpha, mu, M=1.0, R=0.05, w0=30.0):
    scene = Scene2D(gravity=(0.0, -G))
    scene.add_plane((0.0, 0.0), (-math.sin(alpha), math.cos(alpha)))
    scene.add_plane((0.0, 0.0), (math.sin(alpha), math.cos(alpha)))
    scene.add_body(Disk(R), M, (0.0, R / math.cos(alpha) + DROP), angular_velocity=w0)
    return Simulation(scene, Law("routh", e=0.0, mu=mu))


@pytest.mark.parametrize("alpha, mu", [(0.3, 0.2), (0.7, 0.4), (1.1, 0.4), (1.1, 0.1)])
def test_disk_spinning_in_a_v_groove_stops_at_the_closed_form_time(alpha, mu):
    """Both walls push (both normal forces of the sliding solution positive): the disk spins
    down on its two contacts with its centre fixed and rests when w reaches 0."""
    M, R = 1.0, 0.05
    res = _groove_disk(alpha, mu, M, R).run(2.0)
    assert res.status == "done"
    ev = res.events
    te = float(ev[ev["kind"] == "pivot"]["t"][-1])
    we = float(res.sample([te])["omega"][0, 0])
    T = we / -_independent_groove_decel(mu, alpha, M, R)
    rest = ev[ev["kind"] == "rest"]
    assert float(rest["t"][0]) - te == pytest.approx(T, rel=1e-12)


def test_disk_spinning_in_a_shallow_groove_climbs_a_wall():
    """alpha = 0.3, mu = 0.4: the two-contact solution would need a pulling right wall
    (lam_1 = -1.3 N), so the disk is not held on both: friction drives it up the left wall,
    it rolls back, rocks from wall to wall losing energy at each landing, and comes to rest.
    Energy never rises (every impact and every held motion dissipates)."""
    res = _groove_disk(0.3, 0.4).run(4.0)
    assert res.status == "done"
    ev = res.events
    first = ev[ev["t"] == ev["t"][0]]
    assert not (set(first[first["kind"] == "pivot"]["b"]) >= {-1, -2})
    assert np.all(ev["dE"] <= 1e-12)
    assert np.sum(ev["kind"] == "impact") >= 4
    fin = res.sample([4.0])
    assert abs(fin["omega"][0, 0]) <= 1e-9 and abs(fin["x"][0, 0]) <= 1e-9


def test_box_sliding_in_a_frictionless_groove_conserves_energy_and_keeps_both_corners_on():
    """A box in a frictionless V-groove, released with two corners on the two planes: it
    slides back and forth on both (w turns, event "slide" at each turn) conserving energy;
    no corner goes into a plane."""
    alpha, W, H, M = 0.6, 0.3, 0.1, 1.5
    scene = Scene2D(gravity=(0.0, -G))
    scene.add_plane((0.0, 0.0), (-math.sin(alpha), math.cos(alpha)))
    scene.add_plane((0.0, 0.0), (math.sin(alpha), math.cos(alpha)))
    # tilted by 0.2 rad: the lower corners touch the two walls (found numerically)
    th = 0.2
    c, s = math.cos(th), math.sin(th)
    p1 = np.array([W / 2 * c + H / 2 * s, W / 2 * s - H / 2 * c])      # corner (+W/2, -H/2)
    p2 = np.array([-W / 2 * c + H / 2 * s, -W / 2 * s - H / 2 * c])    # corner (-W/2, -H/2)
    n1 = np.array([-math.sin(alpha), math.cos(alpha)])
    n2 = np.array([math.sin(alpha), math.cos(alpha)])
    x = np.linalg.solve(np.array([n1, n2]), np.array([-n1 @ p1, -n2 @ p2]) + DROP)
    scene.add_body(Box(W, H), M, tuple(x), angle=th)
    res = Simulation(scene, Law("kane_levinson", e=0.0, mu=0.0)).run(1.0)
    assert res.status == "done"
    ev = res.events
    piv = ev[ev["kind"] == "pivot"]
    assert set(piv["b"]) == {-1, -2}
    t0 = float(piv["t"][-1])
    t = np.linspace(t0, 1.0, 4001)[1:]       # after the entry (its impulses remove ~1e-8 J)
    smp = res.sample(t)
    I = M * (W * W + H * H) / 12.0
    E = 0.5 * M * (smp["vx"][:, 0] ** 2 + smp["vy"][:, 0] ** 2) \
        + 0.5 * I * smp["omega"][:, 0] ** 2 + M * G * smp["y"][:, 0]
    scale = M * G * W
    assert float(np.max(np.abs(E - E[0]))) <= 1e-9 * scale
    assert np.sum(ev["kind"] == "slide") >= 2          # it turns back and forth
    for k in range(t.size):
        th_k = smp["angle"][k, 0]
        ck, sk = math.cos(th_k), math.sin(th_k)
        xk = np.array([smp["x"][k, 0], smp["y"][k, 0]])
        for (bx, by) in ((W / 2, H / 2), (-W / 2, H / 2), (W / 2, -H / 2), (-W / 2, -H / 2)):
            q = xk + np.array([ck * bx - sk * by, sk * bx + ck * by])
            assert q @ n1 >= -1e-9 * W and q @ n2 >= -1e-9 * W


def _linprog_rest(m, g, contacts):
    """Independent static-equilibrium test: scipy's LP over the contact forces
    (N_k, T_k) with N_k >= 0, |T_k| <= mu_k N_k and the three balance equations."""
    from scipy.optimize import linprog
    K = len(contacts)
    A = np.zeros((3, 2 * K))
    for k, (rx, ry, nx, ny, mu) in enumerate(contacts):
        for j, (fx, fy) in enumerate(((nx, ny), (ny, -nx))):
            A[:, 2 * k + j] = (fx, fy, rx * fy - ry * fx)
    b = np.array([-m * g[0], -m * g[1], 0.0])
    A_ub, b_ub = [], []
    for k, c in enumerate(contacts):
        mu = c[4]
        for s in (1.0, -1.0):
            row = np.zeros(2 * K)
            row[2 * k] = -mu
            row[2 * k + 1] = s
            A_ub.append(row)
            b_ub.append(0.0)
    bounds = [(0, None) if j % 2 == 0 else (None, None) for j in range(2 * K)]
    r = linprog(np.zeros(2 * K), A_ub=np.array(A_ub), b_ub=np.array(b_ub), A_eq=A, b_eq=b,
                bounds=bounds, method="highs")
    return r.status == 0


def test_three_contact_rest_agrees_with_an_lp_on_random_faces_and_corners():
    """``wedge2d.three_contact_rest`` (enumeration of the cone edges' basic solutions)
    against scipy's LP on 400 random configurations: a face (two corners on one plane) and
    a corner on a second plane, random friction; cases within 1e-6 of the boundary (the LP's
    own tolerance) are skipped."""
    from rbimpact.kernels.wedge2d import three_contact_rest
    rng = np.random.default_rng(7)
    agree = checked = 0
    for _ in range(400):
        a = rng.uniform(-1.4, 1.4)
        b = rng.uniform(-1.4, 1.4)
        n1 = (-math.sin(a), math.cos(a))
        n2 = (math.sin(b), math.cos(b))
        mu1, mu2 = rng.choice([0.0, 0.2, 1.0, 5.0], 2)
        t1 = (n1[1], -n1[0])
        h = rng.uniform(0.05, 0.5)
        c0 = (-h * n1[0] - 0.3 * t1[0], -h * n1[1] - 0.3 * t1[1], *n1, mu1)
        c1 = (-h * n1[0] + 0.3 * t1[0], -h * n1[1] + 0.3 * t1[1], *n1, mu1)
        r2 = rng.uniform(-0.5, 0.5, 2)
        c2 = (float(r2[0]), float(r2[1]), *n2, mu2)
        got = three_contact_rest(1.0, 0.0, -G, (c0, c1, c2))
        ref = _linprog_rest(1.0, (0.0, -G), [c0, c1, c2])
        # skip near-boundary cases: perturb the load by 1e-6 and require the same answer
        if (_linprog_rest(1.0, (1e-6, -G), [c0, c1, c2]) != ref
                or _linprog_rest(1.0, (-1e-6, -G), [c0, c1, c2]) != ref):
            continue
        checked += 1
        agree += got == ref
    assert checked >= 300
    assert agree == checked
