"""Persistent contact between spheres in the 3D stepper (issue 16 item 2): ``stepper3d``
wires ``kernels/cluster3d.py`` as ``stepper2d`` wires ``cluster2d`` (PM_CLUSTER).

Real physics that can fail: a closed-form push (a rolling sphere meets a resting one in a
plastic frictionless impact; the pusher's backspin and the pushed one's slip meet their
floor friction while they stay in contact, and both roll at v/2 after ``v / (5 mu g)``);
the contact force of that phase against its closed form; no overlap; energy only lost;
the campaign scenes of two touching spheres that ended with the chatter refusal before;
the named refusal of a cluster member without spherical inertia.
"""
import math

import numpy as np
import pytest

from rbimpact import Law
from rbimpact.campaign import run_drop
from rbimpact.errors import SimulationError
from rbimpact.kernels.codes import PM_CLUSTER
from rbimpact.scene3d import Scene3D
from rbimpact.shapes3d import Sphere
from rbimpact.simulation3d import Simulation3D

G = 9.81


def push_scene(v, r, m, gap, inertia=None):
    """Sphere 0 rolling at v along x on the floor (spin v / r about y) towards sphere 1 at
    rest, their surfaces ``gap`` apart."""
    scene = Scene3D(gravity=(0.0, 0.0, -G))
    scene.add_floor()
    scene.add_body(Sphere(r), m, (0.0, 0.0, r), velocity=(v, 0.0, 0.0),
                   angular_velocity=(0.0, v / r, 0.0))
    scene.add_body(Sphere(r), m, (2.0 * r + gap, 0.0, r), inertia=inertia)
    return scene


@pytest.mark.parametrize("v, r, m, mu", [(1.0, 0.1, 1.0, 0.3), (2.5, 0.04, 0.2, 0.6),
                                         (0.4, 0.5, 7.0, 0.15)])
def test_plastic_push_rolls_together_at_half_speed(v, r, m, mu):
    """After the plastic frictionless impact both move at V = v/2: the pusher (spin v / r)
    slips backwards, its floor friction pushes it forward; the pushed one (no spin) slips
    forwards and is braked. Staying in contact needs the force F = mu m g (equal masses),
    their common acceleration is zero, and each slip closes at 5 mu g / 2: both roll at
    v/2, spin v / (2 r), at t1 + v / (5 mu g), and stay touching."""
    gap = 0.3 * r
    floor = Law("kane_levinson", e=0.0, mu=mu)
    pair = Law("kane_levinson", e=0.0, mu=0.0)
    sim = Simulation3D(push_scene(v, r, m, gap), floor, pair_laws={(0, 1): pair})
    t1 = gap / v
    ts = t1 + v / (5.0 * mu * G)
    t_end = 1.5 * ts
    res = sim.run(t_end)
    assert res.status == "done"
    ev = res.events
    imp = ev[ev["kind"] == "impact"]
    assert len(imp) == 1 and imp["t"][0] == pytest.approx(t1, rel=1e-12)
    # the cluster: entered at t1, both floor slips stop at ts
    cont = ev[(ev["kind"] == "contact") & (ev["b"] == 1)]
    assert len(cont) == 1 and cont["t"][0] == pytest.approx(t1, rel=1e-9)
    # (a slip stops when it falls to cluster3d.SLIP_EPS V: that early, 1e-9 of the time)
    sticks = ev[ev["kind"] == "stick"]
    assert sorted(sticks["a"]) == [0, 1] and np.all(sticks["mode"] == PM_CLUSTER)
    np.testing.assert_allclose(sticks["t"], ts, rtol=1e-7)
    assert np.all(sticks["t"] <= ts)
    # the contact force while they slip: F = mu m g ("contact" event's normal force)
    assert cont["P"][0, 0] == pytest.approx(mu * m * G, rel=1e-9)
    # the phase between: constant speed v/2, contact force mu m g
    tm = 0.5 * (t1 + ts)
    s = res.sample([tm, t_end])
    np.testing.assert_allclose(s["velocity"][0, :, 0], 0.5 * v, rtol=1e-9)
    np.testing.assert_allclose(s["position"][0, 1, 0] - s["position"][0, 0, 0], 2.0 * r,
                               rtol=1e-9)
    # the end: both roll at v/2 with spin v/(2r), on the floor, touching
    np.testing.assert_allclose(s["velocity"][1, :, 0], 0.5 * v, rtol=1e-9)
    np.testing.assert_allclose(s["angular_velocity"][1, :, 1], 0.5 * v / r, rtol=1e-9)
    np.testing.assert_allclose(s["position"][1, :, 2], r, rtol=1e-12)
    d = s["position"][1, 1] - s["position"][1, 0]
    assert np.linalg.norm(d) == pytest.approx(2.0 * r, rel=1e-9)
    assert s["position"][1, 0, 0] == pytest.approx(v * t1 + 0.5 * v * (t_end - t1), rel=1e-9)
    # energy: 0.7 m v^2 before; 2 (m V^2 / 2 + I w^2 / 2) = 0.35 m v^2 after
    K = (0.5 * m * np.sum(s["velocity"][1] ** 2)
         + 0.5 * 0.4 * m * r * r * np.sum(s["angular_velocity"][1] ** 2))
    assert K == pytest.approx(0.35 * m * v * v, rel=1e-9)


def test_cluster_member_without_spherical_inertia_is_refused_by_name():
    """A sphere of unequal principal moments landing plastically on a sphere resting on the
    floor: its impacts accumulate on it, but persistent contact is built for spheres of
    spherical inertia: the run stops with the named refusal (no overlap before it)."""
    r, m = 0.1, 1.0
    I0 = 0.4 * m * r * r
    scene = Scene3D(gravity=(0.0, 0.0, -G))
    scene.add_floor()
    scene.add_body(Sphere(r), m, (0.0, 0.0, r))
    scene.add_body(Sphere(r), m, (0.3 * r, 0.0, 3.2 * r), inertia=(I0, 1.2 * I0, 0.9 * I0))
    sim = Simulation3D(scene, Law("kane_levinson", e=0.0, mu=0.3))
    with pytest.raises(SimulationError, match="spheres of spherical inertia") as info:
        sim.run(1.0)
    res = info.value.result
    assert res.status == "persistent_pair"
    s = res.sample(np.linspace(0.0, res.t_end, 200))
    d = np.linalg.norm(s["position"][:, 1] - s["position"][:, 0], axis=1)
    assert np.all(d >= 2.0 * r - 1e-12)


#: campaign scenes of two spheres touching on the floor (3D, layout "touching"; Routh with
#: Newton's restitution, Kane & Levinson at mu = 10, Smith and Routh's energetic
#: restitution without friction) that ended with the chatter refusal "impacts accumulate
#: at a single contact point of body 0 (Sphere) on body 1" before persistent sphere
#: contact (session 23)
TOUCHING_SEEDS = [1122022965, 148276019, 841340813, 2354148785, 3595373354]


@pytest.mark.parametrize("seed", TOUCHING_SEEDS)
def test_touching_spheres_campaign_scenes_end_ok(seed):
    row = run_drop(3, seed)
    assert row.verdict == "OK", f"{row.reproducer}: {row.note}"
    assert math.isfinite(row.penetration)
