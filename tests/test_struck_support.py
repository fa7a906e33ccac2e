"""A body resting on a plane and struck by another body, under the simultaneous policy:
the plane's reaction is impulsive too, so the contacts the struck body touches its plane
with take part in the joint impact (``stepper2d._held_into_instant``, session 30). Before,
the struck body was first driven into its plane and hit it afterwards, which is the
sequential policy's answer, not the simultaneous one's. Checked against closed forms and
against an independent enumeration of the plastic impact's linear complementarity
problem (Newton's law with e = 0 and Coulomb friction at every contact)."""
import itertools

import numpy as np
import pytest

from rbimpact import Disk, Law, Scene2D, Simulation, scenarios

G = 9.81


def disk_on_disk(policy, e):
    """Disk 0 (r = 0.1 m, 1 kg) at rest on the floor, disk 1 (same) dropped on it from
    0.3 m above its top."""
    sc = Scene2D(gravity=(0.0, -G))
    sc.add_body(Disk(0.1), 1.0, (0.0, 0.1))
    sc.add_body(Disk(0.1), 1.0, (0.0, 0.5))
    sc.add_floor()
    return Simulation(sc, Law("kane_levinson", e=e, mu=0.3), policy=policy)


@pytest.mark.parametrize("e", [0.0, 0.5, 1.0])
def test_disk_struck_on_the_floor_stays_and_the_other_rebounds(e):
    """Simultaneous Newton impact on a vertical column: the lower disk cannot move (the
    floor holds it), so the upper one leaves at e times its speed, sqrt(2 g 0.2) m/s, and
    the floor's impulse equals the top contact's, (1 + e) m v; at e = 0 it rests on it."""
    res = disk_on_disk("simultaneous", e).run(0.25)
    v = np.sqrt(2 * G * 0.2)
    ev = res.events[res.events["kind"] == "impact"]
    top = ev[(ev["a"] == 0) & (ev["b"] == 1)][0]
    floor = ev[(ev["a"] == 0) & (ev["b"] == -1)][0]
    assert top["t"] == floor["t"] == pytest.approx(np.sqrt(2 * 0.2 / G), rel=1e-12)
    assert top["v_i"][0] == pytest.approx(-v, rel=1e-12)
    assert top["v_f"][0] == pytest.approx(e * v, rel=1e-12, abs=1e-12)
    assert top["P"][0] == pytest.approx((1 + e) * v, rel=1e-12)
    assert floor["P"][0] == pytest.approx((1 + e) * v, rel=1e-12)
    assert floor["v_i"][0] == 0.0 and abs(floor["v_f"][0]) <= 1e-12
    s = res.sample([top["t"] + 1e-6])
    assert abs(s["vy"][0, 0]) <= 1e-12 and abs(s["y"][0, 0] - 0.1) <= 1e-12
    if e > 0.0:
        assert s["vy"][0, 1] == pytest.approx(e * v - G * 1e-6, rel=1e-9)
    else:                                    # plastic: it rests on the lower one
        assert abs(s["vy"][0, 1]) <= 1e-12 and abs(s["y"][0, 1] - 0.3) <= 1e-12


def test_sequential_policy_keeps_its_own_answer():
    """The sequential policy resolves the top contact alone first (the lower disk is driven
    into the floor at (1 + e) v / 2 and bounces there): a different, stated answer."""
    res = disk_on_disk("sequential", 0.5).run(0.21)
    ev = res.events
    assert np.any(ev["kind"] == "release")
    floor = ev[(ev["kind"] == "impact") & (ev["a"] == 0) & (ev["b"] == -1)]
    assert floor["v_i"][0][0] == pytest.approx(-0.75 * np.sqrt(2 * G * 0.2), rel=1e-12)


def _plastic_lcp(X, A, V, m, inertia, mu, contacts):
    """Every solution of the plastic impact of two bodies (states X, A, V: centres (m),
    angles (rad), velocities (vx, vy, omega) of both, stacked) at the contacts ``(a, b,
    point, normal)`` (b = -1: the floor; normal from b to a): Newton's law with e = 0 and
    Coulomb friction, each contact separating, sticking or sliding either way (all 4^k
    modes enumerated). Returns the velocities after."""
    def jac(body, p, d):
        J = np.zeros(6)
        r = p - X[body]
        J[3 * body:3 * body + 2] = d
        J[3 * body + 2] = r[0] * d[1] - r[1] * d[0]
        return J
    rows = []
    for a, b, p, n in contacts:
        t = np.array([-n[1], n[0]])
        JN, JT = jac(a, p, n), jac(a, p, t)
        if b >= 0:
            JN, JT = JN - jac(b, p, n), JT - jac(b, p, t)
        rows += [JN, JT]
    J = np.array(rows)
    k = len(contacts)
    Minv = np.diag([1 / m, 1 / m, 1 / inertia] * 2)
    Wc = J @ Minv @ J.T
    v0 = J @ V
    out = []
    for modes in itertools.product(range(4), repeat=k):
        Aeq, beq = [], []
        for c, md in enumerate(modes):
            iN, iT = 2 * c, 2 * c + 1
            if md == 0:
                for i in (iN, iT):
                    row = np.zeros(2 * k)
                    row[i] = 1.0
                    Aeq.append(row)
                    beq.append(0.0)
                continue
            Aeq.append(Wc[iN])
            beq.append(-v0[iN])
            if md == 1:
                Aeq.append(Wc[iT])
                beq.append(-v0[iT])
            else:
                row = np.zeros(2 * k)
                row[iT] = 1.0
                row[iN] = mu if md == 2 else -mu
                Aeq.append(row)
                beq.append(0.0)
        try:
            P = np.linalg.solve(np.array(Aeq), np.array(beq))
        except np.linalg.LinAlgError:
            continue
        vf = v0 + Wc @ P
        ok = True
        for c, md in enumerate(modes):
            PN, PT, vN, vT = P[2 * c], P[2 * c + 1], vf[2 * c], vf[2 * c + 1]
            ok &= vN >= -1e-12 if md == 0 else PN >= -1e-15
            ok &= md != 1 or abs(PT) <= mu * PN + 1e-15
            ok &= md != 2 or vT >= -1e-12
            ok &= md != 3 or vT <= 1e-12
        if ok:
            out.append(V + Minv @ J.T @ P)
    return out


def test_domino_strike_matches_the_plastic_lcp():
    """dominoes (Kane & Levinson, e = 0, mu = 0.5): the first domino, pivoting on its front
    corner, strikes the second, standing on its face. The joint impact of the striking
    corner, the pivot corner and the struck domino's two floor corners has exactly one
    solution (enumerated independently here): the striker slides on the floor and on the
    struck face, the struck domino turns on its far corner (sticking) while its near one
    lifts. rbimpact's velocities just after the strike match it to 1e-9 m/s. (Before the
    struck domino's floor contacts took part, it was driven into the floor and stopped
    turning: pymunk converged to the enumerated answer, rbimpact did not.)"""
    sc = scenarios.get("dominoes", law="kane_levinson", count=3)
    p = sc.params
    w, h, m, mu = p["width"], p["height"], p["mass"], p["mu"]
    res = sc.simulation().run(0.2, max_events=sc.max_events)
    ev = res.events
    ts = float(ev["t"][(ev["kind"] == "impact") & (ev["a"] == 0) & (ev["b"] == 1)][0])
    assert ts == pytest.approx(sc.reference.t1, rel=1e-9)
    before = res.sample([ts * (1 - 1e-13)])
    after = res.sample([ts + 1e-12])
    X = [np.array([before["x"][0, i], before["y"][0, i]]) for i in range(2)]
    A = [before["angle"][0, i] for i in range(2)]
    V = np.array([before[k][0, i] for i in range(2) for k in ("vx", "vy", "omega")])

    def corners(i):
        c, s = np.cos(A[i]), np.sin(A[i])
        return [X[i] + np.array([c * x - s * y, s * x + c * y])
                for x, y in ((-w / 2, -h / 2), (w / 2, -h / 2), (w / 2, h / 2), (-w / 2, h / 2))]
    c0, c1 = corners(0), corners(1)
    up = np.array([0.0, 1.0])
    contacts = [(0, -1, min(c0, key=lambda q: q[1]), up),
                (1, 0, max(c0, key=lambda q: q[0]), np.array([1.0, 0.0]))]
    contacts += [(1, -1, q, up) for q in c1 if abs(q[1]) <= 1e-12]
    assert len(contacts) == 4
    sols = _plastic_lcp(X, A, V, m, m * (w * w + h * h) / 12, mu, contacts)
    assert len(sols) == 1
    got = np.array([after[k][0, i] for i in range(2) for k in ("vx", "vy", "omega")])
    scale = np.array([1, 1, h / 2] * 2)     # rad/s -> m/s at the domino's half height
    np.testing.assert_allclose(got * scale, sols[0] * scale, rtol=0, atol=1e-9)
    assert sols[0][5] < -1.0                 # the struck domino turns toward the next
