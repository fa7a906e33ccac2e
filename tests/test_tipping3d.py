"""A 3D box sliding on a face tips over when the face cannot carry the friction moment
(issue 13: "tipping from a face to an edge or a vertex").

A box of half edges (hx, hy, hz) sliding along x on its bottom face with Coulomb friction
mu feels the friction force -mu m g at the floor, h = hz below its centre of mass. The
moment balance puts the pressure centre at d = mu h ahead of the centre's foot (DESIGN
§6a), inside the face iff mu hz <= hx: then the box slides flat and stops after
v^2 / (2 mu g); beyond, it tips over its leading edge (mode table: slide on a face ->
pivot on an edge; ``stepper3d._tip``), or over its leading corner when it slides along a
diagonal of the face and the pressure centre leaves the face across both of its sides.
"""
import math

import numpy as np
import pytest

from rbimpact import Law
from rbimpact.scene3d import Scene3D
from rbimpact.shapes3d import Box3D
from rbimpact.simulation3d import Simulation3D

G = 9.81
M = 1.3
HALF = (0.05, 0.05, 0.2)      # a tall box: it tips when mu > hx / hz = 0.25
DROP = 1e-7                   # m: it lands flat on its face at 1.4 mm/s (e = 0)


def _slide(mu, velocity, t_end=0.3):
    scene = Scene3D(gravity=(0.0, 0.0, -G))
    scene.add_floor()
    scene.add_body(Box3D(tuple(2 * h for h in HALF)), M, (0.0, 0.0, HALF[2] + DROP),
                   velocity=velocity)
    sim = Simulation3D(scene, Law("kane_levinson", e=0.0, mu=mu))
    return sim, sim.run(t_end)


def _lowest_corner(res, ts):
    s = res.sample(ts)
    x = s["position"][:, 0]
    q = s["orientation"][:, 0]
    low = np.inf
    for sx in (-1, 1):
        for sy in (-1, 1):
            for sz in (-1, 1):
                c = np.array([sx * HALF[0], sy * HALF[1], sz * HALF[2]])
                w, v = q[:, :1], q[:, 1:]
                t = 2.0 * np.cross(v, c)
                rot = c + w * t + np.cross(v, t)
                low = min(low, float(np.min(x[:, 2] + rot[:, 2])))
    return low


def test_below_the_threshold_the_box_slides_flat_and_stops():
    mu, v = 0.2, 0.5                   # mu hz = 0.04 < hx = 0.05
    sim, res = _slide(mu, (v, 0.0, 0.0))
    assert res.status == "done"
    ev = res.events
    assert not np.any(ev["kind"] == "pivot")
    tc = float(ev["t"][ev["kind"] == "contact"][0])     # on the face from here
    c = res.sample([tc + 1e-9])
    xc, vc = c["position"][0, 0, 0], c["velocity"][0, 0, 0]
    s = res.sample([0.29])
    travel = vc * vc / (2 * mu * G)
    assert abs(s["position"][0, 0, 0] - (xc + travel)) <= 1e-9 * travel
    assert np.all(s["angular_velocity"] == 0.0) and np.all(s["velocity"] == 0.0)


@pytest.mark.parametrize("direction,corners", [((1.0, 0.0), 2), ((1.0, 1.0), 1)])
def test_beyond_the_threshold_the_box_tips_over_its_leading_side(direction, corners):
    mu, v = 0.6, 0.5                   # mu hz = 0.12 > hx = hy = 0.05
    u = np.array(direction) / np.linalg.norm(direction)
    sim, res = _slide(mu, (v * u[0], v * u[1], 0.0))
    assert res.status == "done", res.status
    ev = res.events
    piv = ev[ev["kind"] == "pivot"]
    assert len(piv) >= 1
    first = piv[0]
    assert first["mode"] == corners            # held on an edge (2) or a corner (1)
    # the held contact is on the leading side: ahead of the centre along the slip
    s = res.sample([float(first["t"])])
    ahead = (np.asarray(first["point"][:2]) - s["position"][0, 0, :2]) @ u
    assert ahead > 0.9 * HALF[0]
    # it turns forward (about the axis z x u), never sinks, and friction only removes
    # energy from the tipping on
    t = np.linspace(float(first["t"]), 0.3, 400)
    w = res.sample(t[1:2])["angular_velocity"][0, 0]
    assert w @ np.cross([0.0, 0.0, 1.0], [u[0], u[1], 0.0]) > 0.0
    assert _lowest_corner(res, t) >= -sim.tolerances["gap_tol"]
    e = res.energy(t)
    assert np.all(np.diff(e) <= 1e-9 * M * G * HALF[2])


def test_a_box_held_by_friction_on_an_incline_tips_over_its_downhill_edge():
    """The classical block on an incline: with mu > tan(theta) friction holds it, and it
    tips iff tan(theta) > hx / hz (the weight's line of action passes the downhill edge).
    tan(theta) = 0.4 > 0.25: it turns over its downhill edge from rest (rest on a face ->
    pivot on an edge); tan(theta) = 0.2 < 0.25: it stays at rest."""
    for tan_t, tips in ((0.4, True), (0.2, False)):
        th = math.atan(tan_t)
        n = np.array([-math.sin(th), 0.0, math.cos(th)])       # rises towards +x
        scene = Scene3D(gravity=(0.0, 0.0, -G))
        scene.add_plane((0.0, 0.0, 0.0), tuple(n))
        q = (math.cos(-th / 2), 0.0, math.sin(-th / 2), 0.0)   # body z along n
        scene.add_body(Box3D(tuple(2 * h for h in HALF)), M, tuple((HALF[2] + DROP) * n),
                       orientation=q)
        sim = Simulation3D(scene, Law("kane_levinson", e=0.0, mu=0.8))
        res = sim.run(0.2)
        ev = res.events
        piv = ev[ev["kind"] == "pivot"]
        if not tips:
            assert res.status == "done" and len(piv) == 0
            assert ev["kind"][-1] == "rest"
            continue
        assert res.status == "done", res.status
        assert len(piv) >= 1 and piv[0]["mode"] == 2
        downhill = np.array([-math.cos(th), 0.0, -math.sin(th)])
        s = res.sample([float(piv[0]["t"])])
        assert (np.asarray(piv[0]["point"]) - s["position"][0, 0]) @ downhill > 0.9 * HALF[0]
        # it turns downhill (about -y) and never sinks into the incline
        t = np.linspace(float(piv[0]["t"]), 0.2, 200)
        assert res.sample(t[5:6])["angular_velocity"][0, 0, 1] < 0.0
        s = res.sample(t)
        for sx in (-1, 1):
            for sy in (-1, 1):
                for sz in (-1, 1):
                    c = np.array([sx * HALF[0], sy * HALF[1], sz * HALF[2]])
                    qq = s["orientation"][:, 0]
                    tt = 2.0 * np.cross(qq[:, 1:], c)
                    rot = c + qq[:, :1] * tt + np.cross(qq[:, 1:], tt)
                    gap = (s["position"][:, 0] + rot) @ n
                    assert np.min(gap) >= -sim.tolerances["gap_tol"]
