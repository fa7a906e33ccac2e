"""A box or capsule held on two planes at once in 3D (``kernels/pivot3d.py``: each
integrated contact on its own plane, a groove or a corner): one feature on each plane,
sticking or sliding, until a normal force vanishes, a slip starts or stops, or another
feature lands. Checked against an independent integration of the same constrained
Newton-Euler equations (scipy, Lagrange multipliers at the acceleration level), energy
conservation without friction, and both features staying on their planes."""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from rbimpact.kernels.flight3d import qmul, qrot
from rbimpact.laws import Law
from rbimpact.scene3d import Scene3D
from rbimpact.shapes3d import Box3D
from rbimpact.simulation3d import Simulation3D

G = 9.81
DROP = 1e-9     # the two lowest corners start this far (m) above their planes
ALPHA = 0.6     # each groove plane's tilt (rad)
DIMS = (0.3, 0.2, 0.1)
MASS = 1.5
N1 = np.array([-math.sin(ALPHA), 0.0, math.cos(ALPHA)])
N2 = np.array([math.sin(ALPHA), 0.0, math.cos(ALPHA)])
CORNERS = [np.array((sx, sy, sz)) * np.array(DIMS) / 2
           for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]


def _box_in_groove(q, law="kane_levinson", mu=0.0):
    """A box at rest in the V-groove of N1 and N2 (axis y) with orientation q, placed so
    that its lowest corner towards each plane is DROP above it. Returns the simulation and
    the two corner indices."""
    q = np.asarray(q, float) / np.linalg.norm(q)
    V = [np.array(qrot(*q, *b)) for b in CORNERS]
    k1 = int(np.argmin([N1 @ v for v in V]))
    k2 = int(np.argmin([N2 @ v for v in V]))
    xz = np.linalg.solve(np.array([N1[[0, 2]], N2[[0, 2]]]),
                         [DROP - N1 @ V[k1], DROP - N2 @ V[k2]])
    scene = Scene3D(gravity=(0.0, 0.0, -G))
    scene.add_plane((0.0, 0.0, 0.0), tuple(N1))
    scene.add_plane((0.0, 0.0, 0.0), tuple(N2))
    scene.add_body(Box3D(DIMS), MASS, (xz[0], 0.0, xz[1]), orientation=tuple(q))
    return Simulation3D(scene, Law(law, e=0.0, mu=mu)), k1, k2


def _rot(q):
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def _independent(y0, t0, t1, k1, k2):
    """Frictionless motion with corner k1 on plane 1 and k2 on plane 2: Newton-Euler with
    normal forces lam_k n_k from the two acceleration constraints
    ``n_k . (a + al x r_k + w x (w x r_k)) = 0``, integrated by scipy's DOP853."""
    h = np.array(DIMS)
    Ib = MASS / 12.0 * np.array([h[1] ** 2 + h[2] ** 2, h[0] ** 2 + h[2] ** 2,
                                 h[0] ** 2 + h[1] ** 2])
    g = np.array([0.0, 0.0, -G])

    def rhs(t, y):
        q = y[3:7] / np.linalg.norm(y[3:7])
        v, w = y[7:10], y[10:13]
        R = _rot(q)
        Iw = R @ np.diag(Ib) @ R.T
        Ii = np.linalg.inv(Iw)
        al0 = Ii @ (-np.cross(w, Iw @ w))
        rs = (R @ CORNERS[k1], R @ CORNERS[k2])
        ns = (N1, N2)
        A = np.zeros((2, 2))
        b = np.zeros(2)
        for a in range(2):
            b[a] = -(ns[a] @ (g + np.cross(al0, rs[a]) + np.cross(w, np.cross(w, rs[a]))))
            for c in range(2):
                A[a, c] = ns[a] @ (ns[c] / MASS + np.cross(Ii @ np.cross(rs[c], ns[c]), rs[a]))
        lam = np.linalg.solve(A, b)
        F = lam[0] * ns[0] + lam[1] * ns[1]
        T = lam[0] * np.cross(rs[0], ns[0]) + lam[1] * np.cross(rs[1], ns[1])
        return np.concatenate([v, 0.5 * np.array(qmul(0.0, *w, *q)), g + F / MASS,
                               al0 + Ii @ T])

    sol = solve_ivp(rhs, (t0, t1), y0, rtol=1e-12, atol=1e-13, method="DOP853")
    return sol.y[:, -1]


def test_frictionless_box_on_two_groove_planes_agrees_with_an_independent_integration():
    """A tilted box released in a frictionless V-groove lands at once with one corner on
    each plane (event "pivot" with two contacts on two planes) and slides on both. Until
    a third corner lands (t = 0.0965 s) the motion agrees with an independent integration
    of the constrained equations to 1e-10 m, energy is conserved to 1e-9 of m g L, and
    both corners stay on their planes."""
    sim, k1, k2 = _box_in_groove((0.95, 0.2, 0.15, 0.1))
    t_end = 0.09
    res = sim.run(t_end)
    ev = res.events
    assert res.status == "done"
    assert list(ev["kind"]) == ["impact", "impact", "pivot"]
    assert set(ev["b"][:2]) == {-1, -2}
    assert ev["mode"][2] == 2                       # two integrated contacts
    t0 = float(ev["t"][-1])
    t = np.linspace(t0, t_end, 1501)[1:]
    s = res.sample(t)
    L = math.sqrt(sum(d * d for d in DIMS)) / 2
    E = res.energy(t)
    assert float(np.ptp(E)) <= 1e-9 * MASS * G * L      # contact_tol 1e-10 per step
    for j in range(t.size):
        q, x = s["orientation"][j, 0], s["position"][j, 0]
        W = [x + np.array(qrot(*q, *b)) for b in CORNERS]
        assert abs(N1 @ W[k1]) <= 1e-10 * L and abs(N2 @ W[k2]) <= 1e-10 * L
        assert min(min(N1 @ w, N2 @ w) for w in W) >= -1e-10 * L
    s0 = res.sample([t0])
    y0 = np.concatenate([s0["position"][0, 0], s0["orientation"][0, 0],
                         s0["velocity"][0, 0], s0["angular_velocity"][0, 0]])
    y1 = _independent(y0, t0, t_end, k1, k2)
    assert np.max(np.abs(y1[:3] - s["position"][-1, 0])) <= 1e-10 * L
    assert np.max(np.abs(y1[7:10] - s["velocity"][-1, 0])) <= 1e-8 * math.sqrt(G * L)


@pytest.mark.parametrize("mu", [0.2, 1.0])
def test_box_on_two_groove_planes_with_friction_creates_no_energy(mu):
    """The same box with friction (stick and slip on each plane, each with its own cone):
    no energy is created beyond the integrator's tolerance and no corner goes into a plane
    until the run ends or a contact mode it does not support is named."""
    sim, k1, k2 = _box_in_groove((0.95, 0.2, 0.15, 0.1), mu=mu)
    res = sim.run(0.09)
    assert res.status == "done"
    ev = res.events
    assert ev["kind"][2] == "pivot" and ev["mode"][2] == 2
    t = np.linspace(float(ev["t"][2]), 0.09, 1501)[1:]
    E = res.energy(t)
    L = math.sqrt(sum(d * d for d in DIMS)) / 2
    assert float(np.max(E - np.minimum.accumulate(E))) <= 1e-9 * MASS * G * L
    s = res.sample(t)
    for j in range(0, t.size, 10):
        q, x = s["orientation"][j, 0], s["position"][j, 0]
        W = [x + np.array(qrot(*q, *b)) for b in CORNERS]
        assert min(min(N1 @ w, N2 @ w) for w in W) >= -1e-9 * L


def _box_on_groove_face(gap_to_crease, v_down, v_axis, law, e, policy):
    """The box lying with its largest face on plane N1, its lower long edge
    ``gap_to_crease`` (m) up the slope from the groove's crease (the y axis), moving at
    ``v_down`` (m/s) down the slope and ``v_axis`` along the groove."""
    th = -ALPHA                                   # body z onto N1, body x up the slope
    q = (math.cos(th / 2), 0.0, math.sin(th / 2), 0.0)
    up = np.array([math.cos(ALPHA), 0.0, math.sin(ALPHA)])
    centre = (gap_to_crease + DIMS[0] / 2) * up + DIMS[2] / 2 * N1
    scene = Scene3D(gravity=(0.0, 0.0, -G))
    scene.add_plane((0.0, 0.0, 0.0), tuple(N1))
    scene.add_plane((0.0, 0.0, 0.0), tuple(N2))
    v = -v_down * up + np.array([0.0, v_axis, 0.0])
    scene.add_body(Box3D(DIMS), MASS, tuple(centre), orientation=q, velocity=tuple(v))
    return Simulation3D(scene, Law(law, e=e, mu=0.0), policy=policy)


@pytest.mark.parametrize("law, e, policy", [
    ("chatterjee_ruina", 0.3, "sequential"), ("kane_levinson", 0.3, "simultaneous"),
    ("kane_levinson", 0.0, "sequential")])
def test_box_sliding_on_a_groove_face_into_the_crease_slides_along_the_groove(law, e,
                                                                                policy):
    """A frictionless box sliding on one face of a V-groove into its crease (campaign
    scene 3:944403545 stalled there: its edge's impact on the other plane was resolved
    alone, and the held face's projection drove the edge back into that plane at once,
    1500 impacts at one instant decaying by 0.62 each). The held face now takes part in
    the impact. Every contact force is normal to a plane whose normal has no y component
    and gravity is along z, so the momentum along the groove is conserved exactly; the
    box ends sliding along the crease with its face on N1 and its edge on N2, without
    rising energy or any corner below a plane."""
    v_axis = 0.7
    sim = _box_on_groove_face(0.02, 0.3, v_axis, law, e, policy)
    t_end = 1.0
    res = sim.run(t_end, max_events=20_000)
    assert res.status == "done"
    t = np.linspace(0.0, t_end, 2001)
    s = res.sample(t)
    L = math.sqrt(sum(d * d for d in DIMS)) / 2
    assert np.max(np.abs(s["velocity"][:, 0, 1] - v_axis)) <= 1e-12 * v_axis
    E = res.energy(t)
    assert float(np.max(E - np.minimum.accumulate(E))) <= 1e-9 * MASS * G * L
    for j in range(0, t.size, 5):
        q, x = s["orientation"][j, 0], s["position"][j, 0]
        W = [x + np.array(qrot(*q, *b)) for b in CORNERS]
        assert min(min(N1 @ w, N2 @ w) for w in W) >= -1e-9 * L
    # the end: the face on N1 (four corners), the lower edge on N2 (two), each touching
    # within gap_tol, nothing moving but along the groove
    q, x = s["orientation"][-1, 0], s["position"][-1, 0]
    W = [x + np.array(qrot(*q, *b)) for b in CORNERS]
    gap_tol = sim.tolerances["gap_tol"]
    assert sorted(N1 @ w for w in W)[3] <= gap_tol
    assert sorted(N2 @ w for w in W)[1] <= gap_tol
    v_end, w_end = s["velocity"][-1, 0], s["angular_velocity"][-1, 0]
    assert abs(v_end[0]) + abs(v_end[2]) + L * np.abs(w_end).sum() <= 1e-6 * v_axis


def test_sampling_a_held_motion_one_time_at_a_time_gives_the_same_states_bit_for_bit():
    """Result3D.sample keeps each body's integrators between calls (a later time steps on,
    an earlier one resumes from the checkpoint of the previous step or restarts): times
    asked one at a time, in a random order, back and forth as a minimiser asks them, give
    exactly the states of one sorted call (the steps do not depend on the times asked)."""
    sim, _, _ = _box_in_groove((0.95, 0.2, 0.15, 0.1))
    res = sim.run(0.09)
    t0 = float(res.events["t"][-1])         # from the pivot on: one integrated segment
    rng = np.random.default_rng(7)
    t = np.sort(np.concatenate([np.linspace(t0, 0.09, 40),
                                t0 + 0.01 + 1e-6 * rng.random(20)]))
    ref = res.sample(t)
    fresh = sim.run(0.09)                      # a result whose integrators start cold
    for k in rng.permutation(t.size):
        s = fresh.sample([t[k]])
        for key in ref:
            np.testing.assert_array_equal(s[key][0], ref[key][k])
