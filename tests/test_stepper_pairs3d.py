"""Body-body impacts of every 3D shape pair in the event-driven stepper (issue 16 item 1):
``kernels/stepper3d.py`` with ``pair3d_toi.pair_toi`` and ``pair3d_manifold.pair_manifold``.

Real physics that can fail: linear and angular momentum conserved to round-off in zero
gravity; kinetic energy conserved at e = 1 without friction and never created by the laws
that cannot create it; the first impact time against a bisection of the exact signed gap
along the exact flight; the recorded impact equals the law applied by ``Law.resolve`` to
the contact rebuilt independently (witness points, normal, Delassus matrix from the world
inertia tensors); invariance under a rigid motion of the scene and under swapping the
bodies; a fast-spinning capsule and a grazed box edge; a face landing flat on a face as
one cluster of four points; the named refusals of persistent body-body contact (issue 16
item 2); bad input.

Every run here uses two laws in its table (the pair's law and another for the scene), so
they all share one compiled loop (``LAW_ANY``, the same feature switches): one compile.
"""
import math

import numpy as np
import pytest

from rbimpact import Law
from rbimpact.errors import SimulationError
from rbimpact.kernels.flight3d import N_WS, pose_at
from rbimpact.kernels.pair3d import FR_GAP, FR_NX, FR_PAX, FR_PBX, N_FE, N_FR, pair_frame
from rbimpact.scene3d import Scene3D
from rbimpact.shapes3d import Box3D, Capsule, Sphere
from rbimpact.simulation3d import Simulation3D

SHAPES = {
    "sphere": lambda: Sphere(0.08),
    "box": lambda: Box3D((0.3, 0.16, 0.1)),
    "cube": lambda: Box3D((0.2, 0.2, 0.2)),
    "capsule": lambda: Capsule(0.3, 0.05),
}
#: one line per pair kind of pair3d.PAIR_TABLE in both orders where they differ
PAIRS = [("box", "sphere"), ("sphere", "box"), ("box", "box"), ("capsule", "sphere"),
         ("capsule", "capsule"), ("box", "capsule"), ("capsule", "cube")]


def quat(axis, angle):
    a = np.asarray(axis, float)
    a = a / np.linalg.norm(a)
    return (math.cos(0.5 * angle), *(math.sin(0.5 * angle) * a))


def qmul(p, q):
    w1, x1, y1, z1 = p
    w2, x2, y2, z2 = q
    return (w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2)


def rotm(q):
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def sim_with(scene, law, **kw):
    """A simulation whose table holds ``law`` for the pair (0, 1) and another law for the
    scene (never used without planes): the loop compiled for several laws (LAW_ANY)."""
    other = Law("kane_levinson", e=0.5) if law.name != "kane_levinson" else Law("routh", e=0.5)
    return Simulation3D(scene, other, pair_laws={(0, 1): law}, **kw)


def two_body(sa, sb, law, *, R=np.eye(3), shift=(0.0, 0.0, 0.0), swap=False,
             offset=0.03, gravity=(0.0, 0.0, 0.0), **kw):
    """Two bodies thrown at each other in flight, no plane; the scene turned by the
    rotation matrix ``R`` (and the quaternion ``kw['qR']``) and moved by ``shift``."""
    qR = kw.pop("qR", (1.0, 0.0, 0.0, 0.0))
    shift = np.asarray(shift, float)
    specs = [(SHAPES[sa](), 1.3, (-0.45, offset, 0.5 * offset), quat((1, 2, 3), 0.4),
              (2.0, 0.1, -0.05), (3.0, -7.0, 2.0)),
             (SHAPES[sb](), 0.7, (0.45, -offset, -0.5 * offset), quat((-2, 1, 0.5), 0.9),
              (-1.5, 0.05, 0.1), (-2.0, 1.0, 4.0))]
    if swap:
        specs = specs[::-1]
    scene = Scene3D(gravity=gravity)
    for sh, m, p, q, v, w in specs:
        scene.add_body(sh, m, tuple(R @ np.array(p) + shift), orientation=qmul(qR, q),
                       velocity=tuple(R @ np.array(v)), angular_velocity=tuple(R @ np.array(w)))
    return sim_with(scene, law, **kw)


def world_inertia(b, q):
    Rm = rotm(q)
    return Rm @ np.diag(b.inertia) @ Rm.T


def momenta(res, sim, t):
    """Linear momentum, angular momentum about the origin, kinetic energy at t."""
    s = res.sample([t])
    p = np.zeros(3)
    L = np.zeros(3)
    E = 0.0
    for i, b in enumerate(sim.scene.bodies):
        x, v = s["position"][0, i], s["velocity"][0, i]
        q, w = s["orientation"][0, i], s["angular_velocity"][0, i]
        Iw = world_inertia(b, q) @ w
        p += b.mass * v
        L += Iw + b.mass * np.cross(x, v)
        E += 0.5 * b.mass * v @ v + 0.5 * w @ Iw
    return p, L, E


def scales(sim):
    p = sum(b.mass * np.linalg.norm(b.velocity) for b in sim.scene.bodies)
    L = sum(np.linalg.norm(world_inertia(b, b.orientation) @ b.angular_velocity)
            + b.mass * np.linalg.norm(b.position) * np.linalg.norm(b.velocity)
            for b in sim.scene.bodies)
    return p, L


#: (law, parameters, energy): "kept" (e = 1, frictionless), "lost" (a law that cannot
#: create energy), None (Brach and Kane & Levinson with friction may create energy)
LAWS = [("kane_levinson", dict(e=1.0, mu=0.0), "kept"),
        ("routh", dict(e=1.0, mu=0.0, restitution="newton"), "kept"),
        ("routh", dict(e=0.6, mu=0.4), "lost"),
        ("routh", dict(e=0.6, mu=0.4, restitution="poisson"), "lost"),
        ("smith", dict(e=0.5, mu=0.3), "lost"),
        ("chatterjee_ruina", dict(e=0.7, e_t=0.3, mu=0.5), "lost"),
        ("brach", dict(e=0.4, mu=0.2, e_t=0.3), None)]


@pytest.mark.parametrize("sa,sb", PAIRS)
@pytest.mark.parametrize("name,params,energy", LAWS)
def test_momentum_conserved_energy_not_created(sa, sb, name, params, energy):
    sim = two_body(sa, sb, Law(name, **params))
    res = sim.run(0.6)
    assert res.status == "done"
    imp = res.events[res.events["kind"] == "impact"]
    assert len(imp) >= 1 and set(imp["b"]) == {1}
    p0, L0, E0 = momenta(res, sim, 0.0)
    p1, L1, E1 = momenta(res, sim, 0.6)
    ps, Ls = scales(sim)
    assert np.all(np.abs(p1 - p0) <= 1e-13 * ps), (p0, p1)
    # a general rotation is integrated (rot_tol 1e-12): angular momentum to its accuracy
    assert np.all(np.abs(L1 - L0) <= 1e-10 * Ls), (L0, L1)
    if energy == "kept":
        assert abs(E1 - E0) <= 1e-10 * E0, (E0, E1)
        assert abs(imp["dE"]).max() <= 1e-12 * E0
    elif energy == "lost":
        assert E1 <= E0 * (1 + 1e-10), (E0, E1)
        assert imp["dE"].max() <= 1e-13 * E0


def flight_row(b):
    row = np.zeros(19)
    row[0:3] = b.position
    row[3:7] = b.orientation
    row[7:10] = b.velocity
    row[10:13] = b.angular_velocity
    return row


def exact_frame(sim, t):
    """Frame row (pair3d.pair_frame) of bodies 0 and 1 in free flight (zero gravity) at
    ``t``: each body's exact torque-free rotation (closed form, or flight3d's integration
    from t = 0, the stepper's first segment)."""
    rows = []
    for i, b in enumerate(sim.scene.bodies):
        rk, axis = sim._rot[i]
        ws = np.zeros(N_WS)
        ws[0] = -1.0
        out = np.zeros(19)
        rc = pose_at(flight_row(b), rk, axis, *b.inertia, ws, t,
                     sim.tolerances["rot_tol"], int(sim.tolerances["rot_max_steps"]), out)
        assert rc == 0
        rows.append(out)
    fr, fe = np.zeros(N_FR), np.zeros(N_FE, np.int64)
    bint, bflt = sim._bint, sim._bflt
    pair_frame(int(bint[0, 0]), *bflt[0, 4:8], rows[0], int(bint[1, 0]), *bflt[1, 4:8],
               rows[1], fr, fe)
    return fr, rows


@pytest.mark.parametrize("sa,sb", PAIRS)
@pytest.mark.parametrize("name,params", [("routh", dict(e=0.6, mu=0.4)),
                                         ("chatterjee_ruina", dict(e=0.5, e_t=0.4, mu=0.8))])
def test_impact_time_and_law_against_independent_contact(sa, sb, name, params):
    """The first impact time against a bisection of the exact signed gap to 1e-12 s; the
    recorded v_i, P, v_f, dE against the law applied by Law.resolve to the contact rebuilt
    from the pair frame at that time (the Delassus matrix from the arms and the world
    inertia tensors, in the event's own tangent basis)."""
    law = Law(name, **params)
    sim = two_body(sa, sb, law)
    res = sim.run(0.6)
    ev = res.events[0]
    t_imp = float(ev["t"])
    ts = np.linspace(0.0, t_imp + 1e-3, 2001)
    g = np.array([exact_frame(sim, t)[0][FR_GAP] for t in ts])
    k = int(np.argmax(g <= 0.0))
    assert k > 0 and np.all(g[:k] > 0.0)
    lo, hi = ts[k - 1], ts[k]
    while hi - lo > 1e-15:
        mid = 0.5 * (lo + hi)
        if exact_frame(sim, mid)[0][FR_GAP] > 0.0:
            lo = mid
        else:
            hi = mid
    assert abs(t_imp - 0.5 * (lo + hi)) <= 1e-12, (t_imp, lo, hi)
    fr, rows = exact_frame(sim, t_imp)
    assert abs(fr[FR_GAP]) < 1e-11
    n = fr[FR_NX:FR_NX + 3]
    np.testing.assert_allclose(ev["normal"], n, atol=1e-9)
    basis = np.array([ev["normal"], ev["tangent"], np.cross(ev["normal"], ev["tangent"])])
    arms = [fr[FR_PAX:FR_PAX + 3] - rows[0][:3], fr[FR_PBX:FR_PBX + 3] - rows[1][:3]]
    dv = np.zeros(3)
    W = np.zeros((3, 3))
    for i, (b, r, sg) in enumerate(zip(sim.scene.bodies, arms, (1.0, -1.0))):
        v, w = rows[i][7:10], rows[i][10:13]
        dv += sg * (v + np.cross(w, r))
        Iinv = np.linalg.inv(world_inertia(b, rows[i][3:7]))
        X = np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])
        W += basis @ (np.eye(3) / b.mass - X @ Iinv @ X) @ basis.T
    vi = basis @ dv
    np.testing.assert_allclose(ev["v_i"], vi, rtol=1e-8, atol=1e-9)
    imp = law.resolve(vi, W)
    np.testing.assert_allclose(ev["P"], imp.P, rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose(ev["v_f"], imp.v_f, rtol=1e-7, atol=1e-9)
    assert ev["dE"] == pytest.approx(imp.dE, rel=1e-6, abs=1e-10)


@pytest.mark.parametrize("sa,sb", [("box", "sphere"), ("capsule", "capsule"),
                                   ("box", "capsule")])
def test_invariant_under_rigid_motion_and_swap(sa, sb):
    law = Law("routh", e=0.6, mu=0.4)
    ref = two_body(sa, sb, law).run(0.6)
    qR = quat((0.3, -1.0, 0.7), 1.1)
    Rm = rotm(qR)
    shift = (3.1, -5.2, 0.7)
    mv = two_body(sa, sb, law, R=Rm, qR=qR, shift=shift).run(0.6)
    sw = two_body(sa, sb, law, swap=True).run(0.6)
    e0, e1, e2 = (r.events[r.events["kind"] == "impact"] for r in (ref, mv, sw))
    assert len(e0) >= 1 and len(e1) == len(e0) and len(e2) == len(e0)
    np.testing.assert_allclose(e1["t"], e0["t"], rtol=0, atol=1e-11)
    np.testing.assert_allclose(e2["t"], e0["t"], rtol=0, atol=1e-11)
    np.testing.assert_allclose(e1["normal"], e0["normal"] @ Rm.T, atol=1e-9)
    np.testing.assert_allclose(e1["point"], e0["point"] @ Rm.T + shift, atol=1e-9)
    np.testing.assert_allclose(e2["normal"], -e0["normal"], atol=1e-9)
    np.testing.assert_allclose(e2["point"], e0["point"], atol=1e-9)
    # contact-space normal quantities are frame and order invariant (the tangent basis
    # follows each frame's own rule)
    for e in (e1, e2):
        np.testing.assert_allclose(e["v_i"][:, 0], e0["v_i"][:, 0], atol=1e-9)
        np.testing.assert_allclose(e["P"][:, 0], e0["P"][:, 0], atol=1e-9)
        np.testing.assert_allclose(e["dE"], e0["dE"], atol=1e-10)
    f0, f1, f2 = (r.sample([0.6]) for r in (ref, mv, sw))
    for k, j in ((0, 1), (1, 0)):
        np.testing.assert_allclose(f1["velocity"][0, k], Rm @ f0["velocity"][0, k],
                                   atol=1e-9)
        np.testing.assert_allclose(f1["angular_velocity"][0, k],
                                   Rm @ f0["angular_velocity"][0, k], atol=1e-8)
        np.testing.assert_allclose(f2["velocity"][0, j], f0["velocity"][0, k], atol=1e-9)
        np.testing.assert_allclose(f2["angular_velocity"][0, j],
                                   f0["angular_velocity"][0, k], atol=1e-8)


def test_fast_spinning_capsule_does_not_miss_the_ball():
    """A capsule spinning at 300 rad/s drifting slowly toward a sphere: its cap sweeps past
    the sphere about 50 times per second; the first impact is the first time the exact gap
    reaches 0 (dense sampling of the exact flight finds no earlier touch)."""
    scene = Scene3D(gravity=(0.0, 0.0, 0.0))
    scene.add_body(Capsule(0.5, 0.02), 1.0, (0.0, 0.0, 0.0), orientation=quat((1, 0, 0), 1.4),
                   velocity=(0.05, 0.0, 0.0), angular_velocity=(0.0, 0.0, 300.0))
    scene.add_body(Sphere(0.05), 1.0, (0.36, 0.0, 0.0))
    sim = sim_with(scene, Law("kane_levinson", e=1.0, mu=0.0))
    res = sim.run(1.0)
    t_imp = float(res.events["t"][0])
    ts = np.linspace(0.0, t_imp, 100001)[:-1]
    g = np.array([exact_frame(sim, t)[0][FR_GAP] for t in ts])
    assert g.min() > 0.0
    assert abs(exact_frame(sim, t_imp)[0][FR_GAP]) < 1e-12


@pytest.mark.parametrize("delta,hits", [(1e-7, False), (-1e-7, True)])
def test_grazing_box_edge(delta, hits):
    """A sphere passing over a box's top edge: its bottom 1e-7 m above the edge misses,
    1e-7 m below clips it."""
    scene = Scene3D(gravity=(0.0, 0.0, 0.0))
    scene.add_body(Box3D((0.4, 0.4, 0.2)), 2.0, (0.0, 0.0, 0.0))
    r = 0.1
    scene.add_body(Sphere(r), 1.0, (-0.8, 0.05, 0.1 + r + delta), velocity=(3.0, 0.0, 0.0))
    res = sim_with(scene, Law("kane_levinson", e=0.5, mu=0.2)).run(0.6)
    assert (len(res.events) > 0) == hits


@pytest.mark.parametrize("policy", ["simultaneous", "sequential"])
def test_face_on_face_is_a_cluster_of_four(policy):
    """A cube landing flat on a wider box (zero gravity, e = 1, no friction), both with the
    cube's inertia: four contacts at the corners of the cube's face, at one instant (the
    manifold); kinetic energy, momentum and angular momentum kept; equal masses and
    moments exchange their velocities, no rotation (the simultaneous policy in one joint
    solve of the four, the sequential one by resolving them in turn)."""
    scene = Scene3D(gravity=(0.0, 0.0, 0.0))
    scene.add_body(Box3D((0.2, 0.2, 0.2)), 1.0, (0.0, 0.0, 0.5), velocity=(0.0, 0.0, -2.0))
    scene.add_body(Box3D((0.6, 0.5, 0.2)), 1.0, (0.0, 0.0, 0.0),
                   inertia=Box3D((0.2, 0.2, 0.2)).inertia(1.0))
    sim = sim_with(scene, Law("kane_levinson", e=1.0, mu=0.0), policy=policy)
    res = sim.run(0.5)
    imp = res.events[res.events["kind"] == "impact"]
    assert len(imp) >= 1 and np.all(imp["t"] == imp["t"][0])
    assert imp["t"][0] == pytest.approx(0.15, abs=1e-14)
    assert np.all(imp["cluster"] == 4)
    np.testing.assert_allclose(np.abs(imp["point"][:, :2]), 0.1, atol=1e-12)
    np.testing.assert_allclose(imp["point"][:, 2], 0.1, atol=1e-12)
    p0, L0, E0 = momenta(res, sim, 0.0)
    p1, L1, E1 = momenta(res, sim, 0.5)
    assert abs(E1 - E0) <= 1e-12 * E0
    np.testing.assert_allclose(p1, p0, atol=1e-14)
    np.testing.assert_allclose(L1, L0, atol=1e-14)
    s = res.sample([0.5])
    np.testing.assert_allclose(s["velocity"][0, :, 2], [0.0, -2.0], atol=1e-12)
    np.testing.assert_allclose(s["angular_velocity"][0], 0.0, atol=1e-12)
    if policy == "simultaneous":
        assert len(imp) == 4
        assert len(np.unique(np.round(imp["point"][:, :2], 9), axis=0)) == 4


def test_plastic_ride_together_is_refused_by_name():
    """A cube landing flat and centred on a wider box with e = 0 in zero gravity: the two
    then move together touching at zero normal speed (persistent body-body contact, not
    built, issue 16 item 2): a named refusal, the bodies touching and not overlapping."""
    scene = Scene3D(gravity=(0.0, 0.0, 0.0))
    scene.add_body(Box3D((0.2, 0.2, 0.2)), 1.0, (0.0, 0.0, 0.5), velocity=(0.0, 0.0, -2.0))
    scene.add_body(Box3D((0.6, 0.5, 0.2)), 1.0, (0.0, 0.0, 0.0))
    sim = sim_with(scene, Law("kane_levinson", e=0.0, mu=0.5))
    with pytest.raises(SimulationError,
                       match=r"persistent body-body contact .*\(issue 16\)") as info:
        sim.run(1.0)
    res = info.value.result
    assert res.status == "persistent_pair"
    s = res.sample([res.t_end])
    assert s["position"][0, 0, 2] - s["position"][0, 1, 2] == pytest.approx(0.2, abs=1e-12)
    np.testing.assert_allclose(s["velocity"][0, :, 2], -1.0, atol=1e-12)


def test_offset_plastic_landing_turns_and_parts():
    """The same landing off-centre: the plastic impact at the four corners leaves both
    bodies turning together about their common centre of mass with their contact at zero
    normal speed; no contact force can keep them together (it would have to pull), so they
    part: 'done', momentum and angular momentum kept, no energy created, and the gap
    grows afterwards."""
    scene = Scene3D(gravity=(0.0, 0.0, 0.0))
    scene.add_body(Box3D((0.2, 0.2, 0.2)), 1.0, (0.05, 0.0, 0.5), velocity=(0.0, 0.0, -2.0))
    scene.add_body(Box3D((0.6, 0.5, 0.2)), 1.0, (0.0, 0.0, 0.0))
    sim = sim_with(scene, Law("kane_levinson", e=0.0, mu=0.5))
    res = sim.run(1.0)
    assert res.status == "done"
    imp = res.events[res.events["kind"] == "impact"]
    assert np.all(imp["t"] == pytest.approx(0.15, abs=1e-14))
    p0, L0, E0 = momenta(res, sim, 0.0)
    p1, L1, E1 = momenta(res, sim, 1.0)
    np.testing.assert_allclose(p1, p0, atol=1e-13)
    np.testing.assert_allclose(L1, L0, atol=1e-12)
    assert E1 < E0
    fr, fe = np.zeros(N_FR), np.zeros(N_FE, np.int64)
    gaps = []
    for t in (0.3, 0.6, 1.0):
        s = res.sample([t])
        rows = [np.concatenate([s["position"][0, i], s["orientation"][0, i], np.zeros(12)])
                for i in (0, 1)]
        gaps.append(pair_frame(1, 0.0, 0.1, 0.1, 0.1, rows[0], 1, 0.0, 0.3, 0.25, 0.1,
                               rows[1], fr, fe))
    assert 0.0 < gaps[0] < gaps[1] < gaps[2]


def test_box_settling_on_a_box_is_refused_without_overlap():
    """A box bouncing onto a box resting on the floor: its bounces shrink until they would
    accumulate on the lower box (persistent contact between bodies): a named refusal, no
    interpenetration before it."""
    scene = Scene3D(gravity=(0.0, 0.0, -9.81))
    scene.add_floor()
    scene.add_body(Box3D((0.4, 0.4, 0.2)), 1.0, (0.0, 0.0, 0.1))
    scene.add_body(Box3D((0.3, 0.2, 0.1)), 0.5, (0.02, 0.01, 0.4))
    sim = sim_with(scene, Law("routh", e=0.5, mu=0.5))
    with pytest.raises(SimulationError, match="persistent body-body contact") as info:
        sim.run(3.0)
    res = info.value.result
    assert res.status == "persistent_pair"
    assert np.any((res.events["a"] == 0) & (res.events["b"] == 1))   # it landed on the box
    ts = np.linspace(0.0, res.t_end, 1501)
    s = res.sample(ts)
    fr, fe = np.zeros(N_FR), np.zeros(N_FE, np.int64)
    for k in range(len(ts)):
        rows = [np.concatenate([s["position"][k, i], s["orientation"][k, i], np.zeros(12)])
                for i in (1, 0)]
        g = pair_frame(1, 0.0, 0.15, 0.1, 0.05, rows[0], 1, 0.0, 0.2, 0.2, 0.1, rows[1],
                       fr, fe)
        assert g > -1e-9


def test_held_body_and_a_partner_distance_bound():
    """A capsule whose plastic landing makes it pivot on the floor (an integrated contact,
    no closed-form motion to search) next to a box at rest: while their bounding spheres
    surely stay apart (a bound from the held body's kinetic energy and gravity,
    ``stepper3d._held_pair``) the run goes on, checking again as time passes; a box within
    reach makes it stop with the named refusal of body-body contact with a held body. With
    ignore_unsupported_pairs=True they pass through each other (as before issue 16)."""
    def scene(xb):
        sc = Scene3D(gravity=(0.0, 0.0, -9.81))
        sc.add_floor()
        sc.add_body(Capsule(1.0, 0.02), 1.0, (0.0, 0.0, 0.5), orientation=quat((0, 1, 0), 1.2))
        sc.add_body(Box3D((0.2, 0.2, 0.2)), 1.0, (xb, 0.0, 0.1))
        return sc
    law = Law("kane_levinson", e=0.0, mu=0.3)
    far = sim_with(scene(0.9), law).run(1.0)
    assert far.status == "done"
    assert "pivot" in list(far.events["kind"])
    assert not np.any(far.events["b"] == 1)         # no body-body impact
    with pytest.raises(SimulationError, match=r"integrated \(pivot\) contact") as info:
        sim_with(scene(0.6), law).run(1.0)
    assert info.value.result.status == "persistent_pair"
    sim = Simulation3D(scene(0.6), law, ignore_unsupported_pairs=True)
    assert len(sim._pairs) == 0
    res = sim.run(0.5)
    assert "pivot" in list(res.events["kind"])


def test_bad_input():
    scene = Scene3D(gravity=(0.0, 0.0, 0.0))
    scene.add_body(Box3D((0.4, 0.2, 0.2)), 1.0, (0.0, 0.0, 0.0))
    scene.add_body(Capsule(0.3, 0.05), 1.0, (0.24, 0.0, 0.0))
    with pytest.raises(ValueError, match=r"bodies 0 \(Box3D\) and 1 \(Capsule\) overlap"):
        Simulation3D(scene, Law("routh", e=0.5))
    with pytest.raises(ValueError, match="pairs a body with itself"):
        Simulation3D(scene, Law("routh", e=0.5), pair_laws={(1, 1): Law("routh", e=0.2)})


def test_pair_law_is_used():
    """pair_laws[(0, 1)] resolves the body-body impact (e = 1 vs the scene's e = 0.2)."""
    sim = two_body("box", "capsule", Law("kane_levinson", e=1.0, mu=0.0))
    res = Simulation3D(sim.scene, Law("kane_levinson", e=0.2, mu=0.0),
                       pair_laws={(1, 0): Law("kane_levinson", e=1.0, mu=0.0)}).run(0.6)
    ev = res.events[0]
    assert ev["v_f"][0] == pytest.approx(-ev["v_i"][0], rel=1e-12)


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_dice_collide_scenario(seed):
    """The dice_collide scenario (Chatterjee & Ruina, e = 0.5, mu = 0.5): the dice meet in
    the air (at least one die-die impact, the first before either lands), land, tumble and
    come to rest on a face each; no energy created (the law never creates it: the scene's
    energy only falls, beyond the integrated contact's tolerance), the dice never overlap
    (gap of the sampled poses, pair3d) and never go below the table."""
    from rbimpact import scenarios
    from rbimpact.scenarios.die_toss import face_up
    sc = scenarios.get("dice_collide", seed=seed)
    law = sc.law
    plane = sc.scene.planes[0]
    # the law for every contact given by key (the scene's law is another, unused): the
    # loop compiled for several laws, shared with the other tests here
    sim = Simulation3D(sc.scene, Law("kane_levinson", e=0.5),
                       pair_laws={(0, 1): law, plane: law})
    res = sim.run(sc.t_end, max_events=sc.max_events)
    assert res.status == "done"
    ev = res.events
    pair = ev[(ev["a"] == 0) & (ev["b"] == 1)]
    table = ev[ev["b"] < 0]
    assert len(pair) >= 1 and pair["t"][0] < table["t"][table["kind"] == "impact"][0]
    assert face_up(res, 0) in range(1, 7) and face_up(res, 1) in range(1, 7)
    ts = np.linspace(0.0, res.t_end, 2001)
    s = res.sample(ts)
    g = 9.81
    m = np.array([b.mass for b in sim.scene.bodies])
    E = []
    fr, fe = np.zeros(N_FR), np.zeros(N_FE, np.int64)
    h = 0.5 * sc.params["size"]
    for k in range(len(ts)):
        Ek = 0.0
        for i, b in enumerate(sim.scene.bodies):
            v, w = s["velocity"][k, i], s["angular_velocity"][k, i]
            Iw = world_inertia(b, s["orientation"][k, i]) @ w
            Ek += 0.5 * b.mass * v @ v + 0.5 * w @ Iw + b.mass * g * s["position"][k, i, 2]
        E.append(Ek)
        rows = [np.concatenate([s["position"][k, i], s["orientation"][k, i], np.zeros(12)])
                for i in (0, 1)]
        gap = pair_frame(1, 0.0, h, h, h, rows[0], 1, 0.0, h, h, h, rows[1], fr, fe)
        assert gap > -1e-9 * sc.params["size"], (ts[k], gap)
        low = rows[0][2] - math.sqrt(3) * h, rows[1][2] - math.sqrt(3) * h
        assert min(low) > -math.sqrt(3) * h      # centres above the table (coarse)
    E = np.array(E)
    scale = E[0] + float(np.sum(m)) * g * sc.params["height"]
    assert np.max(E - np.minimum.accumulate(E)) <= 1e-9 * scale
